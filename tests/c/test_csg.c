/* test_csg.c: CSG objects: point classification against closed-form insides
** for every leaf kind and operation, distances through known configurations
** (a lens, a dent seen through its hole, a camera inside), coincident and
** tangent cutters that leave the object's own hits bit for bit, nested and
** moved trees, a mesh leaf against the same box, open meshes refused, and
** spawned rays that never meet the leaf they left, at every scale. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "base/interrupt.h"
#include "scene/scene.h"
#include "helpers.h"
#include "scene/compile.h"
#include "render/plan.h"
#include "scene/intersect.h"
#include "scene/csg.h"

/* ---- helpers ---------------------------------------------------------------- */

static uint64_t rng = 88172645463325252ull;
static double uniform(void)                      /* [0, 1) */
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

static lc_vec3 unit_random(void)
{
    for (;;) {
        lc_vec3 v = v3(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
        double l = v3_len(v);
        if (l > 0.1 && l <= 1)
            return v3_mul(v, 1 / l);
    }
}

static lc_csg_node op(lc_csg_op o, int count)
{
    lc_csg_node n;
    memset(&n, 0, sizeof n);
    n.op = o;
    n.count = count;
    return n;
}

static lc_csg_node leaf(lc_shape s, int material)
{
    lc_csg_node n = op(LC_CSG_SHAPE, 0);
    n.shape = s;
    n.material = material;
    n.transform = lc_transform_identity();
    return n;
}

static lc_shape sphere(lc_vec3 c, double r)
{
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_SPHERE;
    s.p = c;
    s.radius = r;
    return s;
}

static lc_shape box(lc_vec3 lo, lc_vec3 hi)
{
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_BOX;
    s.p = lo;
    s.u = v3(hi.x - lo.x, 0, 0);
    s.v = v3(0, hi.y - lo.y, 0);
    s.w = v3(0, 0, hi.z - lo.z);
    return s;
}

/* A scene holding materials 0..7 and the one CSG object; compiled. */
static lc_scene *csg_scene(const lc_csg_node *nodes, size_t n)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    for (int i = 0; i < 8; i++) {
        lc_material m = lc_material_default();
        m.color = rgb(0.1f * (float)i, 0.5f, 0.5f);
        lc_scene_add_material(s, &m, &err);
    }
    if (lc_scene_add_csg(s, nodes, n, &err) < 0)
        fail_msg("add: %s (field '%s')", err.msg, err.field);
    if (plan_scene(s, NULL, interrupt_count(), &err))
        fail_msg("compile: %s", err.msg);
    return s;
}

static void compile_or_fail(lc_scene *s)
{
    lc_error err;
    if (plan_scene(s, NULL, interrupt_count(), &err))
        fail_msg("compile: %s", err.msg);
}

static int trace(const lc_scene *s, ray r, hit *h)
{
    bvh_counts c = {0, 0, 0};
    return intersect_closest(s, &r, HUGE_VAL, h, &c);
}

static void same_vec(lc_vec3 a, lc_vec3 b, double tol, const char *what)
{
    if (!(fabs(a.x - b.x) <= tol && fabs(a.y - b.y) <= tol && fabs(a.z - b.z) <= tol))
        fail_msg("%s: (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)", what, a.x,
                 a.y, a.z, b.x, b.y, b.z);
}

/* ---- leaves with closed-form insides ------------------------------------------ */

/* A leaf and how far inside it a point is (> 0 inside, < 0 outside, of the
** order of a distance: points where it is nearly 0 are not classified). */
typedef struct {
    lc_csg_node node;
    double (*inside)(const lc_csg_node *n, lc_vec3 p);
} test_leaf;

static double in_sphere(const lc_csg_node *n, lc_vec3 p)
{
    return n->shape.radius - v3_len(v3_sub(p, n->shape.p));
}

static double in_box(const lc_csg_node *n, lc_vec3 p)
{
    const lc_shape *s = &n->shape;
    double det = v3_dot(s->u, v3_cross(s->v, s->w));
    lc_vec3 q = v3_sub(p, s->p);
    double a[3] = {v3_dot(q, v3_cross(s->v, s->w)) / det,
                   v3_dot(q, v3_cross(s->w, s->u)) / det,
                   v3_dot(q, v3_cross(s->u, s->v)) / det};
    double m = HUGE_VAL;
    for (int k = 0; k < 3; k++)
        m = fmin(m, fmin(a[k], 1 - a[k]));
    return m;
}

/* Axial shapes: s along the axis (0..1), rho across, radius at s. */
static double in_axial(const lc_csg_node *n, lc_vec3 p)
{
    const lc_shape *s = &n->shape;
    lc_vec3 q = v3_sub(p, s->p);
    double h = v3_dot(q, s->u) / v3_dot(s->u, s->u);
    double rho = v3_len(v3_madd(q, s->u, -h));
    double r = s->kind == LC_CYLINDER ? s->radius
                                      : s->radius + (s->radius2 - s->radius) * h;
    return fmin(fmin(h, 1 - h) * v3_len(s->u), r - rho);
}

static double in_torus(const lc_csg_node *n, lc_vec3 p)
{
    const lc_shape *s = &n->shape;
    lc_vec3 a = v3_norm(s->u), q = v3_sub(p, s->p);
    double h = v3_dot(q, a), rho = v3_len(v3_madd(q, a, -h));
    return s->radius2 - sqrt((rho - s->radius) * (rho - s->radius) + h * h);
}

static double in_ellipsoid(const lc_csg_node *n, lc_vec3 p)
{
    const lc_shape *s = &n->shape;
    lc_vec3 q = v3_sub(p, s->p);
    double f = q.x * q.x / (s->u.x * s->u.x) + q.y * q.y / (s->u.y * s->u.y) +
               q.z * q.z / (s->u.z * s->u.z);
    return (1 - sqrt(f)) * fmin(s->u.x, fmin(s->u.y, s->u.z));
}

/* The cube [-h, h]^3 as 12 faces; `inward` winds them the other way. */
static lc_mesh *cube_mesh(double h, int inward, int drop)
{
    lc_error err;
    lc_mesh *m = lc_mesh_new(&err);
    double v[8][3];
    for (int i = 0; i < 8; i++) {
        v[i][0] = i & 1 ? h : -h;
        v[i][1] = i & 2 ? h : -h;
        v[i][2] = i & 4 ? h : -h;
    }
    /* Outward: each face's corners counter-clockwise seen from outside. */
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    uint32_t f[36];
    int nf = 0;
    for (int q = 0; q < 6; q++) {
        const uint32_t *c = quads[q];
        uint32_t t[2][3] = {{c[0], c[1], c[2]}, {c[0], c[2], c[3]}};
        for (int k = 0; k < 2; k++) {
            if (q * 2 + k == drop)
                continue;
            f[3 * nf] = t[k][0];
            f[3 * nf + 1] = inward ? t[k][2] : t[k][1];
            f[3 * nf + 2] = inward ? t[k][1] : t[k][2];
            nf++;
        }
    }
    lc_mesh_add_vertices(m, &v[0][0], 8, &err);
    lc_mesh_add_faces(m, f, (size_t)nf, &err);
    return m;
}

static lc_mesh *the_cube;

static double in_mesh(const lc_csg_node *n, lc_vec3 p)
{
    lc_transform inv;
    lc_error err;
    lc_transform_inverse(&n->transform, &inv, &err);
    lc_vec3 q = lc_transform_point(&inv, p);
    return 0.7 - fmax(fabs(q.x), fmax(fabs(q.y), fabs(q.z)));
}

static test_leaf test_leaves(int k)
{
    lc_shape s;
    memset(&s, 0, sizeof s);
    test_leaf t;
    switch (k) {
    case 0:
        t.node = leaf(sphere(v3(0.2, 0.1, 0), 1), 1);
        t.inside = in_sphere;
        return t;
    case 1: {
        lc_transform r;
        lc_transform_rotate(v3(1, 1, 1), 25, &r, NULL);
        s.kind = LC_BOX;
        s.p = v3(-0.8, -0.7, -0.9);
        s.u = lc_transform_vector(&r, v3(1.5, 0, 0));
        s.v = lc_transform_vector(&r, v3(0, 1.4, 0));
        s.w = lc_transform_vector(&r, v3(0, 0, 1.6));
        t.inside = in_box;
        break;
    }
    case 2:
        s.kind = LC_CYLINDER;
        s.p = v3(0, -1.2, 0);
        s.u = v3(0, 2.4, 0.3);
        s.radius = 0.6;
        s.caps = 1;
        t.inside = in_axial;
        break;
    case 3:
        s.kind = LC_CONE;
        s.p = v3(-1, 0, 0);
        s.u = v3(2.2, 0.2, 0);
        s.radius = 0.9;
        s.radius2 = 0.2;
        s.caps = 1;
        t.inside = in_axial;
        break;
    case 4:
        s.kind = LC_TORUS;
        s.p = v3(0, 0, 0.1);
        s.u = v3(0, 0.3, 1);
        s.radius = 0.9;
        s.radius2 = 0.35;
        t.inside = in_torus;
        break;
    case 5:
        s.kind = LC_ELLIPSOID;
        s.p = v3(0.1, 0, 0);
        s.u = v3(1.2, 0.6, 0.8);
        t.inside = in_ellipsoid;
        break;
    default: {
        lc_csg_node n = op(LC_CSG_MESH, 0);
        lc_transform r, tr = lc_transform_translate(v3(0.1, 0, 0));
        lc_transform_rotate(v3(0, 0, 1), 30, &r, NULL);
        n.mesh = the_cube;
        n.transform = lc_transform_compose(&tr, &r);
        n.material = 7;
        t.node = n;
        t.inside = in_mesh;
        return t;
    }
    }
    t.node = leaf(s, k + 1);
    return t;
}
#define TEST_LEAVES 7

/* The set of op over the values v[0, n). */
static int combine(lc_csg_op o, const int *v, int n)
{
    int r = v[0], rest = 0;
    for (int k = 1; k < n; k++) {
        if (o == LC_CSG_INTERSECTION)
            r = r && v[k];
        else
            rest = rest || v[k];
    }
    if (o == LC_CSG_DIFFERENCE)
        return r && !rest;
    return o == LC_CSG_INTERSECTION ? r : r || rest;
}

/* Whether p is inside the object by the sweep: its first surface along a
** random direction is one the ray leaves by. */
static int inside_by_ray(const lc_scene *s, lc_vec3 p)
{
    ray r = mkray_unit(p, unit_random());
    hit h;
    return trace(s, r, &h) && v3_dot(h.n, r.d) > 0;
}

/* Classifies random points of [-2, 2]^3 and checks them against the
** closed forms; points within 1e-6 of a leaf's surface are skipped. Also:
** from outside, the any-hit test agrees with the nearest hit. */
static void classify(const lc_csg_node *nodes, size_t n, const test_leaf *const *leaves,
                     int nl, int (*truth)(const int *in), const char *what)
{
    lc_scene *s = csg_scene(nodes, n);
    int tested = 0, in_count = 0;
    for (int i = 0; i < 4000; i++) {
        lc_vec3 p = v3(4 * uniform() - 2, 4 * uniform() - 2, 4 * uniform() - 2);
        int in[8], skip = 0;
        for (int k = 0; k < nl; k++) {
            double d = leaves[k]->inside(&leaves[k]->node, p);
            skip |= fabs(d) < 1e-6;
            in[k] = d > 0;
        }
        if (skip)
            continue;
        tested++;
        int want = truth(in), got = inside_by_ray(s, p);
        in_count += want;
        if (got != want)
            fail_msg("%s: point (%.17g, %.17g, %.17g) is %s, the sweep says %s", what,
                     p.x, p.y, p.z, want ? "inside" : "outside",
                     got ? "inside" : "outside");
        if (!want) {
            ray r = mkray_unit(p, unit_random());
            double tmax = 3 * uniform();
            hit h;
            bvh_counts c = {0, 0, 0};
            int near_hit = intersect_closest(s, &r, tmax, &h, &c);
            if (intersect_occluded(s, &r, tmax, &c) != near_hit)
                fail_msg("%s: any-hit and nearest hit disagree from (%g, %g, %g)", what,
                         p.x, p.y, p.z);
        }
    }
    if (tested < 3000 || in_count < 20)
        fail_msg("%s: only %d points tested, %d inside", what, tested, in_count);
    lc_scene_free(s);
}

static const test_leaf *tl[3];
static lc_csg_op tl_op;
static int truth_pair(const int *in) { return combine(tl_op, in, 2); }
static int truth_classic(const int *in)       /* (a & b) - (c | d) */
{
    return in[0] && in[1] && !(in[2] || in[3]);
}
static int truth_nested(const int *in)        /* a - (b - c) */
{
    return in[0] && !(in[1] && !in[2]);
}

/* A union at the top is a group: every operand's surfaces are drawn, so
** its nearest hit is the nearer of its operands' own. */
static void union_is_a_group(const lc_csg_node *nodes, const char *what)
{
    lc_scene *s = csg_scene(nodes, 3);
    lc_scene *parts[2];
    for (int k = 0; k < 2; k++)
        parts[k] = csg_scene(nodes + 1 + k, 1);
    for (int i = 0; i < 4000; i++) {
        lc_vec3 p = v3(4 * uniform() - 2, 4 * uniform() - 2, 4 * uniform() - 2);
        ray r = mkray_unit(p, unit_random());
        hit h, a, b;
        int k = trace(s, r, &h);
        int ka = trace(parts[0], r, &a), kb = trace(parts[1], r, &b);
        double want = ka && kb ? fmin(a.t, b.t) : ka ? a.t : kb ? b.t : 0;
        if (k != (ka || kb) || (k && h.t != want))
            fail_msg("%s: ray %d: %.17g, its operands' nearest %.17g", what, i,
                     k ? h.t : 0, want);
    }
    for (int k = 0; k < 2; k++)
        lc_scene_free(parts[k]);
    lc_scene_free(s);
}

/* Every operation on every pair of leaf kinds (each leaf the first operand
** once), then nested trees; merge is the union's set. */
static void truth_tables(void **state)
{
    (void)state;
    static const lc_csg_op ops[] = {LC_CSG_UNION, LC_CSG_MERGE, LC_CSG_INTERSECTION,
                                    LC_CSG_DIFFERENCE};
    test_leaf all[TEST_LEAVES];
    for (int k = 0; k < TEST_LEAVES; k++)
        all[k] = test_leaves(k);
    for (int o = 0; o < 4; o++)
        for (int a = 0; a < TEST_LEAVES; a++) {
            int b = (a + 1 + o) % TEST_LEAVES;
            lc_csg_node nodes[3] = {op(ops[o], 2), all[a].node, all[b].node};
            tl[0] = &all[a];
            tl[1] = &all[b];
            tl_op = ops[o];
            char what[80];
            snprintf(what, sizeof what, "%s of leaves %d and %d", lc_csg_op_name(ops[o]),
                     a, b);
            if (ops[o] == LC_CSG_UNION)
                union_is_a_group(nodes, what);
            else
                classify(nodes, 3, tl, 2, truth_pair, what);
        }
    /* (box & sphere) - (cylinder | cone) */
    const test_leaf *four[4] = {&all[1], &all[0], &all[2], &all[3]};
    lc_csg_node classic[7] = {op(LC_CSG_DIFFERENCE, 2), op(LC_CSG_INTERSECTION, 2),
                              all[1].node, all[0].node, op(LC_CSG_UNION, 2), all[2].node,
                              all[3].node};
    classify(classic, 7, four, 4, truth_classic, "(box & sphere) - (cylinder | cone)");
    /* ellipsoid - (mesh - torus) */
    const test_leaf *three[3] = {&all[5], &all[6], &all[4]};
    lc_csg_node nested[5] = {op(LC_CSG_DIFFERENCE, 2), all[5].node,
                             op(LC_CSG_DIFFERENCE, 2), all[6].node, all[4].node};
    classify(nested, 5, three, 3, truth_nested, "ellipsoid - (mesh - torus)");
}

/* ---- known configurations ------------------------------------------------------ */

/* Two unit spheres 1 apart along x: the lens is entered through the farther
** sphere's surface, at the distance the closed form gives, with its
** material and normal. */
static void intersection_of_two_spheres(void **state)
{
    (void)state;
    lc_csg_node nodes[3] = {op(LC_CSG_INTERSECTION, 2), leaf(sphere(v3(0, 0, 0), 1), 1),
                            leaf(sphere(v3(1, 0, 0), 1), 2)};
    lc_scene *s = csg_scene(nodes, 3);
    const double xy[][2] = {{0.5, 0}, {0.3, 0.2}, {0.8, -0.1}, {0.5, 0.6}};
    for (int i = 0; i < 4; i++) {
        double x = xy[i][0], y = xy[i][1];
        double za = sqrt(1 - x * x - y * y), zb = sqrt(1 - (x - 1) * (x - 1) - y * y);
        double z = -fmin(za, zb);
        hit h;
        if (!trace(s, mkray_unit(v3(x, y, -5), v3(0, 0, 1)), &h))
            fail_msg("ray %d missed the lens", i);
        near(h.t, 5 + z, 1e-14, "entry distance");
        /* x = 0.5: both at once, one event; the first operand's face shows */
        if (h.material != (za <= zb ? 1 : 2))
            fail_msg("ray %d: material %d, expected %d", i, h.material,
                     za <= zb ? 1 : 2);
        lc_vec3 c = za <= zb ? v3(0, 0, 0) : v3(1, 0, 0);
        same_vec(h.n, v3_sub(v3(x, y, z), c), 1e-14, "normal");
        /* and out through the nearer sphere */
        ray out = {spawn_origin(&h, v3(0, 0, 1)), v3(0, 0, 1)};
        hit h2;
        if (!trace(s, out, &h2))
            fail_msg("ray %d never left the lens", i);
        near(h2.p.z, fmin(za, zb), 1e-14, "exit");
    }
    /* Outside the lens but inside one sphere: nothing but the lens. */
    hit h;
    if (trace(s, mkray_unit(v3(-0.5, 0, -5), v3(0, 0, 1)), &h))
        fail_msg("a ray through sphere 1 alone hit the lens at %g", h.t);
    lc_scene_free(s);
}

/* A box with a hemispherical dent in its z = -1 face (a sphere of radius
** 0.5 centred on it): through the hole a ray sees the dent's floor, the
** sphere's far side, its normal pointing out of the box (toward the
** sphere's centre), in the cutter's material or, with cut_object, the
** box's; beside the hole, the face. */
static void box_minus_sphere_through_the_hole(void **state)
{
    (void)state;
    for (int cut_object = 0; cut_object < 2; cut_object++) {
        lc_csg_node nodes[3] = {op(LC_CSG_DIFFERENCE, 2),
                                leaf(box(v3(-1, -1, -1), v3(1, 1, 1)), 3),
                                leaf(sphere(v3(0, 0, -1), 0.5), 4)};
        nodes[0].cut_object = cut_object;
        lc_scene *s = csg_scene(nodes, 3);
        const double xy[][2] = {{0.2, 0}, {0, 0}, {-0.3, 0.25}, {0.1, -0.45}};
        for (int i = 0; i < 4; i++) {
            double x = xy[i][0], y = xy[i][1], r2 = x * x + y * y;
            double z = -1 + sqrt(0.25 - r2);
            hit h;
            if (!trace(s, mkray_unit(v3(x, y, -5), v3(0, 0, 1)), &h))
                fail_msg("ray %d went through the box", i);
            near(h.t, 5 + z, 1e-14, "the dent's floor");
            same_vec(h.n, v3_mul(v3(-x, -y, -(z + 1)), 2), 1e-14, "its normal");
            if (h.material != (cut_object ? 3 : 4))
                fail_msg("dent: material %d, expected %d", h.material,
                         cut_object ? 3 : 4);
            if (PRIM_KIND(h.shape) != PRIM_CSG_CUT || h.instance != 3)
                fail_msg("dent: hit kind %u, node %u", PRIM_KIND(h.shape),
                         h.instance - 1);
        }
        hit h;
        if (!trace(s, mkray_unit(v3(0.7, 0.1, -5), v3(0, 0, 1)), &h))
            fail_msg("missed the face beside the hole");
        if (h.t != 4 || h.p.z != -1 || h.n.z != -1 || h.material != 3)
            fail_msg("face: t %.17g, z %.17g, n.z %g, material %d", h.t, h.p.z, h.n.z,
                     h.material);
        lc_scene_free(s);
    }
}

/* Rays of every direction from a point: a box's hits, and the same hits on
** another scene, bit for bit. */
static void same_hits(const lc_scene *a, const lc_scene *b, lc_vec3 from, double spread,
                      lc_vec3 at, int n, const char *what)
{
    int hits = 0;
    for (int i = 0; i < n; i++) {
        lc_vec3 target = v3_madd(at, unit_random(), spread * uniform());
        ray r = mkray_unit(from, v3_sub(target, from));
        hit ha, hb;
        int ka = trace(a, r, &ha), kb = trace(b, r, &hb);
        if (ka != kb)
            fail_msg("%s: ray %d toward (%.17g, %.17g, %.17g) %s the plain box", what, i,
                     target.x, target.y, target.z, ka ? "hit" : "missed");
        if (!ka)
            continue;
        hits++;
        if (ha.t != hb.t || memcmp(&ha.p, &hb.p, sizeof ha.p) ||
            memcmp(&ha.n, &hb.n, sizeof ha.n) ||
            memcmp(&ha.perr, &hb.perr, sizeof ha.perr) || ha.material != hb.material)
            fail_msg("%s: ray %d: t %.17g vs %.17g, n (%g %g %g) vs (%g %g %g), "
                     "material %d vs %d", what, i, hb.t, ha.t, hb.n.x, hb.n.y, hb.n.z,
                     ha.n.x, ha.n.y, ha.n.z, hb.material, ha.material);
    }
    if (hits < n / 4)
        fail_msg("%s: only %d of %d rays hit", what, hits, n);
}

static lc_scene *plain_scene(lc_shape s, int material)
{
    lc_error err;
    lc_scene *sc = lc_scene_new(&err);
    for (int i = 0; i < 8; i++) {
        lc_material m = lc_material_default();
        m.color = rgb(0.1f * (float)i, 0.5f, 0.5f);
        lc_scene_add_material(sc, &m, &err);
    }
    lc_scene_add_shape(sc, &s, material, &err);
    compile_or_fail(sc);
    return sc;
}

/* A box minus cutters flush with its faces (outside it, or touching it at
** a point): exactly the box, ray for ray, axis-aligned and rotated; a
** pocket flush with the top face opens onto its floor. */
static void coincident_and_tangent_cutters(void **state)
{
    (void)state;
    lc_shape a = box(v3(0, 0, 0), v3(1, 1, 1));
    lc_shape flush = box(v3(0.25, 0.25, 1), v3(0.75, 0.75, 2));      /* on top of it */
    lc_shape side = box(v3(1, -0.5, 0.2), v3(3, 0.5, 0.8));          /* beside it */
    lc_shape touch = sphere(v3(0.5, 0.5, 1.5), 0.5);                 /* tangent on top */
    lc_shape edge = sphere(v3(1.5, 0.5, 1.5), sqrt(0.5));            /* along an edge */
    lc_transform rot, mv = lc_transform_translate(v3(3, -2, 1)), m;
    lc_transform_rotate(v3(1, 2, 3), 37, &rot, NULL);
    m = lc_transform_compose(&mv, &rot);
    for (int moved = 0; moved < 2; moved++) {
        lc_error err;
        lc_shape sa = a, sf = flush, ss = side, st = touch, se = edge;
        if (moved) {
            lc_shape_transform(&a, &m, &sa, &err);
            lc_shape_transform(&flush, &m, &sf, &err);
            lc_shape_transform(&side, &m, &ss, &err);
            lc_shape_transform(&touch, &m, &st, &err);
            lc_shape_transform(&edge, &m, &se, &err);
        }
        lc_scene *plain = plain_scene(sa, 2);
        lc_csg_node nodes[5] = {op(LC_CSG_DIFFERENCE, 4), leaf(sa, 2), leaf(sf, 5),
                                leaf(ss, 6), leaf(st, 4)};
        lc_scene *cut = csg_scene(nodes, 5);
        lc_transform id = lc_transform_identity();
        const lc_transform *at = moved ? &m : &id;
        lc_vec3 c = lc_transform_point(at, v3(0.5, 0.5, 0.5));
        lc_vec3 top = lc_transform_point(at, v3(0.5, 0.5, 1));
        lc_vec3 eye = lc_transform_point(at, v3(0.3, -1.5, 4));
        lc_vec3 eye2 = lc_transform_point(at, v3(4, 0.6, 0.5));
        same_hits(plain, cut, eye, 1.2, c, 20000, moved ? "rotated, flush" : "flush");
        same_hits(plain, cut, eye2, 1.2, c, 20000, moved ? "rotated, beside" : "beside");
        same_hits(plain, cut, eye, 1e-6, top, 5000, moved ? "rotated, at the tangent" :
                  "at the tangent point");
        lc_scene_free(cut);
        lc_csg_node nodes2[3] = {op(LC_CSG_DIFFERENCE, 2), leaf(sa, 2), leaf(se, 4)};
        cut = csg_scene(nodes2, 3);
        lc_vec3 e = lc_transform_point(at, v3(1, 0.5, 1));
        same_hits(plain, cut, eye, 1e-4, e, 5000, moved ? "rotated, edge" : "edge");
        lc_scene_free(cut);
        lc_scene_free(plain);
    }
    /* A pocket flush with the top: its floor inside, the face outside. */
    lc_shape pocket = box(v3(0.25, 0.25, 0.5), v3(0.75, 0.75, 1));
    lc_csg_node nodes[3] = {op(LC_CSG_DIFFERENCE, 2), leaf(a, 2), leaf(pocket, 5)};
    lc_scene *s = csg_scene(nodes, 3);
    for (int i = 0; i < 2000; i++) {
        double x = uniform(), y = uniform();
        hit h;
        if (!trace(s, mkray_unit(v3(x, y, 3), v3(0, 0, -1)), &h))
            fail_msg("missed the pocketed box at (%g, %g)", x, y);
        int in = x >= 0.25 && x <= 0.75 && y >= 0.25 && y <= 0.75;
        if (h.p.z != (in ? 0.5 : 1) || h.n.z != 1 || h.material != (in ? 5 : 2))
            fail_msg("pocket at (%g, %g): z %.17g, n.z %g, material %d", x, y, h.p.z,
                     h.n.z, h.material);
    }
    lc_scene_free(s);
}

/* A box hollowed by a sphere: from inside the wall a ray sees the cavity's
** surface or the box's, their normals out of the solid; from inside the
** cavity, its wall all round, the normal toward the eye. */
static void camera_inside(void **state)
{
    (void)state;
    lc_csg_node nodes[3] = {op(LC_CSG_DIFFERENCE, 2),
                            leaf(box(v3(-2, -2, -2), v3(2, 2, 2)), 1),
                            leaf(sphere(v3(0, 0, 0), 1), 2)};
    lc_scene *s = csg_scene(nodes, 3);
    hit h;
    if (!trace(s, mkray_unit(v3(1.5, 0, 0), v3(-1, 0, 0)), &h))
        fail_msg("from the wall toward the cavity: nothing");
    near(h.t, 0.5, 1e-15, "to the cavity");
    same_vec(h.n, v3(-1, 0, 0), 1e-15, "the cavity's normal seen from the wall");
    if (h.material != 2)
        fail_msg("cavity: material %d", h.material);
    if (!trace(s, mkray_unit(v3(1.5, 0, 0), v3(1, 0, 0)), &h) || h.t != 0.5 ||
        h.n.x != 1 || h.material != 1)
        fail_msg("from the wall outward: t %g, n.x %g", h.t, h.n.x);
    for (int i = 0; i < 2000; i++) {
        lc_vec3 o = v3_mul(unit_random(), 0.5 * uniform());
        ray r = mkray_unit(o, unit_random());
        if (!trace(s, r, &h))
            fail_msg("from inside the cavity: nothing");
        near(v3_len(h.p), 1, 1e-15, "on the cavity's wall");
        if (!(v3_dot(h.n, r.d) < 0))
            fail_msg("the cavity's wall faces away from its inside");
        same_vec(h.n, v3_neg(h.p), 1e-15, "toward the centre");
    }
    lc_scene_free(s);
}

/* A nested tree moved by an affine map (rotated, sheared, scaled unevenly,
** moved far) meets the moved ray where the tree meets the ray, mapped. */
static void nested_and_moved(void **state)
{
    (void)state;
    lc_shape cyl;
    memset(&cyl, 0, sizeof cyl);
    cyl.kind = LC_CYLINDER;
    cyl.p = v3(0, 0, -2);
    cyl.u = v3(0, 0, 4);
    cyl.radius = 0.4;
    cyl.caps = 1;
    lc_shape cyl2 = cyl;
    cyl2.p = v3(-2, 0, 0);
    cyl2.u = v3(4, 0, 0);
    lc_csg_node tree[7] = {op(LC_CSG_DIFFERENCE, 2), op(LC_CSG_INTERSECTION, 2),
                           leaf(box(v3(-1, -1, -1), v3(1, 1, 1)), 1),
                           leaf(sphere(v3(0, 0, 0), 1.3), 2), op(LC_CSG_UNION, 2),
                           leaf(cyl, 3), leaf(cyl2, 4)};
    lc_transform m = {{{1.2, 0.3, 0, 1e5}, {-0.2, 0.8, 0.1, -3e4}, {0.1, 0, 2, 7}}};
    lc_csg_node moved[7];
    memcpy(moved, tree, sizeof moved);
    lc_error err;
    for (int k = 0; k < 7; k++)
        if (moved[k].op == LC_CSG_SHAPE && lc_shape_transform(&tree[k].shape, &m,
                                                              &moved[k].shape, &err))
            fail_msg("transform: %s", err.msg);
    lc_scene *a = csg_scene(tree, 7), *b = csg_scene(moved, 7);
    int hits = 0;
    for (int i = 0; i < 20000; i++) {
        lc_vec3 from = v3_mul(unit_random(), 4);
        ray r = mkray_unit(from, v3_sub(v3_mul(unit_random(), 1.2), from));
        lc_vec3 d = lc_transform_vector(&m, r.d);
        ray rm = {lc_transform_point(&m, r.o), v3_norm(d)};
        hit ha, hb;
        int ka = trace(a, r, &ha), kb = trace(b, rm, &hb);
        if (ka != kb) {
            /* A ray grazing a silhouette may go either way by rounding. */
            hit *h = ka ? &ha : &hb;
            if (fabs(v3_dot(h->n, ka ? r.d : rm.d)) < 1e-6)
                continue;
            fail_msg("ray %d %s the tree, the moved ray %s it", i, ka ? "hit" : "missed",
                     kb ? "hit" : "missed");
        }
        if (!ka)
            continue;
        hits++;
        lc_vec3 p = lc_transform_point(&m, ha.p);
        if (!(v3_len(v3_sub(p, hb.p)) < 1e-9 * 1e5) || ha.material != hb.material ||
            ha.instance != hb.instance)
            fail_msg("ray %d: (%g %g %g) vs (%g %g %g), material %d vs %d", i, p.x, p.y,
                     p.z, hb.p.x, hb.p.y, hb.p.z, ha.material, hb.material);
    }
    if (hits < 5000)
        fail_msg("only %d hits", hits);
    lc_scene_free(a);
    lc_scene_free(b);
}

/* A cube mesh minus a sphere is the box minus the sphere: same distances,
** normals and materials, outward or inward winding, on rays aimed at the
** faces' shared diagonals too. */
static void mesh_leaf_against_the_box(void **state)
{
    (void)state;
    for (int inward = 0; inward < 2; inward++) {
        lc_mesh *m = cube_mesh(1, inward, -1);
        lc_csg_node mesh_leaf = op(LC_CSG_MESH, 0);
        mesh_leaf.mesh = m;
        mesh_leaf.transform = lc_transform_identity();
        mesh_leaf.material = 1;
        lc_csg_node cutter = leaf(sphere(v3(0.6, 0.5, 0.9), 0.7), 2);
        lc_csg_node with_mesh[3] = {op(LC_CSG_DIFFERENCE, 2), mesh_leaf, cutter};
        lc_csg_node with_box[3] = {op(LC_CSG_DIFFERENCE, 2),
                                   leaf(box(v3(-1, -1, -1), v3(1, 1, 1)), 1), cutter};
        lc_scene *a = csg_scene(with_mesh, 3), *b = csg_scene(with_box, 3);
        for (int i = 0; i < 40000; i++) {
            lc_vec3 from = v3_mul(unit_random(), 5);
            lc_vec3 at = v3(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
            if (i & 1) {            /* a face's diagonal: x = y on z = 1, and so on */
                at.y = at.x;
                at.z = 1;
            }
            ray r = mkray_unit(from, v3_sub(at, from));
            hit ha, hb;
            int ka = trace(a, r, &ha), kb = trace(b, r, &hb);
            if (ka != kb) {
                hit *h = ka ? &ha : &hb;
                if (fabs(v3_dot(h->n, r.d)) < 1e-9)    /* along an edge: either way */
                    continue;
                fail_msg("winding %d, ray %d: mesh %s, box %s", inward, i,
                         ka ? "hit" : "missed", kb ? "hit" : "missed");
            }
            if (!ka)
                continue;
            if (!(fabs(ha.t - hb.t) <= 1e-14 * 5) || ha.material != hb.material ||
                !(v3_len(v3_sub(ha.n, hb.n)) < 1e-14))
                fail_msg("winding %d, ray %d: t %.17g vs %.17g, material %d vs %d, n "
                         "(%g %g %g) vs (%g %g %g)", inward, i, ha.t, hb.t, ha.material,
                         hb.material, ha.n.x, ha.n.y, ha.n.z, hb.n.x, hb.n.y, hb.n.z);
        }
        lc_scene_free(a);
        lc_scene_free(b);
        lc_mesh_free(m);
    }
}

/* Open meshes, disagreeing windings, open shapes and bad trees are refused,
** saying where. */
static void refusals(void **state)
{
    (void)state;
    lc_error err;
    lc_mesh *open = cube_mesh(1, 0, 3);
    lc_csg_node n[3] = {op(LC_CSG_DIFFERENCE, 2), op(LC_CSG_MESH, 0),
                        leaf(sphere(v3(0, 0, 0), 1), 0)};
    n[1].mesh = open;
    n[1].transform = lc_transform_identity();
    assert_int_equal(lc_csg_check(n, 3, &err), LC_EARG);
    if (!strstr(err.msg, "node 1: the mesh is open: the edge between vertices") ||
        !strstr(err.msg, "is in face"))
        fail_msg("open mesh: %s", err.msg);
    /* Face 1 turned over: its edges run the same way as its neighbours'. */
    lc_mesh *flipped = cube_mesh(1, 0, -1);
    uint32_t t = flipped->f[4];
    flipped->f[4] = flipped->f[5];
    flipped->f[5] = t;
    n[1].mesh = flipped;
    assert_int_equal(lc_csg_check(n, 3, &err), LC_EARG);
    if (!strstr(err.msg, "windings disagree"))
        fail_msg("flipped face: %s", err.msg);
    lc_shape plane;
    memset(&plane, 0, sizeof plane);
    plane.kind = LC_PLANE;
    plane.u = v3(0, 1, 0);
    n[1] = leaf(plane, 0);
    assert_int_equal(lc_csg_check(n, 3, &err), LC_EARG);
    assert_string_equal(err.msg, "node 1: a plane is not a closed solid");
    lc_shape cyl;
    memset(&cyl, 0, sizeof cyl);
    cyl.kind = LC_CYLINDER;
    cyl.u = v3(0, 1, 0);
    cyl.radius = 1;
    n[1] = leaf(cyl, 0);
    assert_int_equal(lc_csg_check(n, 3, &err), LC_EARG);
    assert_string_equal(err.msg,
                        "node 1: a cylinder without caps is not a closed solid");
    n[1] = leaf(sphere(v3(0, 0, 0), -1), 0);
    assert_int_equal(lc_csg_check(n, 3, &err), LC_EARG);
    assert_string_equal(err.field, "radius");
    n[1] = leaf(sphere(v3(0, 0, 0), 1), 0);
    assert_int_equal(lc_csg_check(n, 2, &err), LC_EARG);
    if (!strstr(err.msg, "1 operand still to come"))
        fail_msg("short tree: %s", err.msg);
    n[0].count = 1;
    assert_int_equal(lc_csg_check(n, 3, &err), LC_EARG);
    if (!strstr(err.msg, "node 2 lies past the end"))
        fail_msg("long tree: %s", err.msg);
    n[0].count = 2;
    assert_int_equal(lc_csg_check(n, 3, &err), LC_OK);
    /* A scene checks the materials too. */
    lc_scene *s = lc_scene_new(&err);
    assert_int_equal(lc_scene_add_csg(s, n, 3, &err), -1);
    assert_string_equal(err.msg, "node 1: no material 0 in this scene");
    lc_scene_free(s);
    lc_mesh_free(open);
    lc_mesh_free(flipped);
}

/* ---- spawned rays ---------------------------------------------------------------- */

/* The CSG objects of the scale tests: a box minus a sphere and a cylinder,
** a torus cut by a box, a mesh cube minus a sphere. */
static lc_scene *spawn_scene(void)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    lc_scene_add_material(s, &m, &err);
    lc_shape cyl;
    memset(&cyl, 0, sizeof cyl);
    cyl.kind = LC_CYLINDER;
    cyl.p = v3(0.5, -1, 0.5);
    cyl.u = v3(0, 3, 0);
    cyl.radius = 0.2;
    cyl.caps = 1;
    lc_csg_node a[4] = {op(LC_CSG_DIFFERENCE, 3), leaf(box(v3(0, 0, 0), v3(1, 1, 1)), 0),
                        leaf(sphere(v3(1, 1, 1), 0.6), 0), leaf(cyl, 0)};
    lc_shape tor;
    memset(&tor, 0, sizeof tor);
    tor.kind = LC_TORUS;
    tor.p = v3(3, 0.5, 0.5);
    tor.u = v3(0, 1, 0.2);
    tor.radius = 0.8;
    tor.radius2 = 0.3;
    lc_csg_node b[3] = {op(LC_CSG_INTERSECTION, 2), leaf(tor, 0),
                        leaf(box(v3(2, 0, 0), v3(4, 1, 0.8)), 0)};
    lc_csg_node c[3] = {op(LC_CSG_DIFFERENCE, 2), op(LC_CSG_MESH, 0),
                        leaf(sphere(v3(-1.5, 0.8, 0.5), 0.5), 0)};
    lc_mesh *cube = cube_mesh(0.5, 0, -1);
    c[1].mesh = cube;
    c[1].transform = lc_transform_translate(v3(-2, 0.5, 0.5));
    if (lc_scene_add_csg(s, a, 4, &err) < 0 || lc_scene_add_csg(s, b, 3, &err) < 0 ||
        lc_scene_add_csg(s, c, 3, &err) < 0)
        fail_msg("add: %s", err.msg);
    lc_mesh_free(cube);
    return s;
}

/* From points on the objects' surfaces (found by rays from around them),
** rays spawned either way never meet the leaf they left at the point they
** left (within a thousand times its error bound, with the same normal),
** and a ray leaving a convex leaf's own face outward never meets that leaf
** again: 10^5 rays at each scale 1e-4..1e6 and moved 1e7. */
static void spawned_rays_never_return(void **state)
{
    (void)state;
    const double scales[][2] = {{1e-4, 0}, {1, 0}, {1e6, 0}, {1, 1e7}};
    int rays = getenv("LANCER_PRIMITIVE_RAYS") ? atoi(getenv("LANCER_PRIMITIVE_RAYS"))
                                               : 100000;
    lc_scene *base = spawn_scene();
    for (size_t k = 0; k < sizeof scales / sizeof *scales; k++) {
        double sc = scales[k][0], T = scales[k][1];
        lc_error err;
        lc_vec3 off = v3(T, T / 2, T / 3);
        lc_scene *s = lc_scene_transformed(base, sc, off, &err);
        if (!s)
            fail_msg("transformed: %s", err.msg);
        compile_or_fail(s);
        int hits = 0, back = 0, faces = 0;
        for (int i = 0; i < rays; i++) {
            lc_vec3 at = v3_add(v3_mul(v3(-2.5 + 7 * uniform(), 1.4 * uniform() - 0.2,
                                          1.4 * uniform() - 0.2), sc), off);
            lc_vec3 from = v3_madd(at, unit_random(), 5 * sc);
            ray r = mkray_unit(from, v3_sub(at, from));
            hit h;
            if (!trace(s, r, &h))
                continue;
            hits++;
            lc_vec3 w = unit_random();
            if (i & 1)
                w = v3_dot(w, h.n) > 0 ? w : v3_neg(w);   /* out of the solid */
            ray out = {spawn_origin(&h, w), w};
            hit h2;
            if (!trace(s, out, &h2) || h2.shape != h.shape || h2.instance != h.instance)
                continue;
            if (h2.t < 1000 * v3_len(h.perr) && v3_dot(h2.n, h.n) > 1 - 1e-9)
                back++;
            if (PRIM_KIND(h.shape) == PRIM_CSG_FACE && v3_dot(w, h.n) > 0)
                faces++;
        }
        if (back || faces || hits < rays / 4)
            fail_msg("scale %g, moved %g: %d of %d spawned rays met their point again, "
                     "%d met the convex leaf they left", sc, T, back, hits, faces);
        lc_scene_free(s);
    }
    lc_scene_free(base);
}

/* Bounds: a union's and a merge's enclose their operands', an
** intersection's are their common box, a difference's its first operand's
** (not the union of all), nested alike; and every surface point found
** lies inside them. */
static void bounds_are_tight(void **state)
{
    (void)state;
    lc_shape a = sphere(v3(0, 0, 0), 1), b = sphere(v3(1.5, 0, 0), 1);
    float la[3], ha[3], lb[3], hb[3];
    sphere_geom ga, gb;
    shape_prepare(&a, &ga);
    shape_prepare(&b, &gb);
    shape_bounds(LC_SPHERE, &ga, la, ha);
    shape_bounds(LC_SPHERE, &gb, lb, hb);
    const lc_csg_op ops[] = {LC_CSG_UNION, LC_CSG_MERGE, LC_CSG_INTERSECTION,
                             LC_CSG_DIFFERENCE};
    for (int o = 0; o < 4; o++) {
        lc_csg_node n[3] = {op(ops[o], 2), leaf(a, 0), leaf(b, 0)};
        lc_error err;
        csg_tree *t = csg_build(n, 3, NULL, 0, &err);
        if (!t)
            fail_msg("build: %s", err.msg);
        float lo[3], hi[3];
        csg_bounds(t, lo, hi);
        for (int k = 0; k < 3; k++) {
            float wl = ops[o] == LC_CSG_INTERSECTION ? fmaxf(la[k], lb[k]) :
                       ops[o] == LC_CSG_DIFFERENCE ? la[k] : fminf(la[k], lb[k]);
            float wh = ops[o] == LC_CSG_INTERSECTION ? fminf(ha[k], hb[k]) :
                       ops[o] == LC_CSG_DIFFERENCE ? ha[k] : fmaxf(ha[k], hb[k]);
            if (lo[k] != wl || hi[k] != wh)
                fail_msg("%s, axis %d: [%g, %g], expected [%g, %g]",
                         lc_csg_op_name(ops[o]), k, lo[k], hi[k], wl, wh);
        }
        csg_free(t);
    }
    /* Every hit on the spawn scene's objects lies in its object's box. */
    lc_scene *s = spawn_scene();
    compile_or_fail(s);
    for (int i = 0; i < 20000; i++) {
        lc_vec3 from = v3_add(v3(0.5, 0.5, 0.5), v3_mul(unit_random(), 6));
        lc_vec3 at = v3(-2.5 + 7 * uniform(), uniform(), uniform());
        ray r = mkray_unit(from, v3_sub(at, from));
        hit h;
        if (!trace(s, r, &h))
            continue;
        float lo[3], hi[3];
        csg_bounds(s->csgs[PRIM_INDEX(h.shape)], lo, hi);
        double p[3] = {h.p.x, h.p.y, h.p.z};
        for (int k = 0; k < 3; k++)
            if (!(p[k] >= lo[k] && p[k] <= hi[k]))
                fail_msg("hit %g outside [%g, %g] on axis %d", p[k], lo[k], hi[k], k);
    }
    lc_scene_free(s);
}

/* Listing, removal and copies: the description comes back as stored. */
static void listing_and_removal(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = spawn_scene();
    lc_object objs[4];
    assert_int_equal(lc_scene_objects(s, objs, 4), 3);
    assert_int_equal(objs[0].kind, LC_OBJECT_CSG);
    assert_int_equal(objs[0].csg_nodes, 4);
    assert_int_equal(objs[0].csg[0].op, LC_CSG_DIFFERENCE);
    assert_int_equal(objs[0].csg[2].shape.kind, LC_SPHERE);
    assert_int_equal(objs[2].csg[1].op, LC_CSG_MESH);
    assert_true(objs[2].csg[1].transform.m[0][3] == -2);   /* a double: no int cast */
    assert_int_equal(lc_scene_shape_count(s), 3);
    assert_int_equal(lc_scene_remove(s, objs[1].id, &err), LC_OK);
    assert_int_equal(lc_scene_objects(s, objs, 4), 2);
    assert_int_equal(objs[1].id, 2);
    compile_or_fail(s);
    hit h;
    if (trace(s, mkray_unit(v3(3, 0.5, 5), v3(0, 0, -1)), &h))
        fail_msg("the removed torus is still hit");
    if (!trace(s, mkray_unit(v3(-2, 0.2, 5), v3(0, 0, -1)), &h) || h.t != 4)
        fail_msg("the mesh cube is not where it was");
    lc_scene_free(s);
}

int main(void)
{
    the_cube = cube_mesh(0.7, 0, -1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(truth_tables),
        cmocka_unit_test(intersection_of_two_spheres),
        cmocka_unit_test(box_minus_sphere_through_the_hole),
        cmocka_unit_test(coincident_and_tangent_cutters),
        cmocka_unit_test(camera_inside),
        cmocka_unit_test(nested_and_moved),
        cmocka_unit_test(mesh_leaf_against_the_box),
        cmocka_unit_test(refusals),
        cmocka_unit_test(spawned_rays_never_return),
        cmocka_unit_test(bounds_are_tight),
        cmocka_unit_test(listing_and_removal),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    lc_mesh_free(the_cube);
    return rc;
}
