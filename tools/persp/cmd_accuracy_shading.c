/* persp accuracy --shading: shading modes against the exact per-pixel
 * reference, the t_w approximations and the ΔI analysis of [Romanyuk-PCF] §4.2-4.3. */
#include "options.h"

#include <string.h>

static void usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp accuracy --shading [options]\n\n"
                 "Measures every shading mode (flat, gouraud, gouraud-pc, phong, phong-pc,\n"
                 "phong-pc:quad, phong-pc:pwquad, phong-pc:cubic, phong-slerp,\n"
                 "phong-slerp-screen) against the exact per-pixel reference: colour error in\n"
                 "8-bit levels and normal angle error in degrees on seeded random lit\n"
                 "triangles for each depth ratio, and colour error on a lit scene against its\n"
                 "phong-pc render. Then tabulates the polynomial approximations of t_w\n"
                 "([Romanyuk-PCF] §4.3) and the error factor Delta(u) of screen-linear Gouraud\n"
                 "with its maximum (§4.2, Fig. 4.3-4.4). Sources are cited by the keys of\n"
                 "docs/SOURCES.md.\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
}

static const cli_spec opt_triangles = {.name = "triangles",
                                       .kind = CLI_KIND_INT,
                                       .metavar = "N",
                                       .lo = 1,
                                       .hi = 10000,
                                       .help = "random triangles per depth ratio (default 20)"};
static const cli_spec opt_scene = {.name = "scene",
                                   .kind = CLI_KIND_STRING,
                                   .metavar = "FILE",
                                   .help =
                                       "JSON scene for the lit-scene case (default: a built-in\n"
                                       "floor, coarse sphere, torus and long cylinder)"};
static const cli_spec opt_svg = {.name = "svg",
                                 .kind = CLI_KIND_STRING,
                                 .metavar = "FILE",
                                 .help = "write Fig. 4.3, Fig. 4.4 and the t_w errors as SVG"};

static int shading_body(persp_context *ctx, cli_output *out, void *user)
{
    const persp_shading_accuracy_desc *desc = user;
    persp_status st = persp_shading_accuracy_report(ctx, desc, out->f);
    if (st == PERSP_OK) return CLI_OK;
    return cli_status(ctx, st, desc->scene && st != PERSP_ERR_IO ? desc->scene : "accuracy --shading");
}

int cmd_accuracy_shading(int argc, char **argv)
{
    persp_shading_accuracy_desc desc;
    memset(&desc, 0, sizeof desc);
    persp_scene_load_desc load;
    memset(&load, 0, sizeof load);
    desc.load = &load;
    cli_size size = {0, 0};
    const char *output = NULL;
    size_t max_memory = 0;
    cli_option opts[] = {
        CLI_OPT(cli_opt_seed, &desc.seed),
        CLI_OPT(opt_triangles, &desc.triangles),
        CLI_OPT(opt_scene, &desc.scene),
        CLI_OPT(cli_opt_any_folder, &desc.any_folder),
        CLI_OPT(cli_opt_up, &load.model_up),
        CLI_OPT(cli_opt_formats, &load.formats),
        CLI_OPT(cli_opt_import, &load.import),
        CLI_OPT(cli_opt_import_timeout, &load.import_time_limit_ms),
        CLI_OPT(cli_opt_crease, &load.crease_deg),
        CLI_OPT_HELP(cli_opt_size, &size,
                     "lit-scene image size (default: the scene's, else 640x480)"),
        CLI_OPT(opt_svg, &desc.svg_path),
        CLI_OPT(cli_opt_max_memory, &max_memory),
        CLI_OPT_HELP(cli_opt_output, &output,
                     "write the report to FILE (default, and -: standard output)"),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {"accuracy --shading",
                       "persp accuracy --shading --help",
                       NULL,
                       opts,
                       sizeof opts / sizeof opts[0],
                       NULL,
                       0,
                       0,
                       NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    desc.width = size.width;
    desc.height = size.height;
    /* The figures are written last: a path that cannot be is known now. */
    if ((rc = cli_check_output("accuracy --shading", "--svg", desc.svg_path)) != CLI_OK) return rc;
    if ((rc = cli_check_not_input("accuracy --shading", "--svg", desc.svg_path, desc.scene)) != CLI_OK ||
        (rc = cli_check_not_input("accuracy --shading", "-o", output, desc.scene)) != CLI_OK)
        return rc;
    cli_run_desc run = {.command = "accuracy --shading", .max_memory = max_memory, .report = 1, .output = output};
    return cli_run(&run, shading_body, &desc);
}
