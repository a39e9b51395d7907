/* test_sample.c: the per-pixel point sets: stratification, range, keys. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "base/sample.h"

#define KEYS 8

static pixel_sampler sampler(lc_sampler kind, int k)
{
    return sample_pixel(kind, 1234 + (uint64_t)k * 7919, (uint32_t)k, (uint64_t)k * 131);
}

/* Every elementary interval of area 2^-m (2^a x 2^(m-a) cells) holds
** exactly one of the first 2^m points: a (0, m, 2)-net, for every m up to
** 12, every key and several dimensions. That is what makes any power-of-two
** prefix stratified (progressive). */
static void sobol_prefixes_are_nets(void **state)
{
    (void)state;
    static unsigned char cell[1 << 12];
    for (int k = 0; k < KEYS; k++) {
        pixel_sampler ps = sampler(LC_SAMPLER_SOBOL, k);
        for (uint32_t dim = 0; dim < 3; dim++)
            for (int m = 0; m <= 12; m++) {
                uint32_t n = 1u << m;
                for (int a = 0; a <= m; a++) {
                    memset(cell, 0, n);
                    for (uint32_t i = 0; i < n; i++) {
                        double u[2];
                        sample_2d(&ps, sample_dim(DIM_CONE, dim, 0), i, n, u);
                        assert_true(u[0] >= 0 && u[0] < 1 && u[1] >= 0 && u[1] < 1);
                        uint32_t cx = (uint32_t)(u[0] * (1u << a));
                        uint32_t cy = (uint32_t)(u[1] * (1u << (m - a)));
                        cell[cx << (m - a) | cy]++;
                    }
                    for (uint32_t c = 0; c < n; c++)
                        assert_int_equal(cell[c], 1);
                }
            }
    }
}

/* A jittered set of k*k points puts one in each of the k x k cells; a set
** of any other size puts its points in distinct cells of the covering grid. */
static void jitter_fills_each_cell_once(void **state)
{
    (void)state;
    static unsigned char cell[64 * 64];
    for (int k = 0; k < KEYS; k++) {
        pixel_sampler ps = sampler(LC_SAMPLER_JITTER, k);
        for (uint32_t n = 1; n <= 300; n++) {
            uint32_t g = isqrt_ceil(n);
            assert_true(g * g >= n && (g - 1) * (g - 1) < n);
            memset(cell, 0, g * g);
            for (uint32_t i = 0; i < n; i++) {
                double u[2];
                sample_2d(&ps, sample_dim(DIM_PIXEL, 0, 0), i, n, u);
                assert_true(u[0] >= 0 && u[0] < 1 && u[1] >= 0 && u[1] < 1);
                cell[(uint32_t)(u[1] * g) * g + (uint32_t)(u[0] * g)]++;
            }
            uint32_t filled = 0;
            for (uint32_t c = 0; c < g * g; c++) {
                assert_true(cell[c] <= 1);
                filled += cell[c];
            }
            assert_int_equal(filled, n);
        }
    }
}

/* permute() is a bijection of [0, l) for any l and pattern. */
static void permute_is_a_bijection(void **state)
{
    (void)state;
    static unsigned char seen[5000];
    for (uint32_t l = 1; l < 5000; l += 37)
        for (uint32_t p = 0; p < 5; p++) {
            memset(seen, 0, l);
            for (uint32_t i = 0; i < l; i++) {
                uint32_t j = permute(i, l, p * 0x9e3779b9u);
                assert_true(j < l);
                assert_int_equal(seen[j], 0);
                seen[j] = 1;
            }
        }
}

/* The same (seed, frame, pixel, dimension, index) gives the same point;
** changing any one of them changes it. */
static void points_depend_on_every_key(void **state)
{
    (void)state;
    for (int kind = LC_SAMPLER_SOBOL; kind <= LC_SAMPLER_RANDOM; kind++) {
        double a[2], b[2];
        pixel_sampler p0 = sample_pixel((lc_sampler)kind, 7, 3, 99);
        pixel_sampler p1 = sample_pixel((lc_sampler)kind, 7, 3, 99);
        sample_2d(&p0, sample_dim(DIM_LIGHT, 1, 2), 5, 16, a);
        sample_2d(&p1, sample_dim(DIM_LIGHT, 1, 2), 5, 16, b);
        assert_true(a[0] == b[0] && a[1] == b[1]);
        pixel_sampler other[3] = {sample_pixel((lc_sampler)kind, 8, 3, 99),
                                  sample_pixel((lc_sampler)kind, 7, 4, 99),
                                  sample_pixel((lc_sampler)kind, 7, 3, 100)};
        for (int i = 0; i < 3; i++) {
            sample_2d(&other[i], sample_dim(DIM_LIGHT, 1, 2), 5, 16, b);
            assert_true(a[0] != b[0] || a[1] != b[1]);
        }
        sample_2d(&p0, sample_dim(DIM_LIGHT, 2, 2), 5, 16, b);    /* depth */
        assert_true(a[0] != b[0] || a[1] != b[1]);
        sample_2d(&p0, sample_dim(DIM_LIGHT, 1, 3), 5, 16, b);    /* emitter */
        assert_true(a[0] != b[0] || a[1] != b[1]);
    }
}

/* Dimensions are independent: the pixel and cone coordinates of the same
** samples do not correlate (the seed's duplicated reflections came from a
** cone pattern tied to the pixel). Pearson r over 4096 pixels x 16. */
static void dimensions_do_not_correlate(void **state)
{
    (void)state;
    for (int kind = LC_SAMPLER_SOBOL; kind <= LC_SAMPLER_RANDOM; kind++) {
        double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
        int n = 0;
        for (uint64_t px = 0; px < 4096; px++) {
            pixel_sampler ps = sample_pixel((lc_sampler)kind, 1, 0, px);
            for (uint32_t i = 0; i < 16; i++) {
                double a[2], b[2];
                sample_2d(&ps, sample_dim(DIM_PIXEL, 0, 0), i, 16, a);
                sample_2d(&ps, sample_dim(DIM_CONE, 0, 0), i, 16, b);
                sx += a[0], sy += b[0], sxx += a[0] * a[0], syy += b[0] * b[0];
                sxy += a[0] * b[0];
                n++;
            }
        }
        double cov = sxy / n - sx / n * sy / n;
        double r = cov / sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
        assert_true(fabs(r) < 0.02);
    }
}

/* sobol1 equals the textbook loop over the index bits with direction
** numbers v_k = v_(k-1) ^ (v_(k-1) >> 1), v_0 = 2^31. */
static void sobol1_matches_direction_numbers(void **state)
{
    (void)state;
    uint64_t x = 1;
    for (int n = 0; n < 200000; n++) {
        uint32_t i = n < 70000 ? (uint32_t)n : (uint32_t)(x = rng_mix(x));
        uint32_t r = 0, k = i;
        for (uint32_t v = 1u << 31; k; k >>= 1, v ^= v >> 1)
            if (k & 1)
                r ^= v;
        assert_int_equal(sobol1(i), r);
    }
}

/* The nested count saturates instead of wrapping. */
static void nested_counts_saturate(void **state)
{
    (void)state;
    assert_int_equal(sample_nested_count(16, 16), 256);
    assert_int_equal(sample_nested_count(1u << 20, 4096), 1u << 31);
    assert_int_equal(sample_nested_count(1, 1), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sobol_prefixes_are_nets),
        cmocka_unit_test(jitter_fills_each_cell_once),
        cmocka_unit_test(permute_is_a_bijection),
        cmocka_unit_test(points_depend_on_every_key),
        cmocka_unit_test(dimensions_do_not_correlate),
        cmocka_unit_test(nested_counts_saturate),
        cmocka_unit_test(sobol1_matches_direction_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
