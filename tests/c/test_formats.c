/* test_formats.c: 16-bit and RGBA PNG, OpenEXR (half and float, scanlines
** and tiles, every compression) written and read back by the library itself,
** parts of a frame merged to the bytes of the whole, and broken files. */
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
#include "base/mem.h"
#include "image/raster.h"
#include "helpers.h"

#define W 13                       /* odd sizes: edge tiles and chunks are partial */
#define H 37

static char dir[64];

static int setup(void **state)
{
    (void)state;
    return scratch_dir_make(dir, sizeof dir, "formats");
}

static int teardown(void **state)
{
    (void)state;
    return scratch_dir_remove(dir);
}

static const char *path_of(const char *name)
{
    static char p[8][128];
    static int next;
    char *out = p[next++ % 8];
    snprintf(out, 128, "%s/%s", dir, name);
    return out;
}

/* Values a renderer makes, and what stresses an encoder: 0, tiny, huge,
** negative, between every 8-bit step. */
static float value(int x, int y, int c)
{
    static const float odd[] = {0.0f, 1e-30f, 6e-8f, 1.0f, 2.5f, 70000.0f, -0.25f, 1e30f};
    unsigned h = (unsigned)(x * 7919 + y * 104729 + c * 15485863) % 1000;
    return h < 80 ? odd[h % 8] : (float)h / 997.0f;
}

static lc_image *test_image(int w, int h, int alpha)
{
    lc_error err;
    lc_image *img = lc_image_new(w, h, &err);
    assert_non_null(img);
    if (alpha)
        assert_int_equal(lc_image_add_alpha(img, &err), LC_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            lc_color c = {value(x, y, 0), value(x, y, 1), value(x, y, 2)};
            lc_image_set(img, x, y, c);
            lc_image_set_alpha(img, x, y, (float)((x + y) % 5) / 4);
        }
    return img;
}

static void half_is_exact_and_rounds_to_even(void **state)
{
    (void)state;
    for (uint32_t h = 0; h < 65536; h++) {
        float f = raster_float((uint16_t)h);
        if (isnan(f))
            assert_true(isnan(raster_float(raster_half(f))));
        else if ((h & 0x7fff) == 0x7c00)
            assert_int_equal(raster_half(f), h - 0x7c00 + 0x7bff);  /* inf: clamped */
        else
            assert_int_equal(raster_half(f), h);
    }
    /* Against the compiler's own conversion (IEEE, to nearest even) over every
    ** 2^-8-spaced bit pattern of the finite range. */
    for (uint64_t bits = 0; bits < 0x477fe000u; bits += 251) {
        float f;
        uint32_t b = (uint32_t)bits;
        memcpy(&f, &b, 4);
        _Float16 ref = (_Float16)f;
        uint16_t rb;
        memcpy(&rb, &ref, 2);
        assert_int_equal(raster_half(f), rb);
        assert_int_equal(raster_half(-f), rb | 0x8000);
    }
    assert_int_equal(raster_half(65504.0f), 0x7bff);
    assert_int_equal(raster_half(65519.0f), 0x7bff);  /* IEEE would say infinity */
    assert_int_equal(raster_half(1e30f), 0x7bff);
    assert_int_equal(raster_half(-INFINITY), 0xfbff);
}

static void exr_float_round_trip_is_bit_exact(void **state)
{
    (void)state;
    static const int tiles[] = {0, 4, 64};
    lc_image *img = test_image(W, H, 1);
    lc_error err;
    for (int comp = LC_EXR_ZIP; comp <= LC_EXR_NONE; comp++)
        for (int t = 0; t < 3; t++)
            for (int alpha = 0; alpha <= 1; alpha++) {
                lc_save_options o = lc_save_options_default();
                o.exr_pixel = LC_EXR_FLOAT;
                o.exr_compression = (lc_exr_compression)comp;
                o.exr_tile = tiles[t];
                o.alpha = alpha;
                const char *p = path_of("f.exr");
                assert_int_equal(lc_image_save_with(img, p, &o, &err), LC_OK);
                lc_image *back = lc_image_load_exr(p, &err);
                assert_non_null(back);
                assert_int_equal(lc_image_width(back), W);
                assert_int_equal(lc_image_height(back), H);
                assert_int_equal(lc_image_has_alpha(back), alpha);
                for (int y = 0; y < H; y++)
                    for (int x = 0; x < W; x++) {
                        lc_color a = lc_image_get(img, x, y), b = lc_image_get(back, x, y);
                        assert_memory_equal(&a, &b, sizeof a);
                        float aa = alpha ? lc_image_get_alpha(img, x, y) : 1;
                        float ba = lc_image_get_alpha(back, x, y);
                        assert_memory_equal(&aa, &ba, sizeof aa);
                    }
                lc_image_free(back);
            }
    lc_image_free(img);
}

/* Every compression and tiling: a 4x4 half tile once came back as noise
** (OpenEXRCore's ZIP kept output as long as its input, see exr.c). */
static void exr_half_round_trip_rounds_once(void **state)
{
    (void)state;
    lc_image *img = test_image(W, H, 1);
    lc_error err;
    for (int v = 0; v < 15; v++) {
    lc_save_options o = lc_save_options_default();      /* half, zip */
    static const int tiles[] = {0, 4, 8};
    o.alpha = 1;
    o.exr_tile = tiles[v % 3];
    o.exr_compression = (lc_exr_compression)(v / 3);
    const char *p = path_of("h.exr");
    assert_int_equal(lc_image_save_with(img, p, &o, &err), LC_OK);
    lc_image *back = lc_image_load_exr(p, &err);
    assert_non_null(back);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            lc_color a = lc_image_get(img, x, y), b = lc_image_get(back, x, y);
            assert_true(b.r == raster_float(raster_half(a.r)));
            assert_true(b.g == raster_float(raster_half(a.g)));
            assert_true(b.b == raster_float(raster_half(a.b)));
            assert_true(lc_image_get_alpha(back, x, y) == lc_image_get_alpha(img, x, y));
            if (fabsf(a.r) <= 65504 && fabsf(a.r) >= 6.2e-5f)    /* normal halves */
                assert_true(fabsf(b.r - a.r) <= fabsf(a.r) * 0x1p-11f);
        }
    lc_image_free(back);
    }
    lc_image_free(img);
}

static void png16_round_trip_is_within_one_step(void **state)
{
    (void)state;
    lc_image *img = test_image(W, H, 0);
    lc_error err;
    lc_save_options o = lc_save_options_default();
    o.depth = 16;
    o.encoding = LC_ENCODE_LINEAR;
    const char *p = path_of("d16.png");
    assert_int_equal(lc_image_save_with(img, p, &o, &err), LC_OK);
    lc_image *back = lc_image_load_png(p, LC_ENCODE_LINEAR, &err);
    assert_non_null(back);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            lc_color a = lc_image_get(img, x, y), b = lc_image_get(back, x, y);
            float in[3] = {a.r, a.g, a.b}, out[3] = {b.r, b.g, b.b};
            for (int k = 0; k < 3; k++) {
                double v = in[k] < 0 ? 0 : in[k] > 1 ? 1 : in[k];
                assert_true(fabs(out[k] - v) <= 0.5 / 65535 + 1e-7);
                assert_true(out[k] == (float)(round(v * 65535) / 65535));
            }
        }
    lc_image_free(back);
    /* sRGB: the stored 16-bit codes are round(65535 srgb(v)). */
    o.encoding = LC_ENCODE_SRGB;
    assert_int_equal(lc_image_save_with(img, p, &o, &err), LC_OK);
    back = lc_image_load_png(p, LC_ENCODE_LINEAR, &err);
    assert_non_null(back);
    lc_color a = lc_image_get(img, 3, 1), b = lc_image_get(back, 3, 1);
    double v = a.g < 0 ? 0 : a.g > 1 ? 1 : a.g;
    double e = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
    assert_true(b.g == (float)(round(e * 65535) / 65535));
    lc_image_free(back);
    lc_image_free(img);
}

/* RGBA PNG: straight alpha, as PNG defines it: colour / alpha, then encoded. */
static void png_alpha_is_straight(void **state)
{
    (void)state;
    lc_error err;
    lc_image *img = lc_image_new(4, 1, &err);
    assert_int_equal(lc_image_add_alpha(img, &err), LC_OK);
    lc_color half = {0.25f, 0.5f, 0.125f}, none = {0, 0, 0};
    lc_image_set(img, 0, 0, half);
    lc_image_set_alpha(img, 0, 0, 0.5f);
    lc_image_set(img, 1, 0, none);
    lc_image_set_alpha(img, 1, 0, 0);
    lc_save_options o = lc_save_options_default();
    o.alpha = 1;
    o.encoding = LC_ENCODE_LINEAR;
    const char *p = path_of("a.png");
    assert_int_equal(lc_image_save_with(img, p, &o, &err), LC_OK);
    raster_format f;
    unsigned char *data;
    assert_int_equal(png_read_raster(p, &f, &data, &err), LC_OK);
    assert_int_equal(f.channels, 4);
    assert_int_equal(f.bytes, 1);
    static const unsigned char want[8] = {128, 255, 64, 128, 0, 0, 0, 0};
    assert_memory_equal(data, want, 8);
    mem_free(data);
    /* An image without alpha cannot be saved with it. */
    lc_image *plain = lc_image_new(2, 2, &err);
    assert_int_not_equal(lc_image_save_with(plain, p, &o, &err), LC_OK);
    assert_non_null(strstr(err.msg, "has none"));
    lc_image_free(plain);
    lc_image_free(img);
}

static int read_file(const char *p, unsigned char **buf, size_t *n)
{
    FILE *fp = fopen(p, "rb");
    if (!fp)
        return -1;
    fseek(fp, 0, SEEK_END);
    *n = (size_t)ftell(fp);
    fseek(fp, 0, SEEK_SET);
    *buf = malloc(*n ? *n : 1);
    size_t got = fread(*buf, 1, *n, fp);
    fclose(fp);
    return got == *n ? 0 : -1;
}

static void write_bytes(const char *p, const unsigned char *buf, size_t n)
{
    FILE *fp = fopen(p, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(buf, 1, n, fp), n);
    fclose(fp);
}

static void assert_same_file(const char *a, const char *b)
{
    unsigned char *x = NULL, *y = NULL;
    size_t nx = 0, ny = 0;
    assert_int_equal(read_file(a, &x, &nx), 0);
    assert_int_equal(read_file(b, &y, &ny), 0);
    assert_int_equal(nx, ny);
    assert_memory_equal(x, y, nx);
    free(x);
    free(y);
}

/* The part [x0, x1) x [y0, y1) of img, knowing its place. */
static lc_image *crop(const lc_image *img, int x0, int y0, int x1, int y1)
{
    lc_error err;
    lc_image *c = lc_image_new(x1 - x0, y1 - y0, &err);
    if (lc_image_has_alpha(img))
        lc_image_add_alpha(c, &err);
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            lc_image_set(c, x - x0, y - y0, lc_image_get(img, x, y));
            lc_image_set_alpha(c, x - x0, y - y0, lc_image_get_alpha(img, x, y));
        }
    lc_window w = {x0, y0, lc_image_width(img), lc_image_height(img)};
    assert_int_equal(lc_image_set_window(c, w, &err), LC_OK);
    return c;
}

/* Four parts, rows and a column block, merged: the bytes of the whole. */
static void merge_gives_the_whole_frames_bytes(void **state)
{
    (void)state;
    static const int rect[4][4] = {{0, 0, W, 9}, {0, 9, 5, H}, {5, 9, W, 20},
                                   {5, 20, W, H}};
    lc_image *img = test_image(W, H, 1);
    lc_error err;
    for (int kind = 0; kind < 6; kind++) {
        lc_save_options o = lc_save_options_default();
        const char *ext = kind < 3 ? "png" : "exr";
        o.depth = kind == 1 ? 16 : 8;
        o.alpha = kind == 2 || kind == 4;
        o.encoding = kind == 1 ? LC_ENCODE_LINEAR : LC_ENCODE_SRGB;
        o.exr_pixel = kind == 5 ? LC_EXR_FLOAT : LC_EXR_HALF;
        o.exr_tile = kind == 4 ? 4 : 0;
        o.exr_compression = kind == 5 ? LC_EXR_PIZ : LC_EXR_ZIP;
        char whole[128], merged[128], parts[4][128];
        const char *names[4];
        snprintf(whole, sizeof whole, "%s/whole.%s", dir, ext);
        snprintf(merged, sizeof merged, "%s/merged.%s", dir, ext);
        assert_int_equal(lc_image_save_with(img, whole, &o, &err), LC_OK);
        for (int i = 0; i < 4; i++) {
            lc_image *c = crop(img, rect[i][0], rect[i][1], rect[i][2], rect[i][3]);
            snprintf(parts[i], sizeof parts[i], "%s/part%d.%s", dir, i, ext);
            assert_int_equal(lc_image_save_with(c, parts[i], &o, &err), LC_OK);
            names[3 - i] = parts[i];                 /* any order */
            if (kind == 3 && i == 1) {               /* a part read back knows its place */
                lc_image *back = lc_image_load_exr(parts[i], &err);
                lc_window w = lc_image_window(back);
                assert_int_equal(w.x0, 0);
                assert_int_equal(w.y0, 9);
                assert_int_equal(w.frame_width, W);
                assert_int_equal(w.frame_height, H);
                lc_image_free(back);
            }
            lc_image_free(c);
        }
        assert_int_equal(lc_image_merge(merged, names, 4, &err), LC_OK);
        assert_same_file(whole, merged);
        /* A part missing, or twice, or of another format. */
        assert_int_not_equal(lc_image_merge(merged, names, 3, &err), LC_OK);
        assert_non_null(strstr(err.msg, "uncovered, the first at (0, 0)"));
        const char *twice[5] = {names[0], names[1], names[2], names[3], names[2]};
        assert_int_not_equal(lc_image_merge(merged, twice, 5, &err), LC_OK);
        assert_non_null(strstr(err.msg, "overlaps another part at pixel"));
        assert_non_null(strstr(err.msg, names[2]));
    }
    const char *mixed[2] = {path_of("part0.png"), path_of("part1.exr")};
    assert_int_not_equal(lc_image_merge(path_of("m.png"), mixed, 2, &err), LC_OK);
    assert_non_null(strstr(err.msg, "both must be PNG"));
    lc_image *other = test_image(W, H, 0);
    lc_save_options o16 = lc_save_options_default();
    o16.depth = 16;
    lc_image *c = crop(other, 0, 0, W, 9);
    assert_int_equal(lc_image_save_with(c, path_of("p16.png"), &o16, &err), LC_OK);
    const char *depths[2] = {path_of("part1.png"), path_of("p16.png")};
    assert_int_not_equal(lc_image_merge(path_of("m.png"), depths, 2, &err), LC_OK);
    char want[512];
    snprintf(want, sizeof want, "cannot merge '%s': it is a 16-bit sRGB RGB PNG, and "
             "'%s' is an 8-bit sRGB RGBA PNG", depths[1], depths[0]);
    assert_string_equal(err.msg, want);
    lc_image_free(c);
    lc_image_free(other);
    lc_image_free(img);
}

static void bad_paths_name_the_path(void **state)
{
    (void)state;
    lc_image *img = test_image(4, 4, 0);
    lc_error err;
    lc_save_options o = lc_save_options_default();
    assert_int_equal(lc_image_save_with(img, "/nonexistent-dir/x.exr", &o, &err), LC_EIO);
    assert_string_equal(err.msg, "cannot write '/nonexistent-dir/x.exr': No such file or "
                        "directory");
    assert_int_equal(lc_image_save_with(img, "x.tiff", &o, &err), LC_EARG);
    assert_string_equal(err.msg, "cannot write 'x.tiff': unknown extension '.tiff' "
                        "(lancer writes .png and .exr)");
    assert_null(lc_image_load_exr("/nonexistent-dir/x.exr", &err));
    assert_string_equal(err.msg, "cannot open '/nonexistent-dir/x.exr': No such file or "
                        "directory");
    /* An existing file survives a failed save: nothing is left beside it. */
    lc_image_free(img);
}

/* Every truncation and many single-byte changes of a valid file: a clean
** error naming the file, or (a change the format cannot see, in a pixel) an
** image; never a crash (run under make SAN=1 too). */
static void broken_exr_files_fail_cleanly(void **state)
{
    (void)state;
    lc_image *img = test_image(W, H, 1);
    lc_error err;
    static const lc_exr_compression comps[] = {LC_EXR_ZIP, LC_EXR_PIZ, LC_EXR_RLE,
                                               LC_EXR_NONE};
    const char *bad = path_of("bad.exr");
    for (int v = 0; v < 8; v++) {
        lc_save_options o = lc_save_options_default();
        o.alpha = 1;
        o.exr_compression = comps[v % 4];
        o.exr_tile = v >= 4 ? 8 : 0;
        const char *good = path_of("good.exr");
        assert_int_equal(lc_image_save_with(img, good, &o, &err), LC_OK);
        unsigned char *buf = NULL;
        size_t n = 0;
        assert_int_equal(read_file(good, &buf, &n), 0);
        for (size_t cut = 0; cut < n; cut += cut < 400 ? 1 : 37) {
            write_bytes(bad, buf, cut);
            lc_image *r = lc_image_load_exr(bad, &err);
            assert_null(r);
            assert_non_null(strstr(err.msg, bad));
        }
        unsigned seed = 12345u + (unsigned)v;
        for (int k = 0; k < 300; k++) {
            unsigned char *copy = malloc(n);
            memcpy(copy, buf, n);
            seed = seed * 1103515245u + 12345u;
            size_t at = (seed >> 8) % n;
            copy[at] ^= (unsigned char)(1u << ((seed >> 4) & 7));
            write_bytes(bad, copy, n);
            lc_image *r = lc_image_load_exr(bad, &err);
            if (r)
                lc_image_free(r);
            else
                assert_non_null(strstr(err.msg, bad));
            free(copy);
        }
        free(buf);
    }
    write_bytes(bad, (const unsigned char *)"not an exr at all", 17);
    assert_null(lc_image_load_exr(bad, &err));
    assert_non_null(strstr(err.msg, "cannot read '"));
    lc_image_free(img);
}

/* A header claiming a data window past LC_MAX_SIDE is refused by lancer's
** cap, before any pixel memory is asked for. */
static void huge_exr_headers_name_the_cap(void **state)
{
    (void)state;
    lc_image *img = test_image(4, 4, 0);
    lc_error err;
    lc_save_options o = lc_save_options_default();
    const char *p = path_of("huge.exr");
    assert_int_equal(lc_image_save_with(img, p, &o, &err), LC_OK);
    unsigned char *buf = NULL;
    size_t n = 0;
    assert_int_equal(read_file(p, &buf, &n), 0);
    static const char key[] = "dataWindow\0box2i";
    unsigned char *at = NULL;
    for (size_t i = 0; i + sizeof key < n && !at; i++)
        if (memcmp(buf + i, key, sizeof key) == 0)
            at = buf + i + sizeof key + 4;          /* after the size: min x, y, max x, y */
    assert_non_null(at);
    int32_t big = 3000000;
    memcpy(at + 8, &big, 4);                        /* max.x (little-endian, as EXR) */
    write_bytes(p, buf, n);
    assert_null(lc_image_load_exr(p, &err));
    char want[256];
    snprintf(want, sizeof want, "cannot read '%s': 3000001x4 is more than lancer's "
             "1048576 pixels a side or 268435456 pixels", p);
    assert_string_equal(err.msg, want);
    free(buf);
    lc_image_free(img);
}

/* ---- Channel layouts lancer does not write --------------------------------------- */

/* One channel of a file written through OpenEXRCore directly: lancer's own
** writer makes only the layouts it reads back. */
typedef struct {
    const char *name;           /* the caller lists them sorted by name */
    exr_pixel_type_t type;
    int sampling;               /* 1, or 2 in x and y */
} test_channel;

/* Channel name's samples: its own base value, varying with x and y; every
** one exact in a half. */
static float layout_value(const char *name, int x, int y)
{
    static const char names[] = "RGBAYMZ";
    const char *at = strchr(names, name[0]);
    float base = at ? 0.25f * (float)(at - names + 1) : 5.0f;
    return base + (float)(x % 4) / 16 + (float)(y % 4) / 64;
}

/* A w x h scanline file of n channels. */
static void write_layout(const char *path, const test_channel *chans, int n, int w, int h,
                         exr_compression_t comp)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t ctx = NULL;
    int part = 0;
    assert_int_equal(exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
    assert_int_equal(exr_add_part(ctx, "main", EXR_STORAGE_SCANLINE, &part), 0);
    assert_int_equal(exr_initialize_required_attr_simple(ctx, part, w, h, comp), 0);
    for (int c = 0; c < n; c++)
        assert_int_equal(exr_add_channel(ctx, part, chans[c].name, chans[c].type,
                                         EXR_PERCEPTUALLY_LOGARITHMIC, chans[c].sampling,
                                         chans[c].sampling), 0);
    assert_int_equal(exr_write_header(ctx), 0);
    /* Each channel's samples, planar, at its own sampling. */
    unsigned char *planes[8];
    for (int c = 0; c < n; c++) {
        int s = chans[c].sampling;
        planes[c] = calloc((size_t)w * h, 4);
        for (int y = 0; y < h / s; y++)
            for (int x = 0; x < w / s; x++) {
                float v = layout_value(chans[c].name, x * s, y * s);
                size_t at = (size_t)y * (w / s) + x;
                if (chans[c].type == EXR_PIXEL_HALF) {
                    uint16_t hv = raster_half(v);
                    memcpy(planes[c] + 2 * at, &hv, 2);
                } else if (chans[c].type == EXR_PIXEL_FLOAT) {
                    memcpy(planes[c] + 4 * at, &v, 4);
                } else {
                    uint32_t u = (uint32_t)(v * 64);
                    memcpy(planes[c] + 4 * at, &u, 4);
                }
            }
    }
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int lines = 1;
    assert_int_equal(exr_get_scanlines_per_chunk(ctx, part, &lines), 0);
    for (int y = 0; y < h; y += lines) {
        exr_chunk_info_t ci;
        assert_int_equal(exr_write_scanline_chunk_info(ctx, part, y, &ci), 0);
        if (y == 0)
            assert_int_equal(exr_encoding_initialize(ctx, part, &ci, &enc), 0);
        else
            assert_int_equal(exr_encoding_update(ctx, part, &ci, &enc), 0);
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            int k = 0;
            while (strcmp(chans[k].name, ch->channel_name) != 0)
                k++;
            int s = chans[k].sampling;
            ch->user_bytes_per_element = ch->bytes_per_element;
            ch->user_data_type = ch->data_type;
            ch->user_pixel_stride = ch->bytes_per_element;
            ch->user_line_stride = (w / s) * ch->bytes_per_element;
            ch->encode_from_ptr = planes[k] + (size_t)(y / s) * (w / s) *
                                  ch->bytes_per_element;
        }
        assert_int_equal(exr_encoding_choose_default_routines(ctx, part, &enc), 0);
        assert_int_equal(exr_encoding_run(ctx, part, &enc), 0);
    }
    exr_encoding_destroy(ctx, &enc);
    assert_int_equal(exr_finish(&ctx), 0);
    for (int c = 0; c < n; c++)
        free(planes[c]);
}

/* An R, G, B, A or Y channel that is unsigned int or subsampled is refused,
** the message naming it (made before the file is closed: the channel list
** is the library's, freed with it; make SAN=1 saw a use after free). */
static void exr_channels_lancer_cannot_read_are_named(void **state)
{
    (void)state;
    static const char *const names[] = {"A", "B", "G", "R", "Y"};
    const char *p = path_of("uint.exr");
    for (int k = 0; k < 5; k++)
        for (int sub = 0; sub < 2; sub++) {
            test_channel chans[5];
            for (int c = 0; c < 5; c++)
                chans[c] = (test_channel){names[c], EXR_PIXEL_HALF, 1};
            if (sub)
                chans[k].sampling = 2;
            else
                chans[k].type = EXR_PIXEL_UINT;
            write_layout(p, chans, 5, 4, 4, EXR_COMPRESSION_NONE);
            lc_error err;
            assert_null(lc_image_load_exr(p, &err));
            char want[256];
            snprintf(want, sizeof want, "cannot read '%s': channel %s is %s, lancer "
                     "reads half or float channels at every pixel", p, names[k],
                     sub ? "subsampled" : "unsigned int");
            assert_string_equal(err.msg, want);
        }
}

/* Every set of R, G, B, A, Y and two channels lancer skips (M, Z), of
** halves, floats or both, the skipped ones also unsigned or subsampled,
** uncompressed or in chunks of 16 lines (ZIP):
** each read gives what its channels say, grey from Y alone. OpenEXRCore
** 3.1.5's routine for three interleaved halves wrote through the pointer
** of a channel given none (B, G, M: a segmentation fault). */
static void exr_every_channel_layout_reads(void **state)
{
    (void)state;
    static const char *const names[] = {"A", "B", "G", "M", "R", "Y", "Z"};
    const char *p = path_of("layout.exr");
    enum { N = 7, SIDE = 18 };
    for (int set = 1; set < 1 << N; set++)
        for (int kind = 0; kind < 5; kind++) {
            test_channel chans[N];
            int n = 0, has[N] = {0};
            for (int c = 0; c < N; c++) {
                if (!(set & 1 << c))
                    continue;
                has[c] = 1;
                int skipped = c == 3 || c == 6;
                exr_pixel_type_t t = kind == 1 || (kind == 2 && c % 2) ? EXR_PIXEL_FLOAT
                                                                        : EXR_PIXEL_HALF;
                if (kind == 3 && skipped)
                    t = EXR_PIXEL_UINT;
                chans[n++] = (test_channel){names[c], t, kind == 4 && skipped ? 2 : 1};
            }
            write_layout(p, chans, n, SIDE, SIDE,
                         (set + kind) % 2 ? EXR_COMPRESSION_ZIP : EXR_COMPRESSION_NONE);
            lc_error err;
            lc_image *img = lc_image_load_exr(p, &err);
            if (!img)
                fail_msg("set %#x kind %d: %s", set, kind, err.msg);
            int rgb = has[4] || has[2] || has[1], grey = has[5] && !rgb;
            assert_int_equal(lc_image_has_alpha(img), has[0]);
            for (int y = 0; y < SIDE; y++)
                for (int x = 0; x < SIDE; x++) {
                    lc_color got = lc_image_get(img, x, y);
                    float want[3];
                    static const int slot[3] = {4, 2, 1};           /* R, G, B */
                    for (int i = 0; i < 3; i++)
                        want[i] = grey ? layout_value("Y", x, y) :
                                  has[slot[i]] ? layout_value(names[slot[i]], x, y) : 0;
                    if (got.r != want[0] || got.g != want[1] || got.b != want[2])
                        fail_msg("set %#x kind %d at %d,%d: %g %g %g, not %g %g %g",
                                 set, kind, x, y, got.r, got.g, got.b, want[0], want[1],
                                 want[2]);
                    if (has[0])
                        assert_true(lc_image_get_alpha(img, x, y) ==
                                    layout_value("A", x, y));
                }
            lc_image_free(img);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(half_is_exact_and_rounds_to_even),
        cmocka_unit_test(exr_float_round_trip_is_bit_exact),
        cmocka_unit_test(exr_half_round_trip_rounds_once),
        cmocka_unit_test(png16_round_trip_is_within_one_step),
        cmocka_unit_test(png_alpha_is_straight),
        cmocka_unit_test(merge_gives_the_whole_frames_bytes),
        cmocka_unit_test(bad_paths_name_the_path),
        cmocka_unit_test(broken_exr_files_fail_cleanly),
        cmocka_unit_test(huge_exr_headers_name_the_cap),
        cmocka_unit_test(exr_channels_lancer_cannot_read_are_named),
        cmocka_unit_test(exr_every_channel_layout_reads),
    };
    return cmocka_run_group_tests(tests, setup, getenv("KEEP") ? NULL : teardown);
}
