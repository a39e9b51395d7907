/* mesh.h: the layout of a triangle mesh, shared by mesh.c, obj.c and compile.c. */
#ifndef LC_MESH_H
#define LC_MESH_H

#include "lancer.h"

struct lc_mesh {
    double   *v;        /* 3 per vertex */
    size_t    nv, capv;
    double   *n;        /* 3 per vertex normal, or NULL */
    size_t    nn, capn;
    double   *uv;       /* 2 per vertex texture coordinate, or NULL */
    size_t    nuv, capuv;
    uint32_t *f;        /* 3 vertex indices per face, 0-based */
    size_t    nf, capf;
    int       refs;     /* owners: the creator plus each scene holding it */
};

#endif
