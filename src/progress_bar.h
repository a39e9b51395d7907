/* progress_bar.h: the bar on stderr during long renders, drawn for the Lua
** binding; no Lua header, and not in the core library (the core never prints). */
#ifndef PROGRESS_BAR_H
#define PROGRESS_BAR_H

typedef struct {
    double start;      /* monotonic seconds when the render began */
    double last;       /* when the bar was last drawn */
    int    shown;      /* the bar is on screen */
    int    enabled;
    double delay;      /* seconds before the first draw */
} progress_bar;

/* enabled: 1 always, 0 never, -1 when stderr is a terminal (and TERM is not dumb). */
void progress_bar_begin(progress_bar *p, int enabled);
int  progress_bar_update(void *p, double done);   /* an lc_progress_fn */
void progress_bar_end(progress_bar *p);

#endif
