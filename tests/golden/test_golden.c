/*
 * Golden images with explicit tolerances (docs/DESIGN.md, "Testing", layer 3).
 * On failure the rendered image and an amplified difference image are
 * written into the build folder. PERSP_UPDATE_GOLDEN=1 rewrites the
 * references instead of comparing (review the new images before committing).
 */
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void render(persp_context *ctx, const char *scene_name, const char *method, const char *filter,
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
    desc.method = method;
    assert_int_equal(persp_filter_parse(filter, &desc.filter, &desc.max_aniso), PERSP_OK);
    persp_status st = persp_render(ctx, scene, &desc, &fb, NULL);
    if (st != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    free(depth);
    persp_scene_destroy(scene);
}

static void check_golden(const char *scene, const char *method, const char *filter, int w, int h,
                         test_tolerance tol)
{
    persp_context *ctx = test_context();
    persp_image got;
    render(ctx, scene, method, filter, w, h, &got);
    char name[256];
    snprintf(name, sizeof name, "%s_%s_%s_%dx%d.png", scene, method, filter, w, h);
    test_golden_check(ctx, name, &got, tol);
    persp_image_free(ctx, &got);
    persp_context_destroy(ctx);
}

/* Tolerances: the references were rendered by this code, so differences
 * can come only from floating-point evaluation order on another compiler or
 * CPU (strict C11 FP, -ffp-contract=off): a texel choice flipping at a few
 * exact ties, never a systematic change. */
static const test_tolerance strict = {32, 0.0005, 50.0};

static void test_corridor_exact_bilinear(void **state)
{
    (void)state;
    check_golden("corridor", "exact", "bilinear", 512, 384, strict);
}

static void test_corridor_exact_nearest(void **state)
{
    (void)state;
    check_golden("corridor", "exact", "nearest", 512, 384, strict);
}

static void test_cube_and_floor(void **state)
{
    (void)state;
    check_golden("cube", "exact", "bilinear", 320, 240, strict);
    check_golden("floor", "exact", "bilinear", 320, 240, strict);
}

/* Perspective correction is visible: affine texturing of the corridor is
 * far from the exact image (measured, not assumed). */
static void test_affine_differs_visibly(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image exact, affine;
    render(ctx, "corridor", "exact", "bilinear", 512, 384, &exact);
    render(ctx, "corridor", "affine", "bilinear", 512, 384, &affine);
    test_diff d = test_image_compare(&exact, &affine, NULL);
    print_message("affine vs exact: max abs %d, %.1f%% pixels > 2 levels, PSNR %.1f dB\n", d.max_abs,
                  100.0 * d.share_over2, d.psnr);
    assert_true(d.share_over2 > 0.20);
    assert_true(d.psnr < 20.0);
    assert_true(d.max_abs > 150);
    persp_image_free(ctx, &exact);
    persp_image_free(ctx, &affine);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corridor_exact_bilinear),
        cmocka_unit_test(test_corridor_exact_nearest),
        cmocka_unit_test(test_cube_and_floor),
        cmocka_unit_test(test_affine_differs_visibly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
