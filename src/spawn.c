/* spawn.c: where secondary rays start, clear of the surface they leave. */
#include "geom.h"

/* Move p along the normal by the support of its error box, on the side the
** new ray goes, then one ulp further: the origin is then provably on the
** correct side of the true surface (pbrt-v4 OffsetRayOrigin). No fixed
** epsilon: the offset scales with the point's own rounding error. */
#ifdef LC_NAIVE
/* A fixed offset, built only by `make NAIVE=1` for the benchmark: it jumps
** over thin geometry at small scales and falls short at large ones. */
#define NAIVE_EPSILON 1e-4

lc_vec3 spawn_origin(const hit *h, lc_vec3 w)
{
    return v3_madd(h->p, h->n, v3_dot(w, h->n) < 0 ? -NAIVE_EPSILON : NAIVE_EPSILON);
}
#else
lc_vec3 spawn_origin(const hit *h, lc_vec3 w)
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
