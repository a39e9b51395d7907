/* dielectric.h: Snell's law and the exact Fresnel reflectance of a smooth
** dielectric interface (pbrt-v4's Refract and FrDielectric; docs/numerics.md
** 1.10). eta is n_t / n_i: the index past the surface over the index on the
** ray's side. */
#ifndef LC_DIELECTRIC_H
#define LC_DIELECTRIC_H

#include "base/vec.h"

/* The unpolarised reflectance, the mean of r_parallel^2 and r_perp^2, of a
** ray meeting the surface at cos_i (its cosine with the normal on its own
** side; a negative one is from the other side, where the ratio is 1/eta).
** In [0, 1] for every input and never NaN: exactly 1 past the critical
** angle and at grazing incidence (cos_i = 0), exactly 0 when eta = 1. */
double dielectric_fresnel(double cos_i, double eta);

/* The same, with r_parallel and r_perp (0 past the critical angle, where
** the reflectance is 1). */
double dielectric_fresnel_parts(double cos_i, double eta, double *r_par, double *r_perp);

/* The refracted direction, unit, of the unit direction d at the unit normal
** n on d's side (d.n <= 0): 0 at total internal reflection (sin^2 of the
** transmitted angle >= 1), where nothing is transmitted. eta = 1 gives d
** itself, bit for bit. */
int dielectric_refract(lc_vec3 d, lc_vec3 n, double eta, lc_vec3 *t);

#endif
