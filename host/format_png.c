/* format_png.c — 16-bit greyscale PNG through libpng: min..max mapped to 0..65535, parameters in text chunks. */
#include "internal.h"

#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

/* The 16-bit sample of height v: round((v - min) / (max - min) * 65535); a flat field maps to 0. */
static uint16_t quantise(float v, float min, float max)
{
    if (!(max > min))
        return 0;
    double t = ((double)v - min) / ((double)max - min) * 65535.0 + 0.5;
    if (t < 0.0)
        t = 0.0;
    if (t > 65535.0)
        t = 65535.0;
    return (uint16_t)t;
}

frt_result frt_write_png16(FILE *fp, const float *h, uint32_t width, uint32_t height, const frt_field_meta *m,
                           char *err, size_t err_size)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *row = malloc((size_t)width * 2);
    char *json = frt_meta_json(m, width, height);
    char min_s[32], max_s[32];
    snprintf(min_s, sizeof min_s, "%.9g", (double)m->min);
    snprintf(max_s, sizeof max_s, "%.9g", (double)m->max);
    frt_result r = FRT_SUCCESS;
    if (!png || !info || !row || !json) {
        snprintf(err, err_size, "out of memory writing PNG");
        r = FRT_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    if (setjmp(png_jmpbuf(png))) {
        snprintf(err, err_size, "libpng failed while writing");
        r = FRT_ERROR_IO;
        goto done;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, width, height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_text text[4];
    memset(text, 0, sizeof text);
    char k0[] = "Software", k1[] = "fracterra:min", k2[] = "fracterra:max", k3[] = "fracterra:params";
    char v0[] = "fracterra " FRT_VERSION_STRING;
    text[0].key = k0;
    text[0].text = v0;
    text[1].key = k1;
    text[1].text = min_s;
    text[2].key = k2;
    text[2].text = max_s;
    text[3].key = k3;
    text[3].text = json;
    for (int i = 0; i < 4; ++i)
        text[i].compression = i == 3 ? PNG_TEXT_COMPRESSION_zTXt : PNG_TEXT_COMPRESSION_NONE;
    png_set_text(png, info, text, 4);
    png_write_info(png, info);
    for (uint32_t y = 0; y < height; ++y) {
        const float *src = h + (size_t)y * width;
        for (uint32_t x = 0; x < width; ++x) {
            uint16_t q = quantise(src[x], m->min, m->max);
            row[2 * x] = (uint8_t)(q >> 8); /* PNG samples are big-endian */
            row[2 * x + 1] = (uint8_t)q;
        }
        png_write_row(png, row);
    }
    png_write_end(png, info);
done:
    png_destroy_write_struct(&png, &info);
    free(row);
    free(json);
    return r;
}
