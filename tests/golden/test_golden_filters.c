/*
 * Golden images of the texture filters and of the object-space pipeline
 * (tolerances as in test_golden.c). On failure the rendered image and an
 * amplified difference image are written into the build folder.
 * PERSP_UPDATE_GOLDEN=1 rewrites the references instead of comparing
 * (review the new images before committing).
 */
#include "oracle.h"
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void render_with(persp_context *ctx, const char *scene_name, const char *method, const char *filter,
                        persp_pipeline pipe, int w, int h, persp_image *out)
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
    desc.pipeline = pipe;
    assert_int_equal(persp_filter_parse(filter, &desc.filter, &desc.max_aniso), PERSP_OK);
    persp_status st = persp_render(ctx, scene, &desc, &fb, NULL);
    if (st != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    free(depth);
    persp_scene_destroy(scene);
}

static void render(persp_context *ctx, const char *scene_name, const char *filter, persp_pipeline pipe, int w,
                   int h, persp_image *out)
{
    render_with(ctx, scene_name, "exact", filter, pipe, w, h, out);
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

/* ------------------------------------------------------------- oracles */

/* The references above were rendered by persp itself; these checks hold
 * them to an image computed without persp's rasterizer or samplers: the
 * area-sampled image of tests/golden/oracle.h (4 × 4 sub-pixel samples of
 * GL's trilinear interval, computed in double from the scene's camera,
 * meshes and mip levels by tests/diff/diffref.c). Anisotropic, EWA and
 * object-space filtering all approximate that box integral of the
 * footprint, none exactly (other kernels, a bounded number of taps), so
 * the checks bound the error over the covered pixels (every sub-sample
 * on a surface; every other pixel in x and y, a quarter of the image,
 * keeps the test fast) rather than per pixel. Each bound lies between the
 * golden's measured error and the nearest wrong image the check must
 * reject, rendered again in the test itself:
 * the isotropic trilinear filter (anisotropy lost: blur) and, where the
 * pipeline has it, the affine method (texture coordinates not
 * perspective-correct). Measured at introduction (mean |d| levels, PSNR):
 *
 *   corridor 512×384  aniso:8 golden 1.56, 36.2 dB; trilinear 7.47, 25.1 dB;
 *                     affine aniso:8 66.2, 11.0 dB
 *   floor 320×240     ewa golden 4.09, 31.8 dB; aniso-window:8 golden 5.72,
 *                     26.8 dB; trilinear 8.54, 24.8 dB; affine 44.5, 13.4 dB
 *   corridor 320×240  object-space bilinear golden 3.52, 32.2 dB; screen
 *                     trilinear 8.03, 25.6 dB; screen bilinear 18.3, 17.4 dB */
typedef struct area_bound {
    double max_mean_abs, min_psnr;
} area_bound;

typedef struct area_ref {
    persp_context *ctx;
    const char *scene;
    int w, h;
    double *rgb;
    unsigned char *inside;
} area_ref;

static area_ref area_ref_make(const char *scene_name, int w, int h)
{
    area_ref a = {test_context(), scene_name, w, h, NULL, NULL};
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(a.ctx, scene_name, &scene), PERSP_OK);
    a.rgb = malloc((size_t)w * (size_t)h * 3 * sizeof *a.rgb);
    a.inside = malloc((size_t)w * (size_t)h);
    assert_non_null(a.rgb);
    assert_non_null(a.inside);
    assert_int_equal(oracle_area_image(scene, w, h, 4, 2, a.rgb, a.inside), 0);
    persp_scene_destroy(scene);
    return a;
}

static void area_ref_free(area_ref *a)
{
    free(a->rgb);
    free(a->inside);
    persp_context_destroy(a->ctx);
}

static int area_within(const area_ref *a, const char *what, const persp_image *img, area_bound b)
{
    assert_int_equal(img->width, a->w);
    assert_int_equal(img->height, a->h);
    oracle_error e = oracle_area_error(img, a->rgb, a->inside);
    int ok = e.pixels > 0 && e.mean_abs <= b.max_mean_abs && e.psnr >= b.min_psnr;
    print_message("%s %s against the area-sampled image: %zu pixels, mean |d| %.2f (<= %.2f), PSNR %.2f dB "
                  "(>= %.1f): %s\n",
                  a->scene, what, e.pixels, e.mean_abs, b.max_mean_abs, e.psnr, b.min_psnr,
                  ok ? "within" : "outside");
    return ok;
}

/* The committed reference tests/golden/data/NAME must lie within b. */
static void golden_within(const area_ref *a, const char *name, area_bound b)
{
    char rel[256], path[1024];
    snprintf(rel, sizeof rel, "tests/golden/data/%s", name);
    test_source_path(path, sizeof path, rel);
    persp_image img;
    if (persp_image_load(a->ctx, path, &img) != PERSP_OK) fail_msg("%s: %s", path, persp_context_error(a->ctx));
    int ok = area_within(a, name, &img, b);
    persp_image_free(a->ctx, &img);
    assert_true(ok);
}

/* A render that the check must reject (the check can fail). */
static void render_outside(const area_ref *a, const char *method, const char *filter, persp_pipeline pipe,
                           area_bound b)
{
    persp_image img;
    char what[128];
    snprintf(what, sizeof what, "%s %s%s (must be rejected)", method, filter,
             pipe == PERSP_PIPELINE_OBJECT ? " object-space" : "");
    render_with(a->ctx, a->scene, method, filter, pipe, a->w, a->h, &img);
    int ok = area_within(a, what, &img, b);
    persp_image_free(a->ctx, &img);
    assert_false(ok);
}

/* Anisotropic filtering with 8 taps: the corridor's walls are minified up
 * to far beyond 8:1 along the view, where even 8 taps blur, but the bound
 * (half the isotropic filter's error, 5 dB above it) still rejects losing
 * anisotropy and the affine method. */
static void test_corridor_aniso_oracle(void **state)
{
    (void)state;
    const area_bound b = {3.5, 30.0};
    area_ref a = area_ref_make("corridor", 512, 384);
    golden_within(&a, "corridor_exact_aniso-8_512x384.png", b);
    render_outside(&a, "exact", "trilinear", PERSP_PIPELINE_SCREEN, b);
    render_outside(&a, "affine", "aniso:8", PERSP_PIPELINE_SCREEN, b);
    area_ref_free(&a);
}

/* EWA (Gaussian kernel over the elliptical footprint, Heckbert 1989
 * §3.5.8) comes closest to the box integral of the two; the window-weighted
 * anisotropic filter with 8 taps lies between it and the isotropic filter
 * on the floor, whose far half is minified beyond 8:1, so its bound is the
 * tighter to trilinear's (7.0 against 8.5 levels, 25.5 against 24.8 dB). */
static void test_floor_ewa_oracle(void **state)
{
    (void)state;
    const area_bound ewa = {5.5, 29.0}, window = {7.0, 25.5};
    area_ref a = area_ref_make("floor", 320, 240);
    golden_within(&a, "floor_exact_ewa_320x240.png", ewa);
    golden_within(&a, "floor_exact_aniso-window-8_320x240.png", window);
    render_outside(&a, "exact", "trilinear", PERSP_PIPELINE_SCREEN, ewa);
    render_outside(&a, "exact", "trilinear", PERSP_PIPELINE_SCREEN, window);
    render_outside(&a, "exact", "aniso-window:8", PERSP_PIPELINE_SCREEN, ewa);
    render_outside(&a, "affine", "ewa", PERSP_PIPELINE_SCREEN, ewa);
    render_outside(&a, "affine", "aniso-window:8", PERSP_PIPELINE_SCREEN, window);
    area_ref_free(&a);
}

/* The object-space pipeline walks texels of the chosen levels and splats
 * them onto pixels ([Romaniuk-ObjSpace]): an area filter of its own. It
 * takes no texture-coordinate method (affine draws the same image), so the
 * wrong images it must reject are screen-space ones: the isotropic
 * trilinear filter and bilinear without mip levels (aliasing), i.e. the
 * pipeline falling back to point sampling of the inverse mapping. */
static void test_object_space_oracle(void **state)
{
    (void)state;
    const area_bound b = {5.0, 29.0};
    area_ref a = area_ref_make("corridor", 320, 240);
    golden_within(&a, "corridor_object_bilinear_320x240.png", b);
    render_outside(&a, "exact", "trilinear", PERSP_PIPELINE_SCREEN, b);
    render_outside(&a, "exact", "bilinear", PERSP_PIPELINE_SCREEN, b);
    area_ref_free(&a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corridor_trilinear),
        cmocka_unit_test(test_corridor_aniso),
        cmocka_unit_test(test_floor_ewa_and_window),
        cmocka_unit_test(test_object_space),
        cmocka_unit_test(test_object_space_oracle),
        cmocka_unit_test(test_corridor_aniso_oracle),
        cmocka_unit_test(test_floor_ewa_oracle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
