/* image.h: the image's layout, shared by image.c, the file formats and render.c. */
#ifndef LC_IMAGE_H
#define LC_IMAGE_H

#include "lancer.h"

struct lc_image {
    int    width, height;
    float *px;            /* linear RGB, row-major from the top-left */
    float *alpha;         /* NULL, or one per pixel (coverage; colours premultiplied) */
    lc_window win;        /* where it lies in its frame: (0, 0, width, height) if whole */
    lc_image *aov[LC_AOVS];   /* a render's AOVs (aov.c), owned; NULL: not made */
    float *ranks;         /* an object or material AOV: per pixel LC_AOV_RANKS pairs
                          ** (id, share of samples), most samples first; id 0: none */
};

/* Clamped to [0, 1] (NaN reads as 0), encoded, rounded to nearest 16 bits. */
uint16_t image_encode16(float linear, lc_encoding enc);
/* lc_encode_channel over linear[0, n), into out: a row at a time, so the
** check that its tables are made is paid once a row, not once a value. */
void     image_encode8(const float *linear, size_t n, lc_encoding enc, uint8_t *out);

#endif
