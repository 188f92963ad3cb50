/* Texture-coordinate generation at known points (src/geom/texgen.c). */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI_ 3.14159265358979323846

static persp_vertex vert(float x, float y, float z, float nx, float ny, float nz)
{
    persp_vertex v;
    memset(&v, 0, sizeof v);
    v.pos[0] = x, v.pos[1] = y, v.pos[2] = z;
    v.normal[0] = nx, v.normal[1] = ny, v.normal[2] = nz;
    v.uv[0] = 0.125f, v.uv[1] = 0.875f;
    return v;
}

static persp_object object(persp_texgen mode, int axis)
{
    persp_object o;
    memset(&o, 0, sizeof o);
    o.texgen = mode;
    o.texgen_axis = axis;
    o.model = persp_mat4_identity();
    return o;
}

static void gen1(const persp_object *o, const persp_mat4 *mv, persp_vertex v, double *u, double *t)
{
    float uv[2];
    persp__texgen_apply(o, mv, &v, 1, uv);
    *u = uv[0], *t = uv[1];
}

#define NEAR(a, b) assert_true(fabs((a) - (b)) < 1e-5)

static void test_uv_and_planar(void **state)
{
    (void)state;
    double u, v;
    persp_object o = object(PERSP_TEXGEN_UV, 1);
    o.texgen_scale[0] = 7.0f; /* own coordinates are never scaled */
    gen1(&o, NULL, vert(1, 2, 3, 0, 0, 1), &u, &v);
    NEAR(u, 0.125), NEAR(v, 0.875);
    /* object-linear: u = P_s·(x, y, z, 1), v = P_t·(x, y, z, 1) */
    o = object(PERSP_TEXGEN_PLANAR, 1);
    const float s[4] = {1.0f, 0.0f, 0.0f, 0.5f}, t[4] = {0.0f, 0.25f, 2.0f, -1.0f};
    memcpy(o.texgen_s, s, sizeof s), memcpy(o.texgen_t, t, sizeof t);
    gen1(&o, NULL, vert(1, 2, 3, 0, 0, 1), &u, &v);
    NEAR(u, 1.0 * 1 + 0.5), NEAR(v, 0.25 * 2 + 2.0 * 3 - 1.0);
    o.texgen_scale[0] = 2.0f, o.texgen_scale[1] = 0.5f;
    gen1(&o, NULL, vert(1, 2, 3, 0, 0, 1), &u, &v);
    NEAR(u, 2.0 * 1.5), NEAR(v, 0.5 * 5.5);
}

static void test_cylindrical(void **state)
{
    (void)state;
    double u, v;
    persp_object o = object(PERSP_TEXGEN_CYLINDRICAL, 1);
    /* about +y: u = 1/2 + atan2(x, z)/(2π) (u = 1/2 facing +z), v = 1/2 + y/2 */
    gen1(&o, NULL, vert(0, 0.5f, 1, 0, 0, 1), &u, &v);
    NEAR(u, 0.5), NEAR(v, 0.75);
    gen1(&o, NULL, vert(3, -1, 0, 1, 0, 0), &u, &v);
    NEAR(u, 0.75), NEAR(v, 0.0);
    gen1(&o, NULL, vert(-1, 1, 0, -1, 0, 0), &u, &v);
    NEAR(u, 0.25), NEAR(v, 1.0);
    gen1(&o, NULL, vert(1, 0, 1, 0, 0, 1), &u, &v);
    NEAR(u, 0.5 + 0.125);
    /* the lecture's form about z: θ = tan⁻¹(y/x) */
    o = object(PERSP_TEXGEN_CYLINDRICAL, 2);
    gen1(&o, NULL, vert(0, 2, 0.5f, 0, 1, 0), &u, &v);
    NEAR(u, 0.5 + atan2(2.0, 0.0) / (2 * PI_)), NEAR(v, 0.75);
    /* about x through a centre */
    o = object(PERSP_TEXGEN_CYLINDRICAL, 0);
    o.texgen_center[0] = 5.0f, o.texgen_center[2] = 1.0f;
    gen1(&o, NULL, vert(5.5f, 0, 2, 0, 0, 1), &u, &v); /* d = (0.5, 0, 1): θ = atan2(z, y) */
    NEAR(u, 0.5 + atan2(1.0, 0.0) / (2 * PI_)), NEAR(v, 0.75);
}

static void test_spherical(void **state)
{
    (void)state;
    double u, v;
    persp_object o = object(PERSP_TEXGEN_SPHERICAL, 1);
    gen1(&o, NULL, vert(0, 2, 0, 0, 1, 0), &u, &v);
    NEAR(v, 1.0);
    gen1(&o, NULL, vert(0, -3, 0, 0, -1, 0), &u, &v);
    NEAR(v, 0.0);
    gen1(&o, NULL, vert(4, 0, 0, 1, 0, 0), &u, &v);
    NEAR(u, 0.75), NEAR(v, 0.5);
    /* φ = cos⁻¹(y/r) = 45° from the +y pole: v = 1 − 1/4 */
    gen1(&o, NULL, vert(0, 1, 1, 0, 0, 1), &u, &v);
    NEAR(u, 0.5), NEAR(v, 0.75);
    o.texgen_scale[0] = 4.0f;
    gen1(&o, NULL, vert(0, 1, 1, 0, 0, 1), &u, &v);
    NEAR(u, 2.0), NEAR(v, 0.75);
}

/* The generated map on the matching primitive reproduces the primitive's
 * own coordinates (away from seams and poles, where either value is right). */
static void test_matches_primitives(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh m;
    float *uv;
    assert_int_equal(persp__mesh_sphere(ctx, 16, 8, &m), PERSP_OK);
    uv = persp__calloc(ctx, 2 * m.vertex_count, sizeof *uv);
    persp_object o = object(PERSP_TEXGEN_SPHERICAL, 1);
    persp__texgen_apply(&o, NULL, m.vertices, m.vertex_count, uv);
    size_t checked = 0;
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        NEAR(uv[2 * i + 1], v->uv[1]);
        if (fabsf(v->pos[1]) < 0.99f && v->uv[0] > 0.0f && v->uv[0] < 1.0f) {
            NEAR(uv[2 * i], v->uv[0]);
            checked++;
        }
    }
    assert_true(checked >= 15 * 7);
    persp__free(ctx, uv);
    persp__mesh_free(ctx, &m);

    assert_int_equal(persp__mesh_cylinder(ctx, 12, &m), PERSP_OK);
    uv = persp__calloc(ctx, 2 * m.vertex_count, sizeof *uv);
    o = object(PERSP_TEXGEN_CYLINDRICAL, 1);
    persp__texgen_apply(&o, NULL, m.vertices, m.vertex_count, uv);
    checked = 0;
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        if (v->normal[1] != 0.0f || v->uv[0] <= 0.0f || v->uv[0] >= 1.0f) continue;
        NEAR(uv[2 * i], v->uv[0]), NEAR(uv[2 * i + 1], v->uv[1]);
        checked++;
    }
    assert_int_equal(checked, 2 * 11);
    persp__free(ctx, uv);
    persp__mesh_free(ctx, &m);

    assert_int_equal(persp__mesh_cube(ctx, &m), PERSP_OK);
    uv = persp__calloc(ctx, 2 * m.vertex_count, sizeof *uv);
    o = object(PERSP_TEXGEN_CUBE, 1);
    persp__texgen_apply(&o, NULL, m.vertices, m.vertex_count, uv);
    for (size_t i = 0; i < m.vertex_count; i++) NEAR(uv[2 * i], m.vertices[i].uv[0]), NEAR(uv[2 * i + 1], m.vertices[i].uv[1]);
    persp__free(ctx, uv);
    persp__mesh_free(ctx, &m);
    persp_context_destroy(ctx);
}

static void test_cube_faces(void **state)
{
    (void)state;
    double u, v;
    persp_object o = object(PERSP_TEXGEN_CUBE, 1);
    /* dominant normal +x: (a, b) = (−z, y) */
    gen1(&o, NULL, vert(1, 0.5f, -0.5f, 0.9f, 0.3f, 0.1f), &u, &v);
    NEAR(u, 0.75), NEAR(v, 0.75);
    /* dominant −y: (a, b) = (x, z) */
    gen1(&o, NULL, vert(0.2f, -1, 0.6f, 0.1f, -0.8f, 0.5f), &u, &v);
    NEAR(u, 0.6), NEAR(v, 0.8);
    /* zero normal: the position's dominant axis (−z: (a, b) = (−x, y)) */
    gen1(&o, NULL, vert(0.5f, 0.25f, -2, 0, 0, 0), &u, &v);
    NEAR(u, 0.25), NEAR(v, 0.625);
}

/* Sphere map (OpenGL 2.1 §2.12.4). For a point on the eye's −z axis, û =
 * (0, 0, −1) and r = û − 2(n·û)n gives m = 4 n_z, so (u, v) = (1 + n_x,
 * 1 + n_y)/2 for any eye-space unit normal with n_z > 0. */
static void test_reflection(void **state)
{
    (void)state;
    double u, v;
    persp_object o = object(PERSP_TEXGEN_REFLECTION, 1);
    persp_mat4 rot = persp_mat4_rotate(90.0f, 0, 1, 0);
    persp_mat4 mv = persp_mat4_mul(persp_mat4_translate(0, 0, -5), rot);
    const double ne[][3] = {{0, 0, 1}, {0.5, 0, 0.8660254037844386}, {-0.3, 0.4, 0.8660254037844386}};
    for (size_t k = 0; k < sizeof ne / sizeof ne[0]; k++) {
        /* object normal = Rᵀ n_e (the rotation is orthonormal) */
        double no[3];
        for (int r = 0; r < 3; r++) no[r] = rot.m[r * 4 + 0] * ne[k][0] + rot.m[r * 4 + 1] * ne[k][1] + rot.m[r * 4 + 2] * ne[k][2];
        gen1(&o, &mv, vert(0, 0, 0, (float)no[0], (float)no[1], (float)no[2]), &u, &v);
        NEAR(u, 0.5 + ne[k][0] / 2), NEAR(v, 0.5 + ne[k][1] / 2);
    }
    /* the view along the normal is independent of scale in the modelview */
    persp_mat4 mvs = persp_mat4_mul(mv, persp_mat4_scale(2, 3, 4));
    gen1(&o, &mvs, vert(0, 0, 0, -1, 0, 0), &u, &v);
    NEAR(u, 0.5), NEAR(v, 0.5);
}

/* Renders the scene text written to dir/s.json at 96x72; returns the colour
 * buffer (caller frees). */
static uint8_t *render_text(persp_context *ctx, const char *dir, const char *text, persp_scene **keep)
{
    char path[512];
    snprintf(path, sizeof path, "%s/s.json", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
    persp_scene *scene = NULL;
    if (persp_scene_load(ctx, path, &scene) != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    persp_framebuffer fb = test_framebuffer(96, 72);
    if (persp_render(ctx, scene, NULL, &fb, NULL) != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    free(fb.depth);
    if (keep)
        *keep = scene;
    else
        persp_scene_destroy(scene);
    return fb.color;
}

/* The renderer draws an object with its generated coordinates, in both
 * pipelines: the cube map on the cube gives the cube's own image (the same
 * coordinates, test_matches_primitives), twice the repeats another one,
 * and persp_scene_object_texcoords hands out what was drawn. */
static void test_render_applies_texgen(void **state)
{
    (void)state;
    char dir[256], png[512];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "texgen"), 0);
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 8, 8, &img), PERSP_OK);
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = (uint8_t)(((x ^ y) & 1) ? 230 : 20), p[1] = (uint8_t)(32 * x), p[2] = (uint8_t)(32 * y);
            p[3] = 255;
        }
    snprintf(png, sizeof png, "%s/t.png", dir);
    assert_int_equal(persp_image_write_png(ctx, png, &img), PERSP_OK);
    persp_image_free(ctx, &img);
    const char *head = "{\"camera\": {\"position\": [2.2, 1.8, 3.0], \"target\": [0, 0, 0]},"
                       " \"render\": {\"filter\": \"nearest\"}, \"materials\": {\"m\": {\"texture\": \"t.png\"}},"
                       " \"objects\": [{\"mesh\": \"cube\", \"material\": \"m\"%s}]}";
    const char *modes[3] = {"", ", \"texgen\": \"cube\"", ", \"texgen\": {\"mode\": \"cube\", \"scale\": 2}"};
    uint8_t *px[3];
    persp_scene *scene = NULL;
    for (int i = 0; i < 3; i++) {
        char text[1024];
        snprintf(text, sizeof text, head, modes[i]);
        px[i] = render_text(ctx, dir, text, i == 2 ? &scene : NULL);
    }
    const size_t bytes = (size_t)96 * 72 * 4;
    assert_memory_equal(px[0], px[1], bytes);
    assert_memory_not_equal(px[1], px[2], bytes);
    persp_scene_object so;
    assert_int_equal(persp_scene_get_object(scene, 0, &so), PERSP_OK);
    float *uv = malloc(so.vertex_count * 2 * sizeof *uv);
    assert_non_null(uv);
    const persp_mat4 id = persp_mat4_identity();
    assert_int_equal(persp_scene_object_texcoords(scene, 0, &id, uv), PERSP_OK);
    for (size_t k = 0; k < so.vertex_count; k++)
        NEAR(uv[2 * k], 2.0 * so.vertices[k].uv[0]), NEAR(uv[2 * k + 1], 2.0 * so.vertices[k].uv[1]);
    assert_int_equal(persp_scene_object_texcoords(scene, 1, &id, uv), PERSP_ERR_NOT_FOUND);
    free(uv);
    persp_scene_destroy(scene);
    for (int i = 0; i < 3; i++) free(px[i]);
    char path[512];
    snprintf(path, sizeof path, "%s/s.json", dir);
    assert_int_equal(remove(path), 0);
    assert_int_equal(remove(png), 0);
    assert_int_equal(test_tmpdir_remove(dir), 0);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uv_and_planar), cmocka_unit_test(test_cylindrical),
        cmocka_unit_test(test_spherical),     cmocka_unit_test(test_matches_primitives),
        cmocka_unit_test(test_cube_faces),    cmocka_unit_test(test_reflection),
        cmocka_unit_test(test_render_applies_texgen),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
