/* test_units.c: numbers with units through udunits2, good and bad. */
#include <math.h>
#include <string.h>

#include "command.h"      /* layerfit.h and what the command shares */
#include "testlib.h"

static const struct {
    const char *text;
    lf_quantity q;
    double si;
} good[] = {
    { "1um", LF_Q_LENGTH, 1e-6 },
    { "1 um", LF_Q_LENGTH, 1e-6 },
    { "1\xc2\xb5m", LF_Q_LENGTH, 1e-6 },        /* micro sign */
    { "1\xce\xbcm", LF_Q_LENGTH, 1e-6 },        /* Greek mu */
    { "1mm", LF_Q_LENGTH, 1e-3 },
    { "-10nm", LF_Q_LENGTH, -1e-8 },
    { "2.5e3 nm", LF_Q_LENGTH, 2.5e-6 },
    { "  3 m ", LF_Q_LENGTH, 3.0 },
    { "10mJ/m2", LF_Q_ADHESION, 1e-2 },
    { "10 mJ/m^2", LF_Q_ADHESION, 1e-2 },
    { "10 mJ m-2", LF_Q_ADHESION, 1e-2 },
    { "0.01 J m-2", LF_Q_ADHESION, 1e-2 },
    { "0.01N/m", LF_Q_ADHESION, 1e-2 },
    { "40 mN/m", LF_Q_ADHESION, 4e-2 },
    { "1GPa", LF_Q_PRESSURE, 1e9 },
    { "10MPa", LF_Q_PRESSURE, 1e7 },
    { "100 kPa", LF_Q_PRESSURE, 1e5 },
    { "5uN", LF_Q_FORCE, 5e-6 },
    { "2 mN", LF_Q_FORCE, 2e-3 },
    { "1.5 s", LF_Q_TIME, 1.5 },
    { "250 ms", LF_Q_TIME, 0.25 },
    { "0.3", LF_Q_DIMENSIONLESS, 0.3 },
};

static const struct {
    const char *text;
    lf_quantity q;
    int status;
    const char *msg;
} bad[] = {
    { "1", LF_Q_LENGTH, LF_EUNIT, "'1' has no unit (e.g. 1um)" },
    { "1GPa", LF_Q_LENGTH, LF_EUNIT, "unit 'GPa' is a pressure or modulus, not a length (e.g. 1um)" },
    { "1um", LF_Q_PRESSURE, LF_EUNIT, "unit 'um' is a length, not a pressure or modulus (e.g. 1GPa)" },
    { "10 mJ", LF_Q_ADHESION, LF_EUNIT,
      "unit 'mJ' is another kind of quantity, not a work of adhesion (energy per area) (e.g. 10mJ/m2)" },
    { "1 furlongz", LF_Q_LENGTH, LF_EUNIT, "unknown unit 'furlongz' (expected a length such as 1um)" },
    { "abc", LF_Q_LENGTH, LF_EINVAL, "'abc' does not start with a number (e.g. 1um)" },
    { "", LF_Q_FORCE, LF_EINVAL, "'' does not start with a number (e.g. 10uN)" },
    { "nan m", LF_Q_LENGTH, LF_EINVAL, "'nan m' is not a finite number" },
    { "inf Pa", LF_Q_PRESSURE, LF_EINVAL, "'inf Pa' is not a finite number" },
    { "1e999 m", LF_Q_LENGTH, LF_EINVAL, "'1e999 m' is not a finite number (its magnitude is above about 1e308)" },
    { "1 degC", LF_Q_LENGTH, LF_EUNIT, "unit 'degC' is another kind of quantity, not a length (e.g. 1um)" },
};

int
main(void)
{
    size_t i;
    double v, f;
    lf_error err;

    for (i = 0; i < sizeof good / sizeof good[0]; i++) {
        v = NAN;
        t_int(lf_units_parse(good[i].text, good[i].q, &v, &err), LF_OK, "'%s' parses", good[i].text);
        t_rel(v, good[i].si, 1e-14, "'%s' in SI", good[i].text);
    }
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        lf_error_clear(&err);
        v = 42.0;
        t_int(lf_units_parse(bad[i].text, bad[i].q, &v, &err), bad[i].status,
              "'%s' is refused", bad[i].text);
        t_str(err.msg, bad[i].msg, "message for '%s'", bad[i].text);
        t_rel(v, 42.0, 0, "'%s' leaves the output alone", bad[i].text);
    }
    t_int(lf_units_factor("uN", LF_Q_FORCE, &f, NULL), LF_OK, "uN factor");
    t_rel(f, 1e-6, 1e-15, "uN = 1e-6 N");
    t_int(lf_units_factor("degC", LF_Q_DIMENSIONLESS, &f, &err), LF_EUNIT, "degC refused");
    t_int(lf_units_factor("", LF_Q_FORCE, &f, &err), LF_EUNIT, "empty unit for a force");
    t_str(err.msg, "missing unit: expected a force such as 10uN", "message for an empty unit");
    t_str(lf_quantity_si(LF_Q_ADHESION), "J/m^2", "SI name of w");
    /* a sensitivity as instruments show it, and back through the parser */
    t_str(lf_sensitivity_shown(61.0, "m/A", &v), "nm/nA", "m/A shown per nA");
    t_rel(v, 61.0, 0, "61 m/A is 61 nm/nA");
    t_str(lf_sensitivity_shown(5e-8, "m/V", &v), "nm/V", "m/V shown in nm/V");
    t_rel(v, 50.0, 1e-15, "5e-8 m/V is 50 nm/V");
    t_int(lf_units_parse("50nm/V", LF_Q_SENS_VOLT, &f, &err), LF_OK, "50nm/V parses");
    t_rel(f, 5e-8, 1e-15, "50nm/V back in SI");
    return t_summary();
}
