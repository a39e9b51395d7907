/* lua_fields.h: reading named-argument tables, with errors that name the field. */
#ifndef LUA_FIELDS_H
#define LUA_FIELDS_H

#include <lua.h>
#include <lauxlib.h>
#include "lancer.h"

/* Checks that argument `arg` is a table whose keys are all in `known`
** (NULL-terminated); raises "unknown field 'x'; did you mean 'y'?" otherwise. */
void lf_open(lua_State *L, int arg, const char *const known[]);

/* The name in `known` (NULL-terminated) at most two edits from word (a
** swap of neighbours is one), for did-you-mean hints; NULL when none is.
** The lancer command's options use it too. */
const char *lf_closest(const char *word, const char *const known[]);

/* Raises "bad argument #arg to 'fn' (field 'name': <detail>)". */
int lf_error(lua_State *L, int arg, const char *field, const char *fmt, ...);

/* Raises the core's error: with the field it names when there is one. */
int lf_raise(lua_State *L, int arg, const lc_error *err);

/* Each reads t[name]; absent: the default, or an error when required. */
int      lf_present(lua_State *L, int arg, const char *name);
double   lf_number(lua_State *L, int arg, const char *name, int required, double def);
int      lf_integer(lua_State *L, int arg, const char *name, int required, int def);
int      lf_boolean(lua_State *L, int arg, const char *name, int def);
lc_vec3  lf_vec3(lua_State *L, int arg, const char *name, int required, lc_vec3 def);
lc_color lf_color(lua_State *L, int arg, const char *name, int required, lc_color def);
int      lf_option(lua_State *L, int arg, const char *name, const char *const opts[],
                   int def);
/* Pushes t[name] when it is userdata of type tname (nil when absent and not
** required) and returns it. */
void    *lf_udata(lua_State *L, int arg, const char *name, const char *tname, int required);

/* Reads a value at stack index idx as a colour, or NULL-safe errors at `what`. */
int lf_to_color(lua_State *L, int idx, lc_color *out, char *why, size_t whylen);
int lf_to_vec3(lua_State *L, int idx, lc_vec3 *out, char *why, size_t whylen);

void lf_push_vec3(lua_State *L, lc_vec3 v);
/* For __tostring: "%.6g" numbers, and "name = {x, y, z}". */
void lf_add_number(luaL_Buffer *b, double x);
void lf_add_vec3(luaL_Buffer *b, const char *name, lc_vec3 v);
void lf_push_color(lua_State *L, lc_color c);

#endif
