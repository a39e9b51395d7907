/* geom.h: rays, hit records, and spawning rays off surfaces. */
#ifndef LC_GEOM_H
#define LC_GEOM_H

#include <stdint.h>
#include "vec.h"

typedef struct {
    lc_vec3 o, d;      /* origin; unit direction */
} ray;

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
                       ** placements share their triangles' ids; for a CSG
                       ** hit 1 + the leaf's node in its description */
} hit;

/* How far a shadow ray from o goes toward a light `reach` away: short of it
** by the rounding error of the distances there (that of reach itself, and
** of the distance to a surface through the light, each a few roundings of
** |o| + |light| <= 2 |o| + reach), so a light sitting exactly on a surface
** is not hidden by it, while a wall any farther than that from the light
** still blocks it (a light 1e-12 of the scene inside a box leaves the
** outside dark; a fixed 1e-9 of the distance let it shine through). */
static inline double shadow_reach(lc_vec3 o, double reach)
{
    return reach - vec_gamma(32) * (2 * v3_max_abs(o) + 2 * reach);
}

/* A point just off the surface on the side of w, provably not behind it
** (pbrt-v4's OffsetRayOrigin). */
lc_vec3 spawn_origin(const hit *h, lc_vec3 w);

#endif
