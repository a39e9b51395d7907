/* intersect.c: nearest-hit and any-hit queries: infinite planes one by one,
** everything else through the BVH. */
#include "scene.h"
#include "shapes/triangle4.h"
#include "accel/bvh_packet.h"
#include "shapes/cone.h"
#include "shapes/cylinder.h"
#include "shapes/disc.h"
#include "shapes/ellipsoid.h"
#include "instance.h"
#include "intersect.h"
#include "shapes/plane.h"
#include "shapes/torus.h"
#include "csg.h"

/* Each kind's prepared shapes, as the switches below read them. */
#define SPHERES(s) ((const sphere_geom *)(s)->shapes[LC_SPHERE].geom)
#define QUADS(s)   ((const quad_geom *)(s)->shapes[LC_QUAD].geom)
#define BOXES(s)   ((const box_geom *)(s)->shapes[LC_BOX].geom)
#define PLANES(s)  ((const plane_geom *)(s)->shapes[LC_PLANE].geom)
#define PLACED(s, k) ((const placed_geom *)(s)->shapes[k].geom)

typedef struct {
    const ray *r;      /* a pointer: copying the ray stalled on store forwarding */
    bvh_ray   b;
    triangle_shear sh;
} query;

static void query_init(query *q, const ray *r, int triangles)
{
    q->r = r;
    bvh_ray_init(&q->b, r->o, r->d);
    if (triangles)                      /* the shear only triangles use */
        triangle_shear_init(r->d, &q->sh);
}

/* Distance to primitive id along the query's ray, 0 for a miss. Spheres,
** boxes, planes and the placed shapes compute the distance only, triangles
** the distance and full->bary (the nearest is finished later); quads need
** most of the work anyway to know they are hit, so they fill *full as they
** go, as do the nested searches of instances and CSG objects. */
ALWAYS_INLINE double prim_t(const lc_scene *s, uint32_t id, uint32_t at, const query *q,
                            double tmax, hit *full, bvh_counts *inner)
{
    uint32_t i = PRIM_INDEX(id);
    switch (PRIM_KIND(id)) {
    case PRIM_SPHERE:
        return sphere_t(SPHERES(s) + i, q->r, 0, tmax);
    case PRIM_BOX:
        return box_t(BOXES(s) + i, q->r, q->b.inv, 0, tmax);
    case PRIM_PLANE:
        return plane_t(PLANES(s) + i, q->r, q->b.inv, 0, tmax);
    case PRIM_QUAD:
        if (!quad_hit_inv(QUADS(s) + i, q->r, q->b.inv, 0, tmax, full))
            return 0;
        full->material = s->shapes[LC_QUAD].material[i];
        break;
    default: {                    /* the distance and weights; the rest if nearest */
        const tri_leaf *tl = &s->c.tleaf[at];     /* beside refs[at]: no face lookup */
        const double *v = s->meshes[tl->mesh].mesh->v;
        return triangle_t(v + 3 * (size_t)tl->v[0], v + 3 * (size_t)tl->v[1],
                          v + 3 * (size_t)tl->v[2], q->r, &q->sh, 0, tmax, full->bary);
    }
    case PRIM_INSTANCE:           /* a moved mesh: its own BVH, in its own space */
        return instance_hit(s, i, q->r, tmax, full, inner);
    case PRIM_CSG:                /* a CSG object: the interval sweep, hit complete */
        return csg_hit(s->csgs[i], i, q->r, &q->b, tmax, full, inner);
    case PRIM_DISC:
        return disc_t(PLACED(s, LC_DISC) + i, q->r, 0, tmax);
    case PRIM_CYLINDER:
        return cylinder_t(PLACED(s, LC_CYLINDER) + i, q->r, 0, tmax);
    case PRIM_CONE:
        return cone_t(PLACED(s, LC_CONE) + i, q->r, 0, tmax);
    case PRIM_TORUS:
        return torus_t(PLACED(s, LC_TORUS) + i, q->r, 0, tmax);
    case PRIM_ELLIPSOID:
        return ellipsoid_t(PLACED(s, LC_ELLIPSOID) + i, q->r, 0, tmax);
    }
    full->shape = id;
    full->instance = 0;
    return full->t;
}

/* Fills *h for the nearest hit found by prim_t (at distance t). */
static int prim_finish(const lc_scene *s, uint32_t id, const query *q, double t, hit *h)
{
    uint32_t i = PRIM_INDEX(id);
    int ok;
    switch (PRIM_KIND(id)) {
    case PRIM_SPHERE:
        ok = sphere_finish(SPHERES(s) + i, q->r, t, h);
        h->material = s->shapes[LC_SPHERE].material[i];
        break;
    case PRIM_BOX:
        ok = box_hit_inv(BOXES(s) + i, q->r, q->b.inv, 0, next_up(t), h);  /* same t again */
        h->material = s->shapes[LC_BOX].material[i];
        break;
    case PRIM_PLANE:
        ok = plane_finish(PLANES(s) + i, q->r, t, h);
        h->material = s->shapes[LC_PLANE].material[i];
        break;
    case PRIM_DISC: case PRIM_CYLINDER: case PRIM_CONE: case PRIM_TORUS:
    case PRIM_ELLIPSOID: {
        /* The nearest root again: the one the distance test found, however
        ** the canonical scale rounds t. */
        lc_shape_kind k = shape_kind_of_prim(PRIM_KIND(id));
        const placed_geom *g = PLACED(s, k) + i;
        ok = k == LC_DISC ? disc_hit(g, q->r, 0, HUGE_VAL, h) :
             k == LC_CYLINDER ? cylinder_hit(g, q->r, 0, HUGE_VAL, h) :
             k == LC_CONE ? cone_hit(g, q->r, 0, HUGE_VAL, h) :
             k == LC_TORUS ? torus_hit(g, q->r, 0, HUGE_VAL, h) :
             ellipsoid_hit(g, q->r, 0, HUGE_VAL, h);
        h->material = s->shapes[k].material[i];
        break;
    }
    case PRIM_TRIANGLE: {            /* h->bary: the weights triangle_t gave */
        const tri_ref *tr = &s->c.tris[i];
        const mesh_prim *mp = &s->meshes[tr->mesh];
        const uint32_t *f = mp->mesh->f + 3 * (size_t)tr->face;
        const double *v = mp->mesh->v;
        ok = triangle_finish(v + 3 * (size_t)f[0], v + 3 * (size_t)f[1], v + 3 * (size_t)f[2],
                             q->r, t, h->bary, h);
        h->material = mesh_face_material(mp, tr->face);
        break;
    }
    default:
        return 1;                        /* already complete */
    }
    h->shape = id;
    h->instance = 0;
    return ok;
}

/* Interpolated vertex normals, where the mesh has them. */
static void shading_normal(const lc_scene *s, hit *h)
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

void intersect_uv(const lc_scene *s, const hit *h, double uv[2])
{
    unsigned kind = PRIM_KIND(h->shape);
    if (kind == PRIM_CSG_FACE || kind == PRIM_CSG_CUT) {     /* on a leaf, its own */
        csg_hit_uv(s->csgs[PRIM_INDEX(h->shape)], h, uv);
        return;
    }
    if (kind != PRIM_TRIANGLE) {
        lc_shape_kind k = shape_kind_of_prim(kind);
        shape_uv(k, shape_at(&s->shapes[k], PRIM_INDEX(h->shape)), h->p, uv);
        return;
    }
    /* A face: its mesh's uvs interpolated, or without them the barycentric
    ** weights of its second and third corners. */
    const tri_ref *tr = &s->c.tris[PRIM_INDEX(h->shape)];
    const lc_mesh *m = s->meshes[tr->mesh].mesh;
    if (!m->uv) {
        uv[0] = h->bary[1];
        uv[1] = h->bary[2];
        return;
    }
    const uint32_t *f = m->f + 3 * (size_t)tr->face;
    uv[0] = uv[1] = 0;
    for (int k = 0; k < 3; k++) {
        uv[0] += h->bary[k] * m->uv[2 * (size_t)f[k]];
        uv[1] += h->bary[k] * m->uv[2 * (size_t)f[k] + 1];
    }
}

/* The closest-hit search's state, which the leaf test updates. */
typedef struct {
    const lc_scene *s;
    const query *q;
    double   best;          /* 0: nothing yet */
    uint32_t best_id;
    hit  *h, *tmp;       /* the nearest quad or triangle found; scratch */
    uint64_t np;            /* primitive tests */
    bvh_counts *inner;       /* inside instances and CSG objects: the caller's */
} closest;

/* The kinds prim_t leaves complete, in *full. */
#define COMPLETE ((1u << PRIM_QUAD) | (1u << PRIM_INSTANCE) | (1u << PRIM_CSG))

/* Ties in t go to the lower id, whatever order the BVH visits them in. */
ALWAYS_INLINE double closest_leaf(void *ctx, uint32_t at, double tmax)
{
    closest *c = ctx;
    uint32_t id = c->s->c.bvh.refs[at];
    double t = prim_t(c->s, id, at, c->q, tmax, c->tmp, c->inner);
    c->np++;
    if (t > 0 && (c->best == 0 || t < c->best || (t == c->best && id < c->best_id))) {
        c->best = t;
        c->best_id = id;
        if (PRIM_KIND(id) == PRIM_TRIANGLE) {   /* prim_finish reads them */
            c->h->bary[0] = c->tmp->bary[0];    /* (a loop became a call to memcpy) */
            c->h->bary[1] = c->tmp->bary[1];
            c->h->bary[2] = c->tmp->bary[2];
        } else if ((COMPLETE >> PRIM_KIND(id)) & 1)
            *c->h = *c->tmp;
        tmax = next_up(t);
    }
    return tmax;
}

/* Whether refs[0, count) are all flat triangles (tleaf beside them). */
static inline int all_triangles(const uint32_t *refs, uint32_t count)
{
    for (uint32_t k = 0; k < count; k++)
        if (PRIM_KIND(refs[k]) != PRIM_TRIANGLE)
            return 0;
    return 1;
}

/* refs[at + g, at + g + n)'s faces, four at most, for triangle4. */
static inline void leaf_faces(const lc_scene *s, uint32_t at, int n, triangle4_faces *f)
{
    for (int l = 0; l < n; l++) {
        const tri_leaf *tl = &s->c.tleaf[at + (uint32_t)l];
        const double *v = s->meshes[tl->mesh].mesh->v;
        for (int i = 0; i < 3; i++)
            f->v[l][i] = v + 3 * (size_t)tl->v[i];
    }
}

/* The faces f (n <= 4), tested as one batch against tmax: in AVX's
** lanes, or one by one, as `simd` says (the same bits). */
ALWAYS_INLINE void triangles4(const query *q, const triangle4_faces *f, int n, double tmax,
                              int simd, double t[4], double bary[4][3])
{
    if (simd)
        triangle4_avx(f, n, q->r, &q->sh, tmax, t, bary);
    else
        triangle4_scalar(f, n, q->r, &q->sh, tmax, t, bary);
}

/* A group of n faces (refs[0, n), corners f) tested as one batch against
** tmax, its nearest kept as closest_leaf keeps it (the lower id on a tie);
** returns tmax, shrunk if one was nearer. */
ALWAYS_INLINE double closest_group(closest *c, const uint32_t *refs, int n,
                                   const triangle4_faces *f, double tmax, int simd)
{
    double t[4], bary[4][3];
    triangles4(c->q, f, n, tmax, simd, t, bary);
    c->np += (uint64_t)n;
    int better = 0;
    for (int l = 0; l < n; l++) {
        uint32_t id = refs[l];
        if (t[l] > 0 && (c->best == 0 || t[l] < c->best ||
                         (t[l] == c->best && id < c->best_id))) {
            c->best = t[l];
            c->best_id = id;
            c->h->bary[0] = bary[l][0];
            c->h->bary[1] = bary[l][1];
            c->h->bary[2] = bary[l][2];
            better = 1;
        }
    }
    return better ? next_up(c->best) : tmax;
}

/* A leaf of two or more flat triangles is tested four at a time against
** the tmax each group of four begins with, its nearest kept as
** closest_leaf keeps it (the lower id on a tie); with or without SIMD the
** same batches. Any other leaf: closest_leaf on each, in order. A batch
** has no early outs per face to mispredict: lc-raycast b3 707, incoherent
** rays 0.149 -> 0.129 s, shadow rays 0.104 -> 0.092 s. */
ALWAYS_INLINE double closest_run(void *ctx, uint32_t at, uint32_t count, double tmax,
                                 int simd)
{
    closest *c = ctx;
    const uint32_t *refs = c->s->c.bvh.refs + at;
    if (count < 2 || !all_triangles(refs, count)) {
        for (uint32_t k = 0; k < count; k++)
            tmax = closest_leaf(c, at + k, tmax);
        return tmax;
    }
    for (uint32_t g = 0; g < count; g += 4) {
        int n = count - g < 4 ? (int)(count - g) : 4;
        triangle4_faces f;
        leaf_faces(c->s, at + g, n, &f);
        tmax = closest_group(c, refs + g, n, &f, tmax, simd);
    }
    return tmax;
}

/* closest_leaf on each of refs[at, at + count), out of line: a packet's
** rays on a leaf of other shapes. Inlined into the packet walks as well,
** every kind's test used up the compiler's inlining budget for the file,
** and the single rays' any-hit walks lost their inlined sphere test (B1
** +0.7 % instructions). */
NEVER_INLINE double closest_each(closest *c, uint32_t at, uint32_t count, double tmax)
{
    for (uint32_t k = 0; k < count; k++)
        tmax = closest_leaf(c, at + k, tmax);
    return tmax;
}

/* Leaf slot of node nd for one ray (bvh_walk_closest's leaf test). */
ALWAYS_INLINE double closest_slot_plain(void *ctx, const bvh_node *nd, unsigned slot,
                                        double tmax)
{
    return closest_run(ctx, nd->child[slot], nd->count[slot], tmax, 0);
}

ALWAYS_INLINE double closest_slot_simd(void *ctx, const bvh_node *nd, unsigned slot,
                                       double tmax)
{
    return closest_run(ctx, nd->child[slot], nd->count[slot], tmax, 1);
}

BVH_DISPATCH(uint64_t, closest_walk,
             (const bvh *b, const bvh_ray *q, double tmax, closest *c), (b, q, tmax, c),
             uint64_t nn = 0;
             bvh_walk_closest(b, q, NULL, tmax, c, BVH_TEST, NULL,
                              BVH_LEVEL == BVH_SIMD_OFF ? closest_slot_plain
                                                        : closest_slot_simd, &nn);
             return nn;)

/* A closest-hit search begun: the query made and the planes tested, which
** bound tmax (returned). */
ALWAYS_INLINE double closest_begin(const lc_scene *s, const ray *r, double tmax, hit *h,
                                   hit *tmp, query *q, closest *c, bvh_counts *counts)
{
    query_init(q, r, s->c.nflat > 0);
    const plane_geom *planes = PLANES(s);
    size_t nplanes = s->shapes[LC_PLANE].n;
    c->s = s;
    c->q = q;
    c->best = 0;
    c->best_id = 0;
    c->h = h;
    c->tmp = tmp;
    c->np = nplanes;
    c->inner = counts;
    for (size_t i = 0; i < nplanes; i++) {      /* planes first: they bound tmax */
        double t = plane_query_t(planes + i, q->r, q->b.o, q->b.inv, tmax);
        if (t > 0 && (c->best == 0 || t < c->best)) {  /* in id order: a tie keeps the first */
            c->best = t;
            c->best_id = PRIM_ID(PRIM_PLANE, i);
            tmax = next_up(t);
        }
    }
    return tmax;
}

/* The nearest hit found, finished into *c->h: 1 if any. */
ALWAYS_INLINE int closest_end(const closest *c)
{
    if (c->best == 0 || !prim_finish(c->s, c->best_id, c->q, c->best, c->h))
        return 0;
    shading_normal(c->s, c->h);
    return 1;
}

int intersect_closest(const lc_scene *s, const ray *r, double tmax, hit *h,
                    bvh_counts *counts)
{
    bvh_counts spare;      /* nested searches count into counts, or here */
    hit tmp;
    query q;
    closest c;
    tmax = closest_begin(s, r, tmax, h, &tmp, &q, &c, counts ? counts : &spare);
    uint64_t nn = bvh_lone_leaf(&s->c.bvh) ? bvh_closest_lone(&s->c.bvh, &q.b, tmax, &c,
                                                              closest_leaf)
                                           : closest_walk(&s->c.bvh, &q.b, tmax, &c);
    if (counts) {
        counts->prims += c.np;
        counts->nodes += nn;
    }
    return closest_end(&c);
}

/* ---- Packets: neighbouring rays of an array walked together ---- */

/* A packet's closest-hit searches, one per ray, and its own box test. */
typedef struct {
    const lc_scene *s;
    closest   *c;
    double    *tmax;       /* each ray's */
    int        n;
    bvh_packet p;
} packet;

/* The largest of tmax[0, n). */
static inline double largest(const double *tmax, int n)
{
    double most = 0;
    for (int i = 0; i < n; i++)
        most = tmax[i] > most ? tmax[i] : most;
    return most;
}

/* Leaf refs[at, at + count), child slot of node nd, tested for each ray
** that meets its box before its own tmax (bvh_walk_closest's leaf test
** for the packet, whose tmax is the largest of the rays'). Returns the
** largest tmax. */
ALWAYS_INLINE double packet_leaf(packet *k, const bvh_node *nd, unsigned slot, int simd)
{
    uint32_t at = nd->child[slot], count = nd->count[slot];
    const uint32_t *refs = k->s->c.bvh.refs + at;
    unsigned meet = 0;
    for (int i = 0; i < k->n; i++)
        meet |= (unsigned)bvh_test_slot(nd, slot, &k->c[i].q->b, k->tmax[i]) << i;
    if (count >= 2 && all_triangles(refs, count)) {
        /* closest_run's groups in its order, each group's corners read once */
        for (uint32_t g = 0; meet && g < count; g += 4) {
            int n = count - g < 4 ? (int)(count - g) : 4;
            triangle4_faces f;
            leaf_faces(k->s, at + g, n, &f);
            for (unsigned m = meet; m; m &= m - 1) {
                int i = __builtin_ctz(m);
                k->tmax[i] = closest_group(&k->c[i], refs + g, n, &f, k->tmax[i], simd);
            }
        }
    } else
        for (unsigned m = meet; m; m &= m - 1) {
            int i = __builtin_ctz(m);
            k->tmax[i] = closest_each(&k->c[i], at, count, k->tmax[i]);
        }
    return largest(k->tmax, k->n);
}

ALWAYS_INLINE double packet_slot_plain(void *ctx, const bvh_node *nd, unsigned slot,
                                       double tmax)
{
    (void)tmax;
    return packet_leaf(ctx, nd, slot, 0);
}

ALWAYS_INLINE double packet_slot_simd(void *ctx, const bvh_node *nd, unsigned slot,
                                      double tmax)
{
    (void)tmax;
    return packet_leaf(ctx, nd, slot, 1);
}

/* The packet's closest-hit walk, from the largest of its rays' tmax. */
BVH_DISPATCH(uint64_t, closest_packet, (packet *k, const bvh *b), (k, b),
             uint64_t nn = 0;
             bvh_walk_closest(b, &k->p.lo, k->p.ihi, largest(k->tmax, k->n), k, BVH_TEST,
                              NULL, BVH_LEVEL == BVH_SIMD_OFF ? packet_slot_plain
                                                              : packet_slot_simd, &nn);
             return nn;)

/* Whether the directions r[0, n) share their signs on every axis (-0
** counts as negative, as a reciprocal's sign does), which a packet's box
** test needs: otherwise its bounds would span every direction. */
static int same_signs(const ray *r, int n)
{
    unsigned first = 0, all = 0;
    for (int i = 0; i < n; i++) {
        unsigned sg = (unsigned)!!signbit(r[i].d.x) | (unsigned)!!signbit(r[i].d.y) << 1 |
                      (unsigned)!!signbit(r[i].d.z) << 2;
        if (i == 0)
            first = sg;
        all |= sg ^ first;
    }
    return all == 0;
}

void intersect_closest_n(const lc_scene *s, const ray *r, const double *tmax, int n, hit *h,
                         int *found)
{
    const bvh *b = &s->c.bvh;
    if (n < 2 || !b->nnodes || bvh_lone_leaf(b) || !same_signs(r, n)) {
        for (int i = 0; i < n; i++)
            found[i] = intersect_closest(s, &r[i], tmax[i], &h[i], NULL);
        return;
    }
    bvh_counts spare;
    hit tmp[BVH_PACKET];
    query q[BVH_PACKET];
    closest c[BVH_PACKET];
    double tm[BVH_PACKET];
    packet k = {.s = s, .c = c, .tmax = tm, .n = n};
    int together = 1;
    for (int i = 0; i < n; i++) {
        tm[i] = closest_begin(s, &r[i], tmax[i], &h[i], &tmp[i], &q[i], &c[i], &spare);
        together &= i == 0 ? bvh_packet_start(&k.p, &q[0].b)
                           : bvh_packet_add(&k.p, &q[i].b);
    }
    if (!together)
        for (int i = 0; i < n; i++)
            closest_walk(b, &q[i].b, tm[i], &c[i]);
    else
        closest_packet(&k, b);
    for (int i = 0; i < n; i++)
        found[i] = closest_end(&c[i]);
}

/* The any-hit search's state. */
typedef struct {
    const lc_scene *s;
    const query *q;
    const ray *r;
    uint32_t skip;
    hit  *tmp;
    uint64_t np, nn;
    bvh_counts *inner;      /* what CSG objects' sweeps test */
} any;

/* The kinds with a search of their own inside: a moved mesh, a CSG object. */
#define NESTED ((1u << PRIM_INSTANCE) | (1u << PRIM_CSG))

static int any_nested(any *a, uint32_t id, double tmax)
{
    if (PRIM_KIND(id) == PRIM_CSG)
        return csg_occluded(a->s->csgs[PRIM_INDEX(id)], a->r, &a->q->b, tmax, a->inner);
    bvh_counts inner = {0, 0, 0};
    int found = instance_occluded(a->s, PRIM_INDEX(id), a->r, tmax, &inner);
    a->np += inner.prims;
    a->nn += inner.nodes;
    return found;
}

ALWAYS_INLINE int any_leaf(void *ctx, uint32_t at, double tmax)
{
    any *a = ctx;
    uint32_t id = a->s->c.bvh.refs[at];
    if (id == a->skip)
        return 0;
    ++a->np;
    if ((NESTED >> PRIM_KIND(id)) & 1)
        return any_nested(a, id, tmax);
    return prim_t(a->s, id, at, a->q, tmax, a->tmp, NULL) > 0;   /* not nested */
}

/* A leaf of two or more flat triangles, none the one to skip, is tested
** four at a time, as closest_run does; the tests counted are those up to
** the first blocker in order, as any_leaf on each counts them. */
ALWAYS_INLINE int any_run(void *ctx, uint32_t at, uint32_t count, double tmax, int simd)
{
    any *a = ctx;
    const uint32_t *refs = a->s->c.bvh.refs + at;
    int batch = count >= 2 && all_triangles(refs, count);
    for (uint32_t k = 0; batch && k < count; k++)
        batch = refs[k] != a->skip;
    if (!batch) {
        for (uint32_t k = 0; k < count; k++)
            if (any_leaf(a, at + k, tmax))
                return 1;
        return 0;
    }
    for (uint32_t g = 0; g < count; g += 4) {
        int n = count - g < 4 ? (int)(count - g) : 4;
        double t[4], bary[4][3];
        triangle4_faces f;
        leaf_faces(a->s, at + g, n, &f);
        triangles4(a->q, &f, n, tmax, simd, t, bary);
        for (int l = 0; l < n; l++)
            if (t[l] > 0) {
                a->np += (uint64_t)l + 1;
                return 1;
            }
        a->np += (uint64_t)n;
    }
    return 0;
}

/* Leaf slot of node nd for one ray (bvh_walk_any's leaf test). */
ALWAYS_INLINE int any_slot_plain(void *ctx, const bvh_node *nd, unsigned slot, double *tmax)
{
    return any_run(ctx, nd->child[slot], nd->count[slot], *tmax, 0);
}

ALWAYS_INLINE int any_slot_simd(void *ctx, const bvh_node *nd, unsigned slot, double *tmax)
{
    return any_run(ctx, nd->child[slot], nd->count[slot], *tmax, 1);
}

BVH_DISPATCH(int, any_walk, (const bvh *b, const bvh_ray *q, double tmax, any *a),
             (b, q, tmax, a),
             return bvh_walk_any(b, q, NULL, tmax, a, BVH_TEST, NULL,
                                 BVH_LEVEL == BVH_SIMD_OFF ? any_slot_plain : any_slot_simd,
                                 &a->nn);)

/* An any-hit search begun: the query made and the planes tested; 1 when
** one blocks the ray (the search is then over). */
ALWAYS_INLINE int any_begin(const lc_scene *s, const ray *r, double tmax, uint32_t skip,
                            query *q, any *a, hit *tmp, uint64_t *np, bvh_counts *inner)
{
    query_init(q, r, s->c.nflat > 0);
    const plane_geom *planes = PLANES(s);
    size_t nplanes = s->shapes[LC_PLANE].n;
    for (size_t i = 0; i < nplanes; i++)
        if (plane_query_t(planes + i, q->r, q->b.o, q->b.inv, tmax) > 0) {
            *np += i + 1;
            return 1;
        }
    *np += nplanes;
    *a = (any){s, q, r, skip, tmp, 0, 0, inner};
    return 0;
}

/* Any hit: the first primitive found in (0, tmax) ends the search. */
ALWAYS_INLINE int occluded(const lc_scene *s, const ray *r, double tmax, uint32_t skip,
                           uint64_t *np, uint64_t *nn, bvh_counts *inner)
{
    query q;
    any a;
    hit tmp;
    if (any_begin(s, r, tmax, skip, &q, &a, &tmp, np, inner))
        return 1;
    int found = bvh_lone_leaf(&s->c.bvh) ? bvh_any_lone(&s->c.bvh, &q.b, tmax, &a, any_leaf,
                                                        &a.nn)
                                         : any_walk(&s->c.bvh, &q.b, tmax, &a);
    *np += a.np;
    *nn += a.nn;
    return found;
}

/* A packet's any-hit searches: the rays not yet blocked (live, a mask),
** each with its own tmax. */
typedef struct {
    any       *a;
    const double *tmax;
    int       *blocked;
    unsigned   live;
    bvh_packet p;
} any_packet;

/* Leaf slot of node nd tested for each live ray that meets its box
** (bvh_walk_any's leaf test for the packet): *tmax becomes the largest of
** those still live; 1 when none is. */
ALWAYS_INLINE int any_packet_leaf(any_packet *k, const bvh_node *nd, unsigned slot,
                                  double *tmax, int simd)
{
    uint32_t at = nd->child[slot], count = nd->count[slot];
    double most = 0;
    for (unsigned m = k->live; m; m &= m - 1) {
        int i = __builtin_ctz(m);
        if (bvh_test_slot(nd, slot, &k->a[i].q->b, k->tmax[i]) &&
            any_run(&k->a[i], at, count, k->tmax[i], simd)) {
            k->blocked[i] = 1;
            k->live &= ~(1u << i);
        } else
            most = k->tmax[i] > most ? k->tmax[i] : most;
    }
    *tmax = most;
    return !k->live;
}

ALWAYS_INLINE int any_packet_slot_plain(void *ctx, const bvh_node *nd, unsigned slot,
                                        double *tmax)
{
    return any_packet_leaf(ctx, nd, slot, tmax, 0);
}

ALWAYS_INLINE int any_packet_slot_simd(void *ctx, const bvh_node *nd, unsigned slot,
                                       double *tmax)
{
    return any_packet_leaf(ctx, nd, slot, tmax, 1);
}

/* The packet's any-hit walk, from the largest tmax of its live rays,
** until every ray is blocked. */
BVH_DISPATCH(int, occluded_packet, (any_packet *k, const bvh *b), (k, b),
             double tmax = 0;
             for (unsigned m = k->live; m; m &= m - 1)
                 tmax = k->tmax[__builtin_ctz(m)] > tmax ? k->tmax[__builtin_ctz(m)] : tmax;
             uint64_t nn = 0;
             return bvh_walk_any(b, &k->p.lo, k->p.ihi, tmax, k, BVH_TEST, NULL,
                                 BVH_LEVEL == BVH_SIMD_OFF ? any_packet_slot_plain
                                                           : any_packet_slot_simd, &nn);)

void intersect_occluded_n(const lc_scene *s, const ray *r, const double *tmax, int n,
                          int *blocked)
{
    const bvh *b = &s->c.bvh;
    if (n < 2 || !b->nnodes || bvh_lone_leaf(b) || !same_signs(r, n)) {
        for (int i = 0; i < n; i++)
            blocked[i] = intersect_occluded(s, &r[i], tmax[i], NULL);
        return;
    }
    bvh_counts spare;
    hit tmp[BVH_PACKET];
    query q[BVH_PACKET];
    any a[BVH_PACKET];
    uint64_t np = 0;
    any_packet k = {.a = a, .tmax = tmax, .blocked = blocked, .live = 0};
    int together = 1, first = 1;
    for (int i = 0; i < n; i++) {
        blocked[i] = any_begin(s, &r[i], tmax[i], INTERSECT_SKIP_NONE, &q[i], &a[i], &tmp[i],
                               &np, &spare);
        if (blocked[i])
            continue;
        k.live |= 1u << i;
        together &= first ? bvh_packet_start(&k.p, &q[i].b)
                          : bvh_packet_add(&k.p, &q[i].b);
        first = 0;
    }
    if (!k.live)
        return;
    if (!together)
        for (unsigned m = k.live; m; m &= m - 1) {
            int i = __builtin_ctz(m);
            blocked[i] = any_walk(b, &q[i].b, tmax[i], &a[i]);
        }
    else
        occluded_packet(&k, b);
}

int intersect_occluded(const lc_scene *s, const ray *r, double tmax, bvh_counts *counts)
{
    return intersect_occluded_skip(s, r, tmax, INTERSECT_SKIP_NONE, counts);
}

int intersect_occluded_skip(const lc_scene *s, const ray *r, double tmax, uint32_t skip,
                        bvh_counts *counts)
{
    uint64_t np = 0, nn = 0;
    bvh_counts spare;                 /* CSG sweeps count into it when counts is NULL */
    int found = occluded(s, r, tmax, skip, &np, &nn, counts ? counts : &spare);
    if (counts) {
        counts->prims += np;
        counts->nodes += nn;
    }
    return found;
}
