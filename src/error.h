/* error.h: filling an lc_error with a status, the field at fault and a sentence. */
#ifndef LC_ERROR_H
#define LC_ERROR_H

#include "lancer.h"

#if defined(__GNUC__)
#define LC_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define LC_PRINTF(a, b)
#endif

/* Returns code; err may be NULL. field may be NULL when no input field is at fault. */
lc_status lc_fail(lc_error *err, lc_status code, const char *field, const char *fmt, ...)
    LC_PRINTF(4, 5);
void lc_ok(lc_error *err);

#endif
