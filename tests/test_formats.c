/* test_formats.c — host/format_*.c, formats.c, atomic_file.c: each format read back by an independent reader
 * (libpng for PNG, a strict parser for NPY), the sidecar, and the all-or-nothing file writes. */
#include "check.h"

#include <png.h>
#include <unistd.h>

static char dir[] = "/tmp/frt_formats_XXXXXX";

static char *path_in(const char *name)
{
    static char buf[256];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

static long file_size(const char *p)
{
    FILE *f = fopen(p, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

static void test_png(const float *h, uint32_t w, uint32_t ht, const frt_field_meta *m)
{
    frt_atomic_file af;
    char err[256];
    CHECK(frt_atomic_open(&af, path_in("t.png"), err, sizeof err) == FRT_SUCCESS, "%s", err);
    CHECK(frt_write_png16(af.fp, h, w, ht, m, err, sizeof err) == FRT_SUCCESS, "%s", err);
    CHECK(frt_atomic_commit(&af, err, sizeof err) == FRT_SUCCESS, "%s", err);

    FILE *f = fopen(path_in("t.png"), "rb");
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!f || setjmp(png_jmpbuf(png))) {
        CHECK(0, "libpng could not read the file");
        return;
    }
    png_init_io(png, f);
    png_read_info(png, info);
    CHECK(png_get_image_width(png, info) == w && png_get_image_height(png, info) == ht, "PNG size");
    CHECK(png_get_bit_depth(png, info) == 16 && png_get_color_type(png, info) == PNG_COLOR_TYPE_GRAY, "16-bit grey");
    png_textp text;
    int ntext = 0;
    png_get_text(png, info, &text, &ntext);
    bool have_min = false, have_params = false;
    for (int i = 0; i < ntext; ++i) {
        if (strcmp(text[i].key, "fracterra:min") == 0)
            have_min = fabs(strtod(text[i].text, NULL) - m->min) <= 1e-6 * fabs(m->min);
        if (strcmp(text[i].key, "fracterra:params") == 0)
            have_params = strstr(text[i].text, "\"hurst\": 0.5") != NULL;
    }
    CHECK(have_min && have_params, "text chunks carry min and the parameters");
    uint8_t *row = check_alloc((size_t)w * 2);
    size_t bad = 0;
    uint16_t lo = 65535, hi = 0;
    double scale = (m->max - m->min) / 65535.0;
    for (uint32_t y = 0; y < ht; ++y) {
        png_read_row(png, row, NULL);
        for (uint32_t x = 0; x < w; ++x) {
            uint16_t q = (uint16_t)(row[2 * x] << 8 | row[2 * x + 1]);
            lo = q < lo ? q : lo;
            hi = q > hi ? q : hi;
            /* within half a quantum (+ float slack) of the true height */
            bad += fabs(m->min + q * scale - h[(size_t)y * w + x]) > 0.5 * scale * 1.001;
        }
    }
    CHECK(bad == 0 && lo == 0 && hi == 65535, "PNG samples: %zu off by > half a quantum, range %u..%u", bad, lo, hi);
    free(row);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
}

static void test_npy_f32(const float *h, uint32_t w, uint32_t ht, const frt_field_meta *m)
{
    char err[256];
    frt_atomic_file af;
    CHECK(frt_atomic_open(&af, path_in("t.npy"), err, sizeof err) == FRT_SUCCESS, "%s", err);
    CHECK(frt_write_npy(af.fp, h, w, ht) == FRT_SUCCESS, "npy");
    CHECK(frt_atomic_commit(&af, err, sizeof err) == FRT_SUCCESS, "%s", err);
    FILE *f = fopen(path_in("t.npy"), "rb");
    uint8_t pre[10];
    CHECK(f && fread(pre, 1, 10, f) == 10 && memcmp(pre, "\x93NUMPY\x01\x00", 8) == 0, "NPY magic, v1.0");
    size_t hl = (size_t)pre[8] | (size_t)pre[9] << 8;
    CHECK((10 + hl) % 64 == 0, "data aligned to 64 bytes (header %zu)", hl);
    char *hdr = check_alloc(hl + 1);
    CHECK(fread(hdr, 1, hl, f) == hl, "header");
    hdr[hl] = 0;
    char want[64];
    snprintf(want, sizeof want, "'shape': (%u, %u)", ht, w);
    CHECK(strstr(hdr, "'descr': '<f4'") && strstr(hdr, "'fortran_order': False") && strstr(hdr, want) &&
              hdr[hl - 1] == '\n',
          "header dict: %s", hdr);
    float *back = check_alloc((size_t)w * ht * 4);
    CHECK(fread(back, 4, (size_t)w * ht, f) == (size_t)w * ht && fgetc(f) == EOF, "payload size");
    CHECK(memcmp(back, h, (size_t)w * ht * 4) == 0, "NPY floats identical");
    fclose(f);
    free(hdr);

    CHECK(frt_atomic_open(&af, path_in("t.f32"), err, sizeof err) == FRT_SUCCESS, "%s", err);
    CHECK(frt_write_f32(af.fp, h, (size_t)w * ht) == FRT_SUCCESS, "f32");
    CHECK(frt_atomic_commit(&af, err, sizeof err) == FRT_SUCCESS, "%s", err);
    f = fopen(path_in("t.f32"), "rb");
    CHECK(f && fread(back, 4, (size_t)w * ht, f) == (size_t)w * ht && fgetc(f) == EOF, "f32 size");
    CHECK(memcmp(back, h, (size_t)w * ht * 4) == 0, "f32 floats identical");
    fclose(f);
    free(back);

    char *json = frt_meta_json(m, w, ht);
    CHECK(json && strstr(json, "\"width\": 65") && strstr(json, "\"seed\": 18446744073709551615") &&
              strstr(json, "\"device\": \"quote\\\" back\\\\slash\""),
          "sidecar JSON: %s", json);
    free(json);
    char *sc = frt_sidecar_path("a/b.f32");
    CHECK(strcmp(sc, "a/b.f32.json") == 0, "sidecar path %s", sc);
    free(sc);
}

static void test_atomic(void)
{
    char err[256];
    const char *p = path_in("keep.npy");
    FILE *f = fopen(p, "wb");
    fputs("precious", f);
    fclose(f);
    frt_atomic_file af;
    CHECK(frt_atomic_open(&af, p, err, sizeof err) == FRT_SUCCESS, "%s", err);
    fputs("partial", af.fp);
    frt_atomic_abort(&af);
    CHECK(file_size(p) == 8, "an aborted write leaves the old file");
    CHECK(frt_atomic_open(&af, "/nonexistent-dir/x.png", err, sizeof err) == FRT_ERROR_IO, "missing directory");
    CHECK(strstr(err, "/nonexistent-dir/x.png") && strstr(err, "No such file"), "message: %s", err);
    CHECK(frt_atomic_open(&af, dir, err, sizeof err) == FRT_ERROR_IO && strstr(err, "directory"), "a directory: %s",
          err);
    /* No temporary files remain. */
    char cmd[300];
    snprintf(cmd, sizeof cmd, "ls %s | grep -c tmp- > /dev/null", dir);
    CHECK(system(cmd) != 0, "no temporary files left in %s", dir);
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    CHECK(frt_format_from_path("a.PNG") == FRT_FORMAT_PNG && frt_format_from_path("x.npy") == FRT_FORMAT_NPY &&
              frt_format_from_path("d.f32") == FRT_FORMAT_F32,
          "extensions");
    CHECK(frt_format_from_path("a.tif") == FRT_FORMAT_NONE && frt_format_from_path("dir.png/file") == FRT_FORMAT_NONE &&
              frt_format_from_path("noext") == FRT_FORMAT_NONE,
          "unknown extensions");
    frt_terrain_desc d = {0};
    d.levels = 6, d.hurst = 0.5, d.seed = UINT64_MAX;
    frt_terrain_desc_resolved(&d, &d);
    float h[65 * 65];
    CHECK(frt_generate_cpu(&d, h, 65 * 65, NULL) == FRT_SUCCESS, "generate");
    frt_field_meta m = {0};
    m.desc = d;
    m.backend = "cpu";
    m.device = "quote\" back\\slash";
    frt_field_minmax(h, 65 * 65, &m.min, &m.max);
    test_png(h, 65, 65, &m);
    test_npy_f32(h, 65, 65, &m);
    test_atomic();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK(system(cmd) == 0, "cleanup");
    return check_summary("test_formats");
}
