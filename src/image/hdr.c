/* hdr.c: Radiance .hdr (RGBE) images, read by lancer itself: every count of
** the header and of the run-length code is checked against what it may say. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "base/mem.h"
#include "image.h"

/* stb_image's reader, which this one replaced, looped for ever on a run of
** length 0 at the end of a file. This one reads the same files to the same
** bits: the first scanline says whether the file is run-length coded (only
** widths 8..32767 may be), as stb decided; a later scanline without the
** 2,2 marker is read flat, as Radiance's own reader does. Old-style runs
** (a 1,1,1 pixel repeating the one before) are read as pixels, as stb did. */
#define HDR_LINE 1024
#define RLE_MIN 8
#define RLE_MAX 32767

typedef struct {
    FILE       *fp;
    const char *path;
    lc_error   *err;
    int         w, h;
    int         row;           /* the scanline being read, from 0 */
} hdr_reader;

/* Fails naming the file: "cannot read 'PATH': " and what is wrong. */
static lc_status bad(hdr_reader *r, const char *fmt, ...)
{
    char what[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return error_fail(r->err, LC_EARG, "path", "cannot read '%s': %s", r->path, what);
}

/* One header line without its '\n', cut at HDR_LINE - 1 bytes (the rest is
** skipped); -1 at the end of the file before any byte. */
static int read_line(FILE *fp, char line[HDR_LINE])
{
    int c, n = 0;
    while ((c = getc(fp)) != EOF && c != '\n')
        if (n < HDR_LINE - 1)
            line[n++] = (char)c;
    line[n] = 0;
    return c == EOF && n == 0 ? -1 : n;
}

/* A decimal count in 1..LC_MAX_SIDE at *s, advancing past it; 0 if none. */
static long read_count(const char **s)
{
    const char *p = *s;
    long v = 0;
    if (*p < '0' || *p > '9')
        return 0;
    for (; *p >= '0' && *p <= '9'; p++)
        if ((v = 10 * v + (*p - '0')) > LC_MAX_SIDE)
            v = LC_MAX_SIDE + 1L;       /* too large, and it stays so */
    *s = p;
    return v;
}

/* "-Y height +X width", the one orientation stb and most writers use:
** top to bottom, left to right. */
static lc_status read_resolution(hdr_reader *r, const char *line)
{
    const char *s = line;
    long h = 0, w = 0;
    if (strncmp(s, "-Y ", 3) == 0) {
        s += 3;
        while (*s == ' ')
            s++;
        h = read_count(&s);
        while (*s == ' ')
            s++;
        if (h && strncmp(s, "+X ", 3) == 0) {
            s += 3;
            while (*s == ' ')
                s++;
            w = read_count(&s);
        }
        while (*s == ' ' || *s == '\t' || *s == '\r')
            s++;
    }
    if (!h || !w || *s)
        return bad(r, "the resolution line '%.60s' is not '-Y height +X width' with "
                   "sizes of 1 or more (lancer reads top-to-bottom images only)", line);
    if (w > LC_MAX_SIDE || h > LC_MAX_SIDE)
        return bad(r, "%.60s is more than lancer's %d pixels a side", line, LC_MAX_SIDE);
    if ((size_t)w * (size_t)h > LC_MAX_PIXELS)
        return bad(r, "%ldx%ld is more than lancer's %zu pixels", w, h, LC_MAX_PIXELS);
    r->w = (int)w;
    r->h = (int)h;
    return LC_OK;
}

/* The header: the magic line, lines up to an empty one (FORMAT= among
** them), then the resolution. */
static lc_status read_header(hdr_reader *r)
{
    char line[HDR_LINE];
    if (read_line(r->fp, line) < 0 ||
        (strcmp(line, "#?RADIANCE") != 0 && strcmp(line, "#?RGBE") != 0))
        return error_fail(r->err, LC_EARG, "path", "'%s' is not a Radiance .hdr image "
                          "(its first line is not #?RADIANCE or #?RGBE)", r->path);
    int rgbe = 0, n;
    char format[64] = "";
    while ((n = read_line(r->fp, line)) > 0)
        if (strncmp(line, "FORMAT=", 7) == 0) {
            rgbe = strcmp(line + 7, "32-bit_rle_rgbe") == 0;
            snprintf(format, sizeof format, "%.60s", line + 7);
        }
    if (n < 0)
        return bad(r, "the header has no end (an empty line) before the end of the "
                   "file");
    if (!rgbe && format[0])
        return bad(r, "its FORMAT is '%s', lancer reads 32-bit_rle_rgbe only", format);
    if (!rgbe)
        return bad(r, "the header has no FORMAT=32-bit_rle_rgbe line");
    if (read_line(r->fp, line) < 0)
        return bad(r, "no resolution line after the header");
    return read_resolution(r, line);
}

/* A file too short for its size is refused before the pixels' memory is
** asked for: a 50-byte file saying 16384x16384 would otherwise take 3 GB
** first. A coded scanline is at least its marker and, per channel, a run of
** at most 127 (2 bytes) per 127 pixels; a flat one 4 bytes a pixel. */
static lc_status check_length(hdr_reader *r)
{
    long at = ftell(r->fp);
    if (at < 0 || fseek(r->fp, 0, SEEK_END) != 0)
        return LC_OK;                     /* not seekable: the reads check */
    long end = ftell(r->fp);
    if (end < 0 || fseek(r->fp, at, SEEK_SET) != 0)
        return error_fail(r->err, LC_EIO, "path", "cannot read '%s': %s", r->path,
                          strerror(errno));
    unsigned long long w = (unsigned long long)r->w, row = 4 * w;
    if (w >= RLE_MIN && w <= RLE_MAX)
        row = 4 + 8 * ((w + 126) / 127);
    unsigned long long need = row * (unsigned long long)r->h;
    if ((unsigned long long)(end - at) < need)
        return bad(r, "a %dx%d image needs at least %llu bytes of pixels, the file has "
                   "%ld", r->w, r->h, need, end - at);
    return LC_OK;
}

static lc_status ends_early(hdr_reader *r)
{
    return bad(r, "the data ends in scanline %d of %d", r->row + 1, r->h);
}

/* One channel k of a coded scanline into rgbe[4 * x + k]. */
static lc_status read_channel(hdr_reader *r, unsigned char *rgbe, int k)
{
    unsigned char buf[128];
    for (int x = 0; x < r->w;) {
        int c = getc(r->fp);
        if (c == EOF)
            return ends_early(r);
        int run = c > 128, n = run ? c - 128 : c;
        /* A count of 0 never advances (the loop stb_image never left); a
        ** count of 128 is 128 literal bytes, as Radiance reads it. */
        if (n == 0 || n > r->w - x)
            return bad(r, "scanline %d: %s of length %d%s (channel %d, at pixel %d of "
                       "%d)",
                       r->row + 1, run || n == 0 ? "run" : "literal", n,
                       n ? " past the scanline's end" : "", k + 1, x + 1, r->w);
        if (run) {
            int v = getc(r->fp);
            if (v == EOF)
                return ends_early(r);
            memset(buf, v, (size_t)n);
        } else if (fread(buf, 1, (size_t)n, r->fp) != (size_t)n) {
            return ends_early(r);
        }
        for (int i = 0; i < n; i++, x++)
            rgbe[4 * x + k] = buf[i];
    }
    return LC_OK;
}

/* The scanline's RGBE quadruples into rgbe: coded after a 2,2 marker
** (when `coded`, the file's first scanline having one), else flat. */
static lc_status read_scanline(hdr_reader *r, unsigned char *rgbe, int *coded)
{
    size_t w = (size_t)r->w;
    if (fread(rgbe, 1, 4, r->fp) != 4)
        return ends_early(r);
    int marked = r->w >= RLE_MIN && r->w <= RLE_MAX && rgbe[0] == 2 && rgbe[1] == 2 &&
                 !(rgbe[2] & 0x80);
    if (r->row == 0)
        *coded = marked;
    if (!*coded || !marked)
        return fread(rgbe + 4, 4, w - 1, r->fp) == w - 1 ? LC_OK : ends_early(r);
    int len = rgbe[2] << 8 | rgbe[3];
    if (len != r->w)
        return bad(r, "scanline %d says %d pixels, the image is %d wide", r->row + 1,
                   len, r->w);
    lc_status st = LC_OK;
    for (int k = 0; k < 4 && st == LC_OK; k++)
        st = read_channel(r, rgbe, k);
    return st;
}

/* As stb_image converts, to the bit: m * 2^(e - 136), 0 when e is 0. Every
** value is finite (at most 255 * 2^119). */
static void to_float(const unsigned char *rgbe, float *dst, int w)
{
    for (int x = 0; x < w; x++, rgbe += 4, dst += 3) {
        if (rgbe[3] == 0) {
            dst[0] = dst[1] = dst[2] = 0;
            continue;
        }
        float f = (float)ldexp(1.0f, rgbe[3] - (int)(128 + 8));
        dst[0] = rgbe[0] * f;
        dst[1] = rgbe[1] * f;
        dst[2] = rgbe[2] * f;
    }
}

static lc_image *read_pixels(hdr_reader *r)
{
    lc_image *img = lc_image_new(r->w, r->h, r->err);
    unsigned char *rgbe = img ? mem_alloc(4 * (size_t)r->w) : NULL;
    if (!img || !rgbe) {
        if (img)
            error_fail(r->err, LC_ENOMEM, NULL, "cannot read '%s': out of memory",
                       r->path);
        else if (r->err) {
            /* lc_image_new's sentence (the cap it met, when one did), with
            ** the file's name before it. */
            char why[sizeof r->err->msg];
            memcpy(why, r->err->msg, sizeof why);
            error_fail(r->err, r->err->code, NULL, "cannot read '%s': %s", r->path, why);
        }
        lc_image_free(img);
        mem_free(rgbe);
        return NULL;
    }
    int coded = 0;
    for (r->row = 0; r->row < r->h; r->row++) {
        if (read_scanline(r, rgbe, &coded)) {
            lc_image_free(img);
            mem_free(rgbe);
            return NULL;
        }
        to_float(rgbe, img->px + 3 * (size_t)r->w * (size_t)r->row, r->w);
    }
    mem_free(rgbe);
    return img;
}

lc_image *lc_image_load_hdr(const char *path, lc_error *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    hdr_reader r = {fp, path, err, 0, 0, 0};
    lc_image *img = NULL;
    if (read_header(&r) == LC_OK && check_length(&r) == LC_OK)
        img = read_pixels(&r);
    fclose(fp);
    if (img)
        error_ok(err);
    return img;
}
