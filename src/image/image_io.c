/* image_io.c: saving images in the format their file name asks for, with the
** options of each format. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include "base/error.h"
#include "image.h"
#include "raster.h"

lc_save_options lc_save_options_default(void)
{
    lc_save_options o;
    memset(&o, 0, sizeof o);
    o.encoding = LC_ENCODE_SRGB;
    o.depth = 8;
    o.exr_pixel = LC_EXR_HALF;
    o.exr_compression = LC_EXR_ZIP;
    o.aovs = 1;
    return o;
}

int raster_kind_of(const char *path, lc_error *err)
{
    if (!*path) {
        error_fail(err, LC_EARG, "path", "file name is empty");
        return -1;
    }
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (dot && slash && dot < slash)
        dot = NULL;                                 /* a dot in a folder's name */
    if (dot && strcasecmp(dot, ".png") == 0)
        return RASTER_PNG;
    if (dot && strcasecmp(dot, ".exr") == 0)
        return RASTER_EXR;
    if (!dot || dot[1] == '\0')
        error_fail(err, LC_EARG, "path", "cannot write '%s': no extension (lancer "
                   "writes .png and .exr)", path);
    else
        error_fail(err, LC_EARG, "path", "cannot write '%s': unknown extension '%s' "
                   "(lancer writes .png and .exr)", path, dot);
    return -1;
}

/* What the row function reads. */
typedef struct {
    const lc_image *img;
    const raster_format *f;
    int straight;             /* PNG with alpha: colours divided by it */
    int toned;                /* exposure or a tone curve: scale, then tone */
    double scale;             /* 2^exposure */
    lc_tone tone;
} source;

static void image_row(const void *ud, int y, unsigned char *out)
{
    const source *s = ud;
    const lc_image *img = s->img;
    const raster_format *f = s->f;
    const float *px = img->px + (size_t)y * img->width * 3;
    const float *al = img->alpha ? img->alpha + (size_t)y * img->width : NULL;
    int ch = f->channels;
    if (f->kind == RASTER_PNG && f->bytes == 1 && ch == 3 && !s->toned) {
        /* The common save, 8-bit RGB as rendered: one pass over the row,
        ** without the per-value choice of format below (which with the
        ** encoder's set-up took 200 instructions a pixel, callgrind). */
        image_encode8(px, (size_t)img->width * 3, f->enc, out);
        return;
    }
    for (int x = 0; x < img->width; x++) {
        float v[4] = {px[3 * x], px[3 * x + 1], px[3 * x + 2], al ? al[x] : 1};
        if (s->straight)
            for (int k = 0; k < 3; k++)
                v[k] = v[3] > 0 ? v[k] / v[3] : 0;
        if (s->toned)
            for (int k = 0; k < 3; k++)
                v[k] = (float)lc_tone_curve(v[k] * s->scale, s->tone);
        for (int k = 0; k < ch; k++) {
            size_t i = (size_t)x * ch + k;
            lc_encoding enc = k == 3 ? LC_ENCODE_LINEAR : f->enc;  /* alpha is linear */
            if (f->kind == RASTER_PNG && f->bytes == 1) {
                out[i] = lc_encode_channel(v[k], enc);
            } else if (f->kind == RASTER_PNG) {
                uint16_t q = image_encode16(v[k], enc);
                memcpy(out + 2 * i, &q, 2);
            } else if (f->bytes == 2) {
                uint16_t h = raster_half(v[k]);
                memcpy(out + 2 * i, &h, 2);
            } else {
                memcpy(out + 4 * i, &v[k], 4);
            }
        }
    }
}

static lc_status check_options(const lc_image *img, const lc_save_options *o,
                               const char *path, lc_error *err)
{
    if (o->encoding != LC_ENCODE_SRGB && o->encoding != LC_ENCODE_LINEAR)
        return error_fail(err, LC_EARG, "encoding", "unknown encoding %d", (int)o->encoding);
    if (o->depth != 8 && o->depth != 16)
        return error_fail(err, LC_EARG, "depth", "must be 8 or 16, got %d", o->depth);
    if (o->exr_pixel != LC_EXR_HALF && o->exr_pixel != LC_EXR_FLOAT)
        return error_fail(err, LC_EARG, "pixel", "unknown EXR pixel type %d",
                          (int)o->exr_pixel);
    if ((unsigned)o->exr_compression > LC_EXR_NONE)
        return error_fail(err, LC_EARG, "compression", "unknown EXR compression %d",
                          (int)o->exr_compression);
    if (o->exr_tile < 0 || o->exr_tile > LC_MAX_EXR_TILE)
        return error_fail(err, LC_EARG, "tile", "must be 0 (scanlines) or 1..%d, got %d",
                          LC_MAX_EXR_TILE, o->exr_tile);
    if (!(o->exposure >= -LC_MAX_EXPOSURE && o->exposure <= LC_MAX_EXPOSURE))
        return error_fail(err, LC_EARG, "exposure", "must be in [-%d, %d] stops, got %g",
                          LC_MAX_EXPOSURE, LC_MAX_EXPOSURE, o->exposure);
    if (o->tone != LC_TONE_CLAMP && o->tone != LC_TONE_FILMIC)
        return error_fail(err, LC_EARG, "tone", "unknown tone curve %d", (int)o->tone);
    if (o->alpha && !img->alpha)
        return error_fail(err, LC_EARG, "alpha", "cannot write '%s' with alpha: the image "
                          "has none (render it with alpha = true)", path);
    error_ok(err);
    return LC_OK;
}

/* ---- EXR with AOVs as layers ---------------------------------------------------- */

#define LAYERED_MAX 64     /* R, G, B, A, Z, 3 per AOV, 8 per id AOV's ranks */

/* Where a layered file's channel takes its values: every `stride`th float
** from base; toned ones are the beauty's colours. */
typedef struct {
    const float *base;
    int stride, toned;
} layer_source;

typedef struct {
    const lc_image *img;
    const raster_format *f;
    const layer_source *src;
    double scale;
    lc_tone tone;
} layered;

static void layered_row(const void *ud, int y, unsigned char *out)
{
    const layered *l = ud;
    const raster_format *f = l->f;
    size_t row = (size_t)y * l->img->width;
    for (int x = 0; x < l->img->width; x++)
        for (int k = 0; k < f->channels; k++) {
            const layer_source *s = &l->src[k];
            float v = s->base[(row + x) * s->stride];
            if (s->toned)
                v = (float)lc_tone_curve(v * l->scale, l->tone);
            if (f->named[k].bytes == 2) {
                uint16_t h = raster_half(v);
                memcpy(out, &h, 2);
            } else {
                memcpy(out, &v, 4);
            }
            out += f->named[k].bytes;
        }
}

static void add_channel(raster_channel *names, layer_source *src, int *n, const char *name,
                        int bytes, const float *base, int stride, int toned)
{
    snprintf(names[*n].name, sizeof names[*n].name, "%s", name);
    names[*n].bytes = bytes;
    src[*n].base = base;
    src[*n].stride = stride;
    src[*n].toned = toned;
    ++*n;
}

/* The beauty as R, G, B [, A], depth as Z, every other AOV as the layer of
** its name (`normal.R` ...); an id AOV's ranks as Cryptomatte lays them out,
** `object00.R` id and `object00.G` share of rank 0, B and A rank 1, then
** `object01` for ranks 2 and 3. Depth, position and ids in float. */
static lc_status save_layered(const lc_image *img, const char *path,
                              const lc_save_options *o, raster_format *f, lc_error *err)
{
    static const char rgb_names[4][2] = {"R", "G", "B", "A"};
    raster_channel names[LAYERED_MAX];
    layer_source src[LAYERED_MAX];
    int n = 0, bytes = f->bytes, toned = o->exposure != 0 || o->tone != LC_TONE_CLAMP;
    for (int k = 0; k < 3; k++)
        add_channel(names, src, &n, rgb_names[k], bytes, img->px + k, 3, toned);
    if (o->alpha)
        add_channel(names, src, &n, "A", bytes, img->alpha, 1, 0);
    for (int a = 0; a < LC_AOVS; a++) {
        const lc_image *l = img->aov[a];
        if (!l)
            continue;
        const char *name = lc_aov_name((lc_aov)a);
        int exact = a == LC_AOV_POSITION || a == LC_AOV_OBJECT || a == LC_AOV_MATERIAL;
        if (a == LC_AOV_DEPTH) {
            add_channel(names, src, &n, "Z", 4, l->px, 3, 0);
            continue;
        }
        char ch[40];
        for (int k = 0; k < 3; k++) {
            snprintf(ch, sizeof ch, "%s.%s", name, rgb_names[k]);
            add_channel(names, src, &n, ch, exact ? 4 : bytes, l->px + k, 3, 0);
        }
        for (int r = 0; l->ranks && r < 2 * LC_AOV_RANKS; r++) {
            snprintf(ch, sizeof ch, "%s%02d.%s", name, r / 4, rgb_names[r % 4]);
            add_channel(names, src, &n, ch, 4, l->ranks + r, 2 * LC_AOV_RANKS, 0);
        }
    }
    f->channels = n;
    f->named = names;
    layered l = {img, f, src, exp2(o->exposure), o->tone};
    return exr_write_raster(f, layered_row, &l, path, err);
}

lc_status lc_image_save_with(const lc_image *img, const char *path,
                             const lc_save_options *o, lc_error *err)
{
    int kind = raster_kind_of(path, err);
    if (kind < 0)
        return LC_EARG;
    if (check_options(img, o, path, err))
        return LC_EARG;
    raster_format f;
    memset(&f, 0, sizeof f);
    f.kind = (raster_kind)kind;
    f.width = img->width;
    f.height = img->height;
    f.channels = o->alpha ? 4 : 3;
    f.win = img->win;
    if (kind == RASTER_PNG) {
        f.bytes = o->depth / 8;
        f.enc = o->encoding;
    } else {
        f.bytes = o->exr_pixel == LC_EXR_HALF ? 2 : 4;
        f.enc = LC_ENCODE_LINEAR;
        f.compression = o->exr_compression;
        f.tile = o->exr_tile;
    }
    if (kind == RASTER_EXR && o->aovs && lc_image_aovs(img))
        return save_layered(img, path, o, &f, err);
    source s = {img, &f, kind == RASTER_PNG && o->alpha,
                o->exposure != 0 || o->tone != LC_TONE_CLAMP, exp2(o->exposure), o->tone};
    return kind == RASTER_PNG ? png_write_raster(&f, image_row, &s, path, err)
                              : exr_write_raster(&f, image_row, &s, path, err);
}

lc_status lc_image_save(const lc_image *img, const char *path, lc_encoding enc,
                        lc_error *err)
{
    lc_save_options o = lc_save_options_default();
    o.encoding = enc;
    return lc_image_save_with(img, path, &o, err);
}

lc_status lc_image_save_png(const lc_image *img, const char *path, lc_encoding enc,
                            lc_error *err)
{
    raster_format f;                    /* whatever the name: PNG is what was asked */
    memset(&f, 0, sizeof f);
    f.kind = RASTER_PNG;
    f.width = img->width;
    f.height = img->height;
    f.channels = 3;
    f.bytes = 1;
    f.win = img->win;
    f.enc = enc;
    source s = {img, &f, 0, 0, 1, LC_TONE_CLAMP};
    return png_write_raster(&f, image_row, &s, path, err);
}
