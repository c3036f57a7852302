/* cli/output.c: what the command promises about its outputs.
 *
 * - Every output file is written to a temporary file in its own folder
 *   (mkstemp), flushed, fsync'ed, checked for every write and close error,
 *   and only then renamed over the old one: an interrupted or failed run
 *   leaves the earlier file as it was.  Temporary files of a run that dies
 *   through cli_die are removed at exit.
 * - An output that is the same file as an input (same device and inode, so
 *   that symlinks, hard links and "./" paths count) is refused.
 * - Text taken from data (file names, metadata) is written escaped for
 *   where it goes: JSON strings are valid UTF-8, gnuplot strings cannot be
 *   closed by the data, comments cannot be broken by a line break.
 * - Provenance: the version, the command line and the SHA-256 of every
 *   input, for the JSON, HTML and sidecar writers. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <linux/fs.h>
#endif

#include "cli.h"

/* ------------------------------------------------------------------------
 * Inputs and outputs of the run: collisions and provenance.
 * --------------------------------------------------------------------- */

typedef struct {
    char *path;
    dev_t dev;
    ino_t ino;
    int have_id;          /* dev/ino known (the file existed when noted) */
    char sha256[65];      /* "" when not hashed */
    char *where;          /* outputs: the real path of its folder + "/" +
                             its name ("-" for standard output), or NULL */
    int fifo;             /* outputs: a FIFO opened for writing once a reader
                             came (output_check), kept for cli_out_open; -1 */
} file_note;

static file_note *inputs, *outputs;
static size_t ninputs, noutputs;

static char *
dup_text(const char *s)
{
    char *d = malloc(strlen(s) + 1);
    if (d == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    return strcpy(d, s);
}

static void
note(file_note **list, size_t *n, const char *path, const char *sha256)
{
    file_note *l = realloc(*list, (*n + 1) * sizeof **list);
    struct stat st;
    if (l == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    *list = l;
    l += *n;
    memset(l, 0, sizeof *l);
    l->path = dup_text(path);
    l->fifo = -1;
    if (stat(path, &st) == 0) {
        l->dev = st.st_dev;
        l->ino = st.st_ino;
        l->have_id = 1;
    }
    if (sha256 != NULL)
        snprintf(l->sha256, sizeof l->sha256, "%s", sha256);
    (*n)++;
}

/* The input that path (an output) is, or NULL. */
static const char *
same_as_input(const char *path)
{
    struct stat st;
    size_t i;
    if (stat(path, &st) != 0)
        return NULL;
    for (i = 0; i < ninputs; i++)
        if (inputs[i].have_id && inputs[i].dev == st.st_dev && inputs[i].ino == st.st_ino)
            return inputs[i].path;
    return NULL;
}

int
cli_is_input(const char *path)
{
    return same_as_input(path) != NULL;
}

/* path split at its last slash, trailing slashes dropped ("figures/" names
 * the folder figures): *dir its folder ("/" for the root, NULL when path
 * names none), *name the rest.  Both point into the returned copy (free). */
static char *
split_path(const char *path, const char **dir, const char **name)
{
    char *copy = dup_text(path), *slash;
    size_t len;

    for (len = strlen(copy); len > 1 && copy[len - 1] == '/'; len--)
        copy[len - 1] = '\0';
    slash = strrchr(copy, '/');
    *dir = slash == NULL ? NULL : slash == copy ? "/" : copy;
    *name = slash == NULL ? copy : slash + 1;
    if (slash != NULL && slash != copy)
        *slash = '\0';
    return copy;
}

/* Where an output that may not exist yet will be: the real path of its
 * folder and its name ("-": standard output); NULL when its folder does
 * not resolve (then the folder check says so). */
static char *
output_where(const char *path)
{
    const char *dir, *name;
    char *copy, *real, *out = NULL;

    if (strcmp(path, "-") == 0)
        return dup_text("-");
    copy = split_path(path, &dir, &name);
    if ((real = realpath(dir != NULL ? dir : ".", NULL)) != NULL) {
        out = malloc(strlen(real) + strlen(name) + 2);
        if (out == NULL)
            cli_die(CLI_EXIT_FAIL, "out of memory");
        sprintf(out, "%s/%s", real, name);
        free(real);
    }
    free(copy);
    return out;
}

int
cli_same_place(const char *a, const char *b)
{
    char *pa = output_where(a), *pb = output_where(b);
    int same = pa != NULL && pb != NULL && strcmp(pa, pb) == 0;
    free(pa);
    free(pb);
    return same;
}

/* "PATH.provenance.json", the sidecar of output path (free). */
static char *
sidecar_path(const char *path)
{
    char *side = malloc(strlen(path) + sizeof ".provenance.json");

    if (side == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    sprintf(side, "%s.provenance.json", path);
    return side;
}

/* 1 when the regular file path cannot be replaced or removed whatever the
 * permissions (Linux: the immutable or append-only attribute). */
static int
file_immutable(const char *path)
{
#if defined(__linux__) && defined(FS_IOC_GETFLAGS)
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC), flags = 0, r;
    if (fd < 0)
        return 0;
    r = ioctl(fd, FS_IOC_GETFLAGS, &flags);
    close(fd);
    return r == 0 && (flags & (FS_IMMUTABLE_FL | FS_APPEND_FL)) != 0;
#else
    (void) path;
    return 0;
#endif
}

/* Open a FIFO (or other special file) output for writing without
 * blocking: a FIFO with no reader yet (ENXIO) is tried again for at most
 * LF_STREAM_WAIT seconds, as an input FIFO waits for a writer.  The
 * descriptor is made blocking for the writes.  -1 with errno (ENXIO: no
 * reader came). */
static int
open_special(const char *path)
{
    int fd, fl, tries;
    struct stat st;

    for (tries = 0;; tries++) {
        fd = open(path, O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
        if (fd >= 0 || errno != ENXIO || tries >= 20 * LF_STREAM_WAIT)
            break;
        {
            struct timespec ts = { 0, 50000000L };
            nanosleep(&ts, NULL);
        }
    }
    if (fd < 0)
        return -1;
    if (fstat(fd, &st) != 0 || S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)
        || (fl = fcntl(fd, F_GETFL)) < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        close(fd);
        errno = EINVAL;
        return -1;
    }
    return fd;
}

static const char *
special_error(int e)
{
    return e == ENXIO ? "it is a FIFO and nothing opened it for reading within 10 s "
                        "(start the reader first)"
                      : strerror(e);
}

/* The file an output named path replaces: path, or for a symbolic link
 * the file it names (malloc'ed, NULL with msg for a link to nothing). */
static char *
replaced_file(const char *path, char *msg, size_t n)
{
    struct stat st;
    char *target;

    if (!(lstat(path, &st) == 0 && S_ISLNK(st.st_mode)))
        return dup_text(path);
    if ((target = realpath(path, NULL)) == NULL)
        snprintf(msg, n, "cannot write %s: a symbolic link to %s", path,
                 errno == ENOENT ? "a file that does not exist" : strerror(errno));
    return target;
}

/* What can be known about writing path before any work: a name longer than
 * a file name may be, a symbolic link to nothing, a folder, a file that
 * cannot be replaced (immutable or append-only), a folder that cannot be
 * written; a FIFO is opened now (a reader waited for).  Dies with status
 * 2 (a name that cannot be one) or 1. */
static void
output_check(const char *cmd, const char *path, file_note *note_out)
{
    const char *dir, *name;
    char *copy, *target, msg[4400];
    struct stat st;

    if (strcmp(path, "-") == 0)
        return;
    copy = split_path(path, &dir, &name);
    if (strlen(name) > NAME_MAX)
        cli_die(CLI_EXIT_USAGE, "%s: cannot write %s: a file name has at most %d bytes (this "
                "one %zu)", cmd, path, NAME_MAX, strlen(name));
    free(copy);
    /* the file replaced: path, or what a link names */
    if ((target = replaced_file(path, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "%s: %s", cmd, msg);
    if (stat(target, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            cli_die(CLI_EXIT_FAIL, "%s: cannot write %s: it is a folder", cmd, path);
        if (S_ISREG(st.st_mode) && file_immutable(target))
            cli_die(CLI_EXIT_FAIL, "%s: cannot replace %s: it is immutable or append-only "
                    "(chattr -i -a removes that)", cmd, path);
        if (!S_ISREG(st.st_mode)) {
            /* written in place: opened now, so that a FIFO without a
             * reader is said before the work, not after it */
            int fd = open_special(path);
            if (fd < 0)
                cli_die(CLI_EXIT_FAIL, "%s: cannot write %s: %s", cmd, path, special_error(errno));
            note_out->fifo = fd;
            free(target);
            return;
        }
    }
    /* replaced by a rename in the target's folder (a missing folder is
     * cli_output_folder_check's to say) */
    copy = split_path(target, &dir, &name);
    if (dir == NULL)
        dir = ".";
    if (stat(dir, &st) == 0 && access(dir, W_OK | X_OK) != 0)
        cli_die(CLI_EXIT_FAIL, "%s: cannot write %s: the folder %s cannot be written (%s)",
                cmd, path, dir, strerror(errno));
    free(copy);
    free(target);
}

void
cli_output_note(const char *cmd, const char *path)
{
    const char *in;
    struct stat st;
    char *where;
    size_t i;
    int exists;

    if (path == NULL)
        return;
    if (*path == '\0')
        cli_die(CLI_EXIT_USAGE, "%s: an output needs a name (got an empty one)", cmd);
    if ((in = same_as_input(path)) != NULL)
        cli_die(CLI_EXIT_USAGE, "%s: output %s is the input %s: refusing to replace an input "
                "(name another output)", cmd, path, in);
    /* two outputs of one run in one file: the later would replace the
     * earlier (same file by device and inode where it exists, else by
     * where it will be) */
    exists = strcmp(path, "-") != 0 && stat(path, &st) == 0;
    where = output_where(path);
    for (i = 0; i < noutputs; i++) {
        const file_note *o = &outputs[i];
        if ((exists && o->have_id && o->dev == st.st_dev && o->ino == st.st_ino)
            || (where != NULL && o->where != NULL && strcmp(where, o->where) == 0)) {
            if (strcmp(path, "-") == 0)
                cli_die(CLI_EXIT_USAGE, "%s: two outputs to standard output ('-'): name a file "
                        "for all but one", cmd);
            if (strcmp(path, o->path) == 0)
                cli_die(CLI_EXIT_USAGE, "%s: %s is named for two outputs: one would replace the "
                        "other (name them apart)", cmd, path);
            cli_die(CLI_EXIT_USAGE, "%s: outputs %s and %s are the same file: one would "
                    "replace the other (name them apart)", cmd, o->path, path);
        }
    }
    note(&outputs, &noutputs, path, NULL);
    outputs[noutputs - 1].where = where;
    output_check(cmd, path, &outputs[noutputs - 1]);
}

void
cli_output_note_sidecar(const char *cmd, const char *path)
{
    struct stat st;
    char *side;

    /* an output written in place (standard output, a pipe, a device) has
     * no sidecar: /dev/stdout.provenance.json is nothing to make */
    if (path == NULL || strcmp(path, "-") == 0 || (stat(path, &st) == 0 && !S_ISREG(st.st_mode)))
        return;
    side = sidecar_path(path);
    cli_output_note(cmd, side);
    free(side);
}

void
cli_output_folder_check(const char *cmd, const char *path)
{
    const char *dir, *name;
    char *copy;
    struct stat st;

    if (path == NULL || strcmp(path, "-") == 0)
        return;
    copy = split_path(path, &dir, &name);
    if (dir != NULL && (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)))
        cli_die(CLI_EXIT_FAIL, "%s: cannot write %s: there is no folder %s", cmd, path, dir);
    free(copy);
}

void
cli_input_guard(const char *cmd, const char *path)
{
    struct stat st;
    size_t i;
    if (stat(path, &st) != 0)
        return;   /* the reader says what is wrong with it */
    for (i = 0; i < noutputs; i++) {
        struct stat so;
        if (stat(outputs[i].path, &so) == 0 && so.st_dev == st.st_dev && so.st_ino == st.st_ino)
            cli_die(CLI_EXIT_USAGE, "%s: output %s is the input %s: refusing to replace an "
                    "input (name another output)", cmd, outputs[i].path, path);
    }
}

void
cli_input_note(const char *path, const char *sha256)
{
    note(&inputs, &ninputs, path, sha256);
}

size_t
cli_inputs_count(void)
{
    return ninputs;
}

const char *
cli_input_path(size_t i)
{
    return inputs[i].path;
}

const char *
cli_input_sha256(size_t i)
{
    return inputs[i].sha256;
}

/* ------------------------------------------------------------------------
 * Atomic output files.
 * --------------------------------------------------------------------- */

int
cli_tmp_name(const char *path, char **tmp)
{
    const char *slash = strrchr(path, '/');
    size_t nd = slash ? (size_t) (slash - path) + 1 : 0;
    const char *base = path + nd;
    size_t nb = strlen(base);
    char *t = malloc(nd + nb + 16);
    if (t == NULL)
        return -1;
    /* ".NAME.XXXXXX" has 8 bytes more than NAME: a long name is cut so
     * that the temporary name still fits in NAME_MAX */
    if (nb > NAME_MAX - 8)
        nb = NAME_MAX - 8;
    memcpy(t, path, nd);
    t[nd] = '.';
    memcpy(t + nd + 1, base, nb);
    strcpy(t + nd + 1 + nb, ".XXXXXX");
    *tmp = t;
    return 0;
}

/* An output that is no regular file to replace: standard output ("-"), or
 * an existing pipe, device or socket (a link to one: /dev/stdout), opened
 * for writing in place without blocking (a FIFO waits, boundedly, for a
 * reader: open_special).  1 when it was one (o->f NULL with msg on
 * failure), 0 for a path to be written atomically. */
static int
open_direct(cli_out *o, const char *path, char *msg, size_t n)
{
    struct stat st;
    size_t i;
    int fd = -1;

    if (strcmp(path, "-") == 0) {
        o->f = stdout;
        o->direct = 1;
        return 1;
    }
    if (stat(path, &st) != 0 || S_ISREG(st.st_mode))
        return 0;
    if (S_ISDIR(st.st_mode)) {
        snprintf(msg, n, "cannot write %s: it is a folder", path);
        return 1;
    }
    for (i = 0; i < noutputs; i++)      /* opened by output_check */
        if (outputs[i].fifo >= 0 && strcmp(outputs[i].path, path) == 0) {
            fd = outputs[i].fifo;
            outputs[i].fifo = -1;
            break;
        }
    if (fd < 0 && (fd = open_special(path)) < 0) {
        snprintf(msg, n, "cannot write %s: %s", path, special_error(errno));
        return 1;
    }
    if ((o->f = fdopen(fd, "w")) == NULL) {
        snprintf(msg, n, "cannot write %s: %s", path, strerror(errno));
        close(fd);
        return 1;
    }
    o->direct = 1;
    return 1;
}

FILE *
cli_out_open(cli_out *o, const char *path, char *msg, size_t n)
{
    const char *in;
    char *target;
    mode_t mask;
    int fd;

    memset(o, 0, sizeof o[0]);
    o->slot = -1;
    if ((in = same_as_input(path)) != NULL) {
        snprintf(msg, n, "output %s is the input %s: refusing to replace an input", path, in);
        return NULL;
    }
    if (open_direct(o, path, msg, n)) {
        if (o->f != NULL) {
            o->path = dup_text(path);
            o->name = dup_text(path);
        }
        return o->f;
    }
    /* a link: what it names is replaced, the link stays */
    if ((target = replaced_file(path, msg, n)) == NULL)
        return NULL;
    if (cli_tmp_name(target, &o->tmp) != 0) {
        free(target);
        snprintf(msg, n, "out of memory");
        return NULL;
    }
    fd = mkstemp(o->tmp);
    if (fd < 0) {
        snprintf(msg, n, "cannot write %s: %s", path, strerror(errno));
        free(o->tmp);
        free(target);
        o->tmp = NULL;
        return NULL;
    }
    o->slot = cli_temp_add(o->tmp, 0);
    /* mkstemp makes 0600; an output gets the usual 0666 less the umask */
    mask = umask(0);
    umask(mask);
    (void) fchmod(fd, 0666 & ~mask);
    o->f = fdopen(fd, "w");
    if (o->f == NULL) {
        snprintf(msg, n, "cannot write %s: %s", path, strerror(errno));
        close(fd);
        unlink(o->tmp);
        cli_temp_forget(o->slot);
        free(o->tmp);
        free(target);
        o->tmp = NULL;
        return NULL;
    }
    o->path = target;
    o->name = dup_text(path);
    return o->f;
}

/* Flush, fsync and close the temporary of o: 0, or -1 with msg (the
 * temporary is then removed). */
static int
finish_tmp(cli_out *o, char *msg, size_t n)
{
    int bad = 0, e = 0;

    if (fflush(o->f) != 0 || ferror(o->f))
        bad = 1, e = errno;
    if (!bad && fsync(fileno(o->f)) != 0)
        bad = 1, e = errno;
    if (fclose(o->f) != 0 && !bad)
        bad = 1, e = errno;
    o->f = NULL;
    if (bad) {
        snprintf(msg, n, "error writing %s: %s", o->path, e ? strerror(e) : "write failed");
        unlink(o->tmp);
    }
    return bad ? -1 : 0;
}

static void
release(cli_out *o)
{
    cli_temp_forget(o->slot);
    free(o->tmp);
    free(o->path);
    free(o->name);
    o->tmp = o->path = o->name = NULL;
    o->slot = -1;
}

/* Finish a direct output: flushed (standard output stays open for the
 * report), closed otherwise. */
static int
commit_direct(cli_out *o, char *msg, size_t n)
{
    int bad = fflush(o->f) != 0 || ferror(o->f), e = bad ? errno : 0;

    if (o->f != stdout && fclose(o->f) != 0 && !bad)
        bad = 1, e = errno;
    if (bad)
        snprintf(msg, n, "error writing %s: %s", o->path, e ? strerror(e) : "write failed");
    o->f = NULL;
    release(o);
    return bad ? -1 : 0;
}

int
cli_out_commit(cli_out *o, char *msg, size_t n)
{
    int bad;

    if (o->f == NULL)
        return -1;
    if (o->direct)
        return commit_direct(o, msg, n);
    bad = finish_tmp(o, msg, n) != 0;
    if (!bad && rename(o->tmp, o->path) != 0) {
        snprintf(msg, n, "error writing %s: %s", o->path, strerror(errno));
        unlink(o->tmp);
        bad = 1;
    }
    release(o);
    return bad ? -1 : 0;
}

void
cli_out_discard(cli_out *o)
{
    if (o->f != NULL && o->f != stdout)
        fclose(o->f);
    if (o->tmp != NULL)
        unlink(o->tmp);
    release(o);
    memset(o, 0, sizeof o[0]);
    o->slot = -1;
}

/* An exclusive lock on the folder that holds path (flock: held by the
 * descriptor, so a run that dies lets it go), or -1 where the system
 * gives none (then the pair is put in place unlocked). */
static int
lock_folder_of(const char *path)
{
    const char *dir, *name;
    char *copy = split_path(path, &dir, &name);
    int fd = open(dir != NULL ? dir : ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);

    free(copy);
    if (fd >= 0 && flock(fd, LOCK_EX) != 0) {
        close(fd);
        fd = -1;
    }
    return fd;
}

/* Both temporaries written and checked, then both renamed into place
 * under one lock, with signals held: another run that writes the same
 * pair waits for the lock, so the last to commit leaves its pair whole.
 * If the second rename fails, the first is undone (the earlier main file
 * was kept as a hard link for that), so a failed run leaves the earlier
 * pair as it was. */
static int
commit_pair(cli_out *o, cli_out *side, char *msg, size_t n)
{
    char *keep = NULL;
    int lock, bad = 0, had_main;
    struct stat st;

    if (finish_tmp(o, msg, n) != 0) {
        cli_out_discard(side);
        release(o);
        return -1;
    }
    if (finish_tmp(side, msg, n) != 0) {
        unlink(o->tmp);
        release(o);
        release(side);
        return -1;
    }
    cli_signals_hold();
    lock = lock_folder_of(o->path);
    had_main = lstat(o->path, &st) == 0;
    if (had_main && cli_tmp_name(o->path, &keep) == 0) {
        int fd = mkstemp(keep);
        /* the name reserved, then taken by a link to the earlier file */
        if (fd < 0 || (close(fd), unlink(keep), link(o->path, keep)) != 0) {
            free(keep);
            keep = NULL;
        }
    }
    if (rename(o->tmp, o->path) != 0) {
        snprintf(msg, n, "error writing %s: %s", o->path, strerror(errno));
        unlink(o->tmp);
        unlink(side->tmp);
        bad = 1;
    } else if (rename(side->tmp, side->path) != 0) {
        snprintf(msg, n, "error writing %s: %s (%s is left as it was)", side->path,
                 strerror(errno), o->path);
        unlink(side->tmp);
        if (keep != NULL)
            (void) rename(keep, o->path);
        else if (!had_main)
            (void) unlink(o->path);
        bad = 1;
    }
    if (keep != NULL) {
        (void) unlink(keep);
        free(keep);
    }
    if (lock >= 0)
        close(lock);
    release(o);
    release(side);
    cli_signals_release();
    return bad ? -1 : 0;
}

int
cli_out_commit_sidecar(cli_out *o, const char *command_line, char *msg, size_t n)
{
    cli_out side;
    char *spath;
    FILE *f;

    if (o->f == NULL)
        return -1;
    if (o->direct)          /* written in place: no sidecar */
        return cli_out_commit(o, msg, n);
    spath = sidecar_path(o->name);
    f = cli_out_open(&side, spath, msg, n);
    free(spath);
    if (f == NULL) {
        cli_out_discard(o);
        return -1;
    }
    cli_provenance_json(f, "", command_line);
    fputc('\n', f);
    if (side.direct) {
        /* a pipe or device where the sidecar goes: written in place after
         * the output (nothing there to keep whole) */
        if (cli_out_commit(o, msg, n) != 0) {
            cli_out_discard(&side);
            return -1;
        }
        return cli_out_commit(&side, msg, n);
    }
    return commit_pair(o, &side, msg, n);
}

int
cli_put_in_place(const char *from, const char *to, char *msg, size_t n)
{
    char *target = replaced_file(to, msg, n);
    int status = 0;

    if (target == NULL)
        return -1;
    if (cli_is_input(target)) {
        snprintf(msg, n, "output %s is an input: refusing to replace an input", to);
        status = -1;
    } else if (rename(from, target) != 0) {
        if (errno == EXDEV) {
            /* the link names a file on another file system: copied there
             * through a temporary beside it */
            cli_out o;
            FILE *in = fopen(from, "rb"), *out = in ? cli_out_open(&o, target, msg, n) : NULL;
            char buf[65536];
            size_t got;
            if (in == NULL || out == NULL) {
                if (in == NULL)
                    snprintf(msg, n, "cannot read %s: %s", from, strerror(errno));
                status = -1;
            } else {
                while ((got = fread(buf, 1, sizeof buf, in)) > 0)
                    fwrite(buf, 1, got, out);
                if (ferror(in)) {
                    cli_out_discard(&o);
                    snprintf(msg, n, "cannot read %s", from);
                    status = -1;
                } else {
                    status = cli_out_commit(&o, msg, n);
                }
            }
            if (in != NULL)
                fclose(in);
            unlink(from);
        } else {
            snprintf(msg, n, "cannot put %s in place: %s", to, strerror(errno));
            status = -1;
        }
    }
    free(target);
    return status;
}

/* cli_write_file and cli_write_file_sidecar (command_line: the sidecar's;
 * NULL: none). */
static void
write_file(const char *cmd, const char *path, const char *command_line,
           void (*writer)(FILE *, const void *), const void *ctx)
{
    cli_out o;
    char msg[4400];
    FILE *f = cli_out_open(&o, path, msg, sizeof msg);
    if (f == NULL)
        cli_die(CLI_EXIT_FAIL, "%s: %s", cmd, msg);
    writer(f, ctx);
    if ((command_line != NULL ? cli_out_commit_sidecar(&o, command_line, msg, sizeof msg)
                              : cli_out_commit(&o, msg, sizeof msg)) != 0)
        cli_die(CLI_EXIT_FAIL, "%s: %s", cmd, msg);
}

void
cli_write_file(const char *cmd, const char *path, void (*writer)(FILE *, const void *),
               const void *ctx)
{
    write_file(cmd, path, NULL, writer, ctx);
}

void
cli_write_file_sidecar(const char *cmd, const char *path, const char *command_line,
                       void (*writer)(FILE *, const void *), const void *ctx)
{
    write_file(cmd, path, command_line != NULL ? command_line : "", writer, ctx);
}

void
cli_refuse_existing(const char *cmd, const char *path, int force)
{
    struct stat st;
    if (!force && lstat(path, &st) == 0)
        cli_die(CLI_EXIT_USAGE, "%s: %s exists: not replaced without --force", cmd, path);
    if (same_as_input(path) != NULL)
        cli_die(CLI_EXIT_USAGE, "%s: output %s is an input: refusing to replace it", cmd, path);
}

int
cli_stdout_close(void)
{
    int bad = fflush(stdout) != 0 || ferror(stdout);
    if (fclose(stdout) != 0)
        bad = 1;
    if (bad) {
        cli_say("error writing standard output: %s",
                errno ? strerror(errno) : "write failed");
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------------------
 * Text from data, escaped for where it goes.
 * --------------------------------------------------------------------- */

static void
put_file(void *ctx, const char *s, size_t n)
{
    fwrite(s, 1, n, (FILE *) ctx);
}

void
cli_put_clean(FILE *f, const char *s)
{
    cli_text_clean(s, 0, put_file, f);
}

void
cli_json_string(FILE *f, const char *s)
{
    cli_json_escape(s, put_file, f);
}

void
cli_put_csv_cell(FILE *f, const char *s)
{
    cli_csv_cell(s, put_file, f);
}

int cli_csv_raw;

void
cli_csv_cell(const char *s, void (*put)(void *, const char *, size_t), void *ctx)
{
    lf_csv_cell(s, cli_csv_raw, put, ctx);
}

void
cli_gnuplot_string(FILE *g, const char *s)
{
    const unsigned char *p = (const unsigned char *) (s ? s : "");
    fputc('\'', g);
    while (*p) {
        size_t n = lf_utf8_len(p);
        if (n == 0) {
            fputc('?', g);
            p++;
        } else if (*p == '\'') {
            fputs("''", g);        /* the only special character of '...' */
            p++;
        } else if (n == 1 && (*p < 0x20 || *p == 0x7F)) {
            fputc(' ', g);         /* a line break would end the command */
            p++;
        } else {
            fwrite(p, 1, n, g);
            p += n;
        }
    }
    fputc('\'', g);
}

/* ------------------------------------------------------------------------
 * Provenance.
 * --------------------------------------------------------------------- */

void
cli_provenance_of(const char *command_line, lf_provenance *p)
{
    const char **path = malloc((ninputs ? ninputs : 1) * sizeof *path);
    const char **sha = malloc((ninputs ? ninputs : 1) * sizeof *sha);
    size_t i;

    if (path == NULL || sha == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    for (i = 0; i < ninputs; i++) {
        path[i] = inputs[i].path;
        sha[i] = inputs[i].sha256;
    }
    p->command_line = command_line;
    p->ninputs = ninputs;
    p->input = path;
    p->sha256 = sha;
}

void
cli_provenance_free(lf_provenance *p)
{
    free((void *) p->input);
    free((void *) p->sha256);
}

void
cli_provenance_json(FILE *f, const char *indent, const char *command_line)
{
    lf_provenance p;
    lf_error err;
    char *json;

    cli_provenance_of(command_line, &p);
    if (lf_provenance_json(&p, indent, &json, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "%s", err.msg);
    fputs(json, f);
    lf_free(json);
    cli_provenance_free(&p);
}

