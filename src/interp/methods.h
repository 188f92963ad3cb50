/* Method entries of the registry; one extern per method (src/interp/registry.c). */
#ifndef PERSP_INTERP_METHODS_H
#define PERSP_INTERP_METHODS_H

#include "core/shared.h"

#include "interp/method.h"

/* Plane p(x,y) = px·x + py·y + pc through three (x, y, value) points.
 * Inline: triangle set-up fits seven planes through the same three points,
 * and the compiler then computes their common differences and determinant
 * once (the same operations, so the same bits). */
static inline void persp__plane_through(const double vx[3], const double vy[3], const double val[3],
                                        double *px, double *py, double *pc)
{
    double x10 = vx[1] - vx[0], y10 = vy[1] - vy[0];
    double x20 = vx[2] - vx[0], y20 = vy[2] - vy[0];
    double det = x10 * y20 - x20 * y10;
    if (det == 0.0) {
        *px = *py = 0.0;
        *pc = val[0];
        return;
    }
    double d1 = val[1] - val[0], d2 = val[2] - val[0];
    *px = (d1 * y20 - d2 * y10) / det;
    *py = (d2 * x10 - d1 * x20) / det;
    *pc = val[0] - *px * vx[0] - *py * vy[0];
}

/* The exact method's span for two rationals sharing their denominator (the
 * texture coordinates and the perspective-correct barycentrics of one
 * triangle): the same values as two calls of its span, one reciprocal per
 * pixel. */
static inline void persp__exact_span_pair(const persp_rational *r, const persp_rational *w, int x0, int y,
                                          int n, float *s1, float *s2, float *w1, float *w2)
{
    /* Inline, so that it takes the instruction set of its caller's clone. */
    double px = x0 + 0.5, py = y + 0.5;
    float U = (float)(r->a * px + r->b * py + r->c);
    float V = (float)(r->d * px + r->e * py + r->f);
    float Q = (float)(r->g * px + r->h * py + r->i);
    float A = (float)(w->a * px + w->b * py + w->c);
    float B = (float)(w->d * px + w->e * py + w->f);
    float dU = (float)r->a, dV = (float)r->d, dQ = (float)r->g;
    float dA = (float)w->a, dB = (float)w->d;
    for (int k = 0; k < n; k++) {
        float fk = (float)k;
        float rq = 1.0f / (Q + fk * dQ);
        s1[k] = (U + fk * dU) * rq;
        s2[k] = (V + fk * dV) * rq;
        w1[k] = (A + fk * dA) * rq;
        w2[k] = (B + fk * dB) * rq;
    }
}

extern const persp_method persp__method_affine;
extern const persp_method persp__method_exact;
/* incremental.c, subdiv.c, quadratic.c, bipoly.c, bezier.c */
extern const persp_method persp__method_incremental;
extern const persp_method persp__method_subdiv, persp__method_subdiv_quad;
extern const persp_method persp__method_quadratic, persp__method_quadratic_shifted;
extern const persp_method persp__method_quadratic_unnorm, persp__method_cubic;
extern const persp_method persp__method_biquadratic, persp__method_bicubic;
extern const persp_method persp__method_bezier;
extern const persp_method persp__method_quadratic_pw; /* pwquad.c */
extern const persp_method persp__method_midpoint; /* midpoint.c */
extern const persp_method persp__method_constz;   /* constz.c */
extern const persp_method persp__method_adaptive; /* adaptive.c */
/* midpoint.c: r with its planes rounded to the fixed-point format of
 * midpoint:int at den_bits (42 there). */
void persp__midpoint_quantize(const persp_rational *r, int den_bits, persp_rational *out);
/* midpoint.c: midpoint:int's (edge: midpoint:int,edge's) fixed-point
 * planes of r, and one span of it in that format with its integer state
 * recorded; s1, s2 receive the outputs as the method's span does
 * (persp_midpoint_trace). */
struct persp_midpoint_format;
struct persp_midpoint_span;
struct persp_midpoint_pixel;
PERSP_INTERNAL void persp__midpoint_format(const persp_rational *r, int edge,
                                           struct persp_midpoint_format *out);
PERSP_INTERNAL void persp__midpoint_trace_span(const persp_rational *r,
                                               const struct persp_midpoint_format *f, int x0, int y,
                                               int n, float *s1, float *s2,
                                               struct persp_midpoint_span *span,
                                               struct persp_midpoint_pixel *px);

#endif
