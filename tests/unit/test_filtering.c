/*
 * persp accuracy --filter (src/analysis/filtering.c): the supersampled
 * reference (its tiling and its convergence), the SSIM metric, the texel
 * counts' definitions, and the filter orderings that texture-filtering
 * theory predicts against a box-filtered reference.
 */
#include "support.h"

#include "analysis/filtering.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double psnr_rgb(const float *a, const float *b, size_t n)
{
    double se = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)a[4 * i + (size_t)c] - (double)b[4 * i + (size_t)c];
            se += d * d;
        }
    double mse = se / (3.0 * (double)n);
    return mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
}

/* With one sample per pixel the reference is the plain bilinear render;
 * rendering it in 16×16 tiles through the composed window transform must
 * reproduce it (up to texel choices flipping at exact ties). */
static void test_reference_tiling(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp__tilt_scene(ctx, 45.0, &scene), PERSP_OK);
    const int W = 80, H = 60;
    float *ref = malloc((size_t)W * H * 4 * sizeof *ref);
    uint8_t *color = malloc((size_t)W * H * 4);
    float *depth = malloc((size_t)W * H * sizeof *depth);
    assert_non_null(ref);
    assert_non_null(color);
    assert_non_null(depth);
    assert_int_equal(persp__filter_reference(ctx, scene, W, H, 1, 16, ref), PERSP_OK);
    persp_framebuffer fb = {W, H, color, depth};
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.filter = PERSP_FILTER_BILINEAR;
    assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_OK);
    size_t differ = 0;
    for (size_t i = 0; i < (size_t)W * H * 4; i++)
        if (fabsf(ref[i] - (float)color[i]) > 1.0f) differ++;
    assert_true(differ <= (size_t)W * H * 4 / 500);
    free(ref), free(color), free(depth);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* The box-filtered reference converges as the sample count grows: for a
 * texture with sharp edges the error of an S×S point-sampled box integral
 * falls like 1/S, so doubling S gains about 6 dB against a finer one. */
static void test_reference_converges(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp__tilt_scene(ctx, 70.0, &scene), PERSP_OK);
    const int W = 64, H = 48;
    size_t n = (size_t)W * H;
    float *r2 = malloc(n * 4 * sizeof(float)), *r4 = malloc(n * 4 * sizeof(float)),
          *r8 = malloc(n * 4 * sizeof(float));
    assert_non_null(r2);
    assert_non_null(r4);
    assert_non_null(r8);
    assert_int_equal(persp__filter_reference(ctx, scene, W, H, 2, 64, r2), PERSP_OK);
    assert_int_equal(persp__filter_reference(ctx, scene, W, H, 4, 7, r4), PERSP_OK);
    assert_int_equal(persp__filter_reference(ctx, scene, W, H, 8, 64, r8), PERSP_OK);
    double p24 = psnr_rgb(r2, r8, n), p48 = psnr_rgb(r4, r8, n);
    print_message("reference 2x2 vs 8x8: %.1f dB, 4x4 vs 8x8: %.1f dB\n", p24, p48);
    assert_true(p48 > p24 + 4.0);
    free(r2), free(r4), free(r8);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

static void test_ssim(void **state)
{
    (void)state;
    const int W = 32, H = 24;
    float a[32 * 24], b[32 * 24];
    test_rng rng = {9};
    for (int i = 0; i < W * H; i++) {
        a[i] = (float)test_rng_uniform(&rng, 0, 255);
        b[i] = 255.0f - a[i];
    }
    assert_true(fabs(persp__ssim(a, a, NULL, W, H) - 1.0) < 1e-9);
    assert_true(persp__ssim(a, b, NULL, W, H) < 0.0);
    /* A window counts only if the mask covers one of its pixels. */
    uint8_t mask[32 * 24];
    memset(mask, 0, sizeof mask);
    assert_true(fabs(persp__ssim(a, b, mask, W, H) - 1.0) < 1e-9);
}

static const persp_filter_accuracy_row *row(const persp_filter_accuracy_result *res, const char *c,
                                            const char *f)
{
    for (size_t i = 0; i < persp_filter_accuracy_row_count(res); i++) {
        const persp_filter_accuracy_row *r = persp_filter_accuracy_row_at(res, i);
        if (!strcmp(r->case_name, c) && !strcmp(r->filter, f)) return r;
    }
    fail_msg("no row %s %s", c, f);
    return NULL;
}

/* Minified surfaces: point sampling aliases (mip maps help, Williams 1983),
 * trilinear over-blurs along the minor axis where EXT anisotropic taps do
 * not, and [Romaniuk-ObjSpace]'s object-space texturing (every texel of a level fine
 * enough for the piece, splatted with area weights) beats isotropic
 * filtering. Texel counts follow from the filters' definitions. */
static void test_filter_orderings(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *filters[] = {"nearest", "bilinear", "nearest-mip-linear", "trilinear", "aniso:16", "object"};
    const char *cases[] = {"corridor", "tilt-70"};
    persp_filter_accuracy_desc d;
    memset(&d, 0, sizeof d);
    d.filters = filters;
    d.filter_count = 6;
    d.cases = cases;
    d.case_count = 2;
    d.width = 96, d.height = 72;
    d.samples = 6;
    d.repeats = 1;
    persp_filter_accuracy_result *res = NULL;
    persp_status st = persp_filter_accuracy_run(ctx, &d, &res);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    assert_int_equal(persp_filter_accuracy_row_count(res), 12);
    for (int k = 0; k < 2; k++) {
        const char *c = cases[k];
        const persp_filter_accuracy_row *nn = row(res, c, "nearest"), *bl = row(res, c, "bilinear");
        const persp_filter_accuracy_row *nml = row(res, c, "nearest-mip-linear"), *tri = row(res, c, "trilinear");
        const persp_filter_accuracy_row *an = row(res, c, "aniso:16"), *ob = row(res, c, "object");
        print_message("%s: nearest %.2f, trilinear %.2f, aniso:16 %.2f, object %.2f dB\n", c, nn->psnr,
                      tri->psnr, an->psnr, ob->psnr);
        assert_true(nn->pixels > 1000);
        assert_true(tri->psnr > nn->psnr + 3.0);
        assert_true(an->psnr > tri->psnr + 1.0);
        assert_true(an->ssim > tri->ssim);
        assert_true(ob->psnr > tri->psnr);
        assert_true(ob->max_err <= 255.0 && ob->mean_err > 0.0);
        assert_true(nn->fetches_px == 1.0);
        assert_true(bl->fetches_px == 4.0);
        assert_true(nml->fetches_px >= 1.0 && nml->fetches_px <= 2.0);
        assert_true(tri->fetches_px >= 4.0 && tri->fetches_px <= 8.0);
        assert_true(an->fetches_px >= tri->fetches_px && an->fetches_px <= 16.0 * 8.0);
        assert_true(ob->fetches_px > 1.0);
        assert_int_equal(tri->tex_levels, 9);
        assert_true(fabs(tri->mip_overhead - 1.0 / 3.0) < 1e-3);
    }
    persp_filter_accuracy_destroy(res);
    persp_context_destroy(ctx);
}

static void test_bad_input(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_filter_accuracy_result *res = NULL;
    persp_filter_accuracy_desc d;
    memset(&d, 0, sizeof d);
    const char *bad[] = {"blur"};
    d.filters = bad;
    d.filter_count = 1;
    assert_int_equal(persp_filter_accuracy_run(ctx, &d, &res), PERSP_ERR_NOT_FOUND);
    assert_null(res);
    const char *good[] = {"nearest"}, *nocase[] = {"tilt-33"};
    d.filters = good;
    d.cases = nocase;
    d.case_count = 1;
    assert_int_equal(persp_filter_accuracy_run(ctx, &d, &res), PERSP_ERR_NOT_FOUND);
    d.case_count = 0;
    d.samples = 65;
    assert_int_equal(persp_filter_accuracy_run(ctx, &d, &res), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_filter_accuracy_filter_check("aniso:99"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_filter_accuracy_filter_check("object"), PERSP_OK);
    assert_int_equal(persp_filter_accuracy_case_check("tilt-85"), PERSP_OK);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_tiling),
        cmocka_unit_test(test_reference_converges),
        cmocka_unit_test(test_ssim),
        cmocka_unit_test(test_filter_orderings),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
