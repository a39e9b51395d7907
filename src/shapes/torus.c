/* torus.c: tori: (|p|^2 + 1 - r^2)^2 = 4 (x^2 + y^2) around the z axis, major
** radius 1, minor r < 1, placed; the quartic's roots isolated robustly, its
** hit, bounds and light sampling. */
#include "base/sample.h"
#include "shape.h"
#include "torus.h"
#include "base/validate.h"

#define KIND_NAME "torus"

lc_status torus_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "center", err) || validate_nonzero(s->u, "axis", err) ||
        validate_length(s->radius, "major", err) || validate_length(s->radius2, "minor", err))
        return LC_EARG;
    if (!(s->radius2 < s->radius))
        return error_fail(err, LC_EARG, "minor", "must be less than major (%g), got %g",
                          s->radius, s->radius2);
    return placed_check_xf(s, KIND_NAME, err);
}

/* The canonical torus scaled by the major radius, its axis the shape's. */
static lc_transform to_shape(const lc_shape *s)
{
    return placed_axial(s->p, s->u, s->radius, v3_mul(v3_norm(s->u), s->radius));
}

/* Angle 2 pi a around the axis, 2 pi b around the tube. */
static void patch(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                  lc_vec3 *tb)
{
    double r = g->k0, th = 2 * PI * a, ph = 2 * PI * b;
    double ct = cos(th), st = sin(th), cp = cos(ph), sp = sin(ph), w = 1 + r * cp;
    *p = v3(w * ct, w * st, r * sp);
    *ta = v3(-2 * PI * w * st, 2 * PI * w * ct, 0);
    *tb = v3(-2 * PI * r * sp * ct, -2 * PI * r * sp * st, 2 * PI * r * cp);
}

void torus_prepare(const lc_shape *s, placed_geom *g)
{
    lc_transform t = to_shape(s);
    placed_make(s, &t, g, NULL);
    g->k0 = s->radius2 / s->radius;
}

double torus_area(const placed_geom *g)
{
    return placed_patch_area(g, patch, 64);
}

/* ---- the quartic ------------------------------------------------------------------ */

/* Along the ray o + s d (d unit), shifted to start where it enters the
** bounding sphere, f(s) = (|p|^2 + 1 - r^2)^2 - 4 (x^2 + y^2) is a monic
** quartic with coefficients of the torus's own size. Its roots are isolated
** without any closed form: the roots of f'' (a quadratic) split the span
** into pieces where f' is monotonic; a sign change of f' in a piece brackets
** a critical point of f; between critical points f is monotonic, and each
** sign change brackets one root. Every bracket is narrowed by Newton steps
** that stay inside it, bisection when one would leave: the error is bounded
** by the bracket, in long double. */
typedef struct { long double c[5]; } quartic;     /* c[k]: coefficient of s^k */

static long double eval(const quartic *q, long double s)
{
    return (((s + q->c[3]) * s + q->c[2]) * s + q->c[1]) * s + q->c[0];
}

static long double eval_d1(const quartic *q, long double s)
{
    return ((4 * s + 3 * q->c[3]) * s + 2 * q->c[2]) * s + q->c[1];
}

static long double eval_d2(const quartic *q, long double s)
{
    return (12 * s + 6 * q->c[3]) * s + 2 * q->c[2];
}

/* The root of fn in [a, b], where fn(a) and fn(b) differ in sign (or one is
** 0), narrowed to the last ulp of long double. */
static long double bracket_root(const quartic *q, long double (*fn)(const quartic *,
                                long double), long double (*dfn)(const quartic *,
                                long double), long double a, long double b)
{
    long double fa = fn(q, a), fb = fn(q, b);
    if (fa == 0)
        return a;
    if (fb == 0)
        return b;
    long double x = 0.5L * (a + b);
    for (int i = 0; i < 200; i++) {
        long double fx = fn(q, x);
        if (fx == 0)
            return x;
        if ((fx < 0) == (fa < 0))
            a = x, fa = fx;
        else
            b = x;
        long double d = dfn(q, x), nx = d != 0 ? x - fx / d : a;
        if (!(nx > a && nx < b))
            nx = 0.5L * (a + b);                 /* Newton left the bracket */
        if (nx == x || b - a <= 0)
            break;
        long double mid = 0.5L * (a + b);
        if (mid == a || mid == b)
            break;
        x = nx;
    }
    return x;
}

/* Points of [lo, hi] between which fn is monotonic: lo, the roots of dfn
** inside, hi. Returns their number. */
static int split(const quartic *q, long double (*dfn)(const quartic *, long double),
                 long double (*ddfn)(const quartic *, long double), const long double *cuts,
                 int ncuts, long double lo, long double hi, long double out[5])
{
    int n = 0;
    out[n++] = lo;
    long double prev = lo;
    for (int k = 0; k <= ncuts; k++) {
        long double next = k < ncuts ? cuts[k] : hi;
        if (!(next > prev))
            continue;
        long double a = dfn(q, prev), b = dfn(q, next);
        if ((a < 0) != (b < 0) || a == 0 || b == 0) {
            long double x = bracket_root(q, dfn, ddfn, prev, next);
            if (x > out[n - 1] && x < hi)
                out[n++] = x;
        }
        prev = next;
    }
    out[n++] = hi;
    return n;
}

int torus_roots(double minor, const ray *r, double lo, double hi, double roots[4])
{
    /* The bounding sphere of radius 1 + r, from the closest approach. */
    double B = 1 + minor, b = v3_dot(r->o, r->d);
    lc_vec3 v = v3_madd(r->o, r->d, -b);
    double vv = v3_len(v);
    double disc = (B - vv) * (B + vv);
    if (!(disc >= 0))
        return 0;
    double root = sqrt(disc), s_in = -b - root, s_out = -b + root;
    double a0 = fmax(lo, s_in), a1 = fmin(hi, s_out);
    if (!(a0 < a1))
        return 0;
    double s0 = s_in;                          /* the shift: |o + s0 d| = 1 + r */
    lc_vec3 o = v3_madd(r->o, r->d, s0);
    long double dx = r->d.x, dy = r->d.y, dz = r->d.z;
    long double ox = o.x, oy = o.y, oz = o.z;
    long double a = ox * dx + oy * dy + oz * dz;
    long double g = ox * ox + oy * oy + oz * oz + 1 - (long double)minor * minor;
    long double e2 = dx * dx + dy * dy, e1 = ox * dx + oy * dy, e0 = ox * ox + oy * oy;
    quartic q = {{g * g - 4 * e0, 4 * a * g - 8 * e1, 4 * a * a + 2 * g - 4 * e2, 4 * a, 1}};
    long double l = (long double)a0 - s0, h = (long double)a1 - s0;
    /* f'' = 12 s^2 + 6 c3 s + 2 c2: its roots, ascending. */
    long double cuts2[2];
    int n2 = 0;
    long double A = 12, Bq = 6 * q.c[3], C = 2 * q.c[2], D = Bq * Bq - 4 * A * C;
    if (D >= 0) {
        long double qq = -0.5L * (Bq + copysignl(sqrtl(D), Bq));
        long double x1 = qq / A, x2 = qq != 0 ? C / qq : x1;
        if (x1 > x2) { long double t = x1; x1 = x2; x2 = t; }
        if (x1 > l && x1 < h) cuts2[n2++] = x1;
        if (x2 > l && x2 < h && x2 != x1) cuts2[n2++] = x2;
    }
    long double pts1[5];
    int n1 = split(&q, eval_d1, eval_d2, cuts2, n2, l, h, pts1);
    /* pts1: lo, the critical points of f, hi: f is monotonic between them. */
    int n = 0;
    for (int k = 0; k + 1 < n1 && n < 4; k++) {
        long double fa = eval(&q, pts1[k]), fb = eval(&q, pts1[k + 1]);
        if ((fa < 0) != (fb < 0) || fb == 0) {
            long double x = bracket_root(&q, eval, eval_d1, pts1[k], pts1[k + 1]);
            double s = (double)(x + s0);
            if (s > lo && s < hi && (n == 0 || s > roots[n - 1]))
                roots[n++] = s;
        }
    }
    return n;
}

static double solve(const placed_geom *g, const placed_ray *pr)
{
    double roots[4];
    int n = torus_roots(g->k0, &pr->r, pr->lo, pr->hi, roots);
    return n > 0 ? roots[0] : 0;
}

double torus_t(const placed_geom *g, const ray *r, double tmin, double tmax)
{
    placed_ray pr;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr);
    return s > 0 ? s / pr.scale : 0;
}

int torus_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    placed_ray pr;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = solve(g, &pr);
    return s > 0 && torus_root_hit(g, &pr, s, h);
}

int torus_all_roots(const placed_geom *g, const ray *r, double tmin, placed_ray *pr,
                    double roots[4])
{
    if (!placed_ray_init(g, r, tmin, HUGE_VAL, pr))
        return 0;
    return torus_roots(g->k0, &pr->r, pr->lo, pr->hi, roots);
}

int torus_root_hit(const placed_geom *g, const placed_ray *pr, double s, hit *h)
{
    /* Back onto the tube: c the nearest point of the core circle, then the
    ** point at distance r from it; the normal is that direction. */
    lc_vec3 p = v3_madd(pr->r.o, pr->r.d, s);
    double rho = sqrt(p.x * p.x + p.y * p.y);
    lc_vec3 c = rho > 0 ? v3(p.x / rho, p.y / rho, 0) : v3(1, 0, 0);
    lc_vec3 n = v3_sub(p, c);
    double len = v3_len(n);
    if (!(len > 0))
        return 0;
    n = v3_mul(n, 1 / len);
    p = v3_madd(c, n, g->k0);
    lc_vec3 perr = v3_mul(v3_add(v3_abs(p), v3(1, 1, 1)), vec_gamma(32));
    placed_finish(g, pr, s, p, perr, n, h);
    return 1;
}

/* Within the cylinder of radius 1 + r and height 2 r around the core. */
void torus_bounds(const placed_geom *g, float lo[3], float hi[3])
{
    double b = 1 + g->k0;
    placed_bounds_axial(g, b, b, -g->k0, g->k0, lo, hi);
}

int torus_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                       light_sample *out)
{
    lc_vec3 q, ta, tb;
    patch(g, u[0], u[1], &q, &ta, &tb);
    return placed_light_sample(g, torus_t, q, ta, tb, 1, p, S, out);
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* u: the turn around the axis; v: the turn around the tube, 0.5 on the
** outer equator. */
void torus_uv(const placed_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 c = placed_canonical(g, p);
    uv[0] = placed_turn(c.x, c.y);
    uv[1] = placed_turn(hypot(c.x, c.y) - 1, c.z);
}
