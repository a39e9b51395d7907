/* main.h: what the lancer command's files share: its command line,
** running Lua code with Ctrl-C armed, the caps and the sandbox. */
#ifndef LC_MAIN_H
#define LC_MAIN_H

#include <signal.h>
#include <lua.h>
#include "lancer.h"

#define LANCER_VERSION LC_VERSION
#define ACCURACY_KNOBS 8                 /* --knob options one run takes */
#define HISTORY_FILE   ".lancer_history" /* the REPL's, under $HOME */

/* The animation options: lancer.host hands them to lancer.anim. */
struct anim_opts {
    const char **frames;    /* --frames and --frame lists, checked; nframes of them */
    const char **frame_flags;  /* the option each came with, "--frames" or "--frame" */
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
    int sandbox;            /* --sandbox */
    const char *sandbox_out;    /* --sandbox-out DIR; NULL: not given */
    lua_Integer max_memory; /* --max-memory MB; -1: not given, 0: no cap */
    double max_seconds;     /* --max-seconds S; -1: not given, 0: no cap */
    int allow_bytecode;     /* --allow-bytecode */
    lua_Integer seed;       /* --seed N; -1: not given */
    lua_Integer threads;    /* --threads N; -1: not given */
    const char **defines;   /* -D name=value, as given; ndefines of them */
    int ndefines;
    int region[4];          /* --region x0,y0,x1,y1 */
    int has_region;
    int tile_k, tile_n;     /* --tile K/N; tile_n 0: not given */
    int merge;              /* --merge: argv index of OUT; 0: not given */
    const char *progress;   /* --progress MODE: "bar", "lines" or "none"; NULL: not
                            ** given (the bar on a terminal) */
    int watch;              /* --watch: run the script again on each change */
    int timed_out;          /* the run reached --max-seconds: exit 4 */
};

/* What parsing the command line says to do next. */
enum { PARSE_RUN, PARSE_DONE, PARSE_USAGE };

/* main_args.c: the command line. */
int         args_parse(struct cmdline *cl);          /* PARSE_*; usage errors printed */
int         args_check_accuracy(const struct cmdline *cl);
int         args_check_limits(const struct cmdline *cl);
int         args_check_watch(const struct cmdline *cl);
/* Prints "lancer: " fmt (with what) and a hint; returns PARSE_USAGE. */
int         args_usage_error(const char *fmt, const char *what);
/* Checks a --frames list; with L, appends {A, B, STEP, option = flag} items
** to the table on top of its stack. NULL, or why the list is wrong. */
const char *args_frame_list(const char *s, const char *flag, lua_State *L);

/* main.c: running Lua code, after lua.c. */
extern const char *host_progname;        /* prefix of errors; NULL in the REPL */
void host_set_sigint(void (*handler)(int), struct sigaction *old);
void host_message(const char *msg);      /* to stderr, after host_progname */
int  host_report(lua_State *L, int status);   /* prints the error on the stack */
int  host_docall(lua_State *L, int narg, int nres);  /* pcall with Ctrl-C armed */
/* Pushes require(module)[field] (the module stays under it), taking what
** package.loaded holds first. Unprotected. */
void host_module_field(lua_State *L, const char *module, const char *field);

/* main_caps.c: a state's memory cap and time cap. */
struct caps {
    size_t max_memory;      /* bytes, Lua's and the core's together; 0: no cap */
    double max_seconds;     /* wall clock from caps_newstate; 0: no cap */
    void (*stuck)(void);    /* called on the watchdog thread when C code runs on
                            ** 1 s past the time cap; NULL: none */
};
lua_State *caps_newstate(const struct caps *c);  /* luaL_newstate, capped; NULL */
int    caps_close(lua_State *L);        /* lua_close; 1 when the time cap was reached */
int    caps_expired(lua_State *L);      /* the time cap was reached */
/* Raises "time cap reached<what> ..." at luaL_where(L, level). */
int    caps_time_error(lua_State *L, int level, const char *what);
void   caps_rehook(lua_State *L);       /* the time cap's hook back, after another */
/* coroutine.create and wrap give new coroutines the time cap's hook; after
** the libraries are open. */
void   caps_coroutines(lua_State *L);
size_t caps_memory_refused(lua_State *L);   /* the cap, when it refused Lua a block */
void   caps_collect(lua_State *L);      /* a full collection when the core holds much */

/* main_sandbox.c: the restrictions (lancer_sandbox.h is the embedder's side). */
struct sandbox_policy {
    const char *read_dir;   /* files below it may be read; NULL: none */
    const char *write_dir;  /* files below it may be written and read; NULL: none */
    const char *lua_path;   /* require's path to lancer's modules; NULL: preload only */
    const char *no_write;   /* why nothing may be written, when write_dir is NULL */
};
/* Makes load, loadfile, dofile and require's file searcher take text only. */
void sandbox_text_only(lua_State *L);
/* Wraps the host hook: the time cap's message for renders. After setup;
** a lua_CFunction. */
int  sandbox_hook(lua_State *L);
/* Seals the state (lua_CFunction: the policy as light userdata at 1). */
int  sandbox_seal(lua_State *L);
/* luaL_openlibs without debug. */
void sandbox_openlibs(lua_State *L);

/* main_merge.c: lancer --merge OUT PARTS...; the exit status. */
int merge_run(const struct cmdline *cl);
/* main_defines.c: sets each -D name=value as a global (a number when the
** value reads as one); false, with a usage error printed, for a bad one.
** A lua_CFunction: the cmdline as light userdata at 1. */
int defines_set(lua_State *L);

/* main_repl.c: the interactive prompt. */
void repl_run(lua_State *L);
/* Columns and rows of the terminal on stdout, asked each time; nothing when
** it is not one. A lua_CFunction, for lancer.repl and lancer.watch. */
int  repl_terminal_size(lua_State *L);

/* main_warn.c: the command's warn function, set on each new state: lancer's
** warnings shown from the start, the others after warn("@on"). */
void warn_install(lua_State *L);

/* main_watch.c: lancer --watch: runs the script through run_once (a fresh
** state each time, 1 when it ran clean) whenever a file it read changes, until
** Ctrl-C; the exit status. */
int watch_run(struct cmdline *cl, int (*run_once)(struct cmdline *cl, char ***files));

#endif
