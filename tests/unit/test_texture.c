/*
 * Textures and samplers (src/texture/): mip chains for any size, the
 * samplers in the style of dEQP (every result inside the range reachable
 * from its coordinate, level of detail and colour precision), the level of
 * detail from the analytic Jacobian, EXT_texture_filter_anisotropic's tap
 * rule, the rotated window's daisy-chain traversal against a direct one,
 * and the EWA weight table. Expected values are computed here from the
 * rules' definitions, not taken from the code under test.
 */
#include "support.h"

#include "texture/sample.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static persp_texture *make_texture(persp_context *ctx, int w, int h, uint32_t (*fn)(int x, int y, void *),
                                   void *user)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, w, h, &img), PERSP_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint32_t c = fn(x, y, user);
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            for (int k = 0; k < 4; k++) p[k] = (uint8_t)(c >> (8 * k));
        }
    persp_texture *t = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &t), PERSP_OK);
    persp_image_free(ctx, &img);
    return t;
}

static uint32_t random_texel(int x, int y, void *user)
{
    (void)x, (void)y;
    return (uint32_t)test_rng_next(user);
}

static uint8_t texel_channel(const persp_texture *t, int level, int x, int y, int c)
{
    persp_image_view v;
    assert_int_equal(persp_texture_level(t, level, &v), PERSP_OK);
    return v.pixels[(size_t)y * v.stride + 4 * (size_t)x + (size_t)c];
}

/* ------------------------------------------------------------ mip chains */

static void test_mip_sizes_any_shape(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {7};
    const int sizes[][2] = {{1, 1}, {256, 256}, {256, 64}, {7, 5}, {13, 1}, {1, 9}, {100, 37}, {3, 3}, {640, 480}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        int W = sizes[s][0], H = sizes[s][1];
        persp_texture *t = make_texture(ctx, W, H, random_texel, &rng);
        int big = W > H ? W : H, expect_levels = 1;
        while (big > 1) big /= 2, expect_levels++;
        assert_int_equal(persp_texture_levels(t), expect_levels);
        size_t total = 0;
        for (int l = 0; l < expect_levels; l++) {
            persp_image_view v;
            assert_int_equal(persp_texture_level(t, l, &v), PERSP_OK);
            int ew = W >> l, eh = H >> l;
            if (ew < 1) ew = 1;
            if (eh < 1) eh = 1;
            if (v.width != ew || v.height != eh)
                fail_msg("%dx%d level %d is %dx%d, expected %dx%d", W, H, l, v.width, v.height, ew, eh);
            total += (size_t)ew * (size_t)eh * 4;
        }
        persp_image_view v;
        assert_int_equal(persp_texture_level(t, expect_levels, &v), PERSP_ERR_NOT_FOUND);
        assert_int_equal(persp_texture_level(t, expect_levels - 1, &v), PERSP_OK);
        assert_int_equal(v.width, 1);
        assert_int_equal(v.height, 1);
        size_t all, base;
        persp_texture_memory(t, &all, &base);
        assert_true(all == total);
        assert_true(base == (size_t)W * (size_t)H * 4);
        persp_texture_destroy(t);
    }
    /* The overhead of a full square chain is sum 4^-k - 1 -> 1/3. */
    persp_texture *t = make_texture(ctx, 256, 256, random_texel, &rng);
    size_t all, base;
    persp_texture_memory(t, &all, &base);
    double overhead = (double)all / (double)base - 1.0;
    assert_true(fabs(overhead - 1.0 / 3.0) < 1e-4);
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* Even axes: the 2×2 box, i.e. the rounded mean of four texels. */
static void test_mip_even_is_box_average(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {11};
    persp_texture *t = make_texture(ctx, 64, 32, random_texel, &rng);
    for (int l = 1; l < persp_texture_levels(t); l++) {
        persp_image_view v, p;
        persp_texture_level(t, l, &v);
        persp_texture_level(t, l - 1, &p);
        for (int y = 0; y < v.height; y++)
            for (int x = 0; x < v.width; x++)
                for (int c = 0; c < 4; c++) {
                    double sum = 0.0;
                    int n = 0;
                    for (int dy = 0; dy < 2; dy++)
                        for (int dx = 0; dx < 2; dx++) {
                            int sx = 2 * x + dx, sy = 2 * y + dy;
                            if (sx >= p.width || sy >= p.height) continue;
                            sum += texel_channel(t, l - 1, sx, sy, c);
                            n++;
                        }
                    double want = sum / n;
                    int got = texel_channel(t, l, x, y, c);
                    if (fabs(got - want) > 0.5 + 1e-6)
                        fail_msg("level %d (%d,%d) c%d = %d, box mean %.3f", l, x, y, c, got, want);
                }
    }
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* Weight of source texel k in output texel i when an axis of n texels
 * (odd) shrinks to m = floor(n/2): the overlap of [i·n/m, (i+1)·n/m) with
 * [k, k+1), normalised by n/m (the exact box filter, docs/TEXTURES.md). */
static double box_overlap(int n, int m, int i, int k)
{
    double a = (double)i * n / m, b = (double)(i + 1) * n / m;
    double lo = a > k ? a : k, hi = b < k + 1 ? b : k + 1;
    return hi > lo ? (hi - lo) / ((double)n / m) : 0.0;
}

static void test_mip_odd_is_exact_box(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {5};
    const int sizes[][2] = {{7, 5}, {9, 1}, {1, 11}, {15, 6}, {5, 5}, {3, 3}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        persp_texture *t = make_texture(ctx, sizes[s][0], sizes[s][1], random_texel, &rng);
        persp_image_view p, v;
        persp_texture_level(t, 0, &p);
        persp_texture_level(t, 1, &v);
        for (int y = 0; y < v.height; y++)
            for (int x = 0; x < v.width; x++)
                for (int c = 0; c < 4; c++) {
                    double want = 0.0, wsum = 0.0;
                    for (int sy = 0; sy < p.height; sy++)
                        for (int sx = 0; sx < p.width; sx++) {
                            double wx = p.width == 1 ? 1.0
                                        : (p.width & 1) ? box_overlap(p.width, v.width, x, sx)
                                                        : (sx / 2 == x ? 0.5 : 0.0);
                            double wy = p.height == 1 ? 1.0
                                        : (p.height & 1) ? box_overlap(p.height, v.height, y, sy)
                                                         : (sy / 2 == y ? 0.5 : 0.0);
                            want += wx * wy * texel_channel(t, 0, sx, sy, c);
                            wsum += wx * wy;
                        }
                    assert_true(fabs(wsum - 1.0) < 1e-9);
                    int got = texel_channel(t, 1, x, y, c);
                    if (fabs(got - want) > 0.5 + 1e-3)
                        fail_msg("%dx%d -> (%d,%d) c%d = %d, exact box %.3f", p.width, p.height, x, y, c,
                                 got, want);
                }
        /* Every source texel carries the same total weight, so each level's
         * mean stays the image mean up to the 8-bit rounding of each level. */
        double mean0 = 0.0;
        for (int y = 0; y < p.height; y++)
            for (int x = 0; x < p.width; x++) mean0 += texel_channel(t, 0, x, y, 0);
        mean0 /= (double)p.width * p.height;
        for (int l = 1; l < persp_texture_levels(t); l++) {
            persp_texture_level(t, l, &v);
            double mean = 0.0;
            for (int y = 0; y < v.height; y++)
                for (int x = 0; x < v.width; x++) mean += texel_channel(t, l, x, y, 0);
            mean /= (double)v.width * v.height;
            if (fabs(mean - mean0) > 0.5 * l + 1e-9)
                fail_msg("%dx%d level %d mean %.3f vs %.3f", p.width, p.height, l, mean, mean0);
        }
        persp_texture_destroy(t);
    }
    persp_context_destroy(ctx);
}

/* ---------------------------------------------------------- dEQP-style */

/* A texture whose red channel encodes x and green channel y, monotonically,
 * so the reachable range of a lookup is the range of its texel box (through
 * the wrap modes: any of the four, on each axis). */
static uint32_t gradient_texel(int x, int y, void *user)
{
    const int *wh = user;
    uint32_t r = (uint32_t)(x * 255 / (wh[0] - 1)), g = (uint32_t)(y * 255 / (wh[1] - 1));
    uint32_t b = (uint32_t)((x * 7 + y * 13) & 0xff);
    return r | g << 8 | b << 16 | 0xffu << 24;
}

/* GL 4.6 Table 8.20, written out here independently: the texel index of
 * integer coordinate i on an axis of n texels, -1 for the border colour. */
static int gl_wrap(persp_wrap mode, int i, int n)
{
    switch (mode) {
    case PERSP_WRAP_REPEAT:
        return ((i % n) + n) % n;
    case PERSP_WRAP_CLAMP_TO_EDGE:
        return i < 0 ? 0 : i >= n ? n - 1 : i;
    case PERSP_WRAP_MIRRORED_REPEAT: {
        int m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return m < n ? m : 2 * n - 1 - m;
    }
    default:
        return i < 0 || i >= n ? -1 : i;
    }
}

static const uint8_t border_rgba[4] = {10, 240, 128, 255};

/* Min/max of channel c over the texels of `level` whose centres lie within
 * [x0, x1] × [y0, y1] (level-0 texel units) widened by one level texel
 * (coordinate precision), addressed through the wrap modes. */
static void level_range(const persp_texture *t, int level, persp_wrap ws, persp_wrap wt, double x0,
                        double x1, double y0, double y1, int c, int *lo, int *hi)
{
    persp_image_view v;
    persp_texture_level(t, level, &v);
    double sx = (double)v.width / persp_texture_width(t), sy = (double)v.height / persp_texture_height(t);
    int i0 = (int)floor(x0 * sx - 1.5), i1 = (int)ceil(x1 * sx + 0.5);
    int j0 = (int)floor(y0 * sy - 1.5), j1 = (int)ceil(y1 * sy + 0.5);
    /* A footprint wider than the level covers all of it. */
    if (i1 - i0 > 2 * v.width) i0 = -v.width, i1 = v.width;
    if (j1 - j0 > 2 * v.height) j0 = -v.height, j1 = v.height;
    for (int j = j0; j <= j1; j++)
        for (int i = i0; i <= i1; i++) {
            int ci = gl_wrap(ws, i, v.width), cj = gl_wrap(wt, j, v.height);
            int val = ci < 0 || cj < 0 ? border_rgba[c] : texel_channel(t, level, ci, cj, c);
            if (val < *lo) *lo = val;
            if (val > *hi) *hi = val;
        }
}

static void test_samplers_inside_reachable_range(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const int W = 128, H = 64;
    int wh[2] = {W, H};
    persp_texture *t = make_texture(ctx, W, H, gradient_texel, wh);
    const int top = persp_texture_levels(t) - 1;
    test_rng rng = {99};
    for (int f = PERSP_FILTER_NEAREST; f < PERSP_FILTER_COUNT; f++) {
        for (int it = 0; it < 400; it++) {
            persp_sampler_desc sd;
            memset(&sd, 0, sizeof sd);
            sd.wrap_s = (persp_wrap)(PERSP_WRAP_REPEAT + (int)(test_rng_next(&rng) % 4));
            sd.wrap_t = (persp_wrap)(PERSP_WRAP_REPEAT + (int)(test_rng_next(&rng) % 4));
            memcpy(sd.border, border_rgba, 4);
            sd.filter = (persp_filter)f;
            sd.max_aniso = 2 + (int)(test_rng_next(&rng) % 15);
            float u = (float)test_rng_uniform(&rng, -1.5, 2.5), v = (float)test_rng_uniform(&rng, -1.5, 2.5);
            /* Footprints from strongly magnified to strongly minified, any
             * orientation and anisotropy. */
            double scale = exp2(test_rng_uniform(&rng, -3.0, 7.0)), ang = test_rng_uniform(&rng, 0, 6.283);
            double an = exp2(test_rng_uniform(&rng, 0.0, 4.0));
            double px = scale, py = scale / an;
            double ux = px * cos(ang), vx = px * sin(ang), uy = -py * sin(ang), vy = py * cos(ang);
            uint8_t got[4];
            persp_texture_sample(t, &sd, u, v, (float)(ux / W), (float)(vx / H), (float)(uy / W),
                                 (float)(vy / H), got);
            /* Reachable levels: every level between the lambdas any of the
             * filters' rules can pick (GL rho, EXT lambda', EWA's minor
             * axis, the window's lambda' - 1), one level of slack. */
            double lam_rho = log2(px), lam_min = log2(py);
            int l0 = (int)floor(fmin(lam_min, lam_rho - 5.0)) - 1, l1 = (int)ceil(lam_rho) + 1;
            if (f <= PERSP_FILTER_BILINEAR) l0 = l1 = 0;
            if (f >= PERSP_FILTER_NEAREST_MIP_NEAREST && f <= PERSP_FILTER_TRILINEAR)
                l0 = (int)floor(lam_rho) - 1, l1 = (int)ceil(lam_rho) + 1;
            if (l0 < 0) l0 = 0;
            if (l1 < 0) l1 = 0;
            if (l1 > top) l1 = top;
            if (l0 > top) l0 = top;
            /* Reachable texels: the footprint's bounding box around (u, v)
             * for the filters that integrate it, the point itself for the
             * others. */
            double cx = u * W, cy = v * H, ex = 0.0, ey = 0.0;
            if (f >= PERSP_FILTER_ANISO) ex = fabs(ux) + fabs(uy), ey = fabs(vx) + fabs(vy);
            for (int c = 0; c < 3; c++) {
                int lo = 255, hi = 0;
                for (int l = l0; l <= l1; l++) {
                    double pad = ldexp(1.0, l); /* one texel of the level in level-0 units */
                    level_range(t, l, sd.wrap_s, sd.wrap_t, cx - ex - pad, cx + ex + pad, cy - ey - pad,
                                cy + ey + pad, c, &lo, &hi);
                }
                /* Colour precision: one 8-bit step of rounding. */
                if (got[c] + 1 < lo || got[c] > hi + 1)
                    fail_msg("filter %s, wrap %s/%s at (%.4f, %.4f), footprint %.3g x %.3g: channel %d = %d "
                             "outside [%d, %d] (levels %d..%d)",
                             persp_filter_name((persp_filter)f), persp_wrap_name(sd.wrap_s),
                             persp_wrap_name(sd.wrap_t), (double)u, (double)v, px, py, c, got[c], lo, hi, l0,
                             l1);
            }
        }
    }
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* Nearest without mipmaps returns exactly the texel holding (u, v) (GL 4.6
 * §8.14.2: i = floor(u·W)), away from texel borders. */
static void test_nearest_exact_texel(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {3};
    persp_texture *t = make_texture(ctx, 37, 23, random_texel, &rng);
    persp_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.filter = PERSP_FILTER_NEAREST;
    for (int it = 0; it < 2000; it++) {
        int i = (int)(test_rng_next(&rng) % 37), j = (int)(test_rng_next(&rng) % 23);
        int rep = (int)(test_rng_next(&rng) % 5) - 2;
        double fu = test_rng_uniform(&rng, 0.01, 0.99), fv = test_rng_uniform(&rng, 0.01, 0.99);
        float u = (float)((i + fu) / 37.0 + rep), v = (float)((j + fv) / 23.0 - rep);
        uint8_t got[4];
        persp_texture_sample(t, &sd, u, v, 0.1f, 0.0f, 0.0f, 0.1f, got);
        for (int c = 0; c < 4; c++) assert_int_equal(got[c], texel_channel(t, 0, i, j, c));
    }
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* ------------------------------------------------------ level of detail */

static void test_lod_rules(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {17};
    persp_texture *t = make_texture(ctx, 256, 128, random_texel, &rng);
    persp_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.filter = PERSP_FILTER_TRILINEAR;
    persp_sampler_state st;
    assert_int_equal(persp__sampler_init(&st, t, &sd), PERSP_OK);
    /* GL 4.6 eq. 8.6/8.7: lambda = log2 max(|d(u,v)/dx|, |d(u,v)/dy|) in texels. */
    for (int it = 0; it < 200; it++) {
        double ux = test_rng_uniform(&rng, -20, 20), vx = test_rng_uniform(&rng, -20, 20);
        double uy = test_rng_uniform(&rng, -20, 20), vy = test_rng_uniform(&rng, -20, 20);
        double want = 0.5 * log2(fmax(ux * ux + vx * vx, uy * uy + vy * vy));
        if (want > 7.0) want = 7.0; /* the chain's top level of a 256×128 texture */
        float got = persp__pixel_lambda(&st, (float)(ux / 256), (float)(vx / 128), (float)(uy / 256),
                                        (float)(vy / 128));
        assert_true(fabs(got - want) < 1e-4);
    }
    /* Bias, then [min_lod, max_lod]. */
    sd.lod_bias = 1.5f;
    sd.lod_clamp = PERSP_TOGGLE_ON;
    sd.min_lod = 0.25f;
    sd.max_lod = 3.0f;
    assert_int_equal(persp__sampler_init(&st, t, &sd), PERSP_OK);
    assert_true(fabsf(persp__pixel_lambda(&st, 2.0f / 256, 0, 0, 2.0f / 128) - 2.5f) < 1e-5f);
    assert_true(fabsf(persp__pixel_lambda(&st, 16.0f / 256, 0, 0, 16.0f / 128) - 3.0f) < 1e-5f);
    assert_true(fabsf(persp__pixel_lambda(&st, 0.01f / 256, 0, 0, 0.01f / 128) - 0.25f) < 1e-5f);
    /* Per polygon ([CS300-TexMap]): 0.5·log2(texel area / pixel area). */
    /* uv area 1/2 (16 384 texels of 256×128) over 64·32/2 = 1024 pixels. */
    const double px[3] = {0, 64, 0}, py[3] = {0, 0, 32}, pu[3] = {0, 1, 0}, pv[3] = {0, 0, 1};
    assert_true(fabsf(persp__polygon_lambda(t, px, py, pu, pv) - 2.0f) < 1e-6f);
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* The span Jacobian du/dx = (a - u·g)/Q ... ([Romanyuk-PCF] §4.8) is the
 * derivative of the rational mapping: compare with central differences of
 * the mapping evaluated in double here. */
static void test_span_jacobian_is_derivative(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {23};
    persp_texture *t = make_texture(ctx, 64, 32, random_texel, &rng);
    persp_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.filter = PERSP_FILTER_TRILINEAR;
    persp_sampler_state st;
    assert_int_equal(persp__sampler_init(&st, t, &sd), PERSP_OK);
    for (int it = 0; it < 300; it++) {
        double a = test_rng_uniform(&rng, -0.01, 0.01), b = test_rng_uniform(&rng, -0.01, 0.01);
        double c = test_rng_uniform(&rng, -1, 1), d = test_rng_uniform(&rng, -0.01, 0.01);
        double e = test_rng_uniform(&rng, -0.01, 0.01), f = test_rng_uniform(&rng, -1, 1);
        double g = test_rng_uniform(&rng, -0.002, 0.002), h = test_rng_uniform(&rng, -0.002, 0.002);
        double i = test_rng_uniform(&rng, 0.5, 2.0);
        double x = test_rng_uniform(&rng, 0, 200), y = test_rng_uniform(&rng, 0, 200);
        double q = g * x + h * y + i;
        if (q < 0.2) continue;
#define U(X, Y) ((a * (X) + b * (Y) + c) / (g * (X) + h * (Y) + i))
#define V(X, Y) ((d * (X) + e * (Y) + f) / (g * (X) + h * (Y) + i))
        float u = (float)U(x, y), v = (float)V(x, y), qf = (float)q;
        persp_tex_span_in in = {.n = 1, .u = &u, .v = &v, .q = &qf, .a = (float)a, .b = (float)b,
                                .d = (float)d, .e = (float)e, .g = (float)g, .h = (float)h};
        persp_tex_jac j = persp__span_jacobian(&st, &in, 0);
        const double s = 1e-3;
        double want[4] = {(U(x + s, y) - U(x - s, y)) / (2 * s) * 64, (V(x + s, y) - V(x - s, y)) / (2 * s) * 32,
                          (U(x, y + s) - U(x, y - s)) / (2 * s) * 64, (V(x, y + s) - V(x, y - s)) / (2 * s) * 32};
        double got[4] = {j.ux, j.vx, j.uy, j.vy};
        for (int k = 0; k < 4; k++)
            if (fabs(got[k] - want[k]) > 1e-4 * (1.0 + fabs(want[k])))
                fail_msg("Jacobian entry %d: %.8g, central difference %.8g", k, got[k], want[k]);
#undef U
#undef V
    }
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* EXT_texture_filter_anisotropic: N = min(ceil(Pmax/Pmin), maxAniso) taps,
 * lambda' = log2(Pmax / N). */
static void test_aniso_rule(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {31};
    persp_texture *t = make_texture(ctx, 512, 512, random_texel, &rng);
    for (int it = 0; it < 500; it++) {
        persp_sampler_desc sd;
        memset(&sd, 0, sizeof sd);
        sd.filter = PERSP_FILTER_ANISO;
        sd.max_aniso = 2 + (int)(test_rng_next(&rng) % 15);
        persp_sampler_state st;
        assert_int_equal(persp__sampler_init(&st, t, &sd), PERSP_OK);
        double ux = test_rng_uniform(&rng, -40, 40), vx = test_rng_uniform(&rng, -40, 40);
        double uy = test_rng_uniform(&rng, -40, 40), vy = test_rng_uniform(&rng, -40, 40);
        double px = hypot(ux, vx), py = hypot(uy, vy);
        double pmax = fmax(px, py), pmin = fmin(px, py);
        double ratio = pmax / pmin;
        /* Skip ratios within float noise of an integer, where ceil may go
         * either way. */
        if (fabs(ratio - round(ratio)) < 1e-4) continue;
        int n = (int)ceil(ratio);
        if (n > sd.max_aniso) n = sd.max_aniso;
        double lam = log2(pmax / n);
        if (lam > 9.0) lam = 9.0;
        float got_lam;
        int got_n = persp__aniso_taps(&st, (float)(ux / 512), (float)(vx / 512), (float)(uy / 512),
                                      (float)(vy / 512), &got_lam);
        assert_int_equal(got_n, n);
        assert_true(fabs(got_lam - lam) < 1e-4);
    }
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* ---------------------------------------------------- window and EWA */

static int cmp_xy(const void *a, const void *b)
{
    const int *p = a, *q = b;
    if (p[1] != q[1]) return p[1] < q[1] ? -1 : 1;
    return (p[0] > q[0]) - (p[0] < q[0]);
}

/* [Romanyuk-PCF] §4.8: the daisy chain (one interpolator, the step pattern
 * remembered and replayed rotated between rows) visits exactly the texels
 * of the window computed directly as A + P(i) + Q(r), each once. */
static void test_window_daisy_chain_equals_direct(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {41};
    persp_texture *t = make_texture(ctx, 256, 256, random_texel, &rng);
    int tested = 0;
    for (int it = 0; it < 3000; it++) {
        persp_sampler_desc sd;
        memset(&sd, 0, sizeof sd);
        sd.filter = PERSP_FILTER_ANISO_WINDOW;
        sd.max_aniso = 2 + (int)(test_rng_next(&rng) % 15);
        persp_sampler_state st;
        assert_int_equal(persp__sampler_init(&st, t, &sd), PERSP_OK);
        double scale = exp2(test_rng_uniform(&rng, 0.5, 6.0)), ang = test_rng_uniform(&rng, 0, 6.283);
        double an = exp2(test_rng_uniform(&rng, 0.0, 4.5));
        double px = scale, py = scale / an;
        float ux = (float)(px * cos(ang) / 256), vx = (float)(px * sin(ang) / 256);
        float uy = (float)(-py * sin(ang) / 256), vy = (float)(py * cos(ang) / 256);
        float u = (float)test_rng_uniform(&rng, -2, 2), v = (float)test_rng_uniform(&rng, -2, 2);
        persp_tex_window w;
        if (!persp__window_setup(&st, u, v, ux, vx, uy, vy, &w)) continue;
        size_t n = (size_t)w.len * (size_t)w.rows;
        int *a = malloc(2 * n * sizeof *a), *b = malloc(2 * n * sizeof *b);
        assert_non_null(a);
        assert_non_null(b);
        assert_true(persp__window_visit(&st, &w, 1, a, n) == n);
        assert_true(persp__window_visit(&st, &w, 0, b, n) == n);
        /* Consecutive daisy-chain texels are 8-neighbours: one step of one
         * interpolator. */
        for (size_t k = 1; k < n; k++)
            assert_true(abs(a[2 * k] - a[2 * k - 2]) <= 1 && abs(a[2 * k + 1] - a[2 * k - 1]) <= 1);
        qsort(a, n, 2 * sizeof *a, cmp_xy);
        qsort(b, n, 2 * sizeof *b, cmp_xy);
        for (size_t k = 0; k < 2 * n; k++)
            if (a[k] != b[k]) fail_msg("window %dx%d: daisy chain and direct traversal differ", w.len, w.rows);
        for (size_t k = 1; k < n; k++) assert_true(cmp_xy(a + 2 * k - 2, a + 2 * k) != 0); /* no repeats */
        free(a);
        free(b);
        tested++;
    }
    assert_true(tested > 1000);
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

/* Heckbert's Gaussian weight table exp(-alpha·r²), alpha = 2, and EWA of a
 * constant texture is that constant for any footprint. */
static void test_ewa_gaussian_table(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 64, 64, &img), PERSP_OK);
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = 77, p[1] = 140, p[2] = 201, p[3] = 255;
        }
    persp_texture *t = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &t), PERSP_OK);
    persp_image_free(ctx, &img);
    persp_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.filter = PERSP_FILTER_EWA;
    persp_sampler_state st;
    assert_int_equal(persp__sampler_init(&st, t, &sd), PERSP_OK);
    for (int k = 0; k < PERSP_EWA_TABLE; k++) {
        double r2 = (double)k / (PERSP_EWA_TABLE - 1);
        assert_true(fabs(st.ewa_weight[k] - exp(-2.0 * r2)) < 1e-6);
    }
    test_rng rng = {43};
    for (int it = 0; it < 300; it++) {
        float d[4];
        for (int k = 0; k < 4; k++) d[k] = (float)(test_rng_uniform(&rng, -1, 1) * exp2(test_rng_uniform(&rng, -6, 3)));
        uint8_t got[4];
        persp_texture_sample(t, &sd, (float)test_rng_uniform(&rng, -3, 3), (float)test_rng_uniform(&rng, -3, 3),
                             d[0], d[1], d[2], d[3], got);
        assert_int_equal(got[0], 77);
        assert_int_equal(got[1], 140);
        assert_int_equal(got[2], 201);
    }
    persp_texture_destroy(t);
    persp_context_destroy(ctx);
}

static void test_filter_names(void **state)
{
    (void)state;
    persp_filter f;
    int n = 0;
    assert_int_equal(persp_filter_parse("trilinear", &f, &n), PERSP_OK);
    assert_int_equal(f, PERSP_FILTER_TRILINEAR);
    assert_int_equal(persp_filter_parse("aniso:8", &f, &n), PERSP_OK);
    assert_int_equal(f, PERSP_FILTER_ANISO);
    assert_int_equal(n, 8);
    assert_int_equal(persp_filter_parse("aniso-window:16", &f, &n), PERSP_OK);
    assert_int_equal(f, PERSP_FILTER_ANISO_WINDOW);
    assert_int_equal(n, 16);
    assert_int_equal(persp_filter_parse("aniso:1", &f, &n), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_filter_parse("aniso:17", &f, &n), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_filter_parse("aniso:x", &f, &n), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_filter_parse("ewa:2", &f, &n), PERSP_ERR_NOT_FOUND);
    assert_int_equal(persp_filter_parse("cubic", &f, &n), PERSP_ERR_NOT_FOUND);
    for (int k = 0; k < PERSP_FILTER_COUNT; k++) {
        assert_int_equal(persp_filter_parse(persp_filter_name((persp_filter)k), &f, NULL), PERSP_OK);
        assert_int_equal(f, k);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mip_sizes_any_shape),
        cmocka_unit_test(test_mip_even_is_box_average),
        cmocka_unit_test(test_mip_odd_is_exact_box),
        cmocka_unit_test(test_samplers_inside_reachable_range),
        cmocka_unit_test(test_nearest_exact_texel),
        cmocka_unit_test(test_lod_rules),
        cmocka_unit_test(test_span_jacobian_is_derivative),
        cmocka_unit_test(test_aniso_rule),
        cmocka_unit_test(test_window_daisy_chain_equals_direct),
        cmocka_unit_test(test_ewa_gaussian_table),
        cmocka_unit_test(test_filter_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
