/* box.c: parallelepipeds: checks, moving, bounds, the hit as one solid (slab
** test, not six quads), and sampling one as a light (by area of the faces
** that face the point). */
#include "box.h"
#include "accel/bvh.h"
#include "plane.h"
#include "base/sample.h"
#include "shape.h"
#include "base/validate.h"

lc_status box_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "corner", err) || validate_edge(s->u, "u", err) ||
        validate_edge(s->v, "v", err) || validate_edge(s->w, "w", err) ||
        validate_not_parallel(s->u, s->v, "u", "v", err) ||
        validate_not_parallel(s->v, s->w, "v", "w", err) ||
        validate_not_parallel(s->u, s->w, "u", "w", err))
        return LC_EARG;
    lc_vec3 nu = v3_norm(s->u), nv = v3_norm(s->v), nw = v3_norm(s->w);
    if (!(fabs(v3_dot(v3_cross(nu, nv), nw)) > PARALLEL_SIN))
        return error_fail(err, LC_EARG, "w", "'u', 'v' and 'w' must not be coplanar");
    return LC_OK;
}

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

void box_describe(const box_geom *g, lc_shape *s)
{
    s->p = g->q;
    s->u = g->e[0];
    s->v = g->e[1];
    s->w = g->e[2];
}

lc_status box_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                        lc_error *err)
{
    (void)err;
    shape_move_edges(t, s, out);
    return LC_OK;
}

void box_scale(lc_shape *s, double k, lc_vec3 offset)
{
    s->p = v3(s->p.x * k + offset.x, s->p.y * k + offset.y, s->p.z * k + offset.z);
    s->u = v3_mul(s->u, k);
    s->v = v3_mul(s->v, k);
    s->w = v3_mul(s->w, k);
}

void box_bounds(const box_geom *g, float lo[3], float hi[3])
{
    bvh_bounds_empty(lo, hi);
    for (int corner = 0; corner < 8; corner++) {
        lc_vec3 p = g->q;
        for (int e = 0; e < 3; e++)
            if (corner & (1 << e))
                p = v3_add(p, g->e[e]);
        bvh_bounds_grow(lo, hi, p);
    }
}

static double comp(lc_vec3 v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; }

/* Slabs (Williams et al. 2005): the sign comes from the reciprocal, so -0
** picks the right slab end; NaN from 0*inf (origin on a slab plane of a
** parallel ray) is ignored by the comparisons. One interval for the whole
** solid means one normal per hit: no seam where two faces meet, and ties
** at edges go to the lowest axis. */
static double slabs(const box_geom *g, const ray *r, const double *rinv, double tmin,
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

double box_t(const box_geom *g, const ray *r, const double *inv, double tmin,
             double tmax)
{
    int axis, at_hi;
    return slabs(g, r, inv, tmin, tmax, &axis, &at_hi);
}

int box_hit(const box_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    return box_hit_inv(g, r, NULL, tmin, tmax, h);
}

int box_hit_inv(const box_geom *g, const ray *r, const double *inv, double tmin,
                double tmax, hit *h)
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
        double e = vec_gamma(16) * (v3_max_abs(p) + v3_max_abs(g->q));
        perr = v3_add(perr, v3(e, e, e));
    }
    h->t = t;
    h->p = p;
    h->perr = perr;
    h->n = at_hi ? g->un[axis] : v3_neg(g->un[axis]);
    return 1;
}

/* ---- as a light ------------------------------------------------------------------ */

static lc_vec3 box_centre(const box_geom *g)
{
    return v3_add(g->q, v3_mul(v3_add(v3_add(g->e[0], g->e[1]), g->e[2]), 0.5));
}

/* The face of edge pair (a + 1, a + 2), as a vector of its area: v x w,
** w x u, u x v. */
static lc_vec3 face_area(const box_geom *g, int a)
{
    return v3_cross(g->e[(a + 1) % 3], g->e[(a + 2) % 3]);
}

/* The seed's model: the box's projected area (three faces' worth, of which
** one side each is seen) over d^2, over pi. */
double box_light_centre(const box_geom *g, lc_vec3 l, double d)
{
    double a = fabs(v3_dot(face_area(g, 0), l));
    a += fabs(v3_dot(face_area(g, 1), l)) + fabs(v3_dot(face_area(g, 2), l));
    return a / (PI * d * d);
}

/* The faces that face p; none when p is inside (it lights nothing then). */
int box_light_begin(const box_geom *g, lc_vec3 p, box_light *bl)
{
    lc_vec3 c = box_centre(g);
    bl->total = 0;
    bl->n = 0;
    for (int a = 0; a < 3; a++) {
        lc_vec3 ea = g->e[a], nrm = face_area(g, a);
        if (v3_dot(nrm, ea) < 0)
            nrm = v3_neg(nrm);
        double side = v3_dot(v3_sub(p, c), nrm), half = 0.5 * v3_dot(ea, nrm);
        lc_vec3 *f = bl->face[bl->n];
        if (side > half) {                              /* beyond the + face */
            f[0] = v3_madd(g->q, ea, 1);
        } else if (side < -half) {
            f[0] = g->q;
            nrm = v3_neg(nrm);
        } else {
            continue;
        }
        f[1] = g->e[(a + 1) % 3];
        f[2] = g->e[(a + 2) % 3];
        f[3] = nrm;
        bl->area[bl->n] = v3_len(nrm);
        bl->total += bl->area[bl->n++];
    }
    return bl->n > 0;
}

/* Uniform over the total area of the faces seen: u[0] picks the face (and
** is stretched back to [0, 1) inside it). */
int box_light_sample(const box_geom *g, const box_light *bl, lc_vec3 p,
                     const double u[2], uint32_t S, light_sample *out)
{
    (void)g;
    double pick = u[0] * bl->total;
    int f = 0;
    while (f < bl->n - 1 && pick >= bl->area[f])
        pick -= bl->area[f++];
    double s = fmin(pick / bl->area[f], BELOW_ONE);
    const lc_vec3 *face = bl->face[f];
    lc_vec3 q = v3_madd(v3_madd(face[0], face[1], s), face[2], u[1]);
    lc_vec3 tq = v3_sub(q, p);
    double d2 = v3_dot(tq, tq), dist = sqrt(d2);
    if (!(dist > 0))
        return 0;
    out->l = v3_mul(tq, 1 / dist);
    out->k = bl->total * fabs(v3_dot(face[3], out->l)) / v3_len(face[3]) / (PI * d2 * S);
    out->dist = dist;
    return 1;
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* On the face across edge a, the box's own coordinates along the other two
** edges in turn (a + 1, a + 2), each 0..1. */
void box_uv(const box_geom *g, lc_vec3 p, double uv[2])
{
    lc_vec3 pq = v3_sub(p, g->q);
    double c[3], off = HUGE_VAL;
    int face = 0;
    for (int a = 0; a < 3; a++) {
        c[a] = v3_dot(g->row[a], pq);
        double d = fmin(fabs(c[a]), fabs(c[a] - 1));   /* how far from its faces */
        if (d < off) {
            off = d;
            face = a;
        }
    }
    uv[0] = c[(face + 1) % 3];
    uv[1] = c[(face + 2) % 3];
}
