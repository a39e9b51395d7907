/* tone.c: exposure and the tone curves applied to linear values as an image
** is written. */
#include <math.h>
#include "lancer.h"

/* Narkowicz, "ACES Filmic Tone Mapping Curve" (2015): a rational fit of the
** ACES reference rendering transform's tone scale, per channel. */
#define ACES_A 2.51
#define ACES_B 0.03
#define ACES_C 2.43
#define ACES_D 0.59
#define ACES_E 0.14

double lc_tone_curve(double x, lc_tone tone)
{
    if (!(x > 0))                /* NaN and negatives write as 0 */
        return 0;
    if (tone != LC_TONE_FILMIC)
        return x;
    if (isinf(x))
        return 1;
    double y = x * (ACES_A * x + ACES_B) / (x * (ACES_C * x + ACES_D) + ACES_E);
    return y < 1 ? y : 1;
}
