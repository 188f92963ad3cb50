/*
 * docs/REPRODUCTION.md states the numbers of the claims table
 * (src/analysis/claims.c) that the report page and the tests hold
 * measurements to: every published figure and threshold of a claim
 * appears, as a number of its own, in the part of the document under the
 * claim's label ("1." ... "7.", "S3." or a heading). A threshold changed in
 * one place and not the other fails here.
 */
#include "analysis/claims.h"
#include "support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *read_doc(void)
{
    char path[1024];
    test_source_path(path, sizeof path, "docs/REPRODUCTION.md");
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("%s: cannot open", path);
    char *text = malloc(1 << 20);
    assert_non_null(text);
    size_t n = fread(text, 1, (1 << 20) - 1, f);
    fclose(f);
    text[n] = '\0';
    return text;
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* The part under a label: from the line "LABEL. **" (or the heading "### LABEL")
 * to the next claim label or heading. */
static void section(const char *doc, const char *label, const char **from, const char **to)
{
    char head[128];
    *from = *to = NULL;
    for (const char *line = doc; line && *line;
         line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        const char *p = line;
        while (*p == ' ') p++;
        snprintf(head, sizeof head, "%s. **", label);
        int numbered = !strncmp(p, head, strlen(head));
        snprintf(head, sizeof head, "### %s", label);
        if (numbered || !strncmp(line, head, strlen(head))) {
            *from = line;
            break;
        }
    }
    if (!*from) return;
    const char *line = strchr(*from, '\n');
    for (; line; line = strchr(line + 1, '\n')) {
        const char *p = line + 1;
        while (*p == ' ') p++;
        if (*p == 'S') p++;
        const char *d = p;
        while (is_digit(*d)) d++;
        int next = *p == '#' || (d > p && d - p <= 2 && !strncmp(d, ". **", 4));
        if (next) break;
    }
    *to = line ? line : *from + strlen(*from);
}

/* x as the document writes it: %g, and 1e-4 rather than 0.0001. */
static void format(double x, char *buf, size_t n)
{
    if (x < 1e-3) {
        snprintf(buf, n, "%.0e", x); /* 1e-04 */
        char *e = strstr(buf, "e-0");
        if (e) memmove(e + 2, e + 3, strlen(e + 3) + 1);
    } else {
        snprintf(buf, n, "%g", x);
    }
}

/* The number as a token of its own between from and to. */
static int has_number(const char *from, const char *to, const char *num)
{
    size_t len = strlen(num);
    for (const char *p = from; p + len <= to; p++) {
        if (strncmp(p, num, len)) continue;
        if (p > from && (is_digit(p[-1]) || p[-1] == '.')) continue;
        const char *q = p + len;
        if (q < to && (is_digit(*q) || (*q == '.' && q + 1 < to && is_digit(q[1])))) continue;
        return 1;
    }
    return 0;
}

static void test_doc_states_the_table(void **state)
{
    (void)state;
    char *doc = read_doc();
    int checked = 0;
    for (int id = 0; id < PERSP_CLAIM_COUNT; id++) {
        const persp_claim *c = persp__claim((persp_claim_id)id);
        assert_non_null(c);
        const char *from, *to;
        section(doc, c->doc, &from, &to);
        if (!from) fail_msg("docs/REPRODUCTION.md has no claim \"%s\" (%s)", c->doc, c->source);
        double nums[16];
        int n = 0;
        const double single[] = {c->lo, c->hi, c->bound, c->factor, c->above, c->tol[0], c->tol[1]};
        for (size_t k = 0; k < sizeof single / sizeof *single; k++)
            if (single[k] != 0.0) nums[n++] = single[k];
        for (int k = 0; k < c->nseries && n < 16; k++) nums[n++] = c->series[k];
        for (int k = 0; k < n; k++) {
            char num[32];
            format(nums[k], num, sizeof num);
            if (!has_number(from, to, num))
                fail_msg("docs/REPRODUCTION.md, claim \"%s\" (%s): does not state %s, the claims "
                         "table's",
                         c->doc, c->source, num);
            checked++;
        }
    }
    print_message("%d numbers of %d claims found in docs/REPRODUCTION.md\n", checked,
                  (int)PERSP_CLAIM_COUNT);
    assert_true(checked >= 20);
    free(doc);
}

/* The label lookup finds a claim's own part, not a neighbour's: a number
 * only the next claim states is not found under this one. */
static void test_sections_are_separate(void **state)
{
    (void)state;
    char *doc = read_doc();
    const char *from, *to;
    section(doc, "1", &from, &to);
    assert_non_null(from);
    assert_false(has_number(from, to, "1.7")); /* claim 3's bound */
    section(doc, "3", &from, &to);
    assert_non_null(from);
    assert_true(has_number(from, to, "1.7"));
    free(doc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_doc_states_the_table),
        cmocka_unit_test(test_sections_are_separate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
