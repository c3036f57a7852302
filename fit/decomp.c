/* decomp.c: the one decomposition of a fit's Jacobian that the
 * uncertainty (uncertainty.c) and the model choice (choose.c) share.
 *
 * J is the weighted Jacobian with respect to the physical parameters; its
 * columns are scaled to unit norm, Js = J D^-1, then Js = Q R (Householder)
 * and R = U_R S V^T (one-sided Jacobi SVD of the small p x p R), so that
 * Js = (Q U_R) S V^T: the singular values and right vectors of Js at a
 * fraction of the cost of an SVD of the tall Js.  A singular value below
 * rcond S_0 marks a direction the data do not determine. */
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
    d->QR = gsl_matrix_alloc(n, p);
    d->tau = gsl_vector_alloc(p);
    d->U = gsl_matrix_alloc(p, p);
    d->V = gsl_matrix_alloc(p, p);
    d->S = gsl_vector_alloc(p);
    d->D = gsl_vector_alloc(p);
    d->work = gsl_vector_alloc(p);
    d->qtd = gsl_vector_alloc(n);
    if (!d->QR || !d->tau || !d->U || !d->V || !d->S || !d->D || !d->work || !d->qtd) {
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

int
lf_fit_decomp_run(fit_decomp *d, lf_fit *f, const double *x, double rcond)
{
    size_t i, k, p = d->p;

    if (d->n < p)
        return LF_EINVAL;
    if (lf_fit_jacobian_physical(f, x, d->QR) != GSL_SUCCESS)
        return LF_ENUMERIC;
    for (k = 0; k < p; k++) {
        gsl_vector_view col = gsl_matrix_column(d->QR, k);
        double ss = 0.0, dn;
        for (i = 0; i < d->n; i++) {
            const double v = d->QR->data[i * d->QR->tda + k];
            ss += v * v;
        }
        /* the plain sum of squares unless it over- or underflowed */
        dn = isfinite(ss) && ss > 1e-280 ? sqrt(ss) : gsl_blas_dnrm2(&col.vector);
        gsl_vector_set(d->D, k, dn);
        if (dn > 0)
            gsl_vector_scale(&col.vector, 1.0 / dn);
    }
    if (gsl_linalg_QR_decomp(d->QR, d->tau) != GSL_SUCCESS)
        return LF_ENUMERIC;
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
