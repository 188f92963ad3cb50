/* The persp command-line tool: one file per subcommand, public API only. */
#ifndef PERSP_CLI_H
#define PERSP_CLI_H

#include "persp_analysis.h"

#include <stdio.h>

/* Exit codes: 0 success, 1 a failure while working, 2 bad usage. */
enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2 };

int cmd_render(int argc, char **argv);
int cmd_methods(int argc, char **argv);
int cmd_accuracy(int argc, char **argv);
int cmd_accuracy_shading(int argc, char **argv); /* persp accuracy --shading ... */
int cmd_accuracy_filter(int argc, char **argv);  /* persp accuracy --filter */
int cmd_bench(int argc, char **argv);
int cmd_merge(int argc, char **argv);
int cmd_report(int argc, char **argv);
int cmd_view(int argc, char **argv);
int cmd_vectors(int argc, char **argv);

/* Prints "persp: " + message to stderr and returns code. */
int cli_error(int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* The contexts' warning handler: "persp: warning: message" on stderr, so
 * that problems worked around (a model's missing texture) stay visible. */
void cli_warning(void *user, const char *message);
/* Reports a failed library call: "persp: what: detail (status)". */
int cli_status(persp_context *ctx, persp_status st, const char *what);
/* 1 if name is a built-in scene's (persp_builtin_scene_name). */
int cli_is_builtin(const char *name);
/* CLI_OK if name is a built-in scene or an existing file; otherwise CLI_FAIL
 * after "persp: COMMAND: 'name' is neither a built-in scene (...) nor a
 * file: reason". */
int cli_check_scene(const char *command, const char *name);
/* --texture: the image file path becomes the texture of every textured
 * object of scene (persp_scene_set_texture); a warning when the scene has
 * none, as nothing then changes. CLI_OK, or CLI_FAIL after the error. */
int cli_replace_texture(persp_context *ctx, persp_scene *scene, const char *path);
/* Parses "WxH" with 1 <= W, H <= PERSP_IMAGE_MAX_SIDE and W·H <= PERSP_IMAGE_MAX_PIXELS. */
int cli_parse_size(const char *text, int *w, int *h);
/* Parses a whole decimal integer in [lo, hi]. */
int cli_parse_int(const char *text, long lo, long hi, long *out);
/* A plain decimal number (fraction and exponent allowed) in [lo, hi]. */
int cli_parse_real(const char *text, double lo, double hi, double *out);
/* CLI_OK if spec names a method with valid parameters; otherwise prints
 * "persp: COMMAND: ..." with the accepted form and returns CLI_USAGE. */
int cli_check_method(const char *command, const char *spec);
/* Splits a comma list in place, appending its items to list[*n ...] (at
 * most cap in all); 0 on an empty item or when the list is full. */
int cli_split_list(char *text, const char **list, size_t *n, size_t cap);
/* Where a report goes: standard output, or a file that replaces its path
 * only once everything was written. */
typedef struct cli_output {
    FILE *f;
    const char *path;   /* NULL: standard output */
    char *tmp, *target; /* the temporary file and the file it replaces */
} cli_output;
/* Opens path for a report (NULL or "-": standard output); CLI_OK, or
 * CLI_FAIL after printing "persp: COMMAND: ...". */
int cli_output_open(const char *command, const char *path, cli_output *out);
/* With ok: flushes and closes, puts a file in place and reports any write
 * error (CLI_FAIL). Without (the command failed): removes a file, reports
 * nothing. */
int cli_output_close(const char *command, cli_output *out, int ok);
/* Checks, before any long work, that an output path can be written: an
 * existing file is not a folder or read-only, and the folder it goes in
 * exists and is writable ("-" and devices pass). CLI_OK, or CLI_FAIL after
 * "persp: COMMAND: OPTION 'path': ...". */
int cli_check_output(const char *command, const char *option, const char *path);
/* The library's temp-file handler (persp_context_set_temp_file_handler):
 * remembers the file so that SIGINT/SIGTERM removes it. */
void cli_temp_file(void *user, const char *path);
/* Installs the SIGINT/SIGTERM handlers that remove temporary files. */
void cli_install_signal_handlers(void);
/* Gives SIGINT/SIGTERM their default action back (for a library, SDL, that
 * installs its own only over the default). */
void cli_restore_signal_handlers(void);
/* Seconds from a monotonic clock. */
double cli_now(void);
/* persp vectors --input (cmd_vectors.c): reads the next triangle, 15 numbers
 * a line (x y w u v per vertex), from in, counting lines in *line. 1 with a
 * triangle, 0 at the end of the file, -1 after "persp: vectors: path:line:
 * problem" on stderr (cli_error). */
int vectors_read_triangle(FILE *in, const char *path, long *line, persp_method_vertex v[3]);
/* A random triangle of `persp vectors` (cmd_vectors.c): a few to a few
 * hundred pixels across, somewhere in the window, w log-uniform up to the
 * depth ratio, from a splitmix64 stream, so that a seed gives every module
 * the same triangles. */
void vectors_random_triangle(uint64_t *state, int width, int height, double depth_ratio, double uv_range,
                             persp_method_vertex v[3]);
/* The spans of persp_midpoint_trace (x0, y, n each), collected by
 * vectors_keep_span as its callback; failed: out of memory. */
typedef struct vectors_spans {
    int (*s)[3];
    size_t n, cap;
    int failed;
} vectors_spans;
void vectors_keep_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px);
/* persp vectors --module window_one, window_two, tw_exact, tw_quadratic,
 * tw_pwquad, tw_cubic (vectors_shade.c; formats in docs/HARDWARE.md):
 * vectors_shade_module says whether NAME is one of them, vectors_shade
 * writes them for the parsed options of cmd_vectors (input NULL: random
 * triangles from seed). */
int vectors_shade_module(const char *name);
int vectors_shade(const char *module, const char *input, const char *output, int triangles, unsigned long long seed,
                  double depth_ratio, double uv_range, int width, int height, int tex_w, int tex_h);
/* persp vectors --module subdiv, subdiv:8, incremental, quadratic, cubic,
 * bezier (vectors_span.c; formats in docs/HARDWARE.md), the same way. */
int vectors_span_module(const char *name);
int vectors_span(const char *module, const char *input, const char *output, int triangles, unsigned long long seed,
                 double depth_ratio, double uv_range, int width, int height, int tex_w, int tex_h);

#endif
