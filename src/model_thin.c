/* model_thin.c: the thin-layer adhesive (JKR) model of the seed paper,
 * Papangelo, "Adhesion between a power-law indenter and a thin layer coated
 * on a rigid substrate": Eqs. (7), (10)-(13) for a frictionless base and
 * (21)-(25) for a bonded compressible base, valid for b << a.
 *
 * With M = Z E* (Z = 1 frictionless, (1-nu)^2/(1-2nu) bonded),
 *   c      = sqrt(2 b w / M)                       (Eq. 11, 23)
 *   delta1 = delta + c
 *   P      = C delta1^(2/k) (delta1 - (k+2)/k c)   (Eq. 10, 22)
 *   C      = pi M / b k^((k+2)/k) / (k+2) R^(2(k-1)/k)
 *   a      = (k R^(k-1) delta1)^(1/k)              (Eq. 7)
 * and P = a = 0 where delta1 <= 0 (unloading) or delta < 0 (loading).
 * Derivatives (written for this file, checked in tests/test_model.c):
 *   dP/ddelta = C (k+2)/k delta1^(2/k-1) (delta1 - 2c/k)
 *   dP/dln w  = -C (k+2)/k^2 c^2 delta1^(2/k-1)
 *   dP/dln M  = P - dP/dln w,   dP/dnu = dP/dln M * dln Z/dnu.
 */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* Four points at a time with AVX2 where the processor has it (thin_block4
 * below). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(LF_NO_SIMD)
#define THIN_AVX2 1
#endif

double
lf_thin_Z(lf_base base, double nu)
{
    if (base == LF_BASE_FRICTIONLESS)
        return 1.0;
    return (1.0 - nu) * (1.0 - nu) / (1.0 - 2.0 * nu);
}

double
lf_thin_dlogZ_dnu(lf_base base, double nu)
{
    if (base == LF_BASE_FRICTIONLESS)
        return 0.0;
    return 2.0 * nu / ((1.0 - nu) * (1.0 - 2.0 * nu));
}

double
lf_thin_b_critical(double k, double w, double M, double sigma_th)
{
    double q = k / (k + 2.0);
    return 2.0 * q * q * M * w / (sigma_th * sigma_th);
}

double
lf_thin_scale(const lf_probe *p)
{
    const double k = p->k;

    /* pi/b k/(k+2) B^(-2/k), with B = 1/(k R^(k-1)) as the paper writes it
     * for a probe stated by R (a sphere: its apex's paraboloid) */
    if (lf_probe_by_R(p))
        return M_PI / p->b * pow(k, (k + 2.0) / k) / (k + 2.0) * pow(p->R, 2.0 * (k - 1.0) / k);
    return M_PI / p->b * k / (k + 2.0) * exp(-2.0 / k * lf_probe_log_prefactor(p));
}

/* The constants of one (probe, material) pair. */
typedef struct {
    double M;      /* constrained modulus Z E*, Pa */
    double c;      /* adhesive offset, m */
    double C;      /* force scale, N m^(-(k+2)/k) */
    double dlogZ;  /* dln Z / dnu */
} thin_consts;

static thin_consts
thin_setup(const lf_probe *p, double scale, const lf_material *m)
{
    thin_consts t;

    t.M = lf_thin_Z(p->base, m->nu) * m->Estar;
    t.c = sqrt(2.0 * p->b * m->w / t.M);
    t.C = t.M * scale;
    t.dlogZ = lf_thin_dlogZ_dnu(p->base, m->nu);
    return t;
}

/* The powers of delta1 one point needs.  pow() costs about a log and an
 * exp; all three powers follow from one root r = delta1^(1/k):
 * delta1^(2/k) = r^2, delta1^(2/k-1) = r^2 / delta1, a = (k R^(k-1))^(1/k) r.
 * The root is exact or square roots for k = 1, 2, 4, from a few
 * multiplications for k = 3 (lf_inv_cbrt), exp(log(delta1) / k) for any other
 * k > 2.  For other k < 2,
 * where r^2 / delta1 would lose digits as r^2 underflows, the powers come
 * from one logarithm as before. */
typedef enum {
    ROOT_ONE,      /* k = 1: r = delta1 */
    ROOT_SQRT,     /* k = 2 */
    ROOT_CBRT,     /* k = 3 */
    ROOT_SQRT2,    /* k = 4 */
    ROOT_EXP,      /* other k > 2 */
    ROOT_LOG       /* other k < 2: each power from log(delta1) */
} root_kind;

typedef struct {
    root_kind kind;
    double inv_k;      /* 1/k */
    double e1;         /* 2/k - 1 */
    double log_rk;     /* ln(k R^(k-1)) = -ln B */
    double ak;         /* (k R^(k-1))^(1/k) = B^(-1/k) */
} thin_powers;

static thin_powers
powers_setup(const lf_probe *p)
{
    thin_powers w;
    const int by_R = lf_probe_by_R(p);

    w.inv_k = 1.0 / p->k;
    w.e1 = 2.0 / p->k - 1.0;
    w.log_rk = by_R ? log(p->k) + (p->k - 1.0) * log(p->R) : -lf_probe_log_prefactor(p);
    w.ak = exp(w.inv_k * w.log_rk);
    if (p->k == 1.0) {
        w.kind = ROOT_ONE;
    } else if (p->k == 2.0) {
        w.kind = ROOT_SQRT;
        w.ak = by_R ? sqrt(2.0 * p->R) : sqrt(exp(w.log_rk));
    } else if (p->k == 3.0) {
        w.kind = ROOT_CBRT;
    } else if (p->k == 4.0) {
        w.kind = ROOT_SQRT2;
        w.ak = by_R ? sqrt(sqrt(4.0 * p->R * p->R * p->R)) : sqrt(sqrt(exp(w.log_rk)));
    } else {
        w.kind = p->k > 2.0 ? ROOT_EXP : ROOT_LOG;
    }
    return w;
}

/* A model's state: what depends on its probe alone (a few powers and
 * logarithms, more than the rest of a short curve's evaluation), taken
 * once; a NULL state (a caller without a model) takes them at each call. */
typedef struct {
    double scale;          /* lf_thin_scale */
    thin_powers pw;
} thin_state;

static int
thin_alloc(void **state, const lf_probe *p, lf_error *err)
{
    thin_state *s = malloc(sizeof *s);

    if (s == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory allocating a model");
    s->scale = lf_thin_scale(p);
    s->pw = powers_setup(p);
    *state = s;
    return LF_OK;
}

static void
thin_free(void *state)
{
    free(state);
}

static double
state_scale(const void *state, const lf_probe *p)
{
    return state != NULL ? ((const thin_state *) state)->scale : lf_thin_scale(p);
}

/* g = delta1^(2/k-1) (capped), p2 = delta1^(2/k), a = (k R^(k-1) delta1)^(1/k);
 * d1 > 0; y = lf_inv_cbrt(d1) for k = 3 (unused otherwise). */
static inline void
powers_at(const thin_powers *w, double d1, double y, double *g, double *p2, double *a)
{
    double r, l;

    switch (w->kind) {
    case ROOT_ONE:
        *g = d1;
        *p2 = d1 * d1;
        *a = w->ak * d1;
        return;
    case ROOT_SQRT:
        *g = 1.0;
        *p2 = d1;
        *a = w->ak * sqrt(d1);
        return;
    case ROOT_CBRT:
        if (d1 >= 1e-300 && d1 <= 1e300) {
            *g = y;                          /* delta1^(-1/3) */
            *p2 = d1 * *g;
            *a = w->ak * (*p2 * *g);
            return;
        }
        r = exp(w->inv_k * log(d1));
        break;
    case ROOT_SQRT2:
        r = sqrt(sqrt(d1));
        break;
    case ROOT_EXP:
        r = exp(w->inv_k * log(d1));
        break;
    default:
        l = log(d1);
        *g = fmin(exp(w->e1 * l), LF_BIG);
        *p2 = *g < LF_BIG ? d1 * *g : exp((w->e1 + 1.0) * l);
        *a = exp(w->inv_k * (w->log_rk + l));
        return;
    }
    *p2 = r * r;
    *g = fmin(*p2 / d1, LF_BIG);
    *a = w->ak * r;
}

/* ---- a sphere of radius R ------------------------------------------
 *
 * The pressure is local, p = (M/b)(delta1 - f(r)) inside the contact and
 * delta1 = f(a), so the adhesionless force is M/b times the volume of the
 * spherical cap of height delta1,
 *   P1 = (pi M/b) delta1^2 (R - delta1/3),     a^2 = delta1 (2R - delta1),
 * and the JKR energy balance with the flat-punch stiffness S = pi a^2 M/b
 * of a thin layer keeps delta1 - delta = c = sqrt(2 b w/M) as for the
 * power laws (the seed paper's Eq. 1-2 with S' = 2 pi a M/b):
 *   P = (pi M/b) [delta1^2 (R - delta1/3) - c delta1 (2R - delta1)].
 * For delta1 << R this is the paraboloid's Eq. (10) at k = 2.  Derivatives
 * at fixed delta:
 *   dP/ddelta = (pi M/b) [delta1 (2R - delta1) - 2c (R - delta1)]
 *   dP/dln w  = -(pi M/b) c^2 (R - delta1),  dP/dln M = P - dP/dln w.
 * Force-controlled pull-off where dP/ddelta = 0:
 *   delta1_po = 2 R c / (R + c + sqrt(R^2 + c^2)).
 * Past the equator (delta1 > R) no contact is wider than the sphere: the
 * contact stays at a = R, a flat punch of radius R whose pressure no longer
 * vanishes at the edge, P = (pi M/b) (R^2 delta - R^3/3) (the same relation
 * P = P1 - S c with a fixed, where c cancels), continuous with its slope at
 * delta1 = R; the fit says when a curve gets there (fit/uncertainty.c). */
static double
sphere_force(double K, double R, double c, double d1)
{
    if (d1 > R)
        return K * R * R * (d1 - c - R / 3.0);
    return K * (d1 * d1 * (R - d1 / 3.0) - c * d1 * (2.0 * R - d1));
}

static int
sphere_eval(const lf_probe *p, const thin_consts *t, lf_branch branch, size_t n,
            const double *delta, lf_eval *out)
{
    const double R = p->R, c = t->c, K = M_PI * t->M / p->b;
    const int load = branch == LF_BRANCH_LOAD;
    size_t i;

    for (i = 0; i < n; i++) {
        lf_eval *e = &out[i];
        double d1 = delta[i] + c;

        if (d1 <= 0.0 || (load && delta[i] < 0.0)) {
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            continue;
        }
        e->P = sphere_force(K, R, c, d1);
        if (d1 > R) {                /* past the equator: a flat punch */
            e->a = R;
            e->dP_ddelta = K * R * R;
            e->dP_dlogw = 0.0;
        } else {
            e->a = sqrt(d1 * (2.0 * R - d1));
            e->dP_ddelta = K * (d1 * (2.0 * R - d1) - 2.0 * c * (R - d1));
            e->dP_dlogw = -K * c * c * (R - d1);
        }
        e->dP_dlogE = e->P - e->dP_dlogw;
        e->dP_dnu = e->dP_dlogE * t->dlogZ;
    }
    return LF_OK;
}

static void
sphere_pulloff(const lf_probe *p, const thin_consts *t, lf_pulloff *out)
{
    const double R = p->R, c = t->c, K = M_PI * t->M / p->b;
    const double d1 = 2.0 * R * c / (R + c + sqrt(R * R + c * c));

    out->c = c;
    out->delta_detach = -c;
    out->P_detach = out->a_detach = 0.0;
    out->delta_po = d1 - c;
    out->P_po = sphere_force(K, R, c, d1);
    out->a_po = sqrt(d1 * (2.0 * R - d1));
    out->sigma_po = out->a_po > 0.0 ? -out->P_po / (M_PI * out->a_po * out->a_po) : 0.0;
    /* contact made at delta = 0, delta1 = c (the sphere's when c < R) */
    out->P_jump = sphere_force(K, R, c, c);
}

#define BLOCK 64   /* points whose k = 3 roots are taken together */

/* The constants of one evaluation's loop. */
typedef struct {
    thin_consts t;
    thin_powers pw;
    double Ckk, kkc, c2k, wcoef;
    int load;
} thin_loop;

/* Points i0..i0+nb-1 of thin_eval, for root kind KIND and ADH = (c > 0),
 * both constants in each instance (LF_KERNEL), so that the loop over the
 * points tests neither; y: the block's k = 3 roots. */
LF_KERNEL void
thin_block(const thin_loop *L, root_kind KIND, int ADH, size_t nb, const double *delta,
           const double *y, lf_eval *out)
{
    const thin_consts *t = &L->t;
    thin_powers pw = L->pw;
    size_t j;

    pw.kind = KIND;
    for (j = 0; j < nb; j++) {
        lf_eval *e = &out[j];
        double d1 = delta[j] + t->c, g, p2;

        if (d1 <= 0.0 || (L->load && delta[j] < 0.0)) {
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            continue;
        }
        powers_at(&pw, d1, y[j], &g, &p2, &e->a);     /* g = delta1^(2/k-1) */
        if (ADH) {
            e->P = t->C * p2 * (d1 - L->kkc);
            e->dP_ddelta = lf_capped(L->Ckk * g * (d1 - L->c2k));
            e->dP_dlogw = lf_capped(L->wcoef * g);
        } else {
            e->P = t->C * p2 * d1;
            e->dP_ddelta = L->Ckk * p2;
            e->dP_dlogw = 0.0;
        }
        e->dP_dlogE = lf_capped(e->P - e->dP_dlogw);
        e->dP_dnu = lf_capped(e->dP_dlogE * t->dlogZ);
    }
}

/* lf_thin_roots from point j0 on (the first guesses of the points before
 * it already in xr and y), then the steps over all n: the steps apart from
 * the integer first guesses are loops of arithmetic alone, which the
 * compiler runs on vectors of points (the same operations on each), one
 * step over all points at a time (no step waits on the one before it for
 * the same point: 0.4 ns a point less than the four in a row for the
 * model's roots) */
LF_KERNEL void
roots_from(const double *z, double shift, size_t j0, size_t n, int steps, double *xr, double *y)
{
    size_t j;
    int s;

    for (j = j0; j < n; j++) {
        double x = z[j] + shift;
        xr[j] = x >= 1e-300 && x <= 1e300 ? x : 1.0;
        y[j] = lf_inv_cbrt_seed(xr[j]);
    }
    for (s = 0; s < steps; s++)
        for (j = 0; j < n; j++)
            y[j] = lf_inv_cbrt_step(xr[j], y[j]);
}

/* ---- four points at a time ------------------------------------------
 *
 * thin_block's points are independent: with AVX2, four of them go side by
 * side, one point per lane of a 256-bit register, each lane performing
 * thin_block's operations on its point in thin_block's order (IEEE
 * operations lane by lane; no fused multiply-add: the target is AVX2
 * without FMA, so nothing is contracted), so a point done here has
 * thin_block's bits (tests/test_model.c holds the two paths equal bit for
 * bit).  A lane out of contact computes what it may and is written as
 * thin_block writes it, all zeros; a group of four with a point that
 * thin_block would take through exp and log (k = 3 beyond the fast cube
 * root's range) is left to thin_block.  For k = 1, 2, 3 and 4, chosen at
 * run time (__builtin_cpu_supports); elsewhere, and for other k, the
 * scalar loop. */

/* -1: as the processor allows; 0: the scalar path (lf_simd) */
static _Atomic int simd_mode = -1;

static int
simd_have(void)
{
#ifdef THIN_AVX2
    return __builtin_cpu_supports("avx2") ? 1 : 0;
#else
    return 0;
#endif
}

int
lf_simd(int mode)
{
    if (mode >= 0)
        atomic_store_explicit(&simd_mode, mode ? -1 : 0, memory_order_relaxed);
    return atomic_load_explicit(&simd_mode, memory_order_relaxed) != 0 && simd_have();
}

#ifdef THIN_AVX2
#include "simd.h"

_Static_assert(sizeof(lf_eval) == 6 * sizeof(double), "lf_eval is six numbers");

/* thin_block's points i0..i0+nb-1 for KIND (ROOT_ONE, ROOT_SQRT, ROOT_CBRT,
 * ROOT_SQRT2) and ADH, four at a time; returns how many were done (a
 * multiple of four: the rest are thin_block's). */
__attribute__((target("avx2"), always_inline)) static inline size_t
block4(const thin_loop *L, root_kind KIND, int ADH, size_t nb, const double *delta,
       const double *y, lf_eval *out)
{
    const thin_consts *t = &L->t;
    const v4 c = bc(t->c), C = bc(t->C), Ckk = bc(L->Ckk), kkc = bc(L->kkc), c2k = bc(L->c2k);
    const v4 wcoef = bc(L->wcoef), dlogZ = bc(t->dlogZ), ak = bc(L->pw.ak), zero = bc(0.0);
    size_t j;

    for (j = 0; j + 4 <= nb; j += 4) {
        const v4 d = _mm256_loadu_pd(delta + j), d1 = d + c;
        v4 off = _mm256_cmp_pd(d1, zero, _CMP_LE_OQ), g, p2, a, f[6];
        if (L->load)
            off = _mm256_or_pd(off, _mm256_cmp_pd(d, zero, _CMP_LT_OQ));
        if (KIND == ROOT_ONE) {
            g = d1;
            p2 = d1 * d1;
            a = ak * d1;
        } else if (KIND == ROOT_SQRT) {
            g = bc(1.0);
            p2 = d1;
            a = ak * _mm256_sqrt_pd(d1);
        } else if (KIND == ROOT_CBRT) {
            const v4 in = _mm256_and_pd(_mm256_cmp_pd(d1, bc(1e-300), _CMP_GE_OQ),
                                        _mm256_cmp_pd(d1, bc(1e300), _CMP_LE_OQ));
            if (_mm256_movemask_pd(_mm256_or_pd(in, off)) != 15)
                return j;           /* a point for exp and log: thin_block's */
            g = _mm256_loadu_pd(y + j);
            p2 = d1 * g;
            a = ak * (p2 * g);
        } else {                    /* ROOT_SQRT2 */
            const v4 r = _mm256_sqrt_pd(_mm256_sqrt_pd(d1));
            p2 = r * r;
            /* fmin: a NaN quotient gives LF_BIG, as minpd's second operand */
            g = _mm256_min_pd(p2 / d1, bc(LF_BIG));
            a = ak * r;
        }
        if (ADH) {
            f[0] = C * p2 * (d1 - kkc);
            f[2] = vcapped(Ckk * g * (d1 - c2k));
            f[3] = vcapped(wcoef * g);
        } else {
            f[0] = C * p2 * d1;
            f[2] = Ckk * p2;
            f[3] = zero;
        }
        f[1] = a;
        f[4] = vcapped(f[0] - f[3]);
        f[5] = vcapped(f[4] * dlogZ);
        f[0] = _mm256_andnot_pd(off, f[0]);
        f[1] = _mm256_andnot_pd(off, f[1]);
        f[2] = _mm256_andnot_pd(off, f[2]);
        f[3] = _mm256_andnot_pd(off, f[3]);
        f[4] = _mm256_andnot_pd(off, f[4]);
        f[5] = _mm256_andnot_pd(off, f[5]);
        st_six(&out[j].P, f);
    }
    return j;
}

/* lf_inv_cbrt_seed lane by lane: 0x553F000000000000 - i / 3 for the bits i
 * of x > 0, the quotient exact from 32-bit multiplications: with i = H 2^32
 * + L, H / 3 and L / 3 by the multiplier 0xAAAAAAAB (exact for any 32-bit
 * numerator), remainders rH and rL, and 2^32 = 3 0x55555555 + 1,
 *     i / 3 = (H / 3) 2^32 + rH 0x55555555 + L / 3 + (rH + rL >= 3). */
LF_AVX2 v4
vcbrt_seed(v4 x)
{
    const __m256i i = _mm256_castpd_si256(x), mul = _mm256_set1_epi64x(0xAAAAAAAB);
    const __m256i H = _mm256_srli_epi64(i, 32), L = _mm256_and_si256(i, _mm256_set1_epi64x(0xFFFFFFFF));
    const __m256i qH = _mm256_srli_epi64(_mm256_mul_epu32(H, mul), 33);
    const __m256i qL = _mm256_srli_epi64(_mm256_mul_epu32(L, mul), 33);
    const __m256i rH = _mm256_sub_epi64(H, _mm256_add_epi64(_mm256_add_epi64(qH, qH), qH));
    const __m256i rL = _mm256_sub_epi64(L, _mm256_add_epi64(_mm256_add_epi64(qL, qL), qL));
    const __m256i carry = _mm256_cmpgt_epi64(_mm256_add_epi64(rH, rL), _mm256_set1_epi64x(2));
    __m256i q = _mm256_add_epi64(_mm256_slli_epi64(qH, 32),
                                 _mm256_mul_epu32(rH, _mm256_set1_epi64x(0x55555555)));
    q = _mm256_sub_epi64(_mm256_add_epi64(q, qL), carry);     /* carry: -1 or 0 */
    return _mm256_castsi256_pd(_mm256_sub_epi64(_mm256_set1_epi64x(0x553F000000000000), q));
}

/* lf_thin_roots four points at a time */
__attribute__((target("avx2"))) static void
roots4(const double *z, double shift, size_t n, int steps, double *xr, double *y)
{
    size_t j;

    for (j = 0; j + 4 <= n; j += 4) {
        const v4 x = _mm256_loadu_pd(z + j) + bc(shift);
        const v4 in = _mm256_and_pd(_mm256_cmp_pd(x, bc(1e-300), _CMP_GE_OQ),
                                    _mm256_cmp_pd(x, bc(1e300), _CMP_LE_OQ));
        const v4 r = _mm256_blendv_pd(bc(1.0), x, in);
        _mm256_storeu_pd(xr + j, r);
        _mm256_storeu_pd(y + j, vcbrt_seed(r));
    }
    roots_from(z, shift, j, n, steps, xr, y);
}

/* block4 for the kind and adhesion of L (kinds it has not: none done) */
__attribute__((target("avx2"))) static size_t
thin_block4(const thin_loop *L, int adh, size_t nb, const double *delta, const double *y,
            lf_eval *out)
{
    switch (L->pw.kind) {
    case ROOT_ONE:
        return adh ? block4(L, ROOT_ONE, 1, nb, delta, y, out)
                   : block4(L, ROOT_ONE, 0, nb, delta, y, out);
    case ROOT_SQRT:
        return adh ? block4(L, ROOT_SQRT, 1, nb, delta, y, out)
                   : block4(L, ROOT_SQRT, 0, nb, delta, y, out);
    case ROOT_CBRT:
        return adh ? block4(L, ROOT_CBRT, 1, nb, delta, y, out)
                   : block4(L, ROOT_CBRT, 0, nb, delta, y, out);
    case ROOT_SQRT2:
        return adh ? block4(L, ROOT_SQRT2, 1, nb, delta, y, out)
                   : block4(L, ROOT_SQRT2, 0, nb, delta, y, out);
    default:
        return 0;
    }
}
#endif

void
lf_thin_roots(const double *z, double shift, size_t n, int steps, double *xr, double *y)
{
#ifdef THIN_AVX2
    if (lf_simd(-1)) {
        roots4(z, shift, n, steps, xr, y);
        return;
    }
#endif
    roots_from(z, shift, 0, n, steps, xr, y);
}

static int
thin_eval(void *state, const lf_probe *p, const lf_material *m,
          lf_branch branch, size_t n, const double *delta, lf_eval *out)
{
    thin_loop L;
    const double k = p->k, kk = (k + 2.0) / k;
    double y[BLOCK] = { 0.0 }, xr[BLOCK];
    size_t i0;
#ifdef THIN_AVX2
    const int vec = lf_simd(-1);
#endif

    L.t = thin_setup(p, state_scale(state, p), m);
    L.pw = state != NULL ? ((const thin_state *) state)->pw : powers_setup(p);
    L.Ckk = L.t.C * kk;
    L.kkc = kk * L.t.c;
    L.c2k = 2.0 * L.t.c / k;
    L.wcoef = -L.Ckk / k * L.t.c * L.t.c;
    L.load = branch == LF_BRANCH_LOAD;
    if (p->tip == LF_TIP_SPHERE)
        return sphere_eval(p, &L.t, branch, n, delta, out);
    for (i0 = 0; i0 < n; i0 += BLOCK) {
        size_t nb = n - i0 < BLOCK ? n - i0 : BLOCK;
        const double *d = delta + i0;
        const double *yb = y;
        lf_eval *o = out + i0;
        const int adh = L.t.c > 0.0;
        /* k = 3: the roots of a block first (lf_inv_cbrt's four steps) */
        if (L.pw.kind == ROOT_CBRT)
            lf_thin_roots(d, L.t.c, nb, 4, xr, y);
#ifdef THIN_AVX2
        if (vec) {
            const size_t done = thin_block4(&L, adh, nb, d, y, o);
            d += done;
            yb += done;
            o += done;
            nb -= done;
            if (nb == 0)
                continue;
        }
#endif
        switch (L.pw.kind) {
        case ROOT_SQRT:
            if (adh)
                thin_block(&L, ROOT_SQRT, 1, nb, d, yb, o);
            else
                thin_block(&L, ROOT_SQRT, 0, nb, d, yb, o);
            break;
        case ROOT_CBRT:
            if (adh)
                thin_block(&L, ROOT_CBRT, 1, nb, d, yb, o);
            else
                thin_block(&L, ROOT_CBRT, 0, nb, d, yb, o);
            break;
        default:        /* the other kinds: the kind tested per point */
            if (adh)
                thin_block(&L, L.pw.kind, 1, nb, d, yb, o);
            else
                thin_block(&L, L.pw.kind, 0, nb, d, yb, o);
            break;
        }
    }
    return LF_OK;
}

static int
thin_pulloff(void *state, const lf_probe *p, const lf_material *m,
             lf_pulloff *out)
{
    const thin_consts t = thin_setup(p, state_scale(state, p), m);
    const double k = p->k;
    double d1po = 2.0 * t.c / k;

    if (p->tip == LF_TIP_SPHERE) {
        sphere_pulloff(p, &t, out);
        return LF_OK;
    }
    out->c = t.c;
    out->delta_detach = -t.c;
    out->P_detach = 0.0;
    out->a_detach = 0.0;
    out->delta_po = d1po - t.c;
    out->P_po = -t.C * pow(d1po, 2.0 / k) * t.c;
    /* (2 c / (k B))^(1/k) from logarithms: B, or R^(k-1), alone leaves
     * double precision for a flat punch (k of a few hundred) */
    out->a_po = !(t.c > 0.0) ? 0.0
                : lf_probe_by_R(p) ? exp((log(2.0 * t.c) + (k - 1.0) * log(p->R)) / k)
                : exp((log(2.0 * t.c / k) - lf_probe_log_prefactor(p)) / k);
    out->sigma_po = out->a_po > 0.0 ? -out->P_po / (M_PI * out->a_po * out->a_po) : 0.0;
    out->P_jump = -(2.0 / k) * t.C * pow(t.c, (k + 2.0) / k);
    return LF_OK;
}

const lf_model_type lf_model_thin = {
    "thin",
    "thin-layer closed form (Papangelo; Johnson/Jaffar/Barber limit b << a)",
    thin_alloc,
    thin_free,
    thin_eval,
    thin_pulloff,
    0, LF_SCOPE_THIN, 0.0, 0, NULL, 0.0
};
