/* persp_render_desc.view / .projection and persp_scene_get_camera: the scene's
 * own matrices passed back in give the scene's image; other matrices give
 * another image; non-finite ones are refused. */
/* ctest-labels: threads (renders with several worker threads) */
#include "support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct frame {
    persp_context *ctx;
    persp_scene *scene;
    persp_framebuffer fb;
} frame;

static void frame_open(frame *f, const char *scene, int w, int h)
{
    f->ctx = test_context_threads(2);
    assert_int_equal(persp_scene_builtin(f->ctx, scene, &f->scene), PERSP_OK);
    f->fb.width = w;
    f->fb.height = h;
    f->fb.color = malloc((size_t)w * h * 4);
    f->fb.depth = malloc((size_t)w * h * sizeof(float));
    assert_non_null(f->fb.color);
    assert_non_null(f->fb.depth);
}

static void frame_close(frame *f)
{
    free(f->fb.color);
    free(f->fb.depth);
    persp_scene_destroy(f->scene);
    persp_context_destroy(f->ctx);
}

static uint8_t *render_copy(frame *f, const persp_render_desc *d)
{
    persp_status st = persp_render(f->ctx, f->scene, d, &f->fb, NULL);
    if (st != PERSP_OK) fail_msg("render: %s", persp_context_error(f->ctx));
    size_t n = (size_t)f->fb.width * f->fb.height * 4;
    uint8_t *copy = malloc(n);
    assert_non_null(copy);
    memcpy(copy, f->fb.color, n);
    return copy;
}

static void test_scene_camera_round_trip(void **state)
{
    (void)state;
    const char *scenes[] = {"corridor", "floor", "cube"};
    for (int i = 0; i < 3; i++) {
        frame f;
        frame_open(&f, scenes[i], 160, 100);
        persp_mat4 view, proj;
        persp_scene_get_camera(f.scene, f.fb.width, f.fb.height, &view, &proj);
        uint8_t *plain = render_copy(&f, NULL);
        persp_render_desc d;
        memset(&d, 0, sizeof d);
        d.view = &view;
        d.projection = &proj;
        uint8_t *same = render_copy(&f, &d);
        assert_memory_equal(plain, same, (size_t)f.fb.width * f.fb.height * 4);

        /* Turning the camera changes the image; only the view given keeps
         * the scene's projection. */
        persp_mat4 turned = persp_mat4_mul(persp_mat4_rotate(20.0f, 0, 1, 0), view);
        d.projection = NULL;
        d.view = &turned;
        uint8_t *other = render_copy(&f, &d);
        assert_true(memcmp(plain, other, (size_t)f.fb.width * f.fb.height * 4) != 0);
        free(plain);
        free(same);
        free(other);
        frame_close(&f);
    }
}

static void test_projection_only(void **state)
{
    (void)state;
    frame f;
    frame_open(&f, "cube", 120, 90);
    persp_mat4 proj;
    persp_scene_get_camera(f.scene, f.fb.width, f.fb.height, NULL, &proj);
    /* fovy = 2 atan(1 / P[1][1]) for a gluPerspective matrix (cube: 45°). */
    double fovy = 2.0 * atan(1.0 / proj.m[5]) * 180.0 / 3.14159265358979323846;
    assert_true(fabs(fovy - 45.0) < 1e-3);
    uint8_t *plain = render_copy(&f, NULL);
    persp_mat4 wide = persp_perspective(90.0, 120.0 / 90.0, 0.1, 100.0);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.projection = &wide;
    uint8_t *other = render_copy(&f, &d);
    assert_true(memcmp(plain, other, (size_t)120 * 90 * 4) != 0);
    free(plain);
    free(other);
    frame_close(&f);
}

static void test_bad_matrices(void **state)
{
    (void)state;
    frame f;
    frame_open(&f, "floor", 64, 48);
    persp_mat4 bad = persp_mat4_identity();
    bad.m[5] = NAN;
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.view = &bad;
    assert_int_equal(persp_render(f.ctx, f.scene, &d, &f.fb, NULL), PERSP_ERR_INVALID_ARGUMENT);
    d.view = NULL;
    bad.m[5] = INFINITY;
    d.projection = &bad;
    assert_int_equal(persp_render(f.ctx, f.scene, &d, &f.fb, NULL), PERSP_ERR_INVALID_ARGUMENT);
    /* NULL scene or empty size: refused, no crash. */
    persp_mat4 v, p;
    assert_int_equal(persp_scene_get_camera(NULL, 10, 10, &v, &p), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_scene_get_camera(f.scene, 0, 10, &v, &p), PERSP_ERR_INVALID_ARGUMENT);
    frame_close(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_camera_round_trip),
        cmocka_unit_test(test_projection_only),
        cmocka_unit_test(test_bad_matrices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
