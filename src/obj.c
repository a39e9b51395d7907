/* obj.c: reading Wavefront OBJ meshes (v, vn, f). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "error.h"
#include "mesh.h"
#include "mem.h"

typedef struct { double *a; size_t n, cap; } dbuf;      /* 3 per item */
typedef struct { long *a; size_t n, cap; } lbuf;        /* 2 per corner: v, vn */

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

static int lpush(lbuf *b, long v, long vn)
{
    if (b->n == b->cap) {
        size_t nc = b->cap ? b->cap * 2 : 1024;
        long *p = mem_realloc(b->a, nc * 2 * sizeof *p);
        if (!p)
            return 0;
        b->a = p;
        b->cap = nc;
    }
    b->a[2 * b->n] = v;
    b->a[2 * b->n + 1] = vn;
    b->n++;
    return 1;
}

/* Reads 3 finite numbers after the keyword; extra ones (v's w) are allowed. */
static int numbers(char *s, double x[3])
{
    for (int i = 0; i < 3; i++) {
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

/* Parses one corner "v", "v/t", "v//n" or "v/t/n". */
static int corner(char *tok, size_t nv, size_t nn, long *v, long *n, const char **why)
{
    char *end;
    long i = strtol(tok, &end, 10);
    if (end == tok) {
        *why = "expected a vertex index";
        return 0;
    }
    *v = resolve(i, nv);
    *n = -1;
    if (*v < 0) {
        *why = "vertex index out of range";
        return 0;
    }
    if (*end == '/') {
        char *t = end + 1;
        if (*t != '/') {                       /* texture index: checked, unused */
            strtol(t, &end, 10);
            if (end == t) {
                *why = "bad texture index";
                return 0;
            }
            t = end;
        }
        if (*t == '/') {
            t++;
            long k = strtol(t, &end, 10);
            if (end == t) {
                *why = "bad normal index";
                return 0;
            }
            *n = resolve(k, nn);
            if (*n < 0) {
                *why = "normal index out of range";
                return 0;
            }
        }
    }
    if (*end != '\0') {
        *why = "unexpected characters in a face";
        return 0;
    }
    return 1;
}

/* Vertices that carry a normal are split per (v, vn) pair, found by hashing. */
static lc_status with_normals(lc_mesh *m, const dbuf *v, const dbuf *vn, const lbuf *c,
                              lc_error *err)
{
    size_t cap = 16;
    while (cap < 2 * c->n)
        cap *= 2;
    long *key = mem_alloc(cap * 2 * sizeof *key);
    uint32_t *val = mem_alloc(cap * sizeof *val);
    uint32_t *tri = mem_alloc(c->n * sizeof *tri);
    lc_status st = LC_OK;
    if (!key || !val || !tri) {
        st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading a mesh");
        goto done;
    }
    for (size_t i = 0; i < cap; i++)
        key[2 * i] = -1;
    for (size_t i = 0; i < c->n && st == LC_OK; i++) {
        long a = c->a[2 * i], b = c->a[2 * i + 1];
        size_t h = ((size_t)a * 2654435761u ^ (size_t)b * 40503u) & (cap - 1);
        while (key[2 * h] >= 0 && (key[2 * h] != a || key[2 * h + 1] != b))
            h = (h + 1) & (cap - 1);
        if (key[2 * h] < 0) {
            key[2 * h] = a;
            key[2 * h + 1] = b;
            val[h] = (uint32_t)m->nv;
            st = lc_mesh_add_vertices(m, v->a + 3 * a, 1, err);
            if (st == LC_OK)
                st = lc_mesh_add_normals(m, vn->a + 3 * b, 1, err);
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

lc_mesh *lc_mesh_load_obj(const char *path, lc_error *err)
{
    FILE *fp = fopen(path, "r");
    if (!fp) {
        error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    dbuf v = {0}, vn = {0};
    lbuf c = {0};          /* triangle corners, 3 per triangle */
    int all_normals = 1;
    char *line = NULL;
    size_t cap = 0, lineno = 0;
    lc_status st = LC_OK;
    lc_mesh *m = NULL;
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
        if (strncmp(s, "v ", 2) == 0 || strncmp(s, "v\t", 2) == 0 ||
            strncmp(s, "vn ", 3) == 0 || strncmp(s, "vn\t", 3) == 0) {
            int normal = s[1] == 'n';
            double x[3];
            if (!numbers(s + (normal ? 2 : 1), x))
                st = error_fail(err, LC_EARG, NULL, "%s:%zu: '%s' needs 3 finite numbers",
                             path, lineno, normal ? "vn" : "v");
            else if (!dpush(normal ? &vn : &v, x))
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at line "
                                "%zu", path, lineno);
        } else if (strncmp(s, "f ", 2) == 0 || strncmp(s, "f\t", 2) == 0) {
            long first[2] = {0, 0}, prev[2] = {0, 0};
            int k = 0;
            char *save = NULL;
            for (char *tok = strtok_r(s + 1, " \t", &save); tok && st == LC_OK;
                 tok = strtok_r(NULL, " \t", &save), k++) {
                long cur[2];
                const char *why = NULL;
                if (!corner(tok, v.n, vn.n, &cur[0], &cur[1], &why)) {
                    st = error_fail(err, LC_EARG, NULL, "%s:%zu: %s ('%s')", path, lineno, why,
                                 tok);
                    break;
                }
                if (cur[1] < 0)
                    all_normals = 0;
                if (k == 0)
                    memcpy(first, cur, sizeof cur);
                if (k >= 2 && (!lpush(&c, first[0], first[1]) || !lpush(&c, prev[0], prev[1]) ||
                               !lpush(&c, cur[0], cur[1])))
                    st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s' at "
                                    "line %zu", path, lineno);
                memcpy(prev, cur, sizeof cur);
            }
            if (st == LC_OK && k < 3)
                st = error_fail(err, LC_EARG, NULL, "%s:%zu: a face needs at least 3 vertices, "
                             "got %d", path, lineno, k);
        }
        /* Anything else (vt, o, g, s, usemtl, mtllib, l, ...) is skipped. */
    }
    mem_free(line);
    if (st == LC_OK && (v.n == 0 || c.n == 0))
        st = error_fail(err, LC_EARG, "path", "'%s' has no %s: not an OBJ file, or an empty "
                        "one", path, v.n == 0 ? "vertices ('v' lines)" : "faces ('f' lines)");
    fclose(fp);
    if (st == LC_OK && (m = lc_mesh_new(err)) == NULL)
        st = LC_ENOMEM;
    if (st == LC_OK) {
        if (all_normals && c.n > 0 && vn.n > 0) {
            st = with_normals(m, &v, &vn, &c, err);
        } else {
            uint32_t *tri = mem_alloc((c.n + 1) * sizeof *tri);
            if (!tri)
                st = error_fail(err, LC_ENOMEM, NULL, "out of memory reading '%s'", path);
            for (size_t i = 0; st == LC_OK && i < c.n; i++)
                tri[i] = (uint32_t)c.a[2 * i];
            if (st == LC_OK)
                st = lc_mesh_add_vertices(m, v.a, v.n, err);
            if (st == LC_OK)
                st = lc_mesh_add_faces(m, tri, c.n / 3, err);
            mem_free(tri);
        }
    }
    mem_free(v.a);
    mem_free(vn.a);
    mem_free(c.a);
    if (st != LC_OK) {
        lc_mesh_free(m);
        return NULL;
    }
    error_ok(err);
    return m;
}
