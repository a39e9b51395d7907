/* intersect.h: rays against a compiled scene, nearest or any hit (intersect.c). */
#ifndef LC_INTERSECT_H
#define LC_INTERSECT_H

#include "accel/bvh.h"
#include "base/geom.h"

/* Nearest hit with 0 < t < tmax; 1 if any. counts may be NULL. */
int intersect_closest(const lc_scene *s, const ray *r, double tmax, hit *h,
                    bvh_counts *counts);
/* intersect_closest for rays r[0, n) (n <= BVH_PACKET, bvh_packet.h), each
** with its own tmax, uncounted: found[i] and h[i] as it gives for r[i],
** the same bits. Rays whose directions share their signs walk the BVH
** together, each leaf tested by the rays that meet its box. */
void intersect_closest_n(const lc_scene *s, const ray *r, const double *tmax, int n, hit *h,
                         int *found);
/* 1 if anything lies on the ray with 0 < t < tmax. counts may be NULL. */
int intersect_occluded(const lc_scene *s, const ray *r, double tmax, bvh_counts *counts);
/* The same for rays r[0, n) (n <= BVH_PACKET), uncounted, into blocked[],
** walked together as intersect_closest_n's. */
void intersect_occluded_n(const lc_scene *s, const ray *r, const double *tmax, int n,
                          int *blocked);
/* intersect_occluded, but primitive `skip` (a PRIM_ID, never a plane) is not there:
** a shadow ray toward a point sampled on an emitter cannot be blocked by
** that emitter, whatever the rounding of its own surface. */
int intersect_occluded_skip(const lc_scene *s, const ray *r, double tmax, uint32_t skip,
                        bvh_counts *counts);
/* Every bit set: kind PRIM_NONE (shape.h), the one no primitive has. */
#define INTERSECT_SKIP_NONE 0xffffffffu
/* The texture coordinates of a hit intersect_closest found: computed only
** when asked (a scene without textures never pays for them). */
void intersect_uv(const lc_scene *s, const hit *h, double uv[2]);

#endif
