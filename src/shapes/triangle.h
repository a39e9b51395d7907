/* triangle.h: the watertight triangle test (Woop, Benthin and Wald 2013) in
** two halves: the distance and barycentric weights, inline, which every
** candidate face pays; and the point, its error bound and the normal,
** which only the nearest pays (triangle_finish, triangle.c). */
#ifndef LC_TRIANGLE_H
#define LC_TRIANGLE_H

#include "base/geom.h"

/* Per-ray constants of the watertight triangle test. */
typedef struct {
    int    kx, ky, kz;
    double sx, sy, sz;
} triangle_shear;

void triangle_shear_init(lc_vec3 d, triangle_shear *s);

#ifdef LC_NAIVE
/* Moller-Trumbore with a determinant epsilon, built only by `make NAIVE=1`
** for the benchmark: rays aimed at shared edges slip through it. */
static inline double triangle_t(const double *v0, const double *v1, const double *v2,
                                const ray *r, const triangle_shear *s, double tmin,
                                double tmax, double bary[3])
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
    bary[0] = 1 - u - v;
    bary[1] = u;
    bary[2] = v;
    return t;
}
#else
/* An edge function recomputed in extended precision when double rounding
** left it exactly zero, as the paper does for float: its sign then decides. */
static inline double triangle_edge(double ax, double ay, double bx, double by)
{
    double e = ax * by - ay * bx;
    if (e == 0)
        e = (double)((long double)ax * by - (long double)ay * bx);
    return e;
}

/* The distance to the face v0 v1 v2 (3 doubles each) in (tmin, tmax), and
** bary the weights of the point hit; 0 for a miss.
**
** The ray becomes the +z axis through the origin (translate, permute, shear);
** the triangle is then hit when the origin is inside its 2D projection. Two
** triangles sharing an edge compute that edge's function from the same
** sheared vertices, so one sees exactly the negation of the other: no ray
** slips between them. Zeros count as inside: edges and vertices are closed. */
static inline double triangle_t(const double *v0, const double *v1, const double *v2,
                                const ray *r, const triangle_shear *s, double tmin,
                                double tmax, double bary[3])
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
    double e0 = triangle_edge(x[1], y[1], x[2], y[2]);
    double e1 = triangle_edge(x[2], y[2], x[0], y[0]);
    double e2 = triangle_edge(x[0], y[0], x[1], y[1]);
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
    bary[0] = e0 * inv;
    bary[1] = e1 * inv;
    bary[2] = e2 * inv;
    return t;
}
#endif

/* The rest of the hit at distance t with weights bary, which triangle_t
** gave for this face and ray: h's t, p (the weighted vertices), perr, n
** and bary. 0 for a face whose normal underflows, which compiling skips
** (triangle_degenerate makes the same test), so the nearest face found is
** never refused here. */
int triangle_finish(const double *v0, const double *v1, const double *v2, const ray *r,
                    double t, const double bary[3], hit *h);

/* Both halves: triangle_t, then on a hit triangle_finish; bary is set. */
int triangle_hit(const double *v0, const double *v1, const double *v2, const ray *r,
                 const triangle_shear *s, double tmin, double tmax, hit *h, double bary[3]);

/* A face that can never be hit: zero area (or an area beyond double). */
int  triangle_degenerate(const double *a, const double *b, const double *c);
/* Bounds of a face: its vertices are exact doubles, rounded outward. */
void triangle_bounds(const double *a, const double *b, const double *c, float lo[3],
                float hi[3]);

#endif
