/* transform.c: affine transforms: building, composing, inverting, applying. */
#include <math.h>
#include "error.h"
#include "vec.h"

lc_transform lc_transform_identity(void)
{
    lc_transform t = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    return t;
}

lc_transform lc_transform_translate(lc_vec3 v)
{
    lc_transform t = {{{1, 0, 0, v.x}, {0, 1, 0, v.y}, {0, 0, 1, v.z}}};
    return t;
}

lc_transform lc_transform_scale(lc_vec3 s)
{
    lc_transform t = {{{s.x, 0, 0, 0}, {0, s.y, 0, 0}, {0, 0, s.z, 0}}};
    return t;
}

/* Sine and cosine of an angle in degrees, exact at multiples of 90: a
** quarter turn built from sin(pi/2) would leave 6e-17 where 0 belongs, and
** a mesh turned by it would no longer match one built turned. */
static void sincos_degrees(double deg, double *s, double *c)
{
    double r = fmod(deg, 360);               /* exact */
    if (fmod(r, 90) == 0) {
        static const double sn[4] = {0, 1, 0, -1}, cs[4] = {1, 0, -1, 0};
        int k = ((int)(r / 90) % 4 + 4) % 4;
        *s = sn[k];
        *c = cs[k];
        return;
    }
    double rad = r * (3.14159265358979323846 / 180);
    *s = sin(rad);
    *c = cos(rad);
}

lc_status lc_transform_rotate(lc_vec3 axis, double degrees, lc_transform *out,
                              lc_error *err)
{
    if (!isfinite(degrees))
        return error_fail(err, LC_EARG, "degrees", "must be finite, got %g", degrees);
    if (!isfinite(axis.x) || !isfinite(axis.y) || !isfinite(axis.z))
        return error_fail(err, LC_EARG, "axis", "must be finite, got (%g, %g, %g)", axis.x,
                       axis.y, axis.z);
    double l = v3_len(axis);
    if (!(l > 0) || !isfinite(l))
        return error_fail(err, LC_EARG, "axis", "must have a direction, got (%g, %g, %g)",
                       axis.x, axis.y, axis.z);
    lc_vec3 a = v3_mul(axis, 1.0 / l);
    /* Along a coordinate axis the unit vector is exact. */
    if (axis.y == 0 && axis.z == 0) a = v3(copysign(1, axis.x), 0, 0);
    else if (axis.x == 0 && axis.z == 0) a = v3(0, copysign(1, axis.y), 0);
    else if (axis.x == 0 && axis.y == 0) a = v3(0, 0, copysign(1, axis.z));
    double s, c;
    sincos_degrees(degrees, &s, &c);
    double k = 1 - c;
    /* Rodrigues: R = c I + (1 - c) a a^T + s [a]x */
    lc_transform t = {{
        {c + k * a.x * a.x, k * a.x * a.y - s * a.z, k * a.x * a.z + s * a.y, 0},
        {k * a.x * a.y + s * a.z, c + k * a.y * a.y, k * a.y * a.z - s * a.x, 0},
        {k * a.x * a.z - s * a.y, k * a.y * a.z + s * a.x, c + k * a.z * a.z, 0}}};
    *out = t;
    error_ok(err);
    return LC_OK;
}

lc_transform lc_transform_compose(const lc_transform *a, const lc_transform *b)
{
    lc_transform r;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 4; j++) {
            double x = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] +
                       a->m[i][2] * b->m[2][j];
            r.m[i][j] = j == 3 ? x + a->m[i][3] : x;
        }
    }
    return r;
}

lc_vec3 lc_transform_point(const lc_transform *t, lc_vec3 p)
{
    const double (*m)[4] = t->m;
    return v3(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
              m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
              m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]);
}

lc_vec3 lc_transform_vector(const lc_transform *t, lc_vec3 v)
{
    const double (*m)[4] = t->m;
    return v3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
              m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
              m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
}

int lc_transform_is_identity(const lc_transform *t)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            if (t->m[i][j] != (i == j))
                return 0;
    return 1;
}

/* Cofactors of M (cof[i][j] multiplies m[i][j] in det), the determinant,
** and a bound on its rounding error. */
static double cofactors(const lc_transform *t, double cof[3][3], double *bound)
{
    const double (*m)[4] = t->m;
    double b = 0;
    for (int i = 0; i < 3; i++) {
        int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; j++) {
            int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            cof[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
            if (i == 0)
                b += fabs(m[0][j]) * (fabs(m[i1][j1] * m[i2][j2]) +
                                      fabs(m[i1][j2] * m[i2][j1]));
        }
    }
    *bound = vec_gamma(6) * b;
    return m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
}

lc_status lc_transform_check(const lc_transform *t, lc_error *err)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(t->m[i][j]))
                return error_fail(err, LC_EARG, "transform",
                               "transform entry (%d, %d) must be finite, got %g", i + 1, j + 1,
                               t->m[i][j]);
    double cof[3][3], bound;
    double det = cofactors(t, cof, &bound);
    /* Relative to its own rounding: a scale of 1e-100 is fine, a flattening
    ** (a zero scale, two parallel axes) or an underflowing det is not. */
    if (!(fabs(det) > bound))
        return error_fail(err, LC_EARG, "transform", "transform is singular (determinant %g): it "
                       "flattens space and cannot be undone", det);
    error_ok(err);
    return LC_OK;
}

lc_status lc_transform_inverse(const lc_transform *t, lc_transform *out, lc_error *err)
{
    if (lc_transform_check(t, err))
        return LC_EARG;
    double cof[3][3], bound;
    double det = cofactors(t, cof, &bound);
    lc_transform r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = cof[j][i] / det;
    for (int i = 0; i < 3; i++)
        r.m[i][3] = -(r.m[i][0] * t->m[0][3] + r.m[i][1] * t->m[1][3] +
                      r.m[i][2] * t->m[2][3]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(r.m[i][j]))
                return error_fail(err, LC_EARG, "transform", "transform has no finite inverse "
                               "(determinant %g)", det);
    *out = r;
    return LC_OK;
}

/* n' = sign(det) cof(M) n: the inverse transpose up to a positive factor,
** so a normal stays on the same side of the moved surface, mirror or not. */
lc_vec3 lc_transform_normal(const lc_transform *t, lc_vec3 n)
{
    double cof[3][3], bound;
    double s = cofactors(t, cof, &bound) < 0 ? -1 : 1;
    return v3(s * (cof[0][0] * n.x + cof[0][1] * n.y + cof[0][2] * n.z),
              s * (cof[1][0] * n.x + cof[1][1] * n.y + cof[1][2] * n.z),
              s * (cof[2][0] * n.x + cof[2][1] * n.y + cof[2][2] * n.z));
}
