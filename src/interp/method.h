/*
 * The texture-coordinate method interface (docs/DESIGN.md, "The method interface").
 *
 * A method computes two perspective-correct quantities along a span of pixels
 * from Heckbert's rational form (Heckbert 1989, §2.3.2):
 *
 *     s1(x, y) = (a·x + b·y + c) / (g·x + h·y + i)
 *     s2(x, y) = (d·x + e·y + f) / (g·x + h·y + i)
 *
 * evaluated at pixel centres (x + 0.5, y + 0.5) in window coordinates.
 * For texturing s1, s2 are u, v; for perspective-correct shading the same
 * methods run on the planes of the barycentric weights b1/w, b2/w, so the
 * shading approximations share this code ([Romanyuk-PCF] §4.2-4.3).
 */
#ifndef PERSP_INTERP_METHOD_H
#define PERSP_INTERP_METHOD_H

#include "core/shared.h"

#include "persp.h"

/* Longest span a method is asked to fill in one call (one row of a tile). */
#define PERSP_SPAN_MAX 64
/* Most pixels the texture samplers and the shaders take in one call: the
 * lanes of one small-triangle batch (src/raster/tiles.c), rows of several
 * triangles packed together. Larger batches share their fixed costs among
 * more pixels: 128 rather than 64 took 14–20 % less CPU on the 2k torus,
 * 256 another 4–6 % lit (docs/PERFORMANCE_HISTORY.md, item 44). */
#define PERSP_LANE_MAX 256
/* Bytes of per-triangle state a method may keep (fits, forward differences). */
#define PERSP_METHOD_PREP_BYTES 512
/* Bytes of parsed parameters ("subdiv:16", "incremental:k=4"). */
#define PERSP_METHOD_PARAM_BYTES 32

typedef struct persp_rational {
    double a, b, c;  /* numerator plane of s1 (u/w) */
    double d, e, f;  /* numerator plane of s2 (v/w) */
    double g, h, i;  /* denominator plane (1/w) */
    int xmin, xmax, ymin, ymax; /* inclusive pixel bounding box of the triangle */
    float scale1, scale2;     /* texels per unit of s1, s2 (texture size); 1 if none */
} persp_rational;

/* The values a rational form was fitted through: its triangle's vertices.
 * Only fitting reads them (a method's prepare, the per-polygon level of
 * detail), at set-up, so the set-up record keeps the planes alone: 240
 * bytes less for each triangle a batch holds and its tiles read back
 * (docs/PERFORMANCE_HISTORY.md, item 55). */
typedef struct persp_rational_vertices {
    double x[3], y[3]; /* window positions */
    double s1[3], s2[3];
    double q[3]; /* 1/w (> 0) */
} persp_rational_vertices;

typedef struct persp_method_prep {
    _Alignas(16) unsigned char bytes[PERSP_METHOD_PREP_BYTES];
} persp_method_prep;

typedef struct persp_method_params {
    _Alignas(8) unsigned char bytes[PERSP_METHOD_PARAM_BYTES];
} persp_method_params;

/* Bytes at the end of a persp_method_prep that a method's own state leaves
 * free for a method that wraps it: adaptive keeps there the vertices it
 * classifies a triangle by, in front of its fallback's state. */
#define PERSP_METHOD_PREP_TAIL 48

/* A method keeps its parameters and per-triangle state in these blobs as a
 * struct of its own, copied in and out or read through a cast pointer. Next
 * to each such struct, PERSP_METHOD_BLOB_FITS(type, persp_method_params or
 * persp_method_prep) makes a struct that outgrows its blob, or needs more
 * alignment than the blob has, a compile error instead of an overrun. */
#define PERSP_METHOD_BLOB_FITS(type, blob)                                                   \
    _Static_assert(sizeof(type) <= sizeof(((blob *)0)->bytes) &&                             \
                       _Alignof(type) <= _Alignof(blob),                                     \
                   #type " does not fit in " #blob)
/* The same for a per-triangle state, which leaves PERSP_METHOD_PREP_TAIL
 * bytes free. */
#define PERSP_METHOD_PREP_FITS(type)                                                         \
    _Static_assert(sizeof(type) <= PERSP_METHOD_PREP_BYTES - PERSP_METHOD_PREP_TAIL &&       \
                       _Alignof(type) <= _Alignof(persp_method_prep),                        \
                   #type " does not fit in persp_method_prep before its tail")

/* A batch of fragments handed downstream by a traversal. In span form
 * px == NULL and the pixels are (x0 + k, y); otherwise pixel k is
 * (px[k], py[k]). s1/s2 are filled by the method or the traversal. */
typedef struct persp_frag_batch {
    int n;
    int x0, y;
    const int32_t *px, *py;
    float *s1, *s2;
    /* Span form only: perspective-correct barycentrics already computed
     * with the texture coordinates' reciprocal (NULL: the shader computes
     * them; persp__exact_span_pair). */
    const float *w1, *w2;
} persp_frag_batch;

/* Called by a custom traversal for each batch it produces. */
typedef void (*persp_batch_sink)(void *user, const persp_frag_batch *batch);

/* Clip rectangle (inclusive pixel bounds) plus the coverage test a custom
 * traversal must respect so that its pixel set equals the standard one. */
typedef struct persp_traverse_area {
    int x0, y0, x1, y1; /* tile rectangle, inclusive */
    /* Returns the covered pixel range [*lo, *hi] of row y inside the tile;
     * 0 if the row is empty. */
    int (*row_range)(const void *tri, int y, int *lo, int *hi);
    const void *tri;
} persp_traverse_area;

typedef struct persp_method {
    const char *name;
    const char *params_help; /* e.g. "k=N|bidir"; "" if none */
    const char *summary;
    const char *source; /* citation key and section, e.g. "[Romanyuk-PCF] §4.5";
                         * the keys are defined in docs/SOURCES.md */
    const char *cost;
    /* Parses the text after ':' (NULL if none) into params. Returns
     * PERSP_OK or PERSP_ERR_INVALID_ARGUMENT. May be NULL (no parameters). */
    persp_status (*parse)(const char *text, persp_method_params *params);
    /* Per triangle: anything fitted once per polygon, from the planes r and
     * the vertices v they pass through. May be NULL. */
    void (*prepare)(const persp_rational *r, const persp_rational_vertices *v,
                    const persp_method_params *params, persp_method_prep *prep, persp_opcount *ops);
    /* Per span: fill s1[0..n-1], s2[0..n-1] for pixels (x0 + k, y), n <= PERSP_SPAN_MAX.
     * ops may be NULL; a method adds its operation counts when it is not. */
    void (*span)(const persp_rational *r, const persp_method_params *params,
                 const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                 persp_opcount *ops);
    /* Optional custom traversal (e.g. constant-depth lines, [Romanyuk-PCF] §4.8):
     * visits exactly the covered pixels of area once each, filling s1/s2,
     * and passes them to sink in batches of at most PERSP_SPAN_MAX. */
    void (*traverse)(const persp_rational *r, const persp_method_params *params,
                     const persp_method_prep *prep, const persp_traverse_area *area,
                     persp_batch_sink sink, void *user, persp_opcount *ops);
} persp_method;

/* Covered columns of rows by0..by1 of a custom traversal's area, cut to
 * columns bx0..bx1: lo[y - by0]..hi[y - by0] (empty rows get lo > hi), and
 * the union of the rows' ranges in *xa..*xb (xa > xb when all are empty).
 * Shared by the traversals that walk the area in blocks. */
static inline void persp__area_block_rows(const persp_traverse_area *area, int by0, int by1,
                                          int bx0, int bx1, int *lo, int *hi, int *xa, int *xb)
{
    *xa = bx1 + 1, *xb = bx0 - 1;
    for (int y = by0; y <= by1; y++) {
        int l, h;
        lo[y - by0] = 1, hi[y - by0] = 0;
        if (!area->row_range(area->tri, y, &l, &h)) continue;
        if (l < bx0) l = bx0;
        if (h > bx1) h = bx1;
        if (l > h) continue;
        lo[y - by0] = l, hi[y - by0] = h;
        if (l < *xa) *xa = l;
        if (h > *xb) *xb = h;
    }
}

/* A resolved method spec: entry + parsed parameters. */
typedef struct persp_method_sel {
    const persp_method *m;
    persp_method_params params;
} persp_method_sel;

/* Registry (src/interp/registry.c). */
PERSP_INTERNAL size_t persp__method_count(void);
PERSP_INTERNAL const persp_method *persp__method_at(size_t i);
/* Resolves "name[:params]". ctx may be NULL (no detail message). */
PERSP_INTERNAL persp_status persp__method_resolve(persp_context *ctx, const char *spec,
                                                  persp_method_sel *out);

/* Double-precision evaluation of the rational form at pixel (x, y)'s centre. */
static inline void persp__rational_eval(const persp_rational *r, double x, double y, double *s1,
                                        double *s2)
{
    double px = x + 0.5, py = y + 0.5;
    double q = r->g * px + r->h * py + r->i;
    *s1 = (r->a * px + r->b * py + r->c) / q;
    *s2 = (r->d * px + r->e * py + r->f) / q;
}

/* Operation counting is a run-time choice: the renderer passes ops == NULL,
 * the accuracy tool passes a counter. Methods count per span where the count
 * is fixed and per event where it varies (e.g. midpoint iterations). */
#define PERSP_OPS(ops, field, count)                                                         \
    do {                                                                                     \
        if (ops) (ops)->field += (uint64_t)(count);                                          \
    } while (0)

#endif
