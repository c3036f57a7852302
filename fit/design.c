/* design.c: what a planned set of indentation curves would measure, before
 * the lab records them (the contract is in layerfit.h above
 * lf_design_candidate).
 *
 * Each candidate is prepared once: its indentations, its noise sd and, for
 * each forward model a fit could use (thin, half-space, exact), the QR
 * factor R_m of its weighted gradient rows
 *     g_i = (dP/dln w, dP/dln E*, dP/dnu, -dP/ddelta L, Fs) / sigma
 * (z0 in units of the depth span L, F0 in units of the largest force Fs)
 * and Q_m^T d_m with d_m = (P_exact - P_m) / sigma.  Because J_j = Q_j R_j,
 * the Jacobian of any set has the same singular values and right singular
 * vectors as the stack of the R_j (5 rows per curve, columns picked for
 * the parameters that set frees), and J^T d = sum R_j^T (Q_j^T d_j).  So a
 * set is evaluated from a matrix of 5 rows per curve, without the models.
 *
 * With the stack A (columns scaled to unit norm, A = U S V^T) everything
 * follows the fitter's rules (fit/uncertainty.c, fit/choose.c):
 *  - a direction with S_l <= rcond S_0 is not determined; a parameter with
 *    weight sum_{l undetermined} V_pl^2 > 0.01 on those is not determined;
 *  - the covariance is the pseudo-inverse over the other directions: the
 *    Cramer-Rao bound of that fit (no sqrt(chi2/dof): the truth is known);
 *  - a cheaper model's first-order bias on the material, in standard
 *    errors, is (sum_l V_pl (V^T D^-1 J^T d)_l / S_l^2) / sqrt(sum_l V_pl^2
 *    / S_l^2), the same expression choose.c evaluates at a fitted solution;
 *    here it is evaluated at the truth, where a fit of noise-free data of
 *    the chosen model would land. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include "csvsplit.h"
#include "fit.h"

#define NL 5                    /* local columns: ln w, ln E*, nu, z0, F0 */
enum { C_W = 0, C_E, C_NU, C_Z0, C_F0 };
enum { RUNG_THIN = 0, RUNG_HALFSPACE, RUNG_EXACT, NRUNG };
#define NULL_WEIGHT 0.01        /* as fit/uncertainty.c */
#define K2_BASELINE_SHARE 0.1   /* as fit/uncertainty.c: k2_without_baseline */
#define NO_BASELINE_END 0.9     /* a curve without baseline ends at 0.9 of the
                                   detachment indentation (physics.md s. 2) */

static const char *const mat_names[3] = { "w", "E*", "nu" };

/* ------------------------------------------------------------ settings */

lf_design_settings
lf_design_settings_default(void)
{
    lf_design_settings s;

    memset(&s, 0, sizeof s);
    s.truth.w = NAN;
    s.truth.Estar = NAN;
    s.truth.nu = 0.3;
    s.fix_nu = 0;
    s.noise_rel = 0.01;
    s.noise_abs = NAN;
    s.delta_max = 50e-9;
    s.points = 200;
    s.baseline_fraction = 0.25;
    s.model = NULL;
    s.choose = lf_choose_settings_default();
    s.rcond = 1e-7;
    return s;
}

/* ------------------------------------------------------------ the plan */

enum { D_NAME, D_K, D_R, D_B, D_INTERFACE, D_DMAX, D_DMIN, D_POINTS, D_BASELINE,
       D_Z0, D_F0, D_SEGMENT, D_NOISE, NDCOL };

static const lf_csv_column dcols[NDCOL] = {
    [D_NAME]      = { "name", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_K]         = { "k", LF_Q_DIMENSIONLESS, 1, NULL },
    [D_R]         = { "R", LF_Q_LENGTH, 1, NULL },
    [D_B]         = { "b", LF_Q_LENGTH, 1, NULL },
    [D_INTERFACE] = { "interface", LF_Q_DIMENSIONLESS, 1, NULL },
    [D_DMAX]      = { "delta_max", LF_Q_LENGTH, 0, NULL },
    [D_DMIN]      = { "delta_min", LF_Q_LENGTH, 0, NULL },
    [D_POINTS]    = { "points", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_BASELINE]  = { "baseline", LF_Q_LENGTH, 0, NULL },
    [D_Z0]        = { "z0", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_F0]        = { "F0", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_SEGMENT]   = { "segment", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_NOISE]     = { "noise", LF_Q_FORCE, 0, "give 1% or 2uN in each cell" },
};

#define DCOLUMNS_HINT "a design plan has the columns k,R,b,interface and may add " \
                      "name,delta_max,delta_min,points,baseline,z0,F0,segment,noise"

typedef struct {
    const char *name;
    lf_design_plan *plan;
    size_t cap;
    int have_header;
    long header_line;
    size_t ncols;
    long col[NDCOL];
    int has_unit[NDCOL];
    double factor[NDCOL];
    int decimal_comma;
} dplan_reader;

static int
dplan_header(dplan_reader *rd, const lf_csv_record *r, lf_error *err)
{
    rd->have_header = 1;
    rd->header_line = r->line;
    rd->ncols = r->n;
    rd->decimal_comma = r->delim == ';';
    return lf_csv_columns(rd->name, r, dcols, NDCOL, DCOLUMNS_HINT, rd->col, rd->factor,
                          rd->has_unit, err);
}

/* A number with its unit from the header or the cell, into SI.  An empty
 * cell (or an absent column) leaves *v at NaN. */
static int
dplan_number(dplan_reader *rd, const lf_csv_record *r, int c, double *v, lf_error *err)
{
    long k = rd->col[c];

    *v = NAN;
    if (k < 0 || r->text[k][0] == '\0')
        return LF_OK;
    return lf_csv_cell_number(rd->name, r, k, &dcols[c], rd->has_unit[c], rd->factor[c],
                              rd->decimal_comma, v, err);
}

/* "free" (or empty) -> 1, "fixed"/"known" -> 0, else -1. */
static int
free_word(const char *t)
{
    if (t[0] == '\0' || lf_csv_ieq(t, "free"))
        return 1;
    if (lf_csv_ieq(t, "fixed") || lf_csv_ieq(t, "known"))
        return 0;
    return -1;
}

/* noise: "1%", "0.01" (fractions of the largest |force|) or "2uN". */
static int
dplan_noise(dplan_reader *rd, const lf_csv_record *r, lf_design_candidate *row, lf_error *err)
{
    long k = rd->col[D_NOISE];
    char text[128], buf[64];
    size_t len;
    double v;
    lf_error e;

    if (k < 0 || r->text[k][0] == '\0')
        return LF_OK;
    snprintf(text, sizeof text, "%s", r->text[k]);
    len = strlen(text);
    if (len > 1 && text[len - 1] == '%') {
        text[len - 1] = '\0';
        if (lf_csv_number(text, rd->decimal_comma, &v) == LF_NUM_OK && v > 0) {
            row->noise_rel = v / 100.0;
            return LF_OK;
        }
    } else if (lf_csv_number(text, rd->decimal_comma, &v) == LF_NUM_OK) {
        if (v > 0) {
            row->noise_rel = v;
            return LF_OK;
        }
    } else {
        lf_csv_decimal_point(text, rd->decimal_comma);
        if (lf_units_parse(text, LF_Q_FORCE, &v, &e) == LF_OK && v > 0) {
            row->noise_abs = v;
            return LF_OK;
        }
    }
    return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                      "noise '%s' is not a positive fraction (1%% or 0.01) or force (2uN)",
                      lf_csv_excerpt(r->text[k], buf, sizeof buf));
}

static int
dplan_row(dplan_reader *rd, const lf_csv_record *r, lf_error *err)
{
    lf_design_plan *p = rd->plan;
    lf_design_candidate *row;
    char buf[64];
    double pts;
    long k;
    int st, word;
    lf_error e;

    if ((st = lf_csv_row_cells(rd->name, r, rd->ncols, err)) != LF_OK)
        return st;
    if (p->n == rd->cap) {
        size_t cap = rd->cap ? 2 * rd->cap : 16;
        lf_design_candidate *rows = realloc(p->rows, cap * sizeof *rows);
        if (rows == NULL)
            return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
        p->rows = rows;
        rd->cap = cap;
    }
    row = &p->rows[p->n];
    memset(row, 0, sizeof *row);
    row->line = r->line;
    row->branch = LF_BRANCH_UNLOAD;
    row->noise_rel = row->noise_abs = NAN;
    k = rd->col[D_NAME];
    if (k >= 0 && r->text[k][0] != '\0')
        snprintf(row->name, sizeof row->name, "%s", r->text[k]);
    else
        snprintf(row->name, sizeof row->name, "row %zu", p->n + 1);
    if ((st = lf_csv_cell_interface(rd->name, r, rd->col[D_INTERFACE], &row->probe.base, err))
        != LF_OK)
        return st;
    k = rd->col[D_SEGMENT];
    if (k >= 0 && r->text[k][0] != '\0') {
        word = lf_csv_segment_word(r->text[k]);
        if (word < 0)
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                              "unknown segment '%s' (expected unload or load)",
                              lf_csv_excerpt(r->text[k], buf, sizeof buf));
        row->branch = word == LF_SEG_LOAD ? LF_BRANCH_LOAD : LF_BRANCH_UNLOAD;
    }
    row->free_z0 = row->free_F0 = 1;
    if ((k = rd->col[D_Z0]) >= 0 && (row->free_z0 = free_word(r->text[k])) < 0)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "z0 '%s' must be free or fixed", lf_csv_excerpt(r->text[k], buf, sizeof buf));
    if ((k = rd->col[D_F0]) >= 0 && (row->free_F0 = free_word(r->text[k])) < 0)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "F0 '%s' must be free or fixed", lf_csv_excerpt(r->text[k], buf, sizeof buf));
    k = rd->col[D_BASELINE];
    row->baseline = 0.0;
    if (k >= 0 && (lf_csv_ieq(r->text[k], "yes") || lf_csv_ieq(r->text[k], "y")))
        row->baseline = NAN;
    else if (k >= 0 && !(r->text[k][0] == '\0' || lf_csv_ieq(r->text[k], "no")
                         || lf_csv_ieq(r->text[k], "n"))) {
        if ((st = dplan_number(rd, r, D_BASELINE, &row->baseline, err)) != LF_OK)
            return st;
        if (!(row->baseline >= 0))
            return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[k], r->fcol[k],
                              "baseline must be yes, no or a length >= 0 (e.g. 20nm)");
    }
    if ((st = dplan_number(rd, r, D_K, &row->probe.k, err)) != LF_OK
        || (st = dplan_number(rd, r, D_R, &row->probe.R, err)) != LF_OK
        || (st = dplan_number(rd, r, D_B, &row->probe.b, err)) != LF_OK
        || (st = dplan_number(rd, r, D_DMAX, &row->delta_max, err)) != LF_OK
        || (st = dplan_number(rd, r, D_DMIN, &row->delta_min, err)) != LF_OK
        || (st = dplan_number(rd, r, D_POINTS, &pts, err)) != LF_OK
        || (st = dplan_noise(rd, r, row, err)) != LF_OK)
        return st;
    p->n++;
    if (isnan(row->probe.k) || isnan(row->probe.R) || isnan(row->probe.b))
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->line, 0,
                          "every row needs k, R and b");
    if (lf_probe_check(&row->probe, &e) != LF_OK)
        return lf_fail_at(err, e.status, rd->name, r->line, 0, "%s", e.msg);
    if (!isnan(pts)) {
        k = rd->col[D_POINTS];
        if (!(pts >= 5 && pts <= 1e7 && pts == floor(pts)))
            return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[k], r->fcol[k],
                              "points must be a whole number from 5 to 10000000");
        row->points = (size_t) pts;
    }
    if (!isnan(row->delta_min) && row->baseline != 0.0)
        return lf_fail_at(err, LF_EINVAL, rd->name, r->line, 0,
                          "give delta_min or baseline, not both (delta_min sets the whole range)");
    if (!isnan(row->delta_max) && !(row->delta_max > 0))
        return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[rd->col[D_DMAX]],
                          r->fcol[rd->col[D_DMAX]], "delta_max must be > 0 (e.g. 50nm)");
    return LF_OK;
}

static int
dplan_record(void *ctx, const lf_csv_record *r, lf_error *err)
{
    dplan_reader *rd = ctx;
    return r->index == 0 ? dplan_header(rd, r, err) : dplan_row(rd, r, err);
}

static int
dplan_load(const char *path, const char *buf, size_t len, const char *name,
           lf_design_plan **out, lf_error *err)
{
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    dplan_reader rd;
    int st;

    *out = NULL;
    memset(&rd, 0, sizeof rd);
    rd.name = name ? name : "";
    rd.plan = calloc(1, sizeof *rd.plan);
    if (rd.plan == NULL || (rd.plan->path = lf_strdup(rd.name)) == NULL) {
        lf_design_plan_free(rd.plan);
        return lf_fail_at(err, LF_ENOMEM, rd.name, 0, 0, "out of memory");
    }
    h.ctx = &rd;
    h.record = dplan_record;
    h.comment = NULL;
    st = buf == NULL ? lf_csv_read_file(path, &h, err)
                     : lf_csv_read_buffer(buf, len, 0, rd.name, &h, err);
    if (st == LF_OK && !rd.have_header)
        st = lf_fail_at(err, LF_EFORMAT, rd.name, 0, 0, "empty design plan (expected a header "
                        "such as name,k,R_mm,b_um,interface and one row per candidate curve)");
    if (st == LF_OK && rd.plan->n == 0)
        st = lf_fail_at(err, LF_EDATA, rd.name, rd.header_line, 0,
                        "header but no rows (list one candidate curve per row below it)");
    if (st != LF_OK) {
        lf_design_plan_free(rd.plan);
        return st;
    }
    *out = rd.plan;
    return LF_OK;
}

int
lf_design_plan_read(const char *path, lf_design_plan **out, lf_error *err)
{
    return dplan_load(path, NULL, 0, path, out, err);
}

int
lf_design_plan_parse(const char *buf, size_t len, const char *name, lf_design_plan **out,
                     lf_error *err)
{
    return dplan_load(NULL, buf ? buf : "", len, name, out, err);
}

void
lf_design_plan_free(lf_design_plan *p)
{
    if (p == NULL)
        return;
    free(p->rows);
    free(p->path);
    free(p);
}

/* ------------------------------------------------------- preparation */

/* One model's view of one candidate. */
typedef struct {
    int ok;                 /* 0: the model cannot describe this curve */
    double R[NL * NL];      /* upper triangular, row-major */
    double qd[NL];          /* Q^T d */
    size_t n_past;          /* points out of contact */
} model_part;

typedef struct {
    lf_design_candidate c;  /* defaults resolved */
    double delta_lo, delta_hi, delta_detach, sigma, fmax;
    double ba_min, ba_max, ba_pulloff;
    model_part m[NRUNG];
} prepared;

struct lf_design {
    lf_design_settings s;
    size_t n;
    prepared *p;
};

static const lf_model_type *
rung_type(int rung)
{
    return rung == RUNG_THIN ? &lf_model_thin
           : rung == RUNG_HALFSPACE ? &lf_model_halfspace : &lf_model_exact;
}

static int
rung_of(const lf_model_type *t)
{
    return t == &lf_model_thin ? RUNG_THIN : t == &lf_model_halfspace ? RUNG_HALFSPACE
                                                                      : RUNG_EXACT;
}

/* R and Q^T d of one model from its evaluations ev[0..n-1]. */
static int
factor_part(const prepared *pp, const lf_eval *ev, const double *P_exact, size_t n,
            gsl_matrix *G, gsl_vector *tau, gsl_vector *d, model_part *mp)
{
    double L = pp->delta_hi - pp->delta_lo, s = pp->sigma;
    size_t i, r, c;

    mp->n_past = 0;
    for (i = 0; i < n; i++) {
        double g[NL];
        g[C_W] = ev[i].dP_dlogw;
        g[C_E] = ev[i].dP_dlogE;
        g[C_NU] = ev[i].dP_dnu;
        g[C_Z0] = -ev[i].dP_ddelta * L;
        g[C_F0] = pp->fmax;
        for (c = 0; c < NL; c++)
            gsl_matrix_set(G, i, c, g[c] / s);
        gsl_vector_set(d, i, (P_exact[i] - ev[i].P) / s);
        mp->n_past += ev[i].a == 0.0;
    }
    if (gsl_linalg_QR_decomp(G, tau) != GSL_SUCCESS
        || gsl_linalg_QR_QTvec(G, tau, d) != GSL_SUCCESS)
        return LF_ENUMERIC;
    for (r = 0; r < NL; r++) {
        for (c = 0; c < NL; c++)
            mp->R[r * NL + c] = c >= r ? gsl_matrix_get(G, r, c) : 0.0;
        mp->qd[r] = gsl_vector_get(d, r);
    }
    for (r = 0; r < NL * NL; r++)
        if (!isfinite(mp->R[r]))
            return LF_ENUMERIC;
    mp->ok = 1;
    return LF_OK;
}

static int
prepare(const lf_design_settings *s, const lf_design_candidate *in, prepared *pp,
        lf_error *err)
{
    lf_design_candidate *c = &pp->c;
    lf_model *m = NULL;
    lf_eval *ev = NULL, *evx = NULL;
    double *delta = NULL, *P = NULL;
    gsl_matrix *G = NULL;
    gsl_vector *tau = NULL, *d = NULL;
    lf_pulloff po;
    size_t i, n;
    int st, rung;
    double amin = HUGE_VAL, amax = 0.0;

    *c = *in;
    if (isnan(c->delta_max))
        c->delta_max = s->delta_max;
    if (c->points == 0)
        c->points = s->points;
    n = c->points;
    if (n < NL)
        return lf_fail(err, LF_EINVAL, "%s: at least %d points per curve", c->name, NL);
    if (lf_probe_check(&c->probe, err) != LF_OK)
        return LF_EINVAL;
    if (!(c->delta_max > 0) || !isfinite(c->delta_max))
        return lf_fail(err, LF_EINVAL, "%s: the deepest indentation must be > 0", c->name);
    m = lf_model_alloc(&lf_model_exact, &c->probe, err);
    if (m == NULL)
        return err ? err->status : LF_EINVAL;
    /* a probe the model cannot evaluate would give numbers of no meaning */
    if ((st = lf_model_check_region(m, &s->truth, err)) != LF_OK) {
        if (err != NULL) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            lf_fail(err, st, "%s: %s", c->name, why);
        }
        goto done;
    }
    st = lf_model_pulloff(m, &s->truth, &po, err);
    if (st != LF_OK)
        goto done;
    pp->delta_detach = c->branch == LF_BRANCH_LOAD ? 0.0 : po.delta_detach;
    pp->ba_pulloff = po.a_po > 0 ? c->probe.b / po.a_po : NAN;
    pp->delta_hi = c->delta_max;
    if (!isnan(c->delta_min))
        pp->delta_lo = c->delta_min;
    else if (c->baseline == 0.0)
        pp->delta_lo = NO_BASELINE_END * pp->delta_detach;
    else
        pp->delta_lo = pp->delta_detach
                       - (isnan(c->baseline) ? s->baseline_fraction * (c->delta_max - pp->delta_detach)
                                             : c->baseline);
    if (!(pp->delta_lo < pp->delta_hi)) {
        st = lf_fail(err, LF_EINVAL, "%s: the shallowest indentation (%g m) must lie above "
                     "the deepest (%g m)", c->name, pp->delta_lo, pp->delta_hi);
        goto done;
    }
    delta = malloc(n * sizeof *delta);
    P = malloc(n * sizeof *P);
    ev = malloc(n * sizeof *ev);
    evx = malloc(n * sizeof *evx);
    G = gsl_matrix_alloc(n, NL);
    tau = gsl_vector_alloc(NL);
    d = gsl_vector_alloc(n);
    if (!delta || !P || !ev || !evx || !G || !tau || !d) {
        st = lf_fail(err, LF_ENOMEM, "out of memory preparing a design");
        goto done;
    }
    /* the indentations as lf_simulate writes them */
    for (i = 0; i < n; i++) {
        double t = (double) i / (double) (n - 1);
        delta[i] = c->branch == LF_BRANCH_UNLOAD ? pp->delta_hi - t * (pp->delta_hi - pp->delta_lo)
                                                 : pp->delta_lo + t * (pp->delta_hi - pp->delta_lo);
    }
    st = lf_model_eval(m, &s->truth, c->branch, n, delta, evx, err);
    if (st != LF_OK)
        goto done;
    pp->fmax = 0.0;
    for (i = 0; i < n; i++) {
        P[i] = evx[i].P;
        pp->fmax = lf_fmax(pp->fmax, fabs(P[i]));
        if (evx[i].a > 0) {
            amin = lf_fmin(amin, evx[i].a);
            amax = lf_fmax(amax, evx[i].a);
        }
    }
    if (!(pp->fmax > 0) || !isfinite(pp->fmax)) {
        st = lf_fail(err, LF_EDATA, "%s: the curve has no force (no contact in its range)", c->name);
        goto done;
    }
    pp->ba_min = amax > 0 ? c->probe.b / amax : NAN;
    pp->ba_max = amax > 0 ? c->probe.b / amin : NAN;
    pp->sigma = isfinite(c->noise_abs) ? c->noise_abs
                : isfinite(c->noise_rel) ? c->noise_rel * pp->fmax
                : isfinite(s->noise_abs) ? s->noise_abs : s->noise_rel * pp->fmax;
    if (!(pp->sigma > 0) || !isfinite(pp->sigma)) {
        st = lf_fail(err, LF_EINVAL, "%s: the noise must be > 0", c->name);
        goto done;
    }
    for (rung = 0; rung < NRUNG; rung++) {
        lf_model *mr = m;
        const lf_eval *e = evx;
        memset(&pp->m[rung], 0, sizeof pp->m[rung]);
        if (rung != RUNG_EXACT) {
            if (rung == RUNG_HALFSPACE && !(c->probe.k > 0.5))
                continue;
            if ((mr = lf_model_alloc(rung_type(rung), &c->probe, NULL)) == NULL)
                continue;
            st = lf_model_eval(mr, &s->truth, c->branch, n, delta, ev, NULL);
            lf_model_free(mr);
            if (st != LF_OK) {
                st = LF_OK;     /* this model cannot be used here */
                continue;
            }
            e = ev;
        }
        st = factor_part(pp, e, P, n, G, tau, d, &pp->m[rung]);
        if (st != LF_OK) {
            if (rung == RUNG_EXACT) {
                st = lf_fail(err, st, "%s: the exact model's derivatives are not finite", c->name);
                goto done;
            }
            memset(&pp->m[rung], 0, sizeof pp->m[rung]);
            st = LF_OK;
        }
    }
done:
    lf_model_free(m);
    free(delta);
    free(P);
    free(ev);
    free(evx);
    gsl_matrix_free(G);
    gsl_vector_free(tau);
    gsl_vector_free(d);
    return st;
}

lf_design *
lf_design_alloc(const lf_design_settings *s, size_t n, const lf_design_candidate *cand,
                lf_error *err)
{
    lf_design *d;
    size_t i;

    if (n == 0) {
        lf_fail(err, LF_EINVAL, "no candidate curves");
        return NULL;
    }
    if (!(s->truth.w > 0) || !isfinite(s->truth.w)) {
        lf_fail(err, LF_EINVAL, "the true w must be > 0 (e.g. 10mJ/m2): its error is relative");
        return NULL;
    }
    if (lf_material_check(&s->truth, LF_BASE_BONDED, err) != LF_OK)
        return NULL;
    if (!(s->rcond > 0 && s->rcond < 1) || !(s->choose.tol > 0)
        || !(s->baseline_fraction > 0) || !isfinite(s->baseline_fraction)) {
        lf_fail(err, LF_EINVAL, "design settings out of range (rcond in (0, 1), tolerance and "
                "baseline fraction > 0)");
        return NULL;
    }
    d = calloc(1, sizeof *d);
    if (d == NULL || (d->p = calloc(n, sizeof *d->p)) == NULL) {
        free(d);
        lf_fail(err, LF_ENOMEM, "out of memory");
        return NULL;
    }
    d->s = *s;
    d->n = n;
    for (i = 0; i < n; i++)
        if (prepare(s, &cand[i], &d->p[i], err) != LF_OK) {
            lf_design_free(d);
            return NULL;
        }
    return d;
}

void
lf_design_free(lf_design *d)
{
    if (d == NULL)
        return;
    free(d->p);
    free(d);
}

size_t
lf_design_size(const lf_design *d)
{
    return d->n;
}

/* ------------------------------------------------------- one set */

/* The decomposition of one set with given models. */
typedef struct {
    const lf_design *d;
    size_t ns;              /* curves */
    const size_t *idx;      /* their candidate indices */
    int *rung;              /* their models */
    int nu_free;
    size_t p;               /* columns */
    int col[3];             /* ln w, ln E*, nu columns (nu -1 when held) */
    int *cz0, *cF0;         /* per curve, -1 when held */
    gsl_matrix *A, *V;
    gsl_vector *S, *D, *work;
    size_t rank;
    double *nullw;          /* p */
    double se[3];           /* unscaled se of w, E*, nu in scaled units; 0
                               when not free or not determined */
} setwork;

static void
setwork_free(setwork *w)
{
    free(w->rung);
    free(w->cz0);
    free(w->cF0);
    free(w->nullw);
    gsl_matrix_free(w->A);
    gsl_matrix_free(w->V);
    gsl_vector_free(w->S);
    gsl_vector_free(w->D);
    gsl_vector_free(w->work);
}

static int
setwork_alloc(setwork *w, const lf_design *d, size_t ns, const size_t *idx)
{
    size_t j, p;
    int any_b = 0, any_f = 0;

    memset(w, 0, sizeof *w);
    w->d = d;
    w->ns = ns;
    w->idx = idx;
    for (j = 0; j < ns; j++) {
        if (d->p[idx[j]].c.probe.base == LF_BASE_BONDED)
            any_b = 1;
        else
            any_f = 1;
    }
    /* the fitter's rule (fit/problem.c): nu is free where the plan
     * determines it, bonded curves with frictionless ones */
    w->nu_free = !d->s.fix_nu && any_b && any_f;
    p = 0;
    w->col[0] = (int) p++;
    w->col[1] = (int) p++;
    w->col[2] = w->nu_free ? (int) p++ : -1;
    w->rung = calloc(ns, sizeof *w->rung);
    w->cz0 = calloc(ns, sizeof *w->cz0);
    w->cF0 = calloc(ns, sizeof *w->cF0);
    if (!w->rung || !w->cz0 || !w->cF0)
        return LF_ENOMEM;
    for (j = 0; j < ns; j++) {
        const lf_design_candidate *c = &d->p[idx[j]].c;
        w->cz0[j] = c->free_z0 ? (int) p++ : -1;
        w->cF0[j] = c->free_F0 ? (int) p++ : -1;
    }
    w->p = p;
    w->A = gsl_matrix_alloc(NL * ns, p);
    w->V = gsl_matrix_alloc(p, p);
    w->S = gsl_vector_alloc(p);
    w->D = gsl_vector_alloc(p);
    w->work = gsl_vector_alloc(p);
    w->nullw = calloc(p, sizeof *w->nullw);
    if (!w->A || !w->V || !w->S || !w->D || !w->work || !w->nullw)
        return LF_ENOMEM;
    return LF_OK;
}

/* Global column of local column c of set curve j, or -1. */
static int
column_of(const setwork *w, size_t j, int c)
{
    switch (c) {
    case C_W: return w->col[0];
    case C_E: return w->col[1];
    case C_NU: return w->col[2];
    case C_Z0: return w->cz0[j];
    default: return w->cF0[j];
    }
}

/* Stack, scale and decompose with the current models. */
static int
decompose(setwork *w)
{
    size_t j, r, k, l;
    int c;

    gsl_matrix_set_zero(w->A);
    for (j = 0; j < w->ns; j++) {
        const model_part *mp = &w->d->p[w->idx[j]].m[w->rung[j]];
        for (c = 0; c < NL; c++) {
            int g = column_of(w, j, c);
            if (g < 0)
                continue;
            for (r = 0; r < NL; r++)
                gsl_matrix_set(w->A, NL * j + r, (size_t) g, mp->R[r * NL + (size_t) c]);
        }
    }
    for (k = 0; k < w->p; k++) {
        gsl_vector_view col = gsl_matrix_column(w->A, k);
        double dn = gsl_blas_dnrm2(&col.vector);
        gsl_vector_set(w->D, k, dn);
        if (dn > 0)
            gsl_vector_scale(&col.vector, 1.0 / dn);
    }
    if (gsl_linalg_SV_decomp_jacobi(w->A, w->V, w->S) != GSL_SUCCESS)
        return LF_ENUMERIC;
    w->rank = 0;
    for (k = 0; k < w->p; k++)
        if (gsl_vector_get(w->S, k) > w->d->s.rcond * gsl_vector_get(w->S, 0))
            w->rank++;
    for (k = 0; k < w->p; k++) {
        w->nullw[k] = gsl_vector_get(w->D, k) > 0 ? 0.0 : 1.0;
        for (l = w->rank; l < w->p; l++)
            w->nullw[k] += gsl_matrix_get(w->V, k, l) * gsl_matrix_get(w->V, k, l);
    }
    for (c = 0; c < 3; c++) {
        int g = w->col[c];
        double s2 = 0.0;
        w->se[c] = 0.0;
        if (g < 0 || w->nullw[g] > NULL_WEIGHT)
            continue;
        for (l = 0; l < w->rank; l++) {
            double v = gsl_matrix_get(w->V, (size_t) g, l), sl = gsl_vector_get(w->S, l);
            s2 += v * v / (sl * sl);
        }
        w->se[c] = sqrt(s2);
    }
    return LF_OK;
}

/* Covariance of global columns a, b in the parameters' own units (ln w,
 * ln E*, nu, z0/L, F0/Fs). */
static double
covariance(const setwork *w, int a, int b)
{
    double s = 0.0, da = gsl_vector_get(w->D, (size_t) a), db = gsl_vector_get(w->D, (size_t) b);
    size_t l;

    for (l = 0; l < w->rank; l++) {
        double sl = gsl_vector_get(w->S, l);
        s += gsl_matrix_get(w->V, (size_t) a, l) * gsl_matrix_get(w->V, (size_t) b, l) / (sl * sl);
    }
    return s / (da * db);
}

/* Bias over se of w, E*, nu when set curve j uses model `rung`'s forces
 * in place of the exact ones (with the current decomposition, which must
 * be that of the models being judged). */
static void
project_bias(setwork *w, size_t j, int rung, double r[3])
{
    const model_part *mp = &w->d->p[w->idx[j]].m[rung];
    double *g = w->work->data;
    size_t k, l;
    int c, q;

    for (k = 0; k < w->p; k++)
        g[k] = 0.0;
    for (c = 0; c < NL; c++) {        /* D^-1 R^T Q^T d */
        int gc = column_of(w, j, c);
        double s = 0.0;
        if (gc < 0)
            continue;
        for (q = 0; q <= c; q++)
            s += mp->R[q * NL + c] * mp->qd[q];
        if (gsl_vector_get(w->D, (size_t) gc) > 0)
            g[gc] = s / gsl_vector_get(w->D, (size_t) gc);
    }
    for (c = 0; c < 3; c++) {
        int p = w->col[c];
        double s = 0.0;
        r[c] = 0.0;
        if (p < 0 || w->se[c] == 0.0)
            continue;
        for (l = 0; l < w->rank; l++) {
            double sl = gsl_vector_get(w->S, l), vg = 0.0;
            for (k = 0; k < w->p; k++)
                vg += gsl_matrix_get(w->V, k, l) * g[k];
            s += gsl_matrix_get(w->V, (size_t) p, l) * vg / (sl * sl);
        }
        r[c] = s / w->se[c];
    }
}

static double
max_abs3(const double r[3], int *which)
{
    double m = 0.0;
    int i;

    if (which)
        *which = 0;
    for (i = 0; i < 3; i++)
        if (fabs(r[i]) > m) {
            m = fabs(r[i]);
            if (which)
                *which = i;
        }
    return m;
}

/* The bias of set curve j with model `rung`, the others keeping theirs;
 * decomposes with j swapped and restores.  ok = 0 when that model is not
 * available for the curve. */
static int
curve_bias(setwork *w, size_t j, int rung, double r[3], int *ok)
{
    int saved = w->rung[j], st;

    r[0] = r[1] = r[2] = 0.0;
    *ok = w->d->p[w->idx[j]].m[rung].ok;
    if (!*ok || rung == RUNG_EXACT)
        return LF_OK;
    w->rung[j] = rung;
    st = decompose(w);
    if (st == LF_OK)
        project_bias(w, j, rung, r);
    w->rung[j] = saved;
    return st;
}

/* The auto rule of lf_fit_choose_driver at the truth: start thin; while
 * the summed bias of the cheaper models on w, E*, nu exceeds tol standard
 * errors, move the curve with the largest bias up (to half-space when its
 * own bias there is below tol, else to exact); reassess after each round.
 * Fills reasons and each curve's thin bias.  With settings.model set every
 * curve keeps that model. */
static int
choose_models(setwork *w, lf_design_curve_info *info)
{
    const lf_design_settings *s = &w->d->s;
    const double tol = s->choose.tol;
    double (*cur)[3] = NULL, (*thin)[3] = NULL, (*half)[3] = NULL;
    int *half_ok = NULL, fixed = s->model != NULL, st = LF_OK, ok;
    size_t j, round;

    cur = calloc(w->ns, sizeof *cur);
    thin = calloc(w->ns, sizeof *thin);
    half = calloc(w->ns, sizeof *half);
    half_ok = calloc(w->ns, sizeof *half_ok);
    if (!cur || !thin || !half || !half_ok) {
        st = LF_ENOMEM;
        goto done;
    }
    for (j = 0; j < w->ns; j++) {
        int r = fixed ? rung_of(s->model) : RUNG_THIN;
        if (!w->d->p[w->idx[j]].m[r].ok)
            r = RUNG_EXACT;
        w->rung[j] = r;
    }
    for (round = 0; !fixed && round <= s->choose.max_rounds; round++) {
        double total[3] = { 0, 0, 0 };
        int changed = 0, c;
        if ((st = decompose(w)) != LF_OK)
            goto done;
        for (j = 0; j < w->ns; j++) {
            cur[j][0] = cur[j][1] = cur[j][2] = 0.0;
            if (w->rung[j] != RUNG_EXACT)
                project_bias(w, j, w->rung[j], cur[j]);
            for (c = 0; c < 3; c++)
                total[c] += cur[j][c];
        }
        for (j = 0; j < w->ns; j++)
            half_ok[j] = 0;
        while (max_abs3(total, NULL) >= tol) {
            size_t jw = w->ns;
            double worst = 0.0;
            for (j = 0; j < w->ns; j++) {
                double bm = max_abs3(cur[j], NULL);
                if (w->rung[j] != RUNG_EXACT && bm > worst) {
                    worst = bm;
                    jw = j;
                }
            }
            if (jw == w->ns)
                break;
            for (c = 0; c < 3; c++)
                total[c] -= cur[jw][c];
            if (w->rung[jw] == RUNG_THIN && s->choose.halfspace
                && (st = curve_bias(w, jw, RUNG_HALFSPACE, half[jw], &half_ok[jw])) != LF_OK)
                goto done;
            if (w->rung[jw] == RUNG_THIN && half_ok[jw]
                && max_abs3(half[jw], NULL) < lf_fmin(tol, worst)) {
                w->rung[jw] = RUNG_HALFSPACE;
                memcpy(cur[jw], half[jw], sizeof cur[jw]);
            } else {
                w->rung[jw] = RUNG_EXACT;
                cur[jw][0] = cur[jw][1] = cur[jw][2] = 0.0;
            }
            for (c = 0; c < 3; c++)
                total[c] += cur[jw][c];
            changed = 1;
            if ((st = decompose(w)) != LF_OK)   /* the models being judged */
                goto done;
        }
        if (!changed)
            break;
    }
    /* the final assessment: each curve's thin and half-space biases */
    for (j = 0; j < w->ns && st == LF_OK; j++) {
        st = curve_bias(w, j, RUNG_THIN, thin[j], &ok);
        if (st == LF_OK && w->rung[j] == RUNG_HALFSPACE)
            st = curve_bias(w, j, RUNG_HALFSPACE, half[j], &half_ok[j]);
        info[j].thin_bias = ok ? max_abs3(thin[j], NULL) : NAN;
    }
    if (st != LF_OK)
        goto done;
    st = decompose(w);
    for (j = 0; j < w->ns && st == LF_OK; j++) {
        lf_design_curve_info *ci = &info[j];
        int wt, wh;
        double bt = max_abs3(thin[j], &wt), bh = max_abs3(half[j], &wh);
        ci->model = rung_type(w->rung[j]);
        if (fixed)
            snprintf(ci->model_reason, sizeof ci->model_reason,
                     "as requested; the thin-layer model would bias %s by %.2g se",
                     mat_names[wt], bt);
        else if (w->rung[j] == RUNG_THIN)
            snprintf(ci->model_reason, sizeof ci->model_reason,
                     "the thin-layer model biases %s by at most %.2g se (tolerance %.2g se)",
                     mat_names[wt], bt, tol);
        else if (w->rung[j] == RUNG_HALFSPACE)
            snprintf(ci->model_reason, sizeof ci->model_reason,
                     "the thin-layer model would bias %s by %.2g se, the half-space model "
                     "only %s by %.2g se (tolerance %.2g se)", mat_names[wt], bt,
                     mat_names[wh], bh, tol);
        else
            snprintf(ci->model_reason, sizeof ci->model_reason,
                     "the thin-layer model would bias %s by %.2g se (tolerance %.2g se, "
                     "with the other curves' biases added)", mat_names[wt], bt, tol);
    }
done:
    free(cur);
    free(thin);
    free(half);
    free(half_ok);
    return st;
}

void
lf_design_result_free(lf_design_result *r)
{
    if (r == NULL)
        return;
    free(r->curves);
    lf_warnings_free(&r->identifiability);
    lf_warnings_free(&r->notes);
    memset(r, 0, sizeof *r);
}

static void
estimate_set(lf_design_estimate *e, int free_, int determined, double se, double rel)
{
    e->free = free_;
    e->determined = free_ && determined;
    e->se = e->determined ? se : NAN;
    e->rel = e->determined ? rel : NAN;
}

/* k = 2 alone with free z0 and F0 and under 10% of each curve's points
 * past detachment: w rests on nothing (fit/uncertainty.c). */
static int
k2_without_baseline(const setwork *w)
{
    size_t j;

    for (j = 0; j < w->ns; j++) {
        const prepared *pp = &w->d->p[w->idx[j]];
        if (fabs(pp->c.probe.k - 2.0) > 1e-9 || w->cz0[j] < 0 || w->cF0[j] < 0)
            return 0;
        if ((double) pp->m[w->rung[j]].n_past >= K2_BASELINE_SHARE * (double) pp->c.points)
            return 0;
    }
    return 1;
}

/* What the set would not determine, in the fitter's words
 * (fit/uncertainty.c explain()). */
static void
explain(const setwork *w, lf_design_result *r, int w_null, int F0_null, int any_b, int any_f)
{
    const lf_design_settings *s = &w->d->s;
    char buf[800];
    size_t j, len = 0;
    int all_k2 = 1, other = 0;

    for (j = 0; j < w->ns; j++)
        if (fabs(w->d->p[w->idx[j]].c.probe.k - 2.0) > 1e-9)
            all_k2 = 0;
    if (any_b && !any_f && !r->nu.determined && !s->fix_nu && r->M.determined)
        lf_warn(&r->identifiability,
                "only bonded curves: the data fix M = Z*E* (to %.2g%%) and w; nu is not "
                "determined, so neither is E* (fix nu or add a frictionless curve)",
                100.0 * r->M.rel);
    lf_fit_say_undetermined(&r->identifiability,
                            any_b && !any_f && !r->nu.determined && !s->fix_nu && !r->M.determined,
                            !any_b && !s->fix_nu ? "frictionless" : NULL, w_null && F0_null,
                            all_k2, 0);
    buf[0] = '\0';
    for (j = 0; j < w->ns; j++) {
        const char *name = w->d->p[w->idx[j]].c.name;
        int k;
        for (k = 0; k < 2; k++) {
            int g = k ? w->cF0[j] : w->cz0[j];
            if (g < 0 || w->nullw[g] <= NULL_WEIGHT || (k == 1 && F0_null))
                continue;
            len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0,
                                     "%s%s[%s]", other ? ", " : "", k ? "F0" : "z0", name);
            other = 1;
        }
    }
    if (r->Estar.free && !r->Estar.determined && (any_f || s->fix_nu)) {
        len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0,
                                 "%sE*", other ? ", " : "");
        other = 1;
    }
    if (r->nu.free && !r->nu.determined) {
        len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0,
                                 "%snu", other ? ", " : "");
        other = 1;
    }
    if (!F0_null && r->w.free && !r->w.determined) {
        len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0,
                                 "%sw", other ? ", " : "");
        other = 1;
    }
    if (other && len < sizeof buf)
        lf_warn(&r->identifiability, "not determined by the data: %s (fix some of them or add curves)",
                buf);
    if (r->w.determined && r->w.rel > 0.5)
        lf_warn(&r->identifiability,
                "w is near the noise: its predicted error is %.3g%% of w, and a fit reports only "
                "an upper bound where w < 2 se", 100.0 * r->w.rel);
    if (r->identifiability.n == 0)
        lf_warn(&r->identifiability,
                "every free parameter is determined (smallest scaled singular value %.2g)",
                gsl_vector_get(w->S, w->p - 1) / gsl_vector_get(w->S, 0));
}

static void
notes(const setwork *w, lf_design_result *r)
{
    size_t j;

    for (j = 0; j < w->ns; j++) {
        const prepared *pp = &w->d->p[w->idx[j]];
        const lf_design_curve_info *ci = &r->curves[j];
        if (ci->model == &lf_model_thin && ci->ba_max > 0.1)
            lf_warn(&r->notes, "%s: b/a reaches %.3g in contact: the thin-layer model is "
                    "strained (a fit would warn above 0.1) though its bias is within tolerance",
                    pp->c.name, ci->ba_max);
        if (pp->c.probe.k > 2.0 + 1e-9 && ci->n_past > 0)
            lf_warn(&r->notes, "%s: k > 2 recorded through detachment, where the force's slope "
                    "diverges: the predicted errors (w above all) depend on where the points fall "
                    "next to detachment and may be optimistic (Monte Carlo fits of such curves "
                    "scattered up to 25%% more than predicted)", pp->c.name);
        if (pp->c.baseline != 0.0 && isnan(pp->c.delta_min) && fabs(pp->c.probe.k - 2.0) < 1e-9
            && (double) ci->n_past < K2_BASELINE_SHARE * (double) ci->n)
            lf_warn(&r->notes, "%s: only %zu of %zu points lie past detachment; the fitter "
                    "counts a baseline from %.0f%% of the points", pp->c.name, ci->n_past, ci->n,
                    100.0 * K2_BASELINE_SHARE);
    }
}

static int
eval_set(lf_design *d, size_t ns, const size_t *idx, lf_design_result *r)
{
    setwork w;
    size_t j;
    int st, any_b = 0, any_f = 0, w_null, F0_null = 0, c;
    int det[3], cols[3];
    double cov[3][3];

    memset(r, 0, sizeof *r);
    st = setwork_alloc(&w, d, ns, idx);
    if (st == LF_OK && (r->curves = calloc(ns, sizeof *r->curves)) == NULL)
        st = LF_ENOMEM;
    if (st != LF_OK)
        goto done;
    r->ncurves = ns;
    if ((st = choose_models(&w, r->curves)) != LF_OK)
        goto done;
    for (j = 0; j < ns; j++) {
        const prepared *pp = &d->p[idx[j]];
        lf_design_curve_info *ci = &r->curves[j];
        ci->index = idx[j];
        ci->delta_lo = pp->delta_lo;
        ci->delta_hi = pp->delta_hi;
        ci->delta_detach = pp->delta_detach;
        ci->n = pp->c.points;
        ci->n_past = pp->m[w.rung[j]].n_past;
        ci->sigma = pp->sigma;
        ci->fmax = pp->fmax;
        ci->ba_min = pp->ba_min;
        ci->ba_max = pp->ba_max;
        ci->ba_pulloff = pp->ba_pulloff;
        ci->free_z0 = pp->c.free_z0;
        ci->free_F0 = pp->c.free_F0;
        if (pp->c.probe.base == LF_BASE_BONDED)
            any_b = 1;
        else
            any_f = 1;
        if (w.cF0[j] >= 0 && w.nullw[w.cF0[j]] > NULL_WEIGHT)
            F0_null = 1;
    }
    r->npar = w.p;
    w_null = w.nullw[w.col[0]] > NULL_WEIGHT;
    if (k2_without_baseline(&w))
        w_null = F0_null = 1;
    for (c = 0; c < 3; c++) {
        cols[c] = w.col[c];
        det[c] = cols[c] >= 0 && w.nullw[cols[c]] <= NULL_WEIGHT;
    }
    det[0] = det[0] && !w_null;
    for (c = 0; c < 3; c++) {
        int a;
        for (a = 0; a < 3; a++)
            cov[c][a] = cols[c] >= 0 && cols[a] >= 0 ? covariance(&w, cols[c], cols[a]) : 0.0;
    }
    estimate_set(&r->w, 1, det[0], d->s.truth.w * sqrt(cov[0][0]), sqrt(cov[0][0]));
    estimate_set(&r->nu, w.nu_free, det[2], sqrt(cov[2][2]), sqrt(cov[2][2]));
    /* M = Z(nu) E* where bonded curves are present */
    if (any_b && det[1] && (cols[2] < 0 || det[2] || !any_f)) {
        double dl = lf_thin_dlogZ_dnu(LF_BASE_BONDED, d->s.truth.nu);
        double var = cov[1][1] + (cols[2] >= 0 ? 2 * dl * cov[1][2] + dl * dl * cov[2][2] : 0.0);
        double M = lf_thin_Z(LF_BASE_BONDED, d->s.truth.nu) * d->s.truth.Estar;
        estimate_set(&r->M, 1, var >= 0, M * sqrt(lf_fmax(var, 0)), sqrt(lf_fmax(var, 0)));
    } else {
        estimate_set(&r->M, any_b, 0, NAN, NAN);
    }
    /* E*: bonded curves alone fix M only, unless nu is known */
    if (any_b && !any_f && !d->s.fix_nu)
        det[1] = 0;
    estimate_set(&r->Estar, 1, det[1], d->s.truth.Estar * sqrt(cov[1][1]), sqrt(cov[1][1]));
    r->corr_wE = det[0] && det[1] ? cov[0][1] / sqrt(cov[0][0] * cov[1][1]) : NAN;
    /* the information of the determined material parameters, nuisance
     * profiled: the inverse of their covariance block */
    {
        double blk[9];
        int map[3], m = 0, a, b;
        for (c = 0; c < 3; c++)
            if (det[c] && cols[c] >= 0)
                map[m++] = c;
        r->ndetermined = (size_t) m;
        r->logdet = -HUGE_VAL;
        if (m > 0) {
            gsl_matrix_view B = gsl_matrix_view_array(blk, (size_t) m, (size_t) m);
            double ld = 0.0;
            for (a = 0; a < m; a++)
                for (b = 0; b < m; b++)
                    blk[a * m + b] = cov[map[a]][map[b]];
            if (gsl_linalg_cholesky_decomp1(&B.matrix) == GSL_SUCCESS) {
                for (a = 0; a < m; a++)
                    ld += 2.0 * log(blk[a * m + a]);
                r->logdet = -ld;
            }
        }
    }
    explain(&w, r, w_null, F0_null, any_b, any_f);
    notes(&w, r);
done:
    setwork_free(&w);
    if (st != LF_OK)
        lf_design_result_free(r);
    return st;
}

int
lf_design_eval(lf_design *d, const int *use, lf_design_result *out, lf_error *err)
{
    size_t *idx = malloc(d->n * sizeof *idx), ns = 0, i;
    int st;

    memset(out, 0, sizeof *out);
    if (idx == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    for (i = 0; i < d->n; i++)
        if (use == NULL || use[i])
            idx[ns++] = i;
    if (ns == 0) {
        free(idx);
        return lf_fail(err, LF_EDATA, "no candidate in the set");
    }
    st = eval_set(d, ns, idx, out);
    free(idx);
    if (st != LF_OK)
        return lf_fail(err, st, "the design cannot be evaluated (%s)", lf_strerror(st));
    return LF_OK;
}

/* ------------------------------------------------------- choosing */

static const char *const target_names[] = { "w", "E", "nu", "all" };

const char *
lf_design_target_name(lf_design_target t)
{
    return (unsigned) t < 4 ? target_names[t] : "?";
}

int
lf_design_target_find(const char *name)
{
    int i;
    for (i = 0; i < 4; i++)
        if (strcmp(name, target_names[i]) == 0)
            return i;
    return -1;
}

lf_design_score
lf_design_score_of(const lf_design_result *r, lf_design_target t)
{
    lf_design_score s;
    const lf_design_estimate *e = t == LF_TARGET_W ? &r->w : t == LF_TARGET_E ? &r->Estar : &r->nu;

    s.target = t;
    s.ndetermined = r->ndetermined;
    s.logdet = r->logdet;
    if (t == LF_TARGET_ALL) {
        s.target_determined = r->ndetermined > 0;
        s.value = r->logdet;
    } else {
        s.target_determined = e->determined;
        s.value = e->determined ? -e->rel : -HUGE_VAL;
    }
    return s;
}

int
lf_design_score_cmp(const lf_design_score *a, const lf_design_score *b)
{
    if (a->target_determined != b->target_determined)
        return a->target_determined ? 1 : -1;
    if ((a->target == LF_TARGET_ALL || !a->target_determined) && a->ndetermined != b->ndetermined)
        return a->ndetermined > b->ndetermined ? 1 : -1;
    if (a->value != b->value)
        return a->value > b->value ? 1 : -1;
    if (a->logdet != b->logdet)
        return a->logdet > b->logdet ? 1 : -1;
    return 0;
}

void
lf_design_choice_free(lf_design_choice *c)
{
    if (c == NULL)
        return;
    free(c->steps);
    free(c->chosen);
    memset(c, 0, sizeof *c);
}

/* Score of the set `use` (n flags). */
static int
score_set(lf_design *d, const int *use, lf_design_target t, lf_design_result *r,
          lf_design_score *s, lf_error *err)
{
    int st = lf_design_eval(d, use, r, err);
    if (st == LF_OK)
        *s = lf_design_score_of(r, t);
    return st;
}

int
lf_design_choose(lf_design *d, size_t nchoose, lf_design_target target,
                 lf_design_choice *out, lf_error *err)
{
    size_t step, i;
    int st = LF_OK;

    memset(out, 0, sizeof *out);
    if (nchoose == 0 || nchoose > d->n)
        return lf_fail(err, LF_EINVAL, "choose between 1 and %zu candidates (got %zu)", d->n,
                       nchoose);
    if ((unsigned) target > LF_TARGET_ALL)
        return lf_fail(err, LF_EINVAL, "unknown target");
    out->steps = calloc(nchoose, sizeof *out->steps);
    out->chosen = calloc(d->n, sizeof *out->chosen);
    if (!out->steps || !out->chosen) {
        lf_design_choice_free(out);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (step = 0; step < nchoose; step++) {
        lf_design_step *sp = &out->steps[step];
        lf_design_result best_r;
        int have = 0, have2 = 0;
        memset(&best_r, 0, sizeof best_r);
        sp->runner_up = (size_t) -1;
        for (i = 0; i < d->n; i++) {
            lf_design_result r;
            lf_design_score s;
            if (out->chosen[i])
                continue;
            out->chosen[i] = 1;
            st = score_set(d, out->chosen, target, &r, &s, err);
            out->chosen[i] = 0;
            if (st != LF_OK)
                break;
            if (!have || lf_design_score_cmp(&s, &sp->score) > 0) {
                if (have) {
                    sp->runner_up = sp->added;
                    sp->runner_score = sp->score;
                    have2 = 1;
                }
                lf_design_result_free(&best_r);
                best_r = r;
                sp->added = i;
                sp->score = s;
                have = 1;
            } else {
                if (!have2 || lf_design_score_cmp(&s, &sp->runner_score) > 0) {
                    sp->runner_up = i;
                    sp->runner_score = s;
                    have2 = 1;
                }
                lf_design_result_free(&r);
            }
        }
        if (st != LF_OK) {
            lf_design_result_free(&best_r);
            lf_design_choice_free(out);
            return st;
        }
        out->chosen[sp->added] = 1;
        sp->w = best_r.w;
        sp->Estar = best_r.Estar;
        sp->nu = best_r.nu;
        lf_design_result_free(&best_r);
        out->nsteps = step + 1;
    }
    return LF_OK;
}

int
lf_design_exhaustive(lf_design *d, size_t nchoose, lf_design_target target, size_t max_sets,
                     int *best, lf_design_score *score, lf_error *err)
{
    size_t *comb, i, k = nchoose, n = d->n, nsets = 1;
    int *use, have = 0, st = LF_OK;

    if (nchoose == 0 || nchoose > n)
        return lf_fail(err, LF_EINVAL, "choose between 1 and %zu candidates (got %zu)", n, nchoose);
    for (i = 0; i < k; i++) {       /* C(n, k), capped */
        nsets = nsets * (n - i) / (i + 1);
        if (nsets > max_sets)
            return lf_fail(err, LF_EINVAL, "more than %zu sets of %zu among %zu candidates "
                           "to search", max_sets, k, n);
    }
    comb = malloc(k * sizeof *comb);
    use = calloc(n, sizeof *use);
    if (!comb || !use) {
        free(comb);
        free(use);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (i = 0; i < k; i++)
        comb[i] = i;
    for (;;) {
        lf_design_result r;
        lf_design_score s;
        memset(use, 0, n * sizeof *use);
        for (i = 0; i < k; i++)
            use[comb[i]] = 1;
        if ((st = score_set(d, use, target, &r, &s, err)) != LF_OK)
            break;
        lf_design_result_free(&r);
        if (!have || lf_design_score_cmp(&s, score) > 0) {
            *score = s;
            memcpy(best, use, n * sizeof *use);
            have = 1;
        }
        /* next combination in lexicographic order */
        i = k;
        while (i > 0 && comb[i - 1] == n - k + i - 1)
            i--;
        if (i == 0)
            break;
        comb[i - 1]++;
        for (; i < k; i++)
            comb[i] = comb[i - 1] + 1;
    }
    free(comb);
    free(use);
    return st;
}

/* ------------------------------------------------------- sweeping */

static const char *const factor_names[] = { "k", "delta_max", "points", "b", "R", "baseline" };
#define NFACTOR ((int) (sizeof factor_names / sizeof factor_names[0]))

const char *
lf_design_factor_name(lf_design_factor f)
{
    return (int) f >= 0 && (int) f < NFACTOR ? factor_names[f] : "?";
}

int
lf_design_factor_find(const char *name)
{
    int i;
    if (strcmp(name, "depth") == 0)
        return LF_FACTOR_DELTA_MAX;
    for (i = 0; i < NFACTOR; i++)
        if (strcmp(name, factor_names[i]) == 0)
            return i;
    return -1;
}

lf_quantity
lf_design_factor_quantity(lf_design_factor f)
{
    return f == LF_FACTOR_K || f == LF_FACTOR_POINTS ? LF_Q_DIMENSIONLESS : LF_Q_LENGTH;
}

static int
apply_factor(lf_design_candidate *c, lf_design_factor f, double v, lf_error *err)
{
    switch (f) {
    case LF_FACTOR_K: c->probe.k = v; break;
    case LF_FACTOR_DELTA_MAX: c->delta_max = v; break;
    case LF_FACTOR_B: c->probe.b = v; break;
    case LF_FACTOR_R: c->probe.R = v; break;
    case LF_FACTOR_BASELINE:
        if (!(v >= 0) || !isfinite(v))
            return lf_fail(err, LF_EINVAL, "baseline must be >= 0 (got %g)", v);
        c->baseline = v;
        c->delta_min = NAN;
        break;
    case LF_FACTOR_POINTS:
        if (!(v >= NL && v <= 1e7) || v != floor(v))
            return lf_fail(err, LF_EINVAL, "points must be a whole number from %d (got %g)", NL, v);
        c->points = (size_t) v;
        break;
    default:
        return lf_fail(err, LF_EINVAL, "unknown factor");
    }
    return LF_OK;
}

int
lf_design_sweep(const lf_design_settings *s, size_t n, const lf_design_candidate *cand,
                lf_design_factor factor, size_t which, size_t nv, const double *values,
                lf_design_result *out, lf_error *err)
{
    lf_design_candidate *c = malloc((n ? n : 1) * sizeof *c);
    size_t v, i;
    int st = LF_OK;

    if (c == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    if (which != (size_t) -1 && which >= n) {
        free(c);
        return lf_fail(err, LF_EINVAL, "candidate %zu does not exist", which + 1);
    }
    for (v = 0; v < nv; v++)
        memset(&out[v], 0, sizeof out[v]);
    for (v = 0; v < nv && st == LF_OK; v++) {
        lf_design *d;
        memcpy(c, cand, n * sizeof *c);
        for (i = 0; i < n && st == LF_OK; i++)
            if (which == (size_t) -1 || which == i)
                st = apply_factor(&c[i], factor, values[v], err);
        if (st != LF_OK)
            break;
        d = lf_design_alloc(s, n, c, err);
        if (d == NULL) {
            st = err ? err->status : LF_EINVAL;
            break;
        }
        st = lf_design_eval(d, NULL, &out[v], err);
        lf_design_free(d);
    }
    if (st != LF_OK)
        for (v = 0; v < nv; v++)
            lf_design_result_free(&out[v]);
    free(c);
    return st;
}
