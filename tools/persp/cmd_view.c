#include "options.h"
#include "view_window.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void view_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp view [SCENE] [options]\n\n"
                 "An interactive window comparing two render configurations side by side\n"
                 "(SCENE: a built-in scene, a JSON scene file or a model file, default\n"
                 "corridor). With --play it renders a recorded camera path to PNG frames\n"
                 "instead, without a window. Controls: docs/VIEWER.md.\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
#ifndef PERSP_HAVE_VIEWER
    fprintf(out, "\nThis build has no window (SDL2 and Dear ImGui were not found);\n"
                 "--play works without them.\n");
#endif
}

static const char *const layout_names[] = {"single", "split", "diff", "texel", NULL};
static const int layout_values[] = {VIEW_LAYOUT_SINGLE, VIEW_LAYOUT_SPLIT, VIEW_LAYOUT_DIFF,
                                    VIEW_LAYOUT_TEXEL};

static const cli_spec opt_compare = {.name = "compare",
                                     .kind = CLI_KIND_CUSTOM,
                                     .metavar = "M",
                                     .parse = NULL, /* set from cli_opt_method below */
                                     .help = "method of the right side (default exact)"};
static const cli_spec opt_layout = {.name = "layout",
                                    .kind = CLI_KIND_ENUM,
                                    .metavar = "single|split|diff|texel",
                                    .names = layout_names,
                                    .values = layout_values,
                                    .help = "left only, left | right at the divider, the colour\n"
                                            "difference as a heat map, or the texture-coordinate\n"
                                            "difference in texels of a 1024x1024 texture\n"
                                            "(default split)"};
static const cli_spec opt_divider = {.name = "divider",
                                     .kind = CLI_KIND_REAL,
                                     .metavar = "F",
                                     .lo = 0,
                                     .hi = 1,
                                     .help = "where the split is, 0..1 of the width (default 0.5)"};
static const cli_spec opt_heat_max = {
    .name = "heat-max",
    .kind = CLI_KIND_INT,
    .metavar = "N",
    .lo = 1,
    .hi = 255,
    .help = "difference in levels shown hottest in the heat map (default 16)"};
static const cli_spec opt_play = {.name = "play",
                                  .kind = CLI_KIND_STRING,
                                  .metavar = "FILE",
                                  .help = "render this camera path (JSON) to -o DIR, no window"};
static const cli_spec opt_frames = {
    .name = "frames",
    .kind = CLI_KIND_INT,
    .metavar = "N",
    .lo = 1,
    .hi = 1000000,
    .help = "with --play: frames sampled evenly over the path (default: one per\n"
            "key); in the window: close after N frames"};
static const cli_spec opt_record = {
    .name = "record",
    .kind = CLI_KIND_STRING,
    .metavar = "FILE",
    .help = "where the window saves a recorded flight (default camera-path.json)"};

static const cli_spec opt_window_shot = {
    .name = "window-shot",
    .kind = CLI_KIND_STRING,
    .metavar = "FILE",
    .help = "with --frames: save the window's last frame, panels included, as PNG"};

static const cli_spec opt_script = {
    .name = "script",
    .kind = CLI_KIND_STRING,
    .metavar = "FILE",
    .help = "drive the window with the input actions in FILE (keys, mouse, method\n"
            "changes, screenshots; format in docs/VIEWER.md); closes at its end"};

static const cli_spec opt_mip_levels = {
    .name = "mip-levels",
    .kind = CLI_KIND_FLAG,
    .help = "left side: each mip level as a flat colour (which levels the filter reads)"};

/* A built-in scene or a scene file, with --texture applied. */
static int load_scene(persp_context *ctx, const char *name, const char *texture,
                      const persp_scene_load_desc *load, persp_scene **out)
{
    persp_status st;
    if (cli_is_builtin(name))
        st = persp_scene_builtin(ctx, name, out);
    else
        st = persp_scene_load_ex(ctx, name, load, out);
    if (st != PERSP_OK) return cli_status(ctx, st, name);
    return texture ? cli_replace_texture(ctx, *out, texture) : CLI_OK;
}

static long cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 256 ? 256 : n;
}

static int make_dir(const char *dir)
{
    if (view_make_dirs(dir) != 0)
        return cli_error(CLI_FAIL, "view: cannot create the folder '%s': %s", dir, strerror(errno));
    return CLI_OK;
}

static int play_path(persp_context *ctx, const view_scenes *scenes, const view_path *path,
                     const view_settings *left, const view_settings *right, view_layout layout,
                     double divider, int heat_max, int width, int height, long frames,
                     const char *dir, int quiet)
{
    int rc = make_dir(dir);
    if (rc != CLI_OK) return rc;
    view_frame f;
    memset(&f, 0, sizeof f);
    persp_status st = view_frame_resize(&f, width, height);
    if (st != PERSP_OK) return cli_status(ctx, st, "view");
    double t0 = path->keys[0].t, t1 = path->keys[path->count - 1].t;
    for (long i = 0; i < frames && rc == CLI_OK; i++) {
        double t = frames > 1 ? t0 + (t1 - t0) * (double)i / (double)(frames - 1) : t0;
        view_camera cam;
        view_path_sample(path, t, &cam);
        st = view_frame_render(ctx, scenes, &cam, left, right, layout, divider, heat_max, 1, &f);
        if (st != PERSP_OK) {
            rc = cli_status(ctx, st, "view");
            break;
        }
        char name[4096];
        /* "frames/" names the folder: no doubled slash in the names. */
        const size_t dl = strlen(dir);
        const int sep = !(dl > 0 && dir[dl - 1] == '/');
        snprintf(name, sizeof name, "%s%sframe_%04ld.png", dir, sep ? "/" : "", i);
        persp_image img = {f.width, f.height, (size_t)f.width * 4, f.out};
        if ((st = persp_image_write_png(ctx, name, &img)) != PERSP_OK) {
            rc = cli_status(ctx, st, "view");
            break;
        }
        if (!quiet && layout == VIEW_LAYOUT_TEXEL)
            printf("%s  t=%.3f  left %.1f ms, right %.1f ms  texel error max %.2f, mean %.3f "
                   "where they differ, %.2f%% of pixels differ\n",
                   name, t, f.ms[0], f.ms[1], f.err.texel_max, f.err.texel_mean,
                   f.err.share_diff * 100.0);
        else if (!quiet)
            printf("%s  t=%.3f  left %.1f ms, right %.1f ms  error max %d, mean %.3f, "
                   "%.2f%% of pixels differ, PSNR %.2f dB\n",
                   name, t, f.ms[0], f.ms[1], f.err.max, f.err.mean, f.err.share_diff * 100.0,
                   f.err.psnr);
    }
    view_frame_free(&f);
    return rc;
}

#ifndef PERSP_HAVE_VIEWER
int view_window_run(const view_window_args *args)
{
    (void)args;
    return cli_error(CLI_FAIL,
                     "view: this persp was built without the window (it needs SDL2 and Dear "
                     "ImGui: run scripts/deps.sh, or apt-get install libsdl2-dev libimgui-dev, "
                     "then rebuild); --play renders camera paths without it");
}
#endif

/* The options of `persp view`, as parsed and checked. */
typedef struct view_job {
    const char *scene_name, *texture, *method, *compare, *output, *play, *record, *window_shot, *script;
    view_settings left, right;
    view_layout layout;
    double divider;
    int heat_max, frames, quiet, threads;
    cli_size size;
    persp_scene_load_desc load;
    view_path path;
} view_job;

/* The method of the left side without --method: the scene's where it names
 * one, else affine, so that the default split shows what perspective
 * correction changes (exact against exact would show nothing). */
static void default_left_method(const persp_scene *scene, view_settings *left)
{
    persp_scene_info info;
    persp_scene_get_info(scene, &info);
    snprintf(left->method, sizeof left->method, "%s", strcmp(info.method, "exact") ? info.method : "affine");
}

/* The scene and the copies the layouts need: its mip levels as colours
 * and its texture coordinates as colours. The copies load the same file:
 * its warnings were shown with the first. */
static int view_load(persp_context *ctx, const view_job *job, persp_scene **scene, persp_scene **tinted,
                     persp_scene **coords, persp_image *coord_img)
{
    int rc = load_scene(ctx, job->scene_name, job->texture, &job->load, scene);
    if (rc != CLI_OK) return rc;
    persp_context_set_warning_handler(ctx, NULL, NULL);
    /* The window offers mip levels on either side at any time. */
    if (job->left.mip_levels || !job->play) {
        rc = load_scene(ctx, job->scene_name, job->texture, &job->load, tinted);
        if (rc == CLI_OK) persp_scene_tint_mip_levels(*tinted);
    }
    if (rc == CLI_OK && (job->layout == VIEW_LAYOUT_TEXEL || !job->play)) {
        rc = load_scene(ctx, job->scene_name, NULL, &job->load, coords);
        persp_status st = PERSP_OK;
        if (rc == CLI_OK && ((st = view_coord_image(ctx, coord_img)) != PERSP_OK ||
                             (st = persp_scene_set_texture(*coords, coord_img)) != PERSP_OK))
            rc = cli_status(ctx, st, "view: coordinate texture");
    }
    persp_context_set_warning_handler(ctx, cli_warning, NULL);
    return rc;
}

static int view_play(persp_context *ctx, const view_job *job, const view_scenes *scenes, int width, int height)
{
    long n = job->frames ? job->frames : (long)job->path.count;
    double t0 = cli_now();
    int rc = play_path(ctx, scenes, &job->path, &job->left, &job->right, job->layout, job->divider, job->heat_max,
                       width, height, n, job->output, job->quiet);
    const char *out = job->output;
    if (rc == CLI_OK && !job->quiet)
        printf("played %s (%s | %s): %ld frame%s of %dx%d in %.2f s -> %s%s\n", job->play,
               job->left.method[0] ? job->left.method : "scene's", job->right.method, n, n == 1 ? "" : "s", width,
               height, cli_now() - t0, out, out[0] && out[strlen(out) - 1] == '/' ? "" : "/");
    return rc;
}

static int view_window(persp_context *ctx, const view_job *job, persp_scene *scene, persp_scene *tinted,
                       persp_scene *coords, int width, int height)
{
    view_window_args a = {
        ctx,   scene,  tinted,       coords,       job->scene_name,
        job->left, job->right, job->layout, job->divider, job->heat_max,
        width, height, job->threads, job->frames,  job->record ? job->record : "camera-path.json",
        NULL,  job->output, job->window_shot, job->script, job->quiet,
        cli_temp_file, cli_install_signal_handlers};
    /* SDL turns SIGINT/SIGTERM into its quit event, so that the window
     * closes cleanly, but only where the signal has its default action
     * (SDL_INIT_EVENTS, SDL_HINT_NO_SIGNAL_HANDLERS): hand them back.
     * Where SDL then takes neither, the window puts ours back. */
    cli_restore_signal_handlers();
    return view_window_run(&a);
}

static int view_body(persp_context *ctx, cli_output *out, void *user)
{
    (void)out;
    view_job *job = user;
    persp_scene *scene = NULL, *tinted = NULL, *coords = NULL;
    persp_image coord_img = {0, 0, 0, NULL};
    int rc = view_load(ctx, job, &scene, &tinted, &coords, &coord_img);
    if (rc == CLI_OK) {
        /* The single layout compares nothing: the scene's own method. */
        if (!job->method && job->layout != VIEW_LAYOUT_SINGLE) default_left_method(scene, &job->left);
        view_scenes scenes = {scene, tinted, coords};
        int width = job->size.width, height = job->size.height;
        if (!width) persp_scene_default_size(scene, &width, &height);
        if (!width) width = 1024, height = 768;
        rc = job->play ? view_play(ctx, job, &scenes, width, height)
                       : view_window(ctx, job, scene, tinted, coords, width, height);
    }
    persp_image_free(ctx, &coord_img);
    persp_scene_destroy(coords);
    persp_scene_destroy(tinted);
    persp_scene_destroy(scene);
    return rc;
}

/* Parses argv into job; CLI_OK, CLI_HELP (the help printed) or CLI_USAGE. */
static int view_parse(int argc, char **argv, view_job *job, size_t *max_memory)
{
    cli_filter filter = {NULL, PERSP_FILTER_DEFAULT, 0};
    cli_shading shading = {NULL, PERSP_SHADING_DEFAULT};
    persp_toggle count_ops = PERSP_TOGGLE_DEFAULT;
    int mip_levels = 0;
    view_settings *left = &job->left;
    cli_spec compare_spec = opt_compare;
    compare_spec.parse = cli_opt_method.parse;
    compare_spec.accepts = cli_opt_method.accepts;
    cli_option opts[] = {
        CLI_OPT_HELP(cli_opt_method, &job->method,
                     "method of the left side (default: the scene's, or affine\n"
                     "where the scene names none or exact and the layout\n"
                     "compares)"),
        CLI_OPT(compare_spec, &job->compare),
        CLI_OPT(cli_opt_filter, &filter),
        CLI_OPT(cli_opt_wrap, &left->wrap),
        CLI_OPT(cli_opt_shading, &shading),
        CLI_OPT(cli_opt_depth, &left->depth),
        CLI_OPT(cli_opt_lod, &left->lod),
        CLI_OPT(cli_opt_lod_bias, &left->lod_bias),
        CLI_OPT(cli_opt_pipeline, &left->pipeline),
        CLI_OPT(cli_opt_texture, &job->texture),
        CLI_OPT(cli_opt_any_folder, &job->load.any_folder),
        CLI_OPT(cli_opt_up, &job->load.model_up),
        CLI_OPT(cli_opt_formats, &job->load.formats),
        CLI_OPT(cli_opt_import, &job->load.import),
        CLI_OPT(cli_opt_import_timeout, &job->load.import_time_limit_ms),
        CLI_OPT(cli_opt_crease, &job->load.crease_deg),
        CLI_OPT(cli_opt_count_ops, &count_ops),
        CLI_OPT(opt_mip_levels, &mip_levels),
        CLI_OPT(opt_layout, &job->layout),
        CLI_OPT(opt_divider, &job->divider),
        CLI_OPT(opt_heat_max, &job->heat_max),
        CLI_OPT_HELP(cli_opt_size, &job->size, "window or frame size (default: the scene's, else 1024x768)"),
        CLI_OPT_HELP(cli_opt_threads, &job->threads, "worker threads, 1..256 (default: all CPUs)"),
        CLI_OPT(cli_opt_max_memory, max_memory),
        CLI_OPT(opt_play, &job->play),
        CLI_OPT(opt_frames, &job->frames),
        CLI_OPT_HELP(cli_opt_output, &job->output, "folder for --play frames and screenshots (default out/frames)"),
        CLI_OPT(opt_record, &job->record),
        CLI_OPT(opt_window_shot, &job->window_shot),
        CLI_OPT(opt_script, &job->script),
        CLI_OPT_HELP(cli_opt_quiet, &job->quiet, "print nothing on success"),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    const char *scene_arg[1] = {NULL};
    cli_command cmd = {
        "view", "persp view --help", NULL, opts, sizeof opts / sizeof opts[0], scene_arg, 1, 0, "scene"};
    int rc = cli_parse_or_usage(&cmd, argc, argv, view_usage);
    job->scene_name = scene_arg[0] ? scene_arg[0] : "corridor";
    if (job->method) snprintf(left->method, sizeof left->method, "%s", job->method);
    left->filter = filter.filter;
    left->max_aniso = filter.max_aniso;
    left->shading = shading.shading;
    left->count_ops = count_ops == PERSP_TOGGLE_ON;
    job->right = *left;
    left->mip_levels = mip_levels;
    snprintf(job->right.method, sizeof job->right.method, "%s", job->compare ? job->compare : "exact");
    job->right.count_ops = 0;
    return rc;
}

int cmd_view(int argc, char **argv)
{
    view_job job;
    memset(&job, 0, sizeof job);
    job.threads = (int)cpu_count();
    job.heat_max = 16;
    job.divider = 0.5;
    job.layout = VIEW_LAYOUT_SPLIT;
    job.load.any_folder = PERSP_TOGGLE_DEFAULT;
    size_t max_memory = 0;
    int rc = view_parse(argc, argv, &job, &max_memory);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    if (!job.output) job.output = "out/frames";
    if (strlen(job.left.method) != strlen(job.method ? job.method : "") ||
        strlen(job.right.method) != strlen(job.compare ? job.compare : "exact"))
        return cli_error(CLI_USAGE, "view: method spec too long");
    if ((rc = cli_check_scene("view", job.scene_name)) != CLI_OK) return rc;
    if (job.play) {
        char err[512];
        if (!view_path_load(job.play, &job.path, err, sizeof err)) return cli_error(CLI_FAIL, "view: %s", err);
    }
    cli_run_desc run = {.command = "view", .threads = job.threads, .max_memory = max_memory};
    rc = cli_run(&run, view_body, &job);
    view_path_free(&job.path);
    return rc;
}
