/* format_raw.c — raw little-endian float32 (.f32, with a JSON sidecar) and NumPy .npy version 1.0. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

static int host_is_little_endian(void)
{
    const uint16_t one = 1;
    return *(const uint8_t *)&one == 1;
}

/* Writes floats as little-endian whatever the host's byte order. */
static frt_result write_le_floats(FILE *fp, const float *h, size_t count)
{
    if (host_is_little_endian())
        return fwrite(h, sizeof *h, count, fp) == count ? FRT_SUCCESS : FRT_ERROR_IO;
    uint8_t buf[4096];
    size_t i = 0;
    while (i < count) {
        size_t k = 0;
        for (; k < sizeof buf / 4 && i < count; ++k, ++i) {
            uint32_t u;
            memcpy(&u, &h[i], 4);
            buf[4 * k] = (uint8_t)u;
            buf[4 * k + 1] = (uint8_t)(u >> 8);
            buf[4 * k + 2] = (uint8_t)(u >> 16);
            buf[4 * k + 3] = (uint8_t)(u >> 24);
        }
        if (fwrite(buf, 4, k, fp) != k)
            return FRT_ERROR_IO;
    }
    return FRT_SUCCESS;
}

frt_result frt_write_f32(FILE *fp, const float *h, size_t count)
{
    return write_le_floats(fp, h, count);
}

frt_result frt_write_npy(FILE *fp, const float *h, uint32_t width, uint32_t height)
{
    /* NPY 1.0: magic, version, little-endian uint16 header length, then a Python dict literal padded with
     * spaces and ended by '\n' so that the data starts at a multiple of 64 bytes. */
    char dict[128];
    int len =
        snprintf(dict, sizeof dict, "{'descr': '<f4', 'fortran_order': False, 'shape': (%u, %u), }", height, width);
    size_t total = 10 + (size_t)len + 1;
    size_t padded = (total + 63) / 64 * 64;
    size_t header_len = padded - 10;
    uint8_t pre[10] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, (uint8_t)header_len, (uint8_t)(header_len >> 8)};
    if (fwrite(pre, 1, sizeof pre, fp) != sizeof pre || fwrite(dict, 1, (size_t)len, fp) != (size_t)len)
        return FRT_ERROR_IO;
    for (size_t i = 10 + (size_t)len; i < padded - 1; ++i)
        if (fputc(' ', fp) == EOF)
            return FRT_ERROR_IO;
    if (fputc('\n', fp) == EOF)
        return FRT_ERROR_IO;
    return write_le_floats(fp, h, (size_t)width * height);
}
