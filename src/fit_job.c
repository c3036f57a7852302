/* fit_job.c: a fit as `layerfit fit PATH [options]` makes it, held in one
 * object for programs and bindings that keep objects by handle: the plan
 * or the single curve read as the command reads it, the fit made as the
 * command makes it (lf_fit_request_run), and the result's JSON with the
 * provenance the command records (the plan, then each curve, with their
 * SHA-256).  See lf_fit_job_path in layerfit.h. */
#include <math.h>
#include <stdlib.h>

#include "internal.h"

struct lf_fit_job {
    const lf_fit_request *req;  /* the options', while the job is made */
    char *model;                /* --model as asked */
    double model_tol;           /* the auto choice's tolerance, or NaN */
    lf_fit_input in;
    lf_fit_result res;
    int have_res;
    int status;                 /* LF_OK or LF_ENOCONV */
    char *plan_path;            /* the plan read from a file, or NULL */
    char plan_sha256[65];
    lf_assumption assumed[16];  /* what the fit assumed (lf_fit_assumptions) */
    size_t nassumed;
};

int
lf_plan_from_input(const lf_input *in, const char *path, lf_plan **out, lf_warnings *warn,
                   lf_error *err)
{
    const char *slash = strrchr(path, '/');
    char *dir = NULL;
    int status;

    if (slash != NULL) {
        size_t n = (size_t) (slash - path);
        if ((dir = malloc(n + 2)) == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        memcpy(dir, path, n);
        dir[n] = '\0';
        if (n == 0)
            strcpy(dir, "/");
    }
    status = lf_plan_parse(in->data, in->len, 0, path, dir, out, warn, err);
    free(dir);
    return status;
}

int
lf_plan_need_layers(const lf_plan *plan, const char *model, lf_error *err)
{
    size_t i;

    if (strcmp(model, "halfspace") == 0)
        return LF_OK;
    for (i = 0; i < plan->n; i++)
        if (isnan(plan->rows[i].probe.b))
            return lf_fail_at(err, LF_EDATA, plan->path, plan->rows[i].line, 0,
                              "b and interface are empty (no layer): only the half-space model "
                              "needs neither; the model '%s' needs both (give them, or fit with "
                              "--model halfspace)", model);
    return LF_OK;
}

int
lf_plan_set_source(lf_plan *plan, size_t row, lf_file *f, long index, lf_error *err)
{
    if (row >= plan->n)
        return lf_fail(err, LF_EINVAL, "row %zu of a plan of %zu", row + 1, plan->n);
    if (f == NULL || index < -1 || (index >= 0 && (size_t) index >= lf_file_count(f)))
        return lf_fail(err, LF_EINVAL, "curve %ld of a file of %zu", index,
                       f != NULL ? lf_file_count(f) : 0);
    plan->rows[row].source = f;
    plan->rows[row].index = index;
    return LF_OK;
}

static lf_fit_job *
job_new(lf_fit_options *o, lf_error *err)
{
    lf_fit_job *j = calloc(1, sizeof *j);

    if (j == NULL) {
        lf_fail(err, LF_ENOMEM, "out of memory");
        return NULL;
    }
    if ((j->req = lf_fit_options_checked(o, err)) == NULL
        || (j->model = lf_strdup(j->req->model)) == NULL) {
        if (j->req != NULL)
            lf_fail(err, LF_ENOMEM, "out of memory");
        free(j);
        return NULL;
    }
    j->model_tol = j->req->model_auto ? j->req->choose.tol : NAN;
    return j;
}

/* Fit j's input. */
static int
job_fit(lf_fit_job *j, lf_warnings *warn, lf_error *err)
{
    int status = lf_fit_request_run(j->req, &j->in, 0, &j->res, warn, err);

    if (status != LF_OK && status != LF_ENOCONV)
        return status;
    j->have_res = 1;
    j->nassumed = lf_fit_assumptions(j->req, &j->in, &j->res, j->assumed,
                                     sizeof j->assumed / sizeof j->assumed[0]);
    j->status = status;
    j->req = NULL;              /* the options may change from here on */
    return LF_OK;
}

/* The curves of the plan's rows, as the job's options read them. */
static int
job_read_plan(lf_fit_job *j, const lf_plan *plan, lf_warnings *warn, lf_error *err)
{
    int status = lf_plan_need_layers(plan, j->model, err);

    if (status == LF_OK)
        status = lf_fit_input_from_plan(plan, NULL, 0, &j->req->input, &j->in, warn, err);
    return status;
}

/* Fit j's input once it is read (status LF_OK): *out is j, or j is freed. */
static int
job_done(lf_fit_job *j, int status, lf_fit_job **out, lf_warnings *warn, lf_error *err)
{
    if (status == LF_OK)
        status = job_fit(j, warn, err);
    if (status != LF_OK) {
        lf_fit_job_free(j);
        return status;
    }
    *out = j;
    return LF_OK;
}

int
lf_fit_job_plan(lf_fit_options *o, const lf_plan *plan, lf_fit_job **out, lf_warnings *warn,
                lf_error *err)
{
    lf_fit_job *j;
    lf_probe p;
    int single, status;

    *out = NULL;
    if ((j = job_new(o, err)) == NULL)
        return err != NULL ? err->status : LF_ENOMEM;
    if ((status = lf_fit_options_probe(o, &p, &single, err)) == LF_OK && single)
        status = lf_fail(err, LF_EINVAL, "--k, --R, --b and --interface are for a single curve "
                         "(a plan gives each curve's probe in its row)");
    if (status == LF_OK)
        status = job_read_plan(j, plan, warn, err);
    return job_done(j, status, out, warn, err);
}

int
lf_fit_job_path(lf_fit_options *o, const char *path, lf_fit_job **out, lf_warnings *warn,
                lf_error *err)
{
    lf_fit_job *j;
    lf_plan *plan = NULL;
    lf_input in;
    lf_probe p;
    int single, status;

    *out = NULL;
    if ((j = job_new(o, err)) == NULL)
        return err != NULL ? err->status : LF_ENOMEM;
    status = lf_fit_options_probe(o, &p, &single, err);
    if (status == LF_OK && single) {
        /* a curve named by a program may be a pipe (read once) */
        lf_input_settings one = j->req->input;
        one.open_flags = LF_INPUT_STREAM;
        status = lf_fit_input_from_curve(path, &p, &one, &j->in, warn, err);
    } else if (status == LF_OK
               && (status = lf_input_read(path, LF_INPUT_STREAM, &in, err)) == LF_OK) {
        j->plan_path = lf_strdup(path);
        memcpy(j->plan_sha256, in.sha256, sizeof j->plan_sha256);
        status = j->plan_path == NULL ? lf_fail(err, LF_ENOMEM, "out of memory")
                                       : lf_plan_from_input(&in, path, &plan, warn, err);
        lf_input_free(&in);
        if (status == LF_OK)
            status = job_read_plan(j, plan, warn, err);
        lf_plan_free(plan);
    }
    return job_done(j, status, out, warn, err);
}

const lf_fit_result *
lf_fit_job_result(const lf_fit_job *j)
{
    return &j->res;
}

const lf_fit_input *
lf_fit_job_input(const lf_fit_job *j)
{
    return &j->in;
}

int
lf_fit_job_status(const lf_fit_job *j)
{
    return j->status;
}

size_t
lf_fit_job_curve(const lf_fit_job *j, size_t i, const double **depth, const double **force,
                 const double **fitted, const double **radius)
{
    if (i >= j->in.n || i >= j->res.ncurves)
        return 0;
    *depth = j->in.curves[i].depth;
    *force = j->in.curves[i].force;
    *fitted = j->res.curves[i].fitted;
    *radius = j->res.curves[i].contact_radius;
    return j->in.curves[i].n;
}

int
lf_fit_job_json(const lf_fit_job *j, const char *command_line, char **json, lf_error *err)
{
    size_t n = j->in.n + (j->plan_path != NULL), k = 0, i;
    const char **path = malloc((n ? n : 1) * sizeof *path);
    const char **sha = malloc((n ? n : 1) * sizeof *sha);
    lf_provenance prov;
    lf_report_info info;
    int status;

    if (path == NULL || sha == NULL) {
        free(path);
        free((void *) sha);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    /* the inputs in the order the command notes them: the plan, then each
     * curve as it was read */
    if (j->plan_path != NULL) {
        path[k] = j->plan_path;
        sha[k++] = j->plan_sha256;
    }
    for (i = 0; i < j->in.n; i++) {
        path[k] = j->in.names[i];
        sha[k++] = j->in.sha256[i];
    }
    prov.command_line = command_line;
    prov.ninputs = n;
    prov.input = path;
    prov.sha256 = sha;
    info.model_request = j->model;
    info.model_tol = j->model_tol;
    info.origin = j->in.origin;
    info.provenance = &prov;
    info.assumed = j->assumed;
    info.nassumed = j->nassumed;
    info.observed = j->in.observed;
    info.window = j->in.window;
    status = lf_fit_result_json(&j->res, &info, json, err);
    free(path);
    free((void *) sha);
    return status;
}

void
lf_fit_job_free(lf_fit_job *j)
{
    if (j == NULL)
        return;
    if (j->have_res)
        lf_fit_result_free(&j->res);
    lf_fit_input_free(&j->in);
    free(j->plan_path);
    free(j->model);
    free(j);
}
