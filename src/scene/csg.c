/* csg.c: CSG trees: their checks, building, bounds, and the interval sweep
** that finds where a ray meets the set they describe. */
#include <stdlib.h>
#include <string.h>
#include "shapes/cone.h"
#include "csg.h"
#include "shapes/cylinder.h"
#include "shapes/ellipsoid.h"
#include "base/error.h"
#include "base/mem.h"
#include "mesh.h"
#include "shapes/shape.h"
#include "shapes/torus.h"

static const char *const op_names[LC_CSG_OPS] = {
    [LC_CSG_SHAPE] = "shape", [LC_CSG_MESH] = "mesh", [LC_CSG_UNION] = "union",
    [LC_CSG_INTERSECTION] = "intersection", [LC_CSG_DIFFERENCE] = "difference",
    [LC_CSG_MERGE] = "merge"};

const char *lc_csg_op_name(lc_csg_op op)
{
    return (unsigned)op < LC_CSG_OPS ? op_names[op] : "?";
}

static int is_leaf(lc_csg_op op) { return op == LC_CSG_SHAPE || op == LC_CSG_MESH; }

/* ---- checks -------------------------------------------------------------------- */

/* Whether a shape bounds a solid: the open ones (planes, quads, discs,
** cylinders and cones without caps) have no inside. */
static int closed_kind(const lc_shape *s)
{
    switch (s->kind) {
    case LC_SPHERE: case LC_BOX: case LC_TORUS: case LC_ELLIPSOID:
        return 1;
    case LC_CYLINDER: case LC_CONE:
        return s->caps != 0;
    default:
        return 0;
    }
}

/* err's message, prefixed by "node i: " when the tree has more than one. */
static lc_status at_node(lc_error *err, size_t i, size_t n, lc_status st)
{
    if (n > 1)
        error_prefix(err, "node %zu: ", i);
    return st;
}

static lc_status check_leaf(const lc_csg_node *nd, lc_error *err)
{
    if (nd->op == LC_CSG_SHAPE) {
        if (lc_shape_check(&nd->shape, err))
            return LC_EARG;
        if (!closed_kind(&nd->shape)) {
            int axial = nd->shape.kind == LC_CYLINDER || nd->shape.kind == LC_CONE;
            return error_fail(err, LC_EARG, "shape", "a %s%s is not a closed solid",
                              lc_shape_kind_name(nd->shape.kind),
                              axial ? " without caps" : "");
        }
        return LC_OK;
    }
    if (!nd->mesh)
        return error_fail(err, LC_EARG, "mesh", "a mesh leaf needs a mesh, got NULL");
    if (lc_transform_check(&nd->transform, err))
        return LC_EARG;
    return csg_mesh_check(nd->mesh, nd->mesh->nf, NULL, err);
}

lc_status lc_csg_check(const lc_csg_node *nodes, size_t n, lc_error *err)
{
    if (!nodes || n == 0)
        return error_fail(err, LC_EARG, "nodes", "a CSG object needs at least one node");
    if (n > LC_CSG_MAX_NODES)
        return error_fail(err, LC_EARG, "nodes", "a CSG object has at most %d nodes, "
                          "got %zu", LC_CSG_MAX_NODES, n);
    size_t need = 1;                   /* subtrees still to read */
    for (size_t i = 0; i < n; i++) {
        const lc_csg_node *nd = &nodes[i];
        if (need == 0)
            return error_fail(err, LC_EARG, "nodes", "node %zu lies past the end of "
                              "the tree, which the root's operands close at node %zu",
                              i, i - 1);
        need--;
        if ((unsigned)nd->op >= LC_CSG_OPS)
            return error_fail(err, LC_EARG, "op", "node %zu: unknown operation %d", i,
                              (int)nd->op);
        if (is_leaf(nd->op)) {
            lc_status st = check_leaf(nd, err);
            if (st)
                return at_node(err, i, n, st);
        } else {
            if (nd->count < 1)
                return error_fail(err, LC_EARG, "count", "node %zu: a %s needs at least "
                                  "one operand, got %d", i, lc_csg_op_name(nd->op),
                                  nd->count);
            need += (size_t)nd->count;
        }
    }
    if (need)
        return error_fail(err, LC_EARG, "nodes", "the tree ends after node %zu with %zu "
                          "operand%s still to come", n - 1, need, need == 1 ? "" : "s");
    error_ok(err);
    return LC_OK;
}

/* ---- building ------------------------------------------------------------------ */

static void box_union(csg_box *a, const csg_box *b)
{
    for (int k = 0; k < 3; k++) {
        if (b->lo[k] < a->lo[k]) a->lo[k] = b->lo[k];
        if (b->hi[k] > a->hi[k]) a->hi[k] = b->hi[k];
    }
}

static void box_intersect(csg_box *a, const csg_box *b)
{
    for (int k = 0; k < 3; k++) {
        if (b->lo[k] > a->lo[k]) a->lo[k] = b->lo[k];
        if (b->hi[k] < a->hi[k]) a->hi[k] = b->hi[k];
        if (a->hi[k] < a->lo[k])   /* empty: flat, where the sweep finds nothing */
            a->hi[k] = a->lo[k];
    }
}

/* World bounds of a mesh leaf: its object box's corners through the map,
** widened by the round trip's slack (as instance.c bounds instances). */
static void mesh_box(const csg_mesh *cm, const affine *xf, csg_box *b)
{
    bvh_bounds_empty(b->lo, b->hi);
    if (!xf) {
        bvh_bounds_exact(b->lo, b->hi, cm->lo);
        bvh_bounds_exact(b->lo, b->hi, cm->hi);
        return;
    }
    lc_vec3 big = v3(0, 0, 0);
    lc_vec3 w[8];
    for (int c = 0; c < 8; c++) {
        lc_vec3 p = v3(c & 1 ? cm->hi[0] : cm->lo[0], c & 2 ? cm->hi[1] : cm->lo[1],
                       c & 4 ? cm->hi[2] : cm->lo[2]);
        w[c] = lc_transform_point(&xf->xf, p);
        lc_vec3 a = v3_abs(w[c]);
        big = v3(max2(big.x, a.x), max2(big.y, a.y), max2(big.z, a.z));
    }
    lc_vec3 e = v3_add(affine_slack(xf, big), v3_mul(big, vec_gamma(4)));
    for (int c = 0; c < 8; c++) {
        bvh_bounds_grow(b->lo, b->hi, v3_sub(w[c], e));
        bvh_bounds_grow(b->lo, b->hi, v3_add(w[c], e));
    }
}

void csg_free(csg_tree *t)
{
    if (!t)
        return;
    for (size_t i = 0; i < t->nleaves; i++) {
        csg_mesh_release(t->leaves[i].mesh);
        mem_free(t->leaves[i].xf);
    }
    for (size_t i = 0; t->desc && i < t->n; i++)
        if (t->desc[i].op == LC_CSG_MESH)
            lc_mesh_free(t->desc[i].mesh);
    mem_free(t->desc);
    mem_free(t->nodes);
    mem_free(t->leaves);
    mem_free(t->roots);
    mem_free(t);
}

/* A mesh leaf's shared BVH: one already built for this mesh as it is now,
** or a new one. */
static csg_mesh *find_mesh(lc_mesh *m, csg_tree *const *trees, size_t ntrees,
                           lc_error *err)
{
    for (size_t i = 0; i < ntrees; i++)
        for (size_t j = 0; j < trees[i]->nleaves; j++) {
            csg_mesh *cm = trees[i]->leaves[j].mesh;
            if (cm && cm->mesh == m && cm->nf == m->nf) {
                cm->refs++;
                return cm;
            }
        }
    return csg_mesh_new(m, err);
}

/* One sweep's state for a leaf (below), and what a tree's sweep needs. */
typedef struct csg_cursor csg_cursor;
static size_t scratch_size(size_t n, size_t nleaves, size_t nmesh);

/* Sets up leaf lf from node nd. */
static lc_status make_leaf(csg_leaf *lf, const lc_csg_node *nd, csg_tree *const *trees,
                           size_t ntrees, lc_error *err)
{
    lf->material = nd->material;
    lf->cut_from = -1;
    if (nd->op == LC_CSG_SHAPE) {
        lf->kind = nd->shape.kind;
        lf->convex = nd->shape.kind != LC_TORUS;
        lf->boxed = nd->shape.kind != LC_SPHERE && nd->shape.kind != LC_BOX;
        shape_prepare(&nd->shape, &lf->g);
        shape_bounds(nd->shape.kind, &lf->g, lf->box.lo, lf->box.hi);
        return LC_OK;
    }
    lf->kind = LC_SHAPE_KINDS;
    lf->convex = 0;
    lf->boxed = 1;
    if (!lc_transform_is_identity(&nd->transform)) {
        lf->xf = mem_alloc(sizeof *lf->xf);
        if (!lf->xf)
            return error_fail(err, LC_ENOMEM, NULL, "out of memory adding a CSG object");
        if (affine_make(&nd->transform, lf->xf, err))
            return LC_EARG;
    }
    lf->mesh = find_mesh(nd->mesh, trees, ntrees, err);
    if (!lf->mesh)
        return err ? err->code : LC_ENOMEM;
    mesh_box(lf->mesh, lf->xf, &lf->box);
    return LC_OK;
}

csg_tree *csg_build(const lc_csg_node *nodes, size_t n, csg_tree *const *trees,
                    size_t ntrees, lc_error *err)
{
    if (lc_csg_check(nodes, n, err))
        return NULL;
    size_t nleaves = 0;
    for (size_t i = 0; i < n; i++)
        nleaves += is_leaf(nodes[i].op);
    csg_tree *t = mem_calloc(1, sizeof *t);
    if (!t || !(t->desc = mem_calloc(n, sizeof *t->desc)) ||
        !(t->nodes = mem_calloc(n, sizeof *t->nodes)) ||
        !(t->leaves = mem_calloc(nleaves, sizeof *t->leaves)) ||
        !(t->roots = mem_calloc(n, sizeof *t->roots))) {
        csg_free(t);
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a CSG object of %zu "
                   "nodes", n);
        return NULL;
    }
    /* The description as stored: shapes as a scene lists them. */
    for (size_t i = 0; i < n; i++) {
        lc_csg_node d = nodes[i];
        if (d.op == LC_CSG_SHAPE) {
            lc_shape_stored(&nodes[i].shape, &d.shape, NULL);
        } else if (d.op == LC_CSG_MESH) {
            mesh_retain(d.mesh);
        } else {
            d.material = 0;
        }
        if (d.op != LC_CSG_MESH)
            d.mesh = NULL, d.transform = lc_transform_identity();
        t->desc[t->n++] = d;
    }
    /* Leaves in order, then each node's subtree, bottom-up. */
    size_t leaf = 0;
    for (size_t i = 0; i < n; i++) {
        csg_node *nd = &t->nodes[i];
        nd->op = nodes[i].op;
        nd->count = nodes[i].count;
        if (!is_leaf(nd->op))
            continue;
        csg_leaf *lf = &t->leaves[leaf];
        lf->node = (int)i;
        t->nleaves = ++leaf;
        t->nmesh += nd->op == LC_CSG_MESH;
        if (make_leaf(lf, &t->desc[i], trees, ntrees, err)) {
            csg_free(t);
            return NULL;
        }
        nd->leaf0 = (int)leaf - 1;
        nd->leaf1 = (int)leaf;
        nd->end = (int)i + 1;
        nd->box = lf->box;
    }
    for (size_t i = n; i-- > 0;) {
        csg_node *nd = &t->nodes[i];
        if (is_leaf(nd->op))
            continue;
        int j = (int)i + 1;
        nd->leaf0 = t->nodes[j].leaf0;
        nd->box = t->nodes[j].box;
        for (int k = 0; k < nd->count; k++) {
            const csg_node *c = &t->nodes[j];
            if (k > 0 && (nd->op == LC_CSG_UNION || nd->op == LC_CSG_MERGE))
                box_union(&nd->box, &c->box);
            else if (k > 0 && nd->op == LC_CSG_INTERSECTION)
                box_intersect(&nd->box, &c->box);
            nd->leaf1 = c->leaf1;
            nd->end = c->end;
            j = c->end;
        }
    }
    /* Top down: the group unions, the subtrees swept on their own, and where
    ** each leaf's cut faces take their material (the nearest difference
    ** that cuts with it decides). */
    t->nodes[0].group = t->nodes[0].op == LC_CSG_UNION;
    if (!t->nodes[0].group)
        t->roots[t->nroots++] = 0;
    for (size_t i = 0; i < n; i++) {
        const csg_node *nd = &t->nodes[i];
        int j = (int)i + 1;
        for (int k = 0; k < nd->count; k++) {
            csg_node *c = &t->nodes[j];
            if (nd->group && c->op == LC_CSG_UNION)
                c->group = 1;
            else if (nd->group)
                t->roots[t->nroots++] = j;
            if (nd->op == LC_CSG_DIFFERENCE && k > 0)
                for (int l = c->leaf0; l < c->leaf1; l++)
                    t->leaves[l].cut_from = nodes[i].cut_object ? (int)i + 1 : -1;
            j = c->end;
        }
    }
    t->scratch = scratch_size(n, t->nleaves, t->nmesh);
    error_ok(err);
    return t;
}

void csg_materials(const csg_tree *t, uint16_t *used)
{
    for (size_t i = 0; i < t->nleaves; i++)
        used[t->leaves[i].material] = 1;
}

void csg_bounds(const csg_tree *t, float lo[3], float hi[3])
{
    memcpy(lo, t->nodes[0].box.lo, sizeof t->nodes[0].box.lo);
    memcpy(hi, t->nodes[0].box.hi, sizeof t->nodes[0].box.hi);
}

void csg_name_hit(const csg_tree *t, const hit *h, lc_ray_record *x)
{
    x->csg = (int)x->shape;
    x->shape = -1;
    x->csg_node = (int)h->instance - 1;
    const lc_csg_node *d = &t->desc[x->csg_node];
    x->shape_kind = d->op == LC_CSG_SHAPE ? (int)d->shape.kind : LC_SHAPE_KINDS;
}

/* The leaf a hit on t is on: its node rides in h->instance. */
static const csg_leaf *leaf_of(const csg_tree *t, const hit *h)
{
    int node = (int)h->instance - 1;
    for (size_t i = 0; i < t->nleaves; i++)
        if (t->leaves[i].node == node)
            return &t->leaves[i];
    return NULL;
}

int csg_hit_kind(const csg_tree *t, const hit *h)
{
    const csg_leaf *lf = leaf_of(t, h);
    return lf ? lf->kind : LC_SHAPE_KINDS;
}

void csg_hit_uv(const csg_tree *t, const hit *h, double uv[2])
{
    const csg_leaf *lf = leaf_of(t, h);
    uv[0] = uv[1] = 0;
    if (lf && lf->kind != LC_SHAPE_KINDS)
        shape_uv((lc_shape_kind)lf->kind, &lf->g, h->p, uv);
}

lc_vec3 csg_hit_object_point(const csg_tree *t, const hit *h)
{
    const csg_leaf *lf = leaf_of(t, h);
    if (!lf)
        return h->p;
    if (lf->kind == LC_SHAPE_KINDS)
        return lf->xf ? lc_transform_point(&lf->xf->inv, h->p) : h->p;
    if (lf->kind < LC_DISC || lf->kind > LC_ELLIPSOID || !lf->g.p.shape.moved)
        return h->p;
    lc_transform inv;
    if (lc_transform_inverse(&lf->g.p.shape.xf, &inv, NULL))
        return h->p;
    return lc_transform_point(&inv, h->p);
}

/* ---- the sweep ------------------------------------------------------------------ */

/* Along the ray, each leaf's crossings come in order from its own hit test,
** asked again each time with tmin just past the previous root (a mesh
** leaf's from its BVH, all at once). Crossings of one leaf within each
** other's error bound form a run; a run that goes in (its first and last
** trusted senses in) or out is an event, one that goes in and out (a
** tangent, a mesh silhouette's edge) is a touch, and dropped. A leaf is
** inside wherever its next event is an exit: so a duplicate crossing (a
** mesh edge hit by two faces) or a lost one (a tangent's double root)
** changes nothing. The sweep takes the nearest event, gathers every
** event of any leaf within reach of it (intervals of error overlapping),
** applies them together, evaluates the tree and stops at the first change:
** coincident faces (a cutter flush with a face, a sphere touching a box)
** are one event, decided once, with no film and no speckle. */

/* A mesh leaf queues this many crossings per search of its BVH. */
#define CSG_MESH_QUEUE 32

typedef struct {
    double t, e;
    int    sense;       /* +1 in, -1 out, 0 graze */
    int    mesh;        /* a mesh leaf's: mc holds it, h is made on demand */
    csg_mesh_cross mc;
    hit    h;
} csg_cross;

struct csg_cursor {
    csg_cross slot[3];  /* by number: */
    unsigned char ev;   /* the next event's crossing (the first of its sense) */
    unsigned char got;  /* the last event taken by a group */
    unsigned char peek; /* the crossing after ev's run, when read */
    double lo, hi;      /* ev's reach: its run's crossings, give or take their errors */
    double after;       /* the leaf's crossings beyond this are still to read */
    int    live;        /* ev holds an event */
    int    sense;       /* ev's: +1 in, -1 out */
    int    peeked;      /* 1: peek holds a crossing; 0: none read; -1: no more */
    int    done;        /* the leaf's hit test has no more */
    csg_mesh_cross *queue;   /* mesh leaves: crossings read, queue[at, nq) */
    size_t at, nq;
    int    more;        /* the queue was full: more may lie beyond */
    placed_ray pr;      /* tori: the canonical ray and its roots, roots[at, nq) */
    double roots[4];
};

/* One query's state: the cursors, the leaves' insides before and after a
** group, who is in it, the evaluation's stack. */
typedef struct {
    const csg_tree *t;
    const ray *r;
    const bvh_ray *b;
    csg_cursor *cur;
    unsigned char *state, *pre, *member, *stack;
    int changed;        /* leaves whose inside the group changed */
    uint64_t tests, nodes;
} sweep;

static size_t align16(size_t x) { return (x + 15) & ~(size_t)15; }

static size_t scratch_size(size_t n, size_t nleaves, size_t nmesh)
{
    return align16(nleaves * sizeof(csg_cursor)) +
           align16(nmesh * CSG_MESH_QUEUE * sizeof(csg_mesh_cross)) +
           align16(3 * nleaves + n);
}

static void sweep_init(sweep *x, const csg_tree *t, const ray *r, const bvh_ray *b,
                       unsigned char *mem)
{
    x->t = t;
    x->r = r;
    x->b = b;
    x->cur = (csg_cursor *)(void *)mem;
    mem += align16(t->nleaves * sizeof(csg_cursor));
    csg_mesh_cross *q = (csg_mesh_cross *)(void *)mem;
    mem += align16(t->nmesh * CSG_MESH_QUEUE * sizeof(csg_mesh_cross));
    for (size_t i = 0; t->nmesh && i < t->nleaves; i++)
        if (t->leaves[i].mesh) {
            x->cur[i].queue = q;
            q += CSG_MESH_QUEUE;
        }
    x->state = mem;
    x->pre = mem + t->nleaves;
    x->member = mem + 2 * t->nleaves;
    x->stack = mem + 3 * t->nleaves;
    x->tests = x->nodes = 0;
}

/* A shape leaf's nearest crossing beyond `after`. */
static int shape_cross(const csg_leaf *lf, const ray *r, const double *inv, double after,
                       hit *h)
{
    switch (lf->kind) {
    case LC_SPHERE: return sphere_hit(&lf->g.s, r, after, HUGE_VAL, h);
    case LC_BOX: return box_hit_inv(&lf->g.b, r, inv, after, HUGE_VAL, h);
    case LC_CYLINDER: return cylinder_hit(&lf->g.p, r, after, HUGE_VAL, h);
    case LC_CONE: return cone_hit(&lf->g.p, r, after, HUGE_VAL, h);
    case LC_TORUS: return torus_hit(&lf->g.p, r, after, HUGE_VAL, h);
    default: return ellipsoid_hit(&lf->g.p, r, after, HUGE_VAL, h);
    }
}

/* Leaf i's next crossing, in order; 0 when it has no more. */
static int next_cross(sweep *x, int i, csg_cross *out)
{
    csg_cursor *c = &x->cur[i];
    const csg_leaf *lf = &x->t->leaves[i];
    if (c->done)
        return 0;
    if (lf->mesh) {
        if (c->at == c->nq) {
            if (c->nq && !c->more) {
                c->done = 1;
                return 0;
            }
            csg_mesh_ray q;
            csg_mesh_ray_init(&q, lf->xf, x->r);
            c->nq = csg_mesh_crossings(lf->mesh, lf->xf, &q, x->r, c->after, c->queue,
                                       CSG_MESH_QUEUE, &c->more, &x->tests, &x->nodes);
            c->at = 0;
            if (c->nq == 0) {
                c->done = 1;
                return 0;
            }
        }
        const csg_mesh_cross *m = &c->queue[c->at++];
        out->t = m->t;
        out->e = m->e;
        out->sense = m->sense;
        out->mesh = 1;
        out->mc = *m;
        c->after = m->t;
        return 1;
    }
    if (lf->kind == LC_TORUS) {          /* the quartic once for all its roots */
        if (c->nq == 0 && c->at == 0) {
            x->tests++;
            c->nq = (size_t)torus_all_roots(&lf->g.p, x->r, 0, &c->pr, c->roots);
        }
        while (c->at < c->nq) {
            if (!torus_root_hit(&lf->g.p, &c->pr, c->roots[c->at++], &out->h))
                continue;
            out->t = out->h.t;
            out->mesh = 0;
            csg_cross_sense(x->r->d, &out->h, &out->sense, &out->e);
            c->after = out->t;
            return 1;
        }
        c->done = 1;
        return 0;
    }
    /* Distances come back through each kind's own scaling (a placed shape's
    ** canonical space): a root at `after` may come back as itself. Asked
    ** again from one ulp further, a few times, it cannot. */
    double from = c->after;
    for (int k = 0; k < 4; k++) {
        x->tests++;
        if (!shape_cross(lf, x->r, x->b->inv, from, &out->h))
            break;
        if (out->h.t > c->after) {
            out->t = out->h.t;
            out->mesh = 0;
            csg_cross_sense(x->r->d, &out->h, &out->sense, &out->e);
            c->after = out->t;
            /* A line leaves a convex solid once: nothing after its exit,
            ** and no need to ask. */
            c->done = lf->convex && out->sense < 0;
            return 1;
        }
        from = next_up(max2(from, out->h.t));
    }
    c->done = 1;
    return 0;
}

/* Leaf i's next event: runs of crossings read until one goes in or out.
** The cursor's three crossings move by their slot numbers, not copied. */
static void swap_slots(unsigned char *a, unsigned char *b)
{
    unsigned char t = *a;
    *a = *b;
    *b = t;
}

static void next_event(sweep *x, int i)
{
    csg_cursor *c = &x->cur[i];
    for (;;) {
        if (c->peeked == 1) {
            swap_slots(&c->ev, &c->peek);
            c->peeked = 0;
        } else if (c->peeked < 0 || !next_cross(x, i, &c->slot[c->ev])) {
            c->live = 0;
            c->peeked = -1;
            return;
        }
        const csg_cross *a = &c->slot[c->ev];
        double lo = a->t - a->e, hi = a->t + a->e;
        int first = a->sense, last = a->sense;
        for (;;) {
            const csg_cross *b = &c->slot[c->peek];
            if (!next_cross(x, i, &c->slot[c->peek])) {
                c->peeked = -1;
                break;
            }
            if (b->t - b->e > hi) {
                c->peeked = 1;
                break;
            }
            hi = max2(hi, b->t + b->e);
            if (b->sense) {
                if (!first) {           /* the first that goes somewhere stands for it */
                    first = b->sense;
                    swap_slots(&c->ev, &c->peek);
                }
                last = b->sense;
            }
        }
        if (first && first == last) {
            c->live = 1;
            c->sense = first;
            c->lo = lo;
            c->hi = hi;
            return;
        }
    }
}

/* The set the subtree at root describes, given the leaves' insides: in
** reverse prefix order each node finds its operands' values on the stack,
** the first on top. */
static int eval(const csg_tree *t, int root, const unsigned char *in,
                unsigned char *stack)
{
    int sp = 0;
    for (int i = t->nodes[root].end - 1; i >= root; i--) {
        const csg_node *nd = &t->nodes[i];
        if (is_leaf(nd->op)) {
            stack[sp++] = in[nd->leaf0];
            continue;
        }
        int v = stack[sp - 1], rest = 0;
        for (int k = 1; k < nd->count; k++) {
            int w = stack[sp - 1 - k];
            if (nd->op == LC_CSG_INTERSECTION)
                v &= w;
            else
                rest |= w;
        }
        if (nd->op == LC_CSG_DIFFERENCE)
            v = v && !rest;
        else if (nd->op != LC_CSG_INTERSECTION)
            v = v || rest;
        sp -= nd->count;
        stack[sp++] = (unsigned char)v;
    }
    return stack[0];
}

/* The surface a group that changed the set (from !inside to inside) shows:
** among the leaves whose inside changed, one whose change alone makes it
** (responsible), going the set's way (its own face, not a cut), first in
** the tree. A cutter flush with the object's face changes with it: the
** object's face is shown, as if the cutter were not there. */
static int pick(sweep *x, int root, int inside)
{
    const csg_node *rn = &x->t->nodes[root];
    int best = -1, best_score = -1;
    for (int i = rn->leaf0; i < rn->leaf1; i++) {
        if (!x->member[i] || x->pre[i] == x->state[i])
            continue;
        /* alone: with it as it was, the set would be too (said without
        ** evaluating when it is the only leaf that changed) */
        int alone = 1;
        if (x->changed > 1) {
            x->state[i] = x->pre[i];
            alone = eval(x->t, root, x->state, x->stack) != inside;
            x->state[i] = !x->pre[i];
        }
        int same = x->state[i] == inside;
        int score = 2 * alone + same;
        if (score > best_score) {
            best = i;
            best_score = score;
        }
    }
    return best;
}

/* Fills h for leaf i's crossing that changed the set to `inside`. */
static void finish(sweep *x, int i, int inside, uint32_t index, hit *h)
{
    const csg_tree *t = x->t;
    const csg_leaf *lf = &t->leaves[i];
    const csg_cross *c = &x->cur[i].slot[x->cur[i].got];
    if (c->mesh)
        csg_mesh_hit(lf->mesh, lf->xf, &c->mc, h);
    else
        *h = c->h;
    h->t = c->t;
    int same = x->state[i] == inside;
    int material = lf->material;
    if (!same) {
        /* A cut face: its normal points out of the result, into the leaf;
        ** its material the cutter's, or the object's leaf that holds it. */
        h->n = v3_neg(h->n);
        if (lf->cut_from >= 0) {
            const csg_node *ob = &t->nodes[lf->cut_from];
            const unsigned char *side = inside ? x->state : x->pre;
            material = t->leaves[ob->leaf0].material;
            for (int l = ob->leaf0; l < ob->leaf1; l++)
                if (side[l]) {
                    material = t->leaves[l].material;
                    break;
                }
        }
    }
    h->ns = h->n;
    h->material = material;
    h->shape = PRIM_ID(same && lf->convex ? PRIM_CSG_FACE : PRIM_CSG_CUT, index);
    h->instance = 1 + (uint32_t)lf->node;
}

/* Sweeps the subtree at root over (0, tmax): 1 when its set changes there
** (with `enter`, only to inside), leaving the leaf in *leaf and the set's
** new value in *inside. */
static int sweep_root(sweep *x, int root, double tmax, int enter, int *leaf, int *inside)
{
    const csg_tree *t = x->t;
    const csg_node *rn = &t->nodes[root];
    if (csg_box_enter(&rn->box, x->b, tmax) == HUGE_VAL)
        return 0;
    for (int i = rn->leaf0; i < rn->leaf1; i++) {
        csg_cursor *c = &x->cur[i];
        c->after = 0;
        c->peeked = 0;
        c->ev = 0;
        c->got = 1;
        c->peek = 2;
        c->at = c->nq = 0;
        c->more = 0;
        c->live = 0;
        /* A ray that meets a leaf's box only past tmax, if at all, does not
        ** start in it nor cross it before. (Spheres and boxes are as quick
        ** to test as their boxes.) */
        c->done = t->leaves[i].boxed &&
                  csg_box_enter(&t->leaves[i].box, x->b, tmax) == HUGE_VAL;
        if (!c->done)
            next_event(x, i);
        x->state[i] = c->live && c->sense < 0;
    }
    int f = eval(t, root, x->state, x->stack);
    for (;;) {
        int first = -1;
        for (int i = rn->leaf0; i < rn->leaf1; i++)
            if (x->cur[i].live && (first < 0 || x->cur[i].lo < x->cur[first].lo))
                first = i;
        if (first < 0 || !(x->cur[first].lo < tmax))
            return 0;
        double reach = x->cur[first].hi;
        for (int i = rn->leaf0; i < rn->leaf1; i++) {
            x->member[i] = 0;
            x->pre[i] = x->state[i];
        }
        for (int grew = 1; grew;) {
            grew = 0;
            for (int i = rn->leaf0; i < rn->leaf1; i++) {
                csg_cursor *c = &x->cur[i];
                while (c->live && c->lo <= reach) {
                    x->member[i] = 1;
                    swap_slots(&c->got, &c->ev);
                    reach = max2(reach, c->hi);
                    next_event(x, i);
                    grew = 1;
                }
            }
        }
        x->changed = 0;
        for (int i = rn->leaf0; i < rn->leaf1; i++)
            if (x->member[i]) {
                x->state[i] = x->cur[i].live && x->cur[i].sense < 0;
                x->changed += x->state[i] != x->pre[i];
            }
        int g = eval(t, root, x->state, x->stack);
        if (g != f) {
            int i = pick(x, root, g);
            if (i < 0) {                   /* cannot be: g depends on the leaves alone */
                f = g;
                continue;
            }
            if (!(x->cur[i].slot[x->cur[i].got].t < tmax))
                return 0;
            if (g || !enter) {
                *leaf = i;
                *inside = g;
                return 1;
            }
        }
        f = g;
    }
}

/* Scratch for a sweep: on the stack for small trees, else allocated. */
#define CSG_STACK_SCRATCH 16384

double csg_hit(const csg_tree *t, uint32_t index, const ray *r, const bvh_ray *b,
               double tmax, hit *h, bvh_counts *counts)
{
    union { double d; unsigned char c[CSG_STACK_SCRATCH]; } local;
    unsigned char *mem = t->scratch <= sizeof local ? local.c : malloc(t->scratch);
    if (!mem)                          /* no memory for the sweep: nothing seen */
        return 0;
    sweep x;
    sweep_init(&x, t, r, b, mem);
    double best = 0;
    for (size_t k = 0; k < t->nroots; k++) {
        int leaf, inside;
        if (!sweep_root(&x, t->roots[k], tmax, 0, &leaf, &inside))
            continue;
        finish(&x, leaf, inside, index, h);
        best = h->t;
        tmax = best;                   /* a later group operand must be nearer */
    }
    if (mem != local.c)
        free(mem);
    counts->csg += x.tests;
    counts->nodes += x.nodes;
    return best;
}

int csg_occluded(const csg_tree *t, const ray *r, const bvh_ray *b, double tmax,
                 bvh_counts *counts)
{
    union { double d; unsigned char c[CSG_STACK_SCRATCH]; } local;
    unsigned char *mem = t->scratch <= sizeof local ? local.c : malloc(t->scratch);
    if (!mem)
        return 0;
    sweep x;
    sweep_init(&x, t, r, b, mem);
    int found = 0;
    for (size_t k = 0; k < t->nroots && !found; k++) {
        int leaf, inside;
        found = sweep_root(&x, t->roots[k], tmax, 1, &leaf, &inside);
    }
    if (mem != local.c)
        free(mem);
    counts->csg += x.tests;
    counts->nodes += x.nodes;
    return found;
}
