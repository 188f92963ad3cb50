/*
 * C models of hw/rtl (hw_models.h; formats in docs/HARDWARE.md). Every
 * shift and truncation here is one the Verilog makes, in the same order:
 * the testbenches compare the RTL with these results bit for bit.
 */
#include "hw_models.h"

#include <math.h>
#include <string.h>

/* ------------------------------------------------------------------ exact */

/* round(v·2^s) half away from zero, as midpoint:int quantises its planes
 * (docs/METHODS.md, "Fixed-point model"), or 0 when |v·2^s| ≥ limit. */
static int hx_coef(double v, int s, double limit, int64_t *out)
{
    double x = ldexp(v, s);
    if (!(fabs(x) < limit)) return 0;
    *out = (int64_t)llround(x);
    return 1;
}

void persp__hw_exact_format(const double plane[9], const double P[2], int xmax, int ymax,
                            persp_hw_exact_format *f)
{
    memset(f, 0, sizeof *f);
    if (xmax < 0 || ymax < 0 || xmax >= (1 << 15) || ymax >= (1 << 15)) return;
    const int64_t Xb = 2 * (int64_t)xmax + 2, Yb = 2 * (int64_t)ymax + 2;
    const double g = plane[6], h = plane[7], i = plane[8];
    const double mx = fabs(g) * (double)Xb + fabs(h) * (double)Yb + 2.0 * fabs(i);
    if (!(mx > 0.0) || !isfinite(mx)) return;
    int e;
    (void)frexp(mx, &e);
    /* The normalisation of midpoint:int (docs/METHODS.md) with 40 bits:
     * E = g·X2 + h·Y2 + 2i cancels within a triangle far from the origin,
     * so the planes' rounding needs bits beyond the reciprocal's 16
     * (with 31 it alone gave 0.25 texel on 256 texels). */
    const int s = PERSP_HW_EXACT_EBITS - e;
    const double LE = ldexp(1.0, PERSP_HW_EXACT_EBITS), LN = ldexp(1.0, PERSP_HW_EXACT_NBITS - 1);
    int ok = hx_coef(g, s, LE, &f->G) && hx_coef(h, s, LE, &f->H) && hx_coef(i, s, LE, &f->I);
    for (int j = 0; j < 2 && ok; j++) {
        ok = hx_coef(P[j] * plane[3 * j], s, LN, &f->A[j]) && hx_coef(P[j] * plane[3 * j + 1], s, LN, &f->B[j]) &&
             hx_coef(P[j] * plane[3 * j + 2], s, LN, &f->C[j]);
        ok = ok && fabs((double)f->A[j]) * (double)Xb + fabs((double)f->B[j]) * (double)Yb +
                           2.0 * fabs((double)f->C[j]) < LN;
    }
    f->shift = s, f->X2max = Xb, f->Y2max = Yb, f->in_format = ok;
}

int persp__hw_exact_span(const persp_hw_exact_format *f, int x0, int y, int n, int64_t *E0, int64_t N2[2])
{
    if (!f->in_format || n <= 0 || x0 < 0 || y < 0 || 2 * ((int64_t)x0 + n) - 1 >= f->X2max ||
        2 * (int64_t)y + 1 >= f->Y2max)
        return 0;
    const int64_t X2 = 2 * (int64_t)x0 + 1, Y2 = 2 * (int64_t)y + 1;
    *E0 = f->G * X2 + f->H * Y2 + 2 * f->I;
    for (int j = 0; j < 2; j++) N2[j] = f->A[j] * X2 + f->B[j] * Y2 + 2 * f->C[j];
    /* E is linear along the span: inside (0, 2^31) at both ends, inside
     * everywhere (the planes' rounding may carry it just past 2^31). */
    const int64_t Eend = *E0 + 2 * f->G * (n - 1), L = (int64_t)1 << PERSP_HW_EXACT_EBITS;
    return *E0 > 0 && Eend > 0 && *E0 < L && Eend < L;
}

uint32_t persp__hw_exact_seed(unsigned idx) { return (uint32_t)(33554432u / (513u + 2u * (idx & 255u))); }

/* Arithmetic right shift (floor division by 2^k) without relying on the
 * implementation-defined >> of negative values. */
static int64_t hx_asr(int64_t v, int k) { return v >= 0 ? v >> k : -(((-v) + ((int64_t)1 << k) - 1) >> k); }

int persp__hw_exact_pixel(int64_t E, const int64_t N2[2], int64_t t[2])
{
    /* Normalise E to m ∈ [2^39, 2^40): lz leading zeros in 40 bits. */
    enum { EB = PERSP_HW_EXACT_EBITS, SH = PERSP_HW_EXACT_NBITS - PERSP_HW_EXACT_SBITS };
    int lz = 0;
    while (lz < EB - 1 && !(E & ((int64_t)1 << (EB - 1 - lz)))) lz++;
    const int64_t m = E << lz;
    /* Seed from the 8 bits after the leading one, one Newton–Raphson step
     * r1 = r0·(2 − m·r0) in 16-bit factors (one SB_MAC16 each): m16·r0 =
     * 2^31·(1 + e), r1 = r0 − r0·e, the correction from r0/2 and e·2^23. */
    const int64_t r0 = persp__hw_exact_seed((unsigned)(m >> (EB - 9)) & 255u);
    const int64_t m16 = m >> (EB - 16);
    const int64_t d8 = hx_asr(m16 * r0 - ((int64_t)1 << 31), 8);
    int64_t r1 = r0 - hx_asr((r0 >> 1) * d8, 22);
    /* 1/m ∈ (½, 1]: r1 is kept in [2^15, 2^16) so that r1 − 2^15 is one
     * 16-bit factor of the output multiplies. */
    if (r1 > 65535) r1 = 65535;
    if (r1 < 32768) r1 = 32768;
    /* t·2^8 = N2/E·2^8 = (N2·2^lz / 2^24)·r1 / 2^23, with N2·2^lz in 56 bits
     * (m = E·2^lz = mm·2^39, so t = Ns·2^24 / (mm·2^39) = Ns / (mm·2^15)). */
    const int64_t lim = (int64_t)1 << (PERSP_HW_EXACT_NBITS - 1 - lz);
    for (int j = 0; j < 2; j++)
        if (N2[j] >= lim || N2[j] < -lim) return 1;
    for (int j = 0; j < 2; j++) {
        const int64_t Ns = hx_asr(N2[j] * ((int64_t)1 << lz), SH);
        t[j] = hx_asr(Ns * 32768 + Ns * (r1 - 32768), 23);
    }
    return 0;
}
