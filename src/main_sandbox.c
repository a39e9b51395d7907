/* main_sandbox.c: what the lancer command refuses to run: binary chunks,
** wherever they would be loaded (load, loadfile, dofile, require); and its
** host hook around renders, for the time cap. */
#include <string.h>

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "lua_lancer.h"
#include "main.h"

/* ---- Wrappers -------------------------------------------------------------- */

/* A wrapper is a C closure: upvalue 1 the C function it stands for, which it
** calls directly, in its own frame, after its check, so that errors name
** the function and the script's line as the original's would. Only
** functions without upvalues of their own can be wrapped so. */
#define ORIGINAL(L) (lua_tocfunction(L, lua_upvalueindex(1)))

/* Replaces the function on top with its wrapper f. */
static void push_wrapper(lua_State *L, lua_CFunction f)
{
    if (!lua_tocfunction(L, -1) || lua_getupvalue(L, -1, 1) != NULL)
        luaL_error(L, "cannot wrap a function that is not Lua's or lancer's");
    lua_pushcclosure(L, f, 1);
}

static void wrap(lua_State *L, int t, const char *name, lua_CFunction f)
{
    t = lua_absindex(L, t);
    lua_getfield(L, t, name);
    push_wrapper(L, f);
    lua_setfield(L, t, name);
}

/* ---- Chunks: text only ----------------------------------------------------- */

/* Lua 5.4 does not verify bytecode: a crafted binary chunk can read and
** write memory at will. So no binary chunk is loaded unless the command
** is given --allow-bytecode. */
static const char BINARY_LUA[] = "attempt to load a binary chunk";
static const char REFUSED[] = "binary chunks are refused (Lua does not verify them; "
                              "lancer --allow-bytecode allows them)";

/* After load or loadfile: their failure message, made to say why. */
static int loaded(lua_State *L, int n)
{
    const char *msg = lua_tostring(L, -1);
    if (n == 2 && lua_isnil(L, -2) && msg && strstr(msg, BINARY_LUA)) {
        lua_pop(L, 1);
        lua_pushstring(L, REFUSED);
    }
    return n;
}

/* Makes argument arg (load's and loadfile's mode) "t", keeping the others. */
static void text_mode(lua_State *L, int arg)
{
    if (lua_gettop(L) < arg)
        lua_settop(L, arg);           /* none past it: env stays "not given" */
    lua_pushliteral(L, "t");
    lua_replace(L, arg);
}

static int w_load(lua_State *L)
{
    text_mode(L, 3);
    return loaded(L, ORIGINAL(L)(L));
}

static int w_loadfile(lua_State *L)
{
    text_mode(L, 2);
    return loaded(L, ORIGINAL(L)(L));
}

static int dofile_done(lua_State *L, int status, lua_KContext k)
{
    (void)status;
    (void)k;
    return lua_gettop(L) - 1;
}

/* dofile, as Lua's, in text mode (Lua's calls luaL_loadfile: "bt"). */
static int w_dofile(lua_State *L)
{
    const char *fname = luaL_optstring(L, 1, NULL);
    lua_settop(L, 1);
    if (luaL_loadfilex(L, fname, "t") != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        if (msg && strstr(msg, BINARY_LUA))
            return luaL_error(L, "%s: %s", fname ? fname : "stdin", REFUSED);
        return lua_error(L);
    }
    lua_callk(L, 0, LUA_MULTRET, 0, dofile_done);
    return dofile_done(L, 0, 0);
}

/* require's file searcher, as Lua's (package.path, package.searchpath) but
** loading text only. Upvalue 1: the package table. */
static int searcher_text(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1), *file, *msg;
    lua_getfield(L, lua_upvalueindex(1), "searchpath");
    lua_pushstring(L, name);
    if (lua_getfield(L, lua_upvalueindex(1), "path") != LUA_TSTRING)
        return luaL_error(L, "'package.path' must be a string");
    lua_call(L, 2, 2);
    if (lua_isnil(L, -2))
        return 1;                            /* "no file '...'", as Lua's */
    file = lua_tostring(L, -2);
    if (luaL_loadfilex(L, file, "t") != LUA_OK) {
        msg = lua_tostring(L, -1);
        return luaL_error(L, "error loading module '%s' from file '%s':\n\t%s",
                          name, file, strstr(msg, BINARY_LUA) ? REFUSED : msg);
    }
    lua_pushstring(L, file);
    return 2;
}

void sandbox_text_only(lua_State *L)
{
    lua_pushglobaltable(L);
    wrap(L, -1, "load", w_load);
    wrap(L, -1, "loadfile", w_loadfile);
    wrap(L, -1, "dofile", w_dofile);          /* its original is only a name */
    lua_pop(L, 1);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_getfield(L, -1, LUA_LOADLIBNAME);
    lua_getfield(L, -1, "searchers");
    lua_pushvalue(L, -2);
    lua_pushcclosure(L, searcher_text, 1);
    lua_rawseti(L, -2, 2);                   /* Lua's file searcher */
    lua_pop(L, 3);
}

/* ---- The host hook --------------------------------------------------------- */

/* The host hook of a capped state (src/lua_hook.c): upvalue 1 the hook it
** wraps (the command's) or nil. A render stopped by the time cap, or asked
** for after it, says so. */
static int w_host_hook(lua_State *L)
{
    const char *method = luaL_checkstring(L, 1);
    int render = strcmp(method, "render") == 0;
    if (render) {
        if (caps_expired(L))
            return caps_time_error(L, 2, " before a render");
        caps_collect(L);
    }
    if (lua_isnil(L, lua_upvalueindex(1))) {
        lua_remove(L, 1);                /* plain(self, ...) */
    } else {
        lua_pushvalue(L, lua_upvalueindex(1));
        lua_replace(L, 1);               /* hook(method, plain, self, ...) */
        lua_pushstring(L, method);
        lua_insert(L, 2);
    }
    if (lua_pcall(L, lua_gettop(L) - 1, LUA_MULTRET, 0) != LUA_OK) {
        if (render && caps_expired(L))   /* 0 this hook, 1 scene:render, 2 its caller */
            return caps_time_error(L, 2, " in a render");
        return lua_error(L);
    }
    return lua_gettop(L);
}

/* Installs w_host_hook around the hook set now; core at its index. */
static void install_hook(lua_State *L, int core)
{
    lua_getfield(L, core, "set_host_hook");
    lua_pushnil(L);
    lua_call(L, 1, 1);                   /* the hook set now */
    lua_pushcclosure(L, w_host_hook, 1);
    lua_getfield(L, core, "set_host_hook");
    lua_insert(L, -2);
    lua_call(L, 1, 0);
}

int sandbox_hook(lua_State *L)
{
    luaL_requiref(L, "lancer.core", luaopen_lancer_core, 0);
    install_hook(L, lua_gettop(L));
    return 0;
}
