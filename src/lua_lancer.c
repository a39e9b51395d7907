/* lua_lancer.c: the Lua binding's module, a thin layer over lancer.h: require
** "lancer.core" gathers what the lua_*.c files register. */
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_lancer.h"
#include "lua_types.h"

void lancer_class(lua_State *L, const char *name, const luaL_Reg *meta,
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
    lua_newtable(L);
    objects_register(L);
    shapes_register(L);
    mesh_register(L);
    scene_register(L);
    render_register(L);
    explain_register(L);
    image_register(L);
    motion_register(L);
    scene_objects_register(L);
    hook_register(L);
    lua_pushstring(L, LC_VERSION);
    lua_setfield(L, -2, "version");
    lua_pushstring(L, "lancer " LC_VERSION);
    lua_setfield(L, -2, "_VERSION");
    return 1;
}
