/* pair.h: one job run on two halves of its work at once, for the steps of
** a large build that two cores share. */
#ifndef LC_PAIR_H
#define LC_PAIR_H

/* Runs job(here) on this thread and job(there) on a thread of its own when
** `threaded`; without one (not asked, or none starts), job(there) runs
** here after job(here). Returns once both are done. */
void pair_run(void *(*job)(void *), void *here, void *there, int threaded);

#endif
