/* test_threads.c: the uses of the C API from several threads that lancer.h
** documents: scenes sharing a mesh rendered at once, one scene rendered from
** two threads (they take turns), meshes added and dropped while others
** render, rays cast from several threads while the scene renders. Run under ThreadSanitizer by `make tsan`; in the plain build it
** checks the results. */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "lancer.h"

static lc_mesh *pyramid(void)
{
    static const double v[] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1, 0, 1.5, 0};
    static const uint32_t f[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 2, 1, 0, 3, 2};
    lc_error err;
    lc_mesh *m = lc_mesh_new(&err);
    lc_mesh_add_vertices(m, v, 5, &err);
    lc_mesh_add_faces(m, f, 6, &err);
    return m;
}

static lc_scene *scene_with(lc_mesh *m, double turn)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_camera cam = lc_camera_default();
    cam.from = (lc_vec3){4 * sin(turn), 2, -4 * cos(turn)};
    cam.at = (lc_vec3){0, 0.5, 0};
    lc_scene_set_camera(s, &cam, &err);
    lc_material mat = lc_material_default();
    int mi = lc_scene_add_material(s, &mat, &err);
    lc_transform t = lc_transform_translate((lc_vec3){0.5, 0, 0});
    lc_scene_add_mesh(s, m, mi, &err);
    lc_scene_add_mesh_moved(s, m, &t, mi, &err);
    lc_point_light l = lc_point_light_default();
    l.position = (lc_vec3){2, 5, -3};
    l.intensity = 30;
    lc_scene_add_light(s, &l, &err);
    return s;
}

static double checksum(const lc_image *img)
{
    double sum = 0;
    for (int y = 0; y < lc_image_height(img); y++)
        for (int x = 0; x < lc_image_width(img); x++) {
            lc_color c = lc_image_get(img, x, y);
            sum += c.r + 2 * c.g + 3 * c.b;
        }
    return sum;
}

typedef struct { lc_mesh *mesh; lc_scene *scene; double turn, sum; int rounds; } job;

static lc_render_options small(void)
{
    lc_render_options o = lc_render_options_default();
    o.width = 24;
    o.height = 16;
    o.threads = 2;
    return o;
}

/* Builds a scene around the shared mesh, renders it, frees it: the mesh's
** count goes up and down on both threads at once. */
static void *own_scenes(void *arg)
{
    job *j = arg;
    lc_render_options o = small();
    for (int r = 0; r < j->rounds; r++) {
        lc_scene *s = scene_with(j->mesh, j->turn);
        lc_image *img = lc_scene_render(s, &o, NULL, NULL);
        j->sum = checksum(img);
        lc_image_free(img);
        lc_scene_free(s);
    }
    return NULL;
}

static void scenes_sharing_a_mesh_render_at_once(void **state)
{
    (void)state;
    size_t before = lc_memory_used();
    lc_mesh *m = pyramid();
    job a = {m, NULL, 0.3, 0, 20}, b = {m, NULL, 1.2, 0, 20};
    pthread_t ta, tb;
    pthread_create(&ta, NULL, own_scenes, &a);
    pthread_create(&tb, NULL, own_scenes, &b);
    pthread_join(ta, NULL);
    pthread_join(tb, NULL);
    /* Alone, each gives the same picture. */
    job a1 = {m, NULL, 0.3, 0, 1}, b1 = {m, NULL, 1.2, 0, 1};
    own_scenes(&a1);
    own_scenes(&b1);
    assert_true(a.sum == a1.sum && b.sum == b1.sum && a.sum != b.sum);
    lc_mesh_free(m);                          /* the last owner: all memory back */
    assert_int_equal(lc_memory_used(), before);
}

static void *render_shared(void *arg)
{
    job *j = arg;
    lc_render_options o = small();
    for (int r = 0; r < j->rounds; r++) {
        lc_image *img = lc_scene_render(j->scene, &o, NULL, NULL);
        j->sum = checksum(img);
        lc_image_free(img);
    }
    return NULL;
}

static void one_scene_from_two_threads_takes_turns(void **state)
{
    (void)state;
    lc_mesh *m = pyramid();
    lc_scene *s = scene_with(m, 0.7);
    lc_mesh_free(m);                          /* the scene holds it */
    job a = {NULL, s, 0, 0, 20}, b = {NULL, s, 0, 0, 20};
    pthread_t ta, tb;
    pthread_create(&ta, NULL, render_shared, &a);
    pthread_create(&tb, NULL, render_shared, &b);
    pthread_join(ta, NULL);
    pthread_join(tb, NULL);
    job alone = {NULL, s, 0, 0, 1};
    render_shared(&alone);
    assert_true(a.sum == alone.sum && b.sum == alone.sum);
    lc_scene_free(s);
}

/* Rays cast from two threads into one fresh scene (the first cast of each
** may compile it) while a third renders it: every hit as one thread alone
** finds it. */
enum { CAST_N = 5000 };

typedef struct { lc_scene *scene; const lc_ray *rays; lc_ray_hit *hits; int ok; } cast_job;

static void *cast_rays(void *arg)
{
    cast_job *c = arg;
    lc_error err;
    c->ok = lc_scene_intersect(c->scene, c->rays, CAST_N, c->hits, &err) == LC_OK;
    return NULL;
}

static void casts_from_threads_while_it_renders(void **state)
{
    (void)state;
    lc_mesh *m = pyramid();
    lc_scene *s = scene_with(m, 0.3);
    static lc_ray rays[CAST_N];
    static lc_ray_hit ha[CAST_N], hb[CAST_N], alone[CAST_N];
    for (int i = 0; i < CAST_N; i++) {
        double a = 2 * 3.14159265358979 * i / CAST_N;
        rays[i] = (lc_ray){{3 * cos(a), 0.6, 3 * sin(a)},
                           {-cos(a), -0.1 * (i % 7), -sin(a)}, 0, HUGE_VAL};
    }
    cast_job a = {s, rays, ha, 0}, b = {s, rays, hb, 0};
    job r = {NULL, s, 0, 0, 3};
    pthread_t ta, tb, tr;
    pthread_create(&ta, NULL, cast_rays, &a);
    pthread_create(&tr, NULL, render_shared, &r);
    pthread_create(&tb, NULL, cast_rays, &b);
    pthread_join(ta, NULL);
    pthread_join(tb, NULL);
    pthread_join(tr, NULL);
    cast_job one = {s, rays, alone, 0};
    cast_rays(&one);
    assert_true(a.ok && b.ok && one.ok);
    int hits = 0;
    for (int i = 0; i < CAST_N; i++) {
        assert_true(ha[i].hit == alone[i].hit && hb[i].hit == alone[i].hit);
        assert_true(ha[i].t == alone[i].t && hb[i].t == alone[i].t);
        assert_true(ha[i].object == alone[i].object && ha[i].primitive == alone[i].primitive);
        hits += alone[i].hit;
    }
    assert_true(hits > CAST_N / 4);
    lc_scene_free(s);
    lc_mesh_free(m);
}

static void *interrupt_soon(void *arg)
{
    (void)arg;
    lc_interrupt();
    return NULL;
}

static void interrupt_from_another_thread(void **state)
{
    (void)state;
    pthread_t t;
    pthread_create(&t, NULL, interrupt_soon, NULL);
    pthread_join(t, NULL);
    size_t used = lc_memory_used();           /* any thread may read it */
    (void)used;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(scenes_sharing_a_mesh_render_at_once),
        cmocka_unit_test(one_scene_from_two_threads_takes_turns),
        cmocka_unit_test(casts_from_threads_while_it_renders),
        cmocka_unit_test(interrupt_from_another_thread),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
