/* save.c: writing a file atomically: a temporary beside the target, renamed
** over it once whole; temporaries of saves a signal interrupted removed, now
** or by the next save. */
#define _XOPEN_SOURCE 700          /* realpath */
#include <dirent.h>
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include "error.h"
#include "mem.h"
#include "save.h"

/* A temporary is named TARGET.tmp-HOST-PID-XXXXXX: a later save of the same
** target on the same host can tell one whose process is gone (stale) from
** one another process is still writing. */
#define TMP_TAG ".tmp-"
#define HOST_MAX 32

/* Saves in progress, for lc_save_abandon from a signal handler: a slot is
** claimed, its path written, then marked ready; the handler unlinks the
** ready ones (unlink is async-signal-safe). */
#define SLOTS 16
#define SLOT_PATH 4096
static struct {
    int  state;                 /* 0 free, 1 claimed, 2 ready */
    char path[SLOT_PATH];
} slots[SLOTS];

static int claim(const char *tmp)
{
    if (strlen(tmp) >= SLOT_PATH)
        return -1;
    for (int i = 0; i < SLOTS; i++) {
        int free_state = 0;
        if (__atomic_compare_exchange_n(&slots[i].state, &free_state, 1, 0,
                                        __ATOMIC_ACQ_REL, __ATOMIC_RELAXED)) {
            strcpy(slots[i].path, tmp);
            __atomic_store_n(&slots[i].state, 2, __ATOMIC_RELEASE);
            return i;
        }
    }
    return -1;                  /* more than 16 at once: the next save tidies */
}

static void release(int slot)
{
    if (slot >= 0)
        __atomic_store_n(&slots[slot].state, 0, __ATOMIC_RELEASE);
}

void lc_save_abandon(void)
{
    for (int i = 0; i < SLOTS; i++)
        if (__atomic_load_n(&slots[i].state, __ATOMIC_ACQUIRE) == 2)
            unlink(slots[i].path);
}

/* This host's name, reduced to [A-Za-z0-9.] so it cannot hold the tag's
** dashes. */
static void host_name(char out[HOST_MAX + 1])
{
    char h[256];
    if (gethostname(h, sizeof h) != 0)
        strcpy(h, "host");
    h[sizeof h - 1] = '\0';
    size_t n = 0;
    for (const char *p = h; *p && n < HOST_MAX; p++)
        if ((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') ||
            (*p >= '0' && *p <= '9') || *p == '.')
            out[n++] = *p;
    if (n == 0)
        out[n++] = 'h';
    out[n] = '\0';
}

/* Removes NAME.tmp-HOST-PID-XXXXXX beside `path` whose HOST is this one and
** whose PID no longer runs: what a killed save left. */
static void remove_stale(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t dlen = slash ? (size_t)(slash - path) : 0;
    const char *base = slash ? slash + 1 : path;
    char *dir = mem_alloc(dlen + 2);
    if (!dir)
        return;
    if (!slash)
        strcpy(dir, ".");
    else if (dlen == 0)
        strcpy(dir, "/");
    else
        memcpy(dir, path, dlen), dir[dlen] = '\0';
    DIR *d = opendir(dir);
    char host[HOST_MAX + 1];
    host_name(host);
    size_t blen = strlen(base), hlen = strlen(host);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL) {
        const char *n = e->d_name;
        if (strncmp(n, base, blen) != 0 || strncmp(n + blen, TMP_TAG, 5) != 0)
            continue;
        const char *rest = n + blen + 5;                  /* HOST-PID-XXXXXX */
        if (strncmp(rest, host, hlen) != 0 || rest[hlen] != '-')
            continue;
        char *end;
        long pid = strtol(rest + hlen + 1, &end, 10);
        if (pid <= 0 || *end != '-' || strlen(end + 1) != 6)
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue;                                     /* still running */
        size_t plen = (slash ? dlen + 1 : 0) + strlen(n) + 1;
        char *full = mem_alloc(plen);
        if (!full)
            break;
        snprintf(full, plen, "%.*s%s%s", (int)dlen, path, slash ? "/" : "", n);
        unlink(full);
        mem_free(full);
    }
    if (d)
        closedir(d);
    mem_free(dir);
}

lc_status save_begin(save_file *sf, const char *path, lc_error *err)
{
    memset(sf, 0, sizeof *sf);
    sf->slot = -1;
    if (!*path)
        return error_fail(err, LC_EARG, "path", "file name is empty");
    /* Only files: renaming over a device, a FIFO or a socket would replace
    ** the node (img:save("/dev/null") once did). A symbolic link is saved
    ** through: the file it names is replaced, the link stays. */
    struct stat st;
    char *target = NULL;
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) {
        target = realpath(path, NULL);
        if (!target)
            return error_fail(err, LC_EIO, "path", "cannot write '%s': %s", path,
                              strerror(errno));
        path = target;
    }
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        const char *what = S_ISDIR(st.st_mode) ? "a directory" : S_ISCHR(st.st_mode) ?
                           "a character device" : S_ISBLK(st.st_mode) ? "a block device" :
                           S_ISFIFO(st.st_mode) ? "a FIFO" : S_ISSOCK(st.st_mode) ?
                           "a socket" : "not a regular file";
        lc_status r = error_fail(err, LC_EARG, "path", "cannot write '%s': it is %s, and "
                                 "lancer saves images to files only", path, what);
        free(target);
        return r;
    }
    remove_stale(path);
    char host[HOST_MAX + 1];
    host_name(host);
    size_t n = strlen(path) + strlen(TMP_TAG) + HOST_MAX + 32;
    sf->target = mem_alloc(strlen(path) + 1);
    sf->tmp = mem_alloc(n);
    if (!sf->target || !sf->tmp) {
        free(target);
        save_abort(sf);
        return error_fail(err, LC_ENOMEM, NULL, "out of memory writing '%s'", path);
    }
    strcpy(sf->target, path);
    free(target);
    snprintf(sf->tmp, n, "%s%s%s-%ld-XXXXXX", sf->target, TMP_TAG, host, (long)getpid());
    /* The temporary is made and listed for lc_save_abandon with the fatal
    ** signals held, so no handler runs between the two (and misses it). */
    sigset_t fatal, old_mask;
    sigemptyset(&fatal);
    sigaddset(&fatal, SIGTERM);
    sigaddset(&fatal, SIGINT);
    sigaddset(&fatal, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &fatal, &old_mask);
    int fd = mkstemp(sf->tmp);
    if (fd >= 0)
        sf->slot = claim(sf->tmp);
    pthread_sigmask(SIG_SETMASK, &old_mask, NULL);
    if (fd < 0) {
        lc_status r = error_fail(err, LC_EIO, "path", "cannot write '%s': %s", sf->target,
                                 strerror(errno));
        mem_free(sf->tmp);
        sf->tmp = NULL;
        save_abort(sf);
        return r;
    }
    sf->fp = fdopen(fd, "wb");
    if (!sf->fp) {
        lc_status r = error_fail(err, LC_EIO, "path", "cannot write '%s': %s", sf->target,
                                 strerror(errno));
        close(fd);
        save_abort(sf);
        return r;
    }
    /* Past ulimit -f, the default of SIGXFSZ kills the process and leaves
    ** the temporary: ignored, the write fails with EFBIG and is reported. */
    struct sigaction ign, old;
    memset(&ign, 0, sizeof ign);
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    if (sigaction(SIGXFSZ, NULL, &old) == 0 && old.sa_handler == SIG_DFL)
        sigaction(SIGXFSZ, &ign, NULL);
    return LC_OK;
}

lc_status save_commit(save_file *sf, lc_error *err)
{
    lc_status st = LC_OK;
    if (fflush(sf->fp) != 0 || fsync(fileno(sf->fp)) != 0)
        st = error_fail(err, LC_EIO, "path", "cannot write '%s': %s", sf->target,
                        strerror(errno));
    if (fclose(sf->fp) != 0 && st == LC_OK)
        st = error_fail(err, LC_EIO, "path", "cannot write '%s': %s", sf->target,
                        strerror(errno));
    sf->fp = NULL;
    /* mkstemp makes the file 0600; an image is meant to be shared like any file. */
    if (st == LC_OK) {
        mode_t um = umask(0);
        umask(um);
        chmod(sf->tmp, 0666 & ~um);
    }
    if (st == LC_OK && rename(sf->tmp, sf->target) != 0)
        st = error_fail(err, LC_EIO, "path", "cannot write '%s': %s", sf->target,
                        strerror(errno));
    if (st == LC_OK) {
        release(sf->slot);
        sf->slot = -1;
        mem_free(sf->tmp);
        sf->tmp = NULL;
        mem_free(sf->target);
        sf->target = NULL;
        error_ok(err);
        return LC_OK;
    }
    save_abort(sf);
    return st;
}

void save_abort(save_file *sf)
{
    if (sf->fp)
        fclose(sf->fp);
    if (sf->tmp)
        unlink(sf->tmp);
    release(sf->slot);
    mem_free(sf->tmp);
    mem_free(sf->target);
    memset(sf, 0, sizeof *sf);
    sf->slot = -1;
}
