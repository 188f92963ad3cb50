/*
 * The two reference methods: `affine` (screen-space linear, the classical
 * non-perspective baseline) and `exact` (Heckbert 1989 §2.3.2: interpolate
 * 1/w, u/w, v/w linearly in screen space, one reciprocal per pixel).
 */
#include "core/fmath.h"
#include "interp/method.h"
#include "interp/methods.h"

/* Affine: u is the plane through the three vertex values of u itself, i.e.
 * linear in screen space, ignoring w. Setup solves that plane per triangle. */
typedef struct affine_prep {
    double ux, uy, uc, vx, vy, vc;
} affine_prep;
PERSP_METHOD_PREP_FITS(affine_prep);

static void affine_prepare(const persp_rational *r, const persp_rational_vertices *v,
                           const persp_method_params *params, persp_method_prep *prep, persp_opcount *ops)
{
    (void)r, (void)params;
    affine_prep *p = (affine_prep *)prep->bytes;
    persp__plane_through(v->x, v->y, v->s1, &p->ux, &p->uy, &p->uc);
    persp__plane_through(v->x, v->y, v->s2, &p->vx, &p->vy, &p->vc);
    PERSP_OPS(ops, div, 2);
    PERSP_OPS(ops, mul, 14);
    PERSP_OPS(ops, add, 14);
}

static void affine_span(const persp_rational *r, const persp_method_params *params,
                        const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                        persp_opcount *ops)
{
    (void)r, (void)params;
    const affine_prep *p = (const affine_prep *)prep->bytes;
    double px = x0 + 0.5, py = y + 0.5;
    float u = (float)(p->ux * px + p->uy * py + p->uc);
    float v = (float)(p->vx * px + p->vy * py + p->vc);
    float du = (float)p->ux, dv = (float)p->vx;
    for (int k = 0; k < n; k++) {
        s1[k] = u + (float)k * du;
        s2[k] = v + (float)k * dv;
    }
    PERSP_OPS(ops, mul, 4 + 2 * n);
    PERSP_OPS(ops, add, 4 + 2 * n);
}

/* Exact: numerators and denominator start at the span's first pixel centre
 * and are advanced as k·step from that start (not by repeated addition), so
 * the only rounding per pixel is one multiply-add per plane and the divide. */
PERSP_SIMD_CLONES static void exact_span(const persp_rational *r, const persp_method_params *params,
                       const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                       persp_opcount *ops)
{
    (void)params, (void)prep;
    double px = x0 + 0.5, py = y + 0.5;
    float U = (float)(r->a * px + r->b * py + r->c);
    float V = (float)(r->d * px + r->e * py + r->f);
    float Q = (float)(r->g * px + r->h * py + r->i);
    float dU = (float)r->a, dV = (float)r->d, dQ = (float)r->g;
    for (int k = 0; k < n; k++) {
        float fk = (float)k;
        float rq = 1.0f / (Q + fk * dQ);
        s1[k] = (U + fk * dU) * rq;
        s2[k] = (V + fk * dV) * rq;
    }
    PERSP_OPS(ops, div, n);
    PERSP_OPS(ops, mul, 6 + 5 * n);
    PERSP_OPS(ops, add, 6 + 3 * n);
}

const persp_method persp__method_affine = {
    .name = "affine",
    .params_help = "",
    .summary = "u, v linear in screen space (no perspective correction; the baseline)",
    .source = "[Romanyuk-PCF] §4.4; [CS300-TexMap] \"perspective-correct interpolation\"",
    .cost = "0 div, 2 mul, 2 add /px",
    .prepare = affine_prepare,
    .span = affine_span,
};

const persp_method persp__method_exact = {
    .name = "exact",
    .params_help = "",
    .summary = "1/w, u/w, v/w linear in screen space, one reciprocal per pixel (reference)",
    .source = "Heckbert 1989 §2.3.2; [Romanyuk-PCF] §4.4, [Romaniuk-Incr] (1)-(2)",
    .cost = "1 div, 5 mul, 3 add /px",
    .span = exact_span,
};
