/*
 * C models of the span datapaths of hw/rtl (hw_models.h; formats in
 * docs/HARDWARE.md): subdiv, incremental, quadratic, cubic, bezier. Every
 * shift and truncation here is one the Verilog makes, in the same order.
 * The per-span set-up of the polynomial modules is the float methods' own
 * fit in double (src/interp/quadratic.c, bezier.c) quantised once; only
 * what follows the quantisation is hardware.
 */
#include "hw_models.h"

#include "interp/poly.h"

#include <math.h>
#include <string.h>

/* ------------------------------------------------- forward differences */

/* A W-bit two's-complement register: the low W bits of v, sign-extended. */
static int64_t hs_wrap(uint64_t v, int w)
{
    const uint64_t m = ((uint64_t)1 << w) - 1, sign = (uint64_t)1 << (w - 1);
    v &= m;
    return (v & sign) ? -(int64_t)(m - v) - 1 : (int64_t)v;
}

/* The polynomial of u or v (texels) along the span, in k, as the float
 * method fits it. 0 when the fit leaves the double range. */
static int hs_fit(persp_hw_fd_kind kind, const persp_span_rat *s, int which, int n, persp_fd *fd)
{
    const persp_rat1 f = persp__span_rat1(s, which);
    memset(fd, 0, sizeof *fd);
    if (n <= 2) {
        /* Both pixels are anchors: evaluated exactly by every span method. */
        const double t0 = persp__rat1_eval(&f, 0.0), t1 = n == 2 ? persp__rat1_eval(&f, 1.0) : t0;
        fd->degree = 1, fd->d[0] = t0, fd->d[1] = t1 - t0;
        return isfinite(t0) && isfinite(t1);
    }
    const double L = (double)(n - 1);
    persp_poly p;
    double h = 1.0 / L, s0 = 0.0;
    if (kind == PERSP_HW_FD_QUADRATIC) {
        /* [Romanyuk-PCF] (4.9), A2 corrected (docs/METHODS.md). */
        const double u0 = persp__rat1_eval(&f, 0.0), u1 = persp__rat1_eval(&f, 0.5 * L),
                     u2 = persp__rat1_eval(&f, L);
        p = (persp_poly){2, {u0, -3.0 * u0 + 4.0 * u1 - u2, 2.0 * u0 - 4.0 * u1 + 2.0 * u2, 0.0, 0.0}};
    } else if (kind == PERSP_HW_FD_CUBIC) {
        /* [Romanyuk-PCF] §4.4: nodes 0, 1/3, 2/3, 1 of the normalised span. */
        static const double nodes[4] = {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0};
        double y[4];
        for (int j = 0; j < 4; j++) y[j] = persp__rat1_eval(&f, nodes[j] * L);
        persp__poly_interp(nodes, y, 4, &p, NULL);
    } else {
        /* [Romanyuk-PCF] §4.7, bezier:quadt: the Bézier through the ends with
         * its control point at the tangents' intersection
         * (persp__bezier_control), t(x) the quadratic through (0, 0),
         * (x(½), ½), (L, 1), and u(t(x)) the quartic in x, step 1
         * (src/interp/bezier.c). */
        double x1, u1;
        persp__bezier_control(&f, L, &x1, &u1);
        const double u0 = persp__rat1_eval(&f, 0.0), u2 = persp__rat1_eval(&f, L);
        const double sx = L - 2.0 * x1, bu = 2.0 * (u1 - u0), su = u0 - 2.0 * u1 + u2;
        const double xs[3] = {0.0, x1 + 0.25 * sx, L}, ts[3] = {0.0, 0.5, 1.0};
        persp_poly t;
        persp__poly_interp(xs, ts, 3, &t, NULL);
        const double c1 = t.c[1], c2 = t.c[2];
        p = (persp_poly){4, {u0, bu * c1, bu * c2 + su * c1 * c1, 2.0 * su * c1 * c2, su * c2 * c2}};
        h = 1.0;
    }
    persp__fd_init(&p, s0, h, fd, NULL);
    for (int j = 0; j <= fd->degree; j++)
        if (!isfinite(fd->d[j])) return 0;
    return 1;
}

int persp__hw_fd_setup(persp_hw_fd_kind kind, const double plane[9], const double P[2], int x0, int y, int n,
                       persp_hw_fd *s)
{
    memset(s, 0, sizeof *s);
    s->degree = (int)kind;
    if (n <= 0) return 0;
    persp_rational r;
    memset(&r, 0, sizeof r);
    r.a = P[0] * plane[0], r.b = P[0] * plane[1], r.c = P[0] * plane[2];
    r.d = P[1] * plane[3], r.e = P[1] * plane[4], r.f = P[1] * plane[5];
    r.g = plane[6], r.h = plane[7], r.i = plane[8];
    persp_span_rat sr;
    persp__span_rat_init(&r, x0, y, &sr);
    const double tlim = ldexp(1.0, PERSP_HW_FD_TBITS), dlim = ldexp(1.0, PERSP_HW_FD_BITS - 2 - PERSP_HW_FD_FRAC);
    for (int j = 0; j < 2; j++) {
        persp_fd fd;
        if (!hs_fit(kind, &sr, j, n, &fd)) return 0;
        for (int i = 0; i <= PERSP_POLY_MAX_DEGREE; i++) {
            const double q = ldexp(fd.d[i], PERSP_HW_FD_FRAC);
            if (!(fabs(fd.d[i]) < dlim)) return 0;
            s->d[j][i] = (int64_t)llround(q);
        }
        /* In range: the values below 2^15 texels and every difference below
         * 2^(BITS-2-FRAC) along the whole span (walked in double), so no
         * register wraps and the output's 2^15 is not crossed. */
        for (int k = 0; k < n; k++) {
            if (!(fabs(fd.d[0]) < tlim)) return 0;
            for (int i = 1; i <= fd.degree; i++)
                if (!(fabs(fd.d[i]) < dlim)) return 0;
            for (int i = 0; i < fd.degree; i++) fd.d[i] += fd.d[i + 1];
        }
        /* The denominator's sign: D > 0 over the span, as every method needs. */
        if (!(sr.q > 0.0 && sr.q + sr.dq * (double)(n - 1) > 0.0)) return 0;
    }
    return 1;
}

void persp__hw_fd_pixel(persp_hw_fd *s, int64_t t[2])
{
    enum { W = PERSP_HW_FD_BITS, SH = PERSP_HW_FD_FRAC - PERSP_HW_EXACT_FRAC };
    for (int j = 0; j < 2; j++) {
        int64_t *d = s->d[j];
        /* out = d0 bits [FRAC+16 : FRAC-8]: texels·2^8, 25 bits signed. */
        t[j] = hs_wrap((uint64_t)d[0] >> SH, PERSP_HW_SPAN_TOW);
        /* Ascending order = the RTL's parallel update (each d_i reads the
         * old d_(i+1)). */
        for (int i = 0; i < s->degree; i++) d[i] = hs_wrap((uint64_t)d[i] + (uint64_t)d[i + 1], W);
    }
}

/* ----------------------------------------------------------- subdiv */

uint32_t persp__hw_subdiv_recip(int len)
{
    if (len < 1) len = 1;
    return (uint32_t)((((uint64_t)1 << PERSP_HW_SUBDIV_RBITS) + (uint64_t)len / 2) / (uint64_t)len);
}

/* floor(v / 2^k) for negative v too (as hw_models.c). */
static int64_t hs_asr(int64_t v, int k) { return v >= 0 ? v >> k : -(((-v) + ((int64_t)1 << k) - 1) >> k); }

void persp__hw_subdiv_span(int N, int64_t E0, const int64_t N2[2], int64_t G2, const int64_t A2[2], int n,
                           int *ovf, int64_t (*t)[2])
{
    if (n <= 0) return;
    /* Node k's exact value: exact's datapath at E0 + k·2G (integer steps). */
    int64_t ta[2] = {0, 0}, tb[2] = {0, 0};
    int oa = 0, ob;
    {
        const int64_t N0[2] = {N2[0], N2[1]};
        oa = persp__hw_exact_pixel(E0, N0, ta);
    }
    int k = 0;
    while (k < n - 1) {
        const int len = n - 1 - k < N ? n - 1 - k : N;
        const int64_t kb = k + len;
        const int64_t Nb[2] = {N2[0] + A2[0] * kb, N2[1] + A2[1] * kb};
        tb[0] = tb[1] = 0;
        ob = persp__hw_exact_pixel(E0 + G2 * kb, Nb, tb);
        /* [CS300-TexMap] "Optimization": linear between the nodes, the slope
         * (t_b − t_a)/len as (t_b − t_a)·R[len] with R = 2^24/len rounded (a
         * shift for len = N), FRAC fraction bits kept along the segment. */
        const int64_t R = persp__hw_subdiv_recip(len);
        int64_t S[2];
        for (int j = 0; j < 2; j++)
            S[j] = hs_asr((tb[j] - ta[j]) * R, PERSP_HW_SUBDIV_RBITS - PERSP_HW_SUBDIV_FRAC);
        for (int i = 0; i < len; i++) {
            ovf[k + i] = oa || ob;
            for (int j = 0; j < 2; j++) t[k + i][j] = ta[j] + hs_asr(S[j] * i, PERSP_HW_SUBDIV_FRAC);
        }
        k += len;
        oa = ob, ta[0] = tb[0], ta[1] = tb[1];
    }
    /* The last pixel is a node: its exact value. */
    ovf[n - 1] = oa;
    t[n - 1][0] = ta[0], t[n - 1][1] = ta[1];
}

/* ------------------------------------------------------- incremental */

void persp__hw_incremental_span(int64_t E0, const int64_t N2[2], int64_t G2, const int64_t A2[2], int n,
                                int *ovf, int64_t (*t)[2])
{
    /* [Romaniuk-Incr] Fig. 4: pixel i from the left chain (start + i·step),
     * pixel n−1−i from the right (end − i·step); in integers both are the
     * same exact sums, so every pixel is exact's at its position. */
    for (int k = 0; k < n; k++) {
        const int64_t Nk[2] = {N2[0] + A2[0] * k, N2[1] + A2[1] * k};
        t[k][0] = t[k][1] = 0;
        ovf[k] = persp__hw_exact_pixel(E0 + G2 * k, Nk, t[k]);
    }
}
