/* fuzz_exr.c: libFuzzer harness of the EXR readers: lc_image_load_exr (a
** picture or a sky: R, G, B [, A] or Y, other layers skipped) and
** exr_read_raster (the parts lancer merges: its own layouts alone). The
** input is the file, in memory. FUZZ_EXR_SAVE=FILE writes it out. */
#define _GNU_SOURCE                 /* memfd_create */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lancer.h"
#include "../memfile.h"
#include "base/mem.h"
#include "image/raster.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static memfile in;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    memfile_open(&in, "fuzz.exr");
    /* A header may claim 2^28 pixels: the cap refuses the image as
    ** LC_ENOMEM, a path worth reaching, before libFuzzer's malloc limit. */
    lc_memory_cap((size_t)64 << 20);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    memfile_put(&in, data, size);
    const char *save = getenv("FUZZ_EXR_SAVE");
    if (save) {
        FILE *fp = fopen(save, "wb");
        if (fp) {
            fwrite(data, 1, size, fp);
            fclose(fp);
        }
    }
    lc_error err;
    lc_image *img = lc_image_load_exr(in.path, &err);
    if (img) {
        /* Every sample read is the file's: touching them all lets ASan
        ** see a pixel buffer written short. */
        volatile float sum = 0;
        for (int y = 0; y < lc_image_height(img); y++)
            for (int x = 0; x < lc_image_width(img); x++) {
                lc_color c = lc_image_get(img, x, y);
                sum += c.r + c.g + c.b + lc_image_get_alpha(img, x, y);
            }
        (void)sum;
        lc_image_free(img);
    } else if (!strstr(err.msg, in.path) && err.code != LC_ENOMEM) {
        fprintf(stderr, "an error that does not name the file: %s\n", err.msg);
        abort();
    }
    raster_format f;
    unsigned char *samples = NULL;
    if (exr_read_raster(in.path, &f, &samples, &err) == LC_OK)
        mem_free(samples);
    return 0;
}
