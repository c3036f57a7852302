/* simulate.c: synthetic force-depth curves from any forward model, with
 * Gaussian noise from GSL's Mersenne Twister (gsl_rng_mt19937), so a plan
 * and a seed give the same numbers on every machine.  Used by
 * `layerfit simulate`, the recovery tests and the bundled datasets. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "internal.h"

lf_sim_settings
lf_sim_settings_default(void)
{
    lf_sim_settings s;
    memset(&s, 0, sizeof s);
    s.points = 300;
    s.delta_max = 50e-9;
    s.delta_min = NAN;
    s.past_c = 1.2;
    s.noise = 0.0;
    s.z0 = 0.0;
    s.F0 = 0.0;
    s.seed = 1;
    s.branch = LF_BRANCH_UNLOAD;
    return s;
}

/* One curve without noise: indentations from delta_max down to the
 * shallowest one (reversed for loading), model forces into force[]. */
static int
simulate_curve(const lf_sim_settings *s, const lf_model *m,
               const lf_material *mat, lf_eval *ev, double *depth,
               double *force, double *fbig, lf_error *err)
{
    lf_pulloff po;
    size_t i, n = s->points;
    double lo, hi = s->delta_max;
    int status = lf_model_pulloff(m, mat, &po, err);

    if (status != LF_OK)
        return status;
    lo = s->delta_min;
    if (isnan(lo))
        lo = po.c > 0 ? -s->past_c * po.c : -0.2 * hi;
    if (!(lo < hi))
        return lf_fail(err, LF_EINVAL, "the shallowest indentation (%g m) must lie above "
                       "the deepest (%g m)", lo, hi);
    for (i = 0; i < n; i++) {
        double t = (double) i / (double) (n - 1);
        depth[i] = s->branch == LF_BRANCH_UNLOAD ? hi - t * (hi - lo) : lo + t * (hi - lo);
    }
    status = lf_model_eval(m, mat, s->branch, n, depth, ev, err);
    if (status != LF_OK)
        return status;
    *fbig = 0.0;
    for (i = 0; i < n; i++) {
        force[i] = ev[i].P;
        *fbig = fmax(*fbig, fabs(force[i]));
    }
    return LF_OK;
}

int
lf_simulate(const lf_sim_settings *s, const lf_model_type *type,
            const lf_material *mat, size_t ncurves, const lf_probe *probes,
            double *const *depth, double *const *force, double *sigma,
            lf_error *err)
{
    gsl_rng *rng = NULL;
    lf_eval *ev = NULL;
    size_t i, j;
    int status = LF_OK;

    if (s->points < 2 || !isfinite(s->delta_max) || !(s->noise >= 0)
        || !isfinite(s->noise) || !isfinite(s->z0) || !isfinite(s->F0)
        || !(isnan(s->delta_min) || isfinite(s->delta_min)) || !(s->past_c > 0)
        || (s->branch != LF_BRANCH_UNLOAD && s->branch != LF_BRANCH_LOAD))
        return lf_fail(err, LF_EINVAL, "simulation settings out of range "
                       "(points >= 2, finite depths and offsets, noise >= 0)");
    rng = gsl_rng_alloc(gsl_rng_mt19937);
    ev = malloc(s->points * sizeof *ev);
    if (rng == NULL || ev == NULL) {
        status = lf_fail(err, LF_ENOMEM, "out of memory simulating");
        goto done;
    }
    gsl_rng_set(rng, s->seed);
    for (j = 0; j < ncurves && status == LF_OK; j++) {
        lf_model *m = lf_model_alloc(type, &probes[j], err);
        double fbig = 0.0, sd;
        if (m == NULL) {
            status = err ? err->status : LF_EINVAL;
            break;
        }
        status = lf_model_check_region(m, mat, err);
        if (status == LF_OK)
            status = simulate_curve(s, m, mat, ev, depth[j], force[j], &fbig, err);
        lf_model_free(m);
        if (status != LF_OK)
            break;
        sd = s->noise * fbig;
        for (i = 0; i < s->points; i++) {
            depth[j][i] += s->z0;
            force[j][i] += s->F0 + (sd > 0 ? gsl_ran_gaussian(rng, sd) : 0.0);
            if (!isfinite(depth[j][i]) || !isfinite(force[j][i])) {
                status = lf_fail(err, LF_EINVAL, "curve %zu: the %s at indentation %.4g m is not "
                                 "a finite number (offsets, noise or depths too large for "
                                 "double precision)", j + 1,
                                 isfinite(depth[j][i]) ? "force" : "depth", depth[j][i] - s->z0);
                break;
            }
        }
        if (status != LF_OK)
            break;
        if (sigma != NULL)
            sigma[j] = sd;
    }
done:
    gsl_rng_free(rng);
    free(ev);
    return status;
}
