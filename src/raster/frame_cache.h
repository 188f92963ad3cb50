/* The renderer's buffers kept between frames (struct persp_render_cache),
 * shared by the geometry and batching of frame.c and the tile
 * rasterization of tiles.c (internal). */
#ifndef PERSP_RASTER_FRAME_CACHE_H
#define PERSP_RASTER_FRAME_CACHE_H

#include "raster/frame.h"

#include <stdint.h>

/* Regions at most in a frame drawn sort first (src/render/sort_first.c):
 * beyond a few, each worker's copy of the vertex stage and of the triangle
 * loop for what reaches its rows outweighs its share of the rest. */
#define PERSP_SORT_FIRST_MAX 16

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
 * triangle instead of a cache line of each 560-byte record. */
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
    /* With a capture: the vertices of each triangle's rational form (the
     * records keep the planes only), by the triangle's index in the frame. */
    persp_rational_vertices *fits;
    size_t fit_cap;
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
    uint8_t *lazy; /* per vertex: Gouraud's front colour left to set-up (frame.c, front_colours) */
    size_t lazy_cap;
    uint8_t *cluster_culled; /* per cluster of the mesh being added: culled whole */
    size_t cluster_cap;
    uint8_t *vertex_need; /* per block of the vertex stage: some triangle not culled uses it */
    size_t need_cap;
    persp_tri *slab_tris; /* records set up by the worker threads */
    size_t slab_cap;
    struct setup_slab *slabs;
    size_t slabs_cap;
    uint32_t *bin_count, *bin_start, *bin_items;
    size_t bin_cap, start_cap, item_cap;
    uint32_t *bin_part; /* binning tasks × tiles: each task's count, then its offset */
    size_t part_cap;
    persp_draw_state *states;
    size_t state_cap;
    persp_render_stats *worker_stats;
    size_t worker_cap;
    float *uv; /* generated texture coordinates of the mesh being added (persp__frame_uv_buffer) */
    size_t uv_cap;
    /* Sort first (src/render/sort_first.c): a context a region, kept with
     * its buffers between frames; the latest cross-core probe; the regions'
     * first tiles in row-major order (split[k], split[regions] the frame's
     * tiles) for split_regions and split_tiles, balanced on the last
     * frame's times. */
    persp_context **region_ctx;
    size_t region_cap, region_count;
    double probe_ns, probe_at;
    int split[PERSP_SORT_FIRST_MAX + 1];
    int split_regions, split_tiles;
};

/* Draws the frame's binned batch: every tile on the worker threads, then
 * the workers' counts into f->stats. last: the frame's final batch (its
 * tiles may then be written with streaming stores). */
persp_status persp__frame_draw_tiles(persp_frame *f, int tiles_x, size_t tiles, int last);

/* Whether the small-triangle lane path samples with this filter. */
int persp__lane_filter(persp_filter filter);

#endif
