/* gsl_block.c: GSL's trust region (the runs lm.c hands over, iterate.c)
 * in the block form of a joint fit, with the numbers GSL's own would give.
 *
 * A joint fit's Jacobian has one column per material parameter, touching
 * every row, and a few per curve (its z0, F0, slope), touching only that
 * curve's rows.  GSL's trust region knows none of this:
 *  - its "cholesky" solver forms J^T J with a dense rank-k update, every
 *    column against every other over every row, O(n p^2);
 *  - its finite-difference Jacobian (the runs after the analytic one
 *    stalls at the contact edge) evaluates every curve for every column,
 *    O(n p).
 * Here the same two are done where the numbers are not zero:
 *  - lf_fit_solver_normal, GSL's "cholesky" linear solver (the normal
 *    equations, J^T J + mu D^2 factored by gsl_linalg_cholesky_decomp1)
 *    with each entry of J^T J (and of J^T f) summed over the rows where
 *    both columns are not zero, in row order: every product left out has
 *    an exact zero factor, and adding a zero product to a sum in row order
 *    does not change its bits, so J^T J is the dense update's bit for bit
 *    (a Jacobian with an entry that is not finite takes the dense update,
 *    as a zero times it is not zero); More's scaling (lf_fit_scale_more)
 *    likewise takes each column's norm over its rows that are not zero;
 *  - lf_fit_jacobian_fd, GSL's forward difference (step h |x_k|, or h
 *    where x_k = 0; h = the parameters' h_df) with a column of a curve's
 *    own parameter evaluating that curve alone: the other rows of GSL's
 *    difference subtract a residual from itself, exactly zero, when the
 *    model is a function of its arguments alone.  The exact model's
 *    evaluation starts from its last roots (lf_model_eval_roots), so its
 *    residuals depend, in their last bits, on what was evaluated before:
 *    there the fit keeps GSL's own difference (lf_fit_block_fd).
 * The evaluations counted are GSL's: a Jacobian by differences counts one
 * per column (iterate.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "fit.h"

/* ---- the Jacobian by forward differences, curve by curve ---- */

int
lf_fit_fd_alloc(lf_fit *f)
{
    size_t j, nmax = 0;

    if (f->fd.r0 != NULL)
        return LF_OK;
    for (j = 0; j < f->ncurves; j++)
        nmax = f->c[j].data.n > nmax ? f->c[j].data.n : nmax;
    f->fd.r0 = malloc((2 * f->nres + nmax) * sizeof *f->fd.r0);
    f->fd.ev = malloc(nmax * sizeof *f->fd.ev);
    if (f->fd.r0 == NULL || f->fd.ev == NULL) {
        lf_fit_fd_free(f);
        return LF_ENOMEM;
    }
    f->fd.r1 = f->fd.r0 + f->nres;
    f->fd.delta = f->fd.r1 + f->nres;
    return LF_OK;
}

void
lf_fit_fd_free(lf_fit *f)
{
    free(f->fd.r0);
    free(f->fd.ev);
    memset(&f->fd, 0, sizeof f->fd);
}

fit_df
lf_fit_block_fd(const lf_fit *f)
{
    size_t j;

    if (f->gsl_par.fdtype != GSL_MULTIFIT_NLINEAR_FWDIFF)
        return NULL;
    for (j = 0; j < f->ncurves; j++)
        if (lf_model_get_type(f->c[j].model) == &lf_model_exact)
            return NULL;
    return lf_fit_jacobian_fd;
}

/* The curve whose own parameter x_k is, or ncurves for the material's. */
static size_t
column_curve(const lf_fit *f, size_t k)
{
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        if ((int) k == c->iz0 || (int) k == c->iF0 || (int) k == c->islope)
            return j;
    }
    return f->ncurves;
}

/* Column k of the difference: rows lo .. hi - 1 from r1 - r0 times
 * 1 / delta (GSL's expression), the rest left zero. */
static void
put_column(lf_fit *f, gsl_matrix *J, size_t k, size_t lo, size_t hi, double delta)
{
    size_t i;

    delta = 1.0 / delta;
    for (i = lo; i < hi; i++)
        J->data[i * J->tda + k] = (f->fd.r1[i] - f->fd.r0[i]) * delta;
}

int
lf_fit_jacobian_fd(const gsl_vector *xv, void *params, gsl_matrix *J)
{
    lf_fit *f = params;
    gsl_vector_view r0 = gsl_vector_view_array(f->fd.r0, f->nres);
    gsl_vector_view r1 = gsl_vector_view_array(f->fd.r1, f->nres);
    double *x = xv->data;      /* moved and put back, as GSL's difference does */
    const double h = f->gsl_par.h_df;
    size_t i, k, pass;
    int status;

    if (xv->stride != 1)
        return GSL_EBADFUNC;
    /* the residuals at x: the model's evaluation at x then in f's cache */
    status = lf_fit_residuals(xv, f, &r0.vector);
    if (status != GSL_SUCCESS)
        return status;
    for (i = 0; i < f->nres; i++)
        memset(J->data + i * J->tda, 0, f->np * sizeof *J->data);
    /* the curves' own columns first, F0's and the slope's from the cached
     * evaluation (the model does not depend on them); then the material's,
     * which evaluate every curve (and move the cache) */
    for (pass = 0; pass < 2; pass++)
        for (k = 0; k < f->np; k++) {
            const double xk = x[k];
            const size_t j = column_curve(f, k);
            size_t lo = 0, hi = f->nres;
            double delta = h * fabs(xk);
            if ((j < f->ncurves) != (pass == 0))
                continue;
            if (delta == 0.0)
                delta = h;
            x[k] = xk + delta;
            if (j == f->ncurves) {
                status = lf_fit_residuals(xv, f, &r1.vector);
            } else {
                const int own_model = (int) k == f->c[j].iz0;
                lo = f->c[j].row;
                hi = lo + f->c[j].data.n;
                status = lf_fit_curve_residuals(f, x, j, own_model ? f->fd.delta : NULL,
                                                own_model ? f->fd.ev : NULL, f->fd.r1 + lo);
            }
            x[k] = xk;
            if (status != GSL_SUCCESS)
                return status;
            put_column(f, J, k, lo, hi, delta);
        }
    return GSL_SUCCESS;
}

/* ---- the normal equations of GSL's "cholesky" solver, in block form ---- */

typedef struct {
    gsl_matrix *JTJ;        /* J^T J, lower triangle */
    gsl_matrix *work;       /* J^T J + mu D^2, then its Cholesky factor */
    gsl_vector *rhs;        /* -J^T f */
    gsl_vector *work3p;     /* gsl_linalg_cholesky_rcond's */
    size_t *lo, *hi;        /* each column's first row not zero, and last + 1 */
    int finite;             /* every entry of J finite (else GSL's dense sums) */
    double mu;              /* the damping factored, or -1 before any */
} normal_state;

static void
normal_free(void *vstate)
{
    normal_state *s = vstate;

    if (s == NULL)
        return;
    gsl_matrix_free(s->JTJ);
    gsl_matrix_free(s->work);
    gsl_vector_free(s->rhs);
    gsl_vector_free(s->work3p);
    free(s->lo);
    free(s);
}

static void *
normal_alloc(const size_t n, const size_t p)
{
    normal_state *s = calloc(1, sizeof *s);

    (void) n;
    if (s == NULL)
        return NULL;
    s->JTJ = gsl_matrix_alloc(p, p);
    s->work = gsl_matrix_alloc(p, p);
    s->rhs = gsl_vector_alloc(p);
    s->work3p = gsl_vector_alloc(3 * p);
    s->lo = malloc(2 * p * sizeof *s->lo);
    if (s->JTJ == NULL || s->work == NULL || s->rhs == NULL || s->work3p == NULL
        || s->lo == NULL) {
        normal_free(s);
        return NULL;
    }
    s->hi = s->lo + p;
    s->mu = -1.0;
    return s;
}

/* Each column's rows that are not zero: from lo[j] to hi[j] - 1 (lo = hi
 * = 0 for a column of zeros); 0 when an entry is not finite. */
static int
column_ranges(const gsl_matrix *J, size_t *lo, size_t *hi)
{
    const size_t n = J->size1, p = J->size2, tda = J->tda;
    size_t i, j;
    int finite = 1;

    for (j = 0; j < p; j++) {
        lo[j] = n;
        hi[j] = 0;
    }
    for (i = 0; i < n; i++) {
        const double *row = J->data + i * tda;
        for (j = 0; j < p; j++) {
            if (row[j] == 0.0)
                continue;
            finite &= isfinite(row[j]) != 0;
            if (lo[j] == n)
                lo[j] = i;
            hi[j] = i + 1;
        }
    }
    for (j = 0; j < p; j++)
        if (lo[j] == n)
            lo[j] = 0;
    return finite;
}

/* The lower triangle of J^T J into C from J's column ranges (J finite). */
static void
jtj_in_ranges(const gsl_matrix *J, gsl_matrix *C, const size_t *lo, const size_t *hi)
{
    const size_t p = J->size2, tda = J->tda;
    size_t i, j, k;

    /* the dense update's sums (C = 0, then C += 1 * sum in row order), over
     * the rows where both columns are not zero */
    for (i = 0; i < p; i++)
        for (j = 0; j <= i; j++) {
            const size_t a = lo[i] > lo[j] ? lo[i] : lo[j], b = hi[i] < hi[j] ? hi[i] : hi[j];
            const double *col_i = J->data + i, *col_j = J->data + j;
            double temp = 0.0, *cij = gsl_matrix_ptr(C, i, j);
            for (k = a; k < b; k++)
                temp += col_i[k * tda] * col_j[k * tda];
            *cij = 0.0;
            *cij += temp;
        }
}

int
lf_fit_jtj_lower(const gsl_matrix *J, gsl_matrix *C, size_t *lo, size_t *hi)
{
    if (!column_ranges(J, lo, hi))
        return gsl_blas_dsyrk(CblasLower, CblasTrans, 1.0, J, 0.0, C);
    jtj_in_ranges(J, C, lo, hi);
    return GSL_SUCCESS;
}

static int
normal_init(const void *vtrust_state, void *vstate)
{
    const gsl_multifit_nlinear_trust_state *ts = vtrust_state;
    normal_state *s = vstate;

    s->finite = column_ranges(ts->J, s->lo, s->hi);
    if (!s->finite)
        return gsl_blas_dsyrk(CblasLower, CblasTrans, 1.0, ts->J, 0.0, s->JTJ);
    jtj_in_ranges(ts->J, s->JTJ, s->lo, s->hi);
    return GSL_SUCCESS;
}

static int
normal_presolve(const double mu, const void *vtrust_state, void *vstate)
{
    const gsl_multifit_nlinear_trust_state *ts = vtrust_state;
    normal_state *s = vstate;
    size_t i;
    int status;

    gsl_matrix_tricpy(CblasLower, CblasNonUnit, s->work, s->JTJ);
    if (mu != 0.0)
        for (i = 0; i < ts->diag->size; i++) {
            const double di = gsl_vector_get(ts->diag, i);
            *gsl_matrix_ptr(s->work, i, i) += mu * di * di;
        }
    status = gsl_linalg_cholesky_decomp1(s->work);
    if (status)
        return status;
    s->mu = mu;
    return GSL_SUCCESS;
}

static int
normal_solve(const gsl_vector *fv, gsl_vector *x, const void *vtrust_state, void *vstate)
{
    const gsl_multifit_nlinear_trust_state *ts = vtrust_state;
    normal_state *s = vstate;

    if (!s->finite) {
        gsl_blas_dgemv(CblasTrans, -1.0, ts->J, fv, 0.0, s->rhs);
    } else {
        /* rhs = -J^T f as gsl_blas_dgemv sums it: each entry from 0 over
         * the rows in order, a row whose -f_i is zero left out; here also
         * the rows where the column is zero (zero products: the same bits) */
        const gsl_matrix *J = ts->J;
        size_t i, k;
        for (k = 0; k < J->size2; k++) {
            double acc = 0.0;
            for (i = s->lo[k]; i < s->hi[k]; i++) {
                const double t = -1.0 * gsl_vector_get(fv, i);
                if (t != 0.0)
                    acc += t * J->data[i * J->tda + k];
            }
            gsl_vector_set(s->rhs, k, acc);
        }
    }
    return gsl_linalg_cholesky_solve(s->work, s->rhs, x);
}

static int
normal_rcond(double *rcond, void *vstate)
{
    normal_state *s = vstate;
    double rc;
    int status;

    if (s->mu < 0.0) {
        *rcond = 0.0;
        return GSL_EFAILED;
    }
    if (s->mu != 0.0) {         /* factor J^T J itself */
        gsl_matrix_tricpy(CblasLower, CblasNonUnit, s->work, s->JTJ);
        status = gsl_linalg_cholesky_decomp1(s->work);
        if (status)
            return status;
    }
    status = gsl_linalg_cholesky_rcond(s->work, &rc, s->work3p);
    if (status == GSL_SUCCESS)
        *rcond = sqrt(rc);
    return status;
}

/* ---- More's scaling (GSL's "more"), column norms where not zero ---- */

/* D_j = max(D_j, |J_j|) (|J_j| = 1 where the column is zero): More 1978,
 * eq. 6.3, as gsl_multifit_nlinear_scale_more, each norm by gsl_blas_dnrm2
 * over the column's rows that are not zero (it passes over zeros: the
 * same bits). */
static int
more_update(const gsl_matrix *J, gsl_vector *diag)
{
    const size_t p = J->size2;
    size_t *lo = malloc(2 * p * sizeof *lo), *hi = lo + p, j;

    if (lo == NULL)
        return GSL_ENOMEM;
    (void) column_ranges(J, lo, hi);
    for (j = 0; j < p; j++) {
        double norm = 0.0, *dj = gsl_vector_ptr(diag, j);
        if (hi[j] > lo[j]) {
            gsl_vector_const_view v = gsl_matrix_const_subcolumn(J, j, lo[j], hi[j] - lo[j]);
            norm = gsl_blas_dnrm2(&v.vector);
        }
        if (norm == 0.0)
            norm = 1.0;
        *dj = *dj > norm ? *dj : norm;     /* GSL_MAX, NaN as GSL has it */
    }
    free(lo);
    return GSL_SUCCESS;
}

static int
more_init(const gsl_matrix *J, gsl_vector *diag)
{
    gsl_vector_set_zero(diag);
    return more_update(J, diag);
}

static const gsl_multifit_nlinear_scale more_type = { "more", more_init, more_update };

const gsl_multifit_nlinear_scale *const lf_fit_scale_more = &more_type;

static const gsl_multifit_nlinear_solver normal_type = {
    "cholesky", normal_alloc, normal_init, normal_presolve, normal_solve, normal_rcond,
    normal_free
};

const gsl_multifit_nlinear_solver *const lf_fit_solver_normal = &normal_type;
