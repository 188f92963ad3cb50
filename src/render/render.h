/* Scene rendering internals shared with the analysis tools. */
#ifndef PERSP_RENDER_RENDER_H
#define PERSP_RENDER_RENDER_H

#include "core/shared.h"

#include "pipeline/types.h"

/* Renders scene at width × height into cap (see persp_capture). */
PERSP_INTERNAL persp_status persp__render_capture(persp_context *ctx, const persp_scene *scene,
                                                  const persp_render_desc *desc, int width,
                                                  int height, persp_capture *cap);
PERSP_INTERNAL void persp__capture_free(persp_context *ctx, persp_capture *cap);

struct persp_frame;
/* The settings of desc against their ranges, each named in the error. */
persp_status persp__check_render_desc(persp_context *ctx, const persp_render_desc *desc);
/* Draws scene into fb through f (begun here), with a capture when cap is
 * not NULL; with regions > 0 only tiles tile0 to tile1 - 1 in row-major
 * order (one of that many regions drawn sort first,
 * src/render/sort_first.c). */
persp_status persp__render_frame(persp_context *ctx, const persp_scene *scene, const persp_render_desc *desc,
                                 persp_framebuffer *fb, struct persp_frame *f, persp_capture *cap, int regions,
                                 int tile0, int tile1);
/* Draws the frame sort first when desc and the context's workers ask for
 * it (persp_render_desc.sort_first): returns 1 with the render's status in
 * *st (and its counts in stats, when not NULL), or 0 where the caller
 * draws it sort middle (including when a region ran out of memory, which
 * sort middle, holding one set of buffers, may not). */
int persp__render_sort_first(persp_context *ctx, const persp_scene *scene, const persp_render_desc *desc,
                             persp_framebuffer *fb, persp_render_stats *stats, persp_status *st);

#endif
