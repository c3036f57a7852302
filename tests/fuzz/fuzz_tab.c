/* fuzz_tab.c: libFuzzer target for the tab reader, forced (see fuzz_check.h).
 * The chunk size and the sensitivity's kind follow from the input's length. */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz/fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_reader("tab", (const char *) data, size, 1 + size % 13, (int) (size / 13) & 1))
        abort();
    return 0;
}
