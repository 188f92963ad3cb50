/*
 * Texture storage and sampling, internal interface (src/texture/).
 *
 * Texels are packed RGBA8 in a uint32_t with R in the low byte (the byte
 * order of persp_image). Level 0 row 0 is the bottom row of the image.
 */
#ifndef PERSP_TEXTURE_TEXTURE_H
#define PERSP_TEXTURE_TEXTURE_H

#include "persp.h"

#define PERSP_TEX_MAX_LEVELS 16

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

/* Inputs for sampling one span. Derivatives are analytic (seed 000 §4.8):
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

/* A sampler resolved once per draw against one texture: everything the
 * per-span code needs, so nothing is decided per pixel. */
typedef struct persp_sampler_state {
    const struct persp_texture *tex;
    persp_sampler_desc desc;
    int max_aniso;
    float min_lod, max_lod;
    uint32_t border;
    /* Span sampler chosen from the filter once per draw. */
    void (*span)(const struct persp_sampler_state *st, const struct persp_tex_span_in *in,
                 uint32_t *out);
} persp_sampler_state;

persp_status persp__sampler_init(persp_sampler_state *st, const struct persp_texture *tex,
                                 const persp_sampler_desc *desc);
/* Fills out[0..n-1] with packed RGBA8. No allocation. */
static inline void persp__sample_span(const persp_sampler_state *st, const persp_tex_span_in *in,
                                      uint32_t *out)
{
    st->span(st, in, out);
}
/* Whether the sampler needs q and the Jacobian (any mip or anisotropic filter). */
int persp__sampler_needs_lod(const persp_sampler_state *st);
/* Per-polygon level of detail (seed 002, "mipmap level selection"):
 * lambda = 0.5·log2(texel area / pixel area), areas of the same triangle in
 * texels (uv area × W × H) and in pixels. */
float persp__polygon_lambda(const struct persp_texture *tex, double uv_area, double pixel_area);

#endif
