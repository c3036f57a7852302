/* cache.c: `layerfit cache`, the folder of the exact model's tables. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage_text[] =
    "usage: layerfit cache list|clear|dir\n\n"
    "The exact model's tables (a few per probe profile k and interface, about\n"
    "0.1 s each to build) are kept between runs in $XDG_CACHE_HOME/layerfit, else\n"
    "$HOME/.cache/layerfit.  A stale or damaged file is never used: it is built\n"
    "and written again.\n\n"
    "  list    the files, their sizes and the table each holds\n"
    "  clear   remove the table files (they are rebuilt when next needed)\n"
    "  dir     print the folder\n\n"
    "'layerfit --no-cache COMMAND ...' (or LAYERFIT_NO_CACHE=1 in the environment)\n"
    "neither reads nor writes the cache.\n";

int
cli_cache(int argc, char **argv, const char *command_line)
{
    char dir[4096];
    lf_error err;

    (void) command_line;    /* no provenance record */
    if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        fputs(usage_text, stdout);
        return CLI_EXIT_OK;
    }
    if (argc != 2)
        cli_die(CLI_EXIT_USAGE, "cache: give one of list, clear, dir (see 'layerfit cache --help')");
    if (lf_cache_dir(dir, sizeof dir, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "cache: %s", err.msg);
    if (strcmp(argv[1], "dir") == 0) {
        printf("%s\n", dir);
    } else if (strcmp(argv[1], "list") == 0) {
        lf_cache_entry *e;
        size_t n, i, bad = 0;
        long long total = 0;
        if (lf_cache_list(&e, &n, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "cache: %s", err.msg);
        for (i = 0; i < n; i++) {
            printf("%-48s %9lld  %s\n", e[i].name, e[i].bytes, e[i].what);
            total += e[i].bytes;
            bad += !e[i].valid;
        }
        printf("%zu table file%s, %lld bytes, in %s", n, n == 1 ? "" : "s", total, dir);
        if (bad > 0)
            printf(" (%zu not usable)", bad);
        printf("\n");
        free(e);
    } else if (strcmp(argv[1], "clear") == 0) {
        size_t removed;
        if (lf_cache_clear(&removed, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "cache: %s", err.msg);
        printf("removed %zu table file%s from %s\n", removed, removed == 1 ? "" : "s", dir);
    } else {
        cli_die(CLI_EXIT_USAGE, "cache: unknown action '%s' (list, clear or dir)", argv[1]);
    }
    return CLI_EXIT_OK;
}
