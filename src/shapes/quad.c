/* quad.c: parallelograms (the seed's bounded planes): checks, moving, bounds,
** the hit, and sampling one as a light (by area). */
#include "accel/bvh.h"
#include "plane.h"
#include "quad.h"
#include "shape.h"
#include "base/validate.h"

lc_status quad_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "corner", err) || validate_edge(s->u, "u", err) ||
        validate_edge(s->v, "v", err) || validate_not_parallel(s->u, s->v, "u", "v", err))
        return LC_EARG;
    return LC_OK;
}

void quad_prepare(const lc_shape *s, quad_geom *g)
{
    g->q = s->p;
    g->u = s->u;
    g->v = s->v;
    g->n = v3_cross(s->u, s->v);
    g->w = v3_mul(g->n, 1.0 / v3_dot(g->n, g->n));
    g->un = v3_norm(g->n);
    g->k = v3_dot(g->n, g->q);
    g->axis = -1;
    if (g->n.y == 0 && g->n.z == 0) g->axis = 0;
    else if (g->n.x == 0 && g->n.z == 0) g->axis = 1;
    else if (g->n.x == 0 && g->n.y == 0) g->axis = 2;
}

void quad_describe(const quad_geom *g, lc_shape *s)
{
    s->p = g->q;
    s->u = g->u;
    s->v = g->v;
}

lc_status quad_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                         lc_error *err)
{
    (void)err;
    shape_move_edges(t, s, out);
    return LC_OK;
}

void quad_scale(lc_shape *s, double k, lc_vec3 offset)
{
    s->p = v3(s->p.x * k + offset.x, s->p.y * k + offset.y, s->p.z * k + offset.z);
    s->u = v3_mul(s->u, k);
    s->v = v3_mul(s->v, k);
}

void quad_bounds(const quad_geom *g, float lo[3], float hi[3])
{
    bvh_bounds_empty(lo, hi);
    bvh_bounds_grow(lo, hi, g->q);
    bvh_bounds_grow(lo, hi, v3_add(g->q, g->u));
    bvh_bounds_grow(lo, hi, v3_add(g->q, g->v));
    bvh_bounds_grow(lo, hi, v3_add(v3_add(g->q, g->u), g->v));
}

/* Bounds are inclusive (0 <= alpha, beta <= 1), so a ray through an edge or
** corner hits; two quads sharing an edge leave no crack between them. */
int quad_hit(const quad_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    return quad_hit_inv(g, r, NULL, tmin, tmax, h);
}

/* The distance is the plane's (geom.h), so a quad lying on an infinite
** plane meets a ray at exactly the same t: ties go by id, not by rounding. */
int quad_hit_inv(const quad_geom *g, const ray *r, const double *inv, double tmin,
                 double tmax, hit *h)
{
    double t = plane_distance(g->un, g->q, g->axis, r, inv, tmin, tmax);
    if (!(t > 0))
        return 0;
    lc_vec3 perr;
    lc_vec3 p = plane_snap(v3_madd(r->o, r->d, t), g->n, g->k, g->axis,
                           v3_comp(g->q, g->axis < 0 ? 0 : g->axis), &perr);
    lc_vec3 pq = v3_sub(p, g->q);
    double a = v3_dot(g->w, v3_cross(pq, g->v));
    double b = v3_dot(g->w, v3_cross(g->u, pq));
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1))
        return 0;
    h->t = t;
    h->p = p;
    h->perr = perr;
    h->n = g->un;
    return 1;
}

/* ---- as a light ------------------------------------------------------------------ */

/* The seed's model: the quad's projected area over d^2, over pi. */
double quad_light_centre(const quad_geom *g, lc_vec3 l, double d)
{
    return fabs(v3_dot(g->n, l)) / (PI * d * d);
}

int quad_light_begin(const quad_geom *g, lc_vec3 p, quad_light *ql)
{
    if (v3_dot(v3_sub(p, g->q), g->n) == 0)        /* in the light's plane */
        return 0;
    ql->area = v3_len(g->n);
    return 1;
}

/* Uniform over its area (pdf 1 / A): the solid angle a sample stands for
** is |n_l . l| A / d^2. */
int quad_light_sample(const quad_geom *g, const quad_light *ql, lc_vec3 p,
                      const double u[2], uint32_t S, light_sample *out)
{
    lc_vec3 q = v3_madd(v3_madd(g->q, g->u, u[0]), g->v, u[1]);
    lc_vec3 tq = v3_sub(q, p);
    double d2 = v3_dot(tq, tq), dist = sqrt(d2);
    if (!(dist > 0))
        return 0;
    out->l = v3_mul(tq, 1 / dist);
    out->k = ql->area * fabs(v3_dot(g->n, out->l)) / ql->area / (PI * d2 * S);
    out->dist = dist;
    return 1;
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* (alpha, beta): the corner is (0, 0), corner + u is (1, 0). */
void quad_uv(const quad_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 pq = v3_sub(p, g->q);
    uv[0] = v3_dot(g->w, v3_cross(pq, g->v));
    uv[1] = v3_dot(g->w, v3_cross(g->u, pq));
}
