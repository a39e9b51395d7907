/* shade.c: the seed's shading model (Phong with recursive mirrors) and
** dielectrics along a path: the loop over bounces, the branches a
** dielectric leaves it, the glossy split. The lights are light.h's (its
** LIGHT_SEED sums), explain's recorder in explain.c, the media in media.h. */
#include "material/dielectric.h"
#include "light/light.h"
#include "shade.h"
#include "material/surface.h"
#include "scene/sky.h"
#include "scene/intersect.h"

/* The needs that take the light loops out of line. */
#define LIGHTS_APART (LC_NEED_FILTER | LC_NEED_SPOT | LC_NEED_SUN)

/* The seed's gathering of the lights at a hit into sum. */
ALWAYS_INLINE light_gather seed_gather(const lc_material *m, unsigned plan, lc_vec3 n,
                                       lc_vec3 v, uint32_t index, uint32_t count,
                                       int depth, light_sum *sum, ray_log *lg)
{
    light_gather g;
    g.use = LIGHT_SEED;
    g.how = 0;
    g.lg = lg;
    g.n = n;
    g.index = index;
    g.count = count;
    g.depth = depth;
    g.m = m;
    g.plan = plan;
    g.v = v;
    g.sum = sum;
    return g;
}

/* Every light at a hit of a scene with glass that shadow rays cross, or
** with spot or directional lights (LIGHTS_APART), out of the path loop, so
** the loops of opaque scenes with point lights and emitters stay as they
** were (one test of the needs reaches here, the one glass took before).
** The filter is a constant in each of its two copies. */
NEVER_INLINE void lights_apart(tracer *t, const hit *h, const lc_material *m,
                               unsigned plan, lc_vec3 n, lc_vec3 v, uint32_t index,
                               uint32_t count, int depth, light_sum *sum, ray_log *lg)
{
    light_gather g = seed_gather(m, plan, n, v, index, count, depth, sum, lg);
    if (t->needs & LC_NEED_FILTER) {
        g.how = SHADOW_FILTER;
        light_all(t, h, &g);
    } else {
        light_all(t, h, &g);
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
                           int rec, const media *md);
/* The needs that take a path off trace_opaque (trace_special). */
#define TRACE_SPECIAL (LC_NEED_REFRACT | LC_NEED_AO | TRACE_AOV)
/* The needs without which trace_diffuse's loop draws an opaque scene. */
#define MIRRORS (LC_NEED_SPECULAR | LC_NEED_REFLECT | LC_NEED_GLOSSY)

/* Ambient occlusion (render option ao; Tachyon's): the share of ao_samples
** probes, cosine-weighted about n and stratified over the pixel's samples,
** that go ao_distance without meeting anything: the ambient light's
** visibility, cosine-weighted as the light it stands for would be. */
NEVER_INLINE double ambient_open(tracer *t, const hit *h, lc_vec3 n, const path *pa)
{
    uint32_t S = (uint32_t)t->ao_samples, all = sample_nested_count(pa->count, S), open = 0;
    for (uint32_t j = 0; j < S; j++) {
        double u[2];
        uint32_t idx = (uint32_t)(((uint64_t)pa->index * S + j) % all);
        sample_2d(&t->ps, sample_dim(DIM_AO, (unsigned)pa->depth, 0), idx, all, u);
        double c = sqrt(u[0]), sn = sqrt(1 - u[0]), phi = 2 * PI * u[1];
        lc_vec3 b1, b2;
        sample_frame(n, &b1, &b2);
        lc_vec3 d = v3_norm(v3_madd(v3_madd(v3_mul(n, c), b1, sn * cos(phi)), b2,
                                    sn * sin(phi)));
        ray pr = {spawn_origin(h, d), d};
        t->rays[LC_RAY_AO]++;
        open += !intersect_occluded(t->scene, &pr, t->ao_distance, &t->counts);
    }
    return (double)open / S;
}

/* The seed's diffusion cone, done right: M rays over the cone, stratified
** over all the pixel's cone rays, each weighted by its cosine with the
** normal, weights normalised to sum to 1 (as in the seed). Returns what the
** M sub-paths bring back, weighted by w. */
static radiance glossy_split(tracer *t, const hit *h, const lc_material *m, lc_vec3 n,
                             lc_vec3 axis, const path *pa, radiance w, int rec,
                             const media *md)
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
        acc = r_add(acc, trace_path(t, &r, next, 1, r_scale(w, c / total), sub, md));
    }
    return acc;
}

/* The class of a ray spawned off the camera's first hit toward d, where
** the camera ray came along r: refraction if it crosses the surface. */
static int aov_class(const hit *h, const ray *r, lc_vec3 d)
{
    return v3_dot(d, h->n) * v3_dot(r->d, h->n) > 0 ? AOV_REFRACTION : AOV_REFLECTION;
}

radiance shade_ray(tracer *t, const ray *r0, uint32_t index, uint32_t count)
{
    path pa = {index, count, 0, 0, 0, 0};
    radiance one = {1, 1, 1};
    static const media air;     /* a camera is in air */
    int rec = t->log ? explain_ray(t->log, -1, LC_RAY_CAMERA, r0) : -1;
    return trace_path(t, r0, pa, 0, one, rec, &air);
}

/* Room for a branch to wait in t->pending; NULL, counted as cut, when it
** is full (see BRANCH_MAX: never in practice). */
static branch *branch_wait(tracer *t)
{
    if (t->npending == BRANCH_MAX) {
        t->rays[LC_RAY_CUT]++;
        return NULL;
    }
    return &t->pending[t->npending++];
}

/* The ray that goes on from hit h along unit d, kind `kind`, of weight w,
** from depth `depth`, in media md; recorded from explain record rec. */
static void branch_set(tracer *t, branch *b, const hit *h, lc_vec3 d, radiance w,
                       int depth, const media *md, lc_ray_kind kind, int rec)
{
    b->r.o = spawn_origin(h, d);
    b->r.d = d;
    b->w = w;
    b->depth = depth;
    b->watch = cannot_return(h, d);
    b->from = h->shape;
    b->from_instance = h->instance;
    b->md = *md;
    t->rays[kind]++;
    b->rec = rec >= 0 ? explain_ray(t->log, rec, kind, &b->r) : -1;
}

/* A hit on a surface of a material with kt > 0, after its own light was
** added: what follows, between the indices n1 and n2 of the media either
** side. Fresnel (fresnel = true) reflects kr + kt F and refracts kt (1 - F),
** F the exact unpolarised reflectance; the seed's fixed kr and kt without
** it; past the critical angle F = 1, all of it reflected. Each weighs the
** path's w (times the colour when absorb = 'all'). The loop goes on with
** the heavier, returned in *go; the other waits in t->pending. A branch of
** weight 0 is not traced, one under the cutoff is counted as cut, and a
** first glossy hit splits its reflection into cone rays (what they bring
** is in *add). Returns 0 when the path ends here. Out of the loop: glass
** code there cost opaque scenes registers. */
NEVER_INLINE int dielectric_bounce(tracer *t, const hit *h, const lc_material *m,
                                   unsigned plan, const ray *r, lc_vec3 n, radiance w,
                                   const path *pa, int split, int rec, const media *md,
                                   radiance *add, branch *go)
{
    media past;
    double n1 = 1, n2 = 1;
    media_cross(t->scene, md, (uint32_t)h->material, v3_dot(r->d, h->n) < 0, &past, &n1,
                &n2);
    radiance tint = m->absorb == LC_ABSORB_ALL ? r_mul(w, rad(m->color)) : w;
    double eta = n2 / n1;
    lc_vec3 td;
    int through = dielectric_refract(r->d, n, eta, &td);
    double F = !through ? 1 : m->fresnel ? dielectric_fresnel(-v3_dot(r->d, n), eta) : 0;
    radiance wr = r_scale(tint, m->kr + m->kt * F), wt = {0, 0, 0};
    /* An interpolated normal can bend it back to the side it came from. */
    if (through && v3_dot(td, h->n) * v3_dot(r->d, h->n) > 0)
        wt = r_scale(tint, m->kt * (1 - F));
    int refract = r_max(wt) > 0, reflect = (plan & (PLAN_REFLECT | PLAN_GLOSSY)) &&
                                           r_max(wr) > 0;
    if (refract && r_max(wt) < t->cutoff) {
        t->rays[LC_RAY_CUT]++;
        refract = 0;
    }
    if (reflect && r_max(wr) < t->cutoff) {
        t->rays[LC_RAY_CUT]++;
        reflect = 0;
    }
    lc_vec3 rd = v3_madd(r->d, n, -2 * v3_dot(r->d, n));
    lc_ray_kind kind = LC_RAY_REFLECTION;
    if (reflect && (plan & PLAN_GLOSSY)) {
        lc_vec3 axis = v3_norm(rd);
        if (!split) {
            *add = glossy_split(t, h, m, n, axis, pa, wr, rec, md);
            reflect = 0;
        } else {
            double c = cone_sample(t, m, axis, n, pa->depth, pa->index, pa->count, &rd);
            if (c > 0)
                kind = LC_RAY_GLOSSY;
            else
                reflect = 0;
        }
    }
    if (reflect && refract && r_max(wt) > r_max(wr)) {
        branch *wait = branch_wait(t);     /* the reflection waits */
        if (wait)
            branch_set(t, wait, h, v3_norm(rd), wr, pa->depth + 1, md, kind, rec);
        reflect = 0;
    }
    if (refract && reflect) {
        branch *wait = branch_wait(t);     /* the refraction waits */
        if (wait)
            branch_set(t, wait, h, td, wt, pa->depth + 1, &past, LC_RAY_REFRACTION, rec);
        refract = 0;
    }
    if (refract)
        branch_set(t, go, h, td, wt, pa->depth + 1, &past, LC_RAY_REFRACTION, rec);
    else if (reflect)
        branch_set(t, go, h, v3_norm(rd), wr, pa->depth + 1, md, kind, rec);
    return refract || reflect;
}

/* A surface between a medium and itself: a sphere inside one of the same
** glass, the far wall of an overlap. Out of the loop, as above. */
NEVER_INLINE int no_interface(const lc_scene *s, const media *md, const hit *h,
                              const ray *r, media *past)
{
    double n1, n2;
    return !media_cross(s, md, (uint32_t)h->material, v3_dot(r->d, h->n) < 0, past, &n1,
                        &n2);
}

/* The variants of trace_loop: bits, each a constant in its caller. */
typedef enum {
    LOOP_GLASS  = 1,       /* dielectrics and media (LC_NEED_REFRACT) */
    LOOP_LOG    = 2,       /* explain's records */
    LOOP_AO     = 4,       /* ambient occlusion probes */
    LOOP_AOV    = 8,       /* a camera sample's AOVs (TRACE_AOV) */
    LOOP_MIRROR = 16       /* highlights, mirrors, cones (MIRRORS) */
} loop_flags;

/* A ray that left the scene: the background (or sky) it brings, w after
** the medium it was in. */
ALWAYS_INLINE radiance trace_miss(tracer *t, const ray *r, radiance w, const media *md,
                                  int rec, int cls, unsigned flags)
{
    const lc_scene *s = t->scene;
    if ((flags & LOOP_GLASS) && md->n)   /* inside a medium: nothing comes from infinity */
        w = media_absorb(s, md, w, HUGE_VAL);
    radiance bg = r_mul(w, t->needs & LC_NEED_SKY ? sky_radiance(s, r->d)
                                                  : rad(s->settings.background));
    if ((flags & LOOP_LOG) && rec >= 0) {
        explain_hit(t->log, s, rec, NULL, r->d, w);
        explain_add(t->log, rec, bg);
    }
    if (flags & LOOP_AOV)
        aov_add(t->aov, cls, bg);
    return bg;
}

/* The lights at hit h into *sum: the opaque scenes' loops inline, the
** rest apart (LIGHTS_APART). The light loops' explain record lg is NULL,
** a constant, unless explaining, so a render runs none of their recording
** tests (S7: 1 % of the trace). */
ALWAYS_INLINE void trace_lights(tracer *t, const hit *h, const lc_material *m,
                                unsigned plan, lc_vec3 n, lc_vec3 v, const path *pa,
                                const media *md, light_sum *sum, ray_log *lg)
{
    if (t->needs & LIGHTS_APART) {
        t->media = md;
        lights_apart(t, h, m, plan, n, v, pa->index, pa->count, pa->depth, sum, lg);
        return;
    }
    light_gather g = seed_gather(m, plan, n, v, pa->index, pa->count, pa->depth, sum, lg);
    if (t->needs & LC_NEED_SHADOW)
        light_points(t, h, &g);
    if (t->needs & LC_NEED_EMITTER)
        light_emitter_centres(t, h, &g);
    if (t->needs & LC_NEED_AREA)
        light_emitters(t, h, &g, (uint32_t)t->light_samples);
}

/* The seed's Phong at hit h of material m (plan its steps): the lights,
** ambient, highlights and emission, times the path's weight w; recorded
** for explain and the AOVs (cls: the path's class). */
ALWAYS_INLINE radiance trace_local(tracer *t, const hit *h, const lc_material *m,
                                   unsigned plan, lc_vec3 n, lc_vec3 v, const path *pa,
                                   radiance w, const media *md, int rec, int cls,
                                   unsigned flags)
{
    const lc_scene *s = t->scene;
    light_sum sum = {{0, 0, 0}, {0, 0, 0}};
    if (plan & PLAN_LIGHTS)
        trace_lights(t, h, m, plan, n, v, pa, md, &sum, flags & LOOP_LOG ? t->log : NULL);
    radiance base = r_scale(sum.diffuse, m->kd);             /* kd Cd */
    if (plan & PLAN_AMBIENT) {
        radiance amb = r_scale(rad(s->settings.ambient), m->ka);
        if ((flags & LOOP_AO) && (plan & PLAN_AO))
            amb = r_scale(amb, ambient_open(t, h, n, pa));
        base = r_add(base, amb);
    }
    /* Without highlights sum.specular is 0 and adding it changes no bit
    ** (base has no -0): a diffuse hit skips the sum, as it skips the
    ** weight of the reflection it does not trace (S7's parity). */
    int specular = (plan & PLAN_SPECULAR) != 0;
    radiance local, color = rad(m->color);
    if (m->absorb == LC_ABSORB_ALL)       /* the seed: absorption after the sum */
        local = r_mul(color, specular ? r_add(base, r_scale(sum.specular, m->ks)) : base);
    else if (specular)                                    /* ks H^a Cs */
        local = r_add(r_mul(color, base), r_scale(sum.specular, m->ks));
    else
        local = r_mul(color, base);
    radiance lit = local;
    if (plan & PLAN_EMITS)
        local = r_add(local, rad(m->emission));
    radiance own = r_mul(w, local);
    if ((flags & LOOP_LOG) && rec >= 0)
        explain_add(t->log, rec, own);
    if ((flags & LOOP_AOV) && cls != AOV_CAMERA) {
        aov_add(t->aov, cls, own);
    } else if (flags & LOOP_AOV) {
        aov_add(t->aov, AOV_DIRECT, r_mul(w, lit));
        if (plan & PLAN_EMITS)
            aov_add(t->aov, AOV_EMISSION, r_mul(w, rad(m->emission)));
    }
    return own;
}

/* A dielectric's bounce (dielectric_bounce) with the AOV classes of the
** branches it leaves; what a glossy split brought into *acc. Returns 0 when
** the path ends, else 1 with *go the branch to follow. */
ALWAYS_INLINE int trace_dielectric(tracer *t, const hit *h, const lc_material *m,
                                   unsigned plan, const ray *r, lc_vec3 n, radiance w,
                                   const path *pa, int split, int rec, const media *md,
                                   int *cls, radiance *acc, branch *go, unsigned flags)
{
    radiance add = {0, 0, 0};
    int before = t->npending;
    int on = dielectric_bounce(t, h, m, plan, r, n, w, pa, split, rec, md, &add, go);
    *acc = r_add(*acc, add);
    if (flags & LOOP_AOV) {
        aov_add(t->aov, *cls == AOV_CAMERA ? AOV_REFLECTION : *cls, add);
        for (int k = before; k < t->npending; k++)
            t->pending_cls[k] = (signed char)(*cls == AOV_CAMERA ?
                aov_class(h, r, t->pending[k].r.d) : *cls);
        if (on && *cls == AOV_CAMERA)
            *cls = aov_class(h, r, go->r.d);
    }
    return on;
}

/* The primitive a path's last ray left, which it cannot meet again when
** watch is set: apart from the path struct, whose address the sub-paths
** take, so that these stay in registers. */
typedef struct {
    uint32_t from, from_instance;
    int      watch;
} path_left;

/* A mirror or glossy bounce (kr) off h: the first glossy hit of a path
** that has not split splits (what the sub-paths bring into *acc); else the
** loop goes on along *r, of weight *w, having left *left. Returns 0 when
** the path ends. */
ALWAYS_INLINE int trace_reflect(tracer *t, const hit *h, const lc_material *m,
                                unsigned plan, lc_vec3 n, int split, ray *r, radiance *w,
                                path *pa, path_left *left, int *rec, int *cls,
                                const media *md, radiance *acc, unsigned flags)
{
    radiance next = m->absorb == LC_ABSORB_ALL ? r_scale(r_mul(*w, rad(m->color)), m->kr)
                                               : r_scale(*w, m->kr);
    /* Adaptive depth (POV-Ray's adc_bailout): a bounce that can add at
    ** most cutoff times what it sees is not traced. */
    if (r_max(next) < t->cutoff) {
        t->rays[LC_RAY_CUT]++;
        return 0;
    }
    lc_vec3 rd = v3_madd(r->d, n, -2 * v3_dot(r->d, n));     /* kr Cr */
    lc_ray_kind kind = LC_RAY_REFLECTION;
    if (plan & PLAN_GLOSSY) {
        lc_vec3 axis = v3_norm(rd);
        if (!split) {
            radiance g = glossy_split(t, h, m, n, axis, pa, next, *rec, md);
            *acc = r_add(*acc, g);
            if (flags & LOOP_AOV)
                aov_add(t->aov, *cls == AOV_CAMERA ? AOV_REFLECTION : *cls, g);
            return 0;
        }
        /* After the split, one cone ray per bounce, at the path's own place. */
        if (!(cone_sample(t, m, axis, n, pa->depth, pa->index, pa->count, &rd) > 0))
            return 0;
        kind = LC_RAY_GLOSSY;
    }
    r->o = spawn_origin(h, rd);
    r->d = v3_norm(rd);
    t->rays[kind]++;
    left->from = h->shape;
    left->from_instance = h->instance;
    left->watch = cannot_return(h, rd);
    *w = next;
    pa->depth++;
    if ((flags & LOOP_AOV) && *cls == AOV_CAMERA)
        *cls = AOV_REFLECTION;
    if ((flags & LOOP_LOG) && *rec >= 0)
        *rec = explain_ray(t->log, *rec, kind, r);
    return 1;
}

/* One path: a loop over bounces, so any max_depth costs no stack. Mirror
** bounces go on in the loop (and single cone rays once the path has split);
** the first glossy hit splits into M sub-paths, each a call of this (which
** never splits again: cost is linear in M, not M^depth). A dielectric
** gives two rays: the loop follows the heavier and keeps the other in
** t->pending, traced when the loop's path ends, so the tree costs one ray
** per branch and max_depth and cutoff bound every branch of it. Each
** bounce adds its own light times the product of the weights before it;
** for absorb = 'all' (the seed) the weight includes the colour: colour *
** (... + kr * Cr) expands to that. w: the path's weight in the pixel; rec:
** its first ray's explain record (-1 while rendering); md: the media its
** first ray is in. Compiled several ways (flags, LOOP_* constants, see
** trace_path): a scene without glass runs none of the glass code, a render
** none of explain's, not even their tests, and without LOOP_MIRROR (no
** highlights, mirrors or cones: MIRRORS) a diffuse scene none of theirs
** (S7: 1 440.6M -> 1 429.8M instructions, the same bits). With LOOP_AOV
** (a camera sample's path, TRACE_AOV), each bounce's light also goes to
** t->aov by its class: the first hit's own to direct and emission, the
** rest to the class of the first hit's branch it came by (the sums are the
** same). */
ALWAYS_INLINE radiance trace_loop(tracer *t, const ray *r0, path pa, int split,
                                  radiance w, int rec, const media *md0, unsigned flags)
{
    const lc_scene *s = t->scene;
    int glass = (flags & LOOP_GLASS) != 0, log = (flags & LOOP_LOG) != 0;
    ray r = *r0;
    radiance acc = {0, 0, 0};
    int mine = t->npending;    /* the branches under it are the caller's */
    path_left left = {pa.from, pa.from_instance, pa.watch};
    media md = *md0;
    const branch *b;           /* the branch the loop goes on with */
    branch go;
    int cls = AOV_CAMERA;      /* LOOP_AOV: the class of the path being followed */
    for (;;) {
        hit h;
        if (!intersect_closest(s, &r, HUGE_VAL, &h, &t->counts)) {
            acc = r_add(acc, trace_miss(t, &r, w, &md, rec, cls, flags));
            goto done;
        }
        if (glass && md.n)     /* inside a medium: what it absorbs on the way */
            w = media_absorb(s, &md, w, h.t);
        if (left.watch && h.shape == left.from && h.instance == left.from_instance)
            t->self_hits++;
        const lc_material *m = &s->materials[h.material];
        unsigned plan = t->plan[h.material];
        if (!(flags & LOOP_MIRROR))    /* the needs say no material has these bits */
            plan &= ~(unsigned)(PLAN_SPECULAR | PLAN_REFLECT | PLAN_GLOSSY);
        lc_material textured;
        if (plan & PLAN_TEXTURED)
            m = surface_material(s, &h, m, &textured);
        lc_vec3 n = v3_dot(h.n, r.d) > 0 ? v3_neg(h.ns) : h.ns;  /* face the viewer */
        if (glass && (plan & PLAN_REFRACT) && !md.n && v3_dot(r.d, h.n) > 0)
            w = media_adopt(s, &md, (uint32_t)h.material, w, h.t);
        if (glass && (plan & PLAN_REFRACT) && no_interface(s, &md, &h, &r, &go.md)) {
            /* No surface here, no bounce: the ray goes on at its depth. */
            if (log && rec >= 0)
                explain_hit(t->log, s, rec, &h, n, w);
            branch_set(t, &go, &h, r.d, w, pa.depth, &go.md, LC_RAY_REFRACTION, rec);
            b = &go;
            goto follow;
        }
        if (log && rec >= 0)
            explain_hit(t->log, s, rec, &h, n, w);
        if ((flags & LOOP_AOV) && cls == AOV_CAMERA)
            aov_first_hit(t, &h, m, n);
        acc = r_add(acc, trace_local(t, &h, m, plan, n, v3_neg(r.d), &pa, w, &md, rec, cls,
                                     flags));
        if (!(plan & (PLAN_REFLECT | PLAN_GLOSSY | (glass ? PLAN_REFRACT : 0))) ||
            pa.depth >= t->max_depth)
            goto done;
        if (glass && (plan & PLAN_REFRACT)) {
            if (!trace_dielectric(t, &h, m, plan, &r, n, w, &pa, split, rec, &md, &cls, &acc,
                                  &go, flags))
                goto done;
            b = &go;
            goto follow;
        }
        if (trace_reflect(t, &h, m, plan, n, split, &r, &w, &pa, &left, &rec, &cls, &md,
                          &acc, flags))
            continue;
    done:
        if (!glass || t->npending == mine)
            break;
        b = &t->pending[--t->npending];
        if (flags & LOOP_AOV)
            cls = t->pending_cls[t->npending];
    follow:
        r = b->r;
        w = b->w;
        pa.depth = b->depth;
        left.watch = b->watch;
        rec = b->rec;
        left.from = b->from;
        left.from_instance = b->from_instance;
        md = b->md;
    }
    return acc;
}

static radiance trace_opaque(tracer *t, const ray *r0, path pa, int split, radiance w,
                             int rec, const media *md)
{
    return trace_loop(t, r0, pa, split, w, rec, md, LOOP_MIRROR);
}

/* An opaque scene where no material has highlights, mirrors or cones
** (the needs LC_NEED_SPECULAR, _REFLECT, _GLOSSY off): the loop without
** their code. */
static radiance trace_diffuse(tracer *t, const ray *r0, path pa, int split, radiance w,
                              int rec, const media *md)
{
    return trace_loop(t, r0, pa, split, w, rec, md, 0);
}

static radiance trace_glass(tracer *t, const ray *r0, path pa, int split, radiance w,
                            int rec, const media *md)
{
    return trace_loop(t, r0, pa, split, w, rec, md, LOOP_GLASS | LOOP_MIRROR);
}

/* Ambient occlusion, glass or not (the glass code is behind plan bits). */
static radiance trace_ao(tracer *t, const ray *r0, path pa, int split, radiance w,
                         int rec, const media *md)
{
    return trace_loop(t, r0, pa, split, w, rec, md, LOOP_GLASS | LOOP_AO | LOOP_MIRROR);
}

static radiance trace_explain(tracer *t, const ray *r0, path pa, int split, radiance w,
                              int rec, const media *md)
{
    return trace_loop(t, r0, pa, split, w, rec, md,
                      LOOP_GLASS | LOOP_LOG | LOOP_AO | LOOP_MIRROR);
}

/* A camera sample's path with its AOVs recorded (glass and ambient
** occlusion behind their plan bits, as in trace_ao). */
static radiance trace_aov(tracer *t, const ray *r0, path pa, int split, radiance w,
                          int rec, const media *md)
{
    if (t->needs & LC_NEED_AO)
        return trace_loop(t, r0, pa, split, w, rec, md,
                          LOOP_GLASS | LOOP_AO | LOOP_AOV | LOOP_MIRROR);
    return trace_loop(t, r0, pa, split, w, rec, md, LOOP_GLASS | LOOP_AOV | LOOP_MIRROR);
}

/* The scenes with glass, ambient occlusion or AOVs share the one test of
** the needs that glass took before, so an opaque scene's path to
** trace_opaque is what it was (light that bounces is path.c's: render.c
** sends it there). A camera path with AOVs
** goes to the recording variants; the sub-paths it splits into (depth > 0)
** to the plain ones, what they bring back counted by their caller. */
NEVER_INLINE radiance trace_special(tracer *t, const ray *r0, path pa, int split,
                                    radiance w, int rec, const media *md)
{
    if ((t->needs & TRACE_AOV) && pa.depth == 0)
        return trace_aov(t, r0, pa, split, w, rec, md);
    if (t->needs & LC_NEED_AO)
        return trace_ao(t, r0, pa, split, w, rec, md);
    if (t->needs & LC_NEED_REFRACT)
        return trace_glass(t, r0, pa, split, w, rec, md);
    return trace_opaque(t, r0, pa, split, w, rec, md);
}

static radiance trace_path(tracer *t, const ray *r0, path pa, int split, radiance w,
                           int rec, const media *md)
{
    if (t->log)
        return trace_explain(t, r0, pa, split, w, rec, md);
    if (t->needs & TRACE_SPECIAL)
        return trace_special(t, r0, pa, split, w, rec, md);
    if (!(t->needs & MIRRORS))
        return trace_diffuse(t, r0, pa, split, w, rec, md);
    return trace_opaque(t, r0, pa, split, w, rec, md);
}
