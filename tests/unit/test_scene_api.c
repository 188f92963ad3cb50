/* The read-only scene API (persp_scene_get_object / _light / _texture /
 * _camera, the extra fields of persp_scene_info) and the `soup` primitive:
 * reproducible, the requested count and sizes, front faces towards +z, and
 * its JSON parameters checked. */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "model/model.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static persp_status load(persp_context *ctx, const char *text, persp_scene **out)
{
    return persp__scene_load_memory(ctx, text, strlen(text), "s.json", NULL, 0, out);
}

static const char *scene_text =
    "{\"camera\": {\"position\": [0, 0, 5], \"target\": [0, 0, 0], \"fov\": 45, \"near\": 0.5, \"far\": 50},\n"
    " \"render\": {\"size\": [64, 32], \"clear\": [1, 0.5, 0], \"cull\": true},\n"
    " \"ambient\": [0.3, 0.2, 0.1],\n"
    " \"lights\": [{\"type\": \"point\", \"position\": [0, 5, 0], \"color\": [1, 0.5, 0.25],\n"
    "              \"attenuation\": [1, 0.1, 0.01]},\n"
    "             {\"type\": \"directional\", \"direction\": [0, -3, -4]}],\n"
    " \"materials\": {\"red\": {\"ambient\": [0.1, 0, 0], \"diffuse\": [1, 0, 0], \"specular\": [0.5, 0.5, 0.5],\n"
    "                         \"shininess\": 20, \"env\": \"modulate\"}},\n"
    " \"objects\": [{\"mesh\": \"cube\", \"material\": \"red\", \"transform\": {\"translate\": [1, 2, 3]}},\n"
    "             {\"mesh\": {\"primitive\": \"soup\", \"count\": 10, \"seed\": 7, \"size\": [0.1, 0.2]}}]}\n";

static void test_scene_views(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *s = NULL;
    assert_int_equal(load(ctx, scene_text, &s), PERSP_OK);

    persp_scene_info info;
    persp_scene_get_info(s, &info);
    assert_int_equal(info.cull_backfaces, 1);
    assert_int_equal(info.clear[0], 255);
    assert_int_equal(info.clear[1], 128);
    assert_int_equal(info.clear[2], 0);
    assert_true(fabsf(info.ambient[0] - 0.3f) < 1e-6f && fabsf(info.ambient[2] - 0.1f) < 1e-6f);

    assert_int_equal(persp_scene_object_count(s), 2);
    persp_scene_object o;
    assert_int_equal(persp_scene_get_object(s, 0, &o), PERSP_OK);
    assert_int_equal(o.vertex_count, 24);
    assert_int_equal(o.index_count, 36);
    assert_non_null(o.vertices);
    assert_non_null(o.indices);
    assert_true(o.model.m[12] == 1.0f && o.model.m[13] == 2.0f && o.model.m[14] == 3.0f);
    assert_true(o.material.diffuse[0] == 1.0f && o.material.diffuse[1] == 0.0f);
    assert_true(o.material.specular[2] == 0.5f && o.material.shininess == 20.0f);
    assert_int_equal(o.material.env, PERSP_SCENE_TEXENV_MODULATE);
    assert_int_equal(o.material.texture, -1);
    assert_int_equal(o.material.specular_texture, 0);
    assert_int_equal(persp_scene_get_object(s, 1, &o), PERSP_OK);
    assert_int_equal(o.vertex_count, 30);
    assert_int_equal(o.material.env, PERSP_SCENE_TEXENV_REPLACE);
    assert_int_equal(persp_scene_get_object(s, 2, &o), PERSP_ERR_NOT_FOUND);
    assert_int_equal(persp_scene_get_object(NULL, 0, &o), PERSP_ERR_INVALID_ARGUMENT);

    assert_int_equal(persp_scene_light_count(s), 2);
    persp_scene_light l;
    assert_int_equal(persp_scene_get_light(s, 0, &l), PERSP_OK);
    assert_int_equal(l.directional, 0);
    assert_true(l.position[1] == 5.0f && l.color[1] == 0.5f && l.attenuation[2] == 0.01f);
    assert_int_equal(persp_scene_get_light(s, 1, &l), PERSP_OK);
    assert_int_equal(l.directional, 1);
    /* Towards the light: the opposite of the file's travel direction, unit. */
    assert_true(fabsf(l.position[1] - 0.6f) < 1e-6f && fabsf(l.position[2] - 0.8f) < 1e-6f);
    assert_int_equal(persp_scene_get_light(s, 2, &l), PERSP_ERR_NOT_FOUND);
    assert_null(persp_scene_get_texture(s, 0));

    persp_mat4 proj, view;
    assert_int_equal(persp_scene_get_camera(s, 64, 32, &view, &proj), PERSP_OK);
    persp_mat4 want = persp_perspective(45.0, 2.0, 0.5, 50.0);
    for (int i = 0; i < 16; i++) assert_true(proj.m[i] == want.m[i]);
    assert_true(view.m[14] == -5.0f);
    assert_int_equal(persp_scene_get_camera(s, 0, 32, &view, &proj), PERSP_ERR_INVALID_ARGUMENT);
    persp_scene_destroy(s);

    /* A built-in scene's texture and its mip levels. */
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &s), PERSP_OK);
    assert_int_equal(persp_scene_get_object(s, 0, &o), PERSP_OK);
    const persp_texture *t = persp_scene_get_texture(s, o.material.texture);
    assert_non_null(t);
    persp_image_view v;
    assert_int_equal(persp_texture_level(t, persp_texture_levels(t) - 1, &v), PERSP_OK);
    assert_int_equal(v.width, 1);
    assert_int_equal(persp_scene_get_camera(s, 1024, 768, &view, &proj), PERSP_OK);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

static void test_soup(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh a, b, c;
    assert_int_equal(persp__mesh_soup(ctx, 500, 42, 0.1f, 0.3f, &a), PERSP_OK);
    assert_int_equal(persp__mesh_soup(ctx, 500, 42, 0.1f, 0.3f, &b), PERSP_OK);
    assert_int_equal(persp__mesh_soup(ctx, 500, 43, 0.1f, 0.3f, &c), PERSP_OK);
    assert_int_equal(a.vertex_count, 1500);
    assert_int_equal(a.index_count, 1500);
    assert_memory_equal(a.vertices, b.vertices, a.vertex_count * sizeof *a.vertices);
    assert_true(memcmp(a.vertices, c.vertices, a.vertex_count * sizeof *a.vertices) != 0);
    double lo = 1e9, hi = 0.0;
    for (size_t t = 0; t < a.index_count; t += 3) {
        const float *p[3];
        for (int k = 0; k < 3; k++) p[k] = a.vertices[a.indices[t + (size_t)k]].pos;
        double e1[3], e2[3], n[3];
        for (int i = 0; i < 3; i++) e1[i] = (double)p[1][i] - p[0][i], e2[i] = (double)p[2][i] - p[0][i];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double side = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        lo = fmin(lo, side), hi = fmax(hi, side);
        /* Counter-clockwise seen from +z, within 45° of facing it, with the
         * face normal as every vertex normal. */
        assert_true(n[2] / len >= cos(3.14159265358979 / 4.0) - 1e-6);
        const float *vn = a.vertices[a.indices[t]].normal;
        assert_true(fabs(vn[0] - n[0] / len) < 1e-5 && fabs(vn[2] - n[2] / len) < 1e-5);
        /* Equilateral. */
        double e3 = sqrt(pow((double)p[2][0] - p[1][0], 2) + pow((double)p[2][1] - p[1][1], 2) +
                         pow((double)p[2][2] - p[1][2], 2));
        assert_true(fabs(e3 - side) < 1e-5);
    }
    assert_true(lo >= 0.1 - 1e-6 && hi <= 0.3 + 1e-6 && hi - lo > 0.15);
    persp__mesh_free(ctx, &a);
    persp__mesh_free(ctx, &b);
    persp__mesh_free(ctx, &c);
    assert_int_equal(persp__mesh_soup(ctx, 0, 1, 0.1f, 0.2f, &a), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__mesh_soup(ctx, 10, 1, 0.3f, 0.2f, &a), PERSP_ERR_INVALID_ARGUMENT);

    /* JSON parameters: checked, and errors point at them. */
    static const struct {
        const char *mesh;
        persp_status want;
        const char *detail;
    } cases[] = {
        {"{\"primitive\": \"soup\"}", PERSP_OK, NULL},
        {"{\"primitive\": \"soup\", \"count\": 0}", PERSP_ERR_FORMAT, "count"},
        {"{\"primitive\": \"soup\", \"size\": [0.3, 0.1]}", PERSP_ERR_FORMAT, "min <= max"},
        {"{\"primitive\": \"soup\", \"size\": [0, 0.1]}", PERSP_ERR_FORMAT, "size"},
        {"{\"primitive\": \"soup\", \"seed\": -1}", PERSP_ERR_FORMAT, "seed"},
        {"{\"primitive\": \"soup\", \"slices\": 3}", PERSP_ERR_FORMAT, "slices"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[512];
        snprintf(text, sizeof text, "{\"objects\": [{\"mesh\": %s}]}", cases[i].mesh);
        persp_scene *s = NULL;
        persp_status st = load(ctx, text, &s);
        if (st != cases[i].want) print_error("case %zu: %s: %s\n", i, cases[i].mesh, persp_context_error(ctx));
        assert_int_equal(st, cases[i].want);
        if (cases[i].detail) assert_non_null(strstr(persp_context_error(ctx), cases[i].detail));
        if (st == PERSP_OK) {
            persp_scene_object o;
            assert_int_equal(persp_scene_get_object(s, 0, &o), PERSP_OK);
            assert_int_equal(o.vertex_count, 3000);
        }
        persp_scene_destroy(s);
    }
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_scene_views), cmocka_unit_test(test_soup)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
