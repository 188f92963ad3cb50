/* Text-loader helpers: file reading, paths, a line/column tokenizer. */
#include "io/text.h"

#include "core/internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

persp_status persp__read_file(persp_context *ctx, const char *path, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* The size is taken from the stream itself so that the limit is checked
     * before the buffer exists. */
    if (fseek(f, 0, SEEK_END) != 0) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot seek (not a regular file?)", path);
    }
    long end = ftell(f);
    if (end < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot determine the file size", path);
    }
    if ((unsigned long)end > PERSP_TEXT_MAX_BYTES) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "%s: %ld bytes exceeds the limit of %zu",
                                  path, end, (size_t)PERSP_TEXT_MAX_BYTES);
    }
    size_t n = (size_t)end;
    char *buf = persp__alloc(ctx, n + 1);
    if (!buf) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    size_t got = n ? fread(buf, 1, n, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (got != n || bad) {
        persp__free(ctx, buf);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: read error", path);
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return PERSP_OK;
}

void persp__path_dir(const char *path, char *out, size_t size)
{
    if (size == 0) return;
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + 1 : 0;
    if (n >= size) n = size - 1;
    memcpy(out, path, n);
    out[n] = '\0';
}

int persp__path_join(const char *dir, const char *rel, char *out, size_t size)
{
    int n;
    if (rel[0] == '/' || !dir || !dir[0])
        n = snprintf(out, size, "%s", rel);
    else
        n = snprintf(out, size, "%s%s%s", dir, dir[strlen(dir) - 1] == '/' ? "" : "/", rel);
    return n >= 0 && (size_t)n < size;
}

const char *persp__path_base(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

int persp__next_line(const char *data, size_t size, size_t *offset, persp_line_cursor *cur)
{
    size_t o = *offset;
    if (o >= size) return 0;
    size_t e = o;
    while (e < size && data[e] != '\n') e++;
    size_t len = e - o;
    if (len && data[o + len - 1] == '\r') len--;
    cur->line = data + o;
    cur->len = len;
    cur->pos = 0;
    cur->lineno++;
    *offset = e < size ? e + 1 : size;
    return 1;
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; }

int persp__skip_blanks(persp_line_cursor *cur)
{
    while (cur->pos < cur->len && is_blank(cur->line[cur->pos])) cur->pos++;
    return cur->pos < cur->len;
}

size_t persp__token(persp_line_cursor *cur, const char **tok, size_t *col)
{
    persp__skip_blanks(cur);
    size_t start = cur->pos;
    while (cur->pos < cur->len && !is_blank(cur->line[cur->pos])) cur->pos++;
    *tok = cur->line + start;
    if (col) *col = start + 1;
    return cur->pos - start;
}

size_t persp__column(const persp_line_cursor *cur) { return cur->pos + 1; }

int persp__parse_float(const char *tok, size_t len, float *out)
{
    char buf[64];
    if (len == 0 || len >= sizeof buf) return 0;
    /* Only decimal syntax: strtod would also take "nan", "inf" and hex. */
    for (size_t i = 0; i < len; i++) {
        char c = tok[i];
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'))
            return 0;
    }
    memcpy(buf, tok, len);
    buf[len] = '\0';
    char *end = NULL;
    double d = strtod(buf, &end);
    if (end != buf + len || !isfinite(d) || fabs(d) > 3.0e38) return 0;
    *out = (float)d;
    return 1;
}

int persp__parse_long(const char *tok, size_t len, long limit, long *out)
{
    size_t i = 0;
    int neg = 0;
    if (i < len && (tok[i] == '-' || tok[i] == '+')) neg = tok[i++] == '-';
    if (i == len) return 0;
    long v = 0;
    for (; i < len; i++) {
        if (tok[i] < '0' || tok[i] > '9') return 0;
        v = v * 10 + (tok[i] - '0');
        if (v > limit) return 0;
    }
    *out = neg ? -v : v;
    return 1;
}

int persp__keyword_is(const char *tok, size_t len, const char *kw)
{
    return strlen(kw) == len && memcmp(tok, kw, len) == 0;
}

persp_status persp__text_failv(persp_context *ctx, persp_status st, const char *name, size_t line,
                               size_t col, const char *fmt, va_list ap)
{
    char msg[PERSP_ERRMSG_BYTES];
    vsnprintf(msg, sizeof msg, fmt, ap);
    return persp__fail(ctx, st, "%s:%zu:%zu: %s", name, line, col, msg);
}
