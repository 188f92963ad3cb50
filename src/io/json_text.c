/*
 * JSON text as persp checks it around jansson (2.14): the parser takes no
 * per-call allocator (json_set_alloc_funcs is process-wide, and would also
 * take over the blocks of any other jansson user in the program), so what
 * its allocations do is inferred from the text: how much it may take, and
 * whether a failure it reports, or one it does not report, was an
 * allocation's.
 */
#include "io/json_text.h"

#include "core/internal.h"

#include <locale.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* An upper bound of what jansson (2.14) allocates to parse text: it takes
 * no per-call allocator (json_set_alloc_funcs is process-wide, and would
 * also take over the blocks of any other jansson user in the program), so
 * its need is bounded from the text before it starts, by one pass that
 * counts what the parser will build. The costs per item, malloc's own
 * overhead included, cover what jansson was measured to take (text of a
 * million of each, docs/RELIABILITY.md): an empty object 232 bytes, an
 * empty array 136, a number 40, an empty string 88, a member beyond its key
 * and value at most 90, a string's text 2.9 bytes per byte. */
size_t persp__json_parse_bound(const char *t, size_t n)
{
    size_t objects = 0, arrays = 0, scalars = 0, strings = 0, members = 0, text = 0;
    int value_next = 1; /* after '[', ',', ':' or at the start */
    for (size_t i = 0; i < n; i++) {
        char c = t[i];
        if (c == '"') {
            size_t k = i + 1;
            while (k < n && t[k] != '"') k += t[k] == '\\' ? 2 : 1;
            strings++;
            text += k - i;
            i = k;
            value_next = 0;
        } else if (c == '{') {
            objects++, value_next = 0;
        } else if (c == '[') {
            arrays++, value_next = 1;
        } else if (c == ',' || c == ':') {
            members += c == ':';
            value_next = 1;
        } else if (value_next && c != ' ' && c != '\t' && c != '\n' && c != '\r' && c != ']' &&
                   c != '}') {
            scalars++, value_next = 0;
        }
    }
    double b = 240.0 * (double)objects + 144.0 * (double)arrays + 48.0 * (double)scalars +
               96.0 * (double)strings + 112.0 * (double)members + 4.0 * (double)text + 65536.0;
    return b < (double)((size_t)-1 / 2) ? (size_t)b : (size_t)-1 / 2;
}

/* ------------------------------------------------ JSON syntax, allocation-free */

/* Deepest nesting json_syntax_stop follows; beyond jansson's own limit
 * (JSON_PARSER_MAX_DEPTH, 2048 in 2.14), where it stops parsing anyway. */
#define JSON_CHECK_DEPTH 4096

static int hex_digit(char c)
{
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

/* The value of the \uXXXX escape at t[i] (t[i] == '\\'), -1 when its four
 * hex digits are not all there; *bad: the offset of the first that is not. */
static long syntax_unicode(const char *t, size_t n, size_t i, size_t *bad)
{
    long v = 0;
    for (size_t k = i + 2; k < i + 6; k++) {
        if (k >= n || !hex_digit(t[k])) {
            *bad = k < n ? k : n;
            return -1;
        }
        char c = t[k];
        v = v * 16 + (c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10);
    }
    return v;
}

/* The end of the string token at t[i] (a '"'), or SIZE_MAX with *bad at the
 * first byte no JSON string can continue with (n: the text ended). The
 * rules are RFC 8259 §7 with jansson 2.14's own (load.c, lex_scan_string):
 * no control byte below 0x20, a UTF-16 surrogate only as a high-low pair. */
static size_t syntax_string(const char *t, size_t n, size_t i, size_t *bad)
{
    for (i++; i < n; i++) {
        unsigned char c = (unsigned char)t[i];
        if (c == '"') return i + 1;
        if (c < 0x20) break;
        if (c != '\\') continue;
        if (i + 1 >= n) {
            i = n;
            break;
        }
        char e = t[i + 1];
        if (e != 'u') {
            if (e == '\0' || !strchr("\"\\/bfnrt", e)) { /* strchr finds the NUL too */
                i++;
                break;
            }
            i++;
            continue;
        }
        long v = syntax_unicode(t, n, i, bad);
        if (v < 0) return SIZE_MAX;
        if (v >= 0xdc00 && v <= 0xdfff) break; /* a low surrogate first */
        if (v >= 0xd800 && v <= 0xdbff) {
            size_t low = i + 6;
            if (low >= n || t[low] != '\\' || low + 1 >= n || t[low + 1] != 'u') {
                i = low < n ? low : n;
                break;
            }
            long w = syntax_unicode(t, n, low, bad);
            if (w < 0) return SIZE_MAX;
            if (w < 0xdc00 || w > 0xdfff) {
                i = low;
                break;
            }
            i = low;
        }
        i += 5;
    }
    *bad = i < n ? i : n;
    return SIZE_MAX;
}

/* The end of the number at t[i] (RFC 8259 §6), or SIZE_MAX with *bad. */
static size_t syntax_number(const char *t, size_t n, size_t i, size_t *bad)
{
#define DIGIT(k) ((k) < n && t[k] >= '0' && t[k] <= '9')
    if (i < n && t[i] == '-') i++;
    if (i < n && t[i] == '0')
        i++;
    else if (DIGIT(i))
        while (DIGIT(i)) i++;
    else
        goto bad;
    if (i < n && t[i] == '.') {
        if (!DIGIT(i + 1)) {
            i++;
            goto bad;
        }
        for (i++; DIGIT(i);) i++;
    }
    if (i < n && (t[i] == 'e' || t[i] == 'E')) {
        i++;
        if (i < n && (t[i] == '+' || t[i] == '-')) i++;
        if (!DIGIT(i)) goto bad;
        while (DIGIT(i)) i++;
    }
    return i;
bad:
    *bad = i < n ? i : n;
    return SIZE_MAX;
#undef DIGIT
}

/* jansson 2.14 takes back the byte after a number or a literal
 * (lex_unget_unsave) by stepping back in its one-character buffer, which
 * reads a NUL there as empty: a NUL right after such a token is skipped,
 * and not counted in the error position either. 1 when t[*i] is one (and
 * steps over it). */
static size_t swallowed_nul(const char *t, size_t n, size_t *i)
{
    if (*i >= n || t[*i] != '\0') return 0;
    (*i)++;
    return 1;
}

/* Where text t stops being a JSON text that jansson (with neither
 * JSON_DECODE_ANY nor JSON_DISABLE_EOF_CHECK) accepts as far as syntax goes:
 * the offset of the first byte that no valid text continues with (n when it
 * ends too early), SIZE_MAX when all of it is valid. Needs no memory but a
 * bit per level of nesting, so it still answers when the allocator does
 * not: see scene_json.c's load_json for why it is asked. Limits of numbers, duplicate keys,
 * UTF-8 and \u0000 are not checked (jansson reports those under their own
 * error codes). The offset is counted as jansson counts its position,
 * without the NUL bytes it skips (swallowed_nul). */
static size_t json_syntax_stop(const char *t, size_t n)
{
    unsigned char in_object[JSON_CHECK_DEPTH / 8];
    size_t depth = 0, i = 0, bad = n, lost = 0;
    enum { VALUE, VALUE_OR_CLOSE, KEY, KEY_OR_CLOSE, COLON, NEXT } expect = VALUE;
    for (;;) {
        while (i < n && (t[i] == ' ' || t[i] == '\t' || t[i] == '\n' || t[i] == '\r'))
            i++;
        if (i >= n) return n - lost;
        char c = t[i];
        int closed = 0;
        if (depth == 0 && c != '{' && c != '[') return i - lost; /* jansson: '[' or '{' expected */
        if (expect == VALUE || expect == VALUE_OR_CLOSE) {
            if (c == ']' && expect == VALUE_OR_CLOSE) {
                closed = 1;
            } else if (c == '{' || c == '[') {
                if (depth == JSON_CHECK_DEPTH) return i - lost;
                unsigned char bit = (unsigned char)(1u << (depth % 8));
                if (c == '{')
                    in_object[depth / 8] |= bit;
                else
                    in_object[depth / 8] &= (unsigned char)~bit;
                depth++;
                expect = c == '{' ? KEY_OR_CLOSE : VALUE_OR_CLOSE;
                i++;
                continue;
            } else if (c == '"') {
                if ((i = syntax_string(t, n, i, &bad)) == SIZE_MAX) return bad - lost;
            } else if (c == '-' || (c >= '0' && c <= '9')) {
                if ((i = syntax_number(t, n, i, &bad)) == SIZE_MAX) return bad - lost;
                lost += swallowed_nul(t, n, &i);
            } else {
                const char *word = c == 't' ? "true" : c == 'f' ? "false" : c == 'n' ? "null" : "";
                size_t k = 0;
                while (word[k] && i + k < n && t[i + k] == word[k])
                    k++;
                if (!word[0] || word[k]) return (i + k < n ? i + k : n) - lost;
                i += k;
                lost += swallowed_nul(t, n, &i);
            }
        } else if (expect == KEY || expect == KEY_OR_CLOSE) {
            if (c == '}' && expect == KEY_OR_CLOSE) {
                closed = 1;
            } else {
                if (c != '"') return i - lost;
                if ((i = syntax_string(t, n, i, &bad)) == SIZE_MAX) return bad - lost;
                expect = COLON;
                continue;
            }
        } else if (expect == COLON) {
            if (c != ':') return i - lost;
            expect = VALUE;
            i++;
            continue;
        } else { /* NEXT: after a member or element */
            int object = (in_object[(depth - 1) / 8] >> ((depth - 1) % 8)) & 1;
            if (c == ',') {
                expect = object ? KEY : VALUE;
                i++;
                continue;
            }
            if (c != (object ? '}' : ']')) return i - lost;
            closed = 1;
        }
        if (closed) {
            depth--;
            i++;
        }
        if (depth == 0) {
            /* The top value is complete: only white space may follow. */
            while (i < n && (t[i] == ' ' || t[i] == '\t' || t[i] == '\n' || t[i] == '\r'))
                i++;
            return i < n ? i - lost : SIZE_MAX;
        }
        expect = NEXT;
    }
}

/* 1 when json_loadb failed on text because an allocation failed, whatever
 * its message says. jansson (2.11 and later) classifies errors, but its
 * parser (2.14, load.c) shows a failed allocation in three ways:
 * json_error_out_of_memory where it says so; an empty error text (an
 * object, array, member or the lexer's buffer not allocated: the parser
 * returns NULL without setting one); and a syntax error: lex_scan_string makes
 * a string whose copy it cannot allocate an invalid token, reported as
 * "invalid token" or "string or '}' expected" (json_error_invalid_syntax)
 * at the end of that string. A real syntax error is reported once the
 * parser has read the byte at fault, so it never stops before where
 * json_syntax_stop finds the first bad byte; a syntax error reported
 * before that point, or on text without one, is the allocation's. The
 * per-call hooks that would say so directly do not exist:
 * json_set_alloc_funcs is process-wide (jansson's "Custom memory
 * allocation" docs), so persp leaves it to the program. */
int persp__json_parse_ran_out(const char *text, size_t size, const json_error_t *err)
{
    enum json_error_code code = json_error_code(err);
    if (code == json_error_out_of_memory || !err->text[0]) return 1;
    if (code != json_error_invalid_syntax) return 0;
    size_t stop = json_syntax_stop(text, size);
    return stop == SIZE_MAX || (err->position >= 0 && stop > (size_t)err->position);
}

/* Whether jansson stopped at a closing bracket that follows a comma, the
 * trailing comma that JavaScript and many editors allow and JSON does not
 * (RFC 8259 §4, §5). position: jansson's, just past the bracket. */
int persp__json_trailing_comma(const char *text, size_t size, int position)
{
    if (position < 1 || (size_t)position > size) return 0;
    size_t i = (size_t)position - 1;
    if (text[i] != '}' && text[i] != ']') return 0;
    while (i > 0 && strchr(" \t\r\n", text[i - 1])) i--;
    return i > 0 && text[i - 1] == ',';
}

/* ------------------------------------------- the parsed tree against the text */

/* jansson's lexer keeps each token's text in a buffer that grows (doubling
 * from 16 bytes) when a token outgrows it, and ignores a failed growth
 * (lex_save drops the byte; load.c of 2.14): when a later allocation
 * succeeds, the parse succeeds with a key, string or number short of a
 * byte, a wrong value no error reports. So a parse that succeeded is
 * walked once more against the text: every string's and key's decoded
 * length and every number's value must be what the text holds. */
typedef struct tree_walk {
    persp_context *ctx;
    const char *t;
    size_t n, i;
} tree_walk;

static void skip_blank(tree_walk *w)
{
    while (w->i < w->n && (w->t[w->i] == ' ' || w->t[w->i] == '\t' || w->t[w->i] == '\n' ||
                           w->t[w->i] == '\r'))
        w->i++;
}

/* The UTF-8 length of the string token at w->i, decoded as jansson decodes
 * it (RFC 8259 §7); SIZE_MAX when it is not a valid token. Steps over it. */
static size_t string_length(tree_walk *w)
{
    size_t bad, end = syntax_string(w->t, w->n, w->i, &bad);
    if (end == SIZE_MAX) return SIZE_MAX;
    size_t len = 0;
    for (size_t k = w->i + 1; k + 1 < end; k++) {
        if (w->t[k] != '\\') {
            len++;
            continue;
        }
        if (w->t[k + 1] != 'u') {
            len++, k++;
            continue;
        }
        long v = syntax_unicode(w->t, w->n, k, &bad);
        k += 5;
        if (v >= 0xd800 && v <= 0xdbff) {
            len += 4; /* with its low surrogate, checked by syntax_string */
            k += 6;
        } else {
            len += v < 0x80 ? 1 : v < 0x800 ? 2 : 3;
        }
    }
    w->i = end;
    return len;
}

/* The number token at w->i against v, as jansson converts it: an integer
 * (no fraction or exponent) by strtoll, which never overflowed here (jansson
 * refuses that), else by strtod with the locale's decimal point. */
static int number_matches(tree_walk *w, json_t *v)
{
    size_t bad, start = w->i, end = syntax_number(w->t, w->n, w->i, &bad);
    if (end == SIZE_MAX) return 0;
    w->i = end;
    int integer = 1;
    for (size_t k = start; k < end; k++)
        integer &= w->t[k] != '.' && w->t[k] != 'e' && w->t[k] != 'E';
    if (integer) {
        if (!json_is_integer(v)) return 0;
        const int neg = w->t[start] == '-';
        unsigned long long mag = 0;
        for (size_t k = start + (size_t)neg; k < end; k++)
            mag = mag * 10u + (unsigned long long)(w->t[k] - '0');
        const long long got = json_integer_value(v);
        const unsigned long long gmag =
            got < 0 ? 0ull - (unsigned long long)got : (unsigned long long)got;
        return gmag == mag && (got < 0) == (neg && mag != 0);
    }
    if (!json_is_real(v)) return 0;
    char local[128], *copy = local;
    const size_t len = end - start;
    if (len + 1 > sizeof local && !(copy = persp__alloc(w->ctx, len + 1))) return 0;
    memcpy(copy, w->t + start, len);
    copy[len] = '\0';
    const char point = localeconv()->decimal_point[0];
    char *dot = strchr(copy, '.');
    if (dot && point) *dot = point;
    const double d = strtod(copy, NULL);
    if (copy != local) persp__free(w->ctx, copy);
    return d == json_real_value(v);
}

/* jansson skips a NUL byte right after a number or literal (swallowed_nul). */
static void skip_swallowed(tree_walk *w) { (void)swallowed_nul(w->t, w->n, &w->i); }

static int value_matches(tree_walk *w, json_t *v)
{
    skip_blank(w);
    if (w->i >= w->n || !v) return 0;
    const char c = w->t[w->i];
    if (c == '{') {
        if (!json_is_object(v)) return 0;
        w->i++;
        void *it = json_object_iter(v);
        skip_blank(w);
        if (w->i < w->n && w->t[w->i] == '}') {
            w->i++;
            return it == NULL;
        }
        for (;;) {
            skip_blank(w);
            if (!it || w->i >= w->n || w->t[w->i] != '"') return 0;
            const size_t klen = string_length(w);
            if (klen == SIZE_MAX || klen != strlen(json_object_iter_key(it))) return 0;
            skip_blank(w);
            if (w->i >= w->n || w->t[w->i] != ':') return 0;
            w->i++;
            if (!value_matches(w, json_object_iter_value(it))) return 0;
            it = json_object_iter_next(v, it);
            skip_blank(w);
            if (w->i < w->n && w->t[w->i] == ',') {
                w->i++;
                continue;
            }
            if (w->i < w->n && w->t[w->i] == '}') {
                w->i++;
                return it == NULL;
            }
            return 0;
        }
    }
    if (c == '[') {
        if (!json_is_array(v)) return 0;
        w->i++;
        size_t k = 0;
        skip_blank(w);
        if (w->i < w->n && w->t[w->i] == ']') {
            w->i++;
            return json_array_size(v) == 0;
        }
        for (;; k++) {
            if (k >= json_array_size(v) || !value_matches(w, json_array_get(v, k))) return 0;
            skip_blank(w);
            if (w->i < w->n && w->t[w->i] == ',') {
                w->i++;
                continue;
            }
            if (w->i < w->n && w->t[w->i] == ']') {
                w->i++;
                return k + 1 == json_array_size(v);
            }
            return 0;
        }
    }
    if (c == '"') {
        const size_t len = string_length(w);
        return json_is_string(v) && len != SIZE_MAX && len == json_string_length(v);
    }
    if (c == '-' || (c >= '0' && c <= '9')) {
        int ok = number_matches(w, v);
        skip_swallowed(w);
        return ok;
    }
    const char *word = json_is_true(v) ? "true" : json_is_false(v) ? "false" : json_is_null(v) ? "null" : NULL;
    if (!word) return 0;
    const size_t wl = strlen(word);
    if (w->n - w->i < wl || memcmp(w->t + w->i, word, wl) != 0) return 0;
    w->i += wl;
    skip_swallowed(w);
    return 1;
}

int persp__json_tree_matches(persp_context *ctx, const char *text, size_t size, json_t *root)
{
    tree_walk w = {ctx, text, size, 0};
    return value_matches(&w, root);
}
