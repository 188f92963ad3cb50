/* persp's OBJ + MTL reader (src/model/obj.c): every statement form, relative
 * indices, polygons, continuation lines, line ends, errors with their line
 * numbers, materials and map_Kd options, generated normals, runs of faces,
 * and files read in chunks with lines across a chunk's end. */
#include "model_load.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "model/model.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void expect_error(const char *text, const char *name, persp_status st, const char *what)
{
    loaded l;
    load_text(&l, text, name);
    if (l.st != st || !strstr(persp_context_error(l.ctx), what))
        fail_msg("%s: status %d, '%s', expected '%s'", name, (int)l.st, persp_context_error(l.ctx),
                 what);
    unload(&l);
}

/* Signed area in the xy plane of all triangles (positive: front faces). */
static double xy_area(const persp_mesh *m)
{
    double area = 0;
    for (size_t t = 0; t < m->index_count; t += 3) {
        const float *a = m->vertices[m->indices[t]].pos, *b = m->vertices[m->indices[t + 1]].pos,
                    *c = m->vertices[m->indices[t + 2]].pos;
        double cross = ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
                       ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
        assert_true(cross >= -1e-9);
        area += 0.5 * cross;
    }
    return area;
}

static const persp_vertex *vertex_at(const persp_mesh *m, float x, float y, float z)
{
    for (size_t i = 0; i < m->vertex_count; i++) {
        const float *p = m->vertices[i].pos;
        if (p[0] == x && p[1] == y && p[2] == z) return &m->vertices[i];
    }
    return NULL;
}

static char tmpdir[64];

static void tmp_path(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", tmpdir, name);
}

static void write_file(const char *name, const void *data, size_t size) { test_write_file(tmpdir, name, data, size); }

static void write_text(const char *name, const char *text)
{
    write_file(name, text, strlen(text));
}

/* --------------------------------------------------------------- tests */

static void test_statement_forms(void **state)
{
    (void)state;
    loaded l;
    /* Homogeneous w, colours, one to three texture numbers, each corner
     * form, tabs and repeated blanks, comments, statements persp passes
     * over, lines and points. */
    load_text(&l,
              "# comment\n\n"
              "v 0 0 0 1\nv\t2  0 0 2\n  v 1 1 0\nv 0 1 0 0.5 0.25 1\n"
              "vt 0\nvt 1 0\nvt 1 1 0\nvn 0 0 1\n"
              "o thing\ng part\ns off\nvp 0.5\ncstype bezier\nl 1 2\np 3\n"
              "f 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\n",
              "forms.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(l.model.part_count, 1);
    assert_int_equal(m->index_count, 6);
    assert_true(m->has_normals);
    const persp_vertex *v = vertex_at(m, 1, 0, 0); /* "2 0 0 2": x / w */
    assert_non_null(v);
    assert_true(v->uv[0] == 1.0f && v->uv[1] == 0.0f);
    v = vertex_at(m, 0, 1, 0);
    assert_non_null(v);
    assert_true(v->color[0] == 0.5f && v->color[1] == 0.25f && v->color[2] == 1.0f);
    v = vertex_at(m, 1, 1, 0);
    assert_true(v->color[0] == 1.0f && v->normal[2] == 1.0f); /* no colour given: white */
    assert_true(fabs(xy_area(m) - 1.0) < 1e-6);
    unload(&l);

    /* Every corner form in one file, generated normals. */
    load_text(&l, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2/1 3/\n", "mixed.obj");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    assert_int_equal(l.warn.count, 0);
    unload(&l);

    /* Faces of fewer than three corners are dropped with one warning a
     * file, at the first; a material no library defines is drawn grey with
     * one warning, where it is first used. */
    load_text(&l,
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nf\nf 1 2\nusemtl ghost\nf 1 2 3\nf 3\n"
              "usemtl ghost\nf 1 2 3\n",
              "short.obj");
    assert_int_equal(mesh_of(&l, 0)->index_count, 6);
    assert_int_equal(l.warn.count, 2);
    assert_non_null(strstr(l.warn.last, "short.obj:7: material 'ghost' is defined by no material library"));
    unload(&l);
    load_text(&l, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 3\nf 1\n", "short2.obj");
    assert_int_equal(l.warn.count, 1);
    assert_non_null(strstr(l.warn.last, "short2.obj:5: 2 faces of fewer than three corners dropped"));
    unload(&l);
}

static void test_negative_indices_and_polygons(void **state)
{
    (void)state;
    loaded l;
    /* An L of six corners (concave at (1, 1)) given with relative
     * indices: four triangles covering area 3, all front-facing. */
    load_text(&l,
              "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
              "f -6 -5 -4 -3 -2 -1\n",
              "ell.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 12);
    assert_true(fabs(xy_area(m) - 3.0) < 1e-6);
    unload(&l);
    /* A concave quad (the dart's corner at (1, 0.5)) is cut from that
     * corner: the two triangles stay inside it. */
    load_text(&l, "v 0 0 0\nv 2 0 0\nv 1 0.5 0\nv 1 2 0\nf 1 2 4 3\nf 1 2 3 4\n", "dart.obj");
    m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 6 * 2);
    unload(&l);
    load_text(&l, "v 0 0 0\nv 2 0 0\nv 1 2 0\nv 1 0.5 0\nf 1 2 3 4\n", "dart2.obj");
    m = mesh_of(&l, 0);
    assert_true(fabs(xy_area(m) - 1.25) < 1e-6);
    unload(&l);
    /* A disc of 300 corners, past the ear clipping's limit: a fan of 298
     * triangles covering it. */
    static char disc[300 * 40 + 4000];
    int n = 0;
    for (int i = 0; i < 300; i++) {
        double a = 2 * 3.14159265358979 * i / 300;
        n += snprintf(disc + n, sizeof disc - (size_t)n, "v %.6f %.6f 0\n", cos(a), sin(a));
    }
    n += snprintf(disc + n, sizeof disc - (size_t)n, "f");
    for (int i = 1; i <= 300; i++)
        n += snprintf(disc + n, sizeof disc - (size_t)n, " %d", i);
    snprintf(disc + n, sizeof disc - (size_t)n, "\n");
    load_text(&l, disc, "disc.obj");
    m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 3 * 298);
    assert_true(fabs(xy_area(m) - 150 * sin(2 * 3.14159265358979 / 300)) < 1e-4);
    unload(&l);
    /* A ring: an outline and a hole joined by a cut (two corners at each
     * end of the cut), as Assimp's concave_polygon.obj: area 16 - 4. */
    load_text(&l,
              "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 1 1 0\nv 1 3 0\nv 3 3 0\nv 3 1 0\n"
              "f 1 2 3 4 1 5 6 7 8 5\n",
              "ring.obj");
    m = mesh_of(&l, 0);
    assert_int_equal(m->index_count, 3 * 8);
    assert_true(fabs(xy_area(m) - 12.0) < 1e-5);
    unload(&l);
}

static void test_line_ends_bom_and_continuation(void **state)
{
    (void)state;
    static const char *texts[] = {
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n",
        "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r",
        "\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3",
        "v 0 0 \\\n 0\nv 1 \\\r\n0 0\nv 0 1 0\nf 1 \\\n2 \\\n 3\n",
    };
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        loaded l;
        load_text(&l, texts[i], "ends.obj");
        if (l.st != PERSP_OK) fail_msg("text %zu: %s", i, persp_context_error(l.ctx));
        assert_int_equal(mesh_of(&l, 0)->index_count, 3);
        unload(&l);
    }
    /* Lines are counted the same through CR-only ends and continuations. */
    expect_error("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 4\r", "cr.obj", PERSP_ERR_FORMAT,
                 "cr.obj:4: vertex index 4 out of range");
    expect_error("v 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "cont.obj", PERSP_ERR_FORMAT,
                 "cont.obj:5: vertex index 4");
}

static void test_errors_with_lines(void **state)
{
    (void)state;
    const char *tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    char text[256];
    snprintf(text, sizeof text, "%sf 1 2 0\n", tri);
    expect_error(text, "zero.obj", PERSP_ERR_FORMAT, "zero.obj:4: vertex index 0");
    snprintf(text, sizeof text, "%sf 1 2 -4\n", tri);
    expect_error(text, "neg.obj", PERSP_ERR_FORMAT, "neg.obj:4: vertex index -4 out of range");
    snprintf(text, sizeof text, "%svt 0 0\nf 1/2 2/1 3/1\n", tri);
    expect_error(text, "vt.obj", PERSP_ERR_FORMAT, "vt.obj:5: texture coordinate index 2");
    snprintf(text, sizeof text, "%sf 1//1 2//1 3//1\n", tri);
    expect_error(text, "vn.obj", PERSP_ERR_FORMAT, "vn.obj:4: normal index 1 out of range");
    snprintf(text, sizeof text, "%sf 1 2 x3\n", tri);
    expect_error(text, "corner.obj", PERSP_ERR_FORMAT, "corner.obj:4: malformed face corner 'x3'");
    expect_error("v 0 0 0\nv 1 0,5 0\nv 0 1 0\nf 1 2 3\n", "num.obj", PERSP_ERR_FORMAT,
                 "num.obj:2: malformed number '0,5'");
    expect_error("v 0 0 0\nv 1 0\n", "few.obj", PERSP_ERR_FORMAT,
                 "few.obj:2: expected 3, 4 or 6 numbers after 'v'");
    snprintf(text, sizeof text, "%sv nan 0 0\nf 1 2 3\n", tri);
    expect_error(text, "nan.obj", PERSP_ERR_FORMAT, "nan.obj:4: a vertex position is not finite");
    snprintf(text, sizeof text, "%sv 1e39 0 0\nf 1 2 3\n", tri);
    expect_error(text, "inf.obj", PERSP_ERR_FORMAT, "inf.obj:4: a vertex position is not finite");
    expect_error("v 0 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "w.obj", PERSP_ERR_FORMAT,
                 "w.obj:1: a vertex with w = 0");
    expect_error("v 0 0 0\nv 1 0 0\nf 1 2\nl 1 2\n", "two.obj", PERSP_ERR_FORMAT,
                 "two.obj: the model has no triangles to draw");
    /* A line longer than the cap is refused with its number. */
    size_t big = ((size_t)1 << 20) + 100;
    char *longline = malloc(big + 64);
    assert_non_null(longline);
    int head = snprintf(longline, 64, "%s# ", tri);
    memset(longline + head, 'x', big);
    strcpy(longline + head + big, "\n");
    expect_error(longline, "long.obj", PERSP_ERR_FORMAT, "long.obj:4: a line longer than 1 MiB");
    free(longline);
    /* Numbers as exporters write them. */
    loaded l;
    load_text(&l, "v +1 2. .5\nv -1e2 2.E1 3.1e-1\nv 1E+2 0 0\nf 1 2 3\n", "formats.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_non_null(vertex_at(m, 1.0f, 2.0f, 0.5f));
    assert_non_null(vertex_at(m, -100.0f, 20.0f, 0.31f));
    assert_non_null(vertex_at(m, 100.0f, 0.0f, 0.0f));
    unload(&l);
}

static void test_materials_and_map_options(void **state)
{
    (void)state;
    assert_int_equal(test_tmpdir_make(tmpdir, sizeof tmpdir, "obj"), 0);
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 4, 2, &img), PERSP_OK);
    memset(img.pixels, 200, (size_t)img.stride * 2);
    char path[1024];
    tmp_path(path, sizeof path, "my wall.png");
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_OK);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
    write_text("a b.mtl",
               "newmtl shiny red\nKd 1 0 0\nKs 0.5\nKa 0 0 0\nNs 5000\nd 0.5\nTr 0.5\n"
               "illum 2\nmap_Kd -clamp on -s 1 1 1 -o 0 0 -bm 0.5 -blendu off my wall.png\n"
               "newmtl plain\nKa 0.3 0.3 0.3\n");
    write_text("c.mtl", "newmtl other\nKd 0 0 1\nmap_Kd missing.png\n");
    /* mtllib naming a file with a space, then two libraries on one line;
     * usemtl runs: red, red again (no new run), plain, an unknown name,
     * then faces of a second group. */
    write_text("m.obj", "mtllib a b.mtl\nmtllib c.mtl gone.mtl\n"
                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                        "f 1 2 3\nusemtl shiny red\nf 1/1 2/2 3/3\nusemtl shiny red\nf 1 2 3\n"
                        "usemtl plain\nf 1 2 3\nusemtl nowhere\nf 1 2 3\nusemtl other\nf 1 2 3\n"
                        "g second\nmtllib c.mtl gone.mtl\nf 1 2 3\n");
    tmp_path(path, sizeof path, "m.obj");
    loaded l;
    load_path(&l, path);
    mesh_of(&l, 0);
    assert_int_equal(l.model.part_count, 6);
    /* before any usemtl: persp's default */
    persp_material def = persp__material_default();
    assert_memory_equal(material_of(&l, 0)->diffuse, def.diffuse, sizeof def.diffuse);
    const persp_material *red = material_of(&l, 1);
    assert_int_equal(mesh_of(&l, 1)->index_count, 6);
    assert_true(red->diffuse[0] == 1.0f && red->diffuse[1] == 0.0f);
    assert_true(red->specular[1] == 0.5f && red->shininess == 1000.0f);
    assert_memory_equal(red->ambient, def.ambient, sizeof def.ambient); /* black: not taken */
    assert_true(red->texture >= 0);
    assert_int_equal(red->sampler.wrap_s, PERSP_WRAP_CLAMP_TO_EDGE);
    assert_int_equal(red->env, PERSP_TEXENV_MODULATE);
    const persp_material *plain = material_of(&l, 2);
    assert_true(plain->ambient[0] == 0.3f && fabsf(plain->diffuse[0] - 0.6f) < 1e-6f);
    assert_true(plain->texture == -1);
    /* an unknown name: an empty MTL material (grey), as Assimp made it */
    assert_true(fabsf(material_of(&l, 3)->diffuse[0] - 0.6f) < 1e-6f);
    assert_true(material_of(&l, 4)->diffuse[2] == 1.0f && material_of(&l, 4)->texture == -1);
    assert_true(material_of(&l, 5)->diffuse[2] == 1.0f); /* the group keeps the material */
    /* warnings: the missing library (with the OBJ's line; the repeated
     * statement is read once) and the missing texture (with the library's
     * line) */
    assert_int_equal(l.warn.count, 2);
    assert_non_null(strstr(
        l.warn.last, "m.obj (via c.mtl:3): material 'other': cannot load texture 'missing.png'"));
    unload(&l);
    test_tmpdir_remove(tmpdir);
}

/* More material libraries than the reader keeps: the rest are passed over
 * with one warning, and a later statement, new or repeated, reads nothing
 * past the libraries kept (an out-of-bounds read, found by the model
 * fuzzer). */
static void test_many_material_libraries(void **state)
{
    (void)state;
    char text[8192];
    size_t n = 0;
    for (int i = 0; i < 70; i++) n += (size_t)snprintf(text + n, sizeof text - n, "mtllib lib%02d.mtl\n", i);
    n += (size_t)snprintf(text + n, sizeof text - n, "mtllib lib03.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_true(n < sizeof text);
    loaded l;
    load_text(&l, text, "libs.obj");
    assert_int_equal(mesh_of(&l, 0)->index_count, 3);
    assert_non_null(strstr(l.warn.last, "more than 64 material library statements"));
    unload(&l);
}

/* A texture named by a Windows absolute path (the exporter's machine):
 * only its last part is looked for, beside the model, and the warning says
 * so when it is not there either. */
static void test_windows_texture_path(void **state)
{
    (void)state;
    assert_int_equal(test_tmpdir_make(tmpdir, sizeof tmpdir, "obj"), 0);
    write_text("w.mtl", "newmtl a\nmap_Kd C:\\Users\\me\\tex\\wood.png\n");
    write_text("w.obj", "mtllib w.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                        "usemtl a\nf 1/1 2/2 3/3\n");
    char path[1024];
    tmp_path(path, sizeof path, "w.obj");
    loaded l;
    load_path(&l, path);
    assert_true(material_of(&l, 0)->texture == -1);
    assert_non_null(strstr(l.warn.last, "cannot load texture 'C:/Users/me/tex/wood.png' (a Windows path; "
                                        "no 'wood.png' beside the model either)"));
    unload(&l);
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 2, 2, &img), PERSP_OK);
    memset(img.pixels, 90, (size_t)img.stride * 2);
    char png[1024];
    tmp_path(png, sizeof png, "wood.png");
    assert_int_equal(persp_image_write_png(ctx, png, &img), PERSP_OK);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
    load_path(&l, path);
    assert_true(material_of(&l, 0)->texture >= 0);
    assert_int_equal(l.warn.count, 0);
    unload(&l);
    test_tmpdir_remove(tmpdir);
}

static const persp_vertex *find_normal(const persp_mesh *m, const float *pos, float nx, float ny,
                                       float nz)
{
    for (size_t i = 0; i < m->vertex_count; i++) {
        const persp_vertex *v = &m->vertices[i];
        if (!memcmp(v->pos, pos, sizeof v->pos) && fabsf(v->normal[0] - nx) < 1e-5f &&
            fabsf(v->normal[1] - ny) < 1e-5f && fabsf(v->normal[2] - nz) < 1e-5f)
            return v;
    }
    return NULL;
}

static void test_generated_normals(void **state)
{
    (void)state;
    loaded l;
    /* A cube of 8 positions: faces 90 degrees apart keep their own
     * normals, so each corner becomes three vertices. */
    load_text(&l,
              "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
              "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n",
              "cube.obj");
    const persp_mesh *m = mesh_of(&l, 0);
    assert_int_equal(m->vertex_count, 24);
    assert_true(m->has_normals);
    const float corner[3] = {1, 1, 1};
    assert_non_null(find_normal(m, corner, 1, 0, 0));
    assert_non_null(find_normal(m, corner, 0, 1, 0));
    assert_non_null(find_normal(m, corner, 0, 0, 1));
    unload(&l);
    /* A low cone (a fan of 8 triangles rising 10 degrees to the apex):
     * the apex is one vertex with the averaged normal, straight up. */
    char text[1024];
    int n = snprintf(text, sizeof text, "v 0 0.176327 0\n");
    for (int i = 0; i < 8; i++) {
        double a = i * 3.14159265358979 / 4;
        n += snprintf(text + n, sizeof text - (size_t)n, "v %.6f 0 %.6f\n", cos(a), -sin(a));
    }
    for (int i = 0; i < 8; i++)
        n += snprintf(text + n, sizeof text - (size_t)n, "f 1 %d %d\n", 2 + i, 2 + (i + 1) % 8);
    load_text(&l, text, "cone.obj");
    m = mesh_of(&l, 0);
    assert_int_equal(m->vertex_count, 9);
    const float apex[3] = {0, 0.176327f, 0};
    assert_non_null(find_normal(m, apex, 0, 1, 0));
    unload(&l);
    /* A polygon corner counts once in its neighbours' normals, however
     * many of the polygon's triangles hold it (Assimp kept one vertex per
     * polygon corner): at the origin, the quad's +z and the triangle's
     * normal (35 degrees away) weigh the same. */
    load_text(&l,
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0 0.5\nv 0 -1 0.5\nf 1 2 3 4\nf 1 5 6\n",
              "weights.obj");
    m = mesh_of(&l, 0);
    const float origin[3] = {0, 0, 0};
    const double k = 1 / sqrt(1.5), len = sqrt(2 * (0.5 * k) * (0.5 * k) + (1 + k) * (1 + k));
    if (!find_normal(m, origin, (float)(0.5 * k / len), (float)(0.5 * k / len),
                     (float)((1 + k) / len)))
        fail_msg("the quad's corner counted more than once");
    unload(&l);
    /* Positions closer than 1e-4 of the run's box diagonal smooth
     * together (Assimp's epsilon): the roof's two faces meet at y = 1 and
     * y = 1.00001; the corners there tilt between the faces. */
    load_text(&l,
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 1.00001 0\nv 1 1.00001 0\n"
              "v 0 2 0.36\nv 1 2 0.36\nf 1 2 3 4\nf 5 6 8 7\n",
              "near.obj");
    m = mesh_of(&l, 0);
    int tilted = 0;
    for (size_t i = 0; i < m->vertex_count; i++)
        if (m->vertices[i].pos[1] > 0.5f && m->vertices[i].pos[1] < 1.5f)
            tilted += m->vertices[i].normal[1] < -0.05f && m->vertices[i].normal[1] > -0.3f;
    assert_int_equal(tilted, 4);
    unload(&l);
    /* The file's normals when every corner has one; all made afresh when
     * one is zero. */
    load_text(&l, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0.6 0 0.8\nf 1//1 2//1 3//1\n", "given.obj");
    m = mesh_of(&l, 0);
    assert_true(m->vertices[0].normal[0] == 0.6f);
    unload(&l);
    load_text(&l, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n", "zero.obj");
    m = mesh_of(&l, 0);
    assert_true(m->vertices[0].normal[2] == 1.0f);
    unload(&l);
}

/* A file of more than one chunk (1 MiB) read from disk: a vertex line
 * across the first chunk's end, or a CR LF pair split by it. */
static void write_split(const char *name, size_t at)
{
    const size_t cap = ((size_t)1 << 20) + 4096;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t len = (size_t)snprintf(text, cap, "v 0 0 0\r\nv 1 0 0\r\n");
    /* one comment line ending just before at */
    text[len++] = '#';
    while (len < at - 2)
        text[len++] = '.';
    text[len++] = '\r';
    text[len++] = '\n';
    len += (size_t)snprintf(text + len, cap - len, "v 0.25 0.75 0.5\r\nf 1 2 3\r\n");
    write_file(name, text, len);
    free(text);
}

static void test_chunked_file(void **state)
{
    (void)state;
    assert_int_equal(test_tmpdir_make(tmpdir, sizeof tmpdir, "obj"), 0);
    const size_t chunk = (size_t)1 << 20;
    write_split("across.obj", chunk - 5); /* "v 0.25 ..." spans the chunk's end */
    write_split("crlf.obj", chunk + 1);   /* CR the chunk's last byte, LF the next */
    const char *names[] = {"across.obj", "crlf.obj"};
    for (int i = 0; i < 2; i++) {
        char path[1024];
        tmp_path(path, sizeof path, names[i]);
        loaded l;
        load_path(&l, path);
        const persp_mesh *m = mesh_of(&l, 0);
        assert_int_equal(m->index_count, 3);
        assert_non_null(vertex_at(m, 0.25f, 0.75f, 0.5f));
        unload(&l);
    }
    /* An error past the chunk names the right line (the comment is line 3). */
    char path[1024];
    tmp_path(path, sizeof path, "crlf.obj");
    FILE *f = fopen(path, "ab");
    assert_non_null(f);
    fputs("f 1 2 9\r\n", f);
    assert_int_equal(fclose(f), 0);
    loaded l;
    load_path(&l, path);
    assert_int_equal(l.st, PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(l.ctx), "crlf.obj:6: vertex index 9"));
    unload(&l);
    test_tmpdir_remove(tmpdir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_statement_forms),
        cmocka_unit_test(test_negative_indices_and_polygons),
        cmocka_unit_test(test_line_ends_bom_and_continuation),
        cmocka_unit_test(test_errors_with_lines),
        cmocka_unit_test(test_materials_and_map_options),
        cmocka_unit_test(test_windows_texture_path),
        cmocka_unit_test(test_many_material_libraries),
        cmocka_unit_test(test_generated_normals),
        cmocka_unit_test(test_chunked_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
