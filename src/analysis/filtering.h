/* Texture-filter accuracy internals (src/analysis/filtering.c). */
#ifndef PERSP_ANALYSIS_FILTERING_H
#define PERSP_ANALYSIS_FILTERING_H

#include "persp_analysis.h"

/* The supersampled reference of a scene at width × height: samples ×
 * samples points per pixel (at the centres of a regular sub-grid) of a
 * screen-pipeline render with the exact method and bilinear filtering on
 * level 0, box-filtered; out receives width·height·4 floats (RGBA, 0..255,
 * row 0 = bottom). The high-resolution image is rendered in tiles of at most
 * tile × tile output pixels by composing the projection with a window
 * transform, so memory stays bounded. */
persp_status persp__filter_reference(persp_context *ctx, const persp_scene *scene, int width,
                                     int height, int samples, int tile, float *out);

/* Builds the tilted-plane case scene "tilt-N" (N degrees about the x axis). */
persp_status persp__tilt_scene(persp_context *ctx, double degrees, persp_scene **out);

/* Mean SSIM (Wang et al. 2004) of two luma images over 8×8 windows at
 * stride 4, counting only windows with at least one pixel whose mask is
 * nonzero (mask NULL: all). */
double persp__ssim(const float *a, const float *b, const uint8_t *mask, int w, int h);

#endif
