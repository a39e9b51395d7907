/* save.h: writing a file atomically, a temporary beside the target renamed
** over it once whole. */
#ifndef LC_SAVE_H
#define LC_SAVE_H

#include <stdio.h>
#include "lancer.h"

typedef struct {
    FILE *fp;          /* write here */
    char *target;      /* the file it becomes (a link's target, resolved) */
    char *tmp;         /* TARGET.tmp-HOST-PID-XXXXXX */
    int   slot;        /* in lc_save_abandon's list, or -1 */
} save_file;

/* Refuses targets that are not regular files, removes stale temporaries of
** the target (killed saves on this host), opens a new one. */
lc_status save_begin(save_file *sf, const char *path, lc_error *err);
/* Flushes, syncs and renames over the target; on failure, removes it. */
lc_status save_commit(save_file *sf, lc_error *err);
void      save_abort(save_file *sf);      /* removes the temporary */

#endif
