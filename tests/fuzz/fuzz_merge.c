/* libFuzzer harness: the shard files of `persp merge FILE...`
 * (persp_accuracy_read of src/analysis/report.c, the JSON of `persp
 * accuracy --shard K/N --json`, then persp_accuracy_merge and
 * persp_accuracy_write as cmd_merge.c calls them). The input is one file,
 * or up to 8 files separated by a line "--" ("\n--\n", which no JSON text
 * contains outside a string); each is written to a memory file
 * (memfd_create) and read through its /proc/self/fd/N name, so that
 * Jansson's json_load_file runs as it does for a real path. When every
 * file reads, they are merged; a merged result, or a single whole run, is
 * written as JSON, CSV and the table, and the JSON read back.
 * Checked besides crashes: a refused file yields no result and a one-line
 * detail that starts with the file's name; a read shard's rows are its own
 * (row_index below the total and congruent to its index modulo the
 * count); a merge that succeeds holds every row of the sweep once, each
 * equal to the shard row it came from, or else it yields no result and a
 * one-line detail; what persp merge writes reads back as the same rows
 * (NaN as NaN; a non-positive hbar, written as null, as 0). The row count
 * of a merge is held to what its shards hold (see persp_accuracy_merge),
 * so a short input cannot ask for gigabytes. */
#define _GNU_SOURCE
#include "analysis/analysis.h"
#include "persp_analysis.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_FILES 8

static void broken(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_merge: invariant broken: %s%s%s%s\n", what, detail ? " ('" : "",
            detail ? detail : "", detail ? "')" : "");
    abort();
}

/* Memory file number slot holding size bytes; its name in path. 0 if none. */
static int memory_file(int slot, const void *data, size_t size, char *path, size_t path_size)
{
    static int fd[MAX_FILES + 1] = {-1, -1, -1, -1, -1, -1, -1, -1, -1};
    if (fd[slot] < 0 && (fd[slot] = memfd_create("fuzz_merge", MFD_CLOEXEC)) < 0) return 0;
    if (ftruncate(fd[slot], 0) != 0) return 0;
    const uint8_t *p = data;
    for (size_t at = 0; at < size;) {
        ssize_t n = pwrite(fd[slot], p + at, size - at, (off_t)at);
        if (n <= 0) return 0;
        at += (size_t)n;
    }
    snprintf(path, path_size, "/proc/self/fd/%d", fd[slot]);
    return 1;
}

static void check_detail(persp_context *ctx, const char *path)
{
    const char *e = persp_context_error(ctx);
    if (!e[0]) broken("a refusal left no detail", NULL);
    if (strpbrk(e, "\r\n")) broken("a refusal's detail is not one line", e);
    if (path && (strncmp(e, path, strlen(path)) != 0 || e[strlen(path)] != ':'))
        broken("a refused file's detail does not start with its name", e);
}

static int same_number(double a, double b)
{
    return (a != a && b != b) || memcmp(&a, &b, sizeof a) == 0;
}

/* b equals a (written: b is a as persp_accuracy_write writes and
 * persp_accuracy_read reads it, a non-positive hbar as 0, with rel_floor
 * the file's). */
static int same_row(const persp_accuracy_row *a, const persp_accuracy_row *b, int written,
                    double rel_floor)
{
    const double ah = !written || a->hbar > 0.0 ? a->hbar : 0.0;
    const int ops = a->ops_measured != 0;
    return !strcmp(a->method, b->method) && !strcmp(a->case_name, b->case_name) &&
           same_number(ah, b->hbar) && a->pixels == b->pixels && a->spans == b->spans &&
           a->triangles == b->triangles && same_number(a->max_u, b->max_u) &&
           same_number(a->max_v, b->max_v) && same_number(a->mean_u, b->mean_u) &&
           same_number(a->mean_v, b->mean_v) && same_number(a->p99_u, b->p99_u) &&
           same_number(a->p99_v, b->p99_v) && same_number(a->texel_miss, b->texel_miss) &&
           same_number(a->relpt_u, b->relpt_u) && same_number(a->relpt_v, b->relpt_v) &&
           same_number(a->relspan_u, b->relspan_u) && same_number(a->relspan_v, b->relspan_v) &&
           same_number(written ? rel_floor : a->rel_floor, b->rel_floor) &&
           ops == (b->ops_measured != 0) &&
           (!ops || (same_number(a->div_px, b->div_px) && same_number(a->mul_px, b->mul_px) &&
                     same_number(a->add_px, b->add_px) && same_number(a->cmp_px, b->cmp_px)));
}

static void check_read(const persp_accuracy_result *r)
{
    const size_t n = persp_accuracy_row_count(r);
    if (n != r->count || n > r->cap) broken("a read result's row count is not its own", NULL);
    for (size_t i = 0; i < n; i++) {
        const persp_accuracy_row *row = persp_accuracy_row_at(r, i);
        if (!row || memchr(row->method, 0, sizeof row->method) == NULL ||
            memchr(row->case_name, 0, sizeof row->case_name) == NULL)
            broken("a read row's names are not terminated", NULL);
        if (row->rel_floor != row->rel_floor) broken("a read row's rel_floor is NaN", NULL);
    }
    if (r->shard_count < 0) broken("a negative shard count", NULL);
    if (r->shard_count == 0) {
        if (r->total != n) broken("a whole run's total is not its row count", NULL);
        for (size_t i = 0; i < n; i++)
            if (r->index[i] != i) broken("a whole run's rows are out of place", NULL);
        return;
    }
    if (r->shard_index < 0 || r->shard_index >= r->shard_count)
        broken("a shard's index is not below its count", NULL);
    if (memchr(r->sweep, 0, sizeof r->sweep) == NULL)
        broken("a shard's sweep is not terminated", NULL);
    for (size_t i = 0; i < n; i++)
        if (r->index[i] >= r->total ||
            r->index[i] % (size_t)r->shard_count != (size_t)r->shard_index)
            broken("a shard holds a row that is not its own", NULL);
}

/* What persp merge writes: every format into a memory stream; the JSON read back. */
static void check_written(persp_context *ctx, const persp_accuracy_result *r)
{
    static const persp_report_format formats[] = {PERSP_REPORT_TABLE, PERSP_REPORT_CSV,
                                                  PERSP_REPORT_JSON};
    for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
        char *text = NULL;
        size_t len = 0;
        FILE *s = open_memstream(&text, &len);
        if (!s) return;
        persp_status st = persp_accuracy_write(ctx, r, formats[f], s);
        fclose(s);
        if (st != PERSP_OK) broken("a result was not written", persp_context_error(ctx));
        if (formats[f] == PERSP_REPORT_JSON) {
            char path[64];
            if (!memory_file(MAX_FILES, text, len, path, sizeof path))
                broken("no memory file", NULL);
            persp_accuracy_result *back = NULL;
            if (persp_accuracy_read(ctx, path, &back) != PERSP_OK)
                broken("what persp merge writes does not read back", persp_context_error(ctx));
            const size_t n = persp_accuracy_row_count(r);
            if (persp_accuracy_row_count(back) != n || back->shard_count != r->shard_count)
                broken("what persp merge writes reads back with other rows", NULL);
            /* One rel_floor for the file: the first row's. */
            const double rel_floor = n ? persp_accuracy_row_at(r, 0)->rel_floor : 0.0;
            for (size_t i = 0; i < n; i++)
                if (!same_row(persp_accuracy_row_at(r, i), persp_accuracy_row_at(back, i), 1,
                              rel_floor))
                    broken("a row written reads back different",
                           persp_accuracy_row_at(r, i)->method);
            persp_accuracy_destroy(back);
        }
        free(text);
    }
}

static void check_merged(const persp_accuracy_result *m, persp_accuracy_result *const *parts,
                         size_t count)
{
    if (m->shard_count != 0 || m->count != m->total) broken("a merge is not a whole run", NULL);
    size_t rows = 0;
    for (size_t i = 0; i < count; i++) {
        const persp_accuracy_result *p = parts[i];
        rows += p->count;
        for (size_t r = 0; r < p->count; r++)
            if (p->index[r] >= m->count || !same_row(&m->rows[p->index[r]], &p->rows[r], 0, 0.0))
                broken("a merged row is not its shard's", NULL);
    }
    if (rows != m->count) broken("a merge has rows no shard gave", NULL);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 65536) return 0;
    const char *text = (const char *)data;
    static const char sep[] = "\n--\n";
    const size_t seplen = sizeof sep - 1;
    size_t start[MAX_FILES], len[MAX_FILES], count = 0;
    for (size_t at = 0;;) {
        const char *next = count + 1 < MAX_FILES && size - at >= seplen
                               ? memmem(text + at, size - at, sep, seplen)
                               : NULL;
        start[count] = at;
        len[count] = next ? (size_t)(next - (text + at)) : size - at;
        count++;
        if (!next) break;
        at += len[count - 1] + seplen;
    }

    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) broken("no context", NULL);
    persp_accuracy_result *parts[MAX_FILES] = {NULL};
    int all = 1;
    for (size_t i = 0; i < count; i++) {
        char path[64];
        if (!memory_file((int)i, text + start[i], len[i], path, sizeof path))
            broken("no memory file", NULL);
        parts[i] = (persp_accuracy_result *)1;
        persp_status st = persp_accuracy_read(ctx, path, &parts[i]);
        if (st != PERSP_OK) {
            if (parts[i]) broken("a refused file yielded a result", NULL);
            if (st != PERSP_ERR_FORMAT && st != PERSP_ERR_OUT_OF_MEMORY)
                broken("a file was refused other than as malformed", persp_context_error(ctx));
            if (st == PERSP_ERR_FORMAT) check_detail(ctx, path);
            all = 0;
            continue;
        }
        check_read(parts[i]);
    }
    if (all) {
        if (count == 1 && parts[0]->shard_count == 0) check_written(ctx, parts[0]);
        persp_accuracy_result *merged = (persp_accuracy_result *)1;
        persp_status st =
            persp_accuracy_merge(ctx, (const persp_accuracy_result *const *)parts, count, &merged);
        if (st == PERSP_OK) {
            check_merged(merged, parts, count);
            check_written(ctx, merged);
            persp_accuracy_destroy(merged);
        } else {
            if (merged) broken("a refused merge yielded a result", NULL);
            if (st != PERSP_ERR_INVALID_ARGUMENT && st != PERSP_ERR_OUT_OF_MEMORY)
                broken("a merge was refused other than as invalid", persp_context_error(ctx));
            check_detail(ctx, NULL);
        }
    }
    for (size_t i = 0; i < count; i++)
        persp_accuracy_destroy(parts[i]);
    persp_context_destroy(ctx);
    return 0;
}
