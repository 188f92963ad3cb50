/* Strict decimal numbers for specs and settings, and safe quoting of
 * foreign text in messages.
 *
 * strtol/strtod accept more than a user means to write: leading blanks, a
 * '+', hexadecimal ("0x10" is 16 for strtol with base 0 and for strtod
 * always, C11 7.22.1.3), "inf" and "nan". A spec such as "subdiv: 16"
 * is a typo more often than not, so only plain decimal text is taken. */
#include "core/internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* [-]digits[.digits][(e|E)[-|+]digits], at least one mantissa digit. */
int persp__decimal_syntax(const char *s, int allow_fraction)
{
    if (!s) return 0;
    if (*s == '-') s++;
    int digits = 0;
    while (is_digit(*s))
        s++, digits++;
    if (allow_fraction && *s == '.') {
        s++;
        while (is_digit(*s))
            s++, digits++;
    }
    if (!digits) return 0;
    if (allow_fraction && (*s == 'e' || *s == 'E')) {
        s++;
        if (*s == '-' || *s == '+') s++;
        if (!is_digit(*s)) return 0;
        while (is_digit(*s))
            s++;
    }
    return *s == '\0';
}

int persp__parse_long(const char *s, long lo, long hi, long *out)
{
    if (!persp__decimal_syntax(s, 0)) return 0;
    errno = 0;
    char *end = NULL;
    long v = strtol(s, &end, 10);
    if (errno || *end || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

int persp__parse_double(const char *s, double lo, double hi, double *out)
{
    if (!persp__decimal_syntax(s, 1)) return 0;
    char *end = NULL;
    double v = strtod(s, &end);
    if (*end || !isfinite(v) || !(v >= lo && v <= hi)) return 0;
    *out = v;
    return 1;
}

const char *persp__quote(const char *text, size_t len, char *buf, size_t size)
{
    if (!size) return "";
    size_t n = 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)text[i];
        char esc[8];
        int w;
        if (c >= 0x20 && c < 0x7f && c != '\\')
            esc[0] = (char)c, esc[1] = '\0', w = 1;
        else if (c == '\\')
            w = snprintf(esc, sizeof esc, "\\\\");
        else
            w = snprintf(esc, sizeof esc, "\\x%02x", c);
        /* Keep room for "..." and the terminator. */
        if (n + (size_t)w + 4 > size) {
            size_t k = n + 3 < size ? 3 : size - 1 - n;
            for (size_t d = 0; d < k; d++)
                buf[n++] = '.';
            break;
        }
        for (int d = 0; d < w; d++)
            buf[n++] = esc[d];
    }
    buf[n] = '\0';
    return buf;
}
