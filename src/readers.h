/* readers.h: what the instrument readers share (internal, not installed):
 * building a curve, metadata, segments from a profile, the AFM conversions,
 * and a line-by-line table parser for text exports whose column header is
 * not on line 1 (src/read_table.c). */
#ifndef LF_READERS_H
#define LF_READERS_H

#include "csvsplit.h"

/* ---- curves (src/reader.c) ------------------------------------------- */

/* A new empty curve named name, format set; NULL when out of memory. */
lf_curve *lf_curve_new(const char *name, const char *format);
/* Room for n points (depth, force, segment, line; time when with_time). */
int lf_curve_reserve(lf_curve *c, size_t n, int with_time);
/* Append key = value to the curve's metadata, both converted to UTF-8 when
 * they are not (Latin-1 bytes, as instruments write them).  A key already
 * present is not added twice. */
int lf_curve_add_meta(lf_curve *c, const char *key, const char *value);
/* The value of metadata key (exact match), or NULL. */
const char *lf_curve_meta(const lf_curve *c, const char *key);
/* The number of metadata key in SI: the unit is the key's "(unit)" or
 * what follows its last ", " ("k (N/m)", "Force Constant, nN/nm").  -1
 * when absent, not a number or the unit is not of quantity q. */
int lf_meta_number(const lf_curve *c, const char *key, lf_quantity q, double *si);
/* Copy src to dst (n bytes) as UTF-8, Latin-1 bytes converted when src is
 * not valid UTF-8. */
void lf_latin1_to_utf8(const char *src, char *dst, size_t n);

/* What every reader does at the end: checks that points were read, that
 * depth and force are finite, warns where depth runs backwards in a
 * segment. */
int lf_curve_finish(lf_curve *c, lf_warnings *warn, lf_error *err);

/* ---- segments (src/segments.c) --------------------------------------- */

/* Segments from a profile: drive[i] is the signal the instrument drives,
 * positive into the sample (piezo extension or depth; drive2, if not NULL,
 * a second candidate such as the load of a load-controlled test).  A hold is
 * the stretch around the extreme where the signal stays within its noise
 * (6 sd, at least 0.1% and at most 2% of its range) of the extreme for at least 8 points
 * and 2% of the curve: it becomes LF_SEG_HOLD, what precedes it load and
 * what follows unload.  Without a hold the curve is split at the first
 * deepest point (load before, unload from it on).  A line saying what was
 * found goes to c->info. */
void lf_segments_from_profile(lf_curve *c, const double *drive,
                              const double *drive2, const char *what);

/* How many points of x[0..n-1] share exactly its minimum. */
size_t lf_count_at_min(const double *x, size_t n);
/* Whether a depth column is clamped: many points (at least 20 and 5%)
 * sharing exactly its minimum, as an instrument's "Indentation" held at 0
 * outside contact, which hides the pull-off. */
int lf_is_clamped(const double *x, size_t n);

/* ---- AFM conversions (src/reader.c) ---------------------------------- */

/* The spring constant to use: the file's (file_k, finite and > 0) unless
 * absent, else the option's; neither is an error naming the option and
 * why it is needed.  Fills c->spring_constant and a line of c->info (an
 * option set aside is said by lf_curve_parse, for every reader). */
int lf_afm_spring_constant(lf_curve *c, double file_k, const char *file_key,
                           const lf_read_opts *o, const char *why, lf_error *err);
/* The same for the deflection sensitivity of a signal in volts (per_amp 0)
 * or amperes (per_amp 1), in m/V or m/A. */
int lf_afm_sensitivity(lf_curve *c, double file_s, const char *file_key,
                       int per_amp, const lf_read_opts *o, lf_error *err);

/* ---- delimited tables (src/read_table.c) ----------------------------- */

#define LF_TEXT_TABLE_MAX_COLS 64

typedef struct {
    /* settings */
    int no_header;            /* data from the first line, columns unnamed */
    int skip_bad_rows;
    /* results */
    size_t ncol;
    char name[LF_TEXT_TABLE_MAX_COLS][96];   /* header cell names (UTF-8) */
    char unit[LF_TEXT_TABLE_MAX_COLS][32];   /* their units, micro spelled 'u' */
    char cell[LF_TEXT_TABLE_MAX_COLS][128];  /* the header cells as written */
    double *col[LF_TEXT_TABLE_MAX_COLS];
    long *line;
    size_t n, cap;
    long header_line;         /* 0 when no header */
    char delim;               /* '\t', ';', ',' or ' ' (runs of blanks) */
    int decimal_comma;
    long skipped, first_skipped;
    /* state */
    lf_curve *c;              /* metadata lines go to c->meta */
    const char *name_file;
    int in_data;
    char *pending;            /* the last text line, a header candidate */
    long pending_line;
} lf_text_table;

/* Read a text table: metadata lines (Key<TAB>value, "Key: value",
 * "Key = value") until the first line that names columns and is followed
 * by a numeric row of as many cells; then one numeric row per line (blank
 * lines skipped).  The delimiter is taken from the first numeric row (tab,
 * ';', ',', else runs of blanks); a decimal comma is accepted with any
 * delimiter but ','.  Metadata go to c.  t must be zeroed, with settings
 * filled; free it with lf_text_table_free. */
int lf_text_table_read(lf_text_table *t, const lf_source *in, lf_curve *c, lf_error *err);
void lf_text_table_free(lf_text_table *t);
/* The column whose header name is one of names (any case, NULL-ended), or
 * -1; with prefix, names need only begin the header name. */
int lf_text_table_find(const lf_text_table *t, const char *const *names, int prefix);
/* The end of a table reader: warns about skipped rows, then
 * lf_curve_finish; frees the table. */
int lf_text_table_finish(lf_text_table *t, lf_curve *c, lf_warnings *warn, lf_error *err);
/* The first bytes of a file as a string (at most n - 1), for sniffing. */
const char *lf_sniff_text(const char *head, size_t len, char *buf, size_t n);
/* Read a table and convert it as generic text (the text and hysitron
 * readers). */
int lf_text_read(const lf_source *in, const lf_read_opts *o, lf_curve *c,
                 lf_warnings *warn, lf_error *err);
/* The SI factor of column j for quantity q, an error naming the column. */
int lf_text_table_factor(const lf_text_table *t, int j, lf_quantity q, double *factor,
                    lf_error *err);

/* The generic conversion of a table (src/read_text.c): depth, force and
 * time columns by name and unit, raw signal columns ignored, segments from
 * the depth or load profile. */
int lf_text_curve(lf_text_table *t, const lf_source *in, const lf_read_opts *o, lf_curve *c,
                  lf_warnings *warn, lf_error *err);

/* Split a line into cells at delim (' ' = runs of blanks), trimming blanks;
 * at most max cells (the rest joined into the last); returns the count and
 * the character column where each cell starts (may be NULL).  Modifies
 * text. */
size_t lf_split_cells(char *text, char delim, char **cells, long *cols, size_t max);

/* The entries of the reader table (lf_reader_types), one per file. */
extern const lf_reader_type lf_reader_csv, lf_reader_chiaro, lf_reader_jpk,
    lf_reader_workshop, lf_reader_ntmdt, lf_reader_hysitron, lf_reader_text;

#endif
