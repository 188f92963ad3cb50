/*
 * `bezier` — quadratic Bézier approximation of the texture coordinate along
 * the span (seed 000 §4.7).
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
 * Su = u0 − 2u1 + u2 (the forward-difference constants of (4.31)-(4.34)).
 *
 * Finding t for the integer pixel x = i (both ways of §4.7):
 *
 *   bezier:step  (4.35)-(4.38): t_i = t_{i−1} + Δt_i. Δt_i starts from
 *                Δt_{i−1}, moves by ±dt until |x(t) − i| ≤ ε or the target
 *                is crossed, then corrects by ±dt/2, ±dt/4, … (t_kor, (4.37)),
 *                the sign chosen by the side of the target. dt = 2^-⌈log2 L⌉,
 *                ε = 1/64 pixel, at most 12 halvings (dt·x' ≤ 2 px, so 8
 *                suffice). Unlike (4.35), the tolerance is measured against
 *                the ideal position i, not x_{i−1} + 1, so it does not drift.
 *   bezier:quadt t(x) as the quadratic through (0, 0), (x(½), ½), (L, 1),
 *                evaluated by forward differences (2 add per pixel).
 *
 * Error bound: |Δu| ≤ E_B + |du/dx|max·ε_x, where E_B is the largest vertical
 * distance between the Bézier parabola and the hyperbola u = f(x) over the
 * span and ε_x the error of x(t) at the pixel (≤ 1/64 for step; for quadt
 * the interpolation error of t(x)). E_B has no short closed form; for small
 * depth variation it behaves like |Δu_span|·(ρ − 1)²/27 (ρ = Dmax/Dmin);
 * the tests evaluate E_B per span by dense sampling of the curve.
 *
 * Cost: per span 6 mul + 6 add (planes), 2 div + 10 mul + 6 add (ends),
 * 1 div + ~10 mul + ~12 add (control points). Per pixel:
 *   step   4 mul, 4 add for u, v (Horner in t) + per trial of t 2 mul,
 *          3 add, 2 cmp (typically 2-4 trials);
 *   quadt  4 mul, 6 add; per span + the fit of t(x) (~10 mul, ~15 add, 3 div).
 */
#include "core/internal.h"
#include "interp/methods.h"
#include "interp/poly.h"

#include <math.h>
#include <string.h>

#define BEZ_EPS (1.0 / 64.0)
#define BEZ_MAX_HALVINGS 12
#define BEZ_MAX_STEPS 4096

typedef struct bez_params {
    int quadt;
} bez_params;

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
    double u0, bu, su;     /* u(t) = u0 + t·(bu + t·su) */
    double v0, bv, sv;
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
    c->u0 = u0, c->bu = 2.0 * (u1 - u0), c->su = u0 - 2.0 * u1 + u2;
    c->v0 = v0, c->bv = 2.0 * (v1 - v0), c->sv = v0 - 2.0 * v1 + v2;
    PERSP_OPS(ops, div, 3);
    PERSP_OPS(ops, mul, 18);
    PERSP_OPS(ops, add, 17);
}

static inline double bez_x(const bez_curve *c, double t) { return t * (2.0 * c->x1 + t * c->sx); }

static inline void bez_uv(const bez_curve *c, double t, float *u, float *v)
{
    *u = (float)(c->u0 + t * (c->bu + t * c->su));
    *v = (float)(c->v0 + t * (c->bv + t * c->sv));
}

static void bez_step_run(const bez_curve *c, int n, float *s1, float *s2, persp_opcount *ops)
{
    double L = (double)(n - 1);
    int e = 0;
    (void)frexp(L, &e); /* 2^(e−1) ≤ L < 2^e */
    double dt = ldexp(1.0, -e + (L == ldexp(1.0, e - 1) ? 1 : 0));
    double t = 0.0, step = 0.0;
    uint64_t trials = 0;
    for (int i = 1; i < n - 1; i++) {
        const double X = (double)i;
        double xv = bez_x(c, t + step);
        trials++;
        /* Whole steps of dt until the target is reached or crossed. */
        int guard = 0; /* x(t) is monotone on [0, 1]; this only stops garbage input */
        if (xv < X - BEZ_EPS) {
            do {
                step += dt;
                xv = bez_x(c, t + step);
                trials++;
            } while (xv < X - BEZ_EPS && ++guard < BEZ_MAX_STEPS);
        } else if (xv > X + BEZ_EPS) {
            do {
                step -= dt;
                xv = bez_x(c, t + step);
                trials++;
            } while (xv > X + BEZ_EPS && ++guard < BEZ_MAX_STEPS);
        }
        /* The target now lies within dt of t + step: t_kor = ±dt/2 ± dt/4 … */
        double h = dt;
        for (int m = 0; m < BEZ_MAX_HALVINGS && fabs(xv - X) > BEZ_EPS; m++) {
            h *= 0.5;
            step += xv > X ? -h : h;
            xv = bez_x(c, t + step);
            trials++;
        }
        t += step;
        bez_uv(c, t, &s1[i], &s2[i]);
    }
    PERSP_OPS(ops, mul, 2 * trials);
    PERSP_OPS(ops, add, 3 * trials + (uint64_t)(n - 2));
    PERSP_OPS(ops, cmp, 2 * trials);
}

static void bez_quadt_run(const bez_curve *c, int n, float *s1, float *s2, persp_opcount *ops)
{
    double L = (double)(n - 1);
    const double xs[3] = {0.0, bez_x(c, 0.5), L};
    const double ts[3] = {0.0, 0.5, 1.0};
    persp_poly p;
    persp_fd fd;
    persp__poly_interp(xs, ts, 3, &p, ops);
    persp__fd_init(&p, 1.0, 1.0, &fd, ops);
    double t = fd.d[0], d1 = fd.d[1], d2 = fd.d[2];
    for (int i = 1; i < n - 1; i++) {
        bez_uv(c, t, &s1[i], &s2[i]);
        t += d1;
        d1 += d2;
    }
    PERSP_OPS(ops, add, 2 * (n - 2));
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
    /* End pixels are the curve's end points t = 0 and t = 1. */
    bez_uv(&c, 0.0, &s1[0], &s2[0]);
    bez_uv(&c, 1.0, &s1[n - 1], &s2[n - 1]);
    if (p.quadt)
        bez_quadt_run(&c, n, s1, s2, ops);
    else
        bez_step_run(&c, n, s1, s2, ops);
    PERSP_OPS(ops, mul, 4 * (n - 2));
    PERSP_OPS(ops, add, 4 * n);
}

const persp_method persp__method_bezier = {
    .name = "bezier",
    .params_help = "step|quadt (default step)",
    .summary = "quadratic Bezier through the span ends, inner point at the tangent intersection",
    .source = "seed 000 §4.7, (4.21)-(4.38)",
    .cost = "step: 4 mul, 5 add + ~3x(2 mul, 3 add, 2 cmp) /px; quadt: 4 mul, 6 add /px; 3 div /span",
    .parse = bez_parse,
    .span = bez_span,
};
