/* validate.c: defaults and checks of materials, lights, cameras, settings and
** render options; the helpers shape checks share. */
#include <math.h>
#include "error.h"
#include "validate.h"


lc_material lc_material_default(void)
{
    lc_material m = {{1, 1, 1}, 1, 1, 0, 0, 32, {0, 0, 0}, LC_ABSORB_ALL, 0, 16,
                     0, 1, 1, {0, 0, 0}, LC_SHADOW_FILTERED, {0}, 0, 1};
    return m;
}

const char *lc_slot_name(lc_slot slot)
{
    static const char *const names[LC_SLOTS] = {"color", "kd", "ks", "kr", "kt",
                                                "emission", "bump", "normal_map"};
    return (unsigned)slot < LC_SLOTS ? names[slot] : "?";
}

lc_settings lc_settings_default(void)
{
    lc_settings s = {{0, 0, 0}, 0, {0, 0, 0}, 3};
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

static lc_status check_finite(lc_vec3 v, const char *field, lc_error *err)
{
    if (!isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z))
        return error_fail(err, LC_EARG, field, "must be finite, got (%g, %g, %g)",
                       v.x, v.y, v.z);
    return LC_OK;
}

lc_status validate_vec(lc_vec3 v, const char *field, lc_error *err)
{
    if (check_finite(v, field, err))
        return LC_EARG;
    if (!(v3_max_abs(v) <= LC_MAX_COORD))
        return error_fail(err, LC_EARG, field, "must be within +-%g (lancer's coordinate "
                          "range), got (%g, %g, %g)", LC_MAX_COORD, v.x, v.y, v.z);
    return LC_OK;
}

lc_status validate_length(double x, const char *field, lc_error *err)
{
    if (!isfinite(x))
        return error_fail(err, LC_EARG, field, "must be finite, got %g", x);
    if (!(x > 0))
        return error_fail(err, LC_EARG, field, "must be > 0, got %g", x);
    if (!(x >= LC_MIN_LENGTH && x <= LC_MAX_COORD))
        return error_fail(err, LC_EARG, field, "must be in [%g, %g] (lancer's coordinate "
                          "range), got %g", LC_MIN_LENGTH, LC_MAX_COORD, x);
    return LC_OK;
}

lc_status validate_edge(lc_vec3 v, const char *field, lc_error *err)
{
    if (validate_nonzero(v, field, err))
        return LC_EARG;
    double len = v3_len(v);
    if (!(len >= LC_MIN_LENGTH && len <= LC_MAX_COORD))
        return error_fail(err, LC_EARG, field, "length must be in [%g, %g] (lancer's "
                          "coordinate range), got %g", LC_MIN_LENGTH, LC_MAX_COORD, len);
    return LC_OK;
}

lc_status validate_nonzero(lc_vec3 v, const char *field, lc_error *err)
{
    if (check_finite(v, field, err))
        return LC_EARG;
    if (v.x == 0 && v.y == 0 && v.z == 0)
        return error_fail(err, LC_EARG, field, "must not be zero-length");
    /* A vector too small or too large to square in double has no direction. */
    if (!(v3_dot(v, v) > 0) || !isfinite(v3_dot(v, v)))
        return error_fail(err, LC_EARG, field, "length out of range, got (%g, %g, %g)",
                       v.x, v.y, v.z);
    return LC_OK;
}

static lc_status check_coef(double x, const char *field, lc_error *err)
{
    if (!isfinite(x))
        return error_fail(err, LC_EARG, field, "must be finite, got %g", x);
    if (x < 0)
        return error_fail(err, LC_EARG, field, "must be >= 0, got %g", x);
    return LC_OK;
}

static lc_status check_color(lc_color c, double max, const char *field, lc_error *err)
{
    float ch[3] = {c.r, c.g, c.b};
    for (int i = 0; i < 3; i++) {
        if (!isfinite(ch[i]))
            return error_fail(err, LC_EARG, field, "component %d must be finite, got %g",
                           i + 1, ch[i]);
        if (ch[i] < 0 || ch[i] > max)
            return error_fail(err, LC_EARG, field, "component %d must be in [0, %g], got %g",
                           i + 1, max, ch[i]);
    }
    return LC_OK;
}

lc_status validate_coef(double x, const char *field, lc_error *err)
{
    return check_coef(x, field, err);
}

lc_status validate_color(lc_color c, double max, const char *field, lc_error *err)
{
    return check_color(c, max, field, err);
}

lc_status lc_material_check(const lc_material *m, lc_error *err)
{
    if (check_color(m->color, 1, "color", err) || check_coef(m->ka, "ka", err) ||
        check_coef(m->kd, "kd", err) || check_coef(m->kr, "kr", err) ||
        check_coef(m->ks, "ks", err) || check_coef(m->alpha, "alpha", err) ||
        check_color(m->emission, HUGE_VAL, "emission", err) ||
        check_coef(m->kt, "kt", err))
        return LC_EARG;
    double a[3] = {m->absorption.x, m->absorption.y, m->absorption.z};
    for (int i = 0; i < 3; i++)
        if (!(a[i] >= 0 && a[i] <= 1 / LC_MIN_LENGTH))
            return error_fail(err, LC_EARG, "absorption", "component %d must be in "
                              "[0, %g] (per unit length, one over lancer's shortest), "
                              "got %g", i + 1, 1 / LC_MIN_LENGTH, a[i]);
    /* Below 1 no matter is; up to 100, every ratio of two indices and its
    ** square stay far from overflow in the Fresnel terms. */
    if (!(m->ior >= 1 && m->ior <= LC_MAX_IOR))
        return error_fail(err, LC_EARG, "ior", "must be in [1, %d], got %g", LC_MAX_IOR,
                          m->ior);
    if (m->fresnel != 0 && m->fresnel != 1)
        return error_fail(err, LC_EARG, "fresnel", "must be 0 or 1, got %d", m->fresnel);
    if (m->shadow != LC_SHADOW_FILTERED && m->shadow != LC_SHADOW_OPAQUE)
        return error_fail(err, LC_EARG, "shadow", "unknown shadow mode %d",
                          (int)m->shadow);
    if (!isfinite(m->glossiness) || m->glossiness < 0 || m->glossiness >= 90)
        return error_fail(err, LC_EARG, "glossiness", "must be in [0, 90) degrees, got %g",
                       m->glossiness);
    if (m->cone_samples < 1 || m->cone_samples > LC_MAX_CONE_SAMPLES)
        return error_fail(err, LC_EARG, "cone_samples", "must be in [1, %d], got %d",
                       LC_MAX_CONE_SAMPLES, m->cone_samples);
    if (m->absorb != LC_ABSORB_ALL && m->absorb != LC_ABSORB_DIFFUSE)
        return error_fail(err, LC_EARG, "absorb", "unknown absorb mode %d", (int)m->absorb);
    for (int k = 0; k < LC_SLOTS; k++)
        if (m->texture[k] < 0)
            return error_fail(err, LC_EARG, lc_slot_name((lc_slot)k), "texture index must be "
                              ">= 0 (0: none), got %d", m->texture[k]);
    if (!(m->bump >= -1e6 && m->bump <= 1e6))
        return error_fail(err, LC_EARG, "bump_scale", "must be in [-1e6, 1e6], got %g",
                          m->bump);
    if (!(m->normal_scale >= 0 && m->normal_scale <= 1e6))
        return error_fail(err, LC_EARG, "normal_scale", "must be in [0, 1e6], got %g",
                          m->normal_scale);
    error_ok(err);
    return LC_OK;
}

lc_status validate_not_parallel(lc_vec3 a, lc_vec3 b, const char *fa, const char *fb,
                                lc_error *err)
{
    lc_vec3 c = v3_cross(v3_norm(a), v3_norm(b));
    if (!(v3_len(c) > PARALLEL_SIN))
        return error_fail(err, LC_EARG, fb, "'%s' and '%s' must not be parallel", fa, fb);
    return LC_OK;
}

lc_status lc_point_light_check(const lc_point_light *l, lc_error *err)
{
    if (validate_vec(l->position, "position", err) ||
        check_color(l->color, HUGE_VAL, "color", err) ||
        check_coef(l->intensity, "intensity", err))
        return LC_EARG;
    if (l->falloff != LC_FALLOFF_INVERSE_SQUARE && l->falloff != LC_FALLOFF_NONE)
        return error_fail(err, LC_EARG, "falloff", "unknown falloff %d", (int)l->falloff);
    error_ok(err);
    return LC_OK;
}

lc_status lc_camera_check(const lc_camera *c, lc_error *err)
{
    if (validate_vec(c->from, "from", err) || validate_vec(c->at, "at", err) ||
        validate_nonzero(c->up, "up", err))
        return LC_EARG;
    lc_vec3 f = v3_sub(c->at, c->from);
    if (f.x == 0 && f.y == 0 && f.z == 0)
        return error_fail(err, LC_EARG, "at", "must differ from 'from'");
    if (!isfinite(v3_dot(f, f)) || !(v3_dot(f, f) > 0))
        return error_fail(err, LC_EARG, "at", "distance to 'from' out of range");
    if (validate_not_parallel(f, c->up, "at - from", "up", err))
        return LC_EARG;
    if (!isfinite(c->fov) || !(c->fov > 0 && c->fov < 180))
        return error_fail(err, LC_EARG, "fov", "must be in (0, 180) degrees, got %g", c->fov);
    if (!isfinite(c->aperture) || c->aperture < 0)
        return error_fail(err, LC_EARG, "aperture", "must be finite and >= 0, got %g",
                       c->aperture);
    if (c->aperture > LC_MAX_COORD)
        return error_fail(err, LC_EARG, "aperture", "must be at most %g (lancer's coordinate "
                          "range), got %g", LC_MAX_COORD, c->aperture);
    if (!isfinite(c->focus) || c->focus < 0)
        return error_fail(err, LC_EARG, "focus", "must be finite and >= 0, got %g", c->focus);
    if (c->focus > LC_MAX_COORD)
        return error_fail(err, LC_EARG, "focus", "must be at most %g (lancer's coordinate "
                          "range), got %g", LC_MAX_COORD, c->focus);
    error_ok(err);
    return LC_OK;
}


lc_render_options lc_render_options_default(void)
{
    lc_render_options o;
    memset(&o, 0, sizeof o);
    o.width = 640;
    o.height = 480;
    o.samples = 1;
    o.sampler = LC_SAMPLER_SOBOL;
    o.light_samples = 16;
    o.max_depth = -1;
    o.min_samples = 16;
    o.glossy = 1;
    o.cosine = 1;
    o.cutoff = 1.0 / 255;   /* POV-Ray's adc_bailout: below one step of 8-bit output */
    o.shadows = o.reflections = o.specular = 1;
    o.roulette = o.nee = 1;
    return o;
}

lc_status lc_render_options_check(const lc_render_options *o, lc_error *err)
{
    if (o->width < 1 || o->width > LC_MAX_SIDE)
        return error_fail(err, LC_EARG, "width", "must be in [1, %d], got %d", LC_MAX_SIDE,
                       o->width);
    if (o->height < 1 || o->height > LC_MAX_SIDE)
        return error_fail(err, LC_EARG, "height", "must be in [1, %d], got %d", LC_MAX_SIDE,
                       o->height);
    if ((size_t)o->width * (size_t)o->height > LC_MAX_PIXELS)
        return error_fail(err, LC_EARG, "width", "%dx%d is more than %zu pixels",
                       o->width, o->height, LC_MAX_PIXELS);
    if (o->samples < 1 || o->samples > LC_MAX_SAMPLES)
        return error_fail(err, LC_EARG, "samples", "must be in [1, %d], got %d", LC_MAX_SAMPLES,
                       o->samples);
    if ((unsigned)o->sampler > LC_SAMPLER_RANDOM)
        return error_fail(err, LC_EARG, "sampler", "unknown sampler %d", (int)o->sampler);
    if (o->light_samples < 0 || o->light_samples > LC_MAX_LIGHT_SAMPLES)
        return error_fail(err, LC_EARG, "light_samples", "must be in [0, %d], got %d",
                       LC_MAX_LIGHT_SAMPLES, o->light_samples);
    if (o->cone_samples < 0 || o->cone_samples > LC_MAX_CONE_SAMPLES)
        return error_fail(err, LC_EARG, "cone_samples", "must be in [0, %d], got %d",
                       LC_MAX_CONE_SAMPLES, o->cone_samples);
    if (o->max_depth < -1 || o->max_depth > LC_MAX_DEPTH)
        return error_fail(err, LC_EARG, "max_depth", "must be in [0, %d], got %d",
                       LC_MAX_DEPTH, o->max_depth);
    if (!(o->noise >= 0 && o->noise <= HUGE_VAL) || isinf(o->noise))
        return error_fail(err, LC_EARG, "noise", "must be finite and >= 0, got %g", o->noise);
    if (o->noise > 0 && o->sampler == LC_SAMPLER_JITTER)
        return error_fail(err, LC_EARG, "sampler", "adaptive sampling (noise > 0) stops after "
                       "any number of samples: it needs 'sobol' or 'random', not 'jitter'");
    if (o->min_samples < 1 || o->min_samples > LC_MAX_SAMPLES)
        return error_fail(err, LC_EARG, "min_samples", "must be in [1, %d], got %d",
                       LC_MAX_SAMPLES, o->min_samples);
    if (!(o->cutoff >= 0 && o->cutoff <= 1))
        return error_fail(err, LC_EARG, "cutoff", "must be in [0, 1], got %g", o->cutoff);
    if (o->threads < 0 || o->threads > LC_MAX_THREADS)
        return error_fail(err, LC_EARG, "threads", "must be in [0, %d], got %d", LC_MAX_THREADS,
                       o->threads);
    if (o->indirect < 0 || o->indirect > LC_MAX_INDIRECT)
        return error_fail(err, LC_EARG, "indirect", "must be in [0, %d], got %d",
                          LC_MAX_INDIRECT, o->indirect);
    if (o->ao_samples < 0 || o->ao_samples > LC_MAX_AO_SAMPLES)
        return error_fail(err, LC_EARG, "ao", "samples must be in [0, %d], got %d",
                          LC_MAX_AO_SAMPLES, o->ao_samples);
    if (o->ao_samples > 0 && !(o->ao_distance > 0 && o->ao_distance <= LC_MAX_COORD))
        return error_fail(err, LC_EARG, "ao", "distance must be in (0, %g], got %g",
                          LC_MAX_COORD, o->ao_distance);
    if (o->progressive != 0 && o->progressive != 1)
        return error_fail(err, LC_EARG, "progressive", "must be 0 or 1, got %d",
                          o->progressive);
    if (o->on_pass && !o->progressive)
        return error_fail(err, LC_EARG, "on_pass", "is called after each pass of a "
                          "progressive render: turn progressive on too");
    if (o->aovs & ~LC_AOV_ALL)
        return error_fail(err, LC_EARG, "aovs", "unknown AOV bits 0x%x",
                          o->aovs & ~LC_AOV_ALL);
    if (o->aovs && o->noise > 0)
        return error_fail(err, LC_EARG, "aovs", "AOVs are not made with adaptive sampling "
                          "(noise > 0): render them with a fixed number of samples");
    if (o->aovs && o->progressive)
        return error_fail(err, LC_EARG, "aovs", "AOVs are not made by a progressive render: "
                          "render them in one pass, not progressive");
    const int *r = o->region;
    if ((r[0] | r[1] | r[2] | r[3]) != 0 &&
        !(r[0] >= 0 && r[0] < r[2] && r[2] <= o->width && r[1] >= 0 && r[1] < r[3] &&
          r[3] <= o->height))
        return error_fail(err, LC_EARG, "region", "must be {x0, y0, x1, y1} with 0 <= x0 < "
                          "x1 <= %d and 0 <= y0 < y1 <= %d (pixel edges of the %dx%d "
                          "frame), got {%d, %d, %d, %d}", o->width, o->height, o->width,
                          o->height, r[0], r[1], r[2], r[3]);
    return LC_OK;
}
