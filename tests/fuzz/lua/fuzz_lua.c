/* fuzz_lua.c: libFuzzer harness of the Lua API. The input's bytes are read
** as a program: each statement byte chooses a call (a constructor, a scene
** or image method, a transform, a host hook, closing or collecting an
** object), the bytes after it its target and arguments. The harness writes
** it out as a Lua script and runs it in a fresh lua_State with the module
** opened (luaopen_lancer_core), every statement under pcall, so a refused
** argument is an ordinary outcome and only a crash, a sanitizer report or
** a leak is a finding.
**
** Values cover every type: numbers (NaN, infinities, huge, negative, -0,
** integers at the limits), strings, tables (vectors of the wrong length,
** named fields, nested lists), booleans, nil, functions, and the objects of
** an 8-slot pool (so userdata of the wrong kind comes naturally). Tricks
** (T in the prelude) are tables whose __index and __len close or collect
** a pool object, or turn into the table itself, in the middle of the call
** that reads them; hooks (H) do the same around render, explain and save.
**
** Each input's work is capped: renders and explains at most 8x8, 1 sample
** (a few at 2), threads = 1, shallow mirrors; an instruction-count hook
** stops a script after BUDGET instructions; Lua's heap and the core's
** allocations are capped. FUZZ_LUA_PRINT=1 prints each script (to read a
** crash input: build/fuzz/fuzz_lua crash-file with it set) and the errors
** its statements raise. */
#define _GNU_SOURCE                 /* mkdtemp, dirent */
#include <dirent.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include "lancer.h"
#include "lua/lua_lancer.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define POOL 8                      /* V[1..POOL] */
#define MAX_STATEMENTS 48
#define BUDGET 2000000              /* Lua instructions per input */
#define LUA_HEAP_CAP ((size_t)64 << 20)

static char dir[64];                /* the scratch folder D, emptied per input */
static FILE *say;                   /* the real stderr; stderr itself is muted */
static int verbose;

/* ---- Reading the input ---------------------------------------------------- */

/* Past the end, bytes read 0: rare choices are the last value of a pick,
** so a statement cut short comes out plain (no trick, no misspelt field). */

typedef struct { const uint8_t *p; size_t n, at; } input;

static unsigned byte(input *in) { return in->at < in->n ? in->p[in->at++] : 0; }
static unsigned pick(input *in, unsigned k) { return byte(in) % k; }

/* ---- Writing the script ----------------------------------------------------- */

typedef struct { char *s; size_t n, cap; int failed; } text;

static void out(text *t, const char *fmt, ...)
{
    va_list ap;
    if (!t->s) {
        t->cap = 4096;
        t->s = malloc(t->cap);
        if (!t->s)
            abort();
    }
    for (;;) {
        size_t room = t->cap - t->n;
        va_start(ap, fmt);
        int k = vsnprintf(t->s + t->n, room, fmt, ap);
        va_end(ap);
        if (k < 0)
            abort();
        if ((size_t)k < room) {
            t->n += (size_t)k;
            return;
        }
        size_t nc = t->cap * 2 + (size_t)k + 64;
        char *p = realloc(t->s, nc);
        if (!p)
            abort();
        t->s = p;
        t->cap = nc;
    }
}

/* ---- Values ----------------------------------------------------------------- */

static const char *const numbers[] = {
    "0", "1", "-1", "2", "0.5", "3", "4", "8", "-0.0", "1.5", "0.25", "10", "90", "180",
    "1e-30", "1e-31", "1e30", "1e31", "1e300", "-1e300", "1e-320", "(1/0)", "(-1/0)",
    "(0/0)", "2^31", "2^53", "math.maxinteger", "math.mininteger", "65536", "65537",
    "4096", "4097", "1000000", "1000001", "7.5", "-2", "0.999", "1e154", "-1e-300",
    "89.9",
};
#define NNUMBERS (sizeof numbers / sizeof *numbers)

static const char *const strings[] = {
    "''", "'x'", "'srgb'", "'linear'", "'all'", "'diffuse'", "'inverse_square'",
    "'none'",
    "'sobol'", "'jitter'", "'random'", "'1'", "'nan'", "'y'", "'z'", "'0x10'",
    "string.rep('ab', 300)", "'\\0'", "'radius'", "'camera'", "'min'",
};
#define NSTRINGS (sizeof strings / sizeof *strings)

static void value(input *in, text *t, int depth);

static void number(input *in, text *t)
{
    unsigned k = byte(in);
    if (k < 2 * NNUMBERS) {
        out(t, "%s", numbers[k % NNUMBERS]);
    } else if (k < 2 * NNUMBERS + 60) {
        out(t, "%u", byte(in) % 16);          /* small integers */
    } else {
        int whole = (int)(byte(in) % 21) - 10;
        out(t, "%d.%u", whole, byte(in));
    }
}

static void vector(input *in, text *t)
{
    unsigned shape = pick(in, 16);
    int n = shape == 15 ? 2 : shape == 14 ? 4 : 3;
    out(t, "{");
    for (int i = 0; i < n; i++) {
        if (i)
            out(t, ", ");
        if (shape == 13 && i == 1)
            value(in, t, 2);
        else
            number(in, t);
    }
    out(t, "}");
}

static void color(input *in, text *t)
{
    if (byte(in) & 1)
        number(in, t);
    else
        vector(in, t);
}

static void slot(input *in, text *t) { out(t, "V[%u]", 1 + pick(in, POOL)); }

/* A table the binding reads through metamethods: T(action, victim, backing
** [, flip]), see the prelude. */
static void trick(input *in, text *t, int depth)
{
    unsigned a = byte(in);
    out(t, "T(%u, %u, ", a, 1 + pick(in, POOL));
    if (depth < 3 && (byte(in) & 1)) {
        out(t, "{");
        int n = (int)pick(in, 4);
        for (int i = 0; i < n; i++)
            value(in, t, depth + 1), out(t, ", ");
        if (byte(in) & 1)
            out(t, "SELF");
        out(t, "}");
    } else {
        out(t, "{}");
    }
    out(t, ", %u)", pick(in, 4));
}

static void value(input *in, text *t, int depth)
{
    switch (pick(in, depth > 2 ? 8 : 12)) {
    case 0: case 1: number(in, t); break;
    case 2: out(t, "%s", strings[pick(in, NSTRINGS)]); break;
    case 3: out(t, "%s", byte(in) & 1 ? "true" : "false"); break;
    case 4: out(t, "nil"); break;
    case 5: case 6: slot(in, t); break;
    case 7: out(t, "%s", byte(in) & 1 ? "function() end" : "{}"); break;
    case 8: vector(in, t); break;
    case 9: trick(in, t, depth); break;
    case 10: {                                   /* a list */
        out(t, "{");
        int n = (int)pick(in, 5);
        for (int i = 0; i < n; i++)
            value(in, t, depth + 1), out(t, ", ");
        out(t, "}");
        break;
    }
    default:                                     /* a one-field table */
        out(t, "{[%s] = ", strings[pick(in, NSTRINGS)]);
        value(in, t, depth + 1);
        out(t, "}");
        break;
    }
}

/* ---- Named-field tables ------------------------------------------------------ */

typedef enum { F_NUM, F_VEC, F_COLOR, F_STR, F_MAT, F_CAM, F_BOOL, F_SIZE, F_COUNT,
               F_DEPTH, F_LIST, F_FACES, F_ANY } field_kind;
typedef struct { const char *name; field_kind kind; } field;

/* Sizes a render may take: at most 8, or refused. */
static const char *const sizes[] = {"1", "2", "3", "4", "8", "5", "0", "-1", "(0/0)",
                                    "(1/0)", "'4'", "1.5", "65537", "2^31", "true",
                                    "{}"};
/* Sample counts: 1 or 2, or refused. */
static const char *const counts[] = {"1", "1", "2", "0", "-1", "(0/0)", "'1'", "1.5",
                                     "4097", "2^20 + 1", "nil", "false"};
/* Mirror depths: shallow, or refused. */
static const char *const depths[] = {"0", "1", "2", "3", "-1", "1.5", "'2'", "1000001",
                                     "(0/0)", "nil"};

static void material_expr(input *in, text *t, int depth);
static void camera_expr(input *in, text *t, int depth);

static void list_of(input *in, text *t, int depth, int faces)
{
    out(t, "{");
    int n = (int)pick(in, 10);
    int flat = byte(in) & 1;
    for (int i = 0; i < n; i++) {
        if (flat || faces > 1)
            number(in, t);
        else if (faces)
        {
            unsigned a = 1 + pick(in, 6), b = 1 + pick(in, 6), c = 1 + pick(in, 6);
            out(t, "{%u, %u, %u}", a, b, c);
        }
        else if (pick(in, 8) == 7)
            value(in, t, depth + 1);
        else
            vector(in, t);
        out(t, ", ");
    }
    out(t, "}");
}

static void field_value(input *in, text *t, field_kind k, int depth)
{
    /* Now and then anything at all; never for the sizes, counts and depths
    ** that bound a render's work: those lists hold their wrong values. */
    if (k != F_SIZE && k != F_COUNT && k != F_DEPTH && pick(in, 10) == 9) {
        value(in, t, depth + 1);
        return;
    }
    switch (k) {
    case F_NUM: number(in, t); break;
    case F_VEC: vector(in, t); break;
    case F_COLOR: color(in, t); break;
    case F_STR: out(t, "%s", strings[pick(in, NSTRINGS)]); break;
    case F_MAT:
        if (byte(in) & 1)
            slot(in, t);
        else
            material_expr(in, t, depth + 1);
        break;
    case F_CAM:
        if (byte(in) & 1)
            slot(in, t);
        else
            camera_expr(in, t, depth + 1);
        break;
    case F_BOOL: out(t, "%s", byte(in) & 1 ? "true" : "false"); break;
    case F_SIZE: out(t, "%s", sizes[pick(in, sizeof sizes / sizeof *sizes)]); break;
    case F_COUNT: out(t, "%s", counts[pick(in, sizeof counts / sizeof *counts)]); break;
    case F_DEPTH: out(t, "%s", depths[pick(in, sizeof depths / sizeof *depths)]); break;
    case F_LIST: list_of(in, t, depth, 0); break;
    case F_FACES: list_of(in, t, depth, 1 + (byte(in) & 1)); break;
    default: value(in, t, depth + 1); break;
    }
}

/* {name = value, ...} over some of the fields, now and then a misspelt
** one; or, rarely, a trick whose backing table they are.
** `forced`: fields always given with a safe value (threads = 1). */
static void fields(input *in, text *t, const field *f, size_t nf, int depth,
                   const char *forced)
{
    int tricked = depth < 2 && pick(in, 12) == 11;
    if (tricked)
    {
        unsigned a = byte(in);
        out(t, "(T(%u, %u, ", a, 1 + pick(in, POOL));
    }
    out(t, "{");
    if (forced)
        out(t, "%s, ", forced);
    /* Each field given with odds of `rate` in 8: most constructor calls
    ** have their required fields, most renders few options. */
    unsigned rate = nf > 8 ? 2 : 6;
    for (size_t k = 0; k < nf; k++) {
        if (pick(in, 8) >= rate)
            continue;
        out(t, "%s = ", f[k].name);
        field_value(in, t, f[k].kind, depth);
        out(t, ", ");
    }
    if (pick(in, 16) == 15)
        out(t, "raduis = 1, ");
    out(t, "}");
    if (tricked)
        out(t, ", %u))", pick(in, 4));
}

static const field material_fields[] = {
    {"color", F_COLOR}, {"ka", F_NUM}, {"kd", F_NUM}, {"kr", F_NUM}, {"ks", F_NUM},
    {"alpha", F_NUM}, {"emission", F_COLOR}, {"absorb", F_STR}, {"glossiness", F_NUM},
    {"cone_samples", F_COUNT}};
static const field sphere_fields[] = {{"center", F_VEC}, {"radius", F_NUM},
                                      {"material", F_MAT}};
static const field quad_fields[] = {{"corner", F_VEC}, {"u", F_VEC}, {"v", F_VEC},
                                    {"material", F_MAT}};
static const field box_fields[] = {{"corner", F_VEC}, {"u", F_VEC}, {"v", F_VEC},
                                   {"w", F_VEC}, {"material", F_MAT}};
static const field aabox_fields[] = {{"min", F_VEC}, {"max", F_VEC},
                                     {"material", F_MAT}};
static const field plane_fields[] = {{"point", F_VEC}, {"normal", F_VEC},
                                     {"material", F_MAT}};
static const field triangle_fields[] = {{"a", F_VEC}, {"b", F_VEC}, {"c", F_VEC},
                                        {"material", F_MAT}};
static const field mesh_fields[] = {{"vertices", F_LIST}, {"faces", F_FACES},
                                    {"normals", F_LIST}, {"material", F_MAT}};
static const field light_fields[] = {{"position", F_VEC}, {"color", F_COLOR},
                                     {"intensity", F_NUM}, {"falloff", F_STR}};
static const field camera_fields[] = {{"from", F_VEC}, {"at", F_VEC}, {"up", F_VEC},
                                      {"fov", F_NUM}, {"aperture", F_NUM},
                                      {"focus", F_NUM}};
static const field scene_fields[] = {{"camera", F_CAM}, {"background", F_COLOR},
                                     {"ambient", F_COLOR}, {"max_depth", F_DEPTH}};
static const field image_fields[] = {{"width", F_NUM}, {"height", F_NUM},
                                     {"color", F_COLOR}};
static const field render_fields[] = {
    {"width", F_SIZE}, {"height", F_SIZE}, {"samples", F_COUNT}, {"seed", F_NUM},
    {"cosine", F_BOOL}, {"cutoff", F_NUM}, {"shadows", F_BOOL}, {"reflections", F_BOOL},
    {"specular", F_BOOL}, {"generic", F_BOOL}, {"frame", F_NUM}, {"sampler", F_STR},
    {"light_samples", F_COUNT}, {"cone_samples", F_COUNT}, {"max_depth", F_DEPTH},
    {"noise", F_NUM}, {"min_samples", F_COUNT}, {"glossy", F_BOOL}, {"progress", F_BOOL},
    {"x", F_SIZE}, {"y", F_SIZE}, {"sample", F_COUNT}};
#define N(a) (sizeof a / sizeof *a)

static void material_expr(input *in, text *t, int depth)
{
    out(t, "lancer.material");
    fields(in, t, material_fields, N(material_fields), depth, NULL);
}

static void camera_expr(input *in, text *t, int depth)
{
    out(t, "lancer.camera");
    fields(in, t, camera_fields, N(camera_fields), depth, NULL);
}

/* What scene:add takes: objects, lists of them (nested), groups, tricks. */
static void addable(input *in, text *t, int depth)
{
    switch (pick(in, depth > 2 ? 4 : 8)) {
    case 0: case 1: case 2: slot(in, t); break;
    case 3: value(in, t, depth + 1); break;
    case 4: case 5: {
        out(t, "{");
        int n = (int)pick(in, 4);
        for (int i = 0; i < n; i++)
            addable(in, t, depth + 1), out(t, ", ");
        out(t, "}");
        break;
    }
    case 6:
        out(t, "lancer.group{");
        for (int i = (int)pick(in, 4); i > 0; i--)
            addable(in, t, depth + 1), out(t, ", ");
        out(t, "}");
        break;
    default: trick(in, t, depth); break;
    }
}

/* A path in the scratch folder (D), or one that cannot be read or written. */
static void path(input *in, text *t, int png)
{
    static const char *const names[] = {"a.png", "b.png", "m.obj", "a.PNG", "a.jpg",
                                        "nodir/x.png", "", ".png", "missing.png",
                                        "m.png"};
    unsigned k = pick(in, N(names) + 1);
    if (k == N(names))
        value(in, t, 2);
    else if (png && k == 2)
        out(t, "D .. 'a.png'");
    else
        out(t, "D .. '%s'", names[k]);
}

static const char *const methods[] = {
    "add", "render", "explain", "objects", "remove", "count", "transformed", "pixel",
    "set", "diff", "error", "save", "nonfinite", "add_vertices", "add_faces",
    "add_normals", "moved", "apply", "apply_vector", "inverse", "rows", "is_identity",
};

static void args(input *in, text *t, int n)
{
    for (int i = 0; i < n; i++) {
        if (i)
            out(t, ", ");
        value(in, t, 1);
    }
}

/* The receiver of a method: mostly K(kind, i) (V[i] if it is of that
** kind, else the first pool object that is: see the prelude), now and then
** V[i] as it is, whatever it holds. */
static const char *receiver(input *in, const char *kind, unsigned i, char *buf)
{
    if (pick(in, 8) != 7)
        snprintf(buf, 48, "K('%s', %u)", kind, i);
    else
        snprintf(buf, 48, "V[%u]", i);
    return buf;
}

/* One statement: a line of the script, under pcall. */
static void statement(input *in, text *t, int number_of_statement)
{
    char rb[48], rb2[48];
#define RS(i) receiver(in, "lancer.Scene", i, rb)
#define RI(i) receiver(in, "lancer.Image", i, rb)
#define RI2(i) receiver(in, "lancer.Image", i, rb2)
#define RM(i) receiver(in, "lancer.Mesh", i, rb)
#define RT(i) receiver(in, "lancer.Transform", i, rb)
#define RT2(i) receiver(in, "lancer.Transform", i, rb2)
    /* Read in a fixed order (C leaves the order of a call's arguments open):
    ** the call, its target slot, another slot, a choice. */
    unsigned op = pick(in, 34);
    unsigned i = 1 + pick(in, POOL), j = 1 + pick(in, POOL), c = byte(in);
    const char *r;
    out(t, "P(function() ");
    switch (op) {
    case 0: out(t, "V[%u] = ", i); material_expr(in, t, 0); break;
    case 1: out(t, "V[%u] = lancer.sphere", i);
        fields(in, t, sphere_fields, N(sphere_fields), 0, NULL); break;
    case 2: out(t, "V[%u] = lancer.quad", i);
        fields(in, t, quad_fields, N(quad_fields), 0, NULL); break;
    case 3: out(t, "V[%u] = lancer.box", i);
        if (byte(in) & 1)
            fields(in, t, box_fields, N(box_fields), 0, NULL);
        else
            fields(in, t, aabox_fields, N(aabox_fields), 0, NULL);
        break;
    case 4: out(t, "V[%u] = lancer.plane", i);
        fields(in, t, plane_fields, N(plane_fields), 0, NULL); break;
    case 5: out(t, "V[%u] = lancer.triangle", i);
        fields(in, t, triangle_fields, N(triangle_fields), 0, NULL); break;
    case 6: out(t, "V[%u] = lancer.mesh", i);
        fields(in, t, mesh_fields, N(mesh_fields), 0, NULL); break;
    case 7: out(t, "V[%u] = lancer.load_obj(", i); path(in, t, 0);
        if (byte(in) & 1) {
            out(t, ", {material = ");
            field_value(in, t, F_MAT, 1);
            out(t, "}");
        }
        out(t, ")"); break;
    case 8: out(t, "V[%u] = lancer.point_light", i);
        fields(in, t, light_fields, N(light_fields), 0, NULL); break;
    case 9: out(t, "V[%u] = ", i); camera_expr(in, t, 0); break;
    case 10: out(t, "V[%u] = lancer.scene", i);
        fields(in, t, scene_fields, N(scene_fields), 0, NULL); break;
    case 11:                               /* a whole small scene, to render soon */
        out(t, "V[%u] = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, "
               "at = {0, 1, 0}}}; V[%u]:add(lancer.sphere{center = {0, 1, 0}, "
               "radius = 1, material = lancer.material{kr = 0.5, ks = 0.5}}, "
               "lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}}, "
               "lancer.point_light{position = {2, 4, -3}, intensity = 25}, "
               "lancer.quad{corner = {-1, 3, 0}, u = {1, 0, 0}, v = {0, 0, 1}, "
               "material = lancer.material{emission = 2}})", i, i);
        break;
    case 12:
        switch (pick(in, 5)) {
        case 0: out(t, "V[%u] = lancer.translate(", i); args(in, t, 3); out(t, ")");
            break;
        case 1: out(t, "V[%u] = lancer.rotate(", i); args(in, t, 2); out(t, ")"); break;
        case 2: out(t, "V[%u] = lancer.scale(", i); args(in, t, 1 + 2 * (byte(in) & 1));
            out(t, ")"); break;
        case 3: out(t, "V[%u] = lancer.transform{", i);
            for (int row = 0; row < 3; row++) {
                out(t, "{");
                args(in, t, (int)(byte(in) % 8 != 7 ? 4 : pick(in, 6)));
                out(t, "}, ");
            }
            out(t, "}"); break;
        default: out(t, "V[%u] = lancer.rotate(%s, ", i,
                     (const char *[]){"'x'", "'y'", "'z'", "{1, 1, 0}"}[pick(in, 4)]);
            number(in, t); out(t, ")"); break;
        }
        break;
    case 13: out(t, "V[%u] = lancer.group{", i);
        for (int k = (int)pick(in, 5); k > 0; k--)
            addable(in, t, 1), out(t, ", ");
        out(t, "}"); break;
    case 14: out(t, "V[%u] = V[%u]:moved(", i, 1 + pick(in, POOL)); value(in, t, 1);
        out(t, ")"); break;
    case 15: {
        unsigned a = 1 + pick(in, POOL), b = 1 + pick(in, POOL);
        switch (pick(in, 7)) {
        case 0: r = RT(a); out(t, "V[%u] = %s * %s", i, r, RT2(b)); break;
        case 1: out(t, "V[%u] = %s:apply(", i, RT(a)); value(in, t, 1); out(t, ")");
            break;
        case 2: out(t, "V[%u] = %s:apply_vector(", i, RT(a)); value(in, t, 1);
            out(t, ")"); break;
        case 3: out(t, "V[%u] = %s:inverse()", i, RT(a)); break;
        case 4: out(t, "V[%u] = %s:rows()", i, RT(a)); break;
        case 5: out(t, "V[%u] = %s:is_identity()", i, RT(a)); break;
        default: r = RT(a); out(t, "V[%u] = %s == %s", i, r, RT2(b)); break;
        }
        break;
    }
    case 16: case 17:
        out(t, "%s:add(", RS(i));
        for (int k = 0, n = 1 + (int)pick(in, 3); k < n; k++) {
            if (k)
                out(t, ", ");
            addable(in, t, 0);
        }
        out(t, ")"); break;
    case 18: case 19:
        out(t, "V[%u] = %s:render", j, RS(i));
        fields(in, t, render_fields, N(render_fields) - 3, 0,
               "width = 4, height = 4, threads = 1, samples = 1");
        break;
    case 20:
        out(t, "V[%u] = %s:explain", j, RS(i));
        fields(in, t, render_fields, N(render_fields), 0,
               "x = 1, y = 1, width = 4, height = 4, threads = 1");
        out(t, "; tostring(V[%u])", 1 + pick(in, POOL)); break;
    case 21: {
        unsigned e = 1 + pick(in, POOL);
        switch (pick(in, 4)) {
        case 0: out(t, "V[%u] = %s:objects()", e, RS(i)); break;
        case 1: out(t, "for _, o in ipairs(%s:objects()) do tostring(o) end", RS(i));
            break;
        case 2: out(t, "local s = %s; s:remove(s:objects()[%u])", RS(i), 1 + c % 4);
            break;
        default: out(t, "V[%u] = %s:objects()[%u]", e, RS(i), 1 + c % 4); break;
        }
        break;
    }
    case 22: out(t, "%s:remove(", RS(i)); value(in, t, 0); out(t, ")"); break;
    case 23:
        switch (pick(in, 8)) {
        case 0: out(t, "%s.camera = ", RS(i)); field_value(in, t, F_CAM, 0); break;
        case 1: out(t, "%s.background = ", RS(i)); field_value(in, t, F_COLOR, 0); break;
        case 2: out(t, "%s.ambient = ", RS(i)); field_value(in, t, F_COLOR, 0); break;
        case 3: out(t, "%s.max_depth = ", RS(i)); field_value(in, t, F_DEPTH, 0); break;
        case 4: out(t, "V[%u] = %s:count()", j, RS(i)); break;
        case 5: out(t, "V[%u] = %s:transformed(", j, RS(i));
            args(in, t, 1 + (byte(in) & 1)); out(t, ")"); break;
        case 6: out(t, "V[%u] = V[%u].%s", j, i,
                    (const char *[]){"camera", "background", "ambient", "max_depth",
                                     "width", "height", "vertex_count", "face_count",
                                     "x"}[pick(in, 9)]); break;
        default: out(t, "%s.fog = 1", RS(i)); break;
        }
        break;
    case 24: out(t, "V[%u] = lancer.image", i);
        fields(in, t, image_fields, N(image_fields), 0, NULL); break;
    case 25: {
        unsigned x = 1 + pick(in, 4), y = 1 + pick(in, 4);
        switch (pick(in, 4)) {
        case 0: out(t, "%s:pixel(%u, %u)", RI(i), x, y); break;
        case 1: out(t, "%s:pixel(", RI(i)); args(in, t, 2); out(t, ")"); break;
        case 2: out(t, "%s:set(%u, %u, ", RI(i), x, y); args(in, t, 3); out(t, ")");
            break;
        default: out(t, "%s:set(", RI(i)); args(in, t, 5); out(t, ")"); break;
        }
        break;
    }
    case 26: {
        unsigned b = 1 + pick(in, POOL);
        switch (pick(in, 4)) {
        case 0: r = RI(i); out(t, "%s:diff(%s", r, RI2(b)); break;
        case 1: r = RI(i); out(t, "%s:error(%s", r, RI2(b)); break;
        case 2: r = RI(i); out(t, "%s:add(%s", r, RI2(b)); break;
        default: r = RI(i); out(t, "V[%u] = %s:nonfinite(%s", j, r, RI2(b));
            break;
        }
        if (byte(in) & 1)
            out(t, ", "), value(in, t, 1);
        out(t, ")");
        break;
    }
    case 27:
        if (byte(in) & 1) {
            out(t, "%s:save(", RI(i)); path(in, t, 1);
        } else {
            out(t, "V[%u] = lancer.load_png(", i); path(in, t, 1);
        }
        if (byte(in) & 1) {
            out(t, ", ");
            if (byte(in) & 1)
                out(t, "{encoding = %s}", byte(in) & 1 ? "'linear'" : "'srgb'");
            else
                value(in, t, 1);
        }
        out(t, ")"); break;
    case 28:
        out(t, "%s:%s(", RM(i), (const char *[]){"add_vertices", "add_faces",
            "add_normals"}[c % 3]);
        if (byte(in) & 1)
            list_of(in, t, 0, (int)pick(in, 3));
        else
            value(in, t, 0);
        out(t, ")"); break;
    case 29:
        switch (pick(in, 6)) {
        case 0: out(t, "close(V[%u])", i); break;
        case 1: out(t, "V[%u] = nil; collectgarbage()", i); break;
        case 2: out(t, "collectgarbage()"); break;
        case 3: out(t, "V[%u] = V[%u]", i, 1 + pick(in, POOL)); break;
        case 4: out(t, "do local x <close> = V[%u] end", i); break;
        default: out(t, "V[%u] = ", i); value(in, t, 0); break;
        }
        break;
    case 30:
        if (byte(in) & 3)
            out(t, "lancer.set_host_hook(H(%u, %u, %u))", c, j, pick(in, 6));
        else
            out(t, "lancer.set_host_hook(nil)");
        break;
    case 31: {                               /* an OBJ file for load_obj */
        out(t, "W('m.obj', '");
        for (int k = (int)pick(in, 8); k > 0; k--) {
            if (byte(in) & 1)
            {
                int x = (int)pick(in, 5) - 2, y = (int)pick(in, 5) - 2;
                out(t, "v %d %d %d\\n", x, y, (int)pick(in, 5) - 2);
            }
            else
            {
                int a = (int)pick(in, 9) - 4, b = (int)pick(in, 9) - 4;
                out(t, "f %d %d %d\\n", a, b, (int)pick(in, 9) - 4);
            }
        }
        out(t, "')");
        break;
    }
    case 32: out(t, "V[%u] = V[%u].%s(", j, i, methods[c % N(methods)]);
        value(in, t, 0);
        if (byte(in) & 1) {
            out(t, ", ");
            args(in, t, 1 + (int)pick(in, 2));
        }
        out(t, ")"); break;
    default:
        switch (pick(in, 3)) {
        case 0: out(t, "V[%u] = tostring(V[%u])", 1 + pick(in, POOL), i); break;
        case 1: out(t, "V[%u] = #V[%u]", 1 + pick(in, POOL), i); break;
        default: out(t, "V[%u] = V[%u][%u]", j, i, c % 4); break;
        }
        break;
    }
    out(t, " end, %d)\n", number_of_statement);
}

/* The helpers every script starts with, and a pool that holds one object
** of each kind (the scene renders). T(action, victim, backing, flip):
** a table whose fields and length are backing's, read through __index and
** __len, each read doing ACT[action] to V[victim] first; SELF in backing
** reads as the table itself, and with flip > 0, after `flip` reads every
** field does. H(action, victim, mode): a host hook that does the action,
** then calls plain as asked, or something else. */
static const char prelude[] =
    "local lancer, D, W, verbose = ...\n"
    "local V = {\n"
    "  lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}},\n"
    "  lancer.image{width = 4, height = 4, color = 0.5},\n"
    "  lancer.triangle{a = {-1, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0}},\n"
    "  lancer.sphere{center = {0, 1, 0}, radius = 1},\n"
    "  lancer.material{kr = 0.5, ks = 0.5, glossiness = 5, cone_samples = 2},\n"
    "  lancer.translate(0, 1, 0),\n"
    "  lancer.point_light{position = {2, 4, -3}, intensity = 25},\n"
    "  lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}},\n"
    "}\n"
    "V[1]:add(V[3], V[4], V[7], lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},\n"
    "  material = V[5]})\n"
    "local P = pcall\n"
    "if verbose then P = function(f, n) print('-- statement ' .. n)\n"
    "  local ok, e = pcall(f)\n"
    "  if not ok then print('error: ' .. select(2, pcall(tostring, e))) end end end\n"
    "local SELF = {}\n"
    "local function close(x)\n"
    "  local mt = getmetatable(x)\n"
    "  if type(mt) == 'table' and mt.__close then mt.__close(x) end\n"
    "end\n"
    "local ACT = {\n"
    "  function(k) end,\n"
    "  function(k) close(V[k]) end,\n"
    "  function(k) V[k] = nil; collectgarbage() end,\n"
    "  function(k) collectgarbage() end,\n"
    "  function(k) for i = 1, 8 do close(V[i]) end; collectgarbage() end,\n"
    "  function(k) error('trick') end,\n"
    "  function(k) V[k] = V[k % 8 + 1] end,\n"
    "  function(k) do local x <close> = V[k] end end,\n"
    "}\n"
    "local function act(a, k) ACT[a % #ACT + 1](k) end\n"
    "local function K(name, i)\n"
    "  local function is(x)\n"
    "    local mt = getmetatable(x)\n"
    "    return type(mt) == 'table' and rawget(mt, '__name') == name\n"
    "  end\n"
    "  if is(V[i]) then return V[i] end\n"
    "  for j = 1, 8 do if is(V[j]) then return V[j] end end\n"
    "  return V[i]\n"
    "end\n"
    "local function T(a, k, backing, flip)\n"
    "  local p, reads = {}, 0\n"
    "  return setmetatable(p, {\n"
    "    __index = function(_, key)\n"
    "      act(a, k); reads = reads + 1\n"
    "      if flip > 0 and reads > flip then return p end\n"
    "      local v = backing[key]\n"
    "      if v == SELF then return p end\n"
    "      return v\n"
    "    end,\n"
    "    __len = function() act(a, k); return #backing end,\n"
    "    __tostring = function() act(a, k); return 'trick' end,\n"
    "  })\n"
    "end\n"
    "local function H(a, k, mode)\n"
    "  return function(method, plain, self, ...)\n"
    "    act(a, k)\n"
    "    if mode == 0 then return plain(self, ...)\n"
    "    elseif mode == 1 then return\n"
    "    elseif mode == 2 then return plain(V[k], ...)\n"
    "    elseif mode == 3 then local r = table.pack(plain(self, ...)); act(a, k);\n"
    "      return table.unpack(r, 1, r.n)\n"
    "    elseif mode == 4 then local o = ...\n"
    "      return plain(self, type(o) == 'table' and T(a, k, o, 0) or o,\n"
    "                   select(2, ...))\n"
    "    else return self end\n"
    "  end\n"
    "end\n";

/* ---- Running it ------------------------------------------------------------- */

static size_t lua_heap;

static void *capped_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
    if (!ptr)
        osize = 0;
    if (nsize == 0) {
        free(ptr);
        lua_heap -= osize;
        return NULL;
    }
    if (nsize > osize && lua_heap + (nsize - osize) > LUA_HEAP_CAP)
        return NULL;
    void *p = realloc(ptr, nsize);
    if (p)
        lua_heap = lua_heap - osize + nsize;
    return p;
}

static long executed;

static void count_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    executed += 1000;
    if (executed > BUDGET)
        luaL_error(L, "instruction budget spent");
}

/* W(name, text): writes a file in D; the name is a plain one. */
static int w_write(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1);
    size_t n;
    const char *s = luaL_checklstring(L, 2, &n);
    if (strspn(name, "abcdefghijklmnopqrstuvwxyz0123456789._") != strlen(name) ||
        name[0] == '.')
        return luaL_error(L, "bad name");
    char p[128];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    if (!f)
        return luaL_error(L, "cannot write %s", p);
    fwrite(s, 1, n, f);
    fclose(f);
    return 0;
}

/* Empties D, so no input sees a file another one wrote. */
static void empty_dir(void);

static void remove_dir(void)
{
    empty_dir();
    rmdir(dir);
}

static void empty_dir(void)
{
    DIR *d = opendir(dir);
    if (!d)
        abort();
    struct dirent *e;
    char p[512];
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
            unlink(p);
        }
    closedir(d);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    /* The core's warnings and Lua's messages go to the stdio stream stderr,
    ** thousands a second; the sanitizers and libFuzzer write to file
    ** descriptor 2 through their own handles, which stays open. */
    say = fdopen(dup(2), "w");
    verbose = getenv("FUZZ_LUA_PRINT") != NULL;
    if (!say)
        abort();
    if (!verbose) {
        FILE *null = fopen("/dev/null", "w");
        if (!null)
            abort();
        stderr = null;
        stdout = null;
    }
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/lancer-fuzz-XXXXXX",
             tmp && strlen(tmp) < 40 ? tmp : "/tmp");
    if (!mkdtemp(dir))
        abort();
    atexit(remove_dir);
    /* An image of 2^28 pixels is a legal size: the cap makes it LC_ENOMEM. */
    lc_memory_cap((size_t)64 << 20);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input in = {data, size, 0};
    text t = {NULL, 0, 0, 0};
    out(&t, "%s", prelude);
    for (int k = 0; k < MAX_STATEMENTS && in.at < in.n; k++)
        statement(&in, &t, k + 1);
    if (verbose)
        fprintf(say, "---- script\n%s----\n", t.s), fflush(say);
    empty_dir();

    lua_heap = 0;
    executed = 0;
    lua_State *L = lua_newstate(capped_alloc, NULL);
    if (!L)
        abort();
    luaL_requiref(L, "_G", luaopen_base, 1);
    luaL_requiref(L, "string", luaopen_string, 1);
    luaL_requiref(L, "table", luaopen_table, 1);
    luaL_requiref(L, "math", luaopen_math, 1);
    lua_settop(L, 0);
    lua_sethook(L, count_hook, LUA_MASKCOUNT, 1000);
    int st = luaL_loadbuffer(L, t.s, t.n, "=fuzz");
    if (st != LUA_OK) {
        /* The generator writes only valid Lua: a syntax error is its bug. */
        fprintf(say, "generated script does not compile: %s\n%s\n", lua_tostring(L, -1),
                t.s);
        fflush(say);
        abort();
    }
    lua_pushcfunction(L, luaopen_lancer_core);
    if (lua_pcall(L, 0, 1, 0) != LUA_OK)
        abort();
    lua_pushfstring(L, "%s/", dir);
    lua_pushcfunction(L, w_write);
    lua_pushboolean(L, verbose);
    st = lua_pcall(L, 4, 0, 0);
    if (st != LUA_OK && verbose)
        fprintf(say, "script error: %s\n", lua_tostring(L, -1));
    lua_close(L);
    free(t.s);
    return 0;
}
