/* persp accuracy: every texture-coordinate method against the exact rational form. */
#include "options.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_LIST 256

static void accuracy_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out,
            "usage: persp accuracy [options]\n"
            "       persp accuracy --shading [options]  (shading modes; see --shading --help)\n\n"
            "Measures texture-coordinate methods against the exact rational form\n"
            "u = (a*x+b*y+c)/(g*x+h*y+i), v likewise, evaluated in double precision at\n"
            "each pixel centre: max, mean and 99th-percentile absolute error in texels of\n"
            "u and v, the share of pixels whose nearest texel differs, the maximum\n"
            "point-wise and span-relative errors, and operations per pixel as counted by\n"
            "each method.\n\n"
            "options:\n");
    cli_print_options(out, cmd);
    fprintf(out, "\ncases:\n");
    for (size_t i = 0; i < persp_accuracy_case_count(); i++)
        fprintf(out, "  %-17s %s\n", persp_accuracy_case_name(i), persp_accuracy_case_summary(i));
}

/* Whether text (up to the next ':' or ',') is a registered method name. */
static int starts_method(const char *text)
{
    size_t len = strcspn(text, ":,");
    persp_method_info info;
    for (size_t i = 0; persp_method_get(i, &info) == PERSP_OK; i++)
        if (strlen(info.name) == len && !strncmp(info.name, text, len)) return 1;
    return 0;
}

/* Like cli_split_list, but inside a method's parameters (after its ':') a comma
 * starts a new method only where a method name follows it, so parameter
 * lists such as "midpoint:int,edge" stay whole. */
static int add_method_list(char *text, const char **list, size_t *n)
{
    for (char *p = text;;) {
        char *comma = strchr(p, ',');
        const char *colon = strchr(p, ':');
        while (comma && colon && colon < comma && !starts_method(comma + 1))
            comma = strchr(comma + 1, ',');
        if (comma) *comma = '\0';
        if (!*p || *n >= MAX_LIST) return 0;
        list[(*n)++] = p;
        if (!comma) return 1;
        p = comma + 1;
    }
}

static int parse_method_list(const cli_command *cmd, const cli_option *opt, char *value)
{
    cli_list *list = opt->dest;
    char copy[256];
    snprintf(copy, sizeof copy, "%s", value);
    if (!add_method_list(value, list->items, &list->count))
        return cli_error(CLI_USAGE,
                         "%s: bad --method '%s' (expected a comma-separated list of methods, "
                         "none empty, at most %d in all)",
                         cmd->name, copy, MAX_LIST);
    return CLI_OK;
}

static int parse_rel_floor(const cli_command *cmd, const cli_option *opt, char *value)
{
    double f = 0.0;
    if (!cli_parse_real(value, 0.0, 1.0, &f) || !(f > 0.0)) return cli_bad_value(cmd, opt, value);
    memcpy(opt->dest, &f, sizeof f);
    return CLI_OK;
}

static const cli_spec opt_method_list = {
    .name = "method",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "M[,M...]",
    .parse = parse_method_list,
    .repeatable = 1,
    .accepts = "methods of `persp methods`, comma-separated",
    .help = "methods to measure, repeatable (default: every method of\n"
            "`persp methods` that runs without parameters)"};
static const cli_spec opt_case = {.name = "case",
                                  .kind = CLI_KIND_CUSTOM,
                                  .metavar = "C[,C...]",
                                  .parse = cli_parse_list,
                                  .accepts = "cases, comma-separated",
                                  .help =
                                      "cases, repeatable (default: paper-quad,random-triangles)"};
static const cli_spec opt_triangles = {.name = "triangles",
                                       .kind = CLI_KIND_INT,
                                       .metavar = "N",
                                       .lo = 1,
                                       .hi = 100000,
                                       .help =
                                           "random triangles per depth-ratio group (default 40)"};
static const cli_spec opt_rel_floor = {
    .name = "rel-floor",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "X",
    .parse = parse_rel_floor,
    .accepts = "0 < X <= 1",
    .help = "relative errors only where |s| (and a span's range)\n"
            ">= X, s normalised to [0,1] per texture (default 0.01)"};
typedef struct shard_opt {
    int index, count; /* 0-based index; count 0: not given */
} shard_opt;

static int parse_shard(const cli_command *cmd, const cli_option *opt, char *value)
{
    char *slash = strchr(value, '/');
    long k, n;
    if (!slash) return cli_bad_value(cmd, opt, value);
    *slash = '\0';
    int ok = cli_parse_int(value, 1, 1000000, &k) && cli_parse_int(slash + 1, 1, 1000000, &n) && k <= n;
    *slash = '/';
    if (!ok) return cli_bad_value(cmd, opt, value);
    shard_opt *s = opt->dest;
    s->index = (int)k - 1;
    s->count = (int)n;
    return CLI_OK;
}

static const cli_spec opt_shard = {
    .name = "shard",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "K/N",
    .parse = parse_shard,
    .accepts = "K/N with 1 <= K <= N",
    .help = "measure only slice K of N (rows dealt round-robin); with\n"
            "--json, `persp merge` of all N slices gives the unsharded JSON"};

/* Listed for the help only: --filter switches to cmd_accuracy_filter first. */
static const cli_spec opt_filter_mode = {
    .name = "filter",
    .kind = CLI_KIND_STRING,
    .metavar = "[F,...]",
    .optional = 1,
    .help = "texture filters instead of methods (see persp accuracy "
            "--filter --help)"};

typedef struct accuracy_job {
    const persp_accuracy_desc *desc;
    persp_report_format format;
} accuracy_job;

static int accuracy_body(persp_context *ctx, cli_output *out, void *user)
{
    const accuracy_job *job = user;
    persp_accuracy_result *res = NULL;
    int rc = CLI_OK;
    persp_status st = persp_accuracy_run(ctx, job->desc, &res);
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, "accuracy");
    } else if ((st = persp_accuracy_write(ctx, res, job->format, out->f)) != PERSP_OK) {
        char what[512];
        snprintf(what, sizeof what, "accuracy: writing the report to %s", out->path ? out->path : "standard output");
        rc = cli_status(ctx, st, what);
    }
    persp_accuracy_destroy(res);
    return rc;
}

/* The mode options choose another command; they may stand anywhere among
 * the options (an option's value, as in "--scene --shading", is not one). */
static int mode_index(int argc, char **argv, const char *mode)
{
    size_t len = strlen(mode);
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--")) return 0;
        if (!strncmp(argv[i], mode, len) && (argv[i][len] == '\0' || argv[i][len] == '=')) return i;
    }
    return 0;
}

int cmd_accuracy(int argc, char **argv)
{
    if (mode_index(argc, argv, "--filter")) return cmd_accuracy_filter(argc, argv);
    int shading = mode_index(argc, argv, "--shading");
    if (shading) {
        /* persp accuracy --shading takes no value: drop the switch, keep the rest in order. */
        if (argv[shading][strlen("--shading")] == '=')
            return cli_error(CLI_USAGE, "accuracy: option --shading takes no value");
        for (int i = shading; i > 1; i--) {
            char *t = argv[i];
            argv[i] = argv[i - 1];
            argv[i - 1] = t;
        }
        return cmd_accuracy_shading(argc - 1, argv + 1);
    }
    const char *methods[MAX_LIST], *cases[MAX_LIST], *filter_mode = NULL, *output = NULL;
    cli_list method_list = {methods, 0, MAX_LIST}, case_list = {cases, 0, MAX_LIST};
    cli_size size = {0, 0};
    persp_report_format format = PERSP_REPORT_TABLE;
    shard_opt shard = {0, 0};
    persp_accuracy_desc desc;
    memset(&desc, 0, sizeof desc);
    size_t max_memory = 0;
    cli_option opts[] = {
        CLI_OPT(opt_method_list, &method_list),
        CLI_OPT(opt_case, &case_list),
        CLI_OPT_HELP(cli_opt_size, &size, "image size of scene cases (default 1024x768)"),
        CLI_OPT_HELP(cli_opt_seed, &desc.seed, "seed of random-triangles (default 1)"),
        CLI_OPT(opt_triangles, &desc.triangles),
        CLI_OPT(opt_rel_floor, &desc.rel_floor),
        CLI_OPT_HELP(cli_opt_csv, &format, "CSV instead of the table"),
        CLI_OPT_HELP(cli_opt_json, &format, "JSON instead of the table"),
        CLI_OPT_HELP(cli_opt_output, &output,
                     "write the report to FILE (default, and -: standard output)"),
        CLI_OPT_HELP(cli_opt_heatmap, &desc.heatmap_dir,
                     "write one PNG per method and case with the per-pixel\n"
                     "error in texels on a logarithmic colour scale"),
        CLI_OPT(opt_shard, &shard),
        CLI_OPT(cli_opt_max_memory, &max_memory),
        CLI_OPT(opt_filter_mode, &filter_mode),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {
        "accuracy", "persp accuracy --help", NULL, opts, sizeof opts / sizeof opts[0], NULL, 0, 0,
        NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, accuracy_usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    if (shard.count && format != PERSP_REPORT_JSON)
        return cli_error(CLI_USAGE, "accuracy: --shard needs --json (slices are merged from JSON)");
    desc.shard_index = shard.index;
    desc.shard_count = shard.count;
    desc.width = size.width;
    desc.height = size.height;
    size_t nmethods = method_list.count, ncases = case_list.count;

    /* Usage errors first, before any work. */
    for (size_t i = 0; i < nmethods; i++) {
        int bad = cli_check_method("accuracy", methods[i]);
        if (bad) return bad;
    }
    for (size_t i = 0; i < ncases; i++)
        if (persp_accuracy_case_check(cases[i]) != PERSP_OK)
            return cli_error(CLI_USAGE, "accuracy: unknown case '%s' (see persp accuracy --help)",
                             cases[i]);
    if (desc.heatmap_dir && mkdir(desc.heatmap_dir, 0777) != 0 && errno != EEXIST)
        return cli_error(CLI_FAIL, "accuracy: cannot create heat-map directory '%s': %s",
                         desc.heatmap_dir, strerror(errno));

    desc.methods = methods;
    desc.method_count = nmethods;
    desc.cases = cases;
    desc.case_count = ncases;
    accuracy_job job = {&desc, format};
    cli_run_desc run = {.command = "accuracy", .max_memory = max_memory, .report = 1, .output = output};
    return cli_run(&run, accuracy_body, &job);
}
