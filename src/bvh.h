/* bvh.h: a bounding volume hierarchy over primitive bounds. */
#ifndef LC_BVH_H
#define LC_BVH_H

#include <signal.h>
#include <stddef.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include "lancer.h"
#include "vec.h"

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
** array is taken over and freed. n may be 0. Stops with LC_ECANCEL once
** interrupt_count() differs from interrupts_seen (polled every few
** hundred nodes and every pass over many items). */
lc_status bvh_build(bvh *b, bvh_item *items, size_t n, sig_atomic_t interrupts_seen,
                    lc_error *err);
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
/* Bounds of a primitive: empty, then grown by points. An exact point (a
** mesh vertex, stored as given) is rounded outward to float; a computed one
** (c - r, q + u) is first widened by one ulp, so the box contains the shape
** whatever the rounding of that computation. */
void bvh_bounds_empty(float lo[3], float hi[3]);
void bvh_bounds_exact(float lo[3], float hi[3], const double p[3]);
void bvh_bounds_grow(float lo[3], float hi[3], lc_vec3 p);

/* ---- Traversal: written once, for the scene and for every mesh instance ---- */

/* The build makes leaves at this depth; only a leaf of more than 65 535
** primitives is halved further, which at most 2^28 of them adds 13 levels.
** A traversal pushes at most one node per level: its stack holds twice the
** depth. */
#define BVH_MAX_DEPTH 64
#define BVH_STACK     (2 * BVH_MAX_DEPTH)

/* Intersection work, counted per thread: primitive and BVH node tests, and
** the CSG sweeps' leaf tests (csg.h). */
typedef struct { uint64_t prims, nodes, csg; } bvh_counts;

/* A ray as the slab tests read it: origin, reciprocal direction and the
** signs of the reciprocals (so -0 counts as negative). */
typedef struct {
    double o[3], inv[3];
    int    neg[3];
} bvh_ray;

static inline void bvh_ray_init(bvh_ray *q, lc_vec3 o, lc_vec3 d)
{
    double dd[3] = {d.x, d.y, d.z};
    q->o[0] = o.x;
    q->o[1] = o.y;
    q->o[2] = o.z;
    /* Exact reciprocals, one division each: distances to axis planes, axis
    ** quads and aligned boxes use them too, so coplanar surfaces meet a ray
    ** at the same t. (Three from one division saved ~2 % and cost both.) */
    for (int k = 0; k < 3; k++)
        q->inv[k] = 1.0 / dd[k];         /* +-inf for 0: wanted */
    for (int k = 0; k < 3; k++)
        q->neg[k] = q->inv[k] < 0;
}

/* The traversals take their leaf test as a function, called with a constant:
** once the traversal is inlined into its one caller, so is the leaf. */

/* Closest hit: visits the leaves that may hold a hit nearer than tmax,
** nearer child first, skipping a farther one once a hit lies before it.
** leaf(ctx, ref, tmax) tests one primitive and returns tmax, shrunk when it
** found a nearer hit. Returns the number of node tests. */
ALWAYS_INLINE uint64_t bvh_closest(const bvh *b, const bvh_ray *q, double tmax, void *ctx,
                                double (*leaf)(void *ctx, uint32_t ref, double tmax))
{
    if (!b->nnodes)
        return 0;
    uint64_t nn = 1;
    if (bvh_enter(&b->nodes[0], q->o, q->inv, q->neg, tmax) == HUGE_VAL)
        return nn;
    uint32_t stack[BVH_STACK];
    double enter[BVH_STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const bvh_node *nd = &b->nodes[ni];
        if (nd->count) {
            for (uint32_t k = 0; k < nd->count; k++)
                tmax = leaf(ctx, b->refs[nd->start + k], tmax);
        } else {
            uint32_t c0 = ni + 1, c1 = nd->start;
            double t0 = bvh_enter(&b->nodes[c0], q->o, q->inv, q->neg, tmax);
            double t1 = bvh_enter(&b->nodes[c1], q->o, q->inv, q->neg, tmax);
            nn += 2;
            if (t1 < t0) {
                uint32_t c = c0; c0 = c1; c1 = c;
                double t = t0; t0 = t1; t1 = t;
            }
            if (t0 < HUGE_VAL) {
                if (t1 < HUGE_VAL) {
                    stack[sp] = c1;
                    enter[sp++] = t1;
                }
                ni = c0;
                continue;
            }
        }
        do {
            if (sp == 0)
                return nn;
            --sp;
        } while (enter[sp] > tmax);
        ni = stack[sp];
    }
}

/* Any hit: leaf(ctx, ref, tmax) returns nonzero when the primitive blocks
** the ray, which ends the search. Returns 1 if one did; *nodes counts the
** node tests. */
ALWAYS_INLINE int bvh_any(const bvh *b, const bvh_ray *q, double tmax, void *ctx,
                       int (*leaf)(void *ctx, uint32_t ref, double tmax), uint64_t *nodes)
{
    if (!b->nnodes)
        return 0;
    ++*nodes;
    if (bvh_enter(&b->nodes[0], q->o, q->inv, q->neg, tmax) == HUGE_VAL)
        return 0;
    uint32_t stack[BVH_STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const bvh_node *nd = &b->nodes[ni];
        if (nd->count) {
            for (uint32_t k = 0; k < nd->count; k++)
                if (leaf(ctx, b->refs[nd->start + k], tmax))
                    return 1;
        } else {
            uint32_t c0 = ni + 1, c1 = nd->start;
            int h0 = bvh_enter(&b->nodes[c0], q->o, q->inv, q->neg, tmax) < HUGE_VAL;
            int h1 = bvh_enter(&b->nodes[c1], q->o, q->inv, q->neg, tmax) < HUGE_VAL;
            *nodes += 2;
            if (h0 || h1) {
                if (h0 && h1)
                    stack[sp++] = c1;
                ni = h0 ? c0 : c1;
                continue;
            }
        }
        if (sp == 0)
            return 0;
        ni = stack[--sp];
    }
}

#endif
