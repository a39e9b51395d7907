/* shade.h: the integrator: the colour a ray brings back. */
#ifndef LC_SHADE_H
#define LC_SHADE_H

#include "sample.h"
#include "scene.h"

/* explain's record of the rays one sample traces (NULL while rendering). */
typedef struct {
    lc_ray_record *r;
    double *before;          /* 3 per record: the pixel's sum before that ray */
    size_t n, cap;
    int failed;              /* out of memory: the rest is not recorded */
} ray_log;

typedef struct {
    const lc_scene *scene;
    ray_log *log;
    unsigned needs;            /* copy of c->needs, minus what options turn off */
    const unsigned char *plan; /* per material: the PLAN_* steps its shading takes */
    int      shadows;          /* trace shadow rays (the render's switch) */
    bvh_counts counts;          /* this thread's intersection tests */
    int      max_depth;
    int      cosine;
    double   cutoff;
    int      light_samples;    /* per emissive shape and hit; 0: toward its centre */
    int      cone_samples;     /* > 0: every glossy material's count */
    pixel_sampler ps;          /* the pixel being traced */
    uint64_t rays[LC_RAY_KINDS];   /* this thread's counts */
    int      parent;           /* explain: the record of the ray being shaded */
    double   w[3];             /* explain: that ray's weight in the pixel */
    uint64_t self_hits;
    uint64_t samples;          /* camera samples traced */
} tracer;

/* Radiance in double: the float colours of materials and lights are
** widened once, and sums never round per channel differently. */
typedef struct { double r, g, b; } radiance;

/* Radiance is capped here: pixels clamp to [0, 1] when written, and the cap
** keeps a huge light or coefficient from making an infinity, whose product
** with a zero would be a NaN pixel. */
#define RADIANCE_CAP 1e100

/* The radiance camera sample `index` of `count` of the pixel brings back. */
radiance trace_ray(tracer *t, const lc_ray *r, uint32_t index, uint32_t count);

/* explain: appends a record of ray r (its parent and kind); -1 if it cannot. */
int log_ray(tracer *t, int parent, lc_ray_kind kind, const lc_ray *r);

#endif
