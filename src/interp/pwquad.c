/*
 * `quadratic-pw` — piecewise quadratic along the span ([Romanyuk-PCF] §4.3).
 *
 * The chapter improves the quadratic approximation of t_w by "piecewise
 * quadratic interpolation on two intervals of change t_v": one quadratic on
 * each half of the line, each through its ends and its middle. Applied to
 * the texture coordinates directly, on the span k = 0..L (L = n − 1):
 *
 *     k ∈ [0, ⌊L/2⌋]       nodes 0, L/4, L/2
 *     k ∈ [⌊L/2⌋ + 1, L]   nodes L/2, 3L/4, L
 *
 * each piece interpolating u(k) = (n1 + a·k)/(q + g·k) (and v) at its nodes,
 * evaluated by forward differences (2 additions per pixel and coordinate).
 * This is the shape the perspective-correct shading `phong-pc:pwquad` gives
 * t_w; both run persp__approx_span(PERSP_APPROX_PWQUAD) of poly.c, so the
 * texture and the shading approximation are the same code. (u is a Möbius
 * function of t_w, and t_w of t_v, so the interpolant of u at the nodes is
 * not the chapter's t_w polynomial mapped through u; it is the same
 * construction applied to u.)
 *
 * Error bound (exact remainder of interpolation, poly.h), per piece of
 * length ℓ = L/2 with ρ_p = Dmax/Dmin over the piece and |u'|max its largest
 * slope:
 *
 *     |Δu| ≤ |u'|max · ℓ · (ρ_p − 1)² / (12·√3)
 *
 * (about 1/8 of the single quadratic's bound for small depth variation:
 * half the length, half the depth variation per piece), plus the float
 * rounding of the output. The tests check the point-wise form
 * |cross|·g²·|Π(k − k_j)|/Dmin_p³ per piece.
 *
 * Cost: per span 6 mul, 6 add (planes) and, per coordinate and piece, 3 div,
 * 6 mul, 6 add (the nodes, each a separate rational evaluation in the shared
 * code) + 3 div, 3 mul, 9 add (divided differences) + 20 mul, 8 add (the
 * differences): 24 div per span in all, against 4 for `quadratic`. Per pixel
 * 4 add. Spans of one or two pixels are evaluated exactly.
 */
#include "interp/methods.h"
#include "interp/poly.h"

static void pwquad_span(const persp_rational *r, const persp_method_params *params,
                        const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                        persp_opcount *ops)
{
    (void)params, (void)prep;
    if (n <= 0) return;
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    PERSP_SPAN_RAT_INIT_OPS(ops);
    const persp_rat1 fu = persp__span_rat1(&s, 0), fv = persp__span_rat1(&s, 1);
    persp__approx_span(&fu, PERSP_APPROX_PWQUAD, 0.5, n, s1, ops);
    persp__approx_span(&fv, PERSP_APPROX_PWQUAD, 0.5, n, s2, ops);
}

const persp_method persp__method_quadratic_pw = {
    .name = "quadratic-pw",
    .params_help = "",
    .summary = "two quadratics along the span, each through its half's ends and middle",
    .source = "[Romanyuk-PCF] §4.3 (piecewise quadratic on two intervals)",
    .cost = "4 add /px; 24 div, 122 mul, 98 add /span",
    .span = pwquad_span,
};
