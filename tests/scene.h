/* scene.h: synthetic fitting scenes shared by the fit tests: a material,
 * probes and simulation settings, simulated with lf_simulate and fitted
 * with lf_fit. */
#ifndef LF_TEST_SCENE_H
#define LF_TEST_SCENE_H

#include "layerfit.h"

#define SCENE_MAX 4

typedef struct {
    const char *label;
    lf_material mat;
    size_t n;                   /* probes */
    lf_probe probe[SCENE_MAX];
    lf_sim_settings sim;
    lf_fit_settings fit;
    int fix_z0, fix_F0;         /* hold them at the simulated values */
    const lf_model_type *sim_model; /* model that makes the data (NULL = thin) */
    /* filled by scene_simulate */
    double *depth[SCENE_MAX], *force[SCENE_MAX];
    double sigma[SCENE_MAX];
    lf_fit_curve curve[SCENE_MAX];
} scene;

/* A scene with defaults: w = 12.3 mJ/m^2, E* = 1.85 GPa, nu = 0.35, no
 * probes yet, 300 points, z0 = 15 nm, F0 = 0.21 uN. */
scene scene_default(const char *label);
void scene_add(scene *s, double k, double R, double b, lf_base base);
/* Simulate with the given seed (allocates the arrays once) and describe
 * the curves in s->curve. */
int scene_simulate(scene *s, unsigned long seed);
/* Simulate and fit; res must be freed with lf_fit_result_free. */
int scene_fit(scene *s, unsigned long seed, lf_fit_result *res, lf_error *err);
void scene_free(scene *s);

#endif
