/* fuzz_check.h: what the fuzz targets and the regression test ask of the
 * readers for any input: no crash, no leak, an error message whenever they
 * fail, and the same result whole and fed in chunks.  Each function
 * returns 0 when all holds. */
#ifndef LF_FUZZ_CHECK_H
#define LF_FUZZ_CHECK_H

#include <string.h>

#include "layerfit.h"

static inline int
fuzz_same_error(const lf_error *a, const lf_error *b)
{
    return a->status == b->status && a->line == b->line && a->column == b->column
        && strcmp(a->msg, b->msg) == 0 && a->msg[0] != '\0';
}

/* The curve reader on buf, whole and in pieces of chunk bytes. */
static inline int
fuzz_curve(const char *buf, size_t len, size_t chunk, int skip_bad_rows)
{
    lf_read_opts o;
    lf_curve *a = NULL, *b = NULL;
    lf_error ea, eb;
    lf_warnings w = { 0, NULL };
    int sa, sb, bad = 0;

    lf_read_opts_default(&o);
    o.skip_bad_rows = skip_bad_rows;
    sa = lf_curve_parse(buf, len, 0, "fuzz.csv", &o, &a, &w, &ea);
    sb = lf_curve_parse(buf, len, chunk, "fuzz.csv", &o, &b, NULL, &eb);
    if (sa != sb || (sa != LF_OK && !fuzz_same_error(&ea, &eb)))
        bad = 1;
    else if (sa == LF_OK) {
        size_t nl = lf_curve_segment(a, LF_SEG_LOAD, NULL, NULL);
        size_t nu = lf_curve_segment(a, LF_SEG_UNLOAD, NULL, NULL);
        size_t nh = lf_curve_segment(a, LF_SEG_HOLD, NULL, NULL);
        bad = a->n == 0 || a->n != b->n || nl + nu + nh != a->n
            || memcmp(a->depth, b->depth, a->n * sizeof *a->depth) != 0
            || memcmp(a->force, b->force, a->n * sizeof *a->force) != 0;
        if (lf_curve_check_fit(a, LF_SEG_UNLOAD, 6, &ea) != LF_OK && ea.msg[0] == '\0')
            bad = 1;
        {
            /* what the curve shows without a model, and a window placed
             * from it: no crash, no negative pull or work */
            lf_observables ob;
            lf_window win = lf_window_all();
            lf_window_placed wp;
            if (lf_observe(a, &ob, &ea) != LF_OK
                || ob.adhesion_force < 0 || ob.detachment_work < 0)
                bad = 1;
            win.depth.hi = 0.3;
            win.depth.relative = 1;
            win.force.lo = 0.0;
            if (lf_window_place(&win, &ob, &wp, &ea) != LF_OK && ea.msg[0] == '\0')
                bad = 1;
        }
    }
    lf_curve_free(a);
    lf_curve_free(b);
    lf_warnings_free(&w);
    return bad;
}

/* One instrument reader, forced by name, on buf whole and in pieces, with
 * a spring constant and a sensitivity given (so that the AFM conversions
 * run; per_amp picks m/A or m/V).  Every point must be finite and in one
 * of the three segments. */
static inline int
fuzz_reader(const char *format, const char *buf, size_t len, size_t chunk, int per_amp)
{
    lf_read_opts o;
    lf_curve *a = NULL, *b = NULL;
    lf_error ea, eb;
    lf_warnings w = { 0, NULL };
    int sa, sb, bad = 0;
    size_t i;

    lf_read_opts_default(&o);
    o.format = format;
    o.spring_constant = 0.05;
    o.sensitivity = per_amp ? 61.0 : 5e-8;
    o.sensitivity_per_amp = per_amp;
    o.skip_bad_rows = (int) (len & 1);
    sa = lf_curve_parse(buf, len, 0, "fuzz.txt", &o, &a, &w, &ea);
    sb = lf_curve_parse(buf, len, chunk, "fuzz.txt", &o, &b, NULL, &eb);
    if (sa != sb || (sa != LF_OK && !fuzz_same_error(&ea, &eb)))
        bad = 1;
    else if (sa == LF_OK) {
        bad = a->n == 0 || a->n != b->n || strcmp(a->format, format) != 0
            || memcmp(a->depth, b->depth, a->n * sizeof *a->depth) != 0
            || memcmp(a->force, b->force, a->n * sizeof *a->force) != 0
            || memcmp(a->segment, b->segment, a->n) != 0;
        for (i = 0; !bad && i < a->n; i++)
            bad = !(a->depth[i] - a->depth[i] == 0) || !(a->force[i] - a->force[i] == 0)
                || a->segment[i] > LF_SEG_HOLD;
    }
    lf_curve_free(a);
    lf_curve_free(b);
    lf_warnings_free(&w);
    return bad;
}

/* A reader of many curves per file, forced by name, on buf in memory: the
 * file opened, every curve (the first 8) described and decoded, with a
 * spring constant and a sensitivity given; each point finite and in one
 * of the three segments; an error always says what is wrong.  Then the
 * same through lf_curve_parse (one curve, or how many it holds). */
static inline int
fuzz_file(const char *format, const char *buf, size_t len)
{
    lf_read_opts o;
    lf_file *f = NULL;
    lf_curve *c = NULL;
    lf_error e;
    size_t i, j, n;
    int bad = 0;

    lf_read_opts_default(&o);
    o.format = format;
    o.spring_constant = 0.05;
    o.sensitivity = 5e-8;
    if (lf_file_open_memory(buf, len, "fuzz.bin", &o, &f, NULL, &e) != LF_OK)
        return e.msg[0] == '\0';
    n = lf_file_count(f);
    bad = n == 0 || strcmp(lf_file_format(f), format) != 0;
    for (i = 0; i < n && i < 8 && !bad; i++) {
        lf_curve_info info;
        if (lf_file_info(f, i, &info, &e) != LF_OK) {
            bad = e.msg[0] == '\0';
            continue;
        }
        if (lf_file_curve(f, i, &c, NULL, &e) != LF_OK) {
            bad = e.msg[0] == '\0';
            continue;
        }
        bad = c->n == 0 || c->index != (long) i;
        for (j = 0; !bad && j < c->n; j++)
            bad = !(c->depth[j] - c->depth[j] == 0) || !(c->force[j] - c->force[j] == 0)
                || c->segment[j] > LF_SEG_HOLD;
        lf_curve_free(c);
        c = NULL;
    }
    lf_file_close(f);
    if (!bad && lf_curve_parse(buf, len, 0, "fuzz.bin", &o, &c, NULL, &e) != LF_OK)
        bad = e.msg[0] == '\0';
    lf_curve_free(c);
    return bad;
}

/* The plan reader on buf, whole and in pieces, curves resolved in dir. */
static inline int
fuzz_plan(const char *buf, size_t len, size_t chunk, const char *dir)
{
    lf_plan *a = NULL, *b = NULL;
    lf_error ea, eb;
    int sa, sb, bad = 0;
    size_t i;

    sa = lf_plan_parse(buf, len, 0, "fuzz.csv", dir, &a, NULL, &ea);
    sb = lf_plan_parse(buf, len, chunk, "fuzz.csv", dir, &b, NULL, &eb);
    if (sa != sb || (sa != LF_OK && !fuzz_same_error(&ea, &eb)))
        bad = 1;
    else if (sa == LF_OK) {
        bad = a->n == 0 || a->n != b->n;
        for (i = 0; !bad && i < a->n; i++) {
            /* an empty b is a row without a layer (a half-space fit); the
             * rest of its probe must be valid all the same */
            lf_probe p = a->rows[i].probe;
            if (p.b != p.b)
                p.b = 1e-6;
            bad = strcmp(a->rows[i].file, b->rows[i].file) != 0
                || lf_probe_check(&p, NULL) != LF_OK;
        }
    }
    lf_plan_free(a);
    lf_plan_free(b);
    return bad;
}

/* The design-plan reader on buf: an error always says what, and a plan
 * read has rows whose probes and settings are in their domain. */
static inline int
fuzz_design(const char *buf, size_t len)
{
    lf_design_plan *p = NULL;
    lf_error e;
    int st, bad = 0;
    size_t i;

    st = lf_design_plan_parse(buf, len, "fuzz.csv", &p, &e);
    if (st != LF_OK)
        bad = p != NULL || e.msg[0] == '\0' || e.status != st;
    else {
        bad = p == NULL || p->n == 0;
        for (i = 0; !bad && i < p->n; i++) {
            const lf_design_candidate *c = &p->rows[i];
            bad = lf_probe_check(&c->probe, NULL) != LF_OK
                || !(c->delta_max != c->delta_max || (c->delta_max > 0 && c->delta_max < 1e308))
                || !(c->noise_rel != c->noise_rel || c->noise_rel >= 0)
                || !(c->noise_abs != c->noise_abs || c->noise_abs >= 0)
                || memchr(c->name, '\0', sizeof c->name) == NULL;
        }
    }
    lf_design_plan_free(p);
    return bad;
}

#endif
