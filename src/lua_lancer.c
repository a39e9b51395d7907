/* lua_lancer.c: the Lua binding, a thin layer over lancer.h (require "lancer.core"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_lancer.h"
#include "lua_progress.h"

#define MATERIAL "lancer.Material"
#define SHAPE    "lancer.Shape"
#define LIGHT    "lancer.Light"
#define CAMERA   "lancer.Camera"
#define SCENE    "lancer.Scene"
#define IMAGE    "lancer.Image"
#define MESH     "lancer.Mesh"

typedef struct { lc_material m; } ud_material;
typedef struct { lc_shape s; } ud_shape;          /* user value 1: its material */
typedef struct { lc_point_light l; } ud_light;
typedef struct { lc_camera c; } ud_camera;
typedef struct {
    lc_scene *s;
    double    mark;     /* when the script last handed control back: creation or
                        ** the end of a render; what follows is scene building */
} ud_scene;                                       /* user value 1: see w_scene */

static double monotonic(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}
typedef struct { lc_image *img; } ud_image;
typedef struct { lc_mesh *m; } ud_mesh;           /* user value 1: its material */

/* Mirror bounces: the chain is a loop, so this only bounds the time a
** render of two facing mirrors may take. */
#define MAX_DEPTH 1000000

static const char *const shape_names[LC_SHAPE_KINDS] = {"sphere", "quad", "box", "plane"};

/* ---- small helpers ---------------------------------------------------------- */

static void buf_num(luaL_Buffer *b, double x)
{
    char tmp[40];
    snprintf(tmp, sizeof tmp, "%.6g", x);
    luaL_addstring(b, tmp);
}

static void buf_vec(luaL_Buffer *b, const char *name, lc_vec3 v)
{
    luaL_addstring(b, name);
    luaL_addstring(b, " = {");
    buf_num(b, v.x);
    luaL_addstring(b, ", ");
    buf_num(b, v.y);
    luaL_addstring(b, ", ");
    buf_num(b, v.z);
    luaL_addstring(b, "}");
}

static void buf_color(luaL_Buffer *b, const char *name, lc_color c)
{
    lc_vec3 v = {c.r, c.g, c.b};
    buf_vec(b, name, v);
}

/* ---- materials ------------------------------------------------------------ */

static const char *const absorb_opts[] = {"all", "diffuse", NULL};

static int w_material(lua_State *L)
{
    static const char *const known[] = {"color", "ka", "kd", "kr", "ks", "alpha",
                                        "emission", "absorb", NULL};
    lf_open(L, 1, known);
    lc_material m = lc_material_default();
    m.color = lf_color(L, 1, "color", 0, m.color);
    m.ka = lf_number(L, 1, "ka", 0, m.ka);
    m.kd = lf_number(L, 1, "kd", 0, m.kd);
    m.kr = lf_number(L, 1, "kr", 0, m.kr);
    m.ks = lf_number(L, 1, "ks", 0, m.ks);
    m.alpha = lf_number(L, 1, "alpha", 0, m.alpha);
    m.emission = lf_color(L, 1, "emission", 0, m.emission);
    m.absorb = (lc_absorb)lf_option(L, 1, "absorb", absorb_opts, (int)m.absorb);
    lc_error err;
    if (lc_material_check(&m, &err))
        return lf_raise(L, 1, &err);
    ud_material *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->m = m;
    luaL_setmetatable(L, MATERIAL);
    return 1;
}

static int w_material_tostring(lua_State *L)
{
    const lc_material *m = &((ud_material *)luaL_checkudata(L, 1, MATERIAL))->m;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.material{");
    buf_color(&b, "color", m->color);
    const char *names[] = {"ka", "kd", "kr", "ks", "alpha"};
    double vals[] = {m->ka, m->kd, m->kr, m->ks, m->alpha};
    for (int i = 0; i < 5; i++) {
        luaL_addstring(&b, ", ");
        luaL_addstring(&b, names[i]);
        luaL_addstring(&b, " = ");
        buf_num(&b, vals[i]);
    }
    luaL_addstring(&b, ", ");
    buf_color(&b, "emission", m->emission);
    luaL_addstring(&b, ", absorb = '");
    luaL_addstring(&b, absorb_opts[m->absorb]);
    luaL_addstring(&b, "'}");
    luaL_pushresult(&b);
    return 1;
}

static int w_material_index(lua_State *L)
{
    const lc_material *m = &((ud_material *)luaL_checkudata(L, 1, MATERIAL))->m;
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "color") == 0) lf_push_color(L, m->color);
    else if (strcmp(k, "emission") == 0) lf_push_color(L, m->emission);
    else if (strcmp(k, "ka") == 0) lua_pushnumber(L, m->ka);
    else if (strcmp(k, "kd") == 0) lua_pushnumber(L, m->kd);
    else if (strcmp(k, "kr") == 0) lua_pushnumber(L, m->kr);
    else if (strcmp(k, "ks") == 0) lua_pushnumber(L, m->ks);
    else if (strcmp(k, "alpha") == 0) lua_pushnumber(L, m->alpha);
    else if (strcmp(k, "absorb") == 0) lua_pushstring(L, absorb_opts[m->absorb]);
    else lua_pushnil(L);
    return 1;
}

/* ---- shapes --------------------------------------------------------------- */

/* Validates, then pushes the shape userdata holding `s` and its material. */
static int push_shape(lua_State *L, const lc_shape *s)
{
    lf_udata(L, 1, "material", MATERIAL, 0);        /* pushes it, or nil */
    lc_error err;
    if (lc_shape_check(s, &err))
        return lf_raise(L, 1, &err);
    ud_shape *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->s = *s;
    lua_insert(L, -2);
    lua_setiuservalue(L, -2, 1);
    luaL_setmetatable(L, SHAPE);
    return 1;
}

static int w_sphere(lua_State *L)
{
    static const char *const known[] = {"center", "radius", "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_SPHERE;
    s.p = lf_vec3(L, 1, "center", 1, s.p);
    s.radius = lf_number(L, 1, "radius", 1, 0);
    return push_shape(L, &s);
}

static int w_quad(lua_State *L)
{
    static const char *const known[] = {"corner", "u", "v", "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_QUAD;
    s.p = lf_vec3(L, 1, "corner", 1, s.p);
    s.u = lf_vec3(L, 1, "u", 1, s.u);
    s.v = lf_vec3(L, 1, "v", 1, s.v);
    return push_shape(L, &s);
}

static int w_box(lua_State *L)
{
    static const char *const known[] = {"corner", "u", "v", "w", "min", "max",
                                        "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_BOX;
    if (lf_present(L, 1, "min") || lf_present(L, 1, "max")) {
        const char *other[] = {"corner", "u", "v", "w"};
        for (int i = 0; i < 4; i++)
            if (lf_present(L, 1, other[i]))
                return lf_error(L, 1, other[i], "give either min and max, or corner "
                                "and u, v, w, not both");
        lc_vec3 lo = lf_vec3(L, 1, "min", 1, s.p), hi = lf_vec3(L, 1, "max", 1, s.p);
        double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
        for (int i = 0; i < 3; i++)
            if (!(h[i] > l[i]))
                return lf_error(L, 1, "max", "component %d must be > min's, got %g <= %g",
                                i + 1, h[i], l[i]);
        s.p = lo;
        s.u.x = hi.x - lo.x;
        s.v.y = hi.y - lo.y;
        s.w.z = hi.z - lo.z;
    } else {
        s.p = lf_vec3(L, 1, "corner", 1, s.p);
        s.u = lf_vec3(L, 1, "u", 1, s.u);
        s.v = lf_vec3(L, 1, "v", 1, s.v);
        s.w = lf_vec3(L, 1, "w", 1, s.w);
    }
    return push_shape(L, &s);
}

static int w_plane(lua_State *L)
{
    static const char *const known[] = {"point", "normal", "material", NULL};
    lf_open(L, 1, known);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_PLANE;
    s.p = lf_vec3(L, 1, "point", 1, s.p);
    s.u = lf_vec3(L, 1, "normal", 1, s.u);
    return push_shape(L, &s);
}

static int w_shape_tostring(lua_State *L)
{
    const lc_shape *s = &((ud_shape *)luaL_checkudata(L, 1, SHAPE))->s;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.");
    luaL_addstring(&b, shape_names[s->kind]);
    luaL_addstring(&b, "{");
    switch (s->kind) {
    case LC_SPHERE:
        buf_vec(&b, "center", s->p);
        luaL_addstring(&b, ", radius = ");
        buf_num(&b, s->radius);
        break;
    case LC_QUAD:
        buf_vec(&b, "corner", s->p);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "u", s->u);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "v", s->v);
        break;
    case LC_BOX:
        buf_vec(&b, "corner", s->p);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "u", s->u);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "v", s->v);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "w", s->w);
        break;
    default:
        buf_vec(&b, "point", s->p);
        luaL_addstring(&b, ", ");
        buf_vec(&b, "normal", s->u);
        break;
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    return 1;
}

static int w_shape_index(lua_State *L)
{
    const lc_shape *s = &((ud_shape *)luaL_checkudata(L, 1, SHAPE))->s;
    const char *k = luaL_checkstring(L, 2);
    int sph = s->kind == LC_SPHERE, pl = s->kind == LC_PLANE;
    if (strcmp(k, "kind") == 0) lua_pushstring(L, shape_names[s->kind]);
    else if (strcmp(k, "material") == 0) lua_getiuservalue(L, 1, 1);
    else if (sph && strcmp(k, "center") == 0) lf_push_vec3(L, s->p);
    else if (sph && strcmp(k, "radius") == 0) lua_pushnumber(L, s->radius);
    else if (pl && strcmp(k, "point") == 0) lf_push_vec3(L, s->p);
    else if (pl && strcmp(k, "normal") == 0) lf_push_vec3(L, s->u);
    else if (!sph && !pl && strcmp(k, "corner") == 0) lf_push_vec3(L, s->p);
    else if (!sph && !pl && strcmp(k, "u") == 0) lf_push_vec3(L, s->u);
    else if (!sph && !pl && strcmp(k, "v") == 0) lf_push_vec3(L, s->v);
    else if (s->kind == LC_BOX && strcmp(k, "w") == 0) lf_push_vec3(L, s->w);
    else lua_pushnil(L);
    return 1;
}

/* ---- meshes --------------------------------------------------------------- */

#define CHUNK 1024    /* items converted per call into the core */

static lc_mesh *check_mesh(lua_State *L, int idx)
{
    ud_mesh *u = luaL_checkudata(L, idx, MESH);
    if (!u->m)
        luaL_error(L, "lancer.Mesh already freed");
    return u->m;
}

/* Reads a list of points into the mesh: nested {{x, y, z}, ...} or flat
** {x, y, z, x, y, z, ...} (the fast path for large arrays). `field` names
** it in errors; arg is the argument holding the list's table, or the list. */
static void read_points(lua_State *L, int arg, int list, lc_mesh *m, int normals,
                        const char *field)
{
    double buf[3 * CHUNK];
    size_t nb = 0;
    lc_error err;
    list = lua_absindex(L, list);
    if (lua_type(L, list) != LUA_TTABLE)
        lf_error(L, arg, field, "table of points expected, got %s", luaL_typename(L, list));
    lua_Integer n = luaL_len(L, list);
    int flat = n > 0 && lua_geti(L, list, 1) == LUA_TNUMBER;
    if (n > 0)
        lua_pop(L, 1);
    if (flat && n % 3 != 0)
        lf_error(L, arg, field, "flat list length must be a multiple of 3, got %lld",
                 (long long)n);
    lua_Integer count = flat ? n / 3 : n;
    for (lua_Integer i = 1; i <= count; i++) {
        if (flat) {
            for (int k = 0; k < 3; k++) {
                if (lua_geti(L, list, 3 * (i - 1) + k + 1) != LUA_TNUMBER)
                    lf_error(L, arg, field, "entry %lld: number expected, got %s",
                             (long long)(3 * (i - 1) + k + 1), luaL_typename(L, -1));
                double x = lua_tonumber(L, -1);
                lua_pop(L, 1);
                if (!isfinite(x))
                    lf_error(L, arg, field, "entry %lld: must be finite, got %g",
                             (long long)(3 * (i - 1) + k + 1), x);
                buf[3 * nb + k] = x;
            }
        } else {
            char why[160];
            lc_vec3 v;
            lua_geti(L, list, i);
            if (!lf_to_vec3(L, -1, &v, why, sizeof why))
                lf_error(L, arg, field, "point %lld: %s", (long long)i, why);
            lua_pop(L, 1);
            buf[3 * nb] = v.x;
            buf[3 * nb + 1] = v.y;
            buf[3 * nb + 2] = v.z;
        }
        if (++nb == CHUNK || i == count) {
            lc_status st = normals ? lc_mesh_add_normals(m, buf, nb, &err)
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

/* Faces: nested {{a, b, c}, {a, b, c, d}, ...} (polygons become fans) or flat
** {a, b, c, a, b, c, ...}; indices start at 1, as Lua's do. */
static void read_faces(lua_State *L, int arg, int list, lc_mesh *m, const char *field)
{
    uint32_t buf[3 * CHUNK];
    size_t nb = 0;
    lc_error err;
    size_t nv = lc_mesh_vertex_count(m);
    list = lua_absindex(L, list);
    if (lua_type(L, list) != LUA_TTABLE)
        lf_error(L, arg, field, "table of faces expected, got %s", luaL_typename(L, list));
    lua_Integer n = luaL_len(L, list);
    int flat = n > 0 && lua_geti(L, list, 1) == LUA_TNUMBER;
    if (n > 0)
        lua_pop(L, 1);
    if (flat && n % 3 != 0)
        lf_error(L, arg, field, "flat list length must be a multiple of 3, got %lld",
                 (long long)n);
    lua_Integer count = flat ? n / 3 : n;
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
                    if (lc_mesh_add_faces(m, buf, nb, &err))
                        lf_error(L, arg, field, "%s", err.msg);
                    nb = 0;
                }
            }
            lua_pop(L, 1);
            continue;
        }
        if (nb == CHUNK) {
            if (lc_mesh_add_faces(m, buf, nb, &err))
                lf_error(L, arg, field, "%s", err.msg);
            nb = 0;
        }
    }
    if (nb && lc_mesh_add_faces(m, buf, nb, &err))
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
    static const char *const known[] = {"vertices", "faces", "normals", "material", NULL};
    if (lua_isnoneornil(L, 1)) {
        lua_settop(L, 0);
        lua_newtable(L);
    }
    lf_open(L, 1, known);
    lf_udata(L, 1, "material", MATERIAL, 0);
    int mat = lua_gettop(L);
    lc_mesh *m = push_mesh(L, mat);
    int top = lua_gettop(L);
    if (lua_getfield(L, 1, "vertices") != LUA_TNIL)
        read_points(L, 1, -1, m, 0, "vertices");
    lua_settop(L, top);
    if (lua_getfield(L, 1, "normals") != LUA_TNIL)
        read_points(L, 1, -1, m, 1, "normals");
    lua_settop(L, top);
    if (lua_getfield(L, 1, "faces") != LUA_TNIL)
        read_faces(L, 1, -1, m, "faces");
    lua_settop(L, top);
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
    double v[9] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
    uint32_t f[3] = {0, 1, 2};
    lc_error err;
    if (lc_mesh_add_vertices(m, v, 3, &err) || lc_mesh_add_faces(m, f, 1, &err))
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
    return 1;
}

static int w_mesh_add_vertices(lua_State *L)
{
    lc_mesh *m = check_mesh(L, 1);
    read_points(L, 2, 2, m, 0, "vertices");
    lua_pushinteger(L, (lua_Integer)lc_mesh_vertex_count(m));
    return 1;
}

static int w_mesh_add_normals(lua_State *L)
{
    lc_mesh *m = check_mesh(L, 1);
    read_points(L, 2, 2, m, 1, "normals");
    return 0;
}

static int w_mesh_add_faces(lua_State *L)
{
    lc_mesh *m = check_mesh(L, 1);
    read_faces(L, 2, 2, m, "faces");
    lua_pushinteger(L, (lua_Integer)lc_mesh_face_count(m));
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

/* ---- lights and cameras ----------------------------------------------------- */

static const char *const falloff_opts[] = {"inverse_square", "none", NULL};

static int w_point_light(lua_State *L)
{
    static const char *const known[] = {"position", "color", "intensity", "falloff", NULL};
    lf_open(L, 1, known);
    lc_point_light l;
    memset(&l, 0, sizeof l);
    l.position = lf_vec3(L, 1, "position", 1, l.position);
    l.color = lf_color(L, 1, "color", 0, (lc_color){1, 1, 1});
    l.intensity = lf_number(L, 1, "intensity", 0, 1);
    l.falloff = (lc_falloff)lf_option(L, 1, "falloff", falloff_opts, 0);
    lc_error err;
    if (lc_point_light_check(&l, &err))
        return lf_raise(L, 1, &err);
    ud_light *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->l = l;
    luaL_setmetatable(L, LIGHT);
    return 1;
}

static int w_light_tostring(lua_State *L)
{
    const lc_point_light *l = &((ud_light *)luaL_checkudata(L, 1, LIGHT))->l;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.point_light{");
    buf_vec(&b, "position", l->position);
    luaL_addstring(&b, ", ");
    buf_color(&b, "color", l->color);
    luaL_addstring(&b, ", intensity = ");
    buf_num(&b, l->intensity);
    luaL_addstring(&b, ", falloff = '");
    luaL_addstring(&b, falloff_opts[l->falloff]);
    luaL_addstring(&b, "'}");
    luaL_pushresult(&b);
    return 1;
}

static int w_light_index(lua_State *L)
{
    const lc_point_light *l = &((ud_light *)luaL_checkudata(L, 1, LIGHT))->l;
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "kind") == 0) lua_pushstring(L, "point_light");
    else if (strcmp(k, "position") == 0) lf_push_vec3(L, l->position);
    else if (strcmp(k, "color") == 0) lf_push_color(L, l->color);
    else if (strcmp(k, "intensity") == 0) lua_pushnumber(L, l->intensity);
    else if (strcmp(k, "falloff") == 0) lua_pushstring(L, falloff_opts[l->falloff]);
    else lua_pushnil(L);
    return 1;
}

static int w_camera(lua_State *L)
{
    static const char *const known[] = {"from", "at", "up", "fov", NULL};
    lf_open(L, 1, known);
    lc_camera c;
    memset(&c, 0, sizeof c);
    c.from = lf_vec3(L, 1, "from", 1, c.from);
    c.at = lf_vec3(L, 1, "at", 1, c.at);
    c.up = lf_vec3(L, 1, "up", 0, (lc_vec3){0, 1, 0});
    c.fov = lf_number(L, 1, "fov", 0, 60);
    lc_error err;
    if (lc_camera_check(&c, &err))
        return lf_raise(L, 1, &err);
    ud_camera *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->c = c;
    luaL_setmetatable(L, CAMERA);
    return 1;
}

static int w_camera_tostring(lua_State *L)
{
    const lc_camera *c = &((ud_camera *)luaL_checkudata(L, 1, CAMERA))->c;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.camera{");
    buf_vec(&b, "from", c->from);
    luaL_addstring(&b, ", ");
    buf_vec(&b, "at", c->at);
    luaL_addstring(&b, ", ");
    buf_vec(&b, "up", c->up);
    luaL_addstring(&b, ", fov = ");
    buf_num(&b, c->fov);
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    return 1;
}

static int w_camera_index(lua_State *L)
{
    const lc_camera *c = &((ud_camera *)luaL_checkudata(L, 1, CAMERA))->c;
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "from") == 0) lf_push_vec3(L, c->from);
    else if (strcmp(k, "at") == 0) lf_push_vec3(L, c->at);
    else if (strcmp(k, "up") == 0) lf_push_vec3(L, c->up);
    else if (strcmp(k, "fov") == 0) lua_pushnumber(L, c->fov);
    else lua_pushnil(L);
    return 1;
}

/* ---- scenes --------------------------------------------------------------- */

static int w_records_free(lua_State *L)
{
    lc_ray_record **box = lua_touserdata(L, 1);
    free(*box);
    *box = NULL;
    return 0;
}

/* A scene's user value is a table: [1] its camera userdata, [2] a table from
** material userdata to the index the core gave it (so a material shared by a
** million spheres is stored once), [3] the index of the default material. */
enum { SC_CAMERA = 1, SC_MATERIALS = 2, SC_DEFAULT = 3 };

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
    st.max_depth = lf_integer(L, 1, "max_depth", 0, st.max_depth);
    if (st.max_depth < 0 || st.max_depth > MAX_DEPTH)
        return lf_error(L, 1, "max_depth", "must be in [0, %d], got %d", MAX_DEPTH,
                        st.max_depth);
    int has_camera = lf_present(L, 1, "camera");
    if (has_camera)
        lf_udata(L, 1, "camera", CAMERA, 1);   /* type check before allocating */

    ud_scene *u = lua_newuserdatauv(L, sizeof *u, 1);   /* before the core object */
    u->s = NULL;
    luaL_setmetatable(L, SCENE);
    int sidx = lua_gettop(L);
    lua_createtable(L, 3, 0);
    lua_newtable(L);
    lua_rawseti(L, -2, SC_MATERIALS);
    lua_setiuservalue(L, sidx, 1);
    lc_error err;
    u->s = lc_scene_new(&err);
    u->mark = monotonic();
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

/* Raises unless the value at idx is a shape, a light or an array of them,
** so that a bad call to add leaves the scene as it was. */
static void check_addable(lua_State *L, int idx, int arg, int depth, lua_Integer elem)
{
    idx = lua_absindex(L, idx);
    if (luaL_testudata(L, idx, SHAPE) || luaL_testudata(L, idx, LIGHT))
        return;
    ud_mesh *me = luaL_testudata(L, idx, MESH);
    if (me) {
        if (!me->m)
            luaL_argerror(L, arg, "lancer.Mesh already freed");
        return;
    }
    if (lua_type(L, idx) == LUA_TTABLE && depth < 8) {
        lua_Integer n = luaL_len(L, idx);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_geti(L, idx, i);
            check_addable(L, -1, arg, depth + 1, i);
            lua_pop(L, 1);
        }
        return;
    }
    const char *got = luaL_typename(L, idx);
    if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING)
        got = lua_tostring(L, -1);
    if (elem)
        lua_pushfstring(L, "element %I: shape, mesh, light or array of them expected, got %s",
                        elem, got);
    else
        lua_pushfstring(L, "shape, mesh, light or array of them expected, got %s", got);
    luaL_argerror(L, arg, lua_tostring(L, -1));
}

/* Adds the object at idx, already checked: a shape, a light, or an array. */
static void add_one(lua_State *L, ud_scene *u, int idx, int arg, int depth)
{
    lc_error err;
    idx = lua_absindex(L, idx);
    ud_shape *sh = luaL_testudata(L, idx, SHAPE);
    if (sh) {
        lua_getiuservalue(L, idx, 1);
        int mat = material_index(L, u, 1, lua_gettop(L), arg);
        lua_pop(L, 1);
        if (lc_scene_add_shape(u->s, &sh->s, mat, &err) < 0)
            lf_raise(L, arg, &err);
        return;
    }
    ud_mesh *me = luaL_testudata(L, idx, MESH);
    if (me) {
        lua_getiuservalue(L, idx, 1);
        int mat = material_index(L, u, 1, lua_gettop(L), arg);
        lua_pop(L, 1);
        if (lc_scene_add_mesh(u->s, me->m, mat, &err) < 0)
            lf_raise(L, arg, &err);
        return;
    }
    ud_light *li = luaL_testudata(L, idx, LIGHT);
    if (li) {
        if (lc_scene_add_light(u->s, &li->l, &err) < 0)
            lf_raise(L, arg, &err);
        return;
    }
    lua_Integer n = luaL_len(L, idx);
    for (lua_Integer i = 1; i <= n; i++) {
        lua_geti(L, idx, i);
        add_one(L, u, -1, arg, depth + 1);
        lua_pop(L, 1);
    }
}

static int w_scene_add(lua_State *L)
{
    ud_scene *u = check_scene(L, 1);
    int n = lua_gettop(L);
    if (n < 2)
        return luaL_argerror(L, 2, "shape, mesh, light or array of them expected, got no value");
    for (int i = 2; i <= n; i++)
        check_addable(L, i, i, 0, 0);
    for (int i = 2; i <= n; i++)
        add_one(L, u, i, i, 0);
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
    c->mark = monotonic();
    luaL_setmetatable(L, SCENE);
    int ci = lua_gettop(L);
    lua_createtable(L, 3, 0);
    lua_getiuservalue(L, 1, 1);
    lua_rawgeti(L, -1, SC_MATERIALS);
    lua_rawseti(L, -3, SC_MATERIALS);
    lua_rawgeti(L, -1, SC_DEFAULT);
    lua_rawseti(L, -3, SC_DEFAULT);
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
    lua_createtable(L, 0, LC_RAY_KINDS);
    for (int k = 0; k < LC_RAY_KINDS; k++) {
        lua_pushinteger(L, (lua_Integer)st->rays[k]);
        lua_setfield(L, -2, lc_ray_kind_name((lc_ray_kind)k));
    }
    lua_setfield(L, -2, "rays");
    lua_newtable(L);
    for (unsigned bit = 1; bit <= LC_NEED_AMBIENT; bit <<= 1) {
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
** --stats prints each render's ledger. */
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
    if (o->cutoff < 0 || o->cutoff > 1)
        lf_error(L, arg, "cutoff", "must be in [0, 1], got %g", o->cutoff);
}

static int w_scene_render(lua_State *L)
{
    static const char *const known[] = {"width", "height", "samples", "seed", "threads",
                                        "cosine", "cutoff", "progress", "shadows",
                                        "reflections", "specular", "generic", NULL};
    ud_scene *u = check_scene(L, 1);
    lua_settop(L, 2);
    if (override_flag(L, "check")) {
        lua_getglobal(L, "require");
        lua_pushliteral(L, "lancer.check");
        lua_call(L, 1, 1);
        lua_getfield(L, -1, "render");
        lua_pushvalue(L, 1);
        lua_pushvalue(L, 2);
        lua_call(L, 2, 2);
        return 2;
    }
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
    lua_progress bar;
    lua_progress_begin(&bar, show);
    o.progress = lua_progress_update;
    o.progress_ud = &bar;
    double lua_seconds = monotonic() - u->mark;
    ui->img = lc_scene_render(u->s, &o, &st, &err);
    u->mark = monotonic();
    lua_progress_end(&bar);
    if (!ui->img) {
        if (strcmp(err.field, "camera") == 0)
            return luaL_error(L, "render: the scene has no camera (set scene.camera = "
                              "lancer.camera{...})");
        return lf_raise(L, 2, &err);
    }
    push_stats(L, &st, lua_seconds);
    if (override_flag(L, "stats")) {
        lua_getglobal(L, "require");
        lua_pushliteral(L, "lancer.ledger");
        lua_call(L, 1, 1);
        lua_getfield(L, -1, "report");
        lua_pushvalue(L, -3);
        lua_call(L, 1, 0);
        lua_pop(L, 1);
    }
    return 2;
}

#define RAYTREE "lancer.RayTree"

static const char *const kind_names[] = {"sphere", "quad", "box", "plane", "triangle"};

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
    if (x->kind == LC_RAY_SHADOW) {
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
        lua_pushfstring(L, "%s %d", kind_names[x->shape_kind], (int)x->shape + 1);
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
                                        "reflections", "specular", "generic", NULL};
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
        if (lua_type(L, 3) != LUA_TNUMBER || !isint || d < 0 || d > MAX_DEPTH)
            return luaL_error(L, "scene.max_depth: integer in [0, %d] expected, got %s",
                              MAX_DEPTH, luaL_tolstring(L, 3, NULL));
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

/* ---- images --------------------------------------------------------------- */

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

static int w_image_save(lua_State *L)
{
    static const char *const known[] = {"encoding", NULL};
    lc_image *img = check_image(L, 1);
    luaL_checktype(L, 2, LUA_TSTRING);       /* a number is no file name */
    const char *path = lua_tostring(L, 2);
    lc_encoding enc = LC_ENCODE_SRGB;
    if (!lua_isnoneornil(L, 3)) {
        lf_open(L, 3, known);
        enc = (lc_encoding)lf_option(L, 3, "encoding", encoding_opts, 0);
    }
    lc_error err;
    if (lc_image_save_png(img, path, enc, &err))
        return luaL_argerror(L, 2, err.msg);     /* names 'save' and the path */
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
    ud_image *ui = lua_newuserdatauv(L, sizeof *ui, 0);   /* before the image */
    ui->img = NULL;
    luaL_setmetatable(L, IMAGE);
    lc_error err;
    ui->img = lc_image_load_png(lua_tostring(L, 1), enc, &err);
    if (!ui->img)
        return luaL_argerror(L, 1, err.msg);
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

/* ---- the module ------------------------------------------------------------- */

static void new_class(lua_State *L, const char *name, const luaL_Reg *meta,
                      const luaL_Reg *methods)
{
    luaL_newmetatable(L, name);
    luaL_setfuncs(L, meta, 0);
    if (methods) {
        lua_newtable(L);
        luaL_setfuncs(L, methods, 0);
        lua_setfield(L, -2, "methods");
    }
    lua_pop(L, 1);
}

int luaopen_lancer_core(lua_State *L)
{
    static const luaL_Reg material_meta[] = {
        {"__tostring", w_material_tostring}, {"__index", w_material_index}, {NULL, NULL}};
    static const luaL_Reg shape_meta[] = {
        {"__tostring", w_shape_tostring}, {"__index", w_shape_index}, {NULL, NULL}};
    static const luaL_Reg light_meta[] = {
        {"__tostring", w_light_tostring}, {"__index", w_light_index}, {NULL, NULL}};
    static const luaL_Reg camera_meta[] = {
        {"__tostring", w_camera_tostring}, {"__index", w_camera_index}, {NULL, NULL}};
    static const luaL_Reg scene_meta[] = {
        {"__gc", w_scene_free}, {"__close", w_scene_free}, {"__tostring", w_scene_tostring},
        {"__index", w_scene_index}, {"__newindex", w_scene_newindex}, {NULL, NULL}};
    static const luaL_Reg scene_methods[] = {
        {"add", w_scene_add}, {"render", w_scene_render}, {"count", w_scene_count},
        {"transformed", w_scene_transformed}, {"explain", w_scene_explain},
        {NULL, NULL}};
    static const luaL_Reg image_meta[] = {
        {"__gc", w_image_free}, {"__close", w_image_free}, {"__tostring", w_image_tostring},
        {"__index", w_image_index}, {NULL, NULL}};
    static const luaL_Reg image_methods[] = {
        {"save", w_image_save}, {"pixel", w_image_pixel}, {"diff", w_image_diff},
        {"nonfinite", w_image_nonfinite},
        {NULL, NULL}};
    static const luaL_Reg mesh_meta[] = {
        {"__gc", w_mesh_free}, {"__close", w_mesh_free}, {"__tostring", w_mesh_tostring},
        {"__index", w_mesh_index}, {NULL, NULL}};
    static const luaL_Reg mesh_methods[] = {
        {"add_vertices", w_mesh_add_vertices}, {"add_faces", w_mesh_add_faces},
        {"add_normals", w_mesh_add_normals}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"mesh", w_mesh}, {"triangle", w_triangle}, {"load_obj", w_load_obj},
        {"load_png", w_load_png},
        {"material", w_material}, {"sphere", w_sphere}, {"quad", w_quad}, {"box", w_box},
        {"plane", w_plane}, {"point_light", w_point_light}, {"camera", w_camera},
        {"scene", w_scene}, {NULL, NULL}};

    new_class(L, MATERIAL, material_meta, NULL);
    new_class(L, SHAPE, shape_meta, NULL);
    new_class(L, LIGHT, light_meta, NULL);
    new_class(L, CAMERA, camera_meta, NULL);
    new_class(L, SCENE, scene_meta, scene_methods);
    new_class(L, IMAGE, image_meta, image_methods);
    new_class(L, MESH, mesh_meta, mesh_methods);
    luaL_newmetatable(L, RAYTREE);
    lua_pushcfunction(L, w_raytree_tostring);
    lua_setfield(L, -2, "__tostring");
    lua_pop(L, 1);

    luaL_newlib(L, funcs);
    lua_pushstring(L, LC_VERSION);
    lua_setfield(L, -2, "version");
    lua_pushstring(L, "lancer " LC_VERSION);
    lua_setfield(L, -2, "_VERSION");
    lua_newtable(L);
    lua_setfield(L, -2, "overrides");
    return 1;
}
