/* validate.h: the checks that shape, light and camera descriptions share. */
#ifndef LC_VALIDATE_H
#define LC_VALIDATE_H

#include "error.h"
#include "vec.h"

/* Two directions closer than this angle (radians) count as parallel. Both
** vectors are normalised first, so the test does not depend on scale. */
#define PARALLEL_SIN 1e-12

/* Each returns LC_OK, or fills err naming the field and the value. */
/* A point: finite, every coordinate within +-LC_MAX_COORD. */
lc_status validate_vec(lc_vec3 v, const char *field, lc_error *err);
/* A length (a radius): in [LC_MIN_LENGTH, LC_MAX_COORD]. */
lc_status validate_length(double x, const char *field, lc_error *err);
/* An edge: a vector whose length is one. */
lc_status validate_edge(lc_vec3 v, const char *field, lc_error *err);
/* A direction: finite, of a length that squares in double. */
lc_status validate_nonzero(lc_vec3 v, const char *field, lc_error *err);
/* A coefficient: finite and >= 0. */
lc_status validate_coef(double x, const char *field, lc_error *err);
/* A colour: each component finite and in [0, max]. */
lc_status validate_color(lc_color c, double max, const char *field, lc_error *err);
lc_status validate_not_parallel(lc_vec3 a, lc_vec3 b, const char *fa, const char *fb,
                                lc_error *err);

#endif
