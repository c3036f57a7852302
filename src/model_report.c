/* model_report.c: what `layerfit model --summary` and `--json` report of a
 * model at one material -- the pull-off and detachment, Z, the critical
 * thickness of Eq. (19) and b_cr/a_po of Eq. (20) (seed paper), the
 * default range of a curve -- and its JSON document, for the command and
 * for bindings (lf_model_summarise, lf_model_summary_json in layerfit.h). */
#include <math.h>

#include "internal.h"

int
lf_model_summarise(const lf_model *m, const lf_material *mat, double sigma_th,
                   lf_model_summary *s, lf_error *err)
{
    const lf_pulloff *po = &s->pulloff;
    double span;
    int status;

    s->probe = *lf_model_get_probe(m);
    s->type = lf_model_get_type(m);
    s->mat = *mat;
    s->Z = lf_thin_Z(s->probe.base, s->mat.nu);
    /* parameters the model cannot evaluate: refused, never a summary of
     * NaN or zeros */
    if ((status = lf_model_check_region(m, mat, err)) != LF_OK)
        return status;
    if ((status = lf_model_pulloff(m, &s->mat, &s->pulloff, err)) != LF_OK)
        return status;
    s->sigma_th = sigma_th;
    s->b_cr = s->b_cr_over_a = NAN;
    if (!isnan(sigma_th) && s->mat.w > 0) {   /* w = 0: no pull-off stress */
        /* Eq. (19) and (20): the pull-off radius of a layer of thickness b_cr */
        lf_probe crit = s->probe;
        lf_pulloff pc;
        lf_model *mc;

        s->b_cr = lf_thin_b_critical(s->probe.k, s->mat.w, s->Z * s->mat.Estar, sigma_th);
        crit.b = s->b_cr;
        mc = lf_model_alloc(&lf_model_thin, &crit, err);
        if (mc == NULL)
            return err != NULL ? err->status : LF_ENOMEM;
        status = lf_model_pulloff(mc, &s->mat, &pc, err);
        lf_model_free(mc);
        if (status != LF_OK)
            return status;
        s->b_cr_over_a = s->b_cr / pc.a_po;
    }
    /* a curve from detachment over ten pull-off widths */
    span = fmax(fabs(po->delta_po - po->delta_detach), fabs(po->delta_detach));
    s->from = po->delta_detach;
    s->width = 10.0 * span;
    return LF_OK;
}

static void
jnum(lf_str *b, const char *name, double x, int last)
{
    lf_str_printf(b, "  \"%s\": ", name);
    lf_str_number(b, x, "null");
    lf_str_puts(b, last ? "\n" : ",\n");
}

int
lf_model_summary_json(const lf_model_summary *s, char **json, lf_error *err)
{
    const lf_pulloff *po = &s->pulloff;
    int halfspace = s->type->scope == LF_SCOPE_HALFSPACE;
    int has_R = lf_probe_uses_R(&s->probe);   /* a cone's or a B's R is nothing */
    lf_str b = { NULL, 0, 0, 0 };

    lf_str_printf(&b, "{\n  \"model\": \"%s\",\n  \"interface\": \"%s\",\n", s->type->name,
                  s->probe.base == LF_BASE_BONDED ? "bonded" : "frictionless");
    lf_str_printf(&b, "  \"tip\": \"%s\",\n", lf_tip_name(s->probe.tip));
    jnum(&b, "k", s->probe.k, 0);
    jnum(&b, "R_m", has_R ? s->probe.R : NAN, 0);
    jnum(&b, "B", lf_probe_prefactor(&s->probe), 0);
    jnum(&b, "cone_half_angle_rad", lf_probe_cone_angle(&s->probe), 0);
    jnum(&b, "b_m", halfspace ? NAN : s->probe.b, 0);
    jnum(&b, "w_J_per_m2", s->mat.w, 0);
    jnum(&b, "Estar_Pa", s->mat.Estar, 0);
    jnum(&b, "nu", s->probe.base == LF_BASE_BONDED ? s->mat.nu : NAN, 0);
    jnum(&b, "Z", s->Z, 0);
    jnum(&b, "c_m", po->c, 0);
    jnum(&b, "delta_detach_m", po->delta_detach, 0);
    jnum(&b, "P_detach_N", po->P_detach, 0);
    jnum(&b, "a_detach_m", po->a_detach, 0);
    jnum(&b, "delta_po_m", po->delta_po, 0);
    jnum(&b, "P_po_N", po->P_po, 0);
    jnum(&b, "a_po_m", po->a_po, 0);
    jnum(&b, "sigma_po_Pa", po->sigma_po, 0);
    jnum(&b, "P_jump_N", po->P_jump, 0);
    jnum(&b, "b_over_a_po", halfspace ? NAN : s->probe.b / po->a_po, 0);
    jnum(&b, "a_jkr_sphere_po_m", has_R ? lf_jkr_sphere_a_po(s->probe.R, s->mat.w, s->mat.Estar)
                                        : NAN, 0);
    jnum(&b, "b_cr_m", s->b_cr, 0);
    jnum(&b, "b_cr_over_a_po", s->b_cr_over_a, 1);
    lf_str_puts(&b, "}\n");
    return lf_str_take(&b, json, err);
}
