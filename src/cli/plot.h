/* plot.h: drawing with gnuplot, for the command line only. */
#ifndef LF_PLOT_H
#define LF_PLOT_H

#include <stddef.h>
#include <stdio.h>

typedef struct {
    const char *title;      /* legend entry */
    size_t n;
    const double *x, *y;
    int dashed;             /* 1: dashed line (e.g. unstable branch) */
    int color;              /* 0, 1, 2, ...: series with one color share it */
    int points;             /* 0: a line; 1, 2, ...: unconnected points, each
                               value its own marker shape */
} plot_series;

typedef struct {
    const char *title, *xlabel, *ylabel;
    int logx, logy;
    size_t nseries;
    const plot_series *series;
} plot_figure;

/* 1 when gnuplot can be run. */
int plot_have_gnuplot(void);

/* Draw f into file (terminal from the extension: .svg or .png).  Returns 0,
 * or -1 with a message in msg. */
int plot_draw(const plot_figure *f, const char *file, char *msg, size_t n);

/* The gnuplot terminal for a file name ending in .svg or .png, or NULL. */
const char *plot_terminal(const char *file);

/* Write s to g as a gnuplot single-quoted string ('' for a quote, control
 * characters as spaces). */
void plot_quote(FILE *g, const char *s);

/* Run `gnuplot SCRIPT` with dir as the working folder, so that the file
 * names inside a kept script are relative to it and the user can rerun it
 * there; out, when not NULL, is passed as `-e "out='OUT'"` (a name layerfit
 * made, without quotes).  Returns 0, or -1 with a message in msg. */
int plot_run_script(const char *dir, const char *script, const char *out, char *msg, size_t n);

/* dir/name into buf (n bytes); -1 when it does not fit. */
int plot_path(char *buf, size_t n, const char *dir, const char *name);

/* The command that installs gnuplot, for messages. */
#define PLOT_INSTALL_HINT "install it with 'apt-get install gnuplot-nox' (or 'make deps')"

#endif
