/* format_tiff.c — GeoTIFF through GDAL's C API: float32 out (DEFLATE, predictor 3, tiled when large) with the
 * georeferencing, nodata and fracterra's parameters; in: band 1 of a single-band TIFF of any real sample type. */
#include "internal.h"

#if defined(FRT_HAVE_GDAL)

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* Metadata item (default domain) holding the same JSON as the .f32 sidecar, on one line. GTiff stores it in its
 * GDAL_METADATA tag, which gdalinfo shows and gdal_translate copies. */
#define META_KEY "FRACTERRA"
/* Tiles pay off once both sides exceed one tile; a smaller raster as a tile would be mostly padding. */
#define TILE_SIDE 256
/* Read buffer for sample types other than float32 (converted through double): at most this many bytes a chunk. */
#define READ_CHUNK_BYTES (8u << 20)

/* ---- GDAL's errors: collected per call instead of printed ---- */

/* GDAL reports through a per-thread handler stack; ours keeps the first failure's text for our one-line message
 * and drops warnings (GDAL's default handler would print both to stderr, which a library must not do). */
typedef struct gdal_errors {
    int failures;
    char first[512];
} gdal_errors;

static void CPL_STDCALL collect_error(CPLErr cls, CPLErrorNum num, const char *msg)
{
    (void)num;
    gdal_errors *e = CPLGetErrorHandlerUserData();
    if (!e || cls < CE_Failure)
        return;
    if (e->failures++ == 0)
        snprintf(e->first, sizeof e->first, "%s", msg && *msg ? msg : "unknown GDAL error");
}

static void errors_begin(gdal_errors *e)
{
    memset(e, 0, sizeof *e);
    CPLPushErrorHandlerEx(collect_error, e);
}

static void errors_end(void)
{
    CPLPopErrorHandler();
}

static pthread_once_t registered = PTHREAD_ONCE_INIT;

static void register_drivers(void)
{
    GDALAllRegister();
}

/* ---- writing ---- */

/* The geotransform to write: the caller's (finite, invertible), or north up with pixel centres where the mesh
 * writers put their vertices (frt_mesh_vertex: x = col * spacing_x, y = (height - 1 - row) * spacing_y). A region
 * (docs/ALGORITHM.md §3.2) is placed where it lies in its whole virtual grid, so that the tiles of one grid line up
 * in a GIS (gdalbuildvrt) without further work. */
static frt_result resolve_geotransform(const frt_field_out *f, double gt[6], char *err, size_t err_size)
{
    if (!f->geotransform) {
        double col0 = 0.0, rows_below = (double)f->height; /* rows from the window's top to the grid's bottom */
        const frt_region *reg = &f->terrain.region;
        if (f->has_terrain && frt_region_is_set(reg) && reg->width == f->width && reg->height == f->height) {
            col0 = reg->x;
            rows_below = (double)frt_terrain_side(&f->terrain) - reg->y;
        }
        const double g[6] = {(col0 - 0.5) * f->spacing_x,       f->spacing_x, 0.0,
                             (rows_below - 0.5) * f->spacing_y, 0.0,          -f->spacing_y};
        memcpy(gt, g, sizeof g);
        return FRT_SUCCESS;
    }
    memcpy(gt, f->geotransform, 6 * sizeof *gt);
    bool finite = true;
    for (int i = 0; i < 6; ++i)
        finite = finite && isfinite(gt[i]);
    double det = gt[1] * gt[5] - gt[2] * gt[4];
    if (!finite || det == 0.0 || !isfinite(det))
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                        ": geotransform {%g, %g, %g, %g, %g, %g} must be finite with a non-zero pixel area", gt[0],
                        gt[1], gt[2], gt[3], gt[4], gt[5]);
    return FRT_SUCCESS;
}

/* The nodata value and whether NaN heights need replacing by it. Without one, NaN itself marks nodata when the
 * field has NaNs: it cannot collide with a height, and float32 keeps it exactly. */
static frt_result resolve_nodata(const frt_field_out *f, bool *has, double *nodata, bool *replace, char *err,
                                 size_t err_size)
{
    const size_t n = (size_t)f->width * f->height;
    bool any_nan = false;
    for (size_t i = 0; i < n && !any_nan; ++i)
        any_nan = isnan(f->h[i]);
    *replace = false;
    if (!f->has_nodata) {
        *has = any_nan;
        *nodata = NAN;
        return FRT_SUCCESS;
    }
    *has = true;
    *nodata = f->nodata;
    if (isnan(f->nodata))
        return FRT_SUCCESS;
    if ((double)(float)f->nodata != f->nodata)
        return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                        ": nodata %.17g is not a float32 value, which the samples are", f->nodata);
    const float v = (float)f->nodata;
    for (size_t i = 0; i < n; ++i)
        if (f->h[i] == v)
            return frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                            ": the height at column %zu, row %zu equals the nodata value %g; choose another",
                            i % f->width, i / f->width, f->nodata);
    *replace = any_nan;
    return FRT_SUCCESS;
}

/* Writes the samples, replacing NaN by `nodata` when asked: row by row through a copy then, else straight from the
 * caller's field (GDAL does not write to a buffer it is given for GF_Write). */
static CPLErr write_samples(GDALRasterBandH band, const frt_field_out *f, bool replace, float nodata)
{
    const int w = (int)f->width, hgt = (int)f->height;
    if (!replace)
        return GDALRasterIOEx(band, GF_Write, 0, 0, w, hgt, (void *)f->h, w, hgt, GDT_Float32, sizeof(float),
                              (GSpacing)w * (GSpacing)sizeof(float), NULL);
    float *row = malloc((size_t)w * sizeof *row);
    if (!row) {
        CPLError(CE_Failure, CPLE_OutOfMemory, "out of memory");
        return CE_Failure;
    }
    CPLErr e = CE_None;
    for (int y = 0; y < hgt && e == CE_None; ++y) {
        const float *src = f->h + (size_t)y * f->width;
        for (int x = 0; x < w; ++x)
            row[x] = isnan(src[x]) ? nodata : src[x];
        e = GDALRasterIO(band, GF_Write, 0, y, w, 1, row, w, 1, GDT_Float32, 0, 0);
    }
    free(row);
    return e;
}

frt_result frt_tiff_write(const frt_field_out *f, const char *json, char *err, size_t err_size)
{
    if (f->width > INT_MAX || f->height > INT_MAX)
        return frt_fail(err, err_size, FRT_ERROR_TOO_LARGE, f->name, ": GDAL takes at most %d samples a side", INT_MAX);
    double gt[6], nodata;
    bool has_nodata, replace;
    frt_result r = resolve_geotransform(f, gt, err, err_size);
    if (r == FRT_SUCCESS)
        r = resolve_nodata(f, &has_nodata, &nodata, &replace, err, err_size);
    if (r != FRT_SUCCESS)
        return r;
    pthread_once(&registered, register_drivers);

    gdal_errors ge;
    errors_begin(&ge);
    OGRSpatialReferenceH srs = NULL;
    if (f->projection && *f->projection) {
        srs = OSRNewSpatialReference(NULL);
        if (!srs || OSRSetFromUserInput(srs, f->projection) != OGRERR_NONE) {
            r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, f->name,
                         ": projection '%.200s' is not a coordinate system GDAL knows%s%s", f->projection,
                         ge.failures ? ": " : "", ge.failures ? ge.first : "");
            goto done;
        }
        /* GeoTIFF's geotransform is always x = easting/longitude, y = northing/latitude. */
        OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
    }
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    if (!driver) {
        r = frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, f->name, ": this GDAL has no GTiff driver");
        goto done;
    }
    /* GDAL writes to a path, so the temporary file is made (and named) by frt_atomic_open and then handed to GDAL,
     * which re-creates it in place; the rename happens only after GDAL closed it without a failure. */
    frt_atomic_file af;
    r = frt_atomic_open(&af, f->name, err, err_size);
    if (r != FRT_SUCCESS)
        goto done;
    fclose(af.fp);
    af.fp = NULL;

    const bool tiled = f->width > TILE_SIDE && f->height > TILE_SIDE;
    char **opts = NULL;
    opts = CSLSetNameValue(opts, "COMPRESS", "DEFLATE");
    opts = CSLSetNameValue(opts, "PREDICTOR", "3"); /* floating-point predictor: smooth terrain compresses well */
    opts = CSLSetNameValue(opts, "BIGTIFF", "IF_SAFER");
    if (tiled) {
        opts = CSLSetNameValue(opts, "TILED", "YES");
        opts = CSLSetNameValue(opts, "BLOCKXSIZE", "256");
        opts = CSLSetNameValue(opts, "BLOCKYSIZE", "256");
    }
    GDALDatasetH ds = GDALCreate(driver, af.tmp_path, (int)f->width, (int)f->height, 1, GDT_Float32, opts);
    CSLDestroy(opts);
    if (ds) {
        GDALRasterBandH band = GDALGetRasterBand(ds, 1);
        GDALSetGeoTransform(ds, gt);
        if (srs)
            GDALSetSpatialRef(ds, srs);
        if (has_nodata)
            GDALSetRasterNoDataValue(band, nodata);
        if (json)
            GDALSetMetadataItem(ds, META_KEY, json, NULL);
        GDALSetMetadataItem(ds, "TIFFTAG_SOFTWARE", "fracterra " FRT_VERSION_STRING, NULL);
        write_samples(band, f, replace, (float)nodata);
        /* Failures while writing, and while flushing and closing, all reach the handler. */
        GDALClose(ds);
    }
    if (!ds || ge.failures) {
        r = frt_fail(err, err_size, FRT_ERROR_IO, f->name, ": cannot write GeoTIFF: %s (nothing was replaced)",
                     ge.failures ? ge.first : "GDAL gave no reason");
        frt_atomic_abort(&af);
        goto done;
    }
    /* Re-opened only so that frt_atomic_commit can sync it before the rename. */
    af.fp = fopen(af.tmp_path, "rb");
    if (!af.fp) {
        r = frt_fail(err, err_size, FRT_ERROR_IO, f->name,
                     ": cannot reopen the written GeoTIFF (nothing was replaced)");
        frt_atomic_abort(&af);
        goto done;
    }
    r = frt_atomic_commit(&af, err, err_size);
done:
    errors_end();
    if (srs)
        OSRDestroySpatialReference(srs);
    return r;
}

/* ---- reading ---- */

/* Heights from one chunk of stored samples: NaN and the nodata value become NaN, the rest are scaled. */
typedef struct sample_map {
    bool has_nodata;
    double nodata;
    bool scaled;
    double scale, offset;
} sample_map;

static inline float map_sample(const sample_map *m, double v)
{
    if (isnan(v) || (m->has_nodata && v == m->nodata))
        return NAN;
    return m->scaled ? (float)(v * m->scale + m->offset) : (float)v;
}

static frt_result read_samples(GDALRasterBandH band, const frt_field_info *info, const sample_map *m, float *out)
{
    const int w = (int)info->width, hgt = (int)info->height;
    const bool as_float = GDALGetRasterDataType(band) == GDT_Float32;
    int bx = 0, by = 0;
    GDALGetBlockSize(band, &bx, &by);
    /* Whole rows of blocks where they fit in READ_CHUNK_BYTES, so each block is decoded once. */
    size_t rows = READ_CHUNK_BYTES / ((size_t)w * sizeof(double));
    rows = rows < 1 ? 1 : rows;
    if (by > 0 && rows >= (size_t)by)
        rows -= rows % (size_t)by;
    if (rows > (size_t)hgt)
        rows = (size_t)hgt;
    double *buf = as_float ? NULL : malloc(rows * (size_t)w * sizeof *buf);
    if (!as_float && !buf)
        return FRT_ERROR_OUT_OF_MEMORY;
    CPLErr e = CE_None;
    for (int y = 0; y < hgt && e == CE_None; y += (int)rows) {
        const int n = hgt - y < (int)rows ? hgt - y : (int)rows;
        float *dst = out + (size_t)y * info->width;
        const size_t count = (size_t)n * info->width;
        if (as_float) {
            /* float32 samples straight into the output; double holds every float, so the map is exact. */
            e = GDALRasterIOEx(band, GF_Read, 0, y, w, n, dst, w, n, GDT_Float32, sizeof(float),
                               (GSpacing)w * (GSpacing)sizeof(float), NULL);
            for (size_t i = 0; i < count && e == CE_None; ++i)
                dst[i] = map_sample(m, dst[i]);
        } else {
            e = GDALRasterIOEx(band, GF_Read, 0, y, w, n, buf, w, n, GDT_Float64, sizeof(double),
                               (GSpacing)w * (GSpacing)sizeof(double), NULL);
            for (size_t i = 0; i < count && e == CE_None; ++i)
                dst[i] = map_sample(m, buf[i]);
        }
    }
    free(buf);
    return e == CE_None ? FRT_SUCCESS : FRT_ERROR_IO;
}

/* The band's nodata value in stored units (0 when it has none); 64-bit integer bands keep theirs apart (GDAL 3.5+),
 * and the cast to double is exact up to 2^53. */
static bool band_nodata(GDALRasterBandH band, double *v)
{
    int ok = 0;
    const GDALDataType type = GDALGetRasterDataType(band);
#if GDAL_VERSION_NUM >= GDAL_COMPUTE_VERSION(3, 5, 0)
    if (type == GDT_Int64)
        *v = (double)GDALGetRasterNoDataValueAsInt64(band, &ok);
    else if (type == GDT_UInt64)
        *v = (double)GDALGetRasterNoDataValueAsUInt64(band, &ok);
    else
#endif
        *v = GDALGetRasterNoDataValue(band, &ok);
    (void)type;
    if (!ok)
        *v = 0.0;
    return ok != 0;
}

/* fracterra's own metadata, when it describes this raster (a crop by another tool keeps the item but not the
 * size, and then the parameters are not this field's). A malformed item is ignored, as in the PNG reader. Returns
 * whether it was taken. */
static bool read_meta(GDALDatasetH ds, frt_field_info *info)
{
    const char *json = GDALGetMetadataItem(ds, META_KEY, NULL);
    frt_field_info *m = json ? calloc(1, sizeof *m) : NULL; /* 8 KiB: not on the stack */
    if (!m)
        return false;
    m->spacing_x = m->spacing_y = m->z_scale = 1.0;
    frt_meta_extra ex;
    const bool ok = frt_meta_parse(json, strlen(json), m, &ex, "", "", NULL, 0) == FRT_SUCCESS &&
                    (!ex.has_size || (ex.width == info->width && ex.height == info->height));
    if (ok) {
        info->has_terrain = m->has_terrain;
        info->terrain = m->terrain;
        info->spacing_x = m->spacing_x;
        info->spacing_y = m->spacing_y;
        info->z_scale = m->z_scale;
        memcpy(info->backend, m->backend, sizeof info->backend);
        memcpy(info->device, m->device, sizeof info->device);
    }
    free(m);
    return ok;
}

frt_result frt_tiff_read(const char *path, frt_field_info *info, float *out, size_t out_count, char *err,
                         size_t err_size)
{
    pthread_once(&registered, register_drivers);
    gdal_errors ge;
    errors_begin(&ge);
    /* The content picks GDAL's driver, not the name: a ".tif" holding a VRT could make GDAL read other files or
     * URLs. Only the GTiff driver opens what fracterra reads as TIFF. */
    static const char *const drivers[] = {"GTiff", NULL};
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, drivers, NULL, NULL);
    frt_result r = FRT_SUCCESS;
    if (!ds) {
        r = frt_fail(err, err_size, FRT_ERROR_INVALID_ARGUMENT, path, " is not a TIFF that GDAL reads: %s",
                     ge.failures ? ge.first : "GDAL gave no reason");
        goto done;
    }
    const int bands = GDALGetRasterCount(ds);
    if (bands != 1) {
        /* Several bands are mostly a picture (RGB) or a stack of variables; a height is one of them at most, and
         * guessing band 1 would read a photo's red channel as terrain. */
        r = frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, path,
                     " has %d bands; fracterra reads single-band rasters (take one out with gdal_translate -b N)",
                     bands);
        goto done;
    }
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    const GDALDataType type = GDALGetRasterDataType(band);
    if (GDALDataTypeIsComplex(type)) {
        r = frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, path, " has complex samples (%s), not heights",
                     GDALGetDataTypeName(type));
        goto done;
    }
    info->width = (uint32_t)GDALGetRasterXSize(ds);
    info->height = (uint32_t)GDALGetRasterYSize(ds);
    info->bits = (uint32_t)GDALGetDataTypeSizeBits(type);
    frt_rd rd = {.name = path, .err = err, .err_size = err_size};
    if ((r = frt_rd_check_grid(&rd, info, out, out_count)) != FRT_SUCCESS)
        goto done;

    info->has_geotransform = GDALGetGeoTransform(ds, info->geotransform) == CE_None;
    if (!info->has_geotransform) {
        const double identity[6] = {0, 1, 0, 0, 0, 1};
        memcpy(info->geotransform, identity, sizeof identity);
    }
    const char *wkt = GDALGetProjectionRef(ds);
    const size_t wkt_len = wkt ? strlen(wkt) : 0;
    if (wkt_len >= sizeof info->projection) {
        r = frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, path,
                     ": its coordinate system's WKT has %zu bytes, more than the %zu that fracterra keeps", wkt_len,
                     sizeof info->projection - 1);
        goto done;
    }
    if (wkt_len)
        memcpy(info->projection, wkt, wkt_len + 1);
    info->has_nodata = band_nodata(band, &info->nodata);

    /* Without fracterra's parameters, the spacing is the pixel size of a north-up raster in the CRS's units, which
     * for a projected CRS (or none) are ground units; degrees of a geographic CRS are not, so they leave it 1. */
    OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
    if (!read_meta(ds, info) && info->has_geotransform && info->geotransform[2] == 0.0 &&
        info->geotransform[4] == 0.0 && info->geotransform[1] != 0.0 && info->geotransform[5] != 0.0 &&
        !(srs && OSRIsGeographic(srs))) {
        info->spacing_x = fabs(info->geotransform[1]);
        info->spacing_y = fabs(info->geotransform[5]);
    }
    if (!out)
        goto done;

    int ok_scale = 0, ok_offset = 0;
    sample_map m = {info->has_nodata, info->nodata, false, GDALGetRasterScale(band, &ok_scale),
                    GDALGetRasterOffset(band, &ok_offset)};
    if (!ok_scale)
        m.scale = 1.0;
    if (!ok_offset)
        m.offset = 0.0;
    m.scaled = m.scale != 1.0 || m.offset != 0.0;
    /* Only failures while reading the samples count now: GDAL may have complained earlier about something it then
     * did without (an unreadable .aux.xml, say). */
    ge.failures = 0;
    ge.first[0] = '\0';
    r = read_samples(band, info, &m, out);
    if (r == FRT_ERROR_OUT_OF_MEMORY)
        r = frt_fail(err, err_size, r, path, ": out of memory");
    else if (r != FRT_SUCCESS || ge.failures)
        r = frt_fail(err, err_size, FRT_ERROR_IO, path, ": cannot read its samples: %s",
                     ge.failures ? ge.first : "GDAL gave no reason");
done:
    if (ds)
        GDALClose(ds);
    errors_end();
    return r;
}

#else /* !FRT_HAVE_GDAL */

#define NO_GDAL ": GeoTIFF needs GDAL, and this fracterra was built without GDAL (FRT_WITH_GDAL=OFF)"

frt_result frt_tiff_write(const frt_field_out *f, const char *json, char *err, size_t err_size)
{
    (void)json;
    return frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, f->name, NO_GDAL);
}

frt_result frt_tiff_read(const char *path, frt_field_info *info, float *out, size_t out_count, char *err,
                         size_t err_size)
{
    (void)info;
    (void)out;
    (void)out_count;
    return frt_fail(err, err_size, FRT_ERROR_UNSUPPORTED, path, NO_GDAL);
}

#endif
