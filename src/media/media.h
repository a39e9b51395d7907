/* media.h: the media a path is in (nested dielectrics): the indices on both
** sides of a surface it crosses, and what a medium absorbs along the way. */
#ifndef LC_MEDIA_H
#define LC_MEDIA_H

#include "base/radiance.h"
#include "scene/scene.h"

/* The materials with kt > 0 a path has entered and not left, innermost
** last; none is air, of index 1. A medium left that was never entered is
** the one the ray was in (a camera inside glass). A path more than
** MEDIA_MAX deep forgets the outermost: leaving the innermost it still
** knows, and those it forgot, it takes air to be outside (right for the
** outermost). */
#define MEDIA_MAX 8
#define MEDIUM_AIR UINT32_MAX

typedef struct {
    int      n;
    uint32_t m[MEDIA_MAX];     /* material indices */
} media;

static inline double media_ior(const lc_scene *s, uint32_t m)
{
    return m == MEDIUM_AIR ? 1 : s->materials[m].ior;
}

/* A ray crosses a surface of material mi (kt > 0), `entering` it (going
** against its outward normal) or leaving it: *after is the media past the
** surface, *n1 and *n2 the indices before and past it. The medium a ray is
** in is the innermost it entered: exact for properly nested closed
** objects (a bubble in glass, water in a glass whose walls it slightly
** overlaps); where two volumes overlap otherwise, the overlap belongs to
** the one the ray entered last. Returns 0 when both sides are one medium
** (a sphere inside one of the same material, the far wall of an overlap):
** no interface, the ray goes on as if the surface were not there. */
static inline int media_cross(const lc_scene *s, const media *md, uint32_t mi,
                              int entering, media *after, double *n1, double *n2)
{
    *after = *md;
    uint32_t in = md->n ? md->m[md->n - 1] : MEDIUM_AIR, out;
    if (entering) {
        if (after->n == MEDIA_MAX) {           /* forget the outermost */
            memmove(after->m, after->m + 1, (MEDIA_MAX - 1) * sizeof after->m[0]);
            after->n--;
        }
        after->m[after->n++] = mi;
        out = mi;
    } else {
        int k = after->n - 1;
        while (k >= 0 && after->m[k] != mi)
            k--;
        if (k < 0) {
            in = mi;                           /* never entered: the ray is in it */
        } else {
            memmove(after->m + k, after->m + k + 1,
                    (size_t)(after->n - 1 - k) * sizeof after->m[0]);
            after->n--;
        }
        out = after->n ? after->m[after->n - 1] : MEDIUM_AIR;
    }
    if (in == out)
        return 0;
    *n1 = media_ior(s, in);
    *n2 = media_ior(s, out);
    return 1;
}

/* A ray in air (as far as md knows) leaving mi: it was in mi all along (a
** camera inside glass, a sea floor lit through the sea), from its origin,
** d away. md now says so; returns w times what mi absorbed on the way. */
static inline radiance media_adopt(const lc_scene *s, media *md, uint32_t mi, radiance w,
                                   double d);

/* w after a distance d (HUGE_VAL: to infinity) in the innermost medium
** (md->n > 0): times e^(-sigma d) per channel, Beer-Lambert; a channel the
** medium does not absorb is left alone (0 * inf would be NaN). */
static inline radiance media_absorb(const lc_scene *s, const media *md, radiance w,
                                    double d)
{
    lc_vec3 a = s->materials[md->m[md->n - 1]].absorption;
    if (a.x > 0) w.r *= exp(-a.x * d);
    if (a.y > 0) w.g *= exp(-a.y * d);
    if (a.z > 0) w.b *= exp(-a.z * d);
    return w;
}

static inline radiance media_adopt(const lc_scene *s, media *md, uint32_t mi, radiance w,
                                   double d)
{
    md->m[0] = mi;
    md->n = 1;
    return media_absorb(s, md, w, d);
}

#endif
