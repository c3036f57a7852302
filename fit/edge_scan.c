/* edge_scan.c: the contact-edge scan, a policy for curves whose contact
 * point is free.  Contract: solve, then move each free contact point
 * across neighbouring data points while that lowers the cost, and solve
 * again from there.
 *
 * The model has a kink where contact ends (a vertical tangent for k > 2),
 * and the cost a kink at every data point that crosses it: a gradient
 * method stops at the nearest one. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

/* Points past the edge that an interpolated scan evaluates with the
 * model: the force's derivatives grow without bound towards the edge (a
 * vertical tangent for k > 2), so the cubic interpolation holds only
 * some points away from it. */
#define SCAN_EXACT_NEAR 8

/* What the scan of one curve holds: the material and the curve's offsets
 * at x, the edge (the indentation where contact ends), whether costs come
 * from interpolation, and the best placement so far. */
typedef struct {
    lf_material mat;
    double z0, F0, slope;
    double edge;
    lf_pulloff po;
    int interp;
    double cost, best_z0, best_F0;
    /* an interpolated scan's data at x, in depth order (interp_prepare):
     * the indentations d, the model's forces Pd and slopes Dd there, the
     * first point interpolated (qs) and the range [lo, hi]; at: scratch
     * for the points the model evaluates */
    double *d, *Pd, *Dd, lo, hi;
    size_t qs, *at;
} edge_scan_state;

/* Curve j's weighted sum of squares (robust weights included) with the
 * model's forces P[i] (file order) at contact point z0, its force offset
 * (when free) at its best value for them, returned in *F0; slope as
 * given.  HUGE_VAL when not finite. */
static double
cost_of(const lf_fit *f, size_t j, const double *P, double z0, double *F0, double slope)
{
    const fit_curve *c = &f->c[j];
    const double *sw = f->ws.sqrtw + c->row, *z = c->data.depth, *F = c->data.force;
    double sum = 0.0, ss = 0.0;
    size_t i, n = c->data.n;

    if (c->iF0 >= 0) {
        double wsum = 0.0;
        for (i = 0; i < n; i++) {
            double wt = sw[i] * sw[i];
            sum += wt * (F[i] - P[i] - slope * (z[i] - z0));
            wsum += wt;
        }
        *F0 = sum / wsum;
    }
    for (i = 0; i < n; i++) {
        double r = (P[i] + *F0 + slope * (z[i] - z0) - F[i]) / c->sigma * sw[i];
        ss += r * r;
    }
    return isfinite(ss) ? ss : HUGE_VAL;
}

/* The model's forces of curve j at contact point z0 (material mat) at
 * every point, into P (file order); 0 when it cannot be evaluated. */
static int
model_forces(lf_fit *f, size_t j, const lf_material *mat, double z0, double *P)
{
    const fit_curve *c = &f->c[j];
    double *delta = f->ws.work + c->data.n;
    lf_eval *e = f->ws.scan_ev;
    size_t i, n = c->data.n;

    for (i = 0; i < n; i++)
        delta[i] = c->data.depth[i] - z0;
    if (lf_model_eval(c->model, mat, c->data.branch, n, delta, e, NULL) != LF_OK)
        return 0;
    for (i = 0; i < n; i++)
        P[i] = e[i].P;
    return 1;
}

/* Where an interpolated scan takes the force at indentation t: 0 out of
 * contact (P = 0), 1 from the model (near the edge, or deeper than the
 * data at x), 2 by interpolation among the evaluations at x ([lo, hi]:
 * the interpolation's range of indentations). */
static int
shifted_kind(double t, double edge, double lo, double hi)
{
    if (t < edge)
        return 0;
    return t >= lo && t <= hi ? 2 : 1;
}

/* Set up an interpolated scan of curve j from the model's evaluations at
 * x (f->ws.ev, valid): the indentations at x in depth order, the forces
 * and slopes there, and where the interpolation starts: SCAN_EXACT_NEAR
 * points past the first in contact.  0 when out of memory. */
static int
interp_prepare(lf_fit *f, size_t j, edge_scan_state *s)
{
    const fit_curve *c = &f->c[j];
    const size_t n = c->data.n, *ord = f->order + c->row;
    const lf_eval *ev = f->ws.ev + c->row;
    const double *z = c->data.depth;
    size_t r;

    s->d = malloc(3 * n * sizeof *s->d);
    s->at = malloc(n * sizeof *s->at);
    if (s->d == NULL || s->at == NULL) {
        free(s->d);
        free(s->at);
        s->d = NULL;
        s->at = NULL;
        return 0;
    }
    s->Pd = s->d + n;
    s->Dd = s->d + 2 * n;
    for (r = 0; r < n; r++) {
        s->d[r] = z[ord[r]] - s->z0;
        s->Pd[r] = ev[ord[r]].P;
        s->Dd[r] = ev[ord[r]].dP_ddelta;
    }
    for (r = 0; r < n && !(s->d[r] > s->edge); r++)
        ;
    s->qs = r + SCAN_EXACT_NEAR;
    s->lo = s->qs < n ? s->d[s->qs] : HUGE_VAL;
    s->hi = s->d[n - 1];
    return 1;
}

static void
interp_release(edge_scan_state *s)
{
    free(s->d);
    free(s->at);
    s->d = NULL;
    s->at = NULL;
}

/* Curve j's forces with its contact point moved from s->z0 to z0 (the
 * material as at x), into P (file order), from the model's evaluations at
 * x (interp_prepare): each point's indentation t = z - z0 falls between
 * two data points' indentations at x, where the cubic Hermite interpolant
 * of their forces and slopes gives the force (error h^4 / 384 times the
 * force's fourth derivative: far below the noise for data dense enough to
 * fit); the model itself at the points near the edge or beyond the
 * deepest indentation at x, in one call.  0 when the model cannot be
 * evaluated. */
static int
shifted_forces(lf_fit *f, size_t j, const edge_scan_state *s, double z0, double *P)
{
    const fit_curve *c = &f->c[j];
    const size_t n = c->data.n, *ord = f->order + c->row;
    const double *z = c->data.depth, *d = s->d, *Pd = s->Pd, *Dd = s->Dd;
    double *dl = f->ws.work + n;
    lf_eval *out = f->ws.scan_ev;
    size_t q, r, m = 0, k;

    for (q = 0, r = s->qs; q < n; q++) {
        const double t = z[ord[q]] - z0;
        double h, u, u2, u3;
        switch (shifted_kind(t, s->edge, s->lo, s->hi)) {
        case 0:
            P[ord[q]] = 0.0;
            continue;
        case 1:
            s->at[m] = ord[q];
            dl[m++] = t;
            continue;
        default:
            break;
        }
        while (r + 1 < n && d[r + 1] <= t)
            r++;                    /* d_r <= t < d_{r+1} (t = d_r at the top) */
        if (r + 1 >= n || t == d[r]) {
            P[ord[q]] = Pd[r];
            continue;
        }
        h = d[r + 1] - d[r];
        u = (t - d[r]) / h;
        u2 = u * u;
        u3 = u2 * u;
        P[ord[q]] = (2.0 * u3 - 3.0 * u2 + 1.0) * Pd[r] + (u3 - 2.0 * u2 + u) * h * Dd[r]
                    + (3.0 * u2 - 2.0 * u3) * Pd[r + 1] + (u3 - u2) * h * Dd[r + 1];
    }
    if (m > 0 && lf_model_eval(c->model, &s->mat, c->data.branch, m, dl, out, NULL) != LF_OK)
        return 0;
    for (k = 0; k < m; k++)     /* the model's, in the same order */
        P[s->at[k]] = out[k].P;
    return 1;
}

/* Curve j's cost with its contact point at z0 (force offset re-solved
 * into *F0); HUGE_VAL when the model cannot be evaluated. */
static double
curve_cost(lf_fit *f, size_t j, const edge_scan_state *s, double z0, double *F0)
{
    double *P = f->ws.work;      /* P in work[0, n); the two above use work[n, 2n) */
    int ok = s->interp ? shifted_forces(f, j, s, z0, P) : model_forces(f, j, &s->mat, z0, P);
    return ok ? cost_of(f, j, P, z0, F0, s->slope) : HUGE_VAL;
}

/* 1 when curve j's model costs more per point than the interpolation:
 * every model but the thin layer's with a power-law probe of k = 1, 2 or
 * 4 or a sphere, whose forces are products and square roots (at k = 3 a
 * cube root, at other k exp and log).  Measured: interpolated, a batch of
 * thin k = 3 curves with linear intervals takes 3% fewer instructions (and
 * time), one at k = 1.5 18% fewer, one at k = 2 2% more time; the same
 * outputs on each. */
static int
dearer_than_interpolant(const fit_curve *c)
{
    const lf_probe *p = &c->data.probe;

    return lf_model_get_type(c->model) != &lf_model_thin
           || !(p->tip == LF_TIP_SPHERE || p->k == 1.0 || p->k == 2.0 || p->k == 4.0);
}

/* Set up the scan of curve j at x; 0 when the model has no pull-off
 * there.  Interpolated for a model dearer per point than the
 * interpolation, when the evaluations at x exist. */
static int
scan_state(lf_fit *f, size_t j, const double *x, edge_scan_state *s)
{
    const fit_curve *c = &f->c[j];

    s->d = s->Pd = s->Dd = NULL;
    s->at = NULL;
    lf_fit_unpack(f, x, &s->mat, &s->z0, &s->F0, &s->slope, j);
    if (lf_model_pulloff(c->model, &s->mat, &s->po, NULL) != LF_OK)
        return 0;
    s->edge = c->data.branch == LF_BRANCH_UNLOAD ? s->po.delta_detach : 0.0;
    s->interp = dearer_than_interpolant(c) && lf_fit_eval_at(f, x) == LF_OK
                && interp_prepare(f, j, s);
    return 1;
}

double
lf_fit_scan_cost(lf_fit *f, size_t j, const gsl_vector *x, double z0, int interpolate)
{
    edge_scan_state s;
    double F0, v;

    if (!scan_state(f, j, x->data, &s))
        return HUGE_VAL;
    if (interpolate && !s.interp
        && (lf_fit_eval_at(f, x->data) != LF_OK || !interp_prepare(f, j, &s)))
        return HUGE_VAL;
    s.interp = interpolate;
    F0 = s.F0;
    v = curve_cost(f, j, &s, z0, &F0);
    interp_release(&s);
    return v;
}

/* Curve j's cost at x itself (its force offset re-solved into *F0), from
 * the model's evaluation at x where the fit holds it (the solver's last),
 * else as curve_cost.  The same forces as curve_cost's: bit for bit
 * without interpolation; interpolated, at x's own indentations the
 * interpolation returns these evaluations, and the points near the edge
 * that it would give the model again differ by rounding (the exact
 * model's solution from another start). */
static double
cost_at_x(lf_fit *f, size_t j, const gsl_vector *x, const edge_scan_state *s, double *F0)
{
    const fit_curve *c = &f->c[j];
    double *P = f->ws.work;
    size_t i;

    if (!f->ws.xcache_ok || memcmp(x->data, f->ws.xcache, f->np * sizeof *x->data))
        return curve_cost(f, j, s, s->z0, F0);
    for (i = 0; i < c->data.n; i++)
        P[i] = f->ws.ev[c->row + i].P;
    return cost_of(f, j, P, s->z0, F0, s->slope);
}

/* Try curve j's edge between its points ord[q - 1] and ord[q] in depth (the
 * material held, the force offset re-solved): 1 when that beats the best
 * placement so far (then s holds it), else 0. */
static int
try_edge(lf_fit *f, size_t j, long q, edge_scan_state *s)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    double zq, z0q, F0q = s->F0, v;

    if (q < 1 || q > (long) c->data.n - 1
        || !(c->data.depth[ord[q]] > c->data.depth[ord[q - 1]]))
        return 0;
    zq = 0.5 * (c->data.depth[ord[q - 1]] + c->data.depth[ord[q]]);
    z0q = c->data.branch == LF_BRANCH_UNLOAD ? zq - s->po.delta_detach : zq;
    v = curve_cost(f, j, s, z0q, &F0q);
    if (!(v < s->cost * (1.0 - 1e-12)))
        return 0;
    s->cost = v;
    s->best_z0 = z0q;
    s->best_F0 = F0q;
    return 1;
}

/* For each free contact point, try placing the edge in its own interval
 * between neighbouring points, then outwards each way until
 * FIT_SCAN_PATIENCE positions in a row have not beaten the best (over the
 * positions the cost is a bowl roughened by the noise) or FIT_SCAN_HALF have
 * been tried; the force offset re-solved, the rest held.  Move x to the best
 * when it lowers the cost.  Returns 1 if it moved. */
static int
edge_scan(lf_fit *f, gsl_vector *x)
{
    size_t j;
    int moved = 0;

    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        const size_t *ord = f->order + c->row;
        edge_scan_state s;
        double edge;
        size_t n = c->data.n, pos, d, worse;
        int dir;

        if (c->iz0 < 0 || n < 3 || !scan_state(f, j, x->data, &s))
            continue;
        /* the edge in depth: detachment on unloading, z0 on loading */
        edge = s.z0 + s.edge;
        for (pos = 0; pos < n && c->data.depth[ord[pos]] < edge; pos++)
            ;
        s.best_F0 = s.F0;
        s.cost = cost_at_x(f, j, x, &s, &s.best_F0);
        s.best_z0 = s.z0;
        try_edge(f, j, (long) pos, &s);
        for (dir = -1; dir <= 1; dir += 2)
            for (d = 1, worse = 0; d <= FIT_SCAN_HALF && worse < FIT_SCAN_PATIENCE; d++) {
                long q = (long) pos + dir * (long) d;
                if (q < 1 || q > (long) n - 1)
                    break;
                worse = try_edge(f, j, q, &s) ? 0 : worse + 1;
            }
        interp_release(&s);
        if (s.best_z0 != s.z0) {
            /* back to x: internal = x0 + x - 1, z0 = L internal, F0 = Fs internal */
            gsl_vector_set(x, (size_t) c->iz0, s.best_z0 / c->L - f->x0_internal[c->iz0] + 1.0);
            if (c->iF0 >= 0)
                gsl_vector_set(x, (size_t) c->iF0, s.best_F0 / c->Fs - f->x0_internal[c->iF0] + 1.0);
            moved = 1;
        }
    }
    /* the scan's evaluations went to scan_ev and work: the cache of ev
     * (keyed by x) still holds */
    return moved;
}

int
lf_fit_solve_scanned(lf_fit *f, gsl_vector *x, int from_origin, fit_run *run, lf_error *err)
{
    int scan, status;

    if (from_origin) {
        gsl_vector_set_all(x, 1.0);
        lf_fit_invalidate(f);
    }
    status = lf_fit_iterate(f, x, !from_origin, run, err);
    for (scan = 0; status == LF_OK && !f->ws.basin_hit && !f->stopped_above && scan < FIT_MAX_SCANS
                   && edge_scan(f, x); scan++)
        status = lf_fit_iterate(f, x, 1, run, err);
    return status;
}
