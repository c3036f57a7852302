/* abi.c: the layout of every C structure the Python package mirrors with
 * ctypes (src/python/layerfit/_lib.py), as the compiler lays it out: JSON
 * {"NAME": {"size": N, "fields": {"FIELD": OFFSET, ...}}, ...} on stdout,
 * compared with the mirrors by tests/python/test_abi.py. */
#include <stddef.h>
#include <stdio.h>

#include "layerfit.h"

static int first_struct = 1, first_field;

static void
begin(const char *name, size_t size)
{
    printf("%s\n  \"%s\": {\"size\": %zu, \"fields\": {", first_struct ? "{" : ",", name, size);
    first_struct = 0;
    first_field = 1;
}

static void
field(const char *name, size_t offset)
{
    printf("%s\"%s\": %zu", first_field ? "" : ", ", name, offset);
    first_field = 0;
}

static void
end(void)
{
    printf("}}");
}

#define S(T) begin(#T, sizeof(T))
#define F(T, m) field(#m, offsetof(T, m))

int
main(void)
{
    S(lf_error); F(lf_error, status); F(lf_error, file); F(lf_error, line);
    F(lf_error, column); F(lf_error, msg); end();
    S(lf_warnings); F(lf_warnings, n); F(lf_warnings, msg); end();
    S(lf_meta); F(lf_meta, key); F(lf_meta, value); end();
    S(lf_curve); F(lf_curve, file); F(lf_curve, n); F(lf_curve, depth); F(lf_curve, force);
    F(lf_curve, time); F(lf_curve, segment); F(lf_curve, line); F(lf_curve, nmeta);
    F(lf_curve, meta); F(lf_curve, format); F(lf_curve, R); F(lf_curve, spring_constant);
    F(lf_curve, sensitivity); F(lf_curve, spring_constant_source);
    F(lf_curve, sensitivity_source); F(lf_curve, sensitivity_unit); F(lf_curve, info);
    F(lf_curve, x); F(lf_curve, y); F(lf_curve, grid_i); F(lf_curve, grid_j);
    F(lf_curve, index); end();
    S(lf_curve_info); F(lf_curve_info, x); F(lf_curve_info, y); F(lf_curve_info, grid_i);
    F(lf_curve_info, grid_j); F(lf_curve_info, points); F(lf_curve_info, segment_points); end();
    S(lf_option); F(lf_option, name); F(lf_option, kind); F(lf_option, quantity); end();
    S(lf_probe); F(lf_probe, k); F(lf_probe, R); F(lf_probe, b); F(lf_probe, base);
    F(lf_probe, tip); F(lf_probe, angle); F(lf_probe, B); end();
    S(lf_material); F(lf_material, w); F(lf_material, Estar); F(lf_material, nu); end();
    S(lf_pulloff); F(lf_pulloff, delta_detach); F(lf_pulloff, P_detach);
    F(lf_pulloff, a_detach); F(lf_pulloff, delta_po); F(lf_pulloff, P_po); F(lf_pulloff, a_po);
    F(lf_pulloff, sigma_po); F(lf_pulloff, P_jump); F(lf_pulloff, c); end();
    S(lf_eval); F(lf_eval, P); F(lf_eval, a); F(lf_eval, dP_ddelta); F(lf_eval, dP_dlogw);
    F(lf_eval, dP_dlogE); F(lf_eval, dP_dnu); end();
    S(lf_model_summary); F(lf_model_summary, probe); F(lf_model_summary, mat);
    F(lf_model_summary, type); F(lf_model_summary, pulloff); F(lf_model_summary, Z);
    F(lf_model_summary, sigma_th); F(lf_model_summary, b_cr); F(lf_model_summary, b_cr_over_a);
    F(lf_model_summary, from); F(lf_model_summary, width); end();
    S(lf_sim_settings); F(lf_sim_settings, points); F(lf_sim_settings, delta_max);
    F(lf_sim_settings, delta_min); F(lf_sim_settings, past_c); F(lf_sim_settings, noise);
    F(lf_sim_settings, z0); F(lf_sim_settings, F0); F(lf_sim_settings, seed);
    F(lf_sim_settings, branch); end();
    S(lf_batch_settings); F(lf_batch_settings, json); F(lf_batch_settings, threads);
    F(lf_batch_settings, shard_index); F(lf_batch_settings, shard_count);
    F(lf_batch_settings, ordered); F(lf_batch_settings, results);
    F(lf_batch_settings, csv_raw); end();
    S(lf_batch_row); F(lf_batch_row, fit); F(lf_batch_row, sample); F(lf_batch_row, status);
    F(lf_batch_row, outcome); F(lf_batch_row, text); F(lf_batch_row, len);
    F(lf_batch_row, result); F(lf_batch_row, input); F(lf_batch_row, done);
    F(lf_batch_row, total); F(lf_batch_row, failed); F(lf_batch_row, misfits);
    F(lf_batch_row, why); F(lf_batch_row, cause); end();
    S(lf_batch_summary); F(lf_batch_summary, fits); F(lf_batch_summary, total);
    F(lf_batch_summary, done); F(lf_batch_summary, failed); F(lf_batch_summary, misfits);
    F(lf_batch_summary, stopped); end();
    S(lf_fit_figure); F(lf_fit_figure, z0); F(lf_fit_figure, F0); F(lf_fit_figure, slope);
    F(lf_fit_figure, z_po); F(lf_fit_figure, F_po); F(lf_fit_figure, delta_detach);
    F(lf_fit_figure, delta_po); F(lf_fit_figure, have); end();
    S(lf_provenance); F(lf_provenance, command_line); F(lf_provenance, ninputs);
    F(lf_provenance, input); F(lf_provenance, sha256); end();
    printf("\n}\n");
    return 0;
}
