/*
 * Span polynomials: fitting low-degree polynomials to a rational function of
 * one variable and evaluating them by forward differences.
 *
 * Along one rasterization line every perspective-correct quantity is a
 * 1-D rational function of the screen position,
 *
 *     f(s) = (alpha·s + beta) / (gamma·s + delta),             ([Romanyuk-PCF] (4.8))
 *
 * and so is the world-space parameter t_w of [Romanyuk-PCF] §4.2-4.3 as a function
 * of the screen parameter t_v ((4.6): alpha = Z_A, beta = 0,
 * gamma = Z_A − Z_B, delta = Z_B). The approximating texture methods
 * (quadratic, cubic, subdiv-quad, bi-polynomials) and the perspective-correct
 * shading approximations share this module:
 *
 *   persp__poly_interp   the interpolating polynomial through 2..4 nodes;
 *   persp__fd_init/run   its values on an arithmetic grid by forward
 *                        differences (degree additions per value);
 *   persp__approx_span   fit + evaluate in one call for f along n samples.
 *
 * Interpolation error (the Cauchy remainder made exact for a rational): for
 * nodes s_1..s_m and D(s) = gamma·s + delta without a zero on the hull,
 *
 *     f(s) − p(s) = (−1)^m · (beta·gamma − alpha·delta) · gamma^(m−1)
 *                   · Π(s − s_j) / (D(s) · Π D(s_j)),
 *
 * so |f − p| ≤ |beta·gamma − alpha·delta|·|gamma|^(m−1)·|Π(s − s_j)| / Dmin^(m+1).
 * persp__approx_error evaluates the exact expression.
 *
 * Everything here is double precision; values are rounded to float only on
 * output, so the float result differs from the double polynomial by at most
 * half an ulp plus the forward-difference drift. An error r put into the
 * j-th difference (by its initial rounding, or by an addition) reaches the
 * value k steps later C(k, j) times, so after k steps
 *
 *     |drift| ≤ Σ_j C(k, j)·|r_j(0)| + 2^-53·Σ_{j<degree} C(k, j+1)·max|Δ^j p|,
 *
 * negligible in double over a 64-pixel span (in float the same sum reaches
 * ~35 ulps for the quartic of bezier:quadt, so the differences stay double).
 */
#ifndef PERSP_INTERP_POLY_H
#define PERSP_INTERP_POLY_H

#include "core/shared.h"

#include "interp/method.h"

/* Degree 4 serves bezier:quadt, whose u(t(x)) is a quartic in x. */
#define PERSP_POLY_MAX_DEGREE 4

/* f(s) = (alpha·s + beta) / (gamma·s + delta). */
typedef struct persp_rat1 {
    double alpha, beta, gamma, delta;
} persp_rat1;

static inline double persp__rat1_eval(const persp_rat1 *f, double s)
{
    return (f->alpha * s + f->beta) / (f->gamma * s + f->delta);
}

/* p(s) = c[0] + c[1]·s + … + c[4]·s⁴ (c[j] = 0 above degree). */
typedef struct persp_poly {
    int degree;
    double c[PERSP_POLY_MAX_DEGREE + 1];
} persp_poly;

/* Forward-difference state: d[0] = p(s), d[j] = Δ^j p(s) for the step h. */
typedef struct persp_fd {
    int degree;
    double d[PERSP_POLY_MAX_DEGREE + 1];
} persp_fd;

/* The polynomial of degree count−1 through (s[j], y[j]), j < count,
 * 1 ≤ count ≤ 5, nodes pairwise distinct (Newton divided differences,
 * converted to the power basis). Counts into ops when non-NULL. */
PERSP_INTERNAL void persp__poly_interp(const double *s, const double *y, int count, persp_poly *out,
                                       persp_opcount *ops);

/* p(s0 + k·h) as a double, by Horner (for reference and tests). */
double persp__poly_eval(const persp_poly *p, double s);

/* Starts forward differences of p at s0 with step h. */
PERSP_INTERNAL void persp__fd_init(const persp_poly *p, double s0, double h, persp_fd *fd,
                                   persp_opcount *ops);

/* Writes p(s0 + k·h) for k = 0..n−1 to out[k·stride] as floats and leaves fd
 * at s0 + n·h. Costs degree additions per value (counted). */
void persp__fd_run(persp_fd *fd, int n, float *out, int stride, persp_opcount *ops);

/*
 * Adaptive forward differences of a quadratic (Lien, Shantz & Pratt,
 * "Adaptive forward differencing for rendering curves and surfaces",
 * SIGGRAPH 1987): the state of p(t) = A + B·t + C·t² at t for the step h is
 *
 *     f = p(t),  d1 = p(t + h) − p(t) = h·(B + 2C·t) + C·h²,  d2 = 2C·h².
 *
 * Step forward (t → t + h):  f += d1, d1 += d2            ([Romanyuk-PCF] (4.34))
 * Step back    (t → t − h):  d1 −= d2, f −= d1
 * Halve  (h → h/2):  d1 ← d1/2 − d2/8, d2 ← d2/4
 *     since h·(B + 2C·t) = d1 − d2/2, so (h/2)(B + 2C·t) + C·h²/4 = d1/2 − d2/4 + d2/8;
 * Double (h → 2h):   d1 ← 2·d1 + d2,   d2 ← 4·d2            (the inverse).
 * The scalings are by powers of two (exact in binary floating point, shifts
 * in fixed point); each rescaling rounds once (one addition) and each step
 * twice. Costs: step 2 add; halve 3 mul, 1 add; double 2 mul, 1 add.
 */
typedef struct persp_afd2 {
    double f, d1, d2;
} persp_afd2;

static inline void persp__afd2_fwd(persp_afd2 *a)
{
    a->f += a->d1;
    a->d1 += a->d2;
}

static inline void persp__afd2_back(persp_afd2 *a)
{
    a->d1 -= a->d2;
    a->f -= a->d1;
}

static inline void persp__afd2_halve(persp_afd2 *a)
{
    a->d1 = 0.5 * a->d1 - 0.125 * a->d2;
    a->d2 *= 0.25;
}

static inline void persp__afd2_double(persp_afd2 *a)
{
    a->d1 = 2.0 * a->d1 + a->d2;
    a->d2 *= 4.0;
}

typedef enum persp_approx_kind {
    PERSP_APPROX_QUAD,   /* nodes 0, tau·L, L (tau = 1/2: the traditional quadratic) */
    PERSP_APPROX_PWQUAD, /* two quadratics: 0, L/4, L/2 and L/2, 3L/4, L */
    PERSP_APPROX_CUBIC   /* nodes 0, L/3, 2L/3, L */
} persp_approx_kind;

/* Approximates f on the samples s = 0, 1, ..., n−1 (L = n−1) and writes
 * out[k] ≈ f(k). tau is the inner anchor of PERSP_APPROX_QUAD as a fraction
 * of L (ignored otherwise; values outside (0, 1) mean 1/2). n = 1 and n = 2
 * are evaluated exactly; every node is exact up to rounding. Counts one
 * division per node evaluation plus the fitting and forward-difference work. */
PERSP_INTERNAL void persp__approx_span(const persp_rat1 *f, persp_approx_kind kind, double tau,
                                       int n, float *out, persp_opcount *ops);

/* The exact interpolation error f(s) − p(s) of the polynomial through the
 * nodes s[0..count−1] (formula above). */
double persp__approx_error(const persp_rat1 *f, const double *nodes, int count, double s);

/* Inner anchor (fraction of the line) of the shifted quadratic, [Romanyuk-PCF]
 * Table 4.2, for the values u0, u1 of a normalised texture coordinate at the
 * two ends of the line, taken as they are (no reduction modulo 1: outside
 * [0, 1] the table's "all other cases" gives 1/2). "→ 0" and "→ 1" are read
 * as within 0.05, the table's own margin. */
double persp__quad_shift_anchor(double u0, double u1);

/* Inner control point (x1, u1) of the quadratic Bézier of f on [0, L]: the
 * intersection of the tangents at s = 0 and s = L ([Romanyuk-PCF] (4.25)-(4.26));
 * bezier.c. */
PERSP_INTERNAL void persp__bezier_control(const persp_rat1 *f, double L, double *x1, double *u1);

/* Heckbert's form along row y from pixel x0 (k = 0 is the centre of x0):
 * u = (n1 + dn1·k)/(q + dq·k), v = (n2 + dn2·k)/(q + dq·k). */
typedef struct persp_span_rat {
    double n1, n2, q, dn1, dn2, dq;
} persp_span_rat;

/* 6 mul, 6 add (counted by the caller). */
static inline void persp__span_rat_init(const persp_rational *r, int x0, int y, persp_span_rat *s)
{
    double px = (double)x0 + 0.5, py = (double)y + 0.5;
    s->n1 = r->a * px + r->b * py + r->c;
    s->n2 = r->d * px + r->e * py + r->f;
    s->q = r->g * px + r->h * py + r->i;
    s->dn1 = r->a, s->dn2 = r->d, s->dq = r->g;
}

/* u, v at span position k (fractional allowed): 1 div, 5 mul, 3 add. */
static inline void persp__span_rat_at(const persp_span_rat *s, double k, double *u, double *v)
{
    double rq = 1.0 / (s->q + s->dq * k);
    *u = (s->n1 + s->dn1 * k) * rq;
    *v = (s->n2 + s->dn2 * k) * rq;
}

/* The 1-D rationals of u (which = 0) and v (which = 1) in k. */
static inline persp_rat1 persp__span_rat1(const persp_span_rat *s, int which)
{
    persp_rat1 f = {which ? s->dn2 : s->dn1, which ? s->n2 : s->n1, s->dq, s->q};
    return f;
}

#define PERSP_SPAN_RAT_INIT_OPS(ops)                                                         \
    do {                                                                                     \
        PERSP_OPS(ops, mul, 6);                                                              \
        PERSP_OPS(ops, add, 6);                                                              \
    } while (0)
#define PERSP_SPAN_RAT_AT_OPS(ops, count)                                                    \
    do {                                                                                     \
        PERSP_OPS(ops, div, (count));                                                        \
        PERSP_OPS(ops, mul, 5 * (count));                                                    \
        PERSP_OPS(ops, add, 3 * (count));                                                    \
    } while (0)

#endif
