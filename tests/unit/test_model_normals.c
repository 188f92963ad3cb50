/* Normals of models that have none, by the format's rule (docs/SCENES.md,
 * "Models"): a cube of 8 shared vertices comes out faceted (each face its
 * own normal, 24 vertices), a sphere smooth (no vertex split, normals
 * radial), a glTF without NORMAL flat whatever the crease (glTF 2.0
 * §3.7.2.1), and the crease angle of persp_scene_load_desc decides. */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char tmpdir[64];

static void write_text(const char *name, const char *text)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
    fclose(f);
}

/* The unit cube [-1, 1]^3: 8 corners, 12 triangles wound outwards. */
static const float cube_v[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                   {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
static const int cube_f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                  {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};

static void cube_ply(char *out, size_t cap)
{
    size_t n = (size_t)snprintf(out, cap,
                                "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 12\nproperty list uchar int vertex_indices\n"
                                "end_header\n");
    for (int i = 0; i < 8; i++)
        n += (size_t)snprintf(out + n, cap - n, "%g %g %g\n", cube_v[i][0], cube_v[i][1], cube_v[i][2]);
    for (int i = 0; i < 12; i++)
        n += (size_t)snprintf(out + n, cap - n, "3 %d %d %d\n", cube_f[i][0], cube_f[i][1], cube_f[i][2]);
}

static void cube_obj(char *out, size_t cap)
{
    size_t n = 0;
    for (int i = 0; i < 8; i++)
        n += (size_t)snprintf(out + n, cap - n, "v %g %g %g\n", cube_v[i][0], cube_v[i][1], cube_v[i][2]);
    for (int i = 0; i < 12; i++)
        n += (size_t)snprintf(out + n, cap - n, "f %d %d %d\n", cube_f[i][0] + 1, cube_f[i][1] + 1, cube_f[i][2] + 1);
}

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)in[i] << 16 | (i + 1 < n ? (unsigned)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = abc[v >> 18 & 63];
        out[o++] = abc[v >> 12 & 63];
        out[o++] = i + 1 < n ? abc[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? abc[v & 63] : '=';
    }
    out[o] = '\0';
}

/* The cube as glTF: positions and indices in one data URI, no NORMAL. */
static void cube_gltf(char *out, size_t cap)
{
    unsigned char bin[8 * 12 + 36 * 2];
    memcpy(bin, cube_v, sizeof cube_v);
    for (int i = 0; i < 36; i++) {
        uint16_t ix = (uint16_t)cube_f[i / 3][i % 3];
        memcpy(bin + 96 + 2 * i, &ix, 2);
    }
    char b64[256];
    base64(bin, sizeof bin, b64);
    snprintf(out, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
             "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":96},"
             "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":72}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":8,\"type\":\"VEC3\","
             "\"min\":[-1,-1,-1],\"max\":[1,1,1]},"
             "{\"bufferView\":1,\"componentType\":5123,\"count\":36,\"type\":\"SCALAR\"}]}",
             sizeof bin, b64);
}

/* A UV sphere of shared vertices: rings x segments quads, poles as fans. */
static void sphere_ply(char *out, size_t cap, int rings, int segs)
{
    const int nv = 2 + (rings - 1) * segs, nf = 2 * segs * (rings - 1);
    size_t n = (size_t)snprintf(out, cap,
                                "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                                "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
                                "end_header\n0 1 0\n0 -1 0\n",
                                nv, nf);
    for (int r = 1; r < rings; r++)
        for (int s = 0; s < segs; s++) {
            double th = 3.14159265358979 * r / rings, ph = 2 * 3.14159265358979 * s / segs;
            n += (size_t)snprintf(out + n, cap - n, "%.7f %.7f %.7f\n", sin(th) * cos(ph), cos(th), -sin(th) * sin(ph));
        }
#define RV(r, s) (2 + ((r) - 1) * segs + ((s) % segs))
    for (int s = 0; s < segs; s++) {
        n += (size_t)snprintf(out + n, cap - n, "3 0 %d %d\n", RV(1, s), RV(1, s + 1));
        n += (size_t)snprintf(out + n, cap - n, "3 1 %d %d\n", RV(rings - 1, s + 1), RV(rings - 1, s));
    }
    for (int r = 1; r + 1 < rings; r++)
        for (int s = 0; s < segs; s++)
            n += (size_t)snprintf(out + n, cap - n, "4 %d %d %d %d\n", RV(r, s), RV(r + 1, s), RV(r + 1, s + 1),
                                  RV(r, s + 1));
#undef RV
}

typedef struct loaded {
    persp_context *ctx;
    persp_scene *scene;
} loaded;

static void load(loaded *l, const char *name, float crease)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    l->ctx = test_context();
    persp_scene_load_desc d = {.crease_deg = crease};
    l->scene = NULL;
    if (persp_scene_load_ex(l->ctx, path, &d, &l->scene) != PERSP_OK)
        fail_msg("%s: %s", name, persp_context_error(l->ctx));
    assert_int_equal(l->scene->mesh_count, 1);
}

static void unload(loaded *l)
{
    persp_scene_destroy(l->scene);
    persp_context_destroy(l->ctx);
}

/* Every vertex's normal is the normal of the face it lies on: the unit
 * vector along the coordinate in which the face's corners agree at ±1. */
static void assert_faceted_cube(const persp_mesh *m)
{
    assert_int_equal(m->vertex_count, 24);
    for (size_t t = 0; t < m->index_count; t += 3) {
        const persp_vertex *v[3] = {&m->vertices[m->indices[t]], &m->vertices[m->indices[t + 1]],
                                    &m->vertices[m->indices[t + 2]]};
        int axis = -1;
        for (int k = 0; k < 3; k++)
            if (v[0]->pos[k] == v[1]->pos[k] && v[1]->pos[k] == v[2]->pos[k]) axis = k;
        assert_true(axis >= 0);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) {
                float want = k == axis ? v[0]->pos[axis] : 0.0f;
                if (fabsf(v[c]->normal[k] - want) > 1e-6f)
                    fail_msg("triangle %zu corner %d: normal (%g %g %g)", t / 3, c, (double)v[c]->normal[0],
                             (double)v[c]->normal[1], (double)v[c]->normal[2]);
            }
    }
}

static void test_cube_faceted(void **state)
{
    (void)state;
    static char text[1 << 14];
    cube_ply(text, sizeof text);
    write_text("cube.ply", text);
    cube_obj(text, sizeof text);
    write_text("cube.obj", text);
    cube_gltf(text, sizeof text);
    write_text("cube.gltf", text);
    static const char *const names[] = {"cube.ply", "cube.obj", "cube.gltf"};
    for (int i = 0; i < 3; i++) {
        loaded l;
        load(&l, names[i], 0.0f);
        assert_faceted_cube(&l.scene->meshes[0]);
        unload(&l);
    }
    /* A crease wider than the cube's 90°: smooth corners, no split, except
     * glTF, which is flat whatever the crease. */
    for (int i = 0; i < 3; i++) {
        loaded l;
        load(&l, names[i], 120.0f);
        const persp_mesh *m = &l.scene->meshes[0];
        if (i == 2) {
            assert_faceted_cube(m);
        } else {
            /* Angle-weighted (Assimp's readers): each face's 90° counts once
             * however it is cut, so the normal is the diagonal. persp's OBJ
             * reader weighs each polygon corner once, as Assimp's OBJ path
             * did (docs/SCENES.md), so its corners lean to the faces cut in
             * two there: outwards, not exactly diagonal. */
            assert_int_equal(m->vertex_count, 8);
            for (size_t k = 0; k < m->vertex_count; k++) {
                const persp_vertex *v = &m->vertices[k];
                float d = (v->normal[0] * v->pos[0] + v->normal[1] * v->pos[1] + v->normal[2] * v->pos[2]) / sqrtf(3.0f);
                for (int c = 0; i == 0 && c < 3; c++)
                    assert_true(fabsf(v->normal[c] - v->pos[c] / sqrtf(3.0f)) < 1e-5f);
                assert_true(d > 0.9f);
            }
        }
        unload(&l);
    }
}

static void test_sphere_smooth(void **state)
{
    (void)state;
    static char text[1 << 17];
    sphere_ply(text, sizeof text, 16, 24);
    write_text("sphere.ply", text);
    loaded l;
    load(&l, "sphere.ply", 0.0f);
    const persp_mesh *m = &l.scene->meshes[0];
    assert_int_equal(m->vertex_count, 2 + 15 * 24);
    /* Within the facets' own deviation from the radius (rings 11.25°
     * apart; the fan round each pole leans the first ring's normals most). */
    for (size_t k = 0; k < m->vertex_count; k++) {
        const persp_vertex *v = &m->vertices[k];
        float d = v->normal[0] * v->pos[0] + v->normal[1] * v->pos[1] + v->normal[2] * v->pos[2];
        if (!(d > 0.99f)) fail_msg("vertex %zu: normal off the radius (cos %g)", k, (double)d);
    }
    unload(&l);
}

/* Out of range: refused. */
static void test_crease_checked(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    char path[1024];
    snprintf(path, sizeof path, "%s/cube.ply", tmpdir);
    persp_scene_load_desc d = {.crease_deg = 181.0f};
    assert_int_equal(persp_scene_load_ex(ctx, path, &d, &scene), PERSP_ERR_INVALID_ARGUMENT);
    d.crease_deg = NAN;
    assert_int_equal(persp_scene_load_ex(ctx, path, &d, &scene), PERSP_ERR_INVALID_ARGUMENT);
    persp_context_destroy(ctx);
}

static int setup(void **state)
{
    (void)state;
    return test_tmpdir_make(tmpdir, sizeof tmpdir, "normals");
}

static int teardown(void **state)
{
    (void)state;
    return test_tmpdir_remove(tmpdir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_faceted),
        cmocka_unit_test(test_sphere_smooth),
        cmocka_unit_test(test_crease_checked),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
