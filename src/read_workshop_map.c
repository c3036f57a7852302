/* read_workshop_map.c: AFM Workshop force maps, as a zip archive of the
 * single-curve CSV files the software writes for each point of a map
 * ("Mode: Mapping", "Point: N", "X, um:", "Y, um:" in each header; see
 * read_workshop.c for one file).  The curves are the archive's CSV files
 * in the order of their names; each is read by the workshop reader when
 * it is asked for, its position from its own header. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

#define MAX_MEMBER (256u << 20)

typedef struct {
    char *name;
    lf_zip_entry e;
} ws_member;

typedef struct {
    ws_member *m;
    size_t n, cap;
} ws_state;

static int
ends_with_csv(const char *name, size_t n)
{
    return n > 4 && (memcmp(name + n - 4, ".csv", 4) == 0 || memcmp(name + n - 4, ".CSV", 4) == 0);
}

static int
wsm_sniff(const char *head, size_t len)
{
    size_t i, nlen;
    if (!lf_zip_magic(head, len))
        return 0;
    /* a CSV file among the first entries (a folder may come first) */
    for (i = 0; i + 30 < len; i++)
        if (memcmp(head + i, "PK\3\4", 4) == 0) {
            nlen = lf_le16((const unsigned char *) head + i + 26);
            if (i + 30 + nlen <= len && ends_with_csv(head + i + 30, nlen))
                return 60;
        }
    return 0;
}

static int
visit(void *ctx, const char *name, size_t nlen, const lf_zip_entry *e, lf_error *err)
{
    ws_state *st = ctx;
    if (!ends_with_csv(name, nlen) || strncmp(name, "__MACOSX/", 9) == 0)
        return LF_OK;
    if (st->n == st->cap) {
        size_t cap = st->cap ? 2 * st->cap : 64;
        ws_member *m = realloc(st->m, cap * sizeof *m);
        if (m == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        st->m = m;
        st->cap = cap;
    }
    if ((st->m[st->n].name = lf_strdup(name)) == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    st->m[st->n].e = *e;
    st->n++;
    return LF_OK;
}

static int
cmp_member(const void *a, const void *b)
{
    return strcmp(((const ws_member *) a)->name, ((const ws_member *) b)->name);
}

static void
wsm_close(lf_file *f)
{
    ws_state *st = f->state;
    size_t i;
    if (st == NULL)
        return;
    for (i = 0; i < st->n; i++)
        free(st->m[i].name);
    free(st->m);
    free(st);
    f->state = NULL;
}

/* Member i inflated (text, NUL-terminated). */
static int
member_text(const lf_file *f, size_t i, char **text, size_t *len, lf_error *err)
{
    const ws_state *st = f->state;
    unsigned char *buf, *t;
    int status = lf_zip_extract(&f->src, &st->m[i].e, st->m[i].name, MAX_MEMBER, &buf, err);
    if (status != LF_OK)
        return status;
    if ((t = realloc(buf, (size_t) st->m[i].e.usize + 1)) == NULL) {
        free(buf);
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    }
    t[st->m[i].e.usize] = '\0';
    *text = (char *) t;
    *len = (size_t) st->m[i].e.usize;
    return LF_OK;
}

static int
wsm_open(lf_file *f, lf_warnings *warn, lf_error *err)
{
    ws_state *st = calloc(1, sizeof *st);
    char *text, what[400];
    size_t len;
    int status;

    (void) warn;
    if (st == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    f->state = st;
    if ((status = lf_zip_scan(&f->src, visit, st, NULL, NULL, err)) != LF_OK) {
        if (err != NULL && err->file[0] == '\0')
            lf_fail_at(err, status, f->path, 0, 0, "%s", err->msg);
        return status;
    }
    if (st->n == 0) {
        if (lf_zip_describe(&f->src, what, sizeof what, err) != LF_OK)
            return err->status;
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a zip archive without CSV files: "
                          "not an AFM Workshop map (it holds %s)", what);
    }
    qsort(st->m, st->n, sizeof *st->m, cmp_member);
    /* the first member says whether these are AFM Workshop curves */
    if ((status = member_text(f, 0, &text, &len, err)) != LF_OK)
        return status;
    if (strstr(text, "Force-Distance Curve") == NULL && strstr(text, "Extend Z-Sense") == NULL) {
        free(text);
        if (lf_zip_describe(&f->src, what, sizeof what, err) != LF_OK)
            return err->status;
        return lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "a zip archive of CSV files that are "
                          "not AFM Workshop force-distance curves (no 'Force-Distance Curve' "
                          "header in %s); layerfit reads JPK archives and AFM Workshop mapping "
                          "zips; this one holds %s", st->m[0].name, what);
    }
    free(text);
    f->n = st->n;
    return LF_OK;
}

static int
wsm_info(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err)
{
    char *text, *p;
    size_t len, rows = 0;
    int in_table = 0, status;

    if ((status = member_text(f, i, &text, &len, err)) != LF_OK)
        return status;
    for (p = text; p != NULL && *p; ) {
        char *eol = p + strcspn(p, "\r\n"), end = *eol;
        *eol = '\0';
        if (strncmp(p, "X, um:", 6) == 0)
            info->x = 1e-6 * lf_number_or_nan(p + 6);
        else if (strncmp(p, "Y, um:", 6) == 0)
            info->y = 1e-6 * lf_number_or_nan(p + 6);
        else if (strstr(p, "Z-Sense") != NULL && p < eol)
            in_table = 1;
        else if (in_table && eol > p && (*p == '-' || (*p >= '0' && *p <= '9')))
            rows++;
        if (end == '\0')
            break;
        p = eol + 1;
        p += strspn(p, "\r\n");
    }
    free(text);
    if (isnan(info->x) || isnan(info->y))
        info->x = info->y = NAN;
    info->points = 2 * rows;
    info->segment_points[LF_SEG_LOAD] = rows;
    info->segment_points[LF_SEG_UNLOAD] = rows;
    return LF_OK;
}

static int
wsm_curve(const lf_file *f, size_t i, lf_curve *c, lf_warnings *warn, lf_error *err)
{
    const ws_state *st = f->state;
    char *text = NULL, name[4400];
    lf_source in;
    size_t len = 0;
    int status;

    if ((status = member_text(f, i, &text, &len, err)) != LF_OK)
        return status;
    snprintf(name, sizeof name, "%s (%s)", c->file, st->m[i].name);
    in.buf = text;
    in.len = len;
    in.chunk = 0;
    in.name = name;
    status = lf_reader_workshop.read(&in, &f->opts, c, warn, err);
    free(text);
    if (status == LF_OK)
        lf_warn(&c->info, "archive: AFM Workshop map, curve %zu of %zu: %s", i, f->n,
                st->m[i].name);
    return status;
}

static int
wsm_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
         lf_error *err)
{
    return lf_multi_read_one(&lf_multi_workshop_map, in, o, c, warn, err);
}

const lf_reader_type lf_reader_workshop_map = {
    "workshop-map", "AFM Workshop force map: a zip of its force-distance CSV files (one "
    "curve each, with X, um and Y, um)",
    wsm_sniff, wsm_read
};

const lf_multi_reader lf_multi_workshop_map = {
    &lf_reader_workshop_map, wsm_open, wsm_info, wsm_curve, wsm_close
};
