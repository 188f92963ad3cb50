#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stdio.h>
#include <stdlib.h>

static void join(char *buf, size_t size, const char *env, const char *fallback, const char *rel)
{
    const char *root = getenv(env);
    snprintf(buf, size, "%s/%s", root ? root : fallback, rel);
}

void test_source_path(char *buf, size_t size, const char *rel)
{
    join(buf, size, "PERSP_SOURCE_DIR", "..", rel);
}

void test_binary_path(char *buf, size_t size, const char *rel)
{
    join(buf, size, "PERSP_BINARY_DIR", ".", rel);
}

int test_run(int argc, char **argv, const struct CMUnitTest *tests, size_t count)
{
    const char *only = NULL;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
            only = argv[++i];
        } else {
            fprintf(stderr, "%s: unknown argument '%s' (usage: %s [--only TEST])\n", argv[0], argv[i],
                    argv[0]);
            return 2;
        }
    }
    if (only) {
        size_t i = 0;
        while (i < count && strcmp(tests[i].name, only) != 0)
            ++i;
        if (i == count) {
            fprintf(stderr, "%s: no test named '%s'\n", argv[0], only);
            return 2;
        }
        /* One test of the array: cmocka's filter takes a glob, so name the
         * test by its own pointer instead of passing the pattern on. */
        return _cmocka_run_group_tests(only, &tests[i], 1, NULL, NULL);
    }
    return _cmocka_run_group_tests("tests", tests, count, NULL, NULL);
}

uint64_t test_rng_next(test_rng *r)
{
    uint64_t x = r->s ? r->s : 0x9E3779B97F4A7C15ull;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    r->s = x;
    return x;
}

double test_rng_uniform(test_rng *r, double lo, double hi)
{
    double t = (double)(test_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * t;
}

uint64_t test_hash(const void *data, size_t n)
{
    const uint8_t *p = data;
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

int test_tmpdir_make(char *dir, size_t size, const char *tag)
{
    int n = snprintf(dir, size, "/tmp/persp-%s-XXXXXX", tag);
    if (n < 0 || (size_t)n >= size) return -1;
    return mkdtemp(dir) ? 0 : -1;
}

int test_tmpdir_remove(const char *dir)
{
    char cmd[1100];
    int n = snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (n < 0 || (size_t)n >= sizeof cmd) return -1;
    return system(cmd) == 0 ? 0 : -1;
}

typedef struct tracker_head {
    size_t size;
    size_t pad; /* keeps the caller's part 16-byte aligned */
} tracker_head;

static void *tracker_alloc(void *user, size_t size)
{
    test_tracker *t = user;
    t->calls++;
    if (size > t->largest) t->largest = size;
    tracker_head *h = malloc(sizeof *h + size);
    if (!h) return NULL;
    h->size = size;
    t->blocks++;
    t->live += size;
    if (t->live > t->peak) t->peak = t->live;
    return h + 1;
}

static void tracker_free(void *user, void *ptr)
{
    test_tracker *t = user;
    if (!ptr) return;
    tracker_head *h = (tracker_head *)ptr - 1;
    t->blocks--;
    t->live -= h->size;
    free(h);
}

persp_allocator test_tracker_allocator(test_tracker *t)
{
    memset(t, 0, sizeof *t);
    return (persp_allocator){tracker_alloc, tracker_free, t};
}

persp_context *test_context(void) { return test_context_threads(1); }

persp_context *test_context_threads(int threads)
{
    persp_context *ctx = NULL;
    persp_context_desc cd = {.threads = threads};
    assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
    assert_non_null(ctx);
    return ctx;
}

persp_framebuffer test_framebuffer(int w, int h)
{
    persp_framebuffer fb = {w, h, malloc((size_t)w * (size_t)h * 4), malloc((size_t)w * (size_t)h * sizeof(float))};
    assert_non_null(fb.color);
    assert_non_null(fb.depth);
    return fb;
}

void test_framebuffer_free(persp_framebuffer *fb)
{
    free(fb->color);
    free(fb->depth);
    fb->color = NULL;
    fb->depth = NULL;
}

test_diff test_image_compare(const persp_image *a, const persp_image *b, persp_image *diff)
{
    test_diff d = {0, 0.0, INFINITY};
    double se = 0.0;
    long over = 0, n = (long)a->width * a->height;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++) {
            const uint8_t *p = a->pixels + (size_t)y * a->stride + 4 * (size_t)x;
            const uint8_t *q = b->pixels + (size_t)y * b->stride + 4 * (size_t)x;
            int m = 0;
            for (int c = 0; c < 3; c++) {
                int e = abs((int)p[c] - (int)q[c]);
                se += (double)e * e;
                if (e > m) m = e;
            }
            if (m > d.max_abs) d.max_abs = m;
            if (m > 2) over++;
            if (diff) {
                uint8_t *o = diff->pixels + (size_t)y * diff->stride + 4 * (size_t)x;
                int v = m * 8 > 255 ? 255 : m * 8;
                o[0] = (uint8_t)v, o[1] = (uint8_t)(v / 4), o[2] = (uint8_t)(v / 4), o[3] = 255;
            }
        }
    d.share_over2 = (double)over / (double)n;
    double mse = se / (3.0 * (double)n);
    d.psnr = mse > 0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
    return d;
}

void test_golden_check(persp_context *ctx, const char *name_in, const persp_image *got,
                       test_tolerance tol)
{
    char name[256], path[1024], rel[300];
    snprintf(name, sizeof name, "%s", name_in);
    for (char *c = name; *c; c++)
        if (*c == ':') *c = '-';
    snprintf(rel, sizeof rel, "tests/golden/data/%s", name);
    test_source_path(path, sizeof path, rel);
    const char *update = getenv("PERSP_UPDATE_GOLDEN");
    if (update && !strcmp(update, "1")) {
        assert_int_equal(persp_image_write_png(ctx, path, got), PERSP_OK);
        print_message("updated %s\n", path);
        return;
    }
    persp_image want;
    if (persp_image_load(ctx, path, &want) != PERSP_OK)
        fail_msg("cannot load golden %s: %s", path, persp_context_error(ctx));
    assert_int_equal(want.width, got->width);
    assert_int_equal(want.height, got->height);
    persp_image diff;
    assert_int_equal(persp_image_alloc(ctx, got->width, got->height, &diff), PERSP_OK);
    test_diff d = test_image_compare(got, &want, &diff);
    print_message("%s: max abs %d, %.4f%% pixels > 2 levels, PSNR %.1f dB\n", name, d.max_abs,
                  100.0 * d.share_over2, d.psnr);
    if (d.max_abs > tol.max_abs || d.share_over2 > tol.max_share_over2 || d.psnr < tol.min_psnr) {
        char out[1024];
        snprintf(rel, sizeof rel, "golden-fail-%s", name);
        test_binary_path(out, sizeof out, rel);
        persp_image_write_png(ctx, out, got);
        snprintf(rel, sizeof rel, "golden-diff-%s", name);
        test_binary_path(out, sizeof out, rel);
        persp_image_write_png(ctx, out, &diff);
        fail_msg("%s outside tolerance (max abs <= %d, share > 2 <= %.4f, PSNR >= %.1f); see %s", name,
                 tol.max_abs, tol.max_share_over2, tol.min_psnr, out);
    }
    persp_image_free(ctx, &diff);
    persp_image_free(ctx, &want);
}

void test_write_file(const char *dir, const char *name, const void *data, size_t size)
{
    char path[1024];
    if (dir)
        snprintf(path, sizeof path, "%s/%s", dir, name);
    else
        snprintf(path, sizeof path, "%s", name);
    FILE *f = fopen(path, "wb");
    if (!f) fail_msg("cannot create %s", path);
    assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}
