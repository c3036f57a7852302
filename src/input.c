/* input.c: opening input files safely, for every reader.
 *
 * A file is checked at the moment it is read, on the open descriptor (no
 * stat-then-open race): it is opened with O_NONBLOCK, so that opening a
 * FIFO never waits for a writer, and fstat decides what it is.  A regular
 * file is read as usual.  Anything else (FIFO, pipe, terminal, socket,
 * device) is refused unless the caller asks for a stream: then it is read
 * once, whole, into memory, waiting at most LF_STREAM_WAIT seconds for the
 * first byte (a named FIFO nobody writes to would otherwise block forever).
 * The SHA-256 of what was read comes from nettle. */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nettle/sha2.h>

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

int
lf_input_read(const char *path, unsigned flags, lf_input *in, lf_error *err)
{
    int fd, status;

    memset(in, 0, sizeof *in);
    if ((status = lf_input_open(path, flags, &fd, err)) != LF_OK)
        return status;
    status = lf_input_read_fd(fd, path, in, err);
    close(fd);
    return status;
}

int
lf_input_read_fd(int fd, const char *path, lf_input *in, lf_error *err)
{
    struct sha256_ctx ctx;
    uint8_t digest[SHA256_DIGEST_SIZE];
    size_t cap = 65536, i;

    memset(in, 0, sizeof *in);
    in->data = malloc(cap);
    if (in->data == NULL)
        return lf_fail_at(err, LF_ENOMEM, path, 0, 0, "out of memory");
    for (;;) {
        ssize_t r;
        if (in->len == cap) {
            char *d = cap > ((size_t) -1) / 2 ? NULL : realloc(in->data, 2 * cap);
            if (d == NULL) {
                lf_input_free(in);
                return lf_fail_at(err, LF_ENOMEM, path, 0, 0, "out of memory");
            }
            in->data = d;
            cap *= 2;
        }
        r = read(fd, in->data + in->len, cap - in->len);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            int e = errno;
            lf_input_free(in);
            return lf_fail_at(err, LF_EIO, path, 0, 0, "read error: %s", strerror(e));
        }
        if (r == 0)
            break;
        in->len += (size_t) r;
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
