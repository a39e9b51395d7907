/* lua_explain.c: scene:explain: one pixel's ray tree, as tables that print as a tree. */
#include <stdio.h>
#include <stdlib.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_types.h"

static int w_records_free(lua_State *L)
{
    lc_ray_record **box = lua_touserdata(L, 1);
    free(*box);
    *box = NULL;
    return 0;
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

typedef struct {
    lc_render_options o;
    int x, y, sample;          /* 1-based, as given */
} explain_args;

/* Checks explain's arguments: the scene at 1, the options table at 2. */
static ud_scene *explain_read(lua_State *L, explain_args *a, int plain)
{
    static const char *const known[] = {"x", "y", "sample", RENDER_OPTIONS, NULL};
    ud_scene *u = scene_check(L, 1);
    lua_settop(L, 2);
    lf_open(L, 2, known);
    render_read_options(L, 2, &a->o);
    a->x = lf_integer(L, 2, "x", 1, 0);
    a->y = lf_integer(L, 2, "y", 1, 0);
    a->sample = lf_integer(L, 2, "sample", 0, 1);
    lc_error err;
    if (lc_render_options_check(&a->o, &err))
        hook_raise(L, plain, 2, &err);
    return u;
}

static int explain_work(lua_State *L, ud_scene *u, const explain_args *a, int plain)
{
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
    if (lc_scene_explain(u->s, &a->o, a->x - 1, a->y - 1, a->sample - 1, box, &n, &err))
        return hook_raise(L, plain, 2, &err);
    push_record(L, *box, n, 0);
    return 1;
}

/* The hook's plain explain (lua_hook.c). */
static int explain_plain(lua_State *L)
{
    explain_args a;
    ud_scene *u = explain_read(L, &a, 1);
    return explain_work(L, u, &a, 1);
}

/* scene:explain{x = , y = , sample = 1, ...render options}: the ray tree of
** one sample of one pixel, as nested tables that print as a tree. */
static int w_scene_explain(lua_State *L)
{
    explain_args a;
    ud_scene *u = explain_read(L, &a, 0);
    int n = hook_call(L, "explain", explain_plain, 2);
    return n >= 0 ? n : explain_work(L, u, &a, 0);
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

void explain_register(lua_State *L)
{
    static const luaL_Reg methods[] = {{"explain", w_scene_explain}, {NULL, NULL}};
    static const luaL_Reg raytree_meta[] = {
        {"__tostring", w_raytree_tostring}, {NULL, NULL}};
    luaL_getmetatable(L, SCENE);
    lua_getfield(L, -1, "methods");
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
    lancer_class(L, RAYTREE, raytree_meta, NULL);
}
