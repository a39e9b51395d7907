/* obj.c: reading Wavefront OBJ meshes (v, vt, vn, f). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "error.h"
#include "mesh.h"
#include "mem.h"
#include "vec.h"

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

lc_mesh *lc_mesh_load_obj(const char *path, lc_error *err)
{
    FILE *fp = fopen(path, "r");
    if (!fp) {
        error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    dbuf attr[3] = {{0}, {0}, {0}};     /* v, vt, vn */
    lbuf c = {0};                       /* triangle corners, 3 per triangle */
    int all[3] = {1, 1, 1};             /* every corner has a vt, a vn */
    char *line = NULL;
    size_t cap = 0, lineno = 0;
    lc_status st = LC_OK;
    lc_mesh *m = NULL;
    obj_materials om;
    memset(&om, 0, sizeof om);
    om.current = -1;
    int got;
    while (st == LC_OK && (got = read_line(fp, &line, &cap)) != LINE_EOF) {
        lineno++;
        if (got != LINE_OK) {
            if (got == LINE_NOMEM)
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at line "
                                "%zu", path, lineno);
            else if (got == LINE_ERROR)
                st = error_fail(err, LC_EIO, "path", "cannot read '%s' at line %zu: %s",
                                path, lineno, strerror(errno));
            else
                st = error_fail(err, LC_EARG, "path", "%s:%zu: %s: not an OBJ file", path,
                                lineno, got == LINE_NUL ? "a NUL byte" :
                                "a line longer than 1 MiB");
            break;
        }
        char *s = line + strspn(line, " \t");
        s[strcspn(s, "\r\n#")] = '\0';
        int kind = -1;                  /* 0 v, 1 vt, 2 vn */
        if (strncmp(s, "v ", 2) == 0 || strncmp(s, "v\t", 2) == 0)
            kind = 0;
        else if (strncmp(s, "vt ", 3) == 0 || strncmp(s, "vt\t", 3) == 0)
            kind = 1;
        else if (strncmp(s, "vn ", 3) == 0 || strncmp(s, "vn\t", 3) == 0)
            kind = 2;
        if (kind >= 0) {
            static const char *const key[3] = {"v", "vt", "vn"};
            double x[3];
            int need = kind == 1 ? 2 : 3;
            if (!numbers(s + (kind ? 2 : 1), x, need))
                st = error_fail(err, LC_EARG, NULL, "%s:%zu: '%s' needs %d finite numbers",
                                path, lineno, key[kind], need);
            else if (kind == 0 && !(v3_max_abs(v3(x[0], x[1], x[2])) <= LC_MAX_COORD))
                st = error_fail(err, LC_EARG, NULL, "%s:%zu: 'v' must be within +-%g "
                                "(lancer's coordinate range)", path, lineno, LC_MAX_COORD);
            else if (!dpush(&attr[kind], x))
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at line "
                                "%zu", path, lineno);
        } else if (strncmp(s, "usemtl", 6) == 0 && (s[6] == ' ' || s[6] == '\t' ||
                                                    s[6] == '\0')) {
            char *name = s + 6 + strspn(s + 6, " \t");
            size_t n = strlen(name);
            while (n > 0 && (name[n - 1] == ' ' || name[n - 1] == '\t'))
                name[--n] = '\0';
            if (n == 0)
                st = error_fail(err, LC_EARG, NULL, "%s:%zu: 'usemtl' needs a material name",
                                path, lineno);
            else if ((om.current = slot_of(&om, name)) < 0)
                st = error_fail(err, LC_ENOMEM, NULL, "%s:%zu: out of memory, or more than "
                                "%d materials", path, lineno, LC_MAX_SLOTS);
            om.used = 1;
        } else if (strncmp(s, "mtllib", 6) == 0 && (s[6] == ' ' || s[6] == '\t')) {
            char *save = NULL;
            for (char *f = strtok_r(s + 6, " \t", &save); f && st == LC_OK;
                 f = strtok_r(NULL, " \t", &save)) {
                char *lib = grow((void **)&om.lib, &om.caplib, om.nlib, sizeof *om.lib) ?
                            beside(path, f, strlen(f)) : NULL;
                if (!lib)
                    st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at "
                                    "line %zu", path, lineno);
                else
                    om.lib[om.nlib++] = lib;
            }
        } else if (strncmp(s, "f ", 2) == 0 || strncmp(s, "f\t", 2) == 0) {
            if (om.current < 0 && (om.current = slot_of(&om, NULL)) < 0)
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at line "
                                "%zu", path, lineno);
            const size_t count[3] = {attr[0].n, attr[1].n, attr[2].n};
            long first[3] = {0, 0, 0}, prev[3] = {0, 0, 0};
            int k = 0;
            char *save = NULL;
            for (char *tok = strtok_r(s + 1, " \t", &save); tok && st == LC_OK;
                 tok = strtok_r(NULL, " \t", &save), k++) {
                long cur[3];
                const char *why = NULL;
                if (!corner(tok, count, cur, &why)) {
                    st = error_fail(err, LC_EARG, NULL, "%s:%zu: %s ('%s')", path, lineno,
                                    why, tok);
                    break;
                }
                all[1] &= cur[1] >= 0;
                all[2] &= cur[2] >= 0;
                if (k == 0)
                    memcpy(first, cur, sizeof cur);
                if (k >= 2 && (!lpush(&c, first) || !lpush(&c, prev) || !lpush(&c, cur) ||
                               !grow((void **)&om.tri, &om.captri, om.ntri, sizeof *om.tri)))
                    st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at "
                                    "line %zu", path, lineno);
                else if (k >= 2)
                    om.tri[om.ntri++] = (uint32_t)om.current;
                memcpy(prev, cur, sizeof cur);
            }
            if (st == LC_OK && k < 3)
                st = error_fail(err, LC_EARG, NULL, "%s:%zu: a face needs at least 3 "
                                "vertices, got %d", path, lineno, k);
        }
        /* Anything else (o, g, s, l, ...) is skipped. */
    }
    mem_free(line);
    if (st == LC_OK && (attr[0].n == 0 || c.n == 0))
        st = error_fail(err, LC_EARG, "path", "'%s' has no %s: not an OBJ file, or an empty "
                        "one", path, attr[0].n == 0 ? "vertices ('v' lines)" :
                        "faces ('f' lines)");
    fclose(fp);
    if (st == LC_OK && (m = lc_mesh_new(err)) == NULL)
        st = LC_ENOMEM;
    int use[3] = {1, all[1] && attr[1].n > 0, all[2] && attr[2].n > 0};
    if (st == LC_OK) {
        if (use[1] || use[2]) {
            st = with_attributes(m, &attr[0], &attr[1], &attr[2], &c, use, err);
        } else {
            uint32_t *tri = mem_alloc((c.n + 1) * sizeof *tri);
            if (!tri)
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s'", path);
            for (size_t i = 0; st == LC_OK && i < c.n; i++)
                tri[i] = (uint32_t)c.a[3 * i];
            if (st == LC_OK)
                st = lc_mesh_add_vertices(m, attr[0].a, attr[0].n, err);
            if (st == LC_OK)
                st = lc_mesh_add_faces(m, tri, c.n / 3, err);
            mem_free(tri);
        }
    }
    if (st == LC_OK)
        st = materials_give(&om, m, err);
    materials_free(&om);
    for (int k = 0; k < 3; k++)
        mem_free(attr[k].a);
    mem_free(c.a);
    if (st != LC_OK) {
        lc_mesh_free(m);
        return NULL;
    }
    error_ok(err);
    return m;
}
