/* image.h: the image's layout, shared by image.c, png.c and render.c. */
#ifndef LC_IMAGE_H
#define LC_IMAGE_H

#include "lancer.h"

struct lc_image {
    int    width, height;
    float *px;            /* linear RGB, row-major from the top-left */
};

#endif
