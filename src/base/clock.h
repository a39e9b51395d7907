/* clock.h: monotonic seconds, for the render's phases and the progress bar. */
#ifndef LC_CLOCK_H
#define LC_CLOCK_H

#include <time.h>

static inline double clock_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

#endif
