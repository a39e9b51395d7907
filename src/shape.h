/* shape.h: the shape kinds: each kind's prepared form and functions (one file
** per kind: sphere.c, quad.c, box.c, plane.c, triangle.c), and the dispatch
** over them (shape.c, which says what a new kind touches). */
#ifndef LC_SHAPE_H
#define LC_SHAPE_H

#include "affine.h"
#include "geom.h"
#include "sphere.h"
#include "triangle.h"

/* ---- Primitive ids ----------------------------------------------------------- */

/* A primitive's id: its kind in the top PRIM_KIND_BITS bits, its index in
** that kind's list below them. Ids order ties between equally near hits.
** Kind PRIM_NONE (all bits set) is no kind: INTERSECT_SKIP_NONE, every bit
** of the id set, names no primitive. 5 bits hold 31 kinds besides it; each
** kind holds at most PRIM_MAX = 2^27 primitives (the triangles of a scene
** too). The BVH weighs an item by the same top bits (bvh.h,
** BVH_KIND_SHIFT; compile.c checks that they agree). */
enum { PRIM_SPHERE, PRIM_QUAD, PRIM_BOX, PRIM_TRIANGLE, PRIM_PLANE,
       PRIM_INSTANCE,       /* a moved mesh: only in BVH refs, never in a hit */
       PRIM_DISC, PRIM_CYLINDER, PRIM_CONE, PRIM_TORUS, PRIM_ELLIPSOID,
       PRIM_CSG,            /* a CSG object (csg.h): only in BVH refs, never in a hit */
       PRIM_CSG_FACE,       /* a hit on a CSG object's convex leaf, its normal the
                            ** leaf's: leaving outward, a ray never meets that leaf */
       PRIM_CSG_CUT,        /* any other CSG hit (cut faces, concave leaves) */
       PRIM_KINDS };
#define PRIM_KIND_BITS       5
#define PRIM_SHIFT           (32 - PRIM_KIND_BITS)
#define PRIM_NONE            ((1u << PRIM_KIND_BITS) - 1)    /* no kind */
#define PRIM_ID(kind, index) (((uint32_t)(kind) << PRIM_SHIFT) | (uint32_t)(index))
#define PRIM_KIND(id)        ((unsigned)((id) >> PRIM_SHIFT))
#define PRIM_INDEX(id)       ((id) & ((1u << PRIM_SHIFT) - 1))
#define PRIM_MAX             ((size_t)1 << PRIM_SHIFT)

/* Flat primitives: a ray leaving one can never meet it again. */
#define PRIM_FLAT ((1u << PRIM_QUAD) | (1u << PRIM_PLANE) | (1u << PRIM_TRIANGLE) | \
                   (1u << PRIM_DISC))
static inline int prim_flat(unsigned kind) { return (PRIM_FLAT >> kind) & 1; }
/* Not convex: a ray leaving one outward may meet it again, legitimately.
** A CSG hit names the object and (in hit.instance) the leaf. */
#define PRIM_CONCAVE ((1u << PRIM_TORUS) | (1u << PRIM_CSG) | (1u << PRIM_CSG_CUT))
static inline int prim_cannot_return(unsigned kind, int outward)
{
    return prim_flat(kind) || (outward && !((PRIM_CONCAVE >> kind) & 1));
}

/* ---- Emissive shapes as lights ------------------------------------------------- */

/* An emissive shape, set up when it is added: the seed's model aims one
** shadow ray at `target`; sampled, it is an area light. */
typedef struct {
    lc_shape_kind kind;
    uint32_t index;        /* in the scene's list of that kind */
    uint32_t prim;         /* its PRIM_ID: a hit on it is a hit on the light */
    lc_vec3  target;
    lc_color emission;
} emitter;

/* One point (or direction) sampled on an emitter, seen from a shaded point. */
typedef struct {
    lc_vec3 l;             /* unit direction toward it */
    double  dist;          /* its distance: the shadow ray stops just short */
    double  k;             /* its share: the solid angle it stands for over pi S,
                           ** so that the light adds emission k cos */
} light_sample;

/* Quads and boxes move exactly under any affine map: the corner is a point,
** the edges (u, v, w; zero where unused) vectors. */
static inline void shape_move_edges(const lc_transform *t, const lc_shape *s, lc_shape *out)
{
    *out = *s;
    out->p = lc_transform_point(t, s->p);
    out->u = lc_transform_vector(t, s->u);
    out->v = lc_transform_vector(t, s->v);
    out->w = lc_transform_vector(t, s->w);
}

/* ---- sphere.c ------------------------------------------------------------------- */

/* What sampling a sphere light needs at one shaded point: the cone it subtends. */
typedef struct {
    lc_vec3 tc, axis;      /* centre - p, and its direction */
    double  dc;            /* |centre - p| */
    double  omc, solid;    /* 1 - cos of the cone's half-angle; its solid angle */
} sphere_light;

lc_status sphere_check(const lc_shape *s, lc_error *err);
void      sphere_prepare(const lc_shape *s, sphere_geom *g);
void      sphere_describe(const sphere_geom *g, lc_shape *s);
lc_status sphere_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err);
void      sphere_scale(lc_shape *s, double k, lc_vec3 offset);
void      sphere_bounds(const sphere_geom *g, float lo[3], float hi[3]);
/* Each fills *h and returns 1 for the nearest hit with tmin < t < tmax,
** else returns 0 and leaves *h untouched; the *_t forms return the distance
** only (0 for a miss): enough to find the nearest hit, finished later. */
/* sphere_t: sphere.h. */
int       sphere_hit(const sphere_geom *g, const ray *r, double tmin, double tmax,
                     hit *h);
/* The rest of a hit at distance t, which sphere_t gave for this ray: the
** nearest hit's, found again without the quadratic. */
int       sphere_finish(const sphere_geom *g, const ray *r, double t, hit *h);
/* Texture coordinates of a point p on the shape (each kind's convention:
** docs/manual.md, "Texture coordinates"). */
void      sphere_uv(const sphere_geom *g, lc_vec3 p, double uv[2]);
void      sphere_uv_of_direction(lc_vec3 unit, double uv[2]);
double    sphere_light_centre(const sphere_geom *g, lc_vec3 l, double d);
int       sphere_light_begin(const sphere_geom *g, lc_vec3 p, lc_vec3 n, sphere_light *sl);
int       sphere_light_sample(const sphere_geom *g, const sphere_light *sl, lc_vec3 p,
                              const double u[2], uint32_t S, light_sample *out);

/* ---- quad.c ---------------------------------------------------------------------- */

typedef struct {
    lc_vec3 q, u, v;   /* corner, edges */
    lc_vec3 n;         /* u x v, not normalised */
    lc_vec3 w;         /* n / (n.n): the dual basis for (alpha, beta) */
    lc_vec3 un;        /* unit normal */
    double  k;         /* n.q */
    int     axis;      /* 0..2 when n is along an axis (exact snapping), else -1 */
} quad_geom;

typedef struct { double area; } quad_light;

lc_status quad_check(const lc_shape *s, lc_error *err);
void      quad_prepare(const lc_shape *s, quad_geom *g);
void      quad_describe(const quad_geom *g, lc_shape *s);
lc_status quad_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                         lc_error *err);
void      quad_scale(lc_shape *s, double k, lc_vec3 offset);
void      quad_bounds(const quad_geom *g, float lo[3], float hi[3]);
int       quad_hit(const quad_geom *g, const ray *r, double tmin, double tmax, hit *h);
/* inv: the ray's reciprocal direction (1/d per axis), or NULL to compute it. */
int       quad_hit_inv(const quad_geom *g, const ray *r, const double *inv, double tmin,
                       double tmax, hit *h);
void      quad_uv(const quad_geom *g, lc_vec3 p, double uv[2]);
double    quad_light_centre(const quad_geom *g, lc_vec3 l, double d);
int       quad_light_begin(const quad_geom *g, lc_vec3 p, quad_light *ql);
int       quad_light_sample(const quad_geom *g, const quad_light *ql, lc_vec3 p,
                            const double u[2], uint32_t S, light_sample *out);

/* ---- box.c ----------------------------------------------------------------------- */

typedef struct {
    lc_vec3 q;         /* corner */
    lc_vec3 e[3];      /* edges u, v, w */
    lc_vec3 row[3];    /* rows of the inverse edge matrix: local = row . (x - q) */
    lc_vec3 un[3];     /* unit outward normal of the face where local coord i = 1 */
    double  lo[3], hi[3];  /* axis-aligned boxes: exact face coordinates */
    int     aligned;   /* edges along the axes: slabs in world space, exact snaps */
} box_geom;

/* The faces of a box light that face the shaded point. */
typedef struct {
    lc_vec3 face[3][4];    /* corner, edge, edge, outward normal (not unit) */
    double  area[3], total;
    int     n;
} box_light;

lc_status box_check(const lc_shape *s, lc_error *err);
void      box_prepare(const lc_shape *s, box_geom *g);
void      box_describe(const box_geom *g, lc_shape *s);
lc_status box_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                        lc_error *err);
void      box_scale(lc_shape *s, double k, lc_vec3 offset);
void      box_bounds(const box_geom *g, float lo[3], float hi[3]);
int       box_hit(const box_geom *g, const ray *r, double tmin, double tmax, hit *h);
int       box_hit_inv(const box_geom *g, const ray *r, const double *inv, double tmin,
                      double tmax, hit *h);
double    box_t(const box_geom *g, const ray *r, const double *inv, double tmin,
                double tmax);
void      box_uv(const box_geom *g, lc_vec3 p, double uv[2]);
double    box_light_centre(const box_geom *g, lc_vec3 l, double d);
int       box_light_begin(const box_geom *g, lc_vec3 p, box_light *bl);
int       box_light_sample(const box_geom *g, const box_light *bl, lc_vec3 p,
                           const double u[2], uint32_t S, light_sample *out);

/* ---- plane.c (infinite: never in the BVH, never a light) -------------------------- */

typedef struct {
    lc_vec3 n;         /* unit normal */
    lc_vec3 p;         /* a point on it */
    double  k;         /* n.p */
    double  at;        /* axis >= 0: p's coordinate on that axis */
    int     axis;      /* 0..2 when n is along an axis, else -1 */
} plane_geom;

lc_status plane_check(const lc_shape *s, lc_error *err);
void      plane_prepare(const lc_shape *s, plane_geom *g);
void      plane_describe(const plane_geom *g, lc_shape *s);
lc_status plane_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                          lc_error *err);
void      plane_scale(lc_shape *s, double k, lc_vec3 offset);
int       plane_hit(const plane_geom *g, const ray *r, double tmin, double tmax,
                    hit *h);
/* The rest of a hit at distance t, which plane_t gave for this ray. */
int       plane_finish(const plane_geom *g, const ray *r, double t, hit *h);
void      plane_uv(const plane_geom *g, lc_vec3 p, double uv[2]);
/* Distance along r to the plane through p with unit normal n (axis >= 0:
** n is +-1 on that axis), or 0 for no hit in (tmin, tmax). inv: the ray's
** reciprocals or NULL. Inline: every ray meets every infinite plane. */
static inline double plane_distance(lc_vec3 n, lc_vec3 p, int axis, const ray *r,
                                    const double *inv, double tmin, double tmax)
{
    double t;
    if (axis >= 0) {
        /* Axis planes (walls, floors): one subtraction, exact when the
        ** origin is near the plane, so its side is never in doubt; then
        ** the ray's own reciprocal. A parallel ray gives inf or NaN. */
        double i = inv ? inv[axis] : 1.0 / v3_comp(r->d, axis);
        t = (v3_comp(p, axis) - v3_comp(r->o, axis)) * i;
    } else {
        double denom = v3_dot(n, r->d);
        if (denom == 0)    /* exactly parallel; no epsilon band near grazing */
            return 0;
        /* n.(p - o), not k - n.o: the difference comes first, so t keeps
        ** a few ulps of |p - o|, not of |o|. An origin on the plane within
        ** that rounding cannot tell its side: no hit (a camera on it). */
        lc_vec3 po = v3_sub(p, r->o);
        double num = v3_dot(n, po);
        double band = vec_gamma(4) * (fabs(n.x * po.x) + fabs(n.y * po.y) + fabs(n.z * po.z));
        if (!(fabs(num) > band))
            return 0;
        t = num / denom;
    }
    return t > tmin && t < tmax ? t : 0;   /* NaN and inf fail here */
}

/* plane_t from (0, tmax) for the tracer's loops over every plane, with the
** ray's origin and reciprocals as arrays (bvh_ray's): an axis plane is one
** subtraction and one product, indexed, the same operations as
** plane_distance's, so the same bits. (B1's six walls: every ray tests
** them.) */
static inline double plane_query_t(const plane_geom *g, const ray *r, const double o[3],
                                   const double inv[3], double tmax)
{
    if (g->axis >= 0) {
        double t = (g->at - o[g->axis]) * inv[g->axis];
        return t > 0 && t < tmax ? t : 0;
    }
    return plane_distance(g->n, g->p, -1, r, inv, 0, tmax);
}

/* Shared by plane and quad: puts p back onto the plane n.x = k. */
lc_vec3   plane_snap(lc_vec3 p, lc_vec3 n, double k, int axis, double axis_value,
                     lc_vec3 *perr);

static inline double plane_t(const plane_geom *g, const ray *r, const double *inv,
                             double tmin, double tmax)
{
    return plane_distance(g->n, g->p, g->axis, r, inv, tmin, tmax);
}

/* ---- triangle.c (mesh faces: meshes own their listing and moving) ----------------- */

/* A face that can never be hit: zero area (or an area beyond double). */
int  triangle_degenerate(const double *a, const double *b, const double *c);
/* Bounds of a face: its vertices are exact doubles, rounded outward. */
void triangle_bounds(const double *a, const double *b, const double *c, float lo[3],
                float hi[3]);

/* ---- placed.c: the shapes intersected in their own space --------------------------- */

/* Discs, cylinders, cones, tori and ellipsoids are canonical shapes (a unit
** disc, cylinder, cone, torus, sphere) placed by an affine map: the ray is
** taken into canonical space, solved there, and the hit taken back. */
typedef struct {
    affine   x;        /* canonical space to the world */
    lc_shape shape;    /* as given: what lists, moves and scales */
    double   k0, k1;   /* the kind's canonical parameters */
    double   area;     /* world surface area (the seed's centre model); emitters
                       ** only (shape_prepare_emitter), else 0 */
} placed_geom;

/* A world ray in canonical space, its direction made unit: canonical
** distances are `scale` times the world's. */
typedef struct {
    ray    r;
    double scale;
    double lo, hi;     /* the world's (tmin, tmax), canonical */
    double near;       /* a root nearer than this may be the surface the ray left */
} placed_ray;

/* to_shape: canonical space to the shape as its fields say (the kind's own
** frame); the shape's xf, when moved, follows it. */
lc_status placed_make(const lc_shape *s, const lc_transform *to_shape, placed_geom *g,
                      lc_error *err);
int       placed_ray_init(const placed_geom *g, const ray *r, double tmin, double tmax,
                          placed_ray *pr);
/* The canonical hit at distance s, point p (within perr) with normal n, in
** the world. */
void      placed_finish(const placed_geom *g, const placed_ray *pr, double s, lc_vec3 p,
                        lc_vec3 perr, lc_vec3 n, hit *h);
/* Bounds: canonical points (x, y) of radius rho at heights z0..z1 along
** canonical z, for axial shapes; a whole canonical box otherwise. */
void      placed_bounds_axial(const placed_geom *g, double rho0, double rho1, double z0,
                              double z1, float lo[3], float hi[3]);
/* An axial kind's to_shape: canonical x and y scaled by r across a frame
** around the axis (made unit), canonical z to z, the origin to origin. */
lc_transform placed_axial(lc_vec3 origin, lc_vec3 axis, double r, lc_vec3 z);
/* The nearer of best (0: none) and where canonical ray r meets the caps of
** an axial kind, z = 0 of radius r0 and z = 1 of radius r1 (0: no cap),
** inside pr's span; *part becomes 1 (bottom) or 2 (top) when one is. */
static inline double placed_caps(const ray *r, const placed_ray *pr, double r0, double r1,
                                 double best, int *part)
{
    for (int c = 0; c < 2; c++) {
        double rad = c ? r1 : r0;
        double s = (c - r->o.z) / r->d.z;
        if (rad == 0 || !(s > pr->lo && s < pr->hi) || (best != 0 && !(s < best)))
            continue;
        double x = r->o.x + s * r->d.x, y = r->o.y + s * r->d.y;
        if (x * x + y * y <= rad * rad) {
            best = s;
            *part = c ? 2 : 1;
        }
    }
    return best;
}
/* The shared checks: a moved shape's xf, an axis, a positive length. */
lc_status placed_check_xf(const lc_shape *s, const char *kind, lc_error *err);
lc_status placed_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err);
void      placed_scale(lc_shape *s, double k, lc_vec3 offset, int scales_u);
/* A world point in canonical space; the turn 0..1 of (x, y) about the
** origin, 0.5 along +x. */
lc_vec3   placed_canonical(const placed_geom *g, lc_vec3 p);
double    placed_turn(double x, double y);
/* World area of a canonical parametric patch: sum of |M ta x M tb| da db. */
double    placed_patch_area(const placed_geom *g,
                            void (*patch)(const placed_geom *, double, double, lc_vec3 *,
                                          lc_vec3 *, lc_vec3 *),
                            int n);

/* One sample of a placed light: a canonical point p with tangents ta, tb
** (their cross product's length the canonical area element for the
** sample's share of the parameter square), turned into a light sample, 0
** when the shape itself hides it from `from` (`visible`: the kind's own
** distance test). */
typedef double (*placed_t_fn)(const placed_geom *g, const ray *r, double tmin, double tmax);
int       placed_light_sample(const placed_geom *g, placed_t_fn visible, lc_vec3 p,
                              lc_vec3 ta, lc_vec3 tb, double weight, lc_vec3 from,
                              uint32_t S, light_sample *out);

/* disc.c: the unit disc in z = 0, holed to k0 (inner / outer radius). */
lc_status disc_check(const lc_shape *s, lc_error *err);
void      disc_prepare(const lc_shape *s, placed_geom *g);
double    disc_area(const placed_geom *g);    /* the world area, numerically */
double    disc_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       disc_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      disc_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      disc_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       disc_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                            light_sample *out);

/* cylinder.c: x^2 + y^2 = 1, 0 <= z <= 1, capped when the shape says. */
lc_status cylinder_check(const lc_shape *s, lc_error *err);
void      cylinder_prepare(const lc_shape *s, placed_geom *g);
double    cylinder_area(const placed_geom *g);    /* the world area, numerically */
double    cylinder_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       cylinder_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      cylinder_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      cylinder_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       cylinder_light_sample(const placed_geom *g, lc_vec3 p, const double u[2],
                                uint32_t S, light_sample *out);

/* cone.c: x^2 + y^2 = (k0 + (k1 - k0) z)^2, 0 <= z <= 1, max(k0, k1) = 1. */
lc_status cone_check(const lc_shape *s, lc_error *err);
void      cone_prepare(const lc_shape *s, placed_geom *g);
double    cone_area(const placed_geom *g);    /* the world area, numerically */
double    cone_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       cone_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      cone_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      cone_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       cone_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                            light_sample *out);

/* torus.c: around the z axis, major radius 1, minor k0 < 1; a quartic. */
lc_status torus_check(const lc_shape *s, lc_error *err);
void      torus_prepare(const lc_shape *s, placed_geom *g);
double    torus_area(const placed_geom *g);    /* the world area, numerically */
double    torus_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       torus_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      torus_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      torus_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       torus_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                             light_sample *out);
/* The canonical roots (up to 4, ascending) of the ray's quartic in (lo, hi). */
int       torus_roots(double minor, const ray *r, double lo, double hi, double roots[4]);
/* Every root beyond tmin at once (CSG leaves want them all: one quartic, not
** one per root), with the canonical ray in *pr; each root as a hit. */
int       torus_all_roots(const placed_geom *g, const ray *r, double tmin,
                          placed_ray *pr, double roots[4]);
int       torus_root_hit(const placed_geom *g, const placed_ray *pr, double s, hit *h);

/* ellipsoid.c: the unit sphere, placed. */
lc_status ellipsoid_check(const lc_shape *s, lc_error *err);
void      ellipsoid_prepare(const lc_shape *s, placed_geom *g);
double    ellipsoid_area(const placed_geom *g);    /* the world area, numerically */
double    ellipsoid_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       ellipsoid_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      ellipsoid_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      ellipsoid_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       ellipsoid_light_sample(const placed_geom *g, lc_vec3 p, const double u[2],
                                 uint32_t S, light_sample *out);

/* ---- The dispatch (shape.c) --------------------------------------------------------- */

/* What one emitter needs at one shaded point, set by shape_light_begin. */
typedef union {
    sphere_light sphere;
    quad_light   quad;
    box_light    box;
} light_setup;

size_t    shape_geom_size(lc_shape_kind k);
unsigned  shape_prim_kind(lc_shape_kind k);
/* The shape kind of a primitive kind; LC_SHAPE_KINDS for a mesh's triangle. */
lc_shape_kind shape_kind_of_prim(unsigned prim_kind);
int       shape_bounded(lc_shape_kind k);           /* 0: tested one by one */
int       shape_can_emit(lc_shape_kind k);          /* 0: never a light */
void      shape_prepare(const lc_shape *s, void *geom);
/* What an emitter needs beyond shape_prepare: a placed shape's world area
** (4096 patches of a parametric integral for the curved kinds: 0.13 ms a
** cylinder, paid only by the shapes that glow). */
void      shape_prepare_emitter(lc_shape_kind k, void *geom);
void      shape_describe(lc_shape_kind k, const void *geom, lc_shape *out);
/* The shape scaled by k about the origin, then moved by offset. */
void      shape_scale(lc_shape *s, double k, lc_vec3 offset);
void      shape_bounds(lc_shape_kind k, const void *geom, float lo[3], float hi[3]);
/* Texture coordinates of the point p on the shape. */
void      shape_uv(lc_shape_kind k, const void *geom, lc_vec3 p, double uv[2]);
/* The seed's model: where its one shadow ray aims, and for a point at
** distance d along unit l from that target the irradiance over pi L. */
lc_vec3   shape_light_target(lc_shape_kind k, const void *geom);
double    shape_light_centre(lc_shape_kind k, const void *geom, lc_vec3 l, double d);
/* Sampled: 0 when the shape lights nothing at p (p on or inside it, in its
** plane, or it lies wholly below the horizon of n); then sample u of S,
** 0 when that one adds nothing. */
int       shape_light_begin(lc_shape_kind k, const void *geom, lc_vec3 p, lc_vec3 n,
                            light_setup *ls);
int       shape_light_sample(lc_shape_kind k, const void *geom, const light_setup *ls,
                             lc_vec3 p, const double u[2], uint32_t S, light_sample *out);
/* For MIS with BSDF sampling: the density a sample of S = 1 gave direction
** d from p (normal n) to the point at distance dist on the shape, -1 where
** the kind's density is not known (shape_light_mis 0: its samples take all
** the weight). */
double    shape_light_pdf(lc_shape_kind k, const void *geom, lc_vec3 p, lc_vec3 n,
                          lc_vec3 d, double dist);
int       shape_light_mis(lc_shape_kind k);

/* ---- A scene's shapes of one kind ----------------------------------------------------- */

/* Prepared when added: the render reads them as they are. id[i] is what
** lc_scene_add_* returned (ids grow with each add, so the list is sorted by
** id). */
typedef struct {
    unsigned char *geom;   /* n prepared shapes, size bytes each */
    int    *material, *id;
    size_t  size, n, cap;
} shape_list;

static inline const void *shape_at(const shape_list *l, size_t i)
{
    return l->geom + i * l->size;
}

#endif
