/* light_spot.h: spot lights, point lights whose light is confined to a
** cone (lights.c prepares them): the loop over a scene's spots for both
** integrators. A point outside the cone takes no shadow ray. */
#ifndef LC_LIGHT_SPOT_H
#define LC_LIGHT_SPOT_H

#include "light_point.h"
#include "scene/lights.h"

/* Every spot light at h, into g. */
ALWAYS_INLINE void light_spots(tracer *t, const hit *h, light_gather *g)
{
    const lc_scene *s = t->scene;
    double tooclose2 = too_close2(h);
    for (size_t i = 0; i < s->nspots; i++) {
        const spot_light *L = &s->spots[i];
        lc_vec3 l;
        double d, d2, cosl;
        if (!toward_light(h, g->n, L->d.position, tooclose2, &l, &d, &d2, &cosl))
            continue;
        double share = spot_share(L, v3_neg(l));
        if (!(share > 0) || !light_wants(g, l))
            continue;
        int rec;
        radiance f;
        if (!shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, EXPLAIN_SPOT(i),
                        INTERSECT_SKIP_NONE, &rec, g->how, &f, g->lg))
            continue;
        light_take(t, g, l, cosl, light_point_eval(g->use, L->d.color, L->d.intensity, share,
                                                   L->d.falloff, d, d2, cosl), f, rec);
    }
}

#endif
