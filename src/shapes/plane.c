/* plane.c: infinite planes: checks, moving, the hit, and snapping points onto
** a plane (which quads share). */
#include "plane.h"
#include "base/validate.h"

lc_status plane_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "point", err) || validate_nonzero(s->u, "normal", err))
        return LC_EARG;
    return LC_OK;
}

static int axis_of(lc_vec3 n)
{
    if (n.y == 0 && n.z == 0) return 0;
    if (n.x == 0 && n.z == 0) return 1;
    if (n.x == 0 && n.y == 0) return 2;
    return -1;
}

void plane_prepare(const lc_shape *s, plane_geom *g)
{
    g->n = v3_norm(s->u);
    g->p = s->p;
    g->axis = axis_of(g->n);
    if (g->axis >= 0)      /* exact: the normal is +-1 on that axis */
        g->n = v3(g->axis == 0 ? copysign(1, s->u.x) : 0,
                  g->axis == 1 ? copysign(1, s->u.y) : 0,
                  g->axis == 2 ? copysign(1, s->u.z) : 0);
    /* After the normal is final: (0, 49, 0) normalises to 1 - 2^-53, and a
    ** k from that made rays leaving the plane y = 1 hit it again. */
    g->k = v3_dot(g->n, g->p);
    g->at = g->axis >= 0 ? v3_comp(g->p, g->axis) : 0;
}

void plane_describe(const plane_geom *g, lc_shape *s)
{
    s->p = g->p;
    s->u = g->n;
}

/* The point moves as a point, the normal by the inverse transpose. */
lc_status plane_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                          lc_error *err)
{
    (void)err;
    *out = *s;
    out->p = lc_transform_point(t, s->p);
    out->u = lc_transform_normal(t, s->u);
    return LC_OK;
}

void plane_scale(lc_shape *s, double k, lc_vec3 offset)
{
    s->p = v3(s->p.x * k + offset.x, s->p.y * k + offset.y, s->p.z * k + offset.z);
}

/* p = o + t d carries an error proportional to t, which near the horizon is
** huge; projecting back onto the plane leaves only the residual of n.p - k.
** On an axis-aligned plane the coordinate is set exactly and its error is 0. */
lc_vec3 plane_snap(lc_vec3 p, lc_vec3 n, double k, int axis, double axis_value,
                   lc_vec3 *perr)
{
    double m = v3_max_abs(p);
    if (axis >= 0) {
        if (axis == 0) p.x = axis_value;
        else if (axis == 1) p.y = axis_value;
        else p.z = axis_value;
        *perr = v3(axis == 0 ? 0 : vec_gamma(2) * fabs(p.x),
                   axis == 1 ? 0 : vec_gamma(2) * fabs(p.y),
                   axis == 2 ? 0 : vec_gamma(2) * fabs(p.z));
        return p;
    }
    double nn = v3_dot(n, n);
    p = v3_madd(p, n, -(v3_dot(n, p) - k) / nn);
    /* The residual of n.p - k is a few roundings of the largest term. */
    double e = vec_gamma(8) * (m + fabs(k) / sqrt(nn));
    *perr = v3_add(v3_mul(v3_abs(p), vec_gamma(2)), v3(e, e, e));
    return p;
}

int plane_hit(const plane_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    double t = plane_t(g, r, NULL, tmin, tmax);
    return t > 0 && plane_finish(g, r, t, h);
}

int plane_finish(const plane_geom *g, const ray *r, double t, hit *h)
{
    lc_vec3 raw = v3_madd(r->o, r->d, t);
    if (!isfinite(raw.x + raw.y + raw.z))   /* NaN in a component an axis plane skips */
        return 0;
    lc_vec3 perr;
    lc_vec3 p = plane_snap(raw, g->n, g->k, g->axis,
                           v3_comp(g->p, g->axis < 0 ? 0 : g->axis), &perr);
    h->t = t;
    h->p = p;
    h->perr = perr;
    h->n = g->n;
    return 1;
}


/* ---- texture coordinates ----------------------------------------------------------- */

/* Distances in the plane from its point, along axes that read upright to
** a camera facing it with y up: u horizontal (y x n), v = n x u; a floor
** or ceiling (n mostly along y) takes u along x instead. A floor reads
** u = x, v = -z from its point. */
void plane_uv(const plane_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 n = g->n, e1;
    if (fabs(n.y) >= fabs(n.x) && fabs(n.y) >= fabs(n.z))
        e1 = v3_norm(v3_madd(v3(1, 0, 0), n, -n.x));
    else
        e1 = v3_norm(v3_cross(v3(0, 1, 0), n));
    lc_vec3 e2 = v3_cross(n, e1), d = v3_sub(p, g->p);
    uv[0] = v3_dot(d, e1);
    uv[1] = v3_dot(d, e2);
}
