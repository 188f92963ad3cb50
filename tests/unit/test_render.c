/* End-to-end rendering invariants: thread-count independence, depth modes,
 * immediate drawing, bad framebuffers. */
/* ctest-labels: threads (renders with several worker threads) */
/* ctest-split: each (minutes in all under ThreadSanitizer and qemu-user) */
/* Tests that render with one thread only (batches against one batch, the
 * serial drawings against each other), left out of the ThreadSanitizer pass:
 * ctest-one-thread: test_adaptive_batches_bit_identical
 * ctest-one-thread: test_submission_order_kept_40000_t1_b5, test_submission_order_kept_40000_t1_b999
 * ctest-one-thread: test_submission_order_kept_40000_near_t1_b5
 * ctest-one-thread: test_submission_order_kept_40000_near_t1_b999 */
#include "support.h"

#include "core/internal.h"
#include "raster/raster.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Renders a scene — built-in, or a file named relative to the source tree
 * (it contains a '/') — with d on a context of the given threads and
 * triangle batch size (0: the renderer's), and hashes the colour buffer;
 * keep (when not NULL) receives the colour buffer instead of it being
 * freed, stats (when not NULL) the render's statistics. */
static uint64_t render_hash_batched(const char *scene_name, const persp_render_desc *d, int threads,
                                    size_t batch, int w, int h, uint8_t **keep, persp_render_stats *stats)
{
    persp_context *ctx = test_context_threads(threads);
    ctx->frame_batch = batch;
    persp_scene *scene = NULL;
    if (strchr(scene_name, '/')) {
        char path[1024];
        test_source_path(path, sizeof path, scene_name);
        assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    } else {
        assert_int_equal(persp_scene_builtin(ctx, scene_name, &scene), PERSP_OK);
    }
    persp_framebuffer fb = test_framebuffer(w, h);
    persp_render_stats st;
    persp_status s = persp_render(ctx, scene, d, &fb, &st);
    if (s != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    assert_true(st.pixels_written > 0);
    uint64_t hash = test_hash(fb.color, (size_t)w * h * 4);
    if (stats) *stats = st;
    if (keep) {
        *keep = fb.color;
        fb.color = NULL;
    }
    test_framebuffer_free(&fb);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return hash;
}

/* The small-triangle path (rows packed into lanes) against spans: the
 * same image bit for bit, for the filters and shading it takes, both depth
 * modes, one and two threads. The 2k-triangle torus at 256×192 has
 * triangles a few pixels wide, which all take the packed path. */
static const char *const small_filters[] = {"nearest", "bilinear", "trilinear", "nearest-mip-linear"};
static const char *const small_shadings[] = {"none", "gouraud-pc", "phong-pc"};

static void test_small_triangles_as_spans(void **state)
{
    (void)state;
    int compared = 0;
    for (size_t fi = 0; fi < sizeof small_filters / sizeof *small_filters; fi++)
        for (size_t si = 0; si < sizeof small_shadings / sizeof *small_shadings; si++)
            for (int dm = 0; dm < 2; dm++) {
                uint64_t h[2];
                for (int span_only = 0; span_only < 2; span_only++) {
                    persp_context *ctx = test_context_threads(1 + (int)fi % 2);
                    ctx->span_only = span_only;
                    char path[1024];
                    test_source_path(path, sizeof path, "scenes/bench/torus-2k.json");
                    persp_scene *scene = NULL;
                    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
                    persp_render_desc d;
                    memset(&d, 0, sizeof d);
                    assert_int_equal(persp_filter_parse(small_filters[fi], &d.filter, NULL), PERSP_OK);
                    assert_int_equal(persp_shading_parse(small_shadings[si], &d.shading), PERSP_OK);
                    d.depth_mode = dm ? PERSP_DEPTH_INVW : PERSP_DEPTH_Z;
                    enum { W = 256, H = 192 };
                    persp_framebuffer fb = test_framebuffer(W, H);
                    persp_render_stats st;
                    if (persp_render(ctx, scene, &d, &fb, &st) != PERSP_OK)
                        fail_msg("render: %s", persp_context_error(ctx));
                    assert_true(st.pixels_written > W * H / 4);
                    h[span_only] = test_hash(fb.color, W * H * 4);
                    test_framebuffer_free(&fb);
                    persp_scene_destroy(scene);
                    persp_context_destroy(ctx);
                }
                if (h[0] != h[1])
                    fail_msg("%s, %s, depth %s: packed %016llx, spans %016llx", small_filters[fi],
                             small_shadings[si], dm ? "invw" : "z", (unsigned long long)h[0],
                             (unsigned long long)h[1]);
                compared++;
            }
    assert_int_equal(compared, 24);
}

/* A two-thread context with the given --simd variant, or NULL where this
 * CPU cannot run it. */
static persp_context *soup_context(persp_simd simd)
{
    persp_context *ctx = NULL;
    persp_context_desc cd = {.threads = 2, .simd = simd};
    persp_status st = persp_context_create(&cd, &ctx);
    if (st == PERSP_ERR_UNSUPPORTED) return NULL;
    assert_int_equal(st, PERSP_OK);
    return ctx;
}

/* The soup: triangles of one tile overlap, so consecutive small triangles
 * that share a lane batch often cover the same pixel, which the batch must
 * not hold twice (the depth tests would not see each other); lit, the lanes
 * that fail the depth test are packed out before sampling (by AVX-512
 * compress, by the AVX2 permutation and by the portable loop, each where
 * the CPU runs it), and a filter with a level of detail samples each packed
 * segment with its own triangle's derivatives. One shading and filter per
 * test (si / 2 and si % 2): each takes about a minute under
 * ThreadSanitizer. */
static void small_triangles_as_spans_soup(size_t si)
{
    const char *filter = si % 2 ? "trilinear" : "bilinear";
    /* Lanes packed by AVX-512, spans, lanes packed portably, lanes packed
     * by AVX2. */
    static const char *const kind_name[4] = {"avx512 packing", "spans", "portable packing", "avx2 packing"};
    uint64_t h[4];
    int ran[4] = {0};
    for (int kind = 0; kind < 4; kind++) {
        persp_context *ctx = soup_context(kind == 0 ? PERSP_SIMD_AVX512 : PERSP_SIMD_AVX2);
        if (!ctx && kind == 1) ctx = soup_context(PERSP_SIMD_BASELINE);
        if (!ctx) continue;
        ctx->span_only = kind == 1;
        ctx->pack_portable = kind == 2;
        char path[1024];
        test_source_path(path, sizeof path, "scenes/bench/soup-200k.json");
        persp_scene *scene = NULL;
        assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
        persp_render_desc d;
        memset(&d, 0, sizeof d);
        assert_int_equal(persp_shading_parse(small_shadings[si / 2], &d.shading), PERSP_OK);
        assert_int_equal(persp_filter_parse(filter, &d.filter, NULL), PERSP_OK);
        enum { W = 256, H = 192 };
        persp_framebuffer fb = test_framebuffer(W, H);
        persp_render_stats st;
        if (persp_render(ctx, scene, &d, &fb, &st) != PERSP_OK)
            fail_msg("render: %s", persp_context_error(ctx));
        assert_true(st.fragments > 4 * st.pixels_written / 3); /* overdraw */
        h[kind] = test_hash(fb.color, W * H * 4);
        ran[kind] = 1;
        test_framebuffer_free(&fb);
        persp_scene_destroy(scene);
        persp_context_destroy(ctx);
    }
    assert_true(ran[1]);
    for (int kind = 0; kind < 4; kind++)
        if (ran[kind] && h[kind] != h[1])
            fail_msg("soup, %s, %s: %s %016llx, spans %016llx", small_shadings[si / 2], filter, kind_name[kind],
                     (unsigned long long)h[kind], (unsigned long long)h[1]);
}

static void test_small_triangles_as_spans_soup_none_bilinear(void **state)
{
    (void)state;
    small_triangles_as_spans_soup(0);
}

static void test_small_triangles_as_spans_soup_none_trilinear(void **state)
{
    (void)state;
    small_triangles_as_spans_soup(1);
}

static void test_small_triangles_as_spans_soup_gouraud_bilinear(void **state)
{
    (void)state;
    small_triangles_as_spans_soup(2);
}

static void test_small_triangles_as_spans_soup_gouraud_trilinear(void **state)
{
    (void)state;
    small_triangles_as_spans_soup(3);
}

static void test_small_triangles_as_spans_soup_phong_bilinear(void **state)
{
    (void)state;
    small_triangles_as_spans_soup(4);
}

static void test_small_triangles_as_spans_soup_phong_trilinear(void **state)
{
    (void)state;
    small_triangles_as_spans_soup(5);
}

static uint64_t render_hash_desc(const char *scene_name, const persp_render_desc *d, int threads, int w,
                                 int h, uint8_t **keep)
{
    return render_hash_batched(scene_name, d, threads, 0, w, h, keep, NULL);
}

static uint64_t render_hash(const char *scene_name, const char *method, int threads, persp_depth_mode dm,
                            int w, int h, uint8_t **keep)
{
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.method = method;
    d.depth_mode = dm;
    return render_hash_desc(scene_name, &d, threads, w, h, keep);
}

static void test_threads_bit_identical(void **state)
{
    (void)state;
    const char *scenes[] = {"corridor", "floor", "cube"};
    for (int i = 0; i < 3; i++) {
        uint64_t h1 = render_hash(scenes[i], "exact", 1, PERSP_DEPTH_Z, 333, 257, NULL);
        uint64_t h2 = render_hash(scenes[i], "exact", 2, PERSP_DEPTH_Z, 333, 257, NULL);
        uint64_t h5 = render_hash(scenes[i], "exact", 5, PERSP_DEPTH_Z, 333, 257, NULL);
        assert_true(h1 == h2);
        assert_true(h1 == h5);
    }
}

/* Bit-identical images for 1, 2 and 3 threads across the filters whose span
 * samplers differ (vectorised, general, anisotropic) and methods with their
 * own traversal (constz) or per-triangle fits (bezier). */

static void test_threads_bit_identical_filters(void **state)
{
    (void)state;
    const char *filters[] = {"nearest", "bilinear", "trilinear", "nearest-mip-linear", "aniso:4"};
    const char *methods[] = {"exact", "constz", "bezier"};
    for (size_t fi = 0; fi < sizeof filters / sizeof *filters; fi++)
        for (size_t mi = 0; mi < sizeof methods / sizeof *methods; mi++) {
            persp_render_desc d;
            memset(&d, 0, sizeof d);
            d.method = methods[mi];
            assert_int_equal(persp_filter_parse(filters[fi], &d.filter, &d.max_aniso), PERSP_OK);
            uint64_t h1 = render_hash_desc("corridor", &d, 1, 301, 203, NULL);
            uint64_t h2 = render_hash_desc("corridor", &d, 2, 301, 203, NULL);
            uint64_t h3 = render_hash_desc("corridor", &d, 3, 301, 203, NULL);
            if (h1 != h2 || h1 != h3)
                fail_msg("%s / %s: hashes %016llx %016llx %016llx for 1, 2, 3 threads", filters[fi],
                         methods[mi], (unsigned long long)h1, (unsigned long long)h2,
                         (unsigned long long)h3);
        }
}

/* After the first frame the renderer reuses its buffers: rendering the same
 * scene again allocates nothing (counted through the user allocator), sort
 * first too (persp_render_desc.sort_first) with its regions' shares kept
 * (persp_context.sort_first_static): moved to balance the regions' times,
 * a region's buffers grow (by doubling) when its share outgrows them. */
typedef struct counting_alloc {
    long allocs;
} counting_alloc;

static void *count_alloc(void *user, size_t size)
{
    ((counting_alloc *)user)->allocs++;
    return malloc(size);
}

static void count_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

static void test_no_allocation_after_first_frame(void **state)
{
    (void)state;
    counting_alloc counter = {0};
    persp_allocator a = {count_alloc, count_free, &counter};
    for (int run = 0; run < 3; run++) {
        const int threads = run ? 2 : 1;
        const persp_toggle sort_first = run == 2 ? PERSP_TOGGLE_ON : PERSP_TOGGLE_OFF;
        persp_context_desc cd = {.allocator = &a, .threads = threads};
        persp_context *ctx = NULL;
        assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
        persp_scene *scene = NULL;
        assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
        const int w = 256, h = 192;
        persp_framebuffer fb = test_framebuffer(w, h);
        persp_render_desc d;
        memset(&d, 0, sizeof d);
        d.filter = PERSP_FILTER_TRILINEAR;
        d.sort_first = sort_first;
        ctx->sort_first_static = 1;
        assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_OK);
        long first = counter.allocs;
        assert_true(first > 0);
        for (int frame = 0; frame < 3; frame++)
            assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_OK);
        if (counter.allocs != first)
            fail_msg("%d thread(s)%s: %ld allocations in frames after the first", threads,
                     sort_first == PERSP_TOGGLE_ON ? " sort first" : "", counter.allocs - first);
        test_framebuffer_free(&fb);
        persp_scene_destroy(scene);
        persp_context_destroy(ctx);
    }
}

/* The covered range of a row (found from the edge equations with a rounded
 * quotient and an exact correction) equals the pixels whose centres pass
 * all three edge tests, evaluated one by one. */
static void test_row_range_brute_force(void **state)
{
    (void)state;
    test_rng rng = {77};
    long rows = 0, pixels = 0;
    for (int tri = 0; tri < 3000; tri++) {
        persp_winvert v[3];
        float attr[PERSP_A_COUNT] = {0};
        double span = tri % 3 == 0 ? 4.0 : tri % 3 == 1 ? 200.0 : 30000.0;
        for (int i = 0; i < 3; i++) {
            v[i].x = test_rng_uniform(&rng, 100.0 - span, 100.0 + span);
            v[i].y = test_rng_uniform(&rng, 60.0 - span, 60.0 + span);
            if (tri % 5 == 0) v[i].x = floor(v[i].x) + 0.5; /* edges through pixel centres */
            v[i].z = 0.5;
            v[i].q = 1.0;
            v[i].attr = attr;
        }
        persp_tri t;
        if (!persp__setup_triangle(v, 200, 120, 0, &t, NULL)) continue;
        for (int y = t.ymin; y <= t.ymax; y++) {
            int x0 = (int)(test_rng_next(&rng) % 64), x1 = x0 + 64 + (int)(test_rng_next(&rng) % 100);
            int want_lo = -1, want_hi = -2;
            for (int x = x0 < t.xmin ? t.xmin : x0; x <= x1 && x <= t.xmax; x++) {
                int64_t X = (int64_t)x * PERSP_SUBPIXEL + PERSP_SUBPIXEL / 2;
                int64_t Y = (int64_t)y * PERSP_SUBPIXEL + PERSP_SUBPIXEL / 2;
                int in = 1;
                for (int k = 0; k < 3; k++) in &= t.ea[k] * X + t.eb[k] * Y + t.ec[k] >= 0;
                if (in) {
                    if (want_lo < 0) want_lo = x;
                    if (want_hi != x - 1 && want_hi >= 0) fail_msg("row %d of triangle %d is not convex", y, tri);
                    want_hi = x;
                }
            }
            int lo = -1, hi = -2;
            int got = persp__tri_row_range(&t, y, x0, x1, &lo, &hi);
            if (want_lo < 0) {
                if (got) fail_msg("triangle %d row %d: got [%d, %d], expected empty", tri, y, lo, hi);
            } else if (!got || lo != want_lo || hi != want_hi) {
                fail_msg("triangle %d row %d in [%d, %d]: got %d [%d, %d], expected [%d, %d]", tri, y,
                         x0, x1, got, lo, hi, want_lo, want_hi);
            } else {
                pixels += hi - lo + 1;
            }
            rows++;
        }
    }
    print_message("%ld rows, %ld pixels compared\n", rows, pixels);
    assert_true(rows > 10000);
}

/* Instrumented render: with count_ops the methods' own counts reach the
 * statistics — exact is one division per pixel, and the counts do not depend
 * on the thread count; without it nothing is counted. */
static void test_count_ops(void **state)
{
    (void)state;
    const char *methods[] = {"exact", "constz", "midpoint", "quadratic"};
    for (size_t mi = 0; mi < sizeof methods / sizeof *methods; mi++) {
        persp_opcount got[3];
        uint64_t fragments = 0;
        for (int run = 0; run < 3; run++) {
            persp_context *ctx = test_context_threads(run == 1 ? 3 : 1);
            persp_scene *scene = NULL;
            assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
            enum { W = 160, H = 120 };
            uint8_t *color = malloc(W * H * 4);
            float *depth = malloc(W * H * sizeof(float));
            persp_framebuffer fb = {W, H, color, depth};
            persp_render_desc d;
            memset(&d, 0, sizeof d);
            d.method = methods[mi];
            d.count_ops = run < 2 ? PERSP_TOGGLE_ON : PERSP_TOGGLE_DEFAULT;
            persp_render_stats st;
            assert_int_equal(persp_render(ctx, scene, &d, &fb, &st), PERSP_OK);
            got[run] = st.ops;
            fragments = st.fragments;
            free(color);
            free(depth);
            persp_scene_destroy(scene);
            persp_context_destroy(ctx);
        }
        assert_true(got[0].add > 0);
        assert_memory_equal(&got[0], &got[1], sizeof got[0]);
        assert_true(got[2].div == 0 && got[2].mul == 0 && got[2].add == 0 && got[2].cmp == 0);
        if (mi == 0) assert_true(got[0].div == fragments);
        else assert_true(got[0].div < fragments / 4);
    }
}

static void test_every_pixel_covered_corridor(void **state)
{
    (void)state;
    /* docs/WORKLOADS.md: every pixel of the corridor is covered, each once per
     * depth-passing fragment; with depth mode 1/w the image is the same as
     * with z (both resolve the same nearest surface). */
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
    enum { W = 256, H = 192 };
    uint8_t *color = malloc(W * H * 4);
    float *depth = malloc(W * H * sizeof(float));
    persp_framebuffer fb = {W, H, color, depth};
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    persp_render_stats st;
    assert_int_equal(persp_render(ctx, scene, &d, &fb, &st), PERSP_OK);
    assert_int_equal(st.fragments, (uint64_t)W * H);
    for (int i = 0; i < W * H; i++) assert_true(depth[i] < 1.0f);
    free(color);
    free(depth);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    uint8_t *a, *b;
    render_hash("cube", "exact", 1, PERSP_DEPTH_Z, 200, 150, &a);
    render_hash("cube", "exact", 1, PERSP_DEPTH_INVW, 200, 150, &b);
    long differ = 0;
    for (int i = 0; i < 200 * 150 * 4; i++) differ += a[i] != b[i];
    assert_true(differ < 200 * 150 * 4 / 1000);
    free(a);
    free(b);
}

static void test_draw_depth_order(void **state)
{
    (void)state;
    /* Two overlapping screen-filling triangles: the nearer one wins whatever
     * the submission order, in both depth modes. */
    persp_context *ctx = test_context();
    enum { W = 32, H = 32 };
    uint8_t color[W * H * 4];
    float depth[W * H];
    persp_framebuffer fb = {W, H, color, depth};
    persp_mat4 proj = persp_perspective(90.0, 1.0, 0.1, 10.0);
    persp_vertex v[6];
    memset(v, 0, sizeof v);
    const float zs[2] = {-2.0f, -1.0f};
    for (int t = 0; t < 2; t++) {
        float z = zs[t], s = -z * 3.0f;
        float p[3][2] = {{-s, -s}, {s, -s}, {0, s}};
        for (int k = 0; k < 3; k++) {
            v[3 * t + k].pos[0] = p[k][0], v[3 * t + k].pos[1] = p[k][1], v[3 * t + k].pos[2] = z;
        }
    }
    uint32_t idx[6] = {0, 1, 2, 3, 4, 5};
    for (int mode = 0; mode < 2; mode++) {
        persp_depth_mode dm = mode ? PERSP_DEPTH_INVW : PERSP_DEPTH_Z;
        const uint8_t black[4] = {0, 0, 0, 255};
        persp_framebuffer_clear(&fb, black, dm);
        persp_draw_desc d;
        memset(&d, 0, sizeof d);
        d.mvp = proj;
        d.depth_mode = dm;
        assert_int_equal(persp_draw(ctx, &fb, &d, v, 6, idx, 6), PERSP_OK);
        /* Centre pixel depth equals the nearer triangle's (z = -1). */
        float dc = depth[(H / 2) * W + W / 2];
        if (dm == PERSP_DEPTH_Z) {
            double zn = (-(10.0 + 0.1) / (10.0 - 0.1) * -1.0 - 2 * 10.0 * 0.1 / (10.0 - 0.1)) / 1.0;
            assert_true(fabs(dc - (zn + 1) / 2) < 1e-4);
        } else {
            assert_true(fabs(dc - 1.0) < 1e-5);
        }
    }
    persp_context_destroy(ctx);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "nonexistent", &scene), PERSP_ERR_NOT_FOUND);
    assert_non_null(strstr(persp_context_error(ctx), "nonexistent"));
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
    persp_framebuffer fb = {0, 10, NULL, NULL};
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_ERR_INVALID_ARGUMENT);
    uint8_t color[16 * 4];
    float depth[16];
    persp_framebuffer ok = {4, 4, color, depth};
    d.method = "no-such-method";
    assert_int_equal(persp_render(ctx, scene, &d, &ok, NULL), PERSP_ERR_NOT_FOUND);
    d.method = "exact:7";
    assert_int_equal(persp_render(ctx, scene, &d, &ok, NULL), PERSP_ERR_INVALID_ARGUMENT);
    /* A setting out of range is named, with its range; max_aniso's is that
     * of "aniso:N" (persp_filter_parse), 0 the default. */
    d.method = NULL;
    const int anisos[] = {-1, 1, 17};
    for (int i = 0; i < 3; i++) {
        d.max_aniso = anisos[i];
        assert_int_equal(persp_render(ctx, scene, &d, &ok, NULL), PERSP_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(persp_context_error(ctx), "max_aniso (0, or 2..16)"));
    }
    d.max_aniso = 2;
    assert_int_equal(persp_render(ctx, scene, &d, &ok, NULL), PERSP_OK);
    d.max_aniso = 0;
    d.lod_bias = NAN;
    assert_int_equal(persp_render(ctx, scene, &d, &ok, NULL), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "lod_bias"));
    d.lod_bias = 0;
    persp_filter f1;
    int n1 = 0;
    assert_int_equal(persp_filter_parse("aniso:1", &f1, &n1), PERSP_ERR_INVALID_ARGUMENT);
    /* persp_draw's sampler: the same range, named. */
    persp_draw_desc ad;
    memset(&ad, 0, sizeof ad);
    ad.mvp = persp_perspective(60, 1, 0.1, 10);
    ad.texture = persp_scene_get_texture(scene, 0);
    assert_non_null(ad.texture);
    ad.sampler.filter = PERSP_FILTER_ANISO;
    ad.sampler.max_aniso = 1;
    const persp_vertex av[3] = {{{-1, -1, -2}, {0, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                                {{1, -1, -2}, {1, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                                {{-1, 1, -2}, {0, 1}, {0, 0, 1}, {1, 1, 1, 1}}};
    const uint32_t ai[3] = {0, 1, 2};
    assert_int_equal(persp_draw(ctx, &ok, &ad, av, 3, ai, 3), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "sampler.max_aniso (0, or 2..16)"));
    ad.sampler.max_aniso = 2;
    assert_int_equal(persp_draw(ctx, &ok, &ad, av, 3, ai, 3), PERSP_OK);
    /* NaN and infinite vertices are dropped, not drawn, and cause no UB. */
    persp_vertex v[3];
    memset(v, 0, sizeof v);
    v[0].pos[0] = NAN;
    v[1].pos[0] = INFINITY;
    v[2].pos[2] = -1;
    uint32_t idx[3] = {0, 1, 2};
    persp_draw_desc dd;
    memset(&dd, 0, sizeof dd);
    dd.mvp = persp_perspective(60, 1, 0.1, 10);
    persp_framebuffer_clear(&ok, NULL, PERSP_DEPTH_Z);
    assert_int_equal(persp_draw(ctx, &ok, &dd, v, 3, idx, 3), PERSP_OK);
    for (int i = 0; i < 16; i++) assert_true(depth[i] == 1.0f);
    uint32_t bad[3] = {0, 1, 7};
    assert_int_equal(persp_draw(ctx, &ok, &dd, v, 3, bad, 3), PERSP_ERR_INVALID_ARGUMENT);
    /* A visible triangle is dropped when any attribute of a vertex is not
     * finite (the vertex stage's probe), whichever attribute it is; with
     * all of them finite it is drawn. */
    persp_vertex tri[3] = {{{-1, -1, -2}, {0, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                           {{3, -1, -2}, {1, 0}, {0, 0, 1}, {1, 1, 1, 1}},
                           {{-1, 3, -2}, {0, 1}, {0, 0, 1}, {1, 1, 1, 1}}};
    for (int which = -1; which < 4; which++) {
        persp_vertex w[3];
        memcpy(w, tri, sizeof w);
        if (which == 0) w[1].uv[1] = NAN;
        if (which == 1) w[2].color[2] = INFINITY;
        if (which == 2) w[0].color[3] = -INFINITY;
        if (which == 3) w[1].pos[1] = NAN;
        persp_framebuffer_clear(&ok, NULL, PERSP_DEPTH_Z);
        assert_int_equal(persp_draw(ctx, &ok, &dd, w, 3, idx, 3), PERSP_OK);
        int drawn = 0;
        for (int i = 0; i < 16; i++) drawn += depth[i] != 1.0f;
        if (which < 0) assert_int_equal(drawn, 16);
        else if (drawn) fail_msg("case %d: a vertex with a non-finite attribute was drawn", which);
    }
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* Two-sided Gouraud lights back faces either in the vertex stage, for
 * every vertex, or at set-up, for the triangles that show their back
 * (frame.c, back_colours; chosen by culling): both must give the same
 * image. Seen from inside its tube, every visible triangle of the torus
 * shows its back (its normals face away from the eye), so a back colour
 * computed wrongly in either place changes the image. */
static uint64_t render_back_lighting(const char *scene_name, const persp_render_desc *d, int threads,
                                     int back, persp_render_stats *st)
{
    persp_context *ctx = test_context_threads(threads);
    ctx->back_lighting = back;
    char path[1024];
    test_source_path(path, sizeof path, scene_name);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    persp_framebuffer fb = test_framebuffer(160, 120);
    if (persp_render(ctx, scene, d, &fb, st) != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    const uint64_t h = test_hash(fb.color, (size_t)160 * 120 * 4);
    test_framebuffer_free(&fb);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return h;
}

static void test_back_lighting_places_agree(void **state)
{
    (void)state;
    /* The torus (major radius 1, minor 0.45, in the xz plane): an eye on
     * its tube's centre circle looking along the tube. */
    const persp_mat4 inside = persp_look_at((persp_vec3){0, 0, 1}, (persp_vec3){0.4f, 0.05f, 0.9f},
                                            (persp_vec3){0, 1, 0});
    const char *scenes[] = {"scenes/bench/torus-2k.json", "scenes/bench/torus-2k.json", "scenes/spheres.json"};
    const persp_mat4 *views[] = {&inside, NULL, NULL};
    const persp_shading shadings[] = {PERSP_SHADING_GOURAUD_PC, PERSP_SHADING_GOURAUD};
    const persp_toggle culls[] = {PERSP_TOGGLE_ON, PERSP_TOGGLE_OFF};
    for (int si = 0; si < 3; si++)
        for (int sh = 0; sh < 2; sh++)
            for (int cu = 0; cu < 2; cu++)
                for (int threads = 1; threads <= 2; threads++) {
                    persp_render_desc d;
                    memset(&d, 0, sizeof d);
                    d.shading = shadings[sh];
                    d.cull_backfaces = culls[cu];
                    d.view = views[si];
                    persp_render_stats st[2];
                    const uint64_t vertex = render_back_lighting(scenes[si], &d, threads, 1, &st[0]);
                    const uint64_t setup = render_back_lighting(scenes[si], &d, threads, 2, &st[1]);
                    /* Inside the tube the faces are back faces: culled, the
                     * view is empty. */
                    if (si == 0 && culls[cu] == PERSP_TOGGLE_ON) assert_int_equal(st[0].pixels_written, 0);
                    else assert_true(st[0].pixels_written > 1000);
                    assert_int_equal(st[0].pixels_written, st[1].pixels_written);
                    if (vertex != setup)
                        fail_msg("%s view %d, shading %d, cull %d, %d threads: backs lit in the vertex stage "
                                 "%016llx, at set-up %016llx",
                                 scenes[si], si, (int)shadings[sh], cu, threads, (unsigned long long)vertex,
                                 (unsigned long long)setup);
                }
}

/* Frames with many triangles are drawn in batches, and meshes of more than
 * a few thousand triangles are set up on the worker threads in slabs; the
 * image must depend neither on where the batches end (tiles draw in
 * submission order) nor on the thread count, lit and textured. */
static void test_batches_bit_identical(void **state)
{
    (void)state;
    const char *scenes[] = {"scenes/spheres.json", "scenes/bench/torus-20k.json"};
    enum { W = 200, H = 150 };
    const size_t batches[] = {0, 1, 7, 1000};
    for (size_t si = 0; si < 2; si++) {
        uint64_t ref = 0;
        for (int threads = 1; threads <= 5; threads += 2)
            for (size_t bi = 0; bi < sizeof batches / sizeof *batches; bi++) {
                persp_render_stats st;
                uint64_t h = render_hash_batched(scenes[si], NULL, threads,
                                                 batches[bi] ? batches[bi] : (size_t)-1, W, H, NULL, &st);
                assert_true(st.triangles_drawn > 1000);
                if (threads == 1 && bi == 0) ref = h;
                else if (h != ref)
                    fail_msg("%s, batch %zu, %d threads: hash %016llx, serial one batch %016llx", scenes[si],
                             batches[bi], threads, (unsigned long long)h, (unsigned long long)ref);
            }
    }
}

/* Every benchmark scene of docs/PERFORMANCE.md (scripts/bench.sh), with
 * each shading the table measures, gives the same image on one, two and
 * three worker threads, from the same triangles and fragments, both sort
 * middle and sort first (persp_render_desc.sort_first). Sort middle: the
 * tori and the soup are set up on the workers in slabs (frame.c,
 * mesh_triangles_parallel; the 2k torus in chunks smaller than the
 * others'), the corridor serially, and the tiles are drawn in parallel in
 * every case. Sort first (src/render/sort_first.c): each worker draws its
 * own tile rows from the triangles reaching them, so that those reaching
 * two regions are set up in both and must be counted once. A triangle set
 * up twice would leave the image as it is (its copy fails the depth test)
 * but not the counts. */
/* shading: the index of the one shading to check, or -1 for all three;
 * sort_first_3: sort first on three threads too (not only two). */
static void bench_scene_thread_independent(const char *scene, int shading, int sort_first_3)
{
    const char *scenes[] = {scene};
    const persp_shading shadings[] = {PERSP_SHADING_NONE, PERSP_SHADING_GOURAUD_PC, PERSP_SHADING_PHONG_PC};
    /* One thread (the reference), then two and three sort middle, then two
     * and three sort first. */
    static const struct {
        int threads;
        persp_toggle sort_first;
    } runs[] = {{1, PERSP_TOGGLE_OFF}, {2, PERSP_TOGGLE_OFF}, {3, PERSP_TOGGLE_OFF},
                {2, PERSP_TOGGLE_ON},  {3, PERSP_TOGGLE_ON}};
    enum { W = 320, H = 240 };
    for (size_t si = 0; si < sizeof scenes / sizeof *scenes; si++)
        for (size_t sh = 0; sh < sizeof shadings / sizeof *shadings; sh++) {
            if (shading >= 0 && sh != (size_t)shading) continue;
            persp_render_desc d;
            memset(&d, 0, sizeof d);
            d.shading = shadings[sh];
            uint64_t ref = 0;
            persp_render_stats ref_st;
            memset(&ref_st, 0, sizeof ref_st);
            for (size_t r = 0; r < sizeof runs / sizeof *runs; r++) {
                const int threads = runs[r].threads;
                if (runs[r].sort_first == PERSP_TOGGLE_ON && threads == 3 && !sort_first_3) continue;
                d.sort_first = runs[r].sort_first;
                persp_render_stats st;
                const uint64_t h = render_hash_batched(scenes[si], &d, threads, 0, W, H, NULL, &st);
                assert_true(st.pixels_written > W * H / 4);
                const uint64_t regions = d.sort_first == PERSP_TOGGLE_ON ? (uint64_t)threads : 0;
                if (st.sort_first_regions != regions)
                    fail_msg("%s, %d threads, sort first %d: drawn in %llu regions", scenes[si], threads,
                             (int)d.sort_first, (unsigned long long)st.sort_first_regions);
                if (r == 0) {
                    ref = h, ref_st = st;
                    continue;
                }
                const char *how = d.sort_first == PERSP_TOGGLE_ON ? "sort first" : "sort middle";
                if (h != ref)
                    fail_msg("%s, shading %d, %d threads %s: hash %016llx, one thread %016llx", scenes[si],
                             (int)shadings[sh], threads, how, (unsigned long long)h, (unsigned long long)ref);
                if (st.triangles_in != ref_st.triangles_in || st.triangles_drawn != ref_st.triangles_drawn ||
                    st.fragments != ref_st.fragments || st.pixels_written != ref_st.pixels_written)
                    fail_msg("%s, shading %d, %d threads %s: %llu in, %llu triangles, %llu fragments, %llu "
                             "written; one thread %llu, %llu, %llu, %llu",
                             scenes[si], (int)shadings[sh], threads, how, (unsigned long long)st.triangles_in,
                             (unsigned long long)st.triangles_drawn, (unsigned long long)st.fragments,
                             (unsigned long long)st.pixels_written, (unsigned long long)ref_st.triangles_in,
                             (unsigned long long)ref_st.triangles_drawn, (unsigned long long)ref_st.fragments,
                             (unsigned long long)ref_st.pixels_written);
            }
        }
}

/* One test per scene, and per shading for the two largest: the 2M torus
 * alone took minutes under ThreadSanitizer and qemu-user. */
static void test_bench_scenes_thread_independent_corridor(void **state)
{
    (void)state;
    bench_scene_thread_independent("corridor", -1, 1);
}

static void test_bench_scenes_thread_independent_torus_2k(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/torus-2k.json", -1, 1);
}

static void test_bench_scenes_thread_independent_torus_20k(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/torus-20k.json", -1, 1);
}

static void test_bench_scenes_thread_independent_torus_200k(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/torus-200k.json", -1, 1);
}

static void test_bench_scenes_thread_independent_torus_2m_none(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/torus-2m.json", 0, 0);
}

static void test_bench_scenes_thread_independent_torus_2m_gouraud(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/torus-2m.json", 1, 0);
}

static void test_bench_scenes_thread_independent_torus_2m_phong(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/torus-2m.json", 2, 0);
}

static void test_bench_scenes_thread_independent_soup_200k_none(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/soup-200k.json", 0, 1);
}

static void test_bench_scenes_thread_independent_soup_200k_gouraud(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/soup-200k.json", 1, 1);
}

static void test_bench_scenes_thread_independent_soup_200k_phong(void **state)
{
    (void)state;
    bench_scene_thread_independent("scenes/bench/soup-200k.json", 2, 1);
}

/* The default batches adapt to how spread the last batch was (frame.c,
 * PERSP_FRAME_BATCH_PER_WORKER): the 200k-triangle soup at 1024×768
 * touches every tile in each batch, so its batches after the first are
 * doubled; the image must be the one of a single batch. */
static void test_adaptive_batches_bit_identical(void **state)
{
    (void)state;
    enum { W = 1024, H = 768 };
    persp_render_stats st[2];
    const uint64_t adaptive = render_hash_batched("scenes/bench/soup-200k.json", NULL, 1, 0, W, H, NULL, &st[0]);
    const uint64_t one = render_hash_batched("scenes/bench/soup-200k.json", NULL, 1, (size_t)-1, W, H, NULL, &st[1]);
    assert_true(st[0].triangles_drawn > 3 * 16384); /* several batches, doubled or not */
    assert_int_equal(st[0].pixels_written, st[1].pixels_written);
    if (adaptive != one)
        fail_msg("soup: adaptive batches %016llx, one batch %016llx", (unsigned long long)adaptive,
                 (unsigned long long)one);
}

/* The same with the depth test off, where the image shows the submission
 * order itself: thousands of overlapping triangles drawn with persp_draw,
 * last one wins at every pixel. nt: 40 000 takes several set-up rounds of
 * full chunks on 4 threads, 3000 one round of smaller chunks (frame.c,
 * SETUP_CHUNK_MIN). */
/* only_threads, only_batch: the one drawing compared with the serial one
 * (0 and SIZE_MAX for every one), so that a case can be split over tests. */
static void submission_order_kept_part(int cross_near, int nt, int only_threads, size_t only_batch)
{
    enum { S = 96 };
    const int NT = nt;
    persp_vertex *v = calloc(3 * (size_t)NT, sizeof *v);
    uint32_t *idx = malloc(3 * (size_t)NT * sizeof *idx);
    assert_non_null(v);
    assert_non_null(idx);
    test_rng rng = {77};
    for (int i = 0; i < 3 * NT; i++) {
        v[i].pos[0] = (float)test_rng_uniform(&rng, -1.2, 1.2);
        v[i].pos[1] = (float)test_rng_uniform(&rng, -1.2, 1.2);
        v[i].pos[2] = (float)test_rng_uniform(&rng, -0.9, 0.9);
        for (int k = 0; k < 3; k++) v[i].color[k] = (float)((i / 3 * (k + 3)) % 251) / 250.0f;
        v[i].color[3] = 1.0f;
        idx[i] = (uint32_t)i;
        /* Every triangle's first vertex in front of the near plane (z < −w):
         * clipping turns each into two or more, so every set-up task's
         * region overflows and the rest of its chunk is set up serially. */
        if (cross_near && i % 3 == 0) v[i].pos[2] = -3.0f;
    }
    const size_t batches[] = {0, 5, 999};
    uint64_t ref = 0;
    int compared = 0;
    for (int threads = 1; threads <= 4; threads += 3)
        for (size_t bi = 0; bi < sizeof batches / sizeof *batches; bi++) {
            const int reference = threads == 1 && bi == 0;
            if (!reference && only_threads && (threads != only_threads || batches[bi] != only_batch))
                continue;
            persp_context *ctx = test_context_threads(threads);
            ctx->frame_batch = batches[bi] ? batches[bi] : (size_t)-1;
            uint8_t color[S * S * 4];
            float depth[S * S];
            persp_framebuffer fb = {S, S, color, depth};
            const uint8_t black[4] = {0, 0, 0, 255};
            persp_framebuffer_clear(&fb, black, PERSP_DEPTH_DEFAULT);
            persp_draw_desc d;
            memset(&d, 0, sizeof d);
            d.mvp = persp_mat4_identity();
            d.depth_test = PERSP_TOGGLE_OFF;
            assert_int_equal(persp_draw(ctx, &fb, &d, v, 3 * (size_t)NT, idx, 3 * (size_t)NT), PERSP_OK);
            uint64_t h = test_hash(color, sizeof color);
            if (reference) ref = h;
            else if (h != ref)
                fail_msg("batch %zu, %d threads: hash %016llx, serial %016llx", batches[bi], threads,
                         (unsigned long long)h, (unsigned long long)ref);
            compared += !reference;
            persp_context_destroy(ctx);
        }
    assert_int_equal(compared, only_threads ? 1 : 5);
    free(v);
    free(idx);
}

static void submission_order_kept(int cross_near, int nt)
{
    submission_order_kept_part(cross_near, nt, 0, SIZE_MAX);
}

/* One test per case, and for 40 000 triangles one per drawing compared with
 * the serial one (each case took over 300 s under ThreadSanitizer on a
 * loaded 2-core machine). */
static void test_submission_order_kept_40000_t1_b5(void **state)
{
    (void)state;
    submission_order_kept_part(0, 40000, 1, 5);
}

static void test_submission_order_kept_40000_t1_b999(void **state)
{
    (void)state;
    submission_order_kept_part(0, 40000, 1, 999);
}

static void test_submission_order_kept_40000_t4_b0(void **state)
{
    (void)state;
    submission_order_kept_part(0, 40000, 4, 0);
}

static void test_submission_order_kept_40000_t4_b5(void **state)
{
    (void)state;
    submission_order_kept_part(0, 40000, 4, 5);
}

static void test_submission_order_kept_40000_t4_b999(void **state)
{
    (void)state;
    submission_order_kept_part(0, 40000, 4, 999);
}

static void test_submission_order_kept_40000_near_t1_b5(void **state)
{
    (void)state;
    submission_order_kept_part(1, 40000, 1, 5);
}

static void test_submission_order_kept_40000_near_t1_b999(void **state)
{
    (void)state;
    submission_order_kept_part(1, 40000, 1, 999);
}

static void test_submission_order_kept_40000_near_t4_b0(void **state)
{
    (void)state;
    submission_order_kept_part(1, 40000, 4, 0);
}

static void test_submission_order_kept_40000_near_t4_b5(void **state)
{
    (void)state;
    submission_order_kept_part(1, 40000, 4, 5);
}

static void test_submission_order_kept_40000_near_t4_b999(void **state)
{
    (void)state;
    submission_order_kept_part(1, 40000, 4, 999);
}

static void test_submission_order_kept_3000(void **state)
{
    (void)state;
    submission_order_kept(0, 3000);
}

static void test_submission_order_kept_3000_near(void **state)
{
    (void)state;
    submission_order_kept(1, 3000);
}

/* An object whose transform mirrors it (negative determinant) has its front
 * faces clockwise in the window; culling must drop its back faces, not its
 * front ones (glTF 2.0 §3.7.4). A closed sphere drawn with culling then
 * shows the same surface as without: the same depth buffer, from fewer
 * triangles. Four placements: as modelled, mirrored in x, mirrored in x and
 * y (determinant positive again), mirrored in all three axes. */
static void test_mirrored_objects_cull_back_faces(void **state)
{
    (void)state;
    const char *scales[] = {"[1, 1, 1]", "[-1, 1, 1]", "[-1, -1, 1]", "[-1, -1, -1]"};
    char dir[256], path[512];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "mirror"), 0);
    snprintf(path, sizeof path, "%s/mirror.json", dir);
    persp_context *ctx = test_context();
    for (int i = 0; i < 4; i++) {
        FILE *fp = fopen(path, "w");
        assert_non_null(fp);
        fprintf(fp,
                "{\"camera\": {\"position\": [0.7, 0.9, 3.2], \"target\": [0, 0, 0], \"fov\": 50},\n"
                " \"render\": {\"shading\": \"gouraud-pc\", \"cull\": true},\n"
                " \"lights\": [{\"type\": \"point\", \"position\": [2, 3, 4]}],\n"
                " \"objects\": [{\"mesh\": {\"primitive\": \"sphere\", \"slices\": 24, \"stacks\": 12},\n"
                "   \"transform\": {\"scale\": %s, \"rotate\": [30, 0, 1, 0.2]}}]}\n",
                scales[i]);
        assert_int_equal(fclose(fp), 0);
        persp_scene *scene = NULL;
        if (persp_scene_load(ctx, path, &scene) != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
        float *depth[2];
        persp_render_stats st[2];
        for (int on = 0; on < 2; on++) {
            persp_framebuffer fb = test_framebuffer(160, 120);
            persp_render_desc d;
            memset(&d, 0, sizeof d);
            d.cull_backfaces = on ? PERSP_TOGGLE_ON : PERSP_TOGGLE_OFF;
            if (persp_render(ctx, scene, &d, &fb, &st[on]) != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
            depth[on] = fb.depth;
            fb.depth = NULL;
            test_framebuffer_free(&fb);
        }
        if (memcmp(depth[0], depth[1], (size_t)160 * 120 * sizeof(float)) != 0)
            fail_msg("scale %s: culling changed the visible surface", scales[i]);
        /* About half the sphere faces the eye. */
        assert_true(st[1].triangles_drawn > 0);
        assert_true(st[1].triangles_drawn * 10 < st[0].triangles_drawn * 7);
        free(depth[0]);
        free(depth[1]);
        persp_scene_destroy(scene);
    }
    persp_context_destroy(ctx);
    assert_int_equal(remove(path), 0);
    assert_int_equal(test_tmpdir_remove(dir), 0);
}

/* Scene surfaces are opaque, clamp-to-border's colour too: the default
 * border (0, 0, 0, 0) drew see-through pixels where the corridor's walls
 * run past the texture's edge. */
static void test_border_is_opaque(void **state)
{
    (void)state;
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.wrap = PERSP_WRAP_CLAMP_TO_BORDER;
    d.filter = PERSP_FILTER_TRILINEAR;
    uint8_t *px = NULL;
    render_hash_batched("corridor", &d, 1, 0, 160, 120, &px, NULL);
    size_t black = 0;
    for (size_t i = 0; i < (size_t)160 * 120; i++) {
        assert_int_equal(px[4 * i + 3], 255);
        black += px[4 * i] == 0 && px[4 * i + 1] == 0 && px[4 * i + 2] == 0;
    }
    assert_true(black > 1000); /* the border is drawn (black), not the texture repeated */
    free(px);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_bit_identical),
        cmocka_unit_test(test_small_triangles_as_spans),
        cmocka_unit_test(test_small_triangles_as_spans_soup_none_bilinear),
        cmocka_unit_test(test_small_triangles_as_spans_soup_none_trilinear),
        cmocka_unit_test(test_small_triangles_as_spans_soup_gouraud_bilinear),
        cmocka_unit_test(test_small_triangles_as_spans_soup_gouraud_trilinear),
        cmocka_unit_test(test_small_triangles_as_spans_soup_phong_bilinear),
        cmocka_unit_test(test_small_triangles_as_spans_soup_phong_trilinear),
        cmocka_unit_test(test_threads_bit_identical_filters),
        cmocka_unit_test(test_no_allocation_after_first_frame),
        cmocka_unit_test(test_row_range_brute_force),
        cmocka_unit_test(test_count_ops),
        cmocka_unit_test(test_batches_bit_identical),
        cmocka_unit_test(test_back_lighting_places_agree),
        cmocka_unit_test(test_bench_scenes_thread_independent_corridor),
        cmocka_unit_test(test_bench_scenes_thread_independent_torus_2k),
        cmocka_unit_test(test_bench_scenes_thread_independent_torus_20k),
        cmocka_unit_test(test_bench_scenes_thread_independent_torus_200k),
        cmocka_unit_test(test_bench_scenes_thread_independent_torus_2m_none),
        cmocka_unit_test(test_bench_scenes_thread_independent_torus_2m_gouraud),
        cmocka_unit_test(test_bench_scenes_thread_independent_torus_2m_phong),
        cmocka_unit_test(test_bench_scenes_thread_independent_soup_200k_none),
        cmocka_unit_test(test_bench_scenes_thread_independent_soup_200k_gouraud),
        cmocka_unit_test(test_bench_scenes_thread_independent_soup_200k_phong),
        cmocka_unit_test(test_adaptive_batches_bit_identical),
        cmocka_unit_test(test_submission_order_kept_40000_t1_b5),
        cmocka_unit_test(test_submission_order_kept_40000_t1_b999),
        cmocka_unit_test(test_submission_order_kept_40000_t4_b0),
        cmocka_unit_test(test_submission_order_kept_40000_t4_b5),
        cmocka_unit_test(test_submission_order_kept_40000_t4_b999),
        cmocka_unit_test(test_submission_order_kept_40000_near_t1_b5),
        cmocka_unit_test(test_submission_order_kept_40000_near_t1_b999),
        cmocka_unit_test(test_submission_order_kept_40000_near_t4_b0),
        cmocka_unit_test(test_submission_order_kept_40000_near_t4_b5),
        cmocka_unit_test(test_submission_order_kept_40000_near_t4_b999),
        cmocka_unit_test(test_submission_order_kept_3000),
        cmocka_unit_test(test_submission_order_kept_3000_near),
        cmocka_unit_test(test_every_pixel_covered_corridor),
        cmocka_unit_test(test_draw_depth_order),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_mirrored_objects_cull_back_faces),
        cmocka_unit_test(test_border_is_opaque),
    };
    return TEST_RUN(argc, argv, tests);
}
