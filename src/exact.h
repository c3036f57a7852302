/* exact.h: internals of the finite-thickness ("exact") layer model, shared by
 * src/exact_kernel.c (kernel and Nystrom solver), src/exact_table.c (tables
 * of the dimensionless functions and their process cache) and
 * src/model_exact.c (the forward model).  Not installed.
 *
 * Everything here is dimensionless: lengths in units of the layer thickness
 * h, tau = a/h, x = t/a in [0, 1], E* scaled out (Lebedev & Ufliand 1958;
 * Dimitriadis et al. 2002, Biophys. J. 82:2798).
 * For contact radius a = tau h the model needs four positive functions of
 * tau, from the Fredholm solutions u1 (right-hand side 1) and v
 * (right-hand side x^k):
 *   s = int_0^1 u1 dx            flat-punch stiffness S = 2 E* h tau s
 *   e = u1(1)                    edge value, phi1(a) = e
 *   d = v(1)/u1(1)               delta1 = B kappa_k h^k tau^k d
 *   p = s d - int_0^1 v dx       P1 = 2 E* B kappa_k h^(k+1) tau^(k+1) p
 * with B = 1/(k R^(k-1)).  Half-space (tau -> 0): s = e = d = 1,
 * p = k/(k+1).  Thin layer (tau -> inf): s -> pi Z tau/2,
 * e -> sqrt(pi Z tau), d -> 1/kappa_k, p -> pi Z tau k/(2 kappa_k (k+2)).
 */
#ifndef LF_EXACT_H
#define LF_EXACT_H

#include <stddef.h>

#include "internal.h"

/* ---- kernel kf(z) = int_0^inf (1 - L(u)) cos(u z) du (exact_kernel.c) ---- */

typedef struct lf_exact_kernel lf_exact_kernel;

/* Tabulate kf for one base and nu (nu ignored when frictionless).  Direct
 * quadrature on [0, LF_EXACT_ZC], the asymptotic series in 1/z^2 beyond.
 * Owned by the caller, released with lf_exact_kernel_free (NULL allowed). */
int lf_exact_kernel_alloc(lf_exact_kernel **out, lf_base base, double nu,
                          lf_error *err);
void lf_exact_kernel_free(lf_exact_kernel *kr);

/* kf(z) and, if dkf is not NULL, kf'(z); kf is even in z. */
double lf_exact_kf(const lf_exact_kernel *kr, double z, double *dkf);

/* 1 - L(u) for a base and nu (the integrand of kf). */
double lf_exact_one_minus_L(lf_base base, double nu, double u);

/* Gauss-Legendre nodes x[] and weights w[] of n points on [0, 1]. */
void lf_exact_gauss_legendre(size_t n, double *x, double *w);

/* kappa_k = sqrt(pi) Gamma(k/2 + 1) / Gamma(k/2 + 1/2). */
double lf_exact_kappa(double k);

/* ---- one Nystrom solve (exact_kernel.c) ---- */

/* The four functions of the header comment and their tau-derivatives. */
typedef struct {
    double s, e, d, p;
    double ds, de, dd, dp;   /* d/dtau */
} lf_exact_point;

/* Solve at one tau with N Gauss-Legendre nodes on [0, 1].  Allocates its
 * own workspace.  LF_ENUMERIC if the system is singular or a value is not
 * positive and finite. */
int lf_exact_solve(const lf_exact_kernel *kr, double k, double tau, size_t N,
                   lf_exact_point *out, lf_error *err);

/* The same for a sphere of radius R at contact radius a = rho R
 * (0 < rho < 1): the second right-hand side is the sphere's
 * g(x a) R/a^2 = x atanh(rho x)/rho (x^2 as rho -> 0), so that d and p are
 * those of the paraboloid of R's scales (k = 2, B = 1/(2R)): delta1 =
 * (h^2/R) tau^2 d, P1 = 2 E* (h^3/R) tau^3 p.  Derivatives at fixed rho. */
int lf_exact_solve_sphere(const lf_exact_kernel *kr, double rho, double tau, size_t N,
                          lf_exact_point *out, lf_error *err);

/* The exact model's sphere of radius R (exact_sphere.c): ln f of the k = 2
 * tables at u = ln tau (F, g = dF/du and, where not NULL, dg = dg/du,
 * H = dF/dnu, dH = dH/du), as lf_exact_mix_eval_u gives them, turned into
 * the sphere's in place (entries 2 and 3, d and p) at rho = a/R =
 * tau h/R = exp(u + ln_hR); NaN where rho >= 1. */
void lf_exact_sphere_adjust(double ln_hR, double u, double F[4], double g[4], double dg[4],
                            double H[4], double dH[4]);

/* The node count the tables use at tau for relative accuracy ~1e-8. */
size_t lf_exact_nodes(double tau);

/* ---- tables (exact_table.c) ---- */

/* Range of the direct tabulation; outside it the tables use the limits
 * (see exact_table.c). */
#define LF_EXACT_TAU_MIN 1e-3
#define LF_EXACT_TAU_MAX 100.0

/* Grid in nu for bonded layers: y = ln sqrt(1 - 2 nu) on a uniform grid
 * from LF_EXACT_Y_MIN (nu = LF_EXACT_NU_MAX) to 0 (nu = 0). */
#define LF_EXACT_NU_MAX 0.4995
#define LF_EXACT_NY 60

/* Default spacing of the table in ln tau. */
#define LF_EXACT_STEP 0.1

#define LF_EXACT_NFUN 4

/* One table: ln f_j and d ln f_j/dl at the nodes (from the solves, what a
 * table file holds), and what lf_exact_table_finish derives from them. */
typedef struct lf_exact_table lf_exact_table;
struct lf_exact_table {
    double k;
    lf_base base;
    double nu;           /* 0 when frictionless */
    size_t n;            /* nodes */
    double l0, h;        /* l_i = l0 + i h */
    double *F;           /* ln f_j(l_i) at F[NFUN i + j] */
    double *G;           /* d ln f_j / dl */
    double flo[LF_EXACT_NFUN], dflo[LF_EXACT_NFUN];   /* f and f' at TAU_MIN */
    /* derived (lf_exact_table_finish) */
    double f0[LF_EXACT_NFUN];                         /* half-space values */
    double thin_c[LF_EXACT_NFUN], thin_pow[LF_EXACT_NFUN]; /* f_thin = c tau^pow */
    double lthin_c[LF_EXACT_NFUN];                         /* ln thin_c */
    double alpha[LF_EXACT_NFUN], beta[LF_EXACT_NFUN];      /* tail above TAU_MAX */
    lf_exact_table *next;  /* the process store's list */
    /* what the exact model derives from this table alone (model_exact.c,
     * frictionless: the grid of its conditions), made by the first model
     * object that uses the table and freed with it; NULL until then.  On
     * a bonded node table: a list of blocks (the data of the nu held by
     * fits, model_exact.c) whose first member is the next block's
     * address, freed with it */
    _Atomic(void *) derived;
};

/* Build one table from a kernel: nodes every `step` in ln tau, Nystrom
 * with node_factor * lf_exact_nodes(tau) nodes (1 = the default).  Owned
 * by the caller (lf_exact_table_free); the cache builds its own. */
int lf_exact_table_build(const lf_exact_kernel *kr, double k, lf_base base,
                         double nu, double step, double node_factor,
                         lf_exact_table **out, lf_error *err);
void lf_exact_table_free(lf_exact_table *t);
/* Fill the derived members from k, base, nu, n, l0, h, F, G, flo, dflo. */
void lf_exact_table_finish(lf_exact_table *t);

/* Functions at tau from one table: f[4] = {s, e, d, p}, df[4] their
 * tau-derivatives (df may be NULL). */
void lf_exact_table_eval(const lf_exact_table *t, double tau, double f[4],
                         double df[4]);

/* The process store.  Tables are immutable once published and live until
 * lf_exact_cache_clear() (tests only; not thread-safe against users).
 * lf_exact_table_get returns the table of (k, base, nu): from memory
 * without a lock, else from the disk cache, else built (no lock held while
 * reading or building).  nu is used as given (bonded), ignored for
 * frictionless. */
int lf_exact_table_get(double k, lf_base base, double nu,
                       const lf_exact_table **out, lf_error *err);
void lf_exact_cache_clear(void);
/* How many grids of the exact model's conditions (detachment, pull-off,
 * jump) the process has built: one per frictionless table, shared by its
 * model objects, and one per bonded model object and nu in use.  For tests
 * and the curious. */
unsigned long lf_exact_conditions_built(void);
/* The table of (k, base, nu) if it is in the store or on disk (then it is
 * published in the store); NULL otherwise.  Never builds. */
const lf_exact_table *lf_exact_table_find(double k, lf_base base, double nu);

/* ---- tables on disk (exact_cache.c) ---- */

/* The table of (k, base, nu) built with (step, node_factor) from its file
 * in the cache folder, or NULL when the cache is off, the file is missing,
 * or it is stale or corrupt (then counted in the stats; the caller builds
 * the table and saves it again).  Never prints. */
lf_exact_table *lf_exact_disk_load(double k, lf_base base, double nu, double step,
                                   double node_factor);
/* Write t to the cache folder atomically (temporary file in the same
 * folder, then rename).  Failures are counted, never fatal. */
void lf_exact_disk_save(const lf_exact_table *t, double step, double node_factor);
/* FNV-1a 64-bit hash of n bytes (the files' checksum). */
unsigned long long lf_exact_disk_checksum(const void *p, size_t n);

/* The bonded nu grid: node i (-1 .. LF_EXACT_NY) and its nu; nodes -1 and
 * LF_EXACT_NY are ghosts just outside [0, LF_EXACT_NU_MAX]. */
double lf_exact_nu_node(int i);

/* The functions at (tau, nu) as the model uses them.  Frictionless: one
 * table.  Bonded: 4-point Lagrange interpolation of ln f across the nu grid
 * in y = ln sqrt(1 - 2 nu) (one-sided at the ends); the node tables are
 * built on demand through the cache by lf_exact_mix_init, which is the only
 * step that may allocate.  dfn receives d/dnu of the interpolant, so
 * derivatives in nu are those of the values returned. */
typedef struct lf_exact_premix lf_exact_premix;
typedef struct {
    int m;                         /* tables in use, 1 or 4 */
    int node0;                     /* bonded: nu node of t[0] (-1 .. NY-3) */
    const lf_exact_table *t[4];
    double wl[4];                  /* Lagrange weights at y(nu) */
    double dwl[4];                 /* their d/dnu */
    const lf_exact_premix *pm;     /* the same flattened, or NULL */
} lf_exact_mix;

/* A bonded mix flattened for its nu (the weights are fixed for one
 * material, and ln f mixes linearly): pre holds sum_m w_m ln f_m on the
 * common grid and in the tail above TAU_MAX, pre_nu sum_m dw_m ln f_m, so
 * that one table is read instead of four (below TAU_MIN the four are still
 * used).  Fits on the stack (no allocation). */
#define LF_EXACT_NMAX 128
struct lf_exact_premix {
    lf_exact_table pre, pre_nu;
    double buf[4][LF_EXACT_NFUN * LF_EXACT_NMAX];
};
/* Flatten mx into pm and point mx->pm at it; nothing when mx has one table
 * or the tables' grids differ or exceed LF_EXACT_NMAX nodes. */
void lf_exact_premix_init(lf_exact_premix *pm, lf_exact_mix *mx);

int lf_exact_mix_init(lf_exact_mix *mx, double k, lf_base base, double nu,
                      lf_error *err);
/* The same without the tables: m, node0 and the weights only (t[] is left
 * for the caller; model_exact.c fills it from its model object). */
int lf_exact_mix_weights(lf_exact_mix *mx, lf_base base, double nu, lf_error *err);
/* f, df (d/dtau) and dfn (d/dnu; may be NULL) at tau. */
void lf_exact_mix_eval(const lf_exact_mix *mx, double tau, double f[4],
                       double df[4], double dfn[4]);
/* The same with l = ln tau given (saves the logarithm). */
void lf_exact_mix_eval_l(const lf_exact_mix *mx, double l, double tau, double f[4],
                         double df[4], double dfn[4]);
/* ln f, d ln f/dtau and d ln f/dnu (H may be NULL) at l = ln tau. */
void lf_exact_mix_eval_log(const lf_exact_mix *mx, double l, double tau, double F[4],
                           double G[4], double H[4]);

/* ln f, g = d ln f/dl, dg = dg/dl, H = d ln f/dnu and dH = dH/dl (dg, H,
 * dH may be NULL; dH only with H) at l = ln tau: the functions of
 * lf_exact_mix_eval_log with derivatives in l, which inside the tables'
 * range needs no tau at all (model_exact.c works in l).  dg is the
 * interpolant's own second derivative (it steps at the tables' nodes). */
void lf_exact_mix_eval_u(const lf_exact_mix *mx, double l, double F[4], double g[4],
                         double dg[4], double H[4], double dH[4]);

/* The exact model's evaluation without its shortcuts (model_exact.c):
 * every indentation solved on its own by safeguarded Newton to rounding,
 * with tables from the store.  The reference the fast path is tested
 * against (tests/test_exact.c). */
int lf_exact_eval_precise(const lf_probe *probe, const lf_material *mat, lf_branch branch,
                          size_t n, const double *delta, lf_eval *out, lf_error *err);

/* The exact model's eval started from the roots of the curve's last
 * evaluation (lf_model_eval_roots; roots[0..LF_MODEL_ROOTS_HEAD-1]: the
 * ln lambda, nu and branch they were for). */
int lf_exact_eval_warm(void *state, const lf_probe *probe, const lf_material *mat,
                       lf_branch branch, size_t n, const double *delta, lf_eval *out,
                       double *roots);

/* The fast path's four points at once (x86-64 with AVX2, model_exact.c):
 * mode 0 forces the scalar path, 1 restores the choice by the processor,
 * -1 leaves it; returns 1 when the vector path is in use.  The two give
 * the same bits (tests/test_exact.c). */
int lf_exact_simd(int mode);

/* Build statistics of the last table built in this process (bench). */
double lf_exact_last_build_seconds(void);

#endif
