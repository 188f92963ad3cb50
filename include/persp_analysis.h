/*
 * persp_analysis — measurement of persp's methods, shading modes and filters
 * against exact references (library persp_analysis; link it with persp).
 *
 * The same rules as persp.h apply: zero-initialised descs mean defaults,
 * results are released with their *_destroy function, one context is used
 * by one thread at a time, and a run's threads are its context's.
 * Report writers take a FILE * passed as void *, so that this header does
 * not need <stdio.h>.
 */
#ifndef PERSP_ANALYSIS_H
#define PERSP_ANALYSIS_H

#include "persp.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------- one triangle, per pixel */

/* A vertex for persp_method_triangle: window position in pixels (y up,
 * pixel (x, y) has its centre at (x + 0.5, y + 0.5)), w of clip space
 * (> 0) and texture coordinates (1 = the texture's width or height). */
typedef struct persp_method_vertex {
    double x, y, w;
    float u, v;
} persp_method_vertex;

/* The texture coordinates method spec gives every covered pixel of one
 * triangle, computed as persp_render computes them: the same set-up
 * (positions snapped to 1/256 pixel, the planes of u/w, v/w and 1/w
 * fitted through them in double precision, no culling), the same spans
 * (a row's covered pixels within one 64-pixel tile) or traversal, for a
 * texture of tex_w × tex_h texels (the lattice a method such as midpoint
 * works on; 0: 1). A reference for checking an implementation of a method
 * pixel by pixel (docs/METHODS.md, "Checking an implementation").
 * u_out, v_out: width × height floats each, row 0 at the bottom, written
 * at covered pixels only; covered (may be NULL): width × height bytes, set
 * to 1 at covered pixels and 0 elsewhere; ops (may be NULL): the method's
 * operation counts are added to it. A triangle that covers no pixel centre
 * (or is degenerate) covers nothing and is PERSP_OK. Sizes as an image's
 * (PERSP_ERR_TOO_LARGE beyond). */
PERSP_API persp_status persp_method_triangle(persp_context *ctx, const char *spec,
                                             const persp_method_vertex v[3], int width, int height,
                                             int tex_w, int tex_h, float *u_out, float *v_out,
                                             uint8_t *covered, persp_opcount *ops);

/* ------------------------------------- midpoint:int, register by register */

/* The fixed-point state of `midpoint:int` ([Romanyuk-PCF] §4.5; the format
 * and recurrences are in docs/METHODS.md, "Fixed-point model"), for checking
 * a hardware design of the division-free interpolator cycle by cycle rather
 * than by its outputs only. Index [0] is u, [1] is v. */
typedef struct persp_midpoint_format {
    int in_format;        /* 0: the planes do not fit the format; every span runs the double path */
    int shift;            /* s: G = round(g·2^s), A = round(P·a·2^s), ... */
    int lattice2;         /* 2o: 1 texel centres (midpoint:int), 0 texel edges (midpoint:int,edge) */
    int64_t G, H, I;
    int64_t A[2], B[2], C[2];
    int64_t X2max, Y2max; /* the integer path covers X2 = 2x + 1 < X2max, Y2 < Y2max */
    double P[2];          /* texels per unit of u and v (the texture's level 0) */
    double plane[9];      /* set-up's planes a, b, c (u/w), d, e, f (v/w), g, h, i (1/w) in double */
} persp_midpoint_format;

/* One span: its start values and where the integer path ended. */
typedef struct persp_midpoint_span {
    int x0, y, n;   /* pixels x0 … x0 + n − 1 of row y (a row's covered pixels in one 64-pixel tile) */
    int int_pixels; /* pixels 0 … int_pixels − 1 ran the integer path, the rest the double path */
    int64_t E0;     /* G·X2 + H·Y2 + 2I at pixel 0 */
    int64_t N2[2];  /* A·X2 + B·Y2 + 2C at pixel 0 */
    int64_t n0[2];  /* floor_div(2·N2 + (1 − 2o)·E0, 2·E0) */
    int64_t W0[2], T0[2], K[2];
} persp_midpoint_span;

/* One pixel of a span. n, W, steps and reseed are 0 at pixels of the
 * double path. */
typedef struct persp_midpoint_pixel {
    int64_t n[2];  /* the accepted lattice index */
    int64_t W[2];  /* W after the search: 0 < W ≤ 2E */
    int steps[2];  /* lattice steps of the search, + up and − down (after a re-seed: from the re-seeded index) */
    int reseed[2]; /* 1: the search passed 32 steps and the index was re-seeded by a division */
    float u, v;    /* the method's outputs, as persp_method_triangle gives them */
} persp_midpoint_pixel;

/* Called once per span in the renderer's order; pixels has span->n entries. */
typedef void (*persp_midpoint_span_fn)(void *user, const persp_midpoint_span *span,
                                       const persp_midpoint_pixel *pixels);

/* The triangle of persp_method_triangle (same vertices, window, texture size
 * and set-up) through spec "midpoint:int" or "midpoint:int,edge": *format
 * receives the triangle's fixed-point planes before fn is first called,
 * then fn is called for each span with its integer state (fn may be NULL). Its u and v equal
 * persp_method_triangle's bit for bit. A triangle covering no pixel centre
 * leaves format->in_format 0 and calls fn never. Other specs:
 * PERSP_ERR_INVALID_ARGUMENT. */
PERSP_API persp_status persp_midpoint_trace(persp_context *ctx, const char *spec,
                                            const persp_method_vertex v[3], int width, int height,
                                            int tex_w, int tex_h, persp_midpoint_format *format,
                                            persp_midpoint_span_fn fn, void *user);

/* ------------------------------------------------------- method accuracy */

/* persp accuracy: every texture-coordinate method measured against the exact
 * rational form (Heckbert 1989 §2.3.2) evaluated in double precision at each
 * pixel centre. Cases (docs/WORKLOADS.md): "paper-quad" ([Romanyuk-PCF] §4.6 Fig. 4.10:
 * the line y = 32 of the quad (1,1), (32,96), (96,128), (128,32), resampled
 * to one span of PERSP_ACCURACY_LINE_SAMPLES points from edge to edge),
 * "paper-quad-full" (every pixel of that quad, spans as the renderer cuts
 * them), "random-triangles" (one row per depth ratio 1.25 ... 8) and any
 * built-in scene name (rendered at desc.width × desc.height). */
#define PERSP_ACCURACY_LINE_SAMPLES 64

typedef struct persp_accuracy_desc {
    const char *const *methods; /* method specs; NULL or none: every registered method */
    size_t method_count;
    const char *const *cases;   /* NULL or none: "paper-quad", "random-triangles" */
    size_t case_count;
    int width, height;          /* scene cases; 0: 1024×768 */
    uint64_t seed;              /* random-triangles; 0: 1 */
    int triangles;              /* random triangles per depth-ratio group; 0: 40 */
    double rel_floor;           /* relative errors count |s| >= rel_floor (normalised units); 0: 0.01 */
    const char *heatmap_dir;    /* NULL: no heat maps; else one PNG per method and case */
    /* Sharded sweeps: with shard_count > 0 only the rows whose position in
     * the unsharded run, modulo shard_count, equals shard_index (0-based)
     * are measured. Each row is measured whole by one shard, so
     * persp_accuracy_merge of all shards equals the unsharded result. */
    int shard_index, shard_count;
} persp_accuracy_desc;

/* One method on one case. Errors of u (s1) and v (s2) separately;
 * absolute errors in texels of the case's texture. */
typedef struct persp_accuracy_row {
    char method[64];
    char case_name[48];
    double hbar;                 /* depth ratio of the random-triangles group; 0 elsewhere */
    uint64_t pixels, spans, triangles;
    double max_u, max_v, mean_u, mean_v, p99_u, p99_v;
    double texel_miss;           /* share of pixels whose nearest texel differs from the exact one's */
    double relpt_u, relpt_v;     /* max |Δs| / |s| over pixels with |s| >= rel_floor */
    double relspan_u, relspan_v; /* max |Δs| / (max s - min s) per span, spans with range >= rel_floor */
    double rel_floor;
    int ops_measured;            /* 0: the operation counts below are not available */
    double div_px, mul_px, add_px, cmp_px; /* per pixel, per-triangle and per-span work included */
} persp_accuracy_row;

typedef struct persp_accuracy_result persp_accuracy_result;

/* Runs the measurement. Unknown methods: PERSP_ERR_NOT_FOUND (bad method
 * parameters: PERSP_ERR_INVALID_ARGUMENT); unknown cases: PERSP_ERR_NOT_FOUND.
 * With no methods given, registered methods that need parameters are
 * measured with their default or skipped if they have none. */
PERSP_API persp_status persp_accuracy_run(persp_context *ctx, const persp_accuracy_desc *desc,
                                persp_accuracy_result **out);
PERSP_API size_t persp_accuracy_row_count(const persp_accuracy_result *res);
PERSP_API const persp_accuracy_row *persp_accuracy_row_at(const persp_accuracy_result *res, size_t index);
PERSP_API void persp_accuracy_destroy(persp_accuracy_result *res);

/* Reads what persp_accuracy_write wrote as JSON (a whole run or one shard).
 * PERSP_ERR_IO, PERSP_ERR_FORMAT on a malformed file. Numbers written as
 * null (NaN) read back as NaN; written rows read back bit-exact. */
PERSP_API persp_status persp_accuracy_read(persp_context *ctx, const char *path,
                                           persp_accuracy_result **out);
/* Combines the shards of one sweep (same shard_count and desc, each shard
 * once, in any order) into the result the unsharded run gives.
 * PERSP_ERR_INVALID_ARGUMENT if they are not one complete sweep. */
PERSP_API persp_status persp_accuracy_merge(persp_context *ctx,
                                            const persp_accuracy_result *const *parts,
                                            size_t count, persp_accuracy_result **out);

/* Case names for --help and validation. */
PERSP_API size_t persp_accuracy_case_count(void);
PERSP_API const char *persp_accuracy_case_name(size_t index);
PERSP_API const char *persp_accuracy_case_summary(size_t index);
/* PERSP_OK if name is a case (a fixed case or a built-in scene). */
PERSP_API persp_status persp_accuracy_case_check(const char *name);

typedef enum persp_report_format {
    PERSP_REPORT_TABLE = 0, /* aligned text with the metric definitions below it */
    PERSP_REPORT_CSV,
    PERSP_REPORT_JSON
} persp_report_format;

/* Writes the result to a stdio stream (FILE *, passed as void * so that this
 * header does not need <stdio.h>). PERSP_ERR_IO if writing fails. */
PERSP_API persp_status persp_accuracy_write(persp_context *ctx, const persp_accuracy_result *res,
                                  persp_report_format format, void *stream);
/* persp accuracy --shading (src/analysis/shading*.c): every shading mode
 * against the exact per-pixel reference (seeded random lit triangles per
 * depth ratio: colour error in 8-bit levels and normal angle error in
 * degrees; a lit scene: colour against its phong-pc render), the t_w
 * polynomial approximations of [Romanyuk-PCF] §4.3 and the ΔI analysis of §4.2
 * (Fig. 4.3-4.4), written as a text report; the figures as SVG on request. */
typedef struct persp_shading_accuracy_desc {
    uint64_t seed;        /* random triangles; 0: 1 */
    int triangles;        /* random triangles per depth-ratio group; 0: 20 */
    int width, height;    /* lit-scene image; 0: the scene's size, else 640×480 */
    const char *scene;    /* JSON scene for the lit-scene case; NULL: the built-in lit test scene */
    persp_toggle any_folder; /* ON: the scene may read files outside its folder
                                (persp_scene_load_desc); DEFAULT, OFF: it may not */
    const char *svg_path; /* NULL: no plot; else Fig. 4.3-4.4 (and t_w errors) written there */
    /* How the scene (or model) is loaded: formats, import, up axis, crease
     * (persp_scene_load_desc); NULL: the defaults. any_folder above, when
     * not DEFAULT, overrides its own. */
    const persp_scene_load_desc *load;
} persp_shading_accuracy_desc;

/* Runs every measurement and writes the report to stream (a FILE *).
 * PERSP_ERR_IO if writing the report or the SVG fails (no partial SVG is
 * left behind). */
PERSP_API persp_status persp_shading_accuracy_report(persp_context *ctx, const persp_shading_accuracy_desc *desc,
                                           void *stream);

/* ------------------------------------------------------ filter accuracy */

/* persp accuracy --filter: each texture filter (screen pipeline) and the
 * object-space pipeline ([Romaniuk-ObjSpace]) rendered at width × height and compared
 * with a reference rendered at samples × samples points per pixel (the exact
 * mapping, bilinear reconstruction on level 0), box-filtered to the pixel.
 * Cases: the built-in scenes ("corridor", "floor", "cube") and textured
 * planes tilted away from the viewer ("tilt-0" ... "tilt-85", degrees). */
typedef struct persp_filter_accuracy_desc {
    const char *const *filters; /* persp_filter_parse names, or "object" for the object-space
                                   pipeline; NULL or none: all nine filters (aniso:16,
                                   aniso-window:16) and "object" */
    size_t filter_count;
    const char *const *cases;   /* NULL or none: corridor, floor and every tilt case */
    size_t case_count;
    int width, height;          /* 0: 256×192 */
    int samples;                /* reference samples per pixel along each axis, 1..64; 0: 16 */
    int repeats;                /* timed renders per filter, the fastest kept; 0: 3
                                   (threads: the context's) */
    persp_lod_mode lod_mode;
    float lod_bias;
    const char *heatmap_dir;    /* NULL: none; else one PNG per filter and case */
} persp_filter_accuracy_desc;

typedef struct persp_filter_accuracy_row {
    char filter[32];
    char pipeline[8];            /* "screen" or "object" */
    char case_name[48];
    int tex_width, tex_height, tex_levels;
    double mip_overhead;         /* bytes of the whole mip chain / bytes of level 0, minus 1 */
    int samples;                 /* reference samples per pixel along each axis */
    uint64_t pixels;             /* covered pixels measured */
    double psnr;                 /* dB over R, G, B of covered pixels; 0 error: +inf */
    double ssim;                 /* mean SSIM of luma over 8×8 windows (stride 4) */
    double max_err, mean_err;    /* |filter - reference| in 8-bit levels, over channels */
    double fetches_px;           /* texels read per covered pixel (object: samples walked) */
    double ms, ns_px;            /* fastest render time; per pixel of the image */
} persp_filter_accuracy_row;

typedef struct persp_filter_accuracy_result persp_filter_accuracy_result;

/* Unknown filter or case: PERSP_ERR_NOT_FOUND; bad sizes or counts:
 * PERSP_ERR_INVALID_ARGUMENT. */
PERSP_API persp_status persp_filter_accuracy_run(persp_context *ctx, const persp_filter_accuracy_desc *desc,
                                       persp_filter_accuracy_result **out);
PERSP_API size_t persp_filter_accuracy_row_count(const persp_filter_accuracy_result *res);
PERSP_API const persp_filter_accuracy_row *persp_filter_accuracy_row_at(const persp_filter_accuracy_result *res,
                                                              size_t index);
PERSP_API void persp_filter_accuracy_destroy(persp_filter_accuracy_result *res);
PERSP_API size_t persp_filter_accuracy_case_count(void);
PERSP_API const char *persp_filter_accuracy_case_name(size_t index);
PERSP_API const char *persp_filter_accuracy_case_summary(size_t index);
PERSP_API persp_status persp_filter_accuracy_case_check(const char *name);
/* PERSP_OK for a filter name of persp_filter_parse or "object". */
PERSP_API persp_status persp_filter_accuracy_filter_check(const char *name);
/* Table (with definitions), CSV or JSON to a FILE * passed as void *. */
PERSP_API persp_status persp_filter_accuracy_write(persp_context *ctx, const persp_filter_accuracy_result *res,
                                         persp_report_format format, void *stream);

/* ------------------------------------------------------------ the study */

/* persp report: the whole study as one self-contained web page, dir/index.html,
 * with its images (PNG) and data (accuracy.json, filter.json) beside it and
 * the plots inline as SVG; every number is measured in the call (or read
 * from a merged sweep, from_dir/accuracy.json). */
typedef struct persp_report_html_desc {
    const char *dir;        /* created if missing */
    int quick;              /* fewer triangles and smaller images (seconds, not minutes) */
    const char *from_dir;   /* NULL: measure; else the method accuracy is read from
                               from_dir/accuracy.json (e.g. written by persp merge) */
    const char *command;    /* the command line that made the page, shown on it; NULL: none */
    const char *git_commit; /* shown with the environment; NULL: the sources
                               are no git checkout (the version names them) */
    void *log;              /* FILE * for progress lines; NULL: silent */
    /* The hardware flow's out/hw/summary.json (docs/HARDWARE.md; its
     * pareto.svg beside it is inlined when present): a section with its
     * table. NULL: no hardware section. */
    const char *hardware_summary;
} persp_report_html_desc;

PERSP_API persp_status persp_report_html(persp_context *ctx, const persp_report_html_desc *desc);

#ifdef __cplusplus
}
#endif
#endif
