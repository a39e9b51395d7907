/* quad.c: ray/parallelogram hit (the seed's bounded plane). */
#include "geom.h"

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

/* Bounds are inclusive (0 <= alpha, beta <= 1), so a ray through an edge or
** corner hits; two quads sharing an edge leave no crack between them. */
int quad_hit(const quad_geom *g, const lc_ray *r, double tmin, double tmax, lc_hit *h)
{
    return quad_hit_inv(g, r, NULL, tmin, tmax, h);
}

/* The distance is the plane's (geom.h), so a quad lying on an infinite
** plane meets a ray at exactly the same t: ties go by id, not by rounding. */
int quad_hit_inv(const quad_geom *g, const lc_ray *r, const double *inv, double tmin,
                 double tmax, lc_hit *h)
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
