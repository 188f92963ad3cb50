/* persp accuracy: every texture-coordinate method against the exact rational form. */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_LIST 256

static void accuracy_usage(FILE *out)
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
            "options:\n"
            "  --method M[,M...]   methods to measure, repeatable (default: every method of\n"
            "                      `persp methods` that runs without parameters)\n"
            "  --case C[,C...]     cases, repeatable (default: paper-quad,random-triangles)\n"
            "  --size WxH          image size of scene cases (default 1024x768)\n"
            "  --seed N            seed of random-triangles (default 1)\n"
            "  --triangles N       random triangles per depth-ratio group (default 40)\n"
            "  --rel-floor X       relative errors only where |s| (and a span's range)\n"
            "                      >= X, s normalised to [0,1] per texture (default 0.01)\n"
            "  --csv | --json      machine-readable output instead of the table\n"
            "  --heatmap DIR       write one PNG per method and case with the per-pixel\n"
            "                      error in texels on a logarithmic colour scale\n"
            "  --filter [F,...]    texture filters instead of methods (see persp accuracy --filter --help)\n"
            "  -h, --help          this help\n"
            "\ncases:\n");
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

int cmd_accuracy(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--filter")) return cmd_accuracy_filter(argc, argv);
    const char *methods[MAX_LIST], *cases[MAX_LIST];
    size_t nmethods = 0, ncases = 0;
    persp_report_format format = PERSP_REPORT_TABLE;
    persp_accuracy_desc desc;
    memset(&desc, 0, sizeof desc);
    if (argc > 1 && !strcmp(argv[1], "--shading")) return cmd_accuracy_shading(argc - 1, argv + 1);

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        char *val = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE()                                                                               \
    do {                                                                                           \
        if (!val) return cli_error(CLI_USAGE, "accuracy: option %s needs a value", a);           \
        i++;                                                                                       \
    } while (0)
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            accuracy_usage(stdout);
            return CLI_OK;
        } else if (!strcmp(a, "--method")) {
            NEED_VALUE();
            if (!add_method_list(val, methods, &nmethods))
                return cli_error(CLI_USAGE, "accuracy: bad --method '%s' (empty name or too many)", val);
        } else if (!strcmp(a, "--case")) {
            NEED_VALUE();
            if (!cli_split_list(val, cases, &ncases, MAX_LIST))
                return cli_error(CLI_USAGE, "accuracy: bad --case '%s' (empty name or too many)", val);
        } else if (!strcmp(a, "--size")) {
            NEED_VALUE();
            if (!cli_parse_size(val, &desc.width, &desc.height))
                return cli_error(CLI_USAGE,
                                 "accuracy: bad --size '%s' (expected WxH, each 1..%d, at most %u pixels)",
                                 val, PERSP_IMAGE_MAX_SIDE, PERSP_IMAGE_MAX_PIXELS);
        } else if (!strcmp(a, "--seed")) {
            NEED_VALUE();
            long s;
            if (!cli_parse_int(val, 1, 2147483647L, &s))
                return cli_error(CLI_USAGE, "accuracy: bad --seed '%s' (expected 1..2147483647)", val);
            desc.seed = (uint64_t)s;
        } else if (!strcmp(a, "--triangles")) {
            NEED_VALUE();
            long n;
            if (!cli_parse_int(val, 1, 100000, &n))
                return cli_error(CLI_USAGE, "accuracy: bad --triangles '%s' (expected 1..100000)", val);
            desc.triangles = (int)n;
        } else if (!strcmp(a, "--rel-floor")) {
            NEED_VALUE();
            char *end;
            double f = strtod(val, &end);
            if (*end || end == val || !(f > 0.0 && f <= 1.0))
                return cli_error(CLI_USAGE, "accuracy: bad --rel-floor '%s' (expected 0 < X <= 1)", val);
            desc.rel_floor = f;
        } else if (!strcmp(a, "--csv")) {
            format = PERSP_REPORT_CSV;
        } else if (!strcmp(a, "--json")) {
            format = PERSP_REPORT_JSON;
        } else if (!strcmp(a, "--heatmap")) {
            NEED_VALUE();
            desc.heatmap_dir = val;
        } else if (a[0] == '-') {
            return cli_error(CLI_USAGE, "accuracy: unknown option '%s' (see persp accuracy --help)", a);
        } else {
            return cli_error(CLI_USAGE, "accuracy: unexpected argument '%s' (see persp accuracy --help)",
                             a);
        }
#undef NEED_VALUE
    }

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

    persp_context *ctx = NULL;
    persp_status st = persp_context_create(NULL, &ctx);
    if (st != PERSP_OK) return cli_status(NULL, st, "accuracy: context");
    persp_accuracy_result *res = NULL;
    st = persp_accuracy_run(ctx, &desc, &res);
    int rc = CLI_OK;
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, "accuracy");
    } else if ((st = persp_accuracy_write(ctx, res, format, stdout)) != PERSP_OK) {
        rc = cli_status(ctx, st, "accuracy: writing the report");
    }
    persp_accuracy_destroy(res);
    persp_context_destroy(ctx);
    return rc;
}
