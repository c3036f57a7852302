/* hetero.c: how much curves of one material differ -- a random-effects
 * meta-analysis of single-curve estimates (lf_heterogeneity_of).
 *
 * Each curve's own fit gives an estimate y_i of a parameter with variance
 * v_i (its standard error squared), on the scale the fit estimates it: ln w
 * and ln E* (w and E* are fitted in logs, and a spot-to-spot spread of a
 * modulus is a relative one), nu itself.  The random-effects model (the
 * curves sample spots of one material) is
 *     y_i = mu + u_i + e_i,   u_i ~ N(0, tau^2),   e_i ~ N(0, v_i):
 *  - Cochran's Q = sum (y_i - y_FE)^2 / v_i with the fixed-effect mean
 *    y_FE; chi-square with n - 1 degrees of freedom when tau = 0, whence
 *    p_homogeneous; I^2 = (Q - (n - 1)) / Q, clipped at 0 (Higgins &
 *    Thompson 2002, Stat. Med. 21:1539);
 *  - tau^2 by restricted maximum likelihood, the fixed point
 *        tau^2 = sum w_i^2 ((y_i - mu)^2 - v_i) / sum w_i^2 + 1 / sum w_i,
 *    w_i = 1 / (v_i + tau^2), mu their weighted mean (Viechtbauer 2005, J.
 *    Educ. Behav. Stat. 30:261), from the DerSimonian-Laird value (1986,
 *    Control. Clin. Trials 7:177), clipped at 0;
 *  - its 95% interval by the Q-profile method (Viechtbauer 2007, Stat. Med.
 *    26:37): the generalised Q(tau^2) = sum (y_i - mu(tau^2))^2 /
 *    (v_i + tau^2) falls with tau^2; the interval is where it lies between
 *    the 2.5% and 97.5% points of chi-square on n - 1;
 *  - the population mean mu with the Hartung-Knapp-Sidik-Jonkman interval
 *    (Hartung & Knapp 2001, Stat. Med. 20:1771; Sidik & Jonkman 2002, Stat.
 *    Med. 21:3153): mu +- t(0.975, n - 1) sqrt(q / sum w_i), q = sum w_i
 *    (y_i - mu)^2 / (n - 1), which keeps its coverage with a dozen curves
 *    where the normal interval with the REML error does not.
 * In SI: exp(mu) for w and E* (the median of a log-normal population,
 * its geometric mean), tau = tau_rel exp(mu) (for a spread of 10% the SD of
 * E* itself to 0.5%).
 *
 * Probes on the one material (curves of different k, R, b or interface)
 * are compared as subgroups: the spread within the probes (a DerSimonian-
 * Laird tau^2 of the residual heterogeneity, common to all) weights each
 * probe's pooled estimate, and Q between the probes against chi-square on
 * (probes - 1) tests whether they differ by more than spots do.  A probe
 * that does is model error (the model sees the probes differently), not
 * spot-to-spot variation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "fit.h"

#define HET_ALPHA 0.05
#define HET_REML_ITER 500
#define HET_REML_TOL 1e-12
#define HET_ROOT_ITER 200

/* One parameter's random-effects analysis of k estimates. */
typedef struct {
    double Q, p, I2;
    double tau2, tau2_lo, tau2_hi;
    double mu, se;          /* HKSJ */
    double lo, hi;          /* mu's 95% interval */
} re_fit;

/* The mean of y weighted by 1 / (v + tau2); *sw the sum of the weights. */
static double
weighted_mean(size_t k, const double *y, const double *v, double tau2, double *sw)
{
    double s = 0.0, sy = 0.0;
    size_t i;

    for (i = 0; i < k; i++) {
        double w = 1.0 / (v[i] + tau2);
        s += w;
        sy += w * y[i];
    }
    *sw = s;
    return sy / s;
}

/* The generalised Q at tau2 (Viechtbauer 2007): falls as tau2 grows. */
static double
q_gen(size_t k, const double *y, const double *v, double tau2)
{
    double sw, mu = weighted_mean(k, y, v, tau2, &sw), q = 0.0;
    size_t i;

    for (i = 0; i < k; i++)
        q += (y[i] - mu) * (y[i] - mu) / (v[i] + tau2);
    return q;
}

/* The tau2 >= 0 where q_gen falls to target (q_gen(0) > target), by
 * bisection on a bracket doubled from `scale` (> 0). */
static double
q_root(size_t k, const double *y, const double *v, double target, double scale)
{
    double a = 0.0, b = scale;
    int i;

    for (i = 0; i < 200 && q_gen(k, y, v, b) > target; i++) {
        a = b;
        b *= 2.0;
    }
    for (i = 0; i < HET_ROOT_ITER && b - a > 1e-13 * b; i++) {
        double m = 0.5 * (a + b);
        if (q_gen(k, y, v, m) > target)
            a = m;
        else
            b = m;
    }
    return 0.5 * (a + b);
}

/* The restricted log-likelihood of tau2 (up to a constant; Viechtbauer
 * 2005): -1/2 [sum ln(v_i + tau2) + ln sum w_i + sum w_i (y_i - mu)^2]. */
static double
reml_loglik(size_t k, const double *y, const double *v, double t)
{
    double sw, mu = weighted_mean(k, y, v, t, &sw), s = log(sw);
    size_t i;
    for (i = 0; i < k; i++)
        s += log(v[i] + t) + (y[i] - mu) * (y[i] - mu) / (v[i] + t);
    return -0.5 * s;
}

/* The fixed point of the REML equation (see the top) from t; NaN when
 * none is reached. */
static double
reml_fixed_point(size_t k, const double *y, const double *v, double t)
{
    int it;

    for (it = 0; it < HET_REML_ITER; it++) {
        double sw = 0.0, sw2 = 0.0, num = 0.0, mu, next;
        size_t i;
        mu = weighted_mean(k, y, v, t, &sw);
        for (i = 0; i < k; i++) {
            double w = 1.0 / (v[i] + t);
            sw2 += w * w;
            num += w * w * ((y[i] - mu) * (y[i] - mu) - v[i]);
        }
        next = lf_fmax(num / sw2 + 1.0 / sw, 0.0);
        if (!isfinite(next))
            return NAN;
        if (fabs(next - t) <= HET_REML_TOL * lf_fmax(next, 1e-300) || next == t)
            return next;
        t = next;
    }
    return NAN;
}

/* tau2 by REML: the restricted likelihood's highest maximum.  With
 * variances far apart it can have two (a precise pair that agrees and an
 * imprecise curve far off: the fixed point from the DerSimonian-Laird
 * value dl then stops at the pair's spread, below the Q-profile interval),
 * so the likelihood is also scanned over tau2 = 0 and ten points a decade
 * from 1e-8 to 1e4 of scale (the largest squared departure or variance),
 * and the fixed point is started again from the scan's best where that
 * is higher (no fixed point from there: the scan's best itself). */
static double
reml_tau2(size_t k, const double *y, const double *v, double dl, double scale)
{
    double t = reml_fixed_point(k, y, v, dl), best = 0.0, lbest = reml_loglik(k, y, v, 0.0);
    int j;

    for (j = 0; j <= 120; j++) {
        double u = scale * pow(10.0, -8.0 + 0.1 * j), l = reml_loglik(k, y, v, u);
        if (l > lbest) {
            lbest = l;
            best = u;
        }
    }
    if (!isfinite(t) || lbest > reml_loglik(k, y, v, t) + 1e-9 * fabs(lbest)) {
        double u = best > 0.0 ? reml_fixed_point(k, y, v, best) : 0.0;
        t = isfinite(u) && reml_loglik(k, y, v, u) >= lbest ? u : best;
    }
    return t;
}

/* The analysis of k >= 2 estimates y with variances v (all > 0). */
static void
random_effects(size_t k, const double *y, const double *v, re_fit *o)
{
    const double df = (double) k - 1.0;
    double sw, sw2 = 0.0, mu_fe = weighted_mean(k, y, v, 0.0, &sw), dl, c, q, spread = 0.0;
    size_t i;

    o->Q = 0.0;
    for (i = 0; i < k; i++) {
        double w = 1.0 / v[i];
        o->Q += w * (y[i] - mu_fe) * (y[i] - mu_fe);
        sw2 += w * w;
        spread = lf_fmax(spread, fabs(y[i] - mu_fe));
    }
    o->p = gsl_cdf_chisq_Q(o->Q, df);
    o->I2 = o->Q > df ? (o->Q - df) / o->Q : 0.0;
    c = sw - sw2 / sw;
    dl = c > 0 ? lf_fmax((o->Q - df) / c, 0.0) : 0.0;
    {
        double vmax = 0.0;
        for (i = 0; i < k; i++)
            vmax = lf_fmax(vmax, v[i]);
        o->tau2 = reml_tau2(k, y, v, dl, lf_fmax(lf_fmax(spread * spread, vmax), 1e-300));
    }
    /* the Q-profile interval: Q(0) below a point means that end is 0 */
    {
        double hi_q = gsl_cdf_chisq_Qinv(0.025, df), lo_q = gsl_cdf_chisq_Qinv(0.975, df);
        double scale = lf_fmax(lf_fmax(o->tau2, spread * spread), 1e-300);
        o->tau2_lo = o->Q > hi_q ? q_root(k, y, v, hi_q, scale) : 0.0;
        o->tau2_hi = o->Q > lo_q ? q_root(k, y, v, lo_q, scale) : 0.0;
    }
    /* the population mean, Hartung-Knapp-Sidik-Jonkman */
    o->mu = weighted_mean(k, y, v, o->tau2, &sw);
    q = 0.0;
    for (i = 0; i < k; i++)
        q += (y[i] - o->mu) * (y[i] - o->mu) / (v[i] + o->tau2);
    q /= df;
    o->se = sqrt(q / sw);
    c = gsl_cdf_tdist_Pinv(0.975, df);
    o->lo = o->mu - c * o->se;
    o->hi = o->mu + c * o->se;
}

/* ------------------------------------------------------------------------
 * Per parameter.
 * --------------------------------------------------------------------- */

static void
population_clear(lf_population_estimate *e)
{
    e->n = 0;
    e->mean = e->sd = e->median = e->q1 = e->q3 = NAN;
    e->Q = e->p_homogeneous = e->I2 = NAN;
    e->tau_rel = e->tau_rel_ci95[0] = e->tau_rel_ci95[1] = NAN;
    e->tau = e->tau_ci95[0] = e->tau_ci95[1] = NAN;
    e->population_mean = e->population_ci95[0] = e->population_ci95[1] = NAN;
    e->why = NULL;
}

/* Estimate e's parameter m on the analysed scale into *y, and its
 * variance there: where the curve's 95% interval is known, from the half
 * of it that faces mu, over 1.96 (both halves averaged while mu is NaN:
 * a single curve's profile interval of w is often lopsided, and its
 * linear standard error then overstates how far its estimate is from the
 * others'), else from its standard error; 0 when the curve's own fit does
 * not determine it. */
static int
analysed(const lf_curve_estimate *e, int m, double mu, double *y, double *v)
{
    double x = e->value[m], se = e->se[m], lo = e->ci95[m][0], hi = e->ci95[m][1], sd;
    double dlo, dhi;

    if (!isfinite(x) || !isfinite(se) || !(se > 0) || (m != LF_MAT_NU && !(x > 0)))
        return 0;
    if (m == LF_MAT_NU) {
        *y = x;
        sd = se;
        dlo = (x - lo) / FIT_Z95;
        dhi = (hi - x) / FIT_Z95;
    } else {
        *y = log(x);
        sd = se / x;
        dlo = lo > 0 ? (*y - log(lo)) / FIT_Z95 : NAN;
        dhi = hi > 0 ? (log(hi) - *y) / FIT_Z95 : NAN;
    }
    if (dlo > 0 && dhi > 0 && isfinite(dlo) && isfinite(dhi))
        sd = isnan(mu) ? 0.5 * (dlo + dhi) : mu < *y ? dlo : dhi;
    *v = sd * sd;
    return 1;
}

/* The population centre of parameter m on the analysed scale (NaN when
 * none). */
static double
centre_of(const lf_population_estimate *e, int m)
{
    return m == LF_MAT_NU ? e->population_mean : log(e->population_mean);
}

/* The analysis of parameter m over the curves (y, v, si scratch of n). */
static void
population_one(size_t n, const lf_curve_estimate *each, int m, double *y, double *v,
               double *si, lf_population_estimate *e)
{
    size_t i, k = 0;
    re_fit o;
    int it;

    population_clear(e);
    for (i = 0; i < n; i++)
        if (analysed(&each[i], m, NAN, &y[k], &v[k]))
            si[k++] = each[i].value[m];
    e->n = k;
    if (k == 0) {
        e->why = "no curve determines it alone";
        return;
    }
    e->mean = gsl_stats_mean(si, 1, k);
    gsl_sort(si, 1, k);
    e->median = gsl_stats_median_from_sorted_data(si, 1, k);
    e->q1 = gsl_stats_quantile_from_sorted_data(si, 1, k, 0.25);
    e->q3 = gsl_stats_quantile_from_sorted_data(si, 1, k, 0.75);
    if (k < 2) {
        e->why = "one curve alone determines it: no spread to measure";
        return;
    }
    e->sd = gsl_stats_sd(si, 1, k);
    /* each curve's variance from the side of its interval facing the
     * centre: from both sides' mean, then the side of the centre found,
     * until the centre settles */
    random_effects(k, y, v, &o);
    for (it = 0; it < 8; it++) {
        double last = o.mu;
        for (i = 0, k = 0; i < n; i++)
            k += (size_t) analysed(&each[i], m, o.mu, &y[k], &v[k]);
        random_effects(k, y, v, &o);
        if (fabs(o.mu - last) <= 1e-12 * lf_fmax(fabs(last), 1e-300) + 1e-15)
            break;
    }
    e->Q = o.Q;
    e->p_homogeneous = o.p;
    e->I2 = o.I2;
    e->tau_rel = sqrt(o.tau2);
    e->tau_rel_ci95[0] = sqrt(o.tau2_lo);
    e->tau_rel_ci95[1] = sqrt(o.tau2_hi);
    if (m == LF_MAT_NU) {
        e->population_mean = o.mu;
        e->population_ci95[0] = lf_fmax(o.lo, 0.0);
        e->population_ci95[1] = lf_fmin(o.hi, 0.5);
        e->tau = e->tau_rel;
        e->tau_ci95[0] = e->tau_rel_ci95[0];
        e->tau_ci95[1] = e->tau_rel_ci95[1];
    } else {
        e->population_mean = exp(o.mu);
        e->population_ci95[0] = exp(o.lo);
        e->population_ci95[1] = exp(o.hi);
        e->tau = e->tau_rel * e->population_mean;
        e->tau_ci95[0] = e->tau_rel_ci95[0] * e->population_mean;
        e->tau_ci95[1] = e->tau_rel_ci95[1] * e->population_mean;
    }
}

/* ------------------------------------------------------------------------
 * All parameters together: a multivariate Cochran's Q.
 * --------------------------------------------------------------------- */

/* Invert the symmetric positive definite d x d matrix a (d <= 3) into ai;
 * 0 when it is not positive definite. */
static int
spd_inverse(int d, double a[3][3], double ai[3][3])
{
    double l[3][3] = { { 0 } }, li[3][3] = { { 0 } };
    int i, j, k;

    for (j = 0; j < d; j++) {
        double s = a[j][j];
        for (k = 0; k < j; k++)
            s -= l[j][k] * l[j][k];
        if (!(s > 0))
            return 0;
        l[j][j] = sqrt(s);
        for (i = j + 1; i < d; i++) {
            double t = a[i][j];
            for (k = 0; k < j; k++)
                t -= l[i][k] * l[j][k];
            l[i][j] = t / l[j][j];
        }
    }
    for (j = 0; j < d; j++) {        /* L^-1, lower triangular */
        li[j][j] = 1.0 / l[j][j];
        for (i = j + 1; i < d; i++) {
            double t = 0.0;
            for (k = j; k < i; k++)
                t -= l[i][k] * li[k][j];
            li[i][j] = t / l[i][i];
        }
    }
    for (i = 0; i < d; i++)          /* (L L^T)^-1 = L^-T L^-1 */
        for (j = 0; j < d; j++) {
            double t = 0.0;
            for (k = (i > j ? i : j); k < d; k++)
                t += li[k][i] * li[k][j];
            ai[i][j] = t;
        }
    return 1;
}

/* A curve's estimates of the parameters pm[0..d-1] on the analysed scale
 * and their covariance (w and E* correlated as the fit says; nu's
 * correlations are not kept: 0); 0 when it lacks one. */
static int
curve_vector(const lf_curve_estimate *e, const int *pm, int d, const double *mu, double y[3],
             double c[3][3])
{
    double sd[3];
    int a, b;

    for (a = 0; a < d; a++) {
        double v;
        if (!analysed(e, pm[a], mu[pm[a]], &y[a], &v))
            return 0;
        sd[a] = sqrt(v);
    }
    for (a = 0; a < d; a++)
        for (b = 0; b < d; b++) {
            double rho = a == b ? 1.0 : 0.0;
            if (a != b && ((pm[a] == LF_MAT_W && pm[b] == LF_MAT_E)
                           || (pm[a] == LF_MAT_E && pm[b] == LF_MAT_W)))
                rho = isfinite(e->corr_wE) ? lf_fmax(-0.999, lf_fmin(0.999, e->corr_wE)) : 0.0;
            c[a][b] = rho * sd[a] * sd[b];
        }
    return 1;
}

/* Q of the curves that determine every parameter with a population
 * estimate, about their fixed-effect mean (each weighted by its inverse
 * covariance); the parameters with the fewest curves are dropped until
 * two curves determine all that remain. */
static void
overall(size_t n, const lf_curve_estimate *each, lf_heterogeneity *h)
{
    const lf_population_estimate *pe[3] = { &h->w, &h->Estar, &h->nu };
    int pm[3], d = 0, a, b;
    size_t i, k;
    double centre[3];

    for (a = 0; a < 3; a++)
        centre[a] = centre_of(pe[a], a);
    h->Q = h->df = h->p_homogeneous = h->I2 = NAN;
    for (a = 0; a < 3; a++)
        if (pe[a]->n >= 2)
            pm[d++] = a;
    while (d > 0) {
        double sinv[3][3] = { { 0 } }, sy[3] = { 0 }, mu[3], s[3][3], y[3], c[3][3], ci[3][3];
        for (i = 0, k = 0; i < n; i++) {
            if (!curve_vector(&each[i], pm, d, centre, y, c) || !spd_inverse(d, c, ci))
                continue;
            k++;
            for (a = 0; a < d; a++)
                for (b = 0; b < d; b++) {
                    sinv[a][b] += ci[a][b];
                    sy[a] += ci[a][b] * y[b];
                }
        }
        if (k >= 2 && spd_inverse(d, sinv, s)) {
            double q = 0.0;
            for (a = 0; a < d; a++) {
                mu[a] = 0.0;
                for (b = 0; b < d; b++)
                    mu[a] += s[a][b] * sy[b];
            }
            for (i = 0; i < n; i++) {
                if (!curve_vector(&each[i], pm, d, centre, y, c) || !spd_inverse(d, c, ci))
                    continue;
                for (a = 0; a < d; a++)
                    for (b = 0; b < d; b++)
                        q += (y[a] - mu[a]) * ci[a][b] * (y[b] - mu[b]);
            }
            h->Q = q;
            h->df = (double) d * (double) (k - 1);
            h->p_homogeneous = gsl_cdf_chisq_Q(q, h->df);
            h->I2 = q > h->df ? (q - h->df) / q : 0.0;
            return;
        }
        /* drop the parameter fewest curves determine */
        for (a = 1, b = 0; a < d; a++)
            if (pe[pm[a]]->n < pe[pm[b]]->n)
                b = a;
        for (a = b; a + 1 < d; a++)
            pm[a] = pm[a + 1];
        d--;
    }
}

/* ------------------------------------------------------------------------
 * Probes.
 * --------------------------------------------------------------------- */

static int
same_probe(const lf_probe *a, const lf_probe *b)
{
    return a->k == b->k && a->R == b->R && a->b == b->b && a->base == b->base;
}

/* Compare the probes on parameter m: group[i] is curve i's probe (0..ng-1).
 * Returns the between-probe p (NaN when not testable) and fills the
 * departing probe's group, its difference from the others and z. */
static double
probes_one(size_t n, const lf_curve_estimate *each, const size_t *group, size_t ng, int m,
           double mu, double *mu_g, double *se_g, size_t *cnt, size_t *tested, size_t *dep,
           double *diff, double *z)
{
    double Qw = 0.0, Cw = 0.0, tau2, y, v, qb = 0.0, sb = 0.0, syb = 0.0, mub, best = -1.0;
    size_t g, i, dfw = 0, used = 0;

    for (g = 0; g < ng; g++) {
        double s1 = 0.0, s2 = 0.0, sy = 0.0, q = 0.0, mfe;
        cnt[g] = 0;
        for (i = 0; i < n; i++)
            if (group[i] == g && analysed(&each[i], m, mu, &y, &v)) {
                s1 += 1.0 / v;
                s2 += 1.0 / (v * v);
                sy += y / v;
                cnt[g]++;
            }
        if (cnt[g] < 2)
            continue;
        mfe = sy / s1;
        for (i = 0; i < n; i++)
            if (group[i] == g && analysed(&each[i], m, mu, &y, &v))
                q += (y - mfe) * (y - mfe) / v;
        Qw += q;
        Cw += s1 - s2 / s1;
        dfw += cnt[g] - 1;
    }
    *tested = 0;
    if (dfw == 0)
        return NAN;     /* one curve per probe: spots and probes not apart */
    tau2 = Cw > 0 ? lf_fmax((Qw - (double) dfw) / Cw, 0.0) : 0.0;
    for (g = 0; g < ng; g++) {
        double s = 0.0, sy = 0.0;
        if (cnt[g] == 0)
            continue;
        for (i = 0; i < n; i++)
            if (group[i] == g && analysed(&each[i], m, mu, &y, &v)) {
                s += 1.0 / (v + tau2);
                sy += y / (v + tau2);
            }
        mu_g[g] = sy / s;
        se_g[g] = sqrt(1.0 / s);
        sb += s;
        syb += sy;
        used++;
    }
    *tested = used;
    if (used < 2)
        return NAN;
    mub = syb / sb;
    for (g = 0; g < ng; g++)
        if (cnt[g] > 0)
            qb += (mu_g[g] - mub) * (mu_g[g] - mub) / (se_g[g] * se_g[g]);
    /* the probe furthest from the others pooled, in standard errors */
    for (g = 0; g < ng; g++) {
        double so = 0.0, syo = 0.0, mo, zg;
        size_t h;
        if (cnt[g] == 0)
            continue;
        for (h = 0; h < ng; h++)
            if (h != g && cnt[h] > 0) {
                so += 1.0 / (se_g[h] * se_g[h]);
                syo += mu_g[h] / (se_g[h] * se_g[h]);
            }
        mo = syo / so;
        zg = (mu_g[g] - mo) / sqrt(se_g[g] * se_g[g] + 1.0 / so);
        if (fabs(zg) > best) {
            best = fabs(zg);
            *dep = g;
            *z = zg;
            *diff = m == LF_MAT_NU ? mu_g[g] - mo : exp(mu_g[g] - mo) - 1.0;
        }
    }
    return gsl_cdf_chisq_Q(qb, (double) used - 1.0);
}

static void
probes(size_t n, const lf_curve_estimate *each, size_t *group, double *scratch, size_t *cnt,
       lf_heterogeneity *h)
{
    const lf_probe **rep = (const lf_probe **) (cnt + n);
    double *mu_g = scratch, *se_g = scratch + n, pmin = HUGE_VAL;
    size_t i, g, ng = 0, ntests = 0;
    int m;

    for (i = 0; i < n; i++) {
        for (g = 0; g < ng && !same_probe(rep[g], &each[i].probe); g++)
            ;
        if (g == ng)
            rep[ng++] = &each[i].probe;
        group[i] = g;
    }
    h->probes = ng;
    h->probes_tested = 0;
    h->probes_p = NAN;
    h->probes_disagree = 0;
    h->probe_param = -1;
    h->probe_diff = h->probe_z = NAN;
    memset(&h->probe_departs, 0, sizeof h->probe_departs);
    if (ng < 2)
        return;
    for (m = 0; m < 3; m++) {
        size_t tested, dep = 0;
        double diff = NAN, z = NAN;
        const lf_population_estimate *pe = m == LF_MAT_W ? &h->w : m == LF_MAT_E ? &h->Estar : &h->nu;
        double p = probes_one(n, each, group, ng, m, centre_of(pe, m), mu_g, se_g, cnt, &tested,
                              &dep, &diff, &z);
        if (!isfinite(p))
            continue;
        ntests++;
        h->probes_tested = tested > h->probes_tested ? tested : h->probes_tested;
        if (p < pmin) {
            pmin = p;
            h->probe_param = m;
            h->probe_departs = *rep[dep];
            h->probe_diff = diff;
            h->probe_z = z;
        }
    }
    if (ntests == 0)
        return;
    /* Bonferroni over the parameters compared */
    h->probes_p = lf_fmin(1.0, pmin * (double) ntests);
    h->probes_disagree = h->probes_p < HET_ALPHA;
}

/* ------------------------------------------------------------------------
 * The interface.
 * --------------------------------------------------------------------- */

int
lf_heterogeneity_of(size_t n, const lf_curve_estimate *each, lf_heterogeneity *out,
                    lf_error *err)
{
    double *scratch;
    size_t *idx;

    memset(out, 0, sizeof *out);
    population_clear(&out->w);
    population_clear(&out->Estar);
    population_clear(&out->nu);
    out->Q = out->df = out->p_homogeneous = out->I2 = NAN;
    out->probes_p = out->probe_diff = out->probe_z = NAN;
    out->probe_param = -1;
    if (n == 0)
        return LF_OK;
    if (each == NULL)
        return lf_fail(err, LF_EINVAL, "lf_heterogeneity_of: no estimates");
    scratch = malloc(3 * n * sizeof *scratch);
    /* groups, counts, then one probe pointer per group */
    idx = malloc(2 * n * sizeof *idx + n * sizeof(const lf_probe *));
    if (scratch == NULL || idx == NULL) {
        free(scratch);
        free(idx);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    out->curves = n;
    population_one(n, each, LF_MAT_W, scratch, scratch + n, scratch + 2 * n, &out->w);
    population_one(n, each, LF_MAT_E, scratch, scratch + n, scratch + 2 * n, &out->Estar);
    population_one(n, each, LF_MAT_NU, scratch, scratch + n, scratch + 2 * n, &out->nu);
    if (out->w.n < 2 && out->w.n < n && n >= 2)
        out->w.why = "not determined from single curves: too few of them determine it alone";
    if (out->Estar.n < 2 && out->Estar.n < n && n >= 2)
        out->Estar.why = "not determined from single curves: too few of them determine it alone";
    if (out->nu.n < 2 && out->nu.n < n && n >= 2)
        out->nu.why = "not determined from single curves: too few of them determine it alone";
    overall(n, each, out);
    probes(n, each, idx, scratch, idx + n, out);
    free(scratch);
    free(idx);
    return LF_OK;
}

void
lf_curve_estimate_of(const lf_fit_result *r, lf_curve_estimate *e)
{
    const lf_fit_estimate *p[3] = { &r->w, &r->Estar, &r->nu };
    int m, iw = -1, iE = -1;
    size_t i;

    for (m = 0; m < 3; m++) {
        int ok = p[m]->free && p[m]->determined && !p[m]->upper_bound_only;
        e->value[m] = ok ? p[m]->value : NAN;
        e->se[m] = ok ? p[m]->se : NAN;
        e->ci95[m][0] = ok ? p[m]->ci95[0] : NAN;
        e->ci95[m][1] = ok ? p[m]->ci95[1] : NAN;
    }
    for (i = 0; i < r->npar && r->names != NULL; i++) {
        if (strcmp(r->names[i], "w") == 0)
            iw = (int) i;
        else if (strcmp(r->names[i], "E*") == 0)
            iE = (int) i;
    }
    e->corr_wE = iw >= 0 && iE >= 0 && isfinite(e->value[0]) && isfinite(e->value[1])
                 ? lf_fit_result_corr(r, (size_t) iw, (size_t) iE) : NAN;
    if (r->ncurves > 0 && r->curves != NULL)
        e->probe = r->curves[0].probe;
    else
        memset(&e->probe, 0, sizeof e->probe);
}

void
lf_curve_estimate_none(lf_curve_estimate *e, const lf_probe *p)
{
    int m;

    for (m = 0; m < 3; m++)
        e->value[m] = e->se[m] = e->ci95[m][0] = e->ci95[m][1] = NAN;
    e->corr_wE = NAN;
    e->probe = *p;
}
