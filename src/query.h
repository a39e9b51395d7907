/* query.h: what query.c gives the rest of the core besides the public
** lc_scene_intersect and lc_scene_occluded (lancer.h). */
#ifndef LC_QUERY_H
#define LC_QUERY_H

#include "geom.h"

/* The id lc_scene_add_* gave the object a hit is on. */
int scene_object_id(const lc_scene *s, const hit *h);

#endif
