/* model_exact.c: adhesive (JKR) indentation of an elastic layer of any
 * thickness on a frictionless or bonded rigid base by a power-law punch,
 * from the Lebedev-Ufliand Fredholm equation (Lebedev & Ufliand 1958, PMM
 * 22:442; Hayes et al. 1972; Dimitriadis et al. 2002).
 *
 * With a = tau h, u = ln tau and the tabulated functions s, e, d, p of
 * exact.h:
 *   delta1 = A1 tau^k d,             A1 = B kappa_k h^k,  B = 1/(k R^(k-1))
 *   shift  = A2 sqrt(tau) / e,       A2 = sqrt(2 pi h w / E*)
 *   delta  = delta1 - shift          (JKR edge condition)
 *   P      = F1 tau^(k+1) p - S shift,  F1 = 2 E* B kappa_k h^(k+1) = 2 E* h A1,
 *   S      = 2 E* h tau s            (flat-punch stiffness)
 * Derivatives at fixed delta follow from those at fixed tau and
 * dP/ddelta = (dP/du)/(ddelta/du).
 *
 * One number per material.  Divided by A1 (delta) and F1 (P), the curve
 * depends on the material only through lambda = A2/A1:
 *   delta/A1 = tau^k d - lambda sqrt(tau)/e,
 *   P/F1     = tau^(k+1) p - lambda tau^(3/2) s/e,
 * so each of the conditions the branches need is "a function of tau alone
 * equals ln lambda":
 *   ddelta/du <= 0  iff  rho_d(u) = (k - 1/2) u + ln(d e) + ln((k + g_d)/(1/2 - g_e)) <= ln lambda
 *   dP/du >= 0      iff  rho_p(u) = (k - 1/2) u + ln(p e/s) + ln((k + 1 + g_p)/(3/2 + g_s - g_e)) >= ln lambda
 *   delta >= 0      iff  rho_0(u) = (k - 1/2) u + ln(d e) >= ln lambda
 * (g = d ln f/du).  The three are tabulated once per (tables, nu) on a
 * grid in u (a `mixdata`), so that finding the detachment, the pull-off
 * and the jump of any material is a look-up along the grid and a short
 * root-finding in one cell, not a scan of the curve.
 *
 * Branches.  delta(tau) has a minimum at small tau (the half-space
 * displacement-control instability, section 4): the unloading branch keeps
 * contact for tau above the largest tau where ddelta/dtau = 0 and ends
 * there (delta_detach, P_detach, a_detach); below delta_detach there is no
 * contact.  Loading makes contact at delta = 0 and jumps to the stable
 * branch at delta = 0 (force P_jump), as in the thin-layer model; for
 * delta >= 0 both branches coincide.  Without adhesion (w = 0) the branch
 * reaches tau -> 0 at delta = 0.
 *
 * Evaluation.  Each indentation is inverted by Newton in u from a cubic
 * extrapolation of the previous points (data come in order).  Once a
 * Newton step du is small (|du| <= 1e-6 and |du| <= 1e-5 of the scale
 * ddelta/du / (d2delta/du2) on which the slope changes) the root is taken
 * one second-order step away and the curve is carried there by its
 * second-order expansion instead of being evaluated again (the
 * interpolant's own second derivatives, exact.h): the root and the values
 * are then off by O(du^3) ~ 1e-18 relative, the derivative columns by
 * O(du^2) <= ~1e-10, far below the tables' own accuracy in derivatives
 * (3e-5, tests/test_exact.c).  On a frictionless layer, and on a bonded
 * one at a nu a fit holds, the curve at u comes from polynomials of its
 * four products, expanded once per table or held nu (prodpoly below),
 * instead of the tables' interpolation and four exponentials; the points
 * are then taken in two runs whose root searches the processor overlaps
 * (eval_runs).  A fit evaluates the same depths again and again with
 * parameters that move little: there (lf_model_eval_roots, with a buffer
 * per curve the fit owns) each point starts at its root of the curve's
 * last evaluation carried to second order by the moves of its depth and
 * of lambda, so that no point's start waits on another's root and most
 * points take the second-order finish at once (eval_from; there P's
 * products and tau are evaluated at the root itself).
 * lf_exact_eval_precise skips all this.
 */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "exact.h"

/* The fast path's points four at a time with AVX2 where the processor has
 * it (eval_from4, poly_finish4 below). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(LF_EXACT_NO_SIMD) && !defined(LF_NO_SIMD)
#define EXACT_AVX2 1
#endif

#define U_LOW (-60.0)   /* ln tau treated as contact vanishing */
#define U_HIGH 30.0

/* The grid of the per-material conditions: nodes u_i = GRID_U0 + i
 * GRID_HU over the tables' range (outside it the tables' limits are
 * smooth and monotone and are searched directly). */
#define GRID_N LF_EXACT_NMAX
#define GRID_U0 log(LF_EXACT_TAU_MIN)
#define GRID_HU ((log(LF_EXACT_TAU_MAX) - GRID_U0) / (GRID_N - 1))

/* Newton steps in u below STEP_TAYLOR, and below CURV_TAYLOR of the
 * scale on which ddelta/du changes, are finished to second order
 * (header). */
#define STEP_TAYLOR 1e-6
#define CURV_TAYLOR 1e-5

/* k from which rho_d rises with u below the tables (tau < TAU_MIN, where
 * it is (k - 1/2) u + O(tau)): there a single bracket decides. */
#define K_MONOTONE 0.6

enum { RHO_D, RHO_P, RHO_0 };

/* The tables of one (probe, nu), flattened, and the three conditions at
 * the grid's nodes. */
typedef struct prodpoly prodpoly;
typedef struct {
    double nu;                    /* as asked for (0 when frictionless) */
    const prodpoly *pp;           /* the products' polynomials (a frictionless
                                     table's shared mixdata, a bonded held
                                     nu's), or NULL */
    lf_exact_mix mix;
    lf_exact_premix premix;       /* bonded: the mix flattened for this nu */
    double r[3][GRID_N];          /* rho_d, rho_p, rho_0 at the nodes */
    double dr[3][GRID_N];         /* their u-derivatives */
    double dmin[GRID_N];          /* min of rho_d over the nodes from i up */
    int dmin_ok;                  /* 0: some rho_d is NaN (dmin unused) */
} mixdata;

/* A cache slot of the model object: immutable while READY; readers hold a
 * reference (counted in `word` with the state), a slot is rebuilt only
 * when READY with no reference (compare-and-swap to BUILDING). */
enum { SLOT_EMPTY = 0, SLOT_BUILDING = 1, SLOT_READY = 2 };
#define SLOT_STATE 3UL
#define SLOT_REF 4UL
typedef struct {
    _Atomic unsigned long word;   /* references * SLOT_REF + state */
    _Atomic uint64_t key;         /* bits of nu while READY */
    _Atomic unsigned long stamp;  /* last use, for replacement */
    mixdata d;
} slot;

/* Per-probe constants. */
typedef struct {
    double k, h, A1, Fc;          /* Fc = F1/E* = 2 h A1 */
    double ln_hR;                 /* a sphere (exact_sphere.c): ln(h/R); else NaN */
} probe_consts;

/* The largest a/R of a sphere's contact: the correction of the k = 2
 * tables (exact_sphere.c) holds to a few percent up to 0.9 R and has a
 * logarithmic singularity at R. */
#define SPHERE_RHO_MAX 0.99

/* The tables' ln f at u for a probe: the mix's, made a sphere's where
 * ln_hR is a number (exact_sphere.c). */
static void
mix_u(const lf_exact_mix *mx, double ln_hR, double u, double F[4], double g[4], double dg[4],
      double H[4], double dH[4])
{
    lf_exact_mix_eval_u(mx, u, F, g, dg, H, dH);
    if (!isnan(ln_hR))
        lf_exact_sphere_adjust(ln_hR, u, F, g, dg, H, dH);
}

/* The model object's state: the tables it uses, resolved from the process
 * store when the model is made (frictionless) or prepared for a nu range
 * (bonded), so that eval reads them with one atomic load and no lock.
 * Slot 0 holds the frictionless table, slot i + 1 the bonded nu node i
 * (-1 .. LF_EXACT_NY).  A table slot, once set, always holds the same
 * pointer (the store hands out one table per key).  Then the mixdata of
 * the last few nu in use (one for frictionless layers), filled on first
 * use by eval or pulloff without allocating. */
typedef struct {
    _Atomic(const lf_exact_table *) tab[LF_EXACT_NY + 2];
    _Atomic(const void *) held;   /* bonded: the mixdata of the nu last
                                     prepared alone (held_mixdata), or NULL */
    unsigned long long serial;    /* for the pull-off memo */
    probe_consts pc;
    _Atomic unsigned long clock;
    int nslot;
    slot slots[];
} exact_state;

#define BONDED_SLOTS 4

/* Serial numbers of model objects (never reused in a process). */
static _Atomic unsigned long long serials;

/* A pull-off is a pure function of the model object and the material: the
 * last ones each thread computed are kept, direct-mapped by the model's
 * serial number and the material's bits, so a repeated question is a
 * look-up with the same bits as the answer it repeats.  Callers that
 * search ask it again (fit/guess_model.c's root searches evaluate the
 * pull-off at the root they return once more). */
#define MEMO_N 128
typedef struct {
    unsigned long long serial;    /* 0: empty */
    uint64_t key[3];              /* w, E*, nu */
    lf_pulloff po;
} memo_entry;
static _Thread_local memo_entry memo[MEMO_N];

static memo_entry *
memo_slot(unsigned long long serial, const lf_material *m, uint64_t key[3])
{
    uint64_t h;

    memcpy(&key[0], &m->w, sizeof key[0]);
    memcpy(&key[1], &m->Estar, sizeof key[1]);
    memcpy(&key[2], &m->nu, sizeof key[2]);
    h = key[0] * 0x9E3779B97F4A7C15ULL ^ key[1] * 0xC2B2AE3D27D4EB4FULL ^ key[2]
        ^ serial * 0x165667B19E3779F9ULL;
    h ^= h >> 29;
    return &memo[h & (MEMO_N - 1)];
}

static void
probe_consts_of(const lf_probe *pr, probe_consts *pc)
{
    pc->k = pr->k;
    pc->h = pr->b;
    /* B kappa_k h^k; from logarithms where B alone leaves double precision
     * (a flat punch) */
    pc->A1 = lf_probe_prefactor(pr) * lf_exact_kappa(pr->k) * pow(pr->b, pr->k);
    if (!isnormal(pc->A1))
        pc->A1 = exp(lf_probe_log_prefactor(pr) + log(lf_exact_kappa(pr->k)) + pr->k * log(pr->b));
    pc->Fc = 2.0 * pr->b * pc->A1;
    pc->ln_hR = pr->tip == LF_TIP_SPHERE ? log(pr->b / pr->R) : NAN;
}

/* The table of nu node `node` (ignored when frictionless), from the state
 * or, the first time, from the store. */
static int
resolve(exact_state *st, const lf_probe *pr, int node, const lf_exact_table **out,
        lf_error *err)
{
    int bonded = pr->base == LF_BASE_BONDED, slot_i = bonded ? node + 1 : 0, status;

    *out = atomic_load_explicit(&st->tab[slot_i], memory_order_acquire);
    if (*out != NULL)
        return LF_OK;
    status = lf_exact_table_get(pr->k, pr->base, bonded ? lf_exact_nu_node(node) : 0.0, out, err);
    if (status == LF_OK)
        atomic_store_explicit(&st->tab[slot_i], *out, memory_order_release);
    return status;
}

/* The interpolation at nu from the model's tables. */
static int
state_mix(exact_state *st, const lf_probe *pr, double nu, lf_exact_mix *mx, lf_error *err)
{
    int m, status = lf_exact_mix_weights(mx, pr->base, nu, err);

    for (m = 0; m < mx->m && status == LF_OK; m++)
        status = resolve(st, pr, mx->node0 + m, &mx->t[m], err);
    return status;
}

/* The conditions of the header at u from the mix's ln f (F) and
 * d ln f/du (g).  A factor that changes sign makes the condition hold or
 * fail outright (+-INFINITY). */
static double
rho_of(int which, double k, double u, const double F[4], const double g[4])
{
    double num, den;

    switch (which) {
    case RHO_D:
        num = k + g[2];
        den = 0.5 - g[1];
        break;
    case RHO_P:
        num = k + 1.0 + g[3];
        den = 1.5 + g[0] - g[1];
        break;
    default:
        return (k - 0.5) * u + F[2] + F[1];
    }
    if (!(den > 0.0))
        return num > 0.0 ? INFINITY : -INFINITY;
    if (!(num > 0.0))
        return -INFINITY;
    return (k - 0.5) * u + (which == RHO_D ? F[2] + F[1] : F[3] - F[0] + F[1]) + log(num / den);
}

/* d rho/du from g and dg = dg/du (NAN where rho is infinite). */
static double
drho_of(int which, double k, const double g[4], const double dg[4])
{
    double base = k - 0.5 + (which == RHO_P ? g[3] - g[0] + g[1] : g[2] + g[1]);

    switch (which) {
    case RHO_D:
        if (!(k + g[2] > 0.0 && 0.5 - g[1] > 0.0))
            return NAN;
        return base + dg[2] / (k + g[2]) + dg[1] / (0.5 - g[1]);
    case RHO_P:
        if (!(k + 1.0 + g[3] > 0.0 && 1.5 + g[0] - g[1] > 0.0))
            return NAN;
        return base + dg[3] / (k + 1.0 + g[3]) - (dg[0] - dg[1]) / (1.5 + g[0] - g[1]);
    default:
        return base;
    }
}

/* Grids of conditions built in the process (lf_exact_conditions_built). */
static _Atomic unsigned long conditions_built;

unsigned long
lf_exact_conditions_built(void)
{
    return atomic_load_explicit(&conditions_built, memory_order_relaxed);
}

/* Fill md for nu (k the probe's): the tables from the state (or the store
 * when st is NULL), the flattened mix, the grid. */
static int
mixdata_build(mixdata *md, exact_state *st, const lf_probe *pr, double nu, lf_error *err)
{
    const double ln_hR = pr->tip == LF_TIP_SPHERE ? log(pr->b / pr->R) : NAN;
    const double u_top = isnan(ln_hR) ? INFINITY : log(SPHERE_RHO_MAX) - ln_hR;
    int i, w, status;

    atomic_fetch_add_explicit(&conditions_built, 1, memory_order_relaxed);
    md->nu = nu;
    md->pp = NULL;
    status = st != NULL ? state_mix(st, pr, nu, &md->mix, err)
                        : lf_exact_mix_init(&md->mix, pr->k, pr->base, nu, err);
    if (status != LF_OK)
        return status;
    lf_exact_premix_init(&md->premix, &md->mix);
    for (i = 0; i < GRID_N; i++) {
        double F[4], g[4], dg[4], u = GRID_U0 + GRID_HU * i;
        if (u >= u_top) {
            /* past a sphere's largest contact: delta, P rise there */
            for (w = 0; w < 3; w++) {
                md->r[w][i] = INFINITY;
                md->dr[w][i] = NAN;
            }
            continue;
        }
        mix_u(&md->mix, ln_hR, u, F, g, dg, NULL, NULL);
        for (w = 0; w < 3; w++) {
            md->r[w][i] = rho_of(w, pr->k, u, F, g);
            md->dr[w][i] = drho_of(w, pr->k, g, dg);
        }
    }
    md->dmin_ok = 1;
    for (i = GRID_N - 1; i >= 0; i--) {
        md->dmin_ok &= !isnan(md->r[RHO_D][i]);
        md->dmin[i] = i == GRID_N - 1 ? md->r[RHO_D][i] : fmin(md->r[RHO_D][i], md->dmin[i + 1]);
    }
    return LF_OK;
}


/* A READY slot of nu with a reference taken, or NULL. */
static slot *
slot_find(exact_state *st, double nu)
{
    uint64_t key = lf_bits(nu);
    int i;

    for (i = 0; i < st->nslot; i++) {
        slot *s = &st->slots[i];
        unsigned long w = atomic_load_explicit(&s->word, memory_order_acquire);
        while ((w & SLOT_STATE) == SLOT_READY
               && atomic_load_explicit(&s->key, memory_order_relaxed) == key) {
            if (atomic_compare_exchange_weak_explicit(&s->word, &w, w + SLOT_REF,
                                                      memory_order_acquire, memory_order_relaxed)) {
                /* the key cannot change while a reference is held */
                if (atomic_load_explicit(&s->key, memory_order_relaxed) == key) {
                    atomic_store_explicit(&s->stamp,
                                          atomic_fetch_add_explicit(&st->clock, 1, memory_order_relaxed),
                                          memory_order_relaxed);
                    return s;
                }
                atomic_fetch_sub_explicit(&s->word, SLOT_REF, memory_order_release);
                break;
            }
        }
    }
    return NULL;
}

/* A slot switched to BUILDING for the caller: an empty one, else the least
 * recently used one nobody reads; NULL when every slot is in use. */
static slot *
slot_claim(exact_state *st)
{
    slot *old = NULL;
    unsigned long best = 0;
    int i;

    for (i = 0; i < st->nslot; i++) {
        slot *s = &st->slots[i];
        unsigned long w = atomic_load_explicit(&s->word, memory_order_relaxed);
        if (w == SLOT_EMPTY
            && atomic_compare_exchange_strong_explicit(&s->word, &w, SLOT_BUILDING,
                                                       memory_order_acquire, memory_order_relaxed))
            return s;
        if (w == SLOT_READY) {
            unsigned long t = atomic_load_explicit(&s->stamp, memory_order_relaxed);
            if (old == NULL || t < best) {
                old = s;
                best = t;
            }
        }
    }
    if (old != NULL) {
        unsigned long w = SLOT_READY;
        if (atomic_compare_exchange_strong_explicit(&old->word, &w, SLOT_BUILDING,
                                                    memory_order_acquire, memory_order_relaxed))
            return old;
    }
    return NULL;
}

/* ---- the four products as polynomials (frictionless tables) ----------
 *
 * The curve at u = ln tau is made of four products of a power of tau and
 * tabulated functions, each exp(c(u)) with c a linear term plus sums of
 * the tables' ln f, which are cubics in u on each cell of the table:
 *   E_D = exp(k u + ln d)               delta1 = A1 E_D
 *   E_s = exp(u/2 - ln e)               shift  = A2 E_s
 *   E_S = exp(3u/2 + ln s - ln e)       S shift = Sc E_S
 *   E_P = exp((k + 1) u + ln p)         P1     = F1 E_P
 * None depends on the material, so for a frictionless table they are
 * expanded once (with the table's shared mixdata) on PP_SUB sub-cells of
 * each cell: the Taylor series of exp(c0 + c1 t + c2 t^2 + c3 t^3) about
 * the sub-cell's centre has the coefficients y_0 = e^c0,
 * n y_n = c1 y_(n-1) + 2 c2 y_(n-2) + 3 c3 y_(n-3) (from y' = c' y),
 * kept to degree PP_DEG.  With |t| <= h/(2 PP_SUB) ~ 0.003 and |c1| below
 * k + 2, the first term left out is below ((k + 2) 0.003)^7/7! ~ 1e-17 of
 * the product for k = 2 (1e-15 at k = 6, 6e-14 at k = 12): the curve and its first
 * two u-derivatives then cost a few multiplications a point instead of
 * the table's interpolation and four exponentials (the fast path only;
 * lf_exact_eval_precise keeps the exponentials, and tests/test_exact.c
 * holds the two to 1e-12). */
#define PP_SUB 16
#define PP_DEG 6             /* curve_poly's Estrin scheme is written for 6 */
#define PP_NC (PP_DEG + 1)
#define PP_NF 5              /* the four products and tau = e^u itself */

/* A sub-cell's coefficients, the four products side by side (index 4 n
 * + j for product j) so that the evaluation reads them in order: the
 * Taylor coefficients y_n (n = 0..PP_DEG), those of the first derivative
 * n y_n (n = 1..PP_DEG) and of the second, 2 y_2, 6 y_3 and y_4 (times
 * 12 in pp_d2; the series curve_poly cuts there); then the sub-cell's
 * centre and tau's y_n (its y_0 = e^centre next to the centre, which
 * point_from reads as a pair). */
#define PP_VAL 0
#define PP_D1 (PP_VAL + 4 * PP_NC)
#define PP_D2 (PP_D1 + 4 * PP_DEG)
#define PP_MID (PP_D2 + 4 * 3)
#define PP_TAU (PP_MID + 1)
#define PP_STRIDE (PP_TAU + PP_NC)
/* a bonded mix's: then d ln f_j/dnu (its table's cubic) at 4 n + j */
#define PP_NU PP_STRIDE
#define PP_STRIDE_NU (PP_NU + 16)

struct prodpoly {
    double u0, hs, inv_hs;   /* sub-cell q: [u0 + q hs, u0 + (q + 1) hs] */
    size_t nq;               /* sub-cells */
    size_t stride;           /* PP_STRIDE, or PP_STRIDE_NU for a bonded mix */
    double *c;               /* sub-cell q at c + stride q */
};

/* The one table whose cubics in u a mix evaluates inside the grid: a
 * frictionless table, or a bonded mix flattened for its nu. */
static const lf_exact_table *
mix_table(const lf_exact_mix *mx)
{
    return mx->pm != NULL ? &mx->pm->pre : mx->t[0];
}

/* The storage prodpoly_build needs for table t (beyond sizeof(mixdata)),
 * with room to align the coefficients to 16 bytes. */
static size_t
prodpoly_size(const lf_exact_table *t, int bonded)
{
    return sizeof(prodpoly) + 16
           + (t->n - 1) * PP_SUB * (bonded ? PP_STRIDE_NU : PP_STRIDE) * sizeof(double);
}

/* The constant third derivative on a table's cell of the cubic Hermite
 * interpolant with values F[0], F[NFUN] and slopes G[0], G[NFUN]. */
static double
cubic_d3(const double *F, const double *G, double h)
{
    return (12.0 * (F[0] - F[LF_EXACT_NFUN]) + 6.0 * h * (G[0] + G[LF_EXACT_NFUN])) / (h * h * h);
}

/* Build the polynomials of the mix mx (one frictionless table, or a
 * flattened bonded mix, then with its d ln f/dnu) into mem (prodpoly_size
 * bytes); returns them. */
static const prodpoly *
prodpoly_build(void *mem, const lf_exact_mix *mx, double k)
{
    const lf_exact_table *t = mix_table(mx), *nu = mx->pm != NULL ? &mx->pm->pre_nu : NULL;
    prodpoly *pp = mem;
    lf_exact_mix hm;
    size_t i, q, j, n;

    pp->c = (double *) (((uintptr_t) (pp + 1) + 15) & ~(uintptr_t) 15);
    pp->hs = t->h / PP_SUB;
    pp->inv_hs = 1.0 / pp->hs;
    pp->u0 = t->l0;
    pp->nq = (t->n - 1) * PP_SUB;
    pp->stride = nu != NULL ? PP_STRIDE_NU : PP_STRIDE;
    if (nu != NULL) {
        /* d ln f/dnu of a bonded mix: its flattened table alone */
        memset(&hm, 0, sizeof hm);
        hm.m = 1;
        hm.t[0] = nu;
        hm.wl[0] = 1.0;
    }
    for (i = 0; i + 1 < t->n; i++) {
        const double *Fa = t->F + LF_EXACT_NFUN * i, *Ga = t->G + LF_EXACT_NFUN * i;
        double F3[4], H3[4];
        /* the cell's constant third derivative of each ln f (and of each
         * d ln f/dnu) */
        for (j = 0; j < 4; j++) {
            F3[j] = cubic_d3(Fa + j, Ga + j, t->h);
            if (nu != NULL)
                H3[j] = cubic_d3(nu->F + LF_EXACT_NFUN * i + j, nu->G + LF_EXACT_NFUN * i + j, t->h);
        }
        for (q = 0; q < PP_SUB; q++) {
            const size_t qq = i * PP_SUB + q;
            const double u = t->l0 + (double) i * t->h + ((double) q + 0.5) * pp->hs;
            double F[4], g[4], dg[4], cc[PP_NF][4];
            lf_exact_mix_eval_u(mx, u, F, g, dg, NULL, NULL);
            /* c0 .. c3 of each exponent about u */
            cc[0][0] = k * u + F[2];               cc[0][1] = k + g[2];
            cc[0][2] = 0.5 * dg[2];                cc[0][3] = F3[2] / 6.0;
            cc[1][0] = 0.5 * u - F[1];             cc[1][1] = 0.5 - g[1];
            cc[1][2] = -0.5 * dg[1];               cc[1][3] = -F3[1] / 6.0;
            cc[2][0] = 1.5 * u + F[0] - F[1];      cc[2][1] = 1.5 + g[0] - g[1];
            cc[2][2] = 0.5 * (dg[0] - dg[1]);      cc[2][3] = (F3[0] - F3[1]) / 6.0;
            cc[3][0] = (k + 1.0) * u + F[3];       cc[3][1] = k + 1.0 + g[3];
            cc[3][2] = 0.5 * dg[3];                cc[3][3] = F3[3] / 6.0;
            cc[4][0] = u;                          cc[4][1] = 1.0;
            cc[4][2] = 0.0;                        cc[4][3] = 0.0;
            if (nu != NULL) {
                double H[4], gH[4], dgH[4], *out = pp->c + pp->stride * qq;
                lf_exact_mix_eval_u(&hm, u, H, gH, dgH, NULL, NULL);
                for (j = 0; j < 4; j++) {
                    out[PP_NU + j] = H[j];
                    out[PP_NU + 4 + j] = gH[j];
                    out[PP_NU + 8 + j] = 0.5 * dgH[j];
                    out[PP_NU + 12 + j] = H3[j] / 6.0;
                }
            }
            for (j = 0; j < PP_NF; j++) {
                double y[PP_NC], *out = pp->c + pp->stride * qq;
                y[0] = exp(cc[j][0]);
                for (n = 1; n < PP_NC; n++)
                    y[n] = (cc[j][1] * y[n - 1] + (n >= 2 ? 2.0 * cc[j][2] * y[n - 2] : 0.0)
                            + (n >= 3 ? 3.0 * cc[j][3] * y[n - 3] : 0.0)) / (double) n;
                if (j == 4) {
                    for (n = 0; n < PP_NC; n++)
                        out[PP_TAU + n] = y[n];
                    out[PP_MID] = pp->u0 + ((double) qq + 0.5) * pp->hs;
                    continue;
                }
                for (n = 0; n < PP_NC; n++)
                    out[PP_VAL + 4 * n + j] = y[n];
                for (n = 1; n < PP_NC; n++)
                    out[PP_D1 + 4 * (n - 1) + j] = (double) n * y[n];
                out[PP_D2 + j] = 2.0 * y[2];
                out[PP_D2 + 4 + j] = 6.0 * y[3];
                out[PP_D2 + 8 + j] = y[4];   /* times 12 t in pp_d2 */
            }
        }
    }
    return pp;
}

/* st's frictionless table (NULL: not resolved); its `derived` is the one
 * member written after it is published (table_mixdata). */
static lf_exact_table *
shared_table(exact_state *st)
{
    return (lf_exact_table *) atomic_load_explicit(&st->tab[0], memory_order_acquire);
}

/* The shared mixdata of st's frictionless table, NULL while there is
 * none. */
static const mixdata *
shared_mixdata(exact_state *st)
{
    lf_exact_table *t = shared_table(st);
    return t != NULL ? atomic_load_explicit(&t->derived, memory_order_acquire) : NULL;
}

/* A frictionless table's mixdata, shared by every model object of the
 * process that uses the table (it depends on the table alone): made by
 * the first, published in the table by compare-and-swap (a table is
 * otherwise immutable; `derived` is the one member written after it is
 * published, once, from NULL).  NULL when out of memory: the model's own
 * slot is used then. */
static const mixdata *
table_mixdata(exact_state *st, const lf_probe *pr, lf_error *err)
{
    lf_exact_table *t = shared_table(st);
    const mixdata *ready;
    void *md, *none = NULL;

    if (t == NULL)
        return NULL;
    if ((ready = shared_mixdata(st)) != NULL)
        return ready;
    if ((md = malloc(sizeof(mixdata) + prodpoly_size(t, 0))) == NULL)
        return NULL;
    if (mixdata_build(md, st, pr, 0.0, err) != LF_OK) {
        free(md);
        return NULL;
    }
    ((mixdata *) md)->pp = prodpoly_build((char *) md + sizeof(mixdata), &((mixdata *) md)->mix,
                                          pr->k);
    if (!atomic_compare_exchange_strong_explicit(&t->derived, &none, md, memory_order_acq_rel,
                                                 memory_order_acquire)) {
        free(md);           /* another model object's came first */
        md = none;
    }
    return md;
}

/* ---- a bonded layer at a held nu ----------------------------------
 *
 * A fit that holds nu prepares its models for that nu alone (fit/), and
 * then evaluates them many times there: the mixdata of that nu is built
 * with its products' polynomials, as a frictionless table's (about 1.3
 * MB and 1 ms), once per process: a list on the `derived` member of the
 * nu's first node table (unused otherwise by bonded tables; a block's
 * first member is its link, which lf_exact_table_free follows).  Built
 * the second time a nu is prepared (a map's second curve, a fit's
 * second start), so that a nu held once (a profile's refits at many nu)
 * costs a small note and no build.  Models are also prepared at a free
 * nu's current value (fit/choose.c), so the process builds at most
 * HELD_MAX in all (about 10 MB and 10 ms; beyond, today's path), and
 * notes at most HELD_NOTES nu per node table. */
#define HELD_MAX 8
#define HELD_NOTES 64

/* Held nu built in the process (never decremented: after
 * lf_exact_cache_clear, tests only, fewer can be built). */
static _Atomic int held_built;

typedef struct held_note held_note;
struct held_note {
    held_note *next;     /* first member (exact.h) */
    uint64_t key;        /* bits of nu */
    int full;            /* a held_md (else a note alone) */
};
typedef struct {
    held_note note;
    mixdata md;          /* then its polynomials */
} held_md;

/* Publish h at the head of t's list (a nu pushed twice by two threads at
 * once is harmless: the same data, the first found is used). */
static void
held_push(lf_exact_table *t, held_note *h)
{
    void *old = atomic_load_explicit(&t->derived, memory_order_acquire);

    do
        h->next = old;
    while (!atomic_compare_exchange_weak_explicit(&t->derived, &old, h, memory_order_acq_rel,
                                                  memory_order_acquire));
}

static const mixdata *
held_mixdata(exact_state *st, const lf_probe *pr, double nu)
{
    lf_exact_mix mx;
    lf_exact_table *t0;
    held_note *n;
    held_md *h;
    const uint64_t key = lf_bits(nu);
    int notes = 0, seen = 0;

    if (pr->tip == LF_TIP_SPHERE || state_mix(st, pr, nu, &mx, NULL) != LF_OK)
        return NULL;
    t0 = (lf_exact_table *) mx.t[0];
    for (n = atomic_load_explicit(&t0->derived, memory_order_acquire); n != NULL; n = n->next) {
        if (n->full && n->key == key)
            return &((held_md *) n)->md;
        seen |= n->key == key;
        notes += !n->full;
    }
    if (!seen) {
        if (notes < HELD_NOTES && (n = malloc(sizeof *n)) != NULL) {
            n->key = key;
            n->full = 0;
            held_push(t0, n);
        }
        return NULL;
    }
    if (atomic_fetch_add_explicit(&held_built, 1, memory_order_relaxed) >= HELD_MAX)
        return NULL;
    h = malloc(sizeof *h + prodpoly_size(t0, 1));
    if (h == NULL || mixdata_build(&h->md, st, pr, nu, NULL) != LF_OK || h->md.mix.pm == NULL
        || mix_table(&h->md.mix)->n != t0->n) {
        free(h);
        atomic_fetch_sub_explicit(&held_built, 1, memory_order_relaxed);
        return NULL;
    }
    h->note.key = key;
    h->note.full = 1;
    h->md.pp = prodpoly_build(h + 1, &h->md.mix, pr->k);
    held_push(t0, &h->note);
    return &h->md;
}

/* The mixdata of nu for one call: a frictionless table's shared one, from
 * a slot of the state (*held then holds a reference, released by
 * mixdata_done), built into a fresh slot, or, with no state or no free
 * slot, built into *local. */
static int
mixdata_get(exact_state *st, const lf_probe *pr, double nu, mixdata *local,
            const mixdata **out, slot **held, lf_error *err)
{
    slot *s;
    int status;

    *held = NULL;
    if (pr->base == LF_BASE_BONDED && st != NULL) {
        const mixdata *hm = atomic_load_explicit(&st->held, memory_order_acquire);
        if (hm != NULL && lf_bits(hm->nu) == lf_bits(nu)) {
            *out = hm;
            return LF_OK;
        }
    } else if (pr->base != LF_BASE_BONDED) {
        nu = 0.0;
        /* a frictionless table's shared mixdata is a power law's: a
         * sphere's conditions depend on its R/h too, kept in its slot */
        if (st != NULL && pr->tip != LF_TIP_SPHERE && (*out = shared_mixdata(st)) != NULL)
            return LF_OK;
    }
    if (st != NULL) {
        if ((s = slot_find(st, nu)) != NULL) {
            *held = s;
            *out = &s->d;
            return LF_OK;
        }
        if ((s = slot_claim(st)) != NULL) {
            status = mixdata_build(&s->d, st, pr, nu, err);
            if (status != LF_OK) {
                atomic_store_explicit(&s->word, SLOT_EMPTY, memory_order_release);
                return status;
            }
            atomic_store_explicit(&s->key, lf_bits(nu), memory_order_relaxed);
            atomic_store_explicit(&s->stamp,
                                  atomic_fetch_add_explicit(&st->clock, 1, memory_order_relaxed),
                                  memory_order_relaxed);
            atomic_store_explicit(&s->word, SLOT_READY + SLOT_REF, memory_order_release);
            *held = s;
            *out = &s->d;
            return LF_OK;
        }
    }
    status = mixdata_build(local, st, pr, nu, err);
    *out = local;
    return status;
}

static void
mixdata_done(slot *held)
{
    if (held != NULL)
        atomic_fetch_sub_explicit(&held->word, SLOT_REF, memory_order_release);
}

/* The curve at ln tau = u: delta, P, their u-derivatives, and the parts at
 * fixed tau needed for the Jacobian. */
typedef struct {
    double delta, P, dd, dP;           /* d/du */
    double shift, Ssh, P1;             /* adhesive shift, S shift, P1 */
    double gsh, gSsh, gP1;             /* their d ln/du */
    double ddelta_nu, dP_nu;           /* d/dnu at fixed tau */
    /* second order (curve_from with dg, curve_poly): d/du of dd, dP,
     * ddelta_nu, dP_nu; the first and second u-derivatives of shift, Ssh
     * and P1 */
    double d2, P2, ddelta_nu_u, dP_nu_u;
    double shift1, shift2, Ssh1, Ssh2, P11, P12;
    double tau;                        /* e^u, from curve_poly (else NAN) */
    double idd;                        /* 1/dd, from invert */
} exact_pt;

/* The mix at one u: ln f, g = d ln f/du, dg = dg/du. */
typedef struct {
    double u, F[4], g[4], dg[4];
} mixval;

/* Everything one (probe, material) pair needs. */
typedef struct {
    const lf_exact_mix *mx;
    const mixdata *md;    /* the grid of the conditions (NULL: none) */
    const prodpoly *pp;   /* the products' polynomials, or NULL */
    double k, h;
    double A1, A2, F1, Sc;  /* Sc = 2 E* h A2: S shift = Sc tau^(3/2) s/e */
    double L;             /* ln lambda = ln (A2/A1) */
    double ln_hR;         /* a sphere: ln(h/R) (mix_u); else NaN */
    double u_top;         /* the largest ln tau: U_HIGH, or a sphere's at
                             SPHERE_RHO_MAX */
    double u_det;         /* ln tau at detachment, -INFINITY when none */
    double u_lo;          /* the stable branch's lowest ln tau: u_det, or
                             U_LOW when there is no detachment */
    double delta_det;
    exact_pt det;         /* the curve at u_det (when finite) */
    mixval vdet;          /* the mix near it: u_det = vdet.u + du_det */
    double du_det;
} exact_ctx;

/* Each product of a power of tau and a tabulated function is one
 * exponential of a sum of logarithms; the u-derivatives follow as value
 * times the sum of the logarithmic derivatives.  H: d ln f/dnu, or NULL;
 * dg (with dH when H is given): the second-order terms too, else NULL. */
static void
curve_from(const exact_ctx *c, double u, const double F[4], const double g[4],
           const double *dg, const double *H, const double *dH, exact_pt *o)
{
    double k = c->k, D1, gD1;

    o->tau = NAN;
    D1 = c->A1 * exp(k * u + F[2]);                    /* A1 tau^k d */
    o->shift = c->A2 * exp(0.5 * u - F[1]);            /* A2 sqrt(tau) / e */
    o->Ssh = c->Sc * exp(1.5 * u + F[0] - F[1]);       /* S shift */
    o->P1 = c->F1 * exp((k + 1.0) * u + F[3]);         /* F1 tau^(k+1) p */
    gD1 = k + g[2];
    o->gsh = 0.5 - g[1];
    o->gSsh = 1.5 + g[0] - g[1];
    o->gP1 = k + 1.0 + g[3];
    o->delta = D1 - o->shift;
    o->dd = D1 * gD1 - o->shift * o->gsh;
    o->P = o->P1 - o->Ssh;
    o->dP = o->P1 * o->gP1 - o->Ssh * o->gSsh;
    if (H != NULL) {
        o->ddelta_nu = D1 * H[2] + o->shift * H[1];
        o->dP_nu = o->P1 * H[3] - o->Ssh * (H[0] - H[1]);
    } else {
        o->ddelta_nu = o->dP_nu = 0.0;
    }
    if (dg != NULL) {
        /* (X e^G)'' = X (G'^2 + G'') for each product */
        o->shift1 = o->shift * o->gsh;
        o->shift2 = o->shift * (o->gsh * o->gsh - dg[1]);
        o->Ssh1 = o->Ssh * o->gSsh;
        o->Ssh2 = o->Ssh * (o->gSsh * o->gSsh + dg[0] - dg[1]);
        o->P11 = o->P1 * o->gP1;
        o->P12 = o->P1 * (o->gP1 * o->gP1 + dg[3]);
        o->d2 = D1 * (gD1 * gD1 + dg[2]) - o->shift2;
        o->P2 = o->P12 - o->Ssh2;
        if (H != NULL) {
            o->ddelta_nu_u = D1 * (gD1 * H[2] + dH[2]) + o->shift * (o->gsh * H[1] + dH[1]);
            o->dP_nu_u = o->P1 * (o->gP1 * H[3] + dH[3])
                         - o->Ssh * (o->gSsh * (H[0] - H[1]) + dH[0] - dH[1]);
        } else {
            o->ddelta_nu_u = o->dP_nu_u = 0.0;
        }
    }
}

static void
curve_at(const exact_ctx *c, double u, int want_nu, exact_pt *o)
{
    double F[4], g[4], H[4];

    mix_u(c->mx, c->ln_hR, u, F, g, NULL, want_nu ? H : NULL, NULL);
    curve_from(c, u, F, g, NULL, want_nu ? H : NULL, NULL, o);
}

/* The same with the second-order terms. */
static void
curve_at2(const exact_ctx *c, double u, int want_nu, exact_pt *o)
{
    double F[4], g[4], dg[4], H[4], dH[4];

    mix_u(c->mx, c->ln_hR, u, F, g, dg, want_nu ? H : NULL, want_nu ? dH : NULL);
    curve_from(c, u, F, g, dg, want_nu ? H : NULL, want_nu ? dH : NULL, o);
}

/* tau's series at t (Estrin's scheme: independent pairs of terms, fewer
 * dependent operations than Horner's). */
LF_KERNEL double
pp_tau(const double *a, double t, double t2, double t4)
{
    return (a[0] + a[1] * t) + t2 * (a[2] + a[3] * t) + t4 * ((a[4] + a[5] * t) + a[6] * t2);
}

/* e^t to degree 6 (|t| <= ~0.003: the first term left out ~1e-21), by
 * Estrin's scheme: tau at a root from the sub-cell's e^centre
 * (point_from). */
LF_KERNEL double
pp_exp(double t, double t2, double t4)
{
    return ((1.0 + t) + t2 * (1.0 / 2 + t * (1.0 / 6)))
           + t4 * ((1.0 / 24 + t * (1.0 / 120)) + t2 * (1.0 / 720));
}

/* Two products' value, first and second derivative at t side by side
 * (a at product 0 or 2 of the kind), by Estrin's scheme: the same
 * operations on both in one vector register (GCC/Clang vector
 * extensions; plain SSE2). */
typedef double pp_v2 __attribute__((vector_size(16)));

LF_KERNEL pp_v2
pp_ld(const double *a)
{
    pp_v2 v;
    memcpy(&v, a, sizeof v);
    return v;
}

LF_KERNEL pp_v2
pp_val2(const double *a, double t, double t2, double t4)
{
    return (pp_ld(a) + pp_ld(a + 4) * t) + t2 * (pp_ld(a + 8) + pp_ld(a + 12) * t)
           + t4 * ((pp_ld(a + 16) + pp_ld(a + 20) * t) + pp_ld(a + 24) * t2);
}

LF_KERNEL pp_v2
pp_d12(const double *a, double t, double t2, double t4)
{
    return (pp_ld(a) + pp_ld(a + 4) * t) + t2 * (pp_ld(a + 8) + pp_ld(a + 12) * t)
           + t4 * (pp_ld(a + 16) + pp_ld(a + 20) * t);
}

LF_KERNEL pp_v2
pp_d22(const double *a, double t)
{
    return pp_ld(a) + t * (pp_ld(a + 4) + t * 12.0 * pp_ld(a + 8));
}

/* curve_at2 from the products' polynomials (frictionless, no nu terms);
 * 0 when u lies outside them (then nothing is written).  Values and
 * first derivatives by Estrin's scheme (independent pairs of terms: fewer
 * dependent operations than Horner's); the second derivatives only scale
 * the last step of invert (du^2/2 <= 5e-13) and the first-order update
 * of the slopes there, so their series is cut after t^2, which leaves
 * ~((k + 2) |t|)^3/6 of them (1e-5 at k = 12, |t| <= 0.003). */
static inline int
curve_poly(const exact_ctx *c, double u, exact_pt *o)
{
    const prodpoly *pp = c->pp;
    const double x = (u - pp->u0) * pp->inv_hs;
    double y[4], y1[4], y2[4], t, t2, t4, tv;
    const double *a;
    int j;

    if (!(x >= 0.0 && x < (double) pp->nq))
        return 0;
    a = pp->c + pp->stride * (size_t) x;
    t = u - a[PP_MID];
    t2 = t * t;
    t4 = t2 * t2;
    for (j = 0; j < 4; j += 2) {
        const pp_v2 v = pp_val2(a + PP_VAL + j, t, t2, t4), v1 = pp_d12(a + PP_D1 + j, t, t2, t4);
        const pp_v2 v2 = pp_d22(a + PP_D2 + j, t);
        y[j] = v[0];
        y[j + 1] = v[1];
        y1[j] = v1[0];
        y1[j + 1] = v1[1];
        y2[j] = v2[0];
        y2[j + 1] = v2[1];
    }
    tv = pp_tau(a + PP_TAU, t, t2, t4);
    o->tau = tv;
    o->shift = c->A2 * y[1];
    o->shift1 = c->A2 * y1[1];
    o->shift2 = c->A2 * y2[1];
    o->Ssh = c->Sc * y[2];
    o->Ssh1 = c->Sc * y1[2];
    o->Ssh2 = c->Sc * y2[2];
    o->P1 = c->F1 * y[3];
    o->P11 = c->F1 * y1[3];
    o->P12 = c->F1 * y2[3];
    o->delta = c->A1 * y[0] - o->shift;
    o->dd = c->A1 * y1[0] - o->shift1;
    o->d2 = c->A1 * y2[0] - o->shift2;
    o->P = o->P1 - o->Ssh;
    o->dP = o->P11 - o->Ssh1;
    o->P2 = o->P12 - o->Ssh2;
    o->ddelta_nu = o->dP_nu = o->ddelta_nu_u = o->dP_nu_u = 0.0;
    return 1;
}

/* The curve carried from u to u + du to first order (|du| tiny): the
 * derivatives stay those at u. */
static void
curve_advance(exact_pt *o, double du)
{
    o->delta += o->dd * du;
    o->P += o->dP * du;
    o->shift *= 1.0 + o->gsh * du;
    o->Ssh *= 1.0 + o->gSsh * du;
    o->P1 *= 1.0 + o->gP1 * du;
}

/* The same to second order in du (a curve from curve_at2): values with
 * errors O(du^3), the derivatives O(du^2). */
static void
curve_advance2(exact_pt *o, double du)
{
    double h = 0.5 * du * du;

    o->delta += o->dd * du + o->d2 * h;
    o->P += o->dP * du + o->P2 * h;
    o->dd += o->d2 * du;
    o->dP += o->P2 * du;
    o->tau *= 1.0 + du + h;           /* e^du to O(du^3) */
    o->shift += o->shift1 * du + o->shift2 * h;
    o->Ssh += o->Ssh1 * du + o->Ssh2 * h;
    o->P1 += o->P11 * du + o->P12 * h;
    o->ddelta_nu += o->ddelta_nu_u * du;
    o->dP_nu += o->dP_nu_u * du;
}

/* rho (header) minus ln lambda at u. */
static double
cond_at(const exact_ctx *c, int which, double u)
{
    double F[4], g[4];

    if (u >= c->u_top)
        return INFINITY;     /* past a sphere's largest contact */
    mix_u(c->mx, c->ln_hR, u, F, g, NULL, NULL, NULL);
    return rho_of(which, c->k, u, F, g) - c->L;
}

/* The root of cond(which) in [lo, hi] (<= 0 at lo, > 0 at hi) by Newton
 * in u from u (bisection where a step leaves the bracket or the slope is
 * not positive).  *v receives the mix at the last point evaluated; the
 * root is v->u + *du, |*du| <= ROOT_TAYLOR: the last Newton step, which
 * leaves an error ~ du^2 and is applied to the curve to first order
 * (curve_advance) rather than evaluated. */
#define ROOT_TAYLOR 1e-7
static double
cond_newton(const exact_ctx *c, int which, double lo, double hi, double u, mixval *v,
            double *du)
{
    int i;

    for (i = 0; i < 200; i++) {
        double f, d, un;
        if (!(u > lo && u < hi))
            u = 0.5 * (lo + hi);
        if (u >= c->u_top)
            u = 0.5 * (lo + c->u_top);
        v->u = u;
        mix_u(c->mx, c->ln_hR, u, v->F, v->g, v->dg, NULL, NULL);
        f = rho_of(which, c->k, u, v->F, v->g) - c->L;
        d = drho_of(which, c->k, v->g, v->dg);
        if (f <= 0.0)
            lo = u;
        else
            hi = u;
        un = u - f / d;
        if (d > 0.0 && fabs(un - u) <= ROOT_TAYLOR) {
            *du = un - u;
            return un;
        }
        if (hi - lo <= 1e-14 * fmax(1.0, fabs(lo)))
            break;
        u = d > 0.0 && un > lo && un < hi ? un : 0.5 * (lo + hi);
    }
    *du = 0.0;
    return v->u;
}

/* A start for the root in grid cell [u_i, u_i+1] (values and slopes of
 * cond at both nodes): the zero of the cell's cubic Hermite model. */
static double
cell_start(const exact_ctx *c, int which, int i)
{
    const double *r = c->md->r[which], *dr = c->md->dr[which];
    double f0 = r[i] - c->L, f1 = r[i + 1] - c->L, s0 = dr[i] * GRID_HU, s1 = dr[i + 1] * GRID_HU;
    double t = f0 / (f0 - f1);
    int it;

    if (!(t >= 0.0 && t <= 1.0))
        t = 0.5;
    if (isfinite(s0) && isfinite(s1))
        for (it = 0; it < 2; it++) {
            double t2 = t * t, t3 = t2 * t;
            double p = (2.0 * t3 - 3.0 * t2 + 1.0) * f0 + (t3 - 2.0 * t2 + t) * s0
                       + (3.0 * t2 - 2.0 * t3) * f1 + (t3 - t2) * s1;
            double dp = 6.0 * (t2 - t) * (f0 - f1) + (3.0 * t2 - 4.0 * t + 1.0) * s0
                        + (3.0 * t2 - 2.0 * t) * s1;
            if (!(dp > 0.0))
                break;
            t = fmin(fmax(t - p / dp, 0.0), 1.0);
        }
    return GRID_U0 + GRID_HU * (i + t);
}

/* The regula falsi point of a bracket (its middle if that fails). */
static double
falsi(double lo, double hi, double flo, double fhi)
{
    double u = (lo * fhi - hi * flo) / (fhi - flo);
    return u > lo && u < hi ? u : 0.5 * (lo + hi);
}

/* From lo (f(lo) = *flo <= 0) up in doubling steps to the first u with
 * f > 0: the bracket [*lo, *hi].  0 when f stays <= 0 up to U_HIGH. */
static int
cond_up(const exact_ctx *c, int which, double *lo, double *flo, double *hi, double *fhi)
{
    double step = 0.25;

    for (;;) {
        *hi = fmin(*lo + step, c->u_top);
        *fhi = cond_at(c, which, *hi);
        if (*fhi > 0.0)
            return 1;
        if (*hi >= c->u_top)
            return 0;
        *lo = *hi;
        *flo = *fhi;
        step *= 2.0;
    }
}

/* The first crossing of cond(which) from <= 0 to > 0 above lo (where it
 * is flo <= 0): below the grid in steps of 0.25, then along the grid's
 * nodes, then beyond it.  Returns the root (U_HIGH when there is none)
 * with *v and *du as cond_newton's. */
static double
cond_first_above(const exact_ctx *c, int which, double lo, double flo, mixval *v, double *du)
{
    const double *r = c->md->r[which];
    double hi, fhi;
    int j;

    while (lo < GRID_U0) {
        hi = fmin(lo + 0.25, GRID_U0);
        fhi = hi == GRID_U0 ? r[0] - c->L : cond_at(c, which, hi);
        if (fhi > 0.0)
            return cond_newton(c, which, lo, hi, falsi(lo, hi, flo, fhi), v, du);
        lo = hi;
        flo = fhi;
    }
    for (j = (int) floor((lo - GRID_U0) / GRID_HU) + 1; j < GRID_N; j++) {
        double uj = GRID_U0 + GRID_HU * j;
        if (uj <= lo)
            continue;
        if (r[j] - c->L > 0.0)
            return cond_newton(c, which, lo, uj, cell_start(c, which, j - 1), v, du);
        lo = uj;
        flo = r[j] - c->L;
    }
    if (!cond_up(c, which, &lo, &flo, &hi, &fhi)) {
        v->u = c->u_top;
        mix_u(c->mx, c->ln_hR, c->u_top, v->F, v->g, v->dg, NULL, NULL);
        *du = 0.0;
        return c->u_top;
    }
    return cond_newton(c, which, lo, hi, falsi(lo, hi, flo, fhi), v, du);
}

/* The start of the stable branch: the largest u with ddelta/du = 0, from
 * the grid (down from its top), or beyond it.  c->vdet keeps the mix
 * there for the pull-off (c->u_det = vdet.u + du_det). */
static void
find_detach(exact_ctx *c)
{
    const double *r = c->md->r[RHO_D];
    double lo, hi, flo, fhi, start;
    int i;

    c->u_det = -INFINITY;
    c->delta_det = 0.0;
    if (c->A2 == 0.0)
        return;
    if (c->md->dmin_ok && !isnan(c->L)) {
        /* the largest node with rho_d <= ln lambda: the largest whose
         * minimum from there up is (that minimum rises with i), by
         * bisection */
        const double *m = c->md->dmin;
        int below = -1, above = GRID_N;   /* m[below] <= L < m[above] (ends unread) */
        while (above - below > 1) {
            const int mid = (below + above) / 2;
            if (m[mid] <= c->L)
                below = mid;
            else
                above = mid;
        }
        i = below;
    } else {
        for (i = GRID_N - 1; i >= 0 && r[i] - c->L > 0.0; i--)
            ;
    }
    if (i == GRID_N - 1) {
        /* delta falls with a at the grid's top: the end lies beyond */
        lo = GRID_U0 + GRID_HU * i;
        flo = r[i] - c->L;
        if (!cond_up(c, RHO_D, &lo, &flo, &hi, &fhi))
            lo = hi = c->u_top;
        start = falsi(lo, hi, flo, fhi);
    } else if (i >= 0) {
        lo = GRID_U0 + GRID_HU * i;
        hi = lo + GRID_HU;
        start = cell_start(c, RHO_D, i);
    } else {
        /* delta rises with a over the whole grid: below it, rho_d is
         * (k - 1/2) u + O(tau), monotone for k above 1/2 (one bracket),
         * searched down in steps of 0.25 otherwise */
        hi = GRID_U0;
        fhi = r[0] - c->L;
        if (c->k >= K_MONOTONE) {
            lo = U_LOW;
            flo = cond_at(c, RHO_D, lo);
            if (flo > 0.0)
                return;
        } else {
            for (lo = hi - 0.25; lo > U_LOW; lo -= 0.25) {
                flo = cond_at(c, RHO_D, lo);
                if (flo <= 0.0)
                    break;
                hi = lo;
                fhi = flo;
            }
            if (lo <= U_LOW)
                return; /* monotonic down to a -> 0 (k < 1/2) */
        }
        start = falsi(lo, hi, flo, fhi);
    }
    if (lo == hi) {
        c->vdet.u = lo;
        mix_u(c->mx, c->ln_hR, lo, c->vdet.F, c->vdet.g, c->vdet.dg, NULL, NULL);
        c->du_det = 0.0;
        c->u_det = lo;
    } else {
        c->u_det = cond_newton(c, RHO_D, lo, hi, start, &c->vdet, &c->du_det);
    }
    curve_from(c, c->vdet.u, c->vdet.F, c->vdet.g, NULL, NULL, NULL, &c->det);
    curve_advance(&c->det, c->du_det);
    c->delta_det = c->det.delta;
}

/* Fill c for a material from the mixdata md (its tables and its grid). */
static void
ctx_set(exact_ctx *c, const mixdata *md, const probe_consts *pc, const lf_material *m)
{
    c->md = md;
    c->mx = &md->mix;
    c->pp = md->pp;
    c->k = pc->k;
    c->h = pc->h;
    c->A1 = pc->A1;
    c->F1 = m->Estar * pc->Fc;
    c->A2 = sqrt(2.0 * M_PI * pc->h * m->w / m->Estar);
    c->Sc = 2.0 * m->Estar * pc->h * c->A2;
    c->L = log(c->A2 / c->A1);
    c->ln_hR = pc->ln_hR;
    c->u_top = isnan(pc->ln_hR) ? U_HIGH : log(SPHERE_RHO_MAX) - pc->ln_hR;
    find_detach(c);
    c->u_lo = isfinite(c->u_det) ? c->u_det : U_LOW;
}

/* st: the model's state, or NULL to take the tables from the store.  The
 * mixdata may land in *local (then c points into it); *held is released
 * with mixdata_done when the caller is finished with c. */
static int
ctx_init(exact_ctx *c, exact_state *st, const lf_probe *pr, const lf_material *m,
         mixdata *local, slot **held, lf_error *err)
{
    probe_consts pcl;
    const probe_consts *pc = &pcl;
    const mixdata *md;
    int status;

    *held = NULL;
    if (pr->base == LF_BASE_BONDED && m->nu > LF_EXACT_NU_MAX)
        return lf_fail(err, LF_EINVAL, "exact model: nu must be <= %g", LF_EXACT_NU_MAX);
    if ((status = mixdata_get(st, pr, m->nu, local, &md, held, err)) != LF_OK)
        return status;
    if (st != NULL)
        pc = &st->pc;
    else
        probe_consts_of(pr, &pcl);
    ctx_set(c, md, pc, m);
    return LF_OK;
}

/* ln tau on the stable branch where delta(tau) = target (> delta_det):
 * Newton in ln tau from `guess` (NAN: none), safeguarded by bisection on a
 * bracket [lo, hi] with delta(lo) < target <= delta(hi) (hi = U_HIGH until
 * a point above the target is seen: then steps of at most one e-fold).
 * *out receives the curve at the returned ln tau (with the nu derivatives
 * when want_nu) and out->idd = 1/dd there.  taylor: finish a step below
 * STEP_TAYLOR to second order (header) instead of evaluating once more. */
static double
invert(const exact_ctx *c, double target, double guess, int want_nu, int taylor, exact_pt *out)
{
    exact_pt pt;
    double lo = isfinite(c->u_det) ? c->u_det : U_LOW, hi = c->u_top, u, idd = NAN;
    int i;

    u = guess;
    if (!(u > lo && u < hi)) /* first guess from the half-space form */
        u = fmin(fmax(log(fmax(target - c->delta_det, 1e-300) / c->A1) / c->k, lo + 0.5), c->u_top);
    for (i = 0; i < 200; i++) {
        double g, un;
        if (taylor && !(c->pp != NULL && !want_nu && curve_poly(c, u, &pt)))
            curve_at2(c, u, want_nu, &pt);
        else if (!taylor)
            curve_at(c, u, want_nu, &pt);
        g = pt.delta - target;
        if (g > 0.0)
            hi = u;
        else
            lo = u;
        /* done at the rounding level of delta = A1 tau^k d - shift (the
         * two terms nearly cancel near detachment): chasing g further only
         * bisects rounding noise */
        idd = NAN;
        if (fabs(g) <= 1e-14 * (fabs(pt.delta + pt.shift) + fabs(pt.shift)))
            break;
        idd = 1.0 / pt.dd;
        un = pt.dd > 0.0 ? u - g * idd : NAN;
        if (!(un > lo && un < hi)) {
            un = hi < c->u_top ? 0.5 * (lo + hi) : fmin(lo + 1.0, c->u_top);
        } else if (taylor && fabs(un - u) <= STEP_TAYLOR
                   && fabs((un - u) * pt.d2) <= CURV_TAYLOR * pt.dd) {
            /* the second-order step (the Newton step corrected by the
             * curvature) and the curve carried there (header); 1/dd
             * follows dd by its series in e = d2 du/dd (|e| <= 1e-5,
             * error e^3) instead of another division */
            double du = un - u, e;
            du -= 0.5 * pt.d2 * du * du * idd;
            curve_advance2(&pt, du);
            e = pt.d2 * du * idd;
            idd *= 1.0 - e + e * e;
            u += du;
            break;
        }
        /* the next step is below the rounding of ln tau: the point at u
         * stands (its curve is at hand) */
        if (fabs(un - u) < 1e-13 || hi - lo < 1e-14)
            break;
        u = un;
    }
    *out = pt;
    out->idd = isnan(idd) ? 1.0 / pt.dd : idd;
    return u;
}

/* invert for the common case of the fast path on a frictionless layer
 * (c->pp), in two parts so that the points of independent runs can be
 * interleaved (eval_runs): poly_newton, Newton in u from a warm start on
 * delta's two products alone until the step is small enough to be
 * finished to second order; poly_finish, P's products and tau at that
 * point carried to the root, straight to the evaluation.  The same
 * arithmetic as invert with curve_poly, so the same bits. */
typedef struct {
    double target, u, lo, hi;          /* bracket as invert's */
    const double *a;                   /* the sub-cell's coefficients */
    double t, t2, t4;
    double shift, shift1, shift2, dd, d2, idd, du;
    double root, idd_root, dd_root;    /* u + du and the slope there */
} poly_step;

/* One Newton step of s: 1 when done (root at s->u + s->du, with
 * s->root, s->idd_root and s->dd_root set), 0 to step again from s->u, -1
 * where invert would leave the polynomials or bisect (then invert takes
 * over from the first start). */
LF_KERNEL int
poly_newton(const exact_ctx *c, poly_step *s)
{
    const prodpoly *pp = c->pp;
    const double x = (s->u - pp->u0) * pp->inv_hs, u = s->u;
    double delta, g, un;

    if (!(u > s->lo && u < s->hi) || !(x >= 0.0 && x < (double) pp->nq))
        return -1;
    s->a = pp->c + pp->stride * (size_t) x;
    s->t = u - s->a[PP_MID];
    s->t2 = s->t * s->t;
    s->t4 = s->t2 * s->t2;
    {
        const pp_v2 y = pp_val2(s->a + PP_VAL, s->t, s->t2, s->t4);
        const pp_v2 y1 = pp_d12(s->a + PP_D1, s->t, s->t2, s->t4);
        s->shift = c->A2 * y[1];
        s->shift1 = c->A2 * y1[1];
        delta = c->A1 * y[0] - s->shift;
        s->dd = c->A1 * y1[0] - s->shift1;
    }
    g = delta - s->target;
    s->du = 0.0;
    if (fabs(g) <= 1e-14 * (fabs(delta + s->shift) + fabs(s->shift))) {
        /* at the root already */
        s->idd = s->idd_root = 1.0 / s->dd;
        s->dd_root = s->dd;
        s->root = u;
        return 1;
    }
    if (g > 0.0)
        s->hi = u;
    else
        s->lo = u;
    s->idd = 1.0 / s->dd;
    un = s->dd > 0.0 ? u - g * s->idd : NAN;
    if (!(un > s->lo && un < s->hi))
        return -1;
    {
        const pp_v2 y2 = pp_d22(s->a + PP_D2, s->t);
        s->shift2 = c->A2 * y2[1];
        s->d2 = c->A1 * y2[0] - s->shift2;
    }
    if (fabs(un - u) <= STEP_TAYLOR && fabs((un - u) * s->d2) <= CURV_TAYLOR * s->dd) {
        /* invert's second-order finish; 1/dd carried by its series */
        double e;
        s->du = un - u;
        s->du -= 0.5 * s->d2 * s->du * s->du * s->idd;
        s->dd_root = s->dd + s->d2 * s->du;
        e = s->d2 * s->du * s->idd;
        s->idd_root = s->idd * (1.0 - e + e * e);
        s->root = u + s->du;
        return 1;
    }
    if (fabs(un - u) < 1e-13 || s->hi - s->lo < 1e-14)
        return -1;
    s->u = un;
    return 0;
}

/* The evaluation at a root from the products there: P, the contact
 * radius, the derivative columns (fill_point's), and on a bonded layer
 * d/dnu at fixed tau from the mix's series at tr = t + du in the sub-cell
 * a (curve_from's, with A1 tau^k d = target + shift there). */
LF_KERNEL void
poly_out(const exact_ctx *c, int bonded, const double *a, double tr, double target, double P,
         double tau, double P1, double Ssh, double shift, double dPdd, lf_eval *e)
{
    e->P = P;
    e->a = tau * c->h;
    e->dP_ddelta = lf_capped(dPdd);
    e->dP_dlogw = lf_capped(-0.5 * Ssh + dPdd * 0.5 * shift);
    e->dP_dlogE = lf_capped(P1 - 0.5 * Ssh - dPdd * 0.5 * shift);
    e->dP_dnu = 0.0;
    if (bonded) {
        const pp_v2 h01 = pp_ld(a + PP_NU) + tr * (pp_ld(a + PP_NU + 4) + tr * (pp_ld(a + PP_NU + 8)
                                                  + tr * pp_ld(a + PP_NU + 12)));
        const pp_v2 h23 = pp_ld(a + PP_NU + 2) + tr * (pp_ld(a + PP_NU + 6) + tr * (pp_ld(a + PP_NU + 10)
                                                      + tr * pp_ld(a + PP_NU + 14)));
        e->dP_dnu = lf_capped(P1 * h23[1] - Ssh * (h01[0] - h01[1])
                              - dPdd * ((target + shift) * h23[0] + shift * h01[1]));
    }
}

/* The evaluation at the root of a finished step (poly_newton 1): P's
 * products and tau at s->u carried to the root (curve_advance2), then
 * fill_point's. */
LF_KERNEL void
poly_finish(const exact_ctx *c, int bonded, const poly_step *s, lf_eval *e)
{
    const double *a = s->a, t = s->t, t2 = s->t2, t4 = s->t4, du = s->du;
    const pp_v2 y = pp_val2(a + PP_VAL + 2, t, t2, t4), y1 = pp_d12(a + PP_D1 + 2, t, t2, t4);
    double Ssh = c->Sc * y[0], Ssh1 = c->Sc * y1[0], P1 = c->F1 * y[1], P11 = c->F1 * y1[1];
    double tau = pp_tau(a + PP_TAU, t, t2, t4);
    double P = P1 - Ssh, dP = P11 - Ssh1, shift = s->shift, dPdd;

    if (du != 0.0) {
        const pp_v2 y2 = pp_d22(a + PP_D2 + 2, t);
        double Ssh2 = c->Sc * y2[0], P12 = c->F1 * y2[1];
        double P2 = P12 - Ssh2, h = 0.5 * du * du;
        P += dP * du + P2 * h;
        dP += P2 * du;
        tau *= 1.0 + du + h;
        shift += s->shift1 * du + s->shift2 * h;
        Ssh += Ssh1 * du + Ssh2 * h;
        P1 += P11 * du + P12 * h;
    }
    dPdd = dP * s->idd_root;
    poly_out(c, bonded, a, t + du, s->target, P, tau, P1, Ssh, shift, dPdd, e);
}

/* The evaluation at ln tau = u from the curve there. */
static void
fill_point(const exact_ctx *c, double u, const exact_pt *p, int bonded, lf_eval *e)
{
    double dPdd = p->dP * p->idd;

    if (!(p->dd > 0.0))
        dPdd = LF_BIG;
    e->P = p->P;
    e->a = (isnan(p->tau) ? exp(u) : p->tau) * c->h;
    e->dP_ddelta = lf_capped(dPdd);
    /* at fixed tau: d delta/dln w = -shift/2, dP/dln w = -S shift/2;
     * d delta/dln E = +shift/2, dP/dln E = P1 - S shift/2 */
    e->dP_dlogw = lf_capped(-0.5 * p->Ssh + dPdd * 0.5 * p->shift);
    e->dP_dlogE = lf_capped(p->P1 - 0.5 * p->Ssh - dPdd * 0.5 * p->shift);
    e->dP_dnu = bonded ? lf_capped(p->dP_nu - dPdd * p->ddelta_nu) : 0.0;
}

static int
exact_alloc(void **state, const lf_probe *probe, lf_error *err)
{
    int i, status, nslot = probe->base == LF_BASE_BONDED ? BONDED_SLOTS : 1;
    exact_state *st = calloc(1, sizeof *st + (size_t) nslot * sizeof(slot));
    const lf_exact_table *t;

    *state = NULL;
    if (st == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory (exact model)");
    for (i = 0; i < LF_EXACT_NY + 2; i++)
        atomic_init(&st->tab[i], NULL);
    atomic_init(&st->held, NULL);
    st->nslot = nslot;
    for (i = 0; i < nslot; i++) {
        atomic_init(&st->slots[i].word, SLOT_EMPTY);
        atomic_init(&st->slots[i].key, 0);
        atomic_init(&st->slots[i].stamp, 0);
    }
    atomic_init(&st->clock, 1);
    st->serial = atomic_fetch_add(&serials, 1) + 1;
    probe_consts_of(probe, &st->pc);
    /* the frictionless table now; bonded node tables when a nu range is
     * prepared (or first needed) */
    if (probe->base == LF_BASE_FRICTIONLESS) {
        if ((status = resolve(st, probe, 0, &t, err)) != LF_OK) {
            free(st);
            return status;
        }
        if (probe->tip != LF_TIP_SPHERE)
            (void) table_mixdata(st, probe, NULL);
    }
    *state = st;
    return LF_OK;
}

static int
exact_prepare(void *state, const lf_probe *probe, double nu_lo, double nu_hi, lf_error *err)
{
    lf_exact_mix lo, hi;
    const lf_exact_table *t;
    int i, status;

    if (probe->base != LF_BASE_BONDED)
        return LF_OK;
    nu_lo = fmax(nu_lo, 0.0);
    nu_hi = fmin(nu_hi, LF_EXACT_NU_MAX);
    if (!(nu_lo <= nu_hi))
        return lf_fail(err, LF_EINVAL, "the exact bonded model covers 0 <= nu <= %g",
                       LF_EXACT_NU_MAX);
    if ((status = lf_exact_mix_weights(&lo, probe->base, nu_lo, err)) != LF_OK
        || (status = lf_exact_mix_weights(&hi, probe->base, nu_hi, err)) != LF_OK)
        return status;
    for (i = lo.node0; i <= hi.node0 + 3; i++)
        if ((status = resolve(state, probe, i, &t, err)) != LF_OK)
            return status;
    if (nu_lo == nu_hi) {
        /* nu held: its mixdata with polynomials (NULL: today's path) */
        exact_state *st = state;
        atomic_store_explicit(&st->held, held_mixdata(st, probe, nu_lo), memory_order_release);
    }
    return LF_OK;
}

static void
exact_free(void *state)
{
    free(state);
}

/* The warm start of one run of points: data come in order; u(delta)
 * extrapolated by the cubic through the last two points with their
 * slopes du/ddelta. */
typedef struct {
    double d1, u1, s1, d2, u2, s2;
} warm;

LF_KERNEL double
warm_guess(const warm *w, double delta)
{
    double guess = NAN;

    if (isfinite(w->d2)) {
        double hd = delta - w->d2;
        guess = w->u2 + hd * w->s2;
        if (isfinite(w->d1) && w->d1 != w->d2) {
            /* Hermite cubic on [d1, d2] in t = (delta - d1)/H */
            double H = w->d2 - w->d1, t = (delta - w->d1) / H, t2 = t * t, t3 = t2 * t;
            guess = (2.0 * t3 - 3.0 * t2 + 1.0) * w->u1 + (t3 - 2.0 * t2 + t) * H * w->s1
                    + (3.0 * t2 - 2.0 * t3) * w->u2 + (t3 - t2) * H * w->s2;
        }
    }
    return guess;
}

LF_KERNEL void
warm_push(warm *w, double delta, double u, double idd)
{
    if (delta != w->d2) {
        w->d1 = w->d2; w->u1 = w->u2; w->s1 = w->s2;
        w->d2 = delta; w->u2 = u; w->s2 = idd;
    }
}

/* Whether a point at delta touches (else it is out of contact). */
LF_KERNEL int
touching(const exact_ctx *c, int load, double start, double delta)
{
    return (load ? delta >= start : delta > start) && (isfinite(c->u_det) || delta > 0.0);
}

/* What a curve's evaluation keeps of each point for the next
 * (lf_exact_eval_warm): the root u = ln tau (NAN: none), the indentation
 * it was for, 1/(ddelta/du), the adhesive shift and its u-derivative, and
 * d2delta/du2 there (0 where not at hand): delta(u, ln lambda) =
 * A1 tau^k d - shift with d shift/d ln lambda = shift at fixed u, so
 * these carry the root to second order in the moves of delta and of
 * ln lambda (root_start). */
typedef struct {
    double u, delta, idd, shift, shift1, d2;
} root_rec;

LF_KERNEL void
root_put(root_rec *r, double u, double delta, double idd, double shift, double shift1, double d2)
{
    r->u = u;
    r->delta = delta;
    r->idd = idd;
    r->shift = shift;
    r->shift1 = shift1;
    r->d2 = d2;
}

/* The start of a point at indentation delta from its record, ln lambda
 * having moved by dL: the root of the second-order expansion of delta
 * about the record's, by one fixed-point step from the first-order move
 * (the error is of third order in the moves). */
LF_KERNEL double
root_start(const root_rec *r, double delta, double dL)
{
    const double du1 = (delta - r->delta + r->shift * dL) * r->idd;

    return r->u + du1
           - r->idd * (0.5 * r->d2 * du1 * du1 - r->shift1 * du1 * dL - 0.5 * r->shift * dL * dL);
}

/* One point of eval_points from guess (NAN: none) with invert, the warm
 * start w updated; LF_EINVAL past a sphere's largest contact. */
static int
eval_point(const exact_ctx *c, int bonded, int fast, double delta, double guess, lf_eval *e,
           warm *w, root_rec *ro)
{
    exact_pt pt;
    double u = invert(c, delta, guess, bonded, fast, &pt);

    if (u >= c->u_top && pt.delta < delta - 1e-9 * fabs(delta))
        return LF_EINVAL;
    fill_point(c, u, &pt, bonded, e);
    if (pt.dd > 0.0)
        warm_push(w, delta, u, pt.idd);
    if (ro != NULL)
        root_put(ro, pt.dd > 0.0 ? u : NAN, delta, pt.idd, pt.shift, pt.shift1, pt.d2);
    return LF_OK;
}

/* The fast path on a frictionless layer (c->pp).  Each point's warm
 * start depends on the roots before it: a chain of dependent operations
 * (a Newton step's evaluation and division), which the processor runs one
 * after the other.  So the points are cut into NRUN runs of consecutive
 * points (each with its warm start, at least RUN_MIN points long), whose
 * chains it overlaps, and taken in chunks of CHUNK points per run in two
 * passes: first the roots, the runs' Newton steps side by side (delta's
 * products only), then P's products and the evaluations (independent
 * points). */
#define NRUN 2
#define RUN_MIN 32
#define CHUNK 16

#ifdef EXACT_AVX2
__attribute__((target("avx2"))) static void
poly_finish4(const exact_ctx *c, int bonded, const poly_step *s, lf_eval *e);
#endif

static int
eval_runs(const exact_ctx *c, int bonded, int load, double start, size_t n, const double *delta,
          lf_eval *out, root_rec *ro)
{
    warm w[NRUN];
    poly_step st[NRUN][CHUNK];
    size_t nrun = n / RUN_MIN, len, j0, j, r, nj;
#ifdef EXACT_AVX2
    const int simd = lf_exact_simd(-1);
#endif

    nrun = nrun < 1 ? 1 : nrun > NRUN ? NRUN : nrun;
    len = (n + nrun - 1) / nrun;
    for (r = 0; r < nrun; r++)
        w[r].d1 = w[r].u1 = w[r].s1 = w[r].d2 = w[r].u2 = w[r].s2 = NAN;
    for (j0 = 0; j0 < len; j0 += nj) {
        nj = len - j0 < CHUNK ? len - j0 : CHUNK;
        for (j = 0; j < nj; j++) {
            int res[NRUN];
            /* each run's point: its warm start and first Newton step */
            for (r = 0; r < nrun; r++) {
                poly_step *s = &st[r][j];
                const size_t i = r * len + j0 + j;
                s->a = NULL;
                res[r] = -2;
                if (i >= n)
                    continue;
                if (!touching(c, load, start, delta[i])) {
                    lf_eval *e = &out[i];
                    e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
                    if (ro != NULL)
                        ro[i].u = NAN;
                    continue;
                }
                s->target = delta[i];
                s->u = warm_guess(&w[r], delta[i]);
                s->lo = c->u_lo;
                s->hi = c->u_top;
                res[r] = poly_newton(c, s);
            }
            /* then the rest of each: more steps, or invert */
            for (r = 0; r < nrun; r++) {
                poly_step *s = &st[r][j];
                const size_t i = r * len + j0 + j;
                if (res[r] == -2)
                    continue;
                while (res[r] == 0)
                    res[r] = poly_newton(c, s);
                if (res[r] == 1 && s->dd_root > 0.0) {
                    warm_push(&w[r], s->target, s->root, s->idd_root);
                    if (ro != NULL)
                        root_put(&ro[i], s->root, s->target, s->idd_root,
                                 s->shift + s->shift1 * s->du, s->shift1, 0.0);
                    continue;
                }
                s->a = NULL;
                if (eval_point(c, bonded, 1, delta[i], warm_guess(&w[r], delta[i]), &out[i], &w[r],
                               ro != NULL ? &ro[i] : NULL)
                    != LF_OK)
                    return LF_EINVAL;
            }
        }
        for (r = 0; r < nrun; r++)
            for (j = 0; j < nj; j++) {
#ifdef EXACT_AVX2
                /* four in a row at once (poly_finish4: the same bits) */
                if (simd && j + 4 <= nj && st[r][j].a != NULL && st[r][j + 1].a != NULL
                    && st[r][j + 2].a != NULL && st[r][j + 3].a != NULL) {
                    poly_finish4(c, bonded, &st[r][j], &out[r * len + j0 + j]);
                    j += 3;
                    continue;
                }
#endif
                if (st[r][j].a != NULL)
                    poly_finish(c, bonded, &st[r][j], &out[r * len + j0 + j]);
            }
    }
    return LF_OK;
}

/* The evaluation of n indentations with a context (shared by the model's
 * eval and lf_exact_eval_precise).  fast: warm starts and first-order
 * finish (header); else every point is solved on its own to rounding.
 * LF_EINVAL for a point past a sphere's largest contact (SPHERE_RHO_MAX). */
static int
eval_points(const exact_ctx *c, int bonded, int fast, lf_branch branch, size_t n,
            const double *delta, lf_eval *out, root_rec *ro)
{
    const int load = branch == LF_BRANCH_LOAD;
    double start = load ? fmax(0.0, c->delta_det) : c->delta_det;
    warm w = { NAN, NAN, NAN, NAN, NAN, NAN };
    size_t i;

    if (fast && c->pp != NULL)
        return eval_runs(c, bonded, load, start, n, delta, out, ro);
    for (i = 0; i < n; i++) {
        lf_eval *e = &out[i];
        if (!touching(c, load, start, delta[i])) {
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            if (ro != NULL)
                ro[i].u = NAN;
            continue;
        }
        if (eval_point(c, bonded, fast, delta[i], fast ? warm_guess(&w, delta[i]) : NAN, e, &w,
                       ro != NULL ? &ro[i] : NULL)
            != LF_OK)
            return LF_EINVAL;
    }
    return LF_OK;
}

/* One point from a start u near its root: invert's Newton steps on
 * delta's products (poly_newton's) until one is small enough to be
 * finished to second order, then P's two products (values and slopes)
 * and tau at the root itself in the same sub-cell (no second-order carry:
 * the same work and closer to the precise evaluation), straight to the
 * evaluation, and the point's record *ro.
 * 1 when done; 0 where invert would leave the polynomials or bisect, or
 * after PF_STEPS steps (then nothing is written). */
#define PF_STEPS 6
LF_KERNEL int
point_from(const exact_ctx *c, int bonded, double target, double u, lf_eval *e, root_rec *ro)
{
    const prodpoly *pp = c->pp;
    const double *a;
    double t, t2, t4, tp, tp2, tp4, tau, shift, shift1, shift2, D, dd, d2, g, idd, du, h, ee;
    double Ssh, P1, P, dP, lo = c->u_lo, hi = c->u_top;
    pp_v2 v01, v23, y01, y23, z01;
    int it;

    for (it = 0;; it++) {
        const double x = (u - pp->u0) * pp->inv_hs;
        if (it == PF_STEPS || !(u > lo && u < hi) || !(x >= 0.0 && x < (double) pp->nq))
            return 0;
        a = pp->c + pp->stride * (size_t) x;
        t = u - a[PP_MID];
        t2 = t * t;
        t4 = t2 * t2;
        v01 = pp_val2(a + PP_VAL, t, t2, t4);
        y01 = pp_d12(a + PP_D1, t, t2, t4);
        z01 = pp_d22(a + PP_D2, t);
        shift = c->A2 * v01[1];
        shift1 = c->A2 * y01[1];
        shift2 = c->A2 * z01[1];
        D = c->A1 * v01[0];
        dd = c->A1 * y01[0] - shift1;
        d2 = c->A1 * z01[0] - shift2;
        g = (D - shift) - target;
        if (!(dd > 0.0))
            return 0;
        idd = 1.0 / dd;
        du = -g * idd;
        if (fabs(g) <= 1e-14 * (fabs(D) + fabs(shift))) {
            du = 0.0;     /* at the root already */
            break;
        }
        if (g > 0.0)
            hi = u;
        else
            lo = u;
        if (!(u + du > lo && u + du < hi))
            return 0;
        if (fabs(du) <= STEP_TAYLOR && fabs(du * d2) <= CURV_TAYLOR * dd) {
            du -= 0.5 * d2 * du * du * idd;
            break;
        }
        if (fabs(du) < 1e-13 || hi - lo < 1e-14)
            return 0;
        u += du;
    }
    h = 0.5 * du * du;
    ee = d2 * du * idd;
    idd *= 1.0 - ee + ee * ee;
    /* P's products and tau at the root itself */
    tp = t + du;
    tp2 = tp * tp;
    tp4 = tp2 * tp2;
    v23 = pp_val2(a + PP_VAL + 2, tp, tp2, tp4);
    y23 = pp_d12(a + PP_D1 + 2, tp, tp2, tp4);
    tau = a[PP_TAU] * pp_exp(tp, tp2, tp4);
    Ssh = c->Sc * v23[0];
    P1 = c->F1 * v23[1];
    P = P1 - Ssh;
    dP = c->F1 * y23[1] - c->Sc * y23[0];
    shift += shift1 * du + shift2 * h;
    poly_out(c, bonded, a, tp, target, P, tau, P1, Ssh, shift, dP * idd, e);
    root_put(ro, u + du, target, idd, shift, shift1, d2);
    return 1;
}

/* ---- four points at once (x86-64 with AVX2) ---------------------------
 *
 * eval_from's points are independent, so eight of them (two blocks of
 * four) can take point_from's Newton steps and its second-order finish
 * side by side, one point per lane of a 256-bit register: the sub-cells'
 * coefficients (four products side by side in each row, prodpoly) are
 * read two products at a time from each point's sub-cell and transposed
 * to one product across the four points.  Every lane performs
 * point_from's operations on its point in point_from's order (IEEE
 * operations lane by lane; no fused multiply-add: the target is AVX2
 * without FMA, and neither path contracts), so a point done here has
 * point_from's bits (tests/test_exact.c holds the two paths equal bit for
 * bit).  A point that point_from would give up on is left to invert
 * from the same start; eval_runs' second pass (poly_finish4) is taken
 * four points at a time in the same way.  Chosen at
 * run time (__builtin_cpu_supports); elsewhere eval_from is the scalar
 * loop. */

/* The processor's AVX2 under the one switch the thin model's vector path
 * also follows (lf_simd: 0 forces the scalar paths for the tests). */
int
lf_exact_simd(int mode)
{
#ifdef EXACT_AVX2
    return lf_simd(mode);
#else
    (void) lf_simd(mode);
    return 0;
#endif
}

#ifdef EXACT_AVX2
#include "simd.h"

#define AVX2_FN static inline __attribute__((target("avx2")))

/* Products j0, j0 + 1 of the row at off of the four points' sub-cells a[]
 * as two vectors across the points (lane l: point l). */
AVX2_FN void
ld_pair(const double *const a[4], size_t off, v4 *p0, v4 *p1)
{
    const v4 x = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a[0] + off)),
                                      _mm_loadu_pd(a[2] + off), 1);
    const v4 y = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a[1] + off)),
                                      _mm_loadu_pd(a[3] + off), 1);
    *p0 = _mm256_unpacklo_pd(x, y);
    *p1 = _mm256_unpackhi_pd(x, y);
}

/* pp_val2, pp_d12 and pp_d22 for products j0, j0 + 1 of the sub-cells a[]
 * (off = PP_VAL + j0), across the points.  Only the values' rows are
 * read: the derivatives' coefficients are the same multiples of them
 * that prodpoly_build stores (n y_n; 2 y_2, 6 y_3, y_4), which give the
 * same bits and cost less than reading them.  z NULL: values and first
 * derivatives alone. */
AVX2_FN void
poly4(const double *const a[4], size_t off, v4 t, v4 t2, v4 t4, v4 v[2], v4 y[2], v4 z[2])
{
    v4 c[7][2];
    int n;
    for (n = 0; n < 7; n++)
        ld_pair(a, off + 4 * (size_t) n, &c[n][0], &c[n][1]);
    for (n = 0; n < 2; n++) {
        const v4 b0 = c[1][n], b1 = bc(2.0) * c[2][n], b2 = bc(3.0) * c[3][n];
        const v4 b3 = bc(4.0) * c[4][n], b4 = bc(5.0) * c[5][n], b5 = bc(6.0) * c[6][n];
        v[n] = ((c[0][n] + c[1][n] * t) + t2 * (c[2][n] + c[3][n] * t))
               + t4 * ((c[4][n] + c[5][n] * t) + c[6][n] * t2);
        y[n] = ((b0 + b1 * t) + t2 * (b2 + b3 * t)) + t4 * (b4 + b5 * t);
        if (z != NULL)
            z[n] = b1 + t * (bc(6.0) * c[3][n] + (t * bc(12.0)) * c[4][n]);
    }
}

AVX2_FN v4
vabs(v4 x)
{
    return _mm256_andnot_pd(bc(-0.0), x);
}

AVX2_FN v4
vsel(v4 mask, v4 yes, v4 no)
{
    return _mm256_blendv_pd(no, yes, mask);
}

/* Four consecutive records or evaluations (six numbers each) at p:
 * field pairs (f, f + 1) read as vectors across the points (written by
 * st_six). */
AVX2_FN void
ld_six(const double *p, v4 f[6])
{
    const double *const a[4] = { p, p + 6, p + 12, p + 18 };
    ld_pair(a, 0, &f[0], &f[1]);
    ld_pair(a, 2, &f[2], &f[3]);
    ld_pair(a, 4, &f[4], &f[5]);
}

_Static_assert(sizeof(lf_eval) == 6 * sizeof(double), "lf_eval is six numbers");

/* poly_out for four consecutive points (the evaluation at e) across the
 * lanes: their sub-cells a[], tr = t + du there, and the products at the
 * roots. */
AVX2_FN void
outs4(const exact_ctx *c, int bonded, const double *const a[4], v4 tr, v4 target, v4 P, v4 tau,
      v4 P1, v4 Ssh, v4 shift, v4 dPdd, lf_eval *e)
{
    const v4 half = dPdd * bc(0.5);
    v4 f[6];

    f[0] = P;
    f[1] = tau * bc(c->h);
    f[2] = vcapped(dPdd);
    f[3] = vcapped(bc(-0.5) * Ssh + half * shift);
    f[4] = vcapped((P1 - bc(0.5) * Ssh) - half * shift);
    f[5] = _mm256_setzero_pd();
    if (bonded) {
        /* each point's four cubics in one row (its tr in every lane),
         * then the rows transposed to one product across the points */
        v4 R[4], H[4], lo01, hi01, lo23, hi23;
        int l;
        for (l = 0; l < 4; l++) {
            const double *h = a[l] + PP_NU;
            const v4 x = l == 0 ? _mm256_permute4x64_pd(tr, 0x00)
                         : l == 1 ? _mm256_permute4x64_pd(tr, 0x55)
                         : l == 2 ? _mm256_permute4x64_pd(tr, 0xAA) : _mm256_permute4x64_pd(tr, 0xFF);
            R[l] = _mm256_loadu_pd(h) + x * (_mm256_loadu_pd(h + 4) + x * (_mm256_loadu_pd(h + 8)
                                                                      + x * _mm256_loadu_pd(h + 12)));
        }
        lo01 = _mm256_unpacklo_pd(R[0], R[1]);
        hi01 = _mm256_unpackhi_pd(R[0], R[1]);
        lo23 = _mm256_unpacklo_pd(R[2], R[3]);
        hi23 = _mm256_unpackhi_pd(R[2], R[3]);
        H[0] = _mm256_permute2f128_pd(lo01, lo23, 0x20);
        H[1] = _mm256_permute2f128_pd(hi01, hi23, 0x20);
        H[2] = _mm256_permute2f128_pd(lo01, lo23, 0x31);
        H[3] = _mm256_permute2f128_pd(hi01, hi23, 0x31);
        f[5] = vcapped((P1 * H[3] - Ssh * (H[0] - H[1])) - dPdd * ((target + shift) * H[2] + shift * H[1]));
    }
    st_six(&e->P, f);
}

/* poly_finish for the four points s[0 .. 3] (each with its sub-cell s->a),
 * whose evaluations are e[0 .. 3]: one point per lane, poly_finish's
 * operations in its order (where du is 0 the products at s->u stand, as
 * there). */
__attribute__((target("avx2"))) static void
poly_finish4(const exact_ctx *c, int bonded, const poly_step *s, lf_eval *e)
{
#define LANES(f) _mm256_set_pd(s[3].f, s[2].f, s[1].f, s[0].f)
    const double *const a[4] = { s[0].a, s[1].a, s[2].a, s[3].a };
    const v4 t = LANES(t), t2 = LANES(t2), t4 = LANES(t4), du = LANES(du);
    const v4 still = _mm256_cmp_pd(du, _mm256_setzero_pd(), _CMP_EQ_OQ);
    v4 v[2], y[2], z[2], ta, tb, tc, td, te, tf, tg, tmid, tau, Ssh, Ssh1, Ssh2, P1, P11, P12, P, dP;
    v4 shift = LANES(shift), h, P2;

    poly4(a, PP_VAL + 2, t, t2, t4, v, y, z);
    ld_pair(a, PP_MID, &tmid, &ta);
    ld_pair(a, PP_TAU + 1, &tb, &tc);
    ld_pair(a, PP_TAU + 3, &td, &te);
    ld_pair(a, PP_TAU + 5, &tf, &tg);
    tau = ((ta + tb * t) + t2 * (tc + td * t)) + t4 * ((te + tf * t) + tg * t2);
    Ssh = bc(c->Sc) * v[0];
    Ssh1 = bc(c->Sc) * y[0];
    P1 = bc(c->F1) * v[1];
    P11 = bc(c->F1) * y[1];
    P = P1 - Ssh;
    dP = P11 - Ssh1;
    Ssh2 = bc(c->Sc) * z[0];
    P12 = bc(c->F1) * z[1];
    P2 = P12 - Ssh2;
    h = bc(0.5) * du * du;
    P = vsel(still, P, P + (dP * du + P2 * h));
    dP = vsel(still, dP, dP + P2 * du);
    tau = vsel(still, tau, tau * ((bc(1.0) + du) + h));
    shift = vsel(still, shift, shift + (LANES(shift1) * du + LANES(shift2) * h));
    Ssh = vsel(still, Ssh, Ssh + (Ssh1 * du + Ssh2 * h));
    P1 = vsel(still, P1, P1 + (P11 * du + P12 * h));
    outs4(c, bonded, a, t + du, LANES(target), P, tau, P1, Ssh, shift, dP * LANES(idd_root), e);
#undef LANES
}


/* point_from's finish for four points across the lanes (their sub-cells
 * a[] and t there, the step's u, du, 1/dd and d2, and delta's shift,
 * shift1 and shift2 at u): P's products and tau at the root, the
 * evaluations out[0 .. 3] and the records ro[0 .. 3]. */
__attribute__((target("avx2"), always_inline)) static inline void
finish4(const exact_ctx *c, int bonded, const double *const a[4], v4 t, v4 u, v4 du, v4 idd, v4 d2,
        v4 sh, v4 sh1, v4 sh2, v4 target, lf_eval *out, root_rec *ro)
{
    v4 h, ee, v23[2], y23[2], mid, emid, tp, tp2, tp4, tau, Ssh, P1, P, dP, dPdd, f[6];

    h = bc(0.5) * du * du;
    ee = d2 * du * idd;
    idd = idd * ((bc(1.0) - ee) + ee * ee);
    tp = t + du;
    tp2 = tp * tp;
    tp4 = tp2 * tp2;
    poly4(a, PP_VAL + 2, tp, tp2, tp4, v23, y23, NULL);
    ld_pair(a, PP_MID, &mid, &emid);
    tau = emid * (((bc(1.0) + tp) + tp2 * (bc(1.0 / 2) + tp * bc(1.0 / 6)))
                  + tp4 * ((bc(1.0 / 24) + tp * bc(1.0 / 120)) + tp2 * bc(1.0 / 720)));
    Ssh = bc(c->Sc) * v23[0];
    P1 = bc(c->F1) * v23[1];
    P = P1 - Ssh;
    dP = bc(c->F1) * y23[1] - bc(c->Sc) * y23[0];
    sh = sh + (sh1 * du + sh2 * h);
    dPdd = dP * idd;
    outs4(c, bonded, a, tp, target, P, tau, P1, Ssh, sh, dPdd, out);
    /* root_put's */
    f[0] = u + du;
    f[1] = target;
    f[2] = idd;
    f[3] = sh;
    f[4] = sh1;
    f[5] = d2;
    st_six(&ro->u, f);
}

/* Points taken as up to NB blocks of four (eval_from4); the functions
 * below take the number of blocks nb <= NB as an argument, a constant
 * where they are inlined. */
#define NB 3

/* One Newton step of point_from on the NB blocks of lanes act (st
 * below), and the state kept for the lanes it finishes (all of it where
 * first: the lanes that finish later overwrite theirs). */
typedef struct {
    v4 target[NB], u[NB], lo[NB], hi[NB], act[NB];
    const double *fa[NB][4];
    v4 fu[NB], ft[NB], fsh[NB], fsh1[NB], fsh2[NB], fd2[NB], fidd[NB], fdu[NB];
    int m, live;
} lanes;

__attribute__((target("avx2"), always_inline)) static inline void
lanes_step(const exact_ctx *c, lanes *st, int first, int nb)
{
    const prodpoly *pp = c->pp;
    const double *a[NB][4];
    const v4 zero = _mm256_setzero_pd();
    v4 t[NB], t2[NB], t4[NB], v01[NB][2], y01[NB][2], z01[NB][2];
    int l, b;

    for (b = 0; b < nb; b++) {
        const v4 u = st->u[b], x = (u - bc(pp->u0)) * bc(pp->inv_hs);
        int xs[4];
        /* out of the bracket or the polynomials: point_from gives up */
        st->act[b] = _mm256_and_pd(st->act[b], _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd(u, st->lo[b], _CMP_GT_OQ), _mm256_cmp_pd(u, st->hi[b], _CMP_LT_OQ)),
            _mm256_and_pd(_mm256_cmp_pd(x, zero, _CMP_GE_OQ),
                          _mm256_cmp_pd(x, bc((double) pp->nq), _CMP_LT_OQ))));
        /* the sub-cell (0 where not active): x < nq, far inside int */
        _mm_storeu_si128((__m128i *) (void *) xs, _mm256_cvttpd_epi32(_mm256_and_pd(st->act[b], x)));
        for (l = 0; l < 4; l++)
            a[b][l] = pp->c + pp->stride * (size_t) xs[l];
        t[b] = u - _mm256_set_pd(a[b][3][PP_MID], a[b][2][PP_MID], a[b][1][PP_MID], a[b][0][PP_MID]);
        t2[b] = t[b] * t[b];
        t4[b] = t2[b] * t2[b];
    }
    for (b = 0; b < nb; b++)
        poly4(a[b], PP_VAL, t[b], t2[b], t4[b], v01[b], y01[b], z01[b]);
    for (b = 0; b < nb; b++) {
        const v4 u = st->u[b];
        v4 D, g, gp, un, tay, inb, shift, shift1, shift2, dd, d2, idd, du, at, fin, go, lo, hi;
        int mf;
        shift = bc(c->A2) * v01[b][1];
        shift1 = bc(c->A2) * y01[b][1];
        shift2 = bc(c->A2) * z01[b][1];
        D = bc(c->A1) * v01[b][0];
        dd = bc(c->A1) * y01[b][0] - shift1;
        d2 = bc(c->A1) * z01[b][0] - shift2;
        g = (D - shift) - st->target[b];
        st->act[b] = _mm256_and_pd(st->act[b], _mm256_cmp_pd(dd, zero, _CMP_GT_OQ));
        idd = bc(1.0) / dd;
        du = _mm256_xor_pd(g, bc(-0.0)) * idd;
        at = _mm256_cmp_pd(vabs(g), bc(1e-14) * (vabs(D) + vabs(shift)), _CMP_LE_OQ);
        /* not at the root: the bracket, then the second-order finish where
         * the step is small enough, else another step unless it is below
         * rounding */
        gp = _mm256_cmp_pd(g, zero, _CMP_GT_OQ);
        hi = vsel(gp, u, st->hi[b]);
        lo = vsel(gp, st->lo[b], u);
        un = u + du;
        inb = _mm256_and_pd(_mm256_cmp_pd(un, lo, _CMP_GT_OQ), _mm256_cmp_pd(un, hi, _CMP_LT_OQ));
        tay = _mm256_and_pd(_mm256_cmp_pd(vabs(du), bc(STEP_TAYLOR), _CMP_LE_OQ),
                            _mm256_cmp_pd(vabs(du * d2), bc(CURV_TAYLOR) * dd, _CMP_LE_OQ));
        fin = _mm256_and_pd(st->act[b], _mm256_or_pd(at, _mm256_and_pd(inb, tay)));
        go = _mm256_andnot_pd(_mm256_or_pd(at, tay), _mm256_and_pd(st->act[b], inb));
        go = _mm256_andnot_pd(_mm256_or_pd(_mm256_cmp_pd(vabs(du), bc(1e-13), _CMP_LT_OQ),
                                           _mm256_cmp_pd(hi - lo, bc(1e-14), _CMP_LT_OQ)), go);
        mf = _mm256_movemask_pd(fin);
        du = vsel(at, zero, du - ((bc(0.5) * d2 * du) * du) * idd);
        if (first) {
            st->fu[b] = u;
            st->ft[b] = t[b];
            st->fsh[b] = shift;
            st->fsh1[b] = shift1;
            st->fsh2[b] = shift2;
            st->fd2[b] = d2;
            st->fidd[b] = idd;
            st->fdu[b] = du;
            for (l = 0; l < 4; l++)
                st->fa[b][l] = a[b][l];
        } else if (mf != 0) {
            st->fu[b] = vsel(fin, u, st->fu[b]);
            st->ft[b] = vsel(fin, t[b], st->ft[b]);
            st->fsh[b] = vsel(fin, shift, st->fsh[b]);
            st->fsh1[b] = vsel(fin, shift1, st->fsh1[b]);
            st->fsh2[b] = vsel(fin, shift2, st->fsh2[b]);
            st->fd2[b] = vsel(fin, d2, st->fd2[b]);
            st->fidd[b] = vsel(fin, idd, st->fidd[b]);
            st->fdu[b] = vsel(fin, du, st->fdu[b]);
            for (l = 0; l < 4; l++)
                if (mf & (1 << l))
                    st->fa[b][l] = a[b][l];
        }
        st->m |= mf << (4 * b);
        st->act[b] = go;
        st->u[b] = vsel(go, un, u);
        st->lo[b] = lo;
        st->hi[b] = hi;
        st->live = (st->live & ~(15 << (4 * b))) | (_mm256_movemask_pd(go) << (4 * b));
    }
}

/* The Newton steps after the first (lanes_step), apart so that the first
 * keeps its state in registers. */
__attribute__((target("avx2"), noinline)) static void
lanes_more(const exact_ctx *c, lanes *st, int nb)
{
    int it;

    for (it = 1; it < PF_STEPS && st->live != 0; it++)
        lanes_step(c, st, 0, nb);
}

/* point_from for the NB blocks of four points i .. i + 4 NB - 1 (targets
 * delta[i ..], starts u0[]), its Newton steps (up to PF_STEPS) side by
 * side; the blocks' operations interleaved, so that the processor
 * overlaps their chains.  Returns the points done (bit j: point i + j);
 * the others are those point_from gives up on.  When any is done the
 * evaluations and records of all are written (those of the others are
 * eval_point's to write again). */
__attribute__((target("avx2"), always_inline)) static inline int
point_from4(const exact_ctx *c, int bonded, size_t i, const double *delta, const v4 u0[NB],
            lf_eval *out, root_rec *ro, int nb)
{
    lanes st;
    int b;

    for (b = 0; b < nb; b++) {
        st.target[b] = _mm256_loadu_pd(delta + i + 4 * (size_t) b);
        st.u[b] = u0[b];
        st.lo[b] = bc(c->u_lo);
        st.hi[b] = bc(c->u_top);
        st.act[b] = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    }
    st.m = st.live = 0;
    lanes_step(c, &st, 1, nb);
    if (st.live != 0)
        lanes_more(c, &st, nb);
    const int m = st.m;
    const double *(*fa)[4] = st.fa;
    v4 *fu = st.fu, *ft = st.ft, *fsh = st.fsh, *fsh1 = st.fsh1;
    v4 *fsh2 = st.fsh2, *fd2 = st.fd2, *fidd = st.fidd, *fdu = st.fdu, *target = st.target;
    if (m == 0)
        return 0;
    for (b = 0; b < nb; b++)
        finish4(c, bonded, fa[b], ft[b], fu[b], fdu[b], fidd[b], fd2[b], fsh[b], fsh1[b], fsh2[b],
                target[b], &out[i + 4 * (size_t) b], &ro[i + 4 * (size_t) b]);
    return m;
}

/* point_from4 where every point's first Newton step finishes (a fit's
 * evaluations from the last roots, nearly always): the step and the
 * finish in one pass, the step's state in registers, none of the later
 * steps' bookkeeping.  The first step's operations are lanes_step's from
 * point_from4's start (bracket [u_lo, u_top]), so the bits are the same;
 * where a point does not finish there, point_from4 takes all of them
 * from the start. */
__attribute__((target("avx2"), always_inline)) static inline int
point_one4(const exact_ctx *c, int bonded, size_t i, const double *delta, const v4 u0[NB],
           lf_eval *out, root_rec *ro, int nb)
{
    const prodpoly *pp = c->pp;
    const double *a[NB][4];
    const v4 zero = _mm256_setzero_pd(), ulo = bc(c->u_lo), utop = bc(c->u_top);
    v4 t[NB], t2[NB], t4[NB], v01[NB][2], y01[NB][2], z01[NB][2], target[NB];
    v4 du[NB], idd[NB], d2[NB], sh[NB], sh1[NB], sh2[NB], act[NB];
    int l, b, all = 1;

    for (b = 0; b < nb; b++) {
        const v4 u = u0[b], x = (u - bc(pp->u0)) * bc(pp->inv_hs);
        int xs[4];
        act[b] = _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd(u, ulo, _CMP_GT_OQ), _mm256_cmp_pd(u, utop, _CMP_LT_OQ)),
            _mm256_and_pd(_mm256_cmp_pd(x, zero, _CMP_GE_OQ),
                          _mm256_cmp_pd(x, bc((double) pp->nq), _CMP_LT_OQ)));
        _mm_storeu_si128((__m128i *) (void *) xs, _mm256_cvttpd_epi32(_mm256_and_pd(act[b], x)));
        for (l = 0; l < 4; l++)
            a[b][l] = pp->c + pp->stride * (size_t) xs[l];
        t[b] = u - _mm256_set_pd(a[b][3][PP_MID], a[b][2][PP_MID], a[b][1][PP_MID], a[b][0][PP_MID]);
        t2[b] = t[b] * t[b];
        t4[b] = t2[b] * t2[b];
        target[b] = _mm256_loadu_pd(delta + i + 4 * (size_t) b);
    }
    for (b = 0; b < nb; b++)
        poly4(a[b], PP_VAL, t[b], t2[b], t4[b], v01[b], y01[b], z01[b]);
    for (b = 0; b < nb; b++) {
        const v4 u = u0[b];
        v4 D, g, gp, un, tay, inb, dd, at, fin, lo, hi, s;
        sh[b] = bc(c->A2) * v01[b][1];
        sh1[b] = bc(c->A2) * y01[b][1];
        sh2[b] = bc(c->A2) * z01[b][1];
        D = bc(c->A1) * v01[b][0];
        dd = bc(c->A1) * y01[b][0] - sh1[b];
        d2[b] = bc(c->A1) * z01[b][0] - sh2[b];
        g = (D - sh[b]) - target[b];
        idd[b] = bc(1.0) / dd;
        s = _mm256_xor_pd(g, bc(-0.0)) * idd[b];
        at = _mm256_cmp_pd(vabs(g), bc(1e-14) * (vabs(D) + vabs(sh[b])), _CMP_LE_OQ);
        gp = _mm256_cmp_pd(g, zero, _CMP_GT_OQ);
        hi = vsel(gp, u, utop);
        lo = vsel(gp, ulo, u);
        un = u + s;
        inb = _mm256_and_pd(_mm256_cmp_pd(un, lo, _CMP_GT_OQ), _mm256_cmp_pd(un, hi, _CMP_LT_OQ));
        tay = _mm256_and_pd(_mm256_cmp_pd(vabs(s), bc(STEP_TAYLOR), _CMP_LE_OQ),
                            _mm256_cmp_pd(vabs(s * d2[b]), bc(CURV_TAYLOR) * dd, _CMP_LE_OQ));
        fin = _mm256_and_pd(_mm256_and_pd(act[b], _mm256_cmp_pd(dd, zero, _CMP_GT_OQ)),
                            _mm256_or_pd(at, _mm256_and_pd(inb, tay)));
        all &= _mm256_movemask_pd(fin) == 15;
        du[b] = vsel(at, zero, s - ((bc(0.5) * d2[b] * s) * s) * idd[b]);
    }
    if (!all)
        return point_from4(c, bonded, i, delta, u0, out, ro, nb);
    for (b = 0; b < nb; b++)
        finish4(c, bonded, a[b], t[b], u0[b], du[b], idd[b], d2[b], sh[b], sh1[b], sh2[b],
                target[b], &out[i + 4 * (size_t) b], &ro[i + 4 * (size_t) b]);
    return (1 << 4 * nb) - 1;
}

/* eval_from with the points taken 4 NB at a time by point_one4 where
 * that many in a row touch and have starts, else four at a time where
 * four do; the rest as eval_from takes them (one at a time). */
__attribute__((target("avx2"))) static int
eval_from4(const exact_ctx *c, int bonded, int load, double start, size_t n, const double *delta,
           lf_eval *out, root_rec *ro, double dL)
{
    warm w = { NAN, NAN, NAN, NAN, NAN, NAN };
    const v4 vstart = bc(start), zero = _mm256_setzero_pd(), vdL = bc(dL);
    const int some_det = isfinite(c->u_det);
    size_t i = 0;
    int l, m, b;

    while (i < n) {
        double u0;
        if (i + 4 <= n) {
            v4 u[NB];
            const int most = i + 4 * NB <= n ? NB : 1;
            int nb = 0;
            /* as many blocks as there is room for, or one block, where
             * their points touch and have starts */
            for (b = 0; b < most; b++) {
                const v4 dv = _mm256_loadu_pd(delta + i + 4 * (size_t) b);
                v4 touch = load ? _mm256_cmp_pd(dv, vstart, _CMP_GE_OQ)
                                : _mm256_cmp_pd(dv, vstart, _CMP_GT_OQ);
                v4 r[6], du1;
                if (!some_det)
                    touch = _mm256_and_pd(touch, _mm256_cmp_pd(dv, zero, _CMP_GT_OQ));
                /* root_start's */
                ld_six(&ro[i + 4 * (size_t) b].u, r);
                du1 = ((dv - r[1]) + r[3] * vdL) * r[2];
                u[b] = (r[0] + du1) - r[2] * ((((bc(0.5) * r[5]) * du1) * du1 - (r[4] * du1) * vdL)
                                              - ((bc(0.5) * r[3]) * vdL) * vdL);
                if (_mm256_movemask_pd(_mm256_and_pd(
                        touch, _mm256_cmp_pd(vabs(u[b]), bc(INFINITY), _CMP_LT_OQ))) != 15)
                    break;
            }
            nb = b == most ? most : b > 0 ? 1 : 0;
            if (nb > 0) {
                double us[4 * NB];
                m = nb == NB ? point_one4(c, bonded, i, delta, u, out, ro, NB)
                             : point_one4(c, bonded, i, delta, u, out, ro, 1);
                if (m != (1 << 4 * nb) - 1) {
                    for (b = 0; b < nb; b++)
                        _mm256_storeu_pd(us + 4 * b, u[b]);
                    for (l = 0; l < 4 * nb; l++) {
                        const size_t j = i + (size_t) l;
                        if (m & (1 << l))
                            continue;
                        if (eval_point(c, bonded, 1, delta[j], us[l], &out[j], &w, &ro[j]) != LF_OK)
                            return LF_EINVAL;
                    }
                }
                i += 4 * (size_t) nb;
                continue;
            }
        }
        /* one point as eval_from takes it */
        if (!touching(c, load, start, delta[i])) {
            lf_eval *e = &out[i];
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            ro[i].u = NAN;
            i++;
            continue;
        }
        u0 = root_start(&ro[i], delta[i], dL);
        if (!isfinite(u0))
            u0 = NAN;
        else if (point_from(c, bonded, delta[i], u0, &out[i], &ro[i])) {
            i++;
            continue;
        }
        if (eval_point(c, bonded, 1, delta[i], u0, &out[i], &w, &ro[i]) != LF_OK)
            return LF_EINVAL;
        i++;
    }
    return LF_OK;
}
#endif

/* eval_points' fast path with each point started at its own root of the
 * last evaluation of the same curve, carried by the moves of its
 * indentation and of ln lambda (dL) since (root_start): no point's start
 * waits on another's root (eval_runs' chain), so the processor overlaps
 * the points.  point_from takes it from there on the polynomials; a point
 * it gives up on, without a root, or on the tables (c->pp NULL) goes to
 * invert from that start (or the half-space form). */
static int
eval_from(const exact_ctx *c, int bonded, int load, double start, size_t n, const double *delta,
          lf_eval *out, root_rec *ro, double dL)
{
    warm w = { NAN, NAN, NAN, NAN, NAN, NAN };
    size_t i;

#ifdef EXACT_AVX2
    if (c->pp != NULL && lf_exact_simd(-1))
        return eval_from4(c, bonded, load, start, n, delta, out, ro, dL);
#endif
    for (i = 0; i < n; i++) {
        root_rec *r = &ro[i];
        double u0;
        if (!touching(c, load, start, delta[i])) {
            lf_eval *e = &out[i];
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            r->u = NAN;
            continue;
        }
        u0 = root_start(r, delta[i], dL);
        if (!isfinite(u0))
            u0 = NAN;
        else if (c->pp != NULL && point_from(c, bonded, delta[i], u0, &out[i], r))
            continue;
        if (eval_point(c, bonded, 1, delta[i], u0, &out[i], &w, r) != LF_OK)
            return LF_EINVAL;
    }
    return LF_OK;
}

static int
exact_eval(void *state, const lf_probe *probe, const lf_material *mat,
           lf_branch branch, size_t n, const double *delta, lf_eval *out)
{
    exact_ctx c;
    mixdata local;
    slot *held;
    int status;

    if (ctx_init(&c, state, probe, mat, &local, &held, NULL) != LF_OK)
        return LF_EINVAL;
    status = eval_points(&c, probe->base == LF_BASE_BONDED, 1, branch, n, delta, out, NULL);
    mixdata_done(held);
    return status;
}

/* How far ln lambda (and a bonded layer's nu) may have moved since the
 * roots of a curve's last evaluation for them to start the next: beyond,
 * eval_runs' chained starts take fewer Newton steps (a fit's first steps
 * and its guess move that far; 0.1 made a bonded fit at a held nu 15%
 * slower, bench_models).  On a frictionless layer, whose points from the
 * roots take their Newton steps four at a time (eval_from4), starting
 * from the roots pays up to a move of 0.2 (a 1 024-curve map's default
 * batch 10% faster; bench_models' frictionless fits 0-7%); the answers
 * move by rounding only. */
#define WARM_DL 0.02
#define WARM_DL_FREE 0.2
#define WARM_DNU 0.02

_Static_assert(sizeof(root_rec) == 6 * sizeof(double), "LF_MODEL_ROOTS_SIZE counts 6 numbers a point");

/* lf_model_eval_roots for the exact model: eval_from where the last
 * evaluation's parameters (roots[0..2]: ln lambda, nu, branch) are close,
 * else the chained starts of eval_points; either keeps each point's
 * record (root_rec) after the head for the next call. */
int
lf_exact_eval_warm(void *state, const lf_probe *probe, const lf_material *mat, lf_branch branch,
                   size_t n, const double *delta, lf_eval *out, double *roots)
{
    exact_ctx c;
    mixdata local;
    slot *held;
    int status, bonded = probe->base == LF_BASE_BONDED;
    const double nu = bonded ? mat->nu : 0.0;
    root_rec *ro = (root_rec *) (void *) (roots + LF_MODEL_ROOTS_HEAD);

    if (ctx_init(&c, state, probe, mat, &local, &held, NULL) != LF_OK)
        return LF_EINVAL;
    if (fabs(c.L - roots[0]) <= (bonded ? WARM_DL : WARM_DL_FREE) && fabs(nu - roots[1]) <= WARM_DNU
        && roots[2] == (double) branch) {
        const int load = branch == LF_BRANCH_LOAD;
        status = eval_from(&c, bonded, load, load ? fmax(0.0, c.delta_det) : c.delta_det, n, delta,
                           out, ro, c.L - roots[0]);
    } else {
        status = eval_points(&c, bonded, 1, branch, n, delta, out, ro);
    }
    mixdata_done(held);
    roots[0] = status == LF_OK ? c.L : NAN;
    roots[1] = nu;
    roots[2] = (double) branch;
    return status;
}

int
lf_exact_eval_precise(const lf_probe *probe, const lf_material *mat, lf_branch branch,
                      size_t n, const double *delta, lf_eval *out, lf_error *err)
{
    exact_ctx c;
    slot *held;
    mixdata *local = malloc(sizeof *local);
    int status;

    if (local == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory (exact model)");
    status = ctx_init(&c, NULL, probe, mat, local, &held, err);
    if (status == LF_OK
        && eval_points(&c, probe->base == LF_BASE_BONDED, 0, branch, n, delta, out, NULL) != LF_OK)
        status = lf_fail(err, LF_EINVAL, "an indentation lies past the sphere's largest contact "
                         "(a = %g R)", SPHERE_RHO_MAX);
    free(local);
    return status;
}

static int
pulloff_compute(void *state, const lf_probe *probe, const lf_material *mat,
                lf_pulloff *out)
{
    exact_ctx c;
    exact_pt pt;
    mixdata local;
    mixval v;
    slot *held;
    double u_po, du;

    if (ctx_init(&c, state, probe, mat, &local, &held, NULL) != LF_OK)
        return LF_EINVAL;
    out->c = 0.0;
    if (!isfinite(c.u_det)) {
        out->delta_detach = out->P_detach = out->a_detach = 0.0;
        out->delta_po = out->P_po = out->a_po = out->sigma_po = out->P_jump = 0.0;
        mixdata_done(held);
        return LF_OK;
    }
    out->delta_detach = c.det.delta;
    out->P_detach = c.det.P;
    out->a_detach = exp(c.u_det) * c.h;
    /* force-controlled pull-off: first minimum of P(tau) above detachment */
    if (c.det.dP >= 0.0) {
        pt = c.det;
        u_po = c.u_det;
    } else {
        const mixval *d = &c.vdet;
        double f = rho_of(RHO_P, c.k, d->u, d->F, d->g) - c.L
                   + drho_of(RHO_P, c.k, d->g, d->dg) * c.du_det;
        u_po = cond_first_above(&c, RHO_P, c.u_det, fmin(f, 0.0), &v, &du);
        curve_from(&c, v.u, v.F, v.g, NULL, NULL, NULL, &pt);
        curve_advance(&pt, du);
    }
    out->delta_po = pt.delta;
    out->P_po = pt.P;
    out->a_po = exp(u_po) * c.h;
    out->sigma_po = -out->P_po / (M_PI * out->a_po * out->a_po);
    out->P_jump = 0.0;
    if (c.delta_det < 0.0) {
        /* delta rises from delta_det < 0 above u_det: one crossing of 0 */
        const mixval *d = &c.vdet;
        double f = rho_of(RHO_0, c.k, d->u, d->F, d->g) - c.L
                   + drho_of(RHO_0, c.k, d->g, d->dg) * c.du_det;
        cond_first_above(&c, RHO_0, c.u_det, fmin(f, 0.0), &v, &du);
        curve_from(&c, v.u, v.F, v.g, NULL, NULL, NULL, &pt);
        curve_advance(&pt, du);
        out->P_jump = pt.P;
    }
    mixdata_done(held);
    return LF_OK;
}

static int
exact_pulloff(void *state, const lf_probe *probe, const lf_material *mat,
              lf_pulloff *out)
{
    exact_state *st = state;
    uint64_t key[3];
    memo_entry *e = memo_slot(st->serial, mat, key);
    int status;

    if (e->serial == st->serial && memcmp(e->key, key, sizeof key) == 0) {
        *out = e->po;
        return LF_OK;
    }
    status = pulloff_compute(state, probe, mat, out);
    if (status == LF_OK) {
        e->serial = st->serial;
        memcpy(e->key, key, sizeof key);
        e->po = *out;
    }
    return status;
}

const lf_model_type lf_model_exact = {
    "exact",
    "finite-thickness layer, Lebedev-Ufliand Fredholm equation (Nystrom, tabulated)",
    exact_alloc,
    exact_free,
    exact_eval,
    exact_pulloff,
    2, LF_SCOPE_ANY, 0.0, 1, exact_prepare, LF_EXACT_NU_MAX
};

/* ---------------------------------------------------------------- helpers */

int
lf_exact_thin_ratio(double k, lf_base base, double nu, double tau, double *ratio_P1,
                    lf_error *err)
{
    lf_exact_mix mix;
    double f[4], df[4], kap, Z, p_thin;
    int status;

    *ratio_P1 = NAN;
    if (!(isfinite(k) && k > 0 && isfinite(tau) && tau > 0))
        return lf_fail(err, LF_EINVAL, "exact/thin ratio needs k > 0 and a/b > 0");
    if (base == LF_BASE_BONDED && !(nu >= 0 && nu < 0.5))
        return lf_fail(err, LF_EINVAL, "nu must lie in [0, 0.5) (got %g)", nu);
    status = lf_exact_mix_init(&mix, k, base, nu, err);
    if (status != LF_OK)
        return status;
    lf_exact_mix_eval(&mix, tau, f, df, NULL);
    kap = lf_exact_kappa(k);
    Z = lf_thin_Z(base, nu);
    p_thin = 0.5 * M_PI * Z * tau * k / (kap * (k + 2.0));
    *ratio_P1 = f[3] / p_thin;
    return LF_OK;
}

int
lf_exact_thin_difference(const lf_probe *probe, const lf_material *mat,
                         double ab_min, double ab_max, double *max_rel,
                         lf_error *err)
{
    exact_ctx c;
    mixdata *local;
    slot *held;
    double u0, u1, Pmax = 0.0, dmax = 0.0;
    int status, i, n = 200;

    *max_rel = NAN;
    if ((status = lf_probe_check(probe, err)) != LF_OK
        || (status = lf_material_check(mat, probe->base, err)) != LF_OK)
        return status;
    if (!(ab_min > 0 && ab_max > ab_min && isfinite(ab_max)))
        return lf_fail(err, LF_EINVAL, "need 0 < a/b min < a/b max (got %g, %g)", ab_min, ab_max);
    if ((local = malloc(sizeof *local)) == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory (exact model)");
    status = ctx_init(&c, NULL, probe, mat, local, &held, err);
    u0 = log(ab_min);
    if (status == LF_OK && isfinite(c.u_det) && u0 < c.u_det)
        u0 = c.u_det;
    u1 = log(ab_max);
    if (status == LF_OK && u1 <= u0)
        status = lf_fail(err, LF_EINVAL, "a/b range lies below the detachment radius");
    for (i = 0; i <= n && status == LF_OK; i++) {
        exact_pt pt;
        lf_eval th;
        double d;
        curve_at(&c, u0 + (u1 - u0) * i / n, 0, &pt);
        d = pt.delta;
        status = lf_model_thin.eval(NULL, probe, mat, LF_BRANCH_UNLOAD, 1, &d, &th);
        if (status != LF_OK)
            status = lf_fail(err, status, "thin model failed");
        Pmax = fmax(Pmax, fabs(pt.P));
        dmax = fmax(dmax, fabs(th.P - pt.P));
    }
    free(local);
    if (status == LF_OK)
        *max_rel = Pmax > 0.0 ? dmax / Pmax : 0.0;
    return status;
}

/* ------------------------------------------------------- beyond the tables */

int
lf_exact_far_eval(const lf_probe *pr, const lf_material *mat, lf_branch branch, size_t n,
                  const double *delta, double *P, lf_error *err)
{
    lf_exact_table tail;
    lf_exact_kernel *kr = NULL;
    lf_exact_point pt;
    exact_ctx c;
    probe_consts pc;
    double F[2 * LF_EXACT_NFUN], G[2 * LF_EXACT_NFUN], f[4], df[4], tau = LF_EXACT_TAU_MAX;
    double Mth, cth, umin = log(LF_EXACT_TAU_MAX);
    const lf_exact_table *tt[4];
    lf_exact_mix mx, one;
    size_t i;
    int j, m, status, cached;

    if ((status = lf_probe_check(pr, err)) != LF_OK
        || (status = lf_material_check(mat, pr->base, err)) != LF_OK
        || (status = lf_exact_mix_weights(&mx, pr->base, mat->nu, err)) != LF_OK)
        return status;
    if (pr->tip == LF_TIP_SPHERE)
        return lf_fail(err, LF_EDATA, "a sphere has no thin-layer tail form (its R/b enters)");
    /* quick refusal before any solve: every point beyond TAU_MAX by the
     * thin-layer radius a = (k R^(k-1) (delta + c))^(1/k) with a margin */
    Mth = lf_thin_Z(pr->base, mat->nu) * mat->Estar;
    cth = sqrt(2.0 * pr->b * mat->w / Mth);
    for (i = 0; i < n; i++) {
        double d1 = delta[i] + cth;
        if (branch == LF_BRANCH_LOAD && delta[i] < 0.0)
            continue;
        if (!(d1 > 0.0) || exp((log(d1) - lf_probe_log_prefactor(pr)) / pr->k)
                               < 1.2 * LF_EXACT_TAU_MAX * pr->b)
            return lf_fail(err, LF_EDATA, "point %zu is not beyond a/b = %g", i, LF_EXACT_TAU_MAX);
    }
    /* value and slope at TAU_MAX: from the table if it is at hand
     * (frictionless), else one solve at the tables' own node count.  Bonded
     * layers always solve at nu: the tables' interpolation in nu differs
     * from it by ~1e-7, and the answer must not depend on what is cached */
    cached = pr->base == LF_BASE_FRICTIONLESS;
    for (m = 0; m < mx.m && cached; m++)
        cached = (tt[m] = lf_exact_table_find(pr->k, pr->base, pr->base == LF_BASE_BONDED
                                              ? lf_exact_nu_node(mx.node0 + m) : 0.0)) != NULL;
    if (cached) {
        for (m = 0; m < mx.m; m++)
            mx.t[m] = tt[m];
        lf_exact_mix_eval(&mx, tau, f, df, NULL);
    } else {
        status = lf_exact_kernel_alloc(&kr, pr->base, mat->nu, err);
        if (status == LF_OK)
            status = lf_exact_solve(kr, pr->k, tau, lf_exact_nodes(tau), &pt, err);
        lf_exact_kernel_free(kr);
        if (status != LF_OK)
            return status;
        f[0] = pt.s; f[1] = pt.e; f[2] = pt.d; f[3] = pt.p;
        df[0] = pt.ds; df[1] = pt.de; df[2] = pt.dd; df[3] = pt.dp;
    }
    /* a two-node table whose last node is TAU_MAX: beyond it the tables'
     * own tail (exact_table.c), the only part used here */
    memset(&tail, 0, sizeof tail);
    tail.k = pr->k;
    tail.base = pr->base;
    tail.nu = pr->base == LF_BASE_BONDED ? mat->nu : 0.0;
    tail.n = 2;
    tail.h = 1.0;
    tail.l0 = log(tau) - 1.0;
    tail.F = F;
    tail.G = G;
    for (j = 0; j < LF_EXACT_NFUN; j++) {
        F[j] = F[LF_EXACT_NFUN + j] = log(f[j]);
        G[j] = G[LF_EXACT_NFUN + j] = tau * df[j] / f[j];
        tail.flo[j] = f[j];
        tail.dflo[j] = df[j];
    }
    lf_exact_table_finish(&tail);
    memset(&c, 0, sizeof c);
    memset(&one, 0, sizeof one);
    one.m = 1;
    one.t[0] = &tail;
    one.wl[0] = 1.0;
    probe_consts_of(pr, &pc);
    c.mx = &one;
    c.md = NULL;
    c.k = pc.k;
    c.h = pc.h;
    c.A1 = pc.A1;
    c.F1 = mat->Estar * pc.Fc;
    c.A2 = sqrt(2.0 * M_PI * pr->b * mat->w / mat->Estar);
    c.Sc = 2.0 * mat->Estar * pc.h * c.A2;
    c.ln_hR = NAN;          /* a power law (a sphere was refused above) */
    c.u_top = U_HIGH;
    /* Newton in ln tau on the monotonic part of the branch, never below
     * TAU_MAX (the root there is the stable branch's: delta rises with tau
     * from the detachment up) */
    for (i = 0; i < n; i++) {
        exact_pt e;
        double u = (log(delta[i] + cth) - lf_probe_log_prefactor(pr)) / pr->k - log(pr->b);
        int it, done = 0;
        if (branch == LF_BRANCH_LOAD && delta[i] < 0.0) {
            P[i] = 0.0;
            continue;
        }
        for (it = 0; it < 100 && !done; it++) {
            double g, un;
            curve_at(&c, u, 0, &e);
            g = e.delta - delta[i];
            if (!(e.dd > 0.0))
                break;
            un = u - g / e.dd;
            done = fabs(g) <= 1e-14 * (fabs(e.delta + e.shift) + fabs(e.shift)) || fabs(un - u) < 1e-13;
            u = fmax(un, umin);
        }
        if (!done || u <= umin)
            return lf_fail(err, LF_EDATA, "point %zu is not beyond a/b = %g", i, LF_EXACT_TAU_MAX);
        curve_at(&c, u, 0, &e);
        P[i] = e.P;
    }
    return LF_OK;
}
