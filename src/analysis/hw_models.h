/*
 * C models of the RTL under hw/rtl (docs/HARDWARE.md): each function here is
 * the specification a Verilog module equals bit for bit, and `persp vectors
 * --module NAME` writes its inputs and outputs for the module's Verilator
 * testbench. Internal to persp (the CLI links it); not a public header.
 * midpoint_int's model is persp's own integer path (src/interp/midpoint.c,
 * persp_midpoint_trace), so only the other modules' models live here.
 */
#ifndef PERSP_ANALYSIS_HW_MODELS_H
#define PERSP_ANALYSIS_HW_MODELS_H

#include <stdint.h>

/* ------------------------------------------------------------------ exact */

/* `exact`, the baseline: 1/w, P·u/w, P·v/w stepped linearly
 * along a span in fixed point (exactly, as integers), then per pixel one
 * reciprocal (a 256-entry seed table and one Newton–Raphson step) and two
 * multiplies. Widths (docs/HARDWARE.md, "exact"): */
#define PERSP_HW_EXACT_EBITS 40 /* |E| = |G·X2 + H·Y2 + 2I| < 2^40 over the box */
#define PERSP_HW_EXACT_NBITS 56 /* |N2| = |A·X2 + B·Y2 + 2C| < 2^55 over the box: EBITS + 16 */
#define PERSP_HW_EXACT_SBITS 32 /* the normalised numerator Ns, signed */
#define PERSP_HW_EXACT_FRAC 8   /* fraction bits of the output t = texels · 2^8 */

typedef struct persp_hw_exact_format {
    int in_format; /* 0: the planes do not fit; no span runs in the hardware */
    int shift;     /* s: G = round(g·2^s), A = round(P·a·2^s), ... */
    int64_t G, H, I;
    int64_t A[2], B[2], C[2]; /* [0] u, [1] v */
    int64_t X2max, Y2max;     /* X2 = 2x + 1 < X2max, Y2 < Y2max */
} persp_hw_exact_format;

/* The format of a triangle with set-up's planes a … i (u/w, v/w, 1/w, as
 * persp_midpoint_format's plane), texture P[2] texels and covered pixels
 * within [0, xmax] × [0, ymax]. */
void persp__hw_exact_format(const double plane[9], const double P[2], int xmax, int ymax,
                            persp_hw_exact_format *f);

/* A span's start values at pixel x0 of row y; 1 when the span runs in the
 * hardware (inside the box, E > 0 at both ends), else 0. */
int persp__hw_exact_span(const persp_hw_exact_format *f, int x0, int y, int n, int64_t *E0, int64_t N2[2]);

/* The seed table: 2^25 / (513 + 2·idx), 1/m at the middle of each of 256
 * intervals of the mantissa m ∈ [1, 2), 16 fraction bits. */
uint32_t persp__hw_exact_seed(unsigned idx);

/* One pixel: t[j] = floor(texels · 2^8) as the datapath computes it.
 * Returns 1 (t unset) where the normalised numerator leaves its 32 bits
 * (|t| ≥ 2^15 texels: the pixel is outside the format), else 0. */
int persp__hw_exact_pixel(int64_t E, const int64_t N2[2], int64_t t[2]);

#endif
