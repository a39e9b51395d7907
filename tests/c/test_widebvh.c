/* test_widebvh.c: the 4-wide BVH finds exactly what a scan of every primitive
** finds, for every primitive kind, whatever its box test (SIMD or scalar);
** its box test culls no box an exact slab test meets; images do not depend
** on the box test or the thread count. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "base/mem.h"
#include "scene/scene.h"
#include "shapes/triangle4.h"
#include "accel/bvh_packet.h"
#include "helpers.h"
#include "scene/compile.h"
#include "render/plan.h"
#include "scene/intersect.h"

#define M_PI 3.14159265358979323846
#define RANDOM_RAYS      100000
#define ADVERSARIAL_RAYS 100000

static uint64_t rng_state = 2718281828u;

static double rnd(void)          /* deterministic, [0, 1) */
{
    return lcg(&rng_state);
}

static double range(double a, double b) { return a + (b - a) * rnd(); }
static lc_vec3 rvec(double a, double b) { return v3(range(a, b), range(a, b), range(a, b)); }

static lc_vec3 random_dir(void) { return rand_sphere_dir(&rng_state); }

/* ---- a scene with every primitive kind ------------------------------------------ */

static void add(lc_scene *s, lc_shape sh, int mi)
{
    lc_error err;
    int id = lc_scene_add_shape(s, &sh, mi, &err);
    if (id < 0)
        fail_msg("%s: %s", lc_shape_kind_name(sh.kind), err.msg);
}

/* A small closed mesh: an octahedron, for the instances. */
static lc_mesh *octahedron(void)
{
    static const double v[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    static const uint32_t f[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                                 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    lc_error err;
    lc_mesh *m = lc_mesh_new(&err);
    assert_int_equal(lc_mesh_add_vertices(m, v, 6, &err), LC_OK);
    assert_int_equal(lc_mesh_add_faces(m, f, 8, &err), LC_OK);
    return m;
}

/* Spheres (some coincident: exact ties), aligned and turned boxes, quads
** (some coplanar), a grid mesh with shared edges and loose triangles, moved
** meshes, discs, cylinders, cones, tori, ellipsoids, and two planes. */
static lc_scene *mixed_scene(void)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    for (int i = 0; i < 120; i++) {
        lc_shape sp = {.kind = LC_SPHERE, .p = rvec(-10, 10), .radius = range(0.05, 0.8)};
        add(s, sp, mi);
        if (i % 16 == 0)
            add(s, sp, mi);                       /* the same sphere twice */
    }
    for (int i = 0; i < 60; i++) {
        lc_shape b = {.kind = LC_BOX, .p = rvec(-10, 10), .u = {range(0.1, 1.5), 0, 0},
                      .v = {0, range(0.1, 1.5), 0}, .w = {0, 0, range(0.1, 1.5)}};
        add(s, b, mi);
    }
    for (int i = 0; i < 30; i++) {
        lc_vec3 a = v3_norm(random_dir()), t = v3_norm(v3_cross(a, random_dir()));
        lc_vec3 c = v3_cross(a, t);
        lc_shape b = {.kind = LC_BOX, .p = rvec(-10, 10), .u = v3_mul(a, range(0.1, 1.5)),
                      .v = v3_mul(t, range(0.1, 1.5)), .w = v3_mul(c, range(0.1, 1.5))};
        add(s, b, mi);
    }
    for (int i = 0; i < 60; i++) {
        lc_shape q = {.kind = LC_QUAD, .p = rvec(-10, 10), .u = rvec(-1.5, 1.5),
                      .v = rvec(-1.5, 1.5)};
        if (i % 3 == 0)
            q.u.y = q.v.y = 0;                     /* horizontal: axis planes */
        add(s, q, mi);
        if (i % 10 == 0) {                        /* coplanar, overlapping */
            q.p = v3_add(q.p, v3_mul(q.u, 0.5));
            add(s, q, mi);
        }
    }
    for (int i = 0; i < 25; i++) {
        lc_shape d = {.kind = LC_DISC, .p = rvec(-10, 10), .u = random_dir(),
                      .radius = range(0.2, 1), .radius2 = i % 2 ? 0 : 0.1};
        add(s, d, mi);
        lc_shape cy = {.kind = LC_CYLINDER, .p = rvec(-10, 10),
                       .u = v3_mul(random_dir(), range(0.3, 2)), .radius = range(0.1, 0.7),
                       .caps = i % 2};
        add(s, cy, mi);
        lc_shape co = {.kind = LC_CONE, .p = rvec(-10, 10),
                       .u = v3_mul(random_dir(), range(0.3, 2)), .radius = range(0.2, 0.7),
                       .radius2 = i % 3 ? 0 : 0.1, .caps = i % 2};
        add(s, co, mi);
        lc_shape to = {.kind = LC_TORUS, .p = rvec(-10, 10), .u = random_dir(),
                       .radius = range(0.4, 1), .radius2 = range(0.05, 0.3)};
        add(s, to, mi);
        lc_shape el = {.kind = LC_ELLIPSOID, .p = rvec(-10, 10),
                       .u = v3(range(0.1, 1), range(0.1, 1), range(0.1, 1))};
        add(s, el, mi);
    }
    lc_shape floor = {.kind = LC_PLANE, .p = {0, -12, 0}, .u = {0, 1, 0}};
    add(s, floor, mi);
    lc_shape tilted = {.kind = LC_PLANE, .p = {0, 0, 13}, .u = {0.1, 0.2, -1}};
    add(s, tilted, mi);

    /* A 16 x 16 grid, bumpy, with shared edges and vertices, and loose faces. */
    lc_mesh *grid = lc_mesh_new(&err);
    const int g = 16;
    for (int j = 0; j <= g; j++)
        for (int i = 0; i <= g; i++) {
            double p[3] = {-9 + 18.0 * i / g, 0.3 * sin(i) * cos(j), -9 + 18.0 * j / g};
            lc_mesh_add_vertices(grid, p, 1, &err);
        }
    for (int j = 0; j < g; j++)
        for (int i = 0; i < g; i++) {
            uint32_t a = (uint32_t)(j * (g + 1) + i), b = a + 1, c = a + (uint32_t)g + 1;
            uint32_t f[6] = {a, b, c + 1, a, c + 1, c};
            lc_mesh_add_faces(grid, f, 2, &err);
        }
    for (int i = 0; i < 150; i++) {
        lc_vec3 c = rvec(-10, 10);
        double v[9];
        for (int k = 0; k < 9; k++)
            v[k] = v3_comp(c, k % 3) + range(-0.7, 0.7);
        uint32_t base = (uint32_t)lc_mesh_vertex_count(grid);
        uint32_t f[3] = {base, base + 1, base + 2};
        lc_mesh_add_vertices(grid, v, 3, &err);
        lc_mesh_add_faces(grid, f, 1, &err);
    }
    assert_true(lc_scene_add_mesh(s, grid, mi, &err) >= 0);
    lc_mesh_free(grid);

    lc_mesh *oct = octahedron();
    for (int i = 0; i < 12; i++) {
        lc_transform r, t = lc_transform_translate(rvec(-9, 9));
        lc_transform sc = lc_transform_scale(v3(range(0.2, 1.2), range(0.2, 1.2),
                                                range(0.2, 1.2)));
        assert_int_equal(lc_transform_rotate(random_dir(), range(0, 360), &r, &err), LC_OK);
        lc_transform rs = lc_transform_compose(&r, &sc), x = lc_transform_compose(&t, &rs);
        assert_true(lc_scene_add_mesh_moved(s, oct, &x, mi, &err) >= 0);
    }
    lc_mesh_free(oct);
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    assert_true(s->c.bvh.nnodes > 20);
    return s;
}

/* ---- the reference: every primitive, in id order --------------------------------- */

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* A hierarchy of one node whose leaves hold all of b's refs sorted by id,
** under boxes spanning all of float: a traversal of it tests every
** primitive, whatever the ray. */
static bvh flat_of(const bvh *b)
{
    bvh f;
    memset(&f, 0, sizeof f);
    if (!b->nnodes)
        return f;
    f.refs = malloc(b->nrefs * sizeof *f.refs);
    memcpy(f.refs, b->refs, b->nrefs * sizeof *f.refs);
    qsort(f.refs, b->nrefs, sizeof *f.refs, cmp_u32);
    f.nrefs = b->nrefs;
    if (posix_memalign(&f.block, 64, sizeof(bvh_node)))
        fail_msg("out of memory");
    f.nodes = f.block;
    f.nnodes = 1;
    bvh_node *nd = f.nodes;
    memset(nd, 0, sizeof *nd);
    size_t per = (b->nrefs + 3) / 4;
    assert_true(per <= 0xffff);
    for (int c = 0; c < 4; c++) {
        size_t first = c * per, end = first + per < b->nrefs ? first + per : b->nrefs;
        for (int k = 0; k < 3; k++) {
            nd->lo[k][c] = first < end ? -FLT_MAX : HUGE_VALF;
            nd->hi[k][c] = first < end ? FLT_MAX : -HUGE_VALF;
        }
        if (first < end) {
            nd->child[c] = (uint32_t)first;
            nd->count[c] = (uint16_t)(end - first);
            nd->n = (uint32_t)c + 1;
        }
    }
    return f;
}

static void flat_free(bvh *f)
{
    free(f->refs);
    free(f->block);
}

/* The scene's hierarchies (its own and its moved meshes'), swappable with
** their flat references. */
typedef struct {
    lc_scene *s;
    bvh real, flat, *blas_real, *blas_flat;
    tri_leaf *tleaf_real, *tleaf_flat;    /* the triangles beside each one's refs */
} reference;

static void reference_init(reference *r, lc_scene *s)
{
    r->s = s;
    r->real = s->c.bvh;
    r->flat = flat_of(&s->c.bvh);
    r->tleaf_real = s->c.tleaf;
    r->tleaf_flat = s->c.ntris ? compile_tri_leaves(s, &r->flat) : NULL;
    r->blas_real = malloc((s->nblas + 1) * sizeof *r->blas_real);
    r->blas_flat = malloc((s->nblas + 1) * sizeof *r->blas_flat);
    for (size_t i = 0; i < s->nblas; i++) {
        r->blas_real[i] = s->blas[i].bvh;
        r->blas_flat[i] = flat_of(&s->blas[i].bvh);
    }
}

static void use(reference *r, int flat)
{
    r->s->c.bvh = flat ? r->flat : r->real;
    r->s->c.tleaf = flat ? r->tleaf_flat : r->tleaf_real;
    for (size_t i = 0; i < r->s->nblas; i++)
        r->s->blas[i].bvh = flat ? r->blas_flat[i] : r->blas_real[i];
}

static void reference_free(reference *r)
{
    use(r, 0);
    mem_free(r->tleaf_flat);
    flat_free(&r->flat);
    for (size_t i = 0; i < r->s->nblas; i++)
        flat_free(&r->blas_flat[i]);
    free(r->blas_real);
    free(r->blas_flat);
}

/* ---- one ray, three ways ---------------------------------------------------------- */

typedef struct {
    long rays, hits, mismatches, simd_mismatches, occluded_checks;
    long kind_hits[PRIM_KINDS];
} tally;

static int dbg_case = -1;
static int same_hit(int fa, const hit *a, int fb, const hit *b)
{
    if (fa != fb)
        return 0;
    return !fa || (a->t == b->t && a->shape == b->shape && a->instance == b->instance);
}

/* The BVH with the SIMD box test, with the scalar one, and the scan: the
** same hit (or none), the same distance to the bit, the same primitive;
** the two box tests also the same counts of tests. Any-hit agrees with the
** scan's at a tmax cut short, and with the nearest hit at tmax infinite. */
static void check_ray(reference *ref, const ray *r, tally *t)
{
    lc_scene *s = ref->s;
    hit a, b, c;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    memset(&c, 0, sizeof c);
    bvh_counts ca = {0}, cb = {0}, cd = {0};
    use(ref, 0);
    int was = bvh_simd_set(BVH_SIMD_AVX512);     /* the best the processor has */
    int fa = intersect_closest(s, r, HUGE_VAL, &a, &ca);
    bvh_simd_set(BVH_SIMD_AVX);
    hit d;
    memset(&d, 0, sizeof d);
    int fd = intersect_closest(s, r, HUGE_VAL, &d, &cd);
    bvh_simd_set(BVH_SIMD_OFF);
    int fb = intersect_closest(s, r, HUGE_VAL, &b, &cb);
    use(ref, 1);
    int fc = intersect_closest(s, r, HUGE_VAL, &c, NULL);
    t->rays++;
    t->hits += fc;
    if (fc)
        t->kind_hits[PRIM_KIND(c.shape)]++;
    if (!same_hit(fa, &a, fc, &c)) {
        t->mismatches++;
        if (getenv("DEBUG_WIDE"))
            printf("closest case %d: bvh %d t=%.17g id=%x inst=%u  scan %d t=%.17g id=%x inst=%u\n",
                   dbg_case, fa, a.t, a.shape, a.instance, fc, c.t, c.shape, c.instance);
    }
    if (!same_hit(fa, &a, fb, &b) || ca.nodes != cb.nodes || ca.prims != cb.prims ||
        !same_hit(fa, &a, fd, &d) || ca.nodes != cd.nodes || ca.prims != cd.prims)
        t->simd_mismatches++;
    /* any hit, up to infinity and up to a random fraction of the hit */
    double cut = fc ? c.t * range(0.5, 1.5) : range(1, 40);
    int oc = intersect_occluded(s, r, cut, NULL);
    use(ref, 0);
    int ob = intersect_occluded(s, r, cut, NULL);
    bvh_simd_set(BVH_SIMD_AVX512);
    int oa = intersect_occluded(s, r, cut, NULL), ai = intersect_occluded(s, r, HUGE_VAL, NULL);
    bvh_simd_set(was);
    t->occluded_checks++;
    if (oa != oc || ai != fc) {
        t->mismatches++;
        if (getenv("DEBUG_WIDE"))
            printf("occluded case %d: cut %d/%d inf %d closest %d t=%.17g id=%x cut=%.17g\n",
                   dbg_case, oa, oc, ai, fc, c.t, c.shape, cut);
    }
    if (ob != oa)
        t->simd_mismatches++;
}

/* ---- adversarial rays ------------------------------------------------------------- */

/* A child box of a random node of the scene's hierarchy, in double. */
static void some_box(const bvh *b, double lo[3], double hi[3])
{
    const bvh_node *nd = &b->nodes[(size_t)(rnd() * b->nnodes)];
    uint32_t c = (uint32_t)(rnd() * nd->n);
    for (int k = 0; k < 3; k++) {
        lo[k] = nd->lo[k][c];
        hi[k] = nd->hi[k][c];
    }
}

/* A point on the box's surface: each coordinate a bound, or (for at most
** two of them) strictly between: corners, edges and faces. */
static lc_vec3 on_box(const double lo[3], const double hi[3])
{
    double p[3];
    int free_axes = (int)(rnd() * 3);
    for (int k = 0; k < 3; k++)
        p[k] = k < free_axes ? range(lo[k], hi[k]) : rnd() < 0.5 ? lo[k] : hi[k];
    return v3(p[0], p[1], p[2]);
}

static const double AXES[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

static ray adversarial(const lc_scene *s, int i)
{
    const bvh *b = &s->c.bvh;
    double lo[3], hi[3];
    ray r;
    switch (i % 8) {
    case 0: {                      /* along an axis, from a box's face or outside */
        const double *a = AXES[(int)(rnd() * 6)];
        some_box(b, lo, hi);
        r.o = rnd() < 0.5 ? on_box(lo, hi) : rvec(-15, 15);
        r.d = v3(a[0], a[1], a[2]);
        break;
    }
    case 1:                        /* at a node's box corner, edge or face */
        some_box(b, lo, hi);
        r.o = rvec(-15, 15);
        r.d = v3_norm(v3_sub(on_box(lo, hi), r.o));
        break;
    case 2:                        /* from inside a node's box */
        some_box(b, lo, hi);
        r.o = v3(range(lo[0], hi[0]), range(lo[1], hi[1]), range(lo[2], hi[2]));
        r.d = random_dir();
        break;
    case 3: {                      /* in the plane of a box's face: 0 * inf */
        some_box(b, lo, hi);
        int k = (int)(rnd() * 3);
        r.o = rvec(-15, 15);
        double *o = &r.o.x;
        o[k] = rnd() < 0.5 ? lo[k] : hi[k];
        lc_vec3 d = random_dir();
        (&d.x)[k] = 0;
        if (rnd() < 0.3)
            (&d.x)[(k + 1) % 3] = 0;           /* along an edge's line */
        r.d = v3_norm(d);
        break;
    }
    case 4: {                      /* grazing a sphere */
        const shape_list *l = &s->shapes[LC_SPHERE];
        const sphere_geom *g = shape_at(l, (size_t)(rnd() * l->n));
        lc_vec3 n = random_dir();
        lc_vec3 tan = v3_norm(v3_cross(n, random_dir()));
        lc_vec3 p = v3_add(g->c, v3_mul(n, g->r));
        r.o = v3_sub(p, v3_mul(tan, range(1, 20)));
        r.d = tan;
        break;
    }
    case 5: {                      /* at a mesh vertex or a point of an edge */
        const tri_ref *tr = &s->c.tris[(size_t)(rnd() * s->c.nflat)];
        const lc_mesh *m = s->meshes[tr->mesh].mesh;
        const uint32_t *f = m->f + 3 * (size_t)tr->face;
        const double *v0 = m->v + 3 * (size_t)f[0], *v1 = m->v + 3 * (size_t)f[1];
        double w = rnd() < 0.5 ? 0 : rnd();
        lc_vec3 p = v3(v0[0] + w * (v1[0] - v0[0]), v0[1] + w * (v1[1] - v0[1]),
                       v0[2] + w * (v1[2] - v0[2]));
        r.o = rvec(-15, 15);
        r.d = v3_norm(v3_sub(p, r.o));
        break;
    }
    case 6: {                      /* grazing a triangle: in its plane */
        const tri_ref *tr = &s->c.tris[(size_t)(rnd() * s->c.nflat)];
        const lc_mesh *m = s->meshes[tr->mesh].mesh;
        const uint32_t *f = m->f + 3 * (size_t)tr->face;
        const double *v0 = m->v + 3 * (size_t)f[0], *v1 = m->v + 3 * (size_t)f[1];
        lc_vec3 a = v3(v0[0], v0[1], v0[2]), e = v3_sub(v3(v1[0], v1[1], v1[2]), a);
        r.d = v3_norm(e);
        r.o = v3_sub(a, v3_mul(r.d, range(0.5, 10)));
        break;
    }
    default:                       /* from a node's box corner, any way */
        some_box(b, lo, hi);
        r.o = on_box(lo, hi);
        r.d = random_dir();
        break;
    }
    return r;
}

static void report(const char *what, const tally *t)
{
    printf("%s: %ld rays, %ld hits (sphere %ld quad %ld box %ld triangle %ld plane %ld "
           "disc %ld cylinder %ld cone %ld torus %ld ellipsoid %ld), %ld mismatches with "
           "the scan, %ld between SIMD and scalar\n", what, t->rays, t->hits,
           t->kind_hits[PRIM_SPHERE], t->kind_hits[PRIM_QUAD], t->kind_hits[PRIM_BOX],
           t->kind_hits[PRIM_TRIANGLE], t->kind_hits[PRIM_PLANE], t->kind_hits[PRIM_DISC],
           t->kind_hits[PRIM_CYLINDER], t->kind_hits[PRIM_CONE], t->kind_hits[PRIM_TORUS],
           t->kind_hits[PRIM_ELLIPSOID], t->mismatches, t->simd_mismatches);
}

static void assert_every_kind(const tally *t)
{
    static const int kinds[] = {PRIM_SPHERE, PRIM_QUAD, PRIM_BOX, PRIM_TRIANGLE, PRIM_PLANE,
                                PRIM_DISC, PRIM_CYLINDER, PRIM_CONE, PRIM_TORUS,
                                PRIM_ELLIPSOID};
    for (size_t i = 0; i < sizeof kinds / sizeof *kinds; i++)
        assert_true(t->kind_hits[kinds[i]] >= 50);
}

static void wide_bvh_matches_the_scan(void **state)
{
    (void)state;
    lc_scene *s = mixed_scene();
    reference ref;
    reference_init(&ref, s);
    tally rt, at;
    memset(&rt, 0, sizeof rt);
    memset(&at, 0, sizeof at);
    long instance_hits = 0;
    for (int i = 0; i < RANDOM_RAYS; i++) {
        ray r = {rvec(-15, 15), random_dir()};
        check_ray(&ref, &r, &rt);
    }
    for (int i = 0; i < ADVERSARIAL_RAYS; i++) {
        ray r = adversarial(s, i);
        dbg_case = i % 8;
        check_ray(&ref, &r, &at);
        hit h;
        use(&ref, 0);
        if (intersect_closest(s, &r, HUGE_VAL, &h, NULL) && h.instance)
            instance_hits++;
    }
    report("random", &rt);
    report("adversarial", &at);
    printf("adversarial rays on moved meshes: %ld\n", instance_hits);
    reference_free(&ref);
    assert_int_equal(rt.mismatches, 0);
    assert_int_equal(rt.simd_mismatches, 0);
    assert_int_equal(at.mismatches, 0);
    assert_int_equal(at.simd_mismatches, 0);
    assert_every_kind(&rt);
    assert_every_kind(&at);
    assert_true(instance_hits >= 50);
    lc_scene_free(s);
}

/* A few bounded shapes in one leaf (bvh_lone_leaf: two coincident spheres
** and a box, weighing 4), planes around: the inline path finds what the
** scan finds. */
static void lone_leaf_matches_the_scan(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    add(s, (lc_shape){.kind = LC_SPHERE, .p = {1.8, 0.8, -0.5}, .radius = 0.8}, mi);
    add(s, (lc_shape){.kind = LC_SPHERE, .p = {1.8, 0.8, -0.5}, .radius = 0.8}, mi);
    add(s, (lc_shape){.kind = LC_BOX, .p = {1, 0, -4.4}, .u = {1.6, 0, 0}, .v = {0, 1.6, 0},
                      .w = {0, 0, 1.6}}, mi);
    add(s, (lc_shape){.kind = LC_PLANE, .p = {0, 0, 0}, .u = {0, 1, 0}}, mi);
    add(s, (lc_shape){.kind = LC_PLANE, .p = {0, 0, -6}, .u = {0, 0, 1}}, mi);
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    assert_true(bvh_lone_leaf(&s->c.bvh));
    reference ref;
    reference_init(&ref, s);
    tally t;
    memset(&t, 0, sizeof t);
    for (int i = 0; i < 20000; i++) {
        ray r = {rvec(-5, 5), random_dir()};
        if (i % 2) {                           /* at the leaf's box, or along an axis */
            double lo[3], hi[3];
            some_box(&s->c.bvh, lo, hi);
            r.d = i % 4 == 1 ? v3_norm(v3_sub(on_box(lo, hi), r.o))
                             : v3(AXES[i % 6][0], AXES[i % 6][1], AXES[i % 6][2]);
        }
        check_ray(&ref, &r, &t);
    }
    report("one leaf", &t);
    reference_free(&ref);
    assert_int_equal(t.mismatches, 0);
    assert_int_equal(t.simd_mismatches, 0);
    assert_true(t.kind_hits[PRIM_SPHERE] > 500 && t.kind_hits[PRIM_BOX] > 100);
    lc_scene_free(s);
}

/* ---- the box test itself ---------------------------------------------------------- */

/* The slab interval of the exact ray o + t d against the box, in long
** double (64-bit mantissa: each distance within a few 1e-20 of exact), and
** its width relative to the distances. A ray in a slab's plane is inside
** or outside that slab for every t. */
static int exact_interval(const double o[3], const double d[3], const double lo[3],
                          const double hi[3], double tmax, long double *t0, long double *t1)
{
    *t0 = 0;
    *t1 = tmax;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k])
                return 0;
            continue;
        }
        long double a = ((long double)lo[k] - o[k]) / d[k];
        long double b = ((long double)hi[k] - o[k]) / d[k];
        if (a > b) {
            long double x = a; a = b; b = x;
        }
        if (a > *t0) *t0 = a;
        if (b < *t1) *t1 = b;
    }
    return 1;
}

/* The SIMD box test, where the processor has it. */
BVH_AVX_TARGET static unsigned avx_test(const bvh_node *nd, const bvh_ray *q, double tmax,
                                        double t[BVH_WIDTH])
{
    return bvh_test_avx(nd, q, tmax, t);
}

BVH_AVX512_TARGET static unsigned avx512_test(const bvh_node *nd, const bvh_ray *q,
                                              double tmax, double t[BVH_WIDTH])
{
    return bvh_test_avx512(nd, q, tmax, t);
}

/* Rays at box corners, edges and faces, along faces and from them: each
** box the exact slab test meets by more than the long double's own error is
** met by both box tests, which agree to the bit; some are met within
** double's rounding (where the 1 + 2 gamma(3) matters). */
static void box_test_is_conservative(void **state)
{
    (void)state;
    bvh_node nd __attribute__((aligned(64)));
    int was = bvh_simd_set(BVH_SIMD_AVX512), best = bvh_simd;
    bvh_simd_set(was);
    long cases = 0, tight = 0, culled = 0, differ = 0, meet = 0;
    for (int i = 0; i < 200000; i++) {
        memset(&nd, 0, sizeof nd);
        nd.n = BVH_WIDTH - (uint32_t)(i % 3 == 0 ? rnd() * (BVH_WIDTH - 1) : 0);
        double lo[BVH_WIDTH][3], hi[BVH_WIDTH][3];
        double scale = pow(10, range(-4, 5)), shift = rnd() < 0.3 ? pow(10, range(0, 6)) : 0;
        for (uint32_t c = 0; c < BVH_WIDTH; c++)
            for (int k = 0; k < 3; k++) {
                float a = (float)(shift + scale * range(-1, 1));
                float b = (float)(shift + scale * range(-1, 1));
                if (i % 7 == 0 && c == 1)
                    b = a;                                   /* flat box */
                if (c >= nd.n) {                             /* empty, as collapse leaves it */
                    a = HUGE_VALF;
                    b = -HUGE_VALF;
                }
                nd.lo[k][c] = c >= nd.n || a < b ? a : b;
                nd.hi[k][c] = c >= nd.n || a < b ? b : a;
                lo[c][k] = nd.lo[k][c];
                hi[c][k] = nd.hi[k][c];
            }
        uint32_t c = (uint32_t)(rnd() * nd.n);
        lc_vec3 o = v3_add(v3(shift, shift, shift), v3_mul(rvec(-3, 3), scale));
        lc_vec3 target = on_box(lo[c], hi[c]);
        lc_vec3 d = v3_norm(v3_sub(target, o));
        switch (i % 4) {
        case 1: {                  /* from the target, along a face */
            int k = (int)(rnd() * 3);
            o = target;
            d = random_dir();
            (&d.x)[k] = 0;
            d = v3_norm(d);
            break;
        }
        case 2: {                  /* along an axis through the target */
            const double *a = AXES[(int)(rnd() * 6)];
            d = v3(a[0], a[1], a[2]);
            o = v3_sub(target, v3_mul(d, scale * range(0, 3)));
            break;
        }
        default:
            break;
        }
        bvh_ray q;
        bvh_ray_init(&q, o, d);
        double tmax = rnd() < 0.2 ? scale * range(0.5, 5) : HUGE_VAL;
        double ts[BVH_WIDTH], tv[BVH_WIDTH];
        unsigned ms = bvh_test_scalar(&nd, &q, tmax, ts);
        /* Each SIMD test the processor has agrees with the scalar one. */
        for (int level = BVH_SIMD_AVX; level <= best; level++) {
            unsigned mv = level == BVH_SIMD_AVX ? avx_test(&nd, &q, tmax, tv)
                                                : avx512_test(&nd, &q, tmax, tv);
            for (uint32_t b = 0; b < nd.n; b++)     /* the entry distances of boxes met */
                if ((ms >> b & 1) && memcmp(&ts[b], &tv[b], sizeof *ts))
                    differ++;
            if (mv != ms)
                differ++;
        }
        double od[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
        for (uint32_t b = 0; b < nd.n; b++) {
            long double t0, t1;
            if (!exact_interval(od, dd, lo[b], hi[b], tmax, &t0, &t1))
                continue;
            long double big = fabsl(t0) > fabsl(t1) ? fabsl(t0) : fabsl(t1);
            long double width = t1 - t0;
            if (!(width > 1e-18L * big))
                continue;             /* too close for long double to say: skip */
            cases++;
            if (width < 1e-14L * big)
                tight++;
            if (!((ms >> b) & 1))
                culled++;
            meet++;
        }
    }
    printf("box test: %ld boxes the exact ray meets (%ld within 1e-14 of missing), %ld "
           "culled, %ld SIMD/scalar differences\n", cases, tight, culled, differ);
    assert_true(meet > 100000);
    assert_true(tight > 1000);
    assert_int_equal(culled, 0);
    assert_int_equal(differ, 0);
}

/* ---- images ------------------------------------------------------------------------ */

static lc_image *render(lc_scene *s, int threads)
{
    lc_render_options o = lc_render_options_default();
    o.width = 64;
    o.height = 48;
    o.samples = 2;
    o.threads = threads;
    lc_error err;
    lc_image *img = lc_scene_render(s, &o, NULL, &err);
    if (!img)
        fail_msg("render: %s", err.msg);
    return img;
}

static int same_image(const lc_image *a, const lc_image *b)
{
    for (int y = 0; y < lc_image_height(a); y++)
        for (int x = 0; x < lc_image_width(a); x++) {
            lc_color p = lc_image_get(a, x, y), q = lc_image_get(b, x, y);
            if (memcmp(&p, &q, sizeof p))
                return 0;
        }
    return 1;
}

/* The same bits with the SIMD box test and without, on 1, 2 and 3 threads:
** a mirror and glossy scene, so secondary rays of every kind are traced. */
static void images_do_not_depend_on_simd_or_threads(void **state)
{
    (void)state;
    lc_scene *s = mixed_scene();
    lc_error err;
    lc_camera cam = lc_camera_default();
    cam.from = (lc_vec3){3, 6, -22};
    cam.at = (lc_vec3){0, 0, 0};
    assert_int_equal(lc_scene_set_camera(s, &cam, &err), LC_OK);
    lc_material mirror = lc_material_default();
    mirror.kr = 0.6;
    mirror.kd = 0.4;
    lc_material gloss = mirror;
    gloss.glossiness = 10;
    gloss.cone_samples = 4;
    int mm = lc_scene_add_material(s, &mirror, &err), mg = lc_scene_add_material(s, &gloss, &err);
    lc_shape big = {.kind = LC_SPHERE, .p = {-3, 2, -4}, .radius = 2.5};
    assert_true(lc_scene_add_shape(s, &big, mm, &err) >= 0);
    lc_shape pane = {.kind = LC_QUAD, .p = {1, -2, -6}, .u = {4, 0, 0}, .v = {0, 4, 1}};
    assert_true(lc_scene_add_shape(s, &pane, mg, &err) >= 0);
    lc_point_light l = lc_point_light_default();
    l.position = (lc_vec3){4, 14, -10};
    l.intensity = 300;
    assert_int_equal(lc_scene_add_light(s, &l, &err) >= 0, 1);
    int was = bvh_simd_set(BVH_SIMD_AVX512);
    lc_image *ref = render(s, 1);
    int differ = 0;
    for (int simd = 0; simd < BVH_SIMD_LEVELS; simd++)
        for (int threads = 1; threads <= 3; threads++) {
            bvh_simd_set(simd);
            lc_image *img = render(s, threads);
            differ += !same_image(ref, img);
            lc_image_free(img);
        }
    bvh_simd_set(was);
    printf("images: %d of %d differ (no SIMD, AVX, AVX-512; 1 to 3 threads)\n", differ,
           3 * BVH_SIMD_LEVELS);
    assert_int_equal(differ, 0);
    lc_image_free(ref);
    lc_scene_free(s);
}

/* ---- the four-lane triangle test -------------------------------------------------- */

/* Lanes of triangle4_avx against triangle_t, bit for bit: random faces
** about the ray, fans of faces around a corner or an edge the ray passes
** exactly through (edge functions rounding to 0: the extended-precision
** path), corners on the ray's origin, faces far from the origin and tiny
** ones, edge-on and degenerate faces, and tmax cutting through hits. */
static void triangle4_lanes_are_triangle_t(void **state)
{
    (void)state;
    int was = bvh_simd_set(BVH_SIMD_AVX);
    int have = bvh_simd >= BVH_SIMD_AVX;
    bvh_simd_set(was);
    if (!have)
        skip();
    long hits = 0, zeros = 0, cases = 0;
    for (int c = 0; c < 200000; c++) {
        double scale = pow(10, range(-6, 6)), shift = rnd() < 0.3 ? pow(10, range(0, 8)) : 0;
        lc_vec3 o = v3_add(rvec(-1, 1), v3(shift, -shift, shift));
        ray r = {o, random_dir()};
        triangle_shear sh;
        triangle_shear_init(r.d, &sh);
        lc_vec3 aim = v3_madd(o, r.d, scale * range(0.1, 10));   /* a point on the ray */
        double corners[4][3][3];
        triangle4_faces f;
        int n = 1 + (int)(rnd() * 4);
        int kind = c % 5;
        for (int l = 0; l < n; l++)
            for (int i = 0; i < 3; i++) {
                lc_vec3 p = v3_add(aim, v3_mul(rvec(-1, 1), scale));
                if (kind == 1 && i == 0)
                    p = aim;                               /* a corner on the ray */
                if (kind == 2 && i < 2)                    /* an edge across it */
                    p = v3_add(aim, v3_mul(r.d, (i ? 1 : -1) * scale));
                if (kind == 3 && i == 0 && l == 0)
                    p = o;                                 /* a corner on the origin */
                if (kind == 4 && i == 2)
                    p = v3_add(v3(corners[l][0][0], corners[l][0][1], corners[l][0][2]),
                               v3_mul(v3_sub(v3(corners[l][1][0], corners[l][1][1],
                                                corners[l][1][2]),
                                             v3(corners[l][0][0], corners[l][0][1],
                                                corners[l][0][2])), range(-1, 2)));
                corners[l][i][0] = p.x;
                corners[l][i][1] = p.y;
                corners[l][i][2] = p.z;
                f.v[l][i] = corners[l][i];
            }
        double tmax = rnd() < 0.3 ? scale * range(0, 10) : HUGE_VAL;
        double t4[4], b4[4][3], t1, b1[3];
        triangle4_avx(&f, n, &r, &sh, tmax, t4, b4);
        for (int l = 0; l < n; l++) {
            t1 = triangle_t(f.v[l][0], f.v[l][1], f.v[l][2], &r, &sh, 0, tmax, b1);
            cases++;
            if (memcmp(&t1, &t4[l], sizeof t1) != 0)
                fail_msg("case %d lane %d: triangle_t %a, lane %a", c, l, t1, t4[l]);
            if (t1 > 0) {
                hits++;
                assert_memory_equal(b1, b4[l], sizeof b1);
            } else
                zeros++;
        }
    }
    print_message("%ld lanes, %ld hits, %ld misses, all equal\n", cases, hits, zeros);
    assert_true(hits > 50000 && zeros > 50000);

    /* An edge whose function rounds to exactly 0 in double but is -2^-60 in
    ** extended precision (a miss: the other two are positive), then one
    ** where it is +2^-60 (a hit), in every lane. */
    ray r = {v3(0, 0, -5), v3(0, 0, 1)};
    triangle_shear sh;
    triangle_shear_init(r.d, &sh);
    double a[3] = {1, -1, 0};
    double b[2][3] = {{1 + 0x1p-30, 1 + 0x1p-29, 0}, {1 + 0x1p-29, 1 + 0x1p-30, 0}};
    double c[2][3] = {{-1, -(1 + 0x1p-30), 0}, {-(1 + 0x1p-30), -1, 0}};
    for (int meet = 0; meet < 2; meet++) {
        triangle4_faces f;
        for (int l = 0; l < 4; l++) {
            f.v[l][0] = a;
            f.v[l][1] = b[meet];
            f.v[l][2] = c[meet];
        }
        double t4[4], b4[4][3], b1[3];
        double t1 = triangle_t(f.v[0][0], f.v[0][1], f.v[0][2], &r, &sh, 0, HUGE_VAL, b1);
        assert_true(meet ? t1 == 5 : t1 == 0);
        triangle4_avx(&f, 4, &r, &sh, HUGE_VAL, t4, b4);
        for (int l = 0; l < 4; l++)
            assert_memory_equal(&t1, &t4[l], sizeof t1);
    }
}

/* ---- packets: neighbouring rays of an array walked together ------------------------- */

/* Everything a caller reads of a hit, to the bit (the weights only on a
** face: on other shapes they are scratch no one reads). */
static int same_vec(lc_vec3 a, lc_vec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

static int same_full_hit(int fa, const hit *a, int fb, const hit *b)
{
    if (fa != fb)
        return 0;
    if (!fa)
        return 1;
    return a->t == b->t && a->shape == b->shape && a->instance == b->instance &&
           a->material == b->material && same_vec(a->p, b->p) && same_vec(a->n, b->n) &&
           same_vec(a->ns, b->ns) &&
           (PRIM_KIND(a->shape) != PRIM_TRIANGLE ||
            (a->bary[0] == b->bary[0] && a->bary[1] == b->bary[1] && a->bary[2] == b->bary[2]));
}

/* Whether the rays can walk as one packet (bvh_packet.h's conditions). */
static int walks_together(const ray *r, int n)
{
    bvh_ray q[BVH_PACKET];
    bvh_packet p;
    for (int i = 0; i < n; i++)
        bvh_ray_init(&q[i], r[i].o, r[i].d);
    int ok = n >= 2 && bvh_packet_start(&p, &q[0]);
    for (int i = 1; i < n; i++)
        ok &= bvh_packet_add(&p, &q[i]);
    return ok;
}

/* Packets of 2 to 8 rays from one origin (random, or an adversarial ray's:
** on node boundaries, inside boxes, along axes, grazing spheres and
** faces, at mesh vertices), their directions spread from none (the same
** ray eight times) to wide, each with its own tmax: intersect_closest_n
** and intersect_occluded_n give each ray, under each box test, what
** intersect_closest and intersect_occluded give it alone, to the bit. */
static void packets_match_single_rays(void **state)
{
    (void)state;
    lc_scene *s = mixed_scene();
    enum { PACKETS = 24000 };
    static const double spread[] = {0, 1e-12, 1e-6, 1e-3, 3e-2, 0.3};
    static const int levels[] = {BVH_SIMD_AVX512, BVH_SIMD_AVX, BVH_SIMD_OFF};
    long rays = 0, together = 0, hits = 0, blocked = 0, mismatches = 0;
    int was = bvh_simd_set(BVH_SIMD_AVX512);
    for (int i = 0; i < PACKETS; i++) {
        ray base = i % 2 ? adversarial(s, i / 2) : (ray){rvec(-15, 15), random_dir()};
        int n = i % 4 ? BVH_PACKET : 2 + (int)(rnd() * (BVH_PACKET - 1));
        double sp = spread[(i / 2) % 6];
        ray r[BVH_PACKET];
        double tmax[BVH_PACKET];
        for (int j = 0; j < n; j++) {
            lc_vec3 d = v3_add(base.d, v3_mul(rvec(-1, 1), sp));
            r[j] = (ray){base.o, v3_len(d) > 0 ? v3_norm(d) : base.d};
            tmax[j] = rnd() < 0.7 ? HUGE_VAL : range(0.5, 30);
        }
        rays += n;
        together += walks_together(r, n) ? n : 0;
        hit single[BVH_PACKET];
        int fs[BVH_PACKET], os[BVH_PACKET];
        bvh_simd_set(BVH_SIMD_AVX512);
        for (int j = 0; j < n; j++) {
            memset(&single[j], 0, sizeof single[j]);
            fs[j] = intersect_closest(s, &r[j], tmax[j], &single[j], NULL);
            os[j] = intersect_occluded(s, &r[j], tmax[j], NULL);
            hits += fs[j];
            blocked += os[j];
        }
        for (size_t l = 0; l < sizeof levels / sizeof *levels; l++) {
            bvh_simd_set(levels[l]);
            hit h[BVH_PACKET];
            int f[BVH_PACKET], o[BVH_PACKET];
            memset(h, 0, sizeof h);
            intersect_closest_n(s, r, tmax, n, h, f);
            intersect_occluded_n(s, r, tmax, n, o);
            for (int j = 0; j < n; j++)
                if (!same_full_hit(fs[j], &single[j], f[j], &h[j]) || os[j] != o[j]) {
                    mismatches++;
                    if (getenv("DEBUG_WIDE"))
                        printf("packet %d ray %d level %d: alone %d t=%.17g id=%x, packet %d "
                               "t=%.17g id=%x; occluded %d/%d; p %d n %d ns %d m %d/%d b %g/%g\n", i, j, levels[l], fs[j],
                               single[j].t, single[j].shape, f[j], h[j].t, h[j].shape, os[j],
                               o[j], same_vec(single[j].p, h[j].p), same_vec(single[j].n, h[j].n), same_vec(single[j].ns, h[j].ns), single[j].material, h[j].material, single[j].bary[0], h[j].bary[0]);
                }
        }
    }
    bvh_simd_set(was);
    printf("packets: %ld rays, %ld in packets that walk together, %ld hits, %ld blocked, "
           "%ld mismatches\n", rays, together, hits, blocked, mismatches);
    assert_int_equal(mismatches, 0);
    assert_true(together > rays / 2);
    assert_true(hits > rays / 4 && blocked > rays / 4);
    lc_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(box_test_is_conservative),
        cmocka_unit_test(triangle4_lanes_are_triangle_t),
        cmocka_unit_test(wide_bvh_matches_the_scan),
        cmocka_unit_test(lone_leaf_matches_the_scan),
        cmocka_unit_test(packets_match_single_rays),
        cmocka_unit_test(images_do_not_depend_on_simd_or_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
