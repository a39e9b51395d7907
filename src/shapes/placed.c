/* placed.c: what discs, cylinders, cones, tori and ellipsoids share: a
** canonical shape placed by an affine map, the ray taken into its space and
** the hit brought back, their checks, moves, bounds and area sampling. */
#include <string.h>
#include "accel/bvh.h"
#include "placed.h"
#include "base/sample.h"
#include "shape.h"
#include "base/validate.h"

lc_status placed_make(const lc_shape *s, const lc_transform *to_shape, placed_geom *g,
                      lc_error *err)
{
    memset(g, 0, sizeof *g);
    g->shape = *s;
    lc_transform t = s->moved ? lc_transform_compose(&s->xf, to_shape) : *to_shape;
    return affine_make(&t, &g->x, err);
}

lc_transform placed_axial(lc_vec3 origin, lc_vec3 axis, double r, lc_vec3 z)
{
    lc_vec3 a = v3_norm(axis), b1, b2;
    sample_frame(a, &b1, &b2);
    lc_transform t = {{{r * b1.x, r * b2.x, z.x, origin.x},
                       {r * b1.y, r * b2.y, z.y, origin.y},
                       {r * b1.z, r * b2.z, z.z, origin.z}}};
    return t;
}

/* Canonical shapes are of size 1 about the origin: below gamma(8) of the
** origin's magnitude plus that, a root cannot be told from the surface the
** ray starts on (the origin came through inv, whose rounding the affine's
** slack bounds; in canonical units it is a few ulps of |o| + 1). */
int placed_ray_init(const placed_geom *g, const ray *r, double tmin, double tmax,
                    placed_ray *pr)
{
    ray c = affine_ray(&g->x, r);
    double len = v3_len(c.d);
    if (!(len > 0) || !isfinite(len))
        return 0;
    pr->r.o = c.o;
    pr->r.d = v3_mul(c.d, 1 / len);
    pr->scale = len;
    pr->lo = tmin * len;
    pr->hi = tmax * len;
    pr->near = vec_gamma(16) * (v3_max_abs(c.o) + 1);
    if (pr->lo < pr->near)
        pr->lo = pr->near;
    return 1;
}

void placed_finish(const placed_geom *g, const placed_ray *pr, double s, lc_vec3 p,
                   lc_vec3 perr, lc_vec3 n, hit *h)
{
    h->t = s / pr->scale;
    h->p = affine_point(&g->x, p, perr, &h->perr);
    h->n = affine_normal(&g->x, n);
}

/* The world box of canonical points (rho cos a, rho sin a, z), rho in
** [rho0, rho1] over z in [z0, z1] (as rho grows linearly with z): along
** world axis i that is t_i + M_i2 z +- rho sqrt(M_i0^2 + M_i1^2), so the
** box is exact for every axial shape, and widened by the round trip. */
void placed_bounds_axial(const placed_geom *g, double rho0, double rho1, double z0,
                         double z1, float lo[3], float hi[3])
{
    const double (*m)[4] = g->x.xf.m;
    lc_vec3 a = v3(0, 0, 0), b = v3(0, 0, 0);
    double l[3], h[3];
    for (int i = 0; i < 3; i++) {
        double rad = sqrt(m[i][0] * m[i][0] + m[i][1] * m[i][1]);
        double e0 = m[i][3] + m[i][2] * z0, e1 = m[i][3] + m[i][2] * z1;
        l[i] = fmin(e0 - rho0 * rad, e1 - rho1 * rad);
        h[i] = fmax(e0 + rho0 * rad, e1 + rho1 * rad);
    }
    a = v3(l[0], l[1], l[2]);
    b = v3(h[0], h[1], h[2]);
    lc_vec3 big = v3(fmax(fabs(l[0]), fabs(h[0])), fmax(fabs(l[1]), fabs(h[1])),
                     fmax(fabs(l[2]), fabs(h[2])));
    /* Each term rounded a few times, and points as rays find them. */
    lc_vec3 e = v3_add(affine_slack(&g->x, big), v3_mul(big, vec_gamma(8)));
    bvh_bounds_empty(lo, hi);
    bvh_bounds_grow(lo, hi, v3_sub(a, e));
    bvh_bounds_grow(lo, hi, v3_add(b, e));
}

/* A moved shape must stay inside the coordinate range once placed: its
** centre through xf, plus its size through the largest row of M, within
** LC_MAX_COORD; its size through the cube root of |det M| (the mean scale)
** at least LC_MIN_LENGTH. */
lc_status placed_check_xf(const lc_shape *s, const char *kind, lc_error *err)
{
    if (!s->moved)
        return LC_OK;
    if (lc_transform_check(&s->xf, err))
        return LC_EARG;
    const double (*m)[4] = s->xf.m;
    double size = v3_max_abs(s->u) + s->radius + s->radius2, row = 0;
    for (int i = 0; i < 3; i++)
        row = fmax(row, fabs(m[i][0]) + fabs(m[i][1]) + fabs(m[i][2]));
    lc_vec3 c = lc_transform_point(&s->xf, s->p);
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (!(v3_max_abs(c) + row * size <= LC_MAX_COORD))
        return error_fail(err, LC_EARG, "transform", "the moved %s reaches past +-%g "
                          "(lancer's coordinate range)", kind, LC_MAX_COORD);
    if (!(cbrt(fabs(det)) * size >= LC_MIN_LENGTH))
        return error_fail(err, LC_EARG, "transform", "the moved %s is smaller than %g "
                          "(lancer's coordinate range)", kind, LC_MIN_LENGTH);
    return LC_OK;
}

/* Placed shapes keep their fields and take the map after their own. */
lc_status placed_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err)
{
    (void)err;
    *out = *s;
    out->xf = s->moved ? lc_transform_compose(t, &s->xf) : *t;
    out->moved = 1;
    return LC_OK;
}

/* Scaled about the origin and moved: the fields themselves when the shape
** is not placed further (u scaled when it is a length, not a direction),
** else its xf. */
void placed_scale(lc_shape *s, double k, lc_vec3 offset, int scales_u)
{
    if (s->moved) {
        lc_transform sc = lc_transform_scale(v3(k, k, k));
        lc_transform mv = lc_transform_translate(offset);
        sc = lc_transform_compose(&mv, &sc);
        s->xf = lc_transform_compose(&sc, &s->xf);
        return;
    }
    s->p = v3(s->p.x * k + offset.x, s->p.y * k + offset.y, s->p.z * k + offset.z);
    if (scales_u)
        s->u = v3_mul(s->u, k);
    s->radius *= k;
    s->radius2 *= k;
}

static lc_vec3 through(const placed_geom *g, lc_vec3 v)
{
    return lc_transform_vector(&g->x.xf, v);
}

double placed_patch_area(const placed_geom *g,
                         void (*patch)(const placed_geom *, double, double, lc_vec3 *,
                                       lc_vec3 *, lc_vec3 *),
                         int n)
{
    double sum = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            lc_vec3 p, ta, tb;
            patch(g, (i + 0.5) / n, (j + 0.5) / n, &p, &ta, &tb);
            sum += v3_len(v3_cross(through(g, ta), through(g, tb)));
        }
    return sum / ((double)n * n);
}

/* A point p of the canonical surface, sampled with a density whose inverse
** over the world is |M ta x M tb| / weight (ta, tb the derivatives of the
** point over the unit parameter square; weight the probability of the
** part it was drawn from): the solid angle it stands for is that times
** |n_l . l| / d^2. */
int placed_light_sample(const placed_geom *g, placed_t_fn visible, lc_vec3 p, lc_vec3 ta,
                        lc_vec3 tb, double weight, lc_vec3 from, uint32_t S,
                        light_sample *out)
{
    lc_vec3 q = lc_transform_point(&g->x.xf, p);
    lc_vec3 nl = v3_cross(through(g, ta), through(g, tb));
    double area = v3_len(nl) / weight;
    lc_vec3 tq = v3_sub(q, from);
    double d2 = v3_dot(tq, tq), dist = sqrt(d2);
    if (!(dist > 0) || !(area > 0))
        return 0;
    out->l = v3_mul(tq, 1 / dist);
    /* Shadow rays toward a light skip the light itself (its own rounding
    ** must not hide the point sampled on it): so the shape's own hiding of
    ** the point (its back, a torus's other side, an open cylinder's far
    ** wall) is decided here. The point is seen when the shape's first
    ** surface along the ray lies where the point is, within 1e-6 of the
    ** distance (a part that hides it lies farther off than that). */
    ray toward = {from, out->l};
    double first = visible(g, &toward, 0, HUGE_VAL);
    if (!(first > 0) || first < dist * (1 - 1e-6))
        return 0;
    out->k = area * fabs(v3_dot(nl, out->l)) / v3_len(nl) / (PI * d2 * S);
    out->dist = dist;
    return 1;
}

/* ---- texture coordinates ----------------------------------------------------------- */

lc_vec3 placed_canonical(const placed_geom *g, lc_vec3 p)
{
    return lc_transform_point(&g->x.inv, p);
}

double placed_turn(double x, double y)
{
    return 0.5 + atan2(y, x) / (2 * PI);
}
