/* test_hard.c: docs/numerics.md's hard cases that need internals or many rays. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "scene/scene.h"
#include "helpers.h"
#include "scene/compile.h"
#include "render/plan.h"
#include "scene/intersect.h"
#include "shapes/triangle.h"

#define PI 3.14159265358979323846

/* Scales and translations of the invariance cases (docs/numerics.md H1, H2): a
** scene of size s moved by (T, T/2, T/3). */
static const double scales[] = {1e-4, 1e-2, 1, 1e2, 1e4, 1e6};
static const double shifts[] = {0, 1e3, 1e5, 1e7};
#define NSCALES (sizeof scales / sizeof scales[0])
#define NSHIFTS (sizeof shifts / sizeof shifts[0])

/* ---- Helpers ------------------------------------------------------------- */

/* A direction on the side of unit n given by sign: uniform for even k, for
** odd k within 1e-12 .. 1e-1 radians of the tangent plane (grazing). */
static lc_vec3 rand_dir(uint64_t *s, lc_vec3 n, int sign, int k)
{
    lc_vec3 w = rand_unit(s);
    if (k % 2) {
        lc_vec3 tg = v3_norm(v3_madd(w, n, -v3_dot(w, n)));
        w = v3_norm(v3_madd(tg, n, pow(10, -1 - 11 * lcg(s))));
    }
    if (v3_dot(w, n) * sign < 0)
        w = v3_madd(w, n, -2 * v3_dot(w, n));
    return w;
}

/* A right-handed orthonormal frame: the axes for even i, random for odd. */
static void rand_frame(uint64_t *seed, int i, lc_vec3 e[3])
{
    if (i % 2 == 0) {
        e[0] = v3(1, 0, 0);
        e[1] = v3(0, 1, 0);
        e[2] = v3(0, 0, 1);
        return;
    }
    lc_vec3 x = rand_unit(seed), y = rand_unit(seed);
    y = v3_norm(v3_madd(y, x, -v3_dot(x, y)));
    e[0] = x;
    e[1] = y;
    e[2] = v3_cross(x, y);
}

/* A scene with one white material: the shapes go in through the C API. */
static lc_scene *new_scene(int *mat)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    assert_non_null(s);
    lc_material m = lc_material_default();
    *mat = lc_scene_add_material(s, &m, &err);
    assert_true(*mat >= 0);
    return s;
}

static void add_shape(lc_scene *s, lc_shape sh, int mat)
{
    lc_error err;
    if (lc_scene_add_shape(s, &sh, mat, &err) < 0)
        fail_msg("add_shape: %s", err.msg);
}

static void compile(lc_scene *s)
{
    lc_error err;
    if (plan_scene(s, NULL, 0, &err) != LC_OK)
        fail_msg("compile: %s", err.msg);
}

static lc_shape sphere_shape(lc_vec3 c, double r)
{
    lc_shape sh = {.kind = LC_SPHERE, .p = c, .radius = r};
    return sh;
}

static lc_shape quad_shape(lc_vec3 q, lc_vec3 u, lc_vec3 v)
{
    lc_shape sh = {.kind = LC_QUAD, .p = q, .u = u, .v = v};
    return sh;
}

/* ---- Spawned rays on triangles (docs/numerics.md 1.5, H1, H2) --------------------- */

/* Random triangles at scales 1e-4..1e6 moved up to 1e7; camera rays at the
** interior, an edge or a vertex; from each hit a ray spawned to either side
** never hits the triangle again, and its origin is on that side of the true
** plane (long double). The sphere, quad and box cases are test_geometry.c's. */
static void spawn_triangle(void **state)
{
    (void)state;
    int tested = 0, aim_missed = 0, missed = 0, self = 0, wrong_side = 0;
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            uint64_t seed = 4000 + si * 10 + ti;
            double s = scales[si];
            for (int k = 0; k < 300; k++) {
                lc_vec3 e[3];
                rand_frame(&seed, k / 10, e);
                lc_vec3 base = v3_madd(shift_of(shifts[ti]), rand_unit(&seed), s);
                double p[3][3];
                lc_vec3 vtx[3];
                for (int i = 0; i < 3; i++) {
                    /* an irregular triangle in the frame's (e0, e1) plane */
                    double a = 2 * PI * (i + 0.3 * lcg(&seed)) / 3;
                    double rr = s * (0.5 + lcg(&seed));
                    vtx[i] = v3_madd(v3_madd(base, e[0], rr * cos(a)), e[1],
                                     rr * sin(a));
                    p[i][0] = vtx[i].x;
                    p[i][1] = vtx[i].y;
                    p[i][2] = vtx[i].z;
                }
                /* the aim: 0 interior, 1 an edge, 2 a vertex */
                int aim = k % 5 < 3 ? 0 : k % 5 == 3 ? 1 : 2;
                double b1 = aim == 2 ? 1 : aim == 1 ? lcg(&seed)
                                                    : 0.05 + 0.6 * lcg(&seed);
                double b2 = aim == 2 ? 0 : aim == 1 ? 1 - b1 : 0.05 + 0.3 * lcg(&seed);
                lc_vec3 to = v3_madd(v3_madd(v3_mul(vtx[0], 1 - b1 - b2), vtx[1], b1),
                                     vtx[2], b2);
                lc_vec3 e1 = v3_sub(vtx[1], vtx[0]), e2 = v3_sub(vtx[2], vtx[0]);
                lc_vec3 n = v3_norm(v3_cross(e1, e2));
                lc_vec3 a = rand_unit(&seed);
                while (fabs(v3_dot(a, n)) < 0.1)
                    a = rand_unit(&seed);
                lc_vec3 o = v3_madd(to, a, 4 * s);
                ray cam = mkray(o, v3_norm(v3_sub(to, o)));
                triangle_shear sh;
                triangle_shear_init(cam.d, &sh);
                hit h;
                double bary[3];
                if (!triangle_hit(p[0], p[1], p[2], &cam, &sh, 0, HUGE_VAL, &h, bary)) {
                    if (aim)
                        aim_missed++;     /* the aim point rounded off the triangle */
                    else
                        missed++;
                    continue;
                }
                tested++;
                for (int side = -1; side <= 1; side += 2) {
                    lc_vec3 w = rand_dir(&seed, h.n, side, k);
                    ray sr = mkray(spawn_origin(&h, w), w);
                    triangle_shear_init(w, &sh);
                    hit h2;
                    double b2s[3];
                    if (triangle_hit(p[0], p[1], p[2], &sr, &sh, 0, HUGE_VAL, &h2, b2s))
                        self++;
                    /* signed distance of the new origin from the true plane */
                    long double nx = (long double)e1.y * e2.z - (long double)e1.z * e2.y;
                    long double ny = (long double)e1.z * e2.x - (long double)e1.x * e2.z;
                    long double nz = (long double)e1.x * e2.y - (long double)e1.y * e2.x;
                    long double dist = ((long double)sr.o.x - vtx[0].x) * nx +
                                       ((long double)sr.o.y - vtx[0].y) * ny +
                                       ((long double)sr.o.z - vtx[0].z) * nz;
                    long double side_n = nx * h.n.x + ny * h.n.y + nz * h.n.z;
                    if (dist * side_n * side <= 0)
                        wrong_side++;
                }
            }
        }
    print_message("triangles: %d hits (%d edge/vertex aims rounded off), %d self-hits, "
                  "%d wrong side\n", tested, aim_missed, self, wrong_side);
    if (self || wrong_side || missed)
        fail_msg("of %d hits: %d self-hits, %d origins on the wrong side, %d interior "
                 "aims missed", tested, self, wrong_side, missed);
}

/* ---- Convex solids: which side a spawned ray leaves on ------------------- */

/* A face of a convex solid: the parallelogram (tri = 0) or triangle (tri = 1)
** q + a u + b v, with its outward unit normal. */
typedef struct {
    lc_vec3 q, u, v, n;
    int     tri;
} face;

static face mkface(lc_vec3 q, lc_vec3 u, lc_vec3 v, int tri, lc_vec3 inside)
{
    face f = {q, u, v, v3_norm(v3_cross(u, v)), tri};
    if (v3_dot(f.n, v3_sub(q, inside)) < 0)
        f.n = v3_neg(f.n);
    return f;
}

/* Whether p lies on f within tol (absolute, in the plane and across it). */
static int on_face(const face *f, lc_vec3 p, double tol)
{
    lc_vec3 pq = v3_sub(p, f->q);
    if (fabs(v3_dot(pq, f->n)) > tol)
        return 0;
    lc_vec3 n = v3_cross(f->u, f->v);
    double nn = v3_dot(n, n);
    double a = v3_dot(n, v3_cross(pq, f->v)) / nn;
    double b = v3_dot(n, v3_cross(f->u, pq)) / nn;
    double ea = tol / v3_len(f->u), eb = tol / v3_len(f->v);
    if (a < -ea || b < -eb)
        return 0;
    return f->tri ? a + b <= 1 + ea + eb : a <= 1 + ea && b <= 1 + eb;
}

/* A ray leaving a boundary point p of a convex solid in direction w stays
** outside if it points out of some face through p, and crosses the inside
** if it points into all of them. Returns 1 (out), -1 (in), or 0 when that
** is not decidable in double: the faces through p disagree (an edge or a
** vertex grazed), or across the solid's size the ray moves off a face's
** plane by less than tol, the rounding of the points there (a ray leaving
** the face x = 1000 at 1e-12 rad drifts 1e-16 over a 1e-4 cube: below the
** ulp of 1000, so whether it clips the far edge is a coin toss). */
static int leaves(const face *fs, int n, lc_vec3 p, lc_vec3 w, double tol, double size)
{
    int out = 0, in = 0, on = 0;
    for (int i = 0; i < n; i++)
        if (on_face(&fs[i], p, tol)) {
            double c = v3_dot(w, fs[i].n);
            on++;
            if (fabs(c) * size <= tol) return 0;
            if (c > 0) out++;
            else in++;
        }
    if (!on || (out && in))
        return 0;
    return out ? 1 : -1;
}

/* How far the point o + t w (long double) lies outside the convex solid:
** the largest distance past any face's plane; <= 0 inside. */
static long double outside(const face *fs, int nf, lc_vec3 o, lc_vec3 w, double t)
{
    long double p[3] = {o.x + (long double)t * w.x, o.y + (long double)t * w.y,
                        o.z + (long double)t * w.z};
    long double m = -HUGE_VALL;
    for (int i = 0; i < nf; i++) {
        long double d = (p[0] - fs[i].q.x) * fs[i].n.x + (p[1] - fs[i].q.y) * fs[i].n.y +
                        (p[2] - fs[i].q.z) * fs[i].n.z;
        if (d > m)
            m = d;
    }
    return m;
}

/* Spawns a ray from h toward w in the scene of a convex solid and checks it:
** outgoing rays meet nothing, incoming ones meet another face (the solid is
** closed: no crack lets them out). An outgoing ray may still meet a face
** where it passes within rounding of the solid (4 ulps of the point plus
** tol): along an edge, which double cannot tell from grazing it. Counts into
** bad[0..3]: outgoing rays meeting a face past that, incoming rays lost,
** incoming rays meeting the face they leave, outgoing rays meeting a face
** within rounding (the seam). */
static int check_spawn(const lc_scene *sc, const face *fs, int nf, const hit *h,
                       lc_vec3 w, double tol, double size, int bad[4])
{
    int side = leaves(fs, nf, h->p, w, tol, size);
    if (!side)
        return 0;
    ray sr = mkray(spawn_origin(h, w), w);
    hit h2;
    int found = intersect_closest(sc, &sr, HUGE_VAL, &h2, NULL);
    if (side > 0 && found) {
        double m = v3_max_abs(h2.p);
        double ulp = nextafter(m, HUGE_VAL) - m;
        bad[outside(fs, nf, sr.o, w, h2.t) <= 4 * ulp + tol ? 3 : 0]++;
    }
    else if (side < 0 && !found)
        bad[1]++;
    else if (side < 0 && h2.shape == h->shape)
        bad[2]++;
    return 1;
}

/* ---- A closed mesh in a scene --------------------------------------------- */

/* The icosahedron split twice (162 vertices, 320 faces) on the sphere (c, r). */
typedef struct {
    double   v[3 * 162];
    uint32_t f[3 * 320];
    int      nv, nf;
} ico;

static int ico_mid(ico *m, int a, int b)
{
    lc_vec3 p = v3_norm(v3(m->v[3 * a] + m->v[3 * b], m->v[3 * a + 1] + m->v[3 * b + 1],
                           m->v[3 * a + 2] + m->v[3 * b + 2]));
    for (int i = 0; i < m->nv; i++)
        if (m->v[3 * i] == p.x && m->v[3 * i + 1] == p.y && m->v[3 * i + 2] == p.z)
            return i;
    m->v[3 * m->nv] = p.x;
    m->v[3 * m->nv + 1] = p.y;
    m->v[3 * m->nv + 2] = p.z;
    return m->nv++;
}

static void ico_build(ico *m, lc_vec3 c, double r)
{
    static const int faces[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    double t = (1 + sqrt(5)) / 2;
    double base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t},
                          {0, 1, t}, {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1},
                          {-t, 0, -1}, {-t, 0, 1}};
    uint32_t tmp[3 * 320];
    m->nv = 12;
    for (int i = 0; i < 12; i++) {
        lc_vec3 p = v3_norm(v3(base[i][0], base[i][1], base[i][2]));
        m->v[3 * i] = p.x;
        m->v[3 * i + 1] = p.y;
        m->v[3 * i + 2] = p.z;
    }
    m->nf = 20;
    for (int i = 0; i < 20; i++)
        for (int j = 0; j < 3; j++)
            m->f[3 * i + j] = (uint32_t)faces[i][j];
    for (int level = 0; level < 2; level++) {
        int nf = 0;
        for (int i = 0; i < m->nf; i++) {
            int a = (int)m->f[3 * i], b = (int)m->f[3 * i + 1];
            int cc = (int)m->f[3 * i + 2];
            int ab = ico_mid(m, a, b), bc = ico_mid(m, b, cc), ca = ico_mid(m, cc, a);
            int tri[4][3] = {{a, ab, ca}, {b, bc, ab}, {cc, ca, bc}, {ab, bc, ca}};
            for (int k = 0; k < 4; k++)
                for (int j = 0; j < 3; j++)
                    tmp[3 * nf + 3 * k + j] = (uint32_t)tri[k][j];
            nf += 4;
        }
        memcpy(m->f, tmp, sizeof(uint32_t) * 3 * (size_t)nf);
        m->nf = nf;
    }
    for (int i = 0; i < m->nv; i++) {
        m->v[3 * i] = c.x + r * m->v[3 * i];
        m->v[3 * i + 1] = c.y + r * m->v[3 * i + 1];
        m->v[3 * i + 2] = c.z + r * m->v[3 * i + 2];
    }
}

static lc_vec3 ico_vertex(const ico *m, int i)
{
    return v3(m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2]);
}

/* A closed convex mesh: camera rays aimed at its vertices, edge midpoints and
** face interiors from outside. From each hit, a ray spawned out of the solid
** meets nothing (it is convex); one spawned into it meets another triangle,
** never the one it leaves, and never escapes through a crack. Directions
** are drawn around the hit triangle's normal, half of them grazing. */
static void spawn_closed_mesh(void **state)
{
    (void)state;
    static ico m;
    static face fs[320];
    int tested = 0, rays = 0, cam_missed = 0, bad[4] = {0, 0, 0, 0};
    for (size_t si = 0; si < NSCALES; si += 2)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            double s = scales[si];
            lc_vec3 c = shift_of(shifts[ti]);
            ico_build(&m, c, s);
            for (int i = 0; i < m.nf; i++) {
                lc_vec3 a = ico_vertex(&m, (int)m.f[3 * i]);
                fs[i] = mkface(a, v3_sub(ico_vertex(&m, (int)m.f[3 * i + 1]), a),
                               v3_sub(ico_vertex(&m, (int)m.f[3 * i + 2]), a), 1, c);
            }
            /* the hit point's own rounding, plus that of the translation */
            double tol = 1e-12 * s + 1e-15 * shifts[ti];
            int mat;
            lc_scene *sc = new_scene(&mat);
            lc_error err;
            lc_mesh *mesh = lc_mesh_new(&err);
            assert_int_equal(lc_mesh_add_vertices(mesh, m.v, (size_t)m.nv, &err), LC_OK);
            assert_int_equal(lc_mesh_add_faces(mesh, m.f, (size_t)m.nf, &err), LC_OK);
            assert_true(lc_scene_add_mesh(sc, mesh, mat, &err) >= 0);
            lc_mesh_free(mesh);
            compile(sc);
            uint64_t seed = 5000 + si * 10 + ti;
            for (int k = 0; k < 400; k++) {
                const uint32_t *f = m.f + 3 * (k % m.nf);
                lc_vec3 a = ico_vertex(&m, (int)f[0]), b = ico_vertex(&m, (int)f[1]);
                lc_vec3 cc = ico_vertex(&m, (int)f[2]);
                lc_vec3 to;
                if (k % 3 == 0)
                    to = a;                                         /* a vertex */
                else if (k % 3 == 1)
                    to = v3_mul(v3_add(a, b), 0.5);                 /* an edge */
                else
                    to = v3_add(v3_mul(a, 0.2), v3_add(v3_mul(b, 0.3), v3_mul(cc, 0.5)));
                lc_vec3 out = v3_norm(v3_sub(to, c));
                lc_vec3 dir = rand_unit(&seed);
                if (v3_dot(dir, out) < 0.2)
                    dir = v3_norm(v3_madd(dir, out, 1.2 - v3_dot(dir, out)));
                lc_vec3 o = v3_madd(to, dir, 3 * s);
                ray cam = mkray(o, v3_norm(v3_sub(to, o)));
                hit h;
                if (!intersect_closest(sc, &cam, HUGE_VAL, &h, NULL)) {
                    cam_missed++;
                    continue;
                }
                tested++;
                lc_vec3 n = v3_dot(h.n, v3_sub(h.p, c)) > 0 ? h.n : v3_neg(h.n);
                for (int side = -1; side <= 1; side += 2)
                    rays += check_spawn(sc, fs, m.nf, &h, rand_dir(&seed, n, side, k),
                                        tol, 2 * s, bad);
            }
            lc_scene_free(sc);
        }
    print_message("closed mesh: %d hits, %d spawned rays: %d out ones hit it, %d in "
                  "ones lost, %d self-hits\n", tested, rays, bad[0] + bad[3], bad[1],
                  bad[2]);
    if (cam_missed || bad[0] || bad[1] || bad[2] || bad[3])
        fail_msg("of %d hits (%d camera rays missed), %d spawned rays: %d going out hit "
                 "the mesh, %d going in escaped, %d hit their own triangle", tested,
                 cam_missed, rays, bad[0] + bad[3], bad[1], bad[2]);
}

/* ---- A cube of six quads: the origin project's cube ------------------------ */

/* The seed built boxes from six bounded planes. Six quads, at every scale
** and translation, camera rays aimed at faces, edges and corners from
** outside and from inside; rays spawned from the hits:
** - never meet the quad they leave (0 self-hits), whatever the cube;
** - in a cube whose quads share their edges exactly (axis-aligned, every
**   coordinate a multiple of a power of two: no sum rounds), nothing escapes
**   through an edge: camera rays from inside and spawned rays going in all
**   meet a quad. (A rotated cube's far faces start from a rounded corner and
**   really have gaps of an ulp, so only self-hits are checked there.)
** - going out of the cube they meet nothing, except where they pass within
**   rounding of an edge: there they may meet the neighbouring quad (often
**   at t ~ 1e-20 s), the seed's cube-edge seam. README: lancer's box is one
**   solid to avoid exactly that; loose quads keep it. Counted, not failed. */
static void spawn_cube_of_quads(void **state)
{
    (void)state;
    int tested = 0, rays = 0, escaped = 0, self = 0, bad[4] = {0, 0, 0, 0};
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            uint64_t seed = 6000 + si * 10 + ti;
            double s = scales[si];
            double tol = 1e-12 * s + 1e-15 * shifts[ti];
            for (int rep = 0; rep < 2; rep++) {
                int exact = rep == 0;
                lc_vec3 e[3], q;
                if (exact) {
                    double p2 = ldexp(1, (int)floor(log2(s)));
                    lc_vec3 t = shift_of(shifts[ti]);
                    q = v3(p2 * round(t.x / p2 + 0.25), p2 * round(t.y / p2 - 0.5),
                           p2 * round(t.z / p2 + 0.75));
                    e[0] = v3(p2, 0, 0);
                    e[1] = v3(0, 2 * p2, 0);
                    e[2] = v3(0, 0, p2);
                } else {
                    rand_frame(&seed, 1, e);
                    for (int j = 0; j < 3; j++)
                        e[j] = v3_mul(e[j], s);
                    q = v3_madd(shift_of(shifts[ti]), rand_unit(&seed), s);
                }
                lc_vec3 far = v3_add(v3_add(v3_add(q, e[0]), e[1]), e[2]);
                lc_vec3 centre = v3_mul(v3_add(q, far), 0.5);
                /* the three faces through q, the three through the far corner */
                face fs[6] = {
                    mkface(q, e[0], e[1], 0, centre), mkface(q, e[1], e[2], 0, centre),
                    mkface(q, e[2], e[0], 0, centre),
                    mkface(far, v3_neg(e[0]), v3_neg(e[1]), 0, centre),
                    mkface(far, v3_neg(e[1]), v3_neg(e[2]), 0, centre),
                    mkface(far, v3_neg(e[2]), v3_neg(e[0]), 0, centre)};
                int mat;
                lc_scene *sc = new_scene(&mat);
                for (int i = 0; i < 6; i++)
                    add_shape(sc, quad_shape(fs[i].q, fs[i].u, fs[i].v), mat);
                compile(sc);
                for (int k = 0; k < 200; k++) {
                    /* aim: 1 coordinate 0 or 1 (a face), 2 (an edge), 3 (a corner) */
                    int fixed = k % 3 + 1;
                    int first = (int)(lcg(&seed) * 3);
                    lc_vec3 to = q;
                    for (int j = 0; j < 3; j++) {
                        int ax = (first + j) % 3;
                        double a = j < fixed ? (double)(lcg(&seed) < 0.5)
                                             : 0.02 + 0.96 * lcg(&seed);
                        to = v3_madd(to, e[ax], a);
                    }
                    int inside = k % 4 == 3;
                    lc_vec3 o;
                    if (inside) {
                        o = v3_madd(centre, rand_unit(&seed), 0.2 * s);
                    } else {
                        lc_vec3 out = v3_norm(v3_sub(to, centre));
                        lc_vec3 dir = rand_unit(&seed);
                        if (v3_dot(dir, out) < 0.3)
                            dir = v3_norm(v3_madd(dir, out, 1.3 - v3_dot(dir, out)));
                        o = v3_madd(to, dir, 4 * s);
                    }
                    ray cam = mkray(o, v3_norm(v3_sub(to, o)));
                    hit h;
                    if (!intersect_closest(sc, &cam, HUGE_VAL, &h, NULL)) {
                        if (inside && exact)
                            escaped++;           /* out through a crack */
                        continue;
                    }
                    tested++;
                    lc_vec3 n = v3_dot(h.n, v3_sub(h.p, centre)) > 0 ? h.n : v3_neg(h.n);
                    for (int side = -1; side <= 1; side += 2) {
                        int b[4] = {0, 0, 0, 0};
                        rays += check_spawn(sc, fs, 6, &h, rand_dir(&seed, n, side, k),
                                            tol, 4 * s, b);
                        self += b[2];
                        bad[3] += b[3];
                        if (exact) {
                            bad[0] += b[0];
                            bad[1] += b[1];
                        }
                    }
                }
                lc_scene_free(sc);
            }
        }
    print_message("cube of quads: %d hits, %d spawned rays: %d self-hits; exact cubes: "
                  "%d rays from inside escaped, %d out ones hit it, %d in ones lost; "
                  "all: %d out ones met a quad within rounding of an edge (seam)\n",
                  tested, rays, self, escaped, bad[0], bad[1], bad[3]);
    if (self || escaped || bad[0] || bad[1])
        fail_msg("of %d hits, %d spawned rays: %d hit their own quad; in exactly "
                 "shared cubes %d rays from inside escaped, %d going out hit a quad, "
                 "%d going in escaped", tested, rays, self, escaped, bad[0], bad[1]);
}

/* The same with lancer's box, one solid: no seam at all. */
static void spawn_box_solid(void **state)
{
    (void)state;
    int tested = 0, rays = 0, bad[4] = {0, 0, 0, 0};
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            uint64_t seed = 6500 + si * 10 + ti;
            double s = scales[si];
            double tol = 1e-12 * s + 1e-15 * shifts[ti];
            for (int rep = 0; rep < 2; rep++) {
                lc_vec3 e[3];
                rand_frame(&seed, rep, e);
                for (int j = 0; j < 3; j++)
                    e[j] = v3_mul(e[j], s * (0.5 + lcg(&seed)));
                lc_vec3 q = v3_madd(shift_of(shifts[ti]), rand_unit(&seed), s);
                lc_vec3 far = v3_add(v3_add(v3_add(q, e[0]), e[1]), e[2]);
                lc_vec3 centre = v3_mul(v3_add(q, far), 0.5);
                face fs[6] = {
                    mkface(q, e[0], e[1], 0, centre), mkface(q, e[1], e[2], 0, centre),
                    mkface(q, e[2], e[0], 0, centre),
                    mkface(far, v3_neg(e[0]), v3_neg(e[1]), 0, centre),
                    mkface(far, v3_neg(e[1]), v3_neg(e[2]), 0, centre),
                    mkface(far, v3_neg(e[2]), v3_neg(e[0]), 0, centre)};
                int mat;
                lc_scene *sc = new_scene(&mat);
                lc_shape box = {.kind = LC_BOX, .p = q, .u = e[0], .v = e[1], .w = e[2]};
                add_shape(sc, box, mat);
                compile(sc);
                for (int k = 0; k < 200; k++) {
                    int fixed = k % 3 + 1;
                    int first = (int)(lcg(&seed) * 3);
                    lc_vec3 to = q;
                    for (int j = 0; j < 3; j++) {
                        int ax = (first + j) % 3;
                        double a = j < fixed ? (double)(lcg(&seed) < 0.5)
                                             : 0.02 + 0.96 * lcg(&seed);
                        to = v3_madd(to, e[ax], a);
                    }
                    lc_vec3 out = v3_norm(v3_sub(to, centre));
                    lc_vec3 dir = rand_unit(&seed);
                    if (v3_dot(dir, out) < 0.3)
                        dir = v3_norm(v3_madd(dir, out, 1.3 - v3_dot(dir, out)));
                    lc_vec3 o = v3_madd(to, dir, 4 * s);
                    ray cam = mkray(o, v3_norm(v3_sub(to, o)));
                    hit h;
                    if (!intersect_closest(sc, &cam, HUGE_VAL, &h, NULL))
                        continue;                /* aimed at an edge, rounded off */
                    tested++;
                    /* out of the box: nothing, not even at t ~ 0 */
                    lc_vec3 w = rand_dir(&seed, h.n, 1, k);
                    if (leaves(fs, 6, h.p, w, tol, 4 * s) > 0) {
                        ray sr = mkray(spawn_origin(&h, w), w);
                        hit h2;
                        rays++;
                        if (intersect_closest(sc, &sr, HUGE_VAL, &h2, NULL))
                            bad[0]++;
                    }
                }
                lc_scene_free(sc);
            }
        }
    print_message("box solid: %d hits, %d rays going out, %d met the box\n", tested,
                  rays, bad[0]);
    if (bad[0])
        fail_msg("%d of %d rays spawned out of a box met it again", bad[0], rays);
}

/* ---- H6: thin walls ------------------------------------------------------- */

/* A coating: spheres r and 1.001 r, concentric. Rays from the centre hit the
** inner sphere from inside; from there a ray spawned outward (half of them
** grazing) must hit the outer shell, within its distance along that ray:
** a miss, or a hit on the inner sphere, is a leak. */
static void coating_does_not_leak(void **state)
{
    (void)state;
    int tested = 0, leaks = 0, self = 0, far_off = 0;
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            double s = scales[si];
            lc_vec3 c = shift_of(shifts[ti]);
            int mat;
            lc_scene *sc = new_scene(&mat);
            add_shape(sc, sphere_shape(c, s), mat);
            add_shape(sc, sphere_shape(c, 1.001 * s), mat);
            compile(sc);
            uint64_t seed = 7000 + si * 10 + ti;
            for (int k = 0; k < 300; k++) {
                ray from_c = mkray(c, rand_unit(&seed));
                hit h;
                assert_true(intersect_closest(sc, &from_c, HUGE_VAL, &h, NULL));
                assert_true(h.shape == PRIM_ID(PRIM_SPHERE, 0));
                tested++;
                lc_vec3 w = rand_dir(&seed, h.n, 1, k);
                ray sr = mkray(spawn_origin(&h, w), w);
                hit h2;
                if (!intersect_closest(sc, &sr, HUGE_VAL, &h2, NULL)) {
                    leaks++;
                    continue;
                }
                if (h2.shape != PRIM_ID(PRIM_SPHERE, 1)) {
                    self++;
                    continue;
                }
                /* along w from the inner surface, the outer shell is at most
                ** sqrt(1.001^2 - 1) r away (tangent) and at least 0.001 r */
                double t = h2.t;
                if (!(t >= 0.0009 * s && t <= 0.0448 * s))
                    far_off++;
            }
            lc_scene_free(sc);
        }
    print_message("coating: %d rays from the inner sphere, %d leaked, %d hit it again, "
                  "%d at a wrong distance\n", tested, leaks, self, far_off);
    if (leaks || self || far_off)
        fail_msg("of %d rays spawned outward from the inner sphere: %d missed the "
                 "shell, %d hit the inner sphere, %d met the shell at a wrong "
                 "distance", tested, leaks, self, far_off);
}

/* A slab 1e-6 s thick over a plane, the light above it: every shadow ray
** spawned from the plane under the slab's middle is occluded. */
static void thin_slab_occludes(void **state)
{
    (void)state;
    int tested = 0, leaks = 0;
    for (size_t si = 0; si < NSCALES; si++)
        for (size_t ti = 0; ti < NSHIFTS; ti++) {
            double s = scales[si];
            lc_vec3 o0 = shift_of(shifts[ti]);
            int mat;
            lc_scene *sc = new_scene(&mat);
            lc_shape plane = {.kind = LC_PLANE, .p = o0, .u = {0, 1, 0}};
            add_shape(sc, plane, mat);
            lc_shape slab = {.kind = LC_BOX, .p = v3_madd(o0, v3(-1, 1, -1), s), .u = {2 * s, 0, 0}, .v = {0, 1e-6 * s, 0}, .w = {0, 0, 2 * s}};
            add_shape(sc, slab, mat);
            /* the same slab tilted, further along x */
            lc_vec3 u = v3(2 * s * cos(0.3), 2 * s * sin(0.3), 0);
            lc_vec3 v = v3_mul(v3_norm(v3(-sin(0.3), cos(0.3), 0)), 1e-6 * s);
            lc_shape tilted = {.kind = LC_BOX, .p = v3_madd(o0, v3(4, 1, -1), s), .u = u, .v = v, .w = {0, 0, 2 * s}};
            add_shape(sc, tilted, mat);
            compile(sc);
            uint64_t seed = 8000 + si * 10 + ti;
            for (int k = 0; k < 200; k++) {
                double cx = k % 2 ? 5 : 0;
                lc_vec3 light = v3_madd(o0, v3(cx, 3, 0), s);
                lc_vec3 to = v3_madd(o0, v3(cx + 1.4 * (lcg(&seed) - 0.5), 0,
                                            1.4 * (lcg(&seed) - 0.5)), s);
                lc_vec3 from = v3_madd(to, v3(0.3, 1, -0.4), 0.5 * s);
                ray cam = mkray(from, v3_norm(v3_sub(to, from)));
                hit h;
                assert_true(intersect_closest(sc, &cam, HUGE_VAL, &h, NULL));
                assert_true(PRIM_KIND(h.shape) == PRIM_PLANE);
                tested++;
                lc_vec3 l = v3_sub(light, h.p);
                ray sr = mkray(spawn_origin(&h, l), v3_norm(l));
                double dist = v3_len(v3_sub(light, sr.o));
                if (!intersect_occluded(sc, &sr, dist * (1 - 1e-9), NULL))
                    leaks++;
            }
            lc_scene_free(sc);
        }
    print_message("thin slabs: %d shadow rays, %d leaked\n", tested, leaks);
    if (leaks)
        fail_msg("%d of %d shadow rays passed a 1e-6 s slab", leaks, tested);
}

/* ---- Oblikovati issue #2146 (docs/numerics.md 1.3) ------------------- */

/* The quad (-5,-5,0)..(5,5,0) as two triangles sharing the diagonal y = x;
** the ray from (0,0,10) toward (0.30458447, 0.30458447, -0.9024725) lands
** on the diagonal at (3.375, 3.375, 0), where float Moller-Trumbore misses. */
static void oblikovati_diagonal(void **state)
{
    (void)state;
    double tri_v[] = {-5, -5, 0, 5, -5, 0, 5, 5, 0, -5, 5, 0};
    uint32_t tri_f[] = {0, 1, 2, 0, 2, 3};
    ray r = mkray(v3(0, 0, 10), v3_norm(v3(0.30458447, 0.30458447, -0.9024725)));
    triangle_shear sh;
    triangle_shear_init(r.d, &sh);
    hit h;
    double bary[3];
    int a = triangle_hit(tri_v + 0, tri_v + 3, tri_v + 6, &r, &sh, 0, HUGE_VAL, &h, bary);
    int b = triangle_hit(tri_v + 0, tri_v + 6, tri_v + 9, &r, &sh, 0, HUGE_VAL, &h, bary);
    print_message("Oblikovati ray: first triangle %s, second %s\n", a ? "hit" : "miss",
                  b ? "hit" : "miss");
    assert_true(a || b);
    int mat;
    lc_scene *sc = new_scene(&mat);
    lc_error err;
    lc_mesh *m = lc_mesh_new(&err);
    assert_int_equal(lc_mesh_add_vertices(m, tri_v, 4, &err), LC_OK);
    assert_int_equal(lc_mesh_add_faces(m, tri_f, 2, &err), LC_OK);
    assert_true(lc_scene_add_mesh(sc, m, mat, &err) >= 0);
    compile(sc);
    assert_true(intersect_closest(sc, &r, HUGE_VAL, &h, NULL));
    if (!(fabs(h.p.x - 3.375) < 1e-6 && fabs(h.p.y - 3.375) < 1e-6 && h.p.z == 0))
        fail_msg("hit at (%.17g, %.17g, %.17g)", h.p.x, h.p.y, h.p.z);
    /* Every ray aimed at a point of the diagonal, from anywhere above or
    ** below, at the origin and moved to 1e7: no miss. */
    int missed = 0, total = 0;
    for (size_t ti = 0; ti < NSHIFTS; ti++) {
        lc_scene *s2 = new_scene(&mat);
        lc_mesh *m2 = lc_mesh_new(&err);
        double tv[12];
        lc_vec3 sh3 = shift_of(shifts[ti]);
        for (int i = 0; i < 4; i++) {
            tv[3 * i] = tri_v[3 * i] + sh3.x;
            tv[3 * i + 1] = tri_v[3 * i + 1] + sh3.y;
            tv[3 * i + 2] = tri_v[3 * i + 2] + sh3.z;
        }
        assert_int_equal(lc_mesh_add_vertices(m2, tv, 4, &err), LC_OK);
        assert_int_equal(lc_mesh_add_faces(m2, tri_f, 2, &err), LC_OK);
        assert_true(lc_scene_add_mesh(s2, m2, mat, &err) >= 0);
        lc_mesh_free(m2);
        compile(s2);
        uint64_t seed = 9000 + ti;
        for (int k = 0; k < 5000; k++) {
            /* points of the diagonal: exact binary fractions, so on it */
            double t = -4.5 + 9 * floor(lcg(&seed) * 1024) / 1024;
            lc_vec3 to = v3_add(v3(t, t, 0), sh3);
            lc_vec3 dir = rand_unit(&seed);
            if (fabs(dir.z) < 0.05)
                dir.z = 0.05;
            lc_vec3 o = v3_madd(to, dir, 10 * (0.2 + lcg(&seed)));
            ray aim = mkray(o, v3_norm(v3_sub(to, o)));
            total++;
            if (!intersect_closest(s2, &aim, HUGE_VAL, &h, NULL))
                missed++;
        }
        lc_scene_free(s2);
    }
    lc_mesh_free(m);
    lc_scene_free(sc);
    print_message("diagonal: %d of %d rays missed\n", missed, total);
    assert_int_equal(missed, 0);
}

/* ---- H12: the smallest spheres ---------------------------------------------- */

/* A sphere below the coordinate range (radius 1e-300: its r^2 underflows)
** is refused, naming the radius. One of the smallest radius accepted,
** LC_MIN_LENGTH, is hit exactly by a ray through its centre, the distance
** test and the full test agree, and a ray passing 10 radii beside it sees
** the wall behind (docs/numerics.md H12). */
static void tiny_sphere_is_exact(void **state)
{
    (void)state;
    int mat;
    lc_scene *sc = new_scene(&mat);
    lc_error err;
    lc_shape below = sphere_shape(v3(0, 0, 2), 1e-300);
    assert_int_equal(lc_scene_add_shape(sc, &below, mat, &err), -1);
    assert_string_equal(err.field, "radius");
    add_shape(sc, sphere_shape(v3(0, 0, 2), LC_MIN_LENGTH), mat);
    lc_shape wall = {.kind = LC_PLANE, .p = {0, 0, 5}, .u = {0, 0, -1}};
    add_shape(sc, wall, mat);
    compile(sc);
    ray r = mkray(v3(0, 0, -3), v3(0, 0, 1));
    sphere_geom g = *(const sphere_geom *)shape_at(&sc->shapes[LC_SPHERE], 0);
    hit h;
    double t = sphere_t(&g, &r, 0, HUGE_VAL);
    int full = sphere_hit(&g, &r, 0, HUGE_VAL, &h);
    int found = intersect_closest(sc, &r, HUGE_VAL, &h, NULL);
    assert_true(t > 0 && full && found && PRIM_KIND(h.shape) == PRIM_SPHERE);
    assert_true(fabs(h.t - 5) <= 1e-15);
    ray beside = mkray(v3(10 * LC_MIN_LENGTH, 0, -3), v3(0, 0, 1));
    found = intersect_closest(sc, &beside, HUGE_VAL, &h, NULL);
    int blocked = intersect_occluded(sc, &beside, 7.9, NULL);
    lc_scene_free(sc);
    if (!found || PRIM_KIND(h.shape) != PRIM_PLANE || blocked)
        fail_msg("10 radii beside a sphere of radius 1e-30 a ray %s, and %s before the "
                 "wall", !found ? "finds nothing" : PRIM_KIND(h.shape) == PRIM_PLANE ?
                 "finds the wall" : "finds the sphere", blocked ? "is blocked" : "is clear");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spawn_triangle),
        cmocka_unit_test(spawn_closed_mesh),
        cmocka_unit_test(spawn_cube_of_quads),
        cmocka_unit_test(spawn_box_solid),
        cmocka_unit_test(coating_does_not_leak),
        cmocka_unit_test(thin_slab_occludes),
        cmocka_unit_test(oblikovati_diagonal),
        cmocka_unit_test(tiny_sphere_is_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
