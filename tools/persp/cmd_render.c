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

int cmd_render(int argc, char **argv)
{
    const char *output = NULL, *texture = NULL, *method = NULL;
    cli_filter filter = {NULL, PERSP_FILTER_DEFAULT, 0};
    cli_shading shading = {NULL, PERSP_SHADING_DEFAULT};
    cli_size size = {0, 0};
    int quiet = 0, threads = 1, quality = 0;
    size_t max_memory = 0;
    persp_simd simd = PERSP_SIMD_AUTO;
    float min_lod = -1000.0f, max_lod = 1000.0f;
    persp_image_format format = PERSP_IMAGE_FORMAT_DEFAULT;
    persp_scene_load_desc load = {PERSP_TOGGLE_DEFAULT};
    persp_render_desc desc;
    memset(&desc, 0, sizeof desc);
    cli_option opts[] = {
        CLI_OPT_HELP(cli_opt_output, &output,
                     "image to write, PNG or JPEG by its extension (.png,\n"
                     ".jpg, .jpeg); - for standard output (default:\n"
                     "out/SCENE.png)"),
        CLI_OPT(cli_opt_format, &format),
        CLI_OPT(cli_opt_quality, &quality),
        CLI_OPT(cli_opt_method, &method),
        CLI_OPT(cli_opt_filter, &filter),
        CLI_OPT(cli_opt_wrap, &desc.wrap),
        CLI_OPT(cli_opt_shading, &shading),
        CLI_OPT_HELP(cli_opt_size, &size, "image size (default: the scene's, else 1024x768)"),
        CLI_OPT(cli_opt_depth, &desc.depth_mode),
        CLI_OPT(cli_opt_lod, &desc.lod_mode),
        CLI_OPT(cli_opt_lod_bias, &desc.lod_bias),
        CLI_OPT(cli_opt_min_lod, &min_lod),
        CLI_OPT(cli_opt_max_lod, &max_lod),
        CLI_OPT(cli_opt_pipeline, &desc.pipeline),
        CLI_OPT(cli_opt_texture, &texture),
        CLI_OPT(cli_opt_any_folder, &load.any_folder),
        CLI_OPT(cli_opt_up, &load.model_up),
        CLI_OPT(cli_opt_formats, &load.formats),
        CLI_OPT(cli_opt_import, &load.import),
        CLI_OPT(cli_opt_import_timeout, &load.import_time_limit_ms),
        CLI_OPT(cli_opt_crease, &load.crease_deg),
        CLI_OPT(cli_opt_threads, &threads),
        CLI_OPT(cli_opt_max_memory, &max_memory),
        CLI_OPT(cli_opt_simd, &simd),
        CLI_OPT(cli_opt_cull, &desc.cull_backfaces),
        CLI_OPT(cli_opt_count_ops, &desc.count_ops),
        CLI_OPT_HELP(cli_opt_quiet, &quiet,
                     "print nothing on success (with -o -, the summary goes\n"
                     "to standard error unless -q)"),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    const char *scene_arg[1] = {NULL};
    cli_command cmd = {
        "render", "persp render --help", NULL, opts, sizeof opts / sizeof opts[0], scene_arg, 1, 0,
        "scene"};
    int rc = cli_parse_or_usage(&cmd, argc, argv, render_usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;

    if (cli_given(&cmd, &cli_opt_min_lod) || cli_given(&cmd, &cli_opt_max_lod)) {
        if (min_lod > max_lod)
            return cli_error(CLI_USAGE, "render: --min-lod %g is above --max-lod %g",
                             (double)min_lod, (double)max_lod);
        desc.lod_clamp = PERSP_TOGGLE_ON;
        desc.min_lod = min_lod;
        desc.max_lod = max_lod;
    }
    persp_image_write_desc wd = {PERSP_IMAGE_FORMAT_DEFAULT, quality};
    if ((rc = output_format(output, format, &wd.format)) != CLI_OK) return rc;
    if (cli_given(&cmd, &cli_opt_quality) && wd.format != PERSP_IMAGE_FORMAT_JPEG)
        cli_warning(NULL, "--quality applies to JPEG output only; the PNG is lossless");
    int to_stdout = output && !strcmp(output, "-");
    /* A path that cannot be written fails now, not after the render. */
    if ((rc = cli_check_output("render", "-o", output)) != CLI_OK) return rc;
    if (to_stdout && isatty(STDOUT_FILENO))
        return cli_error(CLI_USAGE,
                         "render: not writing a binary image to a terminal (redirect -o - "
                         "to a file or a pipe)");
    /* With the image on standard output, the summary must not mix with it. */
    FILE *summary = to_stdout ? stderr : stdout;

    const char *scene_name = scene_arg[0] ? scene_arg[0] : "corridor";
    if ((rc = cli_check_scene("render", scene_name)) != CLI_OK) return rc;
    int width = size.width, height = size.height;
    persp_status st;
    desc.method = method;
    desc.filter = filter.filter;
    desc.max_aniso = filter.max_aniso;
    desc.shading = shading.shading;

    persp_context *ctx = NULL;
    persp_context_desc cd = {.threads = threads, .max_memory = cli_max_memory(max_memory), .simd = simd};
    if ((st = persp_context_create(&cd, &ctx)) != PERSP_OK) {
        if (st == PERSP_ERR_UNSUPPORTED)
            return cli_error(CLI_FAIL, "render: this CPU cannot run --simd %s", persp_simd_name(simd));
        return cli_status(NULL, st, "render");
    }
    persp_context_set_warning_handler(ctx, cli_warning, NULL);
    persp_context_set_temp_file_handler(ctx, cli_temp_file, NULL);
    persp_scene *scene = NULL;
    persp_framebuffer fb = {0, 0, NULL, NULL};
    persp_image img = {0, 0, 0, NULL}, depth_img = {0, 0, 0, NULL};
    if (cli_is_builtin(scene_name)) st = persp_scene_builtin(ctx, scene_name, &scene);
    else st = persp_scene_load_ex(ctx, scene_name, &load, &scene);
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, scene_name);
        goto done;
    }
    if (texture && (rc = cli_replace_texture(ctx, scene, texture)) != CLI_OK) goto done;
    if (!width) persp_scene_default_size(scene, &width, &height);
    if (!width) width = 1024, height = 768;
    if ((st = persp_image_alloc(ctx, width, height, &img)) != PERSP_OK) {
        rc = cli_status(ctx, st, "render");
        goto done;
    }
    fb.width = width;
    fb.height = height;
    fb.color = img.pixels;
    /* The depth buffer in an image's storage (4 bytes per pixel, as a float):
     * 64-byte-aligned rows like the colour's, which helps several threads. */
    if ((st = persp_image_alloc(ctx, width, height, &depth_img)) != PERSP_OK) {
        rc = cli_status(ctx, st, "render: depth buffer");
        goto done;
    }
    fb.depth = (float *)(void *)depth_img.pixels;
    persp_render_stats stats;
    double t0 = cli_now();
    st = persp_render(ctx, scene, &desc, &fb, &stats);
    double t1 = cli_now();
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, "render");
        goto done;
    }
    char default_out[512];
    if (!output) {
        const char *base = strrchr(scene_name, '/');
        base = base ? base + 1 : scene_name;
        size_t len = strcspn(base, ".");
        snprintf(default_out, sizeof default_out, "out/%.*s.%s", (int)len, base,
                 wd.format == PERSP_IMAGE_FORMAT_JPEG ? "jpg" : "png");
        output = default_out;
        /* The default folder is persp's own; an -o path's folder is the user's. */
        if (mkdir("out", 0777) != 0 && errno != EEXIST) {
            rc = cli_error(CLI_FAIL, "render: cannot create the folder 'out': %s", strerror(errno));
            goto done;
        }
    }
    if (to_stdout)
        st = persp_image_write_stream(ctx, stdout, "standard output", &img, &wd);
    else
        st = persp_image_write(ctx, output, &img, &wd);
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, "render");
        goto done;
    }
    if (!quiet) {
        /* Name what was used, also where the scene itself chose it. */
        persp_scene_info info;
        persp_scene_get_info(scene, &info);
        char scene_filter[64];
        if (info.filter_count == 0) {
            snprintf(scene_filter, sizeof scene_filter, "none (untextured)");
        } else {
            int n = snprintf(scene_filter, sizeof scene_filter, "%s", persp_filter_name(info.filter));
            if ((info.filter == PERSP_FILTER_ANISO || info.filter == PERSP_FILTER_ANISO_WINDOW) && n > 0)
                snprintf(scene_filter + n, sizeof scene_filter - (size_t)n, ":%d",
                         info.max_aniso ? info.max_aniso : 16);
            if (info.filter_count > 1 && n > 0)
                snprintf(scene_filter + strlen(scene_filter), sizeof scene_filter - strlen(scene_filter),
                         " (and others per object)");
        }
        fprintf(summary,
                "rendered %s: %dx%d, method %s, filter %s, shading %s, depth %s, %d thread%s\n",
                scene_name, width, height, method ? method : info.method,
                filter.name ? filter.name : scene_filter,
                shading.name ? shading.name : persp_shading_name(info.shading),
                desc.depth_mode == PERSP_DEPTH_INVW ? "1/w" : "z", threads,
                threads == 1 ? "" : "s");
        fprintf(summary,
                "  %llu triangles in, %llu drawn (clipping may split one), %llu fragments, %llu pixels "
                "written\n",
                (unsigned long long)stats.triangles_in, (unsigned long long)stats.triangles_drawn,
                (unsigned long long)stats.fragments, (unsigned long long)stats.pixels_written);
        if (desc.pipeline == PERSP_PIPELINE_OBJECT)
            fprintf(summary,
                    "  object space: %llu pieces, %llu samples walked, %llu splats, %llu holes, "
                    "%llu rows and samples visited\n",
                    (unsigned long long)stats.objspace_pieces,
                    (unsigned long long)stats.objspace_samples,
                    (unsigned long long)stats.objspace_splats,
                    (unsigned long long)stats.objspace_holes,
                    (unsigned long long)stats.objspace_visited);
        if (desc.count_ops == PERSP_TOGGLE_ON) {
            /* Per pixel the method computed coordinates for (ops.pixels):
             * spans hidden whole and untextured objects run no method, so
             * dividing by all fragments understated the cost. */
            double px = stats.ops.pixels ? (double)stats.ops.pixels : 1.0;
            fprintf(summary,
                    "  method operations per pixel computed (%llu of %llu fragments): %.3f div, "
                    "%.3f mul, %.3f add, %.3f cmp\n",
                    (unsigned long long)stats.ops.pixels, (unsigned long long)stats.fragments,
                    (double)stats.ops.div / px, (double)stats.ops.mul / px, (double)stats.ops.add / px,
                    (double)stats.ops.cmp / px);
        }
        fprintf(summary, "  %.2f ms (%.1f Mpixels/s) -> %s\n", (t1 - t0) * 1e3,
                (double)width * height / ((t1 - t0) * 1e6), to_stdout ? "standard output" : output);
    }
done:
    persp_image_free(ctx, &depth_img);
    persp_image_free(ctx, &img);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return rc;
}
