/* image_io.c: saving images in the format their file name asks for. */
#include <string.h>
#include <strings.h>
#include "error.h"

lc_status lc_image_save(const lc_image *img, const char *path, lc_encoding enc,
                        lc_error *err)
{
    if (!*path)
        return error_fail(err, LC_EARG, "path", "file name is empty");
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (dot && slash && dot < slash)
        dot = NULL;                                 /* a dot in a folder's name */
    if (dot && strcasecmp(dot, ".png") == 0)
        return lc_image_save_png(img, path, enc, err);
    if (!dot || dot[1] == '\0')
        return error_fail(err, LC_EARG, "path", "cannot write '%s': no extension (lancer "
                       "writes .png)", path);
    return error_fail(err, LC_EARG, "path", "cannot write '%s': unknown extension '%s' "
                   "(lancer writes .png)", path, dot);
}
