/*
 * Texture objects: storage, mip chain generation and the filter / wrap names.
 *
 * Mip rule for any size (docs/TEXTURES.md): level k+1 has
 * max(1, floor(n_k / 2)) texels along each axis. An even axis is reduced by
 * the 2-tap box (1/2, 1/2). An odd axis n = 2m + 1 > 1 is reduced by the
 * exact box filter of the footprint: output texel i covers the source
 * interval [i·n/m, (i+1)·n/m), which overlaps source texels 2i, 2i+1, 2i+2 by
 * (m - i)/m, 1 and (i + 1)/m, so its normalised weights are
 *   (m - i)/n,  m/n,  (i + 1)/n.
 * Every source texel then carries the same total weight m/n, which keeps the
 * level average equal to the source average (up to 8-bit rounding) and lets
 * every texel contribute. An axis of length 1 is copied. The filter is
 * separable and applied to straight (not premultiplied) RGBA, like
 * glGenerateMipmap on an RGBA8 texture.
 */
#include "texture/texture.h"

#include "core/internal.h"

#include <math.h>
#include <string.h>

/* ------------------------------------------------------------------ names */

#define WRAP_COUNT (PERSP_WRAP_CLAMP_TO_BORDER + 1)
static const char *const wrap_names[WRAP_COUNT] = {
    [PERSP_WRAP_DEFAULT] = "default",
    [PERSP_WRAP_REPEAT] = "repeat",
    [PERSP_WRAP_CLAMP_TO_EDGE] = "clamp-to-edge",
    [PERSP_WRAP_MIRRORED_REPEAT] = "mirrored-repeat",
    [PERSP_WRAP_CLAMP_TO_BORDER] = "clamp-to-border"};
static const char *const filter_names[PERSP_FILTER_COUNT] = {
    [PERSP_FILTER_DEFAULT] = "default",
    [PERSP_FILTER_NEAREST] = "nearest",
    [PERSP_FILTER_BILINEAR] = "bilinear",
    [PERSP_FILTER_NEAREST_MIP_NEAREST] = "nearest-mip-nearest",
    [PERSP_FILTER_BILINEAR_MIP_NEAREST] = "bilinear-mip-nearest",
    [PERSP_FILTER_NEAREST_MIP_LINEAR] = "nearest-mip-linear",
    [PERSP_FILTER_TRILINEAR] = "trilinear",
    [PERSP_FILTER_ANISO] = "aniso",
    [PERSP_FILTER_ANISO_WINDOW] = "aniso-window",
    [PERSP_FILTER_EWA] = "ewa"};

persp_status persp_wrap_parse(const char *name, persp_wrap *out)
{
    if (!name || !out) return PERSP_ERR_INVALID_ARGUMENT;
    for (int i = 0; i < WRAP_COUNT; i++) {
        if (strcmp(name, wrap_names[i]) == 0) {
            *out = (persp_wrap)i;
            return PERSP_OK;
        }
    }
    return PERSP_ERR_NOT_FOUND;
}

const char *persp_wrap_name(persp_wrap wrap)
{
    return (unsigned)wrap < (unsigned)WRAP_COUNT ? wrap_names[wrap] : "unknown";
}

/* Parses the N of "aniso:N": a decimal integer 2..16 and nothing else. */
static persp_status parse_aniso_count(const char *s, int *out)
{
    int n = 0, digits = 0;
    for (; *s; s++, digits++) {
        if (*s < '0' || *s > '9' || digits >= 3) return PERSP_ERR_INVALID_ARGUMENT;
        n = n * 10 + (*s - '0');
    }
    if (digits == 0 || n < 2 || n > PERSP_MAX_ANISO) return PERSP_ERR_INVALID_ARGUMENT;
    *out = n;
    return PERSP_OK;
}

persp_status persp_filter_parse(const char *name, persp_filter *out, int *max_aniso)
{
    if (!name || !out) return PERSP_ERR_INVALID_ARGUMENT;
    int aniso = PERSP_MAX_ANISO;
    for (int i = 0; i < PERSP_FILTER_COUNT; i++) {
        size_t len = strlen(filter_names[i]);
        if (strncmp(name, filter_names[i], len) != 0) continue;
        const char *rest = name + len;
        if (*rest == '\0') {
            /* "aniso-window" must not match "aniso" followed by "-window". */
        } else if (*rest == ':' &&
                   (i == PERSP_FILTER_ANISO || i == PERSP_FILTER_ANISO_WINDOW)) {
            persp_status st = parse_aniso_count(rest + 1, &aniso);
            if (st != PERSP_OK) return st;
        } else {
            continue;
        }
        *out = (persp_filter)i;
        if (max_aniso) *max_aniso = aniso;
        return PERSP_OK;
    }
    if (strncmp(name, "aniso", 5) == 0) return PERSP_ERR_INVALID_ARGUMENT;
    return PERSP_ERR_NOT_FOUND;
}

const char *persp_filter_name(persp_filter filter)
{
    return (unsigned)filter < (unsigned)PERSP_FILTER_COUNT ? filter_names[filter] : "unknown";
}

/* -------------------------------------------------------------- mip chain */

static inline uint32_t pack_rgba(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Taps and weights of destination index i along an axis of source length n
 * (see the rule at the top of this file). Returns the tap count. */
static int axis_taps(int n, int i, int idx[3], float w[3])
{
    if (n == 1) {
        idx[0] = 0;
        w[0] = 1.0f;
        return 1;
    }
    if ((n & 1) == 0) {
        idx[0] = 2 * i;
        idx[1] = 2 * i + 1;
        w[0] = w[1] = 0.5f;
        return 2;
    }
    int m = n / 2;
    idx[0] = 2 * i;
    idx[1] = 2 * i + 1;
    idx[2] = 2 * i + 2;
    w[0] = (float)(m - i) / (float)n;
    w[1] = (float)m / (float)n;
    w[2] = (float)(i + 1) / (float)n;
    return 3;
}

static void downsample(const uint32_t *src, int sw, int sh, uint32_t *dst, int dw, int dh)
{
    for (int y = 0; y < dh; y++) {
        int yi[3], xi[3];
        float yw[3], xw[3];
        int ny = axis_taps(sh, y, yi, yw);
        for (int x = 0; x < dw; x++) {
            int nx = axis_taps(sw, x, xi, xw);
            float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            for (int a = 0; a < ny; a++) {
                const uint32_t *row = src + (size_t)yi[a] * (size_t)sw;
                for (int b = 0; b < nx; b++) {
                    uint32_t t = row[xi[b]];
                    float w = yw[a] * xw[b];
                    acc[0] += w * (float)(t & 0xffu);
                    acc[1] += w * (float)(t >> 8 & 0xffu);
                    acc[2] += w * (float)(t >> 16 & 0xffu);
                    acc[3] += w * (float)(t >> 24);
                }
            }
            uint32_t out = 0;
            for (int c = 0; c < 4; c++) {
                float v = acc[c] + 0.5f;
                v = v < 0.0f ? 0.0f : v > 255.0f ? 255.0f : v;
                out |= (uint32_t)v << (8 * c);
            }
            dst[(size_t)y * (size_t)dw + (size_t)x] = out;
        }
    }
}

persp_status persp_texture_create(persp_context *ctx, const persp_image *img, persp_texture **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!img || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "texture: no image or no texture to fill");
    *out = NULL;
    if (!img->pixels || img->width <= 0 || img->height <= 0 ||
        img->stride < (size_t)img->width * 4u)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "texture: invalid image %dx%d",
                                  img->width, img->height);
    if (img->width > PERSP_IMAGE_MAX_SIDE || img->height > PERSP_IMAGE_MAX_SIDE ||
        (size_t)img->width * (size_t)img->height > PERSP_IMAGE_MAX_PIXELS)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "texture: image %dx%d is too large",
                                  img->width, img->height);
    persp_texture *t = persp__calloc(ctx, 1, sizeof *t);
    if (!t) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "texture: out of memory");
    t->ctx = ctx;
    t->width = img->width;
    t->height = img->height;
    size_t total = 0;
    int w = img->width, h = img->height, levels = 0;
    for (;;) {
        t->level[levels].w = w;
        t->level[levels].h = h;
        total += (size_t)w * (size_t)h;
        levels++;
        if ((w == 1 && h == 1) || levels == PERSP_TEX_MAX_LEVELS) break;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    t->levels = levels;
    t->storage = persp__calloc(ctx, total, sizeof(uint32_t));
    if (!t->storage) {
        persp__free(ctx, t);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY,
                                  "texture: out of memory for %dx%d with %d levels", img->width,
                                  img->height, levels);
    }
    t->bytes_all = total * sizeof(uint32_t);
    t->bytes_base = (size_t)img->width * (size_t)img->height * sizeof(uint32_t);
    uint32_t *p = t->storage;
    for (int y = 0; y < img->height; y++) {
        const uint8_t *row = img->pixels + (size_t)y * img->stride;
        for (int x = 0; x < img->width; x++) p[(size_t)y * (size_t)img->width + (size_t)x] =
            pack_rgba(row + 4 * x);
    }
    t->level[0].texels = p;
    for (int l = 1; l < levels; l++) {
        uint32_t *dst = p + (size_t)t->level[l - 1].w * (size_t)t->level[l - 1].h;
        downsample(p, t->level[l - 1].w, t->level[l - 1].h, dst, t->level[l].w, t->level[l].h);
        t->level[l].texels = dst;
        p = dst;
    }
    *out = t;
    return PERSP_OK;
}

void persp_texture_destroy(persp_texture *tex)
{
    if (!tex) return;
    persp_context *ctx = tex->ctx;
    persp__free(ctx, tex->storage);
    persp__free(ctx, tex);
}

int persp_texture_width(const persp_texture *tex)
{
    return tex ? tex->width : 0;
}

int persp_texture_height(const persp_texture *tex)
{
    return tex ? tex->height : 0;
}

int persp_texture_levels(const persp_texture *tex)
{
    return tex ? tex->levels : 0;
}

void persp_texture_memory(const persp_texture *tex, size_t *all_levels, size_t *base_level)
{
    if (all_levels) *all_levels = tex ? tex->bytes_all : 0;
    if (base_level) *base_level = tex ? tex->bytes_base : 0;
}

persp_status persp_texture_level(const persp_texture *tex, int level, persp_image_view *view)
{
    if (!tex || !view) return PERSP_ERR_INVALID_ARGUMENT;
    if (level < 0 || level >= tex->levels) return PERSP_ERR_NOT_FOUND;
    view->width = tex->level[level].w;
    view->height = tex->level[level].h;
    view->stride = (size_t)view->width * 4u;
    /* The texel words are stored R-low, which is the byte order of an image
     * row only on a little-endian host; persp targets those (CONVENTIONS). */
    view->pixels = (const uint8_t *)tex->level[level].texels;
    return PERSP_OK;
}

float persp__polygon_lambda(const struct persp_texture *tex, const double x[3], const double y[3],
                            const double u[3], const double v[3])
{
    const double du1 = u[1] - u[0], dv1 = v[1] - v[0], du2 = u[2] - u[0], dv2 = v[2] - v[0];
    const double uv_area = 0.5 * fabs(du1 * dv2 - du2 * dv1);
    const double pixel_area = 0.5 * fabs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
    if (!tex || !(pixel_area > 0.0) || !(uv_area > 0.0)) return 0.0f;
    double texel_area = uv_area * (double)tex->width * (double)tex->height;
    double lam = 0.5 * log2(texel_area / pixel_area);
    if (!(lam > -64.0)) lam = -64.0;
    if (lam > 64.0) lam = 64.0;
    return (float)lam;
}
