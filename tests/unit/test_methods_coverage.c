/*
 * Every registered method and every variant renders every built-in scene
 * with exactly the exact method's pixel set, in the plain render (depth
 * buffer) and in the analysis capture: no holes, no pixel drawn twice
 * (the fragment count equals the exact render's, which the coverage tests of
 * test_raster.c and test_render.c tie to one fragment per covered pixel), and
 * no garbage at span ends or on 1-pixel spans: every value is finite and
 * lies near the range of the visible triangle's vertex coordinates.
 *
 * The image sizes are not multiples of the 64-pixel tile, so spans are cut
 * at tile borders into pieces of every length, down to 1 pixel.
 */
#include "support.h"

#include "interp/method.h"
#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Every variant named in `persp methods`. A registry entry missing from
 * this table fails the test, so a new method cannot go untested. */
static const char *const variants[] = {
    "affine",
    "exact",
    "incremental",
    "incremental:k=1",
    "incremental:k=3",
    "incremental:k=4",
    "incremental:k=8",
    "incremental:k=16",
    "incremental:bidir",
    "subdiv:4",
    "subdiv:8",
    "subdiv:16",
    "subdiv:32",
    "subdiv-quad:4",
    "subdiv-quad:8",
    "subdiv-quad:16",
    "subdiv-quad:32",
    "quadratic",
    "quadratic-shifted",
    "quadratic-unnorm",
    "quadratic-pw",
    "cubic",
    "biquadratic",
    "bicubic",
    "bezier",
    "bezier:step",
    "bezier:quadt",
    "midpoint",
    "midpoint:int",
    "midpoint:edge",
    "midpoint:int,edge",
    "constz",
    "constz:eps=0",
    "constz:eps=0.25",
    "adaptive",
    "adaptive:fallback=quadratic",
    "adaptive:fallback=constz",
    "adaptive:fallback=midpoint:int",
};
#define NVARIANTS (sizeof variants / sizeof variants[0])

static const char *const scenes[] = {"corridor", "floor", "cube"};
static const int sizes[][2] = {{203, 141}, {67, 45}};

typedef struct run_out {
    persp_capture cap;
    uint64_t fragments, written;
    uint8_t *drawn; /* the plain render's coverage: depth below the cleared 1 */
} run_out;

static void run(persp_context *ctx, const persp_scene *scene, const char *method, int w, int h,
                run_out *out)
{
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.method = method;
    persp_status st = persp__render_capture(ctx, scene, &d, w, h, &out->cap);
    if (st != PERSP_OK) fail_msg("%s: capture: %s", method, persp_context_error(ctx));
    uint8_t *color = malloc((size_t)w * (size_t)h * 4);
    float *depth = malloc((size_t)w * (size_t)h * sizeof(float));
    assert_non_null(color);
    assert_non_null(depth);
    persp_framebuffer fb = {w, h, color, depth};
    persp_render_stats stats;
    st = persp_render(ctx, scene, &d, &fb, &stats);
    if (st != PERSP_OK) fail_msg("%s: render: %s", method, persp_context_error(ctx));
    out->fragments = stats.fragments;
    out->written = stats.pixels_written;
    out->drawn = malloc((size_t)w * (size_t)h);
    assert_non_null(out->drawn);
    for (size_t p = 0; p < (size_t)w * (size_t)h; p++)
        out->drawn[p] = depth[p] < 1.0f;
    free(color);
    free(depth);
}

/* Lowest and highest value of s1 (which = 0) or s2 at the triangle's vertices. */
static void vertex_range(const persp_rational_vertices *v, int which, double *lo, double *hi)
{
    const double *s = which ? v->s2 : v->s1;
    *lo = fmin(s[0], fmin(s[1], s[2]));
    *hi = fmax(s[0], fmax(s[1], s[2]));
}

static void test_every_method_every_scene(void **state)
{
    (void)state;
    /* The table names every registry entry at least once. */
    for (size_t i = 0; i < persp_method_count(); i++) {
        persp_method_info info;
        assert_int_equal(persp_method_get(i, &info), PERSP_OK);
        int found = 0;
        for (size_t k = 0; k < NVARIANTS && !found; k++) {
            size_t len = strlen(info.name);
            found = !strncmp(variants[k], info.name, len) &&
                    (variants[k][len] == '\0' || variants[k][len] == ':');
        }
        if (!found) fail_msg("method '%s' is not covered by this test", info.name);
    }
    persp_context *ctx = test_context();
    for (size_t si = 0; si < sizeof scenes / sizeof scenes[0]; si++) {
        persp_scene *scene = NULL;
        assert_int_equal(persp_scene_builtin(ctx, scenes[si], &scene), PERSP_OK);
        for (size_t zi = 0; zi < sizeof sizes / sizeof sizes[0]; zi++) {
            int w = sizes[zi][0], h = sizes[zi][1];
            run_out ref;
            run(ctx, scene, "exact", w, h, &ref);
            size_t covered = 0;
            for (size_t p = 0; p < (size_t)w * (size_t)h; p++)
                covered += ref.cap.tri[p] >= 0;
            assert_true(covered > (size_t)(w * h) / 4);
            /* [Romaniuk-Incr] (5), Fig. 4: the lane and two-stream forms give the
             * same image as the sequential incremental form, bit for bit. */
            run_out inc;
            run(ctx, scene, "incremental", w, h, &inc);
            for (size_t vi = 0; vi < NVARIANTS; vi++) {
                run_out got;
                run(ctx, scene, variants[vi], w, h, &got);
                if (!strncmp(variants[vi], "incremental:", 12)) {
                    size_t bytes = (size_t)w * (size_t)h * sizeof(float);
                    if (memcmp(got.cap.s1, inc.cap.s1, bytes) ||
                        memcmp(got.cap.s2, inc.cap.s2, bytes))
                        fail_msg("%s on %s %dx%d differs from incremental", variants[vi],
                                 scenes[si], w, h);
                }
                if (got.fragments != ref.fragments || got.written != ref.written)
                    fail_msg("%s on %s %dx%d: %llu fragments, %llu written; exact: %llu, %llu",
                             variants[vi], scenes[si], w, h, (unsigned long long)got.fragments,
                             (unsigned long long)got.written, (unsigned long long)ref.fragments,
                             (unsigned long long)ref.written);
                double worst = 0.0;
                for (int y = 0; y < h; y++)
                    for (int x = 0; x < w; x++) {
                        size_t p = (size_t)y * (size_t)w + (size_t)x;
                        if (got.drawn[p] != ref.drawn[p] || got.drawn[p] != (ref.cap.tri[p] >= 0))
                            fail_msg("%s on %s %dx%d: pixel (%d,%d) drawn %d, exact %d",
                                     variants[vi], scenes[si], w, h, x, y, got.drawn[p],
                                     ref.drawn[p]);
                        if (got.cap.tri[p] != ref.cap.tri[p])
                            fail_msg("%s on %s %dx%d: pixel (%d,%d) shows triangle %d, exact %d",
                                     variants[vi], scenes[si], w, h, x, y, got.cap.tri[p],
                                     ref.cap.tri[p]);
                        if (got.cap.tri[p] < 0) continue;
                        const persp_rational *r = &got.cap.rats[got.cap.tri[p]];
                        for (int c = 0; c < 2; c++) {
                            double s = c ? got.cap.s2[p] : got.cap.s1[p];
                            double lo, hi;
                            vertex_range(&got.cap.rat_vertices[got.cap.tri[p]], c, &lo, &hi);
                            /* A perspective map sends the triangle onto the
                             * triangle of its texture coordinates, so exact
                             * values stay in [lo, hi]. The fits anchor at
                             * exact values; a quadratic through a monotone
                             * span's ends and middle overshoots by at most
                             * 1/8 of the range (middle value equal to an
                             * end: -2t^2 + 3t peaks at 9/8), and midpoint is
                             * within half a texel. */
                            double scale = c ? r->scale2 : r->scale1;
                            double allow = 0.125 * (hi - lo) + 0.5 / scale + 1e-6;
                            double out = fmax(lo - s, s - hi);
                            if (!isfinite(s) || out > allow)
                                fail_msg("%s on %s %dx%d: pixel (%d,%d) s%d = %g outside "
                                         "[%g, %g] by more than %g",
                                         variants[vi], scenes[si], w, h, x, y, c + 1, s, lo, hi,
                                         allow);
                            out /= allow;
                            worst = fmax(worst, out);
                        }
                    }
                print_message("%-30s %-8s %3dx%-3d  %llu fragments  overshoot %.3g of allowance\n",
                              variants[vi], scenes[si], w, h, (unsigned long long)got.fragments,
                              worst);
                persp__capture_free(ctx, &got.cap);
                free(got.drawn);
            }
            persp__capture_free(ctx, &ref.cap);
            free(ref.drawn);
            persp__capture_free(ctx, &inc.cap);
            free(inc.drawn);
        }
        persp_scene_destroy(scene);
    }
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_method_every_scene),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
