/* persp report: the whole study as one web page (persp_report_html). */
#include "options.h"
#include "persp_build_commit.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void report_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp report -o DIR [--quick] [--from DIR] [--max-memory SIZE]\n\n"
                 "Measures every texture-coordinate method, shading mode and filter and writes\n"
                 "DIR/index.html: tables and SVG plots of the errors by depth ratio, the\n"
                 "sources' claims with their verdicts, every method's images with zoomed\n"
                 "crops and error heat maps, a before/after slider, filter PSNR/SSIM and the\n"
                 "environment, with the command that reproduces each figure. The page needs\n"
                 "no network; its images and data (accuracy.json, filter.json) lie beside it.\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
}

static const cli_spec opt_quick = {
    .name = "quick", .kind = CLI_KIND_FLAG, .help = "fewer triangles and smaller images (seconds)"};
static const cli_spec opt_hardware = {.name = "hardware",
                                      .kind = CLI_KIND_STRING,
                                      .metavar = "FILE",
                                      .help = "add the hardware section from scripts/hw.sh's summary\n"
                                              "(default: out/hw/summary.json when it exists)"};
static const cli_spec opt_from = {.name = "from",
                                  .kind = CLI_KIND_STRING,
                                  .metavar = "DIR",
                                  .help =
                                      "read the method accuracy from DIR/accuracy.json (e.g.\n"
                                      "`persp merge` of a sharded sweep) instead of measuring it"};

static int report_body(persp_context *ctx, cli_output *out, void *user)
{
    (void)out;
    double t0 = cli_now();
    persp_status st = persp_report_html(ctx, user);
    if (st != PERSP_OK) return cli_status(ctx, st, "report");
    fprintf(stderr, "report: done in %.1f s\n", cli_now() - t0);
    return CLI_OK;
}

int cmd_report(int argc, char **argv)
{
    const char *output = NULL, *from = NULL, *hardware = NULL;
    int quick = 0;
    size_t max_memory = 0;
    cli_option opts[] = {
        CLI_OPT_HELP(cli_opt_output_dir, &output, "folder for index.html and its files (created)"),
        CLI_OPT(opt_quick, &quick),
        CLI_OPT(opt_from, &from),
        CLI_OPT(opt_hardware, &hardware),
        CLI_OPT(cli_opt_max_memory, &max_memory),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {
        "report", "persp report --help", NULL, opts, sizeof opts / sizeof opts[0], NULL, 0, 0,
        NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, report_usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    if (!output || !strcmp(output, "-"))
        return cli_error(CLI_USAGE, "report: -o DIR is required (the page has files beside it)");

    char line[2048] = "persp";
    for (int i = 0; i < argc; i++) {
        size_t len = strlen(line);
        snprintf(line + len, sizeof line - len, " %s", i == 0 ? "report" : argv[i]);
    }
    /* The build's commit, not the current folder's (a user's project). */
    const char *commit = PERSP_BUILD_COMMIT;
    persp_report_html_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.dir = output;
    desc.quick = quick;
    desc.from_dir = from;
    desc.command = line;
    desc.git_commit = commit[0] ? commit : NULL;
    desc.log = stderr;
    /* `make hw` leaves its summary in out/hw/ of the checkout. */
    if (!hardware && access("out/hw/summary.json", R_OK) == 0) hardware = "out/hw/summary.json";
    desc.hardware_summary = hardware;
    cli_run_desc run = {.command = "report", .max_memory = max_memory};
    return cli_run(&run, report_body, &desc);
}
