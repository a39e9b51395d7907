/* surface.c: a textured material at a hit: each field a texture stands for
** evaluated there, the shading normal bumped. Called only for materials
** that have a texture (PLAN_TEXTURED): a scene without one never comes here. */
#include "base/sample.h"
#include "surface.h"
#include "texture/texture.h"
#include "scene/intersect.h"
#include "scene/csg.h"
#include "shapes/placed.h"

/* The hit point in the space of what was hit, before its transform: a moved
** mesh's object space, a moved placed shape's own; else the world's. */
static lc_vec3 object_point(const lc_scene *s, const hit *h)
{
    unsigned kind = PRIM_KIND(h->shape);
    if (kind == PRIM_CSG_FACE || kind == PRIM_CSG_CUT)   /* instance: the leaf's node */
        return csg_hit_object_point(s->csgs[PRIM_INDEX(h->shape)], h);
    if (h->instance)
        return lc_transform_point(&s->meshes[h->instance - 1].xf->inv, h->p);
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

/* The surface's derivatives along its texture coordinates, dp/du and dp/dv,
** on a mesh face with uvs (in the world); 0 elsewhere. */
static int uv_tangents(const lc_scene *s, const hit *h, lc_vec3 *pu, lc_vec3 *pv)
{
    if (PRIM_KIND(h->shape) != PRIM_TRIANGLE)
        return 0;
    const tri_ref *tr = &s->c.tris[PRIM_INDEX(h->shape)];
    const mesh_prim *mp = &s->meshes[h->instance ? h->instance - 1 : tr->mesh];
    const lc_mesh *m = mp->mesh;
    if (!m->uv)
        return 0;
    const uint32_t *f = m->f + 3 * (size_t)tr->face;
    lc_vec3 p[3];
    double u[3], v[3];
    for (int k = 0; k < 3; k++) {
        const double *x = m->v + 3 * (size_t)f[k];
        p[k] = v3(x[0], x[1], x[2]);
        u[k] = m->uv[2 * (size_t)f[k]];
        v[k] = m->uv[2 * (size_t)f[k] + 1];
    }
    lc_vec3 d1 = v3_sub(p[1], p[0]), d2 = v3_sub(p[2], p[0]);
    double du1 = u[1] - u[0], dv1 = v[1] - v[0], du2 = u[2] - u[0], dv2 = v[2] - v[0];
    double det = du1 * dv2 - dv1 * du2;
    if (!(fabs(det) > 0))
        return 0;
    *pu = v3_mul(v3_sub(v3_mul(d1, dv2), v3_mul(d2, dv1)), 1 / det);
    *pv = v3_mul(v3_sub(v3_mul(d2, du1), v3_mul(d1, du2)), 1 / det);
    if (mp->xf) {
        *pu = lc_transform_vector(&mp->xf->xf, *pu);
        *pv = lc_transform_vector(&mp->xf->xf, *pv);
    }
    return 1;
}

/* A bump over texture coordinates (Blinn 1978): heights h(u, v) displace
** the surface along its normal; n + k (h_u (n x p_v) - h_v (n x p_u)) /
** |p_u x p_v|, the slopes by forward differences in (u, v). */
static void bump_uv(const lc_scene *s, int i, double k, hit *h, lc_vec3 q,
                    const double uv[2])
{
    lc_vec3 pu, pv;
    if (!uv_tangents(s, h, &pu, &pv))
        return;
    const lc_textures *set = s->textures;
    double e = textures_step(set, i);
    double a[2] = {uv[0] + e, uv[1]}, b[2] = {uv[0], uv[1] + e};
    double h0 = textures_scalar(set, i, h->p, q, uv);
    double hu = (textures_scalar(set, i, h->p, q, a) - h0) / e;
    double hv = (textures_scalar(set, i, h->p, q, b) - h0) / e;
    lc_vec3 n = h->ns;
    double area = v3_len(v3_cross(pu, pv));
    if (!(area > 0))
        return;
    lc_vec3 d = v3_sub(v3_mul(v3_cross(n, pv), hu), v3_mul(v3_cross(n, pu), hv));
    lc_vec3 bent = v3_madd(n, d, k / area);
    double l = v3_len(bent);
    if (l > 0 && isfinite(l))
        h->ns = v3_mul(bent, 1 / l);
}

/* A tangent-space normal map (the convention of OpenGL, Blender and glTF):
** the texture's colour c at (u, v) is the normal (2c - 1) in the frame of
** the tangent T along dp/du, the bitangent B along dp/dv and the shading
** normal N, each made orthogonal to those before it (Gram-Schmidt), so a
** mirrored or rotated uv layout bends the right way; the tangent components
** are scaled by k. (0.5, 0.5, 1) leaves N as it is. */
static void normal_map(const lc_scene *s, int i, double k, hit *h, lc_vec3 q,
                       const double uv[2])
{
    lc_vec3 pu, pv;
    if (!uv_tangents(s, h, &pu, &pv))
        return;
    lc_vec3 n = h->ns;
    lc_vec3 t = v3_sub(pu, v3_mul(n, v3_dot(n, pu)));
    double lt = v3_len(t);
    if (!(lt > 0))
        return;
    t = v3_mul(t, 1 / lt);
    lc_vec3 b = v3_sub(v3_sub(pv, v3_mul(n, v3_dot(n, pv))), v3_mul(t, v3_dot(t, pv)));
    double lb = v3_len(b);
    if (!(lb > 0))
        return;
    b = v3_mul(b, 1 / lb);
    lc_color c = lc_textures_eval(s->textures, i, h->p, q, uv);
    double x = (2.0 * c.r - 1) * k, y = (2.0 * c.g - 1) * k, z = 2.0 * c.b - 1;
    if (x == 0 && y == 0 && z > 0)
        return;                                 /* flat: N exactly */
    lc_vec3 bent = v3_madd(v3_madd(v3_mul(n, z), t, x), b, y);
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
    if (tx[LC_SLOT_NORMAL])
        normal_map(s, tx[LC_SLOT_NORMAL] - 1, m->normal_scale, h, q, uv);
    if (tx[LC_SLOT_BUMP] && m->bump != 0) {
        int b = tx[LC_SLOT_BUMP] - 1;
        if (textures_use_uv(set, b))
            bump_uv(s, b, m->bump, h, q, uv);
        else
            bump(set, b, m->bump, h, q, uv);
    }
    return out;
}
