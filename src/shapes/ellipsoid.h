/* ellipsoid.h: the unit sphere, placed (ellipsoid.c). */
#ifndef LC_ELLIPSOID_H
#define LC_ELLIPSOID_H

#include "placed.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

lc_status ellipsoid_check(const lc_shape *s, lc_error *err);
void      ellipsoid_prepare(const lc_shape *s, placed_geom *g);
double    ellipsoid_area(const placed_geom *g);    /* the world area, numerically */
double    ellipsoid_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       ellipsoid_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      ellipsoid_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      ellipsoid_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       ellipsoid_light_sample(const placed_geom *g, lc_vec3 p, const double u[2],
                                 uint32_t S, struct light_sample *out);

#endif
