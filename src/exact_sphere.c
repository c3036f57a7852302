/* exact_sphere.c: a sphere of radius R on a layer of any thickness, as a
 * correction of the exact model's paraboloid (k = 2) tables.
 *
 * The sphere's profile f = R - sqrt(R^2 - r^2) enters the Fredholm
 * equation (exact.h) through g(t) = (t/2) ln((R + t)/(R - t)) (Maugis
 * 1995, J. Colloid Interface Sci. 170:447), which is no power of t: with
 * rho = a/R the tabulated d and p of k = 2 become functions of (tau, rho),
 * d~ = v(1)/u1(1) and p~ = s d~ - int_0^1 v dx for the right-hand side
 * x atanh(rho x)/rho (lf_exact_solve_sphere), so that
 *   delta1 = (h^2/R) tau^2 d~,   P1 = 2 E* (h^3/R) tau^3 p~
 * (s and e, the flat punch's, do not depend on the shape).  Both limits
 * are closed forms: on a half-space (tau -> 0) d~ = Gh(rho) = atanh(rho)/rho
 * and int v = Ih(rho) = ((rho^2 - 1) atanh(rho) + rho)/(2 rho^3) (Maugis'
 * P1); on a thin layer (tau -> inf, local pressure) d~ = Gt(rho) =
 * (1 - sqrt(1 - rho^2))/rho^2 (the cap's height f(a) over a^2/R) and
 * int v = (pi Z tau/2) It(rho), It = eta/rho^2 - eta^2 (1 - eta/3)/rho^4,
 * eta = 1 - sqrt(1 - rho^2) (the cap's volume).  For rho -> 0 all four are
 * the paraboloid's (1, 1/3, 1/2, 1/4).
 *
 * The correction carries the paraboloid's own passage from one limit to
 * the other over to the sphere: with theta = 2 (1 - d_2) (0 on a
 * half-space, 1 on a thin layer; d_2 the k = 2 table's d, which falls from
 * 1 to 1/2 = 1/kappa_2),
 *   d~ = Gh + theta (Gt - Gh),
 *   p~ = s d~ - I_2 (3 Ih + theta (4 It - 3 Ih)),   I_2 = s d_2 - p_2,
 * exact in both limits and for rho -> 0.  Against Nystrom solves with the
 * sphere's right-hand side (tests/test_exact.c, test_sphere) over
 * tau = 0.01 .. 100, frictionless and bonded nu = 0.3, 0.45, the
 * relative error of d~ and p~ is below 7e-3 up to a = 0.5 R, 2e-2 up to
 * 0.7 R, 7e-2 up to 0.9 R (largest at tau ~ 1-3, where the layer's effect
 * changes fastest; the higher powers of the sphere's g, loaded nearer the
 * edge, feel the base less than t^2 does).
 *
 * Derivatives are carried as jets: value, d/du, d^2/du^2 (u = ln tau,
 * rho = tau h/R), d/dnu and d^2/du dnu, as the exact model's evaluation
 * needs them (model_exact.c).
 */
#include <math.h>

#include "exact.h"

typedef struct {
    double v, u, uu, n, un;
} jet;

static jet
jet_const(double v)
{
    jet j = { v, 0.0, 0.0, 0.0, 0.0 };
    return j;
}

static jet
jet_add(jet a, jet b)
{
    jet j = { a.v + b.v, a.u + b.u, a.uu + b.uu, a.n + b.n, a.un + b.un };
    return j;
}

static jet
jet_sub(jet a, jet b)
{
    jet j = { a.v - b.v, a.u - b.u, a.uu - b.uu, a.n - b.n, a.un - b.un };
    return j;
}

static jet
jet_mul(jet a, jet b)
{
    jet j;
    j.v = a.v * b.v;
    j.u = a.u * b.v + a.v * b.u;
    j.uu = a.uu * b.v + 2.0 * a.u * b.u + a.v * b.uu;
    j.n = a.n * b.v + a.v * b.n;
    j.un = a.un * b.v + a.u * b.n + a.n * b.u + a.v * b.un;
    return j;
}

static jet
jet_scale(jet a, double c)
{
    jet j = { c * a.v, c * a.u, c * a.uu, c * a.n, c * a.un };
    return j;
}

/* exp of a jet given as ln f: F, g = dF/du, dg, H = dF/dnu, dH = dH/du */
static jet
jet_exp(double F, double g, double dg, double H, double dH)
{
    jet j;
    j.v = exp(F);
    j.u = j.v * g;
    j.uu = j.v * (g * g + dg);
    j.n = j.v * H;
    j.un = j.v * (g * H + dH);
    return j;
}

/* ln of a jet, as (F, g, dg, H, dH) */
static void
jet_log(jet a, double *F, double *g, double *dg, double *H, double *dH)
{
    double gu = a.u / a.v, gn = a.n / a.v;
    *F = log(a.v);
    *g = gu;
    *dg = a.uu / a.v - gu * gu;
    *H = gn;
    *dH = a.un / a.v - gu * gn;
}

/* A function of rho with its first two rho-derivatives, as a jet in u
 * (d rho/du = rho): value f, f u-derivative rho f', second rho f' + rho^2 f''. */
static jet
jet_of_rho(double rho, double f, double f1, double f2)
{
    jet j = { f, rho * f1, rho * f1 + rho * rho * f2, 0.0, 0.0 };
    return j;
}

/* The four limits of the header and their rho-derivatives, out[w][0..2]
 * for w = Gh, Gt, 3 Ih, 4 It (each 1 at rho = 0 but Gt, 1/2).  Below
 * SERIES_RHO, where the closed forms cancel, from their series in rho^2:
 * Gh = sum y^n/(2n+1), Gt = sum y^n/((2n+1) kappa_(2n+2)),
 * 3 Ih = sum 3 y^n/((2n+1)(2n+3)), 4 It = sum 8 y^n/((2n+1) kappa_(2n+2) (2n+4)),
 * y = rho^2, kappa_(m+2) = kappa_m (m+2)/(m+1), kappa_2 = 2. */
#define SERIES_RHO 0.25
enum { GH, GT, IH, IT };

static void
limits(double r, double out[4][3])
{
    int w, n;

    if (r < SERIES_RHO) {
        double y = r * r, yn = 1.0, kap = 2.0;
        for (w = 0; w < 4; w++)
            out[w][0] = out[w][1] = out[w][2] = 0.0;
        for (n = 0; n < 30; n++) {
            const double m = 2.0 * n + 1.0;
            const double a[4] = { 1.0 / m, 1.0 / (m * kap), 3.0 / (m * (m + 2.0)),
                                  8.0 / (m * kap * (m + 3.0)) };
            /* d/dr r^(2n) = 2n r^(2n-1), d2 = 2n (2n-1) r^(2n-2) */
            const double p0 = yn, p1 = n > 0 ? 2.0 * n * yn / r : 0.0,
                         p2 = n > 0 ? 2.0 * n * (2.0 * n - 1.0) * yn / (r * r) : 0.0;
            for (w = 0; w < 4; w++) {
                out[w][0] += a[w] * p0;
                out[w][1] += a[w] * p1;
                out[w][2] += a[w] * p2;
            }
            yn *= y;
            kap *= (2.0 * n + 4.0) / (2.0 * n + 3.0);
            if (yn < 1e-18)
                break;
        }
        return;
    }
    {
        const double r2 = r * r, r3 = r2 * r, r4 = r2 * r2, r5 = r4 * r, r6 = r3 * r3;
        const double A = atanh(r), A1 = 1.0 / (1.0 - r2), A2 = 2.0 * r * A1 * A1;
        const double s = sqrt(1.0 - r2), N = r2 / (1.0 + s), N1 = r / s, N2 = 1.0 / (s * s * s);
        const double K = (r2 - 1.0) * A + r, K1 = 2.0 * r * A, K2 = 2.0 * A + 2.0 * r * A1;
        const double Q = N * N * (1.0 - N / 3.0), Q1 = (2.0 * N - N * N) * N1;
        const double Q2 = (2.0 - 2.0 * N) * N1 * N1 + (2.0 * N - N * N) * N2;

        out[GH][0] = A / r;
        out[GH][1] = A1 / r - A / r2;
        out[GH][2] = A2 / r - 2.0 * A1 / r2 + 2.0 * A / r3;
        out[GT][0] = N / r2;
        out[GT][1] = N1 / r2 - 2.0 * N / r3;
        out[GT][2] = N2 / r2 - 4.0 * N1 / r3 + 6.0 * N / r4;
        out[IH][0] = 1.5 * K / r3;
        out[IH][1] = 1.5 * (K1 / r3 - 3.0 * K / r4);
        out[IH][2] = 1.5 * (K2 / r3 - 6.0 * K1 / r4 + 12.0 * K / r5);
        out[IT][0] = 4.0 * (N / r2 - Q / r4);
        out[IT][1] = 4.0 * (N1 / r2 - 2.0 * N / r3 - Q1 / r4 + 4.0 * Q / r5);
        out[IT][2] = 4.0 * (N2 / r2 - 4.0 * N1 / r3 + 6.0 * N / r4 - Q2 / r4 + 8.0 * Q1 / r5
                            - 20.0 * Q / r6);
    }
}

void
lf_exact_sphere_adjust(double ln_hR, double u, double F[4], double g[4], double dg[4],
                       double H[4], double dH[4])
{
    const double rho = exp(u + ln_hR);
    double lim[4][3], scr[4];
    jet s, d2, p2, th, Gh, Gt, Ih, It, D, I2, P;
    int j;

    if (!(rho < 1.0)) {
        for (j = 2; j < 4; j++) {
            F[j] = g[j] = NAN;
            if (dg != NULL)
                dg[j] = NAN;
            if (H != NULL)
                H[j] = NAN;
            if (dH != NULL)
                dH[j] = NAN;
        }
        return;
    }
    for (j = 0; j < 4; j++)
        scr[j] = 0.0;
    s = jet_exp(F[0], g[0], dg != NULL ? dg[0] : 0.0, H != NULL ? H[0] : 0.0,
                dH != NULL ? dH[0] : 0.0);
    d2 = jet_exp(F[2], g[2], dg != NULL ? dg[2] : 0.0, H != NULL ? H[2] : 0.0,
                 dH != NULL ? dH[2] : 0.0);
    p2 = jet_exp(F[3], g[3], dg != NULL ? dg[3] : 0.0, H != NULL ? H[3] : 0.0,
                 dH != NULL ? dH[3] : 0.0);
    limits(rho, lim);
    Gh = jet_of_rho(rho, lim[GH][0], lim[GH][1], lim[GH][2]);
    Gt = jet_of_rho(rho, lim[GT][0], lim[GT][1], lim[GT][2]);
    Ih = jet_of_rho(rho, lim[IH][0], lim[IH][1], lim[IH][2]);
    It = jet_of_rho(rho, lim[IT][0], lim[IT][1], lim[IT][2]);
    th = jet_scale(jet_sub(jet_const(1.0), d2), 2.0);
    D = jet_add(Gh, jet_mul(th, jet_sub(Gt, Gh)));
    I2 = jet_sub(jet_mul(s, d2), p2);
    P = jet_sub(jet_mul(s, D), jet_mul(I2, jet_add(Ih, jet_mul(th, jet_sub(It, Ih)))));
    jet_log(D, &F[2], &g[2], dg != NULL ? &dg[2] : &scr[0], H != NULL ? &H[2] : &scr[1],
            dH != NULL ? &dH[2] : &scr[2]);
    jet_log(P, &F[3], &g[3], dg != NULL ? &dg[3] : &scr[0], H != NULL ? &H[3] : &scr[1],
            dH != NULL ? &dH[3] : &scr[2]);
}
