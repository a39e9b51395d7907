/* light_point.h: point lights: toward one from a shaded point, what it
** brings, and the loop over a scene's point lights for both integrators. */
#ifndef LC_LIGHT_POINT_H
#define LC_LIGHT_POINT_H

#include "light_gather.h"

/* The squared distance within which a light sits on the point h itself. */
static inline double too_close2(const hit *h) { return 16 * v3_dot(h->perr, h->perr); }

/* From h toward a light at pos: the unit direction *l, the distance *d (its
** square *d2) and *cosl = n.l. 0 when the light sits on the point itself
** (d2 within tooclose2, too_close2's: no direction) or behind the surface
** (no shadow ray at all). Point and spot lights' sample. */
ALWAYS_INLINE int toward_light(const hit *h, lc_vec3 n, lc_vec3 pos, double tooclose2,
                               lc_vec3 *l, double *d, double *d2, double *cosl)
{
    lc_vec3 tol = v3_sub(pos, h->p);
    *d2 = v3_dot(tol, tol);
    if (!(*d2 > tooclose2))
        return 0;
    *d = sqrt(*d2);
    *l = v3_mul(tol, 1.0 / *d);
    *cosl = v3_dot(n, *l);
    return *cosl > 0;
}

/* What a light of colour c and intensity k (falloff f, share of it this
** way: a spot's cone, 1 for a point light) at distance d (d2 its square,
** n.l = cosl) brings, in use's convention: the seed's light colour
** c k share / d^2, capped; for paths the irradiance times the cosine,
** pi k share c cos / d^2 (radiant intensity pi k), capped. Point and spot
** lights' eval, each convention rounded as it always was. */
ALWAYS_INLINE radiance light_point_eval(light_use use, lc_color c, double k, double share,
                                        lc_falloff f, double d, double d2, double cosl)
{
    if (use == LIGHT_SEED) {
        k *= share;
        if (f == LC_FALLOFF_INVERSE_SQUARE)
            k /= d * d;
        return r_scale(rad(c), radiance_cap(k));
    }
    k = PI * k * share / (f == LC_FALLOFF_INVERSE_SQUARE ? d2 : 1);
    return r_scale(rad(c), radiance_cap(k * cosl));
}

/* Every point light at h, into g. */
ALWAYS_INLINE void light_points(tracer *t, const hit *h, light_gather *g)
{
    const lc_scene *s = t->scene;
    double tooclose2 = too_close2(h);
    /* The lights' directions a few at a time, before their shadow rays:
    ** each is a square root and a division, whose latencies the calls to
    ** the shadow rays kept in series (a fifth of B1's samples in the
    ** shading waited on them; B1 at 16 spp now 0.98x the wall). */
    enum { AHEAD = 4 };
    lc_vec3 ls[AHEAD];
    double ds[AHEAD], d2s[AHEAD], cs[AHEAD];
    int ok[AHEAD];
    for (size_t i = 0; i < s->nlights; i++) {
        const lc_point_light *L = &s->lights[i];
        size_t slot = i % AHEAD;
        if (slot == 0)
            for (size_t j = i; j < s->nlights && j < i + AHEAD; j++)
                ok[j - i] = toward_light(h, g->n, s->lights[j].position, tooclose2,
                                         &ls[j - i], &ds[j - i], &d2s[j - i], &cs[j - i]);
        if (!ok[slot])
            continue;
        lc_vec3 l = ls[slot];
        double d = ds[slot], cosl = cs[slot];
        if (!light_wants(g, l))
            continue;
        /* From the offset origin along l, as far as d: the offset is a few
        ** ulps of |p|, inside what shadow_reach leaves, so the ray still
        ** stops short of L. */
        int rec;
        radiance f;
        if (!shadow_ray(t, h, l, d, NULL, LC_RAY_SHADOW, (int)i, INTERSECT_SKIP_NONE,
                        &rec, g->how, &f, g->lg))
            continue;
        light_take(t, g, l, cosl, light_point_eval(g->use, L->color, L->intensity, 1,
                                                   L->falloff, d, d2s[slot], cosl), f, rec);
    }
}

#endif
