/* path.h: the path tracer (path.c), the integrator of renders with indirect > 0. */
#ifndef LC_PATH_H
#define LC_PATH_H

#include "tracer/tracer.h"

/* The radiance camera sample `index` of `count` of the pixel brings back by
** path tracing (LC_NEED_INDIRECT): shade_ray's counterpart, recording the
** rays while explaining and the AOVs with TRACE_AOV. */
radiance path_ray(tracer *t, const ray *r, uint32_t index, uint32_t count);

#endif
