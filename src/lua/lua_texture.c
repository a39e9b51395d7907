/* lua_texture.c: textures: lancer.checker, stripes, gradient, noise, marble,
** wood, image_texture, mix and sky; tex:moved(T); their registration in a scene
** when a material that uses them is added. */
#include <math.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* A texture's user values: the textures standing for a, b and amount, and
** the image of an image texture (nil where none). */
enum { TU_A = 1, TU_B, TU_AMOUNT, TU_IMAGE, TU_COUNT = TU_IMAGE };

static const char *const kind_names[LC_TEX_KINDS] = {
    "checker", "stripes", "gradient", "noise", "marble", "wood", "image_texture", "mix",
    "sky"};
static const char *const mapping_opts[] = {"world", "object", "uv", NULL};
static const char *const wrap_opts[] = {"repeat", "clamp", "mirror", NULL};
static const char *const filter_opts[] = {"bilinear", "nearest", NULL};
static const char *const encoding_opts[] = {"srgb", "linear", NULL};

static lb_ud_texture *push_texture(lua_State *L, const lc_texture *t)
{
    lb_ud_texture *u = lua_newuserdatauv(L, sizeof *u, TU_COUNT);
    u->t = *t;
    luaL_setmetatable(L, LB_TEXTURE);
    return u;
}

/* Colour slot `field` of the table at 1: a colour into *c, or a texture
** set as user value `uv` of the texture at `tex`. */
static void read_slot(lua_State *L, const char *field, lc_color *c, int tex, int uv)
{
    lua_getfield(L, 1, field);
    if (luaL_testudata(L, -1, LB_TEXTURE)) {
        lua_setiuservalue(L, tex, uv);
        return;
    }
    lua_pop(L, 1);
    *c = lf_color(L, 1, field, 0, *c);
}

static int make(lua_State *L, lc_texture_kind kind, const char *const known[])
{
    lf_open(L, 1, known);
    lc_texture t = lc_texture_default(kind);
    lb_ud_texture *u = push_texture(L, &t);
    int tex = lua_gettop(L);
    if (kind == LC_TEX_SKY) {            /* zenith, horizon, ground: colours */
        t.a = lf_color(L, 1, "zenith", 1, t.a);
        t.b = lf_color(L, 1, "horizon", 1, t.b);
        t.c = lf_color(L, 1, "ground", 0, t.b);
    } else {
        read_slot(L, "a", &t.a, tex, TU_A);
        read_slot(L, "b", &t.b, tex, TU_B);
    }
    t.scale = lf_number(L, 1, "scale", 0, t.scale);
    t.mapping = (lc_texture_mapping)lf_option(L, 1, "mapping", mapping_opts, (int)t.mapping);
    switch (kind) {
    case LC_TEX_STRIPES:
        t.axis = lf_vec3(L, 1, "axis", 0, t.axis);
        break;
    case LC_TEX_GRADIENT: {
        t.origin = lf_vec3(L, 1, "from", 0, t.origin);
        lc_vec3 to = lf_vec3(L, 1, "to", 0, (lc_vec3){t.origin.x, t.origin.y + 1, t.origin.z});
        t.axis = (lc_vec3){to.x - t.origin.x, to.y - t.origin.y, to.z - t.origin.z};
        break;
    }
    case LC_TEX_NOISE: case LC_TEX_MARBLE: case LC_TEX_WOOD:
        t.octaves = lf_integer(L, 1, "octaves", 0, t.octaves);
        t.turbulence = lf_number(L, 1, "turbulence", 0, t.turbulence);
        break;
    case LC_TEX_IMAGE: {
        lua_getfield(L, 1, "image");
        int has_image = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (has_image) {
            lf_udata(L, 1, "image", LB_IMAGE, 1);
        } else {
            /* A PNG's colours are sRGB-encoded; a normal or height map's
            ** values are data, read as stored with encoding = 'linear'. */
            lc_encoding enc = (lc_encoding)lf_option(L, 1, "encoding", encoding_opts, 0);
            lua_getfield(L, 1, "path");
            if (!lua_isstring(L, -1))
                return lf_error(L, 1, "image", "an image or a path to a PNG or .hdr file "
                                "expected");
            lb_check_file(L, 1, lua_tostring(L, -1), 0);
            lc_error err;
            const char *path = lua_tostring(L, -1), *dot = strrchr(path, '.');
            int hdr = dot && (strcmp(dot, ".hdr") == 0 || strcmp(dot, ".HDR") == 0);
            lc_image *img = hdr ? lc_image_load_hdr(path, &err)
                                : lc_image_load_png(path, enc, &err);
            if (!img)
                return lf_error(L, 1, "path", "%s", err.msg);
            lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);
            ui->img = img;
            luaL_setmetatable(L, LB_IMAGE);
            lb_charge(L);
        }
        lua_setiuservalue(L, tex, TU_IMAGE);
        t.wrap = (lc_texture_wrap)lf_option(L, 1, "wrap", wrap_opts, (int)t.wrap);
        t.nearest = lf_option(L, 1, "filter", filter_opts, 0);
        lua_settop(L, tex);
        break;
    }
    case LC_TEX_MIX:
        lua_getfield(L, 1, "amount");
        if (luaL_testudata(L, -1, LB_TEXTURE)) {
            lua_setiuservalue(L, tex, TU_AMOUNT);
        } else {
            lua_pop(L, 1);
            t.amount = lf_number(L, 1, "amount", 0, t.amount);
        }
        break;
    default:
        break;
    }
    /* Checked now with stand-ins for its textures, so a bad field fails
    ** here, where it was written, not when a scene takes it. */
    lc_texture probe = t;
    probe.ta = probe.tb = probe.tamount = 0;
    if (kind == LC_TEX_IMAGE) {
        lua_getiuservalue(L, tex, TU_IMAGE);
        lb_ud_image *ui = luaL_checkudata(L, -1, LB_IMAGE);
        if (!ui->img)
            return lf_error(L, 1, "image", "the image is freed");
        probe.image = ui->img;
        lua_pop(L, 1);
    }
    lc_error err;
    lc_textures *check = lc_textures_new(&err);
    int ok = check && lc_textures_add(check, &probe, &err) >= 0;
    lc_textures_free(check);
    if (!ok)
        return lf_raise(L, 1, &err);
    u = lua_touserdata(L, tex);
    u->t = t;
    lua_settop(L, tex);
    return 1;
}

#define COMMON "a", "b", "scale", "mapping"
static int w_checker(lua_State *L)
{
    static const char *const known[] = {COMMON, NULL};
    return make(L, LC_TEX_CHECKER, known);
}
static int w_stripes(lua_State *L)
{
    static const char *const known[] = {COMMON, "axis", NULL};
    return make(L, LC_TEX_STRIPES, known);
}
static int w_gradient(lua_State *L)
{
    static const char *const known[] = {COMMON, "from", "to", NULL};
    return make(L, LC_TEX_GRADIENT, known);
}
static int w_noise(lua_State *L)
{
    static const char *const known[] = {COMMON, "octaves", "turbulence", NULL};
    return make(L, LC_TEX_NOISE, known);
}
static int w_marble(lua_State *L)
{
    static const char *const known[] = {COMMON, "octaves", "turbulence", NULL};
    return make(L, LC_TEX_MARBLE, known);
}
static int w_wood(lua_State *L)
{
    static const char *const known[] = {COMMON, "octaves", "turbulence", NULL};
    return make(L, LC_TEX_WOOD, known);
}
static int w_image_texture(lua_State *L)
{
    static const char *const known[] = {"image", "path", "wrap", "filter", "scale",
                                        "mapping", "encoding", NULL};
    return make(L, LC_TEX_IMAGE, known);
}
/* lancer.sky{zenith, horizon, ground = horizon}: a gradient over directions,
** for a background. */
static int w_sky(lua_State *L)
{
    static const char *const known[] = {"zenith", "horizon", "ground", NULL};
    return make(L, LC_TEX_SKY, known);
}
static int w_mix(lua_State *L)
{
    static const char *const known[] = {"a", "b", "amount", NULL};
    return make(L, LC_TEX_MIX, known);
}

/* tex:moved(T): the same texture placed by T after its own placement. */
static int w_texture_moved(lua_State *L)
{
    lb_ud_texture *u = luaL_checkudata(L, 1, LB_TEXTURE);
    lb_ud_transform *tr = luaL_checkudata(L, 2, LB_TRANSFORM);
    lc_texture t = u->t;
    t.xf = t.moved ? lc_transform_compose(&tr->t, &t.xf) : tr->t;
    t.moved = 1;
    lc_error err;
    if (lc_transform_check(&t.xf, &err))
        return luaL_argerror(L, 2, err.msg);
    push_texture(L, &t);
    for (int k = 1; k <= TU_COUNT; k++) {
        lua_getiuservalue(L, 1, k);
        lua_setiuservalue(L, -2, k);
    }
    return 1;
}

static int w_texture_tostring(lua_State *L)
{
    lb_ud_texture *u = luaL_checkudata(L, 1, LB_TEXTURE);
    lua_pushfstring(L, "lancer.%s{...}%s", kind_names[u->t.kind],
                    u->t.moved ? " moved" : "");
    return 1;
}

static int w_texture_index(lua_State *L)
{
    lb_ud_texture *u = luaL_checkudata(L, 1, LB_TEXTURE);
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "kind") == 0)
        lua_pushstring(L, kind_names[u->t.kind]);
    else if (strcmp(k, "moved") == 0)
        lua_pushcfunction(L, w_texture_moved);
    else if (strcmp(k, "scale") == 0)
        lua_pushnumber(L, u->t.scale);
    else
        lua_pushnil(L);
    return 1;
}

/* ---- in a scene ------------------------------------------------------------------ */

int lb_texture_scene_index(lua_State *L, int sidx, int tidx, int arg, int depth)
{
    tidx = lua_absindex(L, tidx);
    sidx = lua_absindex(L, sidx);
    if (depth > LC_MAX_TEXTURE_DEPTH)
        return luaL_argerror(L, arg, "textures nest too deep");
    lua_getiuservalue(L, sidx, 1);
    int uv = lua_gettop(L);
    lua_rawgeti(L, uv, LB_SC_TEXTURES);
    int known = lua_gettop(L);
    lua_pushvalue(L, tidx);
    if (lua_rawget(L, known) == LUA_TNUMBER) {
        int index = (int)lua_tointeger(L, -1);
        lua_settop(L, uv - 1);
        return index;
    }
    lua_pop(L, 1);
    lb_ud_texture *u = luaL_checkudata(L, tidx, LB_TEXTURE);
    lc_texture t = u->t;
    int *refs[3] = {&t.ta, &t.tb, &t.tamount};
    for (int k = 0; k < 3; k++) {
        if (lua_getiuservalue(L, tidx, TU_A + k) == LUA_TUSERDATA)
            *refs[k] = 1 + lb_texture_scene_index(L, sidx, -1, arg, depth + 1);
        lua_pop(L, 1);
    }
    if (t.kind == LC_TEX_IMAGE) {
        lua_getiuservalue(L, tidx, TU_IMAGE);
        lb_ud_image *ui = luaL_checkudata(L, -1, LB_IMAGE);
        if (!ui->img)
            return luaL_argerror(L, arg, "an image texture's image was freed");
        t.image = ui->img;
        lua_pop(L, 1);
    }
    lc_error err;
    int index = lc_scene_add_texture(lb_scene_at(L, sidx), &t, &err);
    if (index < 0)
        return lf_raise(L, arg, &err);
    lua_pushvalue(L, tidx);
    lua_pushinteger(L, index);
    lua_rawset(L, known);
    lua_settop(L, uv - 1);
    return index;
}

void lb_texture_push_png(lua_State *L, const char *path, const char *what,
                         lc_encoding enc)
{
    lc_error err;
    lc_image *img = lc_image_load_png(path, enc, &err);
    if (!img)
        luaL_error(L, "%s: %s", what, err.msg);
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);
    ui->img = img;
    luaL_setmetatable(L, LB_IMAGE);
    lb_charge(L);
    lc_texture t = lc_texture_default(LC_TEX_IMAGE);
    t.image = img;
    push_texture(L, &t);
    lua_insert(L, -2);
    lua_setiuservalue(L, -2, TU_IMAGE);
}

int lb_texture_check(lua_State *L, int idx)
{
    return luaL_testudata(L, idx, LB_TEXTURE) != NULL;
}

void lb_texture_register(lua_State *L)
{
    static const luaL_Reg meta[] = {
        {"__tostring", w_texture_tostring}, {"__index", w_texture_index}, {NULL, NULL}};
    luaL_newmetatable(L, LB_TEXTURE);
    luaL_setfuncs(L, meta, 0);
    lua_pop(L, 1);
    static const luaL_Reg ctors[] = {
        {"checker", w_checker}, {"stripes", w_stripes}, {"gradient", w_gradient},
        {"noise", w_noise}, {"marble", w_marble}, {"wood", w_wood},
        {"image_texture", w_image_texture}, {"mix", w_mix}, {"sky", w_sky}, {NULL, NULL}};
    luaL_setfuncs(L, ctors, 0);
}
