/* error.h: filling an lc_error with a status, the field at fault and a sentence. */
#ifndef LC_ERROR_H
#define LC_ERROR_H

#include "lancer.h"

#if defined(__GNUC__)
#define PRINTF_LIKE(a, b) __attribute__((format(printf, a, b)))
#else
#define PRINTF_LIKE(a, b)
#endif

/* Returns code; err may be NULL. field may be NULL when no input field is at fault. */
lc_status error_fail(lc_error *err, lc_status code, const char *field, const char *fmt, ...)
    PRINTF_LIKE(4, 5);
void error_ok(lc_error *err);
/* Puts the formatted words before err's message ("node 3: ..."); returns
** its code (LC_EARG for a NULL err). */
lc_status error_prefix(lc_error *err, const char *fmt, ...) PRINTF_LIKE(2, 3);

#endif
