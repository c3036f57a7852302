/* input.c: opening input files safely, for every reader.
 *
 * A file is checked at the moment it is read, on the open descriptor (no
 * stat-then-open race): it is opened with O_NONBLOCK, so that opening a
 * FIFO never waits for a writer, and fstat decides what it is.  A regular
 * file is read as usual.  Anything else (FIFO, pipe, terminal, socket,
 * device) is refused unless the caller asks for a stream: then it is read
 * once, whole, into memory, waiting at most LF_STREAM_WAIT seconds for the
 * first byte (a named FIFO nobody writes to would otherwise block forever).
 * What is read whole is bounded: a regular file larger than the limit
 * (lf_input_set_limit, LF_INPUT_LIMIT by default) is refused from its size
 * before a byte is read, a stream once it has passed the limit; an input
 * read as text (LF_INPUT_TEXT) stops being read as soon as it shows binary
 * data or a line longer than the line layer takes.  The SHA-256 of what
 * was read comes from nettle. */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nettle/sha2.h>

#include "csvsplit.h"
#include "internal.h"

int
lf_input_open(const char *path, unsigned flags, int *fd_out, lf_error *err)
{
    struct stat st;
    int fd, fl;

    *fd_out = -1;
    fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0)
        return lf_fail_at(err, LF_EIO, path, 0, 0, "cannot open: %s", strerror(errno));
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return lf_fail_at(err, LF_EIO, path, 0, 0, "cannot inspect: %s", strerror(e));
    }
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        return lf_fail_at(err, LF_EIO, path, 0, 0, "is a directory (expected a CSV file)");
    }
    if (!S_ISREG(st.st_mode) && !(flags & LF_INPUT_STREAM)) {
        close(fd);
        return lf_fail_at(err, LF_EIO, path, 0, 0, "is not a regular file (%s; name a "
                          "CSV file)", S_ISFIFO(st.st_mode) ? "a FIFO or pipe"
                          : S_ISCHR(st.st_mode) ? "a device" : "a special file");
    }
    if (!S_ISREG(st.st_mode)) {
        /* a stream: wait, boundedly, for a writer to say something */
        struct pollfd p;
        int r;
        p.fd = fd;
        p.events = POLLIN;
        p.revents = 0;
        do
            r = poll(&p, 1, LF_STREAM_WAIT * 1000);
        while (r < 0 && errno == EINTR);
        if (r == 0) {
            close(fd);
            return lf_fail_at(err, LF_EIO, path, 0, 0, "nothing to read after %d s (a FIFO "
                              "needs a writer: start it first)", LF_STREAM_WAIT);
        }
    }
    fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        int e = errno;
        close(fd);
        return lf_fail_at(err, LF_EIO, path, 0, 0, "cannot read: %s", strerror(e));
    }
    *fd_out = fd;
    return LF_OK;
}

/* The most bytes lf_input_read reads whole (lf_input_set_limit). */
static _Atomic size_t input_limit = LF_INPUT_LIMIT;

void
lf_input_set_limit(size_t bytes)
{
    atomic_store(&input_limit, bytes);
}

size_t
lf_input_limit(void)
{
    return atomic_load(&input_limit);
}

/* "256 MiB", "1.5 GiB", "700 KiB": a size for messages. */
static void
size_words(char *buf, size_t n, double bytes)
{
    static const char *const unit[] = { "bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB" };
    size_t u = 0;
    while (bytes >= 1024.0 && u + 1 < sizeof unit / sizeof unit[0]) {
        bytes /= 1024.0;
        u++;
    }
    snprintf(buf, n, "%.4g %s", bytes, unit[u]);
}

/* A regular file of size bytes, or a stream (size < 0), over the limit. */
static int
too_big(lf_error *err, const char *path, double size, size_t limit)
{
    char a[32], b[32];
    size_words(a, sizeof a, size);
    size_words(b, sizeof b, (double) limit);
    return lf_fail_at(err, LF_EIO, path, 0, 0, "%s%s%s more than the %s layerfit reads whole "
                      "(--max-input SIZE raises it, e.g. --max-input 2GiB)",
                      size >= 0 ? "holds " : "", size >= 0 ? a : "", size >= 0 ? "," : "goes on for",
                      b);
}

int
lf_input_check_size(int fd, const char *path, lf_error *err)
{
    struct stat st;
    const size_t limit = lf_input_limit();

    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && (uintmax_t) st.st_size > (uintmax_t) limit)
        return too_big(err, path, (double) st.st_size, limit);
    return LF_OK;
}

/* The checks of the CSV line layer (csvsplit.c), made while the bytes
 * arrive, so that a stream of binary data or of one endless line stops
 * being read at once instead of after it has filled the memory: reading
 * stops just past the first byte the line layer refuses (a control byte,
 * the second byte of a UTF-16 byte order mark, the byte that makes a line
 * longer than LF_CSV_MAX_LINE).  The bytes kept end there, so that the
 * reader, which meets every line in order, refuses them with its own
 * message at the same place as it would the whole input. */
typedef struct {
    size_t linelen;     /* bytes of the line so far */
    size_t at;          /* bytes seen */
    int prev_cr;
    unsigned char first;
} text_check;

/* How many of the n bytes at p to keep: n, or up to the first refused.
 * Past the first two bytes (a byte order mark's), a printable byte (the
 * bulk of any text) only lengthens its line: that test comes first. */
static size_t
text_scan(text_check *t, const unsigned char *p, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned char c = p[i];
        size_t at = t->at++;
        if (at >= 2 && c >= 0x20 && c != 0x7F) {
            t->prev_cr = 0;
            if (++t->linelen > (size_t) LF_CSV_MAX_LINE)
                return i + 1;
            continue;
        }
        if (at == 0)
            t->first = c;
        if (at == 1 && (t->first == 0xFF || t->first == 0xFE) && (c == 0xFE || c == 0xFF))
            return i + 1;
        if (c == '\n' || c == '\r') {
            if (!(c == '\n' && t->prev_cr))
                t->linelen = 0;
            t->prev_cr = c == '\r';
            continue;
        }
        t->prev_cr = 0;
        if (++t->linelen > (size_t) LF_CSV_MAX_LINE || (c < 0x20 && c != '\t') || c == 0x7F)
            return i + 1;
    }
    return n;
}

int
lf_input_read_path(const char *path, unsigned flags, int (*binary)(const char *, size_t),
                   lf_input *in, lf_error *err)
{
    int fd, status;

    memset(in, 0, sizeof *in);
    if ((status = lf_input_open(path, flags, &fd, err)) != LF_OK)
        return status;
    status = lf_input_read_fd(fd, path, flags, binary, in, err);
    close(fd);
    return status;
}

int
lf_input_read(const char *path, unsigned flags, lf_input *in, lf_error *err)
{
    return lf_input_read_path(path, flags, NULL, in, err);
}

int
lf_input_read_fd(int fd, const char *path, unsigned flags,
                 int (*binary)(const char *head, size_t len), lf_input *in, lf_error *err)
{
    struct sha256_ctx ctx;
    uint8_t digest[SHA256_DIGEST_SIZE];
    const size_t limit = lf_input_limit();
    size_t cap = 65536, scanned = 0, i;
    text_check tc = { 0, 0, 0, 0 };
    int text = (flags & LF_INPUT_TEXT) != 0, decided = binary == NULL, status;
    struct stat st;

    memset(in, 0, sizeof *in);
    /* a regular file says its size: refused before a byte is read */
    if ((status = lf_input_check_size(fd, path, err)) != LF_OK)
        return status;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= 0
        && (uintmax_t) st.st_size < (uintmax_t) limit)
        cap = (size_t) st.st_size + 1;
    in->data = malloc(cap);
    if (in->data == NULL)
        return lf_fail_at(err, LF_ENOMEM, path, 0, 0, "out of memory");
    for (;;) {
        ssize_t r;
        if (in->len == cap) {
            size_t grown = cap > limit / 2 ? limit + 1 : 2 * cap;
            char *d = grown <= cap ? NULL : realloc(in->data, grown);
            if (d == NULL) {
                lf_input_free(in);
                return lf_fail_at(err, LF_ENOMEM, path, 0, 0, "out of memory");
            }
            in->data = d;
            cap = grown;
        }
        r = read(fd, in->data + in->len, cap - in->len);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            int e = errno;
            lf_input_free(in);
            return lf_fail_at(err, LF_EIO, path, 0, 0, "read error: %s", strerror(e));
        }
        in->len += (size_t) r;
        /* whether the input is text is the caller's to say from its first
         * LF_SNIFF_BYTES (a binary format read as a stream) */
        if (!decided && (r == 0 || in->len >= LF_SNIFF_BYTES)) {
            decided = 1;
            text = text && !binary(in->data, in->len < LF_SNIFF_BYTES ? in->len : LF_SNIFF_BYTES);
        }
        if (decided && text && scanned < in->len) {
            size_t keep = text_scan(&tc, (const unsigned char *) in->data + scanned,
                                    in->len - scanned);
            if (keep < in->len - scanned) {
                in->len = scanned + keep;
                in->stopped = 1;    /* what follows is never read */
                break;
            }
            scanned = in->len;
        }
        if (r == 0)
            break;
        if (in->len > limit) {
            lf_input_free(in);
            return too_big(err, path, -1.0, limit);
        }
    }
    sha256_init(&ctx);
    sha256_update(&ctx, in->len, (const uint8_t *) in->data);
    sha256_digest(&ctx, sizeof digest, digest);
    for (i = 0; i < sizeof digest; i++) {
        static const char hex[] = "0123456789abcdef";
        in->sha256[2 * i] = hex[digest[i] >> 4];
        in->sha256[2 * i + 1] = hex[digest[i] & 15];
    }
    in->sha256[64] = '\0';
    return LF_OK;
}

void
lf_input_free(lf_input *in)
{
    if (in == NULL)
        return;
    free(in->data);
    in->data = NULL;
    in->len = 0;
}
