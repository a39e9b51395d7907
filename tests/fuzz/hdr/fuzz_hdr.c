/* fuzz_hdr.c: libFuzzer harness of the Radiance .hdr reader
** (lc_image_load_hdr): the input as the file; an image read must be of its
** caps' size with every channel finite and not negative. */
#define _GNU_SOURCE                 /* memfd_create */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lancer.h"
#include "../memfile.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static memfile in;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    memfile_open(&in, "fuzz.hdr");
    /* A header claiming a huge image that the file could hold is refused as
    ** LC_ENOMEM, a path the harness means to reach. */
    lc_memory_cap((size_t)256 << 20);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    memfile_put(&in, data, size);
    lc_error err;
    lc_image *img = lc_image_load_hdr(in.path, &err);
    if (!img) {
        /* A failure must say why, naming the file. */
        if (err.code == LC_OK || !memchr(err.msg, '\0', sizeof err.msg) ||
            !strstr(err.msg, "/proc/self/fd/")) {
            fprintf(stderr, "failure without a message naming the file (code %d): %s\n",
                    (int)err.code, err.msg);
            abort();
        }
        return 0;
    }
    int w = lc_image_width(img), h = lc_image_height(img);
    if (w < 1 || h < 1 || w > LC_MAX_SIDE || h > LC_MAX_SIDE ||
        (size_t)w * (size_t)h > LC_MAX_PIXELS) {
        fprintf(stderr, "a %dx%d image read\n", w, h);
        abort();
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            lc_color c = lc_image_get(img, x, y);
            if (!isfinite(c.r) || !isfinite(c.g) || !isfinite(c.b) || c.r < 0 || c.g < 0 ||
                c.b < 0) {
                fprintf(stderr, "pixel (%d, %d) is (%g, %g, %g)\n", x, y, c.r, c.g, c.b);
                abort();
            }
        }
    lc_image_free(img);
    return 0;
}
