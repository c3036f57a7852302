/* block.c: the normal matrix of a joint fit in block form, and its
 * Cholesky factor.
 *
 * The free parameters are the material's m (x[0..m-1]) and then each
 * curve's own q_j <= FIT_QMAX (its contact point, force offset, slope),
 * and a curve's residuals touch only the material's columns and its own.
 * So J^T J is an arrowhead: a dense m x m head H, and per curve a q_j x m
 * coupling C_j and a q_j x q_j block B_j, zeros between curves:
 *
 *          [ H    C_1^T  C_2^T ... ]
 *     A =  [ C_1  B_1              ]
 *          [ C_2         B_2       ]
 *          [ ...              ...  ]
 *
 * Ordered curves first, its Cholesky factor has the same pattern (no
 * fill): B_j = L_j L_j^T, E_j = L_j^-1 C_j, and the head's Schur
 * complement S = H - sum_j E_j^T E_j = L_s L_s^T, the reduced system of
 * the material alone (bundle adjustment's Schur complement: Triggs et
 * al., "Bundle adjustment - a modern synthesis", 2000, sec. 6.1).  Every
 * operation below costs O(ncurves) and keeps O(ncurves) numbers, where
 * the dense matrix costs O(p^3) and O(p^2) with p = m + sum q_j.  The
 * results are those of the dense Cholesky up to rounding (the pivots are
 * taken in another order); a pivot that is not positive, or not above rel
 * times its diagonal before the elimination, makes the matrix "not
 * positive definite" as the dense test does. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>

#include "fit.h"

/* Entry (r, c) of a curve's blocks: C at cb[r * FIT_MMAX + c], B at
 * cb[FIT_QMAX * FIT_MMAX + r * FIT_QMAX + c]. */
#define C_AT(cb, r, c) ((cb)[(r) * FIT_MMAX + (c)])
#define B_AT(cb, r, c) ((cb)[FIT_QMAX * FIT_MMAX + (r) * FIT_QMAX + (c)])
#define H_AT(h, r, c) ((h)[(r) * FIT_MMAX + (c)])

int
lf_arrow_alloc(fit_arrow *a, size_t m, size_t n, const unsigned char *q)
{
    size_t j, at = m;

    memset(a, 0, sizeof *a);
    if (m > FIT_MMAX)
        return LF_EINVAL;
    a->m = m;
    a->n = n;
    a->cb = calloc(n ? n * FIT_CB : 1, sizeof *a->cb);
    a->q = malloc(n ? n : 1);
    a->at = malloc((n ? n : 1) * sizeof *a->at);
    if (a->cb == NULL || a->q == NULL || a->at == NULL) {
        lf_arrow_free(a);
        return LF_ENOMEM;
    }
    for (j = 0; j < n; j++) {
        if (q[j] > FIT_QMAX) {
            lf_arrow_free(a);
            return LF_EINVAL;
        }
        a->q[j] = q[j];
        a->at[j] = at;
        at += q[j];
    }
    a->p = at;
    return LF_OK;
}

void
lf_arrow_free(fit_arrow *a)
{
    free(a->cb);
    free(a->q);
    free(a->at);
    memset(a, 0, sizeof *a);
}

int
lf_arrow_copy_layout(fit_arrow *dst, const fit_arrow *src)
{
    return lf_arrow_alloc(dst, src->m, src->n, src->q);
}

void
lf_arrow_zero(fit_arrow *a)
{
    memset(a->head, 0, sizeof a->head);
    memset(a->cb, 0, a->n * FIT_CB * sizeof *a->cb);
}

void
lf_arrow_copy(fit_arrow *dst, const fit_arrow *src)
{
    memcpy(dst->head, src->head, sizeof dst->head);
    memcpy(dst->cb, src->cb, src->n * FIT_CB * sizeof *dst->cb);
}

/* The curve that owns parameter k (>= m): a binary search of at[0..n). */
static size_t
owner(const size_t *at, size_t n, size_t k)
{
    size_t lo = 0, hi = n;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (at[mid] <= k)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Where entry (r, c) lives (NULL: outside the pattern, zero); curve j's
 * entries found from j directly when r or c is its own. */
static double *
entry(fit_arrow *a, size_t j, size_t r, size_t c)
{
    const size_t m = a->m;
    double *cb;

    if (r < m && c < m)
        return &H_AT(a->head, r, c);
    if (r < m) {
        size_t t = r;
        r = c;
        c = t;
    }
    if (j >= a->n || r < a->at[j] || r >= a->at[j] + a->q[j])
        j = owner(a->at, a->n, r);
    cb = a->cb + j * FIT_CB;
    if (c < m)
        return &C_AT(cb, r - a->at[j], c);
    if (c < a->at[j] || c >= a->at[j] + a->q[j])
        return NULL;
    return &B_AT(cb, r - a->at[j], c - a->at[j]);
}

void
lf_arrow_add(fit_arrow *a, size_t j, size_t r, size_t c, double v)
{
    double *e = entry(a, j, r, c);
    if (e == NULL)
        return;
    *e += v;
    if (r != c && ((r < a->m) == (c < a->m))) {     /* the symmetric twin in H or B */
        double *t = entry(a, j, c, r);
        *t += v;
    }
}

void
lf_arrow_scale(fit_arrow *a, const double *s)
{
    const size_t m = a->m;
    size_t j, r, c;

    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            H_AT(a->head, r, c) *= s[r] * s[c];
    for (j = 0; j < a->n; j++) {
        double *cb = a->cb + j * FIT_CB;
        const double *sj = s + a->at[j];
        for (r = 0; r < a->q[j]; r++) {
            for (c = 0; c < m; c++)
                C_AT(cb, r, c) *= sj[r] * s[c];
            for (c = 0; c < a->q[j]; c++)
                B_AT(cb, r, c) *= sj[r] * sj[c];
        }
    }
}

void
lf_arrow_diag(const fit_arrow *a, double *d)
{
    size_t j, r;

    for (r = 0; r < a->m; r++)
        d[r] = H_AT(a->head, r, r);
    for (j = 0; j < a->n; j++)
        for (r = 0; r < a->q[j]; r++)
            d[a->at[j] + r] = B_AT(a->cb + j * FIT_CB, r, r);
}

double
lf_arrow_get(const fit_arrow *a, size_t r, size_t c)
{
    const double *e = entry((fit_arrow *) a, a->n, r, c);
    return e != NULL ? *e : 0.0;
}

void
lf_arrow_dense(const fit_arrow *a, double *G)
{
    const size_t p = a->p, m = a->m;
    size_t j, r, c;

    memset(G, 0, p * p * sizeof *G);
    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            G[r * p + c] = H_AT(a->head, r, c);
    for (j = 0; j < a->n; j++) {
        const double *cb = a->cb + j * FIT_CB;
        const size_t at = a->at[j];
        for (r = 0; r < a->q[j]; r++) {
            for (c = 0; c < m; c++)
                G[(at + r) * p + c] = G[c * p + at + r] = C_AT(cb, r, c);
            for (c = 0; c < a->q[j]; c++)
                G[(at + r) * p + at + c] = B_AT(cb, r, c);
        }
    }
}

void
lf_arrow_mul(const fit_arrow *a, const double *x, double *y)
{
    const size_t m = a->m;
    size_t j, r, c;

    for (r = 0; r < m; r++) {
        double s = 0.0;
        for (c = 0; c < m; c++)
            s += H_AT(a->head, r, c) * x[c];
        y[r] = s;
    }
    for (j = 0; j < a->n; j++) {
        const double *cb = a->cb + j * FIT_CB, *xj = x + a->at[j];
        double *yj = y + a->at[j];
        for (r = 0; r < a->q[j]; r++) {
            double s = 0.0;
            for (c = 0; c < m; c++) {
                s += C_AT(cb, r, c) * x[c];
                y[c] += C_AT(cb, r, c) * xj[r];
            }
            for (c = 0; c < a->q[j]; c++)
                s += B_AT(cb, r, c) * xj[c];
            yj[r] = s;
        }
    }
}

/* ---- the factor -------------------------------------------------------- */

int
lf_arrow_chol_alloc(fit_arrow_chol *L, const fit_arrow *a)
{
    memset(L, 0, sizeof *L);
    L->m = a->m;
    L->n = a->n;
    L->q = a->q;
    L->at = a->at;
    L->p = a->p;
    L->cf = calloc(a->n ? a->n * FIT_CF : 1, sizeof *L->cf);
    return L->cf != NULL ? LF_OK : LF_ENOMEM;
}

void
lf_arrow_chol_free(fit_arrow_chol *L)
{
    free(L->cf);
    memset(L, 0, sizeof *L);
}

/* Curve factor j: L_j (lower, stride FIT_QMAX) then E_j (q x m, stride
 * FIT_MMAX). */
#define LJ_AT(cf, r, c) ((cf)[(r) * FIT_QMAX + (c)])
#define EJ_AT(cf, r, c) ((cf)[FIT_QMAX * FIT_QMAX + (r) * FIT_MMAX + (c)])
#define LS_AT(l, r, c) ((l)[(r) * FIT_MMAX + (c)])

int
lf_small_chol(const double *M, size_t s, size_t n, double rel, const double *diag, double *L)
{
    size_t k, l, q;

    for (k = 0; k < n; k++)
        for (l = 0; l <= k; l++) {
            double v = M[k * s + l];
            for (q = 0; q < l; q++)
                v -= L[k * s + q] * L[l * s + q];
            if (k == l) {
                if (!(v > 0) || !(v > rel * (diag != NULL ? diag[k] : M[k * s + k])))
                    return 0;
                L[k * s + k] = sqrt(v);
            } else {
                L[k * s + l] = v / L[l * s + l];
            }
        }
    return 1;
}

/* y = L^-1 y and y = L^-T y for the n x n lower triangle L (stride s). */
static void
lower_solve(const double *L, size_t s, size_t n, double *y)
{
    size_t k, q;
    for (k = 0; k < n; k++) {
        double v = y[k];
        for (q = 0; q < k; q++)
            v -= L[k * s + q] * y[q];
        y[k] = v / L[k * s + k];
    }
}

static void
upper_solve(const double *L, size_t s, size_t n, double *y)
{
    size_t k, q;
    for (k = n; k-- > 0;) {
        double v = y[k];
        for (q = k + 1; q < n; q++)
            v -= L[q * s + k] * y[q];
        y[k] = v / L[k * s + k];
    }
}

void
lf_small_chol_solve(const double *L, size_t s, size_t n, double *y)
{
    lower_solve(L, s, n, y);
    upper_solve(L, s, n, y);
}

int
lf_arrow_factor(fit_arrow_chol *L, const fit_arrow *a, const double *d2, double mu, double rel)
{
    const size_t m = a->m;
    double S[FIT_MMAX * FIT_MMAX], hd[FIT_MMAX];
    size_t j, r, c, k;

    L->ok = 0;
    memcpy(S, a->head, sizeof S);
    if (d2 != NULL)
        for (r = 0; r < m; r++)
            H_AT(S, r, r) += mu * d2[r];
    for (j = 0; j < a->n; j++) {
        const double *cb = a->cb + j * FIT_CB;
        double *cf = L->cf + j * FIT_CF, Bd[FIT_QMAX * FIT_QMAX];
        const size_t q = a->q[j];
        if (q == 0)
            continue;
        memcpy(Bd, &B_AT(cb, 0, 0), sizeof Bd);
        if (d2 != NULL)
            for (r = 0; r < q; r++)
                Bd[r * FIT_QMAX + r] += mu * d2[a->at[j] + r];
        if (!lf_small_chol(Bd, FIT_QMAX, q, rel, NULL, cf))
            return 0;
        /* E_j = L_j^-1 C_j, column by column, and its share of S */
        for (c = 0; c < m; c++) {
            double y[FIT_QMAX];
            for (r = 0; r < q; r++)
                y[r] = C_AT(cb, r, c);
            lower_solve(cf, FIT_QMAX, q, y);
            for (r = 0; r < q; r++)
                EJ_AT(cf, r, c) = y[r];
        }
        for (r = 0; r < m; r++)
            for (c = 0; c <= r; c++) {
                double s = 0.0;
                for (k = 0; k < q; k++)
                    s += EJ_AT(cf, k, r) * EJ_AT(cf, k, c);
                H_AT(S, r, c) -= s;
            }
    }
    /* S's pivots against the head's own (damped) diagonal */
    for (r = 0; r < m; r++)
        hd[r] = H_AT(a->head, r, r) + (d2 != NULL ? mu * d2[r] : 0.0);
    if (!lf_small_chol(S, FIT_MMAX, m, rel, hd, L->ls))
        return 0;
    L->ok = 1;
    return 1;
}

/* The forward half of a solve: y_j = L_j^-1 b_j into y's curve parts,
 * z = L_s^-1 (b_m - sum E_j^T y_j) into y's head. */
static void
forward(const fit_arrow_chol *L, const double *b, double *y)
{
    const size_t m = L->m;
    double z[FIT_MMAX];
    size_t j, r, c;

    for (r = 0; r < m; r++)
        z[r] = b[r];
    for (j = 0; j < L->n; j++) {
        const double *cf = L->cf + j * FIT_CF;
        const size_t q = L->q[j], at = L->at[j];
        if (q == 0)
            continue;
        for (r = 0; r < q; r++)
            y[at + r] = b[at + r];
        lower_solve(cf, FIT_QMAX, q, y + at);
        for (c = 0; c < m; c++)
            for (r = 0; r < q; r++)
                z[c] -= EJ_AT(cf, r, c) * y[at + r];
    }
    lower_solve(L->ls, FIT_MMAX, m, z);
    for (r = 0; r < m; r++)
        y[r] = z[r];
}

double
lf_arrow_norm2(const fit_arrow_chol *L, const double *b, double *y)
{
    double s = 0.0;
    size_t k;

    forward(L, b, y);
    for (k = 0; k < L->p; k++)
        s += y[k] * y[k];
    return s;
}

void
lf_arrow_solve(const fit_arrow_chol *L, const double *b, double *x)
{
    const size_t m = L->m;
    size_t j, r, c;

    forward(L, b, x);
    upper_solve(L->ls, FIT_MMAX, m, x);
    for (j = 0; j < L->n; j++) {
        const double *cf = L->cf + j * FIT_CF;
        const size_t q = L->q[j], at = L->at[j];
        for (r = 0; r < q; r++)
            for (c = 0; c < m; c++)
                x[at + r] -= EJ_AT(cf, r, c) * x[c];
        upper_solve(cf, FIT_QMAX, q, x + at);
    }
}

/* W = L_s^-1 (m x m lower, stride FIT_MMAX): S^-1 = W^T W. */
static void
head_inverse(const fit_arrow_chol *L, double *W)
{
    const size_t m = L->m;
    size_t c, r;

    memset(W, 0, FIT_MMAX * FIT_MMAX * sizeof *W);
    for (c = 0; c < m; c++) {
        double y[FIT_MMAX] = { 0 };
        y[c] = 1.0;
        lower_solve(L->ls, FIT_MMAX, m, y);
        for (r = 0; r < m; r++)
            W[r * FIT_MMAX + c] = y[r];
    }
}

/* Curve j's F = B_j^-1 C_j = L_j^-T E_j (q x m, stride FIT_MMAX) and
 * Linv = L_j^-1 (q x q lower, stride FIT_QMAX). */
static void
curve_inverse(const fit_arrow_chol *L, size_t j, double *F, double *Linv)
{
    const double *cf = L->cf + j * FIT_CF;
    const size_t q = L->q[j], m = L->m;
    size_t r, c;

    for (c = 0; c < m; c++) {
        double y[FIT_QMAX];
        for (r = 0; r < q; r++)
            y[r] = EJ_AT(cf, r, c);
        upper_solve(cf, FIT_QMAX, q, y);
        for (r = 0; r < q; r++)
            F[r * FIT_MMAX + c] = y[r];
    }
    for (c = 0; c < q; c++) {
        double y[FIT_QMAX] = { 0 };
        y[c] = 1.0;
        lower_solve(cf, FIT_QMAX, q, y);
        for (r = 0; r < q; r++)
            Linv[r * FIT_QMAX + c] = y[r];
    }
}

void
lf_arrow_inv_diag(const fit_arrow_chol *L, double *d)
{
    const size_t m = L->m;
    double W[FIT_MMAX * FIT_MMAX], F[FIT_QMAX * FIT_MMAX], Li[FIT_QMAX * FIT_QMAX];
    size_t j, r, c, k;

    head_inverse(L, W);
    for (c = 0; c < m; c++) {
        double s = 0.0;
        for (r = c; r < m; r++)
            s += W[r * FIT_MMAX + c] * W[r * FIT_MMAX + c];
        d[c] = s;
    }
    for (j = 0; j < L->n; j++) {
        const size_t q = L->q[j], at = L->at[j];
        if (q == 0)
            continue;
        curve_inverse(L, j, F, Li);
        for (r = 0; r < q; r++) {
            double s = 0.0;
            for (k = r; k < q; k++)          /* (B^-1)_rr = |column r of L^-1|^2 */
                s += Li[k * FIT_QMAX + r] * Li[k * FIT_QMAX + r];
            for (k = 0; k < m; k++) {        /* |W f_r|^2, f_r row r of F */
                double v = 0.0;
                for (c = 0; c <= k; c++)
                    v += W[k * FIT_MMAX + c] * F[r * FIT_MMAX + c];
                s += v * v;
            }
            d[at + r] = s;
        }
    }
}

/* ---- the inverse, kept block by block ---------------------------------- */

int
lf_arrow_inv_alloc(fit_arrow_inv *V, size_t m, size_t n, const unsigned char *q,
                   const size_t *at, size_t p)
{
    memset(V, 0, sizeof *V);
    V->m = m;
    V->n = n;
    V->p = p;
    V->q = malloc(n ? n : 1);
    V->at = malloc((n ? n : 1) * sizeof *V->at);
    V->cb = calloc(n ? n * FIT_CB : 1, sizeof *V->cb);
    if (V->q == NULL || V->at == NULL || V->cb == NULL) {
        lf_arrow_inv_free(V);
        return LF_ENOMEM;
    }
    memcpy(V->q, q, n);
    memcpy(V->at, at, n * sizeof *V->at);
    return LF_OK;
}

int
lf_arrow_inv_make(fit_arrow_inv *V, const fit_arrow_chol *L)
{
    const size_t m = L->m;
    double W[FIT_MMAX * FIT_MMAX], Li[FIT_QMAX * FIT_QMAX];
    size_t j, r, c, k;

    if (lf_arrow_inv_alloc(V, m, L->n, L->q, L->at, L->p) != LF_OK)
        return LF_ENOMEM;
    head_inverse(L, W);
    for (r = 0; r < m; r++)         /* S^-1 = W^T W */
        for (c = 0; c < m; c++) {
            double s = 0.0;
            for (k = r > c ? r : c; k < m; k++)
                s += W[k * FIT_MMAX + r] * W[k * FIT_MMAX + c];
            H_AT(V->head, r, c) = s;
        }
    for (j = 0; j < L->n; j++) {
        double *cb = V->cb + j * FIT_CB;
        const size_t q = L->q[j];
        if (q == 0)
            continue;
        /* C holds F = B^-1 C (the inverse's coupling is -F S^-1), B holds
         * B^-1 (the inverse's block is B^-1 + F S^-1 F^T) */
        curve_inverse(L, j, &C_AT(cb, 0, 0), Li);
        for (r = 0; r < q; r++)
            for (c = 0; c < q; c++) {
                double s = 0.0;
                for (k = r > c ? r : c; k < q; k++)
                    s += Li[k * FIT_QMAX + r] * Li[k * FIT_QMAX + c];
                B_AT(cb, r, c) = s;
            }
    }
    return LF_OK;
}

void
lf_arrow_inv_apply(const fit_arrow_inv *V, const double *v, double *out)
{
    const size_t m = V->m;
    double t[FIT_MMAX], u[FIT_MMAX];
    size_t j, r, c;

    /* [[B' + F S F^T, -F S], [-S F^T, S]] v: t = v_m - F^T v_c, u = S t */
    for (c = 0; c < m; c++)
        t[c] = v[c];
    for (j = 0; j < V->n; j++) {
        const double *cb = V->cb + j * FIT_CB, *vj = v + V->at[j];
        for (r = 0; r < V->q[j]; r++)
            for (c = 0; c < m; c++)
                t[c] -= C_AT(cb, r, c) * vj[r];
    }
    for (r = 0; r < m; r++) {
        double s = 0.0;
        for (c = 0; c < m; c++)
            s += H_AT(V->head, r, c) * t[c];
        u[r] = s;
    }
    for (j = 0; j < V->n; j++) {
        const double *cb = V->cb + j * FIT_CB, *vj = v + V->at[j];
        double *oj = out + V->at[j];
        for (r = 0; r < V->q[j]; r++) {
            double s = 0.0;
            for (c = 0; c < V->q[j]; c++)
                s += B_AT(cb, r, c) * vj[c];
            for (c = 0; c < m; c++)
                s -= C_AT(cb, r, c) * u[c];
            oj[r] = s;
        }
    }
    for (r = 0; r < m; r++)
        out[r] = u[r];
}

void
lf_arrow_inv_free(fit_arrow_inv *V)
{
    free(V->q);
    free(V->at);
    free(V->cb);
    memset(V, 0, sizeof *V);
}

/* Row r of F S^-1 (curve cb's local row r) into out[0..m). */
static void
fs_row(const fit_arrow_inv *V, const double *cb, size_t r, double *out)
{
    size_t c, k;
    for (c = 0; c < V->m; c++) {
        double s = 0.0;
        for (k = 0; k < V->m; k++)
            s += C_AT(cb, r, k) * H_AT(V->head, k, c);
        out[c] = s;
    }
}

double
lf_arrow_inv_get(const fit_arrow_inv *V, size_t a, size_t b)
{
    const size_t m = V->m;
    size_t ja, jb, ra, rb, k;
    const double *ca, *cbb;
    double fa[FIT_MMAX], s;

    if (a >= V->p || b >= V->p)
        return NAN;
    if (a < m && b < m)
        return H_AT(V->head, a, b);
    if (a < m) {            /* b the curve's */
        size_t t = a;
        a = b;
        b = t;
    }
    ja = owner(V->at, V->n, a);
    ra = a - V->at[ja];
    ca = V->cb + ja * FIT_CB;
    fs_row(V, ca, ra, fa);
    if (b < m)
        return -fa[b];
    jb = owner(V->at, V->n, b);
    rb = b - V->at[jb];
    cbb = V->cb + jb * FIT_CB;
    for (k = 0, s = 0.0; k < m; k++)
        s += fa[k] * C_AT(cbb, rb, k);
    if (ja == jb)
        s += B_AT(ca, ra, rb);
    return s;
}

/* ---- small dense kernels (decomp.c, decomp_block.c) ---------------------- */

/* The Euclidean norm of column k of A (n rows from row r0, row stride
 * tda): the plain sum of squares unless it over- or underflowed, then
 * BLAS's scaled one. */
double
lf_fit_column_norm(const double *A, size_t tda, size_t r0, size_t n, size_t k)
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
void
lf_fit_householder_qr(double *A, size_t tda, size_t n, size_t p, double *tau)
{
    size_t i, k, l;

    for (k = 0; k < p; k++) {
        double *akk = A + k * tda + k;
        const double alpha = *akk, xnorm = lf_fit_column_norm(A, tda, k + 1, n, k);
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

