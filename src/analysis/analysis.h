/*
 * Accuracy analysis internals (persp accuracy): error statistics, the
 * measurement cases of docs/WORKLOADS.md and the heat-map writer. The metric
 * code is independent of texturing so that shading comparisons can reuse it.
 */
#ifndef PERSP_ANALYSIS_ANALYSIS_H
#define PERSP_ANALYSIS_ANALYSIS_H

#include "persp_analysis.h"
#include "interp/method.h"
#include "raster/raster.h"

#include <stddef.h>
#include <stdint.h>

/* ------------------------------------------------------- error statistics */

/* Accumulator of non-negative errors: count, sum, max and every value, for
 * exact percentiles. Values are stored in a buffer reserved up front
 * (persp__errstats_reserve) so that adding a value never allocates. */
typedef struct persp_errstats {
    persp_context *ctx;
    double *v;
    size_t n, cap;
    uint64_t count;   /* values added, including any that found no room */
    uint64_t dropped; /* values not stored because the buffer was full */
    double sum, max;
} persp_errstats;

void persp__errstats_init(persp_errstats *s, persp_context *ctx);
void persp__errstats_free(persp_errstats *s);
/* Forgets all values, keeps the buffer. */
void persp__errstats_reset(persp_errstats *s);
/* Makes room for `extra` more values; PERSP_ERR_OUT_OF_MEMORY on failure. */
persp_status persp__errstats_reserve(persp_errstats *s, size_t extra);

static inline void persp__errstats_add(persp_errstats *s, double x)
{
    s->count++;
    s->sum += x;
    if (x > s->max) s->max = x;
    if (s->n < s->cap)
        s->v[s->n++] = x;
    else
        s->dropped++;
}

double persp__errstats_mean(const persp_errstats *s);
/* Nearest-rank percentile: the smallest stored value x such that at least
 * p % of the stored values are <= x (p in (0, 100]); 0 when empty. Reorders
 * the stored values. */
double persp__errstats_percentile(persp_errstats *s, double p);

/* ------------------------------------------------- texture-coordinate metrics */

/* Everything persp accuracy reports for one method on one case. */
typedef struct persp_acc_metrics {
    persp_errstats eu, ev;      /* |Δu|, |Δv| in texels */
    uint64_t pixels, spans, triangles;
    uint64_t texel_miss;        /* pixels whose nearest texel differs from the exact one's */
    double relpt_u, relpt_v;    /* max |Δs| / |s| over pixels with |s| >= rel_floor */
    double relspan_u, relspan_v;/* max |Δs| / (max s - min s over the span), spans with range >= rel_floor */
    double rel_floor;           /* in normalised texture units */
    persp_opcount ops;
} persp_acc_metrics;

void persp__acc_metrics_init(persp_acc_metrics *m, persp_context *ctx, double rel_floor);
void persp__acc_metrics_reset(persp_acc_metrics *m);
void persp__acc_metrics_free(persp_acc_metrics *m);

/* Adds one span (or traversal batch) of n pixels: exact s1/s2 (double) and
 * the method's (float), texture scales in texels per unit. If err_out is not
 * NULL it receives max(|Δu|·scale1, |Δv|·scale2) per pixel. */
void persp__acc_metrics_span(persp_acc_metrics *m, int n, const double *s1x, const double *s2x,
                             const float *s1, const float *s2, double scale1, double scale2,
                             float *err_out);

/* Rows of a persp_accuracy_run (src/analysis/accuracy.c, report.c). */
struct persp_accuracy_result {
    persp_context *ctx;
    persp_accuracy_row *rows;
    size_t count, cap;
    /* Sharded runs: position of each row in the unsharded run, the rows it
     * has in all, and a text naming the sweep so that shards of different
     * sweeps are not merged. shard_count 0: a whole run. */
    size_t *index;
    size_t total;
    int shard_index, shard_count;
    char sweep[1024];
    /* The file persp_accuracy_read took it from ("" otherwise): merge's
     * messages name it. */
    char source[256];
};

/* ----------------------------------------------------------------- cases */

/* Heckbert 1989 §2.2.3: the projective map of the unit square onto the quad
 * with corners x[k], y[k] for (u, v) = (0,0), (1,0), (1,1), (0,1), as the
 * forward matrix fwd (row vector [u v 1]·fwd = [x·w y·w w]) and its adjoint,
 * the inverse up to scale, written as Heckbert's a..i of
 * u = (a·x + b·y + c)/(g·x + h·y + i), v = (d·x + e·y + f)/(g·x + h·y + i).
 * Returns 0 if the quad is degenerate. */
int persp__square_to_quad(const double x[4], const double y[4], double fwd[9], double inv[9]);

/* The quad of [Romanyuk-PCF] §4.6 Fig. 4.10: case paper-quad of docs/WORKLOADS.md. */
extern const double persp__paper_quad_x[4], persp__paper_quad_y[4];
/* The chapter's rasterization line. */
#define PERSP_PAPER_QUAD_LINE_Y 32.0

/* Rational form of paper-quad in screen coordinates where pixel (x, y)
 * samples the chapter's point (x, y) (pixel centres shifted by half a pixel,
 * so that integer screen positions are sampled as in the chapter), with the
 * vertices of corners k0, k1, k2. scale = texels per unit. */
void persp__paper_quad_rational(int k0, int k1, int k2, double scale, persp_rational *r,
                                persp_rational_vertices *v);

/* The line y = 32 of the paper quad from its left edge to its right edge,
 * resampled to n equally spaced samples (n <= PERSP_SPAN_MAX) so that one
 * span call covers the whole line as in the chapter's study: pixel (k, 0) of
 * the returned rational is the point x = x_left + k·(x_right-x_left)/(n-1). */
void persp__paper_quad_line(int n, double scale, persp_rational *r, persp_rational_vertices *v,
                            double *x_left, double *x_right);

/* Depth-ratio groups of random-triangles (docs/WORKLOADS.md). */
#define PERSP_HBAR_COUNT 7
extern const double persp__hbar_groups[PERSP_HBAR_COUNT];

/* Seeded generator (splitmix64). */
typedef struct persp_rng { uint64_t s; } persp_rng;
uint64_t persp__rng_next(persp_rng *r);
double persp__rng_uniform(persp_rng *r, double lo, double hi);

#define PERSP_RT_WIDTH 1024
#define PERSP_RT_HEIGHT 768
#define PERSP_RT_MIN_PIXELS 100
#define PERSP_RT_MAX_PIXELS 100000

/* One random triangle of depth ratio hbar (z_far / z_near of its vertices)
 * in eye space, projected with the corridor projection at 1024×768, u, v in
 * [0, 1], texture 256×256 (rat.scale = 256), covering 100..100000 pixels,
 * with the vertices of its rational form in *v.
 * attr is storage for the vertex attributes. Returns its pixel count, or 0
 * if no triangle was found within the retry limit. */
uint64_t persp__random_triangle(persp_rng *rng, double hbar, persp_tri *t, persp_rational_vertices *v,
                                float attr[3][PERSP_A_COUNT]);
/* Covered pixels of a set-up triangle. */
uint64_t persp__tri_pixels(const persp_tri *t);

/* --------------------------------------------------------------- heat map */

/* Writes err (w×h floats, row 0 = bottom, NaN = not covered) as a PNG with
 * a logarithmic colour scale over the five decades ending at 10^top_decade
 * and a legend (colour bar with labelled decade ticks, caption naming the
 * quantity and its unit). The scale is fixed per quantity
 * (PERSP_HEATMAP_*_TOP), not fitted to each map, so that maps shown side by
 * side share one scale and one legend reads for all of them. The image is
 * enlarged by an integer factor so that it is at least 256 pixels wide. */
/* The analyses' shared limits: the first of triangles (0..100000) and
 * width, height (0..PERSP_IMAGE_MAX_SIDE) out of range, named as their
 * descs name them, or NULL. */
const char *persp__analysis_size_problem(int triangles, int width, int height);
#define PERSP_HEATMAP_TEXELS "max(|du|,|dv|) in texels"
#define PERSP_HEATMAP_LEVELS "|error| in 8-bit levels"
/* Texels: 0.001 (below which errors look alike on an 8-bit texture) to 100
 * (affine's worst on the built-in scenes; larger errors take the top colour).
 * Levels: 0.01 to 1000 (an 8-bit channel errs by at most 255). */
#define PERSP_HEATMAP_TEXELS_TOP 2
#define PERSP_HEATMAP_LEVELS_TOP 3
persp_status persp__heatmap_write(persp_context *ctx, const char *path, const float *err, int w,
                                  int h, const char *caption, int top_decade);
/* Colour of value t in [0, 1] on the heat-map scale. */
void persp__heatmap_color(double t, uint8_t rgb[3]);
/* Draws text (digits, '.', '-', 'e', '+') with the built-in 3×5 font at
 * (x, y) = top-left corner, y counted from the top, with integer scale. */
void persp__heatmap_text(persp_image *img, int x, int y, int scale, const char *text,
                         const uint8_t rgb[3]);
/* Width in pixels of text drawn at scale. */
int persp__heatmap_text_width(const char *text, int scale);

#endif
