/* progress_bar.c: a progress bar on stderr for renders longer than a second, or lines. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "progress_bar.h"
#include "base/clock.h"

#define DELAY   1.0    /* when automatic, short renders stay quiet */
#define REDRAW  0.1    /* at most ten redraws a second */
#define WIDTH   30

static void line(progress_bar *p, double done);

void progress_bar_begin(progress_bar *p, int mode)
{
    memset(p, 0, sizeof *p);
    p->delay = mode == PROGRESS_AUTO ? DELAY : 0;   /* asked for: shown from the start */
    if (mode == PROGRESS_AUTO) {
        const char *term = getenv("TERM");
        mode = isatty(STDERR_FILENO) && !(term && strcmp(term, "dumb") == 0)
             ? PROGRESS_BAR : PROGRESS_NONE;
    }
    p->mode = mode;
    p->percent = -1;
    p->start = p->last = clock_seconds();
    if (mode == PROGRESS_LINES)
        line(p, 0);                 /* a render has begun, however short */
}

/* "progress N/100" when N passed the last line's. */
static void line(progress_bar *p, double done)
{
    int n = done >= 1 ? 100 : done > 0 ? (int)(done * 100) : 0;
    if (n <= p->percent)
        return;
    p->percent = n;
    fprintf(stderr, "progress %d/100\n", n);
    fflush(stderr);
}

int progress_bar_update(void *ud, double done)
{
    progress_bar *p = ud;
    if (p->mode == PROGRESS_LINES) {
        line(p, done);
        return 0;
    }
    double t = clock_seconds(), elapsed = t - p->start;
    if (p->mode != PROGRESS_BAR || elapsed < p->delay ||
        (p->shown && t - p->last < REDRAW))
        return 0;
    p->last = t;
    int fill = (int)(done * WIDTH + 0.5);
    char bar[WIDTH + 1];
    for (int i = 0; i < WIDTH; i++)
        bar[i] = i < fill ? '#' : '.';
    bar[WIDTH] = '\0';
    if (done > 0.01)
        fprintf(stderr, "\r[%s] %3.0f%%  %.1f s, about %.1f s left\033[K", bar,
                100 * done, elapsed, elapsed * (1 - done) / done);
    else
        fprintf(stderr, "\r[%s] %3.0f%%  %.1f s\033[K", bar, 100 * done, elapsed);
    fflush(stderr);
    p->shown = 1;
    return 0;
}

void progress_bar_end(progress_bar *p, int finished)
{
    if (p->mode == PROGRESS_LINES && finished)
        line(p, 1);
    if (p->shown) {                 /* leave the line clean for what follows */
        fputs("\r\033[K", stderr);
        fflush(stderr);
    }
}
