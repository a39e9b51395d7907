/* raster.h: samples as an image file stores them, written row by row and read
** back whole, so parts of a frame are assembled without touching a value. */
#ifndef LC_RASTER_H
#define LC_RASTER_H

#include "lancer.h"

typedef enum { RASTER_PNG, RASTER_EXR } raster_kind;

/* What a file holds, apart from its samples. */
typedef struct {
    raster_kind kind;
    int width, height;       /* of the samples stored */
    int channels;            /* 3 (R, G, B) or 4 (R, G, B, A), interleaved in that order */
    int bytes;               /* per sample: 1, 2 (16-bit PNG, half) or 4 (float) */
    lc_window win;           /* where they lie in the frame */
    lc_encoding enc;         /* PNG: the transfer curve it says */
    lc_exr_compression compression;  /* EXR */
    int tile;                /* EXR: 0 scanlines, else the tiles' side */
    const struct raster_channel *named;   /* EXR: NULL, or `channels` of these (layers),
                                          ** interleaved in this order, each of its
                                          ** own bytes; `bytes` is then unused */
} raster_format;

/* One channel of a layered EXR: its name, and 2 (half) or 4 (float). */
typedef struct raster_channel { char name[40]; int bytes; } raster_channel;

/* The format a file name's extension names (.png, .exr, any case); -1, with
** err saying why, for any other. */
int raster_kind_of(const char *path, lc_error *err);

/* Fills row y (0-based, from the top) of width * channels samples, each
** `bytes` long in the machine's byte order (a half as its 16 bits). */
typedef void (*raster_row_fn)(const void *ud, int y, unsigned char *out);

/* Saved atomically (save.c); errors name the path. */
lc_status png_write_raster(const raster_format *f, raster_row_fn row, const void *ud,
                           const char *path, lc_error *err);
lc_status exr_write_raster(const raster_format *f, raster_row_fn row, const void *ud,
                           const char *path, lc_error *err);

/* Reads a file lancer could have written (PNG: 8 or 16-bit RGB or RGBA, not
** interlaced; EXR: one part of R, G, B [, A] of one type) into *data, malloc'd
** by mem_alloc, rows of width * channels * bytes; a file of another layout is
** refused, saying what it holds. */
lc_status png_read_raster(const char *path, raster_format *f, unsigned char **data,
                          lc_error *err);
lc_status exr_read_raster(const char *path, raster_format *f, unsigned char **data,
                          lc_error *err);

/* Float to half, rounded to nearest even, past +-65504 clamped there (NaN
** stays NaN); and back, exactly. */
uint16_t raster_half(float f);
float    raster_float(uint16_t h);

#endif
