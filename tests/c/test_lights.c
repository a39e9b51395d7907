/* test_lights.c: a spot's cone against its closed form (inside, the
** smoothstep edge, outside, a hard edge), directional lights' checks, the
** sky gradient and its texture coordinates per direction, and the tone
** curves' values. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "lancer.h"
#include "helpers.h"

#define PI 3.14159265358979323846

/* The point at angle theta (degrees) off a spot at the origin pointing down
** -y, at distance 3: in the xy plane. */
static lc_vec3 off_axis(double theta)
{
    double t = theta * PI / 180;
    return (lc_vec3){3 * sin(t), -3 * cos(t), 0};
}

static void spot_cone_and_edge(void **state)
{
    (void)state;
    lc_spot_light l = lc_spot_light_default();
    l.angle = 30, l.soft = 10;
    double co = cos(30 * PI / 180), ci = cos(20 * PI / 180);
    for (double th = 0; th <= 40; th += 0.25) {
        double got = lc_spot_light_share(&l, off_axis(th)), want;
        double c = cos(th * PI / 180);
        if (th <= 20) {
            want = 1;
        } else if (th >= 30) {
            want = 0;
        } else {
            double t = (c - co) / (ci - co);
            want = t * t * (3 - 2 * t);
        }
        /* The angle goes in through a rounded sine and cosine: a few ulps. */
        near(got, want, 1e-12, "share");
        if (th >= 30.25 && got != 0)
            fail_msg("outside the cone at %g degrees: %g, not exactly 0", th, got);
        if (th <= 19.75 && got != 1)
            fail_msg("inside the cone at %g degrees: %g, not exactly 1", th, got);
    }
    /* Halfway through the edge in cosine: exactly a half. */
    double half = acos((co + ci) / 2) * 180 / PI;
    near(lc_spot_light_share(&l, off_axis(half)), 0.5, 1e-12, "mid-edge");
    /* A hard edge: 1 to the edge itself, 0 past it; the position is dark. */
    l.soft = 0;
    assert_true(lc_spot_light_share(&l, off_axis(29.999)) == 1);
    assert_true(lc_spot_light_share(&l, off_axis(30.001)) == 0);
    assert_true(lc_spot_light_share(&l, l.position) == 0);
    /* Length and orientation of the axis do not matter. */
    l.direction = (lc_vec3){0, -1e-3, 0};
    assert_true(lc_spot_light_share(&l, off_axis(29.999)) == 1);
    l.direction = (lc_vec3){1, 0, 0};
    l.soft = 10;
    double t = (cos(25 * PI / 180) - co) / (ci - co);
    near(lc_spot_light_share(&l, (lc_vec3){5, 5 * tan(25 * PI / 180), 0}),
         t * t * (3 - 2 * t), 1e-12, "along +x");
}

static void checks(void **state)
{
    (void)state;
    lc_error err;
    lc_spot_light s = lc_spot_light_default();
    assert_int_equal(lc_spot_light_check(&s, &err), LC_OK);
    struct { double angle, soft; const char *field; } bad[] = {
        {0, 0, "angle"}, {180, 5, "angle"}, {NAN, 5, "angle"}, {30, 31, "soft"},
        {30, -1, "soft"}, {30, NAN, "soft"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        lc_spot_light b = s;
        b.angle = bad[i].angle, b.soft = bad[i].soft;
        assert_int_equal(lc_spot_light_check(&b, &err), LC_EARG);
        assert_string_equal(err.field, bad[i].field);
    }
    lc_spot_light z = s;
    z.direction = (lc_vec3){0, 0, 0};
    assert_int_equal(lc_spot_light_check(&z, &err), LC_EARG);
    assert_string_equal(err.field, "direction");
    z = s;
    z.intensity = -1;
    assert_int_equal(lc_spot_light_check(&z, &err), LC_EARG);
    assert_string_equal(err.field, "intensity");
    lc_directional_light d = lc_directional_light_default();
    assert_int_equal(lc_directional_light_check(&d, &err), LC_OK);
    near(d.irradiance, PI, 0, "default irradiance");
    d.direction = (lc_vec3){NAN, 0, 0};
    assert_int_equal(lc_directional_light_check(&d, &err), LC_EARG);
    assert_string_equal(err.field, "direction");
    d = lc_directional_light_default();
    d.irradiance = -2;
    assert_int_equal(lc_directional_light_check(&d, &err), LC_EARG);
    assert_string_equal(err.field, "irradiance");
}

static void sky_gradient_per_direction(void **state)
{
    (void)state;
    lc_error err;
    lc_textures *s = lc_textures_new(&err);
    lc_texture t = lc_texture_default(LC_TEX_SKY);
    t.a = (lc_color){0.25f, 0.5f, 1};      /* zenith */
    t.b = (lc_color){1, 1, 1};             /* horizon */
    t.c = (lc_color){0.5f, 0.25f, 0};      /* ground */
    int i = lc_textures_add(s, &t, &err);
    assert_true(i >= 0);
    const double uv[2] = {0, 0};
    for (int k = -8; k <= 8; k++) {
        double y = k / 8.0, h = sqrt(1 - y * y);
        lc_vec3 d = {h * 0.6, y, h * 0.8};
        lc_vec3 far = {d.x * 1e6, d.y * 1e6, d.z * 1e6};  /* the length does not matter */
        lc_color c = lc_textures_eval(s, i, d, d, uv);
        lc_color f = lc_textures_eval(s, i, far, far, uv);
        double want[3];
        for (int ch = 0; ch < 3; ch++) {
            double zen = ch == 0 ? 0.25 : ch == 1 ? 0.5 : 1, gr = ch == 0 ? 0.5 : ch == 1 ? 0.25 : 0;
            want[ch] = y >= 0 ? 1 + (zen - 1) * y : 1 + (gr - 1) * -y;
        }
        near(c.r, want[0], 1e-7, "r"), near(c.g, want[1], 1e-7, "g"), near(c.b, want[2], 1e-7, "b");
        near(f.r, c.r, 1e-7, "far r");
    }
    lc_textures_free(s);
    /* Sky coordinates: +z is the middle of the map, straight up its top. */
    double q[2];
    lc_sky_uv((lc_vec3){0, 0, 1}, q);
    near(q[0], 0.5, 0, "u of +z"), near(q[1], 0.5, 0, "v of +z");
    lc_sky_uv((lc_vec3){1, 0, 0}, q);
    near(q[0], 0.75, 1e-15, "u of +x");
    lc_sky_uv((lc_vec3){0, 1, 0}, q);
    near(q[1], 1, 0, "v of +y");
    lc_sky_uv((lc_vec3){0, -1, 0}, q);
    near(q[1], 0, 0, "v of -y");
}

static void tone_curves(void **state)
{
    (void)state;
    /* Clamp is the value itself (the encoder clamps), NaN and below 0 are 0. */
    near(lc_tone_curve(0.3, LC_TONE_CLAMP), 0.3, 0, "clamp 0.3");
    near(lc_tone_curve(7, LC_TONE_CLAMP), 7, 0, "clamp 7");
    near(lc_tone_curve(NAN, LC_TONE_FILMIC), 0, 0, "NaN");
    near(lc_tone_curve(-1, LC_TONE_FILMIC), 0, 0, "negative");
    /* Narkowicz's ACES fit at a few values, by hand. */
    static const double x[] = {0.18, 0.5, 1, 2, 4, 16};
    for (size_t i = 0; i < sizeof x / sizeof x[0]; i++) {
        double v = x[i], want = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14);
        near(lc_tone_curve(v, LC_TONE_FILMIC), want < 1 ? want : 1, 1e-15, "filmic");
    }
    near(lc_tone_curve(1, LC_TONE_FILMIC), 2.54 / 3.16, 1e-15, "filmic(1)");
    near(lc_tone_curve(1e30, LC_TONE_FILMIC), 1, 0, "filmic(huge)");
    near(lc_tone_curve(INFINITY, LC_TONE_FILMIC), 1, 0, "filmic(inf)");
    /* Increasing up to where it reaches 1 (x = 7.24): highlights keep their
    ** order. */
    double last = 0;
    for (double v = 0.01; v < 7.2; v *= 1.1) {
        double y = lc_tone_curve(v, LC_TONE_FILMIC);
        if (!(y > last))
            fail_msg("filmic not increasing at %g", v);
        last = y;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spot_cone_and_edge),
        cmocka_unit_test(checks),
        cmocka_unit_test(sky_gradient_per_direction),
        cmocka_unit_test(tone_curves),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
