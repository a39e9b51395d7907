/* bvh.c: building the bounding volume hierarchy (binned SAH). */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "bvh.h"
#include "base/error.h"
#include "base/interrupt.h"
#include "base/mem.h"

#define BINS 16
#define MIN_LEAF 4        /* costing no more is always a leaf: nodes cost memory too */
#define MAX_LEAF 8        /* a leaf never holds more, unless the prims cannot be split */
#define TRAVERSAL_COST 0.5f  /* one node visit, relative to one primitive test */

void bvh_bounds_empty(float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = HUGE_VALF;
        hi[k] = -HUGE_VALF;
    }
}

void bvh_bounds_exact(float lo[3], float hi[3], const double p[3])
{
    for (int k = 0; k < 3; k++) {
        float a = bvh_down(p[k]), b = bvh_up(p[k]);
        if (a < lo[k]) lo[k] = a;
        if (b > hi[k]) hi[k] = b;
    }
}

/* next_toward (vec.h) for libm's nextafter: the same double for every
** finite c, without the call, which was a sixth of building 100k spheres'
** hierarchy (callgrind, scenes/bench/clusters.lua). */
void bvh_bounds_grow(float lo[3], float hi[3], lc_vec3 p)
{
    double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; k++) {
        float a = bvh_down(next_toward(c[k], -1));
        float b = bvh_up(next_toward(c[k], 1));
        if (a < lo[k]) lo[k] = a;
        if (b > hi[k]) hi[k] = b;
    }
}

/* Boxes padded to four floats an end, so that SSE grows all three axes in
** one minimum and one maximum (the fourth lane is never read). Minima and
** maxima of the same floats, in any order, are the same floats: the tree
** is the one the scalar code built (the sign of a zero bound may differ,
** which no slab test can tell). */
typedef struct { float lo[4], hi[4]; } box3;

static void box_empty(box3 *b)
{
    for (int k = 0; k < 4; k++) {
        b->lo[k] = INFINITY;
        b->hi[k] = -INFINITY;
    }
}

#if defined(__SSE2__)
#include <emmintrin.h>
/* An item's lo and hi as four floats each: lo[0..2] and hi[0]; hi[0..2]
** and hi[2] again, read from lo[2] on and shuffled. (Not the id as the
** fourth float: a small id is a subnormal float, and the centroid's
** arithmetic on it made the build twice as slow.) */
static inline __m128 item_lo(const bvh_item *it) { return _mm_loadu_ps(it->lo); }
static inline __m128 item_hi(const bvh_item *it)
{
    __m128 x = _mm_loadu_ps(it->lo + 2);
    return _mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 3, 2, 1));
}

static inline void box_grow_item(box3 *b, const bvh_item *it)
{
    _mm_storeu_ps(b->lo, _mm_min_ps(item_lo(it), _mm_loadu_ps(b->lo)));
    _mm_storeu_ps(b->hi, _mm_max_ps(item_hi(it), _mm_loadu_ps(b->hi)));
}

static inline void box_merge(box3 *b, const box3 *a)
{
    _mm_storeu_ps(b->lo, _mm_min_ps(_mm_loadu_ps(a->lo), _mm_loadu_ps(b->lo)));
    _mm_storeu_ps(b->hi, _mm_max_ps(_mm_loadu_ps(a->hi), _mm_loadu_ps(b->hi)));
}

/* The box of an item's centroid: 0.5 lo + 0.5 hi, lane by lane, as
** centroid() computes each. */
static inline void box_grow_centroid(box3 *b, const bvh_item *it)
{
    const __m128 half = _mm_set1_ps(0.5f);
    __m128 c = _mm_add_ps(_mm_mul_ps(half, item_lo(it)), _mm_mul_ps(half, item_hi(it)));
    _mm_storeu_ps(b->lo, _mm_min_ps(c, _mm_loadu_ps(b->lo)));
    _mm_storeu_ps(b->hi, _mm_max_ps(c, _mm_loadu_ps(b->hi)));
}
#else
static inline void box_grow3(box3 *b, const float lo[3], const float hi[3])
{
    for (int k = 0; k < 3; k++) {
        if (lo[k] < b->lo[k]) b->lo[k] = lo[k];
        if (hi[k] > b->hi[k]) b->hi[k] = hi[k];
    }
}

static inline void box_grow_item(box3 *b, const bvh_item *it) { box_grow3(b, it->lo, it->hi); }
static inline void box_merge(box3 *b, const box3 *a) { box_grow3(b, a->lo, a->hi); }

static inline void box_grow_centroid(box3 *b, const bvh_item *it)
{
    float c[3];
    for (int k = 0; k < 3; k++)
        c[k] = 0.5f * it->lo[k] + 0.5f * it->hi[k];
    box_grow3(b, c, c);
}
#endif

static float box_area(const box3 *b)
{
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    if (!(dx >= 0))     /* empty */
        return 0;
    return 2 * (dx * dy + dy * dz + dz * dx);
}

/* Items are moved as a whole during the build, so every pass reads memory
** in order. */
typedef bvh_item item;

/* The binary tree as it grows. */
typedef struct {
    bvh2_node *nodes;
    size_t     nnodes;
} tree2;

typedef struct {
    tree2 *b;
    size_t cap;
    item  *items;
    int    failed;               /* out of memory, or cancelled */
    int    cancelled;
    sig_atomic_t seen;           /* interrupt_count() when the build began */
    const float *cost;           /* an item's test cost by its kind; NULL: all 1 */
} builder;

/* Polled every 256 nodes and before each pass over many items: a Ctrl-C
** during the build of millions of triangles stops it within ~0.1 s. */
static int stopped(builder *bd)
{
    if (!bd->failed && interrupt_count() != bd->seen)
        bd->failed = bd->cancelled = 1;
    return bd->failed;
}

static uint32_t new_node(builder *bd)
{
    tree2 *b = bd->b;
    if (b->nnodes == bd->cap) {
        size_t nc = bd->cap + bd->cap / 2 + 64;
        bvh2_node *p = mem_realloc(b->nodes, nc * sizeof *p);
        if (!p) {
            bd->failed = 1;
            return 0;
        }
        b->nodes = p;
        bd->cap = nc;
    }
    return (uint32_t)b->nnodes++;
}

/* What testing the item costs, in units of a sphere or triangle test. */
static float item_cost(const builder *bd, const item *it)
{
    return bd->cost ? bd->cost[it->id >> BVH_KIND_SHIFT] : 1;
}

static float centroid(const item *it, int k) { return 0.5f * it->lo[k] + 0.5f * it->hi[k]; }

/* The bin of an item's centroid; the comparisons come before the conversion,
** so an infinite or NaN product (bounds spanning all of float) is no UB. */
static int bin_of(const item *it, int axis, float lo, float scale)
{
    float x = (centroid(it, axis) - lo) * scale;
    return x >= BINS - 1 ? BINS - 1 : x > 0 ? (int)x : 0;
}

static void make_leaf(builder *bd, uint32_t ni, size_t begin, size_t n, const box3 *bounds)
{
    bvh2_node *node = &bd->b->nodes[ni];
    memcpy(node->lo, bounds->lo, sizeof node->lo);
    memcpy(node->hi, bounds->hi, sizeof node->hi);
    node->start = (uint32_t)begin;
    node->count = (uint16_t)n;
    node->axis = 0;
}

/* A side of a split grows by an item: its bounds and its centroid. */
static inline void grow_side(box3 *bounds, box3 *cb, const item *it)
{
    box_grow_item(bounds, it);
    box_grow_centroid(cb, it);
}

/* Bounds and centroid bounds of items[begin, end). */
static void measure(const builder *bd, size_t begin, size_t end, box3 *bounds, box3 *cb)
{
    box_empty(bounds);
    box_empty(cb);
    for (size_t i = begin; i < end; i++)
        grow_side(bounds, cb, &bd->items[i]);
}

/* The axis of cb's widest extent (the first of equal ones). */
static int widest_axis(const box3 *cb)
{
    int axis = 0;
    float ext[3];
    for (int k = 0; k < 3; k++)
        ext[k] = cb->hi[k] - cb->lo[k];
    if (ext[1] > ext[axis]) axis = 1;
    if (ext[2] > ext[axis]) axis = 2;
    return axis;
}

/* A few items costing no more than MIN_LEAF unit tests are a leaf;
** costlier ones (instances, curved placed shapes) are left to the SAH,
** which parts them when a node test is cheaper. All items of cost 1 give
** the tree the counts alone gave. */
static int cheap_leaf(const builder *bd, size_t begin, size_t end)
{
    if (end - begin > MIN_LEAF)
        return 0;
    float w = 0;
    for (size_t i = begin; i < end; i++)
        w += item_cost(bd, &bd->items[i]);
    return w <= MIN_LEAF;
}

/* Items binned along one axis by their centroids (bin_of's lo and scale):
** each bin's count and weight by cost (double: sums of 1 stay exact
** counts, so unit costs give the planes counts gave), and its bounds and
** centroid bounds: a side's are its bins', merged (min and max are exact
** in any order), so partitioning need not measure the sides again. */
typedef struct {
    int    axis;
    float  lo, scale;
    size_t count[BINS];
    double weight[BINS];
    box3   bin[BINS], cbin[BINS];
} binning;

static void bin_items(const builder *bd, size_t begin, size_t end, binning *bn)
{
    const item *items = bd->items;
    for (int i = 0; i < BINS; i++) {
        bn->count[i] = 0;
        bn->weight[i] = 0;
        box_empty(&bn->bin[i]);
        box_empty(&bn->cbin[i]);
    }
    if (bd->cost) {
        for (size_t i = begin; i < end; i++) {
            int bi = bin_of(&items[i], bn->axis, bn->lo, bn->scale);
            bn->count[bi]++;
            bn->weight[bi] += item_cost(bd, &items[i]);
            grow_side(&bn->bin[bi], &bn->cbin[bi], &items[i]);
        }
    } else {           /* all of cost 1: the weights are the counts */
        for (size_t i = begin; i < end; i++) {
            int bi = bin_of(&items[i], bn->axis, bn->lo, bn->scale);
            bn->count[bi]++;
            grow_side(&bn->bin[bi], &bn->cbin[bi], &items[i]);
        }
        for (int i = 0; i < BINS; i++)
            bn->weight[i] = (double)bn->count[i];
    }
}

/* The SAH's best of the BINS-1 planes between bins: the last bin of its
** left side (-1: none parts the items), its area-weighted cost in *best,
** the weight of all the items in *total. */
static int best_plane(const binning *bn, float *best, double *total)
{
    float rarea[BINS];
    double rweight[BINS], w = 0;
    size_t rcount[BINS], cnt = 0;
    box3 acc;
    box_empty(&acc);
    for (int i = BINS - 1; i > 0; i--) {
        box_merge(&acc, &bn->bin[i]);
        cnt += bn->count[i];
        w += bn->weight[i];
        rarea[i] = box_area(&acc);
        rcount[i] = cnt;
        rweight[i] = w;
    }
    *total = w + bn->weight[0];
    box_empty(&acc);
    cnt = 0;
    w = 0;
    *best = INFINITY;
    int split = -1;
    for (int i = 0; i < BINS - 1; i++) {
        box_merge(&acc, &bn->bin[i]);
        cnt += bn->count[i];
        w += bn->weight[i];
        if (cnt == 0 || rcount[i + 1] == 0)
            continue;
        float c = box_area(&acc) * (float)w + rarea[i + 1] * (float)rweight[i + 1];
        if (c < *best) {
            *best = c;
            split = i;
        }
    }
    return split;
}

/* The two sides of a split: their bounds and centroid bounds. */
typedef struct {
    box3 bounds[2], cb[2];
} sides;

static void sides_of_bins(const binning *bn, int split, sides *sd)
{
    for (int k = 0; k < 2; k++) {
        box_empty(&sd->bounds[k]);
        box_empty(&sd->cb[k]);
    }
    for (int k = 0; k < BINS; k++) {
        box_merge(&sd->bounds[k > split], &bn->bin[k]);
        box_merge(&sd->cb[k > split], &bn->cbin[k]);
    }
}

/* Items[begin, end) with their bins up to split first; returns where the
** others begin. Hoare's scheme: from both ends, swapping only pairs that
** are both misplaced. Swapping each right item with the last one, then
** reading the slot just written, stalled on store forwarding: half of
** building B2's 1M spheres, whose order is random. The sides are the
** same sets either way. */
static size_t partition(item *items, size_t begin, size_t end, const binning *bn, int split)
{
    size_t i = begin, j = end;
    for (;;) {
        while (i < j && bin_of(&items[i], bn->axis, bn->lo, bn->scale) <= split)
            i++;
        while (i < j && bin_of(&items[j - 1], bn->axis, bn->lo, bn->scale) > split)
            j--;
        if (i == j)
            break;
        item t = items[i];             /* items[i] goes right, items[j - 1] left */
        items[i] = items[j - 1];
        items[j - 1] = t;
        i++;
        j--;
    }
    return i;
}

/* How a node splits its items: at mid, with the sides' bounds (measured
** when the binning gave them). */
typedef struct {
    int    leaf, measured;
    size_t mid;
    sides  sd;
} plan;

/* Binned SAH along the widest centroid axis (extent ext > 0): of the
** BINS-1 planes, the one minimising area-weighted counts, unless a leaf
** is cheaper. */
static void plan_split(builder *bd, size_t begin, size_t end, const box3 *bounds,
                       const box3 *cb, int axis, plan *pl)
{
    size_t n = end - begin;
    float ext = cb->hi[axis] - cb->lo[axis];
    binning bn;
    bn.axis = axis;
    bn.lo = cb->lo[axis];
    bn.scale = BINS / ext;
    bin_items(bd, begin, end, &bn);
    float best;
    double total;
    int split = best_plane(&bn, &best, &total);
    float area = box_area(bounds);
    float cost = area > 0 ? TRAVERSAL_COST + best / area : INFINITY;
    if (split >= 0 && !(cost >= (float)total && n <= MAX_LEAF)) {
        sides_of_bins(&bn, split, &pl->sd);
        pl->mid = partition(bd->items, begin, end, &bn, split);
        pl->measured = 1;
    } else if (n <= MAX_LEAF) {
        pl->leaf = 1;
    }
}

static void build(builder *bd, uint32_t ni, size_t begin, size_t end, box3 bounds, box3 cb,
                  int depth);

/* Node ni as the interior node over items[begin, end) split at pl's mid:
** its two subtrees built, the first beside it. */
static void build_interior(builder *bd, uint32_t ni, size_t begin, size_t end,
                           const box3 *bounds, int axis, plan *pl, int depth)
{
    size_t mid = pl->mid;
    if (mid == begin || mid == end) {   /* no useful plane: halve by index */
        mid = begin + (end - begin) / 2;
        pl->measured = 0;
    }
    if (!pl->measured) {
        measure(bd, begin, mid, &pl->sd.bounds[0], &pl->sd.cb[0]);
        measure(bd, mid, end, &pl->sd.bounds[1], &pl->sd.cb[1]);
    }
    uint32_t left = new_node(bd);
    if (bd->failed)
        return;
    build(bd, left, begin, mid, pl->sd.bounds[0], pl->sd.cb[0], depth + 1);
    uint32_t right = new_node(bd);
    if (bd->failed)
        return;
    build(bd, right, mid, end, pl->sd.bounds[1], pl->sd.cb[1], depth + 1);
    bvh2_node *node = &bd->b->nodes[ni];   /* the array may have moved */
    memcpy(node->lo, bounds->lo, sizeof node->lo);
    memcpy(node->hi, bounds->hi, sizeof node->hi);
    node->start = right;
    node->count = 0;
    node->axis = (uint16_t)axis;
}

/* Builds the subtree for items[begin, end) into node ni: a leaf, or split
** as plan_split says (two passes over the items per level: binning, which
** measures the bins, then partitioning). */
static void build(builder *bd, uint32_t ni, size_t begin, size_t end, box3 bounds, box3 cb,
                  int depth)
{
    size_t n = end - begin;
    if ((n >= 65536 || (bd->b->nnodes & 255) == 0) && stopped(bd))
        return;
    int axis = widest_axis(&cb);
    plan pl;                /* pl.sd: set where pl.measured is, or measured later */
    pl.leaf = depth >= BVH_MAX_DEPTH;
    pl.measured = 0;
    pl.mid = begin;
    if (!pl.leaf)
        pl.leaf = cheap_leaf(bd, begin, end);
    if (!pl.leaf && cb.hi[axis] - cb.lo[axis] > 0)
        plan_split(bd, begin, end, &bounds, &cb, axis, &pl);
    else if (!pl.leaf && n <= MAX_LEAF)
        pl.leaf = 1;         /* all centroids coincide: nothing to gain */
    if (pl.leaf && n <= 0xffff) {
        make_leaf(bd, ni, begin, n, &bounds);
        return;
    }
    build_interior(bd, ni, begin, end, &bounds, axis, &pl, depth);
}

/* The top split's second half is built on its own thread into its own node
** array, then appended: both cores work on large builds. */
typedef struct {
    builder bd;
    size_t  begin, end;
    box3    bounds, cb;
} job;

static void *build_job(void *arg)
{
    job *j = arg;
    measure(&j->bd, j->begin, j->end, &j->bounds, &j->cb);    /* while the other half is */
    j->bd.b->nnodes = 1;
    build(&j->bd, 0, j->begin, j->end, j->bounds, j->cb, 1);
    return NULL;
}

#define PARALLEL_MIN 100000   /* below this a thread costs more than it saves */

/* Bounds beyond float are clamped to its largest values, so centroids stay
** finite (an infinite bound once made a NaN centroid, and the split loops
** never ended). The coordinate range keeps real shapes well inside. */
static float clamp_lo(float lo)
{
    lo = lo >= -FLT_MAX ? lo : -FLT_MAX;      /* NaN too */
    return lo > FLT_MAX ? FLT_MAX : lo;
}

static float clamp_hi(float hi)
{
    hi = hi <= FLT_MAX ? hi : FLT_MAX;
    return hi < -FLT_MAX ? -FLT_MAX : hi;
}

/* Whether an item's six bounds are finite: those clamping keeps. */
static inline int item_finite(const item *it)
{
#if defined(__SSE2__)
    const __m128 abs = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)), top = _mm_set1_ps(FLT_MAX);
    __m128 a = _mm_and_ps(item_lo(it), abs), b = _mm_and_ps(item_hi(it), abs);
    return _mm_movemask_ps(_mm_and_ps(_mm_cmple_ps(a, top), _mm_cmple_ps(b, top))) == 15;
#else
    for (int k = 0; k < 3; k++)
        if (!(fabsf(it->lo[k]) <= FLT_MAX && fabsf(it->hi[k]) <= FLT_MAX))
            return 0;
    return 1;
#endif
}

/* One pass over all the items: clamps their bounds, measures them (as
** measure() does) and returns the kinds among them (bit id >> BVH_KIND_SHIFT). */
static uint32_t prepare(item *items, size_t n, box3 *bounds, box3 *cb)
{
    uint32_t kinds = 0;
    box_empty(bounds);
    box_empty(cb);
    for (size_t i = 0; i < n; i++) {
        item *it = &items[i];
        kinds |= 1u << (it->id >> BVH_KIND_SHIFT);
        if (!item_finite(it))          /* rare: what clamping changes */
            for (int k = 0; k < 3; k++) {
                it->lo[k] = clamp_lo(it->lo[k]);
                it->hi[k] = clamp_hi(it->hi[k]);
            }
        grow_side(bounds, cb, it);
    }
    return kinds;
}

/* cost, or NULL when every kind among the items costs 1 (the build then
** bins without weighing: the same planes, B3 4M's bins a tenth faster). */
static const float *cost_in_use(const float *cost, uint32_t kinds)
{
    for (unsigned k = 0; cost && k < BVH_KINDS; k++)
        if ((kinds >> k & 1) && cost[k] != 1)
            return cost;
    return NULL;
}

lc_status bvh_build(bvh *out, bvh_item *items, size_t n, sig_atomic_t interrupts_seen,
                    lc_error *err)
{
    return bvh_build_costed(out, items, n, NULL, interrupts_seen, err);
}

/* Quickselect on the centroids along axis: items[0, mid) then lie at or
** below items[mid, n), so the halves split space, not order. Stops early
** when the build is cancelled. */
static void select_median(builder *bd, size_t n, size_t mid, int axis)
{
    item *items = bd->items;
    size_t lo = 0, hi = n;
    while (hi - lo > 1 && !stopped(bd)) {
        float pivot = centroid(&items[lo + (hi - lo) / 2], axis);
        size_t i = lo, j = hi;
        while (i < j) {
            if (centroid(&items[i], axis) < pivot) {
                i++;
            } else {
                item t = items[i];
                items[i] = items[--j];
                items[j] = t;
            }
        }
        size_t eq = i;          /* [lo, i) < pivot; gather == pivot next */
        for (size_t k = i; k < hi; k++)
            if (centroid(&items[k], axis) == pivot) {
                item t = items[k];
                items[k] = items[eq];
                items[eq++] = t;
            }
        if (mid < i) hi = i;
        else if (mid >= eq) lo = eq;
        else break;
    }
}

/* Appends the right half's nodes rb to the tree (its interior nodes point
** within it) and makes the root the interior node over both halves; 0
** when out of memory. */
static int append_half(tree2 *b, const tree2 *rb, const box3 *all, int axis)
{
    size_t off = b->nnodes;
    bvh2_node *p = mem_realloc(b->nodes, (off + rb->nnodes) * sizeof *p);
    if (!p)
        return 0;
    b->nodes = p;
    for (size_t i = 0; i < rb->nnodes; i++) {
        p[off + i] = rb->nodes[i];
        if (p[off + i].count == 0)
            p[off + i].start += (uint32_t)off;
    }
    b->nnodes += rb->nnodes;
    bvh2_node *root = &b->nodes[0];
    memcpy(root->lo, all->lo, sizeof root->lo);
    memcpy(root->hi, all->hi, sizeof root->hi);
    root->start = (uint32_t)off;
    root->count = 0;
    root->axis = (uint16_t)axis;
    return 1;
}

/* The root split as build() would, by the median of the widest centroid
** axis, each half handed to a thread; failures into bd. */
static void build_halves(builder *bd, size_t n, const box3 *all, const box3 *cb)
{
    int axis = widest_axis(cb);
    size_t mid = n / 2;
    select_median(bd, n, mid, axis);
    box3 lb, lcb;
    job right;
    memset(&right, 0, sizeof right);
    tree2 rb;
    memset(&rb, 0, sizeof rb);
    right.bd.b = &rb;
    right.bd.cap = (n - mid) / 3 + 64;
    right.bd.items = bd->items;
    right.bd.seen = bd->seen;
    right.bd.cost = bd->cost;
    right.begin = mid;
    right.end = n;
    if (stopped(bd))
        right.bd.failed = right.bd.cancelled = 1;   /* neither half is built */
    rb.nodes = right.bd.failed ? NULL : mem_alloc(right.bd.cap * sizeof *rb.nodes);
    pthread_t th;
    int threaded = rb.nodes && pthread_create(&th, NULL, build_job, &right) == 0;
    if (rb.nodes && !threaded)
        build_job(&right);
    measure(bd, 0, mid, &lb, &lcb);
    uint32_t left = new_node(bd);
    if (!bd->failed)
        build(bd, left, 0, mid, lb, lcb, 1);
    if (threaded)
        pthread_join(th, NULL);
    if (!rb.nodes || right.bd.failed) {
        bd->failed = 1;
        bd->cancelled |= right.bd.cancelled;
    } else if (!append_half(bd->b, &rb, all, axis)) {
        bd->failed = 1;
    }
    mem_free(rb.nodes);
}

static lc_status build_failed(lc_error *err, int cancelled, size_t n)
{
    if (cancelled)
        return error_fail(err, LC_ECANCEL, NULL, "render cancelled");
    return error_fail(err, LC_ENOMEM, NULL, "out of memory building a BVH over %zu "
                      "primitives", n);
}

/* The built tree made the wide one in *out: the items' order is the
** leaves' order, of which refs keep only the ids, in place. */
static lc_status finish(bvh *out, tree2 *b, item *items, size_t n, lc_error *err)
{
    uint32_t *refs = (uint32_t *)(void *)items;
    for (size_t i = 0; i < n; i++) {
        uint32_t id = items[i].id;
        refs[i] = id;
    }
    uint32_t *fit = mem_realloc(refs, n * sizeof *fit);
    out->refs = fit ? fit : refs;
    out->nrefs = n;
    bvh2_node *bfit = mem_realloc(b->nodes, b->nnodes * sizeof *bfit);
    if (bfit)                 /* the slack returned before the wide nodes come */
        b->nodes = bfit;
    lc_status st = bvh_collapse(out, b->nodes, b->nnodes);
    mem_free(b->nodes);
    if (st) {
        bvh_free(out);
        return build_failed(err, 0, n);
    }
    return LC_OK;
}

lc_status bvh_build_costed(bvh *out, bvh_item *items, size_t n, const float *cost,
                           sig_atomic_t interrupts_seen, lc_error *err)
{
    memset(out, 0, sizeof *out);
    if (n == 0) {
        mem_free(items);
        return LC_OK;
    }
    if (n > 0xffffffffu) {
        mem_free(items);
        return error_fail(err, LC_EARG, NULL, "too many primitives: %zu", n);
    }
    tree2 tree = {NULL, 0}, *b = &tree;
    box3 all, cb;
    cost = cost_in_use(cost, prepare(items, n, &all, &cb));
    builder bd = {b, n / 3 + 64, items, 0, 0, interrupts_seen, cost};
    b->nodes = mem_alloc(bd.cap * sizeof *b->nodes);
    if (!b->nodes) {
        mem_free(items);
        return build_failed(err, 0, n);
    }
    b->nnodes = 1;
    if (n < PARALLEL_MIN)
        build(&bd, 0, 0, n, all, cb, 0);
    else
        build_halves(&bd, n, &all, &cb);
    if (bd.failed || stopped(&bd)) {
        mem_free(items);
        mem_free(b->nodes);
        return build_failed(err, bd.cancelled, n);
    }
    return finish(out, b, items, n, err);
}

void bvh_free(bvh *b)
{
    mem_free(b->block);
    mem_free(b->refs);
    memset(b, 0, sizeof *b);
}
