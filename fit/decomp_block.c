/* decomp_block.c: the decomposition of decomp.c for a joint fit of many
 * curves, in time and memory that grow with the number of curves.
 *
 * decomp.c decomposes the column-scaled Jacobian Js = J D^-1 whole (a QR
 * of its rows and the SVD of the p x p R): O(n p^2) time and O(n p)
 * memory, with p = m + sum q_j (the material's m, each curve's own q_j).
 * Here the same verdicts come from its block structure: the rows of curve
 * j touch only the material's columns and curve j's own, so Js^T Js is an
 * arrowhead (block.c).
 *
 * Well conditioned (the common case, and decomp.c's route through J^T J):
 * the largest and smallest eigenvalues of Js^T Js are found by bisection
 * on the count of its eigenvalues below s, which Sylvester's law of
 * inertia gives from the block elimination (each curve's block B_j -
 * s I through its own eigenvalues, then the m x m Schur complement;
 * Parlett, "The symmetric eigenvalue problem", 1998, sec. 3.3): when every
 * singular value is above FIT_DECOMP_NORMAL_COND S_0 and FIT_DECOMP_NORMAL_
 * MARGIN rcond S_0, every parameter is determined and the covariance is
 * the inverse of the arrowhead (block.c's blocks).
 *
 * Otherwise the rank needs Js itself: a QR of each curve's rows, its own
 * columns first, gives R_jj (q x q), R_jm (q x m) and a remainder T_j (m x
 * m); the remainders stacked and reduced give R_mm.  Then Js = Q R with R
 * block upper triangular, and with x = y - F a (F_j = R_jj^+ R_jm) the
 * quadratic form |R v|^2 splits into |R_cc y|^2 + |R_mm a|^2: a direction
 * the data do not determine is either a curve's own (a singular value of
 * R_jj below rcond S_0: the curve's own columns dependent) or one through
 * the material, v = (-F a, a) with a a generalised singular vector of
 * (R_mm, I + F^T F) whose value is below rcond S_0 (to first order in its
 * square over the curve blocks' own: those directions lie far apart when
 * the data leave one undetermined; the rows of R_jj's own undetermined
 * directions, U_l^T [R_jj R_jm] with R_jj's part cut, join R_mm's).  The
 * covariance over the determined
 * directions is the pseudo-inverse P X P, X = T diag(B^+, S^+) T^T a
 * reflexive generalised inverse in block form (T the change from (y, a) to
 * (x, a), S^+ over the determined generalised directions), P the
 * projector onto the determined ones; a curve's own undetermined
 * directions are X's null space already, so only the m or fewer through
 * the material are kept as vectors. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "fit.h"

#define G_C(cb, r, c) ((cb)[(r) * FIT_MMAX + (c)])
#define G_B(cb, r, c) ((cb)[FIT_QMAX * FIT_MMAX + (r) * FIT_QMAX + (c)])
#define G_H(h, r, c) ((h)[(r) * FIT_MMAX + (c)])
#define KMAX (FIT_MMAX + FIT_QMAX)      /* a curve's columns */
#define BISECT 64

void
lf_fit_bdec_free(fit_bdec *b)
{
    if (b == NULL)
        return;
    lf_arrow_free(&b->G);
    lf_arrow_inv_free(&b->X);
    free(b->D);
    free(b->lw);
    free(b->V);
    free(b->eig);
    memset(b, 0, sizeof *b);
}

void
lf_fit_bdec_trim(fit_bdec *b)
{
    lf_arrow_free(&b->G);
    free(b->eig);
    b->eig = NULL;
}

/* Symmetric eigenvalues (and vectors, W not NULL: column k the k-th) of
 * the n x n matrix A (stride s) by Jacobi rotations; n <= FIT_MMAX. */
static void
small_eig(const double *A, size_t s, size_t n, double *lam, double *W)
{
    double a[FIT_MMAX * FIT_MMAX], w[FIT_MMAX * FIT_MMAX];
    gsl_matrix_view av = gsl_matrix_view_array(a, n, n), wv = gsl_matrix_view_array(w, n, n);
    gsl_vector_view lv = gsl_vector_view_array(lam, n);
    unsigned int nrot;
    size_t r, c;

    for (r = 0; r < n; r++)
        for (c = 0; c < n; c++)
            a[r * n + c] = 0.5 * (A[r * s + c] + A[c * s + r]);
    gsl_eigen_jacobi(&av.matrix, &lv.vector, &wv.matrix, 100, &nrot);
    if (W != NULL)
        for (r = 0; r < n; r++)
            for (c = 0; c < n; c++)
                W[r * s + c] = w[r * n + c];
}

/* Robust sums of squares (LAPACK's dlassq): a column's norm is
 * scale sqrt(ssq). */
static void
lassq(double v, double *scale, double *ssq)
{
    double a = fabs(v);
    if (!(a > 0))
        return;
    if (*scale < a) {
        *ssq = 1.0 + *ssq * (*scale / a) * (*scale / a);
        *scale = a;
    } else {
        *ssq += (a / *scale) * (a / *scale);
    }
}

/* The number of eigenvalues of the scaled Gram below s (Sylvester's law
 * of inertia through the block elimination), from each curve's own
 * eigenvalues (b->eig: q values, then W^T C, q x m) and the head. */
static size_t
count_below(const fit_bdec *b, double s)
{
    const size_t m = b->m;
    double S[FIT_MMAX * FIT_MMAX], lam[FIT_MMAX];
    size_t j, r, c, i, neg = 0;

    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            S[r * FIT_MMAX + c] = G_H(b->G.head, r, c) - (r == c ? s : 0.0);
    for (j = 0; j < b->n; j++) {
        const double *e = b->eig + j * FIT_EIG;
        for (i = 0; i < b->G.q[j]; i++) {
            const double *ch = e + FIT_QMAX + i * FIT_MMAX;
            double d = e[i] - s;
            neg += d < 0;
            if (d == 0.0)
                d = -1e-300;
            for (r = 0; r < m; r++)
                for (c = 0; c <= r; c++)
                    S[r * FIT_MMAX + c] -= ch[r] * ch[c] / d;
        }
    }
    for (r = 0; r < m; r++)
        for (c = 0; c < r; c++)
            S[c * FIT_MMAX + r] = S[r * FIT_MMAX + c];
    small_eig(S, FIT_MMAX, m, lam, NULL);
    for (r = 0; r < m; r++)
        neg += !(lam[r] >= 0);
    return neg;
}

/* Each curve's own eigenvalues and W^T C into b->eig (count_below). */
static void
curve_spectra(fit_bdec *b)
{
    const size_t m = b->m;
    size_t j, i, r, c;

    for (j = 0; j < b->n; j++) {
        const double *cb = b->G.cb + j * FIT_CB;
        double *e = b->eig + j * FIT_EIG, W[FIT_MMAX * FIT_MMAX];
        const size_t q = b->G.q[j];
        if (q == 0)
            continue;
        small_eig(&G_B(cb, 0, 0), FIT_QMAX, q, e, W);     /* W: stride FIT_QMAX */
        for (i = 0; i < q; i++)
            for (c = 0; c < m; c++) {
                double s = 0.0;
                for (r = 0; r < q; r++)
                    s += W[r * FIT_QMAX + i] * G_C(cb, r, c);
                e[FIT_QMAX + i * FIT_MMAX + c] = s;
            }
    }
}

/* The largest eigenvalue of the scaled Gram: the least s with every
 * eigenvalue below it. */
static double
largest(const fit_bdec *b)
{
    double lo = 0.0, hi = 0.0;
    size_t k, it;

    /* Gershgorin: no eigenvalue above the largest absolute row sum */
    {
        double *row = calloc(b->p, sizeof *row);
        size_t j, r, c;
        if (row == NULL)
            return NAN;
        for (r = 0; r < b->m; r++)
            for (c = 0; c < b->m; c++)
                row[r] += fabs(G_H(b->G.head, r, c));
        for (j = 0; j < b->n; j++) {
            const double *cb = b->G.cb + j * FIT_CB;
            const size_t at = b->G.at[j];
            for (r = 0; r < b->G.q[j]; r++) {
                for (c = 0; c < b->m; c++) {
                    row[at + r] += fabs(G_C(cb, r, c));
                    row[c] += fabs(G_C(cb, r, c));
                }
                for (c = 0; c < b->G.q[j]; c++)
                    row[at + r] += fabs(G_B(cb, r, c));
            }
        }
        for (k = 0; k < b->p; k++)
            hi = lf_fmax(hi, row[k]);
        free(row);
    }
    hi *= 1.0 + 1e-12;
    for (it = 0; it < BISECT * 2 && hi - lo > 4e-16 * hi; it++) {
        const double mid = 0.5 * (lo + hi);
        if (count_below(b, mid) >= b->p)
            hi = mid;
        else
            lo = mid;
    }
    return hi;
}

/* The smallest eigenvalue of the scaled Gram within [lo, hi] (count 0 at
 * lo, at least 1 at hi), by bisection in its logarithm. */
static double
smallest(const fit_bdec *b, double lo, double hi)
{
    size_t it;

    for (it = 0; it < 2 * BISECT && hi - lo > 4e-16 * hi; it++) {
        const double mid = lo > 0 && hi / lo > 4.0 ? sqrt(lo * hi) : 0.5 * (lo + hi);
        if (count_below(b, mid) >= 1)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* ---- the pass over the curves' rows ------------------------------------ */

/* Room for a run at f's layout, with nu's column or not. */
static int
bdec_alloc(fit_bdec *b, const lf_fit *f, int with_nu)
{
    int st;

    memset(b, 0, sizeof *b);
    st = lf_fit_arrow_alloc(f, (size_t) with_nu, &b->G);
    if (st != LF_OK)
        return st;
    b->m = b->G.m;
    b->n = f->ncurves;
    b->p = b->G.p;
    b->D = calloc(b->p, sizeof *b->D);
    b->lw = calloc(b->p, sizeof *b->lw);
    b->V = calloc(2 * FIT_MMAX * b->p, sizeof *b->V);
    b->eig = calloc(b->n ? b->n * FIT_EIG : 1, sizeof *b->eig);
    if (b->D == NULL || b->lw == NULL || b->V == NULL || b->eig == NULL)
        return LF_ENOMEM;
    b->Y = b->V + FIT_MMAX * b->p;
    return LF_OK;
}

/* The nu prior's row as a material row (its one entry in nu's column,
 * scaled by inv_d), into row[0..m). */
static int
prior_row(const lf_fit *f, const double *x, const fit_bdec *b, double scale, double *row)
{
    size_t c;

    if (!f->nu_prior)
        return 0;
    for (c = 0; c < b->m; c++)
        row[c] = 0.0;
    row[f->imat[FIT_NU]] = lf_fit_prior_entry(f, x, 1) * scale;
    return 1;
}

/* Pass one: the unscaled Gram of the physical Jacobian into b->G and the
 * columns' norms into b->D. */
static int
gram_pass(fit_bdec *b, lf_fit *f, const double *x, int with_nu, double *rows)
{
    const size_t m = b->m, p = b->p;
    double *scale = calloc(2 * p, sizeof *scale), *ssq = scale + p, prow[FIT_MMAX];
    size_t j, i, k, l, mc;

    if (scale == NULL)
        return LF_ENOMEM;
    lf_arrow_zero(&b->G);
    for (j = 0; j < b->n; j++) {
        const size_t q = b->G.q[j], kc = m + q, at = b->G.at[j];
        double *cb = b->G.cb + j * FIT_CB;
        if (lf_fit_curve_rows(f, x, j, NULL, NULL, with_nu, rows, &mc) != GSL_SUCCESS || mc != m) {
            free(scale);
            return LF_ENUMERIC;
        }
        for (i = 0; i < f->c[j].data.n; i++) {
            const double *v = rows + i * kc;
            for (k = 0; k < kc; k++) {
                const size_t gk = k < m ? k : at + k - m;
                lassq(v[k], &scale[gk], &ssq[gk]);
                for (l = 0; l <= k; l++) {
                    const double a = v[k] * v[l];
                    if (k < m)
                        G_H(b->G.head, k, l) += a;
                    else if (l < m)
                        G_C(cb, k - m, l) += a;
                    else
                        G_B(cb, k - m, l - m) += a;
                }
            }
        }
        for (k = 0; k < q; k++)
            for (l = 0; l < k; l++)
                G_B(cb, l, k) = G_B(cb, k, l);
    }
    if (prior_row(f, x, b, 1.0, prow))
        for (k = 0; k < m; k++) {
            lassq(prow[k], &scale[k], &ssq[k]);
            for (l = 0; l <= k; l++)
                G_H(b->G.head, k, l) += prow[k] * prow[l];
        }
    for (k = 0; k < m; k++)
        for (l = 0; l < k; l++)
            G_H(b->G.head, l, k) = G_H(b->G.head, k, l);
    for (k = 0; k < p; k++)
        b->D[k] = scale[k] * sqrt(ssq[k]);
    free(scale);
    return LF_OK;
}

/* Scale the Gram to unit diagonal (columns of zeros stay zero); 0 when a
 * diagonal is not 1 to rounding afterwards (its squares under- or
 * overflowed: the norms know better). */
static int
scale_gram(fit_bdec *b)
{
    const size_t m = b->m;
    double *D = b->D, inv[FIT_MMAX];
    size_t j, r, c;
    int ok = 1;

    for (r = 0; r < m; r++)
        inv[r] = D[r] > 0 ? 1.0 / D[r] : 0.0;
    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            G_H(b->G.head, r, c) *= inv[r] * inv[c];
    for (r = 0; r < m; r++)
        ok &= D[r] == 0.0 || fabs(G_H(b->G.head, r, r) - 1.0) < 1e-9;
    for (j = 0; j < b->n; j++) {
        double *cb = b->G.cb + j * FIT_CB, iq[FIT_QMAX];
        const size_t at = b->G.at[j];
        for (r = 0; r < b->G.q[j]; r++)
            iq[r] = D[at + r] > 0 ? 1.0 / D[at + r] : 0.0;
        for (r = 0; r < b->G.q[j]; r++) {
            for (c = 0; c < m; c++)
                G_C(cb, r, c) *= iq[r] * inv[c];
            for (c = 0; c < b->G.q[j]; c++)
                G_B(cb, r, c) *= iq[r] * iq[c];
            ok &= D[at + r] == 0.0 || fabs(G_B(cb, r, r) - 1.0) < 1e-9;
        }
    }
    return ok;
}

/* ---- the rank from R --------------------------------------------------- */

/* Reduce the m x m upper triangle Rm with the rows T (t x m, stride m):
 * QR of [Rm; T] (Householder), Rm its new R. */
static void
stack_rows(double *Rm, size_t m, const double *T, size_t t)
{
    double A[(FIT_MMAX + KMAX) * FIT_MMAX], tau[FIT_MMAX];
    size_t r, c;

    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            A[r * m + c] = c >= r ? Rm[r * FIT_MMAX + c] : 0.0;
    for (r = 0; r < t; r++)
        for (c = 0; c < m; c++)
            A[(m + r) * m + c] = T[r * m + c];
    lf_fit_householder_qr(A, m, m + t, m, tau);
    for (r = 0; r < m; r++)
        for (c = 0; c < m; c++)
            Rm[r * FIT_MMAX + c] = c >= r ? A[r * m + c] : 0.0;
}

/* SVD of the n x n matrix A (stride s; n <= FIT_MMAX): A = U S V^T, U into
 * A's place (stride s), V (stride s), S descending. */
static int
small_svd(double *A, size_t s, size_t n, double *S, double *V)
{
    double a[FIT_MMAX * FIT_MMAX], v[FIT_MMAX * FIT_MMAX];
    gsl_matrix_view av = gsl_matrix_view_array(a, n, n), vv = gsl_matrix_view_array(v, n, n);
    gsl_vector_view sv = gsl_vector_view_array(S, n);
    size_t r, c;

    for (r = 0; r < n; r++)
        for (c = 0; c < n; c++)
            a[r * n + c] = A[r * s + c];
    if (gsl_linalg_SV_decomp_jacobi(&av.matrix, &vv.matrix, &sv.vector) != GSL_SUCCESS)
        return LF_ENUMERIC;
    for (r = 0; r < n; r++)
        for (c = 0; c < n; c++) {
            A[r * s + c] = a[r * n + c];
            V[r * s + c] = v[r * n + c];
        }
    return LF_OK;
}

/* The left singular vectors of singular values below tau (columns of U,
 * n x n, stride s, S descending) made an orthonormal completion of the
 * others: one-sided Jacobi normalises what is left of such a column,
 * rounding, into a direction of no meaning. */
static void
complete_left(double *U, size_t s, size_t n, const double *S, double tau)
{
    size_t l, k, e, r;

    for (l = 0; l < n; l++) {
        double best[FIT_MMAX], bn = -1.0;
        if (S[l] >= tau)
            continue;
        for (e = 0; e < n; e++) {         /* e_e less its part along U's others */
            double u[FIT_MMAX], nn = 0.0;
            for (r = 0; r < n; r++)
                u[r] = r == e ? 1.0 : 0.0;
            for (k = 0; k < n; k++) {
                double d = 0.0;
                if (k == l || (k > l && S[k] < tau))
                    continue;             /* itself, and those still to come */
                for (r = 0; r < n; r++)
                    d += U[r * s + k] * u[r];
                for (r = 0; r < n; r++)
                    u[r] -= d * U[r * s + k];
            }
            for (r = 0; r < n; r++)
                nn += u[r] * u[r];
            if (nn > bn) {
                bn = nn;
                memcpy(best, u, n * sizeof *u);
            }
        }
        for (r = 0; r < n; r++)
            U[r * s + l] = best[r] / sqrt(bn);
    }
}

/* Pass two, where the Gram cannot decide: the rank, the undetermined
 * directions and the generalised inverse from the R of Js (see the top). */
static int
rank_pass(fit_bdec *b, lf_fit *f, const double *x, int with_nu, double rcond, double *rows)
{
    const size_t m = b->m, p = b->p;
    const double tau = rcond * b->s0;
    double Rm[FIT_MMAX * FIT_MMAX] = { 0 }, M[FIT_MMAX * FIT_MMAX] = { 0 };
    double L[FIT_MMAX * FIT_MMAX], K[FIT_MMAX * FIT_MMAX], Yv[FIT_MMAX * FIT_MMAX];
    double sig[FIT_MMAX], Sp[FIT_MMAX * FIT_MMAX] = { 0 }, prow[FIT_MMAX];
    double *qr = NULL;
    size_t j, i, r, c, k, l, mc, nmax = 0, nlocal = 0;
    int st = LF_OK;

    for (j = 0; j < b->n; j++)
        nmax = f->c[j].data.n > nmax ? f->c[j].data.n : nmax;
    qr = malloc((nmax > KMAX ? nmax : KMAX) * KMAX * sizeof *qr);
    if (qr == NULL)
        return LF_ENOMEM;
    lf_arrow_inv_free(&b->X);
    if (lf_arrow_inv_alloc(&b->X, m, b->n, b->G.q, b->G.at, p) != LF_OK) {
        free(qr);
        return LF_ENOMEM;
    }
    memset(b->lw, 0, p * sizeof *b->lw);
    b->smin = b->s0;
    for (j = 0; j < b->n; j++) {
        const size_t q = b->G.q[j], kc = m + q, at = b->G.at[j], n = f->c[j].data.n;
        const size_t nr = n > kc ? n : kc;
        double tauq[KMAX], Rjj[FIT_MMAX * FIT_MMAX], Vj[FIT_MMAX * FIT_MMAX], sj[FIT_MMAX];
        double T[FIT_MMAX * FIT_MMAX], *cb = b->X.cb + j * FIT_CB;
        if (lf_fit_curve_rows(f, x, j, NULL, NULL, with_nu, rows, &mc) != GSL_SUCCESS || mc != m) {
            st = LF_ENUMERIC;
            break;
        }
        /* the curve's rows scaled, its own columns first (zero rows pad
         * a curve shorter than its columns) */
        for (i = 0; i < nr; i++)
            for (k = 0; k < kc; k++) {
                const size_t src = k < q ? m + k : k - q, gk = k < q ? at + k : k - q;
                qr[i * kc + k] = i < n && b->D[gk] > 0 ? rows[i * kc + src] / b->D[gk] : 0.0;
            }
        lf_fit_householder_qr(qr, kc, nr, kc, tauq);
        for (r = 0; r < m; r++)
            for (c = 0; c < m; c++)
                T[r * m + c] = c >= r ? qr[(q + r) * kc + q + c] : 0.0;
        stack_rows(Rm, m, T, m);
        if (q == 0)
            continue;
        for (r = 0; r < q; r++)
            for (c = 0; c < q; c++)
                Rjj[r * FIT_MMAX + c] = c >= r ? qr[r * kc + c] : 0.0;
        if ((st = small_svd(Rjj, FIT_MMAX, q, sj, Vj)) != LF_OK)
            break;
        complete_left(Rjj, FIT_MMAX, q, sj, tau);
        /* R_jj = U S V^T: its own undetermined directions, F = R^+ R_jm,
         * B^+ = V S^-2 V^T over the rest */
        for (l = 0; l < q; l++) {
            double row[FIT_MMAX];
            b->smin = lf_fmin(b->smin, sj[l]);
            if (!(sj[l] < tau))
                continue;
            nlocal++;
            for (r = 0; r < q; r++)
                b->lw[at + r] += Vj[r * FIT_MMAX + l] * Vj[r * FIT_MMAX + l];
            /* the row U_l^T [R_jj R_jm] = [~0, U_l^T R_jm] speaks of the
             * material alone: it joins R_mm's rows */
            for (c = 0; c < m; c++) {
                double v = 0.0;
                for (k = 0; k < q; k++)
                    v += Rjj[k * FIT_MMAX + l] * qr[k * kc + q + c];
                row[c] = v;
            }
            if (m > 0)
                stack_rows(Rm, m, row, 1);
        }
        for (r = 0; r < q; r++) {
            for (c = 0; c < m; c++) {
                double s = 0.0;
                for (l = 0; l < q; l++) {
                    double ur = 0.0;      /* (U^T R_jm)_lc */
                    if (!(sj[l] >= tau))
                        continue;
                    for (k = 0; k < q; k++)
                        ur += Rjj[k * FIT_MMAX + l] * qr[k * kc + q + c];
                    s += Vj[r * FIT_MMAX + l] * ur / sj[l];
                }
                G_C(cb, r, c) = s;
            }
            for (c = 0; c < q; c++) {
                double s = 0.0;
                for (l = 0; l < q; l++)
                    if (sj[l] >= tau)
                        s += Vj[r * FIT_MMAX + l] * Vj[c * FIT_MMAX + l] / (sj[l] * sj[l]);
                G_B(cb, r, c) = s;
            }
        }
        for (r = 0; r < m; r++)          /* M = I + sum F^T F */
            for (c = 0; c < m; c++)
                for (k = 0; k < q; k++)
                    M[r * FIT_MMAX + c] += G_C(cb, k, r) * G_C(cb, k, c);
    }
    free(qr);
    if (st != LF_OK)
        return st;
    if (f->nu_prior
        && prior_row(f, x, b, b->D[f->imat[FIT_NU]] > 0 ? 1.0 / b->D[f->imat[FIT_NU]] : 0.0,
                     prow))
        stack_rows(Rm, m, prow, 1);
    /* the directions through the material: (R_mm, I + F^T F) */
    b->k = 0;
    if (m > 0) {
        for (r = 0; r < m; r++)
            M[r * FIT_MMAX + r] += 1.0;
        memset(L, 0, sizeof L);
        for (r = 0; r < m; r++)           /* L L^T = M */
            for (c = 0; c <= r; c++) {
                double v = M[r * FIT_MMAX + c];
                for (k = 0; k < c; k++)
                    v -= L[r * FIT_MMAX + k] * L[c * FIT_MMAX + k];
                if (r == c) {
                    if (!(v > 0))
                        return LF_ENUMERIC;
                    L[r * FIT_MMAX + r] = sqrt(v);
                } else {
                    L[r * FIT_MMAX + c] = v / L[c * FIT_MMAX + c];
                }
            }
        for (r = 0; r < m; r++)           /* K = R_mm L^-T: row r solves L y = R_mm[r]^T */
            for (c = 0; c < m; c++) {
                double v = Rm[r * FIT_MMAX + c];
                for (k = 0; k < c; k++)
                    v -= L[c * FIT_MMAX + k] * K[r * FIT_MMAX + k];
                K[r * FIT_MMAX + c] = v / L[c * FIT_MMAX + c];
            }
        if ((st = small_svd(K, FIT_MMAX, m, sig, Yv)) != LF_OK)
            return st;
        for (l = 0; l < m; l++) {
            double a[FIT_MMAX], *v;
            for (r = m; r-- > 0;) {        /* a = L^-T y_l */
                double s = Yv[r * FIT_MMAX + l];
                for (k = r + 1; k < m; k++)
                    s -= L[k * FIT_MMAX + r] * a[k];
                a[r] = s / L[r * FIT_MMAX + r];
            }
            b->smin = lf_fmin(b->smin, sig[l]);
            if (sig[l] >= tau) {
                for (r = 0; r < m; r++)
                    for (c = 0; c < m; c++)
                        Sp[r * FIT_MMAX + c] += a[r] * a[c] / (sig[l] * sig[l]);
                continue;
            }
            v = b->V + b->k * p;          /* (-F a, a): unit length */
            for (r = 0; r < m; r++)
                v[r] = a[r];
            for (j = 0; j < b->n; j++) {
                const double *cb = b->X.cb + j * FIT_CB;
                for (r = 0; r < b->G.q[j]; r++) {
                    double s = 0.0;
                    for (c = 0; c < m; c++)
                        s += G_C(cb, r, c) * a[c];
                    v[b->G.at[j] + r] = -s;
                }
            }
            b->k++;
        }
    }
    memcpy(b->X.head, Sp, sizeof Sp);
    /* P X P: X V and V^T X V */
    for (l = 0; l < b->k; l++)
        lf_arrow_inv_apply(&b->X, b->V + l * p, b->Y + l * p);
    for (l = 0; l < b->k; l++)
        for (k = 0; k < b->k; k++) {
            double s = 0.0;
            for (r = 0; r < p; r++)
                s += b->V[l * p + r] * b->Y[k * p + r];
            b->Z[l * FIT_MMAX + k] = s;
        }
    b->rank = p - nlocal - b->k;
    return LF_OK;
}

int
lf_fit_bdec_run(fit_bdec *b, lf_fit *f, const double *x, int with_nu, double rcond, int from_r)
{
    double *rows = NULL, lmax, lmin, thr;
    size_t j, nmax = 0;
    int st;

    lf_fit_bdec_free(b);
    if ((st = bdec_alloc(b, f, with_nu)) != LF_OK)
        return st;
    for (j = 0; j < f->ncurves; j++)
        nmax = f->c[j].data.n > nmax ? f->c[j].data.n : nmax;
    rows = malloc((nmax ? nmax : 1) * KMAX * sizeof *rows);
    if (rows == NULL)
        return LF_ENOMEM;
    st = gram_pass(b, f, x, with_nu, rows);
    if (st != LF_OK)
        goto done;
    {
        const int unit = scale_gram(b);
        curve_spectra(b);
        lmax = largest(b);
        b->s0 = sqrt(lmax);
        if (!(b->s0 > 0) || !isfinite(b->s0)) {
            st = LF_ENUMERIC;
            goto done;
        }
        /* every singular value above FIT_DECOMP_NORMAL_COND S_0 and the
         * margin over rcond S_0 (decomp.c's route through J^T J): then the
         * inverse of the arrowhead is the covariance */
        thr = lf_fmax(FIT_DECOMP_NORMAL_COND, FIT_DECOMP_NORMAL_MARGIN * rcond);
        thr *= thr * lmax;
        if (!from_r && unit && count_below(b, thr) == 0) {
            fit_arrow_chol L;
            if (lf_arrow_chol_alloc(&L, &b->G) != LF_OK) {
                st = LF_ENOMEM;
                goto done;
            }
            if (lf_arrow_factor(&L, &b->G, NULL, 0.0, 0.0)
                && lf_arrow_inv_make(&b->X, &L) == LF_OK) {
                lmin = smallest(b, thr, 1.0 + 1e-12);
                b->smin = sqrt(lmin);
                b->rank = b->p;
                b->k = 0;
                memset(b->lw, 0, b->p * sizeof *b->lw);
                lf_arrow_chol_free(&L);
                goto done;
            }
            lf_arrow_chol_free(&L);
        }
    }
    st = rank_pass(b, f, x, with_nu, rcond, rows);
    if (st == LF_OK && b->rank == b->p && b->smin >= b->s0 * 1e-4) {
        /* the rank said full where the Gram could not: its smallest
         * eigenvalue by bisection where that is the better figure */
        lmin = smallest(b, 0.0, b->smin * b->smin * (1.0 + 1e-9));
        b->smin = lf_fmin(b->smin, sqrt(lmin));
    }
done:
    free(rows);
    return st;
}

/* ---- what the judgement reads ------------------------------------------ */

double
lf_fit_bdec_nullw(const fit_bdec *b, size_t k)
{
    double w = b->D[k] > 0 ? 0.0 : 1.0;
    size_t l;

    w += b->lw[k];
    for (l = 0; l < b->k; l++)
        w += b->V[l * b->p + k] * b->V[l * b->p + k];
    return w;
}

/* Entry (a, b) of the pseudo-inverse of the scaled Gram over the
 * determined directions. */
static double
pinv_get(const fit_bdec *b, size_t a, size_t c)
{
    double s = lf_arrow_inv_get(&b->X, a, c);
    size_t l, k;

    for (l = 0; l < b->k; l++) {
        const double va = b->V[l * b->p + a], vc = b->V[l * b->p + c];
        s -= va * b->Y[l * b->p + c] + b->Y[l * b->p + a] * vc;
        for (k = 0; k < b->k; k++)
            s += va * b->Z[l * FIT_MMAX + k] * b->V[k * b->p + c];
    }
    return s;
}

double
lf_fit_bdec_cov(const fit_bdec *b, size_t a, size_t c, double scale)
{
    if (!(b->D[a] > 0) || !(b->D[c] > 0))
        return NAN;
    return scale * pinv_get(b, a, c) / (b->D[a] * b->D[c]);
}

void
lf_fit_bdec_pinv(const fit_bdec *b, const double *g, double *out, double *work)
{
    const size_t p = b->p;
    double t[2 * FIT_MMAX];
    size_t l, k, r;

    /* P X P g: t = V^T g; g' = g - V t; X g'; minus V (V^T X g') */
    for (l = 0; l < b->k; l++) {
        double s = 0.0;
        for (r = 0; r < p; r++)
            s += b->V[l * p + r] * g[r];
        t[l] = s;
    }
    for (r = 0; r < p; r++) {
        double s = g[r];
        for (l = 0; l < b->k; l++)
            s -= b->V[l * p + r] * t[l];
        work[r] = s;
    }
    lf_arrow_inv_apply(&b->X, work, out);
    for (l = 0; l < b->k; l++) {
        double s = 0.0;
        for (r = 0; r < p; r++)
            s += b->V[l * p + r] * out[r];
        t[FIT_MMAX + l] = s;
    }
    for (r = 0; r < p; r++)
        for (k = 0; k < b->k; k++)
            out[r] -= b->V[k * p + r] * t[FIT_MMAX + k];
}

/* The result's covariance entry: its dense cov where held, else from the
 * blocks this file decomposed (layerfit.h). */
double
lf_fit_result_cov(const lf_fit_result *r, size_t a, size_t b)
{
    const struct lf_fit_covariance *c = r->covariance;

    if (a >= r->npar || b >= r->npar)
        return NAN;
    if (r->cov != NULL)
        return r->cov[a * r->npar + b];
    if (c == NULL || !c->det[a] || !c->det[b])
        return NAN;
    return lf_fit_bdec_cov(&c->b, a, b, c->scale);
}

double
lf_fit_result_corr(const lf_fit_result *r, size_t a, size_t b)
{
    if (r->corr != NULL && a < r->npar && b < r->npar)
        return r->corr[a * r->npar + b];
    return lf_fit_result_cov(r, a, b)
           / sqrt(lf_fit_result_cov(r, a, a) * lf_fit_result_cov(r, b, b));
}
