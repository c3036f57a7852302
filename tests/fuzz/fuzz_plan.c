/* fuzz_plan.c: libFuzzer target for the plan reader (see fuzz_check.h).
 * Plans name curves a.csv, b.csv and c.csv, which are made once in a
 * fresh temporary folder so that rows past the first can be reached. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "fuzz/fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *
curve_dir(void)
{
    static char dir[] = "/tmp/layerfit-fuzz-XXXXXX";
    static int made;
    const char *names[] = { "a.csv", "b.csv", "c.csv" };
    char path[64];
    size_t i;

    if (made)
        return dir;
    if (mkdtemp(dir) == NULL)
        abort();
    for (i = 0; i < 3; i++) {
        FILE *f;
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        if ((f = fopen(path, "w")) == NULL)
            abort();
        fputs("depth_nm,force_uN\n0,0\n1,1\n", f);
        fclose(f);
    }
    made = 1;
    return dir;
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_plan((const char *) data, size, 1 + size % 13, curve_dir()))
        abort();
    return 0;
}
