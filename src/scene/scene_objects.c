/* scene_objects.c: listing a scene's objects in the order added, and removing them. */
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "scene.h"
#include "base/mem.h"
#include "csg.h"

/* Ids grow with each add, and removal keeps the order, so every list is
** sorted by id: a binary search finds an object. Returns its index or -1. */
static long find_id(const int *ids, size_t n, int id)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (ids[mid] < id) lo = mid + 1; else hi = mid;
    }
    return lo < n && ids[lo] == id ? (long)lo : -1;
}

static long find_mesh(const lc_scene *s, int id)
{
    size_t lo = 0, hi = s->nmeshes;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->meshes[mid].id < id) lo = mid + 1; else hi = mid;
    }
    return lo < s->nmeshes && s->meshes[lo].id == id ? (long)lo : -1;
}

size_t lc_scene_object_count(const lc_scene *s)
{
    return s->nshapes + lc_scene_light_count(s);
}

static void shape_object(lc_object *o, const lc_scene *s, lc_shape_kind kind, size_t i)
{
    const shape_list *l = &s->shapes[kind];
    memset(&o->shape, 0, sizeof o->shape);
    o->kind = LC_OBJECT_SHAPE;
    o->id = l->id[i];
    o->material = l->material[i];
    shape_describe(kind, shape_at(l, i), &o->shape);
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

static void csg_object(lc_object *o, const csg_tree *t)
{
    o->kind = LC_OBJECT_CSG;
    o->id = t->id;
    o->material = -1;
    o->transform = lc_transform_identity();
    o->csg = t->desc;
    o->csg_nodes = t->n;
}

static long find_csg(const lc_scene *s, int id)
{
    size_t lo = 0, hi = s->ncsgs;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->csgs[mid]->id < id) lo = mid + 1; else hi = mid;
    }
    return lo < s->ncsgs && s->csgs[lo]->id == id ? (long)lo : -1;
}

static void light_object(lc_object *o, const lc_scene *s, size_t i)
{
    o->kind = LC_OBJECT_LIGHT;
    o->id = s->light_ids[i];
    o->material = -1;
    o->light = s->lights[i];
}

static void spot_object(lc_object *o, const lc_scene *s, size_t i)
{
    o->kind = LC_OBJECT_SPOT_LIGHT;
    o->id = s->spot_ids[i];
    o->material = -1;
    o->spot = s->spots[i].d;
}

static void sun_object(lc_object *o, const lc_scene *s, size_t i)
{
    o->kind = LC_OBJECT_DIRECTIONAL_LIGHT;
    o->id = s->sun_ids[i];
    o->material = -1;
    o->sun = s->suns[i].d;
}

/* The sorted lists merged by id: one per shape kind, then meshes, CSG
** objects, lights of each kind. */
enum { LIST_MESHES = LC_SHAPE_KINDS, LIST_CSGS, LIST_LIGHTS, LIST_SPOTS, LIST_SUNS, LISTS };

static size_t list_len(const lc_scene *s, int j)
{
    switch (j) {
    case LIST_MESHES: return s->nmeshes;
    case LIST_CSGS: return s->ncsgs;
    case LIST_LIGHTS: return s->nlights;
    case LIST_SPOTS: return s->nspots;
    case LIST_SUNS: return s->nsuns;
    default: return s->shapes[j].n;
    }
}

static int list_id(const lc_scene *s, int j, size_t i)
{
    switch (j) {
    case LIST_MESHES: return s->meshes[i].id;
    case LIST_CSGS: return s->csgs[i]->id;
    case LIST_LIGHTS: return s->light_ids[i];
    case LIST_SPOTS: return s->spot_ids[i];
    case LIST_SUNS: return s->sun_ids[i];
    default: return s->shapes[j].id[i];
    }
}

size_t lc_scene_objects(const lc_scene *s, lc_object *out, size_t n)
{
    size_t at[LISTS] = {0};
    size_t total = lc_scene_object_count(s);
    for (size_t k = 0; k < n && k < total; k++) {
        int best = -1, best_id = 0;
        for (int j = 0; j < LISTS; j++) {
            if (at[j] == list_len(s, j))
                continue;
            int id = list_id(s, j, at[j]);
            if (best < 0 || id < best_id) {
                best = j;
                best_id = id;
            }
        }
        lc_object *o = &out[k];
        memset(o, 0, sizeof *o);
        size_t i = at[best]++;
        if (best < LC_SHAPE_KINDS)
            shape_object(o, s, (lc_shape_kind)best, i);
        else if (best == LIST_MESHES)
            mesh_object(o, &s->meshes[i]);
        else if (best == LIST_CSGS)
            csg_object(o, s->csgs[i]);
        else if (best == LIST_LIGHTS)
            light_object(o, s, i);
        else if (best == LIST_SPOTS)
            spot_object(o, s, i);
        else
            sun_object(o, s, i);
    }
    return total;
}

lc_status lc_scene_object(const lc_scene *s, int id, lc_object *out, lc_error *err)
{
    long i;
    memset(out, 0, sizeof *out);
    for (int k = 0; k < LC_SHAPE_KINDS; k++)
        if ((i = find_id(s->shapes[k].id, s->shapes[k].n, id)) >= 0) {
            shape_object(out, s, (lc_shape_kind)k, (size_t)i);
            error_ok(err);
            return LC_OK;
        }
    if ((i = find_mesh(s, id)) >= 0)
        return mesh_object(out, &s->meshes[i]), error_ok(err), LC_OK;
    if ((i = find_csg(s, id)) >= 0)
        return csg_object(out, s->csgs[i]), error_ok(err), LC_OK;
    if ((i = find_id(s->light_ids, s->nlights, id)) >= 0)
        return light_object(out, s, (size_t)i), error_ok(err), LC_OK;
    if ((i = find_id(s->spot_ids, s->nspots, id)) >= 0)
        return spot_object(out, s, (size_t)i), error_ok(err), LC_OK;
    if ((i = find_id(s->sun_ids, s->nsuns, id)) >= 0)
        return sun_object(out, s, (size_t)i), error_ok(err), LC_OK;
    return error_fail(err, LC_EARG, "id", "no object %d in this scene (%s)", id,
                   id >= 0 && id < s->next_id ? "it was removed" : "never added");
}

/* Removes element i of an array of n elements of `size` bytes, keeping order. */
static void cut(void *arr, size_t *n, size_t i, size_t size)
{
    char *a = arr;
    memmove(a + i * size, a + (i + 1) * size, (*n - i - 1) * size);
    --*n;
}

/* The emitter of shape i of that kind goes; later ones of the kind move down. */
static void drop_emitter(lc_scene *s, lc_shape_kind kind, size_t i)
{
    for (size_t e = 0; e < s->nemitters; e++) {
        emitter *em = &s->emitters[e];
        if (em->kind != kind || em->index < i)
            continue;
        if (em->index == i) {
            cut(s->emitters, &s->nemitters, e, sizeof *s->emitters);
            e--;
        } else {
            em->index--;
            em->prim--;
        }
    }
}

static void remove_shape(lc_scene *s, lc_shape_kind kind, size_t i)
{
    shape_list *l = &s->shapes[kind];
    size_t n = l->n;
    cut(l->geom, &n, i, l->size);
    n = l->n;
    cut(l->material, &n, i, sizeof *l->material);
    cut(l->id, &l->n, i, sizeof *l->id);
    drop_emitter(s, kind, i);
}

lc_status lc_scene_remove(lc_scene *s, int id, lc_error *err)
{
    lc_object o;
    if (lc_scene_object(s, id, &o, err))
        return LC_EARG;
    long i;
    switch (o.kind) {
    case LC_OBJECT_LIGHT:
        i = find_id(s->light_ids, s->nlights, id);
        memmove(s->light_ids + i, s->light_ids + i + 1,
                (s->nlights - (size_t)i - 1) * sizeof *s->light_ids);
        cut(s->lights, &s->nlights, (size_t)i, sizeof *s->lights);
        break;
    case LC_OBJECT_SPOT_LIGHT:
        i = find_id(s->spot_ids, s->nspots, id);
        memmove(s->spot_ids + i, s->spot_ids + i + 1,
                (s->nspots - (size_t)i - 1) * sizeof *s->spot_ids);
        cut(s->spots, &s->nspots, (size_t)i, sizeof *s->spots);
        break;
    case LC_OBJECT_DIRECTIONAL_LIGHT:
        i = find_id(s->sun_ids, s->nsuns, id);
        memmove(s->sun_ids + i, s->sun_ids + i + 1,
                (s->nsuns - (size_t)i - 1) * sizeof *s->sun_ids);
        cut(s->suns, &s->nsuns, (size_t)i, sizeof *s->suns);
        break;
    case LC_OBJECT_CSG:
        i = find_csg(s, id);
        csg_free(s->csgs[i]);
        cut(s->csgs, &s->ncsgs, (size_t)i, sizeof *s->csgs);
        s->nshapes--;
        break;
    case LC_OBJECT_MESH:
        i = find_mesh(s, id);
        lc_mesh_free(s->meshes[i].mesh);       /* the scene's hold; the cache has its own */
        mem_free(s->meshes[i].xf);
        mem_free(s->meshes[i].palette);
        cut(s->meshes, &s->nmeshes, (size_t)i, sizeof *s->meshes);
        s->nshapes--;
        break;
    default:
        i = find_id(s->shapes[o.shape.kind].id, s->shapes[o.shape.kind].n, id);
        remove_shape(s, o.shape.kind, (size_t)i);
        s->nshapes--;
        break;
    }
    s->c.valid = 0;
    error_ok(err);
    return LC_OK;
}
