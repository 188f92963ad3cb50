/*
 * Golden images of the example scenes (scenes/room.json, scenes/spheres.json):
 * the whole path from JSON, OBJ/MTL and PNG textures through lighting,
 * texture-coordinate generation, shading and filtering. Tolerances are
 * explicit; on failure the rendered image and an amplified difference image
 * are written into the build folder. PERSP_UPDATE_GOLDEN=1 rewrites the
 * references instead of comparing (review the new images before committing).
 */
#include "oracle.h"
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Renders scenes/NAME.json at w × h; shading NULL keeps the scene's. */
static void render(persp_context *ctx, const char *name, const char *shading, int w, int h,
                   persp_image *out)
{
    char rel[256], path[1024];
    snprintf(rel, sizeof rel, "scenes/%s.json", name);
    test_source_path(path, sizeof path, rel);
    persp_scene *scene = NULL;
    if (persp_scene_load(ctx, path, &scene) != PERSP_OK)
        fail_msg("load %s: %s", path, persp_context_error(ctx));
    assert_int_equal(persp_image_alloc(ctx, w, h, out), PERSP_OK);
    float *depth = malloc((size_t)w * (size_t)h * sizeof *depth);
    assert_non_null(depth);
    persp_framebuffer fb = {w, h, out->pixels, depth};
    persp_render_desc desc;
    memset(&desc, 0, sizeof desc);
    if (shading) {
        assert_int_equal(persp_shading_parse(shading, &desc.shading), PERSP_OK);
    }
    if (persp_render(ctx, scene, &desc, &fb, NULL) != PERSP_OK)
        fail_msg("render %s: %s", name, persp_context_error(ctx));
    free(depth);
    persp_scene_destroy(scene);
}

static void check_golden(const char *scene, const char *shading, int w, int h, test_tolerance tol)
{
    persp_context *ctx = test_context();
    persp_image got;
    render(ctx, scene, shading, w, h, &got);
    char name[256];
    snprintf(name, sizeof name, "scene_%s_%s_%dx%d.png", scene, shading ? shading : "default", w, h);
    test_golden_check(ctx, name, &got, tol);
    persp_image_free(ctx, &got);
    persp_context_destroy(ctx);
}

/* The references were rendered by this code and inspected by eye, so
 * differences can come only from floating-point evaluation order on
 * another compiler or CPU (strict C11 FP, -ffp-contract=off; powf and
 * sqrtf of the lighting are the likeliest to differ in the last bit): a
 * level here and there and a texel choice flipping at a few exact ties,
 * never a systematic change. */
static const test_tolerance strict = {32, 0.001, 45.0};

static void test_room(void **state)
{
    (void)state;
    check_golden("room", NULL, 400, 300, strict);
}

static void test_spheres(void **state)
{
    (void)state;
    check_golden("spheres", NULL, 400, 300, strict);
    check_golden("spheres", "gouraud", 400, 300, strict);
}

/* The example scenes are lit: a scene's shading mode changes its image
 * (flat against phong-pc differs on every curved surface), measured. */
static void test_shading_changes_image(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image a, b;
    render(ctx, "spheres", "phong-pc", 200, 150, &a);
    render(ctx, "spheres", "flat", 200, 150, &b);
    test_diff d = test_image_compare(&a, &b, NULL);
    print_message("flat vs phong-pc: max abs %d, %.1f%% pixels > 2 levels\n", d.max_abs, 100.0 * d.share_over2);
    assert_true(d.share_over2 > 0.05);
    assert_true(d.max_abs > 60);
    persp_image_free(ctx, &a);
    persp_image_free(ctx, &b);
    persp_context_destroy(ctx);
}

/* ------------------------------------------------------------- oracles */

/* The references above were rendered by persp itself; this check holds
 * them to the lighting of docs/SCENES.md evaluated without persp's
 * renderer (tests/golden/oracle.h): at each pixel centre whose surface is
 * certain, the triangle seen, its perspective-correct barycentrics, the
 * eye-space normal and position, Blinn–Phong with the scene's lights and
 * the texture environment, all in double (tests/diff/diffref.c supplies
 * the visible triangle and GL's interval of the texel for the scene's
 * filter, widened by the half level of its rounding to 8 bits); where
 * nothing may be seen, the clear colour. Pixels within 0.01 pixel of an
 * edge or at a depth tie are left out. Tolerance 1 level: persp rounds the
 * combined colour once to 8 bits (half a level); the rest is for its float
 * evaluation of the lighting and of the texel weights, which moves a few
 * pixels by tenths of a level (with half a level of tolerance 139 of the
 * room's pixels fell outside, none at 0.75). Measured at
 * introduction: every checked pixel of the three references inside (room
 * 119931 pixels, spheres 71147 lit and 48424 background, the same under
 * gouraud). */
static const double lit_tol = 1.0;

static persp_scene *load_scene(persp_context *ctx, const char *name)
{
    char rel[256], path[1024];
    snprintf(rel, sizeof rel, "scenes/%s.json", name);
    test_source_path(path, sizeof path, rel);
    persp_scene *scene = NULL;
    if (persp_scene_load(ctx, path, &scene) != PERSP_OK) fail_msg("load %s: %s", path, persp_context_error(ctx));
    return scene;
}

static oracle_lit_result lit_report(const char *what, const persp_scene *scene, const persp_image *img, int gouraud)
{
    oracle_lit_result r = oracle_check_lit(scene, img, gouraud, lit_tol);
    print_message("%s against the %s lighting: %zu pixels checked (%zu lit, %zu background), %zu outside "
                  "(%.3f%%)\n",
                  what, gouraud ? "per-vertex" : "per-pixel", r.checked, r.lit, r.background, r.off,
                  r.checked ? 100.0 * (double)r.off / (double)r.checked : 0.0);
    if (r.off)
        print_message("  first at %d,%d: got %d %d %d, expected [%.1f, %.1f] [%.1f, %.1f] [%.1f, %.1f]\n", r.first_x,
                      r.first_y, r.first_got[0], r.first_got[1], r.first_got[2], r.first_lo[0], r.first_hi[0],
                      r.first_lo[1], r.first_hi[1], r.first_lo[2], r.first_hi[2]);
    return r;
}

/* The committed reference tests/golden/data/GOLDEN of scenes/NAME.json:
 * every checked pixel inside. */
static void golden_lit(const char *name, const char *golden, int gouraud)
{
    persp_context *ctx = test_context();
    persp_scene *scene = load_scene(ctx, name);
    char rel[256], path[1024];
    snprintf(rel, sizeof rel, "tests/golden/data/%s", golden);
    test_source_path(path, sizeof path, rel);
    persp_image img;
    if (persp_image_load(ctx, path, &img) != PERSP_OK) fail_msg("%s: %s", path, persp_context_error(ctx));
    assert_int_equal(img.width, 400);
    assert_int_equal(img.height, 300);
    oracle_lit_result r = lit_report(golden, scene, &img, gouraud);
    assert_true(r.checked > 400u * 300u * 9u / 10u);
    assert_true(r.off == 0);
    persp_image_free(ctx, &img);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* A render the check must reject, with more than 1 % of the checked
 * pixels outside (the check can fail). */
static void lit_rejects(const char *name, const char *method, const char *shading, int gouraud)
{
    persp_context *ctx = test_context();
    persp_scene *scene = load_scene(ctx, name);
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 400, 300, &img), PERSP_OK);
    float *depth = malloc(400 * 300 * sizeof *depth);
    assert_non_null(depth);
    persp_framebuffer fb = {400, 300, img.pixels, depth};
    persp_render_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.method = method;
    if (shading) {
        assert_int_equal(persp_shading_parse(shading, &desc.shading), PERSP_OK);
    }
    if (persp_render(ctx, scene, &desc, &fb, NULL) != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    free(depth);
    char what[256];
    snprintf(what, sizeof what, "%s %s %s (must be rejected)", name, method, shading ? shading : "default");
    oracle_lit_result r = lit_report(what, scene, &img, gouraud);
    assert_true(r.off > r.checked / 100);
    persp_image_free(ctx, &img);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

static void test_room_oracle(void **state)
{
    (void)state;
    golden_lit("room", "scene_room_default_400x300.png", 0);
    /* Texture coordinates not perspective-correct (measured 57 % outside). */
    lit_rejects("room", "affine", NULL, 0);
}

/* What the checks catch, measured at introduction: affine texture
 * coordinates (39 % of the pixels outside), lighting per vertex instead of
 * per pixel (gouraud-pc: 29 %), and under gouraud, perspective-correct
 * weights instead of screen-linear ones (gouraud-pc: 21 %) and per-pixel
 * lighting (32 %). Not caught: phong-pc's normals interpolated
 * screen-linearly (`phong`), within 1 level of the perspective-correct
 * ones on these finely tessellated meshes (tests/unit/test_shading_accuracy.c
 * measures that difference). */
static void test_spheres_oracle(void **state)
{
    (void)state;
    golden_lit("spheres", "scene_spheres_default_400x300.png", 0);
    golden_lit("spheres", "scene_spheres_gouraud_400x300.png", 1);
    lit_rejects("spheres", "affine", NULL, 0);
    lit_rejects("spheres", "exact", "gouraud-pc", 0);
    lit_rejects("spheres", "exact", "gouraud-pc", 1);
    lit_rejects("spheres", "exact", "phong-pc", 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_room),
        cmocka_unit_test(test_spheres),
        cmocka_unit_test(test_shading_changes_image),
        cmocka_unit_test(test_room_oracle),
        cmocka_unit_test(test_spheres_oracle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
