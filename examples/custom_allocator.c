/*
 * custom_allocator — route persp's memory through the program's allocator
 * (an arena, a tracking allocator, a budget), here one that counts.
 *
 *   custom_allocator [SCENE]      (a built-in scene, default cube, or a scene
 *                                 or model file: a name with a / or a .)
 *
 * Everything persp allocates for a context — scenes, textures, images, the
 * per-frame buffers, the worker threads' state — goes through the allocator
 * given to persp_context_create. (libpng's simplified API, libjpeg, jansson
 * and the model importer use malloc for their transient working memory:
 * their APIs offer no per-call allocator.)
 *
 * The program renders a scene with two threads and prints the counts, then
 * does it again under a budget too small for the scene, to show that an
 * allocation failure is reported as PERSP_ERR_OUT_OF_MEMORY and leaks
 * nothing.
 *
 *   cc custom_allocator.c $(pkg-config --cflags --libs persp) -o custom_allocator
 */
/* ctest-labels: threads (renders with several worker threads) */
#include <persp.h>

#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* persp asks for 16-byte alignment. Each block starts with a header holding
 * its size (free() is not told the size); the header is 16 bytes, so the
 * pointer handed out keeps the block's alignment. */
typedef union block_header {
    size_t size;
    unsigned char pad[16];
} block_header;

/* persp calls the allocator only from the thread that called into it, never
 * from a worker (persp.h); the counts are atomic all the same, so that a
 * program whose threads each have a context can share one allocator. */
typedef struct counting_allocator {
    atomic_size_t allocs, frees, refused;
    atomic_size_t live_bytes, peak_bytes;
    size_t budget; /* 0: unlimited */
} counting_allocator;

static void *counting_alloc(void *user, size_t size)
{
    counting_allocator *a = user;
    size_t live = atomic_fetch_add(&a->live_bytes, size) + size;
    if (a->budget && live > a->budget) {
        atomic_fetch_sub(&a->live_bytes, size);
        atomic_fetch_add(&a->refused, 1);
        return NULL;
    }
    /* aligned_alloc wants a multiple of the alignment. */
    size_t total = (sizeof(block_header) + size + 15) / 16 * 16;
    block_header *h = aligned_alloc(16, total);
    if (!h) {
        atomic_fetch_sub(&a->live_bytes, size);
        atomic_fetch_add(&a->refused, 1);
        return NULL;
    }
    h->size = size;
    atomic_fetch_add(&a->allocs, 1);
    size_t peak = atomic_load(&a->peak_bytes);
    while (live > peak && !atomic_compare_exchange_weak(&a->peak_bytes, &peak, live)) {
    }
    return h + 1;
}

static void counting_free(void *user, void *ptr)
{
    counting_allocator *a = user;
    if (!ptr) return;
    block_header *h = (block_header *)ptr - 1;
    atomic_fetch_add(&a->frees, 1);
    atomic_fetch_sub(&a->live_bytes, h->size);
    free(h);
}

static int failed(const persp_context *ctx, persp_status status, const char *what)
{
    if (status == PERSP_OK) return 0;
    const char *detail = ctx ? persp_context_error(ctx) : "";
    fprintf(stderr, "custom_allocator: %s: %s%s%s\n", what, persp_status_string(status),
            *detail ? ": " : "", detail);
    return 1;
}

/* Creates a context on the allocator, loads and renders the scene into an
 * image persp allocates, and releases everything. Returns the status of the
 * first call that failed. */
static persp_status render_once(counting_allocator *counter, const char *scene_name, int quiet)
{
    /* persp_context_create copies the allocator struct; what user points
     * to (the counter) must outlive the context. */
    persp_allocator allocator = {counting_alloc, counting_free, counter};
    persp_context_desc cdesc = {.allocator = &allocator, .threads = 2};
    persp_context *ctx = NULL;
    persp_scene *scene = NULL;
    persp_image image = {0};

    persp_status st = persp_context_create(&cdesc, &ctx);
    /* A name with a '/' or a '.' is a scene or model file; else a built-in. */
    if (st == PERSP_OK)
        st = strpbrk(scene_name, "/.") ? persp_scene_load(ctx, scene_name, &scene)
                                       : persp_scene_builtin(ctx, scene_name, &scene);
    if (st == PERSP_OK) st = persp_image_alloc(ctx, 320, 240, &image);
    float *depth = NULL;
    if (st == PERSP_OK) {
        depth = malloc(320 * 240 * sizeof *depth); /* ours, not persp's */
        if (!depth) st = PERSP_ERR_OUT_OF_MEMORY;
    }
    if (st == PERSP_OK) {
        /* The image's rows are contiguous here (stride = width * 4), so it
         * can serve as the colour buffer. */
        persp_framebuffer fb = {image.width, image.height, image.pixels, depth};
        st = persp_render(ctx, scene, NULL, &fb, NULL);
    }
    if (st != PERSP_OK && !quiet) failed(ctx, st, "render");

    free(depth);
    persp_image_free(ctx, &image);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return st;
}

static void print_counts(const char *label, counting_allocator *a)
{
    printf("  %-22s %zu allocations, %zu frees, %zu refused, peak %zu bytes, %zu bytes still held\n",
           label, atomic_load(&a->allocs), atomic_load(&a->frees), atomic_load(&a->refused),
           atomic_load(&a->peak_bytes), atomic_load(&a->live_bytes));
}

int main(int argc, char **argv)
{
    const char *scene_name = argc > 1 ? argv[1] : "cube";
    printf("custom_allocator: %s, 320x240, 2 threads\n", scene_name);

    counting_allocator counter = {0};
    if (render_once(&counter, scene_name, 0) != PERSP_OK) return EXIT_FAILURE;
    print_counts("render:", &counter);
    if (counter.allocs == 0 || counter.allocs != counter.frees || counter.live_bytes != 0) {
        fprintf(stderr, "custom_allocator: allocations and frees do not match\n");
        return EXIT_FAILURE;
    }

    /* Half of what the render needed at its peak cannot be enough: the call
     * that runs out reports it, and everything already allocated is
     * released on the way out. */
    counting_allocator tight = {0};
    tight.budget = counter.peak_bytes / 2;
    persp_status st = render_once(&tight, scene_name, 1);
    print_counts("render in half of it:", &tight);
    if (st != PERSP_ERR_OUT_OF_MEMORY) {
        fprintf(stderr, "custom_allocator: expected %s, got %s\n",
                persp_status_string(PERSP_ERR_OUT_OF_MEMORY), persp_status_string(st));
        return EXIT_FAILURE;
    }
    if (tight.allocs != tight.frees || tight.live_bytes != 0) {
        fprintf(stderr, "custom_allocator: memory left allocated after a failure\n");
        return EXIT_FAILURE;
    }
    return EXIT_SUCCESS;
}
