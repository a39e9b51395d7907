/* sample.h: the points each pixel's samples use in every 2D dimension. */
#ifndef LC_SAMPLE_H
#define LC_SAMPLE_H

#include <math.h>
#include "lancer.h"
#include "rng.h"
#include "vec.h"

/* A pixel's sample set is keyed by (seed, frame, pixel); inside it, each 2D
** dimension (pixel area, lens, the cone at depth d, emitter e at depth d...)
** is a separate, independently scrambled point set, so dimensions never
** correlate (docs/numerics.md 1.11: no duplicated reflections). Point `index` of
** `count` is the sample's place in that set: camera sample s of N is index
** s of N; cone or light sample j of M taken by camera sample s is index
** s*M + j of N*M, so all N*M points of the pixel are stratified together. */
typedef struct {
    uint64_t   key;        /* seed, frame and pixel, mixed */
    lc_sampler kind;
} pixel_sampler;

/* The purposes of 2D dimensions, combined with depth and emitter below. */
enum { DIM_PIXEL, DIM_LENS, DIM_CONE, DIM_LIGHT, DIM_BSDF, DIM_PATH, DIM_AO };

static inline uint32_t sample_dim(unsigned purpose, unsigned depth, unsigned which)
{
    return (uint32_t)purpose << 28 ^ (uint32_t)depth << 16 ^ (uint32_t)which;
}

static inline pixel_sampler sample_pixel(lc_sampler kind, uint64_t seed,
                                               uint32_t frame, uint64_t pixel)
{
    pixel_sampler ps;
    ps.key = rng_mix(seed ^ rng_mix((uint64_t)frame ^ rng_mix(pixel)));
    ps.kind = kind;
    return ps;
}

/* ---- Owen-scrambled Sobol' (Burley, Practical Hash-based Owen Scrambling,
** JCGT 9(4), 2020): the first two Sobol' dimensions, each scrambled by a
** nested uniform (Owen) scramble, with the index itself shuffled the same
** way so every dimension pair is an independent (0, 2)-sequence. Any prefix
** of 2^k points is stratified in every dyadic box of area 2^-k, which makes
** it progressive: adaptive sampling can stop after any power of two. */

static inline uint32_t reverse_bits(uint32_t x)
{
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    return x;
}

/* A hash in which each bit depends only on the bits below it
** (psychopath.io's improved Laine-Karras permutation, 2021): applied to
** reversed bits it is an Owen scramble, a nested uniform scramble of the
** bits from the top. */
static inline uint32_t lk_hash(uint32_t x, uint32_t seed)
{
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

static inline uint32_t owen_scramble(uint32_t x, uint32_t seed)
{
    return reverse_bits(lk_hash(reverse_bits(x), seed));
}

/* The second Sobol' dimension (polynomial x + 1) in reversed bit order:
** its direction numbers are the rows of Pascal's triangle mod 2, so bit m
** of the reversed point is the parity of the index bits k whose positions
** contain m (Lucas: C(k, m) is odd iff m's bits are a subset of k's). That
** superset parity takes five shift-and-xor steps instead of a loop over 32
** bits, which the shuffled (full-width) indices would always run. */
static inline uint32_t sobol1_reversed(uint32_t i)
{
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return i;
}

static inline uint32_t sobol1(uint32_t i) { return reverse_bits(sobol1_reversed(i)); }

#define U32_TO_01 (1.0 / 4294967296.0)       /* [0, 1): never 1 */

/* The first Sobol' dimension is the index with its bits reversed, so each
** scrambled coordinate is reverse(hash(reverse(reverse(...)))): the inner
** reversals cancel, four are left of the eight written out. */
static inline void sobol_2d(uint32_t index, uint64_t key, double out[2])
{
    uint32_t seed = (uint32_t)key, s1 = (uint32_t)(key >> 32);
    index = owen_scramble(index, seed);
    out[0] = reverse_bits(lk_hash(index, s1)) * U32_TO_01;
    out[1] = reverse_bits(lk_hash(sobol1_reversed(index), s1 ^ 0x9e3779b9u)) * U32_TO_01;
}

/* ---- Jittered grid: a k x k grid (k = ceil(sqrt(count))) with one point
** per cell; when count is not a square, the points take count distinct
** cells, chosen by a per-set permutation (Kensler, Correlated Multi-Jittered
** Sampling, 2013: permute() works for any length). */
static inline uint32_t permute(uint32_t i, uint32_t l, uint32_t p)
{
    uint32_t w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    do {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i *= 0x0929eb3fu;
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i *= 1 | p >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= l);
    return (i + p) % l;
}

static inline uint32_t isqrt_ceil(uint32_t n)
{
    uint32_t k = (uint32_t)sqrt((double)n);
    while (k * k < n)
        k++;
    while (k > 1 && (k - 1) * (k - 1) >= n)
        k--;
    return k;
}

/* The largest double below 1: sums that round up to 1 are pulled back. */
#define BELOW_ONE 0x1.fffffffffffffp-1

/* Point `index` of `count` (index < count <= 2^31) of dimension `dim`. */
static inline void sample_2d(const pixel_sampler *ps, uint32_t dim, uint32_t index,
                             uint32_t count, double out[2])
{
    uint64_t key = rng_mix(ps->key ^ rng_mix(dim));
    switch (ps->kind) {
    case LC_SAMPLER_SOBOL:
        sobol_2d(index, key, out);
        return;
    case LC_SAMPLER_JITTER: {
        uint32_t k = isqrt_ceil(count);             /* <= 46341: k*k fits */
        uint32_t cell = permute(index, k * k, (uint32_t)key);
        out[0] = fmin((cell % k + rng_u01(key, 0, index, 0)) / k, BELOW_ONE);
        out[1] = fmin((cell / k + rng_u01(key, 0, index, 1)) / k, BELOW_ONE);
        return;
    }
    default:
        out[0] = rng_u01(key, 0, index, 0);
        out[1] = rng_u01(key, 0, index, 1);
        return;
    }
}

/* The count of a nested set, kept within what sample_2d takes. */
static inline uint32_t sample_nested_count(uint32_t outer, uint32_t inner)
{
    uint64_t n = (uint64_t)outer * inner;
    return n > (1u << 31) ? 1u << 31 : (uint32_t)n;
}

/* ---- Directions from points of the unit square ---------------------------------- */

/* An orthonormal frame around unit a, without a singular direction (Duff et
** al., Building an Orthonormal Basis, Revisited, JCGT 2017). */
static inline void sample_frame(lc_vec3 a, lc_vec3 *b1, lc_vec3 *b2)
{
    double sg = copysign(1.0, a.z), k = -1 / (sg + a.z), b = a.x * a.y * k;
    *b1 = v3(1 + sg * a.x * a.x * k, sg * b, -sg * a.x);
    *b2 = v3(b, sg + a.y * a.y * k, -a.y);
}

/* A direction uniform in solid angle inside the cone of unit axis a whose
** half-angle has 1 - cos = omc (passed as such: no cancellation for tiny
** cones; docs/numerics.md 1.11). */
static inline lc_vec3 sample_cone(lc_vec3 a, double omc, const double u[2])
{
    double one_minus = u[0] * omc, c = 1 - one_minus;
    double sn = sqrt(fmax(0, one_minus * (2 - one_minus)));
    double phi = 2 * PI * u[1];
    lc_vec3 b1, b2;
    sample_frame(a, &b1, &b2);
    return v3_norm(v3_madd(v3_madd(v3_mul(a, c), b1, sn * cos(phi)), b2, sn * sin(phi)));
}

#endif
