/* mesh.c: triangle meshes: vertices, optional vertex normals, faces. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "base/error.h"
#include "scene.h"
#include "base/mem.h"

#define MAX_ELEMENTS ((size_t)1 << 29)   /* indices and ids stay within 32 bits */

lc_mesh *lc_mesh_new(lc_error *err)
{
    lc_mesh *m = mem_calloc(1, sizeof *m);
    if (!m) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory creating a mesh");
        return NULL;
    }
    m->refs = 1;
    error_ok(err);
    return m;
}

lc_mesh *mesh_retain(lc_mesh *m)
{
    __atomic_add_fetch(&m->refs, 1, __ATOMIC_RELAXED);
    return m;
}

void lc_mesh_free(lc_mesh *m)
{
    /* Atomic: scenes on other threads may hold and drop the same mesh. */
    if (!m || __atomic_sub_fetch(&m->refs, 1, __ATOMIC_ACQ_REL) > 0)
        return;
    mem_free(m->v);
    mem_free(m->n);
    mem_free(m->uv);
    mem_free(m->f);
    mem_free(m->slot);
    for (uint32_t i = 0; m->slot_name && i < m->nslots; i++)
        mem_free(m->slot_name[i]);
    mem_free(m->slot_name);
    for (size_t i = 0; i < m->nmtllib; i++)
        mem_free(m->mtllib[i]);
    mem_free(m->mtllib);
    mem_free(m);
}

/* Makes room for `more` items of `width` elements of `size` bytes. */
static int reserve(void **arr, size_t *cap, size_t n, size_t more, size_t width, size_t size)
{
    if (more > MAX_ELEMENTS || n + more > MAX_ELEMENTS)
        return 0;
    if (n + more <= *cap)
        return 1;
    size_t nc = *cap ? *cap : 64;
    while (nc < n + more)
        nc *= 2;
    void *p = mem_realloc(*arr, nc * width * size);
    if (!p)
        return 0;
    *arr = p;
    *cap = nc;
    return 1;
}

static lc_status add_points(lc_mesh *m, double **arr, size_t *n, size_t *cap,
                            const double *xyz, size_t count, const char *what, lc_error *err)
{
    if (count == 0)                      /* nothing to copy, maybe from NULL */
        return error_ok(err), LC_OK;
    for (size_t i = 0; i < 3 * count; i++) {
        if (!isfinite(xyz[i]))
            return error_fail(err, LC_EARG, what, "%s %zu: component %zu must be finite, got %g",
                           what, *n + i / 3 + 1, i % 3 + 1, xyz[i]);
        if (arr == &m->v && !(fabs(xyz[i]) <= LC_MAX_COORD))
            return error_fail(err, LC_EARG, what, "%s %zu: component %zu must be within "
                              "+-%g (lancer's coordinate range), got %g", what,
                              *n + i / 3 + 1, i % 3 + 1, LC_MAX_COORD, xyz[i]);
    }
    if (!reserve((void **)arr, cap, *n, count, 3, sizeof **arr))
        return error_fail(err, LC_ENOMEM, NULL, "out of memory: mesh of %zu %s", *n + count,
                       what);
    memcpy(*arr + 3 * *n, xyz, 3 * count * sizeof **arr);
    *n += count;
    error_ok(err);
    return LC_OK;
}

lc_status lc_mesh_add_vertices(lc_mesh *m, const double *xyz, size_t n, lc_error *err)
{
    return add_points(m, &m->v, &m->nv, &m->capv, xyz, n, "vertices", err);
}

lc_status lc_mesh_add_normals(lc_mesh *m, const double *xyz, size_t n, lc_error *err)
{
    for (size_t i = 0; i < n; i++)
        if (xyz[3 * i] == 0 && xyz[3 * i + 1] == 0 && xyz[3 * i + 2] == 0)
            return error_fail(err, LC_EARG, "normals", "normal %zu is zero-length",
                           m->nn + i + 1);
    return add_points(m, &m->n, &m->nn, &m->capn, xyz, n, "normals", err);
}

lc_status lc_mesh_add_uvs(lc_mesh *m, const double *uv, size_t n, lc_error *err)
{
    if (n == 0)
        return error_ok(err), LC_OK;
    for (size_t i = 0; i < 2 * n; i++)
        if (!isfinite(uv[i]))
            return error_fail(err, LC_EARG, "uvs", "uv %zu: component %zu must be finite, "
                              "got %g", m->nuv + i / 2 + 1, i % 2 + 1, uv[i]);
    if (!reserve((void **)&m->uv, &m->capuv, m->nuv, n, 2, sizeof *m->uv))
        return error_fail(err, LC_ENOMEM, NULL, "out of memory: mesh of %zu uvs", m->nuv + n);
    memcpy(m->uv + 2 * m->nuv, uv, 2 * n * sizeof *uv);
    m->nuv += n;
    error_ok(err);
    return LC_OK;
}

lc_status lc_mesh_add_faces(lc_mesh *m, const uint32_t *abc, size_t n, lc_error *err)
{
    if (n == 0)
        return error_ok(err), LC_OK;
    for (size_t i = 0; i < 3 * n; i++)
        if (abc[i] >= m->nv)
            return error_fail(err, LC_EARG, "faces", "face %zu: vertex index %lu is past the "
                           "%zu vertices", m->nf + i / 3 + 1, (unsigned long)abc[i] + 1,
                           m->nv);
    if (!reserve((void **)&m->f, &m->capf, m->nf, n, 3, sizeof *m->f))
        return error_fail(err, LC_ENOMEM, NULL, "out of memory: mesh of %zu faces", m->nf + n);
    memcpy(m->f + 3 * m->nf, abc, 3 * n * sizeof *abc);
    m->nf += n;
    error_ok(err);
    return LC_OK;
}

size_t lc_mesh_vertex_count(const lc_mesh *m) { return m->nv; }
size_t lc_mesh_face_count(const lc_mesh *m) { return m->nf; }

lc_status lc_mesh_add_face_materials(lc_mesh *m, const uint32_t *slots, size_t n,
                                     lc_error *err)
{
    if (n == 0)
        return error_ok(err), LC_OK;
    for (size_t i = 0; i < n; i++)
        if (slots[i] >= LC_MAX_SLOTS)
            return error_fail(err, LC_EARG, "face_materials", "face %zu: material slot %lu "
                              "is past lancer's %d", m->nslot + i + 1,
                              (unsigned long)slots[i] + 1, LC_MAX_SLOTS);
    if (!reserve((void **)&m->slot, &m->capslot, m->nslot, n, 1, sizeof *m->slot))
        return error_fail(err, LC_ENOMEM, NULL, "out of memory: %zu face materials",
                          m->nslot + n);
    memcpy(m->slot + m->nslot, slots, n * sizeof *slots);
    m->nslot += n;
    for (size_t i = 0; i < n; i++)
        if (slots[i] + 1 > m->nslots)
            m->nslots = slots[i] + 1;
    error_ok(err);
    return LC_OK;
}

size_t lc_mesh_material_slots(const lc_mesh *m) { return m->nslots; }

const char *lc_mesh_slot_name(const lc_mesh *m, size_t slot)
{
    return m->slot_name && slot < m->nslots ? m->slot_name[slot] : NULL;
}

size_t lc_mesh_mtllib_count(const lc_mesh *m) { return m->nmtllib; }

const char *lc_mesh_mtllib(const lc_mesh *m, size_t i)
{
    return i < m->nmtllib ? m->mtllib[i] : NULL;
}

const double *lc_mesh_vertex_data(const lc_mesh *m) { return m->v; }
const uint32_t *lc_mesh_face_data(const lc_mesh *m) { return m->f; }
