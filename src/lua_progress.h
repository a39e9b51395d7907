/* lua_progress.h: the progress bar the binding draws during long renders. */
#ifndef LUA_PROGRESS_H
#define LUA_PROGRESS_H

typedef struct {
    double start;      /* monotonic seconds when the render began */
    double last;       /* when the bar was last drawn */
    int    shown;      /* the bar is on screen */
    int    enabled;
    double delay;      /* seconds before the first draw */
} lua_progress;

/* enabled: 1 always, 0 never, -1 when stderr is a terminal (and TERM is not dumb). */
void lua_progress_begin(lua_progress *p, int enabled);
int  lua_progress_update(void *p, double done);   /* an lc_progress_fn */
void lua_progress_end(lua_progress *p);

#endif
