/* main_defines.c: -D NAME=VALUE, a global the script reads: a number when
** VALUE reads as a Lua numeral, else the string. */
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "main.h"

static const char *const keywords[] = {
    "and", "break", "do", "else", "elseif", "end", "false", "for", "function", "goto",
    "if", "in", "local", "nil", "not", "or", "repeat", "return", "then", "true", "until",
    "while", NULL};

/* Why NAME cannot be a global set from the command line; NULL when it can. */
static const char *bad_name(lua_State *L, const char *name, size_t len)
{
    if (len == 0 || (name[0] >= '0' && name[0] <= '9'))
        return "is not a Lua name (letters, digits and _, not first a digit)";
    for (size_t i = 0; i < len; i++) {
        char c = name[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '_'))
            return "is not a Lua name (letters, digits and _, not first a digit)";
    }
    for (int k = 0; keywords[k]; k++)
        if (strlen(keywords[k]) == len && memcmp(keywords[k], name, len) == 0)
            return "is a Lua keyword";
    lua_pushlstring(L, name, len);
    int taken = lua_rawget(L, -2) != LUA_TNIL;        /* in the globals table */
    lua_pop(L, 1);
    return taken ? "is already a global (Lua's or lancer's): choose another name" : NULL;
}

int defines_set(lua_State *L)
{
    const struct cmdline *cl = lua_touserdata(L, 1);
    lua_pushglobaltable(L);
    for (int i = 0; i < cl->ndefines; i++) {
        const char *d = cl->defines[i], *eq = strchr(d, '=');
        const char *why = bad_name(L, d, (size_t)(eq - d));
        if (why) {
            char msg[300];
            snprintf(msg, sizeof msg, "option '-D %s': '%.*s' %s", d, (int)(eq - d), d, why);
            lua_pushboolean(L, 0);
            lua_pushstring(L, msg);
            return 2;
        }
        /* lua_stringtonumber takes what the Lua lexer reads as a number. */
        if (lua_stringtonumber(L, eq + 1) == 0)
            lua_pushstring(L, eq + 1);
        lua_pushlstring(L, d, (size_t)(eq - d));
        lua_insert(L, -2);
        lua_rawset(L, -3);
    }
    lua_pushboolean(L, 1);
    return 1;
}
