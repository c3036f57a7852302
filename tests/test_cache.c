/* test_cache.c: the exact model's tables kept on disk (src/exact_cache.c)
 * and in the model object (src/model_exact.c), and the `auto` choice that
 * asks for a table only when a bound cannot settle it (fit/choose.c).
 *
 *  1. A table read from the cache is bit for bit the freshly built one, and
 *     so are the model's forces from it.
 *  2. A damaged file (flipped byte, truncated, empty) and a well-formed but
 *     stale one (other format, grid, key or sizes, or a NaN, each with a
 *     valid checksum) are rejected, rebuilt with identical results and
 *     rewritten.
 *  3. Two processes building the same table at once leave one whole file.
 *  4. The model object resolves its tables once: a bonded model prepared
 *     for a nu range evaluates without reading or building anything more.
 *  5. Listing and clearing; the cache folder from XDG_CACHE_HOME or HOME.
 *  6. Beyond a/b = 100 the exact model's forces come without tables and
 *     equal the model's; `auto` judges a curve of a very thin layer there
 *     without building a table; a thick one still gets its tables.
 * Everything runs in a temporary XDG_CACHE_HOME, never the user's cache. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "exact.h"
#include "scene.h"
#include "testlib.h"

#define HDR 120            /* bytes of the file header (exact_cache.c) */
#define OFF_FORMAT 8
#define OFF_K 24
#define OFF_N 48
#define OFF_STEP 72
#define OFF_NDOUBLE 104
#define OFF_SUM 112

static char dir[512];      /* XDG_CACHE_HOME */
static char cdir[600];     /* its layerfit folder */

static const double taus[] = { 1e-4, 2e-3, 0.05, 0.7, 3.3, 17.0, 99.0, 400.0 };
#define NT (sizeof taus / sizeof taus[0])

/* Values of a table at taus[] (f and df side by side). */
static void
values(const lf_exact_table *t, double v[NT][8])
{
    size_t i;
    for (i = 0; i < NT; i++)
        lf_exact_table_eval(t, taus[i], v[i], v[i] + 4);
}

static lf_cache_stats
stats(void)
{
    lf_cache_stats s;
    lf_cache_stats_get(&s);
    return s;
}

static void
path_of(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", cdir, name);
}

static unsigned char *
slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    unsigned char *b;
    long n;

    *len = 0;
    if (f == NULL)
        return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    b = malloc((size_t) n + 1);
    *len = fread(b, 1, (size_t) n, f);
    fclose(f);
    return b;
}

static void
spit(const char *path, const unsigned char *b, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (f == NULL)
        return;
    fwrite(b, 1, len, f);
    fclose(f);
}

/* Re-seal a file's checksum after an edit (FNV-1a over the header with the
 * checksum zeroed, then the payload). */
static void
reseal(unsigned char *b, size_t len)
{
    unsigned long long h;
    memset(b + OFF_SUM, 0, 8);
    h = lf_exact_disk_checksum(b, len);
    memcpy(b + OFF_SUM, &h, 8);
}

static const char *fname = "exact-k2.5-frictionless.lft";

/* ---- 1. a hit is the fresh build ----------------------------------------- */

/* Forget the tables in memory, get (k, base, nu) again: it must come from
 * its file (a hit) and equal ref bit for bit. */
static void
read_back(double k, lf_base base, double nu, double ref[NT][8], const char *what)
{
    const lf_exact_table *t;
    lf_cache_stats s0, s1;
    double v[NT][8];

    lf_exact_cache_clear();
    s0 = stats();
    t_int(lf_exact_table_get(k, base, nu, &t, NULL), LF_OK, "%s: read back", what);
    s1 = stats();
    t_int((long) (s1.hits - s0.hits), 1, "%s: a hit", what);
    t_int((long) (s1.written - s0.written), 0, "%s: nothing written on a hit", what);
    values(t, v);
    t_true(memcmp(v, ref, sizeof v) == 0, "%s: table from the file bit-identical to a fresh build",
           what);
}

static double fresh[NT][8];

static void
hit_is_fresh(void)
{
    const lf_exact_table *t;
    lf_cache_stats s0, s1;
    double v[NT][8];
    char p[700];
    struct stat sb;

    lf_cache_set_enabled(0);
    lf_exact_cache_clear();
    t_int(lf_exact_table_get(2.5, LF_BASE_FRICTIONLESS, 0.0, &t, NULL), LF_OK, "fresh build");
    values(t, fresh);
    path_of(p, sizeof p, fname);
    t_true(stat(p, &sb) != 0, "no file written with the cache off");

    lf_cache_set_enabled(1);
    lf_exact_cache_clear();
    s0 = stats();
    t_int(lf_exact_table_get(2.5, LF_BASE_FRICTIONLESS, 0.0, &t, NULL), LF_OK, "build, cache on");
    s1 = stats();
    t_int((long) (s1.misses - s0.misses), 1, "first use: a miss");
    t_int((long) (s1.written - s0.written), 1, "and a file written");
    t_true(stat(p, &sb) == 0 && sb.st_size > HDR, "file %s there", fname);
    values(t, v);
    t_true(memcmp(v, fresh, sizeof v) == 0, "built with the cache on = built without");
    read_back(2.5, LF_BASE_FRICTIONLESS, 0.0, fresh, "second start");
}

/* The exact model's forces from a fresh model, with the tables in memory
 * forgotten first and the cache on or off. */
static void
forces(const lf_probe *p, const lf_material *m, int cache_on, size_t n, const double *d,
       lf_eval *out)
{
    lf_model *mod;

    lf_exact_cache_clear();
    lf_cache_set_enabled(cache_on);
    mod = lf_model_alloc(&lf_model_exact, p, NULL);
    t_true(mod != NULL, "model, cache %s", cache_on ? "on" : "off");
    t_int(lf_model_eval(mod, m, LF_BRANCH_UNLOAD, n, d, out, NULL), LF_OK, "forces");
    lf_model_free(mod);
    lf_cache_set_enabled(1);
}

/* The model's forces, with and without the cache, are bit-identical. */
static void
model_hit_is_fresh(void)
{
    lf_probe p = { 2.5, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    lf_material m = { 10e-3, 1e9, 0.3 };
    double d[5] = { -2e-9, 0.0, 5e-9, 20e-9, 60e-9 };
    lf_eval a[5], b[5];

    forces(&p, &m, 0, 5, d, a);
    forces(&p, &m, 1, 5, d, b);
    t_true(memcmp(a, b, sizeof a) == 0, "forces from a cached table bit-identical");
}

/* ---- 2. damaged and stale files ------------------------------------------ */

typedef enum { FLIP, TRUNCATE, EMPTY, FORMAT, GRID, STEP, KEY, SIZES, NAN_VALUE } damage;
static const char *const damage_name[] = {
    "flipped byte", "truncated", "empty", "other format version", "other node count",
    "other step", "other key", "wrong sizes", "NaN value"
};

static void
damaged(damage how)
{
    char p[700];
    unsigned char *b;
    size_t len = 0;
    const lf_exact_table *t;
    lf_cache_stats s0, s1;
    double v[NT][8], x;
    unsigned long long u;
    const char *what = damage_name[how];

    path_of(p, sizeof p, fname);
    b = slurp(p, &len);
    if (!t_true(b != NULL && len > HDR + 64, "%s: file to damage", what))
        return;
    switch (how) {
    case FLIP: b[HDR + 200] ^= 0x10; break;
    case TRUNCATE: len = HDR + (len - HDR) / 2; break;
    case EMPTY: len = 0; break;
    case FORMAT: b[OFF_FORMAT] ^= 3; reseal(b, len); break;
    case GRID: memcpy(&u, b + OFF_N, 8); u += 1; memcpy(b + OFF_N, &u, 8); reseal(b, len); break;
    case STEP: memcpy(&x, b + OFF_STEP, 8); x *= 0.5; memcpy(b + OFF_STEP, &x, 8); reseal(b, len); break;
    case KEY: x = 2.0; memcpy(b + OFF_K, &x, 8); reseal(b, len); break;
    case SIZES: memcpy(&u, b + OFF_NDOUBLE, 8); u -= 4; memcpy(b + OFF_NDOUBLE, &u, 8);
                len -= 32; reseal(b, len); break;
    case NAN_VALUE: x = NAN; memcpy(b + HDR + 8 * 17, &x, 8); reseal(b, len); break;
    }
    spit(p, b, len);
    free(b);
    lf_exact_cache_clear();
    s0 = stats();
    t_int(lf_exact_table_get(2.5, LF_BASE_FRICTIONLESS, 0.0, &t, NULL), LF_OK, "%s: table", what);
    s1 = stats();
    t_int((long) (s1.rejected - s0.rejected), 1, "%s: file rejected", what);
    t_int((long) (s1.hits - s0.hits), 0, "%s: not used", what);
    t_int((long) (s1.written - s0.written), 1, "%s: rebuilt and rewritten", what);
    values(t, v);
    t_true(memcmp(v, fresh, sizeof v) == 0, "%s: rebuilt table identical to a fresh build", what);
    read_back(2.5, LF_BASE_FRICTIONLESS, 0.0, fresh, what);
}

/* ---- 3. two processes at once -------------------------------------------- */

static void
two_processes(void)
{
    const lf_exact_table *t;
    double ref[NT][8];
    pid_t pid[2];
    int i, st, ok = 1;
    size_t n, removed;
    lf_cache_entry *e;

    lf_cache_set_enabled(0);
    lf_exact_cache_clear();
    t_int(lf_exact_table_get(1.5, LF_BASE_BONDED, 0.3, &t, NULL), LF_OK, "reference (no cache)");
    values(t, ref);
    lf_cache_set_enabled(1);
    lf_cache_clear(&removed, NULL);
    for (i = 0; i < 2; i++) {
        pid[i] = fork();
        if (pid[i] == 0) {
            const lf_exact_table *tc;
            lf_exact_cache_clear();
            _exit(lf_exact_table_get(1.5, LF_BASE_BONDED, 0.3, &tc, NULL) == LF_OK ? 0 : 1);
        }
    }
    for (i = 0; i < 2; i++)
        ok &= pid[i] > 0 && waitpid(pid[i], &st, 0) == pid[i] && WIFEXITED(st) && WEXITSTATUS(st) == 0;
    t_true(ok, "two processes built the same table at once");
    t_int(lf_cache_list(&e, &n, NULL), LF_OK, "list");
    t_int((long) n, 1, "one file left (no temporary files: %zu entries)", n);
    t_true(n == 1 && e[0].valid, "and it is whole");
    free(e);
    read_back(1.5, LF_BASE_BONDED, 0.3, ref, "the racers' file");
}

/* ---- 4. the model object keeps its tables --------------------------------- */

static void
model_resolves(void)
{
    lf_probe p = { 2.0, 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 };
    lf_material m = { 10e-3, 1e9, 0.31 };
    double d[4] = { 1e-9, 10e-9, 30e-9, 50e-9 };
    lf_eval a[4], b[4];
    lf_cache_stats s0, s1;
    lf_model *mod;
    size_t n, removed;
    lf_cache_entry *e;
    double nu;

    lf_cache_clear(&removed, NULL);
    lf_exact_cache_clear();
    mod = lf_model_alloc(&lf_model_exact, &p, NULL);
    t_true(mod != NULL, "bonded exact model");
    s0 = stats();
    t_int(lf_model_prepare(mod, 0.30, 0.32, NULL), LF_OK, "prepared for nu 0.30-0.32");
    s1 = stats();
    t_true(s1.written - s0.written >= 4, "its node tables built and written (%lu)",
           s1.written - s0.written);
    t_int(lf_cache_list(&e, &n, NULL), LF_OK, "list");
    t_int((long) n, (long) (s1.written - s0.written), "one file per node table");
    free(e);
    /* the store forgets everything: the model must not need it any more */
    s0 = stats();
    for (nu = 0.30; nu <= 0.32; nu += 0.0025) {
        m.nu = nu;
        t_int(lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 4, d, a, NULL), LF_OK, "eval nu %g", nu);
    }
    s1 = stats();
    t_int((long) (s1.hits + s1.misses + s1.written - s0.hits - s0.misses - s0.written), 0,
          "evaluations in the prepared range read or build nothing");
    /* a fresh model from the files gives the same forces */
    lf_model_free(mod);
    m.nu = 0.31;
    forces(&p, &m, 0, 4, d, a);
    forces(&p, &m, 1, 4, d, b);
    t_true(memcmp(a, b, sizeof a) == 0, "bonded forces from cached tables bit-identical");
    mod = lf_model_alloc(&lf_model_exact, &p, NULL);
    t_int(lf_model_prepare(mod, 0.3, 0.2, NULL), LF_EINVAL, "empty nu range refused");
    lf_model_free(mod);
}

/* The flattened bonded mix gives the four tables' values and nu slopes. */
static void
premix_same(void)
{
    lf_exact_mix mx, flat;
    static lf_exact_premix pm;
    double tt[] = { 2e-3, 0.04, 0.9, 7.0, 63.0, 250.0 }, nus[] = { 0.0, 0.21, 0.4, 0.49 }, md = 0.0;
    size_t i, n;
    int j;

    for (n = 0; n < 4; n++) {
        if (!t_int(lf_exact_mix_init(&mx, 2.0, LF_BASE_BONDED, nus[n], NULL), LF_OK, "mix nu %g", nus[n]))
            continue;
        flat = mx;
        lf_exact_premix_init(&pm, &flat);
        t_true(flat.pm == &pm && mx.pm == NULL, "flattened (nu %g)", nus[n]);
        for (i = 0; i < sizeof tt / sizeof tt[0]; i++) {
            double f[4], df[4], dn[4], g[4], dg[4], gn[4];
            lf_exact_mix_eval(&mx, tt[i], f, df, dn);
            lf_exact_mix_eval(&flat, tt[i], g, dg, gn);
            for (j = 0; j < 4; j++) {
                /* dn = f sum_m dw_m ln f_m: its rounding is that of the
                 * terms, not of their (nearly cancelling) sum */
                double dscale = 0.0;
                int m;
                for (m = 0; m < mx.m; m++)
                    dscale += fabs(mx.dwl[m] * log(f[j])) + fabs(mx.dwl[m]);
                md = fmax(md, fabs(g[j] - f[j]) / f[j]);
                /* d ln f / d ln tau is O(1): df on the scale f / tau */
                md = fmax(md, fabs(dg[j] - df[j]) / (fabs(df[j]) + f[j] / tt[i]));
                md = fmax(md, fabs(gn[j] - dn[j]) / (f[j] * dscale));
            }
        }
    }
    t_true(md < 1e-11, "flattened mix = four tables (max rel diff %.2g)", md);
}

/* ---- 5. list, clear, folder ---------------------------------------------- */

static void
list_clear(void)
{
    lf_cache_entry *e;
    size_t n, i, removed;
    char p[700], b[4096];
    int found = 0;
    FILE *f;
    const char *home = getenv("HOME");
    char *saved_home = home ? strdup(home) : NULL;

    path_of(p, sizeof p, "notes.txt");
    f = fopen(p, "w");
    if (f)
        fclose(f);
    t_int(lf_cache_list(&e, &n, NULL), LF_OK, "list");
    for (i = 0; i < n; i++)
        found |= strstr(e[i].what, "k = 2, bonded base, nu = ") != NULL && e[i].valid && e[i].bytes > HDR;
    t_true(found, "list says what a table is");
    free(e);
    t_int(lf_cache_clear(&removed, NULL), LF_OK, "clear");
    t_true(removed >= 4, "removed the table files (%zu)", removed);
    t_int(lf_cache_list(&e, &n, NULL), LF_OK, "list after clear");
    t_int((long) n, 0, "no table files left");
    free(e);
    t_true(access(p, F_OK) == 0, "other files in the folder kept");
    unlink(p);

    t_int(lf_cache_dir(b, sizeof b, NULL), LF_OK, "dir");
    t_str(b, cdir, "folder from XDG_CACHE_HOME");
    setenv("XDG_CACHE_HOME", "relative/path", 1);
    setenv("HOME", "/home/someone", 1);
    t_int(lf_cache_dir(b, sizeof b, NULL), LF_OK, "dir with a relative XDG_CACHE_HOME");
    t_str(b, "/home/someone/.cache/layerfit", "relative XDG_CACHE_HOME ignored, HOME used");
    unsetenv("XDG_CACHE_HOME");
    unsetenv("HOME");
    t_int(lf_cache_dir(b, sizeof b, NULL), LF_EINVAL, "no folder without either");
    setenv("XDG_CACHE_HOME", dir, 1);
    if (saved_home)
        setenv("HOME", saved_home, 1);
    free(saved_home);
}

/* ---- 6. auto asks for a table only when needed ---------------------------- */

/* Beyond a/b = 100 the exact model's forces without tables equal the
 * model's own (frictionless and bonded, unloading and loading). */
static void
far_eval(void)
{
    lf_probe p[2] = { { 2.0, 1e-3, 5e-9, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, { 3.0, 1e-3, 10e-9, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 } };
    lf_material m = { 12e-3, 1.5e9, 0.33 };
    double d[6] = { 2e-9, 5e-9, 10e-9, 20e-9, 40e-9, -1e-9 }, P[6], maxd[2] = { 0, 0 };
    lf_eval ev[6];
    lf_branch br[2] = { LF_BRANCH_UNLOAD, LF_BRANCH_LOAD };
    lf_cache_stats s0, s1;
    size_t i, removed;
    int j, b;

    for (j = 0; j < 2; j++)
        for (b = 0; b < 2; b++) {
            lf_model *mod;
            lf_cache_clear(&removed, NULL);
            lf_exact_cache_clear();
            s0 = stats();
            t_int(lf_exact_far_eval(&p[j], &m, br[b], b ? 6 : 5, d, P, NULL), LF_OK,
                  "far eval k=%g branch %d", p[j].k, b);
            s1 = stats();
            t_int((long) (s1.written - s0.written + s1.hits - s0.hits), 0, "no table read or built");
            mod = lf_model_alloc(&lf_model_exact, &p[j], NULL);
            lf_model_eval(mod, &m, br[b], b ? 6 : 5, d, ev, NULL);
            lf_model_free(mod);
            for (i = 0; i < (size_t) (b ? 6 : 5); i++)
                maxd[j] = fmax(maxd[j], fabs(P[i] - ev[i].P) / fmax(fabs(ev[i].P), 1e-300));
            t_true(b == 0 || P[5] == 0.0, "no contact at delta < 0 when loading");
            /* now with the tables at hand */
            t_int(lf_exact_far_eval(&p[j], &m, br[b], b ? 6 : 5, d, P, NULL), LF_OK, "far eval, tables");
            for (i = 0; i < (size_t) (b ? 6 : 5); i++)
                maxd[j] = fmax(maxd[j], fabs(P[i] - ev[i].P) / fmax(fabs(ev[i].P), 1e-300));
        }
    /* frictionless: the same numbers; bonded: a solve at nu against the
     * tables' interpolation in nu (accurate to ~1e-7) */
    t_true(maxd[0] < 1e-10, "frictionless forces beyond a/b = 100 as the model's (max rel diff %.2g)",
           maxd[0]);
    t_true(maxd[1] < 1e-6, "bonded forces beyond a/b = 100 as the model's (max rel diff %.2g)",
           maxd[1]);
    p[0].b = 1e-6;
    t_int(lf_exact_far_eval(&p[0], &m, LF_BRANCH_UNLOAD, 5, d, P, NULL), LF_EDATA,
          "refused where a/b < 100");
}

static void
auto_needs(void)
{
    scene s = scene_default("thin 5 nm layer, a/b in the thousands");
    lf_choose_settings cs = lf_choose_settings_default();
    lf_fit_result r;
    lf_cache_stats s0, s1;
    lf_cache_entry *e;
    lf_error err;
    size_t removed, n;
    int status;

    lf_cache_clear(&removed, NULL);
    lf_exact_cache_clear();
    scene_add(&s, 2.0, 1e-3, 5e-9, LF_BASE_FRICTIONLESS);
    s.sim.delta_min = 5e-9;
    s.sim.delta_max = 30e-9;
    t_int(scene_simulate(&s, 11), LF_OK, "simulate");
    s0 = stats();
    status = lf_fit_choose_driver(&s.fit, &cs, s.n, s.curve, &r, &err);
    s1 = stats();
    t_true(status == LF_OK || status == LF_ENOCONV, "auto fit (%s)", status ? err.msg : "ok");
    if (status == LF_OK || status == LF_ENOCONV) {
        t_str(r.curves[0].model, "thin", "the very thin layer keeps the thin-layer model");
        t_true(isfinite(r.curves[0].thin_bias) && r.curves[0].thin_bias < cs.tol,
               "its thin-layer bias was assessed: %s", r.curves[0].model_reason);
        lf_fit_result_free(&r);
    }
    t_int((long) (s1.written + s1.hits - s0.written - s0.hits), 0, "no exact table read or built");
    t_int(lf_cache_list(&e, &n, NULL), LF_OK, "list");
    t_int((long) n, 0, "the cache stays empty");
    free(e);
    scene_free(&s);

    /* a thick layer still needs its table */
    s = scene_default("thick 5 um layer");
    scene_add(&s, 2.0, 1e-3, 5e-6, LF_BASE_FRICTIONLESS);
    s.sim.delta_max = 200e-9;
    s.sim_model = &lf_model_exact;
    t_int(scene_simulate(&s, 12), LF_OK, "simulate thick");
    lf_exact_cache_clear();     /* the fit reads the table from the file */
    s0 = stats();
    status = lf_fit_choose_driver(&s.fit, &cs, s.n, s.curve, &r, &err);
    s1 = stats();
    t_true(status == LF_OK || status == LF_ENOCONV, "auto fit thick (%s)", status ? err.msg : "ok");
    if (status == LF_OK || status == LF_ENOCONV) {
        t_true(strcmp(r.curves[0].model, "thin") != 0, "thick layer leaves thin (%s)",
               r.curves[0].model);
        lf_fit_result_free(&r);
    }
    t_true(s1.hits > s0.hits, "its exact table was read from the cache");
    scene_free(&s);
}

/* A fit with nu held resolves its models' tables when it is made
 * (lf_fit_alloc prepares them): the run itself reads and builds nothing,
 * even after the process store has forgotten every table. */
static void
fit_prepares(void)
{
    enum { N = 60 };
    lf_probe p = { 2.0, 1e-3, 3e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 };
    lf_material m = { 10e-3, 1e9, 0.33 };
    double d[N], F[N];
    lf_eval ev[N];
    lf_fit_settings set = lf_fit_settings_default();
    lf_fit_curve c;
    lf_fit_result r;
    lf_cache_stats s0, s1;
    lf_error err;
    lf_model *mod;
    lf_fit *f;
    size_t i, removed;
    int status;

    lf_cache_clear(&removed, NULL);
    lf_exact_cache_clear();
    mod = lf_model_alloc(&lf_model_exact, &p, NULL);
    t_true(mod != NULL, "fit_prepares: model");
    if (mod == NULL)
        return;
    for (i = 0; i < N; i++)
        d[i] = -4e-9 + 54e-9 * (double) i / (N - 1);
    t_int(lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, N, d, ev, NULL), LF_OK, "fit_prepares: data");
    lf_model_free(mod);
    for (i = 0; i < N; i++)
        F[i] = ev[i].P;
    memset(&c, 0, sizeof c);
    c.name = "bonded";
    c.n = N;
    c.depth = d;
    c.force = F;
    c.probe = p;
    c.branch = LF_BRANCH_UNLOAD;
    c.z0 = 0.0;
    c.F0 = 0.0;
    set.model = &lf_model_exact;
    set.nu.mode = LF_PARAM_FIXED;
    set.nu.value = m.nu;
    lf_exact_cache_clear();     /* no model alive: the tables are on disk only */
    s0 = stats();
    f = lf_fit_alloc(&set, 1, &c, &err);
    t_true(f != NULL, "fit_prepares: fit made (%s)", f ? "ok" : err.msg);
    if (f == NULL)
        return;
    s1 = stats();
    t_true(s1.hits > s0.hits, "making the fit read its tables (%lu)", s1.hits - s0.hits);
    s0 = s1;
    status = lf_fit_run(f, &r, &err);
    s1 = stats();
    t_true(status == LF_OK, "fit_prepares: converged (%s)", status ? err.msg : "ok");
    t_int((long) (s1.hits + s1.misses + s1.written - s0.hits - s0.misses - s0.written), 0,
          "a fit with nu held reads and builds no table while it runs");
    if (status == LF_OK || status == LF_ENOCONV) {
        t_rel(r.w.value, m.w, 1e-5, "fit_prepares: w recovered");
        lf_fit_result_free(&r);
    }
    lf_fit_free(f);
}

int
main(void)
{
    char tmpl[] = "/tmp/layerfit-cache-test-XXXXXX";
    static const damage all[] = { FLIP, TRUNCATE, EMPTY, FORMAT, GRID, STEP, KEY, SIZES, NAN_VALUE };
    size_t i, removed;

    gsl_set_error_handler_off();
    if (mkdtemp(tmpl) == NULL) {
        printf("cannot make a temporary folder\n0 passed, 1 failed\n");
        return 1;
    }
    snprintf(dir, sizeof dir, "%s", tmpl);
    snprintf(cdir, sizeof cdir, "%s/layerfit", dir);
    setenv("XDG_CACHE_HOME", dir, 1);
    hit_is_fresh();
    model_hit_is_fresh();
    for (i = 0; i < sizeof all / sizeof all[0]; i++)
        damaged(all[i]);
    two_processes();
    model_resolves();
    premix_same();
    list_clear();
    far_eval();
    auto_needs();
    fit_prepares();
    lf_exact_cache_clear();
    lf_cache_clear(&removed, NULL);
    rmdir(cdir);
    rmdir(dir);
    return t_summary();
}
