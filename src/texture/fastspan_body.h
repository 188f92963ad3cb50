/*
 * The span samplers of fastspan.c as inline bodies, instantiated per
 * instruction set there and, compiled with the vectoriser's gathers
 * enabled, in fastspan_gather.c. Private to those two files.
 */
#ifndef PERSP_TEXTURE_FASTSPAN_BODY_H
#define PERSP_TEXTURE_FASTSPAN_BODY_H

#include "texture/sample.h"

#include "core/internal.h"
#include "interp/method.h"

#include <math.h>
#include <string.h>
#if PERSP_HAVE_ISA_VARIANTS
#include <immintrin.h>
#endif

#define N PERSP_LANE_MAX
/* Forced, so that each target clone gets its own vectorised copy. */
#define PERSP_INLINE __attribute__((always_inline))

/* persp__tex_safe with its bound lim = PERSP_TEX_COORD_LIMIT
 * (persp_tex_pot.coord_limit): the clamp keeps the later conversion to int
 * defined (NaN goes to the lower limit, as there). The selects are in the
 * operand order of maxps and minps. */
static inline PERSP_INLINE float safe_coord(float x, float lim)
{
    x = x > -lim ? x : -lim;
    return lim < x ? lim : x;
}

static inline PERSP_INLINE int32_t wrap_i(int wrap, int32_t i, int32_t mask)
{
    if (wrap == PERSP_WRAP_REPEAT) return i & mask; /* two's complement: i mod 2^k */
    i = i < 0 ? 0 : i;
    return i > mask ? mask : i;
}

/* c is a weighted mean of texel channels (weights >= 0, at most 1 in
 * all), so c + 1/2 converts to int32 and is clamped there: the same
 * integer as clamping the float to [0, 255] first. Clamped as floats, the
 * compiler pushed the conversion through both selects and built each
 * channel from three compares and three blends (a third of the
 * instructions of a bilinear span with AVX2). */
static inline PERSP_INLINE uint32_t pack_ch(float c)
{
    int32_t i = (int32_t)(c + 0.5f);
    i = i > 0 ? i : 0;
    return (uint32_t)(i < 255 ? i : 255);
}

/* Stages 1-2 of the linear filter on level lev[k] of each pixel (or on
 * level one for all when lev == NULL): the four texel addresses and
 * fractions. two: every lev[k] is one or one + 1, whose offsets are then
 * chosen between rather than looked up. */
static inline PERSP_INLINE void
linear_taps_on(const persp_tex_pot *restrict p, int ws, int wt, int n, const float *restrict u,
               const float *restrict v, const int32_t *restrict lev, int32_t one, int two,
               int32_t *restrict a00, int32_t *restrict a10, int32_t *restrict a01,
               int32_t *restrict a11, float *restrict fa, float *restrict fb)
{
    const int32_t off_one = p->off[one], off_next = two ? p->off[one + 1] : 0;
    const int32_t w0 = p->wmask[0] + 1, h0 = p->hmask[0] + 1, s0 = p->shift[0];
    for (int k = 0; k < n; k++) {
        /* Level l of a power-of-two chain is max(w0 >> l, 1) wide: shifts
         * rather than table look-ups, which would each be a gather. */
        int32_t l = lev ? lev[k] : one;
        int32_t wl = w0 >> l, hl = h0 >> l, sh = s0 - l;
        wl = wl > 1 ? wl : 1;
        hl = hl > 1 ? hl : 1;
        sh = sh > 0 ? sh : 0;
        float x = safe_coord(u[k] * (float)wl - 0.5f, p->coord_limit);
        float y = safe_coord(v[k] * (float)hl - 0.5f, p->coord_limit);
        float fx = floorf(x), fy = floorf(y);
        int32_t i0 = (int32_t)fx, j0 = (int32_t)fy;
        fa[k] = x - fx;
        fb[k] = y - fy;
        int32_t wm = wl - 1, hm = hl - 1;
        int32_t off = !lev ? off_one : two ? (l == one ? off_one : off_next) : p->off[l];
        int32_t x0 = wrap_i(ws, i0, wm), x1 = wrap_i(ws, i0 + 1, wm);
        int32_t r0 = off + (wrap_i(wt, j0, hm) << sh), r1 = off + (wrap_i(wt, j0 + 1, hm) << sh);
        a00[k] = r0 + x0;
        a10[k] = r0 + x1;
        a01[k] = r1 + x0;
        a11[k] = r1 + x1;
    }
}

/* linear_taps_on for level lev[k] of each pixel, lev[k] in lo .. hi (lev
 * == NULL: level 0 for all). Where every pixel of the span takes one level
 * or two neighbouring ones, as on most spans of a mipmapped surface
 * (lambda varies slowly along a row), the per-lane look-up of the level's
 * offset, a gather, becomes a choice between two values (corridor,
 * trilinear: the look-up was 7.5 % of the sampler's instructions). */
static inline PERSP_INLINE void
linear_taps(const persp_tex_pot *restrict p, int ws, int wt, int n, const float *restrict u,
            const float *restrict v, const int32_t *restrict lev, int32_t lo, int32_t hi,
            int32_t *restrict a00, int32_t *restrict a10, int32_t *restrict a01,
            int32_t *restrict a11, float *restrict fa, float *restrict fb)
{
    if (!lev || lo == hi)
        linear_taps_on(p, ws, wt, n, u, v, NULL, lev ? lo : 0, 0, a00, a10, a01, a11, fa, fb);
    else if (hi - lo == 1)
        linear_taps_on(p, ws, wt, n, u, v, lev, lo, 1, a00, a10, a01, a11, fa, fb);
    else
        linear_taps_on(p, ws, wt, n, u, v, lev, 0, 0, a00, a10, a01, a11, fa, fb);
}

/* Stage 4: weigh the four texels of pixel k in the order persp__bilinear
 * accumulates (00, 10, 01, 11), one float sum per channel. Channels 1 and
 * 2 are masked in place rather than shifted down, i.e. scaled by 2^8 and
 * 2^16, and the sum is scaled back at the end: scaling every term of a
 * float sum by a power of two scales each rounded product and partial sum
 * exactly, so the result has the same bits and the loop saves eight
 * shifts per pixel. */
static inline PERSP_INLINE void linear_weigh(uint32_t t00, uint32_t t10, uint32_t t01, uint32_t t11,
                                             float a, float b, float c[4][N], int k)
{
    float w00 = (1.0f - a) * (1.0f - b), w10 = a * (1.0f - b);
    float w01 = (1.0f - a) * b, w11 = a * b;
    float s0 = w00 * (float)(int32_t)(t00 & 0xffu);
    s0 += w10 * (float)(int32_t)(t10 & 0xffu);
    s0 += w01 * (float)(int32_t)(t01 & 0xffu);
    s0 += w11 * (float)(int32_t)(t11 & 0xffu);
    float s1 = w00 * (float)(int32_t)(t00 & 0xff00u);
    s1 += w10 * (float)(int32_t)(t10 & 0xff00u);
    s1 += w01 * (float)(int32_t)(t01 & 0xff00u);
    s1 += w11 * (float)(int32_t)(t11 & 0xff00u);
    float s2 = w00 * (float)(int32_t)(t00 & 0xff0000u);
    s2 += w10 * (float)(int32_t)(t10 & 0xff0000u);
    s2 += w01 * (float)(int32_t)(t01 & 0xff0000u);
    s2 += w11 * (float)(int32_t)(t11 & 0xff0000u);
    float s3 = w00 * (float)(int32_t)(t00 >> 24);
    s3 += w10 * (float)(int32_t)(t10 >> 24);
    s3 += w01 * (float)(int32_t)(t01 >> 24);
    s3 += w11 * (float)(int32_t)(t11 >> 24);
    c[0][k] = s0;
    c[1][k] = s1 * 0x1p-8f;
    c[2][k] = s2 * 0x1p-16f;
    c[3][k] = s3;
}

#if PERSP_HAVE_ISA_VARIANTS
/* linear_weigh of 8 pixels, the same operations in the same order (no
 * contraction: the target has no FMA). */
PERSP_TARGET_AVX2 static inline void weigh8_avx2(const __m256i t[4], __m256 a, __m256 b, float c[4][N],
                                                 int k)
{
    const __m256 one = _mm256_set1_ps(1.0f), ra = _mm256_sub_ps(one, a), rb = _mm256_sub_ps(one, b);
    const __m256 w[4] = {_mm256_mul_ps(ra, rb), _mm256_mul_ps(a, rb), _mm256_mul_ps(ra, b), _mm256_mul_ps(a, b)};
    for (int ch = 0; ch < 4; ch++) {
        const __m256i m = _mm256_set1_epi32((int32_t)(0xffu << 8 * ch));
        __m256 sum = _mm256_setzero_ps();
        for (int i = 0; i < 4; i++) {
            const __m256i v = ch < 3 ? _mm256_and_si256(t[i], m) : _mm256_srli_epi32(t[i], 24);
            const __m256 term = _mm256_mul_ps(w[i], _mm256_cvtepi32_ps(v));
            sum = i ? _mm256_add_ps(sum, term) : term;
        }
        if (ch == 1 || ch == 2) sum = _mm256_mul_ps(sum, _mm256_set1_ps(ch == 1 ? 0x1p-8f : 0x1p-16f));
        _mm256_storeu_ps(c[ch] + k, sum);
    }
}

/* Stages 3-4 of the AVX2 variant. The two texels of a row that a pixel
 * filters are neighbours in memory unless the pair wraps or is clamped at
 * the level's edge, so each row is one 64-bit load per pixel rather than
 * two 32-bit ones, and the pairs of 8 pixels are split into their 00 and
 * 10 texels by two shuffles. The vectoriser builds a vector of 8
 * scattered texels from 8 loads and 8 inserts; pairs halve both. A group
 * of 8 with a pixel at the edge is fetched texel by texel; a10 = a00 + 1
 * also means that the second texel of every pair loaded exists. Not
 * inlined, so that the other variants, which never call it, are not
 * compiled for AVX2. */
PERSP_TARGET_AVX2 static void linear_sum_avx2(const uint32_t *restrict tex, int n,
                                              const int32_t *restrict a00, const int32_t *restrict a10,
                                              const int32_t *restrict a01, const int32_t *restrict a11,
                                              const float *restrict fa, const float *restrict fb,
                                              float c[4][N])
{
    int k = 0;
    for (; k + 8 <= n; k += 8) {
        const __m256i i00 = _mm256_loadu_si256((const __m256i *)(const void *)(a00 + k));
        const __m256i i10 = _mm256_loadu_si256((const __m256i *)(const void *)(a10 + k));
        const __m256i next = _mm256_add_epi32(i00, _mm256_set1_epi32(1));
        __m256i t[4];
        if (_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(i10, next))) == 0xff) {
            for (int r = 0; r < 2; r++) {
                const int32_t *a = (r ? a01 : a00) + k;
#define PAIR(i, j)                                                                                 \
    _mm_castpd_si128(_mm_loadh_pd(                                                                 \
        _mm_castsi128_pd(_mm_loadl_epi64((const __m128i *)(const void *)(tex + a[i]))),           \
        (const double *)(const void *)(tex + a[j])))
                const __m128i p01 = PAIR(0, 1), p23 = PAIR(2, 3), p45 = PAIR(4, 5), p67 = PAIR(6, 7);
#undef PAIR
                const __m256 lo = _mm256_castsi256_ps(_mm256_inserti128_si256(_mm256_castsi128_si256(p01), p45, 1));
                const __m256 hi = _mm256_castsi256_ps(_mm256_inserti128_si256(_mm256_castsi128_si256(p23), p67, 1));
                t[2 * r] = _mm256_castps_si256(_mm256_shuffle_ps(lo, hi, 0x88));
                t[2 * r + 1] = _mm256_castps_si256(_mm256_shuffle_ps(lo, hi, 0xdd));
            }
        } else {
            uint32_t e[4][8];
            for (int j = 0; j < 8; j++) {
                e[0][j] = tex[a00[k + j]];
                e[1][j] = tex[a10[k + j]];
                e[2][j] = tex[a01[k + j]];
                e[3][j] = tex[a11[k + j]];
            }
            for (int r = 0; r < 4; r++) t[r] = _mm256_loadu_si256((const __m256i *)(const void *)e[r]);
        }
        weigh8_avx2(t, _mm256_loadu_ps(fa + k), _mm256_loadu_ps(fb + k), c, k);
    }
    for (; k < n; k++) linear_weigh(tex[a00[k]], tex[a10[k]], tex[a01[k]], tex[a11[k]], fa[k], fb[k], c, k);
}
#endif

/* Stages 3-4: fetch and weigh. pairs: linear_sum_avx2 (the AVX2 variant
 * only). */
static inline PERSP_INLINE void linear_sum(const uint32_t *restrict tex, int n,
                                           const int32_t *restrict a00, const int32_t *restrict a10,
                                           const int32_t *restrict a01, const int32_t *restrict a11,
                                           const float *restrict fa, const float *restrict fb,
                                           float c[4][N], int pairs)
{
#if PERSP_HAVE_ISA_VARIANTS
    if (pairs) {
        /* GCC cannot see that the callee reads the addresses only below n,
         * where linear_taps set them. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
        linear_sum_avx2(tex, n, a00, a10, a01, a11, fa, fb, c);
#pragma GCC diagnostic pop
        return;
    }
#endif
    (void)pairs;
    for (int k = 0; k < n; k++)
        linear_weigh(tex[a00[k]], tex[a10[k]], tex[a01[k]], tex[a11[k]], fa[k], fb[k], c, k);
}

static inline PERSP_INLINE void pack_span(int n, float c[4][N], uint32_t *out)
{
    for (int k = 0; k < n; k++)
        out[k] = pack_ch(c[0][k]) | pack_ch(c[1][k]) << 8 | pack_ch(c[2][k]) << 16 |
                 pack_ch(c[3][k]) << 24;
}

/* Texel addresses of the nearest filter on level lev[k] of each pixel (or
 * level 0 for all when lev == NULL): wrap(floor(s·W_l)). */
static inline PERSP_INLINE void nearest_addr(const persp_tex_pot *restrict p, int ws, int wt, int n,
                                             const float *restrict u, const float *restrict v,
                                             const int32_t *restrict lev, int32_t *restrict addr)
{
    const int32_t w0 = p->wmask[0] + 1, h0 = p->hmask[0] + 1, s0 = p->shift[0];
    for (int k = 0; k < n; k++) {
        int32_t l = lev ? lev[k] : 0;
        int32_t wl = w0 >> l, hl = h0 >> l, sh = s0 - l;
        wl = wl > 1 ? wl : 1;
        hl = hl > 1 ? hl : 1;
        sh = sh > 0 ? sh : 0;
        int32_t i = (int32_t)floorf(safe_coord(u[k] * (float)wl, p->coord_limit));
        int32_t j = (int32_t)floorf(safe_coord(v[k] * (float)hl, p->coord_limit));
        int32_t off = lev ? p->off[l] : 0;
        addr[k] = off + (wrap_i(wt, j, hl - 1) << sh) + wrap_i(ws, i, wl - 1);
    }
}

static inline PERSP_INLINE void span_nearest(const persp_sampler_state *st, const persp_tex_span_in *in,
                                             uint32_t *out, int ws, int wt, int pairs)
{
    (void)pairs;
    const uint32_t *restrict tex = st->tex->storage;
    uint32_t *restrict dst = out;
    const int n = in->n;
    int32_t addr[N];
    nearest_addr(&st->pot, ws, wt, n, in->u, in->v, NULL, addr);
    for (int k = 0; k < n; k++) dst[k] = tex[addr[k]];
}

/* Lambda of every pixel: from the Jacobian (persp__span_jacobian,
 * persp__jac_lambda) or once per polygon, as span_iso of sampler.c. */
static inline PERSP_INLINE void span_lambda(const persp_sampler_state *st,
                                            const persp_tex_span_in *in, float *lam)
{
    if (st->desc.lod_mode == PERSP_LOD_POLYGON) {
        float l = persp__clamp_lod(st, in->poly_lambda + st->lod_bias);
        for (int k = 0; k < in->n; k++) lam[k] = l;
    } else {
        for (int k = 0; k < in->n; k++) lam[k] = persp__jac_lambda(st, persp__span_jacobian(st, in, k));
    }
}

/* The lowest and highest level of a span's pixels, for linear_taps. */
typedef struct {
    int32_t lo, hi;
} lev_range;

/* *_MIP_NEAREST level (GL 4.6 eq. 8.17, mip_nearest_level of sampler.c):
 * 0 when lambda <= 1/2, else ceil(lambda + 1/2) - 1 up to the last level;
 * their range into r unless it is NULL. */

static inline PERSP_INLINE void mip_nearest_levels(const persp_sampler_state *st, int n,
                                                   const float *lam, int32_t *lev,
                                                   lev_range *r)
{
    const float top = (float)(st->tex->levels - 1);
    int32_t lo = INT32_MAX, hi = 0;
    for (int k = 0; k < n; k++) {
        float d = ceilf(lam[k] + 0.5f) - 1.0f;
        d = d >= top ? top : d;
        lev[k] = lam[k] <= 0.5f ? 0 : (int32_t)d;
        lo = lev[k] < lo ? lev[k] : lo;
        hi = lev[k] > hi ? lev[k] : hi;
    }
    if (r) *r = (lev_range){lo, hi};
}

/* Blend level d1 towards d2 by f (trilinear and nearest-mip-linear): the
 * levels and factor of every pixel, the ranges of d1 and d2 into r unless
 * it is NULL; returns whether any pixel blends. */
static inline PERSP_INLINE int mip_linear_levels(const persp_sampler_state *st, int n,
                                                 const float *lam, int32_t *d1, int32_t *d2,
                                                 float *f, lev_range r[2])
{
    const int32_t top = st->tex->levels - 1;
    int blend = 0;
    int32_t lo1 = INT32_MAX, hi1 = 0, lo2 = INT32_MAX, hi2 = 0;
    for (int k = 0; k < n; k++) {
        float l = lam[k];
        float fl = floorf(l);
        int32_t il = (int32_t)fl;
        int mag = l <= 0.0f, last = il >= top;
        d1[k] = mag ? 0 : last ? top : il;
        f[k] = mag || last ? 0.0f : l - fl;
        d2[k] = mag || last ? d1[k] : il + 1;
        blend |= !(mag || last);
        lo1 = d1[k] < lo1 ? d1[k] : lo1;
        hi1 = d1[k] > hi1 ? d1[k] : hi1;
        lo2 = d2[k] < lo2 ? d2[k] : lo2;
        hi2 = d2[k] > hi2 ? d2[k] : hi2;
    }
    if (r) {
        r[0] = (lev_range){lo1, hi1};
        r[1] = (lev_range){lo2, hi2};
    }
    return blend;
}

static inline PERSP_INLINE void span_nmn(const persp_sampler_state *st, const persp_tex_span_in *in,
                                         uint32_t *out, int ws, int wt, int pairs)
{
    (void)pairs;
    const uint32_t *restrict tex = st->tex->storage;
    uint32_t *restrict dst = out;
    const int n = in->n;
    float lam[N];
    int32_t lev[N], addr[N];
    span_lambda(st, in, lam);
    mip_nearest_levels(st, n, lam, lev, NULL);
    nearest_addr(&st->pot, ws, wt, n, in->u, in->v, lev, addr);
    for (int k = 0; k < n; k++) dst[k] = tex[addr[k]];
}

static inline PERSP_INLINE void span_bmn(const persp_sampler_state *st, const persp_tex_span_in *in,
                                         uint32_t *out, int ws, int wt, int pairs)
{
    const int n = in->n;
    float lam[N], fa[N], fb[N], c[4][N];
    int32_t lev[N], a00[N], a10[N], a01[N], a11[N];
    span_lambda(st, in, lam);
    lev_range r;
    mip_nearest_levels(st, n, lam, lev, &r);
    linear_taps(&st->pot, ws, wt, n, in->u, in->v, lev, r.lo, r.hi, a00, a10, a01, a11, fa, fb);
    linear_sum(st->tex->storage, n, a00, a10, a01, a11, fa, fb, c, pairs);
    pack_span(n, c, out);
}

/* Nearest-mip-linear: the nearest texels of two levels blended per channel
 * in float (sampler.c: c1 + f·(c2 − c1), one rounding at the end). */
static inline PERSP_INLINE void span_nml(const persp_sampler_state *st, const persp_tex_span_in *in,
                                         uint32_t *out, int ws, int wt, int pairs)
{
    (void)pairs;
    const uint32_t *restrict tex = st->tex->storage;
    const int n = in->n;
    float lam[N], f[N], c[4][N];
    int32_t d1[N], d2[N], a1[N], a2[N];
    span_lambda(st, in, lam);
    mip_linear_levels(st, n, lam, d1, d2, f, NULL);
    nearest_addr(&st->pot, ws, wt, n, in->u, in->v, d1, a1);
    nearest_addr(&st->pot, ws, wt, n, in->u, in->v, d2, a2);
    for (int k = 0; k < n; k++) {
        uint32_t t1 = tex[a1[k]], t2 = tex[a2[k]];
        for (int ch = 0; ch < 4; ch++) {
            float c1 = (float)(int32_t)(t1 >> (8 * ch) & 0xffu);
            float c2 = (float)(int32_t)(t2 >> (8 * ch) & 0xffu);
            c[ch][k] = c1 + f[k] * (c2 - c1);
        }
    }
    pack_span(n, c, out);
}

static inline PERSP_INLINE void span_bilinear(const persp_sampler_state *st, const persp_tex_span_in *in,
                                 uint32_t *out, int ws, int wt, int pairs)
{
    int32_t a00[N], a10[N], a01[N], a11[N];
    float fa[N], fb[N], c[4][N];
    linear_taps(&st->pot, ws, wt, in->n, in->u, in->v, NULL, 0, 0, a00, a10, a01, a11, fa, fb);
    linear_sum(st->tex->level[0].texels, in->n, a00, a10, a01, a11, fa, fb, c, pairs);
    pack_span(in->n, c, out);
}

/* Trilinear (GL 4.6 §8.14.3) with lambda per pixel from the Jacobian
 * (persp__span_jacobian, persp__jac_lambda) or once per polygon. A pixel
 * whose lambda is <= 0 (magnified) or at the last level takes one level with
 * blend factor 0, for which c1 + 0·(c2 − c1) = c1 exactly; the second level
 * is fetched only when some pixel of the span blends. */
static inline PERSP_INLINE void span_trilinear(const persp_sampler_state *st, const persp_tex_span_in *in,
                                  uint32_t *out, int ws, int wt, int pairs)
{
    const int n = in->n;
    const uint32_t *tex = st->tex->storage;
    float lam[N], f[N];
    int32_t d1[N], d2[N];
    span_lambda(st, in, lam);
    lev_range r[2];
    int blend = mip_linear_levels(st, n, lam, d1, d2, f, r);
    int32_t a00[N], a10[N], a01[N], a11[N];
    float fa[N], fb[N], c[4][N];
    linear_taps(&st->pot, ws, wt, n, in->u, in->v, d1, r[0].lo, r[0].hi, a00, a10, a01, a11, fa, fb);
    linear_sum(tex, n, a00, a10, a01, a11, fa, fb, c, pairs);
    if (blend) {
        float c2[4][N];
        linear_taps(&st->pot, ws, wt, n, in->u, in->v, d2, r[1].lo, r[1].hi, a00, a10, a01, a11, fa, fb);
        linear_sum(tex, n, a00, a10, a01, a11, fa, fb, c2, pairs);
        for (int ch = 0; ch < 4; ch++)
            for (int k = 0; k < n; k++) c[ch][k] += f[k] * (c2[ch][k] - c[ch][k]);
    }
    pack_span(n, c, out);
}

/* EXT_texture_filter_anisotropic (sampler.c span_aniso): N trilinear taps
 * along the major axis at the common lambda', averaged. The span runs tap
 * by tap up to its largest N; a pixel whose N is smaller adds 0·c, which
 * leaves its sum exactly as the general sampler's loop over its own N
 * taps leaves it. */
static inline PERSP_INLINE void span_aniso(const persp_sampler_state *st, const persp_tex_span_in *in,
                                           uint32_t *out, int ws, int wt, int pairs)
{
    const int n = in->n;
    const float W = (float)st->tex->width, H = (float)st->tex->height;
    const uint32_t *tex = st->tex->storage;
    float lam[N], du[N], dv[N], inv[N], f[N];
    int32_t taps[N], d1[N], d2[N];
    for (int k = 0; k < n; k++) {
        persp_tex_jac j = persp__span_jacobian(st, in, k);
        int mx;
        taps[k] = persp__aniso_rule(st, j, &lam[k], &mx);
        du[k] = (mx ? j.ux : j.uy) / W;
        dv[k] = (mx ? j.vx : j.vy) / H;
        inv[k] = 1.0f / (float)taps[k];
    }
    int32_t tmax = 1;
    for (int k = 0; k < n; k++) tmax = taps[k] > tmax ? taps[k] : tmax;
    lev_range r[2];
    const int blend = mip_linear_levels(st, n, lam, d1, d2, f, r);
    float acc[4][N];
    for (int ch = 0; ch < 4; ch++)
        for (int k = 0; k < n; k++) acc[ch][k] = 0.0f;
    for (int32_t t = 0; t < tmax; t++) {
        float ut[N], vt[N], m[N], fa[N], fb[N], c[4][N];
        int32_t a00[N], a10[N], a01[N], a11[N];
        for (int k = 0; k < n; k++) {
            float sk = ((float)t + 0.5f) * inv[k] - 0.5f;
            ut[k] = in->u[k] + sk * du[k];
            vt[k] = in->v[k] + sk * dv[k];
            m[k] = t < taps[k] ? 1.0f : 0.0f;
        }
        linear_taps(&st->pot, ws, wt, n, ut, vt, d1, r[0].lo, r[0].hi, a00, a10, a01, a11, fa, fb);
        linear_sum(tex, n, a00, a10, a01, a11, fa, fb, c, pairs);
        if (blend) {
            float c2[4][N];
            linear_taps(&st->pot, ws, wt, n, ut, vt, d2, r[1].lo, r[1].hi, a00, a10, a01, a11, fa, fb);
            linear_sum(tex, n, a00, a10, a01, a11, fa, fb, c2, pairs);
            for (int ch = 0; ch < 4; ch++)
                for (int k = 0; k < n; k++) c[ch][k] += f[k] * (c2[ch][k] - c[ch][k]);
        }
        for (int ch = 0; ch < 4; ch++)
            for (int k = 0; k < n; k++) acc[ch][k] += m[k] * c[ch][k];
    }
    for (int ch = 0; ch < 4; ch++)
        for (int k = 0; k < n; k++) acc[ch][k] *= inv[k];
    pack_span(n, acc, out);
}

/* One function per wrap pair (repeat/clamp-to-edge on s and t) of a body,
 * and the table of the four. */
#define FAST(NAME, ATTR, BODY, WS, WT, PAIRS)                                                      \
    ATTR static void NAME(const persp_sampler_state *st, const persp_tex_span_in *in, uint32_t *out) \
    {                                                                                              \
        BODY(st, in, out, WS, WT, PAIRS);                                                          \
    }
#define FAST4(P, ATTR, BODY, PAIRS)                                                                \
    FAST(P##_RR, ATTR, BODY, PERSP_WRAP_REPEAT, PERSP_WRAP_REPEAT, PAIRS)                          \
    FAST(P##_RE, ATTR, BODY, PERSP_WRAP_REPEAT, PERSP_WRAP_CLAMP_TO_EDGE, PAIRS)                   \
    FAST(P##_ER, ATTR, BODY, PERSP_WRAP_CLAMP_TO_EDGE, PERSP_WRAP_REPEAT, PAIRS)                   \
    FAST(P##_EE, ATTR, BODY, PERSP_WRAP_CLAMP_TO_EDGE, PERSP_WRAP_CLAMP_TO_EDGE, PAIRS)            \
    static const persp_tex_span_fn P[4] = {P##_RR, P##_RE, P##_ER, P##_EE};
/* One instruction-set variant: every body as its wrap pairs, and NAME, the
 * variant's table [filter][wrap pair] for the filters nearest .. aniso
 * (persp_filter order). STORAGE is static or empty; PAIRS 1 fetches with
 * linear_sum_avx2. */
#define FAST_VARIANT(STORAGE, NAME, V, ATTR, PAIRS)                                                \
    FAST4(nearest_##V, ATTR, span_nearest, PAIRS)                                                  \
    FAST4(bilinear_##V, ATTR, span_bilinear, PAIRS)                                                \
    FAST4(nmn_##V, ATTR, span_nmn, PAIRS)                                                          \
    FAST4(bmn_##V, ATTR, span_bmn, PAIRS)                                                          \
    FAST4(nml_##V, ATTR, span_nml, PAIRS)                                                          \
    FAST4(trilinear_##V, ATTR, span_trilinear, PAIRS)                                              \
    FAST4(aniso_##V, ATTR, span_aniso, PAIRS)                                                      \
    STORAGE const persp_tex_span_fn *const NAME[7] = {nearest_##V, bilinear_##V, nmn_##V,          \
                                                      bmn_##V,     nml_##V,      trilinear_##V,    \
                                                      aniso_##V};

#if PERSP_HAVE_ISA_VARIANTS
/* fastspan_gather.c: texels fetched by the vectoriser's gathers. */
extern const persp_tex_span_fn *const persp__fast_avx2g[7];
extern const persp_tex_span_fn *const persp__fast_avx512g[7];
#endif

#endif
