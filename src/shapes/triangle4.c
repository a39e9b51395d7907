/* triangle4.c: the watertight triangle test (triangle.h) on up to four
** faces at once, one per lane of AVX, for a leaf of a mesh's faces. Each
** lane computes triangle_t's expressions with the same IEEE double
** operations in the same order (no FMA: the geometry is built without
** contraction), so each gives triangle_t's bits; triangle4_scalar is the
** same batch one face at a time, for processors without AVX and for
** LANCER_SIMD=0. The four test against one tmax: a batch. */
#include "accel/bvh.h"
#include "triangle4.h"

void triangle4_scalar(const triangle4_faces *f, int n, const ray *r, const triangle_shear *s,
                      double tmax, double t[4], double bary[4][3])
{
    for (int l = 0; l < n; l++)
        t[l] = triangle_t(f->v[l][0], f->v[l][1], f->v[l][2], r, s, 0, tmax, bary[l]);
}

#if BVH_HAVE_SIMD
#include <immintrin.h>

/* Corner i of the four faces (lanes n.. repeat face 0), as x, y and z
** across the lanes: each corner's three doubles loaded at once (the
** fourth masked off: a mesh's last vertex ends its array), then
** transposed. */
BVH_AVX_TARGET static inline void corners(const triangle4_faces *f, const int lane[4], int i,
                                          __m256d c[3])
{
    const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
    __m256d r0 = _mm256_maskload_pd(f->v[lane[0]][i], xyz);
    __m256d r1 = _mm256_maskload_pd(f->v[lane[1]][i], xyz);
    __m256d r2 = _mm256_maskload_pd(f->v[lane[2]][i], xyz);
    __m256d r3 = _mm256_maskload_pd(f->v[lane[3]][i], xyz);
    __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    c[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
    c[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
    c[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
}

#ifndef LC_NAIVE
BVH_AVX_TARGET static inline __m256d vabs(__m256d x)
{
    return _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
}

/* max2(a, b) = a > b ? a : b: vmaxpd returns its second operand unless the
** first is greater, NaN included. */
BVH_AVX_TARGET static inline __m256d vmax(__m256d a, __m256d b)
{
    return _mm256_max_pd(a, b);
}

/* triangle_edge's product difference in each lane, before its fallback. */
BVH_AVX_TARGET static inline __m256d edge(__m256d ax, __m256d ay, __m256d bx, __m256d by)
{
    return _mm256_sub_pd(_mm256_mul_pd(ax, by), _mm256_mul_pd(ay, bx));
}

/* triangle_edge's fallback: lanes that rounded to exactly zero are
** recomputed as it does, in extended precision. */
BVH_AVX_TARGET static inline __m256d edge_again(__m256d e, __m256d ax, __m256d ay,
                                                __m256d bx, __m256d by)
{
    double le[4], lax[4], lay[4], lbx[4], lby[4];
    _mm256_storeu_pd(le, e);
    _mm256_storeu_pd(lax, ax);
    _mm256_storeu_pd(lay, ay);
    _mm256_storeu_pd(lbx, bx);
    _mm256_storeu_pd(lby, by);
    for (int l = 0; l < 4; l++)
        le[l] = triangle_edge(lax[l], lay[l], lbx[l], lby[l]);
    return _mm256_loadu_pd(le);
}

/* The test for a ray whose dominant axis is kz (kx, ky the next two):
** constants, so that the corners' coordinates stay in registers. */
BVH_AVX_TARGET static inline __attribute__((always_inline))
void lanes(const triangle4_faces *f, int n, const ray *r, const triangle_shear *s,
           double tmax, double t[4], double bary[4][3], int kx, int ky, int kz)
{
    const int lane[4] = {0, n > 1, n > 2 ? 2 : 0, n > 3 ? 3 : 0};
    const double o[3] = {r->o.x, r->o.y, r->o.z};
    const __m256d sx = _mm256_set1_pd(s->sx), sy = _mm256_set1_pd(s->sy);
    const __m256d ox = _mm256_set1_pd(o[kx]), oy = _mm256_set1_pd(o[ky]),
                  oz = _mm256_set1_pd(o[kz]);
    __m256d x[3], y[3], z[3];
    for (int i = 0; i < 3; i++) {
        __m256d c[3];
        corners(f, lane, i, c);
        __m256d px = _mm256_sub_pd(c[kx], ox);
        __m256d py = _mm256_sub_pd(c[ky], oy);
        __m256d pz = _mm256_sub_pd(c[kz], oz);
        x[i] = _mm256_add_pd(px, _mm256_mul_pd(sx, pz));
        y[i] = _mm256_add_pd(py, _mm256_mul_pd(sy, pz));
        z[i] = pz;
    }
    __m256d e0 = edge(x[1], y[1], x[2], y[2]);
    __m256d e1 = edge(x[2], y[2], x[0], y[0]);
    __m256d e2 = edge(x[0], y[0], x[1], y[1]);
    const __m256d zero = _mm256_setzero_pd();
    if (_mm256_movemask_pd(_mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_EQ_OQ),
                                                     _mm256_cmp_pd(e1, zero, _CMP_EQ_OQ)),
                                        _mm256_cmp_pd(e2, zero, _CMP_EQ_OQ)))) {
        e0 = edge_again(e0, x[1], y[1], x[2], y[2]);    /* rare */
        e1 = edge_again(e1, x[2], y[2], x[0], y[0]);
        e2 = edge_again(e2, x[0], y[0], x[1], y[1]);
    }
    __m256d neg = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_LT_OQ),
                                            _mm256_cmp_pd(e1, zero, _CMP_LT_OQ)),
                               _mm256_cmp_pd(e2, zero, _CMP_LT_OQ));
    __m256d pos = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_GT_OQ),
                                            _mm256_cmp_pd(e1, zero, _CMP_GT_OQ)),
                               _mm256_cmp_pd(e2, zero, _CMP_GT_OQ));
    __m256d miss = _mm256_and_pd(neg, pos);
    __m256d det = _mm256_add_pd(_mm256_add_pd(e0, e1), e2);
    miss = _mm256_or_pd(miss, _mm256_cmp_pd(det, zero, _CMP_EQ_OQ));
    if (_mm256_movemask_pd(miss) == 15) {       /* the usual case: none hit */
        for (int l = 0; l < n; l++)
            t[l] = 0;
        return;
    }
    __m256d mzr = vmax(vabs(z[0]), vmax(vabs(z[1]), vabs(z[2])));
    const __m256d sz = _mm256_set1_pd(s->sz);
    for (int i = 0; i < 3; i++)
        z[i] = _mm256_mul_pd(z[i], sz);
    __m256d ts = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(e0, z[0]), _mm256_mul_pd(e1, z[1])),
                               _mm256_mul_pd(e2, z[2]));
    /* triangle_t's sign-aware comparisons, tmin = 0 */
    __m256d lo = _mm256_mul_pd(zero, det), hi = _mm256_mul_pd(_mm256_set1_pd(tmax), det);
    __m256d dneg = _mm256_cmp_pd(det, zero, _CMP_LT_OQ), dpos = _mm256_cmp_pd(det, zero, _CMP_GT_OQ);
    miss = _mm256_or_pd(miss, _mm256_and_pd(dneg, _mm256_or_pd(_mm256_cmp_pd(ts, lo, _CMP_GE_OQ),
                                                               _mm256_cmp_pd(ts, hi, _CMP_LT_OQ))));
    miss = _mm256_or_pd(miss, _mm256_and_pd(dpos, _mm256_or_pd(_mm256_cmp_pd(ts, lo, _CMP_LE_OQ),
                                                               _mm256_cmp_pd(ts, hi, _CMP_GT_OQ))));
    __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), det);
    __m256d tt = _mm256_mul_pd(ts, inv);
    __m256d mz = vmax(vabs(z[0]), vmax(vabs(z[1]), vabs(z[2])));
    __m256d mx = vmax(vabs(x[0]), vmax(vabs(x[1]), vabs(x[2])));
    __m256d my = vmax(vabs(y[0]), vmax(vabs(y[1]), vabs(y[2])));
    const __m256d g2 = _mm256_set1_pd(vec_gamma(2)), g3 = _mm256_set1_pd(vec_gamma(3)),
                  g5 = _mm256_set1_pd(vec_gamma(5));
    __m256d dz = _mm256_mul_pd(g3, mz);
    __m256d dx = _mm256_mul_pd(g5, _mm256_add_pd(mx, mzr));
    __m256d dy = _mm256_mul_pd(g5, _mm256_add_pd(my, mzr));
    __m256d de = _mm256_mul_pd(_mm256_set1_pd(2),
                               _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(g2, mx), my),
                                                           _mm256_mul_pd(dy, mx)),
                                             _mm256_mul_pd(dx, my)));
    __m256d me = vmax(vabs(e0), vmax(vabs(e1), vabs(e2)));
    __m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(g3, me), mz),
                                              _mm256_mul_pd(de, mz)),
                                _mm256_mul_pd(dz, me));
    __m256d dt = _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(3), sum), vabs(inv));
    miss = _mm256_or_pd(miss, _mm256_cmp_pd(tt, dt, _CMP_NGT_UQ));      /* !(t > dt) */
    double lt[4], b0[4], b1[4], b2[4];
    _mm256_storeu_pd(lt, _mm256_andnot_pd(miss, tt));
    _mm256_storeu_pd(b0, _mm256_mul_pd(e0, inv));
    _mm256_storeu_pd(b1, _mm256_mul_pd(e1, inv));
    _mm256_storeu_pd(b2, _mm256_mul_pd(e2, inv));
    for (int l = 0; l < n; l++) {
        t[l] = lt[l];
        bary[l][0] = b0[l];
        bary[l][1] = b1[l];
        bary[l][2] = b2[l];
    }
}

BVH_AVX_TARGET void triangle4_avx(const triangle4_faces *f, int n, const ray *r,
                                  const triangle_shear *s, double tmax, double t[4],
                                  double bary[4][3])
{
    if (s->kz == 0)
        lanes(f, n, r, s, tmax, t, bary, 1, 2, 0);
    else if (s->kz == 1)
        lanes(f, n, r, s, tmax, t, bary, 2, 0, 1);
    else
        lanes(f, n, r, s, tmax, t, bary, 0, 1, 2);
}
#else

/* `make NAIVE=1`: the naive Moller-Trumbore of triangle.h in four lanes,
** so that the benchmark's price of robustness compares batch with batch. */
BVH_AVX_TARGET static inline __m256d dot3(const __m256d a[3], const __m256d b[3])
{
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a[0], b[0]), _mm256_mul_pd(a[1], b[1])),
                         _mm256_mul_pd(a[2], b[2]));
}

BVH_AVX_TARGET static inline void cross3(const __m256d a[3], const __m256d b[3], __m256d c[3])
{
    c[0] = _mm256_sub_pd(_mm256_mul_pd(a[1], b[2]), _mm256_mul_pd(a[2], b[1]));
    c[1] = _mm256_sub_pd(_mm256_mul_pd(a[2], b[0]), _mm256_mul_pd(a[0], b[2]));
    c[2] = _mm256_sub_pd(_mm256_mul_pd(a[0], b[1]), _mm256_mul_pd(a[1], b[0]));
}

BVH_AVX_TARGET void triangle4_avx(const triangle4_faces *f, int n, const ray *r,
                                  const triangle_shear *s, double tmax, double t[4],
                                  double bary[4][3])
{
    (void)s;
    const int lane[4] = {0, n > 1, n > 2 ? 2 : 0, n > 3 ? 3 : 0};
    const double o[3] = {r->o.x, r->o.y, r->o.z}, dd[3] = {r->d.x, r->d.y, r->d.z};
    __m256d e1[3], e2[3], d[3], tv[3], pv[3], qv[3];
    __m256d p0[3], p1[3], p2[3];
    corners(f, lane, 0, p0);
    corners(f, lane, 1, p1);
    corners(f, lane, 2, p2);
    for (int k = 0; k < 3; k++) {
        e1[k] = _mm256_sub_pd(p1[k], p0[k]);
        e2[k] = _mm256_sub_pd(p2[k], p0[k]);
        d[k] = _mm256_set1_pd(dd[k]);
        tv[k] = _mm256_sub_pd(_mm256_set1_pd(o[k]), p0[k]);
    }
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1);
    cross3(d, e2, pv);
    __m256d det = dot3(e1, pv);
    __m256d miss = _mm256_cmp_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), det),
                                 _mm256_set1_pd(1e-12), _CMP_LT_OQ);
    __m256d inv = _mm256_div_pd(one, det);
    __m256d u = _mm256_mul_pd(dot3(tv, pv), inv);
    miss = _mm256_or_pd(miss, _mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_LT_OQ),
                                           _mm256_cmp_pd(u, one, _CMP_GT_OQ)));
    cross3(tv, e1, qv);
    __m256d v = _mm256_mul_pd(dot3(d, qv), inv);
    miss = _mm256_or_pd(miss, _mm256_or_pd(_mm256_cmp_pd(v, zero, _CMP_LT_OQ),
                                           _mm256_cmp_pd(_mm256_add_pd(u, v), one,
                                                         _CMP_GT_OQ)));
    __m256d tt = _mm256_mul_pd(dot3(e2, qv), inv);
    miss = _mm256_or_pd(miss, _mm256_or_pd(_mm256_cmp_pd(tt, zero, _CMP_NGT_UQ),
                                           _mm256_cmp_pd(tt, _mm256_set1_pd(tmax),
                                                         _CMP_NLT_UQ)));    /* !(0 < t < tmax) */
    double lt[4], lu[4], lv[4];
    _mm256_storeu_pd(lt, _mm256_andnot_pd(miss, tt));
    _mm256_storeu_pd(lu, u);
    _mm256_storeu_pd(lv, v);
    for (int l = 0; l < n; l++) {
        t[l] = lt[l];
        bary[l][0] = 1 - lu[l] - lv[l];
        bary[l][1] = lu[l];
        bary[l][2] = lv[l];
    }
}
#endif /* LC_NAIVE */
#else
void triangle4_avx(const triangle4_faces *f, int n, const ray *r, const triangle_shear *s,
                   double tmax, double t[4], double bary[4][3])
{
    triangle4_scalar(f, n, r, s, tmax, t, bary);
}
#endif
