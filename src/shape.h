/* shape.h: the shape kinds: each kind's prepared form and functions (one file
** per kind: sphere.c, quad.c, box.c, plane.c, triangle.c), and the dispatch
** over them (shape.c, which says what a new kind touches). */
#ifndef LC_SHAPE_H
#define LC_SHAPE_H

#include "geom.h"

/* ---- Primitive ids ----------------------------------------------------------- */

/* A primitive's id: its kind in the top 4 bits, its index in that kind's
** list. Ids order ties between equally near hits. Kind 15 is no kind
** (INTERSECT_SKIP_NONE). */
enum { PRIM_SPHERE, PRIM_QUAD, PRIM_BOX, PRIM_TRIANGLE, PRIM_PLANE,
       PRIM_INSTANCE,       /* a moved mesh: only in BVH refs, never in a hit */
       PRIM_KINDS };
#define PRIM_ID(kind, index) (((uint32_t)(kind) << 28) | (uint32_t)(index))
#define PRIM_KIND(id)        ((unsigned)((id) >> 28))
#define PRIM_INDEX(id)       ((id) & 0x0fffffffu)
#define PRIM_MAX             ((size_t)1 << 28)

/* Flat primitives: a ray leaving one can never meet it again. */
#define PRIM_FLAT ((1u << PRIM_QUAD) | (1u << PRIM_PLANE) | (1u << PRIM_TRIANGLE))
static inline int prim_flat(unsigned kind) { return (PRIM_FLAT >> kind) & 1; }

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
typedef struct {
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

/* ---- sphere.c ------------------------------------------------------------------- */

typedef struct {
    lc_vec3 c;
    double  r;
    double  r2;        /* r*r, or 0 when that under- or overflows: never hit */
    double  extent;    /* r + |c.x| + |c.y| + |c.z|: the scale of its rounding */
} sphere_geom;

/* What sampling a sphere light needs at one shaded point: the cone it subtends. */
typedef struct {
    lc_vec3 tc, axis;      /* centre - p, and its direction */
    double  dc;            /* |centre - p| */
    double  omc, solid;    /* 1 - cos of the cone's half-angle; its solid angle */
} sphere_light;

lc_status sphere_check(const lc_shape *s, lc_error *err);
void      sphere_prepare(const lc_shape *s, sphere_geom *g);
void      sphere_describe(const sphere_geom *g, lc_shape *s);
lc_status sphere_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                           lc_error *err);
void      sphere_scale(lc_shape *s, double k, lc_vec3 offset);
void      sphere_bounds(const sphere_geom *g, float lo[3], float hi[3]);
/* Each fills *h and returns 1 for the nearest hit with tmin < t < tmax,
** else returns 0 and leaves *h untouched; the *_t forms return the distance
** only (0 for a miss): enough to find the nearest hit, finished later. */
double    sphere_t(const sphere_geom *g, const ray *r, double tmin, double tmax);
int       sphere_hit(const sphere_geom *g, const ray *r, double tmin, double tmax,
                     hit *h);
double    sphere_light_centre(const sphere_geom *g, lc_vec3 l, double d);
int       sphere_light_begin(const sphere_geom *g, lc_vec3 p, lc_vec3 n, sphere_light *sl);
int       sphere_light_sample(const sphere_geom *g, const sphere_light *sl, lc_vec3 p,
                              const double u[2], uint32_t S, light_sample *out);

/* ---- quad.c ---------------------------------------------------------------------- */

typedef struct {
    lc_vec3 q, u, v;   /* corner, edges */
    lc_vec3 n;         /* u x v, not normalised */
    lc_vec3 w;         /* n / (n.n): the dual basis for (alpha, beta) */
    lc_vec3 un;        /* unit normal */
    double  k;         /* n.q */
    int     axis;      /* 0..2 when n is along an axis (exact snapping), else -1 */
} quad_geom;

typedef struct { double area; } quad_light;

lc_status quad_check(const lc_shape *s, lc_error *err);
void      quad_prepare(const lc_shape *s, quad_geom *g);
void      quad_describe(const quad_geom *g, lc_shape *s);
lc_status quad_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                         lc_error *err);
void      quad_scale(lc_shape *s, double k, lc_vec3 offset);
void      quad_bounds(const quad_geom *g, float lo[3], float hi[3]);
int       quad_hit(const quad_geom *g, const ray *r, double tmin, double tmax, hit *h);
/* inv: the ray's reciprocal direction (1/d per axis), or NULL to compute it. */
int       quad_hit_inv(const quad_geom *g, const ray *r, const double *inv, double tmin,
                       double tmax, hit *h);
double    quad_light_centre(const quad_geom *g, lc_vec3 l, double d);
int       quad_light_begin(const quad_geom *g, lc_vec3 p, quad_light *ql);
int       quad_light_sample(const quad_geom *g, const quad_light *ql, lc_vec3 p,
                            const double u[2], uint32_t S, light_sample *out);

/* ---- box.c ----------------------------------------------------------------------- */

typedef struct {
    lc_vec3 q;         /* corner */
    lc_vec3 e[3];      /* edges u, v, w */
    lc_vec3 row[3];    /* rows of the inverse edge matrix: local = row . (x - q) */
    lc_vec3 un[3];     /* unit outward normal of the face where local coord i = 1 */
    double  lo[3], hi[3];  /* axis-aligned boxes: exact face coordinates */
    int     aligned;   /* edges along the axes: slabs in world space, exact snaps */
} box_geom;

/* The faces of a box light that face the shaded point. */
typedef struct {
    lc_vec3 face[3][4];    /* corner, edge, edge, outward normal (not unit) */
    double  area[3], total;
    int     n;
} box_light;

lc_status box_check(const lc_shape *s, lc_error *err);
void      box_prepare(const lc_shape *s, box_geom *g);
void      box_describe(const box_geom *g, lc_shape *s);
lc_status box_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                        lc_error *err);
void      box_scale(lc_shape *s, double k, lc_vec3 offset);
void      box_bounds(const box_geom *g, float lo[3], float hi[3]);
int       box_hit(const box_geom *g, const ray *r, double tmin, double tmax, hit *h);
int       box_hit_inv(const box_geom *g, const ray *r, const double *inv, double tmin,
                      double tmax, hit *h);
double    box_t(const box_geom *g, const ray *r, const double *inv, double tmin,
                double tmax);
double    box_light_centre(const box_geom *g, lc_vec3 l, double d);
int       box_light_begin(const box_geom *g, lc_vec3 p, box_light *bl);
int       box_light_sample(const box_geom *g, const box_light *bl, lc_vec3 p,
                           const double u[2], uint32_t S, light_sample *out);

/* ---- plane.c (infinite: never in the BVH, never a light) -------------------------- */

typedef struct {
    lc_vec3 n;         /* unit normal */
    lc_vec3 p;         /* a point on it */
    double  k;         /* n.p */
    int     axis;      /* 0..2 when n is along an axis, else -1 */
} plane_geom;

lc_status plane_check(const lc_shape *s, lc_error *err);
void      plane_prepare(const lc_shape *s, plane_geom *g);
void      plane_describe(const plane_geom *g, lc_shape *s);
lc_status plane_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                          lc_error *err);
void      plane_scale(lc_shape *s, double k, lc_vec3 offset);
int       plane_hit(const plane_geom *g, const ray *r, double tmin, double tmax,
                    hit *h);
int       plane_hit_inv(const plane_geom *g, const ray *r, const double *inv,
                        double tmin, double tmax, hit *h);
/* Distance along r to the plane through p with unit normal n (axis >= 0:
** n is +-1 on that axis), or 0 for no hit in (tmin, tmax). inv: the ray's
** reciprocals or NULL. Inline: every ray meets every infinite plane. */
static inline double plane_distance(lc_vec3 n, lc_vec3 p, int axis, const ray *r,
                                    const double *inv, double tmin, double tmax)
{
    double t;
    if (axis >= 0) {
        /* Axis planes (walls, floors): one subtraction, exact when the
        ** origin is near the plane, so its side is never in doubt; then
        ** the ray's own reciprocal. A parallel ray gives inf or NaN. */
        double i = inv ? inv[axis] : 1.0 / v3_comp(r->d, axis);
        t = (v3_comp(p, axis) - v3_comp(r->o, axis)) * i;
    } else {
        double denom = v3_dot(n, r->d);
        if (denom == 0)    /* exactly parallel; no epsilon band near grazing */
            return 0;
        /* n.(p - o), not k - n.o: the difference comes first, so t keeps
        ** a few ulps of |p - o|, not of |o|. An origin on the plane within
        ** that rounding cannot tell its side: no hit (a camera on it). */
        lc_vec3 po = v3_sub(p, r->o);
        double num = v3_dot(n, po);
        double band = vec_gamma(4) * (fabs(n.x * po.x) + fabs(n.y * po.y) + fabs(n.z * po.z));
        if (!(fabs(num) > band))
            return 0;
        t = num / denom;
    }
    return t > tmin && t < tmax ? t : 0;   /* NaN and inf fail here */
}

/* Shared by plane and quad: puts p back onto the plane n.x = k. */
lc_vec3   plane_snap(lc_vec3 p, lc_vec3 n, double k, int axis, double axis_value,
                     lc_vec3 *perr);

static inline double plane_t(const plane_geom *g, const ray *r, const double *inv,
                             double tmin, double tmax)
{
    return plane_distance(g->n, g->p, g->axis, r, inv, tmin, tmax);
}

/* ---- triangle.c (mesh faces: meshes own their listing and moving) ----------------- */

/* Per-ray constants of the watertight triangle test. */
typedef struct {
    int    kx, ky, kz;
    double sx, sy, sz;
} triangle_shear;

void triangle_shear_init(lc_vec3 d, triangle_shear *s);
/* v0, v1, v2 point at 3 doubles each; fills bary with the weights of p. */
int  triangle_hit(const double *v0, const double *v1, const double *v2, const ray *r,
             const triangle_shear *s, double tmin, double tmax, hit *h, double bary[3]);
/* A face that can never be hit: zero area (or an area beyond double). */
int  triangle_degenerate(const double *a, const double *b, const double *c);
/* Bounds of a face: its vertices are exact doubles, rounded outward. */
void triangle_bounds(const double *a, const double *b, const double *c, float lo[3],
                float hi[3]);

/* ---- The dispatch (shape.c) --------------------------------------------------------- */

/* What one emitter needs at one shaded point, set by shape_light_begin. */
typedef union {
    sphere_light sphere;
    quad_light   quad;
    box_light    box;
} light_setup;

size_t    shape_geom_size(lc_shape_kind k);
unsigned  shape_prim_kind(lc_shape_kind k);
/* The shape kind of a primitive kind; LC_SHAPE_KINDS for a mesh's triangle. */
lc_shape_kind shape_kind_of_prim(unsigned prim_kind);
int       shape_bounded(lc_shape_kind k);           /* 0: tested one by one */
int       shape_can_emit(lc_shape_kind k);          /* 0: never a light */
void      shape_prepare(const lc_shape *s, void *geom);
void      shape_describe(lc_shape_kind k, const void *geom, lc_shape *out);
/* The shape scaled by k about the origin, then moved by offset. */
void      shape_scale(lc_shape *s, double k, lc_vec3 offset);
void      shape_bounds(lc_shape_kind k, const void *geom, float lo[3], float hi[3]);
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
