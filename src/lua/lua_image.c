/* lua_image.c: images: making, saving, loading, merging parts, pixels, comparing,
** measuring error. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* ---- images --------------------------------------------------------------- */

/* The core image of the userdata at idx, raising when freed: fetched right
** before the lc_ call that uses it (see lb_scene_at in lua_binding.h). */
static lc_image *check_image(lua_State *L, int idx)
{
    lb_ud_image *u = luaL_checkudata(L, idx, LB_IMAGE);
    if (!u->img)
        luaL_argerror(L, idx, "lancer.Image already freed");
    return u->img;
}

static int w_image_free(lua_State *L)              /* __gc and __close */
{
    lb_ud_image *u = luaL_checkudata(L, 1, LB_IMAGE);
    lc_image_free(u->img);
    u->img = NULL;                                  /* safe to call twice */
    return 0;
}

static const char *const encoding_opts[] = {"srgb", "linear", NULL};
static const char *const pixel_opts[] = {"half", "float", NULL};
static const char *const compression_opts[] = {"zip", "piz", "zips", "rle", "none", NULL};
static const char *const tone_opts[] = {"clamp", "filmic", NULL};

/* Checks save's arguments: the image at 1, the path at 2, options at 3.
** Reading the options may run a script's metamethods: save_work checks the
** image again. */
static void save_args(lua_State *L, lc_save_options *o)
{
    static const char *const known[] = {"encoding", "depth", "alpha", "pixel",
                                        "compression", "tile", "exposure", "tone", "aovs",
                                        NULL};
    check_image(L, 1);
    luaL_checktype(L, 2, LUA_TSTRING);       /* a number is no file name */
    lua_settop(L, 3);
    *o = lc_save_options_default();
    if (lua_isnil(L, 3))
        return;
    lf_open(L, 3, known);
    o->encoding = (lc_encoding)lf_option(L, 3, "encoding", encoding_opts, 0);
    o->depth = lf_integer(L, 3, "depth", 0, 8);
    if (o->depth != 8 && o->depth != 16)
        lf_error(L, 3, "depth", "must be 8 or 16, got %d", o->depth);
    o->alpha = lf_boolean(L, 3, "alpha", 0);
    o->exr_pixel = (lc_exr_pixel)lf_option(L, 3, "pixel", pixel_opts, 0);
    o->exr_compression = (lc_exr_compression)lf_option(L, 3, "compression",
                                                       compression_opts, 0);
    o->exr_tile = lf_integer(L, 3, "tile", 0, 0);
    o->exposure = lf_number(L, 3, "exposure", 0, 0);
    if (!(o->exposure >= -LC_MAX_EXPOSURE && o->exposure <= LC_MAX_EXPOSURE))
        lf_error(L, 3, "exposure", "must be in [-%d, %d] stops, got %f", LC_MAX_EXPOSURE,
                 LC_MAX_EXPOSURE, o->exposure);
    o->tone = (lc_tone)lf_option(L, 3, "tone", tone_opts, 0);
    o->aovs = lf_boolean(L, 3, "aovs", 1);
    if (o->exr_tile < 0 || o->exr_tile > LC_MAX_EXR_TILE)
        lf_error(L, 3, "tile", "must be 0 (scanlines) or 1..%d, got %d", LC_MAX_EXR_TILE,
                 o->exr_tile);
}

/* Saves the image at 1 to the path at 2. */
static int save_work(lua_State *L, const lc_save_options *o, int plain)
{
    lc_error err;
    if (lc_image_save_with(check_image(L, 1), lua_tostring(L, 2), o, &err)) {
        if (strcmp(err.field, "alpha") == 0)
            return lb_hook_fail(L, plain, 3,
                                lua_pushfstring(L, "field 'alpha': %s", err.msg));
        return lb_hook_fail(L, plain, 2, err.msg);  /* names 'save' and the path */
    }
    lua_settop(L, 1);
    return 1;
}

/* The hook's plain save (lua_hook.c). */
static int save_plain(lua_State *L)
{
    lc_save_options o;
    save_args(L, &o);
    return save_work(L, &o, 1);
}

/* img:save(path [, {encoding, depth, alpha, pixel, compression, tile, exposure,
** tone}]): the
** image, written by rename, in the format the extension names. */
static int w_image_save(lua_State *L)
{
    lc_save_options o;
    save_args(L, &o);
    int n = lb_hook_call(L, "save", save_plain, 3);
    return n >= 0 ? n : save_work(L, &o, 0);
}

/* An image load(path, err) reads from the path at 1, pushed; the userdata
** comes first, so an error after the load leaks nothing. */
static int push_loaded(lua_State *L, lc_image *(*load)(const char *, lc_error *))
{
    luaL_checktype(L, 1, LUA_TSTRING);
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);
    ui->img = NULL;
    luaL_setmetatable(L, LB_IMAGE);
    lc_error err;
    ui->img = load(lua_tostring(L, 1), &err);
    if (!ui->img)
        return luaL_argerror(L, 1, err.msg);
    lb_charge(L);
    return 1;
}

/* lancer.load_exr(path): R, G, B and A when the file has it. */
static int w_load_exr(lua_State *L) { return push_loaded(L, lc_image_load_exr); }

/* lancer.load_hdr(path): a Radiance .hdr image, linear. */
static int w_load_hdr(lua_State *L) { return push_loaded(L, lc_image_load_hdr); }

/* lancer.merge_tiles(out, {part, ...}): the parts of one frame as the whole. */
static int w_merge(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TSTRING);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_Integer n = (lua_Integer)lua_rawlen(L, 2);
    if (n < 1)
        return luaL_argerror(L, 2, "no parts to merge (a list of file names expected)");
    const char **parts = lua_newuserdatauv(L, (size_t)n * sizeof *parts, 0);
    for (lua_Integer i = 1; i <= n; i++) {
        if (lua_rawgeti(L, 2, i) != LUA_TSTRING)
            return luaL_argerror(L, 2, lua_pushfstring(L, "item %I: file name expected, "
                                                       "got %s", i, luaL_typename(L, -1)));
        parts[i - 1] = lua_tostring(L, -1);        /* kept alive by the table */
        lua_pop(L, 1);
    }
    lc_error err;
    if (lc_image_merge(lua_tostring(L, 1), parts, (size_t)n, &err))
        return luaL_argerror(L, strcmp(err.field, "parts") == 0 ? 2 : 1, err.msg);
    lua_settop(L, 1);
    return 1;
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
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0); /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, LB_IMAGE);
    lc_error err;
    ui->img = lc_image_load_png(lua_tostring(L, 1), enc, &err);
    if (!ui->img)
        return luaL_argerror(L, 1, err.msg);
    lb_charge(L);
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
    if (!lc_image_has_alpha(img))
        return 3;
    lua_pushnumber(L, lc_image_get_alpha(img, (int)x - 1, (int)y - 1));
    return 4;
}

/* img:set(x, y, r, g, b [, a]): 1-based like pixel; linear values, stored as
** given; a gives the image an alpha channel (1 elsewhere) if it has none. */
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
    if (!lua_isnoneornil(L, 7)) {
        float a = (float)luaL_checknumber(L, 7);
        lc_error err;
        if (lc_image_add_alpha(img, &err))
            return luaL_error(L, "%s", err.msg);
        lc_image_set_alpha(img, (int)x - 1, (int)y - 1, a);
        lb_charge(L);
    }
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
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0); /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, LB_IMAGE);
    lc_error err;
    ui->img = lc_image_new(w, h, &err);
    if (!ui->img)
        return lf_raise(L, 1, &err);
    if (c.r != 0 || c.g != 0 || c.b != 0)
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                lc_image_set(ui->img, x, y, c);
    lb_charge(L);
    return 1;
}

/* The AOV named at idx, raising (with the names) for any other value. */
static lc_aov check_aov(lua_State *L, int idx)
{
    const char *why;
    int k = lb_aov_of_name(L, idx, &why);
    if (k < 0)
        luaL_argerror(L, idx, why);
    return (lc_aov)k;
}

/* Pushes a new image userdata for what make returns (NULL: raises err). */
static int push_made(lua_State *L, lc_image *(*make)(const lc_image *, lc_aov, int,
                                                     lc_error *), lc_aov a, int id)
{
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0); /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, LB_IMAGE);
    lc_error err;
    ui->img = make(check_image(L, 1), a, id, &err);
    if (!ui->img)
        return luaL_argerror(L, 2, err.msg);
    lb_charge(L);
    return 1;
}

static lc_image *aov_copy(const lc_image *img, lc_aov a, int id, lc_error *err)
{
    (void)id;
    return lc_image_aov(img, a, err);
}

/* img:aov(name): a new image of that AOV. */
static int w_image_aov(lua_State *L)
{
    check_image(L, 1);
    lc_aov a = check_aov(L, 2);
    return push_made(L, aov_copy, a, 0);
}

/* img:aovs(): the names of the AOVs the image holds, in lc_aov's order. */
static int w_image_aovs(lua_State *L)
{
    lb_aov_push_names(L, lc_image_aovs(check_image(L, 1)));
    return 1;
}

/* img:matte(name, id): the coverage of object (or material) id. */
static int w_image_matte(lua_State *L)
{
    check_image(L, 1);
    lc_aov a = check_aov(L, 2);
    lua_Integer id = luaL_checkinteger(L, 3);
    if (id < 1 || id > INT_MAX)
        luaL_argerror(L, 3, lua_pushfstring(L, "an id >= 1 expected, got %I", id));
    return push_made(L, lc_image_matte, a, (int)id);
}

static int w_image_tostring(lua_State *L)
{
    lb_ud_image *u = luaL_checkudata(L, 1, LB_IMAGE);
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
    } else if (strcmp(k, "alpha") == 0) {
        lua_pushboolean(L, lc_image_has_alpha(check_image(L, 1)));
    } else if (strcmp(k, "region") == 0 || strcmp(k, "frame") == 0) {
        /* region: {x0, y0, x1, y1} in pixel edges, as render's option; frame:
        ** {width, height} of the frame it is part of. */
        lc_image *img = check_image(L, 1);
        lc_window w = lc_image_window(img);
        int v[4] = {w.x0, w.y0, w.x0 + lc_image_width(img), w.y0 + lc_image_height(img)};
        int nv = k[0] == 'r' ? 4 : 2;
        if (nv == 2)
            v[0] = w.frame_width, v[1] = w.frame_height;
        lua_createtable(L, nv, 0);
        for (int i = 0; i < nv; i++) {
            lua_pushinteger(L, v[i]);
            lua_rawseti(L, -2, i + 1);
        }
    } else {
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
    }
    return 1;
}


void lb_image_register(lua_State *L)
{
    static const luaL_Reg image_meta[] = {
        {"__gc", w_image_free}, {"__close", w_image_free}, {"__tostring", w_image_tostring},
        {"__index", w_image_index}, {NULL, NULL}};
    static const luaL_Reg image_methods[] = {
        {"save", w_image_save}, {"pixel", w_image_pixel}, {"diff", w_image_diff},
        {"nonfinite", w_image_nonfinite}, {"set", w_image_set}, {"error", w_image_error},
        {"add", w_image_add}, {"aov", w_image_aov}, {"aovs", w_image_aovs},
        {"matte", w_image_matte}, {NULL, NULL}};
    lb_class(L, LB_IMAGE, image_meta, image_methods);
    lua_pushcfunction(L, w_load_png);
    lua_setfield(L, -2, "load_png");
    lua_pushcfunction(L, w_load_exr);
    lua_setfield(L, -2, "load_exr");
    lua_pushcfunction(L, w_load_hdr);
    lua_setfield(L, -2, "load_hdr");
    lua_pushcfunction(L, w_merge);
    lua_setfield(L, -2, "merge_tiles");
    lua_pushcfunction(L, w_image);
    lua_setfield(L, -2, "image");
}
