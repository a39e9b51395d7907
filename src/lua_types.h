/* lua_types.h: the binding's userdata types, shared by the lua_*.c files. */
#ifndef LUA_TYPES_H
#define LUA_TYPES_H

#include <lua.h>
#include <lauxlib.h>
#include "lancer.h"

/* Metatable names: a wrong argument reads "lancer.Image expected, got nil". */
#define MATERIAL "lancer.Material"
#define SHAPE    "lancer.Shape"
#define LIGHT    "lancer.Light"
#define CAMERA   "lancer.Camera"
#define SCENE    "lancer.Scene"
#define IMAGE    "lancer.Image"
#define MESH     "lancer.Mesh"
#define RAYTREE  "lancer.RayTree"

typedef struct { lc_material m; } ud_material;
typedef struct { lc_shape s; } ud_shape;          /* user value 1: its material */
typedef struct { lc_point_light l; } ud_light;
typedef struct { lc_camera c; } ud_camera;
typedef struct {
    lc_scene *s;
    double    mark;     /* when the script last handed control back: creation or
                        ** the end of a render; what follows is scene building */
} ud_scene;                                       /* user value 1: see lua_scene.c */
typedef struct { lc_image *img; } ud_image;
typedef struct { lc_mesh *m; } ud_mesh;           /* user value 1: its material */

/* A metatable `name` with the metamethods `meta` and, when given, methods
** that its __index looks up under "methods". */
void binding_class(lua_State *L, const char *name, const luaL_Reg *meta,
                   const luaL_Reg *methods);

/* Each file registers its metatables and sets its constructors in the module
** table at the top of the stack. */
void objects_register(lua_State *L);   /* lua_objects.c: materials, shapes, lights, cameras */
void mesh_register(lua_State *L);      /* lua_mesh.c */
void scene_register(lua_State *L);     /* lua_scene.c, with ray trees */
void image_register(lua_State *L);     /* lua_image.c */

#endif
