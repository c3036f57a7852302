/* test_number.c: lf_csv_number reads a decimal to the same double as
 * strtod (correctly rounded), on the short path for plain decimals and on
 * strtod's for the rest; text that is not a number stays so. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csvsplit.h"
#include "testlib.h"

static unsigned long long rng = 0x9E3779B97F4A7C15ULL;   /* seeded */

static unsigned
next(unsigned n)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (unsigned) (rng % n);
}

/* the same bits as strtod, or the text named */
static int
same_as_strtod(const char *t)
{
    double got = -1.0, want = strtod(t, NULL);
    return lf_csv_number(t, 0, &got) == LF_NUM_OK && memcmp(&got, &want, sizeof got) == 0;
}

/* a random decimal: sign, up to 22 digits with a point somewhere, leading
 * zeros, an exponent of either case and sign, or none */
static void
random_decimal(char *t)
{
    int nd = 1 + (int) next(22), point = (int) next((unsigned) nd + 2) - 1, i, w = 0;
    if (next(3) == 0)
        t[w++] = next(2) ? '-' : '+';
    for (i = 0; i < (int) next(4); i++)
        t[w++] = '0';
    for (i = 0; i < nd; i++) {
        if (i == point)
            t[w++] = '.';
        t[w++] = (char) ('0' + (next(4) == 0 ? 0 : next(10)));
    }
    if (point == nd)
        t[w++] = '.';
    if (next(2)) {
        t[w++] = next(2) ? 'e' : 'E';
        if (next(2))
            t[w++] = next(2) ? '-' : '+';
        w += sprintf(t + w, "%u", next(40));
    }
    t[w] = '\0';
}

int
main(void)
{
    static const char *const edge[] = {
        "0", "-0", "+0", "-0.0", "0.1", "0.3", "1e22", "1e23", "-1e-22", "1e-23",
        "123456789012345", "1234567890123456", "9007199254740993", "4.9e-324",
        "2.2250738585072014e-308", "1.7976931348623157e308", "5.", ".5", "-.5e1",
        "49.9014", "27.3947", "0.000123456789012345", "1.0000000000000000000",
        "999999999999999e22", "1E-7", "3e+00005", "7e000001",
    };
    static const char *const bad[] = { "", ".", "e5", "1e", "1e+", "+-1", "1.2.3", "1e5e5", "--1", "1-", "x" };
    char t[96];
    double v;
    size_t i, fails = 0, n = 200000;

    for (i = 0; i < sizeof edge / sizeof edge[0]; i++)
        t_true(same_as_strtod(edge[i]), "'%s' reads as strtod does", edge[i]);
    for (i = 0; i < n; i++) {
        random_decimal(t);
        if (!same_as_strtod(t) && fails++ < 5)
            printf("  '%s' differs from strtod\n", t);
    }
    t_int((long) fails, 0, "%zu random decimals read as strtod does", n);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
        t_true(lf_csv_number(bad[i], 0, &v) != LF_NUM_OK, "'%s' is not a number", bad[i]);
    t_int(lf_csv_number("1e999", 0, &v), LF_NUM_NONFINITE, "1e999 is not finite");
    t_int(lf_csv_number("-inf", 0, &v), LF_NUM_NONFINITE, "-inf is not finite");
    t_int(lf_csv_number("1,5", 1, &v), LF_NUM_OK, "1,5 with a decimal comma");
    t_rel(v, 1.5, 0.0, "1,5 is 1.5");
    return t_summary();
}
