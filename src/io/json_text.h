/*
 * What persp knows of JSON text beyond what jansson tells it: a bound of
 * the parser's memory, an allocation-free syntax check that tells an
 * allocation failure from a syntax error, and a check that the parsed tree
 * holds every token of the text whole (src/io/json_text.c).
 */
#ifndef PERSP_IO_JSON_TEXT_H
#define PERSP_IO_JSON_TEXT_H

#include "core/shared.h"
#include "persp.h"

#include <jansson.h>
#include <stddef.h>

/* An upper bound of the bytes jansson allocates to parse t[0..n). */
PERSP_INTERNAL size_t persp__json_parse_bound(const char *t, size_t n);

/* 1 when json_loadb failed on text because an allocation failed, whatever
 * its message says. */
PERSP_INTERNAL int persp__json_parse_ran_out(const char *text, size_t size, const json_error_t *err);

/* Whether jansson stopped at a closing bracket that follows a comma
 * (position: jansson's, just past the bracket). */
int persp__json_trailing_comma(const char *text, size_t size, int position);

/* 1 when root, parsed from text by json_loadb, holds each key, string and
 * number of the text whole, in the text's order; 0 when one differs, which
 * is an allocation that failed inside jansson unseen (see json_text.c), or
 * when the check itself could not allocate (ctx's allocator). */
PERSP_INTERNAL int persp__json_tree_matches(persp_context *ctx, const char *text, size_t size, json_t *root);

#endif
