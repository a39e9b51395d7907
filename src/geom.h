/* geom.h: rays, hit records, spawning rays off surfaces, and the distance to a plane. */
#ifndef LC_GEOM_H
#define LC_GEOM_H

#include <stdint.h>
#include "vec.h"

typedef struct {
    lc_vec3 o, d;      /* origin; unit direction */
} lc_ray;

typedef struct {
    double   t;        /* distance along the ray */
    lc_vec3  p;        /* hit point, on the surface within perr */
    lc_vec3  perr;     /* per-component bound of p's rounding error */
    lc_vec3  n;        /* unit geometric normal, outward for solids */
    lc_vec3  ns;       /* unit shading normal: n, or interpolated on meshes */
    double   bary[3];  /* triangles: barycentric coordinates of p */
    int      material;
    uint32_t shape;    /* the primitive's id (scene.h: PRIM_ID) */
    uint32_t instance; /* 0, or 1 + the index of the moved mesh hit: its
                       ** placements share their triangles' ids */
} lc_hit;

/* Shadow rays stop this fraction short of their target, so a light sitting
** exactly on a surface is not hidden by that surface. Relative, hence the
** same at every scale (pbrt-v4's ShadowEpsilon, tighter because we are in
** double). Tested by the light-on-surface cases. */
#define SHADOW_SHORTEN 1e-9

/* A point just off the surface on the side of w, provably not behind it
** (pbrt-v4's OffsetRayOrigin). */
lc_vec3 spawn_origin(const lc_hit *h, lc_vec3 w);

/* Distance along r to the plane through p with unit normal n (axis >= 0:
** n is +-1 on that axis), or 0 for no hit in (tmin, tmax). inv: the ray's
** reciprocals or NULL. Inline: every ray meets every infinite plane. */
static inline double plane_distance(lc_vec3 n, lc_vec3 p, int axis, const lc_ray *r,
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
        double band = lc_gamma(4) * (fabs(n.x * po.x) + fabs(n.y * po.y) + fabs(n.z * po.z));
        if (!(fabs(num) > band))
            return 0;
        t = num / denom;
    }
    return t > tmin && t < tmax ? t : 0;   /* NaN and inf fail here */
}

#endif
