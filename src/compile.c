/* compile.c: what a render needs from the scene: the BVH over every bounded
** primitive (moved meshes as one primitive each), the triangle list, and the
** effects the frame calls for. */
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include "error.h"
#include "scene.h"
#include "clock.h"
#include "camera.h"
#include "interrupt.h"
#include "mem.h"
#include "pair.h"
#include "sky.h"
#include "texture.h"

void compile_free(compiled *c)
{
    sky_dist_free(&c->sky);
    mem_free(c->plan);
    mem_free(c->tris);
    mem_free(c->tleaf);
    bvh_free(&c->bvh);
    memset(c, 0, sizeof *c);
}

#define PARALLEL_FACES 200000   /* below this a thread costs more than it saves */

/* The flat meshes' faces [begin, end) of all of them, in order: those not
** degenerate are listed from tris[begin] on; n says how many. */
typedef struct {
    const lc_scene *s;
    tri_ref *tris;
    size_t   begin, end, n, degenerate;
} list_job;

static void *list_faces(void *arg)
{
    list_job *j = arg;
    size_t at = 0;                         /* faces of the meshes before mesh i */
    for (size_t i = 0; i < j->s->nmeshes && at < j->end; i++) {
        const lc_mesh *m = j->s->meshes[i].mesh;
        if (j->s->meshes[i].xf)
            continue;
        size_t f0 = j->begin > at ? j->begin - at : 0, f1 = j->end - at < m->nf ? j->end - at
                                                                              : m->nf;
        for (size_t f = f0; f < f1; f++) {
            const uint32_t *ix = m->f + 3 * f;
            if (triangle_degenerate(m->v + 3 * ix[0], m->v + 3 * ix[1], m->v + 3 * ix[2])) {
                j->degenerate++;
                continue;
            }
            j->tris[j->begin + j->n].mesh = (uint32_t)i;
            j->tris[j->begin + j->n++].face = (uint32_t)f;
        }
        at += m->nf;
    }
    return NULL;
}

/* Lists the non-degenerate triangles: a zero-area face can never be hit,
** and skipping it here keeps NaN normals out of the renderer. A large
** scene's faces are halved between two threads (the test was 47 ms of
** B3 4M on one), the second half's list moved down if the first skipped
** any. */
static lc_status list_triangles(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    size_t flat = 0;
    for (size_t i = 0; i < s->nmeshes; i++)
        if (!s->meshes[i].xf)
            flat += s->meshes[i].mesh->nf;
    size_t total = instance_faces(s) + flat;   /* those listed once, after the flat ones */
    if (total > PRIM_MAX)
        return error_fail(err, LC_EARG, NULL, "too many triangles: %zu (at most %zu)", total,
                       PRIM_MAX);
    c->tris = mem_alloc((total + 1) * sizeof *c->tris);
    if (!c->tris)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory listing %zu triangles", total);
    size_t half = flat >= PARALLEL_FACES ? flat / 2 : flat;
    list_job jobs[2] = {{s, c->tris, 0, half, 0, 0}, {s, c->tris, half, flat, 0, 0}};
    pair_run(list_faces, &jobs[0], &jobs[1], half < flat);
    if (jobs[0].n < half)
        memmove(c->tris + jobs[0].n, c->tris + half, jobs[1].n * sizeof *c->tris);
    c->ntris = jobs[0].n + jobs[1].n;
    c->degenerate += jobs[0].degenerate + jobs[1].degenerate;
    c->nflat = c->ntris;
    return instance_compile(s, seen, err);
}

/* What a leaf test of each primitive kind costs, in units of a sphere,
** quad or triangle test (each 50-70 instructions, callgrind), for the
** BVH's surface area heuristic. Measured on scenes/bench/mixed.lua and
** instances.lua: a cylinder test 260 instructions (the ray brought into
** its canonical space, then the quadratic), an instance 550 (the ray
** moved, the mesh's own walk and triangles). A leaf of four such is a
** leaf of 16 to 32 unit tests; weighed, the build parts them. A box test
** is 75 instructions to a sphere's 67 (B1), but boxes weigh 2, which
** makes leaves of two: tuned on scenes/bench/city.lua (rays grazing rows
** of roofs), 9.7 % fewer trace instructions than at 1, B1 1.6 % fewer,
** for 1.7 times the city's nodes (0.3 MB). Spheres and triangles stay at
** 1: leaves of two would cost B2 1M and B3 4M 16 and 60 MB of nodes. */
static const float prim_cost[16] = {
    [PRIM_SPHERE] = 1, [PRIM_QUAD] = 1, [PRIM_BOX] = 2, [PRIM_TRIANGLE] = 1,
    [PRIM_PLANE] = 1, [PRIM_INSTANCE] = 8, [PRIM_DISC] = 2, [PRIM_CYLINDER] = 4,
    [PRIM_CONE] = 4, [PRIM_TORUS] = 8, [PRIM_ELLIPSOID] = 3, [PRIM_CSG] = 8,
    [PRIM_CSG_FACE] = 1, [PRIM_CSG_CUT] = 1, [15] = 1};

/* Bounds of the bounded shapes (kind by kind) then of the flat triangles:
** items [begin, end) of that order, on a thread of their own for half of
** a large scene. 4M faces took a quarter of a second on one core, writing
** 112 MB of items the kernel had just mapped; 1M spheres 70 ms. */
typedef struct {
    const lc_scene *s;
    bvh_item *items;
    size_t    begin, end;
    sig_atomic_t seen;
    int       cancelled;
} bound_job;

static int bound_cancelled(bound_job *j, size_t g)
{
    if ((g & 0xffff) == 0xffff && interrupt_count() != j->seen)
        j->cancelled = 1;
    return j->cancelled;
}

static void *bound_items(void *arg)
{
    bound_job *j = arg;
    const lc_scene *s = j->s;
    size_t at = 0;                           /* items before kind k's */
    for (int k = 0; k < LC_SHAPE_KINDS; k++) {
        const shape_list *l = &s->shapes[k];
        if (!shape_bounded((lc_shape_kind)k))
            continue;
        for (size_t g = j->begin > at ? j->begin : at; g < j->end && g < at + l->n; g++) {
            if (bound_cancelled(j, g))
                return NULL;
            bvh_item *it = &j->items[g];
            it->id = PRIM_ID(shape_prim_kind((lc_shape_kind)k), g - at);
            shape_bounds((lc_shape_kind)k, shape_at(l, g - at), it->lo, it->hi);
        }
        at += l->n;
    }
    const compiled *c = &s->c;
    for (size_t g = j->begin > at ? j->begin : at; g < j->end; g++) {
        if (bound_cancelled(j, g))
            return NULL;
        size_t i = g - at;
        const lc_mesh *m = s->meshes[c->tris[i].mesh].mesh;
        const uint32_t *ix = m->f + 3 * c->tris[i].face;
        bvh_item *it = &j->items[g];
        it->id = PRIM_ID(PRIM_TRIANGLE, i);
        triangle_bounds(m->v + 3 * ix[0], m->v + 3 * ix[1], m->v + 3 * ix[2], it->lo, it->hi);
    }
    return NULL;
}

static lc_status build_bvh(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    size_t shapes = 0;
    for (int k = 0; k < LC_SHAPE_KINDS; k++)
        if (shape_bounded((lc_shape_kind)k))
            shapes += s->shapes[k].n;
    size_t n = shapes + c->nflat + c->ninstances + s->ncsgs;
    bvh_item *items = mem_alloc((n + 1) * sizeof *items);
    if (!items)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory bounding %zu primitives", n);
    size_t both = shapes + c->nflat, half = both >= PARALLEL_FACES ? both / 2 : both;
    bound_job jobs[2] = {{s, items, 0, half, seen, 0}, {s, items, half, both, seen, 0}};
    pair_run(bound_items, &jobs[0], &jobs[1], half < both);
    if (jobs[0].cancelled || jobs[1].cancelled) {
        mem_free(items);
        return error_fail(err, LC_ECANCEL, NULL, "render cancelled");
    }
    bvh_item *it = items + both;
    for (size_t i = 0; i < s->nmeshes; i++)
        if (s->meshes[i].xf) {
            it->id = PRIM_ID(PRIM_INSTANCE, i);
            instance_bounds(s, i, it->lo, it->hi);
            it++;
        }
    for (size_t i = 0; i < s->ncsgs; i++, it++) {  /* each CSG object one primitive */
        it->id = PRIM_ID(PRIM_CSG, i);
        csg_bounds(s->csgs[i], it->lo, it->hi);
    }
    lc_status st = bvh_build_costed(&c->bvh, items, n, prim_cost, seen, err);
    if (st != LC_OK || c->nflat == 0)
        return st;
    c->tleaf = compile_tri_leaves(s, &c->bvh);
    if (!c->tleaf)
        return error_fail(err, LC_ENOMEM, NULL, "out of memory listing %zu triangles", c->nflat);
    return LC_OK;
}

/* Refs [begin, end) of a BVH: their faces' corners beside them. */
typedef struct {
    const lc_scene *s;
    const bvh *b;
    tri_leaf *tl;
    size_t    begin, end;
} leaves_job;

static void *list_leaves(void *arg)
{
    const leaves_job *j = arg;
    for (size_t r = j->begin; r < j->end; r++) {
        uint32_t id = j->b->refs[r];
        if (PRIM_KIND(id) != PRIM_TRIANGLE)
            continue;
        const tri_ref *tr = &j->s->c.tris[PRIM_INDEX(id)];
        const uint32_t *ix = j->s->meshes[tr->mesh].mesh->f + 3 * (size_t)tr->face;
        j->tl[r] = (tri_leaf){tr->mesh, {ix[0], ix[1], ix[2]}};
    }
    return NULL;
}

/* Halved between two threads for a large scene: 40 ms of B3 4M on one. */
tri_leaf *compile_tri_leaves(const lc_scene *s, const bvh *b)
{
    tri_leaf *tl = mem_alloc((b->nrefs + 1) * sizeof *tl);
    if (!tl)
        return NULL;
    size_t half = b->nrefs >= PARALLEL_FACES ? b->nrefs / 2 : b->nrefs;
    leaves_job jobs[2] = {{s, b, tl, 0, half}, {s, b, tl, half, b->nrefs}};
    pair_run(list_leaves, &jobs[0], &jobs[1], half < b->nrefs);
    return tl;
}

/* A material reflects through a cone when it has one wider than an ulp of a
** unit vector (narrower ones trace exactly the mirror ray: a mirror is
** cheaper and bit-identical) and the render has not switched cones off. */
static int material_cone(const lc_material *m, const lc_render_options *o)
{
    return o->glossy && sin(m->glossiness * (PI / 180)) > DBL_EPSILON;
}

int compile_depth(const lc_scene *s, const lc_render_options *o)
{
    return o && o->max_depth >= 0 ? o->max_depth : s->settings.max_depth;
}

/* First material in use (1-based, in the order the scene met them) with
** the property, and how many have it. */
typedef struct { size_t count, first; } census;

static void count(census *c, size_t i)
{
    if (c->count++ == 0)
        c->first = i + 1;
}

/* Decides the effects the frame needs and why, and each material's plan:
** an effect no material in use can show is never reached by the render
** loop and spawns no ray. */
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

static lc_status decide_needs(lc_scene *s, const lc_render_options *o, lc_error *err)
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
    uint16_t *used = c->plan;               /* 1 = in use, before the plans */
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
    census lit = {0, 0}, spec = {0, 0}, refl = {0, 0}, gloss = {0, 0}, amb = {0, 0},
           inuse = {0, 0}, refr = {0, 0}, filt = {0, 0}, tex = {0, 0};
    for (size_t i = 0; i < s->nmaterials; i++) {
        lc_material mc = material_bound(&s->materials[i]);
        const lc_material *m = &mc;
        if (!used[i])
            continue;
        if (textured(&s->materials[i])) count(&tex, i);
        count(&inuse, i);
        /* A dielectric reflects (Fresnel, or total internal reflection)
        ** whatever its kr. */
        int reflects = m->kr > 0 || m->kt > 0;
        if (m->kd > 0 || m->ks > 0) count(&lit, i);
        if (m->ks > 0) count(&spec, i);
        if (reflects && !material_cone(m, o)) count(&refl, i);
        if (reflects && material_cone(m, o)) count(&gloss, i);
        if (m->ka > 0) count(&amb, i);
        if (m->kt > 0) count(&refr, i);
        if (m->kt > 0 && m->shadow == LC_SHADOW_FILTERED) count(&filt, i);
    }
    int depth = compile_depth(s, o);
    /* For paths, a background that is not black is a light too. */
    int sky_lights = o->indirect > 0 && (s->settings.background_texture > 0 ||
                                         !c_is_black(s->settings.background));
    int lights = s->nlights > 0 || s->nemitters > 0 || s->nspots > 0 || s->nsuns > 0 ||
                 sky_lights;
    int ambient = !c_is_black(s->settings.ambient);
    int area = o->light_samples > 0;
    unsigned needs = 0;
    if (lit.count && s->nlights > 0) needs |= LC_NEED_SHADOW;
    if (lit.count && s->nspots > 0) needs |= LC_NEED_SPOT;
    if (lit.count && s->nsuns > 0) needs |= LC_NEED_SUN;
    if (s->settings.background_texture > 0) needs |= LC_NEED_SKY;
    c->sky_uv = (needs & LC_NEED_SKY) &&
                textures_use_uv(s->textures, s->settings.background_texture - 1);
    if (lit.count && s->nemitters > 0) needs |= area ? LC_NEED_AREA : LC_NEED_EMITTER;
    if (spec.count && lights && o->specular) needs |= LC_NEED_SPECULAR;
    if (refl.count && depth > 0 && o->reflections) needs |= LC_NEED_REFLECT;
    if (gloss.count && depth > 0 && o->reflections) needs |= LC_NEED_GLOSSY;
    if (amb.count && ambient) needs |= LC_NEED_AMBIENT;
    if (s->camera.aperture > 0) needs |= LC_NEED_LENS;
    if (refr.count && depth > 0) needs |= LC_NEED_REFRACT;
    /* Shadow rays are traced from lit materials, toward lights. */
    int shadow_rays = lit.count && lights && o->shadows;
    if (filt.count && shadow_rays) needs |= LC_NEED_FILTER;
    if (tex.count) needs |= LC_NEED_TEXTURE;
    /* Light that bounces replaces the ambient stand-in for it. */
    if (o->indirect > 0) needs = (needs | LC_NEED_INDIRECT) & ~(unsigned)LC_NEED_AMBIENT;
    if (o->ao_samples > 0 && (needs & LC_NEED_AMBIENT)) needs |= LC_NEED_AO;
    if (o->generic) {        /* everything that can run, runs */
        if (s->nlights) needs |= LC_NEED_SHADOW;
        if (s->nspots) needs |= LC_NEED_SPOT;
        if (s->nsuns) needs |= LC_NEED_SUN;
        if (s->nemitters) needs |= area ? LC_NEED_AREA : LC_NEED_EMITTER;
        if (o->specular) needs |= LC_NEED_SPECULAR;
        if (o->reflections && depth > 0) needs |= LC_NEED_REFLECT;
        if (o->reflections && depth > 0 && gloss.count) needs |= LC_NEED_GLOSSY;
        needs |= LC_NEED_AMBIENT;
        if (lights && o->shadows) needs |= LC_NEED_FILTER;   /* shadows walk every hit */
    }
    c->needs = needs;
    c->depth = depth;
    c->sky_lights = sky_lights;

#define WHY(k, ...) snprintf(c->why[k], sizeof c->why[k], __VA_ARGS__)
    if (needs & LC_NEED_SHADOW)
        WHY(0, "%zu point light%s; %zu of %zu materials in use have kd or ks > 0 "
            "(first: #%zu)%s", s->nlights, s->nlights == 1 ? "" : "s", lit.count,
            inuse.count, lit.first, o->shadows ? "" : "; shadows off: no shadow rays");
    else
        WHY(0, s->nlights ? "no material in use has kd or ks > 0" : "no point light");
    if (needs & LC_NEED_EMITTER)
        WHY(1, "%zu emissive shape%s light %zu material%s with kd or ks > 0, "
            "toward their centres (light_samples = 0)",
            s->nemitters, s->nemitters == 1 ? "" : "s", lit.count, lit.count == 1 ? "" : "s");
    else
        WHY(1, !s->nemitters ? "no emissive shape" : !lit.count ?
            "no material in use has kd or ks > 0" : "emitters are sampled as area lights");
    if (needs & LC_NEED_SPECULAR)
        WHY(2, "%zu material%s in use with ks > 0 (first: #%zu)", spec.count,
            spec.count == 1 ? "" : "s", spec.first);
    else
        WHY(2, !o->specular ? "switched off (specular = false)" : !spec.count ?
            "no material in use has ks > 0" : "no light");
    const char *krt = refr.count ? "kr or kt" : "kr";   /* glass reflects too */
    if (needs & LC_NEED_REFLECT)
        WHY(3, "%zu material%s in use with %s > 0 (first: #%zu), max_depth %d",
            refl.count, refl.count == 1 ? "" : "s", krt, refl.first, depth);
    else
        WHY(3, !o->reflections ? "switched off (reflections = false)" :
            !refl.count && !gloss.count ? "no material in use has kr > 0" :
            !refl.count && refr.count ?
                "every material in use with kr or kt > 0 has a cone" :
            !refl.count ? "every material in use with kr > 0 has a cone" : "max_depth is 0");
    if (needs & LC_NEED_AMBIENT)
        WHY(4, "ambient light and %zu material%s in use with ka > 0", amb.count,
            amb.count == 1 ? "" : "s");
    else
        WHY(4, !ambient ? "no ambient light" : "no material in use has ka > 0");
    if (needs & LC_NEED_GLOSSY)
        WHY(5, "%zu material%s in use with %s > 0 and a cone (first: #%zu), %s",
            gloss.count, gloss.count == 1 ? "" : "s", krt, gloss.first,
            o->cone_samples ? "cone_samples set by the render" : "each its cone_samples");
    else
        WHY(5, !o->glossy ? "switched off (glossy = false): cones are mirrors" :
            !o->reflections ? "switched off (reflections = false)" : !gloss.count ?
            "no material in use has kr > 0 and glossiness > 0" : "max_depth is 0");
    if (needs & LC_NEED_AREA)
        WHY(6, "%zu emissive shape%s light %zu material%s with kd or ks > 0; "
            "%d light samples each per hit", s->nemitters, s->nemitters == 1 ? "" : "s",
            lit.count, lit.count == 1 ? "" : "s", o->light_samples);
    else
        WHY(6, !s->nemitters ? "no emissive shape" : !lit.count ?
            "no material in use has kd or ks > 0" :
            "light_samples = 0: one ray to each emitter's centre");
    if (needs & LC_NEED_LENS)
        WHY(7, "camera aperture %g, focus %g", s->camera.aperture,
            camera_focus(&s->camera));
    else
        WHY(7, "camera aperture 0: a pinhole");
    if (needs & LC_NEED_REFRACT)
        WHY(8, "%zu material%s in use with kt > 0 (first: #%zu), max_depth %d",
            refr.count, refr.count == 1 ? "" : "s", refr.first, depth);
    else
        WHY(8, !refr.count ? "no material in use has kt > 0" : "max_depth is 0");
    if ((needs & LC_NEED_FILTER) && filt.count)
        WHY(9, "%zu material%s in use with kt > 0 and shadow = 'filtered' "
            "(first: #%zu): shadow rays go through them", filt.count,
            filt.count == 1 ? "" : "s", filt.first);
    else if (needs & LC_NEED_FILTER)
        WHY(9, "generic: every shadow ray walks its hits");
    else
        WHY(9, !filt.count ? "no material in use has kt > 0 and shadow = 'filtered'" :
            !o->shadows ? "shadows off: no shadow rays" : !lights ? "no light" :
            "no material in use has kd or ks > 0");
    if (needs & LC_NEED_TEXTURE)
        WHY(10, "%zu material%s in use with a texture (first: #%zu)", tex.count,
            tex.count == 1 ? "" : "s", tex.first);
    else
        WHY(10, "no material in use has a texture");
    if (needs & LC_NEED_SPOT)
        WHY(11, "%zu spot light%s; %zu of %zu materials in use have kd or ks > 0 "
            "(first: #%zu)", s->nspots, s->nspots == 1 ? "" : "s", lit.count,
            inuse.count, lit.first);
    else
        WHY(11, s->nspots ? "no material in use has kd or ks > 0" : "no spot light");
    if (needs & LC_NEED_SUN)
        WHY(12, "%zu directional light%s; %zu of %zu materials in use have kd or ks > 0 "
            "(first: #%zu)", s->nsuns, s->nsuns == 1 ? "" : "s", lit.count,
            inuse.count, lit.first);
    else
        WHY(12, s->nsuns ? "no material in use has kd or ks > 0" : "no directional light");
    if (needs & LC_NEED_SKY)
        WHY(13, "the background is a texture over directions");
    else
        WHY(13, "the background is one colour");
    if (needs & LC_NEED_INDIRECT)
        WHY(14, "indirect = %d: paths of up to %d bounce%s%s%s, lights sampled at each%s",
            o->indirect, o->indirect, o->indirect == 1 ? "" : "s",
            sky_lights ? ", the sky a light" : "",
            o->roulette ? ", Russian roulette after 3" : "",
            o->nee ? " (MIS)" : " (no: BSDF sampling alone)");
    else
        WHY(14, "indirect = 0: direct light and mirrors (the seed's model)");
    if (needs & LC_NEED_AO)
        WHY(15, "ambient light darkened by %d probe%s of %g", o->ao_samples,
            o->ao_samples == 1 ? "" : "s", o->ao_distance);
    else
        WHY(15, o->ao_samples == 0 ? "ao off" : o->indirect > 0 ?
            "indirect light replaces ambient light" : "no ambient light to darken");
#undef WHY

    for (size_t i = 0; i < s->nmaterials; i++) {
        lc_material mc = material_bound(&s->materials[i]);
        const lc_material *m = &mc;
        int cone = material_cone(m, o);
        int reflects = m->kr > 0 || m->kt > 0;
        uint16_t p = textured(&s->materials[i]) ? PLAN_TEXTURED : 0;
        if (m->kd > 0 || m->ks > 0) p |= PLAN_LIGHTS;
        if (m->ks > 0 && (needs & LC_NEED_SPECULAR)) p |= PLAN_SPECULAR;
        if (reflects && !cone && (needs & LC_NEED_REFLECT)) p |= PLAN_REFLECT;
        if (reflects && cone && (needs & LC_NEED_GLOSSY)) p |= PLAN_GLOSSY;
        if (m->ka > 0 && (needs & LC_NEED_AMBIENT)) p |= PLAN_AMBIENT;
        if ((p & PLAN_AMBIENT) && (needs & LC_NEED_AO)) p |= PLAN_AO;
        if (!c_is_black(m->emission)) p |= PLAN_EMITS;
        if (o->generic)
            p = PLAN_LIGHTS | PLAN_EMITS | PLAN_AMBIENT |
                (needs & LC_NEED_SPECULAR ? PLAN_SPECULAR : 0) |
                (cone ? (needs & LC_NEED_GLOSSY ? PLAN_GLOSSY : 0)
                      : (needs & LC_NEED_REFLECT ? PLAN_REFLECT : 0));
        /* Only what transmits is a medium or lets shadows through, generic
        ** or not: kt = 0 is opaque. */
        if (m->kt > 0 && (needs & LC_NEED_REFRACT)) p |= PLAN_REFRACT;
        if (m->kt > 0 && m->shadow == LC_SHADOW_FILTERED) p |= PLAN_FILTER;
        if (textured(&s->materials[i]))
            p |= PLAN_TEXTURED;
        c->plan[i] = p;
    }
    return LC_OK;
}

lc_status compile_geometry(lc_scene *s, sig_atomic_t seen, lc_error *err)
{
    compiled *c = &s->c;
    size_t faces = 0;
    for (size_t i = 0; i < s->nmeshes; i++)
        faces += s->meshes[i].mesh->nf;
    if (!c->valid || c->faces_seen != faces) {     /* geometry changed since */
        compile_free(c);
        lc_status st = list_triangles(s, seen, err);
        if (st == LC_OK)
            st = build_bvh(s, seen, err);
        if (st != LC_OK) {
            compile_free(c);
            return st;
        }
        c->valid = 1;
        c->faces_seen = faces;
    }
    error_ok(err);
    return LC_OK;
}

lc_status compile_scene(lc_scene *s, const lc_render_options *o, sig_atomic_t seen,
                        lc_error *err)
{
    double t0 = clock_seconds();
    lc_status st = compile_geometry(s, seen, err);
    if (st != LC_OK)
        return st;
    compiled *c = &s->c;
    /* Out of memory for the plan: the geometry stays, for the rays that
    ** other threads may be casting into it (query.c). */
    if (decide_needs(s, o, err))
        return LC_ENOMEM;
    if ((c->needs & LC_NEED_INDIRECT) && c->sky_lights && sky_dist_build(s, &c->sky, err))
        return LC_ENOMEM;
    if (!(c->needs & LC_NEED_INDIRECT))
        sky_dist_free(&c->sky);
    c->seconds = clock_seconds() - t0;
    error_ok(err);
    return LC_OK;
}
