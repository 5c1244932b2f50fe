/* format_obj.c — Wavefront OBJ triangle mesh of a heightfield: "v", "vn" per vertex, "f a//a b//b c//c"; read back
 * when the vertices form the grid fracterra writes (formats.c, frt_grid_add). */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#define LINE_MAX_BYTES 65536

/* Decimal digits of v at o; returns the end. */
static char *put_index(char *o, uint64_t v)
{
    char d[20];
    int n = 0;
    do
        d[n++] = (char)('0' + v % 10);
    while ((v /= 10) != 0);
    while (n)
        *o++ = d[--n];
    return o;
}

frt_result frt_obj_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    char lines[2][256];
    frt_mesh_comments(f, lines);
    char *json = frt_meta_json(f, FRT_JSON_LINE);
    if (!json)
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, f->name, ": out of memory");
    frt_wr w = {fp, 0};
    frt_wr_printf(&w, "# %s\n# %s\n# fracterra params %s\n", lines[0], lines[1], json);
    free(json);
    uint32_t W = frt_mesh_side(f->width, f->mesh_stride), H = frt_mesh_side(f->height, f->mesh_stride);
    /* %.9g: every float reads back as itself. */
    for (uint32_t j = 0; j < H && !w.errnum; ++j)
        for (uint32_t i = 0; i < W; ++i) {
            float p[3], n[3];
            frt_mesh_vertex(f, i, j, p, n);
            frt_wr_printf(&w, "v %.9g %.9g %.9g\nvn %.9g %.9g %.9g\n", (double)p[0], (double)p[1], (double)p[2],
                          (double)n[0], (double)n[1], (double)n[2]);
        }
    /* Two triangles per cell, counter-clockwise seen from +z (north is +y): SW SE NE and SW NE NW. Formatted by
     * hand: faces are most of the file, and printf would take most of the time. */
    char line[160];
    for (uint32_t j = 0; j + 1 < H && !w.errnum; ++j)
        for (uint32_t i = 0; i + 1 < W; ++i) {
            uint64_t nw = (uint64_t)j * W + i + 1, ne = nw + 1, sw = nw + W, se = sw + 1;
            const uint64_t tri[6] = {sw, se, ne, sw, ne, nw};
            char *o = line;
            for (int t = 0; t < 6; ++t) {
                if (t % 3 == 0)
                    *o++ = 'f';
                *o++ = ' ';
                o = put_index(o, tri[t]);
                *o++ = '/', *o++ = '/';
                o = put_index(o, tri[t]);
                if (t % 3 == 2)
                    *o++ = '\n';
            }
            frt_wr_bytes(&w, line, (size_t)(o - line));
        }
    return frt_wr_finish(&w, f->name, err, err_size);
}

static bool is_blank(char c)
{
    return c == ' ' || c == '\t';
}

static frt_result bad_line(frt_rd *rd, unsigned long long line, const char *why)
{
    if (rd->line_at_end) /* a broken last line without its "\n": the file was cut */
        return frt_rd_truncated(rd, "in its last line");
    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, ": line %llu: %s", line, why);
}

static frt_result obj_read_lines(frt_rd *rd, char *line, frt_grid_rd *g, frt_field_info *info)
{
    unsigned long long lineno = 0, vertices = 0, faces = 0;
    frt_meta_extra params = {0};
    for (;;) {
        long len = frt_rd_line(rd, line, LINE_MAX_BYTES);
        if (len == -1)
            break;
        ++lineno;
        if (len == -2)
            return bad_line(rd, lineno, "longer than 64 KiB");
        const char *s = line;
        while (is_blank(*s))
            ++s;
        if (s[0] == '#') {
            ++s;
            while (is_blank(*s))
                ++s;
            /* Metadata only: damaged parameters are left unknown rather than making the heights unreadable. */
            if (strncmp(s, "fracterra params ", 17) == 0 &&
                frt_meta_parse(s + 17, strlen(s + 17), info, &params, rd->name, "its parameters", NULL, 0) != 0)
                memset(&params, 0, sizeof params);
        } else if (s[0] == 'v' && is_blank(s[1])) {
            double c[3];
            const char *p = s + 2;
            for (int k = 0; k < 3; ++k) {
                char *end;
                c[k] = strtod(p, &end);
                if (end == p || (*end && !is_blank(*end)))
                    return bad_line(rd, lineno, "a vertex needs three numbers x y z");
                p = end;
            }
            frt_result r = frt_grid_add(g, rd, c[0], c[1], c[2]);
            if (r != FRT_SUCCESS)
                return r;
            ++vertices;
        } else if (s[0] == 'f' && is_blank(s[1])) {
            /* Faces are not needed for the heights, but a face that names a missing vertex means a broken file. */
            const char *p = s + 2;
            int refs = 0;
            for (;;) {
                while (is_blank(*p))
                    ++p;
                if (!*p)
                    break;
                char *end;
                long long v = strtoll(p, &end, 10);
                if (end == p || (*end && *end != '/' && !is_blank(*end)))
                    return bad_line(rd, lineno, "a face needs vertex numbers");
                if (v == 0 || (v > 0 && (unsigned long long)v > vertices) || (v < 0 && v < -(long long)vertices))
                    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                                    ": line %llu: a face refers to vertex %lld, but %llu are defined before it", lineno,
                                    v, vertices);
                ++refs;
                p = end;
                while (*p && !is_blank(*p))
                    ++p;
            }
            if (refs < 3)
                return bad_line(rd, lineno, "a face needs at least three vertices");
            ++faces;
        }
    }
    if (rd->read_errno)
        return frt_rd_truncated(rd, "");
    /* OBJ has no counts; when fracterra's own header gives the grid, a file cut at a line still shows. */
    if (params.has_size && params.mesh_stride) {
        unsigned long long W = frt_mesh_side(params.width, params.mesh_stride);
        unsigned long long H = frt_mesh_side(params.height, params.mesh_stride);
        if (vertices != W * H || faces != 2 * (W - 1) * (H - 1))
            return frt_fail(rd->err, rd->err_size, FRT_ERROR_IO, rd->name,
                            " is truncated or damaged (its header says %llu x %llu vertices and %llu triangles; it "
                            "has %llu vertices and %llu faces)",
                            W, H, 2 * (W - 1) * (H - 1), vertices, faces);
    }
    return FRT_SUCCESS;
}

frt_result frt_obj_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count)
{
    char *line = malloc(LINE_MAX_BYTES);
    if (!line)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
    frt_grid_rd g;
    memset(&g, 0, sizeof g);
    g.out = out;
    g.out_count = out_count;
    info->bits = 32;
    frt_result r = obj_read_lines(rd, line, &g, info);
    free(line);
    if (r != FRT_SUCCESS) {
        frt_grid_free(&g);
        return r;
    }
    return frt_grid_finish(&g, rd, info);
}
