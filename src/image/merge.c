/* merge.c: the parts of one frame, saved with their place in it, assembled
** into the whole frame sample for sample. */
#include <stdio.h>
#include <string.h>
#include "base/error.h"
#include "base/mem.h"
#include "raster.h"

/* "an 8-bit sRGB RGB PNG", "a half RGBA EXR (zip, 64x64 tiles)". */
static void describe(const raster_format *f, char *out, size_t n)
{
    static const char *const comp[] = {"zip", "piz", "zips", "rle", "no compression"};
    if (f->kind == RASTER_PNG) {
        snprintf(out, n, "%s %d-bit %s %s PNG", f->bytes == 1 ? "an" : "a", 8 * f->bytes,
                 f->enc == LC_ENCODE_SRGB ? "sRGB" : "linear", f->channels == 4 ? "RGBA" :
                 "RGB");
        return;
    }
    char tiles[32] = "scanlines";
    if (f->tile)
        snprintf(tiles, sizeof tiles, "%dx%d tiles", f->tile, f->tile);
    snprintf(out, n, "a %s %s EXR (%s, %s)", f->bytes == 2 ? "half" : "float",
             f->channels == 4 ? "RGBA" : "RGB", comp[f->compression], tiles);
}

static int same_format(const raster_format *a, const raster_format *b)
{
    return a->kind == b->kind && a->channels == b->channels && a->bytes == b->bytes &&
           a->enc == b->enc && a->compression == b->compression && a->tile == b->tile;
}

typedef struct {
    const unsigned char *data;
    size_t stride;
} frame_rows;

static void frame_row(const void *ud, int y, unsigned char *out)
{
    const frame_rows *fr = ud;
    memcpy(out, fr->data + (size_t)y * fr->stride, fr->stride);
}

lc_status lc_image_merge(const char *out, const char *const *parts, size_t n,
                         lc_error *err)
{
    int kind = raster_kind_of(out, err);
    if (kind < 0)
        return LC_EARG;
    if (n == 0)
        return error_fail(err, LC_EARG, "parts", "no parts to merge into '%s'", out);
    raster_format first, f;
    unsigned char *frame = NULL, *covered = NULL, *part = NULL;
    size_t stride = 0, pixel = 0, fw = 0, fh = 0;
    lc_status st = LC_OK;
    char a[96], b[96];
    for (size_t i = 0; i < n && st == LC_OK; i++) {
        const char *path = parts[i];
        int k = raster_kind_of(path, err);
        if (k < 0) {
            st = LC_EARG;
            break;
        }
        if (k != kind) {
            st = error_fail(err, LC_EARG, "parts", "cannot merge '%s' into '%s': both must "
                            "be %s", path, out, kind == RASTER_PNG ? "PNG" : "EXR");
            break;
        }
        st = k == RASTER_PNG ? png_read_raster(path, &f, &part, err)
                             : exr_read_raster(path, &f, &part, err);
        if (st)
            break;
        if (i == 0) {
            first = f;
            fw = (size_t)f.win.frame_width;
            fh = (size_t)f.win.frame_height;
            pixel = (size_t)f.channels * f.bytes;
            stride = fw * pixel;
            frame = mem_alloc(stride * fh);
            covered = mem_calloc((fw * fh + 7) / 8, 1);
            if (!frame || !covered) {
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory for a %zux%zu frame "
                                "merging into '%s'", fw, fh, out);
                break;
            }
        } else if (!same_format(&first, &f)) {
            describe(&f, a, sizeof a);
            describe(&first, b, sizeof b);
            st = error_fail(err, LC_EARG, "parts", "cannot merge '%s': it is %s, and '%s' "
                            "is %s", path, a, parts[0], b);
            break;
        } else if ((size_t)f.win.frame_width != fw || (size_t)f.win.frame_height != fh) {
            st = error_fail(err, LC_EARG, "parts", "cannot merge '%s': it is part of a %dx%d "
                            "frame, and '%s' of a %zux%zu one", path, f.win.frame_width,
                            f.win.frame_height, parts[0], fw, fh);
            break;
        }
        for (int y = 0; y < f.height && st == LC_OK; y++) {
            size_t fy = (size_t)f.win.y0 + y;
            for (int x = 0; x < f.width; x++) {
                size_t p = fy * fw + (size_t)f.win.x0 + x;
                if (covered[p / 8] & (1u << (p % 8))) {
                    st = error_fail(err, LC_EARG, "parts", "cannot merge '%s': it overlaps "
                                    "another part at pixel (%zu, %zu), counted from 0 at "
                                    "the top-left", path, p % fw, fy);
                    break;
                }
                covered[p / 8] |= (unsigned char)(1u << (p % 8));
            }
            memcpy(frame + fy * stride + (size_t)f.win.x0 * pixel,
                   part + (size_t)y * f.width * pixel, (size_t)f.width * pixel);
        }
        mem_free(part);
        part = NULL;
    }
    if (st == LC_OK) {
        size_t missing = 0, where = 0;
        for (size_t p = 0; p < fw * fh; p++)
            if (!(covered[p / 8] & (1u << (p % 8))) && missing++ == 0)
                where = p;
        if (missing)
            st = error_fail(err, LC_EARG, "parts", "cannot merge into '%s': the parts leave "
                            "%zu of the %zux%zu frame's pixels uncovered, the first at "
                            "(%zu, %zu) counted from 0 at the top-left", out, missing, fw,
                            fh, where % fw, where / fw);
    }
    if (st == LC_OK) {
        f = first;
        f.width = (int)fw;
        f.height = (int)fh;
        f.win.x0 = f.win.y0 = 0;
        frame_rows fr = {frame, stride};
        st = kind == RASTER_PNG ? png_write_raster(&f, frame_row, &fr, out, err)
                                : exr_write_raster(&f, frame_row, &fr, out, err);
    }
    mem_free(part);
    mem_free(frame);
    mem_free(covered);
    return st;
}
