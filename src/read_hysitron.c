/* read_hysitron.c: Hysitron (Bruker) TriboIndenter text exports.
 *
 * Layout, as the instrument writes it: a few header lines (the date,
 * "Number of Points = N"), then a tab-separated table
 *     Depth (nm)  Load (µN)  Time (s)  Depth (V)  Load (V)
 * with the micro sign as the Latin-1 byte 0xB5.  The voltage columns are
 * the raw transducer signals and are ignored.  Depth is the indenter's
 * displacement, positive into the sample; the load is positive pushing.
 * Segments: loading, a hold at the peak load (load-controlled), unloading,
 * from the load and depth profiles. */
#include <string.h>

#include "readers.h"

static int
hysitron_sniff(const char *head, size_t len)
{
    char buf[4096];
    size_t n = len < sizeof buf - 1 ? len : sizeof buf - 1;
    memcpy(buf, head, n);
    buf[n] = '\0';
    if (strstr(buf, "Number of Points = ") != NULL && strstr(buf, "Depth (nm)\tLoad (") != NULL)
        return 90;
    if (strstr(buf, "Depth (nm)\tLoad (") != NULL && strstr(buf, "\tDepth (V)") != NULL)
        return 70;
    return 0;
}

static int
hysitron_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
              lf_error *err)
{
    lf_text_table t;
    int status;
    memset(&t, 0, sizeof t);
    t.skip_bad_rows = o->skip_bad_rows;
    status = lf_text_table_read(&t, in, c, err);
    if (status == LF_OK)
        status = lf_text_curve(&t, in, o, c, warn, err);
    lf_text_table_free(&t);
    return status;
}

const lf_reader_type lf_reader_hysitron = {
    "hysitron", "Hysitron nanoindenter text export (Depth (nm), Load (uN), Time (s), raw "
    "voltages ignored)",
    hysitron_sniff, hysitron_read
};
