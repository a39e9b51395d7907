/* exr.c: OpenEXR through its C library (OpenEXRCore): half or float R, G, B
** [, A] written by scanlines or tiles, atomically, and read back. */
#define _XOPEN_SOURCE 700              /* pread, pwrite */
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <openexr.h>
#include "base/error.h"
#include "image.h"
#include "base/mem.h"
#include "raster.h"
#include "base/save.h"

/* ---- Half floats -------------------------------------------------------------- */

uint16_t raster_half(float f)
{
    uint32_t x;
    memcpy(&x, &f, 4);
    uint16_t sign = (uint16_t)((x >> 16) & 0x8000);
    uint32_t ax = x & 0x7fffffffu;
    if (ax > 0x7f800000u)                              /* NaN: a quiet one */
        return (uint16_t)(sign | 0x7e00 | ((ax >> 13) & 0x3ff));
    if (ax > 0x477fe000u)                              /* past 65504, infinities too */
        return (uint16_t)(sign | 0x7bff);
    if (ax >= 0x38800000u) {                           /* normal: 2^-14 and up */
        uint32_t h = ((((ax >> 23) - 112) << 10) | ((ax >> 13) & 0x3ff));
        uint32_t rem = ax & 0x1fff;
        if (rem > 0x1000 || (rem == 0x1000 && (h & 1)))
            h++;                                       /* a carry moves the exponent */
        return (uint16_t)(sign | h);
    }
    if (ax <= 0x33000000u)                             /* 2^-25 and under: to zero */
        return sign;
    uint32_t mant = (ax & 0x7fffff) | 0x800000, shift = 126 - (ax >> 23);
    uint32_t h = mant >> shift, rem = mant & ((1u << shift) - 1), half = 1u << (shift - 1);
    if (rem > half || (rem == half && (h & 1)))
        h++;
    return (uint16_t)(sign | h);
}

float raster_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h & 0x8000) << 16, e = (h >> 10) & 0x1f, m = h & 0x3ff, x;
    if (e == 0) {
        float f = (float)m * 5.9604644775390625e-8f;  /* m 2^-24, exact */
        return sign ? -f : f;
    }
    x = e == 31 ? sign | 0x7f800000u | (m << 13) : sign | ((e + 112) << 23) | (m << 13);
    float f;
    memcpy(&f, &x, 4);
    return f;
}

/* ---- The library's input and output ------------------------------------------ */

/* What the library's callbacks share: the file, and the first error it said. */
typedef struct {
    int  fd;
    int  io_errno;            /* a failed read or write */
    char msg[200];
} exr_io;

static void on_error(exr_const_context_t ctx, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    exr_get_user_data(ctx, &ud);
    exr_io *io = ud;
    if (io && !io->msg[0])
        snprintf(io->msg, sizeof io->msg, "%s", msg ? msg : exr_get_default_error_message(code));
}

static int64_t write_fn(exr_const_context_t ctx, void *ud, const void *buf, uint64_t sz,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    const char *p = buf;
    uint64_t done = 0;
    (void)ctx;
    (void)error_cb;
    while (done < sz) {
        ssize_t n = pwrite(io->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            io->io_errno = n < 0 ? errno : EIO;
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)sz;
}

static int64_t read_fn(exr_const_context_t ctx, void *ud, void *buf, uint64_t sz,
                       uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    char *p = buf;
    uint64_t done = 0;
    (void)ctx;
    (void)error_cb;
    while (done < sz) {
        ssize_t n = pread(io->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            io->io_errno = errno;
            return -1;
        }
        if (n == 0)
            break;                                     /* the end: a short read */
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t size_fn(exr_const_context_t ctx, void *ud)
{
    exr_io *io = ud;
    struct stat st;
    (void)ctx;
    return fstat(io->fd, &st) == 0 ? (int64_t)st.st_size : -1;
}

/* Fills err for a failed library call: its own sentence when it gave one. */
static lc_status exr_fail(lc_error *err, const exr_io *io, exr_result_t rv, const char *verb,
                          const char *path)
{
    if (io->io_errno)
        return error_fail(err, LC_EIO, "path", "cannot %s '%s': %s", verb, path,
                          strerror(io->io_errno));
    if (rv == EXR_ERR_OUT_OF_MEMORY)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory to %s '%s'", verb, path);
    return error_fail(err, LC_EIO, "path", "cannot %s '%s': %s", verb, path,
                      io->msg[0] ? io->msg : exr_get_default_error_message(rv));
}

static const exr_compression_t compressions[] = {
    EXR_COMPRESSION_ZIP, EXR_COMPRESSION_PIZ, EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_RLE,
    EXR_COMPRESSION_NONE};

/* The file's channels, in the order the library lists them (by name), and
** where each sits among the interleaved R, G, B, A samples of a row. */
static int channel_slot(const char *name)
{
    static const char *const names[] = {"R", "G", "B", "A"};
    for (int k = 0; k < 4; k++)
        if (strcmp(name, names[k]) == 0)
            return k;
    return -1;
}

/* ---- Writing ------------------------------------------------------------------ */

/* The bytes of one pixel's samples, interleaved. */
static int pixel_bytes(const raster_format *f)
{
    int n = 0;
    for (int k = 0; f->named && k < f->channels; k++)
        n += f->named[k].bytes;
    return f->named ? n : f->channels * f->bytes;
}

/* Where the channel `name` sits in a pixel (bytes from its start), and its size. */
static int channel_place(const raster_format *f, const char *name, int *bytes)
{
    if (!f->named) {
        *bytes = f->bytes;
        return channel_slot(name) * f->bytes;
    }
    int at = 0;
    for (int k = 0; k < f->channels; k++) {
        if (strcmp(f->named[k].name, name) == 0) {
            *bytes = f->named[k].bytes;
            return at;
        }
        at += f->named[k].bytes;
    }
    *bytes = 0;
    return -1;                                     /* not reached: the names are ours */
}

/* Points every channel of the pipeline at its samples in `band`, rows of
** `stride` bytes starting at column x0. */
static void encode_channels(exr_encode_pipeline_t *enc, const raster_format *f,
                            const unsigned char *band, size_t stride, int x0)
{
    int px = pixel_bytes(f);
    for (int c = 0; c < enc->channel_count; c++) {
        exr_coding_channel_info_t *ch = &enc->channels[c];
        int bytes, at = channel_place(f, ch->channel_name, &bytes);
        ch->user_bytes_per_element = (int16_t)bytes;
        ch->user_data_type = ch->data_type;
        ch->user_pixel_stride = px;
        ch->user_line_stride = (int32_t)stride;
        ch->encode_from_ptr = band + (size_t)x0 * px + (size_t)at;
    }
}

static int by_name(const void *a, const void *b)
{
    return strcmp(((const raster_channel *)a)->name, ((const raster_channel *)b)->name);
}

/* Bug: OpenEXRCore 3.1.5 keeps ZIP output that is exactly as long as its
** input (it tests >, not >=; fixed upstream in OpenEXR PR #2307), and every
** reader takes a chunk that size as stored uncompressed: one 4x4 half tile
** read back as noise. The library's compressor runs, then a chunk that did
** not shrink is stored raw, as the format means. */
typedef struct {
    exr_result_t (*compress)(exr_encode_pipeline_t *enc);
} compress_hook;

static exr_result_t compress_strictly(exr_encode_pipeline_t *enc)
{
    const compress_hook *h = enc->encoding_user_data;
    exr_result_t rv = h->compress(enc);
    if (rv == EXR_ERR_SUCCESS && enc->compressed_bytes >= enc->packed_bytes &&
        enc->compressed_buffer != enc->packed_buffer &&
        enc->compressed_alloc_size >= enc->packed_bytes) {
        memcpy(enc->compressed_buffer, enc->packed_buffer, enc->packed_bytes);
        enc->compressed_bytes = enc->packed_bytes;
    }
    return rv;
}

/* Encodes and writes the chunk `ci` from band. */
static exr_result_t write_chunk(exr_context_t ctx, exr_encode_pipeline_t *enc, int *started,
                                const exr_chunk_info_t *ci, const raster_format *f,
                                const unsigned char *band, size_t stride, int x0)
{
    exr_result_t rv = *started ? exr_encoding_update(ctx, 0, ci, enc)
                               : exr_encoding_initialize(ctx, 0, ci, enc);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    *started = 1;
    encode_channels(enc, f, band, stride, x0);
    rv = exr_encoding_choose_default_routines(ctx, 0, enc);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    compress_hook hook = {enc->compress_fn};
    if (enc->compress_fn) {
        enc->encoding_user_data = &hook;
        enc->compress_fn = compress_strictly;
    }
    return exr_encoding_run(ctx, 0, enc);
}

static lc_status write_exr(int fd, const raster_format *f, raster_row_fn fill,
                           const void *ud, const char *path, lc_error *err)
{
    exr_io io;
    memset(&io, 0, sizeof io);
    io.fd = fd;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_error;
    init.user_data = &io;
    init.write_fn = write_fn;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS)
        return exr_fail(err, &io, rv, "write", path);
    int part = 0;
    exr_pixel_type_t type = f->bytes == 2 ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
    /* The display window is the frame; the data window, the part of it held. */
    exr_attr_box2i_t display, data;
    exr_attr_v2f_t centre;
    memset(&display, 0, sizeof display);
    display.max.x = f->win.frame_width - 1;
    display.max.y = f->win.frame_height - 1;
    data.min.x = f->win.x0;
    data.min.y = f->win.y0;
    data.max.x = f->win.x0 + f->width - 1;
    data.max.y = f->win.y0 + f->height - 1;
    centre.x = centre.y = 0;
    static const char *const sorted[] = {"A", "B", "G", "R"};
    rv = exr_add_part(ctx, NULL, f->tile ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr(ctx, part, &display, &data, 1.0f, &centre, 1.0f,
                                          EXR_LINEORDER_INCREASING_Y,
                                          compressions[f->compression]);
    if (rv == EXR_ERR_SUCCESS && f->tile)
        rv = exr_set_tile_descriptor(ctx, part, (uint32_t)f->tile, (uint32_t)f->tile,
                                     EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
    if (f->named) {                /* the file lists them by name: added in that order */
        raster_channel *list = mem_alloc((size_t)f->channels * sizeof *list);
        if (!list)
            rv = EXR_ERR_OUT_OF_MEMORY;
        else
            memcpy(list, f->named, (size_t)f->channels * sizeof *list);
        if (list)
            qsort(list, (size_t)f->channels, sizeof *list, by_name);
        for (int k = 0; list && k < f->channels && rv == EXR_ERR_SUCCESS; k++)
            rv = exr_add_channel(ctx, part, list[k].name, list[k].bytes == 2 ?
                                 EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                                 EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
        mem_free(list);
    }
    for (int k = f->channels == 4 ? 0 : 1; !f->named && k < 4 && rv == EXR_ERR_SUCCESS; k++)
        rv = exr_add_channel(ctx, part, sorted[k], type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctx);
    int lines = f->tile;
    if (rv == EXR_ERR_SUCCESS && !f->tile)
        rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
    size_t stride = (size_t)f->width * pixel_bytes(f);
    unsigned char *band = rv == EXR_ERR_SUCCESS ? mem_alloc(stride * (size_t)lines) : NULL;
    if (rv == EXR_ERR_SUCCESS && !band)
        rv = EXR_ERR_OUT_OF_MEMORY;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < f->height && rv == EXR_ERR_SUCCESS; y += lines) {
        int n = f->height - y < lines ? f->height - y : lines;
        for (int i = 0; i < n; i++)
            fill(ud, y + i, band + (size_t)i * stride);
        exr_chunk_info_t ci;
        if (!f->tile) {
            rv = exr_write_scanline_chunk_info(ctx, part, f->win.y0 + y, &ci);
            if (rv == EXR_ERR_SUCCESS)
                rv = write_chunk(ctx, &enc, &started, &ci, f, band, stride, 0);
            continue;
        }
        for (int tx = 0; tx * f->tile < f->width && rv == EXR_ERR_SUCCESS; tx++) {
            rv = exr_write_tile_chunk_info(ctx, part, tx, y / f->tile, 0, 0, &ci);
            if (rv == EXR_ERR_SUCCESS)
                rv = write_chunk(ctx, &enc, &started, &ci, f, band, stride, tx * f->tile);
        }
    }
    if (started)
        exr_encoding_destroy(ctx, &enc);
    mem_free(band);
    exr_result_t fin = exr_finish(&ctx);      /* writes the chunk offsets */
    if (rv == EXR_ERR_SUCCESS)
        rv = fin;
    if (rv != EXR_ERR_SUCCESS)
        return exr_fail(err, &io, rv, "write", path);
    return LC_OK;
}

lc_status exr_write_raster(const raster_format *f, raster_row_fn row, const void *ud,
                           const char *path, lc_error *err)
{
    save_file sf;
    if (save_begin(&sf, path, err))
        return err ? err->code : LC_EIO;
    if (write_exr(fileno(sf.fp), f, row, ud, path, err)) {
        save_abort(&sf);
        return err ? err->code : LC_EIO;
    }
    return save_commit(&sf, err);
}

/* ---- Reading ------------------------------------------------------------------ */

/* An open file's first part, checked against lancer's caps. */
typedef struct {
    exr_io io;
    exr_context_t ctx;
    exr_storage_t storage;
    exr_attr_box2i_t data, display;
    int width, height;
    const exr_attr_chlist_t *channels;
    int tile_w, tile_h;       /* tiled: level 0's tiles */
    exr_compression_t compression;
} exr_file;

static void exr_close(exr_file *x)
{
    if (x->ctx)
        exr_finish(&x->ctx);
    if (x->io.fd >= 0)
        close(x->io.fd);
}

static lc_status exr_open(exr_file *x, const char *path, lc_error *err)
{
    memset(x, 0, sizeof *x);
    x->io.fd = open(path, O_RDONLY);
    if (x->io.fd < 0)
        return error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
    struct stat st;
    if (fstat(x->io.fd, &st) == 0 && !S_ISREG(st.st_mode)) {
        exr_close(x);
        return error_fail(err, LC_EIO, "path", "cannot read '%s': not a file", path);
    }
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_error;
    init.user_data = &x->io;
    init.read_fn = read_fn;
    init.size_fn = size_fn;
    /* Tiles past lancer's own largest are refused before a chunk is read: a
    ** header may claim any size, and a tile is decoded whole. */
    init.max_tile_width = LC_MAX_EXR_TILE;
    init.max_tile_height = LC_MAX_EXR_TILE;
    init.flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
    exr_result_t rv = exr_start_read(&x->ctx, path, &init);
    int parts = 0;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_count(x->ctx, &parts);
    if (rv == EXR_ERR_SUCCESS && parts < 1)
        rv = EXR_ERR_FILE_BAD_HEADER;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_storage(x->ctx, 0, &x->storage);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_data_window(x->ctx, 0, &x->data);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_display_window(x->ctx, 0, &x->display);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_channels(x->ctx, 0, &x->channels);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_compression(x->ctx, 0, &x->compression);
    if (rv != EXR_ERR_SUCCESS) {
        lc_status r = exr_fail(err, &x->io, rv, "read", path);
        exr_close(x);
        return r;
    }
    if (x->storage != EXR_STORAGE_SCANLINE && x->storage != EXR_STORAGE_TILED) {
        exr_close(x);
        return error_fail(err, LC_EARG, "path", "cannot read '%s': its first part holds "
                          "deep samples, which lancer does not read", path);
    }
    int64_t w = (int64_t)x->data.max.x - x->data.min.x + 1;
    int64_t h = (int64_t)x->data.max.y - x->data.min.y + 1;
    if (w < 1 || h < 1 || w > LC_MAX_SIDE || h > LC_MAX_SIDE || (size_t)w * h > LC_MAX_PIXELS) {
        exr_close(x);
        if (w < 1 || h < 1)
            return error_fail(err, LC_EIO, "path", "cannot read '%s': its data window is "
                              "empty", path);
        return error_fail(err, LC_EARG, "path", "cannot read '%s': %lldx%lld is more than "
                          "lancer's %d pixels a side or %zu pixels", path, (long long)w,
                          (long long)h, LC_MAX_SIDE, LC_MAX_PIXELS);
    }
    x->width = (int)w;
    x->height = (int)h;
    if (x->storage == EXR_STORAGE_TILED) {
        rv = exr_get_tile_sizes(x->ctx, 0, 0, 0, &x->tile_w, &x->tile_h);
        if (rv == EXR_ERR_SUCCESS && (x->tile_w < 1 || x->tile_h < 1))
            rv = EXR_ERR_BAD_CHUNK_LEADER;
        if (rv != EXR_ERR_SUCCESS) {
            lc_status r = exr_fail(err, &x->io, rv, "read", path);
            exr_close(x);
            return r;
        }
    }
    error_ok(err);
    return LC_OK;
}

/* Where the decoder puts channel c of a chunk: into out (rows of `stride`
** bytes, `pixel` bytes apart) at the chunk's place, or nowhere. */
typedef struct {
    unsigned char *base[4];   /* R, G, B, A: their first sample, or NULL */
    int    pixel[4];          /* bytes from one pixel to the next */
    size_t stride[4];         /* bytes from one row to the next */
    int    bytes;             /* per sample: 4 (float, converted) or the file's */
    int    convert;           /* decode to float */
    int    grey;              /* Y into R's place (copied to G and B after) */
} exr_target;

/* Bug: OpenEXRCore 3.1.5 picks its unpacking routine from the channels'
** count and types, and its routine for three halves writes through every
** channel's pointer, NULL or not (B, G and M: a NULL write); its routine
** for subsampled channels lost the rows of the others. lancer unpacks the
** decompressed chunk itself, for every layout: line after line, each
** channel's samples of that line in the file's order, little-endian, a
** subsampled channel only on the lines it samples. Only the channels
** given a place are written, as half (copied) or float (copied or from a
** half); the rest are stepped over. */
static exr_result_t unpack_chunk(exr_decode_pipeline_t *dec)
{
    const unsigned char *src = dec->unpacked_buffer;
    uint64_t left = dec->chunk.unpacked_size;
    if (!src && left)
        return EXR_ERR_CORRUPT_CHUNK;
    for (int y = 0; y < dec->chunk.height; y++) {
        int at = dec->chunk.start_y + y;
        for (int c = 0; c < dec->channel_count; c++) {
            const exr_coding_channel_info_t *ch = &dec->channels[c];
            if (ch->y_samples > 1 && at % ch->y_samples != 0)
                continue;
            uint64_t n = (uint64_t)ch->width * (uint64_t)ch->bytes_per_element;
            if (n > left)
                return EXR_ERR_CORRUPT_CHUNK;
            unsigned char *out = ch->decode_to_ptr;
            if (out)
                out += (size_t)y * (size_t)ch->user_line_stride;
            for (int x = 0; out && x < ch->width; x++) {
                const unsigned char *p = src + (size_t)x * ch->bytes_per_element;
                unsigned char *o = out + (size_t)x * ch->user_pixel_stride;
                if (ch->bytes_per_element == 2) {
                    uint16_t h = (uint16_t)(p[0] | p[1] << 8);
                    float f = raster_float(h);
                    if (ch->user_data_type == EXR_PIXEL_FLOAT)
                        memcpy(o, &f, 4);
                    else
                        memcpy(o, &h, 2);
                } else {
                    uint32_t v = (uint32_t)p[0] | (uint32_t)p[1] << 8 |
                                 (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
                    memcpy(o, &v, 4);
                }
            }
            src += n;
            left -= n;
        }
    }
    return EXR_ERR_SUCCESS;
}

static exr_result_t read_chunk(exr_file *x, exr_decode_pipeline_t *dec, int *started,
                               const exr_chunk_info_t *ci, const exr_target *t, int cx,
                               int cy)
{
    exr_result_t rv = *started ? exr_decoding_update(x->ctx, 0, ci, dec)
                               : exr_decoding_initialize(x->ctx, 0, ci, dec);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    *started = 1;
    if (ci->width < 1 || ci->height < 1 || cx < 0 || cy < 0 ||
        cx > x->width - ci->width || cy > x->height - ci->height)
        return EXR_ERR_BAD_CHUNK_LEADER;        /* a chunk outside the data window */
    for (int c = 0; c < dec->channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec->channels[c];
        int k = channel_slot(ch->channel_name);
        if (k < 0 && t->grey && strcmp(ch->channel_name, "Y") == 0)
            k = 0;
        ch->decode_to_ptr = NULL;
        if (k < 0 || !t->base[k] || ch->height != ci->height || ch->width != ci->width ||
            (ch->bytes_per_element != 2 && ch->data_type != EXR_PIXEL_FLOAT))
            continue;                              /* not kept: stepped over */
        ch->user_bytes_per_element = (int16_t)t->bytes;
        ch->user_data_type = t->convert ? EXR_PIXEL_FLOAT : ch->data_type;
        ch->user_pixel_stride = t->pixel[k];
        ch->user_line_stride = (int32_t)t->stride[k];
        ch->decode_to_ptr = t->base[k] + (size_t)cy * t->stride[k] +
                            (size_t)cx * t->pixel[k];
    }
    rv = exr_decoding_choose_default_routines(x->ctx, 0, dec);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    /* None chosen: every channel read straight into its place, uncompressed
    ** and as the file stores it; otherwise lancer's own (see unpack_chunk). */
    if (dec->unpack_and_convert_fn)
        dec->unpack_and_convert_fn = unpack_chunk;
    return exr_decoding_run(x->ctx, 0, dec);
}

/* Decodes every chunk of level 0 into t. */
static exr_result_t read_all(exr_file *x, const exr_target *t)
{
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    exr_result_t rv = EXR_ERR_SUCCESS;
    exr_chunk_info_t ci;
    if (x->storage == EXR_STORAGE_SCANLINE) {
        for (int64_t y = x->data.min.y; y <= x->data.max.y && rv == EXR_ERR_SUCCESS;) {
            rv = exr_read_scanline_chunk_info(x->ctx, 0, (int)y, &ci);
            if (rv != EXR_ERR_SUCCESS)
                break;
            if (ci.height < 1 || ci.start_y > y)
                rv = EXR_ERR_BAD_CHUNK_LEADER;
            else
                rv = read_chunk(x, &dec, &started, &ci, t, 0, ci.start_y - x->data.min.y);
            y = (int64_t)ci.start_y + ci.height;
        }
    } else {
        int nx = (x->width + x->tile_w - 1) / x->tile_w;
        int ny = (x->height + x->tile_h - 1) / x->tile_h;
        for (int ty = 0; ty < ny && rv == EXR_ERR_SUCCESS; ty++)
            for (int tx = 0; tx < nx && rv == EXR_ERR_SUCCESS; tx++) {
                rv = exr_read_tile_chunk_info(x->ctx, 0, tx, ty, 0, 0, &ci);
                if (rv == EXR_ERR_SUCCESS)
                    rv = read_chunk(x, &dec, &started, &ci, t, tx * x->tile_w,
                                    ty * x->tile_h);
            }
    }
    if (started)
        exr_decoding_destroy(x->ctx, &dec);
    return rv;
}

/* The data window inside the display window, as an lc_window; 0 if it is not. */
static int exr_window(const exr_file *x, lc_window *w)
{
    int64_t fw = (int64_t)x->display.max.x - x->display.min.x + 1;
    int64_t fh = (int64_t)x->display.max.y - x->display.min.y + 1;
    int64_t x0 = (int64_t)x->data.min.x - x->display.min.x;
    int64_t y0 = (int64_t)x->data.min.y - x->display.min.y;
    if (fw < 1 || fh < 1 || fw > LC_MAX_SIDE || fh > LC_MAX_SIDE ||
        (size_t)fw * fh > LC_MAX_PIXELS || x0 < 0 || y0 < 0 ||
        x0 + x->width > fw || y0 + x->height > fh)
        return 0;
    w->x0 = (int)x0;
    w->y0 = (int)y0;
    w->frame_width = (int)fw;
    w->frame_height = (int)fh;
    return 1;
}

lc_image *lc_image_load_exr(const char *path, lc_error *err)
{
    exr_file x;
    if (exr_open(&x, path, err))
        return NULL;
    int have[5] = {0, 0, 0, 0, 0};                 /* R, G, B, A, Y */
    for (int i = 0; i < x.channels->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &x.channels->entries[i];
        int k = channel_slot(e->name.str);
        if (k < 0 && strcmp(e->name.str, "Y") == 0)
            k = 4;
        if (k < 0)
            continue;                              /* other layers: not read */
        if (e->x_sampling != 1 || e->y_sampling != 1 || e->pixel_type == EXR_PIXEL_UINT) {
            /* The message first: the channel list is the library's, freed
            ** with the file. */
            error_fail(err, LC_EARG, "path", "cannot read '%s': channel %s is %s, lancer "
                       "reads half or float channels at every pixel", path, e->name.str,
                       e->pixel_type == EXR_PIXEL_UINT ? "unsigned int" : "subsampled");
            exr_close(&x);
            return NULL;
        }
        have[k] = 1;
    }
    int grey = have[4] && !have[0] && !have[1] && !have[2];
    lc_image *img = lc_image_new(x.width, x.height, err);
    if (img && have[3] && lc_image_add_alpha(img, err)) {
        lc_image_free(img);
        img = NULL;
    }
    if (!img) {
        exr_close(&x);
        return NULL;
    }
    exr_target t;
    memset(&t, 0, sizeof t);
    t.bytes = 4;
    t.convert = 1;
    t.grey = grey;
    for (int k = 0; k < 3; k++) {
        if (have[k] || (k == 0 && grey))
            t.base[k] = (unsigned char *)(img->px + k);
        t.pixel[k] = 12;
        t.stride[k] = (size_t)x.width * 12;
    }
    t.base[3] = (unsigned char *)img->alpha;        /* NULL without A */
    t.pixel[3] = 4;
    t.stride[3] = (size_t)x.width * 4;
    exr_result_t rv = read_all(&x, &t);
    if (rv != EXR_ERR_SUCCESS) {
        exr_fail(err, &x.io, rv, "read", path);
        exr_close(&x);
        lc_image_free(img);
        return NULL;
    }
    if (grey)
        for (size_t i = 0; i < (size_t)x.width * x.height; i++)
            img->px[3 * i + 1] = img->px[3 * i + 2] = img->px[3 * i];
    lc_window w;
    if (exr_window(&x, &w))
        img->win = w;
    exr_close(&x);
    error_ok(err);
    return img;
}

lc_status exr_read_raster(const char *path, raster_format *f, unsigned char **data,
                          lc_error *err)
{
    *data = NULL;
    memset(f, 0, sizeof *f);
    exr_file x;
    if (exr_open(&x, path, err))
        return err ? err->code : LC_EIO;
    const char *why = NULL;
    int n = x.channels->num_channels, type = -1;
    int c = 0;
    if (n != 3 && n != 4)
        why = "channels other than R, G, B [, A]";
    for (int i = 0; i < n && !why; i++) {
        const exr_attr_chlist_entry_t *e = &x.channels->entries[i];
        int k = channel_slot(e->name.str);
        if (k < 0 || (k == 3 && n != 4) || e->x_sampling != 1 || e->y_sampling != 1)
            why = "channels other than R, G, B [, A]";
        else if (e->pixel_type == EXR_PIXEL_UINT || (type >= 0 && (int)e->pixel_type != type))
            why = "channels that are not all half or all float";
        type = (int)e->pixel_type;
        c |= 1 << (k < 0 ? 0 : k);
    }
    if (!why && c != (n == 4 ? 15 : 7))
        why = "channels other than R, G, B [, A]";
    int comp = -1;
    for (int i = 0; i < 5; i++)
        if (compressions[i] == x.compression)
            comp = i;
    if (!why && comp < 0)
        why = "a compression lancer does not write";
    int32_t lx = 1, ly = 1;
    if (!why && x.storage == EXR_STORAGE_TILED &&
        (x.tile_w != x.tile_h || x.tile_w > LC_MAX_EXR_TILE ||
         exr_get_tile_levels(x.ctx, 0, &lx, &ly) != EXR_ERR_SUCCESS || lx != 1 || ly != 1))
        why = "tiles that are not square or have levels";
    if (!why && !exr_window(&x, &f->win))
        why = "a data window outside its display window";
    if (why) {
        exr_close(&x);
        return error_fail(err, LC_EARG, "path", "cannot merge '%s': it holds %s", path, why);
    }
    f->kind = RASTER_EXR;
    f->width = x.width;
    f->height = x.height;
    f->channels = n;
    f->bytes = type == EXR_PIXEL_HALF ? 2 : 4;
    f->enc = LC_ENCODE_LINEAR;
    f->compression = (lc_exr_compression)comp;
    f->tile = x.storage == EXR_STORAGE_TILED ? x.tile_w : 0;
    size_t pixel = (size_t)n * f->bytes;
    unsigned char *buf = mem_alloc(pixel * x.width * x.height);
    if (!buf) {
        exr_close(&x);
        return error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' (%dx%d)", path,
                          x.width, x.height);
    }
    exr_target t;
    memset(&t, 0, sizeof t);
    t.bytes = f->bytes;
    for (int k = 0; k < n; k++) {
        t.base[k] = buf + (size_t)k * f->bytes;
        t.pixel[k] = (int)pixel;
        t.stride[k] = pixel * x.width;
    }
    exr_result_t rv = read_all(&x, &t);
    if (rv != EXR_ERR_SUCCESS) {
        lc_status r = exr_fail(err, &x.io, rv, "read", path);
        exr_close(&x);
        mem_free(buf);
        return r;
    }
    exr_close(&x);
    *data = buf;
    error_ok(err);
    return LC_OK;
}
