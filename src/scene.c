/* scene.c: building a scene description: settings, camera, materials, shapes, lights. */
#include <stdlib.h>
#include <string.h>
#include "error.h"
#include "scene.h"

/* Grows *arr to hold one more element of `size` bytes; 0 on failure. */
static int grow(void **arr, size_t *cap, size_t n, size_t size)
{
    if (n < *cap)
        return 1;
    size_t nc = *cap ? *cap * 2 : 16;
    if (nc > ((size_t)-1) / size)
        return 0;
    void *p = realloc(*arr, nc * size);
    if (!p)
        return 0;
    *arr = p;
    *cap = nc;
    return 1;
}

lc_scene *lc_scene_new(lc_error *err)
{
    lc_scene *s = calloc(1, sizeof *s);
    if (!s) {
        lc_fail(err, LC_ENOMEM, NULL, "out of memory creating a scene");
        return NULL;
    }
    s->settings = lc_settings_default();
    lc_ok(err);
    return s;
}

void lc_scene_free(lc_scene *s)
{
    if (!s)
        return;
    compiled_free(&s->c);
    free(s->materials);
    free(s->shapes);
    free(s->shape_material);
    free(s->lights);
    free(s);
}

lc_status lc_scene_configure(lc_scene *s, const lc_settings *st, lc_error *err)
{
    const lc_color *cs[2] = {&st->background, &st->ambient};
    const char *names[2] = {"background", "ambient"};
    for (int i = 0; i < 2; i++) {
        float ch[3] = {cs[i]->r, cs[i]->g, cs[i]->b};
        for (int k = 0; k < 3; k++)
            if (!isfinite(ch[k]) || ch[k] < 0)
                return lc_fail(err, LC_EARG, names[i],
                               "component %d must be finite and >= 0, got %g", k + 1, ch[k]);
    }
    if (st->max_depth < 0)
        return lc_fail(err, LC_EARG, "max_depth", "must be >= 0, got %d", st->max_depth);
    s->settings = *st;
    lc_ok(err);
    return LC_OK;
}

lc_settings lc_scene_settings(const lc_scene *s) { return s->settings; }

lc_status lc_scene_set_camera(lc_scene *s, const lc_camera *c, lc_error *err)
{
    if (lc_camera_check(c, err))
        return LC_EARG;
    s->camera = *c;
    s->has_camera = 1;
    return LC_OK;
}

int lc_scene_add_material(lc_scene *s, const lc_material *m, lc_error *err)
{
    if (lc_material_check(m, err))
        return -1;
    if (s->nmaterials >= (size_t)1 << 30 ||
        !grow((void **)&s->materials, &s->capmaterials, s->nmaterials, sizeof *m)) {
        lc_fail(err, LC_ENOMEM, NULL, "out of memory adding a material");
        return -1;
    }
    s->materials[s->nmaterials] = *m;
    return (int)s->nmaterials++;
}

int lc_scene_add_shape(lc_scene *s, const lc_shape *sh, int material, lc_error *err)
{
    if (lc_shape_check(sh, err))
        return -1;
    if (material < 0 || (size_t)material >= s->nmaterials) {
        lc_fail(err, LC_EARG, "material", "no material %d in this scene", material);
        return -1;
    }
    size_t cap = s->capshapes;
    if (s->nshapes >= 0x7fffffff ||
        !grow((void **)&s->shapes, &cap, s->nshapes, sizeof *sh)) {
        lc_fail(err, LC_ENOMEM, NULL, "out of memory adding a shape");
        return -1;
    }
    if (cap != s->capshapes) {
        int *m = realloc(s->shape_material, cap * sizeof *m);
        if (!m) {
            lc_fail(err, LC_ENOMEM, NULL, "out of memory adding a shape");
            return -1;
        }
        s->shape_material = m;
        s->capshapes = cap;
    }
    s->shapes[s->nshapes] = *sh;
    s->shape_material[s->nshapes] = material;
    return (int)s->nshapes++;
}

int lc_scene_add_light(lc_scene *s, const lc_point_light *l, lc_error *err)
{
    if (lc_point_light_check(l, err))
        return -1;
    if (s->nlights >= (size_t)1 << 30 ||
        !grow((void **)&s->lights, &s->caplights, s->nlights, sizeof *l)) {
        lc_fail(err, LC_ENOMEM, NULL, "out of memory adding a light");
        return -1;
    }
    s->lights[s->nlights] = *l;
    return (int)s->nlights++;
}

size_t lc_scene_shape_count(const lc_scene *s) { return s->nshapes; }
size_t lc_scene_light_count(const lc_scene *s) { return s->nlights; }
