/* instance.c: moved meshes: one BVH per mesh, rays taken into its own space. */
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "scene.h"
#include "base/mem.h"
#include "instance.h"
#include "shapes/triangle.h"

static lc_vec3 vmax(lc_vec3 a, lc_vec3 b)
{
    return v3(max2(a.x, b.x), max2(a.y, b.y), max2(a.z, b.z));
}

/* ---- the per-mesh BVH cache -------------------------------------------------- */

/* Face f's three vertices. */
static void face_vertices(const lc_mesh *m, size_t f, const double *v[3])
{
    const uint32_t *ix = m->f + 3 * f;
    for (int j = 0; j < 3; j++)
        v[j] = m->v + 3 * (size_t)ix[j];
}

static void blas_clear(mesh_bvh *mb)
{
    bvh_free(&mb->bvh);
    mem_free(mb->face);
    mb->face = NULL;
    mb->nface = mb->degenerate = 0;
}

/* Builds mb's BVH over the mesh's faces as they are now. */
static lc_status blas_build(mesh_bvh *mb, sig_atomic_t seen, lc_error *err)
{
    const lc_mesh *m = mb->mesh;
    blas_clear(mb);
    mb->faces = m->nf;
    bvh_bounds_empty(mb->lo, mb->hi);
    mb->face = mem_alloc((m->nf + 1) * sizeof *mb->face);
    bvh_item *items = mem_alloc((m->nf + 1) * sizeof *items);
    if (!mb->face || !items) {
        mem_free(items);
        blas_clear(mb);
        return error_fail(err, LC_ENOMEM, NULL, "out of memory bounding a mesh of %zu faces",
                       m->nf);
    }
    size_t n = 0;
    for (size_t f = 0; f < m->nf; f++) {
        const double *v[3];
        face_vertices(m, f, v);
        if (triangle_degenerate(v[0], v[1], v[2])) {
            mb->degenerate++;
            continue;
        }
        bvh_item *it = &items[n];
        it->id = (uint32_t)n;
        triangle_bounds(v[0], v[1], v[2], it->lo, it->hi);
        for (int a = 0; a < 3; a++) {
            if (it->lo[a] < mb->lo[a]) mb->lo[a] = it->lo[a];
            if (it->hi[a] > mb->hi[a]) mb->hi[a] = it->hi[a];
        }
        mb->face[n++] = (uint32_t)f;
    }
    mb->nface = n;
    lc_status st = bvh_build(&mb->bvh, items, n, seen, err);
    if (st)
        blas_clear(mb);
    return st;
}

static mesh_bvh *blas_find(lc_scene *s, const lc_mesh *m)
{
    for (size_t i = 0; i < s->nblas; i++)
        if (s->blas[i].mesh == m)
            return &s->blas[i];
    return NULL;
}

void instance_free_all(lc_scene *s)
{
    for (size_t i = 0; i < s->nblas; i++) {
        blas_clear(&s->blas[i]);
        lc_mesh_free(s->blas[i].mesh);
    }
    mem_free(s->blas);
    s->blas = NULL;
    s->nblas = s->capblas = 0;
}

size_t instance_faces(const lc_scene *s)
{
    size_t total = 0;
    for (size_t i = 0; i < s->nmeshes; i++) {
        const mesh_prim *mp = &s->meshes[i];
        if (!mp->xf)
            continue;
        size_t j = 0;                       /* each mesh once */
        while (j < i && !(s->meshes[j].xf && s->meshes[j].mesh == mp->mesh))
            j++;
        if (j == i)
            total += mp->mesh->nf;
    }
    return total;
}

lc_status instance_compile(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    for (size_t i = 0; i < s->nblas; i++)
        s->blas[i].used = 0;
    /* Find or build each instanced mesh's BVH, in the order first used. */
    for (size_t i = 0; i < s->nmeshes; i++) {
        mesh_prim *mp = &s->meshes[i];
        if (!mp->xf)
            continue;
        mesh_bvh *mb = blas_find(s, mp->mesh);
        if (!mb) {
            if (s->nblas == s->capblas) {
                size_t nc = s->capblas ? 2 * s->capblas : 8;
                mesh_bvh *p = mem_realloc(s->blas, nc * sizeof *p);
                if (!p)
                    return error_fail(err, LC_ENOMEM, NULL, "out of memory adding a mesh BVH");
                s->blas = p;
                s->capblas = nc;
            }
            mb = &s->blas[s->nblas++];
            memset(mb, 0, sizeof *mb);
            mb->mesh = mesh_retain(mp->mesh);
            mb->faces = (size_t)-1;
        }
        if (mb->faces != mp->mesh->nf) {   /* new, or the mesh grew: rebuild */
            lc_status st = blas_build(mb, seen, err);
            if (st)
                return st;
        }
        mb->used = 1;
    }
    /* Drop what no instance uses any more (removed), keeping the order. */
    size_t k = 0;
    for (size_t i = 0; i < s->nblas; i++) {
        if (s->blas[i].used) {
            s->blas[k++] = s->blas[i];
        } else {
            blas_clear(&s->blas[i]);
            lc_mesh_free(s->blas[i].mesh);
        }
    }
    s->nblas = k;
    /* List each mesh's faces once after the flat triangles. */
    for (size_t i = 0; i < s->nblas; i++) {
        mesh_bvh *mb = &s->blas[i];
        uint32_t owner = 0;
        while (s->meshes[owner].mesh != mb->mesh || !s->meshes[owner].xf)
            owner++;
        mb->tri_base = c->ntris;
        for (size_t f = 0; f < mb->nface; f++) {
            c->tris[c->ntris].mesh = owner;
            c->tris[c->ntris++].face = mb->face[f];
        }
        c->degenerate += mb->degenerate;
    }
    c->ninstances = 0;
    for (size_t i = 0; i < s->nmeshes; i++) {
        mesh_prim *mp = &s->meshes[i];
        if (mp->xf) {
            mp->blas = (uint32_t)(blas_find(s, mp->mesh) - s->blas);
            c->ninstances++;
        }
    }
    return LC_OK;
}

void instance_bounds(const lc_scene *s, size_t i, float lo[3], float hi[3])
{
    const mesh_prim *mp = &s->meshes[i];
    const mesh_bvh *mb = &s->blas[mp->blas];
    lc_vec3 a = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL), b = v3_neg(a), big = v3(0, 0, 0);
    for (int corner = 0; corner < 8; corner++) {
        lc_vec3 p = v3(corner & 1 ? mb->hi[0] : mb->lo[0], corner & 2 ? mb->hi[1] : mb->lo[1],
                       corner & 4 ? mb->hi[2] : mb->lo[2]);
        lc_vec3 w = lc_transform_point(&mp->xf->xf, p);
        a = v3(fmin(a.x, w.x), fmin(a.y, w.y), fmin(a.z, w.z));
        b = v3(fmax(b.x, w.x), fmax(b.y, w.y), fmax(b.z, w.z));
        big = vmax(big, v3_abs(w));
    }
    /* Wide enough for the surface as rays see it through inv. */
    lc_vec3 e = affine_slack(mp->xf, big);
    a = v3_sub(a, e);
    b = v3_add(b, e);
    double lo3[3] = {a.x, a.y, a.z}, hi3[3] = {b.x, b.y, b.z};
    for (int k = 0; k < 3; k++) {
        lo[k] = mb->nface ? bvh_down(nextafter(lo3[k], -HUGE_VAL)) : HUGE_VALF;
        hi[k] = mb->nface ? bvh_up(nextafter(hi3[k], HUGE_VAL)) : -HUGE_VALF;
    }
}

/* ---- tracing ----------------------------------------------------------------- */

typedef struct {
    ray    r;           /* in object space: d is not unit, so t is the world's */
    bvh_ray   b;
    triangle_shear sh;
} object_ray;

static void object_ray_init(object_ray *q, const affine *x, const ray *r)
{
    q->r = affine_ray(x, r);
    bvh_ray_init(&q->b, q->r.o, q->r.d);
    triangle_shear_init(q->r.d, &q->sh);
}

/* The distance to face f, and its weights in bary; 0 for a miss. */
static inline double face_t(const lc_mesh *m, uint32_t f, const object_ray *q, double tmax,
                            double bary[3])
{
    const uint32_t *ix = m->f + 3 * (size_t)f;
    const double *v = m->v;
    return triangle_t(v + 3 * (size_t)ix[0], v + 3 * (size_t)ix[1], v + 3 * (size_t)ix[2],
                      &q->r, &q->sh, 0, tmax, bary);
}

/* The nearest face's hit in object space, from its distance and weights. */
static int face_finish(const lc_mesh *m, uint32_t f, const object_ray *q, double t,
                       const double bary[3], hit *h)
{
    const uint32_t *ix = m->f + 3 * (size_t)f;
    const double *v = m->v;
    return triangle_finish(v + 3 * (size_t)ix[0], v + 3 * (size_t)ix[1],
                           v + 3 * (size_t)ix[2], &q->r, t, bary, h);
}

/* The object-space hit on face f, in the world: the point from the moved
** vertices, its error bound with the transforms' slack, normals by the
** inverse transpose. */
static void to_world(const mesh_prim *mp, const mesh_bvh *mb,
                     uint32_t k, hit *h)
{
    const affine *x = mp->xf;
    const lc_mesh *m = mp->mesh;
    const uint32_t *ix = m->f + 3 * (size_t)mb->face[k];
    lc_vec3 p = v3(0, 0, 0), sum = v3(0, 0, 0), big = v3(0, 0, 0);
    for (int j = 0; j < 3; j++) {
        const double *v = m->v + 3 * (size_t)ix[j];
        lc_vec3 w = lc_transform_point(&x->xf, v3(v[0], v[1], v[2]));
        lc_vec3 a = v3_mul(w, h->bary[j]);
        p = v3_add(p, a);
        sum = v3_add(sum, v3_abs(a));
        big = vmax(big, v3_abs(w));
    }
    h->p = p;
    h->perr = v3_add(v3_mul(sum, vec_gamma(7)), affine_slack(x, vmax(big, v3_abs(p))));
    h->n = affine_normal(x, h->n);
    h->ns = h->n;
    if (m->n) {
        lc_vec3 n = v3(0, 0, 0);
        for (int j = 0; j < 3; j++) {
            const double *nk = m->n + 3 * (size_t)ix[j];
            n = v3_madd(n, v3(nk[0], nk[1], nk[2]), h->bary[j]);
        }
        n = affine_normal_raw(x, n);
        double l = v3_len(n);
        if (l > 0 && isfinite(l)) {
            h->ns = v3_mul(n, 1.0 / l);
            if (v3_dot(h->ns, h->n) < 0)     /* as intersect.c: normals say which side */
                h->n = v3_neg(h->n);
        }
    }
    h->material = mesh_face_material(mp, mb->face[k]);
    h->shape = PRIM_ID(PRIM_TRIANGLE, mb->tri_base + k);
}

/* The nearest-face search in one instance's BVH. */
typedef struct {
    const lc_mesh  *mesh;
    const mesh_bvh *mb;
    const object_ray *q;
    double   best;          /* 0: nothing yet */
    uint32_t best_k;
    double   bary[3];       /* the nearest face's weights */
    uint64_t np;
} face_search;

static inline double closest_face(void *ctx, uint32_t at, double tmax)
{
    face_search *c = ctx;
    uint32_t k = c->mb->bvh.refs[at];
    double w[3];
    c->np++;
    double t = face_t(c->mesh, c->mb->face[k], c->q, tmax, w);
    if (t > 0 && (c->best == 0 || t < c->best || (t == c->best && k < c->best_k))) {
        c->best = t;
        c->best_k = k;
        for (int j = 0; j < 3; j++)
            c->bary[j] = w[j];
        tmax = next_up(t);
    }
    return tmax;
}

/* Sets up a search of instance i for ray r; 0 when its mesh has no face. */
static int search_begin(const lc_scene *s, uint32_t i, const ray *r, object_ray *q,
                        face_search *c)
{
    const mesh_prim *mp = &s->meshes[i];
    const mesh_bvh *mb = &s->blas[mp->blas];
    if (!mb->bvh.nnodes)
        return 0;
    object_ray_init(q, mp->xf, r);
    face_search init = {mp->mesh, mb, q, 0, 0, {0, 0, 0}, 0};
    *c = init;
    return 1;
}

BVH_DISPATCH(uint64_t, closest_walk,
             (const bvh *b, const bvh_ray *q, double tmax, face_search *c), (b, q, tmax, c),
             return bvh_closest(b, q, tmax, c, closest_face, BVH_TEST);)

double instance_hit(const lc_scene *s, uint32_t i, const ray *r, double tmax,
                    hit *h, bvh_counts *counts)
{
    object_ray q;
    face_search c;
    if (!search_begin(s, i, r, &q, &c))
        return 0;
    counts->nodes += closest_walk(&c.mb->bvh, &q.b, tmax, &c);
    counts->prims += c.np;
    if (c.best == 0 || !face_finish(c.mesh, c.mb->face[c.best_k], &q, c.best, c.bary, h))
        return 0;
    to_world(&s->meshes[i], c.mb, c.best_k, h);
    h->instance = i + 1;
    return c.best;
}

static inline int any_face(void *ctx, uint32_t at, double tmax)
{
    face_search *c = ctx;
    uint32_t k = c->mb->bvh.refs[at];
    double w[3];
    c->np++;
    return face_t(c->mesh, c->mb->face[k], c->q, tmax, w) > 0;
}

BVH_DISPATCH(int, any_walk,
             (const bvh *b, const bvh_ray *q, double tmax, face_search *c, uint64_t *nodes),
             (b, q, tmax, c, nodes), return bvh_any(b, q, tmax, c, any_face, nodes, BVH_TEST);)

int instance_occluded(const lc_scene *s, uint32_t i, const ray *r, double tmax,
                      bvh_counts *counts)
{
    object_ray q;
    face_search c;
    if (!search_begin(s, i, r, &q, &c))
        return 0;
    int found = any_walk(&c.mb->bvh, &q.b, tmax, &c, &counts->nodes);
    counts->prims += c.np;
    return found;
}
