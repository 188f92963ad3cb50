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
    persp_status st = persp_render(ctx, scene, &desc, &fb, NULL);
    if (st != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    free(depth);
    persp_scene_destroy(scene);
}

static void check_golden(const char *scene, const char *filter, persp_pipeline pipe, int w, int h,
                         test_tolerance tol)
{
    persp_context *ctx = test_context();
    persp_image got;
    render(ctx, scene, filter, pipe, w, h, &got);
    char name[256];
    snprintf(name, sizeof name, "%s_%s_%s_%dx%d.png", scene, pipe == PERSP_PIPELINE_OBJECT ? "object" : "exact",
             filter, w, h);
    test_golden_check(ctx, name, &got, tol);
    persp_image_free(ctx, &got);
    persp_context_destroy(ctx);
}

/* The references were rendered by this code and inspected; differences can
 * come only from floating-point evaluation order on another compiler or CPU
 * (strict C11 FP, -ffp-contract=off): a texel or level choice flipping at a
 * few exact ties, never a systematic change. */
static const test_tolerance strict = {32, 0.0005, 50.0};

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
