/* tracer.h: what one thread's integrators carry along the rays they trace. */
#ifndef LC_TRACER_H
#define LC_TRACER_H

#include "aov.h"
#include "explain.h"
#include "media/media.h"
#include "base/radiance.h"
#include "base/sample.h"
#include "scene/scene.h"

/* A branch a path put aside to trace later: at a dielectric it follows the
** heavier of reflection and refraction and keeps the other here. */
typedef struct {
    ray      r;
    radiance w;
    int      depth, watch, rec;
    uint32_t from, from_instance;
    media    md;
} branch;

/* Branches waiting at once, per tracer. Each comes from a split at its own
** depth along the path being traced, weighing at least cutoff: more than
** this many means 2^64 rays in the tree, never traced in a lifetime. */
#define BRANCH_MAX 64

/* In a tracer's needs beside the LC_NEED_* bits: AOVs are recorded, so the
** camera's paths take the recording variants of the integrators (their
** one test is the one glass and light that bounces already take). */
#define TRACE_AOV (1u << 30)

typedef struct {
    const lc_scene *scene;
    ray_log *log;              /* explain's record of the rays; NULL while rendering */
    unsigned needs;            /* copy of c->needs, minus what options turn off */
    const uint16_t *plan;   /* per material: the PLAN_* steps its shading takes */
    int      shadows;          /* trace shadow rays (the render's switch) */
    bvh_counts counts;         /* this thread's intersection tests */
    int      max_depth;
    int      cosine;
    double   cutoff;
    int      light_samples;    /* per emissive shape and hit; 0: toward its centre */
    int      cone_samples;     /* > 0: every glossy material's count */
    int      indirect;         /* > 0: paths (path.c), this many bounces */
    int      roulette, nee;    /* path.c: Russian roulette; lights sampled */
    int      ao_samples;       /* > 0: ambient occlusion probes per hit */
    double   ao_distance;
    pixel_sampler ps;          /* the pixel being traced */
    uint64_t rays[LC_RAY_KINDS];   /* this thread's counts */
    uint64_t self_hits;
    uint64_t samples;          /* camera samples traced */
    const media *media;        /* the media of the point being lit (filtered shadows) */
    int      npending;
    branch   pending[BRANCH_MAX];
    aov_sample *aov;           /* TRACE_AOV: the camera sample's record */
    signed char pending_cls[BRANCH_MAX];   /* TRACE_AOV: each branch's AOV_* class */
} tracer;

/* What the AOVs record of the first surface a camera ray meets: h, its
** material m (textured) and its normal n facing the camera (aov.c: it
** reads the tracer, which aov.h cannot name). */
void aov_first_hit(tracer *t, const hit *h, const lc_material *m, lc_vec3 n);

#endif
