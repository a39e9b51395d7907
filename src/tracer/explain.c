/* explain.c: recording the rays one sample traces and what each adds to the
** pixel (lc_scene_explain's ray tree). */
#include <stdlib.h>
#include <string.h>
#include "explain.h"
#include "scene/csg.h"

void explain_free(ray_log *g)
{
    free(g->own);
    g->own = NULL;
}

int explain_ray(ray_log *g, int parent, lc_ray_kind kind, const ray *r)
{
    if (g->failed)
        return -1;
    if (g->n == g->cap) {
        size_t nc = g->cap ? 2 * g->cap : 64;
        lc_ray_record *p = realloc(g->r, nc * sizeof *p);
        if (p)
            g->r = p;
        double *b = p ? realloc(g->own, 3 * nc * sizeof *b) : NULL;
        if (!b) {
            g->failed = 1;
            return -1;
        }
        g->own = b;
        g->cap = nc;
    }
    lc_ray_record *x = &g->r[g->n];
    memset(x, 0, sizeof *x);
    g->own[3 * g->n] = g->own[3 * g->n + 1] = g->own[3 * g->n + 2] = 0;
    x->parent = parent;
    x->kind = kind;
    x->origin = r->o;
    x->direction = r->d;
    x->shape_kind = -1;
    x->shape = -1;
    x->material = -1;
    x->csg = x->csg_node = -1;
    return (int)g->n++;
}

void explain_hit(ray_log *g, const lc_scene *s, int rec, const hit *h, lc_vec3 n,
                 radiance w)
{
    if (rec < 0)
        return;
    g->parent = rec;
    g->w = w;
    if (!h)                                  /* a miss: the background */
        return;
    lc_ray_record *x = &g->r[rec];
    x->hit = 1;
    x->distance = h->t;
    x->point = h->p;
    x->normal = n;
    x->shape_kind = shape_kind_of_prim(PRIM_KIND(h->shape));
    x->shape = PRIM_INDEX(h->shape);
    if (PRIM_KIND(h->shape) == PRIM_TRIANGLE)
        x->shape = s->c.tris[x->shape].face;
    if (PRIM_KIND(h->shape) == PRIM_CSG_FACE || PRIM_KIND(h->shape) == PRIM_CSG_CUT)
        csg_name_hit(s->csgs[x->shape], h, x);
    x->material = h->material;
}

int explain_shadow(ray_log *g, lc_ray_kind kind, const ray *r, int light,
                   double distance)
{
    int rec = explain_ray(g, g->parent, kind, r);
    if (rec >= 0) {
        g->r[rec].light_kind = light < 0 ? LC_LIGHT_EMITTER : light >> 28;
        g->r[rec].light = light < 0 ? light : light & ((1 << 28) - 1);
        g->r[rec].distance = distance;
    }
    return rec;
}

void explain_visible(ray_log *g, int rec)
{
    if (rec >= 0)
        g->r[rec].hit = 1;
}

void explain_light(ray_log *g, int rec, const lc_material *m, radiance d, radiance sp)
{
    if (rec < 0)
        return;
    radiance c = rad(m->color), share;
    d = r_scale(d, m->kd);
    sp = r_scale(sp, m->ks);
    share = m->absorb == LC_ABSORB_ALL ? r_mul(c, r_add(d, sp)) : r_add(r_mul(c, d), sp);
    share = r_mul(g->w, share);
    g->r[rec].contribution = rgb((float)share.r, (float)share.g, (float)share.b);
}

void explain_add(ray_log *g, int rec, radiance add)
{
    if (rec < 0)
        return;
    double *o = g->own + 3 * rec;
    o[0] += add.r, o[1] += add.g, o[2] += add.b;
}

static int is_shadow(lc_ray_kind k) { return k == LC_RAY_SHADOW || k == LC_RAY_LIGHT; }

/* A ray is recorded after the one it leaves from, so from the last record
** back each subtree's sum is whole when its root is reached. */
void explain_finish(ray_log *g)
{
    if (g->failed)
        return;
    for (size_t i = g->n; i-- > 0;) {
        lc_ray_record *x = &g->r[i];
        if (is_shadow(x->kind))
            continue;
        double *o = g->own + 3 * i;
        x->contribution = rgb((float)o[0], (float)o[1], (float)o[2]);
        if (x->parent >= 0) {
            double *p = g->own + 3 * x->parent;
            p[0] += o[0], p[1] += o[1], p[2] += o[2];
        }
    }
}
