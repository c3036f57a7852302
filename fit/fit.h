/* fit.h: the fitter's internal header (not installed), one file per piece
 * in the way of GSL's multifit_nlinear.  Calls go one way, down this list
 * (tests/cli/callgraph.sh checks that no file calls back up):
 *   joint.c       a fit of many curves: each alone, the joint fit from two
 *                 starts, its intervals, how the curves differ (lf_fit_joint)
 *   choose.c      the model choice over whole fits (lf_fit_choose_driver)
 *   profile.c     profile-likelihood intervals (lf_fit_profile)
 *   descend.c     the minimum, always: a lower chi2 near the fit restarts it
 *   driver.c      one run: start, solve, assessment, leave-one-out (loo.c)
 *   design.c      what a planned set of curves would measure (at the truth)
 *   uncertainty.c the assessment: covariance, intervals, estimates
 *                 (plausible.c: numbers no real test gives)
 *   judge.c       what the data determine and why, in words: the one
 *                 judgement of a fit at its solution and a design at the
 *                 truth (and the model choice's rule)
 *   hold.c        a refit with one parameter held (a profile's point)
 *   solve.c       the solve and its restarts: second_start.c, reweight.c,
 *                 the honest end (verdict.c)
 *   edge_scan.c   the contact-edge scan around each solve
 *   iterate.c     the iteration and its stopping rules (lm.c: Levenberg-
 *                 Marquardt on the normal matrix; GSL for the other methods)
 *   layout.c      settings, the problem's layout and workspace (alloc/free)
 *   guess.c       the automatic start (a fit_start; guess_model.c: a
 *                 model's own start)
 *   problem.c     parameter mapping, residuals, Jacobian
 *   decomp.c      the decomposition shared by uncertainty.c and choose.c
 *   noise.c       each curve's noise and the noise model of the residuals
 *   result.c      the result's lifetime;  median.c  medians
 *   hetero.c      how much curves differ (random effects; lf_heterogeneity_of)
 *
 * Three sets of coordinates:
 *  - physical ("rep", what reports and the covariance use):
 *        w, E*, nu, then per curve z0, F0, s  (SI)
 *  - internal: ln w, ln E*, u = atanh(4 nu - 1) (so nu = (1 + tanh u)/4 stays
 *    in (0, 1/2)), z0 / L_j, F0 / Fs_j, s / (Fs_j / L_j), with L_j the
 *    curve's depth span and Fs_j its largest |force|;
 *  - the GSL vector x = 1 + (internal - internal at the guess): every entry
 *    starts at 1, so GSL's relative step test |dx| <= xtol (|x| + xtol) acts
 *    as an absolute test on the internal scale for every parameter. */
#ifndef LF_FIT_H
#define LF_FIT_H

#include <gsl/gsl_multifit_nlinear.h>

#include "internal.h"

enum { FIT_W = 0, FIT_E, FIT_NU, FIT_NMAT };

/* A bonded layer at this nu and above is nearly incompressible: only a
 * model that states its own limit (the exact model's tables: 0.4995)
 * holds there (problem.c). */
#define FIT_NU_INCOMPRESSIBLE 0.4995
/* The nu of a fit where no curve depends on it (frictionless layers,
 * half-spaces) and none was given: a stand-in that changes no curve, never
 * reported (nu is then "not determined"). */
#define FIT_NU_UNUSED 0.25

/* The normal distribution's 97.5% and 95% points: two-sided and
 * one-sided 95% intervals. */
#define FIT_Z95 1.959963984540054
#define FIT_Z95_ONE_SIDED 1.6448536269514722

/* ---- every tolerance the solve and its policies stop on ---------------- */

/* An iteration limit reached with the cost (half chi2, the residuals being
 * in units of the noise) fallen by less than FIT_FLAT_REL of itself or
 * FIT_FLAT_ABS over the last FIT_FLAT_ITERS iterations counts as
 * convergence: at the kinks of the model the trust region can creep
 * without end, and a chi2 change of 0.002 moves no estimate by more than a
 * twentieth of its standard error. */
#define FIT_FLAT_ITERS 20
#define FIT_FLAT_REL 1e-8
#define FIT_FLAT_ABS 1e-3
/* Converged when a Gauss-Newton step from the current point would lower
 * chi2 (residuals in units of the noise) by less than FIT_CHI2_STEP times
 * chi2/dof: the estimates are then within sqrt(FIT_CHI2_STEP) = 1e-3 of
 * their reported standard errors (which are scaled by sqrt(chi2/dof)) of
 * the minimum of the local quadratic, and further iterations only chase
 * rounding.  On noise-free data chi2/dof is tiny and so is the step this
 * allows.  GSL's own tests (the settings' xtol, gtol, ftol) stay in force
 * for data so clean that this one cannot be met. */
#define FIT_CHI2_STEP 1e-6
#define FIT_INFO_CHI2 3     /* the stop reason's code for that test */
/* lm.c only: also converged when the last accepted step moved every
 * estimate by less than sqrt(FIT_CREEP_CHI2) = 0.01 of its standard error
 * and lowered chi2 by less than FIT_CREEP_CHI2 chi2/dof (or the looser
 * chi2_step of a profile refit): a creep along a kink of the cost, where
 * the Gauss-Newton test need not pass and the trust region shrinks step by
 * step (paper-offsets, 1% noise: 33 -> 28 iterations per fit at 1e-4
 * instead of 1e-6, the same errors and interval coverage). */
#define FIT_INFO_CREEP 4
#define FIT_CREEP_CHI2 1e-4
/* A second start whose iteration comes within FIT_SAME_SE standard errors
 * of the first (converged) solution in every parameter, at a cost within
 * FIT_SAME_COST of the first's (half chi2: below it by more, the start has
 * found a lower minimum), has found its basin again and stops there (the
 * first is kept; stop code FIT_INFO_BASIN). */
#define FIT_INFO_BASIN 5
/* A fit that ran away (an offset far outside its curve's data) reports no
 * material parameter whose correlation with that offset reaches
 * FIT_RAN_CORR in size: it moved with the offset, and where the offset
 * stopped is arbitrary (its conditional sd given the offset is under a
 * seventh of its sd).  Parameters the offset does not carry keep the
 * values, and intervals, where the fit stopped. */
#define FIT_RAN_CORR 0.99
#define FIT_SAME_SE 0.2
#define FIT_SAME_COST 0.5
/* A stop with no progress is a minimum when every scaled gradient
 * component is below FIT_GRAD_ROUNDING |J_k| |r| (rounding level)... */
#define FIT_GRAD_ROUNDING 1e-8
/* ... or when no coordinate step of these sizes (internal units) lowers
 * the cost by more than FIT_DESCENT_REL of itself. */
#define FIT_DESCENT_STEPS { 1e-4, 1e-6, 1e-8 }
#define FIT_DESCENT_REL 1e-12
/* A stall where a coordinate step still lowers the cost takes the best such
 * step and solves on, at most FIT_NUDGES times (iterate.c). */
#define FIT_NUDGES 10
/* A Jacobian column below FIT_DEAD_COLUMN of the largest belongs to a
 * parameter that no longer changes the fit (internal coordinates are all
 * of order one). */
#define FIT_DEAD_COLUMN 1e-12
/* Contact-edge scan: at most FIT_MAX_SCANS rounds, each trying the edge
 * between pairs of neighbouring points outwards either side, until
 * FIT_SCAN_PATIENCE in a row have not beaten the best, FIT_SCAN_HALF at
 * most. */
#define FIT_MAX_SCANS 4
#define FIT_SCAN_HALF 8
#define FIT_SCAN_PATIENCE 3
/* Robust reweighting: at most FIT_MAX_REWEIGHT rounds, until no weight's
 * square root moves by more than FIT_REWEIGHT_TOL. */
#define FIT_MAX_REWEIGHT 50
#define FIT_REWEIGHT_TOL 1e-4
/* A second start wins when converged like the first and its cost is lower
 * by FIT_SECOND_WIN_REL; a converged run beats an unconverged one within
 * FIT_SECOND_TIE_REL; an unconverged one needs FIT_SECOND_CLEAR_REL. */
#define FIT_SECOND_WIN_REL 1e-9
#define FIT_SECOND_TIE_REL 1e-6
#define FIT_SECOND_CLEAR_REL 1e-4
/* The guess's runner-up w is a second start when its cost is within
 * FIT_ALT_COST_RATIO of the best's and it differs by more than
 * FIT_ALT_LOG_SEP in ln w. */
#define FIT_ALT_COST_RATIO 3.0
#define FIT_ALT_LOG_SEP 0.1
/* A second start from FIT_EDGE_W_UP times the w found, when a curve with a
 * free contact point has fewer than FIT_EDGE_FEW_OUT points (but some) out
 * of contact (second_start.c). */
#define FIT_EDGE_FEW_OUT 8
#define FIT_EDGE_W_UP 3.0

#define GUESS_GRID 12          /* uniform nodes of a profile search */
#define GUESS_NODES (GUESS_GRID + 1)
#define GUESS_NSUB 64          /* points of a curve's subsample in the guess */

/* What the first stage of the guess learned from one curve alone. */
typedef struct {
    double M, c, z0, F0;
    int sees_w;     /* 0 for k = 2 with free z0 and F0 and no baseline */
} curve_guess;

/* A curve's subsample for the guess's profiles (guess.c), taken once at
 * alloc: up to GUESS_NSUB points in order of depth, the basis's constant K
 * and the sums of y^2 and y, y = F - held (the held F0, or 0). */
typedef struct {
    double *z, *F;
    size_t n;
    double K, held, yy, sy;
} guess_sub;

/* One curve inside the fit: its data and layout (fixed at alloc), then the
 * offsets of the origin. */
typedef struct {
    lf_fit_curve data;
    lf_model *model;
    size_t row;          /* first residual row */
    double L, Fs;        /* depth span (m) and largest |force| (N) */
    double zlo, zhi;     /* the data's shallowest and deepest depth, m */
    double flo, fhi;     /* the data's smallest and largest force, N */
    double eps;          /* derivative guard width at detachment, m */
    double sigma;        /* noise sd, N: at least quantum / sqrt(12) */
    double quantum;      /* the force's quantization step, N (0: none) */
    int iz0, iF0, islope;   /* index in x, or -1 when held */
    double z0, F0, slope;   /* held values or the origin's (physical) */
    guess_sub sub;
    curve_guess guess;
} fit_curve;

/* Where a solve begins, as lf_fit_guess found it.  The origin of the fit is
 * set at mat (with every curve's offsets profiled there). */
typedef struct {
    lf_material mat;       /* the start: the automatic guess, with the
                              settings' guesses where given */
    lf_material automatic; /* the automatic guess alone */
    int user;              /* 1: a settings guess replaced part of it */
    double alt_w;          /* the guess's runner-up w, a second start, or NaN */
} fit_start;

/* block.c: the normal matrix of a joint fit in block form (an arrowhead:
 * the material's m x m head, each curve's q x m coupling and q x q block,
 * zeros between curves), its Cholesky factor and its inverse, each in
 * O(ncurves) numbers and time.  The material's parameters are the first m
 * of x, curve j's own the q[j] from at[j]. */
#define FIT_QMAX 3                      /* a curve's own: z0, F0, slope */
#define FIT_MMAX (FIT_NMAT + 1)         /* w, E*, nu, + nu's column of the
                                           judgement (judge.c) */
#define FIT_CB (FIT_QMAX * FIT_MMAX + FIT_QMAX * FIT_QMAX)  /* a curve's C, B */
#define FIT_CF (FIT_QMAX * FIT_QMAX + FIT_QMAX * FIT_MMAX)  /* its L, E */
typedef struct {
    size_t m, n, p;         /* head, curves, all parameters */
    unsigned char *q;       /* n: each curve's own parameters */
    size_t *at;             /* n: the index of its first */
    double head[FIT_MMAX * FIT_MMAX];   /* H, full, stride FIT_MMAX */
    double *cb;             /* n x FIT_CB: C (stride FIT_MMAX), B (full,
                               stride FIT_QMAX) */
} fit_arrow;
typedef struct {
    size_t m, n, p;
    const unsigned char *q; /* the arrow's */
    const size_t *at;
    double ls[FIT_MMAX * FIT_MMAX];     /* Cholesky of the Schur complement */
    double *cf;             /* n x FIT_CF: L_j, then E_j = L_j^-1 C_j */
    int ok;                 /* the last lf_arrow_factor succeeded */
} fit_arrow_chol;
/* The inverse block by block: head S^-1 (S the Schur complement); per
 * curve F = B^-1 C in C's place and B^-1 in B's (the inverse's coupling
 * is -F S^-1, its block B^-1 + F S^-1 F^T, and between curves j, k
 * F_j S^-1 F_k^T). */
typedef struct {
    size_t m, n, p;
    unsigned char *q;
    size_t *at;
    double head[FIT_MMAX * FIT_MMAX];
    double *cb;
} fit_arrow_inv;
int lf_arrow_alloc(fit_arrow *a, size_t m, size_t n, const unsigned char *q);
int lf_arrow_copy_layout(fit_arrow *dst, const fit_arrow *src);
void lf_arrow_free(fit_arrow *a);
void lf_arrow_zero(fit_arrow *a);
void lf_arrow_copy(fit_arrow *dst, const fit_arrow *src);
/* Add v at (r, c) and (c, r) (global indices; j: a hint of the curve
 * whose parameter one of them is); entries outside the pattern are
 * ignored.  lf_arrow_get reads one. */
void lf_arrow_add(fit_arrow *a, size_t j, size_t r, size_t c, double v);
double lf_arrow_get(const fit_arrow *a, size_t r, size_t c);
void lf_arrow_diag(const fit_arrow *a, double *d);
/* Entry (r, c) times s[r] s[c]. */
void lf_arrow_scale(fit_arrow *a, const double *s);
/* The dense p x p matrix (row-major, both triangles). */
void lf_arrow_dense(const fit_arrow *a, double *G);
/* y = A x. */
void lf_arrow_mul(const fit_arrow *a, const double *x, double *y);
int lf_arrow_chol_alloc(fit_arrow_chol *L, const fit_arrow *a);
void lf_arrow_chol_free(fit_arrow_chol *L);
/* Factor A + mu diag(d2) (d2 NULL: A); 0 when a pivot is not positive or
 * not above rel times its diagonal (not positive definite). */
int lf_arrow_factor(fit_arrow_chol *L, const fit_arrow *a, const double *d2, double mu,
                    double rel);
/* x = A^-1 b (x may be b); |L^-1 b|^2 = b^T A^-1 b, with y (p) scratch;
 * the diagonal of A^-1. */
void lf_arrow_solve(const fit_arrow_chol *L, const double *b, double *x);
double lf_arrow_norm2(const fit_arrow_chol *L, const double *b, double *y);
void lf_arrow_inv_diag(const fit_arrow_chol *L, double *d);
int lf_arrow_inv_make(fit_arrow_inv *V, const fit_arrow_chol *L);
/* Its blocks' room, zeroed, for a layout given (then filled by hand). */
int lf_arrow_inv_alloc(fit_arrow_inv *V, size_t m, size_t n, const unsigned char *q,
                       const size_t *at, size_t p);
/* out = V v (out not v). */
void lf_arrow_inv_apply(const fit_arrow_inv *V, const double *v, double *out);
void lf_arrow_inv_free(fit_arrow_inv *V);
/* Entry (a, b) of the inverse (NaN out of range). */
double lf_arrow_inv_get(const fit_arrow_inv *V, size_t a, size_t b);
/* The Euclidean norm of column k of A (rows r0..n-1, stride tda), safe
 * from over- and underflow; Householder QR of the n x p matrix A (n >= p)
 * in place, stored as LAPACK and GSL store it. */
double lf_fit_column_norm(const double *A, size_t tda, size_t r0, size_t n, size_t k);
void lf_fit_householder_qr(double *A, size_t tda, size_t n, size_t p, double *tau);

/* Levenberg-Marquardt's own state (lm.c), for the "lm" method with the
 * analytic Jacobian. */
#define FIT_LM_MU0 1e-3        /* initial damping over the largest scaled diagonal */
#define FIT_LM_MAX_REJECT 15   /* rejected steps in a row that mean no progress */
#define FIT_LM_MAX_LOG_STEP 2.3 /* the most a trial step moves ln w or ln E* (a factor 10) */
typedef struct {
    gsl_vector *x, *r;      /* np, nres: the current point */
    gsl_vector *xt, *rt;    /* np, nres: the trial point (the previous one
                               after an accepted step) */
    gsl_vector *h;          /* np: the step */
    fit_arrow A;            /* J^T J (block.c) */
    fit_arrow_chol L;       /* the damped matrix's Cholesky factor */
    double *Ah;             /* np: scratch */
    double *g, *D2;         /* np: J^T r, squared scaling */
    double *colmax;         /* np: max |J_ik| of each column at x */
    double cost, cost_prev, mu, nu;
    double mu_first;        /* the damping of the first accepted step (NaN:
                               none yet) */
    size_t niter, nevalf, nevaldf;
} fit_lm;

/* Scratch, sized once at alloc (one block, layout.c): nothing allocates
 * inside a run. */
typedef struct {
    lf_eval *ev;         /* ndata: model at the last residual evaluation */
    lf_eval *scan_ev;    /* the longest curve's n: scratch of the contact-point scan */
    double *sqrtw;       /* ndata: square roots of the robust loss's point
                            weights (1 for least squares) */
    double *delta;       /* ndata: indentations */
    double *roots;       /* each curve's lf_model_eval_roots buffer
                            (lf_fit_roots) */
    double *xcache;      /* np: the x of ev[]; xcache_ok when valid */
    int xcache_ok;
    double *work;        /* max(3 ndata, 2 GUESS_NSUB): scratch */
    double *zsort;       /* ndata: each curve's depths in order of depth
                            (f->order), for the noise estimates */
    double *sub;         /* 2 GUESS_NSUB ncurves: the curves' subsamples */
    double *node;        /* GUESS_NSUB + GUESS_NODES: a profile's nodes */
    gsl_vector *x, *r;   /* np, nres: a solution and its residuals */
    gsl_vector *x2, *r2; /* np, nres: a trial point and its residuals */
    gsl_vector *x0;      /* np: where an iteration started */
    double *keep;        /* 3 ncurves: offsets kept aside by a second start */
    double *off;         /* 4 ncurves: the guess's offsets (a trial's, the best's) */
    double *noise_e;     /* ndata: each curve's residuals in force where its noise
                            was last estimated (lf_fit_curve_noise) */
    double *noise_s1;    /* 2 ncurves: 1 when noise_e holds curve j's, and its
                            point-to-point noise sd there (noise.c) */
    fit_arrow_chol jchol;   /* the Cholesky factor of J^T J where the solver
                               last examined it (iterate.c) */
    fit_arrow gsl_jtj;   /* J^T J of GSL's Jacobian (iterate.c) */
    double *grad, *colmax;  /* np: J^T r and column maxima */
    double *ainv;        /* np: the diagonal of (J^T J)^-1 */
    double *gn_x;        /* np: where the solver last examined its Jacobian */
    double gn_dchi2, gn_chi2;  /* there: the Gauss-Newton decrease, chi2 */
    int gn_ok;           /* 1: gn_* hold for the current weights and origin */
    /* a second start's stop in the first solution's basin (second_start.c) */
    double *basin_x;     /* np: the first solution, internal coordinates */
    double *basin_tol;   /* np: FIT_SAME_SE of its standard errors */
    double basin_cost;   /* its cost */
    int basin_on, basin_hit;
    double cost_hist[FIT_FLAT_ITERS + 1]; /* cost after each iteration, cyclic */
    fit_lm lm;
    int own;             /* 1: lm.c holds the solver's state, 0: GSL */
    double *block;       /* one allocation holding every number above */
    gsl_vector vectors[10];  /* the views x, r, ... into block */
} fit_work;

/* A run's running totals and its verdict. */
typedef struct {
    size_t iters, evals;
    size_t reweightings;    /* robust reweighting rounds (reweight.c) */
    int converged;
    lf_fit_stop stop;       /* LF_STOP_CONVERGED when converged */
    int user_test;          /* converged by the settings' own step or
                               gradient test (xtol, gtol) */
    int ran_col;            /* LF_STOP_RAN_AWAY: the offset's column */
    char why[160];
} fit_run;

/* Set run's verdict: converged when stop is LF_STOP_CONVERGED, and its
 * words (iterate.c). */
void lf_fit_run_says(fit_run *run, lf_fit_stop stop, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* result.c: the result's arrays sized from f's layout (r zeroed first by
 * the caller; LF_ENOMEM, r then half-built: lf_fit_result_free it). */
int lf_fit_result_alloc(const lf_fit *f, lf_fit_result *r);
/* Mark e not determined, for a reason in words (static; NULL: the
 * identifiability notes give it): no value, interval or bound. */
void lf_fit_estimate_drop(lf_fit_estimate *e, const char *why);
/* Every curve's pull-off follows w: determined exactly when w is (after
 * anything that changes w's verdict). */
void lf_fit_pulloff_follows(lf_fit_result *r);
/* nr, a refit of res's curves with the models res's choice gave them,
 * takes what that choice said (model_rounds, thin, each curve's reason
 * and thin bias), the single-curve fits and heterogeneity, and adds res's
 * iterations and evaluations to its own. */
void lf_fit_keep_choice(lf_fit_result *nr, const lf_fit_result *res);
/* The words of what the data determine follow the intervals: the bound
 * of w said in them is the estimate's (its ci95[1]), and where w is no
 * longer bounded from above only, they no longer say it is. */
void lf_fit_bound_words(lf_fit_result *r);
/* Take the verdict (converged, stop, user_test, why) of another run. */
void lf_fit_run_verdict_from(fit_run *run, const fit_run *from);

/* gsl_block.c's scratch for a Jacobian by differences (made with GSL's
 * workspace): the residuals at x and at a step (nres each), a curve's
 * indentations and evaluations (the longest curve's n). */
typedef struct {
    double *r0, *r1, *delta;
    lf_eval *ev;
} fit_fd;

struct lf_fit {
    lf_fit_settings set;    /* copied at alloc, never changed */
    /* the problem's layout, fixed at alloc */
    size_t ncurves;
    fit_curve *c;
    size_t ndata;        /* data rows */
    size_t nres;         /* + 1 prior row when nu has a prior */
    size_t np;           /* free parameters */
    int imat[FIT_NMAT];  /* index in x of ln w, ln E*, u, or -1 */
    int nu_prior;        /* 1 when a prior row is present */
    int nu_determinable; /* the plan alone determines nu */
    double chi2_step;    /* the solve's precision in chi2/dof: FIT_CHI2_STEP,
                            or a profile point's coarser one (profile.c) */
    double stop_above;   /* > 0: the solve ends, not converged, where the
                            Gauss-Newton step's chi2 stays above this
                            (hold.c's k = 2 check asks only whether chi2
                            ends far below it) */
    int stopped_above;   /* the last iterate.c run ended so */
    double mu0;          /* lm.c's first damping (in units of the scaled
                            diagonal): FIT_LM_MU0, or where a profile's last
                            refit took its first step (profile.c) */
    int k2_waits;        /* the assessment leaves out the k = 2 check's refit,
                            taking w as not open above, and sets k2_waited
                            where it would have made it (loo.c) */
    int k2_waited;
    int start_by_model;  /* the start's offsets from the model's force law
                            (guess_model.c), not the thin profile */
    int any_bonded, any_frictionless;
    size_t *order;       /* ndata: each curve's points by depth (ties in
                            file order), indices within the curve */
    /* the origin: x = 1 stands for mat and each curve's z0, F0, slope */
    lf_material mat;
    double *x0_internal; /* np: internal coordinates at the origin */
    fit_work ws;         /* the workspace (scratch sized at alloc) */
    /* the solver */
    const gsl_multifit_nlinear_trs *trs;
    gsl_multifit_nlinear_parameters gsl_par;
    gsl_multifit_nlinear_workspace *gsl;   /* NULL until lf_fit_gsl */
    gsl_multifit_nlinear_fdf fdf;
    fit_fd fd;
};

/* layout.c: GSL's workspace, made on first use (the "lm" method with the
 * analytic Jacobian may never need it); LF_ENOMEM when it cannot be. */
int lf_fit_gsl(lf_fit *f);

/* gsl_block.c: GSL's trust region in the block form of a joint fit, with
 * GSL's numbers.  lf_fit_scale_more: GSL's "more" scaling, column norms
 * over the rows not zero.  lf_fit_solver_normal: GSL's "cholesky" linear
 * solver with J^T J summed where the columns are not zero
 * (lf_fit_jtj_lower: the lower triangle of J^T J into C as gsl_blas_dsyrk
 * gives it; lo, hi: p each, scratch).  lf_fit_jacobian_fd: GSL's forward-difference
 * Jacobian, a curve's own column evaluating that curve alone;
 * lf_fit_block_fd: it, where it gives GSL's bits (forward differences, no
 * curve on the exact model), else NULL (GSL's own).  Its scratch made and
 * freed by lf_fit_fd_alloc and lf_fit_fd_free. */
typedef int (*fit_df)(const gsl_vector *x, void *params, gsl_matrix *J);
extern const gsl_multifit_nlinear_solver *const lf_fit_solver_normal;
extern const gsl_multifit_nlinear_scale *const lf_fit_scale_more;
int lf_fit_jtj_lower(const gsl_matrix *J, gsl_matrix *C, size_t *lo, size_t *hi);
int lf_fit_jacobian_fd(const gsl_vector *x, void *params, gsl_matrix *J);
fit_df lf_fit_block_fd(const lf_fit *f);
int lf_fit_fd_alloc(lf_fit *f);
void lf_fit_fd_free(lf_fit *f);

/* problem.c: the parameter mapping, residuals and Jacobian */
int lf_fit_problem_setup(lf_fit *f, lf_error *err);
/* lf_fit_alloc, with what the layout derives from a curve's points alone
 * (its depth order, noise and quantum) taken from like (NULL: none) for
 * each curve that like also holds, with the same depth and force arrays
 * at any index (layout.c): the same fit, without sorting again. */
lf_fit *lf_fit_alloc_like(const lf_fit_settings *settings, size_t ncurves,
                          const lf_fit_curve *curves, const lf_fit *like, lf_error *err);
/* Map x to the material and per-curve offsets. */
void lf_fit_unpack(const lf_fit *f, const double *x, lf_material *mat,
                double *z0, double *F0, double *slope, size_t j);
/* Put the origin (f->mat, f->c[j].z0/F0/slope) into internal coordinates. */
void lf_fit_set_origin(lf_fit *f);
/* Make the point x the origin: material and offsets into f, x = 1. */
void lf_fit_rebase(lf_fit *f, gsl_vector *x);
/* The model at every point at x into f->ws.ev (kept while x does not
 * change); LF_ENUMERIC when it cannot be evaluated. */
int lf_fit_eval_at(lf_fit *f, const double *x);
/* Curve j's buffer of lf_model_eval_roots in f->ws.roots: the roots of its
 * last evaluation start the next (the fit evaluates the same depths again
 * and again, with parameters that move little). */
double *lf_fit_roots(lf_fit *f, size_t j);
int lf_fit_residuals(const gsl_vector *x, void *params, gsl_vector *r);
/* lf_fit_residuals with their sum of squares, summed in row order (the
 * bits of a separate sum over r). */
int lf_fit_residuals_ss(lf_fit *f, const gsl_vector *x, gsl_vector *r, double *ss);
int lf_fit_jacobian(const gsl_vector *x, void *params, gsl_matrix *J);
/* Curve j's residual rows at x into r (its n_j rows), its model evaluated
 * into delta and ev (n_j each) without the roots of its last evaluation:
 * lf_fit_residuals' rows of curve j, bit for bit, for a model other than
 * the exact one.  delta and ev NULL: the model's evaluation in f's cache
 * (lf_fit_eval_at), which x must share but for curve j's F0 and slope.
 * GSL_EDOM as lf_fit_residuals. */
int lf_fit_curve_residuals(lf_fit *f, const double *x, size_t j, double *delta, lf_eval *ev,
                           double *r);
/* The free force offsets (and slopes) of x moved to their least-squares
 * values for the residuals r at x, x and r updated (variable projection);
 * 0 when there are none (r untouched). */
int lf_fit_project_offsets(lf_fit *f, double *x, double *r);
/* The normal equations of the internal coordinates at x, curve by curve
 * from the model's evaluations (a curve's rows touch only the material's
 * columns and its own offsets'), J never formed: A = J^T J (lower
 * triangle), g = J^T r for the residuals r at x, colmax = max |J_ik| per
 * column.  GSL_EDOM when the model cannot be evaluated. */
int lf_fit_normal_sums(lf_fit *f, const double *x, const double *r, fit_arrow *A, double *g,
                       double *colmax);
/* The same from a Jacobian J (nres x np) and residuals r at hand (GSL's). */
void lf_fit_normal_of_jacobian(const lf_fit *f, const gsl_matrix *J, const double *r,
                               fit_arrow *A, double *g, double *colmax);
/* Cholesky of the n x n matrix M (stride s, lower triangle read) into L
 * (stride s); 0 unless every pivot exceeds 0 and rel times diag[k] (NULL:
 * M's diagonal).  lf_small_chol_solve: y = (L L^T)^-1 y. */
int lf_small_chol(const double *M, size_t s, size_t n, double rel, const double *diag, double *L);
void lf_small_chol_solve(const double *L, size_t s, size_t n, double *y);
/* The arrow of f's layout (lf_arrow_alloc with f's material count, plus
 * extra columns of the material's, and each curve's own). */
int lf_fit_arrow_alloc(const lf_fit *f, size_t extra, fit_arrow *A);
/* Jacobian with respect to the physical coordinates, rows weighted. */
int lf_fit_jacobian_physical(lf_fit *f, const double *x, gsl_matrix *J);
/* The same with one more column (J: nres x (np + 1)): dP/dnu of every row,
 * weighted, as if nu were free while it is held (the judgement of E* apart
 * from nu, judge.c). */
int lf_fit_jacobian_physical_nu(lf_fit *f, const double *x, gsl_matrix *J);
/* Curve j's rows of the weighted physical Jacobian at x into rows
 * (n_j x ncol, row-major): the material's free columns (with_nu: then
 * dP/dnu, as if nu were free), then the curve's own; *mcols the material's
 * count (with nu's).  Of its model, or (model not NULL) of that one,
 * evaluated into ev (n_j) at the same indentations.  GSL_EDOM when the
 * model cannot be evaluated. */
int lf_fit_curve_rows(lf_fit *f, const double *x, size_t j, lf_model *model, lf_eval *ev,
                      int with_nu, double *rows, size_t *mcols);
/* The nu prior's row's one entry (in nu's column; 0 without a prior). */
double lf_fit_prior_entry(const lf_fit *f, const double *x, int physical);
/* c[k] = the internal Jacobian's column k over the physical one at x (each
 * internal coordinate's d(physical)/d(internal): w, E*, dnu/du, L, Fs,
 * Fs/L; all > 0). */
void lf_fit_internal_scale(const lf_fit *f, const double *x, double *c);
/* Half the sum of squared residuals at x (into r); HUGE_VAL if not computable. */
double lf_fit_cost(lf_fit *f, const gsl_vector *x, gsl_vector *r);
double lf_fit_nu_of_u(double u);
double lf_fit_u_of_nu(double nu);
double lf_fit_dnu_du(double u);

/* guess.c: the automatic start.  Fills *start and sets the origin there. */
int lf_fit_guess(lf_fit *f, fit_start *start, lf_error *err);
/* Profile every curve's offsets at f->mat and make that the origin. */
void lf_fit_guess_offsets(lf_fit *f);
/* The median of v[0..n-1], n > 0 (v reordered), in linear time (guess.c). */
double lf_fit_median(double *v, size_t n);
double lf_fit_select_kth(double *v, size_t n, size_t k);
/* The median of sqrt(v[i]), v[i] >= 0 (v reordered), rooting only the middle. */
double lf_fit_median_sqrt(double *v, size_t n);
/* Weights, origin or model changed: what was computed at an x is stale. */
void lf_fit_invalidate(lf_fit *f);
/* Curve j's model object was replaced: its evaluations at the cached x
 * made again (the others' stay), the solver's look at J^T J dropped. */
void lf_fit_model_changed(lf_fit *f, size_t j);
/* guess_model.c: the start of a model with no thickness (half-space) from
 * its own force law: 1 when every curve's model is such a model; the
 * material (0 when no curve gives one); the offsets at f->mat. */
int lf_fit_guess_by_model(const lf_fit *f);
int lf_fit_guess_model(lf_fit *f);
void lf_fit_guess_model_offsets(lf_fit *f);
/* guess_shape.c: the start of half-space curve j from its shape alone
 * (every point in contact; zpo: the depth of its least force): the
 * material (scale and w/E* searched) or the offsets at material m, with
 * the residual sum of squares on its guess subsample, HUGE_VAL when none
 * fits. */
double lf_fit_shape_material(lf_fit *f, size_t j, double nu, double zpo, lf_material *out);
double lf_fit_shape_offsets(lf_fit *f, size_t j, const lf_material *m, double zpo, double *z0,
                            double *F0);
/* For exact-model curves: keep the thin profile's start (the curves'
 * offsets are the thin profile's at f->mat, the caller's part) or the
 * model's, whichever costs less (sets f->start_by_model). */
void lf_fit_guess_compare_model(lf_fit *f);
/* Curve j's subsample for the guess's profiles (c->sub), taken once the
 * depth order is known. */
void lf_fit_guess_subsample(lf_fit *f, size_t j);
/* Noise sd of a curve from how far each point's force lies from the line
 * through its neighbours in depth (order: indices by depth; fbig: the
 * largest |force|; work: 3 n). */
double lf_fit_noise_sigma(const double *depth, const double *force, const size_t *order,
                          size_t n, double fbig, double *work);
/* The step of a quantized force signal, or 0 (noise.c; work holds n,
 * start n + 1). */
double lf_fit_quantum(const double *force, size_t n, double fbig, double *work, size_t *start);

/* iterate.c: the trust-region iteration from x (overwritten with where it
 * stopped) and its stopping rules; adds to run's totals and sets its
 * verdict.  after_scan: x is a converged solution moved by a policy (the
 * contact-edge scan, a reweighting), which sits at a kink of the cost. */
int lf_fit_iterate(lf_fit *f, gsl_vector *x, int after_scan, fit_run *run, lf_error *err);

/* lm.c: init at x (residuals, Jacobian, scaling, damping); one accepted
 * step (GSL_SUCCESS) or GSL_ENOPROG; GSL's step and gradient tests on the
 * step just taken. */
int lf_fit_lm_init(lf_fit *f, const gsl_vector *x);
int lf_fit_lm_iterate(lf_fit *f);
int lf_fit_lm_test(const lf_fit *f, double xtol, double gtol, int *info);

/* Policies, each run only when the data call for it. */
/* edge_scan.c: solve from the origin (x = 1), then move each free contact
 * point across neighbouring data points and solve again while that lowers
 * the cost. */
int lf_fit_solve_scanned(lf_fit *f, gsl_vector *x, int from_origin, fit_run *run, lf_error *err);
/* The scan's cost of curve j at x with its contact point moved to z0 (its
 * force offset re-solved when free): by evaluating the model at every
 * point (interpolate = 0), or from the evaluations at x with the model
 * only near the edge (1, as the scan does for a model dearer than the
 * thin layer's).  For tests. */
double lf_fit_scan_cost(lf_fit *f, size_t j, const gsl_vector *x, double z0, int interpolate);
/* second_start.c: solve again from material `from` (offsets profiled) and
 * keep the lower-cost of that and the solution at x; *ratio > 1 when the
 * new start won (the loser's cost over the winner's), else 1. */
/* 1 when a curve with a free contact point has between 1 and
 * FIT_EDGE_FEW_OUT - 1 points out of contact at x: a minimum that a start
 * from a higher w may beat. */
int lf_fit_edge_doubt(lf_fit *f, const gsl_vector *x);
int lf_fit_second_start(lf_fit *f, gsl_vector *x, const lf_material *from, fit_run *run,
                     double *ratio, lf_error *err);
/* reweight.c: a robust loss by iteratively reweighted least squares from
 * the solution at x. */
int lf_fit_reweight(lf_fit *f, gsl_vector *x, fit_run *run, lf_error *err);
/* loo.c: when every one of three or more curves disagrees with the joint
 * fit, refit without each in turn and name the culprit in res's warnings. */
void lf_fit_leave_one_out(lf_fit *f, lf_fit_result *res);
/* 1 when res calls for it: three or more curves, every one disagreeing */
int lf_fit_loo_due(const lf_fit_result *res);
/* Leave-one-out made later than the assessment (descend.c: only for the
 * point finally reported): of the curves cc[0..n-1] (each with its fitted
 * model) under s, its words inserted at res->warnings' index at, where
 * lf_fit_solve_end_at said they belong; like (NULL: none), a fit of
 * these curves, lends its layout to the first refit's fit. */
void lf_fit_leave_one_out_at(const lf_fit_settings *s, size_t n, const lf_fit_curve *cc,
                             lf_fit_result *res, size_t at, const lf_fit *like);
#define FIT_LOO_NONE ((size_t) -1)

/* descend.c's walk: multiples of the standard error either side */
#define FIT_WALK_N 18
/* hold.c: the points of a profile (profile.c).  A profile of parameter
 * `which` around the fit `best` of the curves cc (each with its fitted
 * model) under settings s: */
typedef struct {
    const lf_fit_settings *s;
    size_t nc;
    lf_fit_curve *cc;          /* the curves, each with its fitted model */
    const lf_fit_result *best;
    int which;                 /* FIT_W, FIT_E, FIT_NU */
    int linear;                /* searched in the parameter itself, not its log */
    int mode;                  /* LF_PROFILE_CHECK, _ALWAYS or _SCREEN */
    int calibrate;             /* LF_PROFILE_CALIBRATE was asked */
    double thr;                /* the threshold of the rise, s^2 F(1, n_eff - p) */
    double stop_above;         /* its refits' stop_above (0: none) */
    const lf_fit *like;        /* a fit of these curves whose layout a refit's
                                  takes (lf_fit_alloc_like; NULL: none) */
    double mu0;                /* the damping at which this profile's last
                                  refit took its first step (NaN: none) */
    size_t fits;
    /* the lowest profile point below the best fit's chi2, if any: the best
     * fit was then not the global minimum (refit_from_lower) */
    double lower_chi2;
    lf_material lower_mat;
    double *lower_off;         /* 3 ncurves: z0, F0, slope */
    /* chi2 along the material parameters' linear paths (descend.c), kept
     * for the screen of profile.c: evaluated with `walker` (a fit of the
     * curves made on first use, freed by lf_fit_profile), the last walk
     * at FIT_WALK_N points about the result as it was after `moves` */
    lf_fit *walker;
    size_t moves;              /* results replaced (lf_fit_refit_lower) */
    size_t loo_at;             /* the result replaced last awaits its
                                  leave-one-out, its words at this index
                                  (lf_fit_refit_settle); loo_due 0: none */
    int loo_due;
    size_t walk_stamp;         /* moves + 1 at the last walk, 0: none */
    int walk_ok[FIT_NMAT];
    double walk_chi2[FIT_NMAT][FIT_WALK_N];
    /* the last profile point's fit (hold.c), made again for the next point
     * of the same parameter, best fit and curves; freed by its owner */
    lf_fit *held;
    int held_which;
    const lf_fit_result *held_best;
    const lf_fit_curve *held_cc;
} fit_prof;
/* hetero.c: a curve estimate with nothing determined, of probe p. */
void lf_curve_estimate_none(lf_curve_estimate *e, const lf_probe *p);
/* descend.c: the minimum, always (see there).  chi2 at the points t[q]
 * (multiples of its standard error) of material parameter k's linear path
 * about res on p's curves, every other free parameter moved by its
 * regression on it (strict: a parameter without a covariance makes the
 * point NaN; else it stays); NaN where the path leaves the parameters'
 * domain.  With mat_low, the material and offsets (3 per curve) of the
 * lowest point into mat_low and off_low; returns 1 when there is one. */
int lf_fit_path_chi2(fit_prof *p, const lf_fit_result *res, int k, int strict, size_t nt,
                     const double *t, double *chi2, lf_material *mat_low, double *off_low);
/* The same (strict) for the screen of profile.c: the last walk's numbers
 * where it was made about res (p->best) at every t, else evaluated. */
void lf_fit_walk_chi2(fit_prof *p, int k, size_t nt, const double *t, double *chi2);
/* A fit of the curves cc solved from material mat and offsets off (3 per
 * curve, NaN: the held value or 0), everything free (lf_fit_solve; with
 * loo_at, leave-one-out left to the caller: lf_fit_solve_end_at). */
int lf_fit_refit_from(const lf_fit_settings *s, size_t nc, const lf_fit_curve *cc,
                      const lf_material *mat, const double *off, lf_fit_result *nr,
                      size_t *loo_at);
/* Refit from p's lower point (p->lower_*); where that ends lower than res
 * by FIT_PROFILE_LOWER of the threshold, it replaces res (the model
 * choice's notes and the single-curve fits kept, a warning naming `where`
 * and the parameter) and 1 is returned (2: it ended lower without
 * converging; res is then that fit, its intervals not yet set); 0: res
 * stands. */
int lf_fit_refit_lower(fit_prof *p, lf_fit_result *res, const char *where);
/* The leave-one-out the last replacement of res left waiting (p->loo_due):
 * called once res is final, before anything reads its curves' agreement. */
void lf_fit_refit_settle(fit_prof *p, lf_fit_result *res);
/* The search of descend.c about res (converged) on p's curves and
 * settings; 1 when it moved res. */
int lf_fit_descend(fit_prof *p, lf_fit_result *res);
/* lf_fit_profile of a result whose leave-one-out its assessment left
 * waiting (lf_fit_solve_end_at's loo_at; FIT_LOO_NONE: none): made on the
 * result finally reported, whether res or a lower point that replaced it;
 * like (NULL: none), a fit of these curves, lends its layout to the
 * profile's fits (lf_fit_alloc_like). */
int lf_fit_profile_at(const lf_fit_settings *settings, size_t ncurves, const lf_fit_curve *curves,
                      lf_fit_result *res, int always, size_t loo_at, const lf_fit *like,
                      lf_error *err);
/* a profile point lower than the best fit by this fraction of the
 * threshold means the best fit was not the global minimum */
#define FIT_PROFILE_LOWER 0.01
/* chi2 minus the best chi2 with parameter p->which held at v (NaN on a
 * failed fit); counts the fit in p->fits and keeps a point below the best
 * in p->lower_*. */
double lf_fit_hold_rise(fit_prof *p, double v);
/* The rise with p->which held at v as the refit's first Gauss-Newton step
 * from the linear path's point predicts it (one evaluation of the model
 * and Jacobian, no fit); the rise at that point into *start_rise. */
double lf_fit_hold_predict(fit_prof *p, double v, double *start_rise);
/* The 95% point of F(1, m), as Student's t at 0.975 squared. */
double lf_fit_f95(double m);
/* The threshold of a rise: s^2 F(1, n_eff - p) of the result r. */
double lf_fit_hold_threshold(const lf_fit_result *r);
/* The fitted value of r's parameter called name (the solution, even where
 * the report says "not determined"), else fallback. */
double lf_fit_best_value(const lf_fit_result *r, const char *name, double fallback);
/* 1 when chi2 with w held at factor times the solution's rises by less
 * than the threshold (the data do not bound w from above). */
int lf_fit_w_open_above(lf_fit *f, const lf_fit_result *r, double factor);
/* That rise (NaN where w is not fitted or not positive), its threshold in
 * *thr, the refit stopped where its Gauss-Newton step stays `stop`
 * thresholds above the best (0: in full; *stopped, when not NULL, says
 * whether it did). */
double lf_fit_w_rise_above(lf_fit *f, const lf_fit_result *r, double factor, double stop,
                           double *thr, int *stopped);

/* verdict.c: refuse a curve with no contact signal (LF_EDATA); at the end
 * of a solve, continue a stalled one, call a stall or offsets far outside
 * the data not converged, and a minimum within rounding converged. */
int lf_fit_refuse_degenerate(const lf_fit *f, lf_error *err);
int lf_fit_honest_end(lf_fit *f, gsl_vector *x, fit_run *run, lf_error *err);
/* A converged result where some material parameter is free and the data
 * determine none of them (nor M) is not converged ("degenerate"), with a
 * warning: run after the assessment and again after the profile. */
void lf_fit_degenerate_end(lf_fit_result *r);
/* iterate.c: 1 when the solver's last look at its Jacobian (gn_*, ainv) was
 * at x, under the current weights and origin. */
int lf_fit_gn_at(const lf_fit *f, const gsl_vector *x);

/* solve.c: the solve from the origin (with start: the automatic guess's
 * start and second starts; NULL: a warm start from the current origin) and
 * the restarts the data call for, without the assessment: the solution in
 * f->ws.x, the run's totals and verdict in *run (a profile point needs its
 * chi2 alone); warn (or NULL) takes the restarts' warnings. */
int lf_fit_solve_run(lf_fit *f, const fit_start *start, fit_run *run, lf_warnings *warn,
                     lf_error *err);
/* driver.c: lf_fit_solve_run, then lf_fit_assess and leave-one-out (three
 * or more curves all disagreeing); fills res as lf_fit_run does.  In two
 * steps for a caller that assesses only the better of two runs
 * (joint.c): _begin solves (res holds the run's warnings and totals; f
 * stays at the solution, whose chi2 lf_fit_residuals_ss gives), _end
 * assesses f at that solution and completes res.  lf_fit_run_begin is
 * lf_fit_run's start and _begin. */
int lf_fit_solve(lf_fit *f, const fit_start *start, lf_fit_result *res, lf_error *err);
int lf_fit_solve_begin(lf_fit *f, const fit_start *start, fit_run *run, lf_fit_result *res,
                       lf_error *err);
int lf_fit_solve_end(lf_fit *f, const fit_run *run, lf_fit_result *res, lf_error *err);
/* lf_fit_solve_end without leave-one-out: *loo_at is where its words go
 * in res->warnings when it is due (lf_fit_loo_due), else FIT_LOO_NONE;
 * the caller runs it (lf_fit_leave_one_out_at) if res is reported. */
int lf_fit_solve_end_at(lf_fit *f, const fit_run *run, lf_fit_result *res, size_t *loo_at,
                        lf_error *err);
int lf_fit_run_begin(lf_fit *f, fit_run *run, lf_fit_result *res, lf_error *err);

/* decomp_block.c: decomp.c's decomposition for many curves, from the
 * block structure (see its top): the scaled Gram, the columns' norms, the
 * largest and smallest singular values, the rank, the weights of the
 * undetermined directions and the pseudo-inverse over the determined ones. */
#define FIT_EIG (FIT_QMAX + FIT_QMAX * FIT_MMAX)    /* a curve's eigenvalues, W^T C */
typedef struct {
    size_t p, m, n;          /* parameters, material columns, curves */
    fit_arrow G;             /* the scaled Gram (its layout: q, at) */
    double *D;               /* p: the physical columns' norms */
    double s0, smin;         /* largest and smallest singular value of J D^-1 */
    size_t rank;
    double *lw;              /* p: weight in the curves' own undetermined
                                directions */
    size_t k;                /* undetermined directions through the material */
    double *V, *Y;           /* p x k each (vector l at l p): them, and X V */
    double Z[FIT_MMAX * FIT_MMAX];   /* V^T X V */
    fit_arrow_inv X;         /* the generalised inverse, block by block */
    double *eig;             /* n x FIT_EIG: each curve's spectrum (scratch) */
} fit_bdec;
/* A result's covariance in block form: the decomposition's pseudo-inverse
 * (its scratch released), s^2, and which rows stand (result.c). */
struct lf_fit_covariance {
    fit_bdec b;
    double scale;
    unsigned char *det;      /* p: 0 where the parameter is not determined */
};
/* Release the decomposition's scratch that the covariance does not need. */
void lf_fit_bdec_trim(fit_bdec *b);
/* Decompose at x (with_nu: dP/dnu as one more material column, nu held;
 * from_r: the rank from R even where the Gram would do, for tests);
 * LF_ENUMERIC when the model cannot be evaluated or the Jacobian is not
 * finite. */
int lf_fit_bdec_run(fit_bdec *b, lf_fit *f, const double *x, int with_nu, double rcond,
                    int from_r);
void lf_fit_bdec_free(fit_bdec *b);
double lf_fit_bdec_nullw(const fit_bdec *b, size_t k);
/* scale times the pseudo-inverse's (a, c) in physical units (NaN for a
 * column of zeros). */
double lf_fit_bdec_cov(const fit_bdec *b, size_t a, size_t c, double scale);
/* out = the pseudo-inverse of the scaled Gram times g (scaled
 * coordinates; work: p scratch). */
void lf_fit_bdec_pinv(const fit_bdec *b, const double *g, double *out, double *work);

/* decomp.c: the one decomposition of the column-scaled physical Jacobian
 * that the uncertainty and the model choice share:
 *     J D^-1 = Q R,  R = U S V^T,
 * D the column norms; rank counts singular values above rcond S_0. */
typedef struct {
    size_t n, p, rank;
    int block;           /* 1: the block form (blk) holds it, not these */
    fit_bdec blk;
    gsl_matrix *QR;      /* n x p: Householder QR of J D^-1 */
    gsl_vector *tau;     /* p */
    gsl_matrix *U, *V;   /* p x p */
    gsl_vector *S, *D;   /* p */
    gsl_vector *work;    /* p */
    gsl_vector *qtd;     /* n: scratch of lf_fit_decomp_project */
} fit_decomp;

int lf_fit_decomp_alloc(fit_decomp *d, size_t n, size_t p);
void lf_fit_decomp_free(fit_decomp *d);
/* Decompose the physical Jacobian of f at x. */
int lf_fit_decomp_run(fit_decomp *d, lf_fit *f, const double *x, double rcond);
/* The same S, V, D and rank from G = J^T J of the internal Jacobian (lower
 * triangle, p x p), c[k] the factor of internal column k over the physical
 * one (lf_fit_internal_scale), when every singular value of J D^-1 is above
 * FIT_DECOMP_NORMAL_COND S_0 and FIT_DECOMP_NORMAL_MARGIN rcond S_0 and no
 * diagonal of G is below FIT_DECOMP_NORMAL_TINY (underflow); else
 * LF_ENUMERIC (then lf_fit_decomp_run).  d from lf_fit_decomp_alloc, n = 0
 * allowed (no QR, no projection). */
#define FIT_DECOMP_NORMAL_COND 1e-4
#define FIT_DECOMP_NORMAL_MARGIN 1.01
#define FIT_DECOMP_NORMAL_TINY 1e-280  /* a diagonal of J^T J at most this: J's own */
int lf_fit_decomp_normal(fit_decomp *d, const double *G, const double *c, double rcond);
/* Decompose the n x p matrix d->QR holds, its columns scaled to unit norm
 * first (scale = 1; D their norms) or not (D = 1: the singular values are
 * the matrix's own). */
int lf_fit_decomp_factor(fit_decomp *d, double rcond, int scale);
/* Weight of parameter k in the undetermined directions (1 for a column of
 * zeros). */
double lf_fit_decomp_nullw(const fit_decomp *d, size_t k);
/* scale times the pseudo-inverse of J^T J over the determined directions
 * at (a, b), D^-1 V S^-2 V^T D^-1: the covariance of the columns'
 * parameters for a noise variance `scale` (NaN for a column of zeros). */
double lf_fit_decomp_cov(const fit_decomp *d, int a, int b, double scale);
/* coef[l] = (U_l . v) / S_l for l < rank, U the left singular vectors of
 * J D^-1 (v of length n). */
void lf_fit_decomp_project(fit_decomp *d, const double *v, double *coef);
/* The least-squares step of the scaled parameters that the residual change
 * v (length n) makes, pinv(J D^-1) v (not in the block form, which has no
 * rows: lf_fit_decomp_pinv of D^-1 J^T v there); coef: rank scratch. */
void lf_fit_decomp_step(fit_decomp *d, const double *v, double *coef, double *step);
/* out = pinv(D^-1 J^T J D^-1) g, the scaled coordinates' (work: p scratch). */
void lf_fit_decomp_pinv(const fit_decomp *d, const double *g, double *out, double *work);
/* The decomposition in block form (decomp_block.c) of f's Jacobian at x
 * (with_nu: with dP/dnu as a column after the material's). */
int lf_fit_decomp_block_run(fit_decomp *d, lf_fit *f, const double *x, int with_nu,
                            double rcond);
/* The smallest singular value over the largest; column k's norm D_k. */
double lf_fit_decomp_smin_ratio(const fit_decomp *d);
double lf_fit_decomp_norm(const fit_decomp *d, size_t k);
/* The weight in the undetermined directions of the combination sum_i
 * g[i] (parameter of column cols[i]) (g in the parameters' own units;
 * columns -1 skipped): 1 when it has no gradient. */
double lf_fit_decomp_combination_nullw(const fit_decomp *d, const int *cols, const double *g,
                                       size_t m);
/* Decompositions of more parameters than this take the block form, and
 * the result keeps its covariance in it (lf_fit_covariance). */
#define FIT_DENSE_P LF_FIT_DENSE_PARAMS

/* judge.c: what a set of curves determines and why, one judgement for a
 * fit at its solution (uncertainty.c) and a design at the truth
 * (design.c); the rules are at the top of judge.c. */
#define FIT_NULL_WEIGHT 0.01    /* more weight than this in the undetermined
                                   directions: not determined */
#define FIT_K2_MIN_OUT 3        /* k = 2: points out of contact a curve needs
                                   for its baseline to count */
#define FIT_K2_W_HIGH 4.0       /* k = 2: ln of the factor w is held higher
                                   by to see whether the data bound it */
#define FIT_K2_STOP_ABOVE 100.0 /* k = 2: that refit stops where the
                                   Gauss-Newton step's chi2 stays this many
                                   thresholds above the best (hold.c) */
/* The words of w bounded from above only, with the bound: the judgement's
 * at the solution, made again from the estimate's own interval once the
 * intervals are made (lf_fit_bound_words), so that a report states one
 * bound. */
#define FIT_W_BOUND_WORDS "adhesion below the noise: w < %.4g J/m^2 (95%%)"
#define FIT_W_BOUND_PREFIX "adhesion below the noise: w < "

/* What the judgement needs to know of one curve. */
typedef struct {
    char label[64];          /* how the words name it: "1", "2", ... (a fit)
                                or a candidate's name (a design) */
    double k;
    lf_base base;
    lf_branch branch;
    const lf_model_type *model;  /* the model in use */
    size_t n_out;            /* points out of contact (at the solution, or
                                at the truth) */
    int col_z0, col_F0, col_slope;  /* columns, -1 when held */
} judge_curve;

typedef struct {
    const fit_decomp *d;     /* of the free parameters' column-scaled
                                Jacobian at the solution (or the truth) */
    int col[FIT_NMAT];       /* columns of w, E*, nu; -1 when held */
    int held_by_user[FIT_NMAT];  /* held at a value the user gave */
    double w, w_se;          /* w there and its standard error */
    double nu;               /* nu there (held or fitted) */
    double M, M_se;          /* Z E* of the bonded curves there, its se */
    double dM[2];            /* dM / d(the parameter of E*'s column),
                                dM / dnu, in the columns' own units */
    size_t ncurves;
    const judge_curve *c;
    int ran_away;            /* a fit's solve ran away (LF_STOP_RAN_AWAY) */
    int ran_col, ran_force;  /* then the offset's column (-1: none) and
                                whether it is a force offset */
    /* measures the judgement asks for only where it needs them: */
    void *ctx;
    /* 1 when chi2 with w held e^FIT_K2_W_HIGH times higher rises by less
     * than its threshold: the data do not bound w from above (NULL: 0) */
    int (*w_open_above)(void *ctx);
    /* with nu's column added to the Jacobian (nu held by the fitter's
     * rule, not given): 1 when E* is still determined, with *dlnE_dnu how
     * ln E* moves with nu given the data (the regression, cov / var);
     * 0 when not (NULL: 0) */
    int (*E_with_nu)(void *ctx, double *dlnE_dnu);
} judge_in;

/* What bonded curves alone (nu neither given nor determined) say of E*. */
enum { FIT_BONDED_NONE = 0,   /* not that case */
       FIT_BONDED_ONLY_M,     /* thin: E* not determined, M is */
       FIT_BONDED_NOTHING,    /* thin: neither E* nor M */
       FIT_BONDED_E };        /* not thin: the data fix E* apart from nu */

typedef struct {
    int det[FIT_NMAT];       /* free and determined */
    int k2;                  /* k = 2: w not separable from the force offsets
                                (w and every F0 not determined) */
    int w_upper;             /* w below 2 se: bounded from above only, by */
    double w_bound;          /* w + 1.645 se */
    int M_free, M_det;       /* M among the results (bonded curves, E* or nu
                                free), and determined */
    const char *M_why;       /* M not determined where it was: why */
    int bonded;              /* FIT_BONDED_* */
    double dlnE_dnu;         /* FIT_BONDED_E: how ln E* moves with nu */
    const char *why[FIT_NMAT];  /* a reason in words (static) for one not
                                   determined that the words below do not
                                   give, or NULL */
} judge_out;

/* Judge, and append the words to `words` (what the data determine). */
void lf_judge(const judge_in *in, judge_out *out, lf_warnings *words);
/* 1 when column col (>= 0) is determined. */
int lf_judge_col_determined(const fit_decomp *d, int col);
/* The thin-layer model past its limit of b/a (at `where`) in the words of
 * lf_thin_scope, prefixed with "who: " when who is not NULL. */
void lf_judge_thin_strain(lf_warnings *w, const char *who, double ba, const char *where,
                          double limit);

/* The models of the auto choice, from the cheapest up; the rung of a
 * model is its scope's. */
enum { FIT_RUNG_THIN = 0, FIT_RUNG_HALFSPACE, FIT_RUNG_EXACT, FIT_NRUNG };
const lf_model_type *lf_fit_rung_type(int rung);
int lf_fit_rung_of(const lf_model_type *t);

/* A curve's model bias on w, E*, nu over their standard errors (0 where
 * not fitted or not determined); ok = 0 when not assessed. */
typedef struct {
    double r[FIT_NMAT];
    int ok;
} judge_bias;
/* The bias from step, the least-squares step of the scaled parameters
 * (lf_fit_decomp_step, _pinv) that the weighted force difference
 * d = (P_exact - P_model) / sigma makes, pinv(J D^-1) d (to first order the
 * estimate moves by (J^T J)^+ J^T d, one Gauss-Newton step), over the
 * standard errors. */
void lf_judge_bias(const fit_decomp *d, const int col[FIT_NMAT], const double *step,
                   double r[FIT_NMAT]);
double lf_judge_bias_max(const double r[FIT_NMAT], int *which);
/* One round of the auto model choice (lf_fit_choose_driver's rule): while
 * the summed bias of the curves' models exceeds tol standard errors, the
 * movable curve (not fixed, not exact, assessed) with the largest bias
 * moves up: to the half-space model when its own bias there (bias(ctx, j,
 * FIT_RUNG_HALFSPACE, &half[j]), asked for thin curves with k above the
 * model's limit when halfspace is set) is below tol and the thin one's,
 * else to the exact model; move(ctx, j, rung) makes it so.  cur[j] is the
 * bias of curve j's current model (zero for exact), kept up to date. */
typedef struct {
    size_t n;
    int *rung;
    const int *fixed;
    const double *k;
    judge_bias *cur, *half;
    double tol;
    int halfspace, allow_change;
    void *ctx;
    int (*bias)(void *ctx, size_t j, int rung, judge_bias *b);
    int (*move)(void *ctx, size_t j, int rung);
} judge_models;
int lf_judge_models(judge_models *jm, double *total_max, int *changed);
/* choose.c: 1 (the default): where every parameter is determined, each
 * curve's bias from the material's Schur complement with its share
 * swapped; 0: from a decomposition of its own (a check for tests). */
extern int lf_fit_choose_fast;
/* Why a curve has its model, in words. */
void lf_judge_model_reason(char *buf, size_t n, int rung, int fixed, const judge_bias *thin,
                           const judge_bias *half, double ab_lo, double ab_hi, double tol);

/* A residual r (weighted, over sigma) back in force units: r sigma / sqrtw,
 * with no division where the weight is 1 (least squares: every point),
 * where it would leave the product unchanged. */
static inline double
lf_fit_unweighted(double r, double sigma, double sqrtw)
{
    return sqrtw == 1.0 ? r * sigma : r * sigma / sqrtw;
}

/* noise.c: the integrated autocorrelation time of e[0..n-1] (1 for white
 * noise); the noise model of curve j at the residuals res (units of sigma):
 * from cr's corr_time and noise_sd (lf_fit_curve_noise at the same res) and
 * rms, which must be set, fills n_eff, chi2_per_point, runs_z, misfit_rel,
 * consistent, agreement; returns tau. */
double lf_fit_corr_time(const double *e, size_t n);
/* Curve j's correlation time (1: white) and noise sd at the residuals res. */
void lf_fit_curve_noise(const lf_fit *f, size_t j, const gsl_vector *res, double *tau,
                        double *noise);
double lf_fit_noise_model(const lf_fit *f, size_t j, const gsl_vector *res,
                          lf_fit_curve_result *cr);
/* The noise sd of squared departures work[0..cnt) (v reordered): the upper
 * median of their roots over 0.6745, NaN when cnt = 0; and whether it
 * exceeds thr, without reordering (a count, exact). */
double lf_fit_noise_of(double *work, size_t cnt);
int lf_fit_noise_above(const double *work, size_t cnt, double thr);

/* plausible.c: numbers no real test gives, with their likely cause: per
 * curve at the solution (contact point z0, largest contact radius amax;
 * f->ws.ev at the solution), and the moduli of the result. */
void lf_fit_plausible_curve(const lf_fit *f, size_t j, double z0, double amax, lf_warnings *w);
void lf_fit_plausible(lf_fit_result *r);

/* uncertainty.c */
/* Wald-Wolfowitz runs test of the signs of curve j's residuals in order of
 * depth: about N(0, 1) when the model fits; below FIT_RUNS_Z_BAD, the
 * curve's shape is not the model's. */
#define FIT_RUNS_Z_BAD (-4.0)
/* The residuals' shape (noise.c): the rms of their means over stretches of
 * the curve over the noise sd; above this, systematic. */
#define FIT_SHAPE_MAX 1.0
double lf_fit_runs_z(const lf_fit *f, size_t j, const gsl_vector *res);
/* The same over every stride-th residual in depth order (noise.c). */
double lf_fit_runs_z_stride(const lf_fit *f, size_t j, const gsl_vector *res, size_t stride);
/* The assessment of the solution x of a run that ended with the verdict
 * run: the result's estimates, errors and words. */
int lf_fit_assess(lf_fit *f, const double *x, const fit_run *run, lf_fit_result *res,
                  lf_error *err);

#endif
