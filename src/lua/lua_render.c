/* lua_render.c: scene:render: its options, the statistics table, the render. */
#include <math.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"
#include "progress_bar.h"
#include "base/clock.h"

static void push_stats(lua_State *L, const lc_stats *st, double lua_seconds)
{
    lua_createtable(L, 0, 16);
    lua_pushnumber(L, lua_seconds);
    lua_setfield(L, -2, "lua_seconds");
    lua_pushinteger(L, (lua_Integer)st->prim_tests);
    lua_setfield(L, -2, "prim_tests");
    lua_pushinteger(L, (lua_Integer)st->node_tests);
    lua_setfield(L, -2, "node_tests");
    lua_pushinteger(L, (lua_Integer)st->csg_tests);
    lua_setfield(L, -2, "csg_tests");
    lua_pushnumber(L, st->seconds);
    lua_setfield(L, -2, "seconds");
    lua_pushnumber(L, st->compile_seconds);
    lua_setfield(L, -2, "compile_seconds");
    lua_pushnumber(L, st->trace_seconds);
    lua_setfield(L, -2, "trace_seconds");
    lua_pushinteger(L, st->threads);
    lua_setfield(L, -2, "threads");
    lua_pushinteger(L, (lua_Integer)st->bvh_nodes);
    lua_setfield(L, -2, "bvh_nodes");
    lua_pushinteger(L, (lua_Integer)st->primitives);
    lua_setfield(L, -2, "primitives");
    lua_pushinteger(L, (lua_Integer)st->degenerate);
    lua_setfield(L, -2, "degenerate");
    lua_pushinteger(L, (lua_Integer)st->self_hits);
    lua_setfield(L, -2, "self_hits");
    lua_pushinteger(L, (lua_Integer)st->samples);
    lua_setfield(L, -2, "samples");
    lua_pushinteger(L, (lua_Integer)st->converged);
    lua_setfield(L, -2, "converged");
    lua_createtable(L, 0, LC_RAY_KINDS);
    for (int k = 0; k < LC_RAY_KINDS; k++) {
        lua_pushinteger(L, (lua_Integer)st->rays[k]);
        lua_setfield(L, -2, lc_ray_kind_name((lc_ray_kind)k));
    }
    lua_setfield(L, -2, "rays");
    lua_newtable(L);
    for (unsigned bit = 1; bit < 1u << LC_NEEDS; bit <<= 1) {
        lua_pushboolean(L, (st->needs & bit) != 0);
        lua_setfield(L, -2, lc_need_name(bit));
    }
    lua_setfield(L, -2, "effects");
    lua_newtable(L);
    for (int k = 0; k < LC_NEEDS; k++) {
        lua_pushstring(L, st->why[k]);
        lua_setfield(L, -2, lc_need_name(1u << k));
    }
    lua_setfield(L, -2, "why");
    lb_aov_push_names(L, st->aovs);
    lua_setfield(L, -2, "aovs");
    if (st->warning[0]) {
        lua_pushstring(L, st->warning);
        lua_setfield(L, -2, "warning");
    }
    lua_pushinteger(L, st->passes);
    lua_setfield(L, -2, "passes");
    lua_pushboolean(L, st->stopped);
    lua_setfield(L, -2, "stopped");
}

static const char *const sampler_opts[] = {"sobol", "jitter", "random", NULL};

int lb_aov_of_name(lua_State *L, int idx, const char **why)
{
    idx = lua_absindex(L, idx);         /* the buffer below pushes */
    const char *name = lua_type(L, idx) == LUA_TSTRING ? lua_tostring(L, idx) : NULL;
    for (int k = 0; name && k < LC_AOVS; k++)
        if (strcmp(name, lc_aov_name((lc_aov)k)) == 0)
            return k;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "expected one of ");
    for (int k = 0; k < LC_AOVS; k++) {
        lua_pushfstring(L, "%s'%s'", k ? ", " : "", lc_aov_name((lc_aov)k));
        luaL_addvalue(&b);
    }
    if (name)
        lua_pushfstring(L, ", got '%s'", name);
    else
        lua_pushfstring(L, ", got %s", luaL_typename(L, idx));
    luaL_addvalue(&b);
    luaL_pushresult(&b);
    *why = lua_tostring(L, -1);               /* on the stack until the caller raises */
    return -1;
}

void lb_aov_push_names(lua_State *L, unsigned bits)
{
    lua_newtable(L);
    int n = 0;
    for (int k = 0; k < LC_AOVS; k++)
        if (bits & (1u << k)) {
            lua_pushstring(L, lc_aov_name((lc_aov)k));
            lua_rawseti(L, -2, ++n);
        }
}

/* aovs = {'depth', 'normal', ...}: the AOVs rendered beside the beauty. */
static unsigned read_aovs(lua_State *L, int arg)
{
    unsigned bits = 0;
    if (lua_getfield(L, arg, "aovs") != LUA_TNIL) {
        if (lua_type(L, -1) != LUA_TTABLE)
            lf_error(L, arg, "aovs", "a list of AOV names expected, got %s",
                     luaL_typename(L, -1));
        lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_rawgeti(L, -1, i);
            const char *why;
            int k = lb_aov_of_name(L, -1, &why);
            if (k < 0)
                lf_error(L, arg, "aovs", "item %d: %s", (int)i, why);
            bits |= 1u << k;
            lua_pop(L, 1);
        }
    }
    lua_pop(L, 1);
    return bits;
}

void lb_render_read_options(lua_State *L, int arg, lc_render_options *o)
{
    *o = lc_render_options_default();
    o->width = lf_integer(L, arg, "width", 0, o->width);
    o->height = lf_integer(L, arg, "height", 0, o->height);
    o->samples = lf_integer(L, arg, "samples", 0, o->samples);
    o->seed = 0;
    if (lua_getfield(L, arg, "seed") != LUA_TNIL) {
        int isint;
        if (lua_type(L, -1) != LUA_TNUMBER)
            lf_error(L, arg, "seed", "number expected, got %s", luaL_typename(L, -1));
        double x = lua_tonumber(L, -1);
        if (isnan(x))
            lf_error(L, arg, "seed", "NaN is not a number here");
        lua_Integer seed = lua_tointegerx(L, -1, &isint);
        if (!isint || seed < 0)
            lf_error(L, arg, "seed", "non-negative integer expected, got %s",
                     luaL_tolstring(L, -1, NULL));
        o->seed = (uint64_t)seed;
    }
    lua_pop(L, 1);
    o->threads = lf_integer(L, arg, "threads", 0, 0);
    o->cosine = lf_boolean(L, arg, "cosine", 1);
    o->shadows = lf_boolean(L, arg, "shadows", 1);
    o->reflections = lf_boolean(L, arg, "reflections", 1);
    o->specular = lf_boolean(L, arg, "specular", 1);
    o->generic = lf_boolean(L, arg, "generic", 0);
    o->cutoff = lf_number(L, arg, "cutoff", 0, o->cutoff);
    int frame = lf_integer(L, arg, "frame", 0, 0);
    if (frame < 0)
        lf_error(L, arg, "frame", "must be >= 0, got %d", frame);
    o->frame = (uint32_t)frame;
    o->sampler = (lc_sampler)lf_option(L, arg, "sampler", sampler_opts, (int)o->sampler);
    o->light_samples = lf_integer(L, arg, "light_samples", 0, o->light_samples);
    o->cone_samples = lf_integer(L, arg, "cone_samples", 0, o->cone_samples);
    o->max_depth = lf_integer(L, arg, "max_depth", 0, o->max_depth);
    o->noise = lf_number(L, arg, "noise", 0, o->noise);
    o->min_samples = lf_integer(L, arg, "min_samples", 0, o->min_samples);
    o->glossy = lf_boolean(L, arg, "glossy", 1);
    o->alpha = lf_boolean(L, arg, "alpha", 0);
    o->indirect = lf_integer(L, arg, "indirect", 0, 0);
    o->roulette = lf_boolean(L, arg, "roulette", 1);
    o->nee = lf_boolean(L, arg, "nee", 1);
    o->aovs = read_aovs(L, arg);
    /* ao = {samples = N, distance = D}: both required. */
    if (lua_getfield(L, arg, "ao") != LUA_TNIL) {
        static const char *const ao_known[] = {"samples", "distance", NULL};
        if (lua_type(L, -1) != LUA_TTABLE)
            lf_error(L, arg, "ao", "{samples = N, distance = D} expected, got %s",
                     luaL_typename(L, -1));
        int at = lua_gettop(L);
        lua_pushnil(L);
        while (lua_next(L, at)) {
            lua_pop(L, 1);
            const char *k = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : NULL;
            int ok = 0;
            for (int i = 0; k && ao_known[i]; i++)
                ok |= strcmp(k, ao_known[i]) == 0;
            if (!ok)
                lf_error(L, arg, "ao", "unknown field '%s'; known fields are samples, "
                         "distance", k ? k : luaL_typename(L, -1));
        }
        lua_getfield(L, at, "samples");
        int isint;
        lua_Integer n = lua_tointegerx(L, -1, &isint);
        if (!isint || n < 1 || n > LC_MAX_AO_SAMPLES)
            lf_error(L, arg, "ao", "samples: an integer in [1, %d] expected, got %s",
                     LC_MAX_AO_SAMPLES, luaL_tolstring(L, -1, NULL));
        lua_getfield(L, at, "distance");
        double d = lua_tonumber(L, -1);
        if (lua_type(L, -1) != LUA_TNUMBER || !(d > 0 && d <= LC_MAX_COORD))
            lf_error(L, arg, "ao", "distance: a number in (0, %g] expected, got %s",
                     LC_MAX_COORD, luaL_tolstring(L, -1, NULL));
        o->ao_samples = (int)n;
        o->ao_distance = d;
        lua_settop(L, at);
    }
    lua_pop(L, 1);
    /* region = {x0, y0, x1, y1}: whole numbers; the core checks they fit. */
    if (lua_getfield(L, arg, "region") != LUA_TNIL) {
        if (lua_type(L, -1) != LUA_TTABLE)
            lf_error(L, arg, "region", "{x0, y0, x1, y1} expected, got %s",
                     luaL_typename(L, -1));
        if (lua_rawlen(L, -1) != 4)
            lf_error(L, arg, "region", "{x0, y0, x1, y1} expected, got %d values",
                     (int)lua_rawlen(L, -1));
        for (int k = 0; k < 4; k++) {
            int isint;
            lua_rawgeti(L, -1, k + 1);
            lua_Integer v = lua_tointegerx(L, -1, &isint);
            if (!isint || v < 0 || v > LC_MAX_SIDE)
                lf_error(L, arg, "region", "item %d: a whole number in [0, %d] expected, "
                         "got %s", k + 1, LC_MAX_SIDE, luaL_tolstring(L, -1, NULL));
            o->region[k] = (int)v;
            lua_pop(L, 1);
        }
    }
    lua_pop(L, 1);
}

/* progress = true, false or 'lines' (absent: automatic). */
static int progress_mode(lua_State *L, int arg)
{
    int mode = PROGRESS_AUTO;
    int t = lua_getfield(L, arg, "progress");
    if (t == LUA_TBOOLEAN)
        mode = lua_toboolean(L, -1) ? PROGRESS_BAR : PROGRESS_NONE;
    else if (t == LUA_TSTRING && strcmp(lua_tostring(L, -1), "lines") == 0)
        mode = PROGRESS_LINES;
    else if (t != LUA_TNIL)
        lf_error(L, arg, "progress", "true, false or 'lines' expected, got %s",
                 t == LUA_TSTRING ? lua_pushfstring(L, "'%s'", lua_tostring(L, -1))
                                  : luaL_typename(L, -1));
    lua_pop(L, 1);
    return mode;
}

/* Stands for a Lua on_pass in the options the core checks; the render
** replaces it with pass_called. */
static int pass_placeholder(void *ud, const lc_image *img, int pass,
                            const struct lc_stats *st)
{
    (void)ud, (void)img, (void)pass, (void)st;
    return 0;
}

/* Checks render's arguments: the scene at 1, the options at 2 (a table
** afterwards); the options in *o and what progress to show in *show.
** Reading the options may run a script's metamethods: render_work checks
** the scene again. */
static void render_args(lua_State *L, lc_render_options *o, int *show, int plain)
{
    static const char *const known[] = {LB_RENDER_OPTIONS, "progress", "progressive",
                                        "on_pass", NULL};
    lb_scene_check(L, 1);
    lua_settop(L, 2);
    if (lua_isnil(L, 2)) {
        lua_newtable(L);
        lua_replace(L, 2);
    }
    lf_open(L, 2, known);
    lb_render_read_options(L, 2, o);
    *show = progress_mode(L, 2);
    o->progressive = lf_boolean(L, 2, "progressive", 0);
    int t = lua_getfield(L, 2, "on_pass");
    if (t != LUA_TNIL && t != LUA_TFUNCTION)
        lf_error(L, 2, "on_pass", "function expected, got %s", luaL_typename(L, -1));
    lua_pop(L, 1);
    if (t == LUA_TFUNCTION && !o->progressive)
        lf_error(L, 2, "on_pass", "is called after each pass of a progressive render: "
                 "set progressive = true too");
    o->on_pass = t == LUA_TFUNCTION ? pass_placeholder : NULL;
    lc_error err;
    if (lc_render_options_check(o, &err))
        lb_hook_raise(L, plain, 2, &err);
}

/* Renders whose on_pass may run Lua code now, in this state. */
static const char passing_key = 'p';

static int passing(lua_State *L)
{
    lua_rawgetp(L, LUA_REGISTRYINDEX, &passing_key);
    int n = (int)lua_tointeger(L, -1);
    lua_pop(L, 1);
    return n;
}

static void set_passing(lua_State *L, int n)
{
    lua_pushinteger(L, n);
    lua_rawsetp(L, LUA_REGISTRYINDEX, &passing_key);
}

void lb_render_check_idle(lua_State *L, const char *what)
{
    if (passing(L) > 0)
        luaL_error(L, "%s: no mesh may grow while a render's on_pass runs (a scene "
                   "rendering may hold it)", what);
}

/* What a render's on_pass calls need, on render_work's stack. */
typedef struct {
    lua_State *L;
    int        fn;          /* stack index of the script's on_pass */
    int        result;      /* stack index of its error, or of the bad value it returned */
    int        failed;      /* 1: it raised; 2: it returned something else than nil,
                            ** true or false */
    double     lua_seconds;
} pass_ctx;

/* lua_pcall'd by pass_called, so that nothing raises through the core:
** on_pass(copy of the image, pass, stats). Returns 0 to go on, 1 to stop,
** or 2 and the value returned, when it is no boolean nor nil. */
static int pass_call(lua_State *L)
{
    const lc_image *img = lua_touserdata(L, 2);
    const lc_stats *st = lua_touserdata(L, 4);
    double lua_seconds = lua_tonumber(L, 5);
    lua_pushvalue(L, 1);
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0); /* before the copy */
    ui->img = NULL;
    luaL_setmetatable(L, LB_IMAGE);
    lc_error err;
    ui->img = lc_image_copy(img, &err);
    if (!ui->img)
        return luaL_error(L, "on_pass: %s", err.msg);
    lua_pushvalue(L, 3);
    push_stats(L, st, lua_seconds);
    lb_charge(L);
    lua_call(L, 3, 1);
    if (lua_isnil(L, -1) || lua_isboolean(L, -1)) {
        lua_pushinteger(L, lua_isboolean(L, -1) && !lua_toboolean(L, -1));
        return 1;
    }
    lua_pushinteger(L, 2);
    lua_insert(L, -2);
    return 2;
}

/* The core's lc_pass_fn: on_pass, protected. What it raised or returned
** wrong stops the render and waits at ctx->result for render_work. */
static int pass_called(void *ud, const lc_image *img, int pass, const struct lc_stats *st)
{
    pass_ctx *c = ud;
    lua_State *L = c->L;
    lua_pushcfunction(L, pass_call);
    lua_pushvalue(L, c->fn);
    lua_pushlightuserdata(L, (void *)img);
    lua_pushinteger(L, pass);
    lua_pushlightuserdata(L, (void *)st);
    lua_pushnumber(L, c->lua_seconds);
    if (lua_pcall(L, 5, 2, 0) != LUA_OK) {
        lua_replace(L, c->result);
        c->failed = 1;
        return 1;
    }
    int r = (int)lua_tointeger(L, -2);
    if (r == 2) {
        lua_pushvalue(L, -1);
        lua_replace(L, c->result);
        c->failed = 2;
    }
    lua_pop(L, 2);
    return r != 0;
}

/* Renders the scene at 1: pushes the image and the statistics. */
static int render_work(lua_State *L, lc_render_options *o, int show, int plain)
{
    lb_ud_scene *u = lb_scene_check(L, 1);
    pass_ctx pc = {L, 0, 0, 0, 0};
    if (o->on_pass) {
        luaL_checkstack(L, 12, "render's on_pass");
        lua_getfield(L, 2, "on_pass");            /* checked by render_args */
        pc.fn = lua_gettop(L);
        if (lua_type(L, pc.fn) != LUA_TFUNCTION)  /* changed by a metamethod since */
            return lb_hook_fail(L, plain, 2, "field 'on_pass': function expected");
        lua_pushnil(L);
        pc.result = lua_gettop(L);
        o->on_pass = pass_called;
        o->on_pass_ud = &pc;
    }
    lb_ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0); /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, LB_IMAGE);
    int image = lua_gettop(L);
    lc_stats st;
    lc_error err;
    progress_bar bar;
    progress_bar_begin(&bar, show);
    o->progress = progress_bar_update;
    o->progress_ud = &bar;
    double lua_seconds = clock_seconds() - u->mark;
    pc.lua_seconds = lua_seconds;
    /* Fetched after the allocations above, which may run finalizers. */
    lc_scene *s = lb_scene_at(L, 1);
    if (o->on_pass) {
        u->rendering = 1;
        set_passing(L, passing(L) + 1);
    }
    ui->img = lc_scene_render(s, o, &st, &err);
    if (o->on_pass) {
        u->rendering = 0;
        set_passing(L, passing(L) - 1);
    }
    u->mark = clock_seconds();
    progress_bar_end(&bar, ui->img != NULL && !st.stopped);
    if (pc.failed) {
        lc_image_free(ui->img);
        ui->img = NULL;
        if (pc.failed == 2)
            return lb_hook_fail(L, plain, 2, lua_pushfstring(L, "field 'on_pass': "
                                "returned %s; nil, true or false expected (false "
                                "stops the render)", luaL_typename(L, pc.result)));
        lua_pushvalue(L, pc.result);
        return lua_error(L);                      /* as the script's on_pass raised it */
    }
    if (!ui->img) {
        if (strcmp(err.field, "camera") == 0)
            return lb_hook_fail(L, plain, 0, "render: the scene has no camera (set "
                                "scene.camera = lancer.camera{...})");
        return lb_hook_raise(L, plain, 2, &err);
    }
    lua_settop(L, image);
    lb_charge(L);
    push_stats(L, &st, lua_seconds);
    return 2;
}

/* The hook's plain render (lua_hook.c). */
static int render_plain(lua_State *L)
{
    lc_render_options o;
    int show;
    render_args(L, &o, &show, 1);
    return render_work(L, &o, show, 1);
}

/* A render's warning, as a Lua warning the host shows or not (its warn
** function; lua5.4 -W; the lancer command always). */
static void warn_render(lua_State *L, const char *msg)
{
    lua_pushfstring(L, "lancer: warning: %s", msg);
    lua_warning(L, lua_tostring(L, -1), 0);
    lua_pop(L, 1);
}

/* scene:render{width = , height = , samples = , ...}: img, stats. The
** warning in the statistics it returns (the hook's, when one is set: once
** for each render the script asked for) is a Lua warning (warn_render). */
static int w_scene_render(lua_State *L)
{
    lc_render_options o;
    int show;
    render_args(L, &o, &show, 0);
    int n = lb_hook_call(L, "render", render_plain, 2);
    if (n < 0)
        n = render_work(L, &o, show, 0);
    if (n >= 2 && lua_type(L, -n + 1) == LUA_TTABLE) {
        if (lua_getfield(L, -n + 1, "warning") == LUA_TSTRING)
            warn_render(L, lua_tostring(L, -1));
        lua_pop(L, 1);
    }
    return n;
}

void lb_render_register(lua_State *L)
{
    static const luaL_Reg methods[] = {{"render", w_scene_render}, {NULL, NULL}};
    luaL_getmetatable(L, LB_SCENE);
    lua_getfield(L, -1, "methods");
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
}
