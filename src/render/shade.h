/* shade.h: the seed's integrator (Whitted's): the colour a ray brings back. */
#ifndef LC_SHADE_H
#define LC_SHADE_H

#include "tracer/tracer.h"

/* The radiance camera sample `index` of `count` of the pixel brings back
** (shade.c; shade_minimal.c in the MINIMAL=1 build). */
radiance shade_ray(tracer *t, const ray *r, uint32_t index, uint32_t count);

#endif
