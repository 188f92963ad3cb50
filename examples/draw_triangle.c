/*
 * draw_triangle — one textured triangle drawn with persp_draw, the immediate
 * API for a renderer that has its own scene graph: the program supplies the
 * vertices, the matrix, the texture and the colour and depth buffers.
 *
 *   draw_triangle [METHOD [OUTPUT.png]]
 *
 * METHOD is the texture-coordinate method (default "exact"; try "affine" to
 * see the texture swim without perspective correction, or "subdiv:16");
 * OUTPUT defaults to triangle.png.
 *
 *   cc draw_triangle.c $(pkg-config --cflags --libs persp) -o draw_triangle
 */
#include <persp.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { WIDTH = 640, HEIGHT = 480, TEX = 64, CHECK = 8 };

static int failed(const persp_context *ctx, persp_status status, const char *what)
{
    if (status == PERSP_OK) return 0;
    const char *detail = ctx ? persp_context_error(ctx) : "";
    fprintf(stderr, "draw_triangle: %s: %s%s%s\n", what, persp_status_string(status),
            *detail ? ": " : "", detail);
    return 1;
}

int main(int argc, char **argv)
{
    const char *method = argc > 1 ? argv[1] : "exact";
    const char *output = argc > 2 ? argv[2] : "triangle.png";

    /* Checking the spec first gives a clear message for a typo, and the
     * list of what exists. */
    persp_status st = persp_method_check(method);
    if (st != PERSP_OK) {
        fprintf(stderr, "draw_triangle: method '%s': %s; known methods:\n", method,
                persp_status_string(st));
        for (size_t i = 0; i < persp_method_count(); i++) {
            persp_method_info info;
            if (persp_method_get(i, &info) == PERSP_OK)
                fprintf(stderr, "  %s%s%s\n", info.name, *info.params ? ":" : "", info.params);
        }
        return EXIT_FAILURE;
    }

    int status = EXIT_FAILURE;
    persp_context *ctx = NULL;
    persp_texture *texture = NULL;
    static uint8_t texels[TEX * TEX * 4];
    static uint8_t color[WIDTH * HEIGHT * 4];
    static float depth[WIDTH * HEIGHT];

    if (failed(NULL, persp_context_create(NULL, &ctx), "persp_context_create")) goto done;

    /* A black-and-white checkerboard in our own memory. persp_texture_create
     * copies it (and builds the mip chain), so texels could be freed or
     * reused right after. Row 0 is the bottom row, as in OpenGL. */
    for (int y = 0; y < TEX; y++)
        for (int x = 0; x < TEX; x++) {
            uint8_t v = ((x / CHECK + y / CHECK) % 2) ? 230 : 30;
            uint8_t *p = &texels[(y * TEX + x) * 4];
            p[0] = p[1] = p[2] = v;
            p[3] = 255;
        }
    persp_image image = {TEX, TEX, TEX * 4, texels};
    if (failed(ctx, persp_texture_create(ctx, &image, &texture), "persp_texture_create")) goto done;

    /* A floor triangle running from just below the camera to far away:
     * strong foreshortening is where the methods differ. Texture
     * coordinates beyond [0, 1] repeat the checkerboard (the default wrap). */
    const persp_vertex vertices[3] = {
        {.pos = {-4.0f, 0.0f, 1.0f}, .uv = {0.0f, 0.0f}, .color = {1, 1, 1, 1}},
        {.pos = {4.0f, 0.0f, 1.0f}, .uv = {8.0f, 0.0f}, .color = {1, 1, 1, 1}},
        {.pos = {0.0f, 0.0f, -30.0f}, .uv = {4.0f, 31.0f}, .color = {1, 1, 1, 1}},
    };
    const uint32_t indices[3] = {0, 1, 2};

    /* OpenGL conventions: clip = projection · view · model. */
    persp_mat4 projection = persp_perspective(60.0, (double)WIDTH / HEIGHT, 0.1, 100.0);
    persp_mat4 view = persp_look_at((persp_vec3){0.0f, 1.5f, 2.0f}, (persp_vec3){0.0f, 0.0f, -10.0f},
                                    (persp_vec3){0.0f, 1.0f, 0.0f});

    /* Zero-initialised fields take their defaults: z-buffer with the depth
     * test on, no culling, repeat wrapping. */
    persp_draw_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.mvp = persp_mat4_mul(projection, view);
    desc.texture = texture;
    desc.method = method;
    desc.sampler.filter = PERSP_FILTER_TRILINEAR; /* mip-mapped: no shimmer in the distance */

    /* persp_draw never clears: the caller decides when a frame starts. */
    persp_framebuffer fb = {WIDTH, HEIGHT, color, depth};
    const uint8_t sky[4] = {90, 140, 200, 255};
    persp_framebuffer_clear(&fb, sky, PERSP_DEPTH_Z);
    if (failed(ctx, persp_draw(ctx, &fb, &desc, vertices, 3, indices, 3), "persp_draw")) goto done;

    /* The triangle covers a good part of the view; finding none of it means
     * something is wrong (a matrix, the depth test), not an empty picture. */
    size_t covered = 0;
    for (size_t i = 0; i < (size_t)WIDTH * HEIGHT; i++)
        if (memcmp(&color[i * 4], sky, 4) != 0) covered++;
    if (covered == 0) {
        fprintf(stderr, "draw_triangle: the triangle covers no pixel\n");
        goto done;
    }

    persp_image frame = {WIDTH, HEIGHT, WIDTH * 4, color};
    if (failed(ctx, persp_image_write_png(ctx, output, &frame), output)) goto done;
    printf("draw_triangle: method %s, trilinear filter: %zu of %d pixels covered, saved %s\n", method,
           covered, WIDTH * HEIGHT, output);
    status = EXIT_SUCCESS;

done:
    persp_texture_destroy(texture);
    persp_context_destroy(ctx);
    return status;
}
