/*
 * The frame pipeline (docs/DESIGN.md):
 *   vertex stage → homogeneous clip → divide + viewport → setup (record per
 *   triangle, method prepare) → binning into 64×64 tiles → tiles in parallel:
 *   spans → depth test → method (u, v) → texture → shading → write.
 * Tiles own disjoint pixels and process their triangles in submission order,
 * so the image is bit-identical for any number of threads.
 */
#include "core/fmath.h"
#include "core/internal.h"
#include "core/pool.h"
#include "geom/scene.h"
#include "interp/methods.h"
#include "raster/raster.h"
#include "raster/frame.h"
#include "shade/shade.h"
#include "texture/texture.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if PERSP_HAVE_ISA_VARIANTS
#include <immintrin.h>
#endif

/* A vertex's window coordinates, computed once however many triangles share
 * it, with the same arithmetic emit_polygon applies to clipped vertices. */
struct vert_win {
    double z, q;
    /* llround(x·256), llround(y·256): the window position in the set-up's
     * fixed point, set when code is 0, and all of it the set-up reads
     * (X/256 rounds back to X exactly). Inside the guard band |x|, |y| are
     * at most the image side plus the guard band, 32 768 pixels, so 32
     * bits hold them; the record is then 32 bytes, not 56 (the per-vertex
     * caches are most of a large mesh's render memory and traffic). */
    int32_t X, Y;
    unsigned code; /* persp__clip_outcode */
};
_Static_assert((PERSP_IMAGE_MAX_SIDE + (long long)PERSP_GUARD_PIXELS) * PERSP_SUBPIXEL < INT32_MAX / 2,
               "guard-band window coordinates fit the 32-bit fixed point");

/* The tiles a set-up triangle covers, kept beside its record when it is
 * appended (and the record is in cache), so that binning reads 8 bytes per
 * triangle instead of a cache line of each ~800-byte record. */
struct tri_tiles {
    uint16_t tx0, tx1, ty0, ty1;
};
_Static_assert(PERSP_IMAGE_MAX_SIDE / PERSP_TILE <= UINT16_MAX, "tile index fits 16 bits");

struct persp_render_cache {
    persp_tri *tris;
    size_t tri_cap;
    struct tri_tiles *tiles; /* per triangle of tris */
    size_t tiles_cap;
    persp_method_prep *preps;
    size_t prep_cap;
    /* Per vertex: the first nattr attributes the draw reads
     * (vertex_attrs), packed: 2 floats unlit, 12 lit (no back colours),
     * instead of a whole persp_clipvert each. The clip position is not
     * kept: only clipping reads it, and recomputes it (clip_position). */
    float *verts;
    size_t vert_cap;
    struct vert_win *win; /* per vertex: window position and outcode */
    size_t win_cap;
    float *back; /* per vertex: Gouraud's back colour, when the vertex stage lights it */
    size_t back_cap;
    persp_tri *slab_tris; /* records set up by the worker threads */
    size_t slab_cap;
    struct setup_slab *slabs;
    size_t slabs_cap;
    uint32_t *bin_count, *bin_start, *bin_items;
    size_t bin_cap, start_cap, item_cap;
    persp_draw_state *states;
    size_t state_cap;
    persp_render_stats *worker_stats;
    size_t worker_cap;
};

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
    persp__free(ctx, c->states);
    persp__free(ctx, c->worker_stats);
    persp__free(ctx, c);
    ctx->render = NULL;
    ctx->render_free = NULL;
}

/* Set-up triangles held before the tiles draw them. A frame with more is
 * drawn in batches: each tile draws its triangles in submission order
 * whatever the batches, so the image is the same. A batch is written by the
 * set-up and read back by the tiles, so it is sized for the caches:
 * PERSP_FRAME_BATCH_PER_WORKER records (~800 bytes each, 6.3 MiB) per
 * worker thread. Against one batch of 65 536 (52 MiB, read back from
 * memory) that took 20 % less CPU time on the 2M-triangle torus and 17 %
 * on the 200k one (docs/PERFORMANCE.md), and memory stays bounded
 * whatever the mesh. A capture refers to triangles by their index in the
 * frame, so it takes one batch.
 *
 * Each batch also copies every tile it touches in and out (64 KiB a
 * tile). A mesh drawn in order touches few tiles a batch (the 2M torus:
 * 34-42 of 192), but unconnected triangles spread over the screen touch
 * all of them each batch (the soup: 8192 triangles in 192 tiles, 12 MiB
 * copied a batch, 13 % of a frame). When the last batch's tile copies
 * outweighed its records, the next batch takes twice as many: soup
 * 5-7 % less CPU, tori unchanged (a fixed doubling cost the tori 0.5-3 %). */
#define PERSP_FRAME_BATCH_PER_WORKER 8192u
#define PERSP_FRAME_BATCH_MAX 65536u

/* PERSP_SIMD_AUTO is resolved here, at the first frame, rather than at
 * context creation: the choice is timed on the samplers of the texture
 * module, which the context's own module sits below. */
persp_simd persp_context_simd(persp_context *ctx)
{
    if (!ctx) return PERSP_SIMD_AUTO;
    if (ctx->isa < 0) ctx->isa = persp__fast_span_auto_isa();
    return persp__simd_from_isa(ctx->isa);
}

persp_status persp__frame_begin(persp_context *ctx, persp_framebuffer *fb, persp_depth_mode mode,
                                persp_frame *f)
{
    memset(f, 0, sizeof *f);
    if (!ctx || !fb || !fb->color || !fb->depth || fb->width <= 0 || fb->height <= 0 ||
        fb->width > PERSP_IMAGE_MAX_SIDE || fb->height > PERSP_IMAGE_MAX_SIDE)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                                  "framebuffer: size must be 1..%d on each side with colour and depth buffers",
                                  PERSP_IMAGE_MAX_SIDE);
    if (!ctx->render) {
        ctx->render = persp__calloc(ctx, 1, sizeof(struct persp_render_cache));
        if (!ctx->render) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        ctx->render_free = render_cache_free;
    }
    f->ctx = ctx;
    f->fb = fb;
    f->depth_mode = mode;
    f->cache = ctx->render;
    f->batch = ctx->frame_batch ? ctx->frame_batch
                                : PERSP_MIN(PERSP_FRAME_BATCH_MAX,
                                            PERSP_FRAME_BATCH_PER_WORKER * (size_t)persp__pool_workers(ctx));
    f->batch_base = f->batch;
    f->batch_adapt = !ctx->frame_batch;
    persp_context_simd(ctx);
    f->pack_avx512 =
        (ctx->isa == PERSP_ISA_AVX512 || ctx->isa == PERSP_ISA_AVX512_GATHER) && !ctx->pack_portable;
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

static int lane_filter(persp_filter filter);

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
                      lane_filter(ds->sampler.desc.filter) &&
                      (ds->shade_is_texel || (pc && !(ds->shading == PERSP_SHADING_GOURAUD_PC &&
                                                      ds->material.env == PERSP_TEXENV_REPLACE)));
    *index = (uint32_t)f->state_count++;
    return PERSP_OK;
}


/* Makes room for one more triangle in the frame, drawing the batch first
 * when it is full. */
static persp_status frame_flush_batch(persp_frame *f, int last);

static size_t frame_batch_limit(const persp_frame *f)
{
    return f->capture ? SIZE_MAX : f->batch;
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
    if (persp__grow(f->ctx, (void **)&c->tris, &c->tri_cap, f->tri_count + n, sizeof *c->tris) != PERSP_OK ||
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
    f->tri_count++;
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
 * LOD; 0 if set-up refuses it. Touches nothing but *t (worker threads). */
static int setup_record(const persp_frame *f, const persp_draw_state *ds, const persp_winvert tv[3],
                        const persp_tri_edges *e, const float *const col[3], const float *const back[3],
                        uint32_t state, int cull, persp_tri *t)
{
    /* A span that is the texel itself reads no shading field; the
     * analyses' capture and the object-space pipeline read them all. With
     * col, Gouraud's back colours come from back_colours; without, with
     * the attributes (clipped polygons: mesh_triangles added them before
     * clipping, which interpolates them). */
    const int gouraud = persp__shade_is_gouraud(ds);
    unsigned need = vertex_attrs(f, ds) <= PERSP_A_V + 1 ? 0u
                    : gouraud && !col                  ? PERSP_SETUP_SHADING | PERSP_SETUP_BACK_COLOURS
                                                       : PERSP_SETUP_SHADING;
    if (need && (!ds->shade_method.m || f->capture)) need |= PERSP_SETUP_LINEAR;
    if (e ? !persp__setup_triangle_edges(tv, e, need, t)
          : !persp__setup_triangle_for(tv, f->fb->width, f->fb->height, cull, need, t))
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
    /* Only the per-polygon level of detail reads it (a log2 per triangle). */
    if (ds->tex && ds->sampler.desc.lod_mode == PERSP_LOD_POLYGON) {
        double du1 = t->rat.s1v[1] - t->rat.s1v[0], dv1 = t->rat.s2v[1] - t->rat.s2v[0];
        double du2 = t->rat.s1v[2] - t->rat.s1v[0], dv2 = t->rat.s2v[2] - t->rat.s2v[0];
        double uv_area = 0.5 * fabs(du1 * dv2 - du2 * dv1);
        double px_area = 0.5 * fabs((t->rat.vx[1] - t->rat.vx[0]) * (t->rat.vy[2] - t->rat.vy[0]) -
                                    (t->rat.vx[2] - t->rat.vx[0]) * (t->rat.vy[1] - t->rat.vy[0]));
        t->poly_lambda = persp__polygon_lambda(ds->tex, uv_area, px_area);
    }
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
    if (!setup_record(f, ds, tv, e, col, back, state, cull, t)) return PERSP_OK;
    if (ds->method.m->prepare) {
        if (persp__grow(f->ctx, (void **)&c->preps, &c->prep_cap, f->prep_count + 1, sizeof *c->preps) !=
            PERSP_OK)
            return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        t->prep = (uint32_t)f->prep_count++;
        ds->method.m->prepare(&t->rat, &ds->method.params, &c->preps[t->prep],
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
    if (setup_record(s->f, ds, tv, e, col, back, state, cull, &sl->tris[sl->count])) {
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
PERSP_SIMD_CLONES_WIDE static void transform_block(const persp_mat4 *m, const persp_vertex *v, size_t n,
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
PERSP_SIMD_CLONES_WIDE static void window_block(const float *o, size_t stride, size_t n,
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

static void vertex_task(void *user, int task, int worker)
{
    (void)worker;
    const vertex_job *j = user;
    struct persp_render_cache *c = j->f->cache;
    const persp_mesh *mesh = j->mesh;
    const size_t a = (size_t)task * VERTEX_TASK;
    const size_t b = PERSP_MIN(a + VERTEX_TASK, mesh->vertex_count);
    const float *nm = j->nm, *uv = j->uv;
    const size_t stride = (size_t)j->nattr;
    const int lit = j->nattr > PERSP_A_V + 1, gouraud = lit && persp__shade_is_gouraud(j->ds);
    const double W = j->f->fb->width, H = j->f->fb->height;
    /* Block by block, each step across the block while it is in L1: a
     * block's normals, positions and colours go to the lighting as arrays
     * (they were gathered back out of the packed cache, 4 % of a frame of
     * the 2M-triangle torus). */
    for (size_t i0 = a; i0 < b; i0 += VERTEX_BLOCK) {
        const size_t n = PERSP_MIN((size_t)VERTEX_BLOCK, b - i0);
        float cp[4][VERTEX_BLOCK], ep[4][VERTEX_BLOCK], en[3][VERTEX_BLOCK], col[3][VERTEX_BLOCK];
        transform_block(&j->mvp, mesh->vertices + i0, n, cp);
        if (lit) transform_block(&j->mv, mesh->vertices + i0, n, ep);
        for (size_t k = 0; k < n; k++) {
            const size_t i = i0 + k;
            const persp_vertex *v = &mesh->vertices[i];
            float *at = c->verts + i * stride;
            at[PERSP_A_U] = uv ? uv[2 * i] : v->uv[0];
            at[PERSP_A_V] = uv ? uv[2 * i + 1] : v->uv[1];
            if (!lit) continue;
            if (!gouraud) /* Gouraud writes its lit colours below */
                for (int r = 0; r < 4; r++) at[PERSP_A_R + r] = v->color[r];
            for (int r = 0; r < 3; r++) {
                col[r][k] = v->color[r];
                en[r][k] = at[PERSP_A_NX + r] =
                    nm[r] * v->normal[0] + nm[3 + r] * v->normal[1] + nm[6 + r] * v->normal[2];
            }
            at[PERSP_A_EX] = ep[0][k], at[PERSP_A_EY] = ep[1][k], at[PERSP_A_EZ] = ep[2][k];
        }
        if (gouraud) {
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
        window_block(c->verts + i0 * stride, stride, n, (const float(*)[VERTEX_BLOCK])cp, j->gx, j->gy, W, H,
                     &c->win[i0]);
    }
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
    double gx, gy;
    setup_slab *slabs;
    size_t first; /* first input triangle of the round */
} tri_job;

/* Where back_colours finds the back colours of triangle ix's vertices. */
static void colour_sources(const tri_job *j, const uint32_t ix[3], const float *col[3], const float *back[3])
{
    for (int k = 0; k < 3; k++) {
        col[k] = j->mesh->vertices[ix[k]].color;
        back[k] = j->back ? j->back + 3 * (size_t)ix[k] : NULL;
    }
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
    for (size_t t = a; t < b; t++) {
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
            if (!persp__tri_edges(X, Y, width, height, j->cull, &e)) continue;
            persp_winvert tv[3];
            for (int k = 0; k < 3; k++) {
                const struct vert_win *w = &c->win[ix[k]];
                tv[k] = (persp_winvert){w->X * (1.0 / PERSP_SUBPIXEL), w->Y * (1.0 / PERSP_SUBPIXEL), w->z,
                                        w->q, c->verts + ix[k] * stride};
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
            const persp_draw_state *ds = &c->states[j->state];
            if (persp__shade_is_gouraud(ds)) {
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
    if (slab) slab->stop = b;
    return PERSP_OK;
}

/* Triangle set-up on the worker threads: a round gives each of its tasks
 * SETUP_CHUNK consecutive input triangles and a slab for their records;
 * the calling thread then appends the slabs in input order, and sets up
 * itself whatever a full slab left over before moving to the next slab, so
 * the frame receives exactly the serial sequence of triangles. */
/* 2048 rather than 512: each round is a start and a wait of the worker
 * threads, and with 512 their wake-ups took a sixth of a two-thread frame
 * of the 2M torus (kernel time); 2048: −13 % wall there, −8 % on the 200k
 * torus. */
#define SETUP_CHUNK 2048u
#define SETUP_SLAB (SETUP_CHUNK + SETUP_CHUNK / 2)

static void setup_task(void *user, int task, int worker)
{
    (void)worker;
    tri_job *j = user;
    setup_slab *slab = &j->slabs[task];
    const size_t a = j->first + (size_t)task * SETUP_CHUNK;
    const size_t b = PERSP_MIN(a + SETUP_CHUNK, j->mesh->index_count / 3);
    slab->count = 0;
    (void)mesh_triangles(j, a, b, slab); /* a slab sink cannot fail */
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
 * region of SETUP_SLAB slots of the frame's records, so that nothing is
 * copied (a copy of every record on the calling thread took a fifth of a
 * two-thread frame of the 2M torus). The slots a task leaves unused stay
 * in the batch as gaps, marked as covering no tile, so binning passes over
 * them; the frame counts them (gap_count) to report only real triangles.
 * Only without a capture, whose users walk the records by index. When a
 * task's slab overflowed, the slabs after it are moved out to the scratch
 * slabs and appended by copying after the overflowing chunk's remainder,
 * which keeps the serial order. */
static persp_status scratch_slabs(persp_frame *f, size_t tasks)
{
    struct persp_render_cache *c = f->cache;
    if (persp__grow(f->ctx, (void **)&c->slab_tris, &c->slab_cap, tasks * SETUP_SLAB,
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
        PERSP_MAX((size_t)workers, PERSP_MIN((size_t)workers * 2, batch_slots / SETUP_SLAB));
    if (persp__grow(f->ctx, (void **)&c->slabs, &c->slabs_cap, tasks_max, sizeof *c->slabs) != PERSP_OK)
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    j->slabs = c->slabs;
    for (j->first = 0; j->first < ntri; j->first += tasks_max * SETUP_CHUNK) {
        const size_t batch = frame_batch_limit(f);
        const size_t left = ntri - j->first;
        const int tasks = (int)PERSP_MIN(tasks_max, (left + SETUP_CHUNK - 1) / SETUP_CHUNK);
        const size_t slots = (size_t)tasks * SETUP_SLAB;
        persp_status st;
        const int in_place = !f->capture && slots <= batch;
        /* The scratch slabs (a batch's worth of records: 13 MB with two
         * workers) exist only once a round needs them: without in-place
         * slabs, or when a slab overflowed (below). */
        if (!in_place && scratch_slabs(f, tasks_max) != PERSP_OK) return PERSP_ERR_OUT_OF_MEMORY;
        if (in_place) {
            if (f->tri_count + slots > batch && f->tri_count > 0) {
                if ((st = frame_flush_batch(f, 0)) != PERSP_OK) return st;
                f->tri_count = f->prep_count = 0;
            }
            if (persp__grow(f->ctx, (void **)&c->tris, &c->tri_cap, f->tri_count + slots, sizeof *c->tris) !=
                    PERSP_OK ||
                persp__grow(f->ctx, (void **)&c->tiles, &c->tiles_cap, f->tri_count + slots,
                            sizeof *c->tiles) != PERSP_OK)
                return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        }
        const size_t base = f->tri_count;
        for (int k = 0; k < tasks; k++) {
            c->slabs[k].tris = in_place ? c->tris + base + (size_t)k * SETUP_SLAB : c->slab_tris + (size_t)k * SETUP_SLAB;
            c->slabs[k].tiles = in_place ? c->tiles + base + (size_t)k * SETUP_SLAB : NULL;
            c->slabs[k].cap = SETUP_SLAB;
        }
        st = persp__pool_run(f->ctx, tasks, setup_task, j);
        if (st != PERSP_OK)
            return persp__fail(f->ctx, st, "render: cannot start worker threads: %s",
                               persp_status_string(st));
        int copying = !in_place;
        for (int k = 0; k < tasks; k++) {
            const setup_slab *slab = &j->slabs[k];
            const size_t end = PERSP_MIN(j->first + ((size_t)k + 1) * SETUP_CHUNK, ntri);
            if (copying) {
                if ((st = append_slab(f, slab)) != PERSP_OK) return st;
            } else {
                /* The records and their tile ranges are in place (the task
                 * wrote both); the unused slots become gaps. */
                const size_t region = base + (size_t)k * SETUP_SLAB;
                for (size_t i = slab->count; i < SETUP_SLAB; i++)
                    c->tiles[region + i] = (struct tri_tiles){1, 0, 1, 0};
                f->gap_count += SETUP_SLAB - slab->count;
                f->tri_count = region + SETUP_SLAB;
                if (slab->stop < end && k + 1 < tasks) {
                    /* The later slabs leave the frame before the serial
                     * remainder of this chunk is appended after it. */
                    if (scratch_slabs(f, tasks_max) != PERSP_OK) return PERSP_ERR_OUT_OF_MEMORY;
                    for (int m = k + 1; m < tasks; m++) {
                        setup_slab *later = &j->slabs[m];
                        memcpy(c->slab_tris + (size_t)m * SETUP_SLAB, later->tris, later->count * sizeof *c->tris);
                        later->tris = c->slab_tris + (size_t)m * SETUP_SLAB;
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
                      .back = persp__shade_is_gouraud(ds) && (back_lighting ? back_lighting == 1 : !cull)};
    if (job.back && (!persp__size_mul(mesh->vertex_count, 3, &floats) ||
                     persp__reserve(f->ctx, (void **)&c->back, &c->back_cap, floats, sizeof *c->back) != PERSP_OK))
        return persp__fail(f->ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    job.mv = persp_mat4_mul(*view, *model);
    job.mvp = persp_mat4_mul(*proj, job.mv);
    if (!persp_mat4_normal_matrix(job.mv, job.nm)) memset(job.nm, 0, sizeof job.nm);
    job.gx = PERSP_GUARD_PIXELS / (0.5 * f->fb->width);
    job.gy = PERSP_GUARD_PIXELS / (0.5 * f->fb->height);
    f->stats.triangles_in += mesh->index_count / 3;
    const int tasks = (int)((mesh->vertex_count + VERTEX_TASK - 1) / VERTEX_TASK);
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
                  .mvp = job.mvp, .back = job.back ? c->back : NULL, .gx = job.gx, .gy = job.gy};
    const int workers = persp__pool_workers(f->ctx);
    if (workers < 2 || job.ds->method.m->prepare || ntri < 4 * SETUP_CHUNK)
        return mesh_triangles(&tj, 0, ntri, NULL);
    return mesh_triangles_parallel(&tj, ntri, workers);
}

/* ------------------------------------------------------------ rasterization */

typedef struct tile_job {
    persp_frame *f;
    int tiles_x;
    int workers;
    int stream; /* write tiles out with non-temporal stores */
} tile_job;

/* Framebuffers (colour + depth) above this size do not stay in the caches
 * between frames, so writing them without reading them in pays. */
#define PERSP_STREAM_BYTES (2u << 20)

/* A tile is drawn into tile-local colour and depth buffers (PERSP_TILE
 * pixels per row, origin ox, oy in the frame), which stay in the level-1
 * cache, and written to the framebuffer once at the end: clearing and the
 * depth test then never touch memory, and the framebuffer is written once
 * per frame in whole rows (docs/PERFORMANCE.md). */
typedef struct span_ctx {
    persp_frame *f;
    const persp_tri *t;
    const persp_draw_state *ds;
    const persp_method_prep *prep;
    persp_render_stats *stats;
    persp_opcount *ops; /* NULL unless the frame counts operations */
    int32_t tri_index;
    uint32_t *color;
    float *depth;
    int ox, oy;
} span_ctx;

PERSP_SIMD_CLONES static void shade_batch(span_ctx *sc, const persp_frag_batch *b)
{
    const persp_frame *f = sc->f;
    const persp_tri *t = sc->t;
    const persp_draw_state *ds = sc->ds;
    const int n = b->n;
    const int W = f->fb->width;
    float q[PERSP_SPAN_MAX], z[PERSP_SPAN_MAX];
    int32_t idx[PERSP_SPAN_MAX], live[PERSP_SPAN_MAX];
    const int invw = f->depth_mode == PERSP_DEPTH_INVW;
    float *depth = sc->depth;
    int any = 0;
    int32_t base = 0;

    if (!b->px) {
        /* Span form: contiguous pixels, pixel k at base + k; every loop is
         * branch-free so that it vectorises. */
        double px = b->x0 + 0.5, py = b->y + 0.5;
        float q0 = (float)(t->rat.g * px + t->rat.h * py + t->rat.i), dq = (float)t->rat.g;
        float z0 = (float)(t->zp[0] * px + t->zp[1] * py + t->zp[2]), dz = (float)t->zp[0];
        base = (b->y - sc->oy) * PERSP_TILE + (b->x0 - sc->ox);
        const float *drow = depth + base;
        for (int k = 0; k < n; k++) {
            q[k] = q0 + (float)k * dq;
            z[k] = z0 + (float)k * dz;
        }
        if (!ds->depth_test) {
            for (int k = 0; k < n; k++) live[k] = 1;
        } else if (invw) {
            /* "1/z buffering" ([CS300-TexMap]): 1/w grows towards the eye and is
             * linear in screen space, so the largest value is the nearest. */
            for (int k = 0; k < n; k++) live[k] = q[k] > drow[k];
        } else {
            for (int k = 0; k < n; k++) live[k] = z[k] < drow[k];
        }
    } else {
        for (int k = 0; k < n; k++) {
            double px = b->px[k] + 0.5, py = b->py[k] + 0.5;
            q[k] = (float)(t->rat.g * px + t->rat.h * py + t->rat.i);
            z[k] = (float)(t->zp[0] * px + t->zp[1] * py + t->zp[2]);
            idx[k] = (b->py[k] - sc->oy) * PERSP_TILE + (b->px[k] - sc->ox);
        }
        for (int k = 0; k < n; k++)
            live[k] = !ds->depth_test ? 1 : invw ? q[k] > depth[idx[k]] : z[k] < depth[idx[k]];
    }
    for (int k = 0; k < n; k++) any += live[k];
    sc->stats->fragments += (uint64_t)n;
    if (!any) return;

    float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX], w1[PERSP_SPAN_MAX], w2[PERSP_SPAN_MAX];
    const float *su = u, *sv = v;
    persp_frag_batch fused;
    if (b->s1) {
        su = b->s1;
        sv = b->s2;
    } else if (!ds->tex && !f->capture && !sc->ops) {
        /* Untextured: nothing reads the texture coordinates. */
    } else if (ds->fuse_weights) {
        /* Texture coordinates and the shader's perspective-correct weights
         * share 1/w: one reciprocal per pixel for both ([Romanyuk-PCF] §4.2
         * weights are Heckbert's rational form with other numerators). */
        persp__exact_span_pair(&t->rat, &t->bary, b->x0, b->y, n, u, v, w1, w2);
        fused = *b;
        fused.w1 = w1;
        fused.w2 = w2;
        b = &fused;
    } else {
        ds->method.m->span(&t->rat, &ds->method.params, sc->prep, b->x0, b->y, n, u, v, sc->ops);
    }
    /* A contiguous span whose pixels all pass is coloured in place in the
     * tile; otherwise into out[] and then merged. */
    uint32_t texel[PERSP_SPAN_MAX], out[PERSP_SPAN_MAX];
    const int in_place = !b->px && any == n;
    uint32_t *dst = in_place ? sc->color + base : out;
    if (ds->tex) {
        persp_tex_span_in in = {
            .n = n, .u = su, .v = sv, .q = q,
            .a = (float)t->rat.a, .b = (float)t->rat.b, .d = (float)t->rat.d,
            .e = (float)t->rat.e, .g = (float)t->rat.g, .h = (float)t->rat.h,
            .poly_lambda = t->poly_lambda,
        };
        persp__sample_span(&ds->sampler, &in, ds->shade_is_texel ? dst : texel);
    }
    if (!ds->shade_is_texel) persp__shade_span(ds, t, b, q, ds->tex ? texel : NULL, dst);
    /* persp draws opaque surfaces (docs/SCENES.md, "Textures"): alpha is no coverage. */
    if (ds->force_opaque)
        for (int k = 0; k < n; k++)
            dst[k] |= 0xff000000u;

    uint32_t *color = sc->color;
    const float *dv = invw ? q : z;
    if (in_place) {
        if (ds->depth_write) {
            float *drow = depth + base;
            for (int k = 0; k < n; k++) drow[k] = dv[k];
        }
    } else if (!b->px) {
        uint32_t *crow = color + base;
        float *drow = depth + base;
        for (int k = 0; k < n; k++) crow[k] = live[k] ? out[k] : crow[k];
        if (ds->depth_write)
            for (int k = 0; k < n; k++) drow[k] = live[k] ? dv[k] : drow[k];
    } else {
        for (int k = 0; k < n; k++) {
            if (!live[k]) continue;
            color[idx[k]] = out[k];
            if (ds->depth_write) depth[idx[k]] = dv[k];
        }
    }
    sc->stats->pixels_written += (uint64_t)any;
    if (f->capture) {
        persp_capture *cap = f->capture;
        for (int k = 0; k < n; k++) {
            if (!live[k]) continue;
            int32_t i = b->px ? b->py[k] * W + b->px[k] : b->y * W + b->x0 + k;
            cap->tri[i] = sc->tri_index;
            cap->s1[i] = su[k];
            cap->s2[i] = sv[k];
        }
    }
}

static void sink(void *user, const persp_frag_batch *b) { shade_batch(user, b); }

/* ---------------------------------------------------- small triangles
 *
 * A triangle narrower than a tile has short rows, and each row as
 * its own span pays the fixed cost of a span (depth set-up, a method call,
 * a sampler call, the write-back) for very few pixels. The rows of such a
 * triangle are packed instead into lanes of one batch, each lane carrying
 * its row's start values and its offset k in the row, so that every value
 * is computed by the same operations as on the span path (row start in
 * double rounded to float, then start + k·step, one reciprocal), and the
 * image is the same bit for bit. Taken where every stage works lane by
 * lane: the exact method, a filter whose footprint is each pixel's own
 * (not the window or EWA filters, nor a custom traversal), and shading
 * that is the texel, perspective-correct Gouraud modulating it, or
 * perspective-correct Phong (whose lighting runs across lanes anyway). */
/* Measured on the tori: 64 against 16 and 32 (20k: 4–6 %, 2k: 7–9 % less
 * CPU than 32); once lane batches took several triangles (items 37–42 of
 * docs/PERFORMANCE.md), 128 against 64 (2k: unlit −6 %, gouraud-pc −6 %,
 * phong-pc −12 %; 256 or no limit gained no more). A triangle wider than
 * that has long rows, which spans draw in place: every triangle on lanes
 * cost the corridor 19 % (bilinear), and so did lanes for every triangle
 * narrower than the tile it is drawn in (its long diagonal edges). */
#define SMALL_TRI_WIDTH 128
/* How many records ahead raster_tile prefetches: a record is read back
 * cold (the batch is 13 MiB of them), and one ahead hid little of the
 * miss. 4 against 1: soup unlit −7.5 %, gouraud-pc −7.5 %, phong-pc −5 %
 * CPU; 2 gained half of that, 8 no more; the tori ±1 %. */
#define PREFETCH_AHEAD 4

/* Lanes of one batch may come from several consecutive small triangles
 * of the tile (segments), all of one draw state: a triangle of a pixel or
 * two fills a sixteenth of a batch, and the sampler and the write-back
 * cost the same for a full one (on the 2M torus, 1.5 pixels per drawn
 * triangle). The per-lane values are the row start plus k·step, computed
 * when the lane is filled by the operations shade_lanes used to apply. No
 * two lanes of a batch are the same pixel (the tile's busy bitmap), so the
 * depth tests of a batch cannot see one another and the order of
 * submission is kept. */
#define LANE_GROUP 16
_Static_assert(PERSP_TILE == 64, "a tile row of the busy bitmap is one 64-bit word");
typedef struct lane_batch {
    int n, nseg;
    int row0, row1; /* the tile rows its lanes lie in */
    const persp_draw_state *ds;
    /* LANE_GROUP lanes of slack: draw_small fills whole groups. */
    float q[PERSP_LANE_MAX + LANE_GROUP], z[PERSP_LANE_MAX + LANE_GROUP];   /* 1/w and depth */
    float un[PERSP_LANE_MAX + LANE_GROUP], vn[PERSP_LANE_MAX + LANE_GROUP]; /* u/w, v/w */
    float an[PERSP_LANE_MAX + LANE_GROUP], bn[PERSP_LANE_MAX + LANE_GROUP]; /* the weights' numerators (lit) */
    int32_t idx[PERSP_LANE_MAX + LANE_GROUP]; /* pixel in the tile: row·PERSP_TILE + column */
    int seg_start[PERSP_LANE_MAX + 1];
    const persp_tri *seg_tri[PERSP_LANE_MAX];
} lane_batch;

/* Filters whose footprint is each pixel's own (per-draw half of the
 * condition: persp__frame_add_state sets small_lanes). */
static int lane_filter(persp_filter filter)
{
    switch (filter) {
    case PERSP_FILTER_NEAREST:
    case PERSP_FILTER_BILINEAR:
    case PERSP_FILTER_NEAREST_MIP_NEAREST:
    case PERSP_FILTER_BILINEAR_MIP_NEAREST:
    case PERSP_FILTER_NEAREST_MIP_LINEAR:
    case PERSP_FILTER_TRILINEAR: return 1;
    default: return 0;
    }
}

static int lanes_apply(const persp_draw_state *ds, const persp_tri *t)
{
    return ds->small_lanes && t->prep == UINT32_MAX && t->xmax - t->xmin < SMALL_TRI_WIDTH;
}

/* Moves the lanes that passed the depth test to the front of the batch,
 * in order, and renumbers the segments (dropping those left empty); every
 * later stage then works on live lanes only. Under overdraw most lanes of a
 * batch are hidden (the soup: about 60 %), and sampling and lighting them
 * cost as much as live ones. Each lane's values were computed when it was
 * filled, so moving them changes no bit. live[] has LANE_GROUP entries of
 * slack; returns the live count, and live[] is all ones after. */
#if PERSP_HAVE_ISA_VARIANTS
/* Sixteen lanes at a time with compress (vcompressps): the portable loop
 * moves one lane at a time and took 14 % of a gouraud-pc frame of the soup
 * with batches of 256 lanes. The stores write whole vectors at the packed
 * position, which never passes the lanes still to be read, into the
 * arrays' LANE_GROUP lanes of slack. */
PERSP_TARGET_AVX512 static void pack_lanes_avx512(lane_batch *lb, int n, const int32_t *live, uint64_t *bits)
{
    float *const arr[6] = {lb->q, lb->z, lb->un, lb->vn, lb->an, lb->bn};
    int m = 0;
    for (int k = 0; k < n; k += LANE_GROUP) {
        const __m512i lv = _mm512_loadu_si512((const void *)(live + k));
        __mmask16 mk = _mm512_test_epi32_mask(lv, lv);
        if (n - k < LANE_GROUP) mk &= (__mmask16)((1u << (n - k)) - 1u);
        bits[k >> 6] |= (uint64_t)mk << (k & 63);
        for (int a = 0; a < 6; a++)
            _mm512_storeu_ps(arr[a] + m, _mm512_maskz_compress_ps(mk, _mm512_loadu_ps(arr[a] + k)));
        _mm512_storeu_si512((void *)(lb->idx + m),
                            _mm512_maskz_compress_epi32(mk, _mm512_loadu_si512((const void *)(lb->idx + k))));
        m += __builtin_popcount(mk);
    }
}
#endif

_Static_assert(PERSP_LANE_MAX % LANE_GROUP == 0, "lane batches hold whole groups");

/* Live lanes before lane p, from the batch's bitmap of live lanes. */
static int live_before(const uint64_t *bits, int p)
{
    int c = 0;
    for (int w = 0; w < p >> 6; w++) c += __builtin_popcountll(bits[w]);
    if (p & 63) c += __builtin_popcountll(bits[p >> 6] & ((1ull << (p & 63)) - 1));
    return c;
}

static int pack_live(lane_batch *lb, int n, int32_t *live, int avx512)
{
    uint64_t bits[PERSP_LANE_MAX / 64 + 1] = {0};
#if PERSP_HAVE_ISA_VARIANTS
    if (avx512) {
        pack_lanes_avx512(lb, n, live, bits);
    } else
#endif
    {
        (void)avx512;
        int j = 0;
        for (int k = 0; k < n; k++) {
            lb->q[j] = lb->q[k];
            lb->z[j] = lb->z[k];
            lb->un[j] = lb->un[k];
            lb->vn[j] = lb->vn[k];
            lb->an[j] = lb->an[k];
            lb->bn[j] = lb->bn[k];
            lb->idx[j] = lb->idx[k];
            j += live[k];
            bits[k >> 6] |= (uint64_t)(live[k] != 0) << (k & 63);
        }
    }
    int nseg = 0, m = 0;
    for (int s = 0; s < lb->nseg; s++) {
        const int end = live_before(bits, lb->seg_start[s + 1]);
        if (end > m) {
            lb->seg_start[nseg] = m;
            lb->seg_tri[nseg++] = lb->seg_tri[s];
        }
        m = end;
    }
    lb->nseg = nseg;
    lb->seg_start[nseg] = m;
    for (int k = 0; k < m; k++) live[k] = 1;
    return m;
}

PERSP_SIMD_CLONES static void shade_lanes(span_ctx *sc, lane_batch *lb, uint64_t *busy)
{
    const persp_frame *f = sc->f;
    const persp_draw_state *ds = lb->ds;
    int n = lb->n;
    const int invw = f->depth_mode == PERSP_DEPTH_INVW;
    float *depth = sc->depth;
    uint32_t *color = sc->color;
    const float *q = lb->q, *z = lb->z;
    int32_t live[PERSP_LANE_MAX + LANE_GROUP];
    /* The bitmap holds this batch's pixels only. */
    memset(busy + lb->row0, 0, (size_t)(lb->row1 - lb->row0 + 1) * sizeof *busy);
    lb->n = 0;
    if (!ds->depth_test) {
        for (int k = 0; k < n; k++) live[k] = 1;
    } else if (invw) {
        for (int k = 0; k < n; k++) live[k] = q[k] > depth[lb->idx[k]];
    } else {
        for (int k = 0; k < n; k++) live[k] = z[k] < depth[lb->idx[k]];
    }
    int any = 0;
    for (int k = 0; k < n; k++) any += live[k];
    sc->stats->fragments += (uint64_t)n;
    if (!any) return;
    /* Unlit, a hidden lane costs about what moving it one at a time costs
     * (soup: +6 % CPU when packed so), and less than moving it by compress
     * (−5 %); lit, it costs its lighting too, so a lit batch is always
     * packed and the shaders below light every lane they are given. */
    if (any < n && (!ds->shade_is_texel || f->pack_avx512)) n = pack_live(lb, n, live, f->pack_avx512);
    float u[PERSP_LANE_MAX], v[PERSP_LANE_MAX], w1[PERSP_LANE_MAX], w2[PERSP_LANE_MAX], rq[PERSP_LANE_MAX];
    const int weights = !ds->shade_is_texel;
    /* exact_span: rq = 1 / (Q + k·dQ), which is q[k]; one for u, v and the
     * weights, as persp__exact_span_pair. */
    for (int k = 0; k < n; k++) {
        rq[k] = 1.0f / q[k];
        u[k] = lb->un[k] * rq[k];
        v[k] = lb->vn[k] * rq[k];
    }
    if (weights)
        for (int k = 0; k < n; k++) {
            w1[k] = lb->an[k] * rq[k];
            w2[k] = lb->bn[k] * rq[k];
        }
    uint32_t texel[PERSP_LANE_MAX], out[PERSP_LANE_MAX];
    uint32_t *tx = weights ? texel : out;
    /* A filter without a level of detail reads no triangle's derivatives:
     * one call for every segment. */
    const int one_call = !persp__sampler_needs_lod(&ds->sampler);
    for (int s = 0; s < lb->nseg; s++) {
        const persp_tri *t = lb->seg_tri[s];
        const int s0 = one_call ? 0 : lb->seg_start[s];
        const int m = (one_call ? n : lb->seg_start[s + 1]) - s0;
        persp_tex_span_in in = {
            .n = m, .u = u + s0, .v = v + s0, .q = q + s0,
            .a = (float)t->rat.a, .b = (float)t->rat.b, .d = (float)t->rat.d,
            .e = (float)t->rat.e, .g = (float)t->rat.g, .h = (float)t->rat.h,
            .poly_lambda = t->poly_lambda,
        };
        persp__sample_span(&ds->sampler, &in, tx + s0);
        if (one_call) break;
    }
    /* One triangle: phong_lanes pads its loops to whole vectors, which
     * segments cannot. */
    if (weights && ds->shading == PERSP_SHADING_PHONG_PC && lb->nseg == 1)
        persp__shade_phong_lanes(ds, lb->seg_tri[0], n, w1, w2, texel, out);
    else if (weights && ds->shading == PERSP_SHADING_PHONG_PC)
        persp__shade_phong_segments(ds, lb->nseg, lb->seg_start, lb->seg_tri, w1, w2, texel, out);
    else if (weights)
        for (int s = 0; s < lb->nseg; s++) {
            const int s0 = lb->seg_start[s], m = lb->seg_start[s + 1] - s0;
            persp__shade_gouraud_lanes(ds, lb->seg_tri[s], m, w1 + s0, w2 + s0, texel + s0, out + s0);
        }
    if (ds->force_opaque)
        for (int k = 0; k < n; k++) out[k] |= 0xff000000u;
    const float *dvals = invw ? q : z;
    for (int k = 0; k < n; k++) {
        if (!live[k]) continue;
        color[lb->idx[k]] = out[k];
        if (ds->depth_write) depth[lb->idx[k]] = dvals[k];
    }
    sc->stats->pixels_written += (uint64_t)any;
}

/* The rows ya..yb of a small triangle within the tile's columns x0..x1,
 * added to the tile's lane batch in whole rows; the batch is shaded first
 * when a row would overfill it or repeat one of its pixels. */
PERSP_SIMD_CLONES static void draw_small(span_ctx *sc, lane_batch *lb, uint64_t *busy, int ya, int yb,
                                         int x0, int x1)
{
    const persp_tri *t = sc->t;
    const int weights = !sc->ds->shade_is_texel;
    const float dq = (float)t->rat.g, dz = (float)t->zp[0];
    const float du = (float)t->rat.a, dv = (float)t->rat.d;
    const float da = weights ? (float)t->bary.a : 0.0f, db = weights ? (float)t->bary.d : 0.0f;
    /* A triangle that may not fit the batch's room starts a batch of its
     * own rather than being split over two: each segment is lit apart,
     * padded to whole vectors. */
    const int box = (yb - ya + 1) * (PERSP_MIN(x1, t->xmax) - PERSP_MAX(x0, t->xmin) + 1);
    if (lb->n && lb->n + box > PERSP_LANE_MAX) shade_lanes(sc, lb, busy);
    persp_row_walk walk;
    persp__row_walk_init(&walk, t, ya, yb - ya + 1, x0, x1);
    for (int y = ya; y <= yb; y++) {
        int lo, hi;
        if (!persp__row_walk_next(&walk, &lo, &hi)) continue;
        const int len = hi - lo + 1;
        const int32_t base = (y - sc->oy) * PERSP_TILE + (lo - sc->ox);
        /* PERSP_TILE is 64: the row's pixels are bits of one word. */
        const uint64_t mask = (len == 64 ? ~0ull : (1ull << len) - 1) << (base & 63);
        if (lb->n + len > PERSP_LANE_MAX || (busy[base >> 6] & mask)) shade_lanes(sc, lb, busy);
        if (lb->n == 0) {
            lb->nseg = 0;
            lb->ds = sc->ds;
            lb->row0 = lb->row1 = base >> 6;
        }
        lb->row0 = PERSP_MIN(lb->row0, base >> 6);
        lb->row1 = PERSP_MAX(lb->row1, base >> 6);
        if (lb->nseg == 0 || lb->seg_tri[lb->nseg - 1] != t) {
            lb->seg_start[lb->nseg] = lb->n;
            lb->seg_tri[lb->nseg++] = t;
        }
        busy[base >> 6] |= mask;
        /* The row's start values as shade_batch and exact_span compute them. */
        const double px = lo + 0.5, py = y + 0.5;
        const float U = (float)(t->rat.a * px + t->rat.b * py + t->rat.c);
        const float V = (float)(t->rat.d * px + t->rat.e * py + t->rat.f);
        const float Q = (float)(t->rat.g * px + t->rat.h * py + t->rat.i);
        const float Z = (float)(t->zp[0] * px + t->zp[1] * py + t->zp[2]);
        float A = 0.0f, B = 0.0f;
        if (weights) {
            A = (float)(t->bary.a * px + t->bary.b * py + t->bary.c);
            B = (float)(t->bary.d * px + t->bary.e * py + t->bary.f);
        }
        float *lq = lb->q + lb->n, *lz = lb->z + lb->n, *lu = lb->un + lb->n, *lv = lb->vn + lb->n;
        float *la = lb->an + lb->n, *lbb = lb->bn + lb->n;
        int32_t *li = lb->idx + lb->n;
        /* Whole groups of 16 lanes, the last running into the slack past
         * the row's end, so that the loop has no scalar remainder (rows
         * are a few pixels long). */
        for (int k0 = 0; k0 < len; k0 += LANE_GROUP)
            for (int j = 0; j < LANE_GROUP; j++) {
                const int k = k0 + j;
                const float fk = (float)k;
                lq[k] = Q + fk * dq;
                lz[k] = Z + fk * dz;
                lu[k] = U + fk * du;
                lv[k] = V + fk * dv;
                la[k] = A + fk * da;
                lbb[k] = B + fk * db;
                li[k] = base + k;
            }
        lb->n += len;
        lb->seg_start[lb->nseg] = lb->n;
    }
}

typedef struct area_tri {
    const persp_tri *t;
    int x0, x1;
} area_tri;

static int row_range_cb(const void *p, int y, int *lo, int *hi)
{
    const area_tri *a = p;
    return persp__tri_row_range(a->t, y, a->x0, a->x1, lo, hi);
}

static void add_ops(persp_opcount *to, const persp_opcount *from)
{
    to->div += from->div, to->mul += from->mul, to->add += from->add, to->cmp += from->cmp;
    to->pixels += from->pixels, to->spans += from->spans, to->triangles += from->triangles;
}

/* Copies one tile row (n 32-bit values) to the framebuffer. With stream
 * set, the whole 64-byte lines of the destination are written by
 * non-temporal stores: a framebuffer larger than the caches is then written
 * without first being read in (write-allocate), which halves its memory
 * traffic. Partial lines at the ends (rows not aligned to 64 bytes, shared
 * with the neighbouring tile) take ordinary stores: streaming part of a line
 * costs more than it saves. */
static void write_row(void *dst, const void *src, int n, int stream)
{
#if defined(__SSE2__)
    if (stream && ((uintptr_t)dst & 3u) == 0) {
        uint32_t *d = dst;
        const uint32_t *s = src;
        int head = (int)(((64u - ((uintptr_t)d & 63u)) & 63u) / 4u);
        if (head > n) head = n;
        memcpy(d, s, (size_t)head * 4);
        int body = (n - head) & ~15;
        for (int i = head; i < head + body; i += 4)
            _mm_stream_si128((__m128i *)(void *)(d + i), _mm_loadu_si128((const __m128i *)(const void *)(s + i)));
        memcpy(d + head + body, s + head + body, (size_t)(n - head - body) * 4);
        return;
    }
#else
    (void)stream;
#endif
    memcpy(dst, src, (size_t)n * 4);
}

PERSP_SIMD_CLONES static void raster_tile(void *user, int tile, int worker)
{
    tile_job *job = user;
    persp_frame *f = job->f;
    struct persp_render_cache *c = f->cache;
    const int tx = tile % job->tiles_x, ty = tile / job->tiles_x;
    const int x0 = tx * PERSP_TILE, y0 = ty * PERSP_TILE;
    const int x1 = PERSP_MIN(x0 + PERSP_TILE, f->fb->width) - 1;
    const int y1 = PERSP_MIN(y0 + PERSP_TILE, f->fb->height) - 1;
    const int tw = x1 - x0 + 1, th = y1 - y0 + 1;
    const size_t W = (size_t)f->fb->width;
    uint32_t *fcolor = (uint32_t *)(void *)f->fb->color;
    float *fdepth = f->fb->depth;
    if (c->bin_count[tile] == 0) {
        if (f->clear_pending) {
            for (int y = 0; y < th; y++) {
                uint32_t *cr = fcolor + (size_t)(y0 + y) * W + x0;
                float *dr = fdepth + (size_t)(y0 + y) * W + x0;
                for (int x = 0; x < tw; x++) cr[x] = f->clear_color;
                for (int x = 0; x < tw; x++) dr[x] = f->clear_depth;
            }
        }
        return;
    }
    _Alignas(64) uint32_t tcolor[PERSP_TILE * PERSP_TILE];
    _Alignas(64) float tdepth[PERSP_TILE * PERSP_TILE];
    if (f->clear_pending) {
        const uint32_t cc = f->clear_color;
        const float cd = f->clear_depth;
        for (int i = 0; i < PERSP_TILE * th; i++) tcolor[i] = cc;
        for (int i = 0; i < PERSP_TILE * th; i++) tdepth[i] = cd;
    } else {
        for (int y = 0; y < th; y++) {
            memcpy(tcolor + y * PERSP_TILE, fcolor + (size_t)(y0 + y) * W + x0, (size_t)tw * 4);
            memcpy(tdepth + y * PERSP_TILE, fdepth + (size_t)(y0 + y) * W + x0, (size_t)tw * 4);
        }
    }
    /* Counted in the tile and added to the worker's slot once: slots of
     * different workers share cache lines. */
    persp_render_stats local;
    memset(&local, 0, sizeof local);
    span_ctx sc = {.f = f, .stats = &local, .ops = f->count_ops ? &local.ops : NULL,
                   .color = tcolor, .depth = tdepth, .ox = x0, .oy = y0};
    lane_batch lb;
    lb.n = lb.nseg = 0;
    lb.ds = NULL;
    uint64_t busy[PERSP_TILE * PERSP_TILE / 64];
    memset(busy, 0, sizeof busy);
    const uint32_t *items = c->bin_items + c->bin_start[tile];
    const uint32_t nitems = c->bin_count[tile];
    for (uint32_t k = 0; k < nitems; k++) {
        const persp_tri *t = &c->tris[items[k]];
        if (k + PREFETCH_AHEAD < nitems) {
            /* A later record's first lines and the parts a lit span reads
             * beyond them (the barycentric planes and the vertex colours,
             * 350 and 600 bytes in) are fetched while this triangle is
             * drawn. */
            const char *next = (const char *)&c->tris[items[k + PREFETCH_AHEAD]];
            __builtin_prefetch(next);
            __builtin_prefetch(next + 64);
            __builtin_prefetch(next + 128);
            __builtin_prefetch(next + 192);
            __builtin_prefetch(next + offsetof(persp_tri, bary));
            __builtin_prefetch(next + offsetof(persp_tri, bary) + 40);
            __builtin_prefetch(next + offsetof(persp_tri, vattr) + PERSP_A_R * sizeof(float));
            __builtin_prefetch(next + offsetof(persp_tri, vattr) + (PERSP_A_COUNT + PERSP_A_R) * sizeof(float));
            __builtin_prefetch(next + offsetof(persp_tri, vattr) + (2 * PERSP_A_COUNT + PERSP_A_R) * sizeof(float));
        }
        sc.t = t;
        sc.ds = &c->states[t->state];
        sc.prep = t->prep != UINT32_MAX ? &c->preps[t->prep] : NULL;
        sc.tri_index = (int32_t)items[k];
        const persp_method *m = sc.ds->method.m;
        const int lanes = lanes_apply(sc.ds, t);
        if (lb.n && (!lanes || lb.ds != sc.ds)) shade_lanes(&sc, &lb, busy);
        if (m->traverse) {
            area_tri at = {t, x0, x1};
            persp_traverse_area area = {x0, PERSP_MAX(y0, t->ymin), x1, PERSP_MIN(y1, t->ymax),
                                        row_range_cb, &at};
            m->traverse(&t->rat, &sc.ds->method.params, sc.prep, &area, sink, &sc, sc.ops);
            continue;
        }
        const int ya = PERSP_MAX(y0, t->ymin), yb = PERSP_MIN(y1, t->ymax);
        if (lanes) {
            draw_small(&sc, &lb, busy, ya, yb, x0, x1);
            continue;
        }
        persp_row_walk walk;
        persp__row_walk_init(&walk, t, ya, yb - ya + 1, x0, x1);
        for (int y = ya; y <= yb; y++) {
            int lo, hi;
            if (!persp__row_walk_next(&walk, &lo, &hi)) continue;
            persp_frag_batch b = {.n = hi - lo + 1, .x0 = lo, .y = y};
            shade_batch(&sc, &b);
        }
    }
    if (lb.n) shade_lanes(&sc, &lb, busy);
    for (int y = 0; y < th; y++) {
        write_row(fcolor + (size_t)(y0 + y) * W + x0, tcolor + y * PERSP_TILE, tw, job->stream);
        write_row(fdepth + (size_t)(y0 + y) * W + x0, tdepth + y * PERSP_TILE, tw, job->stream);
    }
#if defined(__SSE2__)
    if (job->stream) _mm_sfence(); /* streaming stores are weakly ordered */
#endif
    c->worker_stats[worker].fragments += local.fragments;
    c->worker_stats[worker].pixels_written += local.pixels_written;
    add_ops(&c->worker_stats[worker].ops, &local.ops);
}

persp_status persp__frame_flush(persp_frame *f) { return frame_flush_batch(f, 1); }

/* Draws the batch of set-up triangles; last: the frame's final batch. */
static persp_status frame_flush_batch(persp_frame *f, int last)
{
    struct persp_render_cache *c = f->cache;
    persp_context *ctx = f->ctx;
    const int tiles_x = (f->fb->width + PERSP_TILE - 1) / PERSP_TILE;
    const int tiles_y = (f->fb->height + PERSP_TILE - 1) / PERSP_TILE;
    const size_t tiles = (size_t)tiles_x * (size_t)tiles_y;
    const size_t u32 = sizeof(uint32_t);
    if (persp__grow(ctx, (void **)&c->bin_count, &c->bin_cap, tiles, u32) != PERSP_OK ||
        persp__grow(ctx, (void **)&c->bin_start, &c->start_cap, tiles, u32) != PERSP_OK)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    memset(c->bin_count, 0, tiles * sizeof(uint32_t));
    /* Two passes: count triangles per tile, then place their indices in
     * submission order (the order that makes results thread-independent). */
    size_t total = 0;
    for (size_t i = 0; i < f->tri_count; i++) {
        const struct tri_tiles *b = &c->tiles[i];
        const int tx0 = b->tx0, tx1 = b->tx1, ty0 = b->ty0, ty1 = b->ty1;
        for (int ty = ty0; ty <= ty1; ty++)
            for (int tx = tx0; tx <= tx1; tx++) c->bin_count[ty * tiles_x + tx]++;
        total += (size_t)(tx1 - tx0 + 1) * (size_t)(ty1 - ty0 + 1);
    }
    if (total > UINT32_MAX)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "render: too many triangle-tile pairs");
    if (persp__grow(ctx, (void **)&c->bin_items, &c->item_cap, total ? total : 1,
                    sizeof(uint32_t)) != PERSP_OK)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    uint32_t acc = 0;
    if (f->batch_adapt && f->tri_count >= f->batch_base) {
        size_t touched = 0;
        for (size_t k = 0; k < tiles; k++) touched += c->bin_count[k] > 0;
        const size_t tile_bytes = 2u * PERSP_TILE * PERSP_TILE * (sizeof(uint32_t) + sizeof(float));
        /* Against a base batch's records, so that a doubled batch, which
         * touches at least as many tiles, stays doubled. */
        f->batch = touched * tile_bytes > f->batch_base * sizeof *c->tris
                       ? PERSP_MIN(2 * f->batch_base, PERSP_FRAME_BATCH_MAX)
                       : f->batch_base;
    }
    for (size_t k = 0; k < tiles; k++) {
        c->bin_start[k] = acc;
        acc += c->bin_count[k];
        c->bin_count[k] = 0;
    }
    for (size_t i = 0; i < f->tri_count; i++) {
        const struct tri_tiles *b = &c->tiles[i];
        const int tx0 = b->tx0, tx1 = b->tx1, ty0 = b->ty0, ty1 = b->ty1;
        for (int ty = ty0; ty <= ty1; ty++)
            for (int tx = tx0; tx <= tx1; tx++) {
                size_t k = (size_t)ty * (size_t)tiles_x + (size_t)tx;
                c->bin_items[c->bin_start[k] + c->bin_count[k]++] = (uint32_t)i;
            }
    }
    int workers = persp__pool_workers(ctx);
    if (persp__grow(ctx, (void **)&c->worker_stats, &c->worker_cap, (size_t)workers,
                    sizeof *c->worker_stats) != PERSP_OK)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
    memset(c->worker_stats, 0, (size_t)workers * sizeof *c->worker_stats);
    /* Streaming stores only for the last batch: an earlier batch's tiles are
     * read back by the next batch that touches them, from the caches if
     * they were written there. */
    tile_job job = {f, tiles_x, workers,
                    last && (size_t)f->fb->width * (size_t)f->fb->height * 8u > PERSP_STREAM_BYTES};
    persp_status st = persp__pool_run(ctx, (int)tiles, raster_tile, &job);
    if (st != PERSP_OK)
        return persp__fail(ctx, st, "render: cannot start worker threads: %s",
                           persp_status_string(st));
    f->clear_pending = 0;
    f->stats.triangles_drawn += f->tri_count - f->gap_count;
    f->gap_count = 0;
    for (int w = 0; w < workers; w++) {
        f->stats.fragments += c->worker_stats[w].fragments;
        f->stats.pixels_written += c->worker_stats[w].pixels_written;
        add_ops(&f->stats.ops, &c->worker_stats[w].ops);
    }
    return PERSP_OK;
}

const persp_tri *persp__frame_tris(const persp_frame *f) { return f->cache->tris; }

const persp_draw_state *persp__frame_state(const persp_frame *f, uint32_t index)
{
    return &f->cache->states[index];
}
