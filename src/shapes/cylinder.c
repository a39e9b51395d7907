/* cylinder.c: cylinders: x^2 + y^2 = 1 over 0 <= z <= 1 (closed by discs
** at z = 0 and 1 when capped), placed; its hit, bounds and light sampling. */
#include "cylinder.h"
#include "base/sample.h"
#include "shape.h"
#include "base/validate.h"

#define KIND_NAME "cylinder"

lc_status cylinder_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "base", err) || validate_edge(s->u, "axis", err) ||
        validate_length(s->radius, "radius", err))
        return LC_EARG;
    return placed_check_xf(s, KIND_NAME, err);
}

/* The unit cylinder scaled by the radius across, by the axis along. */
static lc_transform to_shape(const lc_shape *s)
{
    return placed_axial(s->p, s->u, s->radius, s->u);
}

enum { SIDE, BOTTOM, TOP };          /* placed_caps says 1 and 2 */

/* The side over (a, b): height a, angle 2 pi b. */
static void side(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                 lc_vec3 *tb)
{
    (void)g;
    double phi = 2 * PI * b, c = cos(phi), s = sin(phi);
    *p = v3(c, s, a);
    *ta = v3(0, 0, 1);
    *tb = v3(-2 * PI * s, 2 * PI * c, 0);
}

/* A cap at height z over (a, b): radius sqrt(a), angle 2 pi b. */
static void cap(double z, double a, double b, lc_vec3 *p, lc_vec3 *ta, lc_vec3 *tb)
{
    double rho = sqrt(a), phi = 2 * PI * b, c = cos(phi), s = sin(phi);
    double dr = rho > 0 ? 0.5 / rho : 0;
    *p = v3(rho * c, rho * s, z);
    *ta = v3(dr * c, dr * s, 0);
    *tb = v3(-2 * PI * rho * s, 2 * PI * rho * c, 0);
}

static void bottom(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                   lc_vec3 *tb)
{
    (void)g;
    cap(0, a, b, p, ta, tb);
}

void cylinder_prepare(const lc_shape *s, placed_geom *g)
{
    lc_transform t = to_shape(s);
    placed_make(s, &t, g, NULL);
}

double cylinder_area(const placed_geom *g)
{
    double a = placed_patch_area(g, side, 64);
    if (g->shape.caps)
        a += 2 * placed_patch_area(g, bottom, 8);
    return a;
}

/* The nearest of the side's roots and the caps' in (lo, hi); *part says
** which. The side's roots are those of |o + s d|_xy = 1 taken from the
** closest approach in the xy plane (no cancellation for thin cylinders or
** far rays), c / q and q / a (Press et al.). */
static double solve(const placed_geom *g, const placed_ray *pr, int *part)
{
    const ray *r = &pr->r;
    double best = 0;
    double a = r->d.x * r->d.x + r->d.y * r->d.y;
    if (a > 0) {
        double b = r->o.x * r->d.x + r->o.y * r->d.y;
        double vx = r->o.x - r->d.x * (b / a), vy = r->o.y - r->d.y * (b / a);
        double v = sqrt(vx * vx + vy * vy);
        double disc = (1 - v) * (1 + v);
        if (disc >= 0) {
            double q = -(b + copysign(sqrt(a * disc), b));
            double c = r->o.x * r->o.x + r->o.y * r->o.y - 1;
            double roots[2] = {q / a, q != 0 ? c / q : q / a};
            for (int k = 0; k < 2; k++) {
                double s = roots[k], z = r->o.z + s * r->d.z;
                if (s > pr->lo && s < pr->hi && z >= 0 && z <= 1 && (best == 0 || s < best)) {
                    best = s;
                    *part = SIDE;
                }
            }
        }
    }
    if (g->shape.caps && r->d.z != 0)
        best = placed_caps(r, pr, 1, 1, best, part);
    return best;
}

double cylinder_t(const placed_geom *g, const ray *r, double tmin, double tmax)
{
    placed_ray pr;
    int part;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr, &part);
    return s > 0 ? s / pr.scale : 0;
}

int cylinder_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    placed_ray pr;
    int part = SIDE;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr, &part);
    if (!(s > 0))
        return 0;
    lc_vec3 p = v3_madd(pr.r.o, pr.r.d, s), n;
    lc_vec3 perr = v3_mul(v3_add(v3_abs(pr.r.o), v3_abs(p)), vec_gamma(4));
    if (part == SIDE) {
        /* Back onto the side: the radial part made unit, exactly 1 apart
        ** from its own rounding. */
        double rho = sqrt(p.x * p.x + p.y * p.y);
        if (!(rho > 0))
            return 0;
        p.x /= rho;
        p.y /= rho;
        n = v3(p.x, p.y, 0);
        perr.x = vec_gamma(4) * fabs(p.x);
        perr.y = vec_gamma(4) * fabs(p.y);
    } else {
        p.z = part == TOP ? 1 : 0;
        perr.z = 0;
        n = v3(0, 0, part == TOP ? 1 : -1);
    }
    placed_finish(g, &pr, s, p, perr, n, h);
    return 1;
}

void cylinder_bounds(const placed_geom *g, float lo[3], float hi[3])
{
    placed_bounds_axial(g, 1, 1, 0, 1, lo, hi);
}

/* A part drawn by its canonical area (side 2 pi, caps pi each), then a
** point uniform over it; the world's density follows from the map. */
int cylinder_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                          light_sample *out)
{
    double ps = g->shape.caps ? 0.5 : 1;            /* 2 pi / (2 pi + 2 pi) */
    lc_vec3 q, ta, tb;
    if (u[0] < ps) {
        side(g, fmin(u[0] / ps, BELOW_ONE), u[1], &q, &ta, &tb);
        return placed_light_sample(g, cylinder_t, q, ta, tb, ps, p, S, out);
    }
    double w = fmin((u[0] - ps) / (1 - ps), BELOW_ONE);
    int top = w >= 0.5;
    cap(top ? 1 : 0, fmin(2 * (top ? w - 0.5 : w), BELOW_ONE), u[1], &q, &ta, &tb);
    return placed_light_sample(g, cylinder_t, q, ta, tb, (1 - ps) / 2, p, S, out);
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* u: the turn around the axis; v: the height from the base over the
** length on the side, the radius over the cap's on the caps. */
void cylinder_uv(const placed_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 c = placed_canonical(g, p);
    uv[0] = placed_turn(c.x, c.y);
    uv[1] = c.z;
    if (g->shape.caps) {
        double rho = hypot(c.x, c.y), cap = fmin(fabs(c.z), fabs(c.z - 1));
        double side = fabs(rho - 1);
        if (cap < side)
            uv[1] = rho;
    }
}
