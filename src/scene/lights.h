/* lights.h: spot and directional lights as a scene stores them (lights.c). */
#ifndef LC_LIGHTS_H
#define LC_LIGHTS_H

#include "base/vec.h"

/* A spot light with what every lit point asks of it worked out once. */
typedef struct {
    lc_spot_light d;       /* as given (direction as given too) */
    lc_vec3 axis;          /* unit */
    double  cos_outer;     /* cos angle: no light past it */
    double  cos_inner;     /* cos(angle - soft): all of it within */
} spot_light;

/* A directional light: the unit direction toward it and its light colour. */
typedef struct {
    lc_directional_light d;
    lc_vec3 to;            /* unit, toward the sun: -direction */
    double  k;             /* irradiance / pi: the light colour's scale */
} sun_light;

void   spot_prepare(const lc_spot_light *l, spot_light *out);
/* The share of the spot's intensity along unit l, from the light outward. */
double spot_share(const spot_light *s, lc_vec3 l);
void   sun_prepare(const lc_directional_light *l, sun_light *out);

#endif
