/* Clipping, triangle setup and coverage (internal). */
#ifndef PERSP_RASTER_RASTER_H
#define PERSP_RASTER_RASTER_H

#include "core/shared.h"

#include "pipeline/types.h"

#include <stdint.h>

#define PERSP_TILE 64
#define PERSP_SUBPIXEL_BITS 8
#define PERSP_SUBPIXEL (1 << PERSP_SUBPIXEL_BITS)
/* Guard band: after clipping, window coordinates stay within this many pixels
 * of the viewport, so 8.8 fixed point and 64-bit edge products never overflow
 * (|coord| < 2^15 · 2^8 = 2^23, products < 2^47). Only the near plane, the
 * far plane and w > 0 are clipped exactly (docs/CONVENTIONS.md, "Rasterization"). */
#define PERSP_GUARD_PIXELS 16384.0

/* A triangle clipped against near, far, w > 0 and the guard band yields a
 * convex polygon of at most 3 + 6 vertices. */
#define PERSP_CLIP_MAX 12

/* Clips triangle in[3] in homogeneous coordinates (before any divide).
 * Returns the number of output vertices (0 or 3..PERSP_CLIP_MAX). Vertices
 * with a NaN or infinite coordinate make the whole triangle rejected. */
int persp__clip_triangle(const persp_clipvert in[3], double guard_x, double guard_y,
                         persp_clipvert out[PERSP_CLIP_MAX]);

/* Per-vertex classification for trivial accept and reject (Cohen–Sutherland
 * outcodes in clip space): bit p is set when the vertex lies outside the
 * p-th plane persp__clip_triangle clips against, decided by the same
 * arithmetic; PERSP_CLIP_NONFINITE alone when a coordinate or attribute is
 * NaN or infinite. A triangle whose three codes share a bit is entirely
 * outside (clipping would leave nothing); one whose codes are all zero
 * passes clipping unchanged. */
#define PERSP_CLIP_NONFINITE 0x100u
unsigned persp__clip_outcode(const persp_clipvert *v, double guard_x, double guard_y);
/* The same for a vertex packed as its clip position followed by its first
 * nattr attributes (the render's per-vertex cache, frame.c). */
unsigned persp__clip_outcode_packed(const float *v, int nattr, double guard_x, double guard_y);

/* The position's part of the outcode (the vertex's values known finite):
 * the planes' own expressions of clip.c (p_w ... p_top), in the order of
 * its planes[]. Inline, so that the render's vertex stage computes it for
 * several vertices at once. */
#define PERSP_CLIP_W_EPSILON 1e-6
static inline unsigned persp__clip_outcode_pos(double x, double y, double z, double w, double gx, double gy)
{
    unsigned code = 0;
    code |= (unsigned)(w - PERSP_CLIP_W_EPSILON < 0.0) << 0;
    code |= (unsigned)(z + w < 0.0) << 1;
    code |= (unsigned)(w - z < 0.0) << 2;
    code |= (unsigned)(gx * w + x < 0.0) << 3;
    code |= (unsigned)(gx * w - x < 0.0) << 4;
    code |= (unsigned)(gy * w + y < 0.0) << 5;
    code |= (unsigned)(gy * w - y < 0.0) << 6;
    return code;
}

/* A vertex after the perspective divide and viewport transform. */
typedef struct persp_winvert {
    double x, y, z; /* window coordinates, depth in [0,1] */
    double q;       /* 1/w_clip */
    const float *attr;
} persp_winvert;

/* What culling drops, by the triangle's winding in the window (y up): the
 * `cull` of set-up, the frame's meshes and the cluster test. An object
 * drawn as modelled has its front faces counter-clockwise
 * (glFrontFace(GL_CCW)); one whose model matrix mirrors it (negative
 * determinant of its linear part) has them clockwise, as glTF 2.0 rules
 * (§3.7.4, "the determinant of the node's global transform defines the
 * winding order"), so culling its back faces drops counter-clockwise ones.
 * Only culling reads it: two-sided lighting picks the side by the normals. */
enum { PERSP_CULL_NONE = 0, PERSP_CULL_CW = 1, PERSP_CULL_CCW = 2 };

/* Sets up one triangle. Returns 0 if it is degenerate (zero area), fully
 * outside the viewport, or culled (cull: PERSP_CULL_*); 1 otherwise. vv, when not NULL, gets
 * the vertices t->rat was fitted through (in set-up order), which a
 * method's prepare reads; t->bary passes through the same x, y and q with
 * s1 = (0, 1, 0), s2 = (0, 0, 1). */
PERSP_INTERNAL int persp__setup_triangle(const persp_winvert v[3], int width, int height, int cull,
                                         persp_tri *t, persp_rational_vertices *vv);
/* The same with only the fields need names: PERSP_SETUP_SHADING adds the
 * perspective-correct barycentric planes (bary), the vertex attributes (vattr) and
 * light_side, which only the span shaders and the analyses read; without
 * it those fields are left unwritten. persp__setup_triangle sets up all. */
#define PERSP_SETUP_SHADING 1u
/* With PERSP_SETUP_SHADING: the back face's vertex colours (PERSP_A_BR..BB,
 * which only Gouraud reads) are copied too; without it they are zero and
 * only the attributes before them are read. */
#define PERSP_SETUP_BACK_COLOURS 2u
/* With PERSP_SETUP_SHADING: the screen-linear barycentric planes (lb1,
 * lb2), which only the screen-linear shading modes read (a shading method
 * of NULL); without it they are left unwritten. */
#define PERSP_SETUP_LINEAR 4u
#define PERSP_SETUP_ALL (PERSP_SETUP_SHADING | PERSP_SETUP_BACK_COLOURS | PERSP_SETUP_LINEAR)
PERSP_INTERNAL int persp__setup_triangle_for(const persp_winvert v[3], int width, int height,
                                             int cull, unsigned need, persp_tri *t,
                                             persp_rational_vertices *vv);

/* floor(a / b) and ceil(a / b) for b > 0 in 64-bit integers. */
static inline int64_t persp__floor_div(int64_t a, int64_t b)
{
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}
static inline int64_t persp__ceil_div(int64_t a, int64_t b)
{
    return a >= 0 ? (a + b - 1) / b : -((-a) / b);
}

/* The integer half of set-up: vertices in 1/256 pixel (PERSP_SUBPIXEL),
 * put counter-clockwise (order: which input vertex is each), the clipped
 * pixel box of the candidate centres, and the edge functions with the
 * top-left rule folded in. */
typedef struct persp_tri_edges {
    int64_t x[3], y[3];
    int order[3];
    int back; /* the input was clockwise in the window */
    int64_t bx0, bx1, by0, by1;
    int64_t ea[3], eb[3], ec[3];
    uint32_t cover; /* small box: the covered candidates (persp_tri.cover), else 0 */
} persp_tri_edges;
#define PERSP_SMALL_BOX_PIXELS 32
/* 0 when the triangle is degenerate, culled (back face with cull), has no
 * candidate centre in the viewport, or covers none of at most
 * PERSP_SMALL_BOX_PIXELS candidates: the triangles set-up drops before any
 * floating-point work. The renderer calls it on the window positions of
 * its vertex stage before building set-up's input, so that a triangle set-up
 * would drop costs no more than this (a third of the set-ups of the
 * 2M-triangle torus covered no pixel centre); inline, as it runs for every
 * triangle inside the clip volume. */
static inline int persp__tri_edges(const int64_t X[3], const int64_t Y[3], int width, int height, int cull,
                                   persp_tri_edges *e)
{
    const int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area == 0) return 0;
    e->back = area < 0; /* clockwise in window space (y up) */
    if (cull && e->back == (cull == PERSP_CULL_CW)) return 0;
    e->order[0] = 0;
    e->order[1] = e->back ? 2 : 1;
    e->order[2] = e->back ? 1 : 2;
    int64_t *x = e->x, *y = e->y;
    for (int i = 0; i < 3; i++) {
        x[i] = X[e->order[i]];
        y[i] = Y[e->order[i]];
    }

    int64_t minx = x[0], maxx = x[0], miny = y[0], maxy = y[0];
    for (int i = 1; i < 3; i++) {
        if (x[i] < minx) minx = x[i];
        if (x[i] > maxx) maxx = x[i];
        if (y[i] < miny) miny = y[i];
        if (y[i] > maxy) maxy = y[i];
    }
    /* Pixel p is a candidate if its centre p·256 + 128 lies inside the box. */
    const int64_t half = PERSP_SUBPIXEL / 2;
    int64_t bx0 = persp__ceil_div(minx - half, PERSP_SUBPIXEL);
    int64_t bx1 = persp__floor_div(maxx - half, PERSP_SUBPIXEL);
    int64_t by0 = persp__ceil_div(miny - half, PERSP_SUBPIXEL);
    int64_t by1 = persp__floor_div(maxy - half, PERSP_SUBPIXEL);
    if (bx0 < 0) bx0 = 0;
    if (by0 < 0) by0 = 0;
    if (bx1 > width - 1) bx1 = width - 1;
    if (by1 > height - 1) by1 = height - 1;
    if (bx0 > bx1 || by0 > by1) return 0;
    e->bx0 = bx0, e->bx1 = bx1, e->by0 = by0, e->by1 = by1;

    int64_t *ea = e->ea, *eb = e->eb, *ec = e->ec;
    for (int k = 0; k < 3; k++) {
        int i = k, j = (k + 1) % 3;
        int64_t dx = x[j] - x[i], dy = y[j] - y[i];
        ea[k] = -dy;
        eb[k] = dx;
        ec[k] = -(ea[k] * x[i] + eb[k] * y[i]);
        /* Top-left rule in y-up window space for a counter-clockwise
         * triangle: a left edge runs downwards, a top edge runs towards -x.
         * Pixels exactly on other edges belong to the neighbour. */
        int top_left = dy < 0 || (dy == 0 && dx < 0);
        if (!top_left) ec[k] -= 1;
    }
    /* A triangle of a few pixels' box often covers no pixel centre at all
     * (on the 2M-triangle torus, about two pixels per triangle, a third of
     * those that reach set-up); testing the few centres with the edge
     * functions the rasterizer uses drops exactly those, before the planes
     * are fitted and the record is binned and walked. The centres that pass
     * are kept as a mask, which the row walk then reads instead of dividing
     * (persp__row_walk_init): the same integer edge values, so the same
     * pixels. Steps of 256·A and 256·B instead of products: all three edges
     * are >= 0 exactly when none of their sign bits is set. */
    e->cover = 0;
    const int64_t bw = bx1 - bx0 + 1;
    if (bw < 32 && bw * (by1 - by0 + 1) <= PERSP_SMALL_BOX_PIXELS) {
        const int64_t Xc = bx0 * PERSP_SUBPIXEL + half, Yc = by0 * PERSP_SUBPIXEL + half;
        int64_t r0 = ea[0] * Xc + eb[0] * Yc + ec[0];
        int64_t r1 = ea[1] * Xc + eb[1] * Yc + ec[1];
        int64_t r2 = ea[2] * Xc + eb[2] * Yc + ec[2];
        uint32_t cover = 0, bit = 1;
        for (int64_t py = by0; py <= by1; py++) {
            int64_t e0 = r0, e1 = r1, e2 = r2;
            for (int64_t px = bx0; px <= bx1; px++, bit <<= 1) {
                if ((e0 | e1 | e2) >= 0) cover |= bit;
                e0 += ea[0] * PERSP_SUBPIXEL, e1 += ea[1] * PERSP_SUBPIXEL, e2 += ea[2] * PERSP_SUBPIXEL;
            }
            r0 += eb[0] * PERSP_SUBPIXEL, r1 += eb[1] * PERSP_SUBPIXEL, r2 += eb[2] * PERSP_SUBPIXEL;
        }
        if (!cover) return 0;
        e->cover = cover;
    }
    return 1;
}

/* The rest of persp__setup_triangle_for, for a triangle whose integer half
 * e was computed from the same vertices (their x, y rounded to e's
 * integers) and accepted, and whose z and q are finite with q > 0 (what
 * the renderer's outcodes guarantee for a vertex inside every plane). */
int persp__setup_triangle_edges(const persp_winvert v[3], const persp_tri_edges *e, unsigned need,
                                persp_tri *t, persp_rational_vertices *vv);

/* Covered pixel range of row y (inclusive), clipped to [x0, x1]. */
PERSP_INTERNAL int persp__tri_row_range(const persp_tri *t, int y, int x0, int x1, int *lo,
                                        int *hi);

/* The covered ranges of consecutive rows, the same as persp__tri_row_range
 * gives, by exact integer stepping: each edge's bound at the first row
 * takes one division, later rows an addition and a comparison (the
 * quotient and remainder of the edge's per-row step are fixed). Small
 * triangles are a few pixels per row, so per-row divisions would otherwise
 * be a large share of their cost. */
typedef struct persp_row_walk {
    int64_t lo, hi;     /* clip range [x0, x1] ∩ bounding box */
    int64_t m[3], r[3]; /* edge k's bound on this row and its remainder in [0, d[k]) */
    int64_t d[3];       /* 256·|A| (0: the edge is horizontal) */
    int64_t q[3], s[3]; /* per-row step of the bound: quotient and remainder by d[k] */
    int64_t R[3];       /* horizontal edges: edge value at the row, and its step in s[k] */
    int sign[3];        /* +1: bound from below (A > 0), −1: from above, 0: horizontal */
    /* A triangle with a coverage mask (persp_tri.cover) walks its mask: the
     * rows still to come, bw bits each (bw 0: the edge walk above), and the
     * columns [lo, hi] as bits from the box's left column x. */
    uint32_t bits, cols;
    int bw, x;
} persp_row_walk;

/* A walk of rows rows from row y (t->ymin <= y; rows >= 1; stepping past
 * them is not defined), clipped to columns [x0, x1]. */
void persp__row_walk_init(persp_row_walk *w, const persp_tri *t, int y, int rows, int x0, int x1);

/* The range of the walk's current row, then advances it by one row. */
static inline int persp__row_walk_next(persp_row_walk *w, int *lo, int *hi)
{
    if (w->bw) {
        const uint32_t row = w->bits & w->cols;
        w->bits >>= w->bw;
        if (!row) return 0;
        *lo = w->x + __builtin_ctz(row);
        *hi = w->x + 31 - __builtin_clz(row);
        return 1;
    }
    int64_t l = w->lo, h = w->hi;
    int ok = 1;
    for (int k = 0; k < 3; k++) {
        if (w->sign[k] > 0) {
            l = w->m[k] > l ? w->m[k] : l;
            int64_t r = w->r[k] + w->s[k];
            int carry = r >= w->d[k];
            w->m[k] -= w->q[k] + carry;
            w->r[k] = carry ? r - w->d[k] : r;
        } else if (w->sign[k] < 0) {
            h = w->m[k] < h ? w->m[k] : h;
            int64_t r = w->r[k] + w->s[k];
            int carry = r >= w->d[k];
            w->m[k] += w->q[k] + carry;
            w->r[k] = carry ? r - w->d[k] : r;
        } else {
            ok &= w->R[k] >= 0;
            w->R[k] += w->s[k];
        }
    }
    if (!ok || l > h) return 0;
    *lo = (int)l;
    *hi = (int)h;
    return 1;
}

/* The run of tiles tile0..tile1 - 1 in row-major order (tiles_x a row)
 * as rows and columns: row r0 from column c0 on, every row after it up to
 * row r1, and that row up to column c1 (one row: columns c0..c1). Worked
 * out once a frame, so that the test of each triangle divides nothing. */
typedef struct persp_tile_run {
    int64_t r0, c0, r1, c1;
} persp_tile_run;

static inline persp_tile_run persp__tile_run(int64_t tiles_x, int64_t tile0, int64_t tile1)
{
    return (persp_tile_run){tile0 / tiles_x, tile0 % tiles_x, (tile1 - 1) / tiles_x, (tile1 - 1) % tiles_x};
}

/* Whether the box of tiles tx0..tx1 × ty0..ty1 holds a tile of the run. */
static inline int persp__box_reaches_run(const persp_tile_run *run, int64_t tx0, int64_t tx1, int64_t ty0,
                                         int64_t ty1)
{
    const int64_t r0 = run->r0, c0 = run->c0, r1 = run->r1, c1 = run->c1;
    if (r0 == r1) return ty0 <= r0 && r0 <= ty1 && tx1 >= c0 && tx0 <= c1;
    return (ty0 <= r0 && r0 <= ty1 && tx1 >= c0) || (ty0 <= r1 && r1 <= ty1 && tx0 <= c1) ||
           (ty0 > r0 ? ty0 : r0 + 1) <= (ty1 < r1 ? ty1 : r1 - 1); /* a whole row between the ends */
}

/* What culling a cluster whole needs of a frame (src/raster/cluster_cull.c):
 * the model-view-projection rows and their xyz parts' lengths, the centre
 * of projection in object space, the clip planes a cluster must be inside
 * (coefficients of the rows and a constant) with their normals' lengths,
 * and the window's bounds. */
typedef struct persp_cluster_view {
    double row[4][4], row_norm[4], E[4];
    double plane[7][5], plane_norm[7];
    double tx, ty, W2, H2, eps;
    /* Sort first (persp_frame.regions, .run; regions 0: none): clusters
     * that cannot reach a tile of the run (tiles_x a row) are culled too. */
    int regions, tiles_x;
    persp_tile_run run;
    int cull; /* PERSP_CULL_*: none culls no cluster as back-facing */
} persp_cluster_view;
void persp__cluster_view_init(persp_cluster_view *cv, const persp_mat4 *mvp, int width, int height, double gx,
                              double gy, int cull);
/* culled[k] = 1 for each of clusters[0..count) every triangle of which the
 * frame, drawing with culling cull (PERSP_CULL_CW or _CCW, as given to
 * persp__cluster_view_init), would cull; with regions, 2 for each other
 * one whose sphere reaches no tile row of the region (none of its
 * triangles would); 0 for the others. Returns how many are 1. */
size_t persp__clusters_cull(const persp_cluster_view *cv, const persp_cluster *clusters, size_t count,
                            uint8_t *culled);
/* 1 when every triangle of cluster cl would be culled as a back face (the
 * test of persp__clusters_cull). */
int persp__cluster_back_facing(const persp_cluster_view *cv, const persp_cluster *cl);
/* need[b] = 1 for each block of `block` vertices that a cluster not culled
 * uses (a superset). */
void persp__clusters_vertex_need(const persp_mesh *mesh, const uint8_t *culled, size_t block, uint8_t *need);

#endif
