/* sphere.c: ray/sphere hit with the rewritten discriminant. */
#include "geom.h"

void sphere_prepare(const lc_shape *s, sphere_geom *g)
{
    g->c = s->p;
    g->r = s->radius;
    g->r2 = s->radius * s->radius;
    g->extent = s->radius + fabs(s->p.x) + fabs(s->p.y) + fabs(s->p.z);
    if (!(g->r2 > 0) || !isfinite(g->r2))   /* 1e-300 or 1e300: beyond double */
        g->r2 = 0;
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
double sphere_t(const sphere_geom *s, const lc_ray *r, double tmin, double tmax)
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
double sphere_t(const sphere_geom *s, const lc_ray *r, double tmin, double tmax)
{
    if (s->r2 == 0)
        return 0;
    lc_vec3 f = v3_sub(r->o, s->c);
    double b = v3_dot(f, r->d);
    double c = v3_dot(f, f) - s->r2;
    if (c > 0 && b > 0)    /* outside and moving away: no square root, no division */
        return 0;
    lc_vec3 v = v3_madd(f, r->d, -b);
    double disc = s->r2 - v3_dot(v, v);
    if (!(disc >= 0))
        return 0;
    double q = -b - copysign(sqrt(disc), b);
    if (q == 0)            /* tangent at the origin itself: both roots are 0 */
        return 0;
    /* From outside toward the sphere (c > 0, q > 0) the near root c/q lies
    ** beyond tmax when c > tmax q: most spheres a BVH visits behind the
    ** nearest hit so far, or past a shadow ray's light, are refused without
    ** a division. The margin keeps exact ties for the division below. */
    if (c > 0 && q > 0 && c > tmax * q * (1 + lc_gamma(4)))
        return 0;
    double t0 = c / q, t1 = q;
    if (t0 > t1) {
        double tt = t0; t0 = t1; t1 = tt;
    }
    /* A root nearer than the rounding of o - c and of c itself could be the
    ** surface the ray starts on (a camera placed on the sphere, a ray
    ** spawned from it): refused, as pbrt-v4 refuses t below its bound. */
    double near = lc_gamma(6) * (s->extent + fabs(r->o.x) + fabs(r->o.y) + fabs(r->o.z));
    if (tmin < near)
        tmin = near;
    if (t0 > tmin && t0 < tmax)
        return t0;
    if (t1 > tmin && t1 < tmax)
        return t1;
    return 0;
}
#endif

int sphere_hit(const sphere_geom *s, const lc_ray *r, double tmin, double tmax, lc_hit *h)
{
    double t = sphere_t(s, r, tmin, tmax);
    if (!(t > 0))
        return 0;
    lc_vec3 f = v3_sub(r->o, s->c);
    /* Put the point back onto the sphere: what remains is bounded by
    ** gamma(5)|p_local| (pbrt-v4); adding the centre rounds once more. */
    lc_vec3 pl = v3_madd(f, r->d, t);
    double len = v3_len(pl);
    if (!(len > 0))
        return 0;
    lc_vec3 n = v3_mul(pl, 1.0 / len);
    pl = v3_mul(n, s->r);
    h->t = t;
    h->p = v3_add(s->c, pl);
    h->perr = v3_add(v3_mul(v3_abs(pl), lc_gamma(7)), v3_mul(v3_abs(h->p), lc_gamma(4)));
    h->n = n;
    return 1;
}
