/* formats.c — choosing a heightfield format by extension, and the parameters every format records. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

frt_format frt_format_from_path(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (!dot || strchr(dot, '/'))
        return FRT_FORMAT_NONE;
    if (strcasecmp(dot, ".f32") == 0)
        return FRT_FORMAT_F32;
    if (strcasecmp(dot, ".npy") == 0)
        return FRT_FORMAT_NPY;
    if (strcasecmp(dot, ".png") == 0)
        return FRT_FORMAT_PNG;
    return FRT_FORMAT_NONE;
}

char *frt_sidecar_path(const char *path)
{
    size_t n = strlen(path);
    char *s = malloc(n + 6);
    if (s)
        snprintf(s, n + 6, "%s.json", path);
    return s;
}

void frt_field_minmax(const float *h, size_t count, float *min, float *max)
{
    float lo = count ? h[0] : 0.0f, hi = lo;
    for (size_t i = 1; i < count; ++i) {
        if (h[i] < lo)
            lo = h[i];
        if (h[i] > hi)
            hi = h[i];
    }
    *min = lo;
    *max = hi;
}

/* Appends `s` to `out` as a JSON string (quotes and escapes included). */
static size_t json_string(char *out, size_t cap, const char *s)
{
    size_t n = 0;
#define PUT(c)                                                                                                         \
    do {                                                                                                               \
        if (n + 1 < cap)                                                                                               \
            out[n] = (c);                                                                                              \
        ++n;                                                                                                           \
    } while (0)
    PUT('"');
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; ++p) {
        if (*p == '"' || *p == '\\') {
            PUT('\\');
            PUT((char)*p);
        } else if (*p < 0x20) {
            char esc[8];
            snprintf(esc, sizeof esc, "\\u%04x", *p);
            for (char *e = esc; *e; ++e)
                PUT(*e);
        } else {
            PUT((char)*p);
        }
    }
    PUT('"');
#undef PUT
    if (cap)
        out[n < cap ? n : cap - 1] = '\0';
    return n;
}

char *frt_meta_json(const frt_field_meta *m, uint32_t width, uint32_t height)
{
    char backend[64], device[600];
    json_string(backend, sizeof backend, m->backend);
    json_string(device, sizeof device, m->device);
    size_t cap = 2048;
    char *s = malloc(cap);
    if (!s)
        return NULL;
    snprintf(s, cap,
             "{\n"
             "  \"format\": \"fracterra heightfield\",\n"
             "  \"width\": %u,\n"
             "  \"height\": %u,\n"
             "  \"dtype\": \"float32\",\n"
             "  \"byte_order\": \"little\",\n"
             "  \"layout\": \"row-major, h[y*width + x]\",\n"
             "  \"levels\": %u,\n"
             "  \"hurst\": %.17g,\n"
             "  \"dimension\": %.17g,\n"
             "  \"sigma\": %.17g,\n"
             "  \"seed\": %llu,\n"
             "  \"edge\": \"ffc\",\n"
             "  \"backend\": %s,\n"
             "  \"device\": %s,\n"
             "  \"min\": %.9g,\n"
             "  \"max\": %.9g,\n"
             "  \"spec_version\": %d,\n"
             "  \"fracterra_version\": \"%s\"\n"
             "}\n",
             width, height, m->desc.levels, m->desc.hurst, 3.0 - m->desc.hurst, m->desc.sigma,
             (unsigned long long)m->desc.seed, backend, device, (double)m->min, (double)m->max, FRT_SPEC_VERSION,
             FRT_VERSION_STRING);
    return s;
}
