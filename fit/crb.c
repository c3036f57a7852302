/* crb.c: the Cramer-Rao bound of an indentation experiment.
 *
 * With Gaussian force noise of standard deviation sigma_j on curve j, the
 * Fisher information of the parameters theta is F = sum_i g_i g_i^T / sigma^2
 * with g_i = dP_i/dtheta.  theta = (ln w, ln E*[, nu], z0_j, F0_j ...);
 * dP/dz0 = -dP/ddelta since delta = z - z0, and dP/dF0 = 1.  F is
 * accumulated directly (no Jacobian is stored), scaled to unit diagonal and
 * inverted by Cholesky. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include "internal.h"

#define CHUNK 256

static size_t
count_params(const lf_design_curve *curves, size_t ncurves, int free_nu)
{
    size_t j, p = 2 + (free_nu ? 1 : 0);
    for (j = 0; j < ncurves; j++)
        p += (curves[j].free_z0 ? 1 : 0) + (curves[j].free_F0 ? 1 : 0);
    return p;
}

/* Add the information of one curve to F (p x p, lower triangle). */
static int
accumulate(const lf_design_curve *cv, const lf_material *truth, int free_nu,
           size_t col_z0, gsl_matrix *F, lf_error *err)
{
    lf_eval e[CHUNK];
    double g[5];          /* ln w, ln E*, nu, z0, F0 at most */
    size_t cols[5];       /* their columns in F */
    size_t start, i, r, c;
    size_t nloc = 2 + (free_nu ? 1u : 0u);
    int status;

    /* columns this curve touches: material ones, then its own nuisance */
    for (r = 0; r < nloc; r++)
        cols[r] = r;
    if (cv->free_z0)
        cols[nloc++] = col_z0++;
    if (cv->free_F0)
        cols[nloc++] = col_z0;
    for (start = 0; start < cv->n; start += CHUNK) {
        size_t m = cv->n - start < CHUNK ? cv->n - start : CHUNK;
        status = lf_model_eval(cv->model, truth, cv->branch, m, cv->delta + start, e, err);
        if (status != LF_OK)
            return status;
        for (i = 0; i < m; i++) {
            size_t q = 0;
            g[q++] = e[i].dP_dlogw;
            g[q++] = e[i].dP_dlogE;
            if (free_nu)
                g[q++] = e[i].dP_dnu;
            if (cv->free_z0)
                g[q++] = -e[i].dP_ddelta;
            if (cv->free_F0)
                g[q++] = 1.0;
            for (r = 0; r < q; r++)
                for (c = 0; c <= r; c++)
                    *gsl_matrix_ptr(F, cols[r], cols[c]) += g[r] * g[c] / (cv->sigma * cv->sigma);
        }
    }
    return LF_OK;
}

int
lf_crb(const lf_design_curve *curves, size_t ncurves, const lf_material *truth,
       int free_nu, lf_crb_result *out, lf_error *err)
{
    size_t p, j, r, c, col;
    gsl_matrix *F = NULL;
    double *scale = NULL;
    int status = LF_OK;

    if (ncurves == 0)
        return lf_fail(err, LF_EINVAL, "no curves in the design");
    for (j = 0; j < ncurves; j++)
        if (!(curves[j].sigma > 0 && isfinite(curves[j].sigma)))
            return lf_fail(err, LF_EINVAL, "curve %zu: noise sigma must be > 0", j + 1);
    p = count_params(curves, ncurves, free_nu);
    F = gsl_matrix_calloc(p, p);
    scale = malloc(p * sizeof *scale);
    if (F == NULL || scale == NULL) {
        status = lf_fail(err, LF_ENOMEM, "out of memory for the Fisher information");
        goto done;
    }
    col = 2 + (free_nu ? 1u : 0u);
    for (j = 0; j < ncurves; j++) {
        status = accumulate(&curves[j], truth, free_nu, col, F, err);
        if (status != LF_OK)
            goto done;
        col += (curves[j].free_z0 ? 1u : 0u) + (curves[j].free_F0 ? 1u : 0u);
    }
    for (r = 0; r < p; r++) {
        double d = gsl_matrix_get(F, r, r);
        if (!(d > 0)) {
            status = lf_fail(err, LF_EDATA, "the data carry no information on parameter %zu", r + 1);
            goto done;
        }
        scale[r] = 1.0 / sqrt(d);
    }
    for (r = 0; r < p; r++)
        for (c = 0; c <= r; c++) {
            double v = gsl_matrix_get(F, r, c) * scale[r] * scale[c];
            gsl_matrix_set(F, r, c, v);
            gsl_matrix_set(F, c, r, v);
        }
    if (gsl_linalg_cholesky_decomp1(F) != GSL_SUCCESS || gsl_linalg_cholesky_invert(F) != GSL_SUCCESS) {
        status = lf_fail(err, LF_EDATA, "the design does not determine all free parameters "
                         "(singular Fisher information)");
        goto done;
    }
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            out->cov[r][c] = NAN;
    for (r = 0; r < 2 + (size_t) (free_nu != 0); r++)
        for (c = 0; c < 2 + (size_t) (free_nu != 0); c++)
            out->cov[r][c] = gsl_matrix_get(F, r, c) * scale[r] * scale[c];
    out->sd_logw = sqrt(out->cov[0][0]);
    out->sd_logE = sqrt(out->cov[1][1]);
    out->sd_nu = free_nu ? sqrt(out->cov[2][2]) : NAN;
    out->corr_wE = out->cov[0][1] / (out->sd_logw * out->sd_logE);
    out->nparams = p;
done:
    gsl_matrix_free(F);
    free(scale);
    return status;
}
