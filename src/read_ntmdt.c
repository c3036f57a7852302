/* read_ntmdt.c: NT-MDT Nova force-curve text exports.
 *
 * Layout, as Nova writes it: no header, tab-separated, decimal comma; three
 * columns: the scanner height (nm), the deflection signal on approach (nA)
 * and on retract (nA), both at the height of their row.  No constants are
 * in the file: the spring constant and the deflection sensitivity (m/A) are
 * given with --spring-constant and --sensitivity.
 *
 * Conventions (those of afmformats, which reads these files): the height
 * falls as the probe moves into the sample, and the deflection grows when
 * the cantilever pushes.  The rows run from the deepest height to the
 * shallowest: the approach is the rows in reverse order, the retract the
 * rows in file order.  The deflection in m is d = signal x sensitivity;
 * the force is k d; the tip-sample separation, positive into the sample,
 * is -(height + d).  Nova pads the start of an exported column with
 * copies of one value: those rows (all but the last) are dropped. */
#include <math.h>
#include <string.h>

#include "readers.h"

static int
ntmdt_sniff(const char *head, size_t len)
{
    /* the first lines: exactly three tab-separated numbers, decimal comma */
    size_t i = 0, lines = 0, tabs = 0, commas = 0;
    for (i = 0; i < len && lines < 5; i++) {
        char ch = head[i];
        if (ch == '\n') {
            if (tabs != 2 || commas == 0)
                return 0;
            lines++;
            tabs = commas = 0;
        } else if (ch == '\t') {
            tabs++;
        } else if (ch == ',') {
            commas++;
        } else if (!(ch >= '0' && ch <= '9') && ch != '-' && ch != '+' && ch != '\r'
                   && ch != 'e' && ch != 'E' && ch != ' ') {
            return 0;
        }
    }
    return lines >= 2 ? 50 : 0;
}

/* Index of the first row after the padding of column x: 0 when none. */
static size_t
padding(const double *x, size_t n)
{
    size_t i = 1;
    while (i < n && x[i] == x[0])
        i++;
    return i >= n ? 0 : i - 1;
}

static int
ntmdt_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
           lf_error *err)
{
    lf_text_table t;
    int status;
    size_t i, m = 0, pa, pr;
    double fd, sens_unit;

    memset(&t, 0, sizeof t);
    t.no_header = 1;
    t.skip_bad_rows = o->skip_bad_rows;
    status = lf_text_table_read(&t, in, c, err);
    if (status != LF_OK)
        goto done;
    if (t.ncol != 3) {
        status = lf_fail_at(err, LF_EFORMAT, in->name, t.n > 0 ? t.line[0] : 0, 0,
                            "%zu columns (an NT-MDT export has 3: height (nm), deflection "
                            "approach (nA), deflection retract (nA))", t.ncol);
        goto done;
    }
    if ((status = lf_afm_spring_constant(c, NAN, "", o, "to turn the deflection into a force",
                                         err)) != LF_OK
        || (status = lf_afm_sensitivity(c, NAN, "", 1, o, err)) != LF_OK)
        goto done;
    pa = padding(t.col[1], t.n);
    pr = padding(t.col[2], t.n);
    if (lf_curve_reserve(c, 2 * t.n, 0) != 0) {
        status = lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
        goto done;
    }
    sens_unit = 1e-9;       /* nA */
    fd = sens_unit * c->sensitivity;
    for (i = t.n; i-- > pa;) {  /* approach: shallow to deep */
        double h = 1e-9 * t.col[0][i], d = fd * t.col[1][i];
        c->depth[m] = -(h + d);
        c->force[m] = c->spring_constant * d;
        c->segment[m] = LF_SEG_LOAD;
        c->line[m++] = t.line[i];
    }
    for (i = pr; i < t.n; i++) {  /* retract: deep to shallow */
        double h = 1e-9 * t.col[0][i], d = fd * t.col[2][i];
        c->depth[m] = -(h + d);
        c->force[m] = c->spring_constant * d;
        c->segment[m] = LF_SEG_UNLOAD;
        c->line[m++] = t.line[i];
    }
    c->n = m;
    lf_warn(&c->info, "columns (no header): height (nm), deflection approach (nA), "
            "deflection retract (nA)%s", t.decimal_comma ? ", decimal comma" : "");
    lf_warn(&c->info, "force: k x sensitivity x deflection; depth: tip-sample separation = "
            "-(height + deflection) (into the sample positive)");
    lf_warn(&c->info, "segments: side-by-side columns, approach %zu points (rows in reverse), "
            "retract %zu points", t.n - pa, t.n - pr);
    if (pa > 0 || pr > 0)
        lf_warn(&c->info, "dropped padded rows at the start of the export: %zu approach, "
                "%zu retract (a constant copied value)", pa, pr);
    return lf_text_table_finish(&t, c, warn, err);
done:
    lf_text_table_free(&t);
    return status;
}

const lf_reader_type lf_reader_ntmdt = {
    "ntmdt", "NT-MDT Nova text export (no header; height, deflection approach and retract "
    "in nA; decimal comma)",
    ntmdt_sniff, ntmdt_read
};
