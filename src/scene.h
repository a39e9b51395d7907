/* scene.h: the scene as described, and as compiled for one render. */
#ifndef LC_SCENE_H
#define LC_SCENE_H

#include "geom.h"

typedef struct { sphere_geom g; uint32_t shape; int material; } sphere_prim;
typedef struct { quad_geom g;   uint32_t shape; int material; } quad_prim;
typedef struct { box_geom g;    uint32_t shape; int material; } box_prim;
typedef struct { plane_geom g;  uint32_t shape; int material; } plane_prim;

/* An emissive shape used as a light (the seed's model): it lights a point
** when the ray toward `target` meets nothing before the emitter itself. */
typedef struct {
    uint32_t shape;
    lc_shape_kind kind;
    lc_vec3  target;     /* sphere centre, quad or box centre */
    double   radius;     /* sphere */
    lc_vec3  area[3];    /* quad: u x v; box: v x w, w x u, u x v (projected area) */
    lc_color emission;
} emitter;

/* The compiled frame: everything the render loop reads, nothing it writes. */
typedef struct {
    sphere_prim *spheres; size_t nspheres;
    quad_prim   *quads;   size_t nquads;
    box_prim    *boxes;   size_t nboxes;
    plane_prim  *planes;  size_t nplanes;
    emitter     *emitters; size_t nemitters;
    unsigned     needs;   /* LC_NEED_* */
} compiled;

struct lc_scene {
    lc_settings     settings;
    lc_camera       camera;
    int             has_camera;
    lc_material    *materials; size_t nmaterials, capmaterials;
    lc_shape       *shapes;    size_t nshapes, capshapes;
    int            *shape_material;
    lc_point_light *lights;    size_t nlights, caplights;
    compiled        c;
};

lc_status scene_compile(lc_scene *s, int max_depth_override, lc_error *err);
void      compiled_free(compiled *c);

/* Nearest hit with 0 < t < tmax; 1 if any. */
int scene_closest(const compiled *c, const lc_ray *r, double tmax, lc_hit *h);
/* 1 if anything lies on the ray with 0 < t < tmax. */
int scene_occluded(const compiled *c, const lc_ray *r, double tmax);

#endif
