/* compile.c: the geometry a render and the caller's rays need: the BVH over
** every bounded primitive (moved meshes as one primitive each) and the
** triangle list. The effects a frame calls for are the plan's (plan.c). */
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "scene.h"
#include "base/interrupt.h"
#include "base/mem.h"
#include "base/pair.h"
#include "sky.h"
#include "compile.h"
#include "instance.h"
#include "csg.h"
#include "shapes/triangle.h"

void compile_free(compiled *c)
{
    sky_dist_free(&c->sky);
    mem_free(c->plan);
    mem_free(c->tris);
    mem_free(c->tleaf);
    bvh_free(&c->bvh);
    memset(c, 0, sizeof *c);
}

#define PARALLEL_FACES 200000   /* below this a thread costs more than it saves */

/* The flat meshes' faces [begin, end) of all of them, in order: those not
** degenerate are listed from tris[begin] on; n says how many. */
typedef struct {
    const lc_scene *s;
    tri_ref *tris;
    size_t   begin, end, n, degenerate;
} list_job;

static void *list_faces(void *arg)
{
    list_job *j = arg;
    size_t at = 0;                         /* faces of the meshes before mesh i */
    for (size_t i = 0; i < j->s->nmeshes && at < j->end; i++) {
        const lc_mesh *m = j->s->meshes[i].mesh;
        if (j->s->meshes[i].xf)
            continue;
        size_t f0 = j->begin > at ? j->begin - at : 0, f1 = j->end - at < m->nf ? j->end - at
                                                                              : m->nf;
        for (size_t f = f0; f < f1; f++) {
            const uint32_t *ix = m->f + 3 * f;
            if (triangle_degenerate(m->v + 3 * ix[0], m->v + 3 * ix[1], m->v + 3 * ix[2])) {
                j->degenerate++;
                continue;
            }
            j->tris[j->begin + j->n].mesh = (uint32_t)i;
            j->tris[j->begin + j->n++].face = (uint32_t)f;
        }
        at += m->nf;
    }
    return NULL;
}

/* Lists the non-degenerate triangles: a zero-area face can never be hit,
** and skipping it here keeps NaN normals out of the renderer. A large
** scene's faces are halved between two threads (the test was 47 ms of
** B3 4M on one), the second half's list moved down if the first skipped
** any. */
static lc_status list_triangles(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    size_t flat = 0;
    for (size_t i = 0; i < s->nmeshes; i++)
        if (!s->meshes[i].xf)
            flat += s->meshes[i].mesh->nf;
    size_t total = instance_faces(s) + flat;   /* those listed once, after the flat ones */
    if (total > PRIM_MAX)
        return error_fail(err, LC_EARG, NULL, "too many triangles: %zu (at most %zu)", total,
                       PRIM_MAX);
    c->tris = mem_alloc((total + 1) * sizeof *c->tris);
    if (!c->tris)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory listing %zu triangles", total);
    size_t half = flat >= PARALLEL_FACES ? flat / 2 : flat;
    list_job jobs[2] = {{s, c->tris, 0, half, 0, 0}, {s, c->tris, half, flat, 0, 0}};
    pair_run(list_faces, &jobs[0], &jobs[1], half < flat);
    if (jobs[0].n < half)
        memmove(c->tris + jobs[0].n, c->tris + half, jobs[1].n * sizeof *c->tris);
    c->ntris = jobs[0].n + jobs[1].n;
    c->degenerate += jobs[0].degenerate + jobs[1].degenerate;
    c->nflat = c->ntris;
    return instance_compile(s, seen, err);
}

/* Bounds of the bounded shapes (kind by kind) then of the flat triangles:
** items [begin, end) of that order, on a thread of their own for half of
** a large scene. 4M faces took a quarter of a second on one core, writing
** 112 MB of items the kernel had just mapped; 1M spheres 70 ms. */
typedef struct {
    const lc_scene *s;
    bvh_item *items;
    size_t    begin, end;
    sig_atomic_t seen;
    int       cancelled;
} bound_job;

static int bound_cancelled(bound_job *j, size_t g)
{
    if ((g & 0xffff) == 0xffff && interrupt_count() != j->seen)
        j->cancelled = 1;
    return j->cancelled;
}

static void *bound_items(void *arg)
{
    bound_job *j = arg;
    const lc_scene *s = j->s;
    size_t at = 0;                           /* items before kind k's */
    for (int k = 0; k < LC_SHAPE_KINDS; k++) {
        const shape_list *l = &s->shapes[k];
        if (!shape_bounded((lc_shape_kind)k))
            continue;
        for (size_t g = j->begin > at ? j->begin : at; g < j->end && g < at + l->n; g++) {
            if (bound_cancelled(j, g))
                return NULL;
            bvh_item *it = &j->items[g];
            it->id = PRIM_ID(shape_prim_kind((lc_shape_kind)k), g - at);
            shape_bounds((lc_shape_kind)k, shape_at(l, g - at), it->lo, it->hi);
        }
        at += l->n;
    }
    const compiled *c = &s->c;
    for (size_t g = j->begin > at ? j->begin : at; g < j->end; g++) {
        if (bound_cancelled(j, g))
            return NULL;
        size_t i = g - at;
        const lc_mesh *m = s->meshes[c->tris[i].mesh].mesh;
        const uint32_t *ix = m->f + 3 * c->tris[i].face;
        bvh_item *it = &j->items[g];
        it->id = PRIM_ID(PRIM_TRIANGLE, i);
        triangle_bounds(m->v + 3 * ix[0], m->v + 3 * ix[1], m->v + 3 * ix[2], it->lo, it->hi);
    }
    return NULL;
}

static lc_status build_bvh(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    size_t shapes = 0;
    for (int k = 0; k < LC_SHAPE_KINDS; k++)
        if (shape_bounded((lc_shape_kind)k))
            shapes += s->shapes[k].n;
    size_t n = shapes + c->nflat + c->ninstances + s->ncsgs;
    bvh_item *items = mem_alloc((n + 1) * sizeof *items);
    if (!items)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory bounding %zu primitives", n);
    size_t both = shapes + c->nflat, half = both >= PARALLEL_FACES ? both / 2 : both;
    bound_job jobs[2] = {{s, items, 0, half, seen, 0}, {s, items, half, both, seen, 0}};
    pair_run(bound_items, &jobs[0], &jobs[1], half < both);
    if (jobs[0].cancelled || jobs[1].cancelled) {
        mem_free(items);
        return error_fail(err, LC_ECANCEL, NULL, "render cancelled");
    }
    bvh_item *it = items + both;
    for (size_t i = 0; i < s->nmeshes; i++)
        if (s->meshes[i].xf) {
            it->id = PRIM_ID(PRIM_INSTANCE, i);
            instance_bounds(s, i, it->lo, it->hi);
            it++;
        }
    for (size_t i = 0; i < s->ncsgs; i++, it++) {  /* each CSG object one primitive */
        it->id = PRIM_ID(PRIM_CSG, i);
        csg_bounds(s->csgs[i], it->lo, it->hi);
    }
    lc_status st = bvh_build_costed(&c->bvh, items, n, shape_prim_cost, seen, err);
    if (st != LC_OK || c->nflat == 0)
        return st;
    c->tleaf = compile_tri_leaves(s, &c->bvh);
    if (!c->tleaf)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory listing %zu triangles", c->nflat);
    return LC_OK;
}

/* Refs [begin, end) of a BVH: their faces' corners beside them. */
typedef struct {
    const lc_scene *s;
    const bvh *b;
    tri_leaf *tl;
    size_t    begin, end;
} leaves_job;

static void *list_leaves(void *arg)
{
    const leaves_job *j = arg;
    for (size_t r = j->begin; r < j->end; r++) {
        uint32_t id = j->b->refs[r];
        if (PRIM_KIND(id) != PRIM_TRIANGLE)
            continue;
        const tri_ref *tr = &j->s->c.tris[PRIM_INDEX(id)];
        const uint32_t *ix = j->s->meshes[tr->mesh].mesh->f + 3 * (size_t)tr->face;
        j->tl[r] = (tri_leaf){tr->mesh, {ix[0], ix[1], ix[2]}};
    }
    return NULL;
}

/* Halved between two threads for a large scene: 40 ms of B3 4M on one. */
tri_leaf *compile_tri_leaves(const lc_scene *s, const bvh *b)
{
    tri_leaf *tl = mem_alloc((b->nrefs + 1) * sizeof *tl);
    if (!tl)
        return NULL;
    size_t half = b->nrefs >= PARALLEL_FACES ? b->nrefs / 2 : b->nrefs;
    leaves_job jobs[2] = {{s, b, tl, 0, half}, {s, b, tl, half, b->nrefs}};
    pair_run(list_leaves, &jobs[0], &jobs[1], half < b->nrefs);
    return tl;
}

lc_status compile_geometry(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    size_t faces = 0;
    for (size_t i = 0; i < s->nmeshes; i++)
        faces += s->meshes[i].mesh->nf;
    if (!c->valid || c->faces_seen != faces) {     /* geometry changed since */
        compile_free(c);
        lc_status st = list_triangles(s, seen, err);
        if (st == LC_OK)
            st = build_bvh(s, seen, err);
        if (st != LC_OK) {
            compile_free(c);
            return st;
        }
        c->valid = 1;
        c->faces_seen = faces;
    }
    error_ok(err);
    return LC_OK;
}
