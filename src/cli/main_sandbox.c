/* main_sandbox.c: the sandbox for untrusted scene files: what a sealed state
** refuses, and text-only chunks everywhere (--sandbox, lancer_sandbox.h).
**
** The whole state is the sandbox: its standard tables themselves lose what
** could run programs, load C code or binary chunks, or touch files outside
** two folders, so the host's own Lua helpers, which run in the same state
** and can be confused by the scene, hold no more power than it does. The
** checks are in C: a scene may replace any Lua function, not these. */
#define _XOPEN_SOURCE 700           /* realpath */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "lancer_sandbox.h"
#include "lua/lua_lancer.h"
#include "main.h"

/* What a sealed state's wrappers check against: resolved folders. */
struct policy {
    char read[PATH_MAX];    /* the scene's folder; "": none */
    char write[PATH_MAX];   /* the output folder; "": none */
    const char *no_write;   /* why nothing may be written, when write is "" */
};

/* ---- Paths ----------------------------------------------------------------- */

/* Appends rest, a path's missing part, to out (a resolved folder). 0 when
** that cannot be told safely: a "..", or a first part that exists although
** realpath could not pass it (a broken or looping link), or too long. */
static int append_missing(char out[PATH_MAX], const char *rest)
{
    int first = 1;
    while (*rest) {
        size_t n = strcspn(rest, "/"), len = strlen(out);
        if (n == 2 && rest[0] == '.' && rest[1] == '.')
            return 0;
        if (n > 0 && !(n == 1 && rest[0] == '.')) {
            int slash = len == 0 || out[len - 1] != '/';
            if (len + slash + n >= PATH_MAX)
                return 0;
            if (slash)
                out[len++] = '/';
            memcpy(out + len, rest, n);
            out[len + n] = '\0';
            if (first) {
                struct stat st;
                if (lstat(out, &st) == 0 || errno != ENOENT)
                    return 0;
                first = 0;
            }
        }
        rest += n;
        while (*rest == '/')
            rest++;
    }
    return 1;
}

/* What path names now: realpath of its longest prefix that exists, the
** rest as written (a file about to be made). 0 when it cannot be told. */
static int resolve(const char *path, char out[PATH_MAX])
{
    char buf[PATH_MAX];
    size_t n = strlen(path), i;
    if (n == 0 || n >= sizeof buf)
        return 0;
    if (realpath(path, out))
        return 1;
    memcpy(buf, path, n + 1);
    for (i = n; i-- > 0;) {
        if (buf[i] != '/')
            continue;
        buf[i] = '\0';
        if (realpath(i == 0 ? "/" : buf, out))
            return append_missing(out, path + i + 1);
    }
    return path[0] != '/' && realpath(".", out) && append_missing(out, path);
}

/* Whether the resolved path p is root or lies below it. */
static int below(const char *p, const char *root)
{
    size_t n = strlen(root);
    if (n == 0)
        return 0;
    if (n == 1)                          /* "/" */
        return 1;
    return strncmp(p, root, n) == 0 && (p[n] == '/' || p[n] == '\0');
}

static int path_allowed(const struct policy *pol, const char *path, int writing)
{
    char p[PATH_MAX];
    if (!resolve(path, p))
        return 0;
    return below(p, pol->write) || (!writing && below(p, pol->read));
}

/* Pushes the sentence saying why path is refused. */
static const char *refusal(lua_State *L, const struct policy *pol, const char *path,
                           int writing)
{
    const char *r = pol->read, *w = pol->write;
    if (writing && !*w)
        return lua_pushfstring(L, "sandbox: not writing '%s': the scene may write no "
                               "files (%s)", path, pol->no_write);
    if (writing)
        return lua_pushfstring(L, "sandbox: not writing '%s': it does not resolve "
                               "below the output folder '%s'", path, w);
    if (!*r && !*w)
        return lua_pushfstring(L, "sandbox: not reading '%s': the scene may read no "
                               "files (it was not read from a file)", path);
    if (*r && *w)
        return lua_pushfstring(L, "sandbox: not reading '%s': it does not resolve "
                               "below the scene's folder '%s' or the output folder "
                               "'%s'", path, r, w);
    return lua_pushfstring(L, "sandbox: not reading '%s': it does not resolve below "
                           "the %s folder '%s'", path, *r ? "scene's" : "output",
                           *r ? r : w);
}

/* ---- Wrappers -------------------------------------------------------------- */

/* A wrapper is a C closure: upvalue 1 the C function it stands for, which it
** calls directly, in its own frame, after its check, so that errors name
** the function and the script's line as the original's would; upvalue 2
** the policy (nil: text-only chunks, no path checks). Only functions
** without upvalues of their own can be wrapped so. */
#define ORIGINAL(L) (lua_tocfunction(L, lua_upvalueindex(1)))
#define POLICY(L)   ((const struct policy *)lua_touserdata(L, lua_upvalueindex(2)))

/* Replaces the function on top with its wrapper f. */
static void push_wrapper(lua_State *L, lua_CFunction f, int pol)
{
    if (!lua_tocfunction(L, -1) || lua_getupvalue(L, -1, 1) != NULL)
        luaL_error(L, "sandbox: cannot wrap a function that is not Lua's or lancer's");
    if (pol)
        lua_pushvalue(L, pol);
    else
        lua_pushnil(L);
    lua_pushcclosure(L, f, 2);
}

static void wrap(lua_State *L, int t, const char *name, lua_CFunction f, int pol)
{
    t = lua_absindex(L, t);
    lua_getfield(L, t, name);
    push_wrapper(L, f, pol);
    lua_setfield(L, t, name);
}

static int allowed(lua_State *L, const char *path, int writing)
{
    return POLICY(L) == NULL || path_allowed(POLICY(L), path, writing);
}

/* Refused as the function fails: raising (argument arg), or io.open's way. */
static int refuse_arg(lua_State *L, int arg, const char *path, int writing)
{
    return luaL_argerror(L, arg, refusal(L, POLICY(L), path, writing));
}

static int refuse_fail(lua_State *L, const char *path, int writing)
{
    luaL_pushfail(L);
    refusal(L, POLICY(L), path, writing);
    lua_pushinteger(L, EACCES);
    return 3;
}

/* io.open, and the loaders, io.lines and io.input (fs_functions): argument
** 1, when a name, is a file to read (io.open: or write, by its mode). */
static int w_io_open(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    const char *mode = luaL_optstring(L, 2, "r");
    if (!allowed(L, path, strpbrk(mode, "wa+") != NULL))
        return refuse_fail(L, path, strpbrk(mode, "wa+") != NULL);
    return ORIGINAL(L)(L);
}

static int w_read_arg(lua_State *L)
{
    if (lua_isstring(L, 1) && !allowed(L, lua_tostring(L, 1), 0))
        return refuse_arg(L, 1, lua_tostring(L, 1), 0);
    return ORIGINAL(L)(L);
}

/* lancer.merge_tiles(out, {part, ...}): out is written, each part read; the list
** is read raw, as the binding reads it, so what is checked is what is used. */
static int w_merge_args(lua_State *L)
{
    if (lua_isstring(L, 1) && !allowed(L, lua_tostring(L, 1), 1))
        return refuse_arg(L, 1, lua_tostring(L, 1), 1);
    if (lua_type(L, 2) == LUA_TTABLE)
        for (lua_Integer i = 1; i <= (lua_Integer)lua_rawlen(L, 2); i++) {
            int bad = lua_rawgeti(L, 2, i) == LUA_TSTRING &&
                      !allowed(L, lua_tostring(L, -1), 0);
            if (bad)
                return refuse_arg(L, 2, lua_tostring(L, -1), 0);
            lua_pop(L, 1);
        }
    return ORIGINAL(L)(L);
}

/* The binding's gate for the files it opens itself (an OBJ's .mtl and
** texture maps, an image texture's path): lua_binding.h, LB_FILE_GATE. */
static int w_file_gate(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    int writing = lua_toboolean(L, 2);
    if (allowed(L, path, writing)) {
        lua_pushboolean(L, 1);
        return 1;
    }
    lua_pushboolean(L, 0);
    refusal(L, POLICY(L), path, writing);
    return 2;
}

static int w_write_arg(lua_State *L)          /* io.output */
{
    if (lua_isstring(L, 1) && !allowed(L, lua_tostring(L, 1), 1))
        return refuse_arg(L, 1, lua_tostring(L, 1), 1);
    return ORIGINAL(L)(L);
}

static int w_os_remove(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    if (!allowed(L, path, 1))
        return refuse_fail(L, path, 1);
    return ORIGINAL(L)(L);
}

static int w_os_rename(lua_State *L)
{
    const char *from = luaL_checkstring(L, 1), *to = luaL_checkstring(L, 2);
    if (!allowed(L, from, 1))
        return refuse_fail(L, from, 1);
    if (!allowed(L, to, 1))
        return refuse_fail(L, to, 1);
    return ORIGINAL(L)(L);
}

/* ---- Chunks: text only ----------------------------------------------------- */

/* Lua 5.4 does not verify bytecode: a crafted binary chunk can read and
** write memory at will. So no binary chunk is loaded, sandbox or not,
** unless the command is given --allow-bytecode. */
static const char BINARY_LUA[] = "attempt to load a binary chunk";

static const char *binary_refused(lua_State *L)
{
    return POLICY(L) ? "sandbox: binary chunks are refused (Lua does not verify them)"
                     : "binary chunks are refused (Lua does not verify them; "
                       "lancer --allow-bytecode allows them)";
}

/* After load or loadfile: their failure message, made to say why. */
static int loaded(lua_State *L, int n)
{
    const char *msg = lua_tostring(L, -1);
    if (n == 2 && lua_isnil(L, -2) && msg && strstr(msg, BINARY_LUA)) {
        lua_pop(L, 1);
        lua_pushstring(L, binary_refused(L));
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
    if (lua_isstring(L, 1) && !allowed(L, lua_tostring(L, 1), 0)) {
        luaL_pushfail(L);
        refusal(L, POLICY(L), lua_tostring(L, 1), 0);
        return 2;
    }
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
    if (fname && !allowed(L, fname, 0))
        return refuse_arg(L, 1, fname, 0);
    if (luaL_loadfilex(L, fname, "t") != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        if (msg && strstr(msg, BINARY_LUA))
            return luaL_error(L, "%s: %s", fname ? fname : "stdin", binary_refused(L));
        return lua_error(L);
    }
    lua_callk(L, 0, LUA_MULTRET, 0, dofile_done);
    return dofile_done(L, 0, 0);
}

/* require's file searcher, as Lua's (package.path, package.searchpath) but
** loading text only. Upvalue 1: the package table; 2: the policy or nil
** (the path is the host's, not checked: only the wording differs). */
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
                          name, file, strstr(msg, BINARY_LUA) ? binary_refused(L) : msg);
    }
    lua_pushstring(L, file);
    return 2;
}

/* load, loadfile and dofile, text only, paths unchecked (a sealed state
** wraps loadfile and dofile through fs_functions, with its policy). */
static void chunks(lua_State *L)
{
    lua_pushglobaltable(L);
    wrap(L, -1, "load", w_load, 0);
    wrap(L, -1, "loadfile", w_loadfile, 0);
    wrap(L, -1, "dofile", w_dofile, 0);       /* its original is only a name */
    lua_pop(L, 1);
}

static void push_searcher(lua_State *L, int package, int pol)
{
    lua_pushvalue(L, package);
    if (pol)
        lua_pushvalue(L, pol);
    else
        lua_pushnil(L);
    lua_pushcclosure(L, searcher_text, 2);
}

void sandbox_text_only(lua_State *L)
{
    chunks(L);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_getfield(L, -1, LUA_LOADLIBNAME);
    lua_getfield(L, -1, "searchers");
    push_searcher(L, lua_absindex(L, -2), 0);
    lua_rawseti(L, -2, 2);                   /* Lua's file searcher */
    lua_pop(L, 3);
}

/* ---- What a sealed state refuses outright ---------------------------------- */

/* Raises "sandbox: NAME is refused (WHY)"; os.execute's says what it was
** asked to run (lancer.animate's mkdir for a missing folder, say). */
static int w_refused(lua_State *L)
{
    const char *name = lua_tostring(L, lua_upvalueindex(1));
    const char *why = lua_tostring(L, lua_upvalueindex(2));
    if (lua_type(L, 1) == LUA_TSTRING && strcmp(name, "os.execute") == 0)
        return luaL_error(L, "sandbox: os.execute(\"%s\") is refused (%s)",
                          lua_tostring(L, 1), why);
    return luaL_error(L, "sandbox: %s is refused (%s)", name, why);
}

static void refuse(lua_State *L, int t, const char *field, const char *name,
                   const char *why)
{
    t = lua_absindex(L, t);
    lua_pushstring(L, name);
    lua_pushstring(L, why);
    lua_pushcclosure(L, w_refused, 2);
    lua_setfield(L, t, field);
}

static int w_debug_index(lua_State *L)
{
    const char *k = lua_tostring(L, 2);
    return luaL_error(L, "sandbox: debug.%s is refused (the debug library reaches "
                      "past every other restriction)", k ? k : "?");
}

/* The modules a sealed state's require loads: lancer's for scenes, and
** the standard ones a script may name (the same tables as its globals). */
static const char *const modules[] = {
    "lancer", "lancer.core", "lancer.motion", "lancer.anim", "lancer.ledger",
    "string", "table", "math", "utf8", "coroutine", "io", "os", NULL};

/* require for a sealed state: upvalue 1 the package table (as Lua's own
** require has it), upvalue 2 Lua's require, called in this frame. */
static int w_require(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1);
    int i;
    for (i = 0; modules[i]; i++)
        if (strcmp(name, modules[i]) == 0)
            return lua_tocfunction(L, lua_upvalueindex(2))(L);
    return luaL_error(L, "sandbox: require '%s' is refused (a scene may require lancer, "
                      "lancer.motion, lancer.anim, lancer.ledger and Lua's own "
                      "libraries)", name);
}

/* ---- The host hook --------------------------------------------------------- */

/* The hook's plain save, checked: upvalue 1 the binding's plain, 2 the
** policy. A refusal is raised as plain raises what the script asked for
** and cannot have (src/lua/lua_hook.c): img:save then names it at the
** script's line. What is checked is what would be written, whatever path
** the hook around it passes. */
static int w_checked_save(lua_State *L)
{
    const struct policy *pol = POLICY(L);
    if (lua_isstring(L, 2) && !path_allowed(pol, lua_tostring(L, 2), 1)) {
        const char *msg = refusal(L, pol, lua_tostring(L, 2), 1);
        lua_createtable(L, 0, 2);
        lua_pushinteger(L, 2);               /* img:save's path, for luaL_argerror */
        lua_setfield(L, -2, "arg");
        lua_pushstring(L, msg);
        lua_setfield(L, -2, "msg");
        luaL_setmetatable(L, "lancer.PlainError");
        return lua_error(L);
    }
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

/* The host hook of a capped or sealed state (src/lua/lua_hook.c): upvalue 1
** the hook it wraps (the command's) or nil, upvalue 2 the policy or nil.
** Saves get a checked plain (a hook that writes nothing, as --check's,
** meets no refusal); a render stopped by the time cap, or asked for
** after it, says so. */
static int w_host_hook(lua_State *L)
{
    const char *method = luaL_checkstring(L, 1);
    int render = strcmp(method, "render") == 0;
    if (POLICY(L) && strcmp(method, "save") == 0) {
        lua_pushvalue(L, 2);
        lua_pushvalue(L, lua_upvalueindex(2));
        lua_pushcclosure(L, w_checked_save, 2);
        lua_replace(L, 2);
    }
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
static void install_hook(lua_State *L, int core, int pol)
{
    lua_getfield(L, core, "set_host_hook");
    lua_pushnil(L);
    lua_call(L, 1, 1);                   /* the hook set now */
    if (pol)
        lua_pushvalue(L, pol);
    else
        lua_pushnil(L);
    lua_pushcclosure(L, w_host_hook, 2);
    lua_getfield(L, core, "set_host_hook");
    lua_insert(L, -2);
    lua_call(L, 1, 0);
}

int sandbox_hook(lua_State *L)
{
    luaL_requiref(L, "lancer.core", luaopen_lancer_core, 0);
    install_hook(L, lua_gettop(L), 0);
    return 0;
}

/* ---- Sealing --------------------------------------------------------------- */

/* Sets field name of every table a scene can reach lancer.core's functions
** through (the core table, the table init.lua lends them from, the lancer
** module) to the value on top, which it pops, where that table holds what
** core.name gives now. */
static void replace_everywhere(lua_State *L, int core, const char *name)
{
    int top = lua_gettop(L), i;
    lua_getfield(L, core, name);                   /* top + 1: the old value */
    lua_pushvalue(L, core);                        /* top + 2 */
    if (lua_getmetatable(L, core)) {               /* top + 3: the lent table */
        lua_getfield(L, -1, "__index");
        lua_remove(L, -2);
    } else {
        lua_pushnil(L);
    }
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_getfield(L, -1, "lancer");                 /* top + 4: the module */
    lua_remove(L, -2);
    for (i = top + 2; i <= top + 4; i++) {
        int same;
        if (!lua_istable(L, i))
            continue;
        lua_pushstring(L, name);
        lua_rawget(L, i);
        same = lua_rawequal(L, -1, top + 1);
        lua_pop(L, 1);
        if (same) {
            lua_pushstring(L, name);
            lua_pushvalue(L, top);
            lua_rawset(L, i);
        }
    }
    lua_settop(L, top - 1);
}

/* Every function of a sealed state that opens a path a scene names, with
** the wrapper that checks it: the seal wraps what this list holds, so a new
** reader or writer (a loader of another format, say) is one row here, and
** tests/lua/test_sandbox_walk.lua, which calls every function a scene can
** reach with a path outside the folders, fails while it is missing. The
** files the binding opens on its own (an image texture's path, an OBJ's
** libraries and their maps) meet the file gate instead, and img:save the
** host hook: see seal_core. */
enum fs_table { FS_CORE, FS_GLOBALS, FS_IO, FS_OS };

static const struct fs_function {
    enum fs_table in;
    const char *name;
    lua_CFunction check;
} fs_functions[] = {
    {FS_CORE, "load_obj", w_read_arg},    {FS_CORE, "load_png", w_read_arg},
    {FS_CORE, "load_exr", w_read_arg},    {FS_CORE, "load_hdr", w_read_arg},
    {FS_CORE, "merge_tiles", w_merge_args},
    {FS_GLOBALS, "loadfile", w_loadfile}, {FS_GLOBALS, "dofile", w_dofile},
    {FS_IO, "open", w_io_open},           {FS_IO, "lines", w_read_arg},
    {FS_IO, "input", w_read_arg},         {FS_IO, "output", w_write_arg},
    {FS_OS, "remove", w_os_remove},       {FS_OS, "rename", w_os_rename},
};

/* Wraps each of fs_functions where a scene can reach it: lancer.core's
** wherever it is lent (replace_everywhere). A name the state lacks is an
** error, so that the list cannot go stale. */
static void seal_files(lua_State *L, int core, int G, int loaded, int P)
{
    size_t i;
    for (i = 0; i < sizeof fs_functions / sizeof *fs_functions; i++) {
        const struct fs_function *f = &fs_functions[i];
        int t = f->in == FS_CORE ? core : f->in == FS_GLOBALS ? G : 0;
        if (t == 0)
            lua_getfield(L, loaded, f->in == FS_IO ? LUA_IOLIBNAME : LUA_OSLIBNAME);
        else
            lua_pushvalue(L, t);
        if (lua_getfield(L, -1, f->name) != LUA_TFUNCTION)
            luaL_error(L, "sandbox: cannot seal '%s': no such function", f->name);
        push_wrapper(L, f->check, P);
        if (f->in == FS_CORE) {
            replace_everywhere(L, core, f->name);
        } else {
            lua_setfield(L, -2, f->name);
        }
        lua_pop(L, 1);
    }
}

static void resolve_dir(lua_State *L, const char *dir, char out[PATH_MAX],
                        const char *what)
{
    struct stat st;
    out[0] = '\0';
    if (dir == NULL)
        return;
    if (!realpath(dir, out) || stat(out, &st) != 0)
        luaL_error(L, "sandbox: cannot use %s '%s': %s", what, dir, strerror(errno));
    if (!S_ISDIR(st.st_mode))
        luaL_error(L, "sandbox: cannot use %s '%s': it is not a folder", what, dir);
}

void sandbox_openlibs(lua_State *L)
{
    static const luaL_Reg libs[] = {
        {LUA_GNAME, luaopen_base}, {LUA_LOADLIBNAME, luaopen_package},
        {LUA_COLIBNAME, luaopen_coroutine}, {LUA_TABLIBNAME, luaopen_table},
        {LUA_IOLIBNAME, luaopen_io}, {LUA_OSLIBNAME, luaopen_os},
        {LUA_STRLIBNAME, luaopen_string}, {LUA_MATHLIBNAME, luaopen_math},
        {LUA_UTF8LIBNAME, luaopen_utf8}, {NULL, NULL}};
    const luaL_Reg *lib;
    for (lib = libs; lib->func; lib++) {
        luaL_requiref(L, lib->name, lib->func, 1);
        lua_pop(L, 1);
    }
}

static const char RUNS[] = "a sandboxed scene runs no programs";
static const char NOTVERIFIED[] = "Lua does not verify binary chunks";

/* lancer.core, at core: the hook around the command's (img:save checked);
** the binding's file gate; and no set_host_hook, which would take the hook
** away. P: the policy's index. */
static void seal_core(lua_State *L, int core, int P)
{
    install_hook(L, core, P);
    lua_pushnil(L);                   /* upvalue 1: no original; 2: the policy */
    if (P)
        lua_pushvalue(L, P);
    else
        lua_pushnil(L);
    lua_pushcclosure(L, w_file_gate, 2);
    lua_setfield(L, LUA_REGISTRYINDEX, "lancer.file_gate");
    lua_pushnil(L);
    replace_everywhere(L, core, "set_host_hook");
}

/* require: lancer's modules only, from package.preload or lua_path; the
** scene's package: nothing that loads or finds files. G, package: the
** global table's and the package library's indices. */
static void seal_package(lua_State *L, int G, int package, const char *lua_path, int P)
{
    lua_pushvalue(L, package);
    lua_getfield(L, G, "require");
    lua_pushcclosure(L, w_require, 2);
    lua_setfield(L, G, "require");
    lua_createtable(L, 2, 0);
    lua_getfield(L, package, "searchers");
    lua_rawgeti(L, -1, 1);                       /* Lua's preload searcher */
    lua_remove(L, -2);
    lua_rawseti(L, -2, 1);
    push_searcher(L, package, P);
    lua_rawseti(L, -2, 2);
    lua_setfield(L, package, "searchers");
    lua_pushstring(L, lua_path ? lua_path : "");
    lua_setfield(L, package, "path");
    lua_pushliteral(L, "");
    lua_setfield(L, package, "cpath");
    lua_pushnil(L);
    lua_setfield(L, package, "loadlib");
    lua_createtable(L, 0, 5);
    lua_getfield(L, package, "config");
    lua_setfield(L, -2, "config");
    lua_pushliteral(L, "");
    lua_setfield(L, -2, "path");
    lua_pushliteral(L, "");
    lua_setfield(L, -2, "cpath");
    refuse(L, -1, "loadlib", "package.loadlib", "a sandboxed scene loads no C code");
    refuse(L, -1, "searchpath", "package.searchpath",
           "a sandboxed scene finds no files");
    lua_setfield(L, G, "package");
}

/* debug gone, and what of string, os and io runs programs, leaves the
** folders or reaches the process refused (their files: fs_functions).
** loaded: the index of package.loaded. */
static void seal_libs(lua_State *L, int G, int loaded)
{
    /* debug: gone from the state; the name answers with a refusal. */
    lua_pushnil(L);
    lua_setfield(L, loaded, LUA_DBLIBNAME);
    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, w_debug_index);
    lua_setfield(L, -2, "__index");
    lua_setmetatable(L, -2);
    lua_setfield(L, G, LUA_DBLIBNAME);

    lua_getfield(L, loaded, LUA_STRLIBNAME);
    refuse(L, -1, "dump", "string.dump", NOTVERIFIED);
    lua_pop(L, 1);

    lua_getfield(L, loaded, LUA_OSLIBNAME);
    refuse(L, -1, "execute", "os.execute", RUNS);
    refuse(L, -1, "exit", "os.exit", "a scene ends by returning or raising an error");
    refuse(L, -1, "getenv", "os.getenv", "the environment may hold secrets");
    refuse(L, -1, "tmpname", "os.tmpname", "it makes a file outside the output folder");
    refuse(L, -1, "setlocale", "os.setlocale", "it changes the whole process");
    lua_pop(L, 1);

    lua_getfield(L, loaded, LUA_IOLIBNAME);
    refuse(L, -1, "popen", "io.popen", RUNS);
    refuse(L, -1, "tmpfile", "io.tmpfile", "it makes a file outside the output folder");
    lua_pop(L, 1);
}

int sandbox_seal(lua_State *L)
{
    const struct sandbox_policy *p = lua_touserdata(L, 1);
    struct policy *pol = lua_newuserdatauv(L, sizeof *pol, 0);
    int P = lua_gettop(L);
    resolve_dir(L, p->read_dir, pol->read, "the scene's folder");
    resolve_dir(L, p->write_dir, pol->write, "the output folder");
    pol->no_write = p->no_write ? p->no_write : "no output folder was given";
    luaL_requiref(L, "lancer.core", luaopen_lancer_core, 0);
    int core = lua_gettop(L);
    seal_core(L, core, P);
    lua_pushglobaltable(L);
    int G = lua_gettop(L);
    wrap(L, G, "load", w_load, P);            /* text only; it opens no file */
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    int loaded = lua_gettop(L);
    seal_files(L, core, G, loaded, P);
    lua_getfield(L, loaded, LUA_LOADLIBNAME);
    seal_package(L, G, lua_gettop(L), p->lua_path, P);
    seal_libs(L, G, loaded);
    return 0;
}

/* ---- For embedders --------------------------------------------------------- */

static int open_sealed(lua_State *L)
{
    const lancer_sandbox_opts *o = lua_touserdata(L, 1);
    struct sandbox_policy p;
    sandbox_openlibs(L);
    caps_coroutines(L);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_lancer_core);
    lua_setfield(L, -2, "lancer.core");
    lua_pop(L, 1);
    p.read_dir = o->read_dir;
    p.write_dir = o->write_dir;
    p.lua_path = o->lua_path;
    p.no_write = "lancer_sandbox_opts.write_dir is NULL";
    lua_pushcfunction(L, sandbox_seal);
    lua_pushlightuserdata(L, &p);
    lua_call(L, 1, 0);
    return 0;
}

lua_State *lancer_sandbox_open(const lancer_sandbox_opts *o, char *err, size_t errlen)
{
    struct caps c;
    lua_State *L;
    c.max_memory = o->max_memory;
    c.max_seconds = o->max_seconds;
    c.stuck = o->stuck;
    if ((L = caps_newstate(&c)) == NULL) {
        snprintf(err, errlen, "cannot create the Lua state: not enough memory, or "
                 "no thread for the time cap");
        return NULL;
    }
    lua_pushcfunction(L, open_sealed);
    lua_pushlightuserdata(L, (void *)o);
    if (lua_pcall(L, 1, 0, 0) != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        snprintf(err, errlen, "%s", msg ? msg : "cannot seal the Lua state");
        caps_close(L);
        return NULL;
    }
    return L;
}

void lancer_sandbox_close(lua_State *L)
{
    if (L)
        caps_close(L);
}

int lancer_sandbox_timed_out(lua_State *L)
{
    return caps_expired(L);
}
