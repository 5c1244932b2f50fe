/* format_png.c — PNG through libpng: heightfields as 16-bit (or 8-bit) grey with min, max and the parameters in
 * text chunks; any PNG read back as grey; 8-bit grey or RGB pictures. */
#include "internal.h"

#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

/* libpng reports through callbacks: errors long-jump back with the message kept here, warnings are dropped (a
 * library does not print to stderr), and I/O goes through frt_rd / frt_wr so that failures keep their cause. */
typedef struct frt_png_io {
    frt_rd *rd;
    frt_wr *wr;
    bool truncated;
    size_t alloc_cap; /* reading: libpng's allocations larger than this are refused */
    char msg[160];
} frt_png_io;

static void on_error(png_structp png, png_const_charp msg)
{
    frt_png_io *io = png_get_error_ptr(png);
    snprintf(io->msg, sizeof io->msg, "%s", msg ? msg : "unknown error");
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* A damaged chunk length makes libpng allocate (and clear) that much before it finds the file too short, and its
 * "chunk data is too large" check is only a warning when reading. No valid file needs more than this cap: chunks
 * are shorter than the file, decompressed text and rows are at most 1032 times it (deflate's largest ratio; rows
 * are checked against it after the header), and libpng's row buffers hold 8 bytes a pixel at most. */
static png_voidp capped_malloc(png_structp png, png_alloc_size_t size)
{
    frt_png_io *io = png_get_mem_ptr(png);
    return size <= io->alloc_cap ? malloc(size) : NULL;
}

static void capped_free(png_structp png, png_voidp p)
{
    (void)png;
    free(p);
}

static void on_read(png_structp png, png_bytep data, size_t n)
{
    frt_png_io *io = png_get_io_ptr(png);
    if (!frt_rd_read(io->rd, data, n)) {
        io->truncated = true;
        png_error(png, "truncated");
    }
}

static void on_write(png_structp png, png_bytep data, size_t n)
{
    frt_png_io *io = png_get_io_ptr(png);
    frt_wr_bytes(io->wr, data, n);
    if (io->wr->errnum)
        png_error(png, "write failed");
}

static void on_flush(png_structp png)
{
    (void)png;
}

/* ---- writing ---- */

typedef struct png_src {
    const frt_field_out *f; /* a heightfield, or: */
    const uint8_t *pixels;  /* a picture */
    uint32_t width, height, channels, bits;
    png_text *text;
    int text_count;
    uint8_t *row; /* width * channels * bits / 8 bytes */
} png_src;

/* Everything between setjmp and the end, so that the caller keeps no local that longjmp could leave stale. */
static int write_png_body(png_structp png, png_infop info, frt_png_io *io, const png_src *s)
{
    if (setjmp(png_jmpbuf(png)))
        return -1;
    png_set_write_fn(png, io, on_write, on_flush);
    /* zlib level 3: for 16-bit heights and relief pictures about 2x faster than the default 6 and only a few
     * percent larger (docs/PERFORMANCE.md). */
    png_set_compression_level(png, 3);
    png_set_IHDR(png, info, s->width, s->height, (int)s->bits,
                 s->channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_text(png, info, s->text, s->text_count);
    png_write_info(png, info);
    size_t row_bytes = (size_t)s->width * s->channels;
    for (uint32_t y = 0; y < s->height; ++y) {
        if (s->f) {
            const float *src = s->f->h + (size_t)y * s->width;
            uint32_t maxq = s->bits == 16 ? 65535u : 255u;
            for (uint32_t x = 0; x < s->width; ++x) {
                uint32_t q = frt_quantise(src[x], s->f->min, s->f->max, maxq);
                if (s->bits == 16) {
                    s->row[2 * x] = (uint8_t)(q >> 8); /* PNG samples are big-endian */
                    s->row[2 * x + 1] = (uint8_t)q;
                } else {
                    s->row[x] = (uint8_t)q;
                }
            }
            png_write_row(png, s->row);
        } else {
            png_write_row(png, (png_const_bytep)(s->pixels + (size_t)y * row_bytes));
        }
    }
    png_write_end(png, info);
    return 0;
}

static frt_result write_png_image(FILE *fp, const char *name, const png_src *src, char *err, size_t err_size)
{
    frt_wr w = {fp, 0};
    frt_png_io io;
    memset(&io, 0, sizeof io);
    io.wr = &w;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &io, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, name, ": out of memory");
    }
    int rc = write_png_body(png, info, &io, src);
    png_destroy_write_struct(&png, &info);
    if (w.errnum || rc == 0)
        return frt_wr_finish(&w, name, err, err_size);
    return frt_fail(err, err_size, FRT_ERROR_IO, name, ": cannot write PNG (libpng: %s)", io.msg);
}

frt_result frt_png_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    if (f->width > 0x7fffffffu || f->height > 0x7fffffffu)
        return frt_fail(err, err_size, FRT_ERROR_TOO_LARGE, f->name, ": PNG sides are at most 2^31 - 1");
    char min_s[32], max_s[32];
    char *json = frt_meta_json(f, FRT_JSON_LINE);
    png_src s;
    memset(&s, 0, sizeof s);
    s.f = f;
    s.width = f->width;
    s.height = f->height;
    s.channels = 1;
    s.bits = f->bits;
    s.row = malloc((size_t)f->width * 2);
    if (!json || !s.row) {
        free(json);
        free(s.row);
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, f->name, ": out of memory");
    }
    png_text text[4];
    memset(text, 0, sizeof text);
    char k0[] = "Software", k1[] = "fracterra:min", k2[] = "fracterra:max", k3[] = "fracterra:params";
    char v0[] = "fracterra " FRT_VERSION_STRING;
    char *keys[4] = {k0, k1, k2, k3}, *values[4] = {v0, min_s, max_s, json};
    frt_float_text(min_s, f->min);
    frt_float_text(max_s, f->max);
    for (int i = 0; i < 4; ++i) {
        text[i].key = keys[i];
        text[i].text = values[i];
        text[i].compression = i == 3 ? PNG_TEXT_COMPRESSION_zTXt : PNG_TEXT_COMPRESSION_NONE;
    }
    s.text = text;
    s.text_count = 4;
    frt_result r = write_png_image(fp, f->name, &s, err, err_size);
    free(json);
    free(s.row);
    return r;
}

frt_result frt_png_write_picture(FILE *fp, const char *name, const uint8_t *pixels, uint32_t width, uint32_t height,
                                 uint32_t channels, char *err, size_t err_size)
{
    png_text text;
    memset(&text, 0, sizeof text);
    char key[] = "Software", value[] = "fracterra " FRT_VERSION_STRING;
    text.key = key;
    text.text = value;
    text.compression = PNG_TEXT_COMPRESSION_NONE;
    png_src s;
    memset(&s, 0, sizeof s);
    s.pixels = pixels;
    s.width = width;
    s.height = height;
    s.channels = channels;
    s.bits = 8;
    s.text = &text;
    s.text_count = 1;
    return write_png_image(fp, name, &s, err, err_size);
}

/* ---- reading ---- */

typedef struct png_read_st {
    frt_field_info *info;
    float *out;
    size_t out_count;
    png_bytep *rows;
    frt_result r; /* set by the body on a failure that is not libpng's */
    bool has_min, has_max, bad_range;
    double min, max;
} png_read_st;

static bool parse_number(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    return end != s && *end == '\0' && isfinite(*v);
}

static int read_png_body(png_structp png, png_infop pinfo, frt_png_io *io, png_read_st *st)
{
    frt_rd *rd = io->rd;
    if (setjmp(png_jmpbuf(png)))
        return -1;
    png_set_read_fn(png, io, on_read);
    png_set_sig_bytes(png, 8);
    png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
    /* Fuzzing (the libFuzzer convention's macro): checksums would stop almost every mutation at its chunk. */
    png_set_crc_action(png, PNG_CRC_QUIET_USE, PNG_CRC_QUIET_USE);
    png_set_option(png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
    png_read_info(png, pinfo);
    frt_field_info *info = st->info;
    info->width = png_get_image_width(png, pinfo);
    info->height = png_get_image_height(png, pinfo);
    if ((st->r = frt_rd_check_grid(rd, info, NULL, 0)) != FRT_SUCCESS)
        return 1;
    /* Deflate expands at most 1032:1, so a file that holds less than that share of its raw rows is cut short:
     * refused before the caller allocates room for it. */
    uint64_t raw_row = (uint64_t)png_get_rowbytes(png, pinfo) + 1;
    if (raw_row > (rd->size * 1100 + 65536) / info->height) {
        st->r = frt_rd_truncated(rd, "its header says more pixels than its size can hold");
        return 1;
    }
    png_textp text = NULL;
    int n_text = 0;
    png_get_text(png, pinfo, &text, &n_text);
    for (int i = 0; i < n_text; ++i) {
        if (!text[i].key || !text[i].text)
            continue;
        if (strcmp(text[i].key, "fracterra:min") == 0) {
            st->has_min = true;
            st->bad_range |= !parse_number(text[i].text, &st->min);
        } else if (strcmp(text[i].key, "fracterra:max") == 0) {
            st->has_max = true;
            st->bad_range |= !parse_number(text[i].text, &st->max);
        } else if (strcmp(text[i].key, "fracterra:params") == 0) {
            /* Metadata only: a damaged chunk leaves the parameters unknown rather than the heights unreadable. */
            frt_meta_extra ex;
            frt_meta_parse(text[i].text, strlen(text[i].text), info, &ex, rd->name, "its parameters", NULL, 0);
        }
    }
    if (st->has_min != st->has_max || st->bad_range || (st->has_min && !(st->min <= st->max))) {
        st->r = frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                         ": its text chunks fracterra:min and fracterra:max are not a range of numbers");
        return 1;
    }
    info->has_range = st->has_min;
    /* Any PNG to grey: palette and low bit depths to 8 bits, alpha dropped, colour to luminance. */
    int color = png_get_color_type(png, pinfo);
    png_set_expand(png);
    png_set_strip_alpha(png);
    if (color & PNG_COLOR_MASK_COLOR)
        png_set_rgb_to_gray_fixed(png, 1, -1, -1);
    png_set_interlace_handling(png);
    png_read_update_info(png, pinfo);
    info->bits = png_get_bit_depth(png, pinfo);
    if (png_get_channels(png, pinfo) != 1 || (info->bits != 8 && info->bits != 16))
        png_error(png, "unexpected layout after conversion to grey");
    if (!st->out)
        return 0;
    if ((st->r = frt_rd_check_grid(rd, info, st->out, st->out_count)) != FRT_SUCCESS)
        return 1;
    /* Rows are decoded straight into the caller's floats: a row of samples (at most 2 bytes each) fits in the
     * first half of its row of floats, and is widened in place from the end. */
    st->rows = malloc(info->height * sizeof *st->rows);
    if (!st->rows) {
        st->r = frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
        return 1;
    }
    for (uint32_t y = 0; y < info->height; ++y)
        st->rows[y] = (png_bytep)(st->out + (size_t)y * info->width);
    png_read_image(png, st->rows);
    png_read_end(png, NULL);
    uint32_t maxq = info->bits == 16 ? 65535u : 255u;
    for (uint32_t y = 0; y < info->height; ++y) {
        const uint8_t *src = st->rows[y];
        float *dst = st->out + (size_t)y * info->width;
        for (uint32_t x = info->width; x-- > 0;) {
            uint32_t q = info->bits == 16 ? (uint32_t)src[2 * x] << 8 | src[2 * x + 1] : src[x];
            dst[x] = frt_dequantise(q, maxq, info->has_range, st->min, st->max);
        }
    }
    return 0;
}

frt_result frt_png_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count)
{
    static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    frt_result r = frt_rd_magic(rd, signature, 8, "a PNG file");
    if (r != FRT_SUCCESS)
        return r;
    frt_png_io io;
    memset(&io, 0, sizeof io);
    io.rd = rd;
    png_read_st st;
    memset(&st, 0, sizeof st);
    st.info = info;
    st.out = out;
    st.out_count = out_count;
    uint64_t cap = 16 * (rd->size * 1100 + 65536);
    io.alloc_cap = cap < SIZE_MAX ? (size_t)cap : SIZE_MAX;
    png_structp png =
        png_create_read_struct_2(PNG_LIBPNG_VER_STRING, &io, on_error, on_warning, &io, capped_malloc, capped_free);
    png_infop pinfo = png ? png_create_info_struct(png) : NULL;
    if (!png || !pinfo) {
        png_destroy_read_struct(&png, &pinfo, NULL);
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
    }
    int rc = read_png_body(png, pinfo, &io, &st);
    png_destroy_read_struct(&png, &pinfo, NULL);
    free(st.rows);
    if (rc == 0)
        return FRT_SUCCESS;
    if (rc > 0)
        return st.r;
    if (io.truncated)
        return frt_rd_truncated(rd, "in the PNG data");
    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, ": not a valid PNG file (libpng: %s)",
                    io.msg);
}
