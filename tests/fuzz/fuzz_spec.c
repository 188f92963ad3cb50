/* libFuzzer harness: the name parsers of the public API, each given the
 * input as one string: texture-coordinate method specs (persp_method_check
 * and, through it, the parameter parsers in src/interp/), filters, wrap
 * modes and shading modes. Besides crashes it checks what the API promises
 * (include/persp.h), without assuming which spellings are accepted:
 *   - a method spec that passes names a method persp_method_get lists, and
 *     one refused as unknown (PERSP_ERR_NOT_FOUND) names none; a refusal
 *     leaves a one-line detail;
 *   - a parsed filter, wrap or shading mode is in range and its canonical
 *     name (persp_*_name, with ":N" for the anisotropic filters) parses
 *     back to the same value. */
#include "confine.h"
#include "core/internal.h"
#include "interp/method.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond, what)                                                                         \
    do {                                                                                          \
        if (!(cond)) {                                                                            \
            fuzz_confine(0);                                                                      \
            fprintf(stderr, "fuzz_spec: invariant broken: %s (input '%s')\n", what, text);        \
            abort();                                                                              \
        }                                                                                         \
    } while (0)

/* 1 when a method of persp_method_get has the name spec starts with (up to
 * its first ':'). */
static int listed(const char *spec, int *takes_params)
{
    size_t len = strcspn(spec, ":");
    persp_method_info info;
    for (size_t i = 0; persp_method_get(i, &info) == PERSP_OK; i++)
        if (strlen(info.name) == len && !strncmp(info.name, spec, len)) {
            *takes_params = info.params[0] != '\0';
            return 1;
        }
    return 0;
}

static void check_method(persp_context *ctx, const char *text)
{
    int takes = 0;
    persp_status st = persp_method_check(text);
    CHECK(st == PERSP_OK || st == PERSP_ERR_NOT_FOUND || st == PERSP_ERR_INVALID_ARGUMENT,
          "persp_method_check returned a status its contract does not list");
    if (st == PERSP_OK) {
        CHECK(listed(text, &takes), "an accepted method spec names no listed method");
        CHECK(takes || !strchr(text, ':'), "parameters accepted by a method that takes none");
    }
    if (st == PERSP_ERR_NOT_FOUND) CHECK(!listed(text, &takes), "a listed method reported unknown");
    /* The internal entry point leaves the detail the CLI and scenes print. */
    persp_method_sel sel;
    persp_status st2 = persp__method_resolve(ctx, text, &sel);
    CHECK(st2 == st, "persp__method_resolve and persp_method_check disagree");
    if (st2 != PERSP_OK) {
        const char *e = persp_context_error(ctx);
        CHECK(e[0] != '\0', "a refused method spec left no detail");
        CHECK(!strpbrk(e, "\r\n"), "a refused method spec's detail is not one line");
    }
}

static void check_filter(const char *text)
{
    persp_filter f = PERSP_FILTER_COUNT;
    int aniso = -1;
    if (persp_filter_parse(text, &f, &aniso) != PERSP_OK) return;
    CHECK((unsigned)f < (unsigned)PERSP_FILTER_COUNT, "parsed filter out of range");
    CHECK(aniso >= 1 && aniso <= 16, "parsed max_aniso outside 1..16");
    char canon[64];
    if (f == PERSP_FILTER_ANISO || f == PERSP_FILTER_ANISO_WINDOW)
        snprintf(canon, sizeof canon, "%s:%d", persp_filter_name(f), aniso);
    else
        snprintf(canon, sizeof canon, "%s", persp_filter_name(f));
    persp_filter g = PERSP_FILTER_COUNT;
    int aniso2 = -1;
    CHECK(persp_filter_parse(canon, &g, &aniso2) == PERSP_OK, "a filter's own name does not parse");
    CHECK(g == f, "a filter's name parses to another filter");
    if (f == PERSP_FILTER_ANISO || f == PERSP_FILTER_ANISO_WINDOW)
        CHECK(aniso2 == aniso, "aniso:N does not round-trip");
}

static void check_wrap(const char *text)
{
    persp_wrap w = (persp_wrap)99;
    if (persp_wrap_parse(text, &w) != PERSP_OK) return;
    CHECK(w >= PERSP_WRAP_DEFAULT && w <= PERSP_WRAP_CLAMP_TO_BORDER, "parsed wrap out of range");
    persp_wrap v = (persp_wrap)99;
    CHECK(persp_wrap_parse(persp_wrap_name(w), &v) == PERSP_OK && v == w,
          "a wrap mode's name does not round-trip");
}

static void check_shading(const char *text)
{
    persp_shading s = PERSP_SHADING_COUNT;
    if (persp_shading_parse(text, &s) != PERSP_OK) return;
    CHECK((unsigned)s < (unsigned)PERSP_SHADING_COUNT, "parsed shading out of range");
    persp_shading t = PERSP_SHADING_COUNT;
    CHECK(persp_shading_parse(persp_shading_name(s), &t) == PERSP_OK && t == s,
          "a shading mode's name does not round-trip");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* The parsers take C strings: the input up to its first NUL. */
    if (size > 4096) return 0;
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) == PERSP_OK) {
        fuzz_confine(1);
        check_method(ctx, text);
        check_filter(text);
        check_wrap(text);
        check_shading(text);
        fuzz_confine(0);
        persp_context_destroy(ctx);
    }
    free(text);
    return 0;
}
