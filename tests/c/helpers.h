/* helpers.h: what the C tests share: random draws, rays, tolerances, scratch folders. */
#ifndef LC_TEST_HELPERS_H
#define LC_TEST_HELPERS_H

/* Include after <cmocka.h> (near() reports through fail_msg). Every function
** is static inline, so a test that uses only some of them warns about none. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include "base/geom.h"

/* ---- Random draws --------------------------------------------------------- */

/* Knuth's MMIX LCG, the benchmark's generator (docs/bench-scenes.md, PRNG):
** each test seeds its own state, so its draws do not depend on the others. */
static inline double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005u + 1442695040888963407u;
    return (double)(*s >> 11) * 0x1p-53;            /* [0, 1) */
}

/* A unit vector, uniform over the sphere: rejection from the cube, away from
** the centre where normalising would lose digits. */
static inline lc_vec3 rand_unit(uint64_t *s)
{
    for (;;) {
        lc_vec3 a = v3(2 * lcg(s) - 1, 2 * lcg(s) - 1, 2 * lcg(s) - 1);
        double l = v3_dot(a, a);
        if (l <= 1 && l > 1e-4)
            return v3_mul(a, 1 / sqrt(l));
    }
}

/* A unit vector, uniform over the sphere, from its height z and its angle:
** two draws, no rejection. */
static inline lc_vec3 rand_sphere_dir(uint64_t *s)
{
    double z = 2 * lcg(s) - 1, a = 2 * 3.14159265358979323846 * lcg(s);
    double r = sqrt(1 - z * z);
    return v3(r * cos(a), r * sin(a), z);
}

/* ---- Rays and scenes -------------------------------------------------------- */

/* A ray with the direction as given (the caller vouches it is a unit vector). */
static inline ray mkray(lc_vec3 o, lc_vec3 d)
{
    ray r = {o, d};
    return r;
}

/* A ray towards d, normalised here. */
static inline ray mkray_unit(lc_vec3 o, lc_vec3 d)
{
    ray r = {o, v3_norm(d)};
    return r;
}

/* Where the translation-invariance case (docs/numerics.md H2) moves a scene
** by t: (t, t/2, t/3), so no coordinate is a round multiple of another. */
static inline lc_vec3 shift_of(double t) { return v3(t, t / 2, t / 3); }

/* ---- Checks ------------------------------------------------------------------ */

/* |got - want| <= tol, NaN failing; the message names the quantity. */
static inline void near(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: got %.17g, expected %.17g (off by %.3g > %.3g)", what, got, want,
                 fabs(got - want), tol);
}

/* ---- Scratch folders ----------------------------------------------------------- */

/* A fresh folder lancer-NAME-XXXXXX for files a test writes: in memory when
** there is a tmpfs, since every save syncs its file to disk. 0 when made. */
static inline int scratch_dir_make(char *dir, size_t size, const char *name)
{
    snprintf(dir, size, "%s/lancer-%s-XXXXXX",
             access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp", name);
    return mkdtemp(dir) ? 0 : -1;
}

/* Removes the folder and all in it. 0 when done. */
static inline int scratch_dir_remove(const char *dir)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

#endif
