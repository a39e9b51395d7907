/* sky.c: the background as a texture over directions: a sky gradient, an
** equirectangular image, or any texture, looked up where a ray leaves. */
#include "sky.h"
#include "texture.h"

void lc_sky_uv(lc_vec3 d, double uv[2])
{
    sphere_uv_of_direction(d, uv);
}

radiance sky_radiance(const lc_scene *s, lc_vec3 d)
{
    int i = s->settings.background_texture - 1;
    lc_vec3 u = v3_norm(d);
    double uv[2] = {0, 0};
    if (s->c.sky_uv)
        lc_sky_uv(u, uv);
    lc_color c = lc_textures_eval(s->textures, i, u, u, uv);
    radiance r = {c.r > 0 ? c.r : 0, c.g > 0 ? c.g : 0, c.b > 0 ? c.b : 0};
    return r;
}
