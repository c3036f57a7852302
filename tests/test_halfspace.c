/* test_halfspace.c: JKR of a power-law punch on a half-space against the
 * closed forms of physics.md section 4 (Borodich et al. 2014) and the
 * classical sphere, its branches and its Jacobian. */
#include <math.h>

#include <gsl/gsl_errno.h>

#include "exact.h"
#include "layerfit.h"
#include "testlib.h"

static void
test_pulloff(double k)
{
    lf_probe pr = {k, 1.7e-3, 2e-6, LF_BASE_FRICTIONLESS};
    lf_material m = {0.0237, 2.385e6, 0.3};
    lf_error err;
    lf_model *mod = lf_model_alloc(&lf_model_halfspace, &pr, &err);
    lf_pulloff po;
    double kap = lf_exact_kappa(k), q8 = sqrt(8.0 * M_PI * m.w / m.Estar);
    double a_c = pow(3.0 / (4.0 * kap) * q8 * pow(pr.R, k - 1.0), 1.0 / (k - 0.5));
    double a_d = pow(sqrt(2.0 * M_PI * m.w / m.Estar) * pow(pr.R, k - 1.0) / (2.0 * kap),
                     1.0 / (k - 0.5));
    double P_c = -(2.0 * k - 1.0) / (2.0 * (k + 1.0)) * sqrt(8.0 * M_PI * m.w * m.Estar)
                 * pow(a_c, 1.5);
    lf_eval e[3];
    double d[3];

    if (mod == NULL || lf_model_pulloff(mod, &m, &po, &err) != LF_OK) {
        t_true(0, "halfspace k=%g", k);
        lf_model_free(mod);
        return;
    }
    t_rel(po.a_po, a_c, 1e-12, "k=%g force-controlled pull-off radius", k);
    t_rel(po.P_po, P_c, 1e-12, "k=%g pull-off force", k);
    t_rel(po.a_detach, a_d, 1e-12, "k=%g displacement-controlled detachment radius", k);
    t_abs(po.c, 0.0, 0.0, "c = 0");
    if (k == 2.0) {
        t_rel(po.P_po, -1.5 * M_PI * m.w * pr.R, 1e-12, "sphere: -3/2 pi w R");
        t_rel(po.a_po, lf_jkr_sphere_a_po(pr.R, m.w, m.Estar), 1e-12, "sphere: classical JKR a_po");
    }
    /* delta(a) minimal at a_detach; P minimal at delta_po */
    d[0] = po.delta_po * 1.001; d[1] = po.delta_po; d[2] = po.delta_po * 0.999;
    lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 3, d, e, NULL);
    t_true(e[0].P > e[1].P && e[2].P > e[1].P, "k=%g P minimal at delta_po", k);
    t_rel(e[1].a, a_c, 1e-9, "k=%g inversion returns a_c at delta_po", k);
    d[0] = po.delta_detach * (1.0 + 1e-9); d[1] = po.delta_detach * (1.0 - 1e-12);
    lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 2, d, e, NULL);
    t_true(e[0].P == 0.0 && e[0].a == 0.0, "k=%g no contact below delta_detach", k);
    t_rel(e[1].a, a_d, 1e-4, "k=%g contact ends at a_detach", k);
    t_true(fabs(e[1].dP_ddelta) <= 1e300, "k=%g slope capped at detachment", k);
    d[0] = -1e-15; d[1] = 0.0;
    lf_model_eval(mod, &m, LF_BRANCH_LOAD, 2, d, e, NULL);
    t_true(e[0].P == 0.0, "k=%g loading: no contact before delta = 0", k);
    t_rel(e[1].P, po.P_jump, 1e-12, "k=%g loading: jump to P_jump", k);
    t_true(po.P_jump < 0.0 && po.P_jump > po.P_po, "k=%g P_po < P_jump < 0", k);
    lf_model_free(mod);
}

/* Without adhesion: Hertz-type P(delta) of section 4, P1(delta1). */
static void
test_adhesiveless(void)
{
    lf_probe pr = {2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS};
    lf_material m = {0.0, 1.3e9, 0.3};
    lf_model *mod = lf_model_alloc(&lf_model_halfspace, &pr, NULL);
    double d = 1e-8;
    lf_eval e;
    if (mod == NULL)
        return;
    lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, &d, &e, NULL);
    /* Hertz: a^2 = R delta, P = 4/3 E* R^(1/2) delta^(3/2) */
    t_rel(e.a, sqrt(pr.R * d), 1e-12, "Hertz contact radius");
    t_rel(e.P, 4.0 / 3.0 * m.Estar * sqrt(pr.R) * pow(d, 1.5), 1e-12, "Hertz force");
    d = -1e-9;
    lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, &d, &e, NULL);
    t_true(e.P == 0.0 && e.a == 0.0, "w = 0: no contact at delta < 0");
    lf_model_free(mod);
}

static void
test_jacobian(void)
{
    lf_probe pr = {2.6, 1e-3, 1e-6, LF_BASE_BONDED};
    lf_material m = {0.0114, 1.37e9, 0.41};
    lf_model *mod = lf_model_alloc(&lf_model_halfspace, &pr, NULL);
    lf_pulloff po;
    int i;
    if (mod == NULL || lf_model_pulloff(mod, &m, &po, NULL) != LF_OK) {
        t_true(0, "alloc");
        lf_model_free(mod);
        return;
    }
    for (i = 0; i < 3; i++) {
        double d = po.delta_detach * (0.8 - 0.9 * i), h = 1e-6 * fabs(po.delta_detach), dp, dm, hl = 1e-6;
        lf_eval e, ep, em;
        lf_material mp = m, mm = m;
        lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, &d, &e, NULL);
        dp = d + h; dm = d - h;
        lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, &dp, &ep, NULL);
        lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, &dm, &em, NULL);
        t_rel(e.dP_ddelta, (ep.P - em.P) / (2 * h), 1e-6, "dP/ddelta pt %d", i);
        mp.w *= exp(hl); mm.w *= exp(-hl);
        lf_model_eval(mod, &mp, LF_BRANCH_UNLOAD, 1, &d, &ep, NULL);
        lf_model_eval(mod, &mm, LF_BRANCH_UNLOAD, 1, &d, &em, NULL);
        t_rel(e.dP_dlogw, (ep.P - em.P) / (2 * hl), 1e-6, "dP/dlnw pt %d", i);
        mp = m; mm = m;
        mp.Estar *= exp(hl); mm.Estar *= exp(-hl);
        lf_model_eval(mod, &mp, LF_BRANCH_UNLOAD, 1, &d, &ep, NULL);
        lf_model_eval(mod, &mm, LF_BRANCH_UNLOAD, 1, &d, &em, NULL);
        t_rel(e.dP_dlogE, (ep.P - em.P) / (2 * hl), 1e-6, "dP/dlnE pt %d", i);
        t_abs(e.dP_dnu, 0.0, 0.0, "dP/dnu = 0");
    }
    lf_model_free(mod);
}

int
main(void)
{
    lf_probe bad = {0.5, 1e-3, 1e-6, LF_BASE_FRICTIONLESS};
    lf_error err;

    gsl_set_error_handler_off();
    test_pulloff(2.0);
    test_pulloff(3.0);
    test_pulloff(1.0);
    test_adhesiveless();
    test_jacobian();
    t_true(lf_model_alloc(&lf_model_halfspace, &bad, &err) == NULL, "k = 1/2 refused");
    t_int(err.status, LF_EINVAL, "k = 1/2: EINVAL");
    t_str(lf_model_type_find("halfspace")->name, "halfspace", "halfspace is registered");
    return t_summary();
}
