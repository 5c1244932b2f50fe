/* format_pgm.c — Netpbm PGM: written as P5 (16-bit or 8-bit, big-endian) with min, max and the parameters in
 * comments; read as P5 or P2 with any maxval 1..65535 (https://netpbm.sourceforge.net/doc/pgm.html). */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define COMMENT_MAX 65536

frt_result frt_pgm_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    char *json = frt_meta_json(f, FRT_JSON_LINE);
    uint8_t *row = malloc((size_t)f->width * 2);
    if (!json || !row) {
        free(json);
        free(row);
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, f->name, ": out of memory");
    }
    uint32_t maxq = f->bits == 16 ? 65535u : 255u;
    char min_s[32], max_s[32];
    frt_wr w = {fp, 0};
    frt_wr_printf(&w, "P5\n# fracterra min=%s max=%s\n# fracterra params %s\n%u %u\n%u\n",
                  frt_float_text(min_s, f->min), frt_float_text(max_s, f->max), json, f->width, f->height, maxq);
    for (uint32_t y = 0; y < f->height && !w.errnum; ++y) {
        const float *src = f->h + (size_t)y * f->width;
        for (uint32_t x = 0; x < f->width; ++x) {
            uint32_t q = frt_quantise(src[x], f->min, f->max, maxq);
            if (f->bits == 16) {
                row[2 * x] = (uint8_t)(q >> 8); /* PGM samples wider than a byte are big-endian */
                row[2 * x + 1] = (uint8_t)q;
            } else {
                row[x] = (uint8_t)q;
            }
        }
        frt_wr_bytes(&w, row, (size_t)f->width * (f->bits / 8));
    }
    free(json);
    free(row);
    return frt_wr_finish(&w, f->name, err, err_size);
}

typedef struct pgm_reader {
    frt_rd *rd;
    frt_field_info *info;
    char *comment; /* COMMENT_MAX bytes */
    bool has_range;
    double min, max;
    frt_result r;
} pgm_reader;

static bool is_space(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* A comment (the '#' already read) up to the end of its line; ours carry the range and the parameters. */
static bool pgm_comment(pgm_reader *p)
{
    size_t n = 0;
    int c;
    while ((c = frt_rd_getc(p->rd)) >= 0 && c != '\n' && c != '\r')
        if (n + 1 < COMMENT_MAX)
            p->comment[n++] = (char)c;
    p->comment[n] = '\0';
    const char *s = p->comment;
    while (*s == ' ')
        ++s;
    if (strncmp(s, "fracterra min=", 14) == 0) {
        char *end;
        p->min = strtod(s + 14, &end);
        bool ok = end != s + 14 && strncmp(end, " max=", 5) == 0;
        if (ok) {
            const char *m = end + 5;
            p->max = strtod(m, &end);
            ok = end != m && (*end == '\0' || *end == ' ');
        }
        if (!ok || !isfinite(p->min) || !isfinite(p->max) || !(p->min <= p->max)) {
            p->r = frt_fail(p->rd->err, p->rd->err_size, FRT_ERROR_INVALID_ARGUMENT, p->rd->name,
                            ": its comment 'fracterra min=... max=...' is not a range of numbers");
            return false;
        }
        p->has_range = true;
    } else if (strncmp(s, "fracterra params ", 17) == 0) {
        /* Metadata only: damaged parameters are left unknown rather than making the heights unreadable. */
        frt_meta_extra ex;
        frt_meta_parse(s + 17, strlen(s + 17), p->info, &ex, p->rd->name, "its parameters", NULL, 0);
    }
    if (c < 0 && p->rd->read_errno) {
        p->r = frt_rd_truncated(p->rd, "in its header");
        return false;
    }
    return true;
}

/* A header number after whitespace and comments. `last`: maxval of P5, which exactly one whitespace ends. */
static bool pgm_number(pgm_reader *p, uint32_t *v, uint32_t max, const char *what, bool last)
{
    int c;
    for (;;) {
        c = frt_rd_getc(p->rd);
        if (c == '#') {
            if (!pgm_comment(p))
                return false;
        } else if (!is_space(c)) {
            break;
        }
    }
    if (c < 0) {
        p->r = frt_rd_truncated(p->rd, "in its header");
        return false;
    }
    uint64_t n = 0;
    bool digits = false;
    while (c >= '0' && c <= '9') {
        n = n * 10 + (uint64_t)(c - '0');
        if (n > max)
            break;
        digits = true;
        c = frt_rd_getc(p->rd);
    }
    if (!digits || n < 1 || n > max) {
        p->r = frt_fail(p->rd->err, p->rd->err_size, FRT_ERROR_INVALID_ARGUMENT, p->rd->name,
                        ": its header's %s is not a whole number from 1 to %u", what, max);
        return false;
    }
    if (c < 0 && !last) {
        p->r = frt_rd_truncated(p->rd, "in its header");
        return false;
    }
    if (c == '#' && !last) {
        if (!pgm_comment(p))
            return false;
    } else if (!is_space(c)) {
        p->r = c < 0 ? frt_rd_truncated(p->rd, "in its header")
                     : frt_fail(p->rd->err, p->rd->err_size, FRT_ERROR_INVALID_ARGUMENT, p->rd->name,
                                ": its header's %s is followed by '%c' instead of whitespace", what, c);
        return false;
    }
    *v = (uint32_t)n;
    return true;
}

/* One sample of a P2 raster. */
static bool pgm_ascii_sample(pgm_reader *p, uint32_t maxval, uint32_t *q)
{
    int c;
    do
        c = frt_rd_getc(p->rd);
    while (is_space(c));
    uint32_t n = 0;
    bool digits = false;
    while (c >= '0' && c <= '9') {
        n = n * 10 + (uint32_t)(c - '0');
        digits = true;
        if (n > maxval)
            break;
        c = frt_rd_getc(p->rd);
    }
    if (!digits && c < 0) {
        p->r = frt_rd_truncated(p->rd, "in the samples");
        return false;
    }
    if (!digits || n > maxval || (c >= 0 && !is_space(c))) {
        p->r = frt_fail(p->rd->err, p->rd->err_size, FRT_ERROR_INVALID_ARGUMENT, p->rd->name,
                        ": a sample is not a whole number from 0 to its maxval %u", maxval);
        return false;
    }
    *q = n;
    return true;
}

static frt_result pgm_read_body(pgm_reader *p, float *out, size_t out_count)
{
    frt_rd *rd = p->rd;
    frt_field_info *info = p->info;
    int c0 = frt_rd_getc(rd), c1 = frt_rd_getc(rd);
    if (c0 >= 0 && (c0 != 'P' || (c1 >= 0 && c1 != '5' && c1 != '2')))
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        " is not a PGM file (it does not start with P5 or P2)");
    if (c1 < 0)
        return frt_rd_truncated(rd, "in its signature");
    bool binary = c1 == '5';
    uint32_t maxval;
    if (!pgm_number(p, &info->width, UINT32_MAX, "width", false) ||
        !pgm_number(p, &info->height, UINT32_MAX, "height", false) || !pgm_number(p, &maxval, 65535, "maxval", binary))
        return p->r;
    info->bits = maxval > 255 ? 16 : 8;
    info->has_range = p->has_range;
    frt_result r = frt_rd_check_grid(rd, info, NULL, 0);
    if (r != FRT_SUCCESS)
        return r;
    uint64_t points = (uint64_t)info->width * info->height;
    uint64_t bytes_per = maxval > 255 ? 2 : 1;
    /* P2 samples take at least a digit and a separator. */
    uint64_t need = binary ? points * bytes_per : 2 * points - 1;
    if (frt_rd_left(rd) < need)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_IO, rd->name,
                        " is truncated (its header says %u x %u samples, which take %s%llu bytes; %llu are left)",
                        info->width, info->height, binary ? "" : "at least ", (unsigned long long)need,
                        (unsigned long long)frt_rd_left(rd));
    if (!out)
        return FRT_SUCCESS;
    if ((r = frt_rd_check_grid(rd, info, out, out_count)) != FRT_SUCCESS)
        return r;
    uint8_t buf[8192];
    for (uint64_t k = 0; k < points;) {
        size_t n = binary ? (size_t)(points - k < sizeof buf / bytes_per ? points - k : sizeof buf / bytes_per) : 1;
        if (binary && !frt_rd_read(rd, buf, n * bytes_per))
            return frt_rd_truncated(rd, "in the samples");
        for (size_t i = 0; i < n; ++i, ++k) {
            uint32_t q;
            if (!binary) {
                if (!pgm_ascii_sample(p, maxval, &q))
                    return p->r;
            } else {
                q = bytes_per == 2 ? (uint32_t)buf[2 * i] << 8 | buf[2 * i + 1] : buf[i];
                if (q > maxval)
                    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                                    ": sample %llu is %u, above its maxval %u", (unsigned long long)k + 1, q, maxval);
            }
            out[k] = frt_dequantise(q, maxval, p->has_range, p->min, p->max);
        }
    }
    return FRT_SUCCESS;
}

frt_result frt_pgm_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count)
{
    pgm_reader p;
    memset(&p, 0, sizeof p);
    p.rd = rd;
    p.info = info;
    p.comment = malloc(COMMENT_MAX);
    if (!p.comment)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
    frt_result r = pgm_read_body(&p, out, out_count);
    free(p.comment);
    return r;
}
