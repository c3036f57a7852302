/* error.c: status names, error reports and warning lists. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

const char *
lf_strerror(int status)
{
    switch (status) {
    case LF_OK:       return "success";
    case LF_EINVAL:   return "invalid argument";
    case LF_ENOMEM:   return "out of memory";
    case LF_EIO:      return "input/output error";
    case LF_EFORMAT:  return "malformed input";
    case LF_EUNIT:    return "bad unit";
    case LF_EDATA:    return "insufficient or degenerate data";
    case LF_ENOCONV:  return "did not converge";
    case LF_ENUMERIC: return "numerical failure";
    default:          return "unknown status";
    }
}

void
lf_error_clear(lf_error *err)
{
    if (err == NULL)
        return;
    err->status = LF_OK;
    err->file[0] = '\0';
    err->line = 0;
    err->column = 0;
    err->msg[0] = '\0';
}

LF_PRINTF(6, 0) static int
vfail(lf_error *err, int status, const char *file, long line, long column,
      const char *fmt, va_list ap)
{
    if (err == NULL)
        return status;
    err->status = status;
    snprintf(err->file, sizeof err->file, "%s", file ? file : "");
    err->line = line;
    err->column = column;
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    return status;
}

int
lf_fail(lf_error *err, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, status, NULL, 0, 0, fmt, ap);
    va_end(ap);
    return status;
}

int
lf_fail_at(lf_error *err, int status, const char *file, long line,
           long column, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, status, file, line, column, fmt, ap);
    va_end(ap);
    return status;
}

char *
lf_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d != NULL)
        memcpy(d, s, n);
    return d;
}

void
lf_warn(lf_warnings *w, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    char **grown;

    if (w == NULL)
        return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    grown = realloc(w->msg, (w->n + 1) * sizeof *grown);
    if (grown == NULL)
        return;
    w->msg = grown;
    w->msg[w->n] = lf_strdup(buf);
    if (w->msg[w->n] != NULL)
        w->n++;
}

void
lf_warnings_free(lf_warnings *w)
{
    size_t i;
    if (w == NULL)
        return;
    for (i = 0; i < w->n; i++)
        free(w->msg[i]);
    free(w->msg);
    w->msg = NULL;
    w->n = 0;
}
