/* light_ray.h: the one shadow ray every kind of light traces, for both
** integrators, and the geometry from a shaded point toward a light. Static
** functions, included through light.h: out of line they cost B1 2.2 % more
** instructions (callgrind, 320x180). */
#ifndef LC_LIGHT_RAY_H
#define LC_LIGHT_RAY_H

#include "material/dielectric.h"
#include "scene/intersect.h"
#include "tracer/tracer.h"

/* How a shadow ray goes: bits, each a constant where the light loops are
** compiled, so the loops of opaque scenes carry no filtered shadows. */
enum {
    SHADOW_FILTER = 1,     /* LC_NEED_FILTER: through glass, filtered (shadow_filter) */
    SHADOW_FAR    = 2      /* toward a light at infinity: reach infinite */
};

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
** with SHADOW_FILTER, *f what reaches the point of the light's
** colour. how: SHADOW_* bits, constants in each caller. */
ALWAYS_INLINE int shadow_ray(tracer *t, const hit *h, lc_vec3 l, double reach,
                             const lc_vec3 *aim, lc_ray_kind kind, int light,
                             uint32_t skip, int *rec, unsigned how, radiance *f,
                             ray_log *lg)
{
    int filter = (how & SHADOW_FILTER) != 0, far = (how & SHADOW_FAR) != 0;
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

#endif
