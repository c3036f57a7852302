/* file.c: curve files of one or many curves (lf_file), what names one
 * curve of a file ("FILE#N"), and what an input that no reader claims is.
 *
 * A text export is read whole and parsed when it is opened, as
 * lf_curve_read always did; a binary format of many curves (an archive, a
 * force volume) is opened by random access: its reader lists the curves
 * from the file's directory and headers, and decodes one when asked, with
 * pread on the open descriptor (lf_src), so that nothing but the curve
 * asked for is held in memory and threads may decode curves at once. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nettle/sha2.h>

#include "readers.h"

#define HASH_BLOCK (1u << 20)

static void
hex_digest(struct sha256_ctx *ctx, char out[65])
{
    static const char hex[] = "0123456789abcdef";
    uint8_t digest[SHA256_DIGEST_SIZE];
    size_t i;
    sha256_digest(ctx, sizeof digest, digest);
    for (i = 0; i < sizeof digest; i++) {
        out[2 * i] = hex[digest[i] >> 4];
        out[2 * i + 1] = hex[digest[i] & 15];
    }
    out[64] = '\0';
}

/* The SHA-256 of the whole input, read in blocks. */
static int
hash_src(const lf_src *s, char out[65], lf_error *err)
{
    struct sha256_ctx ctx;
    unsigned char *block;
    uint64_t at;
    int status = LF_OK;

    sha256_init(&ctx);
    if (s->mem != NULL) {
        sha256_update(&ctx, (size_t) s->size, s->mem);
        hex_digest(&ctx, out);
        return LF_OK;
    }
    if ((block = malloc(HASH_BLOCK)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, s->name, 0, 0, "out of memory");
    for (at = 0; at < s->size && status == LF_OK; at += HASH_BLOCK) {
        size_t n = s->size - at < HASH_BLOCK ? (size_t) (s->size - at) : HASH_BLOCK;
        if ((status = lf_src_read(s, at, block, n, err)) == LF_OK)
            sha256_update(&ctx, n, block);
    }
    free(block);
    if (status == LF_OK)
        hex_digest(&ctx, out);
    return status;
}

int
lf_curve_path_split(const char *path, char *file, size_t n, long *index)
{
    const char *hash = strrchr(path, '#');
    struct stat st;
    size_t len = strlen(path);

    *index = -1;
    if (len >= n)
        return LF_EINVAL;
    strcpy(file, path);
    if (hash == NULL || hash[1] == '\0' || strspn(hash + 1, "0123456789") != strlen(hash + 1)
        || strlen(hash + 1) > 9 || stat(path, &st) == 0)
        return LF_OK;
    file[hash - path] = '\0';
    if (file[0] == '\0' || stat(file, &st) != 0) {
        strcpy(file, path);     /* neither exists: the whole name, said missing */
        return LF_OK;
    }
    *index = strtol(hash + 1, NULL, 10);
    return LF_OK;
}

void
lf_file_curve_name(const lf_file *f, size_t i, char *buf, size_t n)
{
    if (f->n > 1)
        snprintf(buf, n, "%s#%zu", f->path, i);
    else
        snprintf(buf, n, "%s", f->path);
}

/* ---------------------------------------------------------------------- */

/* What an unclaimed binary input is. */
int
lf_describe_binary(const lf_src *s, const char *head, size_t len, char *buf, size_t n)
{
    static const struct {
        const char *magic;
        size_t len;
        const char *what;
    } known[] = {
        { "\x89HDF\r\n\x1a\n", 8, "an HDF5 file, which layerfit does not read (export the "
          "curves as text, or in the instrument's own format)" },
        { "\x1f\x8b", 2, "a gzip-compressed file (decompress it first: gunzip)" },
        { "BZh", 3, "a bzip2-compressed file (decompress it first: bunzip2)" },
        { "\xfd" "7zXZ", 5, "an xz-compressed file (decompress it first: unxz)" },
        { "%PDF", 4, "a PDF document, not a curve file" },
        { "\x89PNG", 4, "a PNG image, not a curve file" },
        { "\xff\xd8\xff", 3, "a JPEG image, not a curve file" },
        { "II*\0", 4, "a TIFF image (an AFM image?), not a curve file" },
        { "MM\0*", 4, "a TIFF image (an AFM image?), not a curve file" },
        { "\xd0\xcf\x11\xe0", 4, "an old Excel or Office file (save the sheet as CSV)" },
    };
    size_t i, look = len < 4096 ? len : 4096;
    char names[300], list[256];
    lf_error err;

    if (len >= 2 && (((unsigned char) head[0] == 0xFF && (unsigned char) head[1] == 0xFE)
                     || ((unsigned char) head[0] == 0xFE && (unsigned char) head[1] == 0xFF)))
        return 0;           /* UTF-16 text: the CSV layer says so */
    if (lf_zip_magic(head, len)) {
        if (lf_zip_describe(s, names, sizeof names, &err) != LF_OK)
            snprintf(names, sizeof names, "nothing readable: %.200s", err.msg);
        snprintf(buf, n, "a zip archive: layerfit reads JPK archives (.jpk-force, "
                 ".jpk-force-map, .jpk-qi-data, .jpk-qi-series) and AFM Workshop mapping zips "
                 "(force-distance CSV files); this one holds %s", names);
        return 1;
    }
    for (i = 0; i < sizeof known / sizeof known[0]; i++)
        if (len >= known[i].len && memcmp(head, known[i].magic, known[i].len) == 0) {
            snprintf(buf, n, "%s", known[i].what);
            return 1;
        }
    if (len >= 4 && memcmp(head, "PK", 2) == 0 && memcmp(head, "PK\7\x08", 4) == 0) {
        snprintf(buf, n, "a split zip archive (join its parts first)");
        return 1;
    }
    /* binary: a NUL byte, or a control byte on the first line, or many of
     * them (a stray control byte in a text file is the text readers'
     * error, with its line and column) */
    {
        size_t ctrl = 0, first = (size_t) -1, line_end = 0;
        while (line_end < look && head[line_end] != '\n' && head[line_end] != '\r')
            line_end++;
        for (i = 0; i < look; i++) {
            unsigned char c = (unsigned char) head[i];
            if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v')
                || c == 0x7F) {
                if (first == (size_t) -1)
                    first = i;
                ctrl++;
                if (c == 0 || i < line_end)
                    break;
            }
        }
        if (first != (size_t) -1 && (i < look || (ctrl > 16 && 100 * ctrl > look))) {
            snprintf(buf, n, "binary data (byte 0x%02X at offset %zu), not a text export and "
                     "not one of the binary formats layerfit reads (readers: %s)",
                     (unsigned char) head[first], first, lf_reader_names(list, sizeof list));
            return 1;
        }
    }
    return 0;
}

/* ---------------------------------------------------------------------- */

static lf_file *
file_new(const char *name, const lf_read_opts *o)
{
    lf_file *f = calloc(1, sizeof *f);
    if (f == NULL)
        return NULL;
    f->path = lf_strdup(name ? name : "");
    if (f->path == NULL) {
        free(f);
        return NULL;
    }
    if (o != NULL)
        f->opts = *o;
    else
        lf_read_opts_default(&f->opts);
    f->fd = -1;
    f->src.fd = -1;
    f->src.name = f->path;
    return f;
}

/* The reader for these first bytes: forced by o, or sniffed; a binary
 * input that only a text reader would take is described instead. */
static const lf_reader_type *
choose(lf_file *f, const lf_read_opts *o, const char *head, size_t len, lf_error *err)
{
    const lf_reader_type *r;
    char what[1024], list[256];

    if (o != NULL && o->format != NULL && o->format[0] != '\0') {
        if ((r = lf_reader_find(o->format)) == NULL) {
            lf_fail_at(err, LF_EINVAL, f->path, 0, 0, "unknown format '%s' (one of: %s)",
                       o->format, lf_reader_names(list, sizeof list));
            return NULL;
        }
    } else {
        r = lf_reader_sniff(head, len);
    }
    if (lf_multi_of(r) == NULL && lf_describe_binary(&f->src, head, len, what, sizeof what)) {
        lf_fail_at(err, LF_EFORMAT, f->path, 0, 0, "%s", what);
        return NULL;
    }
    return r;
}

/* Open f, whose src is set: choose its reader and list its curves. */
static int
file_start(lf_file *f, const char *head, size_t len, const lf_read_opts *o,
           lf_warnings *warn, lf_error *err)
{
    int status;

    if ((f->reader = choose(f, o, head, len, err)) == NULL)
        return err != NULL ? err->status : LF_EFORMAT;
    f->opts.format = NULL;
    f->multi = lf_multi_of(f->reader);
    if (f->multi == NULL) {
        lf_read_opts ro = f->opts;
        ro.format = f->reader->name;
        /* a text export: read as lf_curve_parse always did, by the reader
         * chosen above from its first bytes (which lf_curve_parse would
         * look at again: the same reader, and the same verdict on binary
         * data, the bytes parsed being those read for head or, cut at the
         * first control byte, their beginning) */
        if (f->src.mem == NULL)
            return lf_fail_at(err, LF_EINVAL, f->path, 0, 0, "internal: a text file not in memory");
        status = lf_curve_parse_with(f->reader, (const char *) f->src.mem, (size_t) f->src.size,
                                     0, f->path, &ro, &f->one, warn, err);
        f->n = status == LF_OK ? 1 : 0;
        return status;
    }
    if (f->sha256[0] == '\0' && (status = hash_src(&f->src, f->sha256, err)) != LF_OK)
        return status;
    return f->multi->open(f, warn, err);
}

/* 1 when the first bytes of a stream are a format of many curves (binary). */
static int
binary_head(const char *head, size_t len)
{
    return lf_multi_of(lf_reader_sniff(head, len)) != NULL;
}

int
lf_input_read_sniffed(const char *path, unsigned flags, lf_input *in, lf_error *err)
{
    return lf_input_read_path(path, flags | LF_INPUT_TEXT, binary_head, in, err);
}

int
lf_file_open(const char *path, unsigned flags, const lf_read_opts *o, lf_file **out,
             lf_warnings *warn, lf_error *err)
{
    char head[LF_SNIFF_BYTES];
    struct stat st;
    lf_file *f;
    lf_input in;
    int fd, status;
    size_t len;

    *out = NULL;
    lf_error_clear(err);
    if ((f = file_new(path, o)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, path, 0, 0, "out of memory");
    if ((status = lf_input_open(path, flags, &fd, err)) != LF_OK) {
        lf_file_close(f);
        return status;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        /* a stream: read once, whole, checked as text as it arrives unless
         * its first bytes are a binary format's */
        int forced = o != NULL && o->format != NULL && lf_multi_of(lf_reader_find(o->format));
        status = lf_input_read_fd(fd, path, forced ? 0 : LF_INPUT_TEXT,
                                  forced ? NULL : binary_head, &in, err);
        close(fd);
        if (status != LF_OK) {
            lf_file_close(f);
            return status;
        }
        f->data = (unsigned char *) in.data;
        f->src.mem = f->data;
        f->src.size = in.len;
        memcpy(f->sha256, in.sha256, sizeof f->sha256);
        len = in.len < sizeof head ? in.len : sizeof head;
        memcpy(head, in.data, len);
    } else {
        f->fd = fd;
        f->src.fd = fd;
        f->src.size = (uint64_t) st.st_size;
        len = f->src.size < sizeof head ? (size_t) f->src.size : sizeof head;
        if ((status = lf_src_read(&f->src, 0, head, len, err)) != LF_OK) {
            lf_file_close(f);
            return status;
        }
        if (lf_multi_of(lf_reader_sniff(head, len)) == NULL
            && !(o != NULL && o->format != NULL && lf_multi_of(lf_reader_find(o->format)))) {
            /* a text export, or something no reader claims: read it whole
             * (what is parsed is what is hashed) */
            status = lf_input_read_fd(fd, path, LF_INPUT_TEXT, NULL, &in, err);
            if (status != LF_OK) {
                lf_file_close(f);
                return status;
            }
            close(fd);
            f->fd = f->src.fd = -1;
            f->data = (unsigned char *) in.data;
            f->src.mem = f->data;
            f->src.size = in.len;
            memcpy(f->sha256, in.sha256, sizeof f->sha256);
        }
    }
    status = file_start(f, head, len, o, warn, err);
    if (status == LF_OK && f->multi == NULL) {
        /* the curve is read: the bytes are no longer needed */
        free(f->data);
        f->data = NULL;
        f->src.mem = NULL;
    }
    if (status != LF_OK) {
        lf_file_close(f);
        return status;
    }
    *out = f;
    return LF_OK;
}

int
lf_file_open_memory(const char *buf, size_t len, const char *name, const lf_read_opts *o,
                    lf_file **out, lf_warnings *warn, lf_error *err)
{
    lf_file *f;
    int status;

    *out = NULL;
    lf_error_clear(err);
    if ((f = file_new(name, o)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, name, 0, 0, "out of memory");
    f->src.mem = (const unsigned char *) (buf ? buf : "");
    f->src.size = buf ? len : 0;
    if (lf_multi_of(lf_reader_sniff((const char *) f->src.mem, (size_t) f->src.size)) == NULL
        && !(o != NULL && o->format != NULL && lf_multi_of(lf_reader_find(o->format)))) {
        struct sha256_ctx ctx;
        sha256_init(&ctx);
        sha256_update(&ctx, (size_t) f->src.size, f->src.mem);
        hex_digest(&ctx, f->sha256);
    }
    status = file_start(f, (const char *) f->src.mem,
                        f->src.size < LF_SNIFF_BYTES ? (size_t) f->src.size : LF_SNIFF_BYTES,
                        o, warn, err);
    if (status != LF_OK) {
        lf_file_close(f);
        return status;
    }
    if (f->multi == NULL)
        f->src.mem = NULL;
    *out = f;
    return LF_OK;
}

size_t
lf_file_count(const lf_file *f)
{
    return f->n;
}

const char *
lf_file_format(const lf_file *f)
{
    return f->reader->name;
}

const char *
lf_file_sha256(const lf_file *f)
{
    return f->sha256;
}

static int
no_such_curve(const lf_file *f, size_t i, lf_error *err)
{
    return lf_fail_at(err, LF_EINVAL, f->path, 0, 0, "no curve %zu: the file holds %zu "
                      "(0..%zu)", i, f->n, f->n ? f->n - 1 : 0);
}

int
lf_file_info(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err)
{
    size_t k;
    memset(info, 0, sizeof *info);
    info->x = info->y = NAN;
    info->grid_i = info->grid_j = -1;
    if (i >= f->n)
        return no_such_curve(f, i, err);
    if (f->multi != NULL)
        return f->multi->info(f, i, info, err);
    info->x = f->one->x;
    info->y = f->one->y;
    info->grid_i = f->one->grid_i;
    info->grid_j = f->one->grid_j;
    info->points = f->one->n;
    for (k = 0; k < f->one->n; k++)
        if (f->one->segment[k] <= LF_SEG_HOLD)
            info->segment_points[f->one->segment[k]]++;
    return LF_OK;
}

int
lf_file_curve(const lf_file *f, size_t i, lf_curve **out, lf_warnings *warn, lf_error *err)
{
    lf_warnings local = { 0, NULL };
    char name[4200];
    lf_curve *c;
    int status;

    *out = NULL;
    lf_error_clear(err);
    if (i >= f->n)
        return no_such_curve(f, i, err);
    if (f->multi == NULL) {
        if ((*out = lf_curve_copy(f->one)) == NULL)
            return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
        return LF_OK;
    }
    lf_file_curve_name(f, i, name, sizeof name);
    if ((c = lf_curve_new(name, f->reader->name)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, f->path, 0, 0, "out of memory");
    c->index = (long) i;
    status = f->multi->curve(f, i, c, &local, err);
    if (status != LF_OK) {
        lf_warnings_free(&local);
        lf_curve_free(c);
        return status;
    }
    lf_curve_done(f->reader, c, &f->opts, &local, warn);
    *out = c;
    return LF_OK;
}

void
lf_file_close(lf_file *f)
{
    if (f == NULL)
        return;
    if (f->multi != NULL && f->multi->close != NULL)
        f->multi->close(f);
    if (f->fd >= 0)
        close(f->fd);
    lf_curve_free(f->one);
    free(f->data);
    free(f->path);
    free(f);
}

int
lf_file_sniff_multi(const char *path, const char *format)
{
    char head[LF_SNIFF_BYTES];
    struct stat st;
    lf_src src;
    lf_error err;
    int fd, multi = 0;

    if (format != NULL && format[0] != '\0')
        return lf_multi_of(lf_reader_find(format)) != NULL;
    /* never opens a FIFO (which would wake, then leave, its writer) */
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return 0;
    if (lf_input_open(path, 0, &fd, &err) != LF_OK)
        return 0;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
        src.mem = NULL;
        src.fd = fd;
        src.size = (uint64_t) st.st_size;
        src.name = path;
        if (lf_src_read(&src, 0, head, src.size < sizeof head ? (size_t) src.size : sizeof head,
                        &err) == LF_OK)
            multi = lf_multi_of(lf_reader_sniff(head, src.size < sizeof head ? (size_t) src.size
                                                                               : sizeof head)) != NULL;
    }
    close(fd);
    return multi;
}

/* ---------------------------------------------------------------------- */

int
lf_multi_read_one(const lf_multi_reader *m, const lf_source *in, const lf_read_opts *o,
                  lf_curve *c, lf_warnings *warn, lf_error *err)
{
    lf_file *f;
    int status;

    if ((f = file_new(in->name, o)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
    f->reader = m->reader;
    f->multi = m;
    f->opts.format = NULL;
    f->src.mem = (const unsigned char *) in->buf;
    f->src.size = in->len;
    status = m->open(f, warn, err);
    if (status == LF_OK && f->n != 1)
        status = lf_fail_at(err, LF_EDATA, in->name, 0, 0, "holds %zu curves: name one as "
                            "%s#0 .. %s#%zu (or fit each with layerfit fit --batch)", f->n,
                            in->name, in->name, f->n ? f->n - 1 : 0);
    if (status == LF_OK)
        status = m->curve(f, 0, c, warn, err);
    f->src.mem = NULL;
    lf_file_close(f);
    return status;
}
