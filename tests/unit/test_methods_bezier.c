/*
 * `bezier` by forward differences (src/interp/bezier.c, [Romanyuk-PCF] §4.7):
 *
 *   - the adaptive forward differences of a quadratic (poly.h): stepping
 *     forward and back, halving and doubling the step, reproduce the
 *     quadratic exactly wherever the arithmetic is exact (dyadic values), and
 *     to rounding otherwise;
 *   - bezier:quadt's 4th-order differences equal the direct evaluation of
 *     the Bézier at t(x) within the float rounding of the output plus the
 *     drift bound of poly.h;
 *   - bezier:step puts every pixel within ε = 1/64 pixel of its position on
 *     the curve: its u is u(t) for some t with |x(t) − i| ≤ ε;
 *   - operation counts: quadt costs 8 additions per pixel and nothing else;
 *     step's multiplications are whole halving/doubling pairs.
 */
#include "methods_harness.h"

#include "interp/poly.h"

#define EPS_X (1.0 / 64.0)

/* ------------------------------------------------ adaptive differences */

typedef struct quad {
    double a, b, c; /* a + b·t + c·t² */
} quad;

static double quad_at(const quad *q, double t) { return q->a + t * (q->b + t * q->c); }

/* Random walks of fwd/back/halve/double on quadratics with small integer
 * coefficients, t a multiple of 2^-14 in [−8, 8] and h = 2^-2 .. 2^-14:
 * every exact value has at most 44 significant bits, so the differences
 * must equal p(t), p(t + h) − p(t) and 2c·h² bit for bit. */
static void test_afd2_exact_on_dyadics(void **state)
{
    (void)state;
    test_rng rng = {0xafd2};
    for (int trial = 0; trial < 2000; trial++) {
        quad q = {(double)((int)(test_rng_next(&rng) % 2001) - 1000),
                  (double)((int)(test_rng_next(&rng) % 2001) - 1000),
                  (double)((int)(test_rng_next(&rng) % 2001) - 1000)};
        double t = ldexp((double)((int)(test_rng_next(&rng) % 64) - 32), -3);
        int level = (int)(test_rng_next(&rng) % 4);
        double h = ldexp(1.0, -2 - level);
        persp_afd2 d = {quad_at(&q, t), quad_at(&q, t + h) - quad_at(&q, t), 2.0 * q.c * h * h};
        int halvings = 0;
        for (int op = 0; op < 200; op++) {
            int kind = (int)(test_rng_next(&rng) % 4);
            if (kind == 0 && t + h <= 8.0) {
                persp__afd2_fwd(&d);
                t += h;
            } else if (kind == 1 && t - h >= -8.0) {
                persp__afd2_back(&d);
                t -= h;
            } else if (kind == 2 && level < 12) {
                persp__afd2_halve(&d);
                h *= 0.5, level++, halvings++;
            } else if (kind == 3 && level > 0) {
                persp__afd2_double(&d);
                h *= 2.0, level--;
            }
            double f = quad_at(&q, t), d1 = quad_at(&q, t + h) - f, d2 = 2.0 * q.c * h * h;
            if (d.f != f || d.d1 != d1 || d.d2 != d2)
                fail_msg("trial %d op %d: (%.17g, %.17g, %.17g) != (%.17g, %.17g, %.17g) at t=%g "
                         "h=%g",
                         trial, op, d.f, d.d1, d.d2, f, d1, d2, t, h);
        }
        assert_true(halvings > 0);
    }
}

/* The same walks with real coefficients on t ∈ [0, 1]: f and d1 stay within
 * the rounding of the operations done. Each of the ≤ 400 operations rounds
 * f or d1 once or twice by 2^-53 of |f| ≤ |a| + |b| + |c|; an error of d1 is
 * carried into f by the following steps, at most 1/h of them at step h,
 * with the error scaled by h along with d1, so it adds at most as much again. */
static void test_afd2_real(void **state)
{
    (void)state;
    test_rng rng = {0xafd3};
    for (int trial = 0; trial < 2000; trial++) {
        quad q = {test_rng_uniform(&rng, -2, 2), test_rng_uniform(&rng, -5, 5),
                  test_rng_uniform(&rng, -5, 5)};
        double t = 0.0, h = 1.0 / 64.0;
        int level = 0;
        persp_afd2 d = {q.a, h * (q.b + h * q.c), 2.0 * q.c * h * h};
        double scale = fabs(q.a) + fabs(q.b) + fabs(q.c);
        for (int op = 0; op < 400; op++) {
            int kind = (int)(test_rng_next(&rng) % 4);
            if (kind == 0 && t + h <= 1.0) {
                persp__afd2_fwd(&d);
                t += h;
            } else if (kind == 1 && t - h >= 0.0) {
                persp__afd2_back(&d);
                t -= h;
            } else if (kind == 2 && level < 12) {
                persp__afd2_halve(&d);
                h *= 0.5, level++;
            } else if (kind == 3 && level > 0) {
                persp__afd2_double(&d);
                h *= 2.0, level--;
            }
        }
        double f = quad_at(&q, t), d1 = quad_at(&q, t + h) - f;
        double tol = 800.0 * 0x1p-53 * scale;
        if (fabs(d.f - f) > tol || fabs(d.d1 - d1) > tol)
            fail_msg("trial %d: f %.17g vs %.17g, d1 %.17g vs %.17g", trial, d.f, f, d.d1, d1);
        /* d2 is only ever scaled by powers of two: exact. */
        assert_true(d.d2 == 2.0 * q.c * h * h);
    }
}

/* ------------------------------------------------------------- quadt */

static double binom(int k, int j)
{
    if (j < 0 || j > k) return 0.0;
    double r = 1.0;
    for (int i = 1; i <= j; i++) r = r * (double)(k - j + i) / (double)i;
    return r;
}

typedef struct quadt_ctx {
    persp_method_sel sel;
    double worst_ratio;
    uint64_t pixels, not_nearest;
} quadt_ctx;

/* The Bézier of f on [0, L] at t̂(X), t̂ the quadratic through (0, 0),
 * (x(½), ½), (L, 1) in Lagrange form, u(t) in Bernstein form: the direct
 * evaluation, written independently of the method's power-basis code. */
static long double quadt_direct(const persp_rat1 *f, double L, double X)
{
    double x1, u1;
    persp__bezier_control(f, L, &x1, &u1);
    long double u0 = (long double)persp__rat1_eval(f, 0.0), u2 = (long double)persp__rat1_eval(f, L);
    long double xm = 0.5L * x1 + 0.25L * L, Xl = X;
    long double t = 0.5L * Xl * (Xl - L) / (xm * (xm - L)) + Xl * (Xl - xm) / (L * (L - xm));
    return (1 - t) * (1 - t) * u0 + 2 * t * (1 - t) * (long double)u1 + t * t * u2;
}

static void quadt_span(void *user, const persp_rational *r, int x0, int y, int n)
{
    quadt_ctx *c = user;
    if (n < 3) return;
    float out[2][PERSP_SPAN_MAX];
    c->sel.m->span(r, &c->sel.params, NULL, x0, y, n, out[0], out[1], NULL);
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    const double L = n - 1;
    for (int w = 0; w < 2; w++) {
        persp_rat1 f = persp__span_rat1(&s, w);
        long double U[PERSP_SPAN_MAX + 4];
        for (int k = 0; k < n + 4; k++) U[k] = quadt_direct(&f, L, k);
        /* M_j = max |Δ^j U| over the span (the magnitudes the differences take). */
        double M[5] = {0};
        for (int k = 0; k < n; k++) {
            long double d[5];
            for (int j = 0; j < 5; j++) d[j] = U[k + j];
            for (int j = 1; j < 5; j++)
                for (int i = 4; i >= j; i--) d[i] -= d[i - 1];
            for (int j = 0; j < 5; j++) M[j] = fmax(M[j], (double)fabsl(d[j]));
        }
        double x1, u1;
        persp__bezier_control(&f, L, &x1, &u1);
        double S = fabs((double)U[0]) + fabs(u1) + fabs((double)U[n - 1]);
        for (int k = 0; k < n; k++) {
            /* Half an ulp of the float output; the drift bound of poly.h with
             * the initial differences right to 8 ulps and one rounding per
             * addition; 16 ulps of the curve's size for the coefficients
             * (control point, t̂, the quartic), which are computed by other
             * formulas here. */
            double drift = 0.0;
            for (int j = 0; j <= 4; j++) drift += binom(k, j) * 0x1p-50 * M[j];
            for (int j = 0; j < 4; j++) drift += binom(k, j + 1) * 0x1p-53 * M[j];
            double tol_double = drift + 0x1p-48 * S;
            double tol = 0x1p-24 * fabs((double)U[k]) + tol_double;
            double err = fabs((double)((long double)out[w][k] - U[k]));
            if (!(err <= tol))
                fail_msg("quadt (%d,%d) n=%d k=%d coord %d: %.9g vs direct %.12Lg (err %.3g > tol %.3g)",
                         x0, y, n, k, w, out[w][k], U[k], err, tol);
            if (err / tol > c->worst_ratio) c->worst_ratio = err / tol;
            if (out[w][k] != (float)U[k]) c->not_nearest++;
        }
    }
    c->pixels += (uint64_t)n;
}

static void test_quadt_fd_equals_direct(void **state)
{
    (void)state;
    quadt_ctx c;
    memset(&c, 0, sizeof c);
    c.sel = h_method("bezier:quadt");
    test_rng rng = {0xb321};
    for (size_t ri = 0; ri < H_RATIO_COUNT; ri++)
        for (int i = 0; i < 6; i++) {
            h_triangle T;
            h_random_triangle(&rng, h_ratios[ri], &T);
            h_for_each_span(&T, quadt_span, &c);
        }
    print_message("quadt vs direct: %llu px, worst error/tolerance %.3g, %llu values not the "
                  "nearest float of the direct value\n",
                  (unsigned long long)c.pixels, c.worst_ratio, (unsigned long long)c.not_nearest);
    assert_true(c.pixels > 10000);
    /* The double work is ~1e-15 of the value, a float ulp ~1e-7: the output
     * is the correctly rounded direct value except within ~1e-8 ulp of a tie,
     * which almost never happens. Float differences fail this. */
    assert_true(c.not_nearest * 1000 < c.pixels);
}

/* -------------------------------------------------------------- step */

typedef struct step_ctx {
    persp_method_sel sel;
    double worst_ratio;
    uint64_t pixels;
} step_ctx;

/* The t in [0, 1] with x(t) = X for x(t) = t·(2·x1 + t·sx) (x monotone). */
static double x_inverse(double x1, double sx, double X)
{
    /* sx·t² + 2·x1·t − X = 0, the root in the cancellation-free form. */
    double b = 2.0 * x1;
    return 2.0 * X / (b + sqrt(b * b + 4.0 * sx * X));
}

static void step_span(void *user, const persp_rational *r, int x0, int y, int n)
{
    step_ctx *c = user;
    if (n < 3) return;
    float out[2][PERSP_SPAN_MAX];
    c->sel.m->span(r, &c->sel.params, NULL, x0, y, n, out[0], out[1], NULL);
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    const double L = n - 1;
    for (int w = 0; w < 2; w++) {
        persp_rat1 f = persp__span_rat1(&s, w);
        double x1, u1;
        persp__bezier_control(&f, L, &x1, &u1);
        double u0 = persp__rat1_eval(&f, 0.0), u2 = persp__rat1_eval(&f, L);
        double sx = L - 2.0 * x1, bu = 2.0 * (u1 - u0), su = u0 - 2.0 * u1 + u2;
        double S = fabs(u0) + fabs(u1) + fabs(u2);
        for (int k = 1; k < n - 1; k++) {
            double tk = x_inverse(x1, sx, k);
            double ta = x_inverse(x1, sx, k - EPS_X), tb = x_inverse(x1, sx, fmin(k + EPS_X, L));
            /* du/dx along the curve, u'(t)/x'(t), is a Möbius function of t:
             * its extremes over [ta, tb] are at the ends. */
            double sa = (bu + 2.0 * su * ta) / (2.0 * x1 + 2.0 * sx * ta);
            double sb = (bu + 2.0 * su * tb) / (2.0 * x1 + 2.0 * sx * tb);
            double uk = u0 + tk * (bu + tk * su);
            double tol = EPS_X * fmax(fabs(sa), fabs(sb)) + 0x1p-24 * fabs(uk) + 0x1p-40 * S;
            double err = fabs(out[w][k] - uk);
            if (!(err <= tol))
                fail_msg("step (%d,%d) n=%d k=%d coord %d: %.9g vs u(t(x)) %.12g (err %.3g > %.3g)",
                         x0, y, n, k, w, out[w][k], uk, err, tol);
            if (err / tol > c->worst_ratio) c->worst_ratio = err / tol;
        }
    }
    c->pixels += (uint64_t)n;
}

static void test_step_within_eps(void **state)
{
    (void)state;
    step_ctx c;
    memset(&c, 0, sizeof c);
    c.sel = h_method("bezier:step");
    test_rng rng = {0xb322};
    for (size_t ri = 0; ri < H_RATIO_COUNT; ri++)
        for (int i = 0; i < 6; i++) {
            h_triangle T;
            h_random_triangle(&rng, h_ratios[ri], &T);
            h_for_each_span(&T, step_span, &c);
        }
    print_message("step within 1/64 px: %llu px, worst error/tolerance %.3g\n",
                  (unsigned long long)c.pixels, c.worst_ratio);
    assert_true(c.pixels > 10000);
    /* The landing window is used, not just respected: a search that stopped
     * at exact positions would give ratios near 0. */
    assert_true(c.worst_ratio > 0.3);
}

/* ------------------------------------------------------- op counts */

static void test_op_counts(void **state)
{
    (void)state;
    test_rng rng = {0xb323};
    h_triangle T;
    h_random_triangle(&rng, 3.0, &T);
    const persp_rational *r = &T.t.rat;
    int y = (T.t.ymin + T.t.ymax) / 2, x0 = T.t.xmin;
    float u[64], v[64];
    persp_method_sel qt = h_method("bezier:quadt"), st = h_method("bezier:step");
    persp_opcount a, b;
    for (int n = 3; n < 64; n++) {
        /* quadt: one more pixel costs 4 additions per coordinate and nothing
         * else (the per-span work does not depend on n). */
        memset(&a, 0, sizeof a), memset(&b, 0, sizeof b);
        qt.m->span(r, &qt.params, NULL, x0, y, n, u, v, &a);
        qt.m->span(r, &qt.params, NULL, x0, y, n + 1, u, v, &b);
        assert_int_equal(b.add - a.add, 8);
        assert_int_equal(b.mul, a.mul);
        assert_int_equal(b.div, a.div);
        assert_int_equal(b.cmp, 0);
        assert_int_equal(a.div, 3 + 3); /* ends and control point; the fit of t(x) */
        /* step: 3 divisions per span, and multiplications only in the setup
         * (6 planes + 18 curve + 14 differences) and in whole halving
         * (9) + doubling (6) pairs. */
        memset(&a, 0, sizeof a);
        st.m->span(r, &st.params, NULL, x0, y, n, u, v, &a);
        assert_int_equal(a.div, 3);
        assert_true(a.mul >= 38 && (a.mul - 38) % 15 == 0);
        assert_true(a.cmp >= 2 * (uint64_t)(n - 2));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_afd2_exact_on_dyadics),
        cmocka_unit_test(test_afd2_real),
        cmocka_unit_test(test_quadt_fd_equals_direct),
        cmocka_unit_test(test_step_within_eps),
        cmocka_unit_test(test_op_counts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
