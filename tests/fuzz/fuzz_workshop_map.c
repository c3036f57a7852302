/* fuzz_workshop_map.c: libFuzzer target for the workshop-map reader, forced (see
 * fuzz_check.h): every curve of the file opened from memory. */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz/fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_file("workshop-map", (const char *) data, size))
        abort();
    return 0;
}
