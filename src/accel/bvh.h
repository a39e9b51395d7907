/* bvh.h: a bounding volume hierarchy over primitive bounds. */
#ifndef LC_BVH_H
#define LC_BVH_H

#include <signal.h>
#include <stddef.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include "lancer.h"
#include "base/vec.h"

/* The hierarchy as traversed: BVH_WIDTH-wide nodes (8: 256 bytes, four
** cache lines), collapsed from the binary tree the build makes
** (bvh_wide.c). Child k's box is lo[a][k]..hi[a][k] on axis a, floats
** rounded outward from the double geometry, so a box always contains what
** it claims to; laid out by axis so that one load reads an axis's bounds
** of every child. A child with count > 0 is a leaf,
** refs[child, child + count); with count 0 it is the node nodes[child].
** Slots n.. are empty: no box (lo > hi), never visited. Eight children
** against four: a third fewer levels, and an AVX-512 test of all eight as
** cheap as AVX's of four (B3 1M: -x % nodes visited, see engineering.md). */
#define BVH_WIDTH 8
typedef struct {
    float    lo[3][BVH_WIDTH], hi[3][BVH_WIDTH];
    uint32_t child[BVH_WIDTH];
    uint16_t count[BVH_WIDTH];
    uint32_t n;        /* children in use: 2..BVH_WIDTH (1 for a root that is a leaf) */
    uint32_t pad[(2 * BVH_WIDTH - 4) / 4];
} bvh_node;
/* Whole cache lines, so that nodes 64-byte aligned keep their bounds aligned. */
typedef char bvh_node_is_32_bytes_a_child[sizeof(bvh_node) == 32 * BVH_WIDTH ? 1 : -1];

typedef struct {
    bvh_node *nodes;   /* nodes[0] is the root, 64-byte aligned in `block` */
    size_t    nnodes;
    uint32_t *refs;    /* leaf entries: indices into the caller's primitive list */
    size_t    nrefs;
    void     *block;   /* the allocation holding nodes */
    int       lone;    /* the root's one child is a leaf (bvh_lone_leaf) */
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
/* The same, each item weighed by what testing it costs: cost[id >>
** BVH_KIND_SHIFT], the kind in an id's top bits (shape.h's PRIM_ID), in
** units of one sphere or triangle test (bvh_build: all 1); cost has
** BVH_KINDS entries. */
#define BVH_KIND_SHIFT 27
#define BVH_KINDS      (1u << (32 - BVH_KIND_SHIFT))
lc_status bvh_build_costed(bvh *b, bvh_item *items, size_t n, const float *cost,
                           sig_atomic_t interrupts_seen, lc_error *err);
void      bvh_free(bvh *b);

/* The binary tree the build makes (bvh.c), before bvh_collapse (bvh_wide.c)
** makes it wide: a leaf holds refs[start, start + count); an interior
** node's first child follows it, its second is nodes[start]. */
typedef struct {
    float    lo[3], hi[3];
    uint32_t start;
    uint16_t count;   /* leaf: > 0; interior: 0 */
    uint16_t axis;
} bvh2_node;

/* Fills b->nodes (and nnodes, block) from the binary tree nodes[0, n),
** n >= 1; LC_ENOMEM when out of memory, b then unchanged. */
lc_status bvh_collapse(bvh *b, const bvh2_node *nodes, size_t n);

/* The float one ulp from finite f toward -inf (down) or +inf: nextafterf
** without the call, which was half the time of bounding 2M triangles. */
static inline float bvh_float_step(float f, int up)
{
    if (f == 0)
        return up ? 0x1p-149f : -0x1p-149f;          /* the smallest denormals */
    union { float f; uint32_t u; } b = {f};
    if ((f > 0) == (up > 0))
        b.u++;
    else
        b.u--;
    return b.f;
}

/* Bounds never subnormal: a nonzero bound below 2^-125 in magnitude moves
** outward, to 0 or to -+2^-125 (whose half, in a centroid, is still
** normal). A sphere resting on y = 0 has its lower bound one step below
** 0, which was the smallest subnormal float: every centroid of B2's 1M
** spheres took the processor's slow path for subnormals, and building
** their BVH took 2.6 times as long as for the same spheres lifted off the
** ground. Real shapes are at least 1e-30 (about 2^-100) across, so the
** slack is nothing beside them. */
#define BVH_BOUND_TINY 0x1p-125f

/* Rounds a double outward to a float bound. Inline: bounding 4M
** triangles calls each 36M times. */
static inline float bvh_down(double x)
{
    float f = (float)x;
    if ((double)f > x)
        f = bvh_float_step(f, 0);
    if (f != 0 && fabsf(f) < BVH_BOUND_TINY)
        f = f > 0 ? 0.0f : -BVH_BOUND_TINY;
    return f;
}

static inline float bvh_up(double x)
{
    float f = (float)x;
    if ((double)f < x)
        f = bvh_float_step(f, 1);
    if (f != 0 && fabsf(f) < BVH_BOUND_TINY)
        f = f < 0 ? 0.0f : BVH_BOUND_TINY;
    return f;
}
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
** A wide node is at least one binary level, and a traversal pushes at most
** BVH_WIDTH - 1 children per node it visits. */
#define BVH_MAX_DEPTH 64
#define BVH_STACK     ((BVH_WIDTH - 1) * (BVH_MAX_DEPTH + 16))

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

/* Roundings in a slab distance (bound - o) * inv: the subtraction, the
** reciprocal and the product. */
#define BVH_RECIPROCAL_GAMMA 3
/* 1 + 2 gamma(3): the far distances are enlarged by it. */
#define BVH_WIDEN (1 + 2 * (BVH_RECIPROCAL_GAMMA * (DBL_EPSILON / 2)) / \
                   (1 - BVH_RECIPROCAL_GAMMA * (DBL_EPSILON / 2)))
/* The entry distance is lowered by 1 - 64 eps: past its own gamma(3), this
** covers a primitive's distance rounded up to ~30 ulps short of where the
** ray meets its box. Without it, rays aimed at a mesh vertex lying on a
** box face (18 in 1e5, test_widebvh.c) found the shared vertex's faces at
** one t, but a box's entry rounded above it culled the face of lower id,
** and the tie went the other way. 2 eps sufficed there; 64 costs nothing. */
#define BVH_NEAR_SLACK 64
#define BVH_SHRINK (1 - BVH_NEAR_SLACK * DBL_EPSILON)

/* The box test, and why it culls no hit. Each child box is tested in
** double, exactly as the binary tree's were: the float bound converts to
** double exactly, then (bound - o) * inv rounds three times (the
** subtraction, the reciprocal, the product), each by a factor within
** 1 +- eps, so the computed slab distance is within gamma(3) of the exact
** distance to the float plane. Enlarging every far distance by
** 1 + 2 gamma(3) then puts it beyond the exact far distance whatever those
** roundings did, so the computed interval [max near, min far] is never
** empty when the exact segment (0, tmax) of the ray crosses the box (Ize
** 2013, pbrt-v4): a ray through a box (or along its face, or from inside)
** always enters it, and the float bounds contain their primitives. The
** entry max(0, near) is multiplied by BVH_SHRINK once the axes are done
** (the same bits as shrinking each near: rounding is monotonic), so it
** is a lower bound of the exact entry. NaN
** (0 * inf, a ray in a slab's plane) is ignored: max and min keep the
** running value, as the comparisons `near > t0 ? near : t0` do.
**
** The SIMD form computes the same expressions lane by lane: the same IEEE
** double operations in the same order (conversion, subtraction, product,
** product by BVH_WIDEN), and vmaxpd/vminpd return their second operand
** unless the first is greater (smaller), which is that comparison, NaN
** included. So both forms give the same bits, the traversal visits the
** same boxes in the same order, and images cannot tell them apart. The
** bounds stay floats (memory), the arithmetic is double (the robust
** geometry's): four lanes of double are one AVX instruction, as four
** lanes of float would be one SSE instruction, plus one conversion.
**
** A packet of rays (bvh_packet.h) is tested as one: the same code, given
** the bounds of its rays' reciprocals per axis, ilo in q->inv and ihi
** beside it. Why a box this test rejects is one no ray of the packet
** enters by its own test (with its tmax at most the packet's): a ray's
** near distance on an axis is fl(a * inv), a = fl(bound - o) the same for
** every ray of the packet (they share o). Rounding is monotonic: fl(a * x)
** grows with x when a >= 0 and falls when a < 0, so over inv in
** [ilo, ihi] it is at least the smaller of fl(a * ilo) and fl(a * ihi).
** The far distances are bounded above by the larger, then enlarged by the
** same BVH_WIDEN. The packet's entry (the larger of 0 and the near bounds,
** shrunk) is then at most every ray's, its exit (the smaller of the
** packet's tmax and the far bounds) at least every ray's: if one ray
** enters, the packet does. All of a packet's reciprocals are finite and
** of one sign, so no product is NaN (an overflow is an infinity, still in
** order) and the two products of a zero have one sign. */

/* The box tests take one ray q (ihi NULL) or a packet (ihi its largest
** reciprocals, q->inv its smallest). The traversals pass the NULL as a
** constant: for one ray the packet's products are not compiled at all. */
typedef unsigned (*bvh_box_test)(const bvh_node *nd, const bvh_ray *q, const double *ihi,
                                 double tmax, double t[BVH_WIDTH]);

/* Child c of node nd: 1 when the ray (or packet) meets its box before
** tmax, its entry distance into *entry. */
ALWAYS_INLINE int bvh_slabs_child(const bvh_node *nd, unsigned c, const bvh_ray *q,
                                  const double *ihi, double tmax, double *entry)
{
    double t0 = 0, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        double lo = (double)nd->lo[k][c] - q->o[k], hi = (double)nd->hi[k][c] - q->o[k];
        double near, far;
        if (!ihi) {          /* both products, then the choice: no branch */
            double a = lo * q->inv[k], b = hi * q->inv[k];
            near = q->neg[k] ? b : a;
            far = q->neg[k] ? a : b;
        } else {             /* the choice, then the four products */
            double a = q->neg[k] ? hi : lo, b = q->neg[k] ? lo : hi;
            double n0 = a * q->inv[k], n1 = a * ihi[k], f0 = b * q->inv[k], f1 = b * ihi[k];
            near = n0 < n1 ? n0 : n1;
            far = f0 > f1 ? f0 : f1;
        }
        far *= BVH_WIDEN;
        t0 = near > t0 ? near : t0;
        t1 = far < t1 ? far : t1;
    }
    t0 *= BVH_SHRINK;
    *entry = t0;
    return t0 <= t1;
}

/* Entry distances of the node's children into t[] (for those the ray
** meets before tmax), and a mask of them. */
ALWAYS_INLINE unsigned bvh_slabs_scalar(const bvh_node *nd, const bvh_ray *q,
                                        const double *ihi, double tmax, double t[BVH_WIDTH])
{
    unsigned mask = 0;
    for (uint32_t c = 0; c < nd->n; c++)
        if (bvh_slabs_child(nd, c, q, ihi, tmax, &t[c]))
            mask |= 1u << c;
    return mask;
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(LC_NO_SIMD)
#include <immintrin.h>
#define BVH_HAVE_SIMD 1
/* Functions calling bvh_slabs_avx carry BVH_AVX_TARGET, those calling
** bvh_slabs_avx512 BVH_AVX512_TARGET: nothing more (no FMA: the geometry
** is built without contraction). */
#define BVH_AVX_TARGET    __attribute__((target("avx")))
#define BVH_AVX512_TARGET __attribute__((target("avx512f")))

/* Four lanes of double at a time: the children in groups of four. */
BVH_AVX_TARGET ALWAYS_INLINE unsigned bvh_slabs_avx(const bvh_node *nd, const bvh_ray *q,
                                                    const double *ihi, double tmax,
                                                    double t[BVH_WIDTH])
{
    const __m256d widen = _mm256_set1_pd(BVH_WIDEN), shrink = _mm256_set1_pd(BVH_SHRINK);
    unsigned in = 0;
    for (int g = 0; g < BVH_WIDTH; g += 4) {
        __m256d t0 = _mm256_setzero_pd(), t1 = _mm256_set1_pd(tmax);
        for (int k = 0; k < 3; k++) {
            const float *nb = (q->neg[k] ? nd->hi[k] : nd->lo[k]) + g;
            const float *fb = (q->neg[k] ? nd->lo[k] : nd->hi[k]) + g;
            __m256d o = _mm256_set1_pd(q->o[k]), inv = _mm256_set1_pd(q->inv[k]);
            __m256d a = _mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(nb)), o);
            __m256d b = _mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(fb)), o);
            __m256d near = _mm256_mul_pd(a, inv), far = _mm256_mul_pd(b, inv);
            if (ihi) {
                __m256d hi = _mm256_set1_pd(ihi[k]);
                near = _mm256_min_pd(near, _mm256_mul_pd(a, hi));
                far = _mm256_max_pd(far, _mm256_mul_pd(b, hi));
            }
            far = _mm256_mul_pd(far, widen);
            t0 = _mm256_max_pd(near, t0);
            t1 = _mm256_min_pd(far, t1);
        }
        t0 = _mm256_mul_pd(t0, shrink);
        _mm256_storeu_pd(t + g, t0);
        in |= (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(t0, t1, _CMP_LE_OQ)) << g;
        if (g + 4 >= (int)nd->n)         /* the rest are empty */
            break;
    }
    return in & ((1u << nd->n) - 1);
}

#if BVH_WIDTH == 8
/* All eight lanes in one: the same operations, lane by lane. A node of
** at most four children takes AVX's four lanes instead: B1's one node
** of two ran about 6 % slower under 512-bit operations (the processor
** clocks down for them), B3's full nodes 5 % faster. */
BVH_AVX512_TARGET ALWAYS_INLINE unsigned bvh_slabs_avx512(const bvh_node *nd,
                                                          const bvh_ray *q, const double *ihi,
                                                          double tmax, double t[BVH_WIDTH])
{
    if (nd->n <= 4)
        return bvh_slabs_avx(nd, q, ihi, tmax, t);
    __m512d t0 = _mm512_setzero_pd(), t1 = _mm512_set1_pd(tmax);
    const __m512d widen = _mm512_set1_pd(BVH_WIDEN), shrink = _mm512_set1_pd(BVH_SHRINK);
    for (int k = 0; k < 3; k++) {
        const float *nb = q->neg[k] ? nd->hi[k] : nd->lo[k];
        const float *fb = q->neg[k] ? nd->lo[k] : nd->hi[k];
        __m512d o = _mm512_set1_pd(q->o[k]), inv = _mm512_set1_pd(q->inv[k]);
        __m512d a = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(nb)), o);
        __m512d b = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(fb)), o);
        __m512d near = _mm512_mul_pd(a, inv), far = _mm512_mul_pd(b, inv);
        if (ihi) {
            __m512d hi = _mm512_set1_pd(ihi[k]);
            near = _mm512_min_pd(near, _mm512_mul_pd(a, hi));
            far = _mm512_max_pd(far, _mm512_mul_pd(b, hi));
        }
        far = _mm512_mul_pd(far, widen);
        t0 = _mm512_max_pd(near, t0);
        t1 = _mm512_min_pd(far, t1);
    }
    t0 = _mm512_mul_pd(t0, shrink);
    _mm512_storeu_pd(t, t0);
    unsigned in = (unsigned)_mm512_cmp_pd_mask(t0, t1, _CMP_LE_OQ);
    return in & ((1u << nd->n) - 1);
}
#else
#define bvh_slabs_avx512 bvh_slabs_avx
#endif
#else
#define BVH_HAVE_SIMD 0
#define BVH_AVX_TARGET
#define BVH_AVX512_TARGET
#define bvh_slabs_avx bvh_slabs_scalar
#define bvh_slabs_avx512 bvh_slabs_scalar
#endif

/* The tests of one ray, as the tests of the box test call them. */
ALWAYS_INLINE unsigned bvh_test_scalar(const bvh_node *nd, const bvh_ray *q, double tmax,
                                       double t[BVH_WIDTH])
{
    return bvh_slabs_scalar(nd, q, NULL, tmax, t);
}

BVH_AVX_TARGET ALWAYS_INLINE unsigned bvh_test_avx(const bvh_node *nd, const bvh_ray *q,
                                                   double tmax, double t[BVH_WIDTH])
{
    return bvh_slabs_avx(nd, q, NULL, tmax, t);
}

BVH_AVX512_TARGET ALWAYS_INLINE unsigned bvh_test_avx512(const bvh_node *nd,
                                                         const bvh_ray *q, double tmax,
                                                         double t[BVH_WIDTH])
{
    return bvh_slabs_avx512(nd, q, NULL, tmax, t);
}

/* Which box test traversals use: BVH_SIMD_OFF (bvh_slabs_scalar),
** BVH_SIMD_AVX or BVH_SIMD_AVX512, the best the processor has unless the
** environment says LANCER_SIMD=0 (off) or 1 (AVX at most). Decided once,
** by the first build. All three give the same bits. */
enum { BVH_SIMD_OFF, BVH_SIMD_AVX, BVH_SIMD_AVX512, BVH_SIMD_LEVELS };
extern int bvh_simd;
void bvh_simd_init(void);
/* Tests switch it (a level, clamped to what the processor has) and get
** the previous setting. */
int  bvh_simd_set(int level);

/* The two walks, each written once for one ray and for a packet, for the
** scene and for every mesh instance. They take their box test and their
** leaf tests as functions, called with constants: once a walk is inlined
** into its one caller, so are they. The callers come in threes, one built
** for each box test (BVH_DISPATCH, below). A walk is a packet's when ihi
** is not NULL. A leaf is named by its node and slot: refs[at, at + count)
** for at = nd->child[slot] and count = nd->count[slot], its box the
** slot's (a packet tests its rays on it one by one). Both walks count
** their box tests into *nodes. */

/* The per-primitive form of a leaf test (the position at lets a caller
** keep data in leaf order beside refs): a closest-hit search's returns
** tmax, shrunk when it found a nearer hit; an any-hit search's returns
** nonzero when refs[at] blocks the ray. */
typedef double (*bvh_prim_closest)(void *ctx, uint32_t at, double tmax);
typedef int    (*bvh_prim_any)(void *ctx, uint32_t at, double tmax);
/* The whole-leaf form: a closest-hit search's returns tmax as prim would
** have after the last; an any-hit search's returns 1 to end the walk (the
** ray blocked, or every ray of the packet) and may lower *tmax (to the
** largest of the rays still looking). */
typedef double (*bvh_leaf_closest)(void *ctx, const bvh_node *nd, unsigned slot,
                                   double tmax);
typedef int    (*bvh_leaf_any)(void *ctx, const bvh_node *nd, unsigned slot, double *tmax);

/* Leaf slot of nd in a closest-hit walk: leaf, or prim on each primitive
** in order. */
ALWAYS_INLINE double bvh_closest_leaf(void *ctx, const bvh_node *nd, unsigned slot,
                                      double tmax, bvh_prim_closest prim,
                                      bvh_leaf_closest leaf)
{
    if (leaf)
        return leaf(ctx, nd, slot, tmax);
    uint32_t at = nd->child[slot], count = nd->count[slot];
    for (uint32_t k = 0; k < count; k++)
        tmax = prim(ctx, at + k, tmax);
    return tmax;
}

/* A pushed child of the closest-hit walk: its node and slot (a node to
** visit, or a leaf), and its entry distance. */
typedef struct {
    uint32_t node, slot;
    double   t;
} bvh_entry;

/* The children of nd the test met (mask m, entry distances t), nearest
** first (equal distances in slot order): the farther pushed, farthest
** deepest; returns the nearest's slot. One or two met, the usual case, go
** without the sort. */
ALWAYS_INLINE unsigned bvh_order(uint32_t ni, unsigned m, const double *t, bvh_entry *stack,
                                 int *sp)
{
    unsigned c = (unsigned)__builtin_ctz(m), rest = m & (m - 1);
    if (!rest)
        return c;
    if (!(rest & (rest - 1))) {
        unsigned d = (unsigned)__builtin_ctz(rest);
        unsigned far = t[d] < t[c] ? c : d;
        stack[(*sp)++] = (bvh_entry){ni, far, t[far]};
        return c ^ d ^ far;
    }
    bvh_entry e[BVH_WIDTH];
    int h = 0;
    while (m) {
        unsigned k = (unsigned)__builtin_ctz(m);
        m &= m - 1;
        int j = h++;
        while (j > 0 && e[j - 1].t > t[k]) {
            e[j] = e[j - 1];
            j--;
        }
        e[j] = (bvh_entry){ni, k, t[k]};
    }
    for (int j = h - 1; j > 0; j--)
        stack[(*sp)++] = e[j];
    return e[0].slot;
}

/* Closest hit: visits the leaves that may hold a hit nearer than tmax,
** nearer children first, skipping one once a hit lies before it. Each
** leaf goes to leaf (NULL: prim on each primitive). */
ALWAYS_INLINE void bvh_walk_closest(const bvh *b, const bvh_ray *q, const double *ihi,
                                    double tmax, void *ctx, bvh_box_test test,
                                    bvh_prim_closest prim, bvh_leaf_closest leaf,
                                    uint64_t *nodes)
{
    if (!b->nnodes)
        return;
    uint64_t nn = 0;
    bvh_entry stack[BVH_STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const bvh_node *nd = &b->nodes[ni];
        double t[BVH_WIDTH];
        unsigned m = test(nd, q, ihi, tmax, t);
        nn += nd->n;
        if (m) {
            unsigned c = bvh_order(ni, m, t, stack, &sp);
            if (nd->count[c] == 0) {
                ni = nd->child[c];
                continue;
            }
            tmax = bvh_closest_leaf(ctx, nd, c, tmax, prim, leaf);
        }
        for (;;) {
            if (sp == 0) {
                *nodes += nn;
                return;
            }
            const bvh_entry *p = &stack[--sp];
            if (p->t > tmax)
                continue;
            const bvh_node *pn = &b->nodes[p->node];
            if (pn->count[p->slot] == 0) {
                ni = pn->child[p->slot];
                break;
            }
            tmax = bvh_closest_leaf(ctx, pn, p->slot, tmax, prim, leaf);
        }
    }
}

/* Leaf slot of nd in an any-hit walk: leaf, or prim on each primitive
** until one blocks the ray. */
ALWAYS_INLINE int bvh_any_leaf(void *ctx, const bvh_node *nd, unsigned slot, double *tmax,
                               bvh_prim_any prim, bvh_leaf_any leaf)
{
    if (leaf)
        return leaf(ctx, nd, slot, tmax);
    uint32_t at = nd->child[slot], count = nd->count[slot];
    for (uint32_t k = 0; k < count; k++)
        if (prim(ctx, at + k, *tmax))
            return 1;
    return 0;
}

/* Any hit: children in slot order (any blocker will do), leaves as they
** come, until leaf ends the walk; returns 1 if it did. */
ALWAYS_INLINE int bvh_walk_any(const bvh *b, const bvh_ray *q, const double *ihi, double tmax,
                               void *ctx, bvh_box_test test, bvh_prim_any prim,
                               bvh_leaf_any leaf, uint64_t *nodes)
{
    if (!b->nnodes)
        return 0;
    uint32_t stack[BVH_STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const bvh_node *nd = &b->nodes[ni];
        double t[BVH_WIDTH];
        unsigned m = test(nd, q, ihi, tmax, t);
        *nodes += nd->n;
        int descend = 0;
        while (m) {
            unsigned c = (unsigned)__builtin_ctz(m);
            m &= m - 1;
            if (nd->count[c]) {
                if (bvh_any_leaf(ctx, nd, c, &tmax, prim, leaf))
                    return 1;
            } else if (!descend) {
                descend = 1;
                ni = nd->child[c];
            } else
                stack[sp++] = nd->child[c];
        }
        if (descend)
            continue;
        if (sp == 0)
            return 0;
        ni = stack[--sp];
    }
}

/* One ray, each primitive by prim: the closest walk returns its box tests. */
ALWAYS_INLINE uint64_t bvh_closest(const bvh *b, const bvh_ray *q, double tmax, void *ctx,
                                   bvh_prim_closest prim, bvh_box_test test)
{
    uint64_t nn = 0;
    bvh_walk_closest(b, q, NULL, tmax, ctx, test, prim, NULL, &nn);
    return nn;
}

ALWAYS_INLINE int bvh_any(const bvh *b, const bvh_ray *q, double tmax, void *ctx,
                          bvh_prim_any prim, uint64_t *nodes, bvh_box_test test)
{
    return bvh_walk_any(b, q, NULL, tmax, ctx, test, prim, NULL, nodes);
}

/* A hierarchy of one leaf (a scene of a few bounded shapes weighing at
** most MIN_LEAF, bvh.c: four spheres, or two and a box): its box tested
** inline, then the leaf, as the binary tree did, without the call and
** set-up of a traversal. */
static inline int bvh_lone_leaf(const bvh *b)
{
    return b->lone;
}

/* Whether one ray meets child c of nd before tmax (the root's one child;
** a packet's leaf, for each of its rays). */
ALWAYS_INLINE int bvh_test_slot(const bvh_node *nd, unsigned c, const bvh_ray *q,
                                double tmax)
{
    double entry;
    return bvh_slabs_child(nd, c, q, NULL, tmax, &entry);
}

/* The root's one leaf, for one ray: the box test of bvh_test_slot, then
** prim on each primitive (the closest search returns its one box test). */
ALWAYS_INLINE uint64_t bvh_closest_lone(const bvh *b, const bvh_ray *q, double tmax,
                                        void *ctx, bvh_prim_closest prim)
{
    const bvh_node *nd = &b->nodes[0];
    if (bvh_test_slot(nd, 0, q, tmax))
        bvh_closest_leaf(ctx, nd, 0, tmax, prim, NULL);
    return 1;
}

ALWAYS_INLINE int bvh_any_lone(const bvh *b, const bvh_ray *q, double tmax, void *ctx,
                               bvh_prim_any prim, uint64_t *nodes)
{
    const bvh_node *nd = &b->nodes[0];
    ++*nodes;
    return bvh_test_slot(nd, 0, q, tmax) && bvh_any_leaf(ctx, nd, 0, &tmax, prim, NULL);
}

/* Defines name_scalar, name_avx and name_avx512, the same function of
** (args) built around each box test, and name(), which calls the one
** bvh_simd says. The body (the last arguments) uses BVH_TEST for the box
** test, and BVH_LEVEL (BVH_SIMD_OFF, _AVX or _AVX512) to choose its own. */
#define BVH_DISPATCH(type, name, params, args, ...)                           \
    static type name##_scalar params                                          \
    {                                                                         \
        const bvh_box_test BVH_TEST = bvh_slabs_scalar;                       \
        const int BVH_LEVEL = BVH_SIMD_OFF;                                   \
        (void)BVH_LEVEL;                                                      \
        __VA_ARGS__                                                           \
    }                                                                         \
    BVH_AVX_TARGET static type name##_avx params                              \
    {                                                                         \
        const bvh_box_test BVH_TEST = bvh_slabs_avx;                          \
        const int BVH_LEVEL = BVH_SIMD_AVX;                                   \
        (void)BVH_LEVEL;                                                      \
        __VA_ARGS__                                                           \
    }                                                                         \
    BVH_AVX512_TARGET static type name##_avx512 params                        \
    {                                                                         \
        const bvh_box_test BVH_TEST = bvh_slabs_avx512;                       \
        const int BVH_LEVEL = BVH_SIMD_AVX512;                                \
        (void)BVH_LEVEL;                                                      \
        __VA_ARGS__                                                           \
    }                                                                         \
    static inline type name params                                            \
    {                                                                         \
        return bvh_simd == BVH_SIMD_AVX512 ? name##_avx512 args :             \
               bvh_simd == BVH_SIMD_AVX ? name##_avx args : name##_scalar args; \
    }

#endif
