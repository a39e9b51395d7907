/* shade.h: the integrator: the colour a ray brings back. */
#ifndef LC_SHADE_H
#define LC_SHADE_H

#include "scene.h"

typedef struct {
    const lc_scene *scene;
    unsigned needs;            /* copy of c->needs, minus what options turn off */
    const unsigned char *plan; /* per material: the PLAN_* steps its shading takes */
    int      shadows;          /* trace shadow rays (the render's switch) */
    lc_counts counts;          /* this thread's intersection tests */
    int      max_depth;
    int      cosine;
    double   cutoff;
    uint64_t rays[LC_RAY_KINDS];   /* this thread's counts */
    uint64_t self_hits;
} tracer;

/* Radiance in double: the float colours of materials and lights are
** widened once, and sums never round per channel differently. */
typedef struct { double r, g, b; } radiance;

/* Radiance is capped here: pixels clamp to [0, 1] when written, and the cap
** keeps a huge light or coefficient from making an infinity, whose product
** with a zero would be a NaN pixel. */
#define RADIANCE_CAP 1e100

radiance trace_ray(tracer *t, const lc_ray *r, int depth);

#endif
