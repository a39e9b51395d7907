/* image_aov.c: an image's AOV layers: their names, which it holds, a copy
** of one, an object's or a material's matte. */
#include <string.h>
#include "base/error.h"
#include "image.h"

static const char *const aov_names[LC_AOVS] = {
    "depth", "normal", "albedo", "position", "object", "material", "direct",
    "reflection", "refraction", "indirect", "emission"};

const char *lc_aov_name(lc_aov a)
{
    return (unsigned)a < LC_AOVS ? aov_names[a] : NULL;
}

unsigned lc_image_aovs(const lc_image *img)
{
    unsigned bits = 0;
    for (int k = 0; k < LC_AOVS; k++)
        bits |= img->aov[k] ? 1u << k : 0;
    return bits;
}

static const lc_image *aov_of(const lc_image *img, lc_aov a, lc_error *err)
{
    if ((unsigned)a >= LC_AOVS) {
        error_fail(err, LC_EARG, "aov", "unknown AOV %d", (int)a);
        return NULL;
    }
    if (!img->aov[a])
        error_fail(err, LC_EARG, "aov", "the image has no %s AOV (render it with aovs = "
                   "{'%s', ...})", aov_names[a], aov_names[a]);
    return img->aov[a];
}

lc_image *lc_image_aov(const lc_image *img, lc_aov a, lc_error *err)
{
    const lc_image *src = aov_of(img, a, err);
    lc_image *out = src ? lc_image_new(src->width, src->height, err) : NULL;
    if (!out)
        return NULL;
    memcpy(out->px, src->px, (size_t)3 * src->width * src->height * sizeof *out->px);
    out->win = src->win;
    return out;
}

lc_image *lc_image_matte(const lc_image *img, lc_aov a, int id, lc_error *err)
{
    if (id < 1) {
        error_fail(err, LC_EARG, "id", "an id >= 1 expected, got %d", id);
        return NULL;
    }
    if (a != LC_AOV_OBJECT && a != LC_AOV_MATERIAL) {
        error_fail(err, LC_EARG, "aov", "a matte is of the object or material AOV, not %s",
                   (unsigned)a < LC_AOVS ? aov_names[a] : "?");
        return NULL;
    }
    const lc_image *src = aov_of(img, a, err);
    lc_image *out = src ? lc_image_new(src->width, src->height, err) : NULL;
    if (!out)
        return NULL;
    out->win = src->win;
    size_t n = (size_t)src->width * src->height;
    for (size_t i = 0; i < n; i++) {
        const float *rk = src->ranks + 2 * LC_AOV_RANKS * i;
        float c = 0;
        for (int r = 0; r < LC_AOV_RANKS; r++)
            if (rk[2 * r] == (float)id && id > 0)
                c = rk[2 * r + 1];
        out->px[3 * i] = out->px[3 * i + 1] = out->px[3 * i + 2] = c;
    }
    error_ok(err);
    return out;
}
