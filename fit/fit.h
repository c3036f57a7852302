/* fit.h: the fitter's internal header, shared by problem.c (parameter
 * mapping, residuals, Jacobian), guess.c (initial guess), driver.c (GSL)
 * and uncertainty.c (covariance and identifiability).  Not installed.
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

/* An iteration limit reached with the cost (half chi2, the residuals being
 * in units of the noise) fallen by less than FIT_FLAT_REL of itself or
 * FIT_FLAT_ABS over the last FIT_FLAT_ITERS iterations counts as
 * convergence: at the kinks of the model the trust region can creep
 * without end, and a chi2 change of 0.002 moves no estimate by more than a
 * twentieth of its standard error. */
#define FIT_FLAT_ITERS 20
#define FIT_FLAT_REL 1e-8
#define FIT_FLAT_ABS 1e-3

#define GUESS_GRID 40          /* uniform nodes of a profile search */
#define GUESS_NODES (GUESS_GRID + 1)

/* What the first stage of the guess learned from one curve alone. */
typedef struct {
    double M, c, z0, F0;
    int sees_w;     /* 0 for k = 2 with free z0 and F0 and no baseline */
} curve_guess;

/* One curve inside the fit. */
typedef struct {
    lf_fit_curve data;
    lf_model *model;
    size_t row;          /* first residual row */
    double L, Fs;        /* depth span (m) and largest |force| (N) */
    double eps;          /* derivative guard width at detachment, m */
    double sigma;        /* noise sd, N */
    int iz0, iF0, islope;   /* index in x, or -1 when held */
    double z0, F0, slope;   /* held values or the guess (physical) */
    curve_guess guess;
} fit_curve;

struct lf_fit {
    lf_fit_settings set;
    const gsl_multifit_nlinear_trs *trs;
    size_t ncurves;
    fit_curve *c;
    size_t ndata;        /* data rows */
    size_t nres;         /* + 1 prior row when nu has a prior */
    size_t np;           /* free parameters */
    int imat[FIT_NMAT];  /* index in x of ln w, ln E*, u, or -1 */
    int nu_prior;        /* 1 when a prior row is present */
    int nu_determinable; /* the plan alone determines nu */
    int any_bonded, any_frictionless;
    lf_material mat;     /* held values, then the guess, then the fit */
    lf_material auto_mat; /* the automatic guess */
    int user_start;      /* 1 when the settings' guess replaced some of it */
    double alt_w;        /* the guess's runner-up w, a second start, or NaN */
    int no_loo;          /* 1: a leave-one-out refit, which makes none itself */
    double cost_hist[FIT_FLAT_ITERS + 1]; /* cost after each iteration, cyclic */
    double *x0_internal; /* np: internal coordinates at the guess */
    lf_eval *ev;         /* ndata: model at the last residual evaluation */
    lf_eval *scan_ev;    /* ndata: scratch of the contact-point scan */
    double *sqrtw;       /* ndata: square roots of the robust loss's point
                            weights (1 for least squares) */
    double *delta;       /* ndata: indentations */
    double *xcache;      /* np: the x of ev[]; xcache_ok when valid */
    int xcache_ok;
    double *work;        /* max(ndata, 2 nsub_max): scratch */
    size_t *order;       /* ndata: each curve's points by depth (ties in
                            file order), indices within the curve */
    size_t nsub_max;     /* scratch size of the guess's subsample */
    double *sub;         /* 3 nsub_max + GUESS_NODES: subsample, nodes */
    gsl_multifit_nlinear_workspace *gsl;
    gsl_multifit_nlinear_fdf fdf;
    size_t nfev;         /* residual evaluations of the current run */
};

/* problem.c */
int fit_problem_setup(lf_fit *f, lf_error *err);
/* Map x to the material and per-curve offsets. */
void fit_unpack(const lf_fit *f, const double *x, lf_material *mat,
                double *z0, double *F0, double *slope, size_t j);
/* Put the guess (f->mat, f->c[j].z0/F0/slope) into internal coordinates. */
void fit_set_origin(lf_fit *f);
int fit_residuals(const gsl_vector *x, void *params, gsl_vector *r);
int fit_jacobian(const gsl_vector *x, void *params, gsl_matrix *J);
/* Jacobian with respect to the physical coordinates, rows weighted. */
int fit_jacobian_physical(lf_fit *f, const double *x, gsl_matrix *J);
double fit_nu_of_u(double u);
double fit_u_of_nu(double nu);
double fit_dnu_du(double u);

/* guess.c */
int fit_guess(lf_fit *f, lf_error *err);
/* Profile every curve's offsets at f->mat and make that the origin. */
void fit_guess_offsets(lf_fit *f);
/* Noise sd of a curve from how far each point's force lies from the line
 * through its neighbours in depth (order: indices by depth). */
double fit_noise_sigma(const double *depth, const double *force, const size_t *order,
                       size_t n, double *work);

/* driver.c: the least-squares solve from the origin set by fit_guess or
 * fit_set_origin, then fit_assess; fills res as lf_fit_run does. */
int fit_solve(lf_fit *f, lf_fit_result *res, lf_error *err);

/* uncertainty.c */
/* Wald-Wolfowitz runs test of the signs of curve j's residuals in order of
 * depth: about N(0, 1) when the model fits; below FIT_RUNS_Z_BAD, the
 * curve's shape is not the model's. */
#define FIT_RUNS_Z_BAD (-4.0)
double fit_runs_z(const lf_fit *f, size_t j, const gsl_vector *res);
int fit_assess(lf_fit *f, const double *x, lf_fit_result *res, lf_error *err);

#endif
