/* camera.c: the camera's frame and its primary rays, pinhole or thin lens. */
#include "camera.h"

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
    cf->lens_radius = c->aperture / 2;
    cf->focus = camera_focus(c);
}

double camera_focus(const lc_camera *c)
{
    return c->focus > 0 ? c->focus : v3_len(v3_sub(c->at, c->from));
}

/* Shirley and Chiu's concentric map of the unit square onto the unit disc:
** it keeps strata compact, so a stratified lens stays stratified. */
static void concentric_disc(const double u[2], double *x, double *y)
{
    double a = 2 * u[0] - 1, b = 2 * u[1] - 1;
    if (a == 0 && b == 0) {
        *x = *y = 0;
        return;
    }
    double r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (PI / 4) * (b / a);
    } else {
        r = b;
        phi = PI / 2 - (PI / 4) * (a / b);
    }
    *x = r * cos(phi);
    *y = r * sin(phi);
}

void camera_lens(const camera_frame *cf, ray *r, const double u[2])
{
    double lx, ly;
    concentric_disc(u, &lx, &ly);
    /* Every ray through the pixel meets the plane in focus at the point the
    ** pinhole ray meets it: that plane is sharp, the rest blurs. */
    lc_vec3 p = v3_madd(r->o, r->d, cf->focus / v3_dot(r->d, cf->f));
    lc_vec3 o = v3_madd(v3_madd(r->o, cf->r, lx * cf->lens_radius), cf->u,
                        ly * cf->lens_radius);
    r->o = o;
    r->d = v3_norm(v3_sub(p, o));
}

ray camera_ray(const camera_frame *cf, double px, double py)
{
    double sx = (2 * px / cf->w - 1) * cf->tx;
    double sy = (1 - 2 * py / cf->h) * cf->ty;
    ray r;
    r.o = cf->o;
    r.d = v3_norm(v3_add(cf->f, v3_add(v3_mul(cf->r, sx), v3_mul(cf->u, sy))));
    return r;
}
