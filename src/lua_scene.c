/* lua_scene.c: scenes: building, rendering with statistics, explaining a pixel. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_types.h"
#include "progress_bar.h"
#include "clock.h"

/* Mirror bounces: the chain is a loop, so this only bounds the time a
** render of two facing mirrors may take. */


/* ---- scenes --------------------------------------------------------------- */

static int w_records_free(lua_State *L)
{
    lc_ray_record **box = lua_touserdata(L, 1);
    free(*box);
    *box = NULL;
    return 0;
}

/* The scene's user value: see SC_CAMERA in lua_types.h. */

static ud_scene *check_scene(lua_State *L, int idx)
{
    ud_scene *u = luaL_checkudata(L, idx, SCENE);
    if (!u->s)
        luaL_argerror(L, idx, "lancer.Scene already freed");
    return u;
}

static void set_camera(lua_State *L, ud_scene *u, int sidx, int cidx, int arg,
                       const char *field)
{
    ud_camera *c = luaL_testudata(L, cidx, CAMERA);
    if (!c) {
        const char *got = luaL_typename(L, cidx);
        if (luaL_getmetafield(L, cidx, "__name") == LUA_TSTRING)
            got = lua_tostring(L, -1);
        if (arg)
            lf_error(L, arg, field, "lancer.Camera expected, got %s", got);
        luaL_error(L, "scene.camera: lancer.Camera expected, got %s", got);
    }
    lc_error err;
    if (lc_scene_set_camera(u->s, &c->c, &err))
        luaL_error(L, "%s", err.msg);
    lua_getiuservalue(L, sidx, 1);
    lua_pushvalue(L, cidx);
    lua_rawseti(L, -2, SC_CAMERA);
    lua_pop(L, 1);
}

static int w_scene(lua_State *L)
{
    static const char *const known[] = {"camera", "background", "ambient", "max_depth",
                                        NULL};
    if (lua_isnoneornil(L, 1)) {
        lua_settop(L, 0);
        lua_newtable(L);
    }
    lf_open(L, 1, known);
    lc_settings st = lc_settings_default();
    st.background = lf_color(L, 1, "background", 0, st.background);
    st.ambient = lf_color(L, 1, "ambient", 0, st.ambient);
    st.max_depth = lf_integer(L, 1, "max_depth", 0, st.max_depth);  /* range: the core's */
    int has_camera = lf_present(L, 1, "camera");
    if (has_camera)
        lf_udata(L, 1, "camera", CAMERA, 1);   /* type check before allocating */

    ud_scene *u = lua_newuserdatauv(L, sizeof *u, 1);   /* before the core object */
    u->s = NULL;
    luaL_setmetatable(L, SCENE);
    int sidx = lua_gettop(L);
    lua_createtable(L, 4, 0);
    lua_newtable(L);
    lua_rawseti(L, -2, SC_MATERIALS);
    lua_newtable(L);
    lua_rawseti(L, -2, SC_MESHES);
    lua_setiuservalue(L, sidx, 1);
    lc_error err;
    u->s = lc_scene_new(&err);
    u->mark = clock_seconds();
    if (!u->s)
        return luaL_error(L, "%s", err.msg);
    if (lc_scene_configure(u->s, &st, &err))
        return lf_raise(L, 1, &err);
    if (has_camera) {
        lua_getfield(L, 1, "camera");
        set_camera(L, u, sidx, lua_gettop(L), 1, "camera");
        lua_pop(L, 1);
    }
    lua_settop(L, sidx);
    return 1;
}

static int w_scene_free(lua_State *L)              /* __gc and __close */
{
    ud_scene *u = luaL_checkudata(L, 1, SCENE);
    lc_scene_free(u->s);
    u->s = NULL;                                    /* safe to call twice */
    return 0;
}

/* The core index of the material at stack index midx (nil: the default). */
static int material_index(lua_State *L, ud_scene *u, int sidx, int midx, int arg)
{
    lc_error err;
    lua_getiuservalue(L, sidx, 1);
    int uv = lua_gettop(L);
    int index;
    if (lua_isnil(L, midx)) {
        if (lua_rawgeti(L, uv, SC_DEFAULT) == LUA_TNUMBER) {
            index = (int)lua_tointeger(L, -1);
        } else {
            lc_material def = lc_material_default();
            index = lc_scene_add_material(u->s, &def, &err);
            if (index < 0)
                lf_raise(L, arg, &err);
            lua_pushinteger(L, index);
            lua_rawseti(L, uv, SC_DEFAULT);
        }
    } else {
        lua_rawgeti(L, uv, SC_MATERIALS);
        lua_pushvalue(L, midx);
        if (lua_rawget(L, -2) == LUA_TNUMBER) {
            index = (int)lua_tointeger(L, -1);
        } else {
            const ud_material *m = luaL_checkudata(L, midx, MATERIAL);
            index = lc_scene_add_material(u->s, &m->m, &err);
            if (index < 0)
                lf_raise(L, arg, &err);
            lua_pushvalue(L, midx);
            lua_pushinteger(L, index);
            lua_rawset(L, -4);
        }
    }
    lua_settop(L, uv - 1);
    return index;
}

/* The group at idx moves its members by its transform after xf's (NULL:
** none); fills *out and returns it. */
static const lc_transform *group_xf(lua_State *L, int idx, const lc_transform *xf,
                                    lc_transform *out)
{
    const ud_group *g = lua_touserdata(L, idx);
    *out = xf ? lc_transform_compose(xf, &g->t) : g->t;
    return out;
}

static void element_error(lua_State *L, int arg, lua_Integer elem, const char *msg)
{
    if (elem)
        lua_pushfstring(L, "element %I: %s", elem, msg);
    else
        lua_pushstring(L, msg);
    luaL_argerror(L, arg, lua_tostring(L, -1));
}

/* Raises unless the value at idx is a shape, a light, a group or an array
** of them that can be moved by xf (NULL: not moved), so that a bad call to
** add leaves the scene as it was. */
static void check_addable(lua_State *L, int idx, int arg, int depth, lua_Integer elem,
                          const lc_transform *xf)
{
    idx = lua_absindex(L, idx);
    lc_error err;
    ud_shape *sh = luaL_testudata(L, idx, SHAPE);
    if (sh) {
        lc_shape out;
        if (xf && lc_shape_transform(&sh->s, xf, &out, &err))
            element_error(L, arg, elem, err.msg);
        return;
    }
    ud_light *li = luaL_testudata(L, idx, LIGHT);
    if (li) {
        lc_point_light l = li->l;
        if (xf)
            l.position = lc_transform_point(xf, l.position);
        if (lc_point_light_check(&l, &err))
            element_error(L, arg, elem, err.msg);
        return;
    }
    ud_mesh *me = luaL_testudata(L, idx, MESH);
    if (me) {
        if (!me->m)
            luaL_argerror(L, arg, "lancer.Mesh already freed");
        if (xf && lc_transform_check(xf, &err))
            element_error(L, arg, elem, err.msg);
        return;
    }
    if (luaL_testudata(L, idx, GROUP) && depth < 64) {
        lc_transform g;
        xf = group_xf(L, idx, xf, &g);
        lua_getiuservalue(L, idx, 1);
        lua_Integer n = luaL_len(L, -1);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_geti(L, -1, i);
            check_addable(L, -1, arg, depth + 1, elem ? elem : i, xf);
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
        return;
    }
    if (lua_type(L, idx) == LUA_TTABLE && depth < 64) {
        lua_Integer n = luaL_len(L, idx);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_geti(L, idx, i);
            check_addable(L, -1, arg, depth + 1, i, xf);
            lua_pop(L, 1);
        }
        return;
    }
    const char *got = luaL_typename(L, idx);
    if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING)
        got = lua_tostring(L, -1);
    if (elem)
        lua_pushfstring(L, "element %I: shape, mesh, light, group or array of them "
                        "expected, got %s", elem, got);
    else
        lua_pushfstring(L, "shape, mesh, light, group or array of them expected, got %s",
                        got);
    luaL_argerror(L, arg, lua_tostring(L, -1));
}

/* Adds the object at idx, already checked, moved by xf (NULL: as it is). */
static void add_one(lua_State *L, ud_scene *u, int idx, int arg, const lc_transform *xf)
{
    lc_error err;
    idx = lua_absindex(L, idx);
    ud_shape *sh = luaL_testudata(L, idx, SHAPE);
    if (sh) {
        lc_shape moved = sh->s;
        if (xf && lc_shape_transform(&sh->s, xf, &moved, &err))
            lf_raise(L, arg, &err);
        lua_getiuservalue(L, idx, 1);
        int mat = material_index(L, u, 1, lua_gettop(L), arg);
        lua_pop(L, 1);
        if (lc_scene_add_shape(u->s, &moved, mat, &err) < 0)
            lf_raise(L, arg, &err);
        return;
    }
    ud_mesh *me = luaL_testudata(L, idx, MESH);
    if (me) {
        lua_getiuservalue(L, idx, 1);
        int mat = material_index(L, u, 1, lua_gettop(L), arg);
        lua_pop(L, 1);
        if ((xf ? lc_scene_add_mesh_moved(u->s, me->m, xf, mat, &err)
                : lc_scene_add_mesh(u->s, me->m, mat, &err)) < 0)
            lf_raise(L, arg, &err);
        lua_getiuservalue(L, 1, 1);             /* so scene:objects() can name it */
        lua_rawgeti(L, -1, SC_MESHES);
        lua_pushlightuserdata(L, me->m);
        lua_pushvalue(L, idx);
        lua_rawset(L, -3);
        lua_pop(L, 2);
        return;
    }
    ud_light *li = luaL_testudata(L, idx, LIGHT);
    if (li) {
        lc_point_light l = li->l;
        if (xf)
            l.position = lc_transform_point(xf, l.position);
        if (lc_scene_add_light(u->s, &l, &err) < 0)
            lf_raise(L, arg, &err);
        return;
    }
    lc_transform g;
    if (luaL_testudata(L, idx, GROUP)) {
        xf = group_xf(L, idx, xf, &g);
        lua_getiuservalue(L, idx, 1);
        idx = lua_gettop(L);
    }
    lua_Integer n = luaL_len(L, idx);
    for (lua_Integer i = 1; i <= n; i++) {
        lua_geti(L, idx, i);
        add_one(L, u, -1, arg, xf);
        lua_pop(L, 1);
    }
}

static int w_scene_add(lua_State *L)
{
    ud_scene *u = check_scene(L, 1);
    int n = lua_gettop(L);
    if (n < 2)
        return luaL_argerror(L, 2, "shape, mesh, light, group or array of them expected, "
                             "got no value");
    for (int i = 2; i <= n; i++)
        check_addable(L, i, i, 0, 0, NULL);
    for (int i = 2; i <= n; i++)
        add_one(L, u, i, i, NULL);
    lua_settop(L, 1);
    return 1;
}

/* scene:transformed(scale [, offset]): the copy lc_scene_transformed makes,
** sharing this scene's material table (same indices) with a moved camera. */
static int w_scene_transformed(lua_State *L)
{
    ud_scene *u = check_scene(L, 1);
    double scale = luaL_checknumber(L, 2);
    lc_vec3 off = {0, 0, 0};
    char why[160];
    if (!lua_isnoneornil(L, 3) && !lf_to_vec3(L, 3, &off, why, sizeof why))
        return luaL_argerror(L, 3, why);
    ud_scene *c = lua_newuserdatauv(L, sizeof *c, 1);      /* before the copy */
    c->s = NULL;
    c->mark = clock_seconds();
    luaL_setmetatable(L, SCENE);
    int ci = lua_gettop(L);
    lua_createtable(L, 4, 0);
    lua_getiuservalue(L, 1, 1);
    lua_rawgeti(L, -1, SC_MATERIALS);
    lua_rawseti(L, -3, SC_MATERIALS);
    lua_rawgeti(L, -1, SC_DEFAULT);
    lua_rawseti(L, -3, SC_DEFAULT);
    lua_rawgeti(L, -1, SC_MESHES);         /* instances keep their meshes */
    lua_rawseti(L, -3, SC_MESHES);
    lua_pop(L, 1);
    lua_setiuservalue(L, ci, 1);
    lc_error err;
    c->s = lc_scene_transformed(u->s, scale, off, &err);
    if (!c->s)
        return lf_raise(L, 2, &err);
    lc_camera moved;
    if (lc_scene_camera(c->s, &moved)) {
        ud_camera *cam = lua_newuserdatauv(L, sizeof *cam, 0);
        cam->c = moved;
        luaL_setmetatable(L, CAMERA);
        lua_getiuservalue(L, ci, 1);
        lua_insert(L, -2);
        lua_rawseti(L, -2, SC_CAMERA);
        lua_pop(L, 1);
    }
    lua_settop(L, ci);
    return 1;
}

static int w_scene_count(lua_State *L)
{
    ud_scene *u = check_scene(L, 1);
    lua_pushinteger(L, (lua_Integer)lc_scene_shape_count(u->s));
    lua_pushinteger(L, (lua_Integer)lc_scene_light_count(u->s));
    return 2;
}

/* What the command line (lancer --width ...) asked for wins over the script. */
static void apply_overrides(lua_State *L, lc_render_options *o)
{
    static const char *const mods[] = {"lancer", "lancer.core"};
    static const char *const names[] = {"width", "height", "samples"};
    int *dst[] = {&o->width, &o->height, &o->samples};
    int top = lua_gettop(L);
    lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    int loaded = lua_gettop(L);
    for (int i = 0; i < 2; i++) {
        lua_settop(L, loaded);
        if (lua_getfield(L, loaded, mods[i]) != LUA_TTABLE ||
            lua_getfield(L, -1, "overrides") != LUA_TTABLE)
            continue;
        int t = lua_gettop(L);
        for (int k = 0; k < 3; k++) {
            if (lua_getfield(L, t, names[k]) != LUA_TNIL) {
                if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 ||
                    lua_tointeger(L, -1) > LC_MAX_SIDE)
                    luaL_error(L, "lancer.overrides.%s: integer in [1, %d] expected, got %s",
                               names[k], LC_MAX_SIDE, luaL_tolstring(L, -1, NULL));
                *dst[k] = (int)lua_tointeger(L, -1);
            }
            lua_pop(L, 1);
        }
        break;
    }
    lua_settop(L, top);
}

static void push_stats(lua_State *L, const lc_stats *st, double lua_seconds)
{
    lua_createtable(L, 0, 16);
    lua_pushnumber(L, lua_seconds);
    lua_setfield(L, -2, "lua_seconds");
    lua_pushinteger(L, (lua_Integer)st->prim_tests);
    lua_setfield(L, -2, "prim_tests");
    lua_pushinteger(L, (lua_Integer)st->node_tests);
    lua_setfield(L, -2, "node_tests");
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
}

/* lancer.overrides[name] is true: --check sends renders to lancer.check,
** --accuracy to lancer.accuracy, --stats prints each render's ledger. */
static int override_flag(lua_State *L, const char *name)
{
    int top = lua_gettop(L), on = 0;
    lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    if (lua_getfield(L, -1, "lancer") == LUA_TTABLE &&
        lua_getfield(L, -1, "overrides") == LUA_TTABLE) {
        lua_getfield(L, -1, name);
        on = lua_toboolean(L, -1);
    }
    lua_settop(L, top);
    return on;
}

/* Hands render(scene, opts) to module.render: --check and --accuracy. */
static int divert_render(lua_State *L, const char *module)
{
    lua_getglobal(L, "require");
    lua_pushstring(L, module);
    lua_call(L, 1, 1);
    lua_getfield(L, -1, "render");
    lua_pushvalue(L, 1);
    lua_pushvalue(L, 2);
    lua_call(L, 2, 2);
    return 2;
}

static const char *const sampler_opts[] = {"sobol", "jitter", "random", NULL};

/* The sampling and quality options render and explain both read. */
#define RENDER_KNOBS "frame", "sampler", "light_samples", "cone_samples", "max_depth", \
                     "noise", "min_samples", "glossy"

/* The options render and explain share, from the table at arg (checked). */
static void read_render_options(lua_State *L, int arg, lc_render_options *o)
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
    lc_error err;
    if (lc_render_options_check(o, &err))
        lf_raise(L, arg, &err);
}

static int w_scene_render(lua_State *L)
{
    static const char *const known[] = {"width", "height", "samples", "seed", "threads",
                                        "cosine", "cutoff", "progress", "shadows",
                                        "reflections", "specular", "generic", RENDER_KNOBS,
                                        NULL};
    ud_scene *u = check_scene(L, 1);
    lua_settop(L, 2);
    if (override_flag(L, "check"))
        return divert_render(L, "lancer.check");
    if (override_flag(L, "accuracy"))
        return divert_render(L, "lancer.accuracy");
    if (lua_isnoneornil(L, 2)) {
        lua_settop(L, 1);
        lua_newtable(L);
    }
    lf_open(L, 2, known);
    lc_render_options o;
    read_render_options(L, 2, &o);
    int show = lf_present(L, 2, "progress") ? lf_boolean(L, 2, "progress", 0) : -1;
    apply_overrides(L, &o);

    ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);   /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, IMAGE);
    lc_stats st;
    lc_error err;
    progress_bar bar;
    progress_bar_begin(&bar, show);
    o.progress = progress_bar_update;
    o.progress_ud = &bar;
    double lua_seconds = clock_seconds() - u->mark;
    ui->img = lc_scene_render(u->s, &o, &st, &err);
    u->mark = clock_seconds();
    progress_bar_end(&bar);
    if (!ui->img) {
        if (strcmp(err.field, "camera") == 0)
            return luaL_error(L, "render: the scene has no camera (set scene.camera = "
                              "lancer.camera{...})");
        return lf_raise(L, 2, &err);
    }
    push_stats(L, &st, lua_seconds);
    int top = lua_gettop(L);                /* the image at top - 1, stats at top */
    if (override_flag(L, "stats")) {
        lua_getglobal(L, "require");
        lua_pushliteral(L, "lancer.ledger");
        lua_call(L, 1, 1);
        lua_getfield(L, -1, "report");
        lua_pushvalue(L, -3);
        lua_call(L, 1, 0);
        lua_pop(L, 1);
    }
    /* lancer.overrides.on_render(img, stats): the REPL's preview and save. */
    lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    if (lua_getfield(L, -1, "lancer") == LUA_TTABLE &&
        lua_getfield(L, -1, "overrides") == LUA_TTABLE &&
        lua_getfield(L, -1, "on_render") == LUA_TFUNCTION) {
        lua_pushvalue(L, top - 1);
        lua_pushvalue(L, top);
        lua_call(L, 2, 0);
    }
    lua_settop(L, top);
    return 2;
}

/* Pushes record i of recs as a table, its children (records whose parent is
** i) under 'rays'. */
static void push_record(lua_State *L, const lc_ray_record *recs, size_t n, size_t i)
{
    const lc_ray_record *x = &recs[i];
    lua_createtable(L, 0, 12);
    luaL_setmetatable(L, RAYTREE);
    lua_pushstring(L, lc_ray_kind_name(x->kind));
    lua_setfield(L, -2, "kind");
    lf_push_vec3(L, x->origin);
    lua_setfield(L, -2, "origin");
    lf_push_vec3(L, x->direction);
    lua_setfield(L, -2, "direction");
    lua_pushnumber(L, x->distance);
    lua_setfield(L, -2, "distance");
    lf_push_color(L, x->contribution);
    lua_setfield(L, -2, "contribution");
    if (x->kind == LC_RAY_SHADOW || x->kind == LC_RAY_LIGHT) {
        lua_pushboolean(L, x->hit);
        lua_setfield(L, -2, "visible");
        if (x->light >= 0)
            lua_pushfstring(L, "point light %d", x->light + 1);
        else
            lua_pushfstring(L, "emissive %d", -x->light);
        lua_setfield(L, -2, "light");
    } else if (x->hit) {
        lua_createtable(L, 0, 5);
        lua_pushnumber(L, x->distance);
        lua_setfield(L, -2, "distance");
        lf_push_vec3(L, x->point);
        lua_setfield(L, -2, "point");
        lf_push_vec3(L, x->normal);
        lua_setfield(L, -2, "normal");
        lua_pushfstring(L, "%s %d", lc_shape_kind_name((lc_shape_kind)x->shape_kind),
                        (int)x->shape + 1);
        lua_setfield(L, -2, "shape");
        lua_pushinteger(L, x->material + 1);
        lua_setfield(L, -2, "material");
        lua_setfield(L, -2, "hit");
    }
    lua_newtable(L);
    int k = 0;
    for (size_t j = i + 1; j < n; j++)
        if (recs[j].parent == (int)i) {
            push_record(L, recs, n, j);
            lua_rawseti(L, -2, ++k);
        }
    lua_setfield(L, -2, "rays");
}

/* scene:explain{x = , y = , sample = 1, ...render options}: the ray tree of
** one sample of one pixel, as nested tables that print as a tree. */
static int w_scene_explain(lua_State *L)
{
    static const char *const known[] = {"x", "y", "sample", "width", "height", "samples",
                                        "seed", "threads", "cosine", "cutoff", "shadows",
                                        "reflections", "specular", "generic", RENDER_KNOBS,
                                        NULL};
    ud_scene *u = check_scene(L, 1);
    lf_open(L, 2, known);
    lc_render_options o;
    read_render_options(L, 2, &o);
    apply_overrides(L, &o);
    int x = lf_integer(L, 2, "x", 1, 0), y = lf_integer(L, 2, "y", 1, 0);
    int sample = lf_integer(L, 2, "sample", 0, 1);
    /* The records belong to a userdata from the start: building the tables
    ** may raise (out of memory) and nothing may leak then. */
    lc_ray_record **box = lua_newuserdatauv(L, sizeof *box, 0);
    *box = NULL;
    lua_newtable(L);
    lua_pushcfunction(L, w_records_free);
    lua_setfield(L, -2, "__gc");
    lua_setmetatable(L, -2);
    size_t n;
    lc_error err;
    if (lc_scene_explain(u->s, &o, x - 1, y - 1, sample - 1, box, &n, &err))
        return lf_raise(L, 2, &err);
    push_record(L, *box, n, 0);
    return 1;
}

/* Writes one node and its children, indented, into b. */
static void tree_lines(lua_State *L, luaL_Buffer *b, int idx, int depth)
{
    idx = lua_absindex(L, idx);
    for (int i = 0; i < depth; i++)
        luaL_addstring(b, "  ");
    lua_getfield(L, idx, "kind");
    luaL_addstring(b, lua_tostring(L, -1));
    lua_pop(L, 1);
    char line[300];
    lua_getfield(L, idx, "contribution");
    lua_geti(L, -1, 1);
    lua_geti(L, -2, 2);
    lua_geti(L, -3, 3);
    double cr = lua_tonumber(L, -3), cg = lua_tonumber(L, -2), cb = lua_tonumber(L, -1);
    lua_pop(L, 4);
    if (lua_getfield(L, idx, "light") == LUA_TSTRING) {
        lua_getfield(L, idx, "visible");
        snprintf(line, sizeof line, " to %s: %s, adds (%.4g, %.4g, %.4g)\n",
                 lua_tostring(L, -2), lua_toboolean(L, -1) ? "visible" : "blocked",
                 cr, cg, cb);
        lua_pop(L, 1);
    } else if (lua_getfield(L, idx, "hit") == LUA_TTABLE) {
        lua_getfield(L, -1, "shape");
        lua_getfield(L, -2, "material");
        lua_getfield(L, -3, "distance");
        snprintf(line, sizeof line, " hits %s (material %d) at %.6g, adds (%.4g, %.4g, %.4g)\n",
                 lua_tostring(L, -3), (int)lua_tointeger(L, -2), lua_tonumber(L, -1),
                 cr, cg, cb);
        lua_pop(L, 4);
    } else {
        snprintf(line, sizeof line, " misses: background, adds (%.4g, %.4g, %.4g)\n",
                 cr, cg, cb);
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    luaL_addstring(b, line);
    lua_getfield(L, idx, "rays");
    int rays = lua_gettop(L);
    for (lua_Integer i = 1; lua_geti(L, rays, i) == LUA_TTABLE; i++) {
        tree_lines(L, b, -1, depth + 1);
        lua_pop(L, 1);
    }
    lua_pop(L, 2);
}

static int w_raytree_tostring(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    lua_pushvalue(L, 1);
    tree_lines(L, &b, -1, 0);
    lua_pop(L, 1);
    luaL_pushresult(&b);
    return 1;
}

static int w_scene_tostring(lua_State *L)
{
    ud_scene *u = luaL_checkudata(L, 1, SCENE);
    if (!u->s)
        lua_pushstring(L, "lancer.Scene (freed)");
    else
        lua_pushfstring(L, "lancer.Scene (%d shapes, %d lights)",
                        (int)lc_scene_shape_count(u->s), (int)lc_scene_light_count(u->s));
    return 1;
}

static int w_scene_index(lua_State *L)
{
    ud_scene *u = luaL_checkudata(L, 1, SCENE);
    const char *k = luaL_checkstring(L, 2);
    if (!u->s) {             /* closed: methods still resolve, and raise there */
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
        return 1;
    }
    lc_settings st = lc_scene_settings(u->s);
    if (strcmp(k, "camera") == 0) {
        lua_getiuservalue(L, 1, 1);
        lua_rawgeti(L, -1, SC_CAMERA);
    } else if (strcmp(k, "background") == 0) {
        lf_push_color(L, st.background);
    } else if (strcmp(k, "ambient") == 0) {
        lf_push_color(L, st.ambient);
    } else if (strcmp(k, "max_depth") == 0) {
        lua_pushinteger(L, st.max_depth);
    } else {
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
    }
    return 1;
}

static int w_scene_newindex(lua_State *L)
{
    ud_scene *u = check_scene(L, 1);
    const char *k = luaL_checkstring(L, 2);
    lc_settings st = lc_scene_settings(u->s);
    char why[200];
    if (strcmp(k, "camera") == 0) {
        set_camera(L, u, 1, 3, 0, k);
        return 0;
    } else if (strcmp(k, "background") == 0 || strcmp(k, "ambient") == 0) {
        lc_color c;
        if (!lf_to_color(L, 3, &c, why, sizeof why))
            return luaL_error(L, "scene.%s: %s", k, why);
        *(k[0] == 'b' ? &st.background : &st.ambient) = c;
    } else if (strcmp(k, "max_depth") == 0) {
        int isint;
        lua_Integer d = lua_tointegerx(L, 3, &isint);
        /* Whether it converts to an int; the range is the core's to check. */
        if (lua_type(L, 3) != LUA_TNUMBER || !isint || d < INT_MIN || d > INT_MAX)
            return luaL_error(L, "scene.max_depth: integer in [0, %d] expected, got %s",
                              LC_MAX_DEPTH, luaL_tolstring(L, 3, NULL));
        st.max_depth = (int)d;
    } else {
        return luaL_error(L, "scene.%s: unknown field; settable fields are camera, "
                          "background, ambient, max_depth", k);
    }
    lc_error err;
    if (lc_scene_configure(u->s, &st, &err))
        return luaL_error(L, "scene.%s: %s", k, err.msg);
    return 0;
}


void scene_register(lua_State *L)
{
    static const luaL_Reg scene_meta[] = {
        {"__gc", w_scene_free}, {"__close", w_scene_free}, {"__tostring", w_scene_tostring},
        {"__index", w_scene_index}, {"__newindex", w_scene_newindex}, {NULL, NULL}};
    static const luaL_Reg scene_methods[] = {
        {"add", w_scene_add}, {"render", w_scene_render}, {"count", w_scene_count},
        {"transformed", w_scene_transformed}, {"explain", w_scene_explain},
        {NULL, NULL}};
    static const luaL_Reg raytree_meta[] = {
        {"__tostring", w_raytree_tostring}, {NULL, NULL}};
    binding_class(L, SCENE, scene_meta, scene_methods);
    binding_class(L, RAYTREE, raytree_meta, NULL);
    lua_pushcfunction(L, w_scene);
    lua_setfield(L, -2, "scene");
}
