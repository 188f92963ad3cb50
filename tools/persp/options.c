#include "options.h"

#include <errno.h>
#include <unistd.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Help text starts in this column; a longer option name gets two spaces. */
#define HELP_COLUMN 24

/* ------------------------------------------------------------ messages */

/* "a, b or c" from a NULL-terminated list. */
static void join_names(char *buf, size_t size, const char *const *names)
{
    size_t n = 0;
    while (names[n])
        n++;
    buf[0] = '\0';
    for (size_t i = 0; i < n; i++) {
        size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%s",
                 i == 0       ? ""
                 : i + 1 == n ? " or "
                              : ", ",
                 names[i]);
    }
}

/* The accepted values of opt, for messages. */
static void describe(const cli_option *opt, char *buf, size_t size)
{
    const cli_spec *s = opt->spec;
    if (s->accepts) {
        snprintf(buf, size, "%s", s->accepts);
        return;
    }
    switch (s->kind) {
    case CLI_KIND_INT:
        snprintf(buf, size, "%.0f..%.0f", s->lo, s->hi);
        break;
    case CLI_KIND_REAL:
        snprintf(buf, size, "%g..%g", s->lo, s->hi);
        break;
    case CLI_KIND_SIZE: {
        int hi = s->hi > 0 ? (int)s->hi : PERSP_IMAGE_MAX_SIDE;
        int n = snprintf(buf, size, "WxH, each 1..%d", hi);
        if ((double)hi * hi > (double)PERSP_IMAGE_MAX_PIXELS && n > 0 && (size_t)n < size)
            snprintf(buf + n, size - (size_t)n, ", at most %u pixels", PERSP_IMAGE_MAX_PIXELS);
        break;
    }
    case CLI_KIND_ENUM:
    case CLI_KIND_STRING:
        if (s->names) {
            join_names(buf, size, s->names);
            break;
        }
        /* fall through */
    default:
        snprintf(buf, size, "%s", s->metavar ? s->metavar : "a value");
        break;
    }
}

int cli_bad_value(const cli_command *cmd, const cli_option *opt, const char *value)
{
    char accepts[512];
    describe(opt, accepts, sizeof accepts);
    return cli_error(CLI_USAGE, "%s: bad --%s '%s' (expected %s)", cmd->name, opt->spec->name,
                     value ? value : "", accepts);
}

/* A destination whose size matches none the kind allows is a mistake in a
 * command's table, not in the arguments. */
static int bad_table(const cli_command *cmd, const cli_option *opt)
{
    return cli_error(CLI_FAIL, "%s: internal error: option --%s has a %zu-byte destination",
                     cmd->name, opt->spec->name, opt->size);
}

/* ------------------------------------------------------------ storing */

static int store_int(const cli_option *opt, long v)
{
    if (opt->size == sizeof(int)) {
        int x = (int)v;
        memcpy(opt->dest, &x, sizeof x);
    } else if (opt->size == sizeof(long long)) {
        long long x = v;
        memcpy(opt->dest, &x, sizeof x);
    } else {
        return 0;
    }
    return 1;
}

static int store_real(const cli_option *opt, double v)
{
    if (opt->size == sizeof(float)) {
        float x = (float)v;
        memcpy(opt->dest, &x, sizeof x);
    } else if (opt->size == sizeof(double)) {
        memcpy(opt->dest, &v, sizeof v);
    } else {
        return 0;
    }
    return 1;
}

static int apply(const cli_command *cmd, cli_option *opt, char *value)
{
    const cli_spec *s = opt->spec;
    if (!value && s->optional && s->kind != CLI_KIND_CUSTOM) return CLI_OK;
    switch (s->kind) {
    case CLI_KIND_HELP:
        return CLI_HELP;
    case CLI_KIND_FLAG:
        return store_int(opt, s->set ? s->set : 1) ? CLI_OK : bad_table(cmd, opt);
    case CLI_KIND_INT: {
        long v;
        if (!cli_parse_int(value, (long)s->lo, (long)s->hi, &v))
            return cli_bad_value(cmd, opt, value);
        return store_int(opt, v) ? CLI_OK : bad_table(cmd, opt);
    }
    case CLI_KIND_REAL: {
        double v;
        if (!cli_parse_real(value, s->lo, s->hi, &v)) return cli_bad_value(cmd, opt, value);
        return store_real(opt, v) ? CLI_OK : bad_table(cmd, opt);
    }
    case CLI_KIND_ENUM:
        for (size_t i = 0; s->names[i]; i++)
            if (!strcmp(value, s->names[i]))
                return store_int(opt, s->values[i]) ? CLI_OK : bad_table(cmd, opt);
        return cli_bad_value(cmd, opt, value);
    case CLI_KIND_SIZE: {
        cli_size size;
        int hi = s->hi > 0 ? (int)s->hi : PERSP_IMAGE_MAX_SIDE;
        if (opt->size != sizeof size) return bad_table(cmd, opt);
        if (!cli_parse_size(value, &size.width, &size.height) || size.width > hi ||
            size.height > hi)
            return cli_bad_value(cmd, opt, value);
        memcpy(opt->dest, &size, sizeof size);
        return CLI_OK;
    }
    case CLI_KIND_STRING: {
        if (opt->size != sizeof(const char *)) return bad_table(cmd, opt);
        int ok = !s->names;
        for (size_t i = 0; !ok && s->names[i]; i++)
            ok = !strcmp(value, s->names[i]);
        if (!ok) return cli_bad_value(cmd, opt, value);
        const char *v = value;
        memcpy(opt->dest, &v, sizeof v);
        return CLI_OK;
    }
    case CLI_KIND_CUSTOM:
        return s->parse(cmd, opt, value);
    }
    return bad_table(cmd, opt);
}

/* ------------------------------------------------------------- parsing */

static cli_option *find_long(cli_command *cmd, const char *name, size_t len)
{
    for (size_t i = 0; i < cmd->count; i++) {
        const char *n = cmd->opts[i].spec->name;
        if (strlen(n) == len && !strncmp(n, name, len)) return &cmd->opts[i];
    }
    return NULL;
}

static cli_option *find_short(cli_command *cmd, char c)
{
    for (size_t i = 0; i < cmd->count; i++)
        if (cmd->opts[i].spec->short_name == c) return &cmd->opts[i];
    return NULL;
}

static int add_operand(cli_command *cmd, const char *arg)
{
    if (cmd->operand_count < cmd->max_operands) {
        cmd->operands[cmd->operand_count++] = arg;
        return CLI_OK;
    }
    if (cmd->max_operands == 1 && cmd->operand_name)
        return cli_error(CLI_USAGE, "%s: more than one %s given ('%s', '%s')", cmd->name,
                         cmd->operand_name, cmd->operands[0], arg);
    return cli_error(CLI_USAGE, "%s: unexpected argument '%s' (see %s)", cmd->name, arg,
                     cmd->help_ref);
}

int cli_parse(cli_command *cmd, int argc, char **argv)
{
    int operands_only = 0;
    cmd->operand_count = 0;
    for (int i = 1; i < argc; i++) {
        char *a = argv[i];
        if (operands_only || a[0] != '-' || a[1] == '\0') {
            int rc = add_operand(cmd, a);
            if (rc != CLI_OK) return rc;
            continue;
        }
        if (!strcmp(a, "--")) {
            operands_only = 1;
            continue;
        }
        cli_option *opt;
        char *eq = NULL;
        if (a[1] == '-') {
            eq = strchr(a + 2, '=');
            size_t len = eq ? (size_t)(eq - (a + 2)) : strlen(a + 2);
            opt = find_long(cmd, a + 2, len);
            if (!opt)
                return cli_error(CLI_USAGE, "%s: unknown option '%.*s'%s (see %s)", cmd->name,
                                 (int)len + 2, a, cmd->unknown_note ? cmd->unknown_note : "",
                                 cmd->help_ref);
        } else {
            opt = a[2] == '\0' ? find_short(cmd, a[1]) : NULL;
            if (!opt)
                return cli_error(CLI_USAGE, "%s: unknown option '%s'%s (see %s)", cmd->name, a,
                                 cmd->unknown_note ? cmd->unknown_note : "", cmd->help_ref);
        }
        const cli_spec *s = opt->spec;
        char *value = NULL;
        if (s->kind == CLI_KIND_HELP || s->kind == CLI_KIND_FLAG) {
            if (eq)
                return cli_error(CLI_USAGE, "%s: option --%s takes no value", cmd->name, s->name);
        } else if (eq) {
            value = eq + 1;
        } else if (s->optional) {
            if (i + 1 < argc && argv[i + 1][0] != '-') value = argv[++i];
        } else if (i + 1 < argc) {
            value = argv[++i];
        } else {
            char accepts[512];
            describe(opt, accepts, sizeof accepts);
            return cli_error(CLI_USAGE, "%s: option %s needs a value (expected %s)", cmd->name, a,
                             accepts);
        }
        /* A second value would silently override the first; only list
         * options, which append, may repeat. */
        if (opt->seen && !s->repeatable && s->parse != cli_parse_list)
            return cli_error(CLI_USAGE, "%s: option --%s given more than once", cmd->name,
                             s->name);
        opt->seen++;
        int rc = apply(cmd, opt, value);
        if (rc != CLI_OK) return rc;
    }
    return CLI_OK;
}

int cli_given(const cli_command *cmd, const cli_spec *spec)
{
    for (size_t i = 0; i < cmd->count; i++)
        if (cmd->opts[i].spec == spec) return cmd->opts[i].seen;
    return 0;
}

void cli_print_options(FILE *out, const cli_command *cmd)
{
    for (size_t i = 0; i < cmd->count; i++) {
        const cli_option *opt = &cmd->opts[i];
        const cli_spec *s = opt->spec;
        const char *help = opt->help ? opt->help : s->help;
        if (!help) continue;
        char left[96];
        if (s->short_name)
            snprintf(left, sizeof left, "  -%c, --%s%s%s", s->short_name, s->name,
                     s->metavar ? " " : "", s->metavar ? s->metavar : "");
        else
            snprintf(left, sizeof left, "  --%s%s%s", s->name, s->metavar ? " " : "",
                     s->metavar ? s->metavar : "");
        int pad = (int)strlen(left) <= HELP_COLUMN - 2 ? HELP_COLUMN - (int)strlen(left) : 2;
        fprintf(out, "%s%*s", left, pad, "");
        for (const char *line = help;;) {
            size_t len = strcspn(line, "\n");
            fprintf(out, "%.*s\n", (int)len, line);
            if (!line[len]) break;
            line += len + 1;
            fprintf(out, "%*s", HELP_COLUMN, "");
        }
    }
}

/* ------------------------------------------------------ custom parsers */

int cli_parse_list(const cli_command *cmd, const cli_option *opt, char *value)
{
    cli_list *list = opt->dest;
    if (!value) return CLI_OK; /* an optional list left out */
    size_t items = 1;
    int empty = value[0] == '\0';
    for (const char *p = value; *p; p++) {
        if (*p != ',') continue;
        items++;
        if (p == value || p[1] == ',' || p[1] == '\0') empty = 1;
    }
    if (empty || list->count + items > list->cap)
        return cli_error(CLI_USAGE,
                         "%s: bad --%s '%s' (expected a comma-separated list of names, none empty, "
                         "at most %zu in all)",
                         cmd->name, opt->spec->name, value, list->cap);
    return cli_split_list(value, list->items, &list->count, list->cap)
               ? CLI_OK
               : cli_bad_value(cmd, opt, value);
}

static int parse_method(const cli_command *cmd, const cli_option *opt, char *value)
{
    int bad = cli_check_method(cmd->name, value);
    if (bad) return bad;
    const char *v = value;
    memcpy(opt->dest, &v, sizeof v);
    return CLI_OK;
}

/* "a, b or c" of the names that name() gives for values first..last. */
static void list_names(char *buf, size_t size, int first, int last, const char *(*name)(int),
                       const char *(*suffix)(int))
{
    buf[0] = '\0';
    for (int v = first; v <= last; v++) {
        size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%s%s",
                 v == first  ? ""
                 : v == last ? " or "
                             : ", ",
                 name(v), suffix ? suffix(v) : "");
    }
}

static const char *filter_name(int v)
{
    return persp_filter_name((persp_filter)v);
}

static const char *filter_suffix(int v)
{
    /* The list names the bound PERSP_MAX_ANISO gives. */
#define CLI_STR_(x) #x
#define CLI_STR(x) CLI_STR_(x)
    static const char taps[] = ":N (N = 2.." CLI_STR(PERSP_MAX_ANISO) ")";
    return v == PERSP_FILTER_ANISO || v == PERSP_FILTER_ANISO_WINDOW ? taps : "";
}

static int parse_filter(const cli_command *cmd, const cli_option *opt, char *value)
{
    cli_filter *f = opt->dest;
    persp_status st = persp_filter_parse(value, &f->filter, &f->max_aniso);
    /* persp_filter_parse tells a known filter with a bad tap count apart. */
    if (st == PERSP_ERR_INVALID_ARGUMENT)
        return cli_error(CLI_USAGE, "%s: bad --filter '%s': aniso taps must be 2..%d", cmd->name,
                         value, PERSP_MAX_ANISO);
    if (st != PERSP_OK) {
        char names[512];
        list_names(names, sizeof names, PERSP_FILTER_DEFAULT + 1, PERSP_FILTER_COUNT - 1,
                   filter_name, filter_suffix);
        return cli_error(CLI_USAGE, "%s: unknown filter '%s' (expected %s)", cmd->name, value,
                         names);
    }
    f->name = value;
    return CLI_OK;
}

static const char *shading_name(int v)
{
    return persp_shading_name((persp_shading)v);
}

static int parse_shading(const cli_command *cmd, const cli_option *opt, char *value)
{
    cli_shading *s = opt->dest;
    if (persp_shading_parse(value, &s->shading) != PERSP_OK) {
        char names[512];
        list_names(names, sizeof names, PERSP_SHADING_DEFAULT + 1, PERSP_SHADING_COUNT - 1,
                   shading_name, NULL);
        return cli_error(CLI_USAGE, "%s: unknown shading '%s' (expected %s)", cmd->name, value,
                         names);
    }
    s->name = value;
    return CLI_OK;
}

static const char *wrap_name(int v)
{
    return persp_wrap_name((persp_wrap)v);
}

static int parse_wrap(const cli_command *cmd, const cli_option *opt, char *value)
{
    persp_wrap w;
    if (persp_wrap_parse(value, &w) != PERSP_OK) {
        char names[256];
        list_names(names, sizeof names, PERSP_WRAP_REPEAT, PERSP_WRAP_CLAMP_TO_BORDER, wrap_name,
                   NULL);
        return cli_error(CLI_USAGE, "%s: unknown wrap mode '%s' (expected %s)", cmd->name, value,
                         names);
    }
    memcpy(opt->dest, &w, sizeof w);
    return CLI_OK;
}

/* ------------------------------------------------------- shared specs */

static const char *const depth_names[] = {"z", "invw", NULL};
static const int depth_values[] = {PERSP_DEPTH_Z, PERSP_DEPTH_INVW};
static const char *const lod_names[] = {"pixel", "polygon", NULL};
static const int lod_values[] = {PERSP_LOD_PIXEL, PERSP_LOD_POLYGON};
static const char *const pipeline_names[] = {"screen", "object", NULL};
static const int pipeline_values[] = {PERSP_PIPELINE_SCREEN, PERSP_PIPELINE_OBJECT};
static const char *const cull_names[] = {"on", "off", NULL};
static const int cull_values[] = {PERSP_TOGGLE_ON, PERSP_TOGGLE_OFF};
static const char *const simd_names[] = {"auto",   "baseline", "avx2", "avx2-gather",
                                          "avx512", "avx512-gather", NULL};
static const int simd_values[] = {PERSP_SIMD_AUTO,   PERSP_SIMD_BASELINE, PERSP_SIMD_AVX2,
                                  PERSP_SIMD_AVX2_GATHER, PERSP_SIMD_AVX512,
                                  PERSP_SIMD_AVX512_GATHER};
static const char *const format_names[] = {"png", "jpeg", "jpg", NULL};
static const int format_values[] = {PERSP_IMAGE_FORMAT_PNG, PERSP_IMAGE_FORMAT_JPEG,
                                    PERSP_IMAGE_FORMAT_JPEG};

const cli_spec cli_opt_help = {
    .name = "help", .short_name = 'h', .kind = CLI_KIND_HELP, .help = "this help"};
const cli_spec cli_opt_output = {.name = "output",
                                 .short_name = 'o',
                                 .kind = CLI_KIND_STRING,
                                 .metavar = "FILE",
                                 .help = "where to write; - for standard output"};
const cli_spec cli_opt_output_dir = {.name = "output",
                                     .short_name = 'o',
                                     .kind = CLI_KIND_STRING,
                                     .metavar = "DIR",
                                     .help = "the folder to write into"};
const cli_spec cli_opt_quiet = {
    .name = "quiet", .short_name = 'q', .kind = CLI_KIND_FLAG, .help = "print nothing on success"};
const cli_spec cli_opt_method = {
    .name = "method",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "M",
    .parse = parse_method,
    .accepts = "a method of `persp methods`",
    .help = "texture-coordinate method (default exact; see `persp methods`)"};
const cli_spec cli_opt_filter = {
    .name = "filter",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "F",
    .parse = parse_filter,
    .accepts = "a texture filter",
    .help = "nearest | bilinear | nearest-mip-nearest | bilinear-mip-nearest |\n"
            "nearest-mip-linear | trilinear | aniso:N | aniso-window:N | ewa"};
const cli_spec cli_opt_wrap = {.name = "wrap",
                               .kind = CLI_KIND_CUSTOM,
                               .metavar = "W",
                               .parse = parse_wrap,
                               .accepts = "a wrap mode",
                               .help =
                                   "repeat | clamp-to-edge | mirrored-repeat | clamp-to-border"};
const cli_spec cli_opt_shading = {.name = "shading",
                                  .kind = CLI_KIND_CUSTOM,
                                  .metavar = "S",
                                  .parse = parse_shading,
                                  .accepts = "a shading mode",
                                  .help =
                                      "none | flat | gouraud | gouraud-pc | phong | phong-pc |\n"
                                      "phong-pc:quad | phong-pc:pwquad | phong-pc:cubic |\n"
                                      "phong-slerp | phong-slerp-screen"};
const cli_spec cli_opt_size = {
    .name = "size", .kind = CLI_KIND_SIZE, .metavar = "WxH", .help = "image size"};
const cli_spec cli_opt_depth = {.name = "depth",
                                .kind = CLI_KIND_ENUM,
                                .metavar = "z|invw",
                                .names = depth_names,
                                .values = depth_values,
                                .help = "depth buffer: window z, or 1/w (\"1/z buffering\")"};
const cli_spec cli_opt_lod = {.name = "lod",
                              .kind = CLI_KIND_ENUM,
                              .metavar = "pixel|polygon",
                              .names = lod_names,
                              .values = lod_values,
                              .help = "mip level per pixel (Jacobian) or per polygon"};
const cli_spec cli_opt_lod_bias = {.name = "lod-bias",
                                   .kind = CLI_KIND_REAL,
                                   .metavar = "B",
                                   .lo = -16,
                                   .hi = 16,
                                   .help = "added to the level of detail, -16..16"};
const cli_spec cli_opt_min_lod = {.name = "min-lod",
                                  .kind = CLI_KIND_REAL,
                                  .metavar = "L",
                                  .lo = -PERSP_LOD_LIMIT,
                                  .hi = PERSP_LOD_LIMIT,
                                  .help =
                                      "clamp the level of detail from below (GL default -1000)"};
const cli_spec cli_opt_max_lod = {.name = "max-lod",
                                  .kind = CLI_KIND_REAL,
                                  .metavar = "L",
                                  .lo = -PERSP_LOD_LIMIT,
                                  .hi = PERSP_LOD_LIMIT,
                                  .help = "clamp the level of detail from above (GL default 1000)"};
const cli_spec cli_opt_pipeline = {.name = "pipeline",
                                   .kind = CLI_KIND_ENUM,
                                   .metavar = "screen|object",
                                   .names = pipeline_names,
                                   .values = pipeline_values,
                                   .help = "inverse mapping per pixel, or object-space texturing"};
const cli_spec cli_opt_texture = {.name = "texture",
                                  .kind = CLI_KIND_STRING,
                                  .metavar = "FILE",
                                  .help = "replace the texture of every textured object with a PNG,\n"
                                          "JPEG, TGA or BMP image (warns when nothing is textured)"};
const cli_spec cli_opt_any_folder = {
    .name = "any-folder",
    .kind = CLI_KIND_FLAG,
    .set = PERSP_TOGGLE_ON,
    .help = "let the scene read files outside its own folder (by default\n"
            "a scene or model reads only files in its folder and below)"};
const cli_spec cli_opt_threads = {.name = "threads",
                                  .kind = CLI_KIND_INT,
                                  .metavar = "N",
                                  .lo = 1,
                                  .hi = 256,
                                  .help = "worker threads, 1..256 (default 1)"};
const cli_spec cli_opt_simd = {.name = "simd",
                               .kind = CLI_KIND_ENUM,
                               .metavar = "V",
                               .names = simd_names,
                               .values = simd_values,
                               .help = "vector variant of the texture samplers and width of the\n"
                                       "vertex and lighting loops: auto, baseline, avx2,\n"
                                       "avx2-gather, avx512, avx512-gather (same images;\n"
                                       "default auto: chosen for the CPU)"};
static const char *const up_names[] = {"y", "z", "x", "-x", "-y", "-z", NULL};
static const int up_values[] = {PERSP_MODEL_UP_Y,     PERSP_MODEL_UP_Z,     PERSP_MODEL_UP_X,
                                PERSP_MODEL_UP_NEG_X, PERSP_MODEL_UP_NEG_Y, PERSP_MODEL_UP_NEG_Z};
const cli_spec cli_opt_up = {.name = "up",
                             .kind = CLI_KIND_ENUM,
                             .metavar = "AXIS",
                             .names = up_names,
                             .values = up_values,
                             .help = "a model file's up axis: y, z, x, -x, -y, -z (default y;\n"
                                     "z for .blend, SMD and COB; z: STL, 3DS, CAD exports)"};
const cli_spec cli_opt_cull = {.name = "cull",
                               .kind = CLI_KIND_ENUM,
                               .metavar = "on|off",
                               .names = cull_names,
                               .values = cull_values,
                               .help = "back-face culling (default: the scene's)"};
static const char *const sort_first_names[] = {"auto", "on", "off", NULL};
static const int sort_first_values[] = {PERSP_TOGGLE_DEFAULT, PERSP_TOGGLE_ON, PERSP_TOGGLE_OFF};
const cli_spec cli_opt_sort_first = {.name = "sort-first",
                                     .kind = CLI_KIND_ENUM,
                                     .metavar = "auto|on|off",
                                     .names = sort_first_names,
                                     .values = sort_first_values,
                                     .help = "with several threads, each draws the whole frame for\n"
                                             "its own tile rows (on) or they share every stage (off);\n"
                                             "auto: on for two threads whose cores hand each other\n"
                                             "data slowly (same images; default auto)"};
const cli_spec cli_opt_count_ops = {.name = "count-ops",
                                    .kind = CLI_KIND_FLAG,
                                    .set = PERSP_TOGGLE_ON,
                                    .help = "count the method's divisions, multiplications,\n"
                                            "additions and comparisons (instrumented render)"};
const cli_spec cli_opt_format = {.name = "format",
                                 .kind = CLI_KIND_ENUM,
                                 .metavar = "png|jpeg",
                                 .names = format_names,
                                 .values = format_values,
                                 .help = "image format (default: by the -o file's extension;\n"
                                         "png for -o -)"};
const cli_spec cli_opt_quality = {.name = "quality",
                                  .kind = CLI_KIND_INT,
                                  .metavar = "N",
                                  .lo = 1,
                                  .hi = 100,
                                  .help = "JPEG quality 1..100 (default 92)"};
const cli_spec cli_opt_csv = {.name = "csv",
                              .kind = CLI_KIND_FLAG,
                              .set = PERSP_REPORT_CSV,
                              .help = "CSV instead of the table"};
const cli_spec cli_opt_json = {.name = "json",
                               .kind = CLI_KIND_FLAG,
                               .set = PERSP_REPORT_JSON,
                               .help = "JSON instead of the table"};
const cli_spec cli_opt_heatmap = {.name = "heatmap",
                                  .kind = CLI_KIND_STRING,
                                  .metavar = "DIR",
                                  .help = "write per-pixel error heat maps as PNGs into DIR"};
const cli_spec cli_opt_seed = {.name = "seed",
                               .kind = CLI_KIND_INT,
                               .metavar = "N",
                               .lo = 1,
                               .hi = 2147483647.0,
                               .help = "seed of the random triangles (default 1)"};

/* A byte count with an optional binary suffix: 1048576, 64K, 512M, 2G
 * (K = 1024 bytes, and so on; k, m, g alike). */
static int parse_bytes(const cli_command *cmd, const cli_option *opt, char *value)
{
    char *end = NULL;
    errno = 0;
    unsigned long long n = value[0] >= '0' && value[0] <= '9' ? strtoull(value, &end, 10) : 0;
    if (!end || end == value || errno) return cli_bad_value(cmd, opt, value);
    unsigned shift = 0;
    switch (*end) {
    case '\0': break;
    case 'K': case 'k': shift = 10; break;
    case 'M': case 'm': shift = 20; break;
    case 'G': case 'g': shift = 30; break;
    case 'T': case 't': shift = 40; break;
    default: return cli_bad_value(cmd, opt, value);
    }
    if (shift && end[1] != '\0') return cli_bad_value(cmd, opt, value);
    if (n == 0 || n > (unsigned long long)SIZE_MAX >> shift) return cli_bad_value(cmd, opt, value);
    *(size_t *)opt->dest = (size_t)(n << shift);
    return CLI_OK;
}

const cli_spec cli_opt_max_memory = {.name = "max-memory",
                                     .kind = CLI_KIND_CUSTOM,
                                     .metavar = "SIZE",
                                     .parse = parse_bytes,
                                     .accepts = "a byte count, optionally with K, M, G or T "
                                                "(binary), e.g. 512M",
                                     .help = "memory budget of persp, decoders, parsers and\n"
                                             "the model importer, e.g. 512M or 4G (default: 2G,\n"
                                             "or half this machine's memory if that is less)"};

size_t cli_max_memory(size_t given)
{
    if (given) return given;
    /* A budget by default, so that a file cannot make the command take
     * the machine's memory (a 200 MB JSON scene took 4 GB): 2 GiB holds
     * every workload of docs/WORKLOADS.md at 4K with 16 threads. */
    size_t cap = (size_t)2 << 30;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0 && (size_t)pages / 2 < cap / (size_t)page) cap = (size_t)pages / 2 * (size_t)page;
    return cap;
}

/* Seconds (a decimal number, 0.1 to 3600) into milliseconds (unsigned). */
static int parse_seconds_ms(const cli_command *cmd, const cli_option *opt, char *value)
{
    char *end = NULL;
    errno = 0;
    double v = (value[0] >= '0' && value[0] <= '9') ? strtod(value, &end) : -1.0;
    if (!end || *end || errno || !(v >= 0.1 && v <= 3600.0)) return cli_bad_value(cmd, opt, value);
    *(unsigned *)opt->dest = (unsigned)(v * 1000.0 + 0.5);
    return CLI_OK;
}

const cli_spec cli_opt_import_timeout = {
    .name = "import-timeout",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "SECONDS",
    .parse = parse_seconds_ms,
    .accepts = "seconds from 0.1 to 3600",
    .help = "stop model imports that take longer (a scene's\n"
            "together; default: 5 s and 2 s a MiB of what the\n"
            "importer reads, at most 600 s)"};
const cli_spec cli_opt_crease = {.name = "crease",
                                 .kind = CLI_KIND_REAL,
                                 .metavar = "DEG",
                                 .lo = 0.001,
                                 .hi = 180,
                                 .help = "a model without normals: faces meeting at more than\n"
                                         "DEG degrees keep their own (default 80; glTF: flat)"};
static const char *const formats_names[] = {"common", "all", NULL};
static const int formats_values[] = {PERSP_MODEL_FORMATS_COMMON, PERSP_MODEL_FORMATS_ALL};
const cli_spec cli_opt_formats = {
    .name = "formats",
    .kind = CLI_KIND_ENUM,
    .metavar = "common|all",
    .names = formats_names,
    .values = formats_values,
    .help = "model formats read: common (default: OBJ, glTF/GLB, PLY,\n"
            "STL, OFF, FBX, COLLADA, 3DS) or all of Assimp's readers"};
static const char *const import_names[] = {"isolated", "in-process", NULL};
static const int import_values[] = {PERSP_MODEL_IMPORT_ISOLATED, PERSP_MODEL_IMPORT_IN_PROCESS};
const cli_spec cli_opt_import = {
    .name = "import",
    .kind = CLI_KIND_ENUM,
    .metavar = "isolated|in-process",
    .names = import_names,
    .values = import_values,
    .help = "where models are read: isolated (default: a helper\n"
            "process with limits) or in-process (trusted files only:\n"
            "a reader's crash ends persp)"};

int cli_parse_or_usage(cli_command *cmd, int argc, char **argv,
                       void (*usage)(FILE *out, const cli_command *cmd))
{
    int rc = cli_parse(cmd, argc, argv);
    if (rc == CLI_HELP) usage(stdout, cmd);
    return rc;
}
