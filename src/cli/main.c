/* main.c: the lancer command: runs scripts and one-liners, with Ctrl-C armed;
** main_args.c reads its command line, main_repl.c is its prompt, main_caps.c
** and main_sandbox.c are --max-memory, --max-seconds and --sandbox,
** main_defines.c is -D and main_merge.c --merge. */
#define _XOPEN_SOURCE 700           /* realpath */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "lancer.h"
#include "lua/lua_lancer.h"
#include "main.h"

/* The pure-Lua modules, embedded by tools/embed-lua.sh (NULL-name ended), so
** the command runs from anywhere with no lua/ directory beside it. */
struct embedded_lua {
    const char *name;
    const unsigned char *data;
    size_t len;
};
extern const struct embedded_lua embedded_lua[];

const char *host_progname = "lancer";
static lua_State *globalL;              /* the state Ctrl-C interrupts */

/* ---- Running Lua code, after lua.c ------------------------------------------ */

void host_module_field(lua_State *L, const char *module, const char *field)
{
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    if (lua_getfield(L, -1, module) == LUA_TNIL) {
        /* Not loaded yet (not under --sandbox, whose require is the scene's). */
        lua_pop(L, 1);
        lua_getglobal(L, "require");
        lua_pushstring(L, module);
        lua_call(L, 1, 1);
    }
    lua_remove(L, -2);
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
    caps_rehook(L);                     /* none, or the time cap's */
    luaL_error(L, "interrupted!");
}

/* A signal that ends the process: the temporaries of saves in progress go
** first (nothing half-written is left), then the signal's default. */
static void on_fatal_signal(int sig)
{
    lc_save_abandon();
    signal(sig, SIG_DFL);
    raise(sig);
}

static void laction(int sig)
{
    int flag = LUA_MASKCALL | LUA_MASKRET | LUA_MASKLINE | LUA_MASKCOUNT;
    (void)sig;
    host_set_sigint(on_fatal_signal, NULL);  /* a second Ctrl-C kills */
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

/* Past the memory cap, Lua's own error reads "not enough memory": its
** first line says which cap, as the core's errors do. Printed without Lua,
** which may have no memory left to format with. */
static void report_memory(const char *msg, size_t cap)
{
    size_t first = strcspn(msg, "\n");
    if (host_progname)
        fprintf(stderr, "%s: ", host_progname);
    fprintf(stderr, "%.*s (lancer's memory cap is %.4g MB)%s\n", (int)first, msg,
            (double)cap / 1e6, msg + first);
    fflush(stderr);
}

int host_report(lua_State *L, int status)
{
    if (status != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        size_t cap = caps_memory_refused(L);
        if (msg == NULL)
            msg = "(error object is not a string)";
        if (cap && strstr(msg, "not enough memory"))
            report_memory(msg, cap);
        else
            host_message(msg);
        if (caps_expired(L) && !strstr(msg, "time cap reached"))
            host_message("time cap reached");
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
        caps_rehook(L);
    lua_remove(L, base);
    return status;
}

/* The chunks the command loads: text only, unless --allow-bytecode. */
static const char *chunk_mode(const struct cmdline *cl)
{
    return cl->allow_bytecode ? "bt" : "t";
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

/* luaL_loadfilex, with a refused binary chunk named and explained. */
static int load_script(lua_State *L, const struct cmdline *cl, const char *fname)
{
    int status = luaL_loadfilex(L, fname, chunk_mode(cl));  /* NULL: stdin */
    const char *msg = status == LUA_ERRSYNTAX ? lua_tostring(L, -1) : NULL;
    if (msg && strstr(msg, "attempt to load a binary chunk")) {
        lua_pop(L, 1);
        lua_pushfstring(L, "%s is a binary (precompiled) chunk, refused: Lua does not "
                        "verify them%s", fname ? fname : "stdin",
                        cl->sandbox ? "" : " (--allow-bytecode runs it)");
    }
    return status;
}

static int handle_script(lua_State *L, const struct cmdline *cl)
{
    const char *fname = cl->script_stdin ? NULL : cl->argv[cl->script];
    int status = load_script(L, cl, fname);
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
    const struct embedded_lua *m = lua_touserdata(L, lua_upvalueindex(1));
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
    const struct embedded_lua *m;
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_lancer_core);
    lua_setfield(L, -2, "lancer.core");
    for (m = embedded_lua; m->name != NULL; m++) {
        lua_pushlightuserdata(L, (void *)m);
        lua_pushcclosure(L, load_embedded, 1);
        lua_setfield(L, -2, m->name);
    }
    lua_pop(L, 1);
}

/* Fixed seed: a script that jitters with math.random renders the same
** image on every run (Lua 5.4 seeds it randomly otherwise); --seed's. */
static void seed_random(lua_State *L, lua_Integer seed)
{
    lua_getglobal(L, "math");
    lua_getfield(L, -1, "randomseed");
    lua_pushinteger(L, seed);
    lua_call(L, 1, 0);
    lua_pop(L, 1);
}

/* The frame options, as a table for lancer.host (which hands it to lancer.anim). */
static void push_anim_options(lua_State *L, const struct anim_opts *an)
{
    int k;
    lua_newtable(L);
    lua_pushstring(L, an->first);
    lua_setfield(L, -2, "first");
    if (an->nframes > 0) {
        lua_newtable(L);
        for (k = 0; k < an->nframes; k++)
            args_frame_list(an->frames[k], an->frame_flags[k], L);
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

/* --accuracy's options, as lancer.accuracy.setup reads them. */
static void push_accuracy_options(lua_State *L, const struct cmdline *cl)
{
    lua_createtable(L, 0, 4);
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
}

static void set_integer(lua_State *L, const char *name, lua_Integer v)
{
    if (v) {
        lua_pushinteger(L, v);
        lua_setfield(L, -2, name);
    }
}

static void set_boolean(lua_State *L, const char *name, int v)
{
    lua_pushboolean(L, v);
    lua_setfield(L, -2, name);
}

/* Hands the command line to lancer.host.setup, which installs the host hook
** (src/lua/lua_hook.c); returns true, or nil and a usage error. Runs protected:
** require may fail. */
static int host_setup(lua_State *L)
{
    const struct cmdline *cl = lua_touserdata(L, 1);
    int repl = lua_toboolean(L, 2);
    host_module_field(L, "lancer.host", "setup");
    lua_createtable(L, 0, 10);
    set_integer(L, "width", cl->width);
    set_integer(L, "height", cl->height);
    set_integer(L, "samples", cl->samples);
    if (cl->seed >= 0) {
        lua_pushinteger(L, cl->seed);
        lua_setfield(L, -2, "seed");
    }
    if (cl->threads >= 0) {
        lua_pushinteger(L, cl->threads);
        lua_setfield(L, -2, "threads");
    }
    if (cl->has_region) {
        lua_createtable(L, 4, 0);
        for (int k = 0; k < 4; k++) {
            lua_pushinteger(L, cl->region[k]);
            lua_rawseti(L, -2, k + 1);
        }
        lua_setfield(L, -2, "region");
    }
    if (cl->tile_n > 0) {
        lua_createtable(L, 2, 0);
        lua_pushinteger(L, cl->tile_k);
        lua_rawseti(L, -2, 1);
        lua_pushinteger(L, cl->tile_n);
        lua_rawseti(L, -2, 2);
        lua_setfield(L, -2, "tile");
    }
    set_boolean(L, "check", cl->check);
    set_boolean(L, "stats", cl->stats);
    set_boolean(L, "repl", repl);
    set_boolean(L, "code", cl->nchunks > 0);
    set_boolean(L, "watch", cl->watch);
    if (cl->progress) {
        lua_pushstring(L, cl->progress);
        lua_setfield(L, -2, "progress");
    }
    if (cl->script > 0) {
        lua_pushstring(L, cl->script_stdin ? "stdin" : cl->argv[cl->script]);
        lua_setfield(L, -2, "script");
    }
    if (cl->anim.first) {
        push_anim_options(L, &cl->anim);
        lua_setfield(L, -2, "anim");
    }
    if (cl->accuracy) {
        push_accuracy_options(L, cl);
        lua_setfield(L, -2, "accuracy");
    }
    lua_call(L, 1, 2);
    if (cl->watch) {                  /* what --watch draws with */
        host_module_field(L, "lancer.watch", "start");
        lua_pushboolean(L, isatty(STDOUT_FILENO));
        lua_pushcfunction(L, repl_terminal_size);
        lua_call(L, 2, 0);
        lua_pop(L, 1);
    }
    return 2;
}

/* The folder of the script, resolved, for --sandbox to read below; NULL
** for standard input, or a folder that does not resolve (then loading
** the script fails as it would). */
static const char *script_folder(const struct cmdline *cl, char *dir)
{
    const char *script = cl->script > 0 && !cl->script_stdin ? cl->argv[cl->script]
                                                              : NULL;
    const char *slash = script ? strrchr(script, '/') : NULL;
    char path[PATH_MAX];
    if (script == NULL)
        return NULL;
    if (slash == NULL)
        strcpy(path, ".");
    else if ((size_t)(slash - script) >= sizeof path)
        return NULL;
    else if (slash == script)
        strcpy(path, "/");
    else
        memcpy(path, script, (size_t)(slash - script)), path[slash - script] = '\0';
    return realpath(path, dir);
}

/* Seals the state for --sandbox, after the command's own setup. */
static int seal(lua_State *L, const struct cmdline *cl)
{
    char dir[PATH_MAX];
    struct sandbox_policy p;
    p.read_dir = script_folder(cl, dir);
    p.write_dir = cl->sandbox_out;
    p.lua_path = NULL;                 /* lancer's modules are all preloaded */
    p.no_write = "give it a folder with --sandbox-out DIR";
    lua_pushcfunction(L, sandbox_seal);
    lua_pushlightuserdata(L, &p);
    return host_report(L, host_docall(L, 1, 0));
}

/* After the script: lancer.host.finish's exit status (0: go on). */
static int host_finish(lua_State *L)
{
    host_module_field(L, "lancer.host", "finish");
    lua_call(L, 0, 1);
    return 1;
}

/* ---- main ------------------------------------------------------------------ */

/* --sandbox's caps when none is given: a scene the size of the showcase at
** 1080p needs about 100 MB and a minute; these leave room for much more
** and still stop a runaway scene on a laptop. */
#define SANDBOX_MEGABYTES 1024
#define SANDBOX_SECONDS   600.0

static char stuck_msg[160];

/* The watchdog's last resort (main_caps.c): C code that polls nothing ran
** on 1 s past the time cap. Only async-signal-safe calls from here. */
static void stuck(void)
{
    ssize_t n = write(STDERR_FILENO, stuck_msg, strlen(stuck_msg));
    (void)n;
    _exit(4);
}

/* The caps the command line asks for; NULL when none (a plain state). */
static const struct caps *command_caps(const struct cmdline *cl, struct caps *c)
{
    lua_Integer mb = cl->max_memory >= 0 ? cl->max_memory
                   : cl->sandbox ? SANDBOX_MEGABYTES : 0;
    c->max_memory = (size_t)mb * 1000000;
    c->max_seconds = cl->max_seconds >= 0 ? cl->max_seconds
                   : cl->sandbox ? SANDBOX_SECONDS : 0;
    c->stuck = stuck;
    snprintf(stuck_msg, sizeof stuck_msg, "lancer: time cap reached (lancer's time cap "
             "is %g s), in code that cannot be stopped: ending the process\n",
             c->max_seconds);
    return cl->sandbox || c->max_memory || c->max_seconds > 0 ? c : NULL;
}

/* Everything that touches Lua runs here, under lua_pcall, so even running
** out of memory while setting up is reported rather than aborting. */
static int pmain(lua_State *L)
{
    struct cmdline *cl = lua_touserdata(L, 1);
    int i, code;
    /* The prompt follows the script (or is all there is). */
    int repl = cl->interactive ||
               (cl->script == 0 && cl->nchunks == 0 && isatty(STDIN_FILENO));
    luaL_checkversion(L);
    if (cl->sandbox)
        sandbox_openlibs(L);            /* no debug library */
    else
        luaL_openlibs(L);
    caps_coroutines(L);                 /* nothing without a time cap */
    register_modules(L);
    if (!cl->allow_bytecode && !cl->sandbox)
        sandbox_text_only(L);           /* the sandbox's seal does it too */
    seed_random(L, cl->seed >= 0 ? cl->seed : 0);
    create_arg_table(L, cl);
    lua_gc(L, LUA_GCRESTART);
    lua_gc(L, LUA_GCGEN, 0, 0);         /* lua5.4's mode, for like timings */
    lua_pushcfunction(L, host_setup);
    lua_pushlightuserdata(L, cl);
    lua_pushboolean(L, repl);
    if (host_report(L, host_docall(L, 2, 2)) != LUA_OK)
        return 0;
    if (!lua_toboolean(L, -2)) {
        args_usage_error("%s", lua_tostring(L, -1));
        cl->late_usage = 1;
        return 0;
    }
    lua_pop(L, 2);
    if (cl->sandbox && seal(L, cl) != LUA_OK)
        return 0;
    if (cl->ndefines > 0) {                     /* -D NAME=VALUE */
        lua_pushcfunction(L, defines_set);
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
    if (!cl->sandbox && (cl->max_memory > 0 || cl->max_seconds > 0)) {
        lua_pushcfunction(L, sandbox_hook);    /* the time cap's word on renders */
        if (host_report(L, host_docall(L, 0, 0)) != LUA_OK)
            return 0;
    }
    for (i = 0; i < cl->nchunks; i++) {
        const char *chunk = cl->chunks[i];
        int st = luaL_loadbufferx(L, chunk, strlen(chunk), "=(command line)",
                                  chunk_mode(cl));
        if (dochunk(L, st) != LUA_OK)
            return 0;
    }
    if (cl->script > 0 && handle_script(L, cl) != LUA_OK)
        return 0;
    if (!repl && cl->script == 0 && cl->nchunks == 0 &&
        dochunk(L, load_script(L, cl, NULL)) != LUA_OK)    /* stdin, not a terminal */
        return 0;
    lua_pushcfunction(L, host_finish);
    if (host_report(L, host_docall(L, 0, 1)) != LUA_OK)
        return 0;
    code = (int)lua_tointeger(L, -1);
    lua_pop(L, 1);
    if (code != 0) {
        cl->unstable = code == 3;
        cl->late_usage = code == 2;
        return 0;
    }
    if (repl)
        repl_run(L);
    lua_pushboolean(L, 1);
    return 1;
}

/* The files the script read that --watch watches (lancer.watch.files), as
** a NULL-ended array of malloc'd strings in *files; protected. */
static int watched_files(lua_State *L)
{
    char ***files = lua_touserdata(L, 1);
    host_module_field(L, "lancer.watch", "files");
    int n = (int)luaL_len(L, -1);
    char **f = calloc((size_t)n + 1, sizeof *f);
    if (!f)
        return luaL_error(L, "not enough memory");
    *files = f;
    for (int k = 0; k < n; k++) {
        lua_rawgeti(L, -1, k + 1);
        const char *path = lua_tostring(L, -1);
        if (path && (f[k] = strdup(path)) == NULL)
            return luaL_error(L, "not enough memory");
        lua_pop(L, 1);
    }
    return 0;
}

/* One run of the command in a fresh state; 1 when it ended well. With
** files, also the files the script read (--watch). */
static int run_once(struct cmdline *cl, char ***files)
{
    struct caps caps;
    const struct caps *capped = command_caps(cl, &caps);
    lua_State *L = capped ? caps_newstate(capped) : luaL_newstate();
    int status, ok;
    if (L == NULL) {
        fprintf(stderr, "lancer: cannot create the Lua state: not enough memory\n");
        return 0;
    }
    warn_install(L);
    lua_gc(L, LUA_GCSTOP);              /* no collection while building state */
    lua_pushcfunction(L, pmain);
    lua_pushlightuserdata(L, cl);
    status = lua_pcall(L, 1, 1, 0);
    ok = lua_toboolean(L, -1);
    host_report(L, status);
    if (files) {
        lua_pushcfunction(L, watched_files);
        lua_pushlightuserdata(L, files);
        if (lua_pcall(L, 1, 0, 0) != LUA_OK)
            host_report(L, LUA_ERRRUN);
    }
    cl->timed_out = caps_close(L);      /* lua_close, for a plain state too */
    return ok && status == LUA_OK;
}

int main(int argc, char **argv)
{
    struct cmdline cl;
    int ok, parsed;

    memset(&cl, 0, sizeof cl);
    cl.argc = argc;
    cl.argv = argv;
    signal(SIGTERM, on_fatal_signal);
    signal(SIGHUP, on_fatal_signal);
    signal(SIGXFSZ, SIG_IGN);     /* past ulimit -f a write fails, and says so */
    cl.max_memory = -1;
    cl.max_seconds = -1;
    cl.seed = -1;
    cl.threads = -1;
    if (argc < 1 || argv[0] == NULL) {      /* exec with no argv[0] */
        fprintf(stderr, "lancer: no program name\n");
        return 2;
    }
    cl.chunks = malloc((size_t)argc * sizeof *cl.chunks);
    cl.anim.frames = malloc((size_t)argc * sizeof *cl.anim.frames);
    cl.anim.frame_flags = malloc((size_t)argc * sizeof *cl.anim.frame_flags);
    cl.defines = malloc((size_t)argc * sizeof *cl.defines);
    if (cl.chunks == NULL || cl.anim.frames == NULL || cl.anim.frame_flags == NULL ||
        cl.defines == NULL) {
        fprintf(stderr, "lancer: not enough memory\n");
        free(cl.chunks);
        free(cl.anim.frames);
        free(cl.anim.frame_flags);
        free(cl.defines);
        return 1;
    }
    parsed = args_parse(&cl);
    if (parsed == PARSE_RUN)
        parsed = args_check_accuracy(&cl);
    if (parsed == PARSE_RUN)
        parsed = args_check_limits(&cl);
    if (parsed == PARSE_RUN)
        parsed = args_check_watch(&cl);
    if (parsed != PARSE_RUN || cl.merge || cl.watch) {
        int code = parsed != PARSE_RUN ? (parsed == PARSE_DONE ? 0 : 2)
                 : cl.merge ? merge_run(&cl) : watch_run(&cl, run_once);
        free(cl.chunks);
        free(cl.anim.frames);
        free(cl.anim.frame_flags);
        free(cl.defines);
        return code;
    }

    ok = run_once(&cl, NULL);
    free(cl.chunks);
    free(cl.anim.frames);
    free(cl.anim.frame_flags);
    free(cl.defines);
    if (cl.timed_out)
        return 4;
    if (cl.unstable)
        return 3;
    if (cl.late_usage)
        return 2;
    return ok ? 0 : 1;
}
