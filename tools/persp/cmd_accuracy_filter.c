/* persp accuracy --filter: texture filters and the object-space pipeline
 * against a supersampled reference. */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_LIST 64

static void usage(FILE *out)
{
    fprintf(out,
            "usage: persp accuracy --filter [F[,F...]] [options]\n\n"
            "Renders each texture filter (screen pipeline) and the object-space pipeline\n"
            "([Romaniuk-ObjSpace] in docs/SOURCES.md, filter name \"object\") and\n"
            "compares them with a supersampled reference: N x N samples per pixel of the\n"
            "exact mapping, bilinear on level 0, box-filtered. Reports PSNR, SSIM, the\n"
            "largest and mean channel error, texels read per pixel, render time, and the\n"
            "texture's mip-chain memory overhead.\n\n"
            "options:\n"
            "  --filter [F,...]    filters to measure (default: nearest, bilinear,\n"
            "                      nearest-mip-nearest, bilinear-mip-nearest,\n"
            "                      nearest-mip-linear, trilinear, aniso:16, aniso-window:16,\n"
            "                      ewa, object)\n"
            "  --case C[,C...]     cases (default: corridor, floor, tilt-0 ... tilt-85)\n"
            "  --size WxH          image size (default 256x192)\n"
            "  --samples N         reference samples per pixel along each axis, 1..64 (default 16)\n"
            "  --repeats N         timed renders per filter, the fastest kept (default 3)\n"
            "  --threads N         worker threads (default 1)\n"
            "  --lod pixel|polygon level of detail per pixel or per polygon\n"
            "  --lod-bias B        added to the level of detail\n"
            "  --heatmap DIR       one PNG per filter and case: per-pixel error in 8-bit levels\n"
            "  --csv | --json      machine-readable output instead of the table\n"
            "  -h, --help          this help\n"
            "\ncases:\n");
    for (size_t i = 0; i < persp_filter_accuracy_case_count(); i++)
        fprintf(out, "  %-10s %s\n", persp_filter_accuracy_case_name(i), persp_filter_accuracy_case_summary(i));
}

int cmd_accuracy_filter(int argc, char **argv)
{
    const char *filters[MAX_LIST], *cases[MAX_LIST];
    size_t nf = 0, nc = 0;
    persp_report_format format = PERSP_REPORT_TABLE;
    persp_filter_accuracy_desc d;
    memset(&d, 0, sizeof d);
    int threads = 1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        char *val = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE()                                                                               \
    do {                                                                                           \
        if (!val) return cli_error(CLI_USAGE, "accuracy: option %s needs a value", a);           \
        i++;                                                                                       \
    } while (0)
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return CLI_OK;
        } else if (!strcmp(a, "--filter")) {
            if (val && val[0] != '-') {
                i++;
                if (!cli_split_list(val, filters, &nf, MAX_LIST))
                    return cli_error(CLI_USAGE, "accuracy: bad --filter '%s' (empty name or too many)", val);
            }
        } else if (!strcmp(a, "--case")) {
            NEED_VALUE();
            if (!cli_split_list(val, cases, &nc, MAX_LIST))
                return cli_error(CLI_USAGE, "accuracy: bad --case '%s' (empty name or too many)", val);
        } else if (!strcmp(a, "--size")) {
            NEED_VALUE();
            if (!cli_parse_size(val, &d.width, &d.height) || d.width > 4096 || d.height > 4096)
                return cli_error(CLI_USAGE, "accuracy: bad --size '%s' (expected WxH, each 1..4096)", val);
        } else if (!strcmp(a, "--samples")) {
            NEED_VALUE();
            long n;
            if (!cli_parse_int(val, 1, 64, &n))
                return cli_error(CLI_USAGE, "accuracy: bad --samples '%s' (expected 1..64)", val);
            d.samples = (int)n;
        } else if (!strcmp(a, "--repeats")) {
            NEED_VALUE();
            long n;
            if (!cli_parse_int(val, 1, 100, &n))
                return cli_error(CLI_USAGE, "accuracy: bad --repeats '%s' (expected 1..100)", val);
            d.repeats = (int)n;
        } else if (!strcmp(a, "--threads")) {
            NEED_VALUE();
            long n;
            if (!cli_parse_int(val, 1, 256, &n))
                return cli_error(CLI_USAGE, "accuracy: bad --threads '%s' (expected 1..256)", val);
            threads = (int)n;
        } else if (!strcmp(a, "--lod")) {
            NEED_VALUE();
            if (!strcmp(val, "pixel")) d.lod_mode = PERSP_LOD_PIXEL;
            else if (!strcmp(val, "polygon")) d.lod_mode = PERSP_LOD_POLYGON;
            else return cli_error(CLI_USAGE, "accuracy: bad --lod '%s' (expected pixel or polygon)", val);
        } else if (!strcmp(a, "--lod-bias")) {
            NEED_VALUE();
            char *end;
            double b = strtod(val, &end);
            if (*end || end == val || !(b >= -16.0 && b <= 16.0))
                return cli_error(CLI_USAGE, "accuracy: bad --lod-bias '%s' (expected -16..16)", val);
            d.lod_bias = (float)b;
        } else if (!strcmp(a, "--heatmap")) {
            NEED_VALUE();
            d.heatmap_dir = val;
        } else if (!strcmp(a, "--csv")) {
            format = PERSP_REPORT_CSV;
        } else if (!strcmp(a, "--json")) {
            format = PERSP_REPORT_JSON;
        } else if (a[0] == '-') {
            return cli_error(CLI_USAGE, "accuracy: unknown option '%s' with --filter (see persp accuracy --filter --help)", a);
        } else {
            return cli_error(CLI_USAGE, "accuracy: unexpected argument '%s' (see persp accuracy --filter --help)", a);
        }
#undef NEED_VALUE
    }
    for (size_t i = 0; i < nf; i++) {
        persp_status st = persp_filter_accuracy_filter_check(filters[i]);
        if (st == PERSP_ERR_INVALID_ARGUMENT)
            return cli_error(CLI_USAGE, "accuracy: bad filter '%s' (aniso:N and aniso-window:N take N = 2..16)",
                             filters[i]);
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
    persp_context *ctx = NULL;
    persp_context_desc cd = {NULL, threads};
    persp_status st = persp_context_create(&cd, &ctx);
    if (st != PERSP_OK) return cli_status(NULL, st, "accuracy: context");
    persp_filter_accuracy_result *res = NULL;
    int rc = CLI_OK;
    st = persp_filter_accuracy_run(ctx, &d, &res);
    if (st != PERSP_OK) rc = cli_status(ctx, st, "accuracy --filter");
    else if ((st = persp_filter_accuracy_write(ctx, res, format, stdout)) != PERSP_OK)
        rc = cli_status(ctx, st, "accuracy --filter: writing the report");
    persp_filter_accuracy_destroy(res);
    persp_context_destroy(ctx);
    return rc;
}
