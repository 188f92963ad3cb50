/* persp_method_triangle (src/analysis/method_probe.c): the per-pixel texture
 * coordinates of one triangle, as the renderer computes them. */
#include "support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 96, H = 72 };

/* The renderer's pixels for the same triangle: persp_draw through a clip
 * transform that puts clip (x_ndc·w, y_ndc·w, 0, w) at the given window
 * position, culling off; the pixels it writes. */
static size_t drawn(persp_context *ctx, const persp_method_vertex v[3], uint8_t *mask)
{
    uint8_t color[W * H * 4];
    float depth[W * H];
    persp_framebuffer fb = {W, H, color, depth};
    const uint8_t black[4] = {0, 0, 0, 0};
    persp_framebuffer_clear(&fb, black, PERSP_DEPTH_Z);
    persp_vertex pv[3];
    memset(pv, 0, sizeof pv);
    for (int k = 0; k < 3; k++) {
        const double w = v[k].w;
        pv[k].pos[0] = (float)((v[k].x / (0.5 * W) - 1.0) * w);
        pv[k].pos[1] = (float)((v[k].y / (0.5 * H) - 1.0) * w);
        pv[k].pos[2] = 0.0f;
        for (int c = 0; c < 4; c++) pv[k].color[c] = 1.0f;
    }
    /* clip = M·(x, y, z, 1) with clip w = the vertex's own w: w is put in z
     * and moved to w by the matrix (z_clip = 0). */
    for (int k = 0; k < 3; k++) pv[k].pos[2] = (float)v[k].w;
    persp_draw_desc d;
    memset(&d, 0, sizeof d);
    memset(&d.mvp, 0, sizeof d.mvp);
    d.mvp.m[0] = 1.0f, d.mvp.m[5] = 1.0f, d.mvp.m[11] = 1.0f; /* w_clip = z */
    d.depth_test = PERSP_TOGGLE_OFF;
    const uint32_t ix[3] = {0, 1, 2};
    assert_int_equal(persp_draw(ctx, &fb, &d, pv, 3, ix, 3), PERSP_OK);
    size_t n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) n += mask[i] = color[4 * i + 3] != 0;
    return n;
}

/* Vertices a little beyond the window, w in [0.5, 8], u and v in [-1, 2]. */
static void random_triangle(test_rng *rng, persp_method_vertex t[3])
{
    for (int k = 0; k < 3; k++)
        t[k] = (persp_method_vertex){test_rng_uniform(rng, -10, W + 10), test_rng_uniform(rng, -10, H + 10),
                                     test_rng_uniform(rng, 0.5, 8.0), (float)test_rng_uniform(rng, -1, 2),
                                     (float)test_rng_uniform(rng, -1, 2)};
}

static void test_matches_renderer_and_exact(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {17};
    float *u = malloc(W * H * sizeof *u), *v = malloc(W * H * sizeof *v);
    uint8_t cov[W * H], mask[W * H];
    assert_non_null(u);
    assert_non_null(v);
    size_t checked = 0;
    for (int trial = 0; trial < 40; trial++) {
        persp_method_vertex t[3];
        random_triangle(&rng, t);
        persp_opcount ops;
        memset(&ops, 0, sizeof ops);
        assert_int_equal(persp_method_triangle(ctx, "exact", t, W, H, 64, 64, u, v, cov, &ops), PERSP_OK);
        /* The renderer's pixel set, exactly. */
        const size_t n = drawn(ctx, t, mask);
        size_t ncov = 0;
        for (size_t i = 0; i < (size_t)W * H; i++) {
            ncov += cov[i];
            if (cov[i] != mask[i]) fail_msg("trial %d: pixel %zu covered %d, drawn %d", trial, i, cov[i], mask[i]);
        }
        assert_int_equal(ncov, n);
        assert_int_equal(ops.pixels, ncov);
        /* exact: the rational form at the pixel centre (Heckbert 1989 §2.3.2),
         * from the snapped vertices, within float rounding. */
        double X[3], Y[3];
        for (int k = 0; k < 3; k++) X[k] = llround(t[k].x * 256) / 256.0, Y[k] = llround(t[k].y * 256) / 256.0;
        const double area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                if (!cov[y * W + x]) continue;
                const double px = x + 0.5, py = y + 0.5;
                double b[3], den = 0, nu = 0, nv = 0;
                b[0] = ((X[1] - px) * (Y[2] - py) - (X[2] - px) * (Y[1] - py)) / area;
                b[1] = ((X[2] - px) * (Y[0] - py) - (X[0] - px) * (Y[2] - py)) / area;
                b[2] = 1.0 - b[0] - b[1];
                for (int k = 0; k < 3; k++)
                    den += b[k] / t[k].w, nu += b[k] * t[k].u / t[k].w, nv += b[k] * t[k].v / t[k].w;
                const double eu = nu / den, ev = nv / den;
                if (fabs(u[y * W + x] - eu) > 1e-4 * (1 + fabs(eu)) || fabs(v[y * W + x] - ev) > 1e-4 * (1 + fabs(ev)))
                    fail_msg("trial %d pixel (%d, %d): (%g, %g), exact (%g, %g)", trial, x, y, u[y * W + x],
                             v[y * W + x], eu, ev);
                checked++;
            }
    }
    print_message("%zu pixels checked\n", checked);
    assert_true(checked > 20000);
    free(u);
    free(v);
    persp_context_destroy(ctx);
}

/* midpoint works on the texel lattice: its outputs are texel centres of a
 * tex_w × tex_h texture, and it counts no division per pixel. */
static void test_midpoint_lattice(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    float *u = malloc(W * H * sizeof *u), *v = malloc(W * H * sizeof *v);
    uint8_t cov[W * H];
    assert_non_null(u);
    assert_non_null(v);
    const persp_method_vertex t[3] = {{2, 3, 1.0, 0, 0}, {90, 8, 4.0, 1, 0}, {20, 70, 2.0, 0, 1}};
    persp_opcount ops;
    memset(&ops, 0, sizeof ops);
    assert_int_equal(persp_method_triangle(ctx, "midpoint:int", t, W, H, 256, 128, u, v, cov, &ops), PERSP_OK);
    size_t n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (!cov[i]) continue;
        n++;
        const double tu = u[i] * 256.0 - 0.5, tv = v[i] * 128.0 - 0.5;
        assert_true(fabs(tu - round(tu)) < 1e-3 && fabs(tv - round(tv)) < 1e-3);
    }
    assert_true(n > 1000);
    assert_true(ops.div < ops.spans * 3); /* per span, not per pixel */
    free(u);
    free(v);
    persp_context_destroy(ctx);
}

static void test_bad_input(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    float u[4], v[4];
    persp_method_vertex t[3] = {{0, 0, 1, 0, 0}, {2, 0, 1, 1, 0}, {0, 2, 1, 0, 1}};
    assert_int_equal(persp_method_triangle(ctx, "no-such", t, 2, 2, 1, 1, u, v, NULL, NULL), PERSP_ERR_NOT_FOUND);
    t[1].w = 0.0;
    assert_int_equal(persp_method_triangle(ctx, "exact", t, 2, 2, 1, 1, u, v, NULL, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "vertex 1"));
    t[1].w = 1.0, t[2].x = NAN;
    assert_int_equal(persp_method_triangle(ctx, "exact", t, 2, 2, 1, 1, u, v, NULL, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    t[2].x = 0;
    assert_int_equal(persp_method_triangle(ctx, "exact", t, 20000, 2, 1, 1, u, v, NULL, NULL), PERSP_ERR_TOO_LARGE);
    assert_int_equal(persp_method_triangle(ctx, "exact", t, 2, 2, 1, 1, NULL, v, NULL, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    /* Degenerate: nothing covered, not an error. */
    const persp_method_vertex line[3] = {{0, 0, 1, 0, 0}, {2, 2, 1, 1, 0}, {1, 1, 1, 0, 1}};
    uint8_t cov[4] = {9, 9, 9, 9};
    assert_int_equal(persp_method_triangle(ctx, "exact", line, 2, 2, 1, 1, u, v, cov, NULL), PERSP_OK);
    for (int i = 0; i < 4; i++) assert_int_equal(cov[i], 0);
    persp_context_destroy(ctx);
}

/* persp_midpoint_trace: the same pixels and outputs as persp_method_triangle
 * bit for bit, and integer states that satisfy the acceptance test
 * 0 < W <= 2E at every pixel of the integer path. */
typedef struct trace_check {
    const persp_midpoint_format *f;
    float *u, *v;
    uint8_t *seen;
    size_t pixels, int_pixels;
} trace_check;

static void trace_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px)
{
    trace_check *c = user;
    assert_true(s->n >= 1 && s->n <= 64 && s->int_pixels >= 0 && s->int_pixels <= s->n);
    for (int k = 0; k < s->n; k++) {
        const size_t at = (size_t)s->y * W + (size_t)(s->x0 + k);
        assert_int_equal(c->seen[at], 0);
        c->seen[at] = 1;
        c->pixels++;
        assert_memory_equal(&px[k].u, &c->u[at], sizeof(float));
        assert_memory_equal(&px[k].v, &c->v[at], sizeof(float));
        if (k >= s->int_pixels) continue;
        c->int_pixels++;
        const int64_t E = s->E0 + 2 * c->f->G * k;
        for (int j = 0; j < 2; j++) {
            assert_true(px[k].W[j] > 0 && px[k].W[j] <= 2 * E);
            const double out = ((double)px[k].n[j] + 0.5 * c->f->lattice2) * (1.0 / c->f->P[j]);
            assert_true((float)out == (j ? px[k].v : px[k].u));
        }
    }
}

static void test_midpoint_trace(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {23};
    float *u = malloc(W * H * sizeof *u), *v = malloc(W * H * sizeof *v);
    uint8_t cov[W * H], seen[W * H];
    assert_non_null(u);
    assert_non_null(v);
    size_t total = 0, int_total = 0;
    for (int trial = 0; trial < 40; trial++) {
        persp_method_vertex t[3];
        random_triangle(&rng, t);
        const char *spec = trial % 2 ? "midpoint:int,edge" : "midpoint:int";
        assert_int_equal(persp_method_triangle(ctx, spec, t, W, H, 256, 128, u, v, cov, NULL), PERSP_OK);
        persp_midpoint_format f;
        memset(seen, 0, sizeof seen);
        trace_check c = {&f, u, v, seen, 0, 0};
        assert_int_equal(persp_midpoint_trace(ctx, spec, t, W, H, 256, 128, &f, trace_span, &c), PERSP_OK);
        assert_memory_equal(seen, cov, sizeof cov);
        assert_int_equal(f.lattice2, trial % 2 ? 0 : 1);
        if (c.pixels) assert_int_equal(f.in_format, 1);
        assert_true(f.P[0] == 256.0 && f.P[1] == 128.0);
        total += c.pixels, int_total += c.int_pixels;
    }
    assert_true(total > 20000);
    assert_true(int_total == total); /* texture coordinates in [-1, 2] stay inside the format */
    persp_midpoint_format f;
    const persp_method_vertex t[3] = {{2, 3, 1.0, 0, 0}, {90, 8, 4.0, 1, 0}, {20, 70, 2.0, 0, 1}};
    assert_int_equal(persp_midpoint_trace(ctx, "midpoint", t, W, H, 256, 128, &f, NULL, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "midpoint:int"));
    assert_int_equal(persp_midpoint_trace(ctx, "exact", t, W, H, 256, 128, &f, NULL, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_midpoint_trace(ctx, "midpoint:int", t, W, H, 256, 128, NULL, NULL, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_midpoint_trace(ctx, "midpoint:int", t, W, H, 256, 128, &f, NULL, NULL), PERSP_OK);
    assert_int_equal(f.in_format, 1);
    assert_true(f.shift > 0 && f.G != 0 && f.X2max == 2 * 89 + 2);
    free(u);
    free(v);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_renderer_and_exact),
        cmocka_unit_test(test_midpoint_lattice),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_midpoint_trace),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
