/* Internal helpers shared by every module; not installed. */
#ifndef PERSP_CORE_INTERNAL_H
#define PERSP_CORE_INTERNAL_H

#include "core/shared.h"

#include "persp.h"

#include <stdarg.h>
#include <stddef.h>
#include <time.h>

#define PERSP_ERRMSG_BYTES 512

struct persp_pool;

struct persp_context {
    persp_allocator allocator;
    int threads;
    char error[PERSP_ERRMSG_BYTES];
    struct persp_pool *pool; /* created lazily for threads > 1 */
    /* Per-frame buffers kept between frames, and how to release them: set by
     * the layer that creates them, so that the context, below every other
     * module, never needs to know their type. */
    void *render;
    void (*render_free)(persp_context *ctx);
    /* Set-up triangles the renderer holds before drawing a batch; 0: its
     * default. Changed only by tests, to compare batch sizes. */
    size_t frame_batch;
    /* Nonzero: small triangles are drawn row by row as spans, not packed
     * into lanes. Changed only by tests, to compare the two paths. */
    int span_only;
    /* Nonzero: lane batches are packed by the portable loop even where
     * AVX-512 is available. Changed only by tests, to compare the two. */
    int pack_portable;
    /* Where two-sided Gouraud lights the back faces (frame.c,
     * back_colours): 0 chosen by culling, 1 the vertex stage, 2 set-up.
     * Changed only by tests, to compare the two. */
    int back_lighting;
    /* Nonzero: no mesh cluster is culled whole (src/raster/cluster_cull.c).
     * Changed only by tests, to compare with culling triangle by triangle. */
    int no_cluster_cull;
    /* The cross-core round trip (ns) above which a two-worker frame is
     * drawn sort first by default (src/render/sort_first.c); 0:
     * PERSP_SORT_FIRST_ROUND_TRIP_NS. Changed only by tests, to reach
     * either choice on any machine. */
    double sort_first_ns;
    /* Nonzero: sort first keeps its regions' equal runs of tiles rather
     * than moving them to balance their times. Changed only by tests, to
     * draw frames with the same shares. */
    int sort_first_static;
    /* A region context while a worker thread draws with it (sort first):
     * frozen, persp__alloc and persp__reserve refuse every request without
     * calling the allocator, which is called only from the thread that
     * called into persp (persp_allocator), and set starved; the frame's
     * driver then draws that region again on the calling thread. */
    int frozen, starved;
    /* Clusters culled whole over the context's frames (tests read it). */
    size_t clusters_culled;
    /* Sampler and packing variant (PERSP_ISA_*), from
     * persp_context_desc.simd; -1 for AUTO until persp_context_simd
     * decides it. */
    int isa;
    /* The lighting loops' variant (persp_draw_state.isa), which the vertex
     * stage takes too: the same as isa for a --simd given, timed apart for
     * AUTO (persp__shade_auto_isa); -1 until then. */
    int shade_isa;
    /* Samples and rows the object-space pipeline may walk in one frame; 0:
     * its default. Changed only by tests, to reach the limit cheaply. */
    double objspace_max_work;
    persp_warning_fn warn;
    void *warn_user;
    persp_temp_file_fn temp_fn;
    void *temp_user;
    /* Memory budget (persp_context_desc.max_memory, 0: none): bytes held
     * through persp__alloc plus those reserved for a library's working
     * memory, the most held at once, the request last refused (0: none
     * since the current public call began) and what was held when it was
     * refused (the error is written after the caller has freed its part). */
    size_t max_memory, mem_used, mem_peak, mem_refused, mem_refused_used;
    /* While a scene loads (persp__warn_hold): its warnings, NUL-separated,
     * given when it has loaded and dropped when it fails. */
    char *held;
    size_t held_len, held_cap;
    int holding;
    /* Images from persp_image_alloc (and so _load) not yet freed, newest
     * first: persp_image_free frees only pixels found here, so an image the
     * caller filled in is never taken for one of persp's (src/core/image_alloc.c). */
    struct persp_image_block *images;
};

/* The persp_simd naming variant isa (PERSP_ISA_*); AUTO for none. */
persp_simd persp__simd_from_isa(int isa);

/* A monotonic clock in seconds, for the timings that choose a variant
 * (texture/fastspan.c, shade/shade.c). */
static inline double persp__now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Overflow-checked size arithmetic: returns 0 and leaves *out untouched on overflow. */
static inline int persp__size_mul(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > (size_t)-1 / a) return 0;
    *out = a * b;
    return 1;
}

/* Passes a one-line warning to the context's handler, if any. */
void persp__warn(persp_context *ctx, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Warnings from here to persp__warn_release are held (from the context's
 * allocator; given at once when it refuses), then given if deliver, else
 * dropped. */
void persp__warn_hold(persp_context *ctx);
void persp__warn_release(persp_context *ctx, int deliver);

/* Sets the context's detail message and returns status (NULL ctx: only returns). */
PERSP_INTERNAL persp_status persp__fail(persp_context *ctx, persp_status status, const char *fmt,
                                        ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* The context's allocator, within its memory budget: a request that would
 * exceed the budget returns NULL without calling the allocator, and a
 * following persp__fail with PERSP_ERR_OUT_OF_MEMORY names the budget in
 * its detail. persp__free(ctx, NULL) is a no-op. */
PERSP_INTERNAL void *persp__alloc(persp_context *ctx, size_t size);
PERSP_INTERNAL void persp__free(persp_context *ctx, void *ptr);

/* persp__alloc asks the allocator for this many bytes more than requested:
 * each block carries its size in front of it, so that persp__free can
 * return it to the budget; 16 bytes keep the allocator's 16-byte alignment
 * (persp_allocator) for the caller's part. */
#define PERSP_BLOCK_HEADER 16

/* Reserves bytes of the budget for memory a library allocates on its own
 * (a decoder's or parser's working memory, measured or bounded before it
 * starts); what names it in the detail of the PERSP_ERR_OUT_OF_MEMORY
 * returned when it does not fit. Release the same amount once the library
 * has freed it. Without a budget both only count. */
PERSP_INTERNAL persp_status persp__mem_reserve(persp_context *ctx, size_t bytes, const char *what);
PERSP_INTERNAL void persp__mem_release(persp_context *ctx, size_t bytes);
/* Bytes of the budget still free (SIZE_MAX without a budget). */
size_t persp__mem_available(const persp_context *ctx);

/* A one-thread context for one worker's share of a frame drawn sort first
 * (src/render/sort_first.c), allocated from ctx, with its allocator and
 * vector variants; NULL when out of memory. Its own memory is counted in
 * its mem_used, which the frame's driver adds to ctx's while it holds it. */
persp_context *persp__context_child(persp_context *ctx);
/* Frees child's per-frame buffers and child itself, taking the buffers'
 * bytes (child->mem_used) back out of ctx's count. */
void persp__context_child_free(persp_context *ctx, persp_context *child);

/* Zero-initialised allocation of n elements of size bytes, overflow-checked. */
PERSP_INTERNAL void *persp__calloc(persp_context *ctx, size_t n, size_t size);

/* Makes *ptr, an array of *cap elements of elem bytes from the context's
 * allocator (NULL and 0 at first), hold at least need elements. The capacity
 * at least doubles, so appending one element at a time costs amortised
 * constant time and a steady workload stops allocating; the contents are
 * kept and the added elements are zero. On failure *ptr and *cap are left as
 * they were: PERSP_ERR_TOO_LARGE when need elements do not fit in a size_t,
 * PERSP_ERR_OUT_OF_MEMORY when the allocator fails. Sets no error detail:
 * the caller knows what was being grown. */
PERSP_INTERNAL persp_status persp__grow(persp_context *ctx, void **ptr, size_t *cap, size_t need,
                                        size_t elem);
/* persp__grow for arrays refilled whole each time they are used (a mesh's
 * per-vertex caches): the contents are dropped, the old block is freed
 * before the new one is allocated and exactly need elements (zero) are
 * allocated, so that a mesh of a million vertices holds one copy of its
 * caches, not up to two and a half. On failure *ptr is NULL and *cap 0. */
persp_status persp__reserve(persp_context *ctx, void **ptr, size_t *cap, size_t need, size_t elem);

/* Fails ctx (PERSP_ERR_FORMAT for an empty size, PERSP_ERR_TOO_LARGE above
 * PERSP_IMAGE_MAX_SIDE / PERSP_IMAGE_MAX_PIXELS) with name in the detail. */
PERSP_INTERNAL persp_status persp__image_check_size(persp_context *ctx, const char *name,
                                                    long long w, long long h);

/* Sets every alpha to 255: persp draws opaque surfaces, so a scene's
 * textures carry no coverage into the image. */
void persp__image_set_opaque(persp_image *img);

/* Plain decimal numbers only (see src/core/strict.c): no blanks, no '+',
 * no hexadecimal, inf or nan; integers without a fraction or exponent.
 * 1 when text is well-formed and in [lo, hi]. */
int persp__decimal_syntax(const char *text, int allow_fraction);
int persp__parse_long(const char *text, long lo, long hi, long *out);
int persp__parse_double(const char *text, double lo, double hi, double *out);

/* Text from a file or a user, fit to quote in a one-line message: bytes
 * outside printable ASCII become \xHH, a backslash doubles, and what does
 * not fit in size bytes ends in "...". Returns buf. */
#define PERSP_QUOTE_BYTES 64
PERSP_INTERNAL const char *persp__quote(const char *text, size_t len, char *buf, size_t size);

/* Clears the context's error detail (called at the start of a public call). */
PERSP_INTERNAL void persp__clear_error(persp_context *ctx);

#define PERSP_MIN(a, b) ((a) < (b) ? (a) : (b))
#define PERSP_MAX(a, b) ((a) > (b) ? (a) : (b))
#define PERSP_CLAMP(x, lo, hi) PERSP_MIN(PERSP_MAX(x, lo), hi)

#endif
