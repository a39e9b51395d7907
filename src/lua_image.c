/* lua_image.c: images: making, saving, loading, pixels, comparing, measuring error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_types.h"

/* ---- images --------------------------------------------------------------- */

/* The core image of the userdata at idx, raising when freed: fetched right
** before the lc_ call that uses it (see scene_at in lua_types.h). */
static lc_image *check_image(lua_State *L, int idx)
{
    ud_image *u = luaL_checkudata(L, idx, IMAGE);
    if (!u->img)
        luaL_argerror(L, idx, "lancer.Image already freed");
    return u->img;
}

static int w_image_free(lua_State *L)              /* __gc and __close */
{
    ud_image *u = luaL_checkudata(L, 1, IMAGE);
    lc_image_free(u->img);
    u->img = NULL;                                  /* safe to call twice */
    return 0;
}

static const char *const encoding_opts[] = {"srgb", "linear", NULL};

/* Checks save's arguments: the image at 1, the path at 2, options at 3.
** Reading the options may run a script's metamethods: save_work checks the
** image again. */
static void save_args(lua_State *L, lc_encoding *enc)
{
    static const char *const known[] = {"encoding", NULL};
    check_image(L, 1);
    luaL_checktype(L, 2, LUA_TSTRING);       /* a number is no file name */
    lua_settop(L, 3);
    *enc = LC_ENCODE_SRGB;
    if (!lua_isnil(L, 3)) {
        lf_open(L, 3, known);
        *enc = (lc_encoding)lf_option(L, 3, "encoding", encoding_opts, 0);
    }
}

/* Saves the image at 1 to the path at 2. */
static int save_work(lua_State *L, lc_encoding enc, int plain)
{
    lc_error err;
    if (lc_image_save(check_image(L, 1), lua_tostring(L, 2), enc, &err))
        return hook_fail(L, plain, 2, err.msg);     /* names 'save' and the path */
    lua_settop(L, 1);
    return 1;
}

/* The hook's plain save (lua_hook.c). */
static int save_plain(lua_State *L)
{
    lc_encoding enc;
    save_args(L, &enc);
    return save_work(L, enc, 1);
}

/* img:save(path [, {encoding = 'srgb'}]): the image, written by rename. */
static int w_image_save(lua_State *L)
{
    lc_encoding enc;
    save_args(L, &enc);
    int n = hook_call(L, "save", save_plain, 3);
    return n >= 0 ? n : save_work(L, enc, 0);
}

static int w_load_png(lua_State *L)
{
    static const char *const known[] = {"encoding", NULL};
    luaL_checktype(L, 1, LUA_TSTRING);
    lc_encoding enc = LC_ENCODE_SRGB;
    if (!lua_isnoneornil(L, 2)) {
        lf_open(L, 2, known);
        enc = (lc_encoding)lf_option(L, 2, "encoding", encoding_opts, 0);
    }
    ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);   /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, IMAGE);
    lc_error err;
    ui->img = lc_image_load_png(lua_tostring(L, 1), enc, &err);
    if (!ui->img)
        return luaL_argerror(L, 1, err.msg);
    lancer_charge(L);
    return 1;
}

static int w_image_diff(lua_State *L)
{
    lc_image *a = check_image(L, 1), *b = check_image(L, 2);
    double tol = luaL_optnumber(L, 3, 1.0 / 255);
    if (!(tol >= 0))
        return luaL_argerror(L, 3, "tolerance must be >= 0");
    lc_image_diff d;
    lc_error err;
    if (lc_image_compare(a, b, tol, &d, &err))
        return luaL_argerror(L, 2, err.msg);
    lua_createtable(L, 0, 5);
    lua_pushnumber(L, d.mean_abs);
    lua_setfield(L, -2, "mean");
    lua_pushnumber(L, d.max_abs);
    lua_setfield(L, -2, "max");
    lua_pushnumber(L, d.within);
    lua_setfield(L, -2, "within");
    lua_pushinteger(L, d.worst_x + 1);
    lua_setfield(L, -2, "worst_x");
    lua_pushinteger(L, d.worst_y + 1);
    lua_setfield(L, -2, "worst_y");
    return 1;
}

static int w_image_nonfinite(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)lc_image_nonfinite(check_image(L, 1)));
    return 1;
}

static int w_image_pixel(lua_State *L)
{
    lc_image *img = check_image(L, 1);
    lua_Integer x = luaL_checkinteger(L, 2), y = luaL_checkinteger(L, 3);
    int w = lc_image_width(img), h = lc_image_height(img);
    if (x < 1 || x > w)
        return luaL_argerror(L, 2, lua_pushfstring(L, "x must be in [1, %d], got %I", w, x));
    if (y < 1 || y > h)
        return luaL_argerror(L, 3, lua_pushfstring(L, "y must be in [1, %d], got %I", h, y));
    lc_color c = lc_image_get(img, (int)x - 1, (int)y - 1);
    lua_pushnumber(L, c.r);
    lua_pushnumber(L, c.g);
    lua_pushnumber(L, c.b);
    return 3;
}

/* img:set(x, y, r, g, b): 1-based like pixel; linear values, stored as given. */
static int w_image_set(lua_State *L)
{
    lc_image *img = check_image(L, 1);
    lua_Integer x = luaL_checkinteger(L, 2), y = luaL_checkinteger(L, 3);
    lc_color c = {(float)luaL_checknumber(L, 4), (float)luaL_checknumber(L, 5),
                  (float)luaL_checknumber(L, 6)};
    int w = lc_image_width(img), h = lc_image_height(img);
    if (x < 1 || x > w)
        return luaL_argerror(L, 2, lua_pushfstring(L, "x must be in [1, %d], got %I", w, x));
    if (y < 1 || y > h)
        return luaL_argerror(L, 3, lua_pushfstring(L, "y must be in [1, %d], got %I", h, y));
    lc_image_set(img, (int)x - 1, (int)y - 1, c);
    return 0;
}

/* img:error(ref): {mse, rmse, relmse, mae, bias} of img against ref. */
static int w_image_error(lua_State *L)
{
    lc_image *img = check_image(L, 1), *ref = check_image(L, 2);
    lc_image_error_stats e;
    lc_error err;
    if (lc_image_error(img, ref, &e, &err))
        return luaL_argerror(L, 2, err.msg);
    lua_createtable(L, 0, 5);
    lua_pushnumber(L, e.mse);
    lua_setfield(L, -2, "mse");
    lua_pushnumber(L, e.rmse);
    lua_setfield(L, -2, "rmse");
    lua_pushnumber(L, e.relmse);
    lua_setfield(L, -2, "relmse");
    lua_pushnumber(L, e.mae);
    lua_setfield(L, -2, "mae");
    lua_pushnumber(L, e.bias);
    lua_setfield(L, -2, "bias");
    return 1;
}

/* img:add(other [, weight = 1]): img += weight * other; returns img. */
static int w_image_add(lua_State *L)
{
    lc_image *img = check_image(L, 1), *other = check_image(L, 2);
    double weight = luaL_optnumber(L, 3, 1);
    lc_error err;
    if (lc_image_add(img, other, weight, &err))
        return luaL_argerror(L, strcmp(err.field, "weight") == 0 ? 3 : 2, err.msg);
    lua_settop(L, 1);
    return 1;
}

/* lancer.image{width, height, color = 0}: an image of one colour, to draw
** on (lancer.plot) or to sum renders into (img:add). */
static int w_image(lua_State *L)
{
    static const char *const known[] = {"width", "height", "color", NULL};
    lf_open(L, 1, known);
    int w = lf_integer(L, 1, "width", 1, 0), h = lf_integer(L, 1, "height", 1, 0);
    lc_color black = {0, 0, 0};
    lc_color c = lf_color(L, 1, "color", 0, black);
    ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);   /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, IMAGE);
    lc_error err;
    ui->img = lc_image_new(w, h, &err);
    if (!ui->img)
        return lf_raise(L, 1, &err);
    if (c.r != 0 || c.g != 0 || c.b != 0)
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                lc_image_set(ui->img, x, y, c);
    lancer_charge(L);
    return 1;
}

static int w_image_tostring(lua_State *L)
{
    ud_image *u = luaL_checkudata(L, 1, IMAGE);
    if (!u->img)
        lua_pushstring(L, "lancer.Image (freed)");
    else
        lua_pushfstring(L, "lancer.Image %dx%d", lc_image_width(u->img),
                        lc_image_height(u->img));
    return 1;
}

static int w_image_index(lua_State *L)
{
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "width") == 0) {
        lua_pushinteger(L, lc_image_width(check_image(L, 1)));
    } else if (strcmp(k, "height") == 0) {
        lua_pushinteger(L, lc_image_height(check_image(L, 1)));
    } else {
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
    }
    return 1;
}


void image_register(lua_State *L)
{
    static const luaL_Reg image_meta[] = {
        {"__gc", w_image_free}, {"__close", w_image_free}, {"__tostring", w_image_tostring},
        {"__index", w_image_index}, {NULL, NULL}};
    static const luaL_Reg image_methods[] = {
        {"save", w_image_save}, {"pixel", w_image_pixel}, {"diff", w_image_diff},
        {"nonfinite", w_image_nonfinite}, {"set", w_image_set}, {"error", w_image_error},
        {"add", w_image_add}, {NULL, NULL}};
    lancer_class(L, IMAGE, image_meta, image_methods);
    lua_pushcfunction(L, w_load_png);
    lua_setfield(L, -2, "load_png");
    lua_pushcfunction(L, w_image);
    lua_setfield(L, -2, "image");
}
