/* lua_material.c: the Lua side of materials, over their field table. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

static const char *const absorb_opts[] = {"all", "diffuse", NULL};
static const char *const shadow_opts[] = {"filtered", "opaque", NULL};

static void read_absorption(lua_State *L, int arg, void *rec);

#define M(member) offsetof(lc_material, member)
#define FIELD(name, member, type, shown, rank) \
    {name, M(member), type, 0, shown, NULL, NULL, NULL, 0, rank}
#define SLOT(name, member, type, shown, slot, rank) \
    {name, M(member), type, 0, shown, NULL, NULL, NULL, 1 + slot, rank}
#define OPTION(name, member, opts, shown, rank) \
    {name, M(member), LB_OPTION, 0, shown, opts, NULL, NULL, 0, rank}

/* In the order the constructor reads them; rank: their order in
** __tostring, which writes the dielectric's fields, the normal map's
** strength and the shadow mode only where they are not the defaults. A
** field with a slot may be a texture instead (its user value holds it). */
static const lb_field fields[] = {
    SLOT("color", color, LB_COLOR, LB_SHOWN, LC_SLOT_COLOR, 1),
    FIELD("ka", ka, LB_NUMBER, LB_SHOWN, 2),
    SLOT("kd", kd, LB_NUMBER, LB_SHOWN, LC_SLOT_KD, 3),
    SLOT("kr", kr, LB_NUMBER, LB_SHOWN, LC_SLOT_KR, 4),
    SLOT("ks", ks, LB_NUMBER, LB_SHOWN, LC_SLOT_KS, 5),
    FIELD("alpha", alpha, LB_NUMBER, LB_SHOWN, 6),
    SLOT("emission", emission, LB_COLOR, LB_SHOWN, LC_SLOT_EMISSION, 9),
    OPTION("absorb", absorb, absorb_opts, LB_SHOWN, 10),
    FIELD("glossiness", glossiness, LB_NUMBER, LB_SHOWN, 7),
    FIELD("cone_samples", cone_samples, LB_INTEGER, LB_SHOWN, 8),
    SLOT("kt", kt, LB_NUMBER, LB_SHOWN_CHANGED, LC_SLOT_KT, 11),
    FIELD("ior", ior, LB_NUMBER, LB_SHOWN_CHANGED, 12),
    FIELD("fresnel", fresnel, LB_BOOL, LB_SHOWN_CHANGED, 13),
    {"absorption", M(absorption), LB_VEC3, 0, LB_SHOWN_CHANGED, NULL, "transmittance",
     read_absorption, 0, 14},
    OPTION("shadow", shadow, shadow_opts, LB_SHOWN_CHANGED, 16),
    SLOT("bump", bump, LB_TEXTURE_ONLY, LB_UNSHOWN, LC_SLOT_BUMP, 17),
    FIELD("bump_scale", bump, LB_NUMBER, LB_UNSHOWN, 18),
    SLOT("normal_map", bump, LB_TEXTURE_ONLY, LB_UNSHOWN, LC_SLOT_NORMAL, 19),
    FIELD("normal_scale", normal_scale, LB_NUMBER, LB_SHOWN_CHANGED, 15),
    {NULL, 0, LB_NUMBER, 0, LB_SHOWN, NULL, NULL, NULL, 0, 0}
};

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

/* transmittance = {colour, d}: the share of each channel left after a
** distance d, as its absorption -ln(colour) / d; the table at t. */
static lc_vec3 read_transmittance(lua_State *L, int arg, int t)
{
    char why[200];
    if (lua_type(L, t) != LUA_TTABLE)
        lf_error(L, arg, "transmittance", "{colour, distance} expected, got %s",
                 luaL_typename(L, t));
    if (luaL_len(L, t) != 2)
        lf_error(L, arg, "transmittance", "{colour, distance} expected, got %lld "
                 "entries", (long long)luaL_len(L, t));
    lc_vec3 c;
    lua_geti(L, t, 1);
    if (!to_rgb(L, -1, &c, why, sizeof why))
        lf_error(L, arg, "transmittance", "colour: %s", why);
    lua_geti(L, t, 2);
    if (lua_type(L, -1) != LUA_TNUMBER)
        lf_error(L, arg, "transmittance", "distance: number expected, got %s",
                 luaL_typename(L, -1));
    double d = lua_tonumber(L, -1);
    if (!(d > 0 && d <= LC_MAX_COORD))
        lf_error(L, arg, "transmittance", "distance must be in (0, %g], got %g",
                 LC_MAX_COORD, d);
    double ch[3] = {c.x, c.y, c.z}, a[3];
    for (int i = 0; i < 3; i++) {
        if (!(ch[i] > 0 && ch[i] <= 1))
            lf_error(L, arg, "transmittance",
                     "colour component %d must be in (0, 1], got %g", i + 1, ch[i]);
        a[i] = -log(ch[i]) / d;
        if (a[i] == 0)
            a[i] = 0;                   /* -log(1) is -0 */
    }
    lua_settop(L, t - 1);
    return (lc_vec3){a[0], a[1], a[2]};
}

/* absorption = {r, g, b} per unit length, or transmittance: one of the
** two, or neither (no absorption). */
static void read_absorption(lua_State *L, int arg, void *rec)
{
    lc_material *m = rec;
    char why[200];
    if (lf_present(L, arg, "absorption") && lf_present(L, arg, "transmittance"))
        lf_error(L, arg, "transmittance", "'absorption' is given too: give one of them");
    if (lua_getfield(L, arg, "absorption") != LUA_TNIL) {
        if (!to_rgb(L, -1, &m->absorption, why, sizeof why))
            lf_error(L, arg, "absorption", "%s", why);
    }
    lua_pop(L, 1);
    if (lua_getfield(L, arg, "transmittance") == LUA_TNIL)
        lua_pop(L, 1);
    else
        m->absorption = read_transmittance(L, arg, lua_gettop(L));
}

/* Moves the textures among the fields of the table at 1 to the table at
** tex; returns the bits (lb_record_read's skip) of the fields they fill. */
static unsigned read_textures(lua_State *L, int tex)
{
    unsigned textured = 0;
    for (const lb_field *f = fields; f->name; f++) {
        if (!f->slot)
            continue;
        lua_getfield(L, 1, f->name);
        if (lb_texture_check(L, -1)) {
            textured |= 1u << (f - fields);
            lua_setfield(L, tex, f->name);
            continue;
        }
        if (f->slot == 1 + LC_SLOT_BUMP && !lua_isnil(L, -1))
            lf_error(L, 1, f->name, "a texture (its luminance is the height) expected, "
                     "got %s", luaL_typename(L, -1));
        if (f->slot == 1 + LC_SLOT_NORMAL && !lua_isnil(L, -1))
            lf_error(L, 1, f->name, "a texture (a tangent-space normal map) expected, "
                     "got %s", luaL_typename(L, -1));
        lua_pop(L, 1);
    }
    return textured;
}

static int w_material(lua_State *L)
{
    lb_record_open(L, 1, fields);
    lc_material m = lc_material_default();
    lua_newtable(L);
    int tex = lua_gettop(L);
    unsigned textured = read_textures(L, tex);
    /* A bump map's height scale is 1 unless given. */
    if (textured & 1u << (lb_record_field(fields, "bump") - fields))
        m.bump = 1;
    lb_record_read(L, 1, &m, fields, textured);
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
    lc_material def = lc_material_default();
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    lb_record_tostring(&b, "lancer.material", m, &def, fields);
    luaL_pushresult(&b);
    /* Its textures after it, one per field they stand for. */
    for (const lb_field *f = fields; f->name; f++) {
        lua_settop(L, 2);
        if (f->slot && lua_getiuservalue(L, 1, 1) == LUA_TTABLE &&
            lua_getfield(L, 3, f->name) != LUA_TNIL) {
            luaL_tolstring(L, 4, NULL);
            lua_pushfstring(L, "%s, %s textured by %s", lua_tostring(L, 2), f->name,
                            lua_tostring(L, 5));
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
    const lb_field *f = lb_record_field(fields, k);
    if (f)
        lb_record_push(L, m, f);
    else
        lua_pushnil(L);
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

void lb_material_register(lua_State *L)
{
    static const luaL_Reg meta[] = {
        {"__tostring", w_material_tostring}, {"__index", w_material_index},
        {NULL, NULL}};
    lb_class(L, LB_MATERIAL, meta, NULL);
    lua_pushcfunction(L, w_material);
    lua_setfield(L, -2, "material");
}
