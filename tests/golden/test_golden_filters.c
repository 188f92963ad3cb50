/*
 * Golden images of the texture filters and of the object-space pipeline
 * (tolerances as in test_golden.c). On failure the rendered image and an
 * amplified difference image are written into the build folder.
 * PERSP_UPDATE_GOLDEN=1 rewrites the references instead of comparing
 * (review the new images before committing).
 */
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct tolerance {
    int max_abs;            /* largest per-channel difference */
    double max_share_over2; /* share of pixels with a channel differing by more than 2 */
    double min_psnr;        /* dB */
} tolerance;

typedef struct diff_stats {
    int max_abs;
    double share_over2, psnr;
} diff_stats;

static diff_stats compare(const persp_image *a, const persp_image *b, persp_image *diff)
{
    diff_stats d = {0, 0.0, INFINITY};
    double se = 0.0;
    long over = 0, n = (long)a->width * a->height;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++) {
            const uint8_t *p = a->pixels + (size_t)y * a->stride + 4 * (size_t)x;
            const uint8_t *q = b->pixels + (size_t)y * b->stride + 4 * (size_t)x;
            int m = 0;
            for (int c = 0; c < 3; c++) {
                int e = abs((int)p[c] - (int)q[c]);
                se += (double)e * e;
                if (e > m) m = e;
            }
            if (m > d.max_abs) d.max_abs = m;
            if (m > 2) over++;
            if (diff) {
                uint8_t *o = diff->pixels + (size_t)y * diff->stride + 4 * (size_t)x;
                int v = m * 8 > 255 ? 255 : m * 8;
                o[0] = (uint8_t)v, o[1] = (uint8_t)(v / 4), o[2] = (uint8_t)(v / 4), o[3] = 255;
            }
        }
    d.share_over2 = (double)over / (double)n;
    double mse = se / (3.0 * (double)n);
    d.psnr = mse > 0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
    return d;
}

static void render(persp_context *ctx, const char *scene_name, const char *filter, persp_pipeline pipe,
                   int w, int h, persp_image *out)
{
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, scene_name, &scene), PERSP_OK);
    assert_int_equal(persp_image_alloc(ctx, w, h, out), PERSP_OK);
    float *depth = malloc((size_t)w * (size_t)h * sizeof *depth);
    assert_non_null(depth);
    persp_framebuffer fb = {w, h, out->pixels, depth};
    persp_render_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.method = "exact";
    desc.pipeline = pipe;
    assert_int_equal(persp_filter_parse(filter, &desc.filter, &desc.max_aniso), PERSP_OK);
    desc.filter_set = 1;
    persp_status st = persp_render(ctx, scene, &desc, &fb, NULL);
    if (st != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    free(depth);
    persp_scene_destroy(scene);
}

static void check_golden(const char *scene, const char *filter, persp_pipeline pipe, int w, int h,
                         tolerance tol)
{
    persp_context *ctx = test_context();
    persp_image got;
    render(ctx, scene, filter, pipe, w, h, &got);
    char name[256], path[1024];
    snprintf(name, sizeof name, "%s_%s_%s_%dx%d.png", scene, pipe == PERSP_PIPELINE_OBJECT ? "object" : "exact",
             filter, w, h);
    for (char *c = name; *c; c++)
        if (*c == ':') *c = '-';
    char rel[300];
    snprintf(rel, sizeof rel, "tests/golden/data/%s", name);
    test_source_path(path, sizeof path, rel);
    const char *update = getenv("PERSP_UPDATE_GOLDEN");
    if (update && !strcmp(update, "1")) {
        assert_int_equal(persp_image_write_png(ctx, path, &got), PERSP_OK);
        print_message("updated %s\n", path);
    } else {
        persp_image want;
        persp_status st = persp_image_load(ctx, path, &want);
        if (st != PERSP_OK) fail_msg("cannot load golden %s: %s", path, persp_context_error(ctx));
        assert_int_equal(want.width, w);
        assert_int_equal(want.height, h);
        persp_image diff;
        assert_int_equal(persp_image_alloc(ctx, w, h, &diff), PERSP_OK);
        diff_stats d = compare(&got, &want, &diff);
        print_message("%s: max abs %d, %.4f%% pixels > 2 levels, PSNR %.1f dB\n", name, d.max_abs,
                      100.0 * d.share_over2, d.psnr);
        if (d.max_abs > tol.max_abs || d.share_over2 > tol.max_share_over2 || d.psnr < tol.min_psnr) {
            char out[1024];
            snprintf(rel, sizeof rel, "golden-fail-%s", name);
            test_binary_path(out, sizeof out, rel);
            persp_image_write_png(ctx, out, &got);
            snprintf(rel, sizeof rel, "golden-diff-%s", name);
            test_binary_path(out, sizeof out, rel);
            persp_image_write_png(ctx, out, &diff);
            fail_msg("%s outside tolerance (max abs <= %d, share > 2 <= %.4f, PSNR >= %.1f); see %s",
                     name, tol.max_abs, tol.max_share_over2, tol.min_psnr, out);
        }
        persp_image_free(ctx, &diff);
        persp_image_free(ctx, &want);
    }
    persp_image_free(ctx, &got);
    persp_context_destroy(ctx);
}

/* The references were rendered by this code and inspected; differences can
 * come only from floating-point evaluation order on another compiler or CPU
 * (strict C11 FP, -ffp-contract=off): a texel or level choice flipping at a
 * few exact ties, never a systematic change. */
static const tolerance strict = {32, 0.0005, 50.0};

static void test_corridor_trilinear(void **state)
{
    (void)state;
    check_golden("corridor", "trilinear", PERSP_PIPELINE_SCREEN, 512, 384, strict);
}

static void test_corridor_aniso(void **state)
{
    (void)state;
    check_golden("corridor", "aniso:8", PERSP_PIPELINE_SCREEN, 512, 384, strict);
}

static void test_floor_ewa_and_window(void **state)
{
    (void)state;
    check_golden("floor", "ewa", PERSP_PIPELINE_SCREEN, 320, 240, strict);
    check_golden("floor", "aniso-window:8", PERSP_PIPELINE_SCREEN, 320, 240, strict);
}

static void test_object_space(void **state)
{
    (void)state;
    check_golden("corridor", "bilinear", PERSP_PIPELINE_OBJECT, 320, 240, strict);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corridor_trilinear),
        cmocka_unit_test(test_corridor_aniso),
        cmocka_unit_test(test_floor_ewa_and_window),
        cmocka_unit_test(test_object_space),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
