/*
 * `bezier` — quadratic Bézier approximation of the texture coordinate along
 * the span ([Romanyuk-PCF] §4.7), evaluated by forward differences.
 *
 * The curve r(t) = (1−t)²p0 + 2t(1−t)p1 + t²p2 (4.21) runs through the exact
 * end points p0 = (x0, u0), p2 = (x2, u2) and its inner control point p1 is
 * the intersection of the tangents of u = f(x) at both ends ((4.24)-(4.26)).
 * For f(x) = (α·x + β)/(γ·x + δ) with D(x) = γ·x + δ the intersection has a
 * closed form that needs neither (4.29)'s difference C0 − C2 nor A ≠ 0:
 * equating the tangents, the common factor (βγ − αδ) cancels and
 *
 *     D(x1) = 2·D0·D2/(D0 + D2)      (the harmonic mean of the end denominators)
 *     x1 = x0 + (x2 − x0)·D0/(D0 + D2),
 *     u1 = u0 + f'(x0)(x1 − x0) = u0 + (x2 − x0)·(α − γ·u0)/(D0 + D2).
 *
 * So x1 is the same for u and v, and one parameter t serves both
 * coordinates. This agrees with (4.29)-(4.30) wherever those are defined
 * (checked in the tests). Along the span x0 = 0, x2 = L = n − 1 (pixel index).
 *
 * x(t) = t·(2x1 + t·Sx), Sx = L − 2x1; u(t) = u0 + t·(2(u1 − u0) + t·Su),
 * Su = u0 − 2u1 + u2. Both ways of §4.7 to find the u of the integer pixel
 * x = i evaluate the curve by forward differences only:
 *
 *   bezier:step  (4.31)-(4.38). x(t), u(t), v(t) are walked together by the
 *                forward differences of a quadratic, (4.31)-(4.34) with
 *                step dt: d1 = dt·(2(x1 − x0) + dt·Sx) (the chapter's R_x),
 *                d2 = 2·dt²·Sx (its d_x); a step costs 2 additions per
 *                coordinate. For pixel i: whole steps of dt until
 *                x ≥ i − ε ((4.35)-(4.36)); then while |x − i| > ε the
 *                correction t_kor = ±dt/2 ± dt/4 … (4.37), the sign toward
 *                the target: each term halves the step, which rescales the
 *                differences exactly (adaptive forward differencing, poly.h:
 *                d1 ← d1/2 − d2/8, d2 ← d2/4) and steps once forward or back.
 *                After the pixel the step is doubled back to dt
 *                (d1 ← 2·d1 + d2, d2 ← 4·d2). dt = 2^-⌈log2 L⌉ so that
 *                dt·x'(t) ≤ 2 px; ε = 1/64 pixel, reached after at most 7
 *                halvings (12 allowed). The tolerance is measured against
 *                the ideal position i, not x_{i−1} + 1 as (4.35) does, so it
 *                does not drift. The chapter's reuse of the previous increment
 *                (4.38) is not kept: an increment Δt that is an arbitrary
 *                sum of ±dt/2^j has no forward differences obtainable by
 *                halving and doubling, so each pixel starts from whole steps
 *                of dt (typically 1-2) instead.
 *   bezier:quadt t(x) as the quadratic through (0, 0), (x(½), ½), (L, 1),
 *                t = c1·x + c2·x² (c0 = 0 exactly). Then u(x) = u(t(x)) is a
 *                quartic in x,
 *                    u = u0 + Bu·c1·x + (Bu·c2 + Su·c1²)·x²
 *                           + 2·Su·c1·c2·x³ + Su·c2²·x⁴,   Bu = 2(u1 − u0),
 *                evaluated from the span start by 4th-order forward
 *                differences with step 1 (persp__fd_init: Δ^j x⁴ = 1, 14,
 *                36, 24): 4 additions per pixel and coordinate.
 *
 * Both keep every difference in double: over 64 pixels the drift is
 * ≤ Σ_j C(k, j)·|r_j| + 2^-53·Σ_j C(k, j+1)·max|Δ^j| (poly.h), measured
 * ≤ 4.2e-15 of the span's range for quadt, while float differences drift up
 * to ~35 float ulps (2e-6 of the range), beyond the bound below where the
 * curve is nearly exact. In step each rescaling and each step rounds once
 * or twice in double; over a span the walked u differs from u(t) at the
 * walked t by at most 8.1e-15·(|u0| + |u1| + |u2|) (measured over 100 000
 * random spans, depth ratio up to 8, t tracked exactly alongside).
 *
 * Error bound: |Δu| ≤ E_B + |du/dx|max·ε_x (+ the float rounding of the
 * output), where E_B is the largest vertical distance between the Bézier
 * parabola and the hyperbola u = f(x) over the span and ε_x the error of x(t)
 * at the pixel (≤ 1/64 for step; for quadt the interpolation error of t(x)).
 * E_B has no short closed form; for small depth variation it behaves like
 * |Δu_span|·(ρ − 1)²/27 (ρ = Dmax/Dmin); the tests evaluate E_B per span by
 * dense sampling of the curve.
 *
 * Cost: per span 6 mul + 6 add (planes), 3 div, 18 mul, 17 add (ends and
 * control points). Per pixel:
 *   step   per whole step 6 add (2 per coordinate), per correction 12 add and
 *          15 mul that are exact scalings by powers of two (halving 9,
 *          doubling back 6; shifts in fixed point), 1-2 cmp per test, 2 add
 *          for the window; measured ~1.6 whole steps and 3.0-3.5 corrections
 *          per pixel on random triangles. Per span + 14 mul, 3 add.
 *   quadt  8 add (4 per coordinate); per span + x(½) (1 mul, 1 add), the fit
 *          of t(x) (3 div, 3 mul, 9 add), the quartics (15 mul, 2 add) and
 *          their differences (2 × 51 mul, 19 add).
 */
#include "core/internal.h"
#include "interp/methods.h"
#include "interp/poly.h"

#include <math.h>
#include <string.h>

#define BEZ_EPS (1.0 / 64.0)
#define BEZ_MAX_HALVINGS 12
#define BEZ_MAX_STEPS 4096 /* whole steps per pixel; only garbage input needs more */

typedef struct bez_params {
    int quadt;
} bez_params;
PERSP_METHOD_BLOB_FITS(bez_params, persp_method_params);

static persp_status bez_parse(const char *text, persp_method_params *params)
{
    bez_params p = {0};
    if (text) {
        if (strcmp(text, "step") == 0)
            p.quadt = 0;
        else if (strcmp(text, "quadt") == 0)
            p.quadt = 1;
        else
            return PERSP_ERR_INVALID_ARGUMENT;
    }
    memset(params, 0, sizeof *params);
    memcpy(params->bytes, &p, sizeof p);
    return PERSP_OK;
}

void persp__bezier_control(const persp_rat1 *f, double L, double *x1, double *u1)
{
    double d0 = f->delta, d2 = f->gamma * L + f->delta;
    double u0 = f->beta / d0;
    double sum = d0 + d2;
    *x1 = L * d0 / sum;
    *u1 = u0 + L * (f->alpha - f->gamma * u0) / sum;
}

typedef struct bez_curve {
    double x1, sx;         /* x(t) = t·(2·x1 + t·sx) */
    double u0, bu, su, u2; /* u(t) = u0 + t·(bu + t·su), u(1) = u2 */
    double v0, bv, sv, v2;
} bez_curve;

static void bez_setup(const persp_span_rat *s, int n, bez_curve *c, persp_opcount *ops)
{
    double L = (double)(n - 1);
    double d0 = s->q, d2 = s->q + s->dq * L;
    double rd0 = 1.0 / d0, rd2 = 1.0 / d2, rsum = 1.0 / (d0 + d2);
    double u0 = s->n1 * rd0, v0 = s->n2 * rd0;
    double u2 = (s->n1 + s->dn1 * L) * rd2, v2 = (s->n2 + s->dn2 * L) * rd2;
    double x1 = L * d0 * rsum;
    double u1 = u0 + L * (s->dn1 - s->dq * u0) * rsum;
    double v1 = v0 + L * (s->dn2 - s->dq * v0) * rsum;
    c->x1 = x1;
    c->sx = L - 2.0 * x1;
    c->u0 = u0, c->bu = 2.0 * (u1 - u0), c->su = u0 - 2.0 * u1 + u2, c->u2 = u2;
    c->v0 = v0, c->bv = 2.0 * (v1 - v0), c->sv = v0 - 2.0 * v1 + v2, c->v2 = v2;
    PERSP_OPS(ops, div, 3);
    PERSP_OPS(ops, mul, 18);
    PERSP_OPS(ops, add, 17);
}

/* The forward differences of a + b·t + s·t² at t = 0 for the step dt
 * ((4.31), (4.33)): d1 = dt·(b + dt·s), d2 = 2·dt²·s. */
static persp_afd2 bez_afd_start(double a, double b, double s, double dt, double dt2)
{
    persp_afd2 d = {a, dt * (b + dt * s), 2.0 * dt2 * s};
    return d;
}

static void bez_step_run(const bez_curve *c, int n, float *s1, float *s2, persp_opcount *ops)
{
    double L = (double)(n - 1);
    int e = 0;
    (void)frexp(L, &e); /* 2^(e−1) ≤ L < 2^e */
    const double dt = ldexp(1.0, -e + (L == ldexp(1.0, e - 1) ? 1 : 0));
    const double dt2 = dt * dt;
    persp_afd2 x = bez_afd_start(0.0, 2.0 * c->x1, c->sx, dt, dt2);
    persp_afd2 u = bez_afd_start(c->u0, c->bu, c->su, dt, dt2);
    persp_afd2 v = bez_afd_start(c->v0, c->bv, c->sv, dt, dt2);
    PERSP_OPS(ops, mul, 14);
    PERSP_OPS(ops, add, 3);
    uint64_t moves = 0, halvings = 0, cmps = 0;
    double lo = 1.0 - BEZ_EPS, hi = 1.0 + BEZ_EPS; /* the window of (4.35) around x = i */
    for (int i = 1; i < n - 1; i++) {
        /* Whole steps of dt until the lower bound of (4.35) is reached.
         * x(t) is monotone on [0, 1]; the guard only stops garbage input. */
        int guard = 0;
        while (x.f < lo && guard < BEZ_MAX_STEPS) {
            persp__afd2_fwd(&x), persp__afd2_fwd(&u), persp__afd2_fwd(&v);
            guard++;
        }
        moves += (uint64_t)guard;
        cmps += (uint64_t)guard + 1;
        /* t_kor = ±dt/2 ± dt/4 … (4.37): halve the step, move toward the
         * target; the target stays within the current step of t. */
        int level = 0;
        for (;;) {
            int dir;
            cmps++;
            if (x.f > hi) {
                dir = -1;
            } else {
                cmps++;
                if (x.f >= lo) break;
                dir = 1;
            }
            if (level == BEZ_MAX_HALVINGS) break;
            persp__afd2_halve(&x), persp__afd2_halve(&u), persp__afd2_halve(&v);
            level++;
            if (dir > 0)
                persp__afd2_fwd(&x), persp__afd2_fwd(&u), persp__afd2_fwd(&v);
            else
                persp__afd2_back(&x), persp__afd2_back(&u), persp__afd2_back(&v);
        }
        s1[i] = (float)u.f;
        s2[i] = (float)v.f;
        moves += (uint64_t)level;
        halvings += (uint64_t)level;
        /* Back to the step dt for the next pixel's whole steps. */
        for (; level > 0; level--)
            persp__afd2_double(&x), persp__afd2_double(&u), persp__afd2_double(&v);
        lo += 1.0;
        hi += 1.0;
    }
    /* Per move 2 add per coordinate; per halving 3 mul, 1 add and per
     * doubling 2 mul, 1 add per coordinate (poly.h). */
    PERSP_OPS(ops, add, 6 * moves + 6 * halvings + 2 * (uint64_t)(n - 2));
    PERSP_OPS(ops, mul, 15 * halvings);
    PERSP_OPS(ops, cmp, cmps);
}

/* u(t(x)) with t(x) = c1·x + c2·x²: the quartic in x (c[0..4]). */
static persp_poly bez_quartic(double a, double b, double s, double c1, double c2, double c11,
                              double c12, double c22)
{
    persp_poly q = {4, {a, b * c1, b * c2 + s * c11, 2.0 * s * c12, s * c22}};
    return q;
}

static void bez_quadt_run(const bez_curve *c, int n, float *s1, float *s2, persp_opcount *ops)
{
    double L = (double)(n - 1);
    const double xs[3] = {0.0, c->x1 + 0.25 * c->sx, L}; /* x(½) */
    const double ts[3] = {0.0, 0.5, 1.0};
    PERSP_OPS(ops, mul, 1);
    PERSP_OPS(ops, add, 1);
    persp_poly t;
    persp__poly_interp(xs, ts, 3, &t, ops);
    /* The node (0, 0) makes t.c[0] = 0 exactly (Newton form with s0 = 0, y0 = 0). */
    const double c1 = t.c[1], c2 = t.c[2];
    const double c11 = c1 * c1, c12 = c1 * c2, c22 = c2 * c2;
    persp_poly qu = bez_quartic(c->u0, c->bu, c->su, c1, c2, c11, c12, c22);
    persp_poly qv = bez_quartic(c->v0, c->bv, c->sv, c1, c2, c11, c12, c22);
    PERSP_OPS(ops, mul, 3 + 2 * 6);
    PERSP_OPS(ops, add, 2);
    persp_fd fd;
    /* Pixels 0..n−2 from x = 0; pixel 0 is u0 itself, pixel n−1 the exact end. */
    persp__fd_init(&qu, 0.0, 1.0, &fd, ops);
    persp__fd_run(&fd, n - 1, s1, 1, ops);
    persp__fd_init(&qv, 0.0, 1.0, &fd, ops);
    persp__fd_run(&fd, n - 1, s2, 1, ops);
}

static void bez_span(const persp_rational *r, const persp_method_params *params,
                     const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                     persp_opcount *ops)
{
    (void)prep;
    if (n <= 0) return;
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    if (n <= 2) {
        for (int k = 0; k < n; k++) {
            double u, v;
            persp__span_rat_at(&s, (double)k, &u, &v);
            s1[k] = (float)u;
            s2[k] = (float)v;
        }
        PERSP_SPAN_RAT_AT_OPS(ops, n);
        return;
    }
    bez_params p;
    memcpy(&p, params->bytes, sizeof p);
    bez_curve c;
    bez_setup(&s, n, &c, ops);
    if (p.quadt) {
        bez_quadt_run(&c, n, s1, s2, ops);
    } else {
        s1[0] = (float)c.u0;
        s2[0] = (float)c.v0;
        bez_step_run(&c, n, s1, s2, ops);
    }
    /* The last pixel is the curve's end point t = 1. */
    s1[n - 1] = (float)c.u2;
    s2[n - 1] = (float)c.v2;
}

const persp_method persp__method_bezier = {
    .name = "bezier",
    .params_help = "step|quadt (default step)",
    .summary = "quadratic Bezier through the span ends, inner point at the tangent intersection, "
               "by forward differences",
    .source = "[Romanyuk-PCF] §4.7, (4.21)-(4.38)",
    .cost = "step: 6 add /whole step, 12 add + 15 mul (2^k scalings) /correction, ~1.6 steps + "
            "~3.3 corrections /px, 3 div /span; quadt: 8 add /px, 6 div /span",
    .parse = bez_parse,
    .span = bez_span,
};
