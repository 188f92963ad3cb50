/* Sort-first frames (src/render/sort_first.c): how the default chooses
 * them, what a region that runs out of memory falls back to, how their
 * memory is counted, and the cross-core probe behind the choice. That
 * their images and counts are sort middle's is test_render's
 * bench_scene_thread_independent. */
/* ctest-labels: threads (renders with several worker threads) */
#include "support.h"

#include "core/internal.h"
#include "core/pool.h"
#include "raster/frame_cache.h"
#include "raster/raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct rig {
    test_tracker t;
    persp_allocator al;
    persp_context *ctx;
    persp_scene *scene;
    persp_framebuffer fb;
} rig;

enum { W = 256, H = 192 };

static void rig_open_scene(rig *r, const char *scene, int threads, size_t max_memory)
{
    memset(r, 0, sizeof *r);
    r->al = test_tracker_allocator(&r->t);
    persp_context_desc cd = {.allocator = &r->al, .threads = threads, .max_memory = max_memory};
    assert_int_equal(persp_context_create(&cd, &r->ctx), PERSP_OK);
    char path[1024];
    test_source_path(path, sizeof path, scene);
    assert_int_equal(persp_scene_load(r->ctx, path, &r->scene), PERSP_OK);
    r->fb = test_framebuffer(W, H);
}

static void rig_open(rig *r, int threads, size_t max_memory)
{
    rig_open_scene(r, "scenes/bench/torus-20k.json", threads, max_memory);
}

static void rig_close(rig *r)
{
    test_framebuffer_free(&r->fb);
    persp_scene_destroy(r->scene);
    persp_context_destroy(r->ctx);
    assert_int_equal(r->t.live, 0);
}

static persp_render_stats rig_render(rig *r, persp_toggle sort_first, uint64_t *hash)
{
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.shading = PERSP_SHADING_GOURAUD_PC;
    d.sort_first = sort_first;
    persp_render_stats st;
    persp_status s = persp_render(r->ctx, r->scene, &d, &r->fb, &st);
    if (s != PERSP_OK) fail_msg("render: %s", persp_context_error(r->ctx));
    if (hash) *hash = test_hash(r->fb.color, (size_t)W * H * 4);
    return st;
}

/* The regions' buffers count in the context's use while it keeps them
 * (its count is what the allocator has handed out, exactly), its peak is
 * at least the allocator's, and all of it is given back with the context
 * (rig_close). */
static void test_memory_counted(void **state)
{
    (void)state;
    rig r;
    rig_open(&r, 2, 0);
    uint64_t h_on, h_off;
    persp_render_stats st = rig_render(&r, PERSP_TOGGLE_ON, &h_on);
    assert_int_equal(st.sort_first_regions, 2);
    assert_int_equal(r.ctx->mem_used, r.t.live);
    assert_true(r.ctx->mem_peak >= r.t.peak);
    st = rig_render(&r, PERSP_TOGGLE_OFF, &h_off);
    assert_int_equal(st.sort_first_regions, 0);
    assert_true(h_on == h_off);
    st = rig_render(&r, PERSP_TOGGLE_ON, NULL);
    assert_int_equal(st.sort_first_regions, 2);
    assert_int_equal(r.ctx->mem_used, r.t.live);
    assert_true(r.ctx->mem_peak >= r.t.peak);
    rig_close(&r);
}

/* Under a budget that sort middle fits in and the regions, each holding
 * its own vertex stage and records in half of what is free, do not: the
 * frame is drawn sort middle, the same image, no error, and the regions'
 * buffers given back. On the 2M-triangle torus, with small batches of
 * records, the vertex stage's buffers, which each region holds whole,
 * decide. */
static void test_over_budget_falls_back(void **state)
{
    (void)state;
    enum { BATCH = 512 };
    static const char BIG[] = "scenes/bench/torus-2m.json";
    rig r;
    rig_open_scene(&r, BIG, 2, 0);
    r.ctx->frame_batch = BATCH;
    const size_t loaded = r.t.live;
    uint64_t ref;
    (void)rig_render(&r, PERSP_TOGGLE_OFF, &ref);
    const size_t middle = r.t.peak - loaded;
    rig_close(&r);
    rig_open_scene(&r, BIG, 2, 0);
    r.ctx->frame_batch = BATCH;
    (void)rig_render(&r, PERSP_TOGGLE_ON, NULL);
    const size_t first = r.t.peak - loaded;
    rig_close(&r);
    /* Two copies of the vertex stage's buffers outweigh one. */
    if (first <= middle) fail_msg("sort first took %zu bytes, sort middle %zu", first, middle);

    const size_t budget = loaded + middle + (first - middle) / 2;
    rig_open_scene(&r, BIG, 2, budget);
    r.ctx->frame_batch = BATCH;
    uint64_t h;
    persp_render_stats st = rig_render(&r, PERSP_TOGGLE_ON, &h);
    assert_int_equal(st.sort_first_regions, 0);
    assert_true(h == ref);
    assert_string_equal(persp_context_error(r.ctx), "");
    assert_int_equal(r.ctx->mem_used, r.t.live);
    assert_true(r.t.peak <= budget);
    /* Again: the regions are tried afresh and fall back the same way. */
    st = rig_render(&r, PERSP_TOGGLE_ON, &h);
    assert_int_equal(st.sort_first_regions, 0);
    assert_true(h == ref);
    rig_close(&r);
}

/* The default: sort first with two workers whose round trip is over the
 * threshold, never with one or three, and never when the threshold is out
 * of reach. The probe counts a worker that did not join it within a fifth
 * of a millisecond as near, which on a loaded machine (the suite runs its
 * tests side by side) may happen many times over: each frame here probes
 * afresh, for up to ten seconds. */
static void test_default_choice(void **state)
{
    (void)state;
    rig r;
    rig_open(&r, 2, 0);
    r.ctx->sort_first_ns = 1e-9;
    int sorted = 0;
    const double t0 = persp__now_seconds();
    while (!sorted && persp__now_seconds() - t0 < 10.0) {
        sorted = rig_render(&r, PERSP_TOGGLE_DEFAULT, NULL).sort_first_regions == 2;
        ((struct persp_render_cache *)r.ctx->render)->probe_at = 0.0;
    }
    assert_true(sorted);
    rig_close(&r);
    const int threads[] = {1, 2, 3};
    for (size_t k = 0; k < sizeof threads / sizeof *threads; k++) {
        rig_open(&r, threads[k], 0);
        r.ctx->sort_first_ns = threads[k] == 2 ? 1e12 : 1e-9;
        for (int f = 0; f < 3; f++)
            assert_int_equal(rig_render(&r, PERSP_TOGGLE_DEFAULT, NULL).sort_first_regions, 0);
        rig_close(&r);
    }
}

/* The probe: no figure with one worker; with two, a positive time once the
 * other worker joins (tried for up to ten seconds, as above). */
static void test_round_trip_probe(void **state)
{
    (void)state;
    persp_context *one = test_context_threads(1);
    assert_true(persp__pool_round_trip_ns(one) == 0.0);
    persp_context_destroy(one);
    persp_context *two = test_context_threads(2);
    double ns = 0.0;
    const double t0 = persp__now_seconds();
    while (ns <= 0.0 && persp__now_seconds() - t0 < 10.0)
        ns = persp__pool_round_trip_ns(two);
    /* No upper bound: on a loaded machine a trip waits for the other
     * thread to be scheduled. */
    assert_true(ns > 0.0 && isfinite(ns));
    persp_context_destroy(two);
}

/* The regions' runs of tiles move from frame to frame to balance their
 * times (sort_first.c, balance): every frame keeps sort middle's image,
 * and the runs stay in order, each at least a tile, covering the frame. */
static void test_bands_move_image_stays(void **state)
{
    (void)state;
    for (int threads = 2; threads <= 3; threads++) {
        rig r;
        rig_open(&r, threads, 0);
        uint64_t ref;
        (void)rig_render(&r, PERSP_TOGGLE_OFF, &ref);
        for (int frame = 0; frame < 8; frame++) {
            uint64_t h;
            persp_render_stats st = rig_render(&r, PERSP_TOGGLE_ON, &h);
            assert_int_equal(st.sort_first_regions, (uint64_t)threads);
            if (h != ref) fail_msg("%d threads, frame %d: the image changed", threads, frame);
            const struct persp_render_cache *c = r.ctx->render;
            assert_int_equal(c->split_regions, threads);
            assert_int_equal(c->split_tiles, ((W + PERSP_TILE - 1) / PERSP_TILE) *
                                                 ((H + PERSP_TILE - 1) / PERSP_TILE));
            assert_int_equal(c->split[0], 0);
            assert_int_equal(c->split[threads], c->split_tiles);
            for (int k = 0; k < threads; k++)
                assert_true(c->split[k] < c->split[k + 1]);
        }
        rig_close(&r);
    }
}

/* The test a region's frame drops triangles and clusters by
 * (persp__box_reaches_run) against the tiles themselves, for every box
 * and run of tiles of frames up to 5 × 5 tiles. */
static void test_box_reaches_tiles(void **state)
{
    (void)state;
    long checked = 0;
    for (int w = 1; w <= 5; w++)
        for (int h = 1; h <= 5; h++)
            for (int a = 0; a < w * h; a++)
                for (int b = a + 1; b <= w * h; b++)
                    for (int x0 = 0; x0 < w; x0++)
                        for (int x1 = x0; x1 < w; x1++)
                            for (int y0 = 0; y0 < h; y0++)
                                for (int y1 = y0; y1 < h; y1++) {
                                    int want = 0;
                                    for (int y = y0; y <= y1; y++)
                                        for (int x = x0; x <= x1; x++)
                                            want |= y * w + x >= a && y * w + x < b;
                                    const persp_tile_run run = persp__tile_run(w, a, b);
                                    if (persp__box_reaches_run(&run, x0, x1, y0, y1) != want)
                                        fail_msg("%dx%d tiles, run %d..%d, box %d..%d x %d..%d: %d",
                                                 w, h, a, b - 1, x0, x1, y0, y1, !want);
                                    checked++;
                                }
    assert_true(checked > 100000);
}

/* Settings out of range are named, as persp_render names its others. */
static void test_out_of_range(void **state)
{
    (void)state;
    rig r;
    rig_open(&r, 2, 0);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.sort_first = (persp_toggle)7;
    assert_int_equal(persp_render(r.ctx, r.scene, &d, &r.fb, NULL), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(r.ctx), "persp_render_desc.sort_first"));
    rig_close(&r);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_memory_counted),
        cmocka_unit_test(test_over_budget_falls_back),
        cmocka_unit_test(test_default_choice),
        cmocka_unit_test(test_round_trip_probe),
        cmocka_unit_test(test_bands_move_image_stays),
        cmocka_unit_test(test_box_reaches_tiles),
        cmocka_unit_test(test_out_of_range),
    };
    return TEST_RUN(argc, argv, tests);
}
