/* units.c: numbers with units, through udunits2.  The unit database is read
 * once per process (pthread_once) and udunits2's own messages are silenced,
 * since the library never prints.  udunits2's parser keeps global state, so
 * every call into it holds units_lock: readers may run in parallel threads
 * (layerfit fit --batch).  A batch reads the same few units in every file,
 * and udunits2 parses one in about ten microseconds, so the last
 * UNITS_MEMO good conversions are kept (under the same lock). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <udunits2.h>

#include "internal.h"

static ut_system *units_system;
static pthread_once_t units_once = PTHREAD_ONCE_INIT;
static pthread_mutex_t units_lock = PTHREAD_MUTEX_INITIALIZER;

static const struct {
    const char *si;       /* udunits2 spelling of the SI unit */
    const char *shown;    /* how we write it */
    const char *noun;     /* "a length" */
    const char *example;  /* a good input */
} quantities[] = {
    [LF_Q_LENGTH]        = { "m", "m", "a length", "1um" },
    [LF_Q_FORCE]         = { "N", "N", "a force", "10uN" },
    [LF_Q_ADHESION]      = { "J/m2", "J/m^2", "a work of adhesion (energy per area)", "10mJ/m2" },
    [LF_Q_PRESSURE]      = { "Pa", "Pa", "a pressure or modulus", "1GPa" },
    [LF_Q_TIME]          = { "s", "s", "a time", "1s" },
    [LF_Q_DIMENSIONLESS] = { "1", "", "a pure number", "0.3" },
    [LF_Q_STIFFNESS]     = { "N/m", "N/m", "a spring constant (force per length)", "0.032N/m" },
    [LF_Q_SENS_VOLT]     = { "m/V", "m/V", "a sensitivity (length per volt)", "50nm/V" },
    [LF_Q_SENS_AMP]      = { "m/A", "m/A", "a sensitivity (length per ampere)", "61nm/nA" },
    [LF_Q_VOLTAGE]       = { "V", "V", "a voltage", "1V" },
    [LF_Q_CURRENT]       = { "A", "A", "a current", "1nA" },
    [LF_Q_ANGLE]         = { "rad", "rad", "an angle", "35deg" },
};
#define NQUANT (sizeof quantities / sizeof quantities[0])

#define UNITS_MEMO 16
static struct {
    lf_quantity q;
    char unit[48];         /* trimmed; "" marks a free slot */
    double factor;
} memo[UNITS_MEMO];
static size_t memo_next;

/* The memo's factor of unit for q (units_lock held); 0 when not kept. */
static int
memo_find(const char *unit, lf_quantity q, double *factor)
{
    size_t i;
    for (i = 0; i < UNITS_MEMO; i++)
        if (memo[i].unit[0] != '\0' && memo[i].q == q && strcmp(memo[i].unit, unit) == 0) {
            *factor = memo[i].factor;
            return 1;
        }
    return 0;
}

static void
memo_keep(const char *unit, lf_quantity q, double factor)
{
    if (strlen(unit) >= sizeof memo[0].unit)
        return;
    memo[memo_next].q = q;
    strcpy(memo[memo_next].unit, unit);
    memo[memo_next].factor = factor;
    memo_next = (memo_next + 1) % UNITS_MEMO;
}

static void
units_load(void)
{
    ut_set_error_message_handler(ut_ignore);
    units_system = ut_read_xml(NULL);
}

const char *
lf_quantity_si(lf_quantity q)
{
    return (size_t) q < NQUANT ? quantities[q].shown : "?";
}

static const char *
trim(char *s)
{
    char *end;
    while (isspace((unsigned char) *s))
        s++;
    end = s + strlen(s);
    while (end > s && isspace((unsigned char) end[-1]))
        *--end = '\0';
    return s;
}

/* Name what kind of quantity a unit measures, for messages. */
static const char *
unit_noun(const ut_unit *u)
{
    size_t q;
    for (q = 0; q < NQUANT; q++) {
        ut_unit *si = q == LF_Q_DIMENSIONLESS ? NULL
                    : ut_parse(units_system, quantities[q].si, UT_ASCII);
        int same = si != NULL && ut_are_convertible(u, si);
        ut_free(si);
        if (same)
            return quantities[q].noun;
    }
    return "another kind of quantity";
}

int
lf_units_factor(const char *unit, lf_quantity q, double *factor, lf_error *err)
{
    char buf[256];
    const char *name;
    ut_unit *u = NULL, *si = NULL;
    cv_converter *cv = NULL;
    int status = LF_OK;

    if ((size_t) q >= NQUANT)
        return lf_fail(err, LF_EINVAL, "unknown quantity");
    pthread_once(&units_once, units_load);
    if (units_system == NULL)
        return lf_fail(err, LF_EUNIT, "the udunits2 database could not be read "
                       "(is libudunits2-data installed? UDUNITS2_XML_PATH may name it)");
    if (strlen(unit) >= sizeof buf)
        return lf_fail(err, LF_EUNIT, "unit too long");
    strcpy(buf, unit);
    name = trim(buf);
    if (*name == '\0') {
        if (q == LF_Q_DIMENSIONLESS) {
            *factor = 1.0;
            return LF_OK;
        }
        return lf_fail(err, LF_EUNIT, "missing unit: expected %s such as %s",
                       quantities[q].noun, quantities[q].example);
    }
    /* udunits2 spells the degree "degree", "arc_degree" or with its sign;
     * "deg", as labs write it, is an alias here */
    if (q == LF_Q_ANGLE && strcmp(name, "deg") == 0)
        name = "degree";
    pthread_mutex_lock(&units_lock);
    if (memo_find(name, q, factor)) {
        pthread_mutex_unlock(&units_lock);
        return LF_OK;
    }
    u = ut_parse(units_system, name, UT_UTF8);
    if (u == NULL) {
        status = lf_fail(err, LF_EUNIT, "unknown unit '%s' (expected %s such as %s)",
                         name, quantities[q].noun, quantities[q].example);
        goto done;
    }
    si = ut_parse(units_system, quantities[q].si, UT_ASCII);
    if (si == NULL || !ut_are_convertible(u, si)) {
        status = lf_fail(err, LF_EUNIT, "unit '%s' is %s, not %s (e.g. %s)", name,
                         unit_noun(u), quantities[q].noun, quantities[q].example);
        goto done;
    }
    cv = ut_get_converter(u, si);
    if (cv == NULL || cv_convert_double(cv, 0.0) != 0.0) {
        status = lf_fail(err, LF_EUNIT, "unit '%s' has an offset; use an absolute unit", name);
        goto done;
    }
    *factor = cv_convert_double(cv, 1.0);
    if (!(isfinite(*factor) && *factor > 0.0))
        status = lf_fail(err, LF_EUNIT, "unit '%s' has no usable scale", name);
    else
        memo_keep(name, q, *factor);
done:
    cv_free(cv);
    ut_free(si);
    ut_free(u);
    pthread_mutex_unlock(&units_lock);
    return status;
}

int
lf_units_parse(const char *text, lf_quantity q, double *si, lf_error *err)
{
    char *end;
    double value, factor;
    int status;

    errno = 0;
    while (isspace((unsigned char) *text))
        text++;
    value = strtod(text, &end);
    if (end == text)
        return lf_fail(err, LF_EINVAL, "'%s' does not start with a number (e.g. %s)",
                       text, quantities[(size_t) q < NQUANT ? q : 0].example);
    if (errno == ERANGE && fabs(value) < 1.0)
        return lf_fail(err, LF_EINVAL, "'%s' is too small for double precision (its magnitude "
                       "is below about 1e-308)", text);
    if (errno == ERANGE || !isfinite(value))
        return lf_fail(err, LF_EINVAL, "'%s' is not a finite number%s", text,
                       errno == ERANGE ? " (its magnitude is above about 1e308)" : "");
    status = lf_units_factor(end, q, &factor, err);
    if (status != LF_OK) {
        if (end[strspn(end, " \t")] == '\0')
            return lf_fail(err, LF_EUNIT, "'%s' has no unit (e.g. %s)", text,
                           quantities[q].example);
        return status;
    }
    *si = value * factor;
    if (!isfinite(*si))
        return lf_fail(err, LF_EINVAL, "'%s' overflows in SI units", text);
    if (*si == 0.0 && value != 0.0)
        return lf_fail(err, LF_EINVAL, "'%s' underflows in SI units (too small for double "
                       "precision)", text);
    return LF_OK;
}

const char *
lf_sensitivity_shown(double si, const char *si_unit, double *shown)
{
    const int per_amp = si_unit != NULL && strcmp(si_unit, "m/A") == 0;

    *shown = per_amp ? si : 1e9 * si;
    return per_amp ? "nm/nA" : "nm/V";
}
