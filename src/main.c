/* main.c: the lancer command: runs scripts and one-liners, with Ctrl-C armed;
** main_args.c reads its command line, main_repl.c is its prompt. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "lancer.h"
#include "lua_lancer.h"
#include "main.h"

/* The pure-Lua modules, embedded by tools/embed-lua.sh (NULL-name ended), so
** the command runs from anywhere with no lua/ directory beside it. */
struct lc_embedded_lua {
    const char *name;
    const unsigned char *data;
    size_t len;
};
extern const struct lc_embedded_lua lc_embedded_lua[];

const char *host_progname = "lancer";
static lua_State *globalL;              /* the state Ctrl-C interrupts */

/* ---- Running Lua code, after lua.c ------------------------------------------ */

void host_module_field(lua_State *L, const char *module, const char *field)
{
    lua_getglobal(L, "require");
    lua_pushstring(L, module);
    lua_call(L, 1, 1);
    lua_getfield(L, -1, field);
}

void host_set_sigint(void (*handler)(int), struct sigaction *old)
{
    struct sigaction sa;
    sa.sa_handler = handler;
    sa.sa_flags = 0;            /* no SA_RESTART: a blocked read must return */
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, old);
}

/* A signal handler may do almost nothing, but setting a hook is safe: the
** hook then raises the error from inside Lua, where unwinding is allowed. */
static void lstop(lua_State *L, lua_Debug *ar)
{
    /* Not on entering or leaving a C function: that is the message handler
    ** of a render that Ctrl-C cancelled, whose "render cancelled" must stay.
    ** The next Lua instruction raises instead. */
    if (ar->event != LUA_HOOKCOUNT && ar->event != LUA_HOOKLINE &&
        lua_getinfo(L, "S", ar) && ar->what[0] == 'C')
        return;
    lua_sethook(L, NULL, 0, 0);
    luaL_error(L, "interrupted!");
}

static void laction(int sig)
{
    int flag = LUA_MASKCALL | LUA_MASKRET | LUA_MASKLINE | LUA_MASKCOUNT;
    (void)sig;
    host_set_sigint(SIG_DFL, NULL);  /* a second Ctrl-C kills */
    lc_interrupt();     /* a render stops; the binding raises "render cancelled" */
    lua_sethook(globalL, lstop, flag, 1);
}

void host_message(const char *msg)
{
    if (host_progname)
        fprintf(stderr, "%s: ", host_progname);
    fprintf(stderr, "%s\n", msg);
    fflush(stderr);
}

int host_report(lua_State *L, int status)
{
    if (status != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        host_message(msg ? msg : "(error object is not a string)");
        lua_pop(L, 1);
    }
    return status;
}

/* Message handler: adds the traceback while the failed stack still exists. */
static int msghandler(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (msg == NULL) {
        if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING)
            return 1;
        msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    }
    luaL_traceback(L, L, msg, 1);
    return 1;
}

/* Calls the function under its narg arguments, with Ctrl-C armed. */
int host_docall(lua_State *L, int narg, int nres)
{
    struct sigaction old;
    int base = lua_gettop(L) - narg;
    int status;
    lua_pushcfunction(L, msghandler);
    lua_insert(L, base);
    globalL = L;
    host_set_sigint(laction, &old);
    status = lua_pcall(L, narg, nres, base);
    sigaction(SIGINT, &old, NULL);
    /* A Ctrl-C that came as the code finished must not hit the next line. */
    if (lua_gethook(L) == lstop)
        lua_sethook(L, NULL, 0, 0);
    lua_remove(L, base);
    return status;
}

static int dochunk(lua_State *L, int status)
{
    if (status == LUA_OK)
        status = host_docall(L, 0, 0);
    return host_report(L, status);
}

/* The global 'arg' exactly as lua5.4 builds it: the script at 0, its
** arguments from 1, the command and options before it at negative indices. */
static void create_arg_table(lua_State *L, const struct cmdline *cl)
{
    int script = cl->script;
    int i;
    lua_createtable(L, script ? cl->argc - script - 1 : cl->argc - 1, script + 1);
    for (i = 0; i < cl->argc; i++) {
        lua_pushstring(L, cl->argv[i]);
        lua_rawseti(L, -2, i - script);
    }
    lua_setglobal(L, "arg");
}

static int handle_script(lua_State *L, const struct cmdline *cl)
{
    const char *fname = cl->script_stdin ? NULL : cl->argv[cl->script];
    int status = luaL_loadfile(L, fname);       /* NULL: stdin, named "=stdin" */
    if (status == LUA_OK) {
        int n = cl->argc - cl->script - 1, i;
        luaL_checkstack(L, n + 3, "too many arguments to script");
        for (i = 1; i <= n; i++)
            lua_pushstring(L, cl->argv[cl->script + i]);
        status = host_docall(L, n, 0);
    }
    return host_report(L, status);
}

/* ---- Embedded modules and the lancer table ------------------------------- */

/* package.preload loader of one embedded module. It compiles the source on
** first require, so a broken module fails there and not at every start. */
static int load_embedded(lua_State *L)
{
    const struct lc_embedded_lua *m = lua_touserdata(L, lua_upvalueindex(1));
    const char *path;
    /* tools/embed-lua.sh names lua/lancer/init.lua "lancer" and
    ** lua/lancer/x.lua "lancer.x"; name the chunk after the file. */
    luaL_gsub(L, m->name, ".", "/");
    if (strchr(m->name, '.') == NULL)
        path = lua_pushfstring(L, "@lua/%s/init.lua", lua_tostring(L, -1));
    else
        path = lua_pushfstring(L, "@lua/%s.lua", lua_tostring(L, -1));
    if (luaL_loadbufferx(L, (const char *)m->data, m->len, path, "t") != LUA_OK)
        return lua_error(L);
    lua_pushstring(L, m->name);                 /* ... as the file searcher passes */
    lua_pushstring(L, path + 1);
    lua_call(L, 2, 1);
    return 1;
}

static void register_modules(lua_State *L)
{
    const struct lc_embedded_lua *m;
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_lancer_core);
    lua_setfield(L, -2, "lancer.core");
    for (m = lc_embedded_lua; m->name != NULL; m++) {
        lua_pushlightuserdata(L, (void *)m);
        lua_pushcclosure(L, load_embedded, 1);
        lua_setfield(L, -2, m->name);
    }
    lua_pop(L, 1);
}

/* Fixed seed: a script that jitters with math.random renders the same
** image on every run (Lua 5.4 seeds it randomly otherwise). */
static void seed_random(lua_State *L)
{
    lua_getglobal(L, "math");
    lua_getfield(L, -1, "randomseed");
    lua_pushinteger(L, 0);
    lua_call(L, 1, 0);
    lua_pop(L, 1);
}

/* The animation options, into the overrides table on top of the stack. */
static void store_anim_overrides(lua_State *L, const struct anim_opts *an)
{
    int k;
    if (!an->first)
        return;
    lua_pushboolean(L, 1);          /* usage errors found later exit 2 */
    lua_setfield(L, -2, "cli");
    if (an->nframes > 0) {
        lua_newtable(L);
        for (k = 0; k < an->nframes; k++)
            args_frame_list(an->frames[k], L);
        lua_setfield(L, -2, "frames");
    }
    if (an->shard_n > 0) {
        lua_createtable(L, 2, 0);
        lua_pushinteger(L, an->shard_k);
        lua_rawseti(L, -2, 1);
        lua_pushinteger(L, an->shard_n);
        lua_rawseti(L, -2, 2);
        lua_setfield(L, -2, "shard");
    }
    lua_pushboolean(L, an->skip_existing);
    lua_setfield(L, -2, "skip_existing");
    lua_pushboolean(L, an->list_frames);
    lua_setfield(L, -2, "list_frames");
    if (an->video) {
        lua_pushstring(L, an->video);
        lua_setfield(L, -2, "video");
    }
    if (an->output) {
        lua_pushstring(L, an->output);
        lua_setfield(L, -2, "output");
    }
}

/* After the script: how many animations it declared (lancer.animate calls). */
static int anim_count(lua_State *L)
{
    host_module_field(L, "lancer.anim", "finish");
    lua_call(L, 0, 1);
    return 1;
}

/* Runs protected: require may fail, and lancer may not be a table. */
static int store_overrides(lua_State *L)
{
    const struct cmdline *cl = lua_touserdata(L, 1);
    lua_getglobal(L, "require");
    lua_pushliteral(L, "lancer");
    lua_call(L, 1, 1);
    if (!lua_istable(L, -1))
        return luaL_error(L, "require 'lancer' gave a %s, not a table",
                          luaL_typename(L, -1));
    if (lua_getfield(L, -1, "overrides") != LUA_TTABLE) {
        lua_pop(L, 1);
        lua_newtable(L);
        lua_pushvalue(L, -1);
        lua_setfield(L, -3, "overrides");
    }
    if (cl->width) {
        lua_pushinteger(L, cl->width);
        lua_setfield(L, -2, "width");
    }
    if (cl->height) {
        lua_pushinteger(L, cl->height);
        lua_setfield(L, -2, "height");
    }
    if (cl->samples) {
        lua_pushinteger(L, cl->samples);
        lua_setfield(L, -2, "samples");
    }
    if (cl->check) {
        lua_pushboolean(L, 1);
        lua_setfield(L, -2, "check");
    }
    if (cl->stats) {
        lua_pushboolean(L, 1);
        lua_setfield(L, -2, "stats");
    }
    store_anim_overrides(L, &cl->anim);
    if (cl->accuracy) {
        lua_pushboolean(L, 1);
        lua_setfield(L, -2, "accuracy");
    }
    return 0;
}

/* --accuracy: hands the options to lancer.accuracy.setup, which returns
** true or nil and the usage error. Runs protected. */
static int accuracy_setup(lua_State *L)
{
    const struct cmdline *cl = lua_touserdata(L, 1);
    host_module_field(L, "lancer.accuracy", "setup");
    lua_createtable(L, 0, 3);
    lua_createtable(L, cl->nknobs, 0);
    for (int i = 0; i < cl->nknobs; i++) {
        lua_pushstring(L, cl->knobs[i]);
        lua_rawseti(L, -2, i + 1);
    }
    lua_setfield(L, -2, "knobs");
    if (cl->seeds) {
        lua_pushinteger(L, cl->seeds);
        lua_setfield(L, -2, "seeds");
    }
    if (cl->out) {
        lua_pushstring(L, cl->out);
        lua_setfield(L, -2, "out");
    }
    lua_pushstring(L, cl->script_stdin ? "stdin" : cl->argv[cl->script]);
    lua_setfield(L, -2, "script");
    lua_call(L, 1, 2);
    return 2;
}

/* After an --accuracy run: false when the script rendered nothing. */
static int accuracy_finish(lua_State *L)
{
    host_module_field(L, "lancer.accuracy", "finish");
    lua_call(L, 0, 1);
    return 1;
}

/* After a --check run: lancer.check's verdict, as a boolean. */
static int check_verdict(lua_State *L)
{
    host_module_field(L, "lancer.check", "finish");
    lua_call(L, 0, 1);
    return 1;
}

/* Loads lancer only when asked to, so -e 'print(1)' needs no renderer. */
static int set_overrides(lua_State *L, const struct cmdline *cl)
{
    if (!cl->width && !cl->height && !cl->samples && !cl->check && !cl->stats &&
        !cl->anim.first && !cl->accuracy)
        return LUA_OK;
    lua_pushcfunction(L, store_overrides);
    lua_pushlightuserdata(L, (void *)cl);
    return host_report(L, host_docall(L, 1, 0));
}

/* ---- main ------------------------------------------------------------------ */

/* Everything that touches Lua runs here, under lua_pcall, so even running
** out of memory while setting up is reported rather than aborting. */
static int pmain(lua_State *L)
{
    struct cmdline *cl = lua_touserdata(L, 1);
    int i;
    luaL_checkversion(L);
    luaL_openlibs(L);
    register_modules(L);
    seed_random(L);
    create_arg_table(L, cl);
    lua_gc(L, LUA_GCRESTART);
    lua_gc(L, LUA_GCGEN, 0, 0);         /* lua5.4's mode, for like timings */
    if (set_overrides(L, cl) != LUA_OK)
        return 0;
    if (cl->accuracy) {
        lua_pushcfunction(L, accuracy_setup);
        lua_pushlightuserdata(L, cl);
        if (host_report(L, host_docall(L, 1, 2)) != LUA_OK)
            return 0;
        if (!lua_toboolean(L, -2)) {
            args_usage_error("%s", lua_tostring(L, -1));
            cl->late_usage = 1;
            return 0;
        }
        lua_pop(L, 2);
    }
    for (i = 0; i < cl->nchunks; i++) {
        const char *code = cl->chunks[i];
        int st = luaL_loadbuffer(L, code, strlen(code), "=(command line)");
        if (dochunk(L, st) != LUA_OK)
            return 0;
    }
    if (cl->script > 0 && handle_script(L, cl) != LUA_OK)
        return 0;
    /* Frame options need an animation (not checked for the REPL). */
    if (cl->anim.first && !cl->interactive && (cl->script > 0 || cl->nchunks > 0)) {
        lua_pushcfunction(L, anim_count);
        if (host_report(L, host_docall(L, 0, 1)) != LUA_OK)
            return 0;
        if (lua_tointeger(L, -1) == 0) {
            fprintf(stderr, "lancer: option '%s' needs a script that calls "
                    "lancer.animate{...}; %s does not; try 'lancer --help'\n",
                    cl->anim.first,
                    cl->script > 0 ? cl->argv[cl->script] : "the code run");
            cl->late_usage = 1;
            return 0;
        }
        lua_pop(L, 1);
    }
    if (cl->check) {
        lua_pushcfunction(L, check_verdict);
        if (host_report(L, host_docall(L, 0, 1)) != LUA_OK)
            return 0;
        if (!lua_toboolean(L, -1)) {
            cl->unstable = 1;
            return 0;
        }
        lua_pop(L, 1);
    }
    if (cl->accuracy) {
        lua_pushcfunction(L, accuracy_finish);
        if (host_report(L, host_docall(L, 0, 1)) != LUA_OK || !lua_toboolean(L, -1))
            return 0;
        lua_pop(L, 1);
    }
    if (cl->interactive) {
        repl_run(L);
    } else if (cl->script == 0 && cl->nchunks == 0) {
        if (isatty(STDIN_FILENO)) {
            repl_run(L);
        } else if (dochunk(L, luaL_loadfile(L, NULL)) != LUA_OK) {
            return 0;
        }
    }
    lua_pushboolean(L, 1);
    return 1;
}

int main(int argc, char **argv)
{
    struct cmdline cl;
    lua_State *L;
    int status, ok, parsed;

    memset(&cl, 0, sizeof cl);
    cl.argc = argc;
    cl.argv = argv;
    if (argc < 1 || argv[0] == NULL) {      /* exec with no argv[0] */
        fprintf(stderr, "lancer: no program name\n");
        return 2;
    }
    cl.chunks = malloc((size_t)argc * sizeof *cl.chunks);
    cl.anim.frames = malloc((size_t)argc * sizeof *cl.anim.frames);
    if (cl.chunks == NULL || cl.anim.frames == NULL) {
        fprintf(stderr, "lancer: not enough memory\n");
        free(cl.chunks);
        free(cl.anim.frames);
        return 1;
    }
    parsed = args_parse(&cl);
    if (parsed == PARSE_RUN)
        parsed = args_check_accuracy(&cl);
    if (parsed != PARSE_RUN) {
        free(cl.chunks);
        free(cl.anim.frames);
        return parsed == PARSE_DONE ? 0 : 2;
    }

    L = luaL_newstate();
    if (L == NULL) {
        fprintf(stderr, "lancer: cannot create the Lua state: not enough memory\n");
        free(cl.chunks);
        free(cl.anim.frames);
        return 1;
    }
    lua_gc(L, LUA_GCSTOP);              /* no collection while building state */
    lua_pushcfunction(L, pmain);
    lua_pushlightuserdata(L, &cl);
    status = lua_pcall(L, 1, 1, 0);
    ok = lua_toboolean(L, -1);
    host_report(L, status);
    lua_close(L);
    free(cl.chunks);
    free(cl.anim.frames);
    if (cl.unstable)
        return 3;
    if (cl.late_usage)
        return 2;
    return ok && status == LUA_OK ? 0 : 1;
}
