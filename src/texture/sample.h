/*
 * Inline texel addressing shared by the samplers of src/texture/.
 *
 * Conventions of the OpenGL 4.6 specification §8.14: with u' = s·W, the
 * nearest texel is i = wrap(floor(u')); the linear filter uses
 * i0 = wrap(floor(u' - 1/2)), i1 = wrap(i0 + 1) with weight
 * alpha = frac(u' - 1/2) on i1. Wrapping applies to integer texel indices
 * (Table 8.20), so every filter here addresses texels only through
 * wrap_index(). The wrap mode is a parameter that every caller passes as a
 * compile-time constant, so each instantiated span function has its wrap
 * code folded in and nothing is decided per pixel.
 */
#ifndef PERSP_TEXTURE_SAMPLE_H
#define PERSP_TEXTURE_SAMPLE_H

#include "core/fmath.h"
#include "texture/texture.h"

#include <math.h>

/* Coordinates beyond this many texels are clamped before conversion to int:
 * far outside float's integer precision anyway, and the conversion of a
 * larger value (or NaN) would be undefined. */
#define PERSP_TEX_COORD_LIMIT 8388608.0f

static inline float persp__tex_safe(float x)
{
    if (!(x > -PERSP_TEX_COORD_LIMIT)) return -PERSP_TEX_COORD_LIMIT; /* also NaN */
    if (x > PERSP_TEX_COORD_LIMIT) return PERSP_TEX_COORD_LIMIT;
    return x;
}

/* floor() of an already safe coordinate. */
static inline int persp__tex_floor(float x)
{
    return (int)floorf(x);
}

/* Table 8.20 of the GL 4.6 spec; -1 stands for "the border colour". */
static inline int persp__wrap_index(int wrap, int i, int size)
{
    switch (wrap) {
    case PERSP_WRAP_REPEAT: {
        int m = i % size;
        return m < 0 ? m + size : m;
    }
    case PERSP_WRAP_CLAMP_TO_EDGE:
        return i < 0 ? 0 : i >= size ? size - 1 : i;
    case PERSP_WRAP_MIRRORED_REPEAT: {
        int s2 = 2 * size;
        int m = i % s2;
        if (m < 0) m += s2;
        int t = m - size;                 /* in [-size, size) */
        int mirror = t >= 0 ? t : -(1 + t); /* mirror(a) of Table 8.20 */
        return size - 1 - mirror;
    }
    default: /* PERSP_WRAP_CLAMP_TO_BORDER */
        return i < 0 || i >= size ? -1 : i;
    }
}

static inline uint32_t persp__texel(const persp_sampler_state *st, const persp_tex_level *lv,
                                    int ws, int wt, int i, int j)
{
    int x = persp__wrap_index(ws, i, lv->w);
    int y = persp__wrap_index(wt, j, lv->h);
    if (x < 0 || y < 0) return st->border;
    return lv->texels[(size_t)y * (size_t)lv->w + (size_t)x];
}

static inline void persp__acc(float c[4], uint32_t t, float w)
{
    c[0] += w * (float)(t & 0xffu);
    c[1] += w * (float)(t >> 8 & 0xffu);
    c[2] += w * (float)(t >> 16 & 0xffu);
    c[3] += w * (float)(t >> 24);
}

/* Rounds to the nearest 8-bit value; the filters work in float so that the
 * only quantisation is this final one. */
static inline uint32_t persp__pack(const float c[4])
{
    uint32_t out = 0;
    for (int k = 0; k < 4; k++) {
        float v = c[k] + 0.5f;
        v = v < 0.0f ? 0.0f : v > 255.0f ? 255.0f : v;
        out |= (uint32_t)v << (8 * k);
    }
    return out;
}

static inline void persp__nearest(const persp_sampler_state *st, int level, int ws, int wt, float u,
                                  float v, float c[4])
{
    const persp_tex_level *lv = &st->tex->level[level];
    int i = persp__tex_floor(persp__tex_safe(u * (float)lv->w));
    int j = persp__tex_floor(persp__tex_safe(v * (float)lv->h));
    c[0] = c[1] = c[2] = c[3] = 0.0f;
    persp__acc(c, persp__texel(st, lv, ws, wt, i, j), 1.0f);
}

static inline void persp__bilinear(const persp_sampler_state *st, int level, int ws, int wt,
                                   float u, float v, float c[4])
{
    const persp_tex_level *lv = &st->tex->level[level];
    float x = persp__tex_safe(u * (float)lv->w - 0.5f);
    float y = persp__tex_safe(v * (float)lv->h - 0.5f);
    int i0 = persp__tex_floor(x), j0 = persp__tex_floor(y);
    float a = x - (float)i0, b = y - (float)j0;
    c[0] = c[1] = c[2] = c[3] = 0.0f;
    persp__acc(c, persp__texel(st, lv, ws, wt, i0, j0), (1.0f - a) * (1.0f - b));
    persp__acc(c, persp__texel(st, lv, ws, wt, i0 + 1, j0), a * (1.0f - b));
    persp__acc(c, persp__texel(st, lv, ws, wt, i0, j0 + 1), (1.0f - a) * b);
    persp__acc(c, persp__texel(st, lv, ws, wt, i0 + 1, j0 + 1), a * b);
}

/* Screen-space derivatives of (u, v) in level-0 texels at pixel k, from the
 * rational mapping's coefficients (texture.h): du/dx = (a - u·g)/Q, ... */
typedef struct persp_tex_jac {
    float ux, vx, uy, vy;
} persp_tex_jac;

static inline persp_tex_jac persp__span_jacobian(const persp_sampler_state *st,
                                                 const persp_tex_span_in *in, int k)
{
    float q = in->q[k];
    float iq = q > 1e-30f ? 1.0f / q : 1e30f;
    float W = (float)st->tex->width, H = (float)st->tex->height;
    float u = in->u[k], v = in->v[k];
    persp_tex_jac j;
    j.ux = (in->a - u * in->g) * iq * W;
    j.uy = (in->b - u * in->h) * iq * W;
    j.vx = (in->d - v * in->g) * iq * H;
    j.vy = (in->e - v * in->h) * iq * H;
    return j;
}

/* Clamps a level of detail to the sampler's [min_lod, max_lod]; NaN goes to
 * min_lod so that no later conversion sees it. Two selects in the operand
 * order of maxps and minps (x86: a > b ? a : b, a < b ? a : b), which the
 * vectorised samplers then use; with early returns GCC built the clamp
 * from three compares and two blends. */
static inline float persp__clamp_lod(const persp_sampler_state *st, float lam)
{
    const float lo = lam > st->min_lod ? lam : st->min_lod;
    return st->max_lod < lo ? st->max_lod : lo;
}

/* GL 4.6 eq. 8.6 with rho = max of the two footprint lengths (eq. 8.7).
 * log2 is persp__log2f (error < 1e-5 of a level, well inside the latitude
 * §8.14 allows for lambda) so that the vectorised samplers of fastspan.c
 * compute the same level bit for bit. */
static inline float persp__jac_lambda(const persp_sampler_state *st, persp_tex_jac j)
{
    float rx = j.ux * j.ux + j.vx * j.vx, ry = j.uy * j.uy + j.vy * j.vy;
    float r2 = rx > ry ? rx : ry;
    return persp__clamp_lod(st, 0.5f * persp__log2f(r2) + st->lod_bias);
}

/* EXT_texture_filter_anisotropic: tap count N = min(ceil(Pmax / Pmin),
 * max_aniso) (1 for a zero footprint) and lambda' = log2(Pmax / N) of one
 * footprint, with major_x telling which screen axis is the major one.
 * Written without branches and with the ratio clamped before its conversion
 * to int (a zero or tiny Pmin gives an infinite ratio, never converted), so
 * that the general and the vectorised samplers share it. */
static inline int persp__aniso_rule(const persp_sampler_state *st, persp_tex_jac j, float *lam,
                                    int *major_x)
{
    float px2 = j.ux * j.ux + j.vx * j.vx, py2 = j.uy * j.uy + j.vy * j.vy;
    int mx = px2 >= py2;
    float pmax = sqrtf(mx ? px2 : py2), pmin = sqrtf(mx ? py2 : px2);
    float maxa = (float)st->max_aniso;
    float ratio = pmax / pmin;
    ratio = ratio < maxa ? ratio : maxa; /* also NaN */
    int n = pmin * maxa > pmax ? (int)ceilf(ratio) : st->max_aniso;
    n = n < 1 ? 1 : n;
    n = pmax > 0.0f ? n : 1;
    *major_x = mx;
    *lam = persp__clamp_lod(st, persp__log2f(pmax / (float)n) + st->lod_bias);
    return n;
}

/* Trilinear filtering at an already clamped lambda (GL 4.6 §8.14.3), used as
 * the tap of the anisotropic filter; magnification (lambda <= 0) is bilinear
 * on level 0. */
static inline void persp__trilinear(const persp_sampler_state *st, int ws, int wt, float u, float v,
                                    float lam, float c[4])
{
    int q = st->tex->levels - 1;
    if (lam <= 0.0f) {
        persp__bilinear(st, 0, ws, wt, u, v, c);
        return;
    }
    float fl = floorf(lam);
    int d1 = (int)fl;
    if (d1 >= q) {
        persp__bilinear(st, q, ws, wt, u, v, c);
        return;
    }
    float f = lam - fl, c2[4];
    persp__bilinear(st, d1, ws, wt, u, v, c);
    persp__bilinear(st, d1 + 1, ws, wt, u, v, c2);
    for (int k = 0; k < 4; k++) c[k] += f * (c2[k] - c[k]);
}

/* Index of a (wrap_s, wrap_t) pair of resolved modes (not DEFAULT) in the
 * 16-entry span tables: repeat, edge, mirrored, border in persp_wrap order. */
static inline int persp__wrap_pair_index(persp_wrap ws, persp_wrap wt)
{
    return ((int)ws - PERSP_WRAP_REPEAT) * 4 + ((int)wt - PERSP_WRAP_REPEAT);
}

/* The span samplers of ewa.c and window.c, one per wrap pair, indexed by
 * persp__wrap_pair_index. */
typedef void (*persp_tex_span_fn)(const persp_sampler_state *st, const persp_tex_span_in *in,
                                  uint32_t *out);
extern const persp_tex_span_fn persp__ewa_spans[16];
extern const persp_tex_span_fn persp__window_spans[16];
void persp__ewa_init(persp_sampler_state *st);
/* Texels read by the EWA filter for one footprint (ewa.c). */
int persp__ewa_fetches(const persp_sampler_state *st, float u, float v, persp_tex_jac j);

#endif
