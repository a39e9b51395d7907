/* test_aov.c: a render's AOVs saved as layers of one EXR, read back with
** OpenEXRCore itself (not lancer's reader): every channel's name, type and
** values. */
#define _XOPEN_SOURCE 700              /* mkdtemp */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include <openexr.h>
#include "lancer.h"
#include "image/raster.h"
#include "helpers.h"

#define W 13                       /* odd: the last chunk of rows is partial */
#define H 21
#define MAXCH 64

static char dir[64];

static int setup(void **state)
{
    (void)state;
    return scratch_dir_make(dir, sizeof dir, "aov");
}

static int teardown(void **state)
{
    (void)state;
    return scratch_dir_remove(dir);
}

/* A floor, a glass ball, a mirror ball and a glowing one, lit by a point
** light: every AOV has something to hold, and the background shows. */
static lc_image *render_all(lc_error *err)
{
    lc_scene *s = lc_scene_new(err);
    assert_non_null(s);
    lc_camera cam = lc_camera_default();
    cam.from = (lc_vec3){0, 2, -6};
    cam.at = (lc_vec3){0, 1, 0};
    cam.fov = 50;
    assert_int_equal(lc_scene_set_camera(s, &cam, err), LC_OK);
    lc_material floor = lc_material_default(), glass = lc_material_default();
    lc_material mirror = lc_material_default(), glow = lc_material_default();
    floor.color = (lc_color){0.8f, 0.7f, 0.6f};
    glass.kd = 0, glass.kt = 0.9, glass.ior = 1.5;
    mirror.kd = 0.2, mirror.kr = 0.7;
    glow.emission = (lc_color){2, 1, 0.5f};
    int mf = lc_scene_add_material(s, &floor, err), mg = lc_scene_add_material(s, &glass, err);
    int mm = lc_scene_add_material(s, &mirror, err), me = lc_scene_add_material(s, &glow, err);
    lc_shape pl = {.kind = LC_PLANE, .p = {0, 0, 0}, .u = {0, 1, 0}};
    lc_shape a = {.kind = LC_SPHERE, .p = {0, 1, 0}, .radius = 1};
    lc_shape b = {.kind = LC_SPHERE, .p = {2, 1, 1}, .radius = 1};
    lc_shape c = {.kind = LC_SPHERE, .p = {-2, 2, 2}, .radius = 0.5};
    assert_true(lc_scene_add_shape(s, &pl, mf, err) >= 0);
    assert_true(lc_scene_add_shape(s, &a, mg, err) >= 0);
    assert_true(lc_scene_add_shape(s, &b, mm, err) >= 0);
    assert_true(lc_scene_add_shape(s, &c, me, err) >= 0);
    lc_point_light l = lc_point_light_default();
    l.position = (lc_vec3){2, 4, -3};
    l.intensity = 40;
    assert_true(lc_scene_add_light(s, &l, err) >= 0);
    lc_render_options o = lc_render_options_default();
    o.width = W;
    o.height = H;
    o.samples = 4;
    o.alpha = 1;
    o.aovs = LC_AOV_ALL;
    lc_stats st;
    lc_image *img = lc_scene_render(s, &o, &st, err);
    assert_non_null(img);
    assert_int_equal(st.aovs, LC_AOV_ALL);
    assert_int_equal(lc_image_aovs(img), LC_AOV_ALL);
    lc_scene_free(s);
    return img;
}

/* What a channel should hold: its name, type, and the value at (x, y). */
typedef struct {
    char  name[40];
    int   half;
    float want[W * H];
} expect;

static void expect_plane(expect *e, int *n, const char *name, int half, const lc_image *img,
                         int c)
{
    snprintf(e[*n].name, sizeof e[*n].name, "%s", name);
    e[*n].half = half;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            lc_color v = lc_image_get(img, x, y);
            float f = c == 0 ? v.r : c == 1 ? v.g : c == 2 ? v.b : lc_image_get_alpha(img, x, y);
            e[*n].want[y * W + x] = half ? raster_float(raster_half(f)) : f;
        }
    ++*n;
}

/* The channels lancer should write, from the image's own AOVs. */
static int expected(const lc_image *img, int half, expect *e)
{
    static const char *const rgba[] = {"R", "G", "B", "A"};
    lc_error err;
    int n = 0;
    char name[40];
    for (int c = 0; c < 4; c++)
        expect_plane(e, &n, rgba[c], half, img, c);
    for (int a = 0; a < LC_AOVS; a++) {
        lc_image *l = lc_image_aov(img, (lc_aov)a, &err);
        assert_non_null(l);
        int exact = a == LC_AOV_DEPTH || a == LC_AOV_POSITION || a == LC_AOV_OBJECT ||
                    a == LC_AOV_MATERIAL;
        if (a == LC_AOV_DEPTH) {
            expect_plane(e, &n, "Z", 0, l, 0);
            lc_image_free(l);
            continue;
        }
        for (int c = 0; c < 3; c++) {
            snprintf(name, sizeof name, "%s.%s", lc_aov_name((lc_aov)a), rgba[c]);
            expect_plane(e, &n, name, half && !exact, l, c);
        }
        lc_image_free(l);
    }
    return n;
}

/* Every channel of the file's one part, decoded to float by the library. */
static int read_channels(const char *path, char names[][40], int types[], float *planes)
{
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_read(&ctx, path, &init), EXR_ERR_SUCCESS);
    int parts;
    assert_int_equal(exr_get_count(ctx, &parts), EXR_ERR_SUCCESS);
    assert_int_equal(parts, 1);
    exr_attr_box2i_t dw;
    assert_int_equal(exr_get_data_window(ctx, 0, &dw), EXR_ERR_SUCCESS);
    assert_int_equal(dw.max.x - dw.min.x + 1, W);
    assert_int_equal(dw.max.y - dw.min.y + 1, H);
    const exr_attr_chlist_t *cl;
    assert_int_equal(exr_get_channels(ctx, 0, &cl), EXR_ERR_SUCCESS);
    int nch = cl->num_channels;
    assert_true(nch <= MAXCH);
    for (int i = 0; i < nch; i++) {
        snprintf(names[i], 40, "%s", cl->entries[i].name.str);
        types[i] = cl->entries[i].pixel_type;
    }
    int lines;
    assert_int_equal(exr_get_scanlines_per_chunk(ctx, 0, &lines), EXR_ERR_SUCCESS);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < H; y += lines) {
        exr_chunk_info_t ci;
        assert_int_equal(exr_read_scanline_chunk_info(ctx, 0, dw.min.y + y, &ci),
                         EXR_ERR_SUCCESS);
        assert_int_equal(started ? exr_decoding_update(ctx, 0, &ci, &dec)
                                 : exr_decoding_initialize(ctx, 0, &ci, &dec),
                         EXR_ERR_SUCCESS);
        started = 1;
        for (int c = 0; c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            int k = -1;
            for (int i = 0; i < nch; i++)
                if (strcmp(names[i], ch->channel_name) == 0)
                    k = i;
            assert_true(k >= 0);
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_pixel_stride = 4;
            ch->user_line_stride = 4 * W;
            ch->decode_to_ptr = (uint8_t *)(planes + (size_t)k * W * H + (size_t)y * W);
        }
        assert_int_equal(exr_decoding_choose_default_routines(ctx, 0, &dec), EXR_ERR_SUCCESS);
        assert_int_equal(exr_decoding_run(ctx, 0, &dec), EXR_ERR_SUCCESS);
    }
    exr_decoding_destroy(ctx, &dec);
    exr_finish(&ctx);
    return nch;
}

static int find(char names[][40], int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

static void check_file(const lc_image *img, int half)
{
    static expect e[MAXCH];
    static float planes[MAXCH * W * H];
    static char names[MAXCH][40];
    int types[MAXCH];
    lc_error err;
    char path[128];
    snprintf(path, sizeof path, "%s/aovs-%s.exr", dir, half ? "half" : "float");
    lc_save_options so = lc_save_options_default();
    so.alpha = 1;
    so.exr_pixel = half ? LC_EXR_HALF : LC_EXR_FLOAT;
    assert_int_equal(lc_image_save_with(img, path, &so, &err), LC_OK);
    int n = read_channels(path, names, types, planes);
    int ne = expected(img, half, e);
    /* Beside the expected: the ranks of object and material, 8 each. */
    assert_int_equal(n, ne + 2 * 2 * 4);
    for (int i = 0; i < ne; i++) {
        int k = find(names, n, e[i].name);
        if (k < 0)
            fail_msg("channel %s missing", e[i].name);
        assert_int_equal(types[k], e[i].half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT);
        for (int p = 0; p < W * H; p++) {
            float got = planes[(size_t)k * W * H + p], want = e[i].want[p];
            if (!(got == want || (isinf(got) && isinf(want))))
                fail_msg("%s at pixel %d: %.9g, expected %.9g", e[i].name, p, got, want);
        }
    }
    /* The ranks: each id with the share lc_image_matte gives it, most first;
    ** the shares of the objects and of the background make a whole pixel. */
    static const char *const idaov[] = {"object", "material"};
    for (int a = 0; a < 2; a++) {
        lc_aov which = a ? LC_AOV_MATERIAL : LC_AOV_OBJECT;
        for (int p = 0; p < W * H; p++) {
            double total = 0, last = 2;
            for (int r = 0; r < LC_AOV_RANKS; r++) {
                char nid[40], ncov[40];
                static const char *const rgba[] = {"R", "G", "B", "A"};
                snprintf(nid, sizeof nid, "%s%02d.%s", idaov[a], r / 2, rgba[2 * (r % 2)]);
                snprintf(ncov, sizeof ncov, "%s%02d.%s", idaov[a], r / 2,
                         rgba[2 * (r % 2) + 1]);
                int ki = find(names, n, nid), kc = find(names, n, ncov);
                assert_true(ki >= 0 && kc >= 0);
                assert_int_equal(types[ki], EXR_PIXEL_FLOAT);
                float id = planes[(size_t)ki * W * H + p], cov = planes[(size_t)kc * W * H + p];
                assert_true(cov <= last);
                last = cov;
                total += cov;
                if (id == 0) {
                    assert_true(cov == 0);
                    continue;
                }
                lc_image *m = lc_image_matte(img, which, (int)id, &err);
                assert_non_null(m);
                assert_true(lc_image_get(m, p % W, p / W).r == cov);
                lc_image_free(m);
            }
            /* 4 samples: shares are quarters, exact; alpha is the share that hit. */
            float alpha = lc_image_get_alpha(img, p % W, p / W);
            assert_true(fabs(total - alpha) <= 0);
        }
    }
}

static void exr_layers_hold_every_aov(void **state)
{
    (void)state;
    lc_error err;
    lc_image *img = render_all(&err);
    check_file(img, 0);
    check_file(img, 1);
    lc_image_free(img);
}

/* The light AOVs add up to the beauty (here with glass, a mirror and an
** emitter), to float rounding: each is a float of a double sum. */
static void light_aovs_sum_to_the_beauty(void **state)
{
    (void)state;
    lc_error err;
    lc_image *img = render_all(&err);
    lc_image *l[5];
    for (int k = 0; k < 5; k++)
        assert_non_null(l[k] = lc_image_aov(img, (lc_aov)(LC_AOV_DIRECT + k), &err));
    double nonzero[5] = {0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            lc_color b = lc_image_get(img, x, y);
            double s[3] = {0, 0, 0};
            for (int k = 0; k < 5; k++) {
                lc_color c = lc_image_get(l[k], x, y);
                s[0] += c.r, s[1] += c.g, s[2] += c.b;
                nonzero[k] += c.r + c.g + c.b;
            }
            double bv[3] = {b.r, b.g, b.b};
            for (int c = 0; c < 3; c++)     /* 6 roundings to float, 2^-24 each */
                if (!(fabs(s[c] - bv[c]) <= 6 * 0x1p-24 * bv[c]))
                    fail_msg("(%d, %d) channel %d: %.9g, beauty %.9g", x, y, c, s[c], bv[c]);
        }
    for (int k = 0; k < 5; k++) {
        if (k == LC_AOV_INDIRECT - LC_AOV_DIRECT)
            assert_true(nonzero[k] == 0);   /* Whitted: no light bounces diffusely */
        else
            assert_true(nonzero[k] > 0);
        lc_image_free(l[k]);
    }
    lc_image_free(img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exr_layers_hold_every_aov),
        cmocka_unit_test(light_aovs_sum_to_the_beauty),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
