/* light_emitter.h: emissive shapes as lights: the seed's model (one ray
** toward the shape's centre), sampled as area lights by both integrators,
** and, for the path tracer's MIS, which emitter a hit is on and the density
** light sampling gives the direction that hit it (per kind: shape.c). */
#ifndef LC_LIGHT_EMITTER_H
#define LC_LIGHT_EMITTER_H

#include "light_gather.h"

/* The seed's emissive shapes: visible when the ray toward the shape's centre
** meets the shape itself (or nothing) first. The light colour is E/(pi cos),
** E the irradiance of the whole shape seen from the point: exact for a
** sphere (pi L (r/d)^2 cos), projected area over d^2 for quads and boxes.
** The seed's alone (LIGHT_SEED). */
ALWAYS_INLINE void light_emitter_centres(tracer *t, const hit *h, light_gather *g)
{
    const lc_scene *s = t->scene;
    double tooclose = 4 * v3_len(h->perr);
    for (size_t i = 0; i < s->nemitters; i++) {
        const emitter *e = &s->emitters[i];
        if (e->prim == h->shape)
            continue;
        lc_vec3 tol = v3_sub(e->target, h->p);
        double d = v3_len(tol);
        if (!(d > tooclose))
            continue;
        lc_vec3 l = v3_mul(tol, 1.0 / d);
        double cosl = v3_dot(g->n, l);
        if (!(cosl > 0))
            continue;
        int rec;
        radiance f;
        if (!shadow_ray(t, h, l, d, &e->target, LC_RAY_SHADOW, -1 - (int)i, e->prim,
                        &rec, g->how, &f, g->lg))
            continue;
        double k = shape_light_centre(e->kind, shape_at(&s->shapes[e->kind], e->index), l, d);
        if (k > 1)                  /* no shape gives more than its radiance */
            k = 1;
        light_take(t, g, l, cosl, r_scale(rad(e->emission), k), f, rec);
    }
}

/* What sample ls1 of emitter e brings at n.l = cosl, in g's convention:
** the seed's light colour L k, or for paths L cos / pdf = pi k L cos (k =
** 1 / (pi pdf)), weighed against BSDF sampling where the kind's density is
** known (shape_light_mis). */
ALWAYS_INLINE radiance light_emitter_eval(const light_gather *g, const emitter *e,
                                          const light_sample *ls1, double cosl)
{
    if (g->use == LIGHT_SEED)
        return r_scale(rad(e->emission), radiance_cap(ls1->k));
    double w = shape_light_mis(e->kind) ? bsdf_mis_power(1 / (PI * ls1->k), g->pdf) : 1;
    return r_scale(rad(e->emission), radiance_cap(PI * ls1->k * cosl * w));
}

/* Emissive shapes as area lights: each hit takes S points per emitter (S a
** constant 1 for paths), stratified over all the pixel's samples (camera
** sample g->index of g->count, at g->depth); spheres by solid angle (the
** cone they subtend), quads and boxes by area. For the seed each sample
** adds L * cos / (pi pdf S), so that the sum is E / pi, the same
** convention as the centre-ray model (exact for an unshadowed sphere). */
ALWAYS_INLINE void light_emitters(tracer *t, const hit *h, light_gather *g, uint32_t S)
{
    const lc_scene *s = t->scene;
    uint32_t all = sample_nested_count(g->count, S);
    for (size_t i = 0; i < s->nemitters; i++) {
        const emitter *e = &s->emitters[i];
        if (e->prim == h->shape)
            continue;
        const void *geom = shape_at(&s->shapes[e->kind], e->index);
        light_setup ls;
        if (!shape_light_begin(e->kind, geom, h->p, g->n, &ls))
            continue;
        for (uint32_t j = 0; j < S; j++) {
            double u[2];
            light_sample ls1;
            uint32_t idx = (uint32_t)(((uint64_t)g->index * S + j) % all);
            sample_2d(&t->ps, sample_dim(DIM_LIGHT, (unsigned)g->depth, (unsigned)i), idx,
                      all, u);
            if (!shape_light_sample(e->kind, geom, &ls, h->p, u, S, &ls1))
                continue;
            double cosl = v3_dot(g->n, ls1.l);
            if (!(cosl > 0) || !(ls1.k > 0) || !light_wants(g, ls1.l))
                continue;
            /* Any other shape in the way blocks it: an any-hit query, which
            ** skips the emitter itself (its own surface, rounded, must not
            ** shadow the point sampled on it: at 1e7 from the origin the
            ** rounding is as large as any relative shortening, H2). */
            int rec;
            radiance f;
            if (!shadow_ray(t, h, ls1.l, ls1.dist, NULL, LC_RAY_LIGHT, -1 - (int)i, e->prim,
                            &rec, g->how, &f, g->lg))
                continue;
            light_take(t, g, ls1.l, cosl, light_emitter_eval(g, e, &ls1, cosl), f, rec);
        }
    }
}

/* The emitter whose primitive is prim; NULL when none is. */
static inline const emitter *light_emitter_of(const lc_scene *s, uint32_t prim)
{
    for (size_t i = 0; i < s->nemitters; i++)
        if (s->emitters[i].prim == prim)
            return &s->emitters[i];
    return NULL;
}

/* The density light_emitters' path samples gave direction d from point p
** (normal n) to the point at distance dist on emitter e; -1 when the kind's
** density is not known (its light samples then take all the weight). */
static inline double light_emitter_pdf(const lc_scene *s, const emitter *e, lc_vec3 p,
                                       lc_vec3 n, lc_vec3 d, double dist)
{
    return shape_light_pdf(e->kind, shape_at(&s->shapes[e->kind], e->index), p, n, d, dist);
}

#endif
