/* lancer.h: the whole embeddable C API of lancer, a ray tracer. */
#ifndef LANCER_H
#define LANCER_H

#include <stddef.h>
#include <stdint.h>

#define LC_VERSION "0.1.0"

/* ---- Threads ---------------------------------------------------------------
** lc_scene_render traces on worker threads of its own. Different scenes may
** be used on different threads at once, sharing meshes (a mesh's reference
** count is atomic), as long as no mesh grows while a scene holding it
** renders. On one scene, renders and explains from several threads take
** turns (the scene has a lock); rays cast into it (lc_scene_intersect and
** lc_scene_occluded) run at once on any number of threads; its other calls
** (add, remove, configure, transformed, objects) must not run while it
** renders or is cast into on another thread.
** An image is used by one thread at a time. lc_interrupt, lc_save_abandon,
** lc_memory_cap and lc_memory_used may be called from any thread; the
** first two from a signal handler too. */

/* ---- Errors --------------------------------------------------------------- */

typedef enum { LC_OK, LC_EARG, LC_ENOMEM, LC_EIO, LC_ECANCEL } lc_status;

/* Every call that can fail fills one of these. `field` names the input field
** at fault (empty when none); `msg` is a sentence naming the bad value. */
typedef struct {
    lc_status code;
    char field[32];
    char msg[256];
} lc_error;

/* ---- Memory ---------------------------------------------------------------- */

/* Caps the memory the core allocates (scenes, meshes, BVHs, images), in
** bytes, for the whole process; 0 (the default) is no cap. What would pass
** it fails as LC_ENOMEM, saying so. Returns the previous cap. */
size_t lc_memory_cap(size_t bytes);
size_t lc_memory_used(void);             /* bytes the core holds now */

/* ---- Values ---------------------------------------------------------------- */

typedef struct { double x, y, z; } lc_vec3;   /* geometry is double throughout */

/* The coordinate range: geometry is exact (no square of a square over- or
** underflows) when every coordinate (centres, corners, points, vertices,
** positions) lies within +-LC_MAX_COORD and every length (radii, edges,
** aperture, focus) in [LC_MIN_LENGTH, LC_MAX_COORD]; what lies outside is
** refused, naming the field. */
#define LC_MAX_COORD  1e30
#define LC_MIN_LENGTH 1e-30
typedef struct { float r, g, b; } lc_color;    /* linear RGB */

/* ---- Materials ------------------------------------------------------------- */

/* What the object's colour multiplies: the seed multiplies the whole sum
** (coloured mirrors and highlights); POV-Ray and Tachyon colour only the
** ambient and diffuse terms. */
typedef enum { LC_ABSORB_ALL, LC_ABSORB_DIFFUSE } lc_absorb;

/* How shadow rays cross a material with kt > 0: multiplied by its
** transmission and absorption (POV-Ray's look), or stopped (the seed). */
typedef enum { LC_SHADOW_FILTERED, LC_SHADOW_OPAQUE } lc_shadow_mode;

/* What a texture may stand for in a material (see Textures below): the
** colour, a coefficient (its luminance, clamped to [0, 1]), the emission,
** the height whose slope bends the shading normal, or a tangent-space
** normal map (on mesh faces with uvs). */
typedef enum {
    LC_SLOT_COLOR, LC_SLOT_KD, LC_SLOT_KS, LC_SLOT_KR, LC_SLOT_KT, LC_SLOT_EMISSION,
    LC_SLOT_BUMP, LC_SLOT_NORMAL, LC_SLOTS
} lc_slot;

/* The material field a slot stands for: "color", "kd", ..., "bump", "normal_map". */
const char *lc_slot_name(lc_slot slot);

typedef struct {
    lc_color  color;     /* C: absorption, every component in [0, 1] */
    double    ka;        /* ambient coefficient */
    double    kd;        /* diffuse coefficient (times n.l) */
    double    kr;        /* mirror reflection coefficient */
    double    ks;        /* Phong specular coefficient */
    double    alpha;     /* Phong exponent, >= 0 */
    lc_color  emission;  /* radiance emitted; > 0 makes the shape a light */
    lc_absorb absorb;
    double    glossiness;   /* the seed's diffusion cone: half-angle in degrees of
                            ** the cone of reflected rays, in [0, 90); 0 = mirror */
    int       cone_samples; /* rays over the cone at the first glossy hit, >= 1 */
    double    kt;        /* transmission coefficient: > 0 makes it a dielectric */
    double    ior;       /* index of refraction inside, in [1, LC_MAX_IOR] */
    int       fresnel;   /* 1: reflect kr + kt F, transmit kt (1 - F), F the exact
                         ** unpolarised Fresnel reflectance; 0: kr and kt as they
                         ** are (the seed's), kr + kt at total internal reflection */
    lc_vec3   absorption;   /* Beer-Lambert coefficients inside, per unit length,
                            ** of red, green, blue as x, y, z (a length's inverse:
                            ** double, in [0, 1 / LC_MIN_LENGTH]): e^(-a d) of a
                            ** channel is left after a distance d */
    lc_shadow_mode shadow;  /* shadow rays through it, when kt > 0 */
    int       texture[LC_SLOTS]; /* 1 + index of the scene's texture standing for
                            ** that field (lc_scene_add_texture), or 0: the field's
                            ** own value. Shadow rays and light sampling see the
                            ** constant kt and emission. */
    double    bump;         /* the bump texture's height scale, in [-1e6, 1e6] */
    double    normal_scale; /* the normal map's strength: its tangent components
                            ** times this, in [0, 1e6] (1: as the map says) */
} lc_material;

#define LC_MAX_CONE_SAMPLES 4096
#define LC_MAX_IOR 100

/* White, kd 1, rest 0; 16 cone samples; ior 1, Fresnel on, filtered shadows. */
lc_material lc_material_default(void);
lc_status   lc_material_check(const lc_material *m, lc_error *err);

/* ---- Shapes ---------------------------------------------------------------- */

typedef enum {
    LC_SPHERE, LC_QUAD, LC_BOX, LC_PLANE,
    LC_DISC, LC_CYLINDER, LC_CONE, LC_TORUS, LC_ELLIPSOID,
    LC_SHAPE_KINDS
} lc_shape_kind;

/* An affine map x' = M x + t, row-major: m[i][0..2] is row i of M, m[i][3]
** is t[i]. Compose right to left, as matrices do: (a after b)(x) = a(b(x)). */
typedef struct { double m[3][4]; } lc_transform;

typedef struct {
    lc_shape_kind kind;
    lc_vec3 p;        /* centre: sphere, disc, torus, ellipsoid; corner: quad, box; a
                      ** point: plane; the base's centre: cylinder, cone */
    lc_vec3 u, v, w;  /* quad edges u, v; box edges u, v, w; plane and disc normal u;
                      ** cylinder and cone axis u, from base to top (its length is the
                      ** height); torus axis u (a direction); ellipsoid radii u */
    double  radius;   /* sphere, disc, cylinder; cone's base radius; torus's major */
    double  radius2;  /* cone's top radius; disc's inner radius; torus's minor */
    int     caps;     /* cylinder, cone: closed by a disc at each end (a solid) */
    int     moved;    /* disc, cylinder, cone, torus, ellipsoid: then placed by xf,
                      ** any affine map, and intersected in their own space */
    lc_transform xf;
} lc_shape;

lc_status lc_shape_check(const lc_shape *s, lc_error *err); /* sizes, NaN, parallel */
/* "sphere", "quad", ...; LC_SHAPE_KINDS names a mesh's "triangle". */
const char *lc_shape_kind_name(lc_shape_kind k);
/* The shape as a scene stores and lists it (a plane's normal made unit), so
** that what scene objects list can be compared with what was added. */
lc_status lc_shape_stored(const lc_shape *s, lc_shape *out, lc_error *err);

/* ---- Transforms ------------------------------------------------------------ */

lc_transform lc_transform_identity(void);
lc_transform lc_transform_translate(lc_vec3 t);
lc_transform lc_transform_scale(lc_vec3 s);             /* 0 makes it singular */
/* A rotation by `degrees` about `axis` through the origin, counter-clockwise
** seen from the axis' tip (right-handed); exact at multiples of 90 degrees. */
lc_status    lc_transform_rotate(lc_vec3 axis, double degrees, lc_transform *out,
                                 lc_error *err);
lc_transform lc_transform_compose(const lc_transform *a, const lc_transform *b); /* a after b */
/* Finite entries and an invertible M (|det| above its own rounding error). */
lc_status    lc_transform_check(const lc_transform *t, lc_error *err);
lc_status    lc_transform_inverse(const lc_transform *t, lc_transform *out, lc_error *err);
int          lc_transform_is_identity(const lc_transform *t);
lc_vec3      lc_transform_point(const lc_transform *t, lc_vec3 p);   /* M p + t */
lc_vec3      lc_transform_vector(const lc_transform *t, lc_vec3 v);  /* M v */
/* A surface normal moved with its surface: sign(det M) cof(M) n, the inverse
** transpose up to a positive factor (not unit), outward staying outward. */
lc_vec3      lc_transform_normal(const lc_transform *t, lc_vec3 n);
/* The shape moved by t, exactly: quads and boxes (corner and edges), planes
** (point; normal by the inverse transpose) and spheres under rotation,
** translation and uniform scale keep their kind and fields; a sphere under
** any other map becomes an ellipsoid; discs, cylinders, cones, tori and
** ellipsoids keep their fields and are placed by t after their xf. */
lc_status    lc_shape_transform(const lc_shape *s, const lc_transform *t, lc_shape *out,
                                lc_error *err);

/* ---- Meshes ---------------------------------------------------------------- */

/* A triangle mesh; scenes that hold it keep it alive, so the same mesh can be
** added many times and is stored once. Faces index vertices from 0. */
typedef struct lc_mesh lc_mesh;

lc_mesh  *lc_mesh_new(lc_error *err);
void      lc_mesh_free(lc_mesh *m);                     /* NULL is a no-op */
lc_status lc_mesh_add_vertices(lc_mesh *m, const double *xyz, size_t n, lc_error *err);
lc_status lc_mesh_add_normals(lc_mesh *m, const double *xyz, size_t n, lc_error *err);
/* Texture coordinates, 2 per vertex (as many as vertices, or none). */
lc_status lc_mesh_add_uvs(lc_mesh *m, const double *uv, size_t n, lc_error *err);
lc_status lc_mesh_add_faces(lc_mesh *m, const uint32_t *abc, size_t n, lc_error *err);
size_t    lc_mesh_vertex_count(const lc_mesh *m);
size_t    lc_mesh_face_count(const lc_mesh *m);
/* Material slots, one per face in the order faces were added (faces past
** the last slot given take slot 0); a scene maps each slot to a material
** (lc_scene_add_mesh_materials). 1 + the largest slot is
** lc_mesh_material_slots (0: none given). */
#define LC_MAX_SLOTS 65536
lc_status lc_mesh_add_face_materials(lc_mesh *m, const uint32_t *slots, size_t n,
                                     lc_error *err);
size_t    lc_mesh_material_slots(const lc_mesh *m);
/* From an OBJ file: slot k's usemtl name (NULL if none), and the mtllib
** files it named, resolved against the OBJ's folder. */
const char *lc_mesh_slot_name(const lc_mesh *m, size_t slot);
size_t      lc_mesh_mtllib_count(const lc_mesh *m);
const char *lc_mesh_mtllib(const lc_mesh *m, size_t i);
/* A material of a Wavefront .mtl library, as the file says it. */
#define LC_MTL_PATH 1024
typedef struct {
    char     name[256];
    lc_color kd, ks, ka, ke;   /* Kd (0.8 grey when absent), Ks, Ka, Ke (black) */
    double   ns;               /* Ns: the Phong exponent */
    double   d;                /* d, or 1 - Tr: opacity (1) */
    double   ni;               /* Ni: index of refraction (1) */
    int      illum;            /* illum, -1 when absent */
    char     map_kd[LC_MTL_PATH];   /* map_Kd's file, beside the .mtl ("" none) */
    char     map_bump[LC_MTL_PATH]; /* map_Bump or bump ("" none) */
    char     map_norm[LC_MTL_PATH]; /* norm: a tangent-space normal map ("" none) */
    double   bump_mult;        /* its -bm option (1) */
} lc_mtl;

/* Reads newmtl, Kd, Ks, Ka, Ke, Ns, Ni, d, Tr, illum, map_Kd and
** map_Bump/bump; skips the rest; errors name the file and the line.
** *materials is malloc'd: free() it. */
lc_status   lc_mtl_load(const char *path, lc_mtl **materials, size_t *n, lc_error *err);
/* The lancer material a .mtl material maps to (docs/manual.md, "OBJ
** materials"); its textures are the caller's to add. */
lc_material lc_mtl_material(const lc_mtl *m);
/* What the mesh holds, valid until it grows or is freed: 3 doubles per
** vertex; 3 vertex indices (0-based) per face. */
const double   *lc_mesh_vertex_data(const lc_mesh *m);
const uint32_t *lc_mesh_face_data(const lc_mesh *m);
/* Reads v, vt, vn and f statements (negative indices; polygons become
** fans; a vertex split where its corners carry other vt or vn; uvs and
** normals kept when every corner has one); other statements are skipped;
** errors name the file and the line. */
lc_mesh  *lc_mesh_load_obj(const char *path, lc_error *err);

/* ---- Lights and camera ----------------------------------------------------- */

typedef enum { LC_FALLOFF_INVERSE_SQUARE, LC_FALLOFF_NONE } lc_falloff;

typedef struct {
    lc_vec3    position;
    lc_color   color;
    double     intensity;  /* a white kd = 1 surface facing the light at
                           ** distance d reads intensity / d^2 */
    lc_falloff falloff;
} lc_point_light;

lc_point_light lc_point_light_default(void);  /* at the origin, white, intensity 1,
                                              ** inverse-square falloff */
lc_status lc_point_light_check(const lc_point_light *l, lc_error *err);

/* A point light whose light is confined to a cone (POV-Ray's spotlight, pbrt's
** spot): colour and intensity as a point light's, times the cone's share
** toward the lit point (lc_spot_light_share). */
typedef struct {
    lc_vec3    position;
    lc_vec3    direction;  /* the cone's axis, the way it shines; any length > 0 */
    double     angle;      /* the cone's half-angle in degrees, in (0, 180) */
    double     soft;       /* the edge's width in degrees, in [0, angle]: full light
                           ** within angle - soft of the axis, none past angle, a
                           ** smoothstep of the cosine between */
    lc_color   color;
    double     intensity;  /* as a point light's, on the axis */
    lc_falloff falloff;
} lc_spot_light;

/* At the origin pointing down -y, angle 30, soft 5, white, intensity 1,
** inverse-square falloff. */
lc_spot_light lc_spot_light_default(void);
lc_status lc_spot_light_check(const lc_spot_light *l, lc_error *err);
/* The share of the spot's intensity that goes toward point p: 1 within
** angle - soft of the axis, 0 past angle (and at the position itself), and
** between, with t = (cos theta - cos angle) / (cos(angle - soft) - cos angle),
** t^2 (3 - 2 t). */
double lc_spot_light_share(const lc_spot_light *l, lc_vec3 p);

/* A light infinitely far away (a sun): parallel rays, parallel shadows, no
** falloff. A white kd = 1 surface facing it reads irradiance / pi, as under
** an emissive shape of that irradiance. */
typedef struct {
    lc_vec3  direction;    /* the way its light travels (from the sun); length > 0 */
    lc_color color;
    double   irradiance;   /* on a surface facing it, >= 0 */
} lc_directional_light;

lc_directional_light lc_directional_light_default(void);  /* straight down, white,
                                                          ** irradiance pi */
lc_status lc_directional_light_check(const lc_directional_light *l, lc_error *err);

typedef struct {
    lc_vec3 from, at, up;
    double  fov;          /* horizontal field of view in degrees, in (0, 180) */
    double  aperture;     /* thin lens diameter; 0 = pinhole, all in focus */
    double  focus;        /* distance from `from` to the sharp plane; 0 = to `at` */
} lc_camera;

lc_camera lc_camera_default(void);  /* from (0, 0, 0) at (0, 0, -1), up +y, fov 60,
                                    ** a pinhole: set `from` and `at` */
lc_status lc_camera_check(const lc_camera *c, lc_error *err);

/* ---- Textures ----------------------------------------------------------------
** A texture gives a colour at a surface point: a solid pattern over space
** (checker, stripes, gradient, noise, marble, wood), an image over the
** surface's texture coordinates, or a mix of two. Where a number is wanted
** (kd, ks, ...), its luminance (0.2126 r + 0.7152 g + 0.0722 b) is used. */
typedef enum {
    LC_TEX_CHECKER, LC_TEX_STRIPES, LC_TEX_GRADIENT, LC_TEX_NOISE, LC_TEX_MARBLE,
    LC_TEX_WOOD, LC_TEX_IMAGE, LC_TEX_MIX, LC_TEX_SKY, LC_TEX_KINDS
} lc_texture_kind;

/* Where a pattern is evaluated: at the world point, at the point in the
** object's own space (moved meshes and placed shapes: what their transform
** moved; other shapes: the world), or at (u, v, 0). */
typedef enum { LC_MAP_WORLD, LC_MAP_OBJECT, LC_MAP_UV } lc_texture_mapping;
typedef enum { LC_WRAP_REPEAT, LC_WRAP_CLAMP, LC_WRAP_MIRROR } lc_texture_wrap;

#define LC_MAX_OCTAVES 16
#define LC_MAX_TEXTURE_DEPTH 16   /* textures within textures, at most */

typedef struct lc_image lc_image;         /* see Images */
typedef struct lc_textures lc_textures;   /* a set of textures that refer to each other */

typedef struct {
    lc_texture_kind kind;
    lc_color a, b;         /* checker's two squares, stripes' two bands, the ends of a
                           ** gradient, the ramp of noise, marble and wood; mix: the two;
                           ** sky: the zenith and the horizon */
    lc_color c;            /* sky: the ground (straight down) */
    int      ta, tb;       /* or textures in their place: 1 + index in the set (0: the
                           ** colour) */
    int      tamount;      /* mix: 1 + index of the texture whose luminance weights b
                           ** over a; 0: the constant `amount` */
    double   amount;       /* mix: b's weight, in [0, 1] */
    double   scale;        /* the pattern's period (checker: a square's side), > 0 */
    lc_vec3  axis;         /* stripes: across this direction; gradient: from `origin`
                           ** to origin + axis (a at the start, b at the end) */
    lc_vec3  origin;
    int      octaves;      /* noise, marble, wood: 1..LC_MAX_OCTAVES */
    double   turbulence;   /* noise: 0 smooth noise, else turbulence (|noise| summed);
                           ** marble and wood: how far the noise bends veins and rings */
    lc_texture_mapping mapping;
    int      moved;        /* the pattern is placed by xf: evaluated at xf^-1 p */
    lc_transform xf;
    /* image: linear RGB, width x height, row 0 at the top (v = 1); copied
    ** when added. u wraps as `wrap` says, and v. Bilinear, or nearest. */
    const lc_image *image;
    lc_texture_wrap wrap;
    int      nearest;
} lc_texture;

lc_texture   lc_texture_default(lc_texture_kind kind);   /* white and black, scale 1 */
lc_textures *lc_textures_new(lc_error *err);
void         lc_textures_free(lc_textures *set);           /* NULL is a no-op */
/* Checks t and adds it (an image is copied); returns its index, or -1. A
** texture may refer only to textures added before it. */
int          lc_textures_add(lc_textures *set, const lc_texture *t, lc_error *err);
size_t       lc_textures_count(const lc_textures *set);
/* Texture i at a surface point: p in the world, q in the object's space
** (p where it has none), uv its texture coordinates. */
lc_color     lc_textures_eval(const lc_textures *set, int i, lc_vec3 p, lc_vec3 q,
                              const double uv[2]);
/* A sky (LC_TEX_SKY) over the direction d from the origin to the point, y
** = d_y / |d|: b + (a - b) y above the horizon, b + (c - b)(-y) below:
** zenith, horizon and ground colours at y = 1, 0, -1, linear between. */

/* The texture coordinates of the unit direction d, as on a sphere around
** the origin: u = 0.5 + atan2(d_x, d_z) / 2 pi, v = 0.5 + asin(d_y) / pi, so an
** image texture over them is an equirectangular map (its centre faces +z,
** its top row is straight up). */
void         lc_sky_uv(lc_vec3 d, double uv[2]);

/* Perlin's improved gradient noise (2002): 0 at integer points, in [-1, 1]. */
double       lc_noise(lc_vec3 p);

/* ---- Scenes ---------------------------------------------------------------- */

typedef struct lc_scene lc_scene;

typedef struct {
    lc_color background;  /* what a ray that hits nothing sees */
    int      background_texture;  /* or, when > 0, 1 + the index of the scene's
                          ** texture (lc_scene_add_texture) seen in each direction:
                          ** evaluated at the unit direction d as the point, at the
                          ** (u, v) a sphere has there (see lc_sky_uv) */
    lc_color ambient;     /* Ia: ka * C * Ia is added at every hit */
    int      max_depth;   /* bounces, >= 0: each reflection or refraction adds 1;
                          ** the seed used 3 */
} lc_settings;

#define LC_MAX_DEPTH 1000000

lc_settings lc_settings_default(void);                  /* black, none, 3 */

lc_scene *lc_scene_new(lc_error *err);
void      lc_scene_free(lc_scene *s);                   /* NULL is a no-op */
lc_status lc_scene_configure(lc_scene *s, const lc_settings *st, lc_error *err);
lc_settings lc_scene_settings(const lc_scene *s);
int       lc_scene_camera(const lc_scene *s, lc_camera *out);  /* 0: none set */
lc_status lc_scene_set_camera(lc_scene *s, const lc_camera *c, lc_error *err);
int       lc_scene_add_material(lc_scene *s, const lc_material *m, lc_error *err);
/* Adds a texture (an image is copied) for materials added after it to name
** (material.texture[slot] = 1 + the index returned); ta, tb and tamount
** name the scene's earlier textures the same way. Returns the index, or -1. */
int       lc_scene_add_texture(lc_scene *s, const lc_texture *t, lc_error *err);
int       lc_scene_add_shape(lc_scene *s, const lc_shape *sh, int material,
                             lc_error *err);            /* id >= 0, or -1 */
int       lc_scene_add_mesh(lc_scene *s, lc_mesh *m, int material, lc_error *err);
/* The mesh (moved by t, or as it is when t is NULL) with face material slot
** k taking the scene's material materials[k]: n must cover every slot the
** mesh has (n >= 1; a face without a slot takes materials[0]). */
int       lc_scene_add_mesh_materials(lc_scene *s, lc_mesh *m, const lc_transform *t,
                                      const int *materials, size_t n, lc_error *err);
/* The mesh moved by t, as an instance: however many times a mesh is added
** this way, its faces and their BVH are stored once. (The identity adds it
** as lc_scene_add_mesh does: its triangles join the scene's own BVH.) */
int       lc_scene_add_mesh_moved(lc_scene *s, lc_mesh *m, const lc_transform *t,
                                  int material, lc_error *err);
int       lc_scene_add_light(lc_scene *s, const lc_point_light *l, lc_error *err);
int       lc_scene_add_spot_light(lc_scene *s, const lc_spot_light *l, lc_error *err);
int       lc_scene_add_directional_light(lc_scene *s, const lc_directional_light *l,
                                         lc_error *err);
/* A copy scaled by `scale` about the origin and moved by `offset`, point-light
** intensities times scale^2, the camera's aperture and focus times scale,
** materials' absorption over scale: an exact renderer draws the same picture. */
lc_scene *lc_scene_transformed(const lc_scene *s, double scale, lc_vec3 offset,
                               lc_error *err);
size_t    lc_scene_shape_count(const lc_scene *s);     /* shapes, meshes and CSG */
size_t    lc_scene_light_count(const lc_scene *s);  /* point, spot, directional */

/* ---- Constructive solid geometry -------------------------------------------- */

/* A CSG object is a tree of closed solids, described flat in prefix order:
** an operation is followed by its `count` operands, each a whole subtree,
** and nodes[0] is the root. Leaves are closed solids: spheres, boxes,
** ellipsoids, tori, cylinders and cones with caps, and closed meshes (every
** edge shared by exactly two faces that run it opposite ways; the enclosed
** volume's sign says which side is out). A ray meets the object where the
** tree's set, evaluated on the leaves' insides along the ray, changes;
** crossings of different leaves within each other's rounding count as one
** event, so coincident faces leave no film. Each surface keeps its leaf's
** material; faces a difference cuts take the cutter's, or the first
** operand's with cut_object. A CSG object never lights others (its
** emissive leaves glow). Meshes are shaded flat. */
typedef enum {
    LC_CSG_SHAPE,          /* a leaf: `shape`, `material` */
    LC_CSG_MESH,           /* a leaf: `mesh` placed by `transform`, `material` */
    LC_CSG_UNION,          /* the set union; at the root (and in unions there) a
                           ** group: every operand's own surfaces are drawn */
    LC_CSG_INTERSECTION,   /* the set intersection */
    LC_CSG_DIFFERENCE,     /* the first operand minus the others */
    LC_CSG_MERGE,          /* the set union, drawn by its boundary alone */
    LC_CSG_OPS
} lc_csg_op;

typedef struct {
    lc_csg_op    op;
    int          count;       /* operations: the number of operands, >= 1 */
    int          cut_object;  /* differences: 1 gives the faces the others cut the
                              ** first operand's material; 0 the cutter's own */
    int          material;    /* leaves: a material index of the scene */
    lc_shape     shape;       /* LC_CSG_SHAPE */
    lc_mesh     *mesh;        /* LC_CSG_MESH: borrowed; a scene keeps its own hold */
    lc_transform transform;   /* LC_CSG_MESH: object to world (the identity: as is) */
} lc_csg_node;

#define LC_CSG_MAX_NODES 65536

const char *lc_csg_op_name(lc_csg_op op);           /* "shape", "mesh", "union", ... */
/* The tree's structure and its leaves, without a scene: shapes valid and
** closed, meshes closed (naming the first open edge), transforms invertible.
** The message names the node ("node 3: a plane is not a closed solid"). */
lc_status lc_csg_check(const lc_csg_node *nodes, size_t n, lc_error *err);
/* Adds the CSG object (its meshes with the faces they have now); returns
** its id, or -1. */
int       lc_scene_add_csg(lc_scene *s, const lc_csg_node *nodes, size_t n,
                           lc_error *err);

/* ---- Scene objects: listing and removing ------------------------------------ */

/* Every lc_scene_add_* (shape, mesh or light) returns the next id: 0, 1, 2...
** An id names its object until it is removed, and is never given again. */
typedef enum {
    LC_OBJECT_SHAPE, LC_OBJECT_MESH, LC_OBJECT_LIGHT, LC_OBJECT_CSG, LC_OBJECT_SPOT_LIGHT,
    LC_OBJECT_DIRECTIONAL_LIGHT
} lc_object_kind;

typedef struct {
    int            id;
    lc_object_kind kind;
    int            material;   /* shapes and meshes: the material's index; lights: -1 */
    lc_shape       shape;      /* shapes, as stored: in the world, plane normals unit */
    lc_mesh       *mesh;       /* meshes: borrowed; the scene holds it */
    int            moved;      /* meshes: added with a transform (an instance) */
    lc_transform   transform;  /* meshes: that transform, else the identity */
    lc_point_light light;      /* point lights */
    lc_spot_light  spot;       /* spot lights */
    lc_directional_light sun;  /* directional lights */
    const lc_csg_node *csg;    /* CSG objects: the description as stored (shapes as
                               ** lc_shape_stored gives them); borrowed until the
                               ** scene changes */
    size_t         csg_nodes;  /* its length */
} lc_object;

size_t    lc_scene_object_count(const lc_scene *s);
/* Fills out[0, min(n, count)) with the objects in the order added; returns count. */
size_t    lc_scene_objects(const lc_scene *s, lc_object *out, size_t n);
lc_status lc_scene_object(const lc_scene *s, int id, lc_object *out, lc_error *err);
/* Removes the object `id`; the others keep their ids. The scene is then
** exactly as if it had never been added (the next render compiles again),
** except that its material stays in the material list. */
lc_status lc_scene_remove(lc_scene *s, int id, lc_error *err);

/* ---- Rendering ------------------------------------------------------------- */

/* Effects the compile step found the scene needs; a render tests only these. */
enum {
    LC_NEED_SHADOW   = 1 << 0,   /* point lights light some material in use, with
                                 ** shadow rays unless the shadows switch is off */
    LC_NEED_EMITTER  = 1 << 1,   /* some shape emits and lights others */
    LC_NEED_SPECULAR = 1 << 2,   /* some material has ks > 0 and there are lights */
    LC_NEED_REFLECT  = 1 << 3,   /* some material has kr or kt > 0, max_depth > 0 */
    LC_NEED_AMBIENT  = 1 << 4,   /* ambient light and some ka > 0 */
    LC_NEED_GLOSSY   = 1 << 5,   /* some material has kr or kt > 0 and a cone */
    LC_NEED_AREA     = 1 << 6,   /* emissive shapes sampled as area lights */
    LC_NEED_LENS     = 1 << 7,   /* the camera has an aperture: depth of field */
    LC_NEED_REFRACT  = 1 << 8,   /* some material has kt > 0 and max_depth > 0 */
    LC_NEED_FILTER   = 1 << 9,   /* shadow rays cross materials with kt > 0 and
                                 ** shadow = filtered: no any-hit query for them */
    LC_NEED_TEXTURE  = 1 << 10,  /* some material in use has a texture */
    LC_NEED_SPOT     = 1 << 11,  /* spot lights light some material in use */
    LC_NEED_SUN      = 1 << 12,  /* directional lights light some material in use */
    LC_NEED_SKY      = 1 << 13,  /* the background is a texture over directions */
    LC_NEED_INDIRECT = 1 << 14,  /* indirect > 0: paths traced with light bouncing */
    LC_NEED_AO       = 1 << 15,  /* ambient light darkened by ambient occlusion */
    LC_NEEDS         = 16        /* how many: bit k is 1 << k */
};

typedef enum {
    LC_RAY_CAMERA,
    LC_RAY_SHADOW,       /* toward point lights, and emitters' centres when light_samples = 0 */
    LC_RAY_REFLECTION,   /* perfect mirror bounces */
    LC_RAY_GLOSSY,       /* bounces inside a diffusion cone */
    LC_RAY_LIGHT,        /* shadow rays toward sampled points of area lights */
    LC_RAY_CUT,          /* bounces not traced: their weight fell below the cutoff */
    LC_RAY_REFRACTION,   /* transmitted through a surface with kt > 0 */
    LC_RAY_INDIRECT,     /* a path's diffuse and highlight bounces (indirect > 0) */
    LC_RAY_AO,           /* ambient occlusion probes */
    LC_RAY_KINDS
} lc_ray_kind;

const char *lc_ray_kind_name(lc_ray_kind k);           /* "camera", ... */
const char *lc_need_name(unsigned need);                /* "shadow", ... */

/* Called between tiles on the thread that called lc_scene_render, with the
** share of tiles done; a nonzero return stops the render with LC_ECANCEL. */
typedef int (*lc_progress_fn)(void *ud, double done);

/* Called after each pass of a progressive render (lc_render_options'
** progressive), on the thread that called lc_scene_render with no worker
** running: img is the render's own image as it stands (every pixel the mean
** of the samples it took so far: read or copy it, do not keep or free it),
** pass counts from 1 and st holds the statistics so far. A nonzero return
** stops the render there: lc_scene_render returns that image, LC_OK, with
** st->stopped set when passes were left. */
struct lc_stats;
typedef int (*lc_pass_fn)(void *ud, const lc_image *img, int pass,
                          const struct lc_stats *st);

/* Stops the renders running now (building their BVH or tracing) with
** LC_ECANCEL, once tracing starts, within about 100 ms; renders started
** afterwards are not affected. Async-signal-safe: for a SIGINT handler. */
void lc_interrupt(void);

/* How the samples of one pixel are spread over each 2D dimension (pixel
** area, lens, cone, light): an Owen-scrambled Sobol' sequence (stratified
** at every prefix: what adaptive sampling needs), a jittered grid, or
** independent uniform numbers (the baseline stratification is measured by). */
typedef enum { LC_SAMPLER_SOBOL, LC_SAMPLER_JITTER, LC_SAMPLER_RANDOM } lc_sampler;

/* AOVs ("arbitrary output variables"): images a render returns beside its
** beauty when asked (lc_render_options.aovs, bit 1 << LC_AOV_*), each
** defined in docs/manual.md, "AOVs". Geometry is of the surface each camera
** sample meets first: depth and position of the pixel's nearest sample (not
** anti-aliased; depth is along the camera's axis, +infinity where no sample
** met anything); normal (the world-space shading normal, turned toward the
** camera) and albedo (the material's colour) the mean over all samples, 0
** for those that met nothing; object and material 1 + the object's id
** (what lc_scene_add_* returned) or 1 + its material's index, seen by most
** samples (0: the background), with the share of samples each covers
** (lc_image_matte). The light-path AOVs split the
** beauty by the first bounce of the camera's path, and sum to it: direct
** (lights, highlights and ambient light at the first hit), reflection and
** refraction (all a mirror or glossy reflection, or a refraction, brings
** back from there), indirect (all diffuse and highlight bounces bring back,
** with render option indirect > 0) and emission (the first hit's own
** emission, and the background a camera ray sees). */
typedef enum {
    LC_AOV_DEPTH, LC_AOV_NORMAL, LC_AOV_ALBEDO, LC_AOV_POSITION, LC_AOV_OBJECT,
    LC_AOV_MATERIAL, LC_AOV_DIRECT, LC_AOV_REFLECTION, LC_AOV_REFRACTION,
    LC_AOV_INDIRECT, LC_AOV_EMISSION, LC_AOVS
} lc_aov;

#define LC_AOV_ALL   ((1u << LC_AOVS) - 1)
#define LC_AOV_RANKS 4     /* ids an object or material AOV keeps per pixel */

const char *lc_aov_name(lc_aov a);     /* "depth", "normal", ...; NULL past the last */

typedef struct {
    int      width, height;  /* pixels, each in [1, LC_MAX_SIDE] */
    int      samples;        /* camera rays per pixel, >= 1; 1 = pixel centre (with
                             ** no lens); with noise > 0, the most a pixel takes */
    uint64_t seed;           /* every random number depends on it ... */
    uint32_t frame;          /* ... and on the animation frame */
    lc_sampler sampler;
    int      light_samples;  /* points sampled on each emissive shape at each hit;
                             ** 0: one ray to its centre (the seed's hard shadows) */
    int      cone_samples;   /* > 0: overrides every glossy material's count */
    int      max_depth;      /* >= 0: overrides the scene's; -1: the scene's */
    double   noise;          /* > 0: adaptive sampling: a pixel stops once its
                             ** estimated relative error is below this */
    int      min_samples;    /* adaptive: samples before the first check, >= 1 */
    int      glossy;         /* 0: diffusion cones become perfect mirrors */
    int      threads;        /* 0 = one per core */
    int      cosine;         /* 0 drops the n.l factor (the seed's figure 7) */
    double   cutoff;         /* a bounce whose weight (the product of kr, kt and
                             ** Fresnel terms, of absorption, and of colours when
                             ** absorb = all) is below this is not traced; 0 traces
                             ** every bounce to max_depth */
    int      shadows;        /* 0: lights reach every point facing them, no shadow rays */
    int      reflections;    /* 0: no mirror reflection at all */
    int      specular;       /* 0: no Phong highlights */
    int      generic;        /* 1: every material takes every shading step (a check
                             ** that the planned, specialised shading changes nothing) */
    lc_progress_fn progress; /* may be NULL */
    void    *progress_ud;
    int      alpha;          /* 1: the image gets an alpha channel, the share of each
                             ** pixel's camera samples that hit something; camera
                             ** rays that miss add nothing (the background is
                             ** transparent; reflections still see it) */
    int      indirect;       /* > 0: global illumination, paths of up to this many
                             ** diffuse or highlight bounces (path.c); 0: the seed's
                             ** direct light and mirrors, as ever */
    int      roulette;       /* indirect: 1 ends paths by Russian roulette after
                             ** LC_ROULETTE_DEPTH bounces (unbiased); 0 never */
    int      nee;            /* indirect: 1 samples lights at each bounce, weighted
                             ** against the BSDF's samples by the power heuristic;
                             ** 0 finds emitters and the sky by BSDF sampling alone
                             ** (point, spot and directional lights then light
                             ** nothing): a check of the estimator */
    int      ao_samples;     /* > 0: ambient light times the share of this many
                             ** cosine-weighted probes that travel ao_distance free */
    double   ao_distance;    /* how far a probe must get, > 0 */
    int      region[4];      /* x0, y0, x1, y1: only the pixels [x0, x1) x [y0, y1) of
                             ** the width x height frame, each exactly as in the whole
                             ** frame; the image is the region's size and knows where
                             ** it lies (lc_image_window). All 0: the whole frame */
    int      progressive;    /* 1: trace in passes, each pixel taking 1, 2, 4, ... (then
                             ** samples) camera samples in all, with noise > 0 1, 2, 4,
                             ** ... up to min_samples, then adaptive sampling's passes;
                             ** on_pass sees the image after each. The final image is
                             ** the same, bit for bit, as without (camera sample s of
                             ** N is the same sample); a pass is a lock-step of the
                             ** whole image, so it costs a little more */
    lc_pass_fn on_pass;      /* with progressive; may be NULL */
    void    *on_pass_ud;
    unsigned aovs;           /* bits 1 << LC_AOV_*: images rendered beside the beauty
                             ** (lc_image_aov); 0, the default, renders none and
                             ** costs nothing. Not with noise > 0 */
} lc_render_options;

#define LC_MAX_SAMPLES (1 << 20)      /* camera samples per pixel */
#define LC_MAX_THREADS 256
#define LC_MAX_SIDE   (1 << 20)      /* 1048576: a 70000 x 1 panorama strip fits */
#define LC_MAX_PIXELS ((size_t)1 << 28)  /* 268M pixels, 3 GiB of floats */

#define LC_MAX_LIGHT_SAMPLES 4096
#define LC_MAX_INDIRECT 1024          /* bounces of a path */
#define LC_ROULETTE_DEPTH 3           /* bounces before roulette may end a path */
#define LC_MAX_AO_SAMPLES 4096

/* 640x480, 1 sample, Sobol', 16 light samples, cutoff 1/255, every effect on */
lc_render_options lc_render_options_default(void);
lc_status lc_render_options_check(const lc_render_options *o, lc_error *err);

typedef struct lc_stats {
    double   seconds;            /* compile + trace */
    double   compile_seconds;
    double   trace_seconds;
    uint64_t rays[LC_RAY_KINDS];
    uint64_t samples;            /* camera samples over all pixels */
    uint64_t converged;          /* adaptive: pixels whose estimated error fell
                                 ** under `noise` before `samples` */
    unsigned needs;              /* LC_NEED_* bits */
    int      threads;
    size_t   bvh_nodes;          /* nodes of the hierarchy over bounded shapes */
    size_t   primitives;         /* shapes plus mesh triangles (a CSG object
                                 ** counts one), as traced */
    size_t   degenerate;         /* zero-area triangles skipped */
    uint64_t self_hits;          /* rays that hit the surface they left (not into it):
                                 ** 0 unless the geometry code has a bug */
    uint64_t prim_tests;         /* ray/primitive intersection tests */
    uint64_t node_tests;         /* ray/BVH node tests */
    uint64_t csg_tests;          /* the CSG sweeps' leaf tests: each search for a
                                 ** leaf's next crossing, each triangle of a mesh leaf */
    char     why[LC_NEEDS][160]; /* for each effect, why it is on or off */
    char     warning[160];       /* empty, or why the picture is likely not what was
                                 ** meant (no light at all; every pixel black) */
    int      passes;             /* passes traced: 1, or a progressive or adaptive
                                 ** render's count */
    int      stopped;            /* 1: on_pass stopped the render after `passes`,
                                 ** before its last pass */
    unsigned aovs;               /* the AOVs computed: bits 1 << LC_AOV_* */
} lc_stats;

lc_image *lc_scene_render(lc_scene *s, const lc_render_options *o, lc_stats *st,
                          lc_error *err);

/* The kind of light a shadow ray goes to: `light` is its index among the
** lights of that kind, 0-based (emitters: -1 - n for emissive shape n). */
typedef enum {
    LC_LIGHT_POINT, LC_LIGHT_SPOT, LC_LIGHT_DIRECTIONAL, LC_LIGHT_EMITTER,
    LC_LIGHT_SKY          /* the background, a light for paths (indirect > 0) */
} lc_light_kind;

/* One ray of a pixel's ray tree (lc_scene_explain). */
typedef struct {
    int          parent;        /* the ray this one leaves from; -1 for the camera ray */
    lc_ray_kind  kind;          /* camera, reflection, refraction, glossy, shadow... */
    lc_vec3      origin, direction;
    int          hit;           /* camera, reflection, refraction rays: met a surface;
                                ** shadow rays: reached their light */
    double       distance;      /* to that surface, or to the light */
    lc_vec3      point, normal; /* the surface hit; normal faces the ray */
    int          shape_kind;    /* LC_SPHERE ... LC_PLANE, or LC_SHAPE_KINDS for a
                                ** mesh triangle; -1 when nothing was hit */
    long         shape;         /* index among the shapes of that kind, in the order
                                ** added (triangles: among all meshes' faces) */
    int          material;      /* index of its material in the scene, 0-based */
    int          csg;           /* a CSG object's surface: its index among the scene's
                                ** CSG objects (shape_kind is the leaf's kind, shape
                                ** -1); else -1 */
    int          csg_node;      /* that leaf's index in the CSG's description */
    int          light_kind;    /* shadow rays: LC_LIGHT_POINT, ... */
    int          light;         /* shadow rays: the point light's index, 0-based, or
                                ** -1 - n for the emissive shape n (0-based) */
    lc_color     contribution;  /* what this ray adds to the pixel's value */
} lc_ray_record;

/* Traces one sample of pixel (x, y) (0-based, from the top-left) as render
** would with these options, recording every ray. *records is malloc'd:
** free() it. */
lc_status lc_scene_explain(lc_scene *s, const lc_render_options *o, int x, int y,
                           int sample, lc_ray_record **records, size_t *n,
                           lc_error *err);

/* ---- Casting rays ------------------------------------------------------------
** The scene's exact geometry alone, for scripts (drop objects on a terrain,
** scatter along a surface) and embedders: no shading, no lights. A ray is
** o + t d for tmin < t < tmax; d need not be unit, and t is in units of
** |d| (as in Embree). tmin > 0 starts the ray at o + tmin d. */
typedef struct {
    lc_vec3 origin, direction;
    double  tmin, tmax;           /* 0 <= tmin < tmax; tmax may be HUGE_VAL */
} lc_ray;

typedef struct {
    int      hit;                 /* 0: nothing on the ray, the rest unset */
    double   t;                   /* the hit is origin + t direction */
    lc_vec3  point;               /* on the surface, exactly as shading sees it */
    lc_vec3  normal;              /* unit geometric normal, outward for solids */
    lc_vec3  shading_normal;      /* interpolated on meshes with normals */
    double   uv[2];               /* texture coordinates (docs/manual.md) */
    int      object;              /* what lc_scene_add_* returned for it */
    int      shape_kind;          /* LC_SPHERE ..., or LC_SHAPE_KINDS for a mesh face */
    long     primitive;           /* a mesh face's index in its mesh; 0 for shapes */
    int      material;            /* index of its material in the scene, 0-based */
} lc_ray_hit;

/* The nearest hit of each of n rays into hits[0, n). Every ray is checked
** first (finite origin within the coordinate range, a non-zero finite
** direction, 0 <= tmin < tmax): a bad one fails the call naming it, with
** nothing traced. Stops with LC_ECANCEL on lc_interrupt. Casts on the
** caller's thread; several threads may cast into one scene at once (split
** the rays between them), and a cast waits for a render of that scene in
** progress on another thread to finish. Neighbours in the array that
** share an origin (a camera's rays in scanline or tile order) are traced
** eight at a time, through one walk of the hierarchy: the same answers,
** faster. */
lc_status lc_scene_intersect(lc_scene *s, const lc_ray *rays, size_t n, lc_ray_hit *hits,
                             lc_error *err);
/* Whether anything lies on each ray: blocked[i] = 1 or 0. Faster than
** lc_scene_intersect: the first hit found ends the search. */
lc_status lc_scene_occluded(lc_scene *s, const lc_ray *rays, size_t n,
                            unsigned char *blocked, lc_error *err);

/* ---- Images ---------------------------------------------------------------- */

typedef enum { LC_ENCODE_SRGB, LC_ENCODE_LINEAR } lc_encoding;

lc_image *lc_image_new(int width, int height, lc_error *err); /* black */
void      lc_image_free(lc_image *img);                 /* NULL is a no-op */
lc_image *lc_image_copy(const lc_image *img, lc_error *err); /* pixels, alpha, window */
int       lc_image_width(const lc_image *img);
int       lc_image_height(const lc_image *img);
lc_color  lc_image_get(const lc_image *img, int x, int y);  /* 0-based, top-left */
void      lc_image_set(lc_image *img, int x, int y, lc_color c);
uint8_t   lc_encode_channel(float linear, lc_encoding enc); /* clamp, encode, round */
lc_status lc_image_save_png(const lc_image *img, const char *path, lc_encoding enc,
                            lc_error *err);             /* temp file, then rename */
/* Saves in the format the path's extension names (.png or .exr, any case,
** with lc_save_options_default and enc: 8-bit PNG, half zip EXR); any other
** extension is refused, naming it, rather than written as PNG.
** Saves are atomic: the image goes to TARGET.tmp-HOST-PID-XXXXXX, renamed
** over TARGET once whole; a target that is not a regular file (a device,
** a FIFO, a directory) is refused; a symbolic link is saved through; the
** temporaries a killed save left on this host are removed by the next save
** of that target. */
lc_status lc_image_save(const lc_image *img, const char *path, lc_encoding enc,
                        lc_error *err);
/* Removes the temporaries of the saves in progress: for a SIGTERM or SIGINT
** handler, before the process dies. Async-signal-safe. */
void      lc_save_abandon(void);
/* Reads any PNG (every colour type and bit depth, palettes, tRNS,
** interlacing). LC_ENCODE_SRGB decodes to linear light as the file's
** gAMA/sRGB chunks say (none: sRGB), transparency composited onto black,
** as libpng's own reader does; LC_ENCODE_LINEAR takes the samples as stored,
** v / (2^depth - 1), and drops alpha. Grey becomes RGB. Sizes past
** LC_MAX_SIDE or LC_MAX_PIXELS are refused, naming the cap. */
lc_image *lc_image_load_png(const char *path, lc_encoding enc, lc_error *err);

/* Reads a Radiance .hdr (RGBE) image, linear floats as stored (FORMAT=
** 32-bit_rle_rgbe, -Y height +X width; flat or run-length coded scanlines).
** Every count is checked: sizes past LC_MAX_SIDE or LC_MAX_PIXELS, a file
** shorter than its size needs, a run of length 0 or past its scanline, data
** ending early are refused, naming the file and the scanline, before the
** pixels' memory is asked for where the header alone tells. */
lc_image *lc_image_load_hdr(const char *path, lc_error *err);

/* An image may carry an alpha channel (a render with alpha, a file with one):
** linear, one value per pixel; colours stay premultiplied by it in memory, as
** a render makes them and as EXR stores them. */
lc_status lc_image_add_alpha(lc_image *img, lc_error *err);  /* all 1; kept if there */
int       lc_image_has_alpha(const lc_image *img);
float     lc_image_get_alpha(const lc_image *img, int x, int y);   /* 1 without alpha */
void      lc_image_set_alpha(lc_image *img, int x, int y, float a); /* no-op without */

/* Where an image lies in its frame: a region render, or a part read back
** from a file, covers [x0, x0 + width) x [y0, y0 + height) of a frame_width x
** frame_height frame; every other image is its whole frame (0, 0, its size). */
typedef struct { int x0, y0, frame_width, frame_height; } lc_window;
lc_window lc_image_window(const lc_image *img);
lc_status lc_image_set_window(lc_image *img, lc_window w, lc_error *err); /* fits */

/* How lc_image_save_with writes. PNG: 8 or 16 bits per sample, sRGB or
** linear, RGB or RGBA (straight alpha, as PNG defines it). EXR: linear
** half or float channels R, G, B (and A), premultiplied, scanlines or tiles,
** compressed. A part of a frame (lc_image_window) is saved with its place:
** in EXR as its data window inside the frame's display window; in PNG as an
** oFFs chunk (its offset in pixels) and a tEXt chunk "lancer:frame" holding
** "W H", the frame's size. */
typedef enum { LC_EXR_HALF, LC_EXR_FLOAT } lc_exr_pixel;
/* What happens to a value past 1 (after exposure): clipped (the default), or
** rolled off by a filmic curve (lc_tone_curve) so highlights keep detail. */
typedef enum { LC_TONE_CLAMP, LC_TONE_FILMIC } lc_tone;
typedef enum { LC_EXR_ZIP, LC_EXR_PIZ, LC_EXR_ZIPS, LC_EXR_RLE, LC_EXR_NONE } lc_exr_compression;
typedef struct {
    lc_encoding encoding;            /* PNG: sRGB (default) or linear; EXR is linear */
    int         depth;               /* PNG: 8 (default) or 16 bits per sample */
    int         alpha;               /* 1: write the alpha channel (the image needs one) */
    lc_exr_pixel exr_pixel;          /* EXR: half (default) or float */
    lc_exr_compression exr_compression;  /* EXR: zip (default) */
    int         exr_tile;            /* EXR: 0 scanlines (default), else square tiles of
                                     ** this side, 1..LC_MAX_EXR_TILE */
    double      exposure;            /* colours times 2^exposure before the tone curve,
                                     ** in [-LC_MAX_EXPOSURE, LC_MAX_EXPOSURE]; 0 */
    lc_tone     tone;                /* LC_TONE_CLAMP (default) or LC_TONE_FILMIC */
    int         aovs;                /* EXR: 1 (default) writes the image's AOVs as
                                     ** layers of the one file (docs/manual.md, "AOVs":
                                     ** `Z`, then `normal.R` ...; depth, position and
                                     ** ids as float, the rest as exr_pixel, none of
                                     ** them toned); 0 the beauty alone. PNG: never */
} lc_save_options;

#define LC_MAX_EXPOSURE 64

/* The tone curve applied to one linear channel x (after exposure), before
** encoding: LC_TONE_CLAMP is x itself (clamped to [0, 1] by the encoding);
** LC_TONE_FILMIC is Narkowicz's fit of the ACES reference curve (2015),
** x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]. */
double lc_tone_curve(double x, lc_tone tone);

#define LC_MAX_EXR_TILE 4096

lc_save_options lc_save_options_default(void);       /* 8-bit sRGB; half, zip */
/* As lc_image_save, by the extension (.png or .exr, case-insensitive), with
** these options; half values past 65504 are written as +-65504. */
lc_status lc_image_save_with(const lc_image *img, const char *path,
                             const lc_save_options *o, lc_error *err);
/* Reads the first part of an EXR file: R, G, B (Y as grey when there is no
** colour; absent channels 0) and A when present, as float; its data window
** inside its display window becomes the image's window. Corrupt or
** truncated files, deep or unsupported parts and sizes past LC_MAX_SIDE or
** LC_MAX_PIXELS are refused, naming the file. */
lc_image *lc_image_load_exr(const char *path, lc_error *err);

/* An AOV a render made beside this image (see lc_aov): a new image, the
** caller's to free, of the image's size and window; NULL, saying so, when
** the render was not asked for it. Depth, object and material are grey (the
** same value in r, g and b); normal and position hold x, y, z in r, g, b. */
lc_image *lc_image_aov(const lc_image *img, lc_aov a, lc_error *err);
unsigned  lc_image_aovs(const lc_image *img);        /* bits 1 << LC_AOV_* it holds */
/* The coverage matte of `id` (a value of an object or material AOV, >= 1):
** each pixel the share of its camera samples whose first hit is that
** object (or material),
** exact while the pixel sees at most LC_AOV_RANKS ids (else those it sees
** least read 0). A new image, the caller's to free. */
lc_image *lc_image_matte(const lc_image *img, lc_aov a, int id, lc_error *err);

/* Assembles parts of one frame saved by lc_image_save_with (region renders)
** into the whole frame at `out`, sample for sample: the same bytes as the
** frame saved whole with the same options. The parts must all be PNG or all
** EXR like `out`, of one frame size and one format (depth, channels,
** encoding; pixel type, compression, tiling), cover the frame and not
** overlap; otherwise the error names the part, or the first pixel missed. */
lc_status lc_image_merge(const char *out, const char *const *parts, size_t n,
                         lc_error *err);

typedef struct {
    double mean_abs;      /* mean |a - b| over every channel */
    double max_abs;       /* largest |a - b| */
    double within;        /* share of pixels whose channels all differ <= tol */
    int    worst_x, worst_y;
} lc_image_diff;

size_t    lc_image_nonfinite(const lc_image *img);  /* NaN and infinite channels */
lc_status lc_image_compare(const lc_image *a, const lc_image *b, double tol,
                           lc_image_diff *d, lc_error *err);   /* same size */

/* How far an image is from a reference, over every channel of every pixel,
** on linear values (docs/numerics.md 3.1), summed in double. */
typedef struct {
    double mse;           /* mean (x - ref)^2 */
    double rmse;          /* sqrt(mse) */
    double relmse;        /* mean (x - ref)^2 / (|ref| + 0.01)^2, pbrt-v4's MRSE: dark
                          ** pixels count, bright ones do not drown the rest */
    double mae;           /* mean |x - ref| */
    double bias;          /* mean (x - ref), signed: what more samples do not remove */
} lc_image_error_stats;

lc_status lc_image_error(const lc_image *img, const lc_image *ref,
                         lc_image_error_stats *out, lc_error *err);   /* same size */
/* img += weight * other, channel by channel (same size): averages renders. */
lc_status lc_image_add(lc_image *img, const lc_image *other, double weight,
                       lc_error *err);

#endif
