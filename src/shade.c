/* shade.c: the seed's shading model (Phong with recursive mirrors) along a
** path: the mirror loop and the glossy split. The light loops are in
** shade_lights.h, explain's recorder in explain.c. */
#include "shade.h"
#include "shade_lights.h"

/* Where a path stands in the pixel's sample set: camera sample `index` of
** `count`, or a cone ray's place among all the pixel's cone rays. */
typedef struct {
    uint32_t index, count;
    int      depth;
    uint32_t from, from_instance;  /* the primitive the first ray left ... */
    int      watch;                /* ... which it cannot meet again */
} path;

static double max3(radiance c) { return max2(c.r, max2(c.g, c.b)); }

/* A ray that left primitive `from` away from its inside (or off a flat one)
** cannot meet it again: if it does, the spawn offset failed. */
static int cannot_return(const hit *h, lc_vec3 w)
{
    return prim_cannot_return(PRIM_KIND(h->shape), v3_dot(w, h->n) > 0);
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

static radiance trace_path(tracer *t, const ray *r0, path pa, int split, radiance w,
                           int rec);

/* The seed's diffusion cone, done right: M rays over the cone, stratified
** over all the pixel's cone rays, each weighted by its cosine with the
** normal, weights normalised to sum to 1 (as in the seed). Returns what the
** M sub-paths bring back, weighted by w. */
static radiance glossy_split(tracer *t, const hit *h, const lc_material *m, lc_vec3 n,
                             lc_vec3 axis, const path *pa, radiance w, int rec)
{
    uint32_t M = cone_count(t, m), count = sample_nested_count(pa->count, M);
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
        ray r = {spawn_origin(h, d), d};
        t->rays[LC_RAY_GLOSSY]++;
        int sub = rec >= 0 ? explain_ray(t->log, rec, LC_RAY_GLOSSY, &r) : -1;
        path next = {idx, count, pa->depth + 1, h->shape, h->instance, cannot_return(h, d)};
        acc = r_add(acc, trace_path(t, &r, next, 1, r_scale(w, c / total), sub));
    }
    return acc;
}

radiance shade_ray(tracer *t, const ray *r0, uint32_t index, uint32_t count)
{
    path pa = {index, count, 0, 0, 0, 0};
    radiance one = {1, 1, 1};
    int rec = t->log ? explain_ray(t->log, -1, LC_RAY_CAMERA, r0) : -1;
    return trace_path(t, r0, pa, 0, one, rec);
}

/* One path: a loop over mirror bounces (and single cone rays once the path
** has split), so any max_depth costs no stack; the first glossy hit splits
** into M sub-paths, each a call of this (which never splits again: cost is
** linear in M, not M^depth). Each bounce adds its own light times the
** product of the reflection weights before it; for absorb = 'all' (the
** seed) the weight includes the colour: colour * (... + kr * Cr) expands to
** that. w: the path's weight in the pixel; rec: its first ray's explain
** record (-1 while rendering). */
static radiance trace_path(tracer *t, const ray *r0, path pa, int split, radiance w,
                           int rec)
{
    const lc_scene *s = t->scene;
    ray r = *r0;
    radiance acc = {0, 0, 0};
    uint32_t from = pa.from, from_instance = pa.from_instance;
    int watch = pa.watch;      /* the last spawn cannot return to `from` */
    int first = rec;
    for (;;) {
        hit h;
        if (!intersect_closest(s, &r, HUGE_VAL, &h, &t->counts)) {
            if (rec >= 0)
                explain_hit(t->log, s, rec, NULL, r.d, w, acc);
            acc = r_add(acc, r_mul(w, rad(s->settings.background)));
            break;
        }
        if (watch && h.shape == from && h.instance == from_instance)
            t->self_hits++;
        const lc_material *m = &s->materials[h.material];
        unsigned plan = t->plan[h.material];
        lc_vec3 n = v3_dot(h.n, r.d) > 0 ? v3_neg(h.ns) : h.ns;  /* face the viewer */
        lc_vec3 v = v3_neg(r.d);
        if (rec >= 0)
            explain_hit(t->log, s, rec, &h, n, w, acc);

        light_sum sum = {{0, 0, 0}, {0, 0, 0}};
        if (plan & PLAN_LIGHTS) {
            if (t->needs & LC_NEED_SHADOW)
                point_lights(t, &h, m, plan, n, v, &sum);
            if (t->needs & LC_NEED_EMITTER)
                emitters(t, &h, m, plan, n, v, &sum);
            if (t->needs & LC_NEED_AREA)
                area_lights(t, &h, m, plan, n, v, pa.index, pa.count, pa.depth, &sum);
        }

        radiance base = r_scale(sum.diffuse, m->kd);             /* kd Cd */
        if (plan & PLAN_AMBIENT)
            base = r_add(base, r_scale(rad(s->settings.ambient), m->ka));
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
            rec = explain_ray(t->log, rec, kind, &r);
    }
    if (first >= 0)
        explain_path(t->log, first, rec, acc);
    return acc;
}
