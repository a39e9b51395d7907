/* error.c: filling an lc_error. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "error.h"
#include "mem.h"

/* Formats the sentence; when it is longer than the message buffer, its
** middle gives way, so the end (the reason: "No space left on device")
** always shows after however long a path. */
static void put(char *out, size_t size, const char *fmt, va_list ap)
{
    char full[4096];
    int n = vsnprintf(full, sizeof full, fmt, ap);
    if (n < 0)
        full[0] = '\0', n = 0;
    size_t len = strlen(full);
    if (len < size) {
        memcpy(out, full, len + 1);
        return;
    }
    size_t tail = (size - 4) / 2, head = size - 4 - tail;
    memcpy(out, full, head);
    memcpy(out + head, "...", 3);
    memcpy(out + head + 3, full + len - tail, tail + 1);
}

lc_status error_fail(lc_error *err, lc_status code, const char *field, const char *fmt, ...)
{
    size_t cap = code == LC_ENOMEM ? mem_refused_cap() : 0;
    if (err) {
        va_list ap;
        err->code = code;
        snprintf(err->field, sizeof err->field, "%s", field ? field : "");
        va_start(ap, fmt);
        put(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        size_t len = strlen(err->msg);
        if (cap && len < sizeof err->msg)      /* the cap refused it, not the system */
            snprintf(err->msg + len, sizeof err->msg - len, " (lancer's memory cap is "
                     "%.4g MB)", cap / 1e6);
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

static void put_list(char *out, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    put(out, size, fmt, ap);
    va_end(ap);
}

lc_status error_prefix(lc_error *err, const char *fmt, ...)
{
    if (!err)
        return LC_EARG;
    char head[256], old[sizeof err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(head, sizeof head, fmt, ap);
    va_end(ap);
    memcpy(old, err->msg, sizeof old);
    put_list(err->msg, sizeof err->msg, "%s%s", head, old);
    return err->code;
}
