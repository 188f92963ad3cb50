/* The shared part of `persp view` (tools/persp/view_core.c, compiled into
 * this test): the scene camera decomposed into position, yaw, pitch and
 * frustum gives back the scene's matrices; camera paths survive a save and
 * load and interpolate between keys; the composed layouts. */
/* ctest-labels: threads (renders with several worker threads) */
#include "support.h"

#include "../../tools/persp/view_core.c"

#include <stdio.h>
#include <unistd.h>

static double mat_diff(persp_mat4 a, persp_mat4 b)
{
    double d = 0.0;
    for (int i = 0; i < 16; i++)
        d = fmax(d, fabs((double)a.m[i] - (double)b.m[i]));
    return d;
}

static void test_camera_from_scene(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    for (size_t k = 0; k < persp_builtin_scene_count() + 1; k++) {
        persp_scene *s = NULL;
        if (k < persp_builtin_scene_count()) {
            assert_int_equal(persp_scene_builtin(ctx, persp_builtin_scene_name(k), &s), PERSP_OK);
        } else {
            char path[4096];
            test_source_path(path, sizeof path, "scenes/room.json");
            assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_OK);
        }
        view_camera c;
        view_camera_from_scene(&c, s, 640, 480);
        assert_int_equal(c.scene_own, 1);
        persp_mat4 v0, p0, v1, p1;
        persp_scene_get_camera(s, 640, 480, &v0, &p0);
        view_camera_matrices(&c, 640, 480, &v1, &p1);
        assert_true(mat_diff(v0, v1) < 1e-5);
        assert_true(mat_diff(p0, p1) < 1e-5);
        persp_scene_destroy(s);
    }
    persp_context_destroy(ctx);
}

static void test_camera_moves(void **state)
{
    (void)state;
    view_camera c;
    memset(&c, 0, sizeof c);
    c.fovy = 60, c.znear = 0.1, c.zfar = 100;
    view_camera_set_orbit(&c, 5.0);
    /* yaw 0 looks down -z: forward moves to -z, right to +x. */
    view_camera_move(&c, 2.0, 1.0, 0.5);
    assert_true(fabs(c.eye[0] - 1.0) < 1e-12 && fabs(c.eye[1] - 0.5) < 1e-12 &&
                fabs(c.eye[2] + 2.0) < 1e-12);
    assert_int_equal(c.scene_own, 0);
    /* Orbit keeps the distance to the target. */
    double t[3] = {c.orbit_target[0], c.orbit_target[1], c.orbit_target[2]};
    view_camera_turn(&c, 90.0, 30.0, 1);
    double d = sqrt(pow(c.eye[0] - t[0], 2) + pow(c.eye[1] - t[1], 2) + pow(c.eye[2] - t[2], 2));
    assert_true(fabs(d - 5.0) < 1e-9);
    view_camera_turn(&c, 0.0, 500.0, 0);
    assert_true(c.pitch <= 89.0);
}

static void test_path_round_trip(void **state)
{
    (void)state;
    view_path p;
    memset(&p, 0, sizeof p);
    view_camera c;
    memset(&c, 0, sizeof c);
    c.fovy = 50, c.znear = 0.2, c.zfar = 40;
    assert_true(view_path_add(&p, 0.0, &c));
    c.eye[0] = 2.0, c.yaw = 40.0, c.pitch = -10.0, c.fovy = 70.0;
    assert_true(view_path_add(&p, 2.0, &c));
    char path[] = "/tmp/persp_view_pathXXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    char err[256];
    assert_true(view_path_save(path, &p, err, sizeof err));
    view_path q;
    assert_true(view_path_load(path, &q, err, sizeof err));
    remove(path);
    /* A file that is not there: named, without a line and column. */
    view_path gone;
    assert_false(view_path_load(path, &gone, err, sizeof err));
    assert_non_null(strstr(err, path));
    assert_null(strstr(err, ":-1"));
    assert_int_equal(q.count, 2);
    view_camera m;
    view_path_sample(&q, 1.0, &m);
    assert_true(fabs(m.eye[0] - 1.0) < 1e-6 && fabs(m.yaw - 20.0) < 1e-6 &&
                fabs(m.pitch + 5.0) < 1e-6 && fabs(m.fovy - 60.0) < 1e-6);
    view_path_sample(&q, 99.0, &m); /* clamped at the ends */
    assert_true(fabs(m.eye[0] - 2.0) < 1e-6);
    view_path_sample(&q, -1.0, &m);
    assert_true(fabs(m.eye[0]) < 1e-6);
    view_path_free(&p);
    view_path_free(&q);
}

static void test_layouts(void **state)
{
    (void)state;
    persp_context *ctx = test_context_threads(2);
    persp_scene *s = NULL, *coords = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &s), PERSP_OK);
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &coords), PERSP_OK);
    persp_image ci;
    assert_int_equal(view_coord_image(ctx, &ci), PERSP_OK);
    assert_int_equal(persp_scene_set_texture(coords, &ci), PERSP_OK);
    persp_image_free(ctx, &ci);
    view_scenes sc = {s, NULL, NULL};
    view_camera cam;
    view_camera_from_scene(&cam, s, 96, 64);
    view_settings l, r;
    memset(&l, 0, sizeof l);
    memset(&r, 0, sizeof r);
    snprintf(l.method, sizeof l.method, "affine");
    snprintf(r.method, sizeof r.method, "exact");
    view_frame f;
    memset(&f, 0, sizeof f);
    assert_int_equal(view_frame_resize(&f, 96, 64), PERSP_OK);
    /* Split: left of the divider from the left side, right of it from the right. */
    assert_int_equal(view_frame_render(ctx, &sc, &cam, &l, &r, VIEW_LAYOUT_SPLIT, 0.25, 16, 1, &f),
                     PERSP_OK);
    for (int y = 0; y < 64; y++) {
        size_t row = (size_t)y * 96 * 4;
        assert_memory_equal(f.out + row, f.left + row, 24 * 4);
        assert_memory_equal(f.out + row + 24 * 4, f.right + row + 24 * 4, 72 * 4);
    }
    assert_true(f.err.max > 0 && f.err.share_diff > 0.0);
    /* The texel layout needs the coordinate scene. */
    assert_int_equal(view_frame_render(ctx, &sc, &cam, &l, &r, VIEW_LAYOUT_TEXEL, 0.5, 4, 1, &f),
                     PERSP_ERR_UNAVAILABLE);
    sc.coords = coords;
    assert_int_equal(view_frame_render(ctx, &sc, &cam, &r, &r, VIEW_LAYOUT_TEXEL, 0.5, 4, 1, &f),
                     PERSP_OK);
    assert_true(f.err.texel_max == 0.0 && f.err.share_diff == 0.0);
    assert_int_equal(view_frame_render(ctx, &sc, &cam, &l, &r, VIEW_LAYOUT_TEXEL, 0.5, 4, 1, &f),
                     PERSP_OK);
    assert_true(f.err.texel_max >= 1.0);
    view_frame_free(&f);
    persp_scene_destroy(coords);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

static void test_heat_colors(void **state)
{
    (void)state;
    uint8_t c[3];
    view_heat_color(0.0, 16.0, c);
    assert_true(c[0] == 0 && c[1] == 0 && c[2] == 0);
    view_heat_color(16.0, 16.0, c);
    assert_true(c[0] == 255 && c[1] == 0 && c[2] == 0);
    view_heat_color(1000.0, 16.0, c);
    assert_true(c[0] == 255 && c[1] == 0 && c[2] == 0);
    view_heat_color(1.0, 16.0, c);
    assert_true(c[2] > 0 && c[0] == 0); /* the smallest error is already visible */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_camera_from_scene), cmocka_unit_test(test_camera_moves),
        cmocka_unit_test(test_path_round_trip),   cmocka_unit_test(test_layouts),
        cmocka_unit_test(test_heat_colors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
