/* exact_kernel.c: the Lebedev-Ufliand kernel of an elastic layer on a rigid
 * base and the Nystrom solution of the Fredholm equation of the second kind
 * for an axisymmetric frictionless punch (Lebedev & Ufliand 1958, PMM
 * 22:442; Hayes et al. 1972, J. Biomech. 5:541).
 *
 * Kernel.  kf(z) = int_0^inf g(u) cos(u z) du with g = 1 - L, which decays
 * like u^2 e^(-2u).  For z <= LF_EXACT_ZC it is integrated by Gauss-Legendre
 * panels on u in [0, 40] on a uniform z grid (the cosines advanced by
 * complex rotation, which keeps rounding at n eps) and interpolated by
 * quintic Hermite with the exact first and second derivatives at the nodes
 * (interpolation error ~1e-14: nearly incompressible bonded layers amplify
 * kernel errors by up to s ~ 1e4).  g is not even
 * (L is odd), so kf decays only algebraically; beyond LF_EXACT_ZC the
 * asymptotic series  kf(z) ~ sum_m (-1)^m L^(2m+1)(0) / z^(2m+2)  is used
 * (integration by parts; the remainder is exponentially small, below 1e-12
 * at z = 40 since the poles of L nearest the real axis sit at |Im u| > 0.7).
 * The Taylor coefficients of L come from power-series division.
 *
 * Nystrom.  With t = a x, s = a y, tau = a/h the equation reads
 *   U(x) - (tau/pi) int_0^1 [kf(tau(x-y)) + kf(tau(x+y))] U(y) dy = r(x)
 * for r = 1 (u1) and r = x^k (v).  Gauss-Legendre nodes on [0, 1], one LU
 * factorisation, two right-hand sides; tau-derivatives from
 * A U' = -A' U with the same factors; values at x = 1 by Nystrom
 * interpolation.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_sf_gamma.h>

#include "exact.h"

#define LF_EXACT_ZC 40.0      /* end of the tabulated z range */
#define KF_DZ 0.02            /* z spacing of the kf table */
#define KF_UMAX 40.0          /* u cut: g(40) ~ 1e-32 */
#define KF_PANEL 0.1          /* u panel width */
#define KF_PANEL_NODES 10
#define KF_NASYM 8            /* terms of the asymptotic series */
#define KF_NSER (2 * KF_NASYM + 2)

struct lf_exact_kernel {
    lf_base base;
    double nu;
    size_t nz;        /* nodes z_i = i KF_DZ, i < nz */
    double *kf;       /* kf(z_i) */
    double *dkf;      /* kf'(z_i) */
    double *d2kf;     /* kf''(z_i) */
    double asym[KF_NASYM]; /* kf ~ sum asym[m] / z^(2m+2) */
};

/* Gauss-Legendre rule of n nodes on [0, 1]: Newton on P_n from the
 * Tricomi-type first guess, weights 2/((1-x^2) P_n'(x)^2) halved.  Written
 * here because GSL's glfixed rules for untabulated n carry weight errors
 * near 1e-10, which nearly incompressible layers amplify ~1e4 times. */
void
lf_exact_gauss_legendre(size_t n, double *x, double *w)
{
    size_t i, m = (n + 1) / 2;
    int it;

    for (i = 0; i < m; i++) {
        double z = cos(M_PI * ((double) i + 0.75) / ((double) n + 0.5)), dp = 1.0;
        for (it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = z, dz;
            size_t j;
            for (j = 2; j <= n; j++) {
                double p2 = ((2.0 * (double) j - 1.0) * z * p1 - ((double) j - 1.0) * p0) / (double) j;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) {
                p1 = z;
                p0 = 1.0;
            }
            dp = (double) n * (z * p1 - p0) / (z * z - 1.0);
            dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16)
                break;
        }
        {
            /* recompute P_n' at the converged node */
            double p0 = 1.0, p1 = z;
            size_t j;
            for (j = 2; j <= n; j++) {
                double p2 = ((2.0 * (double) j - 1.0) * z * p1 - ((double) j - 1.0) * p0) / (double) j;
                p0 = p1;
                p1 = p2;
            }
            dp = (double) n * (z * p1 - p0) / (z * z - 1.0);
        }
        /* z decreasing from near 1: node n-1-i on [0,1] is (1+z)/2 */
        x[n - 1 - i] = 0.5 * (1.0 + z);
        x[i] = 0.5 * (1.0 - z);
        w[i] = w[n - 1 - i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
}

double
lf_exact_kappa(double k)
{
    return sqrt(M_PI) * exp(gsl_sf_lngamma(0.5 * k + 1.0) - gsl_sf_lngamma(0.5 * k + 0.5));
}

double
lf_exact_one_minus_L(lf_base base, double nu, double u)
{
    double x2 = 2.0 * u;

    if (u > 300.0)
        return 0.0;
    if (base == LF_BASE_FRICTIONLESS) {
        /* (1 + 2u - e^(-2u)) / (sinh 2u + 2u) */
        if (u < 1e-8)
            return 1.0 - 0.5 * u;
        return (x2 - expm1(-x2)) / (sinh(x2) + x2);
    } else {
        double kap = 3.0 - 4.0 * nu, c0 = 0.5 * (1.0 + kap * kap);
        return (kap * exp(-x2) + 2.0 * u * u + x2 + c0)
               / (kap * cosh(x2) + 2.0 * u * u + c0);
    }
}

/* Taylor coefficients l[0..KF_NSER-1] of L(u) around 0 (L is odd, so the
 * even ones come out zero up to rounding). */
static void
L_series(lf_base base, double nu, double *l)
{
    double num[KF_NSER + 2], den[KF_NSER + 2], fact = 1.0, p2 = 1.0;
    size_t i, j, shift;

    memset(num, 0, sizeof num);
    memset(den, 0, sizeof den);
    /* sinh 2x and cosh 2x coefficients: 2^n / n! */
    for (i = 0; i < KF_NSER + 2; i++) {
        double c = p2 / fact; /* 2^i / i! */
        if (base == LF_BASE_FRICTIONLESS) {
            /* L = (cosh 2x - 1) / (sinh 2x + 2x); both vanish at 0:
             * divide by x, i.e. shift by one. */
            if (i % 2 == 0 && i > 0)
                num[i] = c;
            if (i % 2 == 1)
                den[i] = c;
        } else {
            double kap = 3.0 - 4.0 * nu;
            if (i % 2 == 1)
                num[i] = kap * c;
            if (i % 2 == 0)
                den[i] = kap * c;
        }
        fact *= (double) (i + 1);
        p2 *= 2.0;
    }
    if (base == LF_BASE_FRICTIONLESS) {
        den[1] += 2.0;
        shift = 1;
    } else {
        double kap = 3.0 - 4.0 * nu;
        num[1] -= 2.0;
        den[2] += 2.0;
        den[0] += 0.5 * (1.0 + kap * kap);
        shift = 0;
    }
    /* quotient of num/x^shift by den/x^shift */
    for (i = 0; i < KF_NSER; i++) {
        double acc = num[i + shift];
        for (j = 0; j < i; j++)
            acc -= l[j] * den[i - j + shift];
        l[i] = acc / den[shift];
    }
}

int
lf_exact_kernel_alloc(lf_exact_kernel **out, lf_base base, double nu,
                      lf_error *err)
{
    lf_exact_kernel *kr;
    double glx[KF_PANEL_NODES], glw[KF_PANEL_NODES];
    size_t npanel = (size_t) (KF_UMAX / KF_PANEL + 0.5), ip, iq, i;
    double l[KF_NSER], fact = 1.0;
    int m;

    *out = NULL;
    if (base == LF_BASE_FRICTIONLESS)
        nu = 0.0;
    kr = calloc(1, sizeof *kr);
    if (kr == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory (layer kernel)");
    kr->base = base;
    kr->nu = nu;
    kr->nz = (size_t) (LF_EXACT_ZC / KF_DZ + 0.5) + 1;
    kr->kf = calloc(kr->nz, sizeof *kr->kf);
    kr->dkf = calloc(kr->nz, sizeof *kr->dkf);
    kr->d2kf = calloc(kr->nz, sizeof *kr->d2kf);
    if (kr->kf == NULL || kr->dkf == NULL || kr->d2kf == NULL) {
        lf_exact_kernel_free(kr);
        return lf_fail(err, LF_ENOMEM, "out of memory (layer kernel)");
    }
    lf_exact_gauss_legendre(KF_PANEL_NODES, glx, glw);
    for (ip = 0; ip < npanel; ip++) {
        for (iq = 0; iq < KF_PANEL_NODES; iq++) {
            double u = KF_PANEL * ((double) ip + glx[iq]), wq = KF_PANEL * glw[iq];
            double g, cr, ci, rr, ri;
            g = wq * lf_exact_one_minus_L(base, nu, u);
            if (g == 0.0)
                continue;
            /* e^(i u z_i) advanced by rotation */
            rr = cos(u * KF_DZ);
            ri = sin(u * KF_DZ);
            cr = 1.0;
            ci = 0.0;
            for (i = 0; i < kr->nz; i++) {
                double t;
                kr->kf[i] += g * cr;
                kr->dkf[i] -= g * u * ci;
                kr->d2kf[i] -= g * u * u * cr;
                t = cr * rr - ci * ri;
                ci = cr * ri + ci * rr;
                cr = t;
            }
        }
    }
    L_series(base, nu, l);
    for (m = 0; m < KF_NASYM; m++) {
        /* (-1)^m L^(2m+1)(0) = (-1)^m (2m+1)! l[2m+1] */
        fact *= (m == 0) ? 1.0 : (double) (2 * m) * (double) (2 * m + 1);
        kr->asym[m] = ((m % 2) ? -1.0 : 1.0) * fact * l[2 * m + 1];
    }
    *out = kr;
    return LF_OK;
}

void
lf_exact_kernel_free(lf_exact_kernel *kr)
{
    if (kr == NULL)
        return;
    free(kr->kf);
    free(kr->dkf);
    free(kr->d2kf);
    free(kr);
}

double
lf_exact_kf(const lf_exact_kernel *kr, double z, double *dkf)
{
    double sgn = 1.0;

    if (z < 0.0) {
        z = -z;
        sgn = -1.0;
    }
    if (z < LF_EXACT_ZC) {
        /* quintic Hermite from values, first and second derivatives */
        double q = z / KF_DZ, t, t2, t3, t4, t5, h = KF_DZ, hh = h * h;
        size_t i = (size_t) q;
        const double *f = kr->kf, *df = kr->dkf, *d2 = kr->d2kf;
        if (i >= kr->nz - 1)
            i = kr->nz - 2;
        t = q - (double) i;
        t2 = t * t; t3 = t2 * t; t4 = t3 * t; t5 = t4 * t;
        if (dkf != NULL) {
            double g0 = -30.0 * t2 + 60.0 * t3 - 30.0 * t4;
            double g1 = 1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4;
            double g2 = 0.5 * (2.0 * t - 9.0 * t2 + 12.0 * t3 - 5.0 * t4);
            double g3 = 0.5 * (3.0 * t2 - 8.0 * t3 + 5.0 * t4);
            double g4 = -12.0 * t2 + 28.0 * t3 - 15.0 * t4;
            *dkf = sgn * ((g0 * (f[i] - f[i + 1])) / h + g1 * df[i] + g4 * df[i + 1]
                          + h * (g2 * d2[i] + g3 * d2[i + 1]));
        }
        return f[i] * (1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5)
               + f[i + 1] * (10.0 * t3 - 15.0 * t4 + 6.0 * t5)
               + h * (df[i] * (t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5)
                      + df[i + 1] * (-4.0 * t3 + 7.0 * t4 - 3.0 * t5))
               + hh * 0.5 * (d2[i] * (t2 - 3.0 * t3 + 3.0 * t4 - t5)
                             + d2[i + 1] * (t3 - 2.0 * t4 + t5));
    } else {
        double iz2 = 1.0 / (z * z), pw = iz2, sum = 0.0, dsum = 0.0;
        int m;
        for (m = 0; m < KF_NASYM; m++) {
            sum += kr->asym[m] * pw;
            dsum -= (2.0 * m + 2.0) * kr->asym[m] * pw / z;
            pw *= iz2;
        }
        if (dkf != NULL)
            *dkf = sgn * dsum;
        return sum;
    }
}

size_t
lf_exact_nodes(double tau)
{
    double n = 40.0 + 4.0 * tau;
    return (size_t) ceil(n);
}

static int
solve(const gsl_matrix *A, const gsl_permutation *perm, int chol, gsl_vector *b)
{
    return chol ? gsl_linalg_cholesky_svx(A, b) : gsl_linalg_LU_svx(A, perm, b);
}

/* The right-hand side of the second solution at x = t/a: x^k for a power
 * law, x atanh(rho x)/rho for a sphere with a = rho R (rho > 0). */
static double
rhs_at(double k, double rho, double x)
{
    return rho > 0.0 ? x * atanh(rho * x) / rho : pow(x, k);
}

static int
solve_rhs(const lf_exact_kernel *kr, double k, double rho, double tau, size_t N,
          lf_exact_point *out, lf_error *err);

int
lf_exact_solve(const lf_exact_kernel *kr, double k, double tau, size_t N,
               lf_exact_point *out, lf_error *err)
{
    return solve_rhs(kr, k, 0.0, tau, N, out, err);
}

int
lf_exact_solve_sphere(const lf_exact_kernel *kr, double rho, double tau, size_t N,
                      lf_exact_point *out, lf_error *err)
{
    if (!(rho > 0.0 && rho < 1.0))
        return lf_fail(err, LF_EINVAL, "a sphere's a/R must lie in (0, 1) (got %g)", rho);
    return solve_rhs(kr, 2.0, rho, tau, N, out, err);
}

/* One Nystrom solve; the second right-hand side is rhs_at(k, rho, x).  For
 * a sphere (rho > 0) the tau-derivatives are at fixed rho. */
static int
solve_rhs(const lf_exact_kernel *kr, double k, double rho, double tau, size_t N,
          lf_exact_point *out, lf_error *err)
{
    gsl_matrix *A = NULL;
    gsl_permutation *perm = NULL;
    gsl_vector *x = NULL, *w = NULL, *U = NULL, *V = NULL, *Ud = NULL, *Vd = NULL;
    size_t i, j;
    int sign, chol = 0, status = LF_OK;
    double u1e, ve, du1e, dve, su, sv, dsu, dsv;
    const double ip = 1.0 / M_PI;

    if (!(tau > 0.0) || N < 2)
        return lf_fail(err, LF_EINVAL, "Nystrom solve needs tau > 0 and N >= 2");
    A = gsl_matrix_alloc(N, N);
    perm = gsl_permutation_alloc(N);
    x = gsl_vector_alloc(N);
    w = gsl_vector_alloc(N);
    U = gsl_vector_alloc(N);
    V = gsl_vector_alloc(N);
    Ud = gsl_vector_alloc(N);
    Vd = gsl_vector_alloc(N);
    if (!A || !perm || !x || !w || !U || !V || !Ud || !Vd) {
        status = lf_fail(err, LF_ENOMEM, "out of memory (Nystrom, N = %zu)", N);
        goto done;
    }
    lf_exact_gauss_legendre(N, x->data, w->data);
    /* The system (I - (tau/pi) K W) U = r, symmetrised with W^(1/2):
     * B = I - (tau/pi) W^(1/2) K W^(1/2), B (W^(1/2) U) = W^(1/2) r.
     * B is positive definite (the layer is stiffer than the half-space),
     * so Cholesky; LU if rounding says otherwise. */
    for (i = 0; i < N; i++)
        gsl_vector_set(w, i, sqrt(gsl_vector_get(w, i))); /* w now holds W^(1/2) */
    for (i = 0; i < N; i++) {
        double xi = gsl_vector_get(x, i), wi = gsl_vector_get(w, i);
        for (j = 0; j <= i; j++) {
            double xj = gsl_vector_get(x, j);
            double kk = lf_exact_kf(kr, tau * (xi - xj), NULL)
                        + lf_exact_kf(kr, tau * (xi + xj), NULL);
            double b = (i == j ? 1.0 : 0.0) - tau * ip * wi * gsl_vector_get(w, j) * kk;
            gsl_matrix_set(A, i, j, b);
            gsl_matrix_set(A, j, i, b);
        }
        gsl_vector_set(U, i, wi);
        gsl_vector_set(V, i, wi * rhs_at(k, rho, xi));
    }
    if (gsl_linalg_cholesky_decomp1(A) == GSL_SUCCESS) {
        chol = 1;
    } else {
        /* the failed Cholesky overwrote A: rebuild, then LU */
        for (i = 0; i < N; i++) {
            double xi = gsl_vector_get(x, i), wi = gsl_vector_get(w, i);
            for (j = 0; j < N; j++) {
                double xj = gsl_vector_get(x, j);
                double kk = lf_exact_kf(kr, tau * (xi - xj), NULL)
                            + lf_exact_kf(kr, tau * (xi + xj), NULL);
                gsl_matrix_set(A, i, j, (i == j ? 1.0 : 0.0)
                               - tau * ip * wi * gsl_vector_get(w, j) * kk);
            }
        }
        if (gsl_linalg_LU_decomp(A, perm, &sign) != GSL_SUCCESS) {
            status = lf_fail(err, LF_ENUMERIC, "singular Nystrom system at tau = %g", tau);
            goto done;
        }
    }
    if (solve(A, perm, chol, U) != GSL_SUCCESS || solve(A, perm, chol, V) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "singular Nystrom system at tau = %g", tau);
        goto done;
    }
    /* -B' Ut and -B' Vt, with d/dtau [tau kf(tau r)] = kf(z) + z kf'(z) */
    for (i = 0; i < N; i++) {
        double xi = gsl_vector_get(x, i), wi = gsl_vector_get(w, i), au = 0.0, av = 0.0;
        for (j = 0; j < N; j++) {
            double xj = gsl_vector_get(x, j), z1 = tau * fabs(xi - xj), z2 = tau * (xi + xj);
            double d1, d2, f1 = lf_exact_kf(kr, z1, &d1), f2 = lf_exact_kf(kr, z2, &d2);
            double kd = ip * wi * gsl_vector_get(w, j) * (f1 + z1 * d1 + f2 + z2 * d2);
            au += kd * gsl_vector_get(U, j);
            av += kd * gsl_vector_get(V, j);
        }
        gsl_vector_set(Ud, i, au);
        gsl_vector_set(Vd, i, av);
    }
    if (solve(A, perm, chol, Ud) != GSL_SUCCESS || solve(A, perm, chol, Vd) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "singular Nystrom system at tau = %g", tau);
        goto done;
    }
    /* back from W^(1/2) U to U */
    for (i = 0; i < N; i++) {
        double wi = gsl_vector_get(w, i);
        gsl_vector_set(U, i, gsl_vector_get(U, i) / wi);
        gsl_vector_set(V, i, gsl_vector_get(V, i) / wi);
        gsl_vector_set(Ud, i, gsl_vector_get(Ud, i) / wi);
        gsl_vector_set(Vd, i, gsl_vector_get(Vd, i) / wi);
        gsl_vector_set(w, i, wi * wi);
    }
    /* edge values by Nystrom interpolation at x = 1, integrals by the rule */
    u1e = 1.0;
    ve = rhs_at(k, rho, 1.0);
    du1e = dve = su = sv = dsu = dsv = 0.0;
    for (j = 0; j < N; j++) {
        double xj = gsl_vector_get(x, j), wj = gsl_vector_get(w, j);
        double z1 = tau * (1.0 - xj), z2 = tau * (1.0 + xj), d1, d2;
        double f1 = lf_exact_kf(kr, z1, &d1), f2 = lf_exact_kf(kr, z2, &d2);
        double cj = tau * ip * wj * (f1 + f2);
        double cdj = ip * wj * (f1 + z1 * d1 + f2 + z2 * d2);
        double Uj = gsl_vector_get(U, j), Vj = gsl_vector_get(V, j);
        double Udj = gsl_vector_get(Ud, j), Vdj = gsl_vector_get(Vd, j);
        u1e += cj * Uj;
        ve += cj * Vj;
        du1e += cdj * Uj + cj * Udj;
        dve += cdj * Vj + cj * Vdj;
        su += wj * Uj;
        sv += wj * Vj;
        dsu += wj * Udj;
        dsv += wj * Vdj;
    }
    out->s = su;
    out->ds = dsu;
    out->e = u1e;
    out->de = du1e;
    out->d = ve / u1e;
    out->dd = (dve - out->d * du1e) / u1e;
    out->p = su * out->d - sv;
    out->dp = dsu * out->d + su * out->dd - dsv;
    if (!(isfinite(out->s) && isfinite(out->e) && isfinite(out->d) && isfinite(out->p)
          && out->s > 0 && out->e > 0 && out->d > 0 && out->p > 0
          && isfinite(out->ds) && isfinite(out->de) && isfinite(out->dd)
          && isfinite(out->dp)))
        status = lf_fail(err, LF_ENUMERIC, "Nystrom solution not positive at tau = %g", tau);
done:
    gsl_matrix_free(A);
    gsl_permutation_free(perm);
    gsl_vector_free(x);
    gsl_vector_free(w);
    gsl_vector_free(U);
    gsl_vector_free(V);
    gsl_vector_free(Ud);
    gsl_vector_free(Vd);
    return status;
}
