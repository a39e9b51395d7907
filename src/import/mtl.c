/* mtl.c: Wavefront material libraries (.mtl), and their mapping onto
** lancer's materials. */
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "base/mem.h"

#define MTL_MAX_LINE 4096
#define MTL_MAX_MATERIALS 65536

static lc_mtl mtl_default(void)
{
    lc_mtl m;
    memset(&m, 0, sizeof m);
    m.kd = (lc_color){0.8f, 0.8f, 0.8f};      /* the format's own default */
    m.ns = 0;
    m.d = 1;
    m.ni = 1;
    m.illum = -1;
    m.bump_mult = 1;
    return m;
}

/* One .mtl file being read: the materials so far, the last the one its
** statements set. */
typedef struct {
    const char *path;
    size_t      lineno;
    lc_error   *err;
    lc_mtl     *list;      /* realloc'd: the caller free()s it */
    size_t      n, cap;
} mtl_reader;

static lc_status needs(const mtl_reader *r, const char *key, const char *what)
{
    return error_fail(r->err, LC_EARG, NULL, "%s:%zu: '%s' needs %s", r->path, r->lineno,
                      key, what);
}

static int number_of(const char *s, double *x)
{
    char *end;
    *x = strtod(s, &end);
    return end != s && isfinite(*x);
}

/* Up to 3 numbers after the keyword: one means grey. Each must be a finite
** double that a float (lc_color's) holds: 1e300 would become infinite. */
static lc_status color_of(const mtl_reader *r, const char *key, const char *s,
                          lc_color *c)
{
    double x[3];
    int n = 0;
    while (n < 3) {
        char *end;
        x[n] = strtod(s, &end);
        if (end == s)
            break;
        if (!isfinite(x[n]))
            return needs(r, key, "finite numbers");
        if (fabs(x[n]) > FLT_MAX)
            return error_fail(r->err, LC_EARG, NULL, "%s:%zu: '%s' needs numbers a float "
                              "holds (to %g), not %g", r->path, r->lineno, key,
                              (double)FLT_MAX, x[n]);
        s = end;
        n++;
    }
    if (n == 0)
        return needs(r, key, "finite numbers");
    if (n < 3)
        x[1] = x[2] = x[0];
    *c = (lc_color){(float)x[0], (float)x[1], (float)x[2]};
    return LC_OK;
}

/* illum: a number an int holds (converting one past it is undefined). */
static lc_status illum_of(const mtl_reader *r, const char *s, int *illum)
{
    double x;
    if (!number_of(s, &x))
        return needs(r, "illum", "finite numbers");
    if (!(x >= INT_MIN && x < (double)INT_MAX + 1))
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: 'illum' needs an integer from "
                          "%d to %d, not %g", r->path, r->lineno, INT_MIN, INT_MAX, x);
    *illum = (int)x;
    return LC_OK;
}

/* A map statement's file: the last word, its options (-bm 0.5, -s 1 1 1,
** ...) before it; -bm read into *bm, 0 when it is not a finite number.
** Resolved beside the .mtl file. */
static int map_of(const char *mtl, char *s, char out[LC_MTL_PATH], double *bm,
                  int *bad_bm)
{
    char *words[64];
    int n = 0;
    char *save = NULL;
    for (char *w = strtok_r(s, " \t", &save); w && n < 64; w = strtok_r(NULL, " \t", &save))
        words[n++] = w;
    if (n == 0)
        return 0;
    for (int i = 0; i + 1 < n - 1; i++)
        if (bm && strcmp(words[i], "-bm") == 0 && !number_of(words[i + 1], bm)) {
            *bad_bm = 1;
            return 0;
        }
    const char *file = words[n - 1];
    const char *slash = strrchr(mtl, '/');
    size_t dir = file[0] == '/' || !slash ? 0 : (size_t)(slash - mtl) + 1;
    if (dir + strlen(file) + 1 > LC_MTL_PATH)
        return 0;
    memcpy(out, mtl, dir);
    strcpy(out + dir, file);
    return 1;
}

/* newmtl NAME: a material of the format's defaults, NAME its trailing
** blanks dropped. */
static lc_status read_newmtl(mtl_reader *r, char *name)
{
    if (*name == '\0' || strlen(name) >= sizeof r->list->name)
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: 'newmtl' needs a name of under "
                          "%zu bytes", r->path, r->lineno, sizeof r->list->name);
    if (r->n >= MTL_MAX_MATERIALS)
        return error_fail(r->err, LC_EARG, NULL, "%s:%zu: more than %d materials", r->path,
                          r->lineno, MTL_MAX_MATERIALS);
    if (r->n == r->cap) {
        size_t nc = r->cap ? 2 * r->cap : 8;
        lc_mtl *p = realloc(r->list, nc * sizeof *p);
        if (!p)
            return error_fail(r->err, LC_ENOMEM, NULL, "out of memory reading '%s'",
                              r->path);
        r->list = p;
        r->cap = nc;
    }
    lc_mtl *m = &r->list[r->n++];
    *m = mtl_default();
    size_t l = strlen(name);
    while (l > 0 && (name[l - 1] == ' ' || name[l - 1] == '\t'))
        name[--l] = '\0';
    memcpy(m->name, name, l + 1);
    return LC_OK;
}

/* A statement `key rest` of material m. Keys lancer does not map are
** skipped. */
static lc_status read_statement(const mtl_reader *r, lc_mtl *m, const char *key,
                                char *rest)
{
    double x;
    int ok = 1, bad_bm = 0;
    if (strcmp(key, "Kd") == 0) return color_of(r, key, rest, &m->kd);
    if (strcmp(key, "Ks") == 0) return color_of(r, key, rest, &m->ks);
    if (strcmp(key, "Ka") == 0) return color_of(r, key, rest, &m->ka);
    if (strcmp(key, "Ke") == 0) return color_of(r, key, rest, &m->ke);
    if (strcmp(key, "illum") == 0) return illum_of(r, rest, &m->illum);
    /* Ns, Ni, d and Tr stay doubles, as the core's material keeps them. */
    if (strcmp(key, "Ns") == 0) ok = number_of(rest, &m->ns);
    else if (strcmp(key, "Ni") == 0) ok = number_of(rest, &m->ni);
    else if (strcmp(key, "d") == 0) ok = number_of(rest, &m->d);
    else if (strcmp(key, "Tr") == 0) { ok = number_of(rest, &x); m->d = 1 - x; }
    else if (strcmp(key, "map_Kd") == 0)
        ok = map_of(r->path, rest, m->map_kd, NULL, NULL);
    else if (strcmp(key, "map_Bump") == 0 || strcmp(key, "bump") == 0 ||
             strcmp(key, "map_bump") == 0)
        ok = map_of(r->path, rest, m->map_bump, &m->bump_mult, &bad_bm);
    else if (strcmp(key, "norm") == 0 || strcmp(key, "map_norm") == 0)
        ok = map_of(r->path, rest, m->map_norm, NULL, NULL);
    if (ok)
        return LC_OK;
    if (bad_bm)
        return needs(r, key, "a finite number after -bm");
    return needs(r, key, strncmp(key, "map", 3) == 0 || strcmp(key, "bump") == 0 ||
                         strcmp(key, "norm") == 0 ? "a file name" : "finite numbers");
}

/* One line, its comment and trailing newline dropped. */
static lc_status read_mtl_line(mtl_reader *r, char *line)
{
    char *s = line + strspn(line, " \t");
    s[strcspn(s, "\r\n#")] = '\0';
    char *key = s, *rest = s + strcspn(s, " \t");
    if (*rest)
        *rest++ = '\0';
    rest += strspn(rest, " \t");
    if (*key == '\0')
        return LC_OK;
    if (strcmp(key, "newmtl") == 0)
        return read_newmtl(r, rest);
    if (r->n == 0)
        return LC_OK;            /* statements before any newmtl belong to none */
    return read_statement(r, &r->list[r->n - 1], key, rest);
}

lc_status lc_mtl_load(const char *path, lc_mtl **out, size_t *count, lc_error *err)
{
    *out = NULL;
    *count = 0;
    FILE *fp = fopen(path, "r");
    if (!fp)
        return error_fail(err, LC_EIO, "path", "cannot open '%s': %s", path, strerror(errno));
    mtl_reader r = {path, 0, err, NULL, 0, 0};
    char line[MTL_MAX_LINE];
    lc_status st = LC_OK;
    while (st == LC_OK && fgets(line, sizeof line, fp)) {
        r.lineno++;
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n' && !feof(fp))
            st = error_fail(err, LC_EARG, NULL, "%s:%zu: a line longer than %d bytes", path,
                            r.lineno, MTL_MAX_LINE - 1);
        else
            st = read_mtl_line(&r, line);
    }
    if (st == LC_OK && ferror(fp))
        st = error_fail(err, LC_EIO, "path", "cannot read '%s': %s", path, strerror(errno));
    fclose(fp);
    if (st != LC_OK) {
        free(r.list);
        return st;
    }
    *out = r.list;
    *count = r.n;
    error_ok(err);
    return LC_OK;
}

static double clamp01(double x) { return isfinite(x) ? fmin(1, fmax(0, x)) : 0; }
static double cmax(lc_color c) { return fmax(c.r, fmax(c.g, c.b)); }
static lc_color clamp_color(lc_color c)
{
    return (lc_color){(float)clamp01(c.r), (float)clamp01(c.g), (float)clamp01(c.b)};
}

lc_material lc_mtl_material(const lc_mtl *t)
{
    lc_material m = lc_material_default();
    m.absorb = LC_ABSORB_DIFFUSE;            /* highlights in the light's colour */
    m.color = clamp_color(t->kd);
    m.kd = 1;
    m.ka = clamp01(cmax(t->ka));
    m.ks = clamp01(cmax(t->ks));
    m.alpha = isfinite(t->ns) ? fmin(1e4, fmax(0, t->ns)) : 0;
    m.emission = (lc_color){fmaxf(0, t->ke.r), fmaxf(0, t->ke.g), fmaxf(0, t->ke.b)};
    /* illum 3 and above trace reflections; the mirror's strength is Ks. */
    if (t->illum >= 3)
        m.kr = m.ks;
    double d = clamp01(t->d);
    if (d < 1) {                             /* see-through: what is not opaque passes */
        m.kt = 1 - d;
        m.kd *= d;
        m.ka *= d;
        m.ior = isfinite(t->ni) ? fmin(LC_MAX_IOR, fmax(1, t->ni)) : 1;
    }
    return m;
}
