/* shape.h: the shape kinds' shared part: the primitive ids, emissive shapes
** as lights (emitter, light_sample, light_setup), and the dispatch over the
** kinds (shape.c, which lists what a new kind touches). Each kind's prepared
** form and functions are in its own header: sphere.h, quad.h, box.h,
** plane.h, triangle.h, and placed.h with disc.h, cylinder.h, cone.h,
** torus.h and ellipsoid.h. */
#ifndef LC_SHAPE_H
#define LC_SHAPE_H

#include "lancer.h"
#include "box.h"
#include "quad.h"
#include "sphere.h"

/* ---- Primitive ids ----------------------------------------------------------- */

/* A primitive's id: its kind in the top PRIM_KIND_BITS bits, its index in
** that kind's list below them. Ids order ties between equally near hits.
** Kind PRIM_NONE (all bits set) is no kind: INTERSECT_SKIP_NONE
** (intersect.h), every bit of the id set, names no primitive. 5 bits hold
** 31 kinds besides it; each kind holds at most PRIM_MAX = 2^27 primitives
** (the triangles of a scene too). The BVH weighs an item by the same top
** bits (bvh.h, BVH_KIND_SHIFT; shape.c checks that they agree). */
enum { PRIM_SPHERE, PRIM_QUAD, PRIM_BOX, PRIM_TRIANGLE, PRIM_PLANE,
       PRIM_INSTANCE,       /* a moved mesh: only in BVH refs, never in a hit */
       PRIM_DISC, PRIM_CYLINDER, PRIM_CONE, PRIM_TORUS, PRIM_ELLIPSOID,
       PRIM_CSG,            /* a CSG object (csg.h): only in BVH refs, never in a hit */
       PRIM_CSG_FACE,       /* a hit on a CSG object's convex leaf, its normal the
                            ** leaf's: leaving outward, a ray never meets that leaf */
       PRIM_CSG_CUT,        /* any other CSG hit (cut faces, concave leaves) */
       PRIM_KINDS };
#define PRIM_KIND_BITS       5
#define PRIM_SHIFT           (32 - PRIM_KIND_BITS)
#define PRIM_NONE            ((1u << PRIM_KIND_BITS) - 1)    /* no kind */
#define PRIM_ID(kind, index) (((uint32_t)(kind) << PRIM_SHIFT) | (uint32_t)(index))
#define PRIM_KIND(id)        ((unsigned)((id) >> PRIM_SHIFT))
#define PRIM_INDEX(id)       ((id) & ((1u << PRIM_SHIFT) - 1))
#define PRIM_MAX             ((size_t)1 << PRIM_SHIFT)

/* Flat primitives: a ray leaving one can never meet it again. */
#define PRIM_FLAT ((1u << PRIM_QUAD) | (1u << PRIM_PLANE) | (1u << PRIM_TRIANGLE) | \
                   (1u << PRIM_DISC))
static inline int prim_flat(unsigned kind) { return (PRIM_FLAT >> kind) & 1; }
/* Not convex: a ray leaving one outward may meet it again, legitimately.
** A CSG hit names the object and (in hit.instance) the leaf. */
#define PRIM_CONCAVE ((1u << PRIM_TORUS) | (1u << PRIM_CSG) | (1u << PRIM_CSG_CUT))
static inline int prim_cannot_return(unsigned kind, int outward)
{
    return prim_flat(kind) || (outward && !((PRIM_CONCAVE >> kind) & 1));
}

/* ---- Emissive shapes as lights ------------------------------------------------- */

/* An emissive shape, set up when it is added: the seed's model aims one
** shadow ray at `target`; sampled, it is an area light. */
typedef struct {
    lc_shape_kind kind;
    uint32_t index;        /* in the scene's list of that kind */
    uint32_t prim;         /* its PRIM_ID: a hit on it is a hit on the light */
    lc_vec3  target;
    lc_color emission;
} emitter;

/* One point (or direction) sampled on an emitter, seen from a shaded point. */
typedef struct light_sample {
    lc_vec3 l;             /* unit direction toward it */
    double  dist;          /* its distance: the shadow ray stops just short */
    double  k;             /* its share: the solid angle it stands for over pi S,
                           ** so that the light adds emission k cos */
} light_sample;

/* Quads and boxes move exactly under any affine map: the corner is a point,
** the edges (u, v, w; zero where unused) vectors. */
static inline void shape_move_edges(const lc_transform *t, const lc_shape *s, lc_shape *out)
{
    *out = *s;
    out->p = lc_transform_point(t, s->p);
    out->u = lc_transform_vector(t, s->u);
    out->v = lc_transform_vector(t, s->v);
    out->w = lc_transform_vector(t, s->w);
}

/* ---- The dispatch (shape.c) --------------------------------------------------------- */

/* What one emitter needs at one shaded point, set by shape_light_begin. */
typedef union {
    sphere_light sphere;
    quad_light   quad;
    box_light    box;
} light_setup;

/* What a leaf test of each primitive kind costs, by PRIM_KIND (PRIM_NONE's
** too), in units of a sphere test: the BVH's surface area heuristic
** (bvh_build_costed) weighs each item by it. */
extern const float shape_prim_cost[PRIM_NONE + 1];

size_t    shape_geom_size(lc_shape_kind k);
unsigned  shape_prim_kind(lc_shape_kind k);
/* The shape kind of a primitive kind; LC_SHAPE_KINDS for a mesh's triangle. */
lc_shape_kind shape_kind_of_prim(unsigned prim_kind);
int       shape_bounded(lc_shape_kind k);           /* 0: tested one by one */
int       shape_can_emit(lc_shape_kind k);          /* 0: never a light */
void      shape_prepare(const lc_shape *s, void *geom);
/* What an emitter needs beyond shape_prepare: a placed shape's world area
** (4096 patches of a parametric integral for the curved kinds: 0.13 ms a
** cylinder, paid only by the shapes that glow). */
void      shape_prepare_emitter(lc_shape_kind k, void *geom);
void      shape_describe(lc_shape_kind k, const void *geom, lc_shape *out);
/* The shape scaled by k about the origin, then moved by offset. */
void      shape_scale(lc_shape *s, double k, lc_vec3 offset);
void      shape_bounds(lc_shape_kind k, const void *geom, float lo[3], float hi[3]);
/* Texture coordinates of the point p on the shape. */
void      shape_uv(lc_shape_kind k, const void *geom, lc_vec3 p, double uv[2]);
/* The seed's model: where its one shadow ray aims, and for a point at
** distance d along unit l from that target the irradiance over pi L. */
lc_vec3   shape_light_target(lc_shape_kind k, const void *geom);
double    shape_light_centre(lc_shape_kind k, const void *geom, lc_vec3 l, double d);
/* Sampled: 0 when the shape lights nothing at p (p on or inside it, in its
** plane, or it lies wholly below the horizon of n); then sample u of S,
** 0 when that one adds nothing. */
int       shape_light_begin(lc_shape_kind k, const void *geom, lc_vec3 p, lc_vec3 n,
                            light_setup *ls);
int       shape_light_sample(lc_shape_kind k, const void *geom, const light_setup *ls,
                             lc_vec3 p, const double u[2], uint32_t S, light_sample *out);
/* For MIS with BSDF sampling: the density a sample of S = 1 gave direction
** d from p (normal n) to the point at distance dist on the shape, -1 where
** the kind's density is not known (shape_light_mis 0: its samples take all
** the weight). */
double    shape_light_pdf(lc_shape_kind k, const void *geom, lc_vec3 p, lc_vec3 n,
                          lc_vec3 d, double dist);
int       shape_light_mis(lc_shape_kind k);

/* ---- A scene's shapes of one kind ----------------------------------------------------- */

/* Prepared when added: the render reads them as they are. id[i] is what
** lc_scene_add_* returned (ids grow with each add, so the list is sorted by
** id). */
typedef struct {
    unsigned char *geom;   /* n prepared shapes, size bytes each */
    int    *material, *id;
    size_t  size, n, cap;
} shape_list;

static inline const void *shape_at(const shape_list *l, size_t i)
{
    return l->geom + i * l->size;
}

#endif
