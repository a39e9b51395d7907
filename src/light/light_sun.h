/* light_sun.h: directional lights: the same direction and light colour
** everywhere, the shadow ray to infinity; the loop over a scene's suns for
** both integrators. */
#ifndef LC_LIGHT_SUN_H
#define LC_LIGHT_SUN_H

#include "light_gather.h"
#include "scene/lights.h"

/* What sun L brings at n.l = cosl, in use's convention: the seed's light
** colour E / pi, or for paths the irradiance times the cosine, E cos. */
ALWAYS_INLINE radiance light_sun_eval(light_use use, const sun_light *L, double cosl)
{
    if (use == LIGHT_SEED)
        return r_scale(rad(L->d.color), radiance_cap(L->k));
    return r_scale(rad(L->d.color), radiance_cap(L->d.irradiance * cosl));
}

/* Every directional light at h, into g. */
ALWAYS_INLINE void light_suns(tracer *t, const hit *h, light_gather *g)
{
    const lc_scene *s = t->scene;
    for (size_t i = 0; i < s->nsuns; i++) {
        const sun_light *L = &s->suns[i];
        double cosl = v3_dot(g->n, L->to);
        if (!(cosl > 0) || !light_wants(g, L->to))
            continue;
        int rec;
        radiance f;
        if (!shadow_ray(t, h, L->to, HUGE_VAL, NULL, LC_RAY_SHADOW, EXPLAIN_SUN(i),
                        INTERSECT_SKIP_NONE, &rec, g->how | SHADOW_FAR, &f, g->lg))
            continue;
        light_take(t, g, L->to, cosl, light_sun_eval(g->use, L, cosl), f, rec);
    }
}

#endif
