/*
 * The traversal methods: `constz` (lines of constant depth, [Romanyuk-PCF] §4.8,
 * §4.9) and `adaptive` (direction from the coefficients, §4.9). The visited
 * pixel set must equal the standard coverage of every tile, each pixel once,
 * and the values must stay within the documented bounds of the exact form.
 * Triangles: corridor projection, 1024×768, u, v in [0, 1], 256 texels.
 */
#include "support.h"

#include "interp/methods.h"
#include "raster/raster.h"

#include <math.h>
#include <string.h>

#define VW 1024
#define VH 768
#define TEX 256.0
#define PI 3.14159265358979323846

static const double hbars[] = {1.25, 1.5, 2, 3, 4, 5, 8};
#define NHBAR (sizeof hbars / sizeof hbars[0])

/* Eye-space point → window vertex with the corridor projection. */
static void project(const double e[3], double u, double v, float attr[PERSP_A_COUNT],
                    persp_winvert *out)
{
    const double a = (double)VW / VH, tn = tan(30.0 * PI / 180.0), z = -e[2];
    memset(attr, 0, sizeof(float) * PERSP_A_COUNT);
    out->x = (e[0] / (tn * a * z) + 1.0) * 0.5 * VW;
    out->y = (e[1] / (tn * z) + 1.0) * 0.5 * VH;
    out->z = 0.5;
    out->q = 1.0 / z;
    attr[PERSP_A_U] = (float)u;
    attr[PERSP_A_V] = (float)v;
    out->attr = attr;
}

static int finish(persp_winvert v[3], persp_tri *t, persp_rational_vertices *vv)
{
    if (!persp__setup_triangle(v, VW, VH, 0, t, vv)) return 0;
    t->rat.scale1 = t->rat.scale2 = (float)TEX;
    return 1;
}

static int random_triangle(test_rng *rng, double hbar, persp_tri *t, persp_rational_vertices *vv)
{
    static float attr[3][PERSP_A_COUNT];
    const double a = (double)VW / VH, tn = tan(30.0 * PI / 180.0);
    double zn = test_rng_uniform(rng, 0.5, 4.0);
    double z[3] = {zn, zn * hbar, test_rng_uniform(rng, zn, zn * hbar)};
    persp_winvert v[3];
    for (int i = 0; i < 3; i++) {
        double e[3] = {test_rng_uniform(rng, -0.95, 0.95) * tn * a * z[i],
                       test_rng_uniform(rng, -0.95, 0.95) * tn * z[i], -z[i]};
        project(e, test_rng_uniform(rng, 0, 1), test_rng_uniform(rng, 0, 1), attr[i], &v[i]);
    }
    return finish(v, t, vv);
}

/* A floor-like triangle (eye y = −1, two vertices at one depth as in a quad
 * split along its diagonal): u follows eye x, v follows depth, so d = g = 0.
 * wall != 0: the same on the wall x = −1 (v follows depth, u eye y: e = h = 0). */
static int axis_triangle(test_rng *rng, int wall, persp_tri *t, persp_rational_vertices *vv)
{
    static float attr[3][PERSP_A_COUNT];
    const double a = (double)VW / VH, tn = tan(30.0 * PI / 180.0);
    double z0 = test_rng_uniform(rng, 2.0, 6.0), z1 = z0 * test_rng_uniform(rng, 1.5, 5.0);
    double z[3] = {z0, z0, z1};
    double s0 = test_rng_uniform(rng, -0.9, 0.9), s1 = test_rng_uniform(rng, -0.9, 0.9),
           s2 = test_rng_uniform(rng, -0.9, 0.9);
    double side[3] = {s0, s1, s2};
    persp_winvert v[3];
    for (int i = 0; i < 3; i++) {
        double e[3];
        if (!wall) {
            e[0] = side[i] * tn * a * z[i], e[1] = -1.0;
        } else {
            e[0] = -1.0, e[1] = side[i] * tn * z[i];
        }
        e[2] = -z[i];
        double along = wall ? e[1] : e[0];
        project(e, 0.5 + 0.1 * along, z[i] / 30.0, attr[i], &v[i]);
    }
    return finish(v, t, vv);
}

typedef struct area_tri {
    const persp_tri *t;
    int x0, x1;
} area_tri;

static int row_range_cb(const void *p, int y, int *lo, int *hi)
{
    const area_tri *a = p;
    return persp__tri_row_range(a->t, y, a->x0, a->x1, lo, hi);
}

static unsigned char visits[VH][VW];

typedef struct sink_state {
    const persp_tri *t;
    const persp_method_sel *sel;
    const persp_method_prep *prep;
    double eps2;     /* relative bound of the values (constz: eps², adaptive: 2^-22) */
    double worst;    /* max |error| in texels */
    double over;     /* max excess over the bound */
    long pixels, span_mismatch, bad_batch;
    int pure;        /* bound from the pixel's own denominator (constz without fallback) */
    long unbounded;  /* pure: pixels with D <= 2·max(|g|,|h|), where no bound applies */
    long grid_pixels; /* pixels of the 64×64 tile-grid pass (the one counted in ops) */
} sink_state;

static void sink(void *user, const persp_frag_batch *b)
{
    sink_state *s = user;
    if (b->n < 1 || b->n > PERSP_SPAN_MAX || !b->s1 || !b->s2) {
        s->bad_batch++;
        return;
    }
    for (int k = 0; k < b->n; k++) {
        int x = b->px ? b->px[k] : b->x0 + k, y = b->py ? b->py[k] : b->y;
        if (x < 0 || x >= VW || y < 0 || y >= VH) {
            s->bad_batch++;
            continue;
        }
        if (visits[y][x] < 255) visits[y][x]++;
        double eu, ev;
        persp__rational_eval(&s->t->rat, x, y, &eu, &ev);
        double du = fabs(b->s1[k] - eu) * TEX, dv = fabs(b->s2[k] - ev) * TEX;
        s->worst = fmax(s->worst, fmax(du, dv));
        /* Bound: |s|·rel plus float rounding of the output and of the
         * reference (values below 2 units: 1e-4 texel). */
        double rel = s->eps2;
        if (s->pure) {
            /* δ = m·r/D_line with |r| < 1 and D_line = D + m·r, so
             * |δ| < m/(D − m) for m = max(|g|, |h|) when D > m. */
            const persp_rational *r = &s->t->rat;
            double D = r->g * (x + 0.5) + r->h * (y + 0.5) + r->i, m = fmax(fabs(r->g), fabs(r->h));
            if (D <= 2.0 * m) {
                s->unbounded++;
                rel = HUGE_VAL;
            } else {
                rel = (m / (D - m)) * (m / (D - m)) * (1.0 + 1e-9);
            }
        }
        double bu = fabs(eu) * TEX * rel + 1e-4, bv = fabs(ev) * TEX * rel + 1e-4;
        s->over = fmax(s->over, fmax(du - bu, dv - bv));
        /* The span form of the method gives the same values. */
        float u1, v1;
        s->sel->m->span(&s->t->rat, &s->sel->params, s->prep, x, y, 1, &u1, &v1, NULL);
        if (u1 != b->s1[k] || v1 != b->s2[k]) s->span_mismatch++;
        s->pixels++;
    }
}

/* Traverses tile [x0,x1]×[y0,y1] (clipped to the triangle's rows as the
 * renderer does) and checks the pixel set against the standard coverage. */
static long traverse_tile(const persp_method_sel *sel, const persp_method_prep *prep,
                          const persp_tri *t, int x0, int y0, int x1, int y1, sink_state *st,
                          persp_opcount *ops)
{
    area_tri at = {t, x0, x1};
    int ya = y0 > t->ymin ? y0 : t->ymin, yb = y1 < t->ymax ? y1 : t->ymax;
    if (ya > yb) return 0;
    for (int y = y0; y <= y1; y++) memset(&visits[y][x0], 0, (size_t)(x1 - x0 + 1));
    persp_traverse_area area = {x0, ya, x1, yb, row_range_cb, &at};
    sel->m->traverse(&t->rat, &sel->params, prep, &area, sink, st, ops);
    long wrong = 0;
    for (int y = y0; y <= y1; y++) {
        int lo = 1, hi = 0;
        if (!persp__tri_row_range(t, y, x0, x1, &lo, &hi)) lo = 1, hi = 0;
        for (int x = x0; x <= x1; x++) wrong += visits[y][x] != (x >= lo && x <= hi);
    }
    return wrong;
}

/* Tiles: the renderer's 64×64 grid, the whole bounding box, and random
 * rectangles (also wider than one block). */
static long traverse_all(const persp_method_sel *sel, const persp_tri *t,
                         const persp_rational_vertices *vv, test_rng *rng, sink_state *st,
                         persp_opcount *ops)
{
    persp_method_prep prep;
    memset(&prep, 0, sizeof prep);
    if (sel->m->prepare) sel->m->prepare(&t->rat, vv, &sel->params, &prep, ops);
    st->t = t, st->sel = sel, st->prep = &prep;
    long wrong = 0, before = st->pixels;
    for (int ty = t->ymin / 64 * 64; ty <= t->ymax; ty += 64)
        for (int tx = t->xmin / 64 * 64; tx <= t->xmax; tx += 64)
            wrong += traverse_tile(sel, &prep, t, tx, ty, tx + 63 < VW ? tx + 63 : VW - 1,
                                   ty + 63 < VH ? ty + 63 : VH - 1, st, ops);
    st->grid_pixels += st->pixels - before;
    wrong += traverse_tile(sel, &prep, t, t->xmin, t->ymin, t->xmax, t->ymax, st, NULL);
    for (int i = 0; i < 3; i++) {
        int x0 = (int)test_rng_uniform(rng, 0, VW - 1), y0 = (int)test_rng_uniform(rng, 0, VH - 1);
        int x1 = x0 + (int)test_rng_uniform(rng, 0, 200), y1 = y0 + (int)test_rng_uniform(rng, 0, 150);
        wrong += traverse_tile(sel, &prep, t, x0, y0, x1 < VW ? x1 : VW - 1, y1 < VH ? y1 : VH - 1,
                               st, NULL);
    }
    return wrong;
}

static persp_method_sel resolve(const char *spec)
{
    persp_method_sel sel;
    assert_int_equal(persp__method_resolve(NULL, spec, &sel), PERSP_OK);
    return sel;
}

static void test_constz_coverage_and_values(void **state)
{
    (void)state;
    persp_method_sel sel = resolve("constz");
    test_rng rng = {31337};
    const double eps = 1.0 / 32.0;
    long wrong = 0, tris = 0, xmajor = 0, ymajor = 0;
    sink_state all = {0};
    persp_opcount ops = {0};
    for (size_t h = 0; h < NHBAR; h++) {
        sink_state st = {0};
        st.eps2 = eps * eps * (1.0 + 1e-9);
        for (int i = 0; i < 12; i++) {
            persp_tri t;
            persp_rational_vertices vv;
            if (!random_triangle(&rng, hbars[h], &t, &vv)) continue;
            tris++;
            if (fabs(t.rat.h) >= fabs(t.rat.g)) xmajor++;
            else ymajor++;
            wrong += traverse_all(&sel, &t, &vv, &rng, &st, &ops);
        }
        print_message("constz hbar %.2f: max %.5f texel (bound excess %.2g) over %ld px\n", hbars[h],
                      st.worst, st.over, st.pixels);
        all.worst = fmax(all.worst, st.worst);
        all.over = fmax(all.over, st.over);
        all.pixels += st.pixels, all.span_mismatch += st.span_mismatch, all.bad_batch += st.bad_batch;
        all.grid_pixels += st.grid_pixels;
    }
    print_message("constz: %ld triangles (%ld x-major, %ld y-major), %ld px; tile-grid pass: %ld px, "
                  "%.4f div, %.2f mul, %.2f add, %.2f cmp per px\n",
                  tris, xmajor, ymajor, all.pixels, all.grid_pixels,
                  (double)ops.div / (double)all.grid_pixels, (double)ops.mul / (double)all.grid_pixels,
                  (double)ops.add / (double)all.grid_pixels, (double)ops.cmp / (double)all.grid_pixels);
    assert_true(all.pixels > 100000);
    assert_true(xmajor > 0 && ymajor > 0);
    assert_int_equal(wrong, 0);
    assert_int_equal(all.bad_batch, 0);
    assert_int_equal(all.span_mismatch, 0);
    assert_true(all.over <= 0.0);
    /* Far fewer divisions than pixels: one per line and tile. */
    assert_true(ops.div * 10 < (uint64_t)all.grid_pixels);
}

/* The chapter's method without the eps fallback (eps = 1e9): still no holes, and
 * the error stays |s|·δ² with |δ| < max(|g|,|h|)/D. */
static void test_constz_unguarded(void **state)
{
    (void)state;
    persp_method_sel sel = resolve("constz:eps=1e9");
    test_rng rng = {8};
    long wrong = 0;
    sink_state st = {0};
    st.pure = 1;
    for (size_t h = 0; h < NHBAR; h++)
        for (int i = 0; i < 4; i++) {
            persp_tri t;
            persp_rational_vertices vv;
            if (!random_triangle(&rng, hbars[h], &t, &vv)) continue;
            wrong += traverse_all(&sel, &t, &vv, &rng, &st, NULL);
        }
    print_message("constz:eps=1e9: max %.5f texel over %ld px (%ld px with D <= 2·max(|g|,|h|))\n",
                  st.worst, st.pixels, st.unbounded);
    assert_int_equal(wrong, 0);
    assert_int_equal(st.span_mismatch, 0);
    assert_true(st.over <= 0.0);
}

/* Constant depth (g = h = 0, affine): horizontal lines, r = 0, exact. */
static void test_constz_constant_depth(void **state)
{
    (void)state;
    persp_method_sel sel = resolve("constz");
    static float attr[3][PERSP_A_COUNT];
    const double e[3][3] = {{-1, -1, -3}, {1.5, -0.5, -3}, {0.2, 1.2, -3}};
    persp_winvert v[3];
    for (int i = 0; i < 3; i++) project(e[i], 0.3 * i, 0.9 - 0.4 * i, attr[i], &v[i]);
    persp_tri t;
    persp_rational_vertices vv;
    assert_true(finish(v, &t, &vv));
    test_rng rng = {1};
    sink_state st = {0};
    st.eps2 = 0.0;
    assert_int_equal(traverse_all(&sel, &t, &vv, &rng, &st, NULL), 0);
    assert_true(st.pixels > 1000);
    assert_true(st.over <= 0.0);
}

static void test_adaptive_floor_takes_row_path(void **state)
{
    (void)state;
    persp_method_sel sel = resolve("adaptive");
    test_rng rng = {2718};
    long spans = 0, pixels = 0;
    double worst = 0.0;
    persp_opcount ops = {0};
    int floors = 0;
    for (int i = 0; i < 30; i++) {
        persp_tri t;
        persp_rational_vertices vv;
        if (!axis_triangle(&rng, 0, &t, &vv)) continue;
        /* The premise of statement 4.1 holds exactly for these planes. */
        assert_true(t.rat.g == 0.0 && t.rat.d == 0.0);
        floors++;
        persp_method_prep prep;
        sel.m->prepare(&t.rat, &vv, &sel.params, &prep, &ops);
        for (int y = t.ymin; y <= t.ymax; y++) {
            int lo, hi;
            if (!persp__tri_row_range(&t, y, 0, VW - 1, &lo, &hi)) continue;
            for (int x0 = lo; x0 <= hi; x0 += PERSP_SPAN_MAX) {
                int n = hi - x0 + 1 > PERSP_SPAN_MAX ? PERSP_SPAN_MAX : hi - x0 + 1;
                float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX];
                sel.m->span(&t.rat, &sel.params, &prep, x0, y, n, u, v, &ops);
                for (int k = 0; k < n; k++) {
                    double eu, ev;
                    persp__rational_eval(&t.rat, x0 + k, y, &eu, &ev);
                    worst = fmax(worst, fmax(fabs(u[k] - eu), fabs(v[k] - ev)) * TEX);
                    /* v is constant along the row (statement 4.1). */
                    assert_true(v[k] == v[0]);
                }
                spans++, pixels += n;
            }
        }
    }
    print_message("adaptive on %d floors: %ld px, %ld spans, %llu div, %.2f mul/px, max %.2g texel\n",
                  floors, pixels, spans, (unsigned long long)ops.div,
                  (double)ops.mul / (double)pixels, worst);
    assert_true(floors > 10 && pixels > 10000);
    /* Cheap path: exactly one reciprocal per span, none per pixel. */
    assert_int_equal(ops.div, spans);
    assert_true(worst < 2e-3);
}

static void test_adaptive_wall_takes_column_path(void **state)
{
    (void)state;
    persp_method_sel sel = resolve("adaptive");
    test_rng rng = {161};
    long wrong = 0, walls = 0;
    sink_state st = {0};
    st.eps2 = 2.5e-7; /* 2^-22 */
    for (int i = 0; i < 20; i++) {
        persp_tri t;
        persp_rational_vertices vv;
        if (!axis_triangle(&rng, 1, &t, &vv)) continue;
        assert_true(t.rat.h == 0.0 && t.rat.e == 0.0);
        walls++;
        persp_opcount ops = {0};
        sink_state one = st;
        one.pixels = 0;
        wrong += traverse_all(&sel, &t, &vv, &rng, &one, &ops);
        /* The grid pass costs one reciprocal per covered column and tile. */
        long cols = 0;
        for (int ty = t.ymin / 64 * 64; ty <= t.ymax; ty += 64)
            for (int x = t.xmin; x <= t.xmax; x++) {
                int cov = 0;
                for (int y = ty > t.ymin ? ty : t.ymin; y <= ty + 63 && y <= t.ymax && !cov; y++) {
                    int lo, hi;
                    cov = persp__tri_row_range(&t, y, x, x, &lo, &hi);
                }
                cols += cov;
            }
        assert_int_equal(ops.div, cols);
        st.worst = fmax(st.worst, one.worst), st.over = fmax(st.over, one.over);
        st.pixels += one.pixels, st.span_mismatch += one.span_mismatch;
        st.bad_batch += one.bad_batch;
    }
    print_message("adaptive on %ld walls: %ld px, max %.2g texel\n", walls, st.pixels, st.worst);
    assert_true(walls > 10);
    assert_int_equal(wrong, 0);
    assert_int_equal(st.bad_batch, 0);
    assert_int_equal(st.span_mismatch, 0);
    assert_true(st.over <= 0.0);
}

/* General triangles: the fallback runs, with its own values and traversal. */
static void test_adaptive_fallback(void **state)
{
    (void)state;
    persp_method_sel ad = resolve("adaptive"), ex = resolve("exact");
    persp_method_sel adz = resolve("adaptive:fallback=constz:eps=0.01");
    test_rng rng = {55};
    long differ = 0, wrong = 0;
    sink_state st = {0};
    st.eps2 = 0.01 * 0.01 * (1.0 + 1e-9);
    for (int i = 0; i < 10; i++) {
        persp_tri t;
        persp_rational_vertices vv;
        if (!random_triangle(&rng, 3.0, &t, &vv)) continue;
        persp_method_prep prep;
        ad.m->prepare(&t.rat, &vv, &ad.params, &prep, NULL);
        for (int y = t.ymin; y <= t.ymax; y += 3) {
            int lo, hi;
            if (!persp__tri_row_range(&t, y, 0, VW - 1, &lo, &hi)) continue;
            int n = hi - lo + 1 > PERSP_SPAN_MAX ? PERSP_SPAN_MAX : hi - lo + 1;
            float u[PERSP_SPAN_MAX], v[PERSP_SPAN_MAX], eu[PERSP_SPAN_MAX], ev[PERSP_SPAN_MAX];
            ad.m->span(&t.rat, &ad.params, &prep, lo, y, n, u, v, NULL);
            ex.m->span(&t.rat, &ex.params, NULL, lo, y, n, eu, ev, NULL);
            differ += memcmp(u, eu, (size_t)n * sizeof(float)) != 0;
            differ += memcmp(v, ev, (size_t)n * sizeof(float)) != 0;
        }
        wrong += traverse_all(&adz, &t, &vv, &rng, &st, NULL);
    }
    assert_int_equal(differ, 0);
    assert_int_equal(wrong, 0);
    assert_int_equal(st.span_mismatch, 0);
    assert_true(st.over <= 0.0);
}

/* Bad input: all-zero planes, negative depth, NaN. Finite or zero values,
 * no division by zero (checked under the sanitizers), the traversal still
 * visits only covered pixels. */
static void test_degenerate_planes(void **state)
{
    (void)state;
    static const char *specs[] = {"constz", "adaptive", "adaptive:fallback=constz"};
    persp_rational bad[3];
    memset(bad, 0, sizeof bad);
    const persp_rational_vertices bv = {.x = {0}}; /* at the origin: depths 0, -1 and NaN there */
    bad[1].g = 0.01, bad[1].h = -0.02, bad[1].i = -1.0, bad[1].a = 1.0, bad[1].xmax = 9, bad[1].ymax = 9;
    bad[2].g = NAN, bad[2].i = 1.0, bad[2].xmax = 3, bad[2].ymax = 3;
    for (int s = 0; s < 3; s++) {
        persp_method_sel sel = resolve(specs[s]);
        for (int b = 0; b < 3; b++) {
            persp_method_prep prep;
            memset(&prep, 0, sizeof prep);
            if (sel.m->prepare) sel.m->prepare(&bad[b], &bv, &sel.params, &prep, NULL);
            float u[8], v[8];
            sel.m->span(&bad[b], &sel.params, &prep, 0, 2, 8, u, v, NULL);
            for (int k = 0; k < 8 && b < 2; k++) assert_true(isfinite(u[k]) && isfinite(v[k]));
        }
    }
}

static void test_parse(void **state)
{
    (void)state;
    assert_int_equal(persp_method_check("constz"), PERSP_OK);
    assert_int_equal(persp_method_check("constz:eps=0.001"), PERSP_OK);
    assert_int_equal(persp_method_check("constz:eps=-1"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("constz:eps=x"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("constz:k=2"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("adaptive"), PERSP_OK);
    assert_int_equal(persp_method_check("adaptive:fallback=midpoint:int"), PERSP_OK);
    assert_int_equal(persp_method_check("adaptive:fallback=adaptive"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("adaptive:fallback=nosuch"), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(persp_method_check("adaptive:other=exact"), PERSP_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constz_coverage_and_values),
        cmocka_unit_test(test_constz_unguarded),
        cmocka_unit_test(test_constz_constant_depth),
        cmocka_unit_test(test_adaptive_floor_takes_row_path),
        cmocka_unit_test(test_adaptive_wall_takes_column_path),
        cmocka_unit_test(test_adaptive_fallback),
        cmocka_unit_test(test_degenerate_planes),
        cmocka_unit_test(test_parse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
