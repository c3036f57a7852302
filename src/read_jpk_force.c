/* read_jpk_force.c: JPK (Bruker) binary force files: .jpk-force (one
 * curve), .jpk-force-map (a force map), .jpk-qi-data (a QI map) and
 * .jpk-qi-series (one QI curve).
 *
 * Layout, as JPK's software writes it: a zip archive of Java properties
 * files and channels of big-endian numbers.  A single curve:
 *     header.properties                      the curve's header
 *     shared-data/header.properties          what the headers point into
 *     segments/S/segment-header.properties   segment S (extend, pause, retract)
 *     segments/S/channels/NAME.dat           its channels (vDeflection, height, ...)
 * A map keeps its own header.properties (the grid) and one such curve per
 * index/K/ folder (index/K/header.properties, index/K/segments/S/...).
 *
 * A channel's properties sit in its segment header as
 * channel.NAME.data.encoder.* / channel.NAME.conversion-set.* (older
 * files), or are shared: channel.NAME.lcd-info.*=N stands for every
 * lcd-info.N.* of the shared header (newer files); likewise
 * force-segment-header.force-segment-header-info.*=N for
 * force-segment-header-info.N.*.  A raw value (encoder.type signedshort,
 * unsignedshort, signedinteger, unsignedinteger, signedlong; or float or
 * double data) becomes a value in the base slot (volts) by the encoder's
 * scaling (offset + multiplier x raw), then climbs the conversion set: each
 * slot is offset + multiplier x its base-calibration-slot.  vDeflection:
 * volts -> distance (m; the multiplier is the deflection sensitivity) ->
 * force (N; the multiplier is the spring constant).  Heights: volts ->
 * nominal -> calibrated (m).  Where the file leaves the distance or force
 * conversion undefined (a calibration curve), --sensitivity and
 * --spring-constant supply it.
 *
 * Conventions as in the JPK text export (read_jpk.c): heights grow away
 * from the sample, the deflection d is positive when the cantilever
 * pushes; the tip-sample separation, positive into the sample, is
 * -(height + d).  Height channel, by preference: measuredHeight,
 * capacitiveSensorHeight, strainGaugeHeight, height, head-height,
 * smoothedMeasuredHeight, smoothedCapacitiveSensorHeight; in the nominal
 * slot for the measured ones, calibrated for the piezo's height.
 * Position: the curve header's *.header.position.x/y (m); grid: the map
 * header's *.position-pattern.grid.ilength/jlength, the curve's
 * *.header.position-index, rows walked back and forth where the pattern
 * says so. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

#define MAX_ENTRY (1ull << 30)      /* bytes of one channel */
#define MAX_PROPS (64ull << 20)     /* bytes of one properties file */
#define WHAT_HEADER 0xFFFFu         /* the curve's header.properties */
#define WHAT_SEGMENT 0xFFFEu        /* a segment-header.properties */
#define MAX_SEGMENTS 64

static const char *const height_names[] = {
    "measuredHeight", "capacitiveSensorHeight", "strainGaugeHeight", "height",
    "head-height", "smoothedMeasuredHeight", "smoothedCapacitiveSensorHeight", NULL
};

typedef struct {
    long k;                     /* index/K, 0 for a single curve */
    uint16_t seg;
    uint16_t what;              /* WHAT_*, or a channel's number in chan[] */
    lf_zip_entry e;
} jpk_entry;

/* The entries of one curve, gathered from its part of the directory when
 * it is read (the listing keeps only where that part is). */
typedef struct {
    long want;                  /* the curve's index/K, or -1 (a single curve) */
    jpk_entry *ent;             /* sorted by segment and what */
    size_t nent, cap;
    char **chan;                /* channel names */
    size_t nchan;
} jpk_entries;

/* A stretch of the central directory holding entries of curve k only
 * (JPK writes each curve's folder in one stretch: one run per curve). */
typedef struct {
    long k;                     /* index/K, or -1 (segments/ of a single curve) */
    uint64_t start, end;        /* bytes of the directory */
} jpk_run;

typedef struct {
    int map;                    /* index/K/ folders */
    lf_props top, shared;       /* header.properties, shared-data/header.properties */
    jpk_run *run;               /* sorted by k, then start */
    size_t nrun, cap;
    size_t *first;              /* curve i: run[first[i] .. first[i+1]-1] */
    int in_run;                 /* the stretch being walked */
    long cur_k;
    uint64_t cur_start;
    int have_top, have_shared, have_index, have_segments;
    lf_zip_entry top_e, shared_e;
    long grid_il, grid_jl;      /* grid columns and rows, or 0 */
    int back_and_forth;
} jpk_state;

/* One curve's headers, parsed. */
typedef struct {
    const jpk_state *st;
    const lf_src *src;
    lf_props head;              /* its header.properties (a copy of top when single) */
    int own_head;
    size_t nseg;
    uint16_t segno[MAX_SEGMENTS];
    lf_props seg[MAX_SEGMENTS];
    jpk_entries col;            /* its entries */
    const jpk_entry *ents;      /* = col.ent, col.nent */
    size_t nents;
} jpk_curve;

/* ---------------------------------------------------------------------- */

/* JPK's own names: those of its archives' first entries */
static int
jpk_name(const char *name, size_t n)
{
    static const char *const names[] = { "header.properties", "shared-data/", "segments/",
                                         "index/", "data-image", "thumbnail.png", NULL };
    size_t k;
    for (k = 0; names[k] != NULL; k++)
        if (n >= strlen(names[k]) && memcmp(name, names[k], strlen(names[k])) == 0)
            return 1;
    return 0;
}

static int
jpk_sniff(const char *head, size_t len)
{
    size_t i, nlen;
    if (!lf_zip_magic(head, len))
        return 0;
    /* the first entry's name, then any local header's in the first bytes */
    if (len >= 30 && memcmp(head, "PK\3\4", 4) == 0) {
        nlen = lf_le16((const unsigned char *) head + 26);
        if (30 + nlen <= len && jpk_name(head + 30, nlen))
            return 95;
    }
    for (i = 0; i + 30 < len; i++)
        if (memcmp(head + i, "PK\3\4", 4) == 0) {
            nlen = lf_le16((const unsigned char *) head + i + 26);
            if (i + 30 + nlen <= len && jpk_name(head + i + 30, nlen))
                return 95;
        }
    /* some other zip: the archive's directory decides (jpk_open says
     * what it holds when it is not JPK's) */
    return 40;
}

static long
parse_long(const char *s, size_t n, int *ok)
{
    long v = 0;
    size_t i;
    *ok = n > 0 && n <= 9;
    for (i = 0; *ok && i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            *ok = 0;
        else
            v = 10 * v + (s[i] - '0');
    }
    return v;
}

static int
add_entry(jpk_entries *c, long k, long seg, unsigned what, const lf_zip_entry *e)
{
    if (c->nent == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 16;
        jpk_entry *p = realloc(c->ent, cap * sizeof *p);
        if (p == NULL)
            return LF_ENOMEM;
        c->ent = p;
        c->cap = cap;
    }
    c->ent[c->nent].k = k;
    c->ent[c->nent].seg = (uint16_t) seg;
    c->ent[c->nent].what = (uint16_t) what;
    c->ent[c->nent].e = *e;
    c->nent++;
    return LF_OK;
}

static long
channel_number(jpk_entries *c, const char *name, size_t n)
{
    size_t i;
    char **p;
    for (i = 0; i < c->nchan; i++)
        if (strlen(c->chan[i]) == n && memcmp(c->chan[i], name, n) == 0)
            return (long) i;
    if (c->nchan >= 256)
        return -1;
    if ((p = realloc(c->chan, (c->nchan + 1) * sizeof *p)) == NULL)
        return -2;
    c->chan = p;
    if ((c->chan[c->nchan] = malloc(n + 1)) == NULL)
        return -2;
    memcpy(c->chan[c->nchan], name, n);
    c->chan[c->nchan][n] = '\0';
    return (long) c->nchan++;
}

static void
entries_free(jpk_entries *c)
{
    size_t i;
    for (i = 0; i < c->nchan; i++)
        free(c->chan[i]);
    free(c->chan);
    free(c->ent);
    memset(c, 0, sizeof *c);
}

/* The part of a curve's folder after "segments/": "S/segment-header.properties"
 * or "S/channels/NAME.dat". */
static int
segment_entry(jpk_entries *c, long k, const char *rest, const lf_zip_entry *e)
{
    const char *slash = strchr(rest, '/');
    long seg, ch;
    int ok;
    if (slash == NULL)
        return LF_OK;
    seg = parse_long(rest, (size_t) (slash - rest), &ok);
    if (!ok || seg >= MAX_SEGMENTS)
        return LF_OK;
    rest = slash + 1;
    if (strcmp(rest, "segment-header.properties") == 0)
        return add_entry(c, k, seg, WHAT_SEGMENT, e);
    if (strncmp(rest, "channels/", 9) == 0 && strlen(rest) > 13
        && strcmp(rest + strlen(rest) - 4, ".dat") == 0) {
        ch = channel_number(c, rest + 9, strlen(rest) - 13);
        if (ch == -2)
            return LF_ENOMEM;
        return ch < 0 ? LF_OK : add_entry(c, k, seg, (unsigned) ch, e);
    }
    return LF_OK;
}

/* The curve an entry's name belongs to: index/K (*k = K, *rest after
 * "index/K/") or segments/ of a single curve (*k = -1); 0 for another. */
static int
curve_of_name(const char *name, long *k, const char **rest)
{
    const char *slash;
    int ok;
    if (strncmp(name, "segments/", 9) == 0) {
        *k = -1;
        *rest = name;
        return 1;
    }
    if (strncmp(name, "index/", 6) != 0 || (slash = strchr(name + 6, '/')) == NULL)
        return 0;
    *k = parse_long(name + 6, (size_t) (slash - name - 6), &ok);
    *rest = slash + 1;
    return ok;
}

/* The listing's walk: the shared files, and the stretch of each curve. */
static int
visit(void *ctx, const char *name, size_t nlen, const lf_zip_entry *e, lf_error *err)
{
    jpk_state *st = ctx;
    const char *rest;
    long k = -2;
    (void) nlen;
    if (strcmp(name, "header.properties") == 0) {
        st->have_top = 1;
        st->top_e = *e;
    } else if (strcmp(name, "shared-data/header.properties") == 0) {
        st->have_shared = 1;
        st->shared_e = *e;
    } else if (curve_of_name(name, &k, &rest)) {
        st->have_segments |= k == -1;
        st->have_index |= k >= 0;
    } else {
        k = -2;
    }
    if (st->in_run && k == st->cur_k)
        return LF_OK;
    if (st->in_run) {
        jpk_run *r;
        if (st->nrun == st->cap) {
            size_t cap = st->cap ? 2 * st->cap : 64;
            if ((r = realloc(st->run, cap * sizeof *r)) == NULL)
                return lf_fail(err, LF_ENOMEM, "out of memory");
            st->run = r;
            st->cap = cap;
        }
        r = &st->run[st->nrun++];
        r->k = st->cur_k;
        r->start = st->cur_start;
        r->end = e->cdh;
        st->in_run = 0;
    }
    if (k >= -1) {
        st->in_run = 1;
        st->cur_k = k;
        st->cur_start = e->cdh;
    }
    return LF_OK;
}

/* Reading one curve: its entries, from its stretches of the directory. */
static int
visit_curve(void *ctx, const char *name, size_t nlen, const lf_zip_entry *e, lf_error *err)
{
    jpk_entries *c = ctx;
    const char *rest;
    long k;
    int status = LF_OK;
    (void) nlen;
    if (!curve_of_name(name, &k, &rest) || k != c->want)
        return LF_OK;
    if (k == -1)
        status = segment_entry(c, 0, rest + 9, e);
    else if (strcmp(rest, "header.properties") == 0)
        status = add_entry(c, k, 0, WHAT_HEADER, e);
    else if (strncmp(rest, "segments/", 9) == 0)
        status = segment_entry(c, k, rest + 9, e);
    return status == LF_OK ? LF_OK : lf_fail(err, status, "out of memory");
}

static int
cmp_entry(const void *a, const void *b)
{
    const jpk_entry *x = a, *y = b;
    if (x->seg != y->seg)
        return x->seg < y->seg ? -1 : 1;
    return x->what < y->what ? -1 : x->what > y->what;
}

static int
cmp_run(const void *a, const void *b)
{
    const jpk_run *x = a, *y = b;
    if (x->k != y->k)
        return x->k < y->k ? -1 : 1;
    return x->start < y->start ? -1 : x->start > y->start;
}

/* Inflate and parse one properties file of the archive. */
static int
load_props(const lf_src *src, const lf_zip_entry *e, const char *name, lf_props *p,
           lf_error *err)
{
    unsigned char *text;
    int status = lf_zip_extract(src, e, name, MAX_PROPS, &text, err);
    memset(p, 0, sizeof *p);
    if (status != LF_OK)
        return status;
    if (lf_props_parse(p, (const char *) text, (size_t) e->usize) != LF_OK)
        status = lf_fail_at(err, LF_ENOMEM, src->name, 0, 0, "out of memory");
    free(text);
    return status;
}

static void
jpk_close(lf_file *f)
{
    jpk_state *st = f->state;
    if (st == NULL)
        return;
    lf_props_free(&st->top);
    lf_props_free(&st->shared);
    free(st->run);
    free(st->first);
    free(st);
    f->state = NULL;
}

static int
jpk_open(lf_file *f, lf_warnings *warn, lf_error *err)
{
    jpk_state *st = calloc(1, sizeof *st);
    size_t i, n = 0, w = 0;
    uint64_t cd_end = 0;
    const char *v;
    int status;

    (void) warn;
    if (st == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    f->state = st;
    if ((status = lf_zip_scan(&f->src, visit, st, NULL, &cd_end, err)) != LF_OK) {
        if (err != NULL && err->file[0] == '\0')
            lf_fail_at(err, status, f->path, 0, 0, "%s", err->msg);
        return status;
    }
    if (st->in_run) {
        lf_zip_entry end;
        memset(&end, 0, sizeof end);
        end.cdh = cd_end;
        if ((status = visit(st, "", 0, &end, err)) != LF_OK)
            return status;
    }
    st->map = st->have_index;
    if (!st->map && !st->have_segments) {
        char what[1024];
        lf_describe_binary(&f->src, "PK\3\4", 4, what, sizeof what);
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "%s", what);
    }
    /* a map's curves are its index/K folders; a single curve is segments/ */
    for (i = 0; i < st->nrun; i++)
        if ((st->run[i].k >= 0) == st->map)
            st->run[w++] = st->run[i];
    st->nrun = w;
    qsort(st->run, st->nrun, sizeof *st->run, cmp_run);
    for (i = 0; i < st->nrun; i++)
        n += i == 0 || st->run[i].k != st->run[i - 1].k;
    if (n == 0)
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a JPK archive without curves (no "
                          "segment headers or channels)");
    if ((st->first = malloc((n + 1) * sizeof *st->first)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    for (i = 0, n = 0; i < st->nrun; i++)
        if (i == 0 || st->run[i].k != st->run[i - 1].k)
            st->first[n++] = i;
    st->first[n] = st->nrun;
    f->n = n;
    if (st->have_top && (status = load_props(&f->src, &st->top_e, "header.properties",
                                             &st->top, err)) != LF_OK)
        return status;
    if (st->have_shared && (status = load_props(&f->src, &st->shared_e,
                                                "shared-data/header.properties", &st->shared,
                                                err)) != LF_OK)
        return status;
    if (st->map) {
        st->grid_il = lf_whole(lf_number_or_nan(lf_props_suffix(
            &st->top, ".position-pattern.grid.ilength", NULL)), 1, 1000000, 0);
        st->grid_jl = lf_whole(lf_number_or_nan(lf_props_suffix(
            &st->top, ".position-pattern.grid.jlength", NULL)), 1, 1000000, 0);
        if (st->grid_il == 0 || st->grid_jl == 0)
            st->grid_il = st->grid_jl = 0;
        v = lf_props_suffix(&st->top, ".position-pattern.back-and-forth", NULL);
        st->back_and_forth = v != NULL && strcmp(v, "true") == 0;
    }
    return LF_OK;
}

/* ---------------------------------------------------------------------- */

static void
curve_free(jpk_curve *cv)
{
    size_t s;
    if (cv->own_head)
        lf_props_free(&cv->head);
    for (s = 0; s < cv->nseg; s++)
        lf_props_free(&cv->seg[s]);
    entries_free(&cv->col);
}

/* Parse curve i's header and segment headers. */
static int
curve_headers(const lf_file *f, size_t i, jpk_curve *cv, lf_error *err)
{
    const jpk_state *st = f->state;
    char name[128];
    size_t j;
    int status;

    memset(cv, 0, sizeof *cv);
    cv->st = st;
    cv->src = &f->src;
    cv->col.want = st->run[st->first[i]].k;
    for (j = st->first[i]; j < st->first[i + 1]; j++)
        if ((status = lf_zip_scan_range(&f->src, st->run[j].start, st->run[j].end, visit_curve,
                                        &cv->col, err)) != LF_OK) {
            curve_free(cv);
            return status;
        }
    if (cv->col.nent > 1)       /* none: no array to sort (qsort of NULL) */
        qsort(cv->col.ent, cv->col.nent, sizeof *cv->col.ent, cmp_entry);
    cv->ents = cv->col.ent;
    cv->nents = cv->col.nent;
    if (!st->map) {
        cv->head = st->top;     /* not owned */
    } else {
        for (j = 0; j < cv->nents && cv->ents[j].what != WHAT_HEADER; j++)
            ;
        if (j < cv->nents) {
            snprintf(name, sizeof name, "index/%ld/header.properties", cv->ents[j].k);
            if ((status = load_props(&f->src, &cv->ents[j].e, name, &cv->head, err)) != LF_OK) {
                curve_free(cv);
                return status;
            }
            cv->own_head = 1;
        }
    }
    for (j = 0; j < cv->nents; j++) {
        if (cv->ents[j].what != WHAT_SEGMENT)
            continue;
        if (cv->nseg == MAX_SEGMENTS)
            break;
        if (st->map)
            snprintf(name, sizeof name, "index/%ld/segments/%u/segment-header.properties",
                     cv->ents[j].k, (unsigned) cv->ents[j].seg);
        else
            snprintf(name, sizeof name, "segments/%u/segment-header.properties",
                     (unsigned) cv->ents[j].seg);
        cv->segno[cv->nseg] = cv->ents[j].seg;
        if ((status = load_props(&f->src, &cv->ents[j].e, name, &cv->seg[cv->nseg], err)) != LF_OK) {
            curve_free(cv);
            return status;
        }
        cv->nseg++;
    }
    if (cv->nseg == 0) {
        long k = cv->col.want;
        curve_free(cv);
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "curve %zu (%s%ld) has no "
                          "segment headers", i, st->map ? "index/" : "segments of ",
                          k < 0 ? 0 : k);
    }
    return LF_OK;
}

/* The parts (NULL-ended) joined into buf (n bytes), cut to fit: the keys
 * of a lookup, built for every channel of every curve, without printf. */
static const char *
join(char *buf, size_t n, const char *first, ...)
{
    va_list ap;
    const char *p;
    size_t w = 0;
    va_start(ap, first);
    for (p = first; p != NULL; p = va_arg(ap, const char *)) {
        size_t len = strlen(p);
        if (len > n - 1 - w)
            len = n - 1 - w;
        memcpy(buf + w, p, len);
        w += len;
    }
    va_end(ap);
    buf[w] = '\0';
    return buf;
}

/* A property of segment s, directly or through an indirection
 * ("PREFIX.MEDIATOR.*=N" for "MEDIATOR.N.REST" of the shared header). */
static const char *
seg_get(const jpk_curve *cv, size_t s, const char *key)
{
    char k[256];
    const char *v = lf_props_get(&cv->seg[s], key), *n;
    if (v != NULL)
        return v;
    if (strncmp(key, "force-segment-header.", 21) == 0) {
        n = lf_props_get(&cv->seg[s], "force-segment-header.force-segment-header-info.*");
        if (n != NULL) {
            join(k, sizeof k, "force-segment-header-info.", n, ".", key + 21, (char *) NULL);
            return lf_props_get(&cv->st->shared, k);
        }
    }
    return NULL;
}

/* A property of channel ch in segment s: channel.CH.SUFFIX,
 * channel.CH.data.SUFFIX (older files), or lcd-info.N.SUFFIX of the shared
 * header for channel.CH.lcd-info.*=N. */
static const char *
chan_get(const jpk_curve *cv, size_t s, const char *ch, const char *suffix)
{
    char k[256];
    const char *v, *n;
    join(k, sizeof k, "channel.", ch, ".", suffix, (char *) NULL);
    if ((v = lf_props_get(&cv->seg[s], k)) != NULL)
        return v;
    join(k, sizeof k, "channel.", ch, ".data.", suffix, (char *) NULL);
    if ((v = lf_props_get(&cv->seg[s], k)) != NULL)
        return v;
    join(k, sizeof k, "channel.", ch, ".lcd-info.*", (char *) NULL);
    if ((n = lf_props_get(&cv->seg[s], k)) != NULL) {
        join(k, sizeof k, "lcd-info.", n, ".", suffix, (char *) NULL);
        return lf_props_get(&cv->st->shared, k);
    }
    return NULL;
}

static double
chan_num(const jpk_curve *cv, size_t s, const char *ch, const char *suffix)
{
    return lf_number_or_nan(chan_get(cv, s, ch, suffix));
}

/* The segment's kind from its style (extend, pause, retract). */
static int
segment_kind(const jpk_curve *cv, size_t s, char *style, size_t n)
{
    const char *v = seg_get(cv, s, "force-segment-header.settings.style");
    if (v == NULL)
        v = seg_get(cv, s, "force-segment-header.settings.segment-settings.style");
    if (v == NULL)
        v = seg_get(cv, s, "force-segment-header.name.name");
    if (v == NULL) {        /* first extends, last retracts, between pauses */
        snprintf(style, n, "%s", s == 0 ? "extend" : s + 1 == cv->nseg ? "retract" : "pause");
        return s == 0 ? LF_SEG_LOAD : s + 1 == cv->nseg ? LF_SEG_UNLOAD : LF_SEG_HOLD;
    }
    snprintf(style, n, "%s", v);
    if (strstr(v, "extend") != NULL || strstr(v, "approach") != NULL)
        return LF_SEG_LOAD;
    if (strstr(v, "retract") != NULL)
        return LF_SEG_UNLOAD;
    return LF_SEG_HOLD;
}

/* The entry of channel ch in segment s, or NULL. */
static const lf_zip_entry *
channel_entry(const jpk_curve *cv, size_t s, const char *ch)
{
    size_t j;
    for (j = 0; j < cv->nents; j++)
        if (cv->ents[j].seg == cv->segno[s] && cv->ents[j].what < WHAT_SEGMENT
            && strcmp(cv->col.chan[cv->ents[j].what], ch) == 0)
            return &cv->ents[j].e;
    return NULL;
}

/* The points of segment s: its header's num-points. */
static size_t
segment_points(const jpk_curve *cv, size_t s)
{
    double v = lf_number_or_nan(seg_get(cv, s, "force-segment-header.num-points"));
    return v >= 0 && v < 1e12 ? (size_t) v : 0;
}

/* What curve cv states of itself: position, grid place, points. */
static void
curve_info(const jpk_curve *cv, lf_curve_info *info)
{
    const jpk_state *st = cv->st;
    char style[64];
    double idx;
    size_t s;

    info->x = lf_number_or_nan(lf_props_suffix(&cv->head, ".header.position.x", NULL));
    info->y = lf_number_or_nan(lf_props_suffix(&cv->head, ".header.position.y", NULL));
    idx = lf_number_or_nan(lf_props_suffix(&cv->head, ".header.position-index", NULL));
    if (st->grid_il > 0 && idx >= 0 && idx < (double) st->grid_il * (double) st->grid_jl) {
        long p = (long) idx;
        info->grid_i = p % st->grid_il;
        info->grid_j = p / st->grid_il;
        if (st->back_and_forth && info->grid_j % 2 == 1)
            info->grid_i = st->grid_il - 1 - info->grid_i;
    }
    for (s = 0; s < cv->nseg; s++) {
        size_t n = segment_points(cv, s);
        info->segment_points[segment_kind(cv, s, style, sizeof style)] += n;
        info->points += n;
    }
}

static int
jpk_info(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err)
{
    jpk_curve cv;
    int status;

    if ((status = curve_headers(f, i, &cv, err)) != LF_OK)
        return status;
    curve_info(&cv, info);
    curve_free(&cv);
    return LF_OK;
}

/* ---------------------------------------------------------------------- */

/* value = a * raw-scaled + b in slot, and its unit: the conversion set
 * climbed from slot down to the base. */
static int
slot_affine(const jpk_curve *cv, size_t s, const char *ch, const char *slot, double *a,
            double *b, char *unit, size_t nunit, int depth)
{
    char suffix[160];
    const char *base = chan_get(cv, s, ch, "conversion-set.conversions.base"), *v, *parent;
    double m, o;
    if (depth > 8)
        return -1;
    if (base == NULL || strcmp(slot, base) == 0) {
        v = chan_get(cv, s, ch, "encoder.scaling.unit.unit");
        if (v == NULL)
            v = chan_get(cv, s, ch, "unit.unit");
        snprintf(unit, nunit, "%s", v ? v : "");
        *a = 1.0;
        *b = 0.0;
        return base == NULL && strcmp(slot, "volts") != 0 ? -1 : 0;
    }
    join(suffix, sizeof suffix, "conversion-set.conversion.", slot, ".defined", (char *) NULL);
    v = chan_get(cv, s, ch, suffix);
    if (v == NULL || strcmp(v, "true") != 0)
        return -1;
    join(suffix, sizeof suffix, "conversion-set.conversion.", slot, ".scaling.multiplier", (char *) NULL);
    m = chan_num(cv, s, ch, suffix);
    join(suffix, sizeof suffix, "conversion-set.conversion.", slot, ".scaling.offset", (char *) NULL);
    o = chan_num(cv, s, ch, suffix);
    join(suffix, sizeof suffix, "conversion-set.conversion.", slot, ".base-calibration-slot", (char *) NULL);
    parent = chan_get(cv, s, ch, suffix);
    if (!isfinite(m) || parent == NULL)
        return -1;
    if (!isfinite(o))
        o = 0.0;
    if (slot_affine(cv, s, ch, parent, a, b, unit, nunit, depth + 1) != 0)
        return -1;
    *a *= m;
    *b = m * *b + o;
    join(suffix, sizeof suffix, "conversion-set.conversion.", slot, ".scaling.unit.unit", (char *) NULL);
    v = chan_get(cv, s, ch, suffix);
    if (v == NULL) {
        join(suffix, sizeof suffix, "conversion-set.conversion.", slot, ".scaling.unit", (char *) NULL);
        v = chan_get(cv, s, ch, suffix);
    }
    snprintf(unit, nunit, "%s", v ? v : "");
    return 0;
}

/* Channel ch of segment s decoded into out[0..n-1] in its base slot
 * (volts for most; the encoder's scaling applied). */
static int
read_channel(const jpk_curve *cv, size_t s, const char *ch, size_t n, double *out,
             const char *file, lf_error *err)
{
    const lf_zip_entry *e = channel_entry(cv, s, ch);
    const char *enc = chan_get(cv, s, ch, "encoder.type"), *type = chan_get(cv, s, ch, "type");
    double mult = chan_num(cv, s, ch, "encoder.scaling.multiplier");
    double off = chan_num(cv, s, ch, "encoder.scaling.offset");
    unsigned char *raw;
    size_t bytes, j;
    int kind, status;
    char name[96];

    snprintf(name, sizeof name, "channel %s of segment %u", ch, (unsigned) cv->segno[s]);
    if (e == NULL)
        return lf_fail_at(err, LF_EFORMAT, file, 0, 0, "%s is missing from the archive", name);
    if (enc == NULL && type == NULL)
        type = chan_get(cv, s, ch, "data.type");
    /* 1 i16, 2 u16, 3 i32, 4 u32, 5 i64, 6 f32, 7 f64 */
    kind = enc != NULL ? (strcmp(enc, "signedshort") == 0 ? 1 : strcmp(enc, "unsignedshort") == 0 ? 2
                          : strcmp(enc, "signedinteger") == 0 ? 3 : strcmp(enc, "unsignedinteger") == 0 ? 4
                          : strcmp(enc, "signedlong") == 0 ? 5 : 0)
         : type == NULL ? 0
         : (strstr(type, "float") != NULL ? 6 : strstr(type, "double") != NULL ? 7
            : strstr(type, "short") != NULL ? 1 : strstr(type, "integer") != NULL ? 3
            : strstr(type, "long") != NULL ? 5 : 0);
    if (kind == 0)
        return lf_fail_at(err, LF_EFORMAT, file, 0, 0, "%s: data type '%s' is not one "
                          "layerfit reads (signed or unsigned short or integer, long, float, "
                          "double)", name, enc ? enc : type ? type : "(none stated)");
    bytes = kind <= 2 ? 2 : kind == 3 || kind == 4 || kind == 6 ? 4 : 8;
    if (enc == NULL || !isfinite(mult)) {
        mult = 1.0;
        off = 0.0;
    }
    if (!isfinite(off))
        off = 0.0;
    if (e->usize / bytes < n)
        return lf_fail_at(err, LF_EFORMAT, file, 0, 0, "%s holds %llu values, its segment "
                          "header states %zu", name, (unsigned long long) (e->usize / bytes), n);
    if ((status = lf_zip_extract(cv->src, e, name, MAX_ENTRY, &raw, err)) != LF_OK)
        return status;
    for (j = 0; j < n; j++) {
        const unsigned char *p = raw + j * bytes;
        double v;
        switch (kind) {
        case 1: v = (double) (int16_t) lf_be16(p); break;
        case 2: v = (double) lf_be16(p); break;
        case 3: v = (double) (int32_t) lf_be32(p); break;
        case 4: v = (double) lf_be32(p); break;
        case 5: v = (double) (int64_t) ((uint64_t) lf_be32(p) << 32 | lf_be32(p + 4)); break;
        case 6: {
            uint32_t u = lf_be32(p);
            float x;
            memcpy(&x, &u, sizeof x);
            v = x;
            break;
        }
        default: {
            uint64_t u = (uint64_t) lf_be32(p) << 32 | lf_be32(p + 4);
            memcpy(&v, &u, sizeof v);
            break;
        }
        }
        out[j] = off + mult * v;
    }
    free(raw);
    return LF_OK;
}

/* The height channel of segment s and the slot it is read in. */
static const char *
height_channel(const jpk_curve *cv, size_t s, const char **slot)
{
    size_t h;
    for (h = 0; height_names[h] != NULL; h++) {
        const char *ch = height_names[h];
        if (channel_entry(cv, s, ch) == NULL)
            continue;
        if (strcmp(ch, "height") == 0 || strcmp(ch, "head-height") == 0) {
            const char *v = chan_get(cv, s, ch, "conversion-set.conversion.calibrated.defined");
            *slot = v != NULL && strcmp(v, "true") == 0 ? "calibrated" : "nominal";
        } else {
            *slot = "nominal";
        }
        return ch;
    }
    return NULL;
}

/* The constants of vDeflection in segment s as the file states them: the
 * distance conversion (sensitivity, m/V, with its offset) and the force
 * conversion (spring constant, N/m); NaN where undefined. */
static void
deflection_constants(const jpk_curve *cv, size_t s, double *sens, double *sens_off,
                     double *k, double *k_off, char *base_unit, size_t nunit)
{
    double a, b;
    char unit[32];
    const char *v;
    *sens = *sens_off = *k = *k_off = NAN;
    v = chan_get(cv, s, "vDeflection", "encoder.scaling.unit.unit");
    if (v == NULL)
        v = chan_get(cv, s, "vDeflection", "unit.unit");
    snprintf(base_unit, nunit, "%s", v ? v : "V");
    if (slot_affine(cv, s, "vDeflection", "distance", &a, &b, unit, sizeof unit, 0) == 0
        && strcmp(unit, "m") == 0 && a > 0) {
        *sens = a;
        *sens_off = b;
    }
    v = chan_get(cv, s, "vDeflection", "conversion-set.conversion.force.defined");
    if (v != NULL && strcmp(v, "true") == 0) {
        const char *base = chan_get(cv, s, "vDeflection",
                                    "conversion-set.conversion.force.base-calibration-slot");
        double m = chan_num(cv, s, "vDeflection", "conversion-set.conversion.force.scaling.multiplier");
        double o = chan_num(cv, s, "vDeflection", "conversion-set.conversion.force.scaling.offset");
        if (base != NULL && strcmp(base, "distance") == 0 && m > 0 && isfinite(m)) {
            *k = m;
            *k_off = isfinite(o) ? o : 0.0;
        }
    }
}

static void
add_meta_suffix(lf_curve *c, const lf_props *p, const char *suffix, const char *key)
{
    const char *v = lf_props_suffix(p, suffix, NULL);
    if (v != NULL && v[0] != '\0')
        lf_curve_add_meta(c, key, v);
}

static int
jpk_curve_read(const lf_file *f, size_t i, lf_curve *c, lf_warnings *warn, lf_error *err)
{
    const jpk_state *st = f->state;
    const lf_read_opts *o = &f->opts;
    lf_curve_info info;
    jpk_curve cv;
    double *h = NULL, *d = NULL, sens = NAN, sens_off = 0, k = NAN, k_off = 0, t0 = 0;
    size_t s, total = 0, m = 0, nseg[3] = { 0, 0, 0 };
    char style[64], used[160] = "", base_unit[16] = "V";
    int status, any_time = 1;

    if ((status = curve_headers(f, i, &cv, err)) != LF_OK)
        return status;
    memset(&info, 0, sizeof info);
    info.grid_i = info.grid_j = -1;
    curve_info(&cv, &info);
    c->x = info.x;
    c->y = info.y;
    c->grid_i = info.grid_i;
    c->grid_j = info.grid_j;
    add_meta_suffix(c, &cv.head, ".description.instrument", "instrument");
    add_meta_suffix(c, &cv.head, ".description.source-software", "software");
    add_meta_suffix(c, &cv.head, ".header.position-index", "position index");
    if (st->map) {
        char kbuf[32];
        snprintf(kbuf, sizeof kbuf, "%ld", cv.ents[0].k);
        lf_curve_add_meta(c, "archive folder", kbuf);
        add_meta_suffix(c, &st->top, ".position-pattern.grid.ilength", "grid columns");
        add_meta_suffix(c, &st->top, ".position-pattern.grid.jlength", "grid rows");
    }
    for (s = 0; s < cv.nseg; s++) {
        /* a count no channel could hold is a damaged header: said before
         * anything is allocated for it */
        const lf_zip_entry *e = channel_entry(&cv, s, "vDeflection");
        size_t n = segment_points(&cv, s);
        if (n > 0 && (e == NULL || n > e->usize / 2)) {
            curve_free(&cv);
            return lf_fail_at(err, LF_EFORMAT, c->file, 0, 0, "segment %u states %zu points, "
                              "its vDeflection channel holds %s", (unsigned) cv.segno[s], n,
                              e == NULL ? "none (it is missing)" : "fewer");
        }
        total += n;
    }
    if (total == 0 || lf_curve_reserve(c, total, 1) != 0) {
        curve_free(&cv);
        return total == 0 ? lf_fail_at(err, LF_EFORMAT, c->file, 0, 0, "no points: the segment "
                                       "headers state none (force-segment-header.num-points)")
                          : lf_fail_at(err, LF_ENOMEM, c->file, 0, 0, "out of memory");
    }
    for (s = 0; s < cv.nseg && status == LF_OK; s++) {
        size_t n = segment_points(&cv, s), j;
        const char *hch, *hslot = NULL;
        double ha, hb, da = NAN, db = 0, dur;
        char unit[32];
        int kind = segment_kind(&cv, s, style, sizeof style);
        if (n == 0)
            continue;
        if ((hch = height_channel(&cv, s, &hslot)) == NULL || channel_entry(&cv, s, "vDeflection") == NULL) {
            status = lf_fail_at(err, LF_EFORMAT, c->file, 0, 0, "segment %u (%s) has no %s "
                                "channel (expected vDeflection and one of measuredHeight, "
                                "capacitiveSensorHeight, strainGaugeHeight, height)",
                                (unsigned) cv.segno[s], style, hch == NULL ? "height" : "vDeflection");
            break;
        }
        if (slot_affine(&cv, s, hch, hslot, &ha, &hb, unit, sizeof unit, 0) != 0) {
            /* the slot preferred is not defined: nominal, else the base */
            const char *base = chan_get(&cv, s, hch, "conversion-set.conversions.base");
            hslot = "nominal";
            if (slot_affine(&cv, s, hch, hslot, &ha, &hb, unit, sizeof unit, 0) != 0) {
                hslot = base != NULL ? base : "volts";
                if (slot_affine(&cv, s, hch, hslot, &ha, &hb, unit, sizeof unit, 0) != 0)
                    unit[0] = '\0';
            }
        }
        if (strcmp(unit, "m") != 0) {
            status = lf_fail_at(err, LF_EUNIT, c->file, 0, 0, "%s of segment %u converts to "
                                "'%s', not to metres (its conversion set defines no length)",
                                hch, (unsigned) cv.segno[s], unit);
            break;
        }
        if (strstr(used, hch) == NULL)
            snprintf(used + strlen(used), sizeof used - strlen(used), "%s%s (%s)",
                     used[0] ? ", " : "", hch, hslot);
        /* the deflection's constants: the file's, else the options' */
        deflection_constants(&cv, s, &sens, &sens_off, &k, &k_off, base_unit, sizeof base_unit);
        if (strcmp(base_unit, "V") != 0) {
            status = lf_fail_at(err, LF_EUNIT, c->file, 0, 0, "vDeflection is recorded in '%s' "
                                "(layerfit reads it in volts)", base_unit);
            break;
        }
        if (isnan(c->sensitivity)
            && (status = lf_afm_sensitivity(c, sens, "vDeflection distance conversion", 0, o,
                                            err)) != LF_OK)
            break;
        if (isnan(c->spring_constant)
            && (status = lf_afm_spring_constant(c, k, "vDeflection force conversion", o,
                                                "to turn the deflection into a force", err)) != LF_OK)
            break;
        da = c->sensitivity;
        db = strcmp(c->sensitivity_source, "file header") == 0 ? sens_off : 0.0;
        if ((h == NULL && (h = malloc(total * sizeof *h)) == NULL)
            || (d == NULL && (d = malloc(total * sizeof *d)) == NULL)) {
            status = lf_fail_at(err, LF_ENOMEM, c->file, 0, 0, "out of memory");
            break;
        }
        if ((status = read_channel(&cv, s, hch, n, h, c->file, err)) != LF_OK
            || (status = read_channel(&cv, s, "vDeflection", n, d, c->file, err)) != LF_OK)
            break;
        dur = lf_number_or_nan(seg_get(&cv, s, "force-segment-header.duration"));
        if (!(dur >= 0))
            any_time = 0;
        for (j = 0; j < n; j++, m++) {
            double height = ha * h[j] + hb, defl = da * d[j] + db;
            double force = c->spring_constant * defl
                           + (strcmp(c->spring_constant_source, "file header") == 0 ? k_off : 0.0);
            c->depth[m] = -(height + defl);
            c->force[m] = force;
            c->time[m] = any_time ? t0 + dur * (double) j / (double) n : NAN;
            c->segment[m] = (unsigned char) kind;
            c->line[m] = (long) m + 1;      /* binary: the point's number */
        }
        t0 += isfinite(dur) ? dur : 0.0;
        nseg[kind] += n;
    }
    free(h);
    free(d);
    curve_free(&cv);
    if (status != LF_OK)
        return status;
    c->n = m;
    if (!any_time) {
        free(c->time);
        c->time = NULL;
    }
    lf_warn(&c->info, "archive: JPK %s, curve %zu of %zu", st->map ? "map (index/K folders)"
            : "single curve", i, f->n);
    lf_warn(&c->info, "force: vDeflection (%s) x sensitivity x k, through the file's "
            "conversion set", base_unit);
    lf_warn(&c->info, "depth: tip-sample separation = -(%s + deflection) (into the sample "
            "positive)", used);
    lf_warn(&c->info, "segments: from the segment headers (extend %zu, pause %zu, retract %zu "
            "points)", nseg[LF_SEG_LOAD], nseg[LF_SEG_HOLD], nseg[LF_SEG_UNLOAD]);
    return lf_curve_finish(c, warn, err);
}

static int
jpk_force_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
               lf_error *err)
{
    return lf_multi_read_one(&lf_multi_jpk_force, in, o, c, warn, err);
}

const lf_reader_type lf_reader_jpk_force = {
    "jpk-force", "JPK binary force file: .jpk-force, .jpk-force-map, .jpk-qi-data, "
    ".jpk-qi-series (a zip of properties files and channels; maps: one curve per index)",
    jpk_sniff, jpk_force_read
};

const lf_multi_reader lf_multi_jpk_force = {
    &lf_reader_jpk_force, jpk_open, jpk_info, jpk_curve_read, jpk_close
};
