/* cli/spawn.c: other programs (gnuplot, python) run without a shell.
 *
 * A program is started with posix_spawnp and an argument vector, never a
 * command string: a file name or an option value is one argument whatever
 * quotes, semicolons or line breaks it holds, and nothing is ever parsed by
 * /bin/sh.  Whether a program is installed is looked up along PATH here,
 * not with `command -v` in a shell. */
#define _GNU_SOURCE 1
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"

extern char **environ;

int
cli_have_program(const char *name)
{
    const char *path = getenv("PATH"), *p;

    if (strchr(name, '/') != NULL)
        return access(name, X_OK) == 0;
    if (path == NULL || *path == '\0')
        path = "/usr/local/bin:/usr/bin:/bin";
    for (p = path;; p++) {
        const char *end = strchr(p, ':');
        size_t len = end != NULL ? (size_t) (end - p) : strlen(p);
        char full[PATH_MAX];
        struct stat st;
        /* an empty entry is the current folder, as for execvp */
        if (snprintf(full, sizeof full, "%.*s/%s", len ? (int) len : 1, len ? p : ".", name)
                < (int) sizeof full
            && stat(full, &st) == 0 && S_ISREG(st.st_mode) && access(full, X_OK) == 0)
            return 1;
        if (end == NULL)
            return 0;
        p = end;
    }
}

int
cli_spawn(cli_child *c, const char *const *argv, const char *dir, unsigned how)
{
    posix_spawn_file_actions_t fa;
    int in[2] = { -1, -1 }, out[2] = { -1, -1 }, status, e;
    pid_t pid;

    memset(c, 0, sizeof *c);
    c->pid = -1;
    if (((how & CLI_SPAWN_STDIN) && pipe2(in, O_CLOEXEC) != 0)
        || ((how & CLI_SPAWN_STDOUT) && pipe2(out, O_CLOEXEC) != 0)) {
        e = errno;
        goto fail;
    }
    if ((e = posix_spawn_file_actions_init(&fa)) != 0)
        goto fail;
    /* the pipes' ends are close-on-exec: only the dup2'ed copies reach the
     * program */
    if (how & CLI_SPAWN_STDIN)
        posix_spawn_file_actions_adddup2(&fa, in[0], STDIN_FILENO);
    if (how & CLI_SPAWN_STDOUT)
        posix_spawn_file_actions_adddup2(&fa, out[1], STDOUT_FILENO);
    if (how & CLI_SPAWN_QUIET) {
        posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    } else if (how & CLI_SPAWN_STDERR_TO_OUT) {
        posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
    }
    if (dir != NULL)
        posix_spawn_file_actions_addchdir_np(&fa, dir);
    fflush(NULL);
    status = posix_spawnp(&pid, argv[0], &fa, NULL, (char *const *) argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (status != 0) {
        e = status;
        goto fail;
    }
    c->pid = pid;
    cli_temp_child((long) pid);       /* stopped with layerfit on a signal */
    if (how & CLI_SPAWN_STDIN) {
        close(in[0]);
        if ((c->in = fdopen(in[1], "w")) == NULL) {
            close(in[1]);
        }
    }
    if (how & CLI_SPAWN_STDOUT) {
        close(out[1]);
        if ((c->out = fdopen(out[0], "r")) == NULL)
            close(out[0]);
    }
    if (((how & CLI_SPAWN_STDIN) && c->in == NULL) || ((how & CLI_SPAWN_STDOUT) && c->out == NULL)) {
        (void) cli_child_wait(c);
        errno = ENOMEM;
        return -1;
    }
    return 0;
fail:
    if (in[0] >= 0) {
        close(in[0]);
        close(in[1]);
    }
    if (out[0] >= 0) {
        close(out[0]);
        close(out[1]);
    }
    errno = e;
    return -1;
}

int
cli_child_wait(cli_child *c)
{
    int st = 0, ok = 1;
    pid_t r;

    if (c->in != NULL && fclose(c->in) != 0)
        ok = 0;
    if (c->out != NULL)
        fclose(c->out);
    c->in = c->out = NULL;
    if (c->pid <= 0)
        return -1;
    do
        r = waitpid((pid_t) c->pid, &st, 0);
    while (r < 0 && errno == EINTR);
    cli_temp_child(0);
    c->pid = -1;
    if (r < 0 || !WIFEXITED(st))
        return -1;
    return ok ? WEXITSTATUS(st) : (WEXITSTATUS(st) ? WEXITSTATUS(st) : -1);
}
