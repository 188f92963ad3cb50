/*
 * persp accuracy: the metric code on synthetic data whose answers the test
 * computes itself, the paper-quad mapping (Heckbert 1989 §2.2.3), the exact
 * method against the reference, affine far off at high depth ratio, and the
 * CSV and JSON writers producing parseable output.
 */
#include "support.h"

#include "analysis/analysis.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void test_errstats_percentile(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {12345};
    const size_t sizes[] = {1, 2, 7, 100, 1001, 5000};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        size_t n = sizes[si];
        double *v = malloc(n * sizeof *v), *sorted = malloc(n * sizeof *v);
        assert_non_null(v);
        assert_non_null(sorted);
        persp_errstats s;
        persp__errstats_init(&s, ctx);
        assert_int_equal(persp__errstats_reserve(&s, n), PERSP_OK);
        double sum = 0.0, mx = 0.0;
        for (size_t i = 0; i < n; i++) {
            /* Many duplicates (rounded values) exercise the three-way partition. */
            v[i] = floor(test_rng_uniform(&rng, 0.0, 50.0));
            sum += v[i];
            if (v[i] > mx) mx = v[i];
            persp__errstats_add(&s, v[i]);
        }
        memcpy(sorted, v, n * sizeof *v);
        qsort(sorted, n, sizeof *sorted, cmp_double);
        assert_int_equal(s.count, n);
        assert_int_equal(s.dropped, 0);
        assert_true(fabs(persp__errstats_mean(&s) - sum / (double)n) < 1e-12 * (1.0 + sum));
        assert_true(s.max == mx);
        const double ps[] = {1.0, 50.0, 90.0, 99.0, 100.0};
        for (size_t k = 0; k < sizeof ps / sizeof ps[0]; k++) {
            size_t rank = (size_t)ceil(ps[k] / 100.0 * (double)n);
            if (rank < 1) rank = 1;
            double want = sorted[rank - 1];
            assert_true(persp__errstats_percentile(&s, ps[k]) == want);
        }
        persp__errstats_free(&s);
        free(v);
        free(sorted);
    }
    /* Without room, values still count in max and mean but are not stored. */
    persp_errstats s;
    persp__errstats_init(&s, ctx);
    persp__errstats_add(&s, 3.0);
    assert_int_equal(s.dropped, 1);
    assert_true(s.max == 3.0);
    assert_true(persp__errstats_percentile(&s, 99.0) == 0.0);
    persp__errstats_free(&s);
    persp_context_destroy(ctx);
}

static void test_metrics_span(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    test_rng rng = {777};
    const double floor_v = 0.05, scale1 = 256.0, scale2 = 128.0;
    persp_acc_metrics m;
    persp__acc_metrics_init(&m, ctx, floor_v);
    assert_int_equal(persp__errstats_reserve(&m.eu, 1000), PERSP_OK);
    assert_int_equal(persp__errstats_reserve(&m.ev, 1000), PERSP_OK);
    double want_max_u = 0, want_max_v = 0, want_sum_u = 0, want_relpt_u = 0, want_relpt_v = 0;
    double want_relspan_u = 0, want_relspan_v = 0;
    uint64_t want_miss = 0, want_pixels = 0;
    for (int span = 0; span < 10; span++) {
        int n = 1 + (int)(test_rng_next(&rng) % 40);
        double x1[64], x2[64];
        float s1[64], s2[64], err[64];
        double lo1 = 1e9, hi1 = -1e9, lo2 = 1e9, hi2 = -1e9, dm1 = 0, dm2 = 0;
        for (int k = 0; k < n; k++) {
            x1[k] = test_rng_uniform(&rng, -0.2, 1.0);
            x2[k] = test_rng_uniform(&rng, 0.0, 0.3) * (span + 1) / 10.0;
            s1[k] = (float)(x1[k] + test_rng_uniform(&rng, -0.01, 0.01));
            s2[k] = (float)(x2[k] + test_rng_uniform(&rng, -0.002, 0.002));
            double d1 = fabs((double)s1[k] - x1[k]), d2 = fabs((double)s2[k] - x2[k]);
            want_max_u = fmax(want_max_u, d1 * scale1);
            want_max_v = fmax(want_max_v, d2 * scale2);
            want_sum_u += d1 * scale1;
            if (floor((double)s1[k] * scale1) != floor(x1[k] * scale1) ||
                floor((double)s2[k] * scale2) != floor(x2[k] * scale2))
                want_miss++;
            if (fabs(x1[k]) >= floor_v) want_relpt_u = fmax(want_relpt_u, d1 / fabs(x1[k]));
            if (fabs(x2[k]) >= floor_v) want_relpt_v = fmax(want_relpt_v, d2 / fabs(x2[k]));
            lo1 = fmin(lo1, x1[k]), hi1 = fmax(hi1, x1[k]);
            lo2 = fmin(lo2, x2[k]), hi2 = fmax(hi2, x2[k]);
            dm1 = fmax(dm1, d1), dm2 = fmax(dm2, d2);
        }
        if (hi1 - lo1 >= floor_v) want_relspan_u = fmax(want_relspan_u, dm1 / (hi1 - lo1));
        if (hi2 - lo2 >= floor_v) want_relspan_v = fmax(want_relspan_v, dm2 / (hi2 - lo2));
        want_pixels += (uint64_t)n;
        persp__acc_metrics_span(&m, n, x1, x2, s1, s2, scale1, scale2, err);
        for (int k = 0; k < n; k++) {
            double e = fmax(fabs((double)s1[k] - x1[k]) * scale1, fabs((double)s2[k] - x2[k]) * scale2);
            assert_true(fabs((double)err[k] - e) <= 1e-6 * (1.0 + e));
        }
    }
    assert_int_equal(m.pixels, want_pixels);
    assert_int_equal(m.spans, 10);
    assert_int_equal(m.texel_miss, want_miss);
    assert_true(m.eu.max == want_max_u);
    assert_true(m.ev.max == want_max_v);
    assert_true(fabs(persp__errstats_mean(&m.eu) - want_sum_u / (double)want_pixels) < 1e-9);
    assert_true(m.relpt_u == want_relpt_u);
    assert_true(m.relpt_v == want_relpt_v);
    assert_true(m.relspan_u == want_relspan_u);
    assert_true(m.relspan_v == want_relspan_v);
    /* A NaN from a method is an infinite error, never a silent zero. */
    double x = 0.5;
    float nanv = NAN;
    persp__acc_metrics_span(&m, 1, &x, &x, &nanv, &nanv, 1.0, 1.0, NULL);
    assert_true(isinf(m.eu.max));
    persp__acc_metrics_free(&m);
    persp_context_destroy(ctx);
}

static void test_paper_quad_corners(void **state)
{
    (void)state;
    double fwd[9], inv[9];
    assert_int_equal(persp__square_to_quad(persp__paper_quad_x, persp__paper_quad_y, fwd, inv), 1);
    const double us[4] = {0, 1, 1, 0}, vs[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; k++) {
        /* Forward: [u v 1]·M = [x·w y·w w]. */
        double xw = us[k] * fwd[0] + vs[k] * fwd[3] + fwd[6];
        double yw = us[k] * fwd[1] + vs[k] * fwd[4] + fwd[7];
        double w = us[k] * fwd[2] + vs[k] * fwd[5] + fwd[8];
        assert_true(fabs(xw / w - persp__paper_quad_x[k]) < 1e-12 * 128);
        assert_true(fabs(yw / w - persp__paper_quad_y[k]) < 1e-12 * 128);
        /* Inverse as Heckbert's a..i, and through the rational form at the
         * pixel that samples the corner. */
        double X = persp__paper_quad_x[k], Y = persp__paper_quad_y[k];
        double q = inv[6] * X + inv[7] * Y + inv[8];
        assert_true(q > 0.0);
        assert_true(fabs((inv[0] * X + inv[1] * Y + inv[2]) / q - us[k]) < 1e-12);
        assert_true(fabs((inv[3] * X + inv[4] * Y + inv[5]) / q - vs[k]) < 1e-12);
        persp_rational r;
        persp_rational_vertices rv;
        persp__paper_quad_rational(0, 1, 2, 256.0, &r, &rv);
        double u, v;
        persp__rational_eval(&r, X, Y, &u, &v);
        assert_true(fabs(u - us[k]) < 1e-12);
        assert_true(fabs(v - vs[k]) < 1e-12);
    }
    /* The chapter's line: v runs from 0 on edge c0c1 to 1 at c3 = (128, 32),
     * where u = 0; both ends lie on the quad's edges. */
    persp_rational r;
    persp_rational_vertices rv;
    double xl, xr, u, v;
    persp__paper_quad_line(64, 256.0, &r, &rv, &xl, &xr);
    assert_true(fabs(xl - (1.0 + 31.0 * 31.0 / 95.0)) < 1e-12);
    assert_true(fabs(xr - 128.0) < 1e-12);
    persp__rational_eval(&r, 0, 0, &u, &v);
    assert_true(fabs(v) < 1e-12 && u > 0.0 && u < 1.0);
    persp__rational_eval(&r, 63, 0, &u, &v);
    assert_true(fabs(u) < 1e-12 && fabs(v - 1.0) < 1e-12);
    /* The vertices carried for vertex-based methods agree with the planes. */
    for (int k = 0; k < 3; k++) {
        double q = r.g * rv.x[k] + r.h * rv.y[k] + r.i;
        assert_true(fabs((r.a * rv.x[k] + r.b * rv.y[k] + r.c) / q - rv.s1[k]) < 1e-9);
        assert_true(fabs((r.d * rv.x[k] + r.e * rv.y[k] + r.f) / q - rv.s2[k]) < 1e-9);
        assert_true(fabs(q - rv.q[k]) < 1e-9 * fabs(q));
    }
}

static persp_accuracy_result *run(persp_context *ctx, const char *method, const char *const *cases,
                                  size_t ncases, int triangles)
{
    persp_accuracy_desc d;
    memset(&d, 0, sizeof d);
    d.methods = &method;
    d.method_count = 1;
    d.cases = cases;
    d.case_count = ncases;
    d.triangles = triangles;
    persp_accuracy_result *res = NULL;
    persp_status st = persp_accuracy_run(ctx, &d, &res);
    if (st != PERSP_OK) fprintf(stderr, "accuracy: %s\n", persp_context_error(ctx));
    assert_int_equal(st, PERSP_OK);
    return res;
}

static void test_exact_is_exact(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *cases[] = {"paper-quad", "paper-quad-full", "random-triangles"};
    persp_accuracy_result *res = run(ctx, "exact", cases, 3, 12);
    assert_int_equal(persp_accuracy_row_count(res), 2 + PERSP_HBAR_COUNT);
    for (size_t i = 0; i < persp_accuracy_row_count(res); i++) {
        const persp_accuracy_row *r = persp_accuracy_row_at(res, i);
        assert_true(r->pixels > 0);
        assert_true(r->max_u < 1e-3 && r->max_v < 1e-3);
        assert_true(r->p99_u <= r->max_u && r->mean_u <= r->max_u);
        assert_true(r->ops_measured && r->div_px > 0.0);
    }
    /* The paper line is one span of 64 samples; the full quad covers its
     * area (two triangles, ~8600 pixels by the shoelace formula). */
    assert_int_equal(persp_accuracy_row_at(res, 0)->pixels, PERSP_ACCURACY_LINE_SAMPLES);
    assert_int_equal(persp_accuracy_row_at(res, 0)->spans, 1);
    double area = 0.0;
    for (int k = 0; k < 4; k++)
        area += persp__paper_quad_x[k] * persp__paper_quad_y[(k + 1) % 4] -
                persp__paper_quad_x[(k + 1) % 4] * persp__paper_quad_y[k];
    area = fabs(area) / 2.0;
    double got = (double)persp_accuracy_row_at(res, 1)->pixels;
    assert_true(fabs(got - area) < 0.02 * area);
    persp_accuracy_destroy(res);
    persp_context_destroy(ctx);
}

static void test_affine_far_off(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *cases[] = {"random-triangles"};
    persp_accuracy_result *res = run(ctx, "affine", cases, 1, 12);
    assert_int_equal(persp_accuracy_row_count(res), PERSP_HBAR_COUNT);
    const persp_accuracy_row *lo = persp_accuracy_row_at(res, 0);
    const persp_accuracy_row *hi = persp_accuracy_row_at(res, PERSP_HBAR_COUNT - 1);
    assert_true(lo->hbar == 1.25 && hi->hbar == 8.0);
    /* [Romanyuk-PCF] §4.2 Fig. 4.4: the affine error grows with the depth ratio. */
    assert_true(fmax(hi->max_u, hi->max_v) > 10.0);
    assert_true(fmax(hi->max_u, hi->max_v) > fmax(lo->max_u, lo->max_v));
    assert_true(hi->texel_miss > 0.5);
    persp_accuracy_destroy(res);
    persp_context_destroy(ctx);
}

static void test_writers_parse(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *cases[] = {"paper-quad", "random-triangles"};
    persp_accuracy_result *res = run(ctx, "affine", cases, 2, 3);
    size_t rows = persp_accuracy_row_count(res);
    assert_int_equal(rows, 1 + PERSP_HBAR_COUNT);

    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(persp_accuracy_write(ctx, res, PERSP_REPORT_JSON, f), PERSP_OK);
    rewind(f);
    json_error_t err;
    json_t *root = json_loadf(f, 0, &err);
    assert_non_null(root);
    json_t *arr = json_object_get(root, "rows");
    assert_true(json_is_array(arr));
    assert_int_equal(json_array_size(arr), rows);
    for (size_t i = 0; i < rows; i++) {
        const persp_accuracy_row *r = persp_accuracy_row_at(res, i);
        json_t *o = json_array_get(arr, i);
        assert_string_equal(json_string_value(json_object_get(o, "method")), r->method);
        assert_int_equal(json_integer_value(json_object_get(o, "pixels")), r->pixels);
        assert_true(json_real_value(json_object_get(o, "max_u")) == r->max_u);
        assert_true(json_is_object(json_object_get(o, "ops_per_pixel")));
    }
    json_decref(root);
    fclose(f);

    f = tmpfile();
    assert_non_null(f);
    assert_int_equal(persp_accuracy_write(ctx, res, PERSP_REPORT_CSV, f), PERSP_OK);
    rewind(f);
    char line[2048];
    size_t lines = 0, header_fields = 0;
    while (fgets(line, sizeof line, f)) {
        size_t fields = 1;
        for (char *p = line; *p; p++) fields += *p == ',';
        if (lines == 0)
            header_fields = fields;
        else
            assert_int_equal(fields, header_fields);
        if (lines > 0) {
            /* Column 7 is max_u (method, case, hbar, pixels, spans, triangles, max_u). */
            char *p = line;
            for (int c = 0; c < 6; c++) p = strchr(p, ',') + 1;
            assert_true(fabs(strtod(p, NULL) - persp_accuracy_row_at(res, lines - 1)->max_u) <=
                        1e-8 * persp_accuracy_row_at(res, lines - 1)->max_u);
        }
        lines++;
    }
    assert_int_equal(lines, rows + 1);
    fclose(f);

    f = tmpfile();
    assert_non_null(f);
    assert_int_equal(persp_accuracy_write(ctx, res, PERSP_REPORT_TABLE, f), PERSP_OK);
    rewind(f);
    lines = 0;
    size_t first_len = 0;
    while (fgets(line, sizeof line, f) && line[0] != '\n') {
        if (lines == 0) first_len = strlen(line);
        else assert_int_equal(strlen(line), first_len); /* aligned columns */
        lines++;
    }
    assert_int_equal(lines, rows + 1);
    fclose(f);
    persp_accuracy_destroy(res);
    persp_context_destroy(ctx);
}

/* A built-in scene through the renderer's capture: skipped while the
 * texture module is not built. The corridor's u reaches 64 (L = 64, repeat),
 * where a float's spacing is 2^-18, i.e. 1e-3 texels of 256. */
static void test_scene_case(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *methods[] = {"exact", "affine"}, *c = "corridor";
    persp_accuracy_desc d;
    memset(&d, 0, sizeof d);
    d.methods = methods;
    d.method_count = 2;
    d.cases = &c;
    d.case_count = 1;
    d.width = 64;
    d.height = 48;
    persp_accuracy_result *res = NULL;
    persp_status st = persp_accuracy_run(ctx, &d, &res);
    if (st != PERSP_OK) fail_msg("accuracy on corridor: %s", persp_context_error(ctx));
    assert_int_equal(persp_accuracy_row_count(res), 2);
    const persp_accuracy_row *e = persp_accuracy_row_at(res, 0), *a = persp_accuracy_row_at(res, 1);
    assert_string_equal(e->case_name, "corridor@64x48");
    /* The corridor covers every pixel (docs/WORKLOADS.md). */
    assert_int_equal(e->pixels, 64 * 48);
    assert_true(e->max_u < 0.01 && e->max_v < 0.01);
    assert_true(fmax(a->max_u, a->max_v) > 100.0 * fmax(e->max_u, e->max_v));
    persp_accuracy_destroy(res);
    persp_context_destroy(ctx);
}

static void test_bad_input(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_accuracy_desc d;
    memset(&d, 0, sizeof d);
    persp_accuracy_result *res = NULL;
    const char *bad_method = "no-such-method";
    d.methods = &bad_method;
    d.method_count = 1;
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_ERR_NOT_FOUND);
    assert_null(res);
    assert_non_null(strstr(persp_context_error(ctx), "no-such-method"));
    const char *m = "exact", *bad_case = "no-such-case";
    d.methods = &m;
    d.cases = &bad_case;
    d.case_count = 1;
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_ERR_NOT_FOUND);
    assert_non_null(strstr(persp_context_error(ctx), "no-such-case"));
    d.case_count = 0;
    d.rel_floor = NAN;
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "persp_accuracy_desc.rel_floor"));
    assert_int_equal(persp_accuracy_run(ctx, NULL, &res), PERSP_ERR_INVALID_ARGUMENT);
    /* "NULL or none": a NULL list with a count is none (it was read). */
    d.rel_floor = 0.0;
    d.triangles = 1;
    d.methods = NULL;
    d.method_count = 1;
    const char *pq = "paper-quad";
    d.cases = &pq;
    d.case_count = 1;
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_OK);
    assert_true(persp_accuracy_row_count(res) > 5); /* every method */
    persp_accuracy_destroy(res);
    res = NULL;
    d.methods = &m;
    d.cases = NULL;
    d.case_count = 1;
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_OK);
    assert_true(persp_accuracy_row_count(res) > 1); /* paper-quad and the random groups */
    persp_accuracy_destroy(res);
    assert_int_equal(persp_accuracy_case_check("paper-quad"), PERSP_OK);
    assert_int_equal(persp_accuracy_case_check("corridor"), PERSP_OK);
    persp_context_destroy(ctx);
}

static int same_rgb(const uint8_t *p, const uint8_t rgb[3])
{
    return p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2];
}

/* A heat map carries its legend: a colour bar running through the whole
 * scale (from the colour of the lowest decade at its left end to that of
 * the highest at its right end) below the map, and white tick labels and
 * caption below the bar; uncovered pixels are grey; grid row 0 is drawn at
 * the bottom of the map. */
static void test_heatmap_legend(void **state)
{
    (void)state;
    enum { W = 8, H = 4 };
    float err[W * H];
    for (int i = 0; i < W * H; i++) err[i] = (i / W == H - 1) ? NAN : 1e-3f * (float)(i + 1);
    err[0] = 100.0f; /* bottom-left: the largest error, the top of the scale */
    persp_context *ctx = test_context();
    char path[256];
    snprintf(path, sizeof path, "/tmp/persp-heatmap-%ld.png", (long)getpid());
    assert_int_equal(persp__heatmap_write(ctx, path, err, W, H, PERSP_HEATMAP_TEXELS, PERSP_HEATMAP_TEXELS_TOP), PERSP_OK);
    persp_image img;
    assert_int_equal(persp_image_load(ctx, path, &img), PERSP_OK);
    remove(path);
    uint8_t lo[3], hi[3];
    persp__heatmap_color(0.0, lo);
    persp__heatmap_color(1.0, hi);
    const uint8_t grey[3] = {48, 48, 48}, white[3] = {255, 255, 255};
    int bar_top = -1, bar_rows = 0, map_bottom = -1;
    for (int y = 0; y < img.height; y++) {
        const uint8_t *row = img.pixels + (size_t)y * img.stride;
        /* The bar: the scale's two end colours at the two ends of the row,
         * and colours in between that change monotonically in green. */
        int first = -1, last = -1;
        for (int x = 0; x < img.width; x++)
            if (row[4 * x] || row[4 * x + 1] || row[4 * x + 2]) {
                if (first < 0) first = x;
                last = x;
            }
        if (first >= 0 && same_rgb(row + 4 * first, lo) && same_rgb(row + 4 * last, hi) &&
            last - first > img.width / 2) {
            int monotone = 1;
            for (int x = first + 1; x <= last; x++) monotone &= row[4 * x + 1] >= row[4 * (x - 1) + 1];
            if (monotone) {
                bar_rows++;
                if (y > bar_top) bar_top = y;
            }
        }
        /* The map's bottom row starts with the colour of err[0]. */
        if (map_bottom < 0 && same_rgb(row, hi) && same_rgb(row + 4 * (img.width / W - 1), hi) &&
            bar_top >= 0 && y > bar_top + 2)
            map_bottom = y;
    }
    print_message("heat map %dx%d: bar %d rows, top at %d; map from row %d\n", img.width, img.height,
                  bar_rows, bar_top, map_bottom);
    assert_true(bar_rows >= 8);
    assert_true(map_bottom > bar_top);
    /* Labels: white pixels below the bar. */
    long labels = 0;
    for (int y = 0; y < bar_top - bar_rows; y++)
        for (int x = 0; x < img.width; x++) labels += same_rgb(img.pixels + (size_t)y * img.stride + 4u * (size_t)x, white);
    assert_true(labels > 100);
    /* The top row of the image is grid row H - 1: uncovered, grey. */
    const uint8_t *top = img.pixels + (size_t)(img.height - 1) * img.stride;
    assert_true(same_rgb(top, grey) && same_rgb(top + 4 * (img.width - 1), grey));
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

/* Lowest image row (rows count from the bottom) and run of rows holding a
 * white pixel, from the bottom up: the legend's caption. */
static int caption_rows(const persp_image *img)
{
    const uint8_t white[3] = {255, 255, 255};
    int rows = 0, started = 0;
    for (int y = 0; y < img->height; y++) {
        int any = 0;
        for (int x = 0; x < img->width && !any; x++)
            any = same_rgb(img->pixels + (size_t)y * img->stride + 4u * (size_t)x, white);
        if (any) started = 1, rows++;
        else if (started) break;
    }
    return rows;
}

/* Maps of two methods, one erring a hundredth of a texel at most and one
 * up to 100 texels, show the same error in the same colour: one scale for
 * every map, so that a near-exact method does not look as hot as affine.
 * Their legend's text is at least 11 px tall. */
static void test_heatmap_shared_scale(void **state)
{
    (void)state;
    enum { W = 4, H = 2 };
    float small[W * H], large[W * H];
    for (int i = 0; i < W * H; i++) small[i] = large[i] = 0.01f;
    large[W * H - 1] = 100.0f;
    persp_context *ctx = test_context();
    persp_image img[2];
    const float *err[2] = {small, large};
    for (int k = 0; k < 2; k++) {
        char path[256];
        snprintf(path, sizeof path, "/tmp/persp-heatmap-%ld-%d.png", (long)getpid(), k);
        assert_int_equal(persp__heatmap_write(ctx, path, err[k], W, H, PERSP_HEATMAP_TEXELS,
                                              PERSP_HEATMAP_TEXELS_TOP),
                         PERSP_OK);
        assert_int_equal(persp_image_load(ctx, path, &img[k]), PERSP_OK);
        remove(path);
    }
    assert_int_equal(img[0].width, img[1].width);
    assert_int_equal(img[0].height, img[1].height);
    /* Top-left cell of the map (grid row H - 1): 0.01 texels in both. */
    const uint8_t *a = img[0].pixels + (size_t)(img[0].height - 1) * img[0].stride;
    const uint8_t *b = img[1].pixels + (size_t)(img[1].height - 1) * img[1].stride;
    print_message("0.01 texels: (%d,%d,%d) and (%d,%d,%d)\n", a[0], a[1], a[2], b[0], b[1], b[2]);
    assert_true(same_rgb(a, b));
    uint8_t top[3];
    persp__heatmap_color(1.0, top);
    assert_false(same_rgb(a, top));
    int rows = caption_rows(&img[0]);
    print_message("caption %d px tall\n", rows);
    assert_true(rows >= 11);
    for (int k = 0; k < 2; k++) persp_image_free(ctx, &img[k]);
    persp_context_destroy(ctx);
}

/* Both captions (methods: texels; filters: 8-bit levels) are drawn whole:
 * every character but a space has a glyph of the built-in font, which
 * skips the ones it lacks. */
static void test_heatmap_captions(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *captions[] = {PERSP_HEATMAP_TEXELS, PERSP_HEATMAP_LEVELS};
    const uint8_t white[3] = {255, 255, 255};
    for (int c = 0; c < 2; c++) {
        const char *text = captions[c];
        persp_image img;
        assert_int_equal(persp_image_alloc(ctx, persp__heatmap_text_width(text, 1) + 2, 7, &img), PERSP_OK);
        memset(img.pixels, 0, img.stride * (size_t)img.height);
        persp__heatmap_text(&img, 0, 0, 1, text, white);
        for (size_t i = 0; text[i]; i++) {
            if (text[i] == ' ') continue;
            int lit = 0;
            for (int y = 0; y < img.height; y++)
                for (int x = 4 * (int)i; x < 4 * (int)i + 3; x++) lit |= img.pixels[(size_t)y * img.stride + 4u * (size_t)x] != 0;
            if (!lit) fail_msg("caption \"%s\": no glyph for '%c'", text, text[i]);
        }
        persp_image_free(ctx, &img);
    }
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_errstats_percentile), cmocka_unit_test(test_metrics_span),
        cmocka_unit_test(test_paper_quad_corners),  cmocka_unit_test(test_exact_is_exact),
        cmocka_unit_test(test_affine_far_off),      cmocka_unit_test(test_writers_parse),
        cmocka_unit_test(test_scene_case),         cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_heatmap_legend),
        cmocka_unit_test(test_heatmap_shared_scale), cmocka_unit_test(test_heatmap_captions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
