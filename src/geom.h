/* geom.h: rays, hit records and the prepared shapes the intersectors read. */
#ifndef LC_GEOM_H
#define LC_GEOM_H

#include <stdint.h>
#include "vec.h"

typedef struct {
    lc_vec3 o, d;      /* origin; unit direction */
} lc_ray;

typedef struct {
    double   t;        /* distance along the ray */
    lc_vec3  p;        /* hit point, on the surface within perr */
    lc_vec3  perr;     /* per-component bound of p's rounding error */
    lc_vec3  n;        /* unit geometric normal, outward for solids */
    lc_vec3  ns;       /* unit shading normal: n, or interpolated on meshes */
    double   bary[3];  /* triangles: barycentric coordinates of p */
    int      material;
    uint32_t shape;    /* the primitive's id (scene.h: PRIM_ID) */
    uint32_t instance; /* 0, or 1 + the index of the moved mesh hit: its
                       ** placements share their triangles' ids */
} lc_hit;

/* Per-ray constants of the watertight triangle test. */
typedef struct {
    int    kx, ky, kz;
    double sx, sy, sz;
} tri_shear;

/* Prepared shapes: what compile derives once so a hit test does no setup. */
typedef struct {
    lc_vec3 c;
    double  r;
    double  r2;        /* r*r, or 0 when that under- or overflows: never hit */
    double  extent;    /* r + |c.x| + |c.y| + |c.z|: the scale of its rounding */
} sphere_geom;

typedef struct {
    lc_vec3 q, u, v;   /* corner, edges */
    lc_vec3 n;         /* u x v, not normalised */
    lc_vec3 w;         /* n / (n.n): the dual basis for (alpha, beta) */
    lc_vec3 un;        /* unit normal */
    double  k;         /* n.q */
    int     axis;      /* 0..2 when n is along an axis (exact snapping), else -1 */
} quad_geom;

typedef struct {
    lc_vec3 q;         /* corner */
    lc_vec3 e[3];      /* edges u, v, w */
    lc_vec3 row[3];    /* rows of the inverse edge matrix: local = row . (x - q) */
    lc_vec3 un[3];     /* unit outward normal of the face where local coord i = 1 */
    double  lo[3], hi[3];  /* axis-aligned boxes: exact face coordinates */
    int     aligned;   /* edges along the axes: slabs in world space, exact snaps */
} box_geom;

typedef struct {
    lc_vec3 n;         /* unit normal */
    lc_vec3 p;         /* a point on it */
    double  k;         /* n.p */
    int     axis;      /* 0..2 when n is along an axis, else -1 */
} plane_geom;

/* Each fills *h and returns 1 for the nearest hit with tmin < t < tmax,
** else returns 0 and leaves *h untouched. */
int sphere_hit(const sphere_geom *s, const lc_ray *r, double tmin, double tmax, lc_hit *h);
int quad_hit(const quad_geom *q, const lc_ray *r, double tmin, double tmax, lc_hit *h);
int quad_hit_inv(const quad_geom *q, const lc_ray *r, const double *inv, double tmin,
                 double tmax, lc_hit *h);
int box_hit(const box_geom *b, const lc_ray *r, double tmin, double tmax, lc_hit *h);
int plane_hit(const plane_geom *p, const lc_ray *r, double tmin, double tmax, lc_hit *h);
/* v0, v1, v2 point at 3 doubles each; fills bary with the weights of p. */
int tri_hit(const double *v0, const double *v1, const double *v2, const lc_ray *r,
            const tri_shear *s, double tmin, double tmax, lc_hit *h, double bary[3]);
void tri_shear_init(lc_vec3 d, tri_shear *s);

/* The same tests reduced to the distance (0 for a miss): enough to find the
** nearest hit; only the winner is then finished by the *_hit function. */
double sphere_t(const sphere_geom *s, const lc_ray *r, double tmin, double tmax);
/* inv: the ray's reciprocal direction (1/d per axis), or NULL to compute it;
** the *_inv forms finish a hit found with the same reciprocals. */
int box_hit_inv(const box_geom *b, const lc_ray *r, const double *inv, double tmin,
                double tmax, lc_hit *h);
int plane_hit_inv(const plane_geom *p, const lc_ray *r, const double *inv, double tmin,
                  double tmax, lc_hit *h);
double box_t(const box_geom *b, const lc_ray *r, const double *inv, double tmin,
             double tmax);
static inline double plane_t(const plane_geom *g, const lc_ray *r, const double *inv,
                             double tmin, double tmax);

void sphere_prepare(const lc_shape *s, sphere_geom *g);
void quad_prepare(const lc_shape *s, quad_geom *g);
void box_prepare(const lc_shape *s, box_geom *g);
void plane_prepare(const lc_shape *s, plane_geom *g);

/* Shared by plane and quad: puts p back onto the plane n.x = k. */
lc_vec3 plane_snap(lc_vec3 p, lc_vec3 n, double k, int axis, double axis_value,
                   lc_vec3 *perr);

/* A point just off the surface on the side of w, provably not behind it
** (pbrt-v4's OffsetRayOrigin). */
lc_vec3 spawn_origin(const lc_hit *h, lc_vec3 w);

/* Distance along r to the plane through p with unit normal n (axis >= 0:
** n is +-1 on that axis), or 0 for no hit in (tmin, tmax). inv: the ray's
** reciprocals or NULL. Inline: every ray meets every infinite plane. */
static inline double plane_distance(lc_vec3 n, lc_vec3 p, int axis, const lc_ray *r,
                                    const double *inv, double tmin, double tmax)
{
    double t;
    if (axis >= 0) {
        /* Axis planes (walls, floors): one subtraction, exact when the
        ** origin is near the plane, so its side is never in doubt; then
        ** the ray's own reciprocal. A parallel ray gives inf or NaN. */
        double i = inv ? inv[axis] : 1.0 / v3_comp(r->d, axis);
        t = (v3_comp(p, axis) - v3_comp(r->o, axis)) * i;
    } else {
        double denom = v3_dot(n, r->d);
        if (denom == 0)    /* exactly parallel; no epsilon band near grazing */
            return 0;
        /* n.(p - o), not k - n.o: the difference comes first, so t keeps
        ** a few ulps of |p - o|, not of |o|. An origin on the plane within
        ** that rounding cannot tell its side: no hit (a camera on it). */
        lc_vec3 po = v3_sub(p, r->o);
        double num = v3_dot(n, po);
        double band = lc_gamma(4) * (fabs(n.x * po.x) + fabs(n.y * po.y) + fabs(n.z * po.z));
        if (!(fabs(num) > band))
            return 0;
        t = num / denom;
    }
    return t > tmin && t < tmax ? t : 0;   /* NaN and inf fail here */
}

static inline double plane_t(const plane_geom *g, const lc_ray *r, const double *inv,
                             double tmin, double tmax)
{
    return plane_distance(g->n, g->p, g->axis, r, inv, tmin, tmax);
}

#endif
