/* quad.h: a parallelogram (quad.c): its prepared form and functions. */
#ifndef LC_QUAD_H
#define LC_QUAD_H

#include "base/geom.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

typedef struct {
    lc_vec3 q, u, v;   /* corner, edges */
    lc_vec3 n;         /* u x v, not normalised */
    lc_vec3 w;         /* n / (n.n): the dual basis for (alpha, beta) */
    lc_vec3 un;        /* unit normal */
    double  k;         /* n.q */
    int     axis;      /* 0..2 when n is along an axis (exact snapping), else -1 */
} quad_geom;

typedef struct { double area; } quad_light;

lc_status quad_check(const lc_shape *s, lc_error *err);
void      quad_prepare(const lc_shape *s, quad_geom *g);
void      quad_describe(const quad_geom *g, lc_shape *s);
lc_status quad_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                         lc_error *err);
void      quad_scale(lc_shape *s, double k, lc_vec3 offset);
void      quad_bounds(const quad_geom *g, float lo[3], float hi[3]);
int       quad_hit(const quad_geom *g, const ray *r, double tmin, double tmax, hit *h);
/* inv: the ray's reciprocal direction (1/d per axis), or NULL to compute it. */
int       quad_hit_inv(const quad_geom *g, const ray *r, const double *inv, double tmin,
                       double tmax, hit *h);
void      quad_uv(const quad_geom *g, lc_vec3 p, double uv[2]);
double    quad_light_centre(const quad_geom *g, lc_vec3 l, double d);
int       quad_light_begin(const quad_geom *g, lc_vec3 p, quad_light *ql);
int       quad_light_sample(const quad_geom *g, const quad_light *ql, lc_vec3 p,
                            const double u[2], uint32_t S, struct light_sample *out);

#endif
