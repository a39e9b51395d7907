/* triangle4.h: the watertight triangle test on up to four faces at once,
** against one tmax (triangle4.c). */
#ifndef LC_TRIANGLE4_H
#define LC_TRIANGLE4_H

#include "triangle.h"

/* Faces v[l][0..2] (their corners, 3 doubles each) for lanes l < n. */
typedef struct {
    const double *v[4][3];
} triangle4_faces;

/* For each lane l < n (1 <= n <= 4): t[l] = triangle_t(face l, r, s, 0,
** tmax, bary[l]), the distance of a hit or 0. triangle4_avx computes the
** four in AVX's lanes, triangle4_scalar one by one; both give triangle_t's
** bits (triangle4_avx calls triangle4_scalar where AVX is not built). The
** caller picks by bvh_simd, so that LANCER_SIMD=0 runs the scalar one. */
void triangle4_scalar(const triangle4_faces *f, int n, const ray *r, const triangle_shear *s,
                      double tmax, double t[4], double bary[4][3]);
void triangle4_avx(const triangle4_faces *f, int n, const ray *r, const triangle_shear *s,
                   double tmax, double t[4], double bary[4][3]);

#endif
