/* cli/temps.c: the temporary files and folders of a run, removed however
 * the run ends: when it commits or discards them, at exit (a failure
 * through cli_die included), and when a catchable signal stops it
 * (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE).
 *
 * The signal handler may only use async-signal-safe calls (POSIX.1-2017,
 * 2.4.3): it reads a fixed table of paths (no malloc, no lists that
 * another thread could be relinking), unlinks files, empties and removes
 * folders with openat/getdents64/unlinkat, stops a child program with
 * kill, then restores the default action and raises the signal again, so
 * the run ends as the signal says (status 128 + N in a shell).  A commit
 * of two files that must stay a pair holds signals (cli_signals_hold):
 * one that arrives then is acted on once both renames are done. */
#define _GNU_SOURCE 1
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/syscall.h>
#endif

#include "cli.h"

#define NSLOTS 64
#define FREE 0
#define LIVE 2

static struct {
    volatile sig_atomic_t state;   /* FREE, 1 while being written, LIVE */
    int dir;                       /* 1: a folder, removed with what it holds */
    char path[PATH_MAX];
} slots[NSLOTS];
static pthread_mutex_t slots_lock = PTHREAD_MUTEX_INITIALIZER;
static volatile sig_atomic_t child_pid;   /* a program layerfit waits for, or 0 */
static volatile sig_atomic_t holding, held_signal;
static int installed;

static const int caught[] = { SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE };

/* A folder and everything in it (layerfit's temporary folders hold files
 * and at most a folder or two of files), with calls that are safe in a
 * signal handler.  Outside Linux only an empty folder is removed there;
 * cli_remove_tree (nftw) does the ordinary removal everywhere. */
static void
remove_at(int parent, const char *name, int depth)
{
#if defined(__linux__) && defined(SYS_getdents64)
    int fd = openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0 && depth < 4) {
        char buf[4096];
        int pass, removed = 1;
        /* entries removed while reading may shift the rest: read again */
        for (pass = 0; pass < 4 && removed; pass++) {
            long n, off;
            removed = 0;
            (void) lseek(fd, 0, SEEK_SET);
            while ((n = syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0)
                for (off = 0; off < n;) {
                    /* struct linux_dirent64: ino, off, reclen, type, name */
                    const char *rec = buf + off;
                    unsigned short reclen;
                    const char *entry = rec + 19;
                    memcpy(&reclen, rec + 16, sizeof reclen);
                    off += reclen;
                    if (strcmp(entry, ".") == 0 || strcmp(entry, "..") == 0)
                        continue;
                    if (unlinkat(fd, entry, 0) != 0 && (errno == EISDIR || errno == EPERM))
                        remove_at(fd, entry, depth + 1);
                    removed = 1;
                }
        }
    }
    if (fd >= 0)
        close(fd);
#else
    (void) depth;
#endif
    (void) unlinkat(parent, name, AT_REMOVEDIR);
}

/* Remove every live temporary: files first, then folders, the latest
 * first (a folder made inside another goes before it). */
static void
remove_all(void)
{
    int i;
    for (i = NSLOTS - 1; i >= 0; i--)
        if (slots[i].state == LIVE && !slots[i].dir)
            (void) unlink(slots[i].path);
    for (i = NSLOTS - 1; i >= 0; i--)
        if (slots[i].state == LIVE && slots[i].dir)
            remove_at(AT_FDCWD, slots[i].path, 0);
}

static void
die_by(int sig)
{
    sigset_t s;
    if (child_pid > 0)
        (void) kill((pid_t) child_pid, SIGTERM);
    remove_all();
    (void) signal(sig, SIG_DFL);
    sigemptyset(&s);
    sigaddset(&s, sig);
    (void) sigprocmask(SIG_UNBLOCK, &s, NULL);
    (void) raise(sig);
    _exit(128 + sig);      /* not reached: the default action ends the run */
}

static void
on_signal(int sig)
{
    int e = errno;
    if (holding) {
        held_signal = sig;  /* acted on by cli_signals_release */
        errno = e;
        return;
    }
    die_by(sig);
}

static void
at_exit(void)
{
    remove_all();
}

void
cli_signals_install(void)
{
    struct sigaction sa;
    size_t i;

    if (installed)
        return;
    installed = 1;
    atexit(at_exit);
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigfillset(&sa.sa_mask);      /* one handler at a time */
    for (i = 0; i < sizeof caught / sizeof caught[0]; i++) {
        struct sigaction old;
        /* a signal the caller ignores (nohup, a shell's background job)
         * stays ignored */
        if (sigaction(caught[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue;
        (void) sigaction(caught[i], &sa, NULL);
    }
}

int
cli_temp_add(const char *path, int is_dir)
{
    int i;

    if (strlen(path) >= PATH_MAX)
        return -1;
    pthread_mutex_lock(&slots_lock);
    for (i = 0; i < NSLOTS && slots[i].state != FREE; i++)
        ;
    if (i < NSLOTS) {
        slots[i].state = 1;
        slots[i].dir = is_dir;
        strcpy(slots[i].path, path);
        atomic_thread_fence(memory_order_seq_cst);   /* the path before LIVE */
        slots[i].state = LIVE;
    }
    pthread_mutex_unlock(&slots_lock);
    return i < NSLOTS ? i : -1;
}

void
cli_temp_forget(int slot)
{
    if (slot < 0 || slot >= NSLOTS)
        return;
    pthread_mutex_lock(&slots_lock);
    slots[slot].state = FREE;
    pthread_mutex_unlock(&slots_lock);
}

void
cli_temp_child(long pid)
{
    child_pid = (sig_atomic_t) pid;
}

void
cli_signals_hold(void)
{
    holding = 1;
}

void
cli_signals_release(void)
{
    holding = 0;
    if (held_signal != 0)
        die_by(held_signal);
}

static int
remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void) st;
    (void) ftw;
    if (flag == FTW_DP)
        (void) rmdir(path);
    else
        (void) unlink(path);
    return 0;
}

int
cli_remove_tree(const char *dir)
{
    struct stat st;
    (void) nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    return lstat(dir, &st) == 0 ? -1 : 0;
}
