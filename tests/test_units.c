/* test_units.c: numbers with units through udunits2 (placeholder). */
#include "layerfit.h"
#include "testlib.h"

int
main(void)
{
    double v = 0;
    t_int(lf_units_parse("1um", LF_Q_LENGTH, &v, NULL), LF_OK, "1um parses");
    t_rel(v, 1e-6, 1e-15, "1um = 1e-6 m");
    return t_summary();
}
