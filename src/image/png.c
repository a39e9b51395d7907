/* png.c: writing PNG through libpng (8 or 16 bits, RGB or RGBA, a part of a
** frame with its place), atomically, and reading any PNG back. */
#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/error.h"
#include "image.h"
#include "raster.h"
#include "base/save.h"
#include "base/mem.h"

/* libpng reports errors by longjmp; the message is kept for lc_error. */
typedef struct {
    char msg[200];
} png_failure;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_failure *f = png_get_error_ptr(png);
    snprintf(f->msg, sizeof f->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;                 /* the core never prints */
}

static int little_endian(void)
{
    uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 1;
}

/* The tEXt keyword that holds the frame's size, "W H", in a part of a frame. */
#define FRAME_KEY "lancer:frame"

static int whole(const lc_window *w, int width, int height)
{
    return w->x0 == 0 && w->y0 == 0 && w->frame_width == width &&
           w->frame_height == height;
}

/* Writes rows to an open file; returns 0 or fills err. */
static lc_status write_png(FILE *fp, const raster_format *f, raster_row_fn fill,
                           const void *ud, const char *path, lc_error *err)
{
    png_failure fail = {""};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &fail,
                                              on_png_error, on_png_warning);
    if (!png)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory writing '%s'", path);
    png_infop info = png_create_info_struct(png);
    unsigned char *volatile row = NULL;
    if (!info || setjmp(png_jmpbuf(png))) {
        int why = ferror(fp) ? errno : 0;       /* a failed fwrite: say why */
        png_destroy_write_struct(&png, info ? &info : NULL);
        mem_free(row);
        return error_fail(err, LC_EIO, "path", "cannot write '%s': %s", path,
                          why ? strerror(why) : fail.msg[0] ? fail.msg : "out of memory");
    }
    png_set_user_limits(png, LC_MAX_SIDE, LC_MAX_SIDE);
    png_init_io(png, fp);
    /* zlib level 3 with the Sub filter: about a third of the default's time
    ** for files about a third larger (measured on B1, 1280x720). */
    png_set_compression_level(png, 3);
    png_set_filter(png, 0, PNG_FILTER_SUB);
    png_set_IHDR(png, info, (png_uint_32)f->width, (png_uint_32)f->height, 8 * f->bytes,
                 f->channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (f->enc == LC_ENCODE_SRGB)
        png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    else
        png_set_gAMA(png, info, 1.0);   /* as POV-Ray and Tachyon do for linear output */
    char size[32];
    png_text text;
    if (!whole(&f->win, f->width, f->height)) {
        /* A part of a frame: where it goes (oFFs, a registered chunk) and the
        ** frame's size, so lancer --merge needs nothing beside the file. */
        png_set_oFFs(png, info, f->win.x0, f->win.y0, PNG_OFFSET_PIXEL);
        snprintf(size, sizeof size, "%d %d", f->win.frame_width, f->win.frame_height);
        memset(&text, 0, sizeof text);
        text.compression = PNG_TEXT_COMPRESSION_NONE;
        text.key = (char *)FRAME_KEY;
        text.text = size;
        png_set_text(png, info, &text, 1);
    }
    png_write_info(png, info);
    if (f->bytes == 2 && little_endian())
        png_set_swap(png);              /* PNG samples are big-endian */
    row = mem_alloc((size_t)f->width * f->channels * f->bytes);
    if (!row)
        png_error(png, "out of memory");
    for (int y = 0; y < f->height; y++) {
        fill(ud, y, row);
        png_write_row(png, row);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    mem_free(row);
    return LC_OK;
}

/* The image goes to a temporary file beside the target, is flushed to disk,
** and only then renamed over it (save.c): a crash or a full disk never leaves
** a truncated PNG, and an existing file survives any failure. */
lc_status png_write_raster(const raster_format *f, raster_row_fn row, const void *ud,
                           const char *path, lc_error *err)
{
    save_file sf;
    if (save_begin(&sf, path, err))
        return err ? err->code : LC_EIO;
    if (write_png(sf.fp, f, row, ud, path, err)) {
        save_abort(&sf);
        return err ? err->code : LC_EIO;
    }
    return save_commit(&sf, err);
}

/* Refuses a header whose size passes lancer's caps, naming them (before any
** pixel memory is asked for: "out of memory" would not say why). */
static lc_status check_size(png_uint_32 w, png_uint_32 h, const char *path, lc_error *err)
{
    if (w == 0 || h == 0)
        return error_fail(err, LC_EIO, "path", "cannot read '%s': a %lux%lu image",
                          path, (unsigned long)w, (unsigned long)h);
    if (w > LC_MAX_SIDE || h > LC_MAX_SIDE)
        return error_fail(err, LC_EARG, "path", "cannot read '%s': %lux%lu is more than "
                          "lancer's %d pixels a side", path, (unsigned long)w,
                          (unsigned long)h, LC_MAX_SIDE);
    if ((size_t)w * h > LC_MAX_PIXELS)
        return error_fail(err, LC_EARG, "path", "cannot read '%s': %lux%lu is more than "
                          "lancer's %zu pixels", path, (unsigned long)w, (unsigned long)h,
                          LC_MAX_PIXELS);
    return LC_OK;
}

/* No chunk but image data may be larger: libpng reads an ancillary chunk
** (text, ICC profile, palette) whole into memory, as long as its header
** says, before checking it against anything. */
#define PNG_MAX_CHUNK ((uint32_t)16 << 20)

static uint32_t be32(const unsigned char *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}

/* Walks the chunks' headers (seeking past their data) before libpng reads
** any: a chunk longer than the file or, but for IDAT, than PNG_MAX_CHUNK is
** refused, naming it (a 64-byte file whose zTXt claimed 2 GB had libpng
** allocate and fill 2 GB), as is a chunk type that is not 4 letters.
** Leaves fp at the start. */
static lc_status check_chunks(FILE *fp, const char *path, lc_error *err)
{
    static const unsigned char sig[8] = {137, 'P', 'N', 'G', '\r', '\n', 26, '\n'};
    unsigned char b[8];
    lc_status st = LC_OK;
    if (fseek(fp, 0, SEEK_END) != 0)
        return LC_OK;                        /* not seekable: libpng alone checks */
    long size = ftell(fp);
    rewind(fp);
    if (fread(b, 1, 8, fp) != 8 || memcmp(b, sig, 8) != 0) {
        st = error_fail(err, LC_EIO, "path", "cannot read '%s': not a PNG file", path);
        goto done;
    }
    for (long at = 8; at + 8 <= size;) {
        if (fread(b, 1, 8, fp) != 8)
            break;
        uint32_t len = be32(b);
        char type[5] = {(char)b[4], (char)b[5], (char)b[6], (char)b[7], 0};
        /* Letters only (PNG 5.4); libpng's two readers disagreed on a bad
        ** type after the image data (one stops before it). */
        for (int k = 0; k < 4; k++)
            if (!((type[k] >= 'A' && type[k] <= 'Z') || (type[k] >= 'a' && type[k] <= 'z'))) {
                st = error_fail(err, LC_EIO, "path", "cannot read '%s': the chunk at byte "
                                "%ld has no valid type (bytes %02x %02x %02x %02x)", path, at,
                                b[4], b[5], b[6], b[7]);
                goto done;
            }
        if ((long long)len + 12 > (long long)size - at) {
            st = error_fail(err, LC_EIO, "path", "cannot read '%s': chunk '%s' at byte %ld "
                            "claims %lu bytes, past the end of the file", path, type, at,
                            (unsigned long)len);
            goto done;
        }
        if (len > PNG_MAX_CHUNK && memcmp(type, "IDAT", 4) != 0) {
            st = error_fail(err, LC_EIO, "path", "cannot read '%s': chunk '%s' of %lu bytes "
                            "is past lancer's cap of %lu bytes for one chunk", path, type,
                            (unsigned long)len, (unsigned long)PNG_MAX_CHUNK);
            goto done;
        }
        if (memcmp(type, "IEND", 4) == 0)
            break;
        at += 12 + (long)len;
        if (fseek(fp, at, SEEK_SET) != 0)
            break;
    }
done:
    rewind(fp);
    return st;
}

/* The sRGB curve's inverse (IEC 61966-2-1), exactly, in double. */
static double srgb_to_linear(double v)
{
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

/* Reads every pixel with libpng's low-level reader: palettes and low bit
** depths expanded, interlaced passes merged, grey made RGB. decode = 0: as
** stored, every sample v / (2^depth - 1), whatever the file says of its
** encoding (data, or linear files without a gAMA chunk), alpha and tRNS
** dropped. decode = 1: linear light, each sample through the curve the
** file declares (the sRGB curve for an sRGB chunk, v^(1/g) for a gAMA of g
** alone; when it says nothing, libpng's rule: sRGB at 8 bits and below,
** linear at 16), computed in double for
** every stored value: libpng's simplified reader goes through 8 bits and
** approximates sRGB by a power of 2.2, up to 4/255 off in the darks. Then
** composited onto black where the file is transparent (alpha or tRNS). */
/* Sets libpng's transforms so that rows read as 8- or 16-bit RGB, with
** alpha only when decoding (decode: the sRGB encoding, which premultiplies
** it); then the file's transfer curve: 1 for sRGB (the default of 8-bit
** files), else 0 with its gamma in *gamma. */
static int read_as_rgb(png_structp png, png_infop info, int decode, double *gamma)
{
    int depth = png_get_bit_depth(png, info), type = png_get_color_type(png, info);
    if (type == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    if (depth < 8)
        png_set_expand(png);
    int trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    if (trns)
        png_set_tRNS_to_alpha(png);
    if (!decode && (trns || (type & PNG_COLOR_MASK_ALPHA)))
        png_set_strip_alpha(png);
    int declared = png_get_valid(png, info, PNG_INFO_sRGB) ||
                   (png_get_gAMA(png, info, gamma) && *gamma > 0);
    if (!declared)                     /* libpng's rule: 8 bits sRGB, 16 linear */
        *gamma = depth == 16 ? 1 : 0;
    int srgb = png_get_valid(png, info, PNG_INFO_sRGB) || !(*gamma > 0);
    if (depth == 16)
        png_set_swap(png);             /* PNG is big-endian; read native order */
    png_set_interlace_handling(png);   /* Adam7: every pass lands in place */
    png_read_update_info(png, info);
    return srgb;
}

/* The rows as read (ch channels of `bytes` bytes, alpha last) into img's
** linear RGB through curve, premultiplied by alpha when there is one. */
static void store_rows(lc_image *img, const png_bytep *rows, int ch, int bytes,
                       const float *curve)
{
    unsigned max = bytes == 2 ? 65535 : 255;
    size_t w = (size_t)img->width;
    for (size_t y = 0; y < (size_t)img->height; y++) {
        float *dst = img->px + y * w * 3;
        const uint16_t *r16 = (const uint16_t *)(const void *)rows[y];
        const unsigned char *r8 = rows[y];
        for (size_t x = 0; x < w; x++) {
            size_t at = x * (size_t)ch;
            double a = 1;
            if (ch == 4)
                a = (bytes == 2 ? r16[at + 3] : r8[at + 3]) / (double)max;
            for (size_t c = 0; c < 3; c++) {
                unsigned v = bytes == 2 ? r16[at + c] : r8[at + c];
                dst[3 * x + c] = ch == 4 ? (float)(curve[v] * a) : curve[v];
            }
        }
    }
}

static lc_image *read_png(const char *path, int decode, lc_error *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    if (check_chunks(fp, path, err)) {
        fclose(fp);
        return NULL;
    }
    png_failure fail = {""};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &fail, on_png_error,
                                             on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    lc_image *volatile img = NULL;
    unsigned char *volatile pixels = NULL;
    png_bytep *volatile rows = NULL;
    float *volatile curve = NULL;
    lc_status volatile refused = LC_OK;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(png ? &png : NULL, info ? &info : NULL, NULL);
        fclose(fp);
        mem_free(rows);
        mem_free(pixels);
        mem_free(curve);
        lc_image_free(img);
        if (!refused)
            error_fail(err, LC_EIO, "path", "cannot read '%s': %s", path,
                       fail.msg[0] ? fail.msg : "out of memory");
        return NULL;
    }
    png_set_user_limits(png, LC_MAX_SIDE, LC_MAX_SIDE);
    png_init_io(png, fp);
    png_read_info(png, info);
    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if ((refused = check_size(w, h, path, err)) != LC_OK)
        png_error(png, "refused");
    double gamma = 0;
    int srgb = read_as_rgb(png, info, decode, &gamma);
    int bytes = png_get_bit_depth(png, info) == 16 ? 2 : 1;
    int ch = png_get_channels(png, info);        /* 3, or 4 with alpha */
    size_t rowbytes = png_get_rowbytes(png, info);
    img = lc_image_new((int)w, (int)h, err);
    if (!img) {
        refused = LC_ENOMEM;
        png_error(png, "out of memory");
    }
    unsigned max = bytes == 2 ? 65535 : 255;
    pixels = mem_alloc(rowbytes * h);
    rows = mem_alloc(h * sizeof *rows);
    curve = mem_alloc(((size_t)max + 1) * sizeof *curve);
    if (!pixels || !rows || !curve)
        png_error(png, "out of memory");
    for (unsigned v = 0; v <= max; v++) {
        double x = v / (double)max;
        curve[v] = (float)(!decode ? x : srgb ? srgb_to_linear(x) : pow(x, 1 / gamma));
    }
    for (png_uint_32 y = 0; y < h; y++)
        rows[y] = pixels + y * rowbytes;
    png_read_image(png, rows);
    /* No png_read_end: what follows the image data (text, a bad CRC there)
    ** is not read, so that a file reads in both encodings or in neither. */
    store_rows(img, (const png_bytep *)rows, ch, bytes, curve);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    mem_free(rows);
    mem_free(pixels);
    mem_free(curve);
    error_ok(err);
    return img;
}

lc_image *lc_image_load_png(const char *path, lc_encoding enc, lc_error *err)
{
    return read_png(path, enc == LC_ENCODE_SRGB, err);
}

/* A part as lancer wrote it, samples untouched (16-bit ones in the machine's
** order): for lancer --merge. */
lc_status png_read_raster(const char *path, raster_format *f, unsigned char **data,
                          lc_error *err)
{
    *data = NULL;
    memset(f, 0, sizeof *f);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path,
                          strerror(errno));
    png_failure fail = {""};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &fail, on_png_error,
                                             on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    unsigned char *volatile pixels = NULL;
    lc_status volatile refused = LC_OK;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(png ? &png : NULL, info ? &info : NULL, NULL);
        fclose(fp);
        mem_free(pixels);
        if (!refused)
            return error_fail(err, LC_EIO, "path", "cannot read '%s': %s", path,
                              fail.msg[0] ? fail.msg : "out of memory");
        return refused;
    }
    png_set_user_limits(png, LC_MAX_SIDE, LC_MAX_SIDE);
    png_init_io(png, fp);
    png_read_info(png, info);
    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    int depth = png_get_bit_depth(png, info), type = png_get_color_type(png, info);
    if ((refused = check_size(w, h, path, err)) != LC_OK)
        png_error(png, "refused");
    if ((depth != 8 && depth != 16) ||
        (type != PNG_COLOR_TYPE_RGB && type != PNG_COLOR_TYPE_RGB_ALPHA) ||
        png_get_interlace_type(png, info) != PNG_INTERLACE_NONE) {
        refused = error_fail(err, LC_EARG, "path", "cannot merge '%s': a %d-bit PNG of "
                             "colour type %d%s; lancer's parts are 8 or 16-bit RGB or "
                             "RGBA, not interlaced", path, depth, type,
                             png_get_interlace_type(png, info) ? ", interlaced" : "");
        png_error(png, "refused");
    }
    f->kind = RASTER_PNG;
    f->width = (int)w;
    f->height = (int)h;
    f->channels = type == PNG_COLOR_TYPE_RGB_ALPHA ? 4 : 3;
    f->bytes = depth / 8;
    f->enc = png_get_valid(png, info, PNG_INFO_sRGB) || !png_get_valid(png, info,
             PNG_INFO_gAMA) ? LC_ENCODE_SRGB : LC_ENCODE_LINEAR;
    f->win.frame_width = f->width;
    f->win.frame_height = f->height;
    png_int_32 ox, oy;
    int unit;
    png_textp texts;
    int ntext = png_get_text(png, info, &texts, NULL);
    for (int i = 0; i < ntext; i++) {
        int fw, fh;
        char end;
        if (strcmp(texts[i].key, FRAME_KEY) != 0)
            continue;
        if (sscanf(texts[i].text, "%d %d%c", &fw, &fh, &end) != 2 ||
            !png_get_oFFs(png, info, &ox, &oy, &unit) || unit != PNG_OFFSET_PIXEL ||
            ox < 0 || oy < 0 || fw < 1 || fh < 1 || fw > LC_MAX_SIDE || fh > LC_MAX_SIDE ||
            ox > fw - f->width || oy > fh - f->height) {
            refused = error_fail(err, LC_EARG, "path", "cannot merge '%s': its place in "
                                 "the frame (oFFs and '" FRAME_KEY "' = '%.40s') is not "
                                 "a %dx%d part of a frame", path, texts[i].text, f->width,
                                 f->height);
            png_error(png, "refused");
        }
        f->win.x0 = (int)ox;
        f->win.y0 = (int)oy;
        f->win.frame_width = fw;
        f->win.frame_height = fh;
    }
    if (depth == 16 && little_endian())
        png_set_swap(png);
    png_read_update_info(png, info);
    size_t rowbytes = (size_t)f->width * f->channels * f->bytes;
    pixels = mem_alloc(rowbytes * h);
    if (!pixels) {
        refused = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' (%lux%lu)",
                             path, (unsigned long)w, (unsigned long)h);
        png_error(png, "refused");
    }
    for (png_uint_32 y = 0; y < h; y++)
        png_read_row(png, pixels + y * rowbytes, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    *data = pixels;
    error_ok(err);
    return LC_OK;
}
