/* Clipping, triangle setup and coverage (internal). */
#ifndef PERSP_RASTER_RASTER_H
#define PERSP_RASTER_RASTER_H

#include "interp/method.h"

#include <stdint.h>

#define PERSP_TILE 64
#define PERSP_SUBPIXEL_BITS 8
#define PERSP_SUBPIXEL (1 << PERSP_SUBPIXEL_BITS)
/* Guard band: after clipping, window coordinates stay within this many pixels
 * of the viewport, so 8.8 fixed point and 64-bit edge products never overflow
 * (|coord| < 2^15 · 2^8 = 2^23, products < 2^47). Only the near plane, the
 * far plane and w > 0 are clipped exactly (docs/CONVENTIONS.md, "Rasterization"). */
#define PERSP_GUARD_PIXELS 16384.0

/* Per-vertex attributes carried through clipping (linear in clip space). */
enum {
    PERSP_A_U, PERSP_A_V,
    PERSP_A_R, PERSP_A_G, PERSP_A_B, PERSP_A_A,
    PERSP_A_NX, PERSP_A_NY, PERSP_A_NZ, /* eye-space normal */
    PERSP_A_EX, PERSP_A_EY, PERSP_A_EZ, /* eye-space position */
    PERSP_A_BR, PERSP_A_BG, PERSP_A_BB, /* Gouraud: the back face's vertex colour */
    PERSP_A_COUNT
};

typedef struct persp_clipvert {
    float clip[4];
    float attr[PERSP_A_COUNT];
} persp_clipvert;

/* A triangle clipped against near, far, w > 0 and the guard band yields a
 * convex polygon of at most 3 + 6 vertices. */
#define PERSP_CLIP_MAX 12

/* Clips triangle in[3] in homogeneous coordinates (before any divide).
 * Returns the number of output vertices (0 or 3..PERSP_CLIP_MAX). Vertices
 * with a NaN or infinite coordinate make the whole triangle rejected. */
int persp__clip_triangle(const persp_clipvert in[3], double guard_x, double guard_y,
                         persp_clipvert out[PERSP_CLIP_MAX]);

/* A vertex after the perspective divide and viewport transform. */
typedef struct persp_winvert {
    double x, y, z; /* window coordinates, depth in [0,1] */
    double q;       /* 1/w_clip */
    const float *attr;
} persp_winvert;

/* Set-up triangle: fixed-point edges, bounding box and the screen-space
 * planes every method reads (Heckbert's a..i in `rat`). */
typedef struct persp_tri {
    int64_t ea[3], eb[3], ec[3]; /* edge k: ea·X + eb·Y + ec >= 0 inside (X, Y in 1/256 px), top-left bias folded into ec */
    int xmin, xmax, ymin, ymax;  /* inclusive pixel bounding box inside the viewport */
    persp_rational rat;          /* s1 = u, s2 = v */
    persp_rational bary;         /* s1 = b1, s2 = b2 (perspective-correct barycentrics) */
    double zp[3];                /* window depth plane: z = zp0·x + zp1·y + zp2 */
    double lb1[3], lb2[3];       /* screen-linear barycentric planes (classical Gouraud/Phong) */
    uint32_t state;              /* index of the draw state */
    uint32_t prep;               /* index into the method prep array, or UINT32_MAX */
    float poly_lambda;           /* per-polygon level of detail */
    int backfacing;
    float vattr[3][PERSP_A_COUNT]; /* vertex attributes in setup vertex order */
} persp_tri;

/* Sets up one triangle. Returns 0 if it is degenerate (zero area), fully
 * outside the viewport, or culled; 1 otherwise. */
int persp__setup_triangle(const persp_winvert v[3], int width, int height, int cull,
                          persp_tri *t);

/* Covered pixel range of row y (inclusive), clipped to [x0, x1]. */
int persp__tri_row_range(const persp_tri *t, int y, int x0, int x1, int *lo, int *hi);

#endif
