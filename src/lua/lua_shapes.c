/* lua_shapes.c: the Lua side of shapes: constructors over per-kind field tables. */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* Each kind's fields, in the order the constructor reads them and
** __tostring writes them; each names the lc_shape member that holds it.
** __tostring, __index, scene:objects() and scene:remove() read this table
** and nothing else about a kind, so a new kind adds its row here, its
** constructor below and its entry in lb_shapes_register's list. Kind names
** are the core's (lc_shape_kind_name). */
typedef enum { FIELD_VEC3, FIELD_NUMBER, FIELD_BOOL } field_type;

typedef struct {
    const char *name;          /* NULL ends a kind's list */
    size_t      offset;        /* of its member in lc_shape */
    field_type  type;
    int         optional;      /* 0: required; else absent means `def` */
    double      def;
} shape_field;

#define VEC3(name, member)   {name, offsetof(lc_shape, member), FIELD_VEC3, 0, 0}
#define NUMBER(name, member) {name, offsetof(lc_shape, member), FIELD_NUMBER, 0, 0}
#define NUMBER_OR(name, member, d) {name, offsetof(lc_shape, member), FIELD_NUMBER, 1, d}
#define BOOL_OR(name, member, d) {name, offsetof(lc_shape, member), FIELD_BOOL, 1, d}
#define MAX_FIELDS 5

static const shape_field kind_fields[LC_SHAPE_KINDS][MAX_FIELDS + 1] = {
    [LC_SPHERE]    = {VEC3("center", p), NUMBER("radius", radius)},
    [LC_QUAD]      = {VEC3("corner", p), VEC3("u", u), VEC3("v", v)},
    [LC_BOX]       = {VEC3("corner", p), VEC3("u", u), VEC3("v", v), VEC3("w", w)},
    [LC_PLANE]     = {VEC3("point", p), VEC3("normal", u)},
    [LC_DISC]      = {VEC3("center", p), VEC3("normal", u), NUMBER("radius", radius),
                      NUMBER_OR("inner_radius", radius2, 0)},
    [LC_CYLINDER]  = {VEC3("base", p), VEC3("axis", u), NUMBER("radius", radius),
                      BOOL_OR("caps", caps, 1)},
    [LC_CONE]      = {VEC3("base", p), VEC3("axis", u), NUMBER("base_radius", radius),
                      NUMBER("top_radius", radius2), BOOL_OR("caps", caps, 1)},
    [LC_TORUS]     = {VEC3("center", p), VEC3("axis", u), NUMBER("major", radius),
                      NUMBER("minor", radius2)},
    [LC_ELLIPSOID] = {VEC3("center", p), VEC3("radii", u)},
};

/* A lancer.Transform holding t (a moved shape's placement). */
static void push_transform(lua_State *L, const lc_transform *t)
{
    lb_ud_transform *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->t = *t;
    luaL_setmetatable(L, LB_TRANSFORM);
}

static int *int_of(lc_shape *s, const shape_field *f)
{
    return (int *)((char *)s + f->offset);
}

static lc_vec3 *vec3_of(lc_shape *s, const shape_field *f)
{
    return (lc_vec3 *)((char *)s + f->offset);
}

static double *number_of(lc_shape *s, const shape_field *f)
{
    return (double *)((char *)s + f->offset);
}

/* The field of that kind named k, or NULL. */
static const shape_field *field_named(lc_shape_kind kind, const char *k)
{
    for (const shape_field *f = kind_fields[kind]; f->name; f++)
        if (strcmp(f->name, k) == 0)
            return f;
    return NULL;
}

/* ---- constructors ------------------------------------------------------------ */

/* Checks that the table at 1 holds only the kind's fields, `extra` (at most
** two other field names, NULL-terminated) and material. */
static void shape_open(lua_State *L, lc_shape_kind kind, const char *const extra[])
{
    const char *known[MAX_FIELDS + 4];
    int n = 0;
    for (const shape_field *f = kind_fields[kind]; f->name; f++)
        known[n++] = f->name;
    for (int i = 0; extra && extra[i] && i < 2; i++)
        known[n++] = extra[i];
    known[n++] = "material";
    known[n] = NULL;
    lf_open(L, 1, known);
}

/* Reads every field of the shape's kind from the table at 1 (but `skip`,
** which the constructor reads itself). */
static void shape_read(lua_State *L, lc_shape *s, const char *skip)
{
    for (const shape_field *f = kind_fields[s->kind]; f->name; f++) {
        if (skip && strcmp(f->name, skip) == 0)
            continue;
        if (f->type == FIELD_VEC3)
            *vec3_of(s, f) = lf_vec3(L, 1, f->name, !f->optional, *vec3_of(s, f));
        else if (f->type == FIELD_BOOL)
            *int_of(s, f) = lf_boolean(L, 1, f->name, (int)f->def);
        else
            *number_of(s, f) = lf_number(L, 1, f->name, !f->optional, f->def);
    }
}

/* Validates, then pushes the shape userdata holding `s` and its material. */
static int shape_push_checked(lua_State *L, const lc_shape *s)
{
    lf_udata(L, 1, "material", LB_MATERIAL, 0);     /* pushes it, or nil */
    lc_error err;
    if (lc_shape_check(s, &err))
        return lf_raise(L, 1, &err);
    lb_shape_push(L, s, -1);
    return 1;
}

/* The constructors' upvalues: the metatables they set and test for. */
#define UP_SHAPE    lua_upvalueindex(1)
#define UP_MATERIAL lua_upvalueindex(2)

/* lb_shape_push, with the shape metatable at stack index mt. */
static void push_shape(lua_State *L, const lc_shape *s, int mat, int mt)
{
    mat = lua_absindex(L, mat);
    mt = lua_absindex(L, mt);
    lb_ud_shape *u = lua_newuserdatauv(L, sizeof *u, 1);
    u->s = *s;
    lua_pushvalue(L, mat);
    lua_setiuservalue(L, -2, 1);
    lua_pushvalue(L, mt);
    lua_setmetatable(L, -2);
}

/* A vector read as lf_to_vec3 reads it, from a plain table (no metatable,
** so nothing runs): 0 when it is not one, or not 3 finite numbers. */
static int plain_vec3(lua_State *L, int idx, lc_vec3 *out)
{
    if (lua_type(L, idx) != LUA_TTABLE || lua_getmetatable(L, idx)) {
        if (lua_type(L, idx) == LUA_TTABLE)
            lua_pop(L, 1);
        return 0;
    }
    if (lua_rawlen(L, idx) != 3)
        return 0;
    double c[3];
    for (int i = 0; i < 3; i++) {
        int t = lua_rawgeti(L, idx, i + 1);
        c[i] = lua_tonumber(L, -1);
        lua_pop(L, 1);
        if (t != LUA_TNUMBER || !isfinite(c[i]))
            return 0;
    }
    *out = (lc_vec3){c[0], c[1], c[2]};
    return 1;
}

/* Reads the kind's fields and material from the table at 1 in one pass,
** when it is plain: string keys the kind knows, every value of its type
** and finite, vectors plain tables, every required field there, no
** metatable (whose __index the field reads would ask). Then s holds the
** fields and index 2 the material (or nil), and no Lua code has run.
** Otherwise it returns 0, and the constructor reads the table as before
** (shape_open, shape_read, shape_push_checked), which raises the error it
** always did: the pass reads what is right, never what is wrong. */
static int shape_read_plain(lua_State *L, lc_shape *s)
{
    if (lua_type(L, 1) != LUA_TTABLE || lua_getmetatable(L, 1))
        return 0;              /* (a metatable stays pushed: the caller resets) */
    lua_settop(L, 1);
    lua_pushnil(L);                                  /* 2: the material */
    const shape_field *fields = kind_fields[s->kind];
    unsigned seen = 0;
    lua_pushnil(L);
    while (lua_next(L, 1)) {
        if (lua_type(L, -2) != LUA_TSTRING)
            return 0;
        const char *k = lua_tostring(L, -2);
        int i = 0;
        while (fields[i].name && (fields[i].name[0] != k[0] || strcmp(fields[i].name, k)))
            i++;
        const shape_field *f = &fields[i];
        int t = lua_type(L, -1);
        if (!f->name) {
            if (strcmp(k, "material") || !lb_udata_is(L, -1, UP_MATERIAL))
                return 0;
            lua_copy(L, -1, 2);
        } else if (f->type == FIELD_VEC3) {
            if (!plain_vec3(L, -1, vec3_of(s, f)))
                return 0;
        } else if (f->type == FIELD_BOOL) {
            if (t != LUA_TBOOLEAN)
                return 0;
            *int_of(s, f) = lua_toboolean(L, -1);
        } else {
            double x = lua_tonumber(L, -1);
            if (t != LUA_TNUMBER || !isfinite(x))
                return 0;
            *number_of(s, f) = x;
        }
        seen |= 1u << i;
        lua_pop(L, 1);
    }
    for (int i = 0; fields[i].name; i++)
        if (!(seen & 1u << i)) {
            const shape_field *f = &fields[i];
            if (!f->optional)
                return 0;
            if (f->type == FIELD_BOOL)
                *int_of(s, f) = (int)f->def;
            else if (f->type == FIELD_NUMBER)
                *number_of(s, f) = f->def;
        }
    return 1;
}

/* lancer.<kind>{its fields, material = }: every field required. */
static int shape_new(lua_State *L, lc_shape_kind kind)
{
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = kind;
    if (shape_read_plain(L, &s)) {
        lc_error err;
        if (lc_shape_check(&s, &err))
            return lf_raise(L, 1, &err);
        push_shape(L, &s, 2, UP_SHAPE);
        return 1;
    }
    if (lua_gettop(L) > 1)          /* not to 1: no argument stays "no value" */
        lua_settop(L, 1);
    memset(&s, 0, sizeof s);
    s.kind = kind;
    shape_open(L, kind, NULL);
    shape_read(L, &s, NULL);
    return shape_push_checked(L, &s);
}

static int w_sphere(lua_State *L) { return shape_new(L, LC_SPHERE); }
static int w_quad(lua_State *L) { return shape_new(L, LC_QUAD); }
static int w_plane(lua_State *L) { return shape_new(L, LC_PLANE); }

/* lancer.box{corner, u, v, w} or lancer.box{min = , max = } (axis-aligned). */
static int w_box(lua_State *L)
{
    static const char *const corners[] = {"min", "max", NULL};
    shape_open(L, LC_BOX, corners);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = LC_BOX;
    if (!lf_present(L, 1, "min") && !lf_present(L, 1, "max")) {
        shape_read(L, &s, NULL);
        return shape_push_checked(L, &s);
    }
    for (const shape_field *f = kind_fields[LC_BOX]; f->name; f++)
        if (lf_present(L, 1, f->name))
            return lf_error(L, 1, f->name, "give either min and max, or corner "
                            "and u, v, w, not both");
    lc_vec3 lo = lf_vec3(L, 1, "min", 1, s.p), hi = lf_vec3(L, 1, "max", 1, s.p);
    double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    for (int i = 0; i < 3; i++)
        if (!(h[i] > l[i]))
            return lf_error(L, 1, "max", "component %d must be > min's, got %g <= %g",
                            i + 1, h[i], l[i]);
    s.p = lo;
    s.u.x = hi.x - lo.x;
    s.v.y = hi.y - lo.y;
    s.w.z = hi.z - lo.z;
    return shape_push_checked(L, &s);
}

static int w_disc(lua_State *L) { return shape_new(L, LC_DISC); }
static int w_torus(lua_State *L) { return shape_new(L, LC_TORUS); }
static int w_ellipsoid(lua_State *L) { return shape_new(L, LC_ELLIPSOID); }

/* lancer.cylinder{base, axis or top, radius, caps = true} and lancer.cone{base,
** axis or top, base_radius, top_radius, caps = true}: the axis runs from
** the base to the top, its length the height. */
static int axial(lua_State *L, lc_shape_kind kind)
{
    static const char *const tops[] = {"top", NULL};
    shape_open(L, kind, tops);
    lc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = kind;
    shape_read(L, &s, "axis");
    int has_axis = lf_present(L, 1, "axis"), has_top = lf_present(L, 1, "top");
    if (has_axis && has_top)
        return lf_error(L, 1, "top", "give either axis or top, not both");
    if (has_top) {
        lc_vec3 top = lf_vec3(L, 1, "top", 1, s.p);
        s.u = (lc_vec3){top.x - s.p.x, top.y - s.p.y, top.z - s.p.z};
    } else {
        s.u = lf_vec3(L, 1, "axis", 1, s.u);
    }
    return shape_push_checked(L, &s);
}

static int w_cylinder(lua_State *L) { return axial(L, LC_CYLINDER); }
static int w_cone(lua_State *L) { return axial(L, LC_CONE); }

/* ---- what every kind shares ------------------------------------------------ */

void lb_shape_push(lua_State *L, const lc_shape *s, int mat)
{
    mat = lua_absindex(L, mat);
    luaL_getmetatable(L, LB_SHAPE);
    push_shape(L, s, mat, -1);
    lua_remove(L, -2);
}

int lb_shape_match(const lc_shape *added, const lc_shape *listed)
{
    lc_shape a, b = *listed;
    lc_error err;
    if (added->kind != listed->kind || lc_shape_stored(added, &a, &err))
        return 0;
    if (a.moved != b.moved || (a.moved && memcmp(&a.xf, &b.xf, sizeof a.xf) != 0))
        return 0;
    for (const shape_field *f = kind_fields[a.kind]; f->name; f++) {
        if (f->type == FIELD_NUMBER && *number_of(&a, f) != *number_of(&b, f))
            return 0;
        if (f->type == FIELD_BOOL && !*int_of(&a, f) != !*int_of(&b, f))
            return 0;
        if (f->type == FIELD_VEC3) {
            lc_vec3 x = *vec3_of(&a, f), y = *vec3_of(&b, f);
            if (x.x != y.x || x.y != y.y || x.z != y.z)
                return 0;
        }
    }
    return 1;
}

/* lancer.sphere{center = {0, 0, 0}, radius = 1}: the fields as given. */
static int w_shape_tostring(lua_State *L)
{
    lc_shape s = ((lb_ud_shape *)luaL_checkudata(L, 1, LB_SHAPE))->s;
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    luaL_addstring(&b, "lancer.");
    luaL_addstring(&b, lc_shape_kind_name(s.kind));
    luaL_addstring(&b, "{");
    for (const shape_field *f = kind_fields[s.kind]; f->name; f++) {
        if (f != kind_fields[s.kind])
            luaL_addstring(&b, ", ");
        if (f->type == FIELD_VEC3) {
            lf_add_vec3(&b, f->name, *vec3_of(&s, f));
        } else {
            luaL_addstring(&b, f->name);
            luaL_addstring(&b, " = ");
            if (f->type == FIELD_BOOL)
                luaL_addstring(&b, *int_of(&s, f) ? "true" : "false");
            else
                lf_add_number(&b, *number_of(&s, f));
        }
    }
    luaL_addstring(&b, "}");
    luaL_pushresult(&b);
    if (s.moved) {                        /* "... moved by lancer.transform{...}" */
        int fields = lua_gettop(L);
        push_transform(L, &s.xf);
        const char *t = luaL_tolstring(L, -1, NULL);
        lua_pushfstring(L, "%s moved by %s", lua_tostring(L, fields), t);
    }
    return 1;
}

static int w_shape_index(lua_State *L)
{
    lc_shape s = ((lb_ud_shape *)luaL_checkudata(L, 1, LB_SHAPE))->s;
    const char *k = luaL_checkstring(L, 2);
    const shape_field *f = field_named(s.kind, k);
    if (f && f->type == FIELD_VEC3) lf_push_vec3(L, *vec3_of(&s, f));
    else if (f && f->type == FIELD_BOOL) lua_pushboolean(L, *int_of(&s, f));
    else if (f) lua_pushnumber(L, *number_of(&s, f));
    else if (strcmp(k, "transform") == 0 && s.moved) push_transform(L, &s.xf);
    else if (strcmp(k, "kind") == 0) lua_pushstring(L, lc_shape_kind_name(s.kind));
    else if (strcmp(k, "material") == 0) lua_getiuservalue(L, 1, 1);
    else if (strcmp(k, "moved") == 0) lua_pushcfunction(L, lb_motion_moved);
    else lua_pushnil(L);
    return 1;
}

void lb_shapes_register(lua_State *L)
{
    static const luaL_Reg shape_meta[] = {
        {"__tostring", w_shape_tostring}, {"__index", w_shape_index}, {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"sphere", w_sphere}, {"quad", w_quad}, {"box", w_box}, {"plane", w_plane},
        {"disc", w_disc}, {"cylinder", w_cylinder}, {"cone", w_cone}, {"torus", w_torus},
        {"ellipsoid", w_ellipsoid}, {NULL, NULL}};
    lb_class(L, LB_SHAPE, shape_meta, NULL);
    luaL_getmetatable(L, LB_SHAPE);                /* UP_SHAPE */
    luaL_getmetatable(L, LB_MATERIAL);     /* UP_MATERIAL: lb_material_register's */
    luaL_setfuncs(L, funcs, 2);
}
