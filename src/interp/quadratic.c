/*
 * Polynomial approximations along the span ([Romanyuk-PCF] §4.4, §4.6):
 *
 *   `quadratic`          the traditional quadratic on normalised x through the
 *                        span's start, middle and end, coefficients (4.9);
 *   `quadratic-shifted`  the inner anchor moved by Table 4.2, coefficients
 *                        (4.19)-(4.20) (= Table 4.1), separately for u and v;
 *   `quadratic-unnorm`   the quadratic on un-normalised screen x, coefficients
 *                        by Cramer's rule with one division per span (§4.6 end);
 *   `cubic`              anchors at the start, end and the two points that
 *                        divide the span in thirds (§4.4), normalised x.
 *
 * The anchors are the centres of the span's first and last pixel (k = 0 and
 * k = L = n − 1); the exact values there come from Heckbert's form in double
 * precision, so every method is exact at its anchors up to the final rounding
 * to float. Spans of one or two pixels are evaluated exactly.
 *
 * Error bound (exact remainder of interpolating a rational, poly.h): with the
 * per-pixel denominator D(k) = q + dq·k > 0, ρ = Dmax/Dmin over the span and
 * |u'|max = |n1·dq − dn1·q| / Dmin² the largest slope in the span,
 *
 *     quadratic (τ = 1/2):  |Δu| ≤ |u'|max · L · (ρ − 1)² / (12·√3)
 *     quadratic, anchor τ:  |Δu| ≤ |u'|max · L · (ρ − 1)² · max_s |s(s − τ)(s − 1)|
 *                           (0.0481 = 1/(12·√3) for τ = 1/2; 0.0657, 0.0848, 0.0948
 *                           for τ = 0.4/0.6, 0.3/0.7, 0.25/0.75)
 *     cubic:                |Δu| ≤ |u'|max · L · (ρ − 1)³ / 81
 *
 * plus the float rounding of the output (half an ulp of u). In texels,
 * multiply by the texture size. The tests check the sharper point-wise form
 * |cross|·|dq|^(m−1)·|Π(k − k_j)| / Dmin^(m+1).
 */
#include "interp/methods.h"
#include "interp/poly.h"

#include <math.h>

/* Values at the two ends and (for n ≥ 3) the span length L. */
static void ends(const persp_span_rat *s, int n, double *u0, double *v0, double *u2, double *v2)
{
    persp__span_rat_at(s, 0.0, u0, v0);
    persp__span_rat_at(s, (double)(n - 1), u2, v2);
}

/* Spans of one or two pixels: both pixels are anchors, evaluate exactly. */
static int short_span(const persp_span_rat *s, int n, float *s1, float *s2, persp_opcount *ops)
{
    if (n > 2) return 0;
    for (int k = 0; k < n; k++) {
        double u, v;
        persp__span_rat_at(s, (double)k, &u, &v);
        s1[k] = (float)u;
        s2[k] = (float)v;
    }
    PERSP_SPAN_RAT_AT_OPS(ops, n);
    return 1;
}

/* Runs p(s) = c0 + c1·s + c2·s² (+ c3·s³) at s = k·h, k = 0..n−1. */
static void run_poly(const persp_poly *p, double h, int n, float *out, persp_opcount *ops)
{
    persp_fd fd;
    persp__fd_init(p, 0.0, h, &fd, ops);
    persp__fd_run(&fd, n, out, 1, ops);
}

/* ------------------------------------------------------------ quadratic */

/* Traditional quadratic, [Romanyuk-PCF] (4.9) with its erratum corrected:
 * on s ∈ [0, 1] through (0, u0), (1/2, u1), (1, u2)
 *     A1 = 2u0 − 4u1 + 2u2,  A2 = −3u0 + 4u1 − u2,  A3 = u0
 * (the chapter prints A2 = −3u0 + 4u1 − 2u2, which misses u(1) = u2).
 * Cost: per span 3 div (anchors) + 1 div (h = 1/L, the normalisation the
 * chapter objects to), 27 mul, 25 add; per pixel 4 add (2 per coordinate). */
static void quadratic_span(const persp_rational *r, const persp_method_params *params,
                           const persp_method_prep *prep, int x0, int y, int n, float *s1,
                           float *s2, persp_opcount *ops)
{
    (void)params, (void)prep;
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    if (short_span(&s, n, s1, s2, ops)) return;
    double L = (double)(n - 1);
    double u0, v0, u1, v1, u2, v2;
    ends(&s, n, &u0, &v0, &u2, &v2);
    persp__span_rat_at(&s, 0.5 * L, &u1, &v1);
    PERSP_SPAN_RAT_AT_OPS(ops, 3);
    persp_poly pu = {2, {u0, -3.0 * u0 + 4.0 * u1 - u2, 2.0 * u0 - 4.0 * u1 + 2.0 * u2, 0.0}};
    persp_poly pv = {2, {v0, -3.0 * v0 + 4.0 * v1 - v2, 2.0 * v0 - 4.0 * v1 + 2.0 * v2, 0.0}};
    PERSP_OPS(ops, mul, 8);
    PERSP_OPS(ops, add, 8);
    double h = 1.0 / L;
    PERSP_OPS(ops, div, 1);
    run_poly(&pu, h, n, s1, ops);
    run_poly(&pv, h, n, s2, ops);
}

/* ---------------------------------------------------- quadratic-shifted */

/* q = 1/(τ² − τ) of (4.19) for the anchors of Table 4.2: constants, so the
 * per-span division of (4.20) disappears (as the chapter notes for a fixed τ). */
static double shift_q(double tau)
{
    if (tau == 0.25 || tau == 0.75) return -16.0 / 3.0;
    if (tau == 0.3 || tau == 0.7) return -1.0 / 0.21;
    if (tau == 0.4 || tau == 0.6) return -1.0 / 0.24;
    if (tau == 0.5) return -4.0;
    return 1.0 / (tau * tau - tau);
}

/* Quadratic on s ∈ [0, 1] through (0, c0), (τ, cin), (1, c1), derived from
 * the system (4.16) with x0 = 0, x1 = 1 (the chapter's (4.17)):
 *     C = c0,  A + B = c1 − c0,  A·τ² + B·τ = cin − c0
 *  ⇒  B = (τ²(c1 − c0) + c0 − cin)/(τ² − τ),  A = −(τ(c1 − c0) + c0 − cin)/(τ² − τ),
 * i.e. with r = τ(c1 − c0), s = c0 − cin, q = 1/(τ² − τ):
 *     A = −q(r + s),  B = q(r·τ + s),  C = c0          ((4.19)-(4.20)). */
static persp_poly shifted_poly(double c0, double cin, double c1, double tau)
{
    double q = shift_q(tau);
    double rr = tau * (c1 - c0), ss = c0 - cin;
    persp_poly p = {2, {c0, q * (rr * tau + ss), -q * (rr + ss), 0.0}};
    return p;
}

/* Cost: per span 4 div (ends, the inner anchors of u and v; 3 when both
 * share τ), 6 + 5·4 + 10 mul, 6 + 3·4 + 10 add, up to 14 cmp for Table 4.2;
 * per pixel 4 add. */
static void shifted_span(const persp_rational *r, const persp_method_params *params,
                         const persp_method_prep *prep, int x0, int y, int n, float *s1,
                         float *s2, persp_opcount *ops)
{
    (void)params, (void)prep;
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    if (short_span(&s, n, s1, s2, ops)) return;
    double L = (double)(n - 1);
    double u0, v0, u2, v2, uin, vin, dummy;
    ends(&s, n, &u0, &v0, &u2, &v2);
    double tu = persp__quad_shift_anchor(u0, u2), tv = persp__quad_shift_anchor(v0, v2);
    PERSP_OPS(ops, cmp, 28);
    if (tu == tv) {
        persp__span_rat_at(&s, tu * L, &uin, &vin);
        PERSP_SPAN_RAT_AT_OPS(ops, 3);
    } else {
        persp__span_rat_at(&s, tu * L, &uin, &dummy);
        persp__span_rat_at(&s, tv * L, &dummy, &vin);
        PERSP_SPAN_RAT_AT_OPS(ops, 4);
    }
    persp_poly pu = shifted_poly(u0, uin, u2, tu), pv = shifted_poly(v0, vin, v2, tv);
    PERSP_OPS(ops, mul, 10);
    PERSP_OPS(ops, add, 10);
    double h = 1.0 / L;
    PERSP_OPS(ops, div, 1);
    run_poly(&pu, h, n, s1, ops);
    run_poly(&pv, h, n, s2, ops);
}

/* ----------------------------------------------------- quadratic-unnorm */

/* Quadratic in the screen coordinate X itself (pixel centres X0, X0 + L/2,
 * X0 + L), by Cramer's rule (§4.6 end), one division d = 1/Δ per span:
 *     Δ  = X0²(X1 − X2) + X1²(X2 − X0) + X2²(X0 − X1)
 *     A1 = d·(u0(X1 − X2) + u1(X2 − X0) + u2(X0 − X1))
 *     A2 = d·(X0²(u1 − u2) + X1²(u2 − u0) + X2²(u0 − u1))
 *     A3 = d·(X0²(X1u2 − X2u1) + X1²(X2u0 − X0u2) + X2²(X0u1 − X1u0))
 * Double precision matters here: A3 is the value extrapolated to X = 0 and
 * cancels to ~|u|·X0³/L³ of its terms' size; in single precision this form
 * loses most of its digits far from the origin.
 * Cost: per span 3 div (anchors) + 1 div (d), 6 + 15 + 40 mul, 6 + 9 + 34
 * add; per pixel 4 add. */
static persp_poly cramer_poly(const double X[3], const double X2[3], double d, const double u[3])
{
    double a1 = d * (u[0] * (X[1] - X[2]) + u[1] * (X[2] - X[0]) + u[2] * (X[0] - X[1]));
    double a2 = d * (X2[0] * (u[1] - u[2]) + X2[1] * (u[2] - u[0]) + X2[2] * (u[0] - u[1]));
    double a3 = d * (X2[0] * (X[1] * u[2] - X[2] * u[1]) + X2[1] * (X[2] * u[0] - X[0] * u[2]) +
                     X2[2] * (X[0] * u[1] - X[1] * u[0]));
    persp_poly p = {2, {a3, a2, a1, 0.0}};
    return p;
}

static void unnorm_span(const persp_rational *r, const persp_method_params *params,
                        const persp_method_prep *prep, int x0, int y, int n, float *s1,
                        float *s2, persp_opcount *ops)
{
    (void)params, (void)prep;
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    if (short_span(&s, n, s1, s2, ops)) return;
    double L = (double)(n - 1);
    double u[3], v[3];
    ends(&s, n, &u[0], &v[0], &u[2], &v[2]);
    persp__span_rat_at(&s, 0.5 * L, &u[1], &v[1]);
    PERSP_SPAN_RAT_AT_OPS(ops, 3);
    double X0 = (double)x0 + 0.5;
    const double X[3] = {X0, X0 + 0.5 * L, X0 + L};
    const double X2[3] = {X[0] * X[0], X[1] * X[1], X[2] * X[2]};
    double det = X2[0] * (X[1] - X[2]) + X2[1] * (X[2] - X[0]) + X2[2] * (X[0] - X[1]);
    double d = 1.0 / det;
    PERSP_OPS(ops, div, 1);
    persp_poly pu = cramer_poly(X, X2, d, u), pv = cramer_poly(X, X2, d, v);
    PERSP_OPS(ops, mul, 6 + 40);
    PERSP_OPS(ops, add, 9 + 34);
    persp_fd fd;
    persp__fd_init(&pu, X0, 1.0, &fd, ops);
    persp__fd_run(&fd, n, s1, 1, ops);
    persp__fd_init(&pv, X0, 1.0, &fd, ops);
    persp__fd_run(&fd, n, s2, 1, ops);
}

/* ---------------------------------------------------------------- cubic */

/* Cubic on s ∈ [0, 1] through s = 0, 1/3, 2/3, 1 (§4.4), fitted by the
 * shared interpolation code (poly.c). Cost: per span 4 div (anchors) + 1
 * div (h) + 12 div (divided differences, constant nodes: hardware would
 * fold them), 6 + 20 + ~40 mul, 6 + 12 + ~50 add; per pixel 6 add. */
static void cubic_span(const persp_rational *r, const persp_method_params *params,
                       const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                       persp_opcount *ops)
{
    (void)params, (void)prep;
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    if (short_span(&s, n, s1, s2, ops)) return;
    double L = (double)(n - 1);
    static const double nodes[4] = {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0};
    double u[4], v[4];
    for (int j = 0; j < 4; j++) persp__span_rat_at(&s, nodes[j] * L, &u[j], &v[j]);
    PERSP_SPAN_RAT_AT_OPS(ops, 4);
    persp_poly pu, pv;
    persp__poly_interp(nodes, u, 4, &pu, ops);
    persp__poly_interp(nodes, v, 4, &pv, ops);
    double h = 1.0 / L;
    PERSP_OPS(ops, div, 1);
    run_poly(&pu, h, n, s1, ops);
    run_poly(&pv, h, n, s2, ops);
}

const persp_method persp__method_quadratic = {
    .name = "quadratic",
    .params_help = "",
    .summary = "quadratic through the span's start, middle and end on normalised x",
    .source = "[Romanyuk-PCF] §4.4, (4.9) (A2 corrected)",
    .cost = "4 add /px; 4 div, ~45 mul, ~45 add /span",
    .span = quadratic_span,
};

const persp_method persp__method_quadratic_shifted = {
    .name = "quadratic-shifted",
    .params_help = "",
    .summary = "quadratic with the inner anchor moved by Table 4.2 (per coordinate)",
    .source = "[Romanyuk-PCF] §4.6, (4.16)-(4.20), Tables 4.1, 4.2",
    .cost = "4 add /px; 4-5 div, ~60 mul, ~55 add, 28 cmp /span",
    .span = shifted_span,
};

const persp_method persp__method_quadratic_unnorm = {
    .name = "quadratic-unnorm",
    .params_help = "",
    .summary = "quadratic on un-normalised screen x, Cramer's rule, one division for the fit",
    .source = "[Romanyuk-PCF] §4.6 (end)",
    .cost = "4 add /px; 4 div, ~90 mul, ~85 add /span",
    .span = unnorm_span,
};

const persp_method persp__method_cubic = {
    .name = "cubic",
    .params_help = "",
    .summary = "cubic through the span's ends and the points dividing it in thirds",
    .source = "[Romanyuk-PCF] §4.4",
    .cost = "6 add /px; 5 div (+12 constant), ~90 mul, ~110 add /span",
    .span = cubic_span,
};
