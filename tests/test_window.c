/* test_window.c: fit windows (src/window.c).  Ranges as labs write them
 * parse to SI or fractions, and wrong ones are refused saying why; a
 * window placed on a curve keeps exactly the points whose indentation from
 * the model-free contact point (and force above the baseline) lie within
 * it; and the same curve fitted over 0-30% and 0-100% of its depth gives,
 * each, the fit of the data cut by hand to those points, with E* within
 * its standard errors of the truth. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"
#include "testlib.h"

static void
test_parse(void)
{
    static const struct { const char *text; lf_quantity q; int status; double lo, hi; int rel; }
        c[] = {
            { "0:500nm", LF_Q_LENGTH, LF_OK, 0.0, 500e-9, 0 },
            { "0:30%", LF_Q_LENGTH, LF_OK, 0.0, 0.3, 1 },
            { ":50%", LF_Q_LENGTH, LF_OK, NAN, 0.5, 1 },
            { "-20nN:2uN", LF_Q_FORCE, LF_OK, -20e-9, 2e-6, 0 },
            { "-50nm:", LF_Q_LENGTH, LF_OK, -50e-9, NAN, 0 },
            { " 10 nm : 1 um ", LF_Q_LENGTH, LF_OK, 10e-9, 1e-6, 0 },
            { "1:2", LF_Q_LENGTH, LF_EUNIT, 0, 0, 0 },
            { "30%:10%", LF_Q_LENGTH, LF_EINVAL, 0, 0, 0 },
            { "-1um:30%", LF_Q_LENGTH, LF_EINVAL, 0, 0, 0 },
            { "0:500nN", LF_Q_LENGTH, LF_EUNIT, 0, 0, 0 },
            { "500nm", LF_Q_LENGTH, LF_EINVAL, 0, 0, 0 },
            { "0:1:2", LF_Q_LENGTH, LF_EINVAL, 0, 0, 0 },
            { "0:x%", LF_Q_LENGTH, LF_EINVAL, 0, 0, 0 },
        };
    size_t i;

    for (i = 0; i < sizeof c / sizeof c[0]; i++) {
        lf_range r;
        lf_error err;
        int st = lf_range_parse(c[i].text, c[i].q, &r, &err);
        t_int(st, c[i].status, "range '%s' (%s)", c[i].text, st == LF_OK ? "" : err.msg);
        if (st != LF_OK || c[i].status != LF_OK)
            continue;
        t_true(isnan(c[i].lo) ? isnan(r.lo) : fabs(r.lo - c[i].lo) <= 1e-15 * fabs(c[i].lo) + 1e-30,
               "range '%s': low end %g", c[i].text, r.lo);
        t_true(isnan(c[i].hi) ? isnan(r.hi) : fabs(r.hi - c[i].hi) <= 1e-15 * fabs(c[i].hi),
               "range '%s': high end %g", c[i].text, r.hi);
        t_int(r.relative, c[i].rel, "range '%s': relative", c[i].text);
    }
}

/* A half-space curve of approach and retract as layerfit's CSV in a
 * temporary file; the name into path. */
#define NPT 400
static int
write_curve(char *path, size_t n, const lf_probe *p, const lf_material *m, unsigned long seed)
{
    lf_sim_settings s = lf_sim_settings_default();
    static double z[2][NPT], F[2][NPT];
    double *zp[1], *Fp[1];
    FILE *f;
    int fd, b;

    snprintf(path, n, "/tmp/lf-window-XXXXXX");
    if ((fd = mkstemp(path)) < 0 || (f = fdopen(fd, "w")) == NULL)
        return -1;
    s.points = NPT;
    s.delta_max = 2e-6;
    s.delta_min = -1.5e-6;
    s.noise = 0.005;
    s.z0 = 7e-6;
    s.F0 = -2e-9;
    for (b = 0; b < 2; b++) {
        s.branch = b ? LF_BRANCH_UNLOAD : LF_BRANCH_LOAD;
        s.seed = seed + (unsigned long) b;
        zp[0] = z[b];
        Fp[0] = F[b];
        if (lf_simulate(&s, &lf_model_halfspace, m, 1, p, zp, Fp, NULL, NULL) != LF_OK) {
            fclose(f);
            return -1;
        }
    }
    fprintf(f, "depth_m,force_N,segment\n");
    for (b = 0; b < 2; b++) {
        size_t i;
        for (i = 0; i < NPT; i++)
            fprintf(f, "%.17g,%.17g,%s\n", z[b][i], F[b][i], b ? "retract" : "approach");
    }
    return fclose(f);
}

static void
test_windowed_fits(void)
{
    const lf_probe p = { 2.0, 8e-6, 8e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    const lf_material truth = { 1e-3, 25e3, 0.3 };
    static const double upto[] = { 0.3, 1.0 };
    char path[64];
    lf_curve *c = NULL;
    lf_observables o;
    size_t w;

    gsl_set_error_handler_off();
    if (!t_int(write_curve(path, sizeof path, &p, &truth, 11), 0, "synthetic curve written"))
        return;
    if (!t_int(lf_curve_read(path, NULL, &c, NULL, NULL), LF_OK, "curve read")) {
        unlink(path);
        return;
    }
    lf_observe(c, &o, NULL);
    {
        /* the approach's zero-force point: the JKR sphere's P = 0,
         * a^(3/2) = (3R/(4E*)) sqrt(8 pi w E*), delta = a^2/R - sqrt(2 pi w a/E*),
         * past the simulated z0 (where it touches) */
        double a = pow(3.0 * p.R / (4.0 * truth.Estar) * sqrt(8.0 * M_PI * truth.w * truth.Estar),
                       2.0 / 3.0);
        double d0 = a * a / p.R - sqrt(2.0 * M_PI * truth.w * a / truth.Estar);
        t_abs(o.contact_point, 7e-6 + d0, 0.02 * 2e-6, "contact point %.4g m: the approach's "
              "zero-force point, z0 + %.3g m", o.contact_point, d0);
    }
    for (w = 0; w < sizeof upto / sizeof upto[0]; w++) {
        lf_input_settings is = lf_input_settings_default();
        lf_fit_settings fs = lf_fit_settings_default();
        lf_fit_input in;
        lf_fit_result ra, rb;
        lf_fit_curve cut;
        lf_error err;
        size_t n = lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL), i, m = 0;
        double *z = malloc(n * sizeof *z), *F = malloc(n * sizeof *F);
        const double hi = o.contact_point + upto[w] * o.max_indentation;
        lf_probe pb = p;
        int sa, sb;

        fs.model = &lf_model_halfspace;
        is.window.depth.lo = 0.0;
        is.window.depth.hi = upto[w];
        is.window.depth.relative = 1;
        pb.b = NAN;
        if (!t_int(lf_fit_input_from_curve(path, &pb, &is, &in, NULL, &err), LF_OK,
                   "0-%g%%: input (%s)", 100 * upto[w], err.msg)) {
            free(z);
            free(F);
            continue;
        }
        /* by hand: the retract's points from the contact point to the window's end */
        lf_curve_segment(c, LF_SEG_UNLOAD, z, F);
        for (i = 0; i < n; i++)
            if (z[i] >= o.contact_point && z[i] <= hi) {
                z[m] = z[i];
                F[m++] = F[i];
            }
        t_int((long) in.curves[0].n, (long) m, "0-%g%%: the window keeps the points cut by hand",
              100 * upto[w]);
        t_int((long) in.window[0].n_kept, (long) m, "0-%g%%: n_kept", 100 * upto[w]);
        t_int((long) in.window[0].n_in, (long) n, "0-%g%%: n_in", 100 * upto[w]);
        t_rel(in.window[0].depth_hi, hi, 1e-15, "0-%g%%: placed at the contact point + the "
              "fraction of the deepest indentation", 100 * upto[w]);
        cut = in.curves[0];
        cut.depth = z;
        cut.force = F;
        cut.n = m;
        sa = lf_fit_driver(&fs, 1, in.curves, &ra, &err);
        sb = lf_fit_driver(&fs, 1, &cut, &rb, &err);
        t_int(sa, LF_OK, "0-%g%%: windowed fit converged", 100 * upto[w]);
        t_int(sb, LF_OK, "0-%g%%: fit of the cut data converged", 100 * upto[w]);
        if (sa == LF_OK && sb == LF_OK) {
            t_rel(ra.Estar.value, rb.Estar.value, 0.0, "0-%g%%: E* as the cut data's",
                  100 * upto[w]);
            t_true(ra.w.determined == rb.w.determined
                   && (!ra.w.determined || ra.w.value == rb.w.value),
                   "0-%g%%: w as the cut data's", 100 * upto[w]);
            t_true(fabs(ra.Estar.value - truth.Estar) < 3.0 * ra.Estar.se,
                   "0-%g%%: E* %.5g within 3 se (%.3g) of the truth", 100 * upto[w],
                   ra.Estar.value, ra.Estar.se);
        }
        if (sa == LF_OK || sa == LF_ENOCONV)
            lf_fit_result_free(&ra);
        if (sb == LF_OK || sb == LF_ENOCONV)
            lf_fit_result_free(&rb);
        lf_fit_input_free(&in);
        free(z);
        free(F);
    }
    {
        /* a window keeping too few points is refused naming the curve */
        lf_input_settings is = lf_input_settings_default();
        lf_fit_input in;
        lf_error err;
        lf_probe pb = p;
        pb.b = NAN;
        lf_range_parse("0:1pm", LF_Q_LENGTH, &is.window.depth, NULL);
        t_int(lf_fit_input_from_curve(path, &pb, &is, &in, NULL, &err), LF_EDATA,
              "a window of 1 pm: refused");
        t_contains(err.msg, "the fit window keeps", "a window too narrow: message");
        /* a force window of the largest forces only */
        lf_range_parse("50%:", LF_Q_FORCE, &is.window.depth, NULL);
        is.window.depth = lf_window_all().depth;
        lf_range_parse("50%:", LF_Q_FORCE, &is.window.force, NULL);
        if (t_int(lf_fit_input_from_curve(path, &pb, &is, &in, NULL, &err), LF_OK,
                  "force window 50%%:")) {
            size_t i, bad = 0;
            for (i = 0; i < in.curves[0].n; i++)
                bad += !(in.curves[0].force[i] - o.baseline >= 0.5 * o.max_force);
            t_int((long) bad, 0, "force window: every point kept above half the largest force");
            lf_fit_input_free(&in);
        }
    }
    lf_curve_free(c);
    unlink(path);
}

int
main(void)
{
    test_parse();
    test_windowed_fits();
    return t_summary();
}
