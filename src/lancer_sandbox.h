/* lancer_sandbox.h: a Lua state for untrusted scene files, for a host that
** embeds lancer's Lua binding (the lancer command's --sandbox is one). Build
** src/cli/main_sandbox.c and src/cli/main_caps.c with the host, beside the
** binding's files (src/lua/); docs/manual.md, "Untrusted scenes: the sandbox",
** says what the state refuses and what it does not guard against. */
#ifndef LANCER_SANDBOX_H
#define LANCER_SANDBOX_H

#include <stddef.h>
#include <lua.h>

typedef struct {
    const char *read_dir;   /* files at or below it may be read; NULL: none */
    const char *write_dir;  /* ... written and read; NULL: none */
    size_t max_memory;      /* bytes Lua and the core may hold together; 0: no cap */
    double max_seconds;     /* wall-clock seconds from the open; 0: no cap */
    const char *lua_path;   /* where require finds lancer's Lua modules, as in
                            ** package.path ("lua/?.lua;lua/?/init.lua"); NULL:
                            ** package.preload only */
    void (*stuck)(void);    /* called on a watchdog thread when C code that cannot
                            ** be stopped runs on 1 s past max_seconds; NULL: none */
} lancer_sandbox_opts;

/* A new state: Lua's libraries but debug, "lancer.core" preloaded, and the
** restrictions in force. NULL, and a sentence in err, when it cannot be made.
** The memory cap is process-wide for the core: one capped state at a time. */
lua_State *lancer_sandbox_open(const lancer_sandbox_opts *o, char *err, size_t errlen);
void       lancer_sandbox_close(lua_State *L);   /* lua_close, then the watchdog */
int        lancer_sandbox_timed_out(lua_State *L);   /* the time cap was reached */

#endif
