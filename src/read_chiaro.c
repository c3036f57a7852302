/* read_chiaro.c: Optics11 Chiaro / Piuma nanoindenter text exports.
 *
 * Layout, as the instrument writes it: some 35 header lines
 * (Key<TAB>value, Latin-1 bytes such as 0xB5 for the micro sign, mixed
 * CRLF / LF / LF CR line ends), then a tab-separated table
 *     Time (s)  Load (uN)  Indentation (nm)  Cantilever (nm)  Piezo (nm)  Auxiliary
 * with Load = k x Cantilever.  Conventions: Piezo grows as the probe moves
 * into the sample and Cantilever (the bending) is positive when pushing,
 * so the tip-sample separation, positive into the sample, is
 * Piezo - Cantilever.  The instrument's own "Indentation" is zero outside
 * contact (clamped), which hides the pull-off; it is used only when the
 * file lacks Piezo or Cantilever.  Header facts: "Tip radius (um)",
 * "k (N/m)", and the instrument's Hertz fit "E[eff] (Pa)" (kept as
 * metadata, to compare with). */
#include <math.h>
#include <string.h>

#include "readers.h"

static int
chiaro_sniff(const char *head, size_t len)
{
    char buf[4096];
    const char *p;
    lf_sniff_text(head, len, buf, sizeof buf);
    /* the table header, within the first few kB */
    for (p = buf; (p = strstr(p, "Time (s)\tLoad (")) != NULL; p++)
        if (strstr(p, "Cantilever (") != NULL || strstr(p, "Piezo (") != NULL)
            return 90;
    if (strstr(buf, "Tip radius (um)\t") != NULL && strstr(buf, "k (N/m)\t") != NULL)
        return 60;
    return 0;
}

static int
chiaro_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
            lf_error *err)
{
    static const char *const n_time[] = { "Time", NULL }, *const n_load[] = { "Load", NULL },
        *const n_ind[] = { "Indentation", NULL }, *const n_cant[] = { "Cantilever", NULL },
        *const n_piezo[] = { "Piezo", NULL };
    lf_text_table t;
    int jt, jl, ji, jc, jp, status;
    double ft = 1, fl = 1, fi = 1, fc = 1, fp = 1, R, k = NAN;
    size_t i;

    memset(&t, 0, sizeof t);
    t.skip_bad_rows = o->skip_bad_rows;
    status = lf_text_table_read(&t, in, c, err);
    if (status != LF_OK)
        goto done;
    jt = lf_text_table_find(&t, n_time, 0);
    jl = lf_text_table_find(&t, n_load, 0);
    ji = lf_text_table_find(&t, n_ind, 0);
    jc = lf_text_table_find(&t, n_cant, 0);
    jp = lf_text_table_find(&t, n_piezo, 0);
    if ((jl < 0 && jc < 0) || (ji < 0 && (jp < 0 || jc < 0))) {
        status = lf_fail_at(err, LF_EFORMAT, in->name, t.header_line, 0,
                            "Chiaro table without %s (expected Load (uN) or Cantilever (nm), "
                            "and Piezo (nm) with Cantilever (nm), or Indentation (nm))",
                            jl < 0 && jc < 0 ? "a force" : "a depth");
        goto done;
    }
    if ((jt >= 0 && (status = lf_text_table_factor(&t, jt, LF_Q_TIME, &ft, err)) != LF_OK)
        || (jl >= 0 && (status = lf_text_table_factor(&t, jl, LF_Q_FORCE, &fl, err)) != LF_OK)
        || (ji >= 0 && (status = lf_text_table_factor(&t, ji, LF_Q_LENGTH, &fi, err)) != LF_OK)
        || (jc >= 0 && (status = lf_text_table_factor(&t, jc, LF_Q_LENGTH, &fc, err)) != LF_OK)
        || (jp >= 0 && (status = lf_text_table_factor(&t, jp, LF_Q_LENGTH, &fp, err)) != LF_OK))
        goto done;
    if (lf_meta_number(c, "Tip radius (um)", LF_Q_LENGTH, &R) == 0 && R > 0) {
        c->R = R;
        lf_warn(&c->info, "probe radius %.6g m (file header 'Tip radius (um)')", R);
    }
    if (lf_meta_number(c, "k (N/m)", LF_Q_STIFFNESS, &k) == 0 && k > 0 && jl >= 0) {
        c->spring_constant = k;
        c->spring_constant_source = "file header";
        lf_warn(&c->info, "spring constant %.6g N/m (file header 'k (N/m)'; the file's "
                "Load is already k x Cantilever)", k);
    }
    if (jl < 0 && (status = lf_afm_spring_constant(c, k, "k (N/m)", o,
                   "to turn Cantilever into a force", err)) != LF_OK)
        goto done;
    if (lf_curve_reserve(c, t.n, jt >= 0) != 0) {
        status = lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
        goto done;
    }
    for (i = 0; i < t.n; i++) {
        c->force[i] = jl >= 0 ? fl * t.col[jl][i] : c->spring_constant * fc * t.col[jc][i];
        c->depth[i] = jp >= 0 && jc >= 0 ? fp * t.col[jp][i] - fc * t.col[jc][i]
                                         : fi * t.col[ji][i];
        if (jt >= 0)
            c->time[i] = ft * t.col[jt][i];
        c->line[i] = t.line[i];
    }
    c->n = t.n;
    if (jl >= 0)
        lf_warn(&c->info, "force: column '%s', x %.6g to N", t.cell[jl], fl);
    else
        lf_warn(&c->info, "force: k x column '%s'", t.cell[jc]);
    if (jp >= 0 && jc >= 0)
        lf_warn(&c->info, "depth: tip-sample separation = '%s' - '%s' (into the sample "
                "positive), x %.6g to m", t.cell[jp], t.cell[jc], fp);
    else
        lf_warn(&c->info, "depth: column '%s', x %.6g to m", t.cell[ji], fi);
    if (ji >= 0 && lf_is_clamped(t.col[ji], t.n))
        lf_warn(warn, "%s: column '%s' is clamped: %zu points sit exactly at its minimum "
                "(it hides the pull-off); %s", in->name, t.cell[ji],
                lf_count_at_min(t.col[ji], t.n),
                jp >= 0 && jc >= 0 ? "the separation Piezo - Cantilever is used instead"
                                   : "the file has no Piezo and Cantilever columns to "
                                     "compute the separation from");
    if (jp >= 0) {
        double *drive = t.col[jp];
        lf_segments_from_profile(c, drive, NULL, "piezo");
    } else {
        lf_segments_from_profile(c, c->depth, NULL, "depth");
    }
    return lf_text_table_finish(&t, c, warn, err);
done:
    lf_text_table_free(&t);
    return status;
}

const lf_reader_type lf_reader_chiaro = {
    "chiaro", "Optics11 Chiaro / Piuma text export (header lines, then Time, Load, "
    "Indentation, Cantilever, Piezo)",
    chiaro_sniff, chiaro_read
};
