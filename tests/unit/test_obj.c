/* OBJ and MTL loading: statements, index forms, triangulation, normals,
 * materials and textures from files, and errors with file:line:col. */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "io/obj.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct loaded {
    persp_context *ctx;
    persp_scene *scene;
    persp_obj_result res;
    persp_status st;
} loaded;

static loaded load_text(const char *text)
{
    loaded l;
    memset(&l, 0, sizeof l);
    l.ctx = test_context();
    assert_int_equal(persp__scene_new(l.ctx, &l.scene), PERSP_OK);
    l.st = persp__obj_load_memory(l.scene, text, strlen(text), "t.obj", NULL, NULL, &l.res);
    return l;
}

static void unload(loaded *l)
{
    persp__obj_result_free(l->ctx, &l->res);
    persp_scene_destroy(l->scene);
    persp_context_destroy(l->ctx);
}

static const persp_mesh *mesh0(const loaded *l)
{
    assert_int_equal(l->st, PERSP_OK);
    assert_true(l->res.part_count >= 1);
    return &l->scene->meshes[l->res.parts[0].mesh];
}

/* Position of the vertex at index slot k of the mesh. */
static const float *pos_at(const persp_mesh *m, size_t k) { return m->vertices[m->indices[k]].pos; }

static void test_quad_all_forms(void **state)
{
    (void)state;
    loaded l = load_text("# a unit quad\n"
                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                         "vn 0 0 1\n"
                         "g quad\no thing\ns 1\n"
                         "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
    const persp_mesh *m = mesh0(&l);
    assert_int_equal(l.res.part_count, 1);
    assert_int_equal(m->vertex_count, 4);
    assert_int_equal(m->index_count, 6);
    assert_true(m->has_normals);
    /* fan: (v0, v1, v2), (v0, v2, v3) */
    const int order[6] = {0, 1, 2, 0, 2, 3};
    const float corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 6; k++) {
        const persp_vertex *v = &m->vertices[m->indices[k]];
        assert_true(v->pos[0] == corners[order[k]][0] && v->pos[1] == corners[order[k]][1]);
        assert_true(v->uv[0] == corners[order[k]][0] && v->uv[1] == corners[order[k]][1]);
        assert_true(v->normal[2] == 1.0f && v->color[0] == 1.0f);
    }
    /* the material is the default one */
    const persp_material *mat = &l.scene->materials[l.res.parts[0].material];
    persp_material def = persp__material_default();
    assert_memory_equal(mat->diffuse, def.diffuse, sizeof def.diffuse);
    unload(&l);
}

static void test_pentagon_fan_and_normals(void **state)
{
    (void)state;
    /* a convex pentagon in the plane z = 2 x + 1, no normals given */
    char text[512];
    int n = 0;
    for (int i = 0; i < 5; i++) {
        double a = 2 * 3.14159265358979 * i / 5, x = cos(a), y = sin(a);
        n += snprintf(text + n, sizeof text - (size_t)n, "v %.9f %.9f %.9f\n", x, y, 2 * x + 1);
    }
    snprintf(text + n, sizeof text - (size_t)n, "f 1 2 3 4 5\n");
    loaded l = load_text(text);
    const persp_mesh *m = mesh0(&l);
    assert_int_equal(m->index_count, 9);
    assert_false(m->has_normals);
    for (int t = 0; t < 3; t++) {
        assert_int_equal(m->indices[3 * t], m->indices[0]);
        assert_int_equal(m->indices[3 * t + 1], (uint32_t)(t + 1));
        assert_int_equal(m->indices[3 * t + 2], (uint32_t)(t + 2));
    }
    /* plane normal of z = 2x + 1, pointing +z for the anticlockwise order */
    double nn[3] = {-2, 0, 1}, len = sqrt(5.0);
    for (size_t i = 0; i < m->vertex_count; i++)
        for (int c = 0; c < 3; c++) assert_true(fabs(m->vertices[i].normal[c] - nn[c] / len) < 1e-5);
    unload(&l);
}

static void test_negative_indices(void **state)
{
    (void)state;
    loaded a = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n"
                         "v 5 5 5\nv 6 5 5\nv 5 6 5\nf 4//1 5//1 6//1\n");
    loaded b = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvn 0 0 1\nf -3/-1/-1 -2/-1/-1 -1/-1/-1\n"
                         "v 5 5 5\nv 6 5 5\nv 5 6 5\nf -3//-1 -2//-1 -1//-1\n");
    const persp_mesh *ma = mesh0(&a), *mb = mesh0(&b);
    assert_int_equal(ma->index_count, 6);
    assert_int_equal(mb->index_count, ma->index_count);
    for (size_t k = 0; k < ma->index_count; k++) {
        assert_memory_equal(pos_at(ma, k), pos_at(mb, k), 3 * sizeof(float));
        assert_memory_equal(ma->vertices[ma->indices[k]].uv, mb->vertices[mb->indices[k]].uv, 2 * sizeof(float));
    }
    assert_true(pos_at(mb, 3)[0] == 5.0f && pos_at(mb, 4)[0] == 6.0f);
    unload(&a);
    unload(&b);
}

static void test_shared_corners_and_colours(void **state)
{
    (void)state;
    /* two triangles sharing an edge: 4 distinct vertices, smooth normals
     * averaged across the shared ones; the second vertex has a colour */
    loaded l = load_text("v 0 0 0\nv 1 0 0 0.5 0.25 1\nv 0 1 0\nv 1 1 1\nf 1 2 3\nf 2 4 3\nf 3 2 4\n");
    const persp_mesh *m = mesh0(&l);
    assert_int_equal(m->vertex_count, 4);
    assert_int_equal(m->index_count, 9);
    const persp_vertex *v2 = &m->vertices[m->indices[1]];
    assert_true(v2->pos[0] == 1.0f && v2->color[0] == 0.5f && v2->color[1] == 0.25f && v2->color[2] == 1.0f);
    assert_true(m->vertices[m->indices[0]].color[0] == 1.0f);
    unload(&l);
}

typedef struct bad_case {
    const char *text;
    persp_status status;
    const char *message;
} bad_case;

static void test_malformed(void **state)
{
    (void)state;
    static const bad_case cases[] = {
        {"v 1 x 3\n", PERSP_ERR_FORMAT, "t.obj:1:5: expected a finite number after 'v', found 'x'"},
        {"\n\nv 1 2\n", PERSP_ERR_FORMAT, "t.obj:3:6: expected a number after 'v'"},
        {"v nan 0 0\n", PERSP_ERR_FORMAT, "t.obj:1:3: expected a finite number after 'v', found 'nan'"},
        {"v inf 0 0\n", PERSP_ERR_FORMAT, "t.obj:1:3: expected a finite number"},
        {"v 1e39 0 0\n", PERSP_ERR_FORMAT, "t.obj:1:3: expected a finite number"},
        {"v 1 2 3 4 5\n", PERSP_ERR_FORMAT, "t.obj:1:12: expected x y z [w] or x y z r g b after 'v'"},
        {"vn 0 1\n", PERSP_ERR_FORMAT, "t.obj:1:7: expected a number after 'vn'"},
        {"vt\n", PERSP_ERR_FORMAT, "t.obj:1:3: expected a number after 'vt'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", PERSP_ERR_FORMAT,
         "t.obj:4:7: vertex index 9 out of range (3 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", PERSP_ERR_FORMAT,
         "t.obj:4:7: vertex index -4 out of range (3 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", PERSP_ERR_FORMAT,
         "t.obj:4:3: vertex index 0 is invalid (indices start at 1)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", PERSP_ERR_FORMAT,
         "t.obj:4:6: expected at least 3 vertices after 'f' (found 2)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", PERSP_ERR_FORMAT,
         "t.obj:5:9: texture index 2 out of range (1 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2// 3//\n", PERSP_ERR_FORMAT,
         "t.obj:4:6: expected a normal index after '/'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2/ 3/\n", PERSP_ERR_FORMAT,
         "t.obj:4:5: expected a texture index after '/'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n", PERSP_ERR_FORMAT,
         "t.obj:4:5: expected a texture index, found 'a'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", PERSP_ERR_FORMAT,
         "t.obj:4:7: expected a vertex index"},
        {"v 0 0 0\r\nfoo 1 2\r\n", PERSP_ERR_FORMAT, "t.obj:2:1: unknown statement 'foo'"},
        {"cstype bspline\n", PERSP_ERR_UNSUPPORTED, "t.obj:1:1: free-form geometry ('cstype') is not supported"},
        {"usemtl\n", PERSP_ERR_FORMAT, "t.obj:1:7: expected a material name after 'usemtl'"},
        {"v 0 0 0\n", PERSP_ERR_FORMAT, "t.obj: no faces"},
        {"", PERSP_ERR_FORMAT, "t.obj: no faces"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        loaded l = load_text(cases[i].text);
        const char *err = persp_context_error(l.ctx);
        if (l.st != cases[i].status || !strstr(err, cases[i].message))
            fail_msg("case %zu: status %d, message \"%s\", expected \"%s\"", i, (int)l.st, err, cases[i].message);
        assert_int_equal(l.res.part_count, 0);
        unload(&l);
    }
}

/* ---------------------------------------------------------------- files */

static void write_text(const char *dir, const char *name, const char *text)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void write_png(persp_context *ctx, const char *dir, const char *name, int w, int h)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, w, h, &img), PERSP_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = (uint8_t)(x * 40), p[1] = (uint8_t)(y * 40), p[2] = 128, p[3] = 255;
        }
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_OK);
    persp_image_free(ctx, &img);
}

static void remove_tree(const char *dir)
{
    static const char *const files[] = {"m.obj", "bad.obj", "mat/lib.mtl", "mat/bad.mtl", "mat/tex/t.png"};
    char path[1024];
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        remove(path);
    }
    snprintf(path, sizeof path, "%s/mat/tex", dir);
    rmdir(path);
    snprintf(path, sizeof path, "%s/mat", dir);
    rmdir(path);
    rmdir(dir);
}

static void test_files_materials_textures(void **state)
{
    (void)state;
    char dir[] = "/tmp/persp_obj_XXXXXX", sub[1100];
    assert_non_null(mkdtemp(dir));
    snprintf(sub, sizeof sub, "%s/mat", dir);
    assert_int_equal(mkdir(sub, 0700), 0);
    snprintf(sub, sizeof sub, "%s/mat/tex", dir);
    assert_int_equal(mkdir(sub, 0700), 0);
    persp_context *ctx = test_context();
    write_png(ctx, dir, "mat/tex/t.png", 4, 2);
    /* map_Kd relative to the MTL, mtllib relative to the OBJ */
    write_text(dir, "mat/lib.mtl",
               "# two materials\nnewmtl red\nKa 0.1 0 0\nKd 1 0 0\nKs 0.5\nNs 64\nd 1\nillum 2\n\n"
               "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd -s 1 1 1 tex/t.png\nnewmtl tex2\nmap_Kd tex/t.png\n");
    write_text(dir, "m.obj",
               "mtllib mat/lib.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
               "usemtl red\nf 1 2 3\nusemtl tex\nf 1 3 4\nusemtl red\nf 4 3 2\nusemtl tex2\nf 2 3 4\n");
    persp_scene *scene = NULL;
    assert_int_equal(persp__scene_new(ctx, &scene), PERSP_OK);
    char path[1100];
    snprintf(path, sizeof path, "%s/m.obj", dir);
    persp_texcache cache;
    memset(&cache, 0, sizeof cache);
    persp_obj_result res;
    persp_status st = persp__obj_load_file(scene, path, &cache, &res);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    assert_int_equal(res.part_count, 3); /* red (two faces), tex, tex2 */
    assert_int_equal(scene->material_count, 3);
    assert_int_equal(scene->texture_count, 1); /* one file, decoded once */
    const persp_mesh *red = &scene->meshes[res.parts[0].mesh];
    assert_int_equal(red->index_count, 6);
    const persp_material *mr = &scene->materials[res.parts[0].material];
    assert_true(mr->diffuse[0] == 1.0f && mr->diffuse[1] == 0.0f && mr->ambient[0] == 0.1f);
    assert_true(mr->specular[0] == 0.5f && mr->specular[2] == 0.5f && mr->shininess == 64.0f);
    assert_int_equal(mr->texture, -1);
    const persp_material *mt = &scene->materials[res.parts[1].material];
    assert_int_equal(mt->texture, 0);
    assert_int_equal(mt->env, PERSP_TEXENV_MODULATE);
    assert_true(mt->diffuse[0] == 0.5f);
    assert_int_equal(persp_texture_width(scene->textures[0]), 4);
    assert_int_equal(persp_texture_height(scene->textures[0]), 2);
    assert_int_equal(scene->materials[res.parts[2].material].texture, 0);
    persp__obj_result_free(ctx, &res);
    persp__texcache_free(ctx, &cache);
    persp_scene_destroy(scene);

    /* errors inside the MTL name the MTL file and its line */
    write_text(dir, "mat/bad.mtl", "newmtl a\nKd 1 0\n");
    write_text(dir, "bad.obj", "mtllib mat/bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    snprintf(path, sizeof path, "%s/bad.obj", dir);
    assert_int_equal(persp__scene_new(ctx, &scene), PERSP_OK);
    assert_int_equal(persp__obj_load_file(scene, path, NULL, &res), PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(ctx), "bad.mtl:2:7: expected 1 or 3 numbers after 'Kd'"));
    persp_scene_destroy(scene);

    static const bad_case mtl_cases[] = {
        {"Kd 1 0 0\n", PERSP_ERR_FORMAT, "bad.mtl:1:1: expected 'newmtl' before 'Kd'"},
        {"newmtl a\nKd spectral x.spd\n", PERSP_ERR_UNSUPPORTED, "bad.mtl:2:4: only RGB colours are supported after 'Kd'"},
        {"newmtl a\nNs -1\n", PERSP_ERR_FORMAT, "bad.mtl:2:4: expected a shininess >= 0 after 'Ns'"},
        {"newmtl a\nd 1.5\n", PERSP_ERR_FORMAT, "bad.mtl:2:3: expected a number in [0, 1] after 'd'"},
        {"newmtl a\nKd 1 1 1 1\n", PERSP_ERR_FORMAT, "bad.mtl:2:10: expected at most 3 numbers after 'Kd'"},
        {"newmtl a\nmap_Kd missing.png\n", PERSP_ERR_IO, "bad.mtl:2:8: cannot load texture 'missing.png'"},
        {"newmtl a\nmap_Kd -zz 1 x.png\n", PERSP_ERR_FORMAT, "bad.mtl:2:8: unknown map_Kd option '-zz'"},
        {"newmtl a\nmap_Kd\n", PERSP_ERR_FORMAT, "bad.mtl:2:7: expected a file name after 'map_Kd'"},
        {"newmtl\n", PERSP_ERR_FORMAT, "bad.mtl:1:7: expected a material name after 'newmtl'"},
        {"newmtl a b\n", PERSP_ERR_FORMAT, "bad.mtl:1:10: expected the end of the line after the material name"},
        {"newmtl a\nKx 1\n", PERSP_ERR_FORMAT, "bad.mtl:2:1: unknown statement 'Kx'"},
    };
    for (size_t i = 0; i < sizeof mtl_cases / sizeof mtl_cases[0]; i++) {
        write_text(dir, "mat/bad.mtl", mtl_cases[i].text);
        assert_int_equal(persp__scene_new(ctx, &scene), PERSP_OK);
        st = persp__obj_load_file(scene, path, NULL, &res);
        const char *err = persp_context_error(ctx);
        if (st != mtl_cases[i].status || !strstr(err, mtl_cases[i].message))
            fail_msg("mtl case %zu: status %d, message \"%s\", expected \"%s\"", i, (int)st, err, mtl_cases[i].message);
        persp_scene_destroy(scene);
    }

    /* usemtl of a name no mtllib defines; a missing mtllib file */
    write_text(dir, "mat/bad.mtl", "newmtl a\n");
    write_text(dir, "bad.obj", "mtllib mat/bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl b\nf 1 2 3\n");
    assert_int_equal(persp__scene_new(ctx, &scene), PERSP_OK);
    assert_int_equal(persp__obj_load_file(scene, path, NULL, &res), PERSP_ERR_NOT_FOUND);
    assert_non_null(strstr(persp_context_error(ctx), "bad.obj:5:8: unknown material 'b'"));
    persp_scene_destroy(scene);
    write_text(dir, "bad.obj", "v 0 0 0\nmtllib nothere.mtl\n");
    assert_int_equal(persp__scene_new(ctx, &scene), PERSP_OK);
    assert_int_equal(persp__obj_load_file(scene, path, NULL, &res), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "bad.obj:2:8: cannot read material library 'nothere.mtl'"));
    persp_scene_destroy(scene);

    persp_context_destroy(ctx);
    remove_tree(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quad_all_forms),
        cmocka_unit_test(test_pentagon_fan_and_normals),
        cmocka_unit_test(test_negative_indices),
        cmocka_unit_test(test_shared_corners_and_colours),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_files_materials_textures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
