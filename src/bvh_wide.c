/* bvh_wide.c: the wide nodes traversals read, collapsed from the binary tree. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "bvh.h"
#include "mem.h"

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
    int n = 2;
    kids[0] = ni + 1;
    kids[1] = bn[ni].start;
    while (n < BVH_WIDTH) {
        int best = -1;
        float ba = -1;
        for (int k = 0; k < n; k++) {
            const bvh2_node *c = &bn[kids[k]];
            if (c->count == 0 && half_area(c) > ba) {
                ba = half_area(c);
                best = k;
            }
        }
        if (best < 0)
            break;
        uint32_t x = kids[best];
        memmove(&kids[best + 2], &kids[best + 1], (size_t)(n - best - 1) * sizeof *kids);
        kids[best] = x + 1;
        kids[best + 1] = bn[x].start;
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
    if (!cl->w)
        return wi;
    bvh_node *w = &cl->w[wi];
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
    return wi;
}

lc_status bvh_collapse(bvh *b, const bvh2_node *nodes, size_t n)
{
    (void)n;
    bvh_simd_init();
    /* Counted first, so the array is allocated once at its size. */
    collapser cl = {nodes, NULL, 0};
    collapse(&cl, 0);
    size_t count = cl.n;
    void *block = mem_alloc(count * sizeof(bvh_node) + 64);
    if (!block)
        return LC_ENOMEM;
    uintptr_t at = ((uintptr_t)block + 63) & ~(uintptr_t)63;   /* cache lines */
    cl.w = (bvh_node *)at;
    cl.n = 0;
    collapse(&cl, 0);
    b->block = block;
    b->nodes = cl.w;
    b->nnodes = count;
    b->lone = count == 1 && cl.w[0].n == 1 && cl.w[0].count[0] > 0;
    return LC_OK;
}
