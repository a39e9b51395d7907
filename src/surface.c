/* surface.c: a textured material at a hit: each field a texture stands for
** evaluated there, the shading normal bumped. Called only for materials
** that have a texture (PLAN_TEXTURED): a scene without one never comes here. */
#include "sample.h"
#include "surface.h"
#include "texture.h"

/* The hit point in the space of what was hit, before its transform: a moved
** mesh's object space, a moved placed shape's own; else the world's. */
static lc_vec3 object_point(const lc_scene *s, const hit *h)
{
    if (h->instance)
        return lc_transform_point(&s->meshes[h->instance - 1].xf->inv, h->p);
    unsigned kind = PRIM_KIND(h->shape);
    if (kind == PRIM_TRIANGLE)
        return h->p;
    lc_shape_kind k = shape_kind_of_prim(kind);
    if (k < LC_DISC || k > LC_ELLIPSOID)
        return h->p;
    const placed_geom *g = shape_at(&s->shapes[k], PRIM_INDEX(h->shape));
    lc_transform inv;
    if (!g->shape.moved || lc_transform_inverse(&g->shape.xf, &inv, NULL))
        return h->p;
    return lc_transform_point(&inv, h->p);
}

static double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

/* Bends h->ns by the slope of height texture i (scaled by k) across the
** surface: forward differences along two tangents, a thousandth of the
** texture's period apart. */
static void bump(const lc_textures *set, int i, double k, hit *h, lc_vec3 q,
                 const double uv[2])
{
    lc_vec3 n = h->ns, t1, t2;
    sample_frame(n, &t1, &t2);
    double e = textures_step(set, i);
    double h0 = textures_scalar(set, i, h->p, q, uv);
    double d1 = textures_scalar(set, i, v3_madd(h->p, t1, e), v3_madd(q, t1, e), uv) - h0;
    double d2 = textures_scalar(set, i, v3_madd(h->p, t2, e), v3_madd(q, t2, e), uv) - h0;
    lc_vec3 bent = v3_sub(n, v3_mul(v3_add(v3_mul(t1, d1), v3_mul(t2, d2)), k / e));
    double l = v3_len(bent);
    if (l > 0 && isfinite(l))
        h->ns = v3_mul(bent, 1 / l);
}

const lc_material *surface_material(const lc_scene *s, hit *h, const lc_material *m,
                                    lc_material *out)
{
    const lc_textures *set = s->textures;
    if (!set)
        return m;
    *out = *m;
    double uv[2] = {0, 0};
    int need_uv = 0;
    for (int k = 0; k < LC_SLOTS; k++)
        need_uv |= m->texture[k] && textures_use_uv(set, m->texture[k] - 1);
    if (need_uv)
        intersect_uv(s, h, uv);
    lc_vec3 q = object_point(s, h);
    const int *tx = m->texture;
    if (tx[LC_SLOT_COLOR]) {
        lc_color c = lc_textures_eval(set, tx[LC_SLOT_COLOR] - 1, h->p, q, uv);
        out->color = (lc_color){(float)clamp01(c.r), (float)clamp01(c.g),
                                (float)clamp01(c.b)};
    }
    if (tx[LC_SLOT_KD]) out->kd = clamp01(textures_scalar(set, tx[LC_SLOT_KD] - 1, h->p, q, uv));
    if (tx[LC_SLOT_KS]) out->ks = clamp01(textures_scalar(set, tx[LC_SLOT_KS] - 1, h->p, q, uv));
    if (tx[LC_SLOT_KR]) out->kr = clamp01(textures_scalar(set, tx[LC_SLOT_KR] - 1, h->p, q, uv));
    if (tx[LC_SLOT_KT]) out->kt = clamp01(textures_scalar(set, tx[LC_SLOT_KT] - 1, h->p, q, uv));
    if (tx[LC_SLOT_EMISSION]) {
        lc_color c = lc_textures_eval(set, tx[LC_SLOT_EMISSION] - 1, h->p, q, uv);
        out->emission = (lc_color){fmaxf(0, c.r), fmaxf(0, c.g), fmaxf(0, c.b)};
    }
    if (tx[LC_SLOT_BUMP] && m->bump != 0)
        bump(set, tx[LC_SLOT_BUMP] - 1, m->bump, h, q, uv);
    return out;
}
