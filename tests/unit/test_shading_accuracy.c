/* Shading accuracy ([Romanyuk-PCF] §4.2-4.3): the ΔI factor and its maximum, the
 * derived t_w polynomial coefficients, every shading mode's span shader
 * against the exact per-pixel reference with stated bounds, and the SVG
 * writer. */
#include "support.h"

#include "analysis/claims.h"
#include "analysis/shading.h"
#include "analysis/svg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The derived extremum of Δ agrees with a brute-force search, |Δ| is the
 * same for r and 1/r and the argument mirrors (the chapter: "the maximum value
 * occurs at 1 − u"). */
static void test_delta_extremum(void **state)
{
    (void)state;
    const double r[] = {0.1, 0.2, 0.5, 0.8, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0, 100.0};
    for (size_t i = 0; i < sizeof r / sizeof r[0]; i++) {
        double best = 0.0, at = 0.0;
        for (int k = 0; k <= 200000; k++) {
            double u = k / 200000.0, d = persp__delta_factor(u, r[i]);
            if (fabs(d) > fabs(best)) best = d, at = u;
        }
        double ustar, ext = persp__delta_extremum(r[i], &ustar);
        assert_true(fabs(ext - best) < 1e-9);
        assert_true(fabs(ustar - at) < 1e-4);
        double umirror, emirror = persp__delta_extremum(1.0 / r[i], &umirror);
        assert_true(fabs(fabs(emirror) - fabs(ext)) < 1e-12);
        assert_true(fabs(umirror - (1.0 - ustar)) < 1e-12);
        /* Sign: screen-linear overshoots when the far end is B (r > 1). */
        assert_true(r[i] > 1.0 ? ext > 0.0 : ext < 0.0);
    }
    /* Δ(0) = Δ(1) = 0: the ends are exact. */
    assert_true(fabs(persp__delta_factor(0.0, 4.0)) < 1e-15);
    assert_true(fabs(persp__delta_factor(1.0, 4.0)) < 1e-15);
}

/* The closed-form coefficients (derived here, the chapter's printed ones
 * contain errors) agree with a Newton interpolation of t_w at the nodes,
 * and the pieces of the piecewise quadratic meet at t_v = 1/2. */
static void test_tw_coefficients(void **state)
{
    (void)state;
    for (double h = 0.2; h <= 9.0; h += 0.35) {
        struct {
            persp_approx_kind kind;
            int piece, count;
            double nodes[4];
        } cases[] = {
            {PERSP_APPROX_QUAD, 0, 3, {0.0, 0.5, 1.0, 0}},
            {PERSP_APPROX_PWQUAD, 0, 3, {0.0, 0.25, 0.5, 0}},
            {PERSP_APPROX_PWQUAD, 1, 3, {0.5, 0.75, 1.0, 0}},
            {PERSP_APPROX_CUBIC, 0, 4, {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}},
        };
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            double y[4], coef[4];
            persp_poly p;
            for (int j = 0; j < cases[c].count; j++) y[j] = persp__tw_exact(cases[c].nodes[j], h);
            persp__poly_interp(cases[c].nodes, y, cases[c].count, &p, NULL);
            persp__tw_coeffs(cases[c].kind, h, cases[c].piece, coef);
            for (int j = 0; j < 4; j++) {
                double want = j <= p.degree ? p.c[j] : 0.0;
                if (fabs(coef[j] - want) > 1e-9 * (1.0 + fabs(want)))
                    fail_msg("kind %d piece %d h %g: c%d = %.12g, interpolation gives %.12g",
                             (int)cases[c].kind, cases[c].piece, h, j, coef[j], want);
            }
        }
    }
    /* (4.6) vs (4.7): t_w = Z_A t_v/(Z_B − t_v(Z_B − Z_A)) with ħ = Z_B/Z_A. */
    for (double tv = 0.0; tv <= 1.0; tv += 0.125) {
        double za = 1.7, zb = 5.1;
        assert_true(fabs(persp__tw_exact(tv, zb / za) - za * tv / (zb - tv * (zb - za))) < 1e-15);
    }
}

/* The chapter's stated maximum relative errors (§4.3: piecewise quadratic 1, 4,
 * 8, 13 %; cubic 0.64, 2.9, 6.3, 10.6 % for ħ = 2..5) are reproduced, to
 * the rounding of the stated figures, by |p − t_w|/t_w over t_v ∈ [1/3, 1];
 * over the whole line the cubic's relative error is far larger. The
 * absolute error follows the exact interpolation remainder. */
static void test_tw_errors_vs_claims(void **state)
{
    (void)state;
    const persp_claim *c = persp__claim(PERSP_CLAIM_TW_BOUNDS);
    const double *pw = c->series, *cu = c->series + PERSP_CLAIM_TW_HBARS;
    for (int i = 0; i < PERSP_CLAIM_TW_HBARS; i++) {
        double h = 2.0 + i;
        persp_tw_error ep, ec, eq;
        persp__tw_error(PERSP_APPROX_PWQUAD, h, &ep);
        persp__tw_error(PERSP_APPROX_CUBIC, h, &ec);
        persp__tw_error(PERSP_APPROX_QUAD, h, &eq);
        print_message("h=%g pw rel[1/3,1] %.2f%% (seed %g%%), cubic %.2f%% (seed %g%%)\n", h,
                      100 * ep.rel_third, pw[i], 100 * ec.rel_third, cu[i]);
        assert_true(fabs(100.0 * ep.rel_third - pw[i]) < c->tol[0]);
        assert_true(fabs(100.0 * ec.rel_third - cu[i]) < c->tol[1]);
        assert_true(ec.rel_max > 5.0 * ec.rel_third);
        /* Degree and node count order the absolute errors. */
        assert_true(eq.abs_max > ep.abs_max && eq.abs_max > ec.abs_max);
        /* The sampled absolute error is the exact interpolation remainder
         * of a rational (poly.h), maximised over the same samples. */
        double L = 3072.0;
        persp_rat1 f = {1.0, 0.0, -(h - 1.0), h * L};
        const double nodes[4] = {0.0, L / 3.0, 2.0 * L / 3.0, L};
        double worst = 0.0;
        for (int k = 0; k <= 3072; k++) worst = fmax(worst, fabs(persp__approx_error(&f, nodes, 4, k)));
        assert_true(fabs(worst - ec.abs_max) < 1e-6);
    }
}

/* Every mode's span shader on seeded random lit triangles. Bounds, each
 * with its reason:
 *  - phong-pc, phong-slerp (exact forms) and gouraud-pc against its own
 *    exact form: the 8-bit quantisation (0.5 level) plus float rounding;
 *    normals of the exact forms within 0.01° and unit within 1e-6;
 *  - polynomial t_w: a t_w error δ moves the blended normal by at most
 *    δ·|Nb − Na|/|N|; vertex normals lie within 44° of the face normal
 *    (random_lit_triangle), so |Nb − Na| ≤ 2 sin 44°, |N| ≥ cos 44°, and
 *    the angle error is at most atan(1.93 δ) with δ the span's t_w error,
 *    which is at most the triangle's (the span's depth ratio is ≤ ħ);
 *  - the screen-linear forms (gouraud, phong, phong-slerp-screen) must be
 *    measurably wrong at ħ = 5, or the comparison proves nothing. */
static void test_modes_random_triangles(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const double groups[3] = {1.5, 3.0, 5.0};
    for (int g = 0; g < 3; g++) {
        double h = groups[g];
        persp_shade_err e[PERSP_SHADE_MODES];
        assert_int_equal(persp__shading_random(ctx, 7, h, 6, e), PERSP_OK);
        for (int i = 0; i < PERSP_SHADE_MODES; i++) {
            const persp_shade_err *r = &e[i];
            assert_int_equal((int)r->mode, PERSP_SHADING_FLAT + i);
            assert_true(r->pixels > 500);
            switch (r->mode) {
            case PERSP_SHADING_PHONG_PC:
            case PERSP_SHADING_PHONG_SLERP:
                assert_true(r->col_max <= 0.6);
                assert_true(r->has_normals && r->ang_max < 0.01 && r->len_max < 1e-6);
                break;
            case PERSP_SHADING_GOURAUD_PC: assert_true(r->own_max <= 0.6); break;
            case PERSP_SHADING_PHONG_PC_QUAD:
            case PERSP_SHADING_PHONG_PC_PWQUAD:
            case PERSP_SHADING_PHONG_PC_CUBIC: {
                persp_approx_kind k = r->mode == PERSP_SHADING_PHONG_PC_QUAD     ? PERSP_APPROX_QUAD
                                      : r->mode == PERSP_SHADING_PHONG_PC_PWQUAD ? PERSP_APPROX_PWQUAD
                                                                                 : PERSP_APPROX_CUBIC;
                persp_tw_error te;
                persp__tw_error(k, h, &te);
                double bound = atan(1.93 * te.abs_max) * 180.0 / PI + 0.01;
                if (!(r->ang_max <= bound))
                    fail_msg("%s h=%g: angle %.4f° over the bound %.4f°", persp_shading_name(r->mode), h,
                             r->ang_max, bound);
                assert_true(r->len_max < 1e-6);
                break;
            }
            default: break;
            }
            if (h == 5.0 && (r->mode == PERSP_SHADING_GOURAUD || r->mode == PERSP_SHADING_PHONG ||
                             r->mode == PERSP_SHADING_PHONG_SLERP_SCREEN))
                assert_true(r->own_max > 3.0);
            if (r->mode == PERSP_SHADING_FLAT) assert_true(r->ang_max > 1.0);
        }
    }
    persp_context_destroy(ctx);
}

/* Whole renders of the built-in lit scene: the exact forms agree with the
 * phong-pc image to a level (phong-slerp: same normals up to rounding),
 * the screen-linear ones do not. */
static void test_modes_scene(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *s = NULL;
    assert_int_equal(persp__shading_test_scene(ctx, &s), PERSP_OK);
    persp_shade_err e[PERSP_SHADE_MODES];
    assert_int_equal(persp__shading_scene_compare(ctx, s, 200, 150, e), PERSP_OK);
    for (int i = 0; i < PERSP_SHADE_MODES; i++) {
        print_message("%-20s max %6.2f mean %.4f\n", persp_shading_name(e[i].mode), e[i].col_max, e[i].col_mean);
        assert_true(e[i].pixels > 10000);
    }
    assert_true(e[PERSP_SHADING_PHONG_PC - PERSP_SHADING_FLAT].col_max == 0.0);
    assert_true(e[PERSP_SHADING_PHONG_SLERP - PERSP_SHADING_FLAT].col_mean < 0.01);
    assert_true(e[PERSP_SHADING_PHONG_PC_CUBIC - PERSP_SHADING_FLAT].col_mean < 0.05);
    assert_true(e[PERSP_SHADING_PHONG - PERSP_SHADING_FLAT].col_max > 10.0);
    assert_true(e[PERSP_SHADING_GOURAUD - PERSP_SHADING_FLAT].col_mean > 1.0);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

static void test_svg_writer(void **state)
{
    (void)state;
    double x[3] = {0, 1, 2}, y[3] = {0, 0.5, NAN}, y2[3] = {1, 2, 3};
    persp_svg_panel p;
    memset(&p, 0, sizeof p);
    p.title = "a<b & c";
    p.xlabel = "x", p.ylabel = "y";
    p.xmin = 0, p.xmax = 2;
    p.series[0] = (persp_svg_series){x, y, 3, "one"};
    p.series[1] = (persp_svg_series){x, y2, 3, "two"};
    p.series_count = 2;
    char path[4096];
    test_binary_path(path, sizeof path, "test_svg_writer.svg");
    FILE *f = fopen(path, "w+");
    assert_non_null(f);
    assert_int_equal(persp__svg_write(f, &p, 1, 300, 200), 0);
    rewind(f);
    char buf[16384];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    assert_non_null(strstr(buf, "<?xml"));
    assert_non_null(strstr(buf, "a&lt;b &amp; c"));
    assert_null(strstr(buf, "a<b"));
    assert_true(strstr(buf, "</svg>") == buf + n - 7);
    int lines = 0;
    for (const char *s = buf; (s = strstr(s, "<polyline")); s++) lines++;
    assert_int_equal(lines, 2); /* the NaN ends series one after two points */
    /* An empty x range is refused before anything is written. */
    p.xmax = p.xmin;
    f = fopen(path, "w+");
    assert_non_null(f);
    assert_int_equal(persp__svg_write(f, &p, 1, 300, 200), -1);
    assert_int_equal(ftell(f), 0);
    fclose(f);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_delta_extremum),       cmocka_unit_test(test_tw_coefficients),
        cmocka_unit_test(test_tw_errors_vs_claims),    cmocka_unit_test(test_modes_random_triangles),
        cmocka_unit_test(test_modes_scene),          cmocka_unit_test(test_svg_writer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
