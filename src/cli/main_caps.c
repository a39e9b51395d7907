/* main_caps.c: a Lua state's memory cap and time cap: a counting allocator
** and a watchdog thread (--max-memory, --max-seconds, the sandbox). */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "lancer.h"
#include "main.h"

/* Lua instructions between two looks at the watchdog's flag, in a
** coroutine (the main thread has no hook until the deadline: any hook puts
** Lua 5.4's interpreter in its tracing mode, which measured 2.4 times
** slower on a tight loop). */
#define HOOK_COUNT 1000
/* The core's cap follows Lua's share to within this many bytes: resetting
** it on every Lua allocation would be an atomic exchange each time. */
#define CORE_SLACK (64 * 1024)
/* After the deadline the watchdog calls lc_interrupt() this often, so that
** a render begun just after the first call stops too. */
#define TICK_NS 50000000L
/* And after this many ticks (1 s) of C code that polls nothing (a Lua
** pattern match, a read from a pipe), it calls stuck(). */
#define STUCK_TICKS 20

struct caps_state {
    size_t max;             /* bytes, Lua's and the core's together; 0: none */
    size_t lua;             /* bytes Lua holds */
    size_t lua_at_cap;      /* what Lua held when the core's cap was last set */
    size_t old_core_cap;    /* lc_memory_cap before this state: restored at close */
    int refused;            /* Lua's allocator refused a block for the cap */
    double seconds;         /* the time cap; 0: none */
    struct timespec deadline;   /* CLOCK_MONOTONIC */
    void (*stuck)(void);
    int watching;           /* a watchdog thread runs */
    pthread_t lua_thread;   /* the thread that made the state, and runs it */
    struct sigaction old_alarm;
    pthread_t watchdog;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int closing;            /* under mu: the watchdog is to end */
    int expired;            /* atomic: the deadline has passed */
};

static void *caps_alloc(void *ud, void *ptr, size_t osize, size_t nsize);
static void caps_hook(lua_State *L, lua_Debug *ar);

static struct caps_state *caps_of(lua_State *L)
{
    void *ud;
    return lua_getallocf(L, &ud) == caps_alloc ? ud : NULL;
}

/* The core may take what Lua does not hold (lc_memory_cap(0) is no cap). */
static void set_core_cap(struct caps_state *c)
{
    lc_memory_cap(c->max > c->lua ? c->max - c->lua : 1);
    c->lua_at_cap = c->lua;
}

/* Lua's allocator (lua_Alloc): realloc and free, counted. A block that
** would take Lua's bytes plus the core's past the cap is refused; Lua then
** collects garbage, tries once more, and raises "not enough memory". Only
** growth is refused: Lua assumes shrinking never fails. */
static void *caps_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    struct caps_state *c = ud;
    size_t old = ptr ? osize : 0;          /* without ptr, osize is a type */
    void *p;
    if (nsize == 0) {
        free(ptr);
        c->lua -= old;
    } else {
        if (c->max && nsize > old) {
            size_t more = nsize - old, held = c->lua + lc_memory_used();
            if (more > c->max || held > c->max - more) {
                c->refused = 1;
                return NULL;
            }
        }
        if ((p = realloc(ptr, nsize)) == NULL)
            return NULL;
        c->lua = c->lua - old + nsize;
        ptr = p;
    }
    if (c->max && (c->lua > c->lua_at_cap + CORE_SLACK ||
                   c->lua + CORE_SLACK < c->lua_at_cap))
        set_core_cap(c);
    return nsize == 0 ? NULL : ptr;
}

/* ---- The time cap ---------------------------------------------------------- */

static void add_ns(struct timespec *t, long ns)
{
    t->tv_nsec += ns;
    while (t->tv_nsec >= 1000000000L) {
        t->tv_nsec -= 1000000000L;
        t->tv_sec++;
    }
}

/* The main thread of the capped state, for the SIGALRM handler; NULL once
** it closes. One capped state at a time (the core's memory cap is
** process-wide too). */
static lua_State *volatile watched;

/* On the state's own thread, at the deadline: the hook there from now on
** (lua_sethook may be called from a signal handler, as lua.c does). */
static void on_alarm(int sig)
{
    lua_State *L = watched;
    (void)sig;
    if (L)
        lua_sethook(L, caps_hook, LUA_MASKCOUNT, 1);
}

/* Sleeps until the deadline (or the close), then stops what runs: Lua
** code through SIGALRM on the state's thread and the flag the hook reads
** in coroutines, renders and BVH builds through lc_interrupt(), again
** every tick; C code that does neither meets stuck() after STUCK_TICKS. */
static void *watch(void *ud)
{
    struct caps_state *c = ud;
    struct timespec t = c->deadline;
    int ticks = 0;
    pthread_mutex_lock(&c->mu);
    while (!c->closing) {
        if (pthread_cond_timedwait(&c->cv, &c->mu, &t) != ETIMEDOUT)
            continue;                      /* the close, or a spurious wake */
        if (ticks == 0) {
            __atomic_store_n(&c->expired, 1, __ATOMIC_SEQ_CST);
            pthread_kill(c->lua_thread, SIGALRM);
        }
        lc_interrupt();
        if (++ticks == STUCK_TICKS && c->stuck)
            c->stuck();
        add_ns(&t, TICK_NS);
    }
    pthread_mutex_unlock(&c->mu);
    return NULL;
}

/* The hook: past the deadline, raises; and from then on at every
** instruction of this coroutine, so that a pcall in a loop cannot keep it
** going (each pcall swallows one error, the next instruction raises
** again). */
static void caps_hook(lua_State *L, lua_Debug *ar)
{
    struct caps_state *c = caps_of(L);
    (void)ar;
    if (c && __atomic_load_n(&c->expired, __ATOMIC_SEQ_CST))
        caps_time_error(L, 0, "");
}

/* Raised, from here on every instruction raises too (see caps_hook). */
int caps_time_error(lua_State *L, int level, const char *what)
{
    struct caps_state *c = caps_of(L);
    char s[32];
    if (c && c->seconds > 0)
        lua_sethook(L, caps_hook, LUA_MASKCOUNT, 1);
    snprintf(s, sizeof s, "%g", c ? c->seconds : 0.0);   /* 1, not Lua's 1.0 */
    luaL_where(L, level);
    lua_pushfstring(L, "time cap reached%s (lancer's time cap is %s s)", what, s);
    lua_concat(L, 2);
    return lua_error(L);
}

int caps_expired(lua_State *L)
{
    struct caps_state *c = caps_of(L);
    return c && __atomic_load_n(&c->expired, __ATOMIC_SEQ_CST);
}

void caps_rehook(lua_State *L)
{
    if (caps_expired(L))
        lua_sethook(L, caps_hook, LUA_MASKCOUNT, 1);
    else
        lua_sethook(L, NULL, 0, 0);
}

/* coroutine.create and coroutine.wrap, whose new coroutine gets the hook
** (a signal reaches only the main thread): upvalue 1 Lua's function,
** called in this frame; wrap's result holds the coroutine as upvalue 1. */
static int w_cocreate(lua_State *L)
{
    int n = lua_tocfunction(L, lua_upvalueindex(1))(L);
    lua_State *co = lua_tothread(L, -1);
    if (co == NULL && lua_getupvalue(L, -1, 1) != NULL) {
        co = lua_tothread(L, -1);
        lua_pop(L, 1);
    }
    if (co)
        lua_sethook(co, caps_hook, LUA_MASKCOUNT, HOOK_COUNT);
    return n;
}

void caps_coroutines(lua_State *L)
{
    static const char *const names[] = {"create", "wrap", NULL};
    struct caps_state *c = caps_of(L);
    int i;
    if (c == NULL || c->seconds <= 0)
        return;
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    if (lua_getfield(L, -1, LUA_COLIBNAME) == LUA_TTABLE)
        for (i = 0; names[i]; i++) {
            lua_getfield(L, -1, names[i]);
            if (lua_tocfunction(L, -1) == NULL) {
                lua_pop(L, 1);
                continue;
            }
            lua_pushcclosure(L, w_cocreate, 1);
            lua_setfield(L, -2, names[i]);
        }
    lua_pop(L, 2);
}

size_t caps_memory_refused(lua_State *L)
{
    struct caps_state *c = caps_of(L);
    return c && c->refused ? c->max : 0;
}

void caps_collect(lua_State *L)
{
    struct caps_state *c = caps_of(L);
    if (c && c->max && lc_memory_used() > c->max / 2)
        lua_gc(L, LUA_GCCOLLECT);
}

/* ---- The state ------------------------------------------------------------- */

static int start_watchdog(struct caps_state *c)
{
    pthread_condattr_t ca;
    if (clock_gettime(CLOCK_MONOTONIC, &c->deadline) != 0)
        return 0;
    double whole = (double)(time_t)c->seconds;
    c->deadline.tv_sec += (time_t)whole;
    add_ns(&c->deadline, (long)((c->seconds - whole) * 1e9));
    if (pthread_condattr_init(&ca) != 0)
        return 0;
    int ok = pthread_condattr_setclock(&ca, CLOCK_MONOTONIC) == 0 &&
             pthread_cond_init(&c->cv, &ca) == 0;
    pthread_condattr_destroy(&ca);
    if (!ok)
        return 0;
    if (pthread_mutex_init(&c->mu, NULL) != 0) {
        pthread_cond_destroy(&c->cv);
        return 0;
    }
    /* No SA_RESTART: a read the signal interrupts returns, and the script
    ** meets the hook. */
    struct sigaction sa;
    sa.sa_handler = on_alarm;
    sa.sa_flags = 0;
    sigemptyset(&sa.sa_mask);
    c->lua_thread = pthread_self();
    if (sigaction(SIGALRM, &sa, &c->old_alarm) != 0 ||
        pthread_create(&c->watchdog, NULL, watch, c) != 0) {
        sigaction(SIGALRM, &c->old_alarm, NULL);
        pthread_mutex_destroy(&c->mu);
        pthread_cond_destroy(&c->cv);
        return 0;
    }
    c->watching = 1;
    return 1;
}

lua_State *caps_newstate(const struct caps *o)
{
    struct caps_state *c = calloc(1, sizeof *c);
    lua_State *L;
    if (c == NULL)
        return NULL;
    if ((L = luaL_newstate()) == NULL) {
        free(c);
        return NULL;
    }
    /* What the state holds already, as Lua counts it (lauxlib's allocator
    ** made it; it and this one both use realloc and free). */
    c->lua = (size_t)lua_gc(L, LUA_GCCOUNT) * 1024 + (size_t)lua_gc(L, LUA_GCCOUNTB);
    c->max = o->max_memory;
    c->seconds = o->max_seconds > 0 ? o->max_seconds : 0;
    c->stuck = o->stuck;
    if (c->max) {
        c->old_core_cap = lc_memory_cap(0);
        set_core_cap(c);
    }
    if (c->seconds > 0) {
        watched = L;
        if (!start_watchdog(c)) {
            watched = NULL;
            if (c->max)
                lc_memory_cap(c->old_core_cap);
            lua_close(L);
            free(c);
            return NULL;
        }
    }
    lua_setallocf(L, caps_alloc, c);
    return L;
}

int caps_close(lua_State *L)
{
    struct caps_state *c = caps_of(L);
    int expired;
    if (c == NULL) {
        lua_close(L);
        return 0;
    }
    if (c->watching) {
        /* What lua_close runs still meets the time cap through a hook set
        ** now (the signal handler must not touch a state that lua_close
        ** frees), but for finalizers: Lua runs them without hooks, so a
        ** loop in one meets stuck(), as C code does (docs/manual.md). */
        lua_sethook(L, caps_hook, LUA_MASKCOUNT, caps_expired(L) ? 1 : HOOK_COUNT);
        watched = NULL;
    }
    lua_close(L);
    if (c->watching) {
        pthread_mutex_lock(&c->mu);
        c->closing = 1;
        pthread_cond_signal(&c->cv);
        pthread_mutex_unlock(&c->mu);
        pthread_join(c->watchdog, NULL);
        pthread_mutex_destroy(&c->mu);
        pthread_cond_destroy(&c->cv);
        sigaction(SIGALRM, &c->old_alarm, NULL);   /* no SIGALRM can come now */
    }
    if (c->max)
        lc_memory_cap(c->old_core_cap);
    expired = __atomic_load_n(&c->expired, __ATOMIC_SEQ_CST);
    free(c);
    return expired;
}
