/* plane.h: an infinite plane (plane.c): never in the BVH, never a light. */
#ifndef LC_PLANE_H
#define LC_PLANE_H

#include "base/geom.h"

typedef struct {
    lc_vec3 n;         /* unit normal */
    lc_vec3 p;         /* a point on it */
    double  k;         /* n.p */
    double  at;        /* axis >= 0: p's coordinate on that axis */
    int     axis;      /* 0..2 when n is along an axis, else -1 */
} plane_geom;

lc_status plane_check(const lc_shape *s, lc_error *err);
void      plane_prepare(const lc_shape *s, plane_geom *g);
void      plane_describe(const plane_geom *g, lc_shape *s);
lc_status plane_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                          lc_error *err);
void      plane_scale(lc_shape *s, double k, lc_vec3 offset);
int       plane_hit(const plane_geom *g, const ray *r, double tmin, double tmax,
                    hit *h);
/* The rest of a hit at distance t, which plane_t gave for this ray. */
int       plane_finish(const plane_geom *g, const ray *r, double t, hit *h);
void      plane_uv(const plane_geom *g, lc_vec3 p, double uv[2]);
/* Distance along r to the plane through p with unit normal n (axis >= 0:
** n is +-1 on that axis), or 0 for no hit in (tmin, tmax). inv: the ray's
** reciprocals or NULL. Inline: every ray meets every infinite plane. */
static inline double plane_distance(lc_vec3 n, lc_vec3 p, int axis, const ray *r,
                                    const double *inv, double tmin, double tmax)
{
    double t;
    if (axis >= 0) {
        /* Axis planes (walls, floors): one subtraction, exact when the
        ** origin is near the plane, so its side is never in doubt; then
        ** the ray's own reciprocal. A parallel ray gives inf or NaN. */
        double i = inv ? inv[axis] : 1.0 / v3_comp(r->d, axis);
        t = (v3_comp(p, axis) - v3_comp(r->o, axis)) * i;
    } else {
        double denom = v3_dot(n, r->d);
        if (denom == 0)    /* exactly parallel; no epsilon band near grazing */
            return 0;
        /* n.(p - o), not k - n.o: the difference comes first, so t keeps
        ** a few ulps of |p - o|, not of |o|. An origin on the plane within
        ** that rounding cannot tell its side: no hit (a camera on it). */
        lc_vec3 po = v3_sub(p, r->o);
        double num = v3_dot(n, po);
        double band = vec_gamma(4) * (fabs(n.x * po.x) + fabs(n.y * po.y) + fabs(n.z * po.z));
        if (!(fabs(num) > band))
            return 0;
        t = num / denom;
    }
    return t > tmin && t < tmax ? t : 0;   /* NaN and inf fail here */
}

/* plane_t from (0, tmax) for the tracer's loops over every plane, with the
** ray's origin and reciprocals as arrays (bvh_ray's): an axis plane is one
** subtraction and one product, indexed, the same operations as
** plane_distance's, so the same bits. (B1's six walls: every ray tests
** them.) */
static inline double plane_query_t(const plane_geom *g, const ray *r, const double o[3],
                                   const double inv[3], double tmax)
{
    if (g->axis >= 0) {
        double t = (g->at - o[g->axis]) * inv[g->axis];
        return t > 0 && t < tmax ? t : 0;
    }
    return plane_distance(g->n, g->p, -1, r, inv, 0, tmax);
}

/* Shared by plane, quad and box: puts p back onto the plane n.x = k. */
lc_vec3   plane_snap(lc_vec3 p, lc_vec3 n, double k, int axis, double axis_value,
                     lc_vec3 *perr);

static inline double plane_t(const plane_geom *g, const ray *r, const double *inv,
                             double tmin, double tmax)
{
    return plane_distance(g->n, g->p, g->axis, r, inv, tmin, tmax);
}

#endif
