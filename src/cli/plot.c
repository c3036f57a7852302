/* plot.c: figures through a pipe to gnuplot (started without a shell,
 * cli_spawn), data inline as datablocks. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "plot.h"

int
plot_have_gnuplot(void)
{
    return cli_have_program("gnuplot");
}

const char *
plot_terminal(const char *file)
{
    const char *dot = strrchr(file, '.');
    if (dot != NULL && strcmp(dot, ".svg") == 0)
        return "svg size 800,560 dynamic enhanced font 'Helvetica,13'";
    if (dot != NULL && strcmp(dot, ".png") == 0)
        return "pngcairo size 1000,700 enhanced font 'Helvetica,12'";
    return NULL;
}

void
plot_quote(FILE *g, const char *s)
{
    cli_gnuplot_string(g, s);
}

int
plot_draw(const plot_figure *f, const char *file, char *msg, size_t n)
{
    static const char *colors[] = { "#1b6ca8", "#c0392b", "#27ae60", "#8e44ad",
                                    "#d35400", "#2c3e50", "#16a085", "#7f8c8d" };
    static const int shapes[] = { 7, 5, 9, 13, 11, 15 };   /* filled markers */
    const char *term = plot_terminal(file);
    cli_child child;
    char *tmp = NULL;
    const char *t;
    FILE *g;
    size_t s, i;
    int rc, fd, slot;

    if (term == NULL) {
        snprintf(msg, n, "%s: the plot file must end in .svg or .png", file);
        return -1;
    }
    if (!plot_have_gnuplot()) {
        snprintf(msg, n, "gnuplot is not installed: %s", PLOT_INSTALL_HINT);
        return -1;
    }
    /* gnuplot draws into a temporary file beside file, renamed into place
     * once it has succeeded (cli_tmp_name: ".NAME.XXXXXX") */
    if (cli_tmp_name(file, &tmp) != 0 || (fd = mkstemp(tmp)) < 0) {
        snprintf(msg, n, "cannot write beside %s", file);
        free(tmp);
        return -1;
    }
    {
        mode_t mask = umask(0);     /* the usual 0666 less the umask */
        umask(mask);
        (void) fchmod(fd, 0666 & ~mask);
    }
    close(fd);
    slot = cli_temp_add(tmp, 0);
    rc = -1;
    for (t = tmp; *t; t++)
        if ((unsigned char) *t < 0x20 || *t == 0x7F) {
            snprintf(msg, n, "cannot draw into a path with control characters");
            goto done;
        }
    {
        static const char *const argv[] = { "gnuplot", NULL };
        if (cli_spawn(&child, argv, NULL, CLI_SPAWN_STDIN) != 0) {
            snprintf(msg, n, "could not start gnuplot: %s", strerror(errno));
            goto done;
        }
        g = child.in;
    }
    for (s = 0; s < f->nseries; s++) {
        fprintf(g, "$d%zu << EOD\n", s);
        for (i = 0; i < f->series[s].n; i++)
            fprintf(g, "%.10g %.10g\n", f->series[s].x[i], f->series[s].y[i]);
        fprintf(g, "EOD\n");
    }
    fprintf(g, "set terminal %s\nset output ", term);
    plot_quote(g, tmp);
    fprintf(g, "\nset grid lc rgb '#dddddd'\nset key outside right top\nset title ");
    plot_quote(g, f->title);
    fprintf(g, "\nset xlabel ");
    plot_quote(g, f->xlabel);
    fprintf(g, "\nset ylabel ");
    plot_quote(g, f->ylabel);
    fprintf(g, "\n%s\n%s\nplot ", f->logx ? "set logscale x" : "unset logscale x",
            f->logy ? "set logscale y" : "unset logscale y");
    for (s = 0; s < f->nseries; s++) {
        const plot_series *p = &f->series[s];
        if (p->points > 0)
            fprintf(g, "%s$d%zu using 1:2 with points pt %d ps 1.2 lc rgb '%s' title ",
                    s ? ", " : "", s, shapes[(size_t) (p->points - 1) % 6],
                    colors[(size_t) p->color % 8]);
        else
            fprintf(g, "%s$d%zu using 1:2 with lines lw 2 lc rgb '%s' dt %d title ",
                    s ? ", " : "", s, colors[(size_t) p->color % 8], p->dashed ? 2 : 1);
        plot_quote(g, p->title ? p->title : "");
    }
    fprintf(g, "\nset output\n");
    rc = ferror(g) ? -1 : 0;
    if (cli_child_wait(&child) != 0 || rc != 0) {
        snprintf(msg, n, "gnuplot failed drawing %s", file);
        rc = -1;
    } else {
        rc = cli_put_in_place(tmp, file, msg, n);
    }
done:
    if (rc != 0)
        unlink(tmp);
    cli_temp_forget(slot);
    free(tmp);
    return rc;
}

int
plot_run_script(const char *dir, const char *script, const char *out, char *msg, size_t n)
{
    cli_child child;
    int rc;

    if (!plot_have_gnuplot()) {
        snprintf(msg, n, "gnuplot is not installed: %s", PLOT_INSTALL_HINT);
        return -1;
    }
    {
        /* out is a name layerfit made, never data; quoted all the same */
        char e[4200];
        const char *argv[5];
        size_t k = 0;
        argv[k++] = "gnuplot";
        if (out != NULL) {
            if (strchr(out, '\'') != NULL
                || (size_t) snprintf(e, sizeof e, "out='%s'", out) >= sizeof e) {
                snprintf(msg, n, "cannot draw into %s", out);
                return -1;
            }
            argv[k++] = "-e";
            argv[k++] = e;
        }
        argv[k++] = script;
        argv[k] = NULL;
        if (cli_spawn(&child, argv, dir, 0) != 0) {
            snprintf(msg, n, "could not start gnuplot: %s", strerror(errno));
            return -1;
        }
    }
    if ((rc = cli_child_wait(&child)) != 0) {
        snprintf(msg, n, "gnuplot failed on %s/%s (status %d)", dir, script, rc);
        return -1;
    }
    return 0;
}

int
plot_path(char *buf, size_t n, const char *dir, const char *name)
{
    int len = snprintf(buf, n, "%s/%s", dir, name);
    return len < 0 || (size_t) len >= n ? -1 : 0;
}
