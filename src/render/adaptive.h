/* adaptive.h: adaptive sampling's per-pixel sums, error estimate and passes. */
#ifndef LC_ADAPTIVE_H
#define LC_ADAPTIVE_H

#include <stdint.h>
#include "lancer.h"

/* A render with a noise target runs in passes: every pixel still active
** takes samples up to the pass's target (min_samples, then doubling up to
** samples); between passes each pixel's error is estimated, and a pixel
** stays active while its error or a neighbour's is over the target (the
** dilation catches edges whose first samples all missed a small feature). */
typedef struct {
    int       width, height;
    double   *sum;        /* 6 per pixel: all samples' r, g, b; odd-numbered ones' */
    uint32_t *n;          /* samples taken per pixel */
    unsigned char *active;
    uint32_t  target;     /* this pass: active pixels sample up to here */
    uint32_t  first;      /* the first pass that checks the error: min_samples,
                          ** even; a progressive render's passes before it
                          ** double from 1 with every pixel active */
    uint32_t  max;        /* the render's samples */
    double    noise;
    int       pass;
} adaptive;

/* Over the width x height pixels traced (the frame, or a region and its margin). */
lc_status adaptive_init(adaptive *a, const lc_render_options *o, int width, int height,
                        lc_error *err);
void      adaptive_free(adaptive *a);
/* After a pass: marks the pixels to go on and sets the next target; 0 when
** none is left. */
int       adaptive_next(adaptive *a);
/* The passes a render takes when no pixel converges early: the first included. */
int       adaptive_passes(const adaptive *a);
/* The estimated relative error of pixel p (Dammertz et al. 2010, as Cycles). */
double    adaptive_error(const adaptive *a, size_t p);
/* Pixels whose estimated error is under the target now. */
uint64_t  adaptive_converged(const adaptive *a);

#endif
