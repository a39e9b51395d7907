/* instance.h: moved meshes, their BVHs and the rays through them (instance.c). */
#ifndef LC_INSTANCE_H
#define LC_INSTANCE_H

#include <signal.h>
#include "accel/bvh.h"
#include "base/geom.h"

/* Builds (or reuses) the BVH of every instanced mesh, one for all its
** placements, kept in the scene's cache, and lists their faces after the
** flat triangles in c->tris (room for instance_faces(s) more entries must
** be there). */
size_t    instance_faces(const lc_scene *s);
lc_status instance_compile(lc_scene *s, sig_atomic_t interrupts_seen, lc_error *err);
void      instance_free_all(lc_scene *s);            /* the cache, at scene free */
/* World bounds of mesh_prim i, an instance, rounded outward to float. */
void      instance_bounds(const lc_scene *s, size_t i, float lo[3], float hi[3]);

/* The nearest hit on the instance mesh_prim i in (0, tmax), in world space
** (its distance, 0 for none); any hit. Both count their tests. */
double instance_hit(const lc_scene *s, uint32_t i, const ray *r, double tmax,
                    hit *h, bvh_counts *counts);
int    instance_occluded(const lc_scene *s, uint32_t i, const ray *r, double tmax,
                         bvh_counts *counts);

#endif
