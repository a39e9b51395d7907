/* main_args.c: the lancer command's options, all checked before anything runs. */
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>

#include <lauxlib.h>
#include <lua.h>

#include "lua/lua_fields.h"
#include "main.h"

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
"  lancer -e 'print(lancer.version)'\n"
"  lancer -i scene.lua           run scene.lua, then the interactive prompt\n""  lancer --watch scene.lua out.png\n"
"                                run it again on each save, drawn in the terminal\n"
"  lancer --check scene.lua      is the scene numerically stable?\n"
"  lancer --video orbit.mp4 orbit.lua\n"
"                                render an animation's frames, then an mp4\n"
"  lancer --frames 1-24 --skip-existing orbit.lua\n"
"                                frames 1 to 24 of it, those not yet written\n"
"  lancer --accuracy --knob samples=1,4,16,64 scene.lua\n"
"                                error against time over those levels\n"
"  lancer -D size=2 -D name=ball --seed 7 scene.lua\n"
"                                globals size (2, a number) and name ('ball')\n"
"  lancer --tile 1/4 scene.lua out.exr\n"
"                                the second quarter of the rows: out.tile-1-of-4.exr\n"
"  lancer --merge out.exr out.tile-*-of-4.exr\n"
"                                the four parts as the whole frame\n"
"  lancer                        the interactive prompt\n"
"\n"
"Options go before the script: whatever follows it is the script's, as with\n"
"lua5.4, so 'lancer scene.lua out.png --width 100' hands --width to the script\n"
"(lancer notes it on stderr).\n"
"  -e CODE       run the Lua string CODE, with lancer loaded (may be repeated)\n"
"  -i            enter the interactive prompt after the script\n"
"  -             read the script from standard input\n"
"  --            stop handling options\n"
"  --width W     render at width W, whatever the script asks (positive integer)\n"
"  --height H    render at height H, likewise\n"
"  --samples N   take N samples per pixel, likewise\n"
"  --seed N      render with seed N (a whole number from 0), likewise; and\n"
"                math.random starts from N (animation frames: from N and the frame)\n"
"  --threads N   render on N threads (0: one per core), likewise\n"
"  -D NAME=VALUE set the global NAME before the script runs: a number when VALUE\n"
"                reads as a Lua number (2, 0.5, 1e3, 0x10), else the string\n"
"                (may be repeated; NAME may not be a global Lua already has)\n"
"  --stats       print each render's ledger: rays by kind, tests, phases, effects\n"
"  --progress MODE\n"
"                bar (by default when stderr is a terminal), none, or lines: one\n"
"                'progress N/100' line on stderr per batch of finished tiles that\n"
"                takes the render past another whole percent, 0/100 to 100/100,\n"
"                for render farm managers reading a log\n"
"  --watch       run the script, then again each time it or a file it loaded\n"
"                (dofile, loadfile, require) changes, its renders drawn in the\n"
"                terminal pass by pass; an error keeps the last picture. Ctrl-C\n"
"                quits\n"
"  --check       render each image small at scales 1e-3, 1, 1e3 and moved 1e6\n"
"                away; report differing pixels, NaN and self-hits (exit 3 if\n"
"                the scene is numerically unstable). Writes none of the images\n"
"                the script saves: its files stay as they were\n"
"\n"
"Animations (scripts calling lancer.animate{...}; frames are numbered from 1\n"
"unless the script sets 'first'):\n"
"  --frames LIST frames to render: 7, 1-48, 1-48:4 or 1-48x4 (every 4th), 1,5,9-12\n"
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
"One frame across machines (the manual's \"Render farms\"):\n"
"  --region X0,Y0,X1,Y1\n"
"                render only the pixels X0 <= x < X1, Y0 <= y < Y1 of each frame\n"
"                (pixel edges from 0 at the top-left), each as in the whole frame;\n"
"                saves go to NAME.region-X0-Y0-X1-Y1.EXT, holding their place\n"
"  --tile K/N    the same for tile K of N (0 <= K < N): rows H*K/N to H*(K+1)/N,\n"
"                saved to NAME.tile-K-of-N.EXT\n"
"  --merge OUT PART...\n"
"                assemble the parts of one frame into OUT (all .png or all .exr):\n"
"                the same bytes as the frame saved whole; nothing else runs\n"
"\n"
"  --accuracy    render each image the script asks for at every level of each\n"
"                --knob, against a reference 16x the largest; print error, time\n"
"                and efficiency, write a CSV and a plot (see the README) into\n"
"                --out, and none of the images the script saves\n"
"  --knob NAME=L1,L2,...  with --accuracy: samples, cone_samples,\n"
"                light_samples, max_depth (depth) or indirect, increasing\n"
"                levels, or noise (decreasing, in (0, 1]); may be repeated\n"
"  --seeds N     with --accuracy: renders per level, N >= 2 (default 4)\n"
"  --out DIR     with --accuracy: where the CSV and PNG go (default out/accuracy)\n"
"\n"
"Untrusted scenes (the manual's \"Untrusted scenes: the sandbox\"):\n"
"  --sandbox     run the script sandboxed: no programs, C modules, binary chunks\n"
"                or debug library; files read only below the script's folder\n"
"                (and --sandbox-out), written only below --sandbox-out; with\n"
"                the caps below, by default 1024 MB and 600 s\n"
"  --sandbox-out DIR\n"
"                with --sandbox: the existing folder the script may write in\n"
"                (by default none: img:save and io.open for writing are refused)\n"
"  --max-memory MB\n"
"                cap the memory of Lua and the renderer together at MB megabytes\n"
"                (10^6 bytes; 0: no cap): past it, an 'out of memory' error\n"
"  --max-seconds S\n"
"                stop the run after S seconds of wall time, Lua code and renders\n"
"                alike (0: no cap); exit status 4\n"
"  --allow-bytecode\n"
"                run precompiled (binary) Lua chunks, refused by default since\n"
"                Lua does not verify them; not with --sandbox\n"
"\n"
"  --help        print this help and exit\n"
"  --version     print the version and exit\n"
"\n"
"The script sees its arguments in 'arg' and '...', as with lua5.4.\n"
"math.random starts from a fixed seed, so a script renders the same each run.\n"
"The prompt prints the value of an expression, draws each render in the\n"
"terminal pass by pass and saves it to out/repl_NNN.png; its history is kept\n"
"in ~/" HISTORY_FILE ". Ctrl-C interrupts running code or a render (keeping\n"
"the render's last whole pass, saved too), Ctrl-D quits.\n"
"\n"
"Exit status: 0 success, 1 script error, 2 usage error, 3 unstable (--check),\n"
"4 time cap reached (--max-seconds, --sandbox).\n", stdout);
}

/* The long options, for did-you-mean hints and for noticing one placed
** after the script. */
static const char *const long_options[] = {
    "--width", "--height", "--samples", "--stats", "--check", "--frames", "--frame",
    "--shard", "--skip-existing", "--list-frames", "--video", "--output",
    "--accuracy", "--knob", "--seeds", "--out", "--sandbox", "--sandbox-out",
    "--max-memory", "--max-seconds", "--allow-bytecode", "--help", "--version",
    "--seed", "--threads", "--region", "--tile", "--merge", "--progress", "--watch",
    NULL};

/* argv's word without its "=value". */
static void option_name(const char *arg, char *out, size_t n)
{
    size_t len = strcspn(arg, "=");
    if (len >= n)
        len = n - 1;
    memcpy(out, arg, len);
    out[len] = '\0';
}

static int unknown_option(const char *arg)
{
    char name[64];
    option_name(arg, name, sizeof name);
    const char *hint = NULL;
    if (strncmp(name, "--", 2) == 0)           /* '-x' is not one letter from '-e' */
        hint = lf_closest(name, long_options);
    if (!hint)
        return args_usage_error("unknown option '%s'", arg);
    fprintf(stderr, "lancer: unknown option '%s'; did you mean '%s'?\n", name, hint);
    return PARSE_USAGE;
}

/* Arguments after the script are the script's (Lua's convention); one
** that is a lancer option was likely meant for lancer: say so, once. */
static void note_late_options(char **argv, int script)
{
    for (int i = script + 1; argv[i] != NULL; i++) {
        char name[64];
        option_name(argv[i], name, sizeof name);
        for (int k = 0; long_options[k]; k++)
            if (strcmp(name, long_options[k]) == 0) {
                fprintf(stderr, "lancer: note: '%s' comes after the script, so the "
                        "script gets it; put options before the script\n", name);
                return;
            }
    }
}

int args_usage_error(const char *fmt, const char *what)
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

/* Whether the core takes v as the render option `name` (width, height or
** samples), so that a value no render can use stops the command here. */
static int render_option_ok(const char *name, lua_Integer v)
{
    lc_render_options o = lc_render_options_default();
    lc_error err;
    int *field = strcmp(name, "--width") == 0 ? &o.width
               : strcmp(name, "--height") == 0 ? &o.height
               : strcmp(name, "--samples") == 0 ? &o.samples : NULL;
    if (!field)
        return 1;
    *field = (int)v;
    if (lc_render_options_check(&o, &err) == LC_OK)
        return 1;
    fprintf(stderr, "lancer: option '%s': %s; try 'lancer --help'\n", name, err.msg);
    return 0;
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
            return args_usage_error("option '%s' needs a value", name);
        v = cl->argv[++*i];
    }
    if (!parse_positive(v, out)) {
        fprintf(stderr, "lancer: option '%s' needs a positive integer, got '%s'; "
                "try 'lancer --help'\n", name, v);
        return PARSE_USAGE;
    }
    return render_option_ok(name, *out) ? PARSE_RUN : PARSE_USAGE;
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

/* Reads a --frames list: items N, A-B, A-B:S or A-BxS, separated by commas. With L,
** appends each item as {A, B, S, option = flag} to the table on top of L's
** stack. Returns NULL, or why the list is wrong. */
const char *args_frame_list(const char *s, const char *flag, lua_State *L)
{
    do {
        long a, b, step = 1;
        if (!frame_number(&s, &a))
            return "frames are whole numbers from 0";
        b = a;
        if (*s == '-' && (s++, !frame_number(&s, &b)))
            return "a range is A-B";
        /* A-B:S, or A-BxS as render farm tools write it (Deadline, Tractor). */
        if ((*s == ':' || *s == 'x') && (s++, !frame_number(&s, &step) || step < 1))
            return "a step is a whole number from 1";
        if (*s != ',' && *s != '\0')
            return "items are N, A-B, A-B:STEP or A-BxSTEP, separated by commas";
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
            lua_pushstring(L, flag);
            lua_setfield(L, -2, "option");
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
    static const char *const names[] = {"--frames", "--frame", "--shard",
                                        "--skip-existing", "--list-frames", "--video",
                                        "--output", "-o", NULL};
    static const char *const video_ext[] = {".mp4", ".mkv", ".mov", ".webm", ".gif",
                                            NULL};
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
            *st = args_usage_error("option '%s' takes no value", name);
            return 1;
        }
        *(name[2] == 's' ? &an->skip_existing : &an->list_frames) = 1;
        return 1;
    }
    if ((v = option_value(cl, i, name)) == NULL) {
        *st = args_usage_error("option '%s' needs a value", name);
        return 1;
    }
    if (strcmp(name, "--frames") == 0 || strcmp(name, "--frame") == 0) {
        if ((why = args_frame_list(v, name, NULL)) != NULL) {
            fprintf(stderr, "lancer: option '%s' needs frames like 7, 1-48, 1-48:2 or "
                    "1,5,9-12, got '%s' (%s); try 'lancer --help'\n", name, v, why);
            *st = PARSE_USAGE;
        } else if (strcmp(name, "--frame") == 0 && strpbrk(v, ",-:x")) {
            *st = bad_value(name, "one frame number (--frames takes lists)", v);
        } else {
            an->frame_flags[an->nframes] = name;
            an->frames[an->nframes++] = v;
        }
    } else if (strcmp(name, "--shard") == 0) {
        long sk = 0, sn = 0;
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
        return args_usage_error("option '%s' needs a value", name);
    if (*v == '\0')
        return args_usage_error("option '%s' needs a value", name);
    if (name[2] == 'o') {
        cl->out = v;
    } else if (cl->nknobs == ACCURACY_KNOBS) {
        return args_usage_error("option '%s' may be given at most 8 times", name);
    } else {
        cl->knobs[cl->nknobs++] = v;
    }
    return PARSE_RUN;
}

/* The accuracy options go together: caught before anything runs. */
int args_check_accuracy(const struct cmdline *cl)
{
    if (!cl->accuracy) {
        const char *stray = cl->nknobs ? "--knob" : cl->seeds ? "--seeds"
                          : cl->out ? "--out" : NULL;
        return stray ? args_usage_error("option '%s' needs --accuracy", stray)
                     : PARSE_RUN;
    }
    if (cl->check)
        return args_usage_error("option '%s' cannot go with --check", "--accuracy");
    if (cl->script == 0)
        return args_usage_error("option '%s' needs a script", "--accuracy");
    if (cl->nknobs == 0)
        return args_usage_error("option '%s' needs --knob NAME=L1,L2,...", "--accuracy");
    if (cl->seeds == 1)
        return args_usage_error("option '%s' needs at least 2 seeds, got 1", "--seeds");
    return PARSE_RUN;
}

/* ---- The sandbox and the caps ---------------------------------------------- */

/* "--max-memory MB": digits, 0 (no cap) up to INT_MAX. */
static int parse_memory(struct cmdline *cl, int *i)
{
    const char *v = option_value(cl, i, "--max-memory"), *s;
    lua_Integer mb = 0;
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", "--max-memory");
    for (s = v; *s >= '0' && *s <= '9' && mb <= INT_MAX; s++)
        mb = mb * 10 + (*s - '0');
    if (*s != '\0' || mb > INT_MAX)
        return bad_value("--max-memory", "a whole number of megabytes (0: no cap)", v);
    cl->max_memory = mb;
    return PARSE_RUN;
}

/* "--max-seconds S": a decimal number, 0 (no cap) up to 1e9. */
static int parse_seconds(struct cmdline *cl, int *i)
{
    const char *v = option_value(cl, i, "--max-seconds");
    char *end;
    double s;
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", "--max-seconds");
    s = strtod(v, &end);
    if (*end != '\0' || !(s >= 0 && s <= 1e9) || strchr(v, 'x') ||
        strchr(v, 'X'))
        return bad_value("--max-seconds", "a number of seconds from 0 (no cap) to 1e9",
                         v);
    cl->max_seconds = s;
    return PARSE_RUN;
}

static int parse_sandbox_out(struct cmdline *cl, int *i)
{
    const char *v = option_value(cl, i, "--sandbox-out");
    struct stat st;
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", "--sandbox-out");
    if (stat(v, &st) != 0 || !S_ISDIR(st.st_mode))
        return bad_value("--sandbox-out", "an existing folder", v);
    cl->sandbox_out = v;
    return PARSE_RUN;
}

/* What goes with the caps and --sandbox: caught before anything runs. */
int args_check_limits(const struct cmdline *cl)
{
    int prompt = cl->interactive ||
                 (cl->script == 0 && cl->nchunks == 0 && isatty(STDIN_FILENO));
    if (cl->sandbox_out && !cl->sandbox)
        return args_usage_error("option '%s' needs --sandbox", "--sandbox-out");
    if (cl->has_region && cl->tile_n)
        return args_usage_error("option '%s' cannot go with --tile", "--region");
    if ((cl->has_region || cl->tile_n) && cl->anim.video)
        return args_usage_error("option '%s' cannot go with --region or --tile (merge "
                                "the parts first)", "--video");
    if (!cl->sandbox) {
        if (prompt && cl->max_seconds > 0)
            return args_usage_error("option '%s' cannot go with the prompt",
                                    "--max-seconds");
        return PARSE_RUN;
    }
    if (cl->allow_bytecode)
        return args_usage_error("option '%s' cannot go with --sandbox",
                                "--allow-bytecode");
    if (cl->accuracy)
        return args_usage_error("option '%s' cannot go with --sandbox (it runs "
                                "gnuplot and writes where --out says)", "--accuracy");
    if (cl->anim.video)
        return args_usage_error("option '%s' cannot go with --sandbox (it runs "
                                "ffmpeg)", "--video");
    if (prompt)
        return args_usage_error("option '%s' runs a script, '-' or -e code, not the "
                                "prompt", "--sandbox");
    return PARSE_RUN;
}

/* ---- Seeds, threads, globals, parts of a frame ----------------------------- */

/* Digits only, from 0 up to max; moves *s past them. */
static int whole_number(const char **s, lua_Integer max, lua_Integer *out)
{
    lua_Integer v = 0;
    if (**s < '0' || **s > '9')
        return 0;
    for (; **s >= '0' && **s <= '9'; ++*s) {
        if (v > (max - (**s - '0')) / 10)
            return 0;
        v = v * 10 + (**s - '0');
    }
    *out = v;
    return 1;
}

/* "--seed N" (0 up to 2^63 - 1) or "--threads N" (0 up to LC_MAX_THREADS). */
static int parse_count(struct cmdline *cl, int *i, const char *name, lua_Integer max,
                       lua_Integer *out, const char *want)
{
    const char *v = option_value(cl, i, name), *p = v;
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", name);
    if (!whole_number(&p, max, out) || *p)
        return bad_value(name, want, v);
    return PARSE_RUN;
}

/* "-D NAME=VALUE" or "-DNAME=VALUE"; the name is checked once Lua runs. */
static int parse_define(struct cmdline *cl, int *i)
{
    const char *a = cl->argv[*i], *v = a[2] ? a + 2 : cl->argv[*i + 1];
    if (v == NULL)
        return args_usage_error("option '%s' needs NAME=VALUE", "-D");
    if (!a[2])
        ++*i;
    if (!strchr(v, '=') || v[0] == '=')
        return bad_value("-D", "NAME=VALUE, such as size=2", v);
    cl->defines[cl->ndefines++] = v;
    return PARSE_RUN;
}

/* "--region X0,Y0,X1,Y1": pixel edges, X0 < X1 and Y0 < Y1. */
static int parse_region(struct cmdline *cl, int *i)
{
    const char *v = option_value(cl, i, "--region"), *p = v;
    lua_Integer r[4];
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", "--region");
    for (int k = 0; k < 4; k++)
        if (!whole_number(&p, LC_MAX_SIDE, &r[k]) || *p++ != (k < 3 ? ',' : '\0'))
            return bad_value("--region", "X0,Y0,X1,Y1, four whole numbers such as "
                             "0,0,320,240", v);
    if (r[0] >= r[2] || r[1] >= r[3])
        return bad_value("--region", "X0 < X1 and Y0 < Y1", v);
    for (int k = 0; k < 4; k++)
        cl->region[k] = (int)r[k];
    cl->has_region = 1;
    return PARSE_RUN;
}

static int parse_tile(struct cmdline *cl, int *i)
{
    const char *v = option_value(cl, i, "--tile"), *p = v;
    lua_Integer k = 0, n = 0;
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", "--tile");
    if (!whole_number(&p, LC_MAX_SIDE, &k) || *p++ != '/' ||
        !whole_number(&p, LC_MAX_SIDE, &n) || *p || n < 1 || k >= n)
        return bad_value("--tile", "K/N with 0 <= K < N, such as 0/4", v);
    cl->tile_k = (int)k;
    cl->tile_n = (int)n;
    return PARSE_RUN;
}

/* "--progress MODE": bar, lines or none. */
static int parse_progress(struct cmdline *cl, int *i)
{
    static const char *const modes[] = {"bar", "lines", "none", NULL};
    const char *v = option_value(cl, i, "--progress");
    if (v == NULL || *v == '\0')
        return args_usage_error("option '%s' needs a value", "--progress");
    for (int k = 0; modes[k]; k++)
        if (strcmp(v, modes[k]) == 0) {
            cl->progress = modes[k];
            return PARSE_RUN;
        }
    return bad_value("--progress", "bar, lines or none", v);
}

/* What --watch goes with: a script file, and nothing that writes or
** reports something else than the script's images. */
int args_check_watch(const struct cmdline *cl)
{
    if (!cl->watch)
        return PARSE_RUN;
    if (cl->script == 0 || cl->script_stdin)
        return args_usage_error("option '%s' needs a script file to watch", "--watch");
    const char *other = cl->interactive ? "-i" : cl->check ? "--check"
                      : cl->accuracy ? "--accuracy" : cl->anim.first ? cl->anim.first
                      : cl->sandbox ? "--sandbox" : cl->max_seconds > 0 ? "--max-seconds"
                      : NULL;
    if (other)
        return args_usage_error("option '--watch' cannot go with %s", other);
    return PARSE_RUN;
}

/* Checks every option before anything runs, so a typo costs no render. */
int args_parse(struct cmdline *cl)
{
    char **argv = cl->argv;
    int i;
    for (i = 1; argv[i] != NULL; i++) {
        const char *a = argv[i];
        int st = PARSE_RUN;
        if (a[0] != '-') {                       /* the script */
            cl->script = i;
            note_late_options(argv, i);
            return PARSE_RUN;
        } else if (strcmp(a, "-") == 0) {
            cl->script = i;
            cl->script_stdin = 1;
            note_late_options(argv, i);
            return PARSE_RUN;
        } else if (strcmp(a, "--") == 0) {
            cl->script = argv[i + 1] ? i + 1 : 0;
            if (cl->script)
                note_late_options(argv, cl->script);
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
                return args_usage_error("option '%s' needs an argument", "-e");
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
        } else if (strcmp(a, "--sandbox") == 0) {
            cl->sandbox = 1;
        } else if (is_opt(a, "--sandbox-out")) {
            st = parse_sandbox_out(cl, &i);
        } else if (is_opt(a, "--max-memory")) {
            st = parse_memory(cl, &i);
        } else if (is_opt(a, "--max-seconds")) {
            st = parse_seconds(cl, &i);
        } else if (strcmp(a, "--allow-bytecode") == 0) {
            cl->allow_bytecode = 1;
        } else if (is_opt(a, "--seed")) {
            st = parse_count(cl, &i, "--seed", INT64_MAX, &cl->seed,
                             "a whole number from 0");
        } else if (is_opt(a, "--threads")) {
            st = parse_count(cl, &i, "--threads", LC_MAX_THREADS, &cl->threads,
                             "a whole number of threads from 0 (one per core) to 256");
        } else if (strncmp(a, "-D", 2) == 0) {
            st = parse_define(cl, &i);
        } else if (is_opt(a, "--region")) {
            st = parse_region(cl, &i);
        } else if (is_opt(a, "--tile")) {
            st = parse_tile(cl, &i);
        } else if (is_opt(a, "--progress")) {
            st = parse_progress(cl, &i);
        } else if (strcmp(a, "--watch") == 0) {
            cl->watch = 1;
        } else if (strcmp(a, "--merge") == 0) {
            if (argv[i + 1] == NULL || argv[i + 2] == NULL)
                return args_usage_error("option '%s' needs OUT and at least one part",
                                        "--merge");
            cl->merge = i + 1;
            cl->script = 0;
            return PARSE_RUN;
        } else {
            return unknown_option(a);
        }
        if (st != PARSE_RUN)
            return st;
    }
    cl->script = 0;
    return PARSE_RUN;
}

