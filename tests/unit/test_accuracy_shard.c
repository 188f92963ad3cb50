/*
 * Sharded accuracy runs: the slices of a sweep hold disjoint rows dealt
 * round-robin, and persp_accuracy_merge of them (also after a JSON round
 * trip through persp_accuracy_read) gives the unsharded rows bit for bit
 * and the same JSON. Bad shard settings and incomplete sets are refused.
 */
#include "support.h"

#include "persp_analysis.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const methods[] = {"exact", "affine", "quadratic", "midpoint"};
static const char *const cases[] = {"paper-quad", "random-triangles", "floor"};

static persp_accuracy_desc sweep(int k, int n)
{
    persp_accuracy_desc d;
    memset(&d, 0, sizeof d);
    d.methods = methods, d.method_count = 4;
    d.cases = cases, d.case_count = 3;
    d.width = 48, d.height = 36, d.triangles = 2;
    d.shard_index = k, d.shard_count = n;
    return d;
}

/* The JSON of a result as a string (caller frees). */
static char *json_of(persp_context *ctx, const persp_accuracy_result *res)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    assert_int_equal(persp_accuracy_write(ctx, res, PERSP_REPORT_JSON, f), PERSP_OK);
    fclose(f);
    return buf;
}

static void test_merge_equals_whole(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_accuracy_desc d = sweep(0, 0);
    persp_accuracy_result *whole = NULL, *parts[3] = {NULL}, *read[3] = {NULL}, *merged = NULL,
                          *merged2 = NULL;
    assert_int_equal(persp_accuracy_run(ctx, &d, &whole), PERSP_OK);
    size_t total = persp_accuracy_row_count(whole), seen = 0;
    assert_int_equal(total, 4 * (1 + 7 + 1));
    char path[3][64];
    for (int k = 0; k < 3; k++) {
        d = sweep(k, 3);
        assert_int_equal(persp_accuracy_run(ctx, &d, &parts[k]), PERSP_OK);
        seen += persp_accuracy_row_count(parts[k]);
        /* Row j of slice k is row k + 3j of the whole run. */
        for (size_t j = 0; j < persp_accuracy_row_count(parts[k]); j++)
            assert_memory_equal(persp_accuracy_row_at(parts[k], j),
                                persp_accuracy_row_at(whole, (size_t)k + 3 * j),
                                sizeof(persp_accuracy_row));
        snprintf(path[k], sizeof path[k], "test_accuracy_shard_%d_%d.json", (int)getpid(), k);
        FILE *f = fopen(path[k], "w");
        assert_non_null(f);
        assert_int_equal(persp_accuracy_write(ctx, parts[k], PERSP_REPORT_JSON, f), PERSP_OK);
        fclose(f);
        assert_int_equal(persp_accuracy_read(ctx, path[k], &read[k]), PERSP_OK);
        remove(path[k]);
    }
    assert_int_equal(seen, total);
    const persp_accuracy_result *order[3] = {parts[2], parts[0], parts[1]};
    assert_int_equal(persp_accuracy_merge(ctx, order, 3, &merged), PERSP_OK);
    assert_int_equal(
        persp_accuracy_merge(ctx, (const persp_accuracy_result *const *)read, 3, &merged2),
        PERSP_OK);
    char *a = json_of(ctx, whole), *b = json_of(ctx, merged), *c = json_of(ctx, merged2);
    assert_string_equal(a, b);
    assert_string_equal(a, c);
    for (size_t i = 0; i < total; i++)
        assert_memory_equal(persp_accuracy_row_at(whole, i), persp_accuracy_row_at(merged, i),
                            sizeof(persp_accuracy_row));
    free(a), free(b), free(c);

    /* Incomplete, repeated, or a whole run: refused. */
    persp_accuracy_result *bad = NULL;
    assert_int_equal(persp_accuracy_merge(ctx, order, 2, &bad), PERSP_ERR_INVALID_ARGUMENT);
    /* The detail names what a re-run needs: the missing shard's number. */
    assert_string_equal(persp_context_error(ctx), "merge: missing shard 2 of 3 (2 files given)");
    const persp_accuracy_result *last[1] = {parts[2]};
    assert_int_equal(persp_accuracy_merge(ctx, last, 1, &bad), PERSP_ERR_INVALID_ARGUMENT);
    assert_string_equal(persp_context_error(ctx), "merge: missing shards 1-2 of 3 (1 file given)");
    const persp_accuracy_result *twice[3] = {parts[0], parts[0], parts[1]};
    assert_int_equal(persp_accuracy_merge(ctx, twice, 3, &bad), PERSP_ERR_INVALID_ARGUMENT);
    assert_string_equal(persp_context_error(ctx), "merge: shard 1 of 3 given twice (shard 1, shard 2)");
    /* Read from files, the shards are named by their file. */
    const persp_accuracy_result *twice_read[3] = {read[0], read[0], read[1]};
    assert_int_equal(persp_accuracy_merge(ctx, twice_read, 3, &bad), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "given twice ("));
    const persp_accuracy_result *one[1] = {whole};
    assert_int_equal(persp_accuracy_merge(ctx, one, 1, &bad), PERSP_ERR_INVALID_ARGUMENT);
    assert_null(bad);

    persp_accuracy_destroy(whole);
    persp_accuracy_destroy(merged);
    persp_accuracy_destroy(merged2);
    for (int k = 0; k < 3; k++)
        persp_accuracy_destroy(parts[k]), persp_accuracy_destroy(read[k]);
    persp_context_destroy(ctx);
}

static void test_bad_shard(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_accuracy_result *res = NULL;
    persp_accuracy_desc d = sweep(3, 3);
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_ERR_INVALID_ARGUMENT);
    d = sweep(-1, 2);
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_ERR_INVALID_ARGUMENT);
    d = sweep(0, -2);
    assert_int_equal(persp_accuracy_run(ctx, &d, &res), PERSP_ERR_INVALID_ARGUMENT);
    assert_null(res);
    /* More slices than rows: the extra slices are empty, and still merge. */
    persp_accuracy_result *parts[40] = {NULL}, *merged = NULL, *whole = NULL;
    for (int k = 0; k < 40; k++) {
        d = sweep(k, 40);
        assert_int_equal(persp_accuracy_run(ctx, &d, &parts[k]), PERSP_OK);
    }
    assert_int_equal(persp_accuracy_row_count(parts[39]), 0);
    assert_int_equal(
        persp_accuracy_merge(ctx, (const persp_accuracy_result *const *)parts, 40, &merged),
        PERSP_OK);
    d = sweep(0, 0);
    assert_int_equal(persp_accuracy_run(ctx, &d, &whole), PERSP_OK);
    assert_int_equal(persp_accuracy_row_count(merged), persp_accuracy_row_count(whole));
    for (int k = 0; k < 40; k++)
        persp_accuracy_destroy(parts[k]);
    persp_accuracy_destroy(merged);
    persp_accuracy_destroy(whole);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_merge_equals_whole),
        cmocka_unit_test(test_bad_shard),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
