/*
 * `biquadratic` and `bicubic` — one polynomial in (x, y) per triangle
 * ([Romanyuk-PCF] §4.4):
 *
 *   biquadratic  u = A1x² + A2y² + A3xy + A4x + A5y + A6, interpolating the
 *                exact u at the three vertices and the three edge midpoints;
 *   bicubic      u = A1x³ + A2y³ + A3x²y + A4xy² + A5x² + A6y² + A7xy + A8x
 *                + A9y + A10, interpolating at the vertices, the points that
 *                divide each edge in thirds and the centroid (the 10 nodes of
 *                the cubic Lagrange triangle);
 *
 * v likewise. The nodes are unisolvent for the full polynomial spaces (the
 * standard P2/P3 Lagrange elements), so the fit is a 6×6 / 10×10 linear
 * solve in `prepare`, in coordinates centred on the centroid and scaled by
 * the triangle's radius h for conditioning: X = (x − cx)/h, Y = (y − cy)/h.
 * On a row, y is fixed and the polynomial is a quadratic / cubic in X,
 * evaluated by forward differences (shared code, poly.c).
 *
 * Error bound. With N, D the numerator and denominator planes, c the
 * centroid, h the largest distance from c to a vertex, Dmin the smallest
 * vertex 1/w and m the degree: the Taylor remainder of u about c along any
 * ray is bounded by the 1-D rational remainder (poly.h),
 *     |u − T_m u| ≤ R = |N(c)·∇D − D(c)·∇N| · |∇D|^m · h^(m+1) / Dmin^(m+2),
 * and interpolation reproduces T_m u, so
 *     |u − I u| ≤ (1 + Λ_m) · R,   Λ_2 = 5/3, Λ_3 ≈ 2.27
 * (Λ: Lebesgue constants of the P2 / P3 equispaced triangle nodes), plus the
 * float rounding of the output. The error grows with the triangle's depth
 * range; large triangles with strong perspective are this method's weakness,
 * which is why the chapter calls its use limited.
 *
 * Cost: per triangle 6 (10) exact evaluations (1 div, 5 mul, 3 add each) and
 * the solve (~n³/3 mul for n = 6, 10 with two right-hand sides); per span
 * ~10 (~16) mul + add for the row polynomial and ~20 for the
 * forward-difference start; per pixel 4 (6) add.
 */
#include "core/internal.h"
#include "interp/methods.h"
#include "interp/poly.h"

#include <math.h>
#include <string.h>

#define BIP_MAX 10

typedef struct bip_prep {
    double cu[BIP_MAX], cv[BIP_MAX];
    double cx, cy, invh;
    int degree; /* 2 or 3 */
    int ok;     /* 0: the solve failed; spans fall back to the exact form */
} bip_prep;
PERSP_METHOD_PREP_FITS(bip_prep);

/* Monomials in the chapter's coefficient order. */
static void monomials(int degree, double X, double Y, double *m)
{
    if (degree == 2) {
        const double t[6] = {X * X, Y * Y, X * Y, X, Y, 1.0};
        memcpy(m, t, sizeof t);
    } else {
        const double t[10] = {X * X * X, Y * Y * Y, X * X * Y, X * Y * Y, X * X,
                              Y * Y,     X * Y,     X,         Y,         1.0};
        memcpy(m, t, sizeof t);
    }
}

/* Gaussian elimination with partial pivoting, two right-hand sides.
 * Returns 0 if the matrix is numerically singular. */
static int solve2(int n, double A[BIP_MAX][BIP_MAX], double *b1, double *b2)
{
    for (int col = 0; col < n; col++) {
        int piv = col;
        for (int r = col + 1; r < n; r++)
            if (fabs(A[r][col]) > fabs(A[piv][col])) piv = r;
        if (!(fabs(A[piv][col]) > 1e-12)) return 0;
        if (piv != col) {
            for (int c = 0; c < n; c++) {
                double t = A[col][c];
                A[col][c] = A[piv][c];
                A[piv][c] = t;
            }
            double t = b1[col];
            b1[col] = b1[piv], b1[piv] = t;
            t = b2[col];
            b2[col] = b2[piv], b2[piv] = t;
        }
        for (int r = col + 1; r < n; r++) {
            double f = A[r][col] / A[col][col];
            for (int c = col; c < n; c++) A[r][c] -= f * A[col][c];
            b1[r] -= f * b1[col];
            b2[r] -= f * b2[col];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double s1 = b1[r], s2 = b2[r];
        for (int c = r + 1; c < n; c++) {
            s1 -= A[r][c] * b1[c];
            s2 -= A[r][c] * b2[c];
        }
        b1[r] = s1 / A[r][r];
        b2[r] = s2 / A[r][r];
    }
    return 1;
}

static void exact_at(const persp_rational *r, double x, double y, double *u, double *v)
{
    double q = r->g * x + r->h * y + r->i;
    *u = (r->a * x + r->b * y + r->c) / q;
    *v = (r->d * x + r->e * y + r->f) / q;
}

static void bip_prepare_deg(const persp_rational *r, const persp_rational_vertices *v, int degree,
                            persp_method_prep *prep, persp_opcount *ops)
{
    bip_prep *p = (bip_prep *)(void *)prep->bytes;
    memset(p, 0, sizeof *p);
    p->degree = degree;
    double cx = (v->x[0] + v->x[1] + v->x[2]) / 3.0;
    double cy = (v->y[0] + v->y[1] + v->y[2]) / 3.0;
    double h = 0.0;
    for (int i = 0; i < 3; i++) h = fmax(h, hypot(v->x[i] - cx, v->y[i] - cy));
    if (!(h > 0.0)) h = 1.0;
    p->cx = cx, p->cy = cy, p->invh = 1.0 / h;

    /* Nodes as barycentric weights of the vertices (in units of 1/degree). */
    double nx[BIP_MAX], ny[BIP_MAX];
    int count = 0;
    for (int i = 0; i < 3; i++) {
        nx[count] = v->x[i], ny[count] = v->y[i], count++;
    }
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3;
        for (int s = 1; s < degree; s++) {
            double w = (double)s / (double)degree;
            nx[count] = (1.0 - w) * v->x[i] + w * v->x[j];
            ny[count] = (1.0 - w) * v->y[i] + w * v->y[j];
            count++;
        }
    }
    if (degree == 3) {
        nx[count] = cx, ny[count] = cy, count++;
    }
    double A[BIP_MAX][BIP_MAX], bu[BIP_MAX], bv[BIP_MAX];
    for (int k = 0; k < count; k++) {
        monomials(degree, (nx[k] - cx) * p->invh, (ny[k] - cy) * p->invh, A[k]);
        exact_at(r, nx[k], ny[k], &bu[k], &bv[k]);
    }
    p->ok = solve2(count, A, bu, bv);
    if (p->ok) {
        memcpy(p->cu, bu, sizeof(double) * (size_t)count);
        memcpy(p->cv, bv, sizeof(double) * (size_t)count);
    }
    PERSP_OPS(ops, div, count + count + 1);
    PERSP_OPS(ops, mul, 8 * count + count * count * count / 3 * 2);
    PERSP_OPS(ops, add, 6 * count + count * count * count / 3 * 2);
}

static void biquad_prepare(const persp_rational *r, const persp_rational_vertices *v,
                           const persp_method_params *params, persp_method_prep *prep, persp_opcount *ops)
{
    (void)params;
    bip_prepare_deg(r, v, 2, prep, ops);
}

static void bicubic_prepare(const persp_rational *r, const persp_rational_vertices *v,
                            const persp_method_params *params, persp_method_prep *prep, persp_opcount *ops)
{
    (void)params;
    bip_prepare_deg(r, v, 3, prep, ops);
}

/* The row polynomial in X for fixed Y. */
static persp_poly row_poly(const double *A, int degree, double Y)
{
    persp_poly p;
    memset(&p, 0, sizeof p);
    p.degree = degree;
    if (degree == 2) {
        p.c[2] = A[0];
        p.c[1] = A[2] * Y + A[3];
        p.c[0] = (A[1] * Y + A[4]) * Y + A[5];
    } else {
        p.c[3] = A[0];
        p.c[2] = A[2] * Y + A[4];
        p.c[1] = (A[3] * Y + A[6]) * Y + A[7];
        p.c[0] = ((A[1] * Y + A[5]) * Y + A[8]) * Y + A[9];
    }
    return p;
}

static void bip_span(const persp_rational *r, const persp_method_params *params,
                     const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                     persp_opcount *ops)
{
    (void)params;
    if (n <= 0) return;
    const bip_prep *p = (const bip_prep *)(const void *)prep->bytes;
    if (!p->ok || (p->degree != 2 && p->degree != 3)) {
        /* Unfitted triangle (degenerate solve): exact per pixel. */
        persp_span_rat s;
        persp__span_rat_init(r, x0, y, &s);
        for (int k = 0; k < n; k++) {
            double u, v;
            persp__span_rat_at(&s, (double)k, &u, &v);
            s1[k] = (float)u;
            s2[k] = (float)v;
        }
        PERSP_SPAN_RAT_INIT_OPS(ops);
        PERSP_SPAN_RAT_AT_OPS(ops, n);
        return;
    }
    double X0 = ((double)x0 + 0.5 - p->cx) * p->invh;
    double Y = ((double)y + 0.5 - p->cy) * p->invh;
    PERSP_OPS(ops, mul, 2);
    PERSP_OPS(ops, add, 4);
    persp_poly pu = row_poly(p->cu, p->degree, Y), pv = row_poly(p->cv, p->degree, Y);
    PERSP_OPS(ops, mul, p->degree == 2 ? 6 : 12);
    PERSP_OPS(ops, add, p->degree == 2 ? 6 : 12);
    persp_fd fd;
    persp__fd_init(&pu, X0, p->invh, &fd, ops);
    persp__fd_run(&fd, n, s1, 1, ops);
    persp__fd_init(&pv, X0, p->invh, &fd, ops);
    persp__fd_run(&fd, n, s2, 1, ops);
}

const persp_method persp__method_biquadratic = {
    .name = "biquadratic",
    .params_help = "",
    .summary = "one quadratic in (x, y) per triangle through vertices and edge midpoints",
    .source = "[Romanyuk-PCF] §4.4",
    .cost = "4 add /px; ~40 mul, ~35 add /span; 6 div + 6x6 solve /triangle",
    .prepare = biquad_prepare,
    .span = bip_span,
};

const persp_method persp__method_bicubic = {
    .name = "bicubic",
    .params_help = "",
    .summary = "one cubic in (x, y) per triangle through 10 nodes (vertices, edge thirds, centroid)",
    .source = "[Romanyuk-PCF] §4.4",
    .cost = "6 add /px; ~60 mul, ~50 add /span; 10 div + 10x10 solve /triangle",
    .prepare = bicubic_prepare,
    .span = bip_span,
};
