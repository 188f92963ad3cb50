/* Sort-first frames: each worker draws the whole scene for its own screen
 * region, in the terms of Molnar, Cox, Ellsworth and Fuchs, "A Sorting
 * Classification of Parallel Rendering" (IEEE CG&A 14(4), 1994).
 *
 * The renderer's usual parallel frame is sort middle: the workers share
 * the vertex stage, set-up and the tiles, each stage reading what another
 * core wrote (the 2M-triangle torus hands over about 180 MB of records a
 * frame). Where crossing between the cores is slow, as on a VM whose host
 * places its two vCPUs apart (a cache line's round trip 315-870 ns against
 * 50-100), that frame ran at half its speed, below one thread's, while two
 * independent one-thread renders each kept their full speed
 * (docs/DESIGN.md, "Threads"). Here each worker, on a context of its own
 * whose buffers nothing else touches, runs the vertex stage for the
 * clusters that can reach its tiles (a run of consecutive tiles in
 * row-major order, balance), keeps the triangles whose box reaches them,
 * and draws its tiles; the workers share only the scene, read, and the
 * framebuffer tiles they own. Each tile is drawn by
 * the same code from the same records in the same order as in sort
 * middle, so the image is the same bit for bit; the counts are too (a
 * triangle set up in two regions is counted by the one owning its first
 * first tile).
 *
 * The allocator is called only from the thread that called into persp
 * (persp_allocator): a region's context is frozen while a worker draws
 * with it, and a region whose buffers had to grow is drawn again on the
 * calling thread (the first frame, a larger one). */
#include "core/internal.h"
#include "core/pool.h"
#include "raster/frame.h"
#include "raster/frame_cache.h"
#include "render/render.h"

#include <string.h>

/* How long a probe of the cross-core round trip stands for the frames
 * after it: the host moved the vCPUs apart for seconds at a time, and a
 * probe costs a wake-up of the other worker and a few dozen trips (a few
 * microseconds; 2k-triangle frames take 2 ms). */
#define PROBE_EVERY_S 0.05

#define REGIONS_MAX PERSP_SORT_FIRST_MAX

/* A region's excess over an equal share of the last frame's time below
 * which the regions are left as they are: frame times vary by a few per
 * cent from frame to frame. */
#define BALANCE_SLACK 0.03

/* A region's frame on cache lines of its own: its counts are written for
 * every triangle, and two regions' frames side by side shared a line. */
typedef struct region_frame {
    _Alignas(64) persp_frame f;
} region_frame;

typedef struct region_job {
    const persp_scene *scene;
    const persp_render_desc *desc;
    persp_framebuffer *fb;
    persp_context **ctx;
    region_frame *frame;
    persp_status *status;
    const int *split;
    double *seconds;
    int regions;
} region_job;

static void region_task(void *user, int task, int worker)
{
    (void)worker;
    region_job *j = user;
    const double t0 = persp__now_seconds();
    j->status[task] = persp__render_frame(j->ctx[task], j->scene, j->desc, j->fb, &j->frame[task].f,
                                          NULL, j->regions, j->split[task], j->split[task + 1]);
    j->seconds[task] = persp__now_seconds() - t0;
}

/* The regions' tiles for the next frame (seconds: the last frame's time of
 * each region; NULL: only set them up for regions and tiles): runs of
 * consecutive tiles in row-major order, equal at first, then moved so that
 * each region would have taken the same time in the last frame, were the
 * time spread evenly over each region's tiles (what a sort-first renderer
 * does with frame-to-frame coherence: Mueller, "The Sort-First Rendering
 * Architecture for High-Performance Graphics", I3D 1995). Runs rather
 * than tiles dealt in turn, so that a mesh cluster falls in one region but
 * at a boundary, and the vertex stage and the triangle loop are split
 * between the regions rather than repeated in each
 * (src/raster/cluster_cull.c); runs that may end mid-row rather than runs
 * of whole rows, as a row of the 2M-triangle torus held a sixth of a
 * frame's work. */
static void balance(struct persp_render_cache *c, int regions, int tiles, const double *seconds)
{
    int *b = c->split;
    if (c->split_regions != regions || c->split_tiles != tiles) {
        for (int k = 0; k <= regions; k++)
            b[k] = (int)((long long)tiles * k / regions);
        c->split_regions = regions;
        c->split_tiles = tiles;
        return;
    }
    if (!seconds) return;
    double total = 0.0, most = 0.0;
    for (int k = 0; k < regions; k++) {
        total += seconds[k];
        most = seconds[k] > most ? seconds[k] : most;
    }
    if (!(total > 0.0) || most <= total / regions * (1.0 + BALANCE_SLACK)) return;
    int nb[PERSP_SORT_FIRST_MAX + 1];
    nb[0] = 0, nb[regions] = tiles;
    double acc = 0.0;
    int k = 0;
    for (int j = 1; j < regions; j++) {
        const double target = total * j / regions;
        while (k < regions - 1 && acc + seconds[k] < target)
            acc += seconds[k++];
        const double frac = seconds[k] > 0.0 ? (target - acc) / seconds[k] : 0.0;
        const int at = (int)(b[k] + frac * (b[k + 1] - b[k]) + 0.5);
        /* Half way there (rounded away from zero): the work is
         * not spread evenly, and a boundary moved all the way overshot,
         * back and forth (the 2M torus: 96, 99, 94, 101, 93 tiles). */
        const int step = at - b[j];
        nb[j] = PERSP_CLAMP(b[j] + step / 2 + step % 2, nb[j - 1] + 1, tiles - (regions - j));
    }
    memcpy(b, nb, (size_t)(regions + 1) * sizeof *b);
}

/* Whether the context's workers would rather not share this frame's data. */
static int sort_first_wanted(persp_context *ctx, struct persp_render_cache *c,
                             const persp_render_desc *d)
{
    const int workers = persp__pool_workers(ctx);
    if (workers < 2 || d->sort_first == PERSP_TOGGLE_OFF || d->pipeline == PERSP_PIPELINE_OBJECT ||
        d->count_ops == PERSP_TOGGLE_ON)
        return 0;
    if (d->sort_first == PERSP_TOGGLE_ON) return 1;
    /* By default only for two, the one count measured both ways
     * (docs/PERFORMANCE.md, "Two threads: sort middle and sort first"). */
    if (workers != 2) return 0;
    const double now = persp__now_seconds();
    if (c->probe_at <= 0.0 || now - c->probe_at > PROBE_EVERY_S) {
        c->probe_ns = persp__pool_round_trip_ns(ctx);
        c->probe_at = now;
    }
    return c->probe_ns >
           (ctx->sort_first_ns > 0.0 ? ctx->sort_first_ns : PERSP_SORT_FIRST_ROUND_TRIP_NS);
}

/* Gives back the region contexts and their buffers. */
static void release_regions(persp_context *ctx, struct persp_render_cache *c)
{
    for (size_t k = 0; k < c->region_count; k++)
        persp__context_child_free(ctx, c->region_ctx[k]);
    c->region_count = 0;
}

/* The region contexts, one a worker, with the parent's settings. */
static persp_status region_contexts(persp_context *ctx, struct persp_render_cache *c, int regions)
{
    if ((size_t)regions > c->region_count) {
        if (persp__grow(ctx, (void **)&c->region_ctx, &c->region_cap, (size_t)regions,
                        sizeof *c->region_ctx) != PERSP_OK)
            return PERSP_ERR_OUT_OF_MEMORY;
        for (size_t k = c->region_count; k < (size_t)regions; k++) {
            if (!(c->region_ctx[k] = persp__context_child(ctx))) {
                release_regions(ctx, c);
                return PERSP_ERR_OUT_OF_MEMORY;
            }
            c->region_count = k + 1;
        }
    }
    for (int k = 0; k < regions; k++) {
        persp_context *r = c->region_ctx[k];
        r->isa = ctx->isa;
        r->shade_isa = ctx->shade_isa;
        r->frame_batch = ctx->frame_batch;
        r->span_only = ctx->span_only;
        r->pack_portable = ctx->pack_portable;
        r->back_lighting = ctx->back_lighting;
        r->no_cluster_cull = ctx->no_cluster_cull;
        r->objspace_max_work = ctx->objspace_max_work;
        r->clusters_culled = 0;
        persp__clear_error(r);
    }
    return PERSP_OK;
}

int persp__render_sort_first(persp_context *ctx, const persp_scene *scene,
                             const persp_render_desc *desc, persp_framebuffer *fb,
                             persp_render_stats *stats, persp_status *st)
{
    if (persp__pool_workers(ctx) < 2 || (desc && desc->sort_first == PERSP_TOGGLE_OFF)) return 0;
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    /* Settings out of range fail here, on the caller's context. */
    if ((*st = persp__check_render_desc(ctx, &d)) != PERSP_OK) return 1;
    /* The render cache holds the region contexts. */
    struct persp_render_cache *c = NULL;
    if ((*st = persp__frame_cache(ctx, fb, &c)) != PERSP_OK) return 1;
    if (!sort_first_wanted(ctx, c, &d)) return 0;
    /* AUTO's timings run once, here, rather than in each region. */
    (void)persp_context_simd(ctx);
    (void)persp_context_lighting_simd(ctx);
    const int tiles =
        ((fb->width + PERSP_TILE - 1) / PERSP_TILE) * ((fb->height + PERSP_TILE - 1) / PERSP_TILE);
    const int regions = PERSP_MIN(PERSP_MIN(persp__pool_workers(ctx), REGIONS_MAX), tiles);
    if (regions < 2 || region_contexts(ctx, c, regions) != PERSP_OK) return 0;
    balance(c, regions, tiles, NULL);

    /* The budget's free part is shared out between the regions; their
     * buffers, kept between frames, count in the parent's use. */
    size_t before[REGIONS_MAX];
    const size_t used_before = ctx->mem_used;
    const size_t share = ctx->max_memory ? persp__mem_available(ctx) / (size_t)regions : 0;
    for (int k = 0; k < regions; k++) {
        persp_context *r = c->region_ctx[k];
        before[k] = r->mem_used;
        r->mem_peak = r->mem_used;
        r->max_memory = ctx->max_memory ? PERSP_MAX((size_t)1, r->mem_used + share) : 0;
        r->frozen = 1;
        r->starved = 0;
    }
    region_frame frame[REGIONS_MAX];
    persp_status status[REGIONS_MAX];
    double seconds[REGIONS_MAX];
    region_job job = {scene, &d, fb, c->region_ctx, frame, status, c->split, seconds, regions};
    persp_status pst = persp__pool_run(ctx, regions, region_task, &job);
    /* A region whose buffers had to grow (the first frame, a larger one)
     * is drawn again here, where the allocator may be called; from then on
     * its buffers are kept and it runs on its worker. It owns its tiles,
     * and its frame clears them first, so nothing of the try remains. */
    int drawn_again = 0;
    for (int k = 0; k < regions; k++) {
        persp_context *r = c->region_ctx[k];
        r->frozen = 0;
        if (pst == PERSP_OK && status[k] != PERSP_OK && r->starved) {
            r->starved = 0;
            persp__clear_error(r);
            region_task(&job, k, 0);
            drawn_again = 1;
        }
    }
    size_t peak_extra = 0;
    for (int k = 0; k < regions; k++) {
        persp_context *r = c->region_ctx[k];
        peak_extra += r->mem_peak - before[k];
        ctx->mem_used = ctx->mem_used - before[k] + r->mem_used;
    }
    if (used_before + peak_extra > ctx->mem_peak) ctx->mem_peak = used_before + peak_extra;
    if (pst != PERSP_OK) {
        *st = persp__fail(ctx, pst, "render: cannot start worker threads: %s",
                          persp_status_string(pst));
        return 1;
    }
    /* The first region's failure, as a one-thread render would give it;
     * out of memory, sort middle (one set of buffers) may still fit once
     * the regions' buffers are given back. */
    for (int k = 0; k < regions; k++) {
        if (status[k] == PERSP_OK) continue;
        if (status[k] == PERSP_ERR_OUT_OF_MEMORY) {
            release_regions(ctx, c);
            persp__clear_error(ctx);
            return 0;
        }
        *st = persp__fail(ctx, status[k], "%s", persp_context_error(c->region_ctx[k]));
        return 1;
    }
    /* A frame drawn again in part was timed in part serially. */
    if (!drawn_again && !ctx->sort_first_static) balance(c, regions, tiles, seconds);
    ctx->clusters_culled += c->region_ctx[0]->clusters_culled;
    if (stats) {
        memset(stats, 0, sizeof *stats);
        stats->triangles_in = frame[0].f.stats.triangles_in;
        for (int k = 0; k < regions; k++) {
            stats->triangles_drawn += frame[k].f.stats.triangles_drawn - frame[k].f.foreign;
            stats->fragments += frame[k].f.stats.fragments;
            stats->pixels_written += frame[k].f.stats.pixels_written;
        }
        stats->sort_first_regions = (uint64_t)regions;
    }
    *st = PERSP_OK;
    return 1;
}
