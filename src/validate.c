/* validate.c: defaults and the checks every scene description passes. */
#include <math.h>
#include "error.h"
#include "vec.h"

/* Two directions closer than this angle (radians) count as parallel. Both
** vectors are normalised first, so the test does not depend on scale. */
#define PARALLEL_SIN 1e-12

lc_material lc_material_default(void)
{
    lc_material m = {{1, 1, 1}, 1, 1, 0, 0, 32, {0, 0, 0}, LC_ABSORB_ALL, 0, 16};
    return m;
}

lc_settings lc_settings_default(void)
{
    lc_settings s = {{0, 0, 0}, {0, 0, 0}, 3};
    return s;
}

lc_point_light lc_point_light_default(void)
{
    lc_point_light l = {{0, 0, 0}, {1, 1, 1}, 1, LC_FALLOFF_INVERSE_SQUARE};
    return l;
}

lc_camera lc_camera_default(void)
{
    lc_camera c = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0, 0};
    return c;
}

static int finite3(lc_vec3 v)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

static lc_status check_vec(lc_vec3 v, const char *field, lc_error *err)
{
    if (!finite3(v))
        return lc_fail(err, LC_EARG, field, "must be finite, got (%g, %g, %g)",
                       v.x, v.y, v.z);
    return LC_OK;
}

static lc_status check_nonzero(lc_vec3 v, const char *field, lc_error *err)
{
    if (check_vec(v, field, err))
        return LC_EARG;
    if (v.x == 0 && v.y == 0 && v.z == 0)
        return lc_fail(err, LC_EARG, field, "must not be zero-length");
    /* A vector too small or too large to square in double has no direction. */
    if (!(v3_dot(v, v) > 0) || !isfinite(v3_dot(v, v)))
        return lc_fail(err, LC_EARG, field, "length out of range, got (%g, %g, %g)",
                       v.x, v.y, v.z);
    return LC_OK;
}

static lc_status check_coef(double x, const char *field, lc_error *err)
{
    if (!isfinite(x))
        return lc_fail(err, LC_EARG, field, "must be finite, got %g", x);
    if (x < 0)
        return lc_fail(err, LC_EARG, field, "must be >= 0, got %g", x);
    return LC_OK;
}

static lc_status check_color(lc_color c, double max, const char *field, lc_error *err)
{
    float ch[3] = {c.r, c.g, c.b};
    for (int i = 0; i < 3; i++) {
        if (!isfinite(ch[i]))
            return lc_fail(err, LC_EARG, field, "component %d must be finite, got %g",
                           i + 1, ch[i]);
        if (ch[i] < 0 || ch[i] > max)
            return lc_fail(err, LC_EARG, field, "component %d must be in [0, %g], got %g",
                           i + 1, max, ch[i]);
    }
    return LC_OK;
}

lc_status lc_material_check(const lc_material *m, lc_error *err)
{
    if (check_color(m->color, 1, "color", err) || check_coef(m->ka, "ka", err) ||
        check_coef(m->kd, "kd", err) || check_coef(m->kr, "kr", err) ||
        check_coef(m->ks, "ks", err) || check_coef(m->alpha, "alpha", err) ||
        check_color(m->emission, HUGE_VAL, "emission", err))
        return LC_EARG;
    if (!isfinite(m->glossiness) || m->glossiness < 0 || m->glossiness >= 90)
        return lc_fail(err, LC_EARG, "glossiness", "must be in [0, 90) degrees, got %g",
                       m->glossiness);
    if (m->cone_samples < 1 || m->cone_samples > LC_MAX_CONE_SAMPLES)
        return lc_fail(err, LC_EARG, "cone_samples", "must be in [1, %d], got %d",
                       LC_MAX_CONE_SAMPLES, m->cone_samples);
    if (m->absorb != LC_ABSORB_ALL && m->absorb != LC_ABSORB_DIFFUSE)
        return lc_fail(err, LC_EARG, "absorb", "unknown absorb mode %d", (int)m->absorb);
    lc_ok(err);
    return LC_OK;
}

static lc_status check_not_parallel(lc_vec3 a, lc_vec3 b, const char *fa, const char *fb,
                                    lc_error *err)
{
    lc_vec3 c = v3_cross(v3_norm(a), v3_norm(b));
    if (!(v3_len(c) > PARALLEL_SIN))
        return lc_fail(err, LC_EARG, fb, "'%s' and '%s' must not be parallel", fa, fb);
    return LC_OK;
}

lc_status lc_shape_check(const lc_shape *s, lc_error *err)
{
    switch (s->kind) {
    case LC_SPHERE:
        if (check_vec(s->p, "center", err))
            return LC_EARG;
        if (!isfinite(s->radius))
            return lc_fail(err, LC_EARG, "radius", "must be finite, got %g", s->radius);
        if (!(s->radius > 0))
            return lc_fail(err, LC_EARG, "radius", "must be > 0, got %g", s->radius);
        break;
    case LC_QUAD:
        if (check_vec(s->p, "corner", err) || check_nonzero(s->u, "u", err) ||
            check_nonzero(s->v, "v", err) || check_not_parallel(s->u, s->v, "u", "v", err))
            return LC_EARG;
        break;
    case LC_BOX: {
        if (check_vec(s->p, "corner", err) || check_nonzero(s->u, "u", err) ||
            check_nonzero(s->v, "v", err) || check_nonzero(s->w, "w", err) ||
            check_not_parallel(s->u, s->v, "u", "v", err) ||
            check_not_parallel(s->v, s->w, "v", "w", err) ||
            check_not_parallel(s->u, s->w, "u", "w", err))
            return LC_EARG;
        lc_vec3 nu = v3_norm(s->u), nv = v3_norm(s->v), nw = v3_norm(s->w);
        if (!(fabs(v3_dot(v3_cross(nu, nv), nw)) > PARALLEL_SIN))
            return lc_fail(err, LC_EARG, "w", "'u', 'v' and 'w' must not be coplanar");
        break;
    }
    case LC_PLANE:
        if (check_vec(s->p, "point", err) || check_nonzero(s->u, "normal", err))
            return LC_EARG;
        break;
    default:
        return lc_fail(err, LC_EARG, "kind", "unknown shape kind %d", (int)s->kind);
    }
    lc_ok(err);
    return LC_OK;
}

lc_status lc_point_light_check(const lc_point_light *l, lc_error *err)
{
    if (check_vec(l->position, "position", err) ||
        check_color(l->color, HUGE_VAL, "color", err) ||
        check_coef(l->intensity, "intensity", err))
        return LC_EARG;
    if (l->falloff != LC_FALLOFF_INVERSE_SQUARE && l->falloff != LC_FALLOFF_NONE)
        return lc_fail(err, LC_EARG, "falloff", "unknown falloff %d", (int)l->falloff);
    lc_ok(err);
    return LC_OK;
}

lc_status lc_camera_check(const lc_camera *c, lc_error *err)
{
    if (check_vec(c->from, "from", err) || check_vec(c->at, "at", err) ||
        check_nonzero(c->up, "up", err))
        return LC_EARG;
    lc_vec3 f = v3_sub(c->at, c->from);
    if (f.x == 0 && f.y == 0 && f.z == 0)
        return lc_fail(err, LC_EARG, "at", "must differ from 'from'");
    if (!isfinite(v3_dot(f, f)) || !(v3_dot(f, f) > 0))
        return lc_fail(err, LC_EARG, "at", "distance to 'from' out of range");
    if (check_not_parallel(f, c->up, "at - from", "up", err))
        return LC_EARG;
    if (!isfinite(c->fov) || !(c->fov > 0 && c->fov < 180))
        return lc_fail(err, LC_EARG, "fov", "must be in (0, 180) degrees, got %g", c->fov);
    if (!isfinite(c->aperture) || c->aperture < 0)
        return lc_fail(err, LC_EARG, "aperture", "must be finite and >= 0, got %g",
                       c->aperture);
    if (!isfinite(c->focus) || c->focus < 0)
        return lc_fail(err, LC_EARG, "focus", "must be finite and >= 0, got %g", c->focus);
    lc_ok(err);
    return LC_OK;
}

const char *lc_shape_kind_name(lc_shape_kind k)
{
    static const char *const names[] = {"sphere", "quad", "box", "plane", "triangle"};
    return (unsigned)k <= LC_SHAPE_KINDS ? names[k] : "?";
}
