/* test_number.c: lf_csv_number reads a decimal to the same double as
 * strtod (correctly rounded), on the short path for plain decimals and on
 * strtod's for the rest; text that is not a number stays so.  Read in
 * place, it says of random text (digits, points, commas, signs, exponents,
 * letters) with and without a decimal comma what the rule on a copy says:
 * the comma made a point where it is the only one and no point is there,
 * then strtod. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
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

/* The rule on a copy (lf_csv_number as it read before it read in place):
 * the status, and the value where it is LF_NUM_OK. */
static int
number_by_copy(const char *text, int decimal_comma, double *value)
{
    char buf[80], *end, *p;
    size_t n = strlen(text), i;
    int digits = 0;

    if (n == 0)
        return LF_NUM_EMPTY;
    if (n >= sizeof buf)
        return LF_NUM_BAD;
    memcpy(buf, text, n + 1);
    lf_csv_decimal_point(buf, decimal_comma);
    p = buf + (buf[0] == '+' || buf[0] == '-');
    if (lf_csv_ieq(p, "nan") || lf_csv_ieq(p, "inf") || lf_csv_ieq(p, "infinity"))
        return LF_NUM_NONFINITE;
    for (i = 0; i < n; i++) {
        if (isdigit((unsigned char) buf[i]))
            digits = 1;
        else if (!strchr("+-.eE", buf[i]))
            return LF_NUM_BAD;
    }
    if (!digits)
        return LF_NUM_BAD;
    errno = 0;
    *value = strtod(buf, &end);
    if (end != buf + n)
        return LF_NUM_BAD;
    if (errno == ERANGE && fabs(*value) > 1.0)
        return LF_NUM_NONFINITE;
    return LF_NUM_OK;
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
    {
        static const char alphabet[] = "0123456789012345678901234567890123456789..,,+-eEnNaIif x";
        static const char *const words[] = {
            "1,5", "1,5,6", "1.5,6", ",5", "-,5e3", "1,2345678901234567891", "1,5e999", "NaN",
            "-Infinity", "inf,", "1,e5", "+,", "1,23456789012345678e-400",
        };
        size_t differ = 0, k;
        int dc;
        for (k = 0; k < 2 * sizeof words / sizeof words[0] + 400000; k++) {
            double a = 0.0, b = 0.0;
            int sa, sb;
            dc = (int) (k % 2);
            if (k < 2 * sizeof words / sizeof words[0]) {
                snprintf(t, sizeof t, "%s", words[k / 2]);
            } else {
                size_t len = 1 + next(12), j;
                for (j = 0; j < len; j++)
                    t[j] = alphabet[next(sizeof alphabet - 1)];
                t[len] = '\0';
            }
            sa = lf_csv_number(t, dc, &a);
            sb = number_by_copy(t, dc, &b);
            if (sa != sb || (sa == LF_NUM_OK && memcmp(&a, &b, sizeof a) != 0))
                if (differ++ < 5)
                    printf("  '%s' (decimal comma %d): %d %.17g, on a copy %d %.17g\n", t, dc,
                           sa, a, sb, b);
        }
        t_int((long) differ, 0, "random text read in place as on a copy");
    }
    return t_summary();
}
