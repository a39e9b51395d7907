/* memfile.h: what the harnesses share: the input as an in-memory file that
** a reader opens by its /proc name, so no execution touches the disk. The
** harness defines _GNU_SOURCE (memfd_create) before its first include. */
#ifndef LC_FUZZ_MEMFILE_H
#define LC_FUZZ_MEMFILE_H

#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

typedef struct {
    int  fd;
    char path[64];     /* /proc/self/fd/N: what the reader is given */
} memfile;

/* A new empty file named name (for messages); aborts when none can be made. */
static inline void memfile_open(memfile *f, const char *name)
{
    f->fd = memfd_create(name, 0);
    if (f->fd < 0) {
        perror("memfd_create");
        abort();
    }
    snprintf(f->path, sizeof f->path, "/proc/self/fd/%d", f->fd);
}

/* The file's whole content becomes data[0, size). */
static inline void memfile_put(const memfile *f, const void *data, size_t size)
{
    if (ftruncate(f->fd, 0) || pwrite(f->fd, data, size, 0) != (ssize_t)size)
        abort();
}

#endif
