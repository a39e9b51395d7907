/* main_merge.c: lancer --merge OUT PARTS...: the parts of one frame, rendered
** with --tile or --region (on as many machines), as the whole frame. */
#include <stdio.h>
#include "lancer.h"
#include "main.h"

int merge_run(const struct cmdline *cl)
{
    lc_error err;
    int n = cl->argc - cl->merge - 1;
    const char *const *parts = (const char *const *)(cl->argv + cl->merge + 1);
    if (lc_image_merge(cl->argv[cl->merge], parts, (size_t)n, &err) != LC_OK) {
        fprintf(stderr, "lancer: %s\n", err.msg);
        return 1;
    }
    return 0;
}
