/* scene.c: see scene.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

scene
scene_default(const char *label)
{
    scene s;
    memset(&s, 0, sizeof s);
    s.label = label;
    s.mat.w = 12.3e-3;
    s.mat.Estar = 1.85e9;
    s.mat.nu = 0.35;
    s.sim = lf_sim_settings_default();
    s.sim.z0 = 15e-9;
    s.sim.F0 = 0.21e-6;
    s.fit = lf_fit_settings_default();
    return s;
}

void
scene_add(scene *s, double k, double R, double b, lf_base base)
{
    lf_probe p = { 0 };
    p.k = k;
    p.R = R;
    p.b = b;
    p.base = base;
    if (k == 1.0)
        p.B = 1.0;   /* R cancels at k = 1: the paper's profile is f = r */
    if (s->n < SCENE_MAX)
        s->probe[s->n++] = p;
}

int
scene_simulate(scene *s, unsigned long seed)
{
    size_t j;

    for (j = 0; j < s->n; j++) {
        if (s->depth[j] == NULL) {
            s->depth[j] = malloc(s->sim.points * sizeof(double));
            s->force[j] = malloc(s->sim.points * sizeof(double));
            if (s->depth[j] == NULL || s->force[j] == NULL)
                return LF_ENOMEM;
        }
    }
    s->sim.seed = seed;
    for (j = 0; j < s->n; j++) {
        lf_fit_curve *c = &s->curve[j];
        c->name = s->label;
        c->n = s->sim.points;
        c->depth = s->depth[j];
        c->force = s->force[j];
        c->probe = s->probe[j];
        c->branch = s->sim.branch;
        c->z0 = s->fix_z0 ? s->sim.z0 : NAN;
        c->F0 = s->fix_F0 ? s->sim.F0 : NAN;
    }
    return lf_simulate(&s->sim, s->sim_model ? s->sim_model : &lf_model_thin, &s->mat, s->n, s->probe,
                       s->depth, s->force, s->sigma, NULL);
}

int
scene_fit(scene *s, unsigned long seed, lf_fit_result *res, lf_error *err)
{
    int status = scene_simulate(s, seed);

    if (status != LF_OK)
        return status;
    return lf_fit_driver(&s->fit, s->n, s->curve, res, err);
}

void
scene_free(scene *s)
{
    size_t j;
    for (j = 0; j < s->n; j++) {
        free(s->depth[j]);
        free(s->force[j]);
        s->depth[j] = s->force[j] = NULL;
    }
}
