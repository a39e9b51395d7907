/* radiance.h: the colour a ray carries, in double, capped so it stays finite. */
#ifndef LC_RADIANCE_H
#define LC_RADIANCE_H

#include "lancer.h"

/* Radiance in double: the float colours of materials and lights are
** widened once, and sums never round per channel differently. */
typedef struct { double r, g, b; } radiance;

/* Radiance is capped here: pixels clamp to [0, 1] when written, and the cap
** keeps a huge light or coefficient from making an infinity, whose product
** with a zero would be a NaN pixel. */
#define RADIANCE_CAP 1e100

static inline double radiance_cap(double x) { return x < RADIANCE_CAP ? x : RADIANCE_CAP; }
/* The largest channel (of channels that are not NaN). */
static inline double r_max(radiance c)
{
    double gb = c.g > c.b ? c.g : c.b;
    return c.r > gb ? c.r : gb;
}
static inline radiance rad(lc_color c) { radiance r = {c.r, c.g, c.b}; return r; }
static inline radiance r_scale(radiance a, double k)
{
    radiance r = {radiance_cap(a.r * k), radiance_cap(a.g * k), radiance_cap(a.b * k)};
    return r;
}
/* a (capped: finite) times k in [0, 1] (within a rounding): it cannot grow
** past the cap by more than an ulp, so no cap of its own; for the cosine of
** every light at every point (S7's parity). */
static inline radiance r_scale_unit(radiance a, double k)
{
    radiance r = {a.r * k, a.g * k, a.b * k};
    return r;
}
static inline radiance r_add(radiance a, radiance b)
{
    radiance r = {radiance_cap(a.r + b.r), radiance_cap(a.g + b.g), radiance_cap(a.b + b.b)};
    return r;
}
static inline radiance r_mul(radiance a, radiance b)
{
    radiance r = {radiance_cap(a.r * b.r), radiance_cap(a.g * b.g), radiance_cap(a.b * b.b)};
    return r;
}

#endif
