/* guess_model.c: the automatic start of a model with no thickness (the
 * half-space), and a candidate start of the exact model (which a thick
 * layer makes a half-space), made with that model's own force law, so that nothing the
 * model ignores (the layer thickness b) moves it.
 *
 * The thin-layer profile of guess.c finds, per curve, what does not depend
 * on the model's stiffness scale: the force offset F0 and where contact
 * ends.  From the data, sorted by depth, three features follow:
 *   the pull-off point  (z_po, F_min): the least force (unloading), or the
 *                       jump into contact (loading);
 *   the deepest point   (z_max, F_max);
 * and the model in use gives, for a material, its pull-off force P_po and
 * indentation delta_po (lf_model_pulloff; P_jump at delta = 0 for loading)
 * and its force at any indentation.  The material solves
 *   P_po(E*, w)                       = F_min - F0
 *   P(z_max - z_po + delta_po; E*, w) = F_max - F0.
 * In linear elasticity with an adhesive edge every force is E* times a
 * function of the geometry and w/E* (and nu), and every length a function
 * of w/E*: so at a reference E*_r (the thin profile's) and w = x E*_r the
 * pull-off fixes the scale, E* = E*_r (F_min - F0)/P_po, and the deepest
 * force scaled by it must be the data's: one search in ln x (monotone), a
 * pull-off and a force per trial.  With no adhesion
 * seen (|F_min - F0| below three noise sd) w is set to the value whose
 * pull-off is one noise sd and the contact point is the thin profile's.
 * Curves are combined by geometric means, then every curve's contact point
 * is placed so that its pull-off lands on the data's.
 *
 * A half-space retract curve whose data end before contact does (no flat
 * baseline: cut short of its detachment, and for k > 2 often of its
 * pull-off too, since there both lie well below delta = 0) shows neither
 * F0 nor, perhaps, a pull-off.  There the start from its shape alone
 * (guess_shape.c) competes, for the material and for the offsets at a
 * given one, and wins where it fits the guess subsample decisively better
 * (SHAPE_WINS). */
#include <math.h>
#include <string.h>

#include "fit.h"

/* The searches in ln x and ln w (brackets of about 50): Brent's method on
 * the logarithm of the matched force, nearly linear (a power law), down to
 * ROOT_TOL (1e-5 of w and E*: a start needs no more, and the fits from it
 * are the same); ROOT_MAXIT evaluations at most (bisection alone would
 * need 32).  E* stays within [E_LOW, E_HIGH]. */
#define ROOT_TOL 1e-5
#define ROOT_MAXIT 60
#define E_LOW 1e-6
#define E_HIGH 1e15
/* the value of a trial the model cannot evaluate or whose force has the
 * wrong sign: its side of the root, at about the bracket's scale */
#define ROOT_SIDE 50.0

typedef double (*root_fn)(double t, void *ctx);

/* A zero of fn in [a, b], where fa = fn(a) and fb = fn(b) differ in sign:
 * Brent's method (inverse quadratic or secant steps, bisection where
 * those would not shrink the bracket fast enough), to within tol. */
static double
brent_zero(root_fn fn, void *ctx, double a, double b, double fa, double fb, double tol)
{
    double c = a, fc = fa, d = b - a, e = d;
    int it;

    for (it = 0; it < ROOT_MAXIT; it++) {
        double tol1, xm;
        if ((fb > 0) == (fc > 0)) {         /* keep the root between b and c */
            c = a;
            fc = fa;
            d = e = b - a;
        }
        if (fabs(fc) < fabs(fb)) {          /* b the best so far */
            a = b; b = c; c = a;
            fa = fb; fb = fc; fc = fa;
        }
        tol1 = 2.0 * 2.2e-16 * fabs(b) + 0.5 * tol;
        xm = 0.5 * (c - b);
        if (fabs(xm) <= tol1 || fb == 0.0)
            return b;
        if (fabs(e) >= tol1 && fabs(fa) > fabs(fb)) {
            double p, q, r, sr = fb / fa;
            if (a == c) {                   /* secant */
                p = 2.0 * xm * sr;
                q = 1.0 - sr;
            } else {                        /* inverse quadratic */
                q = fa / fc;
                r = fb / fc;
                p = sr * (2.0 * xm * q * (q - r) - (b - a) * (r - 1.0));
                q = (q - 1.0) * (r - 1.0) * (sr - 1.0);
            }
            if (p > 0)
                q = -q;
            else
                p = -p;
            if (2.0 * p < lf_fmin(3.0 * xm * q - fabs(tol1 * q), fabs(e * q))) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += fabs(d) > tol1 ? d : (xm > 0 ? tol1 : -tol1);
        fb = fn(b, ctx);
    }
    return b;
}

/* The root of fn in [lo, hi], fn > 0 meaning "raise t": an end when fn
 * does not change sign there (as bisection would end). */
static double
root_in(root_fn fn, void *ctx, double lo, double hi)
{
    double flo = fn(lo, ctx), fhi;

    if (!(flo > 0))
        return lo;
    fhi = fn(hi, ctx);
    if (fhi > 0)
        return hi;
    return brent_zero(fn, ctx, lo, hi, flo, fhi, ROOT_TOL);
}

/* 1 when every curve's model has no thickness (uses no b). */
int
lf_fit_guess_by_model(const lf_fit *f)
{
    size_t j;
    for (j = 0; j < f->ncurves; j++)
        if (lf_model_get_type(f->c[j].model) != &lf_model_halfspace)
            return 0;
    return f->ncurves > 0;
}

/* Pull-off force (or the jump force when loading) and its indentation. */
static int
pull(const fit_curve *c, const lf_material *m, double *P, double *delta)
{
    lf_pulloff po;
    if (lf_model_pulloff(c->model, m, &po, NULL) != LF_OK)
        return 0;
    if (c->data.branch == LF_BRANCH_LOAD) {
        *P = po.P_jump;
        *delta = 0.0;
    } else {
        *P = po.P_po;
        *delta = po.delta_po;
    }
    return isfinite(*P) && isfinite(*delta);
}

typedef struct {
    const fit_curve *c;
    double Estar, nu, target;
} w_search;

/* ln(target / P_po) at w = e^t: > 0 while the pull-off is too weak. */
static double
w_gap(double t, void *ctx)
{
    const w_search *q = ctx;
    lf_material m = { exp(t), q->Estar, q->nu };
    double P, d;

    if (!pull(q->c, &m, &P, &d))
        return -ROOT_SIDE;          /* beyond the model: as too much adhesion */
    if (!(P < 0))
        return ROOT_SIDE;           /* no pull-off force yet: too little */
    return log(q->target / P);
}

/* The w (at E*) whose pull-off force is target (< 0). */
static double
w_for_pulloff(const fit_curve *c, double Estar, double nu, double target)
{
    w_search q;
    q.c = c;
    q.Estar = Estar;
    q.nu = nu;
    q.target = target;
    return exp(root_in(w_gap, &q, log(1e-300 + 1e-18 * Estar * lf_probe_length(&c->data.probe)),
                       log(1e6 * Estar * lf_probe_length(&c->data.probe))));
}

/* The model's force at indentation delta, or NaN. */
static double
force_at(const fit_curve *c, const lf_material *m, double delta)
{
    lf_eval e;
    if (lf_model_eval(c->model, m, c->data.branch, 1, &delta, &e, NULL) != LF_OK)
        return NAN;
    return e.P;
}

/* The features of curve j's data. */
static void
features(const lf_fit *f, size_t j, double F0, double *zpo, double *Fmin, double *zmax,
         double *Fmax)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    size_t i, n = c->data.n, ntop = n / 50 + 1;
    double s = 0.0;

    *Fmin = HUGE_VAL;
    *zpo = NAN;
    for (i = 0; i < n; i++)
        if (c->data.force[i] < *Fmin) {
            *Fmin = c->data.force[i];
            *zpo = c->data.depth[i];
        }
    /* the deepest points, averaged against the noise */
    for (i = n - ntop; i < n; i++)
        s += c->data.force[ord[i]];
    *Fmax = s / (double) ntop;
    *zmax = c->data.depth[ord[n - ntop / 2 - 1]];
    (void) F0;
}

/* The number of baseline points of curve j (the shallowest tenth, at
 * least 5) when they all lie shallower than the least force, so past
 * detachment; else 0. */
static size_t
baseline_points(const lf_fit *f, size_t j)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    size_t n = c->data.n, m = n / 10 > 5 ? n / 10 : 5;
    double zpo, Fmin, zmax, Fmax;

    features(f, j, 0.0, &zpo, &Fmin, &zmax, &Fmax);
    return m < n && c->data.depth[ord[m - 1]] < zpo ? m : 0;
}

/* The force offset of curve j: where the shallowest tenth of the points
 * (at least 5) all lie shallower than the least force, they are the
 * baseline past detachment and their median is F0; else the thin profile's
 * F0 (guess.c), kept within the data's forces. */
static double
offset_F0(const lf_fit *f, size_t j)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    size_t i, m;
    double zpo, Fmin, zmax, Fmax, F0;

    if (c->iF0 < 0)
        return c->F0;
    features(f, j, 0.0, &zpo, &Fmin, &zmax, &Fmax);
    if ((m = baseline_points(f, j)) > 0) {
        for (i = 0; i < m; i++)
            f->ws.work[i] = c->data.force[ord[i]];
        return lf_fit_median(f->ws.work, m);
    }
    F0 = c->guess.F0;
    return lf_fmin(lf_fmax(F0, Fmin), Fmax);
}

/* The shape's start replaces the features' only where it fits the
 * subsample decisively better (its sum of squares below this fraction of
 * theirs): the features' start, where it is right, leads the fit across
 * the contact edge's jumps that a start with every point in contact
 * would have to cross (real curves with drifting baselines fit either
 * start about as badly). */
#define SHAPE_WINS 0.5

/* The features' offsets of curve j at material m (header): F0 from the
 * baseline (or the thin profile), z0 placing the model's pull-off on the
 * data's (or the thin profile's). */
static void
features_offsets(lf_fit *f, size_t j, const lf_material *m, double *z0, double *F0)
{
    const fit_curve *c = &f->c[j];
    double zpo, Fmin, zmax, Fmax, P, d;

    *F0 = offset_F0(f, j);
    features(f, j, *F0, &zpo, &Fmin, &zmax, &Fmax);
    if (c->iz0 < 0)
        *z0 = c->z0;
    else if (Fmin - *F0 < -3.0 * c->sigma && pull(c, m, &P, &d))
        *z0 = zpo - d;
    else
        *z0 = c->guess.z0;
}

/* Add to *ss the squared residuals of curve j's guess subsample (guess.c:
 * up to GUESS_NSUB points, in order of depth) at material m, offsets z0,
 * F0 and slope, in units of scale; 0 when the model cannot be evaluated. */
static int
subsample_add(lf_fit *f, size_t j, const lf_material *m, double z0, double F0, double slope,
              double scale, double *ss)
{
    const fit_curve *c = &f->c[j];
    const guess_sub *s = &c->sub;
    double *delta = f->ws.work;
    lf_eval *e = f->ws.ev;
    size_t i;

    for (i = 0; i < s->n; i++)
        delta[i] = s->z[i] - z0;
    if (lf_model_eval(c->model, m, c->data.branch, s->n, delta, e, NULL) != LF_OK)
        return 0;
    for (i = 0; i < s->n; i++) {
        const double r = (e[i].P + F0 + slope * delta[i] - s->F[i]) / scale;
        *ss += r * r;
    }
    return 1;
}

/* The residual sum of squares of curve j's subsample at material m and
 * offsets z0, F0; HUGE_VAL when the model cannot be evaluated. */
static double
subsample_rss(lf_fit *f, size_t j, const lf_material *m, double z0, double F0)
{
    double ss = 0.0;
    return subsample_add(f, j, m, z0, F0, 0.0, 1.0, &ss) && isfinite(ss) ? ss : HUGE_VAL;
}

/* 1 when curve j shows a flat baseline: the points of baseline_points,
 * the shallower half of them (the tenth may reach into contact), have no
 * trend with depth beyond FLAT_T standard errors of a fitted slope, as
 * the rise of a curve that ends before detachment would. */
#define FLAT_T 3.0
static int
flat_baseline(const lf_fit *f, size_t j)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row, m = (baseline_points(f, j) + 1) / 2;
    double mz = 0.0, mF = 0.0, szz = 0.0, szF = 0.0;
    size_t i;

    if (m < 3)
        return 0;
    for (i = 0; i < m; i++) {
        mz += c->data.depth[ord[i]];
        mF += c->data.force[ord[i]];
    }
    mz /= (double) m;
    mF /= (double) m;
    for (i = 0; i < m; i++) {
        const double dz = c->data.depth[ord[i]] - mz;
        szz += dz * dz;
        szF += dz * (c->data.force[ord[i]] - mF);
    }
    /* the slope szF/szz against its standard error sigma/sqrt(szz) */
    return szz > 0.0 && fabs(szF) <= FLAT_T * c->sigma * sqrt(szz);
}

/* 1 when curve j's start may come from its shape: a half-space curve on
 * unloading without a flat baseline (loading curves start with their
 * approach, a baseline to the contact point). */
static int
shape_may_start(const lf_fit *f, size_t j)
{
    return lf_model_get_type(f->c[j].model) == &lf_model_halfspace
           && f->c[j].data.branch == LF_BRANCH_UNLOAD && !flat_baseline(f, j);
}

/* The offsets of curve j at material m: the features' where
 * !shape_may_start (returns 0), else the better fit on the subsample of
 * the features' and the shape's with every point in contact (returns its
 * residual sum of squares; HUGE_VAL when neither fits, the features'
 * offsets in *z0, *F0 then). */
static double
offsets_at(lf_fit *f, size_t j, const lf_material *m, double *z0, double *F0)
{
    double zs, Fs, cf, cs, zpo, Fmin, zmax, Fmax;

    features_offsets(f, j, m, z0, F0);
    if (!shape_may_start(f, j))
        return 0.0;
    cf = subsample_rss(f, j, m, *z0, *F0);
    features(f, j, 0.0, &zpo, &Fmin, &zmax, &Fmax);
    cs = lf_fit_shape_offsets(f, j, m, zpo, &zs, &Fs);
    if (cs < SHAPE_WINS * cf) {
        *z0 = zs;
        *F0 = Fs;
        return cs;
    }
    return cf;
}

typedef struct {
    const fit_curve *c;
    double Eref, nu, target;   /* the pull-off force to match */
    int adhesive;
    double rise, reach;    /* the force to match at the deepest point, and
                              its depth past the pull-off (or contact) */
} x_search;

/* The search in x = w/E* (header): at E* = Eref and w = e^t, the E* whose
 * pull-off is the data's is Eref target/P_po; the force at the deepest
 * point, scaled by the same factor, against the data's: ln(that / rise),
 * > 0 while it is too large (too stiff: raise w/E*). */
static double
x_gap(double t, void *ctx)
{
    const x_search *q = ctx;
    lf_material m = { exp(t), q->Eref, q->nu };
    double P, d, Pmax;

    if (!pull(q->c, &m, &P, &d))
        return -ROOT_SIDE;          /* beyond the model: as too much adhesion */
    if (!(P < 0))
        return ROOT_SIDE;           /* no pull-off force yet: too little */
    Pmax = force_at(q->c, &m, q->reach + (q->adhesive ? d : 0.0));
    if (!isfinite(Pmax))
        return ROOT_SIDE;
    if (!(Pmax > 0))
        return -ROOT_SIDE;
    return log(Pmax * (q->target / P) / q->rise);
}

/* The material of one curve from its features (header); 0 when the data
 * give no contact. */
static int
features_material(lf_fit *f, size_t j, double nu, lf_material *out)
{
    const fit_curve *c = &f->c[j];
    double F0 = offset_F0(f, j);
    double zpo, Fmin, zmax, Fmax, Ppo, rise, z0ref, R = lf_probe_length(&c->data.probe), t, P, d;
    int adhesive;
    x_search q;
    lf_material m;

    features(f, j, F0, &zpo, &Fmin, &zmax, &Fmax);
    Ppo = Fmin - F0;
    adhesive = Ppo < -3.0 * c->sigma && zmax > zpo;
    rise = Fmax - F0;
    if (!(rise > 3.0 * c->sigma))
        return 0;
    if (!adhesive) {
        /* contact from the thin profile's contact point, a pull-off of one
         * noise sd */
        z0ref = c->iz0 >= 0 ? c->guess.z0 : c->z0;
        if (!(zmax > z0ref))
            return 0;
    } else {
        z0ref = NAN;
    }
    q.c = c;
    q.Eref = f->mat.Estar > 0 && isfinite(f->mat.Estar) ? f->mat.Estar : 1e6;
    q.nu = nu;
    q.target = adhesive ? Ppo : -c->sigma;
    q.adhesive = adhesive;
    q.rise = rise;
    q.reach = adhesive ? zmax - zpo : zmax - z0ref;
    t = root_in(x_gap, &q, log(1e-300 + 1e-18 * q.Eref * R), log(1e6 * q.Eref * R));
    m.w = exp(t);
    m.Estar = q.Eref;
    m.nu = nu;
    if (!pull(c, &m, &P, &d) || !(P < 0))
        return 0;
    /* scaled to the E* whose pull-off is the data's, within the range the
     * searches in E* took */
    out->Estar = q.Eref * (q.target / P);
    out->w = m.w * (q.target / P);
    if (!(out->Estar >= E_LOW && out->Estar <= E_HIGH)) {
        out->Estar = lf_fmin(lf_fmax(out->Estar, E_LOW), E_HIGH);
        out->w = w_for_pulloff(c, out->Estar, nu, q.target);
    }
    out->nu = nu;
    return isfinite(out->Estar) && isfinite(out->w);
}

/* The material of one curve; 0 when none is found.  Where the shape may
 * start (shape_may_start), the better fit on the subsample of the
 * features' (at the offsets of offsets_at) and the shape's. */
static int
curve_material(lf_fit *f, size_t j, double nu, lf_material *out)
{
    lf_material ms;
    double cf = HUGE_VAL, cs, z0, F0, zpo, Fmin, zmax, Fmax;
    int have = features_material(f, j, nu, out);

    if (!shape_may_start(f, j))
        return have;
    if (have)
        cf = offsets_at(f, j, out, &z0, &F0);
    features(f, j, 0.0, &zpo, &Fmin, &zmax, &Fmax);
    cs = lf_fit_shape_material(f, j, nu, zpo, &ms);
    if (cs < SHAPE_WINS * cf) {
        *out = ms;
        return 1;
    }
    return have;
}

void
lf_fit_guess_model_offsets(lf_fit *f)
{
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        double z0, F0;
        c->slope = 0.0;
        (void) offsets_at(f, j, &f->mat, &z0, &F0);
        if (c->iF0 >= 0)
            c->F0 = F0;
        if (c->iz0 >= 0)
            c->z0 = z0;
    }
    lf_fit_set_origin(f);
}

int
lf_fit_guess_model(lf_fit *f)
{
    size_t j, n = 0;
    double lnE = 0.0, lnw = 0.0, nu = isfinite(f->mat.nu) ? f->mat.nu : 0.3;

    for (j = 0; j < f->ncurves; j++) {
        lf_material m;
        if (!curve_material(f, j, nu, &m))
            continue;
        lnE += log(m.Estar);
        lnw += log(m.w);
        n++;
    }
    if (n == 0)
        return 0;
    if (f->imat[FIT_E] >= 0)
        f->mat.Estar = exp(lnE / (double) n);
    if (f->imat[FIT_W] >= 0)
        f->mat.w = exp(lnw / (double) n);
    return 1;
}

/* Half the sum of squared residuals, in units of each curve's noise, of
 * the curves' guess subsamples (guess.c: up to GUESS_NSUB points each, in
 * order of depth) at the origin's material and offsets; HUGE_VAL when the
 * model cannot be evaluated.  Enough to tell a good start from a bad one;
 * with the exact model the two cost about one full evaluation together
 * (sparse points start its inversion less well; full costs took two). */
static double
subsample_cost(lf_fit *f)
{
    double ss = 0.0;
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        if (!subsample_add(f, j, &f->mat, c->z0, c->F0, c->slope, c->sigma, &ss))
            return HUGE_VAL;
    }
    return isfinite(ss) ? 0.5 * ss : HUGE_VAL;
}

void
lf_fit_guess_compare_model(lf_fit *f)
{
    lf_material thin = f->mat;
    double a, b;
    size_t j;
    int any = 0;

    f->start_by_model = 0;
    for (j = 0; j < f->ncurves; j++) {
        const lf_model_type *t = lf_model_get_type(f->c[j].model);
        if (t == &lf_model_thin)
            return;
        any |= t != &lf_model_halfspace;
    }
    if (!any)
        return;
    /* the thin profile's start, at its own offsets, against the model's own
     * (evaluations into f->ws.ev: the cache keyed by x is dropped) */
    lf_fit_invalidate(f);
    a = subsample_cost(f);
    if (!lf_fit_guess_model(f)) {
        f->mat = thin;
        return;
    }
    lf_fit_guess_model_offsets(f);
    b = subsample_cost(f);
    if (b < a)
        f->start_by_model = 1;
    else
        f->mat = thin;
    lf_fit_invalidate(f);
}
