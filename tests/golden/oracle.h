/*
 * Oracles of the golden images: what each image should be, computed without
 * persp's renderer, so that a golden is more than a snapshot of persp's own
 * output (docs/DESIGN.md, "Testing", layer 3). Each builds on the
 * double-precision arbiter of the differential test (tests/diff/diffref.c),
 * which reaches the scene through the public API only (camera, meshes,
 * texture coordinates with texgen applied, mip levels) and computes what
 * OpenGL 4.6 defines a pixel to be; it needs no OpenGL library.
 */
#ifndef PERSP_TESTS_GOLDEN_ORACLE_H
#define PERSP_TESTS_GOLDEN_ORACLE_H

#include "persp.h"

#include <stddef.h>

/* Every pixel of img checked against the interval GL allows for filter (a
 * GL filter), clear being the scene's opaque clear colour. off: pixels
 * outside the interval widened by tol levels, unless nothing may be seen
 * there and they show the clear colour; covered / background: pixels the
 * reference says must show a surface / may show only the clear colour. */
typedef struct oracle_interval_result {
    size_t checked, off, covered, background;
    int first_x, first_y;
} oracle_interval_result;
oracle_interval_result oracle_check_interval(const persp_scene *scene, const persp_image *img, persp_filter filter,
                                             double tol, const uint8_t *clear);

/* The area-sampled image: each pixel the mean of k × k sub-pixel samples,
 * each the midpoint of GL's trilinear interval at k times the resolution
 * (a box filter over the pixel of a prefiltered texture: the integral that
 * anisotropic and EWA filters approximate), at the pixels whose x and y
 * are multiples of step. rgb: w·h·3 doubles; inside: w·h flags, 1 where
 * the pixel was evaluated and every sub-sample sees a surface. 0 on
 * success. */
int oracle_area_image(const persp_scene *scene, int w, int h, int k, int step, double *rgb, unsigned char *inside);

/* Error of img against an area image over the pixels marked inside. */
typedef struct oracle_error {
    size_t pixels;
    double mean_abs; /* levels, mean over pixels and channels */
    double psnr;     /* dB */
} oracle_error;
oracle_error oracle_area_error(const persp_image *img, const double *rgb, const unsigned char *inside);

/* A lit scene's image against the lighting of docs/SCENES.md ("Lighting
 * and shading": Blinn–Phong in eye space, two-sided, the texture
 * environments) evaluated in double at each pixel centre whose surface is
 * certain (diff_ref_front), with the texel taken as GL's interval for the
 * scene's filter. gouraud 0: per pixel with perspective-correct normals
 * and eye positions (phong-pc); 1: per vertex, colours screen-linear
 * (gouraud). Pixels where nothing may be seen must show the clear colour.
 * off: pixels outside the expected interval widened by tol levels. */
typedef struct oracle_lit_result {
    size_t checked, lit, background, off;
    int first_x, first_y;
    double first_lo[3], first_hi[3];
    uint8_t first_got[3];
} oracle_lit_result;
oracle_lit_result oracle_check_lit(const persp_scene *scene, const persp_image *img, int gouraud, double tol);

#endif
