/* lua_record.c: records (materials, lights, cameras) over their field tables. */
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

static void *member(const void *rec, const lb_field *f)
{
    return (char *)rec + f->offset;
}

#define VEC3_OF(rec, f)  ((lc_vec3 *)member(rec, f))
#define COLOR_OF(rec, f) ((lc_color *)member(rec, f))
#define NUM_OF(rec, f)   ((double *)member(rec, f))
#define INT_OF(rec, f)   ((int *)member(rec, f))   /* integers, booleans, options */

const lb_field *lb_record_field(const lb_field *fields, const char *name)
{
    for (const lb_field *f = fields; f->name; f++)
        if (strcmp(f->name, name) == 0)
            return f;
    return NULL;
}

void lb_record_open(lua_State *L, int arg, const lb_field *fields)
{
    const char *known[2 * LB_MAX_FIELDS + 2];    /* names, alsos, NULL */
    int n = 0;
    for (const lb_field *f = fields; f->name && n < 2 * LB_MAX_FIELDS; f++) {
        known[n++] = f->name;
        if (f->also)
            known[n++] = f->also;
    }
    known[n] = NULL;
    lf_open(L, arg, known);
}

void lb_record_read(lua_State *L, int arg, void *rec, const lb_field *fields,
                    unsigned skip)
{
    for (const lb_field *f = fields; f->name; f++) {
        if (skip & 1u << (f - fields))
            continue;
        if (f->read) {
            f->read(L, arg, rec);
            continue;
        }
        switch (f->type) {
        case LB_VEC3:
            *VEC3_OF(rec, f) = lf_vec3(L, arg, f->name, f->required, *VEC3_OF(rec, f));
            break;
        case LB_COLOR:
            *COLOR_OF(rec, f) = lf_color(L, arg, f->name, f->required,
                                         *COLOR_OF(rec, f));
            break;
        case LB_NUMBER:
            *NUM_OF(rec, f) = lf_number(L, arg, f->name, f->required, *NUM_OF(rec, f));
            break;
        case LB_INTEGER:
            *INT_OF(rec, f) = lf_integer(L, arg, f->name, f->required, *INT_OF(rec, f));
            break;
        case LB_BOOL:
            *INT_OF(rec, f) = lf_boolean(L, arg, f->name, *INT_OF(rec, f));
            break;
        case LB_OPTION:
            *INT_OF(rec, f) = lf_option(L, arg, f->name, f->opts, *INT_OF(rec, f));
            break;
        case LB_TEXTURE_ONLY:
            break;
        }
    }
}

void lb_record_push(lua_State *L, const void *rec, const lb_field *f)
{
    switch (f->type) {
    case LB_VEC3: lf_push_vec3(L, *VEC3_OF(rec, f)); break;
    case LB_COLOR: lf_push_color(L, *COLOR_OF(rec, f)); break;
    case LB_NUMBER: lua_pushnumber(L, *NUM_OF(rec, f)); break;
    case LB_INTEGER: lua_pushinteger(L, *INT_OF(rec, f)); break;
    case LB_BOOL: lua_pushboolean(L, *INT_OF(rec, f)); break;
    case LB_OPTION: lua_pushstring(L, f->opts[*INT_OF(rec, f)]); break;
    case LB_TEXTURE_ONLY: lua_pushnil(L); break;
    }
}

/* Whether field f holds the same value in a and b. */
static int same(const void *a, const void *b, const lb_field *f)
{
    switch (f->type) {
    case LB_VEC3: {
        lc_vec3 x = *VEC3_OF(a, f), y = *VEC3_OF(b, f);
        return x.x == y.x && x.y == y.y && x.z == y.z;
    }
    case LB_COLOR: {
        lc_color x = *COLOR_OF(a, f), y = *COLOR_OF(b, f);
        return x.r == y.r && x.g == y.g && x.b == y.b;
    }
    case LB_NUMBER: return *NUM_OF(a, f) == *NUM_OF(b, f);
    case LB_BOOL: return !*INT_OF(a, f) == !*INT_OF(b, f);
    case LB_INTEGER:
    case LB_OPTION: return *INT_OF(a, f) == *INT_OF(b, f);
    case LB_TEXTURE_ONLY: return 1;
    }
    return 1;
}

int lb_record_equal(const void *a, const void *b, const lb_field *fields)
{
    for (const lb_field *f = fields; f->name; f++)
        if (!same(a, b, f))
            return 0;
    return 1;
}

/* "name = value", as the constructor would read it back. */
static void add_field(luaL_Buffer *b, const void *rec, const lb_field *f)
{
    if (f->type == LB_VEC3) {
        lf_add_vec3(b, f->name, *VEC3_OF(rec, f));
        return;
    }
    if (f->type == LB_COLOR) {
        lc_color c = *COLOR_OF(rec, f);
        lf_add_vec3(b, f->name, (lc_vec3){c.r, c.g, c.b});
        return;
    }
    luaL_addstring(b, f->name);
    luaL_addstring(b, " = ");
    switch (f->type) {
    case LB_NUMBER: lf_add_number(b, *NUM_OF(rec, f)); break;
    case LB_INTEGER: lf_add_number(b, *INT_OF(rec, f)); break;
    case LB_BOOL: luaL_addstring(b, *INT_OF(rec, f) ? "true" : "false"); break;
    case LB_OPTION:
        luaL_addchar(b, '\'');
        luaL_addstring(b, f->opts[*INT_OF(rec, f)]);
        luaL_addchar(b, '\'');
        break;
    default: break;
    }
}

/* The field __tostring writes at place i (from 0), or NULL past the last. */
static const lb_field *ranked(const lb_field *fields, int i)
{
    if (!fields[0].rank)
        return fields[i].name ? &fields[i] : NULL;
    for (const lb_field *f = fields; f->name; f++)
        if (f->rank == i + 1)
            return f;
    return NULL;
}

void lb_record_tostring(luaL_Buffer *b, const char *ctor, const void *rec,
                        const void *def, const lb_field *fields)
{
    luaL_addstring(b, ctor);
    luaL_addchar(b, '{');
    int any = 0, prev = 0;          /* prev: the field before was written */
    const lb_field *f;
    for (int i = 0; (f = ranked(fields, i)) != NULL; i++) {
        int shown = f->shown == LB_SHOWN ||
                    (f->shown == LB_SHOWN_CHANGED && !same(rec, def, f)) ||
                    (f->shown == LB_SHOWN_WITH_PREV && prev);
        prev = shown;
        if (!shown)
            continue;
        if (any++)
            luaL_addstring(b, ", ");
        add_field(b, rec, f);
    }
    luaL_addchar(b, '}');
}
