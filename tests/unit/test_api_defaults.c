/* The header's contract for defaults: a zero-initialised desc means "as the
 * scene asks" (render) or the documented default (sampler, draw); every
 * enum's DEFAULT is zero; toggles switch each way; out-of-range values are
 * refused rather than read as something else. */
#include "model/model.h"
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 160, H = 120 };

typedef struct frame {
    uint8_t color[W * H * 4];
    float depth[W * H];
    persp_render_stats stats;
} frame;

static persp_status render(persp_context *ctx, const persp_scene *scene, const persp_render_desc *d,
                           frame *out)
{
    persp_framebuffer fb = {W, H, out->color, out->depth};
    return persp_render(ctx, scene, d, &fb, &out->stats);
}

static uint64_t render_hash(persp_context *ctx, const persp_scene *scene, const persp_render_desc *d)
{
    frame *f = malloc(sizeof *f);
    assert_non_null(f);
    persp_status st = render(ctx, scene, d, f);
    if (st != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    uint64_t h = test_hash(f->color, sizeof f->color);
    free(f);
    return h;
}

static void test_zero_is_default(void **state)
{
    (void)state;
    assert_int_equal(PERSP_FILTER_DEFAULT, 0);
    assert_int_equal(PERSP_WRAP_DEFAULT, 0);
    assert_int_equal(PERSP_SHADING_DEFAULT, 0);
    assert_int_equal(PERSP_DEPTH_DEFAULT, 0);
    assert_int_equal(PERSP_LOD_DEFAULT, 0);
    assert_int_equal(PERSP_PIPELINE_DEFAULT, 0);
    assert_int_equal(PERSP_TOGGLE_DEFAULT, 0);
    assert_string_equal(persp_filter_name(PERSP_FILTER_DEFAULT), "default");
    persp_filter f = PERSP_FILTER_NEAREST;
    assert_int_equal(persp_filter_parse("default", &f, NULL), PERSP_OK);
    assert_int_equal(f, PERSP_FILTER_DEFAULT);
    assert_true(PERSP_VERSION == PERSP_VERSION_MAJOR * 10000 + PERSP_VERSION_MINOR * 100 + PERSP_VERSION_PATCH);
    assert_string_equal(persp_version(), PERSP_VERSION_STRING);
}

/* corridor's textures are bilinear: a zero desc, a NULL desc and an
 * explicit bilinear override give one image; nearest gives another. */
static void test_render_desc_keeps_scene(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    uint64_t zero = render_hash(ctx, scene, &d);
    assert_true(render_hash(ctx, scene, NULL) == zero);
    d.filter = PERSP_FILTER_BILINEAR;
    d.wrap = PERSP_WRAP_REPEAT;
    d.depth_mode = PERSP_DEPTH_Z;
    d.lod_mode = PERSP_LOD_PIXEL;
    d.pipeline = PERSP_PIPELINE_SCREEN;
    d.method = "exact";
    d.lod_clamp = PERSP_TOGGLE_OFF;
    assert_true(render_hash(ctx, scene, &d) == zero);
    d.filter = PERSP_FILTER_NEAREST;
    assert_true(render_hash(ctx, scene, &d) != zero);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* GL 4.6 §8.14.1: lambda is clamped to [min_lod, max_lod] before the
 * magnification test, so trilinear clamped to [0, 0] is bilinear on level
 * 0 — a clamp that "both zero means none" could not express. */
static void test_lod_clamp_toggle(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "floor", &scene), PERSP_OK);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.filter = PERSP_FILTER_BILINEAR;
    uint64_t bilinear = render_hash(ctx, scene, &d);
    d.filter = PERSP_FILTER_TRILINEAR;
    uint64_t trilinear = render_hash(ctx, scene, &d);
    assert_true(trilinear != bilinear);
    d.lod_clamp = PERSP_TOGGLE_ON;
    d.min_lod = d.max_lod = 0.0f;
    assert_true(render_hash(ctx, scene, &d) == bilinear);
    d.lod_clamp = PERSP_TOGGLE_OFF;
    assert_true(render_hash(ctx, scene, &d) == trilinear);
    d.lod_clamp = PERSP_TOGGLE_ON;
    d.min_lod = 1.0f;
    d.max_lod = 0.0f;
    frame *f = malloc(sizeof *f);
    assert_non_null(f);
    assert_int_equal(render(ctx, scene, &d, f), PERSP_ERR_INVALID_ARGUMENT);
    free(f);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* The cube culls back faces by default; OFF draws them (hidden by the
 * depth test, so the image is the same but more triangles are drawn). */
static void test_cull_toggle(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "cube", &scene), PERSP_OK);
    frame *a = malloc(sizeof *a), *b = malloc(sizeof *b);
    assert_non_null(a);
    assert_non_null(b);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    assert_int_equal(render(ctx, scene, &d, a), PERSP_OK);
    d.cull_backfaces = PERSP_TOGGLE_OFF;
    assert_int_equal(render(ctx, scene, &d, b), PERSP_OK);
    assert_true(b->stats.triangles_drawn > a->stats.triangles_drawn);
    assert_memory_equal(a->color, b->color, sizeof a->color);
    d.cull_backfaces = PERSP_TOGGLE_ON;
    assert_int_equal(render(ctx, scene, &d, b), PERSP_OK);
    assert_true(b->stats.triangles_drawn == a->stats.triangles_drawn);
    free(a);
    free(b);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

static void test_out_of_range_refused(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "cube", &scene), PERSP_OK);
    frame *f = malloc(sizeof *f);
    assert_non_null(f);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.cull_backfaces = (persp_toggle)3;
    assert_int_equal(render(ctx, scene, &d, f), PERSP_ERR_INVALID_ARGUMENT);
    memset(&d, 0, sizeof d);
    d.filter = PERSP_FILTER_COUNT;
    assert_int_equal(render(ctx, scene, &d, f), PERSP_ERR_INVALID_ARGUMENT);
    memset(&d, 0, sizeof d);
    d.shading = PERSP_SHADING_COUNT;
    assert_int_equal(render(ctx, scene, &d, f), PERSP_ERR_INVALID_ARGUMENT);
    memset(&d, 0, sizeof d);
    d.count_ops = (persp_toggle)7;
    assert_int_equal(render(ctx, scene, &d, f), PERSP_ERR_INVALID_ARGUMENT);
    free(f);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* The texture settings of a render desc are checked by the sampler's rule,
 * and the message names the desc's field, not the sampler's. */
static void refused_naming(persp_context *ctx, const persp_scene *scene, const persp_render_desc *d, frame *f,
                           const char *field)
{
    assert_int_equal(render(ctx, scene, d, f), PERSP_ERR_INVALID_ARGUMENT);
    char want[96];
    snprintf(want, sizeof want, "persp_render_desc.%s", field);
    if (!strstr(persp_context_error(ctx), want)) fail_msg("'%s' lacks '%s'", persp_context_error(ctx), want);
}

static void test_texture_settings_refused(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "cube", &scene), PERSP_OK);
    frame *f = malloc(sizeof *f);
    assert_non_null(f);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.wrap = (persp_wrap)99;
    refused_naming(ctx, scene, &d, f, "wrap is out of range");
    memset(&d, 0, sizeof d);
    d.max_aniso = PERSP_MAX_ANISO + 1;
    refused_naming(ctx, scene, &d, f, "max_aniso");
    d.max_aniso = 1;
    refused_naming(ctx, scene, &d, f, "max_aniso");
    d.max_aniso = PERSP_MAX_ANISO;
    d.filter = PERSP_FILTER_ANISO;
    assert_int_equal(render(ctx, scene, &d, f), PERSP_OK);
    memset(&d, 0, sizeof d);
    d.lod_bias = NAN;
    refused_naming(ctx, scene, &d, f, "lod_bias");
    memset(&d, 0, sizeof d);
    d.lod_mode = (persp_lod_mode)9;
    refused_naming(ctx, scene, &d, f, "lod_mode");
    memset(&d, 0, sizeof d);
    d.lod_clamp = (persp_toggle)5;
    refused_naming(ctx, scene, &d, f, "lod_clamp");
    memset(&d, 0, sizeof d);
    d.lod_clamp = PERSP_TOGGLE_ON;
    d.min_lod = -PERSP_LOD_LIMIT;
    d.max_lod = INFINITY;
    refused_naming(ctx, scene, &d, f, "min_lod, max_lod");
    d.max_lod = PERSP_LOD_LIMIT;
    assert_int_equal(render(ctx, scene, &d, f), PERSP_OK);
    memset(&d, 0, sizeof d);
    d.depth_mode = (persp_depth_mode)9;
    refused_naming(ctx, scene, &d, f, "depth_mode");
    free(f);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* A zero sampler desc samples bilinear with repeat. */
static void test_sampler_defaults(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    uint8_t px[4 * 4 * 4];
    for (int i = 0; i < 64; i++) px[i] = (uint8_t)(i * 37 + 11);
    persp_image img = {4, 4, 16, px};
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &tex), PERSP_OK);
    persp_sampler_desc zero, expl;
    memset(&zero, 0, sizeof zero);
    memset(&expl, 0, sizeof expl);
    expl.filter = PERSP_FILTER_BILINEAR;
    expl.wrap_s = expl.wrap_t = PERSP_WRAP_REPEAT;
    expl.lod_mode = PERSP_LOD_PIXEL;
    persp_sampler_desc nearest = expl;
    nearest.filter = PERSP_FILTER_NEAREST;
    int differs = 0;
    for (int k = 0; k < 50; k++) {
        float u = -1.3f + 0.071f * (float)k, v = 2.2f - 0.053f * (float)k;
        uint8_t a[4], b[4], c[4];
        persp_texture_sample(tex, &zero, u, v, 0.01f, 0, 0, 0.01f, a);
        persp_texture_sample(tex, &expl, u, v, 0.01f, 0, 0, 0.01f, b);
        persp_texture_sample(tex, &nearest, u, v, 0.01f, 0, 0, 0.01f, c);
        assert_memory_equal(a, b, 4);
        differs += memcmp(a, c, 4) != 0;
    }
    assert_true(differs > 10);
    persp_texture_destroy(tex);
    persp_context_destroy(ctx);
}

/* persp_draw with a zero desc (but the mvp): depth test on, no culling;
 * depth_test OFF lets a farther triangle overwrite a nearer one. */
static void test_draw_defaults(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    enum { S = 16 };
    uint8_t color[S * S * 4];
    float depth[S * S];
    persp_framebuffer fb = {S, S, color, depth};
    /* Two screen-filling triangles, near red then far green; the second is
     * clockwise, so culling would drop it. */
    persp_vertex v[6];
    memset(v, 0, sizeof v);
    const float xy[3][2] = {{-4, -4}, {4, -4}, {0, 4}};
    for (int t = 0; t < 2; t++)
        for (int k = 0; k < 3; k++) {
            persp_vertex *p = &v[t * 3 + k];
            p->pos[0] = xy[t ? 2 - k : k][0];
            p->pos[1] = xy[t ? 2 - k : k][1];
            p->pos[2] = t ? 0.5f : -0.5f;
            p->color[t ? 1 : 0] = 1.0f;
            p->color[3] = 1.0f;
        }
    uint32_t near_idx[3] = {0, 1, 2}, far_idx[3] = {3, 4, 5};
    persp_draw_desc d;
    memset(&d, 0, sizeof d);
    d.mvp = persp_mat4_identity();
    const uint8_t black[4] = {0, 0, 0, 255};
    persp_framebuffer_clear(&fb, black, PERSP_DEPTH_DEFAULT);
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 6, near_idx, 3), PERSP_OK);
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 6, far_idx, 3), PERSP_OK);
    const uint8_t *mid = &color[(S / 2 * S + S / 2) * 4];
    assert_true(mid[0] == 255 && mid[1] == 0);
    d.depth_test = PERSP_TOGGLE_OFF;
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 6, far_idx, 3), PERSP_OK);
    assert_true(mid[0] == 0 && mid[1] == 255);
    persp_framebuffer_clear(&fb, black, PERSP_DEPTH_DEFAULT);
    d.depth_test = PERSP_TOGGLE_DEFAULT;
    d.cull_backfaces = PERSP_TOGGLE_ON;
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 6, far_idx, 3), PERSP_OK);
    assert_true(mid[0] == 0 && mid[1] == 0);
    d.depth_test = (persp_toggle)5;
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 6, far_idx, 3), PERSP_ERR_INVALID_ARGUMENT);
    persp_context_destroy(ctx);
}

/* A scene file's method is what a zero desc renders with, and the render
 * section's filter reaches textures that chose none. */
static void test_scene_method_and_filter(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *with_method =
        "{\"render\": {\"method\": \"affine\", \"filter\": \"nearest\"},"
        " \"camera\": {\"position\": [0, 1, 2], \"target\": [0, 0, -4]},"
        " \"materials\": {\"m\": {\"texture\": {\"file\": \"checker.png\"}}},"
        " \"objects\": [{\"mesh\": \"plane\", \"material\": \"m\","
        "   \"transform\": {\"scale\": [8, 1, 8], \"translate\": [0, 0, -4]}}]}";
    char dir[1024];
    test_source_path(dir, sizeof dir, "scenes/textures/");
    persp_scene *s = NULL;
    persp_status st = persp__scene_load_memory(ctx, with_method, strlen(with_method), "m.json", dir, 0, &s);
    if (st != PERSP_OK) fail_msg("load: %s", persp_context_error(ctx));
    persp_scene_info info;
    persp_scene_get_info(s, &info);
    assert_string_equal(info.method, "affine");
    assert_int_equal(info.filter, PERSP_FILTER_NEAREST);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    uint64_t scene_default = render_hash(ctx, s, &d);
    d.method = "affine";
    assert_true(render_hash(ctx, s, &d) == scene_default);
    d.method = "exact";
    assert_true(render_hash(ctx, s, &d) != scene_default);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

/* persp_draw's settings are checked as persp_render's, each named; indices
 * without vertices, NULL outputs and degenerate projections are refused
 * rather than crashing or dividing by zero; a failure on a NULL argument
 * leaves its own detail, not the previous call's. */
static void test_draw_and_helpers_refuse(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    uint8_t color[16 * 4];
    float depth[16];
    persp_framebuffer fb = {4, 4, color, depth};
    const persp_vertex v[3] = {{{-1, -1, -2}, {0, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                               {{1, -1, -2}, {1, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                               {{-1, 1, -2}, {0, 1}, {0, 0, 1}, {1, 1, 1, 1}}};
    const uint32_t ix[3] = {0, 1, 2};
    persp_draw_desc d;
    memset(&d, 0, sizeof d);
    d.mvp = persp_perspective(60, 1, 0.1, 10);
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, ix, 3), PERSP_OK);
    d.depth_mode = (persp_depth_mode)3;
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, ix, 3), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "persp_draw_desc.depth_mode"));
    d.depth_mode = PERSP_DEPTH_DEFAULT;
    d.depth_test = (persp_toggle)5;
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, ix, 3), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "persp_draw_desc.depth_test"));
    d.depth_test = PERSP_TOGGLE_DEFAULT;
    d.mvp.m[3] = INFINITY;
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, ix, 3), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "mvp"));
    d.mvp = persp_perspective(60, 1, 0.1, 10);
    assert_int_equal(persp_draw(ctx, &fb, &d, NULL, 0, ix, 3), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "no vertices"));
    /* GL refuses these frustums: NaN, refused by the draw, no division. */
    const persp_mat4 bad[3] = {persp_frustum(1, 1, -1, 1, 1, 10), persp_perspective(90, 1, 1, 1),
                               persp_perspective(90, 1, 0, 10)};
    for (int i = 0; i < 3; i++) {
        assert_true(isnan(bad[i].m[0]) && isnan(bad[i].m[15]));
        d.mvp = bad[i];
        assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, ix, 3), PERSP_ERR_INVALID_ARGUMENT);
    }
    assert_int_equal(persp_mat4_normal_matrix(persp_mat4_identity(), NULL), 0);
    persp_mip_level_color(0, NULL);
    /* A NULL argument's own detail. */
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 0, 0, &img), PERSP_ERR_INVALID_ARGUMENT);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(ctx, NULL, &scene), PERSP_ERR_INVALID_ARGUMENT);
    assert_null(strstr(persp_context_error(ctx), "invalid size"));
    assert_non_null(strstr(persp_context_error(ctx), "no path"));
    /* Writers keep what persp_image_load takes back; a folder is IO. */
    uint8_t *wide = calloc(20000, 4);
    assert_non_null(wide);
    const persp_image long_row = {20000, 1, 80000, wide};
    assert_int_equal(persp_image_write_png(ctx, "/tmp/persp-never.png", &long_row), PERSP_ERR_TOO_LARGE);
    const persp_image one = {1, 1, 4, wide};
    assert_int_equal(persp_image_write(ctx, "/tmp", &one, NULL), PERSP_ERR_IO);
    free(wide);
    /* A framebuffer over an image's side: TOO_LARGE, as persp_image_alloc. */
    persp_framebuffer huge = {PERSP_IMAGE_MAX_SIDE + 1, 1, color, depth};
    d.mvp = persp_perspective(60, 1, 0.1, 10);
    assert_int_equal(persp_draw(ctx, &huge, &d, v, 3, ix, 3), PERSP_ERR_TOO_LARGE);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zero_is_default),     cmocka_unit_test(test_render_desc_keeps_scene),
        cmocka_unit_test(test_lod_clamp_toggle),    cmocka_unit_test(test_cull_toggle),
        cmocka_unit_test(test_texture_settings_refused),
        cmocka_unit_test(test_out_of_range_refused), cmocka_unit_test(test_sampler_defaults),
        cmocka_unit_test(test_draw_defaults),       cmocka_unit_test(test_scene_method_and_filter),
        cmocka_unit_test(test_draw_and_helpers_refuse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
