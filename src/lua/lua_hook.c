/* lua_hook.c: the host hook, one function a host sets around render, explain, save. */
#include <lauxlib.h>
#include <lua.h>
#include "lua_binding.h"

/* lancer.set_host_hook(fn) sets the hook (nil removes it) and returns the
** one it replaces, or nil. With a hook set, scene:render, scene:explain
** and img:save check their arguments, then return what
**     fn(method, plain, self, ...)
** returns, where method is "render", "explain" or "save", self and ...
** are the arguments as checked (render's and explain's options a table,
** {} for none), and plain(self, ...) does the method without the hook and
** returns its results. The hook may change the arguments (the lancer
** command's --width), do something else instead (--check) or besides
** (the REPL's preview), or refuse by raising. Without a hook, nothing
** stands between a script and the core: what require "lancer" gives
** stock lua5.4.
**
** What plain fails at because of what the script asked (a render
** cancelled, a file that cannot be written, a pixel outside the image)
** is raised as if by the script's own call: the same message at the
** script's line, as with no hook. plain raises it as an error object
** whose tostring is the message, and the method re-raises it from its
** own frame when the hook lets it through (or passes it on with error(e)).
** Errors in plain's own arguments, the hook's doing, are ordinary ones. */

static const char hook_key = 'h';           /* registry[&hook_key]: the hook */

#define PLAIN_ERROR "lancer.PlainError"     /* {arg =, msg =}, raised by plain */

static int w_plain_error_tostring(lua_State *L)
{
    lua_getfield(L, 1, "msg");
    return 1;
}

int lb_hook_fail(lua_State *L, int plain, int arg, const char *msg)
{
    if (!plain)
        return arg ? luaL_argerror(L, arg, msg) : luaL_error(L, "%s", msg);
    lua_createtable(L, 0, 2);
    lua_pushinteger(L, arg);
    lua_setfield(L, -2, "arg");
    lua_pushstring(L, msg);
    lua_setfield(L, -2, "msg");
    luaL_setmetatable(L, PLAIN_ERROR);
    return lua_error(L);
}

int lb_hook_raise(lua_State *L, int plain, int arg, const lc_error *err)
{
    if (err->code != LC_EARG)
        return lb_hook_fail(L, plain, 0, err->msg);
    if (!err->field[0])
        return lb_hook_fail(L, plain, arg, err->msg);
    return lb_hook_fail(L, plain, arg, lua_pushfstring(L, "field '%s': %s", err->field,
                                                       err->msg));
}

int lb_hook_call(lua_State *L, const char *method, lua_CFunction plain, int nargs)
{
    if (lua_rawgetp(L, LUA_REGISTRYINDEX, &hook_key) != LUA_TFUNCTION) {
        lua_pop(L, 1);
        return -1;
    }
    int base = lua_gettop(L);
    lua_pushstring(L, method);
    lua_pushcfunction(L, plain);
    for (int i = 1; i <= nargs; i++)
        lua_pushvalue(L, i);
    if (lua_pcall(L, nargs + 2, LUA_MULTRET, 0) == LUA_OK)
        return lua_gettop(L) - base + 1;
    if (lua_type(L, -1) == LUA_TTABLE && lua_getmetatable(L, -1)) {
        luaL_getmetatable(L, PLAIN_ERROR);
        int ours = lua_rawequal(L, -1, -2);
        lua_pop(L, 2);
        if (ours) {                    /* raised again here: at the script's line */
            lua_getfield(L, -1, "arg");
            lua_getfield(L, -2, "msg");
            return lb_hook_fail(L, 0, (int)lua_tointeger(L, -2), lua_tostring(L, -1));
        }
    }
    return lua_error(L);
}

static int w_set_host_hook(lua_State *L)
{
    if (!lua_isnil(L, 1))
        luaL_checktype(L, 1, LUA_TFUNCTION);
    lua_settop(L, 1);
    lua_rawgetp(L, LUA_REGISTRYINDEX, &hook_key);
    lua_pushvalue(L, 1);
    lua_rawsetp(L, LUA_REGISTRYINDEX, &hook_key);
    return 1;
}

void lb_hook_register(lua_State *L)
{
    static const luaL_Reg error_meta[] = {
        {"__tostring", w_plain_error_tostring}, {NULL, NULL}};
    lb_class(L, PLAIN_ERROR, error_meta, NULL);
    lua_pushcfunction(L, w_set_host_hook);
    lua_setfield(L, -2, "set_host_hook");
}
