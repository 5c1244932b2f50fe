/* atomic_file.c — output files that appear whole or not at all: temporary file beside the target, then rename. */
#include "internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

frt_result frt_atomic_open(frt_atomic_file *af, const char *path, char *err, size_t err_size)
{
    memset(af, 0, sizeof *af);
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        snprintf(err, err_size, "cannot write '%s': it is a directory", path);
        return FRT_ERROR_IO;
    }
    size_t n = strlen(path);
    af->path = strdup(path);
    af->tmp_path = malloc(n + 16);
    if (!af->path || !af->tmp_path) {
        frt_atomic_abort(af);
        snprintf(err, err_size, "out of memory");
        return FRT_ERROR_OUT_OF_MEMORY;
    }
    /* Same directory as the target, so that rename() is atomic; hidden-ish suffix names it as ours. */
    snprintf(af->tmp_path, n + 16, "%s.tmp-XXXXXX", path);
    int fd = mkstemp(af->tmp_path);
    if (fd < 0) {
        snprintf(err, err_size, "cannot write '%s': %s", path, strerror(errno));
        free(af->tmp_path);
        af->tmp_path = NULL;
        frt_atomic_abort(af);
        return FRT_ERROR_IO;
    }
    fchmod(fd, 0644); /* mkstemp makes 0600; heightfields are not secrets */
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        close(fd);
        snprintf(err, err_size, "cannot write '%s': %s", path, strerror(errno));
        frt_atomic_abort(af);
        return FRT_ERROR_IO;
    }
    return FRT_SUCCESS;
}

frt_result frt_atomic_commit(frt_atomic_file *af, char *err, size_t err_size)
{
    int failed = ferror(af->fp);
    int saved = failed ? EIO : 0;
    if (fflush(af->fp) != 0 && !failed) {
        failed = 1;
        saved = errno;
    }
    if (!failed && fsync(fileno(af->fp)) != 0) {
        failed = 1;
        saved = errno;
    }
    if (fclose(af->fp) != 0 && !failed) {
        failed = 1;
        saved = errno;
    }
    af->fp = NULL;
    if (!failed && rename(af->tmp_path, af->path) != 0) {
        failed = 1;
        saved = errno;
    }
    if (failed) {
        snprintf(err, err_size, "writing '%s' failed: %s (nothing was replaced)", af->path, strerror(saved));
        frt_atomic_abort(af);
        return FRT_ERROR_IO;
    }
    free(af->tmp_path);
    free(af->path);
    memset(af, 0, sizeof *af);
    return FRT_SUCCESS;
}

void frt_atomic_abort(frt_atomic_file *af)
{
    if (af->fp)
        fclose(af->fp);
    if (af->tmp_path)
        unlink(af->tmp_path);
    free(af->tmp_path);
    free(af->path);
    memset(af, 0, sizeof *af);
}
