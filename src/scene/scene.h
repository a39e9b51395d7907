/* scene.h: the scene as described, and what compile derives for a render. */
#ifndef LC_SCENE_H
#define LC_SCENE_H

#include <pthread.h>
#include "base/affine.h"
#include "accel/bvh.h"
#include "lights.h"
#include "mesh.h"
#include "shapes/shape.h"

struct csg_tree;           /* csg.h: the scene holds pointers only */

/* xf == NULL: the mesh's triangles join the scene's own BVH as they are;
** else it is an instance: its own BVH, shared by every instance of it. */
typedef struct {
    lc_mesh *mesh;
    int material, id;
    affine *xf;
    uint32_t blas;         /* compile: its entry in the scene's mesh BVH cache */
    int     *palette;      /* slot k's material, or NULL: every face takes `material` */
    uint32_t npalette;
} mesh_prim;

/* The material of face f of mesh prim mp: its slot's, bounded however the
** mesh grew after it was added. */
static inline int mesh_face_material(const mesh_prim *mp, uint32_t f)
{
    if (!mp->palette)
        return mp->material;
    const lc_mesh *m = mp->mesh;
    uint32_t k = f < m->nslot ? m->slot[f] : 0;
    return mp->palette[k < mp->npalette ? k : 0];
}

/* A mesh's own BVH in object space, built once for every instance of it and
** kept across compiles until the mesh grows (instance.c). */
typedef struct {
    lc_mesh *mesh;         /* retained while cached */
    size_t   faces;        /* the mesh's face count when built */
    bvh      bvh;          /* over the non-degenerate faces; refs index `face` */
    uint32_t *face;        /* BVH ref k is face face[k] */
    size_t   nface, degenerate;
    float    lo[3], hi[3]; /* object-space bounds of the whole mesh */
    size_t   tri_base;     /* compile: face[k] is compiled.tris[tri_base + k] */
    int      used;         /* compile: some instance uses it */
} mesh_bvh;

/* One triangle of the compiled scene: which mesh, which face. The first
** nflat are traced in the scene's BVH; the rest list each instanced mesh's
** faces once, whatever its number of instances, so a hit on an instance
** names a triangle like any other. */
typedef struct { uint32_t mesh, face; } tri_ref;

/* A flat triangle as the BVH's leaves test it, in leaf order (beside
** bvh.refs): its mesh and its corners' vertex indices, so a leaf reads
** one entry next to its neighbours' instead of tris[] and the face list
** at two places far apart. Made after the build, whose items it outlives
** by less: no higher peak. */
typedef struct { uint32_t mesh, v[3]; } tri_leaf;

/* The sky's light for paths (sky.c): a tabulated distribution over an
** equirectangular image's texels, or none (w = 0: uniform over the sphere). */
typedef struct {
    int     w, h;
    double *row;           /* h + 1: cumulative weights of the rows, 0 to 1 */
    double *col;           /* h (w + 1): each row's cumulative weights, 0 to 1 */
    double *rowp;          /* h: each row's probability */
} sky_dist;

/* What one render reads and never writes. */
typedef struct {
    tri_ref *tris;
    size_t   ntris, degenerate;
    size_t   nflat;        /* tris[0, nflat) are in bvh; the rest are instances' */
    size_t   ninstances;   /* moved meshes, as BVH primitives */
    bvh      bvh;          /* over the bounded shapes, triangles and instances */
    tri_leaf *tleaf;       /* bvh.nrefs, in ref order: set where refs[i] is a triangle */
    unsigned needs;        /* LC_NEED_* */
    int      depth;        /* the render's max_depth: its own or the scene's */
    uint16_t *plan;        /* per material, PLAN_* below: decided once per render */
    int      sky_uv;       /* the background texture reads texture coordinates */
    int      sky_lights;   /* indirect: the background is not black, it lights */
    sky_dist sky;          /* indirect: how to sample it */
    char     why[LC_NEEDS][160];
    double   seconds;
    int      valid;        /* matches the scene as it is now */
    size_t   faces_seen;   /* total mesh faces when compiled: meshes may grow */
    int      depth_seen;
} compiled;

#define SCENE_ARRAY(type, name) type *name; size_t n##name, cap##name

struct lc_scene {
    pthread_mutex_t lock;          /* one render or explain at a time */
    lc_settings settings;
    lc_camera   camera;
    int         has_camera;
    size_t      nshapes;           /* shapes and meshes in the scene */
    int         next_id;           /* every add takes the next id */
    int        *light_ids;         /* lights[i] has id light_ids[i] */
    SCENE_ARRAY(mesh_bvh, blas);   /* instanced meshes' BVHs, kept across compiles */
    SCENE_ARRAY(lc_material, materials);
    lc_textures *textures;         /* NULL until the first lc_scene_add_texture */
    shape_list  shapes[LC_SHAPE_KINDS];   /* by kind, each sorted by id */
    SCENE_ARRAY(mesh_prim, meshes);
    SCENE_ARRAY(struct csg_tree *, csgs);  /* CSG objects (csg.h), sorted by id */
    SCENE_ARRAY(emitter, emitters);
    SCENE_ARRAY(lc_point_light, lights);
    SCENE_ARRAY(spot_light, spots);       /* spot lights ... */
    int        *spot_ids;                 /* ... and their ids, side by side */
    SCENE_ARRAY(sun_light, suns);         /* directional lights */
    int        *sun_ids;
    compiled    c;
};

/* What each material's shading does, so the per-hit code tests one bit per
** step instead of every coefficient (an effect no material in use needs is
** never reached). */
enum {
    PLAN_LIGHTS   = 1 << 0,   /* kd or ks > 0: the light loops */
    PLAN_SPECULAR = 1 << 1,   /* ks > 0 and specular on */
    PLAN_REFLECT  = 1 << 2,   /* kr or kt > 0 and reflections on */
    PLAN_AMBIENT  = 1 << 3,   /* ka > 0 and an ambient light */
    PLAN_EMITS    = 1 << 4,   /* emission > 0 */
    PLAN_GLOSSY   = 1 << 5,   /* kr or kt > 0 through a diffusion cone, and cones on */
    PLAN_REFRACT  = 1 << 6,   /* kt > 0 and max_depth > 0: a dielectric, a medium */
    PLAN_FILTER   = 1 << 7,   /* kt > 0 and shadow = filtered: shadow rays cross it */
    PLAN_TEXTURED = 1 << 8,   /* some field is a texture: evaluated at each hit */
    PLAN_AO       = 1 << 9    /* ambient light times the unoccluded share (ao) */
};

#endif
