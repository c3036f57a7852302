/* probe.c: the shapes of probes as labs state them, and the domain every
 * model shares.
 *
 * A power law f(r) = B r^k is stated by its prefactor B (m^(1-k)) or, as
 * the seed paper writes it, by a length R with B = 1/(k R^(k-1)) (k = 2: a
 * paraboloid of radius R).  For k = 1 that R cancels: f = r whatever R,
 * a 45-degree cone, so a cone is stated by its half-angle alpha,
 * f = r cot(alpha) (Sneddon 1965, Int. J. Eng. Sci. 3:47: the adhesionless
 * cone on a half-space pushes with P = (2/pi) E* tan(alpha) delta^2).
 * Pyramids enter as their equivalent cones: a Berkovich tip as the cone of
 * the same area-to-depth ratio, 24.5, half-angle 70.3 degrees (Oliver &
 * Pharr 1992, J. Mater. Res. 7:1564; Fischer-Cripps, Nanoindentation,
 * 2011); a four-sided pyramid of face half-angle theta as the cone of the
 * same projected area at every depth, pi tan^2(alpha) = 4 tan^2(theta)
 * (Bilodeau 1992, J. Appl. Mech. 59:519; Rico et al. 2005, Phys. Rev. E
 * 72:021914, for AFM pyramids).  A sphere of radius R,
 * f = R - sqrt(R^2 - r^2), is no power law: the models treat it on its
 * own (model_thin.c, model_halfspace.c, model_exact.c).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"

/* The Berkovich tip's equivalent cone, rad. */
#define BERKOVICH_ALPHA (70.3 * M_PI / 180.0)

double
lf_probe_cone_angle(const lf_probe *p)
{
    switch (p->tip) {
    case LF_TIP_CONE:
        return p->angle;
    case LF_TIP_BERKOVICH:
        return BERKOVICH_ALPHA;
    case LF_TIP_PYRAMID:
        return atan(2.0 * tan(p->angle) / sqrt(M_PI));
    default:
        return NAN;
    }
}

/* ln B of a power law stated by R, without B itself: R^(k-1) alone
 * leaves double precision for a flat punch (k of a few hundred). */
static double
log_prefactor_of_R(const lf_probe *p)
{
    return -log(p->k) - (p->k - 1.0) * log(p->R);
}

double
lf_probe_prefactor(const lf_probe *p)
{
    double B;

    switch (p->tip) {
    case LF_TIP_CONE:
    case LF_TIP_BERKOVICH:
    case LF_TIP_PYRAMID:
        return 1.0 / tan(lf_probe_cone_angle(p));
    case LF_TIP_SPHERE:
        return 0.5 / p->R;
    default:
        if (p->B > 0)
            return p->B;
        /* directly where it is a normal number (the paper's formula, to
         * the last digit), else through its logarithm */
        B = 1.0 / (p->k * pow(p->R, p->k - 1.0));
        return isnormal(B) ? B : exp(log_prefactor_of_R(p));
    }
}

double
lf_probe_log_prefactor(const lf_probe *p)
{
    double B = lf_probe_prefactor(p);

    if (isnormal(B))
        return log(B);
    return p->tip == LF_TIP_POWER && !(p->B > 0) ? log_prefactor_of_R(p) : log(B);
}

double
lf_probe_length(const lf_probe *p)
{
    if (isfinite(p->R) && p->R > 0)
        return p->R;
    if (p->k != 1.0)
        return exp(-(log(p->k) + lf_probe_log_prefactor(p)) / (p->k - 1.0));
    return 1.0;
}

static const char *const tip_names[] = {
    [LF_TIP_POWER] = "power", [LF_TIP_CONE] = "cone", [LF_TIP_BERKOVICH] = "berkovich",
    [LF_TIP_PYRAMID] = "pyramid", [LF_TIP_SPHERE] = "sphere",
};
#define NTIP (sizeof tip_names / sizeof tip_names[0])

const char *
lf_tip_name(lf_tip tip)
{
    return (size_t) tip < NTIP ? tip_names[tip] : "?";
}

int
lf_tip_find(const char *name, double *k)
{
    static const struct { const char *name; lf_tip tip; double k; } words[] = {
        { "power", LF_TIP_POWER, NAN }, { "paraboloid", LF_TIP_POWER, 2.0 },
        { "cone", LF_TIP_CONE, 1.0 }, { "berkovich", LF_TIP_BERKOVICH, 1.0 },
        { "pyramid", LF_TIP_PYRAMID, 1.0 }, { "sphere", LF_TIP_SPHERE, 2.0 },
    };
    size_t i;

    for (i = 0; i < sizeof words / sizeof words[0]; i++)
        if (strcmp(name, words[i].name) == 0) {
            if (k != NULL)
                *k = words[i].k;
            return (int) words[i].tip;
        }
    return -1;
}

#define CONE_HOW "state its half-angle (a cone: tip cone, half-angle 35deg; tip berkovich; " \
                 "tip pyramid with its face half-angle) or its prefactor B of f = B r"

int
lf_probe_check(const lf_probe *p, lf_error *err)
{
    const int k1 = p->tip == LF_TIP_CONE || p->tip == LF_TIP_BERKOVICH
                   || p->tip == LF_TIP_PYRAMID;

    if ((size_t) p->tip >= NTIP)
        return lf_fail(err, LF_EINVAL, "tip: unknown shape %d", (int) p->tip);
    if (!(isfinite(p->k) && p->k > 0))
        return lf_fail(err, LF_EINVAL, "k must be a finite number > 0 (got %g)", p->k);
    if (k1 && p->k != 1.0)
        return lf_fail(err, LF_EINVAL, "k must be 1 for a %s (got %g): its profile is "
                       "f = r cot(alpha)", lf_tip_name(p->tip), p->k);
    if (p->tip == LF_TIP_SPHERE && p->k != 2.0)
        return lf_fail(err, LF_EINVAL, "k must be 2 for a sphere (got %g)", p->k);
    if ((p->tip == LF_TIP_CONE || p->tip == LF_TIP_PYRAMID)
        && !(p->angle > 0 && p->angle < 0.5 * M_PI))
        return lf_fail(err, LF_EINVAL, "half-angle must lie between 0 and 90 degrees for a %s "
                       "(got %g deg)", lf_tip_name(p->tip), p->angle * 180.0 / M_PI);
    if (p->tip == LF_TIP_POWER && p->B != 0 && !(isfinite(p->B) && p->B > 0))
        return lf_fail(err, LF_EINVAL, "B must be a finite prefactor > 0 (got %g m^(1-k))",
                       p->B);
    if (p->tip == LF_TIP_POWER && p->B == 0 && p->k == 1.0)
        return lf_fail(err, LF_EINVAL, "k = 1 is a cone, and R does not shape a cone (f = r "
                       "whatever R): " CONE_HOW);
    if ((p->tip == LF_TIP_SPHERE || (p->tip == LF_TIP_POWER && p->B == 0))
        && !(isfinite(p->R) && p->R > 0))
        return lf_fail(err, LF_EINVAL, "R must be a finite length > 0 (got %g m)", p->R);
    if (!(isfinite(p->b) && p->b > 0))
        return lf_fail(err, LF_EINVAL, "b must be a finite length > 0 (got %g m)", p->b);
    if (p->base != LF_BASE_FRICTIONLESS && p->base != LF_BASE_BONDED)
        return lf_fail(err, LF_EINVAL, "interface must be frictionless or bonded");
    if (!isfinite(lf_probe_log_prefactor(p)))
        return lf_fail(err, LF_EINVAL, "the profile's prefactor of k = %g leaves double "
                       "precision", p->k);
    return LF_OK;
}

int
lf_probe_uses_R(const lf_probe *p)
{
    return p->tip == LF_TIP_SPHERE || (p->tip == LF_TIP_POWER && p->B == 0);
}

/* The layer of the statement: b and interface together, or neither for a
 * half-space. */
static int
layer_of(const lf_probe_statement *a, lf_base *base, lf_error *err)
{
    const char *leave = a->halfspace ? "; the half-space model uses neither: leave both out" : "";

    *base = LF_BASE_FRICTIONLESS;
    if (!isnan(a->b) && a->interface == NULL)
        return lf_fail(err, LF_EINVAL, "--b needs --interface (frictionless or bonded)%s", leave);
    if (isnan(a->b) && a->interface != NULL)
        return lf_fail(err, LF_EINVAL, "--interface needs --b (the layer's thickness, e.g. "
                       "--b 1um)%s", leave);
    if (isnan(a->b)) {
        if (!a->halfspace)
            return lf_fail(err, LF_EINVAL, "the %s model needs the layer: --b and --interface "
                           "(e.g. --b 1um --interface frictionless), or fit the curves as a "
                           "half-space with --model halfspace (no layer)",
                           a->model != NULL ? a->model : "auto");
        return LF_OK;
    }
    if (strcmp(a->interface, "frictionless") == 0)
        *base = LF_BASE_FRICTIONLESS;
    else if (strcmp(a->interface, "bonded") == 0)
        *base = LF_BASE_BONDED;
    else
        return lf_fail(err, LF_EINVAL, "unknown interface '%s' (frictionless or bonded)",
                       a->interface);
    return LF_OK;
}

int
lf_probe_shape_stated(const lf_probe_statement *a)
{
    return !isnan(a->k) || a->tip != NULL || !isnan(a->half_angle) || !isnan(a->B);
}

int
lf_probe_state(const lf_probe_statement *a, lf_probe *p, lf_error *err)
{
    double k = a->k, kt = NAN;
    int tip = LF_TIP_POWER, status;
    lf_probe chk;
    lf_error e;

    memset(p, 0, sizeof *p);
    if (a->tip != NULL) {
        if ((tip = lf_tip_find(a->tip, &kt)) < 0)
            return lf_fail(err, LF_EINVAL, "unknown --tip '%s' (paraboloid, sphere, cone, "
                           "berkovich, pyramid, or power with --k)", a->tip);
        if (!isnan(kt) && !isnan(k) && k != kt)
            return lf_fail(err, LF_EINVAL, "--tip %s is k = %g: leave --k out (got --k %g)",
                           a->tip, kt, k);
        if (!isnan(kt))
            k = kt;
    } else if (!isnan(a->half_angle)) {
        tip = LF_TIP_CONE;        /* a half-angle alone states a cone */
        if (isnan(k))
            k = 1.0;
    }
    if (isnan(k))
        return lf_fail(err, LF_EINVAL, "state the probe's shape: --k K (with --R, or R from the "
                       "file's header, or --B), or --tip paraboloid, sphere, cone, berkovich or "
                       "pyramid");
    if ((tip == LF_TIP_CONE || tip == LF_TIP_PYRAMID) && isnan(a->half_angle))
        return lf_fail(err, LF_EINVAL, "--tip %s needs its %shalf-angle (e.g. --half-angle 35deg)",
                       lf_tip_name((lf_tip) tip), tip == LF_TIP_PYRAMID ? "faces' " : "");
    if (!isnan(a->half_angle) && tip != LF_TIP_CONE && tip != LF_TIP_PYRAMID)
        return lf_fail(err, LF_EINVAL, "--half-angle states a cone or a four-sided pyramid "
                       "(--tip cone, --tip pyramid); %s", tip == LF_TIP_BERKOVICH
                       ? "a Berkovich tip has its own equivalent cone (70.3 deg): leave it out"
                       : "this probe is stated by --R or --B");
    if (!isnan(a->B) && tip != LF_TIP_POWER)
        return lf_fail(err, LF_EINVAL, "--B is the prefactor of a power law f = B r^k (with "
                       "--k); a %s is stated by %s", lf_tip_name((lf_tip) tip),
                       tip == LF_TIP_SPHERE ? "--R" : "its half-angle");
    if (!isnan(a->B) && !isnan(a->R))
        return lf_fail(err, LF_EINVAL, "--R and --B both state the profile (B = 1/(k R^(k-1))): "
                       "give one");
    if (!isnan(a->R) && (tip == LF_TIP_CONE || tip == LF_TIP_BERKOVICH || tip == LF_TIP_PYRAMID))
        return lf_fail(err, LF_EINVAL, "R does not shape a %s (f = r cot(alpha)): leave --R out",
                       lf_tip_name((lf_tip) tip));
    if (tip == LF_TIP_POWER && k == 1.0 && isnan(a->B))
        return lf_fail(err, LF_EINVAL, "k = 1 is a cone, and R does not shape a cone (f = r "
                       "whatever R): state its half-angle (--half-angle 35deg, --tip berkovich, "
                       "or --tip pyramid --half-angle THETA of its faces) or its prefactor --B "
                       "(f = B r)");
    if ((status = layer_of(a, &p->base, err)) != LF_OK)
        return status;
    p->k = k;
    p->tip = (lf_tip) tip;
    p->angle = tip == LF_TIP_CONE || tip == LF_TIP_PYRAMID ? a->half_angle : 0.0;
    p->B = isnan(a->B) ? 0.0 : a->B;
    p->R = a->R;              /* NaN: from each file's header, where it is used */
    p->b = a->b;              /* NaN: no layer (a half-space) */
    chk = *p;
    if (isnan(chk.R) && lf_probe_uses_R(&chk))
        chk.R = 1.0;          /* checked with the file's R once it is read */
    if (isnan(chk.b))
        chk.b = 1.0;
    if (lf_probe_check(&chk, &e) != LF_OK)
        return lf_fail(err, e.status, "%s", e.msg);
    return LF_OK;
}

const char *
lf_probe_words(char *buf, size_t n, const lf_probe *p)
{
    char r[48];

    switch (p->tip) {
    case LF_TIP_CONE:
        snprintf(buf, n, "cone, half-angle %.4g°", p->angle * (180.0 / M_PI));
        break;
    case LF_TIP_BERKOVICH:
        snprintf(buf, n, "Berkovich tip as its equivalent cone, half-angle %.4g°",
                 lf_probe_cone_angle(p) * (180.0 / M_PI));
        break;
    case LF_TIP_PYRAMID:
        snprintf(buf, n, "four-sided pyramid, face half-angle %.4g°, as its equivalent cone "
                 "(equal projected area), half-angle %.4g°", p->angle * (180.0 / M_PI),
                 lf_probe_cone_angle(p) * (180.0 / M_PI));
        break;
    case LF_TIP_SPHERE:
        snprintf(buf, n, "sphere, R = %s", lf_human(r, sizeof r, p->R, "m"));
        break;
    default:
        if (p->B > 0)
            snprintf(buf, n, "k = %g, B = %.4g m^%g (f = B r^k)", p->k, p->B, 1.0 - p->k);
        else
            snprintf(buf, n, "k = %g, R = %s", p->k, lf_human(r, sizeof r, p->R, "m"));
        break;
    }
    return buf;
}
