/* fuzz_read.c — libFuzzer target over every heightfield reader: the first byte picks the format, the rest is the
 * file (for .f32: two bytes of sidecar length, the sidecar's JSON, then the data). Build: docs/TESTING.md. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* Fields larger than this are only read for their header, to keep each run fast. */
#define FUZZ_MAX_POINTS (1u << 22)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    frt_file_format format = (frt_file_format)(1 + data[0] % 6);
    data++, size--;
    char *sidecar = NULL;
    if (format == FRT_FILE_F32) {
        if (size < 2)
            return 0;
        size_t n = (size_t)data[0] | (size_t)data[1] << 8;
        data += 2, size -= 2;
        n = n < size ? n : size;
        sidecar = malloc(n + 1);
        if (!sidecar)
            return 0;
        memcpy(sidecar, data, n);
        sidecar[n] = '\0';
        data += n, size -= n;
    }
    FILE *fp = fmemopen((void *)data, size, "rb"); /* glibc takes size 0: an empty file */
    if (!fp) {
        free(sidecar);
        return 0;
    }
    char err[512];
    frt_field_info info;
    frt_result r = frt_read_stream(fp, format, sidecar, "fuzz", &info, NULL, 0, err, sizeof err);
    if (r != FRT_SUCCESS && !err[0])
        abort(); /* every failure says why */
    uint64_t points = (uint64_t)info.width * info.height;
    if (r == FRT_SUCCESS && points <= FUZZ_MAX_POINTS) {
        float *out = malloc((size_t)points * sizeof *out);
        if (out) {
            r = frt_read_stream(fp, format, sidecar, "fuzz", &info, out, (size_t)points, err, sizeof err);
            if (r != FRT_SUCCESS && !err[0])
                abort();
            free(out);
        }
    }
    fclose(fp);
    free(sidecar);
    return 0;
}
