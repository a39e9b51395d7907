/* cone.h: a cone, truncated or not, placed (cone.c). */
#ifndef LC_CONE_H
#define LC_CONE_H

#include "placed.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

/* Canonically x^2 + y^2 = (k0 + (k1 - k0) z)^2, 0 <= z <= 1, max(k0, k1) = 1. */

lc_status cone_check(const lc_shape *s, lc_error *err);
void      cone_prepare(const lc_shape *s, placed_geom *g);
double    cone_area(const placed_geom *g);    /* the world area, numerically */
double    cone_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       cone_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      cone_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      cone_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       cone_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                            struct light_sample *out);

#endif
