/* persp_scene_tint_mip_levels: with a nearest-mip-nearest filter every
 * textured pixel of the floor (unlit) is one level's colour, and the floor
 * going to the horizon shows several levels, in order of distance. */
/* ctest-labels: threads (renders with several worker threads) */
#include "support.h"

#include <stdlib.h>
#include <string.h>

static int level_of(const uint8_t *px)
{
    for (int l = 0; l < 12; l++) {
        uint8_t c[4];
        persp_mip_level_color(l, c);
        if (!memcmp(c, px, 3)) return l;
    }
    return -1;
}

static void test_floor_levels(void **state)
{
    (void)state;
    persp_context *ctx = test_context_threads(2);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "floor", &scene), PERSP_OK);
    assert_int_equal(persp_scene_tint_mip_levels(scene), PERSP_OK);
    const int w = 160, h = 120;
    persp_framebuffer fb = test_framebuffer(w, h);
    uint8_t *color = fb.color;
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.filter = PERSP_FILTER_NEAREST_MIP_NEAREST;
    d.shading = PERSP_SHADING_NONE;
    assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_OK);
    /* Bottom row (near) and a row just under the horizon (far). */
    int seen[12] = {0}, unknown = 0;
    int near_level = level_of(color + (size_t)(w / 2) * 4);
    for (int y = 0; y < h / 2 - 2; y++)
        for (int x = 0; x < w; x++) {
            int l = level_of(color + ((size_t)y * w + x) * 4);
            if (l < 0)
                unknown++;
            else
                seen[l] = 1;
        }
    int distinct = 0;
    for (int l = 0; l < 12; l++)
        distinct += seen[l];
    assert_int_equal(unknown, 0);
    assert_true(distinct >= 3);
    int far_level = level_of(color + ((size_t)(h / 2 - 3) * w + w / 2) * 4);
    assert_true(near_level >= 0 && far_level > near_level);
    test_framebuffer_free(&fb);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

static void test_palette(void **state)
{
    (void)state;
    uint8_t a[4], b[4];
    persp_mip_level_color(0, a);
    assert_true(a[0] == 255 && a[1] == 255 && a[2] == 255 && a[3] == 255);
    for (int l = 1; l < 10; l++) {
        persp_mip_level_color(l - 1, a);
        persp_mip_level_color(l, b);
        assert_true(memcmp(a, b, 3) != 0);
    }
    persp_mip_level_color(99, a);
    persp_mip_level_color(9, b);
    assert_memory_equal(a, b, 4);
    assert_int_equal(persp_scene_tint_mip_levels(NULL), PERSP_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_floor_levels),
        cmocka_unit_test(test_palette),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
