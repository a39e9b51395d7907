/* texture.h: what shading and scenes need of texture sets beyond lancer.h. */
#ifndef LC_TEXTURE_H
#define LC_TEXTURE_H

#include "lancer.h"

/* A copy of the set for a scene moved by x -> scale x + offset: textures
** over world space move with it (their placement composed with the move),
** but for texture keep - 1 (keep > 0) and those within it: the background,
** over directions, which no move changes. */
lc_textures *textures_transformed(const lc_textures *s, double scale, lc_vec3 offset,
                                  int keep, lc_error *err);
/* Luminance 0.2126 r + 0.7152 g + 0.0722 b of texture i at the point. */
double       textures_scalar(const lc_textures *s, int i, lc_vec3 p, lc_vec3 q,
                             const double uv[2]);
/* The step over which a bump's slope is taken: a thousandth of its period. */
double       textures_step(const lc_textures *s, int i);
/* 1 when texture i is an image laid once over the texture coordinates (not
** moved, scale 1): its linear RGB texels, row 0 at the top, w x h, and
** whether it is read by nearest texel (else bilinearly). */
int          textures_image(const lc_textures *s, int i, const float **px, int *w,
                            int *h, int *nearest);
/* 1 when texture i, or one within it, reads texture coordinates. */
int          textures_use_uv(const lc_textures *s, int i);

#endif
