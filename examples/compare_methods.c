/*
 * compare_methods — how far apart two texture-coordinate methods are, seen
 * two ways:
 *   1. in the picture: render a scene with each and compare the pixels
 *      (core API only, libpersp);
 *   2. in texture space: persp_accuracy_run measures each method's u, v
 *      against the exact mapping in double precision, in texels
 *      (analysis API, libpersp_analysis).
 *
 *   compare_methods [METHOD_A [METHOD_B [SCENE]]]
 *
 * Defaults: exact, quadratic, corridor. The corridor's walls recede along
 * each scanline, which is where approximations part from the exact mapping;
 * on "floor", seen level, depth is constant along a scanline and every
 * span-based method is exact.
 *
 *   cc compare_methods.c $(pkg-config --cflags --libs persp-analysis) -o compare_methods
 */
#include <persp.h>
#include <persp_analysis.h>

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>

static int failed(const persp_context *ctx, persp_status status, const char *what)
{
    if (status == PERSP_OK) return 0;
    const char *detail = ctx ? persp_context_error(ctx) : "";
    fprintf(stderr, "compare_methods: %s: %s%s%s\n", what, persp_status_string(status),
            *detail ? ": " : "", detail);
    return 1;
}

/* Renders scene with one method into fb (whose buffers the caller owns). */
static int render(persp_context *ctx, const persp_scene *scene, const char *method,
                  persp_framebuffer *fb)
{
    persp_render_desc desc = {0};
    desc.method = method;
    return failed(ctx, persp_render(ctx, scene, &desc, fb, NULL), method);
}

int main(int argc, char **argv)
{
    const char *methods[2] = {argc > 1 ? argv[1] : "exact", argc > 2 ? argv[2] : "quadratic"};
    const char *scene_name = argc > 3 ? argv[3] : "corridor";

    int status = EXIT_FAILURE;
    persp_context *ctx = NULL;
    persp_scene *scene = NULL;
    persp_accuracy_result *accuracy = NULL;
    uint8_t *color[2] = {NULL, NULL};
    float *depth = NULL;

    if (failed(NULL, persp_context_create(NULL, &ctx), "persp_context_create")) goto done;
    if (failed(ctx, persp_scene_builtin(ctx, scene_name, &scene), scene_name)) goto done;

    int width = 0, height = 0;
    persp_scene_default_size(scene, &width, &height);
    if (width <= 0 || height <= 0) {
        width = 640;
        height = 480;
    }
    size_t pixels = (size_t)width * (size_t)height;

    /* ---- 1. the pictures. One depth buffer serves both renders, since
     * persp_render clears it. */
    color[0] = malloc(pixels * 4);
    color[1] = malloc(pixels * 4);
    depth = malloc(pixels * sizeof *depth);
    if (!color[0] || !color[1] || !depth) {
        fprintf(stderr, "compare_methods: out of memory\n");
        goto done;
    }
    for (int m = 0; m < 2; m++) {
        persp_framebuffer fb = {width, height, color[m], depth};
        if (render(ctx, scene, methods[m], &fb)) goto done;
    }

    /* Per pixel, the largest difference over R, G and B, in 8-bit levels. */
    int max_diff = 0;
    uint64_t sum_diff = 0, differing = 0;
    for (size_t i = 0; i < pixels; i++) {
        int d = 0;
        for (int c = 0; c < 3; c++) {
            int e = abs(color[0][i * 4 + (size_t)c] - color[1][i * 4 + (size_t)c]);
            if (e > d) d = e;
        }
        if (d > max_diff) max_diff = d;
        sum_diff += (uint64_t)d;
        differing += d > 0;
    }
    printf("compare_methods: %s at %dx%d, %s vs %s\n", scene_name, width, height, methods[0],
           methods[1]);
    printf("  colour difference: max %d, mean %.4f levels; %" PRIu64 " of %zu pixels differ\n",
           max_diff, (double)sum_diff / (double)pixels, differing, pixels);

    /* ---- 2. the texture coordinates, against the exact mapping. A
     * built-in scene name is a case of its own, rendered at width × height. */
    const char *cases[1] = {scene_name};
    persp_accuracy_desc desc = {0};
    desc.methods = methods;
    desc.method_count = 2;
    desc.cases = cases;
    desc.case_count = 1;
    desc.width = width;
    desc.height = height;
    if (failed(ctx, persp_accuracy_run(ctx, &desc, &accuracy), "persp_accuracy_run")) goto done;

    printf("  texel error against the exact mapping (|u|, |v| in texels):\n");
    for (size_t i = 0; i < persp_accuracy_row_count(accuracy); i++) {
        const persp_accuracy_row *row = persp_accuracy_row_at(accuracy, i);
        printf("    %-12s max %.3g, %.3g  mean %.3g, %.3g  nearest texel differs at %.3f%% of %" PRIu64
               " pixels\n",
               row->method, row->max_u, row->max_v, row->mean_u, row->mean_v, 100.0 * row->texel_miss,
               row->pixels);
    }
    status = EXIT_SUCCESS;

done:
    persp_accuracy_destroy(accuracy);
    free(depth);
    free(color[1]);
    free(color[0]);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return status;
}
