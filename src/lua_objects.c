/* lua_objects.c: materials, shapes, point lights and cameras: the scene's values. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_types.h"

static const char *const shape_names[LC_SHAPE_KINDS] = {"sphere", "quad", "box", "plane"};

/* ---- small helpers ---------------------------------------------------------- */

static void buf_num(luaL_Buffer *b, double x)
{
    char tmp[40];
    snprintf(tmp, sizeof tmp, "%.6g", x);
    luaL_addstring(b, tmp);
}

static void buf_vec(luaL_Buffer *b, const char *name, lc_vec3 v)
{
    luaL_addstring(b, name);
    luaL_addstring(b, " = {");
    buf_num(b, v.x);
    luaL_addstring(b, ", ");
    buf_num(b, v.y);
    luaL_addstring(b, ", ");
    buf_num(b, v.z);
    luaL_addstring(b, "}");
}

static void buf_color(luaL_Buffer *b, const char *name, lc_color c)
{
    lc_vec3 v = {c.r, c.g, c.b};
    buf_vec(b, name, v);
}

/* ---- materials ------------------------------------------------------------ */

static const char *const absorb_opts[] = {"all", "diffuse", NULL};

static int w_material(lua_State *L)
{
    static const char *const known[] = {"color", "ka", "kd", "kr", "ks", "alpha",
                                        "emission", "absorb", "glossiness",
                                        "cone_samples", NULL};
    lf_open(L, 1, known);
    lc_material m = lc_material_default();
    m.color = lf_color(L, 1, "color", 0, m.color);
    m.ka = lf_number(L, 1, "ka", 0, m.ka);
    m.kd = lf_number(L, 1, "kd", 0, m.kd);
    m.kr = lf_number(L, 1, "kr", 0, m.kr);
    m.ks = lf_number(L, 1, "ks", 0, m.ks);
    m.alpha = lf_number(L, 1, "alpha", 0, m.alpha);
    m.emission = lf_color(L, 1, "emission", 0, m.emission);
    m.absorb = (lc_absorb)lf_option(L, 1, "absorb", absorb_opts, (int)m.absorb);
    m.glossiness = lf_number(L, 1, "glossiness", 0, m.glossiness);
    m.cone_samples = lf_integer(L, 1, "cone_samples", 0, m.cone_samples);
    lc_error err;
    if (lc_material_check(&m, &err))
        return lf_raise(L, 1, &err);
    ud_material *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->m = m;
    luaL_setmetatable(L, MATERIAL);
    return 1;
}

static int w_material_tostring(lua_State *L)
{
    const lc_material *m = &((ud_material *)luaL_checkudata(L, 1, MATERIAL))->m;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.material{");
    buf_color(&b, "color", m->color);
    const char *names[] = {"ka", "kd", "kr", "ks", "alpha", "glossiness", "cone_samples"};
    double vals[] = {m->ka, m->kd, m->kr, m->ks, m->alpha, m->glossiness, m->cone_samples};
    for (int i = 0; i < 7; i++) {
        luaL_addstring(&b, ", ");
        luaL_addstring(&b, names[i]);
        luaL_addstring(&b, " = ");
        buf_num(&b, vals[i]);
    }
    luaL_addstring(&b, ", ");
    buf_color(&b, "emission", m->emission);
    luaL_addstring(&b, ", absorb = '");
    luaL_addstring(&b, absorb_opts[m->absorb]);
    luaL_addstring(&b, "'}");
    luaL_pushresult(&b);
    return 1;
}

static int w_material_index(lua_State *L)
{
    const lc_material *m = &((ud_material *)luaL_checkudata(L, 1, MATERIAL))->m;
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "color") == 0) lf_push_color(L, m->color);
    else if (strcmp(k, "emission") == 0) lf_push_color(L, m->emission);
    else if (strcmp(k, "ka") == 0) lua_pushnumber(L, m->ka);
    else if (strcmp(k, "kd") == 0) lua_pushnumber(L, m->kd);
    else if (strcmp(k, "kr") == 0) lua_pushnumber(L, m->kr);
    else if (strcmp(k, "ks") == 0) lua_pushnumber(L, m->ks);
    else if (strcmp(k, "alpha") == 0) lua_pushnumber(L, m->alpha);
    else if (strcmp(k, "glossiness") == 0) lua_pushnumber(L, m->glossiness);
    else if (strcmp(k, "cone_samples") == 0) lua_pushinteger(L, m->cone_samples);
    else if (strcmp(k, "absorb") == 0) lua_pushstring(L, absorb_opts[m->absorb]);
    else lua_pushnil(L);
    return 1;
}

/* ---- shapes --------------------------------------------------------------- */

/* Validates, then pushes the shape userdata holding `s` and its material. */
static int push_shape(lua_State *L, const lc_shape *s)
{
    lf_udata(L, 1, "material", MATERIAL, 0);        /* pushes it, or nil */
    lc_error err;
    if (lc_shape_check(s, &err))
        return lf_raise(L, 1, &err);
    ud_shape *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->s = *s;
    lua_insert(L, -2);
    lua_setiuservalue(L, -2, 1);
    luaL_setmetatable(L, SHAPE);
    return 1;
}

void push_shape_value(lua_State *L, const lc_shape *s, int mat)
{
    mat = lua_absindex(L, mat);
    ud_shape *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->s = *s;
    lua_pushvalue(L, mat);
    lua_setiuservalue(L, -2, 1);
    luaL_setmetatable(L, SHAPE);
}

void push_light_value(lua_State *L, const lc_point_light *l)
{
    ud_light *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->l = *l;
    luaL_setmetatable(L, LIGHT);
}

static int w_sphere(lua_State *L)
{
    static const char *const known[] = {"center", "radius", "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_SPHERE;
    s.p = lf_vec3(L, 1, "center", 1, s.p);
    s.radius = lf_number(L, 1, "radius", 1, 0);
    return push_shape(L, &s);
}

static int w_quad(lua_State *L)
{
    static const char *const known[] = {"corner", "u", "v", "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_QUAD;
    s.p = lf_vec3(L, 1, "corner", 1, s.p);
    s.u = lf_vec3(L, 1, "u", 1, s.u);
    s.v = lf_vec3(L, 1, "v", 1, s.v);
    return push_shape(L, &s);
}

static int w_box(lua_State *L)
{
    static const char *const known[] = {"corner", "u", "v", "w", "min", "max",
                                        "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_BOX;
    if (lf_present(L, 1, "min") || lf_present(L, 1, "max")) {
        const char *other[] = {"corner", "u", "v", "w"};
        for (int i = 0; i < 4; i++)
            if (lf_present(L, 1, other[i]))
                return lf_error(L, 1, other[i], "give either min and max, or corner "
                                "and u, v, w, not both");
        lc_vec3 lo = lf_vec3(L, 1, "min", 1, s.p), hi = lf_vec3(L, 1, "max", 1, s.p);
        double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
        for (int i = 0; i < 3; i++)
            if (!(h[i] > l[i]))
                return lf_error(L, 1, "max", "component %d must be > min's, got %g <= %g",
                                i + 1, h[i], l[i]);
        s.p = lo;
        s.u.x = hi.x - lo.x;
        s.v.y = hi.y - lo.y;
        s.w.z = hi.z - lo.z;
    } else {
        s.p = lf_vec3(L, 1, "corner", 1, s.p);
        s.u = lf_vec3(L, 1, "u", 1, s.u);
        s.v = lf_vec3(L, 1, "v", 1, s.v);
        s.w = lf_vec3(L, 1, "w", 1, s.w);
    }
    return push_shape(L, &s);
}

static int w_plane(lua_State *L)
{
    static const char *const known[] = {"point", "normal", "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_PLANE;
    s.p = lf_vec3(L, 1, "point", 1, s.p);
    s.u = lf_vec3(L, 1, "normal", 1, s.u);
    return push_shape(L, &s);
}

static int w_shape_tostring(lua_State *L)
{
    const lc_shape *s = &((ud_shape *)luaL_checkudata(L, 1, SHAPE))->s;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.");
    luaL_addstring(&b, shape_names[s->kind]);
    luaL_addstring(&b, "{");
    switch (s->kind) {
    case LC_SPHERE:
        buf_vec(&b, "center", s->p);
        luaL_addstring(&b, ", radius = ");
        buf_num(&b, s->radius);
        break;
    case LC_QUAD:
        buf_vec(&b, "corner", s->p);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "u", s->u);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "v", s->v);
        break;
    case LC_BOX:
        buf_vec(&b, "corner", s->p);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "u", s->u);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "v", s->v);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "w", s->w);
        break;
    default:
        buf_vec(&b, "point", s->p);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "normal", s->u);
        break;
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    return 1;
}

static int w_shape_index(lua_State *L)
{
    const lc_shape *s = &((ud_shape *)luaL_checkudata(L, 1, SHAPE))->s;
    const char *k = luaL_checkstring(L, 2);
    int sph = s->kind == LC_SPHERE, pl = s->kind == LC_PLANE;
    if (strcmp(k, "kind") == 0) lua_pushstring(L, shape_names[s->kind]);
    else if (strcmp(k, "material") == 0) lua_getiuservalue(L, 1, 1);
    else if (sph && strcmp(k, "center") == 0) lf_push_vec3(L, s->p);
    else if (sph && strcmp(k, "radius") == 0) lua_pushnumber(L, s->radius);
    else if (pl && strcmp(k, "point") == 0) lf_push_vec3(L, s->p);
    else if (pl && strcmp(k, "normal") == 0) lf_push_vec3(L, s->u);
    else if (!sph && !pl && strcmp(k, "corner") == 0) lf_push_vec3(L, s->p);
    else if (!sph && !pl && strcmp(k, "u") == 0) lf_push_vec3(L, s->u);
    else if (!sph && !pl && strcmp(k, "v") == 0) lf_push_vec3(L, s->v);
    else if (s->kind == LC_BOX && strcmp(k, "w") == 0) lf_push_vec3(L, s->w);
    else if (strcmp(k, "moved") == 0) lua_pushcfunction(L, motion_moved);
    else lua_pushnil(L);
    return 1;
}


/* ---- lights and cameras ----------------------------------------------------- */

static const char *const falloff_opts[] = {"inverse_square", "none", NULL};

static int w_point_light(lua_State *L)
{
    static const char *const known[] = {"position", "color", "intensity", "falloff", NULL};
    lf_open(L, 1, known);
    lc_point_light l = lc_point_light_default();
    l.position = lf_vec3(L, 1, "position", 1, l.position);
    l.color = lf_color(L, 1, "color", 0, l.color);
    l.intensity = lf_number(L, 1, "intensity", 0, l.intensity);
    l.falloff = (lc_falloff)lf_option(L, 1, "falloff", falloff_opts, (int)l.falloff);
    lc_error err;
    if (lc_point_light_check(&l, &err))
        return lf_raise(L, 1, &err);
    ud_light *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->l = l;
    luaL_setmetatable(L, LIGHT);
    return 1;
}

static int w_light_tostring(lua_State *L)
{
    const lc_point_light *l = &((ud_light *)luaL_checkudata(L, 1, LIGHT))->l;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.point_light{");
    buf_vec(&b, "position", l->position);
    luaL_addstring(&b, ", ");
    buf_color(&b, "color", l->color);
    luaL_addstring(&b, ", intensity = ");
    buf_num(&b, l->intensity);
    luaL_addstring(&b, ", falloff = '");
    luaL_addstring(&b, falloff_opts[l->falloff]);
    luaL_addstring(&b, "'}");
    luaL_pushresult(&b);
    return 1;
}

static int w_light_index(lua_State *L)
{
    const lc_point_light *l = &((ud_light *)luaL_checkudata(L, 1, LIGHT))->l;
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "kind") == 0) lua_pushstring(L, "point_light");
    else if (strcmp(k, "position") == 0) lf_push_vec3(L, l->position);
    else if (strcmp(k, "color") == 0) lf_push_color(L, l->color);
    else if (strcmp(k, "intensity") == 0) lua_pushnumber(L, l->intensity);
    else if (strcmp(k, "falloff") == 0) lua_pushstring(L, falloff_opts[l->falloff]);
    else if (strcmp(k, "moved") == 0) lua_pushcfunction(L, motion_moved);
    else lua_pushnil(L);
    return 1;
}

static int w_camera(lua_State *L)
{
    static const char *const known[] = {"from", "at", "up", "fov", "aperture", "focus",
                                        NULL};
    lf_open(L, 1, known);
    lc_camera c = lc_camera_default();
    c.from = lf_vec3(L, 1, "from", 1, c.from);
    c.at = lf_vec3(L, 1, "at", 1, c.at);
    c.up = lf_vec3(L, 1, "up", 0, c.up);
    c.fov = lf_number(L, 1, "fov", 0, c.fov);
    c.aperture = lf_number(L, 1, "aperture", 0, c.aperture);
    c.focus = lf_number(L, 1, "focus", 0, c.focus);
    lc_error err;
    if (lc_camera_check(&c, &err))
        return lf_raise(L, 1, &err);
    ud_camera *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->c = c;
    luaL_setmetatable(L, CAMERA);
    return 1;
}

static int w_camera_tostring(lua_State *L)
{
    const lc_camera *c = &((ud_camera *)luaL_checkudata(L, 1, CAMERA))->c;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.camera{");
    buf_vec(&b, "from", c->from);
    luaL_addstring(&b, ", ");
    buf_vec(&b, "at", c->at);
    luaL_addstring(&b, ", ");
    buf_vec(&b, "up", c->up);
    luaL_addstring(&b, ", fov = ");
    buf_num(&b, c->fov);
    if (c->aperture > 0) {
        luaL_addstring(&b, ", aperture = ");
        buf_num(&b, c->aperture);
        luaL_addstring(&b, ", focus = ");
        buf_num(&b, c->focus);
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    return 1;
}

static int w_camera_index(lua_State *L)
{
    const lc_camera *c = &((ud_camera *)luaL_checkudata(L, 1, CAMERA))->c;
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "from") == 0) lf_push_vec3(L, c->from);
    else if (strcmp(k, "at") == 0) lf_push_vec3(L, c->at);
    else if (strcmp(k, "up") == 0) lf_push_vec3(L, c->up);
    else if (strcmp(k, "fov") == 0) lua_pushnumber(L, c->fov);
    else if (strcmp(k, "aperture") == 0) lua_pushnumber(L, c->aperture);
    else if (strcmp(k, "focus") == 0) lua_pushnumber(L, c->focus);
    else lua_pushnil(L);
    return 1;
}


void objects_register(lua_State *L)
{
    static const luaL_Reg material_meta[] = {
        {"__tostring", w_material_tostring}, {"__index", w_material_index}, {NULL, NULL}};
    static const luaL_Reg shape_meta[] = {
        {"__tostring", w_shape_tostring}, {"__index", w_shape_index}, {NULL, NULL}};
    static const luaL_Reg light_meta[] = {
        {"__tostring", w_light_tostring}, {"__index", w_light_index}, {NULL, NULL}};
    static const luaL_Reg camera_meta[] = {
        {"__tostring", w_camera_tostring}, {"__index", w_camera_index}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"material", w_material}, {"sphere", w_sphere}, {"quad", w_quad}, {"box", w_box},
        {"plane", w_plane}, {"point_light", w_point_light}, {"camera", w_camera},
        {NULL, NULL}};
    binding_class(L, MATERIAL, material_meta, NULL);
    binding_class(L, SHAPE, shape_meta, NULL);
    binding_class(L, LIGHT, light_meta, NULL);
    binding_class(L, CAMERA, camera_meta, NULL);
    luaL_setfuncs(L, funcs, 0);
}
