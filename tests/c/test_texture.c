/* test_texture.c: each pattern against its formula at sampled points, noise's
** lattice zeros and range, image lookups (texel centres exact, bilinear
** midpoints exact, each wrap), mixes and nesting, placement, and every
** field's check. */
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

static const double NO_UV[2] = {0, 0};
static const lc_color RED = {1, 0, 0}, BLUE = {0, 0, 1};

static lc_color at(const lc_textures *s, int i, double x, double y, double z)
{
    return lc_textures_eval(s, i, (lc_vec3){x, y, z}, (lc_vec3){x, y, z}, NO_UV);
}

static int add(lc_textures *s, lc_texture t)
{
    lc_error err;
    int i = lc_textures_add(s, &t, &err);
    if (i < 0)
        fail_msg("%s: %s", err.field, err.msg);
    return i;
}

static void same(lc_color c, lc_color want, const char *what)
{
    if (c.r != want.r || c.g != want.g || c.b != want.b)
        fail_msg("%s: got (%.9g, %.9g, %.9g), want (%.9g, %.9g, %.9g)", what, c.r, c.g, c.b,
                 want.r, want.g, want.b);
}

static void checker_and_stripes(void **state)
{
    (void)state;
    lc_error err;
    lc_textures *s = lc_textures_new(&err);
    lc_texture c = lc_texture_default(LC_TEX_CHECKER);
    c.a = RED, c.b = BLUE, c.scale = 0.5;
    int ci = add(s, c);
    uint64_t x = 0x9e3779b97f4a7c15u;
    for (int n = 0; n < 10000; n++) {
        double p[3];
        for (int k = 0; k < 3; k++) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17;
            p[k] = ((double)(x >> 11) / 9007199254740992.0 - 0.5) * 40;
        }
        long sum = (long)floor(p[0] / 0.5) + (long)floor(p[1] / 0.5) + (long)floor(p[2] / 0.5);
        same(at(s, ci, p[0], p[1], p[2]), (sum & 1) ? BLUE : RED, "checker");
    }
    /* On the floor y = 0 exactly (a plane's hits are snapped there). */
    same(at(s, ci, 0.25, 0, 0.25), RED, "first square");
    same(at(s, ci, 0.75, 0, 0.25), BLUE, "its neighbour");
    same(at(s, ci, -0.25, 0, 0.25), BLUE, "across zero");
    same(at(s, ci, 1e15 + 0.25, 0, 0.25), RED, "far away: 2e15 squares, even");
    lc_texture st = lc_texture_default(LC_TEX_STRIPES);
    st.a = RED, st.b = BLUE, st.axis = (lc_vec3){0, 0, 3}, st.scale = 2;
    int si = add(s, st);
    same(at(s, si, 5, 5, 1.9), RED, "stripe 0");
    same(at(s, si, 5, 5, 2.1), BLUE, "stripe 1");
    same(at(s, si, 5, 5, -0.1), BLUE, "stripe -1");
    lc_textures_free(s);
}

static void gradient_noise_marble_wood(void **state)
{
    (void)state;
    lc_error err;
    lc_textures *s = lc_textures_new(&err);
    lc_texture g = lc_texture_default(LC_TEX_GRADIENT);
    g.a = (lc_color){0, 0, 0}, g.b = (lc_color){1, 2, 4};
    g.origin = (lc_vec3){0, 1, 0}, g.axis = (lc_vec3){0, 4, 0};
    int gi = add(s, g);
    same(at(s, gi, 7, 2, 3), (lc_color){0.25f, 0.5f, 1}, "a quarter of the way");
    same(at(s, gi, 7, 0, 3), (lc_color){0, 0, 0}, "before the start: a");
    same(at(s, gi, 7, 9, 3), (lc_color){1, 2, 4}, "past the end: b");
    /* Noise: 0 at every integer point; within [-1, 1]; continuous. */
    double lo = 0, hi = 0;
    for (int i = -20; i <= 20; i++)
        for (int j = -20; j <= 20; j++) {
            assert_true(lc_noise((lc_vec3){i, j, i - j}) == 0);
            assert_true(lc_noise((lc_vec3){i + 1e6, j * 1e9, 3}) == 0);
        }
    for (int n = 0; n < 200000; n++) {
        double v = lc_noise((lc_vec3){n * 0.0137, n * 0.0071 + 0.3, n * 0.0019 - 5});
        lo = fmin(lo, v), hi = fmax(hi, v);
        double w = lc_noise((lc_vec3){n * 0.0137 + 1e-9, n * 0.0071 + 0.3, n * 0.0019 - 5});
        near(w, v, 1e-8, "continuous");
    }
    assert_true(lo >= -1 && hi <= 1 && lo < -0.5 && hi > 0.5);
    /* The noise texture: 0.5 + 0.5 x octaves (Perlin's sum, normalised). */
    lc_texture nt = lc_texture_default(LC_TEX_NOISE);
    nt.a = (lc_color){0, 0, 0}, nt.b = (lc_color){1, 1, 1}, nt.octaves = 3, nt.scale = 2;
    int ni = add(s, nt);
    lc_vec3 p = {0.3, 1.7, -2.2}, q = {0.15, 0.85, -1.1};
    double sum = lc_noise(q) + 0.5 * lc_noise((lc_vec3){0.3, 1.7, -2.2}) +
                 0.25 * lc_noise((lc_vec3){0.6, 3.4, -4.4});
    near(at(s, ni, p.x, p.y, p.z).r, 0.5 + 0.5 * sum / 1.75, 1e-6, "noise texture");
    /* Marble: 0.5 + 0.5 sin(2 pi (x + turbulence T)); with no turbulence a
    ** pure sine across x. */
    lc_texture m = lc_texture_default(LC_TEX_MARBLE);
    m.a = (lc_color){0, 0, 0}, m.b = (lc_color){1, 1, 1}, m.turbulence = 0, m.scale = 4;
    int mi = add(s, m);
    near(at(s, mi, 1, 5, 5).r, 1, 1e-7, "marble crest at x = scale/4");
    near(at(s, mi, 3, 5, 5).r, 0, 1e-7, "marble trough");
    /* Wood: rings frac(sqrt(x^2 + z^2) / scale) without turbulence. */
    lc_texture w = lc_texture_default(LC_TEX_WOOD);
    w.a = (lc_color){0, 0, 0}, w.b = (lc_color){1, 1, 1}, w.turbulence = 0, w.scale = 2;
    int wi = add(s, w);
    near(at(s, wi, 3, 9, 4).r, 0.5, 1e-7, "ring at r = 5: 5 / 2 = 2.5");
    lc_textures_free(s);
}

/* A 3 x 2 image: texel (x, y) holds (x, y, 10 x + y) / 16. */
static lc_image *small_image(void)
{
    lc_image *img = lc_image_new(3, 2, NULL);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++)
            lc_image_set(img, x, y, (lc_color){x / 16.0f, y / 16.0f, (10 * x + y) / 16.0f});
    return img;
}

static lc_color uv_at(const lc_textures *s, int i, double u, double v)
{
    double uv[2] = {u, v};
    lc_vec3 o = {0, 0, 0};
    return lc_textures_eval(s, i, o, o, uv);
}

static void images_exact_at_texels_and_midpoints(void **state)
{
    (void)state;
    lc_error err;
    lc_textures *s = lc_textures_new(&err);
    lc_image *img = small_image();
    lc_texture t = lc_texture_default(LC_TEX_IMAGE);
    t.image = img;
    int ri = add(s, t);
    t.wrap = LC_WRAP_CLAMP;
    int ci = add(s, t);
    t.wrap = LC_WRAP_MIRROR;
    int mi = add(s, t);
    t.wrap = LC_WRAP_REPEAT, t.nearest = 1;
    int ni = add(s, t);
    lc_image_free(img);                           /* the set holds a copy */
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++) {
            double u = (x + 0.5) / 3, v = 1 - (y + 0.5) / 2;      /* v = 1 at the top */
            lc_color want = {x / 16.0f, y / 16.0f, (10 * x + y) / 16.0f};
            same(uv_at(s, ri, u, v), want, "texel centre");
            same(uv_at(s, ri, u + 7, v - 3), want, "texel centre, repeated");
            same(uv_at(s, ni, u + 0.1, v), want, "nearest");
        }
    /* Midway between texels (0, 0) and (1, 0): their mean, exactly. */
    same(uv_at(s, ri, 1.0 / 3, 0.75), (lc_color){0.5f / 16, 0, 5.0f / 16}, "midpoint");
    /* Midway between (0,0), (1,0), (0,1), (1,1). */
    same(uv_at(s, ri, 1.0 / 3, 0.5), (lc_color){0.5f / 16, 0.5f / 16, 5.5f / 16}, "centre");
    /* Past the left edge: repeat blends the last column in, clamp keeps
    ** the first, mirror reflects it. */
    lc_color r = uv_at(s, ri, 0, 0.75), c = uv_at(s, ci, 0, 0.75), m = uv_at(s, mi, 0, 0.75);
    near(r.r, 0.5 * (0 + 2) / 16.0, 1e-7, "repeat: half texel 0, half texel 2");
    near(c.r, 0, 0, "clamp: texel 0");
    near(m.r, 0, 0, "mirror: texel 0 and its mirror");
    same(uv_at(s, ci, -5, 0.75), uv_at(s, ci, 1.0 / 6, 0.75), "clamp far left");
    same(uv_at(s, mi, 2 - 1.0 / 6, 0.75), uv_at(s, mi, 1.0 / 6, 0.75), "mirror folds at 1");
    lc_textures_free(s);
}

static void mixes_nest_and_move(void **state)
{
    (void)state;
    lc_error err;
    lc_textures *s = lc_textures_new(&err);
    lc_texture c = lc_texture_default(LC_TEX_CHECKER);
    c.a = RED, c.b = BLUE;
    int ci = add(s, c);
    lc_texture g = lc_texture_default(LC_TEX_GRADIENT);
    g.a = (lc_color){0, 0, 0}, g.b = (lc_color){1, 1, 1}, g.axis = (lc_vec3){10, 0, 0};
    int gi = add(s, g);
    lc_texture mx = lc_texture_default(LC_TEX_MIX);
    mx.ta = ci + 1, mx.b = (lc_color){0, 1, 0}, mx.tamount = gi + 1;
    int mi = add(s, mx);
    /* At x = 2.5: the gradient's luminance 0.25 weights green over the checker. */
    lc_color m = at(s, mi, 2.5, 0.5, 0.5);
    same(m, (lc_color){(float)(1 + 0.25 * (0 - 1)), (float)(0 + 0.25 * 1), 0}, "mix");
    /* A checker of checkers, and a moved one: evaluated at xf^-1 p. */
    lc_texture cc = lc_texture_default(LC_TEX_CHECKER);
    cc.scale = 4, cc.ta = ci + 1, cc.b = (lc_color){0, 1, 0};
    int cci = add(s, cc);
    same(at(s, cci, 0.5, 0.5, 0.5), RED, "inner checker, square 0");
    same(at(s, cci, 1.5, 0.5, 0.5), BLUE, "inner checker, square 1");
    same(at(s, cci, 4.5, 0.5, 0.5), (lc_color){0, 1, 0}, "outer square 1");
    lc_texture mv = c;
    mv.moved = 1;
    mv.xf = lc_transform_translate((lc_vec3){1, 0, 0});
    int mvi = add(s, mv);
    same(at(s, mvi, 1.5, 0.5, 0.5), RED, "moved by one square");
    /* Object space and uv space. */
    lc_texture ob = c;
    ob.mapping = LC_MAP_OBJECT;
    int oi = add(s, ob);
    double uv[2] = {1.5, 0.5};
    same(lc_textures_eval(s, oi, (lc_vec3){0.5, 0.5, 0.5}, (lc_vec3){1.5, 0.5, 0.5}, uv),
         BLUE, "object space");
    ob.mapping = LC_MAP_UV;
    int ui = add(s, ob);
    same(lc_textures_eval(s, ui, (lc_vec3){0.5, 0.5, 0.5}, (lc_vec3){0.5, 0.5, 0.5}, uv),
         BLUE, "uv space");
    lc_textures_free(s);
}

static void fields_are_checked(void **state)
{
    (void)state;
    lc_error err;
    lc_textures *s = lc_textures_new(&err);
    lc_image *img = small_image();
    static const struct { const char *field, *msg; } want[] = {
        {"kind", "unknown texture kind"}, {"a", "colour must be finite"},
        {"scale", "must"}, {"scale", "must be finite"}, {"axis", "must not be zero-length"},
        {"octaves", "must be in [1, 16], got 0"}, {"turbulence", "must be in [0, 1e6]"},
        {"amount", "must be in [0, 1], got 2"}, {"a", "must name a texture added before"},
        {"image", "an image texture needs an image"}, {"wrap", "unknown wrap"},
        {"mapping", "unknown mapping"}, {"xf", ""},
    };
    for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
        lc_texture t = lc_texture_default(LC_TEX_CHECKER);
        switch (i) {
        case 0: t.kind = LC_TEX_KINDS; break;
        case 1: t.a.g = NAN; break;
        case 2: t.scale = 0; break;
        case 3: t.scale = INFINITY; break;
        case 4: t = lc_texture_default(LC_TEX_STRIPES), t.axis = (lc_vec3){0, 0, 0}; break;
        case 5: t = lc_texture_default(LC_TEX_NOISE), t.octaves = 0; break;
        case 6: t = lc_texture_default(LC_TEX_WOOD), t.turbulence = -1; break;
        case 7: t = lc_texture_default(LC_TEX_MIX), t.amount = 2; break;
        case 8: t.ta = 1; break;
        case 9: t = lc_texture_default(LC_TEX_IMAGE); break;
        case 10: t = lc_texture_default(LC_TEX_IMAGE), t.image = img, t.wrap = 7; break;
        case 11: t.mapping = 9; break;
        default: t.moved = 1, t.xf = lc_transform_scale((lc_vec3){1, 0, 1}); break;
        }
        assert_int_equal(lc_textures_add(s, &t, &err), -1);
        assert_int_equal(err.code, LC_EARG);
        if (i < 12 && (strcmp(err.field, want[i].field) || !strstr(err.msg, want[i].msg)))
            fail_msg("case %zu: %s: %s", i, err.field, err.msg);
    }
    assert_int_equal(lc_textures_count(s), 0);
    /* Nesting is bounded. */
    lc_texture t = lc_texture_default(LC_TEX_MIX);
    int last = add(s, t);
    for (int d = 2; d <= LC_MAX_TEXTURE_DEPTH; d++) {
        t.ta = last + 1;
        last = add(s, t);
    }
    t.ta = last + 1;
    assert_int_equal(lc_textures_add(s, &t, &err), -1);
    assert_non_null(strstr(err.msg, "nest 17 deep"));
    lc_image_free(img);
    lc_textures_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(checker_and_stripes),
        cmocka_unit_test(gradient_noise_marble_wood),
        cmocka_unit_test(images_exact_at_texels_and_midpoints),
        cmocka_unit_test(mixes_nest_and_move),
        cmocka_unit_test(fields_are_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
