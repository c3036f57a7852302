/* bench_exact.c: speed against error of the exact layer model (not a test;
 * `make bench-exact`).  Prints
 *  1. table build time and the table's error against a converged direct
 *     Nystrom solve, for several table steps (in ln tau) and Nystrom node
 *     factors, tau in [0.01, 100];
 *  2. the error of the bonded nu interpolation against tables built at the
 *     exact nu;
 *  3. evaluation time per point of the exact, halfspace and thin models
 *     (unloading branch, warm cache);
 *  4. nearly incompressible bonded layers against the lubrication limit
 *     (Jaffar 1989, IJMS 31:229; Chadwick 2002, SIAM J. Appl. Math.
 *     62:1520).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "exact.h"

static double
now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

#define NREF 40

static void
table_errors(lf_base base, double nu, double k)
{
    lf_exact_kernel *kr;
    lf_error err;
    double taus[NREF], ref[NREF][4];
    double steps[] = {0.3, 0.2, 0.15, 0.1, 0.07};
    double factors[] = {0.5, 0.75, 1.0};
    int i, j, si, fi;

    if (lf_exact_kernel_alloc(&kr, base, nu, &err) != LF_OK) {
        printf("kernel failed: %s\n", err.msg);
        return;
    }
    for (i = 0; i < NREF; i++) {
        lf_exact_point p;
        taus[i] = exp(log(0.01) + (log(100.0) - log(0.01)) * (i + 0.37) / NREF);
        lf_exact_solve(kr, k, taus[i], (size_t) (2 * lf_exact_nodes(taus[i])), &p, &err);
        ref[i][0] = p.s; ref[i][1] = p.e; ref[i][2] = p.d; ref[i][3] = p.p;
    }
    printf("\n%s nu=%g k=%g: table vs direct solve (2x nodes), tau in [0.01,100]\n",
           base == LF_BASE_BONDED ? "bonded" : "frictionless", nu, k);
    printf("  step  nodefac  ntau  build_s   max_rel_err\n");
    for (fi = 0; fi < 3; fi++)
        for (si = 0; si < 5; si++) {
            lf_exact_table *t;
            double t0 = now(), bt, emax = 0.0;
            if (fi != 2 && si != 3)
                continue;
            if (lf_exact_table_build(kr, k, base, nu, steps[si], factors[fi], &t, &err) != LF_OK) {
                printf("build failed: %s\n", err.msg);
                continue;
            }
            bt = now() - t0;
            for (i = 0; i < NREF; i++) {
                double f[4];
                lf_exact_table_eval(t, taus[i], f, NULL);
                for (j = 0; j < 4; j++)
                    emax = fmax(emax, fabs(f[j] / ref[i][j] - 1.0));
            }
            printf("  %.2f  %.2f     %4d  %.3f    %.2e\n", steps[si], factors[fi],
                   (int) ceil((log(LF_EXACT_TAU_MAX) - log(LF_EXACT_TAU_MIN)) / steps[si]) + 1,
                   bt, emax);
            lf_exact_table_free(t);
        }
    lf_exact_kernel_free(kr);
}

static void
nu_interp_errors(double k)
{
    double nus[] = {0.05, 0.2, 0.3, 0.4, 0.45, 0.47, 0.49, 0.495, 0.499};
    int i, j, n;
    lf_error err;

    printf("\nbonded k=%g: nu-grid interpolation vs table at the exact nu (tau 0.01-100)\n", k);
    for (n = 0; n < 9; n++) {
        lf_exact_mix mx;
        const lf_exact_table *t;
        double emax = 0.0;
        if (lf_exact_mix_init(&mx, k, LF_BASE_BONDED, nus[n], &err) != LF_OK
            || lf_exact_table_get(k, LF_BASE_BONDED, nus[n], &t, &err) != LF_OK) {
            printf("failed: %s\n", err.msg);
            return;
        }
        for (i = 0; i < 60; i++) {
            double tau = exp(log(0.01) + log(1e4) * (i + 0.5) / 60), f[4], df[4], g[4];
            lf_exact_mix_eval(&mx, tau, f, df, NULL);
            lf_exact_table_eval(t, tau, g, NULL);
            for (j = 0; j < 4; j++)
                emax = fmax(emax, fabs(f[j] / g[j] - 1.0));
        }
        printf("  nu=%-6g max_rel_err %.2e\n", nus[n], emax);
    }
}

static void
eval_speed(void)
{
    lf_probe pr = {2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0};
    lf_material m = {0.01, 1e9, 0.3};
    const lf_model_type *types[] = {&lf_model_thin, &lf_model_exact, &lf_model_halfspace};
    enum { NP = 2000 };
    static double d[NP];
    static lf_eval out[NP];
    lf_error err;
    int b, ti, i, rep;

    printf("\nevaluation time per point (unloading, 2000 points from detachment to 50 nm, warm cache)\n");
    for (b = 0; b < 2; b++) {
        pr.base = b ? LF_BASE_BONDED : LF_BASE_FRICTIONLESS;
        for (ti = 0; ti < 3; ti++) {
            lf_model *mod = lf_model_alloc(types[ti], &pr, &err);
            lf_pulloff po;
            double t0, t1;
            if (mod == NULL || lf_model_pulloff(mod, &m, &po, &err) != LF_OK) {
                printf("failed: %s\n", err.msg);
                lf_model_free(mod);
                continue;
            }
            for (i = 0; i < NP; i++)
                d[i] = po.delta_detach + (50e-9 - po.delta_detach) * (i + 0.5) / NP;
            lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, NP, d, out, &err); /* warm */
            t0 = now();
            for (rep = 0; rep < 5; rep++)
                lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, NP, d, out, &err);
            t1 = now();
            printf("  %-10s %-12s %8.3f us/point\n", types[ti]->name,
                   b ? "bonded 0.3" : "frictionless", 1e6 * (t1 - t0) / (5.0 * NP));
            lf_model_free(mod);
        }
    }
}

static void
incompressible(void)
{
    double nus[] = {0.45, 0.49, 0.495, 0.499, 0.4995};
    double taus[] = {1, 2, 3, 5, 10, 20, 40, 100};
    int i, j;
    lf_error err;

    printf("\nbonded k=2, P1 exact / lubrication limit pi G a^6/(32 R h^3), G = E*(1-nu)/2\n");
    printf("  (and exact / compressible thin form)\n  nu     ");
    for (j = 0; j < 8; j++)
        printf("  tau=%-5g", taus[j]);
    printf("\n");
    for (i = 0; i < 5; i++) {
        lf_exact_mix mx;
        double kap = lf_exact_kappa(2.0);
        if (lf_exact_mix_init(&mx, 2.0, LF_BASE_BONDED, nus[i], &err) != LF_OK) {
            printf("failed: %s\n", err.msg);
            return;
        }
        printf("  %-6g ", nus[i]);
        for (j = 0; j < 8; j++) {
            double f[4], df[4], tau = taus[j];
            /* P1/(E* h^3/R) = 2 B kappa tau^3 p with B = 1/(2R): kappa tau^3 p */
            double p1;
            lf_exact_mix_eval(&mx, tau, f, df, NULL);
            p1 = kap * pow(tau, 3.0) * f[3];
            printf("  %-9.4f", p1 / (M_PI * 0.5 * (1.0 - nus[i]) * pow(tau, 6.0) / 32.0));
        }
        printf("\n         ");
        for (j = 0; j < 8; j++) {
            double f[4], df[4], tau = taus[j];
            lf_exact_mix_eval(&mx, tau, f, df, NULL);
            printf("  %-9.4f", f[3] / (0.5 * M_PI * lf_thin_Z(LF_BASE_BONDED, nus[i]) * tau * 2.0
                                      / (kap * 4.0)));
        }
        printf("\n");
    }
}

int
main(void)
{
    gsl_set_error_handler_off();
    printf("exact-model bench (tables tau in [%g, %g], default step %g in ln tau)\n",
           LF_EXACT_TAU_MIN, LF_EXACT_TAU_MAX, LF_EXACT_STEP);
    table_errors(LF_BASE_FRICTIONLESS, 0.0, 2.0);
    table_errors(LF_BASE_BONDED, 0.3, 3.0);
    table_errors(LF_BASE_BONDED, 0.499, 2.0);
    nu_interp_errors(2.0);
    eval_speed();
    incompressible();
    return 0;
}
