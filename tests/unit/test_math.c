/* Matrices against the formulas of the OpenGL 2.1 spec / GLU 1.3, evaluated
 * independently in double here. */
#include "support.h"

#include <math.h>

static double el(const persp_mat4 *m, int r, int c) { return m->m[c * 4 + r]; }

static void test_frustum_matches_glFrustum(void **state)
{
    (void)state;
    double l = -0.3, r = 0.5, b = -0.2, t = 0.25, n = 0.1, f = 100.0;
    persp_mat4 m = persp_frustum(l, r, b, t, n, f);
    double want[4][4] = {{2 * n / (r - l), 0, (r + l) / (r - l), 0},
                         {0, 2 * n / (t - b), (t + b) / (t - b), 0},
                         {0, 0, -(f + n) / (f - n), -2 * f * n / (f - n)},
                         {0, 0, -1, 0}};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) assert_true(fabs(el(&m, i, j) - want[i][j]) < 1e-5 * (1 + fabs(want[i][j])));
}

static void test_perspective_is_frustum(void **state)
{
    (void)state;
    double a = 4.0 / 3.0, tt = 0.1 * tan(30.0 * 3.14159265358979323846 / 180.0);
    persp_mat4 p = persp_perspective(60.0, a, 0.1, 100.0);
    persp_mat4 f = persp_frustum(-tt * a, tt * a, -tt, tt, 0.1, 100.0);
    for (int i = 0; i < 16; i++) assert_true(fabs(p.m[i] - f.m[i]) <= 1e-6 * (1 + fabs(f.m[i])));
}

static void test_look_at_default_is_identity(void **state)
{
    (void)state;
    persp_mat4 v = persp_look_at((persp_vec3){0, 0, 0}, (persp_vec3){0, 0, -1}, (persp_vec3){0, 1, 0});
    persp_mat4 id = persp_mat4_identity();
    for (int i = 0; i < 16; i++) assert_true(v.m[i] == id.m[i]);
}

static void test_look_at_maps_eye_and_target(void **state)
{
    (void)state;
    persp_vec3 eye = {3, 2, 5}, target = {-1, 0.5f, 0};
    persp_mat4 v = persp_look_at(eye, target, (persp_vec3){0, 1, 0});
    persp_vec4 e = persp_mat4_apply(v, (persp_vec4){eye.x, eye.y, eye.z, 1});
    assert_true(fabs(e.x) < 1e-5 && fabs(e.y) < 1e-5 && fabs(e.z) < 1e-5);
    persp_vec4 t = persp_mat4_apply(v, (persp_vec4){target.x, target.y, target.z, 1});
    double d = sqrt(16.0 + 2.25 + 25.0);
    assert_true(fabs(t.x) < 1e-5 && fabs(t.y) < 1e-5 && fabs(t.z + d) < 1e-4);
}

static void test_rotate_and_mul(void **state)
{
    (void)state;
    persp_mat4 r = persp_mat4_rotate(90.0f, 0, 0, 1);
    persp_vec4 p = persp_mat4_apply(r, (persp_vec4){1, 0, 0, 1});
    assert_true(fabs(p.x) < 1e-6 && fabs(p.y - 1) < 1e-6);
    persp_mat4 tr = persp_mat4_mul(persp_mat4_translate(1, 2, 3), persp_mat4_scale(2, 2, 2));
    persp_vec4 q = persp_mat4_apply(tr, (persp_vec4){1, 1, 1, 1});
    assert_true(q.x == 3 && q.y == 4 && q.z == 5 && q.w == 1);
}

static void test_normal_matrix(void **state)
{
    (void)state;
    float n[9];
    assert_int_equal(persp_mat4_normal_matrix(persp_mat4_scale(2, 4, 8), n), 1);
    assert_true(fabs(n[0] - 0.5) < 1e-6 && fabs(n[4] - 0.25) < 1e-6 && fabs(n[8] - 0.125) < 1e-6);
    assert_int_equal(persp_mat4_normal_matrix(persp_mat4_scale(0, 1, 1), n), 0);
}

/* The determinant of the linear part decides a mirrored object's winding:
 * the product of the scales, unchanged by rotation and translation. */
static void test_det3(void **state)
{
    (void)state;
    const persp_mat4 rt = persp_mat4_mul(persp_mat4_translate(5, -2, 7), persp_mat4_rotate(40, 1, 2, 3));
    assert_true(fabs(persp_mat4_det3(persp_mat4_scale(2, 4, 8)) - 64.0) < 1e-9);
    assert_true(fabs(persp_mat4_det3(persp_mat4_mul(rt, persp_mat4_scale(-1, 2, 3))) + 6.0) < 1e-5);
    assert_true(persp_mat4_det3(persp_mat4_mul(rt, persp_mat4_scale(-1, -1, 1))) > 0.0);
    assert_true(fabs(persp_mat4_det3(persp_mat4_translate(1, 2, 3)) - 1.0) < 1e-12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frustum_matches_glFrustum), cmocka_unit_test(test_perspective_is_frustum),
        cmocka_unit_test(test_look_at_default_is_identity), cmocka_unit_test(test_look_at_maps_eye_and_target),
        cmocka_unit_test(test_rotate_and_mul), cmocka_unit_test(test_normal_matrix), cmocka_unit_test(test_det3),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
