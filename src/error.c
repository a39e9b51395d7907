/* error.c: filling an lc_error. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "error.h"

lc_status error_fail(lc_error *err, lc_status code, const char *field, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        err->code = code;
        snprintf(err->field, sizeof err->field, "%s", field ? field : "");
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return code;
}

void error_ok(lc_error *err)
{
    if (err) {
        err->code = LC_OK;
        err->field[0] = err->msg[0] = '\0';
    }
}
