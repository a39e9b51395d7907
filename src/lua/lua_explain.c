/* lua_explain.c: scene:explain: one pixel's ray tree, as tables that print as a tree. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

static int w_records_free(lua_State *L)
{
    lc_ray_record **box = lua_touserdata(L, 1);
    free(*box);
    *box = NULL;
    return 0;
}

/* Sets field k of the table at top to the value at top, raw: a node is
** the binding's own table until it is returned. */
static void set_raw(lua_State *L, const char *k)
{
    lua_pushstring(L, k);
    lua_insert(L, -2);
    lua_rawset(L, -3);
}

/* Pushes record x as a table whose 'rays' is an empty table. */
static void push_node(lua_State *L, const lc_ray_record *x)
{
    lua_createtable(L, 0, 12);
    luaL_setmetatable(L, LB_RAYTREE);
    lua_pushstring(L, lc_ray_kind_name(x->kind));
    set_raw(L, "kind");
    lf_push_vec3(L, x->origin);
    set_raw(L, "origin");
    lf_push_vec3(L, x->direction);
    set_raw(L, "direction");
    lua_pushnumber(L, x->distance);
    set_raw(L, "distance");
    lf_push_color(L, x->contribution);
    set_raw(L, "contribution");
    if (x->kind == LC_RAY_SHADOW || x->kind == LC_RAY_LIGHT) {
        lua_pushboolean(L, x->hit);
        set_raw(L, "visible");
        if (x->light_kind == LC_LIGHT_SPOT)
            lua_pushfstring(L, "spot light %d", x->light + 1);
        else if (x->light_kind == LC_LIGHT_DIRECTIONAL)
            lua_pushfstring(L, "directional light %d", x->light + 1);
        else if (x->light_kind == LC_LIGHT_SKY)
            lua_pushliteral(L, "the sky");
        else if (x->light >= 0)
            lua_pushfstring(L, "point light %d", x->light + 1);
        else
            lua_pushfstring(L, "emissive %d", -x->light);
        set_raw(L, "light");
    } else if (x->hit) {
        lua_createtable(L, 0, 5);
        lua_pushnumber(L, x->distance);
        set_raw(L, "distance");
        lf_push_vec3(L, x->point);
        set_raw(L, "point");
        lf_push_vec3(L, x->normal);
        set_raw(L, "normal");
        if (x->csg >= 0)                 /* the leaf of a CSG object */
            lua_pushfstring(L, "%s (node %d of CSG object %d)",
                            x->shape_kind == LC_SHAPE_KINDS ? "mesh" :
                            lc_shape_kind_name((lc_shape_kind)x->shape_kind),
                            x->csg_node + 1, x->csg + 1);
        else
            lua_pushfstring(L, "%s %d", lc_shape_kind_name((lc_shape_kind)x->shape_kind),
                            (int)x->shape + 1);
        set_raw(L, "shape");
        lua_pushinteger(L, x->material + 1);
        set_raw(L, "material");
        set_raw(L, "hit");
    }
    lua_newtable(L);
    set_raw(L, "rays");
}

/* Pushes the tree of the n >= 1 records (each after its parent, the camera
** ray first), each record's children under 'rays' in the order traced.
** One pass and no recursion: a chain of a million bounces takes the same
** few stack slots as one ray. */
static void push_tree(lua_State *L, const lc_ray_record *recs, size_t n)
{
    lua_createtable(L, n < INT_MAX ? (int)n : INT_MAX, 0);   /* [i + 1]: node i */
    int all = lua_gettop(L);
    for (size_t i = 0; i < n; i++) {
        push_node(L, &recs[i]);
        lua_pushvalue(L, -1);
        lua_rawseti(L, all, (lua_Integer)i + 1);
        int p = recs[i].parent;
        if (i > 0 && p >= 0 && (size_t)p < i) {
            lua_rawgeti(L, all, (lua_Integer)p + 1);
            lua_pushliteral(L, "rays");
            lua_rawget(L, -2);
            lua_rotate(L, -3, -1);                  /* parent, rays, node */
            lua_rawseti(L, -2, (lua_Integer)lua_rawlen(L, -2) + 1);
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
    }
    lua_rawgeti(L, all, 1);
    lua_remove(L, all);
}


typedef struct {
    lc_render_options o;
    int x, y, sample;          /* 1-based, as given */
} explain_args;

/* Checks explain's arguments: the scene at 1, the options table at 2.
** Reading the options may run a script's metamethods: explain_work checks
** the scene again. */
static void explain_read(lua_State *L, explain_args *a, int plain)
{
    static const char *const known[] = {"x", "y", "sample", LB_RENDER_OPTIONS, NULL};
    lb_scene_check(L, 1);
    lua_settop(L, 2);
    lf_open(L, 2, known);
    lb_render_read_options(L, 2, &a->o);
    a->x = lf_integer(L, 2, "x", 1, 0);
    a->y = lf_integer(L, 2, "y", 1, 0);
    a->sample = lf_integer(L, 2, "sample", 0, 1);
    lc_error err;
    if (lc_render_options_check(&a->o, &err))
        lb_hook_raise(L, plain, 2, &err);
}

/* Explains a pixel of the scene at 1: pushes its tree. */
static int explain_work(lua_State *L, const explain_args *a, int plain)
{
    lb_scene_check(L, 1);
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
    /* Fetched after the allocations above, which may run finalizers. */
    if (lc_scene_explain(lb_scene_at(L, 1), &a->o, a->x - 1, a->y - 1, a->sample - 1,
                         box,
                         &n, &err))
        return lb_hook_raise(L, plain, 2, &err);
    push_tree(L, *box, n);
    return 1;
}

/* The hook's plain explain (lua_hook.c). */
static int explain_plain(lua_State *L)
{
    explain_args a;
    explain_read(L, &a, 1);
    return explain_work(L, &a, 1);
}

/* scene:explain{x = , y = , sample = 1, ...render options}: the ray tree of
** one sample of one pixel, as nested tables that print as a tree. */
static int w_scene_explain(lua_State *L)
{
    explain_args a;
    explain_read(L, &a, 0);
    int n = lb_hook_call(L, "explain", explain_plain, 2);
    return n >= 0 ? n : explain_work(L, &a, 0);
}

/* The printed tree stops this many levels below the ray printed, with a
** note counting the rays below: a chain of 1000 mirror bounces would print
** a megabyte of indentation, and a million ones could not be printed at
** all. The tables hold every ray; printing a deep one shows what follows. */
#define PRINT_LEVELS 100

/* t[k] of the table at t, raw: a printer runs no script code. */
static int get_raw(lua_State *L, int t, const char *k)
{
    lua_pushstring(L, k);
    return lua_rawget(L, t);
}

/* The string at idx, or "?" for any other value (a tree a script edited). */
static const char *text_at(lua_State *L, int idx)
{
    return lua_type(L, idx) == LUA_TSTRING ? lua_tostring(L, idx) : "?";
}

/* The number at idx, or NaN for any other value. */
static double number_at(lua_State *L, int idx)
{
    return lua_type(L, idx) == LUA_TNUMBER ? lua_tonumber(L, idx) : NAN;
}

/* Writes "adds (r, g, b)" for the node at t into out. */
static void format_adds(lua_State *L, int t, char *out, size_t size)
{
    double c[3] = {0, 0, 0};
    if (get_raw(L, t, "contribution") != LUA_TTABLE) {
        snprintf(out, size, "adds ?");
    } else {
        for (int i = 0; i < 3; i++) {
            lua_rawgeti(L, -1, i + 1);
            c[i] = number_at(L, -1);
            lua_pop(L, 1);
        }
        snprintf(out, size, "adds (%.4g, %.4g, %.4g)", c[0], c[1], c[2]);
    }
    lua_pop(L, 1);
}

/* Pushes the line for the node at t, at `depth` levels of indentation. */
static void push_line(lua_State *L, int t, int depth)
{
    char adds[100], line[2 * PRINT_LEVELS + 400];
    format_adds(L, t, adds, sizeof adds);
    int top = lua_gettop(L);
    get_raw(L, t, "kind");
    const char *kind = text_at(L, -1);
    if (get_raw(L, t, "light") == LUA_TSTRING) {
        get_raw(L, t, "visible");
        snprintf(line, sizeof line, "%*s%.60s to %.60s: %s, %s", 2 * depth, "", kind,
                 lua_tostring(L, -2), lua_toboolean(L, -1) ? "visible" : "blocked",
                 adds);
    } else if (get_raw(L, t, "hit") == LUA_TTABLE) {
        int hit = lua_gettop(L);
        get_raw(L, hit, "shape");
        get_raw(L, hit, "material");
        get_raw(L, hit, "distance");
        snprintf(line, sizeof line, "%*s%.60s hits %.60s (material %.0f) at %.6g, %s",
                 2 * depth, "", kind, text_at(L, -3), number_at(L, -2), number_at(L, -1),
                 adds);
    } else {
        snprintf(line, sizeof line, "%*s%.60s misses: background, %s", 2 * depth, "",
                 kind, adds);
    }
    lua_settop(L, top);
    lua_pushstring(L, line);
}

/* Pushes a node's children (the tables at rays[1], rays[2], ... up to the
** first non-table) onto the work list at todo, last first, at depth. */
static void push_children(lua_State *L, int t, int todo, lua_Integer depth)
{
    if (get_raw(L, t, "rays") == LUA_TTABLE) {
        lua_Integer n = 0;
        while (lua_rawgeti(L, -1, n + 1) == LUA_TTABLE) {
            lua_pop(L, 1);
            n++;
        }
        lua_pop(L, 1);
        lua_Integer top = (lua_Integer)lua_rawlen(L, todo);
        for (lua_Integer i = n; i >= 1; i--) {
            lua_rawgeti(L, -1, i);
            lua_rawseti(L, todo, ++top);
            lua_pushinteger(L, depth);
            lua_rawseti(L, todo, ++top);
        }
    }
    lua_pop(L, 1);
}

/* Pops the last (node, depth) of the work list at todo: the node on the
** stack, the depth returned; -1 (and nothing pushed) when it is empty. */
static lua_Integer pop_work(lua_State *L, int todo)
{
    lua_Integer top = (lua_Integer)lua_rawlen(L, todo);
    if (top < 2)
        return -1;
    lua_rawgeti(L, todo, top);
    lua_Integer depth = lua_tointeger(L, -1);
    lua_pop(L, 1);
    lua_rawgeti(L, todo, top - 1);
    lua_pushnil(L);
    lua_rawseti(L, todo, top);
    lua_pushnil(L);
    lua_rawseti(L, todo, top - 1);
    return depth;
}

/* Marks the node at t seen in the set at `seen`; whether it was already. */
static int seen_before(lua_State *L, int seen, int t)
{
    lua_pushvalue(L, t);
    int was = lua_rawget(L, seen) != LUA_TNIL;
    lua_pop(L, 1);
    lua_pushvalue(L, t);
    lua_pushboolean(L, 1);
    lua_rawset(L, seen);
    return was;
}

/* How many rays lie below the node at t, each counted once. */
static lua_Integer count_below(lua_State *L, int t)
{
    lua_newtable(L);
    int seen = lua_gettop(L);
    lua_newtable(L);
    int todo = lua_gettop(L);
    push_children(L, t, todo, 0);
    lua_Integer n = 0;
    while (pop_work(L, todo) >= 0) {
        int node = lua_gettop(L);
        if (!seen_before(L, seen, node)) {
            n++;
            push_children(L, node, todo, 0);
        }
        lua_pop(L, 1);
    }
    lua_pop(L, 2);
    return n;
}

/* tostring(tree): one line per ray, children indented under their parent.
** Iterative, its work list in a table; the lines are gathered in another
** before the buffer opens, as nothing may be pushed while it is. */
static int w_raytree_tostring(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_settop(L, 1);
    lua_newtable(L);                                /* 2: the lines */
    lua_newtable(L);                                /* 3: the nodes printed */
    lua_newtable(L);                                /* 4: work: node, depth, ... */
    lua_pushvalue(L, 1);
    lua_rawseti(L, 4, 1);
    lua_pushinteger(L, 0);
    lua_rawseti(L, 4, 2);
    lua_Integer nlines = 0, depth;
    char note[2 * PRINT_LEVELS + 160];
    while ((depth = pop_work(L, 4)) >= 0) {
        int node = lua_gettop(L);
        if (seen_before(L, 3, node)) {          /* only in a tree a script edited */
            snprintf(note, sizeof note, "%*s(a ray printed above)", (int)(2 * depth),
                     "");
            lua_pushstring(L, note);
            lua_rawseti(L, 2, ++nlines);
        } else {
            push_line(L, node, (int)depth);
            lua_rawseti(L, 2, ++nlines);
            if (depth + 1 < PRINT_LEVELS) {
                push_children(L, node, 4, depth + 1);
            } else {
                lua_Integer below = count_below(L, node);
                int indent = (int)(2 * (depth + 1));
                snprintf(note, sizeof note, "%*s... %lld more ray%s below: the print "
                         "stops at %d levels (print a deeper ray to see them)", indent,
                         "", (long long)below, below == 1 ? "" : "s", PRINT_LEVELS);
                if (below > 0) {
                    lua_pushstring(L, note);
                    lua_rawseti(L, 2, ++nlines);
                }
            }
        }
        lua_settop(L, node - 1);
    }
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    for (lua_Integer i = 1; i <= nlines; i++) {
        lua_rawgeti(L, 2, i);
        luaL_addvalue(&b);
        luaL_addchar(&b, '\n');
    }
    luaL_pushresult(&b);
    return 1;
}

void lb_explain_register(lua_State *L)
{
    static const luaL_Reg methods[] = {{"explain", w_scene_explain}, {NULL, NULL}};
    static const luaL_Reg raytree_meta[] = {
        {"__tostring", w_raytree_tostring}, {NULL, NULL}};
    luaL_getmetatable(L, LB_SCENE);
    lua_getfield(L, -1, "methods");
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
    lb_class(L, LB_RAYTREE, raytree_meta, NULL);
}
