/*
 * persp — perspective-correct image formation.
 *
 * The only public header of libpersp. Conventions (docs/CONVENTIONS.md):
 * OpenGL matrices (column-major, right-handed eye space looking down -z),
 * window origin bottom-left, pixel centres at (x+0.5, y+0.5), texel centres at
 * ((i+0.5)/W, (j+0.5)/H), texture row 0 = bottom row of the displayed image.
 *
 * Rules of the API: every function returning persp_status reports failure
 * through it and, when a context is given, a human-readable detail through
 * persp_context_error(). Zero-initialised desc structs mean defaults. Buffers
 * passed in are owned by the caller; objects created by persp are released by
 * their *_destroy function. There is no global mutable state.
 */
#ifndef PERSP_H
#define PERSP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PERSP_VERSION_MAJOR 0
#define PERSP_VERSION_MINOR 1
#define PERSP_VERSION_PATCH 0
#define PERSP_VERSION_STRING "0.1.0"

const char *persp_version(void);

/* ------------------------------------------------------------------ status */

typedef enum persp_status {
    PERSP_OK = 0,
    PERSP_ERR_INVALID_ARGUMENT, /* a parameter is out of range, NULL or NaN */
    PERSP_ERR_OUT_OF_MEMORY,    /* the allocator returned NULL */
    PERSP_ERR_IO,               /* a file could not be opened, read or written */
    PERSP_ERR_FORMAT,           /* a file's content is malformed */
    PERSP_ERR_TOO_LARGE,        /* a size or count exceeds persp's limits */
    PERSP_ERR_UNSUPPORTED,      /* valid input that persp does not handle */
    PERSP_ERR_NOT_FOUND,        /* an unknown name (method, filter, scene, ...) */
    PERSP_ERR_UNAVAILABLE       /* an optional component was not built */
} persp_status;

/* A static English description of a status code; never NULL. */
const char *persp_status_string(persp_status status);

/* ----------------------------------------------------------------- context */

typedef struct persp_allocator {
    void *(*alloc)(void *user, size_t size); /* 16-byte aligned or better */
    void (*free)(void *user, void *ptr);
    void *user;
} persp_allocator;

typedef struct persp_context persp_context;

typedef struct persp_context_desc {
    const persp_allocator *allocator; /* NULL: malloc/free */
    int threads;                      /* worker threads for rendering; 0 or 1: none */
} persp_context_desc;

persp_status persp_context_create(const persp_context_desc *desc, persp_context **out);
void persp_context_destroy(persp_context *ctx);
/* Detail of the last failure on this context ("file:line:col: problem"), or "". */
const char *persp_context_error(const persp_context *ctx);
/* Sets the detail message; used by persp's modules, available to callers. */
persp_status persp_context_fail(persp_context *ctx, persp_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
void *persp_alloc(persp_context *ctx, size_t size);
void persp_free(persp_context *ctx, void *ptr);

/* -------------------------------------------------------------------- math */

typedef struct persp_vec3 { float x, y, z; } persp_vec3;
typedef struct persp_vec4 { float x, y, z, w; } persp_vec4;
/* Column-major 4x4 matrix as in OpenGL: element (row r, col c) is m[c*4 + r]. */
typedef struct persp_mat4 { float m[16]; } persp_mat4;

persp_mat4 persp_mat4_identity(void);
persp_mat4 persp_mat4_mul(persp_mat4 a, persp_mat4 b); /* a·b */
persp_vec4 persp_mat4_apply(persp_mat4 m, persp_vec4 v);
persp_mat4 persp_mat4_translate(float x, float y, float z);
persp_mat4 persp_mat4_scale(float x, float y, float z);
persp_mat4 persp_mat4_rotate(float degrees, float ax, float ay, float az); /* glRotate */
/* glFrustum / gluPerspective (fovy in degrees) / gluLookAt. */
persp_mat4 persp_frustum(double l, double r, double b, double t, double n, double f);
persp_mat4 persp_perspective(double fovy_deg, double aspect, double n, double f);
persp_mat4 persp_look_at(persp_vec3 eye, persp_vec3 center, persp_vec3 up);
/* Inverse-transpose of the upper 3x3, for normals. Returns 0 if singular. */
int persp_mat4_normal_matrix(persp_mat4 m, float out3x3[9]);

/* ------------------------------------------------------------------ images */

/* An RGBA8 image; rows are bottom-to-top (row 0 = bottom), like OpenGL.
 * stride is in bytes; pixels are R,G,B,A bytes. */
typedef struct persp_image {
    int width, height;
    size_t stride;
    uint8_t *pixels;
} persp_image;

/* Largest accepted image side and pixel count (refused before allocating). */
#define PERSP_IMAGE_MAX_SIDE 16384
#define PERSP_IMAGE_MAX_PIXELS (64u * 1024u * 1024u)

/* Loads a PNG or JPEG (by content, not by name), flipped so row 0 is the
 * bottom row of the displayed image. Free with persp_image_free. */
persp_status persp_image_load(persp_context *ctx, const char *path, persp_image *out);
persp_status persp_image_load_memory(persp_context *ctx, const void *data, size_t size,
                                     const char *name, persp_image *out);
/* Zeroed pixels whose first row starts on a 64-byte boundary. */
persp_status persp_image_alloc(persp_context *ctx, int width, int height, persp_image *out);
/* Frees an image from persp_image_alloc / _load; NULL pixels are fine. */
void persp_image_free(persp_context *ctx, persp_image *img);
/* Writes a PNG, top row first. Writes to a temporary file renamed on success,
 * so a failure leaves nothing half-written. */
persp_status persp_image_write_png(persp_context *ctx, const char *path, const persp_image *img);

/* ---------------------------------------------------------------- textures */

typedef enum persp_wrap {
    PERSP_WRAP_REPEAT = 0,
    PERSP_WRAP_CLAMP_TO_EDGE,
    PERSP_WRAP_MIRRORED_REPEAT,
    PERSP_WRAP_CLAMP_TO_BORDER
} persp_wrap;

typedef enum persp_filter {
    PERSP_FILTER_NEAREST = 0,
    PERSP_FILTER_BILINEAR,
    PERSP_FILTER_NEAREST_MIP_NEAREST,
    PERSP_FILTER_BILINEAR_MIP_NEAREST,
    PERSP_FILTER_NEAREST_MIP_LINEAR,
    PERSP_FILTER_TRILINEAR,
    PERSP_FILTER_ANISO,        /* EXT_texture_filter_anisotropic, max_aniso taps */
    PERSP_FILTER_ANISO_WINDOW, /* rotated rectangular footprint, seed 000 §4.8 */
    PERSP_FILTER_EWA,          /* Heckbert's elliptical weighted average */
    PERSP_FILTER_COUNT
} persp_filter;

typedef enum persp_lod_mode {
    PERSP_LOD_PIXEL = 0, /* per pixel from the analytic Jacobian */
    PERSP_LOD_POLYGON    /* once per polygon from the texel/pixel area ratio */
} persp_lod_mode;

typedef struct persp_sampler_desc {
    persp_wrap wrap_s, wrap_t;
    persp_filter filter;
    int max_aniso;        /* 0: 16 */
    float lod_bias;
    float min_lod, max_lod; /* both 0: no clamp beyond the chain */
    persp_lod_mode lod_mode;
    uint8_t border[4];    /* RGBA for CLAMP_TO_BORDER */
} persp_sampler_desc;

/* Name <-> enum for the CLI and scene files ("repeat", "clamp-to-edge",
 * "mirrored-repeat", "clamp-to-border"; "nearest", "bilinear", "trilinear",
 * "nearest-mip-nearest", "bilinear-mip-nearest", "nearest-mip-linear",
 * "aniso:N", "aniso-window:N", "ewa"). */
persp_status persp_wrap_parse(const char *name, persp_wrap *out);
const char *persp_wrap_name(persp_wrap wrap);
persp_status persp_filter_parse(const char *name, persp_filter *out, int *max_aniso);
const char *persp_filter_name(persp_filter filter);

typedef struct persp_texture persp_texture;

/* Copies the image (row 0 = bottom) into a texture and builds its mip chain. */
persp_status persp_texture_create(persp_context *ctx, const persp_image *img,
                                  persp_texture **out);
void persp_texture_destroy(persp_texture *tex);
int persp_texture_width(const persp_texture *tex);
int persp_texture_height(const persp_texture *tex);
int persp_texture_levels(const persp_texture *tex);
/* Bytes used by all levels and by level 0 alone (mip overhead = ratio - 1). */
void persp_texture_memory(const persp_texture *tex, size_t *all_levels, size_t *base_level);
/* Level image view (not a copy, owned by the texture: never pass it to
 * persp_image_free). */
persp_status persp_texture_level(const persp_texture *tex, int level, persp_image *view);

/* Samples one texel colour at (u, v) with the given screen-space derivatives
 * of u and v (normalised coordinates). For tests and tools; the renderer
 * samples whole spans internally. */
void persp_texture_sample(const persp_texture *tex, const persp_sampler_desc *sampler, float u,
                          float v, float dudx, float dvdx, float dudy, float dvdy,
                          uint8_t rgba_out[4]);

/* -------------------------------------------------- texture-coordinate methods */

/* Operation counts, per pixel and per span, as counted by a method itself. */
typedef struct persp_opcount {
    uint64_t div, mul, add, cmp; /* divisions (incl. reciprocals), multiplications,
                                    additions/subtractions, comparisons */
    uint64_t pixels, spans, triangles;
} persp_opcount;

typedef struct persp_method_info {
    const char *name;    /* CLI id, e.g. "midpoint" */
    const char *params;  /* accepted parameters, e.g. "k=N|bidir", or "" */
    const char *summary; /* one line */
    const char *source;  /* seed and section */
    const char *cost;    /* operations per pixel / per span, e.g. "1 div, 2 mul, 3 add /px" */
} persp_method_info;

size_t persp_method_count(void);
/* Fills *out for entry index; PERSP_ERR_NOT_FOUND past the end. */
persp_status persp_method_get(size_t index, persp_method_info *out);
/* Parses "name" or "name:params"; PERSP_ERR_NOT_FOUND for an unknown name,
 * PERSP_ERR_INVALID_ARGUMENT for bad parameters. */
persp_status persp_method_check(const char *spec);

/* ----------------------------------------------------------------- shading */

typedef enum persp_shading {
    PERSP_SHADING_NONE = 0, /* texture (or vertex colour) only */
    PERSP_SHADING_FLAT,
    PERSP_SHADING_GOURAUD,
    PERSP_SHADING_GOURAUD_PC,
    PERSP_SHADING_PHONG,
    PERSP_SHADING_PHONG_PC,
    PERSP_SHADING_PHONG_PC_QUAD,
    PERSP_SHADING_PHONG_PC_PWQUAD,
    PERSP_SHADING_PHONG_PC_CUBIC,
    PERSP_SHADING_PHONG_SLERP,
    PERSP_SHADING_PHONG_SLERP_SCREEN,
    PERSP_SHADING_COUNT
} persp_shading;

persp_status persp_shading_parse(const char *name, persp_shading *out);
const char *persp_shading_name(persp_shading shading);

/* ------------------------------------------------------------- framebuffer */

typedef enum persp_depth_mode {
    PERSP_DEPTH_Z = 0, /* window depth in [0,1], less passes, cleared to 1 */
    PERSP_DEPTH_INVW   /* 1/w ("1/z buffering", seed 002): greater passes, cleared to 0 */
} persp_depth_mode;

/* Caller-owned buffers: color is width*height RGBA8 pixels (row 0 = bottom),
 * depth is width*height floats. Any alignment works; buffers aligned to 64
 * bytes render faster with several threads (tiles drawn at once then share
 * no cache line). */
typedef struct persp_framebuffer {
    int width, height;
    uint8_t *color;
    float *depth;
} persp_framebuffer;

void persp_framebuffer_clear(persp_framebuffer *fb, const uint8_t rgba[4], persp_depth_mode mode);

/* ------------------------------------------------------------------ scenes */

typedef struct persp_scene persp_scene;

/* Built-in scenes: "corridor" (../BENCHMARKS.md), "floor", "cube". */
size_t persp_builtin_scene_count(void);
const char *persp_builtin_scene_name(size_t index);
const char *persp_builtin_scene_summary(size_t index);
persp_status persp_scene_builtin(persp_context *ctx, const char *name, persp_scene **out);
/* Loads a JSON scene file; paths inside resolve relative to it. */
persp_status persp_scene_load(persp_context *ctx, const char *path, persp_scene **out);
void persp_scene_destroy(persp_scene *scene);
/* Replaces the texture of every textured object (e.g. --texture FILE). */
persp_status persp_scene_set_texture(persp_scene *scene, const persp_image *img);
/* The scene's preferred image size (0 if none). */
void persp_scene_default_size(const persp_scene *scene, int *width, int *height);

/* What a scene renders with when persp_render_desc overrides nothing, for
 * reports: the default shading and the filter of its textured objects
 * (filter_count 0: untextured; more than 1: objects differ, filter is the
 * first one's). */
typedef struct persp_scene_info {
    size_t objects, textures, lights;
    persp_shading shading;
    int filter_count;
    persp_filter filter;
    int max_aniso;
} persp_scene_info;
void persp_scene_get_info(const persp_scene *scene, persp_scene_info *out);

typedef enum persp_pipeline {
    PERSP_PIPELINE_SCREEN = 0, /* inverse mapping per pixel */
    PERSP_PIPELINE_OBJECT      /* object-space texturing, screen-space filtering (seed 004) */
} persp_pipeline;

/* Render settings; zero fields keep the scene's own (or persp's default). */
typedef struct persp_render_desc {
    const char *method;      /* texture-coordinate method spec; NULL: "exact" */
    int filter_set;          /* nonzero: override every texture's filter */
    persp_filter filter;
    int max_aniso;
    int wrap_set;            /* nonzero: override every texture's wrap mode */
    persp_wrap wrap;
    int shading_set;
    persp_shading shading;
    persp_depth_mode depth_mode;
    persp_lod_mode lod_mode;
    float lod_bias;
    int lod_clamp_set;       /* nonzero: clamp every texture's lambda to [min_lod, max_lod] */
    float min_lod, max_lod;
    persp_pipeline pipeline;
    int threads;             /* 0: the context's */
    int cull_backfaces;      /* -1: off, 1: on, 0: scene default */
    int count_ops;           /* nonzero: the methods count their operations into
                                persp_render_stats.ops (instrumented render) */
} persp_render_desc;

typedef struct persp_render_stats {
    uint64_t triangles_in, triangles_drawn, fragments, pixels_written;
    persp_opcount ops; /* with persp_render_desc.count_ops: the operations of the
                          texture-coordinate method over the frame (per-triangle
                          fits, spans, pixels, traversals); zero otherwise */
    /* Object-space pipeline (seed 004): samples walked (texels or sub-texel
     * positions of the chosen levels), splats onto pixels, polygon pieces
     * (one mip level each), covered pixels that received no sample. */
    uint64_t objspace_samples, objspace_splats, objspace_pieces, objspace_holes;
} persp_render_stats;

/* Clears fb and renders the scene into it. */
persp_status persp_render(persp_context *ctx, const persp_scene *scene, const persp_render_desc *desc,
                          persp_framebuffer *fb, persp_render_stats *stats);

/* ------------------------------------------------- immediate triangle drawing */

/* A vertex for persp_draw: object-space position, texture coordinate,
 * normal and colour. */
typedef struct persp_vertex {
    float pos[3];
    float uv[2];
    float normal[3];
    float color[4];
} persp_vertex;

typedef struct persp_draw_desc {
    persp_mat4 mvp;           /* clip = mvp · pos */
    const persp_texture *texture; /* NULL: vertex colour */
    persp_sampler_desc sampler;
    const char *method;       /* NULL: "exact" */
    persp_depth_mode depth_mode;
    int cull_backfaces;
    int depth_test;           /* 0: on (less / greater for INVW), -1: off */
} persp_draw_desc;

/* Draws indexed triangles (3 indices each) into fb without clearing it. */
persp_status persp_draw(persp_context *ctx, persp_framebuffer *fb, const persp_draw_desc *desc,
                        const persp_vertex *vertices, size_t vertex_count, const uint32_t *indices,
                        size_t index_count);

/* --------------------------------------------------------------- analysis */
/* @section analysis (src/analysis): accuracy measurement API. */

/* persp accuracy: every texture-coordinate method measured against the exact
 * rational form (Heckbert 1989 §2.3.2) evaluated in double precision at each
 * pixel centre. Cases (BENCHMARKS.md): "paper-quad" (seed 000 §4.6 Fig. 4.10:
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
persp_status persp_accuracy_run(persp_context *ctx, const persp_accuracy_desc *desc,
                                persp_accuracy_result **out);
size_t persp_accuracy_row_count(const persp_accuracy_result *res);
const persp_accuracy_row *persp_accuracy_row_at(const persp_accuracy_result *res, size_t index);
void persp_accuracy_destroy(persp_accuracy_result *res);

/* Case names for --help and validation. */
size_t persp_accuracy_case_count(void);
const char *persp_accuracy_case_name(size_t index);
const char *persp_accuracy_case_summary(size_t index);
/* PERSP_OK if name is a case (a fixed case or a built-in scene). */
persp_status persp_accuracy_case_check(const char *name);

typedef enum persp_report_format {
    PERSP_REPORT_TABLE = 0, /* aligned text with the metric definitions below it */
    PERSP_REPORT_CSV,
    PERSP_REPORT_JSON
} persp_report_format;

/* Writes the result to a stdio stream (FILE *, passed as void * so that this
 * header does not need <stdio.h>). PERSP_ERR_IO if writing fails. */
persp_status persp_accuracy_write(persp_context *ctx, const persp_accuracy_result *res,
                                  persp_report_format format, void *stream);
/* persp accuracy --shading (src/analysis/shading*.c): every shading mode
 * against the exact per-pixel reference (seeded random lit triangles per
 * depth ratio: colour error in 8-bit levels and normal angle error in
 * degrees; a lit scene: colour against its phong-pc render), the t_w
 * polynomial approximations of seed 000 §4.3 and the ΔI analysis of §4.2
 * (Fig. 4.3-4.4), written as a text report; the figures as SVG on request. */
typedef struct persp_shading_accuracy_desc {
    uint64_t seed;        /* random triangles; 0: 1 */
    int triangles;        /* random triangles per depth-ratio group; 0: 20 */
    int width, height;    /* lit-scene image; 0: the scene's size, else 640×480 */
    const char *scene;    /* JSON scene for the lit-scene case; NULL: the built-in lit test scene */
    const char *svg_path; /* NULL: no plot; else Fig. 4.3-4.4 (and t_w errors) written there */
} persp_shading_accuracy_desc;

/* Runs every measurement and writes the report to stream (a FILE *).
 * PERSP_ERR_IO if writing the report or the SVG fails (no partial SVG is
 * left behind). */
persp_status persp_shading_accuracy_report(persp_context *ctx, const persp_shading_accuracy_desc *desc,
                                           void *stream);
/* @end analysis */

/* ------------------------------------------------------ filter accuracy */
/* @section filtering (src/analysis/filtering.c): texture filters measured
 * against a supersampled reference. */

/* persp accuracy --filter: each texture filter (screen pipeline) and the
 * object-space pipeline (seed 004) rendered at width × height and compared
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
    int repeats;                /* timed renders per filter, the fastest kept; 0: 3 */
    int threads;                /* 0: 1 */
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
persp_status persp_filter_accuracy_run(persp_context *ctx, const persp_filter_accuracy_desc *desc,
                                       persp_filter_accuracy_result **out);
size_t persp_filter_accuracy_row_count(const persp_filter_accuracy_result *res);
const persp_filter_accuracy_row *persp_filter_accuracy_row_at(const persp_filter_accuracy_result *res,
                                                              size_t index);
void persp_filter_accuracy_destroy(persp_filter_accuracy_result *res);
size_t persp_filter_accuracy_case_count(void);
const char *persp_filter_accuracy_case_name(size_t index);
const char *persp_filter_accuracy_case_summary(size_t index);
persp_status persp_filter_accuracy_case_check(const char *name);
/* PERSP_OK for a filter name of persp_filter_parse or "object". */
persp_status persp_filter_accuracy_filter_check(const char *name);
/* Table (with definitions), CSV or JSON to a FILE * passed as void *. */
persp_status persp_filter_accuracy_write(persp_context *ctx, const persp_filter_accuracy_result *res,
                                         persp_report_format format, void *stream);
/* @end filtering */

/* -------------------------------------------------------------- benchmark */
/* @section bench (bench/, src/analysis/bench*.c): benchmark API. */
/* @end bench */

#ifdef __cplusplus
}
#endif
#endif
