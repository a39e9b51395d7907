/* test_query.c: rays cast through the C API (lc_scene_intersect,
** lc_scene_occluded): distances, points and normals against closed forms,
** each shape's texture coordinates, the ids of what was hit, and bad rays. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "lancer.h"
#include "helpers.h"

#define PI 3.14159265358979323846

static lc_scene *scene_with(const lc_shape *shapes, int n, int *ids)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    assert_non_null(s);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    for (int i = 0; i < n; i++) {
        int id = lc_scene_add_shape(s, &shapes[i], mi, &err);
        if (id < 0)
            fail_msg("shape %d: %s: %s", i, err.field, err.msg);
        if (ids)
            ids[i] = id;
    }
    return s;
}

static lc_ray_hit cast(lc_scene *s, lc_vec3 o, lc_vec3 d)
{
    lc_ray r = {o, d, 0, HUGE_VAL};
    lc_ray_hit h;
    lc_error err;
    if (lc_scene_intersect(s, &r, 1, &h, &err))
        fail_msg("%s", err.msg);
    return h;
}

/* A unit sphere seen along every axis: t, point, normal exact; longitude
** and latitude as the manual gives them. */
static void sphere_hits_and_uvs(void **state)
{
    (void)state;
    lc_shape ball = {.kind = LC_SPHERE, .p = {1, 2, 3}, .radius = 2};
    int id;
    lc_scene *s = scene_with(&ball, 1, &id);
    static const struct { lc_vec3 d; double u, v; } dirs[] = {
        {{0, 0, 1}, 0.5, 0.5}, {{1, 0, 0}, 0.75, 0.5}, {{-1, 0, 0}, 0.25, 0.5},
        {{0, 1, 0}, 0.5, 1}, {{0, -1, 0}, 0.5, 0}};
    for (size_t i = 0; i < sizeof dirs / sizeof *dirs; i++) {
        lc_vec3 d = dirs[i].d;
        /* From 10 out along d, looking back at the centre. */
        lc_vec3 o = {1 + 10 * d.x, 2 + 10 * d.y, 3 + 10 * d.z};
        lc_ray_hit h = cast(s, o, (lc_vec3){-d.x, -d.y, -d.z});
        assert_int_equal(h.hit, 1);
        assert_true(h.t == 8);
        assert_true(h.point.x == 1 + 2 * d.x && h.point.y == 2 + 2 * d.y &&
                    h.point.z == 3 + 2 * d.z);
        assert_true(h.normal.x == d.x && h.normal.y == d.y && h.normal.z == d.z);
        near(h.uv[0], dirs[i].u, 1e-15, "u");
        near(h.uv[1], dirs[i].v, 1e-15, "v");
        assert_int_equal(h.object, id);
        assert_int_equal(h.shape_kind, LC_SPHERE);
        assert_int_equal(h.primitive, 0);
        assert_int_equal(h.material, 0);
    }
    /* Latitude 30 degrees north, longitude 45 east of +z. */
    double la = PI / 6, lo = PI / 4;
    lc_vec3 d = {cos(la) * sin(lo), sin(la), cos(la) * cos(lo)};
    lc_ray_hit h = cast(s, (lc_vec3){1 + 10 * d.x, 2 + 10 * d.y, 3 + 10 * d.z},
                        (lc_vec3){-d.x, -d.y, -d.z});
    near(h.uv[0], 0.5 + 0.125, 1e-14, "u at 45 degrees");
    near(h.uv[1], 0.5 + 1.0 / 6, 1e-14, "v at 30 degrees");
    lc_scene_free(s);
}

/* t counts in units of the direction given, and tmin starts the ray later. */
static void distances_in_units_of_the_direction(void **state)
{
    (void)state;
    lc_shape ball = {.kind = LC_SPHERE, .p = {0, 0, 0}, .radius = 1};
    lc_scene *s = scene_with(&ball, 1, NULL);
    lc_ray r[4] = {{{0, 0, 5}, {0, 0, -2}, 0, HUGE_VAL},
                   {{0, 0, 5}, {0, 0, -1}, 4.5, HUGE_VAL},   /* starts inside: the far side */
                   {{0, 0, 5}, {0, 0, -1}, 0, 3.999},        /* stops short */
                   {{0, 0, 5}, {0, 0, -1e-3}, 0, HUGE_VAL}};
    lc_ray_hit h[4];
    unsigned char blocked[4];
    lc_error err;
    assert_int_equal(lc_scene_intersect(s, r, 4, h, &err), LC_OK);
    assert_int_equal(lc_scene_occluded(s, r, 4, blocked, &err), LC_OK);
    assert_true(h[0].hit && h[0].t == 2 && h[0].point.z == 1);
    assert_true(h[1].hit && h[1].t == 6 && h[1].point.z == -1 && h[1].normal.z == -1);
    assert_false(h[2].hit);
    assert_true(h[3].hit && h[3].t == 4000);
    for (int i = 0; i < 4; i++)
        assert_int_equal(blocked[i], h[i].hit);
    lc_scene_free(s);
}

/* Every kind's texture coordinates at points where the manual's
** conventions give them in closed form. */
static void each_kind_has_its_uvs(void **state)
{
    (void)state;
    lc_shape shapes[] = {
        {.kind = LC_QUAD, .p = {-10, 0, 0}, .u = {4, 0, 0}, .v = {0, 2, 0}},
        {.kind = LC_BOX, .p = {10, 0, 0}, .u = {2, 0, 0}, .v = {0, 4, 0}, .w = {0, 0, 8}},
        {.kind = LC_PLANE, .p = {0, -5, 0}, .u = {0, 1, 0}},
        {.kind = LC_DISC, .p = {0, 10, 0}, .u = {0, 0, 1}, .radius = 2},
        {.kind = LC_CYLINDER, .p = {0, 20, 0}, .u = {0, 4, 0}, .radius = 1, .caps = 1},
        {.kind = LC_TORUS, .p = {0, 30, 0}, .u = {0, 1, 0}, .radius = 2, .radius2 = 0.5},
        {.kind = LC_ELLIPSOID, .p = {0, 40, 0}, .u = {1, 2, 3}},
    };
    int ids[7];
    lc_scene *s = scene_with(shapes, 7, ids);
    /* Quad: (alpha, beta) of the point (-9, 1.5): 1/4 along u, 3/4 along v. */
    lc_ray_hit h = cast(s, (lc_vec3){-9, 1.5, -5}, (lc_vec3){0, 0, 1});
    assert_true(h.hit && h.object == ids[0] && h.shape_kind == LC_QUAD);
    assert_true(h.uv[0] == 0.25 && h.uv[1] == 0.75);
    /* Box: the face z = 0 (across edge w) reads (a, b) along u and v. */
    h = cast(s, (lc_vec3){10.5, 3, -5}, (lc_vec3){0, 0, 1});
    assert_true(h.hit && h.object == ids[1] && h.point.z == 0 && h.normal.z == -1);
    assert_true(h.uv[0] == 0.25 && h.uv[1] == 0.75);
    /* ... the face x = 12 (across u) reads (b, c) along v and w. */
    h = cast(s, (lc_vec3){20, 1, 2}, (lc_vec3){-1, 0, 0});
    assert_true(h.hit && h.point.x == 12 && h.uv[0] == 0.25 && h.uv[1] == 0.25);
    /* Floor: u = x, v = -z from its point. */
    h = cast(s, (lc_vec3){3, 0, 7}, (lc_vec3){0, -1, 0});
    assert_true(h.hit && h.object == ids[2] && h.uv[0] == 3 && h.uv[1] == -7);
    /* Disc of radius 2: the turn around its normal, the radius over 2. */
    h = cast(s, (lc_vec3){1, 10, -5}, (lc_vec3){0, 0, 1});
    assert_true(h.hit && h.object == ids[3]);
    near(h.uv[1], 0.5, 1e-15, "disc radius");
    lc_ray_hit h2 = cast(s, (lc_vec3){-1, 10, -5}, (lc_vec3){0, 0, 1});
    near(fabs(h.uv[0] - h2.uv[0]), 0.5, 1e-15, "disc: opposite points half a turn apart");
    /* Cylinder: height over length on the side, radius on the caps. */
    h = cast(s, (lc_vec3){5, 21, 0}, (lc_vec3){-1, 0, 0});
    assert_true(h.hit && h.object == ids[4] && h.point.x == 1);
    near(h.uv[1], 0.25, 1e-15, "cylinder side height");
    h = cast(s, (lc_vec3){0.5, 30 - 2.5, 0}, (lc_vec3){0, -1, 0});  /* into the top cap */
    assert_true(h.hit && h.object == ids[4]);
    near(h.point.y, 24, 1e-14, "cylinder top");
    near(h.uv[1], 0.5, 1e-15, "cap radius");
    /* Torus: the outer equator is v = 0.5, the top of the tube 0.75. */
    h = cast(s, (lc_vec3){5, 30, 0}, (lc_vec3){-1, 0, 0});
    assert_true(h.hit && h.object == ids[5]);
    near(h.point.x, 2.5, 1e-14, "torus outer");
    near(h.uv[1], 0.5, 1e-15, "torus outer equator");
    h = cast(s, (lc_vec3){2, 35, 0}, (lc_vec3){0, -1, 0});
    near(h.point.y, 30.5, 1e-14, "torus top");
    near(h.uv[1], 0.75, 1e-15, "torus top of the tube");
    /* Ellipsoid: the unit sphere's longitude and latitude, placed. */
    h = cast(s, (lc_vec3){0, 40, 10}, (lc_vec3){0, 0, -1});
    assert_true(h.hit && h.object == ids[6]);
    near(h.point.z, 3, 1e-14, "ellipsoid front");
    near(h.uv[0], 0.5, 1e-15, "ellipsoid u");
    near(h.uv[1], 0.5, 1e-15, "ellipsoid v");
    h = cast(s, (lc_vec3){0, 50, 0}, (lc_vec3){0, -1, 0});
    near(h.point.y, 42, 1e-14, "ellipsoid top");
    near(h.uv[1], 1, 1e-15, "ellipsoid pole");
    lc_scene_free(s);
}

/* Meshes: their uvs interpolated, or barycentric weights without them; a
** moved mesh is named by its placement; the face by its index. */
static void meshes_name_their_faces(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    lc_scene_add_material(s, &m, &err);
    m.kd = 0.5;
    int mi = lc_scene_add_material(s, &m, &err);      /* the second: index 1 */
    lc_mesh *a = lc_mesh_new(&err), *b = lc_mesh_new(&err);
    const double v[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const double vb[] = {-5, 0, 0, -4, 0, 0, -4, 1, 0, -5, 1, 0};
    const double uv[] = {0, 0, 2, 0, 2, 2, 0, 2};
    const uint32_t f[] = {0, 1, 2, 0, 2, 3};
    assert_int_equal(lc_mesh_add_vertices(a, v, 4, &err), LC_OK);
    assert_int_equal(lc_mesh_add_uvs(a, uv, 4, &err), LC_OK);
    assert_int_equal(lc_mesh_add_faces(a, f, 2, &err), LC_OK);
    assert_int_equal(lc_mesh_add_vertices(b, vb, 4, &err), LC_OK);
    assert_int_equal(lc_mesh_add_faces(b, f, 2, &err), LC_OK);
    /* What a mesh holds reads back as it was given. */
    assert_memory_equal(lc_mesh_vertex_data(a), v, sizeof v);
    assert_memory_equal(lc_mesh_face_data(a), f, sizeof f);
    int ia = lc_scene_add_mesh(s, a, mi, &err);
    int ib = lc_scene_add_mesh(s, b, mi, &err);
    lc_transform t = {{{1, 0, 0, 5}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    int i1 = lc_scene_add_mesh_moved(s, a, &t, mi, &err);
    t.m[0][3] = 10;
    int i2 = lc_scene_add_mesh_moved(s, a, &t, mi, &err);
    assert_true(ia >= 0 && ib >= 0 && i1 >= 0 && i2 >= 0);
    lc_ray_hit h = cast(s, (lc_vec3){0.75, 0.25, -1}, (lc_vec3){0, 0, 1});
    assert_true(h.hit && h.object == ia && h.shape_kind == LC_SHAPE_KINDS);
    assert_int_equal(h.primitive, 0);
    near(h.uv[0], 1.5, 1e-15, "mesh u");
    near(h.uv[1], 0.5, 1e-15, "mesh v");
    assert_int_equal(h.material, mi);
    h = cast(s, (lc_vec3){0.25, 0.75, -1}, (lc_vec3){0, 0, 1});
    assert_int_equal(h.primitive, 1);
    /* Without uvs: the weights of the face's second and third corners. */
    h = cast(s, (lc_vec3){-5 + 0.75, 0.25, -1}, (lc_vec3){0, 0, 1});
    assert_true(h.hit && h.object == ib);
    near(h.uv[0], 0.5, 1e-15, "barycentric 1");
    near(h.uv[1], 0.25, 1e-15, "barycentric 2");
    /* Two placements of one mesh share its faces, not its id. */
    h = cast(s, (lc_vec3){5.5, 0.5, -1}, (lc_vec3){0, 0, 1});
    assert_true(h.hit && h.object == i1);
    lc_ray_hit g = cast(s, (lc_vec3){10.5, 0.5, -1}, (lc_vec3){0, 0, 1});
    assert_true(g.hit && g.object == i2 && g.primitive == h.primitive);
    near(g.uv[0], h.uv[0], 1e-15, "placements' uvs");
    lc_mesh_free(a);
    lc_mesh_free(b);
    lc_scene_free(s);
}

/* A bad ray fails the call, naming it, before anything is traced. */
static void bad_rays_are_named(void **state)
{
    (void)state;
    lc_shape ball = {.kind = LC_SPHERE, .p = {0, 0, 0}, .radius = 1};
    lc_scene *s = scene_with(&ball, 1, NULL);
    static const struct { lc_ray r; const char *msg; } bad[] = {
        {{{0, 0, NAN}, {0, 0, 1}, 0, HUGE_VAL}, "ray 2: origin"},
        {{{0, 0, 1e31}, {0, 0, 1}, 0, HUGE_VAL}, "ray 2: origin must be within"},
        {{{0, 0, 5}, {0, 0, 0}, 0, HUGE_VAL}, "ray 2: direction must not be zero-length"},
        {{{0, 0, 5}, {0, INFINITY, 0}, 0, HUGE_VAL}, "ray 2: direction"},
        {{{0, 0, 5}, {0, 0, -1}, 2, 1}, "ray 2: needs 0 <= tmin < tmax"},
        {{{0, 0, 5}, {0, 0, -1}, -1, 1}, "ray 2: needs 0 <= tmin < tmax"},
        {{{0, 0, 5}, {0, 0, -1}, 0, NAN}, "ray 2: needs 0 <= tmin < tmax"},
        {{{0, 0, 5}, {0, 0, -1}, INFINITY, INFINITY}, "ray 2: needs 0 <= tmin < tmax"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        lc_ray r[3] = {{{0, 0, 5}, {0, 0, -1}, 0, HUGE_VAL}, bad[i].r,
                       {{0, 0, 5}, {0, 0, -1}, 0, HUGE_VAL}};
        lc_ray_hit h[3];
        memset(h, 0x5a, sizeof h);
        unsigned char blocked[3] = {7, 7, 7};
        lc_error err;
        assert_int_equal(lc_scene_intersect(s, r, 3, h, &err), LC_EARG);
        if (!strstr(err.msg, bad[i].msg))
            fail_msg("case %zu: '%s' lacks '%s'", i, err.msg, bad[i].msg);
        assert_string_equal(err.field, "rays");
        assert_int_equal(h[0].hit, 0x5a5a5a5a);       /* nothing traced */
        assert_int_equal(lc_scene_occluded(s, r, 3, blocked, &err), LC_EARG);
        assert_int_equal(blocked[0], 7);
    }
    lc_scene_free(s);
}

/* intersect and occluded agree on every ray of a random set, and the
** point found lies on the ray at the distance found. */
static void intersect_and_occluded_agree(void **state)
{
    (void)state;
    lc_shape shapes[] = {
        {.kind = LC_SPHERE, .p = {0, 0, 0}, .radius = 1},
        {.kind = LC_BOX, .p = {2, -1, -1}, .u = {1, 0, 0}, .v = {0, 2, 0}, .w = {0, 0, 2}},
        {.kind = LC_TORUS, .p = {-3, 0, 0}, .u = {1, 1, 0}, .radius = 1, .radius2 = 0.3},
        {.kind = LC_CONE, .p = {0, 2, 0}, .u = {0, 1, 0}, .radius = 1, .radius2 = 0,
         .caps = 1},
    };
    lc_scene *s = scene_with(shapes, 4, NULL);
    enum { N = 20000 };
    lc_ray *r = malloc(N * sizeof *r);
    lc_ray_hit *h = malloc(N * sizeof *h);
    unsigned char *blocked = malloc(N);
    uint64_t x = 88172645463325252u;
    for (int i = 0; i < N; i++) {
        double q[6];
        for (int k = 0; k < 6; k++) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17;
            q[k] = (double)(x >> 11) / 9007199254740992.0 * 8 - 4;
        }
        r[i] = (lc_ray){{q[0], q[1], q[2]}, {q[3], q[4], q[5]}, 0, HUGE_VAL};
    }
    lc_error err;
    assert_int_equal(lc_scene_intersect(s, r, N, h, &err), LC_OK);
    assert_int_equal(lc_scene_occluded(s, r, N, blocked, &err), LC_OK);
    int hits = 0;
    for (int i = 0; i < N; i++) {
        assert_int_equal(blocked[i], h[i].hit);
        if (!h[i].hit)
            continue;
        hits++;
        for (int k = 0; k < 3; k++) {
            double o = (&r[i].origin.x)[k], d = (&r[i].direction.x)[k];
            double p = (&h[i].point.x)[k];
            near(o + h[i].t * d, p, 1e-12 * (1 + fabs(p) + fabs(o)), "point on the ray");
        }
        near(h[i].normal.x * h[i].normal.x + h[i].normal.y * h[i].normal.y +
             h[i].normal.z * h[i].normal.z, 1, 1e-14, "unit normal");
    }
    assert_true(hits > N / 10 && hits < N);
    free(r);
    free(h);
    free(blocked);
    lc_scene_free(s);
}

/* A camera's rays, cast as one array (neighbours walk the BVH together) and
** one at a time: the same answers, byte for byte; the same for occluded. */
static void arrays_answer_as_single_rays(void **state)
{
    (void)state;
    lc_shape shapes[64];
    int n = 0;
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++)
            shapes[n++] = (i + j) % 3 ? (lc_shape){.kind = LC_SPHERE,
                                                    .p = {i - 3.5, j - 3.5, 0}, .radius = 0.45}
                                      : (lc_shape){.kind = LC_BOX, .p = {i - 3.9, j - 3.9, -0.4},
                                                   .u = {0.8, 0, 0}, .v = {0, 0.8, 0},
                                                   .w = {0, 0, 0.8}};
    lc_scene *s = scene_with(shapes, n, NULL);
    enum { W = 64, H = 48, N = W * H };
    lc_ray *r = malloc(N * sizeof *r);
    lc_ray_hit *all = malloc(N * sizeof *all), one;
    unsigned char *blocked = malloc(N), b1;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            r[y * W + x] = (lc_ray){{0.3, -0.2, 9}, {(x + 0.5) / W - 0.5, (y + 0.5) / H - 0.5,
                                                    -1}, 0, (x + y) % 5 ? HUGE_VAL : 9.2};
    lc_error err;
    assert_int_equal(lc_scene_intersect(s, r, N, all, &err), LC_OK);
    assert_int_equal(lc_scene_occluded(s, r, N, blocked, &err), LC_OK);
    int hits = 0;
    for (int i = 0; i < N; i++) {
        assert_int_equal(lc_scene_intersect(s, &r[i], 1, &one, &err), LC_OK);
        assert_int_equal(lc_scene_occluded(s, &r[i], 1, &b1, &err), LC_OK);
        if (memcmp(&one, &all[i], sizeof one) != 0 || b1 != blocked[i])
            fail_msg("ray %d: the array's answer differs from the ray's own", i);
        hits += one.hit;
    }
    assert_true(hits > N / 3 && hits < N);
    free(r);
    free(all);
    free(blocked);
    lc_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sphere_hits_and_uvs),
        cmocka_unit_test(distances_in_units_of_the_direction),
        cmocka_unit_test(each_kind_has_its_uvs),
        cmocka_unit_test(meshes_name_their_faces),
        cmocka_unit_test(bad_rays_are_named),
        cmocka_unit_test(intersect_and_occluded_agree),
        cmocka_unit_test(arrays_answer_as_single_rays),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
