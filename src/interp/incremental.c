/*
 * `incremental` — Heckbert's rational form with the numerators and the
 * denominator advanced by additions ([Romaniuk-Incr] (3)-(4)):
 *
 *     u_n = w_n / v_n,   w_n = w_{n−1} + A1,   v_n = v_{n−1} + D          (4)
 *
 * ([Romaniuk-Incr] names the u-numerator w and the denominator v; here W1, W2 are
 * the numerators of u and v and Q the shared denominator, A1 = a, D = g of
 * Heckbert's planes). Variants:
 *
 *   incremental:k=N  N interleaved lanes, w_n = w_{n−k} + k·A1 ([Romaniuk-Incr] (5)
 *                    and its generalisation); lane j starts at w_j = w_0 + j·A1.
 *                    The lanes are independent, so they map onto SIMD lanes.
 *   incremental:bidir two chains, from the left with +A1 and from the right
 *                    with −A1 ([Romaniuk-Incr] Fig. 4), meeting in the middle.
 *
 * Identical images. Repeated addition in floating point depends on the order
 * of the additions, which the variants change. To make every variant produce
 * the same bits, the per-span start values and increments are first rounded
 * to a grid g = 2^(e−51) with 2^(e−1) ≤ M < 2^e, M = |w_0| + (n + 16)·|A1|
 * bounding every partial sum of the span. All values are then integer
 * multiples of g below 2^52·g, so every addition and every j·A1 (j ≤ 16) is
 * exact in double: w_n = w_0 + n·A1 exactly, whatever the order. Guarantee
 * (tested bit for bit): `incremental`, `incremental:k=N` (N = 1..16) and
 * `incremental:bidir` return identical floats for every span.
 *
 * Per pixel, as in `exact`: r = 1/(float)Q, u = (float)W1·r, v = (float)W2·r.
 *
 * Error bound: the grid rounding moves W1, W2, Q by at most (n + 1)·g/2
 * ≤ 2^-44·M (relative ~2^-44); the float conversions, reciprocal and products
 * add at most 4 roundings: |Δu| ≤ (4·2^-24 + 2^-40)·|u| + 2^-44·M/Q.
 *
 * Cost: per pixel 1 div, 2 mul, 3 add (plus 3 double→float conversions);
 * per span 6 mul + 6 add (planes at the first pixel), 6 mul + 6 add (grid
 * rounding), 3·k mul + 3·k add (lane starts) + 3 mul (k·A1).
 */
#include "core/internal.h"
#include "interp/methods.h"
#include "interp/poly.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define INC_MAX_LANES 16

typedef struct inc_params {
    int lanes; /* 1..16 */
    int bidir;
} inc_params;
PERSP_METHOD_BLOB_FITS(inc_params, persp_method_params);

static persp_status inc_parse(const char *text, persp_method_params *params)
{
    inc_params p = {1, 0};
    if (text && strcmp(text, "bidir") == 0) {
        p.bidir = 1;
    } else if (text) {
        if (strncmp(text, "k=", 2) != 0) return PERSP_ERR_INVALID_ARGUMENT;
        long k = 0;
        if (!persp__parse_long(text + 2, 1, INC_MAX_LANES, &k))
            return PERSP_ERR_INVALID_ARGUMENT;
        p.lanes = (int)k;
    }
    memset(params, 0, sizeof *params);
    memcpy(params->bytes, &p, sizeof p);
    return PERSP_OK;
}

/* Grid step for values bounded by m: every multiple of it below m is exact. */
static double grid_for(double m)
{
    int e = 0;
    (void)frexp(m, &e);
    return ldexp(1.0, e - 51);
}

static double snap(double x, double g) { return nearbyint(x / g) * g; }

typedef struct inc_state {
    double w1, w2, q;    /* at k = 0, on the grid */
    double a1, a2, dq;   /* increments, on the grid */
} inc_state;

static void inc_setup(const persp_rational *r, int x0, int y, int n, inc_state *st,
                      persp_opcount *ops)
{
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    double reach = (double)n + (double)INC_MAX_LANES;
    double g1 = grid_for(fabs(s.n1) + reach * fabs(s.dn1));
    double g2 = grid_for(fabs(s.n2) + reach * fabs(s.dn2));
    double gq = grid_for(fabs(s.q) + reach * fabs(s.dq));
    st->w1 = snap(s.n1, g1), st->a1 = snap(s.dn1, g1);
    st->w2 = snap(s.n2, g2), st->a2 = snap(s.dn2, g2);
    st->q = snap(s.q, gq), st->dq = snap(s.dq, gq);
    PERSP_OPS(ops, mul, 6);
    PERSP_OPS(ops, add, 6);
}

static inline void emit(double w1, double w2, double q, float *s1, float *s2)
{
    float rq = 1.0f / (float)q;
    *s1 = (float)w1 * rq;
    *s2 = (float)w2 * rq;
}

/* k interleaved lanes; inlined with a constant k for the common widths so
 * the lane loop becomes straight SIMD code. */
static inline void run_lanes(const inc_state *st, const int k, int n, float *s1, float *s2)
{
    double w1[INC_MAX_LANES], w2[INC_MAX_LANES], q[INC_MAX_LANES];
    for (int j = 0; j < k; j++) {
        double fj = (double)j;
        w1[j] = st->w1 + fj * st->a1;
        w2[j] = st->w2 + fj * st->a2;
        q[j] = st->q + fj * st->dq;
    }
    const double fk = (double)k;
    const double ka1 = fk * st->a1, ka2 = fk * st->a2, kdq = fk * st->dq;
    int p = 0;
    for (; p + k <= n; p += k) {
        for (int j = 0; j < k; j++) {
            float rq = 1.0f / (float)q[j];
            s1[p + j] = (float)w1[j] * rq;
            s2[p + j] = (float)w2[j] * rq;
            w1[j] += ka1;
            w2[j] += ka2;
            q[j] += kdq;
        }
    }
    for (int j = 0; j < k && p + j < n; j++) emit(w1[j], w2[j], q[j], &s1[p + j], &s2[p + j]);
}

static void run_bidir(const inc_state *st, int n, float *s1, float *s2)
{
    double fw1 = st->w1, fw2 = st->w2, fq = st->q;
    double last = (double)(n - 1);
    double bw1 = st->w1 + last * st->a1, bw2 = st->w2 + last * st->a2, bq = st->q + last * st->dq;
    int half = (n + 1) / 2;
    for (int i = 0; i < half; i++) {
        emit(fw1, fw2, fq, &s1[i], &s2[i]);
        fw1 += st->a1, fw2 += st->a2, fq += st->dq;
        int j = n - 1 - i;
        if (j >= half) {
            emit(bw1, bw2, bq, &s1[j], &s2[j]);
            bw1 -= st->a1, bw2 -= st->a2, bq -= st->dq;
        }
    }
}

static void inc_span(const persp_rational *r, const persp_method_params *params,
                     const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                     persp_opcount *ops)
{
    (void)prep;
    if (n <= 0) return;
    inc_params p;
    memcpy(&p, params->bytes, sizeof p);
    if (p.lanes < 1 || p.lanes > INC_MAX_LANES) p.lanes = 1;
    inc_state st;
    inc_setup(r, x0, y, n, &st, ops);
    if (p.bidir) {
        run_bidir(&st, n, s1, s2);
        PERSP_OPS(ops, mul, 3);
        PERSP_OPS(ops, add, 3);
    } else {
        switch (p.lanes) {
        case 1: run_lanes(&st, 1, n, s1, s2); break;
        case 2: run_lanes(&st, 2, n, s1, s2); break;
        case 4: run_lanes(&st, 4, n, s1, s2); break;
        case 8: run_lanes(&st, 8, n, s1, s2); break;
        case 16: run_lanes(&st, 16, n, s1, s2); break;
        default: run_lanes(&st, p.lanes, n, s1, s2); break;
        }
        PERSP_OPS(ops, mul, 3 * p.lanes + 3);
        PERSP_OPS(ops, add, 3 * p.lanes);
    }
    PERSP_OPS(ops, div, n);
    PERSP_OPS(ops, mul, 2 * n);
    PERSP_OPS(ops, add, 3 * n);
}

const persp_method persp__method_incremental = {
    .name = "incremental",
    .params_help = "k=N (1..16 lanes)|bidir",
    .summary = "Heckbert's form, numerators and denominator advanced by additions; lanes/bidir give identical images",
    .source = "[Romaniuk-Incr] (3)-(5), Fig. 4; Heckbert 1989 §2.3.2",
    .cost = "1 div, 2 mul, 3 add /px; 15 mul, 12 add (+3k mul, 3k add lanes) /span",
    .parse = inc_parse,
    .span = inc_span,
};
