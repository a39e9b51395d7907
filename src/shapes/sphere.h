/* sphere.h: a sphere (sphere.c): its prepared form, its functions, and its
** distance test inline: every sphere a BVH leaf holds is tested through it,
** and B2's million spheres made the call a tenth of the trace. */
#ifndef LC_SPHERE_H
#define LC_SPHERE_H

#include "base/geom.h"

/* 32 bytes: r * r and the scale of its rounding are computed where they
** are used, not kept (B2 1M's spheres took 48 MB with them, 32 without).
** r lies in [LC_MIN_LENGTH, LC_MAX_COORD] (every shape is checked when
** added), so r * r is a normal double, never 0 or inf. */
typedef struct {
    lc_vec3 c;
    double  r;
} sphere_geom;

/* r + |c.x| + |c.y| + |c.z|: the scale of the sphere's rounding. */
static inline double sphere_extent(const sphere_geom *s)
{
    return s->r + fabs(s->c.x) + fabs(s->c.y) + fabs(s->c.z);
}

/* The naive b^2 - 4ac cancels when the sphere is small or far: b^2 and 4ac
** are both ~|f|^4 and differ by ~r^2. With v the ray's closest-approach
** offset from the centre, the discriminant is r^2 - |v|^2, whose terms are
** of the sphere's own size (Haines et al., RTG ch. 7; (r - |v|)(r + |v|)
** is no more accurate and costs a square root). The roots are taken as c/q
** and q (Press et al.), so neither cancels. */
#ifdef LC_NAIVE
/* The textbook quadratic, built only by `make NAIVE=1` so the benchmark can
** show what the robust version costs. It cancels for small or far spheres. */
static inline double sphere_t(const sphere_geom *s, const ray *r, double tmin,
                              double tmax)
{
    lc_vec3 f = v3_sub(r->o, s->c);
    double b = 2 * v3_dot(f, r->d), c = v3_dot(f, f) - s->r * s->r;
    double disc = b * b - 4 * c;
    if (!(disc >= 0))
        return 0;
    double t0 = (-b - sqrt(disc)) / 2, t1 = (-b + sqrt(disc)) / 2;
    if (t0 > tmin && t0 < tmax)
        return t0;
    if (t1 > tmin && t1 < tmax)
        return t1;
    return 0;
}
#else
static inline double sphere_t(const sphere_geom *s, const ray *r, double tmin,
                              double tmax)
{
    double r2 = s->r * s->r;
    lc_vec3 f = v3_sub(r->o, s->c);
    double b = v3_dot(f, r->d);
    double c = v3_dot(f, f) - r2;
    if (c > 0 && b > 0)    /* outside and moving away: no square root, no division */
        return 0;
    lc_vec3 v = v3_madd(f, r->d, -b);
    double disc = r2 - v3_dot(v, v);
    if (!(disc >= 0))
        return 0;
    double q = -b - copysign(sqrt(disc), b);
    if (q == 0)            /* tangent at the origin itself: both roots are 0 */
        return 0;
    /* From outside toward the sphere (c > 0, q > 0) the near root c/q lies
    ** beyond tmax when c > tmax q: most spheres a BVH visits behind the
    ** nearest hit so far, or past a shadow ray's light, are refused without
    ** a division. The margin keeps exact ties for the division below. */
    if (c > 0 && q > 0 && c > tmax * q * (1 + vec_gamma(4)))
        return 0;
    double t0 = c / q, t1 = q;
    if (t0 > t1) {
        double tt = t0; t0 = t1; t1 = tt;
    }
    /* A root nearer than the rounding of o - c and of c itself could be the
    ** surface the ray starts on (a camera placed on the sphere, a ray
    ** spawned from it): refused, as pbrt-v4 refuses t below its bound. */
    double near = vec_gamma(6) * (sphere_extent(s) + fabs(r->o.x) + fabs(r->o.y) +
                                  fabs(r->o.z));
    if (tmin < near)
        tmin = near;
    if (t0 > tmin && t0 < tmax)
        return t0;
    if (t1 > tmin && t1 < tmax)
        return t1;
    return 0;
}
#endif

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

/* What sampling a sphere light needs at one shaded point: the cone it subtends. */
typedef struct {
    lc_vec3 tc, axis;      /* centre - p, and its direction */
    double  dc;            /* |centre - p| */
    double  omc, solid;    /* 1 - cos of the cone's half-angle; its solid angle */
} sphere_light;

lc_status sphere_check(const lc_shape *s, lc_error *err);
void      sphere_prepare(const lc_shape *s, sphere_geom *g);
void      sphere_describe(const sphere_geom *g, lc_shape *s);
lc_status sphere_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err);
void      sphere_scale(lc_shape *s, double k, lc_vec3 offset);
void      sphere_bounds(const sphere_geom *g, float lo[3], float hi[3]);
/* Each fills *h and returns 1 for the nearest hit with tmin < t < tmax,
** else returns 0 and leaves *h untouched; the *_t forms return the distance
** only (0 for a miss): enough to find the nearest hit, finished later. */
/* sphere_t: above. */
int       sphere_hit(const sphere_geom *g, const ray *r, double tmin, double tmax,
                     hit *h);
/* The rest of a hit at distance t, which sphere_t gave for this ray: the
** nearest hit's, found again without the quadratic. */
int       sphere_finish(const sphere_geom *g, const ray *r, double t, hit *h);
/* Texture coordinates of a point p on the shape (each kind's convention:
** docs/manual.md, "Texture coordinates"). */
void      sphere_uv(const sphere_geom *g, lc_vec3 p, double uv[2]);
void      sphere_uv_of_direction(lc_vec3 unit, double uv[2]);
double    sphere_light_centre(const sphere_geom *g, lc_vec3 l, double d);
int       sphere_light_begin(const sphere_geom *g, lc_vec3 p, lc_vec3 n, sphere_light *sl);
int       sphere_light_sample(const sphere_geom *g, const sphere_light *sl, lc_vec3 p,
                              const double u[2], uint32_t S, struct light_sample *out);

#endif
