/* obj.c: reading Wavefront OBJ meshes (v, vt, vn, f). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "scene/mesh.h"
#include "base/mem.h"
#include "base/vec.h"

typedef struct { double *a; size_t n, cap; } dbuf;      /* 3 per item */
typedef struct { long *a; size_t n, cap; } lbuf;        /* 3 per corner: v, vt, vn */

static int dpush(dbuf *b, const double x[3])
{
    if (b->n == b->cap) {
        size_t nc = b->cap ? b->cap * 2 : 1024;
        double *p = mem_realloc(b->a, nc * 3 * sizeof *p);
        if (!p)
            return 0;
        b->a = p;
        b->cap = nc;
    }
    memcpy(b->a + 3 * b->n++, x, 3 * sizeof *x);
    return 1;
}

static int lpush(lbuf *b, const long c[3])
{
    if (b->n == b->cap) {
        size_t nc = b->cap ? b->cap * 2 : 1024;
        long *p = mem_realloc(b->a, nc * 3 * sizeof *p);
        if (!p)
            return 0;
        b->a = p;
        b->cap = nc;
    }
    memcpy(b->a + 3 * b->n++, c, 3 * sizeof *c);
    return 1;
}

/* Reads `count` finite numbers after the keyword; extra ones (v's w, vt's
** w) are allowed. */
static int numbers(char *s, double x[3], int count)
{
    x[2] = 0;
    for (int i = 0; i < count; i++) {
        char *end;
        errno = 0;
        x[i] = strtod(s, &end);
        if (end == s || !isfinite(x[i]))
            return 0;
        s = end;
    }
    return 1;
}

/* OBJ indices start at 1; negative ones count back from the latest. -(i + 1)
** cannot overflow, even for LONG_MIN. */
static long resolve(long i, size_t count)
{
    if (i > 0)
        return (unsigned long)i <= count ? i - 1 : -1;
    if (i < 0)
        return (unsigned long)-(i + 1) < count ? (long)count + i : -1;
    return -1;
}

/* A line longer than this is no OBJ line: the reader stops there, rather
** than growing its buffer without end on a file with no newline. */
#define OBJ_MAX_LINE (1 << 20)

enum { LINE_OK, LINE_EOF, LINE_LONG, LINE_NUL, LINE_NOMEM, LINE_ERROR };

/* Reads one line (its newline dropped) into *buf, grown as needed. */
static int read_line(FILE *fp, char **buf, size_t *cap)
{
    size_t n = 0;
    int c;
    while ((c = getc_unlocked(fp)) != EOF && c != '\n') {
        if (c == '\0')
            return LINE_NUL;
        if (n + 1 >= *cap) {
            if (*cap > OBJ_MAX_LINE)
                return LINE_LONG;
            size_t nc = *cap ? 2 * *cap : 256;
            char *p = mem_realloc(*buf, nc);
            if (!p)
                return LINE_NOMEM;
            *buf = p;
            *cap = nc;
        }
        (*buf)[n++] = (char)c;
    }
    if (c == EOF && ferror(fp))
        return LINE_ERROR;
    if (c == EOF && n == 0)
        return LINE_EOF;
    if (!*buf) {                         /* an empty last line before anything */
        *buf = mem_alloc(1);
        if (!*buf)
            return LINE_NOMEM;
        *cap = 1;
    }
    (*buf)[n] = '\0';
    return LINE_OK;
}

/* Parses one corner "v", "v/t", "v//n" or "v/t/n" into c: vertex, texture
** coordinate and normal indices, 0-based (-1: not given). */
static int corner(char *tok, const size_t count[3], long c[3], const char **why)
{
    static const char *const bad[3] = {"expected a vertex index", "bad texture index",
                                       "bad normal index"};
    static const char *const range[3] = {"vertex index out of range",
                                         "texture index out of range",
                                         "normal index out of range"};
    char *t = tok;
    c[0] = c[1] = c[2] = -1;
    for (int k = 0; k < 3; k++) {
        if (k > 0) {
            if (*t != '/')
                break;
            t++;
            if (*t == '/' || *t == '\0')          /* v//n: no texture index */
                continue;
        }
        char *end;
        long i = strtol(t, &end, 10);
        if (end == t) {
            *why = bad[k];
            return 0;
        }
        if ((c[k] = resolve(i, count[k])) < 0) {
            *why = range[k];
            return 0;
        }
        t = end;
    }
    if (*t != '\0') {
        *why = "unexpected characters in a face";
        return 0;
    }
    return 1;
}

/* Vertices that carry a texture coordinate or a normal are split per
** (v, vt, vn) triplet, found by hashing; use[k] says which of vt and vn the
** mesh keeps (those every corner has). */
static lc_status with_attributes(lc_mesh *m, const dbuf *v, const dbuf *vt, const dbuf *vn,
                                 const lbuf *c, const int use[3], lc_error *err)
{
    size_t cap = 16;
    while (cap < 2 * c->n)
        cap *= 2;
    long *key = mem_alloc(cap * 3 * sizeof *key);
    uint32_t *val = mem_alloc(cap * sizeof *val);
    uint32_t *tri = mem_alloc((c->n + 1) * sizeof *tri);
    lc_status st = LC_OK;
    if (!key || !val || !tri) {
        st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading a mesh");
        goto done;
    }
    for (size_t i = 0; i < cap; i++)
        key[3 * i] = -1;
    for (size_t i = 0; i < c->n && st == LC_OK; i++) {
        long a = c->a[3 * i], b = use[1] ? c->a[3 * i + 1] : -1;
        long n = use[2] ? c->a[3 * i + 2] : -1;
        size_t h = ((size_t)a * 2654435761u ^ (size_t)b * 40503u ^ (size_t)n * 97u) &
                   (cap - 1);
        while (key[3 * h] >= 0 &&
               (key[3 * h] != a || key[3 * h + 1] != b || key[3 * h + 2] != n))
            h = (h + 1) & (cap - 1);
        if (key[3 * h] < 0) {
            key[3 * h] = a;
            key[3 * h + 1] = b;
            key[3 * h + 2] = n;
            val[h] = (uint32_t)m->nv;
            st = lc_mesh_add_vertices(m, v->a + 3 * a, 1, err);
            if (st == LC_OK && use[1])
                st = lc_mesh_add_uvs(m, vt->a + 3 * b, 1, err);
            if (st == LC_OK && use[2])
                st = lc_mesh_add_normals(m, vn->a + 3 * n, 1, err);
        }
        tri[i] = val[h];
    }
    if (st == LC_OK)
        st = lc_mesh_add_faces(m, tri, c->n / 3, err);
done:
    mem_free(key);
    mem_free(val);
    mem_free(tri);
    return st;
}

/* usemtl and mtllib: a slot per material name in the order first used, the
** slot of each triangle, and the material libraries named. */
typedef struct {
    char   **name;         /* by slot; NULL for the faces before any usemtl */
    size_t   n, cap;
    long     current;      /* the slot faces take now; -1: none chosen yet */
    uint32_t *tri;         /* per triangle */
    size_t   ntri, captri;
    char   **lib;
    size_t   nlib, caplib;
    int      used;         /* a usemtl came */
} obj_materials;

static int grow(void **a, size_t *cap, size_t n, size_t size)
{
    if (n < *cap)
        return 1;
    size_t nc = *cap ? 2 * *cap : 16;
    void *p = mem_realloc(*a, nc * size);
    if (!p)
        return 0;
    *a = p;
    *cap = nc;
    return 1;
}

static char *dup_range(const char *a, size_t n)
{
    char *d = mem_alloc(n + 1);
    if (d) {
        memcpy(d, a, n);
        d[n] = '\0';
    }
    return d;
}

/* The slot of name (NULL: the unnamed one), added when new; -1 out of memory
** or past LC_MAX_SLOTS. */
static long slot_of(obj_materials *om, const char *name)
{
    for (size_t i = 0; i < om->n; i++)
        if ((!name && !om->name[i]) || (name && om->name[i] && !strcmp(name, om->name[i])))
            return (long)i;
    if (om->n >= LC_MAX_SLOTS || !grow((void **)&om->name, &om->cap, om->n, sizeof *om->name))
        return -1;
    om->name[om->n] = name ? dup_range(name, strlen(name)) : NULL;
    if (name && !om->name[om->n])
        return -1;
    return (long)om->n++;
}

/* A library's path: as given when absolute, else beside the OBJ file. */
static char *beside(const char *obj, const char *file, size_t n)
{
    const char *slash = strrchr(obj, '/');
    if (file[0] == '/' || !slash)
        return dup_range(file, n);
    size_t dir = (size_t)(slash - obj) + 1;
    char *d = mem_alloc(dir + n + 1);
    if (d) {
        memcpy(d, obj, dir);
        memcpy(d + dir, file, n);
        d[dir + n] = '\0';
    }
    return d;
}

static void materials_free(obj_materials *om)
{
    for (size_t i = 0; i < om->n; i++)
        mem_free(om->name[i]);
    mem_free(om->name);
    for (size_t i = 0; i < om->nlib; i++)
        mem_free(om->lib[i]);
    mem_free(om->lib);
    mem_free(om->tri);
}

/* Gives the mesh its faces' slots, their names and the libraries (taken
** from om). */
static lc_status materials_give(obj_materials *om, lc_mesh *m, lc_error *err)
{
    if (om->used) {
        lc_status st = lc_mesh_add_face_materials(m, om->tri, om->ntri, err);
        if (st)
            return st;
        m->nslots = (uint32_t)om->n;          /* names beyond the last face's slot too */
        m->slot_name = om->name;
        om->name = NULL;
        om->n = 0;
    }
    m->mtllib = om->lib;
    m->nmtllib = om->nlib;
    om->lib = NULL;
    om->nlib = 0;
    return LC_OK;
}

/* One OBJ file being read: what its lines gave so far. */
typedef struct {
    const char   *path;
    size_t        lineno;
    lc_error     *err;
    dbuf          attr[3];     /* v, vt, vn */
    lbuf          c;           /* triangle corners, 3 per triangle */
    int           all[3];      /* every corner has a vt, a vn */
    obj_materials om;
} obj_reader;

static lc_status out_of_memory(obj_reader *r)
{
    return error_fail(r->err, LC_ENOMEM, NULL, "out of memory reading '%s' at line %zu",
                      r->path, r->lineno);
}

/* What read_line said, when it gave no line. */
static lc_status line_failed(obj_reader *r, int got)
{
    if (got == LINE_NOMEM)
        return out_of_memory(r);
    if (got == LINE_ERROR)
        return error_fail(r->err, LC_EIO, "path", "cannot read '%s' at line %zu: %s",
                          r->path, r->lineno, strerror(errno));
    return error_fail(r->err, LC_EARG, "path", "%s:%zu: %s: not an OBJ file", r->path,
                      r->lineno, got == LINE_NUL ? "a NUL byte" : "a line longer than 1 MiB");
}

/* 0 v, 1 vt, 2 vn: the attribute line s gives; -1 none. */
static int attribute_kind(const char *s)
{
    if (strncmp(s, "v ", 2) == 0 || strncmp(s, "v\t", 2) == 0)
        return 0;
    if (strncmp(s, "vt ", 3) == 0 || strncmp(s, "vt\t", 3) == 0)
        return 1;
    if (strncmp(s, "vn ", 3) == 0 || strncmp(s, "vn\t", 3) == 0)
        return 2;
    return -1;
}

/* Whether s is the keyword `key` followed by a blank (or, when bare is
** set, by nothing). */
static int keyword(const char *s, const char *key, int bare)
{
    size_t n = strlen(key);
    return strncmp(s, key, n) == 0 &&
           (s[n] == ' ' || s[n] == '\t' || (bare && s[n] == '\0'));
}

static lc_status read_attribute(obj_reader *r, char *s, int kind)
{
    static const char *const key[3] = {"v", "vt", "vn"};
    double x[3];
    int need = kind == 1 ? 2 : 3;
    if (!numbers(s + (kind ? 2 : 1), x, need))
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: '%s' needs %d finite numbers",
                          r->path, r->lineno, key[kind], need);
    if (kind == 0 && !(v3_max_abs(v3(x[0], x[1], x[2])) <= LC_MAX_COORD))
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: 'v' must be within +-%g "
                          "(lancer's coordinate range)", r->path, r->lineno, LC_MAX_COORD);
    if (!dpush(&r->attr[kind], x))
        return out_of_memory(r);
    return LC_OK;
}

static lc_status read_usemtl(obj_reader *r, char *s)
{
    char *name = s + 6 + strspn(s + 6, " \t");
    size_t n = strlen(name);
    while (n > 0 && (name[n - 1] == ' ' || name[n - 1] == '\t'))
        name[--n] = '\0';
    r->om.used = 1;
    if (n == 0)
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: 'usemtl' needs a material name",
                          r->path, r->lineno);
    if ((r->om.current = slot_of(&r->om, name)) < 0)
        return error_fail(r->err, LC_ENOMEM, NULL, "%s:%zu: out of memory, or more than "
                          "%d materials", r->path, r->lineno, LC_MAX_SLOTS);
    return LC_OK;
}

static lc_status read_mtllib(obj_reader *r, char *s)
{
    obj_materials *om = &r->om;
    char *save = NULL;
    for (char *f = strtok_r(s + 6, " \t", &save); f; f = strtok_r(NULL, " \t", &save)) {
        char *lib = grow((void **)&om->lib, &om->caplib, om->nlib, sizeof *om->lib) ?
                    beside(r->path, f, strlen(f)) : NULL;
        if (!lib)
            return out_of_memory(r);
        om->lib[om->nlib++] = lib;
    }
    return LC_OK;
}

/* A face of k corners is the fan of triangles (first, prev, cur), each
** taking the slot of the current material. */
static lc_status read_face(obj_reader *r, char *s)
{
    obj_materials *om = &r->om;
    if (om->current < 0 && (om->current = slot_of(om, NULL)) < 0)
        return out_of_memory(r);
    const size_t count[3] = {r->attr[0].n, r->attr[1].n, r->attr[2].n};
    long first[3] = {0, 0, 0}, prev[3] = {0, 0, 0};
    int k = 0;
    char *save = NULL;
    for (char *tok = strtok_r(s + 1, " \t", &save); tok;
         tok = strtok_r(NULL, " \t", &save), k++) {
        long cur[3];
        const char *why = NULL;
        if (!corner(tok, count, cur, &why))
            return error_fail(r->err, LC_EARG, NULL, "%s:%zu: %s ('%s')", r->path,
                              r->lineno, why, tok);
        r->all[1] &= cur[1] >= 0;
        r->all[2] &= cur[2] >= 0;
        if (k == 0)
            memcpy(first, cur, sizeof cur);
        if (k >= 2) {
            if (!lpush(&r->c, first) || !lpush(&r->c, prev) || !lpush(&r->c, cur) ||
                !grow((void **)&om->tri, &om->captri, om->ntri, sizeof *om->tri))
                return out_of_memory(r);
            om->tri[om->ntri++] = (uint32_t)om->current;
        }
        memcpy(prev, cur, sizeof cur);
    }
    if (k < 3)
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: a face needs at least 3 "
                          "vertices, got %d", r->path, r->lineno, k);
    return LC_OK;
}

/* One line, its comment and trailing newline dropped. Anything but v, vt,
** vn, usemtl, mtllib and f (o, g, s, l, ...) is skipped. */
static lc_status read_obj_line(obj_reader *r, char *line)
{
    char *s = line + strspn(line, " \t");
    s[strcspn(s, "\r\n#")] = '\0';
    int kind = attribute_kind(s);
    if (kind >= 0)
        return read_attribute(r, s, kind);
    if (keyword(s, "usemtl", 1))
        return read_usemtl(r, s);
    if (keyword(s, "mtllib", 0))
        return read_mtllib(r, s);
    if (keyword(s, "f", 0))
        return read_face(r, s);
    return LC_OK;
}

static lc_status read_obj(obj_reader *r, FILE *fp)
{
    char *line = NULL;
    size_t cap = 0;
    lc_status st = LC_OK;
    int got;
    while (st == LC_OK && (got = read_line(fp, &line, &cap)) != LINE_EOF) {
        r->lineno++;
        st = got == LINE_OK ? read_obj_line(r, line) : line_failed(r, got);
    }
    mem_free(line);
    if (st == LC_OK && (r->attr[0].n == 0 || r->c.n == 0))
        st = error_fail(r->err, LC_EARG, "path", "'%s' has no %s: not an OBJ file, or an "
                        "empty one", r->path, r->attr[0].n == 0 ? "vertices ('v' lines)" :
                        "faces ('f' lines)");
    return st;
}

/* The mesh of what was read: its vertices shared by every corner, unless
** every corner has a texture coordinate or a normal (with_attributes). */
static lc_status fill_mesh(obj_reader *r, lc_mesh *m)
{
    const lbuf *c = &r->c;
    int use[3] = {1, r->all[1] && r->attr[1].n > 0, r->all[2] && r->attr[2].n > 0};
    lc_status st = LC_OK;
    if (use[1] || use[2]) {
        st = with_attributes(m, &r->attr[0], &r->attr[1], &r->attr[2], c, use, r->err);
    } else {
        uint32_t *tri = mem_alloc((c->n + 1) * sizeof *tri);
        if (!tri)
            return error_fail(r->err, LC_ENOMEM, NULL, "out of memory reading '%s'",
                              r->path);
        for (size_t i = 0; i < c->n; i++)
            tri[i] = (uint32_t)c->a[3 * i];
        st = lc_mesh_add_vertices(m, r->attr[0].a, r->attr[0].n, r->err);
        if (st == LC_OK)
            st = lc_mesh_add_faces(m, tri, c->n / 3, r->err);
        mem_free(tri);
    }
    if (st == LC_OK)
        st = materials_give(&r->om, m, r->err);
    return st;
}

lc_mesh *lc_mesh_load_obj(const char *path, lc_error *err)
{
    FILE *fp = fopen(path, "r");
    if (!fp) {
        error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    obj_reader r;
    memset(&r, 0, sizeof r);
    r.path = path;
    r.err = err;
    r.all[0] = r.all[1] = r.all[2] = 1;
    r.om.current = -1;
    lc_status st = read_obj(&r, fp);
    fclose(fp);
    lc_mesh *m = NULL;
    if (st == LC_OK && (m = lc_mesh_new(err)) == NULL)
        st = LC_ENOMEM;
    if (st == LC_OK)
        st = fill_mesh(&r, m);
    materials_free(&r.om);
    for (int k = 0; k < 3; k++)
        mem_free(r.attr[k].a);
    mem_free(r.c.a);
    if (st != LC_OK) {
        lc_mesh_free(m);
        return NULL;
    }
    error_ok(err);
    return m;
}
