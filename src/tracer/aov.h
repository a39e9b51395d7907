/* aov.h: what a camera sample records for the AOVs beside its radiance, and
** the pixel sums those records go into. */
#ifndef LC_AOV_H
#define LC_AOV_H

#include "image/image.h"
#include "base/radiance.h"
#include "base/vec.h"

/* The light-path AOVs, in the order of lc_aov from LC_AOV_DIRECT; a path
** not yet past its first hit is of class AOV_CAMERA, and what it brings
** back counts as emission (the background seen, the surface's own glow). */
enum { AOV_DIRECT, AOV_REFLECTION, AOV_REFRACTION, AOV_INDIRECT, AOV_EMISSION,
       AOV_PATHS, AOV_CAMERA = AOV_PATHS };

typedef struct {
    radiance light[AOV_PATHS];
    int      hit;                 /* the camera ray met a surface: the rest is set */
    lc_vec3  position, normal;
    radiance albedo;
    int      object, material;
} aov_sample;

/* Adds c to the light of class cls (AOV_CAMERA: emission). */
static inline void aov_add(aov_sample *as, int cls, radiance c)
{
    int k = cls == AOV_CAMERA ? AOV_EMISSION : cls;
    as->light[k] = r_add(as->light[k], c);
}

/* One id of a pixel and the samples that saw it. */
typedef struct { int id; uint32_t n; } aov_count;

/* A pixel's records summed over its samples. The id lists have room for
** every sample (`room` of them, the tracer's). */
typedef struct {
    double    light[AOV_PATHS][3], normal[3], albedo[3];
    double    depth;              /* nearest so far; HUGE_VAL: none */
    lc_vec3   position;           /* of the nearest */
    aov_count *objects, *materials;
    uint32_t  nobjects, nmaterials;
} aov_pixel;

/* Room for the id lists of one pixel of n samples (mem_alloc'd: mem_free
** both); 0 when out of memory. */
int  aov_room(uint32_t n, aov_count **objects, aov_count **materials);
void aov_pixel_begin(aov_pixel *p, aov_count *objects, aov_count *materials);
/* Sample as of a camera at eye looking along unit forward. */
void aov_pixel_add(aov_pixel *p, const aov_sample *as, lc_vec3 eye, lc_vec3 forward);
/* The AOV images `aovs` (bits 1 << LC_AOV_*) for img, its size and window;
** 0, saying so, when out of memory. */
lc_status aov_images_new(lc_image *img, unsigned aovs, lc_error *err);
/* Writes pixel (x, y) of img's AOVs from p's sums over n samples. */
void aov_put(lc_image *img, int x, int y, const aov_pixel *p, uint32_t n);

#endif
