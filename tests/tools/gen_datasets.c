/* gen_datasets.c: write the synthetic example curves of datasets/ with the
 * thin-layer model (lf_model_thin), one file per common export style, and
 * the plan that lists them.  Truth and noise are stated in each file and in
 * datasets/README.md.  Run from the top folder:
 *
 *   make && cc -std=c11 -D_DEFAULT_SOURCE -Isrc -o build/gen_datasets \
 *     tests/tools/gen_datasets.c build/liblayerfit.a \
 *     -lgsl -lgslcblas -lcsv -ludunits2 -lpthread -lm
 *   build/gen_datasets datasets
 *
 * Each curve: indentation delta = depth - z0 runs linearly from
 * delta_start = -(c + 10 nm) up to delta_max and back (NPTS points each
 * way), loading on the LF_BRANCH_LOAD branch and unloading on
 * LF_BRANCH_UNLOAD; delta_max is where the unloading force is 20 |P_po|.
 * Gaussian noise of sigma = 0.5% of max |P| is added to the force. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "layerfit.h"

#define NPTS 150                 /* points per segment */
#define W_TRUE 12.3e-3           /* J/m^2 */
#define ESTAR_TRUE 1.85e9        /* Pa */
#define B_TRUE 1e-6              /* m */
#define Z0_TRUE 15e-9            /* m: depth = delta + z0 */
#define NOISE 0.005              /* of max |P| */
#define SEED 20240611UL          /* + index of the curve */
#define DT 0.1                   /* s between points */

typedef enum { STYLE_COMMA_NM_UN, STYLE_PAREN_CRLF, STYLE_SEMICOLON_SI, STYLE_TAB_SEGMENT } style;

static const struct {
    const char *file;
    double k, nu;
    lf_base base;
    style style;
} curves[] = {
    { "k2_frictionless.csv", 2, 0.0, LF_BASE_FRICTIONLESS, STYLE_COMMA_NM_UN },
    { "k3_frictionless.csv", 3, 0.0, LF_BASE_FRICTIONLESS, STYLE_PAREN_CRLF },
    { "k2_bonded_nu035.csv", 2, 0.35, LF_BASE_BONDED, STYLE_SEMICOLON_SI },
    { "k2_frictionless_repeat.tsv", 2, 0.0, LF_BASE_FRICTIONLESS, STYLE_TAB_SEGMENT },
};

static void
die(const char *what)
{
    fprintf(stderr, "gen_datasets: %s\n", what);
    exit(1);
}

static double
force_at(const lf_model *m, const lf_material *mat, lf_branch br, double delta)
{
    lf_eval e;
    if (lf_model_eval(m, mat, br, 1, &delta, &e, NULL) != LF_OK)
        die("model evaluation failed");
    return e.P;
}

/* A number with a decimal comma. */
static void
put_comma(FILE *f, double x)
{
    char buf[40], *dot;
    snprintf(buf, sizeof buf, "%.6e", x);
    if ((dot = strchr(buf, '.')) != NULL)
        *dot = ',';
    fputs(buf, f);
}

static void
write_curve(const char *dir, size_t idx)
{
    lf_probe probe = { curves[idx].k, 1e-3, B_TRUE, curves[idx].base };
    lf_material mat = { W_TRUE, ESTAR_TRUE, curves[idx].nu };
    lf_model *m = lf_model_alloc(&lf_model_thin, &probe, NULL);
    lf_pulloff po;
    double delta[2 * NPTS], P[2 * NPTS], lo, hi, start, pmax = 0, sigma;
    const char *eol = curves[idx].style == STYLE_PAREN_CRLF ? "\r\n" : "\n";
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    char path[1024];
    size_t i;
    FILE *f;

    if (m == NULL || rng == NULL || lf_model_pulloff(m, &mat, &po, NULL) != LF_OK)
        die("model set-up failed");
    gsl_rng_set(rng, SEED + idx);
    /* delta_max: unloading force 20 |P_po|, by bisection */
    lo = 0;
    hi = 1e-6;
    for (i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (force_at(m, &mat, LF_BRANCH_UNLOAD, mid) < 20 * fabs(po.P_po))
            lo = mid;
        else
            hi = mid;
    }
    start = -(po.c + 10e-9);
    for (i = 0; i < NPTS; i++) {
        double t = (double) i / (NPTS - 1);
        delta[i] = start + t * (hi - start);
        P[i] = force_at(m, &mat, LF_BRANCH_LOAD, delta[i]);
        delta[NPTS + i] = hi - t * (hi - start);
        P[NPTS + i] = force_at(m, &mat, LF_BRANCH_UNLOAD, delta[NPTS + i]);
    }
    for (i = 0; i < 2 * NPTS; i++)
        pmax = fmax(pmax, fabs(P[i]));
    sigma = NOISE * pmax;

    snprintf(path, sizeof path, "%s/%s", dir, curves[idx].file);
    if ((f = fopen(path, "wb")) == NULL)
        die("cannot write a curve file");
    fprintf(f, "# source: synthetic, tests/tools/gen_datasets.c, thin-layer model (lf_model_thin)%s", eol);
    fprintf(f, "# truth: w = 12.3 mJ/m^2, E* = 1.85 GPa, b = 1 um, k = %g, R = 1 mm, %s%s%s",
            curves[idx].k, curves[idx].base == LF_BASE_BONDED ? "bonded, nu = " : "frictionless",
            curves[idx].base == LF_BASE_BONDED ? "0.35" : "", eol);
    fprintf(f, "# contact offset: z0 = 15 nm (depth = indentation + z0)%s", eol);
    fprintf(f, "# noise: Gaussian on force, sigma = 0.5%% of max |P| = %.4g uN, mt19937 seed %lu%s",
            sigma * 1e6, SEED + idx, eol);
    fprintf(f, "# pull-off (model): P_po = %.4g uN; max indentation %.4g nm%s",
            po.P_po * 1e6, hi * 1e9, eol);
    switch (curves[idx].style) {
    case STYLE_COMMA_NM_UN:  fprintf(f, "depth_nm,force_uN%s", eol); break;
    case STYLE_PAREN_CRLF:   fprintf(f, "Depth (nm),Load (µN),Time (s)%s", eol); break;
    case STYLE_SEMICOLON_SI: fprintf(f, "displacement_m;force_N%s", eol); break;
    case STYLE_TAB_SEGMENT:  fprintf(f, "Indentation [um]\tForce [mN]\tSegment%s", eol); break;
    }
    for (i = 0; i < 2 * NPTS; i++) {
        double z = delta[i] + Z0_TRUE, F = P[i] + gsl_ran_gaussian(rng, sigma);
        switch (curves[idx].style) {
        case STYLE_COMMA_NM_UN:
            fprintf(f, "%.4f,%.6g%s", z * 1e9, F * 1e6, eol);
            break;
        case STYLE_PAREN_CRLF:
            fprintf(f, "%.4f,%.6g,%.1f%s", z * 1e9, F * 1e6, (double) i * DT, eol);
            break;
        case STYLE_SEMICOLON_SI:
            put_comma(f, z);
            fputc(';', f);
            put_comma(f, F);
            fputs(eol, f);
            break;
        case STYLE_TAB_SEGMENT:
            fprintf(f, "%.7f\t%.6g\t%s%s", z * 1e6, F * 1e3, i < NPTS ? "extend" : "retract", eol);
            break;
        }
    }
    if (fclose(f) != 0)
        die("cannot write a curve file");
    gsl_rng_free(rng);
    lf_model_free(m);
}

int
main(int argc, char **argv)
{
    char path[1024];
    size_t i;
    FILE *f;

    gsl_set_error_handler_off();
    if (argc != 2)
        die("usage: gen_datasets FOLDER");
    for (i = 0; i < sizeof curves / sizeof curves[0]; i++)
        write_curve(argv[1], i);
    snprintf(path, sizeof path, "%s/plan.csv", argv[1]);
    if ((f = fopen(path, "wb")) == NULL)
        die("cannot write the plan");
    fprintf(f, "# fit plan for the synthetic curves of this folder (truth in README.md)\n"
               "file,sample,k,R_mm,b [um],interface,nu,segment\n");
    for (i = 0; i < sizeof curves / sizeof curves[0]; i++)
        fprintf(f, "%s,film-A,%g,1,1,%s,,unload\n", curves[i].file, curves[i].k,
                curves[i].base == LF_BASE_BONDED ? "bonded" : "frictionless");
    return fclose(f) == 0 ? 0 : 1;
}
