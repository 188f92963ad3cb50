/*
 * The sources' claims that persp measures, with their published figures and
 * the thresholds a measurement is held to: one table, read by the report
 * page's verdicts (report_html.c, shading_report.c) and by the tests that
 * assert the claims (tests/unit/test_accuracy_claims.c,
 * test_shading_accuracy.c); tests/unit/test_claims_doc.c checks that
 * docs/REPRODUCTION.md, "Claims", states the same numbers.
 */
#ifndef PERSP_ANALYSIS_CLAIMS_H
#define PERSP_ANALYSIS_CLAIMS_H

typedef enum persp_claim_id {
    PERSP_CLAIM_SHIFTED_ANCHOR,   /* [Romanyuk-PCF] §4.6 */
    PERSP_CLAIM_BEZIER,           /* §4.7, first approach */
    PERSP_CLAIM_BEZIER_QUADT,     /* §4.7, second approach */
    PERSP_CLAIM_QUADRATIC_UNNORM, /* §4.6 end */
    PERSP_CLAIM_CUBIC,            /* §4.4 */
    PERSP_CLAIM_INCREMENTAL,      /* [Romaniuk-Incr] (3)-(4) */
    PERSP_CLAIM_AFFINE_GROWS,     /* §4.2 Fig. 4.4 */
    PERSP_CLAIM_INCREMENTAL_SPEED, /* [Romaniuk-ACIT18] */
    PERSP_CLAIM_TW_BOUNDS,        /* §4.3, t_w on a segment (S3) */
    PERSP_CLAIM_QUADRATIC_HBAR3,  /* §4.3, the quadratic only for ħ <= 3 (S5) */
    PERSP_CLAIM_COUNT
} persp_claim_id;

/* Thresholds are in the units docs/REPRODUCTION.md states them in (per
 * cent for relative errors and gains, texels for absolute errors); 0: the
 * claim has none of that kind. */
typedef struct persp_claim {
    const char *doc;       /* its label in docs/REPRODUCTION.md: "1".."7", "S3", or a heading */
    const char *source;    /* "[Romanyuk-PCF] §4.6" */
    const char *text;      /* the claim, as the report page states it */
    const char *published; /* the published figure, as the report page shows it */
    double lo, hi;         /* window of a ratio that holds */
    double bound;          /* upper bound that holds */
    double factor;         /* "N times less than" that holds */
    double above;          /* lower bound (claim-specific, see its uses) */
    const double *series;  /* published values, nseries of them */
    int nseries;
    double tol[2];         /* points by which series may be exceeded (S3: each approximation) */
} persp_claim;

const persp_claim *persp__claim(persp_claim_id id);

/* S3's depth ratios ħ = 2..5 and its published figures, in per cent:
 * series[0..3] piecewise quadratic, series[4..7] cubic. */
#define PERSP_CLAIM_TW_HBARS 4

#endif
