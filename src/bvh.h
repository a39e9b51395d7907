/* bvh.h: a bounding volume hierarchy over primitive bounds. */
#ifndef LC_BVH_H
#define LC_BVH_H

#include <stddef.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include "lancer.h"

/* 32 bytes. Bounds are floats rounded outward from the double geometry, so a
** node always contains what it claims to. */
typedef struct {
    float    lo[3], hi[3];
    uint32_t start;   /* leaf: first entry of refs; interior: index of the second child */
    uint16_t count;   /* leaf: number of refs (> 0); interior: 0 */
    uint16_t axis;    /* interior: split axis, to visit the nearer child first */
} bvh_node;

typedef struct {
    bvh_node *nodes;   /* nodes[0] is the root; an interior node's first child follows it */
    size_t    nnodes;
    uint32_t *refs;    /* leaf entries: indices into the caller's primitive list */
    size_t    nrefs;
} bvh;

/* One primitive to build over: its bounds and the caller's id for it. */
typedef struct {
    float    lo[3], hi[3];
    uint32_t id;
} bvh_item;

/* Builds over items[0, n) (binned surface area heuristic, two threads at the
** top), reordering them; refs then hold the ids in leaf order. The items
** array is taken over and freed. n may be 0. */
lc_status bvh_build(bvh *b, bvh_item *items, size_t n, lc_error *err);
void      bvh_free(bvh *b);

/* Roundings in a slab distance (bound - o) * inv: the subtraction, the
** reciprocal and the product. */
#define BVH_RECIPROCAL_GAMMA 3

/* Slab test of a node for a ray with origin o, reciprocal direction inv and
** signs neg (inv < 0): its entry distance, or +inf when the ray misses it
** before tmax. The far distance is enlarged by 1 + 2 gamma(n), n the
** roundings above, so they can never turn a hit into a miss (Ize 2013,
** pbrt-v4); NaN from 0 * inf is ignored by the comparisons. */
static inline double bvh_enter(const bvh_node *nd, const double o[3], const double inv[3],
                               const int neg[3], double tmax)
{
    static const double widen = 1 + 2 * (BVH_RECIPROCAL_GAMMA * (DBL_EPSILON / 2)) /
                                    (1 - BVH_RECIPROCAL_GAMMA * (DBL_EPSILON / 2));
    double t0 = 0, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        double a = (nd->lo[k] - o[k]) * inv[k];
        double b = (nd->hi[k] - o[k]) * inv[k];
        double near = neg[k] ? b : a, far = (neg[k] ? a : b) * widen;
        t0 = near > t0 ? near : t0;
        t1 = far < t1 ? far : t1;
    }
    return t0 <= t1 ? t0 : HUGE_VAL;
}

/* Rounds a double outward to a float bound. */
float bvh_down(double x);
float bvh_up(double x);

#endif
