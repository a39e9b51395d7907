/* bvh_packet.h: one box test for a packet of rays, that never rejects a box
** one of them would enter. */
#ifndef LC_BVH_PACKET_H
#define LC_BVH_PACKET_H

#include "bvh.h"

/* Rays walked together by the queries over arrays (intersect.c): at most
** this many, neighbours in the caller's array. */
#define BVH_PACKET 8

/* A packet as its box test reads it: its rays' one origin, and the bounds
** of their reciprocal directions per axis, whose signs all its rays share
** (neg), all finite. Rays from different origins do not make packets: a
** terrain's shadow rays, eight neighbours from eight points, passed a box
** test over the bounds of their origins at 94 leaves a ray where each met
** two, and took 2.6 times as long as walking one by one. */
typedef struct {
    double o[3], ilo[3], ihi[3];
    int    neg[3];
} bvh_packet;

/* Adds ray q to packet *p: 0 when q cannot join, its origin another or
** its reciprocals differing in sign on an axis from the packet's, or one
** infinite (a direction along an axis plane, whose slab distances may be
** NaN). */
static inline int bvh_packet_add(bvh_packet *p, const bvh_ray *q)
{
    for (int k = 0; k < 3; k++) {
        double inv = q->inv[k];
        if (q->o[k] != p->o[k] || q->neg[k] != p->neg[k] || !(fabs(inv) <= DBL_MAX))
            return 0;
        p->ilo[k] = inv < p->ilo[k] ? inv : p->ilo[k];
        p->ihi[k] = inv > p->ihi[k] ? inv : p->ihi[k];
    }
    return 1;
}

/* Starts *p with ray q, which must pass bvh_packet_add's checks as the
** others do (0 if not). */
static inline int bvh_packet_start(bvh_packet *p, const bvh_ray *q)
{
    for (int k = 0; k < 3; k++) {
        p->neg[k] = q->neg[k];
        p->o[k] = q->o[k];
        p->ilo[k] = p->ihi[k] = q->inv[k];
    }
    return bvh_packet_add(p, q);
}

/* Why a box this test rejects is one no ray of the packet enters by its
** own test (bvh_test_scalar, with its tmax at most the packet's). A ray's
** near distance on an axis is fl(a * inv), a = fl(bound - o) the same for
** every ray of the packet. Rounding is monotonic: fl(a * x) grows with x
** when a >= 0 and falls when a < 0, so over inv in [ilo, ihi] it is at
** least the smaller of fl(a * ilo) and fl(a * ihi). The far distances are
** bounded above by the larger, then enlarged by the same BVH_WIDEN. The
** packet's entry (the larger of 0 and the near bounds, shrunk) is then at
** most every ray's, its exit (the smaller of the packet's tmax and the far
** bounds) at least every ray's: if one ray enters, the packet does. All
** reciprocals are finite, so no product is NaN (an overflow is an
** infinity, still in order). Entry distances into t[], for the children's
** order. */
ALWAYS_INLINE unsigned bvh_packet_test_scalar(const bvh_node *nd, const bvh_packet *p,
                                              double tmax, double t[BVH_WIDTH])
{
    unsigned mask = 0;
    for (uint32_t c = 0; c < nd->n; c++) {
        double t0 = 0, t1 = tmax;
        for (int k = 0; k < 3; k++) {
            int g = p->neg[k];
            double a = (double)(g ? nd->hi[k][c] : nd->lo[k][c]) - p->o[k];
            double b = (double)(g ? nd->lo[k][c] : nd->hi[k][c]) - p->o[k];
            double n0 = a * p->ilo[k], n1 = a * p->ihi[k];
            double f0 = b * p->ilo[k], f1 = b * p->ihi[k];
            double near = n0 < n1 ? n0 : n1, far = (f0 > f1 ? f0 : f1) * BVH_WIDEN;
            t0 = near > t0 ? near : t0;
            t1 = far < t1 ? far : t1;
        }
        t0 *= BVH_SHRINK;
        t[c] = t0;
        if (t0 <= t1)
            mask |= 1u << c;
    }
    return mask;
}

#if BVH_HAVE_SIMD
/* The same operations, lane by lane, four children at a time (vminpd and
** vmaxpd are the comparisons above when nothing is NaN). */
BVH_AVX_TARGET ALWAYS_INLINE unsigned bvh_packet_test_avx(const bvh_node *nd,
                                                          const bvh_packet *p, double tmax,
                                                          double t[BVH_WIDTH])
{
    const __m256d widen = _mm256_set1_pd(BVH_WIDEN), shrink = _mm256_set1_pd(BVH_SHRINK);
    unsigned in = 0;
    for (int c = 0; c < BVH_WIDTH; c += 4) {
        __m256d t0 = _mm256_setzero_pd(), t1 = _mm256_set1_pd(tmax);
        for (int k = 0; k < 3; k++) {
            int g = p->neg[k];
            const float *nb = (g ? nd->hi[k] : nd->lo[k]) + c;
            const float *fb = (g ? nd->lo[k] : nd->hi[k]) + c;
            __m256d o = _mm256_set1_pd(p->o[k]);
            __m256d ilo = _mm256_set1_pd(p->ilo[k]), ihi = _mm256_set1_pd(p->ihi[k]);
            __m256d a = _mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(nb)), o);
            __m256d b = _mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(fb)), o);
            __m256d near = _mm256_min_pd(_mm256_mul_pd(a, ilo), _mm256_mul_pd(a, ihi));
            __m256d far = _mm256_max_pd(_mm256_mul_pd(b, ilo), _mm256_mul_pd(b, ihi));
            far = _mm256_mul_pd(far, widen);
            t0 = _mm256_max_pd(near, t0);
            t1 = _mm256_min_pd(far, t1);
        }
        t0 = _mm256_mul_pd(t0, shrink);
        _mm256_storeu_pd(t + c, t0);
        in |= (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(t0, t1, _CMP_LE_OQ)) << c;
        if (c + 4 >= (int)nd->n)         /* the rest are empty */
            break;
    }
    return in & ((1u << nd->n) - 1);
}
#else
#define bvh_packet_test_avx bvh_packet_test_scalar
#endif

#if BVH_HAVE_SIMD && BVH_WIDTH == 8
/* The same operations on all eight children at once. */
BVH_AVX512_TARGET ALWAYS_INLINE unsigned bvh_packet_test_avx512(const bvh_node *nd,
                                                                const bvh_packet *p,
                                                                double tmax,
                                                                double t[BVH_WIDTH])
{
    __m512d t0 = _mm512_setzero_pd(), t1 = _mm512_set1_pd(tmax);
    const __m512d widen = _mm512_set1_pd(BVH_WIDEN), shrink = _mm512_set1_pd(BVH_SHRINK);
    for (int k = 0; k < 3; k++) {
        int g = p->neg[k];
        const float *nb = g ? nd->hi[k] : nd->lo[k], *fb = g ? nd->lo[k] : nd->hi[k];
        __m512d o = _mm512_set1_pd(p->o[k]);
        __m512d ilo = _mm512_set1_pd(p->ilo[k]), ihi = _mm512_set1_pd(p->ihi[k]);
        __m512d a = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(nb)), o);
        __m512d b = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(fb)), o);
        __m512d near = _mm512_min_pd(_mm512_mul_pd(a, ilo), _mm512_mul_pd(a, ihi));
        __m512d far = _mm512_max_pd(_mm512_mul_pd(b, ilo), _mm512_mul_pd(b, ihi));
        far = _mm512_mul_pd(far, widen);
        t0 = _mm512_max_pd(near, t0);
        t1 = _mm512_min_pd(far, t1);
    }
    t0 = _mm512_mul_pd(t0, shrink);
    _mm512_storeu_pd(t, t0);
    unsigned in = (unsigned)_mm512_cmp_pd_mask(t0, t1, _CMP_LE_OQ);
    return in & ((1u << nd->n) - 1);
}
#else
#define bvh_packet_test_avx512 bvh_packet_test_scalar
#endif

#endif
