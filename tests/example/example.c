/* example.c: use liblayerfit directly: load a plan, fit every curve it lists
 * jointly, read the result.
 *
 *   cc example.c $(pkg-config --cflags --libs layerfit) -o example
 *   ./example datasets/plan.csv
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>
#include <layerfit.h>

int
main(int argc, char **argv)
{
    lf_plan *plan = NULL;
    lf_fit_curve *fc;
    lf_fit_result res;
    lf_fit_settings settings = lf_fit_settings_default();
    lf_error err;
    size_t i, j;
    int status;

    if (argc != 2) {
        fprintf(stderr, "usage: example PLAN.csv\n");
        return 2;
    }
    gsl_set_error_handler_off();   /* GSL would abort() on an error */

    /* the plan: one row per curve, with the probe and what is known */
    if (lf_plan_read(argv[1], &plan, NULL, &err) != LF_OK) {
        fprintf(stderr, "%s:%ld: %s\n", err.file, err.line, err.msg);
        return 1;
    }
    fc = calloc(plan->n, sizeof *fc);
    for (i = 0; i < plan->n; i++) {
        const lf_plan_row *row = &plan->rows[i];
        lf_curve *c;
        size_t n;
        double *depth, *force;

        if (lf_curve_read(row->file, NULL, &c, NULL, &err) != LF_OK) {
            fprintf(stderr, "%s:%ld: %s\n", err.file, err.line, err.msg);
            return 1;
        }
        /* the points of the segment the plan names, in SI units */
        n = lf_curve_segment(c, row->segment, NULL, NULL);
        depth = malloc(n * sizeof *depth);
        force = malloc(n * sizeof *force);
        lf_curve_segment(c, row->segment, depth, force);
        lf_curve_free(c);

        fc[i].name = row->file;
        fc[i].n = n;
        fc[i].depth = depth;
        fc[i].force = force;
        fc[i].probe = row->probe;
        fc[i].branch = row->segment == LF_SEG_LOAD ? LF_BRANCH_LOAD : LF_BRANCH_UNLOAD;
        fc[i].z0 = row->z0;    /* NaN: fitted */
        fc[i].F0 = row->F0;
        if (!isnan(row->nu)) {   /* the plan knows nu */
            settings.nu.mode = LF_PARAM_FIXED;
            settings.nu.value = row->nu;
        }
    }

    /* one joint fit: w, E* (and nu where the curves determine it) shared */
    status = lf_fit_driver(&settings, plan->n, fc, &res, &err);
    if (status != LF_OK && status != LF_ENOCONV) {
        fprintf(stderr, "fit: %s\n", err.msg);
        return 1;
    }
    printf("converged: %s\n", res.converged ? "yes" : "no");
    printf("w  = %.6g +- %.2g J/m^2\n", res.w.value, res.w.se);
    printf("E* = %.6g +- %.2g Pa\n", res.Estar.value, res.Estar.se);
    if (res.nu.determined)
        printf("nu = %.4f +- %.2g\n", res.nu.value, res.nu.se);
    for (j = 0; j < res.ncurves; j++)
        printf("curve %zu: pull-off force %.4g N at contact radius %.4g m\n", j + 1,
               res.curves[j].pulloff.P_po, res.curves[j].pulloff.a_po);

    lf_fit_result_free(&res);   /* the result owns its arrays */
    for (i = 0; i < plan->n; i++) {
        free((double *) fc[i].depth);
        free((double *) fc[i].force);
    }
    free(fc);
    lf_plan_free(plan);         /* after the fit: fc[].name points into it */
    return status == LF_OK ? 0 : 3;
}
