/* lua_lancer.h: the Lua binding's entry point, for hosts that embed it. */
#ifndef LUA_LANCER_H
#define LUA_LANCER_H
#include <lua.h>
int luaopen_lancer_core(lua_State *L);   /* the C part of require "lancer" */
#endif
