/* format_raw.c — raw little-endian float32 (.f32, its size in a JSON sidecar) and NumPy .npy (read: versions 1-3,
 * float, integer and byte samples, C or Fortran order; write: version 1.0, '<f4', C order). */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool host_is_little_endian(void)
{
    const uint16_t one = 1;
    return *(const uint8_t *)&one == 1;
}

/* Writes floats as little-endian whatever the host's byte order. */
static void write_le_floats(frt_wr *w, const float *h, size_t count)
{
    if (host_is_little_endian()) {
        frt_wr_bytes(w, h, count * sizeof *h);
        return;
    }
    uint8_t buf[4096];
    for (size_t i = 0; i < count;) {
        size_t k = 0;
        for (; k < sizeof buf / 4 && i < count; ++k, ++i) {
            uint32_t u;
            memcpy(&u, &h[i], 4);
            frt_put_le32(buf + 4 * k, u);
        }
        frt_wr_bytes(w, buf, 4 * k);
    }
}

frt_result frt_f32_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    frt_wr w = {fp, 0};
    write_le_floats(&w, f->h, (size_t)f->width * f->height);
    return frt_wr_finish(&w, f->name, err, err_size);
}

frt_result frt_f32_read(frt_rd *rd, const char *sidecar_json, frt_field_info *info, float *out, size_t out_count)
{
    if (!sidecar_json)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_IO, rd->name, ": its sidecar (FILE.f32.json) is missing");
    frt_meta_extra ex;
    frt_result r =
        frt_meta_parse(sidecar_json, strlen(sidecar_json), info, &ex, rd->name, "its sidecar", rd->err, rd->err_size);
    if (r != FRT_SUCCESS)
        return r;
    if (!ex.has_size)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": its sidecar gives no width and height");
    if ((ex.dtype[0] && strcmp(ex.dtype, "float32") != 0) || (ex.byte_order[0] && strcmp(ex.byte_order, "little")))
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": its sidecar says dtype '%s', byte order '%s'; .f32 is float32, little-endian", ex.dtype,
                        ex.byte_order);
    info->width = ex.width;
    info->height = ex.height;
    info->bits = 32;
    if ((r = frt_rd_check_grid(rd, info, NULL, 0)) != FRT_SUCCESS)
        return r;
    uint64_t bytes = (uint64_t)info->width * info->height * 4; /* <= 2^34 after the check */
    if (rd->size != bytes)
        return frt_fail(rd->err, rd->err_size, rd->size < bytes ? FRT_ERROR_IO : FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        " has %llu bytes but its sidecar says %u x %u (%llu bytes)", (unsigned long long)rd->size,
                        info->width, info->height, (unsigned long long)bytes);
    if (!out)
        return FRT_SUCCESS;
    if ((r = frt_rd_check_grid(rd, info, out, out_count)) != FRT_SUCCESS)
        return r;
    if (!frt_rd_read(rd, out, (size_t)bytes))
        return frt_rd_truncated(rd, "in the data");
    if (!host_is_little_endian())
        for (size_t i = 0; i < (size_t)bytes / 4; ++i) {
            uint32_t u = frt_get_le32((const uint8_t *)&out[i]);
            memcpy(&out[i], &u, 4);
        }
    return FRT_SUCCESS;
}

/* ---- NumPy .npy: https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html ---- */

frt_result frt_npy_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    /* NPY 1.0: magic, version, little-endian uint16 header length, then a Python dict literal padded with
     * spaces and ended by '\n' so that the data starts at a multiple of 64 bytes. */
    char dict[128];
    int len = snprintf(dict, sizeof dict, "{'descr': '<f4', 'fortran_order': False, 'shape': (%u, %u), }", f->height,
                       f->width);
    size_t total = 10 + (size_t)len + 1;
    size_t padded = (total + 63) / 64 * 64;
    size_t header_len = padded - 10;
    uint8_t pre[10] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, (uint8_t)header_len, (uint8_t)(header_len >> 8)};
    frt_wr w = {fp, 0};
    frt_wr_bytes(&w, pre, sizeof pre);
    frt_wr_bytes(&w, dict, (size_t)len);
    static const char spaces[64] = "                                                               ";
    frt_wr_bytes(&w, spaces, padded - 1 - 10 - (size_t)len);
    frt_wr_bytes(&w, "\n", 1);
    write_le_floats(&w, f->h, (size_t)f->width * f->height);
    return frt_wr_finish(&w, f->name, err, err_size);
}

/* The header dict, e.g. {'descr': '<f4', 'fortran_order': False, 'shape': (3, 4), } — the subset of Python
 * literals that numpy writes. */
typedef struct npy_header {
    char descr[16];
    int fortran; /* -1 until seen */
    int dims;    /* -1 until seen */
    uint64_t shape[2];
} npy_header;

typedef struct lit {
    const char *p, *end;
} lit;

static void lit_ws(lit *l)
{
    while (l->p < l->end && (*l->p == ' ' || *l->p == '\t' || *l->p == '\n' || *l->p == '\r'))
        ++l->p;
}

static bool lit_char(lit *l, char c)
{
    lit_ws(l);
    if (l->p < l->end && *l->p == c) {
        ++l->p;
        return true;
    }
    return false;
}

static bool lit_string(lit *l, char *out, size_t cap)
{
    lit_ws(l);
    if (l->p >= l->end || (*l->p != '\'' && *l->p != '"'))
        return false;
    char q = *l->p++;
    size_t n = 0;
    while (l->p < l->end && *l->p != q) {
        if (*l->p == '\\' && ++l->p >= l->end)
            return false;
        if (n + 1 >= cap)
            return false;
        out[n++] = *l->p++;
    }
    if (l->p >= l->end)
        return false;
    ++l->p;
    out[n] = '\0';
    return true;
}

static bool lit_word(lit *l, const char *w)
{
    lit_ws(l);
    size_t n = strlen(w);
    if ((size_t)(l->end - l->p) >= n && memcmp(l->p, w, n) == 0) {
        l->p += n;
        return true;
    }
    return false;
}

static bool lit_shape(lit *l, npy_header *h)
{
    if (!lit_char(l, '('))
        return false;
    h->dims = 0;
    for (;;) {
        if (lit_char(l, ')'))
            return true;
        lit_ws(l);
        if (l->p >= l->end || *l->p < '0' || *l->p > '9')
            return false;
        uint64_t v = 0;
        while (l->p < l->end && *l->p >= '0' && *l->p <= '9') {
            if (v > (UINT64_MAX - 9) / 10)
                return false;
            v = v * 10 + (uint64_t)(*l->p++ - '0');
        }
        if (l->p < l->end && *l->p == 'L') /* Python 2 long */
            ++l->p;
        if (h->dims < 2)
            h->shape[h->dims] = v;
        h->dims++;
        if (h->dims > 32)
            return false;
        if (!lit_char(l, ','))
            return lit_char(l, ')');
    }
}

static bool parse_npy_header(const char *text, size_t len, npy_header *h)
{
    lit l = {text, text + len};
    h->descr[0] = '\0';
    h->fortran = h->dims = -1;
    if (!lit_char(&l, '{'))
        return false;
    for (;;) {
        if (lit_char(&l, '}'))
            break;
        char key[32];
        if (!lit_string(&l, key, sizeof key) || !lit_char(&l, ':'))
            return false;
        if (strcmp(key, "descr") == 0) {
            if (!lit_string(&l, h->descr, sizeof h->descr))
                return false;
        } else if (strcmp(key, "fortran_order") == 0) {
            if (lit_word(&l, "True"))
                h->fortran = 1;
            else if (lit_word(&l, "False"))
                h->fortran = 0;
            else
                return false;
        } else if (strcmp(key, "shape") == 0) {
            if (!lit_shape(&l, h))
                return false;
        } else {
            return false;
        }
        if (lit_char(&l, ','))
            continue;
        if (lit_char(&l, '}'))
            break;
        return false;
    }
    lit_ws(&l);
    return l.p == l.end && h->descr[0] && h->fortran >= 0 && h->dims >= 0;
}

typedef enum sample_kind { S_FLOAT, S_UINT, S_INT } sample_kind;

typedef struct npy_type {
    sample_kind kind;
    unsigned size;
    bool big_endian;
} npy_type;

static bool npy_type_of(const char *descr, npy_type *t)
{
    if (strlen(descr) != 3 || !strchr("<>|=", descr[0]))
        return false;
    t->big_endian = descr[0] == '>' || (descr[0] == '=' && !host_is_little_endian());
    t->size = (unsigned)(descr[2] - '0');
    switch (descr[1]) {
    case 'f': t->kind = S_FLOAT; return t->size == 4 || t->size == 8;
    case 'u': t->kind = S_UINT; return t->size == 1 || t->size == 2;
    case 'i': t->kind = S_INT; return t->size == 1 || t->size == 2 || t->size == 4;
    default: return false;
    }
}

static float decode_sample(const uint8_t *p, const npy_type *t)
{
    uint64_t u = 0;
    for (unsigned i = 0; i < t->size; ++i)
        u |= (uint64_t)p[t->big_endian ? i : t->size - 1 - i] << (8 * (t->size - 1 - i));
    switch (t->kind) {
    case S_FLOAT:
        if (t->size == 4) {
            uint32_t b = (uint32_t)u;
            float f;
            memcpy(&f, &b, 4);
            return f;
        } else {
            double d;
            memcpy(&d, &u, 8);
            return (float)d;
        }
    case S_UINT: return (float)u;
    case S_INT: {
        unsigned shift = 64 - 8 * t->size; /* sign-extend */
        return (float)((int64_t)(u << shift) >> shift);
    }
    }
    return 0.0f;
}

frt_result frt_npy_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count)
{
    frt_result r = frt_rd_magic(rd, "\x93NUMPY", 6, "a NumPy .npy file");
    if (r != FRT_SUCCESS)
        return r;
    uint8_t v[6];
    if (!frt_rd_read(rd, v, 2))
        return frt_rd_truncated(rd, "in its version");
    if (v[0] < 1 || v[0] > 3 || v[1] != 0)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": .npy version %u.%u is not supported (1.0, 2.0 and 3.0 are)", v[0], v[1]);
    size_t len_bytes = v[0] == 1 ? 2 : 4;
    if (!frt_rd_read(rd, v + 2, len_bytes))
        return frt_rd_truncated(rd, "in its header length");
    uint32_t header_len = len_bytes == 2 ? (uint32_t)(v[2] | v[3] << 8) : frt_get_le32(v + 2);
    if (header_len > frt_rd_left(rd))
        return frt_rd_truncated(rd, "in its header");
    if (header_len > (1u << 20))
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": its header of %u bytes is longer than 1 MiB", header_len);
    char *text = malloc(header_len + 1u);
    if (!text)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
    npy_header h;
    bool got = frt_rd_read(rd, text, header_len), parsed = got && parse_npy_header(text, header_len, &h);
    free(text);
    if (!got)
        return frt_rd_truncated(rd, "in its header");
    if (!parsed)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": its header is not a dict with 'descr', 'fortran_order' and 'shape'");
    npy_type t;
    if (!npy_type_of(h.descr, &t))
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": dtype '%s' is not supported (f4, f8, u1, u2, i1, i2, i4 are)", h.descr);
    if (h.dims != 2 || h.shape[0] < 1 || h.shape[1] < 1 || h.shape[0] > UINT32_MAX || h.shape[1] > UINT32_MAX)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": a heightfield is a 2-D array (rows, columns) of at least 1 x 1, not this %d-D one", h.dims);
    info->height = (uint32_t)h.shape[0];
    info->width = (uint32_t)h.shape[1];
    info->bits = 8 * t.size;
    if ((r = frt_rd_check_grid(rd, info, NULL, 0)) != FRT_SUCCESS)
        return r;
    uint64_t points = (uint64_t)info->width * info->height, bytes = points * t.size;
    if (frt_rd_left(rd) != bytes)
        return frt_fail(rd->err, rd->err_size, frt_rd_left(rd) < bytes ? FRT_ERROR_IO : FRT_ERROR_INVALID_ARGUMENT,
                        rd->name, " has %llu bytes of data but its header says %u x %u '%s' (%llu bytes)",
                        (unsigned long long)frt_rd_left(rd), info->height, info->width, h.descr,
                        (unsigned long long)bytes);
    if (!out)
        return FRT_SUCCESS;
    if ((r = frt_rd_check_grid(rd, info, out, out_count)) != FRT_SUCCESS)
        return r;
    if (!h.fortran && t.kind == S_FLOAT && t.size == 4 && !t.big_endian && host_is_little_endian()) {
        if (!frt_rd_read(rd, out, (size_t)bytes))
            return frt_rd_truncated(rd, "in the data");
        return FRT_SUCCESS;
    }
    uint8_t buf[8 * 1024];
    size_t per = sizeof buf / t.size;
    for (uint64_t k = 0; k < points;) {
        size_t n = points - k < per ? (size_t)(points - k) : per;
        if (!frt_rd_read(rd, buf, n * t.size))
            return frt_rd_truncated(rd, "in the data");
        for (size_t i = 0; i < n; ++i, ++k) {
            float value = decode_sample(buf + i * t.size, &t);
            if (h.fortran) /* column-major: element k is (row k % rows, column k / rows) */
                out[(size_t)(k % info->height) * info->width + (size_t)(k / info->height)] = value;
            else
                out[k] = value;
        }
    }
    return FRT_SUCCESS;
}
