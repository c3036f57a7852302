/* bench_call.c: the time of one fit made inside C as a binding makes it --
 * options set by name, lf_fit_job_path (read, fit, profile check),
 * lf_fit_job_free -- for tests/bench/python_overhead.py, which times the
 * same fit through layerfit.fit() from Python.
 *
 *   bench_call FILE ROUNDS NAME=VALUE...   (e.g. k=2 R=1mm b=1um)
 *
 * Prints each round's time in microseconds, one per line, after one fit
 * not timed (tables, caches). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"

static double
now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

static int
one(const char *path, int argc, char **argv)
{
    lf_fit_options *o = lf_fit_options_alloc();
    lf_fit_job *job = NULL;
    lf_error err;
    int i, status = LF_OK;

    for (i = 0; i < argc && status == LF_OK; i++) {
        char name[64], *eq = strchr(argv[i], '=');
        size_t n = eq ? (size_t) (eq - argv[i]) : strlen(argv[i]);
        snprintf(name, sizeof name, "%.*s", (int) n, argv[i]);
        status = lf_fit_options_set(o, name, eq ? eq + 1 : NULL, &err);
    }
    if (status == LF_OK)
        status = lf_fit_job_path(o, path, &job, NULL, &err);
    if (status != LF_OK)
        fprintf(stderr, "bench_call: %s: %s\n", path, err.msg);
    lf_fit_job_free(job);
    lf_fit_options_free(o);
    return status;
}

int
main(int argc, char **argv)
{
    long rounds, r;

    gsl_set_error_handler_off();
    if (argc < 3 || (rounds = strtol(argv[2], NULL, 10)) < 1) {
        fprintf(stderr, "usage: bench_call FILE ROUNDS NAME=VALUE...\n");
        return 2;
    }
    if (one(argv[1], argc - 3, argv + 3) != LF_OK)
        return 1;
    for (r = 0; r < rounds; r++) {
        double t0 = now();
        if (one(argv[1], argc - 3, argv + 3) != LF_OK)
            return 1;
        printf("%.3f\n", 1e6 * (now() - t0));
    }
    return 0;
}
