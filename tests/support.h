/* Helpers shared by the test programs. */
#ifndef PERSP_TESTS_SUPPORT_H
#define PERSP_TESTS_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "persp_analysis.h"

/* Absolute path of a file in the source tree (PERSP_SOURCE_DIR) or the build
 * tree (PERSP_BINARY_DIR); returns a static-per-call buffer owned by caller. */
void test_source_path(char *buf, size_t size, const char *rel);
void test_binary_path(char *buf, size_t size, const char *rel);
/* Deterministic xorshift generator for seeded random tests. */
typedef struct test_rng { uint64_t s; } test_rng;
uint64_t test_rng_next(test_rng *r);
double test_rng_uniform(test_rng *r, double lo, double hi);
/* FNV-1a of n bytes: images compared by hash. */
uint64_t test_hash(const void *data, size_t n);
/* A new directory /tmp/persp-TAG-XXXXXX written to dir, and the removal of
 * such a directory with its contents; 0 on success. */
int test_tmpdir_make(char *dir, size_t size, const char *tag);
int test_tmpdir_remove(const char *dir);
/* Writes size bytes to the file name in dir (dir may be NULL: name is the
 * path); the test fails if that cannot be done. */
void test_write_file(const char *dir, const char *name, const void *data, size_t size);
/* An allocator that tracks what it hands out (test_tracker_allocator):
 * calls, blocks and bytes live, the most bytes live at once and the
 * largest request; the bytes are the sizes persp asked for. */
typedef struct test_tracker {
    long calls, blocks;
    size_t live, peak, largest;
} test_tracker;
persp_allocator test_tracker_allocator(test_tracker *t);

/* A context that fails the test if it cannot be created. */
persp_context *test_context(void);
/* A context drawing with the given number of threads. */
persp_context *test_context_threads(int threads);
/* A w×h framebuffer whose colour and depth come from malloc (the test fails
 * if they cannot be had); test_framebuffer_free frees both (a NULL field is
 * skipped, so a caller may take the colour buffer over). */
persp_framebuffer test_framebuffer(int w, int h);
void test_framebuffer_free(persp_framebuffer *fb);

/* Runs a program's cmocka tests. "--only NAME" runs the test NAME alone and
 * fails when the program has no such test, so that a misspelt name cannot
 * pass by running nothing: CMakeLists.txt registers each test of a source
 * holding "ctest-split: each" as its own ctest entry (PROGRAM.NAME), which
 * keeps every entry far from the time limit under the sanitizers and qemu
 * (docs/RELIABILITY.md, "Continuous integration"). */
int test_run(int argc, char **argv, const struct CMUnitTest *tests, size_t count);
#define TEST_RUN(argc, argv, tests) test_run(argc, argv, tests, sizeof(tests) / sizeof((tests)[0]))

/* Golden images (docs/DESIGN.md, "Testing", layer 3). */
typedef struct test_tolerance {
    int max_abs;            /* largest per-channel difference */
    double max_share_over2; /* share of pixels with a channel differing by more than 2 */
    double min_psnr;        /* dB */
} test_tolerance;
typedef struct test_diff {
    int max_abs;
    double share_over2, psnr;
} test_diff;
/* RGB differences of two images of equal size; diff (optional) receives the
 * largest channel difference per pixel, amplified 8 times, in red. */
test_diff test_image_compare(const persp_image *a, const persp_image *b, persp_image *diff);
/* Compares got with tests/golden/data/NAME (':' in NAME becomes '-') within
 * tol, failing the test and writing golden-fail-NAME and golden-diff-NAME
 * into the build folder when outside it; with PERSP_UPDATE_GOLDEN=1 rewrites
 * the reference instead (review new references before committing them). */
void test_golden_check(persp_context *ctx, const char *name, const persp_image *got,
                       test_tolerance tol);

#endif
