/*
 * Command-line options from tables: each command lists the options it
 * accepts as cli_option entries (a spec and where the value goes); the
 * specs of options several commands share (--method, --size, -o, ...) are
 * defined once below. The same table parses the arguments (--opt value,
 * --opt=value, -o value) and prints the command's option help.
 */
#ifndef PERSP_CLI_OPTIONS_H
#define PERSP_CLI_OPTIONS_H

#include "cli.h"

/* cli_parse's result when -h/--help was given: print the help, exit 0. */
#define CLI_HELP (-1)

typedef enum cli_kind {
    CLI_KIND_HELP, /* -h, --help */
    CLI_KIND_FLAG, /* no value: stores spec->set (0: 1) into an int or enum */
    CLI_KIND_INT,  /* a decimal integer in [lo, hi] into an int, long or uint64_t */
    CLI_KIND_REAL, /* a number in [lo, hi] into a float or double */
    CLI_KIND_ENUM, /* one of names; stores the matching values[i] into an int or enum */
    CLI_KIND_SIZE, /* WxH, each side in [lo, hi] and W·H <= PERSP_IMAGE_MAX_PIXELS, into a cli_size
                    */
    CLI_KIND_STRING, /* the text itself into a const char *; one of names where names is set */
    CLI_KIND_CUSTOM  /* spec->parse */
} cli_kind;

typedef struct cli_command cli_command;
typedef struct cli_option cli_option;

typedef struct cli_spec {
    const char *name; /* long name without the leading "--" */
    char short_name;  /* 0: none */
    cli_kind kind;
    const char *metavar; /* the value as the help shows it ("N", "WxH"); NULL: takes none */
    const char *help;    /* lines separated by '\n'; NULL: not listed in the help */
    double lo, hi; /* INT, REAL: the range; SIZE: each side's (0, 0: 1..PERSP_IMAGE_MAX_SIDE) */
    const char *const *names; /* ENUM, STRING: NULL-terminated */
    const int *values;        /* ENUM: the value of each name */
    int set;                  /* FLAG */
    const char *accepts; /* the accepted values in error messages; NULL: from the range or names */
    int repeatable;      /* may be given more than once (lists that append); otherwise a
                            second occurrence is a usage error */
    int optional;        /* the value may be left out: the next argument is taken only if it
                            does not start with '-' (--opt=value always gives one) */
    /* CUSTOM: parses value (NULL where an optional value was left out) into
     * opt->dest; returns CLI_OK or an exit code, the error already printed. */
    int (*parse)(const cli_command *cmd, const cli_option *opt, char *value);
} cli_spec;

struct cli_option {
    const cli_spec *spec;
    void *dest;       /* what the spec's kind says; NULL for HELP */
    size_t size;      /* sizeof *dest, which tells int from long, float from double */
    const char *help; /* replaces spec->help for this command; NULL: the spec's */
    int seen;         /* how often it was given (set by cli_parse) */
};

#define CLI_OPT(spec, dest)                                                                        \
    {                                                                                              \
        &(spec), (dest), sizeof *(dest), NULL, 0                                                   \
    }
#define CLI_OPT_HELP(spec, dest, text)                                                             \
    {                                                                                              \
        &(spec), (dest), sizeof *(dest), (text), 0                                                 \
    }
#define CLI_OPT_NO_DEST(spec)                                                                      \
    {                                                                                              \
        &(spec), NULL, 0, NULL, 0                                                                  \
    }

struct cli_command {
    const char *name;         /* starts every message: "render", "accuracy --shading" */
    const char *help_ref;     /* where the options are explained: "persp render --help" */
    const char *unknown_note; /* appended to "unknown option 'X'" (" with --filter"); NULL: none */
    cli_option *opts;
    size_t count;
    /* Arguments that are not options, at most max_operands of them (each
     * called operand_name in messages); any more is a usage error. */
    const char **operands;
    size_t max_operands, operand_count;
    const char *operand_name;
};

/* Parses argv[1..argc-1] into the options' destinations. CLI_OK, CLI_HELP,
 * or CLI_USAGE after printing "persp: COMMAND: problem" to stderr. */
int cli_parse(cli_command *cmd, int argc, char **argv);
/* cli_parse, answering --help with usage(stdout, cmd): CLI_OK to go on,
 * CLI_HELP once the help is printed (the command then exits with CLI_OK),
 * or CLI_USAGE. */
int cli_parse_or_usage(cli_command *cmd, int argc, char **argv,
                       void (*usage)(FILE *out, const cli_command *cmd));
/* The option list of the command's help, one entry per listed option. */
void cli_print_options(FILE *out, const cli_command *cmd);
/* How often the option of this spec was given. */
int cli_given(const cli_command *cmd, const cli_spec *spec);
/* Prints "persp: COMMAND: bad --NAME 'value' (expected ...)" and returns CLI_USAGE. */
int cli_bad_value(const cli_command *cmd, const cli_option *opt, const char *value);

/* Destinations of the shared specs. */
typedef struct cli_size {
    int width, height;
} cli_size;

typedef struct cli_filter {
    const char *name; /* as given, NULL if not */
    persp_filter filter;
    int max_aniso;
} cli_filter;

typedef struct cli_shading {
    const char *name; /* as given, NULL if not */
    persp_shading shading;
} cli_shading;

/* A comma-separated list option that may be repeated; items point into argv. */
typedef struct cli_list {
    const char **items;
    size_t count, cap;
} cli_list;

/* CUSTOM parser for cli_list destinations: appends the comma-separated names. */
int cli_parse_list(const cli_command *cmd, const cli_option *opt, char *value);

/* The shared options. */
extern const cli_spec cli_opt_help;     /* -h, --help */
extern const cli_spec cli_opt_output;
/* -o / --output naming a folder a command creates (report). */
extern const cli_spec cli_opt_output_dir;   /* -o, --output FILE (const char *; "-": standard output) */
extern const cli_spec cli_opt_quiet;    /* -q, --quiet (int) */
extern const cli_spec cli_opt_method;   /* --method M (const char *, checked) */
extern const cli_spec cli_opt_filter;   /* --filter F (cli_filter) */
extern const cli_spec cli_opt_wrap;     /* --wrap W (persp_wrap) */
extern const cli_spec cli_opt_shading;  /* --shading S (cli_shading) */
extern const cli_spec cli_opt_size;     /* --size WxH (cli_size) */
extern const cli_spec cli_opt_depth;    /* --depth z|invw (persp_depth_mode) */
extern const cli_spec cli_opt_lod;      /* --lod pixel|polygon (persp_lod_mode) */
extern const cli_spec cli_opt_lod_bias; /* --lod-bias B (float) */
extern const cli_spec cli_opt_min_lod;  /* --min-lod L (float) */
extern const cli_spec cli_opt_max_lod;  /* --max-lod L (float) */
extern const cli_spec cli_opt_pipeline; /* --pipeline screen|object (persp_pipeline) */
extern const cli_spec cli_opt_texture;  /* --texture FILE (const char *) */
extern const cli_spec cli_opt_any_folder; /* --any-folder (persp_toggle) */
extern const cli_spec cli_opt_threads;  /* --threads N (int) */
extern const cli_spec cli_opt_simd;     /* --simd V (persp_simd) */
extern const cli_spec cli_opt_cull;     /* --cull on|off (persp_toggle) */
extern const cli_spec cli_opt_sort_first; /* --sort-first auto|on|off (persp_toggle) */
extern const cli_spec cli_opt_up;       /* --up AXIS (persp_model_up) */
extern const cli_spec cli_opt_count_ops; /* --count-ops (persp_toggle) */
extern const cli_spec cli_opt_format;    /* --format png|jpeg (persp_image_format) */
extern const cli_spec cli_opt_quality;   /* --quality N (int) */
extern const cli_spec cli_opt_csv;       /* --csv (persp_report_format) */
extern const cli_spec cli_opt_json;      /* --json (persp_report_format) */
extern const cli_spec cli_opt_heatmap;   /* --heatmap DIR (const char *) */
extern const cli_spec cli_opt_seed;      /* --seed N (uint64_t) */
extern const cli_spec cli_opt_max_memory; /* --max-memory SIZE (size_t bytes; K, M, G, T) */
extern const cli_spec cli_opt_import_timeout; /* --import-timeout SECONDS (unsigned ms) */
extern const cli_spec cli_opt_formats;   /* --formats common|all (persp_model_formats) */
extern const cli_spec cli_opt_import;    /* --import isolated|in-process (persp_model_import) */
extern const cli_spec cli_opt_crease;    /* --crease DEG (float) */
/* The budget of a command: given, or the default --help names (0: the default). */
size_t cli_max_memory(size_t given);

#endif
