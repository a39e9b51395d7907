/* compile.h: what a render reads, derived from the scene (compile.c). */
#ifndef LC_COMPILE_H
#define LC_COMPILE_H

#include <signal.h>
#include "scene.h"

/* The triangles and the BVH only, rebuilt when the geometry changed: what
** rays cast by the caller (query.c) need. */
lc_status compile_geometry(lc_scene *s, sig_atomic_t interrupts_seen, lc_error *err);
void      compile_free(compiled *c);
/* The flat triangles' corners in b's leaf order (c.tleaf for c.bvh), for
** a hierarchy over the scene's primitives; NULL when out of memory. */
tri_leaf *compile_tri_leaves(const lc_scene *s, const bvh *b);

#endif
