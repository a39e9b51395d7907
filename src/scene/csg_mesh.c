/* csg_mesh.c: closed meshes as CSG leaves: the closedness check, the side
** the winding faces, a BVH in object space and every crossing along a ray. */
#include <stdlib.h>
#include <string.h>
#include "csg.h"
#include "base/error.h"
#include "base/interrupt.h"
#include "base/mem.h"
#include "mesh.h"

/* ---- closed, and which way ------------------------------------------------------ */

/* An edge of a face, its ends sorted: dir says whether the face runs it from
** a to b (0) or from b to a (1). */
typedef struct { uint32_t a, b, face, dir; } edge;

static int edge_order(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    if (p->dir != q->dir) return p->dir < q->dir ? -1 : 1;
    return p->face < q->face ? -1 : p->face > q->face;
}

/* The vertex of face f's corner j, relative to ref (no cancellation in the
** volume however far the mesh lies from the origin). */
static lc_vec3 corner(const lc_mesh *m, size_t f, int j, lc_vec3 ref)
{
    const double *v = m->v + 3 * (size_t)m->f[3 * f + j];
    return v3(v[0] - ref.x, v[1] - ref.y, v[2] - ref.z);
}

/* Vertices are named counting from 1, as OBJ files and lancer.mesh do. */
lc_status csg_mesh_check(const lc_mesh *m, size_t nf, int *orient, lc_error *err)
{
    if (nf == 0)
        return error_fail(err, LC_EARG, "mesh", "the mesh has no face: not a closed "
                          "solid");
    edge *e = mem_alloc(3 * nf * sizeof *e);
    if (!e)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory checking a mesh of %zu "
                          "faces", nf);
    size_t ne = 0;
    for (size_t f = 0; f < nf; f++)
        for (int j = 0; j < 3; j++) {
            uint32_t a = m->f[3 * f + j], b = m->f[3 * f + (j + 1) % 3];
            if (a == b)                 /* a collapsed corner: no edge */
                continue;
            edge x = {a < b ? a : b, a < b ? b : a, (uint32_t)f, a > b};
            e[ne++] = x;
        }
    qsort(e, ne, sizeof *e, edge_order);
    lc_status st = LC_OK;
    for (size_t i = 0; i < ne && st == LC_OK;) {
        size_t j = i;
        while (j < ne && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        const edge *x = &e[i];
        unsigned long va = x->a + 1UL, vb = x->b + 1UL;
        if (j - i == 1)
            st = error_fail(err, LC_EARG, "mesh", "the mesh is open: the edge between "
                            "vertices %lu and %lu is in face %lu only (counting from 1)",
                            va, vb, x->face + 1UL);
        else if (j - i > 2)
            st = error_fail(err, LC_EARG, "mesh", "the mesh is not a closed surface: "
                            "the edge between vertices %lu and %lu is in %zu faces "
                            "(counting from 1)", va, vb, j - i);
        else if (e[i].dir == e[i + 1].dir)
            st = error_fail(err, LC_EARG, "mesh", "faces %lu and %lu both run the edge "
                            "from vertex %lu to %lu: their windings disagree (counting "
                            "from 1)", e[i].face + 1UL, e[i + 1].face + 1UL,
                            e[i].dir ? vb : va, e[i].dir ? va : vb);
        i = j;
    }
    mem_free(e);
    if (st)
        return st;
    /* The enclosed volume, six times over: its sign says which way the
    ** winding's normals point. */
    const double *r = m->v + 3 * (size_t)m->f[0];
    lc_vec3 ref = v3(r[0], r[1], r[2]);
    double vol = 0;
    for (size_t f = 0; f < nf; f++)
        vol += v3_dot(corner(m, f, 0, ref), v3_cross(corner(m, f, 1, ref),
                                                     corner(m, f, 2, ref)));
    if (!(vol != 0) || !isfinite(vol))
        return error_fail(err, LC_EARG, "mesh", "the mesh encloses no volume");
    if (orient)
        *orient = vol > 0 ? 1 : -1;
    return LC_OK;
}

csg_mesh *csg_mesh_new(lc_mesh *m, lc_error *err)
{
    int orient;
    size_t nf = m->nf;
    if (csg_mesh_check(m, nf, &orient, err))
        return NULL;
    csg_mesh *cm = mem_calloc(1, sizeof *cm);
    bvh_item *items = mem_alloc((nf + 1) * sizeof *items);
    uint32_t *face = mem_alloc((nf + 1) * sizeof *face);
    if (!cm || !items || !face) {
        mem_free(cm);
        mem_free(items);
        mem_free(face);
        error_fail(err, LC_ENOMEM, NULL, "out of memory bounding a mesh of %zu faces",
                   nf);
        return NULL;
    }
    for (int k = 0; k < 3; k++) {
        cm->lo[k] = HUGE_VAL;
        cm->hi[k] = -HUGE_VAL;
    }
    size_t n = 0;
    for (size_t f = 0; f < nf; f++) {
        const double *v[3];
        for (int j = 0; j < 3; j++) {
            v[j] = m->v + 3 * (size_t)m->f[3 * f + j];
            for (int k = 0; k < 3; k++) {
                cm->lo[k] = fmin(cm->lo[k], v[j][k]);
                cm->hi[k] = fmax(cm->hi[k], v[j][k]);
            }
        }
        if (triangle_degenerate(v[0], v[1], v[2]))
            continue;
        items[n].id = (uint32_t)n;
        triangle_bounds(v[0], v[1], v[2], items[n].lo, items[n].hi);
        face[n++] = (uint32_t)f;
    }
    if (bvh_build(&cm->bvh, items, n, interrupt_count(), err)) {
        mem_free(face);
        mem_free(cm);
        return NULL;
    }
    cm->mesh = mesh_retain(m);
    cm->nf = nf;
    cm->face = face;
    cm->nface = n;
    cm->orient = orient;
    cm->refs = 1;
    return cm;
}

void csg_mesh_release(csg_mesh *cm)
{
    if (!cm || --cm->refs > 0)
        return;
    bvh_free(&cm->bvh);
    mem_free(cm->face);
    lc_mesh_free(cm->mesh);
    mem_free(cm);
}

/* ---- crossings -------------------------------------------------------------------- */

void csg_mesh_ray_init(csg_mesh_ray *q, const affine *xf, const ray *r)
{
    q->r = xf ? affine_ray(xf, r) : *r;
    bvh_ray_init(&q->b, q->r.o, q->r.d);
    triangle_shear_init(q->r.d, &q->sh);
}

static lc_vec3 vmax(lc_vec3 a, lc_vec3 b)
{
    return v3(max2(a.x, b.x), max2(a.y, b.y), max2(a.z, b.z));
}

/* The world point of BVH ref k at barycentrics b, its error bound (as
** instance.c's: the moved vertices' weighted sum, and the transforms'
** slack), and its outward unit normal. */
static void world_hit(const csg_mesh *cm, const affine *xf, uint32_t k,
                      const double b[3], hit *h)
{
    const lc_mesh *m = cm->mesh;
    const uint32_t *ix = m->f + 3 * (size_t)cm->face[k];
    lc_vec3 v[3], p = v3(0, 0, 0), sum = v3(0, 0, 0), big = v3(0, 0, 0);
    for (int j = 0; j < 3; j++) {
        const double *x = m->v + 3 * (size_t)ix[j];
        v[j] = v3(x[0], x[1], x[2]);
        lc_vec3 w = xf ? lc_transform_point(&xf->xf, v[j]) : v[j];
        lc_vec3 a = v3_mul(w, b[j]);
        p = v3_add(p, a);
        sum = v3_add(sum, v3_abs(a));
        big = vmax(big, v3_abs(w));
    }
    lc_vec3 n = v3_mul(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])), cm->orient);
    h->p = p;
    h->perr = v3_mul(sum, vec_gamma(7));
    if (xf) {
        h->perr = v3_add(h->perr, affine_slack(xf, vmax(big, v3_abs(p))));
        h->n = affine_normal(xf, n);
    } else {
        h->n = v3_norm(n);
    }
    h->ns = h->n;
    h->bary[0] = b[0];
    h->bary[1] = b[1];
    h->bary[2] = b[2];
}

void csg_mesh_hit(const csg_mesh *cm, const affine *xf, const csg_mesh_cross *c, hit *h)
{
    world_hit(cm, xf, c->k, c->bary, h);
    h->t = c->t;
}

/* The search: every face hit beyond `after`, the nearest cap of them kept in
** order (by distance, then ref); once full, nothing past the farthest kept
** is looked at. */
typedef struct {
    const csg_mesh *cm;
    const affine *xf;
    const csg_mesh_ray *q;
    const ray *world;
    double after;
    csg_mesh_cross *out;
    size_t cap, n;
    uint64_t tests;
} collect;

static inline double collect_face(void *ctx, uint32_t at, double tmax)
{
    collect *c = ctx;
    uint32_t k = c->cm->bvh.refs[at];
    const lc_mesh *m = c->cm->mesh;
    const uint32_t *ix = m->f + 3 * (size_t)c->cm->face[k];
    const double *v = m->v;
    hit h;
    c->tests++;
    const double *a = v + 3 * (size_t)ix[0], *b = v + 3 * (size_t)ix[1];
    if (!triangle_hit(a, b, v + 3 * (size_t)ix[2], &c->q->r, &c->q->sh, c->after, tmax,
                      &h, h.bary))
        return tmax;
    csg_mesh_cross x = {h.t, 0, 0, k, {h.bary[0], h.bary[1], h.bary[2]}};
    hit w;
    world_hit(c->cm, c->xf, k, h.bary, &w);
    w.t = h.t;
    csg_cross_sense(c->world->d, &w, &x.sense, &x.e);
    size_t i;
    if (c->n == c->cap) {                 /* full: the farthest kept makes room */
        const csg_mesh_cross *last = &c->out[c->cap - 1];
        if (last->t < x.t || (last->t == x.t && last->k < x.k))
            return next_up(last->t);
        i = c->cap - 1;
    } else {
        i = c->n++;
    }
    while (i > 0 && (c->out[i - 1].t > x.t ||
                     (c->out[i - 1].t == x.t && c->out[i - 1].k > x.k))) {
        c->out[i] = c->out[i - 1];
        i--;
    }
    c->out[i] = x;
    return c->n == c->cap ? next_up(c->out[c->cap - 1].t) : tmax;
}

BVH_DISPATCH(uint64_t, collect_walk,
             (const bvh *b, const bvh_ray *q, double tmax, collect *c), (b, q, tmax, c),
             return bvh_closest(b, q, tmax, c, collect_face, BVH_TEST);)

size_t csg_mesh_crossings(const csg_mesh *cm, const affine *xf, const csg_mesh_ray *q,
                          const ray *world, double after, csg_mesh_cross *out,
                          size_t cap, int *more, uint64_t *tests, uint64_t *nodes)
{
    collect c = {cm, xf, q, world, after, out, cap, 0, 0};
    *nodes += collect_walk(&cm->bvh, &q->b, HUGE_VAL, &c);
    *tests += c.tests;
    *more = 0;
    if (c.n == cap) {
        /* Some may lie beyond: let the next search start before the last
        ** distance kept, so that no run of equal distances is split. */
        *more = 1;
        size_t n = c.n;
        while (n > 0 && out[n - 1].t == out[c.n - 1].t)
            n--;
        if (n > 0)
            c.n = n;
    }
    return c.n;
}
