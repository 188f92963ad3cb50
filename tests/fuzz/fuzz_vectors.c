/* libFuzzer harness: the triangle file of `persp vectors --input FILE`
 * (vectors_read_triangle of tools/persp/cmd_vectors.c: 15 numbers a line,
 * x y w u v per vertex, '#' starts a comment), read from the input through
 * fmemopen, line after line until the end or the first refused line, and
 * the first triangles it accepts traced as the command traces them
 * (persp_midpoint_trace, midpoint:int and midpoint:int,edge, in a small
 * window so that one input stays fast). Checked besides crashes: an
 * accepted triangle has finite x, y, w > 0 and finite u, v, and the line
 * count only grows and is the number of the line (counted by '\n') where
 * the reader stopped; a refused line yields -1 with exactly one message,
 * one line "persp: vectors: FILE:LINE: ..." naming that line (the
 * harness catches it by pointing glibc's stderr at a memory stream while
 * the reader runs; sanitizer reports still go to file descriptor 2); the
 * trace succeeds and reports spans inside the window, at most 64 pixels
 * long, whose integer path covers a prefix. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* fmemopen, open_memstream */
#endif
#include "cli.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define NAME "fuzz.txt"
#define WIDTH 96
#define HEIGHT 64
#define TRACED 4 /* triangles traced per input; the rest are only read */

static void broken(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_vectors: invariant broken: %s%s%s%s\n", what, detail ? " ('" : "",
            detail ? detail : "", detail ? "')" : "");
    abort();
}

/* One triangle's spans, checked as they come. */
typedef struct trace_check {
    long spans;
} trace_check;

static void on_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px)
{
    trace_check *c = user;
    c->spans++;
    if (s->n < 1 || s->n > 64 || s->x0 < 0 || s->x0 + s->n > WIDTH || s->y < 0 || s->y >= HEIGHT)
        broken("a span lies outside the window or is longer than a tile", NULL);
    if (s->int_pixels < 0 || s->int_pixels > s->n)
        broken("a span's integer pixels are not a part of it", NULL);
    for (int k = 0; k < s->n; k++)
        for (int j = 0; j < 2; j++) {
            if (px[k].reseed[j] != 0 && px[k].reseed[j] != 1)
                broken("a pixel's re-seed flag is neither 0 nor 1", NULL);
            if (k >= s->int_pixels &&
                (px[k].n[j] || px[k].W[j] || px[k].steps[j] || px[k].reseed[j]))
                broken("a pixel of the double path has integer state", NULL);
        }
}

static void trace(persp_context *ctx, const persp_method_vertex v[3], long index)
{
    /* Both lattices, as persp vectors --method offers them. */
    const char *method = index % 2 ? "midpoint:int,edge" : "midpoint:int";
    persp_midpoint_format f;
    memset(&f, 0xa5, sizeof f);
    trace_check c = {0};
    persp_status st =
        persp_midpoint_trace(ctx, method, v, WIDTH, HEIGHT, 256, 256, &f, on_span, &c);
    if (st != PERSP_OK)
        broken("persp_midpoint_trace refused a triangle the reader accepted",
               persp_context_error(ctx));
    if (f.in_format != 0 && f.in_format != 1)
        broken("the format's in_format is neither 0 nor 1", NULL);
    if (f.lattice2 != (index % 2 ? 0 : 1)) broken("the format's lattice is not the method's", NULL);
}

/* The message of a refused line: one line, "persp: vectors: NAME:LINE: ...". */
static void check_message(const char *msg, size_t len, long line)
{
    if (len == 0) broken("a refused line left no message", NULL);
    if (msg[len - 1] != '\n' || memchr(msg, '\n', len - 1) || memchr(msg, '\r', len) ||
        strlen(msg) != len)
        broken("a refused line's message is not one line", msg);
    char head[64];
    int n = snprintf(head, sizeof head, "persp: vectors: " NAME ":%ld: ", line);
    if (n < 0 || (size_t)n >= sizeof head || strncmp(msg, head, (size_t)n) != 0)
        broken("a refused line's message does not name the file and the line counted", msg);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 65536) return 0;
    /* fmemopen wants a buffer of one byte at least: a copy with room for a
     * NUL that is not part of the stream (size bytes are read). */
    char *buf = malloc(size + 1);
    if (!buf) return 0;
    if (size) memcpy(buf, data, size);
    buf[size] = '\0';
    FILE *in = size ? fmemopen(buf, size, "r") : fmemopen(buf, 1, "r");
    if (!in) {
        free(buf);
        return 0;
    }
    if (!size) (void)fgetc(in); /* an empty file: the one byte is consumed */
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) broken("no context", NULL);

    long line = 0, index = 0, scanned = 0, newlines = 0;
    for (;;) {
        persp_method_vertex v[3];
        memset(v, 0, sizeof v);
        char *msg = NULL;
        size_t len = 0;
        FILE *err = open_memstream(&msg, &len);
        if (!err) break;
        FILE *saved = stderr;
        stderr = err;
        const long before = line;
        int got = vectors_read_triangle(in, NAME, &line, v);
        stderr = saved;
        fclose(err);
        if (line < before) broken("the line count went back", NULL);
        if (got != 0) {
            /* The line of the last byte read: 1 + the newlines before it. */
            const long pos = ftell(in);
            if (pos < 1 || pos - 1 < scanned) broken("the reader read nothing", msg);
            for (; scanned < pos - 1; scanned++)
                newlines += buf[scanned] == '\n';
            if (line != 1 + newlines) broken("the line counted is not the line read", msg);
        }
        if (got == 1) {
            if (len) broken("an accepted triangle printed a message", msg);
            if (line == before) broken("a triangle was read without a line", NULL);
            for (int k = 0; k < 3; k++)
                if (!isfinite(v[k].x) || !isfinite(v[k].y) || !isfinite(v[k].w) ||
                    !(v[k].w > 0.0) || !isfinite(v[k].u) || !isfinite(v[k].v))
                    broken("an accepted vertex is not finite or has w <= 0", NULL);
            if (index < TRACED) trace(ctx, v, index);
            index++;
        } else if (got == 0) {
            if (len) broken("the end of the file printed a message", msg);
        } else if (got == -1) {
            check_message(msg, len, line);
        } else {
            broken("vectors_read_triangle returned neither 1, 0 nor -1", NULL);
        }
        free(msg);
        if (got != 1) break;
    }
    persp_context_destroy(ctx);
    fclose(in);
    free(buf);
    return 0;
}
