/*
 * Shading accuracy (persp accuracy --shading; src/analysis/shading.c):
 *  - the ΔI analysis of [Romanyuk-PCF] §4.2 (Fig. 4.3-4.4),
 *  - the polynomial approximations of t_w of §4.3 against (4.6),
 *  - every shading mode against the exact per-pixel reference on seeded
 *    random triangles (the renderer's own span shaders, measured per pixel)
 *    and on a lit scene (whole renders).
 */
#ifndef PERSP_ANALYSIS_SHADING_H
#define PERSP_ANALYSIS_SHADING_H

#include "interp/poly.h"
#include "persp_analysis.h"

/* Δ(u) = u·(1 − 1/(r + u·(1 − r))), r = z2/z1 ([Romanyuk-PCF] (4.1)): the
 * factor by which screen-linear Gouraud misses the perspective-correct
 * intensity, ΔI = (I_B − I_A)·Δ(u). */
double persp__delta_factor(double u, double r);
/* The extremum of Δ over u ∈ [0, 1], derived: Δ'(u) = 1 − r/D², D = r + u(1 − r),
 * so D = √r, u* = √r/(1 + √r) and Δ(u*) = (√r − 1)/(√r + 1) (negative for
 * r < 1; |Δ| is the same for r and 1/r). Writes u* when argmax is non-NULL. */
double persp__delta_extremum(double r, double *argmax);

/* t_w(t_v) = t_v/(ħ − t_v·(ħ − 1)), ħ = Z_B/Z_A: (4.7) corrected. */
double persp__tw_exact(double tv, double hbar);

/* Power-basis coefficients (c[0] + c[1]·t + c[2]·t² + c[3]·t³) of the t_w
 * approximations of §4.3, derived in closed form (Z_A = 1, Z_B = ħ):
 *   quadratic through t_v = 0, 1/2, 1 (piece ignored);
 *   piecewise quadratic, piece 0 through 0, 1/4, 1/2 and piece 1 through
 *     1/2, 3/4, 1;
 *   cubic through 0, 1/3, 2/3, 1 (piece ignored). */
void persp__tw_coeffs(persp_approx_kind kind, double hbar, int piece, double c[4]);

/* Errors of one t_w approximation on a dense grid of t_v. */
typedef struct persp_tw_error {
    double abs_max;     /* max |p − t_w| over [0, 1] (fraction of the full range) */
    double rel_max;     /* max |p − t_w|/t_w over (0, 1] */
    double rel_third;   /* max |p − t_w|/t_w over [1/3, 1] */
} persp_tw_error;
/* Evaluates the polynomial as the renderer does (persp__approx_span, the
 * code shared with the texture methods) on 3073 points of t_v, where every
 * node of every kind is a sample. */
void persp__tw_error(persp_approx_kind kind, double hbar, persp_tw_error *out);

/* Errors of one shading mode against the exact per-pixel reference. */
typedef struct persp_shade_err {
    persp_shading mode;
    uint64_t pixels;
    double col_max, col_mean; /* |colour − exact Phong| in 8-bit levels, worst channel */
    double col_over;          /* share of pixels more than 1 level off */
    double own_max;           /* gouraud modes: vs perspective-correct Gouraud in double;
                                 others: = col_max */
    int has_normals;          /* 0: the ang_* and len_max fields are not meaningful */
    double ang_max, ang_mean; /* angle to the exact interpolated normal, degrees */
    double len_max;           /* max | |N| − 1 | of the normals the mode lights with */
} persp_shade_err;

/* The modes measured: every persp_shading but NONE. */
#define PERSP_SHADE_MODES (PERSP_SHADING_COUNT - PERSP_SHADING_FLAT)

/* Seeded random lit triangles of depth ratio hbar (at most `triangles`),
 * rendered span by span with each mode's span shader; out[i] is mode PERSP_SHADING_FLAT + i. */
persp_status persp__shading_random(persp_context *ctx, uint64_t seed, double hbar, int triangles,
                                   persp_shade_err out[PERSP_SHADE_MODES]);

/* The built-in lit test scene: a floor reaching far back, a coarse sphere, a
 * torus and a cylinder, untextured, with a point and a directional light. */
persp_status persp__shading_test_scene(persp_context *ctx, persp_scene **out);

/* Renders scene at w × h with every mode and compares each image with the
 * phong-pc image (exact t_w per pixel): colour fields only, pixels covered
 * by geometry. */
persp_status persp__shading_scene_compare(persp_context *ctx, const persp_scene *scene, int w,
                                          int h, persp_shade_err out[PERSP_SHADE_MODES]);

#endif
