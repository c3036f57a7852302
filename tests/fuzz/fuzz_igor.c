/* fuzz_igor.c: libFuzzer target for the igor reader, forced (see
 * fuzz_check.h): every curve of the file opened from memory. */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz/fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_file("igor", (const char *) data, size))
        abort();
    return 0;
}
