/*
 * persp accuracy: runs every selected method over the measurement cases and
 * compares each pixel with the exact rational form (Heckbert 1989 §2.3.2)
 * evaluated in double precision at the pixel centre (persp__rational_eval).
 *
 * Methods are driven as the renderer drives them (src/raster/tiles.c):
 * `prepare` once per triangle, then `span` on the covered pixels of each row
 * cut at 64-pixel tile columns, or the method's own `traverse` per tile; the
 * operation counts are the method's own (persp_opcount), per-triangle and
 * per-span work included, divided by the pixels measured.
 */
#include "analysis/analysis.h"
#include "core/internal.h"
#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const struct {
    const char *name, *summary;
} fixed_cases[] = {
    {"paper-quad", "line y = 32 of the quad (1,1) (32,96) (96,128) (128,32), "
                   "[Romanyuk-PCF] Fig. 4.10, as one span of 64 samples"},
    {"paper-quad-full", "every pixel of that quad, spans cut as the renderer cuts them"},
    {"random-triangles", "seeded eye-space triangles by depth ratio 1.25..8, 1024x768, 256x256 "
                         "texture"},
};
#define FIXED_CASES (sizeof fixed_cases / sizeof fixed_cases[0])

size_t persp_accuracy_case_count(void) { return FIXED_CASES + persp_builtin_scene_count(); }

const char *persp_accuracy_case_name(size_t index)
{
    if (index < FIXED_CASES) return fixed_cases[index].name;
    return persp_builtin_scene_name(index - FIXED_CASES);
}

const char *persp_accuracy_case_summary(size_t index)
{
    if (index < FIXED_CASES) return fixed_cases[index].summary;
    return index < persp_accuracy_case_count() ? "built-in scene rendered at --size" : NULL;
}

persp_status persp_accuracy_case_check(const char *name)
{
    if (!name) return PERSP_ERR_INVALID_ARGUMENT;
    for (size_t i = 0; i < persp_accuracy_case_count(); i++) {
        const char *c = persp_accuracy_case_name(i);
        if (c && !strcmp(c, name)) return PERSP_OK;
    }
    return PERSP_ERR_NOT_FOUND;
}

size_t persp_accuracy_row_count(const persp_accuracy_result *res) { return res ? res->count : 0; }

const persp_accuracy_row *persp_accuracy_row_at(const persp_accuracy_result *res, size_t index)
{
    return res && index < res->count ? &res->rows[index] : NULL;
}

void persp_accuracy_destroy(persp_accuracy_result *res)
{
    if (!res) return;
    persp_context *ctx = res->ctx;
    persp__free(ctx, res->rows);
    persp__free(ctx, res->index);
    persp__free(ctx, res);
}

/* ------------------------------------------------------------ one run */

typedef struct acc_run {
    persp_context *ctx;
    const persp_accuracy_desc *desc;
    persp_method_sel sel;
    const char *spec;
    persp_acc_metrics m;
    float *grid; /* heat-map grid, NaN = not covered; NULL if no heat map */
    int gw, gh;
    const persp_rational *rat; /* triangle being measured */
    size_t next_row;           /* position of the next row in the unsharded run */
} acc_run;

/* One random triangle: its set-up, the vertices of its rational form and
 * the attributes set-up read. */
typedef struct acc_tri {
    persp_tri t;
    persp_rational_vertices v;
    float attr[3][PERSP_A_COUNT];
} acc_tri;

/* Whether this run's shard measures the next row. */
static int row_wanted(const acc_run *a)
{
    return a->desc->shard_count <= 0 ||
           a->next_row % (size_t)a->desc->shard_count == (size_t)a->desc->shard_index;
}

static void grid_put(acc_run *a, int x, int y, float e)
{
    if (!a->grid || x < 0 || y < 0 || x >= a->gw || y >= a->gh) return;
    float *g = &a->grid[(size_t)y * (size_t)a->gw + (size_t)x];
    if (*g != *g || e > *g || e != e) *g = e;
}

/* Compares one batch the method filled with the exact values. */
static void measure_batch(acc_run *a, const persp_frag_batch *b)
{
    double x1[PERSP_SPAN_MAX], x2[PERSP_SPAN_MAX];
    float err[PERSP_SPAN_MAX];
    for (int off = 0; off < b->n; off += PERSP_SPAN_MAX) {
        int n = PERSP_MIN(b->n - off, PERSP_SPAN_MAX);
        for (int k = 0; k < n; k++) {
            int x = b->px ? b->px[off + k] : b->x0 + off + k;
            int y = b->px ? b->py[off + k] : b->y;
            persp__rational_eval(a->rat, x, y, &x1[k], &x2[k]);
        }
        persp__acc_metrics_span(&a->m, n, x1, x2, b->s1 + off, b->s2 + off, a->rat->scale1,
                                a->rat->scale2, err);
        for (int k = 0; k < n; k++) {
            int x = b->px ? b->px[off + k] : b->x0 + off + k;
            int y = b->px ? b->py[off + k] : b->y;
            grid_put(a, x, y, err[k]);
        }
    }
}

static void sink(void *user, const persp_frag_batch *b) { measure_batch(user, b); }

/* Coverage of the triangle being measured, for spans and traversals. */
typedef struct coverage {
    const persp_tri *t; /* NULL: the single-row line [0, line_n - 1] of row 0 */
    int line_n;
    int x0, x1;         /* tile columns */
} coverage;

static int row_range(const void *p, int y, int *lo, int *hi)
{
    const coverage *c = p;
    if (c->t) return persp__tri_row_range(c->t, y, c->x0, c->x1, lo, hi);
    if (y != 0) return 0;
    *lo = PERSP_MAX(0, c->x0);
    *hi = PERSP_MIN(c->line_n - 1, c->x1);
    return *lo <= *hi;
}

/* Runs the method over one triangle (t) or over the paper line (t == NULL,
 * r the line's rational, line_n samples), as the renderer's tile loop does;
 * v: the vertices r passes through. */
static void measure_triangle(acc_run *a, const persp_tri *t, const persp_rational *r,
                             const persp_rational_vertices *v, int line_n)
{
    const persp_method *m = a->sel.m;
    persp_method_prep prep;
    memset(&prep, 0, sizeof prep);
    if (m->prepare) m->prepare(r, v, &a->sel.params, &prep, &a->m.ops);
    a->m.triangles++;
    a->rat = r;
    int xmin = t ? t->xmin : 0, xmax = t ? t->xmax : line_n - 1;
    int ymin = t ? t->ymin : 0, ymax = t ? t->ymax : 0;
    int tx0 = xmin / PERSP_TILE * PERSP_TILE, ty0 = ymin / PERSP_TILE * PERSP_TILE;
    for (int y0 = ty0; y0 <= ymax; y0 += PERSP_TILE)
        for (int x0 = tx0; x0 <= xmax; x0 += PERSP_TILE) {
            coverage cov = {t, line_n, x0, x0 + PERSP_TILE - 1};
            int ya = PERSP_MAX(y0, ymin), yb = PERSP_MIN(y0 + PERSP_TILE - 1, ymax);
            if (m->traverse) {
                persp_traverse_area area = {x0, ya, x0 + PERSP_TILE - 1, yb, row_range, &cov};
                m->traverse(r, &a->sel.params, &prep, &area, sink, a, &a->m.ops);
                continue;
            }
            for (int y = ya; y <= yb; y++) {
                int lo, hi;
                if (!row_range(&cov, y, &lo, &hi)) continue;
                for (int xs = lo; xs <= hi; xs += PERSP_SPAN_MAX) {
                    int n = PERSP_MIN(hi - xs + 1, PERSP_SPAN_MAX);
                    float s1[PERSP_SPAN_MAX], s2[PERSP_SPAN_MAX];
                    /* Anything a method leaves unwritten shows up as an error. */
                    for (int k = 0; k < n; k++) s1[k] = s2[k] = NAN;
                    m->span(r, &a->sel.params, &prep, xs, y, n, s1, s2, &a->m.ops);
                    persp_frag_batch b = {.n = n, .x0 = xs, .y = y, .s1 = s1, .s2 = s2};
                    measure_batch(a, &b);
                }
            }
        }
}

/* ------------------------------------------------------------ results */

static void sanitize(char *s)
{
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
              *s == '.' || *s == '-' || *s == '_'))
            *s = '-';
}

static persp_status finish_row(acc_run *a, persp_accuracy_result *res, const char *case_name,
                               double hbar, int ops_measured)
{
    if (res->count >= res->cap)
        return persp__fail(a->ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: row overflow");
    res->index[res->count] = a->next_row++;
    persp_accuracy_row *row = &res->rows[res->count++];
    memset(row, 0, sizeof *row);
    snprintf(row->method, sizeof row->method, "%s", a->spec);
    snprintf(row->case_name, sizeof row->case_name, "%s", case_name);
    persp_acc_metrics *m = &a->m;
    row->hbar = hbar;
    row->pixels = m->pixels;
    row->spans = m->spans;
    row->triangles = m->triangles;
    row->max_u = m->eu.max;
    row->max_v = m->ev.max;
    row->mean_u = persp__errstats_mean(&m->eu);
    row->mean_v = persp__errstats_mean(&m->ev);
    row->p99_u = persp__errstats_percentile(&m->eu, 99.0);
    row->p99_v = persp__errstats_percentile(&m->ev, 99.0);
    row->texel_miss = m->pixels ? (double)m->texel_miss / (double)m->pixels : 0.0;
    row->relpt_u = m->relpt_u;
    row->relpt_v = m->relpt_v;
    row->relspan_u = m->relspan_u;
    row->relspan_v = m->relspan_v;
    row->rel_floor = m->rel_floor;
    row->ops_measured = ops_measured;
    double px = m->pixels ? (double)m->pixels : 1.0;
    row->div_px = ops_measured ? (double)m->ops.div / px : NAN;
    row->mul_px = ops_measured ? (double)m->ops.mul / px : NAN;
    row->add_px = ops_measured ? (double)m->ops.add / px : NAN;
    row->cmp_px = ops_measured ? (double)m->ops.cmp / px : NAN;

    if (a->grid && a->desc->heatmap_dir) {
        char name[160], path[1024];
        if (hbar > 0.0)
            snprintf(name, sizeof name, "%s-h%g_%s", case_name, hbar, a->spec);
        else
            snprintf(name, sizeof name, "%s_%s", case_name, a->spec);
        sanitize(name);
        int len = snprintf(path, sizeof path, "%s/%s.png", a->desc->heatmap_dir, name);
        if (len < 0 || (size_t)len >= sizeof path)
            return persp__fail(a->ctx, PERSP_ERR_INVALID_ARGUMENT,
                                      "accuracy: heat-map path too long");
        persp_status st = persp__heatmap_write(a->ctx, path, a->grid, a->gw, a->gh, PERSP_HEATMAP_TEXELS,
                                                PERSP_HEATMAP_TEXELS_TOP);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static persp_status begin_case(acc_run *a, size_t pixels, int gw, int gh)
{
    persp__acc_metrics_reset(&a->m);
    persp_status st = persp__errstats_reserve(&a->m.eu, pixels);
    if (st == PERSP_OK) st = persp__errstats_reserve(&a->m.ev, pixels);
    if (st != PERSP_OK) return persp__fail(a->ctx, st, "accuracy: out of memory");
    persp__free(a->ctx, a->grid);
    a->grid = NULL;
    if (a->desc->heatmap_dir) {
        a->grid = persp__calloc(a->ctx, (size_t)gw * (size_t)gh, sizeof *a->grid);
        if (!a->grid) return persp__fail(a->ctx, PERSP_ERR_OUT_OF_MEMORY, "accuracy: out of memory");
        for (size_t i = 0; i < (size_t)gw * (size_t)gh; i++) a->grid[i] = NAN;
        a->gw = gw, a->gh = gh;
    }
    return PERSP_OK;
}

/* ------------------------------------------------------------ cases */

static persp_status case_paper_line(acc_run *a, persp_accuracy_result *res)
{
    persp_rational r;
    persp_rational_vertices v;
    persp__paper_quad_line(PERSP_ACCURACY_LINE_SAMPLES, 256.0, &r, &v, NULL, NULL);
    persp_status st = begin_case(a, PERSP_ACCURACY_LINE_SAMPLES, PERSP_ACCURACY_LINE_SAMPLES, 1);
    if (st != PERSP_OK) return st;
    measure_triangle(a, NULL, &r, &v, PERSP_ACCURACY_LINE_SAMPLES);
    return finish_row(a, res, "paper-quad", 0.0, 1);
}

/* The two triangles (c0, c1, c2), (c0, c2, c3) of the paper quad, set up by
 * the renderer's own setup so coverage follows its fill rules; pixel (x, y)
 * samples the chapter's point (x, y). */
static int paper_quad_tris(persp_tri t[2], persp_rational_vertices v[2], float attr[4][PERSP_A_COUNT])
{
    double fwd[9], p[9];
    if (!persp__square_to_quad(persp__paper_quad_x, persp__paper_quad_y, fwd, p)) return 0;
    persp_winvert w[4];
    for (int k = 0; k < 4; k++) {
        double X = persp__paper_quad_x[k], Y = persp__paper_quad_y[k];
        double q = p[6] * X + p[7] * Y + p[8];
        memset(attr[k], 0, sizeof(float) * PERSP_A_COUNT);
        attr[k][PERSP_A_U] = (float)((p[0] * X + p[1] * Y + p[2]) / q);
        attr[k][PERSP_A_V] = (float)((p[3] * X + p[4] * Y + p[5]) / q);
        w[k].x = X + 0.5;
        w[k].y = Y + 0.5;
        w[k].z = 0.5;
        w[k].q = q;
        w[k].attr = attr[k];
    }
    const persp_winvert a[3] = {w[0], w[1], w[2]}, b[3] = {w[0], w[2], w[3]};
    if (!persp__setup_triangle(a, 130, 130, 0, &t[0], &v[0]) ||
        !persp__setup_triangle(b, 130, 130, 0, &t[1], &v[1]))
        return 0;
    t[0].rat.scale1 = t[0].rat.scale2 = t[1].rat.scale1 = t[1].rat.scale2 = 256.0f;
    return 1;
}

static persp_status case_paper_full(acc_run *a, persp_accuracy_result *res)
{
    persp_tri t[2];
    persp_rational_vertices v[2];
    float attr[4][PERSP_A_COUNT];
    if (!paper_quad_tris(t, v, attr))
        return persp__fail(a->ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: paper quad setup");
    persp_status st = begin_case(a, persp__tri_pixels(&t[0]) + persp__tri_pixels(&t[1]), 130, 130);
    if (st != PERSP_OK) return st;
    for (int i = 0; i < 2; i++) measure_triangle(a, &t[i], &t[i].rat, &v[i], 0);
    return finish_row(a, res, "paper-quad-full", 0.0, 1);
}

static persp_status case_random(acc_run *a, persp_accuracy_result *res, acc_tri *tris)
{
    int count = a->desc->triangles > 0 ? a->desc->triangles : 40;
    uint64_t seed = a->desc->seed ? a->desc->seed : 1;
    for (int g = 0; g < PERSP_HBAR_COUNT; g++) {
        if (!row_wanted(a)) {
            a->next_row++;
            continue;
        }
        /* Each group has its own stream, so a group's triangles do not
         * depend on the other groups or on the methods measured. */
        persp_rng rng = {seed * UINT64_C(0x100000001b3) + (uint64_t)g * UINT64_C(0x9e3779b97f4a7c15)};
        size_t pixels = 0;
        int made = 0;
        for (int i = 0; i < count; i++) {
            acc_tri *at = &tris[made];
            uint64_t px = persp__random_triangle(&rng, persp__hbar_groups[g], &at->t, &at->v, at->attr);
            if (px) pixels += (size_t)px, made++;
        }
        persp_status st = begin_case(a, pixels, PERSP_RT_WIDTH, PERSP_RT_HEIGHT);
        if (st != PERSP_OK) return st;
        for (int i = 0; i < made; i++) measure_triangle(a, &tris[i].t, &tris[i].t.rat, &tris[i].v, 0);
        st = finish_row(a, res, "random-triangles", persp__hbar_groups[g], 1);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

/* A built-in scene rendered by the renderer itself with the method; the
 * captured u, v are compared with the exact form of the triangle seen at
 * each pixel. Operation counts are the renderer's own (an instrumented
 * render, persp_render_desc.count_ops): per-triangle fits, spans and custom
 * traversals as drawn, over every fragment that reached the method. */
static persp_status case_scene(acc_run *a, persp_accuracy_result *res, const char *name)
{
    int w = a->desc->width > 0 ? a->desc->width : 1024;
    int h = a->desc->height > 0 ? a->desc->height : 768;
    persp_scene *scene = NULL;
    persp_status st = persp_scene_builtin(a->ctx, name, &scene);
    if (st != PERSP_OK) return st;
    persp_render_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.method = a->spec;
    rd.count_ops = PERSP_TOGGLE_ON;
    persp_capture cap;
    memset(&cap, 0, sizeof cap);
    st = persp__render_capture(a->ctx, scene, &rd, w, h, &cap);
    persp_scene_destroy(scene);
    if (st != PERSP_OK) return st;
    st = begin_case(a, (size_t)w * (size_t)h, w, h);
    if (st == PERSP_OK) {
        a->m.triangles = cap.rat_count;
        a->m.ops = cap.ops;
        for (int y = 0; y < h; y++) {
            const size_t row = (size_t)y * (size_t)w;
            int x = 0;
            while (x < w) {
                int32_t tri = cap.tri[row + (size_t)x];
                int end = x + 1;
                /* A run: one triangle, inside one tile column (≤ PERSP_SPAN_MAX). */
                while (end < w && cap.tri[row + (size_t)end] == tri && end % PERSP_TILE != 0) end++;
                if (tri >= 0 && (size_t)tri < cap.rat_count) {
                    a->rat = &cap.rats[tri];
                    persp_frag_batch b = {.n = end - x, .x0 = x, .y = y, .s1 = cap.s1 + row + (size_t)x,
                                          .s2 = cap.s2 + row + (size_t)x};
                    measure_batch(a, &b);
                }
                x = end;
            }
        }
        char label[48];
        snprintf(label, sizeof label, "%s@%dx%d", name, w, h);
        st = finish_row(a, res, label, 0.0, 1);
    }
    persp__capture_free(a->ctx, &cap);
    return st;
}

/* ------------------------------------------------------------ entry */

/* Everything that decides a sweep's rows, with the defaults applied. */
static void sweep_text(char *buf, size_t size, const persp_accuracy_desc *d, const char **specs,
                       size_t nspecs, const char *const *cases, size_t ncases, int ntri)
{
    size_t len = 0;
#define PUT(...)                                                                                   \
    do {                                                                                           \
        int k_ = snprintf(buf + len, size - len, __VA_ARGS__);                                     \
        if (k_ > 0) len = PERSP_MIN(size - 1, len + (size_t)k_);                                   \
    } while (0)
    buf[0] = '\0';
    PUT("methods=");
    for (size_t i = 0; i < nspecs; i++) PUT("%s%s", i ? "," : "", specs[i]);
    PUT(" cases=");
    for (size_t i = 0; i < ncases; i++) PUT("%s%s", i ? "," : "", cases[i]);
    PUT(" seed=%llu triangles=%d size=%dx%d rel_floor=%.17g",
        (unsigned long long)(d->seed ? d->seed : 1), ntri, d->width > 0 ? d->width : 1024,
        d->height > 0 ? d->height : 768, d->rel_floor > 0.0 ? d->rel_floor : 0.01);
#undef PUT
}

static persp_status run_case(acc_run *a, persp_accuracy_result *res, const char *c, acc_tri *tris)
{
    if (!strcmp(c, "random-triangles")) return case_random(a, res, tris);
    if (!row_wanted(a)) {
        a->next_row++;
        return PERSP_OK;
    }
    if (!strcmp(c, "paper-quad")) return case_paper_line(a, res);
    if (!strcmp(c, "paper-quad-full")) return case_paper_full(a, res);
    return case_scene(a, res, c);
}

const char *persp__analysis_size_problem(int triangles, int width, int height)
{
    if (triangles < 0 || triangles > 100000) return "triangles (0..100000)";
    if (width < 0 || height < 0 || width > PERSP_IMAGE_MAX_SIDE || height > PERSP_IMAGE_MAX_SIDE)
        return "width, height (0..16384)";
    return NULL;
}

/* The desc's sizes, floor and slice in range. */
static persp_status accuracy_desc_check(persp_context *ctx, const persp_accuracy_desc *desc)
{
    const char *bad = persp__analysis_size_problem(desc->triangles, desc->width, desc->height);
    if (!bad && (!(desc->rel_floor >= 0.0) || !isfinite(desc->rel_floor))) bad = "rel_floor (finite, >= 0)";
    if (bad)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: persp_accuracy_desc.%s is out of range",
                           bad);
    if (desc->shard_count < 0 || desc->shard_count > 1000000 ||
        (desc->shard_count > 0 && (desc->shard_index < 0 || desc->shard_index >= desc->shard_count)))
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: shard %d of %d", desc->shard_index,
                           desc->shard_count);
    return PERSP_OK;
}

/* Every case known; *groups: the rows a method has over them (one a case,
 * one a depth-ratio group for random-triangles). */
static persp_status case_groups(persp_context *ctx, const char *const *cases, size_t ncases,
                               size_t *groups)
{
    size_t g = 0;
    for (size_t i = 0; i < ncases; i++) {
        if (!cases[i] || persp_accuracy_case_check(cases[i]) != PERSP_OK)
            return persp__fail(ctx, PERSP_ERR_NOT_FOUND, "unknown case '%s'",
                               cases[i] ? cases[i] : "(null)");
        g += strcmp(cases[i], "random-triangles") ? 1 : PERSP_HBAR_COUNT;
    }
    *groups = g;
    return PERSP_OK;
}

/* The methods to measure into specs and sels (nmeth entries each), *used
 * of them: the desc's, every one resolved (a bad spec fails), or else
 * every registered method that runs without parameters. */
static persp_status resolve_methods(persp_context *ctx, const persp_accuracy_desc *desc,
                                    size_t nmeth, const char **specs, persp_method_sel *sels,
                                    size_t *used)
{
    const int given = desc->methods && desc->method_count;
    size_t n = 0;
    for (size_t i = 0; i < nmeth; i++) {
        if (given) {
            specs[n] = desc->methods[i];
            if (!specs[n])
                return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: NULL method");
            persp_status st = persp__method_resolve(ctx, specs[n], &sels[n]);
            if (st != PERSP_OK) return st;
            n++;
        } else {
            /* Entries that cannot run without parameters are left out. */
            specs[n] = persp__method_at(i)->name;
            if (persp__method_resolve(NULL, specs[n], &sels[n]) == PERSP_OK) n++;
        }
    }
    *used = n;
    return PERSP_OK;
}

persp_status persp_accuracy_run(persp_context *ctx, const persp_accuracy_desc *desc,
                                persp_accuracy_result **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!desc || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: no desc");
    *out = NULL;
    persp_status st = accuracy_desc_check(ctx, desc);
    if (st != PERSP_OK) return st;
    static const char *const default_cases[] = {"paper-quad", "random-triangles"};
    /* "NULL or none": a NULL list is none, whatever its count says. */
    const int given_cases = desc->cases && desc->case_count;
    const char *const *cases = given_cases ? desc->cases : default_cases;
    size_t ncases = given_cases ? desc->case_count : 2;
    size_t groups = 0;
    if ((st = case_groups(ctx, cases, ncases, &groups)) != PERSP_OK) return st;
    /* Methods: validate every spec before any work. */
    const int given_methods = desc->methods && desc->method_count;
    size_t nmeth = given_methods ? desc->method_count : persp__method_count();
    const char **specs = persp__calloc(ctx, nmeth ? nmeth : 1, sizeof *specs);
    persp_method_sel *sels = persp__calloc(ctx, nmeth ? nmeth : 1, sizeof *sels);
    persp_accuracy_result *res = persp__calloc(ctx, 1, sizeof *res);
    if (res) res->ctx = ctx;
    acc_tri *tris = NULL;
    acc_run a;
    memset(&a, 0, sizeof a);
    a.ctx = ctx;
    a.desc = desc;
    persp__acc_metrics_init(&a.m, ctx, desc->rel_floor > 0.0 ? desc->rel_floor : 0.01);
    if (!specs || !sels || !res) {
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "accuracy: out of memory");
        goto done;
    }
    size_t used = 0;
    if ((st = resolve_methods(ctx, desc, nmeth, specs, sels, &used)) != PERSP_OK) goto done;
    if (!persp__size_mul(used, groups, &res->cap) || res->cap > 1000000) {
        st = persp__fail(ctx, PERSP_ERR_TOO_LARGE, "accuracy: too many rows");
        goto done;
    }
    res->rows = persp__calloc(ctx, res->cap ? res->cap : 1, sizeof *res->rows);
    res->index = persp__calloc(ctx, res->cap ? res->cap : 1, sizeof *res->index);
    res->total = res->cap;
    res->shard_index = desc->shard_count > 0 ? desc->shard_index : 0;
    res->shard_count = desc->shard_count > 0 ? desc->shard_count : 0;
    int ntri = desc->triangles > 0 ? desc->triangles : 40;
    sweep_text(res->sweep, sizeof res->sweep, desc, specs, used, cases, ncases, ntri);
    tris = persp__calloc(ctx, (size_t)ntri, sizeof *tris);
    if (!res->rows || !res->index || !tris) {
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "accuracy: out of memory");
        goto done;
    }
    for (size_t c = 0; c < ncases && st == PERSP_OK; c++)
        for (size_t i = 0; i < used && st == PERSP_OK; i++) {
            a.sel = sels[i];
            a.spec = specs[i];
            st = run_case(&a, res, cases[c], tris);
        }
done:
    persp__acc_metrics_free(&a.m);
    persp__free(ctx, a.grid);
    persp__free(ctx, tris);
    persp__free(ctx, specs);
    persp__free(ctx, sels);
    if (st != PERSP_OK) {
        persp_accuracy_destroy(res);
        return st;
    }
    *out = res;
    return PERSP_OK;
}
