/* light_gather.h: what the two integrators do with a light a shaded point
** sees: the seed's (shade.c) sums its colour for Phong, the path tracer's
** next-event estimation (path.c) weighs it by the BSDF. Every light kind's
** loop (light_point.h and the others) takes its lights in through these, so
** each kind has one loop for both. */
#ifndef LC_LIGHT_GATHER_H
#define LC_LIGHT_GATHER_H

#include "material/bsdf.h"
#include "light_ray.h"

/* The integrator a gather serves: a constant in each caller, so each
** caller's copy of a loop has only its own arithmetic. */
typedef enum { LIGHT_SEED, LIGHT_PATH } light_use;

typedef struct {
    radiance diffuse;     /* sum of Lc * (n.l) */
    radiance specular;    /* sum of Lc * (R.V)^alpha */
} light_sum;

/* One shaded point's lights being gathered. */
typedef struct {
    light_use use;
    unsigned  how;             /* SHADOW_FILTER or 0 */
    ray_log  *lg;              /* explain's record; NULL (a constant) while rendering */
    lc_vec3   n;               /* the normal facing the viewer */
    uint32_t  index, count;    /* the camera sample, for the sampled lights ... */
    int       depth;           /* ... at this depth */
    /* LIGHT_SEED */
    const lc_material *m;
    unsigned  plan;
    lc_vec3   v;               /* toward the viewer */
    light_sum *sum;
    /* LIGHT_PATH */
    const bsdf *b;
    radiance  beta;            /* the path's weight */
    radiance  acc;             /* what the lights send back, times beta */
    radiance  f;               /* the BSDF toward the light being taken ... */
    double    pdf;             /* ... and the density BSDF sampling gives it */
} light_gather;

/* Adds one light of colour lc seen along unit l with n.l = cosl; while
** explaining, also records what it adds to the pixel on shadow record rec. */
ALWAYS_INLINE void add_light(const tracer *t, const lc_material *m, unsigned plan,
                             lc_vec3 n, lc_vec3 v, lc_vec3 l, double cosl, radiance lc,
                             light_sum *sum, int rec, ray_log *lg)
{
    /* cosl in (0, 1] within a rounding (the callers keep only n.l > 0), lc
    ** capped: the product stays finite, and the sums it goes into are capped. */
    radiance d = r_scale_unit(lc, t->cosine ? cosl : 1.0), sp = {0, 0, 0};
    sum->diffuse = r_add(sum->diffuse, d);
    if (plan & PLAN_SPECULAR) {
        lc_vec3 R = v3_sub(v3_mul(n, 2 * cosl), l);
        double rv = v3_dot(R, v);
        if (rv > 0) {
            sp = r_scale(lc, pow(rv, m->alpha));
            sum->specular = r_add(sum->specular, sp);
        }
    }
    if (lg)
        explain_light(lg, rec, m, d, sp);
}

/* Before a light's shadow ray: whether the light along unit l can add
** anything (the path's BSDF toward it is not black; kept in g). */
ALWAYS_INLINE int light_wants(light_gather *g, lc_vec3 l)
{
    if (g->use == LIGHT_SEED)
        return 1;
    g->f = bsdf_eval(g->b, l, &g->pdf);
    return r_max(g->f) > 0;
}

/* A light the shadow ray reached along unit l, n.l = cosl: lc is what the
** kind's eval gave for g->use (the seed's light colour, or for paths the
** irradiance it brings times the cosine), tr what the filtered shadow let
** through, rec its explain record. */
ALWAYS_INLINE void light_take(const tracer *t, light_gather *g, lc_vec3 l, double cosl,
                              radiance lc, radiance tr, int rec)
{
    if (g->how & SHADOW_FILTER)
        lc = r_mul(lc, tr);
    if (g->use == LIGHT_SEED)
        add_light(t, g->m, g->plan, g->n, g->v, l, cosl, lc, g->sum, rec, g->lg);
    else
        g->acc = r_add(g->acc, r_mul(r_mul(g->f, lc), g->beta));
}

#endif
