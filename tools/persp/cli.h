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
/* A cap on an open output: cli_cap_begin puts a stream that counts in
 * out->f, which refuses what would pass limit bytes; cli_cap_end puts the
 * output back and, where the cap refused bytes and ok (the command had
 * not failed otherwise), fails naming option. Then cli_output_close with
 * ok only if cli_cap_end passed, so that no file is put in place. */
typedef struct cli_cap {
    FILE *raw;
    size_t limit, written;
    int over;
} cli_cap;
int cli_cap_begin(const char *command, cli_output *out, cli_cap *cap, size_t limit);
int cli_cap_end(const char *command, cli_output *out, cli_cap *cap, const char *option, int ok);
/* 1 once a write to out failed (a cap reached, a full disk): a writer
 * stops there; the close reports why. */
int cli_output_full(cli_output *out);
/* With ok: flushes and closes, puts a file in place and reports any write
 * error (CLI_FAIL). Without (the command failed): removes a file, reports
 * nothing. */
int cli_output_close(const char *command, cli_output *out, int ok);
/* CLI_OK unless output names the same file as input (the same device and
 * inode, whatever the spelling or links), which writing output would
 * replace before, or while, it is read; then CLI_USAGE after "persp:
 * COMMAND: OPTION 'output' is the input file 'input'". NULL, "-" and
 * missing files pass. Call before anything is written. */
int cli_check_not_input(const char *command, const char *option, const char *output, const char *input);

/* The skeleton of a command (cli_run.c): creates the context with the
 * common options, sends its warnings to stderr (cli_warning) and its
 * temporary files to the signal handlers, opens the report output where
 * asked, runs body, closes the output (a failed body leaves no file) and
 * destroys the context. Zero fields are the defaults. */
typedef struct cli_run_desc {
    const char *command;  /* starts the messages: "render", "accuracy --shading" */
    int threads;          /* --threads; 0: 1 */
    size_t max_memory;    /* --max-memory; 0: cli_max_memory's default */
    persp_simd simd;      /* --simd; 0: auto */
    int report;           /* 1: open output as a report (cli_output) for body */
    const char *output;   /* with report: -o; NULL or "-": standard output */
    size_t output_limit;  /* with report: at most this many bytes (0: any) */
    const char *limit_option; /* the option that sets output_limit, for its message */
} cli_run_desc;
/* A command's work: out is the report output (NULL without report). Returns
 * a CLI exit code, its errors printed (cli_status for the library's). */
typedef int (*cli_body)(persp_context *ctx, cli_output *out, void *user);
/* The body's code, or CLI_FAIL after the context's or the output's error. */
int cli_run(const cli_run_desc *d, cli_body body, void *user);
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
/* What `persp vectors` was asked for (cmd_vectors.c). */
typedef struct vectors_job {
    const char *module, *method; /* method: midpoint:int's lattice */
    const char *input, *output;  /* input NULL: random triangles from seed */
    int triangles;
    uint64_t seed;
    double depth_ratio, uv_range;
    int width, height, tex_w, tex_h;
    size_t max_output; /* bytes; --max-output */
} vectors_job;
/* One module's writer for vectors_run: its first header line, each
 * triangle's records (into f; a CLI exit code), the closing line with the
 * counts, and the note on stderr once a file was written. */
typedef struct vectors_writer {
    char title[160];
    int (*triangle)(persp_context *ctx, const vectors_job *job, const persp_method_vertex v[3], long index, FILE *f,
                    void *state);
    void (*footer)(FILE *f, long triangles, void *state);
    void (*summary)(long triangles, const char *output, void *state);
    void *state;
} vectors_writer;
/* The skeleton every module's vectors share: the input file or the random
 * triangles, the capped output (cli_run), the header, the loop, the closing
 * line. A CLI exit code. */
int vectors_run(const vectors_job *job, const vectors_writer *w);
/* persp vectors --module window_one, window_two, tw_exact, tw_quadratic,
 * tw_pwquad, tw_cubic (vectors_shade.c; formats in docs/HARDWARE.md):
 * vectors_shade_module says whether NAME is one of them, vectors_shade
 * writes them. */
int vectors_shade_module(const char *name);
int vectors_shade(const vectors_job *job);
/* persp vectors --module subdiv, subdiv:8, incremental, quadratic, cubic,
 * bezier (vectors_span.c; formats in docs/HARDWARE.md), the same way. */
int vectors_span_module(const char *name);
int vectors_span(const vectors_job *job);
/* Whether s is plain decimal text: an optional '-', digits, with fraction
 * a '.' and digits and an exponent (cli_common.c). */
int cli_decimal_syntax(const char *s, int fraction);

/* The round trip of one cache line between the first processor of this
 * thread's mask and each other one (tools/persp/xcore.c), ns: the least
 * and the most over those pairs; pairs 0 (NaN figures) where it cannot be
 * measured. */
typedef struct cli_xcore {
    double min_ns, max_ns;
    int pairs;
} cli_xcore;
cli_xcore cli_xcore_measure(void);

#endif
