/* sky.h: what a ray that leaves the scene sees (sky.c). */
#ifndef LC_SKY_H
#define LC_SKY_H

#include "radiance.h"
#include "scene.h"

/* The background texture in direction d (LC_NEED_SKY), clamped below at 0:
** evaluated at the unit direction as a point and at its sphere (u, v). */
radiance sky_radiance(const lc_scene *s, lc_vec3 d);

#endif
