/* mem.c: the core's allocations, counted so that a cap (lc_memory_cap) can
** refuse a scene, mesh or image that asks for more: the sandbox's memory
** cap, and a test's way to make any allocation fail. */
#include <stdint.h>
#include <stdlib.h>
#include "lancer.h"
#include "mem.h"

/* Each block starts with its size, padded to keep malloc's alignment. */
#define HEADER 16

static size_t used, cap;                 /* bytes; cap 0: none */
static size_t high;                      /* the most used since the last reset */
static __thread size_t refused;          /* the cap that refused this thread's last */

size_t lc_memory_cap(size_t bytes)
{
    return __atomic_exchange_n(&cap, bytes, __ATOMIC_SEQ_CST);
}

size_t lc_memory_used(void)
{
    return __atomic_load_n(&used, __ATOMIC_RELAXED);
}

size_t mem_high_water(void)
{
    return __atomic_load_n(&high, __ATOMIC_RELAXED);
}

void mem_high_water_reset(void)
{
    __atomic_store_n(&high, lc_memory_used(), __ATOMIC_RELAXED);
}

size_t mem_refused_cap(void)
{
    size_t c = refused;
    refused = 0;
    return c;
}

/* Takes n more bytes from the cap; 0 when that would pass it. */
static int take(size_t n)
{
    size_t limit = __atomic_load_n(&cap, __ATOMIC_RELAXED);
    size_t now = __atomic_add_fetch(&used, n, __ATOMIC_RELAXED);
    if (limit && now > limit) {
        __atomic_sub_fetch(&used, n, __ATOMIC_RELAXED);
        refused = limit;
        return 0;
    }
    size_t h = __atomic_load_n(&high, __ATOMIC_RELAXED);
    while (now > h && !__atomic_compare_exchange_n(&high, &h, now, 1, __ATOMIC_RELAXED,
                                                    __ATOMIC_RELAXED))
        ;
    return 1;
}

static void give(size_t n)
{
    __atomic_sub_fetch(&used, n, __ATOMIC_RELAXED);
}

void *mem_alloc(size_t n)
{
    if (n > SIZE_MAX - HEADER || !take(n))
        return NULL;
    unsigned char *p = malloc(n + HEADER);
    if (!p) {
        give(n);
        return NULL;
    }
    *(size_t *)(void *)p = n;
    return p + HEADER;
}

void *mem_calloc(size_t n, size_t size)
{
    if (size && n > (SIZE_MAX - HEADER) / size)
        return NULL;
    size_t bytes = n * size;
    if (!take(bytes))
        return NULL;
    unsigned char *p = calloc(1, bytes + HEADER);
    if (!p) {
        give(bytes);
        return NULL;
    }
    *(size_t *)(void *)p = bytes;
    return p + HEADER;
}

void *mem_realloc(void *q, size_t n)
{
    if (!q)
        return mem_alloc(n);
    unsigned char *p = (unsigned char *)q - HEADER;
    size_t old = *(size_t *)(void *)p;
    if (n > SIZE_MAX - HEADER || (n > old && !take(n - old)))
        return NULL;
    unsigned char *r = realloc(p, n + HEADER);
    if (!r) {
        if (n > old)
            give(n - old);
        return NULL;                     /* q is still valid, as with realloc */
    }
    if (n < old)
        give(old - n);
    *(size_t *)(void *)r = n;
    return r + HEADER;
}

void mem_free(void *q)
{
    if (!q)
        return;
    unsigned char *p = (unsigned char *)q - HEADER;
    give(*(size_t *)(void *)p);
    free(p);
}
