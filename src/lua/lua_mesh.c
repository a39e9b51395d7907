/* lua_mesh.c: triangle meshes: lancer.mesh, lancer.triangle, lancer.load_obj. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* ---- meshes --------------------------------------------------------------- */

#define CHUNK 1024    /* items converted per call into the core */

/* The core mesh of the userdata at idx, raising when freed: fetched right
** before the lc_ call that uses it (see lb_scene_at in lua_binding.h). */
static lc_mesh *check_mesh(lua_State *L, int idx)
{
    lb_ud_mesh *u = luaL_checkudata(L, idx, LB_MESH);
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
/* Face i's material slot from the list at `slots` (0: none): 1-based in
** Lua, at most `nmat`. */
static uint32_t face_slot(lua_State *L, int arg, int slots, lua_Integer i, lua_Integer nmat)
{
    if (!slots)
        return 0;
    int isint;
    lua_geti(L, slots, i);
    lua_Integer k = lua_tointegerx(L, -1, &isint);
    if (!isint || k < 1 || k > nmat)
        lf_error(L, arg, "face_materials", "face %lld: an index into materials (1..%lld) "
                 "expected, got %s", (long long)i, (long long)nmat, luaL_tolstring(L, -1, NULL));
    lua_pop(L, 1);
    return (uint32_t)(k - 1);
}

/* Adds the faces in buf and, with slots, their slots. */
static void flush_faces(lua_State *L, int arg, int mi, const char *field, const uint32_t *buf,
                        const uint32_t *sb, size_t nb, int slots)
{
    lc_error err;
    if (lc_mesh_add_faces(check_mesh(L, mi), buf, nb, &err))
        lf_error(L, arg, field, "%s", err.msg);
    if (slots && lc_mesh_add_face_materials(check_mesh(L, mi), sb, nb, &err))
        lf_error(L, arg, "face_materials", "%s", err.msg);
}

static void read_faces(lua_State *L, int arg, int list, int mi, const char *field, int slots,
                       lua_Integer nmat)
{
    uint32_t buf[3 * CHUNK], sb[CHUNK];
    size_t nb = 0;
    int flat;
    list = lua_absindex(L, list);
    mi = lua_absindex(L, mi);
    lua_Integer count = list_count(L, arg, list, field, "faces", 3, &flat);
    if (slots && (lua_Integer)luaL_len(L, slots) != count)
        lf_error(L, arg, "face_materials", "%lld entries for %lld faces",
                 (long long)luaL_len(L, slots), (long long)count);
    size_t nv = lc_mesh_vertex_count(check_mesh(L, mi));
    for (lua_Integer i = 1; i <= count; i++) {
        uint32_t slot = face_slot(L, arg, slots, i, nmat);
        if (flat) {
            for (int k = 0; k < 3; k++) {
                lua_geti(L, list, 3 * (i - 1) + k + 1);
                buf[3 * nb + k] = face_index(L, arg, field, i, nv);
            }
            sb[nb] = slot;
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
                sb[nb] = slot;
                prev = cur;
                if (++nb == CHUNK) {
                    flush_faces(L, arg, mi, field, buf, sb, nb, slots);
                    nb = 0;
                }
            }
            lua_pop(L, 1);
            continue;
        }
        if (nb == CHUNK) {
            flush_faces(L, arg, mi, field, buf, sb, nb, slots);
            nb = 0;
        }
    }
    if (nb)
        flush_faces(L, arg, mi, field, buf, sb, nb, slots);
}

/* The mesh at mi takes the materials list at `list` as its face slots'. */
static lua_Integer set_palette(lua_State *L, int arg, int list, int mi)
{
    list = lua_absindex(L, list);
    if (lua_type(L, list) != LUA_TTABLE)
        lf_error(L, arg, "materials", "table of materials expected, got %s",
                 luaL_typename(L, list));
    lua_Integer n = luaL_len(L, list);
    if (n < 1 || n > 4096)
        lf_error(L, arg, "materials", "1 to 4096 materials expected, got %lld", (long long)n);
    lua_createtable(L, (int)n, 0);
    for (lua_Integer k = 1; k <= n; k++) {
        lua_geti(L, list, k);
        if (!luaL_testudata(L, -1, LB_MATERIAL))
            lf_error(L, arg, "materials", "entry %lld: lancer.Material expected, got %s",
                     (long long)k, luaL_typename(L, -1));
        lua_rawseti(L, -2, k);
    }
    lua_setiuservalue(L, mi, 2);
    return n;
}

/* Pushes an empty mesh userdata (before the core mesh, so nothing leaks if
** allocation fails) with the material at stack index mat (or nil). */
static lc_mesh *push_mesh(lua_State *L, int mat)
{
    mat = lua_absindex(L, mat);
    lb_ud_mesh *u = lua_newuserdatauv(L, sizeof *u, 2);
    u->m = NULL;
    luaL_setmetatable(L, LB_MESH);
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
                                        "materials", "face_materials", NULL};
    if (lua_isnoneornil(L, 1)) {
        lua_settop(L, 0);
        lua_newtable(L);
    }
    lf_open(L, 1, known);
    lf_udata(L, 1, "material", LB_MATERIAL, 0);
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
    lua_Integer nmat = 0;
    if (lua_getfield(L, 1, "materials") != LUA_TNIL)
        nmat = set_palette(L, 1, -1, top);
    lua_settop(L, top);
    int slots = 0;
    if (lua_getfield(L, 1, "face_materials") != LUA_TNIL) {
        if (!nmat)
            return lf_error(L, 1, "face_materials", "needs 'materials' to index");
        if (lua_type(L, -1) != LUA_TTABLE)
            return lf_error(L, 1, "face_materials", "table of indices expected, got %s",
                            luaL_typename(L, -1));
        slots = lua_gettop(L);
    }
    if (lua_getfield(L, 1, "faces") != LUA_TNIL)
        read_faces(L, 1, -1, top, "faces", slots, nmat);
    else if (slots)
        return lf_error(L, 1, "face_materials", "given without 'faces'");
    lua_settop(L, top);
    lb_charge(L);
    return 1;
}

static int w_triangle(lua_State *L)
{
    static const char *const known[] = {"a", "b", "c", "material", NULL};
    lf_open(L, 1, known);
    lc_vec3 z = {0, 0, 0};
    lc_vec3 a = lf_vec3(L, 1, "a", 1, z), b = lf_vec3(L, 1, "b", 1, z);
    lc_vec3 c = lf_vec3(L, 1, "c", 1, z);
    lf_udata(L, 1, "material", LB_MATERIAL, 0);
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

/* Pushes the material a .mtl record maps to, with its textures (when
** `textures`): a map_Kd for the colour, a bump map, a normal map (norm; its
** values are data, read as stored). */
static void push_mtl_material(lua_State *L, const lc_mtl *t, int textures, const char *obj,
                              int warnings)
{
    lc_material m = lc_mtl_material(t);
    if (t->map_bump[0] && textures)
        m.bump = 0.02 * t->bump_mult;
    lb_material_push(L, &m);
    if (!textures)
        return;
    int mat = lua_gettop(L);
    lua_getiuservalue(L, mat, 1);
    const char *files[3] = {t->map_kd, t->map_bump, t->map_norm};
    const char *slot[3] = {"color", "bump", "normal_map"};
    const char *kind[3] = {"map_Kd", "bump map", "normal map"};
    for (int k = 0; k < 3; k++) {
        if (!files[k][0])
            continue;
        char what[LC_MTL_PATH + 300];
        snprintf(what, sizeof what, "'%s': material '%s': %s", obj, t->name, kind[k]);
        lb_check_file(L, 1, files[k], 0);
        FILE *fp = fopen(files[k], "rb");
        if (!fp) {                           /* not there: noted, the colour stays */
            lua_pushfstring(L, "%s '%s' cannot be opened: %s", what, files[k],
                            strerror(errno));
            lua_rawseti(L, warnings, (lua_Integer)lua_rawlen(L, warnings) + 1);
            if (k == 1)
                ((lb_ud_material *)lua_touserdata(L, mat))->m.bump = 0;
            continue;
        }
        fclose(fp);
        /* There but unreadable: an error. */
        lb_texture_push_png(L, files[k], what,
                            k == 2 ? LC_ENCODE_LINEAR : LC_ENCODE_SRGB);
        lua_setfield(L, -2, slot[k]);
    }
    lua_pop(L, 1);
}

/* The .mtl libraries an OBJ names, copied into one userdata pushed (so an
** error later leaks nothing): its records and their count. */
static const lc_mtl *push_libraries(lua_State *L, const lc_mesh *m, const char *path,
                                    size_t *n, int warnings)
{
    size_t nlibs = lc_mesh_mtllib_count(m), total = 0;
    lc_mtl *part[64];
    size_t count[64];
    if (nlibs > 64)
        luaL_error(L, "'%s': more than 64 mtllib files", path);
    for (size_t l = 0; l < nlibs; l++)      /* all first: a refusal raises, and leaks */
        lb_check_file(L, 1, lc_mesh_mtllib(m, l), 0);
    for (size_t l = 0; l < nlibs; l++) {
        lc_error err;
        if (lc_mtl_load(lc_mesh_mtllib(m, l), &part[l], &count[l], &err)) {
            if (err.code == LC_EIO && strncmp(err.msg, "cannot open", 11) == 0) {
                /* Not there (OBJ files often travel without theirs): noted. */
                part[l] = NULL;
                count[l] = 0;
                lua_pushfstring(L, "'%s': mtllib %s", path, err.msg);
                lua_rawseti(L, warnings, (lua_Integer)lua_rawlen(L, warnings) + 1);
                continue;
            }
            for (size_t k = 0; k < l; k++)
                free(part[k]);
            luaL_error(L, "'%s': mtllib %s", path, err.msg);
        }
        total += count[l];
    }
    lc_mtl *all = lua_newuserdatauv(L, (total ? total : 1) * sizeof *all, 0);
    *n = 0;
    for (size_t l = 0; l < nlibs; l++) {
        if (count[l])                   /* a library not there has none, and no list */
            memcpy(all + *n, part[l], count[l] * sizeof *all);
        *n += count[l];
        free(part[l]);
    }
    return all;
}

static const lc_mtl *mtl_find(const lc_mtl *all, size_t n, const char *name)
{
    for (size_t i = n; i-- > 0;)               /* a later library's wins */
        if (strcmp(all[i].name, name) == 0)
            return &all[i];
    return NULL;
}

/* The OBJ's face slots take their materials: `materials` (by name) first,
** then its .mtl libraries; a slot with no name, or a name found nowhere,
** takes the mesh's own. */
static void obj_palette(lua_State *L, int mesh, int opts, int textures, const char *path)
{
    size_t nslots = lc_mesh_material_slots(check_mesh(L, mesh)), nmtl;
    if (nslots == 0)
        return;
    if (nslots > 4096)
        luaL_error(L, "'%s': %zu materials, past lancer's 4096 for one OBJ", path, nslots);
    lua_newtable(L);
    int warnings = lua_gettop(L);
    lua_pushvalue(L, warnings);
    lua_setiuservalue(L, mesh, 3);
    const lc_mtl *all = push_libraries(L, check_mesh(L, mesh), path, &nmtl, warnings);
    lua_createtable(L, (int)nslots, 0);
    int pal = lua_gettop(L);
    for (size_t k = 0; k < nslots; k++) {
        const char *name = lc_mesh_slot_name(check_mesh(L, mesh), k);
        const lc_mtl *t = name ? mtl_find(all, nmtl, name) : NULL;
        int given = name && opts && lua_getfield(L, opts, "materials") == LUA_TTABLE &&
                    lua_getfield(L, -1, name) != LUA_TNIL;
        if (given && !luaL_testudata(L, -1, LB_MATERIAL))
            lf_error(L, 2, "materials", "'%s': lancer.Material expected, got %s", name,
                     luaL_typename(L, -1));
        if (given) {
            lua_replace(L, pal + 1);
            lua_settop(L, pal + 1);
        } else {
            lua_settop(L, pal);
            if (t)
                push_mtl_material(L, t, textures, path, warnings);
            else
                lua_pushboolean(L, 0);
        }
        lua_rawseti(L, pal, (lua_Integer)k + 1);
    }
    lua_setiuservalue(L, mesh, 2);
    lua_pop(L, 2);                             /* the libraries, the warnings */
}

static int w_load_obj(lua_State *L)
{
    static const char *const known[] = {"material", "materials", "textures", NULL};
    const char *path = luaL_checkstring(L, 1);
    int opts = 0, textures = 1;
    if (!lua_isnoneornil(L, 2)) {
        lf_open(L, 2, known);
        opts = 2;
        textures = lf_boolean(L, 2, "textures", 1);
        lua_getfield(L, 2, "materials");
        if (!lua_isnil(L, -1) && !lua_istable(L, -1))
            return lf_error(L, 2, "materials", "table from material name to lancer.Material "
                            "expected, got %s", luaL_typename(L, -1));
        lua_pop(L, 1);
        lf_udata(L, 2, "material", LB_MATERIAL, 0);
    } else {
        lua_settop(L, 1);
        lua_pushnil(L);
        lua_pushnil(L);
    }
    lb_ud_mesh *u = lua_newuserdatauv(L, sizeof *u, 3);
    u->m = NULL;
    luaL_setmetatable(L, LB_MESH);
    int mesh = lua_gettop(L);
    lua_pushvalue(L, -2);
    lua_setiuservalue(L, -2, 1);
    lc_error err;
    u->m = lc_mesh_load_obj(path, &err);
    if (!u->m)
        return luaL_argerror(L, 1, err.msg);     /* names 'load_obj', the file, the line */
    lb_charge(L);
    obj_palette(L, mesh, opts, textures, path);
    lua_settop(L, mesh);
    return 1;
}

static int w_mesh_add_vertices(lua_State *L)
{
    check_mesh(L, 1);
    lb_render_check_idle(L, "add_vertices");
    read_points(L, 2, 2, 1, POINTS, "vertices");
    lua_pushinteger(L, (lua_Integer)lc_mesh_vertex_count(check_mesh(L, 1)));
    lb_charge(L);
    return 1;
}

static int w_mesh_add_normals(lua_State *L)
{
    check_mesh(L, 1);
    lb_render_check_idle(L, "add_normals");
    read_points(L, 2, 2, 1, NORMALS, "normals");
    lb_charge(L);
    return 0;
}

static int w_mesh_add_uvs(lua_State *L)
{
    check_mesh(L, 1);
    lb_render_check_idle(L, "add_uvs");
    read_points(L, 2, 2, 1, UVS, "uvs");
    lb_charge(L);
    return 0;
}

static int w_mesh_add_faces(lua_State *L)
{
    check_mesh(L, 1);
    lb_render_check_idle(L, "add_faces");
    read_faces(L, 2, 2, 1, "faces", 0, 0);
    lua_pushinteger(L, (lua_Integer)lc_mesh_face_count(check_mesh(L, 1)));
    lb_charge(L);
    return 1;
}

static int w_mesh_free(lua_State *L)              /* __gc and __close */
{
    lb_ud_mesh *u = luaL_checkudata(L, 1, LB_MESH);
    lc_mesh_free(u->m);                          /* scenes keep their own hold */
    u->m = NULL;
    return 0;
}

static int w_mesh_tostring(lua_State *L)
{
    lb_ud_mesh *u = luaL_checkudata(L, 1, LB_MESH);
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
    } else if (strcmp(k, "materials") == 0) {          /* a copy: the mesh keeps its own */
        lua_newtable(L);
        if (lua_getiuservalue(L, 1, 2) == LUA_TTABLE)
            for (lua_Integer i = 1; i <= (lua_Integer)lua_rawlen(L, -1); i++) {
                lua_rawgeti(L, -1, i);
                lua_rawseti(L, -3, i);
            }
        lua_pop(L, 1);
    } else if (strcmp(k, "warnings") == 0) {           /* what load_obj had to leave out */
        lua_newtable(L);
        if (lua_getiuservalue(L, 1, 3) == LUA_TTABLE)
            for (lua_Integer i = 1; i <= (lua_Integer)lua_rawlen(L, -1); i++) {
                lua_rawgeti(L, -1, i);
                lua_rawseti(L, -3, i);
            }
        lua_pop(L, 1);
    } else if (strcmp(k, "material_names") == 0) {
        const lc_mesh *m = check_mesh(L, 1);
        size_t n = lc_mesh_material_slots(m);
        lua_createtable(L, (int)n, 0);
        for (size_t i = 0; i < n; i++) {
            const char *name = lc_mesh_slot_name(m, i);
            if (name)
                lua_pushstring(L, name);
            else
                lua_pushboolean(L, 0);
            lua_rawseti(L, -2, (lua_Integer)i + 1);
        }
    } else {
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
    }
    return 1;
}


void lb_mesh_register(lua_State *L)
{
    static const luaL_Reg mesh_meta[] = {
        {"__gc", w_mesh_free}, {"__close", w_mesh_free}, {"__tostring", w_mesh_tostring},
        {"__index", w_mesh_index}, {NULL, NULL}};
    static const luaL_Reg mesh_methods[] = {
        {"add_vertices", w_mesh_add_vertices}, {"add_faces", w_mesh_add_faces},
        {"add_normals", w_mesh_add_normals},
        {"add_uvs", w_mesh_add_uvs}, {"moved", lb_motion_moved}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"mesh", w_mesh}, {"triangle", w_triangle}, {"load_obj", w_load_obj},
        {NULL, NULL}};
    lb_class(L, LB_MESH, mesh_meta, mesh_methods);
    luaL_setfuncs(L, funcs, 0);
}
