/* files.c — the public heightfield file API: checks, the format by extension, all-or-nothing writes (with the
 * .f32 sidecar), and the dispatch to the format files. */
#include "internal.h"

#include <errno.h>
#include <float.h>
#include <locale.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#define EXTENSIONS ".png, .pgm, .f32, .npy, .obj, .ply or .tif"

#define SIDECAR_MAX_BYTES (1u << 20)

/* Numbers in files are C-locale text whatever the application's locale: under a German LC_NUMERIC, printf would
 * write "0,8" and strtod would stop at the '.'. uselocale() switches this thread only. */
typedef struct c_locale {
    locale_t c, old;
} c_locale;

static void c_locale_begin(c_locale *l)
{
    l->c = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    l->old = l->c ? uselocale(l->c) : (locale_t)0;
}

static void c_locale_end(c_locale *l)
{
    if (l->c) {
        uselocale(l->old);
        freelocale(l->c);
    }
}

/* ---- writing ---- */

static void field_minmax(const float *h, size_t count, float *min, float *max)
{
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < count; ++i) {
        if (!isfinite(h[i]))
            continue;
        lo = h[i] < lo ? h[i] : lo;
        hi = h[i] > hi ? h[i] : hi;
    }
    *min = lo <= hi ? lo : 0.0f;
    *max = lo <= hi ? hi : 0.0f;
}

frt_result frt_field_out_init(frt_field_out *f, const char *name, const float *h, uint32_t width, uint32_t height,
                              const frt_write_desc *desc, char *err, size_t err_size)
{
    memset(f, 0, sizeof *f);
    f->name = name ? name : "";
    frt_write_desc d;
    if (desc)
        d = *desc;
    else
        memset(&d, 0, sizeof d);
    if (!h || width == 0 || height == 0)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                        ": needs a field of at least 1 x 1 heights, got %u x %u%s", width, height,
                        h ? "" : " and no heights");
    if ((uint64_t)width * height > FRT_FILE_MAX_POINTS)
        return frt_fail(err, err_size, FRT_ERROR_TOO_LARGE, f->name, ": %u x %u heights are more than 2^32", width,
                        height);
    f->format = d.format != FRT_FILE_DEFAULT ? d.format : frt_file_format_from_path(name);
    if (d.format != FRT_FILE_DEFAULT && (d.format < FRT_FILE_PNG || d.format > FRT_FILE_TIFF))
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name, ": unknown file format %d", (int)d.format);
    if (f->format == FRT_FILE_DEFAULT)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                        ": unknown extension; fracterra writes " EXTENSIONS);
    f->bits = d.bits ? d.bits : 16;
    if (f->bits != 8 && f->bits != 16)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name, ": bits must be 8 or 16, got %u", d.bits);
    f->mesh_stride = d.mesh_stride ? d.mesh_stride : 1;
    f->spacing_x = d.spacing_x != 0.0 ? d.spacing_x : 1.0;
    f->spacing_y = d.spacing_y != 0.0 ? d.spacing_y : 1.0;
    f->z_scale = d.z_scale != 0.0 ? d.z_scale : 1.0;
    if (!(f->spacing_x > 0.0 && f->spacing_y > 0.0 && isfinite(f->spacing_x) && isfinite(f->spacing_y)))
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                        ": spacing must be positive and finite, got %g, %g", d.spacing_x, d.spacing_y);
    if (!isfinite(f->z_scale))
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name, ": z_scale must be finite");
    if (d.terrain) {
        if (frt_terrain_desc_resolved(d.terrain, &f->terrain) != FRT_SUCCESS)
            return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                            ": the terrain parameters to record are out of range");
        f->has_terrain = true;
    }
    f->backend = d.backend;
    f->device = d.device;
    f->history = d.history;
    f->geotransform = d.geotransform;
    f->projection = d.projection;
    f->has_nodata = d.has_nodata;
    f->nodata = d.nodata;
    f->h = h;
    f->width = width;
    f->height = height;
    field_minmax(h, (size_t)width * height, &f->min, &f->max);
    /* PNG/PGM on the caller's scale (frt_write_desc.range_min/max): the writers quantise on, and record, f->min/max,
     * which are floats, so the range must stay an increasing pair in float. */
    if (d.range_min != d.range_max && (f->format == FRT_FILE_PNG || f->format == FRT_FILE_PGM)) {
        if (!(fabs(d.range_min) <= FLT_MAX && fabs(d.range_max) <= FLT_MAX && (float)d.range_min < (float)d.range_max))
            return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                            ": range %g .. %g is not an increasing pair of finite single-precision numbers",
                            d.range_min, d.range_max);
        f->min = (float)d.range_min;
        f->max = (float)d.range_max;
    }
    return FRT_SUCCESS;
}

frt_result frt_write_stream(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    c_locale l;
    c_locale_begin(&l);
    frt_result r;
    switch (f->format) {
    case FRT_FILE_PNG: r = frt_png_write(fp, f, err, err_size); break;
    case FRT_FILE_PGM: r = frt_pgm_write(fp, f, err, err_size); break;
    case FRT_FILE_F32: r = frt_f32_write(fp, f, err, err_size); break;
    case FRT_FILE_NPY: r = frt_npy_write(fp, f, err, err_size); break;
    case FRT_FILE_OBJ: r = frt_obj_write(fp, f, err, err_size); break;
    case FRT_FILE_PLY: r = frt_ply_write(fp, f, err, err_size); break;
    case FRT_FILE_TIFF:
        r = frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, f->name,
                     ": GeoTIFF is written by GDAL to a path (frt_write_heightfield), not to a stream");
        break;
    default: r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name, ": unknown file format");
    }
    c_locale_end(&l);
    return r;
}

static char *sidecar_path(const char *path)
{
    size_t n = strlen(path);
    char *s = malloc(n + 6);
    if (s)
        snprintf(s, n + 6, "%s.json", path);
    return s;
}

frt_result frt_write_heightfield(const char *path, const float *h, uint32_t width, uint32_t height,
                                 const frt_write_desc *desc, char *err, size_t err_size)
{
    if (err && err_size)
        err[0] = '\0';
    if (!path || !*path)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, "", ": no file name");
    frt_field_out f;
    frt_result r = frt_field_out_init(&f, path, h, width, height, desc, err, err_size);
    if (r != FRT_SUCCESS)
        return r;
    if (f.format == FRT_FILE_TIFF) {
        c_locale l;
        c_locale_begin(&l);
        char *line = frt_meta_json(&f, FRT_JSON_LINE);
        r = line ? frt_tiff_write(&f, line, err, err_size)
                 : frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, path, ": out of memory");
        free(line);
        c_locale_end(&l);
        return r;
    }
    frt_atomic_file data = {0}, side = {0};
    char *side_path = NULL, *json = NULL;
    /* Both temporaries exist before anything is written, so that an unwritable sidecar costs no work. */
    r = frt_atomic_open(&data, path, err, err_size);
    if (r == FRT_SUCCESS && f.format == FRT_FILE_F32) {
        side_path = sidecar_path(path);
        c_locale l;
        c_locale_begin(&l);
        json = frt_meta_json(&f, FRT_JSON_SIDECAR);
        c_locale_end(&l);
        if (!side_path || !json)
            r = frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, path, ": out of memory");
        else
            r = frt_atomic_open(&side, side_path, err, err_size);
    }
    if (r == FRT_SUCCESS)
        r = frt_write_stream(data.fp, &f, err, err_size);
    if (r == FRT_SUCCESS && side.fp) {
        frt_wr w = {side.fp, 0};
        frt_wr_bytes(&w, json, strlen(json));
        r = frt_wr_finish(&w, side_path, err, err_size);
        /* Sync the sidecar before the data is renamed, so that the one step left that can fail after the data file
         * is replaced is the sidecar's rename in the same directory. */
        if (r == FRT_SUCCESS && fsync(fileno(side.fp)) != 0)
            r = frt_fail(err, err_size, FRT_ERROR_IO, side_path, ": cannot write: %s", strerror(errno));
    }
    if (r == FRT_SUCCESS)
        r = frt_atomic_commit(&data, err, err_size);
    if (r == FRT_SUCCESS && side.fp)
        r = frt_atomic_commit(&side, err, err_size);
    if (data.path)
        frt_atomic_abort(&data);
    if (side.path)
        frt_atomic_abort(&side);
    free(side_path);
    free(json);
    return r;
}

frt_result frt_write_picture(const char *path, const uint8_t *pixels, uint32_t width, uint32_t height,
                             uint32_t channels, char *err, size_t err_size)
{
    if (err && err_size)
        err[0] = '\0';
    const char *name = path ? path : "";
    if (!path || !*path || !pixels || width == 0 || height == 0 || (channels != 1 && channels != 3))
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name,
                        ": needs pixels of at least 1 x 1 with 1 (grey) or 3 (RGB) channels, got %u x %u x %u", width,
                        height, channels);
    if (width > 0x7fffffffu || height > 0x7fffffffu || (uint64_t)width * height > FRT_FILE_MAX_POINTS)
        return frt_fail(err, err_size, FRT_ERROR_TOO_LARGE, name, ": %u x %u pixels are too many for PNG", width,
                        height);
    frt_atomic_file af;
    frt_result r = frt_atomic_open(&af, path, err, err_size);
    if (r != FRT_SUCCESS)
        return r;
    r = frt_png_write_picture(af.fp, path, pixels, width, height, channels, err, err_size);
    if (r == FRT_SUCCESS)
        return frt_atomic_commit(&af, err, err_size);
    frt_atomic_abort(&af);
    return r;
}

/* ---- reading ---- */

frt_result frt_read_stream(FILE *fp, frt_file_format format, const char *sidecar_json, const char *name,
                           frt_field_info *info, float *out, size_t out_count, char *err, size_t err_size)
{
    frt_field_info local;
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    info->format = format;
    info->spacing_x = info->spacing_y = info->z_scale = 1.0;
    if (err && err_size)
        err[0] = '\0';
    name = name ? name : "";
    c_locale l;
    c_locale_begin(&l);
    frt_rd rd;
    frt_result r = frt_rd_open(&rd, fp, name, err, err_size);
    if (r == FRT_SUCCESS) {
        switch (format) {
        case FRT_FILE_PNG: r = frt_png_read(&rd, info, out, out_count); break;
        case FRT_FILE_PGM: r = frt_pgm_read(&rd, info, out, out_count); break;
        case FRT_FILE_F32: r = frt_f32_read(&rd, sidecar_json, info, out, out_count); break;
        case FRT_FILE_NPY: r = frt_npy_read(&rd, info, out, out_count); break;
        case FRT_FILE_OBJ: r = frt_obj_read(&rd, info, out, out_count); break;
        case FRT_FILE_PLY: r = frt_ply_read(&rd, info, out, out_count); break;
        case FRT_FILE_TIFF:
            r = frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, name,
                         ": GeoTIFF is read by GDAL from a path (frt_read_heightfield), not from a stream");
            break;
        default:
            r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, name,
                         ": unknown extension; fracterra reads " EXTENSIONS);
        }
    }
    frt_rd_close(&rd);
    c_locale_end(&l);
    if (r == FRT_SUCCESS && out)
        field_minmax(out, (size_t)info->width * info->height, &info->min, &info->max);
    return r;
}

/* Opens `path` for reading and, for .f32, reads its sidecar into *sidecar (malloc'd, NUL-terminated). */
static frt_result open_input(const char *path, FILE **fp, frt_file_format *format, char **sidecar, char *err,
                             size_t err_size)
{
    *fp = NULL;
    *sidecar = NULL;
    if (err && err_size)
        err[0] = '\0';
    if (!path || !*path)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, "", ": no file name");
    *format = frt_file_format_from_path(path);
    if (*format == FRT_FILE_DEFAULT)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, path,
                        ": unknown extension; fracterra reads " EXTENSIONS);
    /* stat before opening: opening a FIFO for reading would wait for a writer. */
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return frt_fail(err, err_size, FRT_ERROR_IO, path,
                        S_ISDIR(st.st_mode) ? " is a directory" : " is not a regular file");
    *fp = fopen(path, "rb");
    if (!*fp)
        return frt_fail(err, err_size, FRT_ERROR_IO, path, ": cannot open: %s", strerror(errno));
    if (*format != FRT_FILE_F32)
        return FRT_SUCCESS;
    char *sp = sidecar_path(path);
    FILE *sf = sp ? fopen(sp, "rb") : NULL;
    frt_result r = FRT_SUCCESS;
    if (!sp) {
        r = frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, path, ": out of memory");
    } else if (!sf) {
        r = frt_fail(err, err_size, FRT_ERROR_IO, path, ": cannot open its sidecar '%s' (it gives the size): %s", sp,
                     strerror(errno));
    } else {
        char *text = malloc(SIDECAR_MAX_BYTES + 1);
        size_t n = text ? fread(text, 1, SIDECAR_MAX_BYTES + 1, sf) : 0;
        if (!text)
            r = frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, path, ": out of memory");
        else if (ferror(sf))
            r = frt_fail(err, err_size, FRT_ERROR_IO, path, ": cannot read its sidecar '%s': %s", sp, strerror(errno));
        else if (n > SIDECAR_MAX_BYTES)
            r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, path, ": its sidecar '%s' is larger than 1 MiB",
                         sp);
        if (r == FRT_SUCCESS) {
            text[n] = '\0';
            *sidecar = text;
        } else {
            free(text);
        }
    }
    if (sf)
        fclose(sf);
    free(sp);
    if (r != FRT_SUCCESS) {
        fclose(*fp);
        *fp = NULL;
    }
    return r;
}

/* GeoTIFF: GDAL reads by name (format_tiff.c); info is set up as frt_read_stream does. */
static frt_result read_tiff(const char *path, float *out, size_t out_count, frt_field_info *info, char *err,
                            size_t err_size)
{
    frt_field_info local;
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    info->format = FRT_FILE_TIFF;
    info->spacing_x = info->spacing_y = info->z_scale = 1.0;
    c_locale l;
    c_locale_begin(&l);
    frt_result r = frt_tiff_read(path, info, out, out_count, err, err_size);
    c_locale_end(&l);
    if (r == FRT_SUCCESS && out)
        field_minmax(out, (size_t)info->width * info->height, &info->min, &info->max);
    return r;
}

/* Opens `path` (and its sidecar) and runs the stream reader: the header only when `out` is NULL. */
static frt_result read_path(const char *path, float *out, size_t out_count, frt_field_info *info, char *err,
                            size_t err_size)
{
    FILE *fp;
    frt_file_format format = FRT_FILE_DEFAULT;
    char *sidecar;
    frt_result r = open_input(path, &fp, &format, &sidecar, err, err_size);
    if (r == FRT_SUCCESS && format == FRT_FILE_TIFF) {
        /* open_input has checked that it is a readable regular file, with the same messages as the others; GDAL
         * opens it again by name. */
        fclose(fp);
        fp = NULL;
        r = read_tiff(path, out, out_count, info, err, err_size);
    } else if (r == FRT_SUCCESS) {
        r = frt_read_stream(fp, format, sidecar, path, info, out, out_count, err, err_size);
    } else if (info) {
        memset(info, 0, sizeof *info);
    }
    if (fp)
        fclose(fp);
    free(sidecar);
    return r;
}

frt_result frt_read_heightfield_info(const char *path, frt_field_info *info, char *err, size_t err_size)
{
    return read_path(path, NULL, 0, info, err, err_size);
}

frt_result frt_read_heightfield(const char *path, float *out, size_t out_count, frt_field_info *info, char *err,
                                size_t err_size)
{
    if (!out) {
        if (info)
            memset(info, 0, sizeof *info);
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, path ? path : "", ": no output buffer");
    }
    return read_path(path, out, out_count, info, err, err_size);
}
