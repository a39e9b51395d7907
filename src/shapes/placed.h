/* placed.h: what the shapes placed by an affine map share (placed.c). */
#ifndef LC_PLACED_H
#define LC_PLACED_H

#include "base/affine.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

/* Discs, cylinders, cones, tori and ellipsoids are canonical shapes (a unit
** disc, cylinder, cone, torus, sphere) placed by an affine map: the ray is
** taken into canonical space, solved there, and the hit taken back. */
typedef struct {
    affine   x;        /* canonical space to the world */
    lc_shape shape;    /* as given: what lists, moves and scales */
    double   k0, k1;   /* the kind's canonical parameters */
    double   area;     /* world surface area (the seed's centre model); emitters
                       ** only (shape_prepare_emitter), else 0 */
} placed_geom;

/* A world ray in canonical space, its direction made unit: canonical
** distances are `scale` times the world's. */
typedef struct {
    ray    r;
    double scale;
    double lo, hi;     /* the world's (tmin, tmax), canonical */
    double near;       /* a root nearer than this may be the surface the ray left */
} placed_ray;

/* to_shape: canonical space to the shape as its fields say (the kind's own
** frame); the shape's xf, when moved, follows it. */
lc_status placed_make(const lc_shape *s, const lc_transform *to_shape, placed_geom *g,
                      lc_error *err);
int       placed_ray_init(const placed_geom *g, const ray *r, double tmin, double tmax,
                          placed_ray *pr);
/* The canonical hit at distance s, point p (within perr) with normal n, in
** the world. */
void      placed_finish(const placed_geom *g, const placed_ray *pr, double s, lc_vec3 p,
                        lc_vec3 perr, lc_vec3 n, hit *h);
/* Bounds: canonical points (x, y) of radius rho at heights z0..z1 along
** canonical z, for axial shapes; a whole canonical box otherwise. */
void      placed_bounds_axial(const placed_geom *g, double rho0, double rho1, double z0,
                              double z1, float lo[3], float hi[3]);
/* An axial kind's to_shape: canonical x and y scaled by r across a frame
** around the axis (made unit), canonical z to z, the origin to origin. */
lc_transform placed_axial(lc_vec3 origin, lc_vec3 axis, double r, lc_vec3 z);
/* The nearer of best (0: none) and where canonical ray r meets the caps of
** an axial kind, z = 0 of radius r0 and z = 1 of radius r1 (0: no cap),
** inside pr's span; *part becomes 1 (bottom) or 2 (top) when one is. */
static inline double placed_caps(const ray *r, const placed_ray *pr, double r0, double r1,
                                 double best, int *part)
{
    for (int c = 0; c < 2; c++) {
        double rad = c ? r1 : r0;
        double s = (c - r->o.z) / r->d.z;
        if (rad == 0 || !(s > pr->lo && s < pr->hi) || (best != 0 && !(s < best)))
            continue;
        double x = r->o.x + s * r->d.x, y = r->o.y + s * r->d.y;
        if (x * x + y * y <= rad * rad) {
            best = s;
            *part = c ? 2 : 1;
        }
    }
    return best;
}
/* The shared checks: a moved shape's xf, an axis, a positive length. */
lc_status placed_check_xf(const lc_shape *s, const char *kind, lc_error *err);
lc_status placed_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err);
void      placed_scale(lc_shape *s, double k, lc_vec3 offset, int scales_u);
/* A world point in canonical space; the turn 0..1 of (x, y) about the
** origin, 0.5 along +x. */
lc_vec3   placed_canonical(const placed_geom *g, lc_vec3 p);
double    placed_turn(double x, double y);
/* World area of a canonical parametric patch: sum of |M ta x M tb| da db. */
double    placed_patch_area(const placed_geom *g,
                            void (*patch)(const placed_geom *, double, double, lc_vec3 *,
                                          lc_vec3 *, lc_vec3 *),
                            int n);

/* One sample of a placed light: a canonical point p with tangents ta, tb
** (their cross product's length the canonical area element for the
** sample's share of the parameter square), turned into a light sample, 0
** when the shape itself hides it from `from` (`visible`: the kind's own
** distance test). */
typedef double (*placed_t_fn)(const placed_geom *g, const ray *r, double tmin, double tmax);
int       placed_light_sample(const placed_geom *g, placed_t_fn visible, lc_vec3 p,
                              lc_vec3 ta, lc_vec3 tb, double weight, lc_vec3 from,
                              uint32_t S, struct light_sample *out);

#endif
