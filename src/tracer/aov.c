/* aov.c: AOVs: camera samples' records summed per pixel into images. */
#include <float.h>
#include <math.h>
#include <string.h>
#include "aov.h"
#include "base/error.h"
#include "base/mem.h"
#include "tracer.h"
#include "scene/query.h"

void aov_first_hit(tracer *t, const hit *h, const lc_material *m, lc_vec3 n)
{
    aov_sample *as = t->aov;
    as->hit = 1;
    as->position = h->p;
    as->normal = n;
    as->albedo = rad(m->color);
    as->object = 1 + scene_object_id(t->scene, h);
    as->material = 1 + h->material;
}

int aov_room(uint32_t n, aov_count **objects, aov_count **materials)
{
    *objects = mem_alloc((size_t)n * sizeof **objects);
    *materials = mem_alloc((size_t)n * sizeof **materials);
    return *objects && *materials;
}

void aov_pixel_begin(aov_pixel *p, aov_count *objects, aov_count *materials)
{
    memset(p, 0, sizeof *p);
    p->depth = HUGE_VAL;
    p->objects = objects;
    p->materials = materials;
}

/* One more sample of `id` in the list (the background counts as 0). */
static void count_id(aov_count *list, uint32_t *n, int id)
{
    for (uint32_t i = 0; i < *n; i++)
        if (list[i].id == id) {
            list[i].n++;
            return;
        }
    list[*n].id = id;
    list[*n].n = 1;
    ++*n;
}

void aov_pixel_add(aov_pixel *p, const aov_sample *as, lc_vec3 eye, lc_vec3 forward)
{
    for (int k = 0; k < AOV_PATHS; k++) {
        p->light[k][0] += as->light[k].r;
        p->light[k][1] += as->light[k].g;
        p->light[k][2] += as->light[k].b;
    }
    count_id(p->objects, &p->nobjects, as->hit ? as->object : 0);
    count_id(p->materials, &p->nmaterials, as->hit ? as->material : 0);
    if (!as->hit)
        return;
    p->normal[0] += as->normal.x, p->normal[1] += as->normal.y, p->normal[2] += as->normal.z;
    p->albedo[0] += as->albedo.r, p->albedo[1] += as->albedo.g, p->albedo[2] += as->albedo.b;
    double z = v3_dot(v3_sub(as->position, eye), forward);
    if (z < p->depth) {           /* the first of equals: the same in any order run */
        p->depth = z;
        p->position = as->position;
    }
}

lc_status aov_images_new(lc_image *img, unsigned aovs, lc_error *err)
{
    size_t n = (size_t)img->width * img->height;
    for (int k = 0; k < LC_AOVS; k++) {
        if (!(aovs & (1u << k)))
            continue;
        lc_image *a = lc_image_new(img->width, img->height, err);
        if (!a)
            return err ? err->code : LC_ENOMEM;
        img->aov[k] = a;
        a->win = img->win;
        if (k == LC_AOV_OBJECT || k == LC_AOV_MATERIAL) {
            a->ranks = mem_alloc(n * 2 * LC_AOV_RANKS * sizeof *a->ranks);
            if (!a->ranks)
                return error_fail(err, LC_ENOMEM, NULL, "out of memory for the %s AOV of "
                                  "%dx%d pixels", lc_aov_name((lc_aov)k), img->width,
                                  img->height);
        }
    }
    error_ok(err);
    return LC_OK;
}

static void set3(lc_image *a, int x, int y, double r, double g, double b)
{
    float *px = a->px + 3 * ((size_t)y * a->width + x);
    px[0] = (float)r;
    px[1] = (float)g;
    px[2] = (float)b;
}

/* The id seen by most samples, the background (0) among them, ties to the
** smaller id; ranks: the objects alone, most samples first, ties the same. */
static void put_ids(lc_image *a, int x, int y, aov_count *list, uint32_t nl, uint32_t n)
{
    float *rk = a->ranks + (size_t)2 * LC_AOV_RANKS * ((size_t)y * a->width + x);
    int top = 0;
    uint32_t most = 0;
    for (uint32_t i = 0; i < nl; i++)
        if (list[i].n > most || (list[i].n == most && list[i].id < top))
            top = list[i].id, most = list[i].n;
    set3(a, x, y, top, top, top);
    for (int r = 0; r < LC_AOV_RANKS; r++) {
        int best = -1;
        for (uint32_t i = 0; i < nl; i++) {
            const aov_count *c = &list[i];
            if (c->id == 0 || c->n == 0)
                continue;
            if (best < 0 || c->n > list[best].n ||
                (c->n == list[best].n && c->id < list[best].id))
                best = (int)i;
        }
        rk[2 * r] = best < 0 ? 0.0f : (float)list[best].id;
        rk[2 * r + 1] = best < 0 ? 0.0f : (float)((double)list[best].n / n);
        if (best >= 0)
            list[best].n = 0;     /* taken: the list is spent with the pixel */
    }
}

void aov_put(lc_image *img, int x, int y, const aov_pixel *p, uint32_t n)
{
    lc_image *const *a = img->aov;
    double inv = 1.0 / n;
    for (int k = 0; k < AOV_PATHS; k++)
        if (a[LC_AOV_DIRECT + k])
            set3(a[LC_AOV_DIRECT + k], x, y, fmin(p->light[k][0] * inv, FLT_MAX),
                 fmin(p->light[k][1] * inv, FLT_MAX), fmin(p->light[k][2] * inv, FLT_MAX));
    if (a[LC_AOV_DEPTH])
        set3(a[LC_AOV_DEPTH], x, y, p->depth, p->depth, p->depth);
    if (a[LC_AOV_POSITION]) {
        lc_vec3 q = p->depth < HUGE_VAL ? p->position : v3(0, 0, 0);
        set3(a[LC_AOV_POSITION], x, y, q.x, q.y, q.z);
    }
    if (a[LC_AOV_NORMAL])
        set3(a[LC_AOV_NORMAL], x, y, p->normal[0] * inv, p->normal[1] * inv,
             p->normal[2] * inv);
    if (a[LC_AOV_ALBEDO])
        set3(a[LC_AOV_ALBEDO], x, y, p->albedo[0] * inv, p->albedo[1] * inv,
             p->albedo[2] * inv);
    if (a[LC_AOV_OBJECT])
        put_ids(a[LC_AOV_OBJECT], x, y, p->objects, p->nobjects, n);
    if (a[LC_AOV_MATERIAL])
        put_ids(a[LC_AOV_MATERIAL], x, y, p->materials, p->nmaterials, n);
}
