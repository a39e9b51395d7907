/* disc.h: a disc or a ring, placed (disc.c). */
#ifndef LC_DISC_H
#define LC_DISC_H

#include "placed.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

/* Canonically the unit disc in z = 0, holed to k0 (inner / outer radius). */

lc_status disc_check(const lc_shape *s, lc_error *err);
void      disc_prepare(const lc_shape *s, placed_geom *g);
double    disc_area(const placed_geom *g);    /* the world area, numerically */
double    disc_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       disc_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      disc_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      disc_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       disc_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                            struct light_sample *out);

#endif
