/* test_render.c — host/hillshade.c and host/profiles.c: shading of planes against the analytic value, the colour
 * ramp, and pixel checks on small profile plots (spacing, hidden lines, dilation sign, base, file formats). */
#include "check.h"

#include <dirent.h>
#include <unistd.h>

#define PI 3.14159265358979323846
/* Hillshade values are rounded to integers; the analytic value computed here in double and the library's Horn
 * differences of float heights can fall on the two sides of a .5, so a pixel may differ by one. */
#define SHADE_TOLERANCE 1
/* Grey levels: a pixel "has ink" below INK (a 1-pixel anti-aliased line puts at least half its coverage in one
 * pixel row, i.e. <= 128) and is "paper" above PAPER (anti-aliasing of a line 2+ pixels away leaves 255). */
#define INK 160
#define PAPER 250

static char dir[] = "/tmp/frt_render_XXXXXX";

static const char *path_in(const char *name)
{
    static char buf[256];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

/* ---- hillshade ---- */

/* gdaldem's value for a plane h = a * column + b * row, from the geometry (not from the library's formula): ground
 * east = column * sx, north = -row * sy, so dz/dE = a / sx and dz/dN = -b / sy; the normal (-z dz/dE, -z dz/dN, 1)
 * against the direction to the light (sin az cos alt, cos az cos alt, sin alt). */
static int plane_shade(double a, double b, double sx, double sy, double z, double az_deg, double alt_deg)
{
    double az = az_deg * PI / 180.0, alt = alt_deg * PI / 180.0;
    double n[3] = {-z * a / sx, z * b / sy, 1.0};
    double l[3] = {sin(az) * cos(alt), cos(az) * cos(alt), sin(alt)};
    double c = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]) / sqrt(n[0] * n[0] + n[1] * n[1] + 1.0);
    return c <= 0.0 ? 1 : (int)floor(1.0 + 254.0 * c + 0.5);
}

static void fill_plane(float *h, uint32_t w, uint32_t ht, double a, double b)
{
    for (uint32_t y = 0; y < ht; ++y)
        for (uint32_t x = 0; x < w; ++x)
            h[(size_t)y * w + x] = (float)(a * x + b * y);
}

/* Largest |pixel - expected| over the whole picture, edges and corners included. */
static int max_shade_error(const uint8_t *pic, size_t n, int expected)
{
    int worst = 0;
    for (size_t i = 0; i < n; ++i) {
        int e = abs((int)pic[i] - expected);
        worst = e > worst ? e : worst;
    }
    return worst;
}

static void test_hillshade_planes(void)
{
    enum { W = 23, H = 17 };
    float h[W * H];
    uint8_t pic[W * H];
    const struct {
        double a, b, sx, sy, z, az, alt;
    } cases[] = {
        {0.0, 0.0, 1, 1, 1, 0, 0},          /* flat, defaults: 1 + 254 sin 45 */
        {0.0, 0.0, 1, 1, 1, 90, 30},        /* flat: 1 + 254 sin 30 */
        {0.5, 0.0, 1, 1, 1, 0, 0},          /* rising to the east, light from the north-west */
        {0.0, 0.7, 1, 1, 1, 0, 0},          /* rising to the south */
        {-0.4, 0.3, 1, 1, 2.5, 0, 0},       /* z-factor */
        {0.3, 0.2, 1, 1, 1, 90, 45},        /* light from the east onto ground rising to the east: dark */
        {-0.6, -0.6, 1, 1, 1, 0, 0},        /* rising to the north-west: faces away from the light */
        {2.0, 1.0, 4, 2, 1, 200, 60},       /* spacing */
        {0.8, -0.3, 1, 1, 1, 360, 20},      /* light from the north */
        {0.05, 0.02, 0.1, 0.1, 3, 135, 10}, /* low sun */
        {3.0, 0.0, 1, 1, 1, 270, 45},       /* steep, facing the light from the west */
        {-3.0, 0.0, 1, 1, 1, 270, 45},      /* steep, facing away from it: in shadow, 1 */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        fill_plane(h, W, H, cases[c].a, cases[c].b);
        frt_hillshade_desc d;
        memset(&d, 0, sizeof d);
        d.azimuth = cases[c].az;
        d.altitude = cases[c].alt;
        d.z_factor = cases[c].z;
        d.spacing_x = cases[c].sx;
        d.spacing_y = cases[c].sy;
        frt_result r = frt_hillshade(h, W, H, &d, pic, sizeof pic);
        CHECK(r == FRT_SUCCESS, "case %zu: %s", c, frt_result_string(r));
        int want = plane_shade(cases[c].a, cases[c].b, cases[c].sx, cases[c].sy, cases[c].z,
                               cases[c].az == 0 ? 315 : cases[c].az, cases[c].alt == 0 ? 45 : cases[c].alt);
        int err = max_shade_error(pic, W * H, want);
        CHECK(err <= SHADE_TOLERANCE, "case %zu: want %d everywhere, off by %d (corner %d, centre %d)", c, want, err,
              pic[0], pic[(H / 2) * W + W / 2]);
    }
    CHECK(plane_shade(0, 0, 1, 1, 1, 315, 45) == 181 && plane_shade(0, 0, 1, 1, 1, 90, 30) == 128,
          "flat ground: 1 + 254 sin(altitude)");

    /* Light from the north-west: a slope facing it (rising to the south-east) is brighter than flat ground, which
     * is brighter than the slope facing away. */
    uint8_t facing, away, flat;
    fill_plane(h, W, H, 0.4, 0.4);
    frt_hillshade(h, W, H, NULL, pic, sizeof pic);
    facing = pic[W * H / 2];
    fill_plane(h, W, H, -0.4, -0.4);
    frt_hillshade(h, W, H, NULL, pic, sizeof pic);
    away = pic[W * H / 2];
    fill_plane(h, W, H, 0, 0);
    frt_hillshade(h, W, H, NULL, pic, sizeof pic);
    flat = pic[W * H / 2];
    CHECK(facing > flat && flat > away, "facing %u > flat %u > away %u", facing, flat, away);

    /* Automatic z: for a plane, |gradient| is the same everywhere, so z * |gradient| = tan 25 degrees exactly. */
    fill_plane(h, W, H, 0.02, 0.0); /* rising to the east */
    frt_hillshade_desc d;
    memset(&d, 0, sizeof d);
    d.azimuth = 90; /* light from the east, onto the slope facing away from it: cos(45 + 25 degrees) */
    frt_hillshade(h, W, H, &d, pic, sizeof pic);
    int want = (int)floor(1.0 + 254.0 * cos(70.0 * PI / 180.0) + 0.5);
    CHECK(max_shade_error(pic, W * H, want) <= SHADE_TOLERANCE, "automatic z: want %d, got %d", want, pic[0]);
}

static void test_hillshade_edges_and_errors(void)
{
    enum { W = 9, H = 7 };
    float h[W * H];
    uint8_t pic[W * H * 3];
    fill_plane(h, W, H, 0.3, -0.2);
    h[3 * W + 4] = NAN;
    h[0] = INFINITY;
    frt_hillshade_desc z1;
    memset(&z1, 0, sizeof z1);
    z1.z_factor = 1.0; /* the automatic z would see the bent gradients around the NaN */
    CHECK(frt_hillshade(h, W, H, &z1, pic, W * H) == FRT_SUCCESS, "NaN field");
    CHECK(pic[3 * W + 4] == 0 && pic[0] == 0, "non-finite heights give 0 (%u, %u)", pic[3 * W + 4], pic[0]);
    int want = plane_shade(0.3, -0.2, 1, 1, 1, 315, 45);
    /* Neighbours of a non-finite height take the centre's value in its place (gdaldem), which bends the plane:
     * still shaded, not 0. Pixels away from both stay exact. */
    CHECK(pic[3 * W + 3] > 0 && pic[2 * W + 4] > 0 && pic[1] > 0, "neighbours of NaN are shaded");
    CHECK(abs(pic[6 * W + 8] - want) <= SHADE_TOLERANCE && abs(pic[5 * W + 1] - want) <= SHADE_TOLERANCE,
          "far pixels exact: want %d, got %u %u", want, pic[6 * W + 8], pic[5 * W + 1]);

    /* Degenerate sides: one row or one column is shaded (the missing direction counts as level). */
    float line[5] = {0, 1, 2, 3, 4};
    CHECK(frt_hillshade(line, 5, 1, NULL, pic, 5) == FRT_SUCCESS && pic[2] > 0, "1-row field");
    CHECK(frt_hillshade(line, 1, 5, NULL, pic, 5) == FRT_SUCCESS && pic[2] > 0, "1-column field");
    float one = 3.0f;
    CHECK(frt_hillshade(&one, 1, 1, NULL, pic, 1) == FRT_SUCCESS && pic[0] == 181, "1x1 field is flat: %u", pic[0]);

    /* Sizes and arguments. */
    frt_hillshade_desc color;
    memset(&color, 0, sizeof color);
    color.color = true;
    CHECK(frt_hillshade_size(W, H, NULL) == W * H && frt_hillshade_size(W, H, &color) == 3 * W * H, "sizes");
    CHECK(frt_hillshade_size(0, H, NULL) == 0 && frt_hillshade_size(W, 0, &color) == 0, "zero side -> 0");
    CHECK(frt_hillshade_size(UINT32_MAX, UINT32_MAX, &color) == 0, "overflow -> 0");
    CHECK(frt_hillshade(h, W, H, NULL, pic, W * H - 1) == FRT_ERROR_BUFFER_TOO_SMALL, "grey buffer too small");
    CHECK(frt_hillshade(h, W, H, &color, pic, W * H * 3 - 1) == FRT_ERROR_BUFFER_TOO_SMALL, "RGB buffer too small");
    CHECK(frt_hillshade(NULL, W, H, NULL, pic, W * H) == FRT_ERROR_INVALID_ARGUMENT, "NULL heights");
    CHECK(frt_hillshade(h, W, H, NULL, NULL, W * H) == FRT_ERROR_INVALID_ARGUMENT, "NULL output");
    CHECK(frt_hillshade(h, 0, H, NULL, pic, W * H) == FRT_ERROR_INVALID_ARGUMENT, "zero width");
    frt_hillshade_desc bad;
    memset(&bad, 0, sizeof bad);
    bad.altitude = 95;
    CHECK(frt_hillshade(h, W, H, &bad, pic, W * H) == FRT_ERROR_INVALID_ARGUMENT, "altitude > 90");
    memset(&bad, 0, sizeof bad);
    bad.azimuth = NAN;
    CHECK(frt_hillshade(h, W, H, &bad, pic, W * H) == FRT_ERROR_INVALID_ARGUMENT, "NaN azimuth");
    memset(&bad, 0, sizeof bad);
    bad.spacing_x = -1;
    CHECK(frt_hillshade(h, W, H, &bad, pic, W * H) == FRT_ERROR_INVALID_ARGUMENT, "negative spacing");
}

static void test_hillshade_color(void)
{
    /* A ramp along x, nearly level (so the shade is the flat value everywhere): the colours run from the ramp's
     * low end (a dark green) to its high end (near white). */
    enum { W = 64, H = 8 };
    float h[W * H];
    uint8_t pic[W * H * 3];
    fill_plane(h, W, H, 1e-3, 0.0);
    frt_hillshade_desc d;
    memset(&d, 0, sizeof d);
    d.color = true;
    d.z_factor = 1.0;
    CHECK(frt_hillshade(h, W, H, &d, pic, sizeof pic) == FRT_SUCCESS, "color");
    const uint8_t *lo = pic + (size_t)(H / 2) * W * 3, *hi = lo + (W - 1) * 3;
    CHECK(lo[1] > lo[0] && lo[1] > lo[2] && lo[1] < 160, "low end is a dark green: %u %u %u", lo[0], lo[1], lo[2]);
    CHECK(hi[0] > 220 && hi[1] > 220 && hi[2] > 220, "high end is near white: %u %u %u", hi[0], hi[1], hi[2]);
    int lum_lo = lo[0] + lo[1] + lo[2], lum_hi = hi[0] + hi[1] + hi[2];
    CHECK(lum_hi > lum_lo + 300, "the ramp brightens upwards (%d -> %d)", lum_lo, lum_hi);
    /* The same row is uniform across y: colour depends on height only (and the shade, constant here). */
    CHECK(memcmp(pic, pic + (size_t)(H - 1) * W * 3, (size_t)W * 3) == 0, "rows alike");
    h[5] = NAN;
    frt_hillshade(h, W, H, &d, pic, sizeof pic);
    CHECK(pic[15] == 0 && pic[16] == 0 && pic[17] == 0, "NaN -> black");
}

/* ---- profiles ---- */

/* Renders with frt_profiles into a malloc'd picture; the layout comes back in *l. NULL on failure. */
static uint8_t *render(const float *h, uint32_t w, uint32_t ht, const frt_profiles_desc *d, frt_profiles_layout *l)
{
    char err[256];
    frt_result r = frt_profiles_layout_compute(h, w, ht, d, l, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "layout: %s", err);
    if (r != FRT_SUCCESS)
        return NULL;
    uint32_t pw = 0, ph = 0;
    r = frt_profiles_size(h, w, ht, d, &pw, &ph);
    CHECK(r == FRT_SUCCESS && pw == l->picture_width && ph == l->picture_height, "size agrees with the layout");
    uint8_t *pic = check_alloc((size_t)pw * ph);
    r = frt_profiles(h, w, ht, d, pic, pw, ph);
    CHECK(r == FRT_SUCCESS, "frt_profiles: %s", frt_result_string(r));
    return pic;
}

/* Darkest pixel within +-r of (x, y); 255 outside the picture. */
static int darkest_near(const uint8_t *pic, const frt_profiles_layout *l, double x, double y, int r)
{
    int best = 255;
    int cx = (int)floor(x), cy = (int)floor(y);
    for (int j = cy - r; j <= cy + r; ++j)
        for (int i = cx - r; i <= cx + r; ++i)
            if (i >= 0 && j >= 0 && i < (int)l->picture_width && j < (int)l->picture_height) {
                int v = pic[(size_t)j * l->picture_width + i];
                best = v < best ? v : best;
            }
    return best;
}

static int ink_at_point(const uint8_t *pic, const frt_profiles_layout *l, double x, double y, double hv, int r)
{
    double px, py;
    frt_profiles_point(l, x, y, hv, &px, &py);
    return darkest_near(pic, l, px, py, r);
}

static void test_profiles_flat(void)
{
    enum { W = 65, H = 65, EVERY = 8 };
    static float h[W * H]; /* zeros */
    frt_profiles_desc d;
    memset(&d, 0, sizeof d);
    d.width = 400;
    frt_profiles_layout l;
    uint8_t *pic = render(h, W, H, &d, &l);
    if (!pic)
        return;
    CHECK(l.rows == 9 && l.back_y == 64 && l.desc.every == EVERY, "9 profiles (%u)", l.rows);
    CHECK(l.desc.dilation == 1.0 && l.desc.tilt == 1.0 && l.desc.line_width == 1.0, "defaults resolved");

    /* Down the middle column every profile crosses once: 9 dark runs, evenly spaced. */
    uint32_t col = l.picture_width / 2;
    double centre[16];
    int lines = 0;
    for (uint32_t y = 0; y < l.picture_height;) {
        if (pic[(size_t)y * l.picture_width + col] >= INK) {
            ++y;
            continue;
        }
        double sum = 0.0, weight = 0.0;
        for (; y < l.picture_height && pic[(size_t)y * l.picture_width + col] < PAPER; ++y) {
            double ink = 255.0 - pic[(size_t)y * l.picture_width + col];
            sum += ink * y;
            weight += ink;
        }
        if (lines < 16)
            centre[lines] = sum / weight;
        ++lines;
    }
    CHECK(lines == 9, "9 lines down the middle, found %d", lines);
    if (lines == 9) {
        double first = centre[1] - centre[0], lo = first, hi = first;
        for (int i = 2; i < 9; ++i) {
            double s = centre[i] - centre[i - 1];
            lo = s < lo ? s : lo;
            hi = s > hi ? s : hi;
        }
        /* Spacing 0.25 * EVERY * tilt * scale in theory; measured line centres within a pixel of each other. */
        double want = 0.25 * EVERY * l.scale;
        CHECK(hi - lo <= 1.0 && fabs(first - want) <= 1.0, "even spacing: %.2f..%.2f px, want %.2f", lo, hi, want);
    }

    /* Straight: each profile's ink sits on its own pixel row from one end to the other, and there is paper
     * between the profiles. */
    int bent = 0;
    for (uint32_t p = 0; p < l.rows; ++p) {
        double y = p * EVERY;
        for (int x = 1; x < W - 1; x += 3) {
            bent += ink_at_point(pic, &l, x, y, 0.0, 1) >= INK;
            bent += ink_at_point(pic, &l, x, y + EVERY / 2, 0.0, 0) < PAPER; /* half-way to the next */
        }
    }
    CHECK(bent == 0, "%d places where a flat profile is not a straight line", bent);
    free(pic);

    /* A non-finite height breaks the line: the front profile has no ink around column 32 (nothing stands behind
     * it there: the profiles behind are higher). */
    h[(H - 1) * W + 32] = NAN;
    pic = render(h, W, H, &d, &l);
    if (pic) {
        CHECK(ink_at_point(pic, &l, 32, 0, 0, 1) >= PAPER, "gap at a NaN");
        CHECK(ink_at_point(pic, &l, 29, 0, 0, 1) < INK && ink_at_point(pic, &l, 35, 0, 0, 1) < INK, "line around it");
    }
    free(pic);
    h[(H - 1) * W + 32] = 0.0f;
}

static void test_profiles_hidden(void)
{
    /* Two profiles (rows 0 and 8 of a 9-row field, every 8): in front (row 8, y = 0) a ridge of height 10 over
     * columns 20..44; behind (row 0, y = 8) flat ground at v = 2 with one spike of height 20 at column 32, which
     * rises to v = 32, above the ridge's v = 15. */
    enum { W = 65, H = 9 };
    static float h[W * H];
    for (int x = 0; x < W; ++x) {
        h[8 * W + x] = (x >= 20 && x <= 44) ? 10.0f : 0.0f;
        h[0 * W + x] = x == 32 ? 20.0f : 0.0f;
    }
    frt_profiles_desc d;
    memset(&d, 0, sizeof d);
    d.width = 500;
    d.dilation = 1.0;
    frt_profiles_layout l;
    uint8_t *pic = render(h, W, H, &d, &l);
    if (!pic)
        return;
    /* The back ground line is visible left of the ridge (u = 1.5 x + 2 < 29) and hidden behind it. */
    CHECK(ink_at_point(pic, &l, 8, 8, 0, 1) < INK, "back line visible beside the ridge");
    CHECK(ink_at_point(pic, &l, 24, 8, 0, 1) >= PAPER && ink_at_point(pic, &l, 28, 8, 0, 1) >= PAPER &&
              ink_at_point(pic, &l, 38, 8, 0, 1) >= PAPER,
          "back line hidden behind the ridge");
    /* The ridge itself is drawn whole. */
    CHECK(ink_at_point(pic, &l, 30, 0, 10, 1) < INK && ink_at_point(pic, &l, 40, 0, 10, 1) < INK, "ridge drawn");
    /* The spike's tip shows above the ridge; its foot (v = 10 < 15, on the flank at column 31.27) does not. */
    CHECK(ink_at_point(pic, &l, 32, 8, 20, 1) < INK, "spike tip visible");
    CHECK(ink_at_point(pic, &l, 31.8, 8, 16, 0) < INK, "spike above the ridge visible");
    CHECK(ink_at_point(pic, &l, 31.27, 8, 5.4, 1) >= PAPER, "spike below the ridge hidden");
    free(pic);
}

static void test_profiles_dilation_and_base(void)
{
    /* One row with a bump in the middle: positive dilation raises it above the ends, negative sinks it. */
    enum { W = 65 };
    float row[W];
    for (int x = 0; x < W; ++x)
        row[x] = (float)(10.0 * exp(-((x - 32) / 6.0) * ((x - 32) / 6.0)));
    frt_profiles_desc d;
    memset(&d, 0, sizeof d);
    d.width = 300;
    frt_profiles_layout up, down;
    uint8_t *pu = render(row, W, 1, &d, &up);
    d.dilation = -up.desc.dilation;
    uint8_t *pd = render(row, W, 1, &d, &down);
    if (pu && pd) {
        CHECK(up.desc.dilation > 0 && down.desc.dilation < 0, "automatic dilation is positive");
        double x0, y0, x1, y1;
        frt_profiles_point(&up, 32, 0, row[32], &x0, &y0);
        frt_profiles_point(&up, 2, 0, row[2], &x1, &y1);
        CHECK(y0 < y1 - 10 && darkest_near(pu, &up, x0, y0, 1) < INK && darkest_near(pu, &up, x1, y1, 1) < INK,
              "bump up: peak above the ends");
        frt_profiles_point(&down, 32, 0, row[32], &x0, &y0);
        frt_profiles_point(&down, 2, 0, row[2], &x1, &y1);
        CHECK(y0 > y1 + 10 && darkest_near(pd, &down, x0, y0, 1) < INK && darkest_near(pd, &down, x1, y1, 1) < INK,
              "negative dilation: the bump is a pit");
        CHECK(up.picture_height == down.picture_height, "inverting keeps the extent");
    }
    free(pu);
    free(pd);

    /* The base: on a flat 33 x 17 field, a floor 6 units below; the front face is light grey with a dark bottom
     * edge, where the plot without a base is paper. */
    enum { BW = 33, BH = 17 };
    static float flat[BW * BH];
    memset(&d, 0, sizeof d);
    d.width = 400;
    d.dilation = 1.0;
    d.base = 6.0;
    frt_profiles_layout lb;
    uint8_t *pb = render(flat, BW, BH, &d, &lb);
    if (pb) {
        CHECK(lb.zbase == -6.0, "floor at zmin - base (%g)", lb.zbase);
        CHECK(ink_at_point(pb, &lb, 16, 0, -6.0, 1) < INK, "dark floor edge below the front profile");
        CHECK(ink_at_point(pb, &lb, 16, 0, 0.0, 1) < INK, "front profile still drawn");
        double px, py;
        frt_profiles_point(&lb, 16, 0, -3.0, &px, &py);
        int face = pb[(size_t)floor(py) * lb.picture_width + (size_t)floor(px)];
        CHECK(face > INK && face < PAPER, "front face is light grey (%d)", face);
        frt_profiles_point(&lb, BW - 1, BH / 2.0, -3.0, &px, &py);
        face = pb[(size_t)floor(py) * lb.picture_width + (size_t)floor(px + 1.5)];
        CHECK(face > INK && face < PAPER, "right face is light grey (%d)", face);
        CHECK(ink_at_point(pb, &lb, BW - 1, 16, -6.0, 1) < INK, "back corner of the floor drawn");
    }
    d.base = 0.0;
    frt_profiles_layout ln;
    uint8_t *pn = render(flat, BW, BH, &d, &ln);
    if (pn) {
        /* without a base, the same place relative to the front profile is paper */
        double px, py;
        frt_profiles_point(&ln, 16, 0, -3.0, &px, &py);
        CHECK(py >= ln.picture_height || darkest_near(pn, &ln, px, py, 1) >= PAPER, "no base: paper below");
        CHECK(ln.picture_height < lb.picture_height, "the base makes the picture taller");
    }
    free(pb);
    free(pn);
}

static bool file_starts(const char *path, const void *magic, size_t n)
{
    unsigned char buf[64] = {0};
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    size_t got = fread(buf, 1, n, f);
    fclose(f);
    return got == n && memcmp(buf, magic, n) == 0;
}

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | p[1] << 16 | p[2] << 8 | p[3];
}

static int temp_files_left(void)
{
    DIR *dd = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (dd && (e = readdir(dd)))
        n += strstr(e->d_name, ".tmp-") != NULL;
    if (dd)
        closedir(dd);
    return n;
}

static void test_profiles_files(void)
{
    enum { W = 33, H = 33 };
    static float h[W * H];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            h[y * W + x] = (float)(sin(x * 0.3) * cos(y * 0.2));
    frt_profiles_desc d;
    memset(&d, 0, sizeof d);
    d.width = 320;
    d.every = 4;
    d.base = 1.0;
    char err[512];
    frt_profiles_layout l;
    frt_profiles_layout_compute(h, W, H, &d, &l, err, sizeof err);

    frt_result r = frt_write_profiles(path_in("p.png"), h, W, H, &d, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "png: %s", err);
    unsigned char head[26] = {0};
    FILE *f = fopen(path_in("p.png"), "rb");
    if (f) {
        CHECK(fread(head, 1, sizeof head, f) == sizeof head, "png header");
        fclose(f);
    }
    CHECK(memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0, "PNG signature");
    CHECK(be32(head + 16) == l.picture_width && be32(head + 20) == l.picture_height && head[24] == 8 && head[25] == 0,
          "8-bit grey PNG of the layout's size (%u x %u, depth %u, type %u)", be32(head + 16), be32(head + 20),
          head[24], head[25]);

    r = frt_write_profiles(path_in("p.SVG"), h, W, H, &d, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "svg: %s", err);
    CHECK(file_starts(path_in("p.SVG"), "<?xml", 5) || file_starts(path_in("p.SVG"), "<svg", 4), "SVG header");
    r = frt_write_profiles(path_in("p.pdf"), h, W, H, &d, err, sizeof err);
    CHECK(r == FRT_SUCCESS, "pdf: %s", err);
    CHECK(file_starts(path_in("p.pdf"), "%PDF", 4), "PDF header");

    /* Unknown extension: an error naming the three, and no file. */
    err[0] = 0;
    r = frt_write_profiles(path_in("p.jpg"), h, W, H, &d, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, ".png") && strstr(err, ".svg") && strstr(err, ".pdf"),
          "unknown extension: %s", err);
    CHECK(access(path_in("p.jpg"), F_OK) != 0, "no file for an unknown extension");
    r = frt_write_profiles(path_in("noext"), h, W, H, &d, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && access(path_in("noext"), F_OK) != 0, "no extension");

    /* A failure keeps an existing file as it was. */
    f = fopen(path_in("keep.png"), "wb");
    if (f) {
        fputs("keep", f);
        fclose(f);
    }
    frt_profiles_desc bad = d;
    bad.dilation = 1e6; /* far over 16384 pixels tall */
    err[0] = 0;
    r = frt_write_profiles(path_in("keep.png"), h, W, H, &bad, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && strstr(err, "16384"), "too tall: %s", err);
    CHECK(file_starts(path_in("keep.png"), "keep", 4), "existing file kept");
    r = frt_write_profiles(path_in("keep.png"), NULL, W, H, &d, err, sizeof err);
    CHECK(r == FRT_ERROR_INVALID_ARGUMENT && file_starts(path_in("keep.png"), "keep", 4), "NULL heights");
    r = frt_write_profiles(dir, h, W, H, &d, err, sizeof err); /* a directory has no extension: refused */
    CHECK(r != FRT_SUCCESS, "directory");
    CHECK(temp_files_left() == 0, "no temporary files left");
}

static void test_profiles_arguments(void)
{
    enum { W = 9, H = 9 };
    static float h[W * H];
    frt_profiles_desc d;
    uint32_t pw, ph;
    memset(&d, 0, sizeof d);
    CHECK(frt_profiles_size(h, W, H, &d, &pw, &ph) == FRT_SUCCESS && pw == 1200, "default width %u", pw);
    CHECK(frt_profiles_size(h, W, H, NULL, &pw, &ph) == FRT_SUCCESS && pw == 1200, "NULL desc");
    CHECK(frt_profiles_size(NULL, W, H, &d, &pw, &ph) == FRT_ERROR_INVALID_ARGUMENT, "NULL heights");
    CHECK(frt_profiles_size(h, 0, H, &d, &pw, &ph) == FRT_ERROR_INVALID_ARGUMENT, "zero width");
    CHECK(frt_profiles_size(h, W, H, &d, NULL, &ph) == FRT_ERROR_INVALID_ARGUMENT, "NULL out");
    const struct {
        double dilation, tilt, base, line_width;
        uint32_t width;
    } bad[] = {{NAN, 0, 0, 0, 0}, {0, -1, 0, 0, 0}, {0, INFINITY, 0, 0, 0}, {0, 0, -1, 0, 0},
               {0, 0, NAN, 0, 0}, {0, 0, 0, -2, 0}, {0, 0, 0, 0, 20000},    {0, 0, 0, 0, 3}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        memset(&d, 0, sizeof d);
        d.dilation = bad[i].dilation;
        d.tilt = bad[i].tilt;
        d.base = bad[i].base;
        d.line_width = bad[i].line_width;
        d.width = bad[i].width;
        CHECK(frt_profiles_size(h, W, H, &d, &pw, &ph) == FRT_ERROR_INVALID_ARGUMENT, "bad desc %zu accepted", i);
    }
    memset(&d, 0, sizeof d);
    d.width = 100;
    CHECK(frt_profiles_size(h, W, H, &d, &pw, &ph) == FRT_SUCCESS, "size");
    uint8_t *pic = check_alloc((size_t)pw * (ph + 1));
    CHECK(frt_profiles(h, W, H, &d, pic, pw, ph + 1) == FRT_ERROR_INVALID_ARGUMENT, "wrong picture size");
    CHECK(frt_profiles(h, W, H, &d, NULL, pw, ph) == FRT_ERROR_INVALID_ARGUMENT, "NULL picture");
    /* every larger than the field: only the front profile */
    d.every = 1000;
    frt_profiles_layout l;
    CHECK(frt_profiles_layout_compute(h, W, H, &d, &l, NULL, 0) == FRT_SUCCESS && l.rows == 1, "one profile");
    /* all heights non-finite: an empty plot, not an error */
    float nan_field[W * H];
    for (int i = 0; i < W * H; ++i)
        nan_field[i] = NAN;
    d.every = 0;
    CHECK(frt_profiles_size(nan_field, W, H, &d, &pw, &ph) == FRT_SUCCESS, "all-NaN field");
    free(pic);
}

int main(void)
{
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_hillshade_planes();
    test_hillshade_edges_and_errors();
    test_hillshade_color();
    test_profiles_flat();
    test_profiles_hidden();
    test_profiles_dilation_and_base();
    test_profiles_files();
    test_profiles_arguments();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return check_summary("test_render");
}
