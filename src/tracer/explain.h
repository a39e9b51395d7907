/* explain.h: recording the rays one sample traces, for lc_scene_explain. The
** tracer calls these only when it has a log: one NULL test while rendering. */
#ifndef LC_EXPLAIN_H
#define LC_EXPLAIN_H

#include "base/radiance.h"
#include "scene/scene.h"

typedef struct {
    lc_ray_record *r;
    double *own;             /* 3 per record: what its own hit (or miss) adds */
    size_t n, cap;
    int failed;              /* out of memory: the rest is not recorded */
    int parent;              /* the record of the ray being shaded */
    radiance w;              /* that ray's weight in the pixel */
} ray_log;

void explain_free(ray_log *g);            /* what recording kept, but records */
/* Appends a record of ray r from record parent (-1: the camera ray's);
** returns its index, or -1 once out of memory. */
int  explain_ray(ray_log *g, int parent, lc_ray_kind kind, const ray *r);
/* The path's ray `rec` met h (NULL: nothing; n faces the viewer), where it
** weighs w in the pixel: the shadow rays that follow are its children. */
void explain_hit(ray_log *g, const lc_scene *s, int rec, const hit *h, lc_vec3 n,
                 radiance w);
/* What ray rec's own hit or miss adds to the pixel (its light, emission,
** background), branches and sub-paths apart. */
void explain_add(ray_log *g, int rec, radiance add);
/* The light numbers explain_shadow takes for spot and directional light i. */
#define EXPLAIN_SPOT(i) ((int)(i) | LC_LIGHT_SPOT << 28)
#define EXPLAIN_SUN(i)  ((int)(i) | LC_LIGHT_DIRECTIONAL << 28)
#define EXPLAIN_SKY     (LC_LIGHT_SKY << 28)

/* A shadow ray toward `light` (i: point light i; -1 - e: emitter e; the
** above for the other kinds) from
** the ray being shaded, as far as distance; returns its record or -1. */
int  explain_shadow(ray_log *g, lc_ray_kind kind, const ray *r, int light,
                    double distance);
void explain_visible(ray_log *g, int rec);
/* The light that shadow ray `rec` brings: diffuse d and specular sp before
** the material's coefficients, in the pixel. */
void explain_light(ray_log *g, int rec, const lc_material *m, radiance d, radiance sp);
/* Once the sample is traced: each camera, reflection, refraction or cone
** ray gets what it adds with everything that follows it (its subtree). */
void explain_finish(ray_log *g);

#endif
