/* test_crb.c: the Cramer-Rao bound against the numbers of a two-probe
 * design (computed independently, and reached by scipy's least_squares)
 * and against what the data can and cannot determine. */
#include <math.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"
#include "testlib.h"

#define N 200

/* Two probes (k = 2, 3; R = 1 mm; b = 1 um; w = 10 mJ/m^2;
 * E* = 1 GPa; delta from -0.9c to 50 nm; 200 points each; noise 1% of
 * max |P|): relative sd 8.6% (w), 0.14% (E*), correlation 0.63. */
static void
two_probes(lf_base base2, int free_z0, int free_F0, int free_nu, lf_crb_result *r, int *status)
{
    const lf_material truth = { 10e-3, 1e9, 0.3 };
    const double c = sqrt(2 * 1e-6 * truth.w / truth.Estar);
    static double delta[N];
    lf_design_curve d[2];
    lf_model *m[2];
    lf_eval e[N];
    size_t i, j;

    for (i = 0; i < N; i++)
        delta[i] = -0.9 * c + (50e-9 + 0.9 * c) * (double) i / (N - 1);
    for (j = 0; j < 2; j++) {
        lf_probe p = { 2.0 + (double) j, 1e-3, 1e-6, j ? base2 : LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
        double pmax = 0;
        m[j] = lf_model_alloc(&lf_model_thin, &p, NULL);
        lf_model_eval(m[j], &truth, LF_BRANCH_UNLOAD, N, delta, e, NULL);
        for (i = 0; i < N; i++)
            pmax = fmax(pmax, fabs(e[i].P));
        d[j].model = m[j];
        d[j].branch = LF_BRANCH_UNLOAD;
        d[j].n = N;
        d[j].delta = delta;
        d[j].sigma = 0.01 * pmax;
        d[j].free_z0 = free_z0;
        d[j].free_F0 = free_F0;
    }
    *status = lf_crb(d, 2, &truth, free_nu, r, NULL);
    lf_model_free(m[0]);
    lf_model_free(m[1]);
}

int
main(void)
{
    lf_crb_result r, r2;
    int status;

    gsl_set_error_handler_off();
    two_probes(LF_BASE_FRICTIONLESS, 0, 0, 0, &r, &status);
    t_int(status, LF_OK, "two-probe design: bound computed");
    t_abs(r.sd_logw, 0.086, 0.0005, "two-probe design: sd(w)/w = 8.6%%");
    t_abs(r.sd_logE, 0.0014, 0.00005, "two-probe design: sd(E*)/E* = 0.14%%");
    t_abs(r.corr_wE, 0.63, 0.005, "two-probe design: correlation 0.63");
    t_true(isnan(r.sd_nu), "nu not estimated: its bound is NaN");
    t_int((long) r.nparams, 2, "two parameters");

    /* nuisance parameters can only widen the bound */
    two_probes(LF_BASE_FRICTIONLESS, 1, 1, 0, &r2, &status);
    t_int(status, LF_OK, "free z0 and F0: bound computed");
    t_true(r2.sd_logw > r.sd_logw && r2.sd_logE > r.sd_logE, "free z0, F0 widen the bound (%.3g > %.3g)",
           r2.sd_logw, r.sd_logw);
    t_int((long) r2.nparams, 6, "2 + 2 x 2 parameters");

    /* nu: undetermined by frictionless curves, determined by a mixed pair */
    two_probes(LF_BASE_FRICTIONLESS, 0, 0, 1, &r, &status);
    t_int(status, LF_EDATA, "frictionless curves alone do not determine nu");
    two_probes(LF_BASE_BONDED, 0, 0, 1, &r, &status);
    t_int(status, LF_OK, "frictionless + bonded determine nu");
    t_true(isfinite(r.sd_nu) && r.sd_nu > 0, "nu bound finite (%.3g)", r.sd_nu);
    return t_summary();
}
