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
    uint32_t *slot;     /* material slot per face, or NULL: faces past nslot take 0 */
    size_t    nslot, capslot;
    uint32_t  nslots;   /* 1 + the largest slot, 0 without slots */
    char    **slot_name;    /* OBJ usemtl names by slot (NULL each when unnamed), or NULL */
    char    **mtllib;       /* OBJ mtllib files, resolved against the OBJ's folder */
    size_t    nmtllib;
    int       refs;     /* owners: the creator plus each scene holding it */
};

/* One more owner of m (a scene, a CSG leaf): lc_mesh_free drops one. */
lc_mesh *mesh_retain(lc_mesh *m);

#endif
