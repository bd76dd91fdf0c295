/* libFuzzer target: the runtime's EXR reader (dm_exr_decode) on arbitrary bytes.
 * Every input either decodes to finite samples of the size the header states or fails
 * with a message; nothing reads outside the buffer (ASan) or asks for unbounded memory. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/dm_exr_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static dm_exr_file f;
    dm_error err = {0};
    if (dm_exr_decode(data, size, "fuzz.exr", &f, &err) == DM_OK) {
        size_t n = (size_t)f.channel_count * f.width * f.height;
        if (f.width < 1 || f.height < 1 || f.channel_count < 1 || !f.planes) abort();
        for (size_t i = 0; i < n; ++i)
            if (!isfinite(f.planes[i])) abort();
    } else if (!err.detail[0] || f.planes) {
        abort(); /* every failure explains itself and leaves nothing allocated */
    }
    dm_exr_file_free(&f);
    return 0;
}
