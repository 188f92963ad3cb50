/* Allocation failures: for a workload (load a scene, render it), a
 * successful run counts the allocations that go through the context's
 * allocator; then, for every N from 1 to that count, the same workload runs
 * again with an allocator that refuses the Nth allocation only. Each such
 * run must fail with PERSP_ERR_OUT_OF_MEMORY and a detail that says "out of
 * memory", must not crash, and must leave no block of the allocator live
 * once everything is destroyed (the allocator counts live blocks, so a leak
 * fails here, and in the ASan build LeakSanitizer sees it too).
 *
 * Drawn sort first (persp_render_desc.sort_first), a refused allocation
 * may instead leave the frame to sort middle, which then succeeds: there
 * the run may also return PERSP_OK, with the image of a run that refused
 * nothing, and all else as above.
 *
 * Covered: every built-in scene, a JSON scene with PNG textures and a glTF
 * model with an embedded texture, each with 1 and 2 threads (2 both sort
 * middle and sort first), and a JSON
 * scene built on an OBJ model with MTL and texture files (1 thread). What the
 * decoders (libpng, libjpeg, jansson, Assimp) allocate with malloc does not
 * go through persp_allocator and is not injected here. */
/* ctest-labels: threads (renders with several worker threads) */
/* ctest-split: each (a minute in all under ThreadSanitizer) */
#include "support.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* persp_allocator's contract (persp.h): called only from the thread that
 * called into persp, so the counts need no atomics; the test checks the
 * promise (owner) and the TSan pass would see a worker thread break it. */
typedef struct fail_alloc {
    size_t fail_at; /* 1-based index of the refused allocation; 0: none */
    size_t calls;   /* allocations asked for, the refused one included */
    size_t live;    /* blocks handed out and not yet freed */
    size_t frees;
    pthread_t owner;
    int other_thread; /* calls from a thread other than owner */
} fail_alloc;

static void *fa_alloc(void *user, size_t size)
{
    fail_alloc *a = user;
    if (!pthread_equal(pthread_self(), a->owner)) a->other_thread++;
    if (++a->calls == a->fail_at) return NULL;
    /* persp asks for 16-byte alignment; aligned_alloc wants a multiple of it. */
    void *p = aligned_alloc(16, (size + 15) / 16 * 16);
    if (p) a->live++;
    return p;
}

static void fa_free(void *user, void *ptr)
{
    fail_alloc *a = user;
    if (!pthread_equal(pthread_self(), a->owner)) a->other_thread++;
    if (!ptr) return;
    a->live--;
    a->frees++;
    free(ptr);
}

typedef struct workload {
    const char *scene; /* built-in name, or a path in the source tree (has a '/') */
    int width, height;
} workload;

typedef struct outcome {
    persp_status status;
    char error[512];
    const char *left; /* an object handed out by a call that failed */
    uint64_t hash;    /* of the last frame drawn */
} outcome;

/* Creates a context on a, loads the scene and renders it twice (the second
 * render reuses the per-frame buffers of the first, at another size so that
 * they grow), then destroys everything. */
static outcome run(const workload *w, int threads, persp_toggle sort_first, fail_alloc *a)
{
    outcome o = {PERSP_OK, "", NULL, 0};
    a->owner = pthread_self();
    persp_allocator al = {fa_alloc, fa_free, a};
    persp_context_desc cd = {.allocator = &al, .threads = threads};
    persp_context *ctx = NULL;
    o.status = persp_context_create(&cd, &ctx);
    if (o.status != PERSP_OK) {
        if (ctx) o.left = "context";
        return o;
    }
    persp_scene *scene = NULL;
    if (strchr(w->scene, '/')) {
        char path[1024];
        test_source_path(path, sizeof path, w->scene);
        o.status = persp_scene_load(ctx, path, &scene);
    } else {
        o.status = persp_scene_builtin(ctx, w->scene, &scene);
    }
    if (o.status != PERSP_OK && scene) o.left = "scene";
    size_t pixels = (size_t)w->width * (size_t)w->height;
    uint8_t *color = malloc(pixels * 4);
    float *depth = malloc(pixels * sizeof *depth);
    assert_non_null(color);
    assert_non_null(depth);
    for (int pass = 0; pass < 2 && o.status == PERSP_OK; pass++) {
        /* The second frame is larger: buffers kept from the first must grow. */
        int shrink = pass == 0 ? 2 : 1;
        persp_framebuffer fb = {w->width / shrink, w->height / shrink, color, depth};
        persp_render_desc d;
        memset(&d, 0, sizeof d);
        d.sort_first = sort_first;
        o.status = persp_render(ctx, scene, &d, &fb, NULL);
        if (o.status == PERSP_OK) o.hash = test_hash(color, (size_t)fb.width * (size_t)fb.height * 4);
    }
    free(color);
    free(depth);
    if (o.status != PERSP_OK) snprintf(o.error, sizeof o.error, "%s", persp_context_error(ctx));
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return o;
}

/* Runs w once to count its allocations, then once per allocation with that
 * one refused; fails the test after listing every run that misbehaved.
 * Returns the count; *pool (may be NULL) receives how many of the refused
 * allocations stopped the worker threads from starting. */
static size_t check_workload_pool(const workload *w, int threads, persp_toggle sort_first, size_t *pool)
{
    size_t pool_refusals = 0;
    fail_alloc ok = {0};
    outcome o = run(w, threads, sort_first, &ok);
    const uint64_t ref = o.hash;
    if (o.status != PERSP_OK) fail_msg("%s: %s", w->scene, o.error);
    assert_int_equal(ok.live, 0);
    assert_int_equal(ok.other_thread, 0);
    assert_true(ok.calls > 1);
    size_t total = ok.calls, bad = 0;
    for (size_t n = 1; n <= total; n++) {
        fail_alloc a = {0};
        a.fail_at = n;
        o = run(w, threads, sort_first, &a);
        const char *why = NULL;
        const int recovered = sort_first == PERSP_TOGGLE_ON && o.status == PERSP_OK;
        if (recovered && o.hash != ref)
            why = "recovered with another image";
        else if (o.status != PERSP_ERR_OUT_OF_MEMORY && !recovered)
            why = "wrong status";
        else if (a.live != 0)
            why = "blocks left allocated";
        else if (o.left)
            why = o.left[0] == 'c' ? "failed call returned a context"
                                   : "failed call returned a scene";
        else if (a.other_thread)
            why = "allocator called from a worker thread";
        else if (n > 1 && !recovered && !strstr(o.error, "out of memory"))
            why = "detail does not say out of memory";
        if (strstr(o.error, "cannot start worker threads")) pool_refusals++;
        if (why) {
            if (bad++ < 20)
                print_message("%s, %d thread(s)%s, allocation %zu of %zu refused: %s (status %s, "
                              "%zu live, detail \"%s\")\n",
                              w->scene, threads, sort_first == PERSP_TOGGLE_ON ? " sort first" : "", n, total,
                              why, persp_status_string(o.status), a.live, o.error);
        }
    }
    print_message("%s, %d thread(s)%s: %zu allocations, each refused once, %zu bad\n", w->scene, threads,
                  sort_first == PERSP_TOGGLE_ON ? " sort first" : "", total, bad);
    if (bad) fail_msg("%zu of %zu refused allocations mishandled", bad, total);
    if (pool) *pool = pool_refusals;
    return total;
}

static size_t check_workload(const workload *w, int threads)
{
    return check_workload_pool(w, threads, PERSP_TOGGLE_OFF, NULL);
}

/* Each workload with 1 and 2 threads. The worker pool's state comes from
 * the allocator too: with 2 threads some refused allocation must have
 * stopped the workers from starting (the image was large enough for them
 * to start, and their start-up was among the refused allocations), with 1
 * none can. */
static void check_threads(const workload *w)
{
    size_t pool_one = 0, pool_two = 0;
    (void)check_workload_pool(w, 1, PERSP_TOGGLE_OFF, &pool_one);
    (void)check_workload_pool(w, 2, PERSP_TOGGLE_OFF, &pool_two);
    assert_int_equal(pool_one, 0);
    assert_true(pool_two > 0);
    (void)check_workload_pool(w, 2, PERSP_TOGGLE_ON, NULL);
}

static void test_builtin_scenes(void **state)
{
    (void)state;
    size_t n = persp_builtin_scene_count();
    assert_true(n > 0);
    for (size_t i = 0; i < n; i++) {
        workload w = {persp_builtin_scene_name(i), 160, 120};
        check_threads(&w);
    }
}

static void test_json_scene_with_textures(void **state)
{
    (void)state;
    workload w = {"scenes/spheres.json", 160, 120};
    check_threads(&w);
}

/* A JSON scene whose mesh is an OBJ model with its MTL file and texture
 * files beside it: the model importer's reads of other files and its
 * texture loads. One thread: the worker pool is covered above. */
static void test_json_scene_with_model(void **state)
{
    (void)state;
    workload w = {"scenes/room.json", 160, 120};
    check_workload(&w, 1);
}

static void test_model_file(void **state)
{
    (void)state;
    workload w = {"tests/data/models/embedded.glb", 160, 120};
    check_threads(&w);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builtin_scenes),
        cmocka_unit_test(test_json_scene_with_textures),
        cmocka_unit_test(test_model_file),
        cmocka_unit_test(test_json_scene_with_model),
    };
    return TEST_RUN(argc, argv, tests);
}
