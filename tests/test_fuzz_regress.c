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

/* Replay the seeds of each reader's fuzz target (tests/fuzz/DIR), and
 * every regression input, through that reader forced: a text reader whole
 * and in chunks of 1 to 13 bytes (fuzz_reader), a reader of binary files
 * of many curves opened from memory, every curve decoded (fuzz_file). */
static void
replay_readers(void)
{
    static const struct {
        const char *dir, *format;
        int binary;
    } readers[] = {
        { "chiaro", "chiaro", 0 }, { "jpk", "jpk", 0 }, { "workshop", "workshop", 0 },
        { "ntmdt", "ntmdt", 0 }, { "hysitron", "hysitron", 0 }, { "text", "text", 0 },
        { "tab", "tab", 0 }, { "jpk_force", "jpk-force", 1 },
        { "workshop_map", "workshop-map", 1 }, { "nanoscope", "nanoscope", 1 },
        { "igor", "igor", 1 },
    };
    char dir[1200], path[2400];
    size_t r;
    for (r = 0; r < sizeof readers / sizeof readers[0]; r++) {
        const char *subs[2];
        size_t s;
        int n = 0;
        subs[0] = readers[r].dir;
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
                if (readers[r].binary)
                    bad = fuzz_file(readers[r].format, buf, len);
                else
                    for (chunk = 1; chunk <= 13; chunk++)
                        bad |= fuzz_reader(readers[r].format, buf, len, chunk, (int) chunk & 1);
                t_int(bad, 0, "%s/%s: %s reader consistent", subs[s], e->d_name,
                      readers[r].format);
                free(buf);
                n += s == 0;
            }
            closedir(d);
        }
        t_true(n > 0, "%s seeds present", readers[r].format);
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
