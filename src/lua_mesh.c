/* lua_mesh.c: triangle meshes: lancer.mesh, lancer.triangle, lancer.load_obj. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_types.h"

/* ---- meshes --------------------------------------------------------------- */

#define CHUNK 1024    /* items converted per call into the core */

/* The core mesh of the userdata at idx, raising when freed: fetched right
** before the lc_ call that uses it (see scene_at in lua_types.h). */
static lc_mesh *check_mesh(lua_State *L, int idx)
{
    ud_mesh *u = luaL_checkudata(L, idx, MESH);
    if (!u->m)
        luaL_error(L, "lancer.Mesh already freed");
    return u->m;
}

/* How many items the list at index `list` holds: a nested list {{...}, ...}
** counts its entries, a flat one {a, b, c, ...} its entries over dim
** (*flat says which). `what` names the items in the error for a non-table. */
static lua_Integer list_count(lua_State *L, int arg, int list, const char *field,
                              const char *what, int dim, int *flat)
{
    if (lua_type(L, list) != LUA_TTABLE)
        lf_error(L, arg, field, "table of %s expected, got %s", what,
                 luaL_typename(L, list));
    lua_Integer n = luaL_len(L, list);
    *flat = n > 0 && lua_geti(L, list, 1) == LUA_TNUMBER;
    if (n > 0)
        lua_pop(L, 1);
    if (*flat && n % dim != 0)
        lf_error(L, arg, field, "flat list length must be a multiple of %d, got %lld", dim,
                 (long long)n);
    return *flat ? n / dim : n;
}

enum { POINTS, NORMALS, UVS };                /* what read_points reads */

/* One nested uv pair {u, v} at idx into uv; 0 with why on failure. */
static int to_uv(lua_State *L, int idx, double uv[2], char *why, size_t whylen)
{
    if (lua_type(L, idx) != LUA_TTABLE) {
        snprintf(why, whylen, "{u, v} expected, got %s", luaL_typename(L, idx));
        return 0;
    }
    for (int k = 0; k < 2; k++) {
        int t = lua_geti(L, idx, k + 1);
        uv[k] = lua_tonumber(L, -1);
        lua_pop(L, 1);
        if (t != LUA_TNUMBER || !isfinite(uv[k])) {
            snprintf(why, whylen, "{u, v} of 2 finite numbers expected");
            return 0;
        }
    }
    return 1;
}

/* Reads a list of points, normals or uvs (what) into the mesh at stack
** index mi: nested {{x, y, z}, ...} or flat {x, y, z, x, y, z, ...} (the
** fast path for large arrays; uvs come in 2s). `field` names it in
** errors; arg is the argument holding the list's table, or the list. The
** list's reads may run a script's metamethods: the mesh is fetched again
** for each chunk. */
static void read_points(lua_State *L, int arg, int list, int mi, int what,
                        const char *field)
{
    double buf[3 * CHUNK];
    int dim = what == UVS ? 2 : 3;
    size_t nb = 0;
    lc_error err;
    int flat;
    list = lua_absindex(L, list);
    mi = lua_absindex(L, mi);
    lua_Integer count = list_count(L, arg, list, field, what == UVS ? "uvs" : "points", dim,
                                   &flat);
    for (lua_Integer i = 1; i <= count; i++) {
        if (flat) {
            for (int k = 0; k < dim; k++) {
                lua_Integer at = dim * (i - 1) + k + 1;
                if (lua_geti(L, list, at) != LUA_TNUMBER)
                    lf_error(L, arg, field, "entry %lld: number expected, got %s",
                             (long long)at, luaL_typename(L, -1));
                double x = lua_tonumber(L, -1);
                lua_pop(L, 1);
                if (!isfinite(x))
                    lf_error(L, arg, field, "entry %lld: must be finite, got %g",
                             (long long)at, x);
                buf[dim * nb + k] = x;
            }
        } else {
            char why[160];
            lc_vec3 v;
            lua_geti(L, list, i);
            if (what == UVS ? !to_uv(L, -1, buf + 2 * nb, why, sizeof why)
                            : !lf_to_vec3(L, -1, &v, why, sizeof why))
                lf_error(L, arg, field, "%s %lld: %s", what == UVS ? "uv" : "point",
                         (long long)i, why);
            lua_pop(L, 1);
            if (what != UVS) {
                buf[3 * nb] = v.x;
                buf[3 * nb + 1] = v.y;
                buf[3 * nb + 2] = v.z;
            }
        }
        if (++nb == CHUNK || i == count) {
            lc_mesh *m = check_mesh(L, mi);
            lc_status st = what == NORMALS ? lc_mesh_add_normals(m, buf, nb, &err)
                         : what == UVS     ? lc_mesh_add_uvs(m, buf, nb, &err)
                                           : lc_mesh_add_vertices(m, buf, nb, &err);
            if (st)
                lf_error(L, arg, field, "%s", err.msg);
            nb = 0;
        }
    }
}

static uint32_t face_index(lua_State *L, int arg, const char *field, lua_Integer face,
                           size_t nv)
{
    int isint;
    lua_Integer k = lua_tointegerx(L, -1, &isint);
    if (!isint)
        lf_error(L, arg, field, "face %lld: integer vertex index expected, got %s",
                 (long long)face, luaL_tolstring(L, -1, NULL));
    if (k < 1 || (size_t)k > nv)
        lf_error(L, arg, field, "face %lld: vertex index %lld out of range [1, %zu]",
                 (long long)face, (long long)k, nv);
    lua_pop(L, 1);
    return (uint32_t)(k - 1);
}

/* Faces into the mesh at stack index mi: nested {{a, b, c}, {a, b, c, d},
** ...} (polygons become fans) or flat {a, b, c, a, b, c, ...}; indices
** start at 1, as Lua's do. The mesh is fetched for each chunk, as in
** read_points. */
static void read_faces(lua_State *L, int arg, int list, int mi, const char *field)
{
    uint32_t buf[3 * CHUNK];
    size_t nb = 0;
    lc_error err;
    int flat;
    list = lua_absindex(L, list);
    mi = lua_absindex(L, mi);
    lua_Integer count = list_count(L, arg, list, field, "faces", 3, &flat);
    size_t nv = lc_mesh_vertex_count(check_mesh(L, mi));
    for (lua_Integer i = 1; i <= count; i++) {
        if (flat) {
            for (int k = 0; k < 3; k++) {
                lua_geti(L, list, 3 * (i - 1) + k + 1);
                buf[3 * nb + k] = face_index(L, arg, field, i, nv);
            }
            nb++;
        } else {
            if (lua_geti(L, list, i) != LUA_TTABLE)
                lf_error(L, arg, field, "face %lld: table of vertex indices expected, got %s",
                         (long long)i, luaL_typename(L, -1));
            int f = lua_gettop(L);
            lua_Integer corners = luaL_len(L, f);
            if (corners < 3)
                lf_error(L, arg, field, "face %lld: at least 3 vertices expected, got %lld",
                         (long long)i, (long long)corners);
            lua_geti(L, f, 1);
            uint32_t first = face_index(L, arg, field, i, nv);
            lua_geti(L, f, 2);
            uint32_t prev = face_index(L, arg, field, i, nv);
            for (lua_Integer c = 3; c <= corners; c++) {
                lua_geti(L, f, c);
                uint32_t cur = face_index(L, arg, field, i, nv);
                buf[3 * nb] = first;
                buf[3 * nb + 1] = prev;
                buf[3 * nb + 2] = cur;
                prev = cur;
                if (++nb == CHUNK) {
                    if (lc_mesh_add_faces(check_mesh(L, mi), buf, nb, &err))
                        lf_error(L, arg, field, "%s", err.msg);
                    nb = 0;
                }
            }
            lua_pop(L, 1);
            continue;
        }
        if (nb == CHUNK) {
            if (lc_mesh_add_faces(check_mesh(L, mi), buf, nb, &err))
                lf_error(L, arg, field, "%s", err.msg);
            nb = 0;
        }
    }
    if (nb && lc_mesh_add_faces(check_mesh(L, mi), buf, nb, &err))
        lf_error(L, arg, field, "%s", err.msg);
}

/* Pushes an empty mesh userdata (before the core mesh, so nothing leaks if
** allocation fails) with the material at stack index mat (or nil). */
static lc_mesh *push_mesh(lua_State *L, int mat)
{
    mat = lua_absindex(L, mat);
    ud_mesh *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->m = NULL;
    luaL_setmetatable(L, MESH);
    lua_pushvalue(L, mat);
    lua_setiuservalue(L, -2, 1);
    lc_error err;
    u->m = lc_mesh_new(&err);
    if (!u->m)
        luaL_error(L, "%s", err.msg);
    return u->m;
}

static int w_mesh(lua_State *L)
{
    static const char *const known[] = {"vertices", "faces", "normals", "uvs", "material",
                                        NULL};
    if (lua_isnoneornil(L, 1)) {
        lua_settop(L, 0);
        lua_newtable(L);
    }
    lf_open(L, 1, known);
    lf_udata(L, 1, "material", MATERIAL, 0);
    int mat = lua_gettop(L);
    push_mesh(L, mat);
    int top = lua_gettop(L);
    if (lua_getfield(L, 1, "vertices") != LUA_TNIL)
        read_points(L, 1, -1, top, POINTS, "vertices");
    lua_settop(L, top);
    if (lua_getfield(L, 1, "normals") != LUA_TNIL)
        read_points(L, 1, -1, top, NORMALS, "normals");
    lua_settop(L, top);
    if (lua_getfield(L, 1, "uvs") != LUA_TNIL)
        read_points(L, 1, -1, top, UVS, "uvs");
    lua_settop(L, top);
    if (lua_getfield(L, 1, "faces") != LUA_TNIL)
        read_faces(L, 1, -1, top, "faces");
    lua_settop(L, top);
    lancer_charge(L);
    return 1;
}

static int w_triangle(lua_State *L)
{
    static const char *const known[] = {"a", "b", "c", "material", NULL};
    lf_open(L, 1, known);
    lc_vec3 z = {0, 0, 0};
    lc_vec3 a = lf_vec3(L, 1, "a", 1, z), b = lf_vec3(L, 1, "b", 1, z);
    lc_vec3 c = lf_vec3(L, 1, "c", 1, z);
    lf_udata(L, 1, "material", MATERIAL, 0);
    lc_mesh *m = push_mesh(L, -1);
    const lc_vec3 *corner[3] = {&a, &b, &c};
    static const char *const names[3] = {"a", "b", "c"};
    lc_error err;
    for (int k = 0; k < 3; k++) {       /* one by one, to name the one at fault */
        double v[3] = {corner[k]->x, corner[k]->y, corner[k]->z};
        if (lc_mesh_add_vertices(m, v, 1, &err)) {
            const char *why = strstr(err.msg, ": ");   /* past "vertices N: " */
            return lf_error(L, 1, names[k], "%s", why ? why + 2 : err.msg);
        }
    }
    uint32_t f[3] = {0, 1, 2};
    if (lc_mesh_add_faces(m, f, 1, &err))
        return luaL_error(L, "%s", err.msg);
    return 1;
}

static int w_load_obj(lua_State *L)
{
    static const char *const known[] = {"material", NULL};
    const char *path = luaL_checkstring(L, 1);
    if (!lua_isnoneornil(L, 2)) {
        lf_open(L, 2, known);
        lf_udata(L, 2, "material", MATERIAL, 0);
    } else {
        lua_settop(L, 1);
        lua_pushnil(L);
    }
    ud_mesh *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->m = NULL;
    luaL_setmetatable(L, MESH);
    lua_pushvalue(L, -2);
    lua_setiuservalue(L, -2, 1);
    lc_error err;
    u->m = lc_mesh_load_obj(path, &err);
    if (!u->m)
        return luaL_argerror(L, 1, err.msg);     /* names 'load_obj', the file, the line */
    lancer_charge(L);
    return 1;
}

static int w_mesh_add_vertices(lua_State *L)
{
    check_mesh(L, 1);
    read_points(L, 2, 2, 1, POINTS, "vertices");
    lua_pushinteger(L, (lua_Integer)lc_mesh_vertex_count(check_mesh(L, 1)));
    lancer_charge(L);
    return 1;
}

static int w_mesh_add_normals(lua_State *L)
{
    check_mesh(L, 1);
    read_points(L, 2, 2, 1, NORMALS, "normals");
    lancer_charge(L);
    return 0;
}

static int w_mesh_add_uvs(lua_State *L)
{
    check_mesh(L, 1);
    read_points(L, 2, 2, 1, UVS, "uvs");
    lancer_charge(L);
    return 0;
}

static int w_mesh_add_faces(lua_State *L)
{
    check_mesh(L, 1);
    read_faces(L, 2, 2, 1, "faces");
    lua_pushinteger(L, (lua_Integer)lc_mesh_face_count(check_mesh(L, 1)));
    lancer_charge(L);
    return 1;
}

static int w_mesh_free(lua_State *L)              /* __gc and __close */
{
    ud_mesh *u = luaL_checkudata(L, 1, MESH);
    lc_mesh_free(u->m);                          /* scenes keep their own hold */
    u->m = NULL;
    return 0;
}

static int w_mesh_tostring(lua_State *L)
{
    ud_mesh *u = luaL_checkudata(L, 1, MESH);
    if (!u->m)
        lua_pushstring(L, "lancer.Mesh (freed)");
    else
        lua_pushfstring(L, "lancer.Mesh (%d vertices, %d faces)",
                        (int)lc_mesh_vertex_count(u->m), (int)lc_mesh_face_count(u->m));
    return 1;
}

static int w_mesh_index(lua_State *L)
{
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "vertex_count") == 0) {
        lua_pushinteger(L, (lua_Integer)lc_mesh_vertex_count(check_mesh(L, 1)));
    } else if (strcmp(k, "face_count") == 0) {
        lua_pushinteger(L, (lua_Integer)lc_mesh_face_count(check_mesh(L, 1)));
    } else if (strcmp(k, "material") == 0) {
        lua_getiuservalue(L, 1, 1);
    } else {
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
    }
    return 1;
}


void mesh_register(lua_State *L)
{
    static const luaL_Reg mesh_meta[] = {
        {"__gc", w_mesh_free}, {"__close", w_mesh_free}, {"__tostring", w_mesh_tostring},
        {"__index", w_mesh_index}, {NULL, NULL}};
    static const luaL_Reg mesh_methods[] = {
        {"add_vertices", w_mesh_add_vertices}, {"add_faces", w_mesh_add_faces},
        {"add_normals", w_mesh_add_normals},
        {"add_uvs", w_mesh_add_uvs}, {"moved", motion_moved}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"mesh", w_mesh}, {"triangle", w_triangle}, {"load_obj", w_load_obj},
        {NULL, NULL}};
    lancer_class(L, MESH, mesh_meta, mesh_methods);
    luaL_setfuncs(L, funcs, 0);
}
