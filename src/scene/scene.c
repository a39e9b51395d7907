/* scene.c: building a scene description: settings, camera, materials, shapes, lights. */
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "scene.h"
#include "texture/texture.h"
#include "base/mem.h"
#include "compile.h"
#include "instance.h"
#include "csg.h"

/* Makes room for one more element of `size` bytes in *arr. */
static int grow(void **arr, size_t *cap, size_t n, size_t size)
{
    if (n < *cap)
        return 1;
    size_t nc = *cap ? *cap * 2 : 16;
    if (nc > ((size_t)-1) / size)
        return 0;
    void *p = mem_realloc(*arr, nc * size);
    if (!p)
        return 0;
    *arr = p;
    *cap = nc;
    return 1;
}
#define GROW(s, name) grow((void **)&(s)->name, &(s)->cap##name, (s)->n##name, sizeof *(s)->name)

lc_scene *lc_scene_new(lc_error *err)
{
    lc_scene *s = mem_calloc(1, sizeof *s);
    if (!s) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory creating a scene");
        return NULL;
    }
    s->settings = lc_settings_default();
    pthread_mutex_init(&s->lock, NULL);
    error_ok(err);
    return s;
}

void lc_scene_free(lc_scene *s)
{
    if (!s)
        return;
    compile_free(&s->c);
    instance_free_all(s);
    pthread_mutex_destroy(&s->lock);
    for (size_t i = 0; i < s->nmeshes; i++) {
        lc_mesh_free(s->meshes[i].mesh);
        mem_free(s->meshes[i].xf);
        mem_free(s->meshes[i].palette);
    }
    for (size_t i = 0; i < s->ncsgs; i++)
        csg_free(s->csgs[i]);
    mem_free(s->csgs);
    mem_free(s->light_ids);
    mem_free(s->materials);
    lc_textures_free(s->textures);
    for (int k = 0; k < LC_SHAPE_KINDS; k++) {
        mem_free(s->shapes[k].geom);
        mem_free(s->shapes[k].material);
        mem_free(s->shapes[k].id);
    }
    mem_free(s->meshes);
    mem_free(s->emitters);
    mem_free(s->lights);
    mem_free(s->spots);
    mem_free(s->spot_ids);
    mem_free(s->suns);
    mem_free(s->sun_ids);
    mem_free(s);
}

lc_status lc_scene_configure(lc_scene *s, const lc_settings *st, lc_error *err)
{
    const lc_color *cs[2] = {&st->background, &st->ambient};
    const char *names[2] = {"background", "ambient"};
    for (int i = 0; i < 2; i++) {
        float ch[3] = {cs[i]->r, cs[i]->g, cs[i]->b};
        for (int k = 0; k < 3; k++)
            if (!isfinite(ch[k]) || ch[k] < 0)
                return error_fail(err, LC_EARG, names[i],
                               "component %d must be finite and >= 0, got %g", k + 1, ch[k]);
    }
    size_t ntex = s->textures ? lc_textures_count(s->textures) : 0;
    if (st->background_texture < 0 || (size_t)st->background_texture > ntex)
        return error_fail(err, LC_EARG, "background", "no texture %d in this scene (it "
                          "has %zu)", st->background_texture, ntex);
    if (st->max_depth < 0 || st->max_depth > LC_MAX_DEPTH)
        return error_fail(err, LC_EARG, "max_depth", "must be in [0, %d], got %d", LC_MAX_DEPTH,
                       st->max_depth);
    s->settings = *st;
    error_ok(err);
    return LC_OK;
}

lc_settings lc_scene_settings(const lc_scene *s) { return s->settings; }

int lc_scene_camera(const lc_scene *s, lc_camera *out)
{
    if (s->has_camera)
        *out = s->camera;
    return s->has_camera;
}

lc_status lc_scene_set_camera(lc_scene *s, const lc_camera *c, lc_error *err)
{
    if (lc_camera_check(c, err))
        return LC_EARG;
    s->camera = *c;
    s->has_camera = 1;
    return LC_OK;
}

int lc_scene_add_texture(lc_scene *s, const lc_texture *t, lc_error *err)
{
    if (!s->textures && !(s->textures = lc_textures_new(err)))
        return -1;
    int i = lc_textures_add(s->textures, t, err);
    if (i >= 0)
        s->c.valid = 0;
    return i;
}

int lc_scene_add_material(lc_scene *s, const lc_material *m, lc_error *err)
{
    if (lc_material_check(m, err))
        return -1;
    size_t ntex = s->textures ? lc_textures_count(s->textures) : 0;
        for (int k = 0; k < LC_SLOTS; k++)
        if ((size_t)m->texture[k] > ntex)
            return error_fail(err, LC_EARG, lc_slot_name((lc_slot)k), "no texture %d in "
                              "this scene (it has %zu)", m->texture[k], ntex), -1;
    if (s->nmaterials >= PRIM_MAX || !GROW(s, materials)) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a material");
        return -1;
    }
    s->materials[s->nmaterials] = *m;
    s->c.valid = 0;
    return (int)s->nmaterials++;
}

static int check_material(const lc_scene *s, int material, lc_error *err)
{
    if (material < 0 || (size_t)material >= s->nmaterials) {
        error_fail(err, LC_EARG, "material", "no material %d in this scene", material);
        return 0;
    }
    return 1;
}

/* Makes room for one more shape in l, whose three arrays grow together. */
static int shape_list_grow(shape_list *l)
{
    if (l->n < l->cap)
        return 1;
    size_t nc = l->cap ? l->cap * 2 : 16;
    if (nc > PRIM_MAX || nc > ((size_t)-1) / l->size)
        return 0;
    unsigned char *g = mem_realloc(l->geom, nc * l->size);
    if (g)
        l->geom = g;
    int *m = g ? mem_realloc(l->material, nc * sizeof *m) : NULL;
    if (m)
        l->material = m;
    int *id = m ? mem_realloc(l->id, nc * sizeof *id) : NULL;
    if (!id)
        return 0;
    l->id = id;
    l->cap = nc;
    return 1;
}

int lc_scene_add_shape(lc_scene *s, const lc_shape *sh, int material, lc_error *err)
{
    if (lc_shape_check(sh, err) || !check_material(s, material, err))
        return -1;
    shape_list *l = &s->shapes[sh->kind];
    l->size = shape_geom_size(sh->kind);
    const lc_material *m = &s->materials[material];
    int emits = shape_can_emit(sh->kind) && !c_is_black(m->emission);
    if (l->n >= PRIM_MAX || !shape_list_grow(l) || (emits && !GROW(s, emitters))) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a shape");
        return -1;
    }
    size_t i = l->n++;
    void *geom = l->geom + i * l->size;
    shape_prepare(sh, geom);
    if (emits)
        shape_prepare_emitter(sh->kind, geom);
    l->material[i] = material;
    l->id[i] = s->next_id;
    if (emits) {
        emitter *e = &s->emitters[s->nemitters++];
        e->kind = sh->kind;
        e->index = (uint32_t)i;
        e->prim = PRIM_ID(shape_prim_kind(sh->kind), i);
        e->target = shape_light_target(sh->kind, geom);
        e->emission = m->emission;
    }
    s->c.valid = 0;
    s->nshapes++;
    return s->next_id++;
}

/* Adds m, moved by xf (taken over) or as it is when xf is NULL. */
static int add_mesh(lc_scene *s, lc_mesh *m, affine *xf, int material, int *palette,
                    uint32_t npalette, lc_error *err)
{
    if (!check_material(s, material, err)) {
        mem_free(xf);
        mem_free(palette);
        return -1;
    }
    if (m->nn != 0 && m->nn != m->nv) {
        error_fail(err, LC_EARG, "normals", "mesh has %zu normals for %zu vertices", m->nn,
                m->nv);
        mem_free(xf);
        mem_free(palette);
        return -1;
    }
    if (m->nuv != 0 && m->nuv != m->nv) {
        error_fail(err, LC_EARG, "uvs", "mesh has %zu uvs for %zu vertices", m->nuv, m->nv);
        mem_free(xf);
        mem_free(palette);
        return -1;
    }
    if (s->nmeshes >= PRIM_MAX || !GROW(s, meshes)) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a mesh");
        mem_free(xf);
        mem_free(palette);
        return -1;
    }
    mesh_prim *mp = &s->meshes[s->nmeshes++];
    memset(mp, 0, sizeof *mp);
    mp->mesh = mesh_retain(m);
    mp->material = material;
    mp->xf = xf;
    mp->palette = palette;
    mp->npalette = npalette;
    mp->id = s->next_id;
    s->c.valid = 0;
    s->nshapes++;
    return s->next_id++;
}

int lc_scene_add_mesh(lc_scene *s, lc_mesh *m, int material, lc_error *err)
{
    return add_mesh(s, m, NULL, material, NULL, 0, err);
}

/* *xf: t made an affine placement, or NULL for the identity. */
static lc_status placement(const lc_transform *t, affine **xf, lc_error *err)
{
    *xf = NULL;
    if (lc_transform_check(t, err))
        return LC_EARG;
    if (lc_transform_is_identity(t))
        return LC_OK;
    if (!(*xf = mem_alloc(sizeof **xf)))
        return error_fail(err, LC_ENOMEM, NULL, "out of memory adding a mesh");
    if (affine_make(t, *xf, err)) {
        mem_free(*xf);
        *xf = NULL;
        return LC_EARG;
    }
    return LC_OK;
}

int lc_scene_add_mesh_moved(lc_scene *s, lc_mesh *m, const lc_transform *t, int material,
                            lc_error *err)
{
    if (lc_transform_check(t, err))
        return -1;
    affine *xf;
    if (placement(t, &xf, err))
        return -1;
    return add_mesh(s, m, xf, material, NULL, 0, err);
}

int lc_scene_add_mesh_materials(lc_scene *s, lc_mesh *m, const lc_transform *t,
                                const int *materials, size_t n, lc_error *err)
{
    if (n == 0 || n > LC_MAX_SLOTS)
        return error_fail(err, LC_EARG, "materials", "between 1 and %d materials, got %zu",
                          LC_MAX_SLOTS, n), -1;
    if (n < m->nslots)
        return error_fail(err, LC_EARG, "materials", "the mesh's faces use %lu material "
                          "slots, %zu materials given", (unsigned long)m->nslots, n), -1;
    for (size_t k = 0; k < n; k++)
        if (!check_material(s, materials[k], err))
            return -1;
    affine *xf = NULL;
    if (t && placement(t, &xf, err))
        return -1;
    int *palette = mem_alloc(n * sizeof *palette);
    if (!palette) {
        mem_free(xf);
        return error_fail(err, LC_ENOMEM, NULL, "out of memory adding a mesh"), -1;
    }
    memcpy(palette, materials, n * sizeof *palette);
    return add_mesh(s, m, xf, materials[0], palette, (uint32_t)n, err);
}

int lc_scene_add_csg(lc_scene *s, const lc_csg_node *nodes, size_t n, lc_error *err)
{
    if (lc_csg_check(nodes, n, err))
        return -1;
    for (size_t i = 0; i < n; i++)
        if ((nodes[i].op == LC_CSG_SHAPE || nodes[i].op == LC_CSG_MESH) &&
            !check_material(s, nodes[i].material, err)) {
            if (n > 1)
                error_prefix(err, "node %zu: ", i);
            return -1;
        }
    if (s->ncsgs >= PRIM_MAX || !GROW(s, csgs)) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a CSG object");
        return -1;
    }
    csg_tree *t = csg_build(nodes, n, s->csgs, s->ncsgs, err);
    if (!t)
        return -1;
    t->id = s->next_id;
    s->csgs[s->ncsgs++] = t;
    s->c.valid = 0;
    s->nshapes++;
    return s->next_id++;
}

int lc_scene_add_light(lc_scene *s, const lc_point_light *l, lc_error *err)
{
    if (lc_point_light_check(l, err))
        return -1;
    size_t cap = s->caplights;
    if (s->nlights >= PRIM_MAX || !GROW(s, lights)) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a light");
        return -1;
    }
    if (s->caplights != cap || !s->light_ids) {     /* ids grow beside the lights */
        int *ids = mem_realloc(s->light_ids, s->caplights * sizeof *ids);
        if (!ids) {
            error_fail(err, LC_ENOMEM, NULL, "out of memory adding a light");
            return -1;
        }
        s->light_ids = ids;
    }
    s->light_ids[s->nlights] = s->next_id;
    s->lights[s->nlights++] = *l;
    s->c.valid = 0;
    return s->next_id++;
}

/* Makes room for one more light in an array whose ids grow beside it. */
static int grow_with_ids(void **arr, size_t *cap, size_t n, size_t size, int **ids)
{
    size_t before = *cap;
    if (n >= PRIM_MAX || !grow(arr, cap, n, size))
        return 0;
    if (*cap != before || !*ids) {
        int *p = mem_realloc(*ids, *cap * sizeof **ids);
        if (!p)
            return 0;
        *ids = p;
    }
    return 1;
}

int lc_scene_add_spot_light(lc_scene *s, const lc_spot_light *l, lc_error *err)
{
    if (lc_spot_light_check(l, err))
        return -1;
    if (!grow_with_ids((void **)&s->spots, &s->capspots, s->nspots, sizeof *s->spots,
                       &s->spot_ids)) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a light");
        return -1;
    }
    s->spot_ids[s->nspots] = s->next_id;
    spot_prepare(l, &s->spots[s->nspots++]);
    s->c.valid = 0;
    return s->next_id++;
}

int lc_scene_add_directional_light(lc_scene *s, const lc_directional_light *l,
                                   lc_error *err)
{
    if (lc_directional_light_check(l, err))
        return -1;
    if (!grow_with_ids((void **)&s->suns, &s->capsuns, s->nsuns, sizeof *s->suns,
                       &s->sun_ids)) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory adding a light");
        return -1;
    }
    s->sun_ids[s->nsuns] = s->next_id;
    sun_prepare(l, &s->suns[s->nsuns++]);
    s->c.valid = 0;
    return s->next_id++;
}

size_t lc_scene_shape_count(const lc_scene *s) { return s->nshapes; }
size_t lc_scene_light_count(const lc_scene *s)
{
    return s->nlights + s->nspots + s->nsuns;
}

/* Scaling by `scale` about the origin, then moving by `t`. */
typedef struct { double scale; lc_vec3 t; } placing;

static lc_vec3 move(lc_vec3 p, const placing *pl)
{
    double s = pl->scale;
    return v3(p.x * s + pl->t.x, p.y * s + pl->t.y, p.z * s + pl->t.z);
}

/* The same as a transform, to compose with an object's own. */
static lc_transform placing_transform(const placing *pl)
{
    lc_transform st = lc_transform_scale(v3(pl->scale, pl->scale, pl->scale));
    lc_transform mv = lc_transform_translate(pl->t);
    return lc_transform_compose(&mv, &st);
}

/* Settings, camera, textures and materials: what the objects refer to. */
static lc_status copy_looks(lc_scene *c, const lc_scene *s, const placing *pl,
                            lc_error *err)
{
    c->settings = s->settings;
    if (s->has_camera) {
        lc_camera cam = s->camera;
        cam.from = move(cam.from, pl);
        cam.at = move(cam.at, pl);
        cam.aperture *= pl->scale;      /* lengths, like the scene's */
        cam.focus *= pl->scale;
        if (lc_scene_set_camera(c, &cam, err))
            return LC_EARG;
    }
    if (s->textures && !(c->textures = textures_transformed(s->textures, pl->scale, pl->t,
                                                             s->settings.background_texture,
                                                             err)))
        return LC_EARG;
    for (size_t i = 0; i < s->nmaterials; i++) {
        lc_material m = s->materials[i];
        /* Per unit length: the same e^(-absorption d) over lengths d * scale. */
        m.absorption = v3_mul(m.absorption, 1 / pl->scale);
        if (lc_scene_add_material(c, &m, err) < 0)
            return LC_EARG;
    }
    return LC_OK;
}

static lc_status copy_shapes(lc_scene *c, const lc_scene *s, const placing *pl,
                             lc_error *err)
{
    for (int k = 0; k < LC_SHAPE_KINDS; k++) {
        const shape_list *l = &s->shapes[k];
        for (size_t i = 0; i < l->n; i++) {
            lc_shape sh;
            memset(&sh, 0, sizeof sh);
            shape_describe((lc_shape_kind)k, shape_at(l, i), &sh);
            shape_scale(&sh, pl->scale, pl->t);
            if (lc_scene_add_shape(c, &sh, l->material[i], err) < 0)
                return LC_EARG;
        }
    }
    return LC_OK;
}

/* Adds mesh m as mp is added (its materials, xf moved or none); -1 if not. */
static int add_mesh_as(lc_scene *c, lc_mesh *m, const lc_transform *xf,
                       const mesh_prim *mp, lc_error *err)
{
    if (mp->palette)
        return lc_scene_add_mesh_materials(c, m, xf, mp->palette, mp->npalette, err);
    return xf ? lc_scene_add_mesh_moved(c, m, xf, mp->material, err)
              : lc_scene_add_mesh(c, m, mp->material, err);
}

/* A flat mesh is copied with its vertices moved. */
static lc_status copy_flat_mesh(lc_scene *c, const mesh_prim *mp, const placing *pl,
                                lc_error *err)
{
    const lc_mesh *src = mp->mesh;
    lc_mesh *m = lc_mesh_new(err);
    lc_status st = m ? LC_OK : LC_ENOMEM;
    for (size_t k = 0; st == LC_OK && k < src->nv; k++) {
        lc_vec3 p = move(v3(src->v[3 * k], src->v[3 * k + 1], src->v[3 * k + 2]), pl);
        double xyz[3] = {p.x, p.y, p.z};
        st = lc_mesh_add_vertices(m, xyz, 1, err);
    }
    if (st == LC_OK && src->nn)
        st = lc_mesh_add_normals(m, src->n, src->nn, err);
    if (st == LC_OK && src->nuv)
        st = lc_mesh_add_uvs(m, src->uv, src->nuv, err);
    if (st == LC_OK)
        st = lc_mesh_add_faces(m, src->f, src->nf, err);
    if (st == LC_OK && src->nslot)
        st = lc_mesh_add_face_materials(m, src->slot, src->nslot, err);
    if (st == LC_OK && add_mesh_as(c, m, NULL, mp, err) < 0)
        st = LC_EARG;
    lc_mesh_free(m);
    return st;
}

static lc_status copy_meshes(lc_scene *c, const lc_scene *s, const placing *pl,
                             lc_error *err)
{
    for (size_t i = 0; i < s->nmeshes; i++) {
        const mesh_prim *mp = &s->meshes[i];
        if (mp->xf) {          /* an instance stays one, of the same mesh */
            lc_transform st = placing_transform(pl);
            st = lc_transform_compose(&st, &mp->xf->xf);
            if (add_mesh_as(c, mp->mesh, &st, mp, err) < 0)
                return LC_EARG;
        } else if (copy_flat_mesh(c, mp, pl, err)) {
            return LC_EARG;
        }
    }
    return LC_OK;
}

static lc_status copy_csgs(lc_scene *c, const lc_scene *s, const placing *pl,
                           lc_error *err)
{
    for (size_t i = 0; i < s->ncsgs; i++) {
        const csg_tree *tr = s->csgs[i];
        lc_csg_node *d = mem_alloc(tr->n * sizeof *d);
        if (!d)
            return error_fail(err, LC_ENOMEM, NULL, "out of memory copying a CSG object");
        memcpy(d, tr->desc, tr->n * sizeof *d);
        for (size_t k = 0; k < tr->n; k++) {
            if (d[k].op == LC_CSG_SHAPE) {
                shape_scale(&d[k].shape, pl->scale, pl->t);
            } else if (d[k].op == LC_CSG_MESH) {
                lc_transform st = placing_transform(pl);
                d[k].transform = lc_transform_compose(&st, &d[k].transform);
            }
        }
        int id = lc_scene_add_csg(c, d, tr->n, err);
        mem_free(d);
        if (id < 0)
            return LC_EARG;
    }
    return LC_OK;
}

/* Point and spot lights falling off as 1/d^2 get intensity * s^2. */
static lc_status copy_lights(lc_scene *c, const lc_scene *s, const placing *pl,
                             lc_error *err)
{
    double s2 = pl->scale * pl->scale;
    for (size_t i = 0; i < s->nlights; i++) {
        lc_point_light l = s->lights[i];
        l.position = move(l.position, pl);
        if (l.falloff == LC_FALLOFF_INVERSE_SQUARE)
            l.intensity *= s2;
        if (lc_scene_add_light(c, &l, err) < 0)
            return LC_EARG;
    }
    for (size_t i = 0; i < s->nspots; i++) {
        lc_spot_light l = s->spots[i].d;
        l.position = move(l.position, pl);
        if (l.falloff == LC_FALLOFF_INVERSE_SQUARE)
            l.intensity *= s2;
        if (lc_scene_add_spot_light(c, &l, err) < 0)
            return LC_EARG;
    }
    for (size_t i = 0; i < s->nsuns; i++)      /* directions: neither scaled nor moved */
        if (lc_scene_add_directional_light(c, &s->suns[i].d, err) < 0)
            return LC_EARG;
    return LC_OK;
}

/* A copy of the scene scaled by s about the origin, then moved by t: every
** position, size and the camera; point lights falling off as 1/d^2 get
** intensity * s^2, so the picture should not change at all. */
lc_scene *lc_scene_transformed(const lc_scene *s, double scale, lc_vec3 t, lc_error *err)
{
    if (!(scale > 0) || !isfinite(scale))
        return error_fail(err, LC_EARG, "scale", "must be finite and > 0, got %g", scale),
               NULL;
    if (!isfinite(t.x) || !isfinite(t.y) || !isfinite(t.z))
        return error_fail(err, LC_EARG, "offset", "must be finite"), NULL;
    lc_scene *c = lc_scene_new(err);
    if (!c)
        return NULL;
    const placing pl = {scale, t};
    if (copy_looks(c, s, &pl, err) || copy_shapes(c, s, &pl, err) ||
        copy_meshes(c, s, &pl, err) || copy_csgs(c, s, &pl, err) ||
        copy_lights(c, s, &pl, err)) {
        lc_scene_free(c);
        return NULL;
    }
    return c;
}
