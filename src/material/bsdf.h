/* bsdf.h: the path tracer's BSDF, mapped from the seed's coefficients.
** Static functions: path.c samples it, and next-event estimation (light.h)
** evaluates it toward every light. See path.c for the lobes. */
#ifndef LC_BSDF_H
#define LC_BSDF_H

#include "base/radiance.h"
#include "scene/scene.h"

typedef struct {
    radiance rd, rs;       /* diffuse and highlight albedos */
    radiance wr, wt;       /* mirror and dielectric weights */
    double   alpha;
    double   p[4];         /* lobe probabilities: diffuse, highlight, mirror, dielectric */
    lc_vec3  n, v, rv;     /* normal facing the viewer, toward the viewer, v mirrored */
} bsdf;

enum { LOBE_DIFFUSE, LOBE_HIGHLIGHT, LOBE_MIRROR, LOBE_DIELECTRIC };

static inline bsdf bsdf_of(const lc_material *m, unsigned plan, lc_vec3 n, lc_vec3 v)
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
static inline radiance bsdf_eval(const bsdf *b, lc_vec3 l, double *pdf)
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

static inline int bsdf_smooth(const bsdf *b)
{
    return b->p[LOBE_DIFFUSE] + b->p[LOBE_HIGHLIGHT] > 0;
}

/* The power heuristic (Veach 1997, beta = 2) for a sample of density a
** against another strategy of density b. */
static inline double bsdf_mis_power(double a, double b)
{
    double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0 ? a2 / (a2 + b2) : 0;
}

#endif
