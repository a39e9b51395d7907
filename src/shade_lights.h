/* shade_lights.h: the light loops at a hit: point, spot and directional
** lights, the seed's emitters (one ray toward their centre) and emitters
** sampled as area lights, with the one shadow ray they all trace. Static
** functions, included by shade.c (and path.c, for the shadow ray): in a
** file of their own they no longer inline into the path loop, and B1 took
** 2.2 % more instructions (callgrind, 320x180). */
#ifndef LC_SHADE_LIGHTS_H
#define LC_SHADE_LIGHTS_H

#include "dielectric.h"
#include "shade.h"

typedef struct {
    radiance diffuse;     /* sum of Lc * (n.l) */
    radiance specular;    /* sum of Lc * (R.V)^alpha */
} light_sum;

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

/* What a shadow ray keeps crossing a surface of m between the indices n1
** and n2 at cosine c with it: kt (1 - F), times the colour when absorb =
** 'all', as a refracted ray would. The shadow ray is not bent, so F is the
** Fresnel reflectance of light entering the denser side at that angle:
** along a straight chord both ends then take the same share, and none is
** lost to a total internal reflection the bent ray would not meet. */
static radiance shadow_crossing(const lc_material *m, double n1, double n2, double c)
{
    double F = m->fresnel ? dielectric_fresnel(c, n2 > n1 ? n2 / n1 : n1 / n2) : 0;
    double k = m->kt * (1 - F);
    radiance r = {k, k, k};
    return m->absorb == LC_ABSORB_ALL ? r_scale(rad(m->color), k) : r;
}

/* A shadow ray through materials with kt > 0 and shadow = 'filtered'
** (LC_NEED_FILTER; POV-Ray's look): it goes on straight through each, times
** the surface's transmission at every crossing and the medium's absorption
** in between; anything else blocks it. From sr.o along sr.d as far as
** reach; aim, skip as in shadow_ray. Returns 0 when blocked, else 1 with
** what gets through in *f. */
static int shadow_filter(tracer *t, ray sr, double reach, int aim, uint32_t skip,
                         radiance *f)
{
    const lc_scene *s = t->scene;
    media md = *t->media;
    radiance k = {1, 1, 1};
    lc_vec3 o0 = sr.o;
    for (;;) {
        double left = reach - v3_dot(v3_sub(sr.o, o0), sr.d);
        /* A directional light is infinitely far: nothing to stop short of. */
        double tmax = isinf(left) ? HUGE_VAL : shadow_reach(sr.o, left);
        hit b;
        if (!intersect_closest(s, &sr, tmax, &b, &t->counts)) {
            if (md.n)
                k = media_absorb(s, &md, k, left);
            break;
        }
        if (b.shape == skip && aim) {           /* the emitter itself: reached */
            if (md.n)
                k = media_absorb(s, &md, k, b.t);
            break;
        }
        if (b.shape != skip) {                  /* a sampled emitter is not there */
            if (!(t->plan[b.material] & PLAN_FILTER))
                return 0;
            if (md.n)
                k = media_absorb(s, &md, k, b.t);
            else if (v3_dot(sr.d, b.n) > 0)
                k = media_adopt(s, &md, (uint32_t)b.material, k, b.t);
            media past;
            double n1, n2;
            if (media_cross(s, &md, (uint32_t)b.material, v3_dot(sr.d, b.n) < 0, &past,
                            &n1, &n2))
                k = r_mul(k, shadow_crossing(&s->materials[b.material], n1, n2,
                                             fabs(v3_dot(sr.d, b.ns))));
            md = past;
            if (!(r_max(k) > 0))
                return 0;
        }
        sr.o = spawn_origin(&b, sr.d);
    }
    *f = k;
    return 1;
}

/* One shadow ray toward a light `reach` away along l: spawned off h,
** counted as `kind`, recorded while explaining (as light `light`), then
** tested for anything in the way before it stops at shadow_reach.
** aim: the seed's emitters, whose ray goes from the spawned origin straight
** at *aim, and is blocked only when something nearer than the emitter
** `skip` itself is hit; otherwise any hit on a primitive but `skip` blocks
** it. Returns 1 when the light is visible; *rec is its explain record;
** with filter (LC_NEED_FILTER), *f what reaches the point of the light's
** colour. far (a constant): a directional light, reach infinite. */
ALWAYS_INLINE int shadow_ray(tracer *t, const hit *h, lc_vec3 l, double reach,
                           const lc_vec3 *aim, lc_ray_kind kind, int light,
                           uint32_t skip, int *rec, int filter, radiance *f, int far,
                           ray_log *lg)
{
    *rec = -1;
    if (!t->shadows) {
        f->r = f->g = f->b = 1;
        return 1;
    }
    ray sr = {spawn_origin(h, l), l};
    if (aim) {
        lc_vec3 so = v3_sub(*aim, sr.o);
        reach = v3_len(so);
        sr.d = v3_mul(so, 1.0 / reach);
    }
    t->rays[kind]++;
    if (lg)
        *rec = explain_shadow(lg, kind, &sr, light, reach);
    double tmax = far ? HUGE_VAL : shadow_reach(sr.o, reach);
    int blocked;
    if (filter) {
        blocked = !shadow_filter(t, sr, reach, aim != NULL, skip, f);
    } else if (aim) {
        hit blk;
        blocked = intersect_closest(t->scene, &sr, tmax, &blk, &t->counts) &&
                  blk.shape != skip;
    } else {
        blocked = intersect_occluded_skip(t->scene, &sr, tmax, skip, &t->counts);
    }
    if (!blocked && lg)
        explain_visible(lg, *rec);
    return !blocked;
}

/* The squared distance within which a light sits on the point h itself. */
static inline double too_close2(const hit *h) { return 16 * v3_dot(h->perr, h->perr); }

/* From h toward a light at pos: the unit direction *l, the distance *d (its
** square *d2) and *cosl = n.l. 0 when the light sits on the point itself
** (d2 within tooclose2, too_close2's: no direction) or behind the surface
** (no shadow ray at all). */
ALWAYS_INLINE int toward_light(const hit *h, lc_vec3 n, lc_vec3 pos, double tooclose2,
                               lc_vec3 *l, double *d, double *d2, double *cosl)
{
    lc_vec3 tol = v3_sub(pos, h->p);
    *d2 = v3_dot(tol, tol);
    if (!(*d2 > tooclose2))
        return 0;
    *d = sqrt(*d2);
    *l = v3_mul(tol, 1.0 / *d);
    *cosl = v3_dot(n, *l);
    return *cosl > 0;
}

/* Each light loop takes `filter` as a constant (LC_NEED_FILTER): the loops
** opaque scenes run have no trace of the filtered shadows. */
ALWAYS_INLINE void point_lights(tracer *t, const hit *h, const lc_material *m,
                                unsigned plan, lc_vec3 n, lc_vec3 v, light_sum *sum,
                                int filter, ray_log *lg)
{
    const lc_scene *s = t->scene;
    double tooclose2 = too_close2(h);
    /* The lights' directions a few at a time, before their shadow rays:
    ** each is a square root and a division, whose latencies the calls to
    ** the shadow rays kept in series (a fifth of B1's samples in the
    ** shading waited on them; B1 at 16 spp now 0.98x the wall). */
    enum { AHEAD = 4 };
    lc_vec3 ls[AHEAD];
    double ds[AHEAD], cs[AHEAD];
    int ok[AHEAD];
    for (size_t i = 0; i < s->nlights; i++) {
        const lc_point_light *L = &s->lights[i];
        size_t slot = i % AHEAD;
        if (slot == 0)
            for (size_t j = i; j < s->nlights && j < i + AHEAD; j++) {
                double d2;
                ok[j - i] = toward_light(h, n, s->lights[j].position, tooclose2, &ls[j - i],
                                         &ds[j - i], &d2, &cs[j - i]);
            }
        if (!ok[slot])
            continue;
        lc_vec3 l = ls[slot];
        double d = ds[slot], cosl = cs[slot];
        /* From the offset origin along l, as far as d: the offset is a few
        ** ulps of |p|, inside what shadow_reach leaves, so the ray still
        ** stops short of L. */
        int rec;
        radiance f;
        if (!shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, (int)i, INTERSECT_SKIP_NONE,
                        &rec, filter, &f, 0, lg))
            continue;
        double k = L->intensity;
        if (L->falloff == LC_FALLOFF_INVERSE_SQUARE)
            k /= d * d;
        radiance lc = r_scale(rad(L->color), radiance_cap(k));
        if (filter)
            lc = r_mul(lc, f);
        add_light(t, m, plan, n, v, l, cosl, lc, sum, rec, lg);
    }
}

/* The seed's emissive shapes: visible when the ray toward the shape's centre
** meets the shape itself (or nothing) first. The light colour is E/(pi cos),
** E the irradiance of the whole shape seen from the point: exact for a
** sphere (pi L (r/d)^2 cos), projected area over d^2 for quads and boxes. */
ALWAYS_INLINE void emitters(tracer *t, const hit *h, const lc_material *m, unsigned plan,
                            lc_vec3 n, lc_vec3 v, light_sum *sum, int filter, ray_log *lg)
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
        radiance f;
        if (!shadow_ray(t, h, l, d, &e->target, LC_RAY_SHADOW, -1 - (int)i, e->prim,
                        &rec, filter, &f, 0, lg))
            continue;
        double k = shape_light_centre(e->kind, shape_at(&s->shapes[e->kind], e->index), l, d);
        if (k > 1)                  /* no shape gives more than its radiance */
            k = 1;
        radiance lc = r_scale(rad(e->emission), k);
        if (filter)
            lc = r_mul(lc, f);
        add_light(t, m, plan, n, v, l, cosl, lc, sum, rec, lg);
    }
}

/* Emissive shapes as area lights (light_samples > 0): each hit takes S
** points per emitter, stratified over all the pixel's samples (camera
** sample `index` of `count`, at this depth); spheres by solid angle (the
** cone they subtend), quads and boxes by area. Each sample adds
** L * cos / (pi pdf S), so that the sum is E / pi, the same convention as
** the centre-ray model (exact for an unshadowed sphere). */
ALWAYS_INLINE void area_lights(tracer *t, const hit *h, const lc_material *m,
                               unsigned plan, lc_vec3 n, lc_vec3 v, uint32_t index,
                               uint32_t count, int depth, light_sum *sum, int filter, ray_log *lg)
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
            radiance f;
            if (!shadow_ray(t, h, ls1.l, ls1.dist, NULL, LC_RAY_LIGHT, -1 - (int)i, e->prim,
                            &rec, filter, &f, 0, lg))
                continue;
            radiance lc = r_scale(rad(e->emission), radiance_cap(ls1.k));
            if (filter)
                lc = r_mul(lc, f);
            add_light(t, m, plan, n, v, ls1.l, cosl, lc, sum, rec, lg);
        }
    }
}

/* Spot lights: point lights whose light is confined to a cone. A point
** outside the cone takes no shadow ray. */
ALWAYS_INLINE void spot_lights(tracer *t, const hit *h, const lc_material *m,
                               unsigned plan, lc_vec3 n, lc_vec3 v, light_sum *sum,
                               int filter, ray_log *lg)
{
    const lc_scene *s = t->scene;
    double tooclose2 = too_close2(h);
    for (size_t i = 0; i < s->nspots; i++) {
        const spot_light *L = &s->spots[i];
        lc_vec3 l;
        double d, d2, cosl;
        if (!toward_light(h, n, L->d.position, tooclose2, &l, &d, &d2, &cosl))
            continue;
        double share = spot_share(L, v3_neg(l));
        if (!(share > 0))
            continue;
        int rec;
        radiance f;
        if (!shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, EXPLAIN_SPOT(i),
                        INTERSECT_SKIP_NONE, &rec, filter, &f, 0, lg))
            continue;
        double k = L->d.intensity * share;
        if (L->d.falloff == LC_FALLOFF_INVERSE_SQUARE)
            k /= d * d;
        radiance lc = r_scale(rad(L->d.color), radiance_cap(k));
        if (filter)
            lc = r_mul(lc, f);
        add_light(t, m, plan, n, v, l, cosl, lc, sum, rec, lg);
    }
}

/* Directional lights: the same direction and light colour everywhere; the
** shadow ray goes to infinity. */
ALWAYS_INLINE void sun_lights(tracer *t, const hit *h, const lc_material *m,
                              unsigned plan, lc_vec3 n, lc_vec3 v, light_sum *sum,
                              int filter, ray_log *lg)
{
    const lc_scene *s = t->scene;
    for (size_t i = 0; i < s->nsuns; i++) {
        const sun_light *L = &s->suns[i];
        double cosl = v3_dot(n, L->to);
        if (!(cosl > 0))
            continue;
        int rec;
        radiance f;
        if (!shadow_ray(t, h, L->to, HUGE_VAL, NULL, LC_RAY_SHADOW, EXPLAIN_SUN(i),
                        INTERSECT_SKIP_NONE, &rec, filter, &f, 1, lg))
            continue;
        radiance lc = r_scale(rad(L->d.color), radiance_cap(L->k));
        if (filter)
            lc = r_mul(lc, f);
        add_light(t, m, plan, n, v, L->to, cosl, lc, sum, rec, lg);
    }
}

/* Every light loop at a hit of a scene with glass that shadow rays cross,
** or with spot or directional lights: apart, so the loops of opaque scenes
** with point lights and emitters stay as they were (one test of the needs
** reaches here, the one glass took before). filter is a constant in each
** of its two copies. */
ALWAYS_INLINE void lights_all(tracer *t, const hit *h, const lc_material *m,
                              unsigned plan, lc_vec3 n, lc_vec3 v, uint32_t index,
                              uint32_t count, int depth, light_sum *sum, int filter, ray_log *lg)
{
    if (t->needs & LC_NEED_SHADOW)
        point_lights(t, h, m, plan, n, v, sum, filter, lg);
    if (t->needs & LC_NEED_SPOT)
        spot_lights(t, h, m, plan, n, v, sum, filter, lg);
    if (t->needs & LC_NEED_SUN)
        sun_lights(t, h, m, plan, n, v, sum, filter, lg);
    if (t->needs & LC_NEED_EMITTER)
        emitters(t, h, m, plan, n, v, sum, filter, lg);
    if (t->needs & LC_NEED_AREA)
        area_lights(t, h, m, plan, n, v, index, count, depth, sum, filter, lg);
}

/* The needs that take the light loops out of line. */
#define LIGHTS_APART (LC_NEED_FILTER | LC_NEED_SPOT | LC_NEED_SUN)

#endif
