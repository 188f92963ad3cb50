/*
 * render_scene — render one of persp's built-in scenes, or a scene or model
 * file, into buffers this program owns, then save the colour buffer as a PNG.
 *
 *   render_scene [SCENE [OUTPUT.png [METHOD]]]
 *
 * SCENE is "corridor" (default), "floor" or "cube", or a path (it holds a
 * '/'): a JSON scene or a model file, which persp reads in its helper
 * process persp-import (installed with the library); OUTPUT defaults to
 * SCENE.png; METHOD is a texture-coordinate method ("exact" unless the scene
 * names one; `persp methods` lists them).
 *
 *   cc render_scene.c $(pkg-config --cflags --libs persp) -o render_scene
 */
#include <persp.h>

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Prints a failed call with the context's detail, which says which value or
 * which file position was wrong; returns nonzero on failure. */
static int failed(const persp_context *ctx, persp_status status, const char *what)
{
    if (status == PERSP_OK) return 0;
    const char *detail = ctx ? persp_context_error(ctx) : "";
    fprintf(stderr, "render_scene: %s: %s%s%s\n", what, persp_status_string(status),
            *detail ? ": " : "", detail);
    return 1;
}

int main(int argc, char **argv)
{
    const char *scene_name = argc > 1 ? argv[1] : "corridor";
    char default_output[256];
    const char *slash = strrchr(scene_name, '/');
    snprintf(default_output, sizeof default_output, "%s.png", slash ? slash + 1 : scene_name);
    const char *output = argc > 2 ? argv[2] : default_output;
    const char *method = argc > 3 ? argv[3] : NULL;

    int status = EXIT_FAILURE;
    persp_context *ctx = NULL;
    persp_scene *scene = NULL;
    uint8_t *color = NULL;
    float *depth = NULL;

    /* A NULL desc: malloc/free, one thread. */
    if (failed(NULL, persp_context_create(NULL, &ctx), "persp_context_create")) goto done;
    if (strchr(scene_name, '/')) {
        if (failed(ctx, persp_scene_load(ctx, scene_name, &scene), scene_name)) goto done;
    } else if (failed(ctx, persp_scene_builtin(ctx, scene_name, &scene), scene_name)) {
        goto done;
    }

    int width = 0, height = 0;
    persp_scene_default_size(scene, &width, &height);
    if (width <= 0 || height <= 0) {
        width = 640;
        height = 480;
    }

    /* The framebuffer is plain memory that stays ours: RGBA8 colour and one
     * float of depth per pixel, row 0 at the bottom as in OpenGL. Any
     * alignment works; 64 bytes lets several render threads write
     * neighbouring tiles without sharing cache lines. */
    size_t pixels = (size_t)width * (size_t)height;
    color = aligned_alloc(64, (pixels * 4 + 63) / 64 * 64);
    depth = aligned_alloc(64, (pixels * sizeof *depth + 63) / 64 * 64);
    if (!color || !depth) {
        fprintf(stderr, "render_scene: out of memory for a %dx%d framebuffer\n", width, height);
        goto done;
    }
    persp_framebuffer fb = {width, height, color, depth};

    /* Zero-initialised means "as the scene asks"; each field set overrides
     * the scene for this call only. persp_render clears fb first. */
    persp_render_desc desc = {0};
    desc.method = method;
    persp_render_stats stats;
    if (failed(ctx, persp_render(ctx, scene, &desc, &fb, &stats), "persp_render")) goto done;

    /* Filled in by hand, a persp_image describes our pixels: persp only
     * reads them (and writes the top row first, as PNG wants). */
    persp_image image = {width, height, (size_t)width * 4, color};
    if (failed(ctx, persp_image_write_png(ctx, output, &image), output)) goto done;

    /* Clipping at the near plane can split a triangle: "drawn" may exceed "in". */
    printf("render_scene: %s at %dx%d, method %s: %" PRIu64 " triangles in, %" PRIu64
           " drawn, %" PRIu64 " pixels written, saved %s\n",
           scene_name, width, height, method ? method : "(the scene's)", stats.triangles_in,
           stats.triangles_drawn, stats.pixels_written, output);
    status = EXIT_SUCCESS;

done:
    free(depth);
    free(color);
    /* Objects made with a context go before it. */
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return status;
}
