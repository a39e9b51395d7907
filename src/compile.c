/* compile.c: turns a scene description into what one render reads, and
** decides once which effects the frame needs. */
#include <stdlib.h>
#include <string.h>
#include "error.h"
#include "scene.h"

void compiled_free(compiled *c)
{
    free(c->spheres);
    free(c->quads);
    free(c->boxes);
    free(c->planes);
    free(c->emitters);
    memset(c, 0, sizeof *c);
}

static int emits(const lc_material *m) { return !c_is_black(m->emission); }

static void make_emitter(const lc_shape *sh, uint32_t id, const lc_material *m, emitter *e)
{
    memset(e, 0, sizeof *e);
    e->shape = id;
    e->kind = sh->kind;
    e->emission = m->emission;
    switch (sh->kind) {
    case LC_SPHERE:
        e->target = sh->p;
        e->radius = sh->radius;
        break;
    case LC_QUAD:
        e->target = v3_add(sh->p, v3_mul(v3_add(sh->u, sh->v), 0.5));
        e->area[0] = v3_cross(sh->u, sh->v);
        break;
    case LC_BOX:
        e->target = v3_add(sh->p, v3_mul(v3_add(v3_add(sh->u, sh->v), sh->w), 0.5));
        e->area[0] = v3_cross(sh->v, sh->w);
        e->area[1] = v3_cross(sh->w, sh->u);
        e->area[2] = v3_cross(sh->u, sh->v);
        break;
    default:
        break;
    }
}

lc_status scene_compile(lc_scene *s, int max_depth, lc_error *err)
{
    compiled *c = &s->c;
    size_t count[LC_SHAPE_KINDS] = {0}, nemit = 0;
    compiled_free(c);
    for (size_t i = 0; i < s->nshapes; i++) {
        count[s->shapes[i].kind]++;
        if (s->shapes[i].kind != LC_PLANE && emits(&s->materials[s->shape_material[i]]))
            nemit++;
    }
    c->spheres = malloc((count[LC_SPHERE] + 1) * sizeof *c->spheres);
    c->quads = malloc((count[LC_QUAD] + 1) * sizeof *c->quads);
    c->boxes = malloc((count[LC_BOX] + 1) * sizeof *c->boxes);
    c->planes = malloc((count[LC_PLANE] + 1) * sizeof *c->planes);
    c->emitters = malloc((nemit + 1) * sizeof *c->emitters);
    if (!c->spheres || !c->quads || !c->boxes || !c->planes || !c->emitters) {
        compiled_free(c);
        return lc_fail(err, LC_ENOMEM, NULL, "out of memory compiling %zu shapes",
                       s->nshapes);
    }

    int lit = 0, specular = 0, reflect = 0, ambient = 0;
    for (size_t i = 0; i < s->nshapes; i++) {
        const lc_shape *sh = &s->shapes[i];
        int mi = s->shape_material[i];
        const lc_material *m = &s->materials[mi];
        uint32_t id = (uint32_t)i;
        switch (sh->kind) {
        case LC_SPHERE: {
            sphere_prim *p = &c->spheres[c->nspheres++];
            sphere_prepare(sh, &p->g); p->shape = id; p->material = mi;
            break;
        }
        case LC_QUAD: {
            quad_prim *p = &c->quads[c->nquads++];
            quad_prepare(sh, &p->g); p->shape = id; p->material = mi;
            break;
        }
        case LC_BOX: {
            box_prim *p = &c->boxes[c->nboxes++];
            box_prepare(sh, &p->g); p->shape = id; p->material = mi;
            break;
        }
        default: {
            plane_prim *p = &c->planes[c->nplanes++];
            plane_prepare(sh, &p->g); p->shape = id; p->material = mi;
            break;
        }
        }
        if (sh->kind != LC_PLANE && emits(m))
            make_emitter(sh, id, m, &c->emitters[c->nemitters++]);
        lit |= m->kd > 0 || m->ks > 0;
        specular |= m->ks > 0;
        reflect |= m->kr > 0;
        ambient |= m->ka > 0;
    }

    /* An effect no visible material can show costs nothing: its code is
    ** never reached, and its rays are never spawned. */
    int has_lights = s->nlights > 0 || c->nemitters > 0;
    c->needs = 0;
    if (lit && s->nlights > 0) c->needs |= LC_NEED_SHADOW;
    if (lit && c->nemitters > 0) c->needs |= LC_NEED_EMITTER;
    if (specular && has_lights) c->needs |= LC_NEED_SPECULAR;
    if (reflect && max_depth > 0) c->needs |= LC_NEED_REFLECT;
    if (ambient && !c_is_black(s->settings.ambient)) c->needs |= LC_NEED_AMBIENT;
    lc_ok(err);
    return LC_OK;
}
