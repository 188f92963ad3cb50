/*
 * The approximating methods (quadratic, quadratic-shifted, quadratic-unnorm,
 * quadratic-pw, cubic, subdiv, subdiv-quad, bezier, biquadratic, bicubic) against the
 * double-precision rational form on the random-triangles set, each checked
 * pixel by pixel against its documented error bound, which the test computes
 * from the method's definition (its nodes) and the triangle's planes.
 */
/* ctest-split: each (over a minute in all under ASan + UBSan) */
#include "methods_harness.h"

#include "interp/poly.h"

#include <float.h>

#define TRIS_PER_RATIO 10
/* Float output: half an ulp of the value, plus double-precision work. */
#define OUT_SLACK(x) (0x1p-24 * fabs(x) + 1e-13)

typedef enum bound_kind {
    B_QUAD, B_SHIFTED, B_UNNORM, B_PWQUAD, B_CUBIC, B_SUBDIV, B_SUBDIV_QUAD, B_BEZ_STEP,
    B_BEZ_QUADT, B_BIQUAD, B_BICUBIC
} bound_kind;

typedef struct approx_ctx {
    persp_method_sel sel;
    bound_kind kind;
    int step;              /* subdiv N */
    persp_method_prep prep;
    double tri_bound;      /* bi-polynomial bound of the current triangle */
    double max_err, max_ratio;
    uint64_t pixels;
    double max_err_by_ratio[H_RATIO_COUNT];
    size_t ratio_index;
} approx_ctx;

/* Point-wise remainder bound |cross|·|γ|^(m−1)·|Π(k − k_j)|/Dmin^(m+1) of the
 * polynomial through nodes[] (poly.h), Dmin over [lo, hi]. */
static double node_bound(const persp_rat1 *f, const double *nodes, int m, double k, double lo,
                         double hi)
{
    double d0 = f->gamma * lo + f->delta, d1 = f->gamma * hi + f->delta;
    double dmin = fmin(d0, d1);
    double cross = fabs(f->beta * f->gamma - f->alpha * f->delta);
    double prod = 1.0;
    for (int j = 0; j < m; j++) prod *= fabs(k - nodes[j]);
    return cross * pow(fabs(f->gamma), m - 1) * prod / pow(dmin, m + 1);
}

/* Largest |u_B(t) − f(x(t))| over the Bézier of f on [0, L] (dense sampling
 * of the curve; the definition of E_B in bezier.c). Also returns the
 * largest |du/dx| of f on the span. */
static double bezier_gap(const persp_rat1 *f, double L, double *slope)
{
    double x1, u1;
    persp__bezier_control(f, L, &x1, &u1);
    double u0 = persp__rat1_eval(f, 0.0), u2 = persp__rat1_eval(f, L);
    double gap = 0.0;
    for (int i = 0; i <= 4000; i++) {
        double t = i / 4000.0;
        double x = 2.0 * t * (1.0 - t) * x1 + t * t * L;
        double u = (1 - t) * (1 - t) * u0 + 2.0 * t * (1 - t) * u1 + t * t * u2;
        /* Compare and select rather than fmax (the same for these values,
         * never NaN): GCC 12's aarch64 vectoriser stops with an internal
         * compiler error (vect_transform_reduction) on fmax reductions here. */
        const double d = fabs(u - persp__rat1_eval(f, x));
        if (d > gap) gap = d;
    }
    double cross = fabs(f->beta * f->gamma - f->alpha * f->delta);
    double dmin = fmin(f->delta, f->gamma * L + f->delta);
    *slope = cross / (dmin * dmin);
    return gap;
}

/* |x(t̂(X)) − X| for the quadratic t̂ through (0,0), (x(½),½), (L,1). */
static double quadt_xerr(const persp_rat1 *f, double L)
{
    double x1, u1;
    persp__bezier_control(f, L, &x1, &u1);
    double xm = 0.5 * x1 + 0.25 * L;
    const double xs[3] = {0, xm, L}, ts[3] = {0, 0.5, 1};
    double worst = 0.0;
    for (int i = 0; i <= 400; i++) {
        double X = L * i / 400.0;
        /* Lagrange form, independent of the method's code path. */
        double t = ts[1] * (X - xs[0]) * (X - xs[2]) / ((xs[1] - xs[0]) * (xs[1] - xs[2])) +
                   ts[2] * (X - xs[0]) * (X - xs[1]) / ((xs[2] - xs[0]) * (xs[2] - xs[1]));
        double x = 2.0 * t * (1.0 - t) * x1 + t * t * L;
        const double d = fabs(x - X); /* as in bezier_gap */
        if (d > worst) worst = d;
    }
    return worst;
}

static double shift_max_prod(double tau)
{
    return tau == 0.5 ? 0.04811252243246882 : 0.0;
}

static void check_span(void *user, const persp_rational *r, int x0, int y, int n)
{
    approx_ctx *c = user;
    float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX];
    c->sel.m->span(r, &c->sel.params, &c->prep, x0, y, n, u, v, NULL);
    persp_span_rat s;
    persp__span_rat_init(r, x0, y, &s);
    const double L = n - 1;
    double bez_slope[2] = {0, 0}, bez_gap[2] = {0, 0}, qt_err = 0.0;
    if ((c->kind == B_BEZ_STEP || c->kind == B_BEZ_QUADT) && n >= 3) {
        for (int w = 0; w < 2; w++) {
            persp_rat1 f = persp__span_rat1(&s, w);
            bez_gap[w] = bezier_gap(&f, L, &bez_slope[w]);
        }
        if (c->kind == B_BEZ_QUADT) {
            persp_rat1 f = persp__span_rat1(&s, 0);
            qt_err = quadt_xerr(&f, L);
        }
    }
    (void)shift_max_prod;
    for (int k = 0; k < n; k++) {
        double ex[2];
        persp__rational_eval(r, x0 + k, y, &ex[0], &ex[1]);
        const float got[2] = {u[k], v[k]};
        for (int w = 0; w < 2; w++) {
            persp_rat1 f = persp__span_rat1(&s, w);
            double bound = 0.0;
            if (n <= 2 && c->kind != B_BIQUAD && c->kind != B_BICUBIC) {
                bound = 0.0; /* both pixels are anchors */
            } else {
                switch (c->kind) {
                case B_QUAD:
                case B_UNNORM: {
                    const double nodes[3] = {0, L / 2, L};
                    bound = node_bound(&f, nodes, 3, k, 0, L);
                    break;
                }
                case B_SHIFTED: {
                    double e0 = persp__rat1_eval(&f, 0), e1 = persp__rat1_eval(&f, L);
                    double tau = persp__quad_shift_anchor(e0, e1);
                    const double nodes[3] = {0, tau * L, L};
                    bound = node_bound(&f, nodes, 3, k, 0, L);
                    break;
                }
                case B_PWQUAD: {
                    /* Pixels 0..⌊L/2⌋ on the first half's quadratic, the rest
                     * on the second's (pwquad.c). */
                    if (k <= (n - 1) / 2) {
                        const double nodes[3] = {0, L / 4, L / 2};
                        bound = node_bound(&f, nodes, 3, k, 0, L / 2);
                    } else {
                        const double nodes[3] = {L / 2, 3 * L / 4, L};
                        bound = node_bound(&f, nodes, 3, k, L / 2, L);
                    }
                    break;
                }
                case B_CUBIC: {
                    const double nodes[4] = {0, L / 3, 2 * L / 3, L};
                    bound = node_bound(&f, nodes, 4, k, 0, L);
                    break;
                }
                case B_SUBDIV:
                case B_SUBDIV_QUAD: {
                    int j = (k / c->step) * c->step;
                    if (j == n - 1) j -= c->step; /* the last pixel closes the previous segment */
                    if (j < 0) j = 0;
                    double len = fmin((double)c->step, L - j);
                    if (c->kind == B_SUBDIV) {
                        const double nodes[2] = {j, j + len};
                        bound = node_bound(&f, nodes, 2, k, j, j + len);
                    } else {
                        const double nodes[3] = {j, j + len / 2, j + len};
                        bound = node_bound(&f, nodes, 3, k, j, j + len);
                    }
                    break;
                }
                case B_BEZ_STEP:
                    bound = bez_gap[w] + bez_slope[w] * (1.0 / 64.0);
                    break;
                case B_BEZ_QUADT:
                    bound = bez_gap[w] + bez_slope[w] * qt_err;
                    break;
                case B_BIQUAD:
                case B_BICUBIC:
                    bound = c->tri_bound;
                    break;
                }
            }
            double slack = OUT_SLACK(ex[w]);
            if (c->kind == B_UNNORM && n > 2) {
                /* Cramer's rule on screen x: the A3 terms reach X³·|u|/|Δ|
                 * with |Δ| = L³/4, cancelled in double (quadratic.c). */
                double X = x0 + 0.5 + L;
                slack += 64.0 * 0x1p-53 * X * X * X * (fabs(ex[w]) + 1.0) / (L * L * L / 4.0);
            }
            if ((c->kind == B_BEZ_STEP || c->kind == B_BEZ_QUADT) && n > 2)
                slack += 1e-12 * (fabs(ex[w]) + 1.0); /* sampled E_B: 4000 steps on a smooth gap */
            double err = fabs((double)got[w] - ex[w]);
            if (!(err <= bound + slack))
                fail_msg("%s: pixel (%d,%d) of a %d-px span, coordinate %d: error %.4g > bound %.4g",
                         c->sel.m->name, x0 + k, y, n, w, err, bound + slack);
            double et = err * H_TEXELS;
            if (et > c->max_err) c->max_err = et;
            if (et > c->max_err_by_ratio[c->ratio_index]) c->max_err_by_ratio[c->ratio_index] = et;
            if (err / (bound + slack) > c->max_ratio) c->max_ratio = err / (bound + slack);
        }
    }
    c->pixels += (uint64_t)n;
}

/* (1 + Λ_m)·|N(c)∇D − D(c)∇N|·|∇D|^m·h^(m+1)/Dmin^(m+2) (bipoly.c), the
 * larger of the u and v bounds. */
static double bipoly_bound(const persp_rational *r, const persp_rational_vertices *v, int m)
{
    double cx = (v->x[0] + v->x[1] + v->x[2]) / 3, cy = (v->y[0] + v->y[1] + v->y[2]) / 3;
    double h = 0, dmin = INFINITY;
    for (int i = 0; i < 3; i++) {
        h = fmax(h, hypot(v->x[i] - cx, v->y[i] - cy));
        dmin = fmin(dmin, r->g * v->x[i] + r->h * v->y[i] + r->i);
    }
    double Dc = r->g * cx + r->h * cy + r->i;
    double gradD = hypot(r->g, r->h);
    double lambda = m == 2 ? 5.0 / 3.0 : 2.27;
    double worst = 0;
    for (int w = 0; w < 2; w++) {
        double na = w ? r->d : r->a, nb = w ? r->e : r->b, nc = w ? r->f : r->c;
        double Nc = na * cx + nb * cy + nc;
        double cross = hypot(Nc * r->g - Dc * na, Nc * r->h - Dc * nb);
        double R = cross * pow(gradD, m) * pow(h, m + 1) / pow(dmin, m + 2);
        worst = fmax(worst, (1 + lambda) * R);
    }
    return worst;
}

static void run_method(const char *spec, bound_kind kind, int step)
{
    approx_ctx c;
    memset(&c, 0, sizeof c);
    c.sel = h_method(spec);
    c.kind = kind;
    c.step = step;
    test_rng rng = {0x5eed0001ULL};
    for (size_t ri = 0; ri < H_RATIO_COUNT; ri++) {
        c.ratio_index = ri;
        for (int i = 0; i < TRIS_PER_RATIO; i++) {
            h_triangle T;
            h_random_triangle(&rng, h_ratios[ri], &T);
            memset(&c.prep, 0, sizeof c.prep);
            if (c.sel.m->prepare) c.sel.m->prepare(&T.t.rat, &T.v, &c.sel.params, &c.prep, NULL);
            if (kind == B_BIQUAD || kind == B_BICUBIC)
                c.tri_bound = bipoly_bound(&T.t.rat, &T.v, kind == B_BIQUAD ? 2 : 3);
            h_for_each_span(&T, check_span, &c);
        }
    }
    print_message("%-18s %8llu px  max %.4g texels (max error/bound %.2f); by ratio:", spec,
                  (unsigned long long)c.pixels, c.max_err, c.max_ratio);
    for (size_t ri = 0; ri < H_RATIO_COUNT; ri++) print_message(" %.3g", c.max_err_by_ratio[ri]);
    print_message("\n");
    assert_true(c.pixels > 10000);
}

static void test_quadratic(void **s) { (void)s, run_method("quadratic", B_QUAD, 0); }
static void test_shifted(void **s) { (void)s, run_method("quadratic-shifted", B_SHIFTED, 0); }
static void test_unnorm(void **s) { (void)s, run_method("quadratic-unnorm", B_UNNORM, 0); }
static void test_cubic(void **s) { (void)s, run_method("cubic", B_CUBIC, 0); }
static void test_pwquad(void **s) { (void)s, run_method("quadratic-pw", B_PWQUAD, 0); }
static void test_subdiv(void **s)
{
    (void)s;
    run_method("subdiv:4", B_SUBDIV, 4);
    run_method("subdiv:8", B_SUBDIV, 8);
    run_method("subdiv", B_SUBDIV, 16);
    run_method("subdiv:32", B_SUBDIV, 32);
}
static void test_subdiv_quad(void **s)
{
    (void)s;
    run_method("subdiv-quad:4", B_SUBDIV_QUAD, 4);
    run_method("subdiv-quad:16", B_SUBDIV_QUAD, 16);
    run_method("subdiv-quad:32", B_SUBDIV_QUAD, 32);
}
static void test_bezier(void **s)
{
    (void)s;
    run_method("bezier", B_BEZ_STEP, 0);
    run_method("bezier:quadt", B_BEZ_QUADT, 0);
}
static void test_bipoly(void **s)
{
    (void)s;
    run_method("biquadratic", B_BIQUAD, 0);
    run_method("bicubic", B_BICUBIC, 0);
}

/* Spans of 1 and 2 pixels, and the anchors of longer spans, are exact up to
 * the float rounding, for every span method of this family. */
static void test_short_spans_and_anchors(void **state)
{
    (void)state;
    static const char *specs[] = {"incremental", "incremental:k=4", "incremental:bidir",
                                  "subdiv:4", "subdiv", "subdiv-quad:8", "quadratic",
                                  "quadratic-shifted", "quadratic-unnorm", "quadratic-pw",
                                  "cubic", "bezier", "bezier:quadt"};
    test_rng rng = {77};
    for (int trial = 0; trial < 40; trial++) {
        h_triangle T;
        h_random_triangle(&rng, h_ratios[trial % H_RATIO_COUNT], &T);
        const persp_rational *r = &T.t.rat;
        int y = (T.t.ymin + T.t.ymax) / 2;
        int x0 = (T.t.xmin + T.t.xmax) / 2;
        for (size_t m = 0; m < sizeof specs / sizeof specs[0]; m++) {
            persp_method_sel sel = h_method(specs[m]);
            for (int n = 1; n <= 40; n += (n < 3 ? 1 : 13)) {
                float u[64], v[64];
                for (int k = 0; k < 64; k++) u[k] = v[k] = NAN;
                sel.m->span(r, &sel.params, NULL, x0, y, n, u, v, NULL);
                for (int k = 0; k < n; k++) {
                    assert_true(isfinite(u[k]) && isfinite(v[k]));
                    if (!(n <= 2 || k == 0 || k == n - 1)) continue;
                    double eu, ev;
                    persp__rational_eval(r, x0 + k, y, &eu, &ev);
                    double tol_u = 4.0 * 0x1p-24 * fabs(eu) + 1e-12;
                    double tol_v = 4.0 * 0x1p-24 * fabs(ev) + 1e-12;
                    if (fabs(u[k] - eu) > tol_u || fabs(v[k] - ev) > tol_v)
                        fail_msg("%s n=%d k=%d: (%.9g, %.9g) vs exact (%.9g, %.9g)", specs[m], n, k,
                                 u[k], v[k], eu, ev);
                }
                for (int k = n; k < 64; k++) assert_true(isnan(u[k]) && isnan(v[k]));
            }
        }
    }
}

/* Every method counts its operations; the per-pixel division count follows
 * the method's definition. */
static void test_op_counts(void **state)
{
    (void)state;
    test_rng rng = {5};
    h_triangle T;
    h_random_triangle(&rng, 3.0, &T);
    const persp_rational *r = &T.t.rat;
    int y = (T.t.ymin + T.t.ymax) / 2;
    int x0 = T.t.xmin;
    float u[64], v[64];
    struct { const char *spec; uint64_t div; } want[] = {
        {"incremental", 64}, {"subdiv:16", 5 + 1}, {"subdiv:4", 17 + 1}, /* nodes + 1/len of the short last segment */ {"quadratic", 4},
        {"quadratic-unnorm", 4}, {"bezier:step", 3},
        {"quadratic-pw", 24}, /* per coordinate and half: 3 nodes + 3 divided differences */
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        persp_method_sel sel = h_method(want[i].spec);
        persp_opcount ops;
        memset(&ops, 0, sizeof ops);
        sel.m->span(r, &sel.params, NULL, x0, y, 64, u, v, &ops);
        if (ops.div != want[i].div)
            fail_msg("%s: %llu divisions, expected %llu", want[i].spec, (unsigned long long)ops.div,
                     (unsigned long long)want[i].div);
        assert_true(ops.add >= 64);
    }
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quadratic),   cmocka_unit_test(test_shifted),
        cmocka_unit_test(test_unnorm),      cmocka_unit_test(test_cubic),
        cmocka_unit_test(test_pwquad),
        cmocka_unit_test(test_subdiv),      cmocka_unit_test(test_subdiv_quad),
        cmocka_unit_test(test_bezier),      cmocka_unit_test(test_bipoly),
        cmocka_unit_test(test_short_spans_and_anchors), cmocka_unit_test(test_op_counts),
    };
    return TEST_RUN(argc, argv, tests);
}
