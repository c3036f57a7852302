/* read_table.c: delimited numeric tables in instrument text exports, whose
 * column header is not on line 1 (see readers.h, lf_text_table_read).  Lines
 * arrive one at a time from the line layer (src/csvsplit.c, raw line mode),
 * so any chunking of the input gives the same table. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

static int
is_blank(char c)
{
    return c == ' ' || c == '\t';
}

size_t
lf_split_cells(char *text, char delim, char **cells, long *cols, size_t max)
{
    size_t n = 0;
    char *p = text;
    long col = 1;

    if (max == 0)
        return 0;
    if (delim == ' ') {
        for (;;) {
            while (is_blank(*p)) {
                p++;
                col++;
            }
            if (*p == '\0')
                break;
            if (n + 1 == max) {           /* the rest, trimmed */
                char *e = p + strlen(p);
                while (e > p && is_blank(e[-1]))
                    *--e = '\0';
                if (cols)
                    cols[n] = col;
                cells[n++] = p;
                break;
            }
            if (cols)
                cols[n] = col;
            cells[n++] = p;
            while (*p != '\0' && !is_blank(*p)) {
                if (((unsigned char) *p & 0xC0) != 0x80)
                    col++;
                p++;
            }
            if (*p == '\0')
                break;
            *p++ = '\0';
            col++;
        }
        return n;
    }
    for (;;) {
        char *end = n + 1 == max ? NULL : strchr(p, delim), *b = p, *e;
        long c0 = col;
        if (end != NULL)
            *end = '\0';
        while (is_blank(*b)) {
            b++;
            c0++;
        }
        e = b + strlen(b);
        while (e > b && is_blank(e[-1]))
            *--e = '\0';
        if (cols)
            cols[n] = c0;
        cells[n++] = b;
        if (end == NULL)
            break;
        for (; p < end; p++)
            if (((unsigned char) *p & 0xC0) != 0x80)
                col++;
        p = end + 1;
        col++;
    }
    return n;
}

/* Whether every cell of a row is a number; empty trailing cells are cut
 * off first (*n updated). */
static int
all_numbers(char **cells, size_t *n, int decimal_comma)
{
    size_t i;
    double v;
    while (*n > 0 && cells[*n - 1][0] == '\0')
        (*n)--;
    if (*n == 0)
        return 0;
    for (i = 0; i < *n; i++)
        if (lf_csv_number(cells[i], decimal_comma, &v) != LF_NUM_OK)
            return 0;
    return 1;
}

/* The delimiter of a numeric row and its cell count, or 0. */
static char
numeric_delim(const char *line, size_t *ncells, int *decimal_comma)
{
    static const char order[] = { '\t', ';', ',', ' ' };
    char *copy = lf_strdup(line), *cells[LF_TEXT_TABLE_MAX_COLS + 1];
    size_t k;
    char found = 0;

    if (copy == NULL)
        return 0;
    for (k = 0; k < sizeof order && !found; k++) {
        size_t n;
        if (order[k] != ' ' && strchr(line, order[k]) == NULL)
            continue;
        strcpy(copy, line);
        n = lf_split_cells(copy, order[k], cells, NULL, LF_TEXT_TABLE_MAX_COLS + 1);
        if (n > LF_TEXT_TABLE_MAX_COLS)
            continue;
        if (all_numbers(cells, &n, order[k] != ',') && n >= 2) {
            size_t i;
            found = order[k];
            *ncells = n;
            *decimal_comma = 0;
            for (i = 0; i < n && order[k] != ','; i++)
                if (strchr(cells[i], ',') != NULL)
                    *decimal_comma = 1;
        }
    }
    free(copy);
    return found;
}

/* A text line above the table: Key<TAB>value, "Key: value" or
 * "Key = value" (or a lone key) into the curve's metadata. */
static int
add_meta_line(lf_text_table *t, char *text)
{
    char *b = text, *sep, *key, *value;
    size_t n;

    while (is_blank(*b))
        b++;
    n = strlen(b);
    while (n > 0 && is_blank(b[n - 1]))
        b[--n] = '\0';
    if (n == 0)
        return 0;
    if ((sep = strchr(b, '\t')) != NULL) {
        *sep = '\0';
        value = sep + 1;
    } else if ((sep = strstr(b, ": ")) != NULL || (sep = strstr(b, " = ")) != NULL) {
        *sep = '\0';
        value = sep + 2;
    } else {
        value = b + n;
    }
    key = b;
    n = strlen(key);
    while (n > 0 && (is_blank(key[n - 1]) || key[n - 1] == ':' || key[n - 1] == '='))
        key[--n] = '\0';
    while (is_blank(*value) || *value == '=')
        value++;
    for (sep = value; *sep; sep++)   /* further cells joined by a space */
        if (*sep == '\t')
            *sep = ' ';
    if (key[0] == '\0')
        return 0;
    return lf_curve_add_meta(t->c, key, value);
}

static int
grow(lf_text_table *t)
{
    size_t cap = t->cap ? 2 * t->cap : 1024, j;
    void *p;
    for (j = 0; j < t->ncol; j++) {
        if ((p = realloc(t->col[j], cap * sizeof *t->col[j])) == NULL)
            return -1;
        t->col[j] = p;
    }
    if ((p = realloc(t->line, cap * sizeof *t->line)) == NULL)
        return -1;
    t->line = p;
    t->cap = cap;
    return 0;
}

static int
set_header(lf_text_table *t, char *text, long line, size_t ncells, lf_error *err)
{
    char *cells[LF_TEXT_TABLE_MAX_COLS + 1];
    size_t n, j;

    t->ncol = ncells;
    t->header_line = line;
    if (text == NULL) {
        for (j = 0; j < ncells; j++) {
            snprintf(t->name[j], sizeof t->name[j], "column %zu", j + 1);
            t->cell[j][0] = t->unit[j][0] = '\0';
        }
        return LF_OK;
    }
    n = lf_split_cells(text, t->delim, cells, NULL, LF_TEXT_TABLE_MAX_COLS + 1);
    for (j = 0; j < ncells; j++) {
        char name[96];
        lf_latin1_to_utf8(j < n ? cells[j] : "", t->cell[j], sizeof t->cell[j]);
        lf_csv_header_cell(t->cell[j], name, sizeof name, t->unit[j], sizeof t->unit[j]);
        strcpy(t->name[j], name);
    }
    (void) err;
    return LF_OK;
}

/* Is text a header for rows of ncells cells split at delim? */
static int
header_fits(const char *text, char delim, size_t ncells)
{
    char *copy = lf_strdup(text), *cells[LF_TEXT_TABLE_MAX_COLS + 1];
    size_t n, i;
    int ok = 0;
    double v;
    if (copy == NULL)
        return 0;
    n = lf_split_cells(copy, delim, cells, NULL, LF_TEXT_TABLE_MAX_COLS + 1);
    while (n > ncells && cells[n - 1][0] == '\0')
        n--;
    if (n == ncells) {
        ok = 1;
        for (i = 0; i < n; i++)      /* names, not numbers; none empty */
            if (cells[i][0] == '\0' || lf_csv_number(cells[i], 1, &v) == LF_NUM_OK)
                ok = 0;
    }
    free(copy);
    return ok;
}

static int
data_row(lf_text_table *t, char *text, long line, lf_error *err)
{
    char *cells[LF_TEXT_TABLE_MAX_COLS + 1], buf[64];
    long cols[LF_TEXT_TABLE_MAX_COLS + 1];
    size_t n, j;

    n = lf_split_cells(text, t->delim, cells, cols, LF_TEXT_TABLE_MAX_COLS + 1);
    while (n > t->ncol && cells[n - 1][0] == '\0')
        n--;
    if (n != t->ncol) {
        if (t->skip_bad_rows && n < t->ncol) {
            if (t->skipped++ == 0)
                t->first_skipped = line;
            return LF_OK;
        }
        return lf_fail_at(err, LF_EFORMAT, t->name_file, line,
                          n > 0 ? cols[n < t->ncol ? n - 1 : t->ncol] : 1,
                          "row has %zu cell%s, the table %zu%s", n, n == 1 ? "" : "s",
                          t->ncol, n < t->ncol ? " (--skip-bad-rows skips such rows)" : "");
    }
    if (t->n == t->cap && grow(t) != 0)
        return lf_fail_at(err, LF_ENOMEM, t->name_file, line, 0, "out of memory");
    for (j = 0; j < n; j++) {
        double v;
        int st = lf_csv_number(cells[j], t->decimal_comma, &v);
        if (st == LF_NUM_EMPTY && t->skip_bad_rows) {
            if (t->skipped++ == 0)
                t->first_skipped = line;
            return LF_OK;
        }
        if (st != LF_NUM_OK)
            return lf_fail_at(err, LF_EFORMAT, t->name_file, line, cols[j],
                              "%s '%s' is not %s (expected a decimal number such as %s)",
                              t->name[j], lf_csv_excerpt(cells[j], buf, sizeof buf),
                              st == LF_NUM_NONFINITE ? "a finite number" : "a number",
                              t->decimal_comma ? "12,5" : "12.5");
        t->col[j][t->n] = v;
    }
    t->line[t->n++] = line;
    return LF_OK;
}

static int
on_line(void *ctx, long line, char *text, size_t len, lf_error *err)
{
    lf_text_table *t = ctx;
    size_t ncells, i;
    int dc;
    char d;

    for (i = 0; i < len && is_blank(text[i]); i++)
        ;
    if (i == len) {                      /* blank: no header across it */
        if (!t->in_data && t->pending != NULL) {
            int st = add_meta_line(t, t->pending);
            free(t->pending);
            t->pending = NULL;
            if (st != 0)
                return lf_fail_at(err, LF_ENOMEM, t->name_file, line, 0, "out of memory");
        }
        return LF_OK;
    }
    if (t->in_data)
        return data_row(t, text, line, err);
    d = numeric_delim(text, &ncells, &dc);
    if (d != 0 && (t->no_header || (t->pending != NULL
                                    && header_fits(t->pending, d, ncells)))) {
        t->delim = d;
        t->decimal_comma = dc;
        set_header(t, t->no_header ? NULL : t->pending, t->no_header ? 0 : t->pending_line,
                   ncells, err);
        free(t->pending);
        t->pending = NULL;
        t->in_data = 1;
        return data_row(t, text, line, err);
    }
    if (d != 0 && t->no_header)
        return LF_OK;
    if (d != 0)
        return lf_fail_at(err, LF_EFORMAT, t->name_file, line, 1,
                          "a row of numbers before any row naming the columns (expected "
                          "a header such as 'Depth (nm)<TAB>Load (uN)' just above the data)");
    if (t->pending != NULL) {
        int st = add_meta_line(t, t->pending);
        free(t->pending);
        t->pending = NULL;
        if (st != 0)
            return lf_fail_at(err, LF_ENOMEM, t->name_file, line, 0, "out of memory");
    }
    if (t->no_header)
        return lf_fail_at(err, LF_EFORMAT, t->name_file, line, 1,
                          "text where numbers were expected (this format has no header: "
                          "every line is a row of numbers)");
    t->pending = lf_strdup(text);
    t->pending_line = line;
    if (t->pending == NULL)
        return lf_fail_at(err, LF_ENOMEM, t->name_file, line, 0, "out of memory");
    return LF_OK;
}

int
lf_text_table_read(lf_text_table *t, const lf_source *in, lf_curve *c, lf_error *err)
{
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    int status;

    t->c = c;
    t->name_file = in->name;
    h.ctx = t;
    h.record = NULL;
    h.comment = NULL;
    h.line = on_line;
    status = lf_csv_read_input(in, &h, err);
    if (status == LF_OK && t->pending != NULL && add_meta_line(t, t->pending) != 0)
        status = lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
    free(t->pending);
    t->pending = NULL;
    if (status == LF_OK && !t->in_data)
        status = lf_fail_at(err, LF_EFORMAT, in->name, 0, 0,
                            "no table found (expected a row naming the columns, "
                            "e.g. 'Depth (nm)<TAB>Load (uN)', followed by rows of numbers)");
    return status;
}

void
lf_text_table_free(lf_text_table *t)
{
    size_t j;
    for (j = 0; j < LF_TEXT_TABLE_MAX_COLS; j++)
        free(t->col[j]);
    free(t->line);
    free(t->pending);
    memset(t, 0, sizeof *t);
}

static int
prefix_ieq(const char *a, const char *b, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (tolower((unsigned char) a[i]) != tolower((unsigned char) b[i]))
            return 0;
    return 1;
}

int
lf_text_table_find(const lf_text_table *t, const char *const *names, int prefix)
{
    size_t j, i;
    for (j = 0; j < t->ncol; j++)
        for (i = 0; names[i] != NULL; i++) {
            size_t n = strlen(names[i]);
            if (prefix ? strlen(t->name[j]) >= n && prefix_ieq(t->name[j], names[i], n)
                       : lf_csv_ieq(t->name[j], names[i]))
                return (int) j;
        }
    return -1;
}

int
lf_text_table_factor(const lf_text_table *t, int j, lf_quantity q, double *factor, lf_error *err)
{
    lf_error e;
    if (lf_units_factor(t->unit[j], q, factor, &e) != LF_OK)
        return lf_fail_at(err, e.status, t->name_file, t->header_line, 0,
                          "column '%s': %s", t->cell[j], e.msg);
    return LF_OK;
}

int
lf_text_table_finish(lf_text_table *t, lf_curve *c, lf_warnings *warn, lf_error *err)
{
    int status;
    if (t->skipped > 0)
        lf_warn(warn, "%s:%ld: skipped %ld row%s with missing cells (first here)",
                t->name_file, t->first_skipped, t->skipped, t->skipped == 1 ? "" : "s");
    status = lf_curve_finish(c, warn, err);
    lf_text_table_free(t);
    return status;
}

const char *
lf_sniff_text(const char *head, size_t len, char *buf, size_t n)
{
    size_t m = len < n - 1 ? len : n - 1;
    memcpy(buf, head, m);
    buf[m] = '\0';
    return buf;
}
