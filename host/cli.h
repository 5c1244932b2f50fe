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

int frt_cmd_generate(int argc, char **argv);
int frt_cmd_bench(int argc, char **argv);

#endif
