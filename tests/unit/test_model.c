/* Model import: OBJ with MTL and textures, the quirks of real OBJ files,
 * glTF with embedded buffers and textures, PLY and STL, node transforms,
 * warnings and fallbacks for missing files, errors naming the file, and
 * scenes built around a bare model. */
#include "model_load.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "model/model.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[64];

static void make_tmp(void) { assert_int_equal(test_tmpdir_make(tmpdir, sizeof tmpdir, "model"), 0); }

static void write_file(const char *name, const void *data, size_t size) { test_write_file(tmpdir, name, data, size); }

static void write_text(const char *name, const char *text)
{
    write_file(name, text, strlen(text));
}

static void write_png(persp_context *ctx, const char *name, int w, int h)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, w, h, &img), PERSP_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = (uint8_t)(x * 40), p[1] = (uint8_t)(y * 40), p[2] = 128, p[3] = 255;
        }
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_OK);
    persp_image_free(ctx, &img);
}

static void tmp_path(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", tmpdir, name);
}

static void remove_tmp(void) { assert_int_equal(test_tmpdir_remove(tmpdir), 0); }

static void test_obj_quad_from_memory(void **state)
{
    (void)state;
    loaded l;
    load_text(&l,
              "# a unit quad\n"
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
              "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
              "vn 0 0 1\n"
              "g quad\no thing\ns 1\n"
              "f 1/1/1 2/2/1 3/3/1 4/4/1\n",
              "t.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(l.model.part_count, 1);
    assert_int_equal(m->index_count, 6);
    assert_int_equal(m->vertex_count, 4);
    assert_true(m->has_normals);
    for (size_t i = 0; i < m->vertex_count; i++) {
        const persp_vertex *v = &m->vertices[i];
        /* uv equals position for this quad */
        assert_true(fabsf(v->uv[0] - v->pos[0]) < 1e-6f && fabsf(v->uv[1] - v->pos[1]) < 1e-6f);
        assert_true(v->normal[2] == 1.0f && v->color[0] == 1.0f && v->color[3] == 1.0f);
    }
    /* counter-clockwise seen from +z, as the file's face */
    for (size_t t = 0; t < m->index_count; t += 3) {
        const float *a = m->vertices[m->indices[t]].pos, *b = m->vertices[m->indices[t + 1]].pos,
                    *c = m->vertices[m->indices[t + 2]].pos;
        float cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert_true(cross > 0);
    }
    /* no material: persp's default */
    persp_material def = persp__material_default();
    assert_memory_equal(material_of(&l, 0)->diffuse, def.diffuse, sizeof def.diffuse);
    assert_int_equal(material_of(&l, 0)->texture, -1);
    assert_true(l.model.bbox_min[0] == 0.0f && l.model.bbox_max[1] == 1.0f);
    unload(&l);
}

/* What the hand-written OBJ reader did: relative (negative) indices,
 * vertex colours after the position, polygons of more than 4 corners,
 * v/vt, v//vn and v/vt/vn corners. */
static void test_obj_indices_colours_polygons(void **state)
{
    (void)state;
    loaded l;
    load_text(&l,
              "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0.5 1.5 0 1 1 0\nv 0 1 0 0 1 1\n"
              "vt 0 0\nvt 1 0\nvn 0 0 1\n"
              "f -5/-2/-1 -4/-1/-1 -3//-1 -2 -1\n",
              "pent.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 9);
    int coloured = 0;
    for (size_t i = 0; i < m->vertex_count; i++) {
        const persp_vertex *v = &m->vertices[i];
        if (v->pos[0] == 0.0f && v->pos[1] == 0.0f)
            coloured += v->color[0] == 1.0f && v->color[1] == 0.0f && v->color[2] == 0.0f;
        if (v->pos[0] == 1.0f && v->pos[1] == 1.0f)
            coloured += v->color[0] == 0.0f && v->color[1] == 0.0f && v->color[2] == 1.0f;
        assert_true(v->color[3] == 1.0f);
    }
    assert_int_equal(coloured, 2);
    float area = 0;
    for (size_t t = 0; t < m->index_count; t += 3) {
        const float *a = m->vertices[m->indices[t]].pos, *b = m->vertices[m->indices[t + 1]].pos,
                    *c = m->vertices[m->indices[t + 2]].pos;
        area += 0.5f * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    assert_true(fabsf(area - 1.25f) < 1e-5f); /* the pentagon, all front-facing */
    unload(&l);
}

static void test_obj_smooth_normals_when_missing(void **state)
{
    (void)state;
    /* Two faces of a shallow roof (20 degrees apart) share an edge: below
     * the crease angle, so the shared corners get one averaged normal. */
    loaded l;
    load_text(&l,
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 2 0.36\nv 1 2 0.36\nf 1 2 3 4\nf 4 3 6 5\n",
              "roof.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 12);
    int shared = 0;
    for (size_t i = 0; i < m->vertex_count; i++) {
        const persp_vertex *v = &m->vertices[i];
        float len = sqrtf(v->normal[0] * v->normal[0] + v->normal[1] * v->normal[1] +
                          v->normal[2] * v->normal[2]);
        assert_true(fabsf(len - 1.0f) < 1e-3f);
        if (v->pos[1] == 1.0f) {
            shared++;
            assert_true(v->normal[1] < -0.05f); /* tilted between the two faces */
        }
    }
    assert_int_equal(shared, 2);
    unload(&l);
}

static void test_obj_mtl_texture_and_quirks(void **state)
{
    (void)state;
    make_tmp();
    char sub[128];
    snprintf(sub, sizeof sub, "%s/tex", tmpdir);
    assert_int_equal(mkdir(sub, 0700), 0);
    persp_context *ctx = test_context();
    write_png(ctx, "tex/t.png", 4, 2);
    persp_context_destroy(ctx);
    /* A byte-order mark, CR-only lines, Windows separators, a material name
     * with spaces and a statement persp ignores (Km). */
    write_text("lib.mtl", "\xef\xbb\xbfnewmtl red stone\rKd 1 0 0\rKs 0.5 0.5 0.5\rNs 20\rKm 1\r"
                          "map_Kd .\\tex\\t.png\r");
    write_text("m.obj",
               "\xef\xbb\xbfmtllib lib.mtl\rv 0 0 0\rv 1 0 0\rv 0 1 0\rvt 0 0\rvt 1 0\rvt 0 1\r"
               "usemtl red stone\rf 1/1 2/2 3/3\r");
    char path[256];
    tmp_path(path, sizeof path, "m.obj");
    loaded l;
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(l.warn.count, 0);
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 3);
    const persp_material *mat = material_of(&l, 0);
    assert_true(mat->diffuse[0] == 1.0f && mat->diffuse[1] == 0.0f);
    assert_true(mat->specular[0] == 0.5f && mat->shininess == 20.0f);
    assert_true(mat->texture >= 0);
    assert_int_equal(mat->env, PERSP_TEXENV_MODULATE);
    assert_int_equal(persp_texture_width(l.scene->textures[mat->texture]), 4);
    unload(&l);
    remove_tmp();
}

/* Names written on systems blind to case (WALL.PNG, LIB.MTL) find the files
 * that carry them in another case. */
static void test_names_in_another_case(void **state)
{
    (void)state;
    make_tmp();
    persp_context *ctx = test_context();
    write_png(ctx, "wall.png", 4, 2);
    persp_context_destroy(ctx);
    write_text("lib.mtl", "newmtl m\nKd 1 1 1\nmap_Kd C:\\MODELS\\WALL.PNG\n");
    write_text("m.obj", "mtllib LIB.MTL\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                        "usemtl m\nf 1/1 2/2 3/3\n");
    char path[256];
    tmp_path(path, sizeof path, "m.obj");
    loaded l;
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(l.warn.count, 0);
    mesh_of(&l, 0);
    const persp_material *mat = material_of(&l, 0);
    assert_true(mat->texture >= 0);
    assert_int_equal(persp_texture_width(l.scene->textures[mat->texture]), 4);
    unload(&l);
    remove_tmp();
}

static void test_obj_missing_files_warn(void **state)
{
    (void)state;
    make_tmp();
    /* usemtl without any mtllib, a missing MTL file, a missing texture. */
    write_text("a.obj", "usemtl Default\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text("b.obj", "mtllib gone.mtl\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text("c.mtl", "newmtl x\nKd 0 1 0\nmap_Kd C:\\textures\\gone.jpg\n");
    write_text("c.obj", "mtllib c.mtl\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    char path[256];
    loaded l;
    tmp_path(path, sizeof path, "a.obj");
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(material_of(&l, 0)->texture, -1);
    unload(&l);

    tmp_path(path, sizeof path, "b.obj");
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(l.warn.count, 1);
    assert_non_null(strstr(l.warn.last, "gone.mtl"));
    assert_non_null(strstr(l.warn.last, "b.obj"));
    assert_int_equal(material_of(&l, 0)->texture, -1);
    unload(&l);

    tmp_path(path, sizeof path, "c.obj");
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(l.warn.count, 1);
    assert_non_null(strstr(l.warn.last, "C:/textures/gone.jpg"));
    assert_non_null(strstr(l.warn.last, "untextured"));
    const persp_material *mat = material_of(&l, 0);
    assert_int_equal(mat->texture, -1);
    assert_true(mat->diffuse[1] == 1.0f);
    unload(&l);
    remove_tmp();
}

static void test_gltf_embedded_texture_and_nodes(void **state)
{
    (void)state;
    char path[1024];
    test_source_path(path, sizeof path, "tests/data/models/embedded.gltf");
    loaded l;
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(l.warn.count, 0);
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 3);
    const persp_material *mat = material_of(&l, 0);
    assert_true(mat->texture >= 0);
    const persp_texture *tex = l.scene->textures[mat->texture];
    assert_int_equal(persp_texture_width(tex), 2);
    persp_image_view v;
    assert_int_equal(persp_texture_level(tex, 0, &v), PERSP_OK);
    /* the image's top row is red, green: persp's row 1 */
    const uint8_t *top = v.pixels + v.stride;
    assert_true(top[0] == 255 && top[1] == 0 && top[4] == 0 && top[5] == 255);
    /* translate (2, 0, 0) above scale (1, 2, 1) */
    const persp_mat4 *t = &l.model.parts[0].transform;
    persp_vec4 p = persp_mat4_apply(*t, (persp_vec4){0, 1, 0, 1});
    assert_true(fabsf(p.x - 2.0f) < 1e-6f && fabsf(p.y - 2.0f) < 1e-6f);
    assert_true(fabsf(l.model.bbox_min[0] - 2.0f) < 1e-6f &&
                fabsf(l.model.bbox_max[1] - 2.0f) < 1e-6f);
    /* glTF's v runs down the image; persp's up: the vertex at uv (0, 1) in
     * the file samples the image's bottom-left */
    for (size_t i = 0; i < m->vertex_count; i++)
        if (m->vertices[i].pos[1] == 1.0f) assert_true(fabsf(m->vertices[i].uv[1]) < 1e-6f);
    unload(&l);
}

/* The text of a file of tests/data/models, for tests that edit it. */
static void source_text(const char *file, char *text, size_t size)
{
    char path[1024];
    test_source_path(path, sizeof path, file);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, size - 1, f);
    fclose(f);
    text[n] = '\0';
}

/* The text of tests/data/models/embedded.gltf, for tests that edit it. */
static void embedded_gltf(char *text, size_t size) { source_text("tests/data/models/embedded.gltf", text, size); }

/* A file the import cannot do without (a glTF buffer) is the error itself,
 * named with the line that names it, not a warning that persp goes on
 * without it followed by Assimp's "could not open". */
static void test_gltf_missing_buffer(void **state)
{
    (void)state;
    char path[1024];
    static char text[8192], edited[8192];
    embedded_gltf(text, sizeof text);
    const char *uri = strstr(text, "\"data:application/octet-stream");
    assert_non_null(uri);
    const char *close = strchr(uri + 1, '"');
    snprintf(edited, sizeof edited, "%.*s\"gone.bin\"%s", (int)(uri - text), text, close + 1);
    make_tmp();
    write_text("b.gltf", edited);
    tmp_path(path, sizeof path, "b.gltf");
    loaded l;
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_ERR_IO);
    const char *e = persp_context_error(l.ctx);
    assert_non_null(strstr(e, "b.gltf:"));
    assert_non_null(strstr(e, "cannot read 'gone.bin'"));
    assert_non_null(strstr(e, "which the model cannot be imported without"));
    assert_int_equal(l.warn.count, 0);
    unload(&l);
    remove_tmp();
}

/* Binary glTF with the image in the binary chunk, COLLADA and ASCII FBX
 * with a node transform (FBX also with a material), binary STL. */
static void test_more_formats(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        int textured;
        float z; /* translation of the instance */
    } cases[] = {{"tests/data/models/embedded.glb", 1, 0.0f},
                 {"tests/data/models/triangle.dae", 0, -1.0f},
                 {"tests/data/models/triangle.fbx", 0, -1.0f},
                 {"tests/data/models/triangle_binary.stl", 0, 0.0f}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[1024];
        test_source_path(path, sizeof path, cases[i].file);
        loaded l;
        load_path(&l, path);
        if (l.st != PERSP_OK) fail_msg("%s: %s", cases[i].file, persp_context_error(l.ctx));
        assert_int_equal(l.warn.count, 0);
        const persp_mesh *m = mesh_of(&l, 0);
        assert_int_equal(m->index_count, 3);
        assert_int_equal(material_of(&l, 0)->texture >= 0, cases[i].textured);
        if (cases[i].textured) {
            persp_image_view v;
            assert_int_equal(
                persp_texture_level(l.scene->textures[material_of(&l, 0)->texture], 0, &v),
                PERSP_OK);
            assert_true(v.width == 2 && v.pixels[v.stride] == 255); /* top-left red */
        }
        if (strstr(cases[i].file, ".fbx")) {
            const float *d = material_of(&l, 0)->diffuse;
            assert_true(d[0] == 1.0f && d[1] == 0.0f && d[2] == 0.0f);
        }
        if (fabsf(l.model.parts[0].transform.m[14] - cases[i].z) > 1e-6f)
            fail_msg("%s: z translation %g", cases[i].file,
                     (double)l.model.parts[0].transform.m[14]);
        unload(&l);
    }
}

static void test_ply_vertex_colours(void **state)
{
    (void)state;
    loaded l;
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
              "y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n"
              "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n",
              "c.ply");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 3);
    int red = 0, green = 0, blue = 0;
    for (size_t i = 0; i < m->vertex_count; i++) {
        const float *c = m->vertices[i].color;
        red += c[0] == 1.0f && c[1] == 0.0f && c[2] == 0.0f;
        green += c[0] == 0.0f && c[1] == 1.0f && c[2] == 0.0f;
        blue += c[0] == 0.0f && c[1] == 0.0f && c[2] == 1.0f;
    }
    assert_true(red == 1 && green == 1 && blue == 1);
    /* No material in the file: persp's default, as for STL (not Assimp's
     * white stand-in, ambient and specular 1 too). */
    const persp_material *mat = material_of(&l, 0), def = persp__material_default();
    assert_memory_equal(mat->diffuse, def.diffuse, sizeof def.diffuse);
    assert_memory_equal(mat->specular, def.specular, sizeof def.specular);
    assert_memory_equal(mat->ambient, def.ambient, sizeof def.ambient);
    unload(&l);
}

/* Old Blender exports carry a bare text line ("Created by Blender3D ...")
 * after the format line; it is read past as a comment would be. A line that
 * is not text still stops the header. */
static void test_ply_bare_text_line_in_header(void **state)
{
    (void)state;
    loaded l;
    load_text(&l,
              "ply\nformat ascii 1.0\nCreated by an old exporter\nelement vertex 3\n"
              "property float x\nproperty float y\nproperty float z\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n"
              "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
              "old.ply");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    unload(&l);
    load_text(&l,
              "ply\nformat ascii 1.0\nCreated \x01\x02\nelement vertex 3\n"
              "property float x\nproperty float y\nproperty float z\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n"
              "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
              "bin.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "bin.ply:3: expected a PLY header keyword"));
    unload(&l);
    /* Inside an element the same text is refused: there Assimp 5.2 took it
     * for the end of the property list and sized arrays by garbage (18 GB
     * for this header with a hundred digits in the line). */
    static char inside[600];
    snprintf(inside, sizeof inside,
             "ply\nformat ascii 1.0\nelement vertex 3\nfoo%0100dy fl\nproperty uchar green\n"
             "property uchar blue\nelement face 4\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 \n",
             0);
    load_text(&l, inside, "inside.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "inside.ply:4: expected a PLY header keyword"));
    unload(&l);
}

static void test_stl_ascii(void **state)
{
    (void)state;
    loaded l;
    load_text(&l,
              "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
              "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\n"
              "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
              "s.stl");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 6);
    for (size_t i = 0; i < m->vertex_count; i++)
        assert_true(fabsf(m->vertices[i].normal[2] - 1.0f) < 1e-5f);
    unload(&l);
}

/* A binary STL whose facet normals are all zero gets normals of its own
 * (here, the quad's +z), not zero normals that leave it unlit. */
static void test_stl_zero_normals_made_afresh(void **state)
{
    (void)state;
    static const float tri[2][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}};
    unsigned char stl[84 + 2 * 50];
    memset(stl, 0, sizeof stl);
    memcpy(stl, "zero normals", 12);
    const uint32_t n = 2;
    memcpy(stl + 80, &n, 4);
    for (int f = 0; f < 2; f++)
        memcpy(stl + 84 + 50 * f + 12, tri[f], sizeof tri[f]); /* normal stays 0 0 0 */
    loaded l;
    begin(&l);
    l.st = persp__model_load_memory(l.scene, stl, sizeof stl, "z.stl", NULL, NULL, 0, &l.model);
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 6);
    for (size_t i = 0; i < m->vertex_count; i++)
        assert_true(fabsf(fabsf(m->vertices[i].normal[2]) - 1.0f) < 1e-5f);
    unload(&l);
}

/* Faces that all lie on a line would draw an empty picture: refused. One
 * face with area is enough. */
static void test_zero_area_model_refused(void **state)
{
    (void)state;
    loaded l;
    load_text(&l, "v 0 0 0\nv 1 2 3\nv -1 -2 -3\nv 2 4 6\nf 1 2 3\nf 1 2 4\n", "line.obj");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(
        strstr(persp_context_error(l.ctx), "line.obj: the model's triangles all have zero area"));
    unload(&l);
    load_text(&l, "v 0 0 0\nv 1 2 3\nv -1 -2 -3\nv 0 1 0\nf 1 2 3\nf 1 2 4\n", "one.obj");
    assert_int_equal(l.st, PERSP_OK);
    unload(&l);
}

/* Points and lines only, and a file no reader takes. */
static void errors_points_and_formats(void)
{
    loaded l;
    /* points and lines only */
    load_text(&l, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n", "lines.obj");
    assert_int_not_equal(l.st, PERSP_OK);
    const char *e = persp_context_error(l.ctx);
    assert_non_null(strstr(e, "lines.obj"));
    assert_null(strchr(e, '\n'));
    unload(&l);
    /* a file no reader takes: an unsupported format, not a malformed one */
    load_text(&l, "\x01\x02 this is not a model \x03", "junk.xyz");
    assert_int_equal(l.st, PERSP_ERR_UNSUPPORTED);
    assert_non_null(strstr(persp_context_error(l.ctx), "junk.xyz: not a model format persp reads"));
    unload(&l);
    load_text(&l, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "range.obj");
    assert_int_not_equal(l.st, PERSP_OK);
    assert_non_null(strstr(persp_context_error(l.ctx), "range.obj"));
    unload(&l);
}

/* OFF header counts beyond the file or persp's limits. */
static void errors_header_counts(void)
{
    loaded l;
    /* header counts beyond the file or persp's limits: refused before
     * the reader sizes its arrays by them */
    load_text(
        &l,
        "ply\nformat ascii 1.0\nelement vertex 999999999\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n",
        "big.ply");
    assert_int_equal(l.st, PERSP_ERR_TOO_LARGE);
    assert_non_null(
        strstr(persp_context_error(l.ctx), "big.ply: the header declares 999999999 vertices"));
    unload(&l);
    load_text(&l, "OFF\n# comment\n3 5000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "big.off");
    assert_int_equal(l.st, PERSP_ERR_TOO_LARGE);
    assert_non_null(strstr(persp_context_error(l.ctx), "5000 faces, more than the file holds"));
    unload(&l);
    /* the OFF keyword is optional: the first line then holds the counts
     * (6666666666660 vertices took Assimp 10 GB), and a count has no sign */
    load_text(&l, "6666666666660 1 0\n0 0 0\n", "nokey.off");
    assert_int_equal(l.st, PERSP_ERR_TOO_LARGE);
    assert_non_null(strstr(persp_context_error(l.ctx), "nokey.off: the header declares 6666666666660 vertices"));
    unload(&l);
    /* after a UTF-8 byte-order mark, which Assimp drops (4.6 GB for a
     * count of twelve 7s); one in UTF-16 is refused; a BOM'd valid file loads */
    load_text(&l, "\xef\xbb\xbf" "777777777777 777 0\n0 0 0\n", "bom.off");
    assert_int_equal(l.st, PERSP_ERR_TOO_LARGE);
    assert_non_null(strstr(persp_context_error(l.ctx), "bom.off: the header declares 777777777777 vertices"));
    unload(&l);
    load_bytes(&l, "\xff\xfe" "3\0 \0" "1\0", 8, "wide.off");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "wide.off: an OFF file in UTF-16 or UTF-32"));
    unload(&l);
    load_text(&l, "\xef\xbb\xbf" "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "bomok.off");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    unload(&l);
    load_text(&l, "OFF -3 1 0\n0 0 0\n", "sign.off");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "sign.off: an OFF count has a sign"));
    unload(&l);
    load_text(&l, "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "plain.off");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    unload(&l);
}

/* PLY headers and ASCII bodies that Assimp's reader would size its arrays by or misread. */
static void errors_ply_ascii(void)
{
    loaded l;
    /* an ASCII list count beyond its line (Assimp sized the list by it:
     * 15 GB for a count of fifteen 6s) */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n666666666666666 0 1 2\n",
              "list.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx),
                           "list.ply: a PLY list of element 2 declares 666666666666666 values"));
    unload(&l);
    /* the body split into lines as Assimp's reader splits it: a form feed
     * ends a line, so the count opens the next one (7.5 GB: the count
     * wrapped to 32 bits); a line starting at a line end is skipped with
     * whatever follows up to the next newline; CRLF files still load */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\f666666629333 0 1 2\n",
              "ff.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx),
                           "ff.ply: a PLY list of element 2 declares 666666629333 values"));
    unload(&l);
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\r\r9 skipped\n666666629333 0 1 2\n",
              "cr.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "cr.ply: a PLY list of element 2 declares 666666629333"));
    unload(&l);
    load_text(&l,
              "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
              "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n"
              "end_header\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n",
              "crlf.ply");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    unload(&l);
    /* two elements named vertex: Assimp wrote the second's three vertices
     * into the array it sized for the first's one (heap overflow) */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
              "property float z\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n0 0 0\n0 0 0\n1 0 0\n0 1 0\n",
              "twice.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "twice.ply: PLY elements 1 and 2 have the same name 'vertex'"));
    unload(&l);
    /* a header line holding another byte Assimp ends lines at */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 3\fproperty float x\nproperty float y\n"
              "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
              "hff.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "hff.ply: the PLY header holds a carriage return, form feed or NUL"));
    unload(&l);
}

/* The same in binary PLY, little- and big-endian. */
static void errors_ply_binary(void)
{
    loaded l;
    /* the same in a binary PLY, little- and big-endian (16.8 and 8.4 GB
     * in Assimp); a valid one still loads */
    {
        static const char head[] =
            "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list int int vertex_indices\nend_header\n";
        unsigned char file[sizeof head - 1 + 36 + 16];
        memcpy(file, head, sizeof head - 1);
        unsigned char *body = file + sizeof head - 1;
        const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        memcpy(body, xyz, sizeof xyz); /* this machine is little-endian, as the header says */
        const int32_t face[4] = {3, 0, 1, 2};
        memcpy(body + 36, face, sizeof face);
        load_bytes(&l, (const char *)file, sizeof file, "bin.ply");
        assert_int_equal(mesh_of(&l, 0)->index_count, 3);
        unload(&l);
        const int32_t huge = 0x7fffffff;
        memcpy(body + 36, &huge, 4);
        load_bytes(&l, (const char *)file, sizeof file, "huge.ply");
        assert_int_equal(l.st, PERSP_ERR_FORMAT);
        assert_non_null(strstr(persp_context_error(l.ctx),
                               "huge.ply: a PLY list of element 2 declares 2147483647 values"));
        unload(&l);
        /* big-endian: the count's bytes 40 00 00 00 read as 2^30 */
        static const char head_be[] =
            "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list int int vertex_indices\nend_header\n";
        unsigned char file_be[sizeof head_be - 1 + 36 + 16];
        memcpy(file_be, head_be, sizeof head_be - 1);
        memset(file_be + sizeof head_be - 1, 0, 52);
        file_be[sizeof head_be - 1 + 36] = 0x40;
        load_bytes(&l, (const char *)file_be, sizeof file_be, "be.ply");
        assert_int_equal(l.st, PERSP_ERR_FORMAT);
        assert_non_null(strstr(persp_context_error(l.ctx),
                               "be.ply: a PLY list of element 2 declares 1073741824 values"));
        unload(&l);
    }
}

/* PLY faces and elements that Assimp validates wrongly. */
static void errors_ply_elements(void)
{
    loaded l;
    /* faces without corners, which pass Assimp's validation and crashed
     * its post-processing (SIGBUS), are left out */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n0\n3 0 1 2\n0\n1 0\n",
              "empty.ply");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    unload(&l);
    /* a PLY element name of digits, which Assimp would read as the count
     * (here 2^32 + 1, which it wraps to 1) */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement 4294967297x 1\nproperty float x\nend_header\n0\n",
              "digits.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx),
                           "digits.ply: PLY element 1: the name starts with a digit"));
    unload(&l);
    /* faces but no vertex element */
    load_text(&l,
              "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
              "end_header\n3 0 1 2\n",
              "novert.ply");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(
        strstr(persp_context_error(l.ctx), "novert.ply: the PLY header declares no vertices"));
    unload(&l);
}

/* OBJ material libraries that Assimp's reader mishandles. */
static void errors_material_urls(void)
{
    loaded l;
    /* a material library named like a URL, which Assimp's OBJ reader
     * mishandles */
    load_text(&l, "mtllib abcde://\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "url.obj");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx),
                           "url.obj:1: the material library is named like a URL"));
    unload(&l);
    /* the same after a NUL byte, which ends a line for Assimp's reader */
    static const char nul_url[] = "usemtl p\0mtllib abcde://\n";
    begin(&l);
    l.st = persp__model_load_memory(l.scene, nul_url, sizeof nul_url - 1, "nul.obj", NULL, NULL, 0,
                                    &l.model);
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "nul.obj:1: the material library is named"));
    unload(&l);
}

/* glTF and binary glTF files whose container lies. */
static void errors_gltf_containers(void)
{
    loaded l;
    /* a .gltf that is neither JSON nor binary glTF */
    load_text(&l, "l-geometrynodev ", "junk.gltf");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "junk.gltf: not a glTF file"));
    unload(&l);
    /* an embedded image whose mimeType has no '/', on which Assimp's glTF
     * reader crashes */
    load_text(&l,
              "{\"asset\": {\"version\": \"2.0\"}, \"images\": [{\"bufferView\": 0, "
              "\"mimeType\": \"image9png\"}]}",
              "mime.gltf");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "mime.gltf: image 0: the mimeType is not"));
    unload(&l);
    /* the same media type in an image's data URI (Assimp searched for '/'
     * on into the data and crashed without one); one with '/' loads on */
    load_text(&l,
              "{\"asset\": {\"version\": \"2.0\"}, \"images\": [{\"uri\": "
              "\"data:image\\u00d9png;base64,iVBORw0KGgo=\"}]}",
              "datauri.gltf");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "datauri.gltf: a data URI's media type is not"));
    unload(&l);
    load_text(&l,
              "{\"asset\": {\"version\": \"2.0\"}, \"images\": [{\"uri\": "
              "\"data:imagepng;base64,iVBORw0KGgo=\"}]}",
              "datauri2.gltf");
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    unload(&l);
    /* binary glTF whose declared lengths exceed the file (glTF 2.0 §4.4;
     * version 1: KHR_binary_glTF): refused before the reader allocates them */
    static const unsigned char glb2[] = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 28, 0, 0, 0,
                                         0x78, 0x03, 0x00, 0xff, 'J', 'S', 'O', 'N',
                                         '{', '}', ' ', ' ', 0, 0, 0, 0};
    static const unsigned char glb1[] = {'g', 'l', 'T', 'F', 1, 0, 0, 0, 24, 0, 0, 0,
                                         0xff, 0xff, 0xff, 0x7f, 0, 0, 0, 0, '{', '}', ' ', ' '};
    begin(&l);
    l.st = persp__model_load_memory(l.scene, glb2, sizeof glb2, "big.glb", NULL, NULL, 0, &l.model);
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx),
                           "big.glb: truncated GLB: the chunk at byte 12 declares 4278190968 bytes"));
    unload(&l);
    begin(&l);
    l.st = persp__model_load_memory(l.scene, glb1, sizeof glb1, "v1.glb", NULL, NULL, 0, &l.model);
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "v1.glb: truncated GLB: the content"));
    unload(&l);
}

/* The vertex budget. */
static void errors_vertex_budget(void)
{
    loaded l;
    /* vertex budget: checked before persp allocates the mesh */
    begin(&l);
    const char *quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    l.st =
        persp__model_load_memory(l.scene, quad, strlen(quad), "big.obj", NULL, NULL, 3, &l.model);
    assert_int_equal(l.st, PERSP_ERR_TOO_LARGE);
    unload(&l);
}

/* Every refusal names the file (and its line where it has one). */
static void test_errors_name_the_file(void **state)
{
    (void)state;
    errors_points_and_formats();
    errors_header_counts();
    errors_ply_ascii();
    errors_ply_binary();
    errors_ply_elements();
    errors_material_urls();
    errors_gltf_containers();
    errors_vertex_budget();
}

static void test_scene_from_bare_model_and_json_override(void **state)
{
    (void)state;
    make_tmp();
    write_text(
        "box.obj",
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n");
    write_text("s.json", "{\"materials\": {\"m\": {\"diffuse\": [0, 0, 1]}},\n"
                         " \"objects\": [{\"mesh\": {\"file\": \"box.obj\"}, \"material\": \"m\",\n"
                         "               \"transform\": {\"translate\": [0, 0, -6]}}]}\n");
    persp_context *ctx = test_context();
    char path[256];
    tmp_path(path, sizeof path, "box.obj");
    persp_scene *s = NULL;
    assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_OK);
    persp_scene_info info;
    persp_scene_get_info(s, &info);
    assert_int_equal(info.objects, 1);
    assert_int_equal(info.lights, 3);
    /* the camera looks at the box's centre from above and in front */
    assert_true(s->camera.eye.y > 0 && s->camera.eye.z > 0 && s->camera.eye.x > 0);
    assert_true(s->camera.znear > 0 && s->camera.zfar > s->camera.znear);
    /* 45 degrees across the image's shorter side, so that a portrait image
     * frames the model as a landscape one does: gluPerspective's
     * projection has P00 = cot(fovx/2), P11 = cot(fovy/2). */
    const double cot = 1.0 / tan(22.5 * 3.14159265358979 / 180.0);
    const int sizes[3][2] = {{400, 200}, {200, 400}, {300, 300}};
    for (int i = 0; i < 3; i++) {
        persp_mat4 proj;
        assert_int_equal(persp_scene_get_camera(s, sizes[i][0], sizes[i][1], NULL, &proj), PERSP_OK);
        const int portrait = sizes[i][0] < sizes[i][1];
        const double shorter = portrait ? proj.m[0] : proj.m[5], longer = portrait ? proj.m[5] : proj.m[0];
        if (fabs(shorter - cot) > 1e-5 || longer > cot + 1e-5)
            fail_msg("%dx%d: P00 %g, P11 %g, want the shorter side's %g", sizes[i][0], sizes[i][1], proj.m[0],
                     proj.m[5], cot);
    }
    /* --up z: the model turned so that its +z points up (+y), the camera
     * framing the turned box: the same view of the box from another side. */
    {
        write_text("tall.obj", "v 0 0 0\nv 1 0 0\nv 0 0 3\nf 1 2 3\n");
        char tall[256];
        tmp_path(tall, sizeof tall, "tall.obj");
        persp_scene_load_desc up = {.model_up = PERSP_MODEL_UP_Z};
        persp_scene *t = NULL;
        assert_int_equal(persp_scene_load_ex(ctx, tall, &up, &t), PERSP_OK);
        persp_scene_object so;
        assert_int_equal(persp_scene_get_object(t, 0, &so), PERSP_OK);
        const persp_vec4 top = persp_mat4_apply(so.model, (persp_vec4){0, 0, 3, 1});
        const persp_vec4 side = persp_mat4_apply(so.model, (persp_vec4){0, 1, 0, 1});
        assert_true(top.x == 0.0f && top.y == 3.0f && top.z == 0.0f);
        assert_true(side.x == 0.0f && side.y == 0.0f && side.z == -1.0f);
        /* the camera looks at the turned triangle's centre, (0.5, 1.5, 0) */
        assert_true(fabsf(t->camera.target.y - 1.5f) < 1e-6f && fabsf(t->camera.target.z) < 1e-6f);
        persp_scene_destroy(t);
        up.model_up = (persp_model_up)7;
        assert_int_equal(persp_scene_load_ex(ctx, tall, &up, &t), PERSP_ERR_INVALID_ARGUMENT);
        assert_null(t);
    }
    uint8_t color[32 * 32 * 4];
    float depth[32 * 32];
    persp_framebuffer fb = {32, 32, color, depth};
    assert_int_equal(persp_render(ctx, s, NULL, &fb, NULL), PERSP_OK);
    /* the centre pixel shows the box, the corner the background */
    const uint8_t *c = &color[4 * (16 * 32 + 16)];
    assert_true(c[0] != 40 || c[1] != 40 || c[2] != 40);
    assert_true(color[0] == 40 && color[3] == 255);
    persp_scene_destroy(s);

    tmp_path(path, sizeof path, "s.json");
    assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_OK);
    assert_int_equal(s->object_count, 1);
    const persp_material *m = &s->materials[s->objects[0].material];
    assert_true(m->diffuse[2] == 1.0f && m->diffuse[0] == 0.0f);
    assert_true(s->objects[0].model.m[14] == -6.0f);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
    remove_tmp();
}

/* text with every `from` replaced by `to` into out. */
static void replaced(const char *text, const char *from, const char *to, char *out, size_t size)
{
    size_t n = 0;
    const size_t fl = strlen(from), tl = strlen(to);
    int found = 0;
    for (const char *p = text; *p;) {
        if (!strncmp(p, from, fl)) {
            assert_true(n + tl < size);
            memcpy(out + n, to, tl), n += tl, p += fl, found = 1;
        } else {
            assert_true(n + 1 < size);
            out[n++] = *p++;
        }
    }
    out[n] = '\0';
    assert_true(found);
}

/* FBX declares its axes and unit (GlobalSettings): persp applies them, so
 * a file exported with +z up stands up and one in centimetres has the size
 * the same model has in metres. tests/data/models/triangle.fbx: metres, y
 * up, the triangle's node translated by (0, 0, -1). */
static void test_fbx_axes_and_unit(void **state)
{
    (void)state;
    static char text[4096], a[4096], b[4096];
    source_text("tests/data/models/triangle.fbx", text, sizeof text);
    static const struct {
        const char *what, *from[3], *to[3];
        float t[3];   /* the part's translation */
        float top[3]; /* where the file's vertex (0, 1, 0) lands */
    } cases[] = {
        {"metres, y up", {NULL}, {NULL}, {0, 0, -1}, {0, 1, -1}},
        {"centimetres", {"\"\",100"}, {"\"\",1"}, {0, 0, -0.01f}, {0, 0.01f, -0.01f}},
        /* Blender's "Up: Z, Forward: Y": z is up, -y towards the viewer */
        {"z up",
         {"\"UpAxis\", \"int\", \"Integer\", \"\",1", "\"FrontAxis\", \"int\", \"Integer\", \"\",2",
          "\"FrontAxisSign\", \"int\", \"Integer\", \"\",1"},
         {"\"UpAxis\", \"int\", \"Integer\", \"\",2", "\"FrontAxis\", \"int\", \"Integer\", \"\",1",
          "\"FrontAxisSign\", \"int\", \"Integer\", \"\",-1"},
         {0, -1, 0},
         {0, -1, -1}},
        /* not three distinct axes: left as the file has them */
        {"bad axes", {"\"FrontAxis\", \"int\", \"Integer\", \"\",2"}, {"\"FrontAxis\", \"int\", \"Integer\", \"\",1"},
         {0, 0, -1}, {0, 1, -1}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(a, sizeof a, "%s", text);
        for (int k = 0; k < 3 && cases[i].from[k]; k++) {
            replaced(a, cases[i].from[k], cases[i].to[k], b, sizeof b);
            snprintf(a, sizeof a, "%s", b);
        }
        loaded l;
        load_text(&l, a, "t.fbx");
        if (l.st != PERSP_OK) fail_msg("%s: %s", cases[i].what, persp_context_error(l.ctx));
        const persp_mat4 *t = &l.model.parts[0].transform;
        persp_vec4 top = persp_mat4_apply(*t, (persp_vec4){0, 1, 0, 1});
        const float got[3] = {top.x, top.y, top.z};
        for (int k = 0; k < 3; k++)
            if (fabsf(t->m[12 + k] - cases[i].t[k]) > 1e-6f || fabsf(got[k] - cases[i].top[k]) > 1e-6f)
                fail_msg("%s: translation (%g %g %g), top (%g %g %g)", cases[i].what, (double)t->m[12],
                         (double)t->m[13], (double)t->m[14], (double)got[0], (double)got[1], (double)got[2]);
        unload(&l);
    }
}

/* glTF names its buffers and images by URI (glTF 2.0 §3.3.1): "%20" is a
 * space, "%C3%A9" an é, as exporters write them. */
static void test_gltf_uri_names(void **state)
{
    (void)state;
    static char text[8192], a[8192];
    embedded_gltf(text, sizeof text);
    const char *uri = strstr(text, "\"data:application/octet-stream;base64,");
    assert_non_null(uri);
    const char *b64 = uri + strlen("\"data:application/octet-stream;base64,");
    const char *end = strchr(b64, '"');
    /* the buffer's bytes into "my buffer é.bin" */
    static unsigned char bin[4096];
    size_t n = 0;
    unsigned acc = 0;
    int bits = 0;
    for (const char *p = b64; p < end; p++) {
        const char *alpha = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char *at = strchr(alpha, *p);
        if (*p == '=' || !at) break;
        acc = (acc << 6) | (unsigned)(at - alpha), bits += 6;
        if (bits >= 8) bits -= 8, bin[n++] = (unsigned char)(acc >> bits);
    }
    make_tmp();
    write_file("my buffer \xc3\xa9.bin", bin, n);
    snprintf(a, sizeof a, "%.*s\"my%%20buffer%%20%%C3%%A9.bin\"%s", (int)(uri - text), text, end + 1);
    /* the image, moved out to a file with a space in its name */
    const char *img = strstr(a, "\"data:image/png;base64,");
    assert_non_null(img);
    static char b[8192];
    snprintf(b, sizeof b, "%.*s\"tex%%20one.png\"%s", (int)(img - a), a, strchr(img + 1, '"') + 1);
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(NULL, &ctx), PERSP_OK);
    write_png(ctx, "tex one.png", 3, 3);
    persp_context_destroy(ctx);
    write_text("uri.gltf", b);
    char path[1024];
    tmp_path(path, sizeof path, "uri.gltf");
    loaded l;
    load_path(&l, path);
    if (l.st != PERSP_OK) fail_msg("%s", persp_context_error(l.ctx));
    assert_int_equal(l.warn.count, 0);
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    assert_true(material_of(&l, 0)->texture >= 0);
    assert_int_equal(persp_texture_width(l.scene->textures[material_of(&l, 0)->texture]), 3);
    unload(&l);
    /* A name whose file is missing is named decoded, with the line. */
    static char c[8192];
    replaced(b, "tex%20one.png", "tex%20two.png", c, sizeof c);
    write_text("uri2.gltf", c);
    tmp_path(path, sizeof path, "uri2.gltf");
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_int_equal(l.warn.count, 1);
    assert_non_null(strstr(l.warn.last, "uri2.gltf:"));
    assert_non_null(strstr(l.warn.last, "cannot load texture 'tex two.png'"));
    assert_true(material_of(&l, 0)->texture < 0);
    unload(&l);
    remove_tmp();
}

/* A textured material on a mesh that has no texture coordinates (a UV
 * layer removed before export) would fetch one texel everywhere: drawn
 * untextured, with a warning naming the material; a scene's texgen gives
 * such a mesh coordinates and keeps the texture. */
static void test_texture_without_coordinates(void **state)
{
    (void)state;
    make_tmp();
    persp_context *ctx = test_context();
    write_png(ctx, "t.png", 2, 2);
    persp_context_destroy(ctx);
    write_text("t.mtl", "newmtl skin\nmap_Kd t.png\n");
    write_text("bare.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl skin\nf 1 2 3\n");
    write_text("uv.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl skin\n"
                         "f 1/1 2/2 3/3\n");
    char path[1024];
    tmp_path(path, sizeof path, "bare.obj");
    loaded l;
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_OK);
    assert_true(mesh_of(&l, 0)->no_uv);
    unload(&l);
    /* The scene around the bare model: the warning, and no texture drawn. */
    persp_context_desc cd = {0};
    assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
    warnings w = {0};
    persp_context_set_warning_handler(ctx, on_warning, &w);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    assert_int_equal(w.count, 1);
    assert_non_null(strstr(w.last, "bare.obj: material 'skin' has a texture, but the mesh it is on has no texture "
                                   "coordinates; drawing it untextured"));
    persp_scene_object o;
    assert_int_equal(persp_scene_get_object(scene, 0, &o), PERSP_OK);
    assert_int_equal(o.material.texture, -1);
    persp_scene_destroy(scene);
    /* With coordinates: no warning, textured. */
    tmp_path(path, sizeof path, "uv.obj");
    w.count = 0;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    assert_int_equal(w.count, 0);
    assert_int_equal(persp_scene_get_object(scene, 0, &o), PERSP_OK);
    assert_true(o.material.texture >= 0);
    persp_scene_destroy(scene);
    /* A scene that generates coordinates for the bare mesh keeps the texture. */
    write_text("gen.json", "{\"objects\": [{\"mesh\": \"bare.obj\", \"texgen\": {\"mode\": \"spherical\"}}]}");
    write_text("nogen.json", "{\"objects\": [{\"mesh\": \"bare.obj\"}]}");
    tmp_path(path, sizeof path, "gen.json");
    w.count = 0;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    assert_int_equal(w.count, 0);
    assert_int_equal(persp_scene_get_object(scene, 0, &o), PERSP_OK);
    assert_true(o.material.texture >= 0);
    persp_scene_destroy(scene);
    tmp_path(path, sizeof path, "nogen.json");
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    assert_int_equal(w.count, 1);
    assert_int_equal(persp_scene_get_object(scene, 0, &o), PERSP_OK);
    assert_int_equal(o.material.texture, -1);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    remove_tmp();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj_quad_from_memory),
        cmocka_unit_test(test_gltf_missing_buffer),
        cmocka_unit_test(test_gltf_uri_names),
        cmocka_unit_test(test_fbx_axes_and_unit),
        cmocka_unit_test(test_texture_without_coordinates),
        cmocka_unit_test(test_obj_indices_colours_polygons),
        cmocka_unit_test(test_obj_smooth_normals_when_missing),
        cmocka_unit_test(test_obj_mtl_texture_and_quirks),
        cmocka_unit_test(test_names_in_another_case),
        cmocka_unit_test(test_obj_missing_files_warn),
        cmocka_unit_test(test_gltf_embedded_texture_and_nodes),
        cmocka_unit_test(test_more_formats),
        cmocka_unit_test(test_ply_vertex_colours),
        cmocka_unit_test(test_ply_bare_text_line_in_header),
        cmocka_unit_test(test_stl_ascii),
        cmocka_unit_test(test_stl_zero_normals_made_afresh),
        cmocka_unit_test(test_errors_name_the_file),
        cmocka_unit_test(test_zero_area_model_refused),
        cmocka_unit_test(test_scene_from_bare_model_and_json_override),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
