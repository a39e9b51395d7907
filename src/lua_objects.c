/* lua_objects.c: materials, lights (point, spot, directional) and cameras
** (shapes: lua_shapes.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* ---- small helpers ---------------------------------------------------------- */

static void buf_color(luaL_Buffer *b, const char *name, lc_color c)
{
    lc_vec3 v = {c.r, c.g, c.b};
    lf_add_vec3(b, name, v);
}

/* ---- materials ------------------------------------------------------------ */

static const char *const absorb_opts[] = {"all", "diffuse", NULL};
static const char *const shadow_opts[] = {"filtered", "opaque", NULL};

/* A colour at idx kept in double (absorption is a length's inverse, not a
** float colour): {r, g, b} or one number for grey. */
static int to_rgb(lua_State *L, int idx, lc_vec3 *v, char *why, size_t n)
{
    if (lua_type(L, idx) == LUA_TNUMBER) {
        double g = lua_tonumber(L, idx);
        if (!isfinite(g)) {
            snprintf(why, n, "must be finite, got %g", g);
            return 0;
        }
        v->x = v->y = v->z = g;
        return 1;
    }
    if (lua_type(L, idx) != LUA_TTABLE) {
        snprintf(why, n, "colour {r, g, b} or number expected, got %s",
                 luaL_typename(L, idx));
        return 0;
    }
    return lf_to_vec3(L, idx, v, why, n);
}

/* absorption = {r, g, b} per unit length, or transmittance = {colour, d}:
** the share of each channel left after a distance d, as its absorption
** -ln(colour) / d. One of the two, or neither (no absorption). */
static lc_vec3 read_absorption(lua_State *L, lc_vec3 def)
{
    char why[200];
    int both = lf_present(L, 1, "absorption") && lf_present(L, 1, "transmittance");
    if (both)
        lf_error(L, 1, "transmittance", "'absorption' is given too: give one of them");
    if (lua_getfield(L, 1, "absorption") != LUA_TNIL) {
        if (!to_rgb(L, -1, &def, why, sizeof why))
            lf_error(L, 1, "absorption", "%s", why);
    }
    lua_pop(L, 1);
    if (lua_getfield(L, 1, "transmittance") == LUA_TNIL) {
        lua_pop(L, 1);
        return def;
    }
    int t = lua_gettop(L);
    if (lua_type(L, t) != LUA_TTABLE)
        lf_error(L, 1, "transmittance", "{colour, distance} expected, got %s",
                 luaL_typename(L, t));
    if (luaL_len(L, t) != 2)
        lf_error(L, 1, "transmittance", "{colour, distance} expected, got %lld entries",
                 (long long)luaL_len(L, t));
    lc_vec3 c;
    lua_geti(L, t, 1);
    if (!to_rgb(L, -1, &c, why, sizeof why))
        lf_error(L, 1, "transmittance", "colour: %s", why);
    lua_geti(L, t, 2);
    if (lua_type(L, -1) != LUA_TNUMBER)
        lf_error(L, 1, "transmittance", "distance: number expected, got %s",
                 luaL_typename(L, -1));
    double d = lua_tonumber(L, -1);
    if (!(d > 0 && d <= LC_MAX_COORD))
        lf_error(L, 1, "transmittance", "distance must be in (0, %g], got %g",
                 LC_MAX_COORD, d);
    double ch[3] = {c.x, c.y, c.z}, a[3];
    for (int i = 0; i < 3; i++) {
        if (!(ch[i] > 0 && ch[i] <= 1))
            lf_error(L, 1, "transmittance",
                     "colour component %d must be in (0, 1], got %g", i + 1, ch[i]);
        a[i] = -log(ch[i]) / d;
        if (a[i] == 0)
            a[i] = 0;                   /* -log(1) is -0 */
    }
    lua_settop(L, t - 1);
    lc_vec3 r = {a[0], a[1], a[2]};
    return r;
}

static int w_material(lua_State *L)
{
    static const char *const known[] = {"color", "ka", "kd", "kr", "ks", "alpha",
                                        "emission", "absorb", "glossiness",
                                        "cone_samples", "kt", "ior", "fresnel",
                                        "absorption", "transmittance", "shadow", "bump",
                                        "bump_scale", "normal_map", "normal_scale", NULL};
    lf_open(L, 1, known);
    lc_material m = lc_material_default();
    /* Fields a texture may stand for: the textures go to the user value,
    ** the rest are read as values. */
        int textured[LC_SLOTS] = {0};
    lua_newtable(L);
    int tex = lua_gettop(L);
    for (int k = 0; k < LC_SLOTS; k++) {
        lua_getfield(L, 1, lc_slot_name((lc_slot)k));
        if (lb_texture_check(L, -1)) {
            textured[k] = 1;
            lua_setfield(L, tex, lc_slot_name((lc_slot)k));
        } else {
            if (k == LC_SLOT_BUMP && !lua_isnil(L, -1))
                return lf_error(L, 1, "bump", "a texture (its luminance is the height) "
                                "expected, got %s", luaL_typename(L, -1));
            if (k == LC_SLOT_NORMAL && !lua_isnil(L, -1))
                return lf_error(L, 1, "normal_map", "a texture (a tangent-space normal "
                                "map) expected, got %s", luaL_typename(L, -1));
            lua_pop(L, 1);
        }
    }
    if (!textured[LC_SLOT_COLOR]) m.color = lf_color(L, 1, "color", 0, m.color);
    m.ka = lf_number(L, 1, "ka", 0, m.ka);
    if (!textured[LC_SLOT_KD]) m.kd = lf_number(L, 1, "kd", 0, m.kd);
    if (!textured[LC_SLOT_KR]) m.kr = lf_number(L, 1, "kr", 0, m.kr);
    if (!textured[LC_SLOT_KS]) m.ks = lf_number(L, 1, "ks", 0, m.ks);
    m.alpha = lf_number(L, 1, "alpha", 0, m.alpha);
    if (!textured[LC_SLOT_EMISSION]) m.emission = lf_color(L, 1, "emission", 0, m.emission);
    m.bump = lf_number(L, 1, "bump_scale", 0, textured[LC_SLOT_BUMP] ? 1 : 0);
    m.normal_scale = lf_number(L, 1, "normal_scale", 0, m.normal_scale);
    m.absorb = (lc_absorb)lf_option(L, 1, "absorb", absorb_opts, (int)m.absorb);
    m.glossiness = lf_number(L, 1, "glossiness", 0, m.glossiness);
    m.cone_samples = lf_integer(L, 1, "cone_samples", 0, m.cone_samples);
    if (!textured[LC_SLOT_KT]) m.kt = lf_number(L, 1, "kt", 0, m.kt);
    m.ior = lf_number(L, 1, "ior", 0, m.ior);
    m.fresnel = lf_boolean(L, 1, "fresnel", m.fresnel);
    m.absorption = read_absorption(L, m.absorption);
    m.shadow = (lc_shadow_mode)lf_option(L, 1, "shadow", shadow_opts, (int)m.shadow);
    lc_error err;
    if (lc_material_check(&m, &err))
        return lf_raise(L, 1, &err);
    lb_ud_material *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->m = m;
    luaL_setmetatable(L, LB_MATERIAL);
    lua_pushvalue(L, tex);
    lua_setiuservalue(L, -2, 1);
    return 1;
}

static int w_material_tostring(lua_State *L)
{
    const lc_material *m = &((lb_ud_material *)luaL_checkudata(L, 1, LB_MATERIAL))->m;
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
        lf_add_number(&b, vals[i]);
    }
    luaL_addstring(&b, ", ");
    buf_color(&b, "emission", m->emission);
    luaL_addstring(&b, ", absorb = '");
    luaL_addstring(&b, absorb_opts[m->absorb]);
    luaL_addstring(&b, "'");
    /* The dielectric's fields where they are not the defaults: an opaque
    ** material prints as it always did. */
    if (m->kt != 0) {
        luaL_addstring(&b, ", kt = ");
        lf_add_number(&b, m->kt);
    }
    if (m->ior != 1) {
        luaL_addstring(&b, ", ior = ");
        lf_add_number(&b, m->ior);
    }
    if (!m->fresnel)
        luaL_addstring(&b, ", fresnel = false");
    if (m->absorption.x != 0 || m->absorption.y != 0 || m->absorption.z != 0) {
        luaL_addstring(&b, ", ");
        lf_add_vec3(&b, "absorption", m->absorption);
    }
    if (m->normal_scale != 1) {
        luaL_addstring(&b, ", normal_scale = ");
        lf_add_number(&b, m->normal_scale);
    }
    if (m->shadow != LC_SHADOW_FILTERED) {
        luaL_addstring(&b, ", shadow = '");
        luaL_addstring(&b, shadow_opts[m->shadow]);
        luaL_addstring(&b, "'");
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    /* Its textures after it, one per field they stand for. */
        for (int k = 0; k < LC_SLOTS; k++) {
        lua_settop(L, 2);
        if (lua_getiuservalue(L, 1, 1) == LUA_TTABLE &&
            lua_getfield(L, 3, lc_slot_name((lc_slot)k)) != LUA_TNIL) {
            luaL_tolstring(L, 4, NULL);
            lua_pushfstring(L, "%s, %s textured by %s", lua_tostring(L, 2),
                            lc_slot_name((lc_slot)k), lua_tostring(L, 5));
            lua_replace(L, 2);
        }
    }
    lua_settop(L, 2);
    return 1;
}

static int w_material_index(lua_State *L)
{
    const lc_material *m = &((lb_ud_material *)luaL_checkudata(L, 1, LB_MATERIAL))->m;
    const char *k = luaL_checkstring(L, 2);
    /* A field a texture stands for reads as that texture. */
    if (lua_getiuservalue(L, 1, 1) == LUA_TTABLE && lua_getfield(L, -1, k) != LUA_TNIL)
        return 1;
    lua_settop(L, 2);
    if (strcmp(k, "bump_scale") == 0) lua_pushnumber(L, m->bump);
    else if (strcmp(k, "normal_scale") == 0) lua_pushnumber(L, m->normal_scale);
    else if (strcmp(k, "color") == 0) lf_push_color(L, m->color);
    else if (strcmp(k, "emission") == 0) lf_push_color(L, m->emission);
    else if (strcmp(k, "ka") == 0) lua_pushnumber(L, m->ka);
    else if (strcmp(k, "kd") == 0) lua_pushnumber(L, m->kd);
    else if (strcmp(k, "kr") == 0) lua_pushnumber(L, m->kr);
    else if (strcmp(k, "ks") == 0) lua_pushnumber(L, m->ks);
    else if (strcmp(k, "alpha") == 0) lua_pushnumber(L, m->alpha);
    else if (strcmp(k, "glossiness") == 0) lua_pushnumber(L, m->glossiness);
    else if (strcmp(k, "cone_samples") == 0) lua_pushinteger(L, m->cone_samples);
    else if (strcmp(k, "absorb") == 0) lua_pushstring(L, absorb_opts[m->absorb]);
    else if (strcmp(k, "kt") == 0) lua_pushnumber(L, m->kt);
    else if (strcmp(k, "ior") == 0) lua_pushnumber(L, m->ior);
    else if (strcmp(k, "fresnel") == 0) lua_pushboolean(L, m->fresnel);
    else if (strcmp(k, "absorption") == 0) lf_push_vec3(L, m->absorption);
    else if (strcmp(k, "shadow") == 0) lua_pushstring(L, shadow_opts[m->shadow]);
    else lua_pushnil(L);
    return 1;
}

void lb_material_push(lua_State *L, const lc_material *m)
{
    lb_ud_material *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->m = *m;
    luaL_setmetatable(L, LB_MATERIAL);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 1);
}

void lb_light_push(lua_State *L, const lb_ud_light *l)
{
    lb_ud_light *u = lua_newuserdatauv(L, sizeof *u, 0);
    *u = *l;
    luaL_setmetatable(L, LB_LIGHT);
}

int lb_light_moved(const lb_ud_light *l, const lc_transform *t, lb_ud_light *out,
                   lc_error *err)
{
    *out = *l;
    switch (l->kind) {
    case LC_OBJECT_SPOT_LIGHT:
        out->spot.position = lc_transform_point(t, l->spot.position);
        out->spot.direction = lc_transform_vector(t, l->spot.direction);
        return lc_spot_light_check(&out->spot, err) == LC_OK;
    case LC_OBJECT_DIRECTIONAL_LIGHT:
        out->sun.direction = lc_transform_vector(t, l->sun.direction);
        return lc_directional_light_check(&out->sun, err) == LC_OK;
    default:
        out->l.position = lc_transform_point(t, l->l.position);
        return lc_point_light_check(&out->l, err) == LC_OK;
    }
}

int lb_light_add(lc_scene *s, const lb_ud_light *l, lc_error *err)
{
    switch (l->kind) {
    case LC_OBJECT_SPOT_LIGHT: return lc_scene_add_spot_light(s, &l->spot, err);
    case LC_OBJECT_DIRECTIONAL_LIGHT: return lc_scene_add_directional_light(s, &l->sun, err);
    default: return lc_scene_add_light(s, &l->l, err);
    }
}

lb_ud_light lb_light_of(const lc_object *o)
{
    lb_ud_light l;
    memset(&l, 0, sizeof l);
    l.kind = o->kind;
    l.l = o->light;
    l.spot = o->spot;
    l.sun = o->sun;
    return l;
}

/* ---- lights and cameras ----------------------------------------------------- */

static const char *const falloff_opts[] = {"inverse_square", "none", NULL};

static int push_new_light(lua_State *L, const lb_ud_light *l)
{
    lb_light_push(L, l);
    return 1;
}

static int w_point_light(lua_State *L)
{
    static const char *const known[] = {"position", "color", "intensity", "falloff", NULL};
    lf_open(L, 1, known);
    lb_ud_light u;
    memset(&u, 0, sizeof u);
    u.kind = LC_OBJECT_LIGHT;
    lc_point_light l = lc_point_light_default();
    l.position = lf_vec3(L, 1, "position", 1, l.position);
    l.color = lf_color(L, 1, "color", 0, l.color);
    l.intensity = lf_number(L, 1, "intensity", 0, l.intensity);
    l.falloff = (lc_falloff)lf_option(L, 1, "falloff", falloff_opts, (int)l.falloff);
    lc_error err;
    if (lc_point_light_check(&l, &err))
        return lf_raise(L, 1, &err);
    u.l = l;
    return push_new_light(L, &u);
}

/* lancer.spot_light{position, direction or at, angle = 30, soft = 5, color,
** intensity, falloff}: `at` is a point the axis goes through. */
static int w_spot_light(lua_State *L)
{
    static const char *const known[] = {"position", "direction", "at", "angle", "soft",
                                        "color", "intensity", "falloff", NULL};
    lf_open(L, 1, known);
    lb_ud_light u;
    memset(&u, 0, sizeof u);
    u.kind = LC_OBJECT_SPOT_LIGHT;
    lc_spot_light l = lc_spot_light_default();
    l.position = lf_vec3(L, 1, "position", 1, l.position);
    int dir = lf_present(L, 1, "direction"), at = lf_present(L, 1, "at");
    if (dir && at)
        return lf_error(L, 1, "at", "'direction' is given too: give one of them");
    if (!dir && !at)
        return lf_error(L, 1, "direction", "required (or 'at', a point it shines on)");
    if (dir) {
        l.direction = lf_vec3(L, 1, "direction", 1, l.direction);
    } else {
        lc_vec3 p = lf_vec3(L, 1, "at", 1, l.position);
        l.direction = (lc_vec3){p.x - l.position.x, p.y - l.position.y, p.z - l.position.z};
        if (l.direction.x == 0 && l.direction.y == 0 && l.direction.z == 0)
            return lf_error(L, 1, "at", "must differ from 'position'");
    }
    l.angle = lf_number(L, 1, "angle", 0, l.angle);
    l.soft = lf_number(L, 1, "soft", 0, l.soft < l.angle ? l.soft : l.angle);
    l.color = lf_color(L, 1, "color", 0, l.color);
    l.intensity = lf_number(L, 1, "intensity", 0, l.intensity);
    l.falloff = (lc_falloff)lf_option(L, 1, "falloff", falloff_opts, (int)l.falloff);
    lc_error err;
    if (lc_spot_light_check(&l, &err))
        return lf_raise(L, 1, &err);
    u.spot = l;
    return push_new_light(L, &u);
}

/* lancer.directional_light{direction, irradiance = pi, color}. */
static int w_directional_light(lua_State *L)
{
    static const char *const known[] = {"direction", "irradiance", "color", NULL};
    lf_open(L, 1, known);
    lb_ud_light u;
    memset(&u, 0, sizeof u);
    u.kind = LC_OBJECT_DIRECTIONAL_LIGHT;
    lc_directional_light l = lc_directional_light_default();
    l.direction = lf_vec3(L, 1, "direction", 1, l.direction);
    l.irradiance = lf_number(L, 1, "irradiance", 0, l.irradiance);
    l.color = lf_color(L, 1, "color", 0, l.color);
    lc_error err;
    if (lc_directional_light_check(&l, &err))
        return lf_raise(L, 1, &err);
    u.sun = l;
    return push_new_light(L, &u);
}

static int w_light_tostring(lua_State *L)
{
    const lb_ud_light *u = luaL_checkudata(L, 1, LB_LIGHT);
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    if (u->kind == LC_OBJECT_SPOT_LIGHT) {
        const lc_spot_light *l = &u->spot;
        luaL_addstring(&b, "lancer.spot_light{");
        lf_add_vec3(&b, "position", l->position);
        luaL_addstring(&b, ", ");
        lf_add_vec3(&b, "direction", l->direction);
        luaL_addstring(&b, ", angle = ");
        lf_add_number(&b, l->angle);
        luaL_addstring(&b, ", soft = ");
        lf_add_number(&b, l->soft);
        luaL_addstring(&b, ", ");
        buf_color(&b, "color", l->color);
        luaL_addstring(&b, ", intensity = ");
        lf_add_number(&b, l->intensity);
        luaL_addstring(&b, ", falloff = '");
        luaL_addstring(&b, falloff_opts[l->falloff]);
        luaL_addstring(&b, "'}");
    } else if (u->kind == LC_OBJECT_DIRECTIONAL_LIGHT) {
        const lc_directional_light *l = &u->sun;
        luaL_addstring(&b, "lancer.directional_light{");
        lf_add_vec3(&b, "direction", l->direction);
        luaL_addstring(&b, ", irradiance = ");
        lf_add_number(&b, l->irradiance);
        luaL_addstring(&b, ", ");
        buf_color(&b, "color", l->color);
        luaL_addstring(&b, "}");
    } else {
        const lc_point_light *l = &u->l;
        luaL_addstring(&b, "lancer.point_light{");
        lf_add_vec3(&b, "position", l->position);
        luaL_addstring(&b, ", ");
        buf_color(&b, "color", l->color);
        luaL_addstring(&b, ", intensity = ");
        lf_add_number(&b, l->intensity);
        luaL_addstring(&b, ", falloff = '");
        luaL_addstring(&b, falloff_opts[l->falloff]);
        luaL_addstring(&b, "'}");
    }
    luaL_pushresult(&b);
    return 1;
}

static int w_light_index(lua_State *L)
{
    const lb_ud_light *u = luaL_checkudata(L, 1, LB_LIGHT);
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "moved") == 0) {
        lua_pushcfunction(L, lb_motion_moved);
    } else if (u->kind == LC_OBJECT_SPOT_LIGHT) {
        const lc_spot_light *l = &u->spot;
        if (strcmp(k, "kind") == 0) lua_pushstring(L, "spot_light");
        else if (strcmp(k, "position") == 0) lf_push_vec3(L, l->position);
        else if (strcmp(k, "direction") == 0) lf_push_vec3(L, l->direction);
        else if (strcmp(k, "angle") == 0) lua_pushnumber(L, l->angle);
        else if (strcmp(k, "soft") == 0) lua_pushnumber(L, l->soft);
        else if (strcmp(k, "color") == 0) lf_push_color(L, l->color);
        else if (strcmp(k, "intensity") == 0) lua_pushnumber(L, l->intensity);
        else if (strcmp(k, "falloff") == 0) lua_pushstring(L, falloff_opts[l->falloff]);
        else lua_pushnil(L);
    } else if (u->kind == LC_OBJECT_DIRECTIONAL_LIGHT) {
        const lc_directional_light *l = &u->sun;
        if (strcmp(k, "kind") == 0) lua_pushstring(L, "directional_light");
        else if (strcmp(k, "direction") == 0) lf_push_vec3(L, l->direction);
        else if (strcmp(k, "irradiance") == 0) lua_pushnumber(L, l->irradiance);
        else if (strcmp(k, "color") == 0) lf_push_color(L, l->color);
        else lua_pushnil(L);
    } else {
        const lc_point_light *l = &u->l;
        if (strcmp(k, "kind") == 0) lua_pushstring(L, "point_light");
        else if (strcmp(k, "position") == 0) lf_push_vec3(L, l->position);
        else if (strcmp(k, "color") == 0) lf_push_color(L, l->color);
        else if (strcmp(k, "intensity") == 0) lua_pushnumber(L, l->intensity);
        else if (strcmp(k, "falloff") == 0) lua_pushstring(L, falloff_opts[l->falloff]);
        else lua_pushnil(L);
    }
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
    lb_ud_camera *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->c = c;
    luaL_setmetatable(L, LB_CAMERA);
    return 1;
}

static int w_camera_tostring(lua_State *L)
{
    const lc_camera *c = &((lb_ud_camera *)luaL_checkudata(L, 1, LB_CAMERA))->c;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.camera{");
    lf_add_vec3(&b, "from", c->from);
    luaL_addstring(&b, ", ");
    lf_add_vec3(&b, "at", c->at);
    luaL_addstring(&b, ", ");
    lf_add_vec3(&b, "up", c->up);
    luaL_addstring(&b, ", fov = ");
    lf_add_number(&b, c->fov);
    if (c->aperture > 0) {
        luaL_addstring(&b, ", aperture = ");
        lf_add_number(&b, c->aperture);
        luaL_addstring(&b, ", focus = ");
        lf_add_number(&b, c->focus);
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    return 1;
}

static int w_camera_index(lua_State *L)
{
    const lc_camera *c = &((lb_ud_camera *)luaL_checkudata(L, 1, LB_CAMERA))->c;
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


void lb_objects_register(lua_State *L)
{
    static const luaL_Reg material_meta[] = {
        {"__tostring", w_material_tostring}, {"__index", w_material_index}, {NULL, NULL}};
    static const luaL_Reg light_meta[] = {
        {"__tostring", w_light_tostring}, {"__index", w_light_index}, {NULL, NULL}};
    static const luaL_Reg camera_meta[] = {
        {"__tostring", w_camera_tostring}, {"__index", w_camera_index}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"material", w_material}, {"point_light", w_point_light},
        {"spot_light", w_spot_light}, {"directional_light", w_directional_light},
        {"camera", w_camera},
        {NULL, NULL}};
    lb_class(L, LB_MATERIAL, material_meta, NULL);
    lb_class(L, LB_LIGHT, light_meta, NULL);
    lb_class(L, LB_CAMERA, camera_meta, NULL);
    luaL_setfuncs(L, funcs, 0);
}
