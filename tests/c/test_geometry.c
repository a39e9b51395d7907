/* test_geometry.c: sphere, quad, box and plane hits and spawned rays, case by case. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "shapes/shape.h"
#include "helpers.h"
#include "shapes/plane.h"

/* Half an ulp of 1: the relative error of one rounding. */
#define EPS (DBL_EPSILON / 2)
/* SQRT1_2 and SQRT2 are not C99: sqrt(1/2) and sqrt(2), rounded. */
#define SQRT1_2 0.70710678118654752440
#define SQRT2   1.41421356237309504880

/* ---- Helpers ------------------------------------------------------------- */

static sphere_geom mksphere(lc_vec3 c, double r)
{
    lc_shape s = {.kind = LC_SPHERE, .p = c, .radius = r};
    sphere_geom g;
    sphere_prepare(&s, &g);
    return g;
}

static quad_geom mkquad(lc_vec3 q, lc_vec3 u, lc_vec3 v)
{
    lc_shape s = {.kind = LC_QUAD, .p = q, .u = u, .v = v};
    quad_geom g;
    quad_prepare(&s, &g);
    return g;
}

static box_geom mkbox(lc_vec3 p, lc_vec3 u, lc_vec3 v, lc_vec3 w)
{
    lc_shape s = {.kind = LC_BOX, .p = p, .u = u, .v = v, .w = w};
    box_geom g;
    box_prepare(&s, &g);
    return g;
}

static plane_geom mkplane(lc_vec3 p, lc_vec3 n)
{
    lc_shape s = {.kind = LC_PLANE, .p = p, .u = n};
    plane_geom g;
    plane_prepare(&s, &g);
    return g;
}

static double ulp(double x)
{
    x = fabs(x);
    return nextafter(x, HUGE_VAL) - x;
}

/* |a - b| within n ulps of the larger. */
static int near_ulps(double a, double b, int n)
{
    return fabs(a - b) <= n * ulp(fmax(fabs(a), fabs(b)));
}

static int v3_eq(lc_vec3 a, lc_vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

static int v3_finite(lc_vec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}

#define assert_v3_equal(a, b) assert_v3_equal_at((a), (b), __FILE__, __LINE__)
static void assert_v3_equal_at(lc_vec3 a, lc_vec3 b, const char *file, int line)
{
    if (!v3_eq(a, b))
        fail_msg("%s:%d: (%.17g, %.17g, %.17g) != (%.17g, %.17g, %.17g)", file, line,
                 a.x, a.y, a.z, b.x, b.y, b.z);
}

/* Per component within tol (absolute). */
#define assert_v3_near(a, b, tol) assert_v3_near_at((a), (b), (tol), __FILE__, __LINE__)
static void assert_v3_near_at(lc_vec3 a, lc_vec3 b, double tol, const char *file,
                              int line)
{
    if (!(fabs(a.x - b.x) <= tol && fabs(a.y - b.y) <= tol && fabs(a.z - b.z) <= tol))
        fail_msg("%s:%d: (%.17g, %.17g, %.17g) vs (%.17g, %.17g, %.17g), tol %g", file,
                 line, a.x, a.y, a.z, b.x, b.y, b.z, tol);
}

#define assert_near_ulps(a, b, n) assert_near_ulps_at((a), (b), (n), __FILE__, __LINE__)
static void assert_near_ulps_at(double a, double b, int n, const char *file, int line)
{
    if (!near_ulps(a, b, n))
        fail_msg("%s:%d: %.17g vs %.17g: %.3g ulps, allowed %d", file, line, a, b,
                 fabs(a - b) / ulp(fmax(fabs(a), fabs(b))), n);
}

/* Every number in a hit is finite, and the normal is a unit vector (1e-15:
** a normalisation is ~4 roundings). */
static void assert_hit_sane(const hit *h)
{
    assert_true(isfinite(h->t));
    assert_true(v3_finite(h->p));
    assert_true(v3_finite(h->perr));
    assert_true(v3_finite(h->n));
    assert_true(h->perr.x >= 0 && h->perr.y >= 0 && h->perr.z >= 0);
    assert_true(fabs(v3_len(h->n) - 1) <= 1e-15);
}

/* A record filled with a byte pattern: a miss must leave every byte alone. */
static void poison(hit *h) { memset(h, 0xa5, sizeof *h); }

static int untouched(const hit *h)
{
    hit ref;
    poison(&ref);
    return memcmp(h, &ref, sizeof ref) == 0;
}

typedef int (*hit_fn)(const void *g, const ray *r, double tmin, double tmax,
                      hit *h);

static int s_hit(const void *g, const ray *r, double a, double b, hit *h)
{
    return sphere_hit(g, r, a, b, h);
}
static int q_hit(const void *g, const ray *r, double a, double b, hit *h)
{
    return quad_hit(g, r, a, b, h);
}
static int b_hit(const void *g, const ray *r, double a, double b, hit *h)
{
    return box_hit(g, r, a, b, h);
}
static int p_hit(const void *g, const ray *r, double a, double b, hit *h)
{
    return plane_hit(g, r, a, b, h);
}

/* Asserts a miss over (tmin, tmax) that leaves the record untouched. */
#define assert_miss(fn, g, r, tmin, tmax) \
    assert_miss_at((fn), (g), (r), (tmin), (tmax), __FILE__, __LINE__)
static void assert_miss_at(hit_fn fn, const void *g, ray r, double tmin, double tmax,
                           const char *file, int line)
{
    hit h;
    poison(&h);
    if (fn(g, &r, tmin, tmax, &h))
        fail_msg("%s:%d: ray (%.17g, %.17g, %.17g) + t (%.17g, %.17g, %.17g) hits at "
                 "t = %.17g", file, line, r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, h.t);
    if (!untouched(&h))
        fail_msg("%s:%d: a miss wrote into the hit record", file, line);
}

/* Asserts a hit over (0, inf) and returns it. */
#define get_hit(fn, g, r) get_hit_at((fn), (g), (r), __FILE__, __LINE__)
static hit get_hit_at(hit_fn fn, const void *g, ray r, const char *file, int line)
{
    hit h;
    poison(&h);
    if (!fn(g, &r, 0, HUGE_VAL, &h))
        fail_msg("%s:%d: ray (%.17g, %.17g, %.17g) + t (%.17g, %.17g, %.17g) misses",
                 file, line, r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z);
    assert_hit_sane(&h);
    return h;
}

static lc_vec3 rand_in_ball(uint64_t *s)
{
    for (;;) {
        double x = 2 * lcg(s) - 1, y = 2 * lcg(s) - 1, z = 2 * lcg(s) - 1;
        lc_vec3 a = v3(x, y, z);
        double l = v3_dot(a, a);
        if (l <= 1 && l > 1e-4)
            return a;
    }
}

static lc_vec3 ball_dir(uint64_t *s) { return v3_norm(rand_in_ball(s)); }

/* A direction on the side of n given by sign: uniform for even k, and for
** odd k within 10^-12 .. 10^-1 radians of the tangent plane (grazing). */
static lc_vec3 rand_dir(uint64_t *s, lc_vec3 n, int sign, int k)
{
    lc_vec3 w = ball_dir(s);
    if (k % 2) {
        lc_vec3 tg = v3_norm(v3_madd(w, n, -v3_dot(w, n)));
        w = v3_norm(v3_madd(tg, n, pow(10, -1 - 11 * lcg(s))));
    }
    if (v3_dot(w, n) * sign < 0)
        w = v3_neg(w);
    return w;
}

/* ---- Sphere -------------------------------------------------------------- */

/* Every step is exact: f = (0,0,-5), b = -5, v = 0, disc = 1, q = 6, c = 24,
** roots 24/6 = 4 and 6. */
static void sphere_from_outside(void **state)
{
    (void)state;
    sphere_geom g = mksphere(v3(0, 0, 0), 1);
    hit h = get_hit(s_hit, &g, mkray(v3(0, 0, -5), v3(0, 0, 1)));
    assert_true(h.t == 4);
    assert_v3_equal(h.p, v3(0, 0, -1));
    assert_v3_equal(h.n, v3(0, 0, -1));
    /* The error bound: gamma(7) |p - c| + gamma(4) |p|, about 11 eps. */
    assert_true(h.perr.z > 0 && h.perr.z <= 12 * EPS);

    /* Same, translated by an exactly representable offset and scaled by 2^k:
    ** still exact. */
    g = mksphere(v3(1024, -512, 256), 8);
    h = get_hit(s_hit, &g, mkray(v3(1024, -512, 256 - 40), v3(0, 0, 1)));
    assert_true(h.t == 32);
    assert_v3_equal(h.p, v3(1024, -512, 248));
    assert_v3_equal(h.n, v3(0, 0, -1));
}

/* From the centre b = 0, so q = -r and c = -r^2: roots -r and r, both exact. */
static void sphere_from_inside(void **state)
{
    (void)state;
    const double r = 2;
    lc_vec3 c = v3(1, 2, 3);
    sphere_geom g = mksphere(c, r);
    hit h = get_hit(s_hit, &g, mkray(c, v3(0, 0, 1)));
    assert_true(h.t == r);
    assert_v3_equal(h.n, v3(0, 0, 1));                  /* outward */
    assert_v3_equal(h.p, v3(1, 2, 5));
    h = get_hit(s_hit, &g, mkray(c, v3(-1, 0, 0)));
    assert_true(h.t == r);
    assert_v3_equal(h.n, v3(-1, 0, 0));
    assert_v3_equal(h.p, v3(-1, 2, 3));

    /* Off-centre at 0.7r (1.4 is inexact, but f = 1.4 exactly and the rest
    ** is done against it). Along the offset: far side at 0.3r and 1.7r. */
    g = mksphere(v3(0, 0, 0), r);
    h = get_hit(s_hit, &g, mkray(v3(0, 0, 0.7 * r), v3(0, 0, 1)));
    assert_near_ulps(h.t, r - 0.7 * r, 2);   /* r - 1.4 is exact; 1 rounding in c/q */
    assert_v3_equal(h.n, v3(0, 0, 1));
    assert_v3_equal(h.p, v3(0, 0, r));
    h = get_hit(s_hit, &g, mkray(v3(0, 0, 0.7 * r), v3(0, 0, -1)));
    assert_near_ulps(h.t, r + 0.7 * r, 2);
    assert_v3_equal(h.n, v3(0, 0, -1));
    /* Across: t = r sqrt(1 - 0.49), n = (0.7, sqrt(0.51), 0). disc takes 2
    ** roundings, t = disc / sqrt(disc) 2 more: 4 ulps. The normal adds a
    ** length (3 roundings + sqrt), a reciprocal and a product: 1e-15. */
    double x = 0.7 * r;
    long double tr = sqrtl((long double)r * r - (long double)x * x);
    h = get_hit(s_hit, &g, mkray(v3(x, 0, 0), v3(0, 1, 0)));
    assert_near_ulps(h.t, (double)tr, 4);
    assert_v3_near(h.n, v3((double)(x / r), (double)(tr / r), 0), 1e-15);
    assert_v3_near(h.p, v3(x, (double)tr, 0), 1e-15 * r);
    assert_true(h.n.x > 0 && h.n.y > 0);
}

/* Tangent: v = (0,1,0) exactly, disc = 0, both roots 5 up to the rounding of
** c = (sqrt 26 - 1)(sqrt 26 + 1) (~2 eps relative) and c/q: 4 ulps of 5. */
static void sphere_tangent(void **state)
{
    (void)state;
    sphere_geom g = mksphere(v3(0, 0, 0), 1);
    hit h = get_hit(s_hit, &g, mkray(v3(-5, 1, 0), v3(1, 0, 0)));
    assert_near_ulps(h.t, 5, 4);
    assert_v3_near(h.p, v3(0, 1, 0), 4 * ulp(5));   /* p.x = t - 5, exactly */
    assert_v3_near(h.n, v3(0, 1, 0), 4 * ulp(5));
    assert_true(h.p.y == 1 && h.n.y == 1);          /* |n| = sqrt(1 + tiny^2) = 1 */

    /* 2^-40 beyond the tangent: |v| = 1 + 2^-40 exactly, disc < 0. */
    assert_miss(s_hit, &g, mkray(v3(-5, 1 + 0x1p-40, 0), v3(1, 0, 0)), 0, HUGE_VAL);
    /* 2^-40 inside: disc = 2^-40 (2 - 2^-40), two roots 5 -+ sqrt(disc). */
    double y = 1 - 0x1p-40;
    long double half = sqrtl(0x1p-40L * (2 - 0x1p-40L));
    h = get_hit(s_hit, &g, mkray(v3(-5, y, 0), v3(1, 0, 0)));
    assert_near_ulps(h.t, (double)(5 - half), 4);
    assert_true(h.n.x < 0);
    double t0 = h.t;
    ray r = mkray(v3(-5, y, 0), v3(1, 0, 0));
    poison(&h);
    assert_true(sphere_hit(&g, &r, t0, HUGE_VAL, &h));  /* tmin = near root */
    assert_near_ulps(h.t, (double)(5 + half), 2);        /* q: sqrt and one sum */
    assert_true(h.t > t0);
    assert_true(h.n.x > 0);
}

static void sphere_misses(void **state)
{
    (void)state;
    sphere_geom g = mksphere(v3(0, 0, 0), 1);
    assert_miss(s_hit, &g, mkray(v3(0, 2, -5), v3(0, 0, 1)), 0, HUGE_VAL);
    assert_miss(s_hit, &g, mkray(v3(0, 0, -5), v3(0, 1, 0)), 0, HUGE_VAL);
    /* Behind the ray: roots -6 and -4. */
    assert_miss(s_hit, &g, mkray(v3(0, 0, 5), v3(0, 0, 1)), 0, HUGE_VAL);
    /* tmax before the near root; bounds are strict, so tmax = 4 misses too. */
    assert_miss(s_hit, &g, mkray(v3(0, 0, -5), v3(0, 0, 1)), 0, 3.9);
    assert_miss(s_hit, &g, mkray(v3(0, 0, -5), v3(0, 0, 1)), 0, 4);
    /* tmin at the far root. */
    assert_miss(s_hit, &g, mkray(v3(0, 0, -5), v3(0, 0, 1)), 6, HUGE_VAL);
    /* tmin between the roots: the far one. */
    hit h;
    ray r = mkray(v3(0, 0, -5), v3(0, 0, 1));
    assert_true(sphere_hit(&g, &r, 4, HUGE_VAL, &h));
    assert_true(h.t == 6);
    assert_v3_equal(h.n, v3(0, 0, 1));
    /* Origin on the surface, leaving: roots 0 and -2; t > 0 is required. */
    assert_miss(s_hit, &g, mkray(v3(0, 0, 1), v3(0, 0, 1)), 0, HUGE_VAL);
    /* NaN anywhere in the ray: a miss, not a NaN hit. */
    assert_miss(s_hit, &g, mkray(v3(NAN, 0, -5), v3(0, 0, 1)), 0, HUGE_VAL);
    assert_miss(s_hit, &g, mkray(v3(0, 0, -5), v3(0, NAN, 1)), 0, HUGE_VAL);
}

/* The hit point's distance to the true surface, in long double. */
static long double sphere_dist(const sphere_geom *g, lc_vec3 p)
{
    long double x = (long double)p.x - g->c.x, y = (long double)p.y - g->c.y,
                z = (long double)p.z - g->c.z;
    return fabsl(sqrtl(x * x + y * y + z * z) - g->r);
}

/* The near root for a unit-direction ray, in long double. */
static long double sphere_near_root(const sphere_geom *g, ray r)
{
    long double f[3] = {(long double)r.o.x - g->c.x, (long double)r.o.y - g->c.y,
                        (long double)r.o.z - g->c.z};
    long double d[3] = {r.d.x, r.d.y, r.d.z};
    long double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    long double b = (f[0] * d[0] + f[1] * d[1] + f[2] * d[2]) / a;
    long double v2 = 0;
    for (int i = 0; i < 3; i++) {
        long double vi = f[i] - b * d[i];
        v2 += vi * vi;
    }
    return -b - sqrtl(((long double)g->r * g->r - v2) / a);
}

/* Small or far spheres, where b^2 - 4ac cancels: the closed form still holds.
** t: its few roundings are relative to |f| ~ t, so 4 ulps of t. The stored
** point is the refined local point plus the centre, one rounding of |p|:
** within perr of the surface (geom.h's promise) and within 1e-9 of it
** relative to the coordinates' magnitude (docs/numerics.md 1.1: error follows |p|). */
static void sphere_small_and_far(void **state)
{
    (void)state;
    struct { lc_vec3 c; double r; lc_vec3 o; } cases[] = {
        {{0, 0, 1e6}, 1e-3, {0.5e-3, 0, 0}},
        {{0, 0, 1e6}, 1e-3, {0, 0.9e-3, 0}},
        {{1e7, 1e7, 1e7}, 1, {1e7 + 0.3, 1e7 + 0.4, 1e7 - 5}},
        {{1e7, 5e6, -1e7 / 3}, 1, {1e7 - 0.6, 5e6 + 0.7, -1e7 / 3 - 5}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sphere_geom g = mksphere(cases[i].c, cases[i].r);
        ray r = mkray(cases[i].o, v3(0, 0, 1));
        hit h = get_hit(s_hit, &g, r);
        long double tr = sphere_near_root(&g, r);
        if (!near_ulps(h.t, (double)tr, 4))
            fail_msg("case %zu: t = %.17g, closed form %.17Lg", i, h.t, tr);
        long double dist = sphere_dist(&g, h.p);
        double bound = v3_dot(v3_abs(h.n), h.perr);
        double mag = v3_max_abs(h.p);
        if (!(dist <= bound && dist <= 1e-9 * mag))
            fail_msg("case %zu: hit %.3Lg off the surface, perr %.3g, |p| %.3g", i, dist,
                     bound, mag);
        assert_true(h.n.z < 0);
    }
}

/* ---- Quad ---------------------------------------------------------------- */

/* The unit square [1, 2] x [1, 2] at z = 3, normal +z: every alpha, beta is
** an exact difference, so the bounds are tested to the ulp. */
static quad_geom unit_quad(void)
{
    return mkquad(v3(1, 1, 3), v3(1, 0, 0), v3(0, 1, 0));
}

static ray up_at(double x, double y) { return mkray(v3(x, y, 0), v3(0, 0, 1)); }

static void quad_inside_hit(void **state)
{
    (void)state;
    quad_geom g = unit_quad();
    assert_int_equal(g.axis, 2);
    hit h = get_hit(q_hit, &g, up_at(1.25, 1.5));
    assert_true(h.t == 3);
    assert_v3_equal(h.p, v3(1.25, 1.5, 3));
    assert_v3_equal(h.n, v3(0, 0, 1));
    assert_true(h.perr.z == 0);                        /* snapped exactly */
    /* From the other side: the normal is u x v either way. */
    h = get_hit(q_hit, &g, mkray(v3(1.5, 1.5, 10), v3(0, 0, -1)));
    assert_true(h.t == 7);
    assert_v3_equal(h.n, v3(0, 0, 1));

    /* A tilted quad: n = u x v = (0, -2, 2); every product here is exact. */
    g = mkquad(v3(0, 0, 0), v3(2, 0, 0), v3(0, 1, 1));
    assert_int_equal(g.axis, -1);
    h = get_hit(q_hit, &g, mkray(v3(1, 0.5, -5), v3(0, 0, 1)));
    assert_true(h.t == 5.5);
    assert_v3_equal(h.p, v3(1, 0.5, 0.5));
    /* un = n * (1/sqrt 8): 3 roundings from the exact 1/sqrt 2. */
    assert_near_ulps(h.n.y, -SQRT1_2, 2);
    assert_near_ulps(h.n.z, SQRT1_2, 2);
    assert_true(h.n.x == 0);
}

static void quad_edges_by_one_ulp(void **state)
{
    (void)state;
    quad_geom g = unit_quad();
    /* One ulp outside each edge: alpha or beta is -2^-53 or 1 + 2^-51, exact. */
    assert_miss(q_hit, &g, up_at(nextafter(1, 0), 1.5), 0, HUGE_VAL);
    assert_miss(q_hit, &g, up_at(nextafter(2, 3), 1.5), 0, HUGE_VAL);
    assert_miss(q_hit, &g, up_at(1.5, nextafter(1, 0)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, up_at(1.5, nextafter(2, 3)), 0, HUGE_VAL);
    /* Diagonally outside each corner. */
    assert_miss(q_hit, &g, up_at(nextafter(1, 0), nextafter(1, 0)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, up_at(nextafter(2, 3), nextafter(2, 3)), 0, HUGE_VAL);
    /* One ulp inside: hits. */
    get_hit(q_hit, &g, up_at(nextafter(1, 2), 1.5));
    get_hit(q_hit, &g, up_at(nextafter(2, 1), 1.5));
    get_hit(q_hit, &g, up_at(1.5, nextafter(1, 2)));
    get_hit(q_hit, &g, up_at(1.5, nextafter(2, 1)));
    /* Exactly on each edge and at each corner: bounds are inclusive. */
    double e[2] = {1, 2};
    for (int i = 0; i < 2; i++) {
        hit h = get_hit(q_hit, &g, up_at(e[i], 1.5));
        assert_v3_equal(h.p, v3(e[i], 1.5, 3));
        h = get_hit(q_hit, &g, up_at(1.5, e[i]));
        assert_v3_equal(h.p, v3(1.5, e[i], 3));
        for (int j = 0; j < 2; j++) {
            h = get_hit(q_hit, &g, up_at(e[i], e[j]));
            assert_true(h.t == 3);
            assert_v3_equal(h.p, v3(e[i], e[j], 3));
            assert_v3_equal(h.n, v3(0, 0, 1));
        }
    }
    /* Two quads sharing the edge x = 2 both claim a ray through it: no crack. */
    quad_geom g2 = mkquad(v3(2, 1, 3), v3(1, 0, 0), v3(0, 1, 0));
    get_hit(q_hit, &g2, up_at(2, 1.25));
    get_hit(q_hit, &g, up_at(2, 1.25));
}

static void quad_parallel_and_behind(void **state)
{
    (void)state;
    quad_geom g = unit_quad();
    /* Parallel to the plane, off it and in it (0/0 must not become a hit). */
    assert_miss(q_hit, &g, mkray(v3(0, 1.5, 0), v3(1, 0, 0)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, mkray(v3(0, 1.5, 3), v3(1, 0, 0)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, mkray(v3(1.5, 1.5, 3), v3(0, -1, 0)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, mkray(v3(1.5, 1.5, 3), v3(SQRT1_2, SQRT1_2, -0.0)), 0,
                HUGE_VAL);
    /* Behind, on the plane, beyond tmax. */
    assert_miss(q_hit, &g, mkray(v3(1.5, 1.5, 5), v3(0, 0, 1)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, mkray(v3(1.5, 1.5, 3), v3(0, 0, 1)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, mkray(v3(1.5, 1.5, 3), v3(0, 0, -1)), 0, HUGE_VAL);
    assert_miss(q_hit, &g, up_at(1.5, 1.5), 0, 3);
    assert_miss(q_hit, &g, mkray(v3(NAN, 1.5, 0), v3(0, 0, 1)), 0, HUGE_VAL);
    /* Tilted quad, ray in its plane. */
    quad_geom t = mkquad(v3(0, 0, 0), v3(2, 0, 0), v3(0, 1, 1));
    assert_miss(q_hit, &t, mkray(v3(-1, 0.5, 0.5), v3(1, 0, 0)), 0, HUGE_VAL);
    assert_miss(q_hit, &t, mkray(v3(1, -1, -1), v3(0, SQRT1_2, SQRT1_2)), 0,
                HUGE_VAL);
}

/* ---- Box ----------------------------------------------------------------- */

/* [-1, 1]^3 as corner + axis edges: kind LC_BOX, aligned. */
static box_geom cube(void)
{
    return mkbox(v3(-1, -1, -1), v3(2, 0, 0), v3(0, 2, 0), v3(0, 0, 2));
}

/* A sheared, rotated parallelepiped: no edge along an axis. */
static void rotated_edges(lc_vec3 e[3])
{
    e[0] = v3(1.6, 0.5, -0.3);
    e[1] = v3(-0.4, 1.2, 0.6);
    e[2] = v3(0.35, -0.55, 1.4);
}

static void box_aligned_faces(void **state)
{
    (void)state;
    /* The same box [-1,1] x [-2,2] x [-3,3] from its lowest and its highest
    ** corner (negative edges). Every slab distance is an exact difference. */
    box_geom gs[2] = {
        mkbox(v3(-1, -2, -3), v3(2, 0, 0), v3(0, 4, 0), v3(0, 0, 6)),
        mkbox(v3(1, 2, 3), v3(-2, 0, 0), v3(0, -4, 0), v3(0, 0, -6)),
    };
    for (int k = 0; k < 2; k++) {
        const box_geom *g = &gs[k];
        assert_true(g->aligned);
        struct { lc_vec3 o, d, p, n; double t; } f[6] = {
            {{-10, 0.5, 0.25}, {1, 0, 0}, {-1, 0.5, 0.25}, {-1, 0, 0}, 9},
            {{10, 0.5, 0.25}, {-1, 0, 0}, {1, 0.5, 0.25}, {1, 0, 0}, 9},
            {{0.5, -10, 0.25}, {0, 1, 0}, {0.5, -2, 0.25}, {0, -1, 0}, 8},
            {{0.5, 10, 0.25}, {0, -1, 0}, {0.5, 2, 0.25}, {0, 1, 0}, 8},
            {{0.5, 0.25, -10}, {0, 0, 1}, {0.5, 0.25, -3}, {0, 0, -1}, 7},
            {{0.5, 0.25, 10}, {0, 0, -1}, {0.5, 0.25, 3}, {0, 0, 1}, 7},
        };
        for (int i = 0; i < 6; i++) {
            hit h = get_hit(b_hit, g, mkray(f[i].o, f[i].d));
            assert_true(h.t == f[i].t);
            assert_v3_equal(h.p, f[i].p);
            assert_v3_equal(h.n, f[i].n);
            assert_true(v3_comp(h.perr, i / 2) == 0);     /* snapped coordinate */
        }
    }
    /* -0 direction components pick the same slabs as +0. */
    box_geom g = cube();
    hit h = get_hit(b_hit, &g, mkray(v3(-10, 0.5, 0.25), v3(1, -0.0, -0.0)));
    assert_true(h.t == 9);
    assert_v3_equal(h.n, v3(-1, 0, 0));
}

/* Rays through an edge or a corner give equal slab distances: the lowest axis
** wins, in both the entry and the exit interval. */
static void box_aligned_edges_and_corners(void **state)
{
    (void)state;
    box_geom g = cube();
    const double s = SQRT1_2;             /* d.x == d.y: both slabs compute alike */
    /* Edge between -x and -y, at z = 0.5. */
    hit h = get_hit(b_hit, &g, mkray(v3(-3, -3, 0.5), v3(s, s, 0)));
    assert_v3_equal(h.n, v3(-1, 0, 0));
    assert_true(h.t == 2 * (1 / s));
    assert_true(h.p.x == -1);                          /* snapped on x only */
    assert_true(fabs(h.p.y + 1) <= 2 * ulp(3));
    assert_true(h.p.z == 0.5);
    /* Edge between +y and +z: y (axis 1) wins over z. */
    h = get_hit(b_hit, &g, mkray(v3(0.25, 3, 3), v3(0, -s, -s)));
    assert_v3_equal(h.n, v3(0, 1, 0));
    assert_true(h.p.y == 1);
    /* Edge between +x and -z. */
    h = get_hit(b_hit, &g, mkray(v3(3, 0.5, -3), v3(-s, 0, s)));
    assert_v3_equal(h.n, v3(1, 0, 0));
    /* Corner (-1,-1,-1) and (1,1,1) on the diagonal: x wins. */
    const double c = 1 / sqrt(3);
    h = get_hit(b_hit, &g, mkray(v3(-3, -3, -3), v3(c, c, c)));
    assert_v3_equal(h.n, v3(-1, 0, 0));
    assert_true(h.p.x == -1);
    assert_true(fabs(h.p.y + 1) <= 2 * ulp(3) && fabs(h.p.z + 1) <= 2 * ulp(3));
    h = get_hit(b_hit, &g, mkray(v3(3, 3, 3), v3(-c, -c, -c)));
    assert_v3_equal(h.n, v3(1, 0, 0));
    /* Exit through an edge and a corner from inside: x again. */
    h = get_hit(b_hit, &g, mkray(v3(0, 0, 0.5), v3(s, s, 0)));
    assert_v3_equal(h.n, v3(1, 0, 0));
    assert_true(h.p.x == 1);
    h = get_hit(b_hit, &g, mkray(v3(0, 0, 0), v3(-c, -c, -c)));
    assert_v3_equal(h.n, v3(-1, 0, 0));
    /* A non-symmetric ray at the edge (-1,-1,0.5): d = (2,1,0)/sqrt 5 rounds
    ** differently per axis, so either face may win, but the normal is exactly
    ** one of the two and the point is the edge to rounding. */
    lc_vec3 d = v3_norm(v3(2, 1, 0));
    h = get_hit(b_hit, &g, mkray(v3(-3, -2, 0.5), d));
    assert_true(v3_eq(h.n, v3(-1, 0, 0)) || v3_eq(h.n, v3(0, -1, 0)));
    assert_v3_near(h.p, v3(-1, -1, 0.5), 4 * ulp(3));
    assert_true(h.p.x == -1 || h.p.y == -1);
}

static void box_origin_inside(void **state)
{
    (void)state;
    box_geom g = mkbox(v3(-1, -2, -3), v3(2, 0, 0), v3(0, 4, 0), v3(0, 0, 6));
    lc_vec3 o = v3(0.5, 0.25, -0.5);
    struct { lc_vec3 d, n; double t; } f[6] = {
        {{1, 0, 0}, {1, 0, 0}, 0.5},   {{-1, 0, 0}, {-1, 0, 0}, 1.5},
        {{0, 1, 0}, {0, 1, 0}, 1.75},  {{0, -1, 0}, {0, -1, 0}, 2.25},
        {{0, 0, 1}, {0, 0, 1}, 3.5},   {{0, 0, -1}, {0, 0, -1}, 2.5},
    };
    for (int i = 0; i < 6; i++) {
        hit h = get_hit(b_hit, &g, mkray(o, f[i].d));
        assert_true(h.t == f[i].t);
        assert_v3_equal(h.n, f[i].n);                 /* outward: the exit face */
    }
    /* tmax before the exit: a miss. */
    assert_miss(b_hit, &g, mkray(o, v3(1, 0, 0)), 0, 0.5);
}

/* The origin exactly on a face plane, moving parallel to it: 0 * inf = NaN in
** that slab, which the comparisons ignore. The face's plane counts as inside
** (closed box): the ray hits the far face it meets, or leaves through the
** exit face when it starts on the face itself. Same with +-0 direction. */
static void box_ray_in_face_plane(void **state)
{
    (void)state;
    box_geom g = cube();
    double zs[2] = {0.0, -0.0};
    for (int k = 0; k < 2; k++) {
        lc_vec3 d = v3(1, zs[k], zs[k]);
        /* On y = hi and on y = lo, coming from outside in x. */
        hit h = get_hit(b_hit, &g, mkray(v3(-3, 1, 0), d));
        assert_true(h.t == 2);
        assert_v3_equal(h.n, v3(-1, 0, 0));
        assert_v3_equal(h.p, v3(-1, 1, 0));
        h = get_hit(b_hit, &g, mkray(v3(-3, -1, 0), d));
        assert_true(h.t == 2);
        assert_v3_equal(h.n, v3(-1, 0, 0));
        /* Along the edge line y = 1, z = 1. */
        h = get_hit(b_hit, &g, mkray(v3(-3, 1, 1), d));
        assert_true(h.t == 2);
        assert_v3_equal(h.n, v3(-1, 0, 0));
        /* Starting on the face itself: the exit at x = 1. */
        h = get_hit(b_hit, &g, mkray(v3(0, 1, 0), d));
        assert_true(h.t == 1);
        assert_v3_equal(h.n, v3(1, 0, 0));
        /* In the face plane but beside the face: a miss. */
        assert_miss(b_hit, &g, mkray(v3(-3, 1, 5), d), 0, HUGE_VAL);
        /* Parallel to a slab, outside it. */
        assert_miss(b_hit, &g, mkray(v3(-3, 2, 0), d), 0, HUGE_VAL);
        assert_miss(b_hit, &g, mkray(v3(-3, nextafter(1, 2), 0), d), 0, HUGE_VAL);
        assert_miss(b_hit, &g, mkray(v3(-3, 0, nextafter(-1, -2)), d), 0, HUGE_VAL);
    }
    /* Parallel to two slabs, outside one; behind. */
    assert_miss(b_hit, &g, mkray(v3(0, 5, 0), v3(0, 0, 1)), 0, HUGE_VAL);
    assert_miss(b_hit, &g, mkray(v3(0, 0, 3), v3(0, 0, 1)), 0, HUGE_VAL);
}

/* A NaN in the ray is no ray: sphere, quad and plane miss it. The box must
** not take it for the harmless 0 * inf of a ray along a slab plane, which
** would report a hit whose point is NaN. */
static void box_nan_ray_misses(void **state)
{
    (void)state;
    box_geom gs[2];
    lc_vec3 e[3];
    gs[0] = cube();
    rotated_edges(e);
    gs[1] = mkbox(v3(-0.5, -0.5, -0.5), e[0], e[1], e[2]);
    ray rays[4] = {
        {{0, 0, -3}, {0, NAN, 1}}, {{NAN, 0, -3}, {0, 0, 1}},
        {{0, 0, -3}, {NAN, NAN, NAN}}, {{0.25, 0.25, NAN}, {0, 0, 1}},
    };
    int hits = 0;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 4; i++) {
            hit h;
            poison(&h);
            if (box_hit(&gs[k], &rays[i], 0, HUGE_VAL, &h)) {
                hits++;
                print_message("%s box, NaN ray %d: hit at t = %g, p = (%g, %g, %g)\n",
                              k ? "rotated" : "aligned", i, h.t, h.p.x, h.p.y, h.p.z);
            } else {
                assert_true(untouched(&h));
            }
        }
    if (hits)
        fail_msg("%d of 8 rays with a NaN component hit a box", hits);
    /* The other kinds, for comparison. */
    sphere_geom sg = mksphere(v3(0, 0, 0), 1);
    quad_geom qg = mkquad(v3(-1, -1, 0), v3(2, 0, 0), v3(0, 2, 0));
    plane_geom pg = mkplane(v3(0, 0, 0), v3(0, 0, 1));
    for (int i = 0; i < 4; i++) {
        assert_miss(s_hit, &sg, rays[i], 0, HUGE_VAL);
        assert_miss(q_hit, &qg, rays[i], 0, HUGE_VAL);
        assert_miss(p_hit, &pg, rays[i], 0, HUGE_VAL);
    }
}

/* Local-space slabs: rows of the inverse via cross products and 1/det (~6
** roundings each), applied to o - q (3 more): t and the normals agree with
** the closed form to ~20 eps relative; 1e-14 leaves a factor 2. */
static void box_rotated(void **state)
{
    (void)state;
    lc_vec3 e[3], q = v3(0.3, -0.2, 0.7);
    rotated_edges(e);
    box_geom g = mkbox(q, e[0], e[1], e[2]);
    assert_false(g.aligned);
    double det = v3_dot(e[0], v3_cross(e[1], e[2]));
    lc_vec3 centre = v3_add(q, v3_mul(v3_add(v3_add(e[0], e[1]), e[2]), 0.5));
    for (int i = 0; i < 3; i++) {
        lc_vec3 ej = e[(i + 1) % 3], ek = e[(i + 2) % 3];
        lc_vec3 nhi = v3_mul(v3_norm(v3_cross(ej, ek)), det > 0 ? 1 : -1);
        for (int hi = 0; hi < 2; hi++) {
            lc_vec3 n = hi ? nhi : v3_neg(nhi);
            lc_vec3 fc = v3_madd(centre, e[i], hi ? 0.5 : -0.5);
            hit h = get_hit(b_hit, &g, mkray(v3_madd(fc, n, 5), v3_neg(n)));
            if (fabs(h.t - 5) > 1e-14 * 5)
                fail_msg("face %d%c: t = %.17g", i, hi ? '+' : '-', h.t);
            assert_v3_near(h.n, n, 1e-14);
            /* The normal is the prepared one, bit for bit. */
            assert_v3_equal(h.n, hi ? g.un[i] : v3_neg(g.un[i]));
            assert_v3_near(h.p, fc, 1e-14 * 5);
            /* From inside (the centre), leaving through this face. */
            lc_vec3 dir = v3_norm(v3_sub(fc, centre));
            h = get_hit(b_hit, &g, mkray(centre, dir));
            assert_v3_equal(h.n, hi ? g.un[i] : v3_neg(g.un[i]));
            assert_v3_near(h.p, fc, 1e-14 * 5);
        }
    }
    /* Through an edge and through a corner: the normal is one of the faces'. */
    for (int i = 0; i < 3; i++) {
        lc_vec3 ej = e[(i + 1) % 3];
        lc_vec3 mid = v3_madd(v3_madd(q, e[i], 0.5), ej, 1);   /* on edge j=1, k=0 */
        lc_vec3 out = v3_norm(v3_sub(mid, centre));
        hit h = get_hit(b_hit, &g, mkray(v3_madd(mid, out, 4), v3_neg(out)));
        int j = (i + 1) % 3, k = (i + 2) % 3;
        if (!v3_eq(h.n, g.un[j]) && !v3_eq(h.n, v3_neg(g.un[k])))
            fail_msg("edge %d: normal (%.17g, %.17g, %.17g)", i, h.n.x, h.n.y, h.n.z);
        assert_v3_near(h.p, mid, 1e-13);
    }
    lc_vec3 corner = v3_add(v3_add(q, e[0]), e[1]);            /* (1, 1, 0) local */
    lc_vec3 out = v3_norm(v3_sub(corner, centre));
    hit h = get_hit(b_hit, &g, mkray(v3_madd(corner, out, 4), v3_neg(out)));
    if (!v3_eq(h.n, g.un[0]) && !v3_eq(h.n, g.un[1]) && !v3_eq(h.n, v3_neg(g.un[2])))
        fail_msg("corner: normal (%.17g, %.17g, %.17g)", h.n.x, h.n.y, h.n.z);
    assert_v3_near(h.p, corner, 1e-13);
    /* Beside the box, and parallel to a face plane outside it. */
    lc_vec3 n0 = g.un[0];
    assert_miss(b_hit, &g, mkray(v3_madd(centre, n0, 5), n0), 0, HUGE_VAL);
    lc_vec3 along = v3_norm(e[1]);
    assert_miss(b_hit, &g, mkray(v3_madd(v3_madd(centre, n0, 3), along, -5), along), 0,
                HUGE_VAL);
}

/* ---- Plane --------------------------------------------------------------- */

static void plane_hit_and_snap(void **state)
{
    (void)state;
    plane_geom g = mkplane(v3(0, 0, 0), v3(0, 1, 0));
    assert_int_equal(g.axis, 1);
    const double s = SQRT1_2;
    hit h = get_hit(p_hit, &g, mkray(v3(1, 2, 3), v3(s, -s, 0)));
    assert_true(h.t == 2 / s);                          /* (0 - 2) / -s: 1 rounding */
    assert_near_ulps(h.t, 2 * SQRT2, 2);
    assert_true(h.p.y == 0);                            /* snapped, exactly */
    assert_true(h.perr.y == 0);
    assert_near_ulps(h.p.x, 3, 2);
    assert_true(h.p.z == 3);
    assert_v3_equal(h.n, v3(0, 1, 0));

    /* A plane y = -2 given by a scaled normal and a point off the axis. */
    g = mkplane(v3(7, -2, 9), v3(0, 4, 0));
    h = get_hit(p_hit, &g, mkray(v3(0.5, 3, 0.25), v3(0, -1, 0)));
    assert_true(h.t == 5);
    assert_v3_equal(h.p, v3(0.5, -2, 0.25));
    assert_v3_equal(h.n, v3(0, 1, 0));
    /* A downward normal. */
    g = mkplane(v3(0, 0, 1.5), v3(0, 0, -2));
    h = get_hit(p_hit, &g, mkray(v3(0.5, 0.5, -1), v3(0, 0, 1)));
    assert_true(h.t == 2.5);
    assert_true(h.p.z == 1.5);
    assert_v3_equal(h.n, v3(0, 0, -1));

    /* A general plane: the snapped point is on it to within its perr. */
    g = mkplane(v3(1, 1, 1), v3(1, 2, 2));
    assert_int_equal(g.axis, -1);
    h = get_hit(p_hit, &g, mkray(v3(-3, 0.1, 7), v3_norm(v3(1, 0.2, -1))));
    long double res = ((long double)h.p.x - 1) * g.n.x +
                      ((long double)h.p.y - 1) * g.n.y +
                      ((long double)h.p.z - 1) * g.n.z;
    assert_true(fabsl(res) <= v3_dot(v3_abs(g.n), h.perr));
}

static void plane_misses(void **state)
{
    (void)state;
    plane_geom g = mkplane(v3(0, 0, 0), v3(0, 1, 0));
    /* Parallel, above and in the plane. */
    assert_miss(p_hit, &g, mkray(v3(0, 1, 0), v3(1, 0, 0)), 0, HUGE_VAL);
    assert_miss(p_hit, &g, mkray(v3(0, 0, 0), v3(1, 0, 0)), 0, HUGE_VAL);
    assert_miss(p_hit, &g, mkray(v3(0, 0, 0), v3(SQRT1_2, -0.0, SQRT1_2)), 0,
                HUGE_VAL);
    /* Starting on the plane: t = 0 is no hit, whichever way the ray goes. */
    assert_miss(p_hit, &g, mkray(v3(3, 0, 4), v3(0, -1, 0)), 0, HUGE_VAL);
    assert_miss(p_hit, &g, mkray(v3(3, 0, 4), v3(0, 1, 0)), 0, HUGE_VAL);
    assert_miss(p_hit, &g, mkray(v3(3, -0.0, 4), v3(0.6, -0.8, 0)), 0, HUGE_VAL);
    /* Going away, beyond tmax, NaN. */
    assert_miss(p_hit, &g, mkray(v3(0, 1, 0), v3(0, 1, 0)), 0, HUGE_VAL);
    assert_miss(p_hit, &g, mkray(v3(0, 1, 0), v3(0, -1, 0)), 0, 1);
    assert_miss(p_hit, &g, mkray(v3(0, NAN, 0), v3(0, -1, 0)), 0, HUGE_VAL);
}

/* A scaled axis normal: v3_norm((0, 49, 0)) is (0, 1 - 2^-53, 0), since
** 49 * (1/49) != 1. The plane is still exactly y = p.y: a ray from a point
** on it must not hit it, and a ray from 1 above it hits at t = 1 exactly. */
static void plane_scaled_normal_is_exact(void **state)
{
    (void)state;
    plane_geom g = mkplane(v3(0, 1, 0), v3(0, 49, 0));
    assert_int_equal(g.axis, 1);
    assert_v3_equal(g.n, v3(0, 1, 0));
    assert_miss(p_hit, &g, mkray(v3(3, 1, 4), v3(0, 1, 0)), 0, HUGE_VAL);
    /* The one that self-hits if k was computed with the inexact normal. */
    assert_miss(p_hit, &g, mkray(v3(3, 1, 4), v3(0, -1, 0)), 0, HUGE_VAL);
    plane_geom far = mkplane(v3(0, 1e7, 0), v3(0, 49, 0));
    hit h = get_hit(p_hit, &far, mkray(v3(0, 1e7 + 1, 0), v3(0, -1, 0)));
    if (h.t != 1)
        fail_msg("t = %.17g, want 1 (p.y = %.17g)", h.t, h.p.y);
    assert_miss(p_hit, &far, mkray(v3(5, 1e7, 0), v3(0.6, -0.8, 0)), 0, HUGE_VAL);
    if (g.k != 1 || far.k != 1e7)
        fail_msg("k = %.17g and %.17g, want 1 and 1e7", g.k, far.k);
}

/* A ray 1e-12 rad below the horizon from height 1: t = 1/sin(1e-12) = 1e12,
** the point 1e12 away; one rounding in d.y and one in the division. */
static void plane_grazing(void **state)
{
    (void)state;
    plane_geom g = mkplane(v3(0, 0, 0), v3(0, 1, 0));
    const double a = 1e-12;
    lc_vec3 d = v3(cos(a), -sin(a), 0);
    hit h = get_hit(p_hit, &g, mkray(v3(0, 1, 0), d));
    long double tr = 1.0L / sinl(1e-12L);
    assert_near_ulps(h.t, (double)tr, 2);
    assert_true(h.p.y == 0);
    assert_near_ulps(h.p.x, (double)(tr * cosl(1e-12L)), 3);
    /* From below at 1e-300 (a normal number): t = 1/1e-300, one rounding. */
    h = get_hit(p_hit, &g, mkray(v3(0, -1, 0), v3(1, 1e-300, 0)));
    assert_true(h.t == 1 / 1e-300);
    assert_true(h.p.y == 0 && h.p.x == h.t);
}

/* ---- Spawned rays -------------------------------------------------------- */

static const double scales[] = {1e-6, 1e-3, 1, 1e3, 1e6};
static const double shifts[] = {0, 1e3, 1e5, 1e7};
#define NSCALES (sizeof scales / sizeof scales[0])
#define NSHIFTS (sizeof shifts / sizeof shifts[0])
#define SPAWN_RAYS 300

/* Both roots of |o + t d - c| = r in long double (any |d|); 0 when none. */
static int sphere_roots_l(const sphere_geom *g, lc_vec3 o, lc_vec3 d, long double *t0,
                          long double *t1, long double *disc)
{
    long double f[3] = {(long double)o.x - g->c.x, (long double)o.y - g->c.y,
                        (long double)o.z - g->c.z};
    long double dd[3] = {d.x, d.y, d.z};
    long double a = 0, b = 0, v2 = 0;
    for (int i = 0; i < 3; i++) {
        a += dd[i] * dd[i];
        b += f[i] * dd[i];
    }
    b /= a;
    for (int i = 0; i < 3; i++) {
        long double vi = f[i] - b * dd[i];
        v2 += vi * vi;
    }
    *disc = (long double)g->r * g->r - v2;
    if (*disc < 0)
        return 0;
    long double sq = sqrtl(*disc / a);
    *t0 = -b - sq;
    *t1 = -b + sq;
    return 1;
}

/* Rays spawned from sphere hits, camera outside or inside: leaving (w.n > 0)
** they never hit the sphere again; entering they hit its far side. The far
** side's t is compared with the closed form from the spawned origin: f and
** b carry a few roundings of |f| ~ r, the discriminant (r - |v|)(r + |v|)
** about 16 eps r^2 absolute, which its square root divides by sqrt(disc). */
static void spawn_sphere(void **state)
{
    (void)state;
    int tested = 0, self = 0, outside_bad = 0, lost = 0, inside_bad = 0, far_bad = 0;
    double worst = 0;
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            uint64_t seed = 1000 + si * 10 + ti;
            double r = scales[si];
            lc_vec3 c = shift_of(shifts[ti]);
            sphere_geom g = mksphere(c, r);
            for (int k = 0; k < SPAWN_RAYS; k++) {
                lc_vec3 o = v3_madd(c, ball_dir(&seed), (k % 4 == 3 ? 0.5 : 4) * r);
                lc_vec3 to = v3_madd(c, rand_in_ball(&seed), 0.9 * r);
                ray cam = mkray(o, v3_norm(v3_sub(to, o)));
                hit h;
                if (!sphere_hit(&g, &cam, 0, HUGE_VAL, &h))
                    fail_msg("r %g, T %g: camera ray %d misses", r, shifts[ti], k);
                tested++;
                long double t0, t1, disc;
                /* Leaving. */
                lc_vec3 w = rand_dir(&seed, h.n, 1, k);
                ray out = mkray(spawn_origin(&h, w), w);
                hit h2;
                if (sphere_hit(&g, &out, 0, HUGE_VAL, &h2))
                    self++;
                if (sphere_roots_l(&g, out.o, w, &t0, &t1, &disc) && t1 > 0)
                    outside_bad++;      /* the true sphere is ahead of the origin */
                /* Entering. */
                w = rand_dir(&seed, h.n, -1, k);
                ray in = mkray(spawn_origin(&h, w), w);
                if (!sphere_hit(&g, &in, 0, HUGE_VAL, &h2)) {
                    lost++;
                    continue;
                }
                if (!sphere_roots_l(&g, in.o, w, &t0, &t1, &disc) ||
                    !(t0 < 0 && t1 > 0)) {
                    inside_bad++;       /* the spawned origin is not inside */
                    continue;
                }
                double a = 16 * EPS * (r + fabs(v3_dot(v3_sub(in.o, c), w)));
                long double dd = 16 * EPS * (long double)r * r;
                double tol = a + (double)(dd < disc ? dd / sqrtl(disc) : sqrtl(dd));
                double err = (double)fabsl(h2.t - t1);
                if (err / tol > worst)
                    worst = err / tol;
                if (!(h2.t > 0) || err > tol)
                    far_bad++;
            }
        }
    print_message("spheres: %d hits, %d self-hits, %d lost, %d far side off "
                  "(worst %.2g of bound)\n", tested, self, lost, far_bad, worst);
    if (self || outside_bad || lost || inside_bad || far_bad)
        fail_msg("of %d hits: %d self-hits leaving, %d origins left inside, %d lost "
                 "entering, %d origins not inside, %d far-side t off (worst %.3g)",
                 tested, self, outside_bad, lost, inside_bad, far_bad, worst);
}

/* An edge frame: axis-aligned for even i (exact snapping), tilted for odd. */
static void rand_frame(uint64_t *seed, int i, lc_vec3 e[3])
{
    if (i % 2 == 0) {
        int a = (i / 2) % 3;
        for (int j = 0; j < 3; j++) {
            int ax = (a + j) % 3;
            e[j] = v3(ax == 0, ax == 1, ax == 2);
        }
        return;
    }
    lc_vec3 x = ball_dir(seed), y = ball_dir(seed);
    y = v3_norm(v3_madd(y, x, -v3_dot(x, y)));
    e[0] = x;
    e[1] = y;
    e[2] = v3_cross(x, y);
}

/* Quads: a ray spawned from a hit toward either side never hits the quad
** again, and its origin is on that side of the true plane. */
static void spawn_quad(void **state)
{
    (void)state;
    int tested = 0, missed = 0, edge_missed = 0, self = 0, wrong_side = 0;
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            uint64_t seed = 2000 + si * 10 + ti;
            double s = scales[si];
            for (int k = 0; k < SPAWN_RAYS; k++) {
                lc_vec3 e[3];
                rand_frame(&seed, k / 10, e);
                double lu = s * (0.5 + lcg(&seed)), lv = s * (0.5 + lcg(&seed));
                double shear = s * (lcg(&seed) - 0.5) * (k / 10 % 2);
                lc_vec3 u = v3_mul(e[0], lu);
                lc_vec3 v = v3_madd(v3_mul(e[1], lv), e[0], shear);
                lc_vec3 q = v3_madd(shift_of(shifts[ti]), rand_in_ball(&seed), s);
                quad_geom g = mkquad(q, u, v);
                /* One in five aims at an edge; its rounding may miss. */
                int edge = k % 5 == 0;
                double al = edge ? (double)(k % 2) : 0.01 + 0.98 * lcg(&seed);
                lc_vec3 to = v3_madd(v3_madd(q, u, al), v, 0.01 + 0.98 * lcg(&seed));
                /* The camera at least 0.1 rad off the plane: t = (k - n.o) / n.d
                ** carries eps |n| |o| absolute, so at T = 1e7 an origin a few
                ** ulps off the plane of a 1e-6 quad may see t = 0. */
                lc_vec3 a = ball_dir(&seed);
                while (fabs(v3_dot(a, g.un)) < 0.1)
                    a = ball_dir(&seed);
                lc_vec3 o = v3_madd(to, a, 4 * s);
                ray cam = mkray(o, v3_norm(v3_sub(to, o)));
                hit h;
                if (!quad_hit(&g, &cam, 0, HUGE_VAL, &h)) {
                    if (edge)
                        edge_missed++;   /* the aim point rounded off the edge */
                    else
                        missed++;
                    continue;
                }
                tested++;
                for (int side = -1; side <= 1; side += 2) {
                    lc_vec3 w = rand_dir(&seed, h.n, side, k);
                    ray sr = mkray(spawn_origin(&h, w), w);
                    hit h2;
                    if (quad_hit(&g, &sr, 0, HUGE_VAL, &h2))
                        self++;
                    long double dist = ((long double)sr.o.x - q.x) * g.n.x +
                                       ((long double)sr.o.y - q.y) * g.n.y +
                                       ((long double)sr.o.z - q.z) * g.n.z;
                    if (dist * side < 0)
                        wrong_side++;
                }
            }
        }
    print_message("quads: %d hits (%d edge aims missed), %d self-hits, %d wrong side\n",
                  tested, edge_missed, self, wrong_side);
    if (self || wrong_side || missed)
        fail_msg("of %d hits: %d self-hits, %d origins on the wrong side, %d interior "
                 "aims missed", tested, self, wrong_side, missed);
}

/* Boxes, aligned and rotated, camera outside or inside: a ray spawned from a
** hit with w.n > 0 leaves the face's half-space and never hits the box. */
static void spawn_box(void **state)
{
    (void)state;
    int tested = 0, self = 0, lost = 0, edge_missed = 0;
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            uint64_t seed = 3000 + si * 10 + ti;
            double s = scales[si];
            for (int k = 0; k < SPAWN_RAYS; k++) {
                lc_vec3 e[3];
                rand_frame(&seed, k / 10, e);
                for (int j = 0; j < 3; j++) {
                    double len = s * (0.5 + lcg(&seed));
                    e[j] = v3_mul(e[j], lcg(&seed) < 0.2 ? -len : len);
                }
                if (k / 10 % 2 == 0) {         /* aligned: edges back in x, y, z order */
                    lc_vec3 a[3];
                    for (int j = 0; j < 3; j++)
                        a[fabs(e[j].x) > 0 ? 0 : fabs(e[j].y) > 0 ? 1 : 2] = e[j];
                    for (int j = 0; j < 3; j++)
                        e[j] = a[j];
                }
                lc_vec3 p = v3_madd(shift_of(shifts[ti]), rand_in_ball(&seed), s);
                box_geom g = mkbox(p, e[0], e[1], e[2]);
                assert_int_equal(g.aligned, k / 10 % 2 == 0);
                lc_vec3 half = v3_mul(v3_add(v3_add(e[0], e[1]), e[2]), 0.5);
                lc_vec3 centre = v3_add(p, half);
                /* Aim inside, or exactly at an edge (k % 5 == 0: two local
                ** coordinates 0 or 1) or a corner (k % 5 == 1: all three). */
                int fixed = k % 5 == 0 ? 2 : k % 5 == 1 ? 3 : 0;
                lc_vec3 to = p;
                for (int j = 0; j < 3; j++)
                    to = v3_madd(to, e[j], j < fixed ? (double)(lcg(&seed) < 0.5)
                                                     : 0.05 + 0.9 * lcg(&seed));
                lc_vec3 o = k % 4 == 3 ? v3_madd(centre, rand_in_ball(&seed), 0.2 * s)
                                       : v3_madd(to, ball_dir(&seed), 5 * s);
                lc_vec3 d = v3_norm(v3_sub(to, o));
                if (k % 4 == 3)
                    d = ball_dir(&seed);
                ray cam = mkray(o, d);
                hit h;
                if (!box_hit(&g, &cam, 0, HUGE_VAL, &h)) {
                    if (fixed && k % 4 != 3)
                        edge_missed++;   /* the aim point rounded off the box */
                    else
                        lost++;
                    continue;
                }
                assert_hit_sane(&h);
                tested++;
                lc_vec3 w = rand_dir(&seed, h.n, 1, k);
                ray sr = mkray(spawn_origin(&h, w), w);
                hit h2;
                if (box_hit(&g, &sr, 0, HUGE_VAL, &h2))
                    self++;
            }
        }
    print_message("boxes: %d hits (%d edge aims missed), %d self-hits, "
                  "%d camera misses\n", tested, edge_missed, self, lost);
    if (self || lost)
        fail_msg("of %d hits: %d self-hits, %d camera rays missed", tested, self, lost);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sphere_from_outside),
        cmocka_unit_test(sphere_from_inside),
        cmocka_unit_test(sphere_tangent),
        cmocka_unit_test(sphere_misses),
        cmocka_unit_test(sphere_small_and_far),
        cmocka_unit_test(quad_inside_hit),
        cmocka_unit_test(quad_edges_by_one_ulp),
        cmocka_unit_test(quad_parallel_and_behind),
        cmocka_unit_test(box_aligned_faces),
        cmocka_unit_test(box_aligned_edges_and_corners),
        cmocka_unit_test(box_origin_inside),
        cmocka_unit_test(box_ray_in_face_plane),
        cmocka_unit_test(box_nan_ray_misses),
        cmocka_unit_test(box_rotated),
        cmocka_unit_test(plane_hit_and_snap),
        cmocka_unit_test(plane_misses),
        cmocka_unit_test(plane_scaled_normal_is_exact),
        cmocka_unit_test(plane_grazing),
        cmocka_unit_test(spawn_sphere),
        cmocka_unit_test(spawn_quad),
        cmocka_unit_test(spawn_box),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
