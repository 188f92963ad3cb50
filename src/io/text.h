/*
 * Small helpers shared by the text-format loaders (OBJ, MTL, scene JSON):
 * whole-file reading with a size limit, path joining, and a line tokenizer
 * that tracks line and column so every error can say where it happened.
 */
#ifndef PERSP_IO_TEXT_H
#define PERSP_IO_TEXT_H

#include "persp.h"

#include <stdarg.h>
#include <stddef.h>

/* Largest text file a loader reads (checked before allocating). */
#define PERSP_TEXT_MAX_BYTES ((size_t)512 * 1024 * 1024)
#define PERSP_PATH_MAX 4096

/* Reads a whole file into a NUL-terminated buffer owned by the caller
 * (persp__free). PERSP_ERR_IO / PERSP_ERR_TOO_LARGE with the path in the detail. */
persp_status persp__read_file(persp_context *ctx, const char *path, char **data, size_t *size);

/* The folder part of path, "" for a bare name ("a/b.obj" -> "a/"). */
void persp__path_dir(const char *path, char *out, size_t size);
/* dir + rel unless rel is absolute; 0 if it does not fit. */
int persp__path_join(const char *dir, const char *rel, char *out, size_t size);
/* The last path component, for short error prefixes. */
const char *persp__path_base(const char *path);

/* A cursor over one line of text. Columns count bytes from 1. */
typedef struct persp_line_cursor {
    const char *line; /* start of the line */
    size_t len;       /* bytes in the line, without the terminator */
    size_t pos;       /* next byte */
    size_t lineno;
} persp_line_cursor;

/* Iterates lines of data[0..size): returns 0 at the end. Handles \n, \r\n
 * and a last line without terminator. OBJ's '\\' continuation is not
 * joined: it is rare, and joined lines would make the reported columns lie. */
int persp__next_line(const char *data, size_t size, size_t *offset, persp_line_cursor *cur);

/* Skips blanks (space, tab, \v, \f, stray \r); returns 1 if a token follows. */
int persp__skip_blanks(persp_line_cursor *cur);
/* Next blank-delimited token; returns its length (0 at end of line) and
 * stores its start and 1-based column. */
size_t persp__token(persp_line_cursor *cur, const char **tok, size_t *col);
/* 1-based column of the cursor. */
size_t persp__column(const persp_line_cursor *cur);

/* Whether the token tok[0..len) is the keyword kw. */
int persp__keyword_is(const char *tok, size_t len, const char *kw);
/* Fails ctx with "NAME:LINE:COL: message" (the parsers' error form). */
persp_status persp__text_failv(persp_context *ctx, persp_status st, const char *name, size_t line,
                               size_t col, const char *fmt, va_list ap);

/* Parses the whole token as a finite float (no NaN/Inf, no overflow). */
int persp__parse_float(const char *tok, size_t len, float *out);
/* Parses the whole token as a decimal integer with optional sign, |v| <= limit. */
int persp__parse_long(const char *tok, size_t len, long limit, long *out);

#endif
