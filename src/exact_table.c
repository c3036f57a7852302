/* exact_table.c: tables of the dimensionless functions s, e, d, p of
 * tau = a/h (see exact.h) for one (k, base, nu), and the process cache that
 * holds them.
 *
 * Grid.  Nodes uniform in l = ln tau on [LF_EXACT_TAU_MIN, LF_EXACT_TAU_MAX];
 * at each node one Nystrom solve (exact_kernel.c) gives the values and their
 * exact tau-derivatives, and ln f is interpolated by cubic Hermite in l
 * (error ~ h^4/384 max|d^4 ln f/dl^4|).
 * Outside the grid:
 *  - tau < TAU_MIN: f = f0 + (f(TAU_MIN) - f0) tau/TAU_MIN with the
 *    half-space values f0 = (1, 1, 1, k/(k+1)); the functions are analytic
 *    in tau, so the error is O(tau TAU_MIN) ~ 1e-6 at most;
 *  - tau > TAU_MAX: ln(f/f_thin) = alpha/tau + beta/tau^2 with alpha, beta
 *    matched to the value and slope at TAU_MAX, f_thin the thin-layer limit
 *    of exact.h (Z of section 1).  This follows the 1/tau approach to the
 *    thin-layer form; it is accurate when TAU_MAX is well past the
 *    compressibility length l/h of the incompressible thin-layer limit
 *    (Jaffar 1989, IJMS 31:229; Chadwick 2002) (every frictionless
 *    layer and bonded nu <= 0.45), and only approximate beyond.
 *
 * Store.  A process-wide list of immutable tables keyed by (k, base, nu):
 * looked up without a lock (the head and the links are published with
 * release stores and read with acquire loads); a missing table is read
 * from the disk cache (exact_cache.c) or built with no lock held, then
 * published under a short mutex that only links it in.  Two threads asking
 * for the same missing table may both build it; the second to publish frees
 * its copy and takes the first.  Tables are never modified or freed until
 * lf_exact_cache_clear().  A model object (model_exact.c) keeps the
 * pointers it needs, so its evaluations do not search the list at all.
 */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "exact.h"

#define NFUN LF_EXACT_NFUN
#define LN_TAU_MIN log(LF_EXACT_TAU_MIN)   /* folded by the compiler */
#define LN_TAU_MAX log(LF_EXACT_TAU_MAX)

static double
now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double) ts.tv_sec + 1e-9 * (double) ts.tv_nsec;
}

void
lf_exact_table_free(lf_exact_table *t)
{
    if (t == NULL)
        return;
    if (t->base == LF_BASE_BONDED) {
        /* a list (exact.h) */
        void *d = atomic_load(&t->derived);
        while (d != NULL) {
            void *next = *(void **) d;
            free(d);
            d = next;
        }
    } else {
        free(atomic_load(&t->derived));
    }
    free(t->F);
    free(t->G);
    free(t);
}

/* One share of a table's nodes: i = first, first + stride, ... */
typedef struct {
    const lf_exact_kernel *kr;
    lf_exact_table *t;
    double node_factor;
    size_t first, stride;
    int status;
    lf_error err;
} build_share;

static void *
build_nodes(void *arg)
{
    build_share *b = arg;
    lf_exact_table *t = b->t;
    size_t i;
    int j;

    b->status = LF_OK;
    for (i = b->first; i < t->n && b->status == LF_OK; i += b->stride) {
        double tau = exp(t->l0 + (double) i * t->h);
        size_t N = (size_t) ceil(b->node_factor * (double) lf_exact_nodes(tau));
        lf_exact_point pt;
        double f[NFUN], df[NFUN];

        b->status = lf_exact_solve(b->kr, t->k, tau, N, &pt, &b->err);
        if (b->status != LF_OK)
            break;
        f[0] = pt.s; f[1] = pt.e; f[2] = pt.d; f[3] = pt.p;
        df[0] = pt.ds; df[1] = pt.de; df[2] = pt.dd; df[3] = pt.dp;
        for (j = 0; j < NFUN; j++) {
            t->F[NFUN * i + (size_t) j] = log(f[j]);
            t->G[NFUN * i + (size_t) j] = tau * df[j] / f[j];
            if (i == 0) {
                t->flo[j] = f[j];
                t->dflo[j] = df[j];
            }
        }
    }
    return NULL;
}

#define BUILD_THREADS 8

int
lf_exact_table_build(const lf_exact_kernel *kr, double k, lf_base base, double nu,
                     double step, double node_factor, lf_exact_table **out,
                     lf_error *err)
{
    lf_exact_table *t;
    double lmin = log(LF_EXACT_TAU_MIN), lmax = log(LF_EXACT_TAU_MAX);
    build_share sh[BUILD_THREADS];
    pthread_t th[BUILD_THREADS];
    int started[BUILD_THREADS] = { 0 };
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    size_t m, nt = ncpu > 1 ? (size_t) (ncpu < BUILD_THREADS ? ncpu : BUILD_THREADS) : 1;

    *out = NULL;
    if (!(step > 0.0) || !(node_factor > 0.0))
        return lf_fail(err, LF_EINVAL, "table step and node factor must be > 0");
    t = calloc(1, sizeof *t);
    if (t == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory (exact table)");
    t->k = k;
    t->base = base;
    t->nu = base == LF_BASE_BONDED ? nu : 0.0;
    t->n = (size_t) ceil((lmax - lmin) / step) + 1;
    t->l0 = lmin;
    t->h = (lmax - lmin) / (double) (t->n - 1);
    t->F = malloc(NFUN * t->n * sizeof *t->F);
    t->G = malloc(NFUN * t->n * sizeof *t->G);
    if (t->F == NULL || t->G == NULL) {
        lf_exact_table_free(t);
        return lf_fail(err, LF_ENOMEM, "out of memory (exact table)");
    }
    /* the nodes are independent solves: shared round-robin (the costly
     * large-tau ones spread out) among up to one thread per core; each
     * node is computed the same way whatever the number of threads */
    for (m = 0; m < nt; m++) {
        sh[m].kr = kr;
        sh[m].t = t;
        sh[m].node_factor = node_factor;
        sh[m].first = m;
        sh[m].stride = nt;
        lf_error_clear(&sh[m].err);
    }
    for (m = 1; m < nt; m++)
        started[m] = pthread_create(&th[m], NULL, build_nodes, &sh[m]) == 0;
    build_nodes(&sh[0]);
    for (m = 1; m < nt; m++) {
        if (started[m])
            pthread_join(th[m], NULL);
        else
            build_nodes(&sh[m]);
    }
    for (m = 0; m < nt; m++)
        if (sh[m].status != LF_OK) {
            if (err != NULL)
                *err = sh[m].err;
            lf_exact_table_free(t);
            return sh[m].status;
        }
    lf_exact_table_finish(t);
    *out = t;
    return LF_OK;
}

void
lf_exact_table_finish(lf_exact_table *t)
{
    double k = t->k, kap = lf_exact_kappa(k), Z = lf_thin_Z(t->base, t->nu);
    int j;

    t->f0[0] = t->f0[1] = t->f0[2] = 1.0;
    t->f0[3] = k / (k + 1.0);
    t->thin_c[0] = 0.5 * M_PI * Z;               t->thin_pow[0] = 1.0;
    t->thin_c[1] = sqrt(M_PI * Z);               t->thin_pow[1] = 0.5;
    t->thin_c[2] = 1.0 / kap;                    t->thin_pow[2] = 0.0;
    t->thin_c[3] = 0.5 * M_PI * Z * k / (kap * (k + 2.0)); t->thin_pow[3] = 1.0;
    for (j = 0; j < NFUN; j++)
        t->lthin_c[j] = log(t->thin_c[j]);
    for (j = 0; j < NFUN; j++) {
        double sm = 1.0 / LF_EXACT_TAU_MAX;
        double r0 = t->F[NFUN * (t->n - 1) + (size_t) j]
                    - log(t->thin_c[j] * pow(LF_EXACT_TAU_MAX, t->thin_pow[j]));
        double g = t->G[NFUN * (t->n - 1) + (size_t) j] - t->thin_pow[j];
        /* r = alpha s + beta s^2, dr/dl = -(alpha s + 2 beta s^2) = g */
        double bs2 = -g - r0;
        t->beta[j] = bs2 / (sm * sm);
        t->alpha[j] = (r0 - bs2) / sm;
    }
}

/* Where l = ln tau falls in a table's grid (the tables of a mix share
 * one) and what the evaluation there needs: the cubic Hermite basis and
 * its first and second derivatives in l inside, tau or 1/tau outside. */
typedef struct {
    int region;              /* -1 below TAU_MIN, 0 inside, 1 above TAU_MAX */
    size_t i;
    double l, x;             /* x: tau below, 1/tau above */
    double h00, h01, h10, h11, g00, g10, g11, c00, c10, c11;
} lpos;

static void
lpos_at(const lf_exact_table *t, double l, lpos *p)
{
    double ih, q, u;

    p->l = l;
    if (l < LN_TAU_MIN) {
        p->region = -1;
        p->x = exp(l);
        return;
    }
    if (l > LN_TAU_MAX) {
        p->region = 1;
        p->x = exp(-l);
        return;
    }
    p->region = 0;
    ih = 1.0 / t->h;
    q = (l - t->l0) * ih;
    p->i = q <= 0.0 ? 0 : (size_t) q;
    if (p->i >= t->n - 1)
        p->i = t->n - 2;
    u = q - (double) p->i;
    p->h01 = u * u * (3.0 - 2.0 * u);
    p->h00 = 1.0 - p->h01;
    p->h10 = u * (1.0 - u) * (1.0 - u) * t->h;
    p->h11 = u * u * (u - 1.0) * t->h;
    p->g00 = 6.0 * u * (u - 1.0) * ih;
    p->g10 = (1.0 - u) * (1.0 - 3.0 * u);
    p->g11 = u * (3.0 * u - 2.0);
    p->c00 = (12.0 * u - 6.0) * ih * ih;
    p->c10 = (6.0 * u - 4.0) * ih;
    p->c11 = (6.0 * u - 2.0) * ih;
}

/* ln f_j, g_j = d ln f_j / dl and, if dg is not NULL, dg_j = d g_j/dl at
 * a position, with derivatives in l (no tau needed inside the grid, where
 * the tables store d ln f/dl).  dg
 * is the second derivative of the piecewise cubic (a step at nodes). */
typedef double tab_v4 __attribute__((vector_size(4 * sizeof(double))));

static void
table_apply(const lf_exact_table *t, const lpos *p, double F[4], double g[4], double dg[4])
{
    int j;

    if (p->region < 0) {
        for (j = 0; j < NFUN; j++) {
            double slope = (t->flo[j] - t->f0[j]) / LF_EXACT_TAU_MIN;
            double f = t->f0[j] + slope * p->x;
            F[j] = log(f);
            g[j] = slope * p->x / f;
            if (dg != NULL)
                dg[j] = g[j] * (1.0 - g[j]);
        }
    } else if (p->region > 0) {
        double sg = p->x;
        for (j = 0; j < NFUN; j++) {
            F[j] = t->lthin_c[j] + t->thin_pow[j] * p->l + t->alpha[j] * sg + t->beta[j] * sg * sg;
            g[j] = t->thin_pow[j] - t->alpha[j] * sg - 2.0 * t->beta[j] * sg * sg;
            if (dg != NULL)
                dg[j] = t->alpha[j] * sg + 4.0 * t->beta[j] * sg * sg;
        }
    } else {
        /* the four functions side by side, one per element of a vector
         * (GCC/Clang vector extensions): each element takes the scalar
         * loop's operations in its order */
        const double *Fa = t->F + NFUN * p->i, *Ga = t->G + NFUN * p->i;
        tab_v4 fa, fb, ga, gb, dF, v;
        memcpy(&fa, Fa, sizeof fa);
        memcpy(&fb, Fa + NFUN, sizeof fb);
        memcpy(&ga, Ga, sizeof ga);
        memcpy(&gb, Ga + NFUN, sizeof gb);
        dF = fa - fb;
        v = p->h00 * fa + p->h01 * fb + p->h10 * ga + p->h11 * gb;
        memcpy(F, &v, sizeof v);
        v = p->g00 * dF + p->g10 * ga + p->g11 * gb;
        memcpy(g, &v, sizeof v);
        if (dg != NULL) {
            v = p->c00 * dF + p->c10 * ga + p->c11 * gb;
            memcpy(dg, &v, sizeof v);
        }
    }
}

void
lf_exact_mix_eval_u(const lf_exact_mix *mx, double l, double F[4], double g[4], double dg[4],
                    double H[4], double dH[4])
{
    lpos p;
    int m, j;

    lpos_at(mx->t[0], l, &p);
    if (mx->pm != NULL && p.region >= 0) {
        /* pre_nu shares pre's grid (both copy t[0]'s) */
        table_apply(&mx->pm->pre, &p, F, g, dg);
        if (H != NULL) {
            double gn[4];
            table_apply(&mx->pm->pre_nu, &p, H, dH != NULL ? dH : gn, NULL);
        }
        return;
    }
    if (mx->m == 1) {
        table_apply(mx->t[0], &p, F, g, dg);
        if (H != NULL)
            for (j = 0; j < NFUN; j++) {
                H[j] = mx->dwl[0] * F[j];
                if (dH != NULL)
                    dH[j] = mx->dwl[0] * g[j];
            }
        return;
    }
    for (j = 0; j < NFUN; j++) {
        F[j] = g[j] = 0.0;
        if (dg != NULL)
            dg[j] = 0.0;
        if (H != NULL)
            H[j] = 0.0;
        if (dH != NULL)
            dH[j] = 0.0;
    }
    for (m = 0; m < mx->m; m++) {
        double Fm[4], gm[4], dgm[4];
        const lf_exact_table *t = mx->t[m];
        if (m > 0 && p.region == 0
            && (t->n != mx->t[0]->n || t->l0 != mx->t[0]->l0 || t->h != mx->t[0]->h))
            lpos_at(t, l, &p);     /* another grid (not made by the store) */
        table_apply(t, &p, Fm, gm, dg != NULL ? dgm : NULL);
        for (j = 0; j < NFUN; j++) {
            F[j] += mx->wl[m] * Fm[j];
            g[j] += mx->wl[m] * gm[j];
            if (dg != NULL)
                dg[j] += mx->wl[m] * dgm[j];
            if (H != NULL)
                H[j] += mx->dwl[m] * Fm[j];
            if (dH != NULL)
                dH[j] += mx->dwl[m] * gm[j];
        }
    }
}

/* ln f_j and d ln f_j / dtau at tau. */
static void
table_eval_log(const lf_exact_table *t, double tau, double F[4], double G[4])
{
    lpos p;
    int j;

    lpos_at(t, log(tau), &p);
    table_apply(t, &p, F, G, NULL);
    for (j = 0; j < NFUN; j++)
        G[j] /= tau;
}

void
lf_exact_table_eval(const lf_exact_table *t, double tau, double f[4], double df[4])
{
    double F[4], G[4];
    int j;

    table_eval_log(t, tau, F, G);
    for (j = 0; j < NFUN; j++) {
        f[j] = exp(F[j]);
        if (df != NULL)
            df[j] = f[j] * G[j];
    }
}

/* ---------------------------------------------------------------- store */

static pthread_mutex_t publish_lock = PTHREAD_MUTEX_INITIALIZER;
static _Atomic(lf_exact_table *) store_head = NULL;
static _Atomic(double) last_build = 0.0;

double
lf_exact_nu_node(int i)
{
    double ymin = 0.5 * log(1.0 - 2.0 * LF_EXACT_NU_MAX);
    double y = ymin * (double) i / (double) (LF_EXACT_NY - 1);
    return 0.5 * (1.0 - exp(2.0 * y));
}

static lf_exact_table *
store_find(double k, lf_base base, double nu)
{
    lf_exact_table *t;

    for (t = atomic_load_explicit(&store_head, memory_order_acquire); t != NULL; t = t->next)
        if (t->k == k && t->base == base && t->nu == nu)
            return t;
    return NULL;
}

/* Link t in unless an equal table got there first (then t is freed and
 * that one returned). */
static const lf_exact_table *
store_publish(lf_exact_table *t)
{
    lf_exact_table *old;

    pthread_mutex_lock(&publish_lock);
    old = store_find(t->k, t->base, t->nu);
    if (old == NULL) {
        t->next = atomic_load_explicit(&store_head, memory_order_relaxed);
        atomic_store_explicit(&store_head, t, memory_order_release);
    }
    pthread_mutex_unlock(&publish_lock);
    if (old != NULL) {
        lf_exact_table_free(t);
        return old;
    }
    return t;
}

const lf_exact_table *
lf_exact_table_find(double k, lf_base base, double nu)
{
    const lf_exact_table *t;
    lf_exact_table *d;

    if (base == LF_BASE_FRICTIONLESS)
        nu = 0.0;
    if ((t = store_find(k, base, nu)) != NULL)
        return t;
    if ((d = lf_exact_disk_load(k, base, nu, LF_EXACT_STEP, 1.0)) == NULL)
        return NULL;
    return store_publish(d);
}

int
lf_exact_table_get(double k, lf_base base, double nu, const lf_exact_table **out,
                   lf_error *err)
{
    lf_exact_table *t;
    lf_exact_kernel *kr = NULL;
    int status;
    double t0;

    if (base == LF_BASE_FRICTIONLESS)
        nu = 0.0;
    *out = store_find(k, base, nu);
    if (*out != NULL)
        return LF_OK;
    t = lf_exact_disk_load(k, base, nu, LF_EXACT_STEP, 1.0);
    if (t == NULL) {
        t0 = now_seconds();
        status = lf_exact_kernel_alloc(&kr, base, nu, err);
        if (status == LF_OK)
            status = lf_exact_table_build(kr, k, base, nu, LF_EXACT_STEP, 1.0, &t, err);
        lf_exact_kernel_free(kr);
        if (status != LF_OK)
            return status;
        atomic_store(&last_build, now_seconds() - t0);
        lf_exact_disk_save(t, LF_EXACT_STEP, 1.0);
    }
    *out = store_publish(t);
    return LF_OK;
}

int
lf_exact_mix_weights(lf_exact_mix *mx, lf_base base, double nu, lf_error *err)
{
    double ymin = 0.5 * log(1.0 - 2.0 * LF_EXACT_NU_MAX), hy, y, q, dydnu;
    int i0, m;

    mx->pm = NULL;
    if (base == LF_BASE_FRICTIONLESS) {
        mx->m = 1;
        mx->node0 = 0;
        mx->wl[0] = 1.0;
        mx->dwl[0] = 0.0;
        return LF_OK;
    }
    if (!(nu >= 0.0 && nu <= LF_EXACT_NU_MAX))
        return lf_fail(err, LF_EINVAL, "the exact bonded model covers 0 <= nu <= %g (got %g)",
                       LF_EXACT_NU_MAX, nu);
    hy = -ymin / (double) (LF_EXACT_NY - 1);
    y = 0.5 * log(1.0 - 2.0 * nu);
    dydnu = -1.0 / (1.0 - 2.0 * nu);
    q = -y / hy;                      /* node coordinate, 0 at nu = 0 */
    /* centred stencil; nodes -1 (nu < 0) and LF_EXACT_NY (nu beyond
     * LF_EXACT_NU_MAX) are ghosts that keep it centred at the ends */
    i0 = (int) floor(q) - 1;
    if (i0 < -1)
        i0 = -1;
    if (i0 > LF_EXACT_NY - 3)
        i0 = LF_EXACT_NY - 3;
    mx->m = 4;
    mx->node0 = i0;
    for (m = 0; m < 4; m++) {
        double w = 1.0, dw = 0.0;
        int j, l;
        /* Lagrange basis in q and its derivative */
        for (j = 0; j < 4; j++) {
            if (j == m)
                continue;
            w *= (q - (double) (i0 + j)) / (double) (m - j);
        }
        for (l = 0; l < 4; l++) {
            double prod = 1.0;
            if (l == m)
                continue;
            for (j = 0; j < 4; j++) {
                if (j == m || j == l)
                    continue;
                prod *= (q - (double) (i0 + j)) / (double) (m - j);
            }
            dw += prod / (double) (m - l);
        }
        mx->wl[m] = w;
        mx->dwl[m] = dw * (-dydnu / hy);  /* dq/dnu = -dy/dnu / hy */
    }
    return LF_OK;
}

int
lf_exact_mix_init(lf_exact_mix *mx, double k, lf_base base, double nu, lf_error *err)
{
    int m, status = lf_exact_mix_weights(mx, base, nu, err);

    if (status != LF_OK)
        return status;
    if (base == LF_BASE_FRICTIONLESS)
        return lf_exact_table_get(k, base, 0.0, &mx->t[0], err);
    for (m = 0; m < 4; m++) {
        status = lf_exact_table_get(k, base, lf_exact_nu_node(mx->node0 + m), &mx->t[m], err);
        if (status != LF_OK)
            return status;
    }
    return LF_OK;
}

void
lf_exact_mix_eval_log(const lf_exact_mix *mx, double l, double tau, double F[4], double G[4],
                      double H[4])
{
    int j;

    lf_exact_mix_eval_u(mx, l, F, G, NULL, H, NULL);
    for (j = 0; j < NFUN; j++)
        G[j] /= tau;
}

void
lf_exact_mix_eval_l(const lf_exact_mix *mx, double l, double tau, double f[4], double df[4],
                    double dfn[4])
{
    double F[4], G[4], H[4];
    int j;

    lf_exact_mix_eval_log(mx, l, tau, F, G, dfn != NULL ? H : NULL);
    for (j = 0; j < NFUN; j++) {
        f[j] = exp(F[j]);
        df[j] = f[j] * G[j];
        if (dfn != NULL)
            dfn[j] = f[j] * H[j];
    }
}

void
lf_exact_premix_init(lf_exact_premix *pm, lf_exact_mix *mx)
{
    const lf_exact_table *t0 = mx->t[0];
    lf_exact_table *pre = &pm->pre, *nu = &pm->pre_nu;
    size_t i, nn;
    int m, j;

    mx->pm = NULL;
    if (mx->m < 2 || t0->n > LF_EXACT_NMAX)
        return;
    for (m = 1; m < mx->m; m++)
        if (mx->t[m]->n != t0->n || mx->t[m]->l0 != t0->l0 || mx->t[m]->h != t0->h)
            return;
    nn = NFUN * t0->n;
    /* a plain copy, less t0's `derived` (a bonded table's list of the
     * exact model's held nu, exact.h) */
    *pre = *t0;
    *nu = *t0;
    atomic_init(&pre->derived, NULL);
    atomic_init(&nu->derived, NULL);
    pre->F = pm->buf[0];
    pre->G = pm->buf[1];
    nu->F = pm->buf[2];
    nu->G = pm->buf[3];
    for (i = 0; i < nn; i++) {
        double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
        for (m = 0; m < mx->m; m++) {
            a += mx->wl[m] * mx->t[m]->F[i];
            b += mx->wl[m] * mx->t[m]->G[i];
            c += mx->dwl[m] * mx->t[m]->F[i];
            d += mx->dwl[m] * mx->t[m]->G[i];
        }
        pre->F[i] = a;
        pre->G[i] = b;
        nu->F[i] = c;
        nu->G[i] = d;
    }
    for (j = 0; j < NFUN; j++) {
        pre->lthin_c[j] = pre->thin_pow[j] = pre->alpha[j] = pre->beta[j] = 0.0;
        nu->lthin_c[j] = nu->thin_pow[j] = nu->alpha[j] = nu->beta[j] = 0.0;
        for (m = 0; m < mx->m; m++) {
            const lf_exact_table *t = mx->t[m];
            pre->lthin_c[j] += mx->wl[m] * t->lthin_c[j];
            pre->thin_pow[j] += mx->wl[m] * t->thin_pow[j];
            pre->alpha[j] += mx->wl[m] * t->alpha[j];
            pre->beta[j] += mx->wl[m] * t->beta[j];
            nu->lthin_c[j] += mx->dwl[m] * t->lthin_c[j];
            nu->thin_pow[j] += mx->dwl[m] * t->thin_pow[j];
            nu->alpha[j] += mx->dwl[m] * t->alpha[j];
            nu->beta[j] += mx->dwl[m] * t->beta[j];
        }
    }
    pre->next = nu->next = NULL;
    mx->pm = pm;
}

void
lf_exact_mix_eval(const lf_exact_mix *mx, double tau, double f[4], double df[4],
                  double dfn[4])
{
    lf_exact_mix_eval_l(mx, log(tau), tau, f, df, dfn);
}

void
lf_exact_cache_clear(void)
{
    lf_exact_table *t, *next;

    pthread_mutex_lock(&publish_lock);
    t = atomic_exchange(&store_head, NULL);
    pthread_mutex_unlock(&publish_lock);
    for (; t != NULL; t = next) {
        next = t->next;
        lf_exact_table_free(t);
    }
}

double
lf_exact_last_build_seconds(void)
{
    return atomic_load(&last_build);
}
