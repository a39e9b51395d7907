/* camera.h: the pinhole camera's frame and its primary rays. */
#ifndef LC_CAMERA_H
#define LC_CAMERA_H

#include "geom.h"

typedef struct {
    lc_vec3 o, f, r, u;   /* eye; forward, right, up (unit) */
    double  tx, ty;       /* half-extent of the image plane at distance 1 */
    double  w, h;
} camera_frame;

void   camera_frame_init(const lc_camera *c, int width, int height, camera_frame *cf);
/* (px, py): image coordinates, x from the left, y from the top; pixel (i, j)
** covers [i, i+1) x [j, j+1), so its centre is (i + 0.5, j + 0.5). */
lc_ray camera_ray(const camera_frame *cf, double px, double py);

#endif
