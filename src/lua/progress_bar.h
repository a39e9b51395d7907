/* progress_bar.h: the bar on stderr during long renders, or lines for render
** farms, drawn for the Lua binding; no Lua header, and not in the core
** library (the core never prints). */
#ifndef PROGRESS_BAR_H
#define PROGRESS_BAR_H

/* What progress_bar_begin shows: nothing, the bar, or lines "progress N/100"
** (for render farm managers that read a log): 0/100 at once, then one each
** time a batch of finished tiles (polled every 0.1 s) takes the share done
** past another whole percent, at most 101 a render. PROGRESS_AUTO is the
** bar when stderr is a terminal (and TERM is not dumb), after the first
** second, else nothing. */
enum { PROGRESS_NONE, PROGRESS_BAR, PROGRESS_LINES, PROGRESS_AUTO };

typedef struct {
    double start;      /* monotonic seconds when the render began */
    double last;       /* when the bar was last drawn */
    int    shown;      /* the bar is on screen */
    int    mode;       /* PROGRESS_NONE, _BAR or _LINES once begun */
    int    percent;    /* lines: the last percent written, -1 none */
    double delay;      /* seconds before the first draw */
} progress_bar;

void progress_bar_begin(progress_bar *p, int mode);
int  progress_bar_update(void *p, double done);   /* an lc_progress_fn */
/* After the render; finished: it rendered all (lines: "progress 100/100"). */
void progress_bar_end(progress_bar *p, int finished);

#endif
