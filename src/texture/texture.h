/*
 * Texture storage and sampling, internal interface (src/texture/).
 *
 * Texels are packed RGBA8 in a uint32_t with R in the low byte (the byte
 * order of persp_image). Level 0 row 0 is the bottom row of the image.
 */
#ifndef PERSP_TEXTURE_TEXTURE_H
#define PERSP_TEXTURE_TEXTURE_H

#include "core/shared.h"

#include "persp.h"

#define PERSP_TEX_MAX_LEVELS 16
#define PERSP_EWA_TABLE 256

typedef struct persp_tex_level {
    int w, h;
    const uint32_t *texels; /* w*h, row-major, row 0 = bottom */
} persp_tex_level;

struct persp_texture {
    persp_context *ctx;
    int width, height, levels;
    persp_tex_level level[PERSP_TEX_MAX_LEVELS];
    uint32_t *storage; /* one allocation holding every level */
    size_t bytes_all, bytes_base;
};

/* Inputs for sampling one span. Derivatives are analytic ([Romanyuk-PCF] §4.8):
 * with u = U/Q, U = a·x + b·y + c, Q = g·x + h·y + i,
 *   du/dx = (a - u·g)/Q,  du/dy = (b - u·h)/Q,  dv/dx = (d - v·g)/Q,  dv/dy = (e - v·h)/Q,
 * all in normalised texture units (multiply by the level size for texels). */
typedef struct persp_tex_span_in {
    int n;
    const float *u, *v; /* normalised texture coordinates */
    const float *q;     /* Q (= 1/w) per pixel; may be NULL if the filter needs no LOD */
    float a, b, d, e, g, h;
    float poly_lambda;  /* level of detail for PERSP_LOD_POLYGON */
} persp_tex_span_in;

/* Per-level addressing of a power-of-two texture for the vectorised span
 * samplers (fastspan.c): texel (i, j) of level l is storage[off[l] +
 * (j << shift[l]) + i]; valid when pot != 0. */
typedef struct persp_tex_pot {
    int pot;
    /* PERSP_TEX_COORD_LIMIT, as data: with a constant bound GCC builds the
     * span samplers' coordinate clamp (and the floor, conversion and wrap
     * it pushes through it) from compares and blends, with a bound it
     * cannot fold from a max and a min (4 to 8 instructions per
     * coordinate and 8 pixels). */
    float coord_limit;
    float fw[PERSP_TEX_MAX_LEVELS], fh[PERSP_TEX_MAX_LEVELS];
    int32_t wmask[PERSP_TEX_MAX_LEVELS], hmask[PERSP_TEX_MAX_LEVELS];
    int32_t shift[PERSP_TEX_MAX_LEVELS], off[PERSP_TEX_MAX_LEVELS];
} persp_tex_pot;

/* A sampler resolved once per draw against one texture: everything the
 * per-span code needs, so nothing is decided per pixel. */
struct persp_sampler_state;
struct persp_tex_span_in;
typedef void (*persp_tex_span_fn)(const struct persp_sampler_state *st,
                                    const struct persp_tex_span_in *in, uint32_t *out);

typedef struct persp_sampler_state {
    const struct persp_texture *tex;
    persp_sampler_desc desc;
    int max_aniso;
    float min_lod, max_lod;
    uint32_t border;
    float lod_bias;
    /* Heckbert's Gaussian weight exp(-alpha·r²) sampled at r² = k/(TABLE-1),
     * filled once by persp__sampler_init for PERSP_FILTER_EWA. */
    float ewa_weight[PERSP_EWA_TABLE];
    persp_tex_pot pot;
    /* Span sampler chosen from the filter once per draw. */
    void (*span)(const struct persp_sampler_state *st, const struct persp_tex_span_in *in,
                 uint32_t *out);
} persp_sampler_state;

PERSP_INTERNAL persp_status persp__sampler_init(persp_sampler_state *st,
                                                const struct persp_texture *tex,
                                                const persp_sampler_desc *desc);
/* The same with the vectorised samplers' variant given (PERSP_ISA_*, one
 * that persp__isa_runs). */
persp_status persp__sampler_init_isa(persp_sampler_state *st, const struct persp_texture *tex,
                                     const persp_sampler_desc *given, int isa);
/* The first field of d (its DEFAULTs resolved or not) out of range, with
 * the range, for messages; NULL when every field is valid. */
const char *persp__sampler_desc_problem(const persp_sampler_desc *d);
/* Fills out[0..n-1] with packed RGBA8, n <= PERSP_LANE_MAX. No allocation. */
static inline void persp__sample_span(const persp_sampler_state *st, const persp_tex_span_in *in,
                                      uint32_t *out)
{
    st->span(st, in, out);
}
/* Whether the sampler needs q and the Jacobian (any mip or anisotropic filter). */
int persp__sampler_needs_lod(const persp_sampler_state *st);
/* The vectorised span sampler for this state (fastspan.c): power-of-two
 * textures, repeat or clamp-to-edge, nearest / bilinear / trilinear; fills
 * st->pot. NULL when the state is not of that kind. Its output equals the
 * general sampler's bit for bit (tests/unit/test_fastspan.c). */
persp_tex_span_fn persp__fast_span_select(persp_sampler_state *st);
/* The same with the instruction set chosen by the caller (PERSP_ISA_BASE,
 * _AVX2, _AVX512 of core/fmath.h; tests compare each the CPU can run
 * against the general sampler). */
persp_tex_span_fn persp__fast_span_select_isa(persp_sampler_state *st, int isa);
/* The variant PERSP_SIMD_AUTO stands for on this CPU (PERSP_ISA_*): AVX2
 * or, where the CPU has it and it times faster, AVX-512; with or without
 * gathers as timed. */
int persp__fast_span_auto_isa(void);
/* The general (table-driven) span sampler of a filter and wrap pair, for
 * comparing the vectorised one against it. */
persp_tex_span_fn persp__general_span(persp_filter filter, persp_wrap ws, persp_wrap wt);
/* Per-polygon level of detail ([CS300-TexMap], "mipmap level selection"):
 * lambda = 0.5·log2(texel area / pixel area), areas of the same triangle in
 * texels (uv area × W × H) and in pixels, from its vertices' window
 * positions x, y and normalised texture coordinates u, v. */
PERSP_INTERNAL float persp__polygon_lambda(const struct persp_texture *tex, const double x[3],
                                           const double y[3], const double u[3], const double v[3]);

/* For tests and tools: the level of detail of one footprint (derivatives of
 * normalised u, v per pixel) after bias and clamping, and the
 * EXT_texture_filter_anisotropic tap count N with its lambda'. */
float persp__pixel_lambda(const persp_sampler_state *st, float dudx, float dvdx, float dudy,
                          float dvdy);
/* The rotated rectangular window of [Romanyuk-PCF] §4.8 on one mip level
 * (src/texture/window.c): len texels per row along the major axis, rows
 * rows, rows offset by the major axis' digital steps rotated by 90 degrees.
 * The major axis' digital line has slope dy/dx (0 <= dy <= dx) along x when
 * x_major, else along y, with signs sx, sy. */
typedef struct persp_tex_window {
    int level;
    int x0, y0; /* start corner A, texel indices on the level (before wrapping) */
    int len, rows;
    int x_major, sx, sy;
    int dx, dy;
} persp_tex_window;
/* Builds the window of a footprint (derivatives of normalised u, v); 0 when
 * it is magnified (the filter is then bilinear on w->level). */
int persp__window_setup(const persp_sampler_state *st, float u, float v, float dudx, float dvdx,
                        float dudy, float dvdy, persp_tex_window *w);
/* Texel indices visited by the daisy-chain traversal (daisy != 0) or by the
 * direct traversal, as x,y pairs in xy[0..2·cap-1] in visiting order;
 * returns the number visited (len·rows). */
size_t persp__window_visit(const persp_sampler_state *st, const persp_tex_window *w, int daisy,
                           int *xy, size_t cap);
/* Texels the sampler reads for pixel k of a span: the same level, tap and
 * footprint decisions as its span function, counted instead of filtered
 * (cost analysis, persp accuracy --filter). */
PERSP_INTERNAL int persp__sampler_fetches(const persp_sampler_state *st,
                                          const persp_tex_span_in *in, int k);
int persp__aniso_taps(const persp_sampler_state *st, float dudx, float dvdx, float dudy, float dvdy,
                      float *lambda);

#endif
