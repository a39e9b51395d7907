/* shape.c: the dispatch over shape kinds: every switch on a kind but the
** nearest-hit one in intersect.c, and each primitive kind's BVH cost.
**
** A new kind of shape (say LC_WEDGE, its primitive id PRIM_WEDGE) touches
** exactly these places (tests/lua/test_layout.lua reads them and fails when
** a PRIM_* kind of shape.h is missing from one that applies to it):
**   1. src/lancer.h: LC_WEDGE in lc_shape_kind (before LC_SHAPE_KINDS), and
**      any lc_shape field it needs;
**   2. src/wedge.c: everything the kind does: wedge_check, _prepare,
**      _describe, _transform, _scale, _bounds, _uv, the hit (wedge_t and
**      wedge_hit), and, if it can glow, _light_centre, _light_begin and
**      _light_sample (a placed kind, placed.h, shares _describe, _transform
**      and _scale, and has _area instead of the light's first two);
**   3. src/wedge.h: its wedge_geom (and wedge_light) and those prototypes;
**   4. src/shapes/shape.h: a PRIM_WEDGE id before PRIM_KINDS (PRIM_KIND_BITS = 5
**      hold 31 kinds besides PRIM_NONE; 14 are used), its bit in PRIM_FLAT
**      if flat or in PRIM_CONCAVE if not convex, and its setup in
**      light_setup if sampling it needs one per shaded point (then the
**      include of wedge.h);
**   5. src/shapes/shape.c, this file: its entries in the tables kind_names,
**      prim_kinds, geom_sizes and shape_prim_cost (its BVH cost, measured),
**      a case in each switch below (or the kind named in shape_bounded and
**      shape_can_emit when it is unbounded or never a light; in
**      placed_kind's range when placed), and the include of wedge.h;
**   6. src/scene/intersect.c: a case in prim_t and prim_finish (or, when prim_t
**      completes the hit, its bit in COMPLETE), the nearest-hit switch kept
**      there for speed, and the include of wedge.h;
**   7. src/lua/lua_shapes.c: its fields in kind_fields, its Lua constructor
**      w_wedge (lancer.wedge{...}) and its entry in lb_shapes_register;
**   8. src/scene/csg.c, if it bounds a solid (CSG takes it as a leaf): a case in
**      closed_kind and in shape_cross, and, if its geometry is none of
**      sphere_geom, box_geom and placed_geom, a member in csg_leaf's union
**      in src/scene/csg.h;
**   9. docs/manual.md: its row lancer.wedge{...} in the shapes' table, and
**      its texture coordinates.
** Scenes store, list, move, bound, remove and sample every kind through
** this file, so nothing else changes. A primitive id that is no shape
** (PRIM_TRIANGLE, PRIM_INSTANCE, the CSG ones) needs its place in 4, its
** entry in shape_prim_cost and its cases in src/scene/intersect.c. */
#include <string.h>
#include "accel/bvh.h"
#include "cone.h"
#include "cylinder.h"
#include "disc.h"
#include "ellipsoid.h"
#include "plane.h"
#include "shape.h"
#include "torus.h"
#include "base/validate.h"

static const char *const kind_names[LC_SHAPE_KINDS + 1] = {
    [LC_SPHERE] = "sphere", [LC_QUAD] = "quad", [LC_BOX] = "box", [LC_PLANE] = "plane",
    [LC_DISC] = "disc", [LC_CYLINDER] = "cylinder", [LC_CONE] = "cone",
    [LC_TORUS] = "torus", [LC_ELLIPSOID] = "ellipsoid", [LC_SHAPE_KINDS] = "triangle"};

static const unsigned prim_kinds[LC_SHAPE_KINDS] = {
    [LC_SPHERE] = PRIM_SPHERE, [LC_QUAD] = PRIM_QUAD, [LC_BOX] = PRIM_BOX,
    [LC_PLANE] = PRIM_PLANE, [LC_DISC] = PRIM_DISC, [LC_CYLINDER] = PRIM_CYLINDER,
    [LC_CONE] = PRIM_CONE, [LC_TORUS] = PRIM_TORUS, [LC_ELLIPSOID] = PRIM_ELLIPSOID};

static const size_t geom_sizes[LC_SHAPE_KINDS] = {
    [LC_SPHERE] = sizeof(sphere_geom), [LC_QUAD] = sizeof(quad_geom),
    [LC_BOX] = sizeof(box_geom), [LC_PLANE] = sizeof(plane_geom),
    [LC_DISC] = sizeof(placed_geom), [LC_CYLINDER] = sizeof(placed_geom),
    [LC_CONE] = sizeof(placed_geom), [LC_TORUS] = sizeof(placed_geom),
    [LC_ELLIPSOID] = sizeof(placed_geom)};

/* What a leaf test of each primitive kind costs, in units of a sphere,
** quad or triangle test (each 50-70 instructions, callgrind), for the
** BVH's surface area heuristic. Measured on scenes/bench/mixed.lua and
** instances.lua: a cylinder test 260 instructions (the ray brought into
** its canonical space, then the quadratic), an instance 550 (the ray
** moved, the mesh's own walk and triangles). A leaf of four such is a
** leaf of 16 to 32 unit tests; weighed, the build parts them. A box test
** is 75 instructions to a sphere's 67 (B1), but boxes weigh 2, which
** makes leaves of two: tuned on scenes/bench/city.lua (rays grazing rows
** of roofs), 9.7 % fewer trace instructions than at 1, B1 1.6 % fewer,
** for 1.7 times the city's nodes (0.3 MB). Spheres and triangles stay at
** 1: leaves of two would cost B2 1M and B3 4M 16 and 60 MB of nodes.
** The ids nothing uses weigh 0: no item has them. */
const float shape_prim_cost[PRIM_NONE + 1] = {
    [PRIM_SPHERE] = 1, [PRIM_QUAD] = 1, [PRIM_BOX] = 2, [PRIM_TRIANGLE] = 1,
    [PRIM_PLANE] = 1, [PRIM_INSTANCE] = 8, [PRIM_DISC] = 2, [PRIM_CYLINDER] = 4,
    [PRIM_CONE] = 4, [PRIM_TORUS] = 8, [PRIM_ELLIPSOID] = 3, [PRIM_CSG] = 8,
    [PRIM_CSG_FACE] = 1, [PRIM_CSG_CUT] = 1, [PRIM_NONE] = 1};

/* The BVH weighs an item by the kind in its id's top bits, reading this
** table: both must agree on where the kind lies; and the kinds must leave
** PRIM_NONE to no primitive. (C99 has no static assertion: an array of
** size -1 stops the build.) */
typedef char prim_kind_is_bvh_kind[PRIM_SHIFT == BVH_KIND_SHIFT ? 1 : -1];
typedef char prim_kinds_fit[PRIM_KINDS <= PRIM_NONE ? 1 : -1];
typedef char prim_costs_fit[sizeof shape_prim_cost / sizeof *shape_prim_cost == BVH_KINDS
                            ? 1 : -1];

/* The kinds placed by an affine map (placed.c). */
static int placed_kind(lc_shape_kind k) { return k >= LC_DISC && k <= LC_ELLIPSOID; }

const char *lc_shape_kind_name(lc_shape_kind k)
{
    return (unsigned)k <= LC_SHAPE_KINDS ? kind_names[k] : "?";
}

size_t   shape_geom_size(lc_shape_kind k) { return geom_sizes[k]; }
unsigned shape_prim_kind(lc_shape_kind k) { return prim_kinds[k]; }
int      shape_bounded(lc_shape_kind k) { return k != LC_PLANE; }
int      shape_can_emit(lc_shape_kind k) { return k != LC_PLANE; }

lc_shape_kind shape_kind_of_prim(unsigned prim_kind)
{
    for (int k = 0; k < LC_SHAPE_KINDS; k++)
        if (prim_kinds[k] == prim_kind)
            return (lc_shape_kind)k;
    return LC_SHAPE_KINDS;                      /* a mesh's triangle */
}

lc_status lc_shape_check(const lc_shape *s, lc_error *err)
{
    lc_status st;
    switch (s->kind) {
    case LC_SPHERE: st = sphere_check(s, err); break;
    case LC_QUAD: st = quad_check(s, err); break;
    case LC_BOX: st = box_check(s, err); break;
    case LC_PLANE: st = plane_check(s, err); break;
    case LC_DISC: st = disc_check(s, err); break;
    case LC_CYLINDER: st = cylinder_check(s, err); break;
    case LC_CONE: st = cone_check(s, err); break;
    case LC_TORUS: st = torus_check(s, err); break;
    case LC_ELLIPSOID: st = ellipsoid_check(s, err); break;
    default:
        return error_fail(err, LC_EARG, "kind", "unknown shape kind %d", (int)s->kind);
    }
    if (st == LC_OK)
        error_ok(err);
    return st;
}

lc_status lc_shape_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                             lc_error *err)
{
    if (lc_shape_check(s, err) || lc_transform_check(t, err))
        return LC_EARG;
    lc_shape r;
    lc_status st;
    switch (s->kind) {
    case LC_SPHERE: st = sphere_transform(s, t, &r, err); break;
    case LC_QUAD: st = quad_transform(s, t, &r, err); break;
    case LC_BOX: st = box_transform(s, t, &r, err); break;
    case LC_PLANE: st = plane_transform(s, t, &r, err); break;
    default: st = placed_transform(s, t, &r, err); break;
    }
    if (st || lc_shape_check(&r, err))
        return LC_EARG;
    *out = r;
    error_ok(err);
    return LC_OK;
}

lc_status lc_shape_stored(const lc_shape *s, lc_shape *out, lc_error *err)
{
    if (lc_shape_check(s, err))
        return LC_EARG;
    union { sphere_geom s; quad_geom q; box_geom b; plane_geom p; placed_geom x; } g;
    shape_prepare(s, &g);
    memset(out, 0, sizeof *out);                /* as the scene lists it */
    shape_describe(s->kind, &g, out);
    return LC_OK;
}

void shape_prepare_emitter(lc_shape_kind k, void *geom)
{
    placed_geom *g = geom;
    switch (k) {
    case LC_DISC: g->area = disc_area(g); break;
    case LC_CYLINDER: g->area = cylinder_area(g); break;
    case LC_CONE: g->area = cone_area(g); break;
    case LC_TORUS: g->area = torus_area(g); break;
    case LC_ELLIPSOID: g->area = ellipsoid_area(g); break;
    default: break;                             /* spheres, quads, boxes: closed forms */
    }
}

void shape_prepare(const lc_shape *s, void *geom)
{
    switch (s->kind) {
    case LC_SPHERE: sphere_prepare(s, geom); break;
    case LC_QUAD: quad_prepare(s, geom); break;
    case LC_BOX: box_prepare(s, geom); break;
    case LC_PLANE: plane_prepare(s, geom); break;
    case LC_DISC: disc_prepare(s, geom); break;
    case LC_CYLINDER: cylinder_prepare(s, geom); break;
    case LC_CONE: cone_prepare(s, geom); break;
    case LC_TORUS: torus_prepare(s, geom); break;
    default: ellipsoid_prepare(s, geom); break;
    }
}

void shape_describe(lc_shape_kind k, const void *geom, lc_shape *out)
{
    out->kind = k;
    switch (k) {
    case LC_SPHERE: sphere_describe(geom, out); break;
    case LC_QUAD: quad_describe(geom, out); break;
    case LC_BOX: box_describe(geom, out); break;
    case LC_PLANE: plane_describe(geom, out); break;
    default: *out = ((const placed_geom *)geom)->shape; break;
    }
}

void shape_scale(lc_shape *s, double k, lc_vec3 offset)
{
    switch (s->kind) {
    case LC_SPHERE: sphere_scale(s, k, offset); break;
    case LC_QUAD: quad_scale(s, k, offset); break;
    case LC_BOX: box_scale(s, k, offset); break;
    case LC_PLANE: plane_scale(s, k, offset); break;
    case LC_DISC: case LC_TORUS: placed_scale(s, k, offset, 0); break;  /* u: a direction */
    default: placed_scale(s, k, offset, 1); break;
    }
}

void shape_bounds(lc_shape_kind k, const void *geom, float lo[3], float hi[3])
{
    switch (k) {
    case LC_SPHERE: sphere_bounds(geom, lo, hi); break;
    case LC_QUAD: quad_bounds(geom, lo, hi); break;
    case LC_BOX: box_bounds(geom, lo, hi); break;
    case LC_DISC: disc_bounds(geom, lo, hi); break;
    case LC_CYLINDER: cylinder_bounds(geom, lo, hi); break;
    case LC_CONE: cone_bounds(geom, lo, hi); break;
    case LC_TORUS: torus_bounds(geom, lo, hi); break;
    case LC_ELLIPSOID: ellipsoid_bounds(geom, lo, hi); break;
    default:                                    /* unbounded: never in the BVH */
        for (int a = 0; a < 3; a++) {
            lo[a] = -HUGE_VALF;
            hi[a] = HUGE_VALF;
        }
        break;
    }
}

void shape_uv(lc_shape_kind k, const void *geom, lc_vec3 p, double uv[2])
{
    switch (k) {
    case LC_SPHERE: sphere_uv(geom, p, uv); break;
    case LC_QUAD: quad_uv(geom, p, uv); break;
    case LC_BOX: box_uv(geom, p, uv); break;
    case LC_PLANE: plane_uv(geom, p, uv); break;
    case LC_DISC: disc_uv(geom, p, uv); break;
    case LC_CYLINDER: cylinder_uv(geom, p, uv); break;
    case LC_CONE: cone_uv(geom, p, uv); break;
    case LC_TORUS: torus_uv(geom, p, uv); break;
    case LC_ELLIPSOID: ellipsoid_uv(geom, p, uv); break;
    default: uv[0] = uv[1] = 0; break;
    }
}

lc_vec3 shape_light_target(lc_shape_kind k, const void *geom)
{
    if (placed_kind(k)) {                       /* the centre of the canonical shape */
        double z = k == LC_CYLINDER || k == LC_CONE ? 0.5 : 0;
        return lc_transform_point(&((const placed_geom *)geom)->x.xf, v3(0, 0, z));
    }
    switch (k) {
    case LC_SPHERE:
        return ((const sphere_geom *)geom)->c;
    case LC_QUAD: {
        const quad_geom *g = geom;
        return v3_add(g->q, v3_mul(v3_add(g->u, g->v), 0.5));
    }
    default: {
        const box_geom *g = geom;
        return v3_add(g->q, v3_mul(v3_add(v3_add(g->e[0], g->e[1]), g->e[2]), 0.5));
    }
    }
}

double shape_light_centre(lc_shape_kind k, const void *geom, lc_vec3 l, double d)
{
    if (k == LC_DISC) {                         /* flat: its area seen along l */
        const placed_geom *g = geom;
        lc_vec3 n = affine_normal(&g->x, v3(0, 0, 1));
        return g->area * fabs(v3_dot(n, l)) / (PI * d * d);
    }
    if (placed_kind(k))    /* a quarter of the area: the mean over directions (Cauchy) */
        return ((const placed_geom *)geom)->area / (4 * PI * d * d);
    switch (k) {
    case LC_SPHERE: return sphere_light_centre(geom, l, d);
    case LC_QUAD: return quad_light_centre(geom, l, d);
    default: return box_light_centre(geom, l, d);
    }
}

int shape_light_begin(lc_shape_kind k, const void *geom, lc_vec3 p, lc_vec3 n,
                      light_setup *ls)
{
    if (placed_kind(k))
        return 1;                               /* sampled over their whole surface */
    switch (k) {
    case LC_SPHERE: return sphere_light_begin(geom, p, n, &ls->sphere);
    case LC_QUAD: return quad_light_begin(geom, p, &ls->quad);
    default: return box_light_begin(geom, p, &ls->box);
    }
}

int shape_light_sample(lc_shape_kind k, const void *geom, const light_setup *ls,
                       lc_vec3 p, const double u[2], uint32_t S, light_sample *out)
{
    switch (k) {
    case LC_SPHERE: return sphere_light_sample(geom, &ls->sphere, p, u, S, out);
    case LC_QUAD: return quad_light_sample(geom, &ls->quad, p, u, S, out);
    case LC_BOX: return box_light_sample(geom, &ls->box, p, u, S, out);
    case LC_DISC: return disc_light_sample(geom, p, u, S, out);
    case LC_CYLINDER: return cylinder_light_sample(geom, p, u, S, out);
    case LC_CONE: return cone_light_sample(geom, p, u, S, out);
    case LC_TORUS: return torus_light_sample(geom, p, u, S, out);
    default: return ellipsoid_light_sample(geom, p, u, S, out);
    }
}

double shape_light_pdf(lc_shape_kind k, const void *geom, lc_vec3 p, lc_vec3 n, lc_vec3 d,
                       double dist)
{
    light_setup ls;
    if (!shape_light_mis(k))
        return -1;
    if (!shape_light_begin(k, geom, p, n, &ls))
        return 0;
    if (k == LC_SPHERE)
        return 1 / ls.sphere.solid;
    double c = fabs(v3_dot(((const quad_geom *)geom)->un, d));
    return c > 0 ? dist * dist / (ls.quad.area * c) : 0;
}

int shape_light_mis(lc_shape_kind k)
{
    return k == LC_SPHERE || k == LC_QUAD;
}
