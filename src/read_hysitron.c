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
    lf_sniff_text(head, len, buf, sizeof buf);
    if (strstr(buf, "Number of Points = ") != NULL && strstr(buf, "Depth (nm)\tLoad (") != NULL)
        return 90;
    if (strstr(buf, "Depth (nm)\tLoad (") != NULL && strstr(buf, "\tDepth (V)") != NULL)
        return 70;
    if (strstr(buf, "\nDepth (nm)\tLoad (") != NULL && strstr(buf, "\tTime (s)") != NULL)
        return 50;
    return 0;
}

const lf_reader_type lf_reader_hysitron = {
    "hysitron", "Hysitron nanoindenter text export (Depth (nm), Load (uN), Time (s), raw "
    "voltages ignored)",
    hysitron_sniff, lf_text_read
};
