/* zip.c: reading zip archives (the JPK binary exports, AFM Workshop
 * mapping zips) by random access, from memory or from a regular file with
 * pread, never the whole archive at once.
 *
 * The layout is PKWARE's APPNOTE (version 6.3): the end of central
 * directory record (signature PK\5\6) at the end of the archive gives the
 * place and size of the central directory, one header (PK\1\2) per entry
 * with its name, sizes, CRC-32, method and the offset of its local header
 * (PK\3\4), after which the entry's data follow.  Archives over 4 GiB or
 * 65 535 entries (large QI files) carry ZIP64 records: a locator (PK\6\7)
 * just before the end record points at the ZIP64 end record (PK\6\6) with
 * 64-bit counts and offsets, and an entry's 64-bit sizes and offset sit in
 * its extra field 0x0001 wherever the 32-bit field reads 0xFFFFFFFF.
 * Entries are stored (method 0) or deflated (method 8, zlib's inflate on
 * raw deflate data); the CRC-32 of what was inflated is checked. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <errno.h>

#include <zlib.h>

#include "readers.h"

#define EOCD_SIZE 22
#define EOCD64_SIZE 56
#define LOCATOR_SIZE 20
#define CDH_SIZE 46
#define LFH_SIZE 30
#define BLOCK (256u * 1024u)        /* central directory read in blocks of this */

static uint16_t
le16(const unsigned char *p)
{
    return (uint16_t) (p[0] | p[1] << 8);
}

static uint32_t
le32(const unsigned char *p)
{
    return (uint32_t) p[0] | (uint32_t) p[1] << 8 | (uint32_t) p[2] << 16
        | (uint32_t) p[3] << 24;
}

static uint64_t
le64(const unsigned char *p)
{
    return (uint64_t) le32(p) | (uint64_t) le32(p + 4) << 32;
}

int
lf_src_read(const lf_src *s, uint64_t off, void *dst, size_t n, lf_error *err)
{
    if (off > s->size || n > s->size - off)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "truncated: %zu bytes at byte "
                          "%llu lie past its end (%llu bytes)", n, (unsigned long long) off,
                          (unsigned long long) s->size);
    if (s->mem != NULL) {
        memcpy(dst, s->mem + off, n);
        return LF_OK;
    }
    while (n > 0) {
        ssize_t r = pread(s->fd, dst, n, (off_t) off);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return lf_fail_at(err, LF_EIO, s->name, 0, 0, "read error at byte %llu: %s",
                              (unsigned long long) off, r < 0 ? strerror(errno)
                              : "the file is shorter than when it was opened");
        dst = (char *) dst + r;
        off += (uint64_t) r;
        n -= (size_t) r;
    }
    return LF_OK;
}

int
lf_zip_magic(const char *head, size_t len)
{
    return len >= 4 && (memcmp(head, "PK\3\4", 4) == 0 || memcmp(head, "PK\5\6", 4) == 0);
}

/* The place and size of the central directory and its number of entries. */
static int
directory(const lf_src *s, uint64_t *cd_off, uint64_t *cd_size, uint64_t *count, lf_error *err)
{
    unsigned char tail[EOCD_SIZE + 65535], *eocd = NULL;
    size_t n = s->size < sizeof tail ? (size_t) s->size : sizeof tail, i;
    uint64_t at;
    int status;

    if (n < EOCD_SIZE)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: too short "
                          "for its end record (%llu bytes)", (unsigned long long) s->size);
    at = s->size - n;
    if ((status = lf_src_read(s, at, tail, n, err)) != LF_OK)
        return status;
    /* the end record is last, followed only by its comment */
    for (i = n - EOCD_SIZE + 1; i-- > 0;)
        if (memcmp(tail + i, "PK\5\6", 4) == 0 && i + EOCD_SIZE + le16(tail + i + 20) <= n) {
            eocd = tail + i;
            break;
        }
    if (eocd == NULL)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: no end of "
                          "central directory record (truncated by a copy or download?)");
    *count = le16(eocd + 10);
    *cd_size = le32(eocd + 12);
    *cd_off = le32(eocd + 16);
    if (*count == 0xFFFF || *cd_size == 0xFFFFFFFFu || *cd_off == 0xFFFFFFFFu
        || (i >= LOCATOR_SIZE && memcmp(eocd - LOCATOR_SIZE, "PK\6\7", 4) == 0)) {
        unsigned char rec[EOCD64_SIZE];
        uint64_t rec_off;
        if (i < LOCATOR_SIZE || memcmp(eocd - LOCATOR_SIZE, "PK\6\7", 4) != 0)
            return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: its end "
                              "record asks for a ZIP64 record that is not there");
        rec_off = le64(eocd - LOCATOR_SIZE + 8);
        if ((status = lf_src_read(s, rec_off, rec, sizeof rec, err)) != LF_OK)
            return status;
        if (memcmp(rec, "PK\6\6", 4) != 0)
            return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: no ZIP64 "
                              "end record at byte %llu", (unsigned long long) rec_off);
        *count = le64(rec + 32);
        *cd_size = le64(rec + 40);
        *cd_off = le64(rec + 48);
    }
    if (*cd_off > s->size || *cd_size > s->size - *cd_off)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: its central "
                          "directory (%llu bytes at byte %llu) lies past its end",
                          (unsigned long long) *cd_size, (unsigned long long) *cd_off);
    if (*count > *cd_size / CDH_SIZE)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: %llu entries "
                          "cannot fit in a central directory of %llu bytes",
                          (unsigned long long) *count, (unsigned long long) *cd_size);
    return LF_OK;
}

/* The ZIP64 extra field of a central directory header: the 64-bit values
 * of the fields that read 0xFFFFFFFF, in the order usize, csize, offset. */
static int
zip64_extra(const unsigned char *x, size_t n, lf_zip_entry *e, int need_u, int need_c,
            int need_o)
{
    while (n >= 4) {
        size_t id = le16(x), len = le16(x + 2), k = 4;
        if (len > n - 4)
            return -1;
        if (id == 0x0001) {
            if (need_u) {
                if (k + 8 > 4 + len)
                    return -1;
                e->usize = le64(x + k);
                k += 8;
            }
            if (need_c) {
                if (k + 8 > 4 + len)
                    return -1;
                e->csize = le64(x + k);
                k += 8;
            }
            if (need_o) {
                if (k + 8 > 4 + len)
                    return -1;
                e->offset = le64(x + k);
            }
            return 0;
        }
        x += 4 + len;
        n -= 4 + len;
    }
    return need_u || need_c || need_o ? -1 : 0;
}

/* Walk the central directory headers from pos up to end: count of them
 * (all must be there), or, when count is UINT64_MAX, as many as follow
 * (the walk ends at the first other signature). */
static int
walk(const lf_src *s, uint64_t pos, uint64_t end, uint64_t count, lf_zip_visit visit,
     void *ctx, lf_error *err)
{
    unsigned char *block = NULL;
    const unsigned char *win = NULL;
    uint64_t wstart = 0, wlen = 0, k;
    char name[65536];
    int status, open_ended = count == UINT64_MAX;

    if (s->mem != NULL) {
        win = s->mem;
        wstart = 0;
        wlen = s->size;
    } else if ((block = malloc(BLOCK)) == NULL) {
        return lf_fail_at(err, LF_ENOMEM, s->name, 0, 0, "out of memory");
    }
    for (k = 0; k < count; k++) {
        const unsigned char *h;
        lf_zip_entry e;
        size_t nlen = 0, elen = 0, clen = 0, whole = CDH_SIZE;
        int pass;
        if (open_ended && pos + CDH_SIZE > end)
            break;
        /* the header, then with its variable part, in the window */
        for (pass = 0; pass < 2; pass++) {
            if (pos + whole > end) {
                free(block);
                return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: "
                                  "entry %llu of %llu runs past its central directory",
                                  (unsigned long long) k + 1, (unsigned long long) count);
            }
            if (pos < wstart || pos + whole > wstart + wlen) {
                wstart = pos;
                wlen = end - pos < BLOCK ? end - pos : BLOCK;
                if ((status = lf_src_read(s, wstart, block, (size_t) wlen, err)) != LF_OK) {
                    free(block);
                    return status;
                }
                win = block;
            }
            h = win + (pos - wstart);
            if (pass == 1)
                break;
            if (memcmp(h, "PK\1\2", 4) != 0) {
                free(block);
                if (open_ended)
                    return LF_OK;
                return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: no "
                                  "central directory header at byte %llu",
                                  (unsigned long long) pos);
            }
            nlen = le16(h + 28);
            elen = le16(h + 30);
            clen = le16(h + 32);
            whole = CDH_SIZE + nlen + elen + clen;
        }
        e.flags = le16(h + 8);
        e.method = le16(h + 10);
        e.crc = le32(h + 16);
        e.csize = le32(h + 20);
        e.usize = le32(h + 24);
        e.offset = le32(h + 42);
        e.cdh = pos;
        if (zip64_extra(h + CDH_SIZE + nlen, elen, &e, e.usize == 0xFFFFFFFFu,
                        e.csize == 0xFFFFFFFFu, e.offset == 0xFFFFFFFFu) != 0) {
            free(block);
            return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: entry "
                              "%llu has a bad ZIP64 extra field", (unsigned long long) k + 1);
        }
        memcpy(name, h + CDH_SIZE, nlen);
        name[nlen] = '\0';
        pos += whole;
        if (visit != NULL && (status = visit(ctx, name, nlen, &e, err)) != LF_OK) {
            free(block);
            return status == LF_ZIP_STOP ? LF_OK : status;
        }
    }
    free(block);
    return LF_OK;
}

int
lf_zip_scan(const lf_src *s, lf_zip_visit visit, void *ctx, uint64_t *count_out, uint64_t *end,
            lf_error *err)
{
    uint64_t cd_off = 0, cd_size = 0, count = 0;
    int status;

    if ((status = directory(s, &cd_off, &cd_size, &count, err)) != LF_OK)
        return status;
    if (count_out != NULL)
        *count_out = count;
    if (end != NULL)
        *end = cd_off + cd_size;
    return walk(s, cd_off, cd_off + cd_size, count, visit, ctx, err);
}

int
lf_zip_scan_range(const lf_src *s, uint64_t from, uint64_t to, lf_zip_visit visit, void *ctx,
                  lf_error *err)
{
    if (to > s->size)
        to = s->size;
    return walk(s, from, to, UINT64_MAX, visit, ctx, err);
}

int
lf_zip_extract(const lf_src *s, const lf_zip_entry *e, const char *name, uint64_t max,
               unsigned char **out, lf_error *err)
{
    unsigned char lfh[LFH_SIZE], *buf, *in = NULL;
    uint64_t data, done = 0;
    z_stream z;
    int status, zs = Z_OK;

    *out = NULL;
    if (e->flags & 1)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "%s is encrypted in the zip "
                          "archive (save it without a password)", name);
    if (e->method != 0 && e->method != 8)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "%s is compressed with method %u "
                          "(layerfit reads stored and deflated zip entries)", name,
                          (unsigned) e->method);
    /* deflate expands at most 1032-fold: a larger size is a damaged (or
     * hostile) entry, refused before anything is allocated */
    if (e->method == 8 && e->usize > 1032 * e->csize + 1024)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: %s states "
                          "%llu bytes uncompressed, more than its %llu compressed bytes can "
                          "hold", name, (unsigned long long) e->usize,
                          (unsigned long long) e->csize);
    if (e->usize > max || e->usize > SIZE_MAX - 1)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "%s: %llu bytes uncompressed, more "
                          "than a part of such a file holds (%llu at most)", name,
                          (unsigned long long) e->usize, (unsigned long long) max);
    if ((status = lf_src_read(s, e->offset, lfh, sizeof lfh, err)) != LF_OK)
        return status;
    if (memcmp(lfh, "PK\3\4", 4) != 0)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: no local "
                          "header for %s at byte %llu", name, (unsigned long long) e->offset);
    data = e->offset + LFH_SIZE + le16(lfh + 26) + le16(lfh + 28);
    if (data > s->size || e->csize > s->size - data)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: %s "
                          "(%llu bytes) runs past its end", name,
                          (unsigned long long) e->csize);
    if (e->method == 0 && e->csize != e->usize)
        return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: %s is "
                          "stored with two sizes (%llu and %llu bytes)", name,
                          (unsigned long long) e->csize, (unsigned long long) e->usize);
    buf = malloc(e->usize ? (size_t) e->usize : 1);
    if (buf == NULL)
        return lf_fail_at(err, LF_ENOMEM, s->name, 0, 0, "out of memory");
    if (e->method == 0) {
        if ((status = lf_src_read(s, data, buf, (size_t) e->usize, err)) != LF_OK) {
            free(buf);
            return status;
        }
    } else {
        memset(&z, 0, sizeof z);
        if (inflateInit2(&z, -MAX_WBITS) != Z_OK) {
            free(buf);
            return lf_fail_at(err, LF_ENOMEM, s->name, 0, 0, "out of memory (zlib)");
        }
        if (s->mem == NULL && (in = malloc(BLOCK)) == NULL) {
            inflateEnd(&z);
            free(buf);
            return lf_fail_at(err, LF_ENOMEM, s->name, 0, 0, "out of memory");
        }
        z.next_out = buf;
        z.avail_out = 0;
        while (zs != Z_STREAM_END) {
            if (z.avail_in == 0 && done < e->csize) {
                size_t n = e->csize - done < BLOCK ? (size_t) (e->csize - done) : BLOCK;
                if (s->mem != NULL) {
                    z.next_in = (unsigned char *) (uintptr_t) (s->mem + data + done);
                } else if ((status = lf_src_read(s, data + done, in, n, err)) != LF_OK) {
                    break;
                } else {
                    z.next_in = in;
                }
                z.avail_in = (uInt) n;
                done += n;
            }
            if (z.avail_out == 0) {
                uint64_t left = e->usize - (uint64_t) (z.next_out - buf);
                z.avail_out = left < UINT_MAX ? (uInt) left : UINT_MAX;
            }
            zs = inflate(&z, Z_NO_FLUSH);
            if (zs == Z_STREAM_END)
                break;
            if (zs != Z_OK && !(zs == Z_BUF_ERROR && z.avail_in == 0 && done < e->csize)) {
                status = lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: "
                                    "%s does not inflate (%s)", name,
                                    zs == Z_BUF_ERROR ? (z.avail_out == 0 ? "more bytes than its "
                                    "size" : "its data end early") : z.msg ? z.msg : "zlib error");
                break;
            }
        }
        if (status == LF_OK && (uint64_t) (z.next_out - buf) != e->usize)
            status = lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: %s "
                                "inflates to %llu bytes, not the %llu its header states", name,
                                (unsigned long long) (z.next_out - buf),
                                (unsigned long long) e->usize);
        inflateEnd(&z);
        free(in);
        if (status != LF_OK) {
            free(buf);
            return status;
        }
    }
    {
        uLong crc = crc32(0L, Z_NULL, 0);
        uint64_t k, step = (uint64_t) UINT_MAX / 2 + 1;
        for (k = 0; k < e->usize; k += step)
            crc = crc32(crc, buf + k, (uInt) (e->usize - k < step ? e->usize - k : step));
        if ((uint32_t) crc != e->crc) {
            free(buf);
            return lf_fail_at(err, LF_EFORMAT, s->name, 0, 0, "a damaged zip archive: %s fails "
                              "its CRC-32 check", name);
        }
    }
    *out = buf;
    return LF_OK;
}

/* lf_zip_describe: count the entries and keep the first names. */
typedef struct {
    char *buf;
    size_t n, len;
    unsigned long files, shown;
} describe_ctx;

static int
describe_one(void *ctx, const char *name, size_t nlen, const lf_zip_entry *e, lf_error *err)
{
    describe_ctx *d = ctx;
    (void) e;
    (void) err;
    if (nlen == 0 || name[nlen - 1] == '/')     /* a folder */
        return LF_OK;
    d->files++;
    if (d->shown < 3 && d->len < d->n) {
        char shown[80];
        lf_latin1_to_utf8(name, shown, sizeof shown);
        d->len += (size_t) snprintf(d->buf + d->len, d->n - d->len, "%s%s", d->shown ? ", " : "",
                                    shown);
        d->shown++;
    }
    return LF_OK;
}

int
lf_zip_describe(const lf_src *s, char *buf, size_t n, lf_error *err)
{
    char names[400];
    describe_ctx d;
    int status;

    d.buf = names;
    d.n = sizeof names;
    d.len = 0;
    d.files = d.shown = 0;
    names[0] = '\0';
    if ((status = lf_zip_scan(s, describe_one, &d, NULL, NULL, err)) != LF_OK)
        return status;
    if (d.files == 0)
        snprintf(buf, n, "no files");
    else
        snprintf(buf, n, "%lu file%s (%s%s)", d.files, d.files == 1 ? "" : "s", names,
                 d.files > d.shown ? ", ..." : "");
    return LF_OK;
}
