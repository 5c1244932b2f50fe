/* cli_info.c — `fracterra info FILE [--json] [--stats]`: what a heightfield file holds (format, size, recorded
 * parameters, georeferencing, and optionally the statistics of its heights), as aligned text or one JSON object. */
#include "cli.h"

#include <getopt.h>
#include <json-c/json.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Text mode: the key column is this wide ("geotransform:" is the longest key, plus one space). */
#define KEY_WIDTH 14
/* Text mode: a projection that is not recognisable WKT is shown as its first line, cut to this many characters. */
#define PROJECTION_TEXT_MAX 72

static void info_help(void)
{
    printf("Usage: fracterra info FILE [--json] [--stats]\n"
           "\n"
           "Prints what a heightfield file holds (.png .pgm .f32 .npy .obj .ply .tif): format, size, bits per\n"
           "sample, spacing, z scale, the backend and device that made it, the terrain parameters fracterra\n"
           "recorded (levels, hurst, dimension, sigma, seed, edge, region and the side of its grid, noise), and\n"
           "a GeoTIFF's geotransform, coordinate system and nodata value. Only the header is read, unless --stats.\n"
           "\n"
           "  --json              one JSON object instead of text lines; every key is always present, null\n"
           "                      where the file records nothing (keys: man fracterra, section info)\n"
           "  --stats             also read the heights: min, max, mean, standard deviation (of the finite\n"
           "                      heights, population: divided by their count) and the count of NaN\n"
           "                      (no-data) cells\n"
           "  -h, --help          this text\n");
}

/* ---- the file's contents, gathered once for both outputs ---- */

typedef struct field_stats {
    uint64_t valid, nans, infs;    /* finite, NaN and infinite cells */
    double min, max, mean, stddev; /* of the finite cells; meaningless when valid == 0 */
} field_stats;

/* Two passes in double: the mean, then the sum of squared deviations from it, which keeps the variance accurate
 * when the mean is large compared with the spread (a single pass of sum and sum of squares would cancel). */
static void compute_stats(const float *h, size_t count, field_stats *s)
{
    memset(s, 0, sizeof *s);
    double sum = 0.0;
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < count; ++i) {
        const float v = h[i];
        if (isnan(v)) {
            ++s->nans;
        } else if (isinf(v)) {
            ++s->infs;
        } else {
            ++s->valid;
            sum += v;
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    }
    if (!s->valid)
        return;
    s->min = lo;
    s->max = hi;
    s->mean = sum / (double)s->valid;
    double ss = 0.0;
    for (size_t i = 0; i < count; ++i)
        if (isfinite(h[i])) {
            const double d = (double)h[i] - s->mean;
            ss += d * d;
        }
    s->stddev = sqrt(ss / (double)s->valid);
}

static const char *edge_name(frt_edge e)
{
    return e == FRT_EDGE_PERIODIC ? "periodic" : "ffc";
}

/* D = 3 - H with 15 digits, as the writers record it, so that H = 0.8 shows D = 2.2 and not 2.2000000000000002. */
static const char *dimension_text(char buf[static 32], double hurst)
{
    snprintf(buf, 32, "%.15g", 3.0 - hurst);
    return buf;
}

/* ---- projection, short form for text ---- */

/* Copies the quoted string that starts at *p (after its opening quote) into buf; WKT doubles a quote inside a
 * string. Returns the character after the closing quote, or NULL when there is none. */
static const char *wkt_string(const char *p, char *buf, size_t n)
{
    size_t k = 0;
    for (; *p; ++p) {
        if (*p == '"') {
            if (p[1] != '"')
                break;
            ++p;
        }
        if (k + 1 < n)
            buf[k++] = *p;
    }
    buf[k] = '\0';
    return *p == '"' ? p + 1 : NULL;
}

/* "NAME (AUTH:CODE)" from WKT 1 or 2: NAME is the first quoted string after the outer keyword, AUTH:CODE the
 * outer object's own ID["AUTH",CODE] (WKT 2) or AUTHORITY["AUTH","CODE"] (WKT 1), the last one at bracket depth 1.
 * Anything else: the first line, cut to PROJECTION_TEXT_MAX characters. */
static void projection_summary(const char *wkt, char *out, size_t n)
{
    const char *p = wkt;
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        ++p;
    const char *kw = p;
    while ((*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '_')
        ++p;
    char name[256];
    if (!(p > kw && (p[0] == '[' || p[0] == '(') && p[1] == '"' && wkt_string(p + 2, name, sizeof name) && name[0])) {
        size_t k = strcspn(p = kw, "\r\n");
        if (k > PROJECTION_TEXT_MAX)
            snprintf(out, n, "%.*s...", PROJECTION_TEXT_MAX, p);
        else
            snprintf(out, n, "%.*s", (int)k, p);
        return;
    }
    /* WKT allows () as well as []; quoted strings may hold either */
    const char *id = NULL;
    int depth = 0;
    bool quoted = false;
    for (const char *q = kw; *q; ++q) {
        if (quoted) {
            if (*q == '"' && q[1] == '"')
                ++q;
            else if (*q == '"')
                quoted = false;
        } else if (*q == '"') {
            quoted = true;
        } else if (*q == '[' || *q == '(') {
            ++depth;
        } else if (*q == ']' || *q == ')') {
            --depth;
        } else if (depth == 1 && (q[-1] == ',' || q[-1] == ' ' || q[-1] == '\n') &&
                   (strncmp(q, "ID[\"", 4) == 0 || strncmp(q, "AUTHORITY[\"", 11) == 0)) {
            id = q;
        }
    }
    char auth[64] = "", code[64] = "";
    const char *after = id ? wkt_string(strchr(id, '"') + 1, auth, sizeof auth) : NULL;
    if (after && *after == ',') {
        ++after;
        if (*after == '"') {
            wkt_string(after + 1, code, sizeof code);
        } else {
            const size_t k = strcspn(after, ",])");
            snprintf(code, sizeof code, "%.*s", (int)(k < sizeof code ? k : sizeof code - 1), after);
        }
    }
    if (auth[0] && code[0])
        snprintf(out, n, "%s (%s:%s)", name, auth, code);
    else
        snprintf(out, n, "%s", name);
}

/* ---- text ---- */

static void line(const char *key, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void line(const char *key, const char *fmt, ...)
{
    char k[64];
    snprintf(k, sizeof k, "%s:", key);
    printf("%-*s", KEY_WIDTH, k);
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    putchar('\n');
}

static const char *nodata_text(char buf[static 32], double v)
{
    if (isnan(v))
        return "nan";
    if (isinf(v))
        return v > 0 ? "inf" : "-inf";
    return frt_double_text(buf, v);
}

static void print_text(const char *path, const frt_field_info *in, const field_stats *st)
{
    char a[32], b[32];
    line("file", "%s", path);
    line("format", "%s", frt_file_format_name(in->format));
    line("size", "%u x %u", in->width, in->height);
    line("bits", "%u", in->bits);
    if (in->has_range)
        line("range", "recorded (quantised samples map back to the heights)");
    line("spacing", "%s x %s", frt_double_text(a, in->spacing_x), frt_double_text(b, in->spacing_y));
    line("z_scale", "%s", frt_double_text(a, in->z_scale));
    if (in->backend[0])
        line("backend", "%s", in->backend);
    if (in->device[0])
        line("device", "%s", in->device);
    if (in->has_terrain) {
        const frt_terrain_desc *t = &in->terrain;
        line("levels", "%u", t->levels);
        line("hurst", "%s", frt_double_text(a, t->hurst));
        line("dimension", "%s", dimension_text(b, t->hurst));
        line("sigma", "%s", frt_double_text(a, t->sigma));
        line("seed", "%llu", (unsigned long long)t->seed);
        line("edge", "%s", edge_name(t->edge));
        if (frt_region_is_set(&t->region)) {
            line("region", "%u,%u,%u,%u", t->region.x, t->region.y, t->region.width, t->region.height);
            line("grid_side", "%u", frt_terrain_side(t));
        }
        line("noise", "%s", frt_noise_name(t->noise));
        if (frt_noise_has_param(t->noise))
            line("noise_param", "%s", frt_double_text(a, t->noise_param));
    } else {
        line("parameters", "none recorded");
    }
    if (in->format == FRT_FILE_TIFF) {
        const double *g = in->geotransform;
        if (in->has_geotransform) {
            char c[32], d[32], e[32], f[32];
            line("geotransform", "%s %s %s %s %s %s", frt_double_text(a, g[0]), frt_double_text(b, g[1]),
                 frt_double_text(c, g[2]), frt_double_text(d, g[3]), frt_double_text(e, g[4]),
                 frt_double_text(f, g[5]));
        } else {
            line("geotransform", "none");
        }
        if (in->projection[0]) {
            char s[400];
            projection_summary(in->projection, s, sizeof s);
            line("projection", "%s", s);
        } else {
            line("projection", "none");
        }
        line("nodata", "%s", in->has_nodata ? nodata_text(a, in->nodata) : "none");
    }
    if (st) {
        if (st->valid) {
            line("min", "%s", frt_float_text(a, (float)st->min));
            line("max", "%s", frt_float_text(a, (float)st->max));
            line("mean", "%s", frt_double_text(a, st->mean));
            line("stddev", "%s", frt_double_text(a, st->stddev));
        } else {
            line("min", "none (no finite heights)");
        }
        line("nan_count", "%llu", (unsigned long long)st->nans);
        if (st->infs)
            line("inf_count", "%llu", (unsigned long long)st->infs);
    }
}

/* ---- JSON ---- */

static json_object *jdouble(double v)
{
    char buf[32];
    if (isnan(v))
        return json_object_new_string("NaN"); /* JSON has no NaN or infinity: these three are strings */
    if (isinf(v))
        return json_object_new_string(v > 0 ? "Infinity" : "-Infinity");
    return json_object_new_double_s(v, frt_double_text(buf, v)); /* shortest text that reads back exactly */
}

static json_object *jfloat(float v)
{
    char buf[32];
    return json_object_new_double_s(v, frt_float_text(buf, v));
}

static json_object *jstring_or_null(const char *s)
{
    return s[0] ? json_object_new_string(s) : NULL;
}

static json_object *terrain_json(const frt_terrain_desc *t)
{
    char buf[32];
    json_object *o = json_object_new_object();
    json_object_object_add(o, "levels", json_object_new_int64(t->levels));
    json_object_object_add(o, "hurst", jdouble(t->hurst));
    json_object_object_add(o, "dimension", json_object_new_double_s(3.0 - t->hurst, dimension_text(buf, t->hurst)));
    json_object_object_add(o, "sigma", jdouble(t->sigma));
    json_object_object_add(o, "seed", json_object_new_uint64(t->seed));
    json_object_object_add(o, "edge", json_object_new_string(edge_name(t->edge)));
    json_object *r = NULL;
    if (frt_region_is_set(&t->region)) {
        r = json_object_new_object();
        json_object_object_add(r, "x", json_object_new_int64(t->region.x));
        json_object_object_add(r, "y", json_object_new_int64(t->region.y));
        json_object_object_add(r, "width", json_object_new_int64(t->region.width));
        json_object_object_add(r, "height", json_object_new_int64(t->region.height));
    }
    json_object_object_add(o, "region", r);
    json_object_object_add(o, "grid_side", json_object_new_int64(frt_terrain_side(t)));
    json_object_object_add(o, "noise", json_object_new_string(frt_noise_name(t->noise)));
    json_object_object_add(o, "noise_param", frt_noise_has_param(t->noise) ? jdouble(t->noise_param) : NULL);
    return o;
}

static json_object *stats_json(const field_stats *st)
{
    json_object *o = json_object_new_object();
    json_object_object_add(o, "min", st->valid ? jfloat((float)st->min) : NULL);
    json_object_object_add(o, "max", st->valid ? jfloat((float)st->max) : NULL);
    json_object_object_add(o, "mean", st->valid ? jdouble(st->mean) : NULL);
    json_object_object_add(o, "stddev", st->valid ? jdouble(st->stddev) : NULL);
    json_object_object_add(o, "valid_count", json_object_new_uint64(st->valid));
    json_object_object_add(o, "nan_count", json_object_new_uint64(st->nans));
    json_object_object_add(o, "inf_count", json_object_new_uint64(st->infs));
    return o;
}

/* Every key is always present (null where the file records nothing), so that scripts need no existence tests. */
static int print_json(const char *path, const frt_field_info *in, const field_stats *st)
{
    json_object *o = json_object_new_object();
    if (!o)
        return frt_cli_fail(FRT_EXIT_IO, "out of memory");
    json_object_object_add(o, "file", json_object_new_string(path));
    json_object_object_add(o, "format", json_object_new_string(frt_file_format_name(in->format)));
    json_object_object_add(o, "width", json_object_new_int64(in->width));
    json_object_object_add(o, "height", json_object_new_int64(in->height));
    json_object_object_add(o, "bits", json_object_new_int64(in->bits));
    json_object_object_add(o, "recorded_range", json_object_new_boolean(in->has_range));
    json_object_object_add(o, "spacing_x", jdouble(in->spacing_x));
    json_object_object_add(o, "spacing_y", jdouble(in->spacing_y));
    json_object_object_add(o, "z_scale", jdouble(in->z_scale));
    json_object_object_add(o, "backend", jstring_or_null(in->backend));
    json_object_object_add(o, "device", jstring_or_null(in->device));
    json_object_object_add(o, "terrain", in->has_terrain ? terrain_json(&in->terrain) : NULL);
    json_object *g = NULL;
    if (in->has_geotransform) {
        g = json_object_new_array();
        for (int i = 0; i < 6; ++i)
            json_object_array_add(g, jdouble(in->geotransform[i]));
    }
    json_object_object_add(o, "geotransform", g);
    json_object_object_add(o, "projection", jstring_or_null(in->projection));
    json_object_object_add(o, "nodata", in->has_nodata ? jdouble(in->nodata) : NULL);
    json_object_object_add(o, "stats", st ? stats_json(st) : NULL);
    const char *text = json_object_to_json_string_ext(o, JSON_C_TO_STRING_PRETTY | JSON_C_TO_STRING_SPACED |
                                                             JSON_C_TO_STRING_NOSLASHESCAPE);
    int code = FRT_EXIT_OK;
    if (text)
        printf("%s\n", text);
    else
        code = frt_cli_fail(FRT_EXIT_IO, "out of memory");
    json_object_put(o);
    return code;
}

/* ---- the command ---- */

/* The exit code of a failed read: 4 for I/O (and memory), 2 for a malformed, inconsistent or unsupported file. */
static int read_exit(frt_result r)
{
    return r == FRT_ERROR_IO || r == FRT_ERROR_OUT_OF_MEMORY ? FRT_EXIT_IO : FRT_EXIT_USAGE;
}

int frt_cmd_info(int argc, char **argv)
{
    frt_cli_command = "fracterra info";
    enum { OPT_JSON = 256, OPT_STATS };
    static const struct option opts[] = {{"json", no_argument, 0, OPT_JSON},
                                         {"stats", no_argument, 0, OPT_STATS},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    bool json = false, stats = false;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_JSON: json = true; break;
        case OPT_STATS: stats = true; break;
        case 'h': info_help(); return FRT_EXIT_OK;
        case ':': return frt_cli_fail(FRT_EXIT_USAGE, "option '%s' needs a value", argv[optind - 1]);
        default: {
            /* getopt_long says '?' for "--json=1" too: name the real problem */
            const char *arg = argv[optind - 1], *eq = strchr(arg, '=');
            for (const struct option *o = opts; eq && strncmp(arg, "--", 2) == 0 && o->name; ++o)
                if (strlen(o->name) == (size_t)(eq - arg - 2) && strncmp(arg + 2, o->name, strlen(o->name)) == 0)
                    return frt_cli_fail(FRT_EXIT_USAGE, "option '%.*s' takes no value", (int)(eq - arg), arg);
            return frt_cli_fail(FRT_EXIT_USAGE, "unknown option '%s' (see --help)", arg);
        }
        }
    }
    if (optind >= argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing the heightfield file (fracterra info FILE [--json] [--stats])");
    const char *path = argv[optind++];
    if (optind < argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s' (one file; see --help)", argv[optind]);

    char err[1200];
    frt_field_info info;
    frt_result r = frt_read_heightfield_info(path, &info, err, sizeof err);
    if (r != FRT_SUCCESS)
        return frt_cli_fail(read_exit(r), "%s", err);

    field_stats st;
    if (stats) {
        const size_t count = (size_t)info.width * info.height;
        if (info.width && count / info.width != info.height)
            return frt_cli_fail(FRT_EXIT_USAGE, "'%s': %u x %u heights do not fit in memory here", path, info.width,
                                info.height);
        float *h = count <= SIZE_MAX / sizeof *h ? malloc((count ? count : 1) * sizeof *h) : NULL;
        if (!h)
            return frt_cli_fail(FRT_EXIT_IO, "'%s': cannot allocate %.1f MiB for %u x %u heights", path,
                                (double)count * 4.0 / 1048576.0, info.width, info.height);
        frt_progress_init(false);
        char label[4200];
        snprintf(label, sizeof label, "reading %s", path);
        frt_progress_begin(label, 0);
        r = frt_read_heightfield(path, h, count, &info, err, sizeof err);
        frt_progress_end();
        if (r != FRT_SUCCESS) {
            free(h);
            return frt_cli_fail(read_exit(r), "%s", err);
        }
        compute_stats(h, count, &st);
        free(h);
    }
    if (json)
        return print_json(path, &info, stats ? &st : NULL);
    print_text(path, &info, stats ? &st : NULL);
    return FRT_EXIT_OK;
}
