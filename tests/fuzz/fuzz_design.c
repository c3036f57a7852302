/* fuzz_design.c: libFuzzer target for the design-plan reader of
 * `layerfit design` (see fuzz_check.h). */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz/fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_design((const char *) data, size))
        abort();
    return 0;
}
