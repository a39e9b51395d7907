/* main_watch.c: lancer --watch: the script again each time a file it read changes. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/stat.h>

#include "main.h"

/* How often the files are looked at: a save shows within this, plus the
** script's run. stat() of a few files ten times a second costs nothing
** measurable, works on every file system (inotify misses network mounts),
** and sees editors that save by renaming a new file over the old. */
#define POLL_NS 100000000L

static volatile sig_atomic_t quit;

static void on_quit(int sig)
{
    (void)sig;
    quit = 1;
}

/* What tells a file changed: its mtime, size and inode (a rename over it). */
typedef struct {
    char           *path;
    int             exists;
    struct timespec mtime;
    off_t           size;
    ino_t           ino;
} stamp;

static void take(stamp *s)
{
    struct stat st;
    s->exists = stat(s->path, &st) == 0;
    if (s->exists) {
        s->mtime = st.st_mtim;
        s->size = st.st_size;
        s->ino = st.st_ino;
    }
}

static int changed(const stamp *s)
{
    stamp now = *s;
    take(&now);
    if (now.exists != s->exists)
        return 1;
    return now.exists && (now.mtime.tv_sec != s->mtime.tv_sec ||
                          now.mtime.tv_nsec != s->mtime.tv_nsec ||
                          now.size != s->size || now.ino != s->ino);
}

static void free_stamps(stamp *s, int n)
{
    for (int k = 0; k < n; k++)
        free(s[k].path);
    free(s);
}

/* The stamps of the files a run read (the script first), each as it was
** before the run when it was watched then (a save during the run is a
** change), else as it is now. NULL when out of memory. */
static stamp *stamps_after(const char *script, char **files, const stamp *before,
                           int nbefore, int *n)
{
    int count = 1;
    for (int k = 0; files && files[k]; k++)
        count++;
    stamp *s = calloc((size_t)count, sizeof *s);
    if (!s)
        return NULL;
    *n = 0;
    for (int k = -1; k < count - 1; k++) {
        const char *path = k < 0 ? script : files[k];
        int dup = 0;
        for (int i = 0; i < *n; i++)
            dup |= strcmp(s[i].path, path) == 0;
        if (dup)
            continue;
        stamp *t = &s[*n];
        if ((t->path = strdup(path)) == NULL) {
            free_stamps(s, *n);
            return NULL;
        }
        ++*n;
        int known = 0;
        for (int i = 0; i < nbefore && !known; i++)
            if (strcmp(before[i].path, path) == 0) {
                char *own = t->path;
                *t = before[i];
                t->path = own;
                known = 1;
            }
        if (!known)
            take(t);
    }
    return s;
}

int watch_run(struct cmdline *cl, int (*run_once)(struct cmdline *cl, char ***files))
{
    const char *script = cl->argv[cl->script];
    struct sigaction old;
    stamp *stamps = NULL;
    int nstamps = 0;
    stamp first = {(char *)script, 0, {0, 0}, 0, 0};
    take(&first);                     /* a save while the first run runs counts */
    host_set_sigint(on_quit, &old);   /* host_docall arms its own while code runs */
    while (!quit) {
        char **files = NULL;
        run_once(cl, &files);
        int nnext = 0;
        stamp *next = stamps_after(script, files, stamps ? stamps : &first,
                                   stamps ? nstamps : 1, &nnext);
        for (int k = 0; files && files[k]; k++)
            free(files[k]);
        free(files);
        if (stamps)
            free_stamps(stamps, nstamps);
        stamps = next;
        nstamps = nnext;
        if (!stamps) {
            fprintf(stderr, "lancer: --watch: not enough memory\n");
            sigaction(SIGINT, &old, NULL);
            return 1;
        }
        fprintf(stderr, "lancer: watching %s%s; Ctrl-C quits\n", script,
                nstamps > 1 ? (nstamps > 2 ? " and the files it loads" : " and the file "
                               "it loads") : "");
        fflush(stderr);
        int again = 0;
        while (!quit && !again) {
            struct timespec pause = {0, POLL_NS};
            nanosleep(&pause, NULL);
            for (int k = 0; k < nstamps && !again; k++)
                again = changed(&stamps[k]);
        }
        /* The stamps as they are now: a file saved again while the run runs
        ** shows as a change after it. */
        for (int k = 0; k < nstamps; k++)
            take(&stamps[k]);
    }
    sigaction(SIGINT, &old, NULL);
    free_stamps(stamps, nstamps);
    fputs("\n", stderr);
    return 0;
}
