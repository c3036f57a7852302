/* testlib.h: a minimal check library for layerfit's tests, one line per
 * check, in the manner of gsl_test_rel.  Every test program ends with
 * `return t_summary();`, which prints "N passed, N failed". */
#ifndef LF_TESTLIB_H
#define LF_TESTLIB_H

#include "layerfit.h"

#if defined(__GNUC__)
#define T_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define T_PRINTF(a, b)
#endif

/* |got - want| <= tol * |want| (absolute when want == 0); NaN and Inf must
 * match exactly.  Returns 1 when the check passed. */
int t_rel(double got, double want, double tol, const char *fmt, ...) T_PRINTF(4, 5);
/* |got - want| <= tol. */
int t_abs(double got, double want, double tol, const char *fmt, ...) T_PRINTF(4, 5);
int t_true(int cond, const char *fmt, ...) T_PRINTF(2, 3);
int t_int(long got, long want, const char *fmt, ...) T_PRINTF(3, 4);
int t_str(const char *got, const char *want, const char *fmt, ...) T_PRINTF(3, 4);
/* got contains want as a substring */
int t_contains(const char *got, const char *want, const char *fmt, ...) T_PRINTF(3, 4);

/* 1 when some message of the list w contains text. */
int t_says(const lf_warnings *w, const char *text);

/* Print the totals and return the exit status (0 when nothing failed). */
int t_summary(void);

#endif
