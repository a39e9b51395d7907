/* triangle.c: mesh faces: the rest of a hit (triangle.h has the test),
** bounds, and which faces can never be hit. */
#include "accel/bvh.h"
#include "triangle.h"

int triangle_degenerate(const double *a, const double *b, const double *c)
{
    lc_vec3 p = v3(a[0], a[1], a[2]);
    lc_vec3 n = v3_cross(v3_sub(v3(b[0], b[1], b[2]), p), v3_sub(v3(c[0], c[1], c[2]), p));
    double l = v3_dot(n, n);
    return !(l > 0 && isfinite(l));
}

/* The corners' least and greatest coordinates, each rounded outward once:
** bvh_down and bvh_up never decrease, so this is the box of the three
** points rounded one by one, for a third of the roundings. */
void triangle_bounds(const double *a, const double *b, const double *c, float lo[3],
                float hi[3])
{
    for (int k = 0; k < 3; k++) {
        double mn = a[k], mx = a[k];
        if (b[k] < mn) mn = b[k];
        if (b[k] > mx) mx = b[k];
        if (c[k] < mn) mn = c[k];
        if (c[k] > mx) mx = c[k];
        lo[k] = bvh_down(mn);
        hi[k] = bvh_up(mx);
    }
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

int triangle_finish(const double *v0, const double *v1, const double *v2, const ray *r,
                    double t, const double bary[3], hit *h)
{
    lc_vec3 p0 = v3(v0[0], v0[1], v0[2]), p1 = v3(v1[0], v1[1], v1[2]);
    lc_vec3 p2 = v3(v2[0], v2[1], v2[2]);
    lc_vec3 n = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0));
#ifdef LC_NAIVE
    h->p = v3_madd(r->o, r->d, t);
    h->perr = v3(0, 0, 0);
    h->n = v3_norm(n);
#else
    (void)r;
    double nl = v3_len(n);
    if (!(nl > 0 && isfinite(nl)))  /* a sliver whose normal underflows */
        return 0;
    lc_vec3 a0 = v3_mul(p0, bary[0]), a1 = v3_mul(p1, bary[1]), a2 = v3_mul(p2, bary[2]);
    h->p = v3_add(v3_add(a0, a1), a2);
    h->perr = v3_mul(v3_add(v3_add(v3_abs(a0), v3_abs(a1)), v3_abs(a2)), vec_gamma(7));
    h->n = v3_mul(n, 1.0 / nl);
#endif
    h->t = t;
    for (int k = 0; k < 3; k++)
        h->bary[k] = bary[k];
    return 1;
}

int triangle_hit(const double *v0, const double *v1, const double *v2, const ray *r,
                 const triangle_shear *s, double tmin, double tmax, hit *h, double bary[3])
{
    double w[3];
    double t = triangle_t(v0, v1, v2, r, s, tmin, tmax, w);
    if (t == 0 || !triangle_finish(v0, v1, v2, r, t, w, h))
        return 0;
    for (int k = 0; k < 3; k++)
        bary[k] = w[k];
    return 1;
}
