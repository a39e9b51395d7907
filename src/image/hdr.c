/* hdr.c: Radiance .hdr (RGBE) images read through stb_image, Debian's
** libstb-dev: a well-kept reader, so lancer has no parser of its own. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <stb_image.h>
#include "base/error.h"
#include "image.h"

lc_image *lc_image_load_hdr(const char *path, lc_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    int hdr = stbi_is_hdr_from_file(f);
    fclose(f);
    if (!hdr) {
        error_fail(err, LC_EARG, "path", "'%s' is not a Radiance .hdr image", path);
        return NULL;
    }
    int w = 0, h = 0, n = 0;
    float *px = stbi_loadf(path, &w, &h, &n, 3);
    if (!px) {
        error_fail(err, LC_EARG, "path", "cannot read '%s': %s", path, stbi_failure_reason());
        return NULL;
    }
    if (w > LC_MAX_SIDE || h > LC_MAX_SIDE || (size_t)w * (size_t)h > LC_MAX_PIXELS) {
        stbi_image_free(px);
        error_fail(err, LC_EARG, "path", "'%s' is %dx%d, past lancer's %d a side and %zu "
                   "pixels", path, w, h, LC_MAX_SIDE, (size_t)LC_MAX_PIXELS);
        return NULL;
    }
    lc_image *img = lc_image_new(w, h, err);
    if (img)
        memcpy(img->px, px, 3 * (size_t)w * (size_t)h * sizeof *px);
    stbi_image_free(px);
    if (img && lc_image_nonfinite(img)) {
        error_fail(err, LC_EARG, "path", "'%s' has %zu NaN or infinite channels", path,
                   lc_image_nonfinite(img));
        lc_image_free(img);
        return NULL;
    }
    return img;
}
