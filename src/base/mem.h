/* mem.h: the core's allocations, counted, and refused past lc_memory_cap. */
#ifndef LC_MEM_H
#define LC_MEM_H

#include <stddef.h>

/* As malloc, calloc, realloc and free, for every block the core owns. A
** block past the cap is refused (NULL), as when the system has no memory. */
void *mem_alloc(size_t n);
void *mem_calloc(size_t n, size_t size);
void *mem_realloc(void *p, size_t n);
void  mem_free(void *p);
/* The most bytes the core held at once since mem_high_water_reset (or
** the start): what a build needed at its peak, for the benchmarks. */
size_t mem_high_water(void);
void   mem_high_water_reset(void);
/* The cap in force when this thread's last refusal happened, then clears
** it: 0 when the system refused, not the cap. error_fail reads it. */
size_t mem_refused_cap(void);

#endif
