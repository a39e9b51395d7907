/* disc.c: discs (rings, with an inner radius): the unit disc in z = 0,
** placed; its hit, bounds and sampling as a light. */
#include "disc.h"
#include "shape.h"
#include "base/validate.h"

#define KIND_NAME "disc"

lc_status disc_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "center", err) || validate_nonzero(s->u, "normal", err) ||
        validate_length(s->radius, "radius", err))
        return LC_EARG;
    if (!isfinite(s->radius2) || s->radius2 < 0)
        return error_fail(err, LC_EARG, "inner_radius", "must be finite and >= 0, got %g",
                          s->radius2);
    if (!(s->radius2 < s->radius))
        return error_fail(err, LC_EARG, "inner_radius", "must be less than the radius "
                          "(%g), got %g", s->radius, s->radius2);
    return placed_check_xf(s, KIND_NAME, err);
}

/* The unit disc scaled by the radius, its normal along the shape's. */
static lc_transform to_shape(const lc_shape *s)
{
    return placed_axial(s->p, s->u, s->radius, v3_mul(v3_norm(s->u), s->radius));
}

/* Radius sqrt(k0^2 + a (1 - k0^2)) at angle 2 pi b: uniform over the ring. */
static void patch(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                  lc_vec3 *tb)
{
    double k2 = g->k0 * g->k0, rho = sqrt(k2 + a * (1 - k2)), phi = 2 * PI * b;
    double c = cos(phi), s = sin(phi);
    *p = v3(rho * c, rho * s, 0);
    double dr = rho > 0 ? (1 - k2) / (2 * rho) : 0;
    *ta = v3(dr * c, dr * s, 0);
    *tb = v3(-2 * PI * rho * s, 2 * PI * rho * c, 0);
}

void disc_prepare(const lc_shape *s, placed_geom *g)
{
    lc_transform t = to_shape(s);
    placed_make(s, &t, g, NULL);
    g->k0 = s->radius2 / s->radius;
}

double disc_area(const placed_geom *g)
{
    return placed_patch_area(g, patch, 8);        /* planar: exact at any n */
}

/* The plane z = 0 (exact for an origin on it: no hit), then the ring. */
static double solve(const placed_geom *g, const placed_ray *pr)
{
    const ray *r = &pr->r;
    if (r->d.z == 0)
        return 0;
    double s = -r->o.z / r->d.z;
    if (!(s > pr->lo && s < pr->hi))
        return 0;
    double x = r->o.x + s * r->d.x, y = r->o.y + s * r->d.y, rho2 = x * x + y * y;
    return rho2 <= 1 && rho2 >= g->k0 * g->k0 ? s : 0;
}

double disc_t(const placed_geom *g, const ray *r, double tmin, double tmax)
{
    placed_ray pr;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr);
    return s > 0 ? s / pr.scale : 0;
}

int disc_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    placed_ray pr;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr);
    if (!(s > 0))
        return 0;
    lc_vec3 p = v3(pr.r.o.x + s * pr.r.d.x, pr.r.o.y + s * pr.r.d.y, 0);   /* on z = 0 */
    lc_vec3 perr = v3(vec_gamma(3) * (fabs(pr.r.o.x) + fabs(p.x)),
                      vec_gamma(3) * (fabs(pr.r.o.y) + fabs(p.y)), 0);
    placed_finish(g, &pr, s, p, perr, v3(0, 0, 1), h);
    return 1;
}

void disc_bounds(const placed_geom *g, float lo[3], float hi[3])
{
    placed_bounds_axial(g, 1, 1, 0, 0, lo, hi);
}

int disc_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                      light_sample *out)
{
    lc_vec3 q, ta, tb;
    patch(g, u[0], u[1], &q, &ta, &tb);
    return placed_light_sample(g, disc_t, q, ta, tb, 1, p, S, out);
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* u: the turn around the centre, v: the radius over the outer radius. */
void disc_uv(const placed_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 c = placed_canonical(g, p);
    uv[0] = placed_turn(c.x, c.y);
    uv[1] = hypot(c.x, c.y);
}
