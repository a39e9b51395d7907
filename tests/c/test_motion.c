/* test_motion.c: transforms, moved shapes, mesh instances, and removing objects. */
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

/* ---- Helpers ------------------------------------------------------------- */

static lc_transform rotate(lc_vec3 axis, double deg)
{
    lc_transform t;
    lc_error err;
    assert_int_equal(lc_transform_rotate(axis, deg, &t, &err), LC_OK);
    return t;
}

static lc_transform compose(lc_transform a, lc_transform b)
{
    return lc_transform_compose(&a, &b);
}

/* A closed convex UV sphere of radius 1 at the origin: rings of `nlon`
** vertices, triangle fans at the poles. */
typedef struct {
    double   v[3 * 200];
    uint32_t f[3 * 400];
    size_t   nv, nf;
} uvs;

static void uvs_build(uvs *m, int nlat, int nlon)
{
    const double pi = 3.14159265358979323846;
    m->nv = m->nf = 0;
    double *v = m->v;
    v[0] = 0, v[1] = 1, v[2] = 0;
    m->nv = 1;
    for (int i = 1; i < nlat; i++)
        for (int j = 0; j < nlon; j++) {
            double th = pi * i / nlat, ph = 2 * pi * j / nlon;
            double *p = v + 3 * m->nv++;
            p[0] = sin(th) * cos(ph), p[1] = cos(th), p[2] = sin(th) * sin(ph);
        }
    double *p = v + 3 * m->nv++;
    p[0] = 0, p[1] = -1, p[2] = 0;
    uint32_t south = (uint32_t)m->nv - 1;
#define TRI(a, b, c) (m->f[3 * m->nf] = (a), m->f[3 * m->nf + 1] = (b), \
                      m->f[3 * m->nf + 2] = (c), m->nf++)
    for (int j = 0; j < nlon; j++) {
        uint32_t a = 1 + (uint32_t)j, b = 1 + (uint32_t)((j + 1) % nlon);
        TRI(0, b, a);
        uint32_t base = 1 + (uint32_t)((nlat - 2) * nlon);
        TRI(south, base + (uint32_t)j, base + (uint32_t)((j + 1) % nlon));
    }
    for (int i = 0; i < nlat - 2; i++)
        for (int j = 0; j < nlon; j++) {
            uint32_t a = 1 + (uint32_t)(i * nlon + j);
            uint32_t b = 1 + (uint32_t)(i * nlon + (j + 1) % nlon);
            uint32_t c = a + (uint32_t)nlon, d = b + (uint32_t)nlon;
            TRI(a, b, d);
            TRI(a, d, c);
        }
#undef TRI
}

static lc_mesh *uvs_mesh(const uvs *u, const lc_transform *moved)
{
    lc_error err;
    lc_mesh *m = lc_mesh_new(&err);
    assert_non_null(m);
    for (size_t i = 0; i < u->nv; i++) {
        lc_vec3 p = v3(u->v[3 * i], u->v[3 * i + 1], u->v[3 * i + 2]);
        if (moved)
            p = lc_transform_point(moved, p);
        double xyz[3] = {p.x, p.y, p.z};
        assert_int_equal(lc_mesh_add_vertices(m, xyz, 1, &err), LC_OK);
    }
    assert_int_equal(lc_mesh_add_faces(m, u->f, u->nf, &err), LC_OK);
    return m;
}

static lc_scene *new_scene(int *mat, double kr)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    assert_non_null(s);
    lc_camera cam = {{0.3, 2, -7}, {0, 0, 0}, {0, 1, 0}, 50, 0, 0};
    assert_int_equal(lc_scene_set_camera(s, &cam, &err), LC_OK);
    lc_material m = lc_material_default();
    m.kr = kr;
    m.ks = 0.5;
    *mat = lc_scene_add_material(s, &m, &err);
    lc_shape floor = {.kind = LC_PLANE, .p = {0, -2, 0}, .u = {0, 1, 0}};
    assert_true(lc_scene_add_shape(s, &floor, *mat, &err) >= 0);
    lc_point_light l = {{3, 5, -4}, {1, 1, 1}, 40, LC_FALLOFF_INVERSE_SQUARE};
    assert_true(lc_scene_add_light(s, &l, &err) >= 0);
    return s;
}

static lc_image *render(lc_scene *s, lc_stats *st)
{
    lc_error err;
    lc_render_options o = lc_render_options_default();
    o.width = 64;
    o.height = 48;
    lc_image *img = lc_scene_render(s, &o, st, &err);
    if (!img)
        fail_msg("render: %s", err.msg);
    return img;
}

/* The largest channel difference between two images of the same size. */
static double max_diff(const lc_image *a, const lc_image *b)
{
    double m = 0;
    for (int y = 0; y < lc_image_height(a); y++)
        for (int x = 0; x < lc_image_width(a); x++) {
            lc_color p = lc_image_get(a, x, y), q = lc_image_get(b, x, y);
            m = fmax(m, fmax(fabs(p.r - q.r), fmax(fabs(p.g - q.g), fabs(p.b - q.b))));
        }
    return m;
}

/* ---- Transforms ------------------------------------------------------------ */

static void rotations_are_exact_at_quarter_turns(void **state)
{
    (void)state;
    lc_transform r = rotate(v3(0, 1, 0), 90);
    const double want[3][4] = {{0, 0, 1, 0}, {0, 1, 0, 0}, {-1, 0, 0, 0}};
    assert_memory_equal(r.m, want, sizeof want);
    lc_vec3 p = lc_transform_point(&r, v3(1, 2, 3));      /* x goes to -z */
    assert_true(p.x == 3 && p.y == 2 && p.z == -1);
    r = rotate(v3(0, 0, 2), -270);                         /* = +90 about z */
    p = lc_transform_point(&r, v3(1, 0, 0));
    assert_true(p.x == 0 && p.y == 1 && p.z == 0);
    r = rotate(v3(1, 0, 0), 720);
    assert_true(lc_transform_is_identity(&r));
}

static void inverse_undoes_and_errors_name_the_field(void **state)
{
    (void)state;
    uint64_t seed = 7;
    lc_error err;
    for (int k = 0; k < 200; k++) {
        double sc = pow(10, 6 * lcg(&seed) - 3);
        lc_transform t = compose(lc_transform_translate(v3_mul(rand_unit(&seed), 1e3)),
                         compose(rotate(rand_unit(&seed), 360 * lcg(&seed)),
                                 lc_transform_scale(v3(sc, 2 * sc, 0.5 * sc))));
        lc_transform inv;
        assert_int_equal(lc_transform_inverse(&t, &inv, &err), LC_OK);
        lc_vec3 p = v3_mul(rand_unit(&seed), 10);
        lc_vec3 q = lc_transform_point(&inv, lc_transform_point(&t, p));
        /* the round trip rounds at 1e3 + 10 sc: well under 1e-9 */
        assert_true(v3_len(v3_sub(p, q)) < 1e-9 * (1 + 1e3 / sc));
    }
    lc_transform flat = lc_transform_scale(v3(1, 0, 1));
    assert_int_equal(lc_transform_check(&flat, &err), LC_EARG);
    assert_string_equal(err.field, "transform");
    assert_non_null(strstr(err.msg, "singular"));
    lc_transform shear = {{{1, 2, 0, 0}, {0.5, 1, 0, 0}, {0, 0, 1, 0}}};   /* rank 2 */
    assert_int_equal(lc_transform_inverse(&shear, &flat, &err), LC_EARG);
    assert_non_null(strstr(err.msg, "singular"));
    lc_transform bad = lc_transform_identity();
    bad.m[1][3] = NAN;
    assert_int_equal(lc_transform_check(&bad, &err), LC_EARG);
    assert_non_null(strstr(err.msg, "entry (2, 4) must be finite"));
    lc_transform tiny = lc_transform_scale(v3(1e-100, 1e-100, 1e-100));
    assert_int_equal(lc_transform_check(&tiny, &err), LC_OK);   /* small, not singular */
    assert_int_equal(lc_transform_rotate(v3(0, 0, 0), 10, &flat, &err), LC_EARG);
    assert_string_equal(err.field, "axis");
}

/* ---- Moved shapes ------------------------------------------------------------ */

static void shapes_move_exactly(void **state)
{
    (void)state;
    lc_error err;
    lc_transform t = compose(lc_transform_translate(v3(0.25, -1, 3)),
                     compose(rotate(v3(0, 1, 0), 90), lc_transform_scale(v3(2, 2, 2))));
    lc_shape ball = {.kind = LC_SPHERE, .p = {1, 0.5, -0.25}, .radius = 0.75};
    lc_shape out;
    assert_int_equal(lc_shape_transform(&ball, &t, &out, &err), LC_OK);
    /* (1, .5, -.25) * 2 = (2, 1, -.5), turned: (-.5, 1, -2), moved: (-.25, 0, 1) */
    assert_true(out.p.x == -0.25 && out.p.y == 0 && out.p.z == 1 && out.radius == 1.5);
    /* Stretched, a sphere becomes the ellipsoid of its radius, placed by the map. */
    lc_transform squash = lc_transform_scale(v3(1, 2, 1));
    assert_int_equal(lc_shape_transform(&ball, &squash, &out, &err), LC_OK);
    assert_int_equal(out.kind, LC_ELLIPSOID);
    assert_true(out.moved && out.u.x == 0.75 && out.u.y == 0.75 && out.u.z == 0.75);
    assert_memory_equal(&out.xf, &squash, sizeof squash);
    /* A box turned a quarter about y is the box with those edges, bit for bit. */
    lc_shape box = {.kind = LC_BOX, .p = {1, 0, 2}, .u = {2, 0, 0}, .v = {0, 1, 0}, .w = {0, 0, 3}};
    lc_shape want = {.kind = LC_BOX, .p = {2, 0, -1}, .u = {0, 0, -2}, .v = {0, 1, 0}, .w = {3, 0, 0}};
    lc_transform q = rotate(v3(0, 1, 0), 90);
    assert_int_equal(lc_shape_transform(&box, &q, &out, &err), LC_OK);
    assert_int_equal(out.kind, LC_BOX);
    lc_vec3 got[4] = {out.p, out.u, out.v, out.w}, exp[4] = {want.p, want.u, want.v, want.w};
    for (int i = 0; i < 4; i++)
        assert_true(got[i].x == exp[i].x && got[i].y == exp[i].y && got[i].z == exp[i].z);
    /* At 30 degrees each edge is within 1 ulp per component of the exact
    ** rotation (long double sines). */
    lc_transform r30 = rotate(v3(0, 1, 0), 30);
    assert_int_equal(lc_shape_transform(&box, &r30, &out, &err), LC_OK);
    long double c = cosl(3.14159265358979323846L / 6), s = sinl(3.14159265358979323846L / 6);
    lc_vec3 e[3] = {out.u, out.v, out.w}, src[3] = {box.u, box.v, box.w};
    for (int i = 0; i < 3; i++) {
        long double x = c * src[i].x + s * src[i].z, z = -s * src[i].x + c * src[i].z;
        double ex = nextafter(fabs((double)x), HUGE_VAL) - fabs((double)x);
        double ez = nextafter(fabs((double)z), HUGE_VAL) - fabs((double)z);
        assert_true(fabsl(e[i].x - x) <= ex && fabsl(e[i].z - z) <= ez);
        assert_true(e[i].y == src[i].y);
    }
    /* A plane's normal goes by the inverse transpose: a shear keeps it normal. */
    lc_shape pl = {.kind = LC_PLANE, .p = {0, 1, 0}, .u = {0, 1, 0}};
    lc_transform sh = {{{1, 1, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};   /* x += y */
    assert_int_equal(lc_shape_transform(&pl, &sh, &out, &err), LC_OK);
    lc_vec3 along = lc_transform_vector(&sh, v3(1, 0, 0)), up = lc_transform_vector(&sh,
                                                                        v3(0, 0, 1));
    assert_true(v3_dot(out.u, along) == 0 && v3_dot(out.u, up) == 0 && out.u.y > 0);
}

/* A sphere translated, turned and scaled draws the same bits as the sphere
** defined where it lands. */
static void moved_sphere_renders_identically(void **state)
{
    (void)state;
    lc_error err;
    lc_transform t = compose(lc_transform_translate(v3(0.5, 0.25, -1)),
                     compose(rotate(v3(1, 0, 0), 180), lc_transform_scale(v3(2, 2, 2))));
    lc_shape ball = {.kind = LC_SPHERE, .p = {0.25, 0.5, 0}, .radius = 0.5};
    lc_shape moved, direct = {.kind = LC_SPHERE, .p = {1, -0.75, -1}, .radius = 1};
    assert_int_equal(lc_shape_transform(&ball, &t, &moved, &err), LC_OK);
    int mat;
    lc_scene *a = new_scene(&mat, 0.3), *b = new_scene(&mat, 0.3);
    assert_true(lc_scene_add_shape(a, &moved, mat, &err) >= 0);
    assert_true(lc_scene_add_shape(b, &direct, mat, &err) >= 0);
    lc_image *ia = render(a, NULL), *ib = render(b, NULL);
    assert_true(max_diff(ia, ib) == 0);
    lc_image_free(ia);
    lc_image_free(ib);
    lc_scene_free(a);
    lc_scene_free(b);
}

/* ---- Mesh instances ------------------------------------------------------------ */

static void instances_store_the_mesh_once(void **state)
{
    (void)state;
    static uvs u;
    uvs_build(&u, 8, 12);
    lc_error err;
    lc_transform t1 = compose(lc_transform_translate(v3(-1.2, 0, 0)),
                              rotate(v3(1, 1, 0), 40));
    lc_transform t2 = compose(lc_transform_translate(v3(1.3, 0.2, 0.5)),
                              lc_transform_scale(v3(0.8, 1.2, 0.8)));
    int mat;
    lc_scene *inst = new_scene(&mat, 0.2), *flat = new_scene(&mat, 0.2);
    lc_mesh *m = uvs_mesh(&u, NULL);
    assert_true(lc_scene_add_mesh_moved(inst, m, &t1, mat, &err) >= 0);
    assert_true(lc_scene_add_mesh_moved(inst, m, &t2, mat, &err) >= 0);
    lc_mesh *m1 = uvs_mesh(&u, &t1), *m2 = uvs_mesh(&u, &t2);
    assert_true(lc_scene_add_mesh(flat, m1, mat, &err) >= 0);
    assert_true(lc_scene_add_mesh(flat, m2, mat, &err) >= 0);
    lc_stats si, sf;
    lc_image *ii = render(inst, &si), *iflat = render(flat, &sf);
    /* the plane, plus the mesh's faces once; the copies hold them twice */
    assert_int_equal(si.primitives, 1 + u.nf);
    assert_int_equal(sf.primitives, 1 + 2 * u.nf);
    assert_int_equal(inst->nblas, 1);
    assert_int_equal(inst->c.ninstances, 2);
    assert_int_equal(si.self_hits, 0);
    double d = max_diff(ii, iflat);
    print_message("two instances vs two moved copies: largest difference %.3g\n", d);
    assert_true(d <= 1.0 / 255);
    lc_image_free(ii);
    lc_image_free(iflat);
    lc_mesh_free(m);
    lc_mesh_free(m1);
    lc_mesh_free(m2);
    lc_scene_free(inst);
    lc_scene_free(flat);
}

/* A quarter turn is exact, so the instance and the mesh built turned are the
** same triangles; only the order of roundings in the hit point differs. */
static void quarter_turn_instance_matches_turned_vertices(void **state)
{
    (void)state;
    static uvs u;
    uvs_build(&u, 8, 12);
    lc_error err;
    lc_transform t = compose(lc_transform_translate(v3(0.5, 0, 0)), rotate(v3(0, 1, 0), 90));
    int mat;
    lc_scene *inst = new_scene(&mat, 0.3), *flat = new_scene(&mat, 0.3);
    lc_mesh *m = uvs_mesh(&u, NULL), *mt = uvs_mesh(&u, &t);
    assert_true(lc_scene_add_mesh_moved(inst, m, &t, mat, &err) >= 0);
    assert_true(lc_scene_add_mesh(flat, mt, mat, &err) >= 0);
    lc_image *ii = render(inst, NULL), *iflat = render(flat, NULL);
    double d = max_diff(ii, iflat);
    print_message("quarter-turn instance vs turned vertices: largest difference %.3g\n", d);
    assert_true(d <= 1e-6);
    lc_image_free(ii);
    lc_image_free(iflat);
    lc_mesh_free(m);
    lc_mesh_free(mt);
    lc_scene_free(inst);
    lc_scene_free(flat);
}

/* Rays spawned from hits on an instanced closed convex mesh, moved by a
** rotation, a shear and a translation at scales 1e-3..1e3: going out they
** meet nothing; going in (half of them grazing) they meet another face,
** never the one they leave, and never escape. */
static void instance_spawns_never_self_hit(void **state)
{
    (void)state;
    static uvs u;
    uvs_build(&u, 10, 16);
    const double scales[] = {1e-3, 1, 1e3};
    const double shifts[] = {0, 1e3, 1e5};
    int tested = 0, out_hit = 0, lost = 0, self = 0;
    uint64_t seed = 99;
    for (int si = 0; si < 3; si++)
        for (int ti = 0; ti < 6; ti++) {
            double s = scales[si];
            lc_vec3 c = v3(shifts[ti % 3], shifts[ti % 3] / 2, -shifts[ti % 3] / 3);
            lc_transform shear = {{{1, 0.3, 0, 0}, {0, 1, 0.2, 0}, {0, 0, 1, 0}}};
            /* half of them flattened 1000:1, turned off the axes */
            double flat = ti < 3 ? 1.5 : 1e-3;
            lc_transform t = compose(lc_transform_translate(c),
                             compose(rotate(rand_unit(&seed), 360 * lcg(&seed)),
                             compose(shear, lc_transform_scale(v3(s, flat * s, s)))));
            lc_error err;
            lc_scene *sc = lc_scene_new(&err);
            lc_material mat = lc_material_default();
            int mi = lc_scene_add_material(sc, &mat, &err);
            lc_mesh *m = uvs_mesh(&u, NULL);
            assert_true(lc_scene_add_mesh_moved(sc, m, &t, mi, &err) >= 0);
            lc_mesh_free(m);
            assert_int_equal(plan_scene(sc, NULL, 0, &err), LC_OK);
            for (int k = 0; k < 400; k++) {
                const uint32_t *f = u.f + 3 * (k % u.nf);
                lc_vec3 p[3];
                for (int j = 0; j < 3; j++)
                    p[j] = lc_transform_point(&t, v3(u.v[3 * f[j]], u.v[3 * f[j] + 1],
                                                     u.v[3 * f[j] + 2]));
                lc_vec3 to = k % 3 == 0 ? p[0] : k % 3 == 1 ? v3_mul(v3_add(p[0], p[1]), 0.5)
                           : v3_add(v3_mul(p[0], 0.2), v3_add(v3_mul(p[1], 0.3),
                                                              v3_mul(p[2], 0.5)));
                lc_vec3 out = v3_norm(v3_sub(to, c));
                lc_vec3 o = v3_madd(to, out, 3 * s);
                if (flat < 1)          /* face on: the flat sides' normals */
                    o = v3_madd(to, v3_norm(lc_transform_vector(&t, v3(0, 1, 0))),
                                (k % 2 ? 3 : -3) * s);
                ray cam = {o, v3_norm(v3_sub(to, o))};
                hit h;
                if (!intersect_closest(sc, &cam, HUGE_VAL, &h, NULL)) {
                    if (k % 3 == 2)    /* vertices and edges may be on the silhouette */
                        fail_msg("camera ray %d missed the instance at scale %g", k, s);
                    continue;
                }
                tested++;
                lc_vec3 n = v3_dot(h.n, cam.d) < 0 ? h.n : v3_neg(h.n);   /* outward */
                /* out: at least 0.1 off the tangent plane, so no edge is grazed */
                lc_vec3 w = rand_unit(&seed);
                w = v3_norm(v3_madd(w, n, 1.1 - v3_dot(w, n)));
                ray sr = {spawn_origin(&h, w), w};
                hit h2;
                if (intersect_closest(sc, &sr, HUGE_VAL, &h2, NULL))
                    out_hit++;
                /* in: uniform, or within 1e-12..1e-1 rad of the tangent plane */
                w = rand_unit(&seed);
                if (k % 2) {
                    lc_vec3 tg = v3_norm(v3_madd(w, n, -v3_dot(w, n)));
                    w = v3_norm(v3_madd(tg, n, -pow(10, -1 - 11 * lcg(&seed))));
                }
                if (v3_dot(w, n) > 0)
                    w = v3_madd(w, n, -2 * v3_dot(w, n));
                sr.o = spawn_origin(&h, w);
                sr.d = w;
                if (!intersect_closest(sc, &sr, HUGE_VAL, &h2, NULL))
                    lost += k % 3 == 2;    /* at a vertex or an edge "in" may leave */
                else if (h2.shape == h.shape)
                    self++;
            }
            lc_scene_free(sc);
        }
    print_message("instance spawns: %d hits, %d out rays hit it, %d in rays lost, %d "
                  "self-hits\n", tested, out_hit, lost, self);
    assert_int_equal(out_hit + lost + self, 0);
}

/* Mirrors facing an instanced closed mesh at scales 1e-3, 1, 1e3: the
** renderer's own count of reflection rays meeting their surface is 0. */
static void instance_mirror_renders_have_no_self_hits(void **state)
{
    (void)state;
    static uvs u;
    uvs_build(&u, 10, 16);
    const double scales[] = {1e-3, 1, 1e3};
    for (int si = 0; si < 3; si++) {
        double s = scales[si];
        lc_error err;
        lc_scene *sc = lc_scene_new(&err);
        lc_camera cam = {{0.3 * s, 2 * s, -7 * s}, {0, 0, 0}, {0, 1, 0}, 50, 0, 0};
        lc_scene_set_camera(sc, &cam, &err);
        lc_material m = lc_material_default();
        m.kr = 0.8;
        int mi = lc_scene_add_material(sc, &m, &err);
        lc_mesh *mesh = uvs_mesh(&u, NULL);
        for (int k = 0; k < 3; k++) {
            lc_transform t = compose(lc_transform_translate(v3((k - 1) * 2.2 * s, 0, 0)),
                             compose(rotate(v3(1, 2, 3), 25.0 * k),
                                     lc_transform_scale(v3(s, s * (1 + 0.3 * k), s))));
            assert_true(lc_scene_add_mesh_moved(sc, mesh, &t, mi, &err) >= 0);
        }
        lc_mesh_free(mesh);
        lc_point_light l = {{3 * s, 5 * s, -4 * s}, {1, 1, 1}, 40 * s * s,
                            LC_FALLOFF_INVERSE_SQUARE};
        lc_scene_add_light(sc, &l, &err);
        lc_stats st;
        lc_image *img = render(sc, &st);
        assert_true(st.rays[LC_RAY_REFLECTION] > 300);
        assert_int_equal(st.self_hits, 0);
        assert_int_equal(lc_image_nonfinite(img), 0);
        lc_image_free(img);
        lc_scene_free(sc);
    }
}

/* ---- Listing and removing objects -------------------------------------------- */

static int add_ball(lc_scene *s, double x, int mat)
{
    lc_error err;
    lc_shape b = {.kind = LC_SPHERE, .p = {x, 0, 0}, .radius = 0.4};
    return lc_scene_add_shape(s, &b, mat, &err);
}

/* Builds the test scene; skip[k] leaves object k out. Returns the ids. */
static void build(lc_scene *s, int mat, int glow, lc_mesh *mesh, const int skip[6],
                  int ids[6])
{
    lc_error err;
    lc_transform t = compose(lc_transform_translate(v3(0, 1, 0)), rotate(v3(0, 0, 1), 30));
    lc_shape box = {.kind = LC_BOX, .p = {-2, -1, 1}, .u = {0.5, 0, 0}, .v = {0, 0.5, 0}, .w = {0, 0, 0.5}};
    lc_shape lamp = {.kind = LC_SPHERE, .p = {0, 2.5, 0}, .radius = 0.2};
    lc_point_light l = {{-3, 4, -4}, {1, 1, 1}, 20, LC_FALLOFF_INVERSE_SQUARE};
    for (int k = 0; k < 6; k++) {
        ids[k] = -1;
        if (skip[k])
            continue;
        switch (k) {
        case 0: ids[k] = add_ball(s, -1, mat); break;
        case 1: ids[k] = lc_scene_add_mesh_moved(s, mesh, &t, mat, &err); break;
        case 2: ids[k] = lc_scene_add_shape(s, &lamp, glow, &err); break;
        case 3: ids[k] = add_ball(s, 1, mat); break;
        case 4: ids[k] = lc_scene_add_light(s, &l, &err); break;
        default: ids[k] = lc_scene_add_shape(s, &box, mat, &err); break;
        }
    }
}

static void removing_equals_never_adding(void **state)
{
    (void)state;
    static uvs u;
    uvs_build(&u, 6, 8);
    lc_error err;
    lc_mesh *mesh = uvs_mesh(&u, NULL);
    for (int drop = 0; drop < 6; drop++) {
        int mat;
        lc_scene *a = new_scene(&mat, 0.3), *b = new_scene(&mat, 0.3);
        lc_material g = lc_material_default();
        g.emission = (lc_color){4, 4, 3};
        int ga = lc_scene_add_material(a, &g, &err), gb = lc_scene_add_material(b, &g, &err);
        int none[6] = {0}, skip[6] = {0}, ids[6], idsb[6];
        skip[drop] = 1;
        build(a, mat, ga, mesh, none, ids);
        build(b, mat, gb, mesh, skip, idsb);
        lc_stats st;
        lc_image_free(render(a, &st));           /* compiled once with everything */
        size_t before = lc_scene_object_count(a);
        assert_int_equal(lc_scene_remove(a, ids[drop], &err), LC_OK);
        assert_int_equal(lc_scene_object_count(a), before - 1);
        lc_stats sa, sb;
        lc_image *ia = render(a, &sa), *ib = render(b, &sb);
        assert_true(max_diff(ia, ib) == 0);
        assert_int_equal(sa.primitives, sb.primitives);
        assert_int_equal(sa.bvh_nodes, sb.bvh_nodes);
        assert_int_equal(sa.rays[LC_RAY_SHADOW], sb.rays[LC_RAY_SHADOW]);
        assert_int_equal(sa.rays[LC_RAY_REFLECTION], sb.rays[LC_RAY_REFLECTION]);
        /* the others keep their ids, in the order added */
        lc_object objs[8];
        size_t n = lc_scene_objects(a, objs, 8);
        assert_int_equal(n, before - 1);
        for (size_t i = 1; i < n; i++)
            assert_true(objs[i].id > objs[i - 1].id);
        for (size_t i = 0; i < n; i++)
            assert_true(objs[i].id != ids[drop]);
        assert_int_equal(lc_scene_remove(a, ids[drop], &err), LC_EARG);
        assert_string_equal(err.field, "id");
        assert_non_null(strstr(err.msg, "was removed"));
        lc_image_free(ia);
        lc_image_free(ib);
        lc_scene_free(a);
        lc_scene_free(b);
    }
    lc_mesh_free(mesh);
}

static void objects_list_what_was_added(void **state)
{
    (void)state;
    lc_error err;
    int mat;
    lc_scene *s = new_scene(&mat, 0);         /* a plane (id 0) and a light (id 1) */
    static uvs u;
    uvs_build(&u, 4, 6);
    lc_mesh *mesh = uvs_mesh(&u, NULL);
    lc_transform t = lc_transform_translate(v3(1, 2, 3));
    assert_int_equal(add_ball(s, 5, mat), 2);
    assert_int_equal(lc_scene_add_mesh_moved(s, mesh, &t, mat, &err), 3);
    assert_int_equal(lc_scene_add_mesh(s, mesh, mat, &err), 4);
    lc_object o[5];
    assert_int_equal(lc_scene_objects(s, o, 5), 5);
    assert_int_equal(o[0].kind, LC_OBJECT_SHAPE);
    assert_int_equal(o[0].shape.kind, LC_PLANE);
    assert_int_equal(o[1].kind, LC_OBJECT_LIGHT);
    assert_int_equal(o[1].material, -1);
    assert_true(o[2].shape.kind == LC_SPHERE && o[2].shape.p.x == 5 && o[2].shape.radius == 0.4);
    assert_true(o[3].kind == LC_OBJECT_MESH && o[3].moved && o[3].mesh == mesh);
    assert_true(o[3].transform.m[2][3] == 3);
    assert_true(o[4].kind == LC_OBJECT_MESH && !o[4].moved);
    assert_int_equal(lc_scene_object(s, 9, o, &err), LC_EARG);
    assert_non_null(strstr(err.msg, "never added"));
    assert_int_equal(lc_scene_remove(s, 3, &err), LC_OK);
    assert_int_equal(lc_scene_shape_count(s), 3);
    assert_int_equal(add_ball(s, 6, mat), 5);      /* ids are never given again */
    lc_mesh_free(mesh);
    lc_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rotations_are_exact_at_quarter_turns),
        cmocka_unit_test(inverse_undoes_and_errors_name_the_field),
        cmocka_unit_test(shapes_move_exactly),
        cmocka_unit_test(moved_sphere_renders_identically),
        cmocka_unit_test(instances_store_the_mesh_once),
        cmocka_unit_test(quarter_turn_instance_matches_turned_vertices),
        cmocka_unit_test(instance_spawns_never_self_hit),
        cmocka_unit_test(instance_mirror_renders_have_no_self_hits),
        cmocka_unit_test(removing_equals_never_adding),
        cmocka_unit_test(objects_list_what_was_added),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
