/* test_image.c: channel encoding, image allocation and atomic PNG writing. */
#include <dirent.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>
#include "lancer.h"

/* ---- Encoding ------------------------------------------------------------ */

static void encode_linear_clamps_and_rounds(void **state)
{
    (void)state;
    assert_int_equal(lc_encode_channel(0.0f, LC_ENCODE_LINEAR), 0);
    assert_int_equal(lc_encode_channel(1.0f, LC_ENCODE_LINEAR), 255);
    /* 0.5 * 255 = 127.5 exactly: round to nearest, half up. */
    assert_int_equal(lc_encode_channel(0.5f, LC_ENCODE_LINEAR), 128);
    assert_int_equal(lc_encode_channel(NAN, LC_ENCODE_LINEAR), 0);
    assert_int_equal(lc_encode_channel(-NAN, LC_ENCODE_LINEAR), 0);
    assert_int_equal(lc_encode_channel(-1.0f, LC_ENCODE_LINEAR), 0);
    assert_int_equal(lc_encode_channel(-0.0f, LC_ENCODE_LINEAR), 0);
    assert_int_equal(lc_encode_channel(2.0f, LC_ENCODE_LINEAR), 255);
    assert_int_equal(lc_encode_channel(INFINITY, LC_ENCODE_LINEAR), 255);
    assert_int_equal(lc_encode_channel(-INFINITY, LC_ENCODE_LINEAR), 0);
    /* Every k/255 encodes back to k: the scale is 255, not 256. */
    for (int k = 0; k <= 255; k++)
        assert_int_equal(lc_encode_channel((float)k / 255.0f, LC_ENCODE_LINEAR), k);
}

static void encode_srgb_values(void **state)
{
    (void)state;
    assert_int_equal(lc_encode_channel(0.0f, LC_ENCODE_SRGB), 0);
    assert_int_equal(lc_encode_channel(1.0f, LC_ENCODE_SRGB), 255);
    /* 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357, * 255 = 187.52 -> 188. */
    assert_int_equal(lc_encode_channel(0.5f, LC_ENCODE_SRGB), 188);
    /* 0.18 (mid grey): 0.461356 * 255 = 117.65 -> 118. */
    assert_int_equal(lc_encode_channel(0.18f, LC_ENCODE_SRGB), 118);
    assert_int_equal(lc_encode_channel(NAN, LC_ENCODE_SRGB), 0);
    assert_int_equal(lc_encode_channel(-1.0f, LC_ENCODE_SRGB), 0);
    assert_int_equal(lc_encode_channel(2.0f, LC_ENCODE_SRGB), 255);
    assert_int_equal(lc_encode_channel(INFINITY, LC_ENCODE_SRGB), 255);
    /* Linear segment: 12.92 * 0.001 * 255 = 3.29 -> 3. */
    assert_int_equal(lc_encode_channel(0.001f, LC_ENCODE_SRGB), 3);
}

/* Both branches of the sRGB curve meet at 0.0031308 (0.04045 encoded, 10.31
** in bytes): the floats on either side of the boundary encode alike. */
static void encode_srgb_boundary_is_continuous(void **state)
{
    (void)state;
    float b = 0.0031308f;
    float below = b, above = b;
    for (int i = 0; i < 64; i++) {
        below = nextafterf(below, 0);
        above = nextafterf(above, 1);
    }
    uint8_t lo = lc_encode_channel(below, LC_ENCODE_SRGB);
    uint8_t at = lc_encode_channel(b, LC_ENCODE_SRGB);
    uint8_t hi = lc_encode_channel(above, LC_ENCODE_SRGB);
    assert_int_equal(lo, 10);
    assert_int_equal(at, 10);
    assert_int_equal(hi, 10);
    /* A jump at the boundary would show as a byte step between neighbours. */
    float x = below;
    while (x <= above) {
        float nx = nextafterf(x, 1);
        assert_int_equal(lc_encode_channel(x, LC_ENCODE_SRGB),
                         lc_encode_channel(nx, LC_ENCODE_SRGB));
        x = nx;
    }
}

/* 10^5 equal steps over [0, 1]: never decreasing, never skipping a byte, and
** every byte value from 0 to 255 is reached. */
/* The encoder counts precomputed thresholds instead of calling pow(): it
** must agree with the textbook formula everywhere, boundaries included. */
static void encode_srgb_matches_direct_formula(void **state)
{
    (void)state;
    int bad = 0;
    for (int i = 0; i <= 2000000; i++) {
        double v = (float)(i / 2000000.0);      /* pixels are floats */
        double e = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
        unsigned want = v >= 1 ? 255 : (unsigned)(e * 255 + 0.5);
        if (lc_encode_channel((float)v, LC_ENCODE_SRGB) != want)
            bad++;
    }
    assert_int_equal(bad, 0);
}

static void encode_is_monotonic(void **state)
{
    (void)state;
    const int steps = 100000;
    for (int e = 0; e < 2; e++) {
        lc_encoding enc = e == 0 ? LC_ENCODE_LINEAR : LC_ENCODE_SRGB;
        int prev = lc_encode_channel(0.0f, enc), seen = 1;
        for (int i = 1; i <= steps; i++) {
            int b = lc_encode_channel((float)((double)i / steps), enc);
            if (b < prev || b > prev + 1)
                fail_msg("encoding %d: step %d gives %d after %d", e, i, b, prev);
            seen += b != prev;
            prev = b;
        }
        assert_int_equal(prev, 255);
        assert_int_equal(seen, 256);
    }
}

/* ---- Images -------------------------------------------------------------- */

static void check_rejected(int w, int h, const char *field, const char *size)
{
    lc_error err;
    memset(&err, 0, sizeof err);
    lc_image *img = lc_image_new(w, h, &err);
    assert_null(img);
    assert_int_equal(err.code, LC_EARG);
    assert_string_equal(err.field, field);
    if (!strstr(err.msg, size))
        fail_msg("'%s' not in: %s", size, err.msg);
}

static void image_new_rejects_bad_sizes(void **state)
{
    (void)state;
    check_rejected(0, 5, "width", "got 0x5");
    check_rejected(-3, 5, "width", "got -3x5");
    check_rejected(LC_MAX_SIDE + 1, 5, "width", "got 1048577x5");
    check_rejected(5, 0, "height", "got 5x0");
    check_rejected(5, -1, "height", "got 5x-1");
    check_rejected(5, LC_MAX_SIDE + 1, "height", "got 5x1048577");
    check_rejected(0, 0, "width", "got 0x0");
    check_rejected(-2147483647 - 1, 1, "width", "got -2147483648x1");
    /* Each side in range, but 16384 x 16385 > LC_MAX_PIXELS = 2^28. */
    check_rejected(16384, 16385, "width", "16384x16385");
    check_rejected(LC_MAX_SIDE, LC_MAX_SIDE, "width", "1048576x1048576");
    /* err may be NULL. */
    assert_null(lc_image_new(0, 1, NULL));
}

static void image_get_set_round_trip(void **state)
{
    (void)state;
    lc_error err;
    lc_image *img = lc_image_new(4, 3, &err);
    assert_non_null(img);
    assert_int_equal(err.code, LC_OK);
    assert_string_equal(err.msg, "");
    assert_int_equal(lc_image_width(img), 4);
    assert_int_equal(lc_image_height(img), 3);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 4; x++) {
            lc_color c = lc_image_get(img, x, y);
            assert_true(c.r == 0 && c.g == 0 && c.b == 0);   /* black */
        }
    /* Distinct values per pixel and channel, including ones outside [0, 1]:
    ** the image stores linear floats bit for bit. */
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 4; x++) {
            lc_color c = {x + 0.1f * y, -1e-7f * (float)(x + 1), 1e30f + (float)y};
            lc_image_set(img, x, y, c);
        }
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 4; x++) {
            lc_color c = lc_image_get(img, x, y);
            assert_true(c.r == x + 0.1f * y);
            assert_true(c.g == -1e-7f * (float)(x + 1));
            assert_true(c.b == 1e30f + (float)y);
        }
    lc_image_free(img);

    img = lc_image_new(1, 1, &err);
    assert_non_null(img);
    lc_image_set(img, 0, 0, (lc_color){NAN, INFINITY, -0.0f});
    lc_color c = lc_image_get(img, 0, 0);
    assert_true(isnan(c.r));
    assert_true(isinf(c.g) && c.g > 0);
    assert_true(c.b == 0 && signbit(c.b));
    lc_image_free(img);
    lc_image_free(NULL);
}

/* ---- PNG ----------------------------------------------------------------- */

/* 3x2, known colours: primaries, mixes, and values that need clamping. */
static const lc_color known[6] = {
    {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f},
    {0.5f, 0.25f, 0.75f}, {0.18f, 0.0031308f, 0.9f}, {2.0f, -1.0f, NAN},
};

static lc_image *known_image(void)
{
    lc_error err;
    lc_image *img = lc_image_new(3, 2, &err);
    assert_non_null(img);
    for (int i = 0; i < 6; i++)
        lc_image_set(img, i % 3, i / 3, known[i]);
    return img;
}

static void expected_bytes(lc_encoding enc, uint8_t out[18])
{
    for (int i = 0; i < 6; i++) {
        out[3 * i + 0] = lc_encode_channel(known[i].r, enc);
        out[3 * i + 1] = lc_encode_channel(known[i].g, enc);
        out[3 * i + 2] = lc_encode_channel(known[i].b, enc);
    }
}

typedef struct {
    char dir[64];
    char path[128];
} tmp_place;


static const char *in_dir(tmp_place *t, const char *name)
{
    snprintf(t->path, sizeof t->path, "%s/%s", t->dir, name);
    return t->path;
}

/* Names in the folder other than . and ..; n counts them, tmp those with
** ".tmp-" in them (lc_image_save_png's temporary files). */
static void list_dir(const char *dir, int *n, int *tmp)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    *n = *tmp = 0;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        ++*n;
        if (strstr(e->d_name, ".tmp-"))
            ++*tmp;
    }
    closedir(d);
}

/* Removes the folder, its files and empty subfolders. */
static void remove_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char p[512];
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        snprintf(p, sizeof p, "%.200s/%.255s", dir, e->d_name);
        if (unlink(p) != 0)
            rmdir(p);
    }
    closedir(d);
    rmdir(dir);
}

/* Each PNG test gets a fresh folder, removed even when the test fails. */
static int setup_dir(void **state)
{
    tmp_place *t = malloc(sizeof *t);
    if (!t)
        return -1;
    snprintf(t->dir, sizeof t->dir, "/tmp/lancer-test-image-XXXXXX");
    if (!mkdtemp(t->dir)) {
        free(t);
        return -1;
    }
    *state = t;
    return 0;
}

static int teardown_dir(void **state)
{
    tmp_place *t = *state;
    remove_dir(t->dir);
    free(t);
    return 0;
}

/* The file's pixels converted by libpng's simplified API to `format`. */
static void read_simplified(const char *path, png_uint_32 format, void *buf, size_t size)
{
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    assert_true(png_image_begin_read_from_file(&pi, path));
    assert_int_equal(pi.width, 3);
    assert_int_equal(pi.height, 2);
    pi.format = format;
    assert_int_equal(PNG_IMAGE_SIZE(pi), size);
    if (!png_image_finish_read(&pi, NULL, buf, 0, NULL))
        fail_msg("libpng: %s", pi.message);
}

/* The file's own bytes, untransformed, and its colour-space chunks. */
typedef struct {
    uint8_t px[18];
    int     color_type, bit_depth;
    int     has_srgb, has_gama;
    double  gamma;
} raw_png;

static void read_raw(const char *path, raw_png *out)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    assert_non_null(png);
    png_infop info = png_create_info_struct(png);
    assert_non_null(info);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        fail_msg("libpng could not read '%s'", path);
    }
    png_init_io(png, fp);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
    assert_int_equal(png_get_image_width(png, info), 3);
    assert_int_equal(png_get_image_height(png, info), 2);
    out->color_type = png_get_color_type(png, info);
    out->bit_depth = png_get_bit_depth(png, info);
    png_bytepp rows = png_get_rows(png, info);
    for (int y = 0; y < 2; y++)
        memcpy(out->px + 9 * y, rows[y], 9);
    int intent;
    out->has_srgb = png_get_sRGB(png, info, &intent) != 0;
    out->has_gama = png_get_gAMA(png, info, &out->gamma) != 0;
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
}

static void save_ok(const lc_image *img, const char *path, lc_encoding enc)
{
    lc_error err;
    memset(&err, 0x5a, sizeof err);
    lc_status st = lc_image_save_png(img, path, enc, &err);
    if (st != LC_OK)
        fail_msg("save '%s': %d %s", path, st, err.msg);
    assert_int_equal(err.code, LC_OK);
    assert_string_equal(err.msg, "");
}

static void png_linear_round_trip(void **state)
{
    tmp_place *t = *state;
    lc_image *img = known_image();
    const char *path = in_dir(t, "linear.png");
    save_ok(img, path, LC_ENCODE_LINEAR);

    uint8_t want[18];
    expected_bytes(LC_ENCODE_LINEAR, want);
    const uint8_t lit[18] = {255, 0, 0, 0, 255, 0, 0, 0, 255,
                             128, 64, 191, 46, 1, 229, 255, 0, 0};
    /* 0.9f is 0.89999998: 229.499994 + 0.5 rounds down to 229. */
    assert_memory_equal(want, lit, 18);

    raw_png raw;
    read_raw(path, &raw);
    assert_int_equal(raw.color_type, PNG_COLOR_TYPE_RGB);
    assert_int_equal(raw.bit_depth, 8);
    assert_memory_equal(raw.px, want, 18);
    assert_false(raw.has_srgb);
    assert_true(raw.has_gama);
    assert_true(raw.gamma == 1.0);      /* stored as 100000: exact */

    /* libpng's simplified reader honours gAMA 1.0: read as 8-bit (sRGB) it
    ** would re-encode, so read it as 16-bit linear, where byte b is b*257. */
    uint16_t lin[18];
    read_simplified(path, PNG_FORMAT_LINEAR_RGB, lin, sizeof lin);
    for (int i = 0; i < 18; i++)
        if (lin[i] != want[i] * 257)
            fail_msg("channel %d: %d, want %d", i, lin[i], want[i] * 257);

    int n, tmp;
    list_dir(t->dir, &n, &tmp);
    assert_int_equal(n, 1);
    assert_int_equal(tmp, 0);
    lc_image_free(img);
}

static void png_srgb_round_trip(void **state)
{
    tmp_place *t = *state;
    lc_image *img = known_image();
    const char *path = in_dir(t, "srgb.png");
    save_ok(img, path, LC_ENCODE_SRGB);

    uint8_t want[18];
    expected_bytes(LC_ENCODE_SRGB, want);
    const uint8_t lit[18] = {255, 0, 0, 0, 255, 0, 0, 0, 255,
                             188, 137, 225, 118, 10, 243, 255, 0, 0};
    assert_memory_equal(want, lit, 18);

    raw_png raw;
    read_raw(path, &raw);
    assert_memory_equal(raw.px, want, 18);
    assert_true(raw.has_srgb);

    uint8_t px[18];
    read_simplified(path, PNG_FORMAT_RGB, px, sizeof px);
    assert_memory_equal(px, want, 18);
    lc_image_free(img);
}

static void png_missing_directory_fails(void **state)
{
    tmp_place *t = *state;
    lc_image *img = known_image();
    const char *path = in_dir(t, "no-such-dir/out.png");
    lc_error err;
    assert_int_equal(lc_image_save_png(img, path, LC_ENCODE_SRGB, &err), LC_EIO);
    assert_int_equal(err.code, LC_EIO);
    assert_string_equal(err.field, "path");
    if (!strstr(err.msg, "cannot write") || !strstr(err.msg, path))
        fail_msg("message lacks 'cannot write' or the path: %s", err.msg);
    if (!strstr(err.msg, "No such file or directory"))
        fail_msg("message lacks the reason: %s", err.msg);
    int n, tmp;
    list_dir(t->dir, &n, &tmp);
    assert_int_equal(n, 0);               /* nothing created, no temporary */
    assert_int_equal(tmp, 0);
    struct stat sb;
    assert_int_not_equal(stat(in_dir(t, "no-such-dir"), &sb), 0);

    assert_int_equal(lc_image_save_png(img, "", LC_ENCODE_SRGB, &err), LC_EARG);
    assert_string_equal(err.field, "path");
    lc_image_free(img);
}

static void png_replaces_existing_file(void **state)
{
    tmp_place *t = *state;
    const char *path = in_dir(t, "out.png");
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    fputs("not a png, and longer than nothing", fp);
    fclose(fp);

    lc_image *a = known_image();
    save_ok(a, path, LC_ENCODE_SRGB);
    lc_image *b = known_image();
    lc_image_set(b, 0, 0, (lc_color){0, 0, 0});
    lc_image_set(b, 2, 1, (lc_color){1, 1, 1});
    save_ok(b, path, LC_ENCODE_SRGB);

    uint8_t px[18];
    read_simplified(path, PNG_FORMAT_RGB, px, sizeof px);
    assert_int_equal(px[0], 0);
    assert_int_equal(px[1], 0);
    assert_int_equal(px[2], 0);
    assert_int_equal(px[15], 255);
    assert_int_equal(px[16], 255);
    assert_int_equal(px[17], 255);
    assert_int_equal(px[9], 188);          /* untouched pixel (0, 1) */

    /* mkstemp makes 0600; the result follows the umask like any new file. */
    mode_t old = umask(022);
    save_ok(b, path, LC_ENCODE_SRGB);
    umask(old);
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    assert_int_equal(sb.st_mode & 0777, 0644);

    int n, tmp;
    list_dir(t->dir, &n, &tmp);
    assert_int_equal(n, 1);
    assert_int_equal(tmp, 0);
    lc_image_free(a);
    lc_image_free(b);
}

static long read_all(const char *path, char *buf, size_t size)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    size_t n = fread(buf, 1, size, fp);
    fclose(fp);
    return (long)n;
}

/* The target is a directory: it is refused before anything is written (a
** rename would fail, or replace a device node), no temporary is left and
** the other file is untouched. */
static void png_failed_rename_cleans_up(void **state)
{
    tmp_place *t = *state;
    lc_image *img = known_image();
    char keep[128];
    snprintf(keep, sizeof keep, "%s", in_dir(t, "keep.png"));
    save_ok(img, keep, LC_ENCODE_LINEAR);
    char before[4096], after[4096];
    long nb = read_all(keep, before, sizeof before);
    assert_true(nb > 0 && nb < (long)sizeof before);

    const char *dir = in_dir(t, "target.png");
    assert_int_equal(mkdir(dir, 0700), 0);
    lc_image *other = known_image();
    lc_image_set(other, 1, 1, (lc_color){0.3f, 0.3f, 0.3f});
    lc_error err;
    assert_int_equal(lc_image_save_png(other, dir, LC_ENCODE_SRGB, &err), LC_EARG);
    assert_string_equal(err.field, "path");
    if (!strstr(err.msg, "cannot write") || !strstr(err.msg, dir) ||
        !strstr(err.msg, "is a directory"))
        fail_msg("message lacks 'cannot write', the path or why: %s", err.msg);

    long na = read_all(keep, after, sizeof after);
    assert_int_equal(na, nb);
    assert_memory_equal(after, before, (size_t)nb);
    struct stat sb;
    assert_int_equal(stat(dir, &sb), 0);
    assert_true(S_ISDIR(sb.st_mode));

    int n, tmp;
    list_dir(t->dir, &n, &tmp);
    assert_int_equal(tmp, 0);
    assert_int_equal(n, 2);               /* keep.png and target.png/ */
    list_dir(dir, &n, &tmp);
    assert_int_equal(n, 0);
    lc_image_free(img);
    lc_image_free(other);
}

/* ---- Error against a reference -------------------------------------------- */

static lc_image *image_2x1(lc_color a, lc_color b)
{
    lc_error err;
    lc_image *img = lc_image_new(2, 1, &err);
    assert_non_null(img);
    lc_image_set(img, 0, 0, a);
    lc_image_set(img, 1, 0, b);
    return img;
}

/* Channel differences 0.25, 0, -0.25 | 0.25, -0.5, 0.125 against references
** 0.25, 0.25, 0.25 | 0.75, 0.5, 0 (all exact in float): by hand, squares sum
** to 0.453125, |d| to 1.375, d to -0.125; relMSE's terms are 0.0625/0.26^2
** twice, 0.0625/0.76^2, 0.25/0.51^2 and 0.015625/0.01^2 = 156.25. */
static void image_error_exact(void **state)
{
    (void)state;
    lc_image *img = image_2x1((lc_color){0.5f, 0.25f, 0}, (lc_color){1, 0, 0.125f});
    lc_image *ref = image_2x1((lc_color){0.25f, 0.25f, 0.25f},
                              (lc_color){0.75f, 0.5f, 0});
    lc_image_error_stats e;
    lc_error err;
    assert_int_equal(lc_image_error(img, ref, &e, &err), LC_OK);
    assert_true(e.mse == 0.453125 / 6);
    assert_true(e.rmse == sqrt(0.453125 / 6));
    assert_true(e.mae == 1.375 / 6);
    assert_true(e.bias == -0.125 / 6);
    assert_true(fabs(e.relmse - 26.52808126307744) < 1e-12 * 26.5);
    /* Against itself: every figure is exactly 0. */
    assert_int_equal(lc_image_error(ref, ref, &e, &err), LC_OK);
    assert_true(e.mse == 0 && e.rmse == 0 && e.relmse == 0 && e.mae == 0 && e.bias == 0);
    lc_image_free(img);
    lc_image_free(ref);
}

static void image_error_and_add_refuse_other_sizes(void **state)
{
    (void)state;
    lc_error err;
    lc_image *a = lc_image_new(2, 1, &err), *b = lc_image_new(1, 2, &err);
    lc_image_error_stats e;
    assert_int_equal(lc_image_error(a, b, &e, &err), LC_EARG);
    assert_non_null(strstr(err.msg, "2x1 and 1x2"));
    assert_int_equal(lc_image_add(a, b, 1, &err), LC_EARG);
    assert_non_null(strstr(err.msg, "2x1 and 1x2"));
    assert_int_equal(lc_image_add(a, a, NAN, &err), LC_EARG);
    assert_string_equal(err.field, "weight");
    lc_image_free(a);
    lc_image_free(b);
}

/* Averaging two renders: a = 0.5 a + 0.5 b, exact for these values. */
static void image_add_weighs(void **state)
{
    (void)state;
    lc_image *a = image_2x1((lc_color){1, 2, 3}, (lc_color){0, -1, 0.5f});
    lc_image *b = image_2x1((lc_color){3, 2, 1}, (lc_color){1, 1, 0.25f});
    lc_error err;
    assert_int_equal(lc_image_add(a, a, -0.5, &err), LC_OK);    /* a itself: halves */
    assert_int_equal(lc_image_add(a, b, 0.5, &err), LC_OK);
    lc_color p = lc_image_get(a, 0, 0), q = lc_image_get(a, 1, 0);
    assert_true(p.r == 2 && p.g == 2 && p.b == 2);
    assert_true(q.r == 0.5f && q.g == 0 && q.b == 0.375f);
    lc_image_free(a);
    lc_image_free(b);
}

#define IN_DIR(f) cmocka_unit_test_setup_teardown(f, setup_dir, teardown_dir)

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(encode_linear_clamps_and_rounds),
        cmocka_unit_test(encode_srgb_values),
        cmocka_unit_test(encode_srgb_boundary_is_continuous),
        cmocka_unit_test(encode_srgb_matches_direct_formula),
        cmocka_unit_test(encode_is_monotonic),
        cmocka_unit_test(image_new_rejects_bad_sizes),
        cmocka_unit_test(image_get_set_round_trip),
        cmocka_unit_test(image_error_exact),
        cmocka_unit_test(image_error_and_add_refuse_other_sizes),
        cmocka_unit_test(image_add_weighs),
        IN_DIR(png_linear_round_trip),
        IN_DIR(png_srgb_round_trip),
        IN_DIR(png_missing_directory_fails),
        IN_DIR(png_replaces_existing_file),
        IN_DIR(png_failed_rename_cleans_up),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
