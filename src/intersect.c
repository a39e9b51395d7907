/* intersect.c: nearest-hit and any-hit queries over a compiled scene. */
#include "scene.h"

/* Each kind in its own tight loop: one switch-free pass per kind. Ties in t
** keep the earlier shape (strict <), so the winner never depends on timing. */
int scene_closest(const compiled *c, const lc_ray *r, double tmax, lc_hit *h)
{
    int found = 0;
    uint32_t best = 0;
    lc_hit tmp;
#define CLOSEST(arr, n, fn)                                                  \
    for (size_t i = 0; i < (n); i++)                                         \
        if (fn(&(arr)[i].g, r, 0, tmax, &tmp) &&                             \
            (!found || tmp.t < h->t || (tmp.t == h->t && (arr)[i].shape < best))) { \
            *h = tmp;                                                        \
            h->shape = best = (arr)[i].shape;                                \
            h->material = (arr)[i].material;                                 \
            tmax = nextafter(tmp.t, HUGE_VAL);                               \
            found = 1;                                                       \
        }
    CLOSEST(c->spheres, c->nspheres, sphere_hit)
    CLOSEST(c->quads, c->nquads, quad_hit)
    CLOSEST(c->boxes, c->nboxes, box_hit)
    CLOSEST(c->planes, c->nplanes, plane_hit)
#undef CLOSEST
    return found;
}

int scene_occluded(const compiled *c, const lc_ray *r, double tmax)
{
    lc_hit tmp;
#define ANY(arr, n, fn)                                                      \
    for (size_t i = 0; i < (n); i++)                                         \
        if (fn(&(arr)[i].g, r, 0, tmax, &tmp))                               \
            return 1;
    ANY(c->spheres, c->nspheres, sphere_hit)
    ANY(c->quads, c->nquads, quad_hit)
    ANY(c->boxes, c->nboxes, box_hit)
    ANY(c->planes, c->nplanes, plane_hit)
#undef ANY
    return 0;
}
