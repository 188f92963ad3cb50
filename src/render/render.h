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

#endif
