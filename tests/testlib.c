/* testlib.c: see testlib.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <unistd.h>

#include "layerfit.h"
#include "testlib.h"

static long passed, failed;

/* A test never touches the user's cache of exact-model tables: unless
 * tests/run.sh gave the whole run one folder (LAYERFIT_TEST_CACHE set), a
 * test program makes its own XDG_CACHE_HOME before main and removes it at
 * exit. */
static char own_cache[64];

static void
drop_own_cache(void)
{
    char sub[96];
    size_t removed;
    lf_cache_clear(&removed, NULL);
    snprintf(sub, sizeof sub, "%s/layerfit", own_cache);
    rmdir(sub);
    rmdir(own_cache);
}

#if defined(__GNUC__)
__attribute__((constructor))
#endif
static void
own_cache_folder(void)
{
    if (getenv("LAYERFIT_TEST_CACHE") != NULL)
        return;
    snprintf(own_cache, sizeof own_cache, "/tmp/layerfit-test-XXXXXX");
    if (mkdtemp(own_cache) == NULL) {
        lf_cache_set_enabled(0);
        return;
    }
    setenv("XDG_CACHE_HOME", own_cache, 1);
    atexit(drop_own_cache);
}

static int
report(int ok, const char *detail, const char *fmt, va_list ap)
{
    static int verbose = -1;
    if (verbose < 0)
        verbose = getenv("TEST_VERBOSE") != NULL;
    if (ok)
        passed++;
    else
        failed++;
    if (!ok || verbose) {
        printf("%s: ", ok ? "PASS" : "FAIL");
        vprintf(fmt, ap);
        if (!ok && detail[0] != '\0')
            printf(" (%s)", detail);
        printf("\n");
    }
    return ok;
}

int
t_rel(double got, double want, double tol, const char *fmt, ...)
{
    char detail[256];
    int ok;
    va_list ap;

    if (isnan(want) || isinf(want))
        ok = isnan(want) ? isnan(got) : got == want;
    else if (!isfinite(got))
        ok = 0;
    else if (want == 0.0)
        ok = fabs(got) <= tol;
    else
        ok = fabs(got - want) <= tol * fabs(want);
    snprintf(detail, sizeof detail, "got %.17g, want %.17g, rel err %.3g, tol %.3g",
             got, want, want != 0 ? fabs(got - want) / fabs(want) : fabs(got), tol);
    va_start(ap, fmt);
    ok = report(ok, detail, fmt, ap);
    va_end(ap);
    return ok;
}

int
t_abs(double got, double want, double tol, const char *fmt, ...)
{
    char detail[256];
    int ok = isfinite(got) && fabs(got - want) <= tol;
    va_list ap;

    snprintf(detail, sizeof detail, "got %.17g, want %.17g, tol %.3g", got, want, tol);
    va_start(ap, fmt);
    ok = report(ok, detail, fmt, ap);
    va_end(ap);
    return ok;
}

int
t_true(int cond, const char *fmt, ...)
{
    va_list ap;
    int ok;
    va_start(ap, fmt);
    ok = report(cond != 0, "", fmt, ap);
    va_end(ap);
    return ok;
}

int
t_int(long got, long want, const char *fmt, ...)
{
    char detail[128];
    va_list ap;
    int ok;
    snprintf(detail, sizeof detail, "got %ld, want %ld", got, want);
    va_start(ap, fmt);
    ok = report(got == want, detail, fmt, ap);
    va_end(ap);
    return ok;
}

int
t_str(const char *got, const char *want, const char *fmt, ...)
{
    char detail[1200];
    va_list ap;
    int ok = got != NULL && strcmp(got, want) == 0;
    snprintf(detail, sizeof detail, "got \"%.500s\", want \"%.500s\"", got ? got : "(null)", want);
    va_start(ap, fmt);
    ok = report(ok, detail, fmt, ap);
    va_end(ap);
    return ok;
}

int
t_contains(const char *got, const char *want, const char *fmt, ...)
{
    char detail[1200];
    va_list ap;
    int ok = got != NULL && strstr(got, want) != NULL;
    snprintf(detail, sizeof detail, "\"%.500s\" lacks \"%.500s\"", got ? got : "(null)", want);
    va_start(ap, fmt);
    ok = report(ok, detail, fmt, ap);
    va_end(ap);
    return ok;
}

int
t_summary(void)
{
    printf("%ld passed, %ld failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}

int
t_says(const lf_warnings *w, const char *text)
{
    size_t i;
    for (i = 0; i < w->n; i++)
        if (strstr(w->msg[i], text) != NULL)
            return 1;
    return 0;
}
