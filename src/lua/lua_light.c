/* lua_light.c: point, spot and directional lights in Lua, over per-kind field tables. */
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

static const char *const falloff_opts[] = {"inverse_square", "none", NULL};

static void read_direction(lua_State *L, int arg, void *rec);
static void read_soft(lua_State *L, int arg, void *rec);

/* A row names a member of lb_ud_light: of the struct of its kind. */
#define F(name, member, type, required) \
    {name, offsetof(lb_ud_light, member), type, required, LB_SHOWN, NULL, NULL, NULL, \
     0, 0}
#define FALLOFF(member) \
    {"falloff", offsetof(lb_ud_light, member), LB_OPTION, 0, LB_SHOWN, falloff_opts, \
     NULL, NULL, 0, 0}
#define READ(name, member, type, also, read) \
    {name, offsetof(lb_ud_light, member), type, 0, LB_SHOWN, NULL, also, read, 0, 0}
#define END {NULL, 0, LB_NUMBER, 0, LB_SHOWN, NULL, NULL, NULL, 0, 0}

/* Each kind's fields, in the order its constructor reads them and
** __tostring writes them; its constructor's and its kind's name. */
static const struct {
    lc_object_kind kind;
    const char    *name;
    lb_field       fields[8];
} kinds[] = {
    {LC_OBJECT_LIGHT, "point_light", {
        F("position", l.position, LB_VEC3, 1), F("color", l.color, LB_COLOR, 0),
        F("intensity", l.intensity, LB_NUMBER, 0), FALLOFF(l.falloff), END}},
    {LC_OBJECT_SPOT_LIGHT, "spot_light", {
        F("position", spot.position, LB_VEC3, 1),
        READ("direction", spot.direction, LB_VEC3, "at", read_direction),
        F("angle", spot.angle, LB_NUMBER, 0),
        READ("soft", spot.soft, LB_NUMBER, NULL, read_soft),
        F("color", spot.color, LB_COLOR, 0),
        F("intensity", spot.intensity, LB_NUMBER, 0),
        FALLOFF(spot.falloff), END}},
    {LC_OBJECT_DIRECTIONAL_LIGHT, "directional_light", {
        F("direction", sun.direction, LB_VEC3, 1),
        F("irradiance", sun.irradiance, LB_NUMBER, 0),
        F("color", sun.color, LB_COLOR, 0),
        END}},
};
#define KINDS (sizeof kinds / sizeof kinds[0])

/* The row of a light's kind (a point light's for any other). */
static int kind_of(lc_object_kind kind)
{
    for (size_t i = 0; i < KINDS; i++)
        if (kinds[i].kind == kind)
            return (int)i;
    return 0;
}

/* A spot's direction, or `at`, a point its axis goes through. */
static void read_direction(lua_State *L, int arg, void *rec)
{
    lc_spot_light *l = &((lb_ud_light *)rec)->spot;
    int dir = lf_present(L, arg, "direction"), at = lf_present(L, arg, "at");
    if (dir && at)
        lf_error(L, arg, "at", "'direction' is given too: give one of them");
    if (!dir && !at)
        lf_error(L, arg, "direction", "required (or 'at', a point it shines on)");
    if (dir) {
        l->direction = lf_vec3(L, arg, "direction", 1, l->direction);
        return;
    }
    lc_vec3 p = lf_vec3(L, arg, "at", 1, l->position);
    l->direction = (lc_vec3){p.x - l->position.x, p.y - l->position.y,
                             p.z - l->position.z};
    if (l->direction.x == 0 && l->direction.y == 0 && l->direction.z == 0)
        lf_error(L, arg, "at", "must differ from 'position'");
}

/* A spot's soft edge: at most its angle unless given. */
static void read_soft(lua_State *L, int arg, void *rec)
{
    lc_spot_light *l = &((lb_ud_light *)rec)->spot;
    l->soft = lf_number(L, arg, "soft", 0, l->soft < l->angle ? l->soft : l->angle);
}

static lc_status check(const lb_ud_light *l, lc_error *err)
{
    switch (l->kind) {
    case LC_OBJECT_SPOT_LIGHT: return lc_spot_light_check(&l->spot, err);
    case LC_OBJECT_DIRECTIONAL_LIGHT: return lc_directional_light_check(&l->sun, err);
    default: return lc_point_light_check(&l->l, err);
    }
}

/* lancer.<kind>{its fields}. */
static int light_new(lua_State *L, lc_object_kind kind)
{
    int k = kind_of(kind);
    lb_record_open(L, 1, kinds[k].fields);
    lb_ud_light u;
    memset(&u, 0, sizeof u);
    u.kind = kinds[k].kind;
    u.l = lc_point_light_default();
    u.spot = lc_spot_light_default();
    u.sun = lc_directional_light_default();
    lb_record_read(L, 1, &u, kinds[k].fields, 0);
    lc_error err;
    if (check(&u, &err))
        return lf_raise(L, 1, &err);
    lb_light_push(L, &u);
    return 1;
}

static int w_point_light(lua_State *L) { return light_new(L, LC_OBJECT_LIGHT); }
static int w_spot_light(lua_State *L) { return light_new(L, LC_OBJECT_SPOT_LIGHT); }
static int w_directional_light(lua_State *L)
{
    return light_new(L, LC_OBJECT_DIRECTIONAL_LIGHT);
}

static int w_light_tostring(lua_State *L)
{
    const lb_ud_light *u = luaL_checkudata(L, 1, LB_LIGHT);
    int k = kind_of(u->kind);
    char ctor[40];
    snprintf(ctor, sizeof ctor, "lancer.%s", kinds[k].name);
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    lb_record_tostring(&b, ctor, u, u, kinds[k].fields);
    luaL_pushresult(&b);
    return 1;
}

static int w_light_index(lua_State *L)
{
    const lb_ud_light *u = luaL_checkudata(L, 1, LB_LIGHT);
    const char *k = luaL_checkstring(L, 2);
    int kind = kind_of(u->kind);
    const lb_field *f = lb_record_field(kinds[kind].fields, k);
    if (f)
        lb_record_push(L, u, f);
    else if (strcmp(k, "moved") == 0)
        lua_pushcfunction(L, lb_motion_moved);
    else if (strcmp(k, "kind") == 0)
        lua_pushstring(L, kinds[kind].name);
    else
        lua_pushnil(L);
    return 1;
}

const char *lb_light_kind_name(lc_object_kind kind)
{
    return kinds[kind_of(kind)].name;
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
        break;
    case LC_OBJECT_DIRECTIONAL_LIGHT:
        out->sun.direction = lc_transform_vector(t, l->sun.direction);
        break;
    default:
        out->l.position = lc_transform_point(t, l->l.position);
        break;
    }
    return check(out, err) == LC_OK;
}

int lb_light_add(lc_scene *s, const lb_ud_light *l, lc_error *err)
{
    switch (l->kind) {
    case LC_OBJECT_SPOT_LIGHT: return lc_scene_add_spot_light(s, &l->spot, err);
    case LC_OBJECT_DIRECTIONAL_LIGHT:
        return lc_scene_add_directional_light(s, &l->sun, err);
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

int lb_light_match(const lb_ud_light *added, const lc_object *listed)
{
    lb_ud_light l = lb_light_of(listed);
    return added->kind == listed->kind &&
           lb_record_equal(added, &l, kinds[kind_of(added->kind)].fields);
}

void lb_light_register(lua_State *L)
{
    static const luaL_Reg meta[] = {
        {"__tostring", w_light_tostring}, {"__index", w_light_index}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"point_light", w_point_light}, {"spot_light", w_spot_light},
        {"directional_light", w_directional_light}, {NULL, NULL}};
    lb_class(L, LB_LIGHT, meta, NULL);
    luaL_setfuncs(L, funcs, 0);
}
