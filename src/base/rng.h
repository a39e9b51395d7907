/* rng.h: random numbers keyed by (seed, pixel, sample, dimension), never by
** a shared stream, so thread count and tile order cannot change a pixel. */
#ifndef LC_RNG_H
#define LC_RNG_H

#include <stdint.h>

static inline uint64_t rng_mix(uint64_t z)      /* splitmix64's finaliser */
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* A double in [0, 1), never 1: a pdf must not see the boundary. */
static inline double rng_u01(uint64_t seed, uint64_t pixel, uint32_t sample, uint32_t dim)
{
    uint64_t h = rng_mix(seed ^ rng_mix(pixel ^ rng_mix(((uint64_t)sample << 32) | dim)));
    return (double)(h >> 11) * (1.0 / 9007199254740992.0);
}

#endif
