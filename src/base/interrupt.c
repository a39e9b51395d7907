/* interrupt.c: lc_interrupt() counts, from a signal handler; work that began
** before polls the count against its snapshot. */
#include "interrupt.h"
#include "lancer.h"

static sig_atomic_t interrupts;

/* Atomic: bumped from a signal handler or any thread, read by the workers. */
void lc_interrupt(void)
{
    __atomic_add_fetch(&interrupts, 1, __ATOMIC_RELAXED);
}

sig_atomic_t interrupt_count(void)
{
    return __atomic_load_n(&interrupts, __ATOMIC_RELAXED);
}
