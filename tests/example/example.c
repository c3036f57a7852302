/* example.c: use liblayerfit directly: load a plan, fit every curve it lists
 * jointly, read the result.
 *
 *   cc example.c $(pkg-config --cflags --libs layerfit) -o example
 *   ./example datasets/plan.csv
 */
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>
#include <layerfit.h>

int
main(int argc, char **argv)
{
    lf_plan *plan = NULL;
    lf_fit_input in;
    lf_fit_result res;
    lf_fit_settings settings = lf_fit_settings_default();
    lf_error err;
    size_t j;
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
    /* its curves: the points of the segment each row names, in SI units,
     * with the row's probe and held offsets (NULL settings: as the plan says) */
    status = lf_fit_input_from_plan(plan, NULL, 0, NULL, &in, NULL, &err);
    lf_plan_free(plan);         /* the input owns what it needs */
    if (status != LF_OK) {
        fprintf(stderr, "%s:%ld: %s\n", err.file, err.line, err.msg);
        return 1;
    }
    lf_fit_input_apply_nu(&in, &settings);   /* the plan's nu, if it gives one */

    /* one joint fit: w, E* (and nu where the curves determine it) shared */
    status = lf_fit_driver(&settings, in.n, in.curves, &res, &err);
    if (status != LF_OK && status != LF_ENOCONV) {
        fprintf(stderr, "fit: %s\n", err.msg);
        lf_fit_input_free(&in);
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
    lf_fit_input_free(&in);     /* after the fit: the curves point into it */
    return status == LF_OK ? 0 : 3;
}
