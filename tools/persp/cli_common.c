/* The CLI's message and argument-parsing helpers, apart from main() so that
 * the option table (options.c) links into a program of its own, such as the
 * option parser's fuzz harness (tests/fuzz/fuzz_options.c). */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* One line, as the library's details are (persp.h): a file named on the
 * command line may hold a line break, which is written as a space, as the
 * library writes it in the detail that follows. */
int cli_error(int code, const char *fmt, ...)
{
    char line[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    for (char *c = line; *c; c++)
        if (*c == '\n' || *c == '\r') *c = ' ';
    fprintf(stderr, "persp: %s\n", line);
    return code;
}

/* Plain decimal text only: strtol and strtod also take leading blanks, a
 * '+', hexadecimal and (strtod) "inf"/"nan" (C11 7.22.1.3-4), none of
 * which a user means in an option value. */
int cli_decimal_syntax(const char *s, int fraction)
{
    if (!s) return 0;
    if (*s == '-') s++;
    int digits = 0;
    for (; *s >= '0' && *s <= '9'; s++)
        digits++;
    if (fraction && *s == '.')
        for (s++; *s >= '0' && *s <= '9'; s++)
            digits++;
    if (!digits) return 0;
    if (fraction && (*s == 'e' || *s == 'E')) {
        s++;
        if (*s == '-' || *s == '+') s++;
        if (*s < '0' || *s > '9') return 0;
        while (*s >= '0' && *s <= '9')
            s++;
    }
    return *s == '\0';
}

int cli_parse_int(const char *text, long lo, long hi, long *out)
{
    if (!cli_decimal_syntax(text, 0)) return 0;
    errno = 0;
    char *end = NULL;
    long v = strtol(text, &end, 10);
    if (errno || *end != '\0' || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

int cli_parse_real(const char *text, double lo, double hi, double *out)
{
    if (!cli_decimal_syntax(text, 1)) return 0;
    char *end = NULL;
    double v = strtod(text, &end);
    if (*end != '\0' || !isfinite(v) || !(v >= lo && v <= hi)) return 0;
    *out = v;
    return 1;
}

int cli_parse_size(const char *text, int *w, int *h)
{
    if (!text) return 0;
    const char *x = strchr(text, 'x');
    if (!x || x == text) return 0;
    char buf[32];
    size_t len = (size_t)(x - text);
    if (len >= sizeof buf) return 0;
    memcpy(buf, text, len);
    buf[len] = '\0';
    long a, b;
    if (!cli_parse_int(buf, 1, PERSP_IMAGE_MAX_SIDE, &a)) return 0;
    if (!cli_parse_int(x + 1, 1, PERSP_IMAGE_MAX_SIDE, &b)) return 0;
    if ((unsigned long)a * (unsigned long)b > PERSP_IMAGE_MAX_PIXELS) return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

int cli_split_list(char *text, const char **list, size_t *n, size_t cap)
{
    for (char *p = text;;) {
        char *comma = strchr(p, ',');
        if (comma) *comma = '\0';
        if (!*p || *n >= cap) return 0;
        list[(*n)++] = p;
        if (!comma) return 1;
        p = comma + 1;
    }
}
