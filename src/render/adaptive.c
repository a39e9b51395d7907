/* adaptive.c: adaptive sampling's per-pixel sums, error estimate and passes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "adaptive.h"
#include "base/error.h"
#include "base/mem.h"

lc_status adaptive_init(adaptive *a, const lc_render_options *o, int width, int height,
                        lc_error *err)
{
    memset(a, 0, sizeof *a);
    size_t np = (size_t)width * (size_t)height;
    a->width = width;
    a->height = height;
    a->sum = mem_calloc(np, 6 * sizeof *a->sum);
    a->n = mem_calloc(np, sizeof *a->n);
    a->active = mem_alloc(np);
    if (!a->sum || !a->n || !a->active) {
        adaptive_free(a);
        return error_fail(err, LC_ENOMEM, NULL, "out of memory for adaptive sampling of "
                       "%zu pixels", np);
    }
    memset(a->active, 1, np);
    a->max = (uint32_t)o->samples;
    a->noise = o->noise;
    /* Even, so the odd-numbered half is half of them. */
    a->target = (uint32_t)o->min_samples + (o->min_samples & 1);
    if (a->target > a->max)
        a->target = a->max;
    a->first = a->target;
    if (o->progressive)
        a->target = 1;          /* 1, 2, 4, ... up to first, every pixel active */
    return LC_OK;
}

void adaptive_free(adaptive *a)
{
    mem_free(a->sum);
    mem_free(a->n);
    mem_free(a->active);
    memset(a, 0, sizeof *a);
}

/* The mean of all n samples against the mean of the odd-numbered half,
** relative to the square root of the brightness (what the eye sees of
** noise), plus 0.01 so black pixels converge. It stays honest with the
** stratified Sobol' points, where the sample variance would be too
** pessimistic: the odd half of a Sobol' prefix is itself stratified. */
double adaptive_error(const adaptive *a, size_t p)
{
    const double *s = a->sum + 6 * p;
    uint32_t n = a->n[p];
    if (n < 2)
        return HUGE_VAL;
    double e = 0, lum = 0;
    for (int c = 0; c < 3; c++) {
        double mean = s[c] / n, half = s[3 + c] / (n / 2);
        e += fabs(mean - half);
        lum += mean;
    }
    return (e / 3) / (sqrt(fmax(lum / 3, 0)) + 0.01);
}

uint64_t adaptive_converged(const adaptive *a)
{
    uint64_t c = 0;
    size_t np = (size_t)a->width * (size_t)a->height;
    for (size_t p = 0; p < np; p++)
        c += adaptive_error(a, p) < a->noise;
    return c;
}

int adaptive_passes(const adaptive *a)
{
    adaptive b = *a;
    int n = 1;
    while (b.target < b.first || b.target < b.max) {   /* as adaptive_next steps it */
        b.target = b.target < b.first ? (b.target > b.first / 2 ? b.first : 2 * b.target)
                 : b.target > b.max / 2 ? b.max : 2 * b.target;
        n++;
    }
    return n;
}

int adaptive_next(adaptive *a)
{
    if (a->target < a->first) {
        /* A progressive render's first passes: they stop nowhere, so that
        ** at `first` every pixel holds the sums a plain render's first pass
        ** leaves, and the passes after it are the plain render's. */
        a->target = a->target > a->first / 2 ? a->first : 2 * a->target;
        return 1;
    }
    if (a->target >= a->max)
        return 0;
    int w = a->width, h = a->height, left = 0;
    unsigned char *over = a->active;    /* reused: 1 = over the target */
    for (size_t p = 0; p < (size_t)w * h; p++)
        over[p] = adaptive_error(a, p) >= a->noise;
    /* Dilation by one pixel, in two separable passes with bit 1 as scratch. */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            int on = (over[p] & 1) || (x > 0 && (over[p - 1] & 1)) ||
                     (x + 1 < w && (over[p + 1] & 1));
            over[p] |= (unsigned char)(on << 1);
        }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            over[p] = (over[p] >> 1) & 1;
        }
    for (int x = 0; x < w; x++)
        for (int y = 0; y < h; y++) {
            size_t p = (size_t)y * w + x;
            int on = (over[p] & 1) || (y > 0 && (over[p - w] & 1)) ||
                     (y + 1 < h && (over[p + w] & 1));
            over[p] |= (unsigned char)(on << 1);
        }
    for (size_t p = 0; p < (size_t)w * h; p++) {
        over[p] = (over[p] >> 1) & 1;
        left += over[p];
    }
    a->target = a->target > a->max / 2 ? a->max : 2 * a->target;
    a->pass++;
    return left > 0;
}
