/* intersect.c: nearest-hit and any-hit queries: infinite planes one by one,
** everything else through the BVH. */
#include "scene.h"

#define STACK 128   /* BVH depth is at most 64 plus halvings of oversized leaves */

typedef struct {
    lc_ray    r;
    double    o[3], inv[3];
    int       neg[3];
    tri_shear sh;
} query;

static void query_init(query *q, const lc_ray *r)
{
    q->r = *r;
    double d[3] = {r->d.x, r->d.y, r->d.z};
    q->o[0] = r->o.x;
    q->o[1] = r->o.y;
    q->o[2] = r->o.z;
    for (int k = 0; k < 3; k++) {
        q->inv[k] = 1.0 / d[k];         /* +-inf for 0: wanted */
        q->neg[k] = q->inv[k] < 0;      /* from the reciprocal, so -0 counts */
    }
    tri_shear_init(r->d, &q->sh);
}

/* Slab test of a node: returns its entry distance, or +inf when the ray
** misses it before tmax. The far distance is enlarged by 1 + 2 gamma(3) so
** the three roundings of (bound - o) * inv can never turn a hit into a miss
** (Ize 2013, pbrt-v4); NaN from 0 * inf is ignored by the comparisons. */
static inline double node_enter(const bvh_node *nd, const query *q, double tmax)
{
    static const double widen = 1 + 2 * (3 * (DBL_EPSILON / 2)) / (1 - 3 * (DBL_EPSILON / 2));
    double t0 = 0, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        double a = (nd->lo[k] - q->o[k]) * q->inv[k];
        double b = (nd->hi[k] - q->o[k]) * q->inv[k];
        double near = q->neg[k] ? b : a, far = (q->neg[k] ? a : b) * widen;
        t0 = near > t0 ? near : t0;
        t1 = far < t1 ? far : t1;
    }
    return t0 <= t1 ? t0 : HUGE_VAL;
}

static int prim_hit(const lc_scene *s, uint32_t id, const query *q, double tmax, lc_hit *h)
{
    uint32_t i = PRIM_INDEX(id);
    switch (PRIM_KIND(id)) {
    case PRIM_SPHERE:
        if (!sphere_hit(&s->spheres[i].g, &q->r, 0, tmax, h))
            return 0;
        h->material = s->spheres[i].material;
        break;
    case PRIM_QUAD:
        if (!quad_hit(&s->quads[i].g, &q->r, 0, tmax, h))
            return 0;
        h->material = s->quads[i].material;
        break;
    case PRIM_BOX:
        if (!box_hit(&s->boxes[i].g, &q->r, 0, tmax, h))
            return 0;
        h->material = s->boxes[i].material;
        break;
    case PRIM_TRIANGLE: {
        const tri_ref *tr = &s->c.tris[i];
        const mesh_prim *mp = &s->meshes[tr->mesh];
        const uint32_t *f = mp->mesh->f + 3 * (size_t)tr->face;
        const double *v = mp->mesh->v;
        if (!tri_hit(v + 3 * (size_t)f[0], v + 3 * (size_t)f[1], v + 3 * (size_t)f[2],
                     &q->r, &q->sh, 0, tmax, h, h->bary))
            return 0;
        h->material = mp->material;
        break;
    }
    default:
        if (!plane_hit(&s->planes[i].g, &q->r, 0, tmax, h))
            return 0;
        h->material = s->planes[i].material;
        break;
    }
    h->shape = id;
    return 1;
}

/* Interpolated vertex normals, where the mesh has them. */
static void shading_normal(const lc_scene *s, lc_hit *h)
{
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
int scene_closest(const lc_scene *s, const lc_ray *r, double tmax, lc_hit *h)
{
    query q;
    query_init(&q, r);
    int found = 0;
    lc_hit tmp;
#define CONSIDER(id)                                                             \
    if (prim_hit(s, (id), &q, tmax, &tmp) &&                                     \
        (!found || tmp.t < h->t || (tmp.t == h->t && tmp.shape < h->shape))) {   \
        *h = tmp;                                                                \
        tmax = nextafter(tmp.t, HUGE_VAL);                                       \
        found = 1;                                                               \
    }
    for (size_t i = 0; i < s->nplanes; i++)
        CONSIDER(PRIM_ID(PRIM_PLANE, i))
    const bvh *b = &s->c.bvh;
    if (b->nnodes && node_enter(&b->nodes[0], &q, tmax) < HUGE_VAL) {
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
    if (found)
        shading_normal(s, h);
    return found;
}

int scene_occluded(const lc_scene *s, const lc_ray *r, double tmax)
{
    query q;
    query_init(&q, r);
    lc_hit tmp;
    for (size_t i = 0; i < s->nplanes; i++)
        if (prim_hit(s, PRIM_ID(PRIM_PLANE, i), &q, tmax, &tmp))
            return 1;
    const bvh *b = &s->c.bvh;
    if (!b->nnodes)
        return 0;
    if (node_enter(&b->nodes[0], &q, tmax) == HUGE_VAL)
        return 0;
    uint32_t stack[STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const bvh_node *nd = &b->nodes[ni];
        if (nd->count) {
            for (uint32_t k = 0; k < nd->count; k++)
                if (prim_hit(s, b->refs[nd->start + k], &q, tmax, &tmp))
                    return 1;
        } else {
            uint32_t c0 = ni + 1, c1 = nd->start;
            int h0 = node_enter(&b->nodes[c0], &q, tmax) < HUGE_VAL;
            int h1 = node_enter(&b->nodes[c1], &q, tmax) < HUGE_VAL;
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
