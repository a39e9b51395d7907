/* sphere.c: spheres: checks, moving, bounds, the hit (rewritten discriminant)
** and sampling one as a light (by the cone it subtends). */
#include "accel/bvh.h"
#include "base/sample.h"
#include "shape.h"
#include "sphere.h"
#include "base/validate.h"

/* A sphere stays a sphere when M's columns are orthogonal and of one length
** (M = s R). Compared relative to the largest squared column length, so the
** test does not depend on scale; rotations built from rounded sines and
** composed a few dozen times are off by ~1e-15, while any shear or stretch
** a user means is far above 1e-9. */
#define UNIFORM_TOL 1e-9

lc_status sphere_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "center", err))
        return LC_EARG;
    return validate_length(s->radius, "radius", err);
}

void sphere_prepare(const lc_shape *s, sphere_geom *g)
{
    g->c = s->p;
    g->r = s->radius;
}

void sphere_describe(const sphere_geom *g, lc_shape *s)
{
    s->p = g->c;
    s->radius = g->r;
}

lc_status sphere_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err)
{
    double g[3][3], big = 0;
    for (int j = 0; j < 3; j++)
        for (int k = 0; k < 3; k++) {
            g[j][k] = t->m[0][j] * t->m[0][k] + t->m[1][j] * t->m[1][k] +
                      t->m[2][j] * t->m[2][k];
            if (j == k && g[j][j] > big)
                big = g[j][j];
        }
    double tol = UNIFORM_TOL * big;
    (void)err;
    *out = *s;
    if (fabs(g[0][1]) > tol || fabs(g[0][2]) > tol || fabs(g[1][2]) > tol ||
        fabs(g[0][0] - g[1][1]) > tol || fabs(g[0][0] - g[2][2]) > tol) {
        /* Stretched or sheared: the ellipsoid of radii r, placed by t. */
        out->kind = LC_ELLIPSOID;
        out->u = v3(s->radius, s->radius, s->radius);
        out->radius = 0;
        out->moved = 1;
        out->xf = *t;
        return LC_OK;
    }
    out->p = lc_transform_point(t, s->p);
    /* The mean square keeps exact scales exact: 2 I gives 2. */
    out->radius = s->radius * sqrt((g[0][0] + g[1][1] + g[2][2]) / 3);
    return LC_OK;
}

void sphere_scale(lc_shape *s, double k, lc_vec3 offset)
{
    s->p = v3(s->p.x * k + offset.x, s->p.y * k + offset.y, s->p.z * k + offset.z);
    s->radius *= k;
}

void sphere_bounds(const sphere_geom *g, float lo[3], float hi[3])
{
    bvh_bounds_empty(lo, hi);
    bvh_bounds_grow(lo, hi, v3(g->c.x - g->r, g->c.y - g->r, g->c.z - g->r));
    bvh_bounds_grow(lo, hi, v3(g->c.x + g->r, g->c.y + g->r, g->c.z + g->r));
}

int sphere_hit(const sphere_geom *s, const ray *r, double tmin, double tmax, hit *h)
{
    double t = sphere_t(s, r, tmin, tmax);
    return t > 0 && sphere_finish(s, r, t, h);
}

int sphere_finish(const sphere_geom *s, const ray *r, double t, hit *h)
{
    lc_vec3 f = v3_sub(r->o, s->c);
    /* Put the point back onto the sphere: what remains is bounded by
    ** gamma(5)|p_local| (pbrt-v4); adding the centre rounds once more. */
    lc_vec3 pl = v3_madd(f, r->d, t);
    double len = v3_len(pl);
    if (!(len > 0.5 * s->r)) {
        /* f + t d cancelled: a sphere far smaller than its distance (down to
        ** LC_MIN_LENGTH at 1e30). From the closest approach v instead, the
        ** point is v -+ sqrt(disc) d, with no cancellation (H12). */
        double b = v3_dot(f, r->d);
        lc_vec3 v = v3_madd(f, r->d, -b);
        double root = sqrt(fmax(0, s->r * s->r - v3_dot(v, v)));
        pl = v3_madd(v, r->d, t < -b ? -root : root);
        len = v3_len(pl);
        if (!(len > 0))
            return 0;
    }
    lc_vec3 n = v3_mul(pl, 1.0 / len);
    pl = v3_mul(n, s->r);
    h->t = t;
    h->p = v3_add(s->c, pl);
    h->perr = v3_add(v3_mul(v3_abs(pl), vec_gamma(7)), v3_mul(v3_abs(h->p), vec_gamma(4)));
    h->n = n;
    return 1;
}

/* ---- as a light ------------------------------------------------------------------ */

/* The seed's model: E / (pi L) of the whole sphere seen from distance d,
** pi L (r/d)^2 cos, exact. */
double sphere_light_centre(const sphere_geom *g, lc_vec3 l, double d)
{
    (void)l;
    return (g->r / d) * (g->r / d);
}

int sphere_light_begin(const sphere_geom *g, lc_vec3 p, lc_vec3 n, sphere_light *sl)
{
    sl->tc = v3_sub(g->c, p);
    double d2 = v3_dot(sl->tc, sl->tc), r2 = g->r * g->r;
    if (!(d2 > r2))                 /* on or inside the light */
        return 0;
    sl->dc = sqrt(d2);
    sl->axis = v3_mul(sl->tc, 1 / sl->dc);
    double sin2 = r2 / d2, cosmax = sqrt(1 - sin2);
    if (v3_dot(n, sl->axis) <= -sqrt(sin2))     /* wholly below the horizon */
        return 0;
    sl->omc = sin2 / (1 + cosmax);
    sl->solid = 2 * PI * sl->omc;
    return 1;
}

/* Uniform in the solid angle of the cone it subtends (pdf 1 / solid). */
int sphere_light_sample(const sphere_geom *g, const sphere_light *sl, lc_vec3 p,
                        const double u[2], uint32_t S, light_sample *out)
{
    (void)p;
    lc_vec3 l = sample_cone(sl->axis, sl->omc, u);
    out->l = l;
    out->k = sl->solid / (PI * S);
    /* Up to the near side: the root from the closest approach (no
    ** cancellation); a ray grazing the rim may miss it by rounding, and
    ** then goes as far as the centre's distance. */
    double b = v3_dot(l, sl->tc);
    lc_vec3 off = v3_madd(sl->tc, l, -b);
    double disc = g->r * g->r - v3_dot(off, off);
    out->dist = disc > 0 ? b - sqrt(disc) : sl->dc;
    return 1;
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* Longitude and latitude, y up: u = 0.5 faces +z (the default camera) and
** grows toward +x, v runs from 0 at the south pole to 1 at the north. */
void sphere_uv_of_direction(lc_vec3 d, double uv[2])
{
    uv[0] = 0.5 + atan2(d.x, d.z) / (2 * PI);
    uv[1] = 0.5 + asin(fmax(-1, fmin(1, d.y))) / PI;
}

void sphere_uv(const sphere_geom *g, lc_vec3 p, double uv[2])
{
    sphere_uv_of_direction(v3_norm(v3_sub(p, g->c)), uv);
}
