/* surface.h: a textured material at a hit (surface.c). */
#ifndef LC_SURFACE_H
#define LC_SURFACE_H

#include "scene/scene.h"

/* Material m as it is at hit h: its textured fields evaluated into *out
** (returned), h->ns bent by its bump texture. m itself when the scene has
** no texture. */
const lc_material *surface_material(const lc_scene *s, hit *h, const lc_material *m,
                                    lc_material *out);

#endif
