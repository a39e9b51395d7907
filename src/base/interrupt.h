/* interrupt.h: lc_interrupt()'s count, which long work polls: a render (its
** BVH build, its tiles) stops once the count differs from its snapshot. */
#ifndef LC_INTERRUPT_H
#define LC_INTERRUPT_H

#include <signal.h>

sig_atomic_t interrupt_count(void);

#endif
