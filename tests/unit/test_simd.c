/* persp_context_desc.simd: names round-trip, out-of-range values are
 * refused, a variant the CPU cannot run fails at creation, the context
 * reports the variant it uses (AUTO resolved to one it can run), and every
 * variant draws the same image, with every lane-path filter and the lit
 * shadings whose batches are packed. A variant the CPU cannot run is
 * reported skipped: by cmocka, and by ctest for test_simd_VARIANT (main). */
#include "core/fmath.h"
#include "core/internal.h"
#include "support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 192, H = 144 };

static const persp_simd variants[] = {PERSP_SIMD_BASELINE, PERSP_SIMD_AVX2, PERSP_SIMD_AVX2_GATHER,
                                      PERSP_SIMD_AVX512, PERSP_SIMD_AVX512_GATHER};

static void test_names(void **state)
{
    (void)state;
    const char *expect[] = {"auto", "baseline", "avx2", "avx2-gather", "avx512", "avx512-gather"};
    for (int i = 0; i <= (int)PERSP_SIMD_AVX512_GATHER; i++) {
        assert_string_equal(persp_simd_name((persp_simd)i), expect[i]);
        persp_simd back = PERSP_SIMD_AUTO;
        assert_int_equal(persp_simd_parse(expect[i], &back), PERSP_OK);
        assert_int_equal(back, i);
    }
    assert_string_equal(persp_simd_name((persp_simd)99), "?");
    assert_string_equal(persp_simd_name((persp_simd)-1), "?");
    persp_simd out = PERSP_SIMD_AVX2;
    assert_int_equal(persp_simd_parse("sse9", &out), PERSP_ERR_NOT_FOUND);
    assert_int_equal(out, PERSP_SIMD_AVX2);
    assert_int_equal(persp_simd_parse(NULL, &out), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_simd_parse("auto", NULL), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_context_simd(NULL), PERSP_SIMD_AUTO);
}

static void test_create(void **state)
{
    (void)state;
    persp_context *ctx = NULL;
    persp_context_desc d = {.simd = (persp_simd)(PERSP_SIMD_AVX512_GATHER + 1)};
    assert_int_equal(persp_context_create(&d, &ctx), PERSP_ERR_INVALID_ARGUMENT);
    assert_null(ctx);
    d.simd = (persp_simd)-1;
    assert_int_equal(persp_context_create(&d, &ctx), PERSP_ERR_INVALID_ARGUMENT);
    int ran = 0;
    for (size_t i = 0; i < sizeof variants / sizeof *variants; i++) {
        d.simd = variants[i];
        /* The CPU check of a gather variant is its instruction set's. */
        const int isa = variants[i] == PERSP_SIMD_BASELINE      ? PERSP_ISA_BASE
                        : variants[i] == PERSP_SIMD_AVX2        ? PERSP_ISA_AVX2
                        : variants[i] == PERSP_SIMD_AVX2_GATHER ? PERSP_ISA_AVX2_GATHER
                        : variants[i] == PERSP_SIMD_AVX512      ? PERSP_ISA_AVX512
                                                                : PERSP_ISA_AVX512_GATHER;
        persp_status st = persp_context_create(&d, &ctx);
        if (!persp__isa_runs(isa)) {
            assert_int_equal(st, PERSP_ERR_UNSUPPORTED);
            assert_null(ctx);
            continue;
        }
        assert_int_equal(st, PERSP_OK);
        assert_int_equal(persp_context_simd(ctx), variants[i]);
        assert_int_equal(persp_context_lighting_simd(ctx), variants[i]);
        persp_context_destroy(ctx);
        ran++;
    }
    assert_true(ran >= 1);
    /* AUTO becomes a variant the CPU runs, the same on every call. */
    assert_int_equal(persp_context_create(NULL, &ctx), PERSP_OK);
    persp_simd a = persp_context_simd(ctx);
    assert_int_not_equal(a, PERSP_SIMD_AUTO);
    assert_int_equal(persp_context_simd(ctx), a);
    /* The lighting loops' AUTO: a width the CPU runs, without gathers (the
     * loops fetch no texels), the same on every call. */
    persp_simd l = persp_context_lighting_simd(ctx);
    assert_true(l == PERSP_SIMD_BASELINE || l == PERSP_SIMD_AVX2 || l == PERSP_SIMD_AVX512);
    assert_true(persp__isa_runs(l == PERSP_SIMD_AVX512 ? PERSP_ISA_AVX512
                                : l == PERSP_SIMD_AVX2 ? PERSP_ISA_AVX2
                                                       : PERSP_ISA_BASE));
    assert_int_equal(persp_context_lighting_simd(ctx), l);
    persp_context_destroy(ctx);
    assert_int_equal(persp_context_lighting_simd(NULL), PERSP_SIMD_AUTO);
}

static uint64_t render_hash(persp_simd simd, const char *scene_name, persp_filter filter,
                            persp_shading shading, int threads)
{
    persp_context *ctx = NULL;
    persp_context_desc d = {.simd = simd, .threads = threads};
    if (persp_context_create(&d, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = NULL;
    if (strchr(scene_name, '/')) {
        char path[1024];
        test_source_path(path, sizeof path, scene_name);
        if (persp_scene_load(ctx, path, &scene) != PERSP_OK)
            fail_msg("%s: %s", path, persp_context_error(ctx));
    } else {
        assert_int_equal(persp_scene_builtin(ctx, scene_name, &scene), PERSP_OK);
    }
    uint8_t *color = malloc((size_t)W * H * 4);
    float *depth = malloc((size_t)W * H * sizeof *depth);
    assert_non_null(color);
    assert_non_null(depth);
    persp_framebuffer fb = {W, H, color, depth};
    persp_render_desc rd = {.filter = filter, .shading = shading};
    if (persp_render(ctx, scene, &rd, &fb, NULL) != PERSP_OK)
        fail_msg("render: %s", persp_context_error(ctx));
    uint64_t h = test_hash(color, (size_t)W * H * 4);
    free(color);
    free(depth);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return h;
}

/* The CPU check of a variant (a gather variant's is its instruction set's). */
static int isa_of(persp_simd v)
{
    return v == PERSP_SIMD_BASELINE      ? PERSP_ISA_BASE
           : v == PERSP_SIMD_AVX2        ? PERSP_ISA_AVX2
           : v == PERSP_SIMD_AVX2_GATHER ? PERSP_ISA_AVX2_GATHER
           : v == PERSP_SIMD_AVX512      ? PERSP_ISA_AVX512
                                         : PERSP_ISA_AVX512_GATHER;
}

/* Every case drawn by variant v (the baseline: at two threads, so that a
 * CPU with no other variant, aarch64, still compares something) against
 * the baseline at one thread. */
static void same_image(persp_simd v)
{
    static const persp_filter filters[] = {PERSP_FILTER_NEAREST,
                                           PERSP_FILTER_BILINEAR,
                                           PERSP_FILTER_NEAREST_MIP_NEAREST,
                                           PERSP_FILTER_BILINEAR_MIP_NEAREST,
                                           PERSP_FILTER_NEAREST_MIP_LINEAR,
                                           PERSP_FILTER_TRILINEAR,
                                           PERSP_FILTER_ANISO};
    static const struct {
        const char *scene;
        persp_shading shading;
    } cases[] = {{"corridor", PERSP_SHADING_NONE},
                 {"scenes/spheres.json", PERSP_SHADING_GOURAUD_PC},
                 {"scenes/bench/torus-2k.json", PERSP_SHADING_PHONG_PC},
                 {"scenes/bench/soup-200k.json", PERSP_SHADING_NONE}};
    const int threads = v == PERSP_SIMD_BASELINE ? 2 : 1;
    int compared = 0;
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++)
        for (size_t f = 0; f < sizeof filters / sizeof *filters; f++) {
            const uint64_t ref =
                render_hash(PERSP_SIMD_BASELINE, cases[c].scene, filters[f], cases[c].shading, 1);
            assert_true(ref != 0);
            uint64_t h = render_hash(v, cases[c].scene, filters[f], cases[c].shading, threads);
            assert_true(h != 0);
            if (h != ref)
                fail_msg("%s, %s, %s, %d thread(s): --simd %s draws another image than baseline",
                         cases[c].scene, persp_filter_name(filters[f]),
                         persp_shading_name(cases[c].shading), threads, persp_simd_name(v));
            compared++;
        }
    assert_true(compared > 0);
}

/* One test per variant; one this CPU cannot run is reported skipped, by
 * name, not passed. */
static void test_same_image(void **state)
{
    const persp_simd v = *(const persp_simd *)*state;
    if (!persp__isa_runs(isa_of(v))) {
        print_message("--simd %s: this CPU cannot run it; skipped\n", persp_simd_name(v));
        skip();
    }
    same_image(v);
}

/* A test of one variant, named after it in cmocka's report. */
#define SAME_IMAGE(name, i)                                                                        \
    {"same_image_" name, test_same_image, NULL, NULL, (void *)&variants[i]}

/* No argument: every test. --common: those that run on any CPU (the names,
 * context creation and the baseline at two threads). --variant NAME: the
 * image comparison of that variant alone, exiting 77 (ctest's
 * SKIP_RETURN_CODE) when the CPU cannot run it. */
int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--variant")) {
        persp_simd v;
        if (persp_simd_parse(argv[2], &v) != PERSP_OK || v == PERSP_SIMD_AUTO) {
            fprintf(stderr, "test_simd: unknown variant %s\n", argv[2]);
            return 2;
        }
        if (!persp__isa_runs(isa_of(v))) {
            printf("SKIP: --simd %s: this CPU cannot run it\n", argv[2]);
            return 77;
        }
        const struct CMUnitTest one[] = {
            {argv[2], test_same_image, NULL, NULL, (void *)&variants[v - PERSP_SIMD_BASELINE]},
        };
        return cmocka_run_group_tests(one, NULL, NULL);
    }
    const struct CMUnitTest common[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_create),
        SAME_IMAGE("baseline", 0),
    };
    if (argc == 2 && !strcmp(argv[1], "--common")) return cmocka_run_group_tests(common, NULL, NULL);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_create),
        SAME_IMAGE("baseline", 0),      SAME_IMAGE("avx2", 1),   SAME_IMAGE("avx2-gather", 2),
        SAME_IMAGE("avx512", 3),        SAME_IMAGE("avx512-gather", 4),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
