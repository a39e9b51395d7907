/* test_primitives.c: discs, cylinders, cones, tori and ellipsoids: closed-form
** hits from outside, inside, along the axis, tangent and grazing; spawned
** rays that never meet their own surface again at any scale; bounds that
** hold every point; the torus's roots against a long-double reference. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "scene/scene.h"
#include "helpers.h"
#include "shapes/cone.h"
#include "shapes/cylinder.h"
#include "shapes/disc.h"
#include "shapes/ellipsoid.h"
#include "shapes/torus.h"

/* One shape prepared as the scene would: checked, then its geometry. */
static placed_geom prepare(lc_shape s)
{
    lc_error err;
    if (lc_shape_check(&s, &err))
        fail_msg("%s: %s", err.field, err.msg);
    placed_geom g;
    shape_prepare(&s, &g);
    return g;
}

static double t_of(lc_shape_kind k, const placed_geom *g, ray r)
{
    switch (k) {
    case LC_DISC: return disc_t(g, &r, 0, HUGE_VAL);
    case LC_CYLINDER: return cylinder_t(g, &r, 0, HUGE_VAL);
    case LC_CONE: return cone_t(g, &r, 0, HUGE_VAL);
    case LC_TORUS: return torus_t(g, &r, 0, HUGE_VAL);
    default: return ellipsoid_t(g, &r, 0, HUGE_VAL);
    }
}

static int hit_of(lc_shape_kind k, const placed_geom *g, ray r, hit *h)
{
    switch (k) {
    case LC_DISC: return disc_hit(g, &r, 0, HUGE_VAL, h);
    case LC_CYLINDER: return cylinder_hit(g, &r, 0, HUGE_VAL, h);
    case LC_CONE: return cone_hit(g, &r, 0, HUGE_VAL, h);
    case LC_TORUS: return torus_hit(g, &r, 0, HUGE_VAL, h);
    default: return ellipsoid_hit(g, &r, 0, HUGE_VAL, h);
    }
}

/* The ray must hit at distance t (relative error 1e-13) with normal n. */
static void expect(lc_shape s, lc_vec3 o, lc_vec3 d, double t, lc_vec3 n, const char *what)
{
    placed_geom g = prepare(s);
    ray r = mkray_unit(o, d);
    hit h;
    double dt = t_of(s.kind, &g, r);
    int ok = hit_of(s.kind, &g, r, &h);
    if (t == 0) {
        if (dt != 0 || ok)
            fail_msg("%s: expected no hit, got t = %.17g", what, dt);
        return;
    }
    if (!ok || fabs(h.t - t) > 1e-13 * (t + 1) || dt != h.t)
        fail_msg("%s: t %.17g (distance test %.17g), expected %.17g", what, ok ? h.t : 0,
                 dt, t);
    lc_vec3 want = v3_norm(n);
    if (fabs(v3_dot(h.n, want) - 1) > 1e-12)
        fail_msg("%s: normal (%g, %g, %g), expected (%g, %g, %g)", what, h.n.x, h.n.y,
                 h.n.z, want.x, want.y, want.z);
    if (!isfinite(h.p.x + h.p.y + h.p.z + h.perr.x + h.perr.y + h.perr.z))
        fail_msg("%s: a NaN or infinite point", what);
}

static lc_shape cylinder(int caps)
{
    lc_shape s = {.kind = LC_CYLINDER, .u = {0, 0, 2}, .radius = 1, .caps = caps};
    return s;
}

static void closed_forms(void **state)
{
    (void)state;
    /* Cylinder r = 1 along z from 0 to 2. */
    expect(cylinder(1), v3(5, 0, 1), v3(-1, 0, 0), 4, v3(1, 0, 0), "cylinder from outside");
    expect(cylinder(1), v3(0, 0, 1), v3(0, 1, 0), 1, v3(0, 1, 0), "cylinder from inside");
    expect(cylinder(1), v3(0.5, 0, -5), v3(0, 0, 1), 5, v3(0, 0, -1), "cylinder along the axis");
    expect(cylinder(0), v3(0.5, 0, -5), v3(0, 0, 1), 0, v3(0, 0, 1), "open cylinder's axis");
    expect(cylinder(0), v3(0.5, 0, 1), v3(0, 0, 1), 0, v3(0, 0, 1), "inside, along the axis");
    expect(cylinder(1), v3(0.5, 0, 1), v3(0, 0, 1), 1, v3(0, 0, 1), "inside, to the top cap");
    expect(cylinder(1), v3(5, 0, 2.5), v3(-1, 0, 0), 0, v3(1, 0, 0), "above the top");
    /* Cone base r 1 at z 0, point at z 2. */
    lc_shape cone = {.kind = LC_CONE, .u = {0, 0, 2}, .radius = 1, .radius2 = 0, .caps = 1};
    expect(cone, v3(5, 0, 1), v3(-1, 0, 0), 4.5, v3(2, 0, 1), "cone at half height");
    expect(cone, v3(0, 0, 5), v3(0, 0, -1), 3, v3(0, 0, 1), "cone's apex from above");
    expect(cone, v3(0.25, 0, -3), v3(0, 0, 1), 3, v3(0, 0, -1), "cone's base cap");
    lc_shape frustum = {.kind = LC_CONE, .p = {0, 0, -1}, .u = {0, 0, 2}, .radius = 0.5,
                        .radius2 = 1, .caps = 1};
    expect(frustum, v3(0, 0, 0), v3(1, 0, 0), 0.75, v3(2, 0, -0.5), "frustum from inside");
    /* Disc of radius 1 with a hole of 0.5, facing z. */
    lc_shape disc = {.kind = LC_DISC, .u = {0, 0, 1}, .radius = 1, .radius2 = 0.5};
    expect(disc, v3(0.75, 0, 5), v3(0, 0, -1), 5, v3(0, 0, 1), "disc's ring");
    expect(disc, v3(0.25, 0, 5), v3(0, 0, -1), 0, v3(0, 0, 1), "disc's hole");
    expect(disc, v3(0.75, 0, 0), v3(1, 0, 0), 0, v3(0, 0, 1), "in the disc's plane");
    /* Torus major 2, minor 0.5, around z. */
    lc_shape torus = {.kind = LC_TORUS, .u = {0, 0, 1}, .radius = 2, .radius2 = 0.5};
    expect(torus, v3(5, 0, 0), v3(-1, 0, 0), 2.5, v3(1, 0, 0), "torus from outside");
    expect(torus, v3(0, 0, 5), v3(0, 0, -1), 0, v3(0, 0, 1), "torus's hole, along the axis");
    expect(torus, v3(0, 0, 0), v3(0, 1, 0), 1.5, v3(0, -1, 0), "torus from its centre");
    expect(torus, v3(2, 0, 0), v3(0, 0, 1), 0.5, v3(0, 0, 1), "torus from inside the tube");
    expect(torus, v3(2, 0, 5), v3(0, 0, -1), 4.5, v3(0, 0, 1), "torus's top from above");
    /* Ellipsoid radii 1, 2, 3; and sheared. */
    lc_shape ell = {.kind = LC_ELLIPSOID, .u = {1, 2, 3}};
    expect(ell, v3(0, 0, -10), v3(0, 0, 1), 7, v3(0, 0, -1), "ellipsoid along z");
    expect(ell, v3(0, 5, 0), v3(0, -1, 0), 3, v3(0, 1, 0), "ellipsoid along y");
    expect(ell, v3(0, 0, 0), v3(1, 0, 0), 1, v3(1, 0, 0), "ellipsoid from inside");
    lc_shape sheared = {.kind = LC_ELLIPSOID, .u = {1, 1, 1}, .moved = 1,
                        .xf = {{{1, 1, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}}};
    /* x' = x + y: the line y = 0 still meets the sphere at x = -1, with the
    ** normal the inverse transpose of (-1, 0, 0): (-1, 1, 0). */
    expect(sheared, v3(-5, 0, 0), v3(1, 0, 0), 4, v3(-1, 1, 0), "sheared unit sphere");
}

/* Tangent and grazing rays: a hit or a miss, never NaN, and the distance
** test and the full test agree. */
static void tangents_and_grazing(void **state)
{
    (void)state;
    lc_shape shapes[] = {
        cylinder(1),
        {.kind = LC_CONE, .u = {0, 0, 2}, .radius = 1, .radius2 = 0.2, .caps = 1},
        {.kind = LC_TORUS, .u = {0, 0, 1}, .radius = 2, .radius2 = 0.5},
        {.kind = LC_ELLIPSOID, .u = {1, 2, 3}},
        {.kind = LC_DISC, .u = {0, 0, 1}, .radius = 1},
    };
    for (size_t k = 0; k < sizeof shapes / sizeof *shapes; k++) {
        placed_geom g = prepare(shapes[k]);
        for (int i = -200; i <= 200; i++) {
            double e = i * 1e-15;
            ray rays[] = {
                mkray_unit(v3(-5, 1 + e, 1), v3(1, 0, 0)),   /* tangent to the side */
                mkray_unit(v3(-5, 0, 2 + e), v3(1, 0, 0)),   /* along the top rim */
                mkray_unit(v3(-5, 2.5 + e, 0), v3(1, 0, 0)), /* torus: outer equator */
                mkray_unit(v3(-5, 0, 0.5 + e), v3(1, 0, 0)), /* torus: top, edge-on */
                mkray_unit(v3(1 + e, 0, -5), v3(0, 0, 1)),   /* along the side */
                mkray_unit(v3(0, 0, -5), v3(e, 0, 1)),       /* along the axis */
            };
            for (size_t j = 0; j < sizeof rays / sizeof *rays; j++) {
                hit h;
                double t = t_of(shapes[k].kind, &g, rays[j]);
                int ok = hit_of(shapes[k].kind, &g, rays[j], &h);
                if ((t > 0) != ok || (ok && (h.t != t || !isfinite(h.n.x + h.n.y + h.n.z +
                                                                    h.p.x + h.p.y + h.p.z))))
                    fail_msg("%s, ray %zu, offset %g: distance %g, hit %d", lc_shape_kind_name(
                             shapes[k].kind), j, e, t, ok);
            }
        }
    }
}

static uint64_t rng = 88172645463325252ull;
static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (rng >> 11) * (1.0 / 9007199254740992.0);
}

static lc_vec3 unit_random(void)
{
    double z = 2 * uniform() - 1, phi = 2 * PI * uniform(), r = sqrt(1 - z * z);
    return v3(r * cos(phi), r * sin(phi), z);
}

static lc_vec3 unit_random(void);

/* A point of the shape's surface: one sampled as the light sampler draws
** them (so every part, caps and all), seen from far off in a random
** direction (the sampler gives only what that viewpoint sees). */
static lc_vec3 surface_point(lc_shape_kind k, const placed_geom *g)
{
    for (;;) {
        light_sample ls;
        double u[2] = {uniform(), uniform()};
        lc_vec3 far = lc_transform_point(&g->x.xf, v3_mul(unit_random(), 100));
        if (shape_light_sample(k, g, NULL, far, u, 1, &ls))
            return v3_madd(far, ls.l, ls.dist);
    }
}

/* The shapes at scale s, moved by (T, T/2, T/3), some sheared. */
static void scaled_shapes(double s, double T, lc_shape out[6])
{
    lc_vec3 o = v3(T, T / 2, T / 3);
    lc_shape base[6] = {
        {.kind = LC_CYLINDER, .p = {-1, 0, 0}, .u = {0.3, 2, 0.1}, .radius = 0.7, .caps = 1},
        {.kind = LC_CONE, .p = {1, 0, 0}, .u = {0, 1.5, 0.5}, .radius = 0.8, .radius2 = 0.3,
         .caps = 1},
        {.kind = LC_TORUS, .p = {0, 1, 0}, .u = {0.2, 1, 0.3}, .radius = 1, .radius2 = 0.3},
        {.kind = LC_ELLIPSOID, .p = {0, -1, 1}, .u = {0.5, 0.9, 0.3}},
        {.kind = LC_DISC, .p = {0, 0, 2}, .u = {0.1, 0.3, 1}, .radius = 1, .radius2 = 0.2},
        {.kind = LC_TORUS, .p = {0, 0, 0}, .u = {0, 0, 1}, .radius = 0.8, .radius2 = 0.2,
         .moved = 1, .xf = {{{1, 0.4, 0, 0}, {0, 1, 0, 0}, {0, 0.3, 1.5, 0}}}},
    };
    for (int i = 0; i < 6; i++) {
        out[i] = base[i];
        shape_scale(&out[i], s, o);
    }
}

/* From every scale and offset: rays to points of each surface, and from
** each hit a ray spawned to either side; one that meets the surface again
** within a thousand times its point's error bound, with the same normal,
** has met the point it left (a ray leaving near a rim may meet the next
** face soon after, legitimately: another normal; one leaving a torus at a
** grazing angle may meet it again, but farther). 10^5 spawned rays per
** shape and scale, none back. */
static void spawned_rays_never_return(void **state)
{
    (void)state;
    const double scales[][2] = {{1e-4, 0}, {1, 0}, {1e6, 0}, {1, 1e7}};
    int rays = getenv("LANCER_PRIMITIVE_RAYS") ? atoi(getenv("LANCER_PRIMITIVE_RAYS"))
                                               : 100000;
    for (size_t c = 0; c < sizeof scales / sizeof *scales; c++) {
        double s = scales[c][0], T = scales[c][1];
        lc_shape shapes[6];
        scaled_shapes(s, T, shapes);
        for (int k = 0; k < 6; k++) {
            placed_geom g = prepare(shapes[k]);
            lc_shape_kind kind = shapes[k].kind;
            int hits = 0, back = 0;
            for (int i = 0; i < rays; i++) {
                lc_vec3 q = surface_point(kind, &g);
                lc_vec3 from = v3_madd(q, unit_random(), 5 * s);
                ray r = mkray_unit(from, v3_sub(q, from));
                hit h;
                if (!hit_of(kind, &g, r, &h))
                    continue;
                hits++;
                lc_vec3 w = unit_random();
                if (i & 1)                       /* away from the side it came from */
                    w = v3_dot(w, r.d) > 0 ? w : v3_neg(w);
                ray out = {spawn_origin(&h, w), w};
                hit h2;
                if (hit_of(kind, &g, out, &h2) && h2.t < 1000 * v3_len(h.perr) &&
                    v3_dot(h2.n, h.n) > 1 - 1e-9)
                    back++;
            }
            if (back || hits < rays / 4)
                fail_msg("%s at scale %g, moved %g: %d of %d hits re-hit their surface",
                         lc_shape_kind_name(kind), s, T, back, hits);
        }
    }
}

/* Every point of every surface lies inside the shape's BVH bounds. */
static void bounds_hold_the_surface(void **state)
{
    (void)state;
    lc_shape shapes[6];
    scaled_shapes(3, 100, shapes);
    for (int k = 0; k < 6; k++) {
        placed_geom g = prepare(shapes[k]);
        float lo[3], hi[3];
        shape_bounds(shapes[k].kind, &g, lo, hi);
        for (int i = 0; i < 20000; i++) {
            lc_vec3 p = surface_point(shapes[k].kind, &g);
            double c[3] = {p.x, p.y, p.z};
            for (int a = 0; a < 3; a++)
                if (!(c[a] >= lo[a] && c[a] <= hi[a]))
                    fail_msg("%s: point %g outside [%g, %g] on axis %d",
                             lc_shape_kind_name(shapes[k].kind), c[a], lo[a], hi[a], a);
        }
    }
}

/* ---- the torus's quartic against a long-double reference -------------------------- */

static long double f_torus(long double minor, const ray *r, long double s)
{
    long double x = r->o.x + s * r->d.x, y = r->o.y + s * r->d.y, z = r->o.z + s * r->d.z;
    long double q = x * x + y * y + z * z + 1 - minor * minor;
    return q * q - 4 * (x * x + y * y);
}

/* The nearest root in (lo, hi) by sign changes over `steps` steps, then
** bisection to long double's last bit: slow and simple. 0 if none. */
static long double reference_root(double minor, const ray *r, double lo, double hi,
                                  int steps)
{
    long double a = lo, fa = f_torus(minor, r, a);
    for (int i = 1; i <= steps; i++) {
        long double b = lo + (hi - (long double)lo) * i / steps, fb = f_torus(minor, r, b);
        if ((fa < 0) != (fb < 0)) {
            for (int k = 0; k < 200; k++) {
                long double m = 0.5L * (a + b), fm = f_torus(minor, r, m);
                if (m == a || m == b)
                    break;
                if ((fm < 0) == (fa < 0))
                    a = m, fa = fm;
                else
                    b = m;
            }
            return 0.5L * (a + b);
        }
        a = b, fa = fb;
    }
    return 0;
}

static void torus_roots_match_the_reference(void **state)
{
    (void)state;
    int rays = getenv("LANCER_TORUS_RAYS") ? atoi(getenv("LANCER_TORUS_RAYS")) : 20000;
    double worst = 0, minor = 0.3;
    int hits = 0, disagree = 0, grazing = 0, refereed = 0;
    for (int i = 0; i < rays; i++) {
        /* From a sphere of radius 4 toward points near the torus, a quarter
        ** of them grazing: aimed 1e-9 to 1e-3 off the tube's outline. */
        lc_vec3 from = v3_mul(unit_random(), 4);
        double th = 2 * PI * uniform(), ph = 2 * PI * uniform();
        double rad = minor * (i % 4 == 0 ? 1 + pow(10, -9 + 6 * uniform()) : uniform());
        lc_vec3 q = v3((1 + rad * cos(ph)) * cos(th), (1 + rad * cos(ph)) * sin(th),
                       rad * sin(ph));
        ray r = mkray_unit(from, v3_sub(q, from));
        double roots[4];
        int n = torus_roots(minor, &r, 1e-9, 10, roots);
        long double ref = reference_root(minor, &r, 1e-9, 10, 4000);
        /* Where the two differ, a scan 1000 times finer decides: a grazing
        ** ray's two roots can lie between two of the coarse steps. */
        if (n > 0 && ref != 0 && fabsl(roots[0] - ref) > 1e-9L * (ref + 1)) {
            ref = reference_root(minor, &r, 1e-9, (double)fmaxl(roots[0], ref) + 1e-6,
                                 4000000);
            refereed++;
        }
        if ((n > 0) != (ref != 0)) {
            /* Hit against miss: only where the ray grazes (the quartic's
            ** minimum within its rounding of zero). */
            long double t = n > 0 ? roots[0] : ref;
            if (fabsl(f_torus(minor, &r, t)) > 1e-12L)
                disagree++;
            grazing++;
            continue;
        }
        if (n == 0)
            continue;
        hits++;
        double err = (double)(fabsl(roots[0] - ref) / (ref + 1));
        if (err > worst)
            worst = err;
    }
    print_message("torus: %d rays, %d hits, largest relative error %.3g (%d decided by "
                  "a finer scan); %d grazing hit-or-miss differences, %d elsewhere\n",
                  rays, hits, worst, refereed, grazing, disagree);
    assert_int_equal(disagree, 0);
    /* Double's own rounding of the root, and a grazing root's ill condition. */
    assert_true(worst < 1e-7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closed_forms),
        cmocka_unit_test(tangents_and_grazing),
        cmocka_unit_test(spawned_rays_never_return),
        cmocka_unit_test(bounds_hold_the_surface),
        cmocka_unit_test(torus_roots_match_the_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
