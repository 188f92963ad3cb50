/*
 * `adaptive` — choosing the rasterization direction from the coefficients of
 * Heckbert's form ([Romanyuk-PCF] §4.9, statements 4.1 and 4.2, affine case (4.48)).
 *
 * The denominator D = g·x + h·y + i of (4.8) is constant along rows when
 * g = 0 and along columns when h = 0. Then one reciprocal per row (column)
 * makes u and v linear along it: u = (a·x + A_u)·B_u with A_u = b·y + c,
 * B_u = 1/(h·y + i) (statement 4.1). If moreover d = 0 (resp. b = 0), v (resp.
 * u) is constant along the line and is computed once (the statements proper:
 * "d = g = 0: v constant along rows", "b = h = 0: u constant along
 * columns"). Statement 4.1 needs only g = 0 for the saving of divisions;
 * d = 0 adds the constant coordinate, so the test here is on g (h) and d (b)
 * separately. Corridor walls, whose v is constant along columns (e = h = 0),
 * take the column path too. With g = h = 0 (affine, (4.48)) one reciprocal
 * per triangle suffices.
 *
 * "Zero" is judged against the triangle: g counts as zero when its
 * contribution over the bounding box, |g|·width, is below 2^-22 of the
 * smallest vertex denominator, so treating D as constant changes u, v by less
 * than 2^-22 relative (below single-precision rounding); d counts as zero when
 * v changes by less than 2^-22 texel along a row (likewise b, h by columns).
 * D is evaluated at the box centre's column (row) so the neglected part is
 * at most half that.
 *
 * Paths and cost (counted in ops):
 *   affine  (g≈h≈0): 1 div per triangle; 1 mul, 1 add /px per varying
 *                    coordinate
 *   row     (g≈0):   1 div /span; 1 mul, 1 add /px per varying coordinate
 *   column  (h≈0):   traversal by columns, 1 div /column; 2 mul, 1 add /px per
 *                    varying coordinate (the `span` form pays 1 div /px and
 *                    returns the same values)
 *   otherwise:       the fallback method (`adaptive:fallback=NAME[:PARAMS]`,
 *                    default `exact`), with its own cost and traversal.
 * Classifying costs 8 mul, 6 add, 6 cmp per call (it is repeated per span
 * because the per-triangle state belongs to the fallback; prepare keeps the
 * vertices it reads in the state's tail, PERSP_METHOD_PREP_TAIL). Spans and
 * traversals need that prepared state: without one they return zeros.
 * Error: |Δs| ≤ 2^-22·|s| (the neglected coefficient) + float rounding on the
 * cheap paths; the fallback's bound otherwise.
 */
#include "interp/method.h"
#include "interp/methods.h"

#include <math.h>
#include <string.h>

#define AD_TOL (1.0 / 4194304.0) /* 2^-22 */
#define AD_BLOCK 64
#define AD_FB_BYTES 30 /* parameter bytes kept for the fallback; 2 more hold its index */
_Static_assert(AD_FB_BYTES + sizeof(uint16_t) <= PERSP_METHOD_PARAM_BYTES,
               "the fallback's parameters and index do not fit in persp_method_params");
/* Affine triangles keep 1/D at the box centre; others the fallback's state. */
PERSP_METHOD_PREP_FITS(double);

enum { AD_AFFINE, AD_ROW, AD_COLUMN, AD_FALLBACK, AD_INVALID };

typedef struct ad_class {
    int kind;
    int const1, const2; /* s1 (s2) constant along the cheap direction */
    double xc, yc;      /* box centre, pixel-centre coordinates */
} ad_class;

static persp_status ad_parse(const char *text, persp_method_params *params)
{
    memset(params, 0, sizeof *params);
    if (!text) return PERSP_OK;
    if (strncmp(text, "fallback=", 9) != 0) return PERSP_ERR_INVALID_ARGUMENT;
    persp_method_sel sel;
    if (persp__method_resolve(NULL, text + 9, &sel) != PERSP_OK) return PERSP_ERR_INVALID_ARGUMENT;
    if (sel.m == &persp__method_adaptive) return PERSP_ERR_INVALID_ARGUMENT;
    for (size_t b = AD_FB_BYTES; b < PERSP_METHOD_PARAM_BYTES; b++)
        if (sel.params.bytes[b]) return PERSP_ERR_UNSUPPORTED;
    size_t idx = 0;
    while (idx < persp__method_count() && persp__method_at(idx) != sel.m) idx++;
    if (idx >= persp__method_count() || idx + 1 > 0xffff) return PERSP_ERR_INVALID_ARGUMENT;
    memcpy(params->bytes, sel.params.bytes, AD_FB_BYTES);
    uint16_t stored = (uint16_t)(idx + 1);
    memcpy(params->bytes + AD_FB_BYTES, &stored, sizeof stored);
    return PERSP_OK;
}

/* The fallback entry and its parameters (aligned copy). */
static const persp_method *ad_fallback(const persp_method_params *params, persp_method_params *fbp)
{
    memset(fbp, 0, sizeof *fbp);
    uint16_t stored = 0;
    if (params) {
        memcpy(fbp->bytes, params->bytes, AD_FB_BYTES);
        memcpy(&stored, params->bytes + AD_FB_BYTES, sizeof stored);
    }
    const persp_method *m = stored ? persp__method_at((size_t)stored - 1) : NULL;
    return m ? m : &persp__method_exact;
}

/* Reciprocal of a denominator, 0 where it is not positive (pixels outside
 * any visible triangle): the values there are 0, never a division by zero. */
static double ad_recip(double D) { return D > 0.0 && isfinite(D) ? 1.0 / D : 0.0; }

static double ad_scale(float s) { return (s > 0.0f && isfinite(s)) ? (double)s : 1.0; }

/* The vertices' window positions, kept where the fallback's state leaves
 * room (PERSP_METHOD_PREP_TAIL). */
_Static_assert(6 * sizeof(double) <= PERSP_METHOD_PREP_TAIL, "adaptive's vertices fit the tail");
static void ad_keep_vertices(persp_method_prep *prep, const persp_rational_vertices *v)
{
    unsigned char *tail = prep->bytes + PERSP_METHOD_PREP_BYTES - PERSP_METHOD_PREP_TAIL;
    memcpy(tail, v->x, sizeof v->x);
    memcpy(tail + sizeof v->x, v->y, sizeof v->y);
}

static void ad_vertices(const persp_method_prep *prep, double x[3], double y[3])
{
    const unsigned char *tail = prep->bytes + PERSP_METHOD_PREP_BYTES - PERSP_METHOD_PREP_TAIL;
    memcpy(x, tail, 3 * sizeof *x);
    memcpy(y, tail + 3 * sizeof *x, 3 * sizeof *y);
}

static ad_class ad_classify(const persp_rational *r, const double vx[3], const double vy[3],
                            persp_opcount *ops)
{
    ad_class c = {AD_FALLBACK, 0, 0, 0.0, 0.0};
    double dmin = HUGE_VAL;
    for (int k = 0; k < 3; k++) {
        double D = r->g * vx[k] + r->h * vy[k] + r->i;
        if (D < dmin) dmin = D;
    }
    const double w = (double)(r->xmax - r->xmin + 1), h = (double)(r->ymax - r->ymin + 1);
    c.xc = 0.5 * (double)(r->xmin + r->xmax + 1);
    c.yc = 0.5 * (double)(r->ymin + r->ymax + 1);
    PERSP_OPS(ops, mul, 8);
    PERSP_OPS(ops, add, 6);
    PERSP_OPS(ops, cmp, 6);
    if (!(dmin > 0.0) || !isfinite(dmin) || !isfinite(r->g) || !isfinite(r->h)) {
        /* Not a visible triangle (a vertex at or behind the eye): no method
         * has meaningful values here; return zeros rather than divide. */
        c.kind = AD_INVALID;
        return c;
    }
    if (!(w >= 1.0) || !(h >= 1.0)) return c;
    const double lim = AD_TOL * dmin;
    const int gz = fabs(r->g) * w <= lim, hz = fabs(r->h) * h <= lim;
    const double P1 = ad_scale(r->scale1), P2 = ad_scale(r->scale2);
    if (gz && hz) {
        c.kind = AD_AFFINE;
        c.const2 = fabs(r->d) * w * P2 <= lim; /* (4.48): v = e·y + f on a row */
    } else if (gz) {
        c.kind = AD_ROW;
        c.const2 = fabs(r->d) * w * P2 <= lim; /* statement 4.1 */
    } else if (hz) {
        c.kind = AD_COLUMN;
        c.const1 = fabs(r->b) * h * P1 <= lim; /* statement 4.2 */
        c.const2 = fabs(r->e) * h * P2 <= lim;
    }
    return c;
}

static void ad_prepare(const persp_rational *r, const persp_rational_vertices *v,
                       const persp_method_params *params, persp_method_prep *prep, persp_opcount *ops)
{
    ad_class c = ad_classify(r, v->x, v->y, ops);
    if (c.kind == AD_FALLBACK) {
        persp_method_params fbp;
        const persp_method *fb = ad_fallback(params, &fbp);
        if (fb->prepare) fb->prepare(r, v, &fbp, prep, ops);
    } else if (c.kind == AD_AFFINE) {
        double k = ad_recip(r->g * c.xc + r->h * c.yc + r->i);
        memcpy(prep->bytes, &k, sizeof k);
        PERSP_OPS(ops, div, 1);
        PERSP_OPS(ops, mul, 2);
        PERSP_OPS(ops, add, 2);
    }
    ad_keep_vertices(prep, v);
}

/* The class of a prepared triangle (AD_INVALID without a prepared state). */
static ad_class ad_class_of(const persp_rational *r, const persp_method_prep *prep, persp_opcount *ops)
{
    if (!prep) return (ad_class){AD_INVALID, 0, 0, 0.0, 0.0};
    double x[3], y[3];
    ad_vertices(prep, x, y);
    return ad_classify(r, x, y, ops);
}

/* Row or affine path: D constant along the row, s linear in x. */
static void ad_row(const persp_rational *r, const ad_class *c, double k, int x0, int y, int n,
                   float *s1, float *s2, persp_opcount *ops)
{
    const double px = x0 + 0.5, py = y + 0.5;
    const double U0 = (r->a * px + r->b * py + r->c) * k, dU = r->a * k;
    const double V0 = (r->d * px + r->e * py + r->f) * k, dV = r->d * k;
    for (int j = 0; j < n; j++) s1[j] = (float)(U0 + (double)j * dU);
    if (c->const2) {
        for (int j = 0; j < n; j++) s2[j] = (float)V0;
    } else {
        for (int j = 0; j < n; j++) s2[j] = (float)(V0 + (double)j * dV);
    }
    PERSP_OPS(ops, mul, 8);
    PERSP_OPS(ops, add, 6);
    PERSP_OPS(ops, mul, (c->const2 ? 1 : 2) * n);
    PERSP_OPS(ops, add, (c->const2 ? 1 : 2) * n);
}

/* Column path: per-column constants, shared by the span form and the
 * traversal so both give identical values. */
typedef struct ad_col {
    double k, U, V; /* U, V: numerator parts independent of y (b·y, e·y added per pixel) */
} ad_col;

static void ad_col_init(const persp_rational *r, const ad_class *c, int x, ad_col *col,
                        persp_opcount *ops)
{
    const double px = x + 0.5;
    col->k = ad_recip(r->g * px + r->h * c->yc + r->i);
    col->U = c->const1 ? (r->a * px + r->b * c->yc + r->c) * col->k : r->a * px + r->c;
    col->V = c->const2 ? (r->d * px + r->e * c->yc + r->f) * col->k : r->d * px + r->f;
    PERSP_OPS(ops, div, 1);
    PERSP_OPS(ops, mul, 2 + (c->const1 ? 3 : 1) + (c->const2 ? 3 : 1));
    PERSP_OPS(ops, add, 3 + (c->const1 ? 2 : 1) + (c->const2 ? 2 : 1));
}

static void ad_col_pixel(const persp_rational *r, const ad_class *c, const ad_col *col, int y,
                         float *s1, float *s2, persp_opcount *ops)
{
    const double py = y + 0.5;
    *s1 = (float)(c->const1 ? col->U : (col->U + r->b * py) * col->k);
    *s2 = (float)(c->const2 ? col->V : (col->V + r->e * py) * col->k);
    PERSP_OPS(ops, mul, (c->const1 ? 0 : 2) + (c->const2 ? 0 : 2));
    PERSP_OPS(ops, add, 1 + (c->const1 ? 0 : 1) + (c->const2 ? 0 : 1));
}

static void ad_span(const persp_rational *r, const persp_method_params *params,
                    const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                    persp_opcount *ops)
{
    if (n <= 0) return;
    ad_class c = ad_class_of(r, prep, ops);
    switch (c.kind) {
    case AD_AFFINE: {
        double k;
        memcpy(&k, prep->bytes, sizeof k);
        ad_row(r, &c, k, x0, y, n, s1, s2, ops);
        break;
    }
    case AD_ROW: {
        double k = ad_recip(r->g * c.xc + r->h * (y + 0.5) + r->i);
        PERSP_OPS(ops, div, 1);
        PERSP_OPS(ops, mul, 2);
        PERSP_OPS(ops, add, 3);
        ad_row(r, &c, k, x0, y, n, s1, s2, ops);
        break;
    }
    case AD_INVALID:
        for (int j = 0; j < n; j++) s1[j] = s2[j] = 0.0f;
        break;
    case AD_COLUMN:
        for (int j = 0; j < n; j++) {
            ad_col col;
            ad_col_init(r, &c, x0 + j, &col, ops);
            ad_col_pixel(r, &c, &col, y, &s1[j], &s2[j], ops);
        }
        break;
    default: {
        persp_method_params fbp;
        const persp_method *fb = ad_fallback(params, &fbp);
        fb->span(r, &fbp, prep, x0, y, n, s1, s2, ops);
        break;
    }
    }
}

typedef struct ad_batch {
    int32_t px[PERSP_SPAN_MAX], py[PERSP_SPAN_MAX];
    float s1[PERSP_SPAN_MAX], s2[PERSP_SPAN_MAX];
    int n;
} ad_batch;

static void ad_flush(ad_batch *b, persp_batch_sink sink, void *user)
{
    if (b->n == 0) return;
    persp_frag_batch fb = {.n = b->n, .x0 = b->px[0], .y = b->py[0], .px = b->px, .py = b->py, .s1 = b->s1, .s2 = b->s2};
    sink(user, &fb);
    b->n = 0;
}

/* Column traversal in blocks of at most 64×64: covered rows fetched once per
 * block, then each column walked bottom to top with one reciprocal. */
static void ad_columns(const persp_rational *r, const ad_class *c, const persp_traverse_area *area,
                       persp_batch_sink sink, void *user, persp_opcount *ops)
{
    ad_batch b;
    b.n = 0;
    for (int by0 = area->y0; by0 <= area->y1; by0 += AD_BLOCK) {
        const int by1 = by0 + AD_BLOCK - 1 < area->y1 ? by0 + AD_BLOCK - 1 : area->y1;
        for (int bx0 = area->x0; bx0 <= area->x1; bx0 += AD_BLOCK) {
            const int bx1 = bx0 + AD_BLOCK - 1 < area->x1 ? bx0 + AD_BLOCK - 1 : area->x1;
            int lo[AD_BLOCK], hi[AD_BLOCK], xa, xb;
            persp__area_block_rows(area, by0, by1, bx0, bx1, lo, hi, &xa, &xb);
            for (int x = xa; x <= xb; x++) {
                ad_col col;
                int started = 0;
                for (int y = by0; y <= by1; y++) {
                    if (x < lo[y - by0] || x > hi[y - by0]) continue;
                    if (!started) {
                        ad_col_init(r, c, x, &col, ops);
                        started = 1;
                    }
                    b.px[b.n] = x;
                    b.py[b.n] = y;
                    ad_col_pixel(r, c, &col, y, &b.s1[b.n], &b.s2[b.n], ops);
                    if (++b.n == PERSP_SPAN_MAX) ad_flush(&b, sink, user);
                }
                PERSP_OPS(ops, cmp, 2 * (by1 - by0 + 1));
            }
        }
    }
    ad_flush(&b, sink, user);
}

static void ad_traverse(const persp_rational *r, const persp_method_params *params,
                        const persp_method_prep *prep, const persp_traverse_area *area,
                        persp_batch_sink sink, void *user, persp_opcount *ops)
{
    if (!area || !area->row_range || !sink) return;
    ad_class c = ad_class_of(r, prep, ops);
    if (c.kind == AD_COLUMN) {
        ad_columns(r, &c, area, sink, user, ops);
        return;
    }
    persp_method_params fbp;
    const persp_method *fb = ad_fallback(params, &fbp);
    if (c.kind == AD_FALLBACK && fb->traverse) {
        fb->traverse(r, &fbp, prep, area, sink, user, ops);
        return;
    }
    /* Rows: the ordinary span order. */
    float s1[PERSP_SPAN_MAX], s2[PERSP_SPAN_MAX];
    for (int y = area->y0; y <= area->y1; y++) {
        int lo, hi;
        if (!area->row_range(area->tri, y, &lo, &hi)) continue;
        if (lo < area->x0) lo = area->x0;
        if (hi > area->x1) hi = area->x1;
        for (int x0 = lo; x0 <= hi; x0 += PERSP_SPAN_MAX) {
            int n = hi - x0 + 1 < PERSP_SPAN_MAX ? hi - x0 + 1 : PERSP_SPAN_MAX;
            ad_span(r, params, prep, x0, y, n, s1, s2, ops);
            persp_frag_batch b = {.n = n, .x0 = x0, .y = y, .s1 = s1, .s2 = s2};
            sink(user, &b);
        }
    }
}

const persp_method persp__method_adaptive = {
    .name = "adaptive",
    .params_help = "fallback=NAME[:PARAMS]",
    .summary = "row spans when g = 0, column spans when h = 0, affine when both; constant "
               "coordinate when d (b) = 0 too; else the fallback (default exact)",
    .source = "[Romanyuk-PCF] §4.9, statements 4.1, 4.2, (4.48)",
    .cost = "row: 1 div /span, 1-2 mul, 1-2 add /px; column: 1 div /column; else fallback",
    .parse = ad_parse,
    .prepare = ad_prepare,
    .span = ad_span,
    .traverse = ad_traverse,
};
