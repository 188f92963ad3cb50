/*
 * Span polynomials (see poly.h): interpolation through 2..4 nodes, forward
 * differences, and the fitted approximations of a 1-D rational function used
 * by the approximating texture methods ([Romanyuk-PCF] §4.4, §4.6) and by the
 * perspective-correct shading approximations ([Romanyuk-PCF] §4.2-4.3).
 */
#include "interp/poly.h"
#include "interp/method.h"

#include <math.h>
#include <string.h>

void persp__poly_interp(const double *s, const double *y, int count, persp_poly *out,
                        persp_opcount *ops)
{
    double dd[PERSP_POLY_MAX_DEGREE + 1];
    memset(out, 0, sizeof *out);
    if (count < 1) return;
    if (count > PERSP_POLY_MAX_DEGREE + 1) count = PERSP_POLY_MAX_DEGREE + 1;
    for (int j = 0; j < count; j++) dd[j] = y[j];
    /* Newton divided differences in place: dd[j] = f[s_0..s_j]. */
    for (int level = 1; level < count; level++)
        for (int j = count - 1; j >= level; j--)
            dd[j] = (dd[j] - dd[j - 1]) / (s[j] - s[j - level]);
    /* Nested form p = dd0 + (s − s0)(dd1 + (s − s1)(dd2 + (s − s2)·dd3)),
     * expanded from the inside out into the power basis. */
    double c[PERSP_POLY_MAX_DEGREE + 1] = {0};
    c[0] = dd[count - 1];
    int deg = 0;
    for (int j = count - 2; j >= 0; j--) {
        /* c ← c·(s − s_j) + dd[j] */
        for (int i = deg + 1; i >= 1; i--) c[i] = c[i - 1] - s[j] * c[i];
        c[0] = dd[j] - s[j] * c[0];
        deg++;
    }
    out->degree = count - 1;
    for (int i = 0; i <= out->degree; i++) out->c[i] = c[i];
    int pairs = count * (count - 1) / 2;
    PERSP_OPS(ops, div, pairs);
    PERSP_OPS(ops, add, 2 * pairs + pairs);
    PERSP_OPS(ops, mul, pairs);
}

double persp__poly_eval(const persp_poly *p, double s)
{
    double v = p->c[p->degree];
    for (int i = p->degree - 1; i >= 0; i--) v = v * s + p->c[i];
    return v;
}

void persp__fd_init(const persp_poly *p, double s0, double h, persp_fd *fd, persp_opcount *ops)
{
    /* Taylor coefficients at s0: p(s0 + x) = b0 + b1·x + b2·x² + b3·x³ (+ b4·x⁴). */
    const double *c = p->c;
    double b0 = persp__poly_eval(p, s0);
    double b1 = c[1] + s0 * (2.0 * c[2] + s0 * 3.0 * c[3]);
    double b2 = c[2] + 3.0 * c[3] * s0;
    double b3 = c[3];
    double h2 = h * h, h3 = h2 * h;
    memset(fd, 0, sizeof *fd);
    fd->degree = p->degree;
    /* Δ p = b1·h + b2·h² + b3·h³, Δ² p = 2·b2·h² + 6·b3·h³, Δ³ p = 6·b3·h³
     * (the differences of x^j on the grid x = 0, h, 2h, ...). */
    fd->d[0] = b0;
    fd->d[1] = b1 * h + b2 * h2 + b3 * h3;
    fd->d[2] = 2.0 * b2 * h2 + 6.0 * b3 * h3;
    fd->d[3] = 6.0 * b3 * h3;
    PERSP_OPS(ops, mul, 3 * p->degree + 14);
    PERSP_OPS(ops, add, p->degree + 6);
    if (p->degree >= 4) {
        /* The quartic term: c4·(s0 + x)⁴ adds 4c4·s0³, 6c4·s0², 4c4·s0 to
         * b1..b3, and Δ^j x⁴ at 0 with step h is j!·S(4, j)·h⁴ = 1, 14, 36, 24
         * times h⁴ (Stirling numbers of the second kind S(4, j) = 1, 7, 6, 1). */
        double c4 = c[4], s02 = s0 * s0, h4 = h2 * h2;
        double e1 = 4.0 * c4 * s02 * s0, e2 = 6.0 * c4 * s02, e3 = 4.0 * c4 * s0;
        fd->d[1] += e1 * h + e2 * h2 + e3 * h3 + c4 * h4;
        fd->d[2] += 2.0 * e2 * h2 + 6.0 * e3 * h3 + 14.0 * c4 * h4;
        fd->d[3] += 6.0 * e3 * h3 + 36.0 * c4 * h4;
        fd->d[4] = 24.0 * c4 * h4;
        PERSP_OPS(ops, mul, 25);
        PERSP_OPS(ops, add, 9);
    }
}

void persp__fd_run(persp_fd *fd, int n, float *out, int stride, persp_opcount *ops)
{
    double d0 = fd->d[0], d1 = fd->d[1], d2 = fd->d[2], d3 = fd->d[3];
    switch (fd->degree) {
    case 0:
        for (int k = 0; k < n; k++) out[k * stride] = (float)d0;
        break;
    case 1:
        for (int k = 0; k < n; k++) {
            out[k * stride] = (float)d0;
            d0 += d1;
        }
        break;
    case 2:
        for (int k = 0; k < n; k++) {
            out[k * stride] = (float)d0;
            d0 += d1;
            d1 += d2;
        }
        break;
    case 3:
        for (int k = 0; k < n; k++) {
            out[k * stride] = (float)d0;
            d0 += d1;
            d1 += d2;
            d2 += d3;
        }
        break;
    default: {
        double d4 = fd->d[4];
        for (int k = 0; k < n; k++) {
            out[k * stride] = (float)d0;
            d0 += d1;
            d1 += d2;
            d2 += d3;
            d3 += d4;
        }
        break;
    }
    }
    fd->d[0] = d0, fd->d[1] = d1, fd->d[2] = d2, fd->d[3] = d3;
    PERSP_OPS(ops, add, (uint64_t)fd->degree * (uint64_t)(n > 0 ? n : 0));
}

/* Fits the polynomial through f at the given nodes and writes p(k) for
 * k = k0..k1 (inclusive) to out[k]. */
static void fit_piece(const persp_rat1 *f, const double *nodes, int count, int k0, int k1,
                      float *out, persp_opcount *ops)
{
    double y[PERSP_POLY_MAX_DEGREE + 1];
    for (int j = 0; j < count; j++) y[j] = persp__rat1_eval(f, nodes[j]);
    PERSP_OPS(ops, div, count);
    PERSP_OPS(ops, mul, 2 * count);
    PERSP_OPS(ops, add, 2 * count);
    persp_poly p;
    persp_fd fd;
    persp__poly_interp(nodes, y, count, &p, ops);
    persp__fd_init(&p, (double)k0, 1.0, &fd, ops);
    persp__fd_run(&fd, k1 - k0 + 1, out + k0, 1, ops);
}

void persp__approx_span(const persp_rat1 *f, persp_approx_kind kind, double tau, int n, float *out,
                        persp_opcount *ops)
{
    if (n <= 0) return;
    if (n <= 2) {
        for (int k = 0; k < n; k++) out[k] = (float)persp__rat1_eval(f, (double)k);
        PERSP_OPS(ops, div, n);
        PERSP_OPS(ops, mul, 2 * n);
        PERSP_OPS(ops, add, 2 * n);
        return;
    }
    const double L = (double)(n - 1);
    switch (kind) {
    case PERSP_APPROX_CUBIC: {
        const double nodes[4] = {0.0, L / 3.0, 2.0 * L / 3.0, L};
        fit_piece(f, nodes, 4, 0, n - 1, out, ops);
        break;
    }
    case PERSP_APPROX_PWQUAD: {
        /* Two pieces meeting at L/2; each interpolates its ends and middle. */
        const double a[3] = {0.0, L / 4.0, L / 2.0};
        const double b[3] = {L / 2.0, 3.0 * L / 4.0, L};
        int m = (n - 1) / 2;
        fit_piece(f, a, 3, 0, m, out, ops);
        fit_piece(f, b, 3, m + 1, n - 1, out, ops);
        break;
    }
    case PERSP_APPROX_QUAD:
    default: {
        if (!(tau > 0.0 && tau < 1.0)) tau = 0.5;
        const double nodes[3] = {0.0, tau * L, L};
        fit_piece(f, nodes, 3, 0, n - 1, out, ops);
        break;
    }
    }
}

double persp__approx_error(const persp_rat1 *f, const double *nodes, int count, double s)
{
    double cross = f->beta * f->gamma - f->alpha * f->delta;
    double num = cross, den = f->gamma * s + f->delta;
    for (int j = 0; j < count; j++) {
        num *= s - nodes[j];
        den *= f->gamma * nodes[j] + f->delta;
        if (j > 0) num *= f->gamma;
    }
    if (count % 2) num = -num;
    return num / den;
}

double persp__quad_shift_anchor(double u0, double u1)
{
    const double eps = 0.05;
    const int in0 = u0 >= 0.0 && u0 <= 1.0, in1 = u1 >= 0.0 && u1 <= 1.0;
    if (fabs(u0) <= eps && in1) return 0.25;
    if (fabs(u1) <= eps && in0) return 0.75;
    if (fabs(u0 - 1.0) <= eps && u1 >= 0.05 && u1 <= 1.0) {
        double d = u0 - u1;
        if (d >= 0.0 && d < 0.35) return 0.5;
        if (d >= 0.35 && d < 0.75) return 0.6;
        if (d >= 0.75 && d <= 0.95) return 0.7;
    }
    if (fabs(u1 - 1.0) <= eps && u0 >= 0.05 && u0 <= 1.0) {
        double d = u1 - u0;
        if (d >= 0.0 && d < 0.35) return 0.5;
        if (d >= 0.35 && d < 0.75) return 0.4;
        if (d >= 0.75 && d <= 0.95) return 0.3;
    }
    if (in0 && in1 && u0 < 0.5 && u1 < 0.5) {
        if (u0 < u1) return 0.4;
        if (u0 > u1) return 0.6;
    }
    return 0.5;
}
