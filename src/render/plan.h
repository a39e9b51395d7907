/* plan.h: the render layer: the effects a frame needs, why, and each
** material's shading plan. */
#ifndef LC_PLAN_H
#define LC_PLAN_H

#include <signal.h>
#include "scene/scene.h"

/* What a render of s with options o (NULL: the defaults) reads: the
** geometry (compile_geometry, which stops with LC_ECANCEL once
** interrupt_count() differs from interrupts_seen), then the plan, and the
** sky's distribution when paths sample it; its time in s->c.seconds. */
lc_status plan_scene(lc_scene *s, const lc_render_options *o,
                     sig_atomic_t interrupts_seen, lc_error *err);

#endif
