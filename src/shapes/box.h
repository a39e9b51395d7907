/* box.h: a parallelepiped (box.c): its prepared form and functions. */
#ifndef LC_BOX_H
#define LC_BOX_H

#include "base/geom.h"

/* A light sample (shape.h) is filled here, never read: the tag is enough. */
struct light_sample;

typedef struct {
    lc_vec3 q;         /* corner */
    lc_vec3 e[3];      /* edges u, v, w */
    lc_vec3 row[3];    /* rows of the inverse edge matrix: local = row . (x - q) */
    lc_vec3 un[3];     /* unit outward normal of the face where local coord i = 1 */
    double  lo[3], hi[3];  /* axis-aligned boxes: exact face coordinates */
    int     aligned;   /* edges along the axes: slabs in world space, exact snaps */
} box_geom;

/* The faces of a box light that face the shaded point. */
typedef struct {
    lc_vec3 face[3][4];    /* corner, edge, edge, outward normal (not unit) */
    double  area[3], total;
    int     n;
} box_light;

lc_status box_check(const lc_shape *s, lc_error *err);
void      box_prepare(const lc_shape *s, box_geom *g);
void      box_describe(const box_geom *g, lc_shape *s);
lc_status box_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                        lc_error *err);
void      box_scale(lc_shape *s, double k, lc_vec3 offset);
void      box_bounds(const box_geom *g, float lo[3], float hi[3]);
int       box_hit(const box_geom *g, const ray *r, double tmin, double tmax, hit *h);
int       box_hit_inv(const box_geom *g, const ray *r, const double *inv, double tmin,
                      double tmax, hit *h);
double    box_t(const box_geom *g, const ray *r, const double *inv, double tmin,
                double tmax);
void      box_uv(const box_geom *g, lc_vec3 p, double uv[2]);
double    box_light_centre(const box_geom *g, lc_vec3 l, double d);
int       box_light_begin(const box_geom *g, lc_vec3 p, box_light *bl);
int       box_light_sample(const box_geom *g, const box_light *bl, lc_vec3 p,
                           const double u[2], uint32_t S, struct light_sample *out);

#endif
