/* intersect.c: nearest-hit and any-hit queries: infinite planes one by one,
** everything else through the BVH. */
#include "scene.h"

#define STACK 128   /* BVH depth is at most 64 plus halvings of oversized leaves */

typedef struct {
    const lc_ray *r;      /* a pointer: copying the ray stalled on store forwarding */
    double    o[3], inv[3];
    int       neg[3];
    tri_shear sh;
} query;

static void query_init(query *q, const lc_ray *r, int triangles)
{
    q->r = r;
    double d[3] = {r->d.x, r->d.y, r->d.z};
    q->o[0] = r->o.x;
    q->o[1] = r->o.y;
    q->o[2] = r->o.z;
    /* Exact reciprocals, one division each: the distances to axis planes,
    ** axis quads and aligned boxes all use them, so coplanar surfaces meet
    ** a ray at the same t, and faces sharing an edge leave no crack.
    ** (Making three from one division saved ~2 % and cost both.) */
    for (int k = 0; k < 3; k++)
        q->inv[k] = 1.0 / d[k];         /* +-inf for 0: wanted */
    for (int k = 0; k < 3; k++)
        q->neg[k] = q->inv[k] < 0;      /* from the reciprocal, so -0 counts */
    if (triangles)                      /* the shear only triangles use */
        tri_shear_init(r->d, &q->sh);
}

static inline double node_enter(const bvh_node *nd, const query *q, double tmax)
{
    return bvh_enter(nd, q->o, q->inv, q->neg, tmax);
}

/* Distance to primitive id along the query's ray, 0 for a miss. Spheres,
** boxes and planes compute the distance only (the nearest is finished
** later); quads and triangles need most of the work anyway to know they
** are hit, so they fill *full as they go. */
static inline double prim_t(const lc_scene *s, uint32_t id, const query *q, double tmax,
                     lc_hit *full, lc_counts *inner)
{
    uint32_t i = PRIM_INDEX(id);
    switch (PRIM_KIND(id)) {
    case PRIM_SPHERE:
        return sphere_t(&s->spheres[i].g, q->r, 0, tmax);
    case PRIM_BOX:
        return box_t(&s->boxes[i].g, q->r, q->inv, 0, tmax);
    case PRIM_PLANE:
        return plane_t(&s->planes[i].g, q->r, q->inv, 0, tmax);
    case PRIM_QUAD:
        if (!quad_hit_inv(&s->quads[i].g, q->r, q->inv, 0, tmax, full))
            return 0;
        full->material = s->quads[i].material;
        break;
    default: {
        const tri_ref *tr = &s->c.tris[i];
        const mesh_prim *mp = &s->meshes[tr->mesh];
        const uint32_t *f = mp->mesh->f + 3 * (size_t)tr->face;
        const double *v = mp->mesh->v;
        if (!tri_hit(v + 3 * (size_t)f[0], v + 3 * (size_t)f[1], v + 3 * (size_t)f[2],
                     q->r, &q->sh, 0, tmax, full, full->bary))
            return 0;
        full->material = mp->material;
        break;
    }
    case PRIM_INSTANCE:           /* a moved mesh: its own BVH, in its own space */
        return instance_hit(s, i, q->r, tmax, full, inner);
    }
    full->shape = id;
    full->instance = 0;
    return full->t;
}

/* Fills *h for the nearest hit found by prim_t (at distance t). */
static int prim_finish(const lc_scene *s, uint32_t id, const query *q, double t, lc_hit *h)
{
    uint32_t i = PRIM_INDEX(id);
    double tmax = next_up(t);               /* the same test finds the same t */
    int ok;
    switch (PRIM_KIND(id)) {
    case PRIM_SPHERE:
        ok = sphere_hit(&s->spheres[i].g, q->r, 0, tmax, h);
        h->material = s->spheres[i].material;
        break;
    case PRIM_BOX:
        ok = box_hit_inv(&s->boxes[i].g, q->r, q->inv, 0, tmax, h);
        h->material = s->boxes[i].material;
        break;
    case PRIM_PLANE:
        ok = plane_hit_inv(&s->planes[i].g, q->r, q->inv, 0, tmax, h);
        h->material = s->planes[i].material;
        break;
    default:
        return 1;                        /* already complete */
    }
    h->shape = id;
    h->instance = 0;
    return ok;
}

/* Interpolated vertex normals, where the mesh has them. */
static void shading_normal(const lc_scene *s, lc_hit *h)
{
    if (PRIM_KIND(h->shape) == PRIM_TRIANGLE && PRIM_INDEX(h->shape) >= s->c.nflat)
        return;                            /* an instance's: set in the world already */
    h->ns = h->n;
    if (PRIM_KIND(h->shape) != PRIM_TRIANGLE)
        return;
    const tri_ref *tr = &s->c.tris[PRIM_INDEX(h->shape)];
    const lc_mesh *m = s->meshes[tr->mesh].mesh;
    if (!m->n)
        return;
    const uint32_t *f = m->f + 3 * (size_t)tr->face;
    lc_vec3 n = v3(0, 0, 0);
    for (int k = 0; k < 3; k++) {
        const double *nk = m->n + 3 * (size_t)f[k];
        n = v3_madd(n, v3(nk[0], nk[1], nk[2]), h->bary[k]);
    }
    double l = v3_len(n);
    if (!(l > 0 && isfinite(l)))
        return;
    h->ns = v3_mul(n, 1.0 / l);
    /* The normals say which side is out, whatever the winding: the geometric
    ** normal follows them (pbrt does the same), so facing tests agree. */
    if (v3_dot(h->ns, h->n) < 0)
        h->n = v3_neg(h->n);
}

/* Ties in t go to the lower id, whatever order the BVH visits them in. */
int scene_closest_n(const lc_scene *s, const lc_ray *r, double tmax, lc_hit *h,
                    lc_counts *counts)
{
    uint64_t np = s->nplanes, nn = 0;   /* counted in registers, added once */
    lc_counts inner = {0, 0};           /* inside instances */
    query q;
    query_init(&q, r, s->c.nflat > 0);
    double best = 0;
    uint32_t best_id = 0;
    lc_hit tmp;
#define CONSIDER(id)                                                             \
    {                                                                            \
        uint32_t id_ = (id);                                                     \
        double t_ = prim_t(s, id_, &q, tmax, &tmp, &inner);                      \
        np++;                                                                    \
        if (t_ > 0 && (best == 0 || t_ < best || (t_ == best && id_ < best_id))) { \
            best = t_;                                                           \
            best_id = id_;                                                       \
            if (PRIM_KIND(id_) == PRIM_QUAD || PRIM_KIND(id_) == PRIM_TRIANGLE || \
                PRIM_KIND(id_) == PRIM_INSTANCE)                                 \
                *h = tmp;                                                        \
            tmax = next_up(t_);                                                  \
        }                                                                        \
    }
    for (size_t i = 0; i < s->nplanes; i++) {   /* planes first: they bound tmax */
        double t = plane_t(&s->planes[i].g, q.r, q.inv, 0, tmax);
        if (t > 0 && (best == 0 || t < best)) {   /* in id order: a tie keeps the first */
            best = t;
            best_id = PRIM_ID(PRIM_PLANE, i);
            tmax = next_up(t);
        }
    }
    const bvh *b = &s->c.bvh;
    if (b->nnodes && (nn++, node_enter(&b->nodes[0], &q, tmax) < HUGE_VAL)) {
        /* Children are tested from their parent: the nearer is visited
        ** first, the farther is skipped once a hit lies before it. */
        uint32_t stack[STACK];
        double enter[STACK];
        int sp = 0;
        uint32_t ni = 0;
        for (;;) {
            const bvh_node *nd = &b->nodes[ni];
            if (nd->count) {
                for (uint32_t k = 0; k < nd->count; k++)
                    CONSIDER(b->refs[nd->start + k])
            } else {
                uint32_t c0 = ni + 1, c1 = nd->start;
                double t0 = node_enter(&b->nodes[c0], &q, tmax);
                double t1 = node_enter(&b->nodes[c1], &q, tmax);
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
                    goto done;
                --sp;
            } while (enter[sp] > tmax);
            ni = stack[sp];
        }
    }
done:
#undef CONSIDER
    if (counts) {
        counts->prims += np + inner.prims;
        counts->nodes += nn + inner.nodes;
    }
    if (best == 0 || !prim_finish(s, best_id, &q, best, h))
        return 0;
    shading_normal(s, h);
    return 1;
}

/* Any hit: the first primitive found in (0, tmax) ends the search. */
static int occluded(const lc_scene *s, const lc_ray *r, double tmax, uint32_t skip,
                    uint64_t *np, uint64_t *nn)
{
    query q;
    query_init(&q, r, s->c.nflat > 0);
    lc_hit tmp;
    lc_counts inner = {0, 0};
    for (size_t i = 0; i < s->nplanes; i++) {
        ++*np;
        if (plane_t(&s->planes[i].g, q.r, q.inv, 0, tmax) > 0)
            return 1;
    }
    const bvh *b = &s->c.bvh;
    if (!b->nnodes)
        return 0;
    ++*nn;
    if (node_enter(&b->nodes[0], &q, tmax) == HUGE_VAL)
        return 0;
    uint32_t stack[STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const bvh_node *nd = &b->nodes[ni];
        if (nd->count) {
            for (uint32_t k = 0; k < nd->count; k++) {
                uint32_t id = b->refs[nd->start + k];
                if (id == skip)
                    continue;
                ++*np;
                if (PRIM_KIND(id) == PRIM_INSTANCE) {
                    int hit = instance_occluded(s, PRIM_INDEX(id), r, tmax, &inner);
                    *np += inner.prims;
                    *nn += inner.nodes;
                    inner.prims = inner.nodes = 0;
                    if (hit)
                        return 1;
                } else if (prim_t(s, id, &q, tmax, &tmp, &inner) > 0) {
                    return 1;
                }
            }
        } else {
            uint32_t c0 = ni + 1, c1 = nd->start;
            int h0 = node_enter(&b->nodes[c0], &q, tmax) < HUGE_VAL;
            int h1 = node_enter(&b->nodes[c1], &q, tmax) < HUGE_VAL;
            *nn += 2;
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

int scene_occluded_n(const lc_scene *s, const lc_ray *r, double tmax, lc_counts *counts)
{
    return scene_occluded_skip(s, r, tmax, SCENE_SKIP_NONE, counts);
}

int scene_occluded_skip(const lc_scene *s, const lc_ray *r, double tmax, uint32_t skip,
                        lc_counts *counts)
{
    uint64_t np = 0, nn = 0;
    int hit = occluded(s, r, tmax, skip, &np, &nn);
    if (counts) {
        counts->prims += np;
        counts->nodes += nn;
    }
    return hit;
}
