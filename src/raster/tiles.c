/*
 * Rasterization of a batch of set-up triangles (docs/DESIGN.md, "tiles in
 * parallel"): each 64×64 tile, on a worker thread, draws the triangles
 * binned to it in submission order into tile-local colour and depth
 * buffers (spans, the small-triangle lane batches, or a method's own
 * traversal) and writes them to the framebuffer once. Tiles own disjoint
 * pixels, so the image is the same for any number of threads. The
 * geometry that fills the batch, and its binning, are in frame.c.
 */
#include "core/fmath.h"
#include "core/internal.h"
#include "core/pool.h"
#include "interp/methods.h"
#include "raster/frame.h"
#include "raster/frame_cache.h"
#include "raster/raster.h"
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
    /* The pixels the method computed coordinates for (persp_opcount.pixels):
     * a traversal every fragment it emits, a span method only the spans
     * with a pixel in front. */
    if (sc->ops && b->s1) sc->ops->pixels += (uint64_t)n, sc->ops->spans++;
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
        if (sc->ops) sc->ops->pixels += (uint64_t)n, sc->ops->spans++;
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
    /* persp draws opaque surfaces (docs/SCENES.md, "Images"): alpha is no coverage. */
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
 * docs/PERFORMANCE_HISTORY.md), 128 against 64 (2k: unlit −6 %, gouraud-pc −6 %,
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
int persp__lane_filter(persp_filter filter)
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
PERSP_TARGET_AVX512 static void pack_lanes_avx512(lane_batch *lb, int n, const int32_t *live, uint64_t *bits,
                                                  int narr)
{
    float *const arr[6] = {lb->q, lb->z, lb->un, lb->vn, lb->an, lb->bn};
    int m = 0;
    for (int k = 0; k < n; k += LANE_GROUP) {
        const __m512i lv = _mm512_loadu_si512((const void *)(live + k));
        __mmask16 mk = _mm512_test_epi32_mask(lv, lv);
        if (n - k < LANE_GROUP) mk &= (__mmask16)((1u << (n - k)) - 1u);
        bits[k >> 6] |= (uint64_t)mk << (k & 63);
        for (int a = 0; a < narr; a++)
            _mm512_storeu_ps(arr[a] + m, _mm512_maskz_compress_ps(mk, _mm512_loadu_ps(arr[a] + k)));
        _mm512_storeu_si512((void *)(lb->idx + m),
                            _mm512_maskz_compress_epi32(mk, _mm512_loadu_si512((const void *)(lb->idx + k))));
        m += __builtin_popcount(mk);
    }
}

/* Without compress, eight lanes at a time by a permutation: entry m of this
 * table lists the set bits of the 8-bit mask m in increasing order, 4 bits
 * each from the lowest (the rest 0), the vpermd indices that move mask m's
 * lanes to the front. The portable loop moves one lane at a time, 9
 * instructions a lane; this is about 3 (soup gouraud-pc, avx2: pack_live
 * was 41 of its 1 201 instructions a pixel). Stores as pack_lanes_avx512. */
static const uint32_t pack_perm[256] = {
    0x00000000u, 0x00000000u, 0x00000001u, 0x00000010u, 0x00000002u, 0x00000020u, 0x00000021u, 0x00000210u,
    0x00000003u, 0x00000030u, 0x00000031u, 0x00000310u, 0x00000032u, 0x00000320u, 0x00000321u, 0x00003210u,
    0x00000004u, 0x00000040u, 0x00000041u, 0x00000410u, 0x00000042u, 0x00000420u, 0x00000421u, 0x00004210u,
    0x00000043u, 0x00000430u, 0x00000431u, 0x00004310u, 0x00000432u, 0x00004320u, 0x00004321u, 0x00043210u,
    0x00000005u, 0x00000050u, 0x00000051u, 0x00000510u, 0x00000052u, 0x00000520u, 0x00000521u, 0x00005210u,
    0x00000053u, 0x00000530u, 0x00000531u, 0x00005310u, 0x00000532u, 0x00005320u, 0x00005321u, 0x00053210u,
    0x00000054u, 0x00000540u, 0x00000541u, 0x00005410u, 0x00000542u, 0x00005420u, 0x00005421u, 0x00054210u,
    0x00000543u, 0x00005430u, 0x00005431u, 0x00054310u, 0x00005432u, 0x00054320u, 0x00054321u, 0x00543210u,
    0x00000006u, 0x00000060u, 0x00000061u, 0x00000610u, 0x00000062u, 0x00000620u, 0x00000621u, 0x00006210u,
    0x00000063u, 0x00000630u, 0x00000631u, 0x00006310u, 0x00000632u, 0x00006320u, 0x00006321u, 0x00063210u,
    0x00000064u, 0x00000640u, 0x00000641u, 0x00006410u, 0x00000642u, 0x00006420u, 0x00006421u, 0x00064210u,
    0x00000643u, 0x00006430u, 0x00006431u, 0x00064310u, 0x00006432u, 0x00064320u, 0x00064321u, 0x00643210u,
    0x00000065u, 0x00000650u, 0x00000651u, 0x00006510u, 0x00000652u, 0x00006520u, 0x00006521u, 0x00065210u,
    0x00000653u, 0x00006530u, 0x00006531u, 0x00065310u, 0x00006532u, 0x00065320u, 0x00065321u, 0x00653210u,
    0x00000654u, 0x00006540u, 0x00006541u, 0x00065410u, 0x00006542u, 0x00065420u, 0x00065421u, 0x00654210u,
    0x00006543u, 0x00065430u, 0x00065431u, 0x00654310u, 0x00065432u, 0x00654320u, 0x00654321u, 0x06543210u,
    0x00000007u, 0x00000070u, 0x00000071u, 0x00000710u, 0x00000072u, 0x00000720u, 0x00000721u, 0x00007210u,
    0x00000073u, 0x00000730u, 0x00000731u, 0x00007310u, 0x00000732u, 0x00007320u, 0x00007321u, 0x00073210u,
    0x00000074u, 0x00000740u, 0x00000741u, 0x00007410u, 0x00000742u, 0x00007420u, 0x00007421u, 0x00074210u,
    0x00000743u, 0x00007430u, 0x00007431u, 0x00074310u, 0x00007432u, 0x00074320u, 0x00074321u, 0x00743210u,
    0x00000075u, 0x00000750u, 0x00000751u, 0x00007510u, 0x00000752u, 0x00007520u, 0x00007521u, 0x00075210u,
    0x00000753u, 0x00007530u, 0x00007531u, 0x00075310u, 0x00007532u, 0x00075320u, 0x00075321u, 0x00753210u,
    0x00000754u, 0x00007540u, 0x00007541u, 0x00075410u, 0x00007542u, 0x00075420u, 0x00075421u, 0x00754210u,
    0x00007543u, 0x00075430u, 0x00075431u, 0x00754310u, 0x00075432u, 0x00754320u, 0x00754321u, 0x07543210u,
    0x00000076u, 0x00000760u, 0x00000761u, 0x00007610u, 0x00000762u, 0x00007620u, 0x00007621u, 0x00076210u,
    0x00000763u, 0x00007630u, 0x00007631u, 0x00076310u, 0x00007632u, 0x00076320u, 0x00076321u, 0x00763210u,
    0x00000764u, 0x00007640u, 0x00007641u, 0x00076410u, 0x00007642u, 0x00076420u, 0x00076421u, 0x00764210u,
    0x00007643u, 0x00076430u, 0x00076431u, 0x00764310u, 0x00076432u, 0x00764320u, 0x00764321u, 0x07643210u,
    0x00000765u, 0x00007650u, 0x00007651u, 0x00076510u, 0x00007652u, 0x00076520u, 0x00076521u, 0x00765210u,
    0x00007653u, 0x00076530u, 0x00076531u, 0x00765310u, 0x00076532u, 0x00765320u, 0x00765321u, 0x07653210u,
    0x00007654u, 0x00076540u, 0x00076541u, 0x00765410u, 0x00076542u, 0x00765420u, 0x00765421u, 0x07654210u,
    0x00076543u, 0x00765430u, 0x00765431u, 0x07654310u, 0x00765432u, 0x07654320u, 0x07654321u, 0x76543210u,
};

PERSP_TARGET_AVX2 static void pack_lanes_avx2(lane_batch *lb, int n, const int32_t *live, uint64_t *bits, int narr)
{
    float *const arr[6] = {lb->q, lb->z, lb->un, lb->vn, lb->an, lb->bn};
    const __m256i nibble = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28), three_bits = _mm256_set1_epi32(7);
    int m = 0;
    for (int k = 0; k < n; k += 8) {
        const __m256i lv = _mm256_slli_epi32(_mm256_loadu_si256((const __m256i *)(const void *)(live + k)), 31);
        unsigned mk = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(lv));
        if (n - k < 8) mk &= (1u << (n - k)) - 1u;
        bits[k >> 6] |= (uint64_t)mk << (k & 63);
        const __m256i perm =
            _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32((int)pack_perm[mk]), nibble), three_bits);
        for (int a = 0; a < narr; a++)
            _mm256_storeu_ps(arr[a] + m, _mm256_permutevar8x32_ps(_mm256_loadu_ps(arr[a] + k), perm));
        _mm256_storeu_si256((__m256i *)(void *)(lb->idx + m),
                            _mm256_permutevar8x32_epi32(
                                _mm256_loadu_si256((const __m256i *)(const void *)(lb->idx + k)), perm));
        m += __builtin_popcount(mk);
    }
}
#endif

_Static_assert(PERSP_LANE_MAX % LANE_GROUP == 0, "lane batches hold whole groups");

/* Live lanes before lane p, from the batch's bitmap of live lanes. Inlined,
 * with pack_live, into shade_lanes, whose AVX2 clone counts bits with
 * popcnt, where the baseline called libgcc's __popcountdi2 for every
 * segment (0.8 % of a gouraud-pc frame of the soup). */
static PERSP_ALWAYS_INLINE int live_before(const uint64_t *bits, int p)
{
    int c = 0;
    for (int w = 0; w < p >> 6; w++) c += __builtin_popcountll(bits[w]);
    if (p & 63) c += __builtin_popcountll(bits[p >> 6] & ((1ull << (p & 63)) - 1));
    return c;
}

static PERSP_ALWAYS_INLINE int pack_live(lane_batch *lb, int n, int32_t *live, int pack, int weights)
{
    int nseg = 0, m = 0;
#if PERSP_HAVE_ISA_VARIANTS
    if (pack) {
        uint64_t bits[PERSP_LANE_MAX / 64 + 1] = {0};
        if (pack == PERSP_PACK_AVX512)
            pack_lanes_avx512(lb, n, live, bits, weights ? 6 : 4);
        else
            pack_lanes_avx2(lb, n, live, bits, weights ? 6 : 4);
        for (int s = 0; s < lb->nseg; s++) {
            const int end = live_before(bits, lb->seg_start[s + 1]);
            if (end > m) {
                lb->seg_start[nseg] = m;
                lb->seg_tri[nseg++] = lb->seg_tri[s];
            }
            m = end;
        }
    } else
#endif
    {
        /* Segment by segment, so that the live lanes before each segment's
         * end are the count so far (a bitmap of live lanes cost 5 of the
         * soup's 1 300 instructions a pixel, gouraud-pc, with AVX2). */
        (void)pack;
        (void)weights;
        (void)n; /* the segments' ends bound the lanes */
        int j = 0, k = 0;
        for (int s = 0; s < lb->nseg; s++) {
            const int end = lb->seg_start[s + 1];
            for (; k < end; k++) {
                lb->q[j] = lb->q[k];
                lb->z[j] = lb->z[k];
                lb->un[j] = lb->un[k];
                lb->vn[j] = lb->vn[k];
                lb->an[j] = lb->an[k];
                lb->bn[j] = lb->bn[k];
                lb->idx[j] = lb->idx[k];
                j += live[k];
            }
            if (j > m) {
                lb->seg_start[nseg] = m;
                lb->seg_tri[nseg++] = lb->seg_tri[s];
            }
            m = j;
        }
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
     * (−5 %) but more than by the AVX2 permutation (soup unlit 895 → 900
     * instructions a pixel); lit, it costs its lighting too, so a lit batch
     * is always packed and the shaders below light every lane they are
     * given. */
    if (any < n && (!ds->shade_is_texel || f->pack == PERSP_PACK_AVX512))
        n = pack_live(lb, n, live, f->pack, !ds->shade_is_texel);
    /* w1, w2, texel and out have PERSP_SHADE_GROUP lanes of slack, zero
     * where read: persp__shade_gouraud_lanes runs whole groups. */
    float u[PERSP_LANE_MAX], v[PERSP_LANE_MAX], rq[PERSP_LANE_MAX];
    float w1[PERSP_LANE_MAX + PERSP_SHADE_GROUP], w2[PERSP_LANE_MAX + PERSP_SHADE_GROUP];
    const int weights = !ds->shade_is_texel;
    /* exact_span: rq = 1 / (Q + k·dQ), which is q[k]; one for u, v and the
     * weights, as persp__exact_span_pair. */
    for (int k = 0; k < n; k++) {
        rq[k] = 1.0f / q[k];
        u[k] = lb->un[k] * rq[k];
        v[k] = lb->vn[k] * rq[k];
    }
    uint32_t texel[PERSP_LANE_MAX + PERSP_SHADE_GROUP], out[PERSP_LANE_MAX + PERSP_SHADE_GROUP];
    if (weights) {
        for (int k = 0; k < n; k++) {
            w1[k] = lb->an[k] * rq[k];
            w2[k] = lb->bn[k] * rq[k];
        }
        for (int k = n; k < n + PERSP_SHADE_GROUP; k++) w1[k] = w2[k] = 0.0f, texel[k] = 0;
    }
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
    const int32_t *idx = lb->idx;
    if (n == any) {
        /* Every lane passed (or was packed so): no test per lane. */
        if (ds->depth_write)
            for (int k = 0; k < n; k++) {
                color[idx[k]] = out[k];
                depth[idx[k]] = dvals[k];
            }
        else
            for (int k = 0; k < n; k++) color[idx[k]] = out[k];
    } else {
        for (int k = 0; k < n; k++) {
            if (!live[k]) continue;
            color[idx[k]] = out[k];
            if (ds->depth_write) depth[idx[k]] = dvals[k];
        }
    }
    sc->stats->pixels_written += (uint64_t)any;
}

/* Trims pixels [*a, *b] of a tile row (at most PERSP_TILE) to its first
 * and last in front of the depth row drow: value D + k·dD against drow[k],
 * nearer when greater (invw) or less, the floats shade_lanes tests. On
 * SSE2, four pixels a compare and their bits by movemask: under overdraw
 * most rows of the soup are hidden whole, and a pixel at a time the scan
 * was 4 % of a frame. It reads up to three floats past the row, which the
 * tile's depth buffer has (TRIM_SLACK). *a > *b when none is in front. */
#define TRIM_SLACK 4
static inline int in_front(float v, float d, int invw) { return invw ? v > d : v < d; }
static inline void trim_row(const float *drow, float D, float dD, int invw, int *a, int *b)
{
    const int len = *b + 1;
#if defined(__SSE2__)
    /* A long row in front at both ends (most rows of large triangles) is
     * kept whole after two tests; a short one takes the two compares
     * below without those branches, which the soup's rows (a few pixels,
     * hidden or not at random) mispredicted (+2 % there). */
    if (len > 8) {
        const float first = D + 0.0f * dD, last = D + (float)(len - 1) * dD;
        if (in_front(first, drow[0], invw) && in_front(last, drow[len - 1], invw)) return;
    }
    const __m128 vd = _mm_set1_ps(D), vdd = _mm_set1_ps(dD);
    __m128i kk = _mm_setr_epi32(0, 1, 2, 3);
    uint64_t pass = 0;
    for (int k = 0; k < len; k += 4) {
        const __m128 v = _mm_add_ps(vd, _mm_mul_ps(_mm_cvtepi32_ps(kk), vdd));
        const __m128 d = _mm_loadu_ps(drow + k);
        const __m128 in_front = invw ? _mm_cmpgt_ps(v, d) : _mm_cmplt_ps(v, d);
        pass |= (uint64_t)(unsigned)_mm_movemask_ps(in_front) << k;
        kk = _mm_add_epi32(kk, _mm_set1_epi32(4));
    }
    if (len < 64) pass &= (1ull << len) - 1;
    if (!pass) {
        *a = len, *b = len - 1;
        return;
    }
    *a = __builtin_ctzll(pass);
    *b = 63 - __builtin_clzll(pass);
#else
    int lo = 0, hi = len - 1;
    while (lo <= hi && !in_front(D + (float)lo * dD, drow[lo], invw)) lo++;
    while (hi > lo && !in_front(D + (float)hi * dD, drow[hi], invw)) hi--;
    *a = lo, *b = hi;
#endif
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
    const int depth_test = sc->ds->depth_test, invw = sc->f->depth_mode == PERSP_DEPTH_INVW;
    uint64_t trimmed = 0;
    for (int y = ya; y <= yb; y++) {
        int lo, hi;
        if (!persp__row_walk_next(&walk, &lo, &hi)) continue;
        const int32_t row = (y - sc->oy) * PERSP_TILE + (lo - sc->ox);
        /* The row's start values as shade_batch and exact_span compute them. */
        const double px = lo + 0.5, py = y + 0.5;
        const float Q = (float)(t->rat.g * px + t->rat.h * py + t->rat.i);
        const float Z = (float)(t->zp[0] * px + t->zp[1] * py + t->zp[2]);
        /* The row is trimmed to its first and last pixel in front of the
         * tile's depth buffer, with the lane values shade_lanes tests (the
         * same floats). A pixel a pending lane of the batch covers may be
         * drawn nearer before this row is shaded, never farther (the test
         * is strict and a passing pixel writes its own depth), so a pixel
         * hidden now stays hidden: the trim drops only lanes that shade_lanes
         * would find dead. Under overdraw whole rows go (the soup: most). */
        int a = 0, b = hi - lo;
        if (depth_test) {
            trim_row(sc->depth + row, invw ? Q : Z, invw ? dq : dz, invw, &a, &b);
            /* Trimmed pixels are fragments that failed the depth test
             * (counted here: busy may alias the statistics). */
            trimmed += (uint64_t)(hi - lo + 1 - (a > b ? 0 : b - a + 1));
            if (a > b) continue;
        }
        const int len = b - a + 1;
        const int32_t base = row + a;
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
        const float U = (float)(t->rat.a * px + t->rat.b * py + t->rat.c);
        const float V = (float)(t->rat.d * px + t->rat.e * py + t->rat.f);
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
        /* Unlit, nothing reads the weights' numerators (nor moves them:
         * pack_live packs lit batches, or on AVX-512 only the arrays read). */
        if (weights)
            for (int k0 = 0; k0 < len; k0 += LANE_GROUP)
                for (int j = 0; j < LANE_GROUP; j++) {
                    const int k = k0 + j;
                    const float fk = (float)(a + k);
                    lq[k] = Q + fk * dq;
                    lz[k] = Z + fk * dz;
                    lu[k] = U + fk * du;
                    lv[k] = V + fk * dv;
                    la[k] = A + fk * da;
                    lbb[k] = B + fk * db;
                    li[k] = base + k;
                }
        else
            for (int k0 = 0; k0 < len; k0 += LANE_GROUP)
                for (int j = 0; j < LANE_GROUP; j++) {
                    const int k = k0 + j;
                    const float fk = (float)(a + k);
                    lq[k] = Q + fk * dq;
                    lz[k] = Z + fk * dz;
                    lu[k] = U + fk * du;
                    lv[k] = V + fk * dv;
                    li[k] = base + k;
                }
        lb->n += len;
        lb->seg_start[lb->nseg] = lb->n;
    }
    sc->stats->fragments += trimmed;
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
    /* Another region's tile (sort-first): its frame clears and draws it. */
    if (f->regions && (tile < f->tile0 || tile >= f->tile1)) return;
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
    _Alignas(64) float tdepth[PERSP_TILE * PERSP_TILE + TRIM_SLACK];
    for (int i = 0; i < TRIM_SLACK; i++) tdepth[PERSP_TILE * PERSP_TILE + i] = 0.0f;
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
             * 232 and 336 bytes in) are fetched while this triangle is
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

persp_status persp__frame_draw_tiles(persp_frame *f, int tiles_x, size_t tiles, int last)
{
    struct persp_render_cache *c = f->cache;
    persp_context *ctx = f->ctx;
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
    for (int w = 0; w < workers; w++) {
        f->stats.fragments += c->worker_stats[w].fragments;
        f->stats.pixels_written += c->worker_stats[w].pixels_written;
        add_ops(&f->stats.ops, &c->worker_stats[w].ops);
    }
    return PERSP_OK;
}
