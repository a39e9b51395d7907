/* shade_minimal.c: diffuse-only shading, the reference for S7's cost parity. */
/*
** Built only by `make MINIMAL=1` (build/minimal), in place of shade.c: the
** same shade_ray with everything but the diffuse path compiled out, so the
** bench (tools/bench/parity.lua) prices what the full shading costs on a
** scene that needs none of it (docs/numerics.md S7: <= 1.05x). What is left: the
** closest hit, the background on a miss, and per point light n.l > 0, one
** shadow ray, kd C I cos / d^2, plus ka C Ia. No specular, mirrors, cutoff,
** emitters, plans, switches (shadows, cosine), radiance cap, self-hit watch
** or explain records.
**
** The arithmetic is shade.c's, operation for operation (1/d as a product,
** d * d for the falloff, lights summed in order before kd, ka Ia added
** after, C last), so a diffuse-only scene renders to the same bits.
*/
#include "shade.h"
#include "scene/intersect.h"

#ifndef LC_MINIMAL
#error "shade_minimal.c replaces shade.c only in the MINIMAL=1 build"
#endif


radiance shade_ray(tracer *t, const ray *r, uint32_t index, uint32_t count)
{
    const lc_scene *s = t->scene;
    hit h;
    (void)index;
    (void)count;
    if (!intersect_closest(s, r, HUGE_VAL, &h, &t->counts)) {
        lc_color bg = s->settings.background;
        radiance c = {bg.r, bg.g, bg.b};
        return c;
    }
    const lc_material *m = &s->materials[h.material];
    lc_vec3 n = v3_dot(h.n, r->d) > 0 ? v3_neg(h.ns) : h.ns;  /* face the viewer */
    double dr = 0, dg = 0, db = 0;         /* sum of Lc (n.l) */
    for (size_t i = 0; i < s->nlights; i++) {
        const lc_point_light *L = &s->lights[i];
        lc_vec3 tol = v3_sub(L->position, h.p);
        double d = sqrt(v3_dot(tol, tol));
        lc_vec3 l = v3_mul(tol, 1.0 / d);
        double cosl = v3_dot(n, l);
        if (!(cosl > 0))                   /* also a light on the point: NaN */
            continue;
        ray sr = {spawn_origin(&h, l), l};
        t->rays[LC_RAY_SHADOW]++;
        if (intersect_occluded(s, &sr, shadow_reach(sr.o, d), &t->counts))
            continue;
        double k = L->intensity;
        if (L->falloff == LC_FALLOFF_INVERSE_SQUARE)
            k /= d * d;
        dr += L->color.r * k * cosl;
        dg += L->color.g * k * cosl;
        db += L->color.b * k * cosl;
    }
    lc_color ia = s->settings.ambient, c = m->color;
    radiance out = {c.r * (dr * m->kd + ia.r * m->ka),
                    c.g * (dg * m->kd + ia.g * m->ka),
                    c.b * (db * m->kd + ia.b * m->ka)};
    return out;
}
