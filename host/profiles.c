/* profiles.c — the 1988 report's orthographic profile plot: every K-th row as a profile, hidden lines removed by a
 * floating horizon, drawn with cairo to a grey picture, PNG, SVG or PDF. */
#include "internal.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_SIDE 16384u      /* largest picture side, in pixels or points */
#define MARGIN_FRACTION 0.03 /* white margin on every side, as a fraction of the picture width */
/* Automatic dilation: the relief (max - min of the heights) spans this fraction of the projected width. Judged on
 * 513^2 plots (H 0.3 and 0.8, every 8): at 1/6 the profiles tangle into one another and the surface no longer reads;
 * at 1/12 it reads well but hills look low; 1/10 keeps both. */
#define AUTO_RELIEF_FRACTION 0.1
/* Horizon samples per device unit (pixel or point): visibility is decided to a quarter of a pixel. */
#define HORIZON_SAMPLES 4.0
#define FACE_GREY 0.85 /* the base's faces: light grey paper */
#define NO_HORIZON (-1e30)

/* ---- layout ---- */

static bool is_pos_finite(double v)
{
    return isfinite(v) && v > 0.0;
}

frt_result frt_profiles_layout_compute(const float *h, uint32_t width, uint32_t height, const frt_profiles_desc *desc,
                                       frt_profiles_layout *l, char *err, size_t err_size)
{
    memset(l, 0, sizeof *l);
    if (!err)
        err_size = 0; /* snprintf(NULL, 0, ...) only measures */
    frt_profiles_desc d;
    if (desc)
        d = *desc;
    else
        memset(&d, 0, sizeof d);
    if (!h || width == 0 || height == 0) {
        snprintf(err, err_size, "no heightfield (%s)", !h ? "NULL heights" : "a side is 0");
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    if ((size_t)width > SIZE_MAX / sizeof(float) / height) {
        snprintf(err, err_size, "a %u x %u field is too large", width, height);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    if (!isfinite(d.dilation)) {
        snprintf(err, err_size, "the dilation must be a finite number");
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    if (d.tilt != 0.0 && !(is_pos_finite(d.tilt) && d.tilt <= 100.0)) {
        snprintf(err, err_size, "the tilt must be in (0, 100], got %g", d.tilt);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    if (!(isfinite(d.base) && d.base >= 0.0)) {
        snprintf(err, err_size, "the base must be a finite number >= 0, got %g", d.base);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    if (d.width > MAX_SIDE || (d.width != 0 && d.width < 16)) {
        snprintf(err, err_size, "the picture width must be 16..%u, got %u", MAX_SIDE, d.width);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    if (d.line_width != 0.0 && !(is_pos_finite(d.line_width) && d.line_width <= 100.0)) {
        snprintf(err, err_size, "the line width must be in (0, 100], got %g", d.line_width);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    d.every = d.every ? d.every : 8;
    d.tilt = d.tilt != 0.0 ? d.tilt : 1.0;
    d.width = d.width ? d.width : 1200;
    d.line_width = d.line_width != 0.0 ? d.line_width : 1.0;

    /* Heights' range over the whole field: the automatic dilation and the base's floor refer to it. */
    bool any = false;
    float hmin = 0.0f, hmax = 0.0f;
    for (size_t i = 0, n = (size_t)width * height; i < n; ++i) {
        float v = h[i];
        if (!isfinite(v))
            continue;
        if (!any || v < hmin)
            hmin = v;
        if (!any || v > hmax)
            hmax = v;
        any = true;
    }
    l->rows = (height - 1) / d.every + 1;
    l->back_y = (l->rows - 1) * d.every;
    double umax = 1.5 * (width - 1) + 0.25 * l->back_y;
    if (umax <= 0.0)
        umax = 1.0; /* a single point: any scale will do */
    if (d.dilation == 0.0)
        d.dilation = hmax > hmin ? AUTO_RELIEF_FRACTION * umax / (1.5 * d.tilt * ((double)hmax - (double)hmin)) : 1.0;
    l->desc = d;
    if (any) {
        double z0 = d.dilation * hmin, z1 = d.dilation * hmax;
        l->zmin = z0 < z1 ? z0 : z1;
        l->zmax = z0 < z1 ? z1 : z0;
    }
    l->zbase = l->zmin - d.base;
    if (!isfinite(l->zbase) || !isfinite(l->zmax) || !isfinite(d.dilation)) {
        snprintf(err, err_size, "the dilation %g makes heights overflow", d.dilation);
        return FRT_ERROR_INVALID_ARGUMENT;
    }

    /* Vertical extent: the drawn profiles, and with a base its side face (the right column) and floor. */
    double vmin = INFINITY, vmax = -INFINITY;
    for (uint32_t k = 0; k < l->rows; ++k) {
        uint32_t y = k * d.every;
        const float *row = h + (size_t)(height - 1 - y) * width;
        for (uint32_t x = 0; x < width; ++x) {
            if (!isfinite(row[x]))
                continue;
            double v = d.tilt * (0.25 * y + 1.5 * d.dilation * row[x]);
            vmin = v < vmin ? v : vmin;
            vmax = v > vmax ? v : vmax;
        }
    }
    if (d.base > 0.0 && any) {
        for (uint32_t y = 0; y <= l->back_y; ++y) {
            float hv = h[(size_t)(height - 1 - y) * width + (width - 1)];
            if (!isfinite(hv))
                continue;
            double v = d.tilt * (0.25 * y + 1.5 * d.dilation * hv);
            vmin = v < vmin ? v : vmin;
            vmax = v > vmax ? v : vmax;
        }
        double vb = d.tilt * 1.5 * l->zbase; /* the front bottom edge is the lowest point of the base */
        vmin = vb < vmin ? vb : vmin;
    }
    if (!(vmin <= vmax))
        vmin = vmax = 0.0; /* nothing finite to draw: an empty strip */
    l->margin = MARGIN_FRACTION * d.width;
    l->scale = (d.width - 2.0 * l->margin) / umax;
    l->vmax = vmax;
    double ph = ceil((vmax - vmin) * l->scale + 2.0 * l->margin - 1e-9);
    if (!(ph <= MAX_SIDE)) {
        snprintf(err, err_size,
                 "the plot would be %u x %.0f, over the limit of %u a side: lower the dilation (%g) or the tilt",
                 d.width, ph, MAX_SIDE, d.dilation);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    l->picture_width = d.width;
    l->picture_height = ph < 1.0 ? 1 : (uint32_t)ph;
    l->field_width = width;
    l->field_height = height;
    return FRT_SUCCESS;
}

void frt_profiles_point(const frt_profiles_layout *l, double x, double y, double hv, double *px, double *py)
{
    double u = 1.5 * x + 0.25 * y;
    double v = l->desc.tilt * (0.25 * y + 1.5 * l->desc.dilation * hv);
    *px = l->margin + u * l->scale;
    *py = l->margin + (l->vmax - v) * l->scale;
}

/* ---- the floating horizon ---- */

/* In device coordinates: X to the right, and "up" U = -Y (so that higher is larger). The horizon is sampled at
 * X = k / HORIZON_SAMPLES and linear between samples; NO_HORIZON where nothing has been drawn yet. */
typedef struct horizon {
    double *h;
    size_t n;
} horizon;

static double horizon_at(const horizon *hz, double x)
{
    double q = x * HORIZON_SAMPLES;
    size_t k = q <= 0.0 ? 0 : (size_t)q;
    if (k > hz->n - 2)
        k = hz->n - 2;
    double t = q - (double)k;
    return hz->h[k] + t * (hz->h[k + 1] - hz->h[k]);
}

/* A growable list of polylines: the visible runs of one profile. */
typedef struct runs {
    double *xy; /* x0 y0 x1 y1 ... in device coordinates (Y down) */
    size_t n, cap;
    size_t *start; /* first point of each run; a run ends where the next starts */
    size_t nruns, runs_cap;
    bool oom;
} runs;

static void runs_point(runs *r, double x, double u)
{
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 4096;
        double *p = realloc(r->xy, cap * 2 * sizeof *p);
        if (!p) {
            r->oom = true;
            return;
        }
        r->xy = p;
        r->cap = cap;
    }
    r->xy[2 * r->n] = x;
    r->xy[2 * r->n + 1] = -u;
    ++r->n;
}

static void runs_begin(runs *r, double x, double u)
{
    if (r->nruns == r->runs_cap) {
        size_t cap = r->runs_cap ? 2 * r->runs_cap : 256;
        size_t *p = realloc(r->start, cap * sizeof *p);
        if (!p) {
            r->oom = true;
            return;
        }
        r->start = p;
        r->runs_cap = cap;
    }
    r->start[r->nruns++] = r->n;
    runs_point(r, x, u);
}

/* Appends the visible runs of the polyline (x[i], u[i]), i < m, x increasing: the parts strictly above the horizon.
 * Events are the polyline's vertices and the horizon's samples; between two events both are linear, so each
 * change of visibility is placed exactly where the two cross. */
static void trace_piece(const horizon *hz, const double *x, const double *u, size_t m, runs *out)
{
    double px = x[0], pu = u[0], pd = pu - horizon_at(hz, px);
    bool vis = pd > 0.0;
    if (vis)
        runs_begin(out, px, pu);
    for (size_t i = 0; i + 1 < m; ++i) {
        double x0 = x[i], u0 = u[i], x1 = x[i + 1], u1 = u[i + 1];
        double slope = (u1 - u0) / (x1 - x0);
        double kf0 = floor(x0 * HORIZON_SAMPLES) + 1.0, kf1 = ceil(x1 * HORIZON_SAMPLES) - 1.0;
        size_t k = kf0 < 0.0 ? 0 : (size_t)kf0;
        size_t kend = kf1 < 0.0 ? 0 : (size_t)kf1;
        if (kend > hz->n - 1)
            kend = hz->n - 1;
        for (;; ++k) {
            bool vertex = k > kend || kf1 < kf0;
            double ex, eu, ed;
            if (!vertex) {
                ex = (double)k / HORIZON_SAMPLES;
                eu = u0 + (ex - x0) * slope;
                ed = eu - hz->h[k];
            } else {
                ex = x1;
                eu = u1;
                ed = eu - horizon_at(hz, ex);
            }
            bool evis = ed > 0.0;
            if (evis != vis) {
                double t = pd / (pd - ed);
                double cx = px + t * (ex - px), cu = pu + t * (eu - pu);
                if (vis)
                    runs_point(out, cx, cu);
                else
                    runs_begin(out, cx, cu);
                vis = evis;
            }
            if (vertex && vis)
                runs_point(out, ex, eu);
            px = ex;
            pu = eu;
            pd = ed;
            if (vertex)
                break;
        }
    }
}

/* Raises the horizon over the polyline so that it lies on or above it everywhere: the samples take the polyline's
 * value, and where a vertex (a peak between samples) is still above the interpolated horizon, the two samples
 * around it rise by the difference. Without the second step a sharp peak narrower than a sample would let the
 * lines behind show through its tip. */
static void raise_piece(horizon *hz, const double *x, const double *u, size_t m)
{
    for (size_t i = 0; i + 1 < m; ++i) {
        double x0 = x[i], u0 = u[i], x1 = x[i + 1], u1 = u[i + 1];
        double slope = (u1 - u0) / (x1 - x0);
        double kf0 = ceil(x0 * HORIZON_SAMPLES), kf1 = floor(x1 * HORIZON_SAMPLES);
        if (kf0 < 0.0)
            kf0 = 0.0;
        if (kf1 > (double)(hz->n - 1))
            kf1 = (double)(hz->n - 1);
        for (size_t k = (size_t)kf0; (double)k <= kf1; ++k) {
            double v = u0 + ((double)k / HORIZON_SAMPLES - x0) * slope;
            if (v > hz->h[k])
                hz->h[k] = v;
        }
    }
    for (size_t i = 0; i < m; ++i) {
        double q = x[i] * HORIZON_SAMPLES;
        size_t k = q <= 0.0 ? 0 : (size_t)q;
        if (k > hz->n - 2)
            k = hz->n - 2;
        /* A sample beyond the polyline's end (undrawn) starts at the end vertex's height: the horizon then extends
         * less than one sample past the polyline. */
        if (hz->h[k] <= NO_HORIZON)
            hz->h[k] = u[i];
        if (hz->h[k + 1] <= NO_HORIZON)
            hz->h[k + 1] = u[i];
        double t = q - (double)k;
        double below = u[i] - (hz->h[k] + t * (hz->h[k + 1] - hz->h[k]));
        if (below > 0.0) {
            hz->h[k] += below;
            hz->h[k + 1] += below;
        }
    }
}

/* ---- drawing ---- */

/* How a target wants its ink: rasters are A8 surfaces holding the grey value itself (paper = alpha 1, ink removes
 * it with DEST_OUT), so the picture is copied out, or written as a grey PNG, without conversion; vector targets
 * get ordinary opaque black lines and grey faces. */
typedef struct ink {
    bool raster;
} ink;

static void set_ink(cairo_t *cr, const ink *k, double grey)
{
    if (k->raster) {
        cairo_set_operator(cr, CAIRO_OPERATOR_DEST_OUT);
        cairo_set_source_rgba(cr, 0, 0, 0, 1.0 - grey);
    } else {
        cairo_set_operator(cr, CAIRO_OPERATOR_OVER);
        cairo_set_source_rgb(cr, grey, grey, grey);
    }
}

/* Strokes the runs, dropping vertices that the eye cannot see: a vertex is skipped while every point since the last
 * kept one stays within SIMPLIFY_TOLERANCE (vertically, in device units) of the segment from the kept one to the
 * next candidate. Runs are monotone in x, so the test is a window of allowed slopes narrowed point by point (O(n)).
 * A 4097-column field on a 1200-wide page has 3-4 vertices per pixel: at 0.1 px (or pt, 0.035 mm) the SVG of such a
 * plot shrinks from 21 to 12 MB, and the deviation stays far below what anti-aliasing or print can show. */
#define SIMPLIFY_TOLERANCE 0.1
static void stroke_runs(cairo_t *cr, const runs *r)
{
    for (size_t i = 0; i < r->nruns; ++i) {
        size_t a = r->start[i], b = i + 1 < r->nruns ? r->start[i + 1] : r->n;
        if (b - a < 2)
            continue;
        const double *p = r->xy;
        size_t anchor = a;
        double lo = -INFINITY, hi = INFINITY; /* slopes from the anchor that keep the skipped points in */
        cairo_move_to(cr, p[2 * a], p[2 * a + 1]);
        for (size_t j = a + 1; j < b; ++j) {
            double dx = p[2 * j] - p[2 * anchor], dy = p[2 * j + 1] - p[2 * anchor + 1];
            if (dx <= 0.0) { /* coincident x (a crossing on a vertex): keep it */
                cairo_line_to(cr, p[2 * j], p[2 * j + 1]);
                anchor = j;
                lo = -INFINITY;
                hi = INFINITY;
                continue;
            }
            double slope = dy / dx;
            if (j > anchor + 1 && (slope < lo || slope > hi)) {
                /* p[j] cannot be reached without leaving a skipped point behind: keep p[j-1] */
                cairo_line_to(cr, p[2 * (j - 1)], p[2 * (j - 1) + 1]);
                anchor = j - 1;
                dx = p[2 * j] - p[2 * anchor];
                dy = p[2 * j + 1] - p[2 * anchor + 1];
                lo = -INFINITY;
                hi = INFINITY;
                if (dx <= 0.0) {
                    cairo_line_to(cr, p[2 * j], p[2 * j + 1]);
                    anchor = j;
                    continue;
                }
            }
            double l = (dy - SIMPLIFY_TOLERANCE) / dx, h = (dy + SIMPLIFY_TOLERANCE) / dx;
            lo = l > lo ? l : lo;
            hi = h < hi ? h : hi;
        }
        if (anchor != b - 1)
            cairo_line_to(cr, p[2 * (b - 1)], p[2 * (b - 1) + 1]);
    }
    cairo_stroke(cr);
}

/* Device points (x, up) of the field row `row_y` (or, `column` true, of the right column from y = y0 to y1) into
 * px/pu, starting at index *from and skipping leading non-finite heights. Returns the number of points written: up
 * to the next non-finite height, past which *from is left (so that a caller loops over the finite pieces), or with
 * `bridge` all the finite points to the end, the gaps closed as the base's faces close them. */
static size_t next_piece(const frt_profiles_layout *l, const float *h, bool column, uint32_t row_y, uint32_t y0,
                         uint32_t y1, bool bridge, uint32_t *from, double *px, double *pu)
{
    const uint32_t W = l->field_width, H = l->field_height;
    uint32_t end = column ? y1 - y0 + 1 : W;
    uint32_t i = *from;
    size_t m = 0;
    for (; i < end; ++i) {
        uint32_t y = column ? y0 + i : row_y;
        uint32_t x = column ? W - 1 : i;
        float hv = h[(size_t)(H - 1 - y) * W + x];
        if (!isfinite(hv)) {
            if (m == 0 || bridge)
                continue;
            break;
        }
        double X, Y;
        frt_profiles_point(l, x, y, hv, &X, &Y);
        px[m] = X;
        pu[m] = -Y;
        ++m;
    }
    *from = i;
    return m;
}

/* The solid base ("stratum"): the front face under the front profile and the right face under the right column,
 * down to z = zbase, filled light grey. Both face the viewer and nothing stands in front of them, so they are
 * drawn whole; the lines come later. */
static void base_faces(cairo_t *cr, const frt_profiles_layout *l, const float *h, const ink *k)
{
    const uint32_t W = l->field_width, H = l->field_height;
    const double zb = l->zbase / l->desc.dilation; /* as a height, for frt_profiles_point */
    double X, Y;
    bool first = true;
    for (uint32_t x = 0; x < W; ++x) { /* front face: the front row, then back along the floor */
        float hv = h[(size_t)(H - 1) * W + x];
        if (!isfinite(hv))
            continue;
        frt_profiles_point(l, x, 0, hv, &X, &Y);
        if (first)
            cairo_move_to(cr, X, Y);
        else
            cairo_line_to(cr, X, Y);
        first = false;
    }
    frt_profiles_point(l, W - 1, 0, zb, &X, &Y);
    first ? cairo_move_to(cr, X, Y) : cairo_line_to(cr, X, Y);
    frt_profiles_point(l, 0, 0, zb, &X, &Y);
    cairo_line_to(cr, X, Y);
    cairo_close_path(cr);
    first = true;
    for (uint32_t y = 0; y <= l->back_y; ++y) { /* right face: the right column, then forward along the floor */
        float hv = h[(size_t)(H - 1 - y) * W + (W - 1)];
        if (!isfinite(hv))
            continue;
        frt_profiles_point(l, W - 1, y, hv, &X, &Y);
        if (first)
            cairo_move_to(cr, X, Y);
        else
            cairo_line_to(cr, X, Y);
        first = false;
    }
    frt_profiles_point(l, W - 1, l->back_y, zb, &X, &Y);
    first ? cairo_move_to(cr, X, Y) : cairo_line_to(cr, X, Y);
    frt_profiles_point(l, W - 1, 0, zb, &X, &Y);
    cairo_line_to(cr, X, Y);
    cairo_close_path(cr);
    set_ink(cr, k, FACE_GREY);
    cairo_fill(cr);
}

/* The base's outline: its top edge along the right column, the floor edges and the three visible vertical edges. */
static void base_outline(cairo_t *cr, const frt_profiles_layout *l, const float *h)
{
    const uint32_t W = l->field_width, H = l->field_height;
    const double zb = l->zbase / l->desc.dilation;
    double X, Y;
    bool drawing = false;
    for (uint32_t y = 0; y <= l->back_y; ++y) {
        float hv = h[(size_t)(H - 1 - y) * W + (W - 1)];
        if (!isfinite(hv)) {
            drawing = false;
            continue;
        }
        frt_profiles_point(l, W - 1, y, hv, &X, &Y);
        drawing ? cairo_line_to(cr, X, Y) : cairo_move_to(cr, X, Y);
        drawing = true;
    }
    /* floor: front-left, front-right, back-right */
    frt_profiles_point(l, 0, 0, zb, &X, &Y);
    cairo_move_to(cr, X, Y);
    frt_profiles_point(l, W - 1, 0, zb, &X, &Y);
    cairo_line_to(cr, X, Y);
    frt_profiles_point(l, W - 1, l->back_y, zb, &X, &Y);
    cairo_line_to(cr, X, Y);
    /* verticals up to the corners' heights (to the floor's top where a corner is not finite) */
    const uint32_t cx[3] = {0, W - 1, W - 1}, cy[3] = {0, 0, l->back_y};
    for (int c = 0; c < 3; ++c) {
        float hv = h[(size_t)(H - 1 - cy[c]) * W + cx[c]];
        if (!isfinite(hv))
            continue;
        frt_profiles_point(l, cx[c], cy[c], zb, &X, &Y);
        cairo_move_to(cr, X, Y);
        frt_profiles_point(l, cx[c], cy[c], hv, &X, &Y);
        cairo_line_to(cr, X, Y);
    }
    cairo_stroke(cr);
}

/* Draws the whole plot on `cr` (device units = pixels or points). Returns FRT_ERROR_OUT_OF_MEMORY when a buffer
 * cannot be had; cairo's own state is checked by the caller. */
static frt_result draw_plot(cairo_t *cr, const frt_profiles_layout *l, const float *h, bool raster)
{
    const uint32_t W = l->field_width;
    const uint32_t K = l->desc.every;
    const bool base = l->desc.base > 0.0;
    ink k = {raster};
    frt_result r = FRT_SUCCESS;
    horizon hz = {0};
    runs rs = {0};
    size_t side = W > l->back_y + 1 ? W : l->back_y + 1;
    double *px = malloc(side * sizeof *px), *pu = malloc(side * sizeof *pu);
    hz.n = (size_t)ceil(l->picture_width * HORIZON_SAMPLES) + 2;
    hz.h = malloc(hz.n * sizeof *hz.h);
    if (!px || !pu || !hz.h) {
        r = FRT_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    for (size_t i = 0; i < hz.n; ++i)
        hz.h[i] = NO_HORIZON;

    /* paper */
    cairo_set_operator(cr, CAIRO_OPERATOR_OVER);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    if (base)
        base_faces(cr, l, h, &k);
    cairo_set_line_width(cr, l->desc.line_width);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    set_ink(cr, &k, 0.0);

    /* Front to back. Each profile shows where it rises above everything drawn before it; then it and the right
     * column up to the next profile (the terrain's right edge, which hides the ends of the profiles behind it)
     * raise the horizon. With a base, the front profile and the right column raise it with their gaps (non-finite
     * heights) bridged, as the faces' filled tops bridge them: nothing may show through a face. */
    for (uint32_t p = 0; p < l->rows; ++p) {
        uint32_t y = p * K;
        rs.n = rs.nruns = 0;
        for (uint32_t from = 0; from < W;) {
            size_t m = next_piece(l, h, false, y, 0, 0, false, &from, px, pu);
            if (m >= 2)
                trace_piece(&hz, px, pu, m, &rs);
        }
        if (rs.oom) {
            r = FRT_ERROR_OUT_OF_MEMORY;
            goto done;
        }
        stroke_runs(cr, &rs);
        for (uint32_t from = 0; from < W;) {
            size_t m = next_piece(l, h, false, y, 0, 0, base && p == 0, &from, px, pu);
            if (m >= 2)
                raise_piece(&hz, px, pu, m);
        }
        if (p + 1 < l->rows)
            for (uint32_t from = 0; from <= K;) {
                size_t m = next_piece(l, h, true, 0, y, y + K, base, &from, px, pu);
                if (m >= 2)
                    raise_piece(&hz, px, pu, m);
            }
    }
    if (base)
        base_outline(cr, l, h);
done:
    free(px);
    free(pu);
    free(hz.h);
    free(rs.xy);
    free(rs.start);
    return r;
}

static frt_result cairo_result(cairo_status_t s)
{
    if (s == CAIRO_STATUS_SUCCESS)
        return FRT_SUCCESS;
    if (s == CAIRO_STATUS_NO_MEMORY)
        return FRT_ERROR_OUT_OF_MEMORY;
    if (s == CAIRO_STATUS_WRITE_ERROR)
        return FRT_ERROR_IO;
    return FRT_ERROR_INVALID_ARGUMENT;
}

/* Renders to an A8 image surface (grey = alpha, see `ink`). */
static frt_result render_raster(const frt_profiles_layout *l, const float *h, cairo_surface_t **out)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_A8, (int)l->picture_width, (int)l->picture_height);
    frt_result r = cairo_result(cairo_surface_status(s));
    if (r == FRT_SUCCESS) {
        cairo_t *cr = cairo_create(s);
        r = cairo_result(cairo_status(cr));
        if (r == FRT_SUCCESS)
            r = draw_plot(cr, l, h, true);
        if (r == FRT_SUCCESS)
            r = cairo_result(cairo_status(cr));
        cairo_destroy(cr);
        cairo_surface_flush(s);
    }
    if (r != FRT_SUCCESS) {
        cairo_surface_destroy(s);
        s = NULL;
    }
    *out = s;
    return r;
}

frt_result frt_profiles_size(const float *h, uint32_t width, uint32_t height, const frt_profiles_desc *desc,
                             uint32_t *picture_width, uint32_t *picture_height)
{
    if (!picture_width || !picture_height)
        return FRT_ERROR_INVALID_ARGUMENT;
    *picture_width = *picture_height = 0;
    frt_profiles_layout l;
    char err[256];
    frt_result r = frt_profiles_layout_compute(h, width, height, desc, &l, err, sizeof err);
    if (r != FRT_SUCCESS)
        return r;
    *picture_width = l.picture_width;
    *picture_height = l.picture_height;
    return FRT_SUCCESS;
}

frt_result frt_profiles(const float *h, uint32_t width, uint32_t height, const frt_profiles_desc *desc, uint8_t *out,
                        uint32_t picture_width, uint32_t picture_height)
{
    frt_profiles_layout l;
    char err[256];
    frt_result r = frt_profiles_layout_compute(h, width, height, desc, &l, err, sizeof err);
    if (r != FRT_SUCCESS)
        return r;
    if (!out || picture_width != l.picture_width || picture_height != l.picture_height)
        return FRT_ERROR_INVALID_ARGUMENT;
    cairo_surface_t *s;
    r = render_raster(&l, h, &s);
    if (r != FRT_SUCCESS)
        return r;
    const unsigned char *data = cairo_image_surface_get_data(s);
    int stride = cairo_image_surface_get_stride(s);
    for (uint32_t y = 0; y < picture_height; ++y)
        memcpy(out + (size_t)y * picture_width, data + (size_t)y * (size_t)stride, picture_width);
    cairo_surface_destroy(s);
    return FRT_SUCCESS;
}

static cairo_status_t write_stream(void *closure, const unsigned char *data, unsigned int length)
{
    return fwrite(data, 1, length, (FILE *)closure) == length ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

frt_result frt_write_profiles(const char *path, const float *h, uint32_t width, uint32_t height,
                              const frt_profiles_desc *desc, char *err, size_t err_size)
{
    char dummy[1];
    if (!err) {
        err = dummy;
        err_size = sizeof dummy;
    }
    if (!path || !*path) {
        snprintf(err, err_size, "no output path");
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (dot && slash && dot < slash)
        dot = NULL;
    enum { PNG, SVG, PDF } kind;
    if (dot && strcasecmp(dot, ".png") == 0)
        kind = PNG;
    else if (dot && strcasecmp(dot, ".svg") == 0)
        kind = SVG;
    else if (dot && strcasecmp(dot, ".pdf") == 0)
        kind = PDF;
    else {
        snprintf(err, err_size, "cannot write '%s': a profile plot is written as .png, .svg or .pdf", path);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    frt_profiles_layout l;
    char why[512];
    frt_result r = frt_profiles_layout_compute(h, width, height, desc, &l, why, sizeof why);
    if (r != FRT_SUCCESS) {
        snprintf(err, err_size, "cannot write '%s': %s", path, why);
        return r;
    }
    frt_atomic_file af;
    r = frt_atomic_open(&af, path, err, err_size);
    if (r != FRT_SUCCESS)
        return r;
    const char *what = "drawing";
    if (kind == PNG) {
        cairo_surface_t *s;
        r = render_raster(&l, h, &s);
        if (r == FRT_SUCCESS) {
            what = "writing";
            r = cairo_result(cairo_surface_write_to_png_stream(s, write_stream, af.fp));
            cairo_surface_destroy(s);
        }
    } else {
        cairo_surface_t *s =
            kind == SVG ? cairo_svg_surface_create_for_stream(write_stream, af.fp, l.picture_width, l.picture_height)
                        : cairo_pdf_surface_create_for_stream(write_stream, af.fp, l.picture_width, l.picture_height);
        r = cairo_result(cairo_surface_status(s));
        if (r == FRT_SUCCESS) {
            cairo_t *cr = cairo_create(s);
            r = draw_plot(cr, &l, h, false);
            if (r == FRT_SUCCESS)
                r = cairo_result(cairo_status(cr));
            cairo_destroy(cr);
            cairo_surface_finish(s); /* the vector file is written out here */
            what = "writing";
            if (r == FRT_SUCCESS)
                r = cairo_result(cairo_surface_status(s));
        }
        cairo_surface_destroy(s);
    }
    if (r != FRT_SUCCESS) {
        snprintf(err, err_size, "%s '%s' failed: %s", what, path, frt_result_string(r));
        frt_atomic_abort(&af);
        return r;
    }
    return frt_atomic_commit(&af, err, err_size);
}
