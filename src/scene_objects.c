/* scene_objects.c: listing a scene's objects in the order added, and removing them. */
#include <stdlib.h>
#include <string.h>
#include "error.h"
#include "scene.h"

/* Ids grow with each add, and removal keeps the order, so each kind's array
** is sorted by id: a binary search finds an object. */
#define FIND(arr, n, id_, out)                                         \
    do {                                                               \
        size_t lo_ = 0, hi_ = (n);                                     \
        while (lo_ < hi_) {                                            \
            size_t mid_ = lo_ + (hi_ - lo_) / 2;                       \
            if ((arr)[mid_].id < (id_)) lo_ = mid_ + 1; else hi_ = mid_; \
        }                                                              \
        (out) = lo_ < (n) && (arr)[lo_].id == (id_) ? (long)lo_ : -1;  \
    } while (0)

static long find_light(const lc_scene *s, int id)
{
    size_t lo = 0, hi = s->nlights;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->light_ids[mid] < id) lo = mid + 1; else hi = mid;
    }
    return lo < s->nlights && s->light_ids[lo] == id ? (long)lo : -1;
}

size_t lc_scene_object_count(const lc_scene *s) { return s->nshapes + s->nlights; }

static void shape_object(lc_object *o, int kind, const void *prim)
{
    memset(&o->shape, 0, sizeof o->shape);
    o->kind = LC_OBJECT_SHAPE;
    o->shape.kind = (lc_shape_kind)kind;
    switch (kind) {
    case LC_SPHERE: {
        const sphere_prim *p = prim;
        o->shape.p = p->g.c;
        o->shape.radius = p->g.r;
        o->id = p->id;
        o->material = p->material;
        break;
    }
    case LC_QUAD: {
        const quad_prim *p = prim;
        o->shape.p = p->g.q;
        o->shape.u = p->g.u;
        o->shape.v = p->g.v;
        o->id = p->id;
        o->material = p->material;
        break;
    }
    case LC_BOX: {
        const box_prim *p = prim;
        o->shape.p = p->g.q;
        o->shape.u = p->g.e[0];
        o->shape.v = p->g.e[1];
        o->shape.w = p->g.e[2];
        o->id = p->id;
        o->material = p->material;
        break;
    }
    default: {
        const plane_prim *p = prim;
        o->shape.p = p->g.p;
        o->shape.u = p->g.n;
        o->id = p->id;
        o->material = p->material;
        break;
    }
    }
}

static void mesh_object(lc_object *o, const mesh_prim *p)
{
    o->kind = LC_OBJECT_MESH;
    o->id = p->id;
    o->material = p->material;
    o->mesh = p->mesh;
    o->moved = p->xf != NULL;
    o->transform = p->xf ? p->xf->xf : lc_transform_identity();
}

static void light_object(lc_object *o, const lc_scene *s, size_t i)
{
    o->kind = LC_OBJECT_LIGHT;
    o->id = s->light_ids[i];
    o->material = -1;
    o->light = s->lights[i];
}

/* The six sorted lists merged by id. */
size_t lc_scene_objects(const lc_scene *s, lc_object *out, size_t n)
{
    size_t at[6] = {0, 0, 0, 0, 0, 0};
    size_t len[6] = {s->nspheres, s->nquads, s->nboxes, s->nplanes, s->nmeshes, s->nlights};
    size_t total = lc_scene_object_count(s);
    for (size_t k = 0; k < n && k < total; k++) {
        int best = -1, best_id = 0;
        for (int j = 0; j < 6; j++) {
            if (at[j] == len[j])
                continue;
            size_t i = at[j];
            int id = j == 0 ? s->spheres[i].id : j == 1 ? s->quads[i].id :
                     j == 2 ? s->boxes[i].id : j == 3 ? s->planes[i].id :
                     j == 4 ? s->meshes[i].id : s->light_ids[i];
            if (best < 0 || id < best_id) {
                best = j;
                best_id = id;
            }
        }
        lc_object *o = &out[k];
        memset(o, 0, sizeof *o);
        size_t i = at[best]++;
        switch (best) {
        case 0: shape_object(o, LC_SPHERE, &s->spheres[i]); break;
        case 1: shape_object(o, LC_QUAD, &s->quads[i]); break;
        case 2: shape_object(o, LC_BOX, &s->boxes[i]); break;
        case 3: shape_object(o, LC_PLANE, &s->planes[i]); break;
        case 4: mesh_object(o, &s->meshes[i]); break;
        default: light_object(o, s, i); break;
        }
    }
    return total;
}

lc_status lc_scene_object(const lc_scene *s, int id, lc_object *out, lc_error *err)
{
    long i;
    memset(out, 0, sizeof *out);
    FIND(s->spheres, s->nspheres, id, i);
    if (i >= 0) return shape_object(out, LC_SPHERE, &s->spheres[i]), lc_ok(err), LC_OK;
    FIND(s->quads, s->nquads, id, i);
    if (i >= 0) return shape_object(out, LC_QUAD, &s->quads[i]), lc_ok(err), LC_OK;
    FIND(s->boxes, s->nboxes, id, i);
    if (i >= 0) return shape_object(out, LC_BOX, &s->boxes[i]), lc_ok(err), LC_OK;
    FIND(s->planes, s->nplanes, id, i);
    if (i >= 0) return shape_object(out, LC_PLANE, &s->planes[i]), lc_ok(err), LC_OK;
    FIND(s->meshes, s->nmeshes, id, i);
    if (i >= 0) return mesh_object(out, &s->meshes[i]), lc_ok(err), LC_OK;
    i = find_light(s, id);
    if (i >= 0) return light_object(out, s, (size_t)i), lc_ok(err), LC_OK;
    return lc_fail(err, LC_EARG, "id", "no object %d in this scene (%s)", id,
                   id >= 0 && id < s->next_id ? "it was removed" : "never added");
}

/* Removes element i of an array of n elements of `size` bytes, keeping order. */
static void cut(void *arr, size_t *n, size_t i, size_t size)
{
    char *a = arr;
    memmove(a + i * size, a + (i + 1) * size, (*n - i - 1) * size);
    --*n;
}

/* The emitter of shape PRIM_ID(kind, i) goes; later ones of that kind move down. */
static void drop_emitter(lc_scene *s, unsigned kind, size_t i)
{
    uint32_t id = PRIM_ID(kind, i);
    for (size_t e = 0; e < s->nemitters; e++) {
        if (s->emitters[e].shape == id) {
            cut(s->emitters, &s->nemitters, e, sizeof *s->emitters);
            e--;
        } else if (PRIM_KIND(s->emitters[e].shape) == kind &&
                   PRIM_INDEX(s->emitters[e].shape) > i) {
            s->emitters[e].shape--;
        }
    }
}

lc_status lc_scene_remove(lc_scene *s, int id, lc_error *err)
{
    lc_object o;
    if (lc_scene_object(s, id, &o, err))
        return LC_EARG;
    long i;
    switch (o.kind) {
    case LC_OBJECT_LIGHT:
        i = find_light(s, id);
        memmove(s->light_ids + i, s->light_ids + i + 1,
                (s->nlights - (size_t)i - 1) * sizeof *s->light_ids);
        cut(s->lights, &s->nlights, (size_t)i, sizeof *s->lights);
        break;
    case LC_OBJECT_MESH:
        FIND(s->meshes, s->nmeshes, id, i);
        lc_mesh_free(s->meshes[i].mesh);       /* the scene's hold; the cache has its own */
        free(s->meshes[i].xf);
        cut(s->meshes, &s->nmeshes, (size_t)i, sizeof *s->meshes);
        s->nshapes--;
        break;
    default:
        switch (o.shape.kind) {
        case LC_SPHERE:
            FIND(s->spheres, s->nspheres, id, i);
            cut(s->spheres, &s->nspheres, (size_t)i, sizeof *s->spheres);
            drop_emitter(s, PRIM_SPHERE, (size_t)i);
            break;
        case LC_QUAD:
            FIND(s->quads, s->nquads, id, i);
            cut(s->quads, &s->nquads, (size_t)i, sizeof *s->quads);
            drop_emitter(s, PRIM_QUAD, (size_t)i);
            break;
        case LC_BOX:
            FIND(s->boxes, s->nboxes, id, i);
            cut(s->boxes, &s->nboxes, (size_t)i, sizeof *s->boxes);
            drop_emitter(s, PRIM_BOX, (size_t)i);
            break;
        default:
            FIND(s->planes, s->nplanes, id, i);
            cut(s->planes, &s->nplanes, (size_t)i, sizeof *s->planes);
            break;
        }
        s->nshapes--;
        break;
    }
    s->c.valid = 0;
    lc_ok(err);
    return LC_OK;
}
