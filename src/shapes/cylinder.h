/* cylinder.h: a cylinder, placed (cylinder.c). */
#ifndef LC_CYLINDER_H
#define LC_CYLINDER_H

#include "placed.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

/* Canonically x^2 + y^2 = 1, 0 <= z <= 1, capped when the shape says. */

lc_status cylinder_check(const lc_shape *s, lc_error *err);
void      cylinder_prepare(const lc_shape *s, placed_geom *g);
double    cylinder_area(const placed_geom *g);    /* the world area, numerically */
double    cylinder_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       cylinder_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      cylinder_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      cylinder_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       cylinder_light_sample(const placed_geom *g, lc_vec3 p, const double u[2],
                                uint32_t S, struct light_sample *out);

#endif
