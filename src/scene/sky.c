/* sky.c: the background as a texture over directions (a sky gradient, an
** equirectangular image, any texture) looked up where a ray leaves, and
** sampled as a light by paths: by luminance over an image, else uniformly. */
#include <string.h>
#include "base/error.h"
#include "base/mem.h"
#include "base/sample.h"
#include "sky.h"
#include "texture/texture.h"

void lc_sky_uv(lc_vec3 d, double uv[2])
{
    sphere_uv_of_direction(d, uv);
}

radiance sky_radiance(const lc_scene *s, lc_vec3 d)
{
    int i = s->settings.background_texture - 1;
    lc_vec3 u = v3_norm(d);
    double uv[2] = {0, 0};
    if (s->c.sky_uv)
        lc_sky_uv(u, uv);
    lc_color c = lc_textures_eval(s->textures, i, u, u, uv);
    radiance r = {c.r > 0 ? c.r : 0, c.g > 0 ? c.g : 0, c.b > 0 ? c.b : 0};
    return r;
}

radiance sky_seen(const lc_scene *s, lc_vec3 d)
{
    return s->c.needs & LC_NEED_SKY ? sky_radiance(s, d) : rad(s->settings.background);
}

/* ---- the sky as a light ------------------------------------------------------------ */

void sky_dist_free(sky_dist *d)
{
    mem_free(d->row);
    mem_free(d->col);
    mem_free(d->rowp);
    memset(d, 0, sizeof *d);
}

/* The latitude of the centre of row j of h, from +pi/2 at the top. */
static double row_latitude(int j, int h)
{
    return (0.5 - (j + 0.5) / h) * PI;
}

static double luminance(const float *px, int w, int i, int j)
{
    const float *t = px + 3 * ((size_t)j * w + i);
    return 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
}

/* A texel's sampling weight when the sky is filtered (a nearest-texel sky
** takes its own luminance): the mean over the texel of the bilinear
** interpolant, which spreads each texel into its neighbours with weights
** 1/8, 3/4, 1/8 along each axis (around in u, clamped at the poles).
** Weighted by its own luminance, a dim texel next to a sun, which the
** filter lights, was almost never sampled, and BSDF rays that met the
** sun's spread took nearly the whole MIS weight: fireflies
** (tests/lua/test_indirect.lua measures the spread). */
static double reach(const float *px, int w, int h, int i, int j)
{
    static const double k[3] = {0.125, 0.75, 0.125};
    double m = 0;
    for (int dj = -1; dj <= 1; dj++) {
        int y = j + dj < 0 ? 0 : j + dj >= h ? h - 1 : j + dj;
        for (int di = -1; di <= 1; di++)
            m += k[dj + 1] * k[di + 1] * luminance(px, w, (i + di + w) % w, y);
    }
    return m;
}

lc_status sky_dist_build(const lc_scene *s, sky_dist *d, lc_error *err)
{
    sky_dist_free(d);
    const float *px;
    int w, h, nearest;
    if (!(s->c.needs & LC_NEED_SKY) ||
        !textures_image(s->textures, s->settings.background_texture - 1, &px, &w, &h,
                        &nearest))
        return LC_OK;                               /* uniform over the sphere */
    d->row = mem_alloc((size_t)(h + 1) * sizeof *d->row);
    d->rowp = mem_alloc((size_t)h * sizeof *d->rowp);
    d->col = mem_alloc((size_t)h * (size_t)(w + 1) * sizeof *d->col);
    if (!d->row || !d->rowp || !d->col) {
        sky_dist_free(d);
        return error_fail(err, LC_ENOMEM, NULL, "out of memory sampling a %dx%d sky", w, h);
    }
    double total = 0;
    d->row[0] = 0;
    for (int j = 0; j < h; j++) {
        double *c = d->col + (size_t)j * (w + 1), cosl = cos(row_latitude(j, h)), sum = 0;
        c[0] = 0;
        for (int i = 0; i < w; i++) {
            double lum = nearest ? luminance(px, w, i, j) : reach(px, w, h, i, j);
            sum += lum > 0 ? lum * cosl : 0;
            c[i + 1] = sum;
        }
        for (int i = 1; i <= w; i++)
            c[i] = sum > 0 ? c[i] / sum : (double)i / w;
        d->rowp[j] = sum;
        total += sum;
        d->row[j + 1] = total;
    }
    if (!(total > 0) || !isfinite(total)) {       /* black: nothing to prefer */
        sky_dist_free(d);
        return LC_OK;
    }
    for (int j = 0; j < h; j++) {
        d->rowp[j] /= total;
        d->row[j + 1] /= total;
    }
    d->row[h] = 1;
    d->w = w;
    d->h = h;
    return LC_OK;
}

/* The k with cdf[k] <= u < cdf[k + 1] among n entries (cdf[0] = 0, cdf[n] = 1),
** skipping empty ones. */
static int find(const double *cdf, int n, double u)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (cdf[mid] <= u) lo = mid; else hi = mid - 1;
    }
    return lo;
}

static lc_vec3 direction_of(double u, double v)
{
    double lon = (u - 0.5) * 2 * PI, lat = (v - 0.5) * PI;
    return v3(cos(lat) * sin(lon), sin(lat), cos(lat) * cos(lon));
}

double sky_sample(const sky_dist *d, const double u[2], lc_vec3 *dir)
{
    if (!d->w) {
        double z = 1 - 2 * u[0], r = sqrt(fmax(0, 1 - z * z)), phi = 2 * PI * u[1];
        *dir = v3(r * cos(phi), z, r * sin(phi));
        return 1 / (4 * PI);
    }
    int j = find(d->row, d->h, u[0]);
    const double *c = d->col + (size_t)j * (d->w + 1);
    int i = find(c, d->w, u[1]);
    double pj = d->row[j + 1] - d->row[j], pi = c[i + 1] - c[i];
    if (!(pj > 0) || !(pi > 0))
        return 0;
    /* The remainders place the point inside the texel, uniformly. */
    double fv = (u[0] - d->row[j]) / pj, fu = (u[1] - c[i]) / pi;
    double uu = (i + fmin(fu, BELOW_ONE)) / d->w, vv = 1 - (j + fmin(fv, BELOW_ONE)) / d->h;
    *dir = direction_of(uu, vv);
    double cosl = cos((vv - 0.5) * PI);
    if (!(cosl > 0))
        return 0;
    return pj * pi * d->w * d->h / (2 * PI * PI * cosl);
}

double sky_pdf(const sky_dist *d, lc_vec3 dir)
{
    if (!d->w)
        return 1 / (4 * PI);
    double uv[2];
    lc_sky_uv(dir, uv);
    int i = (int)fmin(d->w - 1, fmax(0, floor(uv[0] * d->w)));
    int j = (int)fmin(d->h - 1, fmax(0, floor((1 - uv[1]) * d->h)));
    const double *c = d->col + (size_t)j * (d->w + 1);
    double cosl = sqrt(fmax(0, 1 - dir.y * dir.y));
    if (!(cosl > 0))
        return 0;
    return (d->row[j + 1] - d->row[j]) * (c[i + 1] - c[i]) * d->w * d->h /
           (2 * PI * PI * cosl);
}
