/* test_tiff.c — GeoTIFF through the public API (format_tiff.c, files.c): synthetic georeferenced inputs made with
 * GDAL's C API, round trips, georeferencing and nodata, failures that leave nothing behind; without GDAL, the one
 * clean FRT_ERROR_UNSUPPORTED. */
#include "check.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#if defined(FRT_HAVE_GDAL)
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>
#endif

static char dir[] = "/tmp/frt_tiff_XXXXXX";

/* A path in the test directory; four rotating buffers so that a call can hold a few at once. */
static const char *path_in(const char *name)
{
    static char buf[4][256];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

static long file_size(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0 ? (long)st.st_size : -1;
}

static void write_all(const char *p, const void *data, size_t n)
{
    FILE *f = fopen(p, "wb");
    if (!f || fwrite(data, 1, n, f) != n)
        fprintf(stderr, "cannot write %s\n", p);
    if (f)
        fclose(f);
}

static bool file_is(const char *p, const char *content)
{
    char buf[64] = {0};
    FILE *f = fopen(p, "rb");
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    if (f)
        fclose(f);
    return n == strlen(content) && memcmp(buf, content, n) == 0;
}

/* Files in the test directory whose name contains `part` ("" counts all). */
static int files_with(const char *part)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL)
        n += e->d_name[0] != '.' && strstr(e->d_name, part) != NULL;
    if (d)
        closedir(d);
    return n;
}

/* A message is one line that names the file. */
static bool message_ok(const char *err, const char *name)
{
    return err[0] && !strchr(err, '\n') && strstr(err, name);
}

static void remove_dir(void)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char p[512];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        chmod(p, 0755);
        unlink(p);
    }
    if (d)
        closedir(d);
    rmdir(dir);
}

#if !defined(FRT_HAVE_GDAL)

/* Built with FRT_WITH_GDAL=OFF: .tif is a known extension, and both directions fail cleanly with one line. */
int main(void)
{
    if (!mkdtemp(dir))
        return 2;
    const float h[4] = {1, 2, 3, 4};
    char err[512];
    frt_result r = frt_write_heightfield(path_in("a.tif"), h, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && message_ok(err, "a.tif") &&
              strstr(err, "built without GDAL (FRT_WITH_GDAL=OFF)"),
          "write without GDAL: %d %s", (int)r, err);
    CHECK(files_with("") == 0, "nothing written without GDAL");
    write_all(path_in("c.tif"), "precious", 8);
    r = frt_write_heightfield(path_in("c.tif"), h, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && file_is(path_in("c.tif"), "precious") && files_with("") == 1,
          "an existing .tif is kept: %d %s", (int)r, err);
    write_all(path_in("b.tiff"), "II*\0", 4);
    frt_field_info info;
    r = frt_read_heightfield_info(path_in("b.tiff"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && message_ok(err, "b.tiff") &&
              strstr(err, "built without GDAL (FRT_WITH_GDAL=OFF)"),
          "read without GDAL: %d %s", (int)r, err);
    CHECK(file_size(path_in("b.tiff")) == 4, "the input is left alone");
    remove_dir();
    return check_summary("test_tiff (without GDAL)");
}

#else

/* The synthetic input: 33 x 33, non-square pixels (30 m east, 20 m south), UTM 33N, nodata at a few cells. */
#define SIDE 33
#define NODATA_IN (-9999.0)
static const double input_gt[6] = {500000.0, 30.0, 0.0, 4650000.0, 0.0, -20.0};
static bool is_hole(int x, int y)
{
    return (x == 0 && y == 0) || (x == 7 && y == 11) || (x == 32 && y == 32) || (x == 16 && y == 3);
}

/* Heights of the synthetic input, in stored units: a tilted surface with a bump, exact in float32 and in int16. */
static double input_value(GDALDataType type, int x, int y)
{
    if (type == GDT_Int16)
        return 10 * x - 7 * y + (x * y) % 13 - 100;
    return 812.5 + 0.25 * x - 0.5 * y + (double)(float)(0.001 * x * y);
}

/* Writes the synthetic input with `bands` bands (the others are zero) and the given scale/offset (1, 0: none). */
static bool make_input(const char *path, GDALDataType type, int bands, const char *srs_text, double scale,
                       double offset)
{
    GDALDriverH drv = GDALGetDriverByName("GTiff");
    GDALDatasetH ds = drv ? GDALCreate(drv, path, SIDE, SIDE, bands, type, NULL) : NULL;
    if (!ds)
        return false;
    GDALSetGeoTransform(ds, (double *)input_gt);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    if (OSRSetFromUserInput(srs, srs_text) == OGRERR_NONE)
        GDALSetSpatialRef(ds, srs);
    OSRDestroySpatialReference(srs);
    double *v = check_alloc(SIDE * SIDE * sizeof *v);
    for (int y = 0; y < SIDE; ++y)
        for (int x = 0; x < SIDE; ++x)
            v[y * SIDE + x] = is_hole(x, y) ? NODATA_IN : input_value(type, x, y);
    bool ok = true;
    for (int b = 1; b <= bands; ++b) {
        GDALRasterBandH band = GDALGetRasterBand(ds, b);
        GDALSetRasterNoDataValue(band, NODATA_IN);
        if (scale != 1.0 || offset != 0.0) {
            GDALSetRasterScale(band, scale);
            GDALSetRasterOffset(band, offset);
        }
        if (b > 1)
            memset(v, 0, SIDE * SIDE * sizeof *v);
        ok = ok && GDALRasterIO(band, GF_Write, 0, 0, SIDE, SIDE, v, SIDE, SIDE, GDT_Float64, 0, 0) == CE_None;
    }
    GDALClose(ds);
    free(v);
    return ok;
}

/* The EPSG code a WKT names (0 when it names none or is not a CRS). */
static int epsg_of(const char *wkt)
{
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    int code = 0;
    if (wkt && *wkt && OSRSetFromUserInput(srs, wkt) == OGRERR_NONE) {
        OSRAutoIdentifyEPSG(srs);
        const char *c = OSRGetAuthorityCode(srs, NULL);
        code = c ? atoi(c) : 0;
    }
    OSRDestroySpatialReference(srs);
    return code;
}

static bool gt_equal(const double *a, const double *b)
{
    for (int i = 0; i < 6; ++i)
        if (a[i] != b[i])
            return false;
    return true;
}

/* Reads a whole field through the library; NULL (and r set) on failure. */
static float *read_field(const char *p, frt_field_info *info, frt_result *r, char *err, size_t err_size)
{
    *r = frt_read_heightfield_info(p, info, err, err_size);
    if (*r != FRT_SUCCESS)
        return NULL;
    size_t n = (size_t)info->width * info->height;
    float *out = check_alloc(n * sizeof *out + 1);
    *r = frt_read_heightfield(p, out, n, info, err, err_size);
    if (*r != FRT_SUCCESS) {
        free(out);
        return NULL;
    }
    return out;
}

static void test_read_synthetic(GDALDataType type, const char *name)
{
    const char *p = path_in(name);
    CHECK(make_input(p, type, 1, "EPSG:32633", 1.0, 0.0), "made %s", name);
    char err[512];
    frt_field_info info;
    frt_result r;
    float *h = read_field(p, &info, &r, err, sizeof err);
    CHECK(h != NULL, "%s reads: %s", name, err);
    if (!h)
        return;
    CHECK(info.format == FRT_FILE_TIFF && info.width == SIDE && info.height == SIDE, "%s: format %d, %u x %u", name,
          (int)info.format, info.width, info.height);
    CHECK(info.bits == (type == GDT_Int16 ? 16u : 32u), "%s: bits %u", name, info.bits);
    int wrong = 0, holes = 0;
    for (int y = 0; y < SIDE; ++y)
        for (int x = 0; x < SIDE; ++x) {
            float v = h[y * SIDE + x];
            if (is_hole(x, y)) {
                holes += isnan(v);
                wrong += !isnan(v);
            } else {
                wrong += v != (float)input_value(type, x, y);
            }
        }
    CHECK(wrong == 0 && holes == 4, "%s: %d wrong values, %d of 4 nodata cells NaN", name, wrong, holes);
    CHECK(info.has_geotransform && gt_equal(info.geotransform, input_gt), "%s: geotransform {%g %g %g %g %g %g}", name,
          info.geotransform[0], info.geotransform[1], info.geotransform[2], info.geotransform[3], info.geotransform[4],
          info.geotransform[5]);
    CHECK(epsg_of(info.projection) == 32633 && strstr(info.projection, "UTM zone 33N"), "%s: projection '%.80s'", name,
          info.projection);
    CHECK(info.has_nodata && info.nodata == NODATA_IN, "%s: nodata %d %g", name, info.has_nodata, info.nodata);
    /* No fracterra parameters: the spacing is the projected pixel size. */
    CHECK(!info.has_terrain && info.spacing_x == 30.0 && info.spacing_y == 20.0 && info.z_scale == 1.0,
          "%s: terrain %d spacing %g %g", name, info.has_terrain, info.spacing_x, info.spacing_y);
    float lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < SIDE * SIDE; ++i)
        if (!isnan(h[i])) {
            lo = fminf(lo, h[i]);
            hi = fmaxf(hi, h[i]);
        }
    CHECK(info.min == lo && info.max == hi, "%s: min/max %g %g, expected %g %g", name, info.min, info.max, lo, hi);
    /* A buffer one short: refused, and nothing written past it. */
    float *small = check_alloc((SIDE * SIDE) * sizeof *small);
    small[SIDE * SIDE - 1] = 12345.0f;
    r = frt_read_heightfield(p, small, SIDE * SIDE - 1, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_BUFFER_TOO_SMALL && small[SIDE * SIDE - 1] == 12345.0f && message_ok(err, name),
          "%s: short buffer: %d %s", name, (int)r, err);
    free(small);
    free(h);
}

/* Scale and offset of the band give the heights (stored * scale + offset); nodata is compared before scaling. */
static void test_scale_offset(void)
{
    const char *p = path_in("scaled.tif");
    CHECK(make_input(p, GDT_Int16, 1, "EPSG:32633", 0.5, 100.0), "made scaled.tif");
    char err[512];
    frt_field_info info;
    frt_result r;
    float *h = read_field(p, &info, &r, err, sizeof err);
    CHECK(h != NULL, "scaled.tif reads: %s", err);
    if (!h)
        return;
    int wrong = 0;
    for (int y = 0; y < SIDE; ++y)
        for (int x = 0; x < SIDE; ++x) {
            float v = h[y * SIDE + x];
            wrong += is_hole(x, y) ? !isnan(v) : v != (float)(input_value(GDT_Int16, x, y) * 0.5 + 100.0);
        }
    CHECK(wrong == 0, "scaled.tif: %d wrong values", wrong);
    free(h);
}

/* A field from the CPU reference with its parameters. */
static float *make_field(frt_terrain_desc *d, uint32_t *w, uint32_t *hgt)
{
    frt_terrain_extent(d, w, hgt);
    size_t n = frt_heightfield_size(d);
    float *h = check_alloc(n * sizeof *h);
    if (frt_generate_cpu(d, h, n, NULL) != FRT_SUCCESS)
        fprintf(stderr, "generate failed\n");
    return h;
}

/* What GDAL itself sees in a file: band count, type, block, compression, nodata, one raw sample. */
typedef struct gdal_view {
    bool opened;
    int bands;
    GDALDataType type;
    int block_x, block_y;
    char compression[32], predictor[8];
    bool has_nodata;
    double nodata;
    char meta[64];
} gdal_view;

static gdal_view gdal_look(const char *p, int x, int y, float *sample)
{
    gdal_view v;
    memset(&v, 0, sizeof v);
    GDALDatasetH ds = GDALOpenEx(p, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
    if (!ds)
        return v;
    v.opened = true;
    v.bands = GDALGetRasterCount(ds);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    v.type = GDALGetRasterDataType(b);
    GDALGetBlockSize(b, &v.block_x, &v.block_y);
    const char *c = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
    snprintf(v.compression, sizeof v.compression, "%s", c ? c : "");
    c = GDALGetMetadataItem(ds, "PREDICTOR", "IMAGE_STRUCTURE");
    snprintf(v.predictor, sizeof v.predictor, "%s", c ? c : "");
    int ok = 0;
    v.nodata = GDALGetRasterNoDataValue(b, &ok);
    v.has_nodata = ok != 0;
    c = GDALGetMetadataItem(ds, "FRACTERRA", NULL);
    snprintf(v.meta, sizeof v.meta, "%s", c ? c : "");
    if (sample && GDALRasterIO(b, GF_Read, x, y, 1, 1, sample, 1, 1, GDT_Float32, 0, 0) != CE_None)
        *sample = 12345.0f;
    GDALClose(ds);
    return v;
}

static void test_round_trip(void)
{
    frt_terrain_desc d = {0};
    d.levels = 6;
    d.hurst = 0.7;
    d.sigma = 250.0;
    d.seed = 0xfeedbeefcafeULL;
    uint32_t w, hgt;
    float *h = make_field(&d, &w, &hgt);
    /* Holes, and the awkward values float32 must keep bit for bit. */
    h[5] = NAN;
    h[w * 10 + 3] = NAN;
    h[1] = -0.0f;
    h[2] = 1e-40f; /* subnormal */
    h[3] = 3.4028235e38f;
    const size_t n = (size_t)w * hgt;

    const double gt[6] = {350000.5, 2.5, 0.0, 5100000.25, 0.0, -4.0};
    frt_write_desc wd = {0};
    wd.terrain = &d;
    wd.backend = "cpu";
    wd.device = "reference";
    wd.spacing_x = 2.5;
    wd.spacing_y = 4.0;
    wd.geotransform = gt;
    wd.projection = "EPSG:32633";
    wd.has_nodata = true;
    wd.nodata = -32768.0;
    char err[512];
    const char *p = path_in("trip.tif");
    frt_result r = frt_write_heightfield(p, h, w, hgt, &wd, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "write trip.tif: %s", err);

    frt_field_info info;
    float *back = read_field(p, &info, &r, err, sizeof err);
    CHECK(back != NULL, "read trip.tif: %s", err);
    if (back) {
        size_t differ = 0;
        for (size_t i = 0; i < n; ++i)
            differ += isnan(h[i]) ? !isnan(back[i]) : memcmp(&h[i], &back[i], sizeof(float)) != 0;
        CHECK(differ == 0, "round trip bit-exact, NaN kept: %zu differ", differ);
        CHECK(info.width == w && info.height == hgt && info.bits == 32, "size %u x %u, bits %u", info.width,
              info.height, info.bits);
        CHECK(info.has_geotransform && gt_equal(info.geotransform, gt), "geotransform kept");
        CHECK(epsg_of(info.projection) == 32633, "projection kept: '%.80s'", info.projection);
        CHECK(info.has_nodata && info.nodata == -32768.0, "nodata kept: %d %g", info.has_nodata, info.nodata);
        CHECK(info.has_terrain && info.terrain.levels == 6 && info.terrain.hurst == 0.7 &&
                  info.terrain.sigma == 250.0 && info.terrain.seed == 0xfeedbeefcafeULL &&
                  info.terrain.edge == FRT_EDGE_FFC,
              "parameters kept: %d levels %u H %g sigma %g", info.has_terrain, info.terrain.levels, info.terrain.hurst,
              info.terrain.sigma);
        CHECK(strcmp(info.backend, "cpu") == 0 && strcmp(info.device, "reference") == 0 && info.spacing_x == 2.5 &&
                  info.spacing_y == 4.0,
              "backend '%s' device '%s' spacing %g %g", info.backend, info.device, info.spacing_x, info.spacing_y);
        free(back);
    }
    /* What a GIS sees: float32, DEFLATE with the floating-point predictor, strips for a small raster, the holes as
     * the nodata value itself. */
    float raw = 0.0f;
    gdal_view v = gdal_look(p, 5, 0, &raw);
    CHECK(v.opened && v.bands == 1 && v.type == GDT_Float32 && strcmp(v.compression, "DEFLATE") == 0 &&
              strcmp(v.predictor, "3") == 0 && v.block_x == (int)w && v.has_nodata && v.nodata == -32768.0 &&
              raw == -32768.0f && strncmp(v.meta, "{", 1) == 0,
          "GDAL's view: %d bands, type %d, %s predictor %s, block %d x %d, nodata %g, raw %g, meta '%.20s'", v.bands,
          (int)v.type, v.compression, v.predictor, v.block_x, v.block_y, v.nodata, raw, v.meta);

    /* Defaults: no geotransform -> pixel centres at the mesh vertices; NaN holes and no nodata -> nodata NaN; no
     * projection -> none. */
    wd = (frt_write_desc){0};
    wd.spacing_x = 2.0;
    wd.spacing_y = 3.0;
    p = path_in("defaults.tif");
    r = frt_write_heightfield(p, h, w, hgt, &wd, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "write defaults.tif: %s", err);
    back = read_field(p, &info, &r, err, sizeof err);
    const double gt_default[6] = {-1.0, 2.0, 0.0, (hgt - 0.5) * 3.0, 0.0, -3.0};
    CHECK(back && info.has_geotransform && gt_equal(info.geotransform, gt_default),
          "default geotransform {%g %g %g %g %g %g}", info.geotransform[0], info.geotransform[1], info.geotransform[2],
          info.geotransform[3], info.geotransform[4], info.geotransform[5]);
    CHECK(back && info.projection[0] == '\0' && info.has_nodata && isnan(info.nodata) && isnan(back[5]) &&
              back[6] == h[6],
          "no projection, nodata NaN: '%.40s' %d %g", info.projection, info.has_nodata, info.nodata);
    CHECK(back && !info.has_terrain && info.spacing_x == 2.0 && info.spacing_y == 3.0, "spacing recorded: %g %g",
          info.spacing_x, info.spacing_y);
    free(back);

    /* No NaN and no nodata asked for: the file has no nodata value. */
    h[5] = 1.0f;
    h[w * 10 + 3] = 2.0f;
    p = path_in("full.tif");
    r = frt_write_heightfield(p, h, w, hgt, NULL, err, sizeof err);
    CHECK(r == FRT_SUCCESS && frt_read_heightfield_info(p, &info, err, sizeof err) == FRT_SUCCESS && !info.has_nodata,
          "no NaN, no nodata: %d %s", info.has_nodata, err);
    /* Writing and reading made no side files (GDAL's .aux.xml) and left no temporaries. */
    CHECK(files_with("") == files_with(".tif") && files_with(".aux.xml") == 0 && files_with(".tmp-") == 0,
          "no side files or temporaries: %d files, %d .tif", files_with(""), files_with(".tif"));
    free(h);
}

/* Large rasters are tiled 256 x 256; a region sits where it lies in its grid, so two neighbours abut. */
static void test_tiles_and_regions(void)
{
    frt_terrain_desc d = {0};
    d.levels = 9;
    uint32_t w, hgt;
    float *h = make_field(&d, &w, &hgt);
    char err[512];
    const char *p = path_in("big.tif");
    frt_result r = frt_write_heightfield(p, h, w, hgt, NULL, err, sizeof err);
    gdal_view v = gdal_look(p, 0, 0, NULL);
    CHECK(r == FRT_SUCCESS && v.block_x == 256 && v.block_y == 256, "513 x 513 tiled: %s, block %d x %d", err,
          v.block_x, v.block_y);
    frt_field_info info;
    float *back = read_field(p, &info, &r, err, sizeof err);
    CHECK(back && memcmp(back, h, (size_t)w * hgt * sizeof *h) == 0, "tiled round trip bit-exact: %s", err);
    free(back);
    free(h);

    /* Two windows of a 2^7 + 1 grid side by side: the second's left edge is the first's right edge. */
    double gts[2][6];
    for (int k = 0; k < 2; ++k) {
        frt_terrain_desc rd = {0};
        rd.levels = 7;
        rd.region = (frt_region){32 + 33 * (uint32_t)k, 32, 33, 17};
        h = make_field(&rd, &w, &hgt);
        frt_write_desc wd = {0};
        wd.terrain = &rd;
        wd.spacing_x = wd.spacing_y = 10.0;
        p = path_in(k ? "region1.tif" : "region0.tif");
        r = frt_write_heightfield(p, h, w, hgt, &wd, err, sizeof err);
        CHECK(r == FRT_SUCCESS && frt_read_heightfield_info(p, &info, err, sizeof err) == FRT_SUCCESS &&
                  info.has_terrain && info.terrain.region.x == rd.region.x,
              "region %d written and read: %s", k, err);
        memcpy(gts[k], info.geotransform, sizeof gts[k]);
        free(h);
    }
    /* Column 32 of the 129-side grid has its centre at x = 320; row 32 at y = (128 - 32) * 10. */
    const double expect0[6] = {315.0, 10.0, 0.0, 965.0, 0.0, -10.0};
    CHECK(gt_equal(gts[0], expect0), "region placed: {%g %g %g %g %g %g}", gts[0][0], gts[0][1], gts[0][2], gts[0][3],
          gts[0][4], gts[0][5]);
    CHECK(gts[1][0] == gts[0][0] + 33 * 10.0 && gts[1][3] == gts[0][3], "neighbouring regions abut: %g vs %g",
          gts[1][0], gts[0][0] + 330.0);
}

/* Foreign metadata: a crop keeps the FRACTERRA item but not the size (the parameters then do not count); a
 * geographic CRS gives no spacing. */
static void test_foreign_metadata(void)
{
    char err[512];
    frt_field_info info;
    const char *src = path_in("trip.tif");
    GDALDatasetH ds = GDALOpenEx(src, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
    const char *meta = ds ? GDALGetMetadataItem(ds, "FRACTERRA", NULL) : NULL;
    char *copy = meta ? CPLStrdup(meta) : NULL;
    if (ds)
        GDALClose(ds);
    CHECK(copy != NULL, "trip.tif has the FRACTERRA item");
    const char *p = path_in("cropped.tif");
    CHECK(make_input(p, GDT_Float32, 1, "EPSG:32633", 1.0, 0.0), "made cropped.tif");
    ds = GDALOpenEx(p, GDAL_OF_RASTER | GDAL_OF_UPDATE, NULL, NULL, NULL);
    if (ds && copy)
        GDALSetMetadataItem(ds, "FRACTERRA", copy, NULL);
    if (ds)
        GDALClose(ds);
    CPLFree(copy);
    frt_result r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_SUCCESS && !info.has_terrain && info.spacing_x == 30.0 && info.spacing_y == 20.0,
          "metadata of another size ignored: %s terrain %d spacing %g", err, info.has_terrain, info.spacing_x);

    p = path_in("geographic.tif");
    CHECK(make_input(p, GDT_Float32, 1, "EPSG:4326", 1.0, 0.0), "made geographic.tif");
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_SUCCESS && epsg_of(info.projection) == 4326 && info.spacing_x == 1.0 && info.spacing_y == 1.0,
          "geographic: %s epsg %d spacing %g %g", err, epsg_of(info.projection), info.spacing_x, info.spacing_y);
}

/* A write that fails leaves no file, no temporary, and whatever was there before. */
static void test_write_failures(void)
{
    const float h4[4] = {1, 2, NAN, 4};
    char err[512];
    frt_write_desc wd = {0};
    int before = files_with("");

    frt_result r = frt_write_heightfield("/nonexistent-frt-dir/x.tif", h4, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && message_ok(err, "/nonexistent-frt-dir/x.tif") && strstr(err, "No such file"),
          "missing directory: %d %s", (int)r, err);

    write_all(path_in("keep.tif"), "precious", 8);
    ++before;
    wd.projection = "EPSG:999999";
    r = frt_write_heightfield(path_in("keep.tif"), h4, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && message_ok(err, "keep.tif") && strstr(err, "EPSG:999999") &&
              file_is(path_in("keep.tif"), "precious"),
          "unknown projection: %d %s", (int)r, err);
    wd.projection = "not a coordinate system";
    r = frt_write_heightfield(path_in("keep.tif"), h4, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "projection") && file_is(path_in("keep.tif"), "precious"),
          "garbage projection: %d %s", (int)r, err);

    wd = (frt_write_desc){0};
    const double flat[6] = {0, 1, 0, 0, 0, 0};
    wd.geotransform = flat;
    r = frt_write_heightfield(path_in("keep.tif"), h4, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "geotransform") && file_is(path_in("keep.tif"), "precious"),
          "singular geotransform: %d %s", (int)r, err);

    wd = (frt_write_desc){0};
    wd.has_nodata = true;
    wd.nodata = 4.0; /* a height equals it */
    r = frt_write_heightfield(path_in("keep.tif"), h4, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "nodata") && strstr(err, "column 1, row 1") &&
              file_is(path_in("keep.tif"), "precious"),
          "nodata equal to a height: %d %s", (int)r, err);
    wd.nodata = 0.1; /* not a float32 */
    r = frt_write_heightfield(path_in("keep.tif"), h4, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "float32") && file_is(path_in("keep.tif"), "precious"),
          "nodata not a float32: %d %s", (int)r, err);

    /* The file system refuses the data half way (a file size limit, as a full disk would): GDAL's failure is
     * reported, the temporary removed and the old file kept. 513^2 noise-like floats do not compress below 64 KiB. */
    frt_terrain_desc d = {0};
    d.levels = 9;
    d.hurst = 0.1;
    uint32_t w, hgt;
    float *h = make_field(&d, &w, &hgt);
    struct rlimit old;
    getrlimit(RLIMIT_FSIZE, &old);
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    struct rlimit lim = {65536, old.rlim_max};
    bool limited = setrlimit(RLIMIT_FSIZE, &lim) == 0;
    r = frt_write_heightfield(path_in("keep.tif"), h, w, hgt, NULL, err, sizeof err);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, old_handler);
    CHECK(limited, "set a file size limit");
    CHECK(r == FRT_ERROR_IO && message_ok(err, "keep.tif") && strstr(err, "nothing was replaced") &&
              file_is(path_in("keep.tif"), "precious"),
          "write cut short: %d %s", (int)r, err);
    /* ... and the same write without the limit succeeds, so the limit was what failed it. */
    r = frt_write_heightfield(path_in("keep.tif"), h, w, hgt, NULL, err, sizeof err);
    CHECK(r == FRT_SUCCESS && file_size(path_in("keep.tif")) > 65536, "write without the limit: %s", err);
    free(h);

    /* A read-only directory (only as another user than root, who may write anyway). */
    if (geteuid() != 0) {
        mkdir(path_in("ro"), 0755);
        write_all(path_in("ro/old.tif"), "old", 3);
        chmod(path_in("ro"), 0555);
        r = frt_write_heightfield(path_in("ro/old.tif"), h4, 2, 2, NULL, err, sizeof err);
        CHECK(r == FRT_ERROR_IO && strstr(err, "Permission denied") && file_is(path_in("ro/old.tif"), "old"),
              "read-only directory: %s", err);
        chmod(path_in("ro"), 0755);
        unlink(path_in("ro/old.tif"));
        rmdir(path_in("ro"));
    }
    CHECK(files_with(".tmp-") == 0 && files_with("") == before, "no temporaries left: %d files, %d before",
          files_with(""), before);
}

/* Inputs that are not a single-band TIFF give one clear line. */
static void test_read_failures(void)
{
    char err[512];
    frt_field_info info;
    float out[SIDE * SIDE];

    write_all(path_in("garbage.tif"), "this is not a TIFF at all\n", 26);
    frt_result r = frt_read_heightfield(path_in("garbage.tif"), out, SIDE * SIDE, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && message_ok(err, "garbage.tif") && strstr(err, "not a TIFF"),
          "garbage: %d %s", (int)r, err);
    write_all(path_in("empty.tiff"), "", 0);
    r = frt_read_heightfield_info(path_in("empty.tiff"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && message_ok(err, "empty.tiff"), "empty: %d %s", (int)r, err);
    r = frt_read_heightfield_info(path_in("missing.tif"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && message_ok(err, "missing.tif") && strstr(err, "No such file"), "missing: %d %s", (int)r,
          err);
    /* A PNG named .tif: GDAL could read it, but .tif means TIFF (the GTiff driver only). */
    const float h4[4] = {1, 2, 3, 4};
    r = frt_write_heightfield(path_in("png.png"), h4, 2, 2, NULL, err, sizeof err);
    rename(path_in("png.png"), path_in("png.tif"));
    r = frt_read_heightfield_info(path_in("png.tif"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && message_ok(err, "png.tif"), "PNG named .tif: %d %s", (int)r, err);

    /* A valid file cut short: its header may still parse, the samples cannot. */
    FILE *in = fopen(path_in("big.tif"), "rb");
    long size = file_size(path_in("big.tif"));
    uint8_t *b = check_alloc((size_t)(size > 0 ? size : 1));
    size_t got = in ? fread(b, 1, (size_t)size, in) : 0;
    if (in)
        fclose(in);
    write_all(path_in("cut.tif"), b, got / 2);
    free(b);
    r = frt_read_heightfield_info(path_in("cut.tif"), &info, err, sizeof err);
    if (r == FRT_SUCCESS) {
        float *h = check_alloc((size_t)info.width * info.height * sizeof *h);
        r = frt_read_heightfield(path_in("cut.tif"), h, (size_t)info.width * info.height, &info, err, sizeof err);
        free(h);
    }
    CHECK(r != FRT_SUCCESS && message_ok(err, "cut.tif"), "truncated: %d %s", (int)r, err);

    /* Several bands: refused rather than guessing (band 1 of an RGB picture is no terrain). */
    CHECK(make_input(path_in("rgb.tif"), GDT_Float32, 3, "EPSG:32633", 1.0, 0.0), "made rgb.tif");
    r = frt_read_heightfield_info(path_in("rgb.tif"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && message_ok(err, "rgb.tif") && strstr(err, "3 bands"), "3 bands: %d %s", (int)r,
          err);
    r = frt_read_heightfield(path_in("rgb.tif"), out, SIDE * SIDE, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && strstr(err, "3 bands"), "3 bands, read: %d %s", (int)r, err);
    /* Complex samples. */
    CHECK(make_input(path_in("complex.tif"), GDT_CFloat32, 1, "EPSG:32633", 1.0, 0.0), "made complex.tif");
    r = frt_read_heightfield_info(path_in("complex.tif"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && strstr(err, "complex"), "complex: %d %s", (int)r, err);
}

/* A coordinate system whose WKT does not fit frt_field_info.projection fails rather than being cut. GeoTIFF's keys
 * cannot hold one (GDAL shortens long names there), but GDAL's .aux.xml beside a file can, and overrides them. */
static void test_long_projection(void)
{
    const float h4[4] = {1, 2, 3, 4};
    char err[512];
    frt_result r = frt_write_heightfield(path_in("longcrs.tif"), h4, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "write longcrs.tif: %s", err);
    char name[9000];
    memset(name, 'x', sizeof name - 1);
    name[sizeof name - 1] = '\0';
    size_t cap = sizeof name + 1024;
    char *xml = check_alloc(cap);
    snprintf(
        xml, cap,
        "<PAMDataset><SRS dataAxisToSRSAxisMapping=\"1,2\">PROJCS[\"%s\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\","
        "SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],"
        "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",15],"
        "PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],PARAMETER[\"false_northing\",0],"
        "UNIT[\"metre\",1]]</SRS></PAMDataset>\n",
        name);
    write_all(path_in("longcrs.tif.aux.xml"), xml, strlen(xml));
    free(xml);
    frt_field_info info;
    r = frt_read_heightfield_info(path_in("longcrs.tif"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_UNSUPPORTED && message_ok(err, "longcrs.tif") && strstr(err, "WKT"), "long WKT: %d %s", (int)r,
          err);
    /* Without the side file the same file reads. */
    unlink(path_in("longcrs.tif.aux.xml"));
    r = frt_read_heightfield_info(path_in("longcrs.tif"), &info, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "without its .aux.xml: %s", err);
}

static void test_api(void)
{
    char err[512];
    CHECK(frt_file_format_from_path("a/b.tif") == FRT_FILE_TIFF && frt_file_format_from_path("B.TIFF") == FRT_FILE_TIFF,
          ".tif and .tiff are GeoTIFF: %d %d", (int)frt_file_format_from_path("a/b.tif"),
          (int)frt_file_format_from_path("B.TIFF"));
    CHECK(strcmp(frt_file_format_name(FRT_FILE_TIFF), "tif") == 0, "name '%s'", frt_file_format_name(FRT_FILE_TIFF));
    /* An explicit format overrides the extension. */
    const float h4[4] = {1, 2, 3, 4};
    frt_write_desc wd = {0};
    wd.format = FRT_FILE_TIFF;
    frt_result r = frt_write_heightfield(path_in("explicit.dat"), h4, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_SUCCESS && file_size(path_in("explicit.dat")) > 0, "format given: %s", err);
    /* Streams cannot carry GeoTIFF (GDAL needs a name). */
    frt_field_out fo;
    CHECK(frt_field_out_init(&fo, "s.tif", h4, 2, 2, NULL, err, sizeof err) == FRT_SUCCESS, "%s", err);
    FILE *fp = tmpfile();
    r = fp ? frt_write_stream(fp, &fo, err, sizeof err) : FRT_SUCCESS;
    CHECK(r == FRT_ERROR_UNSUPPORTED && message_ok(err, "s.tif"), "write_stream: %d %s", (int)r, err);
    frt_field_info info;
    r = fp ? frt_read_stream(fp, FRT_FILE_TIFF, NULL, "s.tif", &info, NULL, 0, err, sizeof err) : FRT_SUCCESS;
    CHECK(r == FRT_ERROR_UNSUPPORTED && message_ok(err, "s.tif"), "read_stream: %d %s", (int)r, err);
    if (fp)
        fclose(fp);
}

int main(void)
{
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 2;
    }
    GDALAllRegister();
    test_read_synthetic(GDT_Float32, "input_f32.tif");
    test_read_synthetic(GDT_Int16, "input_i16.tiff");
    test_scale_offset();
    test_round_trip();
    test_tiles_and_regions();
    test_foreign_metadata();
    test_write_failures();
    test_read_failures();
    test_long_projection();
    test_api();
    if (getenv("FRT_TEST_KEEP")) /* for a look at the files */
        printf("files kept in %s\n", dir);
    else
        remove_dir();
    GDALDestroy();
    return check_summary("test_tiff");
}

#endif
