/* bench_read.c: how fast a file of many curves is read (reported, not
 * asserted): open FILE (lf_file_open: the listing), then decode every
 * curve once (lf_file_curve), one at a time, and print the file's size,
 * the times, the rate in MB/s of the file's bytes, and the peak memory.
 *
 *   build/bench_read FILE [THREADS]
 *
 * tests/bench/maps.sh runs it beside `unzip -p FILE > /dev/null`. */
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "layerfit.h"

static double
now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

int
main(int argc, char **argv)
{
    lf_file *f = NULL;
    lf_error err;
    struct stat st;
    struct rusage ru;
    double t0, t1, t2, mb;
    size_t n, points = 0, failed = 0;
    const char *format;
    long i, threads = argc > 2 ? strtol(argv[2], NULL, 10) : 1;

    if (argc < 2 || stat(argv[1], &st) != 0) {
        fprintf(stderr, "usage: bench_read FILE [THREADS]\n");
        return 2;
    }
    t0 = now();
    if (lf_file_open(argv[1], 0, NULL, &f, NULL, &err) != LF_OK) {
        fprintf(stderr, "bench_read: %s: %s\n", err.file, err.msg);
        return 1;
    }
    t1 = now();
    n = lf_file_count(f);
    format = lf_file_format(f);     /* the reader's name: outlives f */
#pragma omp parallel for schedule(dynamic, 16) num_threads((int) threads) reduction(+ : points, failed)
    for (i = 0; i < (long) n; i++) {
        lf_curve *c = NULL;
        lf_error e;
        if (lf_file_curve(f, (size_t) i, &c, NULL, &e) == LF_OK)
            points += c->n;
        else
            failed++;
        lf_curve_free(c);
    }
    t2 = now();
    lf_file_close(f);
    getrusage(RUSAGE_SELF, &ru);
    mb = (double) st.st_size / 1e6;
    printf("%s: %.1f MB, %zu curves (%s), %zu points, %zu failed\n", argv[1], mb, n, format,
           points, failed);
    printf("  open (the listing, and the SHA-256 of the file): %.3f s\n", t1 - t0);
    printf("  every curve decoded, %ld thread(s):   %.3f s\n", threads, t2 - t1);
    printf("  in all: %.3f s, %.1f MB/s of the file; peak RSS %ld kB\n", t2 - t0,
           mb / (t2 - t0), ru.ru_maxrss);
    return failed > 0;
}
