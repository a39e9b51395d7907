/* test_bvh.c: the BVH finds exactly what a brute-force scan finds, and meshes are watertight. */
#include <float.h>
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
#include "helpers.h"
#include "scene/compile.h"
#include "render/plan.h"
#include "scene/intersect.h"
#include "shapes/triangle.h"

#define M_PI 3.14159265358979323846

static uint64_t rng_state = 12345;

static double rnd(void)          /* deterministic, [0, 1) */
{
    return lcg(&rng_state);
}

/* Nearest hit by testing every primitive: what the BVH must reproduce. */
static int brute_closest(const lc_scene *s, const ray *r, hit *best)
{
    int found = 0;
    hit h;
    triangle_shear sh;
    triangle_shear_init(r->d, &sh);
    const shape_list *sp = &s->shapes[LC_SPHERE], *bx = &s->shapes[LC_BOX];
    for (size_t i = 0; i < sp->n; i++)
        if (sphere_hit(shape_at(sp, i), r, 0, HUGE_VAL, &h) && (!found || h.t < best->t)) {
            *best = h;
            best->shape = PRIM_ID(PRIM_SPHERE, i);
            found = 1;
        }
    for (size_t i = 0; i < bx->n; i++)
        if (box_hit(shape_at(bx, i), r, 0, HUGE_VAL, &h) && (!found || h.t < best->t)) {
            *best = h;
            best->shape = PRIM_ID(PRIM_BOX, i);
            found = 1;
        }
    for (size_t i = 0; i < s->c.ntris; i++) {
        const lc_mesh *m = s->meshes[s->c.tris[i].mesh].mesh;
        const uint32_t *f = m->f + 3 * (size_t)s->c.tris[i].face;
        if (triangle_hit(m->v + 3 * f[0], m->v + 3 * f[1], m->v + 3 * f[2], r, &sh, 0, HUGE_VAL,
                    &h, h.bary) && (!found || h.t < best->t)) {
            *best = h;
            best->shape = PRIM_ID(PRIM_TRIANGLE, i);
            found = 1;
        }
    }
    return found;
}

static lc_vec3 random_dir(void) { return rand_sphere_dir(&rng_state); }

static void bvh_matches_brute_force(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    for (int i = 0; i < 3000; i++) {
        lc_shape sp = {.kind = LC_SPHERE, .p = {20 * rnd() - 10, 20 * rnd() - 10, 20 * rnd() - 10}, .radius = 0.05 + 0.4 * rnd()};
        assert_true(lc_scene_add_shape(s, &sp, mi, &err) >= 0);
    }
    for (int i = 0; i < 300; i++) {
        lc_vec3 c = v3(20 * rnd() - 10, 20 * rnd() - 10, 20 * rnd() - 10);
        lc_shape b = {.kind = LC_BOX, .p = c, .u = {rnd() + 0.1, 0, 0}, .v = {0, rnd() + 0.1, 0}, .w = {0, 0, rnd() + 0.1}};
        assert_true(lc_scene_add_shape(s, &b, mi, &err) >= 0);
    }
    lc_mesh *mesh = lc_mesh_new(&err);
    for (int i = 0; i < 2000; i++) {
        lc_vec3 c = v3(20 * rnd() - 10, 20 * rnd() - 10, 20 * rnd() - 10);
        double v[9];
        for (int k = 0; k < 3; k++) {
            v[3 * k] = c.x + rnd() - 0.5;
            v[3 * k + 1] = c.y + rnd() - 0.5;
            v[3 * k + 2] = c.z + rnd() - 0.5;
        }
        uint32_t f[3] = {(uint32_t)(3 * i), (uint32_t)(3 * i + 1), (uint32_t)(3 * i + 2)};
        assert_int_equal(lc_mesh_add_vertices(mesh, v, 3, &err), LC_OK);
        assert_int_equal(lc_mesh_add_faces(mesh, f, 1, &err), LC_OK);
    }
    assert_true(lc_scene_add_mesh(s, mesh, mi, &err) >= 0);
    lc_mesh_free(mesh);                      /* the scene keeps its own hold */
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    assert_true(s->c.bvh.nnodes > 1);

    int hits = 0, mismatches = 0;
    for (int i = 0; i < 20000; i++) {
        ray r = {v3(30 * rnd() - 15, 30 * rnd() - 15, 30 * rnd() - 15), random_dir()};
        hit a, b;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        int fa = intersect_closest(s, &r, HUGE_VAL, &a, NULL), fb = brute_closest(s, &r, &b);
        /* the same primitive; t to a few ulps (the BVH path makes its
        ** reciprocals with one division, the brute force with three) */
        if (fa != fb || (fa && (fabs(a.t - b.t) > 1e-14 * b.t || a.shape != b.shape)))
            mismatches++;
        hits += fa;
        /* any-hit agrees with nearest-hit */
        if (intersect_occluded(s, &r, HUGE_VAL, NULL) != fa)
            mismatches++;
    }
    printf("bvh: %d of 20000 rays hit, %d mismatches with brute force\n", hits, mismatches);
    assert_true(hits > 2000);
    assert_int_equal(mismatches, 0);
    lc_scene_free(s);
}

/* Items the builder owns (it frees them with mem_free): n copies of src. */
static bvh_item *owned_items(const bvh_item *src, size_t n)
{
    bvh_item *it = mem_alloc(n * sizeof *it);
    assert_non_null(it);
    memcpy(it, src, n * sizeof *it);
    return it;
}

/* The costed build: four unit boxes in a row are one leaf, as MIN_LEAF
** says; the same four weighed 8 each (instances) are four leaves, one
** item each. All costs 1 give bvh_build's tree, node for node. */
static void costed_build_parts_costly_leaves(void **state)
{
    (void)state;
    lc_error err;
    bvh_item row[4];
    for (uint32_t i = 0; i < 4; i++) {
        float x = 3.0f * (float)i;
        row[i] = (bvh_item){{x, 0, 0}, {x + 1, 1, 1}, PRIM_ID(PRIM_INSTANCE, i)};
    }
    float unit[BVH_KINDS], costly[BVH_KINDS];
    for (unsigned k = 0; k < BVH_KINDS; k++)
        unit[k] = costly[k] = 1;
    costly[PRIM_INSTANCE] = 8;
    bvh a, b;
    assert_int_equal(bvh_build_costed(&a, owned_items(row, 4), 4, unit, 0, &err), LC_OK);
    assert_int_equal(bvh_build_costed(&b, owned_items(row, 4), 4, costly, 0, &err), LC_OK);
    assert_int_equal(a.lone, 1);
    assert_int_equal(a.nodes[0].count[0], 4);
    assert_int_equal(b.lone, 0);
    assert_int_equal(b.nodes[0].n, 4);
    for (int c = 0; c < 4; c++)
        assert_int_equal(b.nodes[0].count[c], 1);
    bvh_free(&a);
    bvh_free(&b);

    size_t n = 20000;
    bvh_item *many = malloc(n * sizeof *many);
    assert_non_null(many);
    for (size_t i = 0; i < n; i++) {
        float c[3] = {(float)(100 * rnd()), (float)(100 * rnd()), (float)(100 * rnd())};
        float r = (float)(0.1 + rnd());
        many[i] = (bvh_item){{c[0] - r, c[1] - r, c[2] - r}, {c[0] + r, c[1] + r, c[2] + r},
                             PRIM_ID(i % 2 ? PRIM_SPHERE : PRIM_BOX, i)};
    }
    assert_int_equal(bvh_build(&a, owned_items(many, n), n, 0, &err), LC_OK);
    assert_int_equal(bvh_build_costed(&b, owned_items(many, n), n, unit, 0, &err), LC_OK);
    assert_int_equal(a.nnodes, b.nnodes);
    assert_true(a.nnodes > 1000);
    assert_memory_equal(a.nodes, b.nodes, a.nnodes * sizeof *a.nodes);
    assert_memory_equal(a.refs, b.refs, n * sizeof *a.refs);
    bvh_free(&a);
    bvh_free(&b);
    free(many);
}

/* Checks the subtree of wide node ni against the items (indexed by id):
** each node is reached once, each child box holds what lies below it, and
** each leaf's refs are marked in seen[]. Returns the nodes reached. */
static size_t check_wide(const bvh *b, uint32_t ni, const bvh_item *items, char *reached,
                         char *seen, const float lo[3], const float hi[3])
{
    assert_true(ni < b->nnodes);
    assert_int_equal(reached[ni], 0);
    reached[ni] = 1;
    const bvh_node *nd = &b->nodes[ni];
    assert_true(nd->n >= 1 && nd->n <= BVH_WIDTH);
    size_t count = 1;
    for (uint32_t c = 0; c < BVH_WIDTH; c++) {
        float clo[3], chi[3];
        for (int k = 0; k < 3; k++) {
            clo[k] = nd->lo[k][c];
            chi[k] = nd->hi[k][c];
            if (c >= nd->n) {                 /* empty slots: no box */
                assert_true(clo[k] > chi[k]);
                continue;
            }
            assert_true(clo[k] >= lo[k] && chi[k] <= hi[k]);   /* inside its parent's */
        }
        if (c >= nd->n)
            continue;
        if (nd->count[c] == 0) {
            count += check_wide(b, nd->child[c], items, reached, seen, clo, chi);
            continue;
        }
        for (uint32_t r = nd->child[c]; r < nd->child[c] + nd->count[c]; r++) {
            assert_true(r < b->nrefs);
            const bvh_item *it = &items[b->refs[r]];
            assert_int_equal(seen[b->refs[r]], 0);
            seen[b->refs[r]] = 1;
            for (int k = 0; k < 3; k++)
                assert_true(it->lo[k] >= clo[k] && it->hi[k] <= chi[k]);
        }
    }
    return count;
}

/* A build large enough for the paths that take two threads (the top split,
** the collapse of the top's children into wide nodes): every node
** reached once from the root, every item in exactly one leaf, every box
** holding what lies below it. */
static void large_build_is_whole(void **state)
{
    (void)state;
    size_t n = 300000;
    bvh_item *items = malloc(n * sizeof *items);
    assert_non_null(items);
    for (size_t i = 0; i < n; i++) {
        float c[3] = {(float)(1000 * rnd()), (float)(10 * rnd()), (float)(1000 * rnd())};
        float r = (float)(0.01 + 0.5 * rnd());
        items[i] = (bvh_item){{c[0] - r, c[1] - r, c[2] - r}, {c[0] + r, c[1] + r, c[2] + r},
                              (uint32_t)i};
    }
    lc_error err;
    bvh b;
    assert_int_equal(bvh_build(&b, owned_items(items, n), n, 0, &err), LC_OK);
    assert_int_equal(b.nrefs, n);
    assert_true(b.nnodes > 10000);
    char *reached = calloc(b.nnodes, 1), *seen = calloc(n, 1);
    assert_non_null(reached);
    assert_non_null(seen);
    const float all_lo[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX}, all_hi[3] = {FLT_MAX, FLT_MAX, FLT_MAX};
    assert_int_equal(check_wide(&b, 0, items, reached, seen, all_lo, all_hi), b.nnodes);
    for (size_t i = 0; i < n; i++)
        assert_int_equal(seen[i], 1);
    free(reached);
    free(seen);
    bvh_free(&b);
    free(items);
}

/* A closed UV sphere; rays aimed exactly at its vertices and at points of its
** edges from outside must all hit (Woop: shared edges are computed alike). */
static void mesh_is_watertight(void **state)
{
    (void)state;
    const int nu = 64, nv = 32;
    lc_error err;
    lc_mesh *mesh = lc_mesh_new(&err);
    double p[3];
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i < nu; i++) {
            double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
            p[0] = sin(th) * cos(ph);
            p[1] = cos(th);
            p[2] = sin(th) * sin(ph);
            lc_mesh_add_vertices(mesh, p, 1, &err);
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = j * nu + i, b = j * nu + (i + 1) % nu;
            uint32_t c = (j + 1) * nu + i, d = (j + 1) * nu + (i + 1) % nu;
            uint32_t f[6] = {a, c, d, a, d, b};
            lc_mesh_add_faces(mesh, f, 2, &err);
        }
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    assert_true(lc_scene_add_mesh(s, mesh, mi, &err) >= 0);
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    assert_true(s->c.degenerate > 0);        /* the poles' zero-area faces */

    int rays = 0, misses = 0;
    for (size_t f = 0; f < mesh->nf; f++) {
        const uint32_t *ix = mesh->f + 3 * f;
        for (int e = 0; e < 3; e++) {
            const double *a = mesh->v + 3 * ix[e], *b = mesh->v + 3 * ix[(e + 1) % 3];
            for (int k = 0; k <= 4; k++) {      /* the vertex (k = 0) and edge points */
                double w = k / 4.0;
                lc_vec3 target = v3(a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]),
                                    a[2] + w * (b[2] - a[2]));
                /* from a random outside point that sees the target face-on */
                lc_vec3 o = v3_madd(v3_mul(target, 3), random_dir(), 0.5);
                ray r = {o, v3_norm(v3_sub(target, o))};
                hit h;
                rays++;
                if (!intersect_closest(s, &r, HUGE_VAL, &h, NULL))
                    misses++;
            }
        }
    }
    printf("watertight: %d rays at vertices and edges, %d misses\n", rays, misses);
    assert_true(rays > 30000);
    assert_int_equal(misses, 0);
    lc_scene_free(s);
    lc_mesh_free(mesh);
}

/* A large scene's faces are listed on two threads, the halves split
** across two meshes: the list is the one-thread list (every face not
** degenerate, in mesh and face order) whichever half skips faces, and a
** ray finds each face. */
static void large_face_lists_keep_their_order(void **state)
{
    (void)state;
    lc_error err;
    /* Two meshes, 320 000 faces: the halves part inside the second. */
    const size_t nfs[2] = {150000, 170000};
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    lc_mesh *mesh[2];
    for (int k = 0; k < 2; k++) {
        size_t nf = nfs[k];
        /* Face f: a unit triangle in the plane z = f, or a sliver with
        ** three equal corners when f % 1000 == (k ? 999 : 7). */
        mesh[k] = lc_mesh_new(&err);
        double *v = malloc(9 * nf * sizeof *v);
        uint32_t *f = malloc(3 * nf * sizeof *f);
        assert_non_null(v);
        assert_non_null(f);
        for (size_t i = 0; i < nf; i++) {
            int flat = i % 1000 == (k ? 999u : 7u);
            double z = (double)i + (k ? 0.5 : 0), x = 3.0 * k;
            double c[9] = {x, 0, z, x + (flat ? 0 : 1), 0, z, x, flat ? 0 : 1, z};
            memcpy(v + 9 * i, c, sizeof c);
            for (int q = 0; q < 3; q++)
                f[3 * i + q] = (uint32_t)(3 * i + (size_t)q);
        }
        assert_int_equal(lc_mesh_add_vertices(mesh[k], v, 3 * nf, &err), LC_OK);
        assert_int_equal(lc_mesh_add_faces(mesh[k], f, nf, &err), LC_OK);
        assert_true(lc_scene_add_mesh(s, mesh[k], mi, &err) >= 0);
        free(v);
        free(f);
    }
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    size_t skipped = nfs[0] / 1000 + nfs[1] / 1000;
    assert_int_equal(s->c.degenerate, skipped);
    assert_int_equal(s->c.ntris, nfs[0] + nfs[1] - skipped);
    size_t at = 0;
    for (uint32_t k = 0; k < 2; k++)
        for (uint32_t i = 0; i < nfs[k]; i++) {
            if (i % 1000 == (k ? 999u : 7u))
                continue;
            assert_int_equal(s->c.tris[at].mesh, k);
            assert_int_equal(s->c.tris[at].face, i);
            at++;
        }
    for (uint32_t k = 0; k < 2; k++)
        for (uint32_t i = 1; i < nfs[k]; i += 9973) {    /* down onto face i of mesh k */
            ray r = {v3(3.0 * k + 0.25, 0.25, (double)i + (k ? 0.5 : 0) + 0.25),
                     v3(0, 0, -1)};
            hit h;
            assert_true(intersect_closest(s, &r, HUGE_VAL, &h, NULL));
            const tri_ref *tr = &s->c.tris[PRIM_INDEX(h.shape)];
            assert_int_equal(tr->mesh, k);
            assert_int_equal(tr->face, i);
        }
    lc_scene_free(s);
    lc_mesh_free(mesh[0]);
    lc_mesh_free(mesh[1]);
}

/* A large scene's shapes are bounded on two threads, the halves parting
** inside the second kind: a ray down onto any sphere or box finds it, by
** its own kind and index. */
static void large_shape_lists_are_bounded_whole(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    const size_t nsph = 100000, nbox = 150000;      /* 250 000: the halves meet in boxes */
    for (size_t i = 0; i < nsph; i++) {
        lc_shape sp = {.kind = LC_SPHERE, .p = {3.0 * (double)i, 0, 0}, .radius = 1};
        assert_true(lc_scene_add_shape(s, &sp, mi, &err) >= 0);
    }
    for (size_t i = 0; i < nbox; i++) {
        lc_shape b = {.kind = LC_BOX, .p = {3.0 * (double)i, 0, 10}, .u = {1, 0, 0},
                      .v = {0, 1, 0}, .w = {0, 0, 1}};
        assert_true(lc_scene_add_shape(s, &b, mi, &err) >= 0);
    }
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    for (size_t i = 0; i < nbox; i += 997) {
        for (int kind = 0; kind < 2; kind++) {
            if (kind == 0 && i >= nsph)
                continue;
            double x = 3.0 * (double)i + (kind ? 0.5 : 0), z = kind ? 10.5 : 0;
            ray r = {v3(x, 5, z), v3(0, -1, 0)};
            hit h;
            assert_true(intersect_closest(s, &r, HUGE_VAL, &h, NULL));
            assert_int_equal(PRIM_KIND(h.shape), kind ? PRIM_BOX : PRIM_SPHERE);
            assert_int_equal(PRIM_INDEX(h.shape), i);
        }
    }
    lc_scene_free(s);
}

/* A degenerate-only mesh compiles to nothing and never yields a hit. */
static void degenerate_triangles_are_skipped(void **state)
{
    (void)state;
    lc_error err;
    lc_mesh *mesh = lc_mesh_new(&err);
    double v[12] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 0, 0, 0};
    uint32_t f[9] = {0, 1, 2, 0, 0, 0, 0, 3, 1};   /* collinear, one point, duplicate */
    lc_mesh_add_vertices(mesh, v, 4, &err);
    lc_mesh_add_faces(mesh, f, 3, &err);
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    lc_scene_add_mesh(s, mesh, mi, &err);
    assert_int_equal(plan_scene(s, NULL, 0, &err), LC_OK);
    assert_int_equal(s->c.degenerate, 3);
    assert_int_equal(s->c.ntris, 0);
    ray r = {v3(1, 1, -5), v3(0, 0, 1)};
    hit h;
    assert_false(intersect_closest(s, &r, HUGE_VAL, &h, NULL));
    lc_scene_free(s);
    lc_mesh_free(mesh);
}

static void mesh_rejects_bad_input(void **state)
{
    (void)state;
    lc_error err;
    lc_mesh *mesh = lc_mesh_new(&err);
    double v[3] = {0, NAN, 0};
    assert_int_equal(lc_mesh_add_vertices(mesh, v, 1, &err), LC_EARG);
    assert_non_null(strstr(err.msg, "finite"));
    double ok[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    assert_int_equal(lc_mesh_add_vertices(mesh, ok, 3, &err), LC_OK);
    uint32_t f[3] = {0, 1, 3};
    assert_int_equal(lc_mesh_add_faces(mesh, f, 1, &err), LC_EARG);
    assert_string_equal(err.field, "faces");
    assert_int_equal(lc_mesh_face_count(mesh), 0);
    lc_mesh_free(mesh);
}

/* Float bounds are never subnormal (arithmetic on subnormals takes the
** processor's slow path: building B2's 1M spheres resting on y = 0 took
** 2.6 times as long), and they still bound their double: below
** 2^-125 in magnitude a bound moves outward, to 0 or to -+2^-125. */
static void bounds_are_never_subnormal(void **state)
{
    (void)state;
    const double xs[] = {0.0, -0.0, 4.9e-324, -4.9e-324, 1e-40, -1e-40, 0x1p-127, -0x1p-127,
                         0x1p-126, -0x1p-126, 0x1p-125, -0x1p-125, 1e-38, -1e-38, 1e-30,
                         -1e-30, 1.0, -1.0};
    for (size_t i = 0; i < sizeof xs / sizeof *xs; i++) {
        float lo = bvh_down(xs[i]), hi = bvh_up(xs[i]);
        assert_true((double)lo <= xs[i] && xs[i] <= (double)hi);
        assert_true(fpclassify(lo) != FP_SUBNORMAL && fpclassify(hi) != FP_SUBNORMAL);
    }
    assert_true(bvh_down(-4.9e-324) == -0x1p-125f);
    assert_true(bvh_up(1e-40) == 0x1p-125f);
    assert_true(bvh_down(1e-40) == 0.0f && bvh_up(-1e-40) == 0.0f);
    /* A sphere resting on the ground: its lower bound is one step below 0. */
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    lc_shape sp = {.kind = LC_SPHERE, .p = {0, 0.25, 0}, .radius = 0.25};
    assert_true(lc_scene_add_shape(s, &sp, mi, &err) >= 0);
    float lo[3], hi[3];
    shape_bounds(LC_SPHERE, shape_at(&s->shapes[LC_SPHERE], 0), lo, hi);
    assert_true(lo[1] == -0x1p-125f && hi[1] >= 0.5f);
    lc_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bvh_matches_brute_force),
        cmocka_unit_test(bounds_are_never_subnormal),
        cmocka_unit_test(costed_build_parts_costly_leaves),
        cmocka_unit_test(large_build_is_whole),
        cmocka_unit_test(mesh_is_watertight),
        cmocka_unit_test(degenerate_triangles_are_skipped),
        cmocka_unit_test(large_face_lists_keep_their_order),
        cmocka_unit_test(large_shape_lists_are_bounded_whole),
        cmocka_unit_test(mesh_rejects_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
