/* affine.c: things placed by an affine map: rays into their space, points
** and normals back, with the round trip's rounding bounded. */
#include <math.h>
#include "affine.h"
#include "error.h"

/* |a| |b| for 3x3 blocks of transforms. */
static void abs_product(const lc_transform *a, const lc_transform *b, double out[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] = fabs(a->m[i][0]) * fabs(b->m[0][j]) +
                        fabs(a->m[i][1]) * fabs(b->m[1][j]) +
                        fabs(a->m[i][2]) * fabs(b->m[2][j]);
}

/* A hit on a placed thing is found in object space, where later rays will meet
** the mesh again after going through `inv`, and reported in the world,
** where they start. Three roundings separate the two, each bounded here
** relative to |x| so the bound holds at any scale and offset:
** - the world points M v + t and the ray origins inv x + t' are rounded
**   (gamma(4) of the products' magnitudes, mapped through |M|);
** - inv is not exactly M's inverse: M inv - I and M t' + t, computed with
**   their own rounding, say by how much a point moves on the round trip.
** Twice each, for the vertices and for the spawned origin. */
lc_status affine_make(const lc_transform *t, affine *x, lc_error *err)
{
    if (lc_transform_inverse(t, &x->inv, err))
        return LC_EARG;
    x->xf = *t;
    for (int i = 0; i < 3; i++)               /* M^-T: outward stays outward */
        for (int j = 0; j < 3; j++)
            x->nrm[i][j] = x->inv.m[j][i];
    double mi[3][3], res[3][3];
    abs_product(t, &x->inv, mi);
    lc_transform p = lc_transform_compose(t, &x->inv);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            res[i][j] = fabs(p.m[i][j] - (i == j)) + vec_gamma(3) * mi[i][j];
    double g = vec_gamma(4);
    double s0[3];
    for (int i = 0; i < 3; i++) {
        double mt = fabs(t->m[i][0]) * fabs(x->inv.m[0][3]) +
                    fabs(t->m[i][1]) * fabs(x->inv.m[1][3]) +
                    fabs(t->m[i][2]) * fabs(x->inv.m[2][3]);
        double rt = fabs(p.m[i][3]) + vec_gamma(3) * (mt + fabs(t->m[i][3]));
        s0[i] = 2 * (g * (mt + fabs(t->m[i][3])) + rt);
        for (int j = 0; j < 3; j++)
            x->slack[i][j] = 2 * (g * mi[i][j] + res[i][j]);
    }
    x->slack0 = v3(s0[0], s0[1], s0[2]);
    return LC_OK;
}

lc_vec3 affine_slack(const affine *x, lc_vec3 a)   /* a: componentwise |x| */
{
    return v3(x->slack[0][0] * a.x + x->slack[0][1] * a.y + x->slack[0][2] * a.z +
                  x->slack0.x,
              x->slack[1][0] * a.x + x->slack[1][1] * a.y + x->slack[1][2] * a.z +
                  x->slack0.y,
              x->slack[2][0] * a.x + x->slack[2][1] * a.y + x->slack[2][2] * a.z +
                  x->slack0.z);
}

static lc_vec3 mat3_apply(const double m[3][3], lc_vec3 v)
{
    return v3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
              m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
              m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
}


ray affine_ray(const affine *a, const ray *r)
{
    ray o = {lc_transform_point(&a->inv, r->o), lc_transform_vector(&a->inv, r->d)};
    return o;
}

lc_vec3 affine_normal_raw(const affine *a, lc_vec3 n)
{
    return mat3_apply(a->nrm, n);
}

lc_vec3 affine_normal(const affine *a, lc_vec3 n)
{
    return v3_norm(mat3_apply(a->nrm, n));
}

lc_vec3 affine_point(const affine *a, lc_vec3 p, lc_vec3 perr, lc_vec3 *world_err)
{
    const double (*m)[4] = a->xf.m;
    lc_vec3 w = lc_transform_point(&a->xf, p);
    lc_vec3 ap = v3_abs(p);
    /* perr through |M|, the rounding of M p + t, and the round trip. */
    lc_vec3 e = v3(fabs(m[0][0]) * (perr.x + vec_gamma(3) * ap.x) +
                       fabs(m[0][1]) * (perr.y + vec_gamma(3) * ap.y) +
                       fabs(m[0][2]) * (perr.z + vec_gamma(3) * ap.z),
                   fabs(m[1][0]) * (perr.x + vec_gamma(3) * ap.x) +
                       fabs(m[1][1]) * (perr.y + vec_gamma(3) * ap.y) +
                       fabs(m[1][2]) * (perr.z + vec_gamma(3) * ap.z),
                   fabs(m[2][0]) * (perr.x + vec_gamma(3) * ap.x) +
                       fabs(m[2][1]) * (perr.y + vec_gamma(3) * ap.y) +
                       fabs(m[2][2]) * (perr.z + vec_gamma(3) * ap.z));
    e = v3_add(e, v3_mul(v3_abs(w), vec_gamma(1)));
    *world_err = v3_add(e, affine_slack(a, v3_abs(w)));
    return w;
}
