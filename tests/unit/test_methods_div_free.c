/*
 * `midpoint` ([Romanyuk-PCF] §4.5) and its fixed-point model `midpoint:int`:
 * against the rational form in double on seeded random triangles of the
 * random-triangles set (docs/WORKLOADS.md: corridor projection, 1024×768, u, v in
 * [0, 1], 256 texels), grouped by depth ratio.
 */
#include "support.h"

#include "interp/methods.h"
#include "raster/raster.h"

#include <math.h>
#include <string.h>

#define VW 1024
#define VH 768
#define TEX 256.0

static const double hbars[] = {1.25, 1.5, 2, 3, 4, 5, 8};
#define NHBAR (sizeof hbars / sizeof hbars[0])

/* A triangle of eye-space points at depths with ratio hbar inside the corridor
 * frustum (fovy 60°, aspect 4:3), projected to the 1024×768 viewport. */
static int random_triangle(test_rng *rng, double hbar, persp_tri *t, persp_rational_vertices *vv)
{
    static float attr[3][PERSP_A_COUNT];
    const double a = (double)VW / VH, tn = tan(30.0 * 3.14159265358979323846 / 180.0);
    double zn = test_rng_uniform(rng, 0.5, 4.0);
    double z[3] = {zn, zn * hbar, test_rng_uniform(rng, zn, zn * hbar)};
    persp_winvert v[3];
    memset(attr, 0, sizeof attr);
    for (int i = 0; i < 3; i++) {
        double x = test_rng_uniform(rng, -0.95, 0.95) * tn * a * z[i];
        double y = test_rng_uniform(rng, -0.95, 0.95) * tn * z[i];
        v[i].x = (x / (tn * a * z[i]) + 1.0) * 0.5 * VW;
        v[i].y = (y / (tn * z[i]) + 1.0) * 0.5 * VH;
        v[i].z = 0.5;
        v[i].q = 1.0 / z[i];
        attr[i][PERSP_A_U] = (float)test_rng_uniform(rng, 0, 1);
        attr[i][PERSP_A_V] = (float)test_rng_uniform(rng, 0, 1);
        v[i].attr = attr[i];
    }
    if (!persp__setup_triangle(v, VW, VH, 0, t, vv)) return 0;
    t->rat.scale1 = t->rat.scale2 = (float)TEX;
    return 1;
}

static persp_method_sel resolve(const char *spec)
{
    persp_method_sel sel;
    assert_int_equal(persp__method_resolve(NULL, spec, &sel), PERSP_OK);
    return sel;
}

typedef struct err_stats {
    double worst;       /* max |P·s − t| in texels */
    long pixels, spans, texel_mismatch, off_lattice;
} err_stats;

/* Runs sel over every covered span of triangle t (rational r), comparing with
 * the double rational form in texels; off is the lattice offset (1/2 for texel
 * centres, 0 for edges) that every output must sit on. */
static void measure(const persp_method_sel *sel, const persp_tri *t, const persp_rational *r,
                    const persp_rational_vertices *vv, double off, err_stats *st, persp_opcount *ops)
{
    persp_method_prep prep;
    memset(&prep, 0, sizeof prep);
    if (sel->m->prepare) sel->m->prepare(r, vv, &sel->params, &prep, ops);
    for (int y = t->ymin; y <= t->ymax; y++) {
        int lo, hi;
        if (!persp__tri_row_range(t, y, 0, VW - 1, &lo, &hi)) continue;
        for (int x0 = lo; x0 <= hi; x0 += PERSP_SPAN_MAX) {
            int n = hi - x0 + 1 > PERSP_SPAN_MAX ? PERSP_SPAN_MAX : hi - x0 + 1;
            float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX];
            sel->m->span(r, &sel->params, &prep, x0, y, n, u, v, ops);
            for (int k = 0; k < n; k++) {
                double eu, ev;
                persp__rational_eval(r, x0 + k, y, &eu, &ev);
                double tu = eu * TEX, tv = ev * TEX, mu = u[k] * TEX, mv = v[k] * TEX;
                double e = fmax(fabs(mu - tu), fabs(mv - tv));
                if (e > st->worst) st->worst = e;
                /* Every output is a lattice point n + off (exact in float). */
                if (mu - off != floor(mu - off) || mv - off != floor(mv - off)) st->off_lattice++;
                /* Centres lattice: the nearest texel equals the exact one, away
                 * from boundaries closer than the double evaluation's rounding. */
                if (off == 0.5) {
                    int near_u = fabs(tu - floor(tu + 0.5)) < 1e-9;
                    int near_v = fabs(tv - floor(tv + 0.5)) < 1e-9;
                    if ((!near_u && floor(mu) != floor(tu)) || (!near_v && floor(mv) != floor(tv)))
                        st->texel_mismatch++;
                }
            }
            st->pixels += n;
            st->spans++;
        }
    }
}

/* Bound (docs/METHODS.md, midpoint): half a texel step, plus the float rounding
 * of the output lattice value (values ≤ 256 texels: 2^-24·256 ≈ 1.5e-5) and
 * the rounding of the double reference; 1e-4 texel covers both. */
#define HALF_STEP_BOUND (0.5 + 1e-4)

static void test_midpoint_within_half_texel(void **state)
{
    (void)state;
    persp_method_sel centre = resolve("midpoint"), edge = resolve("midpoint:edge");
    test_rng rng = {4242};
    err_stats all_c = {0}, all_e = {0};
    persp_opcount ops = {0};
    for (size_t h = 0; h < NHBAR; h++) {
        err_stats sc = {0}, se = {0};
        for (int i = 0; i < 24; i++) {
            persp_tri t;
            persp_rational_vertices vv;
            if (!random_triangle(&rng, hbars[h], &t, &vv)) continue;
            measure(&centre, &t, &t.rat, &vv, 0.5, &sc, &ops);
            measure(&edge, &t, &t.rat, &vv, 0.0, &se, NULL);
        }
        print_message("midpoint hbar %.2f: max %.6f texel (edge lattice %.6f) over %ld px, "
                      "nearest-texel mismatches %ld\n",
                      hbars[h], sc.worst, se.worst, sc.pixels, sc.texel_mismatch);
        all_c.worst = fmax(all_c.worst, sc.worst);
        all_e.worst = fmax(all_e.worst, se.worst);
        all_c.pixels += sc.pixels, all_c.spans += sc.spans;
        all_c.texel_mismatch += sc.texel_mismatch;
        all_c.off_lattice += sc.off_lattice, all_e.off_lattice += se.off_lattice;
    }
    print_message("midpoint: %ld px, %ld spans; per px: %.3f add %.3f cmp %.4f div %.3f mul\n",
                  all_c.pixels, all_c.spans, (double)ops.add / (double)all_c.pixels,
                  (double)ops.cmp / (double)all_c.pixels, (double)ops.div / (double)all_c.pixels,
                  (double)ops.mul / (double)all_c.pixels);
    assert_true(all_c.pixels > 200000);
    assert_true(all_c.worst <= HALF_STEP_BOUND);
    assert_true(all_e.worst <= HALF_STEP_BOUND);
    /* The bound is attained, not loose: the lattice really quantises. */
    assert_true(all_c.worst > 0.45);
    assert_int_equal(all_c.off_lattice, 0);
    assert_int_equal(all_e.off_lattice, 0);
    assert_int_equal(all_c.texel_mismatch, 0);
    /* Division-free per pixel: one reciprocal per span start, plus a re-seed
     * where a thin triangle maps more than 32 texels to one pixel (rare). */
    assert_true(ops.div >= (uint64_t)all_c.spans);
    assert_true(ops.div <= (uint64_t)all_c.spans + (uint64_t)all_c.pixels / 1000);
}

/* midpoint:int is bit-exact with midpoint on planes representable in its
 * fixed-point format whose double evaluation is exact (coarser grid). */
static void test_midpoint_int_bit_exact(void **state)
{
    (void)state;
    persp_method_sel fl = resolve("midpoint"), fx = resolve("midpoint:int");
    persp_method_sel fle = resolve("midpoint:edge"), fxe = resolve("midpoint:int,edge");
    test_rng rng = {99};
    long pixels = 0, differ = 0, differ_raw = 0;
    double worst_raw = 0.0;
    for (size_t h = 0; h < NHBAR; h++)
        for (int i = 0; i < 16; i++) {
            persp_tri t;
            persp_rational_vertices vv;
            if (!random_triangle(&rng, hbars[h], &t, &vv)) continue;
            persp_rational q;
            persp__midpoint_quantize(&t.rat, 30, &q);
            /* The quantised planes differ from the originals (else the test
             * would not exercise rounding to the format). */
            assert_true(q.g != t.rat.g || q.a != t.rat.a);
            persp_method_prep p1, p2, p3, p4, p5;
            fx.m->prepare(&q, &vv, &fx.params, &p1, NULL);
            fxe.m->prepare(&q, &vv, &fxe.params, &p2, NULL);
            fx.m->prepare(&t.rat, &vv, &fx.params, &p3, NULL);
            fl.m->prepare(&q, &vv, &fl.params, &p4, NULL);
            fle.m->prepare(&q, &vv, &fle.params, &p5, NULL);
            for (int y = t.ymin; y <= t.ymax; y++) {
                int lo, hi;
                if (!persp__tri_row_range(&t, y, 0, VW - 1, &lo, &hi)) continue;
                for (int x0 = lo; x0 <= hi; x0 += PERSP_SPAN_MAX) {
                    int n = hi - x0 + 1 > PERSP_SPAN_MAX ? PERSP_SPAN_MAX : hi - x0 + 1;
                    float a[2][PERSP_SPAN_MAX], b[2][PERSP_SPAN_MAX], c[2][PERSP_SPAN_MAX],
                        d[2][PERSP_SPAN_MAX], e[2][PERSP_SPAN_MAX];
                    fl.m->span(&q, &fl.params, &p4, x0, y, n, a[0], a[1], NULL);
                    fx.m->span(&q, &fx.params, &p1, x0, y, n, b[0], b[1], NULL);
                    fle.m->span(&q, &fle.params, &p5, x0, y, n, c[0], c[1], NULL);
                    fxe.m->span(&q, &fxe.params, &p2, x0, y, n, d[0], d[1], NULL);
                    fx.m->span(&t.rat, &fx.params, &p3, x0, y, n, e[0], e[1], NULL);
                    for (int j = 0; j < 2; j++) {
                        differ += memcmp(a[j], b[j], (size_t)n * sizeof(float)) != 0;
                        differ += memcmp(c[j], d[j], (size_t)n * sizeof(float)) != 0;
                    }
                    for (int k = 0; k < n; k++) {
                        double eu, ev;
                        persp__rational_eval(&t.rat, x0 + k, y, &eu, &ev);
                        double err = fmax(fabs(e[0][k] - eu), fabs(e[1][k] - ev)) * TEX;
                        worst_raw = fmax(worst_raw, err);
                        float g[2][1];
                        fl.m->span(&t.rat, &fl.params, &p4, x0 + k, y, 1, g[0], g[1], NULL);
                        differ_raw += g[0][0] != e[0][k] || g[1][0] != e[1][k];
                    }
                    pixels += n;
                }
            }
        }
    print_message("midpoint:int: %ld px, %ld spans differ on representable planes; on raw planes "
                  "max error %.6f texel, %ld px differ from float\n",
                  pixels, differ, worst_raw, differ_raw);
    assert_true(pixels > 100000);
    assert_int_equal(differ, 0);
    /* On unquantised planes the format rounds g..i to 2^-42 of their span and
     * the numerators alike: the result stays within half a texel plus the
     * quantisation's effect (|t|·2^-25 for these depths), and differs from the
     * double path only where t is that close to a texel boundary. */
    assert_true(worst_raw <= 0.5 + 1e-4);
    assert_true(differ_raw < pixels / 10000 + 1);
}

/* 1-pixel spans, spans starting at every position, g = 0 (constant depth
 * along rows), and single spans longer than a tile row. */
static void test_midpoint_short_spans_and_degenerate(void **state)
{
    (void)state;
    static const char *specs[] = {"midpoint", "midpoint:int"};
    test_rng rng = {5};
    for (int s = 0; s < 2; s++) {
        persp_method_sel sel = resolve(specs[s]);
        for (int i = 0; i < 20; i++) {
            persp_tri t;
            persp_rational_vertices vv;
            if (!random_triangle(&rng, 3.0, &t, &vv)) continue;
            persp_rational r = t.rat;
            if (i % 2) r.g = 0.0; /* rows of constant depth */
            persp_method_prep prep;
            if (sel.m->prepare) sel.m->prepare(&r, &vv, &sel.params, &prep, NULL);
            /* The fixed-point model is exact to half a step with respect to
             * the planes as its format holds them; zeroing g makes the
             * denominator cancel, where that rounding shows. */
            persp_rational ref = r;
            if (s == 1) persp__midpoint_quantize(&r, 42, &ref);
            for (int y = t.ymin; y <= t.ymax; y += 7) {
                int lo, hi;
                if (!persp__tri_row_range(&t, y, 0, VW - 1, &lo, &hi)) continue;
                for (int x = lo; x <= hi; x++) {
                    float u, v;
                    sel.m->span(&r, &sel.params, &prep, x, y, 1, &u, &v, NULL);
                    double eu, ev;
                    if (!(ref.g * (x + 0.5) + ref.h * (y + 0.5) + ref.i > 0.0)) {
                        /* Zeroing g left this pixel behind the eye: defined as 0. */
                        assert_true(u == 0.0f && v == 0.0f);
                        continue;
                    }
                    persp__rational_eval(&ref, x, y, &eu, &ev);
                    if (!(fabs(u - eu) * TEX <= HALF_STEP_BOUND && fabs(v - ev) * TEX <= HALF_STEP_BOUND))
                        print_message("%s i=%d x=%d y=%d: %.9g %.9g vs %.9g %.9g\n", specs[s], i, x, y,
                                      u * TEX, v * TEX, eu * TEX, ev * TEX);
                    assert_true(fabs(u - eu) * TEX <= HALF_STEP_BOUND);
                    assert_true(fabs(v - ev) * TEX <= HALF_STEP_BOUND);
                }
            }
        }
        /* Wrong input: zero denominator over the span gives finite values. */
        persp_rational z = {0};
        persp_rational_vertices zv = {0};
        z.scale1 = z.scale2 = 256.0f;
        float u[4], v[4];
        persp_method_prep prep;
        if (sel.m->prepare) sel.m->prepare(&z, &zv, &sel.params, &prep, NULL);
        sel.m->span(&z, &sel.params, &prep, 0, 0, 4, u, v, NULL);
    }
}

/* Strong minification: many texels per pixel. The search is capped and
 * re-seeded, so results stay within the bound and the cost bounded. */
static void test_midpoint_minification(void **state)
{
    (void)state;
    persp_method_sel sel = resolve("midpoint"), isel = resolve("midpoint:int");
    /* u = 40·x/(0.01·x + 1): about 40 texels per pixel near x = 0. */
    persp_rational r = {0};
    r.a = 40.0 / TEX, r.g = 0.01, r.i = 1.0, r.e = 0.5 / TEX, r.h = 0.001;
    r.scale1 = r.scale2 = (float)TEX;
    r.xmax = PERSP_SPAN_MAX - 1, r.ymax = 7; /* the box the fixed-point format covers */
    persp_opcount ops = {0}, iops = {0};
    persp_method_prep prep;
    const persp_rational_vertices rv = {.x = {0}}; /* midpoint fits to the planes alone */
    isel.m->prepare(&r, &rv, &isel.params, &prep, NULL);
    for (int y = 0; y < 8; y++) {
        float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX], iu[PERSP_SPAN_MAX], iv[PERSP_SPAN_MAX];
        sel.m->span(&r, &sel.params, NULL, 0, y, PERSP_SPAN_MAX, u, v, &ops);
        isel.m->span(&r, &isel.params, &prep, 0, y, PERSP_SPAN_MAX, iu, iv, &iops);
        for (int k = 0; k < PERSP_SPAN_MAX; k++) {
            double eu, ev;
            persp__rational_eval(&r, k, y, &eu, &ev);
            assert_true(fabs(u[k] - eu) * TEX <= HALF_STEP_BOUND);
            assert_true(fabs(v[k] - ev) * TEX <= HALF_STEP_BOUND);
            assert_true(fabs(iu[k] - eu) * TEX <= HALF_STEP_BOUND + 1e-3);
            assert_true(fabs(iv[k] - ev) * TEX <= HALF_STEP_BOUND + 1e-3);
        }
    }
    print_message("minification: %llu div, %llu add over 512 px\n", (unsigned long long)ops.div,
                  (unsigned long long)ops.add);
    /* More than one division per span: the capped search re-seeded. */
    assert_true(ops.div > 8);
    assert_true(iops.div > 16);
}

static void test_midpoint_parse(void **state)
{
    (void)state;
    assert_int_equal(persp_method_check("midpoint"), PERSP_OK);
    assert_int_equal(persp_method_check("midpoint:int"), PERSP_OK);
    assert_int_equal(persp_method_check("midpoint:edge,int"), PERSP_OK);
    assert_int_equal(persp_method_check("midpoint:"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("midpoint:int,"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("midpoint:float"), PERSP_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_midpoint_within_half_texel),
        cmocka_unit_test(test_midpoint_int_bit_exact),
        cmocka_unit_test(test_midpoint_short_spans_and_degenerate),
        cmocka_unit_test(test_midpoint_minification),
        cmocka_unit_test(test_midpoint_parse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
