/*
 * The frame pipeline (docs/DESIGN.md):
 *   vertex stage → homogeneous clip → divide + viewport → setup (record per
 *   triangle, method prepare) → binning into 64×64 tiles → tiles in parallel
 *   (tiles.c): spans → depth test → method (u, v) → texture → shading → write.
 * This file holds the frame and its batches, the geometry that fills them
 * and the binning. Tiles own disjoint pixels and process their triangles in
 * submission order, so the image is bit-identical for any number of threads.
 */
#include "core/fmath.h"
#include "core/internal.h"
#include "core/pool.h"
#include "geom/scene.h"
#include "interp/methods.h"
#include "raster/raster.h"
#include "raster/frame.h"
#include "raster/frame_cache.h"
#include "shade/shade.h"
#include "texture/texture.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

static void render_cache_free(persp_context *ctx)
{
    struct persp_render_cache *c = ctx ? ctx->render : NULL;
    if (!c) return;
    persp__free(ctx, c->tris);
    persp__free(ctx, c->tiles);
    persp__free(ctx, c->preps);
    persp__free(ctx, c->verts);
    persp__free(ctx, c->back);
    persp__free(ctx, c->win);
    persp__free(ctx, c->slab_tris);
    persp__free(ctx, c->slabs);
    persp__free(ctx, c->bin_count);
    persp__free(ctx, c->bin_start);
    persp__free(ctx, c->bin_items);
    persp__free(ctx, c->bin_part);
    persp__free(ctx, c->states);
    persp__free(ctx, c->fits);
    persp__free(ctx, c->lazy);
    persp__free(ctx, c->cluster_culled);
    persp__free(ctx, c->vertex_need);
    persp__free(ctx, c->worker_stats);
    persp__free(ctx, c->uv);
    for (size_t k = 0; k < c->region_count; k++) persp__context_child_free(ctx, c->region_ctx[k]);
    persp__free(ctx, c->region_ctx);
    persp__free(ctx, c);
    ctx->render = NULL;
    ctx->render_free = NULL;
}

/* Set-up triangles held before the tiles draw them. A frame with more is
 * drawn in batches: each tile draws its triangles in submission order
 * whatever the batches, so the image is the same. A batch is written by the
 * set-up and read back by the tiles, so it is sized for the caches:
 * PERSP_FRAME_BATCH_PER_WORKER records (560 bytes each, 6.6 MiB) per
 * worker thread. Against one batch of 65 536 records (then 800 bytes
 * each, 52 MiB, read back from memory) 6.3 MiB per worker took 20 % less
 * CPU time on the 2M-triangle torus and 17 % on the 200k one, and memory
 * stays bounded whatever the mesh; it is the bytes that count: with the
 * smaller records 12 288 rather than 8192 took 5 % less CPU on the 2M
 * torus at two threads (docs/PERFORMANCE_HISTORY.md, items 18 and 57). A capture
 * refers to triangles by their index in the frame, so it takes one batch.
 * Set-up on the workers writes records in place, into slabs that a culled
 * mesh fills a third: a batch then spans up to twice its records in slots
 * (mesh_triangles_parallel).
 *
 * Each batch also copies every tile it touches in and out (64 KiB a
 * tile). A mesh drawn in order touches few tiles a batch (the 2M torus:
 * 34-42 of 192), but unconnected triangles spread over the screen touch
 * all of them each batch (the soup: 8192 triangles touched all 192 tiles,
 * 12 MiB copied a batch, 13 % of a frame). When the last batch's tile copies
 * outweighed its records, the next batch takes twice as many: soup
 * 5-7 % less CPU, tori unchanged (a fixed doubling cost the tori 0.5-3 %). */
#define PERSP_FRAME_BATCH_PER_WORKER 12288u
#define PERSP_FRAME_BATCH_MAX 65536u

/* PERSP_SIMD_AUTO is resolved here, at the first frame, rather than at
 * context creation: the choices are timed on the samplers of the texture
 * module and on the lighting loops of the shading module, which the
 * context's own module sits below. */
persp_simd persp_context_simd(persp_context *ctx)
{
    if (!ctx) return PERSP_SIMD_AUTO;
    if (ctx->isa < 0) ctx->isa = persp__fast_span_auto_isa();
    if (ctx->shade_isa < 0) ctx->shade_isa = persp__shade_auto_isa();
    return persp__simd_from_isa(ctx->isa);
}

persp_simd persp_context_lighting_simd(persp_context *ctx)
{
    if (!ctx) return PERSP_SIMD_AUTO;
    persp_context_simd(ctx);
    return persp__simd_from_isa(ctx->shade_isa);
}

persp_status persp__frame_cache(persp_context *ctx, const persp_framebuffer *fb, struct persp_render_cache **out)
{
    if (!ctx || !fb || !fb->color || !fb->depth || fb->width <= 0 || fb->height <= 0)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                           "framebuffer: needs a size of at least 1x1 and colour and depth buffers");
    /* The limits of an image (persp_image_alloc's), with the same status. */
    persp_status sz = persp__image_check_size(ctx, "framebuffer", fb->width, fb->height);
    if (sz != PERSP_OK) return sz;
    if (!ctx->render) {
        ctx->render = persp__calloc(ctx, 1, sizeof(struct persp_render_cache));
        if (!ctx->render) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        ctx->render_free = render_cache_free;
    }
    *out = ctx->render;
    return PERSP_OK;
}

persp_status persp__frame_begin(persp_context *ctx, persp_framebuffer *fb, persp_depth_mode mode,
                                persp_frame *f)
{
    memset(f, 0, sizeof *f);
    struct persp_render_cache *cache = NULL;
    persp_status st = persp__frame_cache(ctx, fb, &cache);
    if (st != PERSP_OK) return st;
    f->ctx = ctx;
    f->fb = fb;
    f->depth_mode = mode;
    f->cache = cache;
    f->batch = ctx->frame_batch ? ctx->frame_batch
                                : PERSP_MIN(PERSP_FRAME_BATCH_MAX,
                                            PERSP_FRAME_BATCH_PER_WORKER * (size_t)persp__pool_workers(ctx));
    f->batch_base = f->batch;
    f->batch_adapt = !ctx->frame_batch;
    persp_context_simd(ctx);
    f->pack = ctx->pack_portable                                                     ? PERSP_PACK_PORTABLE
              : ctx->isa == PERSP_ISA_AVX512 || ctx->isa == PERSP_ISA_AVX512_GATHER ? PERSP_PACK_AVX512
              : ctx->isa == PERSP_ISA_AVX2 || ctx->isa == PERSP_ISA_AVX2_GATHER     ? PERSP_PACK_AVX2
                                                                                    : PERSP_PACK_PORTABLE;
    return PERSP_OK;
}

void persp__frame_clear(persp_frame *f, const uint8_t rgba[4])
{
    uint8_t c[4] = {0, 0, 0, 255};
    if (rgba) memcpy(c, rgba, 4);
    memcpy(&f->clear_color, c, 4);
    f->clear_depth = f->depth_mode == PERSP_DEPTH_INVW ? 0.0f : 1.0f;
    f->clear_pending = 1;
}

persp_status persp__frame_add_state(persp_frame *f, const persp_draw_state *s, uint32_t *index)
{
    struct persp_render_cache *c = f->cache;
    if (persp__grow(f->ctx, (void **)&c->states, &c->state_cap, f->state_count + 1,
                    sizeof *c->states) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    persp_draw_state *ds = &c->states[f->state_count];
    *ds = *s;
    /* Both shortcuts give the values of the general path; they are left out
     * where a method counts its operations or a capture reads the spans. */
    const int exact = ds->method.m == &persp__method_exact && !f->count_ops;
    const int pc = ds->shade_method.m == &persp__method_exact &&
                   (ds->shading == PERSP_SHADING_GOURAUD_PC || ds->shading == PERSP_SHADING_PHONG_PC);
    ds->fuse_weights = exact && pc;
    ds->small_lanes = exact && !f->capture && !f->ctx->span_only && ds->tex &&
                      persp__lane_filter(ds->sampler.desc.filter) &&
                      (ds->shade_is_texel || pc);
    *index = (uint32_t)f->state_count++;
    return PERSP_OK;
}

static persp_status frame_flush_batch(persp_frame *f, int last);

static size_t frame_batch_limit(const persp_frame *f)
{
    return f->capture ? SIZE_MAX : f->batch;
}

/* Room for need records in the frame's array, its first tri_count kept;
 * whole: grow to a batch's slots for in-place set-up at once, twice a
 * batch (mesh_triangles_parallel), rather than by doubling (serial set-up,
 * whatever the scene's size, so that a small scene holds little of the
 * memory budget). Unlike persp__grow nothing is zeroed and only the kept
 * records are copied: the slots that in-place set-up leaves as gaps
 * (mesh_triangles_parallel; most of a batch on a culled mesh) are never
 * written, so their pages stay out of the resident set, and no doubling
 * holds two copies of a batch (docs/PERFORMANCE_HISTORY.md, item 56).
 * Nothing reads a slot before set-up writes it: binning skips gaps by their
 * tile range. */
static persp_status grow_records(persp_frame *f, size_t need, int whole)
{
    struct persp_render_cache *c = f->cache;
    if (need <= c->tri_cap) return PERSP_OK;
    const size_t batch = frame_batch_limit(f);
    const size_t grown = whole && batch <= PERSP_FRAME_BATCH_MAX
                             ? 2 * batch
                             : PERSP_MIN(PERSP_MAX((size_t)16, 2 * c->tri_cap), batch);
    const size_t ncap = PERSP_MAX(need, grown);
    size_t bytes;
    persp_tri *n = persp__size_mul(ncap, sizeof *n, &bytes) ? persp__alloc(f->ctx, bytes) : NULL;
    if (!n) return PERSP_ERR_OUT_OF_MEMORY;
    if (f->tri_count) memcpy(n, c->tris, f->tri_count * sizeof *n);
    persp__free(f->ctx, c->tris);
    c->tris = n;
    c->tri_cap = ncap;
    return PERSP_OK;
}

/* Makes room for up to want more triangles in the frame, drawing the batch
 * first when it is full; *room (may be NULL) receives how many fit in the
 * batch now (at least 1). */
static persp_status reserve_triangles(persp_frame *f, size_t want, size_t *room)
{
    struct persp_render_cache *c = f->cache;
    const size_t batch = frame_batch_limit(f);
    if (f->tri_count >= batch) {
        persp_status st = frame_flush_batch(f, 0);
        if (st != PERSP_OK) return st;
        f->tri_count = f->prep_count = 0;
    }
    const size_t n = PERSP_MAX((size_t)1, PERSP_MIN(want, batch - f->tri_count));
    if (f->tri_count + n <= c->tri_cap && f->tri_count + n <= c->tiles_cap) {
        if (room) *room = n;
        return PERSP_OK;
    }
    if (grow_records(f, f->tri_count + n, 0) != PERSP_OK ||
        persp__grow(f->ctx, (void **)&c->tiles, &c->tiles_cap, f->tri_count + n, sizeof *c->tiles) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    if (room) *room = n;
    return PERSP_OK;
}

static persp_status reserve_triangle(persp_frame *f) { return reserve_triangles(f, 1, NULL); }

/* Records the tiles of the frame's newest triangle (reserve_triangle made
 * room) and counts it in. */
static struct tri_tiles tiles_of(const persp_tri *t)
{
    return (struct tri_tiles){(uint16_t)(t->xmin / PERSP_TILE), (uint16_t)(t->xmax / PERSP_TILE),
                              (uint16_t)(t->ymin / PERSP_TILE), (uint16_t)(t->ymax / PERSP_TILE)};
}

static void commit_triangle(persp_frame *f)
{
    struct persp_render_cache *c = f->cache;
    c->tiles[f->tri_count] = tiles_of(&c->tris[f->tri_count]);
    if (f->regions) {
        const struct tri_tiles *tt = &c->tiles[f->tri_count];
        f->foreign += tt->ty0 < f->run.r0 || (tt->ty0 == f->run.r0 && tt->tx0 < f->run.c0);
    }
    f->tri_count++;
}

/* Whether the pixel box x0..x1 × y0..y1 reaches a tile of the frame's
 * region (always, without regions). */
static inline int region_touches(const persp_frame *f, int64_t x0, int64_t x1, int64_t y0, int64_t y1)
{
    return !f->regions || persp__box_reaches_run(&f->run, x0 / PERSP_TILE, x1 / PERSP_TILE, y0 / PERSP_TILE,
                                                 y1 / PERSP_TILE);
}

/* How many attributes (from PERSP_A_U on) a draw reads: u and v when the
 * span is the texel itself; the analyses' capture and the object-space
 * pipeline read them all; Gouraud adds the back face's colours to what
 * per-pixel lighting reads (colour, normal, eye position). */
static int vertex_attrs(const persp_frame *f, const persp_draw_state *ds)
{
    /* Never the back colours: set-up lights them for the triangles that
     * show them (setup_record). */
    if (ds->shade_is_texel && !f->capture) return PERSP_A_V + 1;
    return PERSP_A_BR;
}

/* Whether a draw whose vertex cache holds nattr attributes lights Gouraud
 * colours (vertex stage, clipping, set-up): not where its span is the
 * texel, Gouraud with the texture environment replace included, whose
 * cache holds only u and v. */
static int gouraud_lit(const persp_draw_state *ds, int nattr)
{
    return nattr > PERSP_A_V + 1 && persp__shade_is_gouraud(ds);
}

/* Two-sided Gouraud needs a vertex's back colour only for the triangles
 * that show their back (light_side −1). Drawn with culling, a closed mesh
 * has few (along the silhouettes), and lighting each vertex's back in the
 * vertex stage cost a sixth of a frame of the 2M-triangle torus: set-up
 * lights the three vertices of such a triangle instead. Without culling
 * about half the triangles show their back and lighting per triangle would
 * cost more (+40 % on the 2M torus), so the vertex stage lights every
 * back into the back array. Either way a vertex gets the same colour
 * (persp__light_vertices on the same normal, position and colour), and a
 * triangle is dropped when a colour it shows is not finite.
 * back_colours: the three vertices' back colours into v[i][PERSP_A_BR..BB]
 * (attributes as clipping takes them), from back[i] or, with back[0]
 * NULL, lit from their normals and positions in v and their own colours. */
static void back_colours(const persp_draw_state *ds, float *const v[3], const float *const col[3],
                         const float *const back[3])
{
    if (back[0]) {
        for (int i = 0; i < 3; i++)
            for (int c = 0; c < 3; c++) v[i][PERSP_A_BR + c] = back[i][c];
        return;
    }
    float a[9][3], out[3][3];
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 3; c++) {
            a[c][i] = v[i][PERSP_A_NX + c];
            a[3 + c][i] = v[i][PERSP_A_EX + c];
            a[6 + c][i] = col[i][c];
        }
    const persp_light_in in = {{a[0], a[1], a[2]}, {a[3], a[4], a[5]}, {a[6], a[7], a[8]}};
    float *const bk[3] = {out[0], out[1], out[2]};
    persp__light_vertices(ds, 3, &in, NULL, bk);
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 3; c++) v[i][PERSP_A_BR + c] = out[c][i];
}

/* The set-up record of one triangle with its texture scale and per-polygon
 * LOD, and in *vv (when not NULL) the vertices its rational form passes
 * through; 0 if set-up refuses it. Touches nothing but *t and *vv (worker
 * threads). */
static int setup_record(const persp_frame *f, const persp_draw_state *ds, const persp_winvert tv[3],
                        const persp_tri_edges *e, const float *const col[3], const float *const back[3],
                        uint32_t state, int cull, persp_tri *t, persp_rational_vertices *vv)
{
    /* Only the per-polygon level of detail reads them (a log2 per triangle). */
    const int poly_lod = ds->tex && ds->sampler.desc.lod_mode == PERSP_LOD_POLYGON;
    persp_rational_vertices lod_vv;
    if (poly_lod && !vv) vv = &lod_vv;
    /* A span that is the texel itself reads no shading field; the
     * analyses' capture and the object-space pipeline read them all. With
     * col, Gouraud's back colours come from back_colours; without, with
     * the attributes (clipped polygons: mesh_triangles added them before
     * clipping, which interpolates them). */
    const int nattr = vertex_attrs(f, ds), gouraud = gouraud_lit(ds, nattr);
    unsigned need = nattr <= PERSP_A_V + 1 ? 0u
                    : gouraud && !col                  ? PERSP_SETUP_SHADING | PERSP_SETUP_BACK_COLOURS
                                                       : PERSP_SETUP_SHADING;
    if (need && (!ds->shade_method.m || f->capture)) need |= PERSP_SETUP_LINEAR;
    if (e ? !persp__setup_triangle_edges(tv, e, need, t, vv)
          : !persp__setup_triangle_for(tv, f->fb->width, f->fb->height, cull, need, t, vv))
        return 0;
    if (gouraud && col && t->light_side < 0.0f) {
        /* In set-up order; a colour that is not finite drops the triangle,
         * as clipping drops one with any attribute that is not. */
        float *v[3] = {t->vattr[0], t->vattr[1], t->vattr[2]};
        const int *o = e->order;
        const float *c[3] = {col[o[0]], col[o[1]], col[o[2]]}, *bk[3] = {back[o[0]], back[o[1]], back[o[2]]};
        back_colours(ds, v, c, bk);
        for (int i = 0; i < 3; i++)
            for (int k = PERSP_A_BR; k <= PERSP_A_BB; k++)
                if (!isfinite(v[i][k])) return 0;
    }
    t->state = state;
    if (ds->tex) {
        t->rat.scale1 = (float)ds->tex->width;
        t->rat.scale2 = (float)ds->tex->height;
    }
    if (poly_lod) t->poly_lambda = persp__polygon_lambda(ds->tex, vv->x, vv->y, vv->s1, vv->s2);
    return 1;
}

/* Sets up one triangle and appends it (with its LOD and method state). */
static persp_status emit_triangle(persp_frame *f, const persp_winvert tv[3], const persp_tri_edges *e,
                                  const float *const col[3], const float *const back[3], uint32_t state,
                                  int cull)
{
    struct persp_render_cache *c = f->cache;
    const persp_draw_state *ds = &c->states[state];
    persp_status st = reserve_triangle(f);
    if (st != PERSP_OK) return st;
    persp_tri *t = &c->tris[f->tri_count];
    persp_rational_vertices prep_vv, *vv = ds->method.m->prepare ? &prep_vv : NULL;
    if (f->capture) {
        if (persp__grow(f->ctx, (void **)&c->fits, &c->fit_cap, f->tri_count + 1, sizeof *c->fits) !=
            PERSP_OK)
            return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        vv = &c->fits[f->tri_count];
    }
    if (!setup_record(f, ds, tv, e, col, back, state, cull, t, vv)) return PERSP_OK;
    if (!region_touches(f, t->xmin, t->xmax, t->ymin, t->ymax)) return PERSP_OK;
    if (ds->method.m->prepare) {
        if (persp__grow(f->ctx, (void **)&c->preps, &c->prep_cap, f->prep_count + 1, sizeof *c->preps) !=
            PERSP_OK)
            return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        t->prep = (uint32_t)f->prep_count++;
        ds->method.m->prepare(&t->rat, vv, &ds->method.params, &c->preps[t->prep],
                              f->count_ops ? &f->stats.ops : NULL);
    }
    commit_triangle(f);
    return PERSP_OK;
}

/* Perspective divide and viewport transform of a clip-space vertex. */
static void to_window(const float clip[4], double W, double H, double *x, double *y, double *z,
                      double *q)
{
    *q = 1.0 / (double)clip[3];
    *x = ((double)clip[0] * *q + 1.0) * 0.5 * W;
    *y = ((double)clip[1] * *q + 1.0) * 0.5 * H;
    *z = ((double)clip[2] * *q + 1.0) * 0.5;
}

/* Where set-up triangles go: the frame (slab NULL), or a worker's slab of
 * records that the calling thread appends to the frame in order. */
typedef struct setup_slab {
    persp_tri *tris;
    struct tri_tiles *tiles; /* in place: the records' tile ranges, written with them; else NULL */
    size_t count, cap;
    size_t stop; /* first input triangle not processed (the slab ran out of room) */
} setup_slab;

typedef struct tri_sink {
    persp_frame *f;
    setup_slab *slab;
} tri_sink;

/* e: the triangle's integer set-up, when the caller has it (NULL: set-up
 * computes it from tv); col and back, with e: the vertices' own colours
 * and back colours (back_colours). */
static persp_status sink_triangle(const tri_sink *s, const persp_winvert tv[3], const persp_tri_edges *e,
                                  const float *const col[3], const float *const back[3], uint32_t state,
                                  int cull)
{
    if (!s->slab) return emit_triangle(s->f, tv, e, col, back, state, cull);
    const persp_draw_state *ds = &s->f->cache->states[state];
    setup_slab *sl = s->slab;
    if (setup_record(s->f, ds, tv, e, col, back, state, cull, &sl->tris[sl->count], NULL)) {
        if (sl->tiles) sl->tiles[sl->count] = tiles_of(&sl->tris[sl->count]);
        sl->count++;
    }
    return PERSP_OK;
}

/* Emits the clipped polygon as a fan (v0, vi, vi+1) of set-up triangles. */
static persp_status emit_polygon(const tri_sink *sk, const persp_clipvert *poly, int n, uint32_t state,
                                 int cull)
{
    persp_frame *f = sk->f;
    const double W = f->fb->width, H = f->fb->height;
    persp_winvert wv[PERSP_CLIP_MAX];
    for (int i = 0; i < n; i++) {
        to_window(poly[i].clip, W, H, &wv[i].x, &wv[i].y, &wv[i].z, &wv[i].q);
        wv[i].attr = poly[i].attr;
    }
    for (int i = 1; i + 1 < n; i++) {
        persp_winvert tv[3] = {wv[0], wv[i], wv[i + 1]};
        persp_status st = sink_triangle(sk, tv, NULL, NULL, NULL, state, cull);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

/* The vertex stage of one mesh: each vertex is transformed, lit (Gouraud)
 * and classified independently, so the work is split over the worker
 * threads in ranges of VERTEX_TASK vertices with the same result. */
#define VERTEX_TASK 4096u
#define VERTEX_TASK_MIN 256u

typedef struct vertex_job {
    persp_frame *f;
    const persp_mesh *mesh;
    const float *uv;
    const persp_draw_state *ds;
    persp_mat4 mv, mvp;
    float nm[9];
    double gx, gy;
    /* The attributes kept per vertex (vertex_attrs): the vertex stage
     * computes only what clipping and set-up use. */
    int nattr;
    int back; /* Gouraud: light the backs too, into the cache's back array (back_colours) */
    int lazy; /* Gouraud: leave the fronts of vertices facing away to set-up (front_colours) */
    const uint8_t *need; /* per block: some triangle not culled with its cluster uses it; NULL: all */
    size_t task_size; /* vertices a task takes: VERTEX_TASK, fewer for a small mesh (a multiple of VERTEX_BLOCK) */
} vertex_job;

/* llround for |v| < 2^31: v − trunc(v) is exact, so halves round away
 * from zero as llround does; unlike it, this vectorises. */
static inline double round_half_away(double v)
{
    const double t = trunc(v), r = v - t;
    return t + (double)(r >= 0.5) - (double)(r <= -0.5);
}

/* The vertex stage works in blocks of this many vertices, each step
 * across the block, so that the compiler vectorises the transform, the
 * outcodes and the window positions (a fifth of a one-thread frame of the
 * 2M-triangle torus, one vertex at a time). */
#define VERTEX_BLOCK 16

/* Clip positions of vertices [a, a + n), n <= VERTEX_BLOCK, by the same
 * operations as persp_mat4_apply (double sums from 0.0, rounded to float). */
static PERSP_ALWAYS_INLINE void transform_block_body(const persp_mat4 *m, const persp_vertex *v, size_t n,
                                                     float out[4][VERTEX_BLOCK])
{
    double x[VERTEX_BLOCK], y[VERTEX_BLOCK], z[VERTEX_BLOCK];
    for (size_t i = 0; i < n; i++) x[i] = v[i].pos[0], y[i] = v[i].pos[1], z[i] = v[i].pos[2];
    for (int r = 0; r < 4; r++) {
        const double m0 = m->m[r], m1 = m->m[4 + r], m2 = m->m[8 + r], m3 = m->m[12 + r];
        for (size_t i = 0; i < n; i++) {
            double o = 0.0;
            o += m0 * x[i];
            o += m1 * y[i];
            o += m2 * z[i];
            o += m3 * 1.0;
            out[r][i] = (float)o;
        }
    }
}
PERSP_ISA_VARIANTS(transform_block,
                   (const persp_mat4 *m, const persp_vertex *v, size_t n, float out[4][VERTEX_BLOCK]),
                   (m, v, n, out))

/* The clip position of one vertex: transform_block's operations, for the
 * triangles that are clipped (the vertex cache keeps no clip positions). */
static void clip_position(const persp_mat4 *m, const persp_vertex *v, float out[4])
{
    const double x = v->pos[0], y = v->pos[1], z = v->pos[2];
    for (int r = 0; r < 4; r++) {
        double o = 0.0;
        o += m->m[r] * x;
        o += m->m[4 + r] * y;
        o += m->m[8 + r] * z;
        o += m->m[12 + r] * 1.0;
        out[r] = (float)o;
    }
}

/* 1 if any of v[0..n) is NaN or infinite (an all-ones exponent). */
static inline uint32_t any_nonfinite(const float *v, size_t n)
{
    uint32_t bad = 0;
    for (size_t k = 0; k < n; k++) {
        uint32_t bits;
        memcpy(&bits, &v[k], sizeof bits);
        bad |= (bits & 0x7f800000u) == 0x7f800000u;
    }
    return bad;
}

/* Outcodes and window positions of n <= VERTEX_BLOCK vertices, as
 * persp__clip_outcode_packed and to_window compute them: o, their packed
 * attributes (stride floats each), cp their clip positions component by
 * component. */
static PERSP_ALWAYS_INLINE void window_block_body(const float *o, size_t stride, size_t n,
                                                  const float cp[4][VERTEX_BLOCK], double gx, double gy,
                                                  double W, double H, struct vert_win *win)
{
    uint32_t bad[VERTEX_BLOCK];
    double x[VERTEX_BLOCK], y[VERTEX_BLOCK], z[VERTEX_BLOCK], w[VERTEX_BLOCK];
    unsigned code[VERTEX_BLOCK];
    /* A non-finite output (NaN input, or a transform that overflowed) has
     * an all-ones exponent. Tested on the bits and combined by OR, which the
     * compiler may reorder and vectorise (a float sum of v·0, NaN for any of
     * them, was a chain of dependent additions, 4 % of a 2M-torus frame):
     * first over the whole block, whose vertices are consecutive, and per
     * vertex only when the block has one. */
    uint32_t block_bad = any_nonfinite(o, n * stride);
    for (int r = 0; r < 4; r++) block_bad |= any_nonfinite(cp[r], n);
    for (size_t i = 0; i < n; i++) bad[i] = block_bad ? any_nonfinite(o + i * stride, stride) : 0u;
    if (block_bad)
        for (int r = 0; r < 4; r++)
            for (size_t i = 0; i < n; i++) bad[i] |= any_nonfinite(&cp[r][i], 1);
    for (size_t i = 0; i < n; i++) x[i] = cp[0][i], y[i] = cp[1][i], z[i] = cp[2][i], w[i] = cp[3][i];
    for (size_t i = 0; i < n; i++)
        code[i] = bad[i] ? PERSP_CLIP_NONFINITE : persp__clip_outcode_pos(x[i], y[i], z[i], w[i], gx, gy);
    for (size_t i = 0; i < n; i++) {
        /* Vertices outside a plane keep no window position: 1 stands in
         * for their w, so that nothing below overflows. */
        const double wi = code[i] ? 1.0 : w[i];
        const double q = 1.0 / wi;
        const double wx = ((code[i] ? 0.0 : x[i]) * q + 1.0) * 0.5 * W;
        const double wy = ((code[i] ? 0.0 : y[i]) * q + 1.0) * 0.5 * H;
        win[i].q = q;
        win[i].z = (z[i] * q + 1.0) * 0.5;
        win[i].X = (int32_t)round_half_away(wx * PERSP_SUBPIXEL);
        win[i].Y = (int32_t)round_half_away(wy * PERSP_SUBPIXEL);
        win[i].code = code[i];
    }
}
PERSP_ISA_VARIANTS(window_block,
                   (const float *o, size_t stride, size_t n, const float cp[4][VERTEX_BLOCK], double gx,
                    double gy, double W, double H, struct vert_win *win),
                   (o, stride, n, cp, gx, gy, W, H, win))

/* The attributes of n <= VERTEX_BLOCK vertices into the vertex cache
 * (out, stride floats each): u, v (from uv, two floats each, or the
 * vertices' own), and for lit != 0 the eye-space normal, by the normal
 * matrix nm, and position ep; lit 2 adds the vertex colour (Gouraud writes
 * its lit colours instead). en and col receive the normals and colours
 * component by component for the lighting. Each step across the block, so
 * that the normals' products vectorise: the vertex stage of the soup's
 * gouraud-pc frame took 110 instructions a vertex instead of 125 (callgrind,
 * avx2; soup 1212 → 1201 a pixel). */
static PERSP_ALWAYS_INLINE void pack_block_body(const persp_vertex *v, size_t n, const float *uv, const float nm[9],
                                                const float ep[4][VERTEX_BLOCK], int lit, float *out, size_t stride,
                                                float en[3][VERTEX_BLOCK], float col[3][VERTEX_BLOCK])
{
    for (size_t k = 0; k < n; k++) {
        out[k * stride + PERSP_A_U] = uv ? uv[2 * k] : v[k].uv[0];
        out[k * stride + PERSP_A_V] = uv ? uv[2 * k + 1] : v[k].uv[1];
    }
    if (!lit) return;
    float nx[VERTEX_BLOCK], ny[VERTEX_BLOCK], nz[VERTEX_BLOCK];
    for (size_t k = 0; k < n; k++) {
        nx[k] = v[k].normal[0], ny[k] = v[k].normal[1], nz[k] = v[k].normal[2];
        col[0][k] = v[k].color[0], col[1][k] = v[k].color[1], col[2][k] = v[k].color[2];
    }
    for (int r = 0; r < 3; r++)
        for (size_t k = 0; k < n; k++) en[r][k] = nm[r] * nx[k] + nm[3 + r] * ny[k] + nm[6 + r] * nz[k];
    for (size_t k = 0; k < n; k++) {
        float *at = out + k * stride;
        if (lit == 2)
            for (int r = 0; r < 4; r++) at[PERSP_A_R + r] = v[k].color[r];
        for (int r = 0; r < 3; r++) at[PERSP_A_NX + r] = en[r][k], at[PERSP_A_EX + r] = ep[r][k];
    }
}
PERSP_ISA_VARIANTS(pack_block,
                   (const persp_vertex *v, size_t n, const float *uv, const float nm[9],
                    const float ep[4][VERTEX_BLOCK], int lit, float *out, size_t stride, float en[3][VERTEX_BLOCK],
                    float col[3][VERTEX_BLOCK]),
                   (v, n, uv, nm, ep, lit, out, stride, en, col))

static void vertex_task(void *user, int task, int worker)
{
    (void)worker;
    const vertex_job *j = user;
    struct persp_render_cache *c = j->f->cache;
    const persp_mesh *mesh = j->mesh;
    const size_t a = (size_t)task * j->task_size;
    const size_t b = PERSP_MIN(a + j->task_size, mesh->vertex_count);
    const float *nm = j->nm, *uv = j->uv;
    const size_t stride = (size_t)j->nattr;
    const int lit = j->nattr > PERSP_A_V + 1, gouraud = gouraud_lit(j->ds, j->nattr);
    const double W = j->f->fb->width, H = j->f->fb->height;
    /* The lighting loops' width (persp_context_lighting_simd): the vertex
     * stage's loops are arithmetic as theirs are, not texel fetches. Taking
     * it rather than the samplers' where AUTO times the two apart (the
     * Zen 5 VM: samplers AVX2, lighting AVX-512): 200k torus phong-pc
     * 33 → 35.6 Mpix/s, soup gouraud-pc +1.5 %, the 2M torus unchanged. */
    const int isa = j->f->ctx->shade_isa;
    /* Block by block, each step across the block while it is in L1: a
     * block's normals, positions and colours go to the lighting as arrays
     * (they were gathered back out of the packed cache, 4 % of a frame of
     * the 2M-triangle torus). */
    for (size_t i0 = a; i0 < b; i0 += VERTEX_BLOCK) {
        /* Used only by clusters culled whole: no triangle reads it. */
        if (j->need && !j->need[i0 / VERTEX_BLOCK]) continue;
        const size_t n = PERSP_MIN((size_t)VERTEX_BLOCK, b - i0);
        float cp[4][VERTEX_BLOCK], ep[4][VERTEX_BLOCK], en[3][VERTEX_BLOCK], col[3][VERTEX_BLOCK];
        transform_block(isa, &j->mvp, mesh->vertices + i0, n, cp);
        if (lit) transform_block(isa, &j->mv, mesh->vertices + i0, n, ep);
        pack_block(isa, mesh->vertices + i0, n, uv ? uv + 2 * i0 : NULL, nm, (const float(*)[VERTEX_BLOCK])ep,
                   lit ? 1 + !gouraud : 0, c->verts + i0 * stride, stride, en, col);
        if (gouraud && j->lazy) {
            /* Only the vertices facing the eye, packed together; the
             * others' fronts are lit by set-up for the few drawn triangles
             * that show them (front_colours), and stand at 0 here. */
            float pk[9][VERTEX_BLOCK], rgb[3][VERTEX_BLOCK];
            size_t lit_k[VERTEX_BLOCK];
            int m = 0;
            for (size_t k = 0; k < n; k++) {
                const float facing = en[0][k] * ep[0][k] + en[1][k] * ep[1][k] + en[2][k] * ep[2][k];
                c->lazy[i0 + k] = (uint8_t)!(facing < 0.0f);
                if (c->lazy[i0 + k]) continue;
                for (int r = 0; r < 3; r++)
                    pk[r][m] = en[r][k], pk[3 + r][m] = ep[r][k], pk[6 + r][m] = col[r][k];
                lit_k[m++] = k;
            }
            const persp_light_in in = {{pk[0], pk[1], pk[2]}, {pk[3], pk[4], pk[5]}, {pk[6], pk[7], pk[8]}};
            float *const front[3] = {rgb[0], rgb[1], rgb[2]};
            persp__light_vertices(j->ds, m, &in, front, NULL);
            for (size_t k = 0; k < n; k++) {
                float *at = c->verts + (i0 + k) * stride;
                at[PERSP_A_R] = at[PERSP_A_G] = at[PERSP_A_B] = 0.0f;
                at[PERSP_A_A] = 1.0f;
            }
            for (int q = 0; q < m; q++) {
                float *at = c->verts + (i0 + lit_k[q]) * stride;
                at[PERSP_A_R] = rgb[0][q], at[PERSP_A_G] = rgb[1][q], at[PERSP_A_B] = rgb[2][q];
            }
        } else if (gouraud) {
            float rgb[6][VERTEX_BLOCK];
            const persp_light_in in = {{en[0], en[1], en[2]}, {ep[0], ep[1], ep[2]}, {col[0], col[1], col[2]}};
            float *const front[3] = {rgb[0], rgb[1], rgb[2]}, *const back[3] = {rgb[3], rgb[4], rgb[5]};
            persp__light_vertices(j->ds, (int)n, &in, front, j->back ? back : NULL);
            for (size_t k = 0; k < n; k++) {
                float *at = c->verts + (i0 + k) * stride;
                at[PERSP_A_R] = rgb[0][k], at[PERSP_A_G] = rgb[1][k], at[PERSP_A_B] = rgb[2][k];
                at[PERSP_A_A] = 1.0f;
            }
            if (j->back) {
                float *bk = c->back + 3 * i0;
                for (size_t k = 0; k < n; k++)
                    bk[3 * k] = rgb[3][k], bk[3 * k + 1] = rgb[4][k], bk[3 * k + 2] = rgb[5][k];
            }
        }
        window_block(isa, c->verts + i0 * stride, stride, n, (const float(*)[VERTEX_BLOCK])cp, j->gx, j->gy, W, H,
                     &c->win[i0]);
    }
}

/* The cluster tests of one mesh (src/raster/cluster_cull.c), split over the
 * workers in ranges of CLUSTER_TASK clusters. */
#define CLUSTER_TASK 2048u

typedef struct cluster_job {
    persp_cluster_view view;
    const persp_mesh *mesh;
    uint8_t *culled;
} cluster_job;

static void cluster_task(void *user, int task, int worker)
{
    (void)worker;
    const cluster_job *j = user;
    const size_t a = (size_t)task * CLUSTER_TASK, b = PERSP_MIN(a + CLUSTER_TASK, j->mesh->cluster_count);
    persp__clusters_cull(&j->view, j->mesh->clusters + a, b - a, j->culled + a);
}

/* Triangles of one mesh after its vertex stage. */
typedef struct tri_job {
    tri_sink sink;
    const persp_mesh *mesh;
    uint32_t state;
    int cull;
    int nattr; /* the vertex cache's attributes per vertex (vertex_attrs) */
    persp_mat4 mvp; /* clip positions of clipped triangles (clip_position) */
    const float *back; /* the vertex stage's back colours, or NULL (back_colours) */
    const uint8_t *lazy; /* the vertices whose front colour set-up lights, or NULL (front_colours) */
    const uint8_t *culled; /* per cluster of the mesh: culled whole, or NULL (src/raster/cluster_cull.c) */
    double gx, gy;
    setup_slab *slabs;
    size_t first; /* first input triangle of the round */
    size_t chunk, slab; /* input triangles a set-up task takes, record slots of its slab */
} tri_job;

/* Where back_colours finds the back colours of triangle ix's vertices. */
static void colour_sources(const tri_job *j, const uint32_t ix[3], const float *col[3], const float *back[3])
{
    for (int k = 0; k < 3; k++) {
        col[k] = j->mesh->vertices[ix[k]].color;
        back[k] = j->back ? j->back + 3 * (size_t)ix[k] : NULL;
    }
}

/* Gouraud's front colours that the vertex stage left to set-up (those of
 * vertices facing away from the eye, which a closed mesh drawn with
 * culling shows only along its silhouettes: lighting them all was about
 * 4 % of a frame of the 2M-triangle torus): into a[k], the attributes of
 * vertex ix[k] as the vertex cache holds them, for each such vertex, from
 * the normal, position and colour the vertex stage lit the others from,
 * through the same persp__light_vertices, so that every vertex gets the
 * bits it would have got there. 0 if a colour is not finite: the triangle
 * is dropped, as the vertex stage's probe drops a vertex whose colour is
 * not. */
static int front_colours(const tri_job *j, const uint32_t ix[3], float *const a[3])
{
    float in[9][3], rgb[3][3];
    int of[3], m = 0;
    for (int k = 0; k < 3; k++) {
        if (!j->lazy[ix[k]]) continue;
        for (int r = 0; r < 3; r++) {
            in[r][m] = a[k][PERSP_A_NX + r];
            in[3 + r][m] = a[k][PERSP_A_EX + r];
            in[6 + r][m] = j->mesh->vertices[ix[k]].color[r];
        }
        of[m++] = k;
    }
    if (!m) return 1;
    const persp_light_in li = {{in[0], in[1], in[2]}, {in[3], in[4], in[5]}, {in[6], in[7], in[8]}};
    float *const front[3] = {rgb[0], rgb[1], rgb[2]};
    persp__light_vertices(&j->sink.f->cache->states[j->state], m, &li, front, NULL);
    for (int q = 0; q < m; q++)
        for (int r = 0; r < 3; r++) {
            if (!isfinite(rgb[r][q])) return 0;
            a[of[q]][PERSP_A_R + r] = rgb[r][q];
        }
    return 1;
}

/* Input triangles [a, b) into the job's sink (or slab, when given): trivial
 * reject, the rejects of set-up's integer half, clipping, set-up. A slab
 * stops early, recording where, when it might not hold a clipped polygon's
 * fan. */
static persp_status mesh_triangles(const tri_job *j, size_t a, size_t b, setup_slab *slab)
{
    persp_frame *f = j->sink.f;
    struct persp_render_cache *c = f->cache;
    const persp_mesh *mesh = j->mesh;
    const int width = f->fb->width, height = f->fb->height;
    tri_sink sk = {f, slab};
    const size_t stride = (size_t)j->nattr;
    for (size_t t = a; t < b;) {
        /* A cluster culled whole is skipped; without clusters the inner
         * loop is the whole range. */
        size_t run_end = b;
        if (j->culled) {
            const size_t k = t / PERSP_CLUSTER_TRIANGLES;
            run_end = PERSP_MIN(b, (k + 1) * PERSP_CLUSTER_TRIANGLES);
            if (j->culled[k]) {
                t = run_end;
                continue;
            }
        }
        for (; t < run_end; t++) {
            if (slab && slab->count + (PERSP_CLIP_MAX - 2) > slab->cap) {
                slab->stop = t;
                return PERSP_OK;
            }
            const uint32_t *ix = &mesh->indices[3 * t];
            const struct vert_win *w0 = &c->win[ix[0]], *w1 = &c->win[ix[1]], *w2 = &c->win[ix[2]];
            const unsigned any = w0->code | w1->code | w2->code;
            if ((any & PERSP_CLIP_NONFINITE) || (w0->code & w1->code & w2->code)) continue;
            persp_status st;
            if (!any) {
                const int64_t X[3] = {w0->X, w1->X, w2->X}, Y[3] = {w0->Y, w1->Y, w2->Y};
                /* What set-up would refuse, decided on the vertex stage's
                 * fixed-point positions (set-up rounds them back to the same
                 * integers): zero area, culled, no candidate centre in the
                 * viewport, or a small box covering none. Most triangles of a
                 * closed mesh end here, before their attributes are read. */
                persp_tri_edges e;
                if (!persp__tri_edges(X, Y, width, height, j->cull, &e) ||
                    !region_touches(f, e.bx0, e.bx1, e.by0, e.by1))
                    continue;
                persp_winvert tv[3];
                for (int k = 0; k < 3; k++) {
                    const struct vert_win *w = &c->win[ix[k]];
                    tv[k] = (persp_winvert){w->X * (1.0 / PERSP_SUBPIXEL), w->Y * (1.0 / PERSP_SUBPIXEL), w->z,
                                            w->q, c->verts + ix[k] * stride};
                }
                float lit[3][PERSP_A_BR];
                if (j->lazy && (j->lazy[ix[0]] | j->lazy[ix[1]] | j->lazy[ix[2]])) {
                    for (int k = 0; k < 3; k++) memcpy(lit[k], tv[k].attr, stride * sizeof(float));
                    float *const la[3] = {lit[0], lit[1], lit[2]};
                    if (!front_colours(j, ix, la)) continue;
                    for (int k = 0; k < 3; k++) tv[k].attr = lit[k];
                }
                const float *col[3], *back[3];
                colour_sources(j, ix, col, back);
                st = sink_triangle(&sk, tv, &e, col, back, j->state, j->cull);
            } else {
                /* The attributes the draw does not read are clipped as zeros;
                 * Gouraud's back colours are lit first, as clipping
                 * interpolates them. */
                persp_clipvert in[3];
                memset(in, 0, sizeof in);
                for (int k = 0; k < 3; k++) {
                    clip_position(&j->mvp, &mesh->vertices[ix[k]], in[k].clip);
                    memcpy(in[k].attr, c->verts + ix[k] * stride, stride * sizeof(float));
                }
                float *const ia[3] = {in[0].attr, in[1].attr, in[2].attr};
                if (j->lazy && !front_colours(j, ix, ia)) continue;
                const persp_draw_state *ds = &c->states[j->state];
                if (gouraud_lit(ds, j->nattr)) {
                    float *v[3] = {in[0].attr, in[1].attr, in[2].attr};
                    const float *col[3], *back[3];
                    colour_sources(j, ix, col, back);
                    back_colours(ds, v, col, back);
                }
                persp_clipvert poly[PERSP_CLIP_MAX];
                int n = persp__clip_triangle(in, j->gx, j->gy, poly);
                st = n >= 3 ? emit_polygon(&sk, poly, n, j->state, j->cull) : PERSP_OK;
            }
            if (st != PERSP_OK) return st;
        }
    }
    if (slab) slab->stop = b;
    return PERSP_OK;
}

/* Triangle set-up on the worker threads: a round gives each of its tasks
 * a chunk of consecutive input triangles and a slab for their records;
 * the calling thread then appends the slabs in input order, and sets up
 * itself whatever a full slab left over before moving to the next slab, so
 * the frame receives exactly the serial sequence of triangles. */
/* 2048 rather than 512: each round is a start and a wait of the worker
 * threads, and with 512 their wake-ups took a sixth of a two-thread frame
 * of the 2M torus (kernel time); 2048: −13 % wall there, −8 % on the 200k
 * torus. A mesh too small for two chunks a worker takes smaller ones,
 * down to SETUP_CHUNK_MIN, so that every worker sets up a share: its one
 * round is one start and wait (the 2k torus, 2000 triangles, was set up
 * by the calling thread alone: docs/PERFORMANCE_HISTORY.md, item 59). A slab holds
 * an eighth more records than its chunk has triangles, for those that
 * clipping adds; a chunk that makes more than that has the rest of it set
 * up serially (mesh_triangles_parallel). Culled meshes fill a third of
 * their slabs, and binning passes over every slot, so the slabs are kept
 * small: with half as many again as triangles the 200k torus unlit ran
 * 86.4 Mpix/s at two threads against 88.7 with an eighth, the soup
 * gouraud-pc 15.7 against 16.0 (medians of 75 runs each, interleaved). */
#define SETUP_CHUNK 2048u
#define SETUP_CHUNK_MIN 256u

static void setup_task(void *user, int task, int worker)
{
    (void)worker;
    tri_job *j = user;
    /* The task counts into a copy on its own stack: the slabs are 40 bytes
     * each, so neighbours share cache lines, and a count written for every
     * triangle by two threads bounced its line between their cores (two
     * threads: 2M torus unlit 20.0 → 21.0 Mpix/s, 200k torus 89 → 97). */
    setup_slab slab = j->slabs[task];
    const size_t a = j->first + (size_t)task * j->chunk;
    const size_t b = PERSP_MIN(a + j->chunk, j->mesh->index_count / 3);
    slab.count = 0;
    (void)mesh_triangles(j, a, b, &slab); /* a slab sink cannot fail */
    /* In place, the slots left unused become gaps, marked as covering no
     * tile here rather than by the calling thread after the round while
     * the other workers wait (most of a slab on a culled mesh). Two
     * threads, medians of about 70 single runs each, interleaved: 2M torus
     * gouraud-pc 15.48 → 15.60 Mpix/s, 200k torus unlit 87.5 → 88.5, the
     * soup unchanged. */
    if (slab.tiles)
        for (size_t i = slab.count; i < slab.cap; i++) slab.tiles[i] = (struct tri_tiles){1, 0, 1, 0};
    j->slabs[task] = slab;
}

/* Appends a slab's records to the frame by copying them, in runs as long
 * as the batch holds. */
static persp_status append_slab(persp_frame *f, const setup_slab *slab)
{
    struct persp_render_cache *c = f->cache;
    for (size_t i = 0; i < slab->count;) {
        size_t room = 0;
        persp_status st = reserve_triangles(f, slab->count - i, &room);
        if (st != PERSP_OK) return st;
        memcpy(&c->tris[f->tri_count], &slab->tris[i], room * sizeof *c->tris);
        for (size_t m = 0; m < room; m++) commit_triangle(f);
        i += room;
    }
    return PERSP_OK;
}

/* Slabs in place: each task of a round sets up straight into its own
 * region of j->slab slots of the frame's records, so that nothing is
 * copied (a copy of every record on the calling thread took a fifth of a
 * two-thread frame of the 2M torus). The slots a task leaves unused stay
 * in the batch as gaps, marked as covering no tile, so binning passes over
 * them; the frame counts them (gap_count) to report only real triangles.
 * (A capture, whose users walk the records by index, is set up serially:
 * persp__frame_add_mesh.) When a task's slab overflowed, the slabs after it are moved out to the scratch
 * slabs and appended by copying after the overflowing chunk's remainder,
 * which keeps the serial order. */
static persp_status scratch_slabs(persp_frame *f, size_t tasks, size_t slab)
{
    struct persp_render_cache *c = f->cache;
    if (persp__grow(f->ctx, (void **)&c->slab_tris, &c->slab_cap, tasks * slab,
                    sizeof *c->slab_tris) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    return PERSP_OK;
}

static persp_status mesh_triangles_parallel(tri_job *j, size_t ntri, int workers)
{
    persp_frame *f = j->sink.f;
    struct persp_render_cache *c = f->cache;
    /* Two tasks per worker for balance, as many as fit one batch in place
     * (at least one per worker). */
    const size_t batch_slots = frame_batch_limit(f);
    const size_t tasks_max =
        PERSP_MAX((size_t)workers, PERSP_MIN((size_t)workers * 2, batch_slots / j->slab));
    if (persp__grow(f->ctx, (void **)&c->slabs, &c->slabs_cap, tasks_max, sizeof *c->slabs) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    j->slabs = c->slabs;
    for (j->first = 0; j->first < ntri; j->first += tasks_max * j->chunk) {
        const size_t batch = frame_batch_limit(f);
        const size_t left = ntri - j->first;
        const int tasks = (int)PERSP_MIN(tasks_max, (left + j->chunk - 1) / j->chunk);
        const size_t slots = (size_t)tasks * j->slab;
        persp_status st;
        const int in_place = slots <= batch;
        /* The scratch slabs (a round's worth of records: 6.9 MB with two
         * workers) exist only once a round needs them: without in-place
         * slabs, or when a slab overflowed (below). */
        if (!in_place && scratch_slabs(f, tasks_max, j->slab) != PERSP_OK) return PERSP_ERR_OUT_OF_MEMORY;
        if (in_place) {
            /* A batch bounds the records it holds, not its slots: rounds
             * go on filling slots, up to twice a batch of them, while the
             * records they may add stay within it. A culled mesh fills a
             * third of its slabs, and each batch costs rounds of binning
             * and tiles and the copies of every tile it touches. Two
             * threads, against batches of a batch's slots (medians of
             * 75-110 runs each, interleaved): 2M torus gouraud-pc 15.4 →
             * 16.3 Mpix/s, 200k torus gouraud-pc 69.5 → 70.5 but unlit
             * 86.8 → 84.5, the soup 15.7 → 15.5; with the vCPUs far apart
             * (a few runs each) 6–13 % faster. Resident memory +6 MiB on
             * the 2M torus (its slots are touched a round at a time). */
            const size_t space = batch > SIZE_MAX / 2 ? SIZE_MAX : 2 * batch;
            if (f->tri_count > 0 && (f->tri_count + slots > space || f->tri_count - f->gap_count + slots > batch)) {
                if ((st = frame_flush_batch(f, 0)) != PERSP_OK) return st;
                f->tri_count = f->prep_count = 0;
            }
            if (grow_records(f, f->tri_count + slots, 1) != PERSP_OK ||
                persp__grow(f->ctx, (void **)&c->tiles, &c->tiles_cap, f->tri_count + slots,
                            sizeof *c->tiles) != PERSP_OK)
                return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        }
        const size_t base = f->tri_count;
        for (int k = 0; k < tasks; k++) {
            c->slabs[k].tris = in_place ? c->tris + base + (size_t)k * j->slab : c->slab_tris + (size_t)k * j->slab;
            c->slabs[k].tiles = in_place ? c->tiles + base + (size_t)k * j->slab : NULL;
            c->slabs[k].cap = j->slab;
        }
        st = persp__pool_run(f->ctx, tasks, setup_task, j);
        if (st != PERSP_OK)
            return persp__fail(f->ctx, st, "render: cannot start worker threads: %s",
                               persp_status_string(st));
        int copying = !in_place;
        for (int k = 0; k < tasks; k++) {
            const setup_slab *slab = &j->slabs[k];
            const size_t end = PERSP_MIN(j->first + ((size_t)k + 1) * j->chunk, ntri);
            if (copying) {
                if ((st = append_slab(f, slab)) != PERSP_OK) return st;
            } else {
                /* The records and their tile ranges are in place, the
                 * unused slots marked as gaps (setup_task). */
                const size_t region = base + (size_t)k * j->slab;
                f->gap_count += j->slab - slab->count;
                f->tri_count = region + j->slab;
                if (slab->stop < end && k + 1 < tasks) {
                    /* The later slabs leave the frame before the serial
                     * remainder of this chunk is appended after it. */
                    if (scratch_slabs(f, tasks_max, j->slab) != PERSP_OK) return PERSP_ERR_OUT_OF_MEMORY;
                    for (int m = k + 1; m < tasks; m++) {
                        setup_slab *later = &j->slabs[m];
                        memcpy(c->slab_tris + (size_t)m * j->slab, later->tris, later->count * sizeof *c->tris);
                        later->tris = c->slab_tris + (size_t)m * j->slab;
                        later->tiles = NULL;
                    }
                    copying = 1;
                }
            }
            if (slab->stop < end && (st = mesh_triangles(j, slab->stop, end, NULL)) != PERSP_OK) return st;
        }
    }
    return PERSP_OK;
}

float *persp__frame_uv_buffer(persp_frame *f, size_t vertices)
{
    struct persp_render_cache *c = f->cache;
    size_t floats;
    if (!persp__size_mul(vertices ? vertices : 1, 2, &floats) ||
        persp__reserve(f->ctx, (void **)&c->uv, &c->uv_cap, floats, sizeof *c->uv) != PERSP_OK)
        return NULL;
    return c->uv;
}

persp_status persp__frame_add_mesh(persp_frame *f, const persp_mesh *mesh, const persp_mat4 *model,
                                   const persp_mat4 *view, const persp_mat4 *proj, uint32_t state,
                                   const float *uv, int cull)
{
    struct persp_render_cache *c = f->cache;
    if (mesh->vertex_count == 0 || mesh->index_count < 3) return PERSP_OK;
    const persp_draw_state *ds = &c->states[state];
    const int nattr = vertex_attrs(f, ds);
    size_t floats;
    if (!persp__size_mul(mesh->vertex_count, (size_t)nattr, &floats) ||
        persp__reserve(f->ctx, (void **)&c->verts, &c->vert_cap, floats, sizeof *c->verts) != PERSP_OK ||
        persp__reserve(f->ctx, (void **)&c->win, &c->win_cap, mesh->vertex_count, sizeof *c->win) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    /* Backs in the vertex stage when most triangles may show theirs
     * (back_colours). */
    const int back_lighting = f->ctx->back_lighting;
    vertex_job job = {.f = f, .mesh = mesh, .uv = uv, .ds = ds, .nattr = nattr,
                      .back = gouraud_lit(ds, nattr) && (back_lighting ? back_lighting == 1 : !cull)};
    /* Fronts left to set-up where backs are too (front_colours), but not
     * for a capture, whose records the analyses read whole. */
    job.lazy = gouraud_lit(ds, nattr) && !job.back && !f->capture && nattr == PERSP_A_BR;
    if (job.lazy && persp__reserve(f->ctx, (void **)&c->lazy, &c->lazy_cap, mesh->vertex_count, 1) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    if (job.back && (!persp__size_mul(mesh->vertex_count, 3, &floats) ||
                     persp__reserve(f->ctx, (void **)&c->back, &c->back_cap, floats, sizeof *c->back) != PERSP_OK))
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    job.mv = persp_mat4_mul(*view, *model);
    job.mvp = persp_mat4_mul(*proj, job.mv);
    job.gx = PERSP_GUARD_PIXELS / (0.5 * f->fb->width);
    job.gy = PERSP_GUARD_PIXELS / (0.5 * f->fb->height);
    /* Clusters of back faces culled whole, and the vertices only they use
     * left out of the vertex stage (src/raster/cluster_cull.c): not for a
     * capture, which the analyses read with every vertex. */
    const uint8_t *culled = NULL;
    if ((cull || f->regions) && mesh->clusters && !f->capture && !f->ctx->no_cluster_cull) {
        const size_t blocks = (mesh->vertex_count + VERTEX_BLOCK - 1) / VERTEX_BLOCK;
        if (persp__reserve(f->ctx, (void **)&c->cluster_culled, &c->cluster_cap, mesh->cluster_count, 1) !=
                PERSP_OK ||
            persp__reserve(f->ctx, (void **)&c->vertex_need, &c->need_cap, blocks, 1) != PERSP_OK)
            return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        cluster_job cj = {.mesh = mesh, .culled = c->cluster_culled};
        persp__cluster_view_init(&cj.view, &job.mvp, f->fb->width, f->fb->height, job.gx, job.gy, cull);
        cj.view.regions = f->regions;
        cj.view.run = f->run;
        cj.view.tiles_x = (f->fb->width + PERSP_TILE - 1) / PERSP_TILE;
        const int ctasks = (int)((mesh->cluster_count + CLUSTER_TASK - 1) / CLUSTER_TASK);
        persp_status cst = persp__pool_run(f->ctx, ctasks, cluster_task, &cj);
        if (cst != PERSP_OK)
            return persp__fail(f->ctx, cst, "render: cannot start worker threads: %s", persp_status_string(cst));
        size_t n = 0, any = 0;
        for (size_t k = 0; k < mesh->cluster_count; k++) {
            n += c->cluster_culled[k] == 1;
            any += c->cluster_culled[k] != 0;
        }
        f->ctx->clusters_culled += n;
        if (any) {
            persp__clusters_vertex_need(mesh, c->cluster_culled, VERTEX_BLOCK, c->vertex_need);
            culled = c->cluster_culled;
            job.need = c->vertex_need;
        }
    }
    if (!persp_mat4_normal_matrix(job.mv, job.nm)) memset(job.nm, 0, sizeof job.nm);
    f->stats.triangles_in += mesh->index_count / 3;
    /* A mesh too small for two tasks a worker takes smaller ones, down to
     * VERTEX_TASK_MIN (as set-up does, mesh_triangles_parallel): the 2k
     * torus's 1000 vertices were lit by one thread while the other waited. */
    const size_t per = mesh->vertex_count / (2 * (size_t)persp__pool_workers(f->ctx));
    job.task_size = PERSP_MIN((size_t)VERTEX_TASK, PERSP_MAX((size_t)VERTEX_TASK_MIN, per)) / VERTEX_BLOCK *
                    VERTEX_BLOCK;
    const int tasks = (int)((mesh->vertex_count + job.task_size - 1) / job.task_size);
    persp_status vst = persp__pool_run(f->ctx, tasks, vertex_task, &job);
    if (vst != PERSP_OK)
        return persp__fail(f->ctx, vst, "render: cannot start worker threads: %s",
                           persp_status_string(vst));
    for (size_t t = 0; t + 2 < mesh->index_count; t += 3) {
        const uint32_t *ix = &mesh->indices[t];
        if (ix[0] >= mesh->vertex_count || ix[1] >= mesh->vertex_count || ix[2] >= mesh->vertex_count)
            return persp__fail(f->ctx, PERSP_ERR_INVALID_ARGUMENT,
                               "mesh: index out of range in triangle %zu", t / 3);
    }
    const size_t ntri = mesh->index_count / 3;
    tri_job tj = {.sink = {f, NULL}, .mesh = mesh, .state = state, .cull = cull, .nattr = nattr,
                  .mvp = job.mvp, .back = job.back ? c->back : NULL, .lazy = job.lazy ? c->lazy : NULL,
                  .culled = culled,
                  .gx = job.gx, .gy = job.gy};
    const int workers = persp__pool_workers(f->ctx);
    tj.chunk =
        PERSP_MIN((size_t)SETUP_CHUNK, PERSP_MAX((size_t)SETUP_CHUNK_MIN, ntri / (2 * (size_t)workers)));
    tj.slab = tj.chunk + tj.chunk / 8;
    /* Serial where set-up appends beside the records (method state, and a
     * capture's vertices: emit_triangle), and for fewer than two chunks a
     * worker. */
    if (workers < 2 || job.ds->method.m->prepare || f->capture ||
        ntri < 2 * (size_t)workers * SETUP_CHUNK_MIN)
        return mesh_triangles(&tj, 0, ntri, NULL);
    return mesh_triangles_parallel(&tj, ntri, workers);
}

persp_status persp__frame_flush(persp_frame *f) { return frame_flush_batch(f, 1); }

/* Draws the batch of set-up triangles; last: the frame's final batch. */
/* Binning: every record's tile range into per-tile lists, in submission
 * order (the order that makes results thread-independent). The records
 * are cut into contiguous parts; each part counts its triangles per tile,
 * a serial prefix sum over tiles then parts gives each part its offset in
 * each tile's list, and each part places its own indices there. The lists
 * are those of one serial pass, for any number of parts. Binned serially,
 * a two-thread frame of the 2M torus spent a fifth of its calling thread's
 * instructions here while the other thread waited. */
typedef struct bin_job {
    struct persp_render_cache *c;
    size_t records, chunk, tiles;
    int tiles_x;
} bin_job;

static void bin_count_task(void *user, int task, int worker)
{
    (void)worker;
    const bin_job *j = user;
    uint32_t *count = j->c->bin_part + (size_t)task * j->tiles;
    const size_t a = (size_t)task * j->chunk, b = PERSP_MIN(a + j->chunk, j->records);
    memset(count, 0, j->tiles * sizeof *count);
    for (size_t i = a; i < b; i++) {
        const struct tri_tiles *r = &j->c->tiles[i];
        for (int ty = r->ty0; ty <= r->ty1; ty++)
            for (int tx = r->tx0; tx <= r->tx1; tx++) count[ty * j->tiles_x + tx]++;
    }
}

static void bin_place_task(void *user, int task, int worker)
{
    (void)worker;
    const bin_job *j = user;
    uint32_t *at = j->c->bin_part + (size_t)task * j->tiles;
    uint32_t *items = j->c->bin_items;
    const size_t a = (size_t)task * j->chunk, b = PERSP_MIN(a + j->chunk, j->records);
    for (size_t i = a; i < b; i++) {
        const struct tri_tiles *r = &j->c->tiles[i];
        for (int ty = r->ty0; ty <= r->ty1; ty++)
            for (int tx = r->tx0; tx <= r->tx1; tx++) items[at[ty * j->tiles_x + tx]++] = (uint32_t)i;
    }
}

/* Records a part bins at least: below it a part's pass costs less than
 * handing it to a worker. */
#define BIN_PART_MIN 4096

static persp_status run_bin_tasks(persp_context *ctx, int parts, persp_task_fn fn, bin_job *j)
{
    if (parts == 1) {
        fn(j, 0, 0);
        return PERSP_OK;
    }
    persp_status st = persp__pool_run(ctx, parts, fn, j);
    if (st != PERSP_OK)
        return persp__fail(ctx, st, "render: cannot start worker threads: %s", persp_status_string(st));
    return PERSP_OK;
}

static persp_status bin_batch(persp_frame *f, int tiles_x, size_t tiles)
{
    struct persp_render_cache *c = f->cache;
    persp_context *ctx = f->ctx;
    const size_t u32 = sizeof(uint32_t);
    const size_t workers = (size_t)persp__pool_workers(ctx);
    const int parts = (int)PERSP_MAX((size_t)1, PERSP_MIN(workers, f->tri_count / BIN_PART_MIN));
    bin_job j = {c, f->tri_count, (f->tri_count + (size_t)parts - 1) / (size_t)parts, tiles, tiles_x};
    if (persp__grow(ctx, (void **)&c->bin_count, &c->bin_cap, tiles, u32) != PERSP_OK ||
        persp__grow(ctx, (void **)&c->bin_start, &c->start_cap, tiles, u32) != PERSP_OK ||
        persp__grow(ctx, (void **)&c->bin_part, &c->part_cap, (size_t)parts * tiles, u32) != PERSP_OK)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    persp_status st = run_bin_tasks(ctx, parts, bin_count_task, &j);
    if (st != PERSP_OK) return st;
    size_t total = 0;
    for (size_t k = 0; k < tiles; k++) {
        size_t n = 0;
        for (int p = 0; p < parts; p++) n += c->bin_part[(size_t)p * tiles + k];
        if (n > UINT32_MAX - total)
            return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "render: too many triangle-tile pairs");
        c->bin_start[k] = (uint32_t)total;
        c->bin_count[k] = (uint32_t)n;
        total += n;
    }
    if (persp__grow(ctx, (void **)&c->bin_items, &c->item_cap, total ? total : 1, u32) != PERSP_OK)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    for (size_t k = 0; k < tiles; k++) {
        uint32_t at = c->bin_start[k];
        for (int p = 0; p < parts; p++) {
            uint32_t *part = &c->bin_part[(size_t)p * tiles + k];
            const uint32_t n = *part;
            *part = at;
            at += n;
        }
    }
    return run_bin_tasks(ctx, parts, bin_place_task, &j);
}

static persp_status frame_flush_batch(persp_frame *f, int last)
{
    const int tiles_x = (f->fb->width + PERSP_TILE - 1) / PERSP_TILE;
    const int tiles_y = (f->fb->height + PERSP_TILE - 1) / PERSP_TILE;
    const size_t tiles = (size_t)tiles_x * (size_t)tiles_y;
    persp_status st = bin_batch(f, tiles_x, tiles);
    if (st != PERSP_OK) return st;
    if (f->batch_adapt && f->tri_count >= f->batch_base) {
        size_t touched = 0;
        for (size_t k = 0; k < tiles; k++) touched += f->cache->bin_count[k] > 0;
        const size_t tile_bytes = 2u * PERSP_TILE * PERSP_TILE * (sizeof(uint32_t) + sizeof(float));
        /* Against a base batch's records, so that a doubled batch, which
         * touches at least as many tiles, stays doubled. */
        f->batch = touched * tile_bytes > f->batch_base * sizeof *f->cache->tris
                       ? PERSP_MIN(2 * f->batch_base, PERSP_FRAME_BATCH_MAX)
                       : f->batch_base;
    }
    st = persp__frame_draw_tiles(f, tiles_x, tiles, last);
    if (st != PERSP_OK) return st;
    f->clear_pending = 0;
    f->stats.triangles_drawn += f->tri_count - f->gap_count;
    f->gap_count = 0;
    return PERSP_OK;
}

const persp_tri *persp__frame_tris(const persp_frame *f) { return f->cache->tris; }

const persp_rational_vertices *persp__frame_fits(const persp_frame *f)
{
    return f->capture ? f->cache->fits : NULL;
}

const persp_draw_state *persp__frame_state(const persp_frame *f, uint32_t index)
{
    return &f->cache->states[index];
}
