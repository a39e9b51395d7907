/* query.h: the object a hit is on, for the rest of the core (query.c). */
#ifndef LC_QUERY_H
#define LC_QUERY_H

#include "base/geom.h"

/* The id lc_scene_add_* gave the object a hit is on. */
int scene_object_id(const lc_scene *s, const hit *h);

#endif
