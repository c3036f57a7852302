/* command.h: what the layerfit command (src/cli/) shares with the library
 * beyond its public interface (layerfit.h): helpers for the command's own
 * reading and writing and words the library's warnings share with it.
 * They are compiled into the library's objects, which the command links,
 * but the installed libraries do not export them and `make install` does
 * not install this header: programs see layerfit.h alone. */
#ifndef LF_COMMAND_H
#define LF_COMMAND_H

#include "layerfit.h"

/* A deflection sensitivity in SI (si_unit "m/A", else m/V) as instruments
 * show it: the number into *shown, its unit returned ("nm/nA", the same
 * number; "nm/V", 1e9 times). */
const char *lf_sensitivity_shown(double si, const char *si_unit, double *shown);

/* What a thin-layer model's result is worth at b/a (thickness over contact
 * radius) in words: NULL up to `limit` (a fit's max_b_over_a, 0.1 by
 * default); "strained" below b = a; from b = a on, the model does not apply
 * (there its force is off by a quarter to a factor 5 against the exact
 * model's, `layerfit model --figure 6`). */
const char *lf_thin_scope(double b_over_a, double limit);

/* Length of the valid UTF-8 sequence that starts at s (1..4), or 0 when
 * the bytes there are not UTF-8 (overlong forms and surrogates included). */
size_t lf_utf8_len(const unsigned char *s);
/* lf_input_read (flags: LF_INPUT_STREAM or 0) of a file that may be a text
 * export, a plan or a binary format read as a stream: checked as text as
 * it arrives (LF_INPUT_TEXT) unless its first LF_SNIFF_BYTES are a binary
 * format's (file.c). */
int lf_input_read_sniffed(const char *path, unsigned flags, lf_input *in, lf_error *err);
/* lf_file_kind_of for a file already in memory (name for messages). */
int lf_file_kind_parse(const char *buf, size_t len, const char *name, lf_file_kind *kind,
                       lf_error *err);

/* ------------------------------------------------------------------------
 * Tables (src/table.c): a CSV file read whole, every cell as text -- e.g.
 * the output of `layerfit fit --batch`.  The same line layer as the curve
 * and plan readers (delimiter from the header, '#' comments, quotes).
 * Ownership: *out is the caller's, released by lf_table_free.
 * --------------------------------------------------------------------- */

typedef struct {
    size_t nrows, ncols;
    long header_line;     /* the line of the header */
    char **names;         /* ncols header cells */
    char **cells;         /* nrows x ncols, row-major; "" where a row is short */
    long *line;           /* nrows: the line where each row starts */
    long *col;            /* nrows x ncols: the character column of each cell
                             (0 where a row is short) */
} lf_table;

int lf_table_read(const char *path, lf_table **out, lf_error *err);
void lf_table_free(lf_table *t);
/* The index of the column named name, or -1. */
long lf_table_column(const lf_table *t, const char *name);
/* A number in a cell: LF_OK with *v, or LF_OK with *v = NaN for an empty
 * cell; LF_EFORMAT (and *v = NaN) when the cell is not a number. */
int lf_table_number(const char *cell, double *v);

#endif
