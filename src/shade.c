/* shade.c: the seed's shading model (Phong with recursive mirrors) at a hit. */
#include <stdlib.h>
#include <string.h>
#include "shade.h"

#define PI 3.14159265358979323846

typedef struct {
    radiance diffuse;     /* sum of Lc * (n.l) */
    radiance specular;    /* sum of Lc * (R.V)^alpha */
} light_sum;

static double cap(double x) { return x < RADIANCE_CAP ? x : RADIANCE_CAP; }
static radiance rad(lc_color c) { radiance r = {c.r, c.g, c.b}; return r; }
static radiance r_scale(radiance a, double k)
{
    radiance r = {cap(a.r * k), cap(a.g * k), cap(a.b * k)};
    return r;
}
static radiance r_add(radiance a, radiance b)
{
    radiance r = {cap(a.r + b.r), cap(a.g + b.g), cap(a.b + b.b)};
    return r;
}
static radiance r_mul(radiance a, radiance b)
{
    radiance r = {cap(a.r * b.r), cap(a.g * b.g), cap(a.b * b.b)};
    return r;
}

int log_ray(tracer *t, int parent, lc_ray_kind kind, const lc_ray *r)
{
    ray_log *g = t->log;
    if (g->failed)
        return -1;
    if (g->n == g->cap) {
        size_t nc = g->cap ? 2 * g->cap : 64;
        lc_ray_record *p = realloc(g->r, nc * sizeof *p);
        if (p)
            g->r = p;
        double *b = p ? realloc(g->before, 3 * nc * sizeof *b) : NULL;
        if (!b) {
            g->failed = 1;
            return -1;
        }
        g->before = b;
        g->cap = nc;
    }
    lc_ray_record *x = &g->r[g->n];
    memset(x, 0, sizeof *x);
    x->parent = parent;
    x->kind = kind;
    x->origin = r->o;
    x->direction = r->d;
    x->shape_kind = -1;
    x->shape = -1;
    x->material = -1;
    return (int)g->n++;
}

static void log_hit(tracer *t, int i, const lc_hit *h, lc_vec3 n)
{
    static const int kinds[] = {LC_SPHERE, LC_QUAD, LC_BOX, LC_SHAPE_KINDS, LC_PLANE};
    if (i < 0)
        return;
    lc_ray_record *x = &t->log->r[i];
    x->hit = 1;
    x->distance = h->t;
    x->point = h->p;
    x->normal = n;
    x->shape_kind = kinds[PRIM_KIND(h->shape)];
    x->shape = PRIM_INDEX(h->shape);
    if (PRIM_KIND(h->shape) == PRIM_TRIANGLE)
        x->shape = t->scene->c.tris[x->shape].face;
    x->material = h->material;
}

/* Adds one light of colour lc seen along unit l with n.l = cosl; while
** explaining, also records what it adds to the pixel on shadow record i. */
static void add_light(const tracer *t, const lc_material *m, unsigned plan, lc_vec3 n,
                      lc_vec3 v, lc_vec3 l, double cosl, radiance lc, light_sum *sum, int i)
{
    radiance d = r_scale(lc, t->cosine ? cosl : 1.0), sp = {0, 0, 0};
    sum->diffuse = r_add(sum->diffuse, d);
    if (plan & PLAN_SPECULAR) {
        lc_vec3 R = v3_sub(v3_mul(n, 2 * cosl), l);
        double rv = v3_dot(R, v);
        if (rv > 0) {
            sp = r_scale(lc, pow(rv, m->alpha));
            sum->specular = r_add(sum->specular, sp);
        }
    }
    if (i >= 0) {
        radiance c = rad(m->color), w = {t->w[0], t->w[1], t->w[2]}, share;
        d = r_scale(d, m->kd);
        sp = r_scale(sp, m->ks);
        share = m->absorb == LC_ABSORB_ALL ? r_mul(c, r_add(d, sp))
                                           : r_add(r_mul(c, d), sp);
        share = r_mul(w, share);
        t->log->r[i].contribution = rgb((float)share.r, (float)share.g, (float)share.b);
    }
}

static void point_lights(tracer *t, const lc_hit *h, const lc_material *m, unsigned plan,
                         lc_vec3 n, lc_vec3 v, light_sum *sum)
{
    const lc_scene *s = t->scene;
    double tooclose2 = 16 * v3_dot(h->perr, h->perr);
    for (size_t i = 0; i < s->nlights; i++) {
        const lc_point_light *L = &s->lights[i];
        lc_vec3 tol = v3_sub(L->position, h->p);
        double d2 = v3_dot(tol, tol);
        if (!(d2 > tooclose2))      /* light on the point itself: no direction */
            continue;
        double d = sqrt(d2);
        lc_vec3 l = v3_mul(tol, 1.0 / d);
        double cosl = v3_dot(n, l);
        if (!(cosl > 0))            /* behind the surface: no shadow ray at all */
            continue;
        /* From the offset origin along l: the offset is a few ulps of |p|,
        ** far inside SHADOW_SHORTEN, so the ray still stops short of L. */
        int rec = -1;
        if (t->shadows) {
            lc_ray sr = {spawn_origin(h, l), l};
            t->rays[LC_RAY_SHADOW]++;
            if (t->log) {
                rec = log_ray(t, t->parent, LC_RAY_SHADOW, &sr);
                if (rec >= 0) {
                    t->log->r[rec].light = (int)i;
                    t->log->r[rec].distance = d;
                }
            }
            if (scene_occluded_n(t->scene, &sr, d * (1 - SHADOW_SHORTEN), &t->counts))
                continue;
            if (rec >= 0)
                t->log->r[rec].hit = 1;
        }
        double k = L->intensity;
        if (L->falloff == LC_FALLOFF_INVERSE_SQUARE)
            k /= d * d;
        add_light(t, m, plan, n, v, l, cosl, r_scale(rad(L->color), cap(k)), sum, rec);
    }
}

/* The seed's emissive shapes: visible when the ray toward the shape's centre
** meets the shape itself (or nothing) first. The light colour is E/(pi cos),
** E the irradiance of the whole shape seen from the point: exact for a
** sphere (pi L (r/d)^2 cos), projected area over d^2 for quads and boxes. */
static void emitters(tracer *t, const lc_hit *h, const lc_material *m, unsigned plan,
                     lc_vec3 n, lc_vec3 v, light_sum *sum)
{
    const lc_scene *s = t->scene;
    double tooclose = 4 * v3_len(h->perr);
    for (size_t i = 0; i < s->nemitters; i++) {
        const emitter *e = &s->emitters[i];
        if (e->shape == h->shape)
            continue;
        lc_vec3 tol = v3_sub(e->target, h->p);
        double d = v3_len(tol);
        if (!(d > tooclose))
            continue;
        lc_vec3 l = v3_mul(tol, 1.0 / d);
        double cosl = v3_dot(n, l);
        if (!(cosl > 0))
            continue;
        int rec = -1;
        if (t->shadows) {
            lc_ray sr;
            sr.o = spawn_origin(h, l);
            lc_vec3 so = v3_sub(e->target, sr.o);
            double sd = v3_len(so);
            sr.d = v3_mul(so, 1.0 / sd);
            t->rays[LC_RAY_SHADOW]++;
            if (t->log) {
                rec = log_ray(t, t->parent, LC_RAY_SHADOW, &sr);
                if (rec >= 0) {
                    t->log->r[rec].light = -1 - (int)i;
                    t->log->r[rec].distance = sd;
                }
            }
            lc_hit blk;
            if (scene_closest_n(t->scene, &sr, sd * (1 - SHADOW_SHORTEN), &blk, &t->counts) &&
                blk.shape != e->shape)
                continue;
            if (rec >= 0)
                t->log->r[rec].hit = 1;
        }
        double k;
        if (e->kind == LC_SPHERE) {
            k = (e->radius / d) * (e->radius / d);
        } else {
            double a = fabs(v3_dot(e->area[0], l));
            if (e->kind == LC_BOX)
                a += fabs(v3_dot(e->area[1], l)) + fabs(v3_dot(e->area[2], l));
            k = a / (PI * d * d);
        }
        if (k > 1)                  /* no shape gives more than its radiance */
            k = 1;
        add_light(t, m, plan, n, v, l, cosl, r_scale(rad(e->emission), k), sum, rec);
    }
}

/* The mirror chain is a loop, not a recursion: each bounce adds its own
** light times the product of the reflection weights before it, so any
** max_depth costs no stack. For absorb = 'all' (the seed) the weight
** includes the colour: colour * (... + kr * Cr) expands to that. */
static double max3(radiance c) { return max2(c.r, max2(c.g, c.b)); }

/* A ray that left primitive `from` away from its inside (or off a flat one)
** cannot meet it again: if it does, the spawn offset failed. */
static int cannot_return(const lc_hit *h, lc_vec3 w)
{
    unsigned k = PRIM_KIND(h->shape);
    return k == PRIM_QUAD || k == PRIM_PLANE || k == PRIM_TRIANGLE || v3_dot(w, h->n) > 0;
}

radiance trace_ray(tracer *t, const lc_ray *r0, int depth)
{
    lc_ray r = *r0;
    radiance acc = {0, 0, 0}, w = {1, 1, 1};
    uint32_t from = 0;
    int watch = 0;             /* the last spawn cannot return to `from` */
    int rec = t->log ? log_ray(t, -1, LC_RAY_CAMERA, &r) : -1;
    for (;;) {
        lc_hit h;
        if (rec >= 0) {        /* explain: the weight so far, for what follows */
            t->parent = rec;
            t->w[0] = w.r, t->w[1] = w.g, t->w[2] = w.b;
            double *b = t->log->before + 3 * rec;
            b[0] = acc.r, b[1] = acc.g, b[2] = acc.b;
        }
        if (!scene_closest_n(t->scene, &r, HUGE_VAL, &h, &t->counts)) {
            acc = r_add(acc, r_mul(w, rad(t->scene->settings.background)));
            break;
        }
        if (watch && h.shape == from)
            t->self_hits++;
        const lc_material *m = &t->scene->materials[h.material];
        unsigned plan = t->plan[h.material];
        lc_vec3 n = v3_dot(h.n, r.d) > 0 ? v3_neg(h.ns) : h.ns;  /* face the viewer */
        lc_vec3 v = v3_neg(r.d);
        if (rec >= 0)
            log_hit(t, rec, &h, n);

        light_sum sum = {{0, 0, 0}, {0, 0, 0}};
        if (plan & PLAN_LIGHTS) {
            if (t->needs & LC_NEED_SHADOW)
                point_lights(t, &h, m, plan, n, v, &sum);
            if (t->needs & LC_NEED_EMITTER)
                emitters(t, &h, m, plan, n, v, &sum);
        }

        radiance base = r_scale(sum.diffuse, m->kd);             /* kd Cd */
        if (plan & PLAN_AMBIENT)
            base = r_add(base, r_scale(rad(t->scene->settings.ambient), m->ka));
        radiance spec = r_scale(sum.specular, m->ks);            /* ks H^a Cs */
        radiance local, next, color = rad(m->color);
        if (m->absorb == LC_ABSORB_ALL) {     /* the seed: absorption after the sum */
            local = r_mul(color, r_add(base, spec));
            next = r_scale(r_mul(w, color), m->kr);
        } else {
            local = r_add(r_mul(color, base), spec);
            next = r_scale(w, m->kr);
        }
        if (plan & PLAN_EMITS)
            local = r_add(local, rad(m->emission));
        acc = r_add(acc, r_mul(w, local));
        if (!(plan & PLAN_REFLECT) || depth >= t->max_depth)
            break;
        /* Adaptive depth (POV-Ray's adc_bailout): a bounce that can add at
        ** most cutoff times what it sees is not traced. */
        if (max3(next) < t->cutoff) {
            t->rays[LC_RAY_CUT]++;
            break;
        }
        lc_vec3 rd = v3_madd(r.d, n, -2 * v3_dot(r.d, n));       /* kr Cr */
        r.o = spawn_origin(&h, rd);
        r.d = v3_norm(rd);
        t->rays[LC_RAY_REFLECTION]++;
        from = h.shape;
        watch = cannot_return(&h, rd);
        w = next;
        depth++;
        if (rec >= 0)
            rec = log_ray(t, rec, LC_RAY_REFLECTION, &r);
    }
    /* explain: each camera or reflection ray brought back everything added
    ** from its own hit on; it held the sum before that. */
    for (int i = rec; i >= 0 && t->log; i = t->log->r[i].parent) {
        lc_ray_record *x = &t->log->r[i];
        const double *b = t->log->before + 3 * i;
        if (x->kind == LC_RAY_SHADOW)
            continue;
        x->contribution = rgb((float)(acc.r - b[0]), (float)(acc.g - b[1]),
                              (float)(acc.b - b[2]));
    }
    return acc;
}
