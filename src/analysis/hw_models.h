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

#include <stddef.h>
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

/* ------------------------------------- window_one, window_two (hw_models_shade.c) */

/* The rotated footprint window of [Romanyuk-PCF] §4.8 in one mip level
 * (the form of src/texture/window.c): corner A, the major axis, the signs
 * of the side AB, its slope dy/4096 and len × rows texels. */
#define PERSP_HW_WINDOW_DX 4096 /* slope resolution: dy/dx, dx = 4096 */
#define PERSP_HW_WINDOW_MAX 63  /* len, rows ≤ 63 (6 bits); max_aniso 16 gives ≤ 33 */
#define PERSP_HW_WINDOW_XBITS 24 /* texel coordinates, signed */

typedef struct persp_hw_window {
    int x0, y0;         /* corner A */
    int x_major, sx, sy; /* sx, sy ∈ {−1, +1} */
    int dy;             /* 0..4096 */
    int len, rows;      /* 1..63 */
    double t;           /* the slope before quantisation (error measurement only) */
} persp_hw_window;

/* The window of a footprint with Jacobian J = (du/dx, dv/dx, du/dy, dv/dy)
 * in texels of level 0 at (u, v) texels, as persp__window_setup makes it for
 * max_aniso; the level's number in *level. 0 when the footprint magnifies
 * (no window) or the window leaves the coordinates' bits. */
int persp__hw_window_setup(const double J[4], double u, double v, int max_aniso, persp_hw_window *w, int *level);

/* The texels in the order of each module: window_one the daisy chain of
 * one interpolator and the remembered step pattern (§4.8, Fig. 4.17–4.18),
 * window_two rows in raster order from two interpolators (row and column).
 * xy[2k], xy[2k + 1]; returns len·rows (at most cap written). ij, when not
 * NULL, gets each texel's (i, r) position in the window. */
size_t persp__hw_window_one(const persp_hw_window *w, int *xy, int *ij, size_t cap);
size_t persp__hw_window_two(const persp_hw_window *w, int *xy, int *ij, size_t cap);

/* ------------------------ tw_exact, tw_quadratic, tw_pwquad, tw_cubic (hw_models_shade.c) */

/* The perspective parameter t_w along a span of n pixels (§4.3, (4.6)):
 * t_w(k) = k·q1 / ((L − k)·q0 + k·q1), L = n − 1, q = 1/w at its ends;
 * output t_w·2^16 (17 bits unsigned). */
typedef enum persp_hw_tw_kind {
    PERSP_HW_TW_EXACT,  /* the division per pixel */
    PERSP_HW_TW_QUAD,   /* nodes 0, L/2, L; forward differences */
    PERSP_HW_TW_PWQUAD, /* 0, L/4, L/2 | L/2, 3L/4, L (persp__approx_span's pieces) */
    PERSP_HW_TW_CUBIC   /* 0, L/3, 2L/3, L */
} persp_hw_tw_kind;

#define PERSP_HW_TW_FRAC 16  /* output fraction bits */
#define PERSP_HW_TW_QBITS 16 /* tw_exact's q0, q1, normalised */
#define PERSP_HW_TW_DBITS 40 /* forward-difference registers, signed */
#define PERSP_HW_TW_DFRAC 32 /* their fraction bits */
#define PERSP_HW_TW_MAXN 64  /* n ≤ 64: spans within a 64-pixel tile */

typedef struct persp_hw_tw_span {
    int n;       /* 1..64 */
    int m;       /* tw_pwquad: the last pixel of the first piece */
    int64_t a[4]; /* exact: Q0, Q1; polynomials: d0..d3 of the (first) piece */
    int64_t b[3]; /* tw_pwquad: d0..d2 of the second piece at pixel m + 1 */
} persp_hw_tw_span;

/* The span's start values from q0, q1 > 0; 0 when a register leaves its
 * bits (the span is outside the format). */
int persp__hw_tw_setup(persp_hw_tw_kind kind, double q0, double q1, int n, persp_hw_tw_span *s);
/* Each pixel's output t_w·2^16, out[0..n−1]. */
void persp__hw_tw_run(persp_hw_tw_kind kind, const persp_hw_tw_span *s, int64_t *out);
/* persp's float method for the same span (persp__approx_span; for
 * PERSP_HW_TW_EXACT the float division), out[0..n−1]. */
void persp__hw_tw_float(persp_hw_tw_kind kind, double q0, double q1, int n, float *out);

/* ------------------------------------------- span datapaths (hw_models_span.c) */

/* quadratic, cubic, bezier ([Romanyuk-PCF] §4.4, §4.7): the float method's
 * polynomial along the span, fitted per span in double (the set-up, outside
 * the RTL), its forward differences quantised to FD_FRAC fraction bits and
 * stepped in FD_BITS-bit registers, u and v; output t·2^8 (25 bits) like
 * exact's. The value is the degree: the accumulators besides d0. */
typedef enum persp_hw_fd_kind {
    PERSP_HW_FD_QUADRATIC = 2,
    PERSP_HW_FD_CUBIC = 3,
    PERSP_HW_FD_BEZIER = 4 /* bezier:quadt's quartic */
} persp_hw_fd_kind;

#define PERSP_HW_FD_FRAC 32  /* fraction bits of d0..d4 */
#define PERSP_HW_FD_BITS 50  /* their registers, signed: |d_j| < 2^16 texels */
#define PERSP_HW_FD_TBITS 15 /* the span's values |t| < 2^15 texels */
#define PERSP_HW_SPAN_TOW 25 /* output t·2^8, signed (exact's TOW) */

typedef struct persp_hw_fd {
    int degree;
    int64_t d[2][5]; /* [u, v][d0..d4] */
} persp_hw_fd;

/* The start values of the span of n pixels at (x0, y) from set-up's planes
 * and the texture size P; 1 when the span is in the format (D > 0, values
 * and differences within their registers along the span), else 0. */
int persp__hw_fd_setup(persp_hw_fd_kind kind, const double plane[9], const double P[2], int x0, int y, int n,
                       persp_hw_fd *s);
/* One pixel: t = texels·2^8 of the current values, then one step. */
void persp__hw_fd_pixel(persp_hw_fd *s, int64_t t[2]);

/* subdiv:N ([CS300-TexMap] "Optimization"): exact's format and datapath at
 * the nodes k = 0, N, 2N, …, n − 1, linear between them with the slope
 * (t_b − t_a)·R[len] / 2^(RBITS − FRAC), R[len] = round(2^RBITS / len). */
#define PERSP_HW_SUBDIV_RBITS 24
#define PERSP_HW_SUBDIV_FRAC 16

uint32_t persp__hw_subdiv_recip(int len);
/* The span's pixels from exact's start values and steps (G2 = 2G, A2 =
 * 2A): ovf[k] (either end node out of range) and t[k] in range. */
void persp__hw_subdiv_span(int N, int64_t E0, const int64_t N2[2], int64_t G2, const int64_t A2[2], int n,
                           int *ovf, int64_t (*t)[2]);

/* incremental ([Romaniuk-Incr] (4), Fig. 4): two chains of exact's
 * datapath, from the left (+2G, +2A) and from the right (−2G, −2A); the
 * pixels in span order. */
void persp__hw_incremental_span(int64_t E0, const int64_t N2[2], int64_t G2, const int64_t A2[2], int n,
                                int *ovf, int64_t (*t)[2]);

#endif
