/* plan.c: the render layer's plan of a frame: which effects it needs
** (LC_NEED_*), why each is on or off, and each material's shading plan
** (PLAN_*), after the geometry (compile.c) is up to date. An effect no
** material in use can show is never reached by the render loop and spawns
** no ray; an effect is one row of `effects` below. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "camera.h"
#include "base/clock.h"
#include "scene/compile.h"
#include "scene/csg.h"
#include "base/error.h"
#include "base/mem.h"
#include "plan.h"
#include "scene/sky.h"
#include "texture/texture.h"

/* First material in use (1-based, in the order the scene met them) with
** the property, and how many have it. */
typedef struct { size_t count, first; } census;

static void count(census *c, size_t i)
{
    if (c->count++ == 0)
        c->first = i + 1;
}

/* What the effects are decided from: the scene, the render's switches, and
** how many materials in use have each property. */
typedef struct {
    const lc_scene *s;
    const lc_render_options *o;
    census inuse, lit, spec, refl, gloss, amb, refr, filt, tex;
    int depth;             /* the render's max_depth: its own or the scene's */
    int sky_lights;        /* paths: a background that is not black lights */
    int lights;            /* something lights the scene */
    int ambient;           /* the scene has an ambient light */
    int area;              /* emitters are sampled as area lights */
} frame;

static int textured(const lc_material *m)
{
    for (int k = 0; k < LC_SLOTS; k++)
        if (m->texture[k])
            return 1;
    return 0;
}

/* The material as planning sees it: a field a texture stands for may take
** any value, so it counts as present (a textured kd lights like kd > 0). */
static lc_material material_bound(const lc_material *m)
{
    lc_material b = *m;
    if (m->texture[LC_SLOT_KD]) b.kd = 1;
    if (m->texture[LC_SLOT_KS]) b.ks = 1;
    if (m->texture[LC_SLOT_KR]) b.kr = 1;
    if (m->texture[LC_SLOT_KT]) b.kt = 1;
    if (m->texture[LC_SLOT_EMISSION]) b.emission = (lc_color){1, 1, 1};
    return b;
}

/* A material reflects through a cone when it has one wider than an ulp of a
** unit vector (narrower ones trace exactly the mirror ray: a mirror is
** cheaper and bit-identical) and the render has not switched cones off. */
static int material_cone(const lc_material *m, const lc_render_options *o)
{
    return o->glossy && sin(m->glossiness * (PI / 180)) > DBL_EPSILON;
}

/* A dielectric reflects (Fresnel, or total internal reflection) whatever
** its kr. */
static int material_reflects(const lc_material *m)
{
    return m->kr > 0 || m->kt > 0;
}

static int render_depth(const lc_scene *s, const lc_render_options *o)
{
    return o->max_depth >= 0 ? o->max_depth : s->settings.max_depth;
}

/* Sets used[i] to 1 for each material some object takes. */
static void mark_used(const lc_scene *s, uint16_t *used)
{
    for (int k = 0; k < LC_SHAPE_KINDS; k++)
        for (size_t i = 0; i < s->shapes[k].n; i++)
            used[s->shapes[k].material[i]] = 1;
    for (size_t i = 0; i < s->nmeshes; i++) {
        used[s->meshes[i].material] = 1;
        for (uint32_t k = 0; k < s->meshes[i].npalette; k++)
            used[s->meshes[i].palette[k]] = 1;
    }
    for (size_t i = 0; i < s->ncsgs; i++)
        csg_materials(s->csgs[i], used);
}

static void count_materials(frame *f, const uint16_t *used)
{
    const lc_scene *s = f->s;
    for (size_t i = 0; i < s->nmaterials; i++) {
        if (!used[i])
            continue;
        lc_material m = material_bound(&s->materials[i]);
        if (textured(&s->materials[i])) count(&f->tex, i);
        count(&f->inuse, i);
        int reflects = material_reflects(&m), cone = material_cone(&m, f->o);
        if (m.kd > 0 || m.ks > 0) count(&f->lit, i);
        if (m.ks > 0) count(&f->spec, i);
        if (reflects && !cone) count(&f->refl, i);
        if (reflects && cone) count(&f->gloss, i);
        if (m.ka > 0) count(&f->amb, i);
        if (m.kt > 0) count(&f->refr, i);
        if (m.kt > 0 && m.shadow == LC_SHADOW_FILTERED) count(&f->filt, i);
    }
}

static frame frame_of(const lc_scene *s, const lc_render_options *o,
                      const uint16_t *used)
{
    frame f;
    memset(&f, 0, sizeof f);
    f.s = s;
    f.o = o;
    count_materials(&f, used);
    f.depth = render_depth(s, o);
    /* For paths, a background that is not black is a light too. */
    f.sky_lights = o->indirect > 0 && (s->settings.background_texture > 0 ||
                                       !c_is_black(s->settings.background));
    f.lights = s->nlights > 0 || s->nemitters > 0 || s->nspots > 0 || s->nsuns > 0 ||
               f.sky_lights;
    f.ambient = !c_is_black(s->settings.ambient);
    f.area = o->light_samples > 0;
    return f;
}

/* ---- The effects: each says whether the frame needs it, and why -------- */

#define WHY_SIZE sizeof ((compiled *)0)->why[0]

static void PRINTF_LIKE(2, 3) say(char *why, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, WHY_SIZE, fmt, ap);
    va_end(ap);
}

static const char *plural(size_t n)
{
    return n == 1 ? "" : "s";
}

/* Lights of a kind light the lit materials; generic, whatever they are. */
static int lights_lit(const frame *f, size_t n)
{
    return n > 0 && (f->lit.count || f->o->generic);
}

static int need_shadow(const frame *f, char *why)
{
    const lc_scene *s = f->s;
    int on = lights_lit(f, s->nlights);
    if (on)
        say(why, "%zu point light%s; %zu of %zu materials in use have kd or ks > 0 "
            "(first: #%zu)%s", s->nlights, plural(s->nlights), f->lit.count,
            f->inuse.count, f->lit.first,
            f->o->shadows ? "" : "; shadows off: no shadow rays");
    else
        say(why, s->nlights ? "no material in use has kd or ks > 0" : "no point light");
    return on;
}

static int need_emitter(const frame *f, char *why)
{
    const lc_scene *s = f->s;
    int on = !f->area && lights_lit(f, s->nemitters);
    if (on)
        say(why, "%zu emissive shape%s light %zu material%s with kd or ks > 0, "
            "toward their centres (light_samples = 0)", s->nemitters,
            plural(s->nemitters), f->lit.count, plural(f->lit.count));
    else
        say(why, !s->nemitters ? "no emissive shape" :
            !f->lit.count ? "no material in use has kd or ks > 0" :
            "emitters are sampled as area lights");
    return on;
}

static int need_specular(const frame *f, char *why)
{
    const lc_render_options *o = f->o;
    int on = o->specular && ((f->spec.count && f->lights) || o->generic);
    if (on)
        say(why, "%zu material%s in use with ks > 0 (first: #%zu)", f->spec.count,
            plural(f->spec.count), f->spec.first);
    else
        say(why, !o->specular ? "switched off (specular = false)" : !f->spec.count ?
            "no material in use has ks > 0" : "no light");
    return on;
}

/* Glass reflects too. */
static const char *reflectors(const frame *f)
{
    return f->refr.count ? "kr or kt" : "kr";
}

static int need_reflect(const frame *f, char *why)
{
    const lc_render_options *o = f->o;
    int on = o->reflections && f->depth > 0 && (f->refl.count || o->generic);
    if (on)
        say(why, "%zu material%s in use with %s > 0 (first: #%zu), max_depth %d",
            f->refl.count, plural(f->refl.count), reflectors(f), f->refl.first,
            f->depth);
    else
        say(why, !o->reflections ? "switched off (reflections = false)" :
            !f->refl.count && !f->gloss.count ? "no material in use has kr > 0" :
            !f->refl.count && f->refr.count ?
                "every material in use with kr or kt > 0 has a cone" :
            !f->refl.count ? "every material in use with kr > 0 has a cone" :
            "max_depth is 0");
    return on;
}

/* Light that bounces replaces the ambient stand-in for it; generic keeps it. */
static int ambient_lights(const frame *f)
{
    return f->amb.count && f->ambient && !(f->o->indirect > 0);
}

static int need_ambient(const frame *f, char *why)
{
    int on = ambient_lights(f) || f->o->generic;
    if (on)
        say(why, "ambient light and %zu material%s in use with ka > 0", f->amb.count,
            plural(f->amb.count));
    else
        say(why, !f->ambient ? "no ambient light" : "no material in use has ka > 0");
    return on;
}

static int need_glossy(const frame *f, char *why)
{
    const lc_render_options *o = f->o;
    int on = f->gloss.count && f->depth > 0 && o->reflections;
    if (on)
        say(why, "%zu material%s in use with %s > 0 and a cone (first: #%zu), %s",
            f->gloss.count, plural(f->gloss.count), reflectors(f), f->gloss.first,
            o->cone_samples ? "cone_samples set by the render"
                            : "each its cone_samples");
    else
        say(why, !o->glossy ? "switched off (glossy = false): cones are mirrors" :
            !o->reflections ? "switched off (reflections = false)" : !f->gloss.count ?
            "no material in use has kr > 0 and glossiness > 0" : "max_depth is 0");
    return on;
}

static int need_area(const frame *f, char *why)
{
    const lc_scene *s = f->s;
    int on = f->area && lights_lit(f, s->nemitters);
    if (on)
        say(why, "%zu emissive shape%s light %zu material%s with kd or ks > 0; "
            "%d light samples each per hit", s->nemitters, plural(s->nemitters),
            f->lit.count, plural(f->lit.count), f->o->light_samples);
    else
        say(why, !s->nemitters ? "no emissive shape" : !f->lit.count ?
            "no material in use has kd or ks > 0" :
            "light_samples = 0: one ray to each emitter's centre");
    return on;
}

static int need_lens(const frame *f, char *why)
{
    const lc_camera *cam = &f->s->camera;
    int on = cam->aperture > 0;
    if (on)
        say(why, "camera aperture %g, focus %g", cam->aperture, camera_focus(cam));
    else
        say(why, "camera aperture 0: a pinhole");
    return on;
}

static int need_refract(const frame *f, char *why)
{
    int on = f->refr.count && f->depth > 0;
    if (on)
        say(why, "%zu material%s in use with kt > 0 (first: #%zu), max_depth %d",
            f->refr.count, plural(f->refr.count), f->refr.first, f->depth);
    else
        say(why, !f->refr.count ? "no material in use has kt > 0" : "max_depth is 0");
    return on;
}

/* Shadow rays are traced from lit materials, toward lights; generic, every
** shadow ray walks its hits. */
static int need_filter(const frame *f, char *why)
{
    const lc_render_options *o = f->o;
    int shadow_rays = f->lit.count && f->lights && o->shadows;
    int filters = f->filt.count && shadow_rays;
    int on = filters || (o->generic && f->lights && o->shadows);
    if (on && f->filt.count)
        say(why, "%zu material%s in use with kt > 0 and shadow = 'filtered' "
            "(first: #%zu): shadow rays go through them", f->filt.count,
            plural(f->filt.count), f->filt.first);
    else if (on)
        say(why, "generic: every shadow ray walks its hits");
    else
        say(why, !f->filt.count ?
            "no material in use has kt > 0 and shadow = 'filtered'" :
            !o->shadows ? "shadows off: no shadow rays" : !f->lights ? "no light" :
            "no material in use has kd or ks > 0");
    return on;
}

static int need_texture(const frame *f, char *why)
{
    int on = f->tex.count > 0;
    if (on)
        say(why, "%zu material%s in use with a texture (first: #%zu)", f->tex.count,
            plural(f->tex.count), f->tex.first);
    else
        say(why, "no material in use has a texture");
    return on;
}

static int need_spot(const frame *f, char *why)
{
    const lc_scene *s = f->s;
    int on = lights_lit(f, s->nspots);
    if (on)
        say(why, "%zu spot light%s; %zu of %zu materials in use have kd or ks > 0 "
            "(first: #%zu)", s->nspots, plural(s->nspots), f->lit.count, f->inuse.count,
            f->lit.first);
    else
        say(why, s->nspots ? "no material in use has kd or ks > 0" : "no spot light");
    return on;
}

static int need_sun(const frame *f, char *why)
{
    const lc_scene *s = f->s;
    int on = lights_lit(f, s->nsuns);
    if (on)
        say(why, "%zu directional light%s; %zu of %zu materials in use have kd or ks "
            "> 0 (first: #%zu)", s->nsuns, plural(s->nsuns), f->lit.count,
            f->inuse.count, f->lit.first);
    else
        say(why, s->nsuns ? "no material in use has kd or ks > 0"
                          : "no directional light");
    return on;
}

static int need_sky(const frame *f, char *why)
{
    int on = f->s->settings.background_texture > 0;
    say(why, on ? "the background is a texture over directions" :
        "the background is one colour");
    return on;
}

static int need_indirect(const frame *f, char *why)
{
    const lc_render_options *o = f->o;
    int on = o->indirect > 0;
    if (on)
        say(why, "indirect = %d: paths of up to %d bounce%s%s%s, lights sampled at "
            "each%s",
            o->indirect, o->indirect, plural((size_t)o->indirect),
            f->sky_lights ? ", the sky a light" : "",
            o->roulette ? ", Russian roulette after 3" : "",
            o->nee ? " (MIS)" : " (no: BSDF sampling alone)");
    else
        say(why, "indirect = 0: direct light and mirrors (the seed's model)");
    return on;
}

/* Probes darken the ambient light itself, not generic's stand-in for it. */
static int need_ao(const frame *f, char *why)
{
    const lc_render_options *o = f->o;
    int on = o->ao_samples > 0 && ambient_lights(f);
    if (on)
        say(why, "ambient light darkened by %d probe%s of %g", o->ao_samples,
            plural((size_t)o->ao_samples), o->ao_distance);
    else
        say(why, o->ao_samples == 0 ? "ao off" : o->indirect > 0 ?
            "indirect light replaces ambient light" : "no ambient light to darken");
    return on;
}

/* One row per effect: its bit, and what decides it and writes why into
** why[k] for bit 1 << k. */
typedef struct {
    unsigned need;                                   /* LC_NEED_* */
    int (*decide)(const frame *f, char *why);        /* 1: the frame needs it */
} effect;

static const effect effects[] = {
    {LC_NEED_SHADOW, need_shadow},     {LC_NEED_EMITTER, need_emitter},
    {LC_NEED_SPECULAR, need_specular}, {LC_NEED_REFLECT, need_reflect},
    {LC_NEED_AMBIENT, need_ambient},   {LC_NEED_GLOSSY, need_glossy},
    {LC_NEED_AREA, need_area},         {LC_NEED_LENS, need_lens},
    {LC_NEED_REFRACT, need_refract},   {LC_NEED_FILTER, need_filter},
    {LC_NEED_TEXTURE, need_texture},   {LC_NEED_SPOT, need_spot},
    {LC_NEED_SUN, need_sun},           {LC_NEED_SKY, need_sky},
    {LC_NEED_INDIRECT, need_indirect}, {LC_NEED_AO, need_ao},
};

/* Every LC_NEED_* has its row: the build fails when one is added without. */
typedef char effects_cover_every_need[sizeof effects / sizeof *effects == LC_NEEDS
                                      ? 1 : -1];

static int need_index(unsigned need)
{
    int k = 0;
    while (need >> (k + 1))
        k++;
    return k;
}

/* ---- Each material's plan -------------------------------------------- */

static uint16_t material_plan(const lc_material *raw, unsigned needs,
                              const lc_render_options *o)
{
    lc_material m = material_bound(raw);
    int cone = material_cone(&m, o), reflects = material_reflects(&m);
    uint16_t p = 0;
    if (o->generic) {        /* everything that can run, runs */
        p = PLAN_LIGHTS | PLAN_EMITS | PLAN_AMBIENT |
            (needs & LC_NEED_SPECULAR ? PLAN_SPECULAR : 0) |
            (cone ? (needs & LC_NEED_GLOSSY ? PLAN_GLOSSY : 0)
                  : (needs & LC_NEED_REFLECT ? PLAN_REFLECT : 0));
    } else {
        if (m.kd > 0 || m.ks > 0) p |= PLAN_LIGHTS;
        if (m.ks > 0 && (needs & LC_NEED_SPECULAR)) p |= PLAN_SPECULAR;
        if (reflects && !cone && (needs & LC_NEED_REFLECT)) p |= PLAN_REFLECT;
        if (reflects && cone && (needs & LC_NEED_GLOSSY)) p |= PLAN_GLOSSY;
        if (m.ka > 0 && (needs & LC_NEED_AMBIENT)) p |= PLAN_AMBIENT;
        if ((p & PLAN_AMBIENT) && (needs & LC_NEED_AO)) p |= PLAN_AO;
        if (!c_is_black(m.emission)) p |= PLAN_EMITS;
    }
    /* Only what transmits is a medium or lets shadows through, generic or
    ** not: kt = 0 is opaque. */
    if (m.kt > 0 && (needs & LC_NEED_REFRACT)) p |= PLAN_REFRACT;
    if (m.kt > 0 && m.shadow == LC_SHADOW_FILTERED) p |= PLAN_FILTER;
    if (textured(raw)) p |= PLAN_TEXTURED;
    return p;
}

/* Decides, for a render of s with options o (NULL: the defaults), s->c's
** needs (LC_NEED_*), their whys, depth, sky_uv, sky_lights and per-material
** plan (PLAN_*). Out of memory, the rest of s->c stays as it was. */
static lc_status plan_frame(lc_scene *s, const lc_render_options *o, lc_error *err)
{
    compiled *c = &s->c;
    lc_render_options def = lc_render_options_default();
    if (!o)
        o = &def;
    mem_free(c->plan);
    c->plan = mem_calloc(s->nmaterials + 1, sizeof *c->plan);
    if (!c->plan)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory planning %zu materials",
                       s->nmaterials);
    mark_used(s, c->plan);                  /* 1 = in use, before the plans */
    frame f = frame_of(s, o, c->plan);
    unsigned needs = 0;
    for (size_t i = 0; i < sizeof effects / sizeof *effects; i++)
        if (effects[i].decide(&f, c->why[need_index(effects[i].need)]))
            needs |= effects[i].need;
    c->needs = needs;
    c->depth = f.depth;
    c->sky_lights = f.sky_lights;
    c->sky_uv = (needs & LC_NEED_SKY) &&
                textures_use_uv(s->textures, s->settings.background_texture - 1);
    for (size_t i = 0; i < s->nmaterials; i++)
        c->plan[i] = material_plan(&s->materials[i], needs, o);
    return LC_OK;
}

lc_status plan_scene(lc_scene *s, const lc_render_options *o, sig_atomic_t seen,
                     lc_error *err)
{
    double t0 = clock_seconds();
    lc_status st = compile_geometry(s, seen, err);
    if (st != LC_OK)
        return st;
    compiled *c = &s->c;
    /* Out of memory for the plan: the geometry stays, for the rays that
    ** other threads may be casting into it (query.c). */
    if (plan_frame(s, o, err))
        return LC_ENOMEM;
    if ((c->needs & LC_NEED_INDIRECT) && c->sky_lights && sky_dist_build(s, &c->sky, err))
        return LC_ENOMEM;
    if (!(c->needs & LC_NEED_INDIRECT))
        sky_dist_free(&c->sky);
    c->seconds = clock_seconds() - t0;
    error_ok(err);
    return LC_OK;
}
