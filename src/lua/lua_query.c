/* lua_query.c: rays cast from scripts: scene:intersect, scene:occluded. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

#define CHUNK 256     /* rays per call into the core */

static const char *const known[] = {"origin", "direction", "origins", "directions", "tmin",
                                    "tmax", NULL};

/* What one call casts: a single ray, or n from flat arrays. */
typedef struct {
    int     single;
    lc_ray  one;
    int     origins, directions;   /* stack indices of the flat arrays */
    size_t  n;
    double  tmin, tmax;
} request;

static size_t flat_count(lua_State *L, int idx, const char *field)
{
    if (lua_type(L, idx) != LUA_TTABLE)
        lf_error(L, 2, field, "flat table of numbers {x, y, z, x, y, z, ...} expected, "
                 "got %s", luaL_typename(L, idx));
    lua_Integer n = luaL_len(L, idx);
    if (n % 3 != 0)
        lf_error(L, 2, field, "flat list length must be a multiple of 3, got %lld",
                 (long long)n);
    return (size_t)(n / 3);
}

static void read_request(lua_State *L, request *q)
{
    lf_open(L, 2, known);
    memset(q, 0, sizeof *q);
    q->tmin = lf_number(L, 2, "tmin", 0, 0);
    q->tmax = lf_number(L, 2, "tmax", 0, HUGE_VAL);
    int one = lf_present(L, 2, "origin") || lf_present(L, 2, "direction");
    int many = lf_present(L, 2, "origins") || lf_present(L, 2, "directions");
    if (one == many)
        lf_error(L, 2, one ? "origins" : "origin", "give origin and direction (one ray) or "
                 "origins and directions (flat arrays), %s", one ? "not both" : "got neither");
    if (one) {
        lc_vec3 z = {0, 0, 0};
        q->single = 1;
        q->n = 1;
        q->one.origin = lf_vec3(L, 2, "origin", 1, z);
        q->one.direction = lf_vec3(L, 2, "direction", 1, z);
        q->one.tmin = q->tmin;
        q->one.tmax = q->tmax;
        return;
    }
    lua_getfield(L, 2, "origins");
    q->origins = lua_gettop(L);
    lua_getfield(L, 2, "directions");
    q->directions = lua_gettop(L);
    q->n = flat_count(L, q->origins, "origins");
    size_t nd = flat_count(L, q->directions, "directions");
    if (nd != q->n)
        lf_error(L, 2, "directions", "%zu directions for %zu origins", nd, q->n);
}

static double flat_number(lua_State *L, int list, size_t at, const char *field)
{
    if (lua_geti(L, list, (lua_Integer)at) != LUA_TNUMBER)
        lf_error(L, 2, field, "entry %zu: number expected, got %s", at, luaL_typename(L, -1));
    double x = lua_tonumber(L, -1);
    lua_pop(L, 1);
    return x;
}

/* Rays [base, base + n) of the request into r. */
static void read_rays(lua_State *L, const request *q, size_t base, size_t n, lc_ray *r)
{
    if (q->single) {
        r[0] = q->one;
        return;
    }
    for (size_t i = 0; i < n; i++) {
        double o[3], d[3];
        for (int k = 0; k < 3; k++) {
            o[k] = flat_number(L, q->origins, 3 * (base + i) + k + 1, "origins");
            d[k] = flat_number(L, q->directions, 3 * (base + i) + k + 1, "directions");
        }
        r[i] = (lc_ray){{o[0], o[1], o[2]}, {d[0], d[1], d[2]}, q->tmin, q->tmax};
    }
}

/* Raises the core's error, its "ray K" counted over the whole request. */
static int raise_at(lua_State *L, const request *q, size_t base, const lc_error *err)
{
    size_t k;
    int off = 0;
    if (err->code == LC_EARG && sscanf(err->msg, "ray %zu: %n", &k, &off) == 1 && off > 0)
        return q->single ? lf_error(L, 2, NULL, "ray: %s", err->msg + off)
                         : lf_error(L, 2, "rays", "ray %zu: %s", base + k, err->msg + off);
    return lf_raise(L, 2, err);
}

static void set_vec3(lua_State *L, int t, lua_Integer at, lc_vec3 v)
{
    lua_pushnumber(L, v.x);
    lua_rawseti(L, t, at);
    lua_pushnumber(L, v.y);
    lua_rawseti(L, t, at + 1);
    lua_pushnumber(L, v.z);
    lua_rawseti(L, t, at + 2);
}

static const char *kind_name(int kind)
{
    return kind == LC_SHAPE_KINDS ? "mesh" : lc_shape_kind_name((lc_shape_kind)kind);
}

/* The hit of a single ray as a table. */
static void push_hit(lua_State *L, const lc_ray_hit *h)
{
    lua_createtable(L, 0, 9);
    lua_pushnumber(L, h->t);
    lua_setfield(L, -2, "t");
    lf_push_vec3(L, h->point);
    lua_setfield(L, -2, "point");
    lf_push_vec3(L, h->normal);
    lua_setfield(L, -2, "normal");
    lf_push_vec3(L, h->shading_normal);
    lua_setfield(L, -2, "shading_normal");
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, h->uv[0]);
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, h->uv[1]);
    lua_rawseti(L, -2, 2);
    lua_setfield(L, -2, "uv");
    lua_pushinteger(L, (lua_Integer)h->object + 1);     /* as scene:objects() counts */
    lua_setfield(L, -2, "id");
    lua_pushstring(L, kind_name(h->shape_kind));
    lua_setfield(L, -2, "kind");
    if (h->shape_kind == LC_SHAPE_KINDS) {
        lua_pushinteger(L, (lua_Integer)h->primitive + 1);
        lua_setfield(L, -2, "face");
    }
}

enum { R_HIT = 1, R_T, R_POINTS, R_NORMALS, R_UVS, R_IDS, R_FACES, R_FIELDS };
static const char *const result_names[R_FIELDS] = {
    NULL, "hit", "t", "points", "normals", "uvs", "ids", "faces"};

/* scene:intersect{origin, direction | origins, directions [, tmin, tmax]} */
static int w_scene_intersect(lua_State *L)
{
    lb_scene_check(L, 1);
    request q;
    read_request(L, &q);
    int res = 0;
    if (!q.single) {
        lua_createtable(L, 0, R_FIELDS);
        res = lua_gettop(L);
        for (int f = R_HIT; f < R_FIELDS; f++) {
            int per = f == R_POINTS || f == R_NORMALS ? 3 : f == R_UVS ? 2 : 1;
            lua_createtable(L, (int)(per * q.n > 1u << 26 ? 1u << 26 : per * q.n), 0);
            lua_setfield(L, res, result_names[f]);
        }
        lua_pushinteger(L, (lua_Integer)q.n);
        lua_setfield(L, res, "count");
    }
    int top = lua_gettop(L);
    lc_ray rays[CHUNK];
    lc_ray_hit hits[CHUNK];
    for (size_t base = 0; base < q.n; base += CHUNK) {
        size_t n = q.n - base < CHUNK ? q.n - base : CHUNK;
        read_rays(L, &q, base, n, rays);
        lc_error err;
        if (lc_scene_intersect(lb_scene_at(L, 1), rays, n, hits, &err))
            return raise_at(L, &q, base, &err);
        if (q.single) {
            if (hits[0].hit)
                push_hit(L, &hits[0]);
            else
                lua_pushnil(L);
            lb_charge(L);               /* the first cast may build the BVH */
            return 1;
        }
        int t[R_FIELDS];
        for (int f = R_HIT; f < R_FIELDS; f++) {
            lua_getfield(L, res, result_names[f]);
            t[f] = lua_gettop(L);
        }
        for (size_t i = 0; i < n; i++) {
            const lc_ray_hit *h = &hits[i];
            lua_Integer k = (lua_Integer)(base + i);
            lc_vec3 zero = {0, 0, 0};
            lua_pushboolean(L, h->hit);
            lua_rawseti(L, t[R_HIT], k + 1);
            lua_pushnumber(L, h->hit ? h->t : HUGE_VAL);
            lua_rawseti(L, t[R_T], k + 1);
            set_vec3(L, t[R_POINTS], 3 * k + 1, h->hit ? h->point : zero);
            set_vec3(L, t[R_NORMALS], 3 * k + 1, h->hit ? h->normal : zero);
            lua_pushnumber(L, h->hit ? h->uv[0] : 0);
            lua_rawseti(L, t[R_UVS], 2 * k + 1);
            lua_pushnumber(L, h->hit ? h->uv[1] : 0);
            lua_rawseti(L, t[R_UVS], 2 * k + 2);
            lua_pushinteger(L, h->hit ? (lua_Integer)h->object + 1 : 0);
            lua_rawseti(L, t[R_IDS], k + 1);
            int face = h->hit && h->shape_kind == LC_SHAPE_KINDS;
            lua_pushinteger(L, face ? (lua_Integer)h->primitive + 1 : 0);
            lua_rawseti(L, t[R_FACES], k + 1);
        }
        lua_settop(L, top);
    }
    lua_pushvalue(L, res);              /* (one ray returned above) */
    lb_charge(L);
    return 1;
}

/* scene:occluded{...}: true when anything lies on the ray, or an array of
** booleans for flat arrays. */
static int w_scene_occluded(lua_State *L)
{
    lb_scene_check(L, 1);
    request q;
    read_request(L, &q);
    int res = 0;
    if (!q.single) {
        lua_createtable(L, (int)(q.n > 1u << 26 ? 1u << 26 : q.n), 0);
        res = lua_gettop(L);
    }
    lc_ray rays[CHUNK];
    unsigned char blocked[CHUNK];
    for (size_t base = 0; base < q.n; base += CHUNK) {
        size_t n = q.n - base < CHUNK ? q.n - base : CHUNK;
        read_rays(L, &q, base, n, rays);
        lc_error err;
        if (lc_scene_occluded(lb_scene_at(L, 1), rays, n, blocked, &err))
            return raise_at(L, &q, base, &err);
        if (q.single) {
            lua_pushboolean(L, blocked[0]);
            lb_charge(L);
            return 1;
        }
        for (size_t i = 0; i < n; i++) {
            lua_pushboolean(L, blocked[i]);
            lua_rawseti(L, res, (lua_Integer)(base + i + 1));
        }
    }
    lua_pushvalue(L, res);
    lb_charge(L);
    return 1;
}

void lb_query_register(lua_State *L)
{
    static const luaL_Reg methods[] = {
        {"intersect", w_scene_intersect}, {"occluded", w_scene_occluded}, {NULL, NULL}};
    luaL_getmetatable(L, LB_SCENE);
    lua_getfield(L, -1, "methods");
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
}
