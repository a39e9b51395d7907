/* lua_scene_objects.c: scene:objects() lists what was added, scene:remove() takes it out. */
#include <stdlib.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* Pushes a table from the core's material index to its material userdata
** (the inverse of the scene's LB_SC_MATERIALS; the default material is absent). */
static void push_materials(lua_State *L, int sidx)
{
    lua_newtable(L);
    lua_getiuservalue(L, sidx, 1);
    lua_rawgeti(L, -1, LB_SC_MATERIALS);
    lua_pushnil(L);
    while (lua_next(L, -2)) {                 /* material -> index */
        lua_pushvalue(L, -2);
        lua_rawseti(L, -6, lua_tointeger(L, -2));
        lua_pop(L, 1);
    }
    lua_pop(L, 2);
}

/* Pushes the entry for o: {id, kind, object, material, transform}; a CSG
** object's kind is its root's operation. */
static void push_entry(lua_State *L, const lc_object *o, int mats, int uv)
{
    lua_createtable(L, 0, 5);
    int e = lua_gettop(L);
    luaL_setmetatable(L, LB_ENTRY);
    lua_pushinteger(L, (lua_Integer)o->id + 1);    /* Lua counts from 1 */
    lua_setfield(L, e, "id");
    if (o->material >= 0)
        lua_rawgeti(L, mats, o->material);   /* nil for the default material */
    else
        lua_pushnil(L);
    int mat = lua_gettop(L);
    switch (o->kind) {
    case LC_OBJECT_SHAPE:
        lua_pushstring(L, lc_shape_kind_name(o->shape.kind));
        lua_setfield(L, e, "kind");
        lb_shape_push(L, &o->shape, mat);
        break;
    case LC_OBJECT_MESH:
        lua_pushliteral(L, "mesh");
        lua_setfield(L, e, "kind");
        if (o->moved) {
            lb_ud_transform *t = lua_newuserdatauv(L, sizeof *t, 0);
            t->t = o->transform;
            luaL_setmetatable(L, LB_TRANSFORM);
            lua_setfield(L, e, "transform");
        }
        lua_rawgeti(L, uv, LB_SC_MESHES);
        lua_pushlightuserdata(L, o->mesh);
        lua_rawget(L, -2);
        lua_remove(L, -2);
        break;
    case LC_OBJECT_CSG:
        lua_pushstring(L, lc_csg_op_name(o->csg[0].op));
        lua_setfield(L, e, "kind");
        lua_rawgeti(L, uv, LB_SC_MESHES);
        lb_csg_push_listed(L, o->csg, o->csg_nodes, mats, -1);
        lua_remove(L, -2);
        break;
    default: {
        lb_ud_light l = lb_light_of(o);
        lua_pushstring(L, lb_light_kind_name(o->kind));
        lua_setfield(L, e, "kind");
        lb_light_push(L, &l);
        break;
    }
    }
    lua_setfield(L, e, "object");
    lua_setfield(L, e, "material");
}

/* scene:objects(): every object in the order added, each a table
** {id =, kind =, object =, material =, transform =} that prints on one line.
** Ids count from 1 (the core's from 0), and stay with their object. */
static int w_scene_objects(lua_State *L)
{
    size_t n = lc_scene_object_count(lb_scene_at(L, 1));
    lc_object *objs = lua_newuserdatauv(L, (n + 1) * sizeof *objs, 0);  /* Lua frees it */
    n = lc_scene_objects(lb_scene_at(L, 1), objs, n); /* after it: it may run Lua */
    push_materials(L, 1);
    int mats = lua_gettop(L);
    lua_getiuservalue(L, 1, 1);
    int uv = lua_gettop(L);
    lua_createtable(L, (int)n, 0);
    for (size_t i = 0; i < n; i++) {
        push_entry(L, &objs[i], mats, uv);
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
    return 1;
}

/* Whether the scene's object o is the value at idx (a shape, light or mesh). */
static int matches(lua_State *L, int idx, const lc_object *o)
{
    lb_ud_shape *sh = luaL_testudata(L, idx, LB_SHAPE);
    if (sh)
        return o->kind == LC_OBJECT_SHAPE && lb_shape_match(&sh->s, &o->shape);
    lb_ud_light *li = luaL_testudata(L, idx, LB_LIGHT);
    if (li)
        return lb_light_match(li, o);
    lb_ud_mesh *me = luaL_testudata(L, idx, LB_MESH);
    return me && o->kind == LC_OBJECT_MESH && me->m == o->mesh;
}

/* scene:remove(x): x is an id, an entry of scene:objects(), or the shape,
** light, mesh or CSG object that was added, when it was added once. */
static int w_scene_remove(lua_State *L)
{
    lb_scene_check(L, 1);
    lc_error err;
    int id = -1;
    if (lua_type(L, 2) == LUA_TTABLE) {
        lua_getfield(L, 2, "id");                  /* may run a script's __index */
        if (!lua_isinteger(L, -1))
            return luaL_argerror(L, 2, "an entry of scene:objects() (with an integer id) "
                                 "expected");
        lua_replace(L, 2);
    }
    if (lua_type(L, 2) == LUA_TNUMBER) {
        if (!lua_isinteger(L, 2))
            return luaL_argerror(L, 2, lua_pushfstring(L, "integer id expected, got %s",
                                                       luaL_tolstring(L, 2, NULL)));
        lua_Integer i = lua_tointeger(L, 2);
        id = i < 1 || i > 0x7fffffff ? -1 : (int)(i - 1);
        if (id < 0)
            return luaL_argerror(L, 2, lua_pushfstring(L, "no object %I in this scene", i));
    } else if (luaL_testudata(L, 2, LB_CSG)) {
        /* The ids it was added under (as itself, not inside a group). */
        int found = 0, other = -1;
        lua_getiuservalue(L, 1, 1);
        if (lua_rawgeti(L, -1, LB_SC_CSGS) == LUA_TTABLE) {
            lua_pushnil(L);
            while (lua_next(L, -2)) {
                lc_object o;
                int k = (int)lua_tointeger(L, -2);
                if (lua_rawequal(L, -1, 2) &&
                    lc_scene_object(lb_scene_at(L, 1), k, &o, &err) == LC_OK) {
                    if (found == 0 || k < id) {
                        other = found ? id : other;
                        id = k;
                    } else if (found == 1 || k < other) {
                        other = k;
                    }
                    found++;
                }
                lua_pop(L, 1);
            }
        }
        if (found == 0)
            return luaL_argerror(L, 2, "this CSG object is not in this scene (as added "
                                 "itself: remove one placed by a group by id)");
        if (found > 1)
            return luaL_argerror(L, 2, lua_pushfstring(L, "this CSG object was added "
                                                       "%d times (ids %d, %d%s): remove "
                                                       "one by id", found, id + 1,
                                                       other + 1, found > 2 ? ", ..." :
                                                       ""));
    } else if (luaL_testudata(L, 2, LB_SHAPE) || luaL_testudata(L, 2, LB_LIGHT) ||
               luaL_testudata(L, 2, LB_MESH)) {
        const char *what = luaL_tolstring(L, 2, NULL);   /* may run a __tostring */
        size_t n = lc_scene_object_count(lb_scene_at(L, 1));
        lc_object *objs = lua_newuserdatauv(L, (n + 1) * sizeof *objs, 0);
        n = lc_scene_objects(lb_scene_at(L, 1), objs, n);
        int found = 0, other = -1;
        for (size_t i = 0; i < n; i++)
            if (matches(L, 2, &objs[i])) {
                if (found == 0)
                    id = objs[i].id;
                else if (found == 1)
                    other = objs[i].id;
                found++;
            }
        if (found == 0)
            return luaL_argerror(L, 2, lua_pushfstring(L, "%s is not in this scene", what));
        if (found > 1)
            return luaL_argerror(L, 2, lua_pushfstring(L, "%s was added %d times (ids %d, "
                                                       "%d%s): remove one by id", what,
                                                       found, id + 1, other + 1,
                                                       found > 2 ? ", ..." : ""));
    } else {
        return luaL_argerror(L, 2, lua_pushfstring(L, "id, entry of scene:objects(), "
                                                   "shape, light, mesh or CSG object "
                                                   "expected, got %s",
                                                   luaL_typename(L, 2)));
    }
    if (lc_scene_remove(lb_scene_at(L, 1), id, &err))
        return luaL_argerror(L, 2, lua_pushfstring(L, "no object %d in this scene (%s)",
                                                   id + 1, strstr(err.msg, "removed") ?
                                                   "it was removed" : "never added"));
    lua_settop(L, 1);
    return 1;
}

static int w_entry_tostring(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_settop(L, 1);
    lua_getfield(L, 1, "id");                 /* 2 */
    lua_getfield(L, 1, "object");             /* 3 */
    lua_getfield(L, 1, "transform");          /* 4 */
    lua_getfield(L, 1, "material");           /* 5 */
    luaL_Buffer b;
    luaL_buffinit(L, &b);                     /* may push: absolute indices below */
    lua_pushfstring(L, "#%I ", lua_tointeger(L, 2));
    luaL_addvalue(&b);
    luaL_tolstring(L, 3, NULL);
    luaL_addvalue(&b);
    if (!lua_isnil(L, 4)) {
        luaL_addstring(&b, " moved by ");
        luaL_tolstring(L, 4, NULL);
        luaL_addvalue(&b);
    }
    if (!lua_isnil(L, 5)) {
        luaL_addstring(&b, ", material ");
        luaL_tolstring(L, 5, NULL);
        luaL_addvalue(&b);
    }
    luaL_pushresult(&b);
    return 1;
}

void lb_scene_objects_register(lua_State *L)
{
    static const luaL_Reg methods[] = {
        {"objects", w_scene_objects}, {"remove", w_scene_remove}, {NULL, NULL}};
    static const luaL_Reg entry_meta[] = {{"__tostring", w_entry_tostring}, {NULL, NULL}};
    luaL_getmetatable(L, LB_SCENE);
    lua_getfield(L, -1, "methods");
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
    lb_class(L, LB_ENTRY, entry_meta, NULL);
}
