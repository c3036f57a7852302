/* exact_cache.c: the exact model's tables kept on disk between runs.
 *
 * Folder: $XDG_CACHE_HOME/layerfit, else $HOME/.cache/layerfit (an
 * XDG_CACHE_HOME that is not an absolute path is ignored, as the XDG spec
 * asks).  One file per table, named from its key, e.g.
 * exact-k2.5-frictionless.lft or exact-k3-bonded-nu0.0084....lft.
 *
 * A file is a fixed header and the table's nodes (ln f and its slope in ln
 * tau at every node, f and f' at TAU_MIN), in the machine's own byte order.
 * The header names the format and the algorithm version, a byte-order mark,
 * the key (k, base, nu, bit for bit), the grid (step, node factor, tau
 * range, node count, l0, h) and the payload's length; a checksum (FNV-1a
 * 64) covers the header and the payload.  A file is used only when all of
 * these match what a build would make now and every number is finite;
 * anything else (stale, truncated, corrupt) is ignored and the table built
 * and written again.  Writes go to a temporary file in the same folder and
 * are renamed over the name, so a reader sees a whole file or none, and two
 * processes building the same table at once both write whole files (the
 * last rename wins; both are the same table).
 *
 * LF_EXACT_ALGO names the numerics of a table (kernel, Nystrom solver, node
 * count rule): change it with any change there so old files go stale.
 *
 * The library never prints: failures are counted (lf_cache_stats_get).
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "exact.h"

#define LF_EXACT_FORMAT 1u
#define LF_EXACT_ALGO 1u
#define MARK 0x0102030405060708ull
#define SUFFIX ".lft"
#define MAX_NODES 100000u

static const char magic[8] = { 'L', 'F', 'E', 'X', 'A', 'C', 'T', '\n' };

typedef struct {
    char magic[8];
    uint32_t format, algo;
    uint64_t mark;
    double k, nu;
    int32_t base;
    uint32_t zero;
    uint64_t n;
    double l0, h, step, node_factor, tau_min, tau_max;
    uint64_t ndouble;       /* payload: F[4n], G[4n], flo[4], dflo[4] */
    uint64_t checksum;      /* of the header with this field 0, then the payload */
} file_header;

/* ---------------------------------------------------------------- switches */

static atomic_int enabled = -1;   /* -1: not decided (environment) */
static atomic_ulong st_hits, st_misses, st_rejected, st_written, st_write_failed;

void
lf_cache_set_enabled(int on)
{
    atomic_store(&enabled, on ? 1 : 0);
}

static int
cache_enabled(void)
{
    int e = atomic_load(&enabled);

    if (e < 0) {
        const char *v = getenv("LAYERFIT_NO_CACHE");
        e = !(v != NULL && v[0] != '\0' && strcmp(v, "0") != 0);
        atomic_store(&enabled, e);
    }
    return e;
}

void
lf_cache_stats_get(lf_cache_stats *s)
{
    s->hits = atomic_load(&st_hits);
    s->misses = atomic_load(&st_misses);
    s->rejected = atomic_load(&st_rejected);
    s->written = atomic_load(&st_written);
    s->write_failed = atomic_load(&st_write_failed);
}

int
lf_cache_dir(char *buf, size_t n, lf_error *err)
{
    const char *x = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    int len;

    if (x != NULL && x[0] == '/')
        len = snprintf(buf, n, "%s/layerfit", x);
    else if (home != NULL && home[0] == '/')
        len = snprintf(buf, n, "%s/.cache/layerfit", home);
    else
        return lf_fail(err, LF_EINVAL, "no cache folder: neither XDG_CACHE_HOME nor HOME "
                       "is an absolute path");
    if (len < 0 || (size_t) len >= n)
        return lf_fail(err, LF_EINVAL, "cache folder name too long");
    return LF_OK;
}

unsigned long long
lf_exact_disk_checksum(const void *p, size_t n)
{
    const unsigned char *b = p;
    unsigned long long h = 1469598103934665603ull;
    size_t i;

    for (i = 0; i < n; i++) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}

static uint64_t
checksum2(const file_header *hd, const double *payload, size_t nd)
{
    file_header c = *hd;
    uint64_t h;
    const unsigned char *b;
    size_t i;

    c.checksum = 0;
    h = lf_exact_disk_checksum(&c, sizeof c);
    /* continue FNV-1a over the payload */
    b = (const unsigned char *) payload;
    for (i = 0; i < nd * sizeof *payload; i++) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* ---------------------------------------------------------------- names */

static int
file_name(char *buf, size_t n, double k, lf_base base, double nu)
{
    int len;

    if (base == LF_BASE_FRICTIONLESS)
        len = snprintf(buf, n, "exact-k%.17g-frictionless" SUFFIX, k);
    else
        len = snprintf(buf, n, "exact-k%.17g-bonded-nu%.17g" SUFFIX, k, nu);
    return len > 0 && (size_t) len < n;
}

static int
file_path(char *buf, size_t n, double k, lf_base base, double nu)
{
    char dir[4096], name[256];
    int len;

    if (lf_cache_dir(dir, sizeof dir, NULL) != LF_OK || !file_name(name, sizeof name, k, base, nu))
        return 0;
    len = snprintf(buf, n, "%s/%s", dir, name);
    return len > 0 && (size_t) len < n;
}

/* mkdir -p of the cache folder. */
static int
make_dir(const char *dir)
{
    char p[4096];
    size_t i, n = strlen(dir);

    if (n == 0 || n >= sizeof p)
        return 0;
    memcpy(p, dir, n + 1);
    for (i = 1; i <= n; i++) {
        if (p[i] == '/' || p[i] == '\0') {
            char c = p[i];
            p[i] = '\0';
            if (mkdir(p, 0755) != 0 && errno != EEXIST)
                return 0;
            p[i] = c;
        }
    }
    return 1;
}

/* ---------------------------------------------------------------- files */

/* The grid a build with these settings makes (exact_table.c). */
static void
grid(double step, size_t *n, double *l0, double *h)
{
    double lmin = log(LF_EXACT_TAU_MIN), lmax = log(LF_EXACT_TAU_MAX);

    *n = (size_t) ceil((lmax - lmin) / step) + 1;
    *l0 = lmin;
    *h = (lmax - lmin) / (double) (*n - 1);
}

/* Read a whole regular file (at most `limit` bytes); NULL when it cannot
 * be read.  Opened without blocking and checked on the descriptor: a FIFO
 * (or a device) put where a table should be is passed over, not waited on. */
static unsigned char *
read_all(const char *path, size_t limit, size_t *len)
{
    struct stat sb;
    unsigned char *buf;
    size_t got = 0;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);

    if (fd < 0)
        return NULL;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || sb.st_size < 0
        || (uintmax_t) sb.st_size > limit || (buf = malloc((size_t) sb.st_size + 1)) == NULL) {
        close(fd);
        return NULL;
    }
    while (got < (size_t) sb.st_size) {
        ssize_t r = read(fd, buf + got, (size_t) sb.st_size - got);
        if (r <= 0)
            break;
        got += (size_t) r;
    }
    close(fd);
    *len = got;
    return buf;
}

/* Check a file's bytes: NULL when it is a usable table (header in *hd,
 * payload at buf + sizeof *hd), else why not.  want_* describe what a
 * build would make now; want_k is NAN to accept any key (listing). */
static const char *
check(const unsigned char *buf, size_t len, file_header *hd, double want_k,
      lf_base want_base, double want_nu, double step, double node_factor)
{
    size_t n, nd, i;
    double l0, h;
    const double *pay;

    if (len < sizeof *hd)
        return "truncated header";
    memcpy(hd, buf, sizeof *hd);
    if (memcmp(hd->magic, magic, sizeof magic) != 0)
        return "not a layerfit table";
    if (hd->mark != MARK)
        return "stale: other byte order";
    if (hd->format != LF_EXACT_FORMAT || hd->algo != LF_EXACT_ALGO)
        return "stale: made by another version";
    if (!isnan(want_k) && (hd->k != want_k || hd->base != (int32_t) want_base
                           || hd->nu != want_nu))
        return "stale: another table";
    if (!(hd->base == LF_BASE_FRICTIONLESS || hd->base == LF_BASE_BONDED))
        return "corrupt: unknown interface";
    grid(step, &n, &l0, &h);
    if (hd->step != step || hd->node_factor != node_factor || hd->tau_min != LF_EXACT_TAU_MIN
        || hd->tau_max != LF_EXACT_TAU_MAX || hd->n != n || hd->l0 != l0 || hd->h != h)
        return "stale: another grid";
    nd = 2 * LF_EXACT_NFUN * n + 2 * LF_EXACT_NFUN;
    if (hd->ndouble != nd)
        return "corrupt: wrong sizes";
    if (len < sizeof *hd + nd * sizeof(double))
        return "truncated";
    if (len != sizeof *hd + nd * sizeof(double))
        return "corrupt: wrong length";
    pay = (const double *) (const void *) (buf + sizeof *hd);
    if (checksum2(hd, pay, nd) != hd->checksum)
        return "corrupt: bad checksum";
    for (i = 0; i < nd; i++) {
        double v;
        memcpy(&v, buf + sizeof *hd + i * sizeof v, sizeof v);
        if (!isfinite(v))
            return "corrupt: a value is not finite";
    }
    for (i = 0; i < LF_EXACT_NFUN; i++) {
        double v;
        memcpy(&v, buf + sizeof *hd + (2 * LF_EXACT_NFUN * n + i) * sizeof v, sizeof v);
        if (!(v > 0))
            return "corrupt: a value is not positive";
    }
    return NULL;
}

lf_exact_table *
lf_exact_disk_load(double k, lf_base base, double nu, double step, double node_factor)
{
    char path[4352];
    unsigned char *buf;
    size_t len, n4;
    file_header hd;
    lf_exact_table *t;
    const unsigned char *p;

    if (!cache_enabled())
        return NULL;
    if (base == LF_BASE_FRICTIONLESS)
        nu = 0.0;
    if (!file_path(path, sizeof path, k, base, nu)
        || (buf = read_all(path, sizeof hd + (4 * LF_EXACT_NFUN * MAX_NODES) * sizeof(double),
                           &len)) == NULL) {
        atomic_fetch_add(&st_misses, 1);
        return NULL;
    }
    if (check(buf, len, &hd, k, base, nu, step, node_factor) != NULL) {
        atomic_fetch_add(&st_rejected, 1);
        free(buf);
        return NULL;
    }
    t = calloc(1, sizeof *t);
    n4 = LF_EXACT_NFUN * (size_t) hd.n;
    if (t == NULL || (t->F = malloc(n4 * sizeof *t->F)) == NULL
        || (t->G = malloc(n4 * sizeof *t->G)) == NULL) {
        lf_exact_table_free(t);
        free(buf);
        return NULL;
    }
    t->k = k;
    t->base = base;
    t->nu = nu;
    t->n = (size_t) hd.n;
    t->l0 = hd.l0;
    t->h = hd.h;
    p = buf + sizeof hd;
    memcpy(t->F, p, n4 * sizeof *t->F);
    p += n4 * sizeof *t->F;
    memcpy(t->G, p, n4 * sizeof *t->G);
    p += n4 * sizeof *t->G;
    memcpy(t->flo, p, sizeof t->flo);
    p += sizeof t->flo;
    memcpy(t->dflo, p, sizeof t->dflo);
    free(buf);
    lf_exact_table_finish(t);
    atomic_fetch_add(&st_hits, 1);
    return t;
}

static int
write_all(int fd, const void *p, size_t n)
{
    const unsigned char *b = p;

    while (n > 0) {
        ssize_t w = write(fd, b, n);
        if (w <= 0)
            return 0;
        b += w;
        n -= (size_t) w;
    }
    return 1;
}

void
lf_exact_disk_save(const lf_exact_table *t, double step, double node_factor)
{
    char dir[4096], name[256], path[4352], tmp[4400];
    file_header hd;
    double *pay;
    size_t nd, n4;
    int fd, ok;

    if (!cache_enabled())
        return;
    n4 = LF_EXACT_NFUN * t->n;
    nd = 2 * n4 + 2 * LF_EXACT_NFUN;
    if (lf_cache_dir(dir, sizeof dir, NULL) != LF_OK
        || !file_name(name, sizeof name, t->k, t->base, t->nu)
        || snprintf(path, sizeof path, "%s/%s", dir, name) >= (int) sizeof path
        || snprintf(tmp, sizeof tmp, "%s/.%s.XXXXXX", dir, name) >= (int) sizeof tmp
        || !make_dir(dir) || (pay = malloc(nd * sizeof *pay)) == NULL) {
        atomic_fetch_add(&st_write_failed, 1);
        return;
    }
    memcpy(pay, t->F, n4 * sizeof *pay);
    memcpy(pay + n4, t->G, n4 * sizeof *pay);
    memcpy(pay + 2 * n4, t->flo, sizeof t->flo);
    memcpy(pay + 2 * n4 + LF_EXACT_NFUN, t->dflo, sizeof t->dflo);
    memset(&hd, 0, sizeof hd);
    memcpy(hd.magic, magic, sizeof magic);
    hd.format = LF_EXACT_FORMAT;
    hd.algo = LF_EXACT_ALGO;
    hd.mark = MARK;
    hd.k = t->k;
    hd.nu = t->nu;
    hd.base = (int32_t) t->base;
    hd.n = t->n;
    hd.l0 = t->l0;
    hd.h = t->h;
    hd.step = step;
    hd.node_factor = node_factor;
    hd.tau_min = LF_EXACT_TAU_MIN;
    hd.tau_max = LF_EXACT_TAU_MAX;
    hd.ndouble = nd;
    hd.checksum = checksum2(&hd, pay, nd);
    fd = mkstemp(tmp);
    ok = fd >= 0;
    if (ok) {
        ok = write_all(fd, &hd, sizeof hd) && write_all(fd, pay, nd * sizeof *pay);
        ok = close(fd) == 0 && ok;
        ok = ok && fchmodat(AT_FDCWD, tmp, 0644, 0) == 0 && rename(tmp, path) == 0;
        if (!ok)
            unlink(tmp);
    }
    free(pay);
    atomic_fetch_add(ok ? &st_written : &st_write_failed, 1);
}

/* ---------------------------------------------------------------- folder */

static int
is_table_name(const char *name)
{
    size_t n = strlen(name), s = strlen(SUFFIX);
    return name[0] != '.' && n > s && strcmp(name + n - s, SUFFIX) == 0;
}

/* A temporary file of ours left by a writer that died. */
static int
is_temp_name(const char *name)
{
    return name[0] == '.' && strstr(name, SUFFIX ".") != NULL;
}

/* The cache folder's name in dir and its listing in *d (NULL when the
 * folder does not exist yet). */
static int
open_folder(char *dir, size_t n, DIR **d, lf_error *err)
{
    int status;

    *d = NULL;
    if ((status = lf_cache_dir(dir, n, err)) != LF_OK)
        return status;
    if ((*d = opendir(dir)) == NULL && errno != ENOENT)
        return lf_fail(err, LF_EIO, "cannot read %s: %s", dir, strerror(errno));
    return LF_OK;
}

int
lf_cache_list(lf_cache_entry **out, size_t *count, lf_error *err)
{
    char dir[4096];
    DIR *d;
    struct dirent *de;
    lf_cache_entry *v = NULL;
    size_t n = 0, cap = 0;
    int status;

    *out = NULL;
    *count = 0;
    if ((status = open_folder(dir, sizeof dir, &d, err)) != LF_OK || d == NULL)
        return status;
    while ((de = readdir(d)) != NULL) {
        char path[4352];
        unsigned char *buf;
        size_t len;
        struct stat sb;
        file_header hd;
        lf_cache_entry *e;
        const char *why;

        if (!is_table_name(de->d_name))
            continue;
        if (snprintf(path, sizeof path, "%s/%s", dir, de->d_name) >= (int) sizeof path
            || stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
            continue;
        if (n == cap) {
            lf_cache_entry *nv = realloc(v, (cap = cap ? 2 * cap : 16) * sizeof *v);
            if (nv == NULL) {
                closedir(d);
                free(v);
                return lf_fail(err, LF_ENOMEM, "out of memory listing the cache");
            }
            v = nv;
        }
        e = &v[n++];
        memset(e, 0, sizeof *e);
        snprintf(e->name, sizeof e->name, "%s", de->d_name);
        e->bytes = (long long) sb.st_size;
        buf = read_all(path, sizeof hd + (4 * LF_EXACT_NFUN * MAX_NODES) * sizeof(double), &len);
        why = buf == NULL ? "unreadable"
                          : check(buf, len, &hd, NAN, LF_BASE_FRICTIONLESS, 0.0, LF_EXACT_STEP, 1.0);
        free(buf);
        e->valid = why == NULL;
        if (why != NULL)
            snprintf(e->what, sizeof e->what, "%s (rebuilt when next needed)", why);
        else if (hd.base == LF_BASE_FRICTIONLESS)
            snprintf(e->what, sizeof e->what, "exact model, k = %g, frictionless base, %zu nodes "
                     "in a/b %g-%g", hd.k, (size_t) hd.n, LF_EXACT_TAU_MIN, LF_EXACT_TAU_MAX);
        else
            snprintf(e->what, sizeof e->what, "exact model, k = %g, bonded base, nu = %.6g, "
                     "%zu nodes in a/b %g-%g", hd.k, hd.nu, (size_t) hd.n, LF_EXACT_TAU_MIN,
                     LF_EXACT_TAU_MAX);
    }
    closedir(d);
    *out = v;
    *count = n;
    return LF_OK;
}

int
lf_cache_clear(size_t *removed, lf_error *err)
{
    char dir[4096];
    DIR *d;
    struct dirent *de;
    int status;

    *removed = 0;
    if ((status = open_folder(dir, sizeof dir, &d, err)) != LF_OK || d == NULL)
        return status;
    while ((de = readdir(d)) != NULL) {
        char path[4352];
        if (!is_table_name(de->d_name) && !is_temp_name(de->d_name))
            continue;
        if (snprintf(path, sizeof path, "%s/%s", dir, de->d_name) >= (int) sizeof path)
            continue;
        if (unlink(path) == 0)
            *removed += is_table_name(de->d_name);
        else if (errno != ENOENT)
            status = lf_fail(err, LF_EIO, "cannot remove %s: %s", path, strerror(errno));
    }
    closedir(d);
    return status;
}
