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
                       ** placements share their triangles' ids */
} hit;

/* Shadow rays stop this fraction short of their target, so a light sitting
** exactly on a surface is not hidden by that surface. Relative, hence the
** same at every scale (pbrt-v4's ShadowEpsilon, tighter because we are in
** double). Tested by the light-on-surface cases. */
#define SHADOW_SHORTEN 1e-9

/* A point just off the surface on the side of w, provably not behind it
** (pbrt-v4's OffsetRayOrigin). */
lc_vec3 spawn_origin(const hit *h, lc_vec3 w);

#endif
