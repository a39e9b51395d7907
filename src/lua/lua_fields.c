/* lua_fields.c: reading named-argument tables, with errors that name the field. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <lauxlib.h>
#include "lua_fields.h"

int lf_error(lua_State *L, int arg, const char *field, const char *fmt, ...)
{
    char detail[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(detail, sizeof detail, fmt, ap);
    va_end(ap);
    if (field && *field)
        lua_pushfstring(L, "field '%s': %s", field, detail);
    else
        lua_pushstring(L, detail);
    return luaL_argerror(L, arg, lua_tostring(L, -1));
}

int lf_raise(lua_State *L, int arg, const lc_error *err)
{
    if (err->code == LC_EARG)
        return lf_error(L, arg, err->field, "%s", err->msg);
    return luaL_error(L, "%s", err->msg);
}

/* Edit distance counting a swap of neighbours as one edit (optimal string
** alignment), for the did-you-mean hint: 'fvo' is one edit from 'fov'. */
static size_t distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    static const size_t far = 99;
    if (la >= 31 || lb >= 31)
        return far;
    size_t d[32][32];
    for (size_t i = 0; i <= la; i++)
        d[i][0] = i;
    for (size_t j = 0; j <= lb; j++)
        d[0][j] = j;
    for (size_t i = 1; i <= la; i++)
        for (size_t j = 1; j <= lb; j++) {
            size_t best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < best) best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    return d[la][lb];
}

const char *lf_closest(const char *word, const char *const known[])
{
    const char *best = NULL;
    size_t bd = 3;                        /* at most two edits away */
    for (int i = 0; known[i]; i++) {
        size_t d = distance(word, known[i]);
        if (d < bd) {
            bd = d;
            best = known[i];
        }
    }
    return best;
}

void lf_open(lua_State *L, int arg, const char *const known[])
{
    if (lua_type(L, arg) != LUA_TTABLE) {
        lua_pushfstring(L, "table of named fields expected, got %s", luaL_typename(L, arg));
        luaL_argerror(L, arg, lua_tostring(L, -1));
    }
    /* pairs() order varies from run to run; report the smallest bad key so
    ** the same mistake always gives the same message. */
    const char *bad = NULL;
    lua_pushnil(L);
    while (lua_next(L, arg)) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            lua_pushvalue(L, -1);
            const char *k = luaL_tolstring(L, -1, NULL);
            lua_pushfstring(L, "unexpected key [%s]; fields are named, as in {radius = 1}", k);
            luaL_argerror(L, arg, lua_tostring(L, -1));
        }
        const char *k = lua_tostring(L, -1);
        int found = 0;
        for (int i = 0; known[i]; i++)
            if (strcmp(k, known[i]) == 0)
                found = 1;
        if (!found && (!bad || strcmp(k, bad) < 0))
            bad = k;     /* the key stays alive in the table */
    }
    if (!bad)
        return;
    const char *best = lf_closest(bad, known);
    if (best)
        lua_pushfstring(L, "unknown field '%s'; did you mean '%s'?", bad, best);
    else {
        luaL_Buffer b;
        luaL_buffinit(L, &b);
        lua_pushfstring(L, "unknown field '%s'; known fields are ", bad);
        luaL_addvalue(&b);
        for (int i = 0; known[i]; i++) {
            if (i)
                luaL_addstring(&b, ", ");
            luaL_addstring(&b, known[i]);
        }
        luaL_pushresult(&b);
    }
    luaL_argerror(L, arg, lua_tostring(L, -1));
}

int lf_present(lua_State *L, int arg, const char *name)
{
    int t = lua_getfield(L, arg, name);
    lua_pop(L, 1);
    return t != LUA_TNIL;
}

/* Pushes t[name]; returns 0 (and pops) when absent and not required. */
static int get(lua_State *L, int arg, const char *name, int required, const char *what)
{
    if (lua_getfield(L, arg, name) == LUA_TNIL) {
        lua_pop(L, 1);
        if (required)
            lf_error(L, arg, name, "%s expected, got no value", what);
        return 0;
    }
    return 1;
}

static void check_finite(lua_State *L, int arg, const char *name, double x)
{
    if (isnan(x))
        lf_error(L, arg, name, "NaN is not a number here");
    if (isinf(x))
        lf_error(L, arg, name, "must be finite, got %s", x > 0 ? "inf" : "-inf");
}

double lf_number(lua_State *L, int arg, const char *name, int required, double def)
{
    if (!get(L, arg, name, required, "number"))
        return def;
    if (lua_type(L, -1) != LUA_TNUMBER)
        lf_error(L, arg, name, "number expected, got %s", luaL_typename(L, -1));
    double x = lua_tonumber(L, -1);
    lua_pop(L, 1);
    check_finite(L, arg, name, x);
    return x;
}

int lf_integer(lua_State *L, int arg, const char *name, int required, int def)
{
    if (!get(L, arg, name, required, "integer"))
        return def;
    if (lua_type(L, -1) != LUA_TNUMBER)
        lf_error(L, arg, name, "integer expected, got %s", luaL_typename(L, -1));
    lua_Integer i;
    if (lua_isinteger(L, -1))
        i = lua_tointeger(L, -1);
    else {
        double x = lua_tonumber(L, -1);
        check_finite(L, arg, name, x);
        if (x != floor(x) || fabs(x) > 2e9)
            lf_error(L, arg, name, "integer expected, got %s", lua_tostring(L, -1));
        i = (lua_Integer)x;
    }
    lua_pop(L, 1);
    if (i < -2000000000 || i > 2000000000)
        lf_error(L, arg, name, "out of range, got %lld", (long long)i);
    return (int)i;
}

int lf_boolean(lua_State *L, int arg, const char *name, int def)
{
    if (!get(L, arg, name, 0, "boolean"))
        return def;
    if (lua_type(L, -1) != LUA_TBOOLEAN)
        lf_error(L, arg, name, "boolean expected, got %s", luaL_typename(L, -1));
    int b = lua_toboolean(L, -1);
    lua_pop(L, 1);
    return b;
}

static const char *const ordinal[] = {"1", "2", "3"};

int lf_to_vec3(lua_State *L, int idx, lc_vec3 *out, char *why, size_t whylen)
{
    idx = lua_absindex(L, idx);
    if (lua_type(L, idx) != LUA_TTABLE) {
        snprintf(why, whylen, "vector {x, y, z} expected, got %s", luaL_typename(L, idx));
        return 0;
    }
    lua_Integer n = luaL_len(L, idx);
    if (n != 3) {
        snprintf(why, whylen, "3 components expected, got %lld", (long long)n);
        return 0;
    }
    double c[3];
    for (int i = 0; i < 3; i++) {
        lua_geti(L, idx, i + 1);
        if (lua_type(L, -1) != LUA_TNUMBER) {
            snprintf(why, whylen, "component %s: number expected, got %s", ordinal[i],
                     luaL_typename(L, -1));
            lua_pop(L, 1);
            return 0;
        }
        c[i] = lua_tonumber(L, -1);
        lua_pop(L, 1);
        if (isnan(c[i])) {
            snprintf(why, whylen, "NaN in component %s", ordinal[i]);
            return 0;
        }
        if (isinf(c[i])) {
            snprintf(why, whylen, "infinite component %s", ordinal[i]);
            return 0;
        }
    }
    out->x = c[0];
    out->y = c[1];
    out->z = c[2];
    return 1;
}

int lf_to_color(lua_State *L, int idx, lc_color *out, char *why, size_t whylen)
{
    lc_vec3 v;
    if (lua_type(L, idx) == LUA_TNUMBER) {
        double g = lua_tonumber(L, idx);
        if (!isfinite(g)) {
            snprintf(why, whylen, "must be finite, got %g", g);
            return 0;
        }
        v.x = v.y = v.z = g;
    } else if (lua_type(L, idx) != LUA_TTABLE) {
        snprintf(why, whylen, "colour {r, g, b} or number expected, got %s",
                 luaL_typename(L, idx));
        return 0;
    } else if (!lf_to_vec3(L, idx, &v, why, whylen)) {
        return 0;
    }
    double ch[3] = {v.x, v.y, v.z};
    for (int i = 0; i < 3; i++) {
        if (ch[i] < 0) {
            snprintf(why, whylen, "component %s must be >= 0, got %g", ordinal[i], ch[i]);
            return 0;
        }
        if (ch[i] > FLT_MAX) {       /* colours are stored as floats */
            snprintf(why, whylen, "component %s must be at most %g, got %g", ordinal[i],
                     (double)FLT_MAX, ch[i]);
            return 0;
        }
    }
    out->r = (float)v.x;
    out->g = (float)v.y;
    out->b = (float)v.z;
    return 1;
}

lc_vec3 lf_vec3(lua_State *L, int arg, const char *name, int required, lc_vec3 def)
{
    if (!get(L, arg, name, required, "vector {x, y, z}"))
        return def;
    char why[200];
    lc_vec3 v;
    if (!lf_to_vec3(L, -1, &v, why, sizeof why))
        lf_error(L, arg, name, "%s", why);
    lua_pop(L, 1);
    return v;
}

lc_color lf_color(lua_State *L, int arg, const char *name, int required, lc_color def)
{
    if (!get(L, arg, name, required, "colour {r, g, b}"))
        return def;
    char why[200];
    lc_color c;
    if (!lf_to_color(L, -1, &c, why, sizeof why))
        lf_error(L, arg, name, "%s", why);
    lua_pop(L, 1);
    return c;
}

int lf_option(lua_State *L, int arg, const char *name, const char *const opts[], int def)
{
    if (!get(L, arg, name, 0, "string"))
        return def;
    if (lua_type(L, -1) != LUA_TSTRING)
        lf_error(L, arg, name, "string expected, got %s", luaL_typename(L, -1));
    const char *s = lua_tostring(L, -1);
    for (int i = 0; opts[i]; i++)
        if (strcmp(s, opts[i]) == 0) {
            lua_pop(L, 1);
            return i;
        }
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "expected one of ");
    for (int i = 0; opts[i]; i++) {
        if (i)
            luaL_addstring(&b, ", ");
        luaL_addchar(&b, '\'');
        luaL_addstring(&b, opts[i]);
        luaL_addchar(&b, '\'');
    }
    luaL_pushresult(&b);
    return lf_error(L, arg, name, "%s, got '%s'", lua_tostring(L, -1), s);
}

void *lf_udata(lua_State *L, int arg, const char *name, const char *tname, int required)
{
    if (!get(L, arg, name, required, tname)) {
        lua_pushnil(L);
        return NULL;
    }
    void *p = luaL_testudata(L, -1, tname);
    if (!p) {
        const char *got = luaL_typename(L, -1);
        if (luaL_getmetafield(L, -1, "__name") == LUA_TSTRING)
            got = lua_tostring(L, -1);
        lf_error(L, arg, name, "%s expected, got %s", tname, got);
    }
    return p;
}

void lf_push_vec3(lua_State *L, lc_vec3 v)
{
    lua_createtable(L, 3, 0);
    lua_pushnumber(L, v.x);
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, v.y);
    lua_rawseti(L, -2, 2);
    lua_pushnumber(L, v.z);
    lua_rawseti(L, -2, 3);
}

void lf_push_color(lua_State *L, lc_color c)
{
    lc_vec3 v = {c.r, c.g, c.b};
    lf_push_vec3(L, v);
}

void lf_add_number(luaL_Buffer *b, double x)
{
    char tmp[40];
    snprintf(tmp, sizeof tmp, "%.6g", x);
    luaL_addstring(b, tmp);
}

void lf_add_vec3(luaL_Buffer *b, const char *name, lc_vec3 v)
{
    luaL_addstring(b, name);
    luaL_addstring(b, " = {");
    lf_add_number(b, v.x);
    luaL_addstring(b, ", ");
    lf_add_number(b, v.y);
    luaL_addstring(b, ", ");
    lf_add_number(b, v.z);
    luaL_addstring(b, "}");
}
