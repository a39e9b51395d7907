/* texture.c: textures: solid patterns over space, images over texture
** coordinates, and mixes of two; checked when added, evaluated where a
** material that uses them is hit. */
#include <math.h>
#include <string.h>
#include "base/error.h"
#include "image/image.h"
#include "base/mem.h"
#include "texture.h"
#include "base/validate.h"
#include "base/vec.h"

typedef struct {
    lc_texture d;          /* as given; d.image is NULL here: px holds the copy */
    lc_transform inv;      /* xf^-1 when moved */
    float   *px;           /* image: linear RGB, row 0 at the top */
    int      w, h;
    lc_vec3  axis;         /* stripes: unit; gradient: axis / |axis|^2 */
} texture;

struct lc_textures {
    texture *t;
    size_t   n, cap;
    int     *depth;        /* textures within each, itself counted */
};

lc_texture lc_texture_default(lc_texture_kind kind)
{
    lc_texture t;
    memset(&t, 0, sizeof t);
    t.kind = kind;
    t.a = (lc_color){1, 1, 1};
    t.b = (lc_color){0, 0, 0};
    t.c = (lc_color){0, 0, 0};
    t.amount = 0.5;
    t.scale = 1;
    t.axis = v3(kind == LC_TEX_GRADIENT ? 0 : 1, kind == LC_TEX_GRADIENT ? 1 : 0, 0);
    t.octaves = 4;
    t.turbulence = kind == LC_TEX_MARBLE || kind == LC_TEX_WOOD ? 1 : 0;
    t.mapping = kind == LC_TEX_IMAGE ? LC_MAP_UV : LC_MAP_WORLD;
    t.xf = lc_transform_identity();
    t.wrap = LC_WRAP_REPEAT;
    return t;
}

lc_textures *lc_textures_new(lc_error *err)
{
    lc_textures *s = mem_calloc(1, sizeof *s);
    if (!s)
        error_fail(err, LC_ENOMEM, NULL, "out of memory making a texture set");
    else
        error_ok(err);
    return s;
}

void lc_textures_free(lc_textures *s)
{
    if (!s)
        return;
    for (size_t i = 0; i < s->n; i++)
        mem_free(s->t[i].px);
    mem_free(s->t);
    mem_free(s->depth);
    mem_free(s);
}

size_t lc_textures_count(const lc_textures *s) { return s->n; }

static int finite_color(lc_color c)
{
    return isfinite(c.r) && isfinite(c.g) && isfinite(c.b);
}

/* A reference to another texture: 0 (none) or 1 + an earlier index. */
static lc_status check_ref(const lc_textures *s, int ref, const char *field, lc_error *err)
{
    if (ref < 0 || (size_t)ref > s->n)
        return error_fail(err, LC_EARG, field, "must name a texture added before this one "
                          "(1..%zu), got %d", s->n, ref);
    return LC_OK;
}

static lc_status check(const lc_textures *s, const lc_texture *t, int *depth, lc_error *err)
{
    if ((unsigned)t->kind >= LC_TEX_KINDS)
        return error_fail(err, LC_EARG, "kind", "unknown texture kind %d", (int)t->kind);
    if (!finite_color(t->a) || !finite_color(t->b) || !finite_color(t->c))
        return error_fail(err, LC_EARG, !finite_color(t->a) ? "a" : !finite_color(t->b) ?
                          "b" : "c", "colour must be finite");
    const int refs[3] = {t->ta, t->tb, t->tamount};
    static const char *const names[3] = {"a", "b", "amount"};
    *depth = 1;
    for (int k = 0; k < 3; k++) {
        if (check_ref(s, refs[k], names[k], err))
            return LC_EARG;
        if (refs[k] && s->depth[refs[k] - 1] + 1 > *depth)
            *depth = s->depth[refs[k] - 1] + 1;
    }
    if (*depth > LC_MAX_TEXTURE_DEPTH)
        return error_fail(err, LC_EARG, "a", "textures nest %d deep, past lancer's %d",
                          *depth, LC_MAX_TEXTURE_DEPTH);
    if (t->kind == LC_TEX_MIX && !(t->amount >= 0 && t->amount <= 1))
        return error_fail(err, LC_EARG, "amount", "must be in [0, 1], got %g", t->amount);
    if (validate_length(t->scale, "scale", err))
        return LC_EARG;
    if ((t->kind == LC_TEX_STRIPES || t->kind == LC_TEX_GRADIENT) &&
        validate_nonzero(t->axis, "axis", err))
        return LC_EARG;
    if (t->kind == LC_TEX_GRADIENT && validate_vec(t->origin, "origin", err))
        return LC_EARG;
    if (t->kind == LC_TEX_NOISE || t->kind == LC_TEX_MARBLE || t->kind == LC_TEX_WOOD) {
        if (t->octaves < 1 || t->octaves > LC_MAX_OCTAVES)
            return error_fail(err, LC_EARG, "octaves", "must be in [1, %d], got %d",
                              LC_MAX_OCTAVES, t->octaves);
        if (!(t->turbulence >= 0 && t->turbulence <= 1e6))
            return error_fail(err, LC_EARG, "turbulence", "must be in [0, 1e6], got %g",
                              t->turbulence);
    }
    if ((unsigned)t->mapping > LC_MAP_UV)
        return error_fail(err, LC_EARG, "mapping", "unknown mapping %d", (int)t->mapping);
    if (t->moved && lc_transform_check(&t->xf, err))
        return LC_EARG;
    if (t->kind == LC_TEX_IMAGE) {
        if (!t->image)
            return error_fail(err, LC_EARG, "image", "an image texture needs an image");
        if ((unsigned)t->wrap > LC_WRAP_MIRROR)
            return error_fail(err, LC_EARG, "wrap", "unknown wrap %d", (int)t->wrap);
        if (lc_image_nonfinite(t->image))
            return error_fail(err, LC_EARG, "image", "has %zu NaN or infinite channels",
                              lc_image_nonfinite(t->image));
    }
    return LC_OK;
}

int lc_textures_add(lc_textures *s, const lc_texture *t, lc_error *err)
{
    int depth = 1;
    if (check(s, t, &depth, err))
        return -1;
    if (s->n >= (size_t)1 << 24)
        return error_fail(err, LC_ENOMEM, NULL, "more than 2^24 textures"), -1;
    if (s->n == s->cap) {
        size_t nc = s->cap ? 2 * s->cap : 8;
        texture *nt = mem_realloc(s->t, nc * sizeof *nt);
        if (!nt)
            return error_fail(err, LC_ENOMEM, NULL, "out of memory adding a texture"), -1;
        s->t = nt;
        int *nd = mem_realloc(s->depth, nc * sizeof *nd);
        if (!nd)
            return error_fail(err, LC_ENOMEM, NULL, "out of memory adding a texture"), -1;
        s->depth = nd;
        s->cap = nc;
    }
    texture x;
    memset(&x, 0, sizeof x);
    x.d = *t;
    x.d.image = NULL;
    if (t->moved && lc_transform_inverse(&t->xf, &x.inv, err))
        return -1;
    if (t->kind == LC_TEX_STRIPES)
        x.axis = v3_norm(t->axis);
    else if (t->kind == LC_TEX_GRADIENT)
        x.axis = v3_mul(t->axis, 1 / v3_dot(t->axis, t->axis));
    if (t->kind == LC_TEX_IMAGE) {
        x.w = t->image->width;
        x.h = t->image->height;
        size_t bytes = 3 * (size_t)x.w * (size_t)x.h * sizeof *x.px;
        x.px = mem_alloc(bytes);
        if (!x.px)
            return error_fail(err, LC_ENOMEM, NULL, "out of memory copying a %dx%d texture "
                              "image", x.w, x.h), -1;
        memcpy(x.px, t->image->px, bytes);
    }
    s->t[s->n] = x;
    s->depth[s->n] = depth;
    error_ok(err);
    return (int)s->n++;
}

/* ---- Perlin's improved noise (2002), his reference implementation ------------- */

static const unsigned char perm[256] = {
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30,
    69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94,
    252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136,
    171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229,
    122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63,
    161, 1, 216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188,
    159, 86, 164, 100, 109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38,
    147, 118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42,
    223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172,
    9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246,
    97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249,
    14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45,
    127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78,
    66, 215, 61, 156, 180};

static int P(int i) { return perm[i & 255]; }
static double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
static double lerp(double t, double a, double b) { return a + t * (b - a); }

static double grad(int hash, double x, double y, double z)
{
    int h = hash & 15;
    double u = h < 8 ? x : y, v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

/* The lattice cell of x, mod 256, and x's place in it: exact for any
** finite x (no conversion of a large floor to int). */
static int cell(double *x)
{
    double f = floor(*x);
    *x -= f;
    return (int)(f - 256 * floor(f / 256));
}

double lc_noise(lc_vec3 p)
{
    double x = p.x, y = p.y, z = p.z;
    if (!isfinite(x + y + z))
        return 0;
    int X = cell(&x), Y = cell(&y), Z = cell(&z);
    double u = fade(x), v = fade(y), w = fade(z);
    int A = P(X) + Y, AA = P(A) + Z, AB = P(A + 1) + Z;
    int B = P(X + 1) + Y, BA = P(B) + Z, BB = P(B + 1) + Z;
    double n = lerp(w, lerp(v, lerp(u, grad(P(AA), x, y, z), grad(P(BA), x - 1, y, z)),
                               lerp(u, grad(P(AB), x, y - 1, z), grad(P(BB), x - 1, y - 1, z))),
                    lerp(v, lerp(u, grad(P(AA + 1), x, y, z - 1),
                                 grad(P(BA + 1), x - 1, y, z - 1)),
                         lerp(u, grad(P(AB + 1), x, y - 1, z - 1),
                              grad(P(BB + 1), x - 1, y - 1, z - 1))));
    return fmax(-1, fmin(1, n));      /* its gradients keep it within about 1.04 */
}

/* Octaves of noise, each at twice the frequency and half the weight of the
** last, over their total weight: in [-1, 1]; `absolute` sums |noise| (in
** [0, 1]), Perlin's turbulence. */
static double octaves(lc_vec3 p, int n, int absolute)
{
    double sum = 0, weight = 1, total = 0;
    for (int k = 0; k < n; k++) {
        double v = lc_noise(p);
        sum += weight * (absolute ? fabs(v) : v);
        total += weight;
        weight *= 0.5;
        p = v3_mul(p, 2);
    }
    return sum / total;
}

/* ---- evaluation ------------------------------------------------------------------ */

static double parity(double f) { return fmod(fabs(f), 2.0); }    /* 0 or 1 */

/* Image coordinate u (1 across the image) wrapped into [0, 1]. */
static double wrap01(double u, lc_texture_wrap w)
{
    switch (w) {
    case LC_WRAP_CLAMP: return fmin(1, fmax(0, u));
    case LC_WRAP_MIRROR: {
        double m = u - 2 * floor(u / 2);
        return m > 1 ? 2 - m : m;
    }
    default: return u - floor(u);
    }
}

/* Texel index i (may be -1 or n) of a row or column of n, as wrap says. */
static int texel(int i, int n, lc_texture_wrap w)
{
    if (i >= 0 && i < n)
        return i;
    if (w == LC_WRAP_REPEAT)
        return i < 0 ? n - 1 : 0;
    return i < 0 ? 0 : n - 1;                 /* clamp; mirror reflects the edge texel */
}

static lc_color fetch(const texture *t, int x, int y)
{
    const float *p = t->px + 3 * ((size_t)y * t->w + x);
    return (lc_color){p[0], p[1], p[2]};
}

/* Within this of a texel centre, a lookup is the texel itself: a render
** aligned to the texels reproduces the image exactly. */
#define TEXEL_SNAP 0x1p-30

static lc_color image_at(const texture *t, double u, double v)
{
    u = wrap01(u, t->d.wrap);
    v = wrap01(v, t->d.wrap);
    if (t->d.nearest) {
        int x = (int)fmin(t->w - 1, floor(u * t->w));
        int y = (int)fmin(t->h - 1, floor((1 - v) * t->h));
        return fetch(t, x, y);
    }
    double fx = u * t->w - 0.5, fy = (1 - v) * t->h - 0.5;
    double x0 = floor(fx), y0 = floor(fy), a = fx - x0, b = fy - y0;
    if (a < TEXEL_SNAP) a = 0;
    if (a > 1 - TEXEL_SNAP) a = 0, x0 += 1;
    if (b < TEXEL_SNAP) b = 0;
    if (b > 1 - TEXEL_SNAP) b = 0, y0 += 1;
    int xa = texel((int)x0, t->w, t->d.wrap), xb = texel((int)x0 + 1, t->w, t->d.wrap);
    int ya = texel((int)y0, t->h, t->d.wrap), yb = texel((int)y0 + 1, t->h, t->d.wrap);
    lc_color c00 = fetch(t, xa, ya), c10 = fetch(t, xb, ya);
    lc_color c01 = fetch(t, xa, yb), c11 = fetch(t, xb, yb);
    double w00 = (1 - a) * (1 - b), w10 = a * (1 - b), w01 = (1 - a) * b, w11 = a * b;
    return (lc_color){(float)(w00 * c00.r + w10 * c10.r + w01 * c01.r + w11 * c11.r),
                      (float)(w00 * c00.g + w10 * c10.g + w01 * c01.g + w11 * c11.g),
                      (float)(w00 * c00.b + w10 * c10.b + w01 * c01.b + w11 * c11.b)};
}

static lc_color blend(lc_color a, lc_color b, double t)
{
    return (lc_color){(float)(a.r + t * (b.r - a.r)), (float)(a.g + t * (b.g - a.g)),
                      (float)(a.b + t * (b.b - a.b))};
}

static double luminance(lc_color c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

static lc_color eval(const lc_textures *s, int i, lc_vec3 p, lc_vec3 q, const double uv[2]);

/* Colour slot a or b: its own texture where it names one. */
static lc_color slot(const lc_textures *s, int ref, lc_color c, lc_vec3 p, lc_vec3 q,
                     const double uv[2])
{
    return ref ? eval(s, ref - 1, p, q, uv) : c;
}

static lc_color eval(const lc_textures *s, int i, lc_vec3 p, lc_vec3 q, const double uv[2])
{
    const texture *t = &s->t[i];
    const lc_texture *d = &t->d;
    lc_vec3 x = d->mapping == LC_MAP_UV ? v3(uv[0], uv[1], 0) :
                d->mapping == LC_MAP_OBJECT ? q : p;
    if (d->moved)
        x = lc_transform_point(&t->inv, x);
    lc_vec3 xs = v3_mul(x, 1 / d->scale);
    int second;                                /* b rather than a */
    double k;                                  /* or the share of b */
    switch (d->kind) {
    case LC_TEX_CHECKER:
        second = parity(floor(xs.x) + floor(xs.y) + floor(xs.z)) == 1;
        return second ? slot(s, d->tb, d->b, p, q, uv) : slot(s, d->ta, d->a, p, q, uv);
    case LC_TEX_STRIPES:
        second = parity(floor(v3_dot(xs, t->axis))) == 1;
        return second ? slot(s, d->tb, d->b, p, q, uv) : slot(s, d->ta, d->a, p, q, uv);
    case LC_TEX_GRADIENT:
        k = fmin(1, fmax(0, v3_dot(v3_sub(x, d->origin), t->axis)));
        break;
    case LC_TEX_NOISE:
        k = d->turbulence > 0 ? octaves(xs, d->octaves, 1)
                              : 0.5 + 0.5 * octaves(xs, d->octaves, 0);
        break;
    case LC_TEX_MARBLE:
        k = 0.5 + 0.5 * sin(2 * PI * (xs.x + d->turbulence * octaves(xs, d->octaves, 1)));
        break;
    case LC_TEX_WOOD: {
        double r = hypot(xs.x, xs.z) + d->turbulence * octaves(xs, d->octaves, 0);
        k = r - floor(r);
        break;
    }
    case LC_TEX_IMAGE:
        return image_at(t, xs.x, xs.y);
    case LC_TEX_SKY: {
        double len = v3_len(x), y = len > 0 ? fmax(-1, fmin(1, x.y / len)) : 0;
        lc_color hz = slot(s, d->tb, d->b, p, q, uv);
        return y >= 0 ? blend(hz, slot(s, d->ta, d->a, p, q, uv), y) : blend(hz, d->c, -y);
    }
    default:                                   /* LC_TEX_MIX */
        k = d->tamount ? luminance(eval(s, d->tamount - 1, p, q, uv)) : d->amount;
        break;
    }
    return blend(slot(s, d->ta, d->a, p, q, uv), slot(s, d->tb, d->b, p, q, uv), k);
}

lc_color lc_textures_eval(const lc_textures *s, int i, lc_vec3 p, lc_vec3 q,
                          const double uv[2])
{
    if (!s || i < 0 || (size_t)i >= s->n)
        return (lc_color){0, 0, 0};
    return eval(s, i, p, q, uv);
}

double textures_scalar(const lc_textures *s, int i, lc_vec3 p, lc_vec3 q, const double uv[2])
{
    return luminance(lc_textures_eval(s, i, p, q, uv));
}

double textures_step(const lc_textures *s, int i)
{
    return 1e-3 * s->t[i].d.scale;
}

int textures_image(const lc_textures *s, int i, const float **px, int *w, int *h,
                   int *nearest)
{
    const texture *t = &s->t[i];
    if (t->d.kind != LC_TEX_IMAGE || t->d.mapping != LC_MAP_UV || t->d.moved ||
        t->d.scale != 1)
        return 0;
    *px = t->px;
    *w = t->w;
    *h = t->h;
    *nearest = t->d.nearest != 0;
    return 1;
}

int textures_use_uv(const lc_textures *s, int i)
{
    const lc_texture *d = &s->t[i].d;
    if (d->mapping == LC_MAP_UV)
        return 1;
    const int refs[3] = {d->ta, d->tb, d->tamount};
    for (int k = 0; k < 3; k++)
        if (refs[k] && textures_use_uv(s, refs[k] - 1))
            return 1;
    return 0;
}

/* Marks texture i and those within it. */
static void mark_within(const lc_textures *s, int i, unsigned char *mark)
{
    const lc_texture *d = &s->t[i].d;
    mark[i] = 1;
    const int refs[3] = {d->ta, d->tb, d->tamount};
    for (int k = 0; k < 3; k++)
        if (refs[k] && !mark[refs[k] - 1])
            mark_within(s, refs[k] - 1, mark);
}

lc_textures *textures_transformed(const lc_textures *s, double scale, lc_vec3 offset,
                                  int keep, lc_error *err)
{
    lc_textures *c = lc_textures_new(err);
    lc_transform move = {{{scale, 0, 0, offset.x}, {0, scale, 0, offset.y},
                          {0, 0, scale, offset.z}}};
    unsigned char *kept = c && keep ? mem_calloc(s->n, 1) : NULL;
    if (c && keep && !kept) {
        lc_textures_free(c);
        error_fail(err, LC_ENOMEM, NULL, "out of memory copying textures");
        return NULL;
    }
    if (kept)
        mark_within(s, keep - 1, kept);
    for (size_t i = 0; c && i < s->n; i++) {
        const texture *t = &s->t[i];
        lc_texture d = t->d;
        lc_image img;
        memset(&img, 0, sizeof img);
        img.width = t->w, img.height = t->h, img.px = t->px;
        d.image = t->px ? &img : NULL;
        if (d.mapping == LC_MAP_WORLD && !(kept && kept[i])) {
            d.xf = d.moved ? lc_transform_compose(&move, &d.xf) : move;
            d.moved = 1;
        }
        if (lc_textures_add(c, &d, err) < 0) {
            lc_textures_free(c);
            c = NULL;
        }
    }
    mem_free(kept);
    return c;
}
