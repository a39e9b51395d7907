/* test_api.c: the embeddable C API, used as the README shows, through lancer.h only. */
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "lancer.h"

/* The README's embedding example, checked against the closed form: a white
** sphere facing a light 3 units from its nearest point reads I/3^2. */
static void readme_example_renders(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    assert_non_null(s);
    lc_camera cam = {{0, 1, -4}, {0, 1, 0}, {0, 1, 0}, 1, 0, 0};
    assert_int_equal(lc_scene_set_camera(s, &cam, &err), LC_OK);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    assert_int_equal(mi, 0);
    lc_shape ball = {.kind = LC_SPHERE, .p = {0, 1, 0}, .radius = 1};
    assert_int_equal(lc_scene_add_shape(s, &ball, mi, &err), 0);
    lc_point_light l = {{0, 1, -4}, {1, 1, 1}, 27, LC_FALLOFF_INVERSE_SQUARE};
    assert_int_equal(lc_scene_add_light(s, &l, &err), 1);   /* ids: one per add */
    lc_render_options o = lc_render_options_default();
    o.width = 3;
    o.height = 3;
    lc_stats st;
    lc_image *img = lc_scene_render(s, &o, &st, &err);
    assert_non_null(img);
    lc_color c = lc_image_get(img, 1, 1);
    assert_true(fabs(c.r - 27.0 / 9.0) < 1e-5);
    assert_int_equal(st.rays[LC_RAY_CAMERA], 9);
    assert_true((st.needs & LC_NEED_REFLECT) == 0);
    lc_image_free(img);
    lc_scene_free(s);
}

/* The defaults the binding builds on live in the core, and every rule the
** binding enforces the core enforces too. */
static void defaults_and_rules_live_in_the_core(void **state)
{
    (void)state;
    lc_error err;
    lc_camera cam = lc_camera_default();
    assert_int_equal(lc_camera_check(&cam, &err), LC_OK);
    assert_true(cam.fov == 60 && cam.up.y == 1 && cam.aperture == 0);
    lc_point_light l = lc_point_light_default();
    assert_int_equal(lc_point_light_check(&l, &err), LC_OK);
    assert_true(l.intensity == 1 && l.color.g == 1 && l.falloff == LC_FALLOFF_INVERSE_SQUARE);
    lc_scene *s = lc_scene_new(&err);
    lc_settings st = lc_settings_default();
    st.max_depth = LC_MAX_DEPTH + 1;
    assert_int_equal(lc_scene_configure(s, &st, &err), LC_EARG);
    assert_string_equal(err.field, "max_depth");
    st.max_depth = LC_MAX_DEPTH;
    assert_int_equal(lc_scene_configure(s, &st, &err), LC_OK);
    lc_render_options o = lc_render_options_default();
    o.cutoff = 1.5;
    assert_int_equal(lc_render_options_check(&o, &err), LC_EARG);
    assert_string_equal(err.field, "cutoff");
    o.cutoff = NAN;
    assert_int_equal(lc_render_options_check(&o, &err), LC_EARG);
    lc_shape pl = {.kind = LC_PLANE, .p = {0, 1, 0}, .u = {0, 3, 4}}, stored;
    assert_int_equal(lc_shape_stored(&pl, &stored, &err), LC_OK);
    assert_true(stored.u.x == 0 && fabs(stored.u.y - 0.6) < 3e-16 &&
                fabs(stored.u.z - 0.8) < 3e-16);
    int mi = lc_scene_add_material(s, &(lc_material){.color = lc_material_default().color,
                                                      .kd = 1, .alpha = 1, .cone_samples = 1,
                                                      .ior = 1, .fresnel = 1,
                                                      .normal_scale = 1},
                                   &err);
    int id = lc_scene_add_shape(s, &pl, mi, &err);
    lc_object obj;
    assert_int_equal(lc_scene_object(s, id, &obj, &err), LC_OK);
    assert_memory_equal(&obj.shape, &stored, sizeof stored);
    assert_string_equal(lc_shape_kind_name(LC_BOX), "box");
    assert_string_equal(lc_shape_kind_name(LC_SHAPE_KINDS), "triangle");
    lc_scene_free(s);
}

/* A picture that is likely a mistake says so in the statistics. */
static void dark_renders_warn(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_camera cam = lc_camera_default();
    cam.from = (lc_vec3){0, 0, 4};
    cam.at = (lc_vec3){0, 0, 0};
    assert_int_equal(lc_scene_set_camera(s, &cam, &err), LC_OK);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    lc_shape ball = {.kind = LC_SPHERE, .radius = 1};
    lc_scene_add_shape(s, &ball, mi, &err);
    lc_render_options o = lc_render_options_default();
    o.width = o.height = 8;
    lc_stats st;
    lc_image *img = lc_scene_render(s, &o, &st, &err);
    assert_non_null(strstr(st.warning, "no light"));
    lc_image_free(img);
    lc_point_light l = lc_point_light_default();
    l.position = (lc_vec3){0, 0, -4};              /* behind the ball: all dark */
    lc_scene_add_light(s, &l, &err);
    img = lc_scene_render(s, &o, &st, &err);
    assert_non_null(strstr(st.warning, "every pixel is black"));
    lc_image_free(img);
    l.position = (lc_vec3){0, 0, 4};
    lc_scene_add_light(s, &l, &err);
    img = lc_scene_render(s, &o, &st, &err);
    assert_string_equal(st.warning, "");
    lc_image_free(img);
    lc_scene_free(s);
}

static void errors_name_the_field(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    lc_shape bad = {.kind = LC_SPHERE, .radius = -2};
    assert_int_equal(lc_scene_add_shape(s, &bad, mi, &err), -1);
    assert_int_equal(err.code, LC_EARG);
    assert_string_equal(err.field, "radius");
    assert_non_null(strstr(err.msg, "got -2"));
    lc_render_options o = lc_render_options_default();
    assert_null(lc_scene_render(s, &o, NULL, &err));
    assert_string_equal(err.field, "camera");
    lc_scene_free(s);
    lc_scene_free(NULL);
    lc_image_free(NULL);
}

static int cancel_at_once(void *ud, double done)
{
    (void)done;
    ++*(int *)ud;
    return 1;
}

static void progress_can_cancel(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_camera cam = {{0, 0, -4}, {0, 0, 0}, {0, 1, 0}, 60, 0, 0};
    lc_scene_set_camera(s, &cam, &err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    for (int i = 0; i < 200; i++) {
        lc_shape b = {.kind = LC_SPHERE, .p = {i * 0.01, 0, 0}, .radius = 1};
        lc_scene_add_shape(s, &b, mi, &err);
    }
    int calls = 0;
    lc_render_options o = lc_render_options_default();
    o.width = 1024;
    o.height = 1024;
    o.samples = 64;         /* seconds of work: the first poll comes at 100 ms */
    o.progress = cancel_at_once;
    o.progress_ud = &calls;
    lc_stats st;
    assert_null(lc_scene_render(s, &o, &st, &err));
    assert_int_equal(err.code, LC_ECANCEL);
    assert_true(calls >= 1);
    lc_scene_free(s);
}

static void on_sigusr1(int sig)
{
    (void)sig;
    lc_interrupt();
}

/* Stands in for Ctrl-C: the first progress call raises a signal whose
** handler calls lc_interrupt(), as the lancer command's SIGINT handler does. */
static int signal_once(void *ud, double done)
{
    (void)done;
    if (++*(int *)ud == 1)
        raise(SIGUSR1);
    return 0;
}

static void interrupt_cancels_running_renders_only(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_camera cam = {{0, 0, -4}, {0, 0, 0}, {0, 1, 0}, 60, 0, 0};
    lc_scene_set_camera(s, &cam, &err);
    lc_material m = lc_material_default();
    int mi = lc_scene_add_material(s, &m, &err);
    lc_shape b = {.kind = LC_SPHERE, .radius = 1};
    lc_scene_add_shape(s, &b, mi, &err);
    struct sigaction sa, old;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigusr1;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGUSR1, &sa, &old);

    int calls = 0;
    lc_render_options o = lc_render_options_default();
    o.width = 1024;
    o.height = 1024;
    o.samples = 64;         /* seconds of work: progress polls every 100 ms */
    o.progress = signal_once;
    o.progress_ud = &calls;
    lc_stats st;
    assert_null(lc_scene_render(s, &o, &st, &err));
    assert_int_equal(err.code, LC_ECANCEL);
    assert_string_equal(err.msg, "render cancelled");
    /* Fewer camera rays than samples: it stopped early. */
    assert_true(st.rays[LC_RAY_CAMERA] < (uint64_t)o.width * o.height * o.samples);

    /* An interrupt before a render starts does not cancel it. */
    lc_interrupt();
    o.width = o.height = 64;
    o.samples = 1;
    o.progress = NULL;
    lc_image *img = lc_scene_render(s, &o, &st, &err);
    assert_non_null(img);
    assert_int_equal(st.rays[LC_RAY_CAMERA], 64 * 64);
    lc_image_free(img);
    sigaction(SIGUSR1, &old, NULL);
    lc_scene_free(s);
}

static int count_calls(void *ud, double done)
{
    (void)done;
    ++*(int *)ud;
    return 0;
}

/* What on_pass saw: the passes, the samples so far, a copy of pass 2. */
typedef struct {
    int       calls, stop_at;
    uint64_t  samples[8];
    lc_image *second;
} passes_seen;

static int note_pass(void *ud, const lc_image *img, int pass, const struct lc_stats *st)
{
    passes_seen *p = ud;
    assert_int_equal(pass, p->calls + 1);
    assert_int_equal(st->passes, pass);
    if (p->calls < 8)
        p->samples[p->calls] = st->samples;
    p->calls++;
    if (pass == 2) {
        lc_error err;
        p->second = lc_image_copy(img, &err);
        assert_non_null(p->second);
    }
    return pass == p->stop_at;
}

static int same_pixels(const lc_image *a, const lc_image *b)
{
    for (int y = 0; y < lc_image_height(a); y++)
        for (int x = 0; x < lc_image_width(a); x++) {
            lc_color p = lc_image_get(a, x, y), q = lc_image_get(b, x, y);
            if (memcmp(&p, &q, sizeof p) != 0)
                return 0;
        }
    return 1;
}

/* A progressive render: passes of 1, 2, 4, 6 samples (6 in all), each seen
** by on_pass; the final image the plain render's bit for bit; a nonzero
** return stops after that pass with st.stopped and the image of that pass. */
static void progressive_passes(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_camera cam = {{0, 1, -4}, {0, 1, 0}, {0, 1, 0}, 50, 0, 0};
    lc_scene_set_camera(s, &cam, &err);
    lc_material m = lc_material_default();
    m.kr = 0.3;
    int mi = lc_scene_add_material(s, &m, &err);
    lc_shape ball = {.kind = LC_SPHERE, .p = {0, 1, 0}, .radius = 1};
    lc_scene_add_shape(s, &ball, mi, &err);
    lc_point_light l = {{2, 4, -3}, {1, 1, 1}, 25, LC_FALLOFF_INVERSE_SQUARE};
    lc_scene_add_light(s, &l, &err);
    lc_render_options o = lc_render_options_default();
    o.width = 20;
    o.height = 12;
    o.samples = 6;
    lc_stats st;
    lc_image *plain = lc_scene_render(s, &o, &st, &err);
    assert_non_null(plain);
    assert_int_equal(st.passes, 1);

    passes_seen p = {0, 0, {0}, NULL};
    o.progressive = 1;
    o.on_pass = note_pass;
    o.on_pass_ud = &p;
    lc_image *img = lc_scene_render(s, &o, &st, &err);
    assert_non_null(img);
    assert_int_equal(p.calls, 4);
    assert_int_equal(st.passes, 4);
    assert_int_equal(st.stopped, 0);
    const uint64_t want[4] = {240, 480, 960, 1440};   /* 20 x 12 pixels x 1, 2, 4, 6 */
    for (int k = 0; k < 4; k++)
        assert_int_equal(p.samples[k], want[k]);
    assert_true(same_pixels(img, plain));
    lc_image_free(img);

    lc_image *second = p.second;
    passes_seen q = {0, 2, {0}, NULL};
    o.on_pass_ud = &q;
    img = lc_scene_render(s, &o, &st, &err);
    assert_non_null(img);
    assert_int_equal(st.passes, 2);
    assert_int_equal(st.stopped, 1);
    assert_int_equal(st.samples, 480);
    assert_true(same_pixels(img, second));
    assert_false(same_pixels(img, plain));
    lc_image_free(img);
    lc_image_free(second);
    lc_image_free(q.second);

    o.progressive = 2;
    assert_null(lc_scene_render(s, &o, &st, &err));
    assert_string_equal(err.field, "progressive");
    o.progressive = 0;
    assert_null(lc_scene_render(s, &o, &st, &err));
    assert_string_equal(err.field, "on_pass");
    lc_image_free(plain);
    lc_scene_free(s);
}

/* The progress callback is called at least once per render, however soon
** the workers finish: a 1x1 render used to end before the first wait and
** never call it (the manual's "stop halfway" example then failed). */
static void progress_is_always_reported(void **state)
{
    (void)state;
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    lc_camera cam = lc_camera_default();
    lc_scene_set_camera(s, &cam, &err);
    lc_render_options o = lc_render_options_default();
    o.width = o.height = 1;
    o.progress = count_calls;
    for (int i = 0; i < 200; i++) {
        int calls = 0;
        o.progress_ud = &calls;
        lc_image *img = lc_scene_render(s, &o, NULL, &err);
        assert_non_null(img);
        lc_image_free(img);
        if (calls < 1)
            fail_msg("render %d: the callback was never called", i);
    }
    lc_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(progress_is_always_reported),
        cmocka_unit_test(readme_example_renders),
        cmocka_unit_test(errors_name_the_field),
        cmocka_unit_test(dark_renders_warn),
        cmocka_unit_test(defaults_and_rules_live_in_the_core),
        cmocka_unit_test(progress_can_cancel),
        cmocka_unit_test(progressive_passes),
        cmocka_unit_test(interrupt_cancels_running_renders_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
