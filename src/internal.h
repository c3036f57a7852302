/* internal.h: helpers shared by the library's own files; not installed. */
#ifndef LF_INTERNAL_H
#define LF_INTERNAL_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "command.h"     /* layerfit.h and what the command shares */

#if defined(__GNUC__)
#define LF_PRINTF(a, b) __attribute__((format(printf, a, b)))
/* a kernel written once and specialised at each call with constant
 * arguments: inlined even where the compiler's size rule would not */
#define LF_KERNEL static inline __attribute__((always_inline))
#else
#define LF_PRINTF(a, b)
#define LF_KERNEL static inline
#endif

/* Fill err (if not NULL) with status and a formatted message; returns status
 * so that callers can write `return lf_fail(err, LF_EINVAL, "...")`. */
int lf_fail(lf_error *err, int status, const char *fmt, ...) LF_PRINTF(3, 4);

/* The same with a place: file (may be NULL), line and column (0 = none). */
int lf_fail_at(lf_error *err, int status, const char *file, long line,
               long column, const char *fmt, ...) LF_PRINTF(6, 7);

/* Append a formatted warning to w (silently dropped on allocation failure,
 * a warning is never worth failing for). */
void lf_warn(lf_warnings *w, const char *fmt, ...) LF_PRINTF(2, 3);

/* ln of the profile's prefactor B (lf_probe_prefactor), formed without B
 * itself, which leaves double precision for large k. */
double lf_probe_log_prefactor(const lf_probe *p);
/* 1 for a power law stated by R (LF_TIP_POWER without B), whose models
 * keep the seed paper's arithmetic in R. */
static inline int
lf_probe_by_R(const lf_probe *p)
{
    return p->tip == LF_TIP_POWER && !(p->B > 0);
}
/* A length that scales the probe: R where it is given, else the R of its
 * B (k != 1), else 1 m (a cone has none); for brackets of searches. */
double lf_probe_length(const lf_probe *p);

/* The thin-layer force scale C of a probe per unit constrained modulus M
 * (model_thin.c): C / M = pi/b k/(k+2) B^(-2/k). */
double lf_thin_scale(const lf_probe *p);
/* The AVX2 paths of the thin model's evaluation and roots (model_thin.c)
 * and of the noise estimates' departures (fit/noise.c), four points at a
 * time, where the processor has AVX2 (mode 1, the default), or always
 * point by point (0, for the tests: the two give the same bits); -1
 * leaves it.  Returns 1 when the vector paths are taken.  The exact
 * model's (lf_exact_simd) follows the same switch; -DLF_NO_SIMD removes
 * them all. */
int lf_simd(int mode);
/* x^(-1/3) for x = z[j] + shift, j < n: xr[j] = x within [1e-300, 1e300]
 * (else 1), y[j] = lf_inv_cbrt_seed(xr[j]) followed by `steps` of
 * lf_inv_cbrt_step, each step over all points before the next; the bits
 * of that scalar loop, four points at a time where lf_simd allows
 * (model_thin.c). */
void lf_thin_roots(const double *z, double shift, size_t n, int steps, double *xr, double *y);

/* LF_OK when the open file fd (named path) is no larger than
 * lf_input_limit(), else LF_EIO with a message saying so and how to raise
 * it (input.c): for readers that read a whole file, in blocks, into what
 * they keep (plans, tables). */
int lf_input_check_size(int fd, const char *path, lf_error *err);

/* A strdup that does not depend on POSIX feature macros. */
char *lf_strdup(const char *s);

/* lf_input_read on a descriptor already opened by lf_input_open (read from
 * its current place to its end; the caller closes it), with the same
 * limit and, with LF_INPUT_TEXT, the same text checks; when binary is
 * given, it says from the first LF_SNIFF_BYTES (or all, if fewer) whether
 * the input is a binary format's, which then goes unchecked (a binary
 * format read as a stream). */
int lf_input_read_fd(int fd, const char *path, unsigned flags,
                     int (*binary)(const char *head, size_t len), lf_input *in, lf_error *err);
/* The same, opening path first (lf_input_open with flags). */
int lf_input_read_path(const char *path, unsigned flags, int (*binary)(const char *, size_t),
                       lf_input *in, lf_error *err);

/* A growable string for the library's writers (src/text.c).  Every call
 * is a no-op once an allocation failed (failed = 1); lf_str_take hands the
 * text over (NULL and LF_ENOMEM after a failure) and empties b.  Zero
 * initialised: an empty string. */
typedef struct {
    char *s;
    size_t len, cap;
    int failed;
} lf_str;

void lf_str_put(lf_str *b, const char *s, size_t n);
void lf_str_puts(lf_str *b, const char *s);
void lf_str_printf(lf_str *b, const char *fmt, ...) LF_PRINTF(2, 3);
/* lf_str_put for the escapes' put(ctx, s, n) (ctx is the lf_str). */
void lf_str_put_cb(void *ctx, const char *s, size_t n);
/* A number that reads back exactly, or nonfinite ("null", "") for NaN, Inf. */
void lf_str_number(lf_str *b, double x, const char *nonfinite);
/* A JSON string (lf_json_escape); null for NULL; "key": name plus
 * "key_raw": its bytes percent-escaped when name is not UTF-8. */
void lf_str_json(lf_str *b, const char *s);
void lf_str_json_or_null(lf_str *b, const char *s);
void lf_str_json_name(lf_str *b, const char *key, const char *name);
/* lf_provenance_json into b. */
void lf_str_provenance(lf_str *b, const char *indent, const lf_provenance *p);
int lf_str_take(lf_str *b, char **out, lf_error *err);
void lf_str_free(lf_str *b);

/* Options held by name (src/fit_options.c), for the fit's and the
 * design's tables: lf_optset_set keeps a copy of the text given to
 * option `name` of table in text[i] and, for a number, its value in
 * values[i] (checked by lf_option_number; a flag's text "1");
 * lf_optset_get returns the text given, or NULL. */
int lf_optset_set(const lf_option *table, char **text, double *values, const char *name,
                  const char *value, lf_error *err);
const char *lf_optset_get(const lf_option *table, char *const *text, const char *name);

/* Largest finite magnitude a derivative is allowed to reach. */
#define LF_BIG 1e300

/* x clamped to [-LF_BIG, LF_BIG]: derivatives that diverge at detachment
 * stay finite (a NaN, which no model should make, becomes LF_BIG). */
static inline double
lf_capped(double x)
{
    /* as two selections, NaN to LF_BIG: a minimum and a maximum the
     * processor takes without a branch */
    x = x < LF_BIG ? x : LF_BIG;
    return x > -LF_BIG ? x : -LF_BIG;
}

/* x^(-1/3) for 1e-300 <= x <= 1e300 without a library call (glibc's cbrt
 * is slower than a log and an exp): a first guess from the bits of x, its
 * exponent divided by -3 (0x5540... is 1023 * 4/3 in the exponent field,
 * lowered to even out the guess's error, at most 4%), then four Newton
 * steps y <- y (4 - x y^3) / 3, each squaring the error: 2 ulp at most.
 * lf_inv_cbrt_seed is the first guess, lf_inv_cbrt_step one step. */
static inline double
lf_inv_cbrt_seed(double x)
{
    uint64_t i;
    double y;

    memcpy(&i, &x, sizeof i);
    i = UINT64_C(0x553F000000000000) - i / 3;
    memcpy(&y, &i, sizeof y);
    return y;
}

/* One Newton step of y = x^(-1/3). */
static inline double
lf_inv_cbrt_step(double x, double y)
{
    return y * ((4.0 - (x * y) * (y * y)) * (1.0 / 3.0));
}

static inline double
lf_inv_cbrt(double x)
{
    double y = lf_inv_cbrt_seed(x);

    /* written out: a loop here stays a loop, and its branch keeps the
     * processor from overlapping the roots of neighbouring points */
    y = lf_inv_cbrt_step(x, y);
    y = lf_inv_cbrt_step(x, y);
    y = lf_inv_cbrt_step(x, y);
    y = lf_inv_cbrt_step(x, y);
    return y;
}

/* x^(2/k) for x > 0: exact or square roots for k = 1, 2, 4, x lf_inv_cbrt(x)
 * for k = 3 (within a few ulp of pow), pow otherwise. */
static inline double
lf_pow_2k(double x, double k)
{
    if (k == 2.0)
        return x;
    if (k == 1.0)
        return x * x;
    if (k == 4.0)
        return sqrt(x);
    if (k == 3.0 && x >= 1e-300 && x <= 1e300)
        return x * lf_inv_cbrt(x);
    return pow(x, 2.0 / k);
}

/* The bits of a double, and the double of some bits (IEEE 754). */
static inline uint64_t
lf_bits(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static inline double
lf_double(uint64_t b)
{
    double x;
    memcpy(&x, &b, sizeof x);
    return x;
}

/* fmax and fmin as the C library defines them for NaN (the other argument),
 * inline: glibc's are calls, and the fit's loops over points make thousands
 * of them. */
static inline double
lf_fmax(double a, double b)
{
    return a > b || isnan(b) ? a : b;
}

static inline double
lf_fmin(double a, double b)
{
    return a < b || isnan(b) ? a : b;
}

/* lf_model_eval for a caller that evaluates one curve again and again
 * (a fit): roots, LF_MODEL_ROOTS_SIZE(n) numbers the caller owns for that
 * curve (roots[0] = NAN before the first call), keeps what the model's
 * inversion found (the exact model: each point's ln tau, its slopes and
 * the parameters it was for) so that the next call starts each point
 * there.  The answers equal lf_model_eval's to rounding; models without
 * roots ignore the buffer. */
#define LF_MODEL_ROOTS_HEAD 3
#define LF_MODEL_ROOTS_SIZE(n) (LF_MODEL_ROOTS_HEAD + 6 * (size_t) (n))
int lf_model_eval_roots(const lf_model *m, const lf_material *mat, lf_branch branch,
                        size_t n, const double *delta, lf_eval *out, double *roots);

/* --model auto once per probe and layer (src/batch.c, fit/choose.c).  A
 * batch's curves of one probe and layer form a group; the model choice of
 * some (its first LF_GROUP_REFS in plan order, and regularly after them) is
 * made by each curve's own rule and recorded; each other curve's is made
 * from the LF_GROUP_REFS records made last before it where they settle it,
 * else by the curve's own rule. */
#define LF_GROUP_REFS 8
typedef struct {
    lf_probe probe;         /* the curve's, as read */
    int ok, half_ok;        /* the thin-layer (half-space) bias was assessed */
    double thin, half;      /* their largest |bias| / se at the thin fit */
    double snr;             /* sqrt(n) * largest |force| / noise sd */
    double ab_lo;           /* a/b where its contact starts, at the thin fit */
    double w, Estar;        /* the thin fit's material */
} lf_group_ref;

struct lf_model_group {
    lf_group_ref *record;       /* non-NULL: one of the first curves: its own
                                   choice is made and recorded here */
    const lf_group_ref *ref;    /* else the first curves' records */
    size_t nref;
};

#endif
