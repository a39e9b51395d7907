/* camera.c: the pinhole camera's frame and its primary rays. */
#include "camera.h"

#define PI 3.14159265358979323846

void camera_frame_init(const lc_camera *c, int width, int height, camera_frame *cf)
{
    cf->o = c->from;
    cf->f = v3_norm(v3_sub(c->at, c->from));
    cf->r = v3_norm(v3_cross(cf->f, c->up));
    cf->u = v3_cross(cf->r, cf->f);
    cf->tx = tan(c->fov * PI / 360.0);          /* fov is horizontal */
    cf->ty = cf->tx * height / width;
    cf->w = width;
    cf->h = height;
}

lc_ray camera_ray(const camera_frame *cf, double px, double py)
{
    double sx = (2 * px / cf->w - 1) * cf->tx;
    double sy = (1 - 2 * py / cf->h) * cf->ty;
    lc_ray r;
    r.o = cf->o;
    r.d = v3_norm(v3_add(cf->f, v3_add(v3_mul(cf->r, sx), v3_mul(cf->u, sy))));
    return r;
}
