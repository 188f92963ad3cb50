/* Clipping, setup, fill rule and watertightness. */
#include "support.h"

#include "raster/raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static persp_clipvert cv(float x, float y, float z, float w)
{
    persp_clipvert v;
    memset(&v, 0, sizeof v);
    v.clip[0] = x, v.clip[1] = y, v.clip[2] = z, v.clip[3] = w;
    v.attr[PERSP_A_U] = x;
    v.attr[PERSP_A_V] = w;
    return v;
}

static void test_clip_inside_unchanged(void **state)
{
    (void)state;
    persp_clipvert in[3] = {cv(-0.5f, -0.5f, 0, 1), cv(0.5f, -0.5f, 0, 1), cv(0, 0.5f, 0, 1)}, out[PERSP_CLIP_MAX];
    assert_int_equal(persp__clip_triangle(in, 8, 8, out), 3);
    assert_memory_equal(in, out, sizeof in);
}

static void test_clip_all_outside(void **state)
{
    (void)state;
    /* Entirely behind the eye (w < 0) and entirely beyond far. */
    persp_clipvert a[3] = {cv(0, 0, 0, -1), cv(1, 0, 0, -2), cv(0, 1, 0, -1)}, out[PERSP_CLIP_MAX];
    assert_int_equal(persp__clip_triangle(a, 8, 8, out), 0);
    persp_clipvert b[3] = {cv(0, 0, 3, 1), cv(1, 0, 3, 1), cv(0, 1, 3, 1)};
    assert_int_equal(persp__clip_triangle(b, 8, 8, out), 0);
}

static void test_clip_near_plane(void **state)
{
    (void)state;
    /* One vertex behind the near plane (z < -w): the result is a quad whose
     * new vertices lie exactly on z = -w, and attributes follow linearly. */
    persp_clipvert in[3] = {cv(0, 0, -3, 1), cv(0.5f, 0, 0.5f, 1), cv(0, 0.5f, 0.5f, 1)}, out[PERSP_CLIP_MAX];
    int n = persp__clip_triangle(in, 8, 8, out);
    assert_int_equal(n, 4);
    int on_plane = 0;
    for (int i = 0; i < n; i++) {
        assert_true(out[i].clip[2] + out[i].clip[3] >= -1e-6f);
        if (fabsf(out[i].clip[2] + out[i].clip[3]) < 1e-6f) {
            on_plane++;
            assert_true(fabsf(out[i].attr[PERSP_A_U] - out[i].clip[0]) < 1e-6f);
        }
    }
    assert_int_equal(on_plane, 2);
}

static void test_clip_rejects_nan_inf(void **state)
{
    (void)state;
    persp_clipvert out[PERSP_CLIP_MAX];
    persp_clipvert a[3] = {cv(NAN, 0, 0, 1), cv(1, 0, 0, 1), cv(0, 1, 0, 1)};
    assert_int_equal(persp__clip_triangle(a, 8, 8, out), 0);
    persp_clipvert b[3] = {cv(0, 0, 0, INFINITY), cv(1, 0, 0, 1), cv(0, 1, 0, 1)};
    assert_int_equal(persp__clip_triangle(b, 8, 8, out), 0);
    persp_clipvert c[3] = {cv(0, 0, 0, 1), cv(1, 0, 0, 1), cv(0, 1, 0, 1)};
    c[2].attr[PERSP_A_U] = NAN;
    assert_int_equal(persp__clip_triangle(c, 8, 8, out), 0);
}

static void test_clip_w_not_positive(void **state)
{
    (void)state;
    /* One vertex behind the eye (w < 0) and one exactly on the eye plane
     * (w = 0): clipping happens before any divide, so every output vertex
     * has w > 0 and lies on the visible side of the near plane. */
    persp_clipvert out[PERSP_CLIP_MAX];
    persp_clipvert a[3] = {cv(0.2f, 0.1f, 0.5f, -0.5f), cv(0.5f, -0.5f, 0.5f, 1), cv(-0.5f, 0.5f, 0.5f, 2)};
    persp_clipvert b[3] = {cv(0.2f, 0.1f, 0, 0), cv(0.5f, -0.5f, 0.5f, 1), cv(-0.5f, 0.5f, 0.5f, 2)};
    for (int t = 0; t < 2; t++) {
        int n = persp__clip_triangle(t ? b : a, 8, 8, out);
        assert_true(n >= 3);
        for (int i = 0; i < n; i++) {
            assert_true(out[i].clip[3] > 0.0f);
            assert_true(out[i].clip[2] + out[i].clip[3] >= -1e-6f);
        }
    }
}

static void test_clip_guard_band(void **state)
{
    (void)state;
    /* Far outside in x: clipped to |x| <= g·w, not rejected. */
    persp_clipvert in[3] = {cv(-100, -0.5f, 0, 1), cv(100, -0.5f, 0, 1), cv(0, 0.5f, 0, 1)}, out[PERSP_CLIP_MAX];
    int n = persp__clip_triangle(in, 8, 8, out);
    assert_true(n >= 4);
    for (int i = 0; i < n; i++) assert_true(fabsf(out[i].clip[0]) <= 8.0f * out[i].clip[3] + 1e-4f);
}

static float zero_attr[PERSP_A_COUNT];

static persp_winvert wv(double x, double y)
{
    persp_winvert v = {x, y, 0.5, 1.0, zero_attr};
    return v;
}

static void test_setup_degenerate_and_cull(void **state)
{
    (void)state;
    persp_tri t;
    persp_winvert line[3] = {wv(1, 1), wv(5, 5), wv(9, 9)};
    assert_int_equal(persp__setup_triangle(line, 16, 16, 0, &t, NULL), 0);
    persp_winvert ccw[3] = {wv(1, 1), wv(9, 1), wv(1, 9)};
    persp_winvert cw[3] = {wv(1, 1), wv(1, 9), wv(9, 1)};
    assert_int_equal(persp__setup_triangle(ccw, 16, 16, 1, &t, NULL), 1);
    assert_int_equal(t.backfacing, 0);
    assert_int_equal(persp__setup_triangle(cw, 16, 16, 1, &t, NULL), 0);
    assert_int_equal(persp__setup_triangle(cw, 16, 16, 0, &t, NULL), 1);
    assert_int_equal(t.backfacing, 1);
    persp_winvert off[3] = {wv(-20, -20), wv(-10, -20), wv(-20, -10)};
    assert_int_equal(persp__setup_triangle(off, 16, 16, 0, &t, NULL), 0);
    persp_winvert bad[3] = {wv(NAN, 1), wv(9, 1), wv(1, 9)};
    assert_int_equal(persp__setup_triangle(bad, 16, 16, 0, &t, NULL), 0);
}

/* Counts coverage of a triangle into cnt (w×h). */
static void cover(const persp_winvert v[3], int w, int h, int *cnt)
{
    persp_tri t;
    if (!persp__setup_triangle(v, w, h, 0, &t, NULL)) return;
    for (int y = 0; y < h; y++) {
        int lo, hi;
        if (!persp__tri_row_range(&t, y, 0, w - 1, &lo, &hi)) continue;
        for (int x = lo; x <= hi; x++) cnt[y * w + x]++;
    }
}

static void test_fill_rule_pixel_centres(void **state)
{
    (void)state;
    /* The square (0,0)-(4,4) split on its diagonal: every pixel exactly once,
     * including centres lying on the shared diagonal. */
    int cnt[36] = {0};
    persp_winvert a[3] = {wv(0, 0), wv(4, 0), wv(4, 4)}, b[3] = {wv(0, 0), wv(4, 4), wv(0, 4)};
    cover(a, 6, 6, cnt);
    cover(b, 6, 6, cnt);
    for (int y = 0; y < 6; y++)
        for (int x = 0; x < 6; x++) assert_int_equal(cnt[y * 6 + x], (x < 4 && y < 4) ? 1 : 0);
    /* Top-left rule: a triangle whose left edge passes exactly through pixel
     * centres (x = 2.5) owns them; one whose right edge does does not. */
    persp_tri t;
    persp_winvert left[3] = {wv(2.5, 0), wv(6, 0), wv(2.5, 4)};
    assert_int_equal(persp__setup_triangle(left, 8, 8, 0, &t, NULL), 1);
    int lo, hi;
    assert_int_equal(persp__tri_row_range(&t, 0, 0, 7, &lo, &hi), 1);
    assert_int_equal(lo, 2);
    persp_winvert right[3] = {wv(0, 0), wv(2.5, 0), wv(2.5, 4)};
    assert_int_equal(persp__setup_triangle(right, 8, 8, 0, &t, NULL), 1);
    assert_int_equal(persp__tri_row_range(&t, 1, 0, 7, &lo, &hi), 1);
    assert_int_equal(hi, 1);
}

static void test_watertight_random_mesh(void **state)
{
    (void)state;
    /* A jittered grid of shared vertices: the union of its triangles is the
     * hull, and every pixel centre inside is covered exactly once. */
    enum { W = 200, H = 160, GX = 9, GY = 7 };
    test_rng rng = {12345};
    double px[GY + 1][GX + 1], py[GY + 1][GX + 1];
    for (int j = 0; j <= GY; j++)
        for (int i = 0; i <= GX; i++) {
            double jx = (i > 0 && i < GX) ? test_rng_uniform(&rng, -7, 7) : 0;
            double jy = (j > 0 && j < GY) ? test_rng_uniform(&rng, -7, 7) : 0;
            /* Off-grid in sub-pixel terms, and some exactly on pixel centres. */
            if (test_rng_next(&rng) % 4 == 0) jx = floor(jx) + 0.5;
            px[j][i] = 10 + i * 20.0 + jx;
            py[j][i] = 5 + j * 20.0 + jy;
        }
    int *cnt = calloc(W * H, sizeof *cnt);
    assert_non_null(cnt);
    for (int j = 0; j < GY; j++)
        for (int i = 0; i < GX; i++) {
            persp_winvert a = wv(px[j][i], py[j][i]), b = wv(px[j][i + 1], py[j][i + 1]);
            persp_winvert c = wv(px[j + 1][i + 1], py[j + 1][i + 1]), d = wv(px[j + 1][i], py[j + 1][i]);
            int flip = (int)(test_rng_next(&rng) & 1);
            persp_winvert t1[3] = {a, b, flip ? d : c}, t2[3] = {flip ? b : a, c, d};
            /* Mixed winding: half the triangles are given clockwise. */
            if (test_rng_next(&rng) & 1) {
                persp_winvert s = t1[1];
                t1[1] = t1[2];
                t1[2] = s;
            }
            cover(t1, W, H, cnt);
            cover(t2, W, H, cnt);
        }
    int inside = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double cx = x + 0.5, cy = y + 0.5;
            int in = cx > 10 && cx < 10 + GX * 20.0 && cy > 5 && cy < 5 + GY * 20.0;
            if (in) {
                inside++;
                if (cnt[y * W + x] != 1) fail_msg("pixel (%d,%d) covered %d times", x, y, cnt[y * W + x]);
            } else if (cnt[y * W + x] != 0 && !(cx == 10 || cy == 5)) {
                fail_msg("pixel (%d,%d) outside the hull covered %d times", x, y, cnt[y * W + x]);
            }
        }
    assert_true(inside > 20000);
    free(cnt);
}

static void test_watertight_guard_band_fan(void **state)
{
    (void)state;
    /* A fan of triangles whose outer vertices lie thousands of pixels
     * outside the viewport (inside the guard band, so set up without
     * clipping, with the 64-bit edge products): every pixel of the viewport
     * is covered exactly once. */
    enum { W = 160, H = 120, N = 10 };
    int *cnt = calloc(W * H, sizeof *cnt);
    assert_non_null(cnt);
    /* The centre is a pixel centre and the edges run along rows, columns,
     * diagonals and other rational slopes, so many pixel centres lie
     * exactly on shared edges and only the fill rule decides them. */
    const double cx = 77.5, cy = 51.5, R = 3000.0;
    static const int dir[N][2] = {{1, 0}, {2, 1}, {1, 1}, {0, 1},  {-1, 2},
                                  {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {3, -1}};
    for (int k = 0; k < N; k++) {
        const int *a = dir[k], *b = dir[(k + 1) % N];
        persp_winvert t[3] = {wv(cx, cy), wv(cx + R * a[0], cy + R * a[1]),
                              wv(cx + R * b[0], cy + R * b[1])};
        cover(t, W, H, cnt);
    }
    for (int i = 0; i < W * H; i++)
        if (cnt[i] != 1) fail_msg("pixel (%d,%d) covered %d times", i % W, i / W, cnt[i]);
    free(cnt);
}

/* The row walk (exact stepping, or the coverage mask set-up keeps for a
 * small box) gives the same ranges as the per-row division for every row
 * and clip window: random triangles of all sizes and slopes, vertices on
 * and off the sub-pixel grid, both windings, and windows that cut them
 * (the tile loop starts a walk at the tile's row). */
static void test_row_walk_matches_row_range(void **state)
{
    (void)state;
    test_rng rng = {777};
    int checked = 0, masked = 0;
    for (int n = 0; n < 4000; n++) {
        double s = n % 4 == 0 ? 300 : n % 4 == 1 ? 40 : n % 4 == 2 ? 6 : 1.5;
        double cx = test_rng_uniform(&rng, -20, 220), cy = test_rng_uniform(&rng, -20, 180);
        persp_winvert v[3];
        for (int k = 0; k < 3; k++) {
            double x = cx + test_rng_uniform(&rng, -s, s), y = cy + test_rng_uniform(&rng, -s, s);
            if (test_rng_next(&rng) % 5 == 0) x = floor(x) + 0.5;
            if (test_rng_next(&rng) % 5 == 0) y = floor(y);
            /* On a half-pixel lattice edges pass exactly through pixel
             * centres of many rows (the remainder reaches its bound). */
            if (n % 3 == 0) x = floor(2 * x) * 0.5, y = floor(2 * y) * 0.5;
            v[k] = wv(x, y);
        }
        if (n % 7 == 0) v[1] = wv(v[0].x + 30, v[0].y); /* a horizontal edge */
        persp_tri t;
        if (!persp__setup_triangle(v, 200, 160, 0, &t, NULL)) continue;
        masked += t.cover != 0;
        const int x0 = (int)(test_rng_next(&rng) % 200), x1 = x0 + (int)(test_rng_next(&rng) % 80);
        /* From the box's first row or a later one, up to two rows below
         * a box of one row (no row then). */
        const int ya = t.ymin + (int)(test_rng_next(&rng) % 3);
        /* Every eighth walk of one row, which skips the per-row steps. */
        const int rows = n % 8 == 0 ? 1 : t.ymax - ya + 1;
        persp_row_walk w;
        persp__row_walk_init(&w, &t, ya, rows, x0, x1);
        for (int y = ya; y <= t.ymax && y < ya + rows; y++) {
            int lo = -1, hi = -1, lo2 = -1, hi2 = -1;
            int a = persp__tri_row_range(&t, y, x0, x1, &lo, &hi);
            int b = persp__row_walk_next(&w, &lo2, &hi2);
            if (a != b || (a && (lo != lo2 || hi != hi2)))
                fail_msg("triangle %d row %d: range %d [%d, %d], walk %d [%d, %d]", n, y, a, lo, hi, b,
                         lo2, hi2);
            checked += a;
        }
    }
    assert_true(checked > 10000);
    assert_true(masked > 500);
    /* Edges with small coefficients, so that a pixel centre often lies
     * exactly on an edge (the remainder reaches its bound) for both signs
     * of A, and horizontal edges; the two functions read only the edges
     * and the box. */
    for (int n = 0; n < 3000; n++) {
        persp_tri t;
        memset(&t, 0, sizeof t);
        t.xmin = (int)(test_rng_next(&rng) % 50), t.xmax = t.xmin + (int)(test_rng_next(&rng) % 150);
        t.ymin = (int)(test_rng_next(&rng) % 50), t.ymax = t.ymin + (int)(test_rng_next(&rng) % 100);
        for (int k = 0; k < 3; k++) {
            /* Through a point of the box (in 1/256 px), so that each edge
             * bounds some rows. */
            int64_t X = (int64_t)(test_rng_next(&rng) % (uint64_t)(256 * (t.xmax + 1)));
            int64_t Y = (int64_t)(test_rng_next(&rng) % (uint64_t)(256 * (t.ymax + 1)));
            t.ea[k] = (int64_t)(test_rng_next(&rng) % 7) - 3;
            t.eb[k] = (int64_t)(test_rng_next(&rng) % 1401) - 700;
            t.ec[k] = -(t.ea[k] * X + t.eb[k] * Y) + (int64_t)(test_rng_next(&rng) % 5) - 2;
        }
        persp_row_walk w;
        persp__row_walk_init(&w, &t, t.ymin, t.ymax - t.ymin + 1, 0, 199);
        for (int y = t.ymin; y <= t.ymax; y++) {
            int lo = -1, hi = -1, lo2 = -1, hi2 = -1;
            int a = persp__tri_row_range(&t, y, 0, 199, &lo, &hi);
            int b = persp__row_walk_next(&w, &lo2, &hi2);
            if (a != b || (a && (lo != lo2 || hi != hi2)))
                fail_msg("edges %d row %d: range %d [%d, %d], walk %d [%d, %d]", n, y, a, lo, hi, b, lo2,
                         hi2);
            checked += a;
        }
    }
}

/* Outcodes agree with the clipper (raster.h's contract): codes sharing a
 * bit mean clipping leaves nothing, all-zero codes mean it returns the
 * triangle unchanged, and a NaN or infinity anywhere gives
 * PERSP_CLIP_NONFINITE alone and a rejected triangle. Vertices are drawn
 * around each plane, on it, and with non-finite values in any field. */
static void test_outcodes_agree_with_clipper(void **state)
{
    (void)state;
    test_rng rng = {4242};
    const double gx = 3.0, gy = 2.0;
    int shared = 0, inside = 0, nonfinite = 0;
    for (int n = 0; n < 20000; n++) {
        persp_clipvert in[3];
        unsigned code[3];
        for (int k = 0; k < 3; k++) {
            const float w = (float)test_rng_uniform(&rng, -0.5, 3.0);
            in[k] = cv((float)test_rng_uniform(&rng, -4, 4) * w, (float)test_rng_uniform(&rng, -3, 3) * w,
                       (float)test_rng_uniform(&rng, -1.3, 1.3) * w, w);
            for (int a = 0; a < PERSP_A_COUNT; a++) in[k].attr[a] = (float)test_rng_uniform(&rng, -1, 1);
            if (test_rng_next(&rng) % 11 == 0) in[k].clip[2] = -in[k].clip[3]; /* on the near plane */
            if (test_rng_next(&rng) % 53 == 0) {
                const float bad[] = {NAN, INFINITY, -INFINITY};
                const float b = bad[test_rng_next(&rng) % 3];
                const unsigned field = (unsigned)(test_rng_next(&rng) % (4 + PERSP_A_COUNT));
                if (field < 4) in[k].clip[field] = b;
                else in[k].attr[field - 4] = b;
            }
            code[k] = persp__clip_outcode(&in[k], gx, gy);
        }
        persp_clipvert out[PERSP_CLIP_MAX];
        const int m = persp__clip_triangle(in, gx, gy, out);
        const unsigned any = code[0] | code[1] | code[2];
        if (any & PERSP_CLIP_NONFINITE) {
            for (int k = 0; k < 3; k++)
                if (code[k] & PERSP_CLIP_NONFINITE) assert_int_equal(code[k], PERSP_CLIP_NONFINITE);
            assert_int_equal(m, 0);
            nonfinite++;
        } else if (code[0] & code[1] & code[2]) {
            if (m != 0) fail_msg("triangle %d: codes %x %x %x share a bit, clipping left %d vertices", n,
                                 code[0], code[1], code[2], m);
            shared++;
        } else if (!any) {
            assert_int_equal(m, 3);
            assert_memory_equal(in, out, sizeof in);
            inside++;
        }
    }
    assert_true(shared > 100 && inside > 100 && nonfinite > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clip_inside_unchanged), cmocka_unit_test(test_clip_all_outside),
        cmocka_unit_test(test_clip_near_plane), cmocka_unit_test(test_clip_rejects_nan_inf),
        cmocka_unit_test(test_clip_w_not_positive), cmocka_unit_test(test_clip_guard_band), cmocka_unit_test(test_setup_degenerate_and_cull),
        cmocka_unit_test(test_fill_rule_pixel_centres), cmocka_unit_test(test_watertight_random_mesh),
        cmocka_unit_test(test_watertight_guard_band_fan), cmocka_unit_test(test_row_walk_matches_row_range), cmocka_unit_test(test_outcodes_agree_with_clipper),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
