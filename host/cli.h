/* cli.h — what the files of the `fracterra` command share: exit codes, message and parsing helpers. */
#ifndef FRT_CLI_H
#define FRT_CLI_H

#include "internal.h"

enum { FRT_EXIT_OK = 0, FRT_EXIT_USAGE = 2, FRT_EXIT_DEVICE = 3, FRT_EXIT_IO = 4 };

extern const char *frt_cli_command; /* "fracterra generate", ... : the prefix of every message */
/* Prints "COMMAND: message" on stderr and returns `code`. */
int frt_cli_fail(int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Whole-string parsers: false on trailing text, sign where none is allowed, overflow, NaN or infinity. */
bool frt_parse_u32(const char *s, uint32_t *out);
bool frt_parse_u64(const char *s, uint64_t *out); /* decimal, or hex with 0x */
bool frt_parse_double(const char *s, double *out);
bool frt_parse_backend(const char *s, frt_backend *out);

/* The terrain options that generate and tiles share, as getopt_long codes. */
enum { FRT_OPT_HURST = 0x1000, FRT_OPT_DIMENSION, FRT_OPT_SIGMA, FRT_OPT_SEED, FRT_OPT_EDGE };
/* Parses `arg` of one of them into `d` (--dimension into *dimension). Returns an exit code after printing the
 * message (0: ok), or -1 when `opt` is not one of them. */
int frt_cli_terrain_option(int opt, const char *arg, frt_terrain_desc *d, double *dimension);

bool frt_parse_spacing(const char *s, double *dx, double *dy); /* "D" or "DX,DY", both > 0 */
/* The format of an output path, or a usage failure naming the known extensions; `allowed` is a bit mask of
 * (1u << frt_file_format). Returns FRT_FILE_DEFAULT after printing the message. */
frt_file_format frt_cli_output_format(const char *path, unsigned allowed);
/* Fails early when `path` cannot be written (creates and removes a temporary file beside it). */
bool frt_cli_probe_writable(const char *path, int *exit_code);

/* cli_progress.c: a progress line for steps longer than about a second, on a terminal only. */
void frt_progress_init(bool quiet);
void frt_progress_begin(const char *label, uint64_t total); /* total 0: elapsed time only */
void frt_progress_set(uint64_t done);
void frt_progress_end(void);

/* cli_frames.c: the growth frames of `field` (levels n, side 2^n + 1, or 2^n periodic) after each level, on the
 * final scale. */
int frt_write_frames(const char *dir, const char *gif, const float *field, uint32_t side, uint32_t levels,
                     const frt_write_desc *wd);

/* cli_inputs.c: whole heightfield files as inputs. Each prints one message and returns an exit code (0: ok). */
int frt_cli_read_field(const char *path, const char *what, float **out, frt_field_info *info);
/* --coarse: a square (2^k+1)^2 grid (2^k x 2^k periodic); sets *k. With fit_pad (FFC only) any w x h grid, w, h >= 2,
 * is placed at the top left of the smallest (2^k+1)^2 grid that holds it, the rest NaN (info keeps w x h). */
int frt_cli_load_coarse(const char *path, bool periodic, bool fit_pad, float **grid, uint32_t *k, frt_field_info *info);
/* --fit pad: fills the cells of the side x side grid outside its top-left w x h data by mirroring the data about
 * its last row and column (docs/ALGORITHM.md §3.4), so that the detail added near those edges sees terrain like the
 * data's rather than a cliff. Reads only data cells. */
void frt_cli_mirror_pad(float *grid, uint32_t side, uint32_t w, uint32_t h);
typedef enum frt_cli_map { FRT_CLI_MAP_HURST, FRT_CLI_MAP_DIMENSION, FRT_CLI_MAP_AMPLITUDE } frt_cli_map;
/* A map (at least 2 x 2) with its values checked; a dimension map is converted to H = 3 - D. */
int frt_cli_load_map(const char *path, frt_cli_map kind, float **data, frt_map *map);
/* "gauss", "truncated[:K]", "clt[:N]", "uniform"; the parameter's range is checked by frt_terrain_desc_check. */
bool frt_parse_noise(const char *s, frt_noise_kind *kind, double *param);

int frt_cmd_generate(int argc, char **argv);
int frt_cmd_render(int argc, char **argv);
int frt_cmd_bench(int argc, char **argv);
int frt_cmd_tiles(int argc, char **argv); /* cli_tiles.c */
int frt_cmd_info(int argc, char **argv);  /* cli_info.c */

#endif
