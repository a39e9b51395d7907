/* fuzz_mtl.c: libFuzzer harness of the Wavefront .mtl reader, reached as a
** scene reaches it: through an OBJ whose mtllib names the input; each
** material read is mapped (lc_mtl_material) and added to a scene with the
** OBJ's triangle. No render: with a 2x2 one (the scene's compile, the
** tiles' threads) it ran 750 inputs a second, a million in 20 minutes, and
** a material the scene takes is one every render takes. */
#define _GNU_SOURCE                 /* memfd_create */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include "lancer.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int mtl_fd = -1;
static char obj_path[64];

/* Two in-memory files, opened by their /proc names: the OBJ, written once,
** and the .mtl (the input) beside it, named by its descriptor's number,
** which the OBJ reader resolves against the OBJ's folder, /proc/self/fd. */
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    int obj_fd = memfd_create("fuzz.obj", 0);
    mtl_fd = memfd_create("fuzz.mtl", 0);
    if (obj_fd < 0 || mtl_fd < 0) {
        perror("memfd_create");
        abort();
    }
    char obj[160];
    int n = snprintf(obj, sizeof obj, "mtllib %d\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                     "usemtl a\nf 1 2 3\n", mtl_fd);
    if (pwrite(obj_fd, obj, (size_t)n, 0) != n)
        abort();
    snprintf(obj_path, sizeof obj_path, "/proc/self/fd/%d", obj_fd);
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

/* Every string of a record ends within its field. */
static void check_record(const lc_mtl *t)
{
    if (!memchr(t->name, '\0', sizeof t->name) || !memchr(t->map_kd, '\0', LC_MTL_PATH) ||
        !memchr(t->map_bump, '\0', LC_MTL_PATH) || !memchr(t->map_norm, '\0', LC_MTL_PATH)) {
        fprintf(stderr, "a record's string runs past its field\n");
        abort();
    }
}

/* The materials on the OBJ's triangle in a scene: each must be one the
** scene takes (the mapping clamps what the file says). */
static void add(lc_mesh *m, const lc_mtl *list, size_t n)
{
    lc_error err;
    lc_scene *s = lc_scene_new(&err);
    if (!s)
        abort();
    for (size_t k = 0; k < n; k++) {
        check_record(&list[k]);
        lc_material mat = lc_mtl_material(&list[k]);
        int mi = lc_scene_add_material(s, &mat, &err);
        if (mi < 0) {
            fprintf(stderr, "material '%s' mapped to one the scene refuses: %s\n",
                    list[k].name, err.msg);
            abort();
        }
        if (k == 0 && lc_scene_add_mesh(s, m, mi, &err) < 0)
            check_failure(&err);
    }
    lc_scene_free(s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (ftruncate(mtl_fd, 0) || pwrite(mtl_fd, data, size, 0) != (ssize_t)size)
        abort();
    lc_error err;
    lc_mesh *m = lc_mesh_load_obj(obj_path, &err);
    if (!m || lc_mesh_mtllib_count(m) != 1)
        abort();                         /* the OBJ is the harness's own */
    lc_mtl *list = NULL;
    size_t n = 0;
    if (lc_mtl_load(lc_mesh_mtllib(m, 0), &list, &n, &err))
        check_failure(&err);
    else
        add(m, list, n);
    free(list);
    lc_mesh_free(m);
    return 0;
}
