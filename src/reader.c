/* reader.c: the table of instrument readers, choosing one (by name or by
 * sniffing the first bytes), and what all readers share: building a curve,
 * its metadata, the final checks and the constants of the AFM conversions
 * (force F = k d from a deflection d in m, or in V or A through a
 * sensitivity in m/V or m/A). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

/* Order breaks ties of the sniff scores: csv first keeps the CSV reader for
 * whatever no instrument claims. */
const lf_reader_type *const lf_reader_types[] = {
    &lf_reader_csv,
    &lf_reader_chiaro,
    &lf_reader_jpk,
    &lf_reader_workshop,
    &lf_reader_ntmdt,
    &lf_reader_hysitron,
    &lf_reader_text,
    &lf_reader_tab,
    &lf_reader_jpk_force,
    &lf_reader_workshop_map,
    &lf_reader_nanoscope,
    &lf_reader_igor,
    NULL
};

/* The binary formats of many curves per file, and their readers' entries. */
static const lf_multi_reader *const multi_readers[] = {
    &lf_multi_jpk_force,
    &lf_multi_workshop_map,
    &lf_multi_nanoscope,
    &lf_multi_igor,
    NULL
};

const lf_multi_reader *
lf_multi_of(const lf_reader_type *r)
{
    size_t i;
    for (i = 0; r != NULL && multi_readers[i] != NULL; i++)
        if (multi_readers[i]->reader == r)
            return multi_readers[i];
    return NULL;
}

const char *
lf_reader_names(char *buf, size_t n)
{
    size_t i, len = 0;
    if (n == 0)
        return buf;
    buf[0] = '\0';
    for (i = 0; lf_reader_types[i] != NULL; i++)
        len += (size_t) snprintf(buf + len, len < n ? n - len : 0, "%s%s", i ? ", " : "",
                                 lf_reader_types[i]->name);
    return buf;
}

const lf_reader_type *
lf_reader_find(const char *name)
{
    size_t i;
    for (i = 0; lf_reader_types[i] != NULL; i++)
        if (lf_csv_ieq(lf_reader_types[i]->name, name))
            return lf_reader_types[i];
    return NULL;
}

const lf_reader_type *
lf_reader_sniff(const char *head, size_t len)
{
    const lf_reader_type *best = &lf_reader_csv;
    int score = 0;
    size_t i;
    if (len > LF_SNIFF_BYTES)
        len = LF_SNIFF_BYTES;
    /* a UTF-8 byte order mark (an editor's, or Windows') says nothing of
     * the format: every reader skips it, and the sniffers look past it */
    if (len >= 3 && memcmp(head, "\xEF\xBB\xBF", 3) == 0) {
        head += 3;
        len -= 3;
    }
    for (i = 0; lf_reader_types[i] != NULL; i++) {
        int s = lf_reader_types[i]->sniff(head, len);
        if (s > score) {
            score = s;
            best = lf_reader_types[i];
        }
    }
    return best;
}

static int
unknown_format(const char *name, const char *format, lf_error *err)
{
    char list[256];
    return lf_fail_at(err, LF_EINVAL, name, 0, 0, "unknown format '%s' (one of: %s)",
                      format, lf_reader_names(list, sizeof list));
}

/* The reading options a file did not use, said: a constant the file states
 * itself (the options are for files that state none), one it needs none
 * of, units an instrument's export states itself. */
static void
options_set_aside(const lf_reader_type *r, const lf_curve *c, const lf_read_opts *o,
                  lf_warnings *warn)
{
    const double k = o->spring_constant, s = o->sensitivity;
    const int table = strcmp(r->name, "csv") == 0 || strcmp(r->name, "text") == 0;
    char what[64];

    snprintf(what, sizeof what, table ? "a table of depth and force" : "this %s export", r->name);
    if (isfinite(k) && k > 0 && c->spring_constant_source == NULL)
        lf_warn(warn, "%s: --spring-constant not used: %s needs none", c->file, what);
    else if (isfinite(k) && k > 0 && strcmp(c->spring_constant_source, "file header") == 0
             && fabs(k - c->spring_constant) > 1e-9 * c->spring_constant)
        lf_warn(warn, "%s: spring constant %.6g N/m from the file header; --spring-constant "
                "%.6g N/m applies only to files that state none", c->file, c->spring_constant, k);
    if (isfinite(s) && s > 0 && c->sensitivity_source == NULL)
        lf_warn(warn, "%s: --sensitivity not used: %s needs none", c->file, what);
    else if (isfinite(s) && s > 0 && strcmp(c->sensitivity_source, "file header") == 0
             && fabs(s - c->sensitivity) > 1e-9 * c->sensitivity) {
        double v;
        const char *u = lf_sensitivity_shown(c->sensitivity, c->sensitivity_unit, &v);
        lf_warn(warn, "%s: sensitivity %.6g %s from the file header; --sensitivity applies "
                "only to files that state none", c->file, v, u);
    }
    if (!table && (o->depth_unit != NULL || o->force_unit != NULL))
        lf_warn(warn, "%s: %s not used: a %s export states its own units", c->file,
                o->depth_unit != NULL && o->force_unit != NULL ? "--depth-unit and --force-unit"
                : o->depth_unit != NULL ? "--depth-unit" : "--force-unit", r->name);
}

/* Read with reader r into a new curve. */
static int
run_reader(const lf_reader_type *r, const lf_source *in, const lf_read_opts *o,
           lf_curve **out, lf_warnings *warn, lf_error *err)
{
    lf_warnings local = { 0, NULL };
    lf_read_opts def;
    lf_curve *c;
    int status;

    if (o == NULL) {
        lf_read_opts_default(&def);
        o = &def;
    }
    lf_error_clear(err);
    c = lf_curve_new(in->name, r->name);
    if (c == NULL)
        return lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
    status = r->read(in, o, c, &local, err);
    if (status != LF_OK) {
        lf_curve_free(c);
        lf_warnings_free(&local);
        return status;
    }
    lf_curve_done(r, c, o, &local, warn);
    *out = c;
    return LF_OK;
}

/* A length stated by metadata key: "x: 12 um" (number and unit), or a key
 * with its unit ("X-position (um)", "X, um"), or in m (unit "m"). */
static double
meta_position(const lf_curve *c, const char *key, const char *unit)
{
    const char *v = lf_curve_meta(c, key);
    double x;
    if (v == NULL)
        return NAN;
    if (unit != NULL) {
        x = lf_number_or_nan(v);
        return x * (strcmp(unit, "m") == 0 ? 1.0 : 1e-6);
    }
    if (lf_units_parse(v, LF_Q_LENGTH, &x, NULL) == LF_OK)
        return x;
    if (lf_meta_number(c, key, LF_Q_LENGTH, &x) == 0)
        return x;
    return NAN;
}

/* The position a text export states in its header: "# x:" / "# y:" lines
 * (layerfit's CSV), Chiaro / Piuma "X-position (um)", AFM Workshop
 * "X, um", JPK text exports "xPosition" (m). */
static void
position_from_meta(lf_curve *c)
{
    static const char *const keys[][3] = {
        { "x", "y", NULL }, { "X-position (um)", "Y-position (um)", "um" },
        { "X, um", "Y, um", "um" }, { "xPosition", "yPosition", "m" },
    };
    size_t k;
    for (k = 0; k < sizeof keys / sizeof keys[0] && isnan(c->x); k++) {
        double x = meta_position(c, keys[k][0], keys[k][2]);
        double y = meta_position(c, keys[k][1], keys[k][2]);
        if (isfinite(x) && isfinite(y)) {
            c->x = x;
            c->y = y;
            lf_warn(&c->info, "position: x %.6g m, y %.6g m (file header '%s', '%s')", x, y,
                    keys[k][0], keys[k][1]);
        }
    }
}

void
lf_curve_done(const lf_reader_type *r, lf_curve *c, const lf_read_opts *o,
              lf_warnings *local, lf_warnings *warn)
{
    lf_read_opts def;
    size_t i;
    if (o == NULL) {
        lf_read_opts_default(&def);
        o = &def;
    }
    for (i = 0; i < local->n; i++)   /* warnings reach the caller only with a curve */
        lf_warn(warn, "%s", local->msg[i]);
    lf_warnings_free(local);
    if (isnan(c->x))
        position_from_meta(c);
    options_set_aside(r, c, o, warn);
}

double
lf_number_or_nan(const char *text)
{
    double v;
    char buf[64];
    size_t n;
    if (text == NULL)
        return NAN;
    text += strspn(text, " \t");
    n = strcspn(text, " \t\r\n");
    if (n == 0 || n >= sizeof buf || text[n + strspn(text + n, " \t\r\n")] != '\0')
        return NAN;
    memcpy(buf, text, n);
    buf[n] = '\0';
    if (lf_csv_number(buf, 0, &v) != LF_NUM_OK || !isfinite(v))
        return NAN;
    return v;
}

static const lf_reader_type *
choose(const lf_read_opts *o, const char *head, size_t len, const char *name,
       lf_error *err)
{
    const lf_reader_type *r;
    char what[1024];
    lf_src src;

    if (o == NULL || o->format == NULL || o->format[0] == '\0')
        r = lf_reader_sniff(head, len);
    else if ((r = lf_reader_find(o->format)) == NULL) {
        unknown_format(name, o->format, err);
        return NULL;
    }
    /* a binary input that only a text reader would take: say what it is */
    src.mem = (const unsigned char *) head;
    src.fd = -1;
    src.size = len;
    src.name = name;
    if (lf_multi_of(r) == NULL
        && lf_describe_binary(&src, head, len < LF_SNIFF_BYTES ? len : LF_SNIFF_BYTES, what,
                              sizeof what)) {
        lf_fail_at(err, LF_EFORMAT, name, 0, 0, "%s", what);
        return NULL;
    }
    return r;
}

int
lf_curve_read(const char *path, const lf_read_opts *o, lf_curve **out,
              lf_warnings *warn, lf_error *err)
{
    char file[4096];
    lf_file *f = NULL;
    long index;
    int status;

    *out = NULL;
    lf_error_clear(err);
    if (lf_curve_path_split(path, file, sizeof file, &index) != LF_OK)
        return lf_fail_at(err, LF_EINVAL, path, 0, 0, "path too long");
    /* a text export is read once, whole, from a descriptor checked when it
     * was opened (the bytes sniffed are the bytes parsed); an archive by
     * random access */
    if ((status = lf_file_open(file, 0, o, &f, warn, err)) != LF_OK)
        return status;
    if (index < 0 && lf_file_count(f) > 1)
        status = lf_fail_at(err, LF_EDATA, file, 0, 0, "holds %zu curves: name one as "
                            "%s#0 .. %s#%zu (or fit each with layerfit fit --batch)",
                            lf_file_count(f), file, file, lf_file_count(f) - 1);
    else
        status = lf_file_curve(f, index < 0 ? 0 : (size_t) index, out, warn, err);
    lf_file_close(f);
    return status;
}

int
lf_curve_parse(const char *buf, size_t len, size_t chunk, const char *name,
               const lf_read_opts *o, lf_curve **out, lf_warnings *warn,
               lf_error *err)
{
    const lf_reader_type *r;

    *out = NULL;
    lf_error_clear(err);
    r = choose(o, buf ? buf : "", buf ? len : 0, name ? name : "", err);
    if (r == NULL)
        return err != NULL ? err->status : LF_EINVAL;
    return lf_curve_parse_with(r, buf, len, chunk, name, o, out, warn, err);
}

int
lf_curve_parse_with(const lf_reader_type *r, const char *buf, size_t len, size_t chunk,
                    const char *name, const lf_read_opts *o, lf_curve **out,
                    lf_warnings *warn, lf_error *err)
{
    lf_source in;

    *out = NULL;
    lf_error_clear(err);
    in.buf = buf ? buf : "";
    in.len = buf ? len : 0;
    in.chunk = chunk;
    in.name = name ? name : "";
    return run_reader(r, &in, o, out, warn, err);
}

/* ---------------------------------------------------------------------- */

lf_curve *
lf_curve_new(const char *name, const char *format)
{
    lf_curve *c = calloc(1, sizeof *c);
    if (c == NULL)
        return NULL;
    c->file = lf_strdup(name ? name : "");
    if (c->file == NULL) {
        free(c);
        return NULL;
    }
    c->format = format;
    c->R = c->spring_constant = c->sensitivity = NAN;
    c->x = c->y = NAN;
    c->grid_i = c->grid_j = -1;
    c->index = 0;
    return c;
}

lf_curve *
lf_curve_copy(const lf_curve *c)
{
    lf_curve *d = lf_curve_new(c->file, c->format);
    size_t i;
    if (d == NULL || lf_curve_reserve(d, c->n, c->time != NULL) != 0) {
        lf_curve_free(d);
        return NULL;
    }
    d->n = c->n;
    if (c->n > 0) {
        memcpy(d->depth, c->depth, c->n * sizeof *d->depth);
        memcpy(d->force, c->force, c->n * sizeof *d->force);
        memcpy(d->segment, c->segment, c->n * sizeof *d->segment);
        memcpy(d->line, c->line, c->n * sizeof *d->line);
        if (c->time != NULL)
            memcpy(d->time, c->time, c->n * sizeof *d->time);
    }
    if (c->nmeta > 0 && (d->meta = calloc(c->nmeta, sizeof *d->meta)) == NULL) {
        lf_curve_free(d);
        return NULL;
    }
    for (i = 0; i < c->nmeta; i++) {
        d->meta[i].key = lf_strdup(c->meta[i].key);
        d->meta[i].value = lf_strdup(c->meta[i].value);
        d->nmeta++;
        if (d->meta[i].key == NULL || d->meta[i].value == NULL) {
            lf_curve_free(d);
            return NULL;
        }
    }
    for (i = 0; i < c->info.n; i++)
        lf_warn(&d->info, "%s", c->info.msg[i]);
    d->R = c->R;
    d->spring_constant = c->spring_constant;
    d->sensitivity = c->sensitivity;
    d->spring_constant_source = c->spring_constant_source;
    d->sensitivity_source = c->sensitivity_source;
    d->sensitivity_unit = c->sensitivity_unit;
    d->x = c->x;
    d->y = c->y;
    d->grid_i = c->grid_i;
    d->grid_j = c->grid_j;
    d->index = c->index;
    return d;
}

int
lf_curve_reserve(lf_curve *c, size_t n, int with_time)
{
    void *p;
    if (n == 0)
        n = 1;
#define GROW(member)                                                 \
    if ((p = realloc(c->member, n * sizeof *c->member)) == NULL)     \
        return -1;                                                   \
    c->member = p;
    GROW(depth)
    GROW(force)
    GROW(segment)
    GROW(line)
    if (with_time) {
        GROW(time)
    }
#undef GROW
    return 0;
}

static int
valid_utf8(const unsigned char *s)
{
    while (*s) {
        size_t n = s[0] < 0x80 ? 1 : (s[0] >= 0xC2 && s[0] <= 0xDF) ? 2
                 : (s[0] >= 0xE0 && s[0] <= 0xEF) ? 3 : (s[0] >= 0xF0 && s[0] <= 0xF4) ? 4 : 0;
        size_t i;
        if (n == 0)
            return 0;
        for (i = 1; i < n; i++)
            if ((s[i] & 0xC0) != 0x80)
                return 0;
        s += n;
    }
    return 1;
}

void
lf_latin1_to_utf8(const char *src, char *dst, size_t n)
{
    const unsigned char *s = (const unsigned char *) src;
    size_t w = 0;
    if (n == 0)
        return;
    if (valid_utf8(s)) {
        size_t len = strlen(src);
        if (len >= n) {         /* cut at a character boundary */
            len = n - 1;
            while (len > 0 && (s[len] & 0xC0) == 0x80)
                len--;
        }
        memcpy(dst, src, len);
        dst[len] = '\0';
        return;
    }
    for (; *s && w + 3 < n; s++) {
        if (*s < 0x80) {
            dst[w++] = (char) *s;
        } else {
            dst[w++] = (char) (0xC0 | (*s >> 6));
            dst[w++] = (char) (0x80 | (*s & 0x3F));
        }
    }
    dst[w] = '\0';
}

const char *
lf_curve_meta(const lf_curve *c, const char *key)
{
    size_t i;
    for (i = 0; i < c->nmeta; i++)
        if (strcmp(c->meta[i].key, key) == 0)
            return c->meta[i].value;
    return NULL;
}

int
lf_curve_add_meta(lf_curve *c, const char *key, const char *value)
{
    char k[256], v[512];
    lf_meta *m;

    lf_latin1_to_utf8(key, k, sizeof k);
    lf_latin1_to_utf8(value, v, sizeof v);
    if (lf_curve_meta(c, k) != NULL)
        return 0;
    m = realloc(c->meta, (c->nmeta + 1) * sizeof *m);
    if (m == NULL)
        return -1;
    c->meta = m;
    m = &c->meta[c->nmeta];
    m->key = lf_strdup(k);
    m->value = lf_strdup(v);
    if (m->key == NULL || m->value == NULL) {
        free(m->key);
        free(m->value);
        return -1;
    }
    c->nmeta++;
    return 0;
}

int
lf_curve_finish(lf_curve *c, lf_warnings *warn, lf_error *err)
{
    size_t i, n[3] = { 0, 0, 0 };
    int seg;

    if (c->n == 0)
        return lf_fail_at(err, LF_EDATA, c->file, 0, 0,
                          "no data rows (expected one row of numbers per point)");
    for (i = 0; i < c->n; i++) {
        if (!isfinite(c->depth[i]) || !isfinite(c->force[i]))
            return lf_fail_at(err, LF_EFORMAT, c->file, c->line[i], 0,
                              "a depth or force here is not finite after conversion "
                              "to SI (check the units and constants)");
        n[c->segment[i] <= LF_SEG_HOLD ? c->segment[i] : 0]++;
    }
    for (seg = LF_SEG_LOAD; seg <= LF_SEG_UNLOAD; seg++) {
        size_t prev = 0, back = 0;
        int have = 0;
        long first = 0;
        double lo = INFINITY, hi = -INFINITY, tol;
        for (i = 0; i < c->n; i++)
            if (c->segment[i] == seg) {
                lo = fmin(lo, c->depth[i]);
                hi = fmax(hi, c->depth[i]);
            }
        /* a measured depth jitters: only steps back beyond 1% of the
         * segment's range are worth a word */
        tol = 0.01 * (hi - lo);
        for (i = 0; i < c->n; i++) {
            if (c->segment[i] != seg)
                continue;
            if (have && (seg == LF_SEG_LOAD ? c->depth[i] < c->depth[prev] - tol
                                            : c->depth[i] > c->depth[prev] + tol))
                if (back++ == 0)
                    first = c->line[i];
            prev = i;
            have = 1;
        }
        if (back > 0)
            lf_warn(warn, "%s:%ld: depth %s at %zu of the %zu points of the %sing "
                    "segment (first here)", c->file, first,
                    seg == LF_SEG_LOAD ? "decreases" : "increases", back, n[seg],
                    lf_segment_name((lf_segment) seg));
    }
    return LF_OK;
}

/* ---------------------------------------------------------------------- */

int
lf_afm_spring_constant(lf_curve *c, double file_k, const char *file_key,
                       const lf_read_opts *o, const char *why, lf_error *err)
{
    double opt = o ? o->spring_constant : NAN;
    if (isfinite(file_k) && file_k > 0) {
        c->spring_constant = file_k;
        c->spring_constant_source = "file header";
        lf_warn(&c->info, "spring constant %.6g N/m (file header '%s')", file_k, file_key);
        return LF_OK;
    }
    if (isfinite(opt) && opt > 0) {
        c->spring_constant = opt;
        c->spring_constant_source = "option";
        lf_warn(&c->info, "spring constant %.6g N/m (option --spring-constant)", opt);
        return LF_OK;
    }
    return lf_fail_at(err, LF_EDATA, c->file, 0, 0,
                      "the cantilever spring constant is not in the file and is needed "
                      "%s (give it: --spring-constant 0.032N/m)", why);
}

int
lf_afm_sensitivity(lf_curve *c, double file_s, const char *file_key, int per_amp,
                   const lf_read_opts *o, lf_error *err)
{
    const char *u = per_amp ? "m/A" : "m/V", *shown;
    double v;
    if (isfinite(file_s) && file_s > 0) {
        c->sensitivity = file_s;
        c->sensitivity_source = "file header";
        c->sensitivity_unit = u;
        shown = lf_sensitivity_shown(file_s, u, &v);
        lf_warn(&c->info, "sensitivity %.6g %s (file header '%s')", v, shown, file_key);
        return LF_OK;
    }
    if (o != NULL && isfinite(o->sensitivity) && o->sensitivity > 0) {
        if (o->sensitivity_per_amp != per_amp)
            return lf_fail_at(err, LF_EUNIT, c->file, 0, 0,
                              "--sensitivity is per %s, but the deflection here is in %s "
                              "(give it in %s, e.g. --sensitivity %s)",
                              o->sensitivity_per_amp ? "ampere" : "volt",
                              per_amp ? "amperes" : "volts", u,
                              per_amp ? "61nm/nA" : "50nm/V");
        c->sensitivity = o->sensitivity;
        c->sensitivity_source = "option";
        c->sensitivity_unit = u;
        shown = lf_sensitivity_shown(o->sensitivity, u, &v);
        lf_warn(&c->info, "sensitivity %.6g %s (option --sensitivity)", v, shown);
        return LF_OK;
    }
    return lf_fail_at(err, LF_EDATA, c->file, 0, 0,
                      "the deflection sensitivity is not in the file and is needed to "
                      "turn the deflection signal (%s) into a length (give it: "
                      "--sensitivity %s)", per_amp ? "A" : "V",
                      per_amp ? "61nm/nA" : "50nm/V");
}

int
lf_meta_number(const lf_curve *c, const char *key, lf_quantity q, double *si)
{
    const char *v = lf_curve_meta(c, key), *comma;
    char name[128], unit[64], num[64];
    double x, f = 1.0;
    size_t n;

    if (v == NULL)
        return -1;
    n = strcspn(v, " \t");
    if (n == 0 || n >= sizeof num)
        return -1;
    memcpy(num, v, n);
    num[n] = '\0';
    if (lf_csv_number(num, 1, &x) != LF_NUM_OK)
        return -1;
    if ((comma = strrchr(key, ',')) != NULL && strchr(key, '(') == NULL) {
        /* "Force Constant, nN/nm": the unit after the comma, µ as 'u' */
        snprintf(name, sizeof name, "x (%s)", comma + 1 + strspn(comma + 1, " "));
        lf_csv_header_cell(name, num, sizeof num, unit, sizeof unit);
    } else {
        lf_csv_header_cell(key, name, sizeof name, unit, sizeof unit);
    }
    if (q != LF_Q_DIMENSIONLESS && lf_units_factor(unit, q, &f, NULL) != LF_OK)
        return -1;
    *si = x * f;
    return isfinite(*si) ? 0 : -1;
}

int
lf_read_opts_constants(lf_read_opts *o, const char *spring_constant,
                       const char *sensitivity, lf_error *err)
{
    lf_error e;
    if (spring_constant != NULL) {
        if (lf_units_parse(spring_constant, LF_Q_STIFFNESS, &o->spring_constant, &e) != LF_OK)
            return lf_fail(err, e.status, "--spring-constant: %s", e.msg);
        if (!(o->spring_constant > 0))
            return lf_fail(err, LF_EINVAL, "--spring-constant must be > 0 (e.g. 0.032N/m)");
    }
    if (sensitivity != NULL) {
        o->sensitivity_per_amp = 1;
        if (lf_units_parse(sensitivity, LF_Q_SENS_AMP, &o->sensitivity, NULL) != LF_OK) {
            o->sensitivity_per_amp = 0;
            if (lf_units_parse(sensitivity, LF_Q_SENS_VOLT, &o->sensitivity, &e) != LF_OK)
                return lf_fail(err, e.status, "--sensitivity: '%s' is not a length per "
                               "volt or per ampere (e.g. 61nm/nA or 50nm/V)", sensitivity);
        }
        if (!(o->sensitivity > 0))
            return lf_fail(err, LF_EINVAL, "--sensitivity must be > 0 (e.g. 61nm/nA)");
    }
    return LF_OK;
}
