/* persp__grow, the one way arrays grow: geometric growth that keeps the
 * contents and zeroes the rest, sizes that overflow refused before the
 * allocator is asked, and an allocator failure leaving the array as it was. */
#include "support.h"

#include "core/internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* An allocator that counts calls, remembers the last size asked for and
 * refuses every call from the fail_from-th on (0: none). */
typedef struct test_alloc {
    long allocs, fails, frees, fail_from;
    size_t last_size;
} test_alloc;

static void *test_alloc_fn(void *user, size_t size)
{
    test_alloc *a = user;
    a->allocs++;
    a->last_size = size;
    if (a->fail_from && a->allocs >= a->fail_from) {
        a->fails++;
        return NULL;
    }
    return malloc(size);
}

static void test_free_fn(void *user, void *ptr)
{
    ((test_alloc *)user)->frees++;
    free(ptr);
}

static persp_context *context_with(test_alloc *a, persp_allocator *al)
{
    *al = (persp_allocator){test_alloc_fn, test_free_fn, a};
    persp_context_desc cd = {.allocator = al, .threads = 1};
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
    a->allocs = a->frees = 0; /* count the arrays' calls only */
    return ctx;
}

static void test_growth(void **state)
{
    (void)state;
    test_alloc a = {0};
    persp_allocator al;
    persp_context *ctx = context_with(&a, &al);
    uint32_t *arr = NULL;
    size_t cap = 0;

    /* Nothing needed: nothing allocated. */
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, 0, sizeof *arr), PERSP_OK);
    assert_null(arr);
    assert_int_equal(cap, 0);
    assert_int_equal(a.allocs, 0);

    /* Appending one at a time: contents kept, new elements zero, and the
     * number of allocations logarithmic in the length. */
    const size_t n = 100000;
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, i + 1, sizeof *arr), PERSP_OK);
        assert_true(cap >= i + 1);
        assert_int_equal(arr[i], 0);
        arr[i] = (uint32_t)(i * 2654435761u);
    }
    for (size_t i = 0; i < n; i++) assert_int_equal(arr[i], (uint32_t)(i * 2654435761u));
    for (size_t i = n; i < cap; i++) assert_int_equal(arr[i], 0);
    assert_true(a.allocs <= 16);
    assert_int_equal(a.frees, a.allocs - 1);

    /* Within the capacity: no call, nothing moves. */
    long before = a.allocs;
    uint32_t *same = arr;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, cap, sizeof *arr), PERSP_OK);
    assert_ptr_equal(arr, same);
    assert_int_equal(a.allocs, before);

    /* A jump far beyond twice the capacity gets at least what was asked. */
    size_t big = 5 * cap + 3;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, big, sizeof *arr), PERSP_OK);
    assert_true(cap >= big);
    assert_int_equal(arr[n - 1], (uint32_t)((n - 1) * 2654435761u));
    assert_int_equal(arr[big - 1], 0);

    persp__free(ctx, arr);
    persp_context_destroy(ctx);
}

static void test_overflow_refused(void **state)
{
    (void)state;
    test_alloc a = {0};
    persp_allocator al;
    persp_context *ctx = context_with(&a, &al);
    double *arr = NULL;
    size_t cap = 0;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, 4, sizeof *arr), PERSP_OK);
    double *kept = arr;
    size_t kept_cap = cap;
    arr[0] = 1.5;
    long before = a.allocs;

    /* need × elem past SIZE_MAX: refused without asking the allocator. */
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, SIZE_MAX / sizeof *arr + 1, sizeof *arr),
                     PERSP_ERR_TOO_LARGE);
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, SIZE_MAX / 2 + 1, 2), PERSP_ERR_TOO_LARGE);
    assert_int_equal(a.allocs, before);
    assert_ptr_equal(arr, kept);
    assert_int_equal(cap, kept_cap);
    assert_true(arr[0] == 1.5);

    /* need bytes fit but twice the capacity would not: exactly need is asked
     * for, with the block's size header (here refused, as any allocator
     * would). */
    unsigned char *bytes = NULL;
    size_t nbytes = 0;
    assert_int_equal(persp__grow(ctx, (void **)&bytes, &nbytes, 4, 1), PERSP_OK);
    a.fail_from = a.allocs + 1;
    assert_int_equal(persp__grow(ctx, (void **)&bytes, &nbytes, SIZE_MAX / 2 + 2, 1),
                     PERSP_ERR_OUT_OF_MEMORY);
    assert_int_equal(a.last_size, SIZE_MAX / 2 + 2 + PERSP_BLOCK_HEADER);
    assert_int_equal(nbytes, 16);
    a.fail_from = 0;

    persp__free(ctx, bytes);
    persp__free(ctx, arr);
    persp_context_destroy(ctx);
}

static void test_allocation_failure(void **state)
{
    (void)state;
    test_alloc a = {0};
    persp_allocator al;
    persp_context *ctx = context_with(&a, &al);
    int *arr = NULL;
    size_t cap = 0;

    /* The very first allocation fails: still empty. */
    a.fail_from = 1;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, 10, sizeof *arr), PERSP_ERR_OUT_OF_MEMORY);
    assert_null(arr);
    assert_int_equal(cap, 0);

    /* A later growth fails: the old array and capacity stay, intact. */
    a.fail_from = 0;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, 10, sizeof *arr), PERSP_OK);
    for (size_t i = 0; i < cap; i++) arr[i] = (int)i + 7;
    int *kept = arr;
    size_t kept_cap = cap;
    long frees = a.frees;
    a.fail_from = a.allocs + 1;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, kept_cap + 1, sizeof *arr),
                     PERSP_ERR_OUT_OF_MEMORY);
    assert_ptr_equal(arr, kept);
    assert_int_equal(cap, kept_cap);
    assert_int_equal(a.frees, frees);
    for (size_t i = 0; i < cap; i++) assert_int_equal(arr[i], (int)i + 7);

    /* And it grows once the allocator recovers. */
    a.fail_from = 0;
    assert_int_equal(persp__grow(ctx, (void **)&arr, &cap, kept_cap + 1, sizeof *arr), PERSP_OK);
    assert_true(cap > kept_cap);
    for (size_t i = 0; i < kept_cap; i++) assert_int_equal(arr[i], (int)i + 7);

    persp__free(ctx, arr);
    persp_context_destroy(ctx);
    assert_int_equal(a.frees, a.allocs - a.fails + 1); /* every array, and the context */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_growth),
        cmocka_unit_test(test_overflow_refused),
        cmocka_unit_test(test_allocation_failure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
