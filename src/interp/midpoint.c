/*
 * `midpoint` — the improved Barenbrug division-free method ([Romanyuk-PCF] §4.5,
 * (4.10)-(4.15)), and its fixed-point model `midpoint:int`.
 *
 * [Romanyuk-PCF] §4.5 replaces the divisions of u = (a·x+b·y+c)/(g·x+h·y+i)
 * (formula (4.8)) by a search: u walks a lattice of step Δu = 1/P (P texels
 * along the axis) and is accepted when it lies within half a step of the
 * exact value, condition (4.11). Multiplying (4.11) by E = 2(g·x+h·y+i) > 0
 * turns it into two sign tests on quantities linear in x, y and u, so that
 * moving one pixel or one lattice step changes them by additions only.
 *
 * Derivation (in texel units, t = P·u_exact = N/D, N = P·(a·x+b·y+c),
 * D = g·x+h·y+i, at the pixel centre x = X2/2, y = Y2/2 with the odd
 * integers X2 = 2·px+1, Y2 = 2·py+1):
 *
 *   E  = 2D = g·X2 + h·Y2 + 2i,     N2 = 2N = A·X2 + B·Y2 + 2C   (A = P·a, ...)
 *   lattice value m = n + o  (o = 1/2: texel centres, the default;
 *                              o = 0: texel edges as printed in the chapter)
 *   M  = 2m = 2n + 2o  (an integer)
 *   W  = M·E − 2·N2 + E            (twice the chapter's W of (4.13), in texels)
 *   Q  = W − 2E                    (twice the chapter's Q)
 *   accept n  ⇔  W > 0 and Q ≤ 0  ⇔  m − 1/2 ≤ t < m + 1/2, read as
 *                                    n = floor(t)       for o = 1/2,
 *                                    n = floor(t + 1/2) for o = 0.
 *   pixel step x → x+1:  E += 2g;  W += T − K,  T = 2g·M,  K = 4A − 2g
 *   lattice step n → n±1: M ±= 2;  W ±= 2E;  T ±= 4g          ((4.14), (4.15))
 *
 * T is the chapter's "2g·u" term kept as a running sum, so the per-pixel work is
 * additions and comparisons only (the chapter's own step multiplies 2g·u).
 *
 * Texel centres by default: with o = 1/2 the accepted value is the centre of
 * the texel containing the exact coordinate, so nearest sampling picks the
 * same texel as the exact form. The chapter's lattice (o = 0, `midpoint:edge`)
 * rounds to the nearest texel *edge*, which makes nearest sampling pick the
 * neighbouring texel for half of the positions. The strictness of the two
 * tests is swapped against (4.13) so that o = 1/2 gives floor(), matching
 * GL_NEAREST on the boundaries.
 *
 * Per-span start: one reciprocal 1/(2E) and floor() give the first n for u and
 * v; the search loop then corrects rounding of that guess. A pixel whose search
 * needs more than MP_ITER_CAP steps (strong minification: many texels per
 * pixel) is re-seeded the same way, so the cost per pixel stays bounded.
 *
 * Cost (counted in ops): per span 1 div, 15 mul, 15 add; per pixel 5 add and
 * 4 cmp for the two coordinates, plus 3 add + 1 cmp per lattice step actually
 * taken, plus 2 mul + 2 add to turn the lattice index into a normalised
 * coordinate (hardware would deliver n itself). Re-seeds add 1 div, 7 mul,
 * 7 add each.
 *
 * Error bound: |P·s − t| ≤ 1/2 texel by construction (exact decisions), plus
 * the float rounding of the output (≤ 2^-24 relative); the double-precision
 * decision variables drift by ~64·2^-53 of their magnitude over a span.
 *
 * `midpoint:int` (the bit-accurate hardware model) runs the same recurrences
 * in 64-bit two's-complement integers. Fixed-point format, per triangle with
 * inclusive pixel bounding box [0, xmax] × [0, ymax] (xmax, ymax < 2^15):
 *   Xb = 2·xmax + 2, Yb = 2·ymax + 2   (bounds of X2, Y2 over the box)
 *   s  = 42 − e, where 2^(e−1) ≤ |g|·Xb + |h|·Yb + 2|i| < 2^e
 *   G, H, I = round(g·2^s), round(h·2^s), round(i·2^s)    (so |E| < 2^42)
 *   A, B, C = round(P1·a·2^s), round(P1·b·2^s), round(P1·c·2^s); v likewise
 *   (round = llround: half away from zero); valid when
 *   |A|·Xb + |B|·Yb + 2|C| < 2^58 and the lattice index |n| < 2^16.
 * Register widths that suffice: E 43 bits, N2 59 bits, W 62 bits, T 60 bits,
 * K 61 bits, n 18 bits. W and Q stay within (0, 2E] after each pixel, so a design
 * that knows its per-pixel texel step is small may keep W modulo 2^48: the
 * start value M·E − 2·N2 + E is exact modulo 2^48 and fits once reduced.
 * The first n is floor_div(2·N2 + (1 − 2o)·E, 2E) (exact integer division,
 * two per span: one for u, one for v). Spans outside these limits (or with
 * E ≤ 0) are computed by the double-precision path.
 * The integer path gives exactly the same outputs as the double path whenever
 * the plane coefficients are representable in the format above and every
 * intermediate of the double path is below 2^53 (then both take identical
 * decisions: scaling by 2^s is exact and sign tests are scale-invariant);
 * persp__midpoint_quantize() builds such planes for the tests.
 */
#include "interp/method.h"
#include "interp/methods.h"
#include "persp_analysis.h"

#include <math.h>
#include <string.h>

#define MP_ITER_CAP 32
#define MP_DEN_BITS 42
#define MP_N_LIMIT ((int64_t)1 << 16)

typedef struct mp_params {
    int fixed; /* `int`: the fixed-point model */
    int edge;  /* `edge`: the chapter's lattice u = n·Δu instead of texel centres */
} mp_params;
PERSP_METHOD_BLOB_FITS(mp_params, persp_method_params);

typedef struct mp_fixed {
    int64_t G, H, I;
    int64_t A[2], B[2], C[2];
    int64_t X2max, Y2max; /* pixel-centre coordinates the format covers: X2 < X2max */
    int ok;
} mp_fixed;
PERSP_METHOD_PREP_FITS(mp_fixed);

static persp_status mp_parse(const char *text, persp_method_params *params)
{
    mp_params p = {0, 0};
    if (text) {
        const char *s = text;
        while (*s) {
            size_t len = strcspn(s, ",");
            /* A repeated flag is a typo, not a request twice over. */
            if (len == 3 && strncmp(s, "int", 3) == 0 && !p.fixed)
                p.fixed = 1;
            else if (len == 4 && strncmp(s, "edge", 4) == 0 && !p.edge)
                p.edge = 1;
            else
                return PERSP_ERR_INVALID_ARGUMENT;
            s += len;
            if (*s == ',') {
                s++;
                if (!*s) return PERSP_ERR_INVALID_ARGUMENT;
            }
        }
        if (!p.fixed && !p.edge) return PERSP_ERR_INVALID_ARGUMENT;
    }
    memset(params, 0, sizeof *params);
    memcpy(params->bytes, &p, sizeof p);
    return PERSP_OK;
}

static mp_params mp_get_params(const persp_method_params *params)
{
    mp_params p = {0, 0};
    if (params) memcpy(&p, params->bytes, sizeof p);
    return p;
}

/* The rational form at a pixel, or 0 where its denominator is not positive
 * (outside any visible triangle): no division by zero on bad input. */
static void mp_eval(const persp_rational *r, int x, int y, float *s1, float *s2)
{
    double px = x + 0.5, py = y + 0.5, q = r->g * px + r->h * py + r->i;
    if (!(q > 0.0) || !isfinite(q)) {
        *s1 = *s2 = 0.0f;
        return;
    }
    *s1 = (float)((r->a * px + r->b * py + r->c) / q);
    *s2 = (float)((r->d * px + r->e * py + r->f) / q);
}

static double mp_scale(float s) { return (s > 0.0f && isfinite(s)) ? (double)s : 1.0; }

static int64_t mp_floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

/* Bounds of the doubled pixel-centre coordinates X2 = 2x+1 the format covers:
 * the triangle's bounding box (at least one pixel), below 2^15 pixels. */
static int mp_coord_bounds(const persp_rational *r, int64_t *X2max, int64_t *Y2max)
{
    int xm = r->xmax > 0 ? r->xmax : 0, ym = r->ymax > 0 ? r->ymax : 0;
    if (xm >= (1 << 15) || ym >= (1 << 15)) return 0;
    *X2max = 2 * (int64_t)xm + 2;
    *Y2max = 2 * (int64_t)ym + 2;
    return 1;
}

static int mp_fixed_coef(double v, int s, double limit, int64_t *out)
{
    double x = ldexp(v, s);
    if (!(fabs(x) < limit)) return 0;
    *out = (int64_t)llround(x);
    return 1;
}

static void mp_quantize_fixed(const persp_rational *r, int den_bits, mp_fixed *fx, int *sout)
{
    memset(fx, 0, sizeof *fx);
    int64_t Xb, Yb;
    if (!mp_coord_bounds(r, &Xb, &Yb)) return;
    double mx = fabs(r->g) * (double)Xb + fabs(r->h) * (double)Yb + 2.0 * fabs(r->i);
    if (!(mx > 0.0) || !isfinite(mx)) return;
    int e, s;
    (void)frexp(mx, &e);
    s = den_bits - e; /* |E| < 2^den_bits over the box */
    const double P[2] = {mp_scale(r->scale1), mp_scale(r->scale2)};
    const double num[2][3] = {{r->a, r->b, r->c}, {r->d, r->e, r->f}};
    const double L43 = 8796093022208.0, L58 = 288230376151691776.0;
    int ok = mp_fixed_coef(r->g, s, L43, &fx->G) && mp_fixed_coef(r->h, s, L43, &fx->H) &&
             mp_fixed_coef(r->i, s, L43, &fx->I);
    for (int c = 0; c < 2 && ok; c++) {
        ok = mp_fixed_coef(P[c] * num[c][0], s, L58, &fx->A[c]) &&
             mp_fixed_coef(P[c] * num[c][1], s, L58, &fx->B[c]) &&
             mp_fixed_coef(P[c] * num[c][2], s, L58, &fx->C[c]);
        /* |N2| = |A·X2 + B·Y2 + 2C| < 2^58 over the box. */
        ok = ok && fabs((double)fx->A[c]) * (double)Xb + fabs((double)fx->B[c]) * (double)Yb +
                           2.0 * fabs((double)fx->C[c]) < L58;
    }
    fx->X2max = Xb, fx->Y2max = Yb;
    fx->ok = ok;
    if (sout) *sout = s;
}

void persp__midpoint_quantize(const persp_rational *r, int den_bits, persp_rational *out)
{
    mp_fixed fx;
    int s = 0;
    *out = *r;
    mp_quantize_fixed(r, den_bits, &fx, &s);
    if (!fx.ok) return;
    const double P[2] = {mp_scale(r->scale1), mp_scale(r->scale2)};
    out->g = ldexp((double)fx.G, -s);
    out->h = ldexp((double)fx.H, -s);
    out->i = ldexp((double)fx.I, -s);
    out->a = ldexp((double)fx.A[0], -s) / P[0];
    out->b = ldexp((double)fx.B[0], -s) / P[0];
    out->c = ldexp((double)fx.C[0], -s) / P[0];
    out->d = ldexp((double)fx.A[1], -s) / P[1];
    out->e = ldexp((double)fx.B[1], -s) / P[1];
    out->f = ldexp((double)fx.C[1], -s) / P[1];
}

/* ------------------------------------------------------- double-precision path */

typedef struct mp_coord {
    double A, B, C2; /* P·a, P·b, 2·P·c */
    double W, T, K;
    int64_t n;
} mp_coord;

/* Largest |t| the double path seeds from; beyond it the lattice index would
 * not be an exact integer in double. */
#define MP_T_LIMIT 1.0e15

static int64_t mp_seed_n(double N2, double rE, double half_off, persp_opcount *ops)
{
    /* First lattice index: floor(t + 1/2 − o) with t = N2/E, from the span's
     * one reciprocal rE = 1/E; the search loop corrects its rounding. */
    double t = N2 * rE + half_off;
    PERSP_OPS(ops, mul, 1);
    PERSP_OPS(ops, add, 1);
    if (!(fabs(t) < MP_T_LIMIT)) t = t > 0 ? MP_T_LIMIT : -MP_T_LIMIT;
    return (int64_t)floor(t);
}

static void mp_coord_start(mp_coord *c, double g, double N2, double E, double rE, int o2,
                           double half_off, persp_opcount *ops)
{
    c->n = mp_seed_n(N2, rE, half_off, ops);
    double M = 2.0 * (double)c->n + o2;
    c->W = M * E - 2.0 * N2 + E;
    c->T = 2.0 * g * M;
    c->K = 4.0 * c->A - 2.0 * g;
    PERSP_OPS(ops, mul, 6);
    PERSP_OPS(ops, add, 4);
}

/* Lattice search at one pixel; returns 0 if it ran past the cap. */
static int mp_coord_search(mp_coord *c, double twoE, double g4, persp_opcount *ops)
{
    int it = 0;
    while (c->W <= 0.0 && it < MP_ITER_CAP) {
        c->n++, c->W += twoE, c->T += g4, it++;
    }
    while (c->W > twoE && it < MP_ITER_CAP) {
        c->n--, c->W -= twoE, c->T -= g4, it++;
    }
    PERSP_OPS(ops, add, 3 * it);
    PERSP_OPS(ops, cmp, 2 + it);
    return it < MP_ITER_CAP || (c->W > 0.0 && c->W <= twoE);
}

static void mp_span_double(const persp_rational *r, int edge, int x0, int y, int n, float *s1,
                           float *s2, persp_opcount *ops)
{
    const double P[2] = {mp_scale(r->scale1), mp_scale(r->scale2)};
    const int o2 = edge ? 0 : 1;
    const double half_off = edge ? 0.5 : 0.0;
    const double X2 = 2.0 * x0 + 1.0, Y2 = 2.0 * y + 1.0;
    const double g = r->g, g2 = 2.0 * g, g4 = 4.0 * g;
    double E = g * X2 + r->h * Y2 + 2.0 * r->i;
    const double Eend = E + g2 * (double)(n - 1);
    mp_coord c[2];
    const double num[2][3] = {{r->a, r->b, r->c}, {r->d, r->e, r->f}};
    float *out[2] = {s1, s2};
    PERSP_OPS(ops, mul, 6);
    PERSP_OPS(ops, add, 5);
    PERSP_OPS(ops, cmp, 2);
    if (!(E > 0.0 && Eend > 0.0 && isfinite(E) && isfinite(Eend))) {
        /* The denominator is not positive over this span: the pixels are not
         * inside a visible triangle. Fill exact values without searching. */
        for (int k = 0; k < n; k++) mp_eval(r, x0 + k, y, &s1[k], &s2[k]);
        PERSP_OPS(ops, div, n);
        PERSP_OPS(ops, mul, 6 * n);
        PERSP_OPS(ops, add, 6 * n);
        return;
    }
    const double rE0 = 1.0 / E;
    PERSP_OPS(ops, div, 1);
    for (int j = 0; j < 2; j++) {
        c[j].A = P[j] * num[j][0];
        c[j].B = P[j] * num[j][1];
        c[j].C2 = 2.0 * P[j] * num[j][2];
        double N2 = c[j].A * X2 + c[j].B * Y2 + c[j].C2;
        mp_coord_start(&c[j], g, N2, E, rE0, o2, half_off, ops);
    }
    PERSP_OPS(ops, mul, 8);
    PERSP_OPS(ops, add, 4);
    const double inv[2] = {1.0 / P[0], 1.0 / P[1]};
    const double off = 0.5 * o2;
    for (int k = 0; k < n; k++) {
        if (k > 0) {
            E += g2;
            c[0].W += c[0].T - c[0].K;
            c[1].W += c[1].T - c[1].K;
        }
        const double twoE = 2.0 * E;
        for (int j = 0; j < 2; j++) {
            if (!mp_coord_search(&c[j], twoE, g4, ops)) {
                /* Strong minification: re-seed from a division at this pixel. */
                double N2 = c[j].A * (X2 + 2.0 * k) + c[j].B * Y2 + c[j].C2;
                PERSP_OPS(ops, mul, 2);
                PERSP_OPS(ops, add, 3);
                PERSP_OPS(ops, div, 1);
                mp_coord_start(&c[j], g, N2, E, 1.0 / E, o2, half_off, ops);
                (void)mp_coord_search(&c[j], twoE, g4, ops);
            }
            out[j][k] = (float)(((double)c[j].n + off) * inv[j]);
        }
    }
    PERSP_OPS(ops, add, 5 * (n - 1) + 2 * n);
    PERSP_OPS(ops, mul, 2 * n);
}

/* ----------------------------------------------------------- fixed-point path */

typedef struct mp_icoord {
    int64_t W, T, K, n;
} mp_icoord;

/* Returns 0 (and leaves W, T, K unset) when the first index is outside the
 * format's texel range, before any product could overflow. */
static int mp_icoord_start(mp_icoord *c, int64_t G, int64_t A, int64_t N2, int64_t E, int o2,
                           persp_opcount *ops)
{
    c->n = mp_floor_div(2 * N2 + (int64_t)(1 - o2) * E, 2 * E);
    PERSP_OPS(ops, div, 1);
    if (c->n <= -MP_N_LIMIT || c->n >= MP_N_LIMIT) return 0;
    int64_t M = 2 * c->n + o2;
    c->W = M * E - 2 * N2 + E;
    c->T = 2 * G * M;
    c->K = 4 * A - 2 * G;
    PERSP_OPS(ops, mul, 4);
    PERSP_OPS(ops, add, 6);
    return 1;
}

static int mp_icoord_search(mp_icoord *c, int64_t twoE, int64_t G4, persp_opcount *ops)
{
    int it = 0;
    while (c->W <= 0 && it < MP_ITER_CAP) {
        c->n++, c->W += twoE, c->T += G4, it++;
    }
    while (c->W > twoE && it < MP_ITER_CAP) {
        c->n--, c->W -= twoE, c->T -= G4, it++;
    }
    PERSP_OPS(ops, add, 3 * it);
    PERSP_OPS(ops, cmp, 2 + it);
    return it < MP_ITER_CAP || (c->W > 0 && c->W <= twoE);
}

/* ts, tp (NULL in the renderer): the span's and each integer pixel's state
 * for persp_midpoint_trace; ts->int_pixels is set to where the integer path
 * ended. */
static void mp_span_fixed(const persp_rational *r, const mp_fixed *fx, int edge, int x0, int y,
                          int n, float *s1, float *s2, persp_opcount *ops, persp_midpoint_span *ts,
                          persp_midpoint_pixel *tp)
{
    if (ts) ts->int_pixels = 0;
    if (!fx->ok || x0 < 0 || y < 0 || 2 * ((int64_t)x0 + n) - 1 >= fx->X2max ||
        2 * (int64_t)y + 1 >= fx->Y2max) {
        mp_span_double(r, edge, x0, y, n, s1, s2, ops);
        return;
    }
    const double P[2] = {mp_scale(r->scale1), mp_scale(r->scale2)};
    const int o2 = edge ? 0 : 1;
    const int64_t X2 = 2 * (int64_t)x0 + 1, Y2 = 2 * (int64_t)y + 1;
    const int64_t G2 = 2 * fx->G, G4 = 4 * fx->G;
    int64_t E = fx->G * X2 + fx->H * Y2 + 2 * fx->I;
    const int64_t Eend = E + G2 * (n - 1);
    PERSP_OPS(ops, mul, 3);
    PERSP_OPS(ops, add, 4);
    PERSP_OPS(ops, cmp, 2);
    if (E <= 0 || Eend <= 0) {
        mp_span_double(r, edge, x0, y, n, s1, s2, ops);
        return;
    }
    mp_icoord c[2];
    for (int j = 0; j < 2; j++) {
        int64_t N2 = fx->A[j] * X2 + fx->B[j] * Y2 + 2 * fx->C[j];
        PERSP_OPS(ops, mul, 3);
        PERSP_OPS(ops, add, 2);
        if (!mp_icoord_start(&c[j], fx->G, fx->A[j], N2, E, o2, ops)) {
            mp_span_double(r, edge, x0, y, n, s1, s2, ops);
            return;
        }
        if (ts) {
            ts->E0 = E, ts->N2[j] = N2, ts->n0[j] = c[j].n;
            ts->W0[j] = c[j].W, ts->T0[j] = c[j].T, ts->K[j] = c[j].K;
        }
    }
    const double inv[2] = {1.0 / P[0], 1.0 / P[1]};
    const double off = 0.5 * o2;
    float *out[2] = {s1, s2};
    for (int k = 0; k < n; k++) {
        if (k > 0) {
            E += G2;
            c[0].W += c[0].T - c[0].K;
            c[1].W += c[1].T - c[1].K;
        }
        const int64_t twoE = 2 * E;
        for (int j = 0; j < 2; j++) {
            int64_t from = c[j].n;
            int reseed = 0;
            if (!mp_icoord_search(&c[j], twoE, G4, ops)) {
                int64_t N2 = fx->A[j] * (X2 + 2 * k) + fx->B[j] * Y2 + 2 * fx->C[j];
                PERSP_OPS(ops, mul, 3);
                PERSP_OPS(ops, add, 3);
                if (!mp_icoord_start(&c[j], fx->G, fx->A[j], N2, E, o2, ops)) {
                    mp_span_double(r, edge, x0 + k, y, n - k, s1 + k, s2 + k, ops);
                    if (ts) ts->int_pixels = k;
                    return;
                }
                from = c[j].n, reseed = 1;
                (void)mp_icoord_search(&c[j], twoE, G4, ops);
            }
            if (c[j].n <= -MP_N_LIMIT || c[j].n >= MP_N_LIMIT) {
                /* Out of the format's texel range: finish in double. */
                mp_span_double(r, edge, x0 + k, y, n - k, s1 + k, s2 + k, ops);
                if (ts) ts->int_pixels = k;
                return;
            }
            if (tp) {
                tp[k].n[j] = c[j].n, tp[k].W[j] = c[j].W;
                tp[k].steps[j] = (int)(c[j].n - from), tp[k].reseed[j] = reseed;
            }
            out[j][k] = (float)(((double)c[j].n + off) * inv[j]);
        }
    }
    if (ts) ts->int_pixels = n;
    PERSP_OPS(ops, add, 5 * (n - 1) + 2 * n);
    PERSP_OPS(ops, mul, 2 * n);
}

/* ------------------------------------------------------ persp_midpoint_trace */

void persp__midpoint_format(const persp_rational *r, int edge, persp_midpoint_format *out)
{
    mp_fixed fx;
    int s = 0;
    mp_quantize_fixed(r, MP_DEN_BITS, &fx, &s);
    memset(out, 0, sizeof *out);
    out->in_format = fx.ok;
    out->shift = fx.ok ? s : 0;
    out->lattice2 = edge ? 0 : 1;
    if (fx.ok) {
        out->G = fx.G, out->H = fx.H, out->I = fx.I;
        for (int j = 0; j < 2; j++) out->A[j] = fx.A[j], out->B[j] = fx.B[j], out->C[j] = fx.C[j];
        out->X2max = fx.X2max, out->Y2max = fx.Y2max;
    }
    out->P[0] = mp_scale(r->scale1), out->P[1] = mp_scale(r->scale2);
    const double pl[9] = {r->a, r->b, r->c, r->d, r->e, r->f, r->g, r->h, r->i};
    memcpy(out->plane, pl, sizeof pl);
}

void persp__midpoint_trace_span(const persp_rational *r, const persp_midpoint_format *f, int x0, int y, int n,
                                float *s1, float *s2, persp_midpoint_span *span, persp_midpoint_pixel *px)
{
    /* The triangle's format, quantised once by persp__midpoint_format. */
    mp_fixed fx;
    memset(&fx, 0, sizeof fx);
    fx.G = f->G, fx.H = f->H, fx.I = f->I;
    for (int j = 0; j < 2; j++) fx.A[j] = f->A[j], fx.B[j] = f->B[j], fx.C[j] = f->C[j];
    fx.X2max = f->X2max, fx.Y2max = f->Y2max, fx.ok = f->in_format;
    const int edge = f->lattice2 == 0;
    memset(span, 0, sizeof *span);
    memset(px, 0, sizeof *px * (size_t)(n > 0 ? n : 0));
    span->x0 = x0, span->y = y, span->n = n;
    if (n <= 0) return;
    mp_span_fixed(r, &fx, edge, x0, y, n, s1, s2, NULL, span, px);
    /* The pixel where v left the integer path holds u's state: the double
     * path has none (persp_midpoint_pixel). */
    if (span->int_pixels < n) memset(&px[span->int_pixels], 0, sizeof *px);
    for (int k = 0; k < n; k++) px[k].u = s1[k], px[k].v = s2[k];
}

/* ---------------------------------------------------------------- the entry */

static void mp_prepare(const persp_rational *r, const persp_rational_vertices *v,
                       const persp_method_params *params, persp_method_prep *prep, persp_opcount *ops)
{
    (void)v;
    mp_params p = mp_get_params(params);
    if (!p.fixed) return;
    mp_fixed fx;
    mp_quantize_fixed(r, MP_DEN_BITS, &fx, NULL);
    memcpy(prep->bytes, &fx, sizeof fx);
    PERSP_OPS(ops, mul, 9);
    PERSP_OPS(ops, add, 2);
    PERSP_OPS(ops, cmp, 9);
}

static void mp_span(const persp_rational *r, const persp_method_params *params,
                    const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                    persp_opcount *ops)
{
    if (n <= 0) return;
    mp_params p = mp_get_params(params);
    if (!p.fixed) {
        mp_span_double(r, p.edge, x0, y, n, s1, s2, ops);
        return;
    }
    mp_fixed fx;
    if (prep) {
        memcpy(&fx, prep->bytes, sizeof fx);
    } else {
        mp_quantize_fixed(r, MP_DEN_BITS, &fx, NULL);
        PERSP_OPS(ops, mul, 9);
        PERSP_OPS(ops, add, 2);
        PERSP_OPS(ops, cmp, 9);
    }
    mp_span_fixed(r, &fx, p.edge, x0, y, n, s1, s2, ops, NULL, NULL);
}

const persp_method persp__method_midpoint = {
    .name = "midpoint",
    .params_help = "int|edge|int,edge",
    .summary = "improved Barenbrug midpoint search: lattice u within half a texel, "
               "additions and comparisons per pixel (int: fixed-point model)",
    .source = "[Romanyuk-PCF] §4.5, (4.10)-(4.15)",
    .cost = "0 div, 5 add, 4 cmp /px + 3 add, 1 cmp per texel step, + 2 mul, 2 add to output u, v; "
            "1 div /span (int: 2)",
    .parse = mp_parse,
    .prepare = mp_prepare,
    .span = mp_span,
};
