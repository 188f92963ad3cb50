/*
 * Golden images with explicit tolerances (docs/DESIGN.md, "Testing", layer 3).
 * On failure the rendered image and an amplified difference image are
 * written into the build folder. PERSP_UPDATE_GOLDEN=1 rewrites the
 * references instead of comparing (review the new images before committing).
 */
#include "oracle.h"
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

/* ------------------------------------------------------------- oracles */

/* The references above were rendered by persp itself. These filters are
 * OpenGL's, so each reference is also held, at every pixel, to the
 * interval GL 4.6 allows for it (tests/diff/diffref.c: the visible
 * triangle, exact perspective-correct coordinates, level of detail and
 * texel weights computed in double from the scene's camera, meshes and
 * mip levels, with margins for where GL leaves latitude: edges, texel and
 * level ties). It needs no OpenGL library, unlike diff_golden, which
 * compares the same references with Mesa llvmpipe when the build has
 * OSMesa. Tolerance as the differential test's: half a level for nearest
 * (persp returns the texel, the interval holds it; the half level is the
 * arbiter's own rounding), one level for the blends (weights in float
 * against double, one rounding). A render with the affine method through
 * the same check shows what it catches. */
static oracle_interval_result interval_report(persp_context *ctx, const char *what, const char *scene_name,
                                              const persp_image *img, const char *filter)
{
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, scene_name, &scene), PERSP_OK);
    persp_filter f;
    int aniso = 0;
    assert_int_equal(persp_filter_parse(filter, &f, &aniso), PERSP_OK);
    persp_scene_info info;
    persp_scene_get_info(scene, &info);
    double tol = f == PERSP_FILTER_NEAREST ? 0.5 : 1.0;
    oracle_interval_result r = oracle_check_interval(scene, img, f, tol, info.clear);
    print_message("%s against GL's interval: %zu pixels (%zu must show a surface, %zu the background), %zu "
                  "outside (first at %d,%d)\n",
                  what, r.checked, r.covered, r.background, r.off, r.first_x, r.first_y);
    persp_scene_destroy(scene);
    return r;
}

static void golden_in_interval(const char *scene_name, const char *filter, int w, int h)
{
    persp_context *ctx = test_context();
    char rel[256], path[1024];
    snprintf(rel, sizeof rel, "tests/golden/data/%s_exact_%s_%dx%d.png", scene_name, filter, w, h);
    test_source_path(path, sizeof path, rel);
    persp_image img;
    if (persp_image_load(ctx, path, &img) != PERSP_OK) fail_msg("%s: %s", path, persp_context_error(ctx));
    assert_int_equal(img.width, w);
    assert_int_equal(img.height, h);
    oracle_interval_result r = interval_report(ctx, rel, scene_name, &img, filter);
    assert_true(r.checked == (size_t)w * (size_t)h);
    assert_true(r.off == 0);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

static void test_goldens_in_gl_interval(void **state)
{
    (void)state;
    golden_in_interval("corridor", "nearest", 512, 384);
    golden_in_interval("corridor", "bilinear", 512, 384);
    golden_in_interval("corridor", "trilinear", 512, 384);
    golden_in_interval("floor", "bilinear", 320, 240);
    golden_in_interval("cube", "bilinear", 320, 240);
}

/* The check can fail: the affine corridor lies outside GL's interval at
 * most of its pixels. */
static void test_interval_rejects_affine(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img;
    render(ctx, "corridor", "affine", "bilinear", 512, 384, &img);
    oracle_interval_result r = interval_report(ctx, "corridor affine bilinear (must be rejected)", "corridor", &img,
                                               "bilinear");
    assert_true(r.off > r.checked / 10);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corridor_exact_bilinear),
        cmocka_unit_test(test_corridor_exact_nearest),
        cmocka_unit_test(test_cube_and_floor),
        cmocka_unit_test(test_affine_differs_visibly),
        cmocka_unit_test(test_goldens_in_gl_interval),
        cmocka_unit_test(test_interval_rejects_affine),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
