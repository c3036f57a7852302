/* cli_model.c: `layerfit model` (being written). */
#include "cli.h"

int
cli_model(int argc, char **argv)
{
    (void) argc;
    (void) argv;
    cli_die(CLI_EXIT_FAIL, "model: not yet available");
}
