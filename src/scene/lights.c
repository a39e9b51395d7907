/* lights.c: spot and directional lights: defaults, checks, what a scene
** stores of them, and a spot's cone. Their loops at a hit are in
** light_spot.h and light_sun.h, beside the point lights' light_point.h. */
#include "base/error.h"
#include "lights.h"
#include "base/validate.h"

lc_spot_light lc_spot_light_default(void)
{
    lc_spot_light l = {{0, 0, 0}, {0, -1, 0}, 30, 5, {1, 1, 1}, 1,
                       LC_FALLOFF_INVERSE_SQUARE};
    return l;
}

lc_directional_light lc_directional_light_default(void)
{
    lc_directional_light l = {{0, -1, 0}, {1, 1, 1}, PI};
    return l;
}

lc_status lc_spot_light_check(const lc_spot_light *l, lc_error *err)
{
    if (validate_vec(l->position, "position", err) ||
        validate_nonzero(l->direction, "direction", err) ||
        validate_color(l->color, HUGE_VAL, "color", err) ||
        validate_coef(l->intensity, "intensity", err))
        return LC_EARG;
    if (!(l->angle > 0 && l->angle < 180))
        return error_fail(err, LC_EARG, "angle", "must be in (0, 180) degrees, got %g",
                          l->angle);
    if (!(l->soft >= 0 && l->soft <= l->angle))
        return error_fail(err, LC_EARG, "soft", "must be in [0, angle] = [0, %g] degrees, "
                          "got %g", l->angle, l->soft);
    if (l->falloff != LC_FALLOFF_INVERSE_SQUARE && l->falloff != LC_FALLOFF_NONE)
        return error_fail(err, LC_EARG, "falloff", "unknown falloff %d", (int)l->falloff);
    error_ok(err);
    return LC_OK;
}

lc_status lc_directional_light_check(const lc_directional_light *l, lc_error *err)
{
    if (validate_nonzero(l->direction, "direction", err) ||
        validate_color(l->color, HUGE_VAL, "color", err) ||
        validate_coef(l->irradiance, "irradiance", err))
        return LC_EARG;
    error_ok(err);
    return LC_OK;
}

void spot_prepare(const lc_spot_light *l, spot_light *out)
{
    out->d = *l;
    out->axis = v3_norm(l->direction);
    out->cos_outer = cos(l->angle * (PI / 180));
    out->cos_inner = cos((l->angle - l->soft) * (PI / 180));
}

/* pbrt-v4's spot: a smoothstep over the cosine, between the cone's edge
** and where the edge begins; a hard edge (soft = 0) is a step, the edge
** itself inside. */
double spot_share(const spot_light *s, lc_vec3 l)
{
    double c = v3_dot(s->axis, l);
    if (c >= s->cos_inner)
        return 1;
    if (!(c > s->cos_outer))
        return 0;
    double t = (c - s->cos_outer) / (s->cos_inner - s->cos_outer);
    return t * t * (3 - 2 * t);
}

double lc_spot_light_share(const lc_spot_light *l, lc_vec3 p)
{
    spot_light s;
    spot_prepare(l, &s);
    lc_vec3 d = v3_sub(p, l->position);
    double len = v3_len(d);
    if (!(len > 0) || !isfinite(len))
        return 0;
    return spot_share(&s, v3_mul(d, 1 / len));
}

void sun_prepare(const lc_directional_light *l, sun_light *out)
{
    out->d = *l;
    out->to = v3_neg(v3_norm(l->direction));
    out->k = l->irradiance / PI;
}
