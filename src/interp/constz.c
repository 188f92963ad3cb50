/*
 * `constz` — texturing along lines of constant depth ([Romanyuk-PCF] §4.8, §4.9,
 * (4.49)-(4.54)), with the bounding-rectangle traversal of §4.8 (Fig. 4.13).
 *
 * Along a line where the denominator D = g·x + h·y + i of (4.8) is constant,
 * u and v are linear and need one reciprocal k = 1/D per line. Stepping one
 * pixel in x keeps D constant when y moves by Δy = −g/h (4.49). Lines are
 * discretised as y = ℓ + ⌈Δy·(x − x_ref)⌉ ((4.50)-(4.52) with the start on a
 * common column x_ref, so that neighbouring lines differ by exactly one pixel
 * in every column: no pixel is skipped or visited twice). The pixel lies
 * r = Δy·(x − x_ref) − ⌈Δy·(x − x_ref)⌉ ∈ (−1, 0] below the true line, so its
 * denominator is D − h·r and k is corrected to first order (4.53), (4.54):
 *
 *     kor = k − r·k'(y) = k + r·k²·h,        u = (a·x + b·y + c)·kor.
 *
 * When |g| > |h| the roles of x and y swap (Δx = −h/g, lines by rows, the
 * correction uses g), so the step along the minor axis never exceeds one
 * pixel; g = h = 0 (affine, (4.48)) gives horizontal lines with r = 0.
 *
 * Error: with δ = h·r/D the exact reciprocal is k/(1 − δ) and kor = k(1 + δ),
 * so u_constz = u_exact·(1 − δ²): the relative error is δ² exactly (up to
 * rounding). Pixels with |δ| > eps (parameter, default 1/32, i.e. relative
 * error ≤ 2^-10) are computed with a division instead; so are lines whose D
 * is not positive. Bound: |Δs| ≤ |s|·eps² + float rounding of the output.
 *
 * Traversal: the tile is processed in blocks of at most 64×64 pixels; in each
 * block the covered row ranges are fetched once (area->row_range), and every
 * line that meets the block's covered bounding rectangle is walked across it
 * (the "virtual rectangle" of §4.8); a visited position is emitted when the
 * coverage test says it is inside, so the pixel set equals the standard one.
 *
 * Cost (counted in ops): per call 1 div (Δy), per line with a covered pixel
 * 1 div, 6 mul, 4 add; per emitted pixel 7 mul, 7 add, 1 cmp (the chapter: "8
 * multiplication and 7 addition operations" for a pair computed directly);
 * per visited rectangle position 1 mul, 1 add, 2 cmp for the discretised line
 * and the coverage test. The `span` form (for tools that need spans) puts each
 * pixel of a row on its own line and so pays 1 div per pixel; it returns the
 * same values as the traversal bit for bit.
 *
 * [Romanyuk-PCF]: divisions per polygon q + 1 for q lines (§4.8/§4.9); here per tile
 * (lines are restarted in each 64×64 block) plus the eps fallbacks.
 */
#include "core/internal.h"
#include "interp/method.h"
#include "interp/methods.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CZ_BLOCK 64
#define CZ_EPS_DEFAULT (1.0 / 32.0)

typedef struct cz_params {
    double eps;
    int set;
} cz_params;
PERSP_METHOD_BLOB_FITS(cz_params, persp_method_params);

typedef struct cz_geom {
    int xmajor;   /* lines advance along x (|h| >= |g|) */
    double slope; /* minor-axis offset per major-axis pixel: −g/h or −h/g, |slope| <= 1 */
    int ref;      /* major coordinate at which every line has r = 0 */
    double m;     /* denominator coefficient along the minor axis: h or g */
    double eps;
} cz_geom;

typedef struct cz_line {
    double k, K2, rlim;
    int ok;
} cz_line;

static persp_status cz_parse(const char *text, persp_method_params *params)
{
    cz_params p = {CZ_EPS_DEFAULT, 1};
    if (text) {
        if (strncmp(text, "eps=", 4) != 0) return PERSP_ERR_INVALID_ARGUMENT;
        double e = 0.0;
        if (!persp__parse_double(text + 4, 0.0, HUGE_VAL, &e))
            return PERSP_ERR_INVALID_ARGUMENT;
        p.eps = e;
    }
    memset(params, 0, sizeof *params);
    memcpy(params->bytes, &p, sizeof p);
    return PERSP_OK;
}

static double cz_eps(const persp_method_params *params)
{
    cz_params p = {0, 0};
    if (params) memcpy(&p, params->bytes, sizeof p);
    return p.set ? p.eps : CZ_EPS_DEFAULT;
}

static void cz_setup(const persp_rational *r, const persp_method_params *params, cz_geom *G,
                     persp_opcount *ops)
{
    G->eps = cz_eps(params);
    if (fabs(r->h) >= fabs(r->g)) {
        G->xmajor = 1;
        G->slope = r->h != 0.0 ? -r->g / r->h : 0.0; /* (4.49) */
        G->ref = r->xmin;
        G->m = r->h;
    } else {
        G->xmajor = 0;
        G->slope = -r->h / r->g;
        G->ref = r->ymin;
        G->m = r->g;
    }
    if (!isfinite(G->slope)) G->slope = 0.0;
    PERSP_OPS(ops, div, 1);
    PERSP_OPS(ops, cmp, 1);
}

/* Discretised line offset at major coordinate p: c = ⌈slope·(p − ref)⌉ (4.52),
 * rr = slope·(p − ref) − c ∈ (−1, 0] (the r_i of (4.53)). */
static int cz_offset(const cz_geom *G, int p, double *rr)
{
    double f = G->slope * (double)(p - G->ref);
    double c = ceil(f);
    *rr = f - c;
    return (int)c;
}

/* Line ℓ: through (ref, ℓ) for x-major, (ℓ, ref) for y-major, pixel centres. */
static void cz_line_init(const persp_rational *r, const cz_geom *G, int l, cz_line *L,
                         persp_opcount *ops)
{
    double px = G->xmajor ? G->ref + 0.5 : l + 0.5;
    double py = G->xmajor ? l + 0.5 : G->ref + 0.5;
    double D = r->g * px + r->h * py + r->i;
    L->ok = D > 0.0 && isfinite(D);
    L->k = L->ok ? 1.0 / D : 0.0;
    L->K2 = L->k * L->k * G->m;                                     /* (4.54): −k'(y) = k²·h */
    L->rlim = G->m != 0.0 ? G->eps * D / fabs(G->m) : HUGE_VAL; /* |δ| <= eps ⇔ |r| <= rlim */
    PERSP_OPS(ops, div, 1);
    PERSP_OPS(ops, mul, 6);
    PERSP_OPS(ops, add, 4);
    PERSP_OPS(ops, cmp, 1);
}

static void cz_pixel(const persp_rational *r, const cz_line *L, int x, int y, double rr, float *s1,
                     float *s2, persp_opcount *ops)
{
    if (!L->ok || -rr > L->rlim) {
        /* Exact division; 0 where the pixel's own denominator is not positive
         * (never inside a visible triangle). */
        double px = x + 0.5, py = y + 0.5, q = r->g * px + r->h * py + r->i;
        int good = q > 0.0 && isfinite(q);
        *s1 = good ? (float)((r->a * px + r->b * py + r->c) / q) : 0.0f;
        *s2 = good ? (float)((r->d * px + r->e * py + r->f) / q) : 0.0f;
        PERSP_OPS(ops, div, 1);
        PERSP_OPS(ops, mul, 6);
        PERSP_OPS(ops, add, 8);
        PERSP_OPS(ops, cmp, 1);
        return;
    }
    double kor = L->k + rr * L->K2; /* (4.53) with (4.54) */
    double px = x + 0.5, py = y + 0.5;
    *s1 = (float)((r->a * px + r->b * py + r->c) * kor);
    *s2 = (float)((r->d * px + r->e * py + r->f) * kor);
    PERSP_OPS(ops, mul, 7);
    PERSP_OPS(ops, add, 7);
    PERSP_OPS(ops, cmp, 1);
}

static void cz_span(const persp_rational *r, const persp_method_params *params,
                    const persp_method_prep *prep, int x0, int y, int n, float *s1, float *s2,
                    persp_opcount *ops)
{
    (void)prep;
    if (n <= 0) return;
    cz_geom G;
    cz_setup(r, params, &G, ops);
    double rr_row = 0.0;
    int c_row = G.xmajor ? 0 : cz_offset(&G, y, &rr_row);
    for (int k = 0; k < n; k++) {
        int x = x0 + k, l;
        double rr;
        if (G.xmajor) {
            l = y - cz_offset(&G, x, &rr);
        } else {
            l = x - c_row;
            rr = rr_row;
        }
        cz_line L;
        cz_line_init(r, &G, l, &L, ops);
        cz_pixel(r, &L, x, y, rr, &s1[k], &s2[k], ops);
    }
    PERSP_OPS(ops, mul, G.xmajor ? n : 1);
    PERSP_OPS(ops, add, G.xmajor ? 2 * n : 1 + n);
}

typedef struct cz_batch {
    int32_t px[PERSP_SPAN_MAX], py[PERSP_SPAN_MAX];
    float s1[PERSP_SPAN_MAX], s2[PERSP_SPAN_MAX];
    int n;
    persp_batch_sink sink;
    void *user;
} cz_batch;

static void cz_flush(cz_batch *b)
{
    if (b->n == 0) return;
    persp_frag_batch fb = {.n = b->n, .x0 = b->px[0], .y = b->py[0], .px = b->px, .py = b->py, .s1 = b->s1, .s2 = b->s2};
    b->sink(b->user, &fb);
    b->n = 0;
}

static void cz_emit(cz_batch *b, const persp_rational *r, const cz_line *L, int x, int y,
                    double rr, persp_opcount *ops)
{
    b->px[b->n] = x;
    b->py[b->n] = y;
    cz_pixel(r, L, x, y, rr, &b->s1[b->n], &b->s2[b->n], ops);
    if (++b->n == PERSP_SPAN_MAX) cz_flush(b);
}

/* One block of at most CZ_BLOCK × CZ_BLOCK pixels. lo/hi: covered columns of
 * rows y0..y1 (lo > hi: empty row); [xa, xb]: their union. */
static void cz_block(const persp_rational *r, const cz_geom *G, int y0, int y1, const int *lo,
                     const int *hi, int xa, int xb, cz_batch *b, persp_opcount *ops)
{
    int cc[CZ_BLOCK];
    double rr[CZ_BLOCK];
    /* Major axis range of the block and the line offsets along it. */
    const int p0 = G->xmajor ? xa : y0, p1 = G->xmajor ? xb : y1;
    int cmin = 0, cmax = 0;
    for (int p = p0; p <= p1; p++) {
        int c = cz_offset(G, p, &rr[p - p0]);
        cc[p - p0] = c;
        if (p == p0 || c < cmin) cmin = c;
        if (p == p0 || c > cmax) cmax = c;
    }
    PERSP_OPS(ops, mul, p1 - p0 + 1);
    PERSP_OPS(ops, add, p1 - p0 + 1);
    /* Minor-axis range the lines must cover: rows y0..y1 or columns xa..xb. */
    const int q0 = G->xmajor ? y0 : xa, q1 = G->xmajor ? y1 : xb;
    long visited = 0;
    for (int l = q0 - cmax; l <= q1 - cmin; l++) {
        cz_line L;
        int started = 0;
        for (int p = p0; p <= p1; p++) {
            int q = l + cc[p - p0];
            visited++;
            if (q < q0 || q > q1) continue;
            int x = G->xmajor ? p : q, y = G->xmajor ? q : p;
            if (x < lo[y - y0] || x > hi[y - y0]) continue;
            if (!started) {
                cz_line_init(r, G, l, &L, ops);
                started = 1;
            }
            cz_emit(b, r, &L, x, y, rr[p - p0], ops);
        }
    }
    PERSP_OPS(ops, add, visited);
    PERSP_OPS(ops, cmp, 2 * visited);
}

static void cz_traverse(const persp_rational *r, const persp_method_params *params,
                        const persp_method_prep *prep, const persp_traverse_area *area,
                        persp_batch_sink sink, void *user, persp_opcount *ops)
{
    (void)prep;
    if (!area || !area->row_range || !sink) return;
    cz_geom G;
    cz_setup(r, params, &G, ops);
    cz_batch b;
    b.n = 0, b.sink = sink, b.user = user;
    for (int by0 = area->y0; by0 <= area->y1; by0 += CZ_BLOCK) {
        const int by1 = by0 + CZ_BLOCK - 1 < area->y1 ? by0 + CZ_BLOCK - 1 : area->y1;
        for (int bx0 = area->x0; bx0 <= area->x1; bx0 += CZ_BLOCK) {
            const int bx1 = bx0 + CZ_BLOCK - 1 < area->x1 ? bx0 + CZ_BLOCK - 1 : area->x1;
            int lo[CZ_BLOCK], hi[CZ_BLOCK], xa, xb;
            persp__area_block_rows(area, by0, by1, bx0, bx1, lo, hi, &xa, &xb);
            if (xa > xb) continue;
            cz_block(r, &G, by0, by1, lo, hi, xa, xb, &b, ops);
        }
    }
    cz_flush(&b);
}

const persp_method persp__method_constz = {
    .name = "constz",
    .params_help = "eps=F",
    .summary = "lines of constant depth (Δy = −g/h), one reciprocal per line with the kor "
               "correction; bounding-rectangle traversal",
    .source = "[Romanyuk-PCF] §4.8, §4.9, (4.49)-(4.54)",
    .cost = "7 mul, 7 add, 1 cmp /px; 1 div /line; rectangle walk 2 cmp /position",
    .parse = cz_parse,
    .span = cz_span,
    .traverse = cz_traverse,
};
