/*
 * `subdiv:N` and `subdiv-quad:N` — exact values every N pixels, interpolated
 * in between ([CS300-TexMap] "Optimization": "perform the perspective-correct
 * division after a fixed interval (8/16/24 pixels), linearly interpolate the
 * values in between"; the classic Quake-era scheme).
 *
 * The nodes of a span of n pixels are k = 0, N, 2N, ... and k = n − 1 (the
 * last segment may be shorter). `subdiv:N` is linear between consecutive
 * nodes; `subdiv-quad:N` is the quadratic through a segment's ends and its
 * middle (k_j + len/2, a half-pixel position when len is odd). The ends are
 * shared between segments, so u is continuous along the span and exact at
 * every node. N ∈ {4, 8, 16, 32}, default 16.
 *
 * Error bound (exact remainder of interpolating a rational, poly.h): on a
 * segment of length ℓ ≤ N with ρ = Dmax/Dmin over the segment and
 * |u'|max = |n1·dq − dn1·q|/Dmin²,
 *     linear:     |Δu| ≤ |u'|max · ℓ · (ρ − 1) / 4
 *     quadratic:  |Δu| ≤ |u'|max · ℓ · (ρ − 1)² / (12·√3)
 * plus half an ulp of u for the float output.
 *
 * Cost, with s = ceil((n − 1)/N) segments:
 *   subdiv:N       per pixel 2 add (1 per coordinate); per node 1 div, 5 mul,
 *                  3 add; per segment 2 mul + 2 add (slopes, 1/ℓ is a
 *                  constant or one div for the short last segment).
 *   subdiv-quad:N  per pixel 4 add; per node and per segment middle 1 div,
 *                  5 mul, 3 add; per segment the fit (~30 mul, ~30 add).
 */
#include "core/internal.h"
#include "interp/methods.h"
#include "interp/poly.h"

#include <stdlib.h>
#include <string.h>

typedef struct subdiv_params {
    int step;
} subdiv_params;
PERSP_METHOD_BLOB_FITS(subdiv_params, persp_method_params);

static persp_status subdiv_parse(const char *text, persp_method_params *params)
{
    subdiv_params p = {16};
    if (text) {
        long v = 0;
        if (!persp__parse_long(text, 4, 32, &v) || !(v == 4 || v == 8 || v == 16 || v == 32))
            return PERSP_ERR_INVALID_ARGUMENT;
        p.step = (int)v;
    }
    memset(params, 0, sizeof *params);
    memcpy(params->bytes, &p, sizeof p);
    return PERSP_OK;
}

static int step_of(const persp_method_params *params)
{
    subdiv_params p;
    memcpy(&p, params->bytes, sizeof p);
    return p.step == 4 || p.step == 8 || p.step == 32 ? p.step : 16;
}

static void subdiv_span(const persp_rational *r, const persp_method_params *params,
                        const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                        persp_opcount *ops)
{
    (void)prep;
    if (n <= 0) return;
    const int N = step_of(params);
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    double ua, va;
    persp__span_rat_at(&s, 0.0, &ua, &va);
    PERSP_SPAN_RAT_AT_OPS(ops, 1);
    int k = 0;
    while (k < n - 1) {
        int len = n - 1 - k < N ? n - 1 - k : N;
        double ub, vb;
        persp__span_rat_at(&s, (double)(k + len), &ub, &vb);
        PERSP_SPAN_RAT_AT_OPS(ops, 1);
        /* 1/len: a power-of-two constant for full segments. */
        double inv = 1.0 / (double)len;
        if (len != N) PERSP_OPS(ops, div, 1);
        double du = (ub - ua) * inv, dv = (vb - va) * inv;
        PERSP_OPS(ops, mul, 2);
        PERSP_OPS(ops, add, 2);
        double u = ua, v = va;
        for (int j = 0; j < len; j++) {
            s1[k + j] = (float)u;
            s2[k + j] = (float)v;
            u += du;
            v += dv;
        }
        PERSP_OPS(ops, add, 2 * len);
        k += len;
        ua = ub, va = vb;
    }
    /* The last pixel is a node: its exact value, not the accumulated one. */
    s1[n - 1] = (float)ua;
    s2[n - 1] = (float)va;
}

static void subdiv_quad_span(const persp_rational *r, const persp_method_params *params,
                             const persp_method_prep *prep, int x0, int y, int n, float *s1,
                             float *s2, persp_opcount *ops)
{
    (void)prep;
    if (n <= 0) return;
    const int N = step_of(params);
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    double ua, va;
    persp__span_rat_at(&s, 0.0, &ua, &va);
    PERSP_SPAN_RAT_AT_OPS(ops, 1);
    int k = 0;
    while (k < n - 1) {
        int len = n - 1 - k < N ? n - 1 - k : N;
        double ub, vb, um, vm;
        double mid = (double)k + 0.5 * (double)len;
        persp__span_rat_at(&s, (double)(k + len), &ub, &vb);
        persp__span_rat_at(&s, mid, &um, &vm);
        PERSP_SPAN_RAT_AT_OPS(ops, 2);
        if (len == 1) {
            s1[k] = (float)ua;
            s2[k] = (float)va;
        } else {
            const double nodes[3] = {(double)k, mid, (double)(k + len)};
            const double yu[3] = {ua, um, ub}, yv[3] = {va, vm, vb};
            persp_poly pu, pv;
            persp_fd fd;
            persp__poly_interp(nodes, yu, 3, &pu, ops);
            persp__poly_interp(nodes, yv, 3, &pv, ops);
            persp__fd_init(&pu, (double)k, 1.0, &fd, ops);
            persp__fd_run(&fd, len, s1 + k, 1, ops);
            persp__fd_init(&pv, (double)k, 1.0, &fd, ops);
            persp__fd_run(&fd, len, s2 + k, 1, ops);
            s1[k] = (float)ua; /* node values exactly, not through the fit */
            s2[k] = (float)va;
        }
        k += len;
        ua = ub, va = vb;
    }
    s1[n - 1] = (float)ua;
    s2[n - 1] = (float)va;
}

const persp_method persp__method_subdiv = {
    .name = "subdiv",
    .params_help = "N (4|8|16|32, default 16)",
    .summary = "exact every N pixels, linear in between",
    .source = "[CS300-TexMap] \"Optimization\"",
    .cost = "2 add /px + (1 div, 7 mul, 5 add) per N px; 6 mul, 6 add /span",
    .parse = subdiv_parse,
    .span = subdiv_span,
};

const persp_method persp__method_subdiv_quad = {
    .name = "subdiv-quad",
    .params_help = "N (4|8|16|32, default 16)",
    .summary = "exact every N pixels, quadratic through each segment's ends and middle",
    .source = "[CS300-TexMap] \"Optimization\"; [Romanyuk-PCF] §4.4 (piecewise approximation)",
    .cost = "4 add /px + (2 div, ~40 mul, ~40 add) per N px; 6 mul, 6 add /span",
    .parse = subdiv_parse,
    .span = subdiv_quad_span,
};
