/* light.h: the lights at a shaded point, one file a kind (light_point.h,
** light_spot.h, light_sun.h, light_emitter.h, light_sky.h, each with its
** sample, eval and loop; the shadow ray in light_ray.h), and the dispatch
** both integrators call: the seed's deterministic sum (shade.c) and the
** path tracer's next-event estimation (path.c). */
#ifndef LC_LIGHT_H
#define LC_LIGHT_H

#include "light_emitter.h"
#include "light_point.h"
#include "light_sky.h"
#include "light_spot.h"
#include "light_sun.h"

/* Every light of the scene at h, into g: in this order, so that each sum
** adds in the order it always has. The seed takes the kinds its needs name
** (the emitters' centres, or S = light_samples points of each); a path
** every light, one point of each emitter, one direction of the sky. */
ALWAYS_INLINE void light_all(tracer *t, const hit *h, light_gather *g)
{
    int path = g->use == LIGHT_PATH;
    if (path || (t->needs & LC_NEED_SHADOW))
        light_points(t, h, g);
    if (path || (t->needs & LC_NEED_SPOT))
        light_spots(t, h, g);
    if (path || (t->needs & LC_NEED_SUN))
        light_suns(t, h, g);
    if (!path && (t->needs & LC_NEED_EMITTER))
        light_emitter_centres(t, h, g);
    if (path)
        light_emitters(t, h, g, 1);
    else if (t->needs & LC_NEED_AREA)
        light_emitters(t, h, g, (uint32_t)t->light_samples);
    if (path && t->scene->c.sky_lights)
        light_sky(t, h, g);
}

#endif
