/* triangle.c: mesh faces: the watertight hit (Woop, Benthin and Wald 2013),
** bounds, and which faces can never be hit. */
#include "bvh.h"
#include "shape.h"

int triangle_degenerate(const double *a, const double *b, const double *c)
{
    lc_vec3 p = v3(a[0], a[1], a[2]);
    lc_vec3 n = v3_cross(v3_sub(v3(b[0], b[1], b[2]), p), v3_sub(v3(c[0], c[1], c[2]), p));
    double l = v3_dot(n, n);
    return !(l > 0 && isfinite(l));
}

void triangle_bounds(const double *a, const double *b, const double *c, float lo[3],
                float hi[3])
{
    bvh_bounds_empty(lo, hi);
    bvh_bounds_exact(lo, hi, a);
    bvh_bounds_exact(lo, hi, b);
    bvh_bounds_exact(lo, hi, c);
}

void triangle_shear_init(lc_vec3 d, triangle_shear *s)
{
    double a[3] = {fabs(d.x), fabs(d.y), fabs(d.z)};
    int kz = a[0] > a[1] ? (a[0] > a[2] ? 0 : 2) : (a[1] > a[2] ? 1 : 2);
    s->kz = kz;
    s->kx = (kz + 1) % 3;
    s->ky = (kz + 2) % 3;
    double dz = v3_comp(d, kz);
    s->sx = -v3_comp(d, s->kx) / dz;
    s->sy = -v3_comp(d, s->ky) / dz;
    s->sz = 1.0 / dz;
}

#ifdef LC_NAIVE
/* Moller-Trumbore with a determinant epsilon, built only by `make NAIVE=1`
** for the benchmark: rays aimed at shared edges slip through it. */
int triangle_hit(const double *v0, const double *v1, const double *v2, const ray *r,
            const triangle_shear *s, double tmin, double tmax, hit *h, double bary[3])
{
    (void)s;
    lc_vec3 p0 = v3(v0[0], v0[1], v0[2]), p1 = v3(v1[0], v1[1], v1[2]);
    lc_vec3 p2 = v3(v2[0], v2[1], v2[2]);
    lc_vec3 e1 = v3_sub(p1, p0), e2 = v3_sub(p2, p0);
    lc_vec3 pv = v3_cross(r->d, e2);
    double det = v3_dot(e1, pv);
    if (fabs(det) < 1e-12)
        return 0;
    double inv = 1 / det;
    lc_vec3 tv = v3_sub(r->o, p0);
    double u = v3_dot(tv, pv) * inv;
    if (u < 0 || u > 1)
        return 0;
    lc_vec3 qv = v3_cross(tv, e1);
    double v = v3_dot(r->d, qv) * inv;
    if (v < 0 || u + v > 1)
        return 0;
    double t = v3_dot(e2, qv) * inv;
    if (!(t > tmin && t < tmax))
        return 0;
    lc_vec3 n = v3_cross(e1, e2);
    h->t = t;
    h->p = v3_madd(r->o, r->d, t);
    h->perr = v3(0, 0, 0);
    h->n = v3_norm(n);
    bary[0] = 1 - u - v;
    bary[1] = u;
    bary[2] = v;
    return 1;
}
#else
/* An edge function recomputed in extended precision when double rounding
** left it exactly zero, as the paper does for float: its sign then decides. */
static double edge(double ax, double ay, double bx, double by)
{
    double e = ax * by - ay * bx;
    if (e == 0)
        e = (double)((long double)ax * by - (long double)ay * bx);
    return e;
}

/* The ray becomes the +z axis through the origin (translate, permute, shear);
** the triangle is then hit when the origin is inside its 2D projection. Two
** triangles sharing an edge compute that edge's function from the same
** sheared vertices, so one sees exactly the negation of the other: no ray
** slips between them. Zeros count as inside: edges and vertices are closed. */
int triangle_hit(const double *v0, const double *v1, const double *v2, const ray *r,
            const triangle_shear *s, double tmin, double tmax, hit *h, double bary[3])
{
    const double *v[3] = {v0, v1, v2};
    double x[3], y[3], z[3];
    double o[3] = {r->o.x, r->o.y, r->o.z};
    for (int i = 0; i < 3; i++) {
        double px = v[i][s->kx] - o[s->kx];
        double py = v[i][s->ky] - o[s->ky];
        double pz = v[i][s->kz] - o[s->kz];
        x[i] = px + s->sx * pz;
        y[i] = py + s->sy * pz;
        z[i] = pz;
    }
    double e0 = edge(x[1], y[1], x[2], y[2]);
    double e1 = edge(x[2], y[2], x[0], y[0]);
    double e2 = edge(x[0], y[0], x[1], y[1]);
    if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0))
        return 0;
    double det = e0 + e1 + e2;
    if (det == 0)                   /* edge-on, or a degenerate triangle */
        return 0;
    /* The shear's error (dx, dy below) is of the z it read, before the
    ** scaling: an instance's object-space ray is not unit (1e-14 long under
    ** a scale of 1e14), and the scaled z once made the bound refuse every
    ** hit on a mesh placed at scale 1e14 and up. */
    double mzr = max2(fabs(z[0]), max2(fabs(z[1]), fabs(z[2])));
    for (int i = 0; i < 3; i++)
        z[i] *= s->sz;
    double ts = e0 * z[0] + e1 * z[1] + e2 * z[2];
    /* Compare before dividing, sign-aware (the paper's trick). */
    if (det < 0 && (ts >= tmin * det || ts < tmax * det))
        return 0;
    if (det > 0 && (ts <= tmin * det || ts > tmax * det))
        return 0;
    double inv = 1.0 / det;
    double b0 = e0 * inv, b1 = e1 * inv, b2 = e2 * inv;
    double t = ts * inv;
    /* pbrt-v4's conservative bound on t's rounding error: a hit closer than
    ** it could be the surface the ray starts from, so it is refused. */
    double mz = max2(fabs(z[0]), max2(fabs(z[1]), fabs(z[2])));
    double mx = max2(fabs(x[0]), max2(fabs(x[1]), fabs(x[2])));
    double my = max2(fabs(y[0]), max2(fabs(y[1]), fabs(y[2])));
    double dz = vec_gamma(3) * mz;
    double dx = vec_gamma(5) * (mx + mzr), dy = vec_gamma(5) * (my + mzr);
    double de = 2 * (vec_gamma(2) * mx * my + dy * mx + dx * my);
    double me = max2(fabs(e0), max2(fabs(e1), fabs(e2)));
    double dt = 3 * (vec_gamma(3) * me * mz + de * mz + dz * me) * fabs(inv);
    if (!(t > dt))
        return 0;
    lc_vec3 p0 = v3(v0[0], v0[1], v0[2]), p1 = v3(v1[0], v1[1], v1[2]);
    lc_vec3 p2 = v3(v2[0], v2[1], v2[2]);
    lc_vec3 a0 = v3_mul(p0, b0), a1 = v3_mul(p1, b1), a2 = v3_mul(p2, b2);
    lc_vec3 n = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0));
    double nl = v3_len(n);
    if (!(nl > 0 && isfinite(nl)))  /* a sliver whose normal underflows */
        return 0;
    h->t = t;
    h->p = v3_add(v3_add(a0, a1), a2);
    h->perr = v3_mul(v3_add(v3_add(v3_abs(a0), v3_abs(a1)), v3_abs(a2)), vec_gamma(7));
    h->n = v3_mul(n, 1.0 / nl);
    bary[0] = b0;
    bary[1] = b1;
    bary[2] = b2;
    return 1;
}
#endif
