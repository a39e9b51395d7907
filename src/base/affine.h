/* affine.h: things placed by an affine map (moved meshes, the shapes that
** are intersected in their own space): rays into that space, points and
** normals back out, with a bound on what the round trip rounds. */
#ifndef LC_AFFINE_H
#define LC_AFFINE_H

#include "geom.h"

/* What a hit needs to go from object space to the world and back, derived
** once when the thing is added. */
typedef struct {
    lc_transform xf;       /* object to world */
    lc_transform inv;      /* world to object: rays go through this */
    double  nrm[3][3];     /* normals: the inverse transpose (up to a positive factor) */
    double  slack[3][3];   /* world error of a point x from the round trip through */
    lc_vec3 slack0;        /* xf and inv: slack |x| + slack0, per component */
} affine;

lc_status affine_make(const lc_transform *t, affine *a, lc_error *err);
/* The world error bound of a point whose coordinates are at most |x|. */
lc_vec3   affine_slack(const affine *a, lc_vec3 absx);
/* A world ray in object space: d is not unit, so t keeps the world's. */
ray       affine_ray(const affine *a, const ray *r);
/* An object-space normal in the world: unit, or as the matrix gives it. */
lc_vec3   affine_normal(const affine *a, lc_vec3 n);
lc_vec3   affine_normal_raw(const affine *a, lc_vec3 n);
/* A point of object space in the world, and the bound of its error given
** its own object-space error perr. */
lc_vec3   affine_point(const affine *a, lc_vec3 p, lc_vec3 perr, lc_vec3 *world_err);

#endif
