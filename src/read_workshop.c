/* read_workshop.c: AFM Workshop force-distance CSV exports.
 *
 * Layout, as the AFM Workshop software writes it: "Force-Distance Curve",
 * then "Key:<TAB>value" lines (date, position, and in newer versions
 * "Light Lever Gain, mV/nm" and "Force Constant, nN/nm"), a blank line, and
 * a comma-separated table holding the extend and the retract side by side:
 *     Extend Z-Sense(nm),Extend T-B(V),Retract Z-Sense(nm),Retract T-B(V)
 * (or "Extend Force(nN)" / "Retract Force(nN)" instead of the T-B signal).
 * Conventions: Z-Sense grows as the probe moves into the sample; T-B (the
 * photodiode's top-minus-bottom deflection signal) and Force grow when the
 * cantilever pushes.  The deflection in m is T-B / gain (gain in V/m) or
 * Force / k; the force is k x deflection; the tip-sample separation,
 * positive into the sample, is Z-Sense - deflection.  The software writes
 * 1.000000 for a gain or force constant nobody set: those are ignored, as
 * afmformats does, and the options --sensitivity / --spring-constant are
 * needed then.  Rows are extend in file order, then retract in file order. */
#include <math.h>
#include <string.h>

#include "readers.h"

static int
workshop_sniff(const char *head, size_t len)
{
    char buf[8192];
    lf_sniff_text(head, len, buf, sizeof buf);
    if (strstr(buf, "Extend Z-Sense") != NULL && strstr(buf, "Retract Z-Sense") != NULL)
        return 90;
    if (strncmp(buf, "Force-Distance Curve", 20) == 0)
        return 60;
    return 0;
}

/* A header constant, unless it is the software's default of exactly 1. */
static double
constant(const lf_curve *c, const char *key, lf_quantity q, lf_warnings *info)
{
    const char *v = lf_curve_meta(c, key);
    double x;
    if (v == NULL || lf_meta_number(c, key, q, &x) != 0)
        return NAN;
    if (lf_csv_number(v, 0, &x) == LF_NUM_OK && x == 1.0) {
        lf_warn(info, "file header '%s' = 1 is the software's unset default: ignored", key);
        return NAN;
    }
    lf_meta_number(c, key, q, &x);
    return x;
}

/* A needed constant whose header line holds the unset default (or no
 * number): say so, rather than that the file has none. */
static int
unset_default(const lf_curve *c, const char *key, const char *what, const char *example,
              lf_error *err)
{
    char buf[64];
    return lf_fail_at(err, LF_EDATA, c->file, 0, 0,
                      "the file's '%s' reads '%s', not a calibrated value (1 is the "
                      "software's unset default), and the %s is needed to convert the "
                      "signals (give it: %s)", key,
                      lf_csv_excerpt(lf_curve_meta(c, key), buf, sizeof buf), what, example);
}

static int
workshop_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
              lf_error *err)
{
    static const char *const ez[] = { "Extend Z-Sense", "Extend Z", NULL },
        *const rz[] = { "Retract Z-Sense", "Retract Z", NULL },
        *const ed[] = { "Extend T-B", "Extend Force", "Extend Deflection", NULL },
        *const rd[] = { "Retract T-B", "Retract Force", "Retract Deflection", NULL };
    lf_text_table t;
    int jz[2], jd[2], status, side, is_force;
    double fz, fd, k = NAN, gain, sens = NAN;
    size_t i, m = 0;

    memset(&t, 0, sizeof t);
    t.skip_bad_rows = o->skip_bad_rows;
    status = lf_text_table_read(&t, in, c, err);
    if (status != LF_OK)
        goto done;
    jz[0] = lf_text_table_find(&t, ez, 0);
    jz[1] = lf_text_table_find(&t, rz, 0);
    jd[0] = lf_text_table_find(&t, ed, 0);
    jd[1] = lf_text_table_find(&t, rd, 0);
    if (jz[0] < 0 || jz[1] < 0 || jd[0] < 0 || jd[1] < 0) {
        status = lf_fail_at(err, LF_EFORMAT, in->name, t.header_line, 0,
                            "expected the columns Extend Z-Sense(nm), Extend T-B(V) or "
                            "Extend Force(nN), Retract Z-Sense(nm), Retract T-B(V) or "
                            "Retract Force(nN)");
        goto done;
    }
    if (strcmp(t.unit[jd[0]], t.unit[jd[1]]) != 0 || strcmp(t.unit[jz[0]], t.unit[jz[1]]) != 0) {
        status = lf_fail_at(err, LF_EUNIT, in->name, t.header_line, 0,
                            "extend and retract columns in different units");
        goto done;
    }
    if ((status = lf_text_table_factor(&t, jz[0], LF_Q_LENGTH, &fz, err)) != LF_OK)
        goto done;
    is_force = lf_units_factor(t.unit[jd[0]], LF_Q_FORCE, &fd, NULL) == LF_OK;
    if (!is_force && (status = lf_text_table_factor(&t, jd[0], LF_Q_VOLTAGE, &fd, err)) != LF_OK)
        goto done;
    k = constant(c, "Force Constant, nN/nm", LF_Q_STIFFNESS, &c->info);
    if (isnan(k) && lf_curve_meta(c, "Force Constant, nN/nm") != NULL
        && !(isfinite(o->spring_constant) && o->spring_constant > 0)) {
        status = unset_default(c, "Force Constant, nN/nm", "cantilever spring constant",
                               "--spring-constant 0.032N/m", err);
        goto done;
    }
    if ((status = lf_afm_spring_constant(c, k, "Force Constant, nN/nm", o, is_force
                                         ? "to turn the force into a deflection for the "
                                           "tip-sample separation"
                                         : "to turn the deflection into a force", err)) != LF_OK)
        goto done;
    if (!is_force) {
        /* gain in mV/nm = V/m x 1e-3 / 1e-9: sensitivity (m/V) = 1e-6 / gain */
        gain = constant(c, "Light Lever Gain, mV/nm", LF_Q_DIMENSIONLESS, &c->info);
        if (isfinite(gain) && gain > 0)
            sens = 1e-6 / gain;
        if (isnan(gain) && lf_curve_meta(c, "Light Lever Gain, mV/nm") != NULL
            && !(isfinite(o->sensitivity) && o->sensitivity > 0)) {
            status = unset_default(c, "Light Lever Gain, mV/nm", "deflection sensitivity",
                                   "--sensitivity 50nm/V", err);
            goto done;
        }
        if ((status = lf_afm_sensitivity(c, sens, "Light Lever Gain, mV/nm", 0, o, err)) != LF_OK)
            goto done;
    }
    if (lf_curve_reserve(c, 2 * t.n, 0) != 0) {
        status = lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
        goto done;
    }
    for (side = 0; side < 2; side++)
        for (i = 0; i < t.n; i++, m++) {
            double z = fz * t.col[jz[side]][i], d, f;
            if (is_force) {
                f = fd * t.col[jd[side]][i];
                d = f / c->spring_constant;
            } else {
                d = fd * t.col[jd[side]][i] * c->sensitivity;
                f = c->spring_constant * d;
            }
            c->depth[m] = z - d;
            c->force[m] = f;
            c->segment[m] = (unsigned char) (side == 0 ? LF_SEG_LOAD : LF_SEG_UNLOAD);
            c->line[m] = t.line[i];
        }
    c->n = m;
    lf_warn(&c->info, "force: '%s' / '%s'%s", t.cell[jd[0]], t.cell[jd[1]],
            is_force ? "" : " x sensitivity x k");
    lf_warn(&c->info, "depth: tip-sample separation = Z-Sense - deflection (into the sample "
            "positive), from '%s' / '%s'", t.cell[jz[0]], t.cell[jz[1]]);
    lf_warn(&c->info, "segments: side-by-side columns, extend %zu and retract %zu points",
            t.n, t.n);
    return lf_text_table_finish(&t, c, warn, err);
done:
    lf_text_table_free(&t);
    return status;
}

const lf_reader_type lf_reader_workshop = {
    "workshop", "AFM Workshop force-distance CSV (extend and retract columns side by side)",
    workshop_sniff, workshop_read
};
