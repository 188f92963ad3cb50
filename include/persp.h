/*
 * persp — perspective-correct image formation.
 *
 * The public header of libpersp (citation keys such as [Romanyuk-PCF] are
 * defined in docs/SOURCES.md). Conventions (docs/CONVENTIONS.md):
 * OpenGL matrices (column-major, right-handed eye space looking down -z),
 * window origin bottom-left, pixel centres at (x+0.5, y+0.5), texel centres at
 * ((i+0.5)/W, (j+0.5)/H), texture row 0 = bottom row of the displayed image.
 *
 * The measurement API (accuracy of methods, shading and filters) is in
 * persp_analysis.h and its own library, persp_analysis.
 *
 * Rules of the API
 * - Status: every function returning persp_status reports failure through
 *   it and, when a context is given, a one-line detail through
 *   persp_context_error() ("file:line:col: problem" for files).
 * - Defaults: a zero-initialised desc struct means "all defaults". Every enum
 *   has a *_DEFAULT = 0 value; in persp_render_desc it keeps what the scene
 *   chose, elsewhere it selects the default that the field's comment names.
 *   On/off settings use persp_toggle, whose zero is likewise DEFAULT.
 * - Ownership: buffers passed in stay the caller's and are only read or
 *   written during the call. Objects persp creates (context, scene, texture,
 *   images from persp_image_alloc/_load) are the caller's to release with the
 *   matching *_destroy / *_free, which accept NULL; views (persp_image_view) point into an
 *   object and live as long as it. Every buffer persp returns or keeps
 *   comes from the context's allocator. The file-format libraries it calls
 *   (libpng's simplified API, libjpeg, jansson, the model importer)
 *   allocate their transient working memory with malloc while a load or
 *   write runs, since their APIs take no per-call allocator; with a memory
 *   budget (persp_context_desc.max_memory) persp reserves their bounded or
 *   measured need from it before they start (docs/RELIABILITY.md).
 * - Threads: a persp_context is used by one thread at a time (it holds the
 *   last error, the worker pool and the per-frame buffers); to render from
 *   several threads at once, give each its own context. Textures and scenes
 *   are read-only while rendering: one may be shared by any number of
 *   contexts and threads at once, provided nothing modifies or destroys it
 *   meanwhile (persp_scene_set_texture modifies). Functions without a
 *   context argument are safe to call from any thread, except those that
 *   create or free memory of a scene or texture (persp_scene_set_texture,
 *   persp_scene_tint_mip_levels, persp_scene_destroy, persp_texture_destroy):
 *   they use the context that made it, so call them where that context
 *   may be used (not while it renders on another thread). A context's own
 *   worker threads (persp_context_desc.threads) parallelise one render; the
 *   image is bit-identical for any thread count. persp keeps no global
 *   mutable state of its own; the one process-wide object is the mutex that
 *   makes model imports in the caller's process take turns, because the
 *   model importer's C API reports errors through one process-wide message
 *   (persp_scene_load; imports in persp-import, the default, run at once).
 */
#ifndef PERSP_H
#define PERSP_H

#include <stddef.h>
#include <stdint.h>

/* Symbols of the public API are the only ones a shared libpersp exports. */
#if defined(_WIN32) && defined(PERSP_SHARED_BUILD)
#define PERSP_API __declspec(dllexport)
#elif defined(__GNUC__) || defined(__clang__)
#define PERSP_API __attribute__((visibility("default")))
#else
#define PERSP_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

#define PERSP_VERSION_MAJOR 0
#define PERSP_VERSION_MINOR 1
#define PERSP_VERSION_PATCH 0
#define PERSP_VERSION_STRING "0.1.0"
/* One number for comparisons: major * 10000 + minor * 100 + patch. */
#define PERSP_VERSION (PERSP_VERSION_MAJOR * 10000 + PERSP_VERSION_MINOR * 100 + PERSP_VERSION_PATCH)

/* The library's version string, which may differ from the header's
 * PERSP_VERSION_STRING when a program runs against another build. */
PERSP_API const char *persp_version(void);

/* On/off settings. DEFAULT (zero) keeps what the field's comment names. */
typedef enum persp_toggle {
    PERSP_TOGGLE_DEFAULT = 0,
    PERSP_TOGGLE_ON,
    PERSP_TOGGLE_OFF
} persp_toggle;

/* ------------------------------------------------------------------ status */

typedef enum persp_status {
    PERSP_OK = 0,
    PERSP_ERR_INVALID_ARGUMENT, /* a parameter is out of range, NULL or NaN */
    PERSP_ERR_OUT_OF_MEMORY,    /* the allocator returned NULL, or the context's memory
                                   budget (persp_context_desc.max_memory) would be exceeded */
    PERSP_ERR_IO,               /* a file could not be opened, read or written */
    PERSP_ERR_FORMAT,           /* a file's content is malformed */
    PERSP_ERR_TOO_LARGE,        /* a size or count exceeds persp's limits */
    PERSP_ERR_UNSUPPORTED,      /* valid input that persp does not handle */
    PERSP_ERR_NOT_FOUND,        /* an unknown name (method, filter, scene, ...) */
    PERSP_ERR_UNAVAILABLE       /* an optional component was not built */
} persp_status;

/* A static English description of a status code; never NULL. */
PERSP_API const char *persp_status_string(persp_status status);

/* ----------------------------------------------------------------- context */

/* Called only from the thread that called into persp (never from a
 * context's worker threads), so it needs no locking for one context. */
typedef struct persp_allocator {
    void *(*alloc)(void *user, size_t size); /* 16-byte aligned or better */
    void (*free)(void *user, void *ptr);
    void *user;
} persp_allocator;

typedef struct persp_context persp_context;

/* Instruction-set variant of the texture span samplers and the lane packing,
 * and the vector width (baseline, AVX2 or AVX-512) of the vertex stage and
 * the lighting loops (docs/PERFORMANCE.md, "On an Intel Xeon: samplers
 * with gathers, 16 threads"; docs/PERFORMANCE_HISTORY.md, item 58). AUTO
 * times the samplers' variant and the lighting loops' width apart
 * (persp_context_simd, persp_context_lighting_simd); the vertex stage
 * takes the lighting loops'. Every
 * variant computes the same bits; they differ only in speed, which depends on the CPU (the texel
 * fetch by gather instructions is fast on some cores and slow on others;
 * 512-bit arithmetic may lower the clock of some). The other span loops take AVX2 wherever the CPU has
 * it, chosen by the dynamic loader. */
typedef enum persp_simd {
    PERSP_SIMD_AUTO = 0,      /* the fastest samplers and lighting loops for this CPU, timed at the first frame */
    PERSP_SIMD_BASELINE,      /* x86-64 baseline (SSE2), or plain C elsewhere */
    PERSP_SIMD_AVX2,          /* 8 lanes, texels fetched by scalar loads */
    PERSP_SIMD_AVX2_GATHER,   /* 8 lanes, texels fetched by vpgatherdd */
    PERSP_SIMD_AVX512,        /* 16 lanes, texels fetched by scalar loads */
    PERSP_SIMD_AVX512_GATHER  /* 16 lanes, texels fetched by vpgatherdd */
} persp_simd;

/* "auto", "baseline", "avx2", "avx2-gather", "avx512", "avx512-gather";
 * "?" for a value outside the enum. */
PERSP_API const char *persp_simd_name(persp_simd simd);
/* PERSP_ERR_NOT_FOUND for an unknown name. */
PERSP_API persp_status persp_simd_parse(const char *name, persp_simd *out);

typedef struct persp_context_desc {
    const persp_allocator *allocator; /* NULL: malloc/free; copied, need not outlive the call */
    int threads;                      /* threads drawing each render, the caller's included,
                                         1..256; 0: 1 */
    /* Memory budget in bytes for everything persp holds at once through this
     * context: its own allocations (scenes, textures with their mip chains,
     * images, per-frame buffers) and the working memory of the file-format
     * libraries while they read (bounded or estimated before they start,
     * docs/RELIABILITY.md). A request that would exceed it fails before
     * anything is allocated, with PERSP_ERR_OUT_OF_MEMORY and a detail naming
     * what and how much. 0: no budget (only the allocator's own limit): a
     * library cannot know how much of the machine its caller means to give
     * it, and persp's fixed size limits already bound each input. */
    size_t max_memory;
    /* PERSP_SIMD_AUTO (0): chosen for the CPU. A variant this CPU (or this
     * build) cannot run: PERSP_ERR_UNSUPPORTED from persp_context_create. */
    persp_simd simd;
} persp_context_desc;

/* desc may be NULL (all defaults). */
PERSP_API persp_status persp_context_create(const persp_context_desc *desc, persp_context **out);
/* Stops the worker threads and frees everything the context holds; objects
 * created with it (scenes, textures, images) must be released first. */
PERSP_API void persp_context_destroy(persp_context *ctx);
/* Detail of the last failure on this context ("file:line:col: problem"), or
 * "". Owned by the context, valid until its next call. */
PERSP_API const char *persp_context_error(const persp_context *ctx);
/* The vector variant the context uses (never PERSP_SIMD_AUTO for a
 * context). For PERSP_SIMD_AUTO the first call, or the first render,
 * decides it by timing the candidates for a fraction of a millisecond. */
PERSP_API persp_simd persp_context_simd(persp_context *ctx);
/* The variant of the lighting loops (per-vertex and per-pixel Blinn-Phong,
 * Gouraud's colours) and of the vertex stage: the context's for a variant
 * given; for PERSP_SIMD_AUTO, timed apart from the samplers'
 * (PERSP_SIMD_AVX512 only where the CPU has it and it wins, else AVX2 or
 * the baseline), as the two need not agree on one CPU. */
PERSP_API persp_simd persp_context_lighting_simd(persp_context *ctx);
/* Warnings: problems persp worked around (a model's missing material or
 * texture file, for instance), one line each without a trailing newline.
 * persp never prints; without a handler warnings are dropped. Called on the
 * thread that called into persp; fn NULL removes the handler. */
typedef void (*persp_warning_fn)(void *user, const char *message);
PERSP_API void persp_context_set_warning_handler(persp_context *ctx, persp_warning_fn fn,
                                                 void *user);
/* Files persp writes (images, reports) go to a temporary file renamed over
 * the target at the end. The handler hears the temporary file's path once
 * it exists and NULL once it is renamed or removed, so that a program can
 * remove it when a signal ends it mid-write (the path is valid until the
 * NULL call; copy it). persp installs no signal handlers itself, but holds
 * every signal off the calling thread from the moment it creates the file
 * until the handler has heard of it, so that a handler never misses a file
 * that exists (a program whose other threads may receive the signal should
 * pass it on to this one). Called on the thread that called into persp; fn
 * NULL removes the handler. */
typedef void (*persp_temp_file_fn)(void *user, const char *path);
PERSP_API void persp_context_set_temp_file_handler(persp_context *ctx, persp_temp_file_fn fn,
                                                   void *user);

/* -------------------------------------------------------------------- math */

typedef struct persp_vec3 { float x, y, z; } persp_vec3;
typedef struct persp_vec4 { float x, y, z, w; } persp_vec4;
/* Column-major 4x4 matrix as in OpenGL: element (row r, col c) is m[c*4 + r]. */
typedef struct persp_mat4 { float m[16]; } persp_mat4;

PERSP_API persp_mat4 persp_mat4_identity(void);
PERSP_API persp_mat4 persp_mat4_mul(persp_mat4 a, persp_mat4 b); /* a·b */
PERSP_API persp_vec4 persp_mat4_apply(persp_mat4 m, persp_vec4 v);
PERSP_API persp_mat4 persp_mat4_translate(float x, float y, float z);
PERSP_API persp_mat4 persp_mat4_scale(float x, float y, float z);
PERSP_API persp_mat4 persp_mat4_rotate(float degrees, float ax, float ay, float az); /* glRotate */
/* glFrustum / gluPerspective (fovy in degrees) / gluLookAt. Arguments GL
 * refuses (n or f not positive, l = r, b = t, n = f) give a matrix of NaN,
 * which persp_render and persp_draw refuse as not finite. */
PERSP_API persp_mat4 persp_frustum(double l, double r, double b, double t, double n, double f);
PERSP_API persp_mat4 persp_perspective(double fovy_deg, double aspect, double n, double f);
PERSP_API persp_mat4 persp_look_at(persp_vec3 eye, persp_vec3 center, persp_vec3 up);
/* Inverse-transpose of the upper 3x3, for normals. Returns 0 if singular
 * or out3x3 is NULL. */
PERSP_API int persp_mat4_normal_matrix(persp_mat4 m, float out3x3[9]);
/* Determinant of the upper 3x3 (in double). Negative: m mirrors, and an
 * object it places has its front faces clockwise in the window (the glTF
 * rule), which culling follows. */
PERSP_API double persp_mat4_det3(persp_mat4 m);

/* ------------------------------------------------------------------ images */

/* An RGBA8 image; rows are bottom-to-top (row 0 = bottom), like OpenGL.
 * stride is in bytes; pixels are R,G,B,A bytes. Filled by persp_image_alloc
 * or persp_image_load it owns its pixels (release with persp_image_free,
 * through the same context); filled in by the caller it borrows the
 * caller's pixels, which persp only reads and never frees. */
typedef struct persp_image {
    int width, height;
    size_t stride;
    uint8_t *pixels;
} persp_image;

/* A read-only view of pixels that belong to a persp object (a texture's mip
 * level); valid as long as that object. Never freed. */
typedef struct persp_image_view {
    int width, height;
    size_t stride;
    const uint8_t *pixels;
} persp_image_view;

/* Largest accepted image side and pixel count (refused before allocating). */
#define PERSP_IMAGE_MAX_SIDE 16384
#define PERSP_IMAGE_MAX_PIXELS (64u * 1024u * 1024u)

/* Loads a PNG, JPEG or BMP (by content, not by name) or a TGA (by its
 * .tga name, or a consistent TGA header: the format has no signature),
 * flipped so row 0 is the bottom row of the displayed image
 * (docs/TEXTURES.md, "Image files"). Free with persp_image_free. */
PERSP_API persp_status persp_image_load(persp_context *ctx, const char *path, persp_image *out);
PERSP_API persp_status persp_image_load_memory(persp_context *ctx, const void *data, size_t size,
                                     const char *name, persp_image *out);
/* Zeroed pixels whose first row starts on a 64-byte boundary. */
PERSP_API persp_status persp_image_alloc(persp_context *ctx, int width, int height, persp_image *out);
/* Frees an image from persp_image_alloc / _load made with this context;
 * NULL pixels are fine. The context records the pixels it allocated, so
 * borrowed pixels (an image the caller filled in) or another context's are
 * recognised without reading them: they are left as they are, img is
 * unchanged and persp_context_error() says so. */
PERSP_API void persp_image_free(persp_context *ctx, persp_image *img);
/* Writes a PNG, top row first. Writes to a temporary file renamed on success,
 * so a failure leaves nothing half-written. */
PERSP_API persp_status persp_image_write_png(persp_context *ctx, const char *path, const persp_image *img);

/* Encoded image formats. */
typedef enum persp_image_format {
    PERSP_IMAGE_FORMAT_DEFAULT = 0, /* by the path's extension; PNG for a stream */
    PERSP_IMAGE_FORMAT_PNG,
    PERSP_IMAGE_FORMAT_JPEG /* baseline, no chroma subsampling; alpha is dropped */
} persp_image_format;

#define PERSP_JPEG_QUALITY_DEFAULT 92

/* Zero-initialised: format by extension, JPEG quality 92. */
typedef struct persp_image_write_desc {
    persp_image_format format;
    int quality; /* JPEG quality 1..100 (libjpeg's scale); 0: PERSP_JPEG_QUALITY_DEFAULT.
                    Ignored for PNG. */
} persp_image_write_desc;

/* The format a file name's extension names: ".png"; ".jpg", ".jpeg" (any
 * case). PERSP_ERR_UNSUPPORTED for any other extension or none. */
PERSP_API persp_status persp_image_format_from_path(const char *path, persp_image_format *out);
/* Writes a JPEG, top row first, atomically like persp_image_write_png.
 * quality 1..100; 0: PERSP_JPEG_QUALITY_DEFAULT. */
PERSP_API persp_status persp_image_write_jpeg(persp_context *ctx, const char *path,
                                              const persp_image *img, int quality);
/* Writes a PNG or JPEG as desc says (NULL: all defaults, the format by the
 * path's extension; PERSP_ERR_UNSUPPORTED, and no file, for an unknown one,
 * except that an existing device or pipe without one gets a PNG).
 * A regular file (or a link to one) is replaced atomically: the image goes
 * to a temporary file in the same folder, renamed on success and removed on
 * failure (persp_context_set_temp_file_handler hears of it). The replacement
 * keeps the old file's permission bits; through a link the file it points
 * to is replaced and the link stays; other hard links to the old file keep
 * the old content. A read-only file (no write permission bit, whoever runs
 * persp), a folder and a link to nothing are refused with PERSP_ERR_IO. Any
 * other existing file (a device such as /dev/null, a pipe) is opened and
 * written in place. */
PERSP_API persp_status persp_image_write(persp_context *ctx, const char *path,
                                         const persp_image *img,
                                         const persp_image_write_desc *desc);
/* Writes a PNG or JPEG to a stdio stream (FILE *, passed as void * so that
 * this header does not need <stdio.h>) and flushes it; desc NULL or format
 * DEFAULT: PNG. name is used in the error detail (NULL: "<stream>").
 * PERSP_ERR_IO if writing fails; what was written up to then stays in the
 * stream. */
PERSP_API persp_status persp_image_write_stream(persp_context *ctx, void *stream, const char *name,
                                                const persp_image *img,
                                                const persp_image_write_desc *desc);

/* ---------------------------------------------------------------- textures */

typedef enum persp_wrap {
    PERSP_WRAP_DEFAULT = 0, /* sampler: REPEAT (GL's default); render desc: the scene's */
    PERSP_WRAP_REPEAT,
    PERSP_WRAP_CLAMP_TO_EDGE,
    PERSP_WRAP_MIRRORED_REPEAT,
    PERSP_WRAP_CLAMP_TO_BORDER
} persp_wrap;

typedef enum persp_filter {
    PERSP_FILTER_DEFAULT = 0, /* sampler: BILINEAR; render desc: the scene's */
    PERSP_FILTER_NEAREST,
    PERSP_FILTER_BILINEAR,
    PERSP_FILTER_NEAREST_MIP_NEAREST,
    PERSP_FILTER_BILINEAR_MIP_NEAREST,
    PERSP_FILTER_NEAREST_MIP_LINEAR,
    PERSP_FILTER_TRILINEAR,
    PERSP_FILTER_ANISO,        /* EXT_texture_filter_anisotropic, max_aniso taps */
    PERSP_FILTER_ANISO_WINDOW, /* rotated rectangular footprint, [Romanyuk-PCF] §4.8 */
    PERSP_FILTER_EWA,          /* Heckbert's elliptical weighted average */
    PERSP_FILTER_COUNT
} persp_filter;

typedef enum persp_lod_mode {
    PERSP_LOD_DEFAULT = 0, /* sampler: PIXEL; render desc: the texture's */
    PERSP_LOD_PIXEL,     /* per pixel from the analytic Jacobian */
    PERSP_LOD_POLYGON    /* once per polygon from the texel/pixel area ratio */
} persp_lod_mode;

/* The most taps of the anisotropic filters ("aniso:N", N = 2..16), and
 * their number where max_aniso is 0. */
#define PERSP_MAX_ANISO 16
/* The bound of the level-of-detail clamp: OpenGL's defaults of
 * TEXTURE_MIN_LOD and TEXTURE_MAX_LOD are -1000 and 1000 (OpenGL 4.6 core
 * profile, Table 23.19), and min_lod, max_lod lie in [-1000, 1000]. */
#define PERSP_LOD_LIMIT 1000.0f

/* Zero-initialised: bilinear, repeat, no LOD bias or clamp. */
typedef struct persp_sampler_desc {
    persp_wrap wrap_s, wrap_t;
    persp_filter filter;
    int max_aniso;          /* taps of the anisotropic filters, 2..16 (as "aniso:N"); 0: 16 */
    float lod_bias;
    persp_toggle lod_clamp; /* ON: clamp lambda to [min_lod, max_lod]; DEFAULT, OFF: only
                               to the mip chain (GL's -1000, 1000) */
    float min_lod, max_lod;
    persp_lod_mode lod_mode;
    uint8_t border[4];      /* RGBA for CLAMP_TO_BORDER */
} persp_sampler_desc;

/* Name <-> enum for the CLI and scene files ("repeat", "clamp-to-edge",
 * "mirrored-repeat", "clamp-to-border"; "nearest", "bilinear", "trilinear",
 * "nearest-mip-nearest", "bilinear-mip-nearest", "nearest-mip-linear",
 * "aniso:N", "aniso-window:N", "ewa"; "default" for the DEFAULT values).
 * Names are static strings; "unknown" for values out of range. */
PERSP_API persp_status persp_wrap_parse(const char *name, persp_wrap *out);
PERSP_API const char *persp_wrap_name(persp_wrap wrap);
/* max_aniso may be NULL; set to N for "aniso:N" / "aniso-window:N", else 16. */
PERSP_API persp_status persp_filter_parse(const char *name, persp_filter *out, int *max_aniso);
PERSP_API const char *persp_filter_name(persp_filter filter);

typedef struct persp_texture persp_texture;

/* Copies the image (row 0 = bottom) into a texture and builds its mip chain. */
/* The texture keeps no reference to img. Release with persp_texture_destroy
 * before the context. */
PERSP_API persp_status persp_texture_create(persp_context *ctx, const persp_image *img,
                                            persp_texture **out);
PERSP_API void persp_texture_destroy(persp_texture *tex);
PERSP_API int persp_texture_width(const persp_texture *tex);
PERSP_API int persp_texture_height(const persp_texture *tex);
PERSP_API int persp_texture_levels(const persp_texture *tex);
/* Bytes used by all levels and by level 0 alone (mip overhead = ratio - 1). */
PERSP_API void persp_texture_memory(const persp_texture *tex, size_t *all_levels, size_t *base_level);
/* A view of one mip level's texels, valid as long as the texture. */
PERSP_API persp_status persp_texture_level(const persp_texture *tex, int level, persp_image_view *view);

/* Samples one texel colour at (u, v) with the given screen-space derivatives
 * of u and v (normalised coordinates). For tests and tools; the renderer
 * samples whole spans internally. A NULL texture or sampler, or a sampler
 * out of range, gives transparent black (0, 0, 0, 0). */
PERSP_API void persp_texture_sample(const persp_texture *tex, const persp_sampler_desc *sampler, float u,
                          float v, float dudx, float dvdx, float dudy, float dvdy,
                          uint8_t rgba_out[4]);

/* -------------------------------------------------- texture-coordinate methods */

/* Operation counts, per pixel and per span, as counted by a method itself. */
typedef struct persp_opcount {
    uint64_t div, mul, add, cmp; /* divisions (incl. reciprocals), multiplications,
                                    additions/subtractions, comparisons */
    uint64_t pixels, spans, triangles; /* in a render: the pixels and spans the method
                                          computed coordinates for (spans hidden whole run
                                          none); triangles only in the analyses */
} persp_opcount;

typedef struct persp_method_info {
    const char *name;    /* CLI id, e.g. "midpoint" */
    const char *params;  /* accepted parameters, e.g. "k=N|bidir", or "" */
    const char *summary; /* one line */
    const char *source;  /* citation key and section (docs/SOURCES.md) */
    const char *cost;    /* operations per pixel / per span, e.g. "1 div, 2 mul, 3 add /px" */
} persp_method_info;

PERSP_API size_t persp_method_count(void);
/* Fills *out for entry index (static strings); PERSP_ERR_NOT_FOUND past the end. */
PERSP_API persp_status persp_method_get(size_t index, persp_method_info *out);
/* Parses "name" or "name:params"; PERSP_ERR_NOT_FOUND for an unknown name,
 * PERSP_ERR_INVALID_ARGUMENT for bad parameters. */
PERSP_API persp_status persp_method_check(const char *spec);

/* ----------------------------------------------------------------- shading */

typedef enum persp_shading {
    PERSP_SHADING_DEFAULT = 0, /* render desc: the scene's; elsewhere NONE */
    PERSP_SHADING_NONE,     /* texture (or vertex colour) only */
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

PERSP_API persp_status persp_shading_parse(const char *name, persp_shading *out);
PERSP_API const char *persp_shading_name(persp_shading shading);

/* ------------------------------------------------------------- framebuffer */

typedef enum persp_depth_mode {
    PERSP_DEPTH_DEFAULT = 0, /* Z */
    PERSP_DEPTH_Z,     /* window depth in [0,1], less passes, cleared to 1 */
    PERSP_DEPTH_INVW   /* 1/w ("1/z buffering", [CS300-TexMap]): greater passes, cleared to 0 */
} persp_depth_mode;

/* Caller-owned buffers: color is width*height RGBA8 pixels (row 0 = bottom),
 * depth is width*height floats. Any alignment works; buffers aligned to 64
 * bytes render faster with several threads (tiles drawn at once then share
 * no cache line). The size limits are an image's (PERSP_IMAGE_MAX_SIDE,
 * PERSP_IMAGE_MAX_PIXELS: PERSP_ERR_TOO_LARGE beyond them). */
typedef struct persp_framebuffer {
    int width, height;
    uint8_t *color;
    float *depth;
} persp_framebuffer;

PERSP_API void persp_framebuffer_clear(persp_framebuffer *fb, const uint8_t rgba[4], persp_depth_mode mode);

/* ------------------------------------------------------------------ scenes */

typedef struct persp_scene persp_scene;

/* Built-in scenes: "corridor" (the reference workload, docs/WORKLOADS.md),
 * "floor", "cube". */
PERSP_API size_t persp_builtin_scene_count(void);
/* Static strings; NULL past the end. */
PERSP_API const char *persp_builtin_scene_name(size_t index);
PERSP_API const char *persp_builtin_scene_summary(size_t index);
/* A scene owns its meshes, materials and textures; release it with
 * persp_scene_destroy before its context. */
PERSP_API persp_status persp_scene_builtin(persp_context *ctx, const char *name, persp_scene **out);
/* Loads a JSON scene file (paths inside resolve relative to it), or a model
 * file in any format Assimp reads (OBJ, glTF/GLB, PLY, STL, FBX, ...) shown
 * with a default camera and lights (docs/SCENES.md). Problems worked around
 * (a model's missing texture or material file) go to the warning handler
 * once the file has loaded; a load that fails gives its error alone.
 * Models other than OBJ are read in a helper process with limits
 * (persp_model_import). The files a scene or model
 * names must lie in the loaded file's folder or below it; see
 * persp_scene_load_ex to allow more. */
PERSP_API persp_status persp_scene_load(persp_context *ctx, const char *path, persp_scene **out);

/* Zero-initialised: the files a scene or model names (textures, models,
 * material libraries, buffers) must lie in the loaded file's folder or
 * below it, after links and ".." are resolved (realpath). A scene file then
 * cannot make persp read, say, /etc/passwd or ~/.ssh. A scene naming a file
 * elsewhere fails with PERSP_ERR_IO ("file:line:col: 'name' is outside the
 * folder ..."); a model's file elsewhere is skipped with a warning, like a
 * missing one. */
/* The direction a model file's "up" points along, for a model loaded
 * without a scene (persp_scene_load on the model itself): glTF and most
 * OBJ files are +y up; STL, 3DS and CAD exports are often +z up, which is
 * turned to +y (a rotation of −90° about x), so that the model stands on
 * the floor the default camera looks down on; some are −z or ±x up. The
 * default is +y, except for the formats that fix +z (Blender's .blend,
 * Valve's SMD, TrueSpace's COB). A scene file turns its objects with
 * "transform" instead. */
typedef enum persp_model_up {
    PERSP_MODEL_UP_DEFAULT = 0, /* +y, or the format's */
    PERSP_MODEL_UP_Y,
    PERSP_MODEL_UP_Z,
    PERSP_MODEL_UP_X,
    PERSP_MODEL_UP_NEG_X,
    PERSP_MODEL_UP_NEG_Y,
    PERSP_MODEL_UP_NEG_Z
} persp_model_up;
/* Where model files other than OBJ are read (docs/RELIABILITY.md, "Model
 * files from strangers"). persp reads them through Assimp, whose readers
 * were not written for hostile input: by default they run in persp-import,
 * a helper process installed with the library (PREFIX/libexec/persp/, or
 * beside the library in a build tree), held to the memory the budget
 * leaves (persp_context_desc.max_memory; half the machine's memory without
 * a budget) and to a time limit, with no files of its own: a reader that
 * crashes, loops or allocates without bound on a file ends that process,
 * and the load fails with a one-line message. IN_PROCESS runs the readers
 * on a thread of the caller's process instead: a few milliseconds faster
 * per model, but a crash in a reader ends the program, no time limit
 * applies and the memory limit is an estimate. Use it for files you
 * trust. */
typedef enum persp_model_import {
    PERSP_MODEL_IMPORT_DEFAULT = 0, /* ISOLATED */
    PERSP_MODEL_IMPORT_ISOLATED,
    PERSP_MODEL_IMPORT_IN_PROCESS
} persp_model_import;
/* The model formats read. COMMON (the default): OBJ, glTF 2.0 / GLB, PLY,
 * STL, OFF, FBX, COLLADA and 3DS, the formats users bring and persp's tests
 * cover, each only when the file's content is what its name says. ALL:
 * every format Assimp reads (X, 3MF, AMF, ASE, LWO, MD5, Blender, ...),
 * still isolated as set above. */
typedef enum persp_model_formats {
    PERSP_MODEL_FORMATS_DEFAULT = 0, /* COMMON */
    PERSP_MODEL_FORMATS_COMMON,
    PERSP_MODEL_FORMATS_ALL
} persp_model_formats;
/* Default limit on the wall-clock time of a load's model imports: a base,
 * and more for every MiB the importer is given (the model file and the
 * files it names, as they are handed over), at most PERSP_IMPORT_TIME_LIMIT_MAX_MS:
 * a hostile 14-byte file is stopped after 5 s, a 100 MB model may take
 * 205 s. */
#define PERSP_IMPORT_TIME_LIMIT_MS 5000u
#define PERSP_IMPORT_TIME_PER_MIB_MS 2000u
#define PERSP_IMPORT_TIME_LIMIT_MAX_MS 600000u
typedef struct persp_scene_load_desc {
    persp_toggle any_folder; /* ON: referenced files may lie anywhere; DEFAULT, OFF: restricted */
    persp_model_up model_up; /* a model file's up axis; DEFAULT: +y */
    persp_model_import import;
    persp_model_formats formats;
    /* Wall-clock limit of a load's model imports together in milliseconds
     * (isolated imports only; a JSON scene's models share it); 0:
     * PERSP_IMPORT_TIME_LIMIT_MS plus PERSP_IMPORT_TIME_PER_MIB_MS a MiB of
     * what the importer reads. */
    unsigned import_time_limit_ms;
    /* persp-import's path; NULL: beside the library, then PREFIX/libexec/persp/. */
    const char *import_helper;
    /* Normals of a model that has none: faces meeting at more than this
     * many degrees keep their own (a cube's edges), the rest are smoothed,
     * angle-weighted; (0, 180]; 0: 80. glTF files without normals are
     * drawn flat whatever it says (glTF 2.0 §3.7.2.1). */
    float crease_deg;
} persp_scene_load_desc;
/* persp_scene_load with settings; desc NULL: all defaults (restricted), as
 * persp_scene_load does. */
PERSP_API persp_status persp_scene_load_ex(persp_context *ctx, const char *path,
                                           const persp_scene_load_desc *desc, persp_scene **out);
PERSP_API void persp_scene_destroy(persp_scene *scene);
/* Replaces the texture of every textured object (e.g. --texture FILE); the
 * scene keeps a copy, not img. */
PERSP_API persp_status persp_scene_set_texture(persp_scene *scene, const persp_image *img);
/* The scene's preferred image size (0 if none). */
PERSP_API void persp_scene_default_size(const persp_scene *scene, int *width, int *height);

/* What a scene renders with when persp_render_desc overrides nothing, for
 * reports: the default shading and the filter of its textured objects
 * (filter_count 0: untextured; more than 1: objects differ, filter is the
 * first one's). */
typedef struct persp_scene_info {
    size_t objects, textures, lights;
    const char *method;   /* the scene's method spec, "exact" if it names none;
                             valid as long as the scene */
    persp_shading shading;
    int filter_count;
    persp_filter filter;
    int max_aniso;
    int cull_backfaces; /* 1: back faces are culled (clockwise in the window;
                           counter-clockwise for a mirrored object) */
    uint8_t clear[4];   /* the colour the image is cleared to, RGBA */
    float ambient[3];   /* global ambient light (GL_LIGHT_MODEL_AMBIENT) */
} persp_scene_info;
PERSP_API void persp_scene_get_info(const persp_scene *scene, persp_scene_info *out);
/* Replaces the texels of every mip level of every texture of the scene by
 * one flat colour per level (persp_mip_level_color), so that a render
 * shows which levels the filters read and how they blend them. For viewers
 * and debugging; load the scene again to get its textures back. */
PERSP_API persp_status persp_scene_tint_mip_levels(persp_scene *scene);
/* The colour of a level in persp_scene_tint_mip_levels: level 0 white, then
 * red, orange, yellow-green, green, cyan, blue, violet, magenta; grey from
 * level 9 on. */
PERSP_API void persp_mip_level_color(int level, uint8_t rgba[4]); /* rgba NULL: nothing */

typedef enum persp_pipeline {
    PERSP_PIPELINE_DEFAULT = 0, /* SCREEN */
    PERSP_PIPELINE_SCREEN,     /* inverse mapping per pixel */
    PERSP_PIPELINE_OBJECT      /* object-space texturing, screen-space filtering ([Romaniuk-ObjSpace]) */
} persp_pipeline;

/* Render settings. Zero-initialised (or a NULL desc) renders the scene as
 * it asks; each non-default field overrides the scene for this call only.
 * The number of threads is the context's (persp_context_desc.threads). */
typedef struct persp_render_desc {
    const char *method;      /* texture-coordinate method spec; NULL: the scene's, else "exact" */
    persp_filter filter;     /* every texture's filter */
    int max_aniso;           /* with an aniso filter: taps 2..16; 0: the texture's, else 16 */
    persp_wrap wrap;         /* every texture's wrap mode, both axes */
    persp_shading shading;
    persp_depth_mode depth_mode;
    persp_lod_mode lod_mode;
    float lod_bias;          /* added to each texture's own */
    persp_toggle lod_clamp;  /* ON: clamp every texture's lambda to [min_lod, max_lod];
                                OFF: remove the textures' clamps; DEFAULT: keep them */
    float min_lod, max_lod;
    persp_pipeline pipeline;
    persp_toggle cull_backfaces; /* DEFAULT: the scene's */
    persp_toggle count_ops;  /* ON: the methods count their operations into
                                persp_render_stats.ops (instrumented, slower render) */
    /* How a context of several threads shares a frame among them. OFF: sort
     * middle, every worker taking vertex ranges, set-up chunks and screen
     * tiles in turn, each reading what another wrote. ON: sort first, each
     * worker running the whole frame for its own screen region (a run of
     * 64x64 tiles in row-major order, moved from frame to frame to balance
     * the workers' times), sharing nothing but the scene it reads and the
     * framebuffer tiles it owns, at the price of each running the vertex
     * stage and the triangle loop for all that may reach its region
     * (docs/DESIGN.md, "Threads"); at most 16 regions, one a tile (a frame
     * of one tile is drawn sort middle). DEFAULT: sort middle, but sort
     * first with two workers while handing a cache line between them and
     * back takes longer than PERSP_SORT_FIRST_ROUND_TRIP_NS (measured before
     * a frame, at most every 50 ms). The image and the counts are the same
     * either way; the object-space pipeline and count_ops always take
     * sort middle. */
    persp_toggle sort_first;
    /* Camera override (interactive viewers, camera paths): each non-NULL
     * matrix replaces the scene camera's (world -> eye, eye -> clip); NULL
     * keeps the scene's (see persp_scene_get_camera). Lights stay in world
     * space, so they follow the new view. */
    const persp_mat4 *view;
    const persp_mat4 *projection;
} persp_render_desc;

typedef struct persp_render_stats {
    /* triangles_drawn: those set up for drawing, after clipping (a clipped
     * triangle may become several) and after dropping culled ones, those
     * outside the view and those covering no pixel centre (tested for
     * triangles whose box holds at most 32 pixel centres; a larger one
     * covering none, a long sliver, is counted and draws nothing). */
    uint64_t triangles_in, triangles_drawn, fragments, pixels_written;
    persp_opcount ops; /* with persp_render_desc.count_ops: the operations of the
                          texture-coordinate method over the frame (per-triangle
                          fits, spans, pixels, traversals); zero otherwise */
    /* Object-space pipeline ([Romaniuk-ObjSpace]): samples walked (texels or sub-texel
     * positions of the chosen levels), splats onto pixels, polygon pieces
     * (one mip level each), covered pixels that received no sample. */
    uint64_t objspace_samples, objspace_splats, objspace_pieces, objspace_holes;
    /* The object-space walk's work: sample rows and samples stepped through,
     * inside the tiles or not (bounded, docs/RELIABILITY.md). */
    uint64_t objspace_visited;
    /* The screen regions the frame was drawn in sort first, one a worker
     * (persp_render_desc.sort_first); 0: sort middle. */
    uint64_t sort_first_regions;
} persp_render_stats;

/* The cross-core round trip (ns) above which a two-worker context draws a
 * frame sort first by default: between the trips of two vCPUs sharing a
 * cache (50-100 ns on the AMD EPYC VM of docs/PERFORMANCE.md) and those of
 * two the host placed apart (315-870 ns), where sort middle ran at half
 * its speed and sort first at the speed of two independent threads. */
#define PERSP_SORT_FIRST_ROUND_TRIP_NS 200.0

/* Clears fb and renders the scene into it. desc and stats may be NULL. */
PERSP_API persp_status persp_render(persp_context *ctx, const persp_scene *scene, const persp_render_desc *desc,
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

/* Zero-initialised except mvp: vertex colours, exact method, z-buffer with
 * the depth test on, no culling. */
typedef struct persp_draw_desc {
    persp_mat4 mvp;           /* clip = mvp · pos */
    const persp_texture *texture; /* NULL: vertex colour; else replaced by the texel */
    persp_sampler_desc sampler;
    const char *method;       /* NULL: "exact" */
    persp_depth_mode depth_mode;
    persp_toggle cull_backfaces; /* DEFAULT: off; ON: counter-clockwise is front */
    persp_toggle depth_test;  /* DEFAULT: on (less; greater for INVW) */
} persp_draw_desc;

/* Draws indexed triangles (3 indices each) into fb without clearing it.
 * Surfaces are opaque: every pixel written has alpha 255, whatever the
 * alpha of the texture or the vertex colours. */
PERSP_API persp_status persp_draw(persp_context *ctx, persp_framebuffer *fb, const persp_draw_desc *desc,
                        const persp_vertex *vertices, size_t vertex_count, const uint32_t *indices,
                        size_t index_count);

/* ---------------------------------------------------------- scene contents */

/* Read-only views of a scene's contents, for drawing the same scene with
 * another renderer (the OpenGL peer of `persp bench`). Pointers stay valid
 * as long as the scene and while nothing modifies it. */

/* How a material combines the texel with lighting. */
typedef enum persp_scene_texenv {
    PERSP_SCENE_TEXENV_REPLACE = 0, /* the texel (GL_REPLACE) */
    PERSP_SCENE_TEXENV_MODULATE     /* lit colour × texel, see persp_scene_material */
} persp_scene_texenv;

/* Blinn–Phong material. With MODULATE the texel multiplies ambient +
 * diffuse and the specular term is added after it, unless specular_texture
 * is set, when it multiplies the specular term too; Gouraud modes light
 * vertices with all three terms and modulate the sum. */
typedef struct persp_scene_material {
    float ambient[3], diffuse[3], specular[3];
    float shininess;           /* 0: no specular term */
    int texture;               /* index for persp_scene_get_texture, -1: untextured */
    int specular_texture;      /* 1: the texel modulates the specular term too */
    persp_scene_texenv env;
    persp_sampler_desc sampler; /* filter DEFAULT: bilinear */
    float emission[3];         /* added to ambient + diffuse before the texel modulates them
                                  (GL_EMISSION) */
    int unlit;                 /* 1: no lighting: vertex colour × diffuse × texel */
} persp_scene_material;

/* One drawn object: an indexed triangle mesh (counter-clockwise = front)
 * in object space, placed by model. Its vertices' uv are the mesh's own;
 * an object with texture-coordinate generation (a scene's "texgen") is
 * drawn with persp_scene_object_texcoords' instead. */
typedef struct persp_scene_object {
    const persp_vertex *vertices;
    size_t vertex_count;
    const uint32_t *indices;   /* 3 per triangle */
    size_t index_count;
    persp_mat4 model;
    persp_scene_material material;
} persp_scene_object;

/* Lights in world space. */
typedef struct persp_scene_light {
    int directional;      /* 1: position is the direction towards the light */
    float position[3];
    float color[3];       /* diffuse and specular intensity */
    float attenuation[3]; /* constant, linear, quadratic (point lights) */
} persp_scene_light;

PERSP_API size_t persp_scene_object_count(const persp_scene *scene);
/* PERSP_ERR_NOT_FOUND past the end. */
PERSP_API persp_status persp_scene_get_object(const persp_scene *scene, size_t index,
                                              persp_scene_object *out);
/* The texture coordinates persp draws object index with, seen through view
 * (the camera's view matrix: the reflection map depends on it): the
 * object's texgen applied to its vertices, or their own uv. uv_out:
 * 2 × vertex_count floats, caller-owned. PERSP_ERR_NOT_FOUND past the end. */
PERSP_API persp_status persp_scene_object_texcoords(const persp_scene *scene, size_t index,
                                                    const persp_mat4 *view, float *uv_out);
PERSP_API size_t persp_scene_light_count(const persp_scene *scene);
PERSP_API persp_status persp_scene_get_light(const persp_scene *scene, size_t index,
                                             persp_scene_light *out);
/* The texture a material's index names (NULL past the end); its levels are
 * read with persp_texture_level. */
PERSP_API const persp_texture *persp_scene_get_texture(const persp_scene *scene, int index);
/* The scene's camera as persp_render uses it for a width×height image (the
 * aspect ratio enters the projection): world -> eye (view) and eye -> clip
 * (projection). Either output may be NULL. */
PERSP_API persp_status persp_scene_get_camera(const persp_scene *scene, int width, int height,
                                              persp_mat4 *view, persp_mat4 *projection);

#ifdef __cplusplus
}
#endif
#endif
