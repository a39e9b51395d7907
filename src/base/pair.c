/* pair.c: one job on two halves at once (pair.h). */
#include <pthread.h>
#include "pair.h"

void pair_run(void *(*job)(void *), void *here, void *there, int threaded)
{
    pthread_t th;
    threaded = threaded && pthread_create(&th, NULL, job, there) == 0;
    job(here);
    if (threaded)
        pthread_join(th, NULL);
    else
        job(there);
}
