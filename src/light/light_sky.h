/* light_sky.h: the sky as a light for paths (its distribution: sky.c):
** one direction sampled toward it per hit, its density for a path that
** leaves the scene (MIS), and what it sends along a direction. The seed
** sees the sky only as its background. */
#ifndef LC_LIGHT_SKY_H
#define LC_LIGHT_SKY_H

#include "light_gather.h"
#include "scene/sky.h"

/* The density light_sky samples unit direction d with. */
static inline double light_sky_pdf(const lc_scene *s, lc_vec3 d)
{
    return sky_pdf(&s->c.sky, d);
}

/* One direction toward the sky at h, into g (LIGHT_PATH), weighed against
** BSDF sampling by the power heuristic. */
ALWAYS_INLINE void light_sky(tracer *t, const hit *h, light_gather *g)
{
    const lc_scene *s = t->scene;
    double u[2];
    lc_vec3 l;
    sample_2d(&t->ps, sample_dim(DIM_PATH, (unsigned)g->depth, 2), g->index, g->count, u);
    double ps = sky_sample(&s->c.sky, u, &l);
    double cosl = v3_dot(g->n, l);
    if (!(ps > 0 && cosl > 0) || !light_wants(g, l))
        return;
    int rec;
    radiance f;
    if (!shadow_ray(t, h, l, HUGE_VAL, NULL, LC_RAY_LIGHT, EXPLAIN_SKY, INTERSECT_SKIP_NONE,
                    &rec, g->how | SHADOW_FAR, &f, g->lg))
        return;
    light_take(t, g, l, cosl, r_scale(sky_seen(s, l),
                                      cosl * bsdf_mis_power(ps, g->pdf) / ps), f, rec);
}

#endif
