/* path.c: global illumination (render option indirect > 0): a path tracer
** over one energy-conserving BSDF mapped from the seed's coefficients, with
** next-event estimation toward every light and multiple importance
** sampling (the power heuristic) between light and BSDF sampling for the
** emitters and the sky that both can find; Russian roulette after a few
** bounces. Whitted's renderer (shade.c) is untouched: a render reaches this
** file only when the compile step found LC_NEED_INDIRECT.
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
#include "dielectric.h"
#include "shade.h"
#include "sky.h"
#include "surface.h"
#include "shade_lights.h"

typedef struct {
    radiance rd, rs;       /* diffuse and highlight albedos */
    radiance wr, wt;       /* mirror and dielectric weights */
    double   alpha;
    double   p[4];         /* lobe probabilities: diffuse, highlight, mirror, dielectric */
    lc_vec3  n, v, rv;     /* normal facing the viewer, toward the viewer, v mirrored */
} bsdf;

enum { LOBE_DIFFUSE, LOBE_HIGHLIGHT, LOBE_MIRROR, LOBE_DIELECTRIC };

static bsdf bsdf_of(const lc_material *m, unsigned plan, lc_vec3 n, lc_vec3 v)
{
    bsdf b;
    double sum = m->kd + m->ks + m->kr + m->kt, sc = sum > 1 ? 1 / sum : 1;
    radiance c = rad(m->color), one = {1, 1, 1};
    radiance tint = m->absorb == LC_ABSORB_ALL ? c : one, zero = {0, 0, 0};
    b.rd = r_scale(c, m->kd * sc);
    b.rs = plan & PLAN_SPECULAR ? r_scale(tint, m->ks * sc) : zero;
    b.wr = plan & (PLAN_REFLECT | PLAN_GLOSSY) ? r_scale(tint, m->kr * sc) : zero;
    b.wt = plan & PLAN_REFRACT ? r_scale(tint, m->kt * sc) : zero;
    b.alpha = m->alpha;
    double a[4] = {r_max(b.rd), r_max(b.rs), r_max(b.wr), r_max(b.wt)}, total = 0;
    for (int k = 0; k < 4; k++)
        total += a[k] > 0 ? a[k] : 0;
    for (int k = 0; k < 4; k++)
        b.p[k] = total > 0 && a[k] > 0 ? a[k] / total : 0;
    b.n = n;
    b.v = v;
    b.rv = v3_sub(v3_mul(n, 2 * v3_dot(n, v)), v);
    return b;
}

/* The non-delta part (diffuse and highlight) toward unit l above the
** surface: f, and the density sampling it picks l with. */
static radiance bsdf_eval(const bsdf *b, lc_vec3 l, double *pdf)
{
    double c = v3_dot(b->n, l);
    radiance f = {0, 0, 0};
    *pdf = 0;
    if (!(c > 0))
        return f;
    f = r_scale(b->rd, 1 / PI);
    *pdf = b->p[LOBE_DIFFUSE] * c / PI;
    if (b->p[LOBE_HIGHLIGHT] > 0) {
        double rl = v3_dot(b->rv, l);
        if (rl > 0) {
            double lobe = pow(rl, b->alpha);
            f = r_add(f, r_scale(b->rs, (b->alpha + 2) / (2 * PI) * lobe));
            *pdf += b->p[LOBE_HIGHLIGHT] * (b->alpha + 1) / (2 * PI) * lobe;
        }
    }
    return f;
}

static int bsdf_smooth(const bsdf *b)
{
    return b->p[LOBE_DIFFUSE] + b->p[LOBE_HIGHLIGHT] > 0;
}

/* The power heuristic (Veach 1997, beta = 2) for a sample of density a
** against another strategy of density b. */
static double power(double a, double b)
{
    double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0 ? a2 / (a2 + b2) : 0;
}

/* A direction around unit axis a with density (e + 1) / 2 pi cos^e: the
** Phong lobe, e = 1 being the cosine-weighted hemisphere's (times 2). */
static lc_vec3 sample_lobe(lc_vec3 a, double e, const double u[2])
{
    double c = pow(u[0], 1 / (e + 1)), sn = sqrt(fmax(0, 1 - c * c)), phi = 2 * PI * u[1];
    lc_vec3 b1, b2;
    sample_frame(a, &b1, &b2);
    return v3_norm(v3_madd(v3_madd(v3_mul(a, c), b1, sn * cos(phi)), b2, sn * sin(phi)));
}

/* The emitter density next-event estimation gave direction d from point p
** (normal n) to the point at distance dist on emitter e; -1 when the kind's
** density is not known here (its light samples then take all the weight). */
static double emitter_pdf(const lc_scene *s, const emitter *e, lc_vec3 p, lc_vec3 n,
                          lc_vec3 d, double dist)
{
    const void *geom = shape_at(&s->shapes[e->kind], e->index);
    light_setup ls;
    if (e->kind == LC_SPHERE) {
        if (!shape_light_begin(e->kind, geom, p, n, &ls))
            return 0;
        return 1 / ls.sphere.solid;
    }
    if (e->kind == LC_QUAD) {
        const quad_geom *q = geom;
        if (!shape_light_begin(e->kind, geom, p, n, &ls))
            return 0;
        double c = fabs(v3_dot(q->un, d));
        return c > 0 ? dist * dist / (ls.quad.area * c) : 0;
    }
    return -1;
}

/* Whether next-event estimation's samples of emitter e are weighted
** against BSDF sampling (its density is known for both). */
static int emitter_mis(const emitter *e)
{
    return e->kind == LC_SPHERE || e->kind == LC_QUAD;
}

/* Next-event estimation at a hit: every point, spot and directional light,
** one point of each emitter, one direction of the sky, each with its
** shadow ray; what they send back, times the path's weight beta. */
static radiance lights_at(tracer *t, const hit *h, const bsdf *b, radiance beta,
                          uint32_t index, uint32_t count, int depth)
{
    const lc_scene *s = t->scene;
    radiance acc = {0, 0, 0};
    int filter = (t->needs & LC_NEED_FILTER) != 0, rec;
    double pdf;
    radiance f, tr;
    lc_vec3 n = b->n;
    double tooclose2 = too_close2(h);
    for (size_t i = 0; i < s->nlights; i++) {
        const lc_point_light *L = &s->lights[i];
        lc_vec3 l;
        double d, d2, c;
        if (!toward_light(h, n, L->position, tooclose2, &l, &d, &d2, &c))
            continue;
        f = bsdf_eval(b, l, &pdf);
        if (!(r_max(f) > 0) ||
            !shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, (int)i, INTERSECT_SKIP_NONE,
                        &rec, filter, &tr, 0, t->log))
            continue;
        double k = PI * L->intensity / (L->falloff == LC_FALLOFF_INVERSE_SQUARE ? d2 : 1);
        radiance e = r_scale(rad(L->color), radiance_cap(k * c));
        acc = r_add(acc, r_mul(r_mul(f, filter ? r_mul(e, tr) : e), beta));
    }
    for (size_t i = 0; i < s->nspots; i++) {
        const spot_light *L = &s->spots[i];
        lc_vec3 l;
        double d, d2, c;
        if (!toward_light(h, n, L->d.position, tooclose2, &l, &d, &d2, &c))
            continue;
        double share = spot_share(L, v3_neg(l));
        if (!(share > 0))
            continue;
        f = bsdf_eval(b, l, &pdf);
        if (!(r_max(f) > 0) ||
            !shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, EXPLAIN_SPOT(i), INTERSECT_SKIP_NONE,
                        &rec, filter, &tr, 0, t->log))
            continue;
        double k = PI * L->d.intensity * share /
                   (L->d.falloff == LC_FALLOFF_INVERSE_SQUARE ? d2 : 1);
        radiance e = r_scale(rad(L->d.color), radiance_cap(k * c));
        acc = r_add(acc, r_mul(r_mul(f, filter ? r_mul(e, tr) : e), beta));
    }
    for (size_t i = 0; i < s->nsuns; i++) {
        const sun_light *L = &s->suns[i];
        double c = v3_dot(n, L->to);
        if (!(c > 0))
            continue;
        f = bsdf_eval(b, L->to, &pdf);
        if (!(r_max(f) > 0) ||
            !shadow_ray(t, h, L->to, HUGE_VAL, NULL, LC_RAY_SHADOW, EXPLAIN_SUN(i),
                        INTERSECT_SKIP_NONE, &rec, filter, &tr, 1, t->log))
            continue;
        radiance e = r_scale(rad(L->d.color), radiance_cap(L->d.irradiance * c));
        acc = r_add(acc, r_mul(r_mul(f, filter ? r_mul(e, tr) : e), beta));
    }
    for (size_t i = 0; i < s->nemitters; i++) {
        const emitter *em = &s->emitters[i];
        if (em->prim == h->shape)
            continue;
        const void *geom = shape_at(&s->shapes[em->kind], em->index);
        light_setup ls;
        if (!shape_light_begin(em->kind, geom, h->p, n, &ls))
            continue;
        double u[2];
        light_sample ls1;
        sample_2d(&t->ps, sample_dim(DIM_LIGHT, (unsigned)depth, (unsigned)i), index, count, u);
        if (!shape_light_sample(em->kind, geom, &ls, h->p, u, 1, &ls1))
            continue;
        double c = v3_dot(n, ls1.l);
        if (!(c > 0) || !(ls1.k > 0))
            continue;
        f = bsdf_eval(b, ls1.l, &pdf);
        if (!(r_max(f) > 0) ||
            !shadow_ray(t, h, ls1.l, ls1.dist, NULL, LC_RAY_LIGHT, -1 - (int)i, em->prim,
                        &rec, filter, &tr, 0, t->log))
            continue;
        /* k = 1 / (pi pdf): the sample's light is L cos / pdf = pi k L cos. */
        double w = emitter_mis(em) ? power(1 / (PI * ls1.k), pdf) : 1;
        radiance e = r_scale(rad(em->emission), radiance_cap(PI * ls1.k * c * w));
        acc = r_add(acc, r_mul(r_mul(f, filter ? r_mul(e, tr) : e), beta));
    }
    if (t->scene->c.sky_lights) {
        double u[2];
        lc_vec3 l;
        sample_2d(&t->ps, sample_dim(DIM_PATH, (unsigned)depth, 2), index, count, u);
        double ps = sky_sample(&s->c.sky, u, &l);
        double c = v3_dot(n, l);
        if (ps > 0 && c > 0) {
            f = bsdf_eval(b, l, &pdf);
            if (r_max(f) > 0 &&
                shadow_ray(t, h, l, HUGE_VAL, NULL, LC_RAY_LIGHT, EXPLAIN_SKY,
                           INTERSECT_SKIP_NONE, &rec, filter, &tr, 1, t->log)) {
                radiance e = r_scale(sky_seen(s, l), c * power(ps, pdf) / ps);
                acc = r_add(acc, r_mul(r_mul(f, filter ? r_mul(e, tr) : e), beta));
            }
        }
    }
    return acc;
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

/* One path; with aov (a constant: path_radiance_aov), its light also goes
** to t->aov by class: at the first hit, emission and direct; after it, the
** class of the first bounce's lobe (diffuse and highlight: indirect). */
ALWAYS_INLINE radiance path_loop(tracer *t, const ray *r0, uint32_t index, uint32_t count,
                                 int rec, int aov)
{
    const lc_scene *s = t->scene;
    static const media air;
    media md = air;
    ray r = *r0;
    radiance beta = {1, 1, 1}, L = {0, 0, 0};
    int bounces = 0, depth = 0, specular_depth = 0;
    int smooth = 0;             /* the last bounce was diffuse or a highlight ... */
    double pdf_prev = 0;        /* ... of this density ... */
    lc_vec3 p_prev = {0, 0, 0}, n_prev = {0, 0, 0};   /* ... from here, ... */
    uint32_t from = INTERSECT_SKIP_NONE;              /* ... off this primitive */
    int cls = AOV_CAMERA;
    for (;;) {
        hit h;
        if (!intersect_closest(s, &r, HUGE_VAL, &h, &t->counts)) {
            if (md.n)
                beta = media_absorb(s, &md, beta, HUGE_VAL);
            double w = smooth && t->nee && s->c.sky_lights
                       ? power(pdf_prev, sky_pdf(&s->c.sky, r.d)) : 1;
            radiance add = r_mul(beta, r_scale(sky_seen(s, r.d), w));
            if (t->log && rec >= 0) {
                explain_hit(t->log, s, rec, NULL, r.d, beta);
                explain_add(t->log, rec, add);
            }
            L = r_add(L, add);
            if (aov)
                aov_add(t->aov, cls, add);
            break;
        }
        if (md.n)
            beta = media_absorb(s, &md, beta, h.t);
        const lc_material *m = &s->materials[h.material];
        unsigned plan = t->plan[h.material];
        lc_material textured;
        if (plan & PLAN_TEXTURED)
            m = surface_material(s, &h, m, &textured);
        lc_vec3 n = v3_dot(h.n, r.d) > 0 ? v3_neg(h.ns) : h.ns;
        lc_vec3 v = v3_neg(r.d);
        if ((plan & PLAN_REFRACT) && !md.n && v3_dot(r.d, h.n) > 0)
            beta = media_adopt(s, &md, (uint32_t)h.material, beta, h.t);
        if (plan & PLAN_REFRACT) {
            media past;
            double n1, n2;
            if (!media_cross(s, &md, (uint32_t)h.material, v3_dot(r.d, h.n) < 0, &past, &n1,
                             &n2)) {
                r.o = spawn_origin(&h, r.d);     /* no surface here: straight on */
                md = past;
                continue;
            }
        }
        if (t->log && rec >= 0)
            explain_hit(t->log, s, rec, &h, n, beta);
        if (aov && cls == AOV_CAMERA)
            aov_first_hit(t, &h, m, n);
        radiance own = {0, 0, 0};
        if (plan & PLAN_EMITS) {
            double w = 1;
            if (smooth && t->nee) {
                const emitter *e = NULL;
                for (size_t i = 0; i < s->nemitters && !e; i++)
                    if (s->emitters[i].prim == h.shape)
                        e = &s->emitters[i];
                if (e && e->prim != from) {      /* an emitter never samples itself */
                    double pl = emitter_pdf(s, e, p_prev, n_prev, r.d, h.t);
                    w = pl < 0 ? 0 : power(pdf_prev, pl);
                }
            }
            own = r_mul(beta, r_scale(rad(m->emission), w));
        }
        if (bounces > t->indirect) {
            L = r_add(L, own);
            if (aov)
                aov_add(t->aov, cls, own);
            if (t->log && rec >= 0)
                explain_add(t->log, rec, own);
            break;
        }
        bsdf b = bsdf_of(m, plan, n, v);
        if (t->needs & LC_NEED_FILTER)
            t->media = &md;
        if (aov && cls == AOV_CAMERA)
            aov_add(t->aov, AOV_EMISSION, own);
        if (t->nee && bsdf_smooth(&b)) {
            radiance lit = lights_at(t, &h, &b, beta, index, count, depth);
            if (aov && cls == AOV_CAMERA)
                aov_add(t->aov, AOV_DIRECT, lit);
            own = r_add(own, lit);
        }
        if (aov && cls != AOV_CAMERA)
            aov_add(t->aov, cls, own);
        L = r_add(L, own);
        if (t->log && rec >= 0)
            explain_add(t->log, rec, own);

        /* The next bounce: a lobe in proportion to its weight. */
        double u[2], ur[2];
        sample_2d(&t->ps, sample_dim(DIM_PATH, (unsigned)depth, 0), index, count, ur);
        double pick = ur[0];
        int lobe = 0;
        while (lobe < 3 && pick >= b.p[lobe]) {
            pick -= b.p[lobe];
            lobe++;
        }
        if (!(b.p[lobe] > 0))
            break;                               /* black: the path ends */
        double rest = fmin(pick / b.p[lobe], BELOW_ONE);   /* for the dielectric */
        lc_ray_kind kind;
        lc_vec3 d;
        if (lobe <= LOBE_HIGHLIGHT) {
            sample_2d(&t->ps, sample_dim(DIM_BSDF, (unsigned)depth, 0), index, count, u);
            d = lobe == LOBE_DIFFUSE ? sample_lobe(n, 1, u) : sample_lobe(b.rv, b.alpha, u);
            double pdf;
            radiance f = bsdf_eval(&b, d, &pdf);
            if (!(pdf > 0))
                break;                           /* a highlight sample under the surface */
            beta = r_mul(beta, r_scale(f, v3_dot(n, d) / pdf));
            smooth = 1;
            if (aov && cls == AOV_CAMERA)
                cls = AOV_INDIRECT;
            pdf_prev = pdf;
            p_prev = h.p;
            n_prev = n;
            from = h.shape;
            bounces++;
            kind = LC_RAY_INDIRECT;
        } else {
            if (specular_depth >= t->max_depth)
                break;
            lc_vec3 rd = v3_norm(v3_madd(r.d, n, -2 * v3_dot(r.d, n)));
            if (lobe == LOBE_MIRROR) {
                d = mirror_direction(t, m, plan, rd, n, depth, index, count);
                beta = r_mul(beta, r_scale(b.wr, 1 / b.p[LOBE_MIRROR]));
                kind = plan & PLAN_GLOSSY ? LC_RAY_GLOSSY : LC_RAY_REFLECTION;
            } else {
                media past;
                double n1 = 1, n2 = 1;
                media_cross(s, &md, (uint32_t)h.material, v3_dot(r.d, h.n) < 0, &past, &n1,
                            &n2);
                double eta = n2 / n1;
                lc_vec3 td;
                int through = dielectric_refract(r.d, n, eta, &td);
                if (through && !(v3_dot(td, h.n) * v3_dot(r.d, h.n) > 0))
                    through = 0;                 /* an interpolated normal bent it back */
                double F = !through ? 1 : m->fresnel ? dielectric_fresnel(-v3_dot(r.d, n), eta)
                                                     : 0;
                beta = r_mul(beta, r_scale(b.wt, 1 / b.p[LOBE_DIELECTRIC]));
                if (rest < F) {
                    d = mirror_direction(t, m, plan, rd, n, depth, index, count);
                    kind = LC_RAY_REFLECTION;
                } else {
                    d = td;
                    md = past;
                    kind = LC_RAY_REFRACTION;
                }
            }
            smooth = 0;
            specular_depth++;
            if (aov && cls == AOV_CAMERA)
                cls = kind == LC_RAY_REFRACTION ? AOV_REFRACTION : AOV_REFLECTION;
        }
        depth++;
        /* Russian roulette: a path of little weight goes on with probability
        ** q and is weighed 1 / q when it does, which keeps the mean. */
        if (t->roulette && depth >= LC_ROULETTE_DEPTH) {
            double q = fmin(0.95, r_max(beta));
            if (!(ur[1] < q))
                break;
            beta = r_scale(beta, 1 / q);
        }
        if (!(r_max(beta) > 0))
            break;
        r.o = spawn_origin(&h, d);
        r.d = d;
        t->rays[kind]++;
        if (t->log && rec >= 0)
            rec = explain_ray(t->log, rec, kind, &r);
    }
    return L;
}

radiance path_radiance(tracer *t, const ray *r0, uint32_t index, uint32_t count, int rec)
{
    return path_loop(t, r0, index, count, rec, 0);
}

radiance path_radiance_aov(tracer *t, const ray *r0, uint32_t index, uint32_t count)
{
    return path_loop(t, r0, index, count, -1, 1);
}
