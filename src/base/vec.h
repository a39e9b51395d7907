/* vec.h: small vector maths in double, and floating-point error helpers. */
#ifndef LC_VEC_H
#define LC_VEC_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "lancer.h"

#define PI 3.14159265358979323846

/* For the few hot helpers written once for several callers (a BVH
** traversal, the shadow ray) that the compiler would otherwise call: each
** caller gets its own inlined copy, as when the code was written out. */
#if defined(__GNUC__)
#define ALWAYS_INLINE static inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE static inline
#endif
/* And the other way: code a hot loop reaches only for some scenes (glass),
** kept out of it so its registers stay the loop's (inlined, the dielectric
** code cost B1 2 % more instructions without ever running). */
#if defined(__GNUC__)
#define NEVER_INLINE static __attribute__((noinline))
#else
#define NEVER_INLINE static
#endif

static inline lc_vec3 v3(double x, double y, double z)
{
    lc_vec3 r = {x, y, z};
    return r;
}
static inline lc_vec3 v3_add(lc_vec3 a, lc_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline lc_vec3 v3_sub(lc_vec3 a, lc_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline lc_vec3 v3_mul(lc_vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline lc_vec3 v3_neg(lc_vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline double  v3_dot(lc_vec3 a, lc_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double  v3_len(lc_vec3 a) { return sqrt(v3_dot(a, a)); }
static inline lc_vec3 v3_abs(lc_vec3 a) { return v3(fabs(a.x), fabs(a.y), fabs(a.z)); }
/* The larger of two numbers that are not NaN: one instruction, where
** fmax() is a library call (it must order NaNs). */
static inline double max2(double a, double b) { return a > b ? a : b; }

static inline double  v3_max_abs(lc_vec3 a)
{
    return max2(fabs(a.x), max2(fabs(a.y), fabs(a.z)));
}
static inline double v3_comp(lc_vec3 a, int i) { return i == 0 ? a.x : i == 1 ? a.y : a.z; }
static inline lc_vec3 v3_cross(lc_vec3 a, lc_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline lc_vec3 v3_norm(lc_vec3 a) { return v3_mul(a, 1.0 / v3_len(a)); }
static inline lc_vec3 v3_madd(lc_vec3 a, lc_vec3 b, double s)  /* a + b*s */
{
    return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}

/* The next double above a positive finite x, without libm's call: the
** render loop widens every accepted distance by one ulp to keep ties. */
static inline double next_up(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    u++;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* One ulp from finite x, up (+1) or down (-1): nextafter without the call. */
static inline double next_toward(double x, int up)
{
    if (x == 0)
        return up > 0 ? 4.9406564584124654e-324 : -4.9406564584124654e-324;
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    if ((x > 0) == (up > 0))
        u++;
    else
        u--;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* gamma(n) bounds the relative error of n chained roundings (pbrt-v4, 6.8). */
static inline double vec_gamma(int n)
{
    const double e = DBL_EPSILON * 0.5;
    return (n * e) / (1 - n * e);
}

static inline lc_color rgb(float r, float g, float b)
{
    lc_color c = {r, g, b};
    return c;
}
static inline int c_is_black(lc_color a) { return a.r == 0 && a.g == 0 && a.b == 0; }

#endif
