/* Primitive meshes: counts, surfaces, outward normals, counter-clockwise
 * front faces, uv ranges and seams (src/geom/primitives.c). */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <string.h>

#define M_PI_ 3.14159265358979323846

static void cross(const float *a, const float *b, const float *c, double n[3])
{
    double e1[3], e2[3];
    for (int i = 0; i < 3; i++) e1[i] = (double)b[i] - a[i], e2[i] = (double)c[i] - a[i];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* Properties every primitive has: indices in range, unit normals, every
 * non-degenerate triangle counter-clockwise seen from the side its vertex
 * normals point to, uv in [0,1] and no triangle spanning more than half of
 * the texture in u (which would mean interpolation across the seam). */
static void check_common(const persp_mesh *m, double max_du)
{
    assert_true(m->index_count % 3 == 0);
    assert_true(m->has_normals);
    for (size_t i = 0; i < m->index_count; i++) assert_true(m->indices[i] < m->vertex_count);
    for (size_t i = 0; i < m->vertex_count; i++) {
        const persp_vertex *v = &m->vertices[i];
        double l = sqrt((double)v->normal[0] * v->normal[0] + (double)v->normal[1] * v->normal[1] +
                        (double)v->normal[2] * v->normal[2]);
        assert_true(fabs(l - 1.0) < 1e-5);
        assert_true(v->uv[0] >= 0.0f && v->uv[0] <= 1.0f && v->uv[1] >= 0.0f && v->uv[1] <= 1.0f);
        assert_true(v->color[3] == 1.0f);
    }
    size_t degenerate = 0;
    for (size_t t = 0; t < m->index_count; t += 3) {
        const persp_vertex *a = &m->vertices[m->indices[t]], *b = &m->vertices[m->indices[t + 1]],
                           *c = &m->vertices[m->indices[t + 2]];
        double n[3];
        cross(a->pos, b->pos, c->pos, n);
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len < 1e-9) {
            degenerate++;
            continue;
        }
        double avg[3];
        for (int k = 0; k < 3; k++) avg[k] = (double)a->normal[k] + b->normal[k] + c->normal[k];
        double d = (n[0] * avg[0] + n[1] * avg[1] + n[2] * avg[2]) / len;
        assert_true(d > 0.5); /* facing the normals' side, not merely grazing */
        double du = fmax(fabs((double)a->uv[0] - b->uv[0]), fmax(fabs((double)b->uv[0] - c->uv[0]),
                                                                  fabs((double)a->uv[0] - c->uv[0])));
        assert_true(du <= max_du + 1e-6);
    }
    assert_int_equal(degenerate, 0);
}

static void test_plane(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh m;
    assert_int_equal(persp__mesh_plane(ctx, 4, &m), PERSP_OK);
    assert_int_equal(m.vertex_count, 25);
    assert_int_equal(m.index_count, 4 * 4 * 6);
    check_common(&m, 0.25);
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        assert_true(v->pos[1] == 0.0f && v->normal[1] == 1.0f);
        /* u along +x, v along -z, the whole plane is [-1,1]^2 */
        assert_true(fabs(v->pos[0] - (2.0 * v->uv[0] - 1.0)) < 1e-6);
        assert_true(fabs(v->pos[2] - (1.0 - 2.0 * v->uv[1])) < 1e-6);
    }
    persp__mesh_free(ctx, &m);
    assert_int_equal(persp__mesh_plane(ctx, 0, &m), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "plane: subdivisions"));
    persp_context_destroy(ctx);
}

static void test_cube(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh m;
    assert_int_equal(persp__mesh_cube(ctx, &m), PERSP_OK);
    assert_int_equal(m.vertex_count, 24);
    assert_int_equal(m.index_count, 36);
    check_common(&m, 1.0);
    int faces[6] = {0};
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        int axis = -1;
        for (int k = 0; k < 3; k++) {
            assert_true(fabsf(v->pos[k]) == 1.0f);
            if (v->normal[k] != 0.0f) axis = k;
        }
        assert_true(axis >= 0);
        /* the normal is the outward face direction: pos·n = 1 */
        assert_true(v->pos[axis] == v->normal[axis]);
        faces[2 * axis + (v->normal[axis] > 0)]++;
    }
    for (int f = 0; f < 6; f++) assert_int_equal(faces[f], 4);
    persp__mesh_free(ctx, &m);
    persp_context_destroy(ctx);
}

static void test_sphere(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh m;
    const int slices = 24, stacks = 12;
    assert_int_equal(persp__mesh_sphere(ctx, slices, stacks, &m), PERSP_OK);
    assert_int_equal(m.vertex_count, (size_t)(slices + 1) * (stacks + 1));
    /* quads except one triangle per slice at each pole */
    assert_int_equal(m.index_count, 3 * (size_t)slices * (2 * stacks - 2));
    check_common(&m, 1.0 / slices);
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        double r = sqrt((double)v->pos[0] * v->pos[0] + (double)v->pos[1] * v->pos[1] +
                        (double)v->pos[2] * v->pos[2]);
        assert_true(fabs(r - 1.0) < 1e-6);
        for (int k = 0; k < 3; k++) assert_true(fabs(v->pos[k] - v->normal[k]) < 1e-6);
        /* latitude: v = 1 - φ/π with φ from +y */
        assert_true(fabs(v->uv[1] - (1.0 - acos(fmax(-1.0, fmin(1.0, v->pos[1]))) / M_PI_)) < 1e-5);
        /* longitude about +y with u = 1/2 facing +z (away from the poles) */
        if (fabs(v->pos[1]) < 0.999 && v->uv[0] > 0.0f && v->uv[0] < 1.0f)
            assert_true(fabs(v->uv[0] - (0.5 + atan2(v->pos[0], v->pos[2]) / (2 * M_PI_))) < 1e-5);
    }
    persp__mesh_free(ctx, &m);
    assert_int_equal(persp__mesh_sphere(ctx, 2, 8, &m), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__mesh_sphere(ctx, 8, 1, &m), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__mesh_sphere(ctx, 100000, 8, &m), PERSP_ERR_INVALID_ARGUMENT);
    persp_context_destroy(ctx);
}

static void test_cylinder(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh m;
    const int slices = 16;
    assert_int_equal(persp__mesh_cylinder(ctx, slices, &m), PERSP_OK);
    assert_int_equal(m.index_count, 3 * (2 * (size_t)slices + 2 * (size_t)slices));
    check_common(&m, 1.0);
    size_t side = 0, cap = 0;
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        assert_true(fabsf(v->pos[1]) == 1.0f);
        if (v->normal[1] == 0.0f) {
            side++;
            assert_true(fabs(hypot(v->pos[0], v->pos[2]) - 1.0) < 1e-6);
            assert_true(fabs(v->uv[1] - 0.5 * (v->pos[1] + 1.0)) < 1e-6);
        } else {
            cap++;
            assert_true(v->normal[1] == v->pos[1]);
        }
    }
    assert_int_equal(side, 2 * (size_t)(slices + 1));
    assert_int_equal(cap, 2 * (size_t)(slices + 2));
    persp__mesh_free(ctx, &m);
    persp_context_destroy(ctx);
}

static void test_torus(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_mesh m;
    const float R = 1.0f, r = 0.3f;
    assert_int_equal(persp__mesh_torus(ctx, R, r, 20, 10, &m), PERSP_OK);
    assert_int_equal(m.vertex_count, 21 * 11);
    assert_int_equal(m.index_count, 6 * 20 * 10);
    check_common(&m, 1.0 / 20);
    for (size_t i = 0; i < m.vertex_count; i++) {
        const persp_vertex *v = &m.vertices[i];
        /* distance from the tube's centre circle is the minor radius, along the normal */
        double rho = hypot(v->pos[0], v->pos[2]);
        double c[3] = {v->pos[0] * R / rho, 0.0, v->pos[2] * R / rho};
        double d = sqrt((v->pos[0] - c[0]) * (v->pos[0] - c[0]) + (double)v->pos[1] * v->pos[1] +
                        (v->pos[2] - c[2]) * (v->pos[2] - c[2]));
        assert_true(fabs(d - r) < 1e-5);
        for (int k = 0; k < 3; k++) assert_true(fabs((v->pos[k] - c[k]) / r - v->normal[k]) < 1e-4);
    }
    persp__mesh_free(ctx, &m);
    assert_int_equal(persp__mesh_torus(ctx, 1.0f, 2.0f, 8, 8, &m), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__mesh_torus(ctx, NAN, 0.2f, 8, 8, &m), PERSP_ERR_INVALID_ARGUMENT);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plane),    cmocka_unit_test(test_cube),  cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_cylinder), cmocka_unit_test(test_torus),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
