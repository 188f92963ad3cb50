#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void render_usage(FILE *out)
{
    fprintf(out,
            "usage: persp render [SCENE] [options]\n\n"
            "SCENE is a built-in scene name or a JSON scene file (default: corridor).\n\n"
            "options:\n"
            "  -o, --output FILE     PNG to write (default: out/SCENE.png)\n"
            "  --method M            texture-coordinate method (default exact; see `persp methods`)\n"
            "  --filter F            nearest | bilinear | nearest-mip-nearest | bilinear-mip-nearest |\n"
            "                        nearest-mip-linear | trilinear | aniso:N | aniso-window:N | ewa\n"
            "  --wrap W              repeat | clamp-to-edge | mirrored-repeat | clamp-to-border\n"
            "  --shading S           none | flat | gouraud | gouraud-pc | phong | phong-pc |\n"
            "                        phong-pc:quad | phong-pc:pwquad | phong-pc:cubic |\n"
            "                        phong-slerp | phong-slerp-screen\n"
            "  --size WxH            image size (default: the scene's, corridor 1024x768)\n"
            "  --depth z|invw        depth buffer: window z, or 1/w (\"1/z buffering\")\n"
            "  --lod pixel|polygon   mip level per pixel (Jacobian) or per polygon\n"
            "  --lod-bias B          added to the level of detail\n"
            "  --min-lod L, --max-lod L  clamp the level of detail (GL defaults -1000, 1000)\n"
            "  --pipeline screen|object  inverse mapping per pixel, or object-space texturing\n"
            "  --texture FILE        replace the scene's texture with a PNG or JPEG\n"
            "  --threads N           worker threads (default 1)\n"
            "  --cull on|off         back-face culling (default: the scene's)\n"
            "  --count-ops           count the method's divisions, multiplications,\n"
            "                        additions and comparisons (instrumented render)\n"
            "  -q, --quiet           print nothing on success\n"
            "\nbuilt-in scenes:\n");
    for (size_t i = 0; i < persp_builtin_scene_count(); i++)
        fprintf(out, "  %-10s %s\n", persp_builtin_scene_name(i), persp_builtin_scene_summary(i));
}

static int is_builtin(const char *name)
{
    for (size_t i = 0; i < persp_builtin_scene_count(); i++)
        if (!strcmp(name, persp_builtin_scene_name(i))) return 1;
    return 0;
}

int cmd_render(int argc, char **argv)
{
    const char *scene_name = NULL, *output = NULL, *texture = NULL;
    const char *method = NULL, *filter_name = NULL, *wrap_name = NULL, *shading_name = NULL;
    int width = 0, height = 0, quiet = 0, threads = 1;
    persp_render_desc desc;
    memset(&desc, 0, sizeof desc);

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE()                                                                               \
    do {                                                                                           \
        if (!val) return cli_error(CLI_USAGE, "render: option %s needs a value", a);             \
        i++;                                                                                       \
    } while (0)
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            render_usage(stdout);
            return CLI_OK;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            NEED_VALUE();
            output = val;
        } else if (!strcmp(a, "--method")) {
            NEED_VALUE();
            method = val;
        } else if (!strcmp(a, "--filter")) {
            NEED_VALUE();
            filter_name = val;
        } else if (!strcmp(a, "--wrap")) {
            NEED_VALUE();
            wrap_name = val;
        } else if (!strcmp(a, "--shading")) {
            NEED_VALUE();
            shading_name = val;
        } else if (!strcmp(a, "--size")) {
            NEED_VALUE();
            if (!cli_parse_size(val, &width, &height))
                return cli_error(CLI_USAGE,
                                 "render: bad --size '%s' (expected WxH, each 1..%d, at most %u pixels)",
                                 val, PERSP_IMAGE_MAX_SIDE, PERSP_IMAGE_MAX_PIXELS);
        } else if (!strcmp(a, "--depth")) {
            NEED_VALUE();
            if (!strcmp(val, "z")) desc.depth_mode = PERSP_DEPTH_Z;
            else if (!strcmp(val, "invw")) desc.depth_mode = PERSP_DEPTH_INVW;
            else return cli_error(CLI_USAGE, "render: bad --depth '%s' (expected z or invw)", val);
        } else if (!strcmp(a, "--lod")) {
            NEED_VALUE();
            if (!strcmp(val, "pixel")) desc.lod_mode = PERSP_LOD_PIXEL;
            else if (!strcmp(val, "polygon")) desc.lod_mode = PERSP_LOD_POLYGON;
            else return cli_error(CLI_USAGE, "render: bad --lod '%s' (expected pixel or polygon)", val);
        } else if (!strcmp(a, "--lod-bias")) {
            NEED_VALUE();
            char *end;
            double b = strtod(val, &end);
            if (*end || !(b >= -16.0 && b <= 16.0))
                return cli_error(CLI_USAGE, "render: bad --lod-bias '%s' (expected -16..16)", val);
            desc.lod_bias = (float)b;
        } else if (!strcmp(a, "--min-lod") || !strcmp(a, "--max-lod")) {
            NEED_VALUE();
            char *end;
            double l = strtod(val, &end);
            if (*end || end == val || !(l >= -1000.0 && l <= 1000.0))
                return cli_error(CLI_USAGE, "render: bad %s '%s' (expected -1000..1000)", a, val);
            if (desc.lod_clamp != PERSP_TOGGLE_ON) desc.min_lod = -1000.0f, desc.max_lod = 1000.0f;
            desc.lod_clamp = PERSP_TOGGLE_ON;
            if (a[2] == 'm' && a[3] == 'i') desc.min_lod = (float)l;
            else desc.max_lod = (float)l;
        } else if (!strcmp(a, "--pipeline")) {
            NEED_VALUE();
            if (!strcmp(val, "screen")) desc.pipeline = PERSP_PIPELINE_SCREEN;
            else if (!strcmp(val, "object")) desc.pipeline = PERSP_PIPELINE_OBJECT;
            else return cli_error(CLI_USAGE, "render: bad --pipeline '%s' (expected screen or object)", val);
        } else if (!strcmp(a, "--texture")) {
            NEED_VALUE();
            texture = val;
        } else if (!strcmp(a, "--threads")) {
            NEED_VALUE();
            long n;
            if (!cli_parse_int(val, 1, 256, &n))
                return cli_error(CLI_USAGE, "render: bad --threads '%s' (expected 1..256)", val);
            threads = (int)n;
        } else if (!strcmp(a, "--cull")) {
            NEED_VALUE();
            if (!strcmp(val, "on")) desc.cull_backfaces = PERSP_TOGGLE_ON;
            else if (!strcmp(val, "off")) desc.cull_backfaces = PERSP_TOGGLE_OFF;
            else return cli_error(CLI_USAGE, "render: bad --cull '%s' (expected on or off)", val);
        } else if (!strcmp(a, "--count-ops")) {
            desc.count_ops = PERSP_TOGGLE_ON;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return cli_error(CLI_USAGE, "render: unknown option '%s' (see persp render --help)", a);
        } else if (!scene_name) {
            scene_name = a;
        } else {
            return cli_error(CLI_USAGE, "render: more than one scene given ('%s', '%s')", scene_name, a);
        }
#undef NEED_VALUE
    }
    if (!scene_name) scene_name = "corridor";
    if (!is_builtin(scene_name) && access(scene_name, F_OK) != 0) {
        char names[256] = "";
        for (size_t i = 0; i < persp_builtin_scene_count(); i++) {
            size_t used = strlen(names);
            snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "",
                     persp_builtin_scene_name(i));
        }
        return cli_error(CLI_FAIL, "render: '%s' is neither a built-in scene (%s) nor a file: %s",
                         scene_name, names, strerror(errno));
    }
    if (desc.lod_clamp == PERSP_TOGGLE_ON && desc.min_lod > desc.max_lod)
        return cli_error(CLI_USAGE, "render: --min-lod %g is above --max-lod %g", (double)desc.min_lod,
                         (double)desc.max_lod);

    if (method) {
        int bad = cli_check_method("render", method);
        if (bad) return bad;
    }
    persp_status st;
    desc.method = method;
    if (filter_name) {
        if (persp_filter_parse(filter_name, &desc.filter, &desc.max_aniso) != PERSP_OK)
            return cli_error(CLI_USAGE, "render: unknown filter '%s' (see persp render --help)", filter_name);
    }
    if (wrap_name) {
        if (persp_wrap_parse(wrap_name, &desc.wrap) != PERSP_OK)
            return cli_error(CLI_USAGE, "render: unknown wrap mode '%s'", wrap_name);
    }
    if (shading_name) {
        if (persp_shading_parse(shading_name, &desc.shading) != PERSP_OK)
            return cli_error(CLI_USAGE, "render: unknown shading '%s' (see persp render --help)", shading_name);
    }

    persp_context *ctx = NULL;
    persp_context_desc cd = {NULL, threads};
    if ((st = persp_context_create(&cd, &ctx)) != PERSP_OK) return cli_status(NULL, st, "render");
    persp_scene *scene = NULL;
    int rc = CLI_OK;
    persp_framebuffer fb = {0, 0, NULL, NULL};
    persp_image img = {0, 0, 0, NULL}, depth_img = {0, 0, 0, NULL};
    if (is_builtin(scene_name)) st = persp_scene_builtin(ctx, scene_name, &scene);
    else st = persp_scene_load(ctx, scene_name, &scene);
    if (st != PERSP_OK) {
        rc = cli_status(ctx, st, scene_name);
        goto done;
    }
    if (texture) {
        persp_image tex;
        if ((st = persp_image_load(ctx, texture, &tex)) != PERSP_OK) {
            rc = cli_status(ctx, st, texture);
            goto done;
        }
        st = persp_scene_set_texture(scene, &tex);
        persp_image_free(ctx, &tex);
        if (st != PERSP_OK) {
            rc = cli_status(ctx, st, texture);
            goto done;
        }
    }
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
        snprintf(default_out, sizeof default_out, "out/%.*s.png", (int)len, base);
        output = default_out;
        /* The default folder is persp's own; an -o path's folder is the user's. */
        if (mkdir("out", 0777) != 0 && errno != EEXIST) {
            rc = cli_error(CLI_FAIL, "render: cannot create the folder 'out': %s", strerror(errno));
            goto done;
        }
    }
    if ((st = persp_image_write_png(ctx, output, &img)) != PERSP_OK) {
        rc = cli_status(ctx, st, output);
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
        printf("rendered %s: %dx%d, method %s, filter %s, shading %s, depth %s, %d thread%s\n",
               scene_name, width, height, method ? method : info.method, filter_name ? filter_name : scene_filter,
               shading_name ? shading_name : persp_shading_name(info.shading),
               desc.depth_mode == PERSP_DEPTH_INVW ? "1/w" : "z", threads, threads == 1 ? "" : "s");
        printf("  %llu triangles in, %llu after clipping, %llu fragments, %llu pixels written\n",
               (unsigned long long)stats.triangles_in, (unsigned long long)stats.triangles_drawn,
               (unsigned long long)stats.fragments, (unsigned long long)stats.pixels_written);
        if (desc.pipeline == PERSP_PIPELINE_OBJECT)
            printf("  object space: %llu pieces, %llu samples walked, %llu splats, %llu holes\n",
                   (unsigned long long)stats.objspace_pieces, (unsigned long long)stats.objspace_samples,
                   (unsigned long long)stats.objspace_splats, (unsigned long long)stats.objspace_holes);
        if (desc.count_ops == PERSP_TOGGLE_ON) {
            /* Per fragment the method was run for (covered and not hidden at
             * the time it was drawn). */
            double fr = stats.fragments ? (double)stats.fragments : 1.0;
            printf("  method operations per fragment: %.3f div, %.3f mul, %.3f add, %.3f cmp\n",
                   (double)stats.ops.div / fr, (double)stats.ops.mul / fr, (double)stats.ops.add / fr,
                   (double)stats.ops.cmp / fr);
        }
        printf("  %.2f ms (%.1f Mpixels/s) -> %s\n", (t1 - t0) * 1e3,
               (double)width * height / ((t1 - t0) * 1e6), output);
    }
done:
    persp_image_free(ctx, &depth_img);
    persp_image_free(ctx, &img);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return rc;
}
