/* test_fuzz_regress.c: replay every input kept in tests/fuzz/regress (and
 * the fuzz seeds) through the curve, plan and design-plan readers with the checks of the
 * fuzz targets (tests/fuzz/fuzz_check.h) at chunk sizes 1 to 13, so that an
 * input that once broke a reader keeps being tried by `make check`. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "layerfit.h"
#include "testlib.h"
#include "testdata.h"
#include "fuzz/fuzz_check.h"

/* Replay every file of tests/fuzz/SUB; returns how many there were. */
static int
replay(const char *sub)
{
    char dir[1200], path[2400];
    struct dirent *e;
    DIR *d;
    int n = 0;

    snprintf(dir, sizeof dir, "%s/../fuzz/%s", data, sub);
    d = opendir(dir);
    if (!t_true(d != NULL, "%s: folder readable", dir))
        return 0;
    while ((e = readdir(d)) != NULL) {
        size_t len = 0, chunk;
        int bad_curve = 0, bad_plan = 0;
        char *buf;
        if (e->d_name[0] == '.' || strstr(e->d_name, ".md") != NULL)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        buf = slurp(path, &len);
        if (!t_true(buf != NULL, "%s readable", path))
            continue;
        for (chunk = 1; chunk <= 13; chunk++) {
            bad_curve |= fuzz_curve(buf, len, chunk, (int) chunk & 1);
            bad_plan |= fuzz_plan(buf, len, chunk, data);
        }
        t_int(bad_curve, 0, "%s/%s: curve reader consistent", sub, e->d_name);
        t_int(bad_plan, 0, "%s/%s: plan reader consistent", sub, e->d_name);
        t_int(fuzz_design(buf, len), 0, "%s/%s: design-plan reader consistent", sub, e->d_name);
        free(buf);
        n++;
    }
    closedir(d);
    return n;
}

/* Replay the seeds of each instrument reader's fuzz target, and every
 * regression input, through that reader forced. */
static void
replay_readers(void)
{
    static const char *const readers[] = { "chiaro", "jpk", "workshop", "ntmdt", "hysitron",
                                           "text", NULL };
    char dir[1200], path[2400];
    size_t r;
    for (r = 0; readers[r] != NULL; r++) {
        const char *subs[2];
        size_t s;
        int n = 0;
        subs[0] = readers[r];
        subs[1] = "regress";
        for (s = 0; s < 2; s++) {
            struct dirent *e;
            DIR *d;
            snprintf(dir, sizeof dir, "%s/../fuzz/%s", data, subs[s]);
            if ((d = opendir(dir)) == NULL)
                continue;
            while ((e = readdir(d)) != NULL) {
                size_t len = 0, chunk;
                int bad = 0;
                char *buf;
                if (e->d_name[0] == '.' || strstr(e->d_name, ".md") != NULL)
                    continue;
                snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
                if ((buf = slurp(path, &len)) == NULL)
                    continue;
                for (chunk = 1; chunk <= 13; chunk++)
                    bad |= fuzz_reader(readers[r], buf, len, chunk, (int) chunk & 1);
                t_int(bad, 0, "%s/%s: %s reader consistent", subs[s], e->d_name, readers[r]);
                free(buf);
                n += s == 0;
            }
            closedir(d);
        }
        t_true(n > 0, "%s seeds present", readers[r]);
    }
}

int
main(int argc, char **argv)
{
    (void) argc;
    find_data(argv[0]);
    t_true(replay("regress") > 0, "regression inputs present");
    t_true(replay("curve") > 0, "curve seeds present");
    t_true(replay("plan") > 0, "plan seeds present");
    t_true(replay("design") > 0, "design-plan seeds present");
    replay_readers();
    return t_summary();
}
