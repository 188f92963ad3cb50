#include "options.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void render_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp render [SCENE] [options]\n\n"
                 "SCENE is a built-in scene name or a JSON scene file (default: corridor),\n"
                 "or a model file (OBJ, glTF/GLB, PLY, STL, FBX, COLLADA, 3DS, ...) shown with a\n"
                 "default camera and lights (docs/SCENES.md).\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
    fprintf(out, "\nbuilt-in scenes:\n");
    for (size_t i = 0; i < persp_builtin_scene_count(); i++)
        fprintf(out, "  %-10s %s\n", persp_builtin_scene_name(i), persp_builtin_scene_summary(i));
}

/* The encoding of the output: --format, else the -o file's extension (PNG
 * for standard output and for a device or pipe without one); a known
 * extension that --format contradicts is refused. */
static int output_format(const char *output, persp_image_format format, persp_image_format *out)
{
    persp_image_format by_name = PERSP_IMAGE_FORMAT_DEFAULT;
    int named = output && strcmp(output, "-");
    int known = named && persp_image_format_from_path(output, &by_name) == PERSP_OK;
    struct stat sb;
    if (named && !known && stat(output, &sb) == 0 && !S_ISREG(sb.st_mode) && !S_ISDIR(sb.st_mode))
        named = 0;
    if (format == PERSP_IMAGE_FORMAT_DEFAULT) {
        if (named && !known)
            return cli_error(
                CLI_USAGE,
                "render: cannot tell the image format of '%s' from its extension (expected "
                ".png, .jpg or .jpeg, or --format png|jpeg)",
                output);
        *out = known ? by_name : PERSP_IMAGE_FORMAT_PNG;
        return CLI_OK;
    }
    if (known && by_name != format)
        return cli_error(CLI_USAGE, "render: --format %s does not match the extension of '%s'",
                         format == PERSP_IMAGE_FORMAT_JPEG ? "jpeg" : "png", output);
    *out = format;
    return CLI_OK;
}

/* Everything the phases of `persp render` share: the options as parsed,
 * then what the checks derive from them. */
typedef struct render_job {
    const char *scene_name, *output, *texture, *method;
    cli_filter filter;
    cli_shading shading;
    cli_size size;
    int quiet, threads, quality;
    size_t max_memory;
    persp_simd simd;
    float min_lod, max_lod;
    persp_image_format format;
    persp_scene_load_desc load;
    persp_render_desc desc;
    persp_image_write_desc wd;
    int to_stdout;
    FILE *summary;     /* stdout, or stderr when the image goes to stdout */
    double t_start;    /* cmd_render's start: the total time is from here */
    char default_out[512];
} render_job;

/* Seconds each phase took, for the summary. */
typedef struct render_times {
    double render, write, total;
} render_times;

/* Parses argv into job; CLI_OK, CLI_HELP (the help printed) or CLI_USAGE. */
static int render_parse(int argc, char **argv, render_job *job, int *lod_given)
{
    cli_option opts[] = {
        CLI_OPT_HELP(cli_opt_output, &job->output,
                     "image to write, PNG or JPEG by its extension (.png,\n"
                     ".jpg, .jpeg); - for standard output (default:\n"
                     "out/SCENE.png)"),
        CLI_OPT(cli_opt_format, &job->format),
        CLI_OPT(cli_opt_quality, &job->quality),
        CLI_OPT(cli_opt_method, &job->method),
        CLI_OPT(cli_opt_filter, &job->filter),
        CLI_OPT(cli_opt_wrap, &job->desc.wrap),
        CLI_OPT(cli_opt_shading, &job->shading),
        CLI_OPT_HELP(cli_opt_size, &job->size, "image size (default: the scene's, else 1024x768)"),
        CLI_OPT(cli_opt_depth, &job->desc.depth_mode),
        CLI_OPT(cli_opt_lod, &job->desc.lod_mode),
        CLI_OPT(cli_opt_lod_bias, &job->desc.lod_bias),
        CLI_OPT(cli_opt_min_lod, &job->min_lod),
        CLI_OPT(cli_opt_max_lod, &job->max_lod),
        CLI_OPT(cli_opt_pipeline, &job->desc.pipeline),
        CLI_OPT(cli_opt_texture, &job->texture),
        CLI_OPT(cli_opt_any_folder, &job->load.any_folder),
        CLI_OPT(cli_opt_up, &job->load.model_up),
        CLI_OPT(cli_opt_formats, &job->load.formats),
        CLI_OPT(cli_opt_import, &job->load.import),
        CLI_OPT(cli_opt_import_timeout, &job->load.import_time_limit_ms),
        CLI_OPT(cli_opt_crease, &job->load.crease_deg),
        CLI_OPT(cli_opt_threads, &job->threads),
        CLI_OPT(cli_opt_max_memory, &job->max_memory),
        CLI_OPT(cli_opt_simd, &job->simd),
        CLI_OPT(cli_opt_cull, &job->desc.cull_backfaces),
        CLI_OPT(cli_opt_sort_first, &job->desc.sort_first),
        CLI_OPT(cli_opt_count_ops, &job->desc.count_ops),
        CLI_OPT_HELP(cli_opt_quiet, &job->quiet,
                     "print nothing on success (with -o -, the summary goes\n"
                     "to standard error unless -q)"),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    const char *scene_arg[1] = {NULL};
    cli_command cmd = {
        "render", "persp render --help", NULL, opts, sizeof opts / sizeof opts[0], scene_arg, 1, 0,
        "scene"};
    int rc = cli_parse_or_usage(&cmd, argc, argv, render_usage);
    job->scene_name = scene_arg[0] ? scene_arg[0] : "corridor";
    *lod_given = cli_given(&cmd, &cli_opt_min_lod) || cli_given(&cmd, &cli_opt_max_lod);
    return rc;
}

/* The usage and file checks, before any work: the render takes seconds, the
 * error must not come after it, and nothing may be written over an input. */
static int render_check(render_job *job, int lod_given, int quality_given)
{
    int rc;
    if (lod_given) {
        if (job->min_lod > job->max_lod)
            return cli_error(CLI_USAGE, "render: --min-lod %g is above --max-lod %g", (double)job->min_lod,
                             (double)job->max_lod);
        job->desc.lod_clamp = PERSP_TOGGLE_ON;
        job->desc.min_lod = job->min_lod;
        job->desc.max_lod = job->max_lod;
    }
    job->wd.quality = job->quality;
    if ((rc = output_format(job->output, job->format, &job->wd.format)) != CLI_OK) return rc;
    if (quality_given && job->wd.format != PERSP_IMAGE_FORMAT_JPEG)
        cli_warning(NULL, "--quality applies to JPEG output only; the PNG is lossless");
    job->to_stdout = job->output && !strcmp(job->output, "-");
    if ((rc = cli_check_output("render", "-o", job->output)) != CLI_OK) return rc;
    if ((rc = cli_check_not_input("render", "-o", job->output, job->scene_name)) != CLI_OK) return rc;
    if ((rc = cli_check_not_input("render", "-o", job->output, job->texture)) != CLI_OK) return rc;
    if (job->to_stdout && isatty(STDOUT_FILENO))
        return cli_error(CLI_USAGE, "render: not writing a binary image to a terminal (redirect -o - "
                                    "to a file or a pipe)");
    /* With the image on standard output, the summary must not mix with it. */
    job->summary = job->to_stdout ? stderr : stdout;
    if ((rc = cli_check_scene("render", job->scene_name)) != CLI_OK) return rc;
    job->desc.method = job->method;
    job->desc.filter = job->filter.filter;
    job->desc.max_aniso = job->filter.max_aniso;
    job->desc.shading = job->shading.shading;
    return CLI_OK;
}

/* The built-in scene or the file, with --texture applied. */
static int render_load(persp_context *ctx, const render_job *job, persp_scene **scene)
{
    persp_status st = cli_is_builtin(job->scene_name) ? persp_scene_builtin(ctx, job->scene_name, scene)
                                                      : persp_scene_load_ex(ctx, job->scene_name, &job->load, scene);
    if (st != PERSP_OK) return cli_status(ctx, st, job->scene_name);
    return job->texture ? cli_replace_texture(ctx, *scene, job->texture) : CLI_OK;
}

/* The colour image and the depth buffer in an image's storage (4 bytes per
 * pixel, as a float): 64-byte-aligned rows like the colour's, which helps
 * several threads. */
static int render_buffers(persp_context *ctx, int width, int height, persp_image *img, persp_image *depth,
                          persp_framebuffer *fb)
{
    persp_status st = persp_image_alloc(ctx, width, height, img);
    if (st != PERSP_OK) return cli_status(ctx, st, "render");
    if ((st = persp_image_alloc(ctx, width, height, depth)) != PERSP_OK)
        return cli_status(ctx, st, "render: depth buffer");
    fb->width = width;
    fb->height = height;
    fb->color = img->pixels;
    fb->depth = (float *)(void *)depth->pixels;
    return CLI_OK;
}

/* Encodes and writes the image: to -o, standard output, or out/SCENE.EXT. */
static int render_write(persp_context *ctx, render_job *job, const persp_image *img)
{
    if (!job->output) {
        const char *base = strrchr(job->scene_name, '/');
        base = base ? base + 1 : job->scene_name;
        size_t len = strcspn(base, ".");
        snprintf(job->default_out, sizeof job->default_out, "out/%.*s.%s", (int)len, base,
                 job->wd.format == PERSP_IMAGE_FORMAT_JPEG ? "jpg" : "png");
        job->output = job->default_out;
        /* The default folder is persp's own; an -o path's folder is the user's. */
        if (mkdir("out", 0777) != 0 && errno != EEXIST)
            return cli_error(CLI_FAIL, "render: cannot create the folder 'out': %s", strerror(errno));
    }
    persp_status st = job->to_stdout ? persp_image_write_stream(ctx, stdout, "standard output", img, &job->wd)
                                     : persp_image_write(ctx, job->output, img, &job->wd);
    return st == PERSP_OK ? CLI_OK : cli_status(ctx, st, "render");
}

/* The filter the scene used, where --filter did not choose one. */
static void scene_filter_name(const persp_scene_info *info, char *buf, size_t size)
{
    if (info->filter_count == 0) {
        snprintf(buf, size, "none (untextured)");
        return;
    }
    int n = snprintf(buf, size, "%s", persp_filter_name(info->filter));
    if ((info->filter == PERSP_FILTER_ANISO || info->filter == PERSP_FILTER_ANISO_WINDOW) && n > 0)
        snprintf(buf + n, size - (size_t)n, ":%d", info->max_aniso ? info->max_aniso : PERSP_MAX_ANISO);
    if (info->filter_count > 1 && n > 0)
        snprintf(buf + strlen(buf), size - strlen(buf), " (and others per object)");
}

static void render_summary(const render_job *job, const persp_scene *scene, int width, int height,
                           const persp_render_stats *stats, const render_times *t)
{
    FILE *f = job->summary;
    /* Name what was used, also where the scene itself chose it. */
    persp_scene_info info;
    persp_scene_get_info(scene, &info);
    char scene_filter[64];
    scene_filter_name(&info, scene_filter, sizeof scene_filter);
    fprintf(f, "rendered %s: %dx%d, method %s, filter %s, shading %s, depth %s, %d thread%s%s\n", job->scene_name,
            width, height, job->method ? job->method : info.method, job->filter.name ? job->filter.name : scene_filter,
            job->shading.name ? job->shading.name : persp_shading_name(info.shading),
            job->desc.depth_mode == PERSP_DEPTH_INVW ? "1/w" : "z", job->threads, job->threads == 1 ? "" : "s",
            stats->sort_first_regions ? " sort first" : "");
    fprintf(f, "  %llu triangles in, %llu drawn (clipping may split one), %llu fragments, %llu pixels written\n",
            (unsigned long long)stats->triangles_in, (unsigned long long)stats->triangles_drawn,
            (unsigned long long)stats->fragments, (unsigned long long)stats->pixels_written);
    if (job->desc.pipeline == PERSP_PIPELINE_OBJECT)
        fprintf(f,
                "  object space: %llu pieces, %llu samples walked, %llu splats, %llu holes, "
                "%llu rows and samples visited\n",
                (unsigned long long)stats->objspace_pieces, (unsigned long long)stats->objspace_samples,
                (unsigned long long)stats->objspace_splats, (unsigned long long)stats->objspace_holes,
                (unsigned long long)stats->objspace_visited);
    if (job->desc.count_ops == PERSP_TOGGLE_ON) {
        /* Per pixel the method computed coordinates for (ops.pixels):
         * spans hidden whole and untextured objects run no method, so
         * dividing by all fragments understated the cost. */
        double px = stats->ops.pixels ? (double)stats->ops.pixels : 1.0;
        fprintf(f,
                "  method operations per pixel computed (%llu of %llu fragments): %.3f div, "
                "%.3f mul, %.3f add, %.3f cmp\n",
                (unsigned long long)stats->ops.pixels, (unsigned long long)stats->fragments,
                (double)stats->ops.div / px, (double)stats->ops.mul / px, (double)stats->ops.add / px,
                (double)stats->ops.cmp / px);
    }
    /* The render alone is what the methods change; encoding and writing a
     * large PNG can take far longer, so both are named, and the total. */
    fprintf(f, "  render %.2f ms (%.1f Mpixels/s), encode and write %.2f ms, total %.2f ms -> %s\n",
            t->render * 1e3, (double)width * height / (t->render * 1e6), t->write * 1e3, t->total * 1e3,
            job->to_stdout ? "standard output" : job->output);
}

static int render_body(persp_context *ctx, cli_output *out, void *user)
{
    (void)out;
    render_job *job = user;
    persp_scene *scene = NULL;
    persp_framebuffer fb = {0, 0, NULL, NULL};
    persp_image img = {0, 0, 0, NULL}, depth = {0, 0, 0, NULL};
    persp_render_stats stats;
    render_times t = {0.0, 0.0, 0.0};
    int width = job->size.width, height = job->size.height;
    int rc = render_load(ctx, job, &scene);
    if (rc == CLI_OK) {
        if (!width) persp_scene_default_size(scene, &width, &height);
        if (!width) width = 1024, height = 768;
        rc = render_buffers(ctx, width, height, &img, &depth, &fb);
    }
    if (rc == CLI_OK) {
        double t0 = cli_now();
        persp_status st = persp_render(ctx, scene, &job->desc, &fb, &stats);
        t.render = cli_now() - t0;
        if (st != PERSP_OK) rc = cli_status(ctx, st, "render");
    }
    if (rc == CLI_OK) {
        double t0 = cli_now();
        rc = render_write(ctx, job, &img);
        t.write = cli_now() - t0;
        t.total = cli_now() - job->t_start;
    }
    if (rc == CLI_OK && !job->quiet) render_summary(job, scene, width, height, &stats, &t);
    persp_image_free(ctx, &depth);
    persp_image_free(ctx, &img);
    persp_scene_destroy(scene);
    return rc;
}

int cmd_render(int argc, char **argv)
{
    render_job job;
    memset(&job, 0, sizeof job);
    job.t_start = cli_now();
    job.threads = 1;
    job.min_lod = -PERSP_LOD_LIMIT;
    job.max_lod = PERSP_LOD_LIMIT;
    int lod_given = 0;
    int rc = render_parse(argc, argv, &job, &lod_given);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    if ((rc = render_check(&job, lod_given, job.quality != 0)) != CLI_OK) return rc;
    cli_run_desc run = {.command = "render", .threads = job.threads, .max_memory = job.max_memory, .simd = job.simd};
    return cli_run(&run, render_body, &job);
}
