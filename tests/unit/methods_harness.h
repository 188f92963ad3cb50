/*
 * Shared by the test_methods_*.c programs of the approximating methods:
 * seeded random triangles of the `random-triangles` accuracy set
 * (docs/WORKLOADS.md: eye-space vertices with a fixed depth ratio ħ, corridor
 * projection, 1024×768, u, v in [0, 1], 256×256 texels, 100..100,000 pixels)
 * set up by the real triangle setup, and a walk over their covered spans cut
 * at 64-pixel tile borders, as the renderer cuts them.
 */
#ifndef PERSP_TESTS_METHODS_HARNESS_H
#define PERSP_TESTS_METHODS_HARNESS_H

#include "support.h"

#include "interp/method.h"
#include "interp/methods.h"
#include "raster/raster.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define H_WIDTH 1024
#define H_HEIGHT 768
#define H_TEXELS 256.0
#define H_PI 3.14159265358979323846

static const double h_ratios[] = {1.25, 1.5, 2.0, 3.0, 4.0, 5.0, 8.0};
#define H_RATIO_COUNT (sizeof h_ratios / sizeof h_ratios[0])

typedef struct h_triangle {
    persp_tri t;
    persp_rational_vertices v; /* the vertices of t.rat, for a method's prepare */
    float attr[3][PERSP_A_COUNT];
} h_triangle;

/* Corridor projection (docs/WORKLOADS.md): glFrustum(−t·a, t·a, −t, t, 0.1, 100),
 * t = 0.1·tan(30°), a = width/height; eye point → window vertex. */
static inline void h_project(const double eye[3], const float *attr, persp_winvert *out)
{
    const double n = 0.1, f = 100.0, t = 0.1 * tan(30.0 * H_PI / 180.0);
    const double a = (double)H_WIDTH / (double)H_HEIGHT;
    persp_mat4 P = persp_frustum(-t * a, t * a, -t, t, n, f);
    persp_vec4 c = persp_mat4_apply(P, (persp_vec4){(float)eye[0], (float)eye[1], (float)eye[2], 1.0f});
    double w = c.w;
    out->x = ((double)c.x / w + 1.0) * 0.5 * H_WIDTH;
    out->y = ((double)c.y / w + 1.0) * 0.5 * H_HEIGHT;
    out->z = ((double)c.z / w + 1.0) * 0.5;
    out->q = 1.0 / w;
    out->attr = attr;
}

/* A random triangle whose vertex depths have ratio z_far/z_near = hbar. */
static inline void h_random_triangle(test_rng *rng, double hbar, h_triangle *T)
{
    const double t = 0.1 * tan(30.0 * H_PI / 180.0), a = (double)H_WIDTH / (double)H_HEIGHT;
    for (int attempt = 0; attempt < 100000; attempt++) {
        double zn = test_rng_uniform(rng, 0.5, 4.0);
        double dist[3] = {zn, zn * hbar, zn * test_rng_uniform(rng, 1.0, hbar)};
        int rot = (int)(test_rng_next(rng) % 3);
        double size = test_rng_uniform(rng, 0.05, 1.2); /* NDC spread around a centre */
        double cx = test_rng_uniform(rng, -0.6, 0.6), cy = test_rng_uniform(rng, -0.6, 0.6);
        persp_winvert v[3];
        for (int i = 0; i < 3; i++) {
            double d = dist[(i + rot) % 3];
            double nx = cx + size * test_rng_uniform(rng, -0.5, 0.5);
            double ny = cy + size * test_rng_uniform(rng, -0.5, 0.5);
            double eye[3] = {nx * d * t * a / 0.1, ny * d * t / 0.1, -d};
            memset(T->attr[i], 0, sizeof T->attr[i]);
            T->attr[i][PERSP_A_U] = (float)test_rng_uniform(rng, 0.0, 1.0);
            T->attr[i][PERSP_A_V] = (float)test_rng_uniform(rng, 0.0, 1.0);
            h_project(eye, T->attr[i], &v[i]);
        }
        double area = 0.5 * fabs((v[1].x - v[0].x) * (v[2].y - v[0].y) -
                                 (v[2].x - v[0].x) * (v[1].y - v[0].y));
        if (area < 100.0 || area > 100000.0) continue;
        if (!persp__setup_triangle(v, H_WIDTH, H_HEIGHT, 0, &T->t, &T->v)) continue;
        T->t.rat.scale1 = T->t.rat.scale2 = (float)H_TEXELS;
        return;
    }
    fail_msg("no random triangle found");
}

typedef void (*h_span_fn)(void *user, const persp_rational *r, int x0, int y, int n);

/* Visits the covered spans of T, cut at 64-pixel tile columns. */
static inline void h_for_each_span(const h_triangle *T, h_span_fn fn, void *user)
{
    for (int y = T->t.ymin; y <= T->t.ymax; y++) {
        int lo, hi;
        if (!persp__tri_row_range(&T->t, y, T->t.xmin, T->t.xmax, &lo, &hi)) continue;
        for (int x = lo; x <= hi;) {
            int end = (x / PERSP_SPAN_MAX) * PERSP_SPAN_MAX + PERSP_SPAN_MAX - 1;
            if (end > hi) end = hi;
            fn(user, &T->t.rat, x, y, end - x + 1);
            x = end + 1;
        }
    }
}

/* Resolves a method spec or fails the test. */
static inline persp_method_sel h_method(const char *spec)
{
    persp_method_sel sel;
    assert_int_equal(persp__method_resolve(NULL, spec, &sel), PERSP_OK);
    assert_non_null(sel.m);
    return sel;
}

#endif
