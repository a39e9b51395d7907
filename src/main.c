/* main.c: the lancer command: runs scripts, one-liners and the REPL. */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/ioctl.h>

#include <editline/readline.h>
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "lancer.h"
#include "lua_lancer.h"

#define LANCER_VERSION LC_VERSION
#define HISTORY_FILE   ".lancer_history" /* under $HOME */
#define HISTORY_MAX    1000              /* lines kept across sessions */
#define ACCURACY_KNOBS 8                 /* --knob options one run takes */

/* The pure-Lua modules, embedded by tools/embed-lua.sh (NULL-name ended), so
** the command runs from anywhere with no lua/ directory beside it. */
struct lc_embedded_lua {
    const char *name;
    const unsigned char *data;
    size_t len;
};
extern const struct lc_embedded_lua lc_embedded_lua[];

/* The animation options: lancer.animate reads them from lancer.overrides. */
struct anim_opts {
    const char **frames;    /* --frames and --frame lists, checked; nframes of them */
    int nframes;
    int shard_k, shard_n;   /* --shard K/N; shard_n 0: every frame */
    int skip_existing;      /* --skip-existing */
    int list_frames;        /* --list-frames: print the paths, render nothing */
    const char *video;      /* --video PATH: assemble with ffmpeg */
    const char *output;     /* -o PATTERN: replaces the script's output pattern */
    const char *first;      /* the first of these given, to name in errors */
};

/* The parsed command line. Options stop at the script, as with lua5.4:
** whatever follows the script belongs to the script. */
struct cmdline {
    int argc;
    char **argv;
    int script;             /* argv index of the script; 0: none */
    int script_stdin;       /* the script is "-": read standard input */
    int interactive;        /* -i */
    const char **chunks;    /* -e strings, in order */
    int nchunks;
    lua_Integer width, height, samples;  /* --width...; 0: not given */
    int check;              /* --check: is the scene numerically stable? */
    int stats;              /* --stats: print each render's ledger */
    int unstable;           /* --check found it was not: exit 3 */
    struct anim_opts anim;  /* --frames, --shard, --video, ... */
    int late_usage;         /* a usage error found once Lua ran (a frame option
                            ** without an animation, a bad --knob): exit 2 */
    int accuracy;           /* --accuracy: error against time over --knob levels */
    const char *knobs[ACCURACY_KNOBS];  /* --knob NAME=L1,L2,... as given */
    int nknobs;
    lua_Integer seeds;      /* --seeds N; 0: not given */
    const char *out;        /* --out DIR; NULL: not given */
};

enum { PARSE_RUN, PARSE_DONE, PARSE_USAGE };

static const char *progname = "lancer";  /* prefix of errors; NULL in the REPL */
static lua_State *globalL;               /* the state Ctrl-C interrupts */

static void print_usage(void)
{
    fputs(
"usage: lancer [options] [script.lua [args...]]\n"
"\n"
"Examples:\n"
"  lancer scene.lua              run scene.lua (it renders and saves its images)\n"
"  lancer --width 320 --height 240 --samples 1 scene.lua\n"
"                                the same, as a quick preview\n"
"  lancer scene.lua a b          the script sees arg[1] == 'a', arg[2] == 'b'\n"
"  lancer - < scene.lua          read the script from standard input\n"
"  lancer -e 'print(require(\"lancer\").version)'\n"
"  lancer -i scene.lua           run scene.lua, then the interactive prompt\n"
"  lancer --check scene.lua      is the scene numerically stable?\n"
"  lancer --video orbit.mp4 orbit.lua\n"
"                                render an animation's frames, then an mp4\n"
"  lancer --frames 1-24 --skip-existing orbit.lua\n"
"                                frames 1 to 24 of it, those not yet written\n"
"  lancer --accuracy --knob samples=1,4,16,64 scene.lua\n"
"                                error against time over those levels\n"
"  lancer                        the interactive prompt\n"
"\n"
"Options (before the script; arguments after it go to the script):\n"
"  -e CODE       run the Lua string CODE (may be repeated)\n"
"  -i            enter the interactive prompt after the script\n"
"  -             read the script from standard input\n"
"  --            stop handling options\n"
"  --width W     render at width W, whatever the script asks (positive integer)\n"
"  --height H    render at height H, likewise\n"
"  --samples N   take N samples per pixel, likewise\n"
"  --stats       print each render's ledger: rays by kind, tests, phases, effects\n"
"  --check       render each image small at scales 1e-3, 1, 1e3 and moved 1e6\n"
"                away; report differing pixels, NaN and self-hits (exit 3 if\n"
"                the scene is numerically unstable)\n"
"\n"
"Animations (scripts calling lancer.animate{...}; frames are numbered from 1\n"
"unless the script sets 'first'):\n"
"  --frames LIST frames to render: 7, 1-48, 1-48:4 (every 4th), 1,5,9-12\n"
"  --frame N     the same as --frames N\n"
"  --shard K/N   of those, only frames whose number mod N is K (0 <= K < N)\n"
"  --skip-existing\n"
"                leave frames whose file exists (files appear whole, by rename)\n"
"  --list-frames print the selected frames' paths, render nothing\n"
"  -o PATTERN    write frames to PATTERN (out/f_%04d.png or out/f_####.png);\n"
"                also --output PATTERN\n"
"  --video FILE  then assemble every frame with ffmpeg (.mp4 .mkv .mov .webm .gif)\n"
"  Each frame logs one line on stderr; a failed frame does not stop the others,\n"
"  and the exit status is then 1.\n"
"\n"
"  --accuracy    render each image the script asks for at every level of each\n"
"                --knob, against a reference 16x the largest; print error, time\n"
"                and efficiency, write a CSV and a plot (see the README)\n"
"  --knob NAME=L1,L2,...  with --accuracy: samples, cone_samples,\n"
"                light_samples or max_depth (depth), increasing levels;\n"
"                may be repeated\n"
"  --seeds N     with --accuracy: renders per level, N >= 2 (default 4)\n"
"  --out DIR     with --accuracy: where the CSV and PNG go (default out/accuracy)\n"
"  --help        print this help and exit\n"
"  --version     print the version and exit\n"
"\n"
"The script sees its arguments in 'arg' and '...', as with lua5.4.\n"
"math.random starts from a fixed seed, so a script renders the same each run.\n"
"The prompt prints the value of an expression, draws each render in the\n"
"terminal and saves it to out/repl_NNN.png; its history is kept in\n"
"~/" HISTORY_FILE ". Ctrl-C interrupts running code or a render, Ctrl-D quits.\n"
"\n"
"Exit status: 0 success, 1 script error, 2 usage error, 3 unstable (--check).\n", stdout);
}

static int usage_error(const char *fmt, const char *what)
{
    fprintf(stderr, "lancer: ");
    fprintf(stderr, fmt, what);
    fprintf(stderr, "; try 'lancer --help'\n");
    return PARSE_USAGE;
}

/* Reads a --width style value: digits only (no sign, no spaces), 1..INT_MAX.
** The binding checks the real limits when it renders. */
static int parse_positive(const char *s, lua_Integer *out)
{
    lua_Integer v = 0;
    if (*s == '\0')
        return 0;
    for (; *s; s++) {
        if (*s < '0' || *s > '9')
            return 0;
        v = v * 10 + (*s - '0');
        if (v > INT_MAX)
            return 0;
    }
    *out = v;
    return v > 0;
}

/* Handles one "--width W" or "--width=W"; *i moves past the value. */
static int parse_size(struct cmdline *cl, int *i, const char *name, lua_Integer *out)
{
    const char *a = cl->argv[*i];
    size_t n = strlen(name);
    const char *v;
    if (a[n] == '=') {
        v = a + n + 1;
    } else {
        if (cl->argv[*i + 1] == NULL)
            return usage_error("option '%s' needs a value", name);
        v = cl->argv[++*i];
    }
    if (!parse_positive(v, out)) {
        fprintf(stderr, "lancer: option '%s' needs a positive integer, got '%s'; "
                "try 'lancer --help'\n", name, v);
        return PARSE_USAGE;
    }
    return PARSE_RUN;
}

static int is_opt(const char *arg, const char *name)
{
    size_t n = strlen(name);
    return strncmp(arg, name, n) == 0 && (arg[n] == '\0' || arg[n] == '=');
}

/* ---- Animation options ----------------------------------------------------- */

#define FRAME_MAX 1000000000L   /* frame numbers and steps, as lancer.animate allows */

/* Reads a frame number at *s (digits only, at most FRAME_MAX); moves *s past it. */
static int frame_number(const char **s, long *out)
{
    long v = 0;
    if (**s < '0' || **s > '9')
        return 0;
    for (; **s >= '0' && **s <= '9'; ++*s) {
        v = v * 10 + (**s - '0');
        if (v > FRAME_MAX)
            return 0;
    }
    *out = v;
    return 1;
}

/* Reads a --frames list: items N, A-B or A-B:S separated by commas. With L,
** appends each item as {A, B, S} to the table on top of L's stack. Returns
** NULL, or why the list is wrong. */
static const char *frame_list(const char *s, lua_State *L)
{
    do {
        long a, b, step = 1;
        if (!frame_number(&s, &a))
            return "frames are whole numbers from 0";
        b = a;
        if (*s == '-' && (s++, !frame_number(&s, &b)))
            return "a range is A-B";
        if (*s == ':' && (s++, !frame_number(&s, &step) || step < 1))
            return "a step is a whole number from 1";
        if (*s != ',' && *s != '\0')
            return "items are N, A-B or A-B:STEP, separated by commas";
        if (b < a)
            return "a range A-B needs A <= B";
        if (L) {
            lua_createtable(L, 3, 0);
            lua_pushinteger(L, a);
            lua_rawseti(L, -2, 1);
            lua_pushinteger(L, b);
            lua_rawseti(L, -2, 2);
            lua_pushinteger(L, step);
            lua_rawseti(L, -2, 3);
            lua_rawseti(L, -2, (lua_Integer)luaL_len(L, -2) + 1);
        }
    } while (*s++ == ',');
    return NULL;
}

/* The value of "--name V" or "--name=V"; NULL when it is missing. */
static const char *option_value(struct cmdline *cl, int *i, const char *name)
{
    const char *a = cl->argv[*i];
    size_t n = strlen(name);
    if (a[n] == '=')
        return a + n + 1;
    return cl->argv[*i + 1] ? cl->argv[++*i] : NULL;
}

static int bad_value(const char *name, const char *want, const char *got)
{
    fprintf(stderr, "lancer: option '%s' needs %s, got '%s'; try 'lancer --help'\n",
            name, want, got);
    return PARSE_USAGE;
}

/* Handles one animation option at argv[*i]: 1 and *st set when it was one. */
static int parse_anim_option(struct cmdline *cl, int *i, int *st)
{
    static const char *const names[] = {"--frames", "--frame", "--shard", "--skip-existing",
                                        "--list-frames", "--video", "--output", "-o", NULL};
    static const char *const video_ext[] = {".mp4", ".mkv", ".mov", ".webm", ".gif", NULL};
    struct anim_opts *an = &cl->anim;
    const char *a = cl->argv[*i], *name = NULL, *v = NULL, *why;
    int k;
    for (k = 0; names[k] && !name; k++)
        if (is_opt(a, names[k]))
            name = names[k];
    if (!name)
        return 0;
    *st = PARSE_RUN;
    if (!an->first)
        an->first = name;
    if (strcmp(name, "--skip-existing") == 0 || strcmp(name, "--list-frames") == 0) {
        if (a[strlen(name)] == '=') {
            *st = usage_error("option '%s' takes no value", name);
            return 1;
        }
        *(name[2] == 's' ? &an->skip_existing : &an->list_frames) = 1;
        return 1;
    }
    if ((v = option_value(cl, i, name)) == NULL) {
        *st = usage_error("option '%s' needs a value", name);
        return 1;
    }
    if (strcmp(name, "--frames") == 0 || strcmp(name, "--frame") == 0) {
        if ((why = frame_list(v, NULL)) != NULL) {
            fprintf(stderr, "lancer: option '%s' needs frames like 7, 1-48, 1-48:2 or "
                    "1,5,9-12, got '%s' (%s); try 'lancer --help'\n", name, v, why);
            *st = PARSE_USAGE;
        } else if (strcmp(name, "--frame") == 0 && strpbrk(v, ",-:")) {
            *st = bad_value(name, "one frame number (--frames takes lists)", v);
        } else {
            an->frames[an->nframes++] = v;
        }
    } else if (strcmp(name, "--shard") == 0) {
        long sk, sn;
        const char *p = v;
        if (!frame_number(&p, &sk) || *p++ != '/' || !frame_number(&p, &sn) || *p ||
            sn < 1 || sk >= sn)
            *st = bad_value(name, "K/N with 0 <= K < N, such as 0/4", v);
        an->shard_k = (int)sk;
        an->shard_n = (int)sn;
    } else if (strcmp(name, "--video") == 0) {
        size_t n = strlen(v), e;
        for (k = 0; video_ext[k]; k++)
            if (n > (e = strlen(video_ext[k])) && strcmp(v + n - e, video_ext[k]) == 0)
                break;
        if (!video_ext[k])
            *st = bad_value(name, "a file ending in .mp4, .mkv, .mov, .webm or .gif", v);
        an->video = v;
    } else {                                    /* -o, --output */
        if (!strchr(v, '%') && !strchr(v, '#'))
            *st = bad_value(name, "a pattern with a frame field, such as "
                            "out/f_%04d.png or out/f_####.png", v);
        an->output = v;
    }
    return 1;
}

/* "--knob V", "--out V" or with '='; lancer.accuracy checks what V says. */
static int parse_accuracy_value(struct cmdline *cl, int *i, const char *name)
{
    const char *a = cl->argv[*i], *v;
    if (a[strlen(name)] == '=')
        v = a + strlen(name) + 1;
    else if (cl->argv[*i + 1] != NULL)
        v = cl->argv[++*i];
    else
        return usage_error("option '%s' needs a value", name);
    if (*v == '\0')
        return usage_error("option '%s' needs a value", name);
    if (name[2] == 'o') {
        cl->out = v;
    } else if (cl->nknobs == ACCURACY_KNOBS) {
        return usage_error("option '%s' may be given at most 8 times", name);
    } else {
        cl->knobs[cl->nknobs++] = v;
    }
    return PARSE_RUN;
}

/* The accuracy options go together: caught before anything runs. */
static int check_accuracy_args(const struct cmdline *cl)
{
    if (!cl->accuracy) {
        const char *stray = cl->nknobs ? "--knob" : cl->seeds ? "--seeds"
                          : cl->out ? "--out" : NULL;
        return stray ? usage_error("option '%s' needs --accuracy", stray) : PARSE_RUN;
    }
    if (cl->check)
        return usage_error("option '%s' cannot go with --check", "--accuracy");
    if (cl->script == 0)
        return usage_error("option '%s' needs a script", "--accuracy");
    if (cl->nknobs == 0)
        return usage_error("option '%s' needs --knob NAME=L1,L2,...", "--accuracy");
    if (cl->seeds == 1)
        return usage_error("option '%s' needs at least 2 seeds, got 1", "--seeds");
    return PARSE_RUN;
}

/* Checks every option before anything runs, so a typo costs no render. */
static int parse_args(struct cmdline *cl)
{
    char **argv = cl->argv;
    int i;
    for (i = 1; argv[i] != NULL; i++) {
        const char *a = argv[i];
        int st = PARSE_RUN;
        if (a[0] != '-') {                       /* the script */
            cl->script = i;
            return PARSE_RUN;
        } else if (strcmp(a, "-") == 0) {
            cl->script = i;
            cl->script_stdin = 1;
            return PARSE_RUN;
        } else if (strcmp(a, "--") == 0) {
            cl->script = argv[i + 1] ? i + 1 : 0;
            return PARSE_RUN;
        } else if (strcmp(a, "--help") == 0) {
            print_usage();
            return PARSE_DONE;
        } else if (strcmp(a, "--version") == 0) {
            printf("lancer %s (%s)\n", LANCER_VERSION, LUA_RELEASE);
            return PARSE_DONE;
        } else if (strcmp(a, "-i") == 0) {
            cl->interactive = 1;
        } else if (strncmp(a, "-e", 2) == 0) {   /* -e CODE or -eCODE, as lua5.4 */
            if (a[2] != '\0')
                cl->chunks[cl->nchunks++] = a + 2;
            else if (argv[i + 1] != NULL)
                cl->chunks[cl->nchunks++] = argv[++i];
            else
                return usage_error("option '%s' needs an argument", "-e");
        } else if (strcmp(a, "--check") == 0) {
            cl->check = 1;
        } else if (strcmp(a, "--stats") == 0) {
            cl->stats = 1;
        } else if (is_opt(a, "--width")) {
            st = parse_size(cl, &i, "--width", &cl->width);
        } else if (is_opt(a, "--height")) {
            st = parse_size(cl, &i, "--height", &cl->height);
        } else if (is_opt(a, "--samples")) {
            st = parse_size(cl, &i, "--samples", &cl->samples);
        } else if (parse_anim_option(cl, &i, &st)) {
            /* --frames, --shard, --video, ... */
        } else if (strcmp(a, "--accuracy") == 0) {
            cl->accuracy = 1;
        } else if (is_opt(a, "--knob") || is_opt(a, "--out")) {
            st = parse_accuracy_value(cl, &i, a[2] == 'k' ? "--knob" : "--out");
        } else if (is_opt(a, "--seeds")) {
            st = parse_size(cl, &i, "--seeds", &cl->seeds);
        } else {
            return usage_error("unknown option '%s'", a);
        }
        if (st != PARSE_RUN)
            return st;
    }
    cl->script = 0;
    return PARSE_RUN;
}

/* ---- Running Lua code, after lua.c ------------------------------------------ */

static void set_sigint(void (*handler)(int), struct sigaction *old)
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
    set_sigint(SIG_DFL, NULL);  /* a second Ctrl-C kills */
    lc_interrupt();             /* a render stops; the binding raises "render cancelled" */
    lua_sethook(globalL, lstop, flag, 1);
}

static void l_message(const char *msg)
{
    if (progname)
        fprintf(stderr, "%s: ", progname);
    fprintf(stderr, "%s\n", msg);
    fflush(stderr);
}

static int report(lua_State *L, int status)
{
    if (status != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        l_message(msg ? msg : "(error object is not a string)");
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
static int docall(lua_State *L, int narg, int nres)
{
    struct sigaction old;
    int base = lua_gettop(L) - narg;
    int status;
    lua_pushcfunction(L, msghandler);
    lua_insert(L, base);
    globalL = L;
    set_sigint(laction, &old);
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
        status = docall(L, 0, 0);
    return report(L, status);
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
        status = docall(L, n, 0);
    }
    return report(L, status);
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
            frame_list(an->frames[k], L);
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
    lua_getglobal(L, "require");
    lua_pushliteral(L, "lancer.anim");
    lua_call(L, 1, 1);
    lua_getfield(L, -1, "finish");
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
    lua_getglobal(L, "require");
    lua_pushliteral(L, "lancer.accuracy");
    lua_call(L, 1, 1);
    lua_getfield(L, -1, "setup");
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
    lua_getglobal(L, "require");
    lua_pushliteral(L, "lancer.accuracy");
    lua_call(L, 1, 1);
    lua_getfield(L, -1, "finish");
    lua_call(L, 0, 1);
    return 1;
}

/* After a --check run: lancer.check's verdict, as a boolean. */
static int check_verdict(lua_State *L)
{
    lua_getglobal(L, "require");
    lua_pushliteral(L, "lancer.check");
    lua_call(L, 1, 1);
    lua_getfield(L, -1, "finish");
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
    return report(L, docall(L, 1, 0));
}

/* ---- The REPL ------------------------------------------------------------ */

#define EOFMARK "<eof>"

static char *history_path;              /* NULL: keep no history */
static volatile sig_atomic_t prompt_interrupted;

/* Ctrl-C at the prompt: readline() returns NULL (its read fails with EINTR)
** and this flag tells that apart from Ctrl-D. */
static void on_prompt_sigint(int sig)
{
    (void)sig;
    prompt_interrupted = 1;
}

static void history_open(void)
{
    const char *home = getenv("HOME");
    rl_readline_name = "lancer";       /* ~/.editrc lines "lancer:..." */
    using_history();
    stifle_history(HISTORY_MAX);
    if (home == NULL || *home == '\0')
        return;
    history_path = malloc(strlen(home) + sizeof "/" HISTORY_FILE);
    if (history_path == NULL)
        return;
    sprintf(history_path, "%s/%s", home, HISTORY_FILE);
    read_history(history_path);         /* none yet is fine */
}

static void history_close(void)
{
    if (history_path != NULL)
        write_history(history_path);    /* an unwritable HOME is not an error */
    free(history_path);
    history_path = NULL;
}

static const char *get_prompt(lua_State *L, int firstline)
{
    if (lua_getglobal(L, firstline ? "_PROMPT" : "_PROMPT2") == LUA_TNIL) {
        lua_pop(L, 1);
        return lua_pushstring(L, firstline ? "> " : ">> ");
    }
    {
        const char *p = luaL_tolstring(L, -1, NULL);
        lua_remove(L, -2);
        return p;
    }
}

/* Reads one line onto the stack. 0 at end of input or on Ctrl-C. */
static int pushline(lua_State *L, int firstline)
{
    char *line;
    size_t len;
    prompt_interrupted = 0;
    line = readline(get_prompt(L, firstline));
    lua_pop(L, 1);                      /* the prompt */
    if (line == NULL)
        return 0;                       /* prompt_interrupted: Ctrl-C, else EOF */
    prompt_interrupted = 0;             /* a Ctrl-C that raced a whole line */
    len = strlen(line);
    if (len > 0 && line[len - 1] == '\n')
        line[--len] = '\0';
    lua_pushlstring(L, line, len);
    free(line);
    return 1;
}

static void saveline(const char *line)
{
    if (line[0] != '\0')
        add_history(line);
}

/* An expression prints its value: try "return LINE" first. */
static int addreturn(lua_State *L)
{
    const char *line = lua_tostring(L, -1);
    const char *retline = lua_pushfstring(L, "return %s;", line);
    int status = luaL_loadbuffer(L, retline, strlen(retline), "=stdin");
    if (status == LUA_OK) {
        lua_remove(L, -2);
        saveline(line);
    } else {
        lua_pop(L, 2);
    }
    return status;
}

/* A statement that ends early ("<eof>" in the message) reads more lines. */
static int incomplete(lua_State *L, int status)
{
    if (status == LUA_ERRSYNTAX) {
        size_t lmsg;
        const char *msg = lua_tolstring(L, -1, &lmsg);
        size_t mark = sizeof EOFMARK - 1;
        if (lmsg >= mark && strcmp(msg + lmsg - mark, EOFMARK) == 0) {
            lua_pop(L, 1);
            return 1;
        }
    }
    return 0;
}

static int multiline(lua_State *L)
{
    for (;;) {
        size_t len;
        const char *line = lua_tolstring(L, 1, &len);
        int status = luaL_loadbuffer(L, line, len, "=stdin");
        if (!incomplete(L, status) || !pushline(L, 0)) {
            saveline(line);
            return status;
        }
        lua_pushliteral(L, "\n");
        lua_insert(L, -2);
        lua_concat(L, 3);
    }
}

#define LINE_EOF         (-1)
#define LINE_INTERRUPTED (-2)

/* Leaves the compiled chunk (or an error message) alone on the stack. */
static int loadline(lua_State *L)
{
    int status;
    lua_settop(L, 0);
    if (!pushline(L, 1))
        return prompt_interrupted ? LINE_INTERRUPTED : LINE_EOF;
    if ((status = addreturn(L)) != LUA_OK)
        status = multiline(L);
    if (prompt_interrupted)             /* Ctrl-C on a continuation line */
        return LINE_INTERRUPTED;
    lua_remove(L, 1);
    return status;
}

/* Prints what the line returned, through 'print' as lua.c does. */
static void l_print(lua_State *L)
{
    int n = lua_gettop(L);
    if (n > 0) {
        luaL_checkstack(L, LUA_MINSTACK, "too many results to print");
        lua_getglobal(L, "print");
        lua_insert(L, 1);
        if (lua_pcall(L, n, 0, 0) != LUA_OK)
            l_message(lua_pushfstring(L, "error calling 'print' (%s)",
                                      lua_tostring(L, -1)));
    }
}

/* lancer.repl.terminal_size(): columns and rows of the terminal on stdout,
** asked each time (it may have been resized); nothing when it is not one. */
static int terminal_size(lua_State *L)
{
    struct winsize ws;
    if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) != 0 || ws.ws_col == 0 || ws.ws_row == 0)
        return 0;
    lua_pushinteger(L, ws.ws_col);
    lua_pushinteger(L, ws.ws_row);
    return 2;
}

/* Runs protected: renders at the prompt show a preview and are saved. */
static int repl_start(lua_State *L)
{
    lua_getglobal(L, "require");
    lua_pushliteral(L, "lancer.repl");
    lua_call(L, 1, 1);
    lua_getfield(L, -1, "start");
    lua_pushboolean(L, isatty(STDOUT_FILENO));
    lua_pushcfunction(L, terminal_size);
    lua_call(L, 2, 0);
    return 0;
}

static void do_repl(lua_State *L)
{
    struct sigaction old;
    const char *oldprogname = progname;
    int status;
    progname = NULL;
    printf("lancer %s (%s) -- renders are previewed and saved; ls(scene), "
           "show(img); Ctrl-D quits\n",
           LANCER_VERSION, LUA_VERSION);
    fflush(stdout);
    lua_pushcfunction(L, repl_start);
    report(L, docall(L, 0, 0));         /* without it, a plain Lua prompt */
    history_open();
    set_sigint(on_prompt_sigint, &old);     /* docall swaps in laction */
    while ((status = loadline(L)) != LINE_EOF) {
        if (status == LINE_INTERRUPTED) {
            fputs("\n", stdout);             /* a fresh, empty prompt */
            fflush(stdout);
            continue;
        }
        if (status == LUA_OK)
            status = docall(L, 0, LUA_MULTRET);
        if (status == LUA_OK)
            l_print(L);
        else
            report(L, status);
    }
    sigaction(SIGINT, &old, NULL);
    history_close();
    lua_settop(L, 0);
    fputs("\n", stdout);
    fflush(stdout);
    progname = oldprogname;
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
        if (report(L, docall(L, 1, 2)) != LUA_OK)
            return 0;
        if (!lua_toboolean(L, -2)) {
            usage_error("%s", lua_tostring(L, -1));
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
        if (report(L, docall(L, 0, 1)) != LUA_OK)
            return 0;
        if (lua_tointeger(L, -1) == 0) {
            fprintf(stderr, "lancer: option '%s' needs a script that calls "
                    "lancer.animate{...}; %s does not; try 'lancer --help'\n",
                    cl->anim.first, cl->script > 0 ? cl->argv[cl->script] : "the code run");
            cl->late_usage = 1;
            return 0;
        }
        lua_pop(L, 1);
    }
    if (cl->check) {
        lua_pushcfunction(L, check_verdict);
        if (report(L, docall(L, 0, 1)) != LUA_OK)
            return 0;
        if (!lua_toboolean(L, -1)) {
            cl->unstable = 1;
            return 0;
        }
        lua_pop(L, 1);
    }
    if (cl->accuracy) {
        lua_pushcfunction(L, accuracy_finish);
        if (report(L, docall(L, 0, 1)) != LUA_OK || !lua_toboolean(L, -1))
            return 0;
        lua_pop(L, 1);
    }
    if (cl->interactive) {
        do_repl(L);
    } else if (cl->script == 0 && cl->nchunks == 0) {
        if (isatty(STDIN_FILENO)) {
            do_repl(L);
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
    parsed = parse_args(&cl);
    if (parsed == PARSE_RUN)
        parsed = check_accuracy_args(&cl);
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
    report(L, status);
    lua_close(L);
    free(cl.chunks);
    free(cl.anim.frames);
    if (cl.unstable)
        return 3;
    if (cl.late_usage)
        return 2;
    return ok && status == LUA_OK ? 0 : 1;
}
