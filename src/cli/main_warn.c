/* main_warn.c: the lancer command's warn function: Lua warnings on stderr. */
#include <stdio.h>
#include <string.h>
#include <lua.h>
#include "main.h"

/* The binding's warnings (a render's "the scene has no light") are Lua
** warnings whose text starts "lancer: ", so any host sees them through its
** own warn function, and stock lua5.4 shows them under -W, as lauxlib's
** "Lua warning: ...". The command shows lancer's from the start, one line
** each as they are, and the others, once warn("@on") asks, as lauxlib's
** does ("Lua warning: "); warn("@off") silences both. */
enum { SHOW_LANCER, SHOW_ALL, SHOW_NONE };

typedef struct {
    int show;       /* SHOW_ */
    int piece;      /* 0: the next piece starts a warning; 1: it continues one
                    ** being written; 2: one being left out */
} warn_state;

static char warn_key;   /* registry[&warn_key]: the state's warn_state */

static void warn_function(void *ud, const char *msg, int tocont)
{
    warn_state *w = ud;
    if (w->piece == 0) {
        if (!tocont && msg[0] == '@') {            /* a control message */
            if (strcmp(msg, "@on") == 0)
                w->show = SHOW_ALL;
            else if (strcmp(msg, "@off") == 0)
                w->show = SHOW_NONE;
            return;
        }
        int ours = strncmp(msg, "lancer: ", 8) == 0;
        int shown = w->show == SHOW_ALL || (w->show == SHOW_LANCER && ours);
        if (shown && !ours)
            fputs("Lua warning: ", stderr);
        w->piece = shown ? 1 : 2;
    }
    if (w->piece == 1)
        fputs(msg, stderr);
    if (!tocont) {
        if (w->piece == 1) {
            fputc('\n', stderr);
            fflush(stderr);
        }
        w->piece = 0;
    }
}

void warn_install(lua_State *L)
{
    /* Kept by the registry until the state closes: finalizers that warn
    ** run before its last objects are freed. */
    warn_state *w = lua_newuserdatauv(L, sizeof *w, 0);
    w->show = SHOW_LANCER;
    w->piece = 0;
    lua_rawsetp(L, LUA_REGISTRYINDEX, &warn_key);
    lua_setwarnf(L, warn_function, w);
}
