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
 *    compressibility length l/h of physics.md section 5 (every frictionless
 *    layer and bonded nu <= 0.45), and only approximate beyond.
 *
 * Cache.  A process-wide list of immutable tables keyed by (k, base, nu),
 * guarded by one mutex: a missing table is built under the lock (other
 * threads wait; no table is built twice), published, and never modified or
 * freed until lf_exact_cache_clear().
 */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <time.h>

#include "exact.h"

#define NFUN 4

struct lf_exact_table {
    double k;
    lf_base base;
    double nu;
    size_t n;            /* nodes */
    double l0, h;        /* l_i = l0 + i h */
    double *F;           /* ln f_j(l_i) at F[NFUN i + j] */
    double *G;           /* d ln f_j / dl */
    double f0[NFUN];     /* half-space values */
    double flo[NFUN], dflo[NFUN];   /* f and f' at TAU_MIN */
    double thin_c[NFUN], thin_pow[NFUN]; /* f_thin = c tau^pow */
    double alpha[NFUN], beta[NFUN];      /* tail above TAU_MAX */
    lf_exact_table *next;  /* cache list */
};

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
    free(t->F);
    free(t->G);
    free(t);
}

int
lf_exact_table_build(const lf_exact_kernel *kr, double k, lf_base base, double nu,
                     double step, double node_factor, lf_exact_table **out,
                     lf_error *err)
{
    lf_exact_table *t;
    double lmin = log(LF_EXACT_TAU_MIN), lmax = log(LF_EXACT_TAU_MAX);
    double kap = lf_exact_kappa(k), Z = lf_thin_Z(base, nu);
    size_t i;
    int j, status;

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
    for (i = 0; i < t->n; i++) {
        double tau = exp(t->l0 + (double) i * t->h);
        size_t N = (size_t) ceil(node_factor * (double) lf_exact_nodes(tau));
        lf_exact_point pt;
        double f[NFUN], df[NFUN];

        status = lf_exact_solve(kr, k, tau, N, &pt, err);
        if (status != LF_OK) {
            lf_exact_table_free(t);
            return status;
        }
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
    t->f0[0] = t->f0[1] = t->f0[2] = 1.0;
    t->f0[3] = k / (k + 1.0);
    t->thin_c[0] = 0.5 * M_PI * Z;               t->thin_pow[0] = 1.0;
    t->thin_c[1] = sqrt(M_PI * Z);               t->thin_pow[1] = 0.5;
    t->thin_c[2] = 1.0 / kap;                    t->thin_pow[2] = 0.0;
    t->thin_c[3] = 0.5 * M_PI * Z * k / (kap * (k + 2.0)); t->thin_pow[3] = 1.0;
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
    *out = t;
    return LF_OK;
}

/* ln f_j and d ln f_j / dtau at tau. */
static void
table_eval_log(const lf_exact_table *t, double tau, double F[4], double G[4])
{
    int j;

    if (tau < LF_EXACT_TAU_MIN) {
        for (j = 0; j < NFUN; j++) {
            double slope = (t->flo[j] - t->f0[j]) / LF_EXACT_TAU_MIN;
            double f = t->f0[j] + slope * tau;
            F[j] = log(f);
            G[j] = slope / f;
        }
    } else if (tau > LF_EXACT_TAU_MAX) {
        double sg = 1.0 / tau, lt = log(tau);
        for (j = 0; j < NFUN; j++) {
            F[j] = log(t->thin_c[j]) + t->thin_pow[j] * lt
                   + t->alpha[j] * sg + t->beta[j] * sg * sg;
            G[j] = sg * (t->thin_pow[j] - t->alpha[j] * sg - 2.0 * t->beta[j] * sg * sg);
        }
    } else {
        double q = (log(tau) - t->l0) / t->h, u, h00, h10, h01, h11, g00, g10, g11;
        size_t i = q <= 0.0 ? 0 : (size_t) q;
        if (i >= t->n - 1)
            i = t->n - 2;
        u = q - (double) i;
        h00 = (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u);
        h10 = u * (1.0 - u) * (1.0 - u);
        h01 = u * u * (3.0 - 2.0 * u);
        h11 = u * u * (u - 1.0);
        g00 = 6.0 * u * (u - 1.0);
        g10 = (1.0 - u) * (1.0 - 3.0 * u);
        g11 = u * (3.0 * u - 2.0);
        for (j = 0; j < NFUN; j++) {
            size_t a = NFUN * i + (size_t) j, b = a + NFUN;
            F[j] = h00 * t->F[a] + h01 * t->F[b] + t->h * (h10 * t->G[a] + h11 * t->G[b]);
            G[j] = ((g00 * (t->F[a] - t->F[b])) / t->h + g10 * t->G[a] + g11 * t->G[b]) / tau;
        }
    }
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

/* ---------------------------------------------------------------- cache */

static pthread_mutex_t cache_lock = PTHREAD_MUTEX_INITIALIZER;
static lf_exact_table *cache_head = NULL;
static double last_build = 0.0;

double
lf_exact_nu_node(int i)
{
    double ymin = 0.5 * log(1.0 - 2.0 * LF_EXACT_NU_MAX);
    double y = ymin * (double) i / (double) (LF_EXACT_NY - 1);
    return 0.5 * (1.0 - exp(2.0 * y));
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
    *out = NULL;
    if (pthread_mutex_lock(&cache_lock) != 0)
        return lf_fail(err, LF_ENUMERIC, "cannot lock the table cache");
    for (t = cache_head; t != NULL; t = t->next)
        if (t->k == k && t->base == base && t->nu == nu)
            break;
    if (t == NULL) {
        t0 = now_seconds();
        status = lf_exact_kernel_alloc(&kr, base, nu, err);
        if (status == LF_OK)
            status = lf_exact_table_build(kr, k, base, nu, LF_EXACT_STEP, 1.0, &t, err);
        lf_exact_kernel_free(kr);
        if (status != LF_OK) {
            pthread_mutex_unlock(&cache_lock);
            return status;
        }
        t->next = cache_head;
        cache_head = t;
        last_build = now_seconds() - t0;
    }
    pthread_mutex_unlock(&cache_lock);
    *out = t;
    return LF_OK;
}

int
lf_exact_mix_init(lf_exact_mix *mx, double k, lf_base base, double nu, lf_error *err)
{
    double ymin = 0.5 * log(1.0 - 2.0 * LF_EXACT_NU_MAX), hy, y, q, dydnu;
    int i0, m, status;

    if (base == LF_BASE_FRICTIONLESS) {
        mx->m = 1;
        mx->wl[0] = 1.0;
        mx->dwl[0] = 0.0;
        return lf_exact_table_get(k, base, 0.0, &mx->t[0], err);
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
        status = lf_exact_table_get(k, base, lf_exact_nu_node(i0 + m), &mx->t[m], err);
        if (status != LF_OK)
            return status;
    }
    return LF_OK;
}

void
lf_exact_mix_eval(const lf_exact_mix *mx, double tau, double f[4], double df[4],
                  double dfn[4])
{
    double F[4] = {0, 0, 0, 0}, G[4] = {0, 0, 0, 0}, H[4] = {0, 0, 0, 0};
    int m, j;

    for (m = 0; m < mx->m; m++) {
        double Fm[4], Gm[4];
        table_eval_log(mx->t[m], tau, Fm, Gm);
        for (j = 0; j < NFUN; j++) {
            F[j] += mx->wl[m] * Fm[j];
            G[j] += mx->wl[m] * Gm[j];
            H[j] += mx->dwl[m] * Fm[j];
        }
    }
    for (j = 0; j < NFUN; j++) {
        f[j] = exp(F[j]);
        df[j] = f[j] * G[j];
        if (dfn != NULL)
            dfn[j] = f[j] * H[j];
    }
}

void
lf_exact_cache_clear(void)
{
    lf_exact_table *t, *next;

    pthread_mutex_lock(&cache_lock);
    for (t = cache_head; t != NULL; t = next) {
        next = t->next;
        lf_exact_table_free(t);
    }
    cache_head = NULL;
    pthread_mutex_unlock(&cache_lock);
}

double
lf_exact_last_build_seconds(void)
{
    double s;
    pthread_mutex_lock(&cache_lock);
    s = last_build;
    pthread_mutex_unlock(&cache_lock);
    return s;
}
