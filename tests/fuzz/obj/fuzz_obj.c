/* fuzz_obj.c: libFuzzer harness of the OBJ reader (lc_mesh_load_obj), and of
** what a loaded mesh goes through next: a scene's BVH, as the scene's own
** triangles and as an instance, and a 4x4 render. */
#define _GNU_SOURCE                 /* memfd_create */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lancer.h"
#include "../memfile.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static memfile in;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    memfile_open(&in, "fuzz.obj");
    /* What a huge face list would take is refused as LC_ENOMEM, a path the
    ** harness means to reach, before libFuzzer's own malloc limit. */
    lc_memory_cap((size_t)256 << 20);
    return 0;
}

/* A failure must say why: the core never fails without a sentence. */
static void check_failure(const lc_error *err)
{
    if (err->code == LC_OK || !err->msg[0] || !memchr(err->msg, '\0', sizeof err->msg)) {
        fprintf(stderr, "failure without a message (code %d)\n", (int)err->code);
        abort();
    }
}

static void render(lc_scene *s)
{
    lc_render_options o = lc_render_options_default();
    o.width = o.height = 4;
    o.threads = 1;
    lc_stats st;
    lc_error err;
    lc_image *img = lc_scene_render(s, &o, &st, &err);
    if (!img)
        check_failure(&err);
    lc_image_free(img);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    memfile_put(&in, data, size);
    lc_error err;
    lc_mesh *m = lc_mesh_load_obj(in.path, &err);
    if (!m) {
        check_failure(&err);
        return 0;
    }
    if (!lc_mesh_vertex_count(m) || !lc_mesh_face_count(m)) {
        fprintf(stderr, "a mesh of %zu vertices and %zu faces loaded without error\n",
                lc_mesh_vertex_count(m), lc_mesh_face_count(m));
        abort();
    }
    lc_scene *s = lc_scene_new(&err);
    if (!s)
        abort();
    lc_camera cam = lc_camera_default();
    cam.from = (lc_vec3){0, 0, 5};
    cam.at = (lc_vec3){0, 0, 0};
    lc_point_light light = lc_point_light_default();
    light.position = (lc_vec3){1, 2, 5};
    lc_material mat = lc_material_default();
    int mi = lc_scene_add_material(s, &mat, &err);
    if (lc_scene_set_camera(s, &cam, &err) || lc_scene_add_light(s, &light, &err) < 0 ||
        mi < 0)
        abort();
    if (lc_scene_add_mesh(s, m, mi, &err) < 0)
        check_failure(&err);
    lc_transform t = lc_transform_translate((lc_vec3){0.5, 0, 0});
    if (lc_scene_add_mesh_moved(s, m, &t, mi, &err) < 0)
        check_failure(&err);
    render(s);
    lc_scene_free(s);
    lc_mesh_free(m);
    return 0;
}
