/* query.c: rays cast by the caller (lc_scene_intersect, lc_scene_occluded):
** the scene's geometry without shading. */
#include "base/error.h"
#include "base/interrupt.h"
#include "scene.h"
#include "base/validate.h"
#include "accel/bvh_packet.h"
#include "compile.h"
#include "intersect.h"
#include "query.h"
#include "csg.h"

static int object_of(const lc_scene *s, const hit *h, int *kind, long *primitive);

#define POLL 4096     /* rays between looks at lc_interrupt() */

/* The caller's ray as the tracer takes it: a unit direction from the start
** of the interval; *len is |d|, so the caller's t is tmin + t' / len. */
typedef struct {
    ray    r;
    double tmax, len;
} cast;

static lc_status check_ray(const lc_ray *q, size_t i, lc_error *err)
{
    lc_error e;
    if (validate_vec(q->origin, "origin", &e) || validate_nonzero(q->direction, "direction", &e))
        return error_fail(err, LC_EARG, "rays", "ray %zu: %s %s", i + 1, e.field, e.msg);
    if (!(q->tmin >= 0 && q->tmin < q->tmax) || isnan(q->tmax) || isinf(q->tmin))
        return error_fail(err, LC_EARG, "rays", "ray %zu: needs 0 <= tmin < tmax, got tmin "
                          "%g, tmax %g", i + 1, q->tmin, q->tmax);
    return LC_OK;
}

/* check_ray's verdict without its messages, for the rays that pass: an
** origin within the coordinate range (so finite), a direction whose
** square is finite and positive (so finite and not zero: what
** validate_nonzero asks), and 0 <= tmin < tmax (so neither is NaN, and
** tmin is not infinite). */
static inline int ray_ok(const lc_ray *q)
{
    lc_vec3 o = q->origin, d = q->direction;
    double dd = v3_dot(d, d);
    return fabs(o.x) <= LC_MAX_COORD && fabs(o.y) <= LC_MAX_COORD &&
           fabs(o.z) <= LC_MAX_COORD && dd > 0 && dd <= DBL_MAX && q->tmin >= 0 &&
           q->tmin < q->tmax;
}

static cast cast_of(const lc_ray *q)
{
    cast c;
    /* Scaled first: |d| of a direction near the top of the range would
    ** overflow as it squares. */
    double big = v3_max_abs(q->direction);
    c.len = big * v3_len(v3_mul(q->direction, 1.0 / big));
    c.r.d = v3_mul(q->direction, 1.0 / c.len);
    c.r.o = q->tmin > 0 ? v3_madd(q->origin, q->direction, q->tmin) : q->origin;
    c.tmax = (q->tmax - q->tmin) * c.len;
    return c;
}

/* The next block of rays (up to BVH_PACKET of the `left`), cast: the rays
** walked together when they can (intersect_closest_n). Returns how many. */
static int cast_block(const lc_ray *rays, size_t left, ray *r, double *tmax, double *len)
{
    int m = left < BVH_PACKET ? (int)left : BVH_PACKET;
    for (int j = 0; j < m; j++) {
        cast c = cast_of(&rays[j]);
        r[j] = c.r;
        tmax[j] = c.tmax;
        len[j] = c.len;
    }
    return m;
}

/* Validates every ray, then compiles the geometry if it changed, under the
** scene's lock (a render in progress holds it); tracing needs no lock, so
** several threads cast into one scene at once. */
static lc_status begin(lc_scene *s, const lc_ray *rays, size_t n, sig_atomic_t seen,
                       lc_error *err)
{
    for (size_t i = 0; i < n; i++)
        if (!ray_ok(&rays[i]) && check_ray(&rays[i], i, err))
            return LC_EARG;
    pthread_mutex_lock(&s->lock);
    lc_status st = compile_geometry(s, seen, err);
    pthread_mutex_unlock(&s->lock);
    return st;
}

int scene_object_id(const lc_scene *s, const hit *h)
{
    int kind;
    long primitive;
    return object_of(s, h, &kind, &primitive);
}

static int object_of(const lc_scene *s, const hit *h, int *kind, long *primitive)
{
    unsigned pk = PRIM_KIND(h->shape);
    *primitive = 0;
    if (pk == PRIM_CSG_FACE || pk == PRIM_CSG_CUT) {    /* a CSG object: its leaf's kind */
        const csg_tree *t = s->csgs[PRIM_INDEX(h->shape)];
        *kind = csg_hit_kind(t, h);
        return t->id;
    }
    if (pk != PRIM_TRIANGLE) {
        lc_shape_kind k = shape_kind_of_prim(pk);
        *kind = (int)k;
        return s->shapes[k].id[PRIM_INDEX(h->shape)];
    }
    const tri_ref *tr = &s->c.tris[PRIM_INDEX(h->shape)];
    *kind = LC_SHAPE_KINDS;
    *primitive = (long)tr->face;
    /* An instance's faces are listed once for all its placements. */
    return s->meshes[h->instance ? h->instance - 1 : tr->mesh].id;
}

/* The caller's answer for its ray q (h: the hit, NULL for none; len: |d|). */
static void put_hit(const lc_scene *s, const lc_ray *q, double len, const hit *h,
                    lc_ray_hit *out)
{
    memset(out, 0, sizeof *out);
    if (!h) {
        out->object = -1;
        out->shape_kind = -1;
        out->material = -1;
        return;
    }
    out->hit = 1;
    out->t = q->tmin + h->t / len;
    out->point = h->p;
    out->normal = h->n;
    out->shading_normal = h->ns;
    intersect_uv(s, h, out->uv);
    out->object = object_of(s, h, &out->shape_kind, &out->primitive);
    out->material = h->material;
}

/* The rays cast in blocks of BVH_PACKET: for their nearest hits into hits,
** or (hits NULL) for whether anything blocks them into blocked. */
static lc_status cast_rays(lc_scene *s, const lc_ray *rays, size_t n, lc_ray_hit *hits,
                           unsigned char *blocked, lc_error *err)
{
    sig_atomic_t seen = interrupt_count();
    if (begin(s, rays, n, seen, err))
        return err ? err->code : LC_EARG;
    for (size_t i = 0; i < n; i += BVH_PACKET) {
        if (i % POLL == POLL - BVH_PACKET && interrupt_count() != seen)
            return error_fail(err, LC_ECANCEL, NULL, "interrupted after %zu of %zu rays", i, n);
        ray r[BVH_PACKET];
        double tmax[BVH_PACKET], len[BVH_PACKET];
        hit h[BVH_PACKET];
        int found[BVH_PACKET];
        int m = cast_block(rays + i, n - i, r, tmax, len);
        if (!hits) {
            intersect_occluded_n(s, r, tmax, m, found);
            for (int j = 0; j < m; j++)
                blocked[i + (size_t)j] = (unsigned char)found[j];
            continue;
        }
        intersect_closest_n(s, r, tmax, m, h, found);
        for (int j = 0; j < m; j++)
            put_hit(s, &rays[i + (size_t)j], len[j], found[j] ? &h[j] : NULL,
                    &hits[i + (size_t)j]);
    }
    error_ok(err);
    return LC_OK;
}

lc_status lc_scene_intersect(lc_scene *s, const lc_ray *rays, size_t n, lc_ray_hit *hits,
                             lc_error *err)
{
    return cast_rays(s, rays, n, hits, NULL, err);
}

lc_status lc_scene_occluded(lc_scene *s, const lc_ray *rays, size_t n,
                            unsigned char *blocked, lc_error *err)
{
    return cast_rays(s, rays, n, NULL, blocked, err);
}
