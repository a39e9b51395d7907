/* scene.h: the scene as described, and what compile derives for a render. */
#ifndef LC_SCENE_H
#define LC_SCENE_H

#include "bvh.h"
#include "geom.h"
#include "mesh.h"

/* A primitive's id: its kind in the top 3 bits, its index in that kind's
** array below. Ids order ties between equally near hits. */
enum { PRIM_SPHERE, PRIM_QUAD, PRIM_BOX, PRIM_TRIANGLE, PRIM_PLANE };
#define PRIM_ID(kind, index) (((uint32_t)(kind) << 29) | (uint32_t)(index))
#define PRIM_KIND(id)        ((unsigned)((id) >> 29))
#define PRIM_INDEX(id)       ((id) & 0x1fffffffu)
#define PRIM_MAX             ((size_t)1 << 29)

/* Shapes are prepared when added: the render reads them as they are. */
typedef struct { sphere_geom g; int material; } sphere_prim;
typedef struct { quad_geom g;   int material; } quad_prim;
typedef struct { box_geom g;    int material; } box_prim;
typedef struct { plane_geom g;  int material; } plane_prim;
typedef struct { lc_mesh *mesh; int material; } mesh_prim;

/* One triangle of the compiled scene: which mesh, which face. */
typedef struct { uint32_t mesh, face; } tri_ref;

/* An emissive shape used as a light (the seed's model): it lights a point
** when the ray toward `target` meets nothing before the emitter itself. */
typedef struct {
    uint32_t shape;      /* PRIM_ID */
    lc_shape_kind kind;
    lc_vec3  target;     /* sphere centre, quad or box centre */
    double   radius;     /* sphere */
    lc_vec3  corner;     /* quad and box: as given */
    lc_vec3  edge[3];    /* quad: u, v; box: u, v, w */
    lc_vec3  area[3];    /* quad: u x v; box: v x w, w x u, u x v (projected area) */
    lc_color emission;
} emitter;

/* What one render reads and never writes. */
typedef struct {
    tri_ref *tris;
    size_t   ntris, degenerate;
    bvh      bvh;          /* over spheres, quads, boxes and triangles */
    unsigned needs;        /* LC_NEED_* */
    int      depth;        /* the render's max_depth: its own or the scene's */
    unsigned char *plan;   /* per material, PLAN_* below: decided once per render */
    char     why[LC_NEEDS][160];
    double   seconds;
    int      valid;        /* matches the scene as it is now */
    size_t   faces_seen;   /* total mesh faces when compiled: meshes may grow */
    int      depth_seen;
} compiled;

#define SCENE_ARRAY(type, name) type *name; size_t n##name, cap##name

struct lc_scene {
    lc_settings settings;
    lc_camera   camera;
    int         has_camera;
    size_t      nshapes;           /* shapes and meshes added, for ids */
    SCENE_ARRAY(lc_material, materials);
    SCENE_ARRAY(sphere_prim, spheres);
    SCENE_ARRAY(quad_prim, quads);
    SCENE_ARRAY(box_prim, boxes);
    SCENE_ARRAY(plane_prim, planes);
    SCENE_ARRAY(mesh_prim, meshes);
    SCENE_ARRAY(emitter, emitters);
    SCENE_ARRAY(lc_point_light, lights);
    compiled    c;
};

/* What each material's shading does, so the per-hit code tests one bit per
** step instead of every coefficient (an effect no material in use needs is
** never reached). */
enum {
    PLAN_LIGHTS   = 1 << 0,   /* kd or ks > 0: the light loops */
    PLAN_SPECULAR = 1 << 1,   /* ks > 0 and specular on */
    PLAN_REFLECT  = 1 << 2,   /* kr > 0 and reflections on */
    PLAN_AMBIENT  = 1 << 3,   /* ka > 0 and an ambient light */
    PLAN_EMITS    = 1 << 4,   /* emission > 0 */
    PLAN_GLOSSY   = 1 << 5    /* kr > 0 through a diffusion cone, and cones on */
};

/* o: the render's switches, or NULL for the defaults. */
lc_status scene_compile(lc_scene *s, const lc_render_options *o, lc_error *err);
void      compiled_free(compiled *c);
int       render_depth(const lc_scene *s, const lc_render_options *o);
lc_mesh  *mesh_retain(lc_mesh *m);

/* Intersection work, counted per thread: primitive and BVH node tests. */
typedef struct { uint64_t prims, nodes; } lc_counts;

/* Nearest hit with 0 < t < tmax; 1 if any. counts may be NULL. */
int scene_closest_n(const lc_scene *s, const lc_ray *r, double tmax, lc_hit *h,
                    lc_counts *counts);
/* 1 if anything lies on the ray with 0 < t < tmax. counts may be NULL. */
int scene_occluded_n(const lc_scene *s, const lc_ray *r, double tmax, lc_counts *counts);
#define scene_closest(s, r, tmax, h) scene_closest_n((s), (r), (tmax), (h), NULL)
#define scene_occluded(s, r, tmax)   scene_occluded_n((s), (r), (tmax), NULL)

#endif
