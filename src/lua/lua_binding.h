/* lua_binding.h: the binding's cross-file helpers (lb_) and userdata types. */
#ifndef LUA_BINDING_H
#define LUA_BINDING_H

#include <lua.h>
#include <lauxlib.h>
#include "lancer.h"

/* Metatable names: a wrong argument reads "lancer.Image expected, got nil". */
#define LB_MATERIAL  "lancer.Material"
#define LB_SHAPE     "lancer.Shape"
#define LB_LIGHT     "lancer.Light"
#define LB_CAMERA    "lancer.Camera"
#define LB_SCENE     "lancer.Scene"
#define LB_IMAGE     "lancer.Image"
#define LB_MESH      "lancer.Mesh"
#define LB_RAYTREE   "lancer.RayTree"
#define LB_TRANSFORM "lancer.Transform"
#define LB_GROUP     "lancer.Group"
#define LB_ENTRY     "lancer.SceneObject"
#define LB_TEXTURE   "lancer.Texture"
#define LB_CSG       "lancer.CSG"

/* luaL_testudata(L, idx, name) for the metatable of that name held at index
** mt (an upvalue): a third of the cost of a lookup by name (callgrind),
** which counts in the calls a script makes a million times (lancer.sphere,
** scene:add). */
static inline void *lb_udata_is(lua_State *L, int idx, int mt)
{
    void *p = lua_touserdata(L, idx);
    if (!p || !lua_getmetatable(L, idx))
        return NULL;
    int same = lua_rawequal(L, -1, mt);
    lua_pop(L, 1);
    return same ? p : NULL;
}

typedef struct { lc_material m; } lb_ud_material; /* user value 1: its textures, by
                                                  ** field name, or nil */
typedef struct { lc_texture t; } lb_ud_texture;   /* user values: lua_texture.c */
typedef struct { lc_shape s; } lb_ud_shape;       /* user value 1: its material */
/* A light of any kind (lancer.point_light, spot_light, directional_light):
** kind is LC_OBJECT_LIGHT, LC_OBJECT_SPOT_LIGHT or LC_OBJECT_DIRECTIONAL_LIGHT,
** and the field of that kind holds it. */
typedef struct {
    lc_object_kind kind;
    lc_point_light l;
    lc_spot_light spot;
    lc_directional_light sun;
} lb_ud_light;
typedef struct { lc_camera c; } lb_ud_camera;
typedef struct {
    lc_scene *s;
    double    mark;     /* when the script last handed control back: creation or
                        ** the end of a render; what follows is scene building */
    int       rendering;  /* a render of it runs Lua code (its on_pass): the core
                        ** scene is locked and in use, lb_scene_at refuses it */
} lb_ud_scene;                                    /* user value 1: see LB_SC_CAMERA */
typedef struct { lc_image *img; } lb_ud_image;
/* user value 1: its material; 2: the materials of its face slots, or nil */
typedef struct { lc_mesh *m; } lb_ud_mesh;
typedef struct { lc_transform t; } lb_ud_transform;
typedef struct { lc_transform t; } lb_ud_group;   /* user value 1: its members, an array */
typedef struct {
    lc_csg_op    op;
    int          cut_object;   /* differences: cut = 'object' */
    int          moved;        /* t is not the identity */
    lc_transform t;            /* placed by it, after its operands' own placings */
    int          depth;        /* nesting levels of operations below, this one counted */
    size_t       nodes;        /* the length of its description */
} lb_ud_csg;          /* user values: 1 its operands, an array; 2 its material or nil */

/* A scene's user value is a table: [LB_SC_CAMERA] its camera userdata,
** [LB_SC_MATERIALS] a table from material userdata to the index the core gave
** it (so a material shared by a million spheres is stored once),
** [LB_SC_DEFAULT] the index of the default material, [LB_SC_MESHES] a table from
** each mesh's core pointer (light userdata) to its userdata, for listing,
** [LB_SC_TEXTURES] a table from texture userdata to the scene's index for it,
** [LB_SC_CSGS] a table from each CSG object's id (the core's) to the value
** added, for scene:remove(csg). */
enum { LB_SC_CAMERA = 1, LB_SC_MATERIALS = 2, LB_SC_DEFAULT = 3, LB_SC_MESHES = 4,
       LB_SC_TEXTURES = 5, LB_SC_CSGS = 6,
       LB_SC_BACKGROUND = 7 }; /* the background's texture, when it is one */

/* lua_lancer.c: a metatable `name` with the metamethods `meta` and, when
** given, methods that its __index looks up under "methods". */
void lb_class(lua_State *L, const char *name, const luaL_Reg *meta,
              const luaL_Reg *methods);

/* lua_lancer.c: tells Lua's collector how much the core's memory grew since
** the last call (images, meshes, scenes): called after each lc_ call that
** makes or grows one. It may run finalizers: call it last, with no core
** pointer in use after it. */
void lb_charge(lua_State *L);

/* lua_lancer.c: files the binding opens itself, beyond its arguments (an
** OBJ's .mtl libraries, their texture maps, an image texture's path), are
** first shown to the host's gate, a function at registry[LB_FILE_GATE]
** called with (path, writing) and returning true, or false and why (the
** sandbox sets one); raises at argument arg when it says no. No gate: all
** may be read. */
#define LB_FILE_GATE "lancer.file_gate"
void lb_check_file(lua_State *L, int arg, const char *path, int writing);

/* lua_record.c: materials, lights and cameras as field tables, as shapes
** (lua_shapes.c) are: each kind's constructor, __index, __tostring and
** scene:objects() read its table and nothing else about its fields, so a
** field is one row. A row names a member of the record (lc_material,
** lb_ud_light, lc_camera) by its offset. */
typedef enum {
    LB_VEC3, LB_COLOR, LB_NUMBER, LB_INTEGER, LB_BOOL,
    LB_OPTION,          /* an enum, named by opts */
    LB_TEXTURE_ONLY     /* no member: only a texture stands for it (a bump map) */
} lb_field_type;

/* When __tostring writes a field: always; when it differs from the
** default (so a plain material prints as it always did); when the field
** before it is written; never. */
typedef enum { LB_SHOWN, LB_SHOWN_CHANGED, LB_SHOWN_WITH_PREV, LB_UNSHOWN } lb_shown;

#define LB_MAX_FIELDS 24   /* a kind's fields at most; lb_record_read's skip bits */

typedef struct {
    const char   *name;       /* NULL ends a kind's list */
    size_t        offset;     /* of its member in the record */
    lb_field_type type;
    int           required;   /* 0: absent keeps the record's default */
    lb_shown      shown;
    const char *const *opts;  /* LB_OPTION: the names of its values, in order */
    const char   *also;       /* another field the constructor reads for it, or NULL */
    /* Reads it when its type's reader does not do (a field given one of two
    ** ways, a default that depends on another field), or NULL. */
    void (*read)(lua_State *L, int arg, void *rec);
    int           slot;       /* materials: 1 + the lc_slot a texture may fill, or 0 */
    int           rank;       /* its place in __tostring, from 1, when that is not
                              ** its row's (the rows' order is the constructor's,
                              ** which its unknown-field error lists); 0: its row's */
} lb_field;

/* The field named name, or NULL. */
const lb_field *lb_record_field(const lb_field *fields, const char *name);
/* lf_open of the table at arg against the fields' names (and alsos). */
void lb_record_open(lua_State *L, int arg, const lb_field *fields);
/* Reads every field (but those whose bit, 1 << its index, is in skip) from
** the table at arg into rec, which holds the defaults. */
void lb_record_read(lua_State *L, int arg, void *rec, const lb_field *fields,
                    unsigned skip);
/* Pushes the value of field f of rec (nil: LB_TEXTURE_ONLY). */
void lb_record_push(lua_State *L, const void *rec, const lb_field *f);
/* Whether every field holds the same value in a and b. */
int  lb_record_equal(const void *a, const void *b, const lb_field *fields);
/* Adds "ctor{name = value, ...}", the fields shown as their lb_shown says
** against the default record def, in their rows' order or their ranks'. */
void lb_record_tostring(luaL_Buffer *b, const char *ctor, const void *rec,
                        const void *def, const lb_field *fields);

/* Each file registers its metatables and sets its constructors in the module
** table at the top of the stack. */
void lb_material_register(lua_State *L); /* lua_material.c: first, shapes test for it */
void lb_light_register(lua_State *L);    /* lua_light.c: point, spot, directional */
void lb_camera_register(lua_State *L);   /* lua_camera.c */
void lb_shapes_register(lua_State *L);   /* lua_shapes.c */
void lb_mesh_register(lua_State *L);     /* lua_mesh.c */
void lb_scene_register(lua_State *L);    /* lua_scene.c: first, the others add methods */
void lb_render_register(lua_State *L);   /* lua_render.c */
void lb_explain_register(lua_State *L);  /* lua_explain.c, with ray trees */
void lb_image_register(lua_State *L);    /* lua_image.c */
void lb_motion_register(lua_State *L);   /* lua_motion.c: transforms and groups */
void lb_scene_objects_register(lua_State *L);  /* lua_scene_objects.c: objects, remove */
void lb_csg_register(lua_State *L);      /* lua_csg.c: union, intersection, ... */
void lb_hook_register(lua_State *L);     /* lua_hook.c: set_host_hook */
void lb_query_register(lua_State *L);    /* lua_query.c: intersect, occluded */
void lb_texture_register(lua_State *L);  /* lua_texture.c: checker, ..., mix */
/* lua_texture.c: the index in the scene at sidx of the texture at tidx,
** added (with the textures within it) the first time; raises naming arg. */
int  lb_texture_scene_index(lua_State *L, int sidx, int tidx, int arg, int depth);
int  lb_texture_check(lua_State *L, int idx);    /* 1: a texture */

/* lua_scene.c: the scene userdata at idx, raising when it is not one or is freed. */
lb_ud_scene *lb_scene_check(lua_State *L, int idx);
/* The core scene of the userdata at idx, raising as lb_scene_check does. Any
** call that can run Lua code may close a scene, mesh or image: a metamethod
** (lua_getfield, lua_geti, luaL_len, luaL_tolstring on a script's value) or
** a finalizer, which the collector may run at any allocation. So a binding
** fetches a core pointer after the last such call, right before the lc_
** call that uses it, and never keeps one across such a call. */
lc_scene *lb_scene_at(lua_State *L, int idx);

/* lua_render.c: raises, naming `what`, while a render's on_pass runs: a
** mesh that grows then would move under the scene rendering it. */
void lb_render_check_idle(lua_State *L, const char *what);

/* lua_render.c: the options render and explain share, from the named-field
** table at arg (checked by the caller's lf_open against LB_RENDER_OPTIONS). */
#define LB_RENDER_OPTIONS "width", "height", "samples", "seed", "threads", "cosine", \
                       "cutoff", "shadows", "reflections", "specular", "generic", \
                       "frame", "sampler", "light_samples", "cone_samples", "max_depth", \
                       "noise", "min_samples", "glossy", "alpha", "region", "indirect", \
                       "roulette", "nee", "ao", "aovs"
void lb_render_read_options(lua_State *L, int arg, lc_render_options *o);
/* The AOV named by the string at idx (lc_aov), or -1 (with *why set to a
** sentence listing the names) for any other value. */
int  lb_aov_of_name(lua_State *L, int idx, const char **why);
/* Pushes the names of the AOV bits as a list. */
void lb_aov_push_names(lua_State *L, unsigned bits);

/* lua_hook.c: the host hook (lancer.set_host_hook; the comment there says
** what it sees). lb_hook_call calls it for `method`, with `plain` (the method
** without the hook) and the nargs checked arguments at 1..nargs, and
** returns the count of its results on top; -1 when no hook is set.
** lb_hook_fail raises msg (with arg > 0 as luaL_argerror's detail): here, or
** with plain set as the plain call's error object, which the method re-raises
** from the script's call. lb_hook_raise does the same for a core error, naming
** its field as lf_raise does. */
int lb_hook_call(lua_State *L, const char *method, lua_CFunction plain, int nargs);
int lb_hook_fail(lua_State *L, int plain, int arg, const char *msg);
int lb_hook_raise(lua_State *L, int plain, int arg, const lc_error *err);

/* lua_motion.c: obj:moved(T) for shapes, lights, meshes and groups. */
int lb_motion_moved(lua_State *L);
/* lua_shapes.c: pushes the shape userdata for a core value, with the material
** userdata (or nil) at stack index mat; whether a shape as added is the one
** a scene lists (lc_shape_stored, then the kind's fields compared). */
void lb_shape_push(lua_State *L, const lc_shape *s, int mat);
int  lb_shape_match(const lc_shape *added, const lc_shape *listed);
/* lua_light.c: pushes a light userdata holding *l; the light moved by t
** (checked: 1, or 0 with err filled); adds it to the scene (its id, or -1). */
void lb_light_push(lua_State *L, const lb_ud_light *l);
int  lb_light_moved(const lb_ud_light *l, const lc_transform *t, lb_ud_light *out,
                    lc_error *err);
int  lb_light_add(lc_scene *s, const lb_ud_light *l, lc_error *err);
/* The light of a scene's listed object o (a light of any kind); whether
** the light as added is the one a scene lists (every field compared); the
** name of its kind and constructor ("spot_light"). */
lb_ud_light lb_light_of(const lc_object *o);
int  lb_light_match(const lb_ud_light *added, const lc_object *listed);
const char *lb_light_kind_name(lc_object_kind kind);
/* A material userdata of m, with no texture (lua_material.c). */
void lb_material_push(lua_State *L, const lc_material *m);
/* A camera userdata of c (lua_camera.c). */
void lb_camera_push(lua_State *L, const lc_camera *c);
/* An image texture of the PNG at path, decoded as enc says; raises naming
** `what` (lua_texture.c). */
void lb_texture_push_png(lua_State *L, const char *path, const char *what,
                         lc_encoding enc);
/* lua_motion.c: pushes a group of the members at stack index members,
** placed by t. */
void lb_motion_push_group(lua_State *L, const lc_transform *t, int members);

/* lua_csg.c: the CSG object at idx moved by t, pushed. */
int    lb_csg_moved(lua_State *L, int idx, const lc_transform *t);
/* Pushes the flat description of the CSG object at idx, placed by xf (or
** not: NULL), as three values: a userdata holding its lc_csg_node array
** (meshes not filled in, materials 0), a table from each leaf's node
** number (from 1) to its material userdata (absent: the default), and one
** from each mesh leaf's to its mesh userdata. Returns the node count;
** raises at arg when a leaf cannot be placed by xf. */
size_t lb_csg_describe(lua_State *L, int idx, const lc_transform *xf, int arg);
/* Pushes the CSG object a scene lists, nodes[0, n); mats: the scene's
** materials by index (lua_scene_objects.c), meshes: its LB_SC_MESHES. */
void   lb_csg_push_listed(lua_State *L, const lc_csg_node *nodes, size_t n, int mats,
                          int meshes);

#endif
