/* cli/read.c: reading the command's inputs once, whole, from a descriptor
 * checked when it is opened (lf_input_read), so that what is parsed is what
 * is hashed for provenance, and a pipe named on the command line is read
 * exactly once. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

int
cli_plan_from(const lf_input *in, const char *path, lf_plan **out, lf_warnings *warn,
              lf_error *err)
{
    return lf_plan_from_input(in, path, out, warn, err);
}

void
cli_plan_need_layers(const lf_plan *plan, const char *model)
{
    lf_error err;

    if (lf_plan_need_layers(plan, model, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
}

/* The format of an input that reads as a curve ("csv", "chiaro", ...): an
 * instrument's export by its sniffed format (its constants may be missing:
 * it is a curve all the same), a table when it parses as one; NULL when it
 * is neither. */
static const char *
curve_kind(const lf_input *in, const char *path)
{
    const lf_reader_type *t = lf_reader_sniff(in->data, in->len);    /* looks at the head */
    lf_read_opts o;
    lf_curve *c = NULL;
    lf_error err;

    if (strcmp(t->name, "csv") != 0)
        return t->name;
    lf_read_opts_default(&o);
    if (lf_curve_parse(in->data, in->len, 0, path, &o, &c, NULL, &err) != LF_OK)
        return NULL;
    lf_curve_free(c);
    return "csv";
}

int
cli_reads_as_plan(const char *path)
{
    lf_file_kind kind;
    lf_error err;

    /* regular files only (lf_file_kind_of): a pipe was read once already */
    return lf_file_kind_of(path, &kind, &err) == LF_OK && kind == LF_FILE_PLAN;
}

lf_plan *
cli_plan_load(const char *cmd, const char *path)
{
    lf_plan *plan = NULL;
    lf_warnings warn = { 0, NULL };
    lf_input in;
    lf_error err;

    cli_input_guard(cmd, path);
    if (lf_input_read(path, LF_INPUT_STREAM | LF_INPUT_TEXT, &in, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    cli_input_note(path, in.sha256);
    if (cli_plan_from(&in, path, &plan, &warn, &err) != LF_OK) {
        const char *kind = err.status == LF_ENOMEM ? NULL : curve_kind(&in, path);
        if (kind != NULL)       /* a curve where a plan was wanted */
            cli_die(CLI_EXIT_USAGE, "%s: %s is a curve (a %s%s), not a plan: fit it alone "
                    "with its probe, e.g. layerfit fit FILE --k 2 --R 8um --model halfspace (or "
                    "--b and --interface for a layer)", cmd, path,
                    strcmp(kind, "csv") == 0 ? "table of depth and force" : kind,
                    strcmp(kind, "csv") == 0 ? "" : " export");
        cli_die_error(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, &err);
    }
    lf_input_free(&in);
    cli_print_warnings(&warn);
    lf_warnings_free(&warn);
    return plan;
}
