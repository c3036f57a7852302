/* model_halfspace.c: JKR adhesion of a power-law punch on an elastic
 * half-space (Borodich, Galanov & Suarez-Alvarez 2014, JMPS 68:14), the
 * thick-layer limit of the exact model.
 *
 *   delta = A a^k - sqrt(2 pi w a / E*),          A = kappa_k / (k R^(k-1))
 *   P     = 2 E* A k a^(k+1)/(k+1) - sqrt(8 pi w E* a^3)
 * Displacement control is unstable where ddelta/da < 0: the unloading
 * branch ends at a_det^(k-1/2) = sqrt(2 pi w/E*) R^(k-1)/(2 kappa_k), the
 * minimum of delta(a); below it there is no contact.  The force-controlled
 * pull-off is the minimum of P, a_c^(k-1/2) = (3/(4 kappa_k)) sqrt(8 pi w/E*)
 * R^(k-1).  Loading makes contact at delta = 0 and jumps onto the stable
 * branch there (P_jump), as the other models do.  The construction needs
 * k > 1/2: for k <= 1/2 the adhesive term outgrows the elastic one and no
 * stable branch exists.
 *
 * One curve per k.  With q = sqrt(2 pi w/E*), the radius a_s where the
 * two terms of delta are equal, A a_s^k = q a_s^(1/2), and
 *   a_s = (q/A)^(1/(k-1/2)),  delta_s = A a_s^k,  P_s = E* A a_s^(k+1),
 * the curve in r = (a/a_s)^(1/2) depends on k alone:
 *   delta/delta_s = D(r)  = r^(2k) - r,
 *   P/P_s         = Pi(r) = 2k/(k+1) r^(2k+2) - 2 r^3.
 * D'(r) = 2k r^(2k-1) - 1 vanishes at r_det = (2k)^(-1/(2k-1)), where
 * D_det = r_det (1/(2k) - 1) < 0: the stable branch is r > r_det.  w and
 * E* enter through the scales only (d ln a_s/d ln w = 1/(2k-1)), so at
 * fixed delta, with S = 2 E* a the flat-punch stiffness,
 *   dP/ddelta = S (1 - 2/D'(r)),
 *   dP/dln w  = -2 P_s r^3 / D'(r),
 *   dP/dln E* = P - dP/dln w   (P is E* times a function of w/E*).
 *
 * Inversion without a search.  r(delta) comes from a table of the stable
 * branch, built once per k in the process (about 1 ms, 200 kB): y = r - r_det
 * against s = delta/delta_s - D_det > 0 at the nodes s = 2^e (1 + j/32),
 * 2^-40 <= s <= 2^100, so the cell of an s is read from its bits (exponent
 * and five mantissa bits) and spans 1/32 of its left end.  Cubic Hermite
 * interpolation with the exact slopes dy/ds = 1/D'(r) (each cell's cubic in
 * the fraction u of the cell kept as its four coefficients, so a point
 * costs a load and three multiply-adds); y behaves like a
 * power of s at both ends (s^(1/2) at detachment, s^(1/(2k)) deep), and on
 * such a cell the interpolation's relative error is below
 * |p(p-1)(p-2)(p-3)| 32^-4 / 384 ~ 2.4e-9 (p = 1/2);
 * lf_halfspace_table_error measures it over every cell (2.2e-9 to 2.9e-9
 * for k = 0.51 to 30; tests assert < 5e-9).  One Newton step on
 * D(r) = delta/delta_s from there squares the error, leaving r within
 * ~1e-12 of the root (nearest the fold, where the step's own rounding
 * would exceed the table's error, the table's value stands; newton_min
 * below).  Below 2^-40 the series y = c1 s^(1/2) + c2 s
 * starts the step (relative error ~ s), above 2^100 the fixed point
 * r = (t + r)^(1/(2k)) (adhesion a vanishing correction there).  So each
 * point costs one power r^(2k) (multiplications when 2k is an integer)
 * and one division.  Where the scales leave the range of doubles (w or E*
 * absurdly small or large) the curve is solved in a, point by point, by
 * safeguarded Newton.
 */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>

#include "exact.h"
#include "halfspace.h"

/* ---- the table of one k ------------------------------------------------ */

#define MB 5                         /* mantissa bits of the cell index */
#define LOG2_SMIN (-40)
#define LOG2_SMAX 100
#define NNODE ((size_t) (LOG2_SMAX - LOG2_SMIN) * (1u << MB) + 1)
/* the cell index of s is (bits of s >> (52 - MB)) - BASE */
#define BASE ((uint64_t) (1023 + LOG2_SMIN) << MB)
#define S_MIN 0x1p-40

typedef struct hs_table hs_table;
struct hs_table {
    double k, k2;          /* k and 2k */
    unsigned n2k;          /* 2k when it is an integer up to 64, else 0 */
    double k2h;            /* 2k (2k - 1) / 2 */
    double ck;             /* 2k/(k+1) */
    double inv_k2;         /* 1/(2k) */
    double r_det, D_det;   /* the stable branch's end */
    double c1, c2;         /* y = c1 s^(1/2) + c2 s + O(s^(3/2)) */
    /* Below this D'(r) (near detachment, s below ~1e-7) the table's start
     * is kept as it is: the Newton step's residual D(r) - t, a difference
     * of terms of order one, carries rounding ~1e-16 that the step divides
     * by D'(r), and that exceeds the table's error, ~3e-9 y = 3e-9
     * D'(r)/D''(r_det), where D'(r) < 2e-4 D''(r_det)^(1/2) */
    double newton_min;
    double *node;          /* y, dy/ds at node i: node[2 i], node[2 i + 1] */
    /* cell i's cubic in u = (s - s_i)/(s_(i+1) - s_i) in [0, 1):
     * r = cell[4 i] + u (cell[4 i + 1] + u (cell[4 i + 2] + u cell[4 i + 3])),
     * the Hermite interpolant of the nodes with r_det added, formed once
     * here rather than per point */
    double *cell;
    hs_table *next;        /* the store's list */
};

/* r^(2k) for r > 0, n = 2k when that is an integer up to 64 (then by
 * multiplications, written out for the usual probes, k = 1.5, 2, 3, 4,
 * where n is a constant), else 0. */
LF_KERNEL double
rpow_n(double k2, unsigned n, double r)
{
    double v = 1.0, r2 = r * r;

    switch (n) {
    case 0: return exp(k2 * log(r));
    case 3: return r2 * r;
    case 4: return r2 * r2;
    case 6: return r2 * r2 * r2;
    case 8: return (r2 * r2) * (r2 * r2);
    default: break;
    }
    for (;;) {
        if (n & 1u)
            v *= r;
        n >>= 1;
        if (n == 0)
            return v;
        r *= r;
    }
}

static double
rpow(const hs_table *t, double r)
{
    return rpow_n(t->k2, t->n2k, r);
}

/* g = (1 + rho)^k2 - 1 - k2 rho and gp = (1 + rho)^(k2 - 1) - 1, rho >= 0,
 * without the cancellation of the direct forms at small rho (binomial
 * series there). */
static void
binomial_rest(double k2, double rho, double *g, double *gp)
{
    if (rho < 0.5) {
        double c = k2 * (k2 - 1.0) / 2.0 * rho * rho, s = 0.0;   /* n = 2 term of g */
        double d = (k2 - 1.0) * rho, sp = 0.0;                  /* n = 1 term of gp */
        int n;
        for (n = 2; n < 80 && fabs(c) > 1e-18 * fabs(s); n++) {
            s += c;
            c *= (k2 - n) / (n + 1.0) * rho;
        }
        for (n = 1; n < 80 && fabs(d) > 1e-18 * fabs(sp); n++) {
            sp += d;
            d *= (k2 - 1.0 - n) / (n + 1.0) * rho;
        }
        *g = s;
        *gp = sp;
        return;
    }
    *g = expm1(k2 * log1p(rho)) - k2 * rho;
    *gp = expm1((k2 - 1.0) * log1p(rho));
}

/* y = r - r_det with D(r) - D_det = s > 0, to rounding: Newton on
 * F(y) = D(r_det + y) - D_det = (r_det/2k) g(y/r_det), convex and rising,
 * so from any y > 0 the first step lands above the root and the rest
 * descend onto it. */
static double
solve_y(const hs_table *t, double s, double y, double *slope)
{
    double g, gp, dy;
    int i;

    if (!(y > 0.0))   /* the smaller of the two ends' laws */
        y = fmin(t->c1 * sqrt(s), exp(t->inv_k2 * log(s)));
    binomial_rest(t->k2, y / t->r_det, &g, &gp);
    for (i = 0; i < 200; i++) {
        dy = (t->r_det * t->inv_k2 * g - s) / gp;
        /* after the first step the iterates only descend: a step that
         * does not is rounding, and y stands */
        if (i > 0 && !(dy > 0.0))
            break;
        y -= dy;
        binomial_rest(t->k2, y / t->r_det, &g, &gp);
        if (!(dy > 1e-15 * y) && i > 0)
            break;
    }
    if (slope != NULL)
        *slope = 1.0 / gp;    /* dy/ds = 1/D'(r) */
    return y;
}

static void
table_free(hs_table *t)
{
    if (t != NULL) {
        free(t->node);
        free(t->cell);
    }
    free(t);
}

static hs_table *
table_build(double k)
{
    hs_table *t = calloc(1, sizeof *t);
    double k2 = 2.0 * k, Drr, Drrr, y = 0.0;
    size_t i;

    if (t == NULL || (t->node = malloc(2 * NNODE * sizeof *t->node)) == NULL
        || (t->cell = malloc(4 * (NNODE - 1) * sizeof *t->cell)) == NULL) {
        table_free(t);
        return NULL;
    }
    t->k = k;
    t->k2 = k2;
    t->n2k = k2 == floor(k2) && k2 <= 64.0 ? (unsigned) k2 : 0;
    t->k2h = k2 * (k2 - 1.0) / 2.0;
    t->ck = k2 / (k + 1.0);
    t->inv_k2 = 1.0 / k2;
    t->r_det = pow(k2, -1.0 / (k2 - 1.0));
    t->D_det = t->r_det * (t->inv_k2 - 1.0);
    /* D'' and D''' at r_det: s = D''/2 y^2 + D'''/6 y^3 + ... inverted */
    Drr = k2 * (k2 - 1.0) * pow(t->r_det, k2 - 2.0);
    Drrr = Drr * (k2 - 2.0) / t->r_det;
    t->c1 = sqrt(2.0 / Drr);
    t->c2 = -Drrr / (3.0 * Drr * Drr);
    t->newton_min = 2e-4 * sqrt(Drr);
    for (i = 0; i < NNODE; i++) {
        double s = lf_double((BASE + i) << (52 - MB));
        if (i > 0)   /* the tangent from the last node: above the root (y concave) */
            y += t->node[2 * i - 1] * (s - lf_double((BASE + i - 1) << (52 - MB)));
        y = solve_y(t, s, y, &t->node[2 * i + 1]);
        t->node[2 * i] = y;
    }
    for (i = 0; i + 1 < NNODE; i++) {
        /* the slopes in u: times the cell's width, a power of two */
        const double h = lf_double(((BASE + i) >> MB << 52) - ((uint64_t) MB << 52));
        const double *nd = t->node + 2 * i;
        const double y0 = nd[0], y1 = nd[2], m0 = nd[1] * h, m1 = nd[3] * h, dy = y1 - y0;
        double *cf = t->cell + 4 * i;
        cf[0] = t->r_det + y0;
        cf[1] = m0;
        cf[2] = 3.0 * dy - 2.0 * m0 - m1;
        cf[3] = m0 + m1 - 2.0 * dy;
    }
    return t;
}

/* The process store: a list of immutable tables read without a lock,
 * linked in under a mutex (a second builder of the same k frees its copy),
 * kept for the life of the process (about 200 kB each). */
static pthread_mutex_t store_lock = PTHREAD_MUTEX_INITIALIZER;
static _Atomic(hs_table *) store_head = NULL;

static const hs_table *
store_find(double k)
{
    const hs_table *t;
    for (t = atomic_load_explicit(&store_head, memory_order_acquire); t != NULL; t = t->next)
        if (t->k == k)
            return t;
    return NULL;
}

static const hs_table *
table_get(double k)
{
    const hs_table *found = store_find(k);
    hs_table *t;

    if (found != NULL)
        return found;
    if ((t = table_build(k)) == NULL)
        return NULL;
    pthread_mutex_lock(&store_lock);
    found = store_find(k);
    if (found == NULL) {
        t->next = atomic_load_explicit(&store_head, memory_order_relaxed);
        atomic_store_explicit(&store_head, t, memory_order_release);
        found = t;
        t = NULL;
    }
    pthread_mutex_unlock(&store_lock);
    table_free(t);
    return found;
}

/* The start of r for s = t - D_det (see the header), its error ~1e-9. */
static inline double
r_start(const hs_table *tb, double s, double t)
{
    /* the cell from the bits, 2^-40 <= s < 2^100 the one test (a negative
     * s or a NaN has bits above the table's: its cell is out of range) */
    const uint64_t b = lf_bits(s), i = (b >> (52 - MB)) - BASE;

    if (i < NNODE - 1) {
        /* u from the mantissa's bits below the cell's: 2^MB + u - 2^MB,
         * exact, as (s - s_i)/(s_(i+1) - s_i) is */
        const uint64_t low = (UINT64_C(1) << (52 - MB)) - 1;
        const double *cf = tb->cell + 4 * i;
        const double u = lf_double((b & low) | ((uint64_t) (1023 + MB) << 52)) - (double) (1u << MB);
        return cf[0] + u * (cf[1] + u * (cf[2] + u * cf[3]));
    }
    if (s < S_MIN)
        return tb->r_det + (s > 0.0 ? tb->c1 * sqrt(s) + tb->c2 * s : 0.0);
    /* deep: r^(2k) = t + r, the correction r/t below 2^-100 (k - 1/2)/(2k) */
    {
        double r = exp(tb->inv_k2 * log(t));
        return exp(tb->inv_k2 * log(t + r));
    }
}

/* r where D(r) = t when the start r (with v = r^(2k), den = r D'(r)) is
 * off, or near r_det (rare: not the table's cells): full Newton steps. */
static double
r_polish(const hs_table *tb, double t, double r, double v, double den, double *vout,
         double *inv)
{
    int i;

    for (i = 0; i < 60 && den > tb->newton_min * r; i++) {
        double e = (v - r - t) / den;
        r *= 1.0 - lf_fmax(lf_fmin(e, 0.5), -1.0);
        v = rpow(tb, r);
        den = tb->k2 * v - r;
        if (!(fabs(e) > 1e-15))
            break;
    }
    *vout = v;
    *inv = den > 0.0 ? 1.0 / den : INFINITY;
    return r;
}

/* r where D(r) = t from its start r: one Newton step, with v = r^(2k)
 * and inv = 1/(r D'(r)) (INFINITY at r_det).  n: as rpow_n. */
LF_KERNEL double
r_step_n(const hs_table *tb, unsigned n, double t, double r, double *v, double *inv)
{
    double vr = rpow_n(tb->k2, n, r);
    double den = tb->k2 * vr - r, q = 1.0 / den, e = (vr - r - t) * q;

    if (!(den > tb->newton_min * r && fabs(e) <= 1e-4))
        return r_polish(tb, t, r, vr, den, v, inv);
    /* the step over r, e; (1 - e)^(2k) to second order, O(e^3) below
     * rounding; 1/den moved by one Newton step of the reciprocal (den
     * changes by a fraction ~e r/(r - r_det) < 1e-5, its square below
     * rounding) */
    r *= 1.0 - e;
    vr *= 1.0 - e * (tb->k2 - tb->k2h * e);
    den = tb->k2 * vr - r;
    *v = vr;
    *inv = q * (2.0 - den * q);
    return r;
}

LF_KERNEL double
r_of_n(const hs_table *tb, unsigned n, double t, double *v, double *inv)
{
    return r_step_n(tb, n, t, r_start(tb, t - tb->D_det, t), v, inv);
}

static inline double
r_of(const hs_table *tb, double t, double *v)
{
    double inv;
    return r_of_n(tb, tb->n2k, t, v, &inv);
}

/* ---- the model ---------------------------------------------------------- */

/* What a model object keeps for its probe. */
typedef struct {
    const hs_table *tab;
    double A, lnA;         /* A = kappa_k B = kappa_k / (k R^(k-1)), ln A */
} hs_state;

/* The constants of one (probe, material). */
typedef struct {
    double k, A, lnA, Estar, q;   /* q = sqrt(2 pi w / E*) */
    double a_det, delta_det;
    /* the scales (header), when they are normal numbers */
    int scaled;
    double a_s, delta_s, inv_ds, P_s;
} hs_ctx;

static void
hs_curve(const hs_ctx *c, double a, double *delta, double *ddelta, double *P,
         double *dP, double *shift, double *P1)
{
    double ak = pow(a, c->k), sa = sqrt(a);
    *shift = c->q * sa;
    *delta = c->A * ak - *shift;
    *ddelta = c->k * c->A * ak / a - 0.5 * c->q / sa;
    *P1 = 2.0 * c->Estar * c->A * c->k * ak * a / (c->k + 1.0);
    /* S shift = 2 E* a q sqrt(a) */
    *P = *P1 - 2.0 * c->Estar * c->q * a * sa;
    *dP = 2.0 * c->Estar * c->A * c->k * ak - 3.0 * c->Estar * c->q * sa;
}

/* A = kappa_k B, and *lnA its logarithm (B leaves double precision for a
 * flat punch, where the scales below may not; A is then exp(ln A)). */
static double
A_of(const lf_probe *p, double *lnA)
{
    double kap = lf_exact_kappa(p->k);
    double A = lf_probe_by_R(p) ? kap / (p->k * pow(p->R, p->k - 1.0))
                                : kap * lf_probe_prefactor(p);

    *lnA = log(kap) + lf_probe_log_prefactor(p);
    return isnormal(A) ? A : exp(*lnA);
}

static int
hs_init(hs_ctx *c, const hs_state *st, const lf_probe *p, const lf_material *m)
{
    double dd, P, dP, sh, P1, ln_as;

    if (!(p->k > 0.5))
        return LF_EINVAL;
    c->k = p->k;
    if (st != NULL) {
        c->A = st->A;
        c->lnA = st->lnA;
    } else {
        c->A = A_of(p, &c->lnA);
    }
    c->Estar = m->Estar;
    c->q = sqrt(2.0 * M_PI * m->w / m->Estar);
    c->a_det = 0.0;
    c->scaled = 0;
    if (c->q > 0.0 && st != NULL) {
        /* ln a_s, and the scales where every one of them, and 1/delta_s,
         * is a normal number with room to spare */
        ln_as = (log(c->q) - c->lnA) / (c->k - 0.5);
        if (fabs(ln_as) < 300.0 && fabs(ln_as * c->k + c->lnA) < 600.0) {
            c->a_s = exp(ln_as);
            c->delta_s = c->q * sqrt(c->a_s);
            c->inv_ds = 1.0 / c->delta_s;
            c->P_s = c->Estar * c->delta_s * c->a_s;
            c->scaled = isnormal(c->P_s) && isnormal(c->inv_ds);
        }
    }
    if (c->scaled) {
        c->a_det = c->a_s * st->tab->r_det * st->tab->r_det;
        c->delta_det = st->tab->D_det * c->delta_s;
    } else if (c->q > 0.0) {
        c->a_det = pow(c->q / (2.0 * c->k * c->A), 1.0 / (c->k - 0.5));
        hs_curve(c, c->a_det, &c->delta_det, &dd, &P, &dP, &sh, &P1);
    } else {
        c->delta_det = 0.0;
    }
    return LF_OK;
}

/* a on the stable branch with delta(a) = target > delta_det: Newton in
 * ln a from `guess` (NAN: none) with a bisection bracket.  The path for
 * scales outside the doubles' range. */
static double
hs_invert(const hs_ctx *c, double target, double guess)
{
    double lo = c->a_det > 0.0 ? log(c->a_det) : -700.0, hi, u, step = 0.25;
    double d, dd, P, dP, sh, P1;
    int i;

    u = guess > 0.0 ? log(guess) : NAN;
    if (!(u > lo))
        u = fmax(log(fmax(target - c->delta_det, 1e-300) / c->A) / c->k, lo + 0.5);
    hs_curve(c, exp(u), &d, &dd, &P, &dP, &sh, &P1);
    if (d >= target) {
        hi = u;
    } else {
        lo = u;
        for (hi = u + step, i = 0; i < 2000; hi += step, step *= 2.0, i++) {
            hs_curve(c, exp(hi), &d, &dd, &P, &dP, &sh, &P1);
            if (d >= target)
                break;
            lo = hi;
        }
        if (lo != u)           /* else keep the guess: Newton from there */
            u = 0.5 * (lo + hi);
        hs_curve(c, exp(u), &d, &dd, &P, &dP, &sh, &P1);
    }
    for (i = 0; i < 200; i++) {
        double g = d - target, un;
        if (g > 0.0)
            hi = u;
        else
            lo = u;
        un = dd > 0.0 ? u - g / (dd * exp(u)) : 0.5 * (lo + hi);
        if (!(un > lo && un < hi))
            un = 0.5 * (lo + hi);
        if (g == 0.0 || fabs(un - u) < 1e-13 || hi - lo < 1e-14)
            return exp(un);
        u = un;
        hs_curve(c, exp(u), &d, &dd, &P, &dP, &sh, &P1);
    }
    return exp(u);
}

/* The points delta[0..n-1] on the stable branch by the scales and the
 * table (n2k: rpow_n's n; start: where contact begins).  In blocks, each
 * stage over the block's points before the next, so that the processor
 * overlaps the points' chains of dependent operations. */
#define BLOCK 32
LF_KERNEL void
points_scaled(const hs_ctx *c, const hs_table *tb, unsigned n2k, int load, double start,
              size_t n, const double *delta, lf_eval *out)
{
    const double two_E = 2.0 * c->Estar;
    double t[BLOCK], r[BLOCK], v[BLOCK], inv[BLOCK];
    size_t i0, j;

    for (i0 = 0; i0 < n; i0 += BLOCK) {
        const size_t nb = n - i0 < BLOCK ? n - i0 : BLOCK;
        for (j = 0; j < nb; j++) {
            t[j] = delta[i0 + j] * c->inv_ds;
            r[j] = r_start(tb, t[j] - tb->D_det, t[j]);
        }
        for (j = 0; j < nb; j++)
            r[j] = r_step_n(tb, n2k, t[j], r[j], &v[j], &inv[j]);
        for (j = 0; j < nb; j++) {
            lf_eval *e = &out[i0 + j];
            const double d = delta[i0 + j], rr = r[j], r2 = rr * rr;
            const double a = c->a_s * r2, P = c->P_s * r2 * (tb->ck * v[j] - 2.0 * rr);
            const double dlw = -2.0 * c->P_s * r2 * r2 * inv[j];   /* -2 P_s r^3 / D'(r) */

            if (load ? !(d >= start) : !(d > start)) {
                e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
                continue;
            }
            e->P = P;
            e->a = a;
            e->dP_ddelta = lf_capped(two_E * a * (1.0 - 2.0 * rr * inv[j]));   /* S (1 - 2/D') */
            e->dP_dlogw = lf_capped(dlw);
            e->dP_dlogE = lf_capped(P - dlw);
            e->dP_dnu = 0.0;
        }
    }
}

/* The same by Newton in a (no scales); *a_prev warm-starts the next. */
static void
point_direct(const hs_ctx *c, double delta, double *a_prev, lf_eval *e)
{
    double a, d, dd, P, dP, sh, P1, S, dPdd;

    a = *a_prev = hs_invert(c, delta, *a_prev);
    hs_curve(c, a, &d, &dd, &P, &dP, &sh, &P1);
    S = 2.0 * c->Estar * a;
    dPdd = dd > 0.0 ? dP / dd : -LF_BIG;
    e->P = P;
    e->a = a;
    e->dP_ddelta = lf_capped(dPdd);
    e->dP_dlogw = lf_capped(-0.5 * S * sh + 0.5 * dPdd * sh);
    e->dP_dlogE = lf_capped(P1 - 0.5 * S * sh - 0.5 * dPdd * sh);
    e->dP_dnu = 0.0;
}

/* Without adhesion (w = 0): delta = A a^k, P = 2 E* A k a^(k+1)/(k+1). */
static void
point_hertz(const hs_ctx *c, double delta, lf_eval *e)
{
    double a = pow(delta / c->A, 1.0 / c->k);
    e->a = a;
    e->P = 2.0 * c->Estar * c->A * c->k * pow(a, c->k + 1.0) / (c->k + 1.0);
    e->dP_ddelta = 2.0 * c->Estar * a;
    e->dP_dlogw = 0.0;
    e->dP_dlogE = e->P;
    e->dP_dnu = 0.0;
}

/* ---- a sphere of radius R ------------------------------------------------
 *
 * Exact for a sphere on a half-space, whatever a/R (Maugis 1995, J. Colloid
 * Interface Sci. 170:447, Eqs. 5-6): with a = R tanh(v), v = atanh(a/R),
 *   delta1 = (a/2) ln((R + a)/(R - a)) = R v tanh(v),
 *   P1     = (E* / 2) [(a^2 + R^2) ln((R + a)/(R - a)) - 2 a R]
 *          = E* R^2 [(1 + tanh^2 v) v - tanh v],
 * and the JKR edge condition with the flat punch's stiffness 2 E* a, as for
 * the power laws: delta = delta1 - q sqrt(a), P = P1 - 2 E* q a^(3/2).
 * v runs over (0, inf) as a runs over (0, R): every indentation has its
 * contact, which tends to R as delta1 grows without bound.  In v,
 *   d delta/dv = R (t + v s) - q R s / (2 sqrt a),   t = tanh v, s = 1 - t^2,
 *   dP/dv      = 2 E* a R (t + v s) - 3 E* q R s sqrt(a),
 * so each condition is one increasing function of v equal to a number:
 *   detachment (d delta/dv = 0):   (sinh v cosh v + v) sqrt(a) = q/2,
 *   pull-off (dP/dv = 0):          (sinh v cosh v + v) sqrt(a) = 3q/2,
 *   contact on loading (delta = 0): v sqrt(a) = q.
 * For a << R these are the paraboloid's (k = 2) of the header. */

typedef struct {
    double R, Estar, q;
    double v_det, delta_det;   /* v_det 0 and delta_det 0 without adhesion */
} sp_ctx;

/* (1 + t^2) v - t, t = tanh v: by its series in t where the two terms
 * nearly cancel (t < 0.1: they cancel to 4/3 t^2 of themselves, two
 * digits at t = 0.1, where eight terms of the series reach rounding), sum
 * over n >= 1 of 4n t^(2n+1) / (4n^2 - 1). */
static double
sp_cap(double v, double t)
{
    double t2 = t * t, term = t * t2, sum = 0.0;
    int n;

    if (t >= 0.1)
        return (1.0 + t2) * v - t;
    for (n = 1; n < 60; n++) {
        double add = 4.0 * n / (4.0 * n * n - 1.0) * term;
        sum += add;
        if (add < 1e-17 * sum)
            break;
        term *= t2;
    }
    return sum;
}

typedef struct {
    double a, delta, dd, P, dP, P1, shift;
} sp_pt;

static void
sp_curve(const sp_ctx *c, double v, sp_pt *o)
{
    /* tanh v and sech^2 v = 1 - t^2 from one expm1(2v) (past v = 350 the
     * exponential overflows: t = 1, s = 0) */
    const double em = v < 350.0 ? expm1(2.0 * v) : INFINITY;
    const double t = isfinite(em) ? em / (em + 2.0) : 1.0;
    const double s = isfinite(em) ? 4.0 * (em + 1.0) / ((em + 2.0) * (em + 2.0)) : 0.0;
    const double a = c->R * t, sa = sqrt(a), d1v = c->R * (t + v * s);

    o->a = a;
    o->shift = c->q * sa;
    o->delta = c->R * v * t - o->shift;
    o->dd = d1v - (sa > 0.0 ? 0.5 * c->q / sa * c->R * s : 0.0);
    o->P1 = c->Estar * c->R * c->R * sp_cap(v, t);
    o->P = o->P1 - 2.0 * c->Estar * a * o->shift;
    o->dP = 2.0 * c->Estar * a * d1v - 3.0 * c->Estar * c->q * c->R * s * sa;
}

/* The conditions of the header: (sinh v cosh v + v) sqrt(a) (which 0), or
 * v sqrt(a) (which 1). */
static double
sp_cond(const sp_ctx *c, int which, double v)
{
    double ra = sqrt(c->R * tanh(v));
    return which == 0 ? (0.5 * sinh(2.0 * v) + v) * ra : v * ra;
}

/* v > 0 where the increasing sp_cond(which) equals target > 0: bisection
 * in ln v on a bracket grown from the small-v law (cond ~ 2 v^(3/2) R^(1/2)
 * or v^(3/2) R^(1/2)), to the rounding of v. */
static double
sp_root(const sp_ctx *c, int which, double target)
{
    double x = target / ((which == 0 ? 2.0 : 1.0) * sqrt(c->R));
    double lo = log(fmax(cbrt(x * x), 1e-300)), hi = lo;
    int i;

    while (sp_cond(c, which, exp(lo)) > target && lo > -700.0)
        lo -= 1.0;
    while (sp_cond(c, which, exp(hi)) <= target && hi < 700.0)
        hi += 1.0;
    for (i = 0; i < 200 && hi - lo > 1e-15 * fmax(1.0, fabs(lo)); i++) {
        double m = 0.5 * (lo + hi);
        if (sp_cond(c, which, exp(m)) > target)
            hi = m;
        else
            lo = m;
    }
    return exp(0.5 * (lo + hi));
}

static void
sp_init(sp_ctx *c, const lf_probe *p, const lf_material *m)
{
    sp_pt pt;

    c->R = p->R;
    c->Estar = m->Estar;
    c->q = sqrt(2.0 * M_PI * m->w / m->Estar);
    c->v_det = c->delta_det = 0.0;
    if (c->q > 0.0) {
        c->v_det = sp_root(c, 0, 0.5 * c->q);
        sp_curve(c, c->v_det, &pt);
        c->delta_det = pt.delta;
    }
}

/* v on the stable branch where delta(v) = target > delta_det: Newton from
 * `guess` (NAN: from delta1 ~ R v^2 at small v, R v at large), kept in a
 * bracket grown by doubling. */
static double
sp_invert(const sp_ctx *c, double target, double guess, sp_pt *o)
{
    double lo = c->v_det, hi = INFINITY, v = guess, x;
    int i;

    if (!(v > lo && isfinite(v))) {
        x = fmax(target - c->delta_det, 0.0) / c->R;
        v = fmax(sqrt(x + x * x), lo * (1.0 + 1e-6) + 1e-300);
    }
    for (i = 0; i < 300; i++) {
        double g, vn;
        sp_curve(c, v, o);
        g = o->delta - target;
        if (g > 0.0)
            hi = v;
        else
            lo = v;
        if (fabs(g) <= 1e-15 * (fabs(o->delta + o->shift) + o->shift))
            break;
        vn = o->dd > 0.0 ? v - g / o->dd : NAN;
        if (!(vn > lo && vn < hi))
            vn = isfinite(hi) ? 0.5 * (lo + hi) : 2.0 * v;
        if (fabs(vn - v) <= 1e-15 * v || (isfinite(hi) && hi - lo <= 1e-15 * hi))
            break;
        v = vn;
    }
    return v;
}

static int
sp_eval(const lf_probe *probe, const lf_material *mat, lf_branch branch, size_t n,
        const double *delta, lf_eval *out)
{
    const int load = branch == LF_BRANCH_LOAD;
    sp_ctx c;
    double v = NAN, start;
    size_t i;

    sp_init(&c, probe, mat);
    start = load ? fmax(0.0, c.delta_det) : c.delta_det;
    for (i = 0; i < n; i++) {
        lf_eval *e = &out[i];
        int touching = load ? delta[i] >= start : delta[i] > start;
        double S, dPdd;
        sp_pt pt;

        if (!touching || (c.q == 0.0 && delta[i] <= 0.0)) {
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            continue;
        }
        v = sp_invert(&c, delta[i], v, &pt);   /* warm start: data come in order */
        S = 2.0 * c.Estar * pt.a;
        dPdd = pt.dd > 0.0 ? pt.dP / pt.dd : LF_BIG;
        e->P = pt.P;
        e->a = pt.a;
        e->dP_ddelta = lf_capped(dPdd);
        /* at fixed a: d delta/dln w = -shift/2, dP/dln w = -S shift/2;
         * d delta/dln E* = shift/2, dP/dln E* = P1 - S shift/2 */
        e->dP_dlogw = lf_capped(-0.5 * S * pt.shift + 0.5 * dPdd * pt.shift);
        e->dP_dlogE = lf_capped(pt.P1 - 0.5 * S * pt.shift - 0.5 * dPdd * pt.shift);
        e->dP_dnu = 0.0;
    }
    return LF_OK;
}

static int
sp_pulloff(const lf_probe *probe, const lf_material *mat, lf_pulloff *out)
{
    sp_ctx c;
    sp_pt pt;

    sp_init(&c, probe, mat);
    out->c = 0.0;
    if (c.q == 0.0) {
        out->delta_detach = out->P_detach = out->a_detach = 0.0;
        out->delta_po = out->P_po = out->a_po = out->sigma_po = out->P_jump = 0.0;
        return LF_OK;
    }
    sp_curve(&c, c.v_det, &pt);
    out->delta_detach = pt.delta;
    out->P_detach = pt.P;
    out->a_detach = pt.a;
    sp_curve(&c, sp_root(&c, 0, 1.5 * c.q), &pt);
    out->delta_po = pt.delta;
    out->P_po = pt.P;
    out->a_po = pt.a;
    out->sigma_po = -pt.P / (M_PI * pt.a * pt.a);
    sp_curve(&c, sp_root(&c, 1, c.q), &pt);
    out->P_jump = pt.P;
    return LF_OK;
}

static int
hs_eval(void *state, const lf_probe *probe, const lf_material *mat,
        lf_branch branch, size_t n, const double *delta, lf_eval *out)
{
    const hs_state *st = state;
    const int load = branch == LF_BRANCH_LOAD;
    hs_ctx c;
    size_t i;
    double a_prev = NAN, start;   /* warm start of the direct path: data come in order */

    if (probe->tip == LF_TIP_SPHERE)
        return sp_eval(probe, mat, branch, n, delta, out);
    if (hs_init(&c, st, probe, mat) != LF_OK)
        return LF_EINVAL;
    start = load ? fmax(0.0, c.delta_det) : c.delta_det;
    if (c.scaled) {
        /* the powers of the usual probes by multiplications */
        switch (st->tab->n2k) {
        case 3: points_scaled(&c, st->tab, 3, load, start, n, delta, out); break;
        case 4: points_scaled(&c, st->tab, 4, load, start, n, delta, out); break;
        case 6: points_scaled(&c, st->tab, 6, load, start, n, delta, out); break;
        case 8: points_scaled(&c, st->tab, 8, load, start, n, delta, out); break;
        default: points_scaled(&c, st->tab, st->tab->n2k, load, start, n, delta, out); break;
        }
        return LF_OK;
    }
    for (i = 0; i < n; i++) {
        lf_eval *e = &out[i];
        int touching = load ? delta[i] >= start : delta[i] > start;

        if (!touching || (c.q == 0.0 && delta[i] <= 0.0))
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
        else if (c.q == 0.0)
            point_hertz(&c, delta[i], e);
        else
            point_direct(&c, delta[i], &a_prev, e);
    }
    return LF_OK;
}

static int
hs_pulloff(void *state, const lf_probe *probe, const lf_material *mat,
           lf_pulloff *out)
{
    hs_ctx c;
    double d, dd, P, dP, sh, P1, a_c, a_0;

    if (probe->tip == LF_TIP_SPHERE)
        return sp_pulloff(probe, mat, out);
    if (hs_init(&c, state, probe, mat) != LF_OK)
        return LF_EINVAL;
    out->c = 0.0;
    if (c.q == 0.0) {
        out->delta_detach = out->P_detach = out->a_detach = 0.0;
        out->delta_po = out->P_po = out->a_po = out->sigma_po = out->P_jump = 0.0;
        return LF_OK;
    }
    hs_curve(&c, c.a_det, &d, &dd, &P, &dP, &sh, &P1);
    out->delta_detach = d;
    out->P_detach = P;
    out->a_detach = c.a_det;
    a_c = pow(3.0 * c.q / (2.0 * c.k * c.A), 1.0 / (c.k - 0.5));
    hs_curve(&c, a_c, &d, &dd, &P, &dP, &sh, &P1);
    out->delta_po = d;
    out->P_po = P;
    out->a_po = a_c;
    out->sigma_po = -P / (M_PI * a_c * a_c);
    /* delta = 0 where A a^k = q a^(1/2): a = a_s */
    a_0 = pow(c.q / c.A, 1.0 / (c.k - 0.5));
    hs_curve(&c, a_0, &d, &dd, &P, &dP, &sh, &P1);
    out->P_jump = P;
    return LF_OK;
}

static int
hs_alloc(void **state, const lf_probe *probe, lf_error *err)
{
    hs_state *st;

    *state = NULL;
    if (!(probe->k > 0.5))
        return lf_fail(err, LF_EINVAL,
                       "half-space JKR needs k > 1/2 (got %g): no stable branch", probe->k);
    if ((st = malloc(sizeof *st)) == NULL || (st->tab = table_get(probe->k)) == NULL) {
        free(st);
        return lf_fail(err, LF_ENOMEM, "out of memory (half-space model)");
    }
    st->A = A_of(probe, &st->lnA);
    *state = st;
    return LF_OK;
}

static void
hs_free(void *state)
{
    free(state);
}

const lf_model_type lf_model_halfspace = {
    "halfspace",
    "elastic half-space JKR for a power-law punch (Borodich et al. 2014)",
    hs_alloc,
    hs_free,
    hs_eval,
    hs_pulloff,
    1, LF_SCOPE_HALFSPACE, 0.5, 0, NULL, 0.0
};

/* ---- for tests ----------------------------------------------------------- */

int
lf_halfspace_invert(double k, double t, double *r_fast, double *r_precise)
{
    const hs_table *tb;
    double v;

    if (!(k > 0.5))
        return LF_EINVAL;
    if ((tb = table_get(k)) == NULL)
        return LF_ENOMEM;
    *r_fast = r_of(tb, t, &v);
    *r_precise = tb->r_det + solve_y(tb, t - tb->D_det, 0.0, NULL);
    return LF_OK;
}

int
lf_halfspace_table_error(double k, double *interp, double *final)
{
    static const double frac[] = { 0.125, 0.3, 0.5, 0.7, 0.875 };
    const hs_table *tb;
    size_t i, j;

    *interp = *final = 0.0;
    if (!(k > 0.5))
        return LF_EINVAL;
    if ((tb = table_get(k)) == NULL)
        return LF_ENOMEM;
    for (i = 0; i + 1 < NNODE; i++) {
        double s0 = lf_double((BASE + i) << (52 - MB)), s1 = lf_double((BASE + i + 1) << (52 - MB));
        for (j = 0; j < sizeof frac / sizeof frac[0]; j++) {
            /* s as the model sees it, from delta/delta_s = s + D_det */
            double t = s0 + frac[j] * (s1 - s0) + tb->D_det, s = t - tb->D_det;
            double y = solve_y(tb, s, tb->node[2 * i], NULL);
            double v, r0 = r_start(tb, s, t), r = r_of(tb, t, &v);
            *interp = fmax(*interp, fabs(r0 - tb->r_det - y) / y);
            *final = fmax(*final, fabs(r - tb->r_det - y) / (tb->r_det + y));
        }
    }
    return LF_OK;
}
