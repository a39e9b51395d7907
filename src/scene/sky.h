/* sky.h: what a ray that leaves the scene sees (sky.c), and the sky as a
** light for paths (indirect > 0). */
#ifndef LC_SKY_H
#define LC_SKY_H

#include "base/radiance.h"
#include "scene.h"

/* The background texture in direction d (LC_NEED_SKY), clamped below at 0:
** evaluated at the unit direction as a point and at its sphere (u, v). */
radiance sky_radiance(const lc_scene *s, lc_vec3 d);
/* What a ray leaving in direction d sees, whatever the background is. */
radiance sky_seen(const lc_scene *s, lc_vec3 d);

/* The sky's light distribution for sampling directions toward it: by
** luminance over an equirectangular image (texel (i, j) in proportion to its
** luminance times the solid angle it covers), else uniform over the sphere. */
lc_status sky_dist_build(const lc_scene *s, sky_dist *d, lc_error *err);
void      sky_dist_free(sky_dist *d);
/* A unit direction for the point u of the unit square, and its density in
** solid angle; 0 when it has none. */
double    sky_sample(const sky_dist *d, const double u[2], lc_vec3 *dir);
/* The density sky_sample gives unit direction dir. */
double    sky_pdf(const sky_dist *d, lc_vec3 dir);

#endif
