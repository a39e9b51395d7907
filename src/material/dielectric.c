/* dielectric.c: Snell's law and the Fresnel equations at a dielectric surface. */
#include "dielectric.h"

/* cos of the transmitted angle for cos_i in [0, 1], or -1 past the critical
** angle. sin^2 as (1 - c)(1 + c): 1 - c is exact for c >= 1/2 (Sterbenz),
** so near normal incidence sin^2 keeps its digits where 1 - c*c would
** cancel them away. sin^2 t >= 1 is total internal reflection, exactly at
** the critical angle too, so the square root never sees a negative. */
static double cos_transmitted(double cos_i, double eta)
{
    double sin2_i = (1 - cos_i) * (1 + cos_i);
    double sin2_t = sin2_i / (eta * eta);
    if (!(sin2_t < 1))
        return -1;
    return sqrt(1 - sin2_t);
}

double dielectric_fresnel_parts(double cos_i, double eta, double *r_par, double *r_perp)
{
    /* Rounding can give cosines past +-1 (and NaN would be a bug upstream:
    ** it is taken as grazing rather than passed on). */
    if (!(cos_i >= -1))
        cos_i = -1;
    if (cos_i > 1)
        cos_i = 1;
    if (cos_i < 0) {               /* from the other side */
        eta = 1 / eta;
        cos_i = -cos_i;
    }
    *r_par = *r_perp = 0;
    if (eta == 1)                  /* no interface: not even at grazing */
        return 0;
    double cos_t = cos_transmitted(cos_i, eta);
    if (cos_t < 0) {
        *r_par = *r_perp = 1;
        return 1;
    }
    /* Both denominators are > 0: cos_t > 0 here. Each ratio is (a - b) /
    ** (a + b) with a, b >= 0, whose rounding keeps |ratio| <= 1, so F
    ** never leaves [0, 1]; at cos_i = 0 both are -1 exactly and F = 1. */
    double a = eta * cos_i, b = eta * cos_t;
    *r_par = (a - cos_t) / (a + cos_t);
    *r_perp = (cos_i - b) / (cos_i + b);
    return (*r_par * *r_par + *r_perp * *r_perp) / 2;
}

double dielectric_fresnel(double cos_i, double eta)
{
    double p, s;
    return dielectric_fresnel_parts(cos_i, eta, &p, &s);
}

int dielectric_refract(lc_vec3 d, lc_vec3 n, double eta, lc_vec3 *t)
{
    if (eta == 1) {                /* straight through, exactly (H19) */
        *t = d;
        return 1;
    }
    double cos_i = -v3_dot(d, n);
    if (cos_i < 0)
        cos_i = 0;
    if (cos_i > 1)
        cos_i = 1;
    double cos_t = cos_transmitted(cos_i, eta);
    if (cos_t < 0)
        return 0;
    /* d / eta + (cos_i / eta - cos_t) n: unit in exact arithmetic. */
    *t = v3_norm(v3_madd(v3_mul(d, 1 / eta), n, cos_i / eta - cos_t));
    return 1;
}
