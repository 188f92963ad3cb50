/*
 * `incremental` and its variants ([Romaniuk-Incr] (3)-(5)): the lane and
 * bidirectional forms return bit-identical floats to the sequential form on
 * every span, and all of them stay within the documented bound of the
 * double-precision rational form.
 */
#include "methods_harness.h"

#include <float.h>

#define TRIS_PER_RATIO 12

typedef struct inc_ctx {
    persp_method_sel base, variants[20];
    int nvariants;
    uint64_t spans, pixels, mismatches;
    double max_err_texels, max_ratio_to_bound;
} inc_ctx;

static void check_span(void *user, const persp_rational *r, int x0, int y, int n)
{
    inc_ctx *c = user;
    float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX], u2[PERSP_SPAN_MAX], v2[PERSP_SPAN_MAX];
    persp_opcount ops = {0};
    c->base.m->span(r, &c->base.params, NULL, x0, y, n, u, v, &ops);
    assert_int_equal(ops.div, (uint64_t)n);
    for (int i = 0; i < c->nvariants; i++) {
        persp_method_sel *s = &c->variants[i];
        s->m->span(r, &s->params, NULL, x0, y, n, u2, v2, NULL);
        if (memcmp(u, u2, sizeof(float) * (size_t)n) != 0 ||
            memcmp(v, v2, sizeof(float) * (size_t)n) != 0)
            c->mismatches++;
    }
    for (int k = 0; k < n; k++) {
        double eu, ev;
        persp__rational_eval(r, x0 + k, y, &eu, &ev);
        /* Documented bound (incremental.c): 4 float roundings, plus the
         * grid rounding of numerator and denominator, each at most
         * 2^-44·M with M = |start| + (n + 16)·|increment|. */
        double px = x0 + 0.5, py = y + 0.5, reach = n + 16.0;
        double n1 = r->a * px + r->b * py + r->c, n2 = r->d * px + r->e * py + r->f;
        double q = r->g * px + r->h * py + r->i, qk = q + r->g * k;
        double mq = fabs(q) + reach * fabs(r->g);
        double bu = (4.0 * 0x1p-24 + 0x1p-40) * fabs(eu) +
                    0x1p-44 * (fabs(n1) + reach * fabs(r->a) + fabs(eu) * mq) / qk;
        double bv = (4.0 * 0x1p-24 + 0x1p-40) * fabs(ev) +
                    0x1p-44 * (fabs(n2) + reach * fabs(r->d) + fabs(ev) * mq) / qk;
        double du = fabs((double)u[k] - eu), dv = fabs((double)v[k] - ev);
        if (du > bu || dv > bv)
            fail_msg("incremental off bound at (%d,%d): du %.3g (bound %.3g) dv %.3g (bound %.3g)",
                     x0 + k, y, du, bu, dv, bv);
        double e = fmax(du, dv) * H_TEXELS;
        if (e > c->max_err_texels) c->max_err_texels = e;
        double ratio = fmax(du / fmax(bu, DBL_MIN), dv / fmax(bv, DBL_MIN));
        if (ratio > c->max_ratio_to_bound) c->max_ratio_to_bound = ratio;
    }
    c->spans++;
    c->pixels += (uint64_t)n;
}

static void test_variants_identical_and_bounded(void **state)
{
    (void)state;
    inc_ctx c;
    memset(&c, 0, sizeof c);
    c.base = h_method("incremental");
    char spec[32];
    for (int k = 1; k <= 16; k++) {
        snprintf(spec, sizeof spec, "incremental:k=%d", k);
        c.variants[c.nvariants++] = h_method(spec);
    }
    c.variants[c.nvariants++] = h_method("incremental:bidir");
    test_rng rng = {0x1234abcdULL};
    for (size_t ri = 0; ri < H_RATIO_COUNT; ri++) {
        for (int i = 0; i < TRIS_PER_RATIO; i++) {
            h_triangle T;
            h_random_triangle(&rng, h_ratios[ri], &T);
            h_for_each_span(&T, check_span, &c);
        }
    }
    print_message("incremental: %llu spans, %llu px, max error %.3g texels (%.2f of bound), "
                  "%llu variant mismatches\n",
                  (unsigned long long)c.spans, (unsigned long long)c.pixels, c.max_err_texels,
                  c.max_ratio_to_bound, (unsigned long long)c.mismatches);
    assert_true(c.pixels > 10000);
    assert_int_equal(c.mismatches, 0);
}

/* Identical also on synthetic spans of every length 1..64 with large
 * coordinates (the grid must hold the partial sums of a whole span). */
static void test_identical_all_lengths(void **state)
{
    (void)state;
    persp_method_sel base = h_method("incremental"), bidir = h_method("incremental:bidir");
    persp_method_sel k3 = h_method("incremental:k=3"), k8 = h_method("incremental:k=8");
    test_rng rng = {99};
    for (int trial = 0; trial < 200; trial++) {
        persp_rational r;
        memset(&r, 0, sizeof r);
        r.a = test_rng_uniform(&rng, -3, 3), r.b = test_rng_uniform(&rng, -3, 3);
        r.c = test_rng_uniform(&rng, -2000, 2000);
        r.d = test_rng_uniform(&rng, -3, 3), r.e = test_rng_uniform(&rng, -3, 3);
        r.f = test_rng_uniform(&rng, -2000, 2000);
        r.g = test_rng_uniform(&rng, -1e-3, 1e-3), r.h = test_rng_uniform(&rng, -1e-3, 1e-3);
        r.i = test_rng_uniform(&rng, 3.0, 5.0);
        int x0 = (int)(test_rng_next(&rng) % 960), y = (int)(test_rng_next(&rng) % 700);
        for (int n = 1; n <= PERSP_SPAN_MAX; n++) {
            float u0[64], v0[64], u1[64], v1[64];
            base.m->span(&r, &base.params, NULL, x0, y, n, u0, v0, NULL);
            const persp_method_sel *vs[3] = {&bidir, &k3, &k8};
            for (int i = 0; i < 3; i++) {
                vs[i]->m->span(&r, &vs[i]->params, NULL, x0, y, n, u1, v1, NULL);
                assert_memory_equal(u0, u1, sizeof(float) * (size_t)n);
                assert_memory_equal(v0, v1, sizeof(float) * (size_t)n);
            }
        }
    }
}

static void test_parse(void **state)
{
    (void)state;
    persp_method_sel sel;
    assert_int_equal(persp__method_resolve(NULL, "incremental:k=0", &sel), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__method_resolve(NULL, "incremental:k=17", &sel), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__method_resolve(NULL, "incremental:k=4x", &sel), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__method_resolve(NULL, "incremental:bi", &sel), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__method_resolve(NULL, "incremental:k=", &sel), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp__method_resolve(NULL, "incremental:k=16", &sel), PERSP_OK);
    assert_int_equal(persp_method_check("subdiv:12"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("subdiv:32"), PERSP_OK);
    assert_int_equal(persp_method_check("subdiv-quad:4"), PERSP_OK);
    assert_int_equal(persp_method_check("bezier:quadt"), PERSP_OK);
    assert_int_equal(persp_method_check("bezier:fast"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("quadratic:1"), PERSP_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_variants_identical_and_bounded),
        cmocka_unit_test(test_identical_all_lengths),
        cmocka_unit_test(test_parse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
