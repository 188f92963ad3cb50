/* The sources' claims and their thresholds (see claims.h); the reasons for
 * each threshold are in docs/REPRODUCTION.md under the claim's label. */
#include "analysis/claims.h"

#include <stddef.h>

static const double tw_published[2 * PERSP_CLAIM_TW_HBARS] = {1.0,  4.0, 8.0, 13.0,
                                                             0.64, 2.9, 6.3, 10.6};
static const double speed_published[1] = {26.0};

static const persp_claim claims[PERSP_CLAIM_COUNT] = {
    [PERSP_CLAIM_SHIFTED_ANCHOR] = {.doc = "1",
                                    .source = "[Romanyuk-PCF] §4.6",
                                    .text = "shifting the inner anchor to x_int = 0.25 reduces "
                                            "the maximum relative error by almost half",
                                    .published = "ratio ≈ 0.5",
                                    .lo = 0.4,
                                    .hi = 0.7},
    [PERSP_CLAIM_BEZIER] = {.doc = "2",
                            .source = "[Romanyuk-PCF] §4.7",
                            .text = "Bézier with the inner control point at the tangents' "
                                    "intersection: max relative error ≤ 0.7 %, 7 times less "
                                    "than the quadratic",
                            .published = "≤ 0.7 %, 7×",
                            .bound = 0.7,
                            .factor = 7.0},
    /* "Almost 3 times": 2.5. */
    [PERSP_CLAIM_BEZIER_QUADT] = {.doc = "3",
                                  .source = "[Romanyuk-PCF] §4.7",
                                  .text = "t as a quadratic in x: max relative error ≤ 1.7 %, "
                                          "almost 3 times less than the quadratic",
                                  .published = "≤ 1.7 %, ≈3×",
                                  .bound = 1.7,
                                  .factor = 2.5},
    /* The same polynomial: max errors within 0.001 texels. */
    [PERSP_CLAIM_QUADRATIC_UNNORM] = {.doc = "4",
                                      .source = "[Romanyuk-PCF] §4.6",
                                      .text = "the quadratic on un-normalised x (Cramer's rule) "
                                              "gives the same approximation",
                                      .published = "same errors",
                                      .bound = 1e-3},
    [PERSP_CLAIM_CUBIC] = {.doc = "5",
                           .source = "[Romanyuk-PCF] §4.4",
                           .text = "the cubic through the thirds is more accurate than the "
                                   "quadratic",
                           .published = "more accurate"},
    /* Exact: below 1e-4 texels, float rounding. */
    [PERSP_CLAIM_INCREMENTAL] = {.doc = "6",
                                 .source = "[Romaniuk-Incr] (3)–(4)",
                                 .text = "the incremental form is exact",
                                 .published = "exact",
                                 .bound = 1e-4},
    [PERSP_CLAIM_AFFINE_GROWS] = {.doc = "7",
                                  .source = "[Romanyuk-PCF] §4.2 Fig. 4.4",
                                  .text = "the affine error grows with the depth ratio",
                                  .published = "11.5 → 113 texels (docs, 40 triangles)"},
    /* Holds from half the published gain on (timing noise), partly above 0. */
    [PERSP_CLAIM_INCREMENTAL_SPEED] = {.doc = "Speed of the incremental form",
                                       .source = "[Romaniuk-ACIT18]",
                                       .text = "the incremental form renders faster than the "
                                               "per-pixel division",
                                       .published = "+26 %",
                                       .above = 13.0,
                                       .series = speed_published,
                                       .nseries = 1},
    [PERSP_CLAIM_TW_BOUNDS] = {.doc = "S3",
                               .source = "[Romanyuk-PCF] §4.3",
                               .text = "t_w on a segment of depth ratio ħ = 2, 3, 4, 5: piecewise "
                                       "quadratic does not exceed 1, 4, 8, 13 %; cubic 0.64, 2.9, "
                                       "6.3, 10.6 %",
                               .published = "1 / 4 / 8 / 13 %; 0.64 / 2.9 / 6.3 / 10.6 %",
                               .series = tw_published,
                               .nseries = 2 * PERSP_CLAIM_TW_HBARS,
                               .tol = {0.5, 0.2}},
    /* Satisfactory: max absolute t_w error below 8 % at ħ = 3, and not
     * above 4: over 10 % there. */
    [PERSP_CLAIM_QUADRATIC_HBAR3] = {.doc = "S5",
                                     .source = "[Romanyuk-PCF] §4.3",
                                     .text = "the quadratic approximation gives satisfactory "
                                             "results only for ħ ≤ 3",
                                     .published = "ħ ≤ 3",
                                     .bound = 8.0,
                                     .above = 10.0},
};

const persp_claim *persp__claim(persp_claim_id id)
{
    return id >= 0 && id < PERSP_CLAIM_COUNT ? &claims[id] : NULL;
}
