/* table.c: a CSV table read whole, every cell as text (layerfit.h,
 * lf_table), through the line and record layer of the readers
 * (csvsplit.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "csvsplit.h"

typedef struct {
    lf_table *t;
    size_t cap;
} table_reader;

static int
table_record(void *ctx, const lf_csv_record *r, lf_error *err)
{
    table_reader *rd = ctx;
    lf_table *t = rd->t;
    size_t i, at;

    if (r->index == 0) {
        t->header_line = r->line;
        t->ncols = r->n;
        t->names = calloc(r->n ? r->n : 1, sizeof *t->names);
        if (t->names == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        for (i = 0; i < r->n; i++)
            if ((t->names[i] = lf_strdup(r->text[i])) == NULL)
                return lf_fail(err, LF_ENOMEM, "out of memory");
        return LF_OK;
    }
    if (t->nrows == rd->cap) {
        size_t cap = rd->cap ? 2 * rd->cap : 256;
        char **cells = realloc(t->cells, cap * (t->ncols ? t->ncols : 1) * sizeof *cells);
        long *line, *col;
        if (cells == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        t->cells = cells;
        line = realloc(t->line, cap * sizeof *line);
        if (line == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        t->line = line;
        col = realloc(t->col, cap * (t->ncols ? t->ncols : 1) * sizeof *col);
        if (col == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        t->col = col;
        rd->cap = cap;
    }
    at = t->nrows * t->ncols;
    for (i = 0; i < t->ncols; i++) {
        t->cells[at + i] = lf_strdup(i < r->n ? r->text[i] : "");
        t->col[at + i] = i < r->n ? r->fcol[i] : 0;
        if (t->cells[at + i] == NULL) {
            size_t k;
            for (k = 0; k < i; k++)
                free(t->cells[at + k]);
            return lf_fail(err, LF_ENOMEM, "out of memory");
        }
    }
    t->line[t->nrows++] = r->line;
    return LF_OK;
}

void
lf_table_free(lf_table *t)
{
    size_t i;

    if (t == NULL)
        return;
    for (i = 0; t->names != NULL && i < t->ncols; i++)
        free(t->names[i]);
    for (i = 0; t->cells != NULL && i < t->nrows * t->ncols; i++)
        free(t->cells[i]);
    free(t->names);
    free(t->cells);
    free(t->line);
    free(t->col);
    free(t);
}

int
lf_table_read(const char *path, lf_table **out, lf_error *err)
{
    table_reader rd;
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    int status;

    *out = NULL;
    rd.t = calloc(1, sizeof *rd.t);
    rd.cap = 0;
    if (rd.t == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    h.ctx = &rd;
    h.record = table_record;
    h.comment = NULL;
    h.line = NULL;
    status = lf_csv_read_file(path, &h, err);
    if (status != LF_OK) {
        lf_table_free(rd.t);
        return status;
    }
    *out = rd.t;
    return LF_OK;
}

long
lf_table_column(const lf_table *t, const char *name)
{
    size_t i;
    for (i = 0; i < t->ncols; i++)
        if (strcmp(t->names[i], name) == 0)
            return (long) i;
    return -1;
}

int
lf_table_number(const char *cell, double *v)
{
    *v = NAN;
    if (lf_csv_number(cell, 0, v) == LF_NUM_BAD) {
        *v = NAN;
        return LF_EFORMAT;
    }
    return LF_OK;
}
