/* torus.h: a torus, placed (torus.c). */
#ifndef LC_TORUS_H
#define LC_TORUS_H

#include "placed.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

/* Canonically around the z axis, major radius 1, minor k0 < 1; a quartic. */

lc_status torus_check(const lc_shape *s, lc_error *err);
void      torus_prepare(const lc_shape *s, placed_geom *g);
double    torus_area(const placed_geom *g);    /* the world area, numerically */
double    torus_t(const placed_geom *g, const ray *r, double tmin, double tmax);
int       torus_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h);
void      torus_uv(const placed_geom *g, lc_vec3 p, double uv[2]);
void      torus_bounds(const placed_geom *g, float lo[3], float hi[3]);
int       torus_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                             struct light_sample *out);
/* The canonical roots (up to 4, ascending) of the ray's quartic in (lo, hi). */
int       torus_roots(double minor, const ray *r, double lo, double hi, double roots[4]);
/* Every root beyond tmin at once (CSG leaves want them all: one quartic, not
** one per root), with the canonical ray in *pr; each root as a hit. */
int       torus_all_roots(const placed_geom *g, const ray *r, double tmin,
                          placed_ray *pr, double roots[4]);
int       torus_root_hit(const placed_geom *g, const placed_ray *pr, double s, hit *h);

#endif
