/*
 * The shared span-polynomial module (src/interp/poly.c) and the formulas of
 * [Romanyuk-PCF] it replaces: interpolation, forward differences, the exact
 * remainder formula, Table 4.1, and the Bézier control point
 * (4.29)-(4.30).
 */
#include "support.h"

#include "interp/poly.h"

#include <math.h>
#include <string.h>

#define NEAR(a, b, tol) assert_true(fabs((double)(a) - (double)(b)) <= (tol))

static persp_rat1 random_rat(test_rng *rng)
{
    /* Denominator positive on [0, 63]: depth ratio up to ~9. */
    double delta = test_rng_uniform(rng, 0.5, 4.0);
    double gamma = test_rng_uniform(rng, -delta * 0.88, delta * 8.0) / 63.0;
    persp_rat1 f = {test_rng_uniform(rng, -2, 2), test_rng_uniform(rng, -5, 5), gamma, delta};
    return f;
}

static void test_interp_and_fd(void **state)
{
    (void)state;
    test_rng rng = {11};
    for (int trial = 0; trial < 500; trial++) {
        persp_rat1 f = random_rat(&rng);
        int count = 1 + (int)(test_rng_next(&rng) % 5);
        double s[5], y[5];
        for (int j = 0; j < count; j++) {
            /* Nodes within [0, 70], where random_rat's denominator stays positive. */
            s[j] = j * (count == 5 ? 15.0 : 21.0) + test_rng_uniform(&rng, 0, 5);
            y[j] = persp__rat1_eval(&f, s[j]);
        }
        persp_poly p;
        persp__poly_interp(s, y, count, &p, NULL);
        assert_int_equal(p.degree, count - 1);
        for (int j = 0; j < count; j++) NEAR(persp__poly_eval(&p, s[j]), y[j], 1e-11 * (1 + fabs(y[j])));
        /* The exact remainder formula of poly.h against the fitted polynomial. */
        for (double x = 0; x <= 63; x += 3.5) {
            double err = persp__rat1_eval(&f, x) - persp__poly_eval(&p, x);
            NEAR(persp__approx_error(&f, s, count, x), err, 1e-9 * (1 + fabs(err)));
        }
        /* Forward differences reproduce Horner on a grid. */
        persp_fd fd;
        float out[64];
        double s0 = test_rng_uniform(&rng, -3, 3), h = test_rng_uniform(&rng, 0.01, 1.0);
        persp__fd_init(&p, s0, h, &fd, NULL);
        persp__fd_run(&fd, 64, out, 1, NULL);
        for (int k = 0; k < 64; k++) {
            double want = persp__poly_eval(&p, s0 + k * h);
            NEAR(out[k], want, 0x1p-23 * fabs(want) + 1e-9 * (1 + fabs(p.c[0]) + fabs(p.c[1]) * 64 +
                                                             fabs(p.c[2]) * 4096 + fabs(p.c[3]) * 262144 +
                                                             fabs(p.c[4]) * 16777216));
        }
    }
}

/* Forward differences of quartics (bezier:quadt) with integer coefficients
 * on integer and half-integer grids: every value and difference is a dyadic
 * number far below 2^53, and every value below 2^24, so the float output
 * must equal the polynomial exactly. */
static void test_fd_quartic_exact(void **state)
{
    (void)state;
    test_rng rng = {13};
    for (int trial = 0; trial < 300; trial++) {
        persp_poly p = {4, {0}};
        for (int i = 0; i <= 4; i++) p.c[i] = (double)((int)(test_rng_next(&rng) % 7) - 3);
        if (p.c[4] == 0.0) p.c[4] = 1.0;
        const double s0 = (double)((int)(test_rng_next(&rng) % 15) - 7);
        const double h = (trial % 2) ? 1.0 : 0.5;
        persp_fd fd;
        float out[40];
        persp__fd_init(&p, s0, h, &fd, NULL);
        assert_int_equal(fd.degree, 4);
        persp__fd_run(&fd, 40, out, 1, NULL);
        for (int k = 0; k < 40; k++) {
            double want = persp__poly_eval(&p, s0 + k * h);
            if (out[k] != (float)want)
                fail_msg("trial %d k %d: %.9g != %.17g", trial, k, out[k], want);
        }
    }
}

/* persp__approx_span: exact at its nodes, and its error is the remainder. */
static void test_approx_span(void **state)
{
    (void)state;
    test_rng rng = {12};
    for (int trial = 0; trial < 300; trial++) {
        persp_rat1 f = random_rat(&rng);
        int n = 3 + (int)(test_rng_next(&rng) % 62);
        double L = n - 1;
        float out[64];
        const persp_approx_kind kinds[3] = {PERSP_APPROX_QUAD, PERSP_APPROX_PWQUAD, PERSP_APPROX_CUBIC};
        for (int kk = 0; kk < 3; kk++) {
            persp__approx_span(&f, kinds[kk], 0.5, n, out, NULL);
            for (int k = 0; k < n; k++) {
                double nodes[4];
                int count;
                if (kinds[kk] == PERSP_APPROX_QUAD) {
                    nodes[0] = 0, nodes[1] = L / 2, nodes[2] = L, count = 3;
                } else if (kinds[kk] == PERSP_APPROX_CUBIC) {
                    nodes[0] = 0, nodes[1] = L / 3, nodes[2] = 2 * L / 3, nodes[3] = L, count = 4;
                } else if (k <= (n - 1) / 2) {
                    nodes[0] = 0, nodes[1] = L / 4, nodes[2] = L / 2, count = 3;
                } else {
                    nodes[0] = L / 2, nodes[1] = 3 * L / 4, nodes[2] = L, count = 3;
                }
                double ex = persp__rat1_eval(&f, k);
                double want = ex - persp__approx_error(&f, nodes, count, k);
                NEAR(out[k], want, 0x1p-23 * fabs(want) + 1e-10);
            }
            NEAR(out[0], persp__rat1_eval(&f, 0), 0x1p-24 * fabs(out[0]) + 1e-12);
            NEAR(out[n - 1], persp__rat1_eval(&f, L), 0x1p-23 * fabs(out[n - 1]) + 1e-10);
        }
    }
}

/* Table 4.1 of [Romanyuk-PCF] from (4.18): A = a1·u1 + a0·u0 + ai·u_in,
 * B = b1·u1 + b0·u0 + bi·u_in, compared with the printed coefficients
 * (to their 3-4 printed digits). The printed 1.4297 for τ = 0.3 is an
 * erratum (10/7 = 1.4286), checked separately. */
static void test_table_4_1(void **state)
{
    (void)state;
    const struct { double tau, a1, a0, ai, b1, b0, bi; } rows[] = {
        {0.75, 4, 1.333, -5.333, -3, -2.333, 5.333},
        {0.7, 3.333, 1.429, -4.762, -2.333, -2.429, 4.762},
        {0.6, 2.5, 1.667, -4.167, -1.5, -2.667, 4.167},
        {0.5, 2, 2, -4, -1, -3, 4},
        {0.4, 1.667, 2.5, -4.167, -0.667, -3.5, 4.167},
        {0.3, 1.4286, 3.333, -4.762, -0.429, -4.333, 4.762}, /* printed 1.4297 */
        {0.25, 1.333, 4, -5.333, -0.333, -5, 5.333},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        double t = rows[i].tau, q = 1.0 / (t * t - t);
        /* Coefficients of u1, u0, u_in in A = −q(τ(u1 − u0) + u0 − u_in), B = q(τ²(u1 − u0) + u0 − u_in). */
        NEAR(-q * t, rows[i].a1, 1e-3);
        NEAR(-q * (1 - t), rows[i].a0, 1e-3);
        NEAR(q, rows[i].ai, 1e-3);
        NEAR(q * t * t, rows[i].b1, 1e-3);
        NEAR(q * (1 - t * t), rows[i].b0, 1e-3);
        NEAR(-q, rows[i].bi, 1e-3);
        /* The fit through (0,u0), (τ,u_in), (1,u1) by the shared code agrees. */
        const double s[3] = {0, t, 1}, y[3] = {0.3, 0.55, 0.9};
        persp_poly p;
        persp__poly_interp(s, y, 3, &p, NULL);
        NEAR(p.c[2], -q * (t * (y[2] - y[0]) + y[0] - y[1]), 1e-12);
        NEAR(p.c[1], q * (t * t * (y[2] - y[0]) + y[0] - y[1]), 1e-12);
    }
    NEAR(-1.0 / (0.09 - 0.3) * 0.3, 10.0 / 7.0, 1e-12);
    assert_true(fabs(10.0 / 7.0 - 1.4297) > 1e-3); /* the printed value is off */
}

/* (4.9): the printed A2 = −3u0 + 4u1 − 2u2 misses u(1) = u2; −u2 is right. */
static void test_formula_4_9(void **state)
{
    (void)state;
    double u0 = 0.2, u1 = 0.45, u2 = 0.9;
    double a1 = 2 * u0 - 4 * u1 + 2 * u2, a3 = u0;
    NEAR(a1 + (-3 * u0 + 4 * u1 - u2) + a3, u2, 1e-15);
    NEAR(a1 * 0.25 + (-3 * u0 + 4 * u1 - u2) * 0.5 + a3, u1, 1e-15);
    assert_true(fabs(a1 + (-3 * u0 + 4 * u1 - 2 * u2) + a3 - u2) > 0.5);
}

/* The closed-form Bézier control point (bezier.c) equals (4.29)-(4.30) and
 * is the intersection of the end tangents. */
static void test_bezier_control(void **state)
{
    (void)state;
    test_rng rng = {13};
    for (int trial = 0; trial < 200; trial++) {
        persp_rat1 f = random_rat(&rng);
        double L = 3 + (double)(test_rng_next(&rng) % 60);
        if (fabs(f.gamma) < 1e-6) continue;
        double x1, u1;
        persp__bezier_control(&f, L, &x1, &u1);
        /* (4.27)-(4.30) with x0 = 0, x2 = L, y folded into B = δ, A = α·δ − γ·β. */
        double A = f.alpha * f.delta - f.gamma * f.beta, B = f.delta;
        double x0 = 0, x2 = L, u0 = persp__rat1_eval(&f, x0), u2 = persp__rat1_eval(&f, x2);
        double C0 = (f.gamma * x0 + B) * (f.gamma * x0 + B), C2 = (f.gamma * x2 + B) * (f.gamma * x2 + B);
        if (fabs(A) < 1e-9) continue;
        double x1s = ((u0 - u2) * C0 * C2 - A * (x0 * C2 - x2 * C0)) / (A * (C0 - C2));
        double u1s = u0 + A / C0 * (x1s - x0);
        NEAR(x1, x1s, 1e-7 * L);
        NEAR(u1, u1s, 1e-7 * (1 + fabs(u1)));
        /* Tangent at x2 passes through (x1, u1) as well. */
        double d2 = A / C2;
        NEAR(u2 + d2 * (x1 - x2), u1, 1e-7 * (1 + fabs(u1)));
        assert_true(x1 > 0 && x1 < L);
    }
}

/* [Romanyuk-PCF] §4.7, t as a quadratic in x through (x0,0), (x1,t1), (x2,1):
 * the printed A3 = d(x0²(x1 − x2t1) − x0(x1² + x2²t1)) has a sign error;
 * Cramer's rule gives A3 = d(x0²(x1 − x2t1) − x0(x1² − x2²t1)). */
static void test_quadt_cramer(void **state)
{
    (void)state;
    double x0 = 3, x1 = 9, x2 = 20, t1 = 0.4;
    double d = 1.0 / (x0 * x0 * (x1 - x2) + x1 * x1 * (x2 - x0) + x2 * x2 * (x0 - x1));
    double A1 = d * (t1 * (x2 - x0) + x0 - x1);
    double A2 = d * (t1 * (x0 * x0 - x2 * x2) - x0 * x0 + x1 * x1);
    double A3 = d * (x0 * x0 * (x1 - x2 * t1) - x0 * (x1 * x1 - x2 * x2 * t1));
    double A3p = d * (x0 * x0 * (x1 - x2 * t1) - x0 * (x1 * x1 + x2 * x2 * t1));
    NEAR(A1 * x0 * x0 + A2 * x0 + A3, 0.0, 1e-12);
    NEAR(A1 * x1 * x1 + A2 * x1 + A3, t1, 1e-12);
    NEAR(A1 * x2 * x2 + A2 * x2 + A3, 1.0, 1e-12);
    assert_true(fabs(A1 * x0 * x0 + A2 * x0 + A3p) > 1e-3);
}

/* [Romanyuk-PCF] §4.3 piecewise quadratic for t_w(t_v) on [0, 1/2] (Z_A = 1,
 * Z_B = ħ): through t_v = 0, 1/4, 1/2 the fit gives a = 8(ħ − 1)/((ħ + 1)(3ħ + 1)),
 * b = 2(ħ + 3)/((ħ + 1)(3ħ + 1)); the printed a has the opposite sign and
 * the printed b lacks the factor 2. */
static void test_tw_piecewise(void **state)
{
    (void)state;
    for (double hb = 1.5; hb <= 5; hb += 0.5) {
        persp_rat1 tw = {1.0, 0.0, 1.0 - hb, hb}; /* (4.6): t_w = Z_A t/(Z_B − t(Z_B − Z_A)) */
        const double s[3] = {0, 0.25, 0.5};
        double y[3];
        for (int j = 0; j < 3; j++) y[j] = persp__rat1_eval(&tw, s[j]);
        persp_poly p;
        persp__poly_interp(s, y, 3, &p, NULL);
        double den = (hb + 1) * (3 * hb + 1);
        NEAR(p.c[2], 8 * (hb - 1) / den, 1e-12);
        NEAR(p.c[1], 2 * (hb + 3) / den, 1e-12);
        NEAR(p.c[0], 0.0, 1e-12);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_interp_and_fd),  cmocka_unit_test(test_fd_quartic_exact),
        cmocka_unit_test(test_approx_span),
        cmocka_unit_test(test_table_4_1),      cmocka_unit_test(test_formula_4_9),
        cmocka_unit_test(test_bezier_control), cmocka_unit_test(test_quadt_cramer),
        cmocka_unit_test(test_tw_piecewise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
