/* Materials as glTF defines them: KHR_texture_transform applied to the
 * coordinates (offset, rotation, scale; the extension's README), emissive
 * colour and emissive map (glTF 2.0 §3.9.2 "emissive"), and
 * KHR_materials_unlit (base colour × texture, no lighting); each in a
 * small glTF written here, loaded through persp_scene_load or the model
 * loader and, where it shows, rendered. */
#include "model_load.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char tmpdir[64];

static void write_file(const char *name, const void *data, size_t size) { test_write_file(tmpdir, name, data, size); }

static void tmp_path(char *out, size_t size, const char *name) { snprintf(out, size, "%s/%s", tmpdir, name); }

/* A 4×4 image whose texels all differ (seed varies the colours). */
static void write_png(persp_context *ctx, const char *name, int seed)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 4, 4, &img), PERSP_OK);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = (uint8_t)(60 + x * 60), p[1] = (uint8_t)(60 + y * 60), p[2] = (uint8_t)(seed * 100 + 20),
            p[3] = 255;
        }
    char path[1024];
    tmp_path(path, sizeof path, name);
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_OK);
    persp_image_free(ctx, &img);
}

/* quad.bin: a square in z = 0 facing +z (positions, normals, glTF
 * coordinates with v down, two triangles). */
static void write_quad_buffer(const char *name)
{
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    unsigned char buf[140];
    memcpy(buf, pos, 48);
    memcpy(buf + 48, nrm, 48);
    memcpy(buf + 96, uv, 32);
    memcpy(buf + 128, idx, 12);
    write_file(name, buf, sizeof buf);
}

/* name: the quad with material (a JSON object) and the textures
 * "tex.png" (0) and "glow.png" (1); extensions: the extensionsUsed list. */
static void write_gltf_uri(const char *name, const char *extensions, const char *material, const char *uri);

static void write_gltf(const char *name, const char *extensions, const char *material)
{
    write_gltf_uri(name, extensions, material, "tex.png");
}

/* write_gltf with uri (JSON text) for the first image; quad.bin beside name. */
static void write_gltf_uri(const char *name, const char *extensions, const char *material, const char *uri)
{
    char text[4096];
    int n = snprintf(
        text, sizeof text,
        "{\"asset\": {\"version\": \"2.0\"}, \"extensionsUsed\": [%s],\n"
        "\"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}],\n"
        "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"NORMAL\": 1, "
        "\"TEXCOORD_0\": 2}, \"indices\": 3, \"material\": 0}]}],\n"
        "\"materials\": [%s],\n"
        "\"textures\": [{\"source\": 0}, {\"source\": 1}],\n"
        "\"images\": [{\"uri\": \"%s\"}, {\"uri\": \"glow.png\"}],\n"
        "\"buffers\": [{\"byteLength\": 140, \"uri\": \"quad.bin\"}],\n"
        "\"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 48},\n"
        " {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48},\n"
        " {\"buffer\": 0, \"byteOffset\": 96, \"byteLength\": 32},\n"
        " {\"buffer\": 0, \"byteOffset\": 128, \"byteLength\": 12}],\n"
        "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\", "
        "\"min\": [-1, -1, 0], \"max\": [1, 1, 0]},\n"
        " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},\n"
        " {\"bufferView\": 2, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},\n"
        " {\"bufferView\": 3, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}]}\n",
        extensions, material, uri);
    assert_true(n > 0 && (size_t)n < sizeof text);
    write_file(name, text, (size_t)n);
}

/* ------------------------------------------------------- texture transform */

/* The glTF coordinates (u, v down) the extension maps (u, v) to: its
 * README's uv' = T(offset) R(rotation) S(scale) uv, the rotation's sign
 * fixed by its example (offset [0, 1], rotation π/2, scale 0.5: the lower
 * left quadrant). */
static void spec_transform(const double off[2], double rot, const double sc[2], double u, double v,
                           double out[2])
{
    const double c = cos(rot), s = sin(rot);
    out[0] = c * sc[0] * u + s * sc[1] * v + off[0];
    out[1] = -s * sc[0] * u + c * sc[1] * v + off[1];
}

static void test_texture_transform_applied(void **state)
{
    (void)state;
    static const struct {
        double off[2], rot, sc[2];
    } cases[] = {
        {{0.5, 0.25}, 0.0, {1, 1}},
        {{0, 0}, 0.3, {1, 1}},
        {{0, 0}, 0.0, {2, 0.5}},
        {{0, 1}, 1.57079632679, {0.5, 0.5}},
        {{-0.25, 0.75}, -0.7, {1.5, -2}},
    };
    char path[1024], material[512];
    write_gltf("plain.gltf", "", "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}");
    tmp_path(path, sizeof path, "plain.gltf");
    loaded plain;
    load_path(&plain, path);
    assert_int_equal(mesh_of(&plain, 0)->vertex_count, 4);
    float uv0[4][2];
    for (size_t i = 0; i < 4; i++) memcpy(uv0[i], mesh_of(&plain, 0)->vertices[i].uv, sizeof uv0[i]);
    unload(&plain);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        snprintf(material, sizeof material,
                 "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0, \"extensions\": "
                 "{\"KHR_texture_transform\": {\"offset\": [%.17g, %.17g], \"rotation\": %.17g, "
                 "\"scale\": [%.17g, %.17g]}}}}}",
                 cases[k].off[0], cases[k].off[1], cases[k].rot, cases[k].sc[0], cases[k].sc[1]);
        write_gltf("moved.gltf", "\"KHR_texture_transform\"", material);
        tmp_path(path, sizeof path, "moved.gltf");
        loaded l;
        load_path(&l, path);
        const persp_mesh *m = mesh_of(&l, 0);
        assert_int_equal(l.warn.count, 0);
        assert_int_equal(m->vertex_count, 4);
        for (size_t i = 0; i < m->vertex_count; i++) {
            /* persp's v runs up the image: v = 1 − v_gltf, before and after. */
            double g[2];
            spec_transform(cases[k].off, cases[k].rot, cases[k].sc, uv0[i][0], 1.0 - uv0[i][1], g);
            const double want[2] = {g[0], 1.0 - g[1]};
            for (int c = 0; c < 2; c++)
                if (fabs(m->vertices[i].uv[c] - want[c]) > 1e-5)
                    fail_msg("case %zu vertex %zu: uv[%d] %g, the extension gives %g", k, i, c,
                             (double)m->vertices[i].uv[c], want[c]);
        }
        unload(&l);
    }
}

/* The transform's texCoord picks the coordinate set it transforms
 * ("overrides the textureInfo texCoord"): TEXCOORD_1 here, scaled. */
static void test_texture_transform_texcoord(void **state)
{
    (void)state;
    write_gltf("tc.gltf", "\"KHR_texture_transform\"",
               "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0, \"texCoord\": 0, "
               "\"extensions\": {\"KHR_texture_transform\": {\"scale\": [2, 2], \"texCoord\": 1}}}}}");
    /* A second set: the normals' first 32 bytes read as 4 VEC2, (0, 0),
     * (1, 0), (0, 1), (0, 0) in glTF's terms. */
    char path[1024];
    tmp_path(path, sizeof path, "tc.gltf");
    static char text[8192], edited[8400];
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    const size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *attr = strstr(text, "\"TEXCOORD_0\": 2}"), *last = strrchr(text, ']');
    assert_true(attr && last);
    snprintf(edited, sizeof edited, "%.*s\"TEXCOORD_0\": 2, \"TEXCOORD_1\": 4}%.*s,\n {\"bufferView\": 1, "
             "\"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"}%s",
             (int)(attr - text), text, (int)(last - attr - 16), attr + 16, last);
    write_file("tc.gltf", edited, strlen(edited));
    loaded l;
    load_path(&l, path);
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(l.warn.count, 0);
    assert_int_equal(m->vertex_count, 4);
    static const float set1[4][2] = {{0, 0}, {1, 0}, {0, 1}, {0, 0}};
    for (size_t i = 0; i < 4; i++) {
        const double want[2] = {2.0 * set1[i][0], 1.0 - 2.0 * set1[i][1]};
        for (int c = 0; c < 2; c++)
            if (fabs(m->vertices[i].uv[c] - want[c]) > 1e-6)
                fail_msg("vertex %zu: uv[%d] %g, TEXCOORD_1 scaled gives %g", i, c, (double)m->vertices[i].uv[c],
                         want[c]);
    }
    unload(&l);
}

/* ------------------------------------------------------------------- paths */

/* A texture named with Windows separators is found inside the model's
 * folder; one that leads out of it ("..\\") is not read, and said. */
static void test_windows_separators(void **state)
{
    (void)state;
    char path[1024];
    tmp_path(path, sizeof path, "win");
    assert_int_equal(mkdir(path, 0700), 0);
    tmp_path(path, sizeof path, "win/textures");
    assert_int_equal(mkdir(path, 0700), 0);
    persp_context *ctx = test_context();
    write_png(ctx, "win/textures/wood.png", 1);
    persp_context_destroy(ctx);
    write_quad_buffer("win/quad.bin");
    const char *mat = "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}";
    write_gltf_uri("win/in.gltf", "", mat, "textures\\\\wood.png");
    write_gltf_uri("win/out.gltf", "", mat, "..\\\\tex.png");
    tmp_path(path, sizeof path, "win/in.gltf");
    loaded l;
    load_path(&l, path);
    (void)mesh_of(&l, 0);
    assert_int_equal(l.warn.count, 0);
    assert_true(material_of(&l, 0)->texture >= 0);
    unload(&l);
    /* Through persp_scene_load, whose folder rule keeps reads inside the
     * model's folder: tex.png lies one level up. */
    ctx = test_context();
    warnings w;
    memset(&w, 0, sizeof w);
    persp_context_set_warning_handler(ctx, on_warning, &w);
    tmp_path(path, sizeof path, "win/out.gltf");
    persp_scene *s = NULL;
    if (persp_scene_load(ctx, path, &s) != PERSP_OK) fail_msg("out.gltf: %s", persp_context_error(ctx));
    persp_scene_object o;
    assert_int_equal(persp_scene_get_object(s, 0, &o), PERSP_OK);
    assert_int_equal(o.material.texture, -1);
    assert_int_equal(w.count, 1);
    assert_non_null(strstr(w.last, "outside the folder the model may read from"));
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

/* --------------------------------------------------------------- rendering */

#define SIDE 48

typedef struct frame {
    uint8_t color[SIDE * SIDE * 4];
    float depth[SIDE * SIDE];
    int covered; /* pixels not of the background */
} frame;

static int is_background(const uint8_t *p) { return p[0] == 40 && p[1] == 40 && p[2] == 40; }

/* The model name through persp_scene_load, rendered with its own lights
 * and camera. */
static void render(const char *name, frame *f, persp_scene_material *mat)
{
    persp_context *ctx = test_context();
    char path[1024];
    tmp_path(path, sizeof path, name);
    persp_scene *s = NULL;
    if (persp_scene_load(ctx, path, &s) != PERSP_OK) fail_msg("%s: %s", name, persp_context_error(ctx));
    persp_scene_object o;
    assert_int_equal(persp_scene_get_object(s, 0, &o), PERSP_OK);
    if (mat) *mat = o.material;
    persp_framebuffer fb = {SIDE, SIDE, f->color, f->depth};
    assert_int_equal(persp_render(ctx, s, NULL, &fb, NULL), PERSP_OK);
    f->covered = 0;
    for (int i = 0; i < SIDE * SIDE; i++) f->covered += !is_background(f->color + 4 * i);
    assert_true(f->covered > SIDE * SIDE / 8);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

/* A black surface with an emissive colour glows in it: every pixel is at
 * least the emission (the lights add to it, never take away). */
static void test_emissive_colour(void **state)
{
    (void)state;
    write_gltf("glow.gltf", "",
               "{\"emissiveFactor\": [1, 0.6, 0], \"pbrMetallicRoughness\": {\"baseColorFactor\": [0, 0, 0, 1]}}");
    static frame f;
    persp_scene_material m;
    render("glow.gltf", &f, &m);
    assert_true(m.emission[0] == 1.0f && fabsf(m.emission[1] - 0.6f) < 1e-6f && m.emission[2] == 0.0f);
    for (int i = 0; i < SIDE * SIDE; i++) {
        const uint8_t *p = f.color + 4 * i;
        if (is_background(p)) continue;
        if (!(p[0] == 255 && p[1] >= 153 && p[2] < p[1]))
            fail_msg("pixel %d is (%d, %d, %d), not the emission (255, 153, 0) or more", i, p[0], p[1], p[2]);
    }
}

/* An emissive map on a black surface without a base colour texture is
 * drawn: the pixels are the map's texels (several colours, none black). */
static void test_emissive_map(void **state)
{
    (void)state;
    write_gltf("label.gltf", "",
               "{\"emissiveFactor\": [1, 1, 1], \"emissiveTexture\": {\"index\": 1}, "
               "\"pbrMetallicRoughness\": {\"baseColorFactor\": [0, 0, 0, 1]}}");
    static frame f;
    persp_scene_material m;
    render("label.gltf", &f, &m);
    assert_true(m.texture >= 0);
    int distinct = 0;
    uint8_t seen[16][3];
    for (int i = 0; i < SIDE * SIDE; i++) {
        const uint8_t *p = f.color + 4 * i;
        if (is_background(p)) continue;
        /* glow.png's blue is 120 in every texel. */
        if (p[2] < 120) fail_msg("pixel %d is (%d, %d, %d): the emissive map is not drawn", i, p[0], p[1], p[2]);
        int known = 0;
        for (int k = 0; k < distinct && !known; k++) known = !memcmp(seen[k], p, 3);
        if (!known && distinct < 16) memcpy(seen[distinct++], p, 3);
    }
    assert_true(distinct >= 4);
}

/* MTL's Ke and map_Ke (Blender's OBJ exporter writes them) read by
 * persp's OBJ reader: the same glow. */
static void test_obj_emission(void **state)
{
    (void)state;
    const char *obj = "mtllib e.mtl\nusemtl m\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    write_file("e.obj", obj, strlen(obj));
    const char *mtl = "newmtl m\nKd 0 0 0\nKe 1 0.6 0\n";
    write_file("e.mtl", mtl, strlen(mtl));
    static frame f;
    persp_scene_material m;
    render("e.obj", &f, &m);
    assert_true(m.emission[0] == 1.0f && fabsf(m.emission[1] - 0.6f) < 1e-6f && m.emission[2] == 0.0f);
    for (int i = 0; i < SIDE * SIDE; i++) {
        const uint8_t *p = f.color + 4 * i;
        if (!is_background(p) && !(p[0] == 255 && p[1] >= 153 && p[2] < p[1]))
            fail_msg("e.obj: pixel %d is (%d, %d, %d), not the emission", i, p[0], p[1], p[2]);
    }
    mtl = "newmtl m\nKd 0 0 0\nKe 1 1 1\nmap_Ke glow.png\n";
    write_file("e.mtl", mtl, strlen(mtl));
    render("e.obj", &f, &m);
    assert_true(m.texture >= 0);
    for (int i = 0; i < SIDE * SIDE; i++) {
        const uint8_t *p = f.color + 4 * i;
        if (!is_background(p) && p[2] < 120)
            fail_msg("e.obj: pixel %d is (%d, %d, %d): map_Ke is not drawn", i, p[0], p[1], p[2]);
    }
}

/* A base colour texture and another emissive map: drawn through the base
 * colour texture, said. */
static void test_emissive_map_beside_base_warned(void **state)
{
    (void)state;
    write_gltf("both.gltf", "",
               "{\"emissiveFactor\": [1, 1, 1], \"emissiveTexture\": {\"index\": 1}, "
               "\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}");
    char path[1024];
    tmp_path(path, sizeof path, "both.gltf");
    loaded l;
    load_path(&l, path);
    (void)mesh_of(&l, 0);
    assert_int_equal(l.warn.count, 1);
    assert_non_null(strstr(l.warn.last, "emissive map is not its base colour texture"));
    unload(&l);
}

/* KHR_materials_unlit: the base colour, whatever the lights. */
static void test_unlit_colour(void **state)
{
    (void)state;
    write_gltf("flat.gltf", "\"KHR_materials_unlit\"",
               "{\"extensions\": {\"KHR_materials_unlit\": {}}, "
               "\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.2, 0.4, 0.6, 1]}}");
    static frame f;
    persp_scene_material m;
    render("flat.gltf", &f, &m);
    assert_int_equal(m.unlit, 1);
    for (int i = 0; i < SIDE * SIDE; i++) {
        const uint8_t *p = f.color + 4 * i;
        if (is_background(p)) continue;
        if (p[0] != 51 || p[1] != 102 || p[2] != 153)
            fail_msg("pixel %d is (%d, %d, %d), not the base colour (51, 102, 153)", i, p[0], p[1], p[2]);
    }
}

/* Textured and unlit: the texel (factor white), or the texel times the
 * factor; the same pixels either way. */
static void test_unlit_texture(void **state)
{
    (void)state;
    write_gltf("white.gltf", "\"KHR_materials_unlit\"",
               "{\"extensions\": {\"KHR_materials_unlit\": {}}, "
               "\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}");
    write_gltf("half.gltf", "\"KHR_materials_unlit\"",
               "{\"extensions\": {\"KHR_materials_unlit\": {}}, "
               "\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 0.5, 0.5, 1], "
               "\"baseColorTexture\": {\"index\": 0}}}");
    static frame white, half;
    render("white.gltf", &white, NULL);
    render("half.gltf", &half, NULL);
    assert_int_equal(white.covered, half.covered);
    for (int i = 0; i < SIDE * SIDE; i++) {
        const uint8_t *a = white.color + 4 * i, *b = half.color + 4 * i;
        if (is_background(a)) continue;
        for (int c = 0; c < 3; c++)
            if (abs((int)b[c] - (int)(a[c] * 0.5 + 0.5)) > 1)
                fail_msg("pixel %d channel %d: %d with the factor 0.5, %d without", i, c, b[c], a[c]);
    }
    /* The white one is the texture's own texels: tex.png's blue is 20. */
    for (int i = 0; i < SIDE * SIDE; i++)
        if (!is_background(white.color + 4 * i)) assert_int_equal(white.color[4 * i + 2], 20);
}

static int setup(void **state)
{
    (void)state;
    if (test_tmpdir_make(tmpdir, sizeof tmpdir, "materials") != 0) return -1;
    persp_context *ctx = test_context();
    write_png(ctx, "tex.png", 0);
    write_png(ctx, "glow.png", 1);
    persp_context_destroy(ctx);
    write_quad_buffer("quad.bin");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    return test_tmpdir_remove(tmpdir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_texture_transform_applied),
        cmocka_unit_test(test_texture_transform_texcoord),
        cmocka_unit_test(test_windows_separators),
        cmocka_unit_test(test_emissive_colour),
        cmocka_unit_test(test_emissive_map),
        cmocka_unit_test(test_emissive_map_beside_base_warned),
        cmocka_unit_test(test_obj_emission),
        cmocka_unit_test(test_unlit_colour),
        cmocka_unit_test(test_unlit_texture),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
