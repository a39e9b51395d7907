/* shade.c: the seed's shading model (Phong with recursive mirrors) at a hit.
** The light loops (point lights, emitters, area lights) live here with the
** path loop they serve: moved to a file of their own they no longer inline
** into it, and B1 took 2.2 % more instructions (callgrind, 320x180). */
#include <stdlib.h>
#include <string.h>
#include "shade.h"

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
    if (i < 0)
        return;
    lc_ray_record *x = &t->log->r[i];
    x->hit = 1;
    x->distance = h->t;
    x->point = h->p;
    x->normal = n;
    x->shape_kind = shape_kind_of_prim(PRIM_KIND(h->shape));
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
        if (e->prim == h->shape)
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
                blk.shape != e->prim)
                continue;
            if (rec >= 0)
                t->log->r[rec].hit = 1;
        }
        double k = shape_light_centre(e->kind, shape_at(&s->shapes[e->kind], e->index), l, d);
        if (k > 1)                  /* no shape gives more than its radiance */
            k = 1;
        add_light(t, m, plan, n, v, l, cosl, r_scale(rad(e->emission), k), sum, rec);
    }
}

/* Where a path stands in the pixel's sample set: camera sample `index` of
** `count`, or a cone ray's place among all the pixel's cone rays. */
typedef struct {
    uint32_t index, count;
    int      depth;
    uint32_t from, from_instance;  /* the primitive the first ray left ... */
    int      watch;                /* ... which it cannot meet again */
} path;

/* Traces the shadow ray of an area-light sample toward emitter e along l,
** up to its sampled point (tmax); 1 if nothing else is in the way. Logs it
** while explaining. */
static int light_visible(tracer *t, const lc_hit *h, const emitter *e, int which,
                         lc_vec3 l, double tmax, int *rec)
{
    *rec = -1;
    if (!t->shadows)
        return 1;
    lc_ray sr = {spawn_origin(h, l), l};
    t->rays[LC_RAY_LIGHT]++;
    if (t->log) {
        *rec = log_ray(t, t->parent, LC_RAY_LIGHT, &sr);
        if (*rec >= 0) {
            t->log->r[*rec].light = -1 - which;
            t->log->r[*rec].distance = tmax;
        }
    }
    /* Any other shape in the way blocks it: an any-hit query, which skips
    ** the emitter itself (its own surface, rounded, must not shadow the
    ** point sampled on it: at 1e7 from the origin the rounding is as large
    ** as any relative shortening, H2). */
    if (scene_occluded_skip(t->scene, &sr, tmax, e->prim, &t->counts))
        return 0;
    if (*rec >= 0)
        t->log->r[*rec].hit = 1;
    return 1;
}

/* Emissive shapes as area lights (light_samples > 0): each hit takes S
** points per emitter, stratified over all the pixel's samples; spheres by
** solid angle (the cone they subtend), quads and boxes by area. Each sample
** adds L * cos / (pi pdf S), so that the sum is E / pi, the same convention
** as the centre-ray model (exact for an unshadowed sphere). */
static void area_lights(tracer *t, const lc_hit *h, const lc_material *m, unsigned plan,
                        lc_vec3 n, lc_vec3 v, const path *pa, light_sum *sum)
{
    const lc_scene *s = t->scene;
    uint32_t S = (uint32_t)t->light_samples, count = nested_count(pa->count, S);
    for (size_t i = 0; i < s->nemitters; i++) {
        const emitter *e = &s->emitters[i];
        if (e->prim == h->shape)
            continue;
        const void *geom = shape_at(&s->shapes[e->kind], e->index);
        light_setup ls;
        if (!shape_light_begin(e->kind, geom, h->p, n, &ls))
            continue;
        for (uint32_t j = 0; j < S; j++) {
            double u[2];
            light_sample ps;
            uint32_t idx = (uint32_t)(((uint64_t)pa->index * S + j) % count);
            sample_2d(&t->ps, sample_dim(DIM_LIGHT, (unsigned)pa->depth, (unsigned)i), idx,
                      count, u);
            if (!shape_light_sample(e->kind, geom, &ls, h->p, u, S, &ps))
                continue;
            lc_vec3 l = ps.l;
            double k = ps.k, dist = ps.dist;
            double cosl = v3_dot(n, l);
            if (!(cosl > 0) || !(k > 0))
                continue;
            int rec;
            if (!light_visible(t, h, e, (int)i, l, dist, &rec))
                continue;
            add_light(t, m, plan, n, v, l, cosl, r_scale(rad(e->emission), cap(k)), sum, rec);
        }
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
    return prim_flat(PRIM_KIND(h->shape)) || v3_dot(w, h->n) > 0;
}

/* The number of rays a glossy hit splits into. */
static uint32_t cone_count(const tracer *t, const lc_material *m)
{
    return (uint32_t)(t->cone_samples > 0 ? t->cone_samples : m->cone_samples);
}

/* Cone direction `index` of `count` around unit axis a, folded above the
** surface: a sample under the tangent plane is mirrored about it (so none
** is traced into the surface and the lobe keeps its energy: H21(d), H24).
** Returns its cosine with n (0: exactly in the plane, not traced). */
static double cone_sample(tracer *t, const lc_material *m, lc_vec3 a, lc_vec3 n,
                          int depth, uint32_t index, uint32_t count, lc_vec3 *d)
{
    double u[2], half = m->glossiness * (PI / 360);    /* half the half-angle */
    double omc = 2 * sin(half) * sin(half);            /* 1 - cos, no cancellation */
    sample_2d(&t->ps, sample_dim(DIM_CONE, (unsigned)depth, 0), index, count, u);
    lc_vec3 w = sample_cone(a, omc, u);
    double c = v3_dot(w, n);
    if (c < 0) {
        w = v3_madd(w, n, -2 * c);
        c = -c;
    }
    *d = w;
    return c;
}

static radiance trace_path(tracer *t, const lc_ray *r0, path pa, int split, radiance w0,
                           int rec);

/* The seed's diffusion cone, done right: M rays over the cone, stratified
** over all the pixel's cone rays, each weighted by its cosine with the
** normal, weights normalised to sum to 1 (as in the seed). Returns what the
** M sub-paths bring back, weighted by w. */
static radiance glossy_split(tracer *t, const lc_hit *h, const lc_material *m, lc_vec3 n,
                             lc_vec3 axis, const path *pa, radiance w, int rec)
{
    uint32_t M = cone_count(t, m), count = nested_count(pa->count, M);
    radiance acc = {0, 0, 0};
    double total = 0;
    lc_vec3 d;
    for (uint32_t j = 0; j < M; j++)         /* first the sum of the weights */
        total += cone_sample(t, m, axis, n, pa->depth, (uint32_t)(((uint64_t)pa->index * M + j)
                             % count), count, &d);
    if (!(total > 0))
        return acc;
    for (uint32_t j = 0; j < M; j++) {
        uint32_t idx = (uint32_t)(((uint64_t)pa->index * M + j) % count);
        double c = cone_sample(t, m, axis, n, pa->depth, idx, count, &d);
        if (!(c > 0))
            continue;
        lc_ray r = {spawn_origin(h, d), d};
        t->rays[LC_RAY_GLOSSY]++;
        int sub = rec >= 0 ? log_ray(t, rec, LC_RAY_GLOSSY, &r) : -1;
        path next = {idx, count, pa->depth + 1, h->shape, h->instance, cannot_return(h, d)};
        acc = r_add(acc, trace_path(t, &r, next, 1, r_scale(w, c / total), sub));
    }
    return acc;
}

radiance trace_ray(tracer *t, const lc_ray *r0, uint32_t index, uint32_t count)
{
    path pa = {index, count, 0, 0, 0, 0};
    radiance one = {1, 1, 1};
    int rec = t->log ? log_ray(t, -1, LC_RAY_CAMERA, r0) : -1;
    return trace_path(t, r0, pa, 0, one, rec);
}

/* One path: a loop over mirror bounces (and single cone rays once the path
** has split), so any max_depth costs no stack; the first glossy hit splits
** into M sub-paths, each a call of this (which never splits again: cost is
** linear in M, not M^depth). w0: the path's weight in the pixel; rec: its
** first ray's explain record. */
static radiance trace_path(tracer *t, const lc_ray *r0, path pa, int split, radiance w,
                           int rec)
{
    lc_ray r = *r0;
    radiance acc = {0, 0, 0};
    uint32_t from = pa.from, from_instance = pa.from_instance;
    int watch = pa.watch;      /* the last spawn cannot return to `from` */
    int first = rec;
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
        if (watch && h.shape == from && h.instance == from_instance)
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
            if (t->needs & LC_NEED_AREA)
                area_lights(t, &h, m, plan, n, v, &pa, &sum);
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
        if (!(plan & (PLAN_REFLECT | PLAN_GLOSSY)) || pa.depth >= t->max_depth)
            break;
        /* Adaptive depth (POV-Ray's adc_bailout): a bounce that can add at
        ** most cutoff times what it sees is not traced. */
        if (max3(next) < t->cutoff) {
            t->rays[LC_RAY_CUT]++;
            break;
        }
        lc_vec3 rd = v3_madd(r.d, n, -2 * v3_dot(r.d, n));       /* kr Cr */
        lc_ray_kind kind = LC_RAY_REFLECTION;
        if (plan & PLAN_GLOSSY) {
            lc_vec3 axis = v3_norm(rd);
            if (!split) {
                acc = r_add(acc, glossy_split(t, &h, m, n, axis, &pa, next, rec));
                break;
            }
            /* After the split, one cone ray per bounce, at the path's own place. */
            if (!(cone_sample(t, m, axis, n, pa.depth, pa.index, pa.count, &rd) > 0))
                break;
            kind = LC_RAY_GLOSSY;
        }
        r.o = spawn_origin(&h, rd);
        r.d = v3_norm(rd);
        t->rays[kind]++;
        from = h.shape;
        from_instance = h.instance;
        watch = cannot_return(&h, rd);
        w = next;
        pa.depth++;
        if (rec >= 0)
            rec = log_ray(t, rec, kind, &r);
    }
    /* explain: each camera, reflection or cone ray brought back everything
    ** added from its own hit on; it held the sum before that. */
    for (int i = rec; i >= 0 && t->log; i = t->log->r[i].parent) {
        lc_ray_record *x = &t->log->r[i];
        const double *b = t->log->before + 3 * i;
        if (x->kind != LC_RAY_SHADOW && x->kind != LC_RAY_LIGHT)
            x->contribution = rgb((float)(acc.r - b[0]), (float)(acc.g - b[1]),
                                  (float)(acc.b - b[2]));
        if (i == first)
            break;
    }
    return acc;
}
