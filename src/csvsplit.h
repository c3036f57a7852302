/* csvsplit.h: the line and record layer shared by the curve and plan
 * readers (internal, not installed).
 *
 * Input arrives in blocks of any size.  It is cut into physical lines (LF,
 * CRLF or CR), each at most LF_CSV_MAX_LINE bytes, so memory stays bounded
 * by one line whatever the file size.  A UTF-8 byte order mark is dropped,
 * blank lines are skipped, lines whose first non-blank character is '#' go
 * to the comment callback, and the first other line is the header: the
 * delimiter (tab, ';' or ',') is taken from it.  Header and data lines go
 * through libcsv in strict mode (CSV_APPEND_NULL); a quoted field may span
 * lines.  Each complete record goes to the record callback with the line and
 * column (in characters, 1-based) where each field starts. */
#ifndef LF_CSVSPLIT_H
#define LF_CSVSPLIT_H

#include <stdio.h>

#include "internal.h"

#define LF_CSV_MAX_LINE (1024L * 1024L)   /* bytes in a line, or in a record */
#define LF_CSV_STOP (-1)  /* returned by a callback: stop reading, no error */

typedef struct {
    long index;      /* 0 for the header, then 1, 2, ... */
    long line;       /* line where the record starts */
    size_t n;        /* number of fields */
    char **text;     /* NUL-terminated; blanks around an unquoted field
                        removed, a quoted field kept byte for byte */
    const long *fline, *fcol;   /* where each field starts */
    char delim;      /* ',', ';' or '\t' */
} lf_csv_record;

/* What the caller does with records and comments.  A callback returns LF_OK
 * to go on, LF_CSV_STOP to end the reading early (the reader then returns
 * LF_OK), or a status after filling err. */
typedef struct {
    void *ctx;
    int (*record)(void *ctx, const lf_csv_record *r, lf_error *err);
    /* text after the '#', trimmed; before_header is 1 until the header */
    int (*comment)(void *ctx, long line, const char *text, int before_header,
                   lf_error *err);
    /* Raw line mode (the instrument readers): when not NULL, every physical
     * line (a UTF-8 byte order mark dropped, blank lines included, NUL-
     * terminated, writable) goes here instead, and record and comment are
     * never called. */
    int (*line)(void *ctx, long line, char *text, size_t n, lf_error *err);
} lf_csv_handler;

/* Read the file at path in blocks.  Messages name the file by path. */
int lf_csv_read_file(const char *path, const lf_csv_handler *h, lf_error *err);
/* Read buf[0..len-1], handed over in pieces of chunk bytes (0 = at once). */
int lf_csv_read_buffer(const char *buf, size_t len, size_t chunk,
                       const char *name, const lf_csv_handler *h, lf_error *err);
/* lf_csv_read_buffer on a reader's source. */
int lf_csv_read_input(const lf_source *in, const lf_csv_handler *h, lf_error *err);

/* Split a header cell into a name and a unit: "depth_nm", "Depth (nm)",
 * "Indentation [um]", "depth / nm" give ("depth"|"Depth"|..., "nm"); a cell
 * without a unit gives an empty unit.  µ (U+00B5), μ (U+03BC) and a Latin-1
 * 0xB5 byte in the unit are spelled 'u'.  Output is truncated to fit. */
void lf_csv_header_cell(const char *cell, char *name, size_t nname,
                        char *unit, size_t nunit);

/* The segment a word names (load, loading, approach, extend / hold,
 * holding, pause, dwell / unload, unloading, retract, withdraw; any case),
 * or -1. */
int lf_csv_segment_word(const char *word);

/* Case-insensitive ASCII equality. */
int lf_csv_ieq(const char *a, const char *b);

/* Parse a plain decimal number (digits, sign, '.', exponent; with
 * decimal_comma a single ',' stands for '.').  Returns one of: */
enum { LF_NUM_OK, LF_NUM_EMPTY, LF_NUM_BAD, LF_NUM_NONFINITE };
int lf_csv_number(const char *text, int decimal_comma, double *value);

/* With decimal_comma, replace the only ',' of text (when it has no '.')
 * with '.', in place. */
void lf_csv_decimal_point(char *text, int decimal_comma);

/* Whether all cells of a record are valid UTF-8 text (a header that is
 * not is most likely binary data). */
int lf_csv_is_text(const lf_csv_record *r);

/* One column a table's header may name (a plan's, a design plan's): its
 * name, the quantity of its numbers (LF_Q_DIMENSIONLESS: plain numbers or
 * text), whether the header must name it, and, for a quantity whose unit
 * goes in each cell rather than the header, what to write there. */
typedef struct {
    const char *name;
    lf_quantity q;
    int required;
    const char *unit_in_cells;    /* NULL: a unit in the header is taken */
} lf_csv_column;

/* Map header record r of file onto cols[0..ncols-1]: col[c] the field of
 * column c (-1 when absent), factor[c] the factor of its header unit to
 * SI (1 without one), has_unit[c] whether it had one.  A whole cell that
 * names a column has no unit ("delta_max" is not delta in the unit
 * "max"); other cells are split by lf_csv_header_cell.  hint lists the
 * columns, for messages.  LF_OK, or a message with the cell's place. */
int lf_csv_columns(const char *file, const lf_csv_record *r, const lf_csv_column *cols,
                   int ncols, const char *hint, long *col, double *factor, int *has_unit,
                   lf_error *err);

/* A table row of record r against a header of ncols columns: empty cells
 * past the header's width are ignored, otherwise the count must match.
 * LF_OK, or a message with the place. */
int lf_csv_row_cells(const char *file, const lf_csv_record *r, size_t ncols, lf_error *err);

/* The interface word in cell k of record r (frictionless or bonded, any
 * case) into *base; LF_OK, or a message with the cell's place. */
int lf_csv_cell_interface(const char *file, const lf_csv_record *r, long k, lf_base *base,
                          lf_error *err);

/* The number in the non-empty cell k of record r, of column col, in SI: a
 * bare number in the header's unit (has_unit: factor) or of a pure number,
 * else a number with its own unit ("1.5mm").  LF_OK, or a message with
 * the cell's place. */
int lf_csv_cell_number(const char *file, const lf_csv_record *r, long k,
                       const lf_csv_column *col, int has_unit, double factor,
                       int decimal_comma, double *v, lf_error *err);

/* A table whose header names its columns (a fit plan, a design plan:
 * plan.c): the columns it may have and, once its header is read, where
 * each sits and the factor of its header unit.  The readers fill file,
 * cols, ncol and hint and zero the rest. */
#define LF_CSV_MAX_COLUMNS 24
typedef struct {
    const char *file;           /* for messages */
    const lf_csv_column *cols;  /* ncol (at most LF_CSV_MAX_COLUMNS) */
    int ncol;
    const char *hint;           /* the columns, for messages */
    int have_header;
    long header_line;
    size_t ncells;              /* the header's cells */
    long col[LF_CSV_MAX_COLUMNS];
    int has_unit[LF_CSV_MAX_COLUMNS];
    double factor[LF_CSV_MAX_COLUMNS];
    int decimal_comma;          /* ';' separates the cells */
} lf_csv_table;

/* Read header record r into t (lf_csv_columns). */
int lf_csv_table_header(lf_csv_table *t, const lf_csv_record *r, lf_error *err);
/* Column c's cell of row r as a number in SI: NaN when the column is
 * absent, or when the cell is empty or "nan" and empty_ok; an empty cell
 * otherwise fails ("every row needs ...").  LF_OK, or a message with the
 * cell's place. */
int lf_csv_table_number(const lf_csv_table *t, const lf_csv_record *r, int c, int empty_ok,
                        double *v, lf_error *err);
/* Read a table from path (buf NULL) or from buf[0..len-1] in pieces of
 * chunk bytes, handing each record to record(ctx, ...); then refuse one
 * with no header ("empty WHAT (expected a header such as EXAMPLE and one
 * row per ROW)") or, once read, *nrows == 0 ("header but no rows"). */
int lf_csv_table_load(const lf_csv_table *t, const char *path, const char *buf, size_t len,
                      size_t chunk, int (*record)(void *, const lf_csv_record *, lf_error *),
                      void *ctx, const size_t *nrows, const char *what, const char *example,
                      const char *row, lf_error *err);
/* Column c's segment word (unload or load; empty or absent: unload) into
 * *seg; a hold is refused, never fitted. */
int lf_csv_table_segment(const lf_csv_table *t, const lf_csv_record *r, int c, lf_segment *seg,
                         lf_error *err);

/* The message for a header that is not text. */
#define LF_CSV_NOT_TEXT "binary data or text that is not UTF-8 (expected a CSV text file)"

/* A printable excerpt of text for messages: at most about 40 characters,
 * control and invalid bytes shown as '?'.  Returns buf. */
const char *lf_csv_excerpt(const char *text, char *buf, size_t n);

#endif
