/* What exporters write that a model's format does not mean literally:
 * Blender's "//" paths (relative to the .blend file) and colour channels
 * that hold nothing (every colour zero or negative: old Blender, AMF); and
 * refusals that name their real cause. */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char tmpdir[64];

static void write_file(const char *name, const void *data, size_t size) { test_write_file(tmpdir, name, data, size); }

static void write_text(const char *name, const char *text) { write_file(name, text, strlen(text)); }

static persp_scene *load(persp_context *ctx, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    persp_scene *s = NULL;
    if (persp_scene_load(ctx, path, &s) != PERSP_OK) fail_msg("%s: %s", name, persp_context_error(ctx));
    return s;
}

/* A PLY triangle whose colours are c (the same at each corner). */
static void ply_coloured(const char *name, const char *type, const char *c)
{
    char text[1024];
    snprintf(text, sizeof text,
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "property %s red\nproperty %s green\nproperty %s blue\nelement face 1\n"
             "property list uchar int vertex_indices\nend_header\n0 0 0 %s\n1 0 0 %s\n0 1 0 %s\n3 0 1 2\n",
             type, type, type, c, c, c);
    write_text(name, text);
}

static void test_junk_colours_dropped(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    ply_coloured("black.ply", "uchar", "0 0 0");
    ply_coloured("minus.ply", "float", "-1 -1 -1");
    ply_coloured("red.ply", "uchar", "255 0 0");
    static const char *const names[] = {"black.ply", "minus.ply", "red.ply"};
    static const float want[3][3] = {{1, 1, 1}, {1, 1, 1}, {1, 0, 0}};
    for (int i = 0; i < 3; i++) {
        persp_scene *s = load(ctx, names[i]);
        const persp_mesh *m = &s->meshes[0];
        for (size_t v = 0; v < m->vertex_count; v++)
            for (int k = 0; k < 3; k++)
                if (m->vertices[v].color[k] != want[i][k])
                    fail_msg("%s vertex %zu: colour %g %g %g", names[i], v, (double)m->vertices[v].color[0],
                             (double)m->vertices[v].color[1], (double)m->vertices[v].color[2]);
        persp_scene_destroy(s);
    }
    persp_context_destroy(ctx);
}

static void count_warning(void *user, const char *message)
{
    (void)message;
    ++*(int *)user;
}

static void keep_warning(void *user, const char *message)
{
    snprintf((char *)user, 1024, "%s", message);
}

/* "//textures/tex.png" in a material library: the file in the model's
 * folder's textures/, found without a warning (by its last part alone it
 * would be looked for beside the model, where it is not). */
static void test_blender_relative_paths(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    int warned = 0;
    persp_context_set_warning_handler(ctx, count_warning, &warned);
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 2, 2, &img), PERSP_OK);
    memset(img.pixels, 200, (size_t)img.stride * 2);
    char path[1024];
    snprintf(path, sizeof path, "%s/textures", tmpdir);
    assert_int_equal(mkdir(path, 0700), 0);
    snprintf(path, sizeof path, "%s/textures/tex.png", tmpdir);
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_OK);
    persp_image_free(ctx, &img);
    write_text("b.mtl", "newmtl m\nmap_Kd //textures/tex.png\n");
    write_text("b.obj", "mtllib b.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    persp_scene *s = load(ctx, "b.obj");
    assert_int_equal(s->texture_count, 1);
    assert_int_equal(warned, 0);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

/* Refusals that name the real cause: a text model saved in UTF-16, and a
 * glTF requiring an extension its reader cannot read (both were refused
 * as "zero area"). */
static void test_causes_named(void **state)
{
    (void)state;
    static const char dae[] = "<?xml version=\"1.0\"?><COLLADA version=\"1.4.1\"></COLLADA>";
    char wide[2 + 2 * sizeof dae];
    wide[0] = '\xff', wide[1] = '\xfe';
    for (size_t i = 0; i < sizeof dae - 1; i++) wide[2 + 2 * i] = dae[i], wide[3 + 2 * i] = 0;
    write_file("wide.dae", wide, 2 + 2 * (sizeof dae - 1));
    write_text("tech.gltf", "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_technique_webgl\"],"
                            "\"extensionsRequired\":[\"KHR_technique_webgl\"],\"scenes\":[{\"nodes\":[]}]}");
    write_text("quant.gltf", "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_mesh_quantization\"],"
                             "\"extensionsRequired\":[\"KHR_mesh_quantization\"],\"scenes\":[{\"nodes\":[]}]}");
    static const struct {
        const char *name, *detail;
        persp_status st;
    } cases[] = {
        {"wide.dae", "wide.dae: a model file in UTF-16 or UTF-32", PERSP_ERR_FORMAT},
        {"quant.gltf", "quant.gltf: the file requires the glTF extension KHR_mesh_quantization",
         PERSP_ERR_UNSUPPORTED},
        {"tech.gltf", "tech.gltf: the file requires the glTF extension KHR_technique_webgl",
         PERSP_ERR_UNSUPPORTED},
        /* A file named for one format holding another: the content named,
         * also for OBJ, whose reader would find no faces in it. */
        {"glb.obj", "glb.obj: the content is not that of an OBJ file (it looks like binary glTF: rename it .glb)",
         PERSP_ERR_FORMAT},
        {"ply.stl", "ply.stl: the content is not that of an STL file (it looks like PLY: rename it .ply)",
         PERSP_ERR_FORMAT},
    };
    char glb[1024];
    test_source_path(glb, sizeof glb, "tests/data/models/embedded.glb");
    FILE *gf = fopen(glb, "rb");
    assert_non_null(gf);
    static char bytes[1 << 16];
    const size_t nb = fread(bytes, 1, sizeof bytes, gf);
    fclose(gf);
    write_file("glb.obj", bytes, nb);
    write_text("ply.stl", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    /* A texture that is there but no image persp reads: said so, not
     * reported missing "beside the model" as well. */
    char path[1024], warning[1024] = "";
    snprintf(path, sizeof path, "%s/img", tmpdir);
    assert_int_equal(mkdir(path, 0700), 0);
    write_file("img/t.webp", "RIFF\x1a\0\0\0WEBPVP8 ", 16);
    write_text("g.mtl", "newmtl m\nmap_Kd img/t.webp\n");
    write_text("g.obj", "mtllib g.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n");
    persp_context *wctx = test_context();
    persp_context_set_warning_handler(wctx, keep_warning, warning);
    persp_scene *g = load(wctx, "g.obj");
    if (!strstr(warning, "not an image persp reads") || strstr(warning, "beside the model"))
        fail_msg("warning '%s'", warning);
    persp_scene_destroy(g);
    persp_context_destroy(wctx);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        persp_context *ctx = test_context();
        snprintf(path, sizeof path, "%s/%s", tmpdir, cases[i].name);
        persp_scene *s = NULL;
        persp_status st = persp_scene_load(ctx, path, &s);
        if (st != cases[i].st || !strstr(persp_context_error(ctx), cases[i].detail))
            fail_msg("%s: status %d, '%s'", cases[i].name, (int)st, persp_context_error(ctx));
        persp_context_destroy(ctx);
    }
}

/* --up AXIS: the named axis of the file becomes +y, by a turn (no
 * mirror): a triangle spanning the file's +A axis from the origin stands
 * up along +y after the turn, for each of the six axes. */
static void test_up_axes(void **state)
{
    (void)state;
    static const struct {
        persp_model_up up;
        float dir[3];
    } axes[] = {{PERSP_MODEL_UP_Y, {0, 1, 0}},  {PERSP_MODEL_UP_Z, {0, 0, 1}},     {PERSP_MODEL_UP_X, {1, 0, 0}},
                {PERSP_MODEL_UP_NEG_X, {-1, 0, 0}}, {PERSP_MODEL_UP_NEG_Y, {0, -1, 0}}, {PERSP_MODEL_UP_NEG_Z, {0, 0, -1}}};
    for (size_t a = 0; a < sizeof axes / sizeof axes[0]; a++) {
        const float *d = axes[a].dir;
        /* a second, sideways vertex off the axis keeps the triangle's area */
        const float side[3] = {d[0] == 0 ? 1.0f : 0.0f, 0.0f, d[0] == 0 ? 0.0f : 1.0f};
        char text[256];
        snprintf(text, sizeof text, "v 0 0 0\nv %g %g %g\nv %g %g %g\nf 1 2 3\n", (double)d[0], (double)d[1],
                 (double)d[2], (double)(0.1f * side[0]), (double)(0.1f * side[1]), (double)(0.1f * side[2]));
        write_text("pole.obj", text);
        persp_context *ctx = test_context();
        char path[1024];
        snprintf(path, sizeof path, "%s/pole.obj", tmpdir);
        persp_scene_load_desc desc = {.model_up = axes[a].up};
        persp_scene *s = NULL;
        assert_int_equal(persp_scene_load_ex(ctx, path, &desc, &s), PERSP_OK);
        persp_vec4 tip = persp_mat4_apply(s->objects[0].model, (persp_vec4){d[0], d[1], d[2], 1.0f});
        if (!(tip.x == 0.0f && tip.y == 1.0f && tip.z == 0.0f))
            fail_msg("up %d: the axis went to (%g %g %g)", (int)axes[a].up, (double)tip.x, (double)tip.y,
                     (double)tip.z);
        assert_true(persp_mat4_det3(s->objects[0].model) > 0.0f);
        persp_scene_destroy(s);
        persp_context_destroy(ctx);
    }
}

static int setup(void **state)
{
    (void)state;
    return test_tmpdir_make(tmpdir, sizeof tmpdir, "conventions");
}

static int teardown(void **state)
{
    (void)state;
    return test_tmpdir_remove(tmpdir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_junk_colours_dropped),
        cmocka_unit_test(test_blender_relative_paths),
        cmocka_unit_test(test_causes_named),
        cmocka_unit_test(test_up_axes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
