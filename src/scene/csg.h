/* csg.h: CSG objects as a scene stores them: the tree (csg.c: building,
** checks, bounds, the interval sweep) and its closed-mesh leaves
** (csg_mesh.c). */
#ifndef LC_CSG_H
#define LC_CSG_H

#include "base/affine.h"
#include "accel/bvh.h"
#include "shapes/box.h"
#include "shapes/placed.h"
#include "shapes/sphere.h"
#include "shapes/triangle.h"

/* ---- A crossing's sense and how far off it may be --------------------------------- */

/* Below this cosine between a ray and a surface the sign of d.n, whether
** the ray goes in or out, is not to be trusted: a tangent's two roots
** may come back as one, with either sign. Such a crossing is a graze: it
** never decides a leaf's inside (a near-tangent pair is a touch either
** way). The cosine is a ratio, free of scale; rays this close to tangent
** sweep a band 1e-16 of a radius wide around a silhouette. */
#define CSG_GRAZE_COS 1.4901161193847656e-08     /* sqrt(DBL_EPSILON) */

/* Hit h of a ray along unit d: *sense +1 going in (d.n < 0), -1 going out,
** 0 a graze; *e bounds the error of h->t: the point's error along the
** normal over the cosine (floored at CSG_GRAZE_COS), plus t's own rounding.
** Crossings of different leaves within each other's e are one event. */
static inline void csg_cross_sense(lc_vec3 d, const hit *h, int *sense, double *e)
{
    lc_vec3 n = h->n;
    double dn = v3_dot(d, n);
    double along = fabs(n.x) * h->perr.x + fabs(n.y) * h->perr.y + fabs(n.z) * h->perr.z;
    *sense = dn < -CSG_GRAZE_COS ? 1 : dn > CSG_GRAZE_COS ? -1 : 0;
    *e = along / max2(fabs(dn), CSG_GRAZE_COS) + vec_gamma(8) * h->t;
}

/* ---- csg_mesh.c: a closed mesh as a leaf ----------------------------------------- */

/* A mesh's faces as one CSG leaf sees them: a BVH over them in object space,
** built when added, shared by every leaf of the scene on that mesh with as
** many faces (reference-counted). */
/* A box as the BVH's nodes bound a child: floats rounded outward. */
typedef struct { float lo[3], hi[3]; } csg_box;

/* Where the ray enters box b before tmax, or HUGE_VAL: the BVH's own
** conservative slab test (bvh.h, bvh_test_scalar) on one box. */
static inline double csg_box_enter(const csg_box *b, const bvh_ray *q, double tmax)
{
    double t0 = 0, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        double a = ((double)b->lo[k] - q->o[k]) * q->inv[k];
        double c = ((double)b->hi[k] - q->o[k]) * q->inv[k];
        double near = q->neg[k] ? c : a, far = (q->neg[k] ? a : c) * BVH_WIDEN;
        t0 = near > t0 ? near : t0;
        t1 = far < t1 ? far : t1;
    }
    t0 *= BVH_SHRINK;
    return t0 <= t1 ? t0 : HUGE_VAL;
}

typedef struct csg_mesh {
    lc_mesh  *mesh;        /* retained */
    size_t    nf;          /* the faces it covers: those the mesh had when added */
    bvh       bvh;         /* over the non-degenerate faces; refs index `face` */
    uint32_t *face;
    size_t    nface;
    int       orient;      /* +1: the winding's normals point out; -1: in */
    double    lo[3], hi[3];    /* object-space bounds of its vertices */
    int       refs;
} csg_mesh;

/* Every edge in exactly two faces that run it opposite ways, and a volume:
** else LC_EARG naming the first edge at fault. Faces [0, nf). *orient, when
** not NULL, gets the winding's side (+1 out). */
lc_status csg_mesh_check(const lc_mesh *m, size_t nf, int *orient, lc_error *err);
/* Checks, then builds; NULL with err filled. */
csg_mesh *csg_mesh_new(lc_mesh *m, lc_error *err);
void      csg_mesh_release(csg_mesh *cm);          /* NULL is a no-op */

/* One crossing of a mesh leaf, as the sweep queues it: its hit is made only
** when it is the one reported (csg_mesh_hit). */
typedef struct {
    double   t, e;         /* distance; the bound of its error */
    int      sense;        /* +1 into the solid, -1 out, 0 a graze (unknown) */
    uint32_t k;            /* the BVH ref (face[k]) */
    double   bary[3];
} csg_mesh_cross;

/* A ray as a mesh leaf reads it: in object space when placed. */
typedef struct {
    ray    r;              /* d not unit when placed: t stays the world's */
    bvh_ray b;
    triangle_shear sh;
} csg_mesh_ray;

void   csg_mesh_ray_init(csg_mesh_ray *q, const affine *xf, const ray *r);
/* The crossings with after < t, nearest first: at most cap of them in out;
** returns how many, and *more = 1 when some beyond were left out (those at
** the last distance kept were dropped too, so none at one t is split).
** *tests counts the triangles tested, *nodes the BVH nodes. */
size_t csg_mesh_crossings(const csg_mesh *cm, const affine *xf, const csg_mesh_ray *q,
                          const ray *world, double after, csg_mesh_cross *out,
                          size_t cap, int *more, uint64_t *tests, uint64_t *nodes);
/* The world hit of crossing c: point, error bound, outward normal. */
void   csg_mesh_hit(const csg_mesh *cm, const affine *xf, const csg_mesh_cross *c,
                    hit *h);

/* ---- csg.c: the tree --------------------------------------------------------- */

/* A node of the stored tree, in the description's (prefix) order. */
typedef struct {
    lc_csg_op op;
    int      count;        /* operations: operands */
    int      end;          /* the index past its subtree */
    int      leaf0, leaf1; /* its leaves: [leaf0, leaf1) */
    int      group;        /* a union drawn as a group: the root's, and those under it */
    csg_box  box;          /* bounds, tight for intersections and
                           ** differences */
} csg_node;

typedef struct {
    int      node;         /* its index in the description */
    int      kind;         /* an lc_shape_kind; LC_SHAPE_KINDS for a mesh */
    int      material;
    int      convex;       /* a ray leaving it outward never meets it again */
    int      boxed;        /* slower to test than its box: the box goes first */
    int      cut_from;     /* the node whose leaves' material its cut faces take;
                           ** -1: its own */
    csg_box  box;          /* bounds */
    csg_mesh *mesh;        /* mesh leaves */
    affine   *xf;          /* mesh leaves: placed by it, or NULL */
    union { sphere_geom s; box_geom b; placed_geom p; } g;     /* shape leaves */
} csg_leaf;

typedef struct csg_tree {
    int          id;
    lc_csg_node *desc;     /* as added, shapes stored; meshes retained */
    size_t       n, nleaves, nmesh;
    csg_node    *nodes;
    csg_leaf    *leaves;
    int         *roots;    /* the subtrees swept on their own: the root, or the
                           ** operands of the group unions at the top */
    size_t       nroots;
    size_t       scratch;  /* bytes of a sweep's state */
} csg_tree;

/* Builds the tree for the description (checked with lc_csg_check first);
** shares mesh leaves with trees[0, ntrees). NULL with err filled. */
csg_tree *csg_build(const lc_csg_node *nodes, size_t n, csg_tree *const *trees,
                    size_t ntrees, lc_error *err);
void      csg_free(csg_tree *t);                   /* NULL is a no-op */
void      csg_bounds(const csg_tree *t, float lo[3], float hi[3]);
/* Sets used[m] for every material m of its leaves. */
void      csg_materials(const csg_tree *t, uint16_t *used);

/* The nearest surface of tree t in (0, tmax) along r (b: its slab form):
** its distance (0: none) with *h filled, its id PRIM_ID(PRIM_CSG_*, index).
** csg_occluded: whether the ray enters the solid before tmax. Both add
** their leaf tests to counts. */
double csg_hit(const csg_tree *t, uint32_t index, const ray *r, const bvh_ray *b,
               double tmax, hit *h, bvh_counts *counts);
int    csg_occluded(const csg_tree *t, const ray *r, const bvh_ray *b, double tmax,
                    bvh_counts *counts);
/* For explain: the leaf a hit on t names (its kind and node), in x; x->shape
** holds t's index among the scene's CSG objects. */
void   csg_name_hit(const csg_tree *t, const hit *h, lc_ray_record *x);
/* Of the leaf a hit on t is on: its kind (an lc_shape_kind, LC_SHAPE_KINDS
** for a mesh), and its texture coordinates there, the shape's own (0, 0 on
** a mesh leaf, whose faces carry none here). */
int    csg_hit_kind(const csg_tree *t, const hit *h);
void   csg_hit_uv(const csg_tree *t, const hit *h, double uv[2]);
/* The hit point in its leaf's own space: a moved shape's or a placed
** mesh's, else the world's (textures' 'object' mapping). */
lc_vec3 csg_hit_object_point(const csg_tree *t, const hit *h);

#endif
