/* Helpers shared by the test programs. */
#ifndef PERSP_TESTS_SUPPORT_H
#define PERSP_TESTS_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "persp.h"

/* Absolute path of a file in the source tree (PERSP_SOURCE_DIR) or the build
 * tree (PERSP_BINARY_DIR); returns a static-per-call buffer owned by caller. */
void test_source_path(char *buf, size_t size, const char *rel);
void test_binary_path(char *buf, size_t size, const char *rel);
/* Deterministic xorshift generator for seeded random tests. */
typedef struct test_rng { uint64_t s; } test_rng;
uint64_t test_rng_next(test_rng *r);
double test_rng_uniform(test_rng *r, double lo, double hi);
/* A context that fails the test if it cannot be created. */
persp_context *test_context(void);

#endif
