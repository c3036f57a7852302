/* edge_scan.c: the contact-edge scan, a policy for curves whose contact
 * point is free.  Contract: solve, then move each free contact point
 * across neighbouring data points while that lowers the cost, and solve
 * again from there.
 *
 * The model has a kink where contact ends (a vertical tangent for k > 2),
 * and the cost a kink at every data point that crosses it: a gradient
 * method stops at the nearest one. */
#include <math.h>

#include "fit.h"

/* Curve j's weighted sum of squares (robust weights included) at material
 * mat and contact point z0, with its force offset (when free) at its best
 * value for them, returned in *F0; slope as given.  HUGE_VAL when the model cannot be evaluated. */
static double
curve_cost(lf_fit *f, size_t j, const lf_material *mat, double z0, double *F0,
           double slope)
{
    const fit_curve *c = &f->c[j];
    double *delta = f->w.work, sum = 0.0, ss = 0.0;
    const double *sw = f->w.sqrtw + c->row;
    lf_eval *e = f->w.scan_ev;
    size_t i, n = c->data.n;

    for (i = 0; i < n; i++)
        delta[i] = c->data.depth[i] - z0;
    if (lf_model_eval(c->model, mat, c->data.branch, n, delta, e, NULL) != LF_OK)
        return HUGE_VAL;
    if (c->iF0 >= 0) {
        double wsum = 0.0;
        for (i = 0; i < n; i++) {
            double wt = sw[i] * sw[i];
            sum += wt * (c->data.force[i] - e[i].P - slope * delta[i]);
            wsum += wt;
        }
        *F0 = sum / wsum;
    }
    for (i = 0; i < n; i++) {
        double r = (e[i].P + *F0 + slope * delta[i] - c->data.force[i]) / c->sigma * sw[i];
        ss += r * r;
    }
    return isfinite(ss) ? ss : HUGE_VAL;
}

/* The best placement of curve j's edge so far, as the scan finds it. */
typedef struct {
    double cost, z0, F0;
} edge_best;

/* Try curve j's edge between its points ord[q - 1] and ord[q] in depth (the
 * material mat held, the force offset re-solved): 1 when that beats *b
 * (then b holds it), else 0. */
static int
try_edge(lf_fit *f, size_t j, long q, const lf_material *mat, const lf_pulloff *po, double F0,
         double slope, edge_best *b)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    double zq, z0q, F0q = F0, v;

    if (q < 1 || q > (long) c->data.n - 1
        || !(c->data.depth[ord[q]] > c->data.depth[ord[q - 1]]))
        return 0;
    zq = 0.5 * (c->data.depth[ord[q - 1]] + c->data.depth[ord[q]]);
    z0q = c->data.branch == LF_BRANCH_UNLOAD ? zq - po->delta_detach : zq;
    v = curve_cost(f, j, mat, z0q, &F0q, slope);
    if (!(v < b->cost * (1.0 - 1e-12)))
        return 0;
    b->cost = v;
    b->z0 = z0q;
    b->F0 = F0q;
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
        lf_material mat;
        lf_pulloff po;
        edge_best b;
        double z0, F0, slope, edge;
        size_t n = c->data.n, pos, d, worse;
        int dir;

        if (c->iz0 < 0 || n < 3)
            continue;
        lf_fit_unpack(f, x->data, &mat, &z0, &F0, &slope, j);
        if (lf_model_pulloff(c->model, &mat, &po, NULL) != LF_OK)
            continue;
        /* the edge in depth: detachment on unloading, z0 on loading */
        edge = c->data.branch == LF_BRANCH_UNLOAD ? z0 + po.delta_detach : z0;
        for (pos = 0; pos < n && c->data.depth[ord[pos]] < edge; pos++)
            ;
        b.F0 = F0;
        b.cost = curve_cost(f, j, &mat, z0, &b.F0, slope);
        b.z0 = z0;
        try_edge(f, j, (long) pos, &mat, &po, F0, slope, &b);
        for (dir = -1; dir <= 1; dir += 2)
            for (d = 1, worse = 0; d <= FIT_SCAN_HALF && worse < FIT_SCAN_PATIENCE; d++) {
                long q = (long) pos + dir * (long) d;
                if (q < 1 || q > (long) n - 1)
                    break;
                worse = try_edge(f, j, q, &mat, &po, F0, slope, &b) ? 0 : worse + 1;
            }
        if (b.z0 != z0) {
            /* back to x: internal = x0 + x - 1, z0 = L internal, F0 = Fs internal */
            gsl_vector_set(x, (size_t) c->iz0, b.z0 / c->L - f->x0_internal[c->iz0] + 1.0);
            if (c->iF0 >= 0)
                gsl_vector_set(x, (size_t) c->iF0, b.F0 / c->Fs - f->x0_internal[c->iF0] + 1.0);
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
    for (scan = 0; status == LF_OK && scan < FIT_MAX_SCANS && edge_scan(f, x); scan++)
        status = lf_fit_iterate(f, x, 1, run, err);
    return status;
}
