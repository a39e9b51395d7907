/* interrupt.c: lc_interrupt() counts, from a signal handler; work that began
** before polls the count against its snapshot. */
#include "interrupt.h"
#include "lancer.h"

static volatile sig_atomic_t interrupts;

void lc_interrupt(void)
{
    interrupts++;
}

sig_atomic_t interrupt_count(void)
{
    return interrupts;
}
