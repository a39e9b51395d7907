/* raycast.c: lancer's ray queries against Embree 3's on the same geometry and
** the same rays, for `make bench` (tools/bench/embree.lua). A benchmark peer
** only: lancer itself never links Embree.
**
** Usage: lc-raycast b2 N | b3 Q | mesh FILE.obj  [threads [runs]]
**
** The geometry is docs/bench-scenes.md's B2 (N spheres on a ground plane) or B3 (a Q x Q
** terrain), built from the same generator as scenes/bench/b2.lua and b3.lua,
** in double for lancer and rounded to float for Embree (sphere radii
** rounded up); or an OBJ mesh, seen from a camera that frames it. Three ray
** sets, built once in double and given to both (Embree's rounded to float):
**   primary    one ray through each pixel centre of the 1280x720 camera;
**   shadow     from each primary hit (lancer's), toward the light;
**   incoherent from each primary hit, one cosine-distributed direction
**              about the normal: what ambient occlusion or a diffuse bounce
**              casts.
** Each run times lancer's build, then Embree's, then each set on lancer and
** on Embree in turn (A B A B ...), `threads` threads each, splitting the
** rays in blocks. Prints one line per measure:
**   raycast <what> lancer=<s> embree=<s> ratio=<lancer/embree> rays=<n>
** with medians over the runs, then how often the two disagree (float
** against double: a hit one finds and the other misses, or another
** primitive). */
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "lancer.h"
#include "base/mem.h"

#define W 1280
#define H 720
#define BLOCK 1024
#define MAX_RUNS 31
#define PI 3.14159265358979323846

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void die(const char *what, const char *why)
{
    fprintf(stderr, "lc-raycast: %s: %s\n", what, why);
    exit(1);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p)
        die("out of memory", "allocating the rays");
    return p;
}

/* ---- the geometry ---------------------------------------------------------------- */

/* docs/bench-scenes.md's PRNG (seed 1). */
static uint64_t prng = 1;
static double u01(void)
{
    prng = prng * 6364136223846793005u + 1442695040888963407u;
    return (double)(prng >> 11) * (1.0 / 9007199254740992.0);
}

static double terrain(double x, double z)
{
    return 3.0 * sin(0.11 * x) * cos(0.13 * z) + 1.2 * sin(0.37 * x + 1.0) * sin(0.29 * z + 2.0)
         + 0.35 * sin(1.3 * x + 0.3) * cos(1.7 * z + 0.7) + 0.1 * sin(5.1 * x) * cos(4.3 * z);
}

typedef struct {
    const char *name;
    /* spheres: 4 doubles each (x, y, z, r); the ground plane y = 0 with them */
    double   *spheres;
    size_t    nspheres;
    /* a mesh: 3 doubles a vertex, 3 indices a face */
    double   *v;
    uint32_t *f;
    size_t    nv, nf;
    lc_vec3   eye, at, light;
} geometry;

static void make_b2(geometry *g, size_t n)
{
    g->spheres = xmalloc(4 * n * sizeof *g->spheres);
    g->nspheres = n;
    for (size_t k = 0; k < n; k++) {
        double x = -50 + 100 * u01();
        double z = -50 + 100 * u01();
        double r = 0.05 + 0.25 * u01();
        double *s = g->spheres + 4 * k;
        s[0] = x, s[1] = r, s[2] = z, s[3] = r;
    }
    /* docs/bench-scenes.md's reference values: the same generator as b2.lua. */
    if (n >= 3 && (fabs(g->spheres[0] + 7.679082913) > 1e-9 ||
                   fabs(g->spheres[4 + 2] - 29.544774925) > 1e-9 ||
                   fabs(g->spheres[8 + 3] - 0.259931527) > 1e-9))
        die("b2", "the generator does not match the reference values "
            "(docs/bench-scenes.md)");
    g->eye = (lc_vec3){0, 12, 62};
    g->at = (lc_vec3){0, 0, 0};
    g->light = (lc_vec3){40, 60, 30};
}

static void make_b3(geometry *g, size_t q)
{
    g->nv = (q + 1) * (q + 1);
    g->nf = 2 * q * q;
    g->v = xmalloc(3 * g->nv * sizeof *g->v);
    g->f = xmalloc(3 * g->nf * sizeof *g->f);
    for (size_t j = 0; j <= q; j++)
        for (size_t i = 0; i <= q; i++) {
            double x = -50 + 100.0 * (double)i / (double)q;
            double z = -50 + 100.0 * (double)j / (double)q;
            double *p = g->v + 3 * (j * (q + 1) + i);
            p[0] = x, p[1] = terrain(x, z), p[2] = z;
        }
    uint32_t *f = g->f;
    for (size_t j = 0; j < q; j++)
        for (size_t i = 0; i < q; i++) {
            uint32_t v00 = (uint32_t)(j * (q + 1) + i), v10 = v00 + 1;
            uint32_t v01 = v00 + (uint32_t)q + 1, v11 = v01 + 1;
            *f++ = v00, *f++ = v10, *f++ = v11;
            *f++ = v00, *f++ = v11, *f++ = v01;
        }
    if (fabs(terrain(0, 0) - 0.997286094) > 1e-9 || fabs(terrain(10, -20) + 3.123107719) > 1e-9)
        die("b3", "the height field does not match the reference values "
            "(docs/bench-scenes.md)");
    g->eye = (lc_vec3){0, 14, 62};
    g->at = (lc_vec3){0, 0, 0};
    g->light = (lc_vec3){60, 25, 20};
}

/* An OBJ mesh through lancer's own reader, on a ground of two triangles;
** the camera frames it. */
static void make_obj(geometry *g, const char *path)
{
    lc_error err;
    lc_mesh *m = lc_mesh_load_obj(path, &err);
    if (!m)
        die(path, err.msg);
    size_t nv = lc_mesh_vertex_count(m), nf = lc_mesh_face_count(m);
    g->nv = nv + 4;
    g->nf = nf + 2;
    g->v = xmalloc(3 * g->nv * sizeof *g->v);
    g->f = xmalloc(3 * g->nf * sizeof *g->f);
    memcpy(g->v, lc_mesh_vertex_data(m), 3 * nv * sizeof *g->v);
    memcpy(g->f, lc_mesh_face_data(m), 3 * nf * sizeof *g->f);
    lc_mesh_free(m);
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], g->v[3 * i + k]);
            hi[k] = fmax(hi[k], g->v[3 * i + k]);
        }
    lc_vec3 c = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    double r = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                          (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double ground[12] = {c.x - 4 * r, lo[1], c.z - 4 * r, c.x + 4 * r, lo[1], c.z - 4 * r,
                               c.x + 4 * r, lo[1], c.z + 4 * r, c.x - 4 * r, lo[1], c.z + 4 * r};
    memcpy(g->v + 3 * nv, ground, sizeof ground);
    const uint32_t quad[6] = {0, 2, 1, 0, 3, 2};
    for (int k = 0; k < 6; k++)
        g->f[3 * nf + k] = (uint32_t)nv + quad[k];
    g->at = c;
    g->eye = (lc_vec3){c.x + 0.6 * r, c.y + 0.8 * r, c.z + 2.2 * r};
    g->light = (lc_vec3){c.x + 3 * r, c.y + 4 * r, c.z + 2 * r};
}

/* ---- lancer's side --------------------------------------------------------------- */

static lc_scene *lancer_scene(const geometry *g)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    if (!s)
        die("lancer", err.msg);
    lc_material m = lc_material_default();
    lc_scene_add_material(s, &m, &err);
    if (g->nspheres) {
        lc_shape ground = {.kind = LC_PLANE, .p = {0, 0, 0}, .u = {0, 1, 0}};
        lc_scene_add_shape(s, &ground, 0, &err);               /* id 0 */
        for (size_t k = 0; k < g->nspheres; k++) {
            const double *q = g->spheres + 4 * k;
            lc_shape b = {.kind = LC_SPHERE, .p = {q[0], q[1], q[2]}, .radius = q[3]};
            if (lc_scene_add_shape(s, &b, 0, &err) < 0)        /* id 1 + k */
                die("lancer", err.msg);
        }
    } else {
        lc_mesh *mesh = lc_mesh_new(&err);
        if (lc_mesh_add_vertices(mesh, g->v, g->nv, &err) ||
            lc_mesh_add_faces(mesh, g->f, g->nf, &err) || lc_scene_add_mesh(s, mesh, 0, &err) < 0)
            die("lancer", err.msg);
        lc_mesh_free(mesh);                                      /* the scene holds it */
    }
    return s;
}

/* ---- Embree's side --------------------------------------------------------------- */

/* Embree's own allocations (its BVH and the geometry buffers it holds), as
** its memory monitor reports them: now, and the most since a reset. */
static _Atomic long long embree_bytes, embree_high;

static bool embree_monitor(void *user, ssize_t bytes, bool post)
{
    (void)user, (void)post;
    long long now = atomic_fetch_add(&embree_bytes, (long long)bytes) + bytes;
    long long h = atomic_load(&embree_high);
    while (now > h && !atomic_compare_exchange_weak(&embree_high, &h, now))
        ;
    return true;
}

static float round_up(double x)
{
    float f = (float)x;
    return f < x ? nextafterf(f, INFINITY) : f;
}

static RTCScene embree_scene(RTCDevice dev, const geometry *g)
{
    RTCScene sc = rtcNewScene(dev);
    if (g->nspheres) {
        RTCGeometry s = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        float *b = rtcSetNewGeometryBuffer(s, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                           4 * sizeof(float), g->nspheres);
        for (size_t k = 0; k < g->nspheres; k++) {
            const double *q = g->spheres + 4 * k;
            b[4 * k] = (float)q[0], b[4 * k + 1] = (float)q[1], b[4 * k + 2] = (float)q[2];
            b[4 * k + 3] = round_up(q[3]);
        }
        rtcCommitGeometry(s);
        rtcAttachGeometryByID(sc, s, 0);
        rtcReleaseGeometry(s);
        /* The infinite ground as two triangles far beyond what the camera sees. */
        RTCGeometry t = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *v = rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           3 * sizeof(float), 4);
        unsigned *ix = rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                               3 * sizeof(unsigned), 2);
        const float e = 1e5f, quad[12] = {-e, 0, -e, e, 0, -e, e, 0, e, -e, 0, e};
        memcpy(v, quad, sizeof quad);
        const unsigned tri[6] = {0, 1, 2, 0, 2, 3};
        memcpy(ix, tri, sizeof tri);
        rtcCommitGeometry(t);
        rtcAttachGeometryByID(sc, t, 1);
        rtcReleaseGeometry(t);
    } else {
        RTCGeometry t = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *v = rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           3 * sizeof(float), g->nv);
        unsigned *ix = rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                               3 * sizeof(unsigned), g->nf);
        for (size_t i = 0; i < 3 * g->nv; i++)
            v[i] = (float)g->v[i];
        for (size_t i = 0; i < 3 * g->nf; i++)
            ix[i] = g->f[i];
        rtcCommitGeometry(t);
        rtcAttachGeometryByID(sc, t, 0);
        rtcReleaseGeometry(t);
    }
    rtcCommitScene(sc);
    return sc;
}

/* ---- the rays -------------------------------------------------------------------- */

static lc_vec3 add(lc_vec3 a, lc_vec3 b) { return (lc_vec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static lc_vec3 sub(lc_vec3 a, lc_vec3 b) { return (lc_vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static lc_vec3 mul(lc_vec3 a, double k) { return (lc_vec3){a.x * k, a.y * k, a.z * k}; }
static double dot(lc_vec3 a, lc_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static lc_vec3 cross(lc_vec3 a, lc_vec3 b)
{
    return (lc_vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static lc_vec3 unit(lc_vec3 a) { return mul(a, 1 / sqrt(dot(a, a))); }

/* The benchmark's pinhole camera (docs/bench-scenes.md), 60 degrees across,
** through each pixel centre. */
static lc_ray *camera_rays(const geometry *g)
{
    lc_ray *r = xmalloc((size_t)W * H * sizeof *r);
    lc_vec3 f = unit(sub(g->at, g->eye)), rt = unit(cross(f, (lc_vec3){0, 1, 0}));
    lc_vec3 up = cross(rt, f);
    double tx = tan(60 * PI / 360), ty = tx * H / W;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            lc_vec3 d = add(f, add(mul(rt, (2 * (i + 0.5) / W - 1) * tx),
                                   mul(up, (1 - 2 * (j + 0.5) / H) * ty)));
            r[(size_t)j * W + i] = (lc_ray){g->eye, unit(d), 0, HUGE_VAL};
        }
    return r;
}

/* From each hit, just off the surface on the side the ray came from: a
** shadow ray to the light (t = 1 at the light) and a cosine-distributed
** one about the normal. */
static size_t secondary_rays(const geometry *g, const lc_ray *prim, const lc_ray_hit *h,
                             size_t n, lc_ray *shadow, lc_ray *bounce)
{
    size_t m = 0;
    uint64_t keep = prng;
    prng = 7;
    for (size_t i = 0; i < n; i++) {
        if (!h[i].hit)
            continue;
        lc_vec3 nf = h[i].normal;
        if (dot(nf, prim[i].direction) > 0)
            nf = mul(nf, -1);
        double big = fmax(fabs(h[i].point.x), fmax(fabs(h[i].point.y), fabs(h[i].point.z)));
        lc_vec3 o = add(h[i].point, mul(nf, 1e-4 * (1 + big)));
        shadow[m] = (lc_ray){o, sub(g->light, o), 0, 1};
        /* Duff et al.'s branchless frame about nf. */
        double sg = copysign(1.0, nf.z), a = -1 / (sg + nf.z), b = nf.x * nf.y * a;
        lc_vec3 t1 = {1 + sg * nf.x * nf.x * a, sg * b, -sg * nf.x};
        lc_vec3 t2 = {b, sg + nf.y * nf.y * a, -nf.y};
        double u1 = u01(), u2 = u01(), rr = sqrt(u1), phi = 2 * PI * u2;
        lc_vec3 d = add(add(mul(t1, rr * cos(phi)), mul(t2, rr * sin(phi))),
                        mul(nf, sqrt(fmax(0, 1 - u1))));
        bounce[m] = (lc_ray){o, d, 0, HUGE_VAL};
        m++;
    }
    prng = keep;
    return m;
}

static void to_embree(const lc_ray *r, struct RTCRay *e)
{
    e->org_x = (float)r->origin.x, e->org_y = (float)r->origin.y, e->org_z = (float)r->origin.z;
    e->dir_x = (float)r->direction.x, e->dir_y = (float)r->direction.y;
    e->dir_z = (float)r->direction.z;
    e->tnear = (float)r->tmin;
    e->tfar = r->tmax >= HUGE_VAL ? INFINITY : (float)r->tmax;
    e->mask = 0xffffffffu;
    e->flags = 0;
    e->time = 0;
    e->id = 0;
}

/* ---- tracing on threads ---------------------------------------------------------- */

enum { LANCER_HIT, LANCER_OCCLUDED, EMBREE_HIT, EMBREE_OCCLUDED };

typedef struct {
    int          mode;
    lc_scene    *scene;
    RTCScene     esc;
    const lc_ray *rays;
    size_t       n;
    lc_ray_hit  *hits;         /* lancer's results */
    unsigned char *blocked;
    struct RTCRayHit   *ehits;        /* Embree's */
    atomic_size_t next;
    atomic_int   failed;
} trace_job;

static void *trace_worker(void *arg)
{
    trace_job *j = arg;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (;;) {
        size_t b = atomic_fetch_add(&j->next, BLOCK);
        if (b >= j->n)
            break;
        size_t e = b + BLOCK < j->n ? b + BLOCK : j->n;
        lc_error err;
        switch (j->mode) {
        case LANCER_HIT:
            if (lc_scene_intersect(j->scene, j->rays + b, e - b, j->hits + b, &err))
                atomic_store(&j->failed, 1);
            break;
        case LANCER_OCCLUDED:
            if (lc_scene_occluded(j->scene, j->rays + b, e - b, j->blocked + b, &err))
                atomic_store(&j->failed, 1);
            break;
        case EMBREE_HIT:
            for (size_t i = b; i < e; i++) {
                struct RTCRayHit *rh = &j->ehits[i];
                to_embree(&j->rays[i], &rh->ray);
                rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(j->esc, &ctx, rh);
            }
            break;
        case EMBREE_OCCLUDED:
            for (size_t i = b; i < e; i++) {
                struct RTCRay r;
                to_embree(&j->rays[i], &r);
                rtcOccluded1(j->esc, &ctx, &r);
                j->blocked[i] = r.tfar == -INFINITY;
            }
            break;
        }
    }
    return NULL;
}

static double trace(trace_job *j, int threads)
{
    pthread_t t[64];
    atomic_store(&j->next, 0);
    atomic_store(&j->failed, 0);
    double t0 = now();
    for (int i = 0; i < threads; i++)
        pthread_create(&t[i], NULL, trace_worker, j);
    for (int i = 0; i < threads; i++)
        pthread_join(t[i], NULL);
    double dt = now() - t0;
    if (atomic_load(&j->failed))
        die("lancer", "a cast failed");
    return dt;
}

/* ---- the report ------------------------------------------------------------------ */

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *x, int n)
{
    qsort(x, (size_t)n, sizeof *x, cmp);
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

static void line(const char *what, double *l, double *e, int runs, size_t rays)
{
    double ml = median(l, runs), me = median(e, runs);
    printf("raycast %s lancer=%.4f embree=%.4f ratio=%.3f rays=%zu", what, ml, me, ml / me, rays);
    if (rays)
        printf(" lancer_mrays=%.2f embree_mrays=%.2f", rays / ml * 1e-6, rays / me * 1e-6);
    printf("\n");
}

/* The primitive lancer's hit names, in Embree's numbering. */
static void lancer_prim(const geometry *g, const lc_ray_hit *h, unsigned *geom, unsigned *prim)
{
    if (g->nspheres) {
        *geom = h->object == 0 ? 1 : 0;
        *prim = h->object == 0 ? 0 : (unsigned)(h->object - 1);
    } else {
        *geom = 0;
        *prim = (unsigned)h->primitive;
    }
}

static void agreement(const char *what, const geometry *g, const lc_ray_hit *h,
                      const struct RTCRayHit *e, size_t n)
{
    size_t only_lancer = 0, only_embree = 0, other_prim = 0, both = 0;
    double worst = 0;
    for (size_t i = 0; i < n; i++) {
        int eh = e[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
        if (h[i].hit != eh) {
            only_lancer += h[i].hit, only_embree += eh;
            continue;
        }
        if (!eh)
            continue;
        both++;
        unsigned geom, prim;
        lancer_prim(g, &h[i], &geom, &prim);
        /* The ground of B2 is two triangles in Embree: either is the plane. */
        if (geom != e[i].hit.geomID || (geom == 0 && prim != e[i].hit.primID)) {
            other_prim++;
            continue;
        }
        double rel = fabs(e[i].ray.tfar - h[i].t) / h[i].t;
        worst = fmax(worst, rel);
    }
    printf("raycast agree %s both=%zu only_lancer=%zu only_embree=%zu other_primitive=%zu "
           "max_rel_t=%.2e\n", what, both, only_lancer, only_embree, other_prim, worst);
}

int main(int argc, char **argv)
{
    if (argc < 3)
        die("usage", "lc-raycast b2 N | b3 Q | mesh FILE.obj [threads [runs]]");
    geometry g;
    memset(&g, 0, sizeof g);
    g.name = argv[1];
    if (strcmp(argv[1], "b2") == 0)
        make_b2(&g, (size_t)atol(argv[2]));
    else if (strcmp(argv[1], "b3") == 0)
        make_b3(&g, (size_t)atol(argv[2]));
    else if (strcmp(argv[1], "mesh") == 0)
        make_obj(&g, argv[2]);
    else
        die(argv[1], "unknown scene (b2, b3 or mesh)");
    int threads = argc > 3 ? atoi(argv[3]) : 2;
    int runs = argc > 4 ? atoi(argv[4]) : 5;
    if (threads < 1 || threads > 64 || runs < 1 || runs > MAX_RUNS)
        die("usage", "threads in [1, 64], runs in [1, 31]");
    char config[32];
    snprintf(config, sizeof config, "threads=%d", threads);
    RTCDevice dev = rtcNewDevice(config);
    if (!dev)
        die("embree", "rtcNewDevice failed");
    rtcSetDeviceMemoryMonitorFunction(dev, embree_monitor, NULL);

    size_t np = (size_t)W * H;
    lc_ray *prim = camera_rays(&g), *shadow = xmalloc(np * sizeof *shadow);
    lc_ray *bounce = xmalloc(np * sizeof *bounce);
    lc_ray_hit *hits = xmalloc(np * sizeof *hits);
    struct RTCRayHit *ehits = xmalloc(np * sizeof *ehits);
    unsigned char *blocked = xmalloc(np), *eblocked = xmalloc(np);
    size_t ns = 0;

    double bl[MAX_RUNS], be[MAX_RUNS], t[6][MAX_RUNS];
    size_t mem[4] = {0};             /* lancer's and Embree's bytes: held, at the build's peak */
    lc_scene *s = NULL;
    RTCScene esc = NULL;
    for (int r = 0; r < runs; r++) {
        /* Builds: a fresh scene each run; lancer compiles on its first cast. */
        if (s)
            lc_scene_free(s);
        if (esc)
            rtcReleaseScene(esc);
        mem_high_water_reset();
        s = lancer_scene(&g);
        lc_error err;
        double t0 = now();
        if (lc_scene_intersect(s, prim, 0, hits, &err))
            die("lancer", err.msg);
        bl[r] = now() - t0;
        mem[0] = lc_memory_used(), mem[1] = mem_high_water();
        atomic_store(&embree_high, atomic_load(&embree_bytes));
        t0 = now();
        esc = embree_scene(dev, &g);
        be[r] = now() - t0;
        mem[2] = (size_t)atomic_load(&embree_bytes), mem[3] = (size_t)atomic_load(&embree_high);

        trace_job j = {.scene = s, .esc = esc, .hits = hits, .ehits = ehits};
        j.rays = prim, j.n = np;
        j.mode = LANCER_HIT, t[0][r] = trace(&j, threads);
        j.mode = EMBREE_HIT, t[1][r] = trace(&j, threads);
        if (r == 0) {
            agreement("primary", &g, hits, ehits, np);
            ns = secondary_rays(&g, prim, hits, np, shadow, bounce);
        }
        j.rays = shadow, j.n = ns;
        j.blocked = blocked, j.mode = LANCER_OCCLUDED, t[2][r] = trace(&j, threads);
        j.blocked = eblocked, j.mode = EMBREE_OCCLUDED, t[3][r] = trace(&j, threads);
        if (r == 0) {
            size_t differ = 0, n_blocked = 0;
            for (size_t i = 0; i < ns; i++)
                differ += blocked[i] != eblocked[i], n_blocked += blocked[i];
            printf("raycast agree shadow rays=%zu blocked=%zu differ=%zu\n", ns, n_blocked,
                   differ);
        }
        j.rays = bounce, j.n = ns;
        j.mode = LANCER_HIT, t[4][r] = trace(&j, threads);
        j.mode = EMBREE_HIT, t[5][r] = trace(&j, threads);
        if (r == 0)
            agreement("incoherent", &g, hits, ehits, ns);
        fprintf(stderr, "  run %d: build %.3f / %.3f s, primary %.3f / %.3f, shadow %.3f / "
                "%.3f, incoherent %.3f / %.3f\n", r + 1, bl[r], be[r], t[0][r], t[1][r],
                t[2][r], t[3][r], t[4][r], t[5][r]);
    }
    printf("raycast scene %s %s threads=%d runs=%d primitives=%zu\n", g.name, argv[2],
           threads, runs, g.nspheres ? g.nspheres + 1 : g.nf);
    line("build", bl, be, runs, 0);
    line("primary", t[0], t[1], runs, np);
    line("shadow", t[2], t[3], runs, ns);
    double ps_l[MAX_RUNS], ps_e[MAX_RUNS];
    for (int r = 0; r < runs; r++)
        ps_l[r] = t[0][r] + t[2][r], ps_e[r] = t[1][r] + t[3][r];
    line("primary+shadow", ps_l, ps_e, runs, np + ns);
    line("incoherent", t[4], t[5], runs, ns);
    /* Each side's own bytes for the scene (the ray arrays, and the other
    ** side, are not in them): held once built, and at the build's peak.
    ** Embree's are held with a scene already released, so the first
    ** figure is its scene's alone. */
    printf("raycast memory lancer_mb=%.1f lancer_build_mb=%.1f embree_mb=%.1f "
           "embree_build_mb=%.1f\n", mem[0] / 1048576.0, mem[1] / 1048576.0,
           mem[2] / 1048576.0, mem[3] / 1048576.0);
    lc_scene_free(s);
    rtcReleaseScene(esc);
    rtcReleaseDevice(dev);
    return 0;
}
