/* image.c: linear floating-point RGB images. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "image.h"
#include "base/mem.h"

lc_image *lc_image_new(int width, int height, lc_error *err)
{
    if (width < 1 || height < 1 || width > LC_MAX_SIDE || height > LC_MAX_SIDE) {
        error_fail(err, LC_EARG, width < 1 || width > LC_MAX_SIDE ? "width" : "height",
                "image size must be 1..%d per side, got %dx%d", LC_MAX_SIDE, width, height);
        return NULL;
    }
    size_t n = (size_t)width * (size_t)height;      /* both <= 2^20: no overflow */
    if (n > LC_MAX_PIXELS) {
        error_fail(err, LC_EARG, "width", "image of %dx%d exceeds %zu pixels",
                width, height, LC_MAX_PIXELS);
        return NULL;
    }
    lc_image *img = mem_alloc(sizeof *img);
    float *px = mem_calloc(n * 3, sizeof *px);
    if (!img || !px) {
        mem_free(img);
        mem_free(px);
        error_fail(err, LC_ENOMEM, NULL, "out of memory for a %dx%d image", width, height);
        return NULL;
    }
    img->width = width;
    img->height = height;
    img->px = px;
    img->alpha = NULL;
    img->ranks = NULL;
    for (int k = 0; k < LC_AOVS; k++)
        img->aov[k] = NULL;
    img->win.x0 = img->win.y0 = 0;
    img->win.frame_width = width;
    img->win.frame_height = height;
    error_ok(err);
    return img;
}

lc_image *lc_image_copy(const lc_image *img, lc_error *err)
{
    lc_image *c = lc_image_new(img->width, img->height, err);
    if (!c)
        return NULL;
    size_t n = (size_t)img->width * (size_t)img->height;
    memcpy(c->px, img->px, 3 * n * sizeof *c->px);
    c->win = img->win;
    if (img->alpha) {
        if (lc_image_add_alpha(c, err)) {
            lc_image_free(c);
            return NULL;
        }
        memcpy(c->alpha, img->alpha, n * sizeof *c->alpha);
    }
    return c;
}

void lc_image_free(lc_image *img)
{
    if (!img)
        return;
    for (int k = 0; k < LC_AOVS; k++)
        lc_image_free(img->aov[k]);
    mem_free(img->px);
    mem_free(img->alpha);
    mem_free(img->ranks);
    mem_free(img);
}

lc_status lc_image_add_alpha(lc_image *img, lc_error *err)
{
    size_t n = (size_t)img->width * img->height;
    if (img->alpha) {
        error_ok(err);
        return LC_OK;
    }
    img->alpha = mem_alloc(n * sizeof *img->alpha);
    if (!img->alpha)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory for the alpha of a %dx%d "
                          "image", img->width, img->height);
    for (size_t i = 0; i < n; i++)
        img->alpha[i] = 1;
    error_ok(err);
    return LC_OK;
}

int lc_image_has_alpha(const lc_image *img) { return img->alpha != NULL; }

float lc_image_get_alpha(const lc_image *img, int x, int y)
{
    return img->alpha ? img->alpha[(size_t)y * img->width + x] : 1;
}

void lc_image_set_alpha(lc_image *img, int x, int y, float a)
{
    if (img->alpha)
        img->alpha[(size_t)y * img->width + x] = a;
}

lc_window lc_image_window(const lc_image *img) { return img->win; }

lc_status lc_image_set_window(lc_image *img, lc_window w, lc_error *err)
{
    if (w.frame_width < 1 || w.frame_height < 1 || w.frame_width > LC_MAX_SIDE ||
        w.frame_height > LC_MAX_SIDE ||
        (size_t)w.frame_width * (size_t)w.frame_height > LC_MAX_PIXELS)
        return error_fail(err, LC_EARG, "window", "a frame of %dx%d is outside 1..%d a "
                          "side and %zu pixels", w.frame_width, w.frame_height,
                          LC_MAX_SIDE, LC_MAX_PIXELS);
    if (w.x0 < 0 || w.y0 < 0 || w.x0 > w.frame_width - img->width ||
        w.y0 > w.frame_height - img->height)
        return error_fail(err, LC_EARG, "window", "a %dx%d image at (%d, %d) does not "
                          "fit in a %dx%d frame", img->width, img->height, w.x0, w.y0,
                          w.frame_width, w.frame_height);
    img->win = w;
    error_ok(err);
    return LC_OK;
}

int lc_image_width(const lc_image *img) { return img->width; }
int lc_image_height(const lc_image *img) { return img->height; }

lc_color lc_image_get(const lc_image *img, int x, int y)
{
    const float *p = img->px + 3 * ((size_t)y * img->width + x);
    lc_color c = {p[0], p[1], p[2]};
    return c;
}

void lc_image_set(lc_image *img, int x, int y, lc_color c)
{
    float *p = img->px + 3 * ((size_t)y * img->width + x);
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
}

/* The sRGB transfer curve, from linear [0, 1]. */
static double srgb(double v)
{
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
}

static double srgb_inverse(double e)
{
    return e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4);
}

/* threshold[k]: the linear value from which sRGB output rounds to k + 1.
** Counting the thresholds below v (from a table indexed by v * 4096, a step
** or two) replaces one pow() per channel, which dominated saving an image;
** tests/c/test_image.c checks it against the direct formula. */
static double threshold[256];       /* threshold[255] = 2: past every input */
static uint8_t start[4097];         /* the code at v = i / 4096: where to look */
static pthread_once_t threshold_once = PTHREAD_ONCE_INIT;

static void threshold_init(void)
{
    for (int k = 0; k < 255; k++) {
        double v = srgb_inverse((k + 0.5) / 255);
        /* Settle on the exact boundary of the rounding below. */
        while (v > 0 && (int)(srgb(v) * 255 + 0.5) > k)
            v = nextafter(v, 0);
        while ((int)(srgb(v) * 255 + 0.5) <= k)
            v = nextafter(v, 1);
        threshold[k] = v;
    }
    threshold[255] = 2;
    int k = 0;
    for (int i = 0; i <= 4096; i++) {
        while (k < 255 && threshold[k] <= i / 4096.0)
            k++;
        start[i] = (uint8_t)k;
    }
}

/* lc_encode_channel once the tables are made. */
static inline uint8_t encode8(float linear, lc_encoding enc)
{
    double v = linear;
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 255;
    if (enc == LC_ENCODE_LINEAR)
        return (uint8_t)(v * 255 + 0.5);
    int k = start[(int)(v * 4096)];  /* the answer is the count of thresholds <= v */
    while (threshold[k] <= v)
        k++;
    return (uint8_t)k;
}

/* Clamped to [0, 1] (NaN reads as 0), encoded, rounded to nearest. */
uint8_t lc_encode_channel(float linear, lc_encoding enc)
{
    pthread_once(&threshold_once, threshold_init);
    return encode8(linear, enc);
}

void image_encode8(const float *linear, size_t n, lc_encoding enc, uint8_t *out)
{
    pthread_once(&threshold_once, threshold_init);
    for (size_t i = 0; i < n; i++)
        out[i] = encode8(linear[i], enc);
}

uint16_t image_encode16(float linear, lc_encoding enc)
{
    double v = linear;
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 65535;
    return (uint16_t)((enc == LC_ENCODE_LINEAR ? v : srgb(v)) * 65535 + 0.5);
}

lc_status lc_image_compare(const lc_image *a, const lc_image *b, double tol,
                           lc_image_diff *d, lc_error *err)
{
    if (a->width != b->width || a->height != b->height)
        return error_fail(err, LC_EARG, "image", "sizes differ: %dx%d and %dx%d", a->width,
                       a->height, b->width, b->height);
    size_t n = (size_t)a->width * a->height;
    double sum = 0, worst = 0;
    size_t ok = 0, wi = 0;
    for (size_t i = 0; i < n; i++) {
        int pixel_ok = 1;
        for (int k = 0; k < 3; k++) {
            double e = fabs((double)a->px[3 * i + k] - b->px[3 * i + k]);
            if (!(e <= worst) && !(e != e && worst != worst)) {   /* NaN is worst */
                worst = e;
                wi = i;
            }
            sum += e;
            if (!(e <= tol))
                pixel_ok = 0;
        }
        ok += pixel_ok;
    }
    d->mean_abs = sum / (3.0 * n);
    d->max_abs = worst;
    d->within = (double)ok / n;
    d->worst_x = (int)(wi % a->width);
    d->worst_y = (int)(wi / a->width);
    error_ok(err);
    return LC_OK;
}

size_t lc_image_nonfinite(const lc_image *img)
{
    size_t n = 3 * (size_t)img->width * img->height, bad = 0;
    for (size_t i = 0; i < n; i++)
        bad += !isfinite(img->px[i]);
    return bad;
}

/* pbrt-v4's MRSE offset: a black reference pixel weighs 1e4, not infinity. */
#define RELMSE_OFFSET 0.01

static lc_status same_size(const lc_image *a, const lc_image *b, const char *what,
                           lc_error *err)
{
    if (a->width != b->width || a->height != b->height)
        return error_fail(err, LC_EARG, "image", "%s sizes differ: %dx%d and %dx%d", what,
                       a->width, a->height, b->width, b->height);
    return LC_OK;
}

lc_status lc_image_error(const lc_image *img, const lc_image *ref,
                         lc_image_error_stats *out, lc_error *err)
{
    lc_status st = same_size(img, ref, "image and reference", err);
    if (st)
        return st;
    size_t n = 3 * (size_t)img->width * img->height;
    double se = 0, rel = 0, ae = 0, sum = 0;
    for (size_t i = 0; i < n; i++) {
        double r = ref->px[i], d = (double)img->px[i] - r;
        double q = fabs(r) + RELMSE_OFFSET;
        se += d * d;
        rel += d * d / (q * q);
        ae += fabs(d);
        sum += d;
    }
    out->mse = se / n;
    out->rmse = sqrt(out->mse);
    out->relmse = rel / n;
    out->mae = ae / n;
    out->bias = sum / n;
    error_ok(err);
    return LC_OK;
}

lc_status lc_image_add(lc_image *img, const lc_image *other, double weight, lc_error *err)
{
    if (!isfinite(weight))
        return error_fail(err, LC_EARG, "weight", "weight must be finite, got %g", weight);
    lc_status st = same_size(img, other, "image", err);
    if (st)
        return st;
    size_t n = 3 * (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        img->px[i] = (float)(img->px[i] + weight * other->px[i]);
    error_ok(err);
    return LC_OK;
}
