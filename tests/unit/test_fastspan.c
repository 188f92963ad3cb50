/*
 * The vectorised span samplers (src/texture/fastspan.c) of the isotropic
 * filters (nearest, bilinear, the three mip-nearest/linear ones, trilinear)
 * and the anisotropic filter (EXT_texture_filter_anisotropic)
 * against the general ones (sampler.c): identical bits for every pixel of random spans, over
 * power-of-two sizes (square and not, down to 1 texel), both wrap modes per
 * axis, per-pixel and per-polygon LOD, bias and LOD clamps, and coordinates
 * far outside the texture, at its edges, infinite and NaN. Also that the
 * vectorised path is chosen exactly where it applies.
 */
/* ctest-split: each (minutes in all under ASan + UBSan) */
#include "support.h"

#include "interp/method.h"
#include "core/fmath.h"
#include "texture/sample.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static persp_texture *random_texture(persp_context *ctx, test_rng *rng, int w, int h)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, w, h, &img), PERSP_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < 4 * w; x++)
            img.pixels[(size_t)y * img.stride + (size_t)x] = (uint8_t)(test_rng_next(rng) >> 40);
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &tex), PERSP_OK);
    persp_image_free(ctx, &img);
    return tex;
}

/* A coordinate drawn from a mixture: inside, near texel edges, far outside,
 * and the special values. */
static float random_coord(test_rng *rng, int size)
{
    switch (test_rng_next(rng) % 16) {
    case 0: return NAN;
    case 1: return (test_rng_next(rng) & 1) ? INFINITY : -INFINITY;
    case 2: return (float)test_rng_uniform(rng, -1e9, 1e9);
    case 3: return (float)((double)(int)(test_rng_next(rng) % (uint64_t)(4 * size + 1)) / size - 2.0);
    case 4: return (float)(((double)(int)(test_rng_next(rng) % (uint64_t)(2 * size)) + 0.5) / size);
    default: return (float)test_rng_uniform(rng, -3.0, 3.0);
    }
}

static void compare_spans(persp_context *ctx, int w, int h, uint64_t seed)
{
    test_rng rng = {seed};
    persp_texture *tex = random_texture(ctx, &rng, w, h);
    const persp_filter filters[] = {PERSP_FILTER_NEAREST, PERSP_FILTER_BILINEAR,
                                    PERSP_FILTER_NEAREST_MIP_NEAREST,
                                    PERSP_FILTER_BILINEAR_MIP_NEAREST,
                                    PERSP_FILTER_NEAREST_MIP_LINEAR, PERSP_FILTER_TRILINEAR,
                                    PERSP_FILTER_ANISO};
    long compared = 0;
    for (size_t fi = 0; fi < sizeof filters / sizeof *filters; fi++)
        for (int ws = 0; ws < 2; ws++)
            for (int wt = 0; wt < 2; wt++)
                for (int mode = 0; mode < 3; mode++) {
                    persp_sampler_desc desc;
                    memset(&desc, 0, sizeof desc);
                    desc.filter = filters[fi];
                    desc.wrap_s = (persp_wrap)(PERSP_WRAP_REPEAT + ws);
                    desc.wrap_t = (persp_wrap)(PERSP_WRAP_REPEAT + wt);
                    desc.lod_mode = mode == 1 ? PERSP_LOD_POLYGON : PERSP_LOD_PIXEL;
                    desc.max_aniso = filters[fi] == PERSP_FILTER_ANISO ? 2 + 7 * mode : 0;
                    if (mode == 2) {
                        desc.lod_bias = 0.75f;
                        desc.lod_clamp = PERSP_TOGGLE_ON;
                        desc.min_lod = 0.5f;
                        desc.max_lod = 2.5f;
                    }
                    persp_sampler_state st;
                    assert_int_equal(persp__sampler_init(&st, tex, &desc), PERSP_OK);
                    persp_tex_span_fn general = persp__general_span(desc.filter, desc.wrap_s, desc.wrap_t);
                    assert_non_null(general);
                    assert_true(st.span != general); /* the vectorised one was chosen */
                    /* Every instruction-set variant this CPU can run, whatever
                     * it picks by default. */
                    persp_sampler_state st_isa[PERSP_ISA_COUNT];
                    persp_tex_span_fn variant[PERSP_ISA_COUNT];
                    const int nvar = PERSP_ISA_COUNT;
                    for (int isa = 0; isa < nvar; isa++) {
                        st_isa[isa] = st;
                        variant[isa] = persp__isa_runs(isa)
                                           ? persp__fast_span_select_isa(&st_isa[isa], isa)
                                           : NULL;
                        assert_true(variant[isa] || !persp__isa_runs(isa));
                    }
                    for (int rep = 0; rep < 200; rep++) {
                        float u[PERSP_LANE_MAX], v[PERSP_LANE_MAX], q[PERSP_LANE_MAX];
                        int n = 1 + (int)(test_rng_next(&rng) % PERSP_LANE_MAX);
                        /* Half of the spans are smooth (a real perspective span),
                         * half are random values per pixel. */
                        int smooth = rep & 1;
                        float u0 = random_coord(&rng, w), v0 = random_coord(&rng, h);
                        float du = (float)test_rng_uniform(&rng, -0.2, 0.2);
                        float dv = (float)test_rng_uniform(&rng, -0.2, 0.2);
                        for (int k = 0; k < n; k++) {
                            u[k] = smooth ? u0 + (float)k * du : random_coord(&rng, w);
                            v[k] = smooth ? v0 + (float)k * dv : random_coord(&rng, h);
                            q[k] = (float)test_rng_uniform(&rng, 1e-3, 10.0);
                            if (k % 17 == 16) q[k] = 0.0f;
                        }
                        double sc = pow(10.0, test_rng_uniform(&rng, -4.0, 1.0));
                        persp_tex_span_in in = {
                            .n = n, .u = u, .v = v, .q = q,
                            .a = (float)(sc * test_rng_uniform(&rng, -1, 1)),
                            .b = (float)(sc * test_rng_uniform(&rng, -1, 1)),
                            .d = (float)(sc * test_rng_uniform(&rng, -1, 1)),
                            .e = (float)(sc * test_rng_uniform(&rng, -1, 1)),
                            .g = (float)(sc * test_rng_uniform(&rng, -0.1, 0.1)),
                            .h = (float)(sc * test_rng_uniform(&rng, -0.1, 0.1)),
                            .poly_lambda = (float)test_rng_uniform(&rng, -3.0, 12.0),
                        };
                        uint32_t fast[PERSP_LANE_MAX], ref[PERSP_LANE_MAX];
                        general(&st, &in, ref);
                        for (int isa = 0; isa < nvar; isa++) {
                            if (!variant[isa]) continue;
                            variant[isa](&st_isa[isa], &in, fast);
                            for (int k = 0; k < n; k++) {
                                if (fast[k] != ref[k])
                                    fail_msg("%dx%d filter %s wrap %d,%d mode %d isa %d rep %d pixel %d "
                                             "(u %.9g v %.9g q %.9g): got %08x expected %08x",
                                             w, h, persp_filter_name(desc.filter), ws, wt, mode, isa,
                                             rep, k, (double)u[k], (double)v[k], (double)q[k], fast[k],
                                             ref[k]);
                                compared++;
                            }
                        }
                    }
                }
    assert_true(compared > 10000);
    persp_texture_destroy(tex);
}

static void fast_equals_general(int w, int h, uint64_t seed)
{
    persp_context *ctx = test_context();
    compare_spans(ctx, w, h, seed);
    persp_context_destroy(ctx);
}

/* One test per texture size: together they took 268 s under ASan + UBSan on
 * a loaded 2-core machine. */
static void test_fast_equals_general_256x256(void **state)
{
    (void)state;
    fast_equals_general(256, 256, 1);
}

static void test_fast_equals_general_64x16(void **state)
{
    (void)state;
    fast_equals_general(64, 16, 2);
}

static void test_fast_equals_general_8x128(void **state)
{
    (void)state;
    fast_equals_general(8, 128, 3);
}

static void test_fast_equals_general_1x1(void **state)
{
    (void)state;
    fast_equals_general(1, 1, 4);
}

static void test_fast_equals_general_2x1(void **state)
{
    (void)state;
    fast_equals_general(2, 1, 5);
}

/* Not power-of-two, mirrored, border and the other filters keep the general
 * samplers. */
static void test_fast_applicability(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {9};
    persp_texture *pot = random_texture(ctx, &rng, 32, 32);
    persp_texture *npot = random_texture(ctx, &rng, 48, 32);
    persp_sampler_desc desc;
    memset(&desc, 0, sizeof desc);
    persp_sampler_state st;
    desc.filter = PERSP_FILTER_BILINEAR;
    assert_int_equal(persp__sampler_init(&st, npot, &desc), PERSP_OK);
    assert_ptr_equal(st.span, persp__general_span(desc.filter, desc.wrap_s, desc.wrap_t));
    desc.wrap_t = PERSP_WRAP_MIRRORED_REPEAT;
    assert_int_equal(persp__sampler_init(&st, pot, &desc), PERSP_OK);
    assert_ptr_equal(st.span, persp__general_span(desc.filter, desc.wrap_s, desc.wrap_t));
    desc.wrap_t = PERSP_WRAP_CLAMP_TO_BORDER;
    assert_int_equal(persp__sampler_init(&st, pot, &desc), PERSP_OK);
    assert_ptr_equal(st.span, persp__general_span(desc.filter, desc.wrap_s, desc.wrap_t));
    desc.wrap_t = PERSP_WRAP_REPEAT;
    desc.filter = PERSP_FILTER_EWA;
    assert_int_equal(persp__sampler_init(&st, pot, &desc), PERSP_OK);
    assert_null(persp__fast_span_select(&st));
    desc.filter = PERSP_FILTER_ANISO_WINDOW;
    assert_int_equal(persp__sampler_init(&st, pot, &desc), PERSP_OK);
    assert_null(persp__fast_span_select(&st));
    desc.filter = PERSP_FILTER_BILINEAR;
    desc.wrap_s = PERSP_WRAP_MIRRORED_REPEAT;
    assert_int_equal(persp__sampler_init(&st, pot, &desc), PERSP_OK);
    assert_ptr_equal(st.span, persp__general_span(desc.filter, desc.wrap_s, desc.wrap_t));
    persp_texture_destroy(pot);
    persp_texture_destroy(npot);
    persp_context_destroy(ctx);
}

/* The log2 used for lambda: exact at powers of two, within 1e-5 elsewhere
 * over the whole normal range, and the clamping values for the rest. */
static void test_log2f(void **state)
{
    (void)state;
    for (int e = -126; e <= 127; e++) assert_true(persp__log2f(ldexpf(1.0f, e)) == (float)e);
    double worst = 0.0;
    for (float x = 1.2e-38f; x < 3e38f; x *= 1.00731f) {
        double err = fabs((double)persp__log2f(x) - log2((double)x));
        if (err > worst) worst = err;
    }
    print_message("max |log2 error| %.3g\n", worst);
    assert_true(worst < 1e-5);
    assert_true(persp__log2f(0.0f) < -1e29f);
    assert_true(persp__log2f(-1.0f) < -1e29f);
    assert_true(persp__log2f(1e-40f) < -1e29f);
    assert_true(persp__log2f(NAN) < -1e29f);
    assert_true(persp__log2f(INFINITY) > 1e29f);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fast_equals_general_256x256),
        cmocka_unit_test(test_fast_equals_general_64x16),
        cmocka_unit_test(test_fast_equals_general_8x128),
        cmocka_unit_test(test_fast_equals_general_1x1),
        cmocka_unit_test(test_fast_equals_general_2x1),
        cmocka_unit_test(test_fast_applicability),
        cmocka_unit_test(test_log2f),
    };
    return TEST_RUN(argc, argv, tests);
}
