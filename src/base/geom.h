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

/* A point just off the surface on the side of w, provably not behind it:
** p moved along the normal by the support of its error box, on the side
** the new ray goes, then one ulp further (pbrt-v4's OffsetRayOrigin). No
** fixed epsilon: the offset scales with the point's own rounding error.
** Inline: every shadow and secondary ray starts here, two or three a hit. */
#ifdef LC_NAIVE
/* A fixed offset, built only by `make NAIVE=1` for the benchmark: it jumps
** over thin geometry at small scales and falls short at large ones. */
#define NAIVE_EPSILON 1e-4

static inline lc_vec3 spawn_origin(const hit *h, lc_vec3 w)
{
    return v3_madd(h->p, h->n, v3_dot(w, h->n) < 0 ? -NAIVE_EPSILON : NAIVE_EPSILON);
}
#else
static inline lc_vec3 spawn_origin(const hit *h, lc_vec3 w)
{
    lc_vec3 n = h->n;
    double dist = fabs(n.x) * h->perr.x + fabs(n.y) * h->perr.y + fabs(n.z) * h->perr.z;
    lc_vec3 off = v3_mul(n, dist);
    if (v3_dot(w, n) < 0)
        off = v3_neg(off);
    lc_vec3 po = v3_add(h->p, off);
    if (off.x != 0) po.x = next_toward(po.x, off.x > 0 ? 1 : -1);
    if (off.y != 0) po.y = next_toward(po.y, off.y > 0 ? 1 : -1);
    if (off.z != 0) po.z = next_toward(po.z, off.z > 0 ? 1 : -1);
    return po;
}
#endif

#endif
