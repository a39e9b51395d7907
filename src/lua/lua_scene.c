/* lua_scene.c: building scenes: the constructor, add, fields, transformed, count. */
#include <limits.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"
#include "base/clock.h"

/* A scene's user value holds its camera, materials and meshes: see LB_SC_CAMERA in
** lua_binding.h. */

lb_ud_scene *lb_scene_check(lua_State *L, int idx)
{
    lb_ud_scene *u = luaL_checkudata(L, idx, LB_SCENE);
    if (!u->s)
        luaL_argerror(L, idx, "lancer.Scene already freed");
    return u;
}

lc_scene *lb_scene_at(lua_State *L, int idx)
{
    lb_ud_scene *u = lb_scene_check(L, idx);
    if (u->rendering)            /* the core holds its lock: it would wait for itself */
        luaL_argerror(L, idx, "lancer.Scene is rendering: its render's on_pass cannot "
                      "change, render or query it");
    return u->s;
}

static void set_camera(lua_State *L, int sidx, int cidx, int arg, const char *field)
{
    lb_ud_camera *c = luaL_testudata(L, cidx, LB_CAMERA);
    if (!c) {
        const char *got = luaL_typename(L, cidx);
        if (luaL_getmetafield(L, cidx, "__name") == LUA_TSTRING)
            got = lua_tostring(L, -1);
        if (arg)
            lf_error(L, arg, field, "lancer.Camera expected, got %s", got);
        luaL_error(L, "scene.camera: lancer.Camera expected, got %s", got);
    }
    lc_error err;
    if (lc_scene_set_camera(lb_scene_at(L, sidx), &c->c, &err))
        luaL_error(L, "%s", err.msg);
    lua_getiuservalue(L, sidx, 1);
    lua_pushvalue(L, cidx);
    lua_rawseti(L, -2, LB_SC_CAMERA);
    lua_pop(L, 1);
}

/* The texture at tidx becomes the background of the scene at sidx: added
** to the scene (raising at arg) and kept in its user value to read back. */
static void set_background(lua_State *L, int sidx, int tidx, int arg)
{
    tidx = lua_absindex(L, tidx);
    int index = lb_texture_scene_index(L, sidx, tidx, arg, 0);
    lc_scene *s = lb_scene_at(L, sidx);
    lc_settings st = lc_scene_settings(s);
    st.background_texture = 1 + index;
    lc_error err;
    if (lc_scene_configure(s, &st, &err))
        luaL_error(L, "scene.background: %s", err.msg);
    lua_getiuservalue(L, sidx, 1);
    lua_pushvalue(L, tidx);
    lua_rawseti(L, -2, LB_SC_BACKGROUND);
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
    lua_getfield(L, 1, "background");
    int sky = lb_texture_check(L, -1);
    lua_pop(L, 1);
    if (!sky)
        st.background = lf_color(L, 1, "background", 0, st.background);
    st.ambient = lf_color(L, 1, "ambient", 0, st.ambient);
    st.max_depth = lf_integer(L, 1, "max_depth", 0, st.max_depth);  /* range: the core's */
    int has_camera = lf_present(L, 1, "camera");
    if (has_camera)
        lf_udata(L, 1, "camera", LB_CAMERA, 1); /* type check before allocating */

    lb_ud_scene *u = lua_newuserdatauv(L, sizeof *u, 1); /* before the core object */
    u->s = NULL;
    u->rendering = 0;
    luaL_setmetatable(L, LB_SCENE);
    int sidx = lua_gettop(L);
    lua_createtable(L, 5, 0);
    lua_newtable(L);
    lua_rawseti(L, -2, LB_SC_MATERIALS);
    lua_newtable(L);
    lua_rawseti(L, -2, LB_SC_MESHES);
    lua_newtable(L);
    lua_rawseti(L, -2, LB_SC_TEXTURES);
    lua_setiuservalue(L, sidx, 1);
    lc_error err;
    u->s = lc_scene_new(&err);
    u->mark = clock_seconds();
    if (!u->s)
        return luaL_error(L, "%s", err.msg);
    if (lc_scene_configure(u->s, &st, &err))
        return lf_raise(L, 1, &err);
    if (sky) {
        lua_getfield(L, 1, "background");
        set_background(L, sidx, lua_gettop(L), 1);
        lua_pop(L, 1);
    }
    if (has_camera) {
        lua_getfield(L, 1, "camera");
        set_camera(L, sidx, lua_gettop(L), 1, "camera");
        lua_pop(L, 1);
    }
    lua_settop(L, sidx);
    return 1;
}

static int w_scene_free(lua_State *L)              /* __gc and __close */
{
    lb_ud_scene *u = luaL_checkudata(L, 1, LB_SCENE);
    if (u->rendering)            /* not __gc: the render holds it on its stack */
        return luaL_error(L, "lancer.Scene is rendering: its render's on_pass cannot "
                          "close it");
    lc_scene_free(u->s);
    u->s = NULL;                                    /* safe to call twice */
    return 0;
}

/* The core index, in the scene at sidx, of the material at stack index midx
** (nil: the default). */
static int material_index(lua_State *L, int sidx, int midx, int arg)
{
    lc_error err;
    lua_getiuservalue(L, sidx, 1);
    int uv = lua_gettop(L);
    int index;
    if (lua_isnil(L, midx)) {
        if (lua_rawgeti(L, uv, LB_SC_DEFAULT) == LUA_TNUMBER) {
            index = (int)lua_tointeger(L, -1);
        } else {
            lc_material def = lc_material_default();
            index = lc_scene_add_material(lb_scene_at(L, sidx), &def, &err);
            if (index < 0)
                lf_raise(L, arg, &err);
            lua_pushinteger(L, index);
            lua_rawseti(L, uv, LB_SC_DEFAULT);
        }
    } else {
        lua_rawgeti(L, uv, LB_SC_MATERIALS);
        lua_pushvalue(L, midx);
        if (lua_rawget(L, -2) == LUA_TNUMBER) {
            index = (int)lua_tointeger(L, -1);
        } else {
            const lb_ud_material *m = luaL_checkudata(L, midx, LB_MATERIAL);
            lc_material mc = m->m;
            /* Its textures join the scene first (each once), named by index. */
                        if (lua_getiuservalue(L, midx, 1) == LUA_TTABLE)
                for (int k = 0; k < LC_SLOTS; k++) {
                    lua_pushstring(L, lc_slot_name((lc_slot)k));
                    if (lua_rawget(L, -2) == LUA_TUSERDATA)
                        mc.texture[k] = 1 + lb_texture_scene_index(L, sidx, -1, arg, 0);
                    lua_pop(L, 1);
                }
            lua_pop(L, 1);
            index = lc_scene_add_material(lb_scene_at(L, sidx), &mc, &err);
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

/* scene:add reads its arguments once, into a flat list (below), and
** adds from that list: a list read again could answer differently (its
** __index, or a finalizer changing it), and the metamethods it runs may
** close the scene or a mesh, so the adding re-checks every pointer. */

/* Lists and groups nest at most this deep in one scene:add: a list that
** holds itself is refused instead of filling the C stack. */
#define MAX_NESTING 64

/* The flat list, a table at stack index `at` holding n values: runs of
** objects (shape, light and mesh userdata) each after a marker: an integer
** i, the objects come from argument i, not moved; false, not moved; a
** transform (a plain userdata holding an lc_transform), moved by it. */
typedef struct {
    int         at;
    lua_Integer n;
    int         meshes;     /* how many of the objects are meshes */
} flat_list;

/* Appends the value at the top to the list, popping it. */
static void flat_append(lua_State *L, flat_list *fl)
{
    lua_rawseti(L, fl->at, ++fl->n);
}

/* Appends the transform marker for xf (0: none). */
static void flat_mark(lua_State *L, flat_list *fl, int xf)
{
    if (xf)
        lua_pushvalue(L, xf);
    else
        lua_pushboolean(L, 0);
    flat_append(L, fl);
}

static const lc_transform *xf_at(lua_State *L, int xf)
{
    return xf ? lua_touserdata(L, xf) : NULL;
}

static void element_error(lua_State *L, int arg, lua_Integer elem, const char *msg)
{
    if (elem)
        lua_pushfstring(L, "element %I: %s", elem, msg);
    else
        lua_pushstring(L, msg);
    luaL_argerror(L, arg, lua_tostring(L, -1));
}

/* The mesh userdata at idx, raising at arg when it was freed. */
static lc_mesh *mesh_at(lua_State *L, int idx, int arg)
{
    lc_mesh *m = ((lb_ud_mesh *)lua_touserdata(L, idx))->m;
    if (!m)
        luaL_argerror(L, arg, "lancer.Mesh already freed");
    return m;
}

/* Checks that the value at idx is a shape, a light, a mesh, a group or an
** array of them that can be moved by the transform at xf (0: not moved),
** and appends what it holds to flat, so that a bad call to add leaves the
** scene as it was. Arrays are read as a script reads them (# and [i]),
** once; a group's members are its own copy, read raw. */
static void flatten(lua_State *L, int idx, int arg, int depth, lua_Integer elem, int xf,
                    flat_list *fl)
{
    idx = lua_absindex(L, idx);
    luaL_checkstack(L, 8, "scene:add: lists nested too deep");   /* 3 a level */
    lc_error err;
    const lc_transform *t = xf_at(L, xf);
    lb_ud_shape *sh = luaL_testudata(L, idx, LB_SHAPE);
    lb_ud_light *li = sh ? NULL : luaL_testudata(L, idx, LB_LIGHT);
    lb_ud_mesh *me = sh || li ? NULL : luaL_testudata(L, idx, LB_MESH);
    if (!sh && !li && !me && luaL_testudata(L, idx, LB_CSG)) {
        /* Described and checked as it will be added: a leaf the transform
        ** carries out of range, a mesh left open since, is refused now. */
        int top = lua_gettop(L);
        size_t n = lb_csg_describe(L, idx, t, arg);
        lc_csg_node *nodes = lua_touserdata(L, top + 1);
        for (size_t k = 0; k < n; k++)
            if (nodes[k].op == LC_CSG_MESH) {
                lua_rawgeti(L, top + 3, (lua_Integer)k + 1);
                nodes[k].mesh = mesh_at(L, -1, arg);
                lua_pop(L, 1);
            }
        if (lc_csg_check(nodes, n, &err))
            element_error(L, arg, elem, err.msg);
        lua_settop(L, top);
        fl->meshes++;               /* its meshes are checked again before adding */
        lua_pushvalue(L, idx);
        flat_append(L, fl);
        return;
    }
    if (sh) {
        lc_shape out;
        if (t && lc_shape_transform(&sh->s, t, &out, &err))
            element_error(L, arg, elem, err.msg);
    } else if (li) {
        lb_ud_light l;
        if (t && !lb_light_moved(li, t, &l, &err))
            element_error(L, arg, elem, err.msg);
    } else if (me) {
        if (!me->m)
            luaL_argerror(L, arg, "lancer.Mesh already freed");
        if (t && lc_transform_check(t, &err))
            element_error(L, arg, elem, err.msg);
    }
    if (sh || li || me) {
        fl->meshes += me != NULL;
        lua_pushvalue(L, idx);
        flat_append(L, fl);
        return;
    }
    int group = luaL_testudata(L, idx, LB_GROUP) != NULL;
    if ((group || lua_type(L, idx) == LUA_TTABLE) && depth >= MAX_NESTING)
        element_error(L, arg, elem, "lists and groups nest at most 64 deep (does a "
                      "list hold itself?)");
    if (group) {
        const lb_ud_group *g = lua_touserdata(L, idx);
        lc_transform *moved = lua_newuserdatauv(L, sizeof *moved, 0);
        *moved = t ? lc_transform_compose(t, &g->t) : g->t;
        int gxf = lua_gettop(L);
        flat_mark(L, fl, gxf);
        lua_getiuservalue(L, idx, 1);
        lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_rawgeti(L, -1, i);
            flatten(L, -1, arg, depth + 1, elem ? elem : i, gxf, fl);
            lua_pop(L, 1);
        }
        lua_pop(L, 2);
        flat_mark(L, fl, xf);
        return;
    }
    if (lua_type(L, idx) == LUA_TTABLE) {
        lua_Integer n = luaL_len(L, idx);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_geti(L, idx, i);
            flatten(L, -1, arg, depth + 1, i, xf, fl);
            lua_pop(L, 1);
        }
        return;
    }
    const char *got = luaL_typename(L, idx);
    if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING)
        got = lua_tostring(L, -1);
    if (elem)
        lua_pushfstring(L, "element %I: shape, mesh, light, group, CSG object or array "
                        "of them expected, got %s", elem, got);
    else
        lua_pushfstring(L, "shape, mesh, light, group, CSG object or array of them "
                        "expected, got %s", got);
    luaL_argerror(L, arg, lua_tostring(L, -1));
}

/* Adds the CSG object at idx to the scene at 1, placed by t (or not):
** its description, each leaf's material found or added, then its meshes'
** core pointers and the scene's, fetched after everything that may run Lua
** code, right before the core call. */
static void add_csg(lua_State *L, int idx, int arg, const lc_transform *t)
{
    lc_error err;
    int top = lua_gettop(L);
    size_t n = lb_csg_describe(L, idx, t, arg);
    int buf = top + 1, mats = top + 2, meshes = top + 3;
    for (size_t k = 0; k < n; k++) {
        lc_csg_node *nd = (lc_csg_node *)lua_touserdata(L, buf) + k;
        if (nd->op != LC_CSG_SHAPE && nd->op != LC_CSG_MESH)
            continue;
        lua_rawgeti(L, mats, (lua_Integer)k + 1);
        int mat = material_index(L, 1, lua_gettop(L), arg);
        lua_pop(L, 1);
        ((lc_csg_node *)lua_touserdata(L, buf))[k].material = mat;
    }
    lua_getiuservalue(L, 1, 1);                    /* top + 4: for listing, removal */
    luaL_checkstack(L, 4, "scene:add");
    lc_csg_node *nodes = lua_touserdata(L, buf);
    for (size_t k = 0; k < n; k++)
        if (nodes[k].op == LC_CSG_MESH) {
            lua_rawgeti(L, meshes, (lua_Integer)k + 1);
            nodes[k].mesh = mesh_at(L, -1, arg);
            lua_pop(L, 1);
        }
    int id = lc_scene_add_csg(lb_scene_at(L, 1), nodes, n, &err);
    if (id < 0)
        lf_raise(L, arg, &err);
    /* The scene holds the meshes now: naming them may run the collector. */
    lua_rawgeti(L, top + 4, LB_SC_MESHES);
    for (size_t k = 0; k < n; k++) {
        if (lua_rawgeti(L, meshes, (lua_Integer)k + 1) == LUA_TNIL) {
            lua_pop(L, 1);
            continue;
        }
        lua_pushlightuserdata(L, ((lb_ud_mesh *)lua_touserdata(L, -1))->m);
        lua_insert(L, -2);
        lua_rawset(L, -3);
    }
    lua_pop(L, 1);
    if (lua_rawgeti(L, top + 4, LB_SC_CSGS) != LUA_TTABLE) {
        lua_pop(L, 1);
        lua_newtable(L);
        lua_pushvalue(L, -1);
        lua_rawseti(L, top + 4, LB_SC_CSGS);
    }
    lua_pushvalue(L, idx);
    lua_rawseti(L, -2, id);
    lua_settop(L, top);
}

/* Adds the object at idx (checked by flatten) to the scene at 1, moved by
** the transform at xf (0: as it is). */
/* Materials a mesh's faces may name through their slots, from Lua: enough
** for any OBJ file seen; more take lc_scene_add_mesh_materials from C. */
#define PALETTE_MAX 4096

/* Adds the shape sh, the userdata at idx, moved by t (NULL: as it is), to
** the scene at 1, whose userdata is u: its core pointer is read again after
** the material's lookup, which may run Lua code (lb_scene_at's comment). */
static void add_shape(lua_State *L, lb_ud_scene *u, const lb_ud_shape *sh, int idx,
                      int arg, const lc_transform *t)
{
    lc_error err;
    lc_shape moved = sh->s;
    if (t && lc_shape_transform(&sh->s, t, &moved, &err))
        lf_raise(L, arg, &err);
    lua_getiuservalue(L, idx, 1);
    int mat = material_index(L, 1, lua_gettop(L), arg);
    lua_pop(L, 1);
    if (!u->s)
        luaL_argerror(L, 1, "lancer.Scene already freed");     /* as lb_scene_check */
    if (u->rendering)                                           /* as lb_scene_at */
        luaL_argerror(L, 1, "lancer.Scene is rendering: its render's on_pass cannot "
                      "change, render or query it");
    if (lc_scene_add_shape(u->s, &moved, mat, &err) < 0)
        lf_raise(L, arg, &err);
}

static void add_one(lua_State *L, int idx, int arg, int xf)
{
    lc_error err;
    const lc_transform *t = xf_at(L, xf);
    lb_ud_shape *sh = luaL_testudata(L, idx, LB_SHAPE);
    if (sh) {
        add_shape(L, lua_touserdata(L, 1), sh, idx, arg, t);
        return;
    }
    lb_ud_light *li = luaL_testudata(L, idx, LB_LIGHT);
    if (li) {
        lb_ud_light l = *li;
        if (t && !lb_light_moved(li, t, &l, &err))
            lf_raise(L, arg, &err);
        if (lb_light_add(lb_scene_at(L, 1), &l, &err) < 0)
            lf_raise(L, arg, &err);
        return;
    }
    if (luaL_testudata(L, idx, LB_CSG)) {
        add_csg(L, idx, arg, t);
        return;
    }
    lua_getiuservalue(L, idx, 1);                  /* a mesh */
    int mat = material_index(L, 1, lua_gettop(L), arg);
    lua_pop(L, 1);
    /* A material per face slot: each slot's material in the scene. */
    int slots[PALETTE_MAX];
    int nslots = 0;
    if (lua_getiuservalue(L, idx, 2) == LUA_TTABLE) {
        int pal = lua_gettop(L);
        lua_Integer n = (lua_Integer)lua_rawlen(L, pal);
        if (n > PALETTE_MAX)
            lf_error(L, arg, NULL, "a mesh of %lld materials: at most %d", (long long)n,
                     PALETTE_MAX);
        for (lua_Integer k = 1; k <= n; k++) {
            lua_rawgeti(L, pal, k);
            if (lua_type(L, -1) == LUA_TBOOLEAN)     /* false: the mesh's own material */
                slots[nslots++] = mat;
            else
                slots[nslots++] = material_index(L, 1, lua_gettop(L), arg);
            lua_pop(L, 1);
        }
    }
    lua_pop(L, 1);
    lua_getiuservalue(L, 1, 1);                    /* so scene:objects() can name it */
    lua_rawgeti(L, -1, LB_SC_MESHES);
    lc_scene *s = lb_scene_at(L, 1);
    lc_mesh *m = mesh_at(L, idx, arg);
    if ((nslots ? lc_scene_add_mesh_materials(s, m, t, slots, (size_t)nslots, &err)
         : t ? lc_scene_add_mesh_moved(s, m, t, mat, &err)
             : lc_scene_add_mesh(s, m, mat, &err)) < 0)
        lf_raise(L, arg, &err);
    lua_pushlightuserdata(L, m);
    lua_pushvalue(L, idx);
    lua_rawset(L, -3);
    lua_pop(L, 2);
}

/* scene:add's upvalues: the metatables its fast path tests for. */
#define UP_SHAPE lua_upvalueindex(1)
#define UP_SCENE lua_upvalueindex(2)

static int w_scene_add(lua_State *L)
{
    lb_ud_scene *u = lb_udata_is(L, 1, UP_SCENE);
    if (!u || !u->s)
        u = lb_scene_check(L, 1);                  /* raises */
    int n = lua_gettop(L);
    if (n < 2)
        return luaL_argerror(L, 2, "shape, mesh, light, group, CSG object or array of "
                             "them expected, got no value");
    /* One shape alone, the common call (a script adding a million spheres
    ** one at a time): nothing to flatten, move or re-check, as nothing runs
    ** Lua code before add_shape fetches the scene again; the list would
    ** cost a table and its growth per call, a third of the call's time. */
    const lb_ud_shape *one = n == 2 ? lb_udata_is(L, 2, UP_SHAPE) : NULL;
    if (one) {
        add_shape(L, u, one, 2, 2, NULL);
        lua_settop(L, 1);
        lb_charge(L);
        return 1;
    }
    lua_newtable(L);
    int flat = n + 1;
    flat_list fl = {flat, 0, 0};
    for (int i = 2; i <= n; i++) {
        lua_pushinteger(L, i);
        flat_append(L, &fl);
        flatten(L, i, i, 0, 0, 0, &fl);
    }
    /* What the reading ran may have closed a mesh or the scene: check
    ** them all before adding anything. */
    lua_Integer len = fl.n;
    int arg = 2;
    for (lua_Integer k = 1; fl.meshes && k <= len; k++) {
        if (lua_rawgeti(L, flat, k) == LUA_TNUMBER)
            arg = (int)lua_tointeger(L, -1);
        else if (luaL_testudata(L, -1, LB_MESH))
            mesh_at(L, -1, arg);
        else if (luaL_testudata(L, -1, LB_CSG)) {
            int at = lua_gettop(L);
            size_t nodes = lb_csg_describe(L, at, NULL, arg);
            for (size_t i = 0; i < nodes; i++)
                if (lua_rawgeti(L, at + 3, (lua_Integer)i + 1) == LUA_TNIL)
                    lua_pop(L, 1);
                else
                    mesh_at(L, -1, arg), lua_pop(L, 1);
            lua_settop(L, at);
        }
        lua_pop(L, 1);
    }
    lb_scene_check(L, 1);
    lua_pushnil(L);                                /* flat + 1: the transform */
    int xf = 0;
    for (lua_Integer k = 1; k <= len; k++) {
        int type = lua_rawgeti(L, flat, k);        /* flat + 2 */
        if (type == LUA_TNUMBER) {
            arg = (int)lua_tointeger(L, -1);
            xf = 0;
        } else if (type == LUA_TBOOLEAN) {
            xf = 0;
        } else if (lua_getmetatable(L, -1)) {      /* a shape, light or mesh */
            lua_pop(L, 1);
            add_one(L, flat + 2, arg, xf);
        } else {                                   /* a transform marker */
            lua_copy(L, -1, flat + 1);
            xf = flat + 1;
        }
        lua_settop(L, flat + 1);
    }
    lua_settop(L, 1);
    lb_charge(L);
    return 1;
}

/* scene:transformed(scale [, offset]): the copy lc_scene_transformed makes,
** sharing this scene's material table (same indices) with a moved camera. */
static int w_scene_transformed(lua_State *L)
{
    lb_scene_check(L, 1);
    double scale = luaL_checknumber(L, 2);
    lc_vec3 off = {0, 0, 0};
    char why[160];
    if (!lua_isnoneornil(L, 3) && !lf_to_vec3(L, 3, &off, why, sizeof why))
        return luaL_argerror(L, 3, why);
    lb_ud_scene *c = lua_newuserdatauv(L, sizeof *c, 1);   /* before the copy */
    c->s = NULL;
    c->rendering = 0;
    c->mark = clock_seconds();
    luaL_setmetatable(L, LB_SCENE);
    int ci = lua_gettop(L);
    lua_createtable(L, 4, 0);
    lua_getiuservalue(L, 1, 1);
    lua_rawgeti(L, -1, LB_SC_MATERIALS);
    lua_rawseti(L, -3, LB_SC_MATERIALS);
    lua_rawgeti(L, -1, LB_SC_DEFAULT);
    lua_rawseti(L, -3, LB_SC_DEFAULT);
    lua_rawgeti(L, -1, LB_SC_MESHES);      /* instances keep their meshes */
    lua_rawseti(L, -3, LB_SC_MESHES);
    lua_rawgeti(L, -1, LB_SC_TEXTURES);    /* the copy keeps their order */
    lua_rawseti(L, -3, LB_SC_TEXTURES);
    lua_rawgeti(L, -1, LB_SC_BACKGROUND);
    lua_rawseti(L, -3, LB_SC_BACKGROUND);
    lua_pop(L, 1);
    lua_setiuservalue(L, ci, 1);
    lc_error err;
    /* The offset's reads and the allocations above may have run Lua code
    ** (metamethods, finalizers) that closed the scene: fetch it now. */
    c->s = lc_scene_transformed(lb_scene_at(L, 1), scale, off, &err);
    if (!c->s)
        return lf_raise(L, 2, &err);
    lc_camera moved;
    if (lc_scene_camera(c->s, &moved)) {
        lb_camera_push(L, &moved);
        lua_getiuservalue(L, ci, 1);
        lua_insert(L, -2);
        lua_rawseti(L, -2, LB_SC_CAMERA);
        lua_pop(L, 1);
    }
    lua_settop(L, ci);
    lb_charge(L);
    return 1;
}

static int w_scene_count(lua_State *L)
{
    const lc_scene *s = lb_scene_at(L, 1);
    lua_pushinteger(L, (lua_Integer)lc_scene_shape_count(s));
    lua_pushinteger(L, (lua_Integer)lc_scene_light_count(s));
    return 2;
}
static int w_scene_tostring(lua_State *L)
{
    lb_ud_scene *u = luaL_checkudata(L, 1, LB_SCENE);
    if (!u->s)
        lua_pushstring(L, "lancer.Scene (freed)");
    else
        lua_pushfstring(L, "lancer.Scene (%d shapes, %d lights)",
                        (int)lc_scene_shape_count(u->s), (int)lc_scene_light_count(u->s));
    return 1;
}

/* __index's upvalues: the scene metatable and its methods table. */
#define UP_META    lua_upvalueindex(1)
#define UP_METHODS lua_upvalueindex(2)

static int w_scene_index(lua_State *L)
{
    /* A method first, the common look-up (scene:add a million times): by
    ** the key's own string, raw, in the table held here, a sixth of the
    ** by-name look-ups below (callgrind). No method shares a field's name,
    ** so the answer is the one the fields-first order gives. */
    if (lb_udata_is(L, 1, UP_META)) {
        lua_pushvalue(L, 2);
        if (lua_rawget(L, UP_METHODS) != LUA_TNIL)
            return 1;
        lua_pop(L, 1);
    }
    lb_ud_scene *u = luaL_checkudata(L, 1, LB_SCENE);
    const char *k = luaL_checkstring(L, 2);
    if (!u->s) {             /* closed: methods still resolve, and raise there */
        luaL_getmetafield(L, 1, "methods");
        lua_getfield(L, -1, k);
        return 1;
    }
    lc_settings st = lc_scene_settings(u->s);
    if (strcmp(k, "camera") == 0) {
        lua_getiuservalue(L, 1, 1);
        lua_rawgeti(L, -1, LB_SC_CAMERA);
    } else if (strcmp(k, "background") == 0 && st.background_texture > 0) {
        lua_getiuservalue(L, 1, 1);
        lua_rawgeti(L, -1, LB_SC_BACKGROUND);
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
    lb_scene_check(L, 1);
    const char *k = luaL_checkstring(L, 2);
    char why[200];
    lc_color c = {0, 0, 0};
    lua_Integer d = 0;
    if (strcmp(k, "camera") == 0) {
        set_camera(L, 1, 3, 0, k);
        return 0;
    } else if (strcmp(k, "background") == 0 && lb_texture_check(L, 3)) {
        set_background(L, 1, 3, 3);
        return 0;
    } else if (strcmp(k, "background") == 0 || strcmp(k, "ambient") == 0) {
        if (!lf_to_color(L, 3, &c, why, sizeof why))
            return luaL_error(L, "scene.%s: %s%s", k, why,
                              k[0] == 'b' ? " (or a texture over directions)" : "");
    } else if (strcmp(k, "max_depth") == 0) {
        int isint;
        d = lua_tointegerx(L, 3, &isint);
        /* Whether it converts to an int; the range is the core's to check. */
        if (lua_type(L, 3) != LUA_TNUMBER || !isint || d < INT_MIN || d > INT_MAX)
            return luaL_error(L, "scene.max_depth: integer in [0, %d] expected, got %s",
                              LC_MAX_DEPTH, luaL_tolstring(L, 3, NULL));
    } else {
        return luaL_error(L, "scene.%s: unknown field; settable fields are camera, "
                          "background, ambient, max_depth", k);
    }
    /* Reading the colour may have run a script's metamethods, which may
    ** have closed the scene or changed its settings: read them now. */
    lc_scene *s = ((lb_ud_scene *)lua_touserdata(L, 1))->s;
    if (!s)
        return luaL_error(L, "scene.%s: lancer.Scene already freed", k);
    lc_settings st = lc_scene_settings(s);
    if (k[0] == 'm') {
        st.max_depth = (int)d;
    } else if (k[0] == 'b') {
        st.background = c;
        st.background_texture = 0;          /* a colour again */
    } else {
        st.ambient = c;
    }
    lc_error err;
    if (lc_scene_configure(s, &st, &err))
        return luaL_error(L, "scene.%s: %s", k, err.msg);
    return 0;
}

void lb_scene_register(lua_State *L)
{
    static const luaL_Reg scene_meta[] = {
        {"__gc", w_scene_free}, {"__close", w_scene_free}, {"__tostring", w_scene_tostring},
        {"__newindex", w_scene_newindex}, {NULL, NULL}};
    static const luaL_Reg scene_methods[] = {
        {"count", w_scene_count},
        {"transformed", w_scene_transformed}, {NULL, NULL}};
    lb_class(L, LB_SCENE, scene_meta, scene_methods);
    luaL_getmetatable(L, LB_SCENE);
    lua_getfield(L, -1, "methods");
    luaL_getmetatable(L, LB_SHAPE);                /* add, with its upvalues */
    lua_pushvalue(L, -3);
    lua_pushcclosure(L, w_scene_add, 2);
    lua_setfield(L, -2, "add");
    lua_pushvalue(L, -2);                          /* __index, with its upvalues */
    lua_pushvalue(L, -2);
    lua_pushcclosure(L, w_scene_index, 2);
    lua_setfield(L, -3, "__index");
    lua_pop(L, 2);
    lua_pushcfunction(L, w_scene);
    lua_setfield(L, -2, "scene");
}
