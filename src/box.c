/* box.c: ray/parallelepiped hit as one solid (slab test), not six quads. */
#include "geom.h"

void box_prepare(const lc_shape *s, box_geom *g)
{
    lc_vec3 e[3] = {s->u, s->v, s->w};
    g->q = s->p;
    g->e[0] = s->u;
    g->e[1] = s->v;
    g->e[2] = s->w;
    g->aligned = s->u.y == 0 && s->u.z == 0 && s->v.x == 0 && s->v.z == 0 &&
                 s->w.x == 0 && s->w.y == 0;
    double det = v3_dot(s->u, v3_cross(s->v, s->w));
    g->row[0] = v3_mul(v3_cross(s->v, s->w), 1.0 / det);
    g->row[1] = v3_mul(v3_cross(s->w, s->u), 1.0 / det);
    g->row[2] = v3_mul(v3_cross(s->u, s->v), 1.0 / det);
    for (int i = 0; i < 3; i++) {
        g->un[i] = v3_norm(g->row[i]);
        if (g->aligned) {
            double a = v3_comp(s->p, i), b = a + v3_comp(e[i], i);
            g->lo[i] = fmin(a, b);
            g->hi[i] = fmax(a, b);
            g->un[i] = v3(i == 0, i == 1, i == 2);
        } else {
            g->lo[i] = 0;
            g->hi[i] = 1;
        }
    }
}

static double comp(lc_vec3 v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; }

/* Slabs (Williams et al. 2005): the sign comes from the reciprocal, so -0
** picks the right slab end; NaN from 0*inf (origin on a slab plane of a
** parallel ray) is ignored by the comparisons. One interval for the whole
** solid means one normal per hit: no seam where two faces meet, and ties
** at edges go to the lowest axis. */
static double slabs(const box_geom *g, const lc_ray *r, const double *rinv, double tmin,
                    double tmax, int *axis_out, int *hi_out)
{
    lc_vec3 o = r->o, d = r->d;
    double inv[3];
    if (g->aligned && rinv) {            /* the ray's own reciprocals serve */
        inv[0] = rinv[0];
        inv[1] = rinv[1];
        inv[2] = rinv[2];
    } else {
        if (!g->aligned) {
        lc_vec3 oq = v3_sub(r->o, g->q);
        o = v3(v3_dot(g->row[0], oq), v3_dot(g->row[1], oq), v3_dot(g->row[2], oq));
            d = v3(v3_dot(g->row[0], r->d), v3_dot(g->row[1], r->d),
                   v3_dot(g->row[2], r->d));
        }
        inv[0] = 1.0 / d.x;
        inv[1] = 1.0 / d.y;
        inv[2] = 1.0 / d.z;
    }
    double t0 = -HUGE_VAL, t1 = HUGE_VAL;
    int a0 = -1, a1 = -1, hi0 = 0, hi1 = 0;
    for (int i = 0; i < 3; i++) {
        double tn = (g->lo[i] - comp(o, i)) * inv[i];
        double tf = (g->hi[i] - comp(o, i)) * inv[i];
        int neg = inv[i] < 0;
        if (neg) {
            double tt = tn; tn = tf; tf = tt;
        }
        if (tn > t0) { t0 = tn; a0 = i; hi0 = neg; }
        if (tf < t1) { t1 = tf; a1 = i; hi1 = !neg; }
    }
    if (!(t0 <= t1))
        return 0;
    if (t0 > tmin && t0 < tmax && a0 >= 0) {
        *axis_out = a0;
        *hi_out = hi0;
        return t0;
    }
    if (t1 > tmin && t1 < tmax && a1 >= 0) {
        *axis_out = a1;
        *hi_out = hi1;
        return t1;
    }
    return 0;
}

double box_t(const box_geom *g, const lc_ray *r, const double *inv, double tmin,
             double tmax)
{
    int axis, at_hi;
    return slabs(g, r, inv, tmin, tmax, &axis, &at_hi);
}

int box_hit(const box_geom *g, const lc_ray *r, double tmin, double tmax, lc_hit *h)
{
    return box_hit_inv(g, r, NULL, tmin, tmax, h);
}

int box_hit_inv(const box_geom *g, const lc_ray *r, const double *inv, double tmin,
                double tmax, lc_hit *h)
{
    int axis, at_hi;
    double t = slabs(g, r, inv, tmin, tmax, &axis, &at_hi);
    if (!(t > 0))
        return 0;
    lc_vec3 p = v3_madd(r->o, r->d, t);
    if (!isfinite(p.x + p.y + p.z))   /* a NaN ray slips past the NaN-blind slabs */
        return 0;
    lc_vec3 perr;
    if (g->aligned) {
        p = plane_snap(p, g->un[axis], 0, axis, at_hi ? g->hi[axis] : g->lo[axis], &perr);
    } else {
        /* The face is row.(x - q) = 0 or 1. Later rays see this box through
        ** the same local transform, whose rounding grows with |x| and |q|:
        ** the error bound covers it so spawned rays clear the face. */
        lc_vec3 n = g->row[axis];
        p = plane_snap(p, n, v3_dot(n, g->q) + (at_hi ? 1 : 0), -1, 0, &perr);
        double e = lc_gamma(16) * (v3_max_abs(p) + v3_max_abs(g->q));
        perr = v3_add(perr, v3(e, e, e));
    }
    h->t = t;
    h->p = p;
    h->perr = perr;
    h->n = at_hi ? g->un[axis] : v3_neg(g->un[axis]);
    return 1;
}
