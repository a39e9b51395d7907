/* fuzz_png.c: libFuzzer harness of the PNG reader (lc_image_load_png), in
** both encodings. The input is a PNG file whose chunk CRCs the harness
** recomputes first: libpng refuses a chunk with a wrong CRC, so without
** this almost every mutation of a header or a palette would end there.
** FUZZ_PNG_SAVE=FILE writes the file as the reader sees it. */
#define _GNU_SOURCE                 /* memfd_create */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
#include "lancer.h"
#include "../memfile.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static memfile in;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    memfile_open(&in, "fuzz.png");
    /* A header may ask for 2^28 pixels (3 GiB): the cap refuses it as
    ** LC_ENOMEM, a path worth reaching, before libFuzzer's malloc limit. */
    lc_memory_cap((size_t)64 << 20);
    return 0;
}

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Rewrites the CRC of every whole chunk after the signature. */
static void fix_crcs(uint8_t *p, size_t n)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n < 8 || memcmp(p, sig, 8))
        return;
    size_t at = 8;
    while (n - at >= 12) {
        uint32_t len = be32(p + at);
        if (len > n - at - 12)
            break;
        uint32_t crc = (uint32_t)crc32(0L, p + at + 4, (uInt)len + 4);
        uint8_t *c = p + at + 8 + len;
        c[0] = (uint8_t)(crc >> 24), c[1] = (uint8_t)(crc >> 16);
        c[2] = (uint8_t)(crc >> 8), c[3] = (uint8_t)crc;
        at += 12 + (size_t)len;
    }
}

static void check_failure(const lc_error *err)
{
    if (err->code == LC_OK || !err->msg[0] || !memchr(err->msg, '\0', sizeof err->msg)) {
        fprintf(stderr, "failure without a message (code %d)\n", (int)err->code);
        abort();
    }
}

/* A decoded image: a sane size, every channel a stored value over its
** maximum (or that decoded from sRGB), so within [0, 1]. */
static void check_image(const lc_image *img)
{
    int w = lc_image_width(img), h = lc_image_height(img);
    if (w < 1 || h < 1 || w > LC_MAX_SIDE || h > LC_MAX_SIDE) {
        fprintf(stderr, "loaded an image of %dx%d\n", w, h);
        abort();
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            lc_color c = lc_image_get(img, x, y);
            if (!(c.r >= 0 && c.r <= 1 && c.g >= 0 && c.g <= 1 &&
                  c.b >= 0 && c.b <= 1)) {
                fprintf(stderr, "pixel (%d, %d) is (%g, %g, %g)\n", x, y, c.r, c.g, c.b);
                abort();
            }
        }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = malloc(size ? size : 1);
    if (!buf)
        abort();
    memcpy(buf, data, size);
    fix_crcs(buf, size);
    memfile_put(&in, buf, size);
    /* FUZZ_PNG_SAVE=FILE: the file as read, CRCs fixed, to try elsewhere. */
    const char *save = getenv("FUZZ_PNG_SAVE");
    FILE *f = save ? fopen(save, "wb") : NULL;
    if (f)
        fwrite(buf, 1, size, f), fclose(f);
    free(buf);
    lc_image *img[2];
    const lc_encoding enc[2] = {LC_ENCODE_SRGB, LC_ENCODE_LINEAR};
    for (int i = 0; i < 2; i++) {
        lc_error err;
        img[i] = lc_image_load_png(in.path, enc[i], &err);
        if (img[i])
            check_image(img[i]);
        else
            check_failure(&err);
    }
    /* The encoding changes the values, never whether the file reads. */
    if (!img[0] != !img[1]) {
        fprintf(stderr, "the file reads in one encoding only\n");
        abort();
    }
    lc_image_free(img[0]);
    lc_image_free(img[1]);
    return 0;
}
