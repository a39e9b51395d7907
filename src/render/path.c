/* path.c: global illumination (render option indirect > 0): a path tracer
** over one energy-conserving BSDF mapped from the seed's coefficients, with
** next-event estimation toward every light and multiple importance
** sampling (the power heuristic) between light and BSDF sampling for the
** emitters and the sky that both can find; Russian roulette after a few
** bounces. Whitted's renderer (shade.c) is untouched: the render loop
** (render.c) comes here only when the compile step found LC_NEED_INDIRECT.
** The lights are light.h's, taken in by LIGHT_PATH; the BSDF is bsdf.h's.
**
** The BSDF at a hit of material m, its coefficients scaled by
** s = min(1, 1 / (kd + ks + kr + kt)) so that no material reflects more
** than it receives (T = colour when absorb = 'all', else 1):
**   diffuse    Lambert, albedo kd s colour:  f = kd s C / pi
**   highlight  normalised Phong of exponent alpha, albedo ks s T:
**              f = ks s T (alpha + 2) / (2 pi) max(0, R(v).l)^alpha
**   mirror     kr s T along the mirror direction (over the seed's cone
**              when glossiness > 0, uniform in its solid angle)
**   dielectric kt s T, Fresnel's F of it reflected, 1 - F refracted
** With these, a diffuse surface's direct light is Whitted's exactly:
** kd C Lc cos for a light colour Lc (point light I / d^2: radiant
** intensity pi I; a sun: irradiance E, Lc = E / pi). */
#include "material/dielectric.h"
#include "light/light.h"
#include "path.h"
#include "material/surface.h"

/* A direction around unit axis a with density (e + 1) / 2 pi cos^e: the
** Phong lobe, e = 1 being the cosine-weighted hemisphere's (times 2). */
static lc_vec3 sample_lobe(lc_vec3 a, double e, const double u[2])
{
    double c = pow(u[0], 1 / (e + 1)), sn = sqrt(fmax(0, 1 - c * c)), phi = 2 * PI * u[1];
    lc_vec3 b1, b2;
    sample_frame(a, &b1, &b2);
    return v3_norm(v3_madd(v3_madd(v3_mul(a, c), b1, sn * cos(phi)), b2, sn * sin(phi)));
}

/* Next-event estimation at a hit: every point, spot and directional light,
** one point of each emitter, one direction of the sky, each with its
** shadow ray (light_all); what they send back, times the path's weight beta. */
static radiance lights_at(tracer *t, const hit *h, const bsdf *b, radiance beta,
                          uint32_t index, uint32_t count, int depth)
{
    light_gather g;
    memset(&g, 0, sizeof g);
    g.use = LIGHT_PATH;
    g.how = t->needs & LC_NEED_FILTER ? SHADOW_FILTER : 0;
    g.lg = t->log;
    g.n = b->n;
    g.index = index;
    g.count = count;
    g.depth = depth;
    g.b = b;
    g.beta = beta;
    light_all(t, h, &g);
    return g.acc;
}

/* A reflection direction off the mirror direction rd: itself, or over the
** material's cone (folded above the surface, as the seed's cone is). */
static lc_vec3 mirror_direction(tracer *t, const lc_material *m, unsigned plan, lc_vec3 rd,
                                lc_vec3 n, int depth, uint32_t index, uint32_t count)
{
    if (!(plan & PLAN_GLOSSY))
        return rd;
    double u[2], half = m->glossiness * (PI / 360);
    sample_2d(&t->ps, sample_dim(DIM_CONE, (unsigned)depth, 0), index, count, u);
    lc_vec3 w = sample_cone(rd, 2 * sin(half) * sin(half), u);
    double c = v3_dot(w, n);
    return c < 0 ? v3_madd(w, n, -2 * c) : w;
}

/* Whether a path records its AOVs (t->aov): a constant in each variant of
** path_loop, so the plain one has none of their code. */
typedef enum { PATH_PLAIN, PATH_AOV } path_aovs;

/* One path being traced: where it is and what it carries. */
typedef struct {
    ray      r;
    media    md;
    radiance beta, L;
    uint32_t index, count;      /* the camera sample */
    int      rec;               /* the ray's explain record, or -1 */
    int      bounces, depth, specular_depth;
    int      smooth;            /* the last bounce was diffuse or a highlight ... */
    double   pdf_prev;          /* ... of this density ... */
    lc_vec3  p_prev, n_prev;    /* ... from here, ... */
    uint32_t from;              /* ... off this primitive */
    int      cls;               /* aov: the class of the light it brings */
} path_state;

/* Light the path brings: into its sum, the AOVs (aov, a constant) by the
** path's class, and explain's record. */
ALWAYS_INLINE void path_add(tracer *t, path_state *ps, radiance add, path_aovs aov)
{
    ps->L = r_add(ps->L, add);
    if (aov)
        aov_add(t->aov, ps->cls, add);
    if (t->log && ps->rec >= 0)
        explain_add(t->log, ps->rec, add);
}

/* The path leaves the scene: the sky it sees, weighed against the sky's
** light samples after a smooth bounce. */
ALWAYS_INLINE void path_miss(tracer *t, path_state *ps, path_aovs aov)
{
    const lc_scene *s = t->scene;
    if (ps->md.n)
        ps->beta = media_absorb(s, &ps->md, ps->beta, HUGE_VAL);
    double w = ps->smooth && t->nee && s->c.sky_lights
               ? bsdf_mis_power(ps->pdf_prev, light_sky_pdf(s, ps->r.d)) : 1;
    radiance add = r_mul(ps->beta, r_scale(sky_seen(s, ps->r.d), w));
    if (t->log && ps->rec >= 0)
        explain_hit(t->log, s, ps->rec, NULL, ps->r.d, ps->beta);
    path_add(t, ps, add, aov);
}

/* What the emissive surface m the path met at h sends back along it,
** weighed against the emitter's light samples after a smooth bounce. */
static radiance path_emission(const tracer *t, const path_state *ps, const hit *h,
                              const lc_material *m)
{
    const lc_scene *s = t->scene;
    double w = 1;
    if (ps->smooth && t->nee) {
        const emitter *e = light_emitter_of(s, h->shape);
        if (e && e->prim != ps->from) {      /* an emitter never samples itself */
            double pl = light_emitter_pdf(s, e, ps->p_prev, ps->n_prev, ps->r.d, h->t);
            w = pl < 0 ? 0 : bsdf_mis_power(ps->pdf_prev, pl);
        }
    }
    return r_mul(ps->beta, r_scale(rad(m->emission), w));
}

/* The next bounce off a diffuse or highlight lobe: its direction *d, the
** path's weight and MIS state after it. 0: the sample went under the
** surface, the path ends. */
static int path_smooth_bounce(tracer *t, path_state *ps, const hit *h, const bsdf *b,
                              int lobe, lc_vec3 *d)
{
    double u[2];
    sample_2d(&t->ps, sample_dim(DIM_BSDF, (unsigned)ps->depth, 0), ps->index, ps->count,
              u);
    *d = lobe == LOBE_DIFFUSE ? sample_lobe(b->n, 1, u) : sample_lobe(b->rv, b->alpha, u);
    double pdf;
    radiance f = bsdf_eval(b, *d, &pdf);
    if (!(pdf > 0))
        return 0;
    ps->beta = r_mul(ps->beta, r_scale(f, v3_dot(b->n, *d) / pdf));
    ps->smooth = 1;
    ps->pdf_prev = pdf;
    ps->p_prev = h->p;
    ps->n_prev = b->n;
    ps->from = h->shape;
    ps->bounces++;
    return 1;
}

/* The next bounce off the mirror or dielectric lobe: its direction *d and
** the path's weight (and media) after it; returns the new ray's kind. rest:
** what is left of the lobe's pick, in [0, 1), chooses between the
** dielectric's reflection and refraction. */
static lc_ray_kind path_delta_bounce(tracer *t, path_state *ps, const hit *h,
                                     const lc_material *m, unsigned plan, const bsdf *b,
                                     int lobe, double rest, lc_vec3 *d)
{
    const lc_scene *s = t->scene;
    lc_vec3 n = b->n, rd = v3_norm(v3_madd(ps->r.d, n, -2 * v3_dot(ps->r.d, n)));
    ps->smooth = 0;
    ps->specular_depth++;
    if (lobe == LOBE_MIRROR) {
        *d = mirror_direction(t, m, plan, rd, n, ps->depth, ps->index, ps->count);
        ps->beta = r_mul(ps->beta, r_scale(b->wr, 1 / b->p[LOBE_MIRROR]));
        return plan & PLAN_GLOSSY ? LC_RAY_GLOSSY : LC_RAY_REFLECTION;
    }
    media past;
    double n1 = 1, n2 = 1;
    media_cross(s, &ps->md, (uint32_t)h->material, v3_dot(ps->r.d, h->n) < 0, &past, &n1,
                &n2);
    double eta = n2 / n1;
    lc_vec3 td;
    int through = dielectric_refract(ps->r.d, n, eta, &td);
    if (through && !(v3_dot(td, h->n) * v3_dot(ps->r.d, h->n) > 0))
        through = 0;                 /* an interpolated normal bent it back */
    double F = !through ? 1 : m->fresnel ? dielectric_fresnel(-v3_dot(ps->r.d, n), eta) : 0;
    ps->beta = r_mul(ps->beta, r_scale(b->wt, 1 / b->p[LOBE_DIELECTRIC]));
    if (rest < F) {
        *d = mirror_direction(t, m, plan, rd, n, ps->depth, ps->index, ps->count);
        return LC_RAY_REFLECTION;
    }
    *d = td;
    ps->md = past;
    return LC_RAY_REFRACTION;
}

/* After the light at h: the next bounce, a lobe in proportion to its
** weight, then Russian roulette. Returns 0 when the path ends, else 1 with
** the path's ray the next one. */
ALWAYS_INLINE int path_bounce(tracer *t, path_state *ps, const hit *h, const lc_material *m,
                              unsigned plan, const bsdf *b, path_aovs aov)
{
    double ur[2];
    sample_2d(&t->ps, sample_dim(DIM_PATH, (unsigned)ps->depth, 0), ps->index, ps->count, ur);
    double pick = ur[0];
    int lobe = 0;
    while (lobe < 3 && pick >= b->p[lobe]) {
        pick -= b->p[lobe];
        lobe++;
    }
    if (!(b->p[lobe] > 0))
        return 0;                                /* black: the path ends */
    double rest = fmin(pick / b->p[lobe], BELOW_ONE);   /* for the dielectric */
    lc_ray_kind kind;
    lc_vec3 d;
    if (lobe <= LOBE_HIGHLIGHT) {
        if (!path_smooth_bounce(t, ps, h, b, lobe, &d))
            return 0;                            /* a highlight sample under the surface */
        if (aov && ps->cls == AOV_CAMERA)
            ps->cls = AOV_INDIRECT;
        kind = LC_RAY_INDIRECT;
    } else {
        if (ps->specular_depth >= t->max_depth)
            return 0;
        kind = path_delta_bounce(t, ps, h, m, plan, b, lobe, rest, &d);
        if (aov && ps->cls == AOV_CAMERA)
            ps->cls = kind == LC_RAY_REFRACTION ? AOV_REFRACTION : AOV_REFLECTION;
    }
    ps->depth++;
    /* Russian roulette: a path of little weight goes on with probability
    ** q and is weighed 1 / q when it does, which keeps the mean. */
    if (t->roulette && ps->depth >= LC_ROULETTE_DEPTH) {
        double q = fmin(0.95, r_max(ps->beta));
        if (!(ur[1] < q))
            return 0;
        ps->beta = r_scale(ps->beta, 1 / q);
    }
    if (!(r_max(ps->beta) > 0))
        return 0;
    ps->r.o = spawn_origin(h, d);
    ps->r.d = d;
    t->rays[kind]++;
    if (t->log && ps->rec >= 0)
        ps->rec = explain_ray(t->log, ps->rec, kind, &ps->r);
    return 1;
}

/* The light at hit h of material m: its emission and, where the BSDF is
** smooth, next-event estimation; into the path's sum (and at the first
** hit, the AOVs' emission and direct). */
ALWAYS_INLINE void path_light(tracer *t, path_state *ps, const hit *h, const bsdf *b,
                              radiance own, path_aovs aov)
{
    if (t->needs & LC_NEED_FILTER)
        t->media = &ps->md;
    if (aov && ps->cls == AOV_CAMERA)
        aov_add(t->aov, AOV_EMISSION, own);
    if (t->nee && bsdf_smooth(b)) {
        radiance lit = lights_at(t, h, b, ps->beta, ps->index, ps->count, ps->depth);
        if (aov && ps->cls == AOV_CAMERA)
            aov_add(t->aov, AOV_DIRECT, lit);
        own = r_add(own, lit);
    }
    ps->L = r_add(ps->L, own);
    if (aov && ps->cls != AOV_CAMERA)
        aov_add(t->aov, ps->cls, own);
    if (t->log && ps->rec >= 0)
        explain_add(t->log, ps->rec, own);
}

/* One path; with PATH_AOV (path_ray's variant for TRACE_AOV), its light also goes
** to t->aov by class: at the first hit, emission and direct; after it, the
** class of the first bounce's lobe (diffuse and highlight: indirect). */
ALWAYS_INLINE radiance path_loop(tracer *t, const ray *r0, uint32_t index, uint32_t count,
                                 int rec, path_aovs aov)
{
    const lc_scene *s = t->scene;
    path_state ps;
    memset(&ps, 0, sizeof ps);
    ps.r = *r0;
    ps.beta.r = ps.beta.g = ps.beta.b = 1;
    ps.index = index;
    ps.count = count;
    ps.rec = rec;
    ps.from = INTERSECT_SKIP_NONE;
    ps.cls = AOV_CAMERA;
    for (;;) {
        hit h;
        if (!intersect_closest(s, &ps.r, HUGE_VAL, &h, &t->counts)) {
            path_miss(t, &ps, aov);
            break;
        }
        if (ps.md.n)
            ps.beta = media_absorb(s, &ps.md, ps.beta, h.t);
        const lc_material *m = &s->materials[h.material];
        unsigned plan = t->plan[h.material];
        lc_material textured;
        if (plan & PLAN_TEXTURED)
            m = surface_material(s, &h, m, &textured);
        lc_vec3 n = v3_dot(h.n, ps.r.d) > 0 ? v3_neg(h.ns) : h.ns;
        if ((plan & PLAN_REFRACT) && !ps.md.n && v3_dot(ps.r.d, h.n) > 0)
            ps.beta = media_adopt(s, &ps.md, (uint32_t)h.material, ps.beta, h.t);
        if (plan & PLAN_REFRACT) {
            media past;
            double n1, n2;
            if (!media_cross(s, &ps.md, (uint32_t)h.material, v3_dot(ps.r.d, h.n) < 0, &past,
                             &n1, &n2)) {
                ps.r.o = spawn_origin(&h, ps.r.d);   /* no surface here: straight on */
                ps.md = past;
                continue;
            }
        }
        if (t->log && ps.rec >= 0)
            explain_hit(t->log, s, ps.rec, &h, n, ps.beta);
        if (aov && ps.cls == AOV_CAMERA)
            aov_first_hit(t, &h, m, n);
        radiance own = {0, 0, 0};
        if (plan & PLAN_EMITS)
            own = path_emission(t, &ps, &h, m);
        if (ps.bounces > t->indirect) {
            path_add(t, &ps, own, aov);
            break;
        }
        bsdf b = bsdf_of(m, plan, n, v3_neg(ps.r.d));
        path_light(t, &ps, &h, &b, own, aov);
        if (!path_bounce(t, &ps, &h, m, plan, &b, aov))
            break;
    }
    return ps.L;
}

radiance path_ray(tracer *t, const ray *r, uint32_t index, uint32_t count)
{
    if (t->log)
        return path_loop(t, r, index, count, explain_ray(t->log, -1, LC_RAY_CAMERA, r),
                         PATH_PLAIN);
    if (t->needs & TRACE_AOV)
        return path_loop(t, r, index, count, -1, PATH_AOV);
    return path_loop(t, r, index, count, -1, PATH_PLAIN);
}
