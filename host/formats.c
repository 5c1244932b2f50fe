/* formats.c — what the heightfield formats share: extensions, metadata JSON, number text, quantisation, buffered
 * reading and writing, and the mesh grid (its geometry when writing, its recognition when reading). */
#include "internal.h"

#include <errno.h>
#include <json-c/json.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/types.h>

/* ---- extensions ---- */

static const char *const format_names[] = {"", "png", "pgm", "f32", "npy", "obj", "ply", "tif"};
#define FORMAT_COUNT (sizeof format_names / sizeof format_names[0])

frt_file_format frt_file_format_from_path(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (!dot || strchr(dot, '/'))
        return FRT_FILE_DEFAULT;
    for (size_t i = 1; i < FORMAT_COUNT; ++i)
        if (strcasecmp(dot + 1, format_names[i]) == 0)
            return (frt_file_format)i;
    if (strcasecmp(dot + 1, "tiff") == 0) /* TIFF's other spelling */
        return FRT_FILE_TIFF;
    return FRT_FILE_DEFAULT;
}

const char *frt_file_format_name(frt_file_format format)
{
    return (unsigned)format < FORMAT_COUNT ? format_names[format] : "";
}

/* ---- messages and numbers ---- */

frt_result frt_fail(char *err, size_t err_size, frt_result r, const char *name, const char *fmt, ...)
{
    if (err && err_size) {
        int n = snprintf(err, err_size, "'%s'", name ? name : "");
        if (n >= 0 && (size_t)n < err_size) {
            va_list ap;
            va_start(ap, fmt);
            vsnprintf(err + n, err_size - (size_t)n, fmt, ap);
            va_end(ap);
        }
        /* One line, whatever a file name or a library's message held. */
        for (char *p = err; *p; ++p)
            if (*p == '\n' || *p == '\r')
                *p = ' ';
    }
    return r;
}

/* Formatted in a local buffer: GCC 12 with -fsanitize=undefined warns of a null destination otherwise. */
const char *frt_float_text(char buf[static 32], float v)
{
    char t[32];
    for (int prec = 6; prec <= 9; ++prec) {
        snprintf(t, sizeof t, "%.*g", prec, (double)v);
        if ((float)strtod(t, NULL) == v || v != v)
            break;
    }
    memcpy(buf, t, sizeof t);
    return buf;
}

const char *frt_double_text(char buf[static 32], double v)
{
    char t[32];
    for (int prec = 15; prec <= 17; ++prec) {
        snprintf(t, sizeof t, "%.*g", prec, v);
        if (strtod(t, NULL) == v || v != v)
            break;
    }
    memcpy(buf, t, sizeof t);
    return buf;
}

uint32_t frt_quantise(float v, float min, float max, uint32_t maxq)
{
    if (!(max > min))
        return 0;
    double t = ((double)v - min) / ((double)max - min) * maxq + 0.5;
    if (!(t >= 0.0)) /* also NaN */
        return 0;
    return t >= maxq ? maxq : (uint32_t)t;
}

float frt_dequantise(uint32_t q, uint32_t maxq, bool has_range, double min, double max)
{
    if (!has_range)
        return (float)q;
    return (float)(min + (double)q / maxq * (max - min));
}

/* ---- metadata JSON ---- */

static void put_double(json_object *o, const char *key, double v)
{
    char buf[32];
    json_object_object_add(o, key, isfinite(v) ? json_object_new_double_s(v, frt_double_text(buf, v)) : NULL);
}

static void put_float(json_object *o, const char *key, float v)
{
    char buf[32];
    json_object_object_add(o, key, isfinite(v) ? json_object_new_double_s(v, frt_float_text(buf, v)) : NULL);
}

char *frt_meta_json(const frt_field_out *f, int style)
{
    json_object *o = json_object_new_object();
    if (!o)
        return NULL;
    json_object_object_add(o, "format", json_object_new_string("fracterra heightfield"));
    json_object_object_add(o, "width", json_object_new_int64(f->width));
    json_object_object_add(o, "height", json_object_new_int64(f->height));
    if (style == FRT_JSON_SIDECAR) {
        json_object_object_add(o, "dtype", json_object_new_string("float32"));
        json_object_object_add(o, "byte_order", json_object_new_string("little"));
        json_object_object_add(o, "layout", json_object_new_string("row-major, h[y*width + x]"));
    }
    if (f->format == FRT_FILE_OBJ || f->format == FRT_FILE_PLY)
        json_object_object_add(o, "mesh_stride", json_object_new_int64(f->mesh_stride));
    if (f->has_terrain) {
        char buf[32];
        json_object_object_add(o, "levels", json_object_new_int64(f->terrain.levels));
        put_double(o, "hurst", f->terrain.hurst);
        /* Derived, for the reader's eyes only: 15 digits, so that H = 0.8 shows D = 2.2. */
        snprintf(buf, sizeof buf, "%.15g", 3.0 - f->terrain.hurst);
        json_object_object_add(o, "dimension", json_object_new_double_s(3.0 - f->terrain.hurst, buf));
        put_double(o, "sigma", f->terrain.sigma);
        json_object_object_add(o, "seed", json_object_new_uint64(f->terrain.seed));
        json_object_object_add(o, "edge",
                               json_object_new_string(f->terrain.edge == FRT_EDGE_PERIODIC ? "periodic" : "ffc"));
        if (frt_region_is_set(&f->terrain.region)) {
            /* A window of a larger virtual grid (docs/ALGORITHM.md §3.2): where it lies, and that grid's side. */
            json_object *g = json_object_new_object();
            if (g) {
                json_object_object_add(g, "x", json_object_new_int64(f->terrain.region.x));
                json_object_object_add(g, "y", json_object_new_int64(f->terrain.region.y));
                json_object_object_add(g, "width", json_object_new_int64(f->terrain.region.width));
                json_object_object_add(g, "height", json_object_new_int64(f->terrain.region.height));
            }
            json_object_object_add(o, "region", g);
            json_object_object_add(o, "grid_side", json_object_new_int64(frt_terrain_side(&f->terrain)));
        }
        /* §2.8: the distribution, with its parameter where it has one */
        json_object_object_add(o, "noise", json_object_new_string(frt_noise_name(f->terrain.noise)));
        if (frt_noise_has_param(f->terrain.noise))
            put_double(o, "noise_param", f->terrain.noise_param);
        if (f->terrain.coarse) /* §3.4: levels 0..k came from known heights */
            json_object_object_add(o, "coarse_levels", json_object_new_int64(f->terrain.coarse_levels));
    }
    if (f->history)
        json_object_object_add(o, "history", json_object_new_string(f->history));
    if (f->backend)
        json_object_object_add(o, "backend", json_object_new_string(f->backend));
    if (f->device)
        json_object_object_add(o, "device", json_object_new_string(f->device));
    put_float(o, "min", f->min);
    put_float(o, "max", f->max);
    put_double(o, "spacing_x", f->spacing_x);
    put_double(o, "spacing_y", f->spacing_y);
    put_double(o, "z_scale", f->z_scale);
    json_object_object_add(o, "spec_version", json_object_new_int(FRT_SPEC_VERSION));
    json_object_object_add(o, "fracterra_version", json_object_new_string(FRT_VERSION_STRING));
    int flags = JSON_C_TO_STRING_SPACED | JSON_C_TO_STRING_NOSLASHESCAPE;
    if (style == FRT_JSON_SIDECAR)
        flags |= JSON_C_TO_STRING_PRETTY;
    const char *text = json_object_to_json_string_ext(o, flags);
    char *s = NULL;
    if (text) {
        size_t n = strlen(text);
        s = malloc(n + 2);
        if (s) {
            memcpy(s, text, n);
            s[n] = style == FRT_JSON_SIDECAR ? '\n' : '\0';
            s[n + 1] = '\0';
        }
    }
    json_object_put(o);
    return s;
}

static bool get_number(json_object *root, const char *key, double *v)
{
    json_object *o;
    if (!json_object_object_get_ex(root, key, &o))
        return false;
    if (!json_object_is_type(o, json_type_double) && !json_object_is_type(o, json_type_int))
        return false;
    *v = json_object_get_double(o);
    return isfinite(*v);
}

static bool get_uint(json_object *root, const char *key, uint64_t *v)
{
    json_object *o;
    if (!json_object_object_get_ex(root, key, &o) || !json_object_is_type(o, json_type_int))
        return false;
    if (json_object_get_int64(o) < 0) /* above INT64_MAX it saturates, so only true negatives land here */
        return false;
    *v = json_object_get_uint64(o);
    return true;
}

static const char *get_string(json_object *root, const char *key)
{
    json_object *o;
    if (!json_object_object_get_ex(root, key, &o) || !json_object_is_type(o, json_type_string))
        return NULL;
    return json_object_get_string(o);
}

/* A whole number in 0..UINT32_MAX. */
static bool get_u32(json_object *root, const char *key, uint32_t *v)
{
    uint64_t u;
    if (!get_uint(root, key, &u) || u > UINT32_MAX)
        return false;
    *v = (uint32_t)u;
    return true;
}

/* width or height: absent is fine (0), present must be a whole number in 1..UINT32_MAX. */
static bool get_side(json_object *root, const char *key, uint32_t *side)
{
    *side = 0;
    if (!json_object_object_get_ex(root, key, NULL))
        return true;
    uint64_t v;
    if (!get_uint(root, key, &v) || v < 1 || v > UINT32_MAX)
        return false;
    *side = (uint32_t)v;
    return true;
}

frt_result frt_meta_parse(const char *text, size_t len, frt_field_info *info, frt_meta_extra *extra, const char *name,
                          const char *what, char *err, size_t err_size)
{
    memset(extra, 0, sizeof *extra);
    if (len > (1u << 20))
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name, ": %s is longer than 1 MiB", what);
    json_tokener *tok = json_tokener_new();
    if (!tok)
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, name, ": out of memory");
    json_object *root = json_tokener_parse_ex(tok, text, (int)len);
    enum json_tokener_error jerr = json_tokener_get_error(tok);
    size_t end = json_tokener_get_parse_end(tok);
    json_tokener_free(tok);
    frt_result r = FRT_SUCCESS;
    if (!root || jerr != json_tokener_success) {
        r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name, ": %s is not valid JSON (%s)", what,
                     root ? "trailing characters" : json_tokener_error_desc(jerr));
        goto done;
    }
    while (end < len && (text[end] == ' ' || text[end] == '\n' || text[end] == '\r' || text[end] == '\t'))
        ++end;
    if (end < len && text[end] != '\0') {
        r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name, ": %s has text after its JSON object", what);
        goto done;
    }
    if (!json_object_is_type(root, json_type_object)) {
        r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name, ": %s is not a JSON object", what);
        goto done;
    }
    if (!get_side(root, "width", &extra->width) || !get_side(root, "height", &extra->height)) {
        r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name,
                     ": %s: width and height must be whole numbers from 1 to 4294967295", what);
        goto done;
    }
    extra->has_size = extra->width && extra->height;
    uint64_t stride;
    if (get_uint(root, "mesh_stride", &stride) && stride >= 1 && stride <= UINT32_MAX)
        extra->mesh_stride = (uint32_t)stride;
    const char *s;
    if ((s = get_string(root, "dtype")) != NULL)
        snprintf(extra->dtype, sizeof extra->dtype, "%s", s);
    if ((s = get_string(root, "byte_order")) != NULL)
        snprintf(extra->byte_order, sizeof extra->byte_order, "%s", s);
    if ((s = get_string(root, "backend")) != NULL)
        snprintf(info->backend, sizeof info->backend, "%s", s);
    if ((s = get_string(root, "device")) != NULL)
        snprintf(info->device, sizeof info->device, "%s", s);
    double v;
    if (get_number(root, "spacing_x", &v) && v > 0.0)
        info->spacing_x = v;
    if (get_number(root, "spacing_y", &v) && v > 0.0)
        info->spacing_y = v;
    if (get_number(root, "z_scale", &v) && v != 0.0)
        info->z_scale = v;

    /* The parameters count only when all are there and in range: a reader should not invent any. A region (files
     * before it existed have none: the whole grid) must be complete, match the file's size and the recorded side
     * of its grid, and lets levels go up to FRT_MAX_REGION_LEVELS. */
    frt_terrain_desc d;
    memset(&d, 0, sizeof d);
    uint64_t levels = 0, grid_side = 0;
    const char *edge = get_string(root, "edge");
    json_object *go = NULL;
    const bool has_region = json_object_object_get_ex(root, "region", &go);
    const bool region_ok =
        !has_region || (json_object_is_type(go, json_type_object) && get_u32(go, "x", &d.region.x) &&
                        get_u32(go, "y", &d.region.y) && get_u32(go, "width", &d.region.width) &&
                        get_u32(go, "height", &d.region.height) && d.region.width >= 1 && d.region.height >= 1 &&
                        (!extra->has_size || (extra->width == d.region.width && extra->height == d.region.height)));
    const bool has_grid_side = json_object_object_get_ex(root, "grid_side", NULL);
    if (has_grid_side && !get_uint(root, "grid_side", &grid_side))
        grid_side = 0; /* present but not a whole number: never matches */
    if (region_ok && get_uint(root, "levels", &levels) && levels >= 1 &&
        levels <= (has_region ? FRT_MAX_REGION_LEVELS : FRT_MAX_LEVELS) && get_number(root, "hurst", &d.hurst) &&
        d.hurst != 0.0 && get_number(root, "sigma", &d.sigma) && d.sigma != 0.0 && get_uint(root, "seed", &d.seed) &&
        (!edge || strcmp(edge, "ffc") == 0 || strcmp(edge, "periodic") == 0)) {
        d.levels = (uint32_t)levels;
        d.seed_is_explicit = true;
        d.edge = edge && strcmp(edge, "periodic") == 0 ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
        const char *noise = get_string(root, "noise");
        if (noise) {
            d.noise = (frt_noise_kind)99; /* unknown: fails the check below */
            for (frt_noise_kind k = FRT_NOISE_GAUSS; k <= FRT_NOISE_UNIFORM; ++k)
                if (strcmp(noise, frt_noise_name(k)) == 0)
                    d.noise = k;
        }
        if (frt_noise_has_param(d.noise))
            get_number(root, "noise_param", &d.noise_param);
        if (frt_terrain_desc_resolved(&d, &info->terrain) == FRT_SUCCESS &&
            (!has_grid_side || grid_side == frt_terrain_side(&info->terrain)))
            info->has_terrain = true;
        else
            memset(&info->terrain, 0, sizeof info->terrain);
    }
done:
    json_object_put(root);
    return r;
}

/* ---- buffered reading ---- */

#define RD_BUF_SIZE 65536

frt_result frt_rd_open(frt_rd *rd, FILE *fp, const char *name, char *err, size_t err_size)
{
    memset(rd, 0, sizeof *rd);
    rd->fp = fp;
    rd->name = name;
    rd->err = err;
    rd->err_size = err_size;
    off_t size = -1;
    if (fseeko(fp, 0, SEEK_END) != 0 || (size = ftello(fp)) < 0 || fseeko(fp, 0, SEEK_SET) != 0)
        return frt_fail(err, err_size, FRT_ERROR_IO, name, ": cannot measure the file: %s", strerror(errno));
    rd->size = (uint64_t)size;
    rd->buf = malloc(RD_BUF_SIZE);
    if (!rd->buf)
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, name, ": out of memory");
    return FRT_SUCCESS;
}

void frt_rd_close(frt_rd *rd)
{
    free(rd->buf);
    rd->buf = NULL;
}

static bool rd_fill(frt_rd *rd)
{
    if (rd->read_errno)
        return false;
    size_t n = fread(rd->buf, 1, RD_BUF_SIZE, rd->fp);
    if (n == 0) {
        if (ferror(rd->fp))
            rd->read_errno = errno ? errno : EIO;
        return false;
    }
    rd->pos = 0;
    rd->len = n;
    return true;
}

int frt_rd_getc(frt_rd *rd)
{
    if (rd->pos == rd->len && !rd_fill(rd))
        return -1;
    rd->offset++;
    return rd->buf[rd->pos++];
}

bool frt_rd_read(frt_rd *rd, void *dst, size_t n)
{
    uint8_t *d = dst;
    while (n) {
        if (rd->pos == rd->len) {
            if (n >= RD_BUF_SIZE && !rd->read_errno) { /* large reads go straight to the caller's memory */
                size_t k = fread(d, 1, n, rd->fp);
                rd->offset += k;
                if (k < n && ferror(rd->fp))
                    rd->read_errno = errno ? errno : EIO;
                return k == n;
            }
            if (!rd_fill(rd))
                return false;
        }
        size_t k = rd->len - rd->pos < n ? rd->len - rd->pos : n;
        memcpy(d, rd->buf + rd->pos, k);
        rd->pos += k;
        rd->offset += k;
        d += k;
        n -= k;
    }
    return true;
}

long frt_rd_line(frt_rd *rd, char *line, size_t cap)
{
    size_t n = 0;
    bool overflow = false;
    int c = frt_rd_getc(rd);
    if (c < 0)
        return -1;
    for (; c >= 0 && c != '\n'; c = frt_rd_getc(rd)) {
        if (n + 1 < cap)
            line[n++] = (char)c;
        else
            overflow = true;
    }
    rd->line_at_end = c < 0;
    if (n && line[n - 1] == '\r')
        --n;
    line[n] = '\0';
    return overflow ? -2 : (long)n;
}

frt_result frt_rd_truncated(frt_rd *rd, const char *what)
{
    if (rd->read_errno)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_IO, rd->name, ": cannot read: %s", strerror(rd->read_errno));
    return frt_fail(rd->err, rd->err_size, FRT_ERROR_IO, rd->name, " is truncated (%s)", what);
}

frt_result frt_rd_magic(frt_rd *rd, const void *magic, size_t n, const char *what)
{
    const uint8_t *m = magic;
    for (size_t i = 0; i < n; ++i) {
        int c = frt_rd_getc(rd);
        if (c < 0)
            return frt_rd_truncated(rd, "in its signature");
        if (c != m[i])
            return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, " is not %s", what);
    }
    return FRT_SUCCESS;
}

frt_result frt_rd_check_grid(frt_rd *rd, const frt_field_info *info, const float *out, size_t out_count)
{
    uint64_t points = (uint64_t)info->width * info->height;
    if (points == 0)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, ": its header says %u x %u",
                        info->width, info->height);
    if (points > FRT_FILE_MAX_POINTS)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_TOO_LARGE, rd->name,
                        ": %u x %u heights are more than fracterra reads (2^32)", info->width, info->height);
    if (out && out_count < points)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_BUFFER_TOO_SMALL, rd->name,
                        ": holds %u x %u heights but the output has room for %zu", info->width, info->height,
                        out_count);
    return FRT_SUCCESS;
}

/* ---- buffered writing ---- */

void frt_wr_bytes(frt_wr *w, const void *p, size_t n)
{
    if (!w->errnum && n && fwrite(p, 1, n, w->fp) != n)
        w->errnum = errno ? errno : EIO;
}

void frt_wr_printf(frt_wr *w, const char *fmt, ...)
{
    if (w->errnum)
        return;
    va_list ap;
    va_start(ap, fmt);
    if (vfprintf(w->fp, fmt, ap) < 0)
        w->errnum = errno ? errno : EIO;
    va_end(ap);
}

frt_result frt_wr_finish(frt_wr *w, const char *name, char *err, size_t err_size)
{
    if (!w->errnum && fflush(w->fp) != 0)
        w->errnum = errno ? errno : EIO;
    if (!w->errnum && ferror(w->fp))
        w->errnum = EIO;
    if (w->errnum)
        return frt_fail(err, err_size, FRT_ERROR_IO, name, ": cannot write: %s", strerror(w->errnum));
    return FRT_SUCCESS;
}

void frt_put_le32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

uint32_t frt_get_le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* ---- mesh geometry (writing) ---- */

uint32_t frt_mesh_side(uint32_t n, uint32_t stride)
{
    if (n <= 1)
        return n;
    uint32_t m = n - 1;
    return m / stride + (m % stride != 0) + 1;
}

/* Grid row or column of thinned index i: i * K, and the last one for the last index. */
static uint32_t mesh_source(uint32_t i, uint32_t n, uint32_t stride)
{
    uint64_t s = (uint64_t)i * stride;
    return s < n - 1 ? (uint32_t)s : n - 1;
}

void frt_mesh_vertex(const frt_field_out *f, uint32_t i, uint32_t j, float pos[3], float normal[3])
{
    uint32_t W = frt_mesh_side(f->width, f->mesh_stride), H = frt_mesh_side(f->height, f->mesh_stride);
    uint32_t col = mesh_source(i, f->width, f->mesh_stride), row = mesh_source(j, f->height, f->mesh_stride);
#define X(c) ((double)(c)*f->spacing_x)
#define Y(r) ((double)(f->height - 1u - (r)) * f->spacing_y)
#define Z(r, c) ((double)f->h[(size_t)(r)*f->width + (c)] * f->z_scale)
    pos[0] = (float)X(col);
    pos[1] = (float)Y(row);
    pos[2] = (float)Z(row, col);
    /* Central differences on the thinned grid, one-sided at its edges: exact for a plane, whatever the spacing of
     * the last row or column. */
    double dzdx = 0.0, dzdy = 0.0;
    if (W > 1) {
        uint32_t cl = mesh_source(i > 0 ? i - 1 : i, f->width, f->mesh_stride);
        uint32_t cr = mesh_source(i + 1 < W ? i + 1 : i, f->width, f->mesh_stride);
        dzdx = (Z(row, cr) - Z(row, cl)) / (X(cr) - X(cl));
    }
    if (H > 1) {
        uint32_t rn = mesh_source(j > 0 ? j - 1 : j, f->height, f->mesh_stride); /* north: larger y */
        uint32_t rs = mesh_source(j + 1 < H ? j + 1 : j, f->height, f->mesh_stride);
        dzdy = (Z(rn, col) - Z(rs, col)) / (Y(rn) - Y(rs));
    }
#undef X
#undef Y
#undef Z
    double len = sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
    normal[0] = (float)(-dzdx / len);
    normal[1] = (float)(-dzdy / len);
    normal[2] = (float)(1.0 / len);
}

int frt_mesh_comments(const frt_field_out *f, char lines[2][256])
{
    uint32_t W = frt_mesh_side(f->width, f->mesh_stride), H = frt_mesh_side(f->height, f->mesh_stride);
    char sx[32], sy[32], zs[32];
    snprintf(lines[0], 256, "fracterra %s heightfield mesh: %u x %u grid, stride %u: %u x %u vertices, %llu triangles",
             FRT_VERSION_STRING, f->width, f->height, f->mesh_stride, W, H, (unsigned long long)2 * (W - 1) * (H - 1));
    snprintf(lines[1], 256, "x = column * %s, y = (%u - 1 - row) * %s (north up), z = height * %s",
             frt_double_text(sx, f->spacing_x), f->height, frt_double_text(sy, f->spacing_y),
             frt_double_text(zs, f->z_scale));
    return 2;
}

/* ---- mesh grid recognition (reading) ---- */

static frt_result not_grid(frt_rd *rd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static frt_result not_grid(frt_rd *rd, const char *fmt, ...)
{
    char why[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                    ": not a regular grid mesh (%s); fracterra reads back the vertex grids it writes", why);
}

frt_result frt_grid_add(frt_grid_rd *g, frt_rd *rd, double x, double y, double z)
{
    uint64_t i = g->n;
    if (!isfinite(x) || !isfinite(y))
        return not_grid(rd, "vertex %llu has a coordinate that is not a finite number", (unsigned long long)i + 1);
    if (i >= FRT_FILE_MAX_POINTS)
        return not_grid(rd, "more than %llu vertices", (unsigned long long)FRT_FILE_MAX_POINTS);
    if (g->out) {
        if (i < g->out_count)
            g->out[i] = (float)z;
        else
            g->buffer_small = true;
    }
    if (i == 0) {
        g->xs_cap = 64;
        g->xs = malloc(g->xs_cap * sizeof *g->xs);
        if (!g->xs)
            return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
        g->xs[0] = x;
        g->y_row = g->y0 = y;
        g->n = 1;
        return FRT_SUCCESS;
    }
    if (g->width == 0) {
        if (i == 1) {
            /* Positions are compared within 1e-4 of the first step, so that meshes re-exported by other tools
             * (with rounded coordinates) still read. */
            double step = fmax(fabs(x - g->xs[0]), fabs(y - g->y0));
            if (!(step > 0.0) || !isfinite(step))
                return not_grid(rd, "vertices 1 and 2 coincide");
            g->tol = 1e-4 * step;
        }
        if (fabs(y - g->y0) <= g->tol) { /* still the first row */
            if (!(x > g->xs[i - 1] + g->tol))
                return not_grid(rd, "x does not increase along the first row at vertex %llu",
                                (unsigned long long)i + 1);
            if (i == g->xs_cap) {
                double *p = realloc(g->xs, 2 * g->xs_cap * sizeof *g->xs);
                if (!p)
                    return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
                g->xs = p;
                g->xs_cap *= 2;
            }
            g->xs[i] = x;
            g->n++;
            return FRT_SUCCESS;
        }
        if (i > UINT32_MAX)
            return not_grid(rd, "the first row has more than %u vertices", UINT32_MAX);
        g->width = (uint32_t)i;
    }
    uint64_t col = i % g->width, row = i / g->width;
    if (col == 0) {
        if (!(y < g->y_row - g->tol))
            return not_grid(rd, "row %llu is not south of row %llu: y must decrease from row to row",
                            (unsigned long long)row + 1, (unsigned long long)row);
        if (row == 1)
            g->y1 = y;
        g->y_row = y;
    } else if (fabs(y - g->y_row) > g->tol) {
        return not_grid(rd, "vertex %llu is off the y of its row %llu", (unsigned long long)i + 1,
                        (unsigned long long)row + 1);
    }
    if (fabs(x - g->xs[col]) > g->tol)
        return not_grid(rd, "vertex %llu is off the x of its column %llu", (unsigned long long)i + 1,
                        (unsigned long long)col + 1);
    g->n++;
    return FRT_SUCCESS;
}

frt_result frt_grid_finish(frt_grid_rd *g, frt_rd *rd, frt_field_info *info)
{
    frt_result r = FRT_SUCCESS;
    if (g->n == 0) {
        r = frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, ": the mesh has no vertices");
        goto done;
    }
    if (g->width == 0) { /* a single row */
        if (g->n > UINT32_MAX) {
            r = not_grid(rd, "the first row has more than %u vertices", UINT32_MAX);
            goto done;
        }
        g->width = (uint32_t)g->n;
    }
    if (g->n % g->width != 0) {
        r = not_grid(rd, "%llu vertices do not fill rows of %u", (unsigned long long)g->n, g->width);
        goto done;
    }
    info->width = g->width;
    info->height = (uint32_t)(g->n / g->width);
    if (info->width > 1)
        info->spacing_x = g->xs[1] - g->xs[0];
    if (info->height > 1)
        info->spacing_y = g->y0 - g->y1;
    if (g->out) {
        size_t n = g->n < g->out_count ? (size_t)g->n : g->out_count;
        if (info->z_scale != 1.0)
            for (size_t k = 0; k < n; ++k)
                g->out[k] = (float)(g->out[k] / info->z_scale);
        if (g->buffer_small)
            r = frt_fail(rd->err, rd->err_size, FRT_ERROR_BUFFER_TOO_SMALL, rd->name,
                         ": holds %u x %u heights but the output has room for %zu", info->width, info->height,
                         g->out_count);
    }
done:
    frt_grid_free(g);
    return r;
}

void frt_grid_free(frt_grid_rd *g)
{
    free(g->xs);
    g->xs = NULL;
    g->xs_cap = 0;
}
