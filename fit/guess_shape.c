/* guess_shape.c: the start of a half-space curve from its shape alone,
 * for a retract curve that ends before its detachment (fit/guess_model.c
 * decides when; header there).
 *
 * In linear elasticity with an adhesive edge every force is E* times a
 * function of the geometry and w/E*, every length a function of w/E*: at
 * a trial x = w/E* the curve F(z) = alpha P(z - z0; x E*_r, E*_r) + F0 is
 * linear in its scale alpha (E* = alpha E*_r) and in F0, and its contact
 * point z0 follows by Gauss-Newton steps on the residuals projected off
 * those two columns (variable projection; Golub & Pereyra 1973, SIAM J.
 * Numer. Anal. 10:413), every point of the guess subsample held in
 * contact: the data end before detachment, and the edge's jump would make
 * minima of its own.  x runs over a grid on which the model's detachment
 * depth goes from 1e-6 to 1e3 depth spans, and the grid's lowest local
 * minima are refined by golden sections.  The same fit with the scale
 * held gives a curve's offsets at a given material. */
#include <math.h>

#include "fit.h"

#define SHAPE_GN_ITERS 20     /* Gauss-Newton steps in z0 at most */
#define SHAPE_HALVINGS 8      /* of a step that does not lower the cost */
#define SHAPE_Z0_NODES 12     /* grid of z0 where nothing better is known */
#define SHAPE_X_NODES 18      /* grid of w/E*: a node per factor 3 in the detachment depth */
#define SHAPE_GOLDEN 16       /* golden sections of a node's bracket */
#define SHAPE_REFINE 3        /* local minima of the grid refined */
/* The grid's range: the model's detachment depth |delta_det| from
 * SHAPE_DET_LO to SHAPE_DET_HI times the curve's depth span (below,
 * adhesion is lost in the curve; above, the data are a sliver of it). */
#define SHAPE_DET_LO 1e-6
#define SHAPE_DET_HI 1e3

/* One curve's fit at a material m on its guess subsample: the force
 * alpha P(z - z0; m) + F0, alpha free when scale_free (else 1), F0 free
 * when the curve's is, every point in contact. */
typedef struct {
    const fit_curve *c;
    lf_material m;
    int scale_free;
    double zpo;           /* the depth of the data's least force */
    double gmax;          /* bound on |d force/d z0| per point (detachment) */
    double alpha, F0;     /* at the last z0 */
} shape_fit;

static void
shape_init(shape_fit *s, const lf_fit *f, size_t j, const lf_material *m, int scale_free,
           double zpo)
{
    s->c = &f->c[j];
    s->m = *m;
    s->scale_free = scale_free;
    s->zpo = zpo;
    s->gmax = 1e3 * (s->c->fhi - s->c->flo) / s->c->L;
}

/* The residual sum of squares at contact point z0 with alpha and F0 at
 * their least-squares values (kept in s), and in *step the Gauss-Newton
 * step of z0 for the residuals projected off those (NAN when there is
 * none); HUGE_VAL when the model cannot be evaluated, alpha <= 0, a point
 * is out of contact, or an offset lies where the fit would call it run
 * away. */
static double
shape_at(lf_fit *f, shape_fit *s, double z0, double *step)
{
    const fit_curve *c = s->c;
    const guess_sub *sub = &c->sub;
    const int F0_free = c->iF0 >= 0;
    double *delta = f->ws.work, Saa = 0, Sab = 0, Sbb, Say = 0, Sby = 0;
    double Sgg = 0, Sga = 0, Sgb = 0, Sgr = 0, rss = 0, den, proj;
    lf_eval *e = f->ws.ev;
    size_t i, n = sub->n;

    *step = NAN;
    for (i = 0; i < n; i++)
        delta[i] = sub->z[i] - z0;
    if (lf_model_eval(c->model, &s->m, c->data.branch, n, delta, e, NULL) != LF_OK)
        return HUGE_VAL;
    for (i = 0; i < n; i++)
        if (!(e[i].a > 0.0))
            return HUGE_VAL;
    /* columns a = P (when scale_free) and b = 1 (when F0 is free) */
    for (i = 0; i < n; i++) {
        const double y = sub->F[i] - (s->scale_free ? 0.0 : e[i].P) - (F0_free ? 0.0 : c->F0);
        Saa += e[i].P * e[i].P;
        Sab += e[i].P;
        Say += e[i].P * y;
        Sby += y;
    }
    Sbb = (double) n;
    if (s->scale_free && F0_free) {
        const double det = Saa * Sbb - Sab * Sab;
        if (!(det > 0.0))
            return HUGE_VAL;
        s->alpha = (Sbb * Say - Sab * Sby) / det;
        s->F0 = (Saa * Sby - Sab * Say) / det;
    } else {
        s->alpha = s->scale_free ? (Saa > 0.0 ? Say / Saa : 0.0) : 1.0;
        s->F0 = F0_free ? Sby / Sbb : c->F0;
    }
    /* the bounds of verdict.c's "ran away": a sliver of a far curve can
     * fit a few points well, and is no start */
    if (!(s->alpha > 0.0) || !(fabs(s->F0 - 0.5 * (c->flo + c->fhi)) <= 1.5 * (c->fhi - c->flo))
        || !(fabs(z0 - 0.5 * (c->zlo + c->zhi)) <= 2.5 * (c->zhi - c->zlo)))
        return HUGE_VAL;
    for (i = 0; i < n; i++) {
        const double r = sub->F[i] - s->alpha * e[i].P - s->F0;
        const double g = lf_fmax(lf_fmin(s->alpha * e[i].dP_ddelta, s->gmax), -s->gmax);
        rss += r * r;
        Sgg += g * g;
        Sga += g * e[i].P;
        Sgb += g;
        Sgr += g * r;
    }
    if (c->iz0 < 0)
        return rss;
    /* |g|^2 less its part in the span of the free columns */
    if (s->scale_free && F0_free)
        proj = (Sbb * Sga * Sga - 2.0 * Sab * Sga * Sgb + Saa * Sgb * Sgb) / (Saa * Sbb - Sab * Sab);
    else if (s->scale_free)
        proj = Sga * Sga / Saa;
    else if (F0_free)
        proj = Sgb * Sgb / Sbb;
    else
        proj = 0.0;
    den = Sgg - proj;
    /* r(z0 + h) ~ r + h g: the step minimising |r + h g_perp|^2 */
    if (den > 1e-12 * Sgg)
        *step = -Sgr / den;
    return rss;
}

/* The fit at s's material: z0 from the best of its starts (the hint *z0
 * when a number, the contact point that puts the model's pull-off on the
 * data's least force, and with grid = 1 a grid from below the data to the
 * deepest point), then Gauss-Newton steps (each at most a quarter of the
 * depth span, halved while they do not lower the cost).  The cost, *z0
 * and s's alpha and F0 at the end; HUGE_VAL when no start fits. */
static double
shape_solve(lf_fit *f, shape_fit *s, double *z0, int grid)
{
    const fit_curve *c = s->c;
    const double L = c->L;
    double start[SHAPE_Z0_NODES + 3], best = HUGE_VAL, zb = NAN, h, cost;
    size_t ns = 0, i;
    int it, k;
    lf_pulloff po;

    if (c->iz0 < 0)
        return shape_at(f, s, c->z0, &h);
    if (isfinite(*z0))
        start[ns++] = *z0;
    if (lf_model_pulloff(c->model, &s->m, &po, NULL) == LF_OK)
        start[ns++] = s->zpo - (c->data.branch == LF_BRANCH_LOAD ? 0.0 : po.delta_po);
    if (grid || ns == 0)
        for (i = 0; i <= SHAPE_Z0_NODES; i++)
            start[ns++] = c->zlo - L + 2.0 * L * (double) i / SHAPE_Z0_NODES;
    for (i = 0; i < ns; i++)
        if ((cost = shape_at(f, s, start[i], &h)) < best) {
            best = cost;
            zb = start[i];
        }
    if (!(best < HUGE_VAL))
        return HUGE_VAL;
    cost = shape_at(f, s, zb, &h);
    for (it = 0; it < SHAPE_GN_ITERS && isfinite(h); it++) {
        double cnew = HUGE_VAL, hn = NAN, z = zb;
        h = lf_fmax(lf_fmin(h, 0.25 * L), -0.25 * L);
        for (k = 0; k < SHAPE_HALVINGS; k++, h *= 0.5) {
            z = zb + h;
            if ((cnew = shape_at(f, s, z, &hn)) < cost)
                break;
        }
        if (!(cnew < cost))
            break;
        zb = z;
        cost = cnew;
        if (fabs(h) < 1e-7 * L)
            break;
        h = hn;
    }
    *z0 = zb;
    /* s's alpha and F0 at zb (the last trial may have been elsewhere) */
    return shape_at(f, s, zb, &h);
}

/* The fit of curve j's shape at w/E* = e^t (E* = Eref, scale free), z0
 * from *z0 on. */
static double
shape_trial(lf_fit *f, size_t j, double Eref, double nu, double zpo, double t, double *z0,
            int grid, shape_fit *s)
{
    lf_material m;

    m.w = exp(t) * Eref;
    m.Estar = Eref;
    m.nu = nu;
    shape_init(s, f, j, &m, 1, zpo);
    return shape_solve(f, s, z0, grid);
}

/* The range of ln(w/E*) at E* = Eref over which the model's detachment
 * depth runs from SHAPE_DET_LO to SHAPE_DET_HI times curve j's depth span
 * (a power of w/E* for the half-space, found from two pull-offs).  0 when
 * the model gives no detachment. */
static int
shape_range(const lf_fit *f, size_t j, double Eref, double nu, double *t_lo, double *t_hi)
{
    const fit_curve *c = &f->c[j];
    const double ta = log(c->L), tb = ta - log(1e3);
    lf_material m = { exp(ta) * Eref, Eref, nu };
    lf_pulloff pa, pb;
    double slope;

    if (lf_model_pulloff(c->model, &m, &pa, NULL) != LF_OK)
        return 0;
    m.w = exp(tb) * Eref;
    if (lf_model_pulloff(c->model, &m, &pb, NULL) != LF_OK)
        return 0;
    slope = log(pa.delta_detach / pb.delta_detach) / (ta - tb);
    if (!(pa.delta_detach < 0.0 && pb.delta_detach < 0.0 && slope > 0.0 && isfinite(slope)))
        return 0;
    *t_lo = ta + log(SHAPE_DET_LO * c->L / -pa.delta_detach) / slope;
    *t_hi = ta + log(SHAPE_DET_HI * c->L / -pa.delta_detach) / slope;
    return 1;
}

/* Golden sections of [a, b] in ln(w/E*) for curve j: the best trial
 * (cost, *tb, *zb; each trial's z0 from the best so far, and the
 * pull-off's), starting from z0 = *zb. */
static double
shape_golden(lf_fit *f, size_t j, double Eref, double nu, double zpo, double a, double b,
             double *tb, double *zb)
{
    const double gr = 0.5 * (sqrt(5.0) - 1.0);
    double x[2], fx[2], zx[2], best = HUGE_VAL;
    shape_fit s;
    int i, q;

    x[0] = b - gr * (b - a);
    x[1] = a + gr * (b - a);
    for (q = 0; q < 2; q++) {
        zx[q] = *zb;
        fx[q] = shape_trial(f, j, Eref, nu, zpo, x[q], &zx[q], 0, &s);
    }
    for (i = 0;; i++) {
        q = fx[0] < fx[1] ? 0 : 1;     /* the better inner point stays */
        if (fx[q] < best) {
            best = fx[q];
            *tb = x[q];
            *zb = zx[q];
        }
        if (i == SHAPE_GOLDEN)
            return best;
        if (q == 0) {
            b = x[1];
            x[1] = x[0]; fx[1] = fx[0]; zx[1] = zx[0];
            x[0] = b - gr * (b - a);
        } else {
            a = x[0];
            x[0] = x[1]; fx[0] = fx[1]; zx[0] = zx[1];
            x[1] = a + gr * (b - a);
        }
        zx[1 - q] = *zb;
        fx[1 - q] = shape_trial(f, j, Eref, nu, zpo, x[1 - q], &zx[1 - q], 0, &s);
    }
}

/* Without a baseline a curve of no adhesion (w -> 0) with its own z0 and
 * F0 can come within ~1e-4 of the data's sum of squares, and the true
 * minimum is a narrow valley in w/E*: so each of the grid's SHAPE_REFINE
 * lowest local minima is refined, not only the lowest node. */
double
lf_fit_shape_material(lf_fit *f, size_t j, double nu, double zpo, lf_material *out)
{
    const double Eref = f->mat.Estar > 0 && isfinite(f->mat.Estar) ? f->mat.Estar : 1e6;
    double cost[SHAPE_X_NODES + 1], zn[SHAPE_X_NODES + 1];
    double best = HUGE_VAL, tb = NAN, zb = NAN, z0 = NAN, t_lo, t_hi, dt;
    int done[SHAPE_X_NODES + 1], i, r;
    shape_fit s;

    if (!shape_range(f, j, Eref, nu, &t_lo, &t_hi))
        return HUGE_VAL;
    dt = (t_hi - t_lo) / SHAPE_X_NODES;
    for (i = 0; i <= SHAPE_X_NODES; i++) {
        cost[i] = shape_trial(f, j, Eref, nu, zpo, t_lo + dt * i, &z0, 1, &s);
        zn[i] = z0;
    }
    for (i = 0; i <= SHAPE_X_NODES; i++)    /* the local minima */
        done[i] = !((i == 0 || cost[i] <= cost[i - 1])
                    && (i == SHAPE_X_NODES || cost[i] <= cost[i + 1]));
    for (r = 0; r < SHAPE_REFINE; r++) {
        double low = HUGE_VAL, t = NAN, z;
        int m = -1;
        for (i = 0; i <= SHAPE_X_NODES; i++)
            if (!done[i] && cost[i] < low) {
                low = cost[i];
                m = i;
            }
        if (m < 0)
            break;
        done[m] = 1;
        z = zn[m];
        low = lf_fmin(low, shape_golden(f, j, Eref, nu, zpo, t_lo + dt * (m - 1), t_lo + dt * (m + 1),
                                        &t, &z));
        if (low < best) {
            best = low;
            tb = isfinite(t) ? t : t_lo + dt * m;
            zb = isfinite(t) ? z : zn[m];
        }
    }
    if (!isfinite(tb))
        return HUGE_VAL;
    best = shape_trial(f, j, Eref, nu, zpo, tb, &zb, 0, &s);
    out->w = s.alpha * s.m.w;
    out->Estar = s.alpha * s.m.Estar;
    out->nu = nu;
    return best < HUGE_VAL && isfinite(out->w) && out->Estar > 0 ? best : HUGE_VAL;
}

double
lf_fit_shape_offsets(lf_fit *f, size_t j, const lf_material *m, double zpo, double *z0,
                     double *F0)
{
    shape_fit s;
    double cost;

    shape_init(&s, f, j, m, 0, zpo);
    *z0 = NAN;
    cost = shape_solve(f, &s, z0, 1);
    *F0 = s.F0;
    return cost;
}
