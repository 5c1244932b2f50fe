/* format_ply.c — PLY triangle mesh of a heightfield: written binary little-endian (float x y z nx ny nz, uchar/int
 * faces); read as ascii or binary of either byte order with any scalar vertex properties, and read back when the
 * vertices form the grid fracterra writes (formats.c, frt_grid_add). http://paulbourke.net/dataformats/ply/ */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LINE_MAX_BYTES 65536
#define MAX_ELEMENTS 16
#define MAX_PROPS 32

/* ---- writing ---- */

static void put_f32(uint8_t *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, 4);
    frt_put_le32(p, u);
}

frt_result frt_ply_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size)
{
    uint32_t W = frt_mesh_side(f->width, f->mesh_stride), H = frt_mesh_side(f->height, f->mesh_stride);
    uint64_t vertices = (uint64_t)W * H, faces = 2 * (uint64_t)(W - 1) * (H - 1);
    if (vertices - 1 > INT32_MAX)
        return frt_fail(err, err_size, FRT_ERROR_TOO_LARGE, f->name,
                        ": %llu vertices are more than PLY's int indices can name; thin the mesh with a larger stride",
                        (unsigned long long)vertices);
    char lines[2][256];
    frt_mesh_comments(f, lines);
    char *json = frt_meta_json(f, FRT_JSON_LINE);
    uint8_t *buf = malloc(1024 * 24);
    if (!json || !buf) {
        free(json);
        free(buf);
        return frt_fail(err, err_size, FRT_ERROR_OUT_OF_MEMORY, f->name, ": out of memory");
    }
    frt_wr w = {fp, 0};
    /* The counts before the long parameters line, so that the first few hundred bytes tell what the file holds. */
    frt_wr_printf(
        &w,
        "ply\nformat binary_little_endian 1.0\ncomment %s\ncomment %s\n"
        "element vertex %llu\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "element face %llu\nproperty list uchar int vertex_indices\ncomment fracterra params %s\nend_header\n",
        lines[0], lines[1], (unsigned long long)vertices, (unsigned long long)faces, json);
    free(json);
    size_t n = 0;
    for (uint32_t j = 0; j < H && !w.errnum; ++j)
        for (uint32_t i = 0; i < W; ++i) {
            float p[3], nrm[3];
            frt_mesh_vertex(f, i, j, p, nrm);
            uint8_t *o = buf + 24 * n;
            for (int k = 0; k < 3; ++k) {
                put_f32(o + 4 * k, p[k]);
                put_f32(o + 12 + 4 * k, nrm[k]);
            }
            if (++n == 1024) {
                frt_wr_bytes(&w, buf, 24 * n);
                n = 0;
            }
        }
    frt_wr_bytes(&w, buf, 24 * n);
    n = 0;
    /* Two triangles per cell, counter-clockwise seen from +z (north is +y): SW SE NE and SW NE NW. */
    for (uint32_t j = 0; j + 1 < H && !w.errnum; ++j)
        for (uint32_t i = 0; i + 1 < W; ++i) {
            uint32_t nw = j * W + i, ne = nw + 1, sw = nw + W, se = sw + 1;
            uint32_t tri[2][3] = {{sw, se, ne}, {sw, ne, nw}};
            for (int t = 0; t < 2; ++t) {
                uint8_t *o = buf + 13 * n++;
                o[0] = 3;
                for (int k = 0; k < 3; ++k)
                    frt_put_le32(o + 1 + 4 * k, tri[t][k]);
            }
            if (n >= 1024) {
                frt_wr_bytes(&w, buf, 13 * n);
                n = 0;
            }
        }
    frt_wr_bytes(&w, buf, 13 * n);
    free(buf);
    return frt_wr_finish(&w, f->name, err, err_size);
}

/* ---- reading ---- */

typedef enum ply_type { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

static const struct {
    const char *name, *alias;
    unsigned size;
} ply_types[] = {{"", "", 0},           {"char", "int8", 1},     {"uchar", "uint8", 1},
                 {"short", "int16", 2}, {"ushort", "uint16", 2}, {"int", "int32", 4},
                 {"uint", "uint32", 4}, {"float", "float32", 4}, {"double", "float64", 8}};

typedef struct ply_prop {
    char name[64];
    ply_type type;       /* of the value, or of the list items */
    ply_type count_type; /* T_NONE: a scalar */
} ply_prop;

typedef struct ply_element {
    char name[64];
    uint64_t count;
    ply_prop props[MAX_PROPS];
    int n_props;
} ply_element;

enum { PLY_ASCII = 1, PLY_LE, PLY_BE };

typedef struct ply_file {
    int format;
    ply_element el[MAX_ELEMENTS];
    int n_el;
} ply_file;

static ply_type type_of(const char *s)
{
    for (int t = T_I8; t <= T_F64; ++t)
        if (strcmp(s, ply_types[t].name) == 0 || strcmp(s, ply_types[t].alias) == 0)
            return (ply_type)t;
    return T_NONE;
}

/* Splits a header line into at most `max` blank-separated words (in place). */
static int split(char *s, char **words, int max)
{
    int n = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t')
            *s++ = '\0';
        if (!*s || n == max)
            return n;
        words[n++] = s;
        while (*s && *s != ' ' && *s != '\t')
            ++s;
    }
}

static frt_result bad_header(frt_rd *rd, unsigned line, const char *why)
{
    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, ": header line %u: %s", line, why);
}

static frt_result ply_header(frt_rd *rd, char *line, ply_file *pf, frt_field_info *info)
{
    frt_result r = frt_rd_magic(rd, "ply", 3, "a PLY file");
    if (r != FRT_SUCCESS)
        return r;
    for (unsigned lineno = 1;; ++lineno) {
        long len = frt_rd_line(rd, line, LINE_MAX_BYTES);
        if (len == -1)
            return frt_rd_truncated(rd, "in its header");
        if (len == -2)
            return bad_header(rd, lineno, "longer than 64 KiB");
        if (lineno == 1) {
            if (len != 0)
                return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name, " is not a PLY file");
            continue;
        }
        if (strncmp(line, "comment", 7) == 0 || strncmp(line, "obj_info", 8) == 0) {
            const char *s = line;
            while (*s && *s != ' ' && *s != '\t')
                ++s;
            while (*s == ' ' || *s == '\t')
                ++s;
            /* Metadata only: damaged parameters are left unknown rather than making the heights unreadable. */
            if (strncmp(s, "fracterra params ", 17) == 0) {
                frt_meta_extra ex;
                frt_meta_parse(s + 17, strlen(s + 17), info, &ex, rd->name, "its parameters", NULL, 0);
            }
            continue;
        }
        char *w[6];
        int n = split(line, w, 6);
        if (n == 0)
            continue;
        if (strcmp(w[0], "end_header") == 0 && n == 1)
            return pf->format ? FRT_SUCCESS : bad_header(rd, lineno, "end_header before the format line");
        if (strcmp(w[0], "format") == 0 && n == 3) {
            if (strcmp(w[2], "1.0") != 0)
                return bad_header(rd, lineno, "only PLY version 1.0 is supported");
            pf->format = strcmp(w[1], "ascii") == 0                  ? PLY_ASCII
                         : strcmp(w[1], "binary_little_endian") == 0 ? PLY_LE
                         : strcmp(w[1], "binary_big_endian") == 0    ? PLY_BE
                                                                     : 0;
            if (!pf->format)
                return bad_header(rd, lineno, "the format is not ascii, binary_little_endian or binary_big_endian");
        } else if (strcmp(w[0], "element") == 0 && n == 3) {
            if (pf->n_el == MAX_ELEMENTS)
                return bad_header(rd, lineno, "more than 16 elements");
            ply_element *e = &pf->el[pf->n_el++];
            memset(e, 0, sizeof *e);
            snprintf(e->name, sizeof e->name, "%s", w[1]);
            const char *c = w[2];
            if (!*c)
                return bad_header(rd, lineno, "an element count is not a whole number");
            for (; *c; ++c) {
                if (*c < '0' || *c > '9' || e->count > (UINT64_MAX - 9) / 10)
                    return bad_header(rd, lineno, "an element count is not a whole number");
                e->count = e->count * 10 + (uint64_t)(*c - '0');
            }
        } else if (strcmp(w[0], "property") == 0 && (n == 3 || (n == 5 && strcmp(w[1], "list") == 0))) {
            if (pf->n_el == 0)
                return bad_header(rd, lineno, "a property before any element");
            ply_element *e = &pf->el[pf->n_el - 1];
            if (e->n_props == MAX_PROPS)
                return bad_header(rd, lineno, "more than 32 properties in an element");
            ply_prop *p = &e->props[e->n_props++];
            p->count_type = n == 5 ? type_of(w[2]) : T_NONE;
            p->type = type_of(w[n - 2]);
            snprintf(p->name, sizeof p->name, "%s", w[n - 1]);
            if (p->type == T_NONE || (n == 5 && (p->count_type == T_NONE || p->count_type >= T_F32)))
                return bad_header(rd, lineno, "unknown property type");
        } else {
            return bad_header(rd, lineno, "not a format, element, property, comment or end_header line");
        }
    }
}

static double decode(const uint8_t *b, ply_type t, bool big_endian)
{
    unsigned size = ply_types[t].size;
    uint64_t u = 0;
    for (unsigned i = 0; i < size; ++i)
        u |= (uint64_t)b[big_endian ? i : size - 1 - i] << (8 * (size - 1 - i));
    switch (t) {
    case T_I8: return (double)(int8_t)u;
    case T_U8: return (double)(uint8_t)u;
    case T_I16: return (double)(int16_t)u;
    case T_U16: return (double)(uint16_t)u;
    case T_I32: return (double)(int32_t)u;
    case T_U32: return (double)(uint32_t)u;
    case T_F32: {
        uint32_t b32 = (uint32_t)u;
        float f;
        memcpy(&f, &b32, 4);
        return f;
    }
    case T_F64: {
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    default: return 0.0;
    }
}

/* One value of the data section. */
static frt_result ply_value(frt_rd *rd, int format, ply_type t, double *v)
{
    if (format != PLY_ASCII) {
        uint8_t b[8];
        if (!frt_rd_read(rd, b, ply_types[t].size))
            return frt_rd_truncated(rd, "in its data");
        *v = decode(b, t, format == PLY_BE);
        return FRT_SUCCESS;
    }
    char tok[64];
    size_t n = 0;
    int c;
    do
        c = frt_rd_getc(rd);
    while (c == ' ' || c == '\t' || c == '\n' || c == '\r');
    for (; c >= 0 && c != ' ' && c != '\t' && c != '\n' && c != '\r'; c = frt_rd_getc(rd)) {
        if (n + 1 == sizeof tok)
            return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                            ": a value in its data is longer than 63 characters");
        tok[n++] = (char)c;
    }
    if (n == 0)
        return frt_rd_truncated(rd, "in its data");
    tok[n] = '\0';
    char *end;
    *v = strtod(tok, &end);
    if (*end)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": '%s' in its data is not a number", tok);
    return FRT_SUCCESS;
}

static frt_result ply_data(frt_rd *rd, const ply_file *pf, const ply_element *vertex, const int xyz[3], frt_grid_rd *g)
{
    for (int e = 0; e < pf->n_el; ++e) {
        const ply_element *el = &pf->el[e];
        if (el->n_props == 0)
            continue; /* no data, whatever its count */
        bool is_vertex = el == vertex, is_face = strcmp(el->name, "face") == 0;
        for (uint64_t rec = 0; rec < el->count; ++rec) {
            double pos[3] = {0, 0, 0};
            for (int k = 0; k < el->n_props; ++k) {
                const ply_prop *p = &el->props[k];
                double v;
                frt_result r;
                if (p->count_type == T_NONE) {
                    if ((r = ply_value(rd, pf->format, p->type, &v)) != FRT_SUCCESS)
                        return r;
                    for (int a = 0; a < 3; ++a)
                        if (is_vertex && k == xyz[a])
                            pos[a] = v;
                    continue;
                }
                double count;
                if ((r = ply_value(rd, pf->format, p->count_type, &count)) != FRT_SUCCESS)
                    return r;
                /* Each item takes at least a byte, so a count beyond the bytes left is a cut or broken file. */
                if (!(count >= 0.0) || count != floor(count) || count > (double)frt_rd_left(rd))
                    return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                                    ": %s %llu has a list of %g items", el->name, (unsigned long long)rec + 1, count);
                bool indices =
                    is_face && (strcmp(p->name, "vertex_indices") == 0 || strcmp(p->name, "vertex_index") == 0);
                for (uint64_t i = 0; i < (uint64_t)count; ++i) {
                    if ((r = ply_value(rd, pf->format, p->type, &v)) != FRT_SUCCESS)
                        return r;
                    if (indices && !(v >= 0.0 && v < (double)vertex->count && v == floor(v)))
                        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                                        ": face %llu refers to vertex %g of %llu", (unsigned long long)rec + 1, v,
                                        (unsigned long long)vertex->count);
                }
            }
            if (is_vertex) {
                frt_result r = frt_grid_add(g, rd, pos[0], pos[1], pos[2]);
                if (r != FRT_SUCCESS)
                    return r;
            }
        }
    }
    return FRT_SUCCESS;
}

static frt_result ply_read_body(frt_rd *rd, char *line, frt_grid_rd *g, frt_field_info *info)
{
    ply_file pf;
    memset(&pf, 0, sizeof pf);
    frt_result r = ply_header(rd, line, &pf, info);
    if (r != FRT_SUCCESS)
        return r;
    const ply_element *vertex = NULL;
    int xyz[3] = {-1, -1, -1};
    for (int e = 0; e < pf.n_el && !vertex; ++e)
        if (strcmp(pf.el[e].name, "vertex") == 0)
            vertex = &pf.el[e];
    static const char *const axes[3] = {"x", "y", "z"};
    for (int k = 0; vertex && k < vertex->n_props; ++k)
        for (int a = 0; a < 3; ++a)
            if (vertex->props[k].count_type == T_NONE && strcmp(vertex->props[k].name, axes[a]) == 0)
                xyz[a] = k;
    if (!vertex || xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_INVALID_ARGUMENT, rd->name,
                        ": it has no vertex element with x, y and z");
    if (vertex->count > FRT_FILE_MAX_POINTS)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_TOO_LARGE, rd->name,
                        ": %llu vertices are more than fracterra reads (2^32)", (unsigned long long)vertex->count);
    info->bits = 8 * ply_types[vertex->props[xyz[2]].type].size;
    /* The least data the header promises: refused before reading when the file is shorter. */
    uint64_t need = 0;
    for (int e = 0; e < pf.n_el; ++e) {
        uint64_t rec = 0;
        for (int k = 0; k < pf.el[e].n_props; ++k) {
            const ply_prop *p = &pf.el[e].props[k];
            rec += pf.format == PLY_ASCII ? 1 : ply_types[p->count_type != T_NONE ? p->count_type : p->type].size;
        }
        if (rec && pf.el[e].count > (UINT64_MAX - need) / rec)
            need = UINT64_MAX;
        else
            need += pf.el[e].count * rec;
    }
    if (need > frt_rd_left(rd))
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_IO, rd->name,
                        " is truncated (its header promises at least %llu bytes of data; %llu are left)",
                        (unsigned long long)need, (unsigned long long)frt_rd_left(rd));
    return ply_data(rd, &pf, vertex, xyz, g);
}

frt_result frt_ply_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count)
{
    char *line = malloc(LINE_MAX_BYTES);
    if (!line)
        return frt_fail(rd->err, rd->err_size, FRT_ERROR_OUT_OF_MEMORY, rd->name, ": out of memory");
    frt_grid_rd g;
    memset(&g, 0, sizeof g);
    g.out = out;
    g.out_count = out_count;
    frt_result r = ply_read_body(rd, line, &g, info);
    free(line);
    if (r != FRT_SUCCESS) {
        frt_grid_free(&g);
        return r;
    }
    return frt_grid_finish(&g, rd, info);
}
