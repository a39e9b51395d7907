/* bvh_wide.c: the wide nodes traversals read, collapsed from the binary tree. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "bvh.h"
#include "base/mem.h"
#include "base/pair.h"

/* ---- which box test ------------------------------------------------------------- */

int bvh_simd;
static int simd_best;                   /* what the processor can */
static pthread_once_t simd_once = PTHREAD_ONCE_INIT;

static void simd_decide(void)
{
#if BVH_HAVE_SIMD
    __builtin_cpu_init();
    /* Each checks that the OS saves the registers, too. */
    simd_best = __builtin_cpu_supports("avx512f") ? BVH_SIMD_AVX512 :
                __builtin_cpu_supports("avx") ? BVH_SIMD_AVX : BVH_SIMD_OFF;
#endif
    const char *e = getenv("LANCER_SIMD");
    bvh_simd = simd_best;
    if (e && strcmp(e, "0") == 0)
        bvh_simd = BVH_SIMD_OFF;
    else if (e && strcmp(e, "1") == 0 && bvh_simd > BVH_SIMD_AVX)
        bvh_simd = BVH_SIMD_AVX;
}

void bvh_simd_init(void)
{
    pthread_once(&simd_once, simd_decide);
}

int bvh_simd_set(int level)
{
    bvh_simd_init();
    int was = bvh_simd;
    bvh_simd = level < 0 ? BVH_SIMD_OFF : level < simd_best ? level : simd_best;
    return was;
}

/* ---- collapsing ------------------------------------------------------------------ */

static float half_area(const bvh2_node *n)
{
    float dx = n->hi[0] - n->lo[0], dy = n->hi[1] - n->lo[1], dz = n->hi[2] - n->lo[2];
    return dx * dy + dy * dz + dz * dx;
}

/* The binary nodes that become the children of the wide node for interior
** node ni: its two children, then while there is room the interior one of
** largest area replaced by its own two (Wald et al. 2008's collapse, as
** Embree makes its BVH4 and BVH8), kept in the binary tree's order.
** Returns how many (2..BVH_WIDTH). */
static int gather(const bvh2_node *bn, uint32_t ni, uint32_t kids[BVH_WIDTH])
{
    /* Each kid's area once (-1: a leaf, never opened), beside it: measured
    ** again at every look, they were half the time of collapsing B3 4M. */
    float area[BVH_WIDTH];
    int n = 2;
    kids[0] = ni + 1;
    kids[1] = bn[ni].start;
    for (int k = 0; k < 2; k++)
        area[k] = bn[kids[k]].count == 0 ? half_area(&bn[kids[k]]) : -1;
    while (n < BVH_WIDTH) {
        int best = -1;
        float ba = -1;
        for (int k = 0; k < n; k++)
            if (area[k] > ba) {
                ba = area[k];
                best = k;
            }
        if (best < 0)
            break;
        uint32_t x = kids[best];
        memmove(&kids[best + 2], &kids[best + 1], (size_t)(n - best - 1) * sizeof *kids);
        memmove(&area[best + 2], &area[best + 1], (size_t)(n - best - 1) * sizeof *area);
        kids[best] = x + 1;
        kids[best + 1] = bn[x].start;
        for (int k = best; k < best + 2; k++)
            area[k] = bn[kids[k]].count == 0 ? half_area(&bn[kids[k]]) : -1;
        n++;
    }
    return n;
}

typedef struct {
    const bvh2_node *bn;
    bvh_node *w;           /* NULL: only counting */
    size_t    n;
} collapser;

static void slot(bvh_node *w, int c, const bvh2_node *b)
{
    for (int k = 0; k < 3; k++) {
        w->lo[k][c] = b->lo[k];
        w->hi[k][c] = b->hi[k];
    }
}

/* Writes wide node w: the binary nodes kids[0, n) as its children, whose
** own wide nodes (or leaves) are child[]. */
static void write_node(bvh_node *w, const bvh2_node *bn, const uint32_t *kids,
                       const uint32_t *child, int n)
{
    memset(w, 0, sizeof *w);
    for (int c = 0; c < BVH_WIDTH; c++)
        for (int k = 0; k < 3; k++) {
            w->lo[k][c] = HUGE_VALF;      /* empty: no ray meets it */
            w->hi[k][c] = -HUGE_VALF;
        }
    for (int c = 0; c < n; c++) {
        slot(w, c, &bn[kids[c]]);
        w->child[c] = child[c];
        w->count[c] = bn[kids[c]].count;
    }
    w->n = (uint32_t)n;
}

/* Makes the wide node for binary node ni (interior, or a leaf at the root)
** and, depth first, those below it; returns its index. */
static uint32_t collapse(collapser *cl, uint32_t ni)
{
    const bvh2_node *bn = cl->bn;
    uint32_t kids[BVH_WIDTH];
    int n = 1;
    kids[0] = ni;
    if (bn[ni].count == 0)
        n = gather(bn, ni, kids);
    uint32_t wi = (uint32_t)cl->n++;
    uint32_t child[BVH_WIDTH] = {0};
    for (int c = 0; c < n; c++)
        child[c] = bn[kids[c]].count ? bn[kids[c]].start : collapse(cl, kids[c]);
    if (cl->w)
        write_node(&cl->w[wi], bn, kids, child, n);
    return wi;
}

/* The subtrees of the root's children kids[from, to), depth first from
** wide node `first` on (w NULL: only counted); `end` is where they stop. */
typedef struct {
    const bvh2_node *bn;
    bvh_node *w;
    const uint32_t *kids;
    int      from, to;
    size_t   first, end;
    uint32_t child[BVH_WIDTH];
} kids_job;

static void *collapse_kids(void *arg)
{
    kids_job *j = arg;
    collapser cl = {j->bn, j->w, j->first};
    for (int c = j->from; c < j->to; c++)
        j->child[c] = j->bn[j->kids[c]].count ? j->bn[j->kids[c]].start
                                              : collapse(&cl, j->kids[c]);
    j->end = cl.n;
    return NULL;
}

#define PARALLEL_COLLAPSE 100000   /* binary nodes; below, a thread costs more */

lc_status bvh_collapse(bvh *b, const bvh2_node *nodes, size_t n)
{
    bvh_simd_init();
    /* The root's children, halved between two threads by how many binary
    ** nodes lie under them: a subtree is a run of the array (depth first),
    ** so kids[c + 1] - kids[c] bounds kid c's. One thread: one half empty. */
    uint32_t kids[BVH_WIDTH] = {0};        /* a leaf root: itself */
    int nk = nodes[0].count ? 1 : gather(nodes, 0, kids);
    int h = 0;
    if (nodes[0].count == 0 && n >= PARALLEL_COLLAPSE)
        while (h < nk && kids[h] < n / 2)
            h++;
    /* Counted first, so the array is allocated once at its size. */
    kids_job a = {nodes, NULL, kids, 0, h, 0, 0, {0}};
    kids_job z = {nodes, NULL, kids, h, nk, 0, 0, {0}};
    int leaf = nodes[0].count > 0;          /* a root that is a leaf: one node */
    if (!leaf)
        pair_run(collapse_kids, &z, &a, a.from < a.to);
    size_t count = 1 + a.end + z.end;
    void *block = mem_alloc(count * sizeof(bvh_node) + 64);
    if (!block)
        return LC_ENOMEM;
    uintptr_t at = ((uintptr_t)block + 63) & ~(uintptr_t)63;   /* cache lines */
    bvh_node *w = (bvh_node *)at;
    uint32_t child[BVH_WIDTH] = {nodes[0].start};
    if (!leaf) {
        a.w = z.w = w;
        z.first = 1 + a.end;
        a.first = 1;
        pair_run(collapse_kids, &z, &a, a.from < a.to);
        for (int c = 0; c < nk; c++)
            child[c] = c < h ? a.child[c] : z.child[c];
    }
    write_node(w, nodes, kids, child, nk);
    b->block = block;
    b->nodes = w;
    b->nnodes = count;
    b->lone = count == 1 && w[0].n == 1 && w[0].count[0] > 0;
    return LC_OK;
}
