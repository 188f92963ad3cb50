/*
 * The arbiter of the differential test: what OpenGL defines a pixel to be,
 * computed in double precision straight from the specification, for the
 * pixels where persp and the peer disagree (and a sample of those where
 * they agree, to check the arbiter itself).
 *
 * Geometry: the point of each triangle seen through the pixel centre is
 * found in homogeneous clip space (barycentrics b with Σ b_i c_i lying on
 * the pixel's ray and Σ b_i = 1), which is the perspective-correct
 * interpolation of GL 4.6 §14.6.1 eq. 14.9 and needs no clipping: the point
 * is kept when -w <= z <= w and w > 0 (§13.7). The nearest point wins
 * (depth test LESS, first drawn on equal depth). Culling takes the sign of
 * the homogeneous determinant of (x, y, w), which is the window-space
 * orientation of the visible part (§14.6.1 eq. 14.8).
 *
 * Texturing: level of detail from the exact derivatives of (u·W, v·H)
 * (§8.14.1 eq. 8.9 with the ideal rho), texel selection and wrap of §8.14.2
 * (Table 8.20), level selection and blending of §8.14.3. Every texel and
 * weight is computed in double; the result is a real-valued colour.
 */
#ifndef PERSP_TESTS_DIFFREF_H
#define PERSP_TESTS_DIFFREF_H

#include "persp.h"

typedef struct diff_ref diff_ref;

/* Margins of the latitude GL leaves (see diffref.c for the reasoning). */
#define DIFF_REF_TEXEL_MARGIN 2e-3 /* texels, on u·W - (texel edge) */
#define DIFF_REF_LOD_MARGIN 2e-3   /* levels, on lambda - (switch point) */
#define DIFF_REF_EDGE_MARGIN 1e-2  /* pixels: centre this close to an edge */

diff_ref *diff_ref_create(const persp_scene *scene, int width, int height, persp_filter filter);
void diff_ref_destroy(diff_ref *ref);

typedef struct diff_ref_pixel {
    int covered;       /* some triangle may be seen through the pixel */
    int background_ok; /* no triangle may be seen (edge within the margin) */
    double lo[3], hi[3]; /* per channel, 0..255: the values GL allows when covered */
} diff_ref_pixel;

/* Pixel (x, y), y = 0 the bottom row. */
diff_ref_pixel diff_ref_eval(const diff_ref *ref, int x, int y);

/* The surface seen through pixel (x, y) when only one triangle may be:
 * object index, the triangle's first index in the object's index list,
 * its perspective-correct barycentrics at the centre (the weights of the
 * vertex attributes, GL 4.6 §14.6.1 eq. 14.9) and, when every vertex lies
 * in front of the eye, the screen-linear ones (screen_ok). Returns 0 where
 * the background, an edge within the margin or a depth tie leaves the
 * surface in doubt. */
typedef struct diff_ref_hit {
    int object;
    size_t first_index;
    double b[3];
    int screen_ok;
    double screen_b[3];
} diff_ref_hit;
int diff_ref_front(const diff_ref *ref, int x, int y, diff_ref_hit *out);

#endif
