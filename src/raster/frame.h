/* One frame being assembled (src/raster/frame.c) and rasterized (tiles.c). */
#ifndef PERSP_RASTER_FRAME_H
#define PERSP_RASTER_FRAME_H

#include "geom/scene.h"
#include "raster/raster.h"
#include "texture/texture.h"

struct persp_render_cache;

/* How shade_lanes packs a lane batch's live lanes together (tiles.c,
 * pack_live): one lane at a time, eight by a permutation, sixteen by
 * compress. The portable loop stays for tests to compare with
 * (persp_context.pack_portable) and where the CPU has no AVX2. */
enum { PERSP_PACK_PORTABLE, PERSP_PACK_AVX2, PERSP_PACK_AVX512 };

typedef struct persp_frame {
    persp_context *ctx;
    persp_framebuffer *fb;
    persp_depth_mode depth_mode;
    struct persp_render_cache *cache;
    size_t state_count, tri_count, prep_count;
    size_t gap_count; /* slots of tris that hold no triangle (frame.c, slabs in place) */
    size_t batch; /* records drawn at once without a capture (frame.c, frame_batch_limit) */
    size_t batch_base; /* batch before adapting to how spread the last one was (frame.c) */
    int batch_adapt;
    int pack; /* how lane batches are packed (tiles.c pack_live): PERSP_PACK_* */
    persp_render_stats stats;
    persp_capture *capture; /* non-NULL: record per-pixel triangle and u, v */
    persp_mat4 proj;        /* projection of the scene's camera */
    /* Clear deferred to the tiles: each tile fills its own rectangle just
     * before drawing into it, while it is in cache, and in parallel. */
    int count_ops; /* methods count into stats.ops */
    int clear_pending;
    uint32_t clear_color;
    float clear_depth;
    /* Sort first (src/render/sort_first.c): with regions > 0 the frame
     * draws only the tiles tile0 to tile1 - 1 (in row-major order; run,
     * the same as rows and columns), and sets up only the triangles whose
     * box reaches one of them; foreign counts those it set up whose box's
     * first tile comes before tile0 (another region's), so that the
     * regions' triangles_drawn add up to the whole frame's. */
    int regions, tile0, tile1;
    persp_tile_run run;
    size_t foreign;
} persp_frame;

persp_status persp__frame_begin(persp_context *ctx, persp_framebuffer *fb, persp_depth_mode mode,
                                persp_frame *f);
/* fb checked as a frame's target, and the context's buffers kept between
 * frames in *out, made at the first call. */
persp_status persp__frame_cache(persp_context *ctx, const persp_framebuffer *fb, struct persp_render_cache **out);
/* Clears fb to rgba (NULL: opaque black) and the far depth of the frame's
 * mode, tile by tile during persp__frame_flush. */
void persp__frame_clear(persp_frame *f, const uint8_t rgba[4]);
persp_status persp__frame_add_state(persp_frame *f, const persp_draw_state *s, uint32_t *index);
/* Vertex stage, clipping and setup of one mesh. uv (2 per vertex) replaces
 * the vertices' own coordinates when non-NULL (texture-coordinate generation). */
/* Room for 2 floats a vertex of a mesh about to be added, for its
 * generated texture coordinates (the uv of persp__frame_add_mesh, which
 * reads them before it returns, so one buffer serves every mesh); NULL
 * when out of memory. */
float *persp__frame_uv_buffer(persp_frame *f, size_t vertices);
persp_status persp__frame_add_mesh(persp_frame *f, const persp_mesh *mesh, const persp_mat4 *model,
                                   const persp_mat4 *view, const persp_mat4 *proj, uint32_t state,
                                   const float *uv, int cull /* PERSP_CULL_* */);
persp_status persp__frame_flush(persp_frame *f);
/* The set-up triangles of the frame so far (valid until the next frame). */
const persp_tri *persp__frame_tris(const persp_frame *f);
/* With a capture: the vertices of each of those triangles' rational form
 * (NULL without one). */
const persp_rational_vertices *persp__frame_fits(const persp_frame *f);
const persp_draw_state *persp__frame_state(const persp_frame *f, uint32_t index);

#endif
