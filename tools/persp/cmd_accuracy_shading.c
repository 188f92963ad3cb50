/* persp accuracy --shading: shading modes against the exact per-pixel
 * reference, the t_w approximations and the ΔI analysis of [Romanyuk-PCF] §4.2-4.3. */
#include "cli.h"

#include <string.h>

static void usage(FILE *out)
{
    fprintf(out,
            "usage: persp accuracy --shading [options]\n\n"
            "Measures every shading mode (flat, gouraud, gouraud-pc, phong, phong-pc,\n"
            "phong-pc:quad, phong-pc:pwquad, phong-pc:cubic, phong-slerp,\n"
            "phong-slerp-screen) against the exact per-pixel reference: colour error in\n"
            "8-bit levels and normal angle error in degrees on seeded random lit\n"
            "triangles for each depth ratio, and colour error on a lit scene against its\n"
            "phong-pc render. Then tabulates the polynomial approximations of t_w\n"
            "([Romanyuk-PCF] §4.3) and the error factor Delta(u) of screen-linear\n"
            "Gouraud with its maximum (§4.2, Fig. 4.3-4.4). Sources are cited by the\n"
            "keys of docs/SOURCES.md.\n\n"
            "options:\n"
            "  --seed N          seed of the random triangles (default 1)\n"
            "  --triangles N     random triangles per depth ratio (default 20)\n"
            "  --scene FILE      JSON scene for the lit-scene case (default: a built-in\n"
            "                    floor, coarse sphere, torus and long cylinder)\n"
            "  --size WxH        lit-scene image size (default: the scene's, else 640x480)\n"
            "  --svg FILE        write Fig. 4.3, Fig. 4.4 and the t_w errors as SVG\n"
            "  -h, --help        this help\n");
}

int cmd_accuracy_shading(int argc, char **argv)
{
    persp_shading_accuracy_desc desc;
    memset(&desc, 0, sizeof desc);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return CLI_OK;
        }
        int takes = !strcmp(a, "--seed") || !strcmp(a, "--triangles") || !strcmp(a, "--scene") ||
                    !strcmp(a, "--size") || !strcmp(a, "--svg");
        if (!takes) {
            if (a[0] == '-')
                return cli_error(CLI_USAGE, "accuracy --shading: unknown option '%s' (see persp accuracy --shading --help)", a);
            return cli_error(CLI_USAGE, "accuracy --shading: unexpected argument '%s'", a);
        }
        if (!val) return cli_error(CLI_USAGE, "accuracy --shading: option %s needs a value", a);
        i++;
        long n;
        if (!strcmp(a, "--seed")) {
            if (!cli_parse_int(val, 1, 2147483647L, &n))
                return cli_error(CLI_USAGE, "accuracy --shading: bad --seed '%s' (expected 1..2147483647)", val);
            desc.seed = (uint64_t)n;
        } else if (!strcmp(a, "--triangles")) {
            if (!cli_parse_int(val, 1, 10000, &n))
                return cli_error(CLI_USAGE, "accuracy --shading: bad --triangles '%s' (expected 1..10000)", val);
            desc.triangles = (int)n;
        } else if (!strcmp(a, "--size")) {
            if (!cli_parse_size(val, &desc.width, &desc.height))
                return cli_error(CLI_USAGE, "accuracy --shading: bad --size '%s' (expected WxH, each 1..%d)",
                                 val, PERSP_IMAGE_MAX_SIDE);
        } else if (!strcmp(a, "--scene")) {
            desc.scene = val;
        } else {
            desc.svg_path = val;
        }
    }
    persp_context *ctx = NULL;
    persp_status st = persp_context_create(NULL, &ctx);
    if (st != PERSP_OK) return cli_status(NULL, st, "accuracy --shading: context");
    int rc = CLI_OK;
    st = persp_shading_accuracy_report(ctx, &desc, stdout);
    if (st != PERSP_OK) rc = cli_status(ctx, st, desc.scene && st != PERSP_ERR_IO ? desc.scene : "accuracy --shading");
    persp_context_destroy(ctx);
    return rc;
}
