/* main.c: the layerfit command, a table of subcommands. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "cli.h"

static const cli_command commands[] = {
    { "model", "compute model curves, pull-off and the paper's figures", cli_model },
    { "fit", "fit w, E* and nu jointly to curves from several probes", cli_fit },
    { "simulate", "write synthetic curves, a plan and the truth", cli_simulate },
    { "check", "read a fit plan or a curve file and report what it holds", cli_check },
    { "design", "what a planned test would measure: predicted errors, best probes", cli_design },
    { "map", "heat maps of w and E* from a batch fit; synthetic force maps", cli_map },
    { "bench", "what a fit costs and how accurate it is (against the Cramer-Rao bound)", cli_bench },
    { "cache", "list or clear the exact model's tables kept between runs", cli_cache },
    { NULL, NULL, NULL }
};

static void
usage(FILE *f)
{
    const cli_command *c;
    fprintf(f, "usage: layerfit COMMAND [OPTIONS]\n\n"
               "Adhesion (w) and elasticity (E*, nu) of thin coatings from indentation\n"
               "curves taken with power-law probes f(r) = r^k/(k R^(k-1)).\n\ncommands:\n");
    for (c = commands; c->name != NULL; c++)
        fprintf(f, "  %-10s %s\n", c->name, c->summary);
    fprintf(f, "\n'layerfit COMMAND --help' describes each command.\n"
               "Every dimensional value takes a unit: --b 1um, --E 1GPa, --w 10mJ/m2.\n"
               "Anywhere on the line:\n"
               "  --no-cache        do not read or write the exact model's tables on disk\n"
               "                    (see 'layerfit cache --help')\n"
               "  --max-input SIZE  read inputs of up to SIZE bytes whole (default 256MiB;\n"
               "                    e.g. --max-input 2GiB)\n"
               "  --csv-raw         write CSV text cells as they are, without the quote\n"
               "                    that keeps a spreadsheet from running =, +, -, @\n");
}

/* The command line as typed, shell-quoted ("layerfit" for argv[0]), into
 * buf (at most n bytes; cut short when longer): what the provenance
 * records and the HTML report show. */
static void
quote_command_line(int argc, char **argv, char *buf, size_t n)
{
    size_t len = 0;
    int i;

    buf[0] = '\0';
    for (i = 0; i < argc && len < n; i++) {
        const char *a = i == 0 ? "layerfit" : argv[i], *p;
        int plain = *a != '\0' && strspn(a, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789-_./=:,+@%") == strlen(a);
        if (i > 0)
            buf[len++] = ' ';
        if (plain) {
            len += (size_t) snprintf(buf + len, n - len, "%s", a);
            continue;
        }
        if (len < n - 1)
            buf[len++] = '\'';
        for (p = a; *p && len < n - 5; p++) {
            if (*p == '\'') {
                memcpy(buf + len, "'\\''", 4);
                len += 4;
            } else {
                buf[len++] = *p;
            }
        }
        if (len < n - 1)
            buf[len++] = '\'';
        buf[len < n ? len : n - 1] = '\0';
    }
    if (len >= n)
        buf[n - 1] = '\0';
}

/* Take the global options out of argv: --no-cache, --max-input SIZE,
 * --csv-raw. */
static int
global_options(int argc, char **argv)
{
    int i, n = 1;

    for (i = 1; i < argc; i++) {
        const char *size = NULL;
        if (strcmp(argv[i], "--") == 0) {      /* the rest are not options */
            while (i < argc)
                argv[n++] = argv[i++];
            break;
        }
        if (strcmp(argv[i], "--no-cache") == 0)
            lf_cache_set_enabled(0);
        else if (strcmp(argv[i], "--csv-raw") == 0)
            cli_csv_raw = 1;
        else if (strncmp(argv[i], "--max-input=", 12) == 0)
            size = argv[i] + 12;
        else if (strcmp(argv[i], "--max-input") == 0) {
            if (i + 1 >= argc)
                cli_die(CLI_EXIT_USAGE, "--max-input needs a size (e.g. --max-input 2GiB)");
            size = argv[++i];
        } else
            argv[n++] = argv[i];
        if (size != NULL) {
            double bytes;
            if (cli_parse_size(size, &bytes) != 0)
                cli_die(CLI_EXIT_USAGE, "--max-input: '%s' is not a size in bytes (e.g. "
                        "--max-input 2GiB, 512MiB or 1e9)", size);
            lf_input_set_limit(bytes >= (double) SIZE_MAX ? SIZE_MAX : (size_t) bytes);
        }
    }
    argv[n] = NULL;
    return n;
}

/* A report lost on a full disk is a failure: stdout is checked at the end. */
static int
finish(int status)
{
    if (cli_stdout_close() != 0)
        return CLI_EXIT_FAIL;
    return status;
}

int
main(int argc, char **argv)
{
    const cli_command *c;
    /* saved before options are parsed (parsing reorders argv) */
    static char command_line[8192];

    gsl_set_error_handler_off();
    cli_signals_install();
    quote_command_line(argc, argv, command_line, sizeof command_line);
    argc = global_options(argc, argv);
    if (argc < 2) {
        usage(stderr);
        return CLI_EXIT_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0
        || strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return finish(CLI_EXIT_OK);
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("layerfit %s\n", LF_VERSION);
        return cli_stdout_close() == 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
    }
    if (strcmp(argv[1], "fit") == 0 && cli_wants_batch(argc - 1, argv + 1))
        return finish(cli_fit_batch(argc - 1, argv + 1, command_line));
    for (c = commands; c->name != NULL; c++)
        if (strcmp(argv[1], c->name) == 0)
            return finish(c->run(argc - 1, argv + 1, command_line));
    cli_say("unknown command '%s' (see 'layerfit --help')", argv[1]);
    return CLI_EXIT_USAGE;
}
