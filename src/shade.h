/* shade.h: the integrator: the colour a ray brings back. */
#ifndef LC_SHADE_H
#define LC_SHADE_H

#include "scene.h"

typedef struct {
    const lc_scene *scene;
    unsigned needs;            /* copy of c->needs, minus what options turn off */
    int      max_depth;
    int      cosine;
    double   cutoff;
    uint64_t rays[LC_RAY_KINDS];   /* this thread's counts */
    uint64_t self_hits;
} tracer;

lc_color trace_ray(tracer *t, const lc_ray *r, int depth);

#endif
