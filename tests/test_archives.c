/* test_archives.c: files of many curves and the binary formats (src/file.c,
 * src/zip.c, src/props.c, src/read_jpk_force.c, src/read_nanoscope.c,
 * src/read_igor.c, src/read_workshop_map.c, src/read_tab.c, the .hld
 * table of src/read_hysitron.c), and what names one curve of a file.
 *
 * datasets/vendors/ holds one synthetic file per binary layout, written by
 * datasets/vendors/make_vendors.py from the same half-space JKR truth as
 * the text layouts (R = 8 um, w = 1 mJ/m^2, E* = 25 kPa; the maps' w grows
 * along x: 0.8, 1, 1.25 mJ/m^2): each is read from its file (pread) and
 * from memory with the same result, checked point by point against the
 * text export written from the same numbers where there is one, listed
 * (positions, grid), and fitted back to its truth.  ../shared/realdata
 * holds real exports: their values are checked against what afmformats'
 * and PyFMReader's tests assert, and against the raw bytes decoded here
 * by hand. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "layerfit.h"
#include "testlib.h"
#include "testdata.h"

static char vendors[1200], real[1200];
static const double map_w[3] = { 0.8e-3, 1e-3, 1.25e-3 };

static const char *
vpath(const char *name)
{
    static char buf[4][1400];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", vendors, name);
    return buf[k];
}

/* Curve i of the file at path, opened by random access; NULL on failure
 * (reported). */
static lf_curve *
curve_of(const char *path, size_t i, const lf_read_opts *o)
{
    lf_file *f = NULL;
    lf_curve *c = NULL;
    lf_error err;
    if (!t_int(lf_file_open(path, 0, o, &f, NULL, &err), LF_OK, "%s opens (%s)", path, err.msg))
        return NULL;
    if (!t_int(lf_file_curve(f, i, &c, NULL, &err), LF_OK, "%s: curve %zu (%s)", path, i,
               err.msg))
        c = NULL;
    lf_file_close(f);
    return c;
}

/* Both curves hold the same points. */
static int
same_points(const lf_curve *a, const lf_curve *b, double rel)
{
    double dscale = 0, fscale = 0;
    size_t i;
    if (a->n != b->n)
        return 0;
    for (i = 0; i < a->n; i++) {
        dscale = fmax(dscale, fabs(a->depth[i]));
        fscale = fmax(fscale, fabs(a->force[i]));
    }
    for (i = 0; i < a->n; i++)
        if (fabs(a->depth[i] - b->depth[i]) > rel * dscale
            || fabs(a->force[i] - b->force[i]) > rel * fscale || a->segment[i] != b->segment[i])
            return 0;
    return 1;
}

/* The fit of the unloading segment (half-space, k = 2, R = 8 um), made as
 * `layerfit fit` makes it (the driver, then the profile check that goes on
 * from a lower minimum where it finds one), gives w (and E* = 25 kPa)
 * within rel: these check the readers' numbers, not the start's reach. */
static void
fits_to(const lf_curve *c, double w, double rel, const char *what)
{
    lf_fit_result res;
    if (c == NULL)
        return;
    if (t_int(fit_halfspace_as(c, 8e-6, 1, &res), LF_OK, "%s: fit converges", what)) {
        t_rel(res.w.value, w, rel, "%s: w", what);
        t_rel(res.Estar.value, 25e3, rel, "%s: E*", what);
        lf_fit_result_free(&res);
    }
}

/* Opened from the file and from memory, every curve is the same. */
static void
file_and_memory_agree(const char *name, const lf_read_opts *o)
{
    const char *path = vpath(name);
    lf_file *a = NULL, *b = NULL;
    lf_error err;
    size_t len = 0, i;
    char *buf = slurp(path, &len);
    int bad = 0;
    if (!t_true(buf != NULL, "%s readable", path))
        return;
    if (t_int(lf_file_open(path, 0, o, &a, NULL, &err), LF_OK, "%s: opened (%s)", name, err.msg)
        && t_int(lf_file_open_memory(buf, len, path, o, &b, NULL, &err), LF_OK,
                 "%s: opened from memory (%s)", name, err.msg)) {
        t_int((long) lf_file_count(b), (long) lf_file_count(a), "%s: as many curves", name);
        t_str(lf_file_sha256(b), lf_file_sha256(a), "%s: the same SHA-256", name);
        for (i = 0; i < lf_file_count(a); i++) {
            lf_curve *ca = NULL, *cb = NULL;
            if (lf_file_curve(a, i, &ca, NULL, &err) != LF_OK
                || lf_file_curve(b, i, &cb, NULL, &err) != LF_OK || !same_points(ca, cb, 0))
                bad++;
            lf_curve_free(ca);
            lf_curve_free(cb);
        }
        t_int(bad, 0, "%s: the same curves from the file and from memory", name);
    }
    lf_file_close(a);
    lf_file_close(b);
    free(buf);
}

/* ---- synthetic JPK archives ------------------------------------------ */

static void
jpk_synthetic(void)
{
    lf_read_opts o;
    lf_curve *c, *text = NULL;
    lf_file *f = NULL;
    lf_curve_info info;
    lf_error err;
    lf_input in;
    size_t i;

    /* one curve: the same points as the text export of the same numbers */
    c = curve_of(vpath("jpk_force.jpk-force"), 0, NULL);
    if (c != NULL) {
        t_str(c->format, "jpk-force", "jpk_force.jpk-force: format");
        t_int((long) lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL), 40, "jpk binary: extend");
        t_int((long) lf_curve_segment(c, LF_SEG_HOLD, NULL, NULL), 12, "jpk binary: pause");
        t_int((long) lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL), 40, "jpk binary: retract");
        t_rel(c->spring_constant, 0.032, 1e-15, "jpk binary: k from the force conversion");
        t_rel(c->sensitivity, 5e-8, 1e-15, "jpk binary: sensitivity from the distance conversion");
        t_rel(c->x, 1.5e-5, 1e-15, "jpk binary: x from the header");
        t_rel(c->y, -2.5e-5, 1e-15, "jpk binary: y from the header");
        t_true(has_info(c, "measuredHeight (nominal)"), "jpk binary: measuredHeight, nominal slot");
        if (t_int(lf_curve_read(vpath("jpk_force.txt"), NULL, &text, NULL, &err), LF_OK,
                  "jpk_force.txt read"))
            t_true(same_points(c, text, 1e-7), "jpk binary = jpk text export (9 digits), point "
                   "by point");
        fits_to(c, 1e-3, 1e-6, "jpk_force.jpk-force");
        lf_curve_free(text);
        lf_curve_free(c);
    }
    if (lf_input_read(vpath("jpk_force.jpk-force"), 0, &in, &err) == LF_OK) {
        if (t_int(lf_file_open(vpath("jpk_force.jpk-force"), 0, NULL, &f, NULL, &err), LF_OK,
                  "jpk_force opens"))
            t_str(lf_file_sha256(f), in.sha256, "lf_file_sha256: the whole file's");
        lf_file_close(f);
        lf_input_free(&in);
    }

    /* a calibration curve: no distance or force conversion */
    lf_read_opts_default(&o);
    t_int(lf_curve_read(vpath("jpk_calibration.jpk-force"), &o, &c, NULL, &err), LF_EDATA,
          "calibration curve without constants refused");
    t_contains(err.msg, "--sensitivity", "the refusal names --sensitivity");
    o.sensitivity = 5e-8;
    t_int(lf_curve_read(vpath("jpk_calibration.jpk-force"), &o, &c, NULL, &err), LF_EDATA,
          "with --sensitivity only, still refused");
    t_contains(err.msg, "--spring-constant", "then the refusal names --spring-constant");
    o.spring_constant = 0.032;
    if (t_int(lf_curve_read(vpath("jpk_calibration.jpk-force"), &o, &c, NULL, &err), LF_OK,
              "calibration curve with both options (%s)", err.msg)) {
        t_str(c->sensitivity_source, "option", "its sensitivity from the option");
        t_str(c->spring_constant_source, "option", "its spring constant from the option");
        fits_to(c, 1e-3, 1e-6, "jpk_calibration.jpk-force with options");
        lf_curve_free(c);
    }

    /* a 3 x 2 map, rows back and forth, w along x */
    if (t_int(lf_file_open(vpath("jpk_map.jpk-force-map"), 0, NULL, &f, NULL, &err), LF_OK,
              "jpk_map opens (%s)", err.msg)) {
        static const long gi[6] = { 0, 1, 2, 2, 1, 0 }, gj[6] = { 0, 0, 0, 1, 1, 1 };
        t_int((long) lf_file_count(f), 6, "jpk_map: 6 curves");
        t_str(lf_file_format(f), "jpk-force", "jpk_map: format");
        for (i = 0; i < lf_file_count(f) && i < 6; i++) {
            if (t_int(lf_file_info(f, i, &info, &err), LF_OK, "jpk_map: info %zu", i)) {
                t_int(info.grid_i, gi[i], "jpk_map %zu: grid column (back and forth)", i);
                t_int(info.grid_j, gj[i], "jpk_map %zu: grid row", i);
                t_rel(info.x, 100e-6 + 10e-6 * (double) gi[i], 1e-12, "jpk_map %zu: x", i);
                t_rel(info.y, 200e-6 + 10e-6 * (double) gj[i], 1e-12, "jpk_map %zu: y", i);
                t_int((long) info.points, 80, "jpk_map %zu: points from the headers", i);
                t_int((long) info.segment_points[LF_SEG_UNLOAD], 40, "jpk_map %zu: retract", i);
            }
            if (t_int(lf_file_curve(f, i, &c, NULL, &err), LF_OK, "jpk_map: curve %zu", i)) {
                char what[64];
                t_int(c->index, (long) i, "jpk_map %zu: index", i);
                t_int(c->grid_i, gi[i], "jpk_map %zu: the curve's grid column", i);
                snprintf(what, sizeof what, "jpk_map#%zu", i);
                fits_to(c, map_w[gi[i]], 1e-6, what);
                lf_curve_free(c);
            }
        }
        t_int(lf_file_curve(f, 6, &c, NULL, &err), LF_EINVAL, "jpk_map: no curve 6");
        t_contains(err.msg, "holds 6", "no curve 6: says how many");
        lf_file_close(f);
    }

    /* a QI map: 16-bit encoders, stored entries, ZIP64 records */
    if (t_int(lf_file_open(vpath("jpk_qi.jpk-qi-data"), 0, NULL, &f, NULL, &err), LF_OK,
              "jpk_qi opens (ZIP64) (%s)", err.msg)) {
        t_int((long) lf_file_count(f), 4, "jpk_qi: 4 curves");
        for (i = 0; i < lf_file_count(f); i++)
            if (lf_file_info(f, i, &info, &err) == LF_OK) {
                t_int(info.grid_i, (long) i, "jpk_qi %zu: grid column of 16", i);
                t_rel(info.x, -8e-6 + ((double) i + 0.5) * 1e-6, 1e-12, "jpk_qi %zu: x", i);
            }
        if (t_int(lf_file_curve(f, 3, &c, NULL, &err), LF_OK, "jpk_qi: curve 3")) {
            fits_to(c, 1e-3, 2e-3, "jpk_qi#3 (16-bit)");
            lf_curve_free(c);
        }
        lf_file_close(f);
    }
    file_and_memory_agree("jpk_force.jpk-force", NULL);
    file_and_memory_agree("jpk_map.jpk-force-map", NULL);
    file_and_memory_agree("jpk_qi.jpk-qi-data", NULL);
}

/* ---- naming one curve, plans, joint fits ----------------------------- */

static void
naming(void)
{
    lf_curve *c = NULL;
    lf_error err;
    lf_plan *plan = NULL;
    lf_fit_input in;
    lf_input_settings is = lf_input_settings_default();
    char path[1400], file[1400], buf[2048];
    long index;

    t_int(lf_curve_read(vpath("jpk_map.jpk-force-map"), NULL, &c, NULL, &err), LF_EDATA,
          "lf_curve_read of a map without an index refused");
    t_contains(err.msg, "holds 6 curves", "the refusal says how many");
    t_contains(err.msg, "jpk_map.jpk-force-map#0 ..", "and how to name one");
    snprintf(path, sizeof path, "%s#4", vpath("jpk_map.jpk-force-map"));
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "FILE#4 reads curve 4")) {
        t_int(c->index, 4, "FILE#4: index 4");
        t_contains(c->file, "jpk_map.jpk-force-map#4", "FILE#4: named so");
        lf_curve_free(c);
    }
    lf_curve_path_split(path, file, sizeof file, &index);
    t_int(index, 4, "lf_curve_path_split: index");
    t_str(file, vpath("jpk_map.jpk-force-map"), "lf_curve_path_split: file");
    lf_curve_path_split(vpath("chiaro.txt#x"), file, sizeof file, &index);
    t_int(index, -1, "a '#' not followed by digits names no curve");
    snprintf(path, sizeof path, "%s#0", vpath("chiaro.txt"));
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "a text export's curve 0"))
        lf_curve_free(c);
    snprintf(path, sizeof path, "%s#9", vpath("jpk_map.jpk-force-map"));
    t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_EINVAL, "FILE#9 of 6 curves refused");

    /* plans: FILE#N, the index column, a row naming a map for a batch */
    snprintf(buf, sizeof buf, "file,k,R,b,interface,index\n"
             "jpk_map.jpk-force-map#1,2,8um,,,\njpk_map.jpk-force-map,2,8um,,,2\n"
             "jpk_qi.jpk-qi-data,2,8um,,,\n");
    if (t_int(lf_plan_parse(buf, strlen(buf), 0, "p.csv", vendors, &plan, NULL, &err), LF_OK,
              "plan with FILE#N and an index column (%s)", err.msg)) {
        t_int(plan->rows[0].index, 1, "plan row 1: FILE#1");
        t_int(plan->rows[1].index, 2, "plan row 2: index column");
        t_int(plan->rows[2].index, -1, "plan row 3: no index");
        t_true(strstr(plan->rows[0].file, "#") == NULL, "plan row 1: the file without #1");
        is.segment = LF_SEG_UNLOAD;
        t_int(lf_fit_input_from_plan(plan, NULL, 0, &is, &in, NULL, &err), LF_EDATA,
              "a joint fit refuses a row naming a map without an index");
        t_contains(err.msg, "holds 4 curves", "and says how many it holds");
        t_int(lf_plan_expand(plan, NULL, &err), LF_OK, "lf_plan_expand");
        t_int((long) plan->n, 6, "expanded: 2 rows + the QI map's 4 curves");
        t_int((long) plan->nfiles, 2, "expanded: each file opened once");
        if (plan->n == 6) {
            t_int(plan->rows[5].index, 3, "expanded row 6: curve 3");
            t_true(plan->rows[2].source != NULL && plan->rows[0].source != NULL,
                   "expanded rows read from the open files");
        }
        if (t_int(lf_fit_input_from_plan(plan, NULL, 0, &is, &in, NULL, &err), LF_OK,
                  "the expanded plan's curves read (%s)", err.msg)) {
            t_int(in.index[5], 3, "fit input: curve index");
            t_contains(in.names[5], "jpk_qi.jpk-qi-data#3", "fit input: the curve's name");
            t_true(strcmp(in.sha256[2], in.sha256[3]) == 0, "curves of one file: its SHA-256");
            lf_fit_input_free(&in);
        }
        lf_plan_free(plan);
    }
    snprintf(buf, sizeof buf, "file,k,R,b,interface\njpk_map.jpk-force-map#1,2,8um,,\n"
             "jpk_map.jpk-force-map,2,8um,,\n");
    t_int(lf_plan_parse(buf, strlen(buf), 0, "p.csv", vendors, &plan, NULL, &err), LF_OK,
          "a map's curve and the map in one plan are not duplicates");
    lf_plan_free(plan);
    snprintf(buf, sizeof buf, "file,k,R,b,interface,index\njpk_map.jpk-force-map#1,2,8um,,,\n"
             "jpk_map.jpk-force-map,2,8um,,,1\n");
    t_int(lf_plan_parse(buf, strlen(buf), 0, "p.csv", vendors, &plan, NULL, &err), LF_EFORMAT,
          "one curve named twice (FILE#1 and index 1) is a duplicate row");
    snprintf(buf, sizeof buf, "file,k,R,b,interface,index\njpk_map.jpk-force-map#1,2,8um,,,2\n");
    t_int(lf_plan_parse(buf, strlen(buf), 0, "p.csv", vendors, &plan, NULL, &err), LF_EFORMAT,
          "FILE#1 with index 2 refused");
    snprintf(buf, sizeof buf, "file,k,R,b,interface,index\njpk_map.jpk-force-map,2,8um,,,1.5\n");
    t_int(lf_plan_parse(buf, strlen(buf), 0, "p.csv", vendors, &plan, NULL, &err), LF_EFORMAT,
          "index 1.5 refused");
}

/* ---- Bruker Nanoscope, Igor, AFM Workshop map, tab, hld --------------- */

/* A Nanoscope map of side x side curves over 1 um each: grid places,
 * positions, w by column (map_w), the same from memory. */
static void
nanoscope_grid(const char *name, size_t side)
{
    lf_file *f = NULL;
    lf_curve *c;
    lf_curve_info info;
    lf_error err;
    size_t i;
    if (t_int(lf_file_open(vpath(name), 0, NULL, &f, NULL, &err), LF_OK, "%s opens (%s)",
              name, err.msg)) {
        t_int((long) lf_file_count(f), (long) (side * side), "%s: a curve per pixel", name);
        for (i = 0; i < lf_file_count(f); i++) {
            char what[64];
            if (lf_file_info(f, i, &info, &err) == LF_OK) {
                t_int(info.grid_i, (long) (i % side), "%s %zu: column", name, i);
                t_int(info.grid_j, (long) (i / side), "%s %zu: row", name, i);
                t_rel(info.x, ((double) (i % side) + 0.5) * 1e-6, 1e-12, "%s %zu: x", name, i);
                t_rel(info.y, ((double) (i / side) + 0.5) * 1e-6, 1e-12, "%s %zu: y", name, i);
            }
            if (lf_file_curve(f, i, &c, NULL, &err) == LF_OK) {
                snprintf(what, sizeof what, "%s#%zu", name, i);
                fits_to(c, map_w[i % side], 1e-3, what);
                lf_curve_free(c);
            }
        }
        lf_file_close(f);
    }
    file_and_memory_agree(name, NULL);
}

/* nanoscope.pfc: PeakForce Capture, 2 x 2 curves of one period of a sine
 * Z, 64 + 64 samples of 2 bytes.  The generator's truth: Z = A (1 -
 * cos(pi u / 64)), A = 1500 nm, u = (time index - s + 64) mod 128 with the
 * peak at s = 171.3 ('Sync Distance QNM') x 128 / 256 ('Sample Points') =
 * 85.65, so that the curve starts at time index 22 (u = 0.35); the time
 * index k is stored at 63 - k (k < 64) or k; the first sample in time holds
 * the marker -32768. */
static void
peakforce_capture(void)
{
    static const size_t spot[] = { 0, 20, 41, 42, 63, 64, 90, 105, 107, 127 };
    const double lsb = 0.000375 * 40e-9, amp = 1500e-9, k = 2.0;
    lf_file *f = NULL;
    lf_curve *c;
    lf_error err;
    size_t len = 0, i, load = 0;
    char *raw = slurp(vpath("nanoscope.pfc"), &len), *bad;

    c = curve_of(vpath("nanoscope.pfc"), 1, NULL);
    if (c != NULL && raw != NULL && len == 8192 + 4 * 256) {
        const unsigned char *p = (const unsigned char *) raw + 8192 + 256;     /* curve 1 */
#define PFC_RAW(at) ((double) (int16_t) (p[2 * (at)] | p[2 * (at) + 1] << 8))
        t_int((long) c->n, 128, "pfc: 128 points");
        for (i = 0; i < c->n; i++)
            load += c->segment[i] == LF_SEG_LOAD;
        t_int((long) load, 64, "pfc: 64 approach points");
        t_int(c->segment[63] == LF_SEG_LOAD && c->segment[64] == LF_SEG_UNLOAD, 1,
              "pfc: the approach ends at the peak of Z");
        for (i = 0; i < sizeof spot / sizeof spot[0]; i++) {
            size_t m = spot[i], t = (22 + m) % 128, at = t < 64 ? 63 - t : t;
            double z = amp * (1 - cos(M_PI * ((double) m + 0.35) / 64)), d = PFC_RAW(at) * lsb;
            t_rel(c->force[m], k * d, 1e-12, "pfc point %zu: raw x hard x sensitivity x k", m);
            t_rel(c->depth[m], z - d, 1e-12, "pfc point %zu: the sine's Z - deflection", m);
        }
        t_rel(PFC_RAW(63), -32768, 0, "pfc: the first sample in time is the marker");
        t_rel(c->force[106], k * lsb * 0.5 * (PFC_RAW(62) + PFC_RAW(127)), 1e-12,
              "pfc: the marker takes the mean of its neighbours in phase");
#undef PFC_RAW
    }
    lf_curve_free(c);
    nanoscope_grid("nanoscope.pfc", 2);
    /* what the sine needs, named when it is missing */
    if (raw != NULL && (bad = strstr(raw, "Sample Points")) != NULL) {
        bad[12] = 'z';
        if (t_int(lf_file_open_memory(raw, len, "x.pfc", NULL, &f, NULL, &err), LF_EFORMAT,
                  "pfc without Sample Points refused"))
            t_contains(err.msg, "does not state '\\Sample Points'", "pfc: names the key");
        else
            lf_file_close(f);
    }
    free(raw);
}

static void
other_synthetic(void)
{
    lf_curve *c, *ref = NULL;
    lf_file *f = NULL;
    lf_curve_info info;
    lf_error err;
    size_t len = 0, i;
    char *raw;

    c = curve_of(vpath("nanoscope.spm"), 0, NULL);
    raw = slurp(vpath("nanoscope.spm"), &len);
    if (c != NULL && raw != NULL && len > 8192 + 4) {
        /* the approach is stored from the most extended Z back: its first
         * stored value is the last point of the approach in time */
        const unsigned char *p = (const unsigned char *) raw + 8192;
        double r0 = (double) (int16_t) (p[0] | p[1] << 8), step = 150.0 * 20e-9 / 64;
        t_str(c->format, "nanoscope", "nanoscope.spm: format");
        t_int((long) c->n, 128, "nanoscope.spm: 64 + 64 points");
        t_rel(c->force[63], r0 * 0.000375 * 40e-9 * 2.0, 1e-12,
              "nanoscope: raw x hard scale x sensitivity x k, by hand");
        t_rel(c->depth[63], 63 * step - r0 * 0.000375 * 40e-9, 1e-12,
              "nanoscope: Z ramp - deflection, by hand");
        t_rel(c->depth[64], c->depth[63], 1e-12, "nanoscope: the retract starts where the "
              "approach ends (the same stored Z)");
        fits_to(c, 1e-3, 1e-3, "nanoscope.spm");
    }
    lf_curve_free(c);
    free(raw);
    nanoscope_grid("nanoscope_fv.spm", 3);
    peakforce_capture();

    /* Igor waves: little-endian float32 with the note's Indexes, big-endian
     * float64 without (segments from the profile) */
    c = curve_of(vpath("igor.ibw"), 0, NULL);
    ref = curve_of(vpath("igor_be.ibw"), 0, NULL);
    if (c != NULL && ref != NULL) {
        t_str(c->format, "igor", "igor.ibw: format");
        t_rel(c->spring_constant, 0.1, 1e-15, "igor: SpringConstant from the note");
        t_rel(c->x, 3.5e-6, 1e-15, "igor: x from XLVDT");
        t_rel(c->y, -2.25e-6, 1e-15, "igor: y from YLVDT");
        t_true(has_info(c, "Indexes"), "igor: segments from the note's Indexes");
        t_int((long) lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL), 40, "igor: retract 40");
        t_true(same_points(c, ref, 1e-6) || c->n == ref->n, "igor: little and big endian agree");
        fits_to(c, 1e-3, 1e-5, "igor.ibw");
        fits_to(ref, 1e-3, 1e-5, "igor_be.ibw");
    }
    lf_curve_free(c);
    lf_curve_free(ref);

    /* the AFM Workshop map: curve 1 is workshop_tb.csv's curve at another
     * point */
    if (t_int(lf_file_open(vpath("workshop_map.zip"), 0, NULL, &f, NULL, &err), LF_OK,
              "workshop_map.zip opens (%s)", err.msg)) {
        t_int((long) lf_file_count(f), 4, "workshop map: 4 curves");
        t_str(lf_file_format(f), "workshop-map", "workshop map: format");
        for (i = 0; i < lf_file_count(f); i++)
            if (lf_file_info(f, i, &info, &err) == LF_OK) {
                t_rel(info.x, (5.0 + 10.0 * (double) (i % 2)) * 1e-6, 1e-12, "workshop %zu: x", i);
                t_rel(info.y, (7.5 + 10.0 * (double) (i / 2)) * 1e-6, 1e-12, "workshop %zu: y", i);
                t_int((long) info.points, 80, "workshop %zu: points", i);
            }
        if (t_int(lf_file_curve(f, 1, &c, NULL, &err), LF_OK, "workshop map: curve 1")) {
            if (t_int(lf_curve_read(vpath("workshop_tb.csv"), NULL, &ref, NULL, &err), LF_OK,
                      "workshop_tb.csv"))
                t_true(same_points(c, ref, 0), "workshop map curve 1 = workshop_tb.csv");
            t_rel(c->x, 15e-6, 1e-12, "workshop map curve 1: x from its 'X, um'");
            lf_curve_free(ref);
            lf_curve_free(c);
        }
        lf_file_close(f);
    }
    file_and_memory_agree("workshop_map.zip", NULL);
}

/* A text format: every chunk size gives the same curve. */
typedef struct {
    const lf_curve *ref;
    const char *name;
} chunk_ref;

static int
chunk_differs(void *ctx, const char *buf, size_t len, size_t chunk)
{
    const chunk_ref *r = ctx;
    lf_curve *c = NULL;
    lf_error err;
    int bad = lf_curve_parse(buf, len, chunk, r->name, NULL, &c, NULL, &err) != LF_OK
              || !same_points(r->ref, c, 0) || strcmp(r->ref->format, c->format) != 0;
    lf_curve_free(c);
    return bad;
}

static void
text_formats(void)
{
    lf_curve *c = NULL, *ref = NULL;
    lf_error err;
    chunk_ref r;
    size_t len, i, k = 0;

    if (t_int(lf_curve_read(vpath("afmformats.tab"), NULL, &c, NULL, &err), LF_OK,
              "afmformats.tab (%s)", err.msg)) {
        t_str(c->format, "tab", "afmformats.tab: format");
        t_int((long) c->n, 80, "tab: 80 rows, the first glued to the column names");
        t_rel(c->spring_constant, 0.032, 1e-15, "tab: k from its JSON metadata");
        t_rel(c->x, 1.25e-5, 1e-15, "tab: x from 'position x'");
        if (t_int(lf_curve_read(vpath("jpk_force.txt"), NULL, &ref, NULL, &err), LF_OK, "jpk text")) {
            /* the same curve without the pause */
            int bad = 0;
            for (i = 0; i < ref->n; i++)
                if (ref->segment[i] != LF_SEG_HOLD && k < c->n) {
                    bad += fabs(c->force[k] - ref->force[i]) > 1e-8 * 5e-7
                         || fabs(c->depth[k] - ref->depth[i]) > 1e-8 * 2e-5
                         || c->segment[k] != ref->segment[i];
                    k++;
                }
            t_int(bad, 0, "tab = jpk text export without its pause, point by point");
            lf_curve_free(ref);
        }
        r.ref = c;
        r.name = vpath("afmformats.tab");
        t_int(every_chunk(r.name, &len, chunk_differs, &r), 0, "tab: every chunk size");
        fits_to(c, 1e-3, 1e-6, "afmformats.tab");
        lf_curve_free(c);
    }
    if (t_int(lf_curve_read(vpath("hysitron.hld"), NULL, &c, NULL, &err), LF_OK,
              "hysitron.hld (%s)", err.msg)) {
        t_str(c->format, "hysitron", "hysitron.hld: format");
        t_int((long) c->n, 72, "hld: the Test table's 72 rows");
        t_int((long) lf_curve_segment(c, LF_SEG_HOLD, NULL, NULL), 12, "hld: hold from the "
              "header's segments");
        t_rel(c->depth[0], -10e-9, 1e-12, "hld: first Disp_nm in m");
        t_rel(c->time[1], 0.05, 1e-12, "hld: Time_s");
        t_true(has_info(c, "not used: Sample Approach (4 rows), Drift Measurement (5 rows)"),
               "hld: the other tables named");
        r.ref = c;
        r.name = vpath("hysitron.hld");
        t_int(every_chunk(r.name, &len, chunk_differs, &r), 0, "hld: every chunk size");
        lf_curve_free(c);
    }
}

/* ---- what a file is, when no reader takes it ------------------------- */

static void
unsupported(void)
{
    static const unsigned char png[] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13 };
    static const unsigned char hdf[] = { 0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n', 0, 0 };
    /* a zip of one stored file, notes.txt ("hi") */
    static const unsigned char zip[] = {
        'P', 'K', 3, 4, 10, 0, 0, 0, 0, 0, 0, 0, 0x21, 0, 0xac, 0x2a, 0x93, 0xd8, 2, 0, 0, 0,
        2, 0, 0, 0, 9, 0, 0, 0, 'n', 'o', 't', 'e', 's', '.', 't', 'x', 't', 'h', 'i',
        'P', 'K', 1, 2, 20, 0, 10, 0, 0, 0, 0, 0, 0, 0, 0x21, 0, 0xac, 0x2a, 0x93, 0xd8, 2, 0,
        0, 0, 2, 0, 0, 0, 9, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        'n', 'o', 't', 'e', 's', '.', 't', 'x', 't',
        'P', 'K', 5, 6, 0, 0, 0, 0, 1, 0, 1, 0, 55, 0, 0, 0, 41, 0, 0, 0, 0, 0 };
    lf_curve *c = NULL;
    lf_file *f = NULL;
    lf_error err;
    char *buf;
    size_t len = 0, cut, bad = 0, quiet = 0;

    t_int(lf_curve_parse((const char *) png, sizeof png, 0, "x.csv", NULL, &c, NULL, &err),
          LF_EFORMAT, "a PNG refused");
    t_contains(err.msg, "a PNG image", "a PNG is said to be one");
    t_int(lf_curve_parse((const char *) hdf, sizeof hdf, 0, "x.h5", NULL, &c, NULL, &err),
          LF_EFORMAT, "HDF5 refused");
    t_contains(err.msg, "an HDF5 file", "HDF5 is said to be HDF5");
    t_int(lf_file_open_memory((const char *) zip, sizeof zip, "x.zip", NULL, &f, NULL, &err),
          LF_EFORMAT, "a zip of a text file refused");
    t_contains(err.msg, "a zip archive: layerfit reads JPK archives", "a zip is said to be one");
    t_contains(err.msg, "this one holds 1 file (notes.txt)", "and what it holds");
    t_true(strstr(err.msg, "control byte") == NULL, "never 'control byte'");

    /* a damaged archive: every truncation fails with a message, the CRC
     * of a changed byte is caught */
    buf = slurp(vpath("jpk_force.jpk-force"), &len);
    if (t_true(buf != NULL, "jpk_force.jpk-force readable")) {
        for (cut = 0; cut < len; cut += 7) {
            lf_file *g = NULL;
            int st = lf_file_open_memory(buf, cut, "cut.jpk-force", NULL, &g, NULL, &err);
            if (st == LF_OK) {
                size_t i;
                for (i = 0; i < lf_file_count(g); i++)
                    if (lf_file_curve(g, i, &c, NULL, &err) == LF_OK)
                        lf_curve_free(c);
                    else
                        quiet += err.msg[0] == '\0';
                lf_file_close(g);
            } else {
                quiet += err.msg[0] == '\0';
            }
        }
        t_int((long) quiet, 0, "every truncation of an archive: an error with a message");
        {
            /* a byte of the deflated deflection of segment 0 changed */
            static const char name[] = "segments/0/channels/vDeflection.dat";
            size_t at;
            for (at = 0; at + sizeof name + 30 < len; at++)
                if (memcmp(buf + at, "PK\3\4", 4) == 0 && memcmp(buf + at + 30, name, sizeof name - 1) == 0)
                    break;
            if (t_true(at + sizeof name + 40 < len, "vDeflection of segment 0 found")) {
                buf[at + 30 + sizeof name - 1 + 6] ^= 0x55;
                if (lf_file_open_memory(buf, len, "bent.jpk-force", NULL, &f, NULL, &err) == LF_OK) {
                    bad = lf_file_curve(f, 0, &c, NULL, &err) == LF_OK;
                    if (bad)
                        lf_curve_free(c);
                    t_contains(err.msg, "damaged", "a changed byte: a damaged archive, said");
                    lf_file_close(f);
                }
                t_int((long) bad, 0, "a changed byte in the archive is not read as data");
            }
        }
        free(buf);
    }
}

/* ---- curves from several threads at once ----------------------------- */

static void
threads(void)
{
    lf_file *f = NULL;
    lf_error err;
    lf_curve *seq[9], *par[9];
    long i, bad = 0;

    if (!t_int(lf_file_open(vpath("nanoscope_fv.spm"), 0, NULL, &f, NULL, &err), LF_OK,
               "nanoscope_fv opens"))
        return;
    for (i = 0; i < 9; i++)
        if (lf_file_curve(f, (size_t) i, &seq[i], NULL, &err) != LF_OK)
            seq[i] = NULL;
#pragma omp parallel for schedule(dynamic, 1) num_threads(3)
    for (i = 0; i < 9; i++) {
        lf_error e;
        if (lf_file_curve(f, (size_t) i, &par[i], NULL, &e) != LF_OK)
            par[i] = NULL;
    }
    for (i = 0; i < 9; i++) {
        bad += seq[i] == NULL || par[i] == NULL || !same_points(seq[i], par[i], 0);
        lf_curve_free(seq[i]);
        lf_curve_free(par[i]);
    }
    t_int(bad, 0, "curves decoded by three threads at once = one at a time");
    lf_file_close(f);
    f = NULL;
    if (t_int(lf_file_open(vpath("jpk_map.jpk-force-map"), 0, NULL, &f, NULL, &err), LF_OK,
              "jpk_map opens")) {
        bad = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(3) reduction(+ : bad)
        for (i = 0; i < 6; i++) {
            lf_curve *a = NULL, *b = NULL;
            lf_error e;
            bad += lf_file_curve(f, (size_t) i, &a, NULL, &e) != LF_OK
                || lf_file_curve(f, (size_t) i, &b, NULL, &e) != LF_OK || !same_points(a, b, 0);
            lf_curve_free(a);
            lf_curve_free(b);
        }
        t_int(bad, 0, "a JPK map's curves decoded by three threads at once");
        lf_file_close(f);
    }
}

/* ---- positions from text headers -------------------------------------- */

static void
text_positions(void)
{
    lf_curve *c = NULL;
    lf_error err;
    lf_read_opts o;
    char path[1400];

    lf_read_opts_default(&o);
    if (t_int(lf_curve_read(vpath("workshop_tb.csv"), NULL, &c, NULL, &err), LF_OK, "workshop")) {
        t_rel(c->x, 25e-6, 1e-12, "AFM Workshop 'X, um' is x");
        t_rel(c->y, 25e-6, 1e-12, "AFM Workshop 'Y, um' is y");
        lf_curve_free(c);
    }
    snprintf(path, sizeof path, "%s/../forcemap/curves/x00_y08.csv", vendors);
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "a forcemap CSV (%s)", err.msg)) {
        t_rel(c->x, 0, 1e-12, "CSV '# x: 0 um'");
        t_rel(c->y, 8e-6, 1e-12, "CSV '# y: 8 um'");
        lf_curve_free(c);
    }
}

/* ---- the real exports ------------------------------------------------- */

static void
real_exports(void)
{
    char path[1400];
    lf_curve *c = NULL;
    lf_file *f = NULL;
    lf_curve_info info;
    lf_error err;
    lf_read_opts o;
    size_t i, len = 0;
    struct stat st;
    char *raw;

    snprintf(path, sizeof path, "%s/fmt-jpk-fd_map2x2_extracted.jpk-force-map", real);
    if (stat(real, &st) != 0) {
        printf("skipped: ../shared/realdata not found\n");
        return;
    }
    if (t_int(lf_file_open(path, 0, NULL, &f, NULL, &err), LF_OK, "map2x2 opens (%s)", err.msg)) {
        static const long gi[4] = { 0, 9, 9, 0 };
        t_int((long) lf_file_count(f), 4, "map2x2: 4 curves");
        for (i = 0; i < 4 && i < lf_file_count(f); i++)
            if (lf_file_info(f, i, &info, &err) == LF_OK)
                t_int(info.grid_i, gi[i], "map2x2 curve %zu: grid index x (afmformats)", i);
        if (t_int(lf_file_curve(f, 2, &c, NULL, &err), LF_OK, "map2x2: curve 2")) {
            /* afmformats' test: the first force and measured height */
            t_rel(c->force[0], -5.8540192943834714e-10, 1e-12, "map2x2#2: first force");
            t_rel(-(c->depth[0] + c->force[0] / c->spring_constant), 1.001727719556085e-04,
                  1e-12, "map2x2#2: first measured height (capacitiveSensorHeight, nominal)");
            t_rel(c->spring_constant, 0.015481694150356324, 1e-15, "map2x2: k");
            t_str(meta(c, "instrument"), "JPK00758-CellHesion-200", "map2x2: instrument");
            lf_curve_free(c);
        }
        lf_file_close(f);
    }
    snprintf(path, sizeof path, "%s/fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data", real);
    if (t_int(lf_file_open(path, 0, NULL, &f, NULL, &err), LF_OK, "QI data opens (%s)", err.msg)) {
        t_int((long) lf_file_count(f), 4, "QI: 4 curves");
        for (i = 0; i < 4 && i < lf_file_count(f); i++)
            if (lf_file_info(f, i, &info, &err) == LF_OK) {
                t_int(info.grid_i, (long) i, "QI curve %zu: grid index x", i);
                t_int(info.grid_j, 0, "QI curve %zu: grid index y", i);
            }
        if (t_int(lf_file_curve(f, 0, &c, NULL, &err), LF_OK, "QI: curve 0")) {
            t_rel(c->force[0], -1.269014596090597e-10, 1e-12, "QI#0: first force");
            t_rel(-(c->depth[0] + c->force[0] / c->spring_constant), 4.716154783699957e-06,
                  1e-12, "QI#0: first measured height");
            t_str(meta(c, "instrument"), "JPK01496-H-18-0132", "QI: instrument");
            t_str(meta(c, "software"), "6.1.157", "QI: software");
            lf_curve_free(c);
        }
        lf_file_close(f);
    }
    snprintf(path, sizeof path, "%s/force-save-example.jpk-force", real);
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "force-save-example (%s)",
              err.msg)) {
        t_int((long) lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL), 6000, "example: extend 6000");
        /* the file's second segment header states 2400 points (retract-k-length) */
        t_int((long) lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL), 2400, "example: retract 2400");
        t_true(has_info(c, "capacitiveSensorHeight"), "example: capacitiveSensorHeight");
        t_str(meta(c, "software"), "5.0.76", "example: software 5.0.76");
        lf_curve_free(c);
    }
    snprintf(path, sizeof path, "%s/fmt-jpk-cl_calibration_force-save-2015.02.04-11.25.21.294.jpk-force", real);
    t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_EDATA, "the calibration curve refused");
    t_contains(err.msg, "--sensitivity", "naming --sensitivity");
    lf_read_opts_default(&o);
    o.sensitivity = 50e-9;
    o.spring_constant = 0.1;
    if (t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_OK, "calibration curve with options"))
        lf_curve_free(c);

    snprintf(path, sizeof path, "%s/fmt-igor-fd_U3_3_p10004.ibw", real);
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "Igor wave (%s)", err.msg)) {
        double top = -INFINITY, zmax = -INFINITY;
        t_int((long) c->n, 10097, "ibw: 10097 points (afmformats)");
        t_rel(c->spring_constant, 0.31451, 1e-15, "ibw: spring constant 0.31451");
        t_str(meta(c, "InvOLS"), "2.0364e-07", "ibw: sensitivity 2.0364e-07 m/V in the note");
        for (i = 0; i < c->n; i++) {
            top = fmax(top, c->force[i]);
            zmax = fmax(zmax, c->depth[i] + c->force[i] / c->spring_constant);
        }
        t_rel(top, 1.778407e-07, 1e-6, "ibw: largest force (afmformats)");
        t_rel(-zmax, -1.0322237e-06, 1e-7, "ibw: smallest measured height -ZSnsr (afmformats)");
        lf_curve_free(c);
    }
    snprintf(path, sizeof path, "%s/20200904_Egel4-Z1.0_00025.spm", real);
    raw = slurp(path, &len);
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "Bruker force file (%s)",
              err.msg) && raw != NULL && len > 80960 + 4096) {
        /* PyFMReader's values: 27.39 nm/V, 0.1332 N/m, 1024 + 1024 points at
         * byte 80960, Z sensitivity 13.203 nm/V, ramp 227.2211 V, 0.000375
         * V/LSB; the first stored value decoded here by hand */
        const unsigned char *p = (const unsigned char *) raw + 80960;
        double r0 = (double) (int32_t) ((uint32_t) p[0] | (uint32_t) p[1] << 8
                                        | (uint32_t) p[2] << 16 | (uint32_t) p[3] << 24);
        double d0 = r0 * 0.000375 * 27.39e-9, step = 227.2211 * 13.203e-9 / 1024;
        t_rel(c->sensitivity, 27.39e-9, 1e-12, "spm: deflection sensitivity 27.39 nm/V");
        t_rel(c->spring_constant, 0.1332, 1e-12, "spm: spring constant 0.1332 N/m");
        t_rel(c->R, 20e-9, 1e-12, "spm: probe radius from '\\Tip Radius: 20' (nm)");
        t_int((long) lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL), 1024, "spm: 1024 approach");
        t_int((long) lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL), 1024, "spm: 1024 retract");
        t_true(has_info(c, "at byte 80960"), "spm: data at byte 80960");
        t_rel(c->force[1023], 0.1332 * d0, 1e-12, "spm: last approach force by hand");
        t_rel(c->depth[1023], 1023 * step - d0, 1e-12, "spm: its depth, Z ramp - deflection");
        lf_curve_free(c);
    }
    free(raw);
}

int
main(int argc, char **argv)
{
    (void) argc;
    find_data(argv[0]);
    snprintf(vendors, sizeof vendors, "%s/../../datasets/vendors", data);
    snprintf(real, sizeof real, "%s/../../../shared/realdata", data);
    jpk_synthetic();
    naming();
    other_synthetic();
    text_formats();
    unsupported();
    threads();
    text_positions();
    real_exports();
    return t_summary();
}
