/* guess.c: a deterministic initial guess that needs nothing from the user.
 *
 * The guess uses the thin-layer closed form of the seed paper (Eq. 10, 22)
 * whatever model is then fitted.  With M = Z E*, K = pi/b k^((k+2)/k)/(k+2)
 * R^(2(k-1)/k) and d1 = z - z_d (z_d = z0 - c is where contact ends on
 * unloading):
 *     F = M K d1^(2/k) (d1 - (k+2)/k c) + F0
 *       = alpha K d1^((k+2)/k) + beta K d1^(2/k) + F0,
 * linear in (alpha, beta, F0) for a given z_d, with M = alpha and
 * c = -beta k / ((k+2) alpha).  So each curve is profiled over the single
 * nonlinear parameter z_d (variable projection: the linear parameters are
 * solved exactly at each trial), on a grid and then by Brent's method.
 * When z0 is held, the profile runs over c instead; when c is held (second
 * stage) over z0, with M and F0 linear.
 *
 * Curves are treated one at a time and combined by symmetric means (E*
 * from frictionless curves, Z and so nu from bonded over frictionless, w as
 * the geometric mean over the curves that can see it), then every curve's
 * z0 and F0 are profiled again at the combined material.  Nothing depends
 * on the order of the curves or on an earlier fit.  The result is polished
 * by the full least-squares fit (driver.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

/* Brent's search after the grid: at most GUESS_BRENT trials, down to
 * GUESS_XTOL of the bracket between the best node's neighbours */
#define GUESS_BRENT 12
#define GUESS_XTOL 2e-3
#define GUESS_TIE_REL 1e-12
/* the start's w: candidates of their own from at most this many curves */
#define GUESS_OWN_W 6

/* ---- one curve --------------------------------------------------------- */

typedef enum {
    PROFILE_ZD,     /* search z_d; alpha, beta (, F0) linear */
    PROFILE_C,      /* z0 held; search c; M (, F0) linear */
    PROFILE_Z0      /* c held; search z0; M (, F0) linear */
} profile_kind;

typedef struct {
    const double *z, *F;   /* subsample */
    size_t n;
    double k, K;
    double R_sphere;       /* a sphere's R (its thin-layer law), else 0 */
    lf_branch branch;
    int F0_free;
    double F0_held;
    double z0_held;        /* PROFILE_C */
    double c_held;         /* PROFILE_Z0 */
    profile_kind kind;
    double yy, sy;         /* sums of y^2 and y, y = F - (F0 held or 0) */
    /* solution at the last trial */
    double M, c, z0, F0;
} profile;

/* Solve the 1-3 column least-squares problem sum (y - X b)^2 by normal
 * equations with unit-diagonal scaling and Cholesky; 0 when singular. */
static int
solve_small(size_t p, double A[3][3], double *rhs, double *sol)
{
    double d[3], L[3][3] = { { 0 } };
    size_t i, j, k;

    for (i = 0; i < p; i++) {
        if (!(A[i][i] > 0))
            return 0;
        d[i] = 1.0 / sqrt(A[i][i]);
    }
    for (i = 0; i < p; i++)
        for (j = 0; j <= i; j++) {
            double s = A[i][j] * d[i] * d[j];
            for (k = 0; k < j; k++)
                s -= L[i][k] * L[j][k];
            if (i == j) {
                if (!(s > 1e-13))
                    return 0;
                L[i][i] = sqrt(s);
            } else {
                L[i][j] = s / L[j][j];
            }
        }
    for (i = 0; i < p; i++) {          /* L y = D rhs */
        double s = rhs[i] * d[i];
        for (k = 0; k < i; k++)
            s -= L[i][k] * sol[k];
        sol[i] = s / L[i][i];
    }
    for (i = p; i-- > 0;) {            /* L^T v = y, b = D v */
        double s = sol[i];
        for (k = i + 1; k < p; k++)
            s -= L[k][i] * sol[k];
        sol[i] = s / L[i][i];
    }
    for (i = 0; i < p; i++)
        sol[i] *= d[i];
    return 1;
}

/* The sums of the normal equations of one trial: the columns x0 = phi0,
 * x1 = phi1 (PROFILE_ZD only) and the constant of a free F0, over the
 * points in contact (phi is zero elsewhere, and the constant column's own
 * sums n, y, y^2 are the profile's, taken once). */
typedef struct {
    double a00, a10, a20, a11, a21, r0, r1;
} trial_sums;

/* Least squares on the basis phi0 (, phi1 when ncol = 2) plus a constant
 * when F0 is free, from the sums t of the trial.  Returns the residual sum
 * of squares (HUGE_VAL when singular) and the coefficients in b (F0
 * last). */
static double
linear_fit(const profile *p, size_t ncol, const trial_sums *t, double *b)
{
    double A[3][3] = { { 0 } }, rhs[3] = { 0 };
    size_t r, m = ncol + (size_t) p->F0_free;
    double fit = 0.0;

    A[0][0] = t->a00;
    rhs[0] = t->r0;
    if (ncol > 1) {
        A[1][0] = A[0][1] = t->a10;
        A[1][1] = t->a11;
        rhs[1] = t->r1;
        if (p->F0_free) {
            A[2][0] = A[0][2] = t->a20;
            A[2][1] = A[1][2] = t->a21;
            A[2][2] = (double) p->n;
            rhs[2] = p->sy;
        }
    } else if (p->F0_free) {
        A[1][0] = A[0][1] = t->a20;
        A[1][1] = (double) p->n;
        rhs[1] = p->sy;
    }
    if (!solve_small(m, A, rhs, b))
        return HUGE_VAL;
    /* |y - X b|^2 = y^T y - b^T X^T y at the least-squares b: one pass */
    for (r = 0; r < m; r++)
        fit += b[r] * rhs[r];
    return lf_fmax(p->yy - fit, 0.0);
}

/* x^(2/k) for the guess's basis, x > 0: for k = 3 from the bits of x and
 * two Newton steps (relative error below 2e-5: a start needs no more, and
 * the steps are most of a trial's time), else lf_pow_2k. */
static inline double
guess_pow_2k(double x, double k)
{
    if (k == 3.0 && x >= 1e-300 && x <= 1e300)
        return x * lf_inv_cbrt_step(x, lf_inv_cbrt_step(x, lf_inv_cbrt_seed(x)));
    return lf_pow_2k(x, k);
}

/* The sums of one trial over the points i0..n-1 of the subsample, all in
 * contact (d1 = z - zd > 0 there).  KC is 2, 3 (d1 within the range of
 * the fast cube root at both ends, so at every point: d1 grows with z), 0
 * (any k, by guess_pow_2k) or -1, a sphere of radius R_sphere, whose thin
 * layer's law (model_thin.c) has the basis d1^2 - d1^3/(3R) and
 * d1 - d1^2/(2R) in place of d1^2 and d1 (past the equator, d1 > R, the
 * flat punch's R (d1 - R/3) and R/2); zd_kind the two-column basis.  Constants in
 * each instance, so the loop over the points tests neither.  Returns the
 * count of points with a positive basis. */
LF_KERNEL size_t
trial_loop(const profile *p, size_t i0, double zd, double c, double held, int KC,
           int zd_kind, trial_sums *t)
{
    const double k = p->k, kk = (k + 2.0) / k, K = p->K;
    /* the sums in registers: a struct whose address is taken lives in
     * memory, and every addition would wait for the last store */
    double a00 = 0, a10 = 0, a20 = 0, a11 = 0, a21 = 0, r0 = 0, r1 = 0;
    double root[GUESS_NSUB], xr[GUESS_NSUB];
    size_t i, ncontact = 0;

    if (KC == 3 && i0 < p->n)
        /* the roots first: the seeds from the bits, then the two Newton
         * steps, a step over all points before the next (none waits on
         * the last), four points at a time where the processor allows
         * (z - zd is z + (-zd) to the bit, and within the fast root's
         * range here: xr is z - zd) */
        lf_thin_roots(p->z + i0, -zd, p->n - i0, 2, xr + i0, root + i0);
    for (i = i0; i < p->n; i++) {
        const double d1 = p->z[i] - zd;
        double g, x0, y;
        if (KC == -1) {
            const double R = p->R_sphere;
            const double y0 = d1 > R ? R * (d1 - R / 3.0) : d1 * d1 * (1.0 - d1 / (3.0 * R));
            const double y1 = d1 > R ? 0.5 * R : d1 * (1.0 - 0.5 * d1 / R);
            if (!(d1 > 0))
                continue;
            ncontact++;
            y = p->F[i] - held;
            if (zd_kind) {
                const double x1 = K * y1;
                x0 = K * y0;
                a11 += x1 * x1;
                a21 += x1;
                r1 += x1 * y;
                a10 += x1 * x0;
            } else {
                x0 = K * (y0 - kk * c * y1);
            }
            a00 += x0 * x0;
            a20 += x0;
            r0 += x0 * y;
            continue;
        }
        if (KC == 2)
            g = d1;
        else if (KC == 3)
            g = d1 * root[i];
        else
            g = guess_pow_2k(d1, k);
        /* KC = 2, 3: g > 0 at every point, as d1 is (and within the cube
         * root's range), so the test and the count are left out */
        if (KC != 2 && KC != 3) {
            if (!(g > 0))
                continue;
            ncontact++;
        }
        y = p->F[i] - held;
        if (zd_kind) {
            const double x1 = K * g;
            x0 = K * g * d1;
            a11 += x1 * x1;
            a21 += x1;
            r1 += x1 * y;
            a10 += x1 * x0;
        } else {
            x0 = K * g * (d1 - kk * c);
        }
        a00 += x0 * x0;
        a20 += x0;
        r0 += x0 * y;
    }
    t->a00 = a00;
    t->a10 = a10;
    t->a20 = a20;
    t->a11 = a11;
    t->a21 = a21;
    t->r0 = r0;
    t->r1 = r1;
    return KC == 2 || KC == 3 ? (i0 < p->n ? p->n - i0 : 0) : ncontact;
}

/* The residual sum of squares at trial value s of the profiled parameter;
 * fills p->M, c, z0, F0.  The points in contact are those deeper than the
 * contact edge, the subsample's last ones (it is in order of depth): one
 * pass over them builds the basis at each point and adds it into the sums
 * of the normal equations. */
static double
profile_cost(profile *p, double s)
{
    const double k = p->k, kk = (k + 2.0) / k;
    const double held = p->F0_free ? 0.0 : p->F0_held;
    const int zd_kind = p->kind == PROFILE_ZD;
    const int from_z0 = p->branch == LF_BRANCH_LOAD && !zd_kind;
    trial_sums t;
    size_t lo = 0, hi = p->n, ncontact;
    int kc = 0;
    double b[3], rss;
    double zd, c, z0, zc;   /* zc: contact for z > zc (>= for loading) */

    switch (p->kind) {
    case PROFILE_ZD: zd = s; c = 0.0; z0 = s; zc = s; break;
    case PROFILE_C:  c = lf_fmax(s, 0.0); z0 = p->z0_held; zd = z0 - c; break;
    default:         c = p->c_held; z0 = s; zd = z0 - c; break;
    }
    zc = from_z0 ? z0 : zd;
    /* the first point in contact with d1 > 0 (none when zd is NaN) */
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        const double z = p->z[mid];
        if ((from_z0 ? z >= zc : z > zc) && z - zd > 0)
            hi = mid;
        else
            lo = mid + 1;
    }
    if (lo < p->n) {
        const double first = p->z[lo] - zd, last = p->z[p->n - 1] - zd;
        if (p->R_sphere > 0)
            kc = -1;
        else if (k == 2.0)
            kc = 2;
        else if (k == 3.0 && first >= 1e-300 && last <= 1e300)
            kc = 3;
    }
    if (zd_kind)
        ncontact = kc == 2 ? trial_loop(p, lo, zd, c, held, 2, 1, &t)
                 : kc == 3 ? trial_loop(p, lo, zd, c, held, 3, 1, &t)
                 : kc == -1 ? trial_loop(p, lo, zd, c, held, -1, 1, &t)
                           : trial_loop(p, lo, zd, c, held, 0, 1, &t);
    else
        ncontact = kc == 2 ? trial_loop(p, lo, zd, c, held, 2, 0, &t)
                 : kc == 3 ? trial_loop(p, lo, zd, c, held, 3, 0, &t)
                 : kc == -1 ? trial_loop(p, lo, zd, c, held, -1, 0, &t)
                           : trial_loop(p, lo, zd, c, held, 0, 0, &t);
    if (ncontact < 3)
        return HUGE_VAL;
    if (!zd_kind) {
        rss = linear_fit(p, 1, &t, b);
        p->M = b[0];
        p->F0 = p->F0_free ? b[1] : p->F0_held;
        p->c = c;
        p->z0 = z0;
        return p->M > 0 ? rss : HUGE_VAL;
    }
    rss = linear_fit(p, 2, &t, b);
    if (rss < HUGE_VAL && b[0] > 0 && b[1] <= 0) {
        p->M = b[0];
        p->c = -b[1] / (kk * b[0]);
        p->F0 = p->F0_free ? b[2] : p->F0_held;
    } else {            /* no adhesion: c = 0, alpha and F0 only */
        double u[2];
        rss = linear_fit(p, 1, &t, u);
        if (!(rss < HUGE_VAL && u[0] > 0))
            return HUGE_VAL;
        p->M = u[0];
        p->c = 0.0;
        p->F0 = p->F0_free ? u[1] : p->F0_held;
    }
    p->z0 = zd + p->c;
    return rss;
}

/* The solution profile_cost leaves in p, kept so that the minimum's need
 * not be computed again. */
typedef struct {
    double M, c, z0, F0;
} profile_sol;

static double
profile_cost_kept(profile *p, double s, profile_sol *sol)
{
    double v = profile_cost(p, s);
    sol->M = p->M;
    sol->c = p->c;
    sol->z0 = p->z0;
    sol->F0 = p->F0;
    return v;
}

/* Minimise profile_cost over the sorted nodes: the best node, then Brent's
 * method (parabolic steps through the three best points, golden section
 * where a parabola would leave the bracket or shrink it too slowly) between
 * its neighbours, until the bracket is GUESS_XTOL of its first width or
 * GUESS_BRENT trials are spent.  Leaves the solution of the minimum in p.
 * Returns the minimum (HUGE_VAL when no trial was valid). */
static double
profile_min(profile *p, const double *node, size_t nn)
{
    const double g2 = 0.5 * (3.0 - sqrt(5.0));     /* 1 - golden ratio */
    double fx = HUGE_VAL, a, b, x, w, v, fw, fv, d = 0.0, e = 0.0, tol;
    profile_sol sx = { 0 }, trial;
    size_t i, ib = 0;

    for (i = 0; i < nn; i++) {
        double f = profile_cost_kept(p, node[i], &trial);
        if (f < fx) {
            fx = f;
            ib = i;
            sx = trial;
        }
    }
    if (fx == HUGE_VAL)
        return fx;
    a = node[ib > 0 ? ib - 1 : 0];
    b = node[ib + 1 < nn ? ib + 1 : nn - 1];
    x = w = v = node[ib];
    fw = fv = fx;
    tol = GUESS_XTOL * (b - a);
    for (i = 0; i < GUESS_BRENT; i++) {
        const double m = 0.5 * (a + b);
        double u, fu, pn = 0.0, q = 0.0;
        int parabola = 0;
        if (fabs(x - m) <= 2.0 * tol - 0.5 * (b - a))
            break;                      /* x within 2 tol of both ends */
        if (fabs(e) > tol) {            /* the parabola through x, w, v */
            double r = (x - w) * (fx - fv), olde = e;
            q = (x - v) * (fx - fw);
            pn = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if (q > 0)
                pn = -pn;
            q = fabs(q);
            /* inside the bracket and less than half the step before last */
            parabola = fabs(pn) < fabs(0.5 * q * olde) && pn > q * (a - x) && pn < q * (b - x);
        }
        if (parabola) {
            e = d;
            d = pn / q;
            if ((x + d) - a < 2.0 * tol || b - (x + d) < 2.0 * tol)
                d = x < m ? tol : -tol;
        } else {
            e = x < m ? b - x : a - x;
            d = g2 * e;
        }
        u = x + (fabs(d) >= tol ? d : d > 0 ? tol : -tol);
        fu = profile_cost_kept(p, u, &trial);
        /* within rounding of a tie, the smaller trial value: a flat profile
         * (a parameter the data do not fix) ends at the bracket's low end */
        if (fu < fx - GUESS_TIE_REL * fx || (fu <= fx + GUESS_TIE_REL * fx && u < x)) {
            if (u < x)
                b = x;
            else
                a = x;
            v = w; fv = fw;
            w = x; fw = fx;
            x = u; fx = fu;
            sx = trial;
        } else {
            if (u < x)
                a = u;
            else
                b = u;
            if (fu <= fw || w == x) {
                v = w; fv = fw;
                w = u; fw = fu;
            } else if (fu <= fv || v == x || v == w) {
                v = u; fv = fu;
            }
        }
    }
    /* the cost is a function of the trial value alone: the kept solution
     * is what evaluating it again would give */
    p->M = sx.M;
    p->c = sx.c;
    p->z0 = sx.z0;
    p->F0 = sx.F0;
    return fx;
}

/* Nodes for a search: n uniform in [lo, hi), then (when with_data) the
 * subsample's depths from hi up, sorted; returns the count.  The profile
 * over a contact edge has kinks at the data, so the data are its nodes. */
static size_t
make_nodes(const profile *p, double lo, double hi, size_t n, int with_data,
           double *node)
{
    size_t i, m = 0;

    for (i = 0; i < n; i++)
        node[m++] = lo + (hi - lo) * (double) i / (double) n;
    if (with_data) {            /* the subsample is in order of depth already */
        for (i = 0; i < p->n; i++)
            if (p->z[i] >= hi)
                node[m++] = p->z[i];
    } else {
        node[m++] = hi;
    }
    return m;
}

/* The sums of y^2 and y over the subsample, y = F - held, in linear_fit's
 * order. */
static void
sub_sums(guess_sub *sub, double held)
{
    size_t i;

    sub->held = held;
    sub->yy = sub->sy = 0.0;
    for (i = 0; i < sub->n; i++) {
        const double y = sub->F[i] - held;
        sub->yy += y * y;
        sub->sy += y;
    }
}

/* Curve j's subsample for the profiles: at most GUESS_NSUB points, taken
 * in order of depth (so the order of the rows does not matter):
 * GUESS_NSUB/4 points spread over the shallowest eighth of the points
 * (where contact ends and the baseline starts, which a sparse sample would
 * miss) and evenly spaced points among the rest.  Taken once (lf_fit_alloc,
 * after the depth order): the profiles of every stage and candidate share
 * it. */
void
lf_fit_guess_subsample(lf_fit *f, size_t j)
{
    fit_curve *c = &f->c[j];
    const double held = c->iF0 >= 0 ? 0.0 : c->F0;
    const size_t n = c->data.n, nshallow = GUESS_NSUB / 4;
    const size_t *ord = f->order + c->row;     /* by depth */
    size_t i, m = 0;
    double *z = f->ws.sub + 2 * GUESS_NSUB * j, *F = z + GUESS_NSUB;

    if (n <= GUESS_NSUB) {            /* a small curve: every point */
        for (i = 0; i < n; i++) {
            z[i] = c->data.depth[ord[i]];
            F[i] = c->data.force[ord[i]];
        }
        m = n;
    } else {
        /* nshallow evenly among the shallowest eighth (at least nshallow
         * points), then evenly in depth order among the rest */
        size_t low = n / 8 > nshallow ? n / 8 : nshallow;
        size_t rest = n - low, want = GUESS_NSUB - nshallow;
        for (i = 0; i < nshallow; i++) {
            size_t q = (i * (low - 1)) / (nshallow - 1);
            z[m] = c->data.depth[ord[q]];
            F[m++] = c->data.force[ord[q]];
        }
        for (i = 0; i < want; i++) {
            size_t q = low + (i * (rest - 1)) / (want - 1);
            z[m] = c->data.depth[ord[q]];
            F[m++] = c->data.force[ord[q]];
        }
    }
    c->sub.z = z;
    c->sub.F = F;
    c->sub.n = m;
    c->sub.K = lf_thin_scale(&c->data.probe);
    sub_sums(&c->sub, held);
}

/* The per-curve profile on curve j's subsample. */
static void
profile_init(lf_fit *f, size_t j, profile *p)
{
    fit_curve *c = &f->c[j];
    const double held = c->iF0 >= 0 ? 0.0 : c->F0;

    if (held != c->sub.held)        /* a held F0 set anew since alloc */
        sub_sums(&c->sub, held);
    memset(p, 0, sizeof *p);
    p->z = c->sub.z;
    p->F = c->sub.F;
    p->n = c->sub.n;
    p->k = c->data.probe.k;
    p->K = c->sub.K;
    p->R_sphere = c->data.probe.tip == LF_TIP_SPHERE ? c->data.probe.R : 0.0;
    p->branch = c->data.branch;
    p->F0_free = c->iF0 >= 0;
    p->F0_held = c->F0;
    p->yy = c->sub.yy;
    p->sy = c->sub.sy;
}

/* Stage 1 of curve j: M, c, and whether the curve sees adhesion. */
static int
guess_curve(lf_fit *f, size_t j, curve_guess *g)
{
    const fit_curve *c = &f->c[j];
    const double zmin = c->zlo, span = c->L;
    double rss;
    profile p;
    size_t i, nbase = 0, nn;
    double *node = f->ws.node;

    profile_init(f, j, &p);
    if (c->iz0 >= 0) {
        p.kind = PROFILE_ZD;
        nn = make_nodes(&p, zmin - 2.0 * span, zmin, GUESS_GRID, 1, node);
        rss = profile_min(&p, node, nn);
        if (rss < HUGE_VAL && c->data.branch == LF_BRANCH_LOAD) {
            p.kind = PROFILE_Z0;
            p.c_held = p.c;
            nn = make_nodes(&p, zmin - span, zmin, GUESS_GRID, 1, node);
            rss = profile_min(&p, node, nn);
        }
    } else {
        p.kind = PROFILE_C;
        p.z0_held = c->z0;
        nn = make_nodes(&p, 0.0, 2.0 * span, GUESS_GRID, 0, node);
        rss = profile_min(&p, node, nn);
    }
    if (rss == HUGE_VAL)
        return LF_EDATA;
    for (i = 0; i < c->data.n; i++)
        nbase += c->data.depth[i] < p.z0 - p.c;
    g->M = p.M;
    g->c = p.c;
    g->z0 = p.z0;
    g->F0 = p.F0;
    g->sees_w = !(fabs(p.k - 2.0) < 1e-9 && c->iz0 >= 0 && c->iF0 >= 0
                  && nbase < 3);
    return LF_OK;
}

/* Invert Z(nu) = (1-nu)^2/(1-2nu) on [0, 1/2). */
static double
nu_of_Z(double Z)
{
    double a = Z - 1.0;
    if (!(a > 0))
        return 0.0;
    return -a + sqrt(a * a + a);
}

/* Stage 2: every curve's z0 and F0 at the material f->mat, the contact
 * offset c_j following from it, M and F0 linear.  Returns the total
 * weighted sum of squares on the subsamples; puts z0 and F0 of curve j
 * into off[2 j], off[2 j + 1] (the stage-1 values where the profile
 * fails). */
static double
offsets_at(lf_fit *f, double *off)
{
    const lf_material *m = &f->mat;
    double total = 0.0;
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        double rss, M = lf_thin_Z(c->data.probe.base, m->nu) * m->Estar;
        double *node = f->ws.node;
        size_t nn;
        profile p;

        profile_init(f, j, &p);
        p.kind = PROFILE_Z0;
        p.c_held = sqrt(2.0 * c->data.probe.b * m->w / M);
        if (c->iz0 >= 0) {
            nn = make_nodes(&p, c->guess.z0 - 0.5 * c->L, c->guess.z0 + 0.5 * c->L,
                            GUESS_GRID, 0, node);
            rss = profile_min(&p, node, nn);
        } else {
            rss = profile_cost(&p, c->z0);
        }
        total += rss / (c->sigma * c->sigma);
        off[2 * j] = rss < HUGE_VAL ? p.z0 : c->guess.z0;
        off[2 * j + 1] = rss < HUGE_VAL ? p.F0 : c->guess.F0;
    }
    return total;
}

/* Make the offsets off (from offsets_at) the origin's, with f->mat. */
static void
set_offsets(lf_fit *f, const double *off)
{
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        c->slope = 0.0;
        if (c->iz0 >= 0)
            c->z0 = off[2 * j];
        if (c->iF0 >= 0)
            c->F0 = off[2 * j + 1];
    }
    lf_fit_set_origin(f);
}

/* Curve j's own w from the first stage. */
static double
own_w(const lf_fit *f, size_t j)
{
    const fit_curve *c = &f->c[j];
    return c->guess.M * c->guess.c * c->guess.c / (2.0 * c->data.probe.b);
}

static int
cmp_double(const void *a, const void *b)
{
    const double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

/* The candidates of the start's w into cand (room for ncurves + 2):
 * each curve's own, then the mean, then the floor; with more curves than
 * GUESS_OWN_W, the own w of GUESS_OWN_W of them at even steps through
 * their order (the smallest and the largest among them), so that the
 * search costs GUESS_OWN_W + 2 profiles per curve, not ncurves + 2: each
 * candidate's cost is a profile of every curve's offsets.  Returns the
 * count. */
static size_t
candidates(const lf_fit *f, double wmean, double wfloor, double *cand)
{
    size_t j, n = 0, nv = 0;

    if (f->ncurves <= GUESS_OWN_W) {
        for (j = 0; j < f->ncurves; j++)
            cand[n++] = own_w(f, j);
    } else {
        double *v = cand + GUESS_OWN_W;    /* the valid ones, sorted, after the picks */
        for (j = 0; j < f->ncurves; j++) {
            const double w = own_w(f, j);
            if (w >= wfloor && isfinite(w))
                v[nv++] = w;
        }
        qsort(v, nv, sizeof *v, cmp_double);
        for (j = 0; j < GUESS_OWN_W && nv > 0; j++)
            cand[n++] = v[j * (nv - 1) / (GUESS_OWN_W - 1)];
    }
    cand[n++] = wmean;
    cand[n++] = wfloor;
    return n;
}

int
lf_fit_guess(lf_fit *f, fit_start *start, lf_error *err)
{
    size_t j, nf = 0, nb = 0, nw = 0;
    double lnMf = 0, lnMb = 0, lnw = 0, wfloor = HUGE_VAL;
    double *off = f->ws.off, *off_best = f->ws.off + 2 * f->ncurves;
    int have_best = 0;
    lf_material *m = &f->mat;
    int by_model;

    start->alt_w = NAN;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        double w_j;
        if (guess_curve(f, j, &f->c[j].guess) != LF_OK)
            return lf_fail(err, LF_EDATA, "curve %zu (%s): no contact found for an initial guess",
                           j + 1, c->data.name ? c->data.name : "");
        if (c->data.probe.base == LF_BASE_FRICTIONLESS) {
            lnMf += log(c->guess.M);
            nf++;
        } else {
            lnMb += log(c->guess.M);
            nb++;
        }
        w_j = c->guess.M * c->guess.c * c->guess.c / (2.0 * c->data.probe.b);
        wfloor = lf_fmin(wfloor, c->guess.M * 1e-6 * c->L * c->L / (2.0 * c->data.probe.b));
        if (w_j > 0 && c->guess.sees_w) {
            lnw += log(w_j);
            nw++;
        }
    }
    if (f->imat[FIT_NU] >= 0) {
        if (nf > 0 && nb > 0)
            m->nu = nu_of_Z(exp(lnMb / (double) nb - lnMf / (double) nf));
        else if (!isfinite(m->nu))
            m->nu = 0.3;
        m->nu = lf_fmin(lf_fmax(m->nu, 0.02), 0.4999);
    }
    if (f->imat[FIT_E] >= 0)
        m->Estar = nf > 0 ? exp(lnMf / (double) nf)
                          : exp(lnMb / (double) nb) / lf_thin_Z(LF_BASE_BONDED, m->nu);
    /* a model with no thickness: its own force law (guess_model.c) */
    by_model = lf_fit_guess_by_model(f) && lf_fit_guess_model(f);
    if (f->imat[FIT_W] >= 0 && !by_model) {
        /* candidates: each curve's own w (of GUESS_OWN_W of many curves),
         * their geometric mean and the floor; the one whose offsets fit all
         * curves best wins (ties to the smaller w, so the order of the
         * curves does not matter) */
        double best = HUGE_VAL, wbest = wfloor, second = HUGE_VAL, wsecond = NAN;
        const double wmean = nw > 0 ? exp(lnw / (double) nw) : 0.0;
        double *cand = f->ws.work;      /* ncurves + 2 of its 2 ndata */
        size_t ncand = candidates(f, wmean, wfloor, cand), i, q;
        int any_z0;
        for (i = 0; i < ncand; i++) {
            double wc = cand[i], cost;
            if (!(wc >= wfloor) || !isfinite(wc))
                continue;
            for (q = 0; q < i && cand[q] != wc; q++)
                ;
            if (q < i)
                continue;           /* the same w again (one curve: its own w is the mean) */
            m->w = wc;
            cost = offsets_at(f, off);
            if (cost < best || (cost == best && wc < wbest)) {
                if (!(fabs(log(wc / wbest)) < FIT_ALT_LOG_SEP)) {
                    second = best;
                    wsecond = wbest;
                }
                best = cost;
                wbest = wc;
                memcpy(off_best, off, 2 * f->ncurves * sizeof *off);
                have_best = 1;
            } else if (cost < second && !(fabs(log(wc / wbest)) < FIT_ALT_LOG_SEP)) {
                second = cost;
                wsecond = wc;
            }
        }
        m->w = wbest;
        /* a runner-up within a factor 3 in cost is a second start where a
         * contact point is free: its kinks make the other basins.  Not the
         * floor: a start at no adhesion ends, when w is determined, where
         * the first did, after climbing ten e-folds of w (half the
         * iterations of a fit with free offsets), and where w is not, in a
         * minimum within a chi2 of the first's (bench, paper-offsets: the
         * same errors and interval coverage without it) */
        for (i = 0, any_z0 = 0; i < f->ncurves; i++)
            any_z0 |= f->c[i].iz0 >= 0;
        start->alt_w = any_z0 && second <= FIT_ALT_COST_RATIO * best && isfinite(wsecond)
                       && wsecond != wfloor ? wsecond : NAN;
    }
    /* the exact model: the thin profile's start or its own force law's,
     * whichever fits better (guess_model.c), from the offsets profiled at
     * the winning w above */
    if (!by_model) {
        if (have_best)
            set_offsets(f, off_best);
        else
            lf_fit_guess_offsets(f);
        lf_fit_guess_compare_model(f);
    }
    /* the user's starting point, where given, replaces the automatic one */
    start->automatic = *m;
    start->user = 0;
    if (f->imat[FIT_W] >= 0 && !isnan(f->set.w.guess)) {
        m->w = f->set.w.guess;
        start->user = 1;
    }
    if (f->imat[FIT_E] >= 0 && !isnan(f->set.Estar.guess)) {
        m->Estar = f->set.Estar.guess;
        start->user = 1;
    }
    if (f->imat[FIT_NU] >= 0 && !isnan(f->set.nu.guess)) {
        m->nu = f->set.nu.guess;
        start->user = 1;
    }
    start->mat = *m;
    if (f->start_by_model && !start->user)
        ;                           /* the model's own start, offsets set with it */
    else if (have_best && !start->user)
        set_offsets(f, off_best);   /* profiled at this material already */
    else
        lf_fit_guess_offsets(f);
    return LF_OK;
}

void
lf_fit_guess_offsets(lf_fit *f)
{
    if (f->start_by_model || lf_fit_guess_by_model(f)) {
        lf_fit_guess_model_offsets(f);
        return;
    }
    offsets_at(f, f->ws.off);
    set_offsets(f, f->ws.off);
}
