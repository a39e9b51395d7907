/* camera.h: the camera's frame and its primary rays, pinhole or thin lens. */
#ifndef LC_CAMERA_H
#define LC_CAMERA_H

#include "base/geom.h"

typedef struct {
    lc_vec3 o, f, r, u;   /* eye; forward, right, up (unit) */
    double  tx, ty;       /* half-extent of the image plane at distance 1 */
    double  w, h;
    double  lens_radius;  /* half the aperture; 0 for a pinhole */
    double  focus;        /* distance to the plane in focus, along f */
} camera_frame;

void   camera_frame_init(const lc_camera *c, int width, int height, camera_frame *cf);
/* (px, py): image coordinates, x from the left, y from the top; pixel (i, j)
** covers [i, i+1) x [j, j+1), so its centre is (i + 0.5, j + 0.5). */
ray camera_ray(const camera_frame *cf, double px, double py);
/* The distance to the plane in focus: the camera's, or |at - from|. */
double camera_focus(const lc_camera *c);
/* Moves the ray's origin to the lens point u (in [0, 1)^2) and aims it at
** the point it saw on the plane in focus (thin lens). */
void   camera_lens(const camera_frame *cf, ray *r, const double u[2]);

#endif
