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
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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
}

void
cli_output_note_sidecar(const char *cmd, const char *path)
{
    char *side;

    if (path == NULL || strcmp(path, "-") == 0)
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

static cli_out *pending;        /* open outputs, removed at exit if not committed */
static int cleanup_set;

static void
remove_pending(void)
{
    cli_out *o;
    for (o = pending; o != NULL; o = o->next)
        if (o->tmp != NULL)
            unlink(o->tmp);
}

static void
unlink_pending(cli_out *o)
{
    cli_out **p;
    for (p = &pending; *p != NULL; p = &(*p)->next)
        if (*p == o) {
            *p = o->next;
            break;
        }
    o->next = NULL;
}

int
cli_tmp_name(const char *path, char **tmp)
{
    const char *slash = strrchr(path, '/');
    size_t nd = slash ? (size_t) (slash - path) + 1 : 0;
    const char *base = path + nd;
    char *t = malloc(nd + strlen(base) + 16);
    if (t == NULL)
        return -1;
    memcpy(t, path, nd);
    sprintf(t + nd, ".%s.XXXXXX", base);
    *tmp = t;
    return 0;
}

/* An output that is no regular file to replace: standard output ("-"), or
 * an existing pipe, device or socket (a link to one: /dev/stdout), opened
 * for writing in place.  1 when it was one (o->f NULL with msg on failure),
 * 0 for a path to be written atomically. */
static int
open_direct(cli_out *o, const char *path, char *msg, size_t n)
{
    struct stat st;
    int fd;

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
    fd = open(path, O_WRONLY | O_NOCTTY);
    if (fd < 0 || (o->f = fdopen(fd, "w")) == NULL) {
        snprintf(msg, n, "cannot write %s: %s", path, strerror(errno));
        if (fd >= 0)
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
    char *target = NULL;
    struct stat st;
    mode_t mask;
    int fd;

    memset(o, 0, sizeof o[0]);
    if ((in = same_as_input(path)) != NULL) {
        snprintf(msg, n, "output %s is the input %s: refusing to replace an input", path, in);
        return NULL;
    }
    if (open_direct(o, path, msg, n)) {
        if (o->f != NULL)
            o->path = dup_text(path);
        return o->f;
    }
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) {
        /* replace what the link names, not the link */
        if ((target = realpath(path, NULL)) == NULL) {
            snprintf(msg, n, "cannot write %s: a symbolic link to %s", path,
                     errno == ENOENT ? "a file that does not exist" : strerror(errno));
            return NULL;
        }
        path = target;
    }
    if (cli_tmp_name(path, &o->tmp) != 0) {
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
    /* mkstemp makes 0600; an output gets the usual 0666 less the umask */
    mask = umask(0);
    umask(mask);
    (void) fchmod(fd, 0666 & ~mask);
    o->f = fdopen(fd, "w");
    if (o->f == NULL) {
        snprintf(msg, n, "cannot write %s: %s", path, strerror(errno));
        close(fd);
        unlink(o->tmp);
        free(o->tmp);
        free(target);
        o->tmp = NULL;
        return NULL;
    }
    o->path = dup_text(path);
    free(target);
    if (!cleanup_set) {
        atexit(remove_pending);
        cleanup_set = 1;
    }
    o->next = pending;
    pending = o;
    return o->f;
}

int
cli_out_commit(cli_out *o, char *msg, size_t n)
{
    int bad = 0, e = 0;

    if (o->f == NULL)
        return -1;
    if (o->direct) {
        /* in place: flushed (standard output stays open for the report) */
        bad = fflush(o->f) != 0 || ferror(o->f);
        e = bad ? errno : 0;
        if (o->f != stdout && fclose(o->f) != 0 && !bad)
            bad = 1, e = errno;
        if (bad)
            snprintf(msg, n, "error writing %s: %s", o->path, e ? strerror(e) : "write failed");
        o->f = NULL;
        free(o->path);
        o->path = NULL;
        return bad ? -1 : 0;
    }
    if (fflush(o->f) != 0 || ferror(o->f))
        bad = 1, e = errno;
    if (!bad && fsync(fileno(o->f)) != 0)
        bad = 1, e = errno;
    if (fclose(o->f) != 0 && !bad)
        bad = 1, e = errno;
    o->f = NULL;
    if (!bad && rename(o->tmp, o->path) != 0)
        bad = 1, e = errno;
    if (bad) {
        snprintf(msg, n, "error writing %s: %s", o->path, e ? strerror(e) : "write failed");
        unlink(o->tmp);
    }
    unlink_pending(o);
    free(o->tmp);
    free(o->path);
    o->tmp = o->path = NULL;
    return bad ? -1 : 0;
}

void
cli_out_discard(cli_out *o)
{
    if (o->f != NULL && o->f != stdout)
        fclose(o->f);
    if (o->tmp != NULL)
        unlink(o->tmp);
    unlink_pending(o);
    free(o->tmp);
    free(o->path);
    memset(o, 0, sizeof o[0]);
}

void
cli_write_file(const char *cmd, const char *path, void (*writer)(FILE *, const void *),
               const void *ctx)
{
    cli_out o;
    char msg[4400];
    FILE *f = cli_out_open(&o, path, msg, sizeof msg);
    if (f == NULL)
        cli_die(CLI_EXIT_FAIL, "%s: %s", cmd, msg);
    writer(f, ctx);
    if (cli_out_commit(&o, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "%s: %s", cmd, msg);
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
        fprintf(stderr, "layerfit: error writing standard output: %s\n",
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

static void
sidecar_writer(FILE *f, const void *ctx)
{
    cli_provenance_json(f, "", ctx);
    fputc('\n', f);
}

void
cli_provenance_sidecar(const char *cmd, const char *output, const char *command_line)
{
    char *path = sidecar_path(output);
    cli_write_file(cmd, path, sidecar_writer, command_line);
    free(path);
}
