/* fuzz_curve.c: libFuzzer target for the curve reader (see fuzz_check.h).
 * The chunk size and --skip-bad-rows follow from the input's length. */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz/fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_curve((const char *) data, size, 1 + size % 13, (int) (size / 13) & 1))
        abort();
    return 0;
}
