/* decomp.c: the one decomposition of a fit's Jacobian that the
 * uncertainty (uncertainty.c) and the model choice (choose.c) share.
 *
 * J is the weighted Jacobian with respect to the physical parameters; its
 * columns are scaled to unit norm, Js = J D^-1, then Js = Q R (Householder,
 * our own sweep for a tall, narrow matrix, in GSL's storage)
 * and R = U_R S V^T (one-sided Jacobi SVD of the small p x p R), so that
 * Js = (Q U_R) S V^T: the singular values and right vectors of Js at a
 * fraction of the cost of an SVD of the tall Js.  A singular value below
 * rcond S_0 marks a direction the data do not determine.
 *
 * Where Js is well conditioned (every singular value above
 * FIT_DECOMP_NORMAL_COND S_0), lf_fit_decomp_normal gets the same S, V and
 * D from J^T J, which the solver has at hand, instead of from J: D^-1 J^T J
 * D^-1 = R^T R by Cholesky, then the SVD of R.  Forming J^T J squares the
 * condition number, so the smallest singular value's relative error grows
 * to about p eps cond(Js)^2 / 2: 7e-8 for six parameters at the
 * threshold's 1e4, below 2e-11 at the cond(Js) of 2 to 160 of the bench's
 * two-probe scenes, far below the digits reported.  Anything worse
 * conditioned takes the QR of J. */
#include <math.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "fit.h"

int
lf_fit_decomp_alloc(fit_decomp *d, size_t n, size_t p)
{
    memset(d, 0, sizeof *d);
    d->n = n;
    d->p = p;
    d->U = gsl_matrix_alloc(p, p);
    d->V = gsl_matrix_alloc(p, p);
    d->S = gsl_vector_alloc(p);
    d->D = gsl_vector_alloc(p);
    d->work = gsl_vector_alloc(p);
    if (n > 0) {
        d->QR = gsl_matrix_alloc(n, p);
        d->tau = gsl_vector_alloc(p);
        d->qtd = gsl_vector_alloc(n);
    }
    if (!d->U || !d->V || !d->S || !d->D || !d->work
        || (n > 0 && (!d->QR || !d->tau || !d->qtd))) {
        lf_fit_decomp_free(d);
        return LF_ENOMEM;
    }
    return LF_OK;
}

void
lf_fit_decomp_free(fit_decomp *d)
{
    gsl_matrix_free(d->QR);
    gsl_vector_free(d->tau);
    gsl_matrix_free(d->U);
    gsl_matrix_free(d->V);
    gsl_vector_free(d->S);
    gsl_vector_free(d->D);
    gsl_vector_free(d->work);
    gsl_vector_free(d->qtd);
    memset(d, 0, sizeof *d);
}

/* The Euclidean norm of column k of A (n rows from row r0, row stride
 * tda): the plain sum of squares unless it over- or underflowed, then
 * BLAS's scaled one. */
static double
column_norm(const double *A, size_t tda, size_t r0, size_t n, size_t k)
{
    double ss, s0 = 0.0, s1 = 0.0;       /* two sums: half the adds' latency */
    size_t i;

    for (i = r0; i + 1 < n; i += 2) {
        s0 += A[i * tda + k] * A[i * tda + k];
        s1 += A[(i + 1) * tda + k] * A[(i + 1) * tda + k];
    }
    if (i < n)
        s0 += A[i * tda + k] * A[i * tda + k];
    ss = s0 + s1;
    if (isfinite(ss) && (ss > 1e-280 || ss == 0.0))
        return sqrt(ss);
    {
        gsl_vector_const_view col = gsl_vector_const_view_array_with_stride(A + r0 * tda + k, tda,
                                                                            n - r0);
        return gsl_blas_dnrm2(&col.vector);
    }
}

/* Householder QR of the n x p matrix A (row stride tda, n >= p) in place,
 * stored as LAPACK and GSL store it (R on and above the diagonal, each
 * reflector's vector below it with an implicit leading 1, H_k = I - tau_k
 * v v^T), so that gsl_linalg_QR_QTvec applies Q^T.  A tall, narrow J: each
 * reflector is applied to the columns on its right one at a time. */
static void
householder_qr(double *A, size_t tda, size_t n, size_t p, double *tau)
{
    size_t i, k, l;

    for (k = 0; k < p; k++) {
        double *akk = A + k * tda + k;
        const double alpha = *akk, xnorm = column_norm(A, tda, k + 1, n, k);
        double beta, scale;
        if (xnorm == 0.0) {         /* nothing below the diagonal: H = I */
            tau[k] = 0.0;
            continue;
        }
        beta = -(alpha >= 0.0 ? 1.0 : -1.0) * hypot(alpha, xnorm);
        tau[k] = (beta - alpha) / beta;
        scale = 1.0 / (alpha - beta);   /* |alpha - beta| >= xnorm > 0 */
        for (i = k + 1; i < n; i++)
            A[i * tda + k] *= scale;
        *akk = beta;
        if (k + 1 == p)
            break;
        /* each column on the right: w = tau (v^T A[k:, l]), A[k:, l] -= w v,
         * column by column so that the sum stays in a register */
        for (l = k + 1; l < p; l++) {
            double wl = A[k * tda + l];
            for (i = k + 1; i < n; i++)
                wl += A[i * tda + k] * A[i * tda + l];
            wl *= tau[k];
            A[k * tda + l] -= wl;
            for (i = k + 1; i < n; i++)
                A[i * tda + l] -= A[i * tda + k] * wl;
        }
    }
}

int
lf_fit_decomp_factor(fit_decomp *d, double rcond, int scale)
{
    size_t i, k, p = d->p;

    if (d->n < p)
        return LF_EINVAL;
    for (k = 0; k < p; k++) {
        const double dn = scale ? column_norm(d->QR->data, d->QR->tda, 0, d->n, k) : 1.0;
        gsl_vector_set(d->D, k, dn);
        if (scale && dn > 0) {
            const double inv = 1.0 / dn;    /* a multiplication per element, not a division */
            for (i = 0; i < d->n; i++)
                d->QR->data[i * d->QR->tda + k] *= inv;
        }
    }
    householder_qr(d->QR->data, d->QR->tda, d->n, p, d->tau->data);
    gsl_matrix_set_zero(d->U);
    for (i = 0; i < p; i++)
        for (k = i; k < p; k++)
            gsl_matrix_set(d->U, i, k, gsl_matrix_get(d->QR, i, k));
    if (gsl_linalg_SV_decomp_jacobi(d->U, d->V, d->S) != GSL_SUCCESS)
        return LF_ENUMERIC;
    d->rank = 0;
    for (k = 0; k < p; k++)
        if (gsl_vector_get(d->S, k) > rcond * gsl_vector_get(d->S, 0))
            d->rank++;
    return LF_OK;
}

int
lf_fit_decomp_normal(fit_decomp *d, const double *G, const double *c, double rcond)
{
    const size_t p = d->p;
    size_t k, l, q;
    double *dk = d->work->data, smin;

    for (k = 0; k < p; k++) {
        const double g = G[k * p + k];
        /* a column whose squares underflow (w driven towards zero: w
         * dP/dw ~ 1e-160) has lost its bits in G; the QR scales it first */
        if (!(g > FIT_DECOMP_NORMAL_TINY) || !isfinite(g) || !(c[k] > 0) || !isfinite(c[k]))
            return LF_ENUMERIC;
        dk[k] = sqrt(g);
        gsl_vector_set(d->D, k, dk[k] / c[k]);
    }
    /* C = D^-1 G D^-1 = R^T R, R upper triangular, into U */
    gsl_matrix_set_zero(d->U);
    for (k = 0; k < p; k++)
        for (l = 0; l <= k; l++) {
            double sum = G[k * p + l] / (dk[k] * dk[l]);
            for (q = 0; q < l; q++)
                sum -= gsl_matrix_get(d->U, q, k) * gsl_matrix_get(d->U, q, l);
            if (l == k) {
                if (!(sum > 0))
                    return LF_ENUMERIC;
                gsl_matrix_set(d->U, k, k, sqrt(sum));
            } else {
                gsl_matrix_set(d->U, l, k, sum / gsl_matrix_get(d->U, l, l));
            }
        }
    if (gsl_linalg_SV_decomp_jacobi(d->U, d->V, d->S) != GSL_SUCCESS)
        return LF_ENUMERIC;
    /* every direction determined, with room: else the decision (and the
     * smallest singular values) need J itself */
    smin = gsl_vector_get(d->S, p - 1);
    if (!(smin >= FIT_DECOMP_NORMAL_COND * gsl_vector_get(d->S, 0))
        || !(smin > FIT_DECOMP_NORMAL_MARGIN * rcond * gsl_vector_get(d->S, 0)))
        return LF_ENUMERIC;
    d->rank = p;
    return LF_OK;
}

int
lf_fit_decomp_run(fit_decomp *d, lf_fit *f, const double *x, double rcond)
{
    if (lf_fit_jacobian_physical(f, x, d->QR) != GSL_SUCCESS)
        return LF_ENUMERIC;
    return lf_fit_decomp_factor(d, rcond, 1);
}

double
lf_fit_decomp_nullw(const fit_decomp *d, size_t k)
{
    double w = gsl_vector_get(d->D, k) > 0 ? 0.0 : 1.0;
    size_t l;

    for (l = d->rank; l < d->p; l++)
        w += gsl_matrix_get(d->V, k, l) * gsl_matrix_get(d->V, k, l);
    return w;
}

void
lf_fit_decomp_project(fit_decomp *d, const double *v, double *coef)
{
    size_t i, l;

    for (i = 0; i < d->n; i++)
        gsl_vector_set(d->qtd, i, v[i]);
    gsl_linalg_QR_QTvec(d->QR, d->tau, d->qtd);     /* Q^T v: first p rows */
    for (l = 0; l < d->rank; l++) {
        double s = 0.0;
        for (i = 0; i < d->p; i++)
            s += gsl_matrix_get(d->U, i, l) * gsl_vector_get(d->qtd, i);
        coef[l] = s / gsl_vector_get(d->S, l);
    }
}

double
lf_fit_decomp_cov(const fit_decomp *d, int a, int b, double scale)
{
    double s = 0.0, da = gsl_vector_get(d->D, (size_t) a), db = gsl_vector_get(d->D, (size_t) b);
    size_t l;

    if (!(da > 0) || !(db > 0))
        return NAN;
    for (l = 0; l < d->rank; l++) {
        double sl = gsl_vector_get(d->S, l);
        s += gsl_matrix_get(d->V, (size_t) a, l) * gsl_matrix_get(d->V, (size_t) b, l) / (sl * sl);
    }
    return scale * s / (da * db);
}
