#include "support.h"

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

persp_context *test_context(void)
{
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(NULL, &ctx), PERSP_OK);
    assert_non_null(ctx);
    return ctx;
}
