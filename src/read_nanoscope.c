/* read_nanoscope.c: Bruker (Veeco, Digital Instruments) Nanoscope force
 * files: single force curves and force volumes (.spm, .pfc, .000, ...).
 *
 * Layout, as the Nanoscope software writes it (NanoScope User Guide,
 * "File format"): a text header of "\key: value" lines, from
 * "\*Force file list" to "\*File list end" (then a 0x1A byte and padding up
 * to the header's "\Data length", the offset of the data), grouped in
 * sections "\*Name".  Each "\*Ciao force image list" section describes one
 * channel's data: "\Data offset", "\Data length", "\Samps/line" (points of
 * the approach and of the retract), and its scale "\@4:Z scale: V [Sens.
 * DeflSens] (0.000375 V/LSB) 2.5 V": a value is raw x hard scale (the
 * number in parentheses, V per least significant bit) x soft scale (the
 * "\@Sens. DeflSens: V 27.39 nm/V" the brackets name, here the deflection
 * sensitivity).  Values are little-endian signed integers; their width is
 * the data length over the number of values (files of NanoScope 9 store 4
 * bytes where "\Bytes/pixel" still says 2).  A curve is its approach then
 * its retract, both stored from the most extended Z back (so the approach
 * runs backwards in time); Z is the ramp: "\@4:Ramp size" volts x the Z
 * sensitivity ("\@Sens. Zsens", nm/V), in equal steps.  A force volume
 * ("\Operating mode: Force Volume") holds "\Samps/line" x "\Lines" curves
 * of its "\*Ciao scan list", one after another, row by row, over the
 * "\Scan Size" of the image.
 *
 * PeakForce Capture ("\PeakForce Capture: Allow" in the scan list, files
 * .pfc) stores one curve per pixel of the scan (its "\Samps/line" x
 * "\Lines", else a single curve), Z driven as a sine and not recorded:
 * each curve is one period of 2n samples, n the first number of the force
 * image list's "\Samps/line" (both halves n, as NanoScope's own toolbox
 * reads them), stored as above (the first n backwards).  In time order
 * the most extended Z (the peak force) falls at sample s = S x 2n / P
 * (mod 2n), S the "\Sync Distance QNM" (else "\Sync Distance") and P the
 * "\Sample Points" per period that S counts in; the curve is taken from
 * the Z minimum before that peak, s - n, round the period, so that with
 * u = (time index - s + n) mod 2n,
 *     Z = A (1 - cos(pi u / n)),  A the "\Peak Force Amplitude" (nm),
 * the approach being u < n and the retract u >= n.  The first sample in
 * time may hold the integer's least value, a marker: it takes the mean of
 * its neighbours in phase, the second and the last sample (AtomicJ reports
 * Bruker's MATLAB toolbox doing so).  (AtomicJ's Nanoscope reader, P.
 * Hermanowicz, and the readers of magic-afm and pyAF state the same sine
 * and, to a sample, the same phase; Bruker does not document them.)  Z is
 * relative to the sine's lowest point: the height image is not used.
 *
 * Conventions: the deflection d (raw x hard x soft) is positive when the
 * cantilever pushes; Z grows into the sample; the tip-sample separation,
 * positive into the sample, is Z - d; the force is k d with k the "\Spring
 * Constant" of the force image list.  The "\Deflection Sensitivity
 * Correction" some files state is reported, not applied (the sensitivity
 * is used as the file states it). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

#define MAX_HEADER (4u << 20)

typedef struct {
    const char *section;
    const char *key;        /* without "\", "@" and a group number "4:" */
    const char *value;
} ns_line;

typedef struct {
    char *text;             /* the header, split in place */
    ns_line *line;
    size_t n;
    /* what the curves need */
    uint64_t data_offset;
    size_t napp, nret, bytes, ncurves;
    double hard, soft;          /* V/LSB, m/V (NaN: not stated) */
    double k;                   /* N/m, NaN */
    double zstep;               /* m per point of the ramp */
    int pfc;                    /* PeakForce Capture: Z a sine */
    double amp, sync, delta;    /* its amplitude (m), peak sample s, ceil(s-n)-(s-n) */
    size_t k0;                  /* the time index of its first point */
    const char *sync_key;
    double dsc;                 /* deflection sensitivity correction, NaN */
    long samps, lines;          /* force volume grid, 0 for one curve */
    double sx, sy, x0, y0;      /* scan size and offsets, m */
} ns_state;

static int
ns_sniff(const char *head, size_t len)
{
    if (len >= 17 && memcmp(head, "\\*Force file list", 17) == 0)
        return 95;
    if (len >= 11 && memcmp(head, "\\*File list", 11) == 0)
        return 60;
    if (len >= 14 && memcmp(head, "\\*EC File list", 14) == 0)
        return 60;
    return 0;
}

/* Split the header text into lines of (section, key, value). */
static int
parse_header(ns_state *st, size_t len)
{
    char *p = st->text, *end = st->text + len;
    const char *section = "";
    size_t cap = 0;

    while (p < end) {
        char *eol = p, *colon, *key;
        while (eol < end && *eol != '\r' && *eol != '\n')
            eol++;
        *eol = '\0';
        if (p[0] == '\\' && p[1] == '*') {
            section = p + 2;
            if (strncmp(section, "File list end", 13) == 0)
                break;
        } else if (p[0] == '\\' && (colon = strstr(p, ": ")) != NULL) {
            *colon = '\0';
            key = p + 1;
            if (*key == '@')
                key++;
            if (key[0] >= '0' && key[0] <= '9' && key[1] == ':')
                key += 2;
            if (st->n == cap) {
                ns_line *l;
                cap = cap ? 2 * cap : 256;
                if ((l = realloc(st->line, cap * sizeof *l)) == NULL)
                    return LF_ENOMEM;
                st->line = l;
            }
            st->line[st->n].section = section;
            st->line[st->n].key = key;
            st->line[st->n].value = colon + 2;
            st->n++;
        }
        p = eol + 1;
        while (p < end && (*p == '\r' || *p == '\n'))
            p++;
    }
    return LF_OK;
}

/* The value of key in the first section named section (NULL: any), from
 * line `from` on; *at gets its line. */
static const char *
get(const ns_state *st, const char *section, const char *key, size_t from, size_t *at)
{
    size_t i;
    for (i = from; i < st->n; i++)
        if ((section == NULL || strcmp(st->line[i].section, section) == 0)
            && strcmp(st->line[i].key, key) == 0) {
            if (at != NULL)
                *at = i;
            return st->line[i].value;
        }
    return NULL;
}

/* The first number of a value, or NaN; *rest after it. */
static double
number(const char *v, const char **rest)
{
    char *end;
    double x;
    if (v == NULL)
        return NAN;
    v += strspn(v, " \t");
    x = strtod(v, &end);
    if (end == v || !isfinite(x))
        return NAN;
    if (rest != NULL)
        *rest = end;
    return x;
}

/* A CIAO value "V [soft] (hard unit) value unit": the hard scale, the
 * soft scale's name (into soft, may be empty) and the value. */
static void
ciao_value(const char *v, double *hard, char *soft, size_t nsoft, double *value)
{
    const char *b, *e, *rest = NULL;
    *hard = *value = NAN;
    soft[0] = '\0';
    if (v == NULL)
        return;
    if ((b = strchr(v, '[')) != NULL && (e = strchr(b, ']')) != NULL) {
        snprintf(soft, nsoft, "%.*s", (int) (e - b - 1), b + 1);
        v = e + 1;
    }
    if ((b = strchr(v, '(')) != NULL && (e = strchr(b, ')')) != NULL) {
        *hard = number(b + 1, NULL);
        v = e + 1;
    } else {
        v += strspn(v, " \tVCS");
    }
    *value = number(v, &rest);
}

/* A soft scale "\@Sens. Zsens: V 13.203 nm/V" in SI (m/V). */
static double
soft_scale(const ns_state *st, const char *name)
{
    const char *v = get(st, NULL, name, 0, NULL), *rest = NULL;
    double x;
    char unit[32] = "";
    if (v == NULL)
        return NAN;
    v += strspn(v, " \tV");
    x = number(v, &rest);
    if (!isfinite(x))
        return NAN;
    if (rest != NULL)
        sscanf(rest, " %31s", unit);
    if (unit[0] == '\0' || strcmp(unit, "nm/V") == 0)
        return x * 1e-9;
    if (strcmp(unit, "um/V") == 0 || strcmp(unit, "~m/V") == 0)
        return x * 1e-6;
    if (strcmp(unit, "m/V") == 0)
        return x;
    return NAN;
}

/* A length "2000 nm", "2 2 ~m" (x and y): into *x, *y (y = x when one). */
static int
scan_size(const char *v, double *x, double *y)
{
    const char *rest = NULL;
    double a = number(v, &rest), b, f;
    char unit[16] = "";
    if (!isfinite(a))
        return -1;
    b = number(rest, &rest);
    if (!isfinite(b))
        b = a;
    sscanf(rest ? rest : "", " %15s", unit);
    f = strcmp(unit, "nm") == 0 ? 1e-9 : strcmp(unit, "~m") == 0 || strcmp(unit, "um") == 0
        || strcmp(unit, "\xb5m") == 0 || strcmp(unit, "\xc2\xb5m") == 0 ? 1e-6
        : strcmp(unit, "mm") == 0 ? 1e-3 : NAN;
    if (!isfinite(f))
        return -1;
    *x = a * f;
    *y = b * f;
    return 0;
}

/* PeakForce Capture: the sine of Z from the scan list (see the top). */
static int
pfc_sine(const lf_file *f, ns_state *st, lf_error *err)
{
    const char *v, *rest = NULL, *missing = NULL;
    double amp, sync, points, n2 = 2.0 * (double) st->napp, c, unit = 1e-9;
    char word[16] = "";

    amp = number(get(st, NULL, "Peak Force Amplitude", 0, NULL), &rest);
    if (isfinite(amp) && rest != NULL && sscanf(rest, " %15s", word) == 1)
        unit = strcmp(word, "nm") == 0 ? 1e-9 : strcmp(word, "~m") == 0
            || strcmp(word, "um") == 0 ? 1e-6 : NAN;
    st->sync_key = "Sync Distance QNM";
    if ((v = get(st, NULL, st->sync_key, 0, NULL)) == NULL)
        v = get(st, NULL, st->sync_key = "Sync Distance", 0, NULL);
    sync = number(v, NULL);
    points = number(get(st, NULL, "Sample Points", 0, NULL), NULL);
    if (!(amp > 0 && amp < 1e9 && isfinite(unit)))
        missing = "'\\Peak Force Amplitude' (nm), the sine's amplitude";
    else if (!(fabs(sync) < 1e9))
        missing = "'\\Sync Distance QNM' or '\\Sync Distance', the sine's phase";
    else if (!(points >= 1 && points < 1e9))
        missing = "'\\Sample Points', the samples per period the sync distance counts in";
    if (missing != NULL)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "PeakForce Capture data: the Z of "
                          "its curves is a sine the header states, and it does not state %s",
                          missing);
    st->amp = amp * unit;
    st->sync = fmod(sync * n2 / points, n2);
    if (st->sync < 0)
        st->sync += n2;
    c = st->sync - (double) st->napp;           /* the Z minimum before the peak */
    st->delta = ceil(c) - c;
    st->k0 = (size_t) fmod(ceil(c) + n2, n2);
    return LF_OK;
}

static void
ns_close(lf_file *f)
{
    ns_state *st = f->state;
    if (st == NULL)
        return;
    free(st->text);
    free(st->line);
    free(st);
    f->state = NULL;
}

static int
ns_open(lf_file *f, lf_warnings *warn, lf_error *err)
{
    ns_state *st = calloc(1, sizeof *st);
    const char *v, *section = "Ciao force image list";
    size_t len, at = 0, sect_at = 0, i;
    uint64_t data_len;
    double hard, full, ramp, zsoft, gs, gl;
    char soft[64], zsoft_name[64];
    int status, fv;

    (void) warn;
    if (st == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    f->state = st;
    len = f->src.size < MAX_HEADER ? (size_t) f->src.size : MAX_HEADER;
    if ((st->text = malloc(len + 1)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    if ((status = lf_src_read(&f->src, 0, st->text, len, err)) != LF_OK)
        return status;
    for (i = 0; i < len && st->text[i] != '\x1a' && st->text[i] != '\0'; i++)
        ;
    len = i;
    st->text[len] = '\0';
    if (parse_header(st, len) != LF_OK)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    if (strncmp(st->text, "\\*", 2) != 0)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "not a Nanoscope file: it does not "
                          "start with a '\\*Force file list' header");
    if (get(st, NULL, "Data offset", 0, NULL) == NULL && strncmp(st->text, "\\*Force", 7) != 0)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a Nanoscope file without force "
                          "data (an image?): layerfit reads force curves and force volumes");
    /* the deflection channel: the force image list whose data are the
     * deflection (its "Image Data", else its scale's soft scale) */
    for (i = 0, v = NULL; (v = get(st, section, "Data offset", at, &at)) != NULL; at++) {
        const char *name;
        size_t j = at;
        /* the section's own lines: up to the next section */
        while (j > 0 && st->line[j - 1].section == st->line[at].section)
            j--;
        sect_at = j;
        name = get(st, st->line[at].section, "Image Data", j, NULL);
        ciao_value(get(st, st->line[at].section, "Z scale", j, NULL), &hard, soft, sizeof soft,
                   &full);
        if ((name != NULL && strstr(name, "Defl") != NULL)
            || (name == NULL && strstr(soft, "Defl") != NULL))
            break;
        i++;
    }
    if (v == NULL)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "no deflection data: no '\\*Ciao "
                          "force image list' section of deflection (%zu force channels)", i);
    {
        double off = number(v, NULL), dl = number(get(st, section, "Data length", sect_at, NULL), NULL);
        if (!(off >= 0 && off < 4e18 && dl >= 0 && dl < 4e18))
            return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "the force image list states no "
                              "data offset and length ('\\Data offset', '\\Data length')");
        st->data_offset = (uint64_t) off;
        data_len = (uint64_t) dl;
    }
    {
        const char *rest = NULL;
        double a = number(get(st, section, "Samps/line", sect_at, NULL), &rest);
        double r = number(rest, NULL);
        if (!isfinite(r))
            r = a;
        if (!(a >= 2 && r >= 2 && a < 1e8 && r < 1e8))
            return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "the force image list states no "
                              "points per curve ('\\Samps/line')");
        st->napp = (size_t) a;
        st->nret = (size_t) r;
    }
    /* the hard scale (V/LSB), else the full scale over 16 bits */
    ciao_value(get(st, section, "Z scale", sect_at, NULL), &hard, soft, sizeof soft, &full);
    st->hard = isfinite(hard) ? hard : full / 65536.0;
    st->soft = soft[0] ? soft_scale(st, soft) : NAN;
    if (isnan(st->soft))
        st->soft = soft_scale(st, "Sens. DeflSens");
    if (isnan(st->soft))
        st->soft = soft_scale(st, "Sens. Deflection");
    st->k = number(get(st, section, "Spring Constant", sect_at, NULL), NULL);
    if (isnan(st->k))
        st->k = number(get(st, section, "Spring constant", sect_at, NULL), NULL);
    st->dsc = number(get(st, NULL, "Deflection Sensitivity Correction", 0, NULL), NULL);
    v = get(st, NULL, "PeakForce Capture", 0, NULL);
    st->pfc = v != NULL && (v[0] == 'A' || v[0] == 'a') && strncmp(v + 1, "llow", 4) == 0;
    if (st->pfc) {
        st->nret = st->napp;    /* one period of 2n: both halves the first number */
        if ((status = pfc_sine(f, st, err)) != LF_OK)
            return status;
    } else {
        /* the ramp: in the force image list, else the force list */
        v = get(st, section, "Ramp Size", sect_at, NULL);
        if (v == NULL)
            v = get(st, section, "Ramp size", sect_at, NULL);
        if (v == NULL)
            v = get(st, "Ciao force list", "Ramp size", 0, NULL);
        if (v == NULL)
            v = get(st, "Ciao force list", "Ramp Size Zsweep", 0, NULL);
        ciao_value(v, &hard, zsoft_name, sizeof zsoft_name, &ramp);
        zsoft = soft_scale(st, zsoft_name[0] ? zsoft_name : "Sens. Zsens");
        if (isnan(zsoft))
            zsoft = soft_scale(st, "Sens. Zscan");
        if (!(ramp > 0) || !(zsoft > 0))
            return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "no Z ramp: '\\@4:Ramp size' and "
                              "the Z sensitivity '\\@Sens. Zsens' are needed for the piezo's "
                              "travel");
        st->zstep = ramp * zsoft / (double) (st->napp > st->nret ? st->napp : st->nret);
    }
    /* one curve, or a force volume; PeakForce Capture: a curve per pixel
     * of the scan when the data hold that many, else one */
    v = get(st, "Ciao scan list", "Operating mode", 0, NULL);
    fv = v != NULL && strstr(v, "Force Volume") != NULL;
    gs = number(get(st, "Ciao scan list", "Samps/line", 0, NULL), NULL);
    gl = number(get(st, "Ciao scan list", "Lines", 0, NULL), NULL);
    if (st->pfc && !fv && gs * gl > 1 && gs * gl < 1e8) {
        double per = gs * gl * 2.0 * (double) st->napp;
        fv = (double) data_len == 2 * per || (double) data_len == 4 * per;
    }
    st->ncurves = 1;
    if (fv) {
        if (!(gs >= 1 && gl >= 1 && gs * gl < 1e8))
            return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a force volume without its grid "
                              "('\\Samps/line' and '\\Lines' of the scan list)");
        st->samps = (long) gs;
        st->lines = (long) gl;
        st->ncurves = (size_t) (gs * gl);
        st->x0 = st->y0 = 0;
        st->sx = st->sy = NAN;
        v = get(st, "Ciao image list", "Scan Size", 0, NULL);
        if (v == NULL || scan_size(v, &st->sx, &st->sy) != 0)
            scan_size(get(st, "Ciao scan list", "Scan Size", 0, NULL), &st->sx, &st->sy);
        v = get(st, "Ciao scan list", "X Offset", 0, NULL);
        if (v != NULL && scan_size(v, &st->x0, &hard) != 0)
            st->x0 = 0;
        v = get(st, "Ciao scan list", "Y Offset", 0, NULL);
        if (v != NULL && scan_size(v, &st->y0, &hard) != 0)
            st->y0 = 0;
    }
    if (!(data_len > 0) || data_len % ((uint64_t) st->ncurves * (st->napp + st->nret)) != 0)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "the data length (%llu bytes) is not "
                          "a whole number of values for %zu curve%s of %zu + %zu points",
                          (unsigned long long) data_len, st->ncurves, st->ncurves == 1 ? "" : "s",
                          st->napp, st->nret);
    st->bytes = (size_t) (data_len / ((uint64_t) st->ncurves * (st->napp + st->nret)));
    if (st->bytes != 2 && st->bytes != 4)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "%zu bytes per value (the data "
                          "length over the points): layerfit reads 2 or 4", st->bytes);
    if (st->data_offset > f->src.size || data_len > f->src.size - st->data_offset)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "truncated: its data (%llu bytes at "
                          "byte %llu) run past its end (%llu bytes)",
                          (unsigned long long) data_len, (unsigned long long) st->data_offset,
                          (unsigned long long) f->src.size);
    f->n = st->ncurves;
    return LF_OK;
}

static int
ns_info(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err)
{
    const ns_state *st = f->state;
    (void) err;
    if (st->samps > 0) {
        info->grid_i = (long) (i % (size_t) st->samps);
        info->grid_j = (long) (i / (size_t) st->samps);
        if (isfinite(st->sx) && isfinite(st->sy)) {
            info->x = st->x0 + ((double) info->grid_i + 0.5) * st->sx / (double) st->samps;
            info->y = st->y0 + ((double) info->grid_j + 0.5) * st->sy / (double) st->lines;
        }
    }
    info->points = st->napp + st->nret;
    info->segment_points[LF_SEG_LOAD] = st->napp;
    info->segment_points[LF_SEG_UNLOAD] = st->nret;
    return LF_OK;
}

/* The value stored at index at. */
static long
raw_at(const unsigned char *raw, size_t bytes, size_t at)
{
    const unsigned char *p = raw + at * bytes;
    return bytes == 2 ? (long) (int16_t) lf_le16(p) : (long) (int32_t) lf_le32(p);
}

/* A PeakForce Capture curve from its raw values (s metres per LSB): the
 * period from the Z minimum before its peak, Z the sine (see the top).
 * Returns whether its first sample in time was the marker. */
static int
pfc_points(const ns_state *st, const unsigned char *raw, double s, lf_curve *c)
{
    size_t n = st->napp, m;
    long least = st->bytes == 2 ? INT16_MIN : INT32_MIN;
    int marker = 0;
    for (m = 0; m < 2 * n; m++) {
        size_t k = (st->k0 + m) % (2 * n);             /* its time index */
        long rv = raw_at(raw, st->bytes, k < n ? n - 1 - k : k);
        double d = (double) rv * s;
        if (k == 0 && rv == least) {    /* the marker: its neighbours in phase */
            d = 0.5 * s * (double) (raw_at(raw, st->bytes, n - 2)
                                    + raw_at(raw, st->bytes, 2 * n - 1));
            marker = 1;
        }
        c->depth[m] = st->amp * (1.0 - cos(M_PI * ((double) m + st->delta) / (double) n)) - d;
        c->force[m] = c->spring_constant * d;
        c->segment[m] = (unsigned char) (m < n ? LF_SEG_LOAD : LF_SEG_UNLOAD);
        c->line[m] = (long) m + 1;
    }
    return marker;
}

static int
ns_curve(const lf_file *f, size_t i, lf_curve *c, lf_warnings *warn, lf_error *err)
{
    const ns_state *st = f->state;
    size_t n = st->napp + st->nret, m;
    unsigned char *raw;
    lf_curve_info info;
    const char *v;
    int status, marker = 0;
    double s;

    memset(&info, 0, sizeof info);
    info.x = info.y = NAN;
    info.grid_i = info.grid_j = -1;
    ns_info(f, i, &info, err);
    c->x = info.x;
    c->y = info.y;
    c->grid_i = info.grid_i;
    c->grid_j = info.grid_j;
    if ((status = lf_afm_sensitivity(c, isfinite(st->soft) ? st->soft : NAN, "Sens. DeflSens",
                                     0, &f->opts, err)) != LF_OK
        || (status = lf_afm_spring_constant(c, st->k, "Spring Constant", &f->opts,
                                            "to turn the deflection into a force", err)) != LF_OK)
        return status;
    /* the probe's radius where the header states one (NanoScope writes
     * '\Tip Radius' in nm) */
    if ((v = get(st, NULL, "Tip Radius", 0, NULL)) != NULL && (s = number(v, NULL)) > 0
        && isfinite(s)) {
        c->R = 1e-9 * s;
        lf_warn(&c->info, "probe radius %.6g m (file header '\\Tip Radius', nm)", c->R);
    }
    if (lf_curve_reserve(c, n, 0) != 0 || (raw = malloc(n * st->bytes)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, c->file, 0, 0, "out of memory");
    status = lf_src_read(&f->src, st->data_offset + (uint64_t) i * n * st->bytes, raw,
                         n * st->bytes, err);
    if (status != LF_OK) {
        free(raw);
        return status;
    }
    s = st->hard * c->sensitivity;      /* m per LSB */
    if (st->pfc)
        marker = pfc_points(st, raw, s, c);
    for (m = 0; m < n && !st->pfc; m++) {
        /* approach: stored from the most extended Z back, so read it
         * backwards; retract: as stored */
        size_t seg_n = m < st->napp ? st->napp : st->nret;
        size_t k = m < st->napp ? st->napp - 1 - m : m - st->napp;
        size_t at = m < st->napp ? k : st->napp + k;
        double d = (double) raw_at(raw, st->bytes, at) * s;
        double z = (double) (seg_n - 1 - k) * st->zstep;
        c->depth[m] = z - d;
        c->force[m] = c->spring_constant * d;
        c->segment[m] = (unsigned char) (m < st->napp ? LF_SEG_LOAD : LF_SEG_UNLOAD);
        c->line[m] = (long) m + 1;      /* binary: the point's number */
    }
    free(raw);
    c->n = n;
    if ((v = get(st, NULL, "Microscope", 0, NULL)) != NULL)
        lf_curve_add_meta(c, "instrument", v);
    if ((v = get(st, NULL, "Version", 0, NULL)) != NULL)
        lf_curve_add_meta(c, "version", v);
    if ((v = get(st, NULL, "Date", 0, NULL)) != NULL)
        lf_curve_add_meta(c, "date", v);
    if ((v = get(st, "Ciao scan list", "Operating mode", 0, NULL)) != NULL)
        lf_curve_add_meta(c, "operating mode", v);
    lf_warn(&c->info, "data: %zu curve%s of %zu approach + %zu retract points, %zu-byte "
            "little-endian integers at byte %llu", st->ncurves, st->ncurves == 1 ? "" : "s",
            st->napp, st->nret, st->bytes, (unsigned long long) st->data_offset);
    lf_warn(&c->info, "force: raw x %.6g V/LSB (hard scale) x sensitivity x k", st->hard);
    if (isfinite(st->dsc) && st->dsc != 1.0)
        lf_warn(&c->info, "Deflection Sensitivity Correction %.6g stated, not applied",
                st->dsc);
    if (st->pfc) {
        lf_warn(&c->info, "depth: tip-sample separation = Z - deflection (into the sample "
                "positive), Z = A (1 - cos(pi u / %zu)) the PeakForce Capture sine, A = %.6g nm "
                "('Peak Force Amplitude'), u the sample's place from the Z minimum",
                st->napp, st->amp * 1e9);
        lf_warn(&c->info, "segments: one period of %zu samples in time order, its peak at "
                "sample %.6g ('%s' x %zu / 'Sample Points'), from the Z minimum before it: "
                "approach %zu, retract %zu points", n, st->sync, st->sync_key, n, st->napp,
                st->nret);
        if (marker)
            lf_warn(&c->info, "the first sample in time holds the integer's least value (a "
                    "marker, not a deflection): it takes the mean of its neighbours in phase, "
                    "the second and the last sample");
    } else {
        lf_warn(&c->info, "depth: tip-sample separation = Z - deflection (into the sample "
                "positive), Z the ramp in steps of %.6g nm", st->zstep * 1e9);
        lf_warn(&c->info, "segments: approach %zu (stored backwards), retract %zu points",
                st->napp, st->nret);
    }
    return lf_curve_finish(c, warn, err);
}

static int
ns_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
        lf_error *err)
{
    return lf_multi_read_one(&lf_multi_nanoscope, in, o, c, warn, err);
}

const lf_reader_type lf_reader_nanoscope = {
    "nanoscope", "Bruker Nanoscope force file or force volume (.spm, .000, ...: a "
    "'\\*Force file list' header, then little-endian integers)",
    ns_sniff, ns_read
};

const lf_multi_reader lf_multi_nanoscope = {
    &lf_reader_nanoscope, ns_open, ns_info, ns_curve, ns_close
};
