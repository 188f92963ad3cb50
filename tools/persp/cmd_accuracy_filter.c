/* persp accuracy --filter: texture filters and the object-space pipeline
 * against a supersampled reference. */
#include "options.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_LIST 64

static void usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp accuracy --filter [F[,F...]] [options]\n\n"
                 "Renders each texture filter (screen pipeline) and the object-space pipeline\n"
                 "([Romaniuk-ObjSpace] in docs/SOURCES.md, filter name \"object\") and compares\n"
                 "them with a supersampled reference: N x N samples per pixel of the exact\n"
                 "mapping, bilinear on level 0, box-filtered. Reports PSNR, SSIM, the largest and mean channel error, texels\n"
                 "read per pixel, render time, and the texture's mip-chain memory overhead.\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
    fprintf(out, "\ncases:\n");
    for (size_t i = 0; i < persp_filter_accuracy_case_count(); i++)
        fprintf(out, "  %-10s %s\n", persp_filter_accuracy_case_name(i), persp_filter_accuracy_case_summary(i));
}

static const cli_spec opt_filters = {
    .name = "filter",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "[F,...]",
    .optional = 1,
    .parse = cli_parse_list,
    .accepts = "filters, comma-separated",
    .help = "filters to measure (default: nearest, bilinear,\n"
            "nearest-mip-nearest, bilinear-mip-nearest,\n"
            "nearest-mip-linear, trilinear, aniso:16, aniso-window:16,\n"
            "ewa, object)"};
static const cli_spec opt_case = {.name = "case",
                                  .kind = CLI_KIND_CUSTOM,
                                  .metavar = "C[,C...]",
                                  .parse = cli_parse_list,
                                  .accepts = "cases, comma-separated",
                                  .help = "cases (default: corridor, floor, tilt-0 ... tilt-85)"};
static const cli_spec opt_size = {.name = "size",
                                  .kind = CLI_KIND_SIZE,
                                  .metavar = "WxH",
                                  .hi = 4096,
                                  .help = "image size, each side 1..4096 (default 256x192)"};
static const cli_spec opt_samples = {
    .name = "samples",
    .kind = CLI_KIND_INT,
    .metavar = "N",
    .lo = 1,
    .hi = 64,
    .help = "reference samples per pixel along each axis, 1..64 (default 16)"};
static const cli_spec opt_repeats = {.name = "repeats",
                                     .kind = CLI_KIND_INT,
                                     .metavar = "N",
                                     .lo = 1,
                                     .hi = 100,
                                     .help =
                                         "timed renders per filter, the fastest kept (default 3)"};

typedef struct filter_job {
    const persp_filter_accuracy_desc *desc;
    persp_report_format format;
} filter_job;

static int filter_body(persp_context *ctx, cli_output *out, void *user)
{
    const filter_job *job = user;
    persp_filter_accuracy_result *res = NULL;
    int rc = CLI_OK;
    persp_status st = persp_filter_accuracy_run(ctx, job->desc, &res);
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, "accuracy --filter");
    } else if ((st = persp_filter_accuracy_write(ctx, res, job->format, out->f)) != PERSP_OK) {
        char what[512];
        snprintf(what, sizeof what, "accuracy --filter: writing the report to %s",
                 out->path ? out->path : "standard output");
        rc = cli_status(ctx, st, what);
    }
    persp_filter_accuracy_destroy(res);
    return rc;
}

int cmd_accuracy_filter(int argc, char **argv)
{
    const char *filters[MAX_LIST], *cases[MAX_LIST], *output = NULL;
    cli_list filter_list = {filters, 0, MAX_LIST}, case_list = {cases, 0, MAX_LIST};
    cli_size size = {0, 0};
    persp_report_format format = PERSP_REPORT_TABLE;
    persp_filter_accuracy_desc d;
    memset(&d, 0, sizeof d);
    int threads = 1;
    size_t max_memory = 0;
    cli_option opts[] = {
        CLI_OPT(opt_filters, &filter_list),
        CLI_OPT(opt_case, &case_list),
        CLI_OPT(opt_size, &size),
        CLI_OPT(opt_samples, &d.samples),
        CLI_OPT(opt_repeats, &d.repeats),
        CLI_OPT(cli_opt_threads, &threads),
        CLI_OPT(cli_opt_max_memory, &max_memory),
        CLI_OPT_HELP(cli_opt_lod, &d.lod_mode, "level of detail per pixel or per polygon"),
        CLI_OPT(cli_opt_lod_bias, &d.lod_bias),
        CLI_OPT_HELP(cli_opt_heatmap, &d.heatmap_dir,
                     "one PNG per filter and case: per-pixel error in 8-bit levels"),
        CLI_OPT(cli_opt_csv, &format),
        CLI_OPT(cli_opt_json, &format),
        CLI_OPT_HELP(cli_opt_output, &output,
                     "write the report to FILE (default, and -: standard output)"),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {"accuracy",
                       "persp accuracy --filter --help",
                       " with --filter",
                       opts,
                       sizeof opts / sizeof opts[0],
                       NULL,
                       0,
                       0,
                       NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    d.width = size.width;
    d.height = size.height;
    size_t nf = filter_list.count, nc = case_list.count;
    for (size_t i = 0; i < nf; i++) {
        persp_status st = persp_filter_accuracy_filter_check(filters[i]);
        if (st == PERSP_ERR_INVALID_ARGUMENT)
            return cli_error(CLI_USAGE, "accuracy: bad filter '%s' (aniso:N and aniso-window:N take N = 2..%d)",
                             filters[i], PERSP_MAX_ANISO);
        if (st != PERSP_OK)
            return cli_error(CLI_USAGE, "accuracy: unknown filter '%s' (see persp accuracy --filter --help)",
                             filters[i]);
    }
    for (size_t i = 0; i < nc; i++)
        if (persp_filter_accuracy_case_check(cases[i]) != PERSP_OK)
            return cli_error(CLI_USAGE, "accuracy: unknown case '%s' (see persp accuracy --filter --help)",
                             cases[i]);
    if (d.heatmap_dir && mkdir(d.heatmap_dir, 0777) != 0 && errno != EEXIST)
        return cli_error(CLI_FAIL, "accuracy: cannot create heat-map directory '%s': %s", d.heatmap_dir,
                         strerror(errno));
    d.filters = filters;
    d.filter_count = nf;
    d.cases = cases;
    d.case_count = nc;
    filter_job job = {&d, format};
    cli_run_desc run = {.command = "accuracy", .threads = threads, .max_memory = max_memory, .report = 1,
                        .output = output};
    return cli_run(&run, filter_body, &job);
}
