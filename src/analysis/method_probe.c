/*
 * persp_method_triangle: one triangle through set-up and a method, pixel by
 * pixel, as the renderer's tile loop (src/raster/tiles.c) drives it, for
 * comparing another implementation of a method with persp's, and
 * persp_midpoint_trace: the same for midpoint:int with its integer state.
 */
#include "analysis/analysis.h"
#include "core/internal.h"
#include "interp/methods.h"
#include "raster/raster.h"

#include <math.h>
#include <string.h>

typedef struct probe {
    const persp_tri *t;
    int width;
    float *u, *v;
    uint8_t *covered;
    int x0, x1; /* the tile's columns */
} probe;

static void store(void *user, const persp_frag_batch *b)
{
    const probe *p = user;
    for (int k = 0; k < b->n; k++) {
        const int x = b->px ? b->px[k] : b->x0 + k, y = b->px ? b->py[k] : b->y;
        const size_t at = (size_t)y * (size_t)p->width + (size_t)x;
        p->u[at] = b->s1[k], p->v[at] = b->s2[k];
        if (p->covered) p->covered[at] = 1;
    }
}

static int rows(const void *user, int y, int *lo, int *hi)
{
    const probe *p = user;
    return persp__tri_row_range(p->t, y, p->x0, p->x1, lo, hi);
}

/* The checks and set-up persp_method_triangle and persp_midpoint_trace
 * share: PERSP_OK with *covers 0 for a triangle that covers no pixel centre. */
static persp_status probe_setup(persp_context *ctx, const char *what, const persp_method_vertex v[3],
                                int width, int height, int tex_w, int tex_h, persp_tri *t,
                                persp_rational_vertices *vv, int *covers)
{
    *covers = 0;
    if (width <= 0 || height <= 0)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: size %dx%d", what, width, height);
    persp_status st = persp__image_check_size(ctx, what, width, height);
    if (st != PERSP_OK) return st;
    if (tex_w < 0 || tex_h < 0 || tex_w > PERSP_IMAGE_MAX_SIDE || tex_h > PERSP_IMAGE_MAX_SIDE)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: texture size %dx%d (0..%d)", what, tex_w,
                           tex_h, PERSP_IMAGE_MAX_SIDE);
    for (int k = 0; k < 3; k++)
        if (!isfinite(v[k].x) || !isfinite(v[k].y) || !(v[k].w > 0.0) || !isfinite(v[k].w) ||
            !isfinite(v[k].u) || !isfinite(v[k].v))
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: vertex %d is not finite or has w <= 0",
                               what, k);
    float attr[3][PERSP_A_COUNT];
    persp_winvert tv[3];
    memset(attr, 0, sizeof attr);
    for (int k = 0; k < 3; k++) {
        attr[k][PERSP_A_U] = v[k].u, attr[k][PERSP_A_V] = v[k].v;
        tv[k] = (persp_winvert){v[k].x, v[k].y, 0.5, 1.0 / v[k].w, attr[k]};
    }
    if (!persp__setup_triangle_for(tv, width, height, 0, 0, t, vv)) return PERSP_OK;
    t->rat.scale1 = tex_w ? (float)tex_w : 1.0f;
    t->rat.scale2 = tex_h ? (float)tex_h : 1.0f;
    *covers = 1;
    return PERSP_OK;
}

persp_status persp_method_triangle(persp_context *ctx, const char *spec, const persp_method_vertex v[3],
                                   int width, int height, int tex_w, int tex_h, float *u_out, float *v_out,
                                   uint8_t *covered, persp_opcount *ops)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!spec || !v || !u_out || !v_out)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "method triangle: no spec, vertices or outputs");
    persp_tri t;
    persp_rational_vertices vv;
    int covers;
    persp_status st = probe_setup(ctx, "method triangle", v, width, height, tex_w, tex_h, &t, &vv, &covers);
    if (st != PERSP_OK) return st;
    persp_method_sel sel;
    if ((st = persp__method_resolve(ctx, spec, &sel)) != PERSP_OK) return st;
    if (covered) memset(covered, 0, (size_t)width * (size_t)height);
    if (!covers) return PERSP_OK;
    const persp_method *m = sel.m;
    persp_method_prep prep;
    memset(&prep, 0, sizeof prep);
    if (m->prepare) m->prepare(&t.rat, &vv, &sel.params, &prep, ops);
    probe p = {&t, width, u_out, v_out, covered, 0, 0};
    for (int y0 = t.ymin / PERSP_TILE * PERSP_TILE; y0 <= t.ymax; y0 += PERSP_TILE)
        for (int x0 = t.xmin / PERSP_TILE * PERSP_TILE; x0 <= t.xmax; x0 += PERSP_TILE) {
            p.x0 = x0, p.x1 = PERSP_MIN(x0 + PERSP_TILE - 1, width - 1);
            const int ya = PERSP_MAX(y0, t.ymin), yb = PERSP_MIN(y0 + PERSP_TILE - 1, t.ymax);
            if (m->traverse) {
                persp_traverse_area area = {x0, ya, p.x1, yb, rows, &p};
                m->traverse(&t.rat, &sel.params, &prep, &area, store, &p, ops);
                continue;
            }
            for (int y = ya; y <= yb; y++) {
                int lo, hi;
                if (!rows(&p, y, &lo, &hi)) continue;
                float s1[PERSP_SPAN_MAX], s2[PERSP_SPAN_MAX];
                const int n = hi - lo + 1;
                if (ops) ops->pixels += (uint64_t)n, ops->spans++;
                m->span(&t.rat, &sel.params, &prep, lo, y, n, s1, s2, ops);
                persp_frag_batch b = {.n = n, .x0 = lo, .y = y, .s1 = s1, .s2 = s2};
                store(&p, &b);
            }
        }
    if (ops) ops->triangles++;
    return PERSP_OK;
}

persp_status persp_midpoint_trace(persp_context *ctx, const char *spec, const persp_method_vertex v[3],
                                  int width, int height, int tex_w, int tex_h, persp_midpoint_format *format,
                                  persp_midpoint_span_fn fn, void *user)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!spec || !v || !format)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "midpoint trace: no spec, vertices or format");
    int edge;
    if (!strcmp(spec, "midpoint:int"))
        edge = 0;
    else if (!strcmp(spec, "midpoint:int,edge") || !strcmp(spec, "midpoint:edge,int"))
        edge = 1;
    else
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                           "midpoint trace: method '%s' (midpoint:int or midpoint:int,edge)", spec);
    memset(format, 0, sizeof *format);
    format->lattice2 = edge ? 0 : 1;
    persp_tri t;
    persp_rational_vertices vv;
    int covers;
    persp_status st = probe_setup(ctx, "midpoint trace", v, width, height, tex_w, tex_h, &t, &vv, &covers);
    if (st != PERSP_OK || !covers) return st;
    persp__midpoint_format(&t.rat, edge, format);
    probe p = {&t, width, NULL, NULL, NULL, 0, 0};
    for (int y0 = t.ymin / PERSP_TILE * PERSP_TILE; y0 <= t.ymax; y0 += PERSP_TILE)
        for (int x0 = t.xmin / PERSP_TILE * PERSP_TILE; x0 <= t.xmax; x0 += PERSP_TILE) {
            p.x0 = x0, p.x1 = PERSP_MIN(x0 + PERSP_TILE - 1, width - 1);
            const int ya = PERSP_MAX(y0, t.ymin), yb = PERSP_MIN(y0 + PERSP_TILE - 1, t.ymax);
            for (int y = ya; y <= yb; y++) {
                int lo, hi;
                if (!rows(&p, y, &lo, &hi)) continue;
                float s1[PERSP_SPAN_MAX], s2[PERSP_SPAN_MAX];
                persp_midpoint_pixel px[PERSP_SPAN_MAX];
                persp_midpoint_span span;
                persp__midpoint_trace_span(&t.rat, format, lo, y, hi - lo + 1, s1, s2, &span, px);
                if (fn) fn(user, &span, px);
            }
        }
    return PERSP_OK;
}
