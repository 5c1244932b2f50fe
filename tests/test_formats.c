/* test_formats.c — heightfield files through the public API (files.c, formats.c, format_*.c, atomic_file.c): round
 * trips of every format, independent readers (libpng; strict NPY, PGM and PLY parsers here), meshes, files from
 * other tools, failures that leave old files intact, and a robustness pass over truncated and mutated files. */
#include "check.h"

#define FRT_STR2(x) #x
#define FRT_STR(x) FRT_STR2(x)

#include <dirent.h>
#include <errno.h>
#include <png.h>
#include <sys/stat.h>
#include <unistd.h>

/* Quantised formats map back within half a quantum (round to nearest) plus float32 rounding of the result: 2^-23
 * relative to the largest magnitude, twice (the mapping and the subtraction). */
#define QUANTUM_HALF 0.5
#define FLOAT_SLACK (2.0 * 1.1920929e-7)
/* A unit normal's components rounded to float32 and printed with %.9g: within 2^-24 of the exact value, plus the
 * rounding of the central difference in double (far smaller). */
#define NORMAL_TOL 1.2e-7
#define ROBUST_MUTATIONS 2500

static char dir[] = "/tmp/frt_formats_XXXXXX";

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

static uint8_t *read_all(const char *p, size_t *n)
{
    FILE *f = fopen(p, "rb");
    long size = file_size(p);
    *n = 0;
    if (!f || size < 0) {
        if (f)
            fclose(f);
        return NULL;
    }
    uint8_t *b = check_alloc((size_t)size + 1);
    *n = fread(b, 1, (size_t)size, f);
    fclose(f);
    return b;
}

static void write_all(const char *p, const void *data, size_t n)
{
    FILE *f = fopen(p, "wb");
    if (!f || fwrite(data, 1, n, f) != n)
        fprintf(stderr, "cannot write %s\n", p);
    if (f)
        fclose(f);
}

static int temp_files_left(void)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL)
        n += strstr(e->d_name, ".tmp-") != NULL;
    if (d)
        closedir(d);
    return n;
}

/* Reads a whole heightfield; NULL (and r set) on failure. */
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

static bool message_ok(const char *err, const char *path)
{
    char want[300];
    snprintf(want, sizeof want, "'%s'", path);
    return strncmp(err, want, strlen(want)) == 0 && !strchr(err, '\n');
}

/* ---- the field every round trip uses ---- */

static frt_terrain_desc terrain;
static float field[65 * 65];
static const char *device_name = "quote\" back\\slash";

static void test_extensions(void)
{
    CHECK(frt_file_format_from_path("a.PNG") == FRT_FILE_PNG && frt_file_format_from_path("x.npy") == FRT_FILE_NPY &&
              frt_file_format_from_path("d.f32") == FRT_FILE_F32 &&
              frt_file_format_from_path("a/b.Pgm") == FRT_FILE_PGM &&
              frt_file_format_from_path("m.obj") == FRT_FILE_OBJ && frt_file_format_from_path("m.PLY") == FRT_FILE_PLY,
          "extensions");
    CHECK(frt_file_format_from_path("a.tif") == FRT_FILE_TIFF && frt_file_format_from_path("a.TIFF") == FRT_FILE_TIFF,
          "GeoTIFF extensions");
    CHECK(frt_file_format_from_path("a.xyz") == FRT_FILE_DEFAULT &&
              frt_file_format_from_path("dir.png/file") == FRT_FILE_DEFAULT &&
              frt_file_format_from_path("noext") == FRT_FILE_DEFAULT && frt_file_format_from_path(NULL) == 0,
          "unknown extensions");
    CHECK(strcmp(frt_file_format_name(FRT_FILE_PLY), "ply") == 0 &&
              strcmp(frt_file_format_name(FRT_FILE_F32), "f32") == 0 &&
              strcmp(frt_file_format_name(FRT_FILE_DEFAULT), "") == 0 &&
              strcmp(frt_file_format_name((frt_file_format)99), "") == 0,
          "format names");
}

typedef struct round_trip {
    const char *name;
    uint32_t bits; /* written */
    bool exact;    /* floats come back identical */
    bool records;  /* the file records the parameters */
    uint32_t read_bits;
} round_trip;

static void test_round_trips(void)
{
    static const round_trip cases[] = {
        {"rt.f32", 0, true, true, 32},  {"rt.npy", 0, true, false, 32},    {"rt16.png", 0, false, true, 16},
        {"rt8.png", 8, false, true, 8}, {"rt16.pgm", 16, false, true, 16}, {"rt8.pgm", 8, false, true, 8},
        {"rt.obj", 0, true, true, 32},  {"rt.ply", 0, true, true, 32},
    };
    float lo = field[0], hi = field[0];
    for (size_t i = 0; i < 65 * 65; ++i)
        lo = fminf(lo, field[i]), hi = fmaxf(hi, field[i]);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        const round_trip *t = &cases[c];
        const char *p = path_in(t->name);
        frt_write_desc wd = {0};
        wd.bits = t->bits;
        wd.terrain = &terrain;
        wd.backend = "cpu";
        wd.device = device_name;
        char err[512];
        frt_result r = frt_write_heightfield(p, field, 65, 65, &wd, err, sizeof err);
        CHECK(r == FRT_SUCCESS, "%s: %s", t->name, err);
        frt_field_info info;
        float *back = read_field(p, &info, &r, err, sizeof err);
        CHECK(back != NULL, "%s: %s", t->name, err);
        if (!back)
            continue;
        CHECK(info.format == frt_file_format_from_path(p) && info.width == 65 && info.height == 65 &&
                  info.bits == t->read_bits,
              "%s: info %d %ux%u bits %u", t->name, (int)info.format, info.width, info.height, info.bits);
        if (t->exact) {
            CHECK(memcmp(back, field, sizeof field) == 0, "%s: floats identical", t->name);
            CHECK(info.min == lo && info.max == hi, "%s: min/max %g %g", t->name, info.min, info.max);
        } else {
            double q = ((double)hi - lo) / (t->read_bits == 16 ? 65535.0 : 255.0);
            double tol = QUANTUM_HALF * q + FLOAT_SLACK * fmax(fabs(lo), fabs(hi));
            float worst = max_abs_diff(back, field, 65 * 65);
            CHECK(worst <= tol, "%s: off by %g > %g (half a quantum)", t->name, worst, tol);
            CHECK(info.has_range, "%s: range recorded", t->name);
        }
        CHECK(info.has_terrain == t->records, "%s: has_terrain %d", t->name, info.has_terrain);
        if (t->records) {
            CHECK(info.terrain.levels == terrain.levels && info.terrain.hurst == terrain.hurst &&
                      info.terrain.sigma == terrain.sigma && info.terrain.seed == UINT64_MAX &&
                      info.terrain.edge == FRT_EDGE_FFC,
                  "%s: parameters %u %g %g %llu", t->name, info.terrain.levels, info.terrain.hurst, info.terrain.sigma,
                  (unsigned long long)info.terrain.seed);
            CHECK(strcmp(info.backend, "cpu") == 0 && strcmp(info.device, device_name) == 0,
                  "%s: backend '%s' device '%s'", t->name, info.backend, info.device);
        }
        free(back);
    }
}

/* libpng itself, as the independent reader: depth, colour type, text chunks and every sample. */
static void test_png_by_libpng(uint32_t bits)
{
    const char *p = path_in(bits == 16 ? "rt16.png" : "rt8.png");
    FILE *f = fopen(p, "rb");
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    uint8_t *row = check_alloc(65 * 2);
    if (!f || setjmp(png_jmpbuf(png))) {
        CHECK(0, "libpng could not read %s", p);
        return;
    }
    png_init_io(png, f);
    png_read_info(png, info);
    CHECK(png_get_image_width(png, info) == 65 && png_get_image_height(png, info) == 65, "PNG size");
    CHECK(png_get_bit_depth(png, info) == (int)bits && png_get_color_type(png, info) == PNG_COLOR_TYPE_GRAY,
          "%u-bit grey", bits);
    png_textp text;
    int ntext = 0;
    png_get_text(png, info, &text, &ntext);
    double min = NAN, max = NAN;
    bool have_params = false;
    for (int i = 0; i < ntext; ++i) {
        if (strcmp(text[i].key, "fracterra:min") == 0)
            min = strtod(text[i].text, NULL);
        if (strcmp(text[i].key, "fracterra:max") == 0)
            max = strtod(text[i].text, NULL);
        if (strcmp(text[i].key, "fracterra:params") == 0)
            have_params = strstr(text[i].text, "\"hurst\": 0.5,") &&
                          strstr(text[i].text, "\"seed\": 18446744073709551615") &&
                          text[i].compression == PNG_TEXT_COMPRESSION_zTXt;
    }
    CHECK(have_params && isfinite(min) && isfinite(max), "text chunks carry min, max and the parameters (zTXt)");
    size_t bad = 0;
    uint32_t lo = 65535, hi = 0, maxq = bits == 16 ? 65535 : 255;
    double scale = (max - min) / maxq;
    for (uint32_t y = 0; y < 65; ++y) {
        png_read_row(png, row, NULL);
        for (uint32_t x = 0; x < 65; ++x) {
            uint32_t q = bits == 16 ? (uint32_t)(row[2 * x] << 8 | row[2 * x + 1]) : row[x];
            lo = q < lo ? q : lo;
            hi = q > hi ? q : hi;
            bad += fabs(min + q * scale - field[y * 65 + x]) > QUANTUM_HALF * scale * 1.001;
        }
    }
    CHECK(bad == 0 && lo == 0 && hi == maxq, "PNG samples: %zu off by > half a quantum, range %u..%u", bad, lo, hi);
    free(row);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
}

/* A strict NPY check: magic, version, alignment, the header dict, and the payload. */
static void test_npy_layout(void)
{
    size_t n;
    uint8_t *b = read_all(path_in("rt.npy"), &n);
    CHECK(b && n > 10 && memcmp(b, "\x93NUMPY\x01\x00", 8) == 0, "NPY magic, v1.0");
    if (!b || n <= 10)
        return;
    size_t hl = (size_t)b[8] | (size_t)b[9] << 8;
    CHECK((10 + hl) % 64 == 0 && 10 + hl + sizeof field == n, "data aligned to 64 bytes (header %zu), size %zu", hl, n);
    char hdr[256] = {0};
    memcpy(hdr, b + 10, hl < 255 ? hl : 255);
    CHECK(strstr(hdr, "'descr': '<f4'") && strstr(hdr, "'fortran_order': False") && strstr(hdr, "'shape': (65, 65)") &&
              hdr[hl - 1] == '\n',
          "header dict: %s", hdr);
    CHECK(10 + hl + sizeof field <= n && memcmp(b + 10 + hl, field, sizeof field) == 0, "NPY payload identical");
    free(b);
}

/* The sidecar as JSON text: the keys, exact seed, escaped strings, pretty layout. */
static void test_sidecar(void)
{
    size_t n;
    uint8_t *b = read_all(path_in("rt.f32.json"), &n);
    CHECK(b != NULL, "sidecar exists");
    if (!b)
        return;
    b[n] = 0;
    const char *s = (const char *)b;
    CHECK(strstr(s, "\"width\": 65,\n") && strstr(s, "\"seed\": 18446744073709551615") &&
              strstr(s, "\"device\": \"quote\\\" back\\\\slash\"") && strstr(s, "\"hurst\": 0.5,") &&
              strstr(s, "\"dimension\": 2.5,") && strstr(s, "\"dtype\": \"float32\"") &&
              strstr(s, "\"byte_order\": \"little\"") && strstr(s, "\"spacing_x\": 1,") &&
              strstr(s, "\"z_scale\": 1,") && strstr(s, "\"spec_version\": " FRT_STR(FRT_SPEC_VERSION)) &&
              strstr(s, "\"fracterra_version\": \"" FRT_VERSION_STRING "\""),
          "sidecar JSON: %s", s);
    free(b);
    CHECK(file_size(path_in("rt.f32")) == (long)sizeof field, "f32 is the bare floats");

    /* Without terrain parameters none are written or read; spacing and z_scale are. */
    frt_write_desc wd = {0};
    wd.spacing_x = 2.5;
    wd.spacing_y = 0.8;
    wd.z_scale = -2;
    char err[512];
    CHECK(frt_write_heightfield(path_in("plain.f32"), field, 65, 65, &wd, err, sizeof err) == FRT_SUCCESS, "%s", err);
    b = read_all(path_in("plain.f32.json"), &n);
    if (b) {
        b[n] = 0;
        CHECK(!strstr((char *)b, "levels") && !strstr((char *)b, "seed") && !strstr((char *)b, "backend") &&
                  strstr((char *)b, "\"spacing_y\": 0.8,") && strstr((char *)b, "\"z_scale\": -2,"),
              "sidecar without parameters: %s", (char *)b);
        free(b);
    }
    frt_field_info info;
    CHECK(frt_read_heightfield_info(path_in("plain.f32"), &info, err, sizeof err) == FRT_SUCCESS && !info.has_terrain &&
              info.spacing_x == 2.5 && info.spacing_y == 0.8 && info.z_scale == -2 && info.backend[0] == 0,
          "spacing and z_scale read back: %s", err);
}

/* A region's metadata (docs/ALGORITHM.md §3.2): where the window lies and the side of its virtual grid, written by
 * every format that records parameters and read back into info.terrain.region. Levels above FRT_MAX_LEVELS count
 * only with a region; a record that contradicts itself or the file is left out, not trusted; files without a
 * region (all before it existed) read as whole grids. */
static void test_region_metadata(void)
{
    static const struct {
        const char *name;
        frt_edge edge;
        uint32_t levels, x, y;
        const char *grid_side;
    } cases[] = {
        {"reg.f32", FRT_EDGE_FFC, 24, 1000000, 16777217 - 65, "16777217"},
        {"reg.png", FRT_EDGE_PERIODIC, 30, 1073741800, 5, "1073741824"}, /* wraps around the torus */
        {"reg.pgm", FRT_EDGE_FFC, 30, 0, 0, "1073741825"},
        {"reg.obj", FRT_EDGE_PERIODIC, 7, 100, 120, "128"},
        {"reg.ply", FRT_EDGE_FFC, 20, 7, 1048577 - 65, "1048577"},
    };
    char err[512];
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        frt_terrain_desc d = {0};
        d.levels = cases[c].levels, d.hurst = 0.5, d.seed = 42, d.edge = cases[c].edge;
        d.region = (frt_region){cases[c].x, cases[c].y, 65, 65};
        frt_write_desc wd = {0};
        wd.terrain = &d;
        const char *p = path_in(cases[c].name);
        CHECK(frt_write_heightfield(p, field, 65, 65, &wd, err, sizeof err) == FRT_SUCCESS, "%s: %s", cases[c].name,
              err);
        frt_field_info info;
        CHECK(frt_read_heightfield_info(p, &info, err, sizeof err) == FRT_SUCCESS, "%s: %s", cases[c].name, err);
        const frt_region g = info.terrain.region;
        CHECK(info.has_terrain && info.terrain.levels == cases[c].levels && info.terrain.edge == cases[c].edge &&
                  info.terrain.seed == 42 && g.x == cases[c].x && g.y == cases[c].y && g.width == 65 && g.height == 65,
              "%s: has_terrain %d, levels %u, region %u,%u %ux%u", cases[c].name, info.has_terrain, info.terrain.levels,
              g.x, g.y, g.width, g.height);
        /* The text records the virtual grid's side for a reader without the library. */
        char want[64];
        snprintf(want, sizeof want, "\"grid_side\": %s", cases[c].grid_side);
        size_t n;
        uint8_t *b = read_all(c == 0 ? path_in("reg.f32.json") : p, &n);
        bool found = false;
        for (size_t i = 0; b && i + strlen(want) <= n && !found; ++i)
            found = memcmp(b + i, want, strlen(want)) == 0;
        if (c != 1) /* the PNG's params chunk is zlib-compressed */
            CHECK(found, "%s records %s", cases[c].name, want);
        free(b);
    }
    frt_field_info info;
    CHECK(frt_read_heightfield_info(path_in("rt.f32"), &info, err, sizeof err) == FRT_SUCCESS && info.has_terrain &&
              !frt_region_is_set(&info.terrain.region),
          "a file without a region reads as the whole grid: %s", err);

    /* Hand-written sidecars of a 2 x 2 field: only consistent records count. */
    static const struct {
        const char *params;
        bool counts;
    } sidecars[] = {
        {"\"levels\": 24, \"region\": {\"x\": 5, \"y\": 6, \"width\": 2, \"height\": 2}, \"grid_side\": 16777217",
         true},
        {"\"levels\": 24, \"region\": {\"x\": 5, \"y\": 6, \"width\": 2, \"height\": 2}", true},
        {"\"levels\": 24", false}, /* more than a whole grid may have */
        {"\"levels\": 24, \"region\": {\"x\": 5, \"y\": 6, \"width\": 3, \"height\": 2}", false}, /* not 2 x 2 */
        {"\"levels\": 24, \"region\": {\"x\": 5, \"y\": 6, \"width\": 2, \"height\": 2}, \"grid_side\": 4097", false},
        {"\"levels\": 24, \"region\": {\"x\": 5, \"y\": 6, \"width\": 2, \"height\": 2}, \"grid_side\": \"big\"",
         false},
        {"\"levels\": 2, \"region\": {\"x\": 4, \"y\": 0, \"width\": 2, \"height\": 2}", false}, /* outside 5 x 5 */
        {"\"levels\": 24, \"region\": {\"x\": 5, \"y\": 6, \"width\": 2}", false},
        {"\"levels\": 24, \"region\": {\"x\": -5, \"y\": 6, \"width\": 2, \"height\": 2}", false},
        {"\"levels\": 24, \"region\": [5, 6, 2, 2]", false},
        {"\"levels\": 31, \"region\": {\"x\": 5, \"y\": 6, \"width\": 2, \"height\": 2}", false},
        {"\"levels\": 2, \"region\": {\"x\": 3, \"y\": 3, \"width\": 2, \"height\": 2}, \"edge\": \"periodic\"", true},
    };
    const float h[4] = {1, 2, 3, 4};
    write_all(path_in("hand.f32"), h, sizeof h);
    for (size_t i = 0; i < sizeof sidecars / sizeof sidecars[0]; ++i) {
        char json[512];
        int len =
            snprintf(json, sizeof json, "{\"width\": 2, \"height\": 2, \"hurst\": 0.5, \"sigma\": 1, \"seed\": 7, %s}",
                     sidecars[i].params);
        write_all(path_in("hand.f32.json"), json, (size_t)len);
        frt_result r = frt_read_heightfield_info(path_in("hand.f32"), &info, err, sizeof err);
        CHECK(r == FRT_SUCCESS && info.has_terrain == sidecars[i].counts &&
                  (!info.has_terrain || (info.terrain.region.width == 2 && info.terrain.seed == 7)),
              "sidecar %zu (%s): %d, has_terrain %d: %s", i, json, (int)r, info.has_terrain, err);
    }
}

/* PGM bytes as Netpbm defines them: P5, comments before the size, maxval, big-endian samples. */
static void test_pgm_layout(void)
{
    size_t n;
    uint8_t *b = read_all(path_in("rt16.pgm"), &n);
    CHECK(b && n > 20 && memcmp(b, "P5\n# fracterra min=", 19) == 0, "PGM magic and range comment");
    if (!b)
        return;
    b[n] = 0;
    const char *size_line = strstr((char *)b, "\n65 65\n65535\n");
    CHECK(size_line && strstr((char *)b, "\n# fracterra params {") < size_line, "size and maxval after the comments");
    if (size_line) {
        size_t data = (size_t)(size_line - (char *)b) + 13;
        CHECK(n - data == 65 * 65 * 2, "16-bit samples: %zu bytes", n - data);
        uint32_t lo = 65535, hi = 0;
        for (size_t i = data; i + 1 < n; i += 2) {
            uint32_t q = (uint32_t)b[i] << 8 | b[i + 1];
            lo = q < lo ? q : lo, hi = q > hi ? q : hi;
        }
        CHECK(lo == 0 && hi == 65535, "samples span 0..65535 (big-endian): %u..%u", lo, hi);
    }
    free(b);
}

/* ---- meshes ---- */

typedef struct mesh {
    size_t nv, nvn, nf;
    float *v, *vn; /* 3 per vertex */
    uint32_t *f;   /* 3 per face, 0-based */
} mesh;

static void mesh_free(mesh *m)
{
    free(m->v), free(m->vn), free(m->f);
    memset(m, 0, sizeof *m);
}

/* An OBJ parser of our own, strict about the lines fracterra writes. */
static bool parse_obj(const char *p, mesh *m)
{
    memset(m, 0, sizeof *m);
    FILE *f = fopen(p, "r");
    if (!f)
        return false;
    size_t cap = 1 << 16;
    m->v = check_alloc(cap * 12), m->vn = check_alloc(cap * 12), m->f = check_alloc(2 * cap * 12);
    char line[512];
    bool ok = true;
    while (ok && fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        float a, b, c;
        unsigned long long i[6];
        if (sscanf(line, "v %f %f %f", &a, &b, &c) == 3 && m->nv < cap)
            m->v[3 * m->nv] = a, m->v[3 * m->nv + 1] = b, m->v[3 * m->nv++ + 2] = c;
        else if (sscanf(line, "vn %f %f %f", &a, &b, &c) == 3 && m->nvn < cap)
            m->vn[3 * m->nvn] = a, m->vn[3 * m->nvn + 1] = b, m->vn[3 * m->nvn++ + 2] = c;
        else if (sscanf(line, "f %llu//%llu %llu//%llu %llu//%llu", &i[0], &i[1], &i[2], &i[3], &i[4], &i[5]) == 6 &&
                 i[0] == i[1] && i[2] == i[3] && i[4] == i[5] && m->nf < 2 * cap)
            for (int k = 0; k < 3; ++k)
                m->f[3 * m->nf + k] = (uint32_t)i[2 * k] - 1, ok &= i[2 * k] >= 1 && i[2 * k] <= m->nv;
        else
            ok = false;
        if (line[0] == 'f')
            m->nf++;
    }
    fclose(f);
    return ok;
}

static float le_float(const uint8_t *b)
{
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    float x;
    memcpy(&x, &u, 4);
    return x;
}

/* A PLY parser of our own for exactly the layout fracterra documents. */
static bool parse_ply(const char *p, mesh *m)
{
    memset(m, 0, sizeof *m);
    size_t n;
    uint8_t *b = read_all(p, &n);
    if (!b)
        return false;
    b[n] = 0;
    unsigned long long nv = 0, nf = 0;
    const char *s = (const char *)b, *v = strstr(s, "\nelement vertex "), *fe = strstr(s, "\nelement face ");
    const char *end = strstr(s, "end_header\n");
    bool ok = strncmp(s, "ply\nformat binary_little_endian 1.0\n", 36) == 0 && v && fe && end &&
              sscanf(v, "\nelement vertex %llu", &nv) == 1 && sscanf(fe, "\nelement face %llu", &nf) == 1 &&
              strstr(s, "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                        "property float nz\nelement face") &&
              strstr(s, "property list uchar int vertex_indices\ncomment fracterra params {") &&
              strstr(s, "}\nend_header\n");
    size_t data = ok ? (size_t)(end - s) + 11 : 0;
    ok = ok && n == data + nv * 24 + nf * 13;
    if (ok) {
        m->nv = m->nvn = nv, m->nf = nf;
        m->v = check_alloc(nv * 12 + 1), m->vn = check_alloc(nv * 12 + 1), m->f = check_alloc(nf * 12 + 1);
        for (size_t i = 0; i < nv; ++i)
            for (int k = 0; k < 3; ++k)
                m->v[3 * i + k] = le_float(b + data + 24 * i + 4 * k),
                             m->vn[3 * i + k] = le_float(b + data + 24 * i + 12 + 4 * k);
        const uint8_t *fp = b + data + nv * 24;
        for (size_t i = 0; i < nf && ok; ++i, fp += 13) {
            ok = fp[0] == 3;
            for (int k = 0; k < 3; ++k) {
                uint32_t idx = (uint32_t)fp[1 + 4 * k] | (uint32_t)fp[2 + 4 * k] << 8 | (uint32_t)fp[3 + 4 * k] << 16 |
                               (uint32_t)fp[4 + 4 * k] << 24;
                m->f[3 * i + k] = idx;
                ok &= idx < nv;
            }
        }
    }
    free(b);
    return ok;
}

/* Counts, positions, normals and winding of a mesh of the tilted plane h = a*col + b*row. */
static void check_plane_mesh(const char *what, const mesh *m, uint32_t w, uint32_t h, uint32_t stride, double sx,
                             double sy, double zs, double a, double b)
{
    uint32_t W = (w - 1 + stride - 1) / stride + 1, H = (h - 1 + stride - 1) / stride + 1;
    CHECK(m->nv == (size_t)W * H && m->nvn == m->nv && m->nf == 2 * (size_t)(W - 1) * (H - 1),
          "%s: %zu vertices, %zu normals, %zu faces for a %u x %u grid", what, m->nv, m->nvn, m->nf, W, H);
    if (m->nv != (size_t)W * H)
        return;
    /* z = zs*(a*col + b*row) with col = x/sx, row = h-1 - y/sy: dz/dx = zs*a/sx, dz/dy = -zs*b/sy. */
    double gx = zs * a / sx, gy = -zs * b / sy, len = sqrt(gx * gx + gy * gy + 1);
    double nx = -gx / len, ny = -gy / len, nz = 1 / len;
    size_t bad_pos = 0, bad_n = 0, bad_wind = 0;
    for (uint32_t j = 0; j < H; ++j)
        for (uint32_t i = 0; i < W; ++i) {
            uint32_t col = i * stride < w - 1 ? i * stride : w - 1, row = j * stride < h - 1 ? j * stride : h - 1;
            const float *v = m->v + 3 * ((size_t)j * W + i), *n = m->vn + 3 * ((size_t)j * W + i);
            bad_pos += v[0] != (float)(col * sx) || v[1] != (float)((h - 1 - row) * sy) ||
                       v[2] != (float)(zs * (float)(a * col + b * row));
            bad_n += fabs(n[0] - nx) > NORMAL_TOL || fabs(n[1] - ny) > NORMAL_TOL || fabs(n[2] - nz) > NORMAL_TOL;
        }
    for (size_t t = 0; t < m->nf; ++t) {
        const float *p0 = m->v + 3 * m->f[3 * t], *p1 = m->v + 3 * m->f[3 * t + 1], *p2 = m->v + 3 * m->f[3 * t + 2];
        double cross_z =
            ((double)p1[0] - p0[0]) * ((double)p2[1] - p0[1]) - ((double)p1[1] - p0[1]) * ((double)p2[0] - p0[0]);
        bad_wind += !(cross_z > 0);
    }
    CHECK(bad_pos == 0, "%s: %zu vertices off the grid", what, bad_pos);
    CHECK(bad_n == 0, "%s: %zu normals differ from the plane's (%g %g %g)", what, bad_n, nx, ny, nz);
    CHECK(bad_wind == 0, "%s: %zu triangles not counter-clockwise from +z", what, bad_wind);
}

static void test_meshes(void)
{
    /* A tilted plane with exactly representable heights; 9 x 7 with stride 4 keeps columns 0, 4, 8 and rows 0, 4, 6:
     * the last step is shorter, and the normals must still be the plane's. */
    const uint32_t w = 9, h = 7;
    const double a = 0.5, b = -0.25;
    float plane[9 * 7];
    for (uint32_t r = 0; r < h; ++r)
        for (uint32_t c = 0; c < w; ++c)
            plane[r * w + c] = (float)(a * c + b * r);
    static const struct {
        uint32_t stride;
        double sx, sy, zs;
    } cases[] = {{1, 1, 1, 1}, {1, 2, 0.5, 3}, {4, 1.5, 2, -2}, {3, 1, 1, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        frt_write_desc wd = {0};
        wd.mesh_stride = cases[c].stride, wd.spacing_x = cases[c].sx, wd.spacing_y = cases[c].sy;
        wd.z_scale = cases[c].zs;
        wd.terrain = &terrain;
        char err[512], what[64];
        for (int fmt = 0; fmt < 2; ++fmt) {
            const char *p = path_in(fmt ? "plane.ply" : "plane.obj");
            snprintf(what, sizeof what, "%s stride %u z_scale %g", fmt ? "PLY" : "OBJ", cases[c].stride, cases[c].zs);
            CHECK(frt_write_heightfield(p, plane, w, h, &wd, err, sizeof err) == FRT_SUCCESS, "%s: %s", what, err);
            mesh m;
            CHECK(fmt ? parse_ply(p, &m) : parse_obj(p, &m), "%s parses", what);
            check_plane_mesh(what, &m, w, h, cases[c].stride, cases[c].sx, cases[c].sy, cases[c].zs, a, b);
            mesh_free(&m);
            /* Read back: the thinned grid, heights z / z_scale (exact here: z_scale is a power of two or 3 with
             * heights that are multiples of 1/4), spacing of the thinned grid's first step. */
            frt_field_info info;
            frt_result r;
            float *back = read_field(p, &info, &r, err, sizeof err);
            uint32_t W = frt_mesh_side(w, cases[c].stride), H = frt_mesh_side(h, cases[c].stride);
            CHECK(back && info.width == W && info.height == H && info.has_terrain && info.z_scale == cases[c].zs &&
                      info.spacing_x == cases[c].sx * cases[c].stride &&
                      info.spacing_y == cases[c].sy * cases[c].stride,
                  "%s reads back as a %u x %u grid: %s (%u x %u, spacing %g %g)", what, W, H, err, info.width,
                  info.height, info.spacing_x, info.spacing_y);
            size_t bad = 0;
            for (uint32_t j = 0; back && j < H && info.width == W; ++j)
                for (uint32_t i = 0; i < W; ++i) {
                    uint32_t col = i * cases[c].stride < w - 1 ? i * cases[c].stride : w - 1;
                    uint32_t row = j * cases[c].stride < h - 1 ? j * cases[c].stride : h - 1;
                    bad += back[j * W + i] != plane[row * w + col];
                }
            CHECK(back && bad == 0, "%s: %zu heights differ after reading back", what, bad);
            free(back);
        }
    }
    /* The 65 x 65 field: vertex and face counts with stride 3 (ceil(64/3) + 1 = 23 per side). */
    frt_write_desc wd = {0};
    wd.mesh_stride = 3;
    char err[512];
    CHECK(frt_write_heightfield(path_in("s3.obj"), field, 65, 65, &wd, err, sizeof err) == FRT_SUCCESS, "%s", err);
    CHECK(frt_write_heightfield(path_in("s3.ply"), field, 65, 65, &wd, err, sizeof err) == FRT_SUCCESS, "%s", err);
    mesh mo, mp;
    CHECK(parse_obj(path_in("s3.obj"), &mo) && parse_ply(path_in("s3.ply"), &mp), "stride-3 meshes parse");
    CHECK(mo.nv == 23 * 23 && mo.nf == 2 * 22 * 22 && mp.nv == mo.nv && mp.nf == mo.nf &&
              memcmp(mo.v, mp.v, mo.nv * 12) == 0 && memcmp(mo.vn, mp.vn, mo.nv * 12) == 0,
          "stride 3: %zu vertices, %zu faces, OBJ and PLY agree", mo.nv, mo.nf);
    mesh_free(&mo), mesh_free(&mp);
    /* One-point and one-row fields. */
    float one = 2.5f, row5[5] = {1, 2, 3, 4, 5};
    frt_field_info info;
    float back[5];
    CHECK(frt_write_heightfield(path_in("one.ply"), &one, 1, 1, NULL, err, sizeof err) == FRT_SUCCESS &&
              frt_read_heightfield(path_in("one.ply"), back, 5, &info, err, sizeof err) == FRT_SUCCESS &&
              info.width == 1 && info.height == 1 && back[0] == 2.5f,
          "a 1 x 1 mesh: %s", err);
    CHECK(frt_write_heightfield(path_in("row.obj"), row5, 5, 1, NULL, err, sizeof err) == FRT_SUCCESS &&
              frt_read_heightfield(path_in("row.obj"), back, 5, &info, err, sizeof err) == FRT_SUCCESS &&
              info.width == 5 && info.height == 1 && memcmp(back, row5, sizeof row5) == 0,
          "a 5 x 1 mesh: %s", err);
}

/* ---- files written by other tools ---- */

static void write_png_raw(const char *p, uint32_t w, uint32_t h, int depth, int color, int interlace,
                          const uint8_t *rows, size_t row_bytes, const png_color *palette, int n_palette)
{
    FILE *f = fopen(p, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!f || setjmp(png_jmpbuf(png))) {
        CHECK(0, "libpng could not write %s", p);
        return;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, w, h, depth, color, interlace, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (palette)
        png_set_PLTE(png, info, palette, n_palette);
    png_write_info(png, info);
    int passes = png_set_interlace_handling(png);
    for (int pass = 0; pass < passes; ++pass)
        for (uint32_t y = 0; y < h; ++y)
            png_write_row(png, rows + y * row_bytes);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    fclose(f);
}

static void expect_values(const char *what, const char *p, uint32_t w, uint32_t h, uint32_t bits, const float *want)
{
    frt_field_info info;
    frt_result r;
    char err[512];
    float *back = read_field(p, &info, &r, err, sizeof err);
    CHECK(back && info.width == w && info.height == h && (bits == 0 || info.bits == bits) && !info.has_range &&
              !info.has_terrain,
          "%s: %s (%u x %u, %u bits)", what, err, info.width, info.height, info.bits);
    if (back) {
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)w * h; ++i)
            bad += back[i] != want[i];
        CHECK(bad == 0, "%s: %zu values differ", what, bad);
    }
    free(back);
}

static void test_foreign_png(void)
{
    /* 8-bit grey without text chunks: raw sample values. */
    uint8_t g8[4 * 3];
    float want[4 * 3];
    for (int i = 0; i < 12; ++i)
        g8[i] = (uint8_t)(i * 20), want[i] = (float)(i * 20);
    write_png_raw(path_in("g8.png"), 4, 3, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, g8, 4, NULL, 0);
    expect_values("8-bit grey PNG", path_in("g8.png"), 4, 3, 8, want);
    /* RGB with R = G = B: luminance is the common value. */
    uint8_t rgb[4 * 3 * 3];
    for (int i = 0; i < 12; ++i)
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g8[i];
    write_png_raw(path_in("rgb.png"), 4, 3, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, rgb, 12, NULL, 0);
    expect_values("RGB PNG", path_in("rgb.png"), 4, 3, 8, want);
    /* 16-bit grey + alpha, Adam7-interlaced: alpha dropped, samples kept. */
    uint8_t ga[9 * 9 * 4];
    float want16[81];
    for (int i = 0; i < 81; ++i) {
        uint32_t q = (uint32_t)i * 800u;
        ga[4 * i] = (uint8_t)(q >> 8), ga[4 * i + 1] = (uint8_t)q, ga[4 * i + 2] = 0x12, ga[4 * i + 3] = 0x34;
        want16[i] = (float)q;
    }
    write_png_raw(path_in("ga16.png"), 9, 9, 16, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_INTERLACE_ADAM7, ga, 36, NULL, 0);
    expect_values("16-bit grey+alpha interlaced PNG", path_in("ga16.png"), 9, 9, 16, want16);
    /* 2-bit grey: expanded to 8 bits by bit replication (0, 85, 170, 255). */
    uint8_t g2[3] = {0x1B, 0xE4, 0x00}; /* 00 01 10 11 | 11 10 01 00 | ... */
    float want2[12] = {0, 85, 170, 255, 255, 170, 85, 0, 0, 0, 0, 0};
    write_png_raw(path_in("g2.png"), 4, 3, 2, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, g2, 1, NULL, 0);
    expect_values("2-bit grey PNG", path_in("g2.png"), 4, 3, 8, want2);
    /* A grey palette. */
    png_color pal[4] = {{0, 0, 0}, {60, 60, 60}, {120, 120, 120}, {240, 240, 240}};
    uint8_t idx[2] = {0x01, 0x23}; /* 4-bit indices: 0 1 | 2 3 */
    float wantp[4] = {0, 60, 120, 240};
    write_png_raw(path_in("pal.png"), 2, 2, 4, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, idx, 1, pal, 4);
    expect_values("4-bit palette PNG", path_in("pal.png"), 2, 2, 8, wantp);
}

static void test_foreign_pgm(void)
{
    float want[6] = {0, 1, 999, 1000, 7, 500};
    const char p2[] = "P2\n# made by hand\n3 # width\n# height next\n2\n1000\n0 1 999\n1000 7\n500\n";
    write_all(path_in("a.pgm"), p2, sizeof p2 - 1);
    expect_values("P2 with comments, maxval 1000", path_in("a.pgm"), 3, 2, 16, want);
    uint8_t p5[64];
    int n = snprintf((char *)p5, sizeof p5, "P5 3 2 1000\n");
    for (int i = 0; i < 6; ++i)
        p5[n + 2 * i] = (uint8_t)((int)want[i] >> 8), p5[n + 2 * i + 1] = (uint8_t)((int)want[i] & 0xff);
    write_all(path_in("b.pgm"), p5, (size_t)n + 12);
    expect_values("P5 maxval 1000 (big-endian)", path_in("b.pgm"), 3, 2, 16, want);
    float want8[4] = {0, 17, 200, 255};
    const uint8_t p5b[] = {'P', '5', '\n', '2', ' ', '2', '\n', '2', '5', '5', '\n', 0, 17, 200, 255};
    write_all(path_in("c.pgm"), p5b, sizeof p5b);
    expect_values("P5 8-bit", path_in("c.pgm"), 2, 2, 8, want8);
    /* A sample above maxval is an error. */
    const char bad[] = "P2 2 1 10 3 11\n";
    write_all(path_in("d.pgm"), bad, sizeof bad - 1);
    frt_field_info info;
    frt_result r;
    char err[512];
    float *back = read_field(path_in("d.pgm"), &info, &r, err, sizeof err);
    CHECK(!back && r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "maxval"), "sample above maxval: %s", err);
    free(back);
}

/* A .npy with header dict `dict` (version major) followed by `data`. */
static void write_npy(const char *p, int major, const char *dict, const void *data, size_t n)
{
    uint8_t b[512];
    size_t len = strlen(dict), pre = major == 1 ? 10 : 12;
    memcpy(b, "\x93NUMPY", 6);
    b[6] = (uint8_t)major, b[7] = 0;
    b[8] = (uint8_t)len, b[9] = (uint8_t)(len >> 8), b[10] = b[11] = 0;
    memcpy(b + pre, dict, len);
    memcpy(b + pre + len, data, n);
    write_all(p, b, pre + len + n);
}

static void test_foreign_npy(void)
{
    float want[6] = {-1.5f, 0, 2, 3.25f, 100, -7};
    double f8[6];
    uint8_t f4be[24];
    for (int i = 0; i < 6; ++i) {
        f8[i] = want[i];
        uint32_t u;
        memcpy(&u, &want[i], 4);
        for (int k = 0; k < 4; ++k)
            f4be[4 * i + k] = (uint8_t)(u >> (24 - 8 * k));
    }
    write_npy(path_in("f8.npy"), 1, "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }\n", f8, sizeof f8);
    expect_values("'<f8'", path_in("f8.npy"), 3, 2, 64, want);
    write_npy(path_in("f4be.npy"), 2, "{'descr': '>f4', 'fortran_order': False, 'shape': (2, 3)}\n", f4be, 24);
    expect_values("'>f4' version 2.0", path_in("f4be.npy"), 3, 2, 32, want);
    /* Fortran order: column-major data, transposed on reading. */
    float colmajor[6] = {want[0], want[3], want[1], want[4], want[2], want[5]};
    write_npy(path_in("fo.npy"), 3, "{\"descr\": \"<f4\", \"fortran_order\": True, \"shape\": (2, 3), }   \n", colmajor,
              24);
    expect_values("fortran_order True, version 3.0", path_in("fo.npy"), 3, 2, 32, want);
    uint8_t u1[6] = {0, 1, 2, 250, 255, 7};
    float want_u1[6] = {0, 1, 2, 250, 255, 7};
    write_npy(path_in("u1.npy"), 1, "{'descr': '|u1', 'fortran_order': False, 'shape': (3, 2), }\n", u1, 6);
    expect_values("'|u1'", path_in("u1.npy"), 2, 3, 8, want_u1);
    uint8_t u2be[4] = {0x01, 0x02, 0xff, 0xff}, i2le[4] = {0xfe, 0xff, 0x10, 0x00},
            i4le[8] = {0xff, 0xff, 0xff, 0xff, 1, 0, 0, 0};
    float want_u2[2] = {258, 65535}, want_i2[2] = {-2, 16}, want_i4[2] = {-1, 1};
    write_npy(path_in("u2.npy"), 1, "{'descr': '>u2', 'fortran_order': False, 'shape': (1, 2), }\n", u2be, 4);
    expect_values("'>u2'", path_in("u2.npy"), 2, 1, 16, want_u2);
    write_npy(path_in("i2.npy"), 1, "{'descr': '<i2', 'fortran_order': False, 'shape': (2, 1), }\n", i2le, 4);
    expect_values("'<i2'", path_in("i2.npy"), 1, 2, 16, want_i2);
    write_npy(path_in("i4.npy"), 1, "{'descr': '<i4', 'fortran_order': False, 'shape': (1, 2), }\n", i4le, 8);
    expect_values("'<i4'", path_in("i4.npy"), 2, 1, 32, want_i4);
    /* Refused: 3-D, 1-D, an unknown dtype, a header longer than the file, trailing data. */
    static const struct {
        const char *dict;
        size_t n;
        frt_result r;
        const char *says;
    } bad[] = {
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2, 3), }\n", 24, FRT_ERROR_INVALID_ARGUMENT, "2-D"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (6,), }\n", 24, FRT_ERROR_INVALID_ARGUMENT, "2-D"},
        {"{'descr': '<c8', 'fortran_order': False, 'shape': (2, 3), }\n", 48, FRT_ERROR_INVALID_ARGUMENT, "dtype"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }\n", 20, FRT_ERROR_IO, "24 bytes"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }\n", 28, FRT_ERROR_INVALID_ARGUMENT, "24 bytes"},
        {"{'descr': '<f4', 'fortran_order': Maybe, 'shape': (2, 3), }\n", 24, FRT_ERROR_INVALID_ARGUMENT, "dict"}};
    uint8_t zeros[64] = {0};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        write_npy(path_in("bad.npy"), 1, bad[i].dict, zeros, bad[i].n);
        frt_field_info info;
        char err[512];
        frt_result r = frt_read_heightfield_info(path_in("bad.npy"), &info, err, sizeof err);
        CHECK(r == bad[i].r && strstr(err, bad[i].says) && message_ok(err, path_in("bad.npy")), "bad npy %zu: %d %s", i,
              (int)r, err);
    }
}

static void test_foreign_meshes(void)
{
    /* An OBJ from another tool: no fracterra comments, rounded coordinates, plain "f a b c" faces with negative
     * (relative) indices, texture coordinates and groups. */
    const char obj[] = "o terrain\ng ground\nv 0 10 1.5\nv 5.0000001 10 2\nv 10 10 2.5\nvt 0 0\n"
                       "v 0 5 3\nv 5 4.9999999 3.5\nv 10 5 4\nf -6 -3 -5\nf 2 5 3\ns off\n";
    write_all(path_in("other.obj"), obj, sizeof obj - 1);
    float want[6] = {1.5f, 2, 2.5f, 3, 3.5f, 4};
    expect_values("OBJ from another tool", path_in("other.obj"), 3, 2, 32, want);
    frt_field_info info;
    char err[512];
    CHECK(frt_read_heightfield_info(path_in("other.obj"), &info, err, sizeof err) == FRT_SUCCESS &&
              fabs(info.spacing_x - 5) < 1e-6 && info.spacing_y == 5,
          "spacing inferred: %g %g", info.spacing_x, info.spacing_y);
    /* Not a grid: a row that does not line up. */
    const char skew[] = "v 0 1 0\nv 1 1 0\nv 0.5 0 0\nv 1.5 0 0\n";
    write_all(path_in("skew.obj"), skew, sizeof skew - 1);
    frt_result r = frt_read_heightfield_info(path_in("skew.obj"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "not a regular grid mesh"), "skewed grid: %s", err);
    const char face[] = "v 0 1 0\nv 1 1 0\nv 0 0 0\nf 1 2 4\n";
    write_all(path_in("face.obj"), face, sizeof face - 1);
    r = frt_read_heightfield_info(path_in("face.obj"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "line 4") && strstr(err, "vertex 4"), "bad face: %s", err);

    /* ascii PLY with doubles, an extra colour property, and faces. */
    const char ply[] = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 4\r\n"
                       "property double x\r\nproperty uchar red\r\nproperty double y\r\nproperty double z\r\n"
                       "element face 2\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                       "0 255 1 7\r\n1 0 1 8\r\n0 0 0 9\r\n1 0 0 10.5\r\n3 2 3 1\r\n3 2 1 0\r\n";
    write_all(path_in("a.ply"), ply, sizeof ply - 1);
    float want4[4] = {7, 8, 9, 10.5f};
    expect_values("ascii PLY with doubles and colours", path_in("a.ply"), 2, 2, 64, want4);
    /* binary big-endian PLY with float64 x y z. */
    uint8_t be[256];
    int n = snprintf((char *)be, sizeof be,
                     "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float64 x\nproperty float64 y\n"
                     "property float64 z\nend_header\n");
    double coords[6] = {0, 0, -3, 2, 0, 4.75};
    for (int i = 0; i < 6; ++i) {
        uint64_t u;
        memcpy(&u, &coords[i], 8);
        for (int k = 0; k < 8; ++k)
            be[n + 8 * i + k] = (uint8_t)(u >> (56 - 8 * k));
    }
    write_all(path_in("be.ply"), be, (size_t)n + 48);
    float want2[2] = {-3, 4.75f};
    expect_values("binary big-endian PLY", path_in("be.ply"), 2, 1, 64, want2);
    /* A face index beyond the vertices. */
    const char badply[] =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n3 0 1 2\n";
    write_all(path_in("bad.ply"), badply, sizeof badply - 1);
    r = frt_read_heightfield_info(path_in("bad.ply"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "vertex 2 of 2"), "face index out of range: %s", err);
}

/* ---- failures ---- */

static void test_read_failures(void)
{
    char err[512];
    frt_field_info info;
    const char *p = path_in("missing.png");
    frt_result r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && message_ok(err, p) && strstr(err, "No such file"), "missing file: %s", err);
    mkdir(path_in("adir.png"), 0755);
    p = path_in("adir.png");
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && message_ok(err, p) && strstr(err, "directory"), "a directory: %s", err);
    p = path_in("x.xyz");
    write_all(p, "x", 1);
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && message_ok(err, p) && strstr(err, ".png, .pgm, .f32, .npy, .obj, .ply or .tif"),
          "unknown extension: %s", err);
    char under_file[300];
    write_all(path_in("plain.txt"), "x", 1);
    snprintf(under_file, sizeof under_file, "%s/x.png", path_in("plain.txt"));
    r = frt_read_heightfield_info(under_file, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && message_ok(err, under_file) && strstr(err, "Not a directory"), "unreachable path: %s",
          err);
    mkfifo(path_in("fifo.pgm"), 0644);
    r = frt_read_heightfield_info(path_in("fifo.pgm"), &info, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && strstr(err, "not a regular file"), "a FIFO is refused without waiting: %s", err);
    /* Unreadable: root reads anything, so only as another user. */
    if (geteuid() != 0) {
        p = path_in("secret.npy");
        write_all(p, "x", 1);
        chmod(p, 0);
        r = frt_read_heightfield_info(p, &info, err, sizeof err);
        CHECK(r == FRT_ERROR_IO && strstr(err, "Permission denied"), "unreadable: %s", err);
    }
    /* The sidecar: wrong size (both ways), missing, not JSON, no size. */
    size_t n;
    uint8_t *data = read_all(path_in("rt.f32"), &n);
    char side_p[300];
    snprintf(side_p, sizeof side_p, "%s", path_in("side.f32"));
    p = side_p;
    write_all(p, data, 4000);
    const char small[] = "{ \"width\": 33, \"height\": 33 }";
    write_all(path_in("side.f32.json"), small, sizeof small - 1);
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    char want[400];
    snprintf(want, sizeof want, "'%s' has 4000 bytes but its sidecar says 33 x 33 (4356 bytes)", p);
    CHECK(r == FRT_ERROR_IO && strcmp(err, want) == 0, "short data: %s", err);
    write_all(p, data, n);
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "16900 bytes but its sidecar says 33 x 33"), "long data: %s",
          err);
    write_all(path_in("side.f32.json"), "{\"width\": 65, \"height\": ", 23);
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && message_ok(err, p) && strstr(err, "JSON"), "broken sidecar: %s", err);
    write_all(path_in("side.f32.json"), "{\"width\": 65.5, \"height\": 65}", 30);
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "whole numbers"), "fractional width: %s", err);
    write_all(path_in("side.f32.json"), "{\"levels\": 6}", 13);
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "no width and height"), "no size: %s", err);
    unlink(path_in("side.f32.json"));
    r = frt_read_heightfield_info(p, &info, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && message_ok(err, p) && strstr(err, "sidecar") && strstr(err, "No such file"),
          "missing sidecar: %s", err);
    free(data);

    /* Truncated files of every format; and an output one float short is refused without a write beyond it. */
    static const char *names[] = {"rt16.png", "rt8.pgm", "rt.f32", "rt.npy", "rt.obj", "rt.ply"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        float *out = check_alloc(sizeof field);
        out[65 * 65 - 1] = 12345.0f;
        r = frt_read_heightfield(path_in(names[i]), out, 65 * 65 - 1, &info, err, sizeof err);
        CHECK(r == FRT_ERROR_BUFFER_TOO_SMALL && out[65 * 65 - 1] == 12345.0f && strstr(err, "65 x 65"),
              "%s: output too small: %d %s", names[i], (int)r, err);
        free(out);
        uint8_t *b = read_all(path_in(names[i]), &n);
        char cut[64];
        snprintf(cut, sizeof cut, "cut-%s", names[i]);
        if (strcmp(names[i], "rt.f32") == 0) {
            size_t side_n;
            uint8_t *side = read_all(path_in("rt.f32.json"), &side_n);
            write_all(path_in("cut-rt.f32.json"), side, side_n);
            free(side);
        }
        write_all(path_in(cut), b, n / 2);
        r = frt_read_heightfield_info(path_in(cut), &info, err, sizeof err);
        if (r == FRT_SUCCESS) { /* a mesh cut at a line may still be a smaller grid; its data must then fail */
            float *o = check_alloc(sizeof field);
            r = frt_read_heightfield(path_in(cut), o, 65 * 65, &info, err, sizeof err);
            free(o);
        }
        CHECK(r == FRT_ERROR_IO && message_ok(err, path_in(cut)), "%s cut in half: %d %s", names[i], (int)r, err);
        free(b);
    }
    /* An empty file of every format. */
    for (int f = FRT_FILE_PNG; f <= FRT_FILE_PLY; ++f) {
        char name[32];
        snprintf(name, sizeof name, "empty.%s", frt_file_format_name((frt_file_format)f));
        write_all(path_in(name), "", 0);
        if (f == FRT_FILE_F32)
            write_all(path_in("empty.f32.json"), "{\"width\": 1, \"height\": 1}", 26);
        r = frt_read_heightfield_info(path_in(name), &info, err, sizeof err);
        CHECK(r != FRT_SUCCESS && message_ok(err, path_in(name)), "%s: %d %s", name, (int)r, err);
    }
}

static void test_write_failures(void)
{
    char err[512];
    float h[4] = {1, 2, 3, 4};
    frt_write_desc wd = {0};
    frt_result r;
    /* Bad arguments. */
    wd.bits = 12;
    r = frt_write_heightfield(path_in("b.png"), h, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "bits"), "bits 12: %s", err);
    wd.bits = 0, wd.spacing_x = -1;
    r = frt_write_heightfield(path_in("b.obj"), h, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "spacing"), "negative spacing: %s", err);
    wd.spacing_x = 0, wd.z_scale = NAN;
    r = frt_write_heightfield(path_in("b.ply"), h, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "z_scale"), "NaN z_scale: %s", err);
    frt_terrain_desc bad_terrain = {0};
    bad_terrain.hurst = 2;
    wd.z_scale = 0, wd.terrain = &bad_terrain;
    r = frt_write_heightfield(path_in("b.f32"), h, 2, 2, &wd, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "terrain"), "bad terrain: %s", err);
    r = frt_write_heightfield(path_in("b.png"), h, 0, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT, "width 0: %s", err);
    r = frt_write_heightfield(path_in("b.xyz"), h, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, ".png, .pgm, .f32, .npy, .obj, .ply or .tif"),
          "unknown extension: %s", err);
    r = frt_write_picture(path_in("pic.png"), (const uint8_t *)"abcd", 2, 2, 2, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT, "picture with 2 channels: %s", err);
    /* Unwritable places: a missing directory, a file as directory, a directory as target. */
    r = frt_write_heightfield("/nonexistent-dir/x.png", h, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && strstr(err, "/nonexistent-dir/x.png") && strstr(err, "No such file"),
          "missing directory: %s", err);
    write_all(path_in("plain.txt"), "x", 1);
    char p[300];
    snprintf(p, sizeof p, "%s/x.npy", path_in("plain.txt"));
    r = frt_write_heightfield(p, h, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && strstr(err, "Not a directory"), "a file as directory: %s", err);
    mkdir(path_in("dir.pgm"), 0755);
    r = frt_write_heightfield(path_in("dir.pgm"), h, 2, 2, NULL, err, sizeof err);
    CHECK(r == FRT_ERROR_IO && strstr(err, "directory"), "a directory as target: %s", err);
    /* Old output intact: a failed write to an existing file leaves its bytes. */
    write_all(path_in("keep.png"), "precious", 8);
    wd = (frt_write_desc){0};
    wd.bits = 7;
    r = frt_write_heightfield(path_in("keep.png"), h, 2, 2, &wd, err, sizeof err);
    size_t n;
    uint8_t *b = read_all(path_in("keep.png"), &n);
    CHECK(r != FRT_SUCCESS && b && n == 8 && memcmp(b, "precious", 8) == 0, "failed write leaves the old file");
    free(b);
    /* .f32 whose sidecar cannot be written: neither file is replaced. */
    write_all(path_in("keep.f32"), "old data", 8);
    mkdir(path_in("keep.f32.json"), 0755);
    r = frt_write_heightfield(path_in("keep.f32"), h, 2, 2, NULL, err, sizeof err);
    b = read_all(path_in("keep.f32"), &n);
    CHECK(r == FRT_ERROR_IO && strstr(err, "keep.f32.json") && b && n == 8 && memcmp(b, "old data", 8) == 0,
          "unwritable sidecar leaves the data file: %s", err);
    free(b);
    /* A read-only directory (again only as another user than root). */
    if (geteuid() != 0) {
        mkdir(path_in("ro"), 0755);
        write_all(path_in("ro/old.npy"), "old", 3);
        chmod(path_in("ro"), 0555);
        r = frt_write_heightfield(path_in("ro/old.npy"), h, 2, 2, NULL, err, sizeof err);
        CHECK(r == FRT_ERROR_IO && strstr(err, "Permission denied") && file_size(path_in("ro/old.npy")) == 3,
              "read-only directory: %s", err);
        chmod(path_in("ro"), 0755);
    }
    /* A full disk: every writer reports the failed write with its cause (the rename never happens then). */
    for (int f = FRT_FILE_PNG; f <= FRT_FILE_PLY; ++f) {
        FILE *full = fopen("/dev/full", "wb");
        if (!full)
            break;
        frt_field_out fo;
        wd = (frt_write_desc){0};
        wd.format = (frt_file_format)f;
        CHECK(frt_field_out_init(&fo, "full", field, 65, 65, &wd, err, sizeof err) == FRT_SUCCESS, "%s", err);
        r = frt_write_stream(full, &fo, err, sizeof err);
        CHECK(r == FRT_ERROR_IO && strstr(err, "No space left on device") && message_ok(err, "full"),
              "%s on a full disk: %d %s", frt_file_format_name((frt_file_format)f), (int)r, err);
        fclose(full);
    }
    CHECK(temp_files_left() == 0, "no temporary files left in %s", dir);
}

static void test_atomic(void)
{
    char err[256];
    const char *p = path_in("keep.npy");
    write_all(p, "precious", 8);
    frt_atomic_file af;
    CHECK(frt_atomic_open(&af, p, err, sizeof err) == FRT_SUCCESS, "%s", err);
    fputs("partial", af.fp);
    frt_atomic_abort(&af);
    CHECK(file_size(p) == 8, "an aborted write leaves the old file");
    CHECK(frt_atomic_open(&af, "/nonexistent-dir/x.png", err, sizeof err) == FRT_ERROR_IO, "missing directory");
    CHECK(strstr(err, "/nonexistent-dir/x.png") && strstr(err, "No such file"), "message: %s", err);
    CHECK(frt_atomic_open(&af, dir, err, sizeof err) == FRT_ERROR_IO && strstr(err, "directory"), "a directory: %s",
          err);
    CHECK(temp_files_left() == 0, "no temporary files left in %s", dir);
}

/* ---- robustness: every truncation and seeded random mutations of a small file of each format ---- */

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint32_t rng(void)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 11);
}

/* Reads `data` as `format` from memory; true when the reader returned cleanly (success, or a message). */
static bool read_clean(frt_file_format format, const uint8_t *data, size_t n, const char *sidecar, bool *ok)
{
    FILE *fp = fmemopen((void *)data, n, "rb");
    if (!fp)
        return true;
    char err[512];
    frt_field_info info;
    frt_result r = frt_read_stream(fp, format, sidecar, "mem", &info, NULL, 0, err, sizeof err);
    bool clean = r == FRT_SUCCESS || message_ok(err, "mem");
    uint64_t points = (uint64_t)info.width * info.height;
    if (r == FRT_SUCCESS && points <= (1u << 20)) {
        float *out = check_alloc((size_t)points * sizeof *out + 1);
        r = frt_read_stream(fp, format, sidecar, "mem", &info, out, (size_t)points, err, sizeof err);
        clean &= r == FRT_SUCCESS || message_ok(err, "mem");
        free(out);
    }
    *ok = r == FRT_SUCCESS;
    fclose(fp);
    return clean;
}

static void test_robustness(void)
{
    float small[6 * 5];
    for (int i = 0; i < 30; ++i)
        small[i] = (float)((i * 7919) % 31) * 0.125f - 1.0f;
    for (int f = FRT_FILE_PNG; f <= FRT_FILE_PLY; ++f) {
        char name[32], err[512];
        snprintf(name, sizeof name, "small.%s", frt_file_format_name((frt_file_format)f));
        frt_write_desc wd = {0};
        wd.terrain = &terrain;
        wd.device = "dev";
        CHECK(frt_write_heightfield(path_in(name), small, 6, 5, &wd, err, sizeof err) == FRT_SUCCESS, "%s", err);
        size_t n, side_n = 0;
        uint8_t *data = read_all(path_in(name), &n), *side = NULL;
        if (f == FRT_FILE_F32) {
            snprintf(name, sizeof name, "small.f32.json");
            side = read_all(path_in(name), &side_n);
            side[side_n] = 0;
        }
        bool ok, all_clean = true;
        size_t successes = 0;
        all_clean &= read_clean((frt_file_format)f, data, n, (char *)side, &ok);
        CHECK(ok, "%s: the whole file reads", name);
        for (size_t len = 0; len < n; ++len) {
            all_clean &= read_clean((frt_file_format)f, data, len, (char *)side, &ok);
            successes += ok;
        }
        uint8_t *m = check_alloc(n + side_n + 1);
        size_t mutated_ok = 0;
        for (int k = 0; k < ROBUST_MUTATIONS; ++k) {
            bool in_side = side && rng() % 2;
            uint8_t *t = in_side ? m + n : m;
            size_t tn = in_side ? side_n : n;
            memcpy(m, data, n);
            if (side)
                memcpy(m + n, side, side_n + 1);
            static const uint8_t special[] = {0, 0xff, 0x7f, 0x80, '0', '9', ' ', '\n', '#', '-', '.', 'e', ','};
            for (int j = 1 + (int)(rng() % 4); j > 0; --j) {
                size_t at = rng() % tn;
                switch (rng() % 3) {
                case 0: t[at] ^= (uint8_t)(1u << (rng() % 8)); break;
                case 1: t[at] = special[rng() % sizeof special]; break;
                default: t[at] = (uint8_t)rng(); break;
                }
            }
            if (in_side)
                m[n + side_n] = 0;
            all_clean &= read_clean((frt_file_format)f, m, n, side ? (char *)m + n : NULL, &ok);
            mutated_ok += ok;
        }
        CHECK(all_clean, "%s: every truncation and mutation returned success or a message", name);
        printf("%s: %zu bytes; %zu of %zu truncations and %zu of %d mutations read\n", name, n, successes, n,
               mutated_ok, ROBUST_MUTATIONS);
        free(m);
        free(data);
        free(side);
    }
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    double t0 = frt_now_seconds();
    frt_terrain_desc d = {0};
    d.levels = 6, d.hurst = 0.5, d.seed = UINT64_MAX;
    frt_terrain_desc_resolved(&d, &terrain);
    CHECK(frt_generate_cpu(&terrain, field, 65 * 65, NULL) == FRT_SUCCESS, "generate");
    test_extensions();
    test_round_trips();
    test_png_by_libpng(16);
    test_png_by_libpng(8);
    test_npy_layout();
    test_sidecar();
    test_region_metadata();
    test_pgm_layout();
    test_meshes();
    test_foreign_png();
    test_foreign_pgm();
    test_foreign_npy();
    test_foreign_meshes();
    test_read_failures();
    test_write_failures();
    test_atomic();
    test_robustness();
    printf("%.2f s\n", frt_now_seconds() - t0);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK(system(cmd) == 0, "cleanup");
    return check_summary("test_formats");
}
