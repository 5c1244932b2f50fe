/* format_gif.c — animated GIF through giflib (GIF89a, Netscape loop extension), written atomically. */
#include "internal.h"

#include <gif_lib.h>
#include <stdlib.h>
#include <string.h>

struct frt_gif_writer {
    frt_atomic_file file;
    GifFileType *gif;
    uint32_t width, height;
    bool failed; /* a write to the temporary file failed (reported by the output callback) */
};

static int write_bytes(GifFileType *gif, const GifByteType *bytes, int n)
{
    frt_gif_writer *g = gif->UserData;
    if (fwrite(bytes, 1, (size_t)n, g->file.fp) != (size_t)n) {
        g->failed = true;
        return 0;
    }
    return n;
}

static frt_result gif_error(frt_gif_writer *g, int code, const char *what, char *err, size_t err_size)
{
    const char *msg = GifErrorString(code);
    snprintf(err, err_size, "writing '%s' failed: %s (%s)", g->file.path ? g->file.path : "GIF", what,
             g->failed ? "the disk write failed"
             : msg     ? msg
                       : "giflib error");
    return FRT_ERROR_IO;
}

frt_result frt_gif_open(frt_gif_writer **out, const char *path, uint32_t width, uint32_t height,
                        const uint8_t palette_rgb[768], char *err, size_t err_size)
{
    *out = NULL;
    if (width == 0 || height == 0 || width > 65535 || height > 65535) {
        snprintf(err, err_size, "'%s': a GIF is 1..65535 pixels a side, not %u x %u", path, width, height);
        return FRT_ERROR_INVALID_ARGUMENT;
    }
    frt_gif_writer *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(err, err_size, "out of memory");
        return FRT_ERROR_OUT_OF_MEMORY;
    }
    frt_result r = frt_atomic_open(&g->file, path, err, err_size);
    if (r != FRT_SUCCESS) {
        free(g);
        return r;
    }
    g->width = width;
    g->height = height;
    int code = 0;
    g->gif = EGifOpen(g, write_bytes, &code);
    if (!g->gif) {
        r = gif_error(g, code, "opening", err, err_size);
        frt_gif_abort(g);
        return r;
    }
    EGifSetGifVersion(g->gif, true); /* GIF89a: needed for the delay and loop extensions */
    GifColorType colors[256];
    for (int i = 0; i < 256; ++i) {
        colors[i].Red = palette_rgb[3 * i];
        colors[i].Green = palette_rgb[3 * i + 1];
        colors[i].Blue = palette_rgb[3 * i + 2];
    }
    ColorMapObject *map = GifMakeMapObject(256, colors);
    static const GifByteType loop[3] = {1, 0, 0}; /* sub-block 1, loop count 0 = forever */
    if (!map || EGifPutScreenDesc(g->gif, (int)width, (int)height, 8, 0, map) == GIF_ERROR ||
        EGifPutExtensionLeader(g->gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
        EGifPutExtensionBlock(g->gif, 11, "NETSCAPE2.0") == GIF_ERROR ||
        EGifPutExtensionBlock(g->gif, 3, loop) == GIF_ERROR || EGifPutExtensionTrailer(g->gif) == GIF_ERROR) {
        r = gif_error(g, g->gif->Error, "header", err, err_size);
        GifFreeMapObject(map);
        frt_gif_abort(g);
        return r;
    }
    GifFreeMapObject(map);
    *out = g;
    return FRT_SUCCESS;
}

frt_result frt_gif_add_frame(frt_gif_writer *g, const uint8_t *indices, uint32_t delay_centiseconds, char *err,
                             size_t err_size)
{
    GraphicsControlBlock gcb = {.DisposalMode = DISPOSE_DO_NOT,
                                .UserInputFlag = false,
                                .DelayTime = (int)delay_centiseconds,
                                .TransparentColor = NO_TRANSPARENT_COLOR};
    GifByteType ext[4];
    EGifGCBToExtension(&gcb, ext);
    if (EGifPutExtension(g->gif, GRAPHICS_EXT_FUNC_CODE, 4, ext) == GIF_ERROR ||
        EGifPutImageDesc(g->gif, 0, 0, (int)g->width, (int)g->height, false, NULL) == GIF_ERROR)
        return gif_error(g, g->gif->Error, "frame header", err, err_size);
    for (uint32_t y = 0; y < g->height; ++y)
        /* giflib takes a non-const line but does not modify it */
        if (EGifPutLine(g->gif, (GifPixelType *)(uintptr_t)(indices + (size_t)y * g->width), (int)g->width) ==
            GIF_ERROR)
            return gif_error(g, g->gif->Error, "frame data", err, err_size);
    return FRT_SUCCESS;
}

frt_result frt_gif_commit(frt_gif_writer *g, char *err, size_t err_size)
{
    int code = 0;
    int rc = EGifCloseFile(g->gif, &code); /* writes the trailer through our callback, frees the handle */
    g->gif = NULL;
    if (rc == GIF_ERROR || g->failed) {
        frt_result r = gif_error(g, code, "closing", err, err_size);
        frt_gif_abort(g);
        return r;
    }
    frt_result r = frt_atomic_commit(&g->file, err, err_size);
    free(g);
    return r;
}

void frt_gif_abort(frt_gif_writer *g)
{
    if (!g)
        return;
    if (g->gif)
        EGifCloseFile(g->gif, NULL);
    frt_atomic_abort(&g->file);
    free(g);
}
