/* Renderer internals shared with the analysis tools. */
#ifndef PERSP_RASTER_RENDER_H
#define PERSP_RASTER_RENDER_H

#include "geom/scene.h"
#include "interp/method.h"

/* Per-pixel capture of a scene render for analysis (persp accuracy on a
 * built-in scene): for every pixel the index of the triangle visible there
 * (-1: background) and the s1 = u, s2 = v the method produced; rats[i] is
 * the rational form (Heckbert's coefficients, texture coordinates in
 * normalised units) of triangle i. All arrays are allocated with the
 * context's allocator; release with persp__capture_free. */
typedef struct persp_capture {
    int width, height;
    int32_t *tri;  /* width*height, row 0 = bottom */
    float *s1, *s2;
    persp_rational *rats;
    size_t rat_count;
    persp_opcount ops; /* the method's operations, with desc->count_ops */
} persp_capture;

persp_status persp__render_capture(persp_context *ctx, const persp_scene *scene,
                                   const persp_render_desc *desc, int width, int height,
                                   persp_capture *cap);
void persp__capture_free(persp_context *ctx, persp_capture *cap);

#endif
