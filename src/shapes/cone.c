/* cone.c: cones, truncated or not: x^2 + y^2 = r(z)^2 with r linear from k0
** at z = 0 to k1 at z = 1 (the larger 1), closed by discs when capped,
** placed; its hit, bounds and light sampling. */
#include "cone.h"
#include "base/sample.h"
#include "shape.h"
#include "base/validate.h"

#define KIND_NAME "cone"

lc_status cone_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "base", err) || validate_edge(s->u, "axis", err))
        return LC_EARG;
    const char *names[2] = {"base_radius", "top_radius"};
    double r[2] = {s->radius, s->radius2};
    for (int i = 0; i < 2; i++) {
        if (!isfinite(r[i]) || r[i] < 0)
            return error_fail(err, LC_EARG, names[i], "must be finite and >= 0, got %g",
                              r[i]);
        if (r[i] > LC_MAX_COORD)
            return error_fail(err, LC_EARG, names[i], "must be at most %g (lancer's "
                              "coordinate range), got %g", LC_MAX_COORD, r[i]);
    }
    double big = fmax(r[0], r[1]);
    if (validate_length(big, r[0] >= r[1] ? names[0] : names[1], err))
        return LC_EARG;
    return placed_check_xf(s, KIND_NAME, err);
}

/* The canonical cone (larger radius 1) scaled by the larger radius across,
** by the axis along. */
static lc_transform to_shape(const lc_shape *s)
{
    return placed_axial(s->p, s->u, fmax(s->radius, s->radius2), s->u);
}

enum { SIDE, BOTTOM, TOP };          /* placed_caps says 1 and 2 */

static double radius_at(const placed_geom *g, double z) { return g->k0 + (g->k1 - g->k0) * z; }

/* The side over (a, b): height a, angle 2 pi b. */
static void side(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                 lc_vec3 *tb)
{
    double phi = 2 * PI * b, c = cos(phi), s = sin(phi), rho = radius_at(g, a);
    double k = g->k1 - g->k0;
    *p = v3(rho * c, rho * s, a);
    *ta = v3(k * c, k * s, 1);
    *tb = v3(-2 * PI * rho * s, 2 * PI * rho * c, 0);
}

static void cap(double z, double radius, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                lc_vec3 *tb)
{
    double rho = radius * sqrt(a), phi = 2 * PI * b, c = cos(phi), s = sin(phi);
    double dr = a > 0 ? radius * 0.5 / sqrt(a) : 0;
    *p = v3(rho * c, rho * s, z);
    *ta = v3(dr * c, dr * s, 0);
    *tb = v3(-2 * PI * rho * s, 2 * PI * rho * c, 0);
}

static void bottom(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                   lc_vec3 *tb)
{
    cap(0, g->k0, a, b, p, ta, tb);
}

static void top(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                lc_vec3 *tb)
{
    cap(1, g->k1, a, b, p, ta, tb);
}

void cone_prepare(const lc_shape *s, placed_geom *g)
{
    lc_transform t = to_shape(s);
    placed_make(s, &t, g, NULL);
    double big = fmax(s->radius, s->radius2);
    g->k0 = s->radius / big;
    g->k1 = s->radius2 / big;
}

double cone_area(const placed_geom *g)
{
    double a = placed_patch_area(g, side, 64);
    if (g->shape.caps)
        a += placed_patch_area(g, bottom, 8) + placed_patch_area(g, top, 8);
    return a;
}

/* The side: x^2 + y^2 - r(z)^2 = 0 along the ray, A s^2 + 2 B s + C = 0,
** roots by Press's pair c / q and q / a; each kept where 0 <= z <= 1 (the
** other nappe lies outside). The caps: discs of radius k0 and k1. */
static double solve(const placed_geom *g, const placed_ray *pr, int *part)
{
    const ray *r = &pr->r;
    double k = g->k1 - g->k0, rz = g->k0 + k * r->o.z;
    double A = r->d.x * r->d.x + r->d.y * r->d.y - k * k * r->d.z * r->d.z;
    double B = r->o.x * r->d.x + r->o.y * r->d.y - k * r->d.z * rz;
    double C = r->o.x * r->o.x + r->o.y * r->o.y - rz * rz;
    double best = 0, roots[2];
    int n = 0;
    if (A != 0) {
        double disc = B * B - A * C;
        if (disc >= 0) {
            double q = -(B + copysign(sqrt(disc), B));
            roots[n++] = q / A;
            if (q != 0)
                roots[n++] = C / q;
        }
    } else if (B != 0) {
        roots[n++] = -C / (2 * B);              /* parallel to the slope: one root */
    }
    for (int i = 0; i < n; i++) {
        double s = roots[i], z = r->o.z + s * r->d.z;
        if (s > pr->lo && s < pr->hi && z >= 0 && z <= 1 && (best == 0 || s < best)) {
            best = s;
            *part = SIDE;
        }
    }
    if (g->shape.caps && r->d.z != 0)
        best = placed_caps(r, pr, g->k0, g->k1, best, part);
    return best;
}

double cone_t(const placed_geom *g, const ray *r, double tmin, double tmax)
{
    placed_ray pr;
    int part;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr, &part);
    return s > 0 ? s / pr.scale : 0;
}

int cone_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h)
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
        /* Back onto the side at that height; the normal is the gradient of
        ** x^2 + y^2 - r(z)^2, (x, y, -k r) over 2. */
        double rho = sqrt(p.x * p.x + p.y * p.y), want = radius_at(g, p.z);
        if (rho > 0 && want > 0) {
            p.x *= want / rho;
            p.y *= want / rho;
        }
        double k = g->k1 - g->k0;
        n = v3_norm(v3(p.x, p.y, -k * want));
        if (!(want > 0))                         /* the apex: along the axis */
            n = v3(0, 0, k > 0 ? -1 : 1);
    } else {
        p.z = part == TOP ? 1 : 0;
        perr.z = 0;
        n = v3(0, 0, part == TOP ? 1 : -1);
    }
    placed_finish(g, &pr, s, p, perr, n, h);
    return 1;
}

void cone_bounds(const placed_geom *g, float lo[3], float hi[3])
{
    placed_bounds_axial(g, g->k0, g->k1, 0, 1, lo, hi);
}

/* A part drawn by its canonical area, then a point uniform in its
** parameters; the Jacobian makes the world's density. */
int cone_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                      light_sample *out)
{
    double k = g->k1 - g->k0, slant = sqrt(1 + k * k);
    double as = PI * (g->k0 + g->k1) * slant;            /* the side's canonical area */
    double ab = g->shape.caps ? PI * g->k0 * g->k0 : 0, at = g->shape.caps ? PI * g->k1 *
                g->k1 : 0;
    double total = as + ab + at, pick = u[0] * total;
    lc_vec3 q, ta, tb;
    if (pick < as) {
        side(g, fmin(pick / as, BELOW_ONE), u[1], &q, &ta, &tb);
        return placed_light_sample(g, cone_t, q, ta, tb, as / total, p, S, out);
    }
    if (pick < as + ab) {
        cap(0, g->k0, fmin((pick - as) / ab, BELOW_ONE), u[1], &q, &ta, &tb);
        return placed_light_sample(g, cone_t, q, ta, tb, ab / total, p, S, out);
    }
    cap(1, g->k1, fmin((pick - as - ab) / at, BELOW_ONE), u[1], &q, &ta, &tb);
    return placed_light_sample(g, cone_t, q, ta, tb, at / total, p, S, out);
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* u: the turn around the axis; v: the height from the base over the
** length on the side, the radius over the cap's on the caps. */
void cone_uv(const placed_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 c = placed_canonical(g, p);
    uv[0] = placed_turn(c.x, c.y);
    uv[1] = c.z;
    if (g->shape.caps) {
        double rho = hypot(c.x, c.y), cap = fmin(fabs(c.z), fabs(c.z - 1));
        double side = fabs(rho - (g->k0 + (g->k1 - g->k0) * c.z));
        if (cap < side) {
            double r = c.z > 0.5 ? g->k1 : g->k0;
            uv[1] = r > 0 ? rho / r : 0;
        }
    }
}
