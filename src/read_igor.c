/* read_igor.c: Asylum Research force curves saved as Igor binary waves
 * (.ibw, version 5).
 *
 * Layout, as Igor Pro writes it (WaveMetrics Technical Note 003): a
 * 64-byte BinHeader5 (version 5, a checksum, the sizes of the parts that
 * follow), a 320-byte WaveHeader5 (number of points, data type, wave name,
 * nDim[4]: rows and columns, the data units), the data (column after
 * column), then the formula, the note, the units and the dimension labels
 * of each dimension (one label per column, preceded by the dimension's
 * own, in fields of equal width).  The byte order is the writer's: the
 * version field reads 5 in it.  The 16-bit words of the two headers sum to
 * zero.  Asylum's note is "Key: value" lines separated by carriage
 * returns; it states SpringConstant (N/m), InvOLS (the deflection
 * sensitivity, m/V), the segment boundaries "Indexes: 0,5057,10096" with
 * "Direction: NaN,1,-1," (1 extend, 0 dwell, -1 retract), XLVDT / YLVDT.
 *
 * Columns (labels): Defl or Deflection, the cantilever deflection in m,
 * positive pushing; ZSnsr or ZSensor, the measured Z, growing into the
 * sample (else Raw or Height, the piezo's).  The tip-sample separation,
 * positive into the sample, is Z - Defl; the force is SpringConstant x
 * Defl (InvOLS is not needed: Defl is already a length). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

#define BIN5 64
#define WAVE5 320
#define MAX_NOTE (16u << 20)

typedef struct {
    int le;                     /* little-endian */
    uint32_t npnts, nrows, ncols;
    int type;
    uint64_t data_off, note_off, labels_off;
    uint32_t note_size, labels_size;
    char *note;                 /* NUL-terminated, \r turned into \n */
    char unit[5];
    char name[33];
    char labels[64][40];        /* column labels, up to 64 columns */
} ibw_state;

static uint32_t
u32(const ibw_state *st, const unsigned char *p)
{
    return st->le ? lf_le32(p) : lf_be32(p);
}

static uint16_t
u16(const ibw_state *st, const unsigned char *p)
{
    return st->le ? lf_le16(p) : lf_be16(p);
}

static int
ibw_sniff(const char *head, size_t len)
{
    const unsigned char *p = (const unsigned char *) head;
    if (len < BIN5 + WAVE5)
        return 0;
    /* version 5 in either byte order, and a plausible data type */
    if ((p[0] == 5 && p[1] == 0) || (p[0] == 0 && p[1] == 5)) {
        int le = p[0] == 5;
        uint16_t type = le ? lf_le16(p + BIN5 + 16) : lf_be16(p + BIN5 + 16);
        uint32_t i, sum = 0;
        for (i = 0; i < BIN5 + WAVE5; i += 2)
            sum += le ? lf_le16(p + i) : lf_be16(p + i);
        if ((sum & 0xFFFF) == 0 && type != 0)
            return 95;
        return 40;
    }
    return 0;
}

/* The value of note key (exact, before its ':'), or NULL; into buf. */
static const char *
note_get(const ibw_state *st, const char *key, char *buf, size_t n)
{
    size_t klen = strlen(key);
    const char *p = st->note;
    while (p != NULL && *p) {
        const char *eol = strchr(p, '\n');
        size_t len = eol ? (size_t) (eol - p) : strlen(p);
        if (len > klen && memcmp(p, key, klen) == 0 && p[klen] == ':') {
            const char *v = p + klen + 1;
            size_t vl = len - klen - 1;
            while (vl > 0 && (*v == ' ' || *v == '\t')) {
                v++;
                vl--;
            }
            snprintf(buf, n, "%.*s", (int) vl, v);
            return buf;
        }
        p = eol ? eol + 1 : NULL;
    }
    return NULL;
}

static double
note_number(const ibw_state *st, const char *key)
{
    char buf[128];
    return lf_number_or_nan(note_get(st, key, buf, sizeof buf));
}

static void
ibw_close(lf_file *f)
{
    ibw_state *st = f->state;
    if (st == NULL)
        return;
    free(st->note);
    free(st);
    f->state = NULL;
}

static int
ibw_open(lf_file *f, lf_warnings *warn, lf_error *err)
{
    unsigned char h[BIN5 + WAVE5];
    ibw_state *st = calloc(1, sizeof *st);
    uint32_t sum = 0, i, wfm, formula, dim_eunits = 0, eunits, lsize[4];
    uint64_t elem, need;
    int status, version;

    (void) warn;
    if (st == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    f->state = st;
    if ((status = lf_src_read(&f->src, 0, h, sizeof h, err)) != LF_OK)
        return status;
    st->le = h[0] != 0;
    version = u16(st, h);
    if (version != 5)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "an Igor binary wave of version %d: "
                          "layerfit reads version 5 (save it again from Igor Pro 3 or later)",
                          version);
    for (i = 0; i < sizeof h; i += 2)
        sum += u16(st, h + i);
    if ((sum & 0xFFFF) != 0)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a damaged Igor binary wave: its "
                          "header checksum does not add up");
    wfm = u32(st, h + 4);
    formula = u32(st, h + 8);
    st->note_size = u32(st, h + 12);
    eunits = u32(st, h + 16);
    for (i = 0; i < 4; i++) {
        dim_eunits += u32(st, h + 20 + 4 * i);
        lsize[i] = u32(st, h + 36 + 4 * i);
    }
    st->npnts = u32(st, h + BIN5 + 12);
    st->type = u16(st, h + BIN5 + 16);
    memcpy(st->name, h + BIN5 + 28, 32);
    st->name[32] = '\0';
    st->nrows = u32(st, h + BIN5 + 68);
    st->ncols = u32(st, h + BIN5 + 72);
    memcpy(st->unit, h + BIN5 + 148, 4);
    st->unit[4] = '\0';
    if (st->ncols == 0)
        st->ncols = 1;
    if (u32(st, h + BIN5 + 76) > 1)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a wave of %u layers: layerfit reads "
                          "a force curve's table (rows of points, one column per signal)",
                          (unsigned) u32(st, h + BIN5 + 76));
    elem = (st->type & 0x3E) == 2 ? 4 : (st->type & 0x3E) == 4 ? 8 : (st->type & 0x3E) == 8 ? 1
         : (st->type & 0x3E) == 0x10 ? 2 : (st->type & 0x3E) == 0x20 ? 4 : 0;
    if (elem == 0 || (st->type & 1))
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "an Igor wave of type 0x%x (text or "
                          "complex): layerfit reads real numbers", (unsigned) st->type);
    if ((uint64_t) st->nrows * st->ncols != st->npnts || st->npnts == 0 || st->ncols > 64)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a wave of %u points in %u rows of %u "
                          "columns: not a force curve's table", (unsigned) st->npnts,
                          (unsigned) st->nrows, (unsigned) st->ncols);
    st->data_off = BIN5 + WAVE5;
    need = (uint64_t) st->npnts * elem;
    if (wfm < WAVE5 || need > (uint64_t) wfm - WAVE5 + 16 || st->data_off + need > f->src.size)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "truncated: %llu bytes of data "
                          "stated, the file holds %llu", (unsigned long long) need,
                          (unsigned long long) (f->src.size > st->data_off
                                                ? f->src.size - st->data_off : 0));
    st->note_off = BIN5 + (uint64_t) wfm + formula;
    st->labels_off = st->note_off + st->note_size + eunits + dim_eunits + lsize[0];
    st->labels_size = lsize[1];
    if (st->note_size > MAX_NOTE || st->note_off + st->note_size > f->src.size)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "truncated: its note (%u bytes) "
                          "runs past its end", (unsigned) st->note_size);
    if ((st->note = malloc(st->note_size + 1)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    if ((status = lf_src_read(&f->src, st->note_off, st->note, st->note_size, err)) != LF_OK)
        return status;
    st->note[st->note_size] = '\0';
    for (i = 0; i < st->note_size; i++)
        if (st->note[i] == '\r' || st->note[i] == '\0')
            st->note[i] = '\n';
    /* the column labels: nDim[1] + 1 fields of equal width */
    if (st->labels_size > 0 && st->labels_size % (st->ncols + 1) == 0
        && st->labels_off + st->labels_size <= f->src.size) {
        uint32_t w = st->labels_size / (st->ncols + 1), c;
        char *lab = malloc(st->labels_size);
        if (lab == NULL)
            return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
        if ((status = lf_src_read(&f->src, st->labels_off, lab, st->labels_size, err)) != LF_OK) {
            free(lab);
            return status;
        }
        for (c = 0; c < st->ncols; c++)
            snprintf(st->labels[c], sizeof st->labels[c], "%.*s", (int) (w < 39 ? w : 39),
                     lab + (c + 1) * w);
        free(lab);
    }
    f->n = 1;
    return LF_OK;
}

static int
column(const ibw_state *st, const char *const *names)
{
    size_t k;
    uint32_t c;
    for (k = 0; names[k] != NULL; k++)
        for (c = 0; c < st->ncols; c++)
            if (strcmp(st->labels[c], names[k]) == 0)
                return (int) c;
    return -1;
}

/* Value r of column c. */
static double
value(const ibw_state *st, const unsigned char *data, uint32_t r, uint32_t c)
{
    uint64_t at = (uint64_t) c * st->nrows + r;
    int t = st->type & 0x3E, uns = st->type & 0x40;
    const unsigned char *p;
    switch (t) {
    case 2: {
        uint32_t u;
        float x;
        p = data + at * 4;
        u = u32(st, p);
        memcpy(&x, &u, sizeof x);
        return x;
    }
    case 4: {
        uint64_t u;
        double x;
        p = data + at * 8;
        u = st->le ? (uint64_t) lf_le32(p + 4) << 32 | lf_le32(p)
                   : (uint64_t) lf_be32(p) << 32 | lf_be32(p + 4);
        memcpy(&x, &u, sizeof x);
        return x;
    }
    case 8:
        return uns ? (double) data[at] : (double) (int8_t) data[at];
    case 0x10:
        p = data + at * 2;
        return uns ? (double) u16(st, p) : (double) (int16_t) u16(st, p);
    default:
        p = data + at * 4;
        return uns ? (double) u32(st, p) : (double) (int32_t) u32(st, p);
    }
}

static int
ibw_info(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err)
{
    const ibw_state *st = f->state;
    (void) i;
    (void) err;
    info->x = note_number(st, "XLVDT");
    info->y = note_number(st, "YLVDT");
    if (isnan(info->x) || isnan(info->y))
        info->x = info->y = NAN;
    info->points = st->nrows;
    return LF_OK;
}

/* Segments from "Indexes" and "Direction"; 0 when the note has none. */
static int
note_segments(const ibw_state *st, lf_curve *c)
{
    char ib[512], db[512], *p, *q, *end;
    long idx[64];
    int dir[64], ni = 0, nd = 0, k;
    size_t m;
    if (note_get(st, "Indexes", ib, sizeof ib) == NULL
        || note_get(st, "Direction", db, sizeof db) == NULL)
        return 0;
    for (p = ib; *p && ni < 64; p = *end ? end + 1 : end) {
        idx[ni++] = strtol(p, &end, 10);
        end += strspn(end, " ");
        if (end == p || (*end && *end != ','))
            return 0;
    }
    for (q = db; *q && nd < 64; q = *end ? end + 1 : end) {
        double v;
        char cell[32];
        size_t n = strcspn(q, ",");
        end = q + n;
        snprintf(cell, sizeof cell, "%.*s", (int) (n < 31 ? n : 31), q);
        v = lf_number_or_nan(cell);
        dir[nd++] = isnan(v) ? 99 : v > 0 ? LF_SEG_LOAD : v < 0 ? LF_SEG_UNLOAD : LF_SEG_HOLD;
    }
    if (ni < 2 || nd != ni || idx[0] != 0 || idx[ni - 1] != (long) c->n - 1)
        return 0;
    for (k = 1; k < ni; k++)
        if (idx[k] <= idx[k - 1] || dir[k] == 99)
            return 0;
    for (k = 1, m = 0; k < ni; k++)
        for (; (long) m < idx[k] || (k == ni - 1 && m < c->n); m++)
            c->segment[m] = (unsigned char) dir[k];
    return 1;
}

static int
ibw_curve(const lf_file *f, size_t i, lf_curve *c, lf_warnings *warn, lf_error *err)
{
    static const char *const defl[] = { "Defl", "Deflection", NULL };
    static const char *const zs[] = { "ZSnsr", "ZSensor", "Raw", "Height", NULL };
    static const char *const keys[] = { "MicroscopeModel", "Version", "Date", "Time",
                                         "SpringConstant", "InvOLS", "Indexes",
                                         "XLVDT", "YLVDT", "TipRadius", NULL };
    const ibw_state *st = f->state;
    lf_curve_info info;
    unsigned char *data;
    uint64_t bytes = (uint64_t) st->npnts * ((st->type & 0x3E) == 4 ? 8 : (st->type & 0x3E) == 8
                     ? 1 : (st->type & 0x3E) == 0x10 ? 2 : 4);
    int jd = column(st, defl), jz = column(st, zs), status;
    double *z;
    uint32_t r;
    size_t k;
    char buf[160];

    if (jd < 0 || jz < 0)
        return lf_fail_at(err, LF_EFORMAT, c->file, 0, 0, "no %s column (the wave's columns: "
                          "%s%s%s%s%s; expected Defl, and ZSnsr or Raw)",
                          jd < 0 ? "deflection" : "Z", st->labels[0],
                          st->ncols > 1 ? ", " : "", st->ncols > 1 ? st->labels[1] : "",
                          st->ncols > 2 ? ", " : "", st->ncols > 2 ? st->labels[2] : "");
    if (strcmp(st->unit, "m") != 0)
        return lf_fail_at(err, LF_EUNIT, c->file, 0, 0, "the wave's data are in '%s' "
                          "(expected m: Defl and ZSnsr as lengths)", st->unit);
    if ((status = lf_afm_spring_constant(c, note_number(st, "SpringConstant"), "SpringConstant",
                                         &f->opts, "to turn the deflection into a force",
                                         err)) != LF_OK)
        return status;
    if ((data = malloc((size_t) bytes)) == NULL || lf_curve_reserve(c, st->nrows, 0) != 0
        || (z = malloc(st->nrows * sizeof *z)) == NULL) {
        free(data);
        return lf_fail_at(err, LF_ENOMEM, c->file, 0, 0, "out of memory");
    }
    if ((status = lf_src_read(&f->src, st->data_off, data, (size_t) bytes, err)) != LF_OK) {
        free(data);
        free(z);
        return status;
    }
    for (r = 0; r < st->nrows; r++) {
        double d = value(st, data, r, (uint32_t) jd);
        z[r] = value(st, data, r, (uint32_t) jz);
        c->depth[r] = z[r] - d;
        c->force[r] = c->spring_constant * d;
        c->segment[r] = LF_SEG_LOAD;
        c->line[r] = (long) r + 1;      /* binary: the point's number */
    }
    c->n = st->nrows;
    free(data);
    (void) i;
    memset(&info, 0, sizeof info);
    ibw_info(f, 0, &info, err);
    c->x = info.x;
    c->y = info.y;
    for (k = 0; keys[k] != NULL; k++)
        if (note_get(st, keys[k], buf, sizeof buf) != NULL && buf[0] != '\0')
            lf_curve_add_meta(c, keys[k], buf);
    lf_curve_add_meta(c, "wave", st->name);
    lf_warn(&c->info, "wave: %u rows x %u columns (%s), type 0x%x, %s-endian", (unsigned) st->nrows,
            (unsigned) st->ncols, st->labels[0], (unsigned) st->type, st->le ? "little" : "big");
    lf_warn(&c->info, "force: SpringConstant x '%s' (m)", st->labels[jd]);
    lf_warn(&c->info, "depth: tip-sample separation = '%s' - '%s' (into the sample positive)",
            st->labels[jz], st->labels[jd]);
    if (note_segments(st, c)) {
        note_get(st, "Indexes", buf, sizeof buf);
        lf_warn(&c->info, "segments: from the note's Indexes (%s) and Direction", buf);
    } else {
        lf_segments_from_profile(c, z, NULL, st->labels[jz]);
    }
    free(z);
    return lf_curve_finish(c, warn, err);
}

static int
ibw_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
         lf_error *err)
{
    return lf_multi_read_one(&lf_multi_igor, in, o, c, warn, err);
}

const lf_reader_type lf_reader_igor = {
    "igor", "Asylum Research force curve as an Igor binary wave (.ibw, version 5: Raw, "
    "Defl, ZSnsr columns, SpringConstant in the note)",
    ibw_sniff, ibw_read
};

const lf_multi_reader lf_multi_igor = {
    &lf_reader_igor, ibw_open, ibw_info, ibw_curve, ibw_close
};
