/* testdata.h: finding and reading the files under tests/data, for the
 * reader tests (static inline: each test includes what it uses). */
#ifndef LF_TESTDATA_H
#define LF_TESTDATA_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "layerfit.h"

static char data[1024];   /* tests/data, found from argv[0] (BUILD/tests/NAME) */

static inline void
find_data(const char *argv0)
{
    const char *slash = strrchr(argv0, '/');
    int n = slash ? (int) (slash - argv0) : 1;
    snprintf(data, sizeof data, "%.*s/../../tests/data", n, slash ? argv0 : ".");
}

/* The whole file in a new buffer (caller frees), or NULL. */
static inline char *
slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long n;
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0
        || fseek(f, 0, SEEK_SET) != 0 || (buf = malloc((size_t) n + 1)) == NULL
        || fread(buf, 1, (size_t) n, f) != (size_t) n) {
        if (f)
            fclose(f);
        free(buf);
        return NULL;
    }
    fclose(f);
    *len = (size_t) n;
    return buf;
}

/* Read the file at path and call differs(ctx, buf, len, chunk) for every
 * chunk size from 0 (all at once) to the file's length; returns how many
 * sizes gave a different result (differs() != 0), or -1 when the file
 * cannot be read.  *len gets the file's length. */
static inline long
every_chunk(const char *path, size_t *len,
            int (*differs)(void *ctx, const char *buf, size_t len, size_t chunk),
            void *ctx)
{
    size_t chunk;
    long bad = 0;
    char *buf = slurp(path, len);
    if (buf == NULL)
        return -1;
    for (chunk = 0; chunk <= *len; chunk++)
        bad += differs(ctx, buf, *len, chunk) != 0;
    free(buf);
    return bad;
}

/* Two error reports say the same thing. */
static inline int
same_error(const lf_error *a, const lf_error *b)
{
    return a->status == b->status && a->line == b->line && a->column == b->column
        && strcmp(a->msg, b->msg) == 0 && strcmp(a->file, b->file) == 0;
}

/* Whether a line of what the reader found (c->info) holds text. */
static inline int
has_info(const lf_curve *c, const char *text)
{
    size_t i;
    for (i = 0; i < c->info.n; i++)
        if (strstr(c->info.msg[i], text) != NULL)
            return 1;
    return 0;
}

/* The curve's metadata value of key, or NULL. */
static inline const char *
meta(const lf_curve *c, const char *key)
{
    size_t i;
    for (i = 0; i < c->nmeta; i++)
        if (strcmp(c->meta[i].key, key) == 0)
            return c->meta[i].value;
    return NULL;
}

/* Fit the unloading segment with the half-space JKR model (k = 2, R);
 * with profile, then the profile check a single fit makes (it goes on
 * from a lower minimum where it finds one), as `layerfit fit` does. */
static inline int
fit_halfspace_as(const lf_curve *c, double R, int profile, lf_fit_result *res)
{
    lf_fit_settings s = lf_fit_settings_default();
    lf_fit_curve fc;
    lf_error err;
    size_t n = lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL);
    double *d = malloc((n ? n : 1) * sizeof *d), *f = malloc((n ? n : 1) * sizeof *f);
    int st;

    memset(&fc, 0, sizeof fc);
    lf_curve_segment(c, LF_SEG_UNLOAD, d, f);
    s.model = &lf_model_halfspace;
    fc.name = c->file;
    fc.n = n;
    fc.depth = d;
    fc.force = f;
    fc.probe.k = 2;
    fc.probe.R = R;
    fc.probe.b = R;     /* not used by the half-space model */
    fc.probe.base = LF_BASE_FRICTIONLESS;
    fc.branch = LF_BRANCH_UNLOAD;
    fc.z0 = fc.F0 = NAN;
    st = lf_fit_driver(&s, 1, &fc, res, &err);
    if (st == LF_OK && profile)
        lf_fit_profile(&s, 1, &fc, res, LF_PROFILE_CHECK, &err);
    free(d);
    free(f);
    return st;
}

static inline int
fit_halfspace(const lf_curve *c, double R, lf_fit_result *res)
{
    return fit_halfspace_as(c, R, 0, res);
}

#endif
