/* libFuzzer harness: the CLI's option parser (tools/persp/options.c) with a
 * table of every shared option spec (--method, --filter, --wrap, --shading,
 * --size, --lod, --lod-bias, --min-lod, --max-lod, ...), a comma-list option
 * (cli_parse_list) and one operand. The input is the argument vector, its
 * arguments separated by NUL bytes. When cli_parse accepts, every value it
 * stored must be one the option's spec allows (the ranges and names in
 * options.c, the method, filter, wrap and shading contracts of persp.h);
 * when it refuses, it must say so with CLI_USAGE (CLI_FAIL is kept for
 * mistakes in a command's table). The parser's messages go to stderr:
 * scripts/fuzz.sh runs the harness with -close_fd_mask=2. */
#include "confine.h"
#include "options.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_ARGS 24
#define MAX_ITEMS 8

static void broken(const char *what)
{
    fprintf(stderr, "fuzz_options: invariant broken: %s\n", what);
    abort();
}

/* The destinations of one parse, zeroed before it (a zero means "not given"). */
typedef struct dests {
    const char *output, *method, *texture, *heatmap;
    int quiet, threads, quality;
    cli_filter filter;
    persp_wrap wrap;
    cli_shading shading;
    cli_size size;
    persp_depth_mode depth;
    persp_lod_mode lod;
    float lod_bias, min_lod, max_lod;
    persp_pipeline pipeline;
    persp_toggle cull, count_ops, sort_first;
    persp_image_format format;
    persp_report_format report;
    long long seed;
    const char *items[MAX_ITEMS];
    cli_list list;
    const char *operand;
} dests;

static const cli_spec opt_list = {.name = "list",
                                  .kind = CLI_KIND_CUSTOM,
                                  .metavar = "A,B",
                                  .parse = cli_parse_list,
                                  .optional = 1,
                                  .help = "a comma-separated list"};

static int in_range(double v, const cli_spec *s)
{
    return v >= s->lo && v <= s->hi;
}

static void check(const cli_command *cmd, const dests *d)
{
    if (cli_given(cmd, &cli_opt_method) && persp_method_check(d->method) != PERSP_OK)
        broken("--method accepted a spec persp_method_check refuses");
    if (cli_given(cmd, &cli_opt_filter)) {
        const cli_filter *f = &d->filter;
        persp_filter g;
        if ((unsigned)f->filter >= (unsigned)PERSP_FILTER_COUNT || f->max_aniso < 1 ||
            f->max_aniso > 16 || !f->name)
            broken("--filter stored a filter out of range");
        if (persp_filter_parse(f->name, &g, NULL) != PERSP_OK || g != f->filter)
            broken("--filter's stored name does not parse to the stored filter");
    }
    if (cli_given(cmd, &cli_opt_wrap) &&
        !(d->wrap >= PERSP_WRAP_DEFAULT && d->wrap <= PERSP_WRAP_CLAMP_TO_BORDER))
        broken("--wrap stored a mode out of range");
    if (cli_given(cmd, &cli_opt_shading)) {
        persp_shading t;
        if ((unsigned)d->shading.shading >= (unsigned)PERSP_SHADING_COUNT || !d->shading.name ||
            persp_shading_parse(d->shading.name, &t) != PERSP_OK || t != d->shading.shading)
            broken("--shading stored a mode out of range or not its name's");
    }
    if (cli_given(cmd, &cli_opt_size)) {
        const cli_size *s = &d->size;
        if (s->width < 1 || s->height < 1 || s->width > PERSP_IMAGE_MAX_SIDE ||
            s->height > PERSP_IMAGE_MAX_SIDE ||
            (unsigned long long)s->width * (unsigned long long)s->height > PERSP_IMAGE_MAX_PIXELS)
            broken("--size stored a size outside the limits");
    }
    if (cli_given(cmd, &cli_opt_depth) && d->depth != PERSP_DEPTH_Z && d->depth != PERSP_DEPTH_INVW)
        broken("--depth stored another value");
    if (cli_given(cmd, &cli_opt_lod) && d->lod != PERSP_LOD_PIXEL && d->lod != PERSP_LOD_POLYGON)
        broken("--lod stored another value");
    if (cli_given(cmd, &cli_opt_lod_bias) &&
        (!isfinite(d->lod_bias) || !in_range(d->lod_bias, &cli_opt_lod_bias)))
        broken("--lod-bias stored a value outside its range");
    if (cli_given(cmd, &cli_opt_min_lod) &&
        (!isfinite(d->min_lod) || !in_range(d->min_lod, &cli_opt_min_lod)))
        broken("--min-lod stored a value outside its range");
    if (cli_given(cmd, &cli_opt_max_lod) &&
        (!isfinite(d->max_lod) || !in_range(d->max_lod, &cli_opt_max_lod)))
        broken("--max-lod stored a value outside its range");
    if (cli_given(cmd, &cli_opt_pipeline) && d->pipeline != PERSP_PIPELINE_SCREEN &&
        d->pipeline != PERSP_PIPELINE_OBJECT)
        broken("--pipeline stored another value");
    if (cli_given(cmd, &cli_opt_threads) && !in_range(d->threads, &cli_opt_threads))
        broken("--threads stored a value outside its range");
    if (cli_given(cmd, &cli_opt_quality) && !in_range(d->quality, &cli_opt_quality))
        broken("--quality stored a value outside its range");
    if (cli_given(cmd, &cli_opt_seed) && !in_range((double)d->seed, &cli_opt_seed))
        broken("--seed stored a value outside its range");
    if (cli_given(cmd, &cli_opt_cull) && d->cull != PERSP_TOGGLE_ON && d->cull != PERSP_TOGGLE_OFF)
        broken("--cull stored another value");
    if (cli_given(cmd, &cli_opt_sort_first) && d->sort_first != PERSP_TOGGLE_DEFAULT &&
        d->sort_first != PERSP_TOGGLE_ON && d->sort_first != PERSP_TOGGLE_OFF)
        broken("--sort-first stored another value");
    if (cli_given(cmd, &cli_opt_format) && d->format != PERSP_IMAGE_FORMAT_PNG &&
        d->format != PERSP_IMAGE_FORMAT_JPEG)
        broken("--format stored another value");
    if (d->list.count > d->list.cap) broken("--list stored more items than it has room for");
    for (size_t i = 0; i < d->list.count; i++)
        if (!d->list.items[i][0] || strchr(d->list.items[i], ','))
            broken("--list stored an empty item or one with a comma");
    if (cmd->operand_count > cmd->max_operands) broken("more operands stored than allowed");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 4096) return 0;
    char *buf = malloc(size + 1);
    if (!buf) return 0;
    memcpy(buf, data, size);
    buf[size] = '\0';
    char *argv[MAX_ARGS + 2];
    int argc = 0;
    argv[argc++] = "fuzz";
    for (char *p = buf; argc <= MAX_ARGS && p <= buf + size; p += strlen(p) + 1)
        argv[argc++] = p;
    argv[argc] = NULL;

    dests d;
    memset(&d, 0, sizeof d);
    d.list.items = d.items;
    d.list.cap = MAX_ITEMS;
    cli_option opts[] = {
        CLI_OPT(cli_opt_output, &d.output),      CLI_OPT(cli_opt_quiet, &d.quiet),
        CLI_OPT(cli_opt_method, &d.method),      CLI_OPT(cli_opt_filter, &d.filter),
        CLI_OPT(cli_opt_wrap, &d.wrap),          CLI_OPT(cli_opt_shading, &d.shading),
        CLI_OPT(cli_opt_size, &d.size),          CLI_OPT(cli_opt_depth, &d.depth),
        CLI_OPT(cli_opt_lod, &d.lod),            CLI_OPT(cli_opt_lod_bias, &d.lod_bias),
        CLI_OPT(cli_opt_min_lod, &d.min_lod),    CLI_OPT(cli_opt_max_lod, &d.max_lod),
        CLI_OPT(cli_opt_pipeline, &d.pipeline),  CLI_OPT(cli_opt_texture, &d.texture),
        CLI_OPT(cli_opt_threads, &d.threads),    CLI_OPT(cli_opt_cull, &d.cull),
        CLI_OPT(cli_opt_count_ops, &d.count_ops), CLI_OPT(cli_opt_format, &d.format),
        CLI_OPT(cli_opt_quality, &d.quality),    CLI_OPT(cli_opt_csv, &d.report),
        CLI_OPT(cli_opt_json, &d.report),        CLI_OPT(cli_opt_heatmap, &d.heatmap),
        CLI_OPT(cli_opt_seed, &d.seed),          CLI_OPT(opt_list, &d.list),
        CLI_OPT(cli_opt_sort_first, &d.sort_first),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {"fuzz", "fuzz --help", NULL, opts, sizeof opts / sizeof opts[0],
                       &d.operand, 1, 0, "operand"};
    fuzz_confine(1);
    int rc = cli_parse(&cmd, argc, argv);
    fuzz_confine(0);
    if (rc == CLI_OK) check(&cmd, &d);
    else if (rc != CLI_HELP && rc != CLI_USAGE) broken("cli_parse failed other than with CLI_USAGE");
    free(buf);
    return 0;
}
