/* main_repl.c: the lancer command's interactive prompt (libedit, history, Ctrl-C). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/ioctl.h>

#include <editline/readline.h>
#include <lauxlib.h>
#include <lua.h>

#include "main.h"

#define HISTORY_MAX    1000              /* lines kept across sessions */
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

/* An expression prints its value: try "return LINES" first, LINES being
** the line or the lines read so far, on top; on success the chunk goes on
** top of them. */
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

/* Reads lines until what was typed compiles (as an expression first, so a
** call spread over lines prints its value as a one-line one does) or is
** wrong for a reason more lines cannot mend. */
static int multiline(lua_State *L)
{
    for (;;) {
        size_t len;
        const char *line = lua_tolstring(L, 1, &len);
        if (addreturn(L) == LUA_OK)
            return LUA_OK;
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
            host_message(lua_pushfstring(L, "error calling 'print' (%s)",
                                      lua_tostring(L, -1)));
    }
}

/* lancer.repl.terminal_size(): columns and rows of the terminal on stdout,
** asked each time (it may have been resized); nothing when it is not one. */
int repl_terminal_size(lua_State *L)
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
    host_module_field(L, "lancer.repl", "start");
    lua_pushboolean(L, isatty(STDOUT_FILENO));
    lua_pushcfunction(L, repl_terminal_size);
    lua_call(L, 2, 0);
    return 0;
}

/* After a line that failed: lancer.repl keeps what a stopped render left. */
static int repl_after_error(lua_State *L)
{
    host_module_field(L, "lancer.repl", "after_error");
    if (lua_isfunction(L, -1))
        lua_call(L, 0, 0);
    return 0;
}

void repl_run(lua_State *L)
{
    struct sigaction old;
    const char *oldprogname = host_progname;
    int status;
    host_progname = NULL;
    printf("lancer %s (%s) -- renders are previewed and saved; ls(scene), "
           "show(img); Ctrl-D quits\n",
           LANCER_VERSION, LUA_VERSION);
    fflush(stdout);
    lua_pushcfunction(L, repl_start);
    host_report(L, host_docall(L, 0, 0));         /* without it, a plain Lua prompt */
    history_open();
    host_set_sigint(on_prompt_sigint, &old);     /* host_docall swaps in laction */
    while ((status = loadline(L)) != LINE_EOF) {
        if (status == LINE_INTERRUPTED) {
            fputs("\n", stdout);             /* a fresh, empty prompt */
            fflush(stdout);
            continue;
        }
        if (status == LUA_OK)
            status = host_docall(L, 0, LUA_MULTRET);
        if (status == LUA_OK) {
            l_print(L);
        } else {
            host_report(L, status);
            lua_pushcfunction(L, repl_after_error);
            host_report(L, host_docall(L, 0, 0));
        }
    }
    sigaction(SIGINT, &old, NULL);
    history_close();
    lua_settop(L, 0);
    fputs("\n", stdout);
    fflush(stdout);
    host_progname = oldprogname;
}

