/* lua_motion.c: transforms (lancer.translate, rotate, scale), groups, obj:moved(T). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* Raises the core's complaint about a transform at argument arg. Its
** sentences name the transform already ("transform is singular ..."). */
static int raise_transform(lua_State *L, int arg, const lc_error *err)
{
    if (err->code != LC_EARG)
        return luaL_error(L, "%s", err->msg);
    return luaL_argerror(L, arg, err->msg);
}

/* Pushes a new transform userdata holding t, checked: every lancer.Transform
** is finite and invertible. */
static int push_transform(lua_State *L, const lc_transform *t, int arg)
{
    lc_error err;
    if (lc_transform_check(t, &err))
        return raise_transform(L, arg, &err);
    lb_ud_transform *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->t = *t;
    luaL_setmetatable(L, LB_TRANSFORM);
    return 1;
}

static const lc_transform *check_transform(lua_State *L, int idx)
{
    return &((lb_ud_transform *)luaL_checkudata(L, idx, LB_TRANSFORM))->t;
}

static double finite_arg(lua_State *L, int arg)
{
    double x = luaL_checknumber(L, arg);
    if (!isfinite(x))
        luaL_argerror(L, arg, lua_pushfstring(L, "must be finite, got %f", x));
    return x;
}

/* (x, y, z) as three numbers or one {x, y, z}; `one` allows a single number
** for all three (scale). */
static lc_vec3 vec_args(lua_State *L, int one)
{
    if (lua_type(L, 1) == LUA_TTABLE) {
        lc_vec3 v;
        char why[160];
        if (!lf_to_vec3(L, 1, &v, why, sizeof why))
            luaL_argerror(L, 1, why);
        return v;
    }
    double x = finite_arg(L, 1);
    if (one && lua_isnoneornil(L, 2))
        return (lc_vec3){x, x, x};
    return (lc_vec3){x, finite_arg(L, 2), finite_arg(L, 3)};
}

static int w_translate(lua_State *L)
{
    lc_transform t = lc_transform_translate(vec_args(L, 0));
    return push_transform(L, &t, 1);
}

static int w_scale(lua_State *L)
{
    lc_transform t = lc_transform_scale(vec_args(L, 1));
    return push_transform(L, &t, 1);
}

/* rotate(axis, degrees): axis 'x', 'y', 'z' or a vector {x, y, z}. */
static int w_rotate(lua_State *L)
{
    lc_vec3 axis;
    if (lua_type(L, 1) == LUA_TSTRING) {
        const char *a = lua_tostring(L, 1);
        if (strcmp(a, "x") && strcmp(a, "y") && strcmp(a, "z"))
            return luaL_argerror(L, 1, lua_pushfstring(L, "axis 'x', 'y', 'z' or {x, y, z} "
                                                       "expected, got '%s'", a));
        axis = (lc_vec3){a[0] == 'x', a[0] == 'y', a[0] == 'z'};
    } else {
        char why[160];
        if (!lf_to_vec3(L, 1, &axis, why, sizeof why))
            return luaL_argerror(L, 1, why);
    }
    double deg = finite_arg(L, 2);
    lc_transform t;
    lc_error err;
    if (lc_transform_rotate(axis, deg, &t, &err))
        return luaL_argerror(L, strcmp(err.field, "axis") == 0 ? 1 : 2, err.msg);
    return push_transform(L, &t, 1);
}

/* transform() is the identity; transform{{a, b, c, d}, {e, ...}, {i, ...}}
** takes the rows of [M | t]. */
static int w_transform(lua_State *L)
{
    lc_transform t = lc_transform_identity();
    if (lua_isnoneornil(L, 1))
        return push_transform(L, &t, 1);
    luaL_checktype(L, 1, LUA_TTABLE);
    if (luaL_len(L, 1) != 3)
        return luaL_argerror(L, 1, "3 rows of 4 numbers expected (M | t)");
    for (int i = 0; i < 3; i++) {
        if (lua_geti(L, 1, i + 1) != LUA_TTABLE || luaL_len(L, -1) != 4)
            return luaL_argerror(L, 1, lua_pushfstring(L, "row %d: 4 numbers expected",
                                                       i + 1));
        for (int j = 0; j < 4; j++) {
            if (lua_geti(L, -1, j + 1) != LUA_TNUMBER)
                return luaL_argerror(L, 1, lua_pushfstring(L, "row %d, entry %d: number "
                                                           "expected, got %s", i + 1, j + 1,
                                                           luaL_typename(L, -1)));
            t.m[i][j] = lua_tonumber(L, -1);
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
    }
    return push_transform(L, &t, 1);
}

/* a * b: b first, then a (as matrices compose). */
static int w_transform_mul(lua_State *L)
{
    const lc_transform *a = check_transform(L, 1), *b = check_transform(L, 2);
    lc_transform t = lc_transform_compose(a, b);
    lc_error err;
    if (lc_transform_check(&t, &err))       /* a product of extremes may underflow */
        return luaL_error(L, "%s", err.msg);
    return push_transform(L, &t, 1);
}

static int w_transform_eq(lua_State *L)
{
    const lc_transform *a = check_transform(L, 1), *b = check_transform(L, 2);
    int eq = 1;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            eq = eq && a->m[i][j] == b->m[i][j];
    lua_pushboolean(L, eq);
    return 1;
}

static int w_transform_apply(lua_State *L)
{
    const lc_transform *t = check_transform(L, 1);
    lc_vec3 p;
    char why[160];
    if (!lf_to_vec3(L, 2, &p, why, sizeof why))
        return luaL_argerror(L, 2, why);
    lf_push_vec3(L, lc_transform_point(t, p));
    return 1;
}

static int w_transform_apply_vector(lua_State *L)
{
    const lc_transform *t = check_transform(L, 1);
    lc_vec3 v;
    char why[160];
    if (!lf_to_vec3(L, 2, &v, why, sizeof why))
        return luaL_argerror(L, 2, why);
    lf_push_vec3(L, lc_transform_vector(t, v));
    return 1;
}

static int w_transform_inverse(lua_State *L)
{
    lc_transform inv;
    lc_error err;
    if (lc_transform_inverse(check_transform(L, 1), &inv, &err))
        return luaL_error(L, "%s", err.msg);
    return push_transform(L, &inv, 1);
}

static int w_transform_rows(lua_State *L)
{
    const lc_transform *t = check_transform(L, 1);
    lua_createtable(L, 3, 0);
    for (int i = 0; i < 3; i++) {
        lua_createtable(L, 4, 0);
        for (int j = 0; j < 4; j++) {
            lua_pushnumber(L, t->m[i][j]);
            lua_rawseti(L, -2, j + 1);
        }
        lua_rawseti(L, -2, i + 1);
    }
    return 1;
}

static int w_transform_is_identity(lua_State *L)
{
    lua_pushboolean(L, lc_transform_is_identity(check_transform(L, 1)));
    return 1;
}

/* Prints as the call that builds it back: lancer.transform{{...}, ...}. */
static int w_transform_tostring(lua_State *L)
{
    const lc_transform *t = check_transform(L, 1);
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.transform{");
    for (int i = 0; i < 3; i++) {
        luaL_addstring(&b, i ? ", {" : "{");
        for (int j = 0; j < 4; j++) {
            char tmp[40];
            snprintf(tmp, sizeof tmp, "%s%.17g", j ? ", " : "", t->m[i][j]);
            luaL_addstring(&b, tmp);
        }
        luaL_addstring(&b, "}");
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    return 1;
}

/* ---- groups ------------------------------------------------------------------ */

static const char *type_name(lua_State *L, int idx)
{
    const char *got = luaL_typename(L, idx);
    if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING) {
        got = lua_tostring(L, -1);
        lua_pop(L, 1);
    }
    return got;
}

void lb_motion_push_group(lua_State *L, const lc_transform *t, int members)
{
    members = lua_absindex(L, members);
    lb_ud_group *g = lua_newuserdatauv(L, sizeof *g, 1);
    g->t = *t;
    lua_pushvalue(L, members);
    lua_setiuservalue(L, -2, 1);
    luaL_setmetatable(L, LB_GROUP);
}

/* lancer.group{a, b, ...}: shapes, meshes, lights, groups and CSG objects that move
** together. The list is copied: changing the table later changes nothing. */
static int w_group(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_Integer n = luaL_len(L, 1);
    lua_createtable(L, (int)n, 0);
    for (lua_Integer i = 1; i <= n; i++) {
        lua_geti(L, 1, i);
        if (!luaL_testudata(L, -1, LB_SHAPE) && !luaL_testudata(L, -1, LB_MESH) &&
            !luaL_testudata(L, -1, LB_LIGHT) && !luaL_testudata(L, -1, LB_GROUP) &&
            !luaL_testudata(L, -1, LB_CSG))
            return luaL_argerror(L, 1, lua_pushfstring(L, "element %I: shape, mesh, "
                                                       "light, group or CSG object "
                                                       "expected, got %s", i,
                                                       type_name(L, -1)));
        lua_rawseti(L, -2, i);
    }
    lua_pushnil(L);                  /* only the array part: no stray fields */
    if (lua_next(L, 1)) {
        lua_pop(L, 1);
        if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n)
            return luaL_argerror(L, 1, lua_pushfstring(L, "a list of members expected, "
                                                       "got key '%s'",
                                                       luaL_tolstring(L, -1, NULL)));
        lua_pop(L, 1);
    }
    lc_transform id = lc_transform_identity();
    lb_motion_push_group(L, &id, -1);
    return 1;
}

static int w_group_index(lua_State *L)
{
    lb_ud_group *g = luaL_checkudata(L, 1, LB_GROUP);
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "kind") == 0) {
        lua_pushliteral(L, "group");
    } else if (strcmp(k, "transform") == 0) {
        push_transform(L, &g->t, 1);
    } else if (strcmp(k, "members") == 0) {     /* a copy: the group is a value */
        lua_getiuservalue(L, 1, 1);
        lua_Integer n = luaL_len(L, -1);
        lua_createtable(L, (int)n, 0);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_geti(L, -2, i);
            lua_rawseti(L, -2, i);
        }
    } else if (strcmp(k, "moved") == 0) {
        lua_pushcfunction(L, lb_motion_moved);
    } else {
        lua_pushnil(L);
    }
    return 1;
}

static int w_group_len(lua_State *L)
{
    luaL_checkudata(L, 1, LB_GROUP);
    lua_getiuservalue(L, 1, 1);
    lua_pushinteger(L, luaL_len(L, -1));
    return 1;
}

static int w_group_tostring(lua_State *L)
{
    lb_ud_group *g = luaL_checkudata(L, 1, LB_GROUP);
    lua_getiuservalue(L, 1, 1);
    lua_Integer n = luaL_len(L, -1);
    lua_pushfstring(L, "lancer.Group (%I member%s%s)", n, n == 1 ? "" : "s",
                    lc_transform_is_identity(&g->t) ? "" : ", moved");
    return 1;
}

/* obj:moved(T): a new object, T applied after whatever moved it before.
** Shapes and lights are values, moved now (exactly: lc_shape_transform);
** a mesh is shared data, so it becomes a group of one, placed by T; a CSG
** object keeps T, and its leaves take it when added. */
int lb_motion_moved(lua_State *L)
{
    const lc_transform *t = check_transform(L, 2);
    lc_error err;
    lb_ud_shape *sh = luaL_testudata(L, 1, LB_SHAPE);
    if (sh) {
        lc_shape out;
        if (lc_shape_transform(&sh->s, t, &out, &err))
            return raise_transform(L, 2, &err);
        lua_getiuservalue(L, 1, 1);
        lb_shape_push(L, &out, -1);
        return 1;
    }
    lb_ud_light *li = luaL_testudata(L, 1, LB_LIGHT);
    if (li) {
        lb_ud_light l;
        if (!lb_light_moved(li, t, &l, &err))
            return luaL_argerror(L, 2, err.msg);
        lb_light_push(L, &l);
        return 1;
    }
    if (luaL_testudata(L, 1, LB_MESH)) {
        lua_createtable(L, 1, 0);
        lua_pushvalue(L, 1);
        lua_rawseti(L, -2, 1);
        lb_motion_push_group(L, t, -1);
        return 1;
    }
    if (luaL_testudata(L, 1, LB_CSG))
        return lb_csg_moved(L, 1, t);
    lb_ud_group *g = luaL_testudata(L, 1, LB_GROUP);
    if (g) {
        lc_transform c = lc_transform_compose(t, &g->t);
        if (lc_transform_check(&c, &err))
            return raise_transform(L, 2, &err);
        lua_getiuservalue(L, 1, 1);
        lb_motion_push_group(L, &c, -1);
        return 1;
    }
    return luaL_argerror(L, 1, lua_pushfstring(L, "shape, mesh, light, group or CSG "
                                               "object expected, got %s",
                                               type_name(L, 1)));
}

void lb_motion_register(lua_State *L)
{
    static const luaL_Reg transform_meta[] = {
        {"__mul", w_transform_mul}, {"__eq", w_transform_eq},
        {"__tostring", w_transform_tostring}, {NULL, NULL}};
    static const luaL_Reg transform_methods[] = {
        {"apply", w_transform_apply}, {"apply_vector", w_transform_apply_vector},
        {"inverse", w_transform_inverse}, {"rows", w_transform_rows},
        {"is_identity", w_transform_is_identity}, {NULL, NULL}};
    static const luaL_Reg group_meta[] = {
        {"__index", w_group_index}, {"__len", w_group_len},
        {"__tostring", w_group_tostring}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"translate", w_translate}, {"rotate", w_rotate}, {"scale", w_scale},
        {"transform", w_transform}, {"group", w_group}, {NULL, NULL}};
    lb_class(L, LB_TRANSFORM, transform_meta, transform_methods);
    luaL_getmetatable(L, LB_TRANSFORM);           /* methods straight from __index */
    lua_getfield(L, -1, "methods");
    lua_setfield(L, -2, "__index");
    lua_pop(L, 1);
    lb_class(L, LB_GROUP, group_meta, NULL);
    luaL_setfuncs(L, funcs, 0);
}
