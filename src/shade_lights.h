/* shade_lights.h: the light loops at a hit: point lights, the seed's emitters
** (one ray toward their centre) and emitters sampled as area lights, with
** the one shadow ray they all trace. Static functions, included by shade.c
** alone: in a file of their own they no longer inline into the path loop,
** and B1 took 2.2 % more instructions (callgrind, 320x180). */
#ifndef LC_SHADE_LIGHTS_H
#define LC_SHADE_LIGHTS_H

#include "shade.h"

typedef struct {
    radiance diffuse;     /* sum of Lc * (n.l) */
    radiance specular;    /* sum of Lc * (R.V)^alpha */
} light_sum;

/* Adds one light of colour lc seen along unit l with n.l = cosl; while
** explaining, also records what it adds to the pixel on shadow record rec. */
static void add_light(const tracer *t, const lc_material *m, unsigned plan, lc_vec3 n,
                      lc_vec3 v, lc_vec3 l, double cosl, radiance lc, light_sum *sum,
                      int rec)
{
    radiance d = r_scale(lc, t->cosine ? cosl : 1.0), sp = {0, 0, 0};
    sum->diffuse = r_add(sum->diffuse, d);
    if (plan & PLAN_SPECULAR) {
        lc_vec3 R = v3_sub(v3_mul(n, 2 * cosl), l);
        double rv = v3_dot(R, v);
        if (rv > 0) {
            sp = r_scale(lc, pow(rv, m->alpha));
            sum->specular = r_add(sum->specular, sp);
        }
    }
    if (t->log)
        explain_light(t->log, rec, m, d, sp);
}

/* One shadow ray toward a light `reach` away along l: spawned off h,
** counted as `kind`, recorded while explaining (as light `light`), then
** tested for anything in the way before it stops at shadow_reach.
** aim: the seed's emitters, whose ray goes from the spawned origin straight
** at *aim, and is blocked only when something nearer than the emitter
** `skip` itself is hit; otherwise any hit on a primitive but `skip` blocks
** it. Returns 1 when the light is visible; *rec is its explain record. */
ALWAYS_INLINE int shadow_ray(tracer *t, const hit *h, lc_vec3 l, double reach,
                           const lc_vec3 *aim, lc_ray_kind kind, int light,
                           uint32_t skip, int *rec)
{
    *rec = -1;
    if (!t->shadows)
        return 1;
    ray sr = {spawn_origin(h, l), l};
    if (aim) {
        lc_vec3 so = v3_sub(*aim, sr.o);
        reach = v3_len(so);
        sr.d = v3_mul(so, 1.0 / reach);
    }
    t->rays[kind]++;
    if (t->log)
        *rec = explain_shadow(t->log, kind, &sr, light, reach);
    double tmax = shadow_reach(sr.o, reach);
    int blocked;
    if (aim) {
        hit blk;
        blocked = intersect_closest(t->scene, &sr, tmax, &blk, &t->counts) &&
                  blk.shape != skip;
    } else {
        blocked = intersect_occluded_skip(t->scene, &sr, tmax, skip, &t->counts);
    }
    if (!blocked && t->log)
        explain_visible(t->log, *rec);
    return !blocked;
}

static void point_lights(tracer *t, const hit *h, const lc_material *m, unsigned plan,
                         lc_vec3 n, lc_vec3 v, light_sum *sum)
{
    const lc_scene *s = t->scene;
    double tooclose2 = 16 * v3_dot(h->perr, h->perr);
    for (size_t i = 0; i < s->nlights; i++) {
        const lc_point_light *L = &s->lights[i];
        lc_vec3 tol = v3_sub(L->position, h->p);
        double d2 = v3_dot(tol, tol);
        if (!(d2 > tooclose2))      /* light on the point itself: no direction */
            continue;
        double d = sqrt(d2);
        lc_vec3 l = v3_mul(tol, 1.0 / d);
        double cosl = v3_dot(n, l);
        if (!(cosl > 0))            /* behind the surface: no shadow ray at all */
            continue;
        /* From the offset origin along l, as far as d: the offset is a few
        ** ulps of |p|, inside what shadow_reach leaves, so the ray still
        ** stops short of L. */
        int rec;
        if (!shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, (int)i, INTERSECT_SKIP_NONE, &rec))
            continue;
        double k = L->intensity;
        if (L->falloff == LC_FALLOFF_INVERSE_SQUARE)
            k /= d * d;
        add_light(t, m, plan, n, v, l, cosl, r_scale(rad(L->color), radiance_cap(k)), sum,
                  rec);
    }
}

/* The seed's emissive shapes: visible when the ray toward the shape's centre
** meets the shape itself (or nothing) first. The light colour is E/(pi cos),
** E the irradiance of the whole shape seen from the point: exact for a
** sphere (pi L (r/d)^2 cos), projected area over d^2 for quads and boxes. */
static void emitters(tracer *t, const hit *h, const lc_material *m, unsigned plan,
                     lc_vec3 n, lc_vec3 v, light_sum *sum)
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
        double cosl = v3_dot(n, l);
        if (!(cosl > 0))
            continue;
        int rec;
        if (!shadow_ray(t, h, l, d, &e->target, LC_RAY_SHADOW, -1 - (int)i, e->prim, &rec))
            continue;
        double k = shape_light_centre(e->kind, shape_at(&s->shapes[e->kind], e->index), l, d);
        if (k > 1)                  /* no shape gives more than its radiance */
            k = 1;
        add_light(t, m, plan, n, v, l, cosl, r_scale(rad(e->emission), k), sum, rec);
    }
}

/* Emissive shapes as area lights (light_samples > 0): each hit takes S
** points per emitter, stratified over all the pixel's samples (camera
** sample `index` of `count`, at this depth); spheres by solid angle (the
** cone they subtend), quads and boxes by area. Each sample adds
** L * cos / (pi pdf S), so that the sum is E / pi, the same convention as
** the centre-ray model (exact for an unshadowed sphere). */
static void area_lights(tracer *t, const hit *h, const lc_material *m, unsigned plan,
                        lc_vec3 n, lc_vec3 v, uint32_t index, uint32_t count, int depth,
                        light_sum *sum)
{
    const lc_scene *s = t->scene;
    uint32_t S = (uint32_t)t->light_samples, all = sample_nested_count(count, S);
    for (size_t i = 0; i < s->nemitters; i++) {
        const emitter *e = &s->emitters[i];
        if (e->prim == h->shape)
            continue;
        const void *geom = shape_at(&s->shapes[e->kind], e->index);
        light_setup ls;
        if (!shape_light_begin(e->kind, geom, h->p, n, &ls))
            continue;
        for (uint32_t j = 0; j < S; j++) {
            double u[2];
            light_sample ls1;
            uint32_t idx = (uint32_t)(((uint64_t)index * S + j) % all);
            sample_2d(&t->ps, sample_dim(DIM_LIGHT, (unsigned)depth, (unsigned)i), idx, all,
                      u);
            if (!shape_light_sample(e->kind, geom, &ls, h->p, u, S, &ls1))
                continue;
            double cosl = v3_dot(n, ls1.l);
            if (!(cosl > 0) || !(ls1.k > 0))
                continue;
            /* Any other shape in the way blocks it: an any-hit query, which
            ** skips the emitter itself (its own surface, rounded, must not
            ** shadow the point sampled on it: at 1e7 from the origin the
            ** rounding is as large as any relative shortening, H2). */
            int rec;
            if (!shadow_ray(t, h, ls1.l, ls1.dist, NULL, LC_RAY_LIGHT, -1 - (int)i, e->prim,
                            &rec))
                continue;
            add_light(t, m, plan, n, v, ls1.l, cosl,
                      r_scale(rad(e->emission), radiance_cap(ls1.k)), sum, rec);
        }
    }
}

#endif
