/* ellipsoid.c: ellipsoids (and spheres under any affine map): the unit
** sphere, placed; its hit, bounds and sampling as a light. */
#include "accel/bvh.h"
#include "ellipsoid.h"
#include "shape.h"
#include "base/validate.h"

#define KIND_NAME "ellipsoid"

lc_status ellipsoid_check(const lc_shape *s, lc_error *err)
{
    if (validate_vec(s->p, "center", err) || validate_length(s->u.x, "radii", err) ||
        validate_length(s->u.y, "radii", err) || validate_length(s->u.z, "radii", err))
        return LC_EARG;
    return placed_check_xf(s, KIND_NAME, err);
}

/* The unit sphere scaled by the radii along the axes, at the centre. */
static lc_transform to_shape(const lc_shape *s)
{
    lc_transform t = {{{s->u.x, 0, 0, s->p.x}, {0, s->u.y, 0, s->p.y},
                       {0, 0, s->u.z, s->p.z}}};
    return t;
}

/* (cos phi sin theta, sin phi sin theta, cos theta) over (a, b) in [0, 1]^2,
** a = (1 - cos theta) / 2, b = phi / 2 pi: uniform over the unit sphere. */
static void patch(const placed_geom *g, double a, double b, lc_vec3 *p, lc_vec3 *ta,
                  lc_vec3 *tb)
{
    (void)g;
    double z = 1 - 2 * a, r = sqrt(fmax(0, 1 - z * z)), phi = 2 * PI * b;
    double c = cos(phi), s = sin(phi);
    *p = v3(r * c, r * s, z);
    /* d/da: z' = -2, r' = 2 z / r; d/db: 2 pi (-y, x, 0). Their cross
    ** product has length 4 pi: the unit sphere's area, evenly. */
    double dr = r > 0 ? 2 * z / r : 0;
    *ta = v3(dr * c, dr * s, -2);
    *tb = v3(-2 * PI * r * s, 2 * PI * r * c, 0);
}

void ellipsoid_prepare(const lc_shape *s, placed_geom *g)
{
    lc_transform t = to_shape(s);
    placed_make(s, &t, g, NULL);
}

double ellipsoid_area(const placed_geom *g)
{
    return placed_patch_area(g, patch, 64);
}

static const sphere_geom unit = {{0, 0, 0}, 1};

double ellipsoid_t(const placed_geom *g, const ray *r, double tmin, double tmax)
{
    placed_ray pr;
    if (!placed_ray_init(g, r, tmin, tmax, &pr))
        return 0;
    double s = sphere_t(&unit, &pr.r, pr.lo, pr.hi);
    return s > 0 ? s / pr.scale : 0;
}

int ellipsoid_hit(const placed_geom *g, const ray *r, double tmin, double tmax, hit *h)
{
    placed_ray pr;
    hit c;
    if (!placed_ray_init(g, r, tmin, tmax, &pr) || !sphere_hit(&unit, &pr.r, pr.lo, pr.hi, &c))
        return 0;
    placed_finish(g, &pr, c.t, c.p, c.perr, c.n, h);
    return 1;
}

/* Exact: along world axis i the unit sphere reaches t_i +- |row i of M|. */
void ellipsoid_bounds(const placed_geom *g, float lo[3], float hi[3])
{
    const double (*m)[4] = g->x.xf.m;
    double l[3], h[3];
    for (int i = 0; i < 3; i++) {
        double e = sqrt(m[i][0] * m[i][0] + m[i][1] * m[i][1] + m[i][2] * m[i][2]);
        l[i] = m[i][3] - e;
        h[i] = m[i][3] + e;
    }
    lc_vec3 big = v3(fmax(fabs(l[0]), fabs(h[0])), fmax(fabs(l[1]), fabs(h[1])),
                     fmax(fabs(l[2]), fabs(h[2])));
    lc_vec3 e = v3_add(affine_slack(&g->x, big), v3_mul(big, vec_gamma(8)));
    bvh_bounds_empty(lo, hi);
    bvh_bounds_grow(lo, hi, v3_sub(v3(l[0], l[1], l[2]), e));
    bvh_bounds_grow(lo, hi, v3_add(v3(h[0], h[1], h[2]), e));
}

int ellipsoid_light_sample(const placed_geom *g, lc_vec3 p, const double u[2], uint32_t S,
                           light_sample *out)
{
    lc_vec3 q, ta, tb;
    patch(g, u[0], u[1], &q, &ta, &tb);
    return placed_light_sample(g, ellipsoid_t, q, ta, tb, 1, p, S, out);
}

/* ---- texture coordinates ----------------------------------------------------------- */

/* The sphere's longitude and latitude, on the unit sphere it is placed from. */
void ellipsoid_uv(const placed_geom *g, lc_vec3 p, double uv[2])
{
    sphere_uv_of_direction(v3_norm(placed_canonical(g, p)), uv);
}
