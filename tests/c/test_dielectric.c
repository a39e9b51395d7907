/* test_dielectric.c: Snell's law, the Fresnel equations (docs/numerics.md 1.10,
** H19) and the media a path is in (H20's rules), against closed forms. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>
#include "material/dielectric.h"
#include "media/media.h"
#include "helpers.h"

#define SUBNORMAL_MIN 0x1p-1074       /* C11's DBL_TRUE_MIN */

/* The indices of H19: leaving glass, entering glass, none, diamond. */
static const double etas[] = {1 / 1.5, 1.5, 1.0, 2.4};
#define NETAS (sizeof etas / sizeof etas[0])

/* ((n - 1) / (n + 1))^2, from either side. */
static void normal_incidence(void **state)
{
    (void)state;
    const double ns[] = {1.5, 1.333, 2.4, 1.0001, 100};
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        double n = ns[i], want = (n - 1) / (n + 1) * ((n - 1) / (n + 1));
        assert_true(fabs(dielectric_fresnel(1, n) - want) <= 4 * DBL_EPSILON * want);
        /* From inside: the same for the ratio as rounded, 1 / n. */
        double e = 1 / n, back = (e - 1) / (e + 1) * ((e - 1) / (e + 1));
        assert_true(fabs(dielectric_fresnel(1, e) - back) <= 4 * DBL_EPSILON * back);
        assert_true(fabs(dielectric_fresnel(-1, n) - back) <= 4 * DBL_EPSILON * back);
        assert_true(fabs(back - want) <= 1e-11 * want);
    }
    assert_true(fabs(dielectric_fresnel(1, 1.5) - 0.04) <= 1e-12);
    assert_true(fabs(dielectric_fresnel(-1, 1.5) - 0.04) <= 1e-12);
}

/* At Brewster's angle, tan = eta, r_parallel vanishes and F is r_perp^2 / 2,
** r_perp = (1 - eta^2) / (1 + eta^2); so entering and leaving. */
static void brewster(void **state)
{
    (void)state;
    const double ns[] = {1.5, 1 / 1.5, 1.333, 2.4};
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        double eta = ns[i], c = 1 / sqrt(1 + eta * eta), rp, rs;
        double F = dielectric_fresnel_parts(c, eta, &rp, &rs);
        double perp = (1 - eta * eta) / (1 + eta * eta);
        assert_true(fabs(rp) <= 8 * DBL_EPSILON);
        assert_true(fabs(rs - perp) <= 8 * DBL_EPSILON);
        assert_true(fabs(F - perp * perp / 2) <= 8 * DBL_EPSILON * F);
    }
    /* glass, 56.31 degrees: 0.0739645 */
    double glass = dielectric_fresnel(1 / sqrt(1 + 2.25), 1.5);
    assert_true(fabs(glass - 0.07396449704142) < 1e-13);
}

/* The largest cosine (smallest angle) at which eta totally reflects: the
** doubles around the critical angle, searched one ulp at a time from the
** closed form. */
static double critical_cos(double eta)
{
    double c = sqrt(1 - eta * eta);           /* cos of asin(eta), eta < 1 */
    lc_vec3 t, n = v3(0, 0, 1);
    for (int k = 0; k < 64; k++)
        c = nextafter(c, 2);                  /* from above: transmitted */
    for (;;) {
        lc_vec3 d = v3(sqrt((1 - c) * (1 + c)), 0, -c);
        if (!dielectric_refract(d, n, eta, &t))
            return c;
        c = nextafter(c, 0);
    }
}

/* At and past the critical angle: R = 1 and T = 0 exactly, no refracted
** ray; one ulp short of it, a grazing refracted ray and F just under 1. */
static void critical_angle(void **state)
{
    (void)state;
    const double ns[] = {1 / 1.5, 1 / 1.333, 1 / 2.4};
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        double eta = ns[i], c = critical_cos(eta);
        /* 41.81 degrees for glass, 48.61 for water */
        assert_true(fabs(acos(c) - asin(eta)) < 1e-7);
        for (double x = c; x >= 0; x = x > 1e-3 ? x - 1e-3 : x > 0 ? 0 : -1) {
            double F = dielectric_fresnel(x, eta);
            assert_true(F == 1);
            assert_true(1 - F == 0);
            lc_vec3 t, d = v3(sqrt((1 - x) * (1 + x)), 0, -x);
            assert_int_equal(dielectric_refract(d, v3(0, 0, 1), eta, &t), 0);
        }
        double up = nextafter(c, 2), F = dielectric_fresnel(up, eta);
        assert_true(F < 1 && F > 1 - 1e-6);
        lc_vec3 t, d = v3(sqrt((1 - up) * (1 + up)), 0, -up);
        assert_int_equal(dielectric_refract(d, v3(0, 0, 1), eta, &t), 1);
        assert_true(t.z < 0 && t.z > -1e-6);   /* along the surface */
    }
}

/* One check of H19 at cos c and eta. */
static void check_f(double c, double eta)
{
    double F = dielectric_fresnel(c, eta);
    assert_false(isnan(F));
    assert_true(F >= 0 && F <= 1);
    assert_true(F + (1 - F) == 1);            /* R + T = 1 exactly */
    if (eta == 1)
        assert_true(F == 0);
    /* Past the critical angle, from whichever side, exactly 1. */
    double a = c < -1 ? 1 : c > 1 ? 1 : fabs(c), e = c < 0 ? 1 / eta : eta;
    if (eta != 1 && (1 - a) * (1 + a) / (e * e) >= 1)
        assert_true(F == 1);
}

/* H19: 10^6 cosines over [-1, 1] and the values rounding makes, for each
** eta: never NaN, F in [0, 1], R + T = 1, 1 at grazing, 0 for eta = 1. */
static void grazing_sweep(void **state)
{
    (void)state;
    const double specials[] = {0.0, -0.0, 1, -1, nextafter(1, 0), -nextafter(1, 0),
                               nextafter(1, 2), -nextafter(1, 2), SUBNORMAL_MIN,
                               -SUBNORMAL_MIN, DBL_MIN, -DBL_MIN, 1e-300, -1e-300,
                               DBL_EPSILON, -DBL_EPSILON};
    for (size_t k = 0; k < NETAS; k++) {
        double eta = etas[k];
        uint64_t seed = 19 + k;
        for (int i = 0; i < 1000000; i++)
            check_f(2 * lcg(&seed) - 1, eta);
        for (size_t i = 0; i < sizeof specials / sizeof specials[0]; i++)
            check_f(specials[i], eta);
        if (eta != 1) {
            assert_true(dielectric_fresnel(0.0, eta) == 1);
            assert_true(dielectric_fresnel(-0.0, eta) == 1);
            assert_true(dielectric_fresnel(SUBNORMAL_MIN, eta) > 1 - 1e-15);
        }
    }
    assert_true(dielectric_fresnel(0.0, 1) == 0);       /* no interface at all */
}

/* Snell's law: eta sin t = sin i, t unit, in the plane of d and n, on the
** far side; eta = 1 and a ray along the normal go straight on. */
static void snell(void **state)
{
    (void)state;
    uint64_t seed = 7;
    int refracted = 0;
    for (int i = 0; i < 200000; i++) {
        lc_vec3 n = rand_unit(&seed), d = rand_unit(&seed);
        if (v3_dot(d, n) > 0)
            d = v3_neg(d);
        if (v3_dot(d, n) == 0)
            continue;
        double eta = etas[i % NETAS], F = dielectric_fresnel(-v3_dot(d, n), eta);
        lc_vec3 t;
        if (!dielectric_refract(d, n, eta, &t)) {
            assert_true(F == 1);
            continue;
        }
        refracted++;
        assert_true(F < 1);
        assert_true(fabs(v3_len(t) - 1) <= 4 * DBL_EPSILON);
        assert_true(v3_dot(t, n) < 0);
        double si = v3_len(v3_cross(d, n)), st = v3_len(v3_cross(t, n));
        assert_true(fabs(eta * st - si) <= 1e-14);
        assert_true(fabs(v3_dot(v3_cross(d, n), t)) <= 1e-14);     /* coplanar */
        if (eta == 1)
            assert_memory_equal(&t, &d, sizeof t);                  /* bit for bit */
    }
    assert_true(refracted > 150000);
    /* Along the normal, undeflected (a ray through a sphere's centre). */
    const double ns[] = {1.5, 1 / 1.5, 2.4};
    for (size_t i = 0; i < 3; i++) {
        lc_vec3 t, d = v3_norm(v3(0.3, -1, 0.2)), n = v3_neg(d);
        assert_int_equal(dielectric_refract(d, n, ns[i], &t), 1);
        assert_true(v3_len(v3_sub(t, d)) <= 4 * DBL_EPSILON);
    }
}

/* ---- media --------------------------------------------------------------- */

static uint32_t add_medium(lc_scene *s, double ior)
{
    lc_material m = lc_material_default();
    m.kt = 1;
    m.ior = ior;
    lc_error err;
    int i = lc_scene_add_material(s, &m, &err);
    assert_true(i >= 0);
    return (uint32_t)i;
}

/* Crosses mi (entering or not) from md: returns 1 for an interface and
** checks its indices; md becomes the media past it. */
static int cross(const lc_scene *s, media *md, uint32_t mi, int entering, double want1,
                 double want2)
{
    media past;
    double n1 = 0, n2 = 0;
    int real = media_cross(s, md, mi, entering, &past, &n1, &n2);
    if (real) {
        assert_true(n1 == want1);
        assert_true(n2 == want2);
    }
    *md = past;
    return real;
}

/* The index ratio at every interface of nested closed objects (H20), a
** camera inside glass, overlaps, and more media than the stack holds. */
static void nested_media(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    uint32_t glass = add_medium(s, 1.5), air = add_medium(s, 1);
    uint32_t water = add_medium(s, 1.333);
    media md = {0, {0}};
    /* An air bubble in glass: 1 -> 1.5 -> 1 -> 1.5 -> 1. */
    assert_true(cross(s, &md, glass, 1, 1, 1.5));
    assert_true(cross(s, &md, air, 1, 1.5, 1));
    assert_true(cross(s, &md, air, 0, 1, 1.5));
    assert_true(cross(s, &md, glass, 0, 1.5, 1));
    assert_int_equal(md.n, 0);
    /* A glass sphere in the same glass: its surface is no interface. */
    assert_true(cross(s, &md, glass, 1, 1, 1.5));
    assert_false(cross(s, &md, glass, 1, 0, 0));
    assert_false(cross(s, &md, glass, 0, 0, 0));
    assert_true(cross(s, &md, glass, 0, 1.5, 1));
    assert_int_equal(md.n, 0);
    /* Water in a glass, overlapping its walls: glass -> water at the water's
    ** surface, and the glass's inner wall, inside the water, is none. */
    assert_true(cross(s, &md, glass, 1, 1, 1.5));
    assert_true(cross(s, &md, water, 1, 1.5, 1.333));
    assert_false(cross(s, &md, glass, 0, 0, 0));
    assert_true(cross(s, &md, glass, 1, 1.333, 1.5));
    assert_false(cross(s, &md, water, 0, 0, 0));
    assert_true(cross(s, &md, glass, 0, 1.5, 1));
    assert_int_equal(md.n, 0);
    /* A camera inside glass leaves what it never entered. */
    assert_true(cross(s, &md, glass, 0, 1.5, 1));
    assert_int_equal(md.n, 0);
    /* Deeper than the stack: the outermost two are forgotten; the last in
    ** the stack and they are left into air, right for the outermost. */
    uint32_t shells[MEDIA_MAX + 2];
    double prev = 1;
    for (int i = 0; i < MEDIA_MAX + 2; i++) {
        double n = 1.1 + 0.1 * i;
        shells[i] = add_medium(s, n);
        assert_true(cross(s, &md, shells[i], 1, prev, n));
        prev = n;
    }
    assert_int_equal(md.n, MEDIA_MAX);
    for (int i = MEDIA_MAX + 1; i >= 0; i--) {
        double out = i > 0 ? 1.1 + 0.1 * (i - 1) : 1;
        if (i <= 2)                /* inside the forgotten ones: air outside */
            out = 1;
        assert_true(cross(s, &md, shells[i], 0, 1.1 + 0.1 * i, out));
    }
    assert_int_equal(md.n, 0);
    lc_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(normal_incidence),
        cmocka_unit_test(brewster),
        cmocka_unit_test(critical_angle),
        cmocka_unit_test(grazing_sweep),
        cmocka_unit_test(snell),
        cmocka_unit_test(nested_media),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
