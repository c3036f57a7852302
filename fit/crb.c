/* crb.c: the Cramer-Rao bound of an indentation experiment.
 *
 * With Gaussian force noise of standard deviation sigma_j on curve j, the
 * Fisher information of the parameters theta is F = sum_i g_i g_i^T / sigma^2
 * with g_i = dP_i/dtheta.  theta = (ln w, ln E*[, nu], z0_j, F0_j ...);
 * dP/dz0 = -dP/ddelta since delta = z - z0, and dP/dF0 = 1.  F is
 * accumulated directly (no Jacobian is stored), in block form (each
 * curve's nuisance couples only to the material: block.c), scaled to unit
 * diagonal and inverted by the block Cholesky. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

#define CHUNK 256

/* Add the information of curve j to the arrowhead F (block.c: the
 * material's ln w, ln E* (, nu), then each curve's z0, F0). */
static int
accumulate(const lf_design_curve *cv, size_t j, const lf_material *truth, int free_nu,
           fit_arrow *F, lf_error *err)
{
    lf_eval e[CHUNK];
    double g[5];          /* ln w, ln E*, nu, z0, F0 at most */
    size_t cols[5];       /* their columns in F */
    size_t start, i, r, c, col = F->at[j];
    size_t nloc = 2 + (free_nu ? 1u : 0u);
    int status;

    /* columns this curve touches: material ones, then its own nuisance */
    for (r = 0; r < nloc; r++)
        cols[r] = r;
    if (cv->free_z0)
        cols[nloc++] = col++;
    if (cv->free_F0)
        cols[nloc++] = col;
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
                    lf_arrow_add(F, j, cols[r], cols[c], g[r] * g[c] / (cv->sigma * cv->sigma));
        }
    }
    return LF_OK;
}

int
lf_crb(const lf_design_curve *curves, size_t ncurves, const lf_material *truth,
       int free_nu, lf_crb_result *out, lf_error *err)
{
    const size_t m = 2 + (free_nu ? 1u : 0u);
    size_t p, j, r, c;
    unsigned char *q = malloc(ncurves ? ncurves : 1);
    fit_arrow F;
    fit_arrow_chol L;
    fit_arrow_inv V;
    double *scale = NULL;
    int status = LF_OK;

    memset(&F, 0, sizeof F);
    memset(&L, 0, sizeof L);
    memset(&V, 0, sizeof V);
    if (ncurves == 0) {
        free(q);
        return lf_fail(err, LF_EINVAL, "no curves in the design");
    }
    for (j = 0; j < ncurves; j++)
        if (!(curves[j].sigma > 0 && isfinite(curves[j].sigma))) {
            free(q);
            return lf_fail(err, LF_EINVAL, "curve %zu: noise sigma must be > 0", j + 1);
        }
    /* the Fisher information is an arrowhead (a curve's nuisance touches
     * only its own rows): kept and inverted in blocks, linear in the
     * curves (block.c) */
    for (j = 0; q != NULL && j < ncurves; j++)
        q[j] = (unsigned char) ((curves[j].free_z0 ? 1 : 0) + (curves[j].free_F0 ? 1 : 0));
    if (q == NULL || lf_arrow_alloc(&F, m, ncurves, q) != LF_OK
        || lf_arrow_chol_alloc(&L, &F) != LF_OK
        || (scale = malloc(F.p * sizeof *scale)) == NULL) {
        status = lf_fail(err, LF_ENOMEM, "out of memory for the Fisher information");
        goto done;
    }
    p = F.p;
    for (j = 0; j < ncurves; j++) {
        status = accumulate(&curves[j], j, truth, free_nu, &F, err);
        if (status != LF_OK)
            goto done;
    }
    lf_arrow_diag(&F, scale);
    for (r = 0; r < p; r++) {
        if (!(scale[r] > 0)) {
            status = lf_fail(err, LF_EDATA, "the data carry no information on parameter %zu", r + 1);
            goto done;
        }
        scale[r] = 1.0 / sqrt(scale[r]);
    }
    lf_arrow_scale(&F, scale);
    if (!lf_arrow_factor(&L, &F, NULL, 0.0, 0.0) || lf_arrow_inv_make(&V, &L) != LF_OK) {
        status = lf_fail(err, LF_EDATA, "the design does not determine all free parameters "
                         "(singular Fisher information)");
        goto done;
    }
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            out->cov[r][c] = NAN;
    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            out->cov[r][c] = lf_arrow_inv_get(&V, r, c) * scale[r] * scale[c];
    out->sd_logw = sqrt(out->cov[0][0]);
    out->sd_logE = sqrt(out->cov[1][1]);
    out->sd_nu = free_nu ? sqrt(out->cov[2][2]) : NAN;
    out->corr_wE = out->cov[0][1] / (out->sd_logw * out->sd_logE);
    out->nparams = p;
done:
    lf_arrow_inv_free(&V);
    lf_arrow_chol_free(&L);
    lf_arrow_free(&F);
    free(scale);
    free(q);
    return status;
}
