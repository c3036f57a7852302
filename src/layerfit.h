/* layerfit.h: the public interface of liblayerfit.
 *
 * layerfit measures the work of adhesion w, the effective modulus
 * E* = E/(1-nu^2) and, where the data can tell, Poisson's ratio nu of a thin
 * elastic layer on a rigid substrate from indentation curves taken with
 * rigid axisymmetric power-law probes f(r) = r^k / (k R^(k-1)).
 *
 * Data flows one way: CSV + units at the edge -> curves in SI -> forward
 * model -> fitter -> result.  Every quantity crossing this interface is in SI
 * units (m, N, Pa, J/m^2, s).  Indentation delta is positive into the layer,
 * force P positive when compressive (adhesive forces are negative).
 *
 * Conventions for every function below:
 *  - the return value is a status, LF_OK (0) on success; lf_strerror() names
 *    it.  Where a function takes an lf_error *, a failure also fills it with
 *    a message (and the file, line and column where the cause sits, if any);
 *    passing NULL is allowed.
 *  - the library never prints and never exits.
 *  - objects made by an _alloc or _read function are owned by the caller and
 *    released with the matching _free, which accepts NULL and half-built
 *    objects.  Pointers returned inside an object stay owned by that object.
 */
#ifndef LAYERFIT_H
#define LAYERFIT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LF_VERSION "0.1.0"

/* LF_API marks what liblayerfit exports: the library is built with
 * -fvisibility=hidden, so that its shared and static forms export exactly
 * the functions and tables this header declares. */
#ifndef LF_API
#if defined(__GNUC__) && __GNUC__ >= 4
#define LF_API __attribute__((visibility("default")))
#else
#define LF_API
#endif
#endif

/* ------------------------------------------------------------------------
 * Status codes and error reports
 * --------------------------------------------------------------------- */

enum {
    LF_OK = 0,
    LF_EINVAL,     /* a parameter or argument outside its domain */
    LF_ENOMEM,     /* out of memory */
    LF_EIO,        /* a file could not be opened or read */
    LF_EFORMAT,    /* a file's content is malformed */
    LF_EUNIT,      /* a unit is unknown or of the wrong dimension */
    LF_EDATA,      /* data too few or degenerate for the task */
    LF_ENOCONV,    /* an iteration did not converge (not an error in input) */
    LF_ENUMERIC    /* a numerical failure (singular system, non-finite value) */
};

/* Where and why something failed.  line and column are 1-based, 0 when not
 * applicable; file is empty when not applicable. */
typedef struct {
    int status;
    char file[512];
    long line;
    long column;
    char msg[512];
} lf_error;

/* The library's LF_VERSION, as it was built (a program or binding loaded
 * against another header can compare). */
LF_API const char *lf_version(void);

/* A short constant name of a status code ("invalid argument", ...). */
LF_API const char *lf_strerror(int status);

/* Clear an error report (status LF_OK, empty strings). Accepts NULL. */
LF_API void lf_error_clear(lf_error *err);

/* Warnings collected by readers and the fitter for the caller to show.
 * Each message is owned by the list. */
typedef struct {
    size_t n;
    char **msg;
} lf_warnings;

LF_API void lf_warnings_free(lf_warnings *w); /* frees the messages, not w itself */

/* ------------------------------------------------------------------------
 * Units (udunits2)
 * --------------------------------------------------------------------- */

typedef enum {
    LF_Q_LENGTH,      /* m */
    LF_Q_FORCE,       /* N */
    LF_Q_ADHESION,    /* J/m^2 = N/m (work of adhesion) */
    LF_Q_PRESSURE,    /* Pa (modulus, strength) */
    LF_Q_TIME,        /* s */
    LF_Q_DIMENSIONLESS,
    LF_Q_STIFFNESS,   /* N/m (cantilever spring constant) */
    LF_Q_SENS_VOLT,   /* m/V (deflection sensitivity of a voltage signal) */
    LF_Q_SENS_AMP,    /* m/A (deflection sensitivity of a current signal) */
    LF_Q_VOLTAGE,     /* V (a raw signal) */
    LF_Q_CURRENT,     /* A (a raw signal) */
    LF_Q_ANGLE        /* rad (a probe's half-angle: "35deg", "35°", "0.61rad") */
} lf_quantity;

/* The SI unit symbol of a quantity ("m", "N", "J/m^2", "Pa", "s", ""). */
LF_API const char *lf_quantity_si(lf_quantity q);

/* Parse a number with its unit ("1um", "10 mJ/m2", "1.5e9 Pa", "1 µm") into
 * SI.  A bare number is accepted only for LF_Q_DIMENSIONLESS.  Fails with
 * LF_EUNIT (unknown unit or wrong dimension) or LF_EINVAL (not a number, or
 * not finite); err->msg says which. */
LF_API int lf_units_parse(const char *text, lf_quantity q, double *si, lf_error *err);

/* The factor that converts a value in `unit` ("nm", "uN", "mN", "µm") into
 * SI for quantity q (value_SI = factor * value).  Offsets (degC) are refused. */
LF_API int lf_units_factor(const char *unit, lf_quantity q, double *factor, lf_error *err);


/* ------------------------------------------------------------------------
 * Forward models
 * --------------------------------------------------------------------- */

typedef enum {
    LF_BASE_FRICTIONLESS = 0, /* layer slides freely on the rigid base */
    LF_BASE_BONDED = 1        /* layer bonded to the rigid base */
} lf_base;

/* The branch a curve's points follow, which is also the segment of a lab
 * curve they come from (lf_segment below is the same enum). */
typedef enum {
    LF_BRANCH_UNLOAD = 0,     /* retract / withdraw: contact kept down to detachment */
    LF_BRANCH_LOAD = 1        /* approach / extend: contact made at delta = 0 */
} lf_branch;

/* How a probe's shape is stated (lf_probe.tip).  Every shape but the
 * sphere is a power law f(r) = B r^k, B its prefactor in m^(1-k)
 * (lf_probe_prefactor). */
typedef enum {
    LF_TIP_POWER = 0, /* f = B r^k with B as stated, else B = 1/(k R^(k-1))
                         from R (k = 2: a paraboloid of radius R) */
    LF_TIP_CONE,      /* k = 1, a cone of half-angle `angle`: f = r cot(angle) */
    LF_TIP_BERKOVICH, /* k = 1, a Berkovich pyramid as its equivalent cone, the
                         cone of the same area-to-depth ratio (24.5): half-angle
                         70.3 deg (Oliver & Pharr 1992, J. Mater. Res. 7:1564;
                         Fischer-Cripps, Nanoindentation) */
    LF_TIP_PYRAMID,   /* k = 1, a four-sided pyramid of face half-angle `angle`
                         as the cone of the same projected area at every depth,
                         tan(alpha) = 2 tan(angle) / sqrt(pi) (Bilodeau 1992,
                         J. Appl. Mech. 59:519; Rico et al. 2005, Phys. Rev. E
                         72:021914) */
    LF_TIP_SPHERE     /* k = 2, a sphere of radius R: f = R - sqrt(R^2 - r^2),
                         contact radius a < R, no assumption a << R */
} lf_tip;

/* What is known about one probe and the layer under it.  A probe zeroed
 * beyond its first four members is the power law of R. */
typedef struct {
    double k;        /* profile exponent, > 0 */
    double R;        /* reference length of the profile, m, > 0; unused (NaN
                        allowed) by a cone, a pyramid, or a stated B */
    double b;        /* layer thickness, m, > 0 */
    lf_base base;    /* interface with the rigid substrate */
    lf_tip tip;      /* the shape (LF_TIP_POWER by default) */
    double angle;    /* LF_TIP_CONE: its half-angle; LF_TIP_PYRAMID: its face
                        half-angle; rad, in (0, pi/2); else unused */
    double B;        /* LF_TIP_POWER: the prefactor of f = B r^k, m^(1-k), or
                        0: from R; else unused */
} lf_probe;

/* The profile's prefactor B of f = B r^k, m^(1-k): as stated, from R
 * (1/(k R^(k-1))), or cot of the (equivalent) cone's half-angle; for a
 * sphere its apex's paraboloid, 1/(2R).  NaN for a probe without one. */
LF_API double lf_probe_prefactor(const lf_probe *probe);
/* The half-angle of a k = 1 tip's (equivalent) cone, rad; NaN for others. */
LF_API double lf_probe_cone_angle(const lf_probe *probe);
/* A tip's name ("power", "cone", "berkovich", "pyramid", "sphere"), and the
 * tip of a name (those and "paraboloid", the power law with k = 2), with
 * the k the name implies (*k: 1, 2, or NaN when it implies none; may be
 * NULL); -1 for an unknown name. */
LF_API const char *lf_tip_name(lf_tip tip);
LF_API int lf_tip_find(const char *name, double *k);
/* 1 when the probe's shape is stated by R (a power law without a stated
 * B, a sphere); 0 when R is unused (a cone, a pyramid, a stated B). */
LF_API int lf_probe_uses_R(const lf_probe *probe);

/* The material: what a fit estimates. */
typedef struct {
    double w;        /* work of adhesion, J/m^2, >= 0 */
    double Estar;    /* effective modulus E/(1-nu^2), Pa, > 0 */
    double nu;       /* Poisson's ratio, [0, 0.5); used by bonded layers */
} lf_material;

/* The model at one indentation: force, contact radius and derivatives.
 * Out of contact every member is 0.  Derivatives are those of P; they are
 * finite wherever the point is (for k > 2 they grow like delta1^(2/k-1) at
 * detachment and are capped at a large finite value there). */
typedef struct {
    double P;          /* force, N */
    double a;          /* contact radius, m */
    double dP_ddelta;  /* N/m */
    double dP_dlogw;   /* dP/d(ln w), N */
    double dP_dlogE;   /* dP/d(ln E*), N */
    double dP_dnu;     /* dP/dnu, N (0 for frictionless layers) */
} lf_eval;

/* Derived quantities of a model at given probe and material. */
typedef struct {
    double delta_detach; /* end of contact under displacement control on
                            unloading, m (thin layer: -c) */
    double P_detach;     /* force there, N */
    double a_detach;     /* contact radius there, m */
    double delta_po;     /* force-controlled pull-off indentation, m */
    double P_po;         /* pull-off force (negative), N */
    double a_po;         /* contact radius at pull-off, m */
    double sigma_po;     /* mean tension |P_po| / (pi a_po^2), Pa */
    double P_jump;       /* force on making contact when loading, N */
    double c;            /* thin layer: offset sqrt(2 b w/(Z E*)), m; else 0 */
} lf_pulloff;

typedef struct lf_model lf_model;

/* Which layers a model is meant for: what the `auto` choice, the b/a
 * warnings and the help text go by (never the model's name). */
typedef enum {
    LF_SCOPE_ANY = 0,        /* any thickness: the reference others are judged by */
    LF_SCOPE_THIN = 1,       /* assumes a thin layer, b << a */
    LF_SCOPE_HALFSPACE = 2   /* assumes a thick layer, b >> a */
} lf_model_scope;


/* A forward model is one entry of this table.  Entries share one contract:
 *  alloc  prepares state for one probe (may be NULL when none is needed);
 *  eval   fills out[0..n-1] for indentations delta[0..n-1]; must not
 *         allocate; returns LF_EINVAL for materials outside the domain;
 *  pulloff fills the derived quantities;
 *  prepare (may be NULL) readies the state for nu in [nu_lo, nu_hi], so
 *         that eval needs nothing more (lf_model_prepare).
 * Adding a model is one file and one line in lf_model_types (src/model.c). */
typedef struct {
    const char *name;        /* "thin", "exact", "halfspace" */
    const char *description; /* one line for reports */
    int (*alloc)(void **state, const lf_probe *probe, lf_error *err);
    void (*free)(void *state);
    int (*eval)(void *state, const lf_probe *probe, const lf_material *mat,
                lf_branch branch, size_t n, const double *delta, lf_eval *out);
    int (*pulloff)(void *state, const lf_probe *probe, const lf_material *mat,
                   lf_pulloff *out);
    int cost;                /* rank of a fit's cost, 0 = cheapest */
    lf_model_scope scope;    /* the layers it is meant for */
    double k_above;          /* needs k > k_above (0: any k > 0) */
    int uses_tables;         /* 1: set-up may build tables (kept on disk) */
    int (*prepare)(void *state, const lf_probe *probe, double nu_lo,
                   double nu_hi, lf_error *err);
    double nu_max;           /* bonded layers: nu <= nu_max (0: any nu < 0.5) */
} lf_model_type;

LF_API extern const lf_model_type lf_model_thin;      /* the seed paper, b << a */
LF_API extern const lf_model_type lf_model_exact;     /* any thickness (Nystrom tables) */
LF_API extern const lf_model_type lf_model_halfspace; /* b -> infinity, needs k > 1/2 */

/* The table of all models, NULL-terminated, and lookup by name (NULL when
 * no model has that name; the entries are static, never freed). */
LF_API extern const lf_model_type *const lf_model_types[];
LF_API const lf_model_type *lf_model_type_find(const char *name);

/* Check a probe and a material against the domain every model shares
 * (k > 0, R > 0 where the shape uses it, b > 0, w >= 0, E* > 0,
 * 0 <= nu < 0.5 for bonded layers, everything finite; a tip's k and
 * angle).  A k = 1 power law needs a stated B: R does not shape a cone.
 * LF_EINVAL with a message naming the parameter. */
LF_API int lf_probe_check(const lf_probe *probe, lf_error *err);
LF_API int lf_material_check(const lf_material *mat, lf_base base, lf_error *err);

/* Whether model m can be evaluated for material mat where its curve lives
 * (from detachment over ten pull-off widths): the pull-off and the
 * unloading branch there finite, an adhesive material pulling off, the
 * deepest point pressing.  Each model computes powers of its lengths in
 * double precision, so far from k = 2, or with lengths far from the
 * micrometre, its numbers can leave double precision: such a region is
 * LF_EINVAL with a message that names the model, k, R, b, w and E*.
 * lf_model_check_probe checks a model type for a probe alone, with the
 * seed paper's material (w = 10 mJ/m^2, E* = 1 GPa, nu = 0.3), for a fit
 * whose material is not known yet. */
LF_API int lf_model_check_region(const lf_model *m, const lf_material *mat, lf_error *err);
LF_API int lf_model_check_probe(const lf_model_type *type, const lf_probe *probe,
                                lf_error *err);

/* A model bound to one probe.  lf_model_alloc copies the probe and returns
 * a new object owned by the caller (NULL with err filled on a bad probe or
 * no memory); lf_model_free releases it (NULL allowed).  The getters return
 * pointers owned by the model.  lf_model_eval fills out[0..n-1] (caller's
 * array) for the indentations delta[0..n-1], does not allocate, and fails
 * with LF_EINVAL for a material outside the domain; lf_model_pulloff fills
 * *out.  A model may be shared by threads for eval and pulloff (they only
 * read it). */
LF_API lf_model *lf_model_alloc(const lf_model_type *type, const lf_probe *probe,
                         lf_error *err);
LF_API void lf_model_free(lf_model *m);
LF_API const lf_model_type *lf_model_get_type(const lf_model *m);
LF_API const lf_probe *lf_model_get_probe(const lf_model *m);
LF_API int lf_model_eval(const lf_model *m, const lf_material *mat, lf_branch branch,
                  size_t n, const double *delta, lf_eval *out, lf_error *err);
LF_API int lf_model_pulloff(const lf_model *m, const lf_material *mat,
                     lf_pulloff *out, lf_error *err);
/* Ready the model for materials with nu in [nu_lo, nu_hi] (bonded layers;
 * ignored for frictionless ones): the exact model resolves the tables of
 * those nu into the model object here (reading or building them, which may
 * take a while the first time), so that lf_model_eval takes no lock and
 * allocates nothing.  Without it the exact bonded model resolves the
 * tables of a nu on the first evaluation that needs them (once per model).
 * Safe to call from several threads. */
LF_API int lf_model_prepare(lf_model *m, double nu_lo, double nu_hi, lf_error *err);
/* The cheapest model of a scope in lf_model_types (NULL if none). */
LF_API const lf_model_type *lf_model_type_cheapest(lf_model_scope scope);

/* What `layerfit model --summary` and `--json` report of model m at one
 * material: the pull-off and detachment (lf_model_pulloff), Z, with a
 * theoretical strength sigma_th (NaN: none) the critical thickness of
 * Eq. (19) and b_cr/a_po there (Eq. 20; NaN without sigma_th or w = 0),
 * and the range a curve is drawn over by default: from detachment over
 * ten pull-off widths, [from, from + width]. */
typedef struct {
    lf_probe probe;
    lf_material mat;
    const lf_model_type *type;
    lf_pulloff pulloff;
    double Z;
    double sigma_th;       /* as given, or NaN */
    double b_cr;           /* m, or NaN */
    double b_cr_over_a;    /* or NaN */
    double from, width;    /* the default range of a curve, m */
} lf_model_summary;

LF_API int lf_model_summarise(const lf_model *m, const lf_material *mat, double sigma_th,
                              lf_model_summary *s, lf_error *err);
/* The summary as the JSON of `layerfit model --json` (SI, null for NaN),
 * into *json (lf_free). */
LF_API int lf_model_summary_json(const lf_model_summary *s, char **json, lf_error *err);

/* Closed-form helpers of the thin-layer model (seed paper). */
LF_API double lf_thin_Z(lf_base base, double nu);      /* 1, or (1-nu)^2/(1-2nu) */
LF_API double lf_thin_dlogZ_dnu(lf_base base, double nu);
/* Critical thickness below which the mean pull-off tension reaches the
 * theoretical strength sigma_th (Eq. 19, with M = Z E*). */
LF_API double lf_thin_b_critical(double k, double w, double M, double sigma_th);
/* Exact layer model helpers (src/model_exact.c).
 * lf_exact_thin_ratio: exact over thin-layer adhesiveless force P1 at the
 * same contact radius a = tau b, for the exact model's tables (bonded nu
 * up to 0.4995).  lf_exact_thin_difference: along the exact model's
 * unloading branch for a/b in [ab_min, ab_max] (clipped below at
 * detachment), max |P_thin(delta) - P_exact(delta)| / max |P_exact|, both
 * at the same indentation delta; what the `auto` model choice weighs. */
LF_API int lf_exact_thin_ratio(double k, lf_base base, double nu, double tau,
                        double *ratio_P1, lf_error *err);
LF_API int lf_exact_thin_difference(const lf_probe *probe, const lf_material *mat,
                             double ab_min, double ab_max, double *max_rel,
                             lf_error *err);
/* The exact model's forces P[i] at indentations delta[i] of a curve whose
 * contact lies wholly beyond a/b = 100, where the model is the thin-layer
 * form times exp(alpha/tau + beta/tau^2) matched at a/b = 100: from the
 * frictionless table when it is at hand, else from one solve there, so no
 * table is built (what the `auto` choice uses for very thin layers).  Equal
 * to the model's forces to rounding (frictionless) or to the tables'
 * interpolation in nu, ~1e-7 (bonded).  LF_EDATA when a point is not beyond
 * 100 (or past the thin-layer detachment on unloading). */
LF_API int lf_exact_far_eval(const lf_probe *probe, const lf_material *mat,
                      lf_branch branch, size_t n, const double *delta,
                      double *P, lf_error *err);
/* Classical half-space JKR pull-off contact radius of a sphere of radius R,
 * (9 pi R^2 w / (8 E*))^(1/3), for comparison. */
LF_API double lf_jkr_sphere_a_po(double R, double w, double Estar);


/* ------------------------------------------------------------------------
 * Fitting (fit/): shared material, per-curve nuisance parameters
 *
 * The measured force of curve j at instrument depth z is modelled as
 *     F = P(delta; w, E*, nu, probe_j) + F0_j + s_j delta,  delta = z - z0_j
 * with P the forward model, z0_j the contact point, F0_j the force offset
 * (the baseline's force at the contact point) and s_j an optional baseline
 * slope.  w, E* and nu are shared by all
 * curves.  Residuals are weighted by each curve's noise level sigma_j,
 * estimated from the data without the model (the spread of second
 * differences of the force, a robust median estimate that assumes white
 * noise); standard errors are then scaled by sqrt(chi2/dof), so they stay
 * honest when that estimate is off, and chi2/dof itself tells how well the
 * model describes the data (about 1 when it does).
 *
 * Ownership: lf_fit_alloc keeps pointers to the caller's curve arrays
 * (depth, force, name), which must outlive the lf_fit; everything in an
 * lf_fit_result is owned by it and released by lf_fit_result_free.
 * A fit object is not shared between threads; separate objects are
 * independent (no global state).
 * --------------------------------------------------------------------- */

typedef enum {
    LF_PARAM_AUTO = 0,   /* free where the plan determines it, else held */
    LF_PARAM_FREE,       /* always fitted */
    LF_PARAM_FIXED       /* held at value */
} lf_param_mode;

/* What is known of one material parameter before the fit. */
typedef struct {
    lf_param_mode mode;
    double value;        /* SI: the fixed value (FIXED), the value held when
                            AUTO finds it undetermined, or the prior mean */
    double prior_sd;     /* nu only: sd of a Gaussian prior at value, or NaN */
    double guess;        /* SI: a starting value when fitted, or NaN
                            (default): the automatic guess only.  The
                            offsets are profiled at the given material;
                            the fit is repeated from the automatic guess
                            and the lower cost wins (a warning says when
                            that was the automatic one) */
} lf_fit_param;

typedef enum {
    LF_JAC_ANALYTIC = 0, /* derivatives from the forward model */
    LF_JAC_FORWARD,      /* GSL forward finite differences */
    LF_JAC_CENTRAL       /* GSL central finite differences */
} lf_jacobian;

/* How residuals count: least squares, or a robust loss solved by
 * iteratively reweighted least squares (points far from the model, in
 * units of their curve's noise sd, get less weight). */
typedef enum {
    LF_LOSS_LINEAR = 0,  /* least squares (default) */
    LF_LOSS_HUBER,       /* quadratic within loss_scale sd, linear beyond */
    LF_LOSS_CAUCHY       /* log(1 + (r/loss_scale)^2): far points hardly count */
} lf_loss;

/* "linear", "huber", "cauchy"; lf_loss_find returns -1 for an unknown name. */
LF_API const char *lf_loss_name(lf_loss loss);
LF_API int lf_loss_find(const char *name);

typedef struct {
    const lf_model_type *model; /* forward model of every curve that names
                                   none itself (default lf_model_thin) */
    const char *method;         /* trust-region method: "lm" (default),
                                   "lmaccel", "dogleg", "ddogleg", "subspace2D" */
    lf_jacobian jacobian;
    lf_fit_param w;             /* default AUTO (= free) */
    lf_fit_param Estar;         /* default AUTO (= free) */
    lf_fit_param nu;            /* default AUTO: fitted where the plan
                                   determines it (bonded and frictionless
                                   curves together, or E* held), else held
                                   at nu.value, which is NaN by default:
                                   then a bonded curve that depends on nu
                                   is refused (LF_EDATA), never fitted at
                                   an assumed nu.  Bonded nu >= 0.4995 is
                                   refused unless the model states a limit
                                   it holds to (exact: 0.4995) */
    int fit_slope;              /* 1: fit a baseline slope s_j per curve */
    size_t max_iter;            /* default 200 */
    double xtol, gtol, ftol;    /* GSL convergence tests (defaults 1e-11,
                                   1e-12, 0) */
    double rcond;               /* identifiability: a direction of the
                                   column-scaled Jacobian with singular value
                                   below rcond * the largest is not
                                   determined (default 1e-7) */
    double max_b_over_a;        /* warn where b/a exceeds this (default 0.1) */
    lf_loss loss;               /* default LF_LOSS_LINEAR */
    double loss_scale;          /* robust losses: in units of each curve's
                                   noise sd; NaN (default) for the usual
                                   constants with 95% efficiency on Gaussian
                                   noise, 1.345 (Huber) and 2.385 (Cauchy) */
} lf_fit_settings;

LF_API lf_fit_settings lf_fit_settings_default(void);

/* Names of the trust-region methods, NULL-terminated, for help texts. */
LF_API extern const char *const lf_fit_methods[];

/* One curve to fit: data in SI and what is known of the probe. */
typedef struct {
    const char *name;       /* label for reports (a file path), may be NULL */
    size_t n;
    const double *depth;    /* instrument depth z, m, positive into layer */
    const double *force;    /* measured force, N */
    lf_probe probe;
    lf_branch branch;       /* which branch the points follow */
    double z0;              /* contact point if known, m; NaN = fitted */
    double F0;              /* force offset if known, N; NaN = fitted */
    const lf_model_type *model; /* this curve's forward model; NULL = the
                                   settings' model (so a zeroed curve keeps
                                   the old behaviour) */
} lf_fit_curve;

/* An estimate of one material parameter. */
typedef struct {
    double value;           /* SI; NaN when not determined */
    double se;              /* standard error, SI; NaN when fixed or not
                               determined */
    double ci95[2];         /* 95% interval (log-normal for w and E*,
                               normal clipped to [0, 0.5] for nu); for an
                               upper bound only: [0, bound]; after a
                               profile that does not close, the side it
                               closes on and NaN for the other (value and
                               se then NaN, determined 0) */
    int free;               /* 1 when fitted */
    int determined;         /* 1 when the data fix it (or it was fixed) */
    int upper_bound_only;   /* w: the data only bound it from above */
    const char *interval_method; /* how ci95 was found: "linear (Wald)",
                               "profile likelihood" (lf_fit_profile),
                               LF_INTERVAL_JUMP, LF_INTERVAL_UNCHECKED or
                               LF_INTERVAL_AT_STOP; NULL when not profiled
                               (linear) */
    const char *why;        /* when not determined for a reason the
                               identifiability notes do not give (a linear
                               interval that spans everything), that reason
                               in words (static); NULL otherwise */
} lf_fit_estimate;

/* interval_method of a fit that did not converge: the linear interval at
 * the point where it stopped (a profile's rises are measured from a
 * minimum, and that point is none; lf_fit_profile makes no refits then) */
#define LF_INTERVAL_AT_STOP "linear (Wald), where the fit stopped"
/* interval_method after lf_fit_profile(..., LF_PROFILE_LINEAR): the linear
 * interval, not checked against the profile */
#define LF_INTERVAL_UNCHECKED "linear (Wald), not checked"
/* A profile interval with a side kept at the linear end: there the profile
 * crossed its threshold by a jump of chi2 (a point crossing the model's
 * abrupt contact edge) nearer to the estimate than the linear end. */
#define LF_INTERVAL_JUMP "profile likelihood, linear where it jumps"

/* Many curves of one material: how much they differ (fit/hetero.c).
 *
 * What one curve's own fit says of the material: its estimates of w, E*
 * and nu with their standard errors, for the heterogeneity of several
 * curves and the summaries of a batch (lf_heterogeneity_of).  Indices
 * LF_MAT_W, LF_MAT_E, LF_MAT_NU. */
enum { LF_MAT_W = 0, LF_MAT_E = 1, LF_MAT_NU = 2 };
typedef struct {
    double value[3];        /* w (J/m^2), E* (Pa), nu: NaN where the curve's
                               own fit does not determine it (an upper bound
                               of w, a fixed or undetermined parameter) */
    double se[3];           /* their standard errors (the fit's, scaled by
                               its chi2/dof and noise correlation); NaN */
    double ci95[3][2];      /* their 95% intervals (profile likelihood where
                               the fit made one), NaN where not known: a
                               curve's weight in the analysis comes from the
                               side of its interval that faces the
                               population's mean (single-curve profiles of w
                               are often lopsided), else from se */
    double corr_wE;         /* correlation of w and E*, NaN unless both */
    lf_probe probe;         /* the curve's probe and layer */
} lf_curve_estimate;

/* What single-curve estimates of one parameter say of the population of
 * spots the curves sample (random effects: each curve's value is the
 * population's plus a spot's deviation of SD tau, measured with its own
 * standard error).  w and E* are analysed as the fit estimates them, in
 * ln w and ln E* (a log-normal population), nu as it is.  Every member
 * is NaN where it is not determined (why says why). */
typedef struct {
    size_t n;               /* curves whose own fit determines it */
    double mean, sd;        /* of those estimates, SI (sd: n - 1 divisor) */
    double median, q1, q3;  /* quartiles (linear interpolation) */
    double Q;               /* Cochran's Q, n - 1 degrees of freedom */
    double p_homogeneous;   /* P(chi2 >= Q) if the curves agree */
    double I2;              /* share of the spread beyond the errors, [0, 1] */
    double tau_rel;         /* between-curve SD on the analysed scale: of
                               ln w, ln E* (a relative SD), of nu itself;
                               REML (Viechtbauer 2005) */
    double tau_rel_ci95[2]; /* Q-profile interval (Viechtbauer 2007) */
    double tau;             /* between-curve SD in SI: tau_rel times the
                               population mean for w and E*, tau_rel for nu */
    double tau_ci95[2];
    double population_mean; /* the population's centre in SI: exp(mu) for w
                               and E* (a log-normal population's median, its
                               geometric mean), mu for nu */
    double population_ci95[2];  /* 95% interval, including tau
                               (Hartung-Knapp-Sidik-Jonkman: Student's t on
                               n - 1 degrees of freedom) */
    const char *why;        /* NULL, or why there is no population estimate
                               (static words) */
} lf_population_estimate;

typedef struct {
    size_t curves;          /* curves analysed (0: none) */
    /* all determined parameters together (a multivariate Cochran's Q over
     * the curves that determine them all, with each curve's covariance) */
    double Q, df, p_homogeneous, I2;
    lf_population_estimate w, Estar, nu;
    /* probes of different k, R, b or interface on the one material: */
    size_t probes;          /* distinct probes among the curves */
    size_t probes_tested;   /* probes that enter the comparison */
    double probes_p;        /* between-probe test, NaN when not made (fewer
                               than two probes, or one curve per probe:
                               then spot-to-spot variation and model error
                               cannot be told apart) */
    int probes_disagree;    /* probes_p < 0.05: model error, not spot-to-spot
                               variation */
    lf_probe probe_departs; /* the probe that departs most from the others */
    int probe_param;        /* LF_MAT_* where it departs most */
    double probe_diff;      /* its pooled estimate against the others':
                               relative (w, E*) or absolute (nu) */
    double probe_z;         /* that difference in standard errors */
} lf_heterogeneity;

typedef struct {
    const char *name;       /* the curve's label (not owned) */
    lf_probe probe;
    lf_branch branch;
    size_t n;
    double z0, z0_se;       /* m; se NaN when fixed or not determined */
    double F0, F0_se;       /* N */
    double slope, slope_se; /* N/m */
    int z0_free, F0_free, slope_free;
    double sigma;           /* noise sd used as the weight, N */
    double quantum;         /* the force's quantization step, N (0: the
                               forces lie on no lattice); sigma is never
                               below quantum / sqrt(12) */
    double rms;             /* rms residual, N */
    lf_pulloff pulloff;     /* predicted at the fitted material */
    double b_over_a_min_contact; /* b/a at the shallowest point in contact */
    double b_over_a_pulloff;     /* b/a at force-controlled pull-off */
    int pulloff_determined; /* 1 when w is determined (or fixed), so that the
                               pull-off and b/a there follow from the data;
                               0: pulloff and b_over_a_pulloff are the
                               model's where the fit ended, a w the data do
                               not fix (the reports say "not determined") */
    double *fitted;         /* n fitted forces, N */
    double *contact_radius; /* n contact radii, m */
    const char *model;      /* name of the forward model used (static) */
    char model_reason[240]; /* why that model (lf_fit_choose_driver), or
                               "as requested" */
    double thin_bias;       /* largest |bias| / se that the thin-layer model
                               of this curve alone would put on w, E* or nu
                               (linearised, see lf_fit_choose_driver); NaN
                               when not assessed */
    double thin_bias_se[3]; /* that bias, signed, of w, E*, nu in units of
                               their unscaled standard errors (se /
                               se_scale); 0 where not fitted, NaN when not
                               assessed */
    int model_by_group;     /* 1: the model was decided with the curve's
                               group of one probe and layer in a batch
                               (lf_choose_settings.group), 0: by the
                               curve's own assessment */
    /* Is this curve consistent with the material fitted to all?  The noise
     * sd comes from the data alone (not the model), so: */
    double chi2_per_point;  /* sum (residual/sigma)^2 / n: about 1 when the
                               model describes the curve */
    double p_value;         /* chance of a chi2 that high or higher if it
                               does (chi-square with n - its own parameters
                               degrees of freedom, the noise sd taken as
                               known: it is estimated to ~10%, so read
                               small p with chi2_per_point near 1 calmly) */
    double runs_z;          /* Wald-Wolfowitz runs test of the residuals'
                               signs in order of depth: about N(0, 1) if the
                               model fits, far below 0 for systematic misfit */
    double shape;           /* the residuals' shape over the noise: the rms
                               of their means over sixteenths of the curve
                               (in depth order) over the noise sd; noise of
                               any correlation shorter than a sixteenth
                               stays below 1 (fit/noise.c) */
    int consistent;         /* 0: the curve disagrees (runs_z < -4,
                               chi2_per_point > 4, or shape > 1: a
                               systematic shape larger than the noise,
                               whatever the correlation) */
    size_t downweighted;    /* robust loss: points weighted below 1/2 */
    /* The noise model of real data (fit/noise.c): filtered, oversampled
     * curves have correlated neighbouring residuals.  From the residuals'
     * autocorrelation in file order: */
    double corr_time;       /* integrated autocorrelation time, points (1 for
                               white noise) */
    double n_eff;           /* n / corr_time: independent points */
    double noise_sd;        /* the data's noise sd at the correlation lag
                               (model-free), N: >= sigma */
    double misfit_rel;      /* rms residual / the curve's force range */
    int agreement;          /* 2: within the noise; 1: systematic deviations
                               below 5% of the force range (the model
                               describes the shape, not within the noise);
                               0: disagrees */
    lf_curve_estimate alone;  /* this curve fitted alone (lf_fit_joint; its
                               values NaN when not) */
    lf_warnings warnings;
} lf_fit_curve_result;

/* What the all-thin-layer fit of the same curves gives, beside a fit made
 * (partly) with other models.  Relative differences are (thin - final) /
 * final; nu's is absolute.  done = 0 when not computed (every curve was
 * already thin, or the comparison was not asked for). */
typedef struct {
    int done;
    int converged;          /* the thin fit converged */
    lf_fit_estimate w, Estar, nu;
    double chi2;            /* of the thin fit */
    double w_rel, Estar_rel, nu_diff;
    double w_in_se;         /* (thin - final) w in standard errors of the
                               final w */
} lf_fit_thin_comparison;

/* Why a fit stopped (lf_fit_result.stop; stop_reason says it in words). */
typedef enum {
    LF_STOP_CONVERGED = 0,  /* at a minimum (converged = 1) */
    LF_STOP_ITERATIONS,     /* the limit of iterations per solve reached */
    LF_STOP_NO_PROGRESS,    /* no step lowers the cost, yet no minimum */
    LF_STOP_STALLED,        /* claimed converged, but a step still lowers
                               chi2 by more than the noise allows */
    LF_STOP_DEAD_PARAMETER, /* a parameter (not w) no longer changes the fit */
    LF_STOP_RAN_AWAY,       /* an offset ran far outside its curve's data:
                               the material is then not determined */
    LF_STOP_REWEIGHTING,    /* robust weights still moving */
    LF_STOP_DEGENERATE,     /* ended where the data determine none of the
                               material parameters fitted */
    LF_STOP_FAILED          /* the solver or the model failed numerically */
} lf_fit_stop;

/* Its name in reports and JSON ("converged", "iteration limit", ...). */
LF_API const char *lf_fit_stop_name(lf_fit_stop stop);

typedef struct {
    lf_fit_estimate w, Estar, nu;
    lf_fit_estimate M;      /* Z E* of the bonded curves (NaN if none) */
    size_t npar;            /* free parameters */
    char (*names)[32];      /* their names: "w", "E*", "nu", "z0[1]", ... */
    double *value;          /* npar values, SI */
    double *cov;            /* npar x npar covariance, SI, row-major; rows of
                               undetermined parameters are NaN.  NULL for a
                               fit of more than LF_FIT_DENSE_PARAMS free
                               parameters: read any entry with
                               lf_fit_result_cov, which works for both */
    double *corr;           /* npar x npar correlation (NULL with cov) */
    double *singular;       /* npar singular values of the column-scaled
                               Jacobian, relative to the largest; beyond
                               LF_FIT_DENSE_PARAMS free parameters only the
                               first (1) and the last (the smallest) are
                               computed, the others NaN */
    struct lf_fit_covariance *covariance;   /* where cov is NULL: the
                               covariance in block form (internal) */
    double chi2;            /* weighted sum of squares at the solution */
    size_t dof;             /* residuals - free parameters */
    double se_scale;        /* sqrt(chi2/dof * corr_time), the factor
                               applied to se */
    size_t profile_fits;    /* fits made by lf_fit_profile (0: none) */
    double corr_time;       /* the residuals' autocorrelation time, pooled
                               (1 for white noise; fit/noise.c) */
    size_t iterations, evaluations;
    int converged;
    lf_fit_stop stop;       /* why it stopped */
    char stop_reason[160];
    const char *method;     /* static strings */
    const char *model;      /* the curves' model name, or "mixed" */
    const char *loss;       /* "linear", "huber" or "cauchy" */
    size_t reweightings;    /* robust loss: reweighting rounds */
    size_t ncurves;
    lf_fit_curve_result *curves;
    size_t model_rounds;    /* fits made by lf_fit_choose_driver (1 else) */
    lf_fit_thin_comparison thin;
    lf_heterogeneity heterogeneity; /* how the curves differ (lf_fit_joint;
                               curves = 0 when not analysed) */
    lf_warnings identifiability; /* what the data determine, in words */
    lf_warnings warnings;        /* everything else worth saying */
} lf_fit_result;

typedef struct lf_fit lf_fit;

/* Check the settings and curves and allocate everything a fit needs. */
LF_API lf_fit *lf_fit_alloc(const lf_fit_settings *settings, size_t ncurves,
                     const lf_fit_curve *curves, lf_error *err);
/* Guess, fit and assess.  Fills res (free it with lf_fit_result_free) and
 * returns LF_OK on convergence, LF_ENOCONV when the fit stopped without
 * converging (res is still complete, with converged = 0 and the reason),
 * other statuses on errors (res is then empty). */
LF_API int lf_fit_run(lf_fit *fit, lf_fit_result *res, lf_error *err);
LF_API void lf_fit_free(lf_fit *fit);

/* Profile-likelihood 95% intervals of w, E* and nu (fit/profile.c) for a
 * result res of lf_fit_driver / lf_fit_choose_driver on these settings and
 * curves: each free, determined one is profiled at its linear (Wald)
 * endpoints, and where the rise of chi2 there is not 3.84 s^2 within 25%
 * (always: in any case) its interval is replaced by the profile's, which
 * may be asymmetric; e->interval_method names the method.  An upper side
 * the profile never closes marks w or E* not determined.  Costs a few fits
 * per parameter (res->profile_fits).  The threshold is s^2 F(1, n_eff - p)
 * (3.84 s^2 for many points) and the interval the hull of the values below
 * it.  First, in every mode, the search for the minimum (fit/descend.c):
 * chi2 along each determined parameter's linear path, 0.5 to 6 standard
 * errors either side; a point below res's chi2 restarts the fit there.  A
 * profile point below res's own chi2 (res stopped in a local minimum)
 * likewise: res is replaced by the fit continued from there (converged fits
 * only; a warning says so, the model choice's notes are kept).  A fit that
 * did not converge keeps its linear intervals, marked LF_INTERVAL_AT_STOP.
 * Where a linear interval is the one reported (a fit that did not converge,
 * a robust loss, LF_PROFILE_LINEAR), one that spans everything is no
 * estimate: a w or E* whose standard error exceeds its value (a log-normal
 * 95% interval wider than a factor 50 each way), or a nu whose interval
 * covers all of [0, 0.5], is marked not determined (e->why says so). */
/* The modes of lf_fit_profile's `always`: the check by refits at the linear
 * endpoints (0), the profile in any case (1).  Either check is made only
 * where a cheap screen (chi2 along the linear path, the refits' first
 * Gauss-Newton step predicted, no fit) does not say that its refits would
 * bear out the linear interval; LF_PROFILE_SCREEN (`fit --batch`) is now
 * the same as LF_PROFILE_CHECK. */
#define LF_PROFILE_CHECK 0
#define LF_PROFILE_ALWAYS 1
#define LF_PROFILE_SCREEN 2
/* The linear intervals reported, marked LF_INTERVAL_UNCHECKED: the
 * search of LF_PROFILE_CHECK is made all the same, its refits being where
 * a lower minimum is found, so that the estimate does not depend on the
 * intervals asked.  LF_PROFILE_REPORT_LINEAR or'ed into a mode does the
 * same after that mode's search (LF_PROFILE_SCREEN for a batch). */
#define LF_PROFILE_LINEAR 3
#define LF_PROFILE_REPORT_LINEAR 8
/* Or'ed into a mode: the threshold of each profile that is used is
 * calibrated by a parametric bootstrap (200 data sets from the fit, each
 * fitted free and held: some 400 fits per parameter), for likelihoods that
 * are not regular (points at the contact edge of a k > 2 probe).  Slow; off
 * in `layerfit fit`. */
#define LF_PROFILE_CALIBRATE 4
LF_API int lf_fit_profile(const lf_fit_settings *settings, size_t ncurves, const lf_fit_curve *curves,
                   lf_fit_result *res, int always, lf_error *err);
LF_API void lf_fit_result_free(lf_fit_result *res);
/* The covariance (SI) and correlation of free parameters a and b (indices
 * of res->names): res->cov's entry where it is held, else computed from the
 * blocks of a joint fit of many curves (each curve's offsets couple only to
 * the material, so nothing of size npar x npar is kept); NaN where either
 * is not determined or out of range. */
#define LF_FIT_DENSE_PARAMS 64
LF_API double lf_fit_result_cov(const lf_fit_result *res, size_t a, size_t b);
LF_API double lf_fit_result_corr(const lf_fit_result *res, size_t a, size_t b);
/* alloc + run + free */
LF_API int lf_fit_driver(const lf_fit_settings *settings, size_t ncurves,
                  const lf_fit_curve *curves, lf_fit_result *res,
                  lf_error *err);

/* Compare the analytic Jacobian with central differences at the material
 * mat (nu used for bonded curves) and the curves' z0 = 0, F0 = 0 unless
 * fixed; *max_rel_err is the largest difference relative to each column's
 * largest entry.  For tests and the curious. */
LF_API int lf_fit_check_jacobian(lf_fit *fit, const lf_material *mat,
                          double *max_rel_err, lf_error *err);

/* ------------------------------------------------------------------------
 * Choosing the forward model of each curve (fit/choose.c)
 *
 * The thin-layer closed form is cheap but wrong where b/a is not small, and
 * its error lands on w while the residuals still look fine (fitted to
 * curves of the exact layer model of Lebedev & Ufliand 1958, it leaves
 * residuals below 1% of the force while w moves by 10-70%).  So a curve is judged by what its model error does to the
 * material parameters, not by its residuals.  For curve j using model m,
 * with d_j = (P_exact - P_m)/sigma_j on the curve's points (zero on the
 * other curves) at the fitted parameters and J the weighted Jacobian of the
 * joint fit, the first-order bias of the parameters is
 *     bias_j = (J^T J)^+ J^T d_j,
 * compared with the standard errors se = sqrt(diag (J^T J)^+) (not scaled
 * by chi2/dof: the weights are the noise estimated from the data).  A set
 * of models is good enough when, for each fitted and determined w, E*, nu,
 * |sum of bias_j over the curves not using exact| < tol se.
 *
 * lf_fit_choose_driver: fit every curve with the thin-layer model from the
 * automatic guess; at the solution, while the summed bias exceeds tol, move
 * the curve with the largest bias up to the cheapest better model (thin ->
 * halfspace when its own bias is below tol and k > 1/2, else exact); refit
 * from the previous solution; repeat until nothing moves or max_rounds
 * refits.  Curves only move up, so it stops.  Curves that name their own
 * model (lf_fit_curve.model) keep it.  res is as from lf_fit_driver, with
 * curves[].model, model_reason and thin_bias filled, model_rounds the number
 * of fits, and res->thin the first (all-thin) fit when the final models are
 * not all thin and choose->thin_comparison is set.  Returns as
 * lf_fit_driver (the status of the final fit).
 * --------------------------------------------------------------------- */

typedef struct lf_model_group lf_model_group;

typedef struct {
    double tol;              /* bias allowed, in standard errors (0.2) */
    size_t max_rounds;       /* refits after the first fit (3) */
    int halfspace;           /* 1: the half-space model is a candidate (1) */
    int thin_comparison;     /* 1: fill res->thin (1) */
    int each;                /* 1: in a batch too, every curve decides
                                alone (0, default: once per probe and layer
                                where that settles it, lf_batch_run) */
    lf_model_group *group;   /* NULL (default): the curve decides alone; a
                                batch's group of curves of one probe and
                                layer (lf_batch_run), for a fit of one
                                curve */
} lf_choose_settings;

LF_API lf_choose_settings lf_choose_settings_default(void);

LF_API int lf_fit_choose_driver(const lf_fit_settings *settings,
                         const lf_choose_settings *choose, size_t ncurves,
                         const lf_fit_curve *curves, lf_fit_result *res,
                         lf_error *err);

/* Fit the same curves with the thin-layer model only (from the automatic
 * guess) and put the outcome beside res in res->thin; for a fit made with
 * other models by lf_fit_driver.  res must hold a completed fit. */
LF_API int lf_fit_compare_thin(const lf_fit_settings *settings, size_t ncurves,
                        const lf_fit_curve *curves, lf_fit_result *res,
                        lf_error *err);

/* ------------------------------------------------------------------------
 * Many curves of one material: how much they differ (fit/joint.c,
 * fit/hetero.c)
 *
 * A joint fit assumes that every curve probes the same material.  Real
 * samples vary from spot to spot, and then the joint fit's standard errors
 * say how well the model pins the material of these spots taken as one,
 * not what another set of spots would give.  So lf_fit_joint fits each
 * curve alone as well and measures how the curves differ:
 *
 *  1. each curve alone, with the joint fit's settings (its model the
 *     curve's own, the settings', or chosen for it alone when choose is
 *     given), with lf_fit_profile(LF_PROFILE_LINEAR): its estimates into
 *     res->curves[j].alone;
 *  2. the joint fit from the automatic guess (lf_fit_choose_driver when
 *     choose is given, else lf_fit_driver), and again from the pooled
 *     single fits (the material at the single fits' random-effects mean,
 *     each curve's offsets at its own fit's) with the models the first
 *     chose: the lower chi2 wins;
 *  3. lf_fit_profile(intervals): a lower chi2 found on any parameter's
 *     linear path or profile restarts the fit from there, whatever the
 *     intervals asked, then the intervals;
 *  4. lf_heterogeneity_of over the single-curve estimates into
 *     res->heterogeneity.
 * With one curve, steps 1, 2 (its second start) and 4 are skipped and
 * res->curves[0].alone holds the fit's own estimates.  Returns as
 * lf_fit_driver; res is complete on LF_OK and LF_ENOCONV.
 *
 * lf_heterogeneity_of: a random-effects meta-analysis of n single-curve
 * estimates per material parameter (w and E* in logs, where the fit
 * estimates them; nu as it is), over the curves whose own fit determines
 * it (lf_population_estimate): Cochran's Q and I^2, the between-curve SD
 * tau by restricted maximum likelihood (Viechtbauer 2005, J. Educ. Behav.
 * Stat. 30:261) with its Q-profile interval (Viechtbauer 2007, Stat. Med.
 * 26:37), and the population mean with the Hartung-Knapp-Sidik-Jonkman
 * interval (Hartung & Knapp 2001, Stat. Med. 20:1771; Sidik & Jonkman
 * 2002, Stat. Med. 21:3153), which keeps its coverage with few curves.
 * Where fewer than two curves determine a parameter alone (a k = 2 curve
 * without baseline cannot determine w), its population estimate is "not
 * determined from single curves" (why says so; no hierarchical fit is
 * made).  All parameters together: a multivariate Q over the curves that
 * determine them all, with each curve's covariance of ln w and ln E*.
 * Probes that differ (k, R, b or interface) are compared by their pooled
 * estimates, each with the spot-to-spot spread measured within the
 * probes: where they disagree beyond their errors (p < 0.05), that is
 * model error, not spot-to-spot variation, and the probe that departs most
 * is named.  I^2 is (Q - (n - 1)) / Q (Higgins & Thompson 2002).  out is
 * filled whole (scratch of n numbers is allocated and freed: LF_ENOMEM);
 * LF_EINVAL when n > 0 and each is NULL.
 *
 * lf_curve_estimate_of: the estimates of a fit of one curve (curves[0]'s
 * probe) as a single-curve estimate.
 * --------------------------------------------------------------------- */

LF_API int lf_fit_joint(const lf_fit_settings *settings, const lf_choose_settings *choose,
                        size_t ncurves, const lf_fit_curve *curves, int intervals,
                        lf_fit_result *res, lf_error *err);
LF_API int lf_heterogeneity_of(size_t n, const lf_curve_estimate *each, lf_heterogeneity *out,
                               lf_error *err);
LF_API void lf_curve_estimate_of(const lf_fit_result *r, lf_curve_estimate *e);

/* ------------------------------------------------------------------------
 * Model tables kept on disk (src/exact_cache.c)
 *
 * The exact model's tables (one per k and base, and per node of a nu grid
 * for bonded layers; about 0.1 s each to build) are kept between runs in
 * $XDG_CACHE_HOME/layerfit, else $HOME/.cache/layerfit, one file each,
 * written atomically.  A file is used only when its version, key, grid,
 * sizes and checksum match and every number is finite; a stale or corrupt
 * file is ignored and rewritten.  The cache is on unless the environment
 * variable LAYERFIT_NO_CACHE is set (non-empty and not "0") or
 * lf_cache_set_enabled(0) is called (process-wide, before the first model
 * is made).  Writing failures are not errors (the table is still used);
 * lf_cache_stats_get counts them: hits (tables read), misses (no file),
 * rejected (stale or corrupt files), written, write_failed.
 * --------------------------------------------------------------------- */

typedef struct {
    unsigned long hits, misses, rejected, written, write_failed;
} lf_cache_stats;

typedef struct {
    char name[256];          /* file name in the folder */
    long long bytes;         /* its size */
    int valid;               /* 1: usable by this version */
    char what[200];          /* the table it holds, or why it is not usable */
} lf_cache_entry;

LF_API void lf_cache_set_enabled(int on);
LF_API void lf_cache_stats_get(lf_cache_stats *stats);
/* The folder (whether or not it exists); LF_EINVAL when there is none. */
LF_API int lf_cache_dir(char *buf, size_t n, lf_error *err);
/* The table files in the folder (none when it does not exist); *entries is
 * the caller's, released with free(). */
LF_API int lf_cache_list(lf_cache_entry **entries, size_t *count, lf_error *err);
/* Remove the table files (and temporary files left by writers); the folder
 * and anything else in it stay. */
LF_API int lf_cache_clear(size_t *removed, lf_error *err);

/* ------------------------------------------------------------------------
 * Synthetic data (src/simulate.c)
 * --------------------------------------------------------------------- */

typedef struct {
    size_t points;          /* points per curve (default 300) */
    double delta_max;       /* deepest model indentation, m (default 50 nm) */
    double delta_min;       /* shallowest indentation, m, or NaN: then
                               -past_c * c (default NaN) */
    double past_c;          /* default 1.2: 20% of c past detachment */
    double noise;           /* Gaussian sd relative to the curve's largest
                               |force| (default 0) */
    double z0, F0;          /* offsets added: z = delta + z0, F = P + F0 */
    unsigned long seed;     /* gsl_rng_mt19937 seed (default 1) */
    lf_branch branch;       /* default unloading, written deep to shallow */
} lf_sim_settings;

LF_API lf_sim_settings lf_sim_settings_default(void);

/* Simulate ncurves curves of the model type for the material.  Curve j has
 * settings->points points, written into depth[j][..] and force[j][..]
 * (caller-owned arrays of that length); sigma[j] receives the noise sd in N
 * (may be NULL).  One generator seeded once draws the noise of all curves in
 * order, so a plan and a seed give the same data on every machine. */
LF_API int lf_simulate(const lf_sim_settings *settings, const lf_model_type *type,
                const lf_material *mat, size_t ncurves, const lf_probe *probes,
                double *const *depth, double *const *force, double *sigma,
                lf_error *err);

/* ------------------------------------------------------------------------
 * Experiment design: the Cramer-Rao bound (fit/crb.c)
 * --------------------------------------------------------------------- */

/* One curve of an experiment, as the bound sees it. */
typedef struct {
    const lf_model *model;   /* probe and forward model */
    lf_branch branch;
    size_t n;
    const double *delta;     /* true indentations, m */
    double sigma;            /* standard deviation of the force noise, N */
    int free_z0;             /* contact point estimated with the material */
    int free_F0;             /* force offset estimated with the material */
} lf_design_curve;

/* The smallest standard deviations any unbiased estimator can reach with
 * Gaussian noise: the inverse Fisher information at the truth.  w and E*
 * are bounded relatively (sd of ln w, ln E*); nu absolutely. */
typedef struct {
    double sd_logw;          /* ~ relative sd of w */
    double sd_logE;          /* ~ relative sd of E* */
    double sd_nu;            /* NaN when nu is not estimated */
    double corr_wE;          /* correlation of ln w and ln E* */
    double cov[3][3];        /* covariance of (ln w, ln E*, nu); nu row NaN if fixed */
    size_t nparams;          /* parameters counted, nuisance included */
} lf_crb_result;

/* Fisher information of w, E* (and nu when free_nu) together with the
 * nuisance parameters each curve declares free, inverted.  LF_EDATA when the
 * design does not determine them all (singular information). */
LF_API int lf_crb(const lf_design_curve *curves, size_t ncurves, const lf_material *truth,
           int free_nu, lf_crb_result *out, lf_error *err);

/* ------------------------------------------------------------------------
 * Lab data: curves and fit plans (readers in src/csv_curve.c, src/plan.c)
 * --------------------------------------------------------------------- */

/* A curve's segment is the branch its points follow: one enum. */
typedef lf_branch lf_segment;
#define LF_SEG_UNLOAD LF_BRANCH_UNLOAD   /* retract / withdraw */
#define LF_SEG_LOAD LF_BRANCH_LOAD       /* approach / extend */
#define LF_SEG_HOLD ((lf_segment) 2)     /* hold / pause / dwell at the deepest point:
                                            never fitted, reported */

typedef struct {
    char *key;
    char *value;
} lf_meta;

/* One force-depth curve in SI, points in file order. */
typedef struct {
    char *file;               /* path it was read from (the name given to
                                 lf_curve_parse when read from memory) */
    size_t n;                 /* number of points */
    double *depth;            /* instrument depth z, m (positive into layer) */
    double *force;            /* N */
    double *time;             /* s, or NULL when the file has no time */
    unsigned char *segment;   /* lf_segment of each point */
    long *line;               /* source line of each point, for messages */
    size_t nmeta;
    lf_meta *meta;            /* "# key: value" lines before the header, or
                                 the instrument's header lines (UTF-8) */
    /* What the reader found (src/reader.c and src/read_*.c): */
    const char *format;       /* the reader's name ("csv", "chiaro", ...) */
    double R;                 /* probe radius stated in the file, m, or NaN */
    double spring_constant;   /* cantilever k used for the conversions, N/m,
                                 or NaN when none was needed */
    double sensitivity;       /* deflection sensitivity used, m/V or m/A, or NaN */
    const char *spring_constant_source;  /* "file header", "option", or NULL */
    const char *sensitivity_source;      /* "file header", "option", or NULL */
    const char *sensitivity_unit;        /* "m/V" or "m/A" (with a sensitivity) */
    lf_warnings info;         /* what was detected, for `layerfit check`:
                                 columns and units, conversions, segments */
    /* Where the curve was taken, as its file states it (force maps): */
    double x, y;              /* position on the sample, m, or NaN */
    long grid_i, grid_j;      /* column and row on the map's grid (0-based), or -1 */
    long index;               /* its place in its file (0 for a file of one curve) */
} lf_curve;

/* A fit window (src/window.c): the part of a curve a fit takes.  Depth
 * bounds the indentation from the curve's contact point, force the force
 * above its baseline, both found without a model (lf_observe); each bound
 * in SI (m, N), or, when relative, a fraction of the deepest indentation
 * or the largest force (0.3 for 30%); NaN: open. */
typedef struct {
    double lo, hi;
    int relative;
} lf_range;

typedef struct {
    lf_range depth;
    lf_range force;
} lf_window;

/* One row of a fit plan: which curve, and what is known about it.
 * A value that the plan leaves open is NaN (nu) or empty (sample). */
typedef struct {
    char *file;               /* curve path, resolved against the plan */
    long line;                /* line of the row in the plan */
    lf_probe probe;
    double nu;                /* Poisson's ratio if the row gives one, else NaN */
    lf_segment segment;       /* which segment to fit (default unload) */
    char *sample;             /* material group, "" when not given */
    double z0;                /* contact point offset, m, if the plan fixes it, else NaN */
    double F0;                /* force offset, N, if the plan fixes it, else NaN */
    char *format;             /* the curve file's reader name, "" = sniffed */
    lf_window window;         /* the fit window of the row's curve (its
                                 depth_range and force_range cells), or all */
    long index;               /* which curve of a file of many (`file#N` or the
                                 index column), or -1: the file's only curve
                                 (lf_plan_expand: all of them) */
    struct lf_file *source;   /* the open file of the row's curve, kept by the
                                 plan (lf_plan_expand, lf_plan_open_files), or
                                 NULL */
    int text_export;          /* 1: lf_plan_open_files found no file of many
                                 curves there (a text export, read when the
                                 row is fitted): not sniffed again */
} lf_plan_row;               /* probe.R is NaN where the plan's R cell says
                                "header": the curve file's header gives it;
                                probe.b is NaN where the b and interface cells
                                are empty: no layer, for half-space fits only */

typedef struct {
    char *path;               /* the plan's own path */
    size_t n;
    lf_plan_row *rows;
    size_t nfiles;            /* files opened by lf_plan_expand or */
    struct lf_file **files;   /* lf_plan_open_files, closed by lf_plan_free */
    int of_files;             /* 1: made by lf_plan_of_files from files and a
                                 probe given by the caller, not read from a
                                 plan file (messages say so) */
} lf_plan;

/* Release a curve or a plan made by the readers below and everything it
 * holds (NULL allowed). */
LF_API void lf_curve_free(lf_curve *c);
LF_API void lf_plan_free(lf_plan *p);

/* How to read a curve file. */
typedef struct {
    const char *depth_unit;   /* unit of the depth column; NULL = from header */
    const char *force_unit;   /* unit of the force column; NULL = from header */
    int skip_bad_rows;        /* skip rows with missing cells (with a warning)
                                 instead of failing */
    const char *format;       /* reader name (lf_reader_types); NULL = sniffed */
    double spring_constant;   /* N/m, used when the file states none; NaN */
    double sensitivity;       /* m/V or m/A (sensitivity_per_amp), used when
                                 the file states none; NaN */
    int sensitivity_per_amp;  /* 1: sensitivity is in m/A, 0: in m/V */
} lf_read_opts;

/* Fill o with the defaults: units from the header, bad rows are errors,
 * format sniffed, no constants. */
LF_API void lf_read_opts_default(lf_read_opts *o);
/* Set o's spring constant ("0.032N/m") and deflection sensitivity
 * ("61nm/nA" or "50nm/V") from text, either may be NULL.  LF_EUNIT or
 * LF_EINVAL with a message naming the option on a bad value. */
LF_API int lf_read_opts_constants(lf_read_opts *o, const char *spring_constant,
                           const char *sensitivity, lf_error *err);

/* Read one curve file: layerfit's CSV (format in datasets/README.md) or an
 * instrument's export, the reader named by o->format or sniffed from the
 * first bytes (see lf_reader_types below).  On success *out is a
 * new curve owned by the caller (lf_curve_free) and warnings, if any, are
 * appended to warn (may be NULL).  On failure *out is NULL and err names the
 * file, line and column (column = character in the line, 1-based) with
 * LF_EIO, LF_EFORMAT, LF_EUNIT or LF_EDATA.  o may be NULL for defaults. */
LF_API int lf_curve_read(const char *path, const lf_read_opts *o, lf_curve **out,
                  lf_warnings *warn, lf_error *err);
/* The same from memory, feeding the CSV parser chunk bytes at a time
 * (0 = all at once); name is used in messages and stored as c->file. */
LF_API int lf_curve_parse(const char *buf, size_t len, size_t chunk, const char *name,
                   const lf_read_opts *o, lf_curve **out, lf_warnings *warn,
                   lf_error *err);

/* ------------------------------------------------------------------------
 * Files of many curves: force maps, QI data, force volumes (src/file.c)
 *
 * lf_file_open opens any curve file layerfit reads and lists its curves
 * without decoding them: a text export or a single binary curve holds one;
 * a JPK force map or QI file, a Bruker force volume or an AFM Workshop
 * mapping zip holds many.  A binary file is read by random access (pread),
 * never whole, and lf_file_curve decodes one curve at a time, so a loop
 * over the curves needs the memory of one.  Once a file is open,
 * lf_file_info and lf_file_curve may be called from several threads at
 * once.  lf_file_sha256 is the SHA-256 of the whole file, computed once
 * when it is opened.
 *
 * Naming one curve: "FILE#N" is curve N (0-based) of FILE, when no file
 * is named "FILE#N" itself; lf_curve_read, plans (or their `index` column)
 * and the command line take it.  lf_curve_read on a file of many curves
 * without an index fails, saying how many it holds and how to name one;
 * a joint fit (lf_fit_input_from_plan) likewise: each of its rows is one
 * curve.  lf_plan_expand makes one row per curve of such a file;
 * `layerfit fit --batch` fits each curve (lf_plan_open_files, then one fit
 * per row and curve).
 *
 * Ownership: the lf_file is the caller's (lf_file_close, NULL allowed);
 * each curve of lf_file_curve is the caller's (lf_curve_free).  The buffer
 * of lf_file_open_memory is not copied: it must outlive the file.
 * --------------------------------------------------------------------- */

typedef struct lf_file lf_file;

/* What a file states of one of its curves before it is decoded. */
typedef struct {
    double x, y;              /* position on the sample, m, or NaN */
    long grid_i, grid_j;      /* column and row on the map's grid, or -1 */
    size_t points;            /* points of all segments */
    size_t segment_points[3]; /* points per lf_segment (unload, load, hold) */
} lf_curve_info;

/* flags as for lf_input_open (0: a regular file; LF_INPUT_STREAM: also a
 * pipe or FIFO, read whole).  o may be NULL (defaults); o->format forces a
 * reader, else it is sniffed from the first bytes.  A text export is read
 * and checked here (its errors, with line and column, are lf_curve_read's);
 * an archive's listing is checked here, each curve when it is decoded.
 * Errors: LF_EIO, LF_EFORMAT, LF_EUNIT, LF_EDATA, LF_ENOMEM, naming path. */
LF_API int lf_file_open(const char *path, unsigned flags, const lf_read_opts *o, lf_file **out,
                 lf_warnings *warn, lf_error *err);
LF_API int lf_file_open_memory(const char *buf, size_t len, const char *name, const lf_read_opts *o,
                        lf_file **out, lf_warnings *warn, lf_error *err);
LF_API size_t lf_file_count(const lf_file *f);
LF_API const char *lf_file_format(const lf_file *f);     /* the reader's name */
LF_API const char *lf_file_sha256(const lf_file *f);     /* lowercase hex */
/* Curve i (0 <= i < count) as the file states it, without decoding it. */
LF_API int lf_file_info(const lf_file *f, size_t i, lf_curve_info *info, lf_error *err);
/* Curve i decoded into a new curve in SI (c->index = i; c->file is
 * "FILE#i" when the file holds several).  Warnings go to warn (may be NULL). */
LF_API int lf_file_curve(const lf_file *f, size_t i, lf_curve **out, lf_warnings *warn,
                  lf_error *err);
LF_API void lf_file_close(lf_file *f);
/* Split "FILE#N" into FILE (into file, n bytes) and N when no file of the
 * whole name exists but FILE does; else file = path, *index = -1.
 * LF_EINVAL when path does not fit in n bytes. */
LF_API int lf_curve_path_split(const char *path, char *file, size_t n, long *index);

/* Read a fit plan: one row per curve, `file,k,R,b,interface` and optional
 * `nu,segment,sample,z0,F0,format,index` columns (`file#N` names curve N
 * of a file of many, as the index column does).  Relative curve paths are resolved
 * against the plan's folder (dir for lf_plan_parse; NULL or "" = as
 * written); whether they exist is checked when they are read.  Rows are checked with
 * lf_probe_check and, on bonded rows, 0 <= nu < 0.5.  Ownership and errors
 * as for lf_curve_read. */
LF_API int lf_plan_read(const char *path, lf_plan **out, lf_warnings *warn, lf_error *err);
LF_API int lf_plan_parse(const char *buf, size_t len, size_t chunk, const char *name,
                  const char *dir, lf_plan **out, lf_warnings *warn, lf_error *err);
/* A plan of one row: the curve(s) of the file at path with one probe (R
 * NaN: from the file's header; b NaN: no layer, a half-space) on segment
 * seg; for `layerfit fit --batch MAP --k ...`. */
LF_API int lf_plan_of_file(const char *path, const lf_probe *probe, lf_segment seg, lf_plan **out,
                    lf_error *err);
/* The same for n files, one row each in their order (`layerfit fit a.txt
 * b.txt ...`): every row the same probe and segment, no sample. */
LF_API int lf_plan_of_files(size_t n, const char *const *paths, const lf_probe *probe, lf_segment seg,
                     lf_plan **out, lf_error *err);
/* Name each row's sample by a rule (`layerfit fit --group-by RULE`):
 *   "field:KEY"  the value of the curve file's header field KEY (its
 *                metadata, as `layerfit check` lists it);
 *   "name:REGEX" the first group (else the whole match) of the POSIX
 *                extended regular expression REGEX in the file's name
 *                (without its folder);
 *   "dir"        the file's folder.
 * A row the rule does not match is LF_EDATA naming it.  Rows that name a
 * file of many curves take the field of its first curve. */
LF_API int lf_plan_group(lf_plan *plan, const char *rule, const lf_read_opts *o, lf_error *err);
/* Make one row per curve of every file of many curves that a row names
 * without an index (the row's other cells copied; index 0..N-1), opening
 * each such file once (lf_file_open, o as there) and keeping it open in
 * the plan, where the fit input reads its curves from (row->source).
 * Files of one curve, and files that cannot be opened (the fit of their
 * row says why), are left as they are.  LF_ENOMEM only. */
LF_API int lf_plan_expand(lf_plan *plan, const lf_read_opts *o, lf_error *err);
/* Only the first half of lf_plan_expand: open each file of many curves the
 * rows name (row->source, plan->files), leaving the rows as they are; a
 * caller that walks a row's curves itself (a batch over a large map) needs
 * no row per curve.  A row whose source is set already (a call before,
 * lf_plan_set_source) keeps it. */
LF_API int lf_plan_open_files(lf_plan *plan, const lf_read_opts *o, lf_error *err);

/* Read row `row`'s curve from the open file f, curve index of it (-1: its
 * only one), instead of from the file the row names, which stays its name
 * in reports: for curves a program holds open or in memory
 * (lf_file_open_memory).  f stays the caller's, open while the plan is
 * used.  LF_EINVAL for a row or curve that does not exist. */
LF_API int lf_plan_set_source(lf_plan *plan, size_t row, lf_file *f, long index,
                              lf_error *err);

/* Whether a CSV file is a plan (its header has a "file" column) or a curve,
 * from its header alone. */
typedef enum { LF_FILE_CURVE = 0, LF_FILE_PLAN = 1 } lf_file_kind;
LF_API int lf_file_kind_of(const char *path, lf_file_kind *kind, lf_error *err);

/* Reading an input file safely (input.c).  lf_input_open opens path
 * without blocking (O_NONBLOCK), checks the open descriptor with fstat and
 * then makes it blocking again: a regular file is required unless flags
 * has LF_INPUT_STREAM, which admits a FIFO, pipe or device (read once, as
 * a stream; at most LF_STREAM_WAIT seconds are waited for the first byte).
 * On success *fd is open and owned by the caller; nothing is read, so a
 * reader of large binary files (random access, pread or mmap) opens them
 * with it, without the limit below.  lf_input_read reads the whole input
 * into in->data (owned by in, lf_input_free) and puts its SHA-256 in hex
 * into in->sha256.  It reads at most lf_input_limit() bytes (a regular
 * file larger than that is refused from its size before anything is read,
 * a stream when it gets there).  With LF_INPUT_TEXT in flags it also
 * checks text as it arrives: at a control byte (other than tab, CR, LF), a
 * UTF-16 byte order mark or a line over 1 MiB it stops reading (nothing
 * after is read, in->stopped is 1) and keeps the bytes up to that one, so
 * that a text reader refuses them with its own message at the same place
 * as it would the whole file.  Errors: LF_EIO, LF_ENOMEM, naming path.
 * Every reader opens its files through these.  lf_input_set_limit sets
 * the limit for the process (set it before reading starts; default
 * LF_INPUT_LIMIT, 256 MiB). */
#define LF_INPUT_STREAM 1u
#define LF_INPUT_TEXT 2u
#define LF_STREAM_WAIT 10
#define LF_INPUT_LIMIT ((size_t) 256 * 1024 * 1024)
typedef struct {
    char *data;               /* the bytes read (not NUL-terminated) */
    size_t len;
    char sha256[65];          /* lowercase hex */
    int stopped;              /* 1 (LF_INPUT_TEXT): reading stopped at a byte
                                 no text reader takes (only the bytes up to
                                 it are here) */
} lf_input;
LF_API void lf_input_set_limit(size_t bytes);
LF_API size_t lf_input_limit(void);
LF_API int lf_input_open(const char *path, unsigned flags, int *fd, lf_error *err);
LF_API int lf_input_read(const char *path, unsigned flags, lf_input *in, lf_error *err);
LF_API void lf_input_free(lf_input *in);

/* Copy the points of one segment, in file order, into depth and force
 * (either may be NULL to skip it) and return how many there are.  Call with
 * NULL, NULL to size the arrays. */
LF_API size_t lf_curve_segment(const lf_curve *c, lf_segment seg, double *depth,
                        double *force);

/* Check that a segment can be fitted: at least min_points points, force
 * not zero everywhere, depth not the same everywhere.  LF_EDATA with a
 * message naming the file and what is wrong. */
LF_API int lf_curve_check_fit(const lf_curve *c, lf_segment seg, size_t min_points,
                       lf_error *err);

/* The name of a segment ("load", "unload", "hold"), and the segment of a
 * word as plans and options take it (case aside): load, loading, approach,
 * extend; unload, unloading, retract, withdraw; hold, holding, pause,
 * dwell.  -1 for another word. */
LF_API const char *lf_segment_name(lf_segment seg);
LF_API int lf_segment_find(const char *word);

/* What a lab reads off a curve without any contact model (src/observe.c),
 * in SI.  Each segment is taken in order of depth; its baseline is the
 * median force over its flat shallow end (the shallowest fifth of its
 * depth range, halved while not flat).  A value the curve does not show
 * (no retract segment, no rise above the baseline) is NaN. */
typedef struct {
    double adhesion_force;   /* N, >= 0: the retract segment's baseline less
                                its least force (the largest pull) */
    double detachment_work;  /* J, >= 0: the area between the retract
                                segment and its baseline, over the dip
                                around that least force, in depth */
    double contact_point;    /* m: the zero-force point (LF_CONTACT_METHOD) */
    lf_segment contact_segment; /* the segment it was found on (approach,
                                else retract) */
    double max_indentation;  /* m: the deepest point less the contact point */
    double max_force;        /* N: the largest force less the baseline */
    double baseline;         /* N: the retract's baseline force, else the
                                approach's */
    double noise;            /* N: the force's sd about that baseline */
    double instrument_Eeff;  /* Pa: the modulus the instrument's header states
                                (Chiaro / Piuma "E[eff] (Pa)"), or NaN */
    char instrument_model[32]; /* the header's model of it ("Hertz"), or "" */
} lf_observables;

/* How the contact point is found, in words for reports. */
#define LF_CONTACT_METHOD "zero-force point: from the deepest point towards the surface, " \
    "past the first point within 3 noise sd of the baseline, where the force crosses " \
    "the baseline (the approach segment's, else the retract's)"

/* Fill *o for curve c (every segment it holds).  LF_ENOMEM only. */
LF_API int lf_observe(const lf_curve *c, lf_observables *o, lf_error *err);

/* The window that keeps everything, and whether w is it. */
LF_API lf_window lf_window_all(void);
LF_API int lf_window_is_all(const lf_window *w);
/* Parse "LO:HI" ("0:500nm", "0:30%", ":2uN", "-20nN:"): each side empty
 * (open), a percentage, a value with a unit of q (LF_Q_LENGTH or
 * LF_Q_FORCE), or a bare 0; both sides of one kind.  LF_EINVAL or LF_EUNIT
 * with a message. */
LF_API int lf_range_parse(const char *text, lf_quantity q, lf_range *r, lf_error *err);

/* A window placed on one curve, in its own depth and force. */
typedef struct {
    int active;                /* 0: every point kept */
    lf_window window;          /* as stated */
    double depth_lo, depth_hi; /* the curve's depth, m (-inf, inf: open) */
    double force_lo, force_hi; /* the curve's force, N */
    double contact_point;      /* m, and the baseline, N, it was placed from */
    double baseline;
    size_t n_in, n_kept;       /* the segment's points, and those kept
                                  (filled by the caller) */
} lf_window_placed;

/* Place w on a curve from its observables: LF_EDATA (with what is missing)
 * when the curve shows no contact point for a depth window, no baseline
 * for a force window, or nothing to take a fraction of. */
LF_API int lf_window_place(const lf_window *w, const lf_observables *o, lf_window_placed *out,
                    lf_error *err);
/* 1 when a point lies within the placed window. */
LF_API int lf_window_keeps(const lf_window_placed *p, double depth, double force);

/* ------------------------------------------------------------------------
 * Planning a test: what a set of candidate curves would measure (fit/design.c)
 *
 * A candidate is a curve a lab could record: probe, layer and interface,
 * the indentations it would span, how many points, whether the baseline
 * past detachment is recorded and which offsets (z0, F0) a fit would leave
 * free.  The data are taken to follow the exact layer model at the true
 * material with Gaussian force noise; each set is judged as `layerfit fit`
 * with `--model auto` would fit it: each curve gets the model the rule of
 * lf_fit_choose_driver picks (evaluated at the truth, where a noise-free
 * fit lands), nu is free only where the fitter frees it (bonded and
 * frictionless curves together, unless held), and what the fit could not
 * determine, and why, is judged by the very judgement lf_fit_run makes at
 * its solution (fit/judge.c: the column-scaled Jacobian, singular values
 * below rcond, weight > 0.01 on those directions; k = 2 alone with free z0
 * and F0 needs a curve with three points past detachment and a w the data
 * bound from above, here predicted from the linearised model; bonded
 * curves alone fix only M = Z E* where their layer is thin).  The standard
 * errors are the Cramer-Rao bound of that fit: the inverse Fisher
 * information with every free nuisance parameter estimated too.
 *
 * Ownership: a plan made by lf_design_plan_read/parse is the caller's
 * (lf_design_plan_free); results are filled into caller structs and their
 * contents released with lf_design_result_free / lf_design_choice_free.
 * --------------------------------------------------------------------- */

/* One candidate curve.  NaN / 0 members take the settings' defaults. */
typedef struct {
    char name[64];          /* label ("" in a plan row: "row N") */
    long line;              /* line of the plan row, 0 when not from a file */
    lf_probe probe;
    lf_branch branch;       /* default unloading */
    double delta_max;       /* deepest indentation, m (NaN: settings) */
    double delta_min;       /* shallowest indentation, m; NaN: 0.9 of the
                               detachment indentation without a baseline,
                               the detachment minus the baseline with one */
    double baseline;        /* length recorded past detachment, m: 0 none,
                               NaN "yes" (settings' baseline_fraction of the
                               contact part) */
    size_t points;          /* 0: settings */
    int free_z0, free_F0;   /* offsets a fit would estimate */
    double noise_rel;       /* this curve's noise (fraction of its largest
                               |force|), or NaN: settings */
    double noise_abs;       /* this curve's noise sd, N, or NaN: settings */
} lf_design_candidate;

typedef struct {
    char *path;
    size_t n;
    lf_design_candidate *rows;
} lf_design_plan;

/* Read a design plan: a CSV with the columns k,R,b,interface and optional
 * name,delta_max,delta_min,points,baseline,z0,F0,segment,noise (units in
 * the header or in each cell, as in fit plans; baseline is yes, no or a
 * length; z0 and F0 are free or fixed; noise a fraction such as 1% or
 * 0.01, or a force such as 2uN).  Errors name the file, line and column. */
LF_API int lf_design_plan_read(const char *path, lf_design_plan **out, lf_error *err);
LF_API int lf_design_plan_parse(const char *buf, size_t len, const char *name,
                         lf_design_plan **out, lf_error *err);
LF_API void lf_design_plan_free(lf_design_plan *p);

typedef struct {
    lf_material truth;      /* w > 0, E*, nu (nu used by bonded curves) */
    int fix_nu;             /* 1: nu known and held (fit --fix-nu) */
    double noise_rel;       /* default noise: fraction of each curve's
                               largest |force| (0.01) */
    double noise_abs;       /* default noise sd in N; used instead of
                               noise_rel when finite (NaN) */
    double delta_max;       /* default deepest indentation (50 nm) */
    size_t points;          /* default points per curve (200) */
    double baseline_fraction; /* "baseline yes": the recording goes on past
                               detachment for this fraction of the contact
                               part's depth span (0.25) */
    const lf_model_type *model; /* NULL (default): auto, as `fit`; else the
                                   model every curve is fitted with */
    lf_choose_settings choose;  /* the auto rule's tolerance (0.2 se) */
    double rcond;           /* as lf_fit_settings (1e-7) */
} lf_design_settings;

LF_API lf_design_settings lf_design_settings_default(void);

/* What one parameter of the material would be. */
typedef struct {
    int free;               /* a fit would estimate it */
    int determined;         /* ... and the data would fix it */
    double se;              /* predicted standard error, SI; NaN when not
                               free or not determined */
    double rel;             /* se / true value (w, E*, M); se for nu */
    int upper_bound_only;   /* w: below two of its standard errors, so a
                               fit would report only an upper bound */
    const char *why;        /* when not determined, a reason in words that
                               the identifiability notes do not give
                               (static), or NULL */
} lf_design_estimate;

/* One curve of an evaluated set, as it would be recorded and fitted. */
typedef struct {
    size_t index;           /* candidate index */
    const lf_model_type *model; /* the model a fit would use */
    char model_reason[200];
    double thin_bias;       /* largest |bias| / se the thin-layer model of
                               this curve would put on w, E*, nu; NaN when
                               not assessed */
    double delta_lo, delta_hi;  /* indentations recorded, m */
    double delta_detach;    /* end of contact (exact model), m */
    size_t n, n_past;       /* points, points past detachment */
    double sigma;           /* noise sd, N */
    double fmax;            /* largest |force| of the curve, N */
    double ba_min, ba_max;  /* b/a over the points in contact */
    double ba_pulloff;      /* b/a at force-controlled pull-off */
    int free_z0, free_F0;
} lf_design_curve_info;

typedef struct {
    lf_design_estimate w, Estar, nu;
    lf_design_estimate M;   /* Z E* of bonded curves (when E* itself is
                               not determined by bonded curves alone) */
    double corr_wE;         /* NaN when either is undetermined */
    size_t npar;            /* free parameters, nuisance included */
    size_t ndetermined;     /* of w, E*, nu: free and determined */
    double logdet;          /* ln det of the Fisher information of the
                               determined ones among ln w, ln E*, nu, the
                               nuisance parameters profiled out; -inf when
                               none is determined */
    size_t ncurves;
    lf_design_curve_info *curves;
    lf_warnings identifiability; /* what is not determined and why, in words */
    lf_warnings notes;           /* everything else worth saying */
} lf_design_result;

LF_API void lf_design_result_free(lf_design_result *r);

typedef struct lf_design lf_design;

/* Prepare the candidates (each curve's indentations, noise and the
 * derivatives of the thin, half-space and exact models at the truth);
 * every later evaluation is then cheap.  The candidates are copied. */
LF_API lf_design *lf_design_alloc(const lf_design_settings *s, size_t n,
                           const lf_design_candidate *cand, lf_error *err);
LF_API void lf_design_free(lf_design *d);

/* Evaluate the set of candidates with use[i] != 0 (use NULL: all).
 * LF_EDATA when the set is empty. */
LF_API int lf_design_eval(lf_design *d, const int *use, lf_design_result *out, lf_error *err);

typedef enum {
    LF_TARGET_W = 0,        /* smallest se of w */
    LF_TARGET_E,            /* smallest se of E* */
    LF_TARGET_NU,           /* smallest se of nu */
    LF_TARGET_ALL           /* D-optimal: largest logdet */
} lf_design_target;

/* "w", "E", "nu", "all"; lf_design_target_find returns -1 when unknown. */
LF_API const char *lf_design_target_name(lf_design_target t);
LF_API int lf_design_target_find(const char *name);

/* How good a result is for a target, as a comparable score.  A set that
 * determines the target beats one that does not; two that do compare by
 * value (-relative se of w or E*, -se of nu; for all: first how many of
 * w, E*, nu are determined, then logdet); two that do not compare by how
 * many of w, E*, nu they determine, then by logdet. */
typedef struct {
    lf_design_target target;
    int target_determined;
    size_t ndetermined;
    double value;           /* larger is better; -inf when undetermined */
    double logdet;          /* the result's logdet, the last tie-break */
} lf_design_score;

LF_API lf_design_score lf_design_score_of(const lf_design_result *r, lf_design_target t);
/* > 0 when a is better than b, < 0 when worse, 0 when equal. */
LF_API int lf_design_score_cmp(const lf_design_score *a, const lf_design_score *b);

/* One step of a choice: the candidate added and what the set gives. */
typedef struct {
    size_t added;           /* candidate index */
    lf_design_score score;
    lf_design_estimate w, Estar, nu;
    size_t runner_up;       /* next best candidate at this step, or
                               (size_t) -1 when there was none */
    lf_design_score runner_score;
} lf_design_step;

typedef struct {
    size_t nsteps;
    lf_design_step *steps;
    int *chosen;            /* per candidate: 1 when chosen */
} lf_design_choice;

LF_API void lf_design_choice_free(lf_design_choice *c);

/* Pick nchoose candidates greedily: at each step the one whose addition
 * scores best for the target (ties: the earlier candidate). */
LF_API int lf_design_choose(lf_design *d, size_t nchoose, lf_design_target target,
                     lf_design_choice *out, lf_error *err);
/* The best set of nchoose candidates over all subsets (for small sets:
 * LF_EINVAL when there are more than max_sets subsets).  best[] (one per
 * candidate) receives 1 for the chosen ones; *score their score. */
LF_API int lf_design_exhaustive(lf_design *d, size_t nchoose, lf_design_target target,
                         size_t max_sets, int *best, lf_design_score *score,
                         lf_error *err);

/* A factor to sweep, applied to every candidate (or to one). */
typedef enum {
    LF_FACTOR_K = 0,        /* probe exponent */
    LF_FACTOR_DELTA_MAX,    /* deepest indentation, m */
    LF_FACTOR_POINTS,       /* points per curve */
    LF_FACTOR_B,            /* layer thickness, m */
    LF_FACTOR_R,            /* probe reference length, m */
    LF_FACTOR_BASELINE      /* baseline length past detachment, m */
} lf_design_factor;

/* "k", "delta_max", "points", "b", "R", "baseline"; find: -1 when unknown
 * (also accepts "depth" for delta_max). */
LF_API const char *lf_design_factor_name(lf_design_factor f);
LF_API int lf_design_factor_find(const char *name);
/* The quantity of a factor's values (LF_Q_DIMENSIONLESS for k, points). */
LF_API lf_quantity lf_design_factor_quantity(lf_design_factor f);

/* Evaluate the whole set with the factor set to each of values[0..nv-1]
 * on candidate `which` (or on all when which == (size_t) -1).  out[]
 * (nv results, caller's array) is filled; a value the candidates refuse
 * (e.g. k <= 0) fails with LF_EINVAL. */
LF_API int lf_design_sweep(const lf_design_settings *s, size_t n,
                    const lf_design_candidate *cand, lf_design_factor factor,
                    size_t which, size_t nv, const double *values,
                    lf_design_result *out, lf_error *err);

/* ------------------------------------------------------------------------
 * From a plan to a fit's input (src/fit_input.c)
 *
 * The one step from a plan and its curve files to the curves a fit takes,
 * for the command's single and batch fits and for programs alike.
 *
 * nu (one rule): a plan's nu column is the layer's Poisson ratio.  Every row
 * that gives nu, whatever its interface, must give the same value (one
 * material, one nu), else LF_EDATA naming the row; that value is in->nu
 * (NaN when no row gives one).  lf_fit_input_apply_nu then holds nu at it
 * unless the settings already hold nu (a value from the command line wins).
 *
 * Ownership: the input owns its arrays (points, names) and releases them in
 * lf_fit_input_free; in->curves may be handed to lf_fit_alloc,
 * lf_fit_driver or lf_fit_choose_driver while the input lives.  The plan
 * may be freed once the input is made.
 * --------------------------------------------------------------------- */

typedef struct {
    int segment;          /* -1 (default): each row's segment; else the
                             lf_segment of every curve */
    double z0, F0;        /* NaN (default): each row's (held where the plan
                             gives one, else fitted); else held for every
                             curve, m and N */
    const lf_read_opts *read;  /* how to read the curve files; NULL = defaults */
    size_t min_points;    /* fewest points of a segment (default 5) */
    unsigned open_flags;  /* lf_input_read flags for the curve files: 0
                             (default) regular files only; LF_INPUT_STREAM
                             also a pipe or FIFO (a file named by a user) */
    lf_window window;     /* all (default): each row's window (none unless
                             its plan gives one); else every curve's */
} lf_input_settings;

LF_API lf_input_settings lf_input_settings_default(void);

/* Where the probe values and AFM constants of one curve came from, for the
 * reports. */
typedef struct {
    const char *R;            /* "option", "plan" or "file header" */
    const char *b;            /* "option" or "plan"; NULL: no layer (a
                                 half-space fit; probe b is a stand-in, R) */
    double spring_constant;   /* N/m used to convert the file's signals, or NaN */
    const char *spring_constant_source;  /* "file header", "option", or NULL */
    double sensitivity;       /* m/V or m/A used, or NaN */
    const char *sensitivity_unit;        /* "m/V" or "m/A" */
    const char *sensitivity_source;      /* "file header", "option", or NULL */
} lf_curve_origin;

typedef struct {
    size_t n;
    lf_fit_curve *curves; /* n curves: the points of their segment in SI */
    double nu;            /* the plan's nu, or NaN */
    double x, y;          /* where the first curve sits on a force map, m,
                             as its file states it (lf_curve x, y), else NaN */
    long grid_i, grid_j;  /* and its place on the map's grid, or -1 */
    double **points;      /* owned storage: 2 n arrays (depth, force) */
    char **names;         /* owned storage: n curve paths */
    char (*sha256)[65];   /* n SHA-256 digests (hex) of the curve files as read */
    const char **R_source;  /* n: where each probe radius came from: "option"
                               (the caller's probe), "plan" or "file header" */
    const char **format;    /* n: the reader of each file ("csv", "jpk", ...) */
    lf_curve_origin *origin;  /* n: where each curve's probe and constants came from */
    long *index;              /* n: each curve's place in its file (0 for a file
                                 of one curve) */
    lf_observables *observed; /* n: what each curve shows without a model
                                 (lf_observe, over all its segments) */
    lf_window_placed *window; /* n: each curve's fit window as placed (its
                                 points outside it are not in curves[]) */
} lf_fit_input;

/* Read the curves of rows[0..nrows-1] of the plan (rows NULL: every row,
 * nrows ignored) into in.  Each text file is read once, whole, from a
 * descriptor checked when it is opened (lf_input_read with s->open_flags),
 * a binary file of many curves by random access (lf_file_open; the row's
 * source when the plan opened it), and the file's SHA-256 kept in
 * in->sha256.  A row is one curve: FILE#N or its index, or a file's only
 * curve (a file of many named without an index: LF_EDATA saying how many
 * it holds).  Warnings of the readers are appended to warn
 * (may be NULL).  On failure in holds nothing and err names the file, line
 * and column where it can (LF_EIO, LF_EFORMAT, LF_EUNIT, LF_EDATA).  A row
 * without a layer (b NaN: empty b and interface cells) gets b = R, a
 * stand-in no half-space formula uses, and origin[j].b NULL: such rows suit
 * half-space fits only, which the caller checks (the model is its choice).
 * One input is one material (LF_EDATA naming the row otherwise): the rows'
 * nu must agree, so must their non-empty samples, and no curve may be an
 * earlier row's (the same bytes, the same curve of them, the same segment). */
LF_API int lf_fit_input_from_plan(const lf_plan *plan, const size_t *rows, size_t nrows,
                           const lf_input_settings *s, lf_fit_input *in,
                           lf_warnings *warn, lf_error *err);
/* The same for one curve file with a probe given by the caller (no plan:
 * in->nu is NaN; the segment is s->segment, unload when -1).  A probe R of
 * NaN is taken from the file's header (LF_EDATA when it states none); a b
 * of NaN (no layer: half-space models only) becomes R, a stand-in no
 * half-space formula uses.  A plan row's format column chooses its reader
 * unless s->read names one. */
LF_API int lf_fit_input_from_curve(const char *path, const lf_probe *probe,
                            const lf_input_settings *s, lf_fit_input *in,
                            lf_warnings *warn, lf_error *err);
/* Hold nu at in->nu when that is a number and the settings do not already
 * hold nu. */
LF_API void lf_fit_input_apply_nu(const lf_fit_input *in, lf_fit_settings *settings);
/* Release what the input owns (NULL and an empty input allowed). */
LF_API void lf_fit_input_free(lf_fit_input *in);

/* ------------------------------------------------------------------------
 * The fit's options, as `layerfit fit` takes them (src/fit_options.c)
 *
 * One table of options for the command and for programs and bindings:
 * each is set by its name on the command line (without "--") from text
 * as a command line gives it ("0.3", "1mm", "10 mJ/m2"), so that a
 * program asks for a fit in the command's words and gets the command's
 * checks and messages.  lf_fit_options_request turns them into the
 * settings of the fit, lf_fit_options_probe into the probe of a single
 * curve (or of every curve of a file of many), and lf_fit_request_run
 * makes the fit as the command does: the model choice or the model asked
 * for, the thin-layer comparison, the profile-likelihood check of the
 * intervals.
 *
 * Ownership: the options are the caller's (lf_fit_options_free) and hold
 * copies of the text they are given; a request points into its options,
 * which must outlive it.
 * --------------------------------------------------------------------- */

typedef enum {
    LF_OPTION_FLAG = 0,      /* no value: given or not */
    LF_OPTION_TEXT,          /* a word or a name (checked by the request) */
    LF_OPTION_NUMBER,        /* a bare number */
    LF_OPTION_COUNT,         /* a whole number >= 0 */
    LF_OPTION_QUANTITY       /* a number with its unit, of `quantity` */
} lf_option_kind;

typedef struct {
    const char *name;        /* "fix-nu", "R", ... (the command's --NAME) */
    lf_option_kind kind;
    lf_quantity quantity;    /* LF_OPTION_QUANTITY, and a text option that
                                is a quantity checked later (spring-constant):
                                what its unit measures; else
                                LF_Q_DIMENSIONLESS */
} lf_option;

/* The options of a fit, ended by an entry whose name is NULL: method,
 * jacobian, model, segment, nu, fix-nu, fix-z0, fix-F0, max-b-over-a,
 * model-tol, slope, max-iter, guess-w, guess-E, guess-nu, loss,
 * loss-scale, intervals, format, spring-constant, sensitivity,
 * depth-unit, force-unit, skip-bad-rows, the probe of curve files k, R,
 * b, interface, tip, half-angle, B, the fit windows depth-range and
 * force-range, and the samples of curve files sample and group-by
 * (`layerfit fit --help` says what each means). */
LF_API extern const lf_option lf_fit_option_table[];

/* The fewest points of a segment worth fitting: one more than the most
 * parameters a fit can have (w, E*, nu, z0, F0); `layerfit check` and
 * every fit of a request refuse a curve with fewer. */
#define LF_FIT_MIN_POINTS 6

typedef struct lf_fit_options lf_fit_options;

/* Options at their defaults (NULL when out of memory). */
LF_API lf_fit_options *lf_fit_options_alloc(void);
LF_API void lf_fit_options_free(lf_fit_options *o);
/* Set option `name` from text (value NULL for a flag, which turns it on;
 * a flag given a value, a value option given none, an unknown name, a
 * value that is not a number or not of the option's quantity: LF_EINVAL or
 * LF_EUNIT with a message "--NAME: ..." as the command's).  A later call
 * for the same name replaces the value. */
LF_API int lf_fit_options_set(lf_fit_options *o, const char *name, const char *value,
                              lf_error *err);
/* The text an option was given (a flag: "1"), or NULL when it was not. */
LF_API const char *lf_fit_options_get(const lf_fit_options *o, const char *name);

/* What a request of options asks: the settings of the fit, of the model
 * choice and of reading the curves. */
typedef struct {
    lf_fit_settings fit;
    lf_choose_settings choose;
    lf_input_settings input;     /* input.read points into the options */
    int model_auto;              /* --model auto: each curve's model chosen
                                    (lf_fit_choose_driver) */
    int profile;                 /* lf_fit_profile's mode of a single fit:
                                    LF_PROFILE_CHECK, or LF_PROFILE_LINEAR
                                    (--intervals linear) */
    const char *model;           /* --model as given ("auto", ...) */
    const char *nu_option;       /* "--fix-nu" or "--nu" when an option
                                    holds nu, else NULL (static) */
} lf_fit_request;

/* Check the options together and fill req (LF_EINVAL or LF_EUNIT naming
 * the option otherwise). */
LF_API int lf_fit_options_request(lf_fit_options *o, lf_fit_request *req, lf_error *err);
/* The same for programs that keep objects by handle: the request held by
 * the options themselves (valid until they are set again or freed), or
 * NULL with err. */
LF_API const lf_fit_request *lf_fit_options_checked(lf_fit_options *o, lf_error *err);
/* How the options read curve files (format, spring-constant,
 * sensitivity, depth-unit, force-unit, skip-bad-rows): checked, held by
 * the options as the request's are; NULL with err on a bad value. */
LF_API const lf_read_opts *lf_fit_options_read(lf_fit_options *o, lf_error *err);
/* The probe options k, R, b, interface, tip, half-angle, B: with the
 * shape given (k, tip, half-angle or B), *single = 1 and p the probe of a
 * single curve, of every curve of a file of many or of curve files (R NaN:
 * from each file's header; b NaN with no interface: no layer, for the
 * half-space model, which then needs neither); without it, *single = 0
 * (a plan gives each curve's probe in its row, and R, b or interface
 * given then is an error).  LF_EINVAL naming what is missing or wrong. */
LF_API int lf_fit_options_probe(const lf_fit_options *o, lf_probe *p, int *single,
                                lf_error *err);

/* A fit of one of `layerfit fit --batch`: the profile check screened
 * cheaply first (LF_PROFILE_SCREEN unless --intervals linear), no
 * thin-layer comparison beside a fit with another model. */
#define LF_RUN_BATCH 1u
/* Fit the curves of in as `layerfit fit` does (the input's nu held unless
 * the request holds nu): lf_fit_choose_driver for --model auto, else
 * lf_fit_driver, each curve also alone, the profile and how the curves
 * differ (lf_fit_joint), and, where every curve has a layer and the model
 * is not the thin one, lf_fit_compare_thin.  What goes
 * wrong after the fit (the comparison or the profile failed) is a note in
 * notes (may be NULL), the result standing.  Returns LF_OK, LF_ENOCONV
 * (res complete, not converged: also when the profile found the minimum
 * was a local one) or an error of the fit (res empty). */
LF_API int lf_fit_request_run(const lf_fit_request *req, const lf_fit_input *in, unsigned flags,
                              lf_fit_result *res, lf_warnings *notes, lf_error *err);

/* A fit held in one object, for programs and bindings that keep objects by
 * handle: made as `layerfit fit PATH [options]` makes it.
 * lf_fit_job_path reads a single curve when the options give k (R, b,
 * interface, as the command's --k, --R, ...), else the plan at path (a
 * file, a pipe or FIFO read once); lf_fit_job_plan takes a plan already
 * read (lf_plan_parse of rows a program wrote, its rows' curves perhaps
 * open files of the program's: lf_plan_set_source).  A plan's rows without
 * a layer need --model halfspace (LF_EDATA at the row otherwise).  On
 * LF_OK *out is the caller's (lf_fit_job_free), its fit converged or not
 * (lf_fit_job_status: LF_OK or LF_ENOCONV); warnings of the readers and
 * notes of the fit go to warn (may be NULL).  Errors as the readers' and
 * lf_fit_request_run's, err naming the file, line and column where the
 * cause sits.  The job keeps what it needs of the options: they may be
 * set again or freed once it is made. */
typedef struct lf_fit_job lf_fit_job;

LF_API int lf_fit_job_path(lf_fit_options *o, const char *path, lf_fit_job **out,
                           lf_warnings *warn, lf_error *err);
LF_API int lf_fit_job_plan(lf_fit_options *o, const lf_plan *plan, lf_fit_job **out,
                           lf_warnings *warn, lf_error *err);
LF_API const lf_fit_result *lf_fit_job_result(const lf_fit_job *j);
LF_API const lf_fit_input *lf_fit_job_input(const lf_fit_job *j);
LF_API int lf_fit_job_status(const lf_fit_job *j);
/* Curve i's points (pointers owned by the job): depth and force fitted,
 * the fitted force and the contact radius there; their number, 0 when
 * there is no curve i. */
LF_API size_t lf_fit_job_curve(const lf_fit_job *j, size_t i, const double **depth,
                               const double **force, const double **fitted,
                               const double **radius);
/* The result as `layerfit fit --json` writes it (lf_fit_result_json), its
 * provenance the command line (or a binding's call) given and the inputs
 * in the order the command records them: the plan read from a file, then
 * each curve with its SHA-256. */
LF_API int lf_fit_job_json(const lf_fit_job *j, const char *command_line, char **json,
                           lf_error *err);
LF_API void lf_fit_job_free(lf_fit_job *j);

/* What the figures of a fit draw of curve j (`layerfit fit --plot`, a
 * binding's plot): the offsets it is drawn with (the reported ones, else
 * where the fit ended, else 0), the fitted model on n >= 2 depths z[]
 * spanning the curve's data (and past detachment), in instrument
 * coordinates, with forces F[] and each point's class cls[] (0 out of
 * contact, 1 stable under force control, 2 unstable), and the
 * force-controlled pull-off point (NaN when w is not determined or the
 * branch is loading).  have = 0 when no model could be drawn (a material
 * not determined).  z, F and cls are the caller's arrays of n; n = 0: the
 * offsets alone. */
typedef struct {
    double z0, F0, slope;  /* m, N, N/m */
    double z_po, F_po;     /* m, N, or NaN */
    double delta_detach, delta_po;  /* indentations of detachment and of
                              pull-off at the fitted material, m, or NaN */
    int have;
} lf_fit_figure;

LF_API int lf_fit_figure_curve(const lf_fit_result *res, size_t j, const lf_fit_curve *c,
                               size_t n, double *z, double *F, int *cls, lf_fit_figure *out,
                               lf_error *err);
/* The same for curve i of a job. */
LF_API int lf_fit_job_figure(const lf_fit_job *j, size_t i, size_t n, double *z, double *F,
                             int *cls, lf_fit_figure *out, lf_error *err);

/* ------------------------------------------------------------------------
 * Many independent fits: the batch of `layerfit fit --batch` (src/batch.c)
 *
 * Every curve of a plan, or every group of curves that share a non-empty
 * sample, is fitted on its own, as lf_fit_request_run(LF_RUN_BATCH) fits
 * it, by worker threads; each fit is one row of the batch's table, handed
 * to the caller's function as soon as it may be (lf_batch_settings.ordered).
 * A plan row naming a file of many curves without an index stands for each
 * of its curves (the file opened once, lf_plan_open_files).  A bad curve
 * (a missing file included) is a row with status "error" and its message;
 * the batch goes on.  The rows, in plan order, do not depend on the number
 * of threads.  With --model auto (and not lf_choose_settings.each), the
 * fits of one curve are grouped by probe and layer and the model decided
 * once per group where that settles it (lf_choose_settings.group; column
 * model_by); the rows do not depend on the threads or the shard either.
 * --------------------------------------------------------------------- */

typedef struct {
    int json;              /* rows as JSON Lines (1) or CSV (0, default:
                              lf_batch_csv_header's columns) */
    long threads;          /* worker threads, 0 (default): one per processor */
    long shard_index, shard_count;  /* only the I-th of N contiguous shares
                              of the fits (1, 1: all); the rows of shards
                              1..N in order are those of the whole plan */
    int ordered;           /* 1 (default): rows handed over in plan order,
                              at most 128 per thread waiting for an earlier
                              one; 0: as the fits finish */
    int results;           /* 1: each row carries its fit's result and
                              input (0, default: the text only) */
    int csv_raw;           /* 1: CSV text cells as they are; 0 (default): a
                              cell a spreadsheet would run as a formula
                              (starting with =, +, -, @, tab or CR) gets a
                              leading ' (OWASP, "CSV injection") */
} lf_batch_settings;

LF_API lf_batch_settings lf_batch_settings_default(void);

typedef enum {
    LF_BATCH_OK = 0,       /* status "ok" */
    LF_BATCH_FAILED = 1,   /* "error" or "noconv" */
    LF_BATCH_MISFIT = 2    /* "misfit": converged, but the model does not
                              describe a curve of the fit */
} lf_batch_outcome;

/* One fit of a batch, as handed over.  Everything it points to is valid
 * during the call only. */
typedef struct {
    size_t fit;            /* its number in the plan, from 1 */
    const char *sample;    /* its sample ("" for a curve on its own) */
    const char *status;    /* "ok", "misfit", "noconv", "error" */
    lf_batch_outcome outcome;
    const char *text;      /* the row as the command writes it: a CSV line
                              or a JSON line, with its line break */
    size_t len;            /* strlen(text) */
    const lf_fit_result *result;  /* with settings.results: the fit (NULL
                              for an error row) */
    const lf_fit_input *input;    /* with settings.results: its curves
                              (NULL when they could not be read) */
    size_t done, total;    /* rows handed over so far, this one included,
                              of the shard's */
    size_t failed, misfits; /* of those done */
    const char *why;       /* a failed fit (LF_BATCH_FAILED): why, its message
                              or the fit's stop reason; else NULL */
    const char *cause;     /* the same with its files' names as '@' and every
                              number as '#', so that failures of one cause
                              compare equal; NULL with why (or out of memory) */
} lf_batch_row;

/* Called once per row, one call at a time, from the worker threads (the
 * caller's among them).  A nonzero return stops the batch: no fit starts
 * after it, and those running end without being handed over. */
typedef int (*lf_batch_fn)(void *ctx, const lf_batch_row *row);

typedef struct {
    size_t fits;           /* fits of the whole plan */
    size_t total;          /* fits of this shard */
    size_t done, failed, misfits;  /* rows handed over, failed, misfits */
    int stopped;           /* the function stopped the batch */
} lf_batch_summary;

/* The CSV rows' header line ("fit,sample,file,...,sha256\n"; static). */
LF_API const char *lf_batch_csv_header(void);

/* Fit every fit of the plan with the request's settings, handing each row
 * to each(ctx, row) (each may be NULL).  bs NULL: the defaults; sum (may
 * be NULL) says how many fits there were, were handed over and failed.
 * Returns LF_OK when the batch ran (whatever its fits' outcomes, or when
 * each stopped it), LF_EINVAL for bad settings, LF_EDATA at the first row
 * without b and interface unless the model is the half-space, LF_ENOMEM
 * when a row could not be made (the batch stops there). */
LF_API int lf_batch_run(lf_plan *plan, const lf_fit_request *req, const lf_batch_settings *bs,
                        lf_batch_fn each, void *ctx, lf_batch_summary *sum, lf_error *err);
/* A row's fit (settings.results) as `layerfit fit --json` writes a fit of
 * its curves (lf_fit_result_json; req the batch's), its provenance the
 * command line given and the row's curves.  LF_EINVAL for a row without
 * a result (an error row). */
LF_API int lf_batch_row_json(const lf_batch_row *row, const lf_fit_request *req,
                             const char *command_line, char **json, lf_error *err);

/* ------------------------------------------------------------------------
 * Results as text (src/report_json.c, src/report_html.c, src/text.c)
 *
 * The documents `layerfit fit` writes, made by the library so that a
 * program or a binding gets the very same: the JSON of --json and the
 * tables of the --report page.  The library never prints: each writer
 * returns a new NUL-terminated string, the caller's, released with
 * lf_free (LF_ENOMEM when it could not be made, *out NULL then).
 * --------------------------------------------------------------------- */

/* Release memory the library handed over (the writers' strings); NULL
 * allowed. */
LF_API void lf_free(void *p);

/* What a program records of where a result came from: how it was asked
 * for (a command line, a binding's call) and what it read. */
typedef struct {
    const char *command_line;      /* NULL: null */
    size_t ninputs;
    const char *const *input;      /* ninputs paths, in the order read */
    const char *const *sha256;     /* ninputs SHA-256 digests in hex, an entry
                                      NULL or "" when not hashed; or NULL */
} lf_provenance;

/* A value a fit assumed rather than fitted, stated at the top of every
 * report: held (w, E*, nu, an offset z0 or F0) or a probe radius read from
 * a file's header.  first..last: the curves it concerns, from 1 (0, 0:
 * every curve). */
typedef struct {
    const char *name;       /* "w", "E*", "nu", "z0", "F0", "R" (static) */
    double value;           /* SI */
    const char *unit;       /* "J/m^2", "Pa", "", "m", "N" (static) */
    size_t first, last;
    char source[96];        /* where it came from: "--nu", "the plan's nu
                               column", "the file headers, chiaro exports" */
} lf_assumption;

/* The assumptions of a fit of in made with req (lf_fit_request_run), in
 * the order w, E*, nu, z0, F0, R, runs of curves with one value and one
 * source together, into out[0..max-1]; returns how many. */
LF_API size_t lf_fit_assumptions(const lf_fit_request *req, const lf_fit_input *in,
                                 const lf_fit_result *r, lf_assumption *out, size_t max);

/* What the fit was asked, beside its result. */
typedef struct {
    const char *model_request;     /* --model as given ("auto", "exact", ...);
                                      NULL: the result's model */
    double model_tol;              /* the auto choice's tolerance, NaN else */
    const lf_curve_origin *origin; /* where each curve's probe and AFM
                                      constants came from (lf_fit_input), or
                                      NULL */
    const lf_provenance *provenance; /* NULL: no "provenance" key */
    const lf_assumption *assumed;  /* what the fit assumed rather than
                                      fitted (lf_fit_assumptions), or NULL */
    size_t nassumed;
    const lf_observables *observed; /* what each curve shows without a model
                                      (lf_fit_input), or NULL */
    const lf_window_placed *window; /* each curve's fit window (lf_fit_input),
                                      or NULL */
} lf_report_info;

/* The result as the JSON document of `layerfit fit --json` (SI, numbers
 * that read back exactly, NaN and Inf as null, text from data as valid
 * UTF-8): assumed, heterogeneity, parameters, fit, thin_comparison,
 * free_parameters, values, covariance, singular_values, curves,
 * identifiability, warnings and provenance.  info may be NULL. */
LF_API int lf_fit_result_json(const lf_fit_result *r, const lf_report_info *info, char **json,
                              lf_error *err);

/* The tables of the `layerfit fit --report` page as HTML: a note when the
 * fit did not converge, then the sections heterogeneity (how the curves
 * differ, for two or more), parameters, identifiability,
 * warnings, correlations, statistics and curves (text from data escaped).
 * scope NULL: the sections alone, for a page with the report's style;
 * else a class name (letters, digits, - and _; LF_EINVAL otherwise), and
 * the sections come inside <div class="SCOPE"> with the report's style
 * confined to it, for a notebook. */
LF_API int lf_fit_result_html(const lf_fit_result *r, const char *scope, char **html,
                              lf_error *err);

/* What `layerfit design PLAN [options]` answers, for the command and for
 * bindings alike (src/design_run.c).  The options are set by name from
 * text as a command line gives them (as lf_fit_options_set does): w, E,
 * nu, fix-nu, noise, points, delta-max, model, model-tol, choose, target,
 * grid, vary (`layerfit design --help`).  lf_design_run evaluates the
 * whole set of the plan's candidates, the set without each (what each
 * adds), with choose the greedy choice of that many for the target (and
 * the best of all sets by exhaustive search where there are at most 2000)
 * and the chosen set, with grid the sweep of a factor over every
 * candidate or the one vary names; lf_design_report_json writes the
 * command's --json document of it.  The report is the caller's
 * (lf_design_report_free); it points at the plan, which must outlive it. */
typedef struct lf_design_options lf_design_options;

LF_API extern const lf_option lf_design_option_table[];
LF_API lf_design_options *lf_design_options_alloc(void);
LF_API void lf_design_options_free(lf_design_options *o);
LF_API int lf_design_options_set(lf_design_options *o, const char *name, const char *value,
                                 lf_error *err);
LF_API const char *lf_design_options_get(const lf_design_options *o, const char *name);
/* The settings the options give (LF_EINVAL naming the option otherwise:
 * w and E required, nu, noise "1%", 0.01 or "2uN", points, delta-max,
 * model, model-tol, target, grid and choose apart). */
LF_API int lf_design_options_settings(const lf_design_options *o, lf_design_settings *s,
                                      lf_error *err);
/* The grid's factor and values (values: room for 200), *nv = 0 without
 * one: "k=2,2.5,3" (values with units), "delta_max=20nm:200nm:10"
 * (LO:HI:N), "b=0.1um:10um:9:log". */
LF_API int lf_design_options_grid(const lf_design_options *o, lf_design_factor *factor,
                                  double *values, size_t *nv, lf_error *err);

typedef struct {
    lf_design_settings settings;
    const lf_design_plan *plan;
    lf_design_target target;
    lf_design_result all;          /* the whole set */
    size_t n;                      /* candidates */
    lf_design_result *without;     /* n: the set without candidate i */
    int *without_done;             /* n: 1 where it was evaluated (n > 1) */
    size_t nchoose;                /* choose, or 0 */
    lf_design_choice choice;       /* nchoose > 0: the greedy choice */
    int exhaustive;                /* 1: best[] is the best of all nsets sets */
    int *best;
    size_t nsets;
    lf_design_result chosen;       /* nchoose > 0: the chosen set */
    size_t nsweep;                 /* grid values, or 0 */
    lf_design_factor factor;
    size_t which;                  /* the swept candidate, (size_t) -1: all */
    double *values;
    lf_design_result *sweep;       /* nsweep results */
} lf_design_report;

LF_API int lf_design_run(const lf_design_options *o, const lf_design_plan *plan,
                         lf_design_report **out, lf_error *err);
/* prov NULL: no "provenance" key.  Into *json (lf_free). */
LF_API int lf_design_report_json(const lf_design_report *r, const lf_provenance *prov,
                                 char **json, lf_error *err);
LF_API void lf_design_report_free(lf_design_report *r);

/* ------------------------------------------------------------------------
 * Instrument readers (src/reader.c, one src/read_*.c file per format)
 *
 * Each format is one entry of lf_reader_types: sniff looks at the first
 * bytes of a file (at most LF_SNIFF_BYTES) and says how sure it is that the
 * file is its own (0 = not mine, 100 = certain); read parses the whole
 * input, from a file or from memory in chunks, into a curve in SI with its
 * metadata (a binary format of many curves reads its only curve from
 * memory; lf_file_open reads such files by random access).  lf_curve_read / lf_curve_parse use o->format when given, else
 * the entry with the highest score ("csv" on a tie or when none claims it).
 * --------------------------------------------------------------------- */

#define LF_SNIFF_BYTES 65536

/* Where a reader takes its bytes from: buf[0..len-1], handed over in pieces
 * of chunk bytes (0 = at once); name is used in messages.  Files are read
 * whole first, from a checked descriptor (lf_input_read), so a reader never
 * opens anything itself. */
typedef struct {
    const char *buf;
    size_t len, chunk;
    const char *name;
} lf_source;

typedef struct {
    const char *name;         /* "csv", "chiaro", "jpk", ... (--format) */
    const char *description;  /* one line for `layerfit check --help` */
    int (*sniff)(const char *head, size_t len);
    int (*read)(const lf_source *in, const lf_read_opts *o, lf_curve *c,
                lf_warnings *warn, lf_error *err);
} lf_reader_type;

LF_API extern const lf_reader_type *const lf_reader_types[];  /* NULL-terminated */
LF_API const lf_reader_type *lf_reader_find(const char *name);  /* NULL if unknown */
/* The reader sniffing picks for these first bytes (never NULL). */
LF_API const lf_reader_type *lf_reader_sniff(const char *head, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* LAYERFIT_H */
