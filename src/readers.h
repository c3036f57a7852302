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

/* lf_curve_parse with its reader chosen (and the first bytes found to be
 * no binary data) by the caller: lf_file_open, which chose it from the
 * same bytes (src/reader.c). */
int lf_curve_parse_with(const lf_reader_type *r, const char *buf, size_t len, size_t chunk,
                        const char *name, const lf_read_opts *o, lf_curve **out,
                        lf_warnings *warn, lf_error *err);

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
    lf_reader_workshop, lf_reader_ntmdt, lf_reader_hysitron, lf_reader_text,
    lf_reader_jpk_force, lf_reader_nanoscope, lf_reader_igor, lf_reader_workshop_map,
    lf_reader_tab;

/* What every reader does after reading a curve (src/reader.c): its
 * warnings (local) go to warn, its position comes from its metadata where
 * the reader set none, and the options it did not use are said. */
void lf_curve_done(const lf_reader_type *r, lf_curve *c, const lf_read_opts *o,
                   lf_warnings *local, lf_warnings *warn);
/* A deep copy of c (NULL when out of memory). */
lf_curve *lf_curve_copy(const lf_curve *c);
/* The names of the reader table, ", "-separated, into buf. */
const char *lf_reader_names(char *buf, size_t n);

/* ---- random access to an input (src/zip.c) --------------------------- */

/* The bytes of an input: in memory, or in a regular file read with pread
 * (safe from several threads at once). */
typedef struct {
    const unsigned char *mem;   /* all the bytes, or NULL: read fd */
    int fd;
    uint64_t size;
    const char *name;           /* for messages */
} lf_src;

/* n bytes at offset off into dst; LF_EFORMAT naming the file when they lie
 * past its end, LF_EIO on a read error. */
int lf_src_read(const lf_src *s, uint64_t off, void *dst, size_t n, lf_error *err);

/* ---- zip archives (src/zip.c) ---------------------------------------- */

typedef struct {
    uint64_t offset;            /* of the local header */
    uint64_t csize, usize;      /* compressed and uncompressed sizes */
    uint64_t cdh;               /* of its central directory header */
    uint32_t crc;
    uint16_t method, flags;
} lf_zip_entry;

#define LF_ZIP_STOP (-2)        /* returned by a visit: stop the scan, no error */

/* Called for each entry of the central directory, in its order: name is
 * NUL-terminated (nlen bytes) and valid during the call only. */
typedef int (*lf_zip_visit)(void *ctx, const char *name, size_t nlen, const lf_zip_entry *e,
                            lf_error *err);

/* 1 when the first bytes are those of a zip archive. */
int lf_zip_magic(const char *head, size_t len);
/* Walk the central directory (ZIP64 included), reading it in blocks;
 * *count and *end (may be NULL) get the number of entries and where the
 * directory ends. */
int lf_zip_scan(const lf_src *s, lf_zip_visit visit, void *ctx, uint64_t *count,
                uint64_t *end, lf_error *err);
/* The same over the directory headers from byte from up to byte to (a
 * part of the directory found by lf_zip_scan: the entries' cdh), ending
 * early at anything that is not a directory header. */
int lf_zip_scan_range(const lf_src *s, uint64_t from, uint64_t to, lf_zip_visit visit,
                      void *ctx, lf_error *err);
/* Entry e (name for messages) inflated into a new buffer of e->usize bytes
 * (the caller frees it), its CRC-32 checked; LF_EFORMAT when it is larger
 * than max bytes, damaged, encrypted or compressed with another method. */
int lf_zip_extract(const lf_src *s, const lf_zip_entry *e, const char *name, uint64_t max,
                   unsigned char **out, lf_error *err);
/* "3 files (a.csv, b.csv, c.png)" for a message about an archive. */
int lf_zip_describe(const lf_src *s, char *buf, size_t n, lf_error *err);

/* ---- Java properties files (src/props.c) ----------------------------- */

typedef struct {
    const char *key, *value;
    size_t klen;                /* strlen(key) */
} lf_prop;

typedef struct {
    char *buf;                  /* the unescaped text */
    size_t n;
    lf_prop *kv;                /* sorted by key */
} lf_props;

/* Parse text (escapes, continued lines, comments as java.util.Properties
 * reads them); p owns a copy.  LF_ENOMEM only. */
int lf_props_parse(lf_props *p, const char *text, size_t len);
/* The value of key (the last one given), or NULL. */
const char *lf_props_get(const lf_props *p, const char *key);
/* The value of the first key (in sorted order) ending in suffix, or NULL;
 * *key (may be NULL) gets that key. */
const char *lf_props_suffix(const lf_props *p, const char *suffix, const char **key);
void lf_props_free(lf_props *p);

/* ---- files of many curves (src/file.c) ------------------------------- */

/* A format of many curves per file (an archive, a force volume) reads
 * through these: open lists the curves of f (f->n, f->state) without
 * decoding them, info describes curve i, curve decodes it into c (ending
 * with lf_curve_finish), close frees f->state.  info and curve read f
 * only, and may run in several threads at once. */
typedef struct {
    const lf_reader_type *reader;
    int (*open)(lf_file *f, lf_warnings *warn, lf_error *err);
    int (*info)(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err);
    int (*curve)(const lf_file *f, size_t i, lf_curve *c, lf_warnings *warn, lf_error *err);
    void (*close)(lf_file *f);
} lf_multi_reader;

struct lf_file {
    char *path;                 /* as given: messages and curve names */
    const lf_reader_type *reader;
    const lf_multi_reader *multi;   /* NULL: a text format of one curve */
    lf_read_opts opts;          /* how to read (format not kept) */
    lf_src src;
    int fd;                     /* owned descriptor, or -1 */
    unsigned char *data;        /* owned bytes (a stream read whole), or NULL */
    char sha256[65];
    size_t n;                   /* curves */
    void *state;                /* the multi reader's */
    lf_curve *one;              /* a text format: its curve, read at open */
};

extern const lf_multi_reader lf_multi_jpk_force, lf_multi_nanoscope, lf_multi_igor,
    lf_multi_workshop_map;
/* The multi-curve side of reader r, or NULL for a text format. */
const lf_multi_reader *lf_multi_of(const lf_reader_type *r);
/* The read function of a multi-curve format on an input in memory: its
 * only curve, or an error saying how many it holds and how to pick one. */
int lf_multi_read_one(const lf_multi_reader *m, const lf_source *in, const lf_read_opts *o,
                      lf_curve *c, lf_warnings *warn, lf_error *err);
/* 1 when the file at path is one a reader of many curves reads (format
 * names the reader, else it is sniffed from the first bytes); 0 for a
 * text export or a file that cannot be read. */
int lf_file_sniff_multi(const char *path, const char *format);
/* The name of curve i of f as messages give it: "path#i" when f holds
 * several, else the path. */
void lf_file_curve_name(const lf_file *f, size_t i, char *buf, size_t n);
/* What an input that no reader claims is, for its error message: "a zip
 * archive: ...", "an HDF5 file ...", "binary data ...".  0 when the first
 * bytes look like text (then the text readers say what is wrong). */
int lf_describe_binary(const lf_src *s, const char *head, size_t len, char *buf, size_t n);

/* ---- reading binary numbers ------------------------------------------ */

static inline uint32_t
lf_be32(const unsigned char *p)
{
    return (uint32_t) p[0] << 24 | (uint32_t) p[1] << 16 | (uint32_t) p[2] << 8 | p[3];
}

static inline uint32_t
lf_le32(const unsigned char *p)
{
    return (uint32_t) p[3] << 24 | (uint32_t) p[2] << 16 | (uint32_t) p[1] << 8 | p[0];
}

static inline uint16_t
lf_be16(const unsigned char *p)
{
    return (uint16_t) (p[0] << 8 | p[1]);
}

static inline uint16_t
lf_le16(const unsigned char *p)
{
    return (uint16_t) (p[1] << 8 | p[0]);
}

/* A finite number from a whole string (blanks around allowed), else NaN. */
double lf_number_or_nan(const char *text);

/* v as a whole number when it is one within [lo, hi], else fallback. */
static inline long
lf_whole(double v, long lo, long hi, long fallback)
{
    return v >= (double) lo && v <= (double) hi && v == floor(v) ? (long) v : fallback;
}

#endif
