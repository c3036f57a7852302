/* internal.h: helpers shared by the library's own files; not installed. */
#ifndef LF_INTERNAL_H
#define LF_INTERNAL_H

#include "layerfit.h"

#if defined(__GNUC__)
#define LF_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define LF_PRINTF(a, b)
#endif

/* Fill err (if not NULL) with status and a formatted message; returns status
 * so that callers can write `return lf_fail(err, LF_EINVAL, "...")`. */
int lf_fail(lf_error *err, int status, const char *fmt, ...) LF_PRINTF(3, 4);

/* The same with a place: file (may be NULL), line and column (0 = none). */
int lf_fail_at(lf_error *err, int status, const char *file, long line,
               long column, const char *fmt, ...) LF_PRINTF(6, 7);

/* Append a formatted warning to w (silently dropped on allocation failure,
 * a warning is never worth failing for). */
void lf_warn(lf_warnings *w, const char *fmt, ...) LF_PRINTF(2, 3);

/* A strdup that does not depend on POSIX feature macros. */
char *lf_strdup(const char *s);

/* Largest finite magnitude a derivative is allowed to reach. */
#define LF_BIG 1e300

/* x clamped to [-LF_BIG, LF_BIG]: derivatives that diverge at detachment
 * stay finite (a NaN, which no model should make, becomes LF_BIG). */
static inline double
lf_capped(double x)
{
    if (!(x < LF_BIG))
        return LF_BIG;
    if (!(x > -LF_BIG))
        return -LF_BIG;
    return x;
}

#endif
