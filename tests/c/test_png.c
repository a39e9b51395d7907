/* test_png.c: lc_image_load_png over every colour type, bit depth,
** palette, tRNS, gAMA/sRGB chunk and interlacing libpng writes: each pixel
** against the closed form of what the file stores (its curve, its alpha),
** and near libpng's own simplified reader, which quantizes to 8 bits. */
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include "lancer.h"

#define W 13                       /* odd sizes: Adam7's passes are uneven */
#define H 11

enum { GAMMA_NONE, GAMMA_LINEAR, GAMMA_22, GAMMA_SRGB };

typedef struct {
    int type, depth, interlace, trns, gamma;
} spec;

/* Sample c (0: r or grey, 1: g, 2: b, 3: alpha) of pixel (x, y), below 2^depth. */
static unsigned sample(int x, int y, int c, int depth)
{
    unsigned max = (1u << depth) - 1;
    return (unsigned)(x * 7919 + y * 104729 + c * 15485863 + (x * y) * 31) % (max + 1);
}

static int channels(int type)
{
    switch (type) {
    case PNG_COLOR_TYPE_GRAY: return 1;
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_PALETTE: return 1;
    case PNG_COLOR_TYPE_RGB: return 3;
    default: return 4;
    }
}

/* The palette: entry i. */
static png_color palette_entry(int i)
{
    png_color c = {(png_byte)(i * 37 % 256), (png_byte)(i * 91 % 256),
                   (png_byte)(255 - i * 13 % 256)};
    return c;
}

/* Writes the image `sp` describes with libpng's low-level writer. */
static void write_png(const char *path, spec sp)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    assert_int_equal(setjmp(png_jmpbuf(png)), 0);
    png_init_io(png, fp);
    png_set_IHDR(png, info, W, H, sp.depth, sp.type, sp.interlace ? PNG_INTERLACE_ADAM7 :
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    int entries = 1 << sp.depth;
    if (sp.type == PNG_COLOR_TYPE_PALETTE) {
        png_color pal[256];
        for (int i = 0; i < entries; i++)
            pal[i] = palette_entry(i);
        png_set_PLTE(png, info, pal, entries);
    }
    if (sp.trns) {
        if (sp.type == PNG_COLOR_TYPE_PALETTE) {
            png_byte a[256];
            for (int i = 0; i < entries; i++)
                a[i] = (png_byte)(i % 3 == 0 ? 0 : 255 - i);
            png_set_tRNS(png, info, a, entries, NULL);
        } else {
            png_color_16 key = {0, (png_uint_16)sample(1, 1, 0, sp.depth),
                                (png_uint_16)sample(1, 1, 1, sp.depth),
                                (png_uint_16)sample(1, 1, 2, sp.depth),
                                (png_uint_16)sample(1, 1, 0, sp.depth)};
            png_set_tRNS(png, info, NULL, 0, &key);
        }
    }
    if (sp.gamma == GAMMA_LINEAR)
        png_set_gAMA(png, info, 1.0);
    else if (sp.gamma == GAMMA_22)
        png_set_gAMA(png, info, 1 / 2.2);
    else if (sp.gamma == GAMMA_SRGB)
        png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    if (sp.depth < 8)
        png_set_packing(png);
    if (sp.depth == 16)
        png_set_swap(png);
    int ch = channels(sp.type), bytes = sp.depth == 16 ? 2 : 1;
    unsigned char *pixels = calloc((size_t)W * H * ch * bytes, 1);
    png_bytep rows[H];
    for (int y = 0; y < H; y++) {
        rows[y] = pixels + (size_t)y * W * ch * bytes;
        for (int x = 0; x < W; x++)
            for (int c = 0; c < ch; c++) {
                unsigned v = sample(x, y, c, sp.depth);
                if (bytes == 2)
                    ((uint16_t *)(void *)rows[y])[x * ch + c] = (uint16_t)v;
                else
                    rows[y][x * ch + c] = (unsigned char)v;
            }
    }
    png_write_image(png, rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(pixels);
    fclose(fp);
}

/* What "as stored" reads for pixel (x, y): each sample over its maximum,
** palette entries over 255, alpha dropped. */
static void stored(spec sp, int x, int y, double out[3])
{
    double max = (1u << sp.depth) - 1;
    if (sp.type == PNG_COLOR_TYPE_PALETTE) {
        png_color c = palette_entry((int)sample(x, y, 0, sp.depth));
        out[0] = c.red / 255.0, out[1] = c.green / 255.0, out[2] = c.blue / 255.0;
    } else if (sp.type == PNG_COLOR_TYPE_GRAY || sp.type == PNG_COLOR_TYPE_GRAY_ALPHA) {
        out[0] = out[1] = out[2] = sample(x, y, 0, sp.depth) / max;
    } else {
        for (int c = 0; c < 3; c++)
            out[c] = sample(x, y, c, sp.depth) / max;
    }
}

/* The alpha pixel (x, y) has: its alpha sample, its palette entry's tRNS,
** 0 where a tRNS key colour matches, else 1. */
static double alpha_of(spec sp, int x, int y)
{
    double max = (1u << sp.depth) - 1;
    if (sp.type == PNG_COLOR_TYPE_GRAY_ALPHA)
        return sample(x, y, 1, sp.depth) / max;
    if (sp.type == PNG_COLOR_TYPE_RGB_ALPHA)
        return sample(x, y, 3, sp.depth) / max;
    if (!sp.trns)
        return 1;
    if (sp.type == PNG_COLOR_TYPE_PALETTE) {
        int i = (int)sample(x, y, 0, sp.depth);
        return (i % 3 == 0 ? 0 : 255 - i) / 255.0;
    }
    int n = sp.type == PNG_COLOR_TYPE_GRAY ? 1 : 3;
    for (int c = 0; c < n; c++)
        if (sample(x, y, c, sp.depth) != sample(1, 1, c, sp.depth))
            return 1;
    return 0;
}

/* What decoding must give: the stored value through the file's curve (the
** sRGB curve for an sRGB chunk, v^(1/g) for a gAMA of g: libpng stores
** 1/2.2 as 45455 / 100000; saying nothing, sRGB at 8 bits and below and
** linear at 16), times the alpha. */
static void decoded(spec sp, int x, int y, double out[3])
{
    stored(sp, x, y, out);
    double a = alpha_of(sp, x, y);
    for (int c = 0; c < 3; c++) {
        double v = out[c];
        if (sp.gamma == GAMMA_LINEAR || (sp.gamma == GAMMA_NONE && sp.depth == 16))
            ;                        /* 16 bits saying nothing: linear, as libpng */
        else if (sp.gamma == GAMMA_22)
            v = pow(v, 1 / 0.45455);
        else
            v = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
        out[c] = (float)v * a;
    }
}

/* libpng's simplified reader, linear RGB: a cross-check. */
static void reference(const char *path, float *out)
{
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    assert_true(png_image_begin_read_from_file(&pi, path));
    pi.format = PNG_FORMAT_LINEAR_RGB;
    uint16_t *buf = malloc(PNG_IMAGE_SIZE(pi));
    assert_true(png_image_finish_read(&pi, NULL, buf, 0, NULL));
    for (int i = 0; i < W * H * 3; i++)
        out[i] = (float)(buf[i] / 65535.0);
    free(buf);
}

static lc_image *load(const char *path, lc_encoding enc)
{
    lc_error err;
    lc_image *img = lc_image_load_png(path, enc, &err);
    if (!img)
        fail_msg("%s", err.msg);
    assert_int_equal(lc_image_width(img), W);
    assert_int_equal(lc_image_height(img), H);
    return img;
}

static int same(const lc_image *a, const lc_image *b)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            lc_color p = lc_image_get(a, x, y), q = lc_image_get(b, x, y);
            if (p.r != q.r || p.g != q.g || p.b != q.b)
                return 0;
        }
    return 1;
}

static void check_one(spec sp, int *cases)
{
    char plain[] = "/tmp/lancer-png-XXXXXX", laced[] = "/tmp/lancer-png-XXXXXX";
    close(mkstemp(plain));
    close(mkstemp(laced));
    spec a = sp, b = sp;
    a.interlace = 0;
    b.interlace = 1;
    write_png(plain, a);
    write_png(laced, b);
    char what[160];
    snprintf(what, sizeof what, "type %d depth %d tRNS %d gamma %d", sp.type, sp.depth,
             sp.trns, sp.gamma);
    for (int enc = 0; enc < 2; enc++) {
        lc_image *p = load(plain, (lc_encoding)enc), *q = load(laced, (lc_encoding)enc);
        /* The campaign's bug: an interlaced copy decoded to other pixels. */
        if (!same(p, q))
            fail_msg("%s, %s: the interlaced copy reads differently", what,
                     enc ? "as stored" : "decoded");
        if (enc == LC_ENCODE_SRGB) {
            float ref[W * H * 3];
            reference(plain, ref);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    lc_color c = lc_image_get(p, x, y);
                    double e[3];
                    decoded(sp, x, y, e);
                    if ((float)e[0] != c.r || (float)e[1] != c.g || (float)e[2] != c.b)
                        fail_msg("%s: decoded (%d, %d) = (%.9g, %.9g, %.9g), its curve "
                                 "gives (%.9g, %.9g, %.9g)", what, x, y, c.r, c.g, c.b,
                                 e[0], e[1], e[2]);
                    /* libpng's 8-bit path and its 2.2 power for sRGB: near. */
                    const float *r = ref + 3 * (y * W + x);
                    if (fabs(c.r - r[0]) > 0.012 || fabs(c.g - r[1]) > 0.012 ||
                        fabs(c.b - r[2]) > 0.012)
                        fail_msg("%s: decoded (%d, %d) = (%g, %g, %g), libpng (%g, %g, %g)",
                                 what, x, y, c.r, c.g, c.b, r[0], r[1], r[2]);
                }
        } else {
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    double e[3];
                    stored(sp, x, y, e);
                    lc_color c = lc_image_get(p, x, y);
                    if (c.r != (float)e[0] || c.g != (float)e[1] || c.b != (float)e[2])
                        fail_msg("%s: stored (%d, %d) = (%g, %g, %g), written (%g, %g, %g)",
                                 what, x, y, c.r, c.g, c.b, e[0], e[1], e[2]);
                }
            /* An opaque linear file: libpng's decoding is the stored values. */
            int opaque = !sp.trns && !(sp.type & PNG_COLOR_MASK_ALPHA);
            if (opaque && sp.gamma == GAMMA_LINEAR) {
                float ref[W * H * 3];
                reference(plain, ref);
                for (int i = 0; i < W * H; i++) {
                    lc_color c = lc_image_get(p, i % W, i / W);
                    const float *r = ref + 3 * i;
                    if (fabs(c.r - r[0]) > 1e-7 || fabs(c.g - r[1]) > 1e-7 ||
                        fabs(c.b - r[2]) > 1e-7)
                        fail_msg("%s: stored %g, libpng's linear %g", what, c.r, r[0]);
                }
            }
        }
        lc_image_free(p);
        lc_image_free(q);
    }
    unlink(plain);
    unlink(laced);
    ++*cases;
}

static void every_kind_of_png_loads_right(void **state)
{
    (void)state;
    static const struct { int type, depths[5], n; } kinds[] = {
        {PNG_COLOR_TYPE_GRAY, {1, 2, 4, 8, 16}, 5},
        {PNG_COLOR_TYPE_GRAY_ALPHA, {8, 16}, 2},
        {PNG_COLOR_TYPE_PALETTE, {1, 2, 4, 8}, 4},
        {PNG_COLOR_TYPE_RGB, {8, 16}, 2},
        {PNG_COLOR_TYPE_RGB_ALPHA, {8, 16}, 2},
    };
    int cases = 0;
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++)
        for (int d = 0; d < kinds[k].n; d++)
            for (int trns = 0; trns < 2; trns++)
                for (int gamma = GAMMA_NONE; gamma <= GAMMA_SRGB; gamma++) {
                    if (trns && (kinds[k].type & PNG_COLOR_MASK_ALPHA))
                        continue;              /* tRNS only without an alpha channel */
                    spec sp = {kinds[k].type, kinds[k].depths[d], 0, trns, gamma};
                    check_one(sp, &cases);
                }
    print_message("%d PNG kinds, each plain and interlaced, read both ways\n", cases);
    assert_true(cases >= 80);
}

/* PNG's CRC-32 (ISO 3309), bit by bit. */
static unsigned long crc32_of(const unsigned char *p, size_t n)
{
    unsigned long c = 0xffffffffUL;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = c & 1 ? 0xedb88320UL ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xffffffffUL;
}

/* A header asking for more than lancer's caps is refused naming the cap,
** before any pixel is allocated ("out of memory" said nothing). */
static void oversized_png_names_the_cap(void **state)
{
    (void)state;
    /* A valid PNG signature and IHDR of 20000 x 20000, nothing after. */
    static const unsigned char head[] = {
        0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
        0, 0, 0x4e, 0x20, 0, 0, 0x4e, 0x20, 8, 2, 0, 0, 0};
    /* ... then an empty IDAT, so the header reads whole. */
    static const unsigned char idat[] = {0, 0, 0, 0, 'I', 'D', 'A', 'T'};
    unsigned char file[sizeof head + 4 + sizeof idat + 4];
    memcpy(file, head, sizeof head);
    unsigned long crc = crc32_of(head + 12, sizeof head - 12);
    for (int i = 0; i < 4; i++)
        file[sizeof head + i] = (unsigned char)(crc >> (24 - 8 * i));
    memcpy(file + sizeof head + 4, idat, sizeof idat);
    crc = crc32_of(idat + 4, 4);
    for (int i = 0; i < 4; i++)
        file[sizeof head + 4 + sizeof idat + i] = (unsigned char)(crc >> (24 - 8 * i));
    char path[] = "/tmp/lancer-png-XXXXXX";
    int fd = mkstemp(path);
    assert_int_equal(write(fd, file, sizeof file), (ssize_t)sizeof file);
    close(fd);
    for (int enc = 0; enc < 2; enc++) {
        lc_error err;
        assert_null(lc_image_load_png(path, (lc_encoding)enc, &err));
        if (!strstr(err.msg, "20000x20000") || !strstr(err.msg, "268435456 pixels"))
            fail_msg("not the size and the cap: %s", err.msg);
    }
    unlink(path);
}

/* Appends chunk `type` claiming `claim` bytes, holding the first `n` of
** data, with its CRC; returns the new end. */
static unsigned char *put_chunk(unsigned char *at, const char *type, uint32_t claim,
                                const unsigned char *data, size_t n)
{
    for (int i = 0; i < 4; i++)
        at[i] = (unsigned char)(claim >> (24 - 8 * i));
    memcpy(at + 4, type, 4);
    if (n)
        memcpy(at + 8, data, n);
    unsigned long crc = crc32_of(at + 4, 4 + n);
    for (int i = 0; i < 4; i++)
        at[8 + n + i] = (unsigned char)(crc >> (24 - 8 * i));
    return at + 12 + n;
}

static void expect_refused(const unsigned char *file, size_t n, const char *want)
{
    char path[] = "/tmp/lancer-png-XXXXXX";
    int fd = mkstemp(path);
    assert_int_equal(write(fd, file, n), (ssize_t)n);
    close(fd);
    for (int enc = 0; enc < 2; enc++) {
        lc_error err;
        assert_null(lc_image_load_png(path, (lc_encoding)enc, &err));
        if (!strstr(err.msg, want))
            fail_msg("'%s' lacks '%s'", err.msg, want);
    }
    unlink(path);
}

/* Chunks are checked before libpng reads them: a 64-byte file whose zTXt
** claimed 2 GB had libpng allocate and fill 2 GB (found by the PNG
** fuzzer); a text chunk past 16 MiB is refused too, naming the cap. */
static void chunk_lengths_are_checked_first(void **state)
{
    (void)state;
    static const unsigned char ihdr[13] = {0, 0, 0, 1, 0, 0, 0, 1, 8, 2, 0, 0, 0};
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char small[64];
    memcpy(small, sig, 8);
    unsigned char *end = put_chunk(small + 8, "IHDR", 13, ihdr, 13);
    end = put_chunk(end, "zTXt", 1998913536u, (const unsigned char *)"Comment", 7);
    expect_refused(small, (size_t)(end - small),
                   "chunk 'zTXt' at byte 33 claims 1998913536 bytes, past the end of the file");
    size_t big = (17u << 20);
    unsigned char *file = calloc(1, big + 128);
    memcpy(file, sig, 8);
    end = put_chunk(file + 8, "IHDR", 13, ihdr, 13);
    memcpy(end + 8, "Comment", 8);
    end = put_chunk(end, "tEXt", (uint32_t)big, end + 8, big);
    expect_refused(file, (size_t)(end - file),
                   "chunk 'tEXt' of 17825792 bytes is past lancer's cap of 16777216 bytes");
    free(file);
    expect_refused((const unsigned char *)"GIF89a, not a PNG", 17, "not a PNG file");
    /* A bad type after the image data: libpng's simplified reader stopped
    ** before it, the low-level one failed; both refuse it now. */
    end = put_chunk(small + 8, "IHDR", 13, ihdr, 13);
    end = put_chunk(end, "\tEND", 0, NULL, 0);
    expect_refused(small, (size_t)(end - small),
                   "the chunk at byte 33 has no valid type (bytes 09 45 4e 44)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_kind_of_png_loads_right),
        cmocka_unit_test(oversized_png_names_the_cap),
        cmocka_unit_test(chunk_lengths_are_checked_first),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
