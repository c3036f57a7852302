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
    lf_fit_bdec_free(&d->blk);
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
lf_fit_decomp_factor(fit_decomp *d, double rcond, int scale)
{
    size_t i, k, p = d->p;

    if (d->n < p)
        return LF_EINVAL;
    for (k = 0; k < p; k++) {
        const double dn = scale ? lf_fit_column_norm(d->QR->data, d->QR->tda, 0, d->n, k) : 1.0;
        gsl_vector_set(d->D, k, dn);
        if (scale && dn > 0) {
            const double inv = 1.0 / dn;    /* a multiplication per element, not a division */
            for (i = 0; i < d->n; i++)
                d->QR->data[i * d->QR->tda + k] *= inv;
        }
    }
    lf_fit_householder_qr(d->QR->data, d->QR->tda, d->n, p, d->tau->data);
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

int
lf_fit_decomp_block_run(fit_decomp *d, lf_fit *f, const double *x, int with_nu, double rcond)
{
    int st = lf_fit_bdec_run(&d->blk, f, x, with_nu, rcond, 0);

    d->block = 1;
    d->p = d->blk.p;
    d->n = 0;
    d->rank = d->blk.rank;
    return st;
}

double
lf_fit_decomp_norm(const fit_decomp *d, size_t k)
{
    return d->block ? d->blk.D[k] : gsl_vector_get(d->D, k);
}

double
lf_fit_decomp_smin_ratio(const fit_decomp *d)
{
    if (d->p == 0)
        return 1.0;
    if (d->block)
        return d->blk.smin / d->blk.s0;
    return gsl_vector_get(d->S, d->p - 1) / gsl_vector_get(d->S, 0);
}

double
lf_fit_decomp_nullw(const fit_decomp *d, size_t k)
{
    double w;
    size_t l;

    if (d->block)
        return lf_fit_bdec_nullw(&d->blk, k);
    w = gsl_vector_get(d->D, k) > 0 ? 0.0 : 1.0;
    for (l = d->rank; l < d->p; l++)
        w += gsl_matrix_get(d->V, k, l) * gsl_matrix_get(d->V, k, l);
    return w;
}

double
lf_fit_decomp_combination_nullw(const fit_decomp *d, const int *cols, const double *g, size_t m)
{
    double norm = 0.0, null = 0.0;
    size_t i, l, nl = d->block ? d->blk.k : d->p - d->rank;

    for (i = 0; i < m; i++)
        if (cols[i] >= 0) {
            double dk = lf_fit_decomp_norm(d, (size_t) cols[i]);
            if (!(dk > 0))
                return 1.0;
            norm += g[i] * g[i] / (dk * dk);
        }
    if (!(norm > 0))
        return 1.0;
    for (l = 0; l < nl; l++) {
        double s = 0.0;
        for (i = 0; i < m; i++)
            if (cols[i] >= 0) {
                const size_t c = (size_t) cols[i];
                const double v = d->block ? d->blk.V[l * d->p + c]
                                          : gsl_matrix_get(d->V, c, d->rank + l);
                s += v * g[i] / lf_fit_decomp_norm(d, c);
            }
        null += s * s;
    }
    return null / norm;
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

void
lf_fit_decomp_step(fit_decomp *d, const double *v, double *coef, double *step)
{
    size_t k, l;

    lf_fit_decomp_project(d, v, coef);
    for (k = 0; k < d->p; k++) {
        double s = 0.0;
        for (l = 0; l < d->rank; l++)
            s += gsl_matrix_get(d->V, k, l) * coef[l];
        step[k] = s;
    }
}

void
lf_fit_decomp_pinv(const fit_decomp *d, const double *g, double *out, double *work)
{
    size_t k, l;

    if (d->block) {
        lf_fit_bdec_pinv(&d->blk, g, out, work);
        return;
    }
    for (l = 0; l < d->rank; l++) {
        double s = 0.0, sl = gsl_vector_get(d->S, l);
        for (k = 0; k < d->p; k++)
            s += gsl_matrix_get(d->V, k, l) * g[k];
        work[l] = s / (sl * sl);
    }
    for (k = 0; k < d->p; k++) {
        double s = 0.0;
        for (l = 0; l < d->rank; l++)
            s += gsl_matrix_get(d->V, k, l) * work[l];
        out[k] = s;
    }
}

double
lf_fit_decomp_cov(const fit_decomp *d, int a, int b, double scale)
{
    double s = 0.0, da, db;
    size_t l;

    if (d->block)
        return lf_fit_bdec_cov(&d->blk, (size_t) a, (size_t) b, scale);
    da = gsl_vector_get(d->D, (size_t) a);
    db = gsl_vector_get(d->D, (size_t) b);
    if (!(da > 0) || !(db > 0))
        return NAN;
    for (l = 0; l < d->rank; l++) {
        double sl = gsl_vector_get(d->S, l);
        s += gsl_matrix_get(d->V, (size_t) a, l) * gsl_matrix_get(d->V, (size_t) b, l) / (sl * sl);
    }
    return scale * s / (da * db);
}
