/* lua_csg.c: CSG in Lua: lancer.union, intersection, difference and merge,
** their fields and printing, csg:moved(T), and the flat description that
** scene:add hands the core (and scene:objects() reads back). */
#include <string.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

/* Operations nest at most this deep (groups inside them count): a tree
** built by a script stays within what the C stack walks comfortably. */
#define CSG_MAX_DEPTH 200

static const char *const cut_opts[] = {"cutter", "object", NULL};

static const char *type_name(lua_State *L, int idx)
{
    const char *got = luaL_typename(L, idx);
    if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING) {
        got = lua_tostring(L, -1);
        lua_pop(L, 1);
    }
    return got;
}

/* ---- operands ------------------------------------------------------------------- */

/* Raises "bad argument #1 to 'difference' (operand 2: <msg>)". `where`
** says which operand (and member of a group within it). */
static int operand_error(lua_State *L, const char *where, const char *msg)
{
    lua_pushfstring(L, "%s: %s", where, msg);
    return luaL_argerror(L, 1, lua_tostring(L, -1));
}

/* Checks the operand at idx (a closed shape, a closed mesh, a group of
** them, a CSG object); adds its nesting depth and description length. */
static void check_operand(lua_State *L, int idx, const char *where, int *depth,
                          size_t *nodes)
{
    idx = lua_absindex(L, idx);
    luaL_checkstack(L, 8, "CSG operands nested too deep");
    lc_error err;
    lb_ud_shape *sh = luaL_testudata(L, idx, LB_SHAPE);
    if (sh) {
        lc_csg_node n;
        memset(&n, 0, sizeof n);
        n.op = LC_CSG_SHAPE;
        n.shape = sh->s;
        if (lc_csg_check(&n, 1, &err))
            operand_error(L, where, err.msg);
        *depth = 0;
        *nodes = 1;
        return;
    }
    lb_ud_mesh *me = luaL_testudata(L, idx, LB_MESH);
    if (me) {
        if (!me->m)
            operand_error(L, where, "lancer.Mesh already freed");
        lc_csg_node n;
        memset(&n, 0, sizeof n);
        n.op = LC_CSG_MESH;
        n.mesh = me->m;
        n.transform = lc_transform_identity();
        if (lc_csg_check(&n, 1, &err)) {
            lua_pushfstring(L, "%s (%s)", where, luaL_tolstring(L, idx, NULL));
            operand_error(L, lua_tostring(L, -1), err.msg);
        }
        *depth = 0;
        *nodes = 1;
        return;
    }
    lb_ud_csg *c = luaL_testudata(L, idx, LB_CSG);
    if (c) {
        *depth = c->depth;
        *nodes = c->nodes;
        return;
    }
    if (luaL_testudata(L, idx, LB_GROUP)) {      /* a union of its members */
        lua_getiuservalue(L, idx, 1);
        lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
        if (n == 0)
            operand_error(L, where, "an empty group is not a closed solid");
        int deepest = 0;
        size_t total = 1;
        for (lua_Integer i = 1; i <= n; i++) {
            lua_rawgeti(L, -1, i);
            lua_pushfstring(L, "%s, member %I", where, i);
            int d;
            size_t k;
            check_operand(L, -2, lua_tostring(L, -1), &d, &k);
            lua_pop(L, 2);
            deepest = d > deepest ? d : deepest;
            total += k;
        }
        lua_pop(L, 1);
        *depth = deepest + 1;
        *nodes = total;
        return;
    }
    if (luaL_testudata(L, idx, LB_LIGHT))
        operand_error(L, where, "a point light is not a closed solid");
    lua_pushfstring(L, "shape, mesh, group or CSG object expected, got %s",
                    type_name(L, idx));
    operand_error(L, where, lua_tostring(L, -1));
}

/* Pushes a CSG userdata: op over the operands (an array at stack index
** ops), with the material at mat (nil: none). */
static lb_ud_csg *push_csg(lua_State *L, lc_csg_op op, int ops, int mat)
{
    ops = lua_absindex(L, ops);
    mat = lua_absindex(L, mat);
    lb_ud_csg *u = lua_newuserdatauv(L, sizeof *u, 2);
    memset(u, 0, sizeof *u);
    u->op = op;
    u->t = lc_transform_identity();
    lua_pushvalue(L, ops);
    lua_setiuservalue(L, -2, 1);
    lua_pushvalue(L, mat);
    lua_setiuservalue(L, -2, 2);
    luaL_setmetatable(L, LB_CSG);
    return u;
}

/* lancer.<op>{a, b, ..., material = m} (and cut = 'cutter' | 'object' for
** difference): operands in the array part; the material, when given,
** dresses the operands that have none. */
static int csg_new(lua_State *L, lc_csg_op op)
{
    static const char *const plain[] = {"material", NULL};
    static const char *const diff[] = {"material", "cut", NULL};
    const char *const *known = op == LC_CSG_DIFFERENCE ? diff : plain;
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_Integer n = luaL_len(L, 1);
    /* The named fields: every other key must be an operand's position. */
    const char *bad = NULL;
    lua_pushnil(L);
    while (lua_next(L, 1)) {
        lua_pop(L, 1);
        if (lua_isinteger(L, -1)) {
            lua_Integer k = lua_tointeger(L, -1);
            if (k >= 1 && k <= n)
                continue;
        }
        if (lua_type(L, -1) != LUA_TSTRING) {
            lua_pushvalue(L, -1);
            lua_pushfstring(L, "unexpected key [%s]; operands are a list, as in "
                            "{a, b}", luaL_tolstring(L, -1, NULL));
            return luaL_argerror(L, 1, lua_tostring(L, -1));
        }
        const char *k = lua_tostring(L, -1);
        int found = 0;
        for (int i = 0; known[i]; i++)
            found |= strcmp(k, known[i]) == 0;
        if (!found && (!bad || strcmp(k, bad) < 0))
            bad = k;
    }
    if (bad) {
        const char *best = lf_closest(bad, known);
        if (best)
            lua_pushfstring(L, "unknown field '%s'; did you mean '%s'?", bad, best);
        else
            lua_pushfstring(L, "unknown field '%s'; known fields are %s%s", bad,
                            op == LC_CSG_DIFFERENCE ? "material, cut" : "material",
                            ", and the operands");
        return luaL_argerror(L, 1, lua_tostring(L, -1));
    }
    if (n < 1)
        return luaL_argerror(L, 1, "at least one operand expected, got none");
    lf_udata(L, 1, "material", LB_MATERIAL, 0);          /* pushes it, or nil */
    int mat = lua_gettop(L);
    int cut = op == LC_CSG_DIFFERENCE ? lf_option(L, 1, "cut", cut_opts, 0) : 0;
    lua_createtable(L, (int)n, 0);
    int ops = lua_gettop(L);
    int deepest = 0;
    size_t total = 1;
    for (lua_Integer i = 1; i <= n; i++) {
        lua_geti(L, 1, i);
        lua_pushfstring(L, "operand %I", i);
        int d;
        size_t k;
        check_operand(L, -2, lua_tostring(L, -1), &d, &k);
        lua_pop(L, 1);
        lua_rawseti(L, ops, i);
        deepest = d > deepest ? d : deepest;
        total += k;
    }
    if (deepest + 1 > CSG_MAX_DEPTH)
        return luaL_argerror(L, 1, lua_pushfstring(L, "CSG operations nest at most %d "
                                                   "deep, got %d", CSG_MAX_DEPTH,
                                                   deepest + 1));
    if (total > LC_CSG_MAX_NODES)
        return luaL_argerror(L, 1, lua_pushfstring(L, "a CSG object has at most %d "
                                                   "nodes, got %d", LC_CSG_MAX_NODES,
                                                   (int)total));
    lb_ud_csg *u = push_csg(L, op, ops, mat);
    u->cut_object = cut;
    u->depth = deepest + 1;
    u->nodes = total;
    return 1;
}

static int w_union(lua_State *L) { return csg_new(L, LC_CSG_UNION); }
static int w_intersection(lua_State *L) { return csg_new(L, LC_CSG_INTERSECTION); }
static int w_difference(lua_State *L) { return csg_new(L, LC_CSG_DIFFERENCE); }
static int w_merge(lua_State *L) { return csg_new(L, LC_CSG_MERGE); }

int lb_csg_moved(lua_State *L, int idx, const lc_transform *t)
{
    idx = lua_absindex(L, idx);
    const lb_ud_csg *c = luaL_checkudata(L, idx, LB_CSG);
    lc_transform m = lc_transform_compose(t, &c->t);
    lc_error err;
    if (lc_transform_check(&m, &err))
        return luaL_argerror(L, 2, err.msg);
    lua_getiuservalue(L, idx, 1);
    lua_getiuservalue(L, idx, 2);
    lb_ud_csg *u = push_csg(L, c->op, -2, -1);
    u->cut_object = c->cut_object;
    u->depth = c->depth;
    u->nodes = c->nodes;
    u->t = m;
    u->moved = !lc_transform_is_identity(&m);
    return 1;
}

/* ---- the flat description ------------------------------------------------------- */

typedef struct {
    lc_csg_node *nodes;
    size_t n, cap;
    int mats, meshes;      /* stack indices of the two tables */
    int arg;
} describer;

/* Appends the operand at idx, placed by t (NULL: as it is), dressed in the
** material at stack index mat when it has none (0: none). */
static void describe(lua_State *L, int idx, const lc_transform *t, int mat, describer *d)
{
    idx = lua_absindex(L, idx);
    luaL_checkstack(L, 8, "CSG operands nested too deep");
    if (d->n == d->cap)                 /* cannot be: counted when built */
        luaL_error(L, "CSG description longer than counted");
    size_t at = d->n++;
    lc_csg_node *nd = &d->nodes[at];
    memset(nd, 0, sizeof *nd);
    nd->transform = lc_transform_identity();
    lc_error err;
    lb_ud_shape *sh = luaL_testudata(L, idx, LB_SHAPE);
    lb_ud_mesh *me = sh ? NULL : luaL_testudata(L, idx, LB_MESH);
    if (sh || me) {
        nd->op = sh ? LC_CSG_SHAPE : LC_CSG_MESH;
        if (sh) {
            nd->shape = sh->s;
            if (t && lc_shape_transform(&sh->s, t, &nd->shape, &err))
                lf_raise(L, d->arg, &err);
        } else if (t) {
            nd->transform = *t;
        }
        lua_getiuservalue(L, idx, 1);   /* its own material, or the one it wears */
        if (lua_isnil(L, -1) && mat) {
            lua_pop(L, 1);
            lua_pushvalue(L, mat);
        }
        lua_rawseti(L, d->mats, (lua_Integer)at + 1);
        if (me) {
            lua_pushvalue(L, idx);
            lua_rawseti(L, d->meshes, (lua_Integer)at + 1);
        }
        return;
    }
    lb_ud_csg *c = luaL_testudata(L, idx, LB_CSG);
    lc_transform placed;
    if (c) {
        nd->op = c->op;
        nd->cut_object = c->cut_object;
        placed = t ? lc_transform_compose(t, &c->t) : c->t;
        lua_getiuservalue(L, idx, 2);
        if (!lua_isnil(L, -1))
            mat = lua_gettop(L);
    } else {                            /* a group: a union of its members */
        const lb_ud_group *g = lua_touserdata(L, idx);
        nd->op = LC_CSG_UNION;
        placed = t ? lc_transform_compose(t, &g->t) : g->t;
        lua_pushnil(L);                 /* keeps the stack's shape */
    }
    int moved = !lc_transform_is_identity(&placed);
    lua_getiuservalue(L, idx, 1);
    lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
    d->nodes[at].count = (int)n;
    for (lua_Integer i = 1; i <= n; i++) {
        lua_rawgeti(L, -1, i);
        describe(L, -1, moved ? &placed : NULL, mat, d);
        lua_pop(L, 1);
    }
    lua_pop(L, 2);
}

size_t lb_csg_describe(lua_State *L, int idx, const lc_transform *xf, int arg)
{
    idx = lua_absindex(L, idx);
    const lb_ud_csg *c = luaL_checkudata(L, idx, LB_CSG);
    size_t n = c->nodes;
    describer d;
    d.nodes = lua_newuserdatauv(L, n * sizeof *d.nodes, 0);
    d.n = 0;
    d.cap = n;
    lua_newtable(L);
    d.mats = lua_gettop(L);
    lua_newtable(L);
    d.meshes = lua_gettop(L);
    d.arg = arg;
    describe(L, idx, xf, 0, &d);
    return d.n;
}

/* ---- what a scene lists --------------------------------------------------------- */

/* The nesting depth and description length of the operand at idx, as the
** constructor counts them (a group is a union), without checking it again
** (a mesh may have grown since: the scene holds the faces it had). */
static void count_operand(lua_State *L, int idx, int *depth, size_t *nodes)
{
    idx = lua_absindex(L, idx);
    lb_ud_csg *c = luaL_testudata(L, idx, LB_CSG);
    *depth = c ? c->depth : 0;
    *nodes = c ? c->nodes : 1;
    if (!luaL_testudata(L, idx, LB_GROUP))
        return;
    lua_getiuservalue(L, idx, 1);
    lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
    for (lua_Integer i = 1; i <= n; i++) {
        int d;
        size_t k;
        lua_rawgeti(L, -1, i);
        count_operand(L, -1, &d, &k);
        lua_pop(L, 1);
        *depth = d + 1 > *depth ? d + 1 : *depth;
        *nodes += k;
    }
    lua_pop(L, 1);
}

/* Pushes node i's subtree; returns the index past it. */
static size_t push_listed(lua_State *L, const lc_csg_node *nodes, size_t n, size_t i,
                          int mats, int meshes, int depth)
{
    luaL_checkstack(L, 8, "CSG object nested too deep");
    if (depth > CSG_MAX_DEPTH)
        luaL_error(L, "a CSG object nests deeper than %d: it cannot be listed",
                   CSG_MAX_DEPTH);
    const lc_csg_node *nd = &nodes[i];
    if (nd->op == LC_CSG_SHAPE) {
        lua_rawgeti(L, mats, nd->material);              /* nil: the default */
        lb_shape_push(L, &nd->shape, -1);
        lua_remove(L, -2);
        return i + 1;
    }
    if (nd->op == LC_CSG_MESH) {
        lua_pushlightuserdata(L, nd->mesh);
        lua_rawget(L, meshes);
        int m = lua_gettop(L);
        if (lua_isnil(L, m))           /* added by a host, not from Lua */
            return i + 1;
        /* Dressed in another material than its own: inside a union of one
        ** that wears it. */
        lua_getiuservalue(L, m, 1);
        lua_rawgeti(L, mats, nd->material);
        if (!lua_rawequal(L, -1, -2)) {
            lua_createtable(L, 1, 0);
            lua_pushvalue(L, m);
            lua_rawseti(L, -2, 1);
            lb_ud_csg *u = push_csg(L, LC_CSG_UNION, -1, -2);
            u->depth = 1;
            u->nodes = 2;
            lua_replace(L, m);
        }
        lua_settop(L, m);
        if (!lc_transform_is_identity(&nd->transform)) {
            lua_createtable(L, 1, 0);
            lua_pushvalue(L, m);
            lua_rawseti(L, -2, 1);
            lb_motion_push_group(L, &nd->transform, -1);
            lua_replace(L, m);
            lua_settop(L, m);
        }
        return i + 1;
    }
    lua_createtable(L, nd->count, 0);
    int ops = lua_gettop(L);
    size_t j = i + 1, total = 1;
    int deepest = 0;
    for (int k = 0; k < nd->count && j < n; k++) {
        j = push_listed(L, nodes, n, j, mats, meshes, depth + 1);
        int d;
        size_t c;
        count_operand(L, -1, &d, &c);
        deepest = d > deepest ? d : deepest;
        total += c;
        lua_rawseti(L, ops, k + 1);
    }
    lua_pushnil(L);
    lb_ud_csg *u = push_csg(L, nd->op, ops, -1);
    u->cut_object = nd->cut_object;
    u->depth = deepest + 1;
    u->nodes = total;
    lua_replace(L, ops);
    lua_pop(L, 1);
    return j;
}

void lb_csg_push_listed(lua_State *L, const lc_csg_node *nodes, size_t n, int mats,
                        int meshes)
{
    mats = lua_absindex(L, mats);
    meshes = lua_absindex(L, meshes);
    push_listed(L, nodes, n, 0, mats, meshes, 0);
}

/* ---- fields and printing -------------------------------------------------------- */

/* lancer.difference{lancer.box{...}, lancer.sphere{...}, cut = 'object'}, its
** operands as they print, then "moved by lancer.transform{...}" when moved. */
static int w_csg_tostring(lua_State *L)
{
    const lb_ud_csg *c = luaL_checkudata(L, 1, LB_CSG);
    lua_settop(L, 1);
    lua_getiuservalue(L, 1, 1);                      /* 2 */
    lua_getiuservalue(L, 1, 2);                      /* 3 */
    luaL_Buffer b;
    luaL_buffinit(L, &b);                            /* may push: absolute indices */
    luaL_addstring(&b, "lancer.");
    luaL_addstring(&b, lc_csg_op_name(c->op));
    luaL_addstring(&b, "{");
    lua_Integer n = (lua_Integer)lua_rawlen(L, 2);
    for (lua_Integer i = 1; i <= n; i++) {
        if (i > 1)
            luaL_addstring(&b, ", ");
        lua_rawgeti(L, 2, i);
        luaL_tolstring(L, -1, NULL);
        lua_remove(L, -2);
        luaL_addvalue(&b);
    }
    if (c->op == LC_CSG_DIFFERENCE && c->cut_object)
        luaL_addstring(&b, ", cut = 'object'");
    if (!lua_isnil(L, 3)) {
        luaL_addstring(&b, ", material = ");
        luaL_tolstring(L, 3, NULL);
        luaL_addvalue(&b);
    }
    luaL_addstring(&b, "}");
    if (c->moved) {
        luaL_addstring(&b, " moved by ");
        lb_ud_transform *t = lua_newuserdatauv(L, sizeof *t, 0);
        t->t = c->t;
        luaL_setmetatable(L, LB_TRANSFORM);
        luaL_tolstring(L, -1, NULL);
        lua_remove(L, -2);
        luaL_addvalue(&b);
    }
    luaL_pushresult(&b);
    return 1;
}

static int w_csg_index(lua_State *L)
{
    const lb_ud_csg *c = luaL_checkudata(L, 1, LB_CSG);
    const char *k = luaL_checkstring(L, 2);
    if (strcmp(k, "kind") == 0) {
        lua_pushstring(L, lc_csg_op_name(c->op));
    } else if (strcmp(k, "operands") == 0) {         /* a copy: the object is a value */
        lua_getiuservalue(L, 1, 1);
        lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
        lua_createtable(L, (int)n, 0);
        for (lua_Integer i = 1; i <= n; i++) {
            lua_rawgeti(L, -2, i);
            lua_rawseti(L, -2, i);
        }
    } else if (strcmp(k, "material") == 0) {
        lua_getiuservalue(L, 1, 2);
    } else if (strcmp(k, "cut") == 0 && c->op == LC_CSG_DIFFERENCE) {
        lua_pushstring(L, cut_opts[c->cut_object]);
    } else if (strcmp(k, "transform") == 0 && c->moved) {
        lb_ud_transform *t = lua_newuserdatauv(L, sizeof *t, 0);
        t->t = c->t;
        luaL_setmetatable(L, LB_TRANSFORM);
    } else if (strcmp(k, "moved") == 0) {
        lua_pushcfunction(L, lb_motion_moved);
    } else {
        lua_pushnil(L);
    }
    return 1;
}

static int w_csg_len(lua_State *L)
{
    luaL_checkudata(L, 1, LB_CSG);
    lua_getiuservalue(L, 1, 1);
    lua_pushinteger(L, (lua_Integer)lua_rawlen(L, -1));
    return 1;
}

void lb_csg_register(lua_State *L)
{
    static const luaL_Reg meta[] = {
        {"__tostring", w_csg_tostring}, {"__index", w_csg_index}, {"__len", w_csg_len},
        {NULL, NULL}};
    static const luaL_Reg funcs[] = {
        {"union", w_union}, {"intersection", w_intersection},
        {"difference", w_difference}, {"merge", w_merge}, {NULL, NULL}};
    lb_class(L, LB_CSG, meta, NULL);
    luaL_setfuncs(L, funcs, 0);
}
