/*
 * Wavefront OBJ and MTL, read by persp (docs/SCENES.md, "Models").
 *
 * Two passes over the text, line by line: the first counts (vertices,
 * texture coordinates, normals, and per mesh its triangles and face
 * corners) and reads the material libraries, the second parses into
 * attribute and index arrays allocated once at their final size (only the
 * list of a run's distinct corners grows, by doubling). A file is read in
 * chunks of OBJ_CHUNK bytes, never whole, so a model costs what its mesh
 * costs (docs/RELIABILITY.md, "Memory and time bounds"); nothing is allocated
 * per line or per face.
 *
 * The results follow what Assimp 5.2 made of the same files, so that images
 * stay as they were: one mesh per run of faces between a change of group,
 * object or material; polygons cut the way Assimp's triangulation cuts
 * them; normals, where the file gives none, made the way its
 * GenVertexNormals step makes them (80 degree crease, src/model/obj_vertices.c);
 * the MTL defaults of its reader. The reader's state is in model/obj_reader.h.
 */
#include "model/obj.h"
#include "model/obj_reader.h"

#include "core/internal.h"
#include "io/text.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bytes read from a file at a time, and the longest line taken: a longer
 * one is refused rather than buffered without bound. */
#define OBJ_CHUNK ((size_t)1 << 20)
#define OBJ_LINE_MAX ((size_t)1 << 20)
/* Largest polygon cut by ear clipping (see emit_polygon). */
#define OBJ_EAR_MAX 256

/* ------------------------------------------------------------------ lines */

typedef struct obj_lines {
    persp_context *ctx;
    const char *display; /* the file in messages */
    FILE *f;             /* NULL: the whole text is in text */
    const char *text;    /* window of unread bytes: text[pos, len) */
    char *buf;           /* a file's window of cap bytes: at most OBJ_CHUNK + OBJ_LINE_MAX */
    size_t cap, len, pos;
    int eof;
    int skip_lf;         /* a CR ended the window: a following LF belongs to it */
    size_t line;         /* number of the next physical line */
    char *join;          /* a line continued with '\' (allocated when first met) */
    persp_status status; /* of the failure when a call returned -1 */
} obj_lines;

static int lines_fail(obj_lines *l, persp_status st, const char *what)
{
    l->status = persp__fail(l->ctx, st, "%s:%zu: %s", l->display, l->line, what);
    return -1;
}

/* More of the file into the window, keeping its unread bytes. */
static int refill(obj_lines *l)
{
    if (!l->f || l->eof) return 0;
    if (l->pos) {
        memmove(l->buf, l->buf + l->pos, l->len - l->pos);
        l->len -= l->pos;
        l->pos = 0;
    }
    if (l->len == l->cap && l->cap < OBJ_CHUNK + OBJ_LINE_MAX) {
        /* A line longer than the window so far: the window grows once, to
         * hold a line of the longest length taken and a chunk. */
        char *wide = persp__alloc(l->ctx, OBJ_CHUNK + OBJ_LINE_MAX);
        if (!wide) {
            l->status =
                persp__fail(l->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", l->display);
            return -1;
        }
        memcpy(wide, l->buf, l->len);
        persp__free(l->ctx, l->buf);
        l->buf = wide;
        l->cap = OBJ_CHUNK + OBJ_LINE_MAX;
    }
    size_t room = l->cap - l->len;
    if (room > OBJ_CHUNK) room = OBJ_CHUNK;
    size_t got = room ? fread(l->buf + l->len, 1, room, l->f) : 0;
    if (got == 0) {
        if (ferror(l->f)) {
            l->status = persp__fail(l->ctx, PERSP_ERR_IO, "%s: read error", l->display);
            return -1;
        }
        l->eof = 1;
    }
    l->len += got;
    l->text = l->buf;
    return 0;
}

/* Starts (again) at the beginning, past a UTF-8 byte-order mark. */
static int lines_rewind(obj_lines *l, const char *data, size_t size)
{
    l->line = 1;
    l->skip_lf = 0;
    l->pos = 0;
    if (l->f) {
        if (fseek(l->f, 0, SEEK_SET) != 0) {
            l->status = persp__fail(l->ctx, PERSP_ERR_IO, "%s: cannot seek (not a regular file?)",
                                    l->display);
            return -1;
        }
        l->len = 0;
        l->eof = 0;
        if (refill(l) != 0) return -1;
    } else {
        l->text = data;
        l->len = size;
        l->eof = 1;
    }
    if (l->len - l->pos >= 3 && !memcmp(l->text + l->pos, "\xef\xbb\xbf", 3)) l->pos += 3;
    /* UTF-16 text (its byte-order mark) would read as lines cut at every
     * NUL: refused by name instead. */
    if (l->len - l->pos >= 2 &&
        (!memcmp(l->text + l->pos, "\xfe\xff", 2) || !memcmp(l->text + l->pos, "\xff\xfe", 2))) {
        l->status = persp__fail(l->ctx, PERSP_ERR_FORMAT,
                                "%s: UTF-16 text; OBJ and MTL files are read as UTF-8 or ASCII",
                                l->display);
        return -1;
    }
    return 0;
}

/* The next physical line, without its end: LF, CRLF, a lone CR (classic Mac
 * files) or a NUL, which ends a line for Assimp's reader too (it does not
 * count as a new line in messages). 1, 0 at the end, -1 on error. */
static int physical(obj_lines *l, const char **s, size_t *n)
{
    for (;;) {
        if (l->skip_lf && l->pos < l->len) {
            if (l->text[l->pos] == '\n') l->pos++;
            l->skip_lf = 0;
        }
        const char *p = l->text + l->pos, *end = l->text + l->len, *q = p;
        while (q < end && *q != '\n' && *q != '\r' && *q != '\0')
            q++;
        if (q == end && !l->eof) {
            if ((size_t)(q - p) > OBJ_LINE_MAX)
                return lines_fail(l, PERSP_ERR_FORMAT, "a line longer than 1 MiB");
            if (refill(l) != 0) return -1;
            continue;
        }
        if (p == end) return 0;
        if ((size_t)(q - p) > OBJ_LINE_MAX)
            return lines_fail(l, PERSP_ERR_FORMAT, "a line longer than 1 MiB");
        *s = p;
        *n = (size_t)(q - p);
        l->pos = (size_t)(q - l->text);
        if (q < end) {
            l->pos++;
            if (*q != '\0') l->line++;
            if (*q == '\r') {
                if (q + 1 < end) {
                    if (q[1] == '\n') l->pos++;
                } else {
                    l->skip_lf = 1;
                }
            }
        }
        return 1;
    }
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}

/* The next logical line: physical lines ending in '\' continue on the next
 * (OBJ specification, "General statement"). *at: its first line's number. */
static int next_line(obj_lines *l, const char **s, const char **e, size_t *at)
{
    const char *p;
    size_t n;
    *at = l->line;
    int got = physical(l, &p, &n);
    if (got <= 0) return got;
    size_t trail = n;
    while (trail && is_blank(p[trail - 1]))
        trail--;
    if (trail == 0 || p[trail - 1] != '\\') {
        *s = p;
        *e = p + n;
        return 1;
    }
    if (!l->join && !(l->join = persp__alloc(l->ctx, OBJ_LINE_MAX + 1))) {
        l->status = persp__fail(l->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", l->display);
        return -1;
    }
    size_t len = 0;
    for (;;) {
        trail = n;
        while (trail && is_blank(p[trail - 1]))
            trail--;
        int more = trail && p[trail - 1] == '\\';
        size_t take = more ? trail - 1 : n;
        if (len + take + 1 > OBJ_LINE_MAX) {
            l->line = *at;
            return lines_fail(l, PERSP_ERR_FORMAT, "a line longer than 1 MiB");
        }
        memcpy(l->join + len, p, take);
        len += take;
        if (!more) break;
        l->join[len++] = ' ';
        got = physical(l, &p, &n);
        if (got < 0) return -1;
        if (got == 0) break;
    }
    *s = l->join;
    *e = l->join + len;
    return 1;
}

/* ------------------------------------------------------------- tokens */

static const char *skip_blanks(const char *p, const char *e)
{
    while (p < e && is_blank(*p))
        p++;
    return p;
}

static const char *token_end(const char *p, const char *e)
{
    while (p < e && !is_blank(*p))
        p++;
    return p;
}

static int token_is(const char *p, const char *q, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(q - p) == n && memcmp(p, word, n) == 0;
}

static int token_is_nocase(const char *p, const char *q, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(q - p) != n) return 0;
    for (size_t i = 0; i < n; i++) {
        char c = p[i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != word[i]) return 0;
    }
    return 1;
}

/* The rest of the line without surrounding blanks. */
static void rest_of_line(const char *p, const char *e, const char **s, const char **t)
{
    p = skip_blanks(p, e);
    while (e > p && is_blank(e[-1]))
        e--;
    *s = p;
    *t = e;
}

static size_t count_tokens(const char *p, const char *e)
{
    size_t n = 0;
    for (p = skip_blanks(p, e); p < e; p = skip_blanks(token_end(p, e), e))
        n++;
    return n;
}

/* A decimal number as exporters write it: optional sign, digits with an
 * optional point ("2." and ".5" included), optional exponent; also nan and
 * inf (then refused where a finite value is needed). Locale-independent.
 * The token must end at a blank or the end. 1 when well-formed. */
static int parse_number(const char *p, const char *e, float *out)
{
    int neg = 0;
    if (p < e && (*p == '+' || *p == '-')) neg = *p++ == '-';
    if (e - p >= 3 && (token_is_nocase(p, e, "nan") || token_is_nocase(p, e, "inf") ||
                       token_is_nocase(p, e, "infinity"))) {
        *out = (p[0] == 'n' || p[0] == 'N') ? NAN : (neg ? -INFINITY : INFINITY);
        return 1;
    }
    uint64_t m = 0;
    int digits = 0, exp10 = 0, any = 0;
    for (; p < e && *p >= '0' && *p <= '9'; p++, any = 1) {
        if (digits < 19) {
            if (m || *p != '0') digits++;
            m = m * 10 + (uint64_t)(*p - '0');
        } else {
            exp10++;
        }
    }
    if (p < e && *p == '.') {
        for (p++; p < e && *p >= '0' && *p <= '9'; p++, any = 1)
            if (digits < 19) {
                if (m || *p != '0') digits++;
                m = m * 10 + (uint64_t)(*p - '0');
                exp10--;
            }
    }
    if (!any) return 0;
    if (p < e && (*p == 'e' || *p == 'E')) {
        p++;
        int eneg = 0;
        long x = 0;
        if (p < e && (*p == '+' || *p == '-')) eneg = *p++ == '-';
        if (p == e || *p < '0' || *p > '9') return 0;
        for (; p < e && *p >= '0' && *p <= '9'; p++)
            if (x < 100000) x = x * 10 + (*p - '0');
        exp10 += (int)(eneg ? -x : x);
    }
    if (p != e) return 0;
    double v;
    static const double pow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                   1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                   1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    if (m == 0)
        v = 0.0;
    else if (m < ((uint64_t)1 << 53) && exp10 >= -22 && exp10 <= 22)
        /* Both exact in a double: one correctly rounded operation. */
        v = exp10 >= 0 ? (double)m * pow10[exp10] : (double)m / pow10[-exp10];
    else
        v = (double)((long double)m * powl(10.0L, (long double)exp10));
    *out = (float)(neg ? -v : v);
    return 1;
}

/* ------------------------------------------------------------- the reader */

persp_status persp__obj_oom(obj_reader *r)
{
    return persp__fail(r->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", r->display);
}

static persp_status line_error(obj_reader *r, size_t line, const char *what, const char *p,
                               const char *q)
{
    if (p) {
        char qt[PERSP_QUOTE_BYTES];
        return persp__fail(r->ctx, PERSP_ERR_FORMAT, "%s:%zu: %s '%s'", r->display, line, what,
                           persp__quote(p, (size_t)(q - p), qt, sizeof qt));
    }
    return persp__fail(r->ctx, PERSP_ERR_FORMAT, "%s:%zu: %s", r->display, line, what);
}

persp_status persp__obj_too_large(obj_reader *r)
{
    return persp__fail(r->ctx, PERSP_ERR_TOO_LARGE,
                       "%s: more than %zu vertices or %u triangle corners", r->display,
                       r->max_vertices, PERSP_SCENE_MAX_INDICES);
}

/* ------------------------------------------------------------- materials */

static persp_status pool_add(obj_reader *r, const char *s, size_t n, size_t *off)
{
    if (persp__grow(r->ctx, (void **)&r->pool, &r->pool_cap, r->pool_len + n + 1, 1) != PERSP_OK)
        return persp__obj_oom(r);
    memcpy(r->pool + r->pool_len, s, n);
    r->pool[r->pool_len + n] = '\0';
    *off = r->pool_len;
    r->pool_len += n + 1;
    return PERSP_OK;
}

static size_t name_slot(const char *name, size_t n, size_t cap)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (size_t k = 0; k < n; k++) h = (h ^ (unsigned char)name[k]) * 1099511628211ull;
    return (size_t)(h ^ (h >> 32)) & (cap - 1);
}

/* Found through a hash of the names: a library of 10^5 materials, each
 * compared with all before it, took half a minute. */
static int find_material(const obj_reader *r, const char *name, size_t n)
{
    if (!r->mat_table_cap) return -1;
    for (size_t s = name_slot(name, n, r->mat_table_cap);; s = (s + 1) & (r->mat_table_cap - 1)) {
        const uint32_t e = r->mat_table[s];
        if (!e) return -1;
        const char *m = r->pool + r->mats[e - 1].name;
        if (strlen(m) == n && memcmp(m, name, n) == 0) return (int)(e - 1);
    }
}

/* Material i into the name hash, which is kept at most half full. */
static persp_status hash_material(obj_reader *r, size_t i)
{
    if (2 * (i + 1) > r->mat_table_cap) {
        size_t cap = r->mat_table_cap ? 2 * r->mat_table_cap : 64;
        uint32_t *t = persp__calloc(r->ctx, cap, sizeof *t);
        if (!t) return persp__obj_oom(r);
        persp__free(r->ctx, r->mat_table);
        r->mat_table = t;
        r->mat_table_cap = cap;
        for (size_t k = 0; k < i; k++) {
            const char *m = r->pool + r->mats[k].name;
            size_t s = name_slot(m, strlen(m), cap);
            while (t[s]) s = (s + 1) & (cap - 1);
            t[s] = (uint32_t)k + 1;
        }
    }
    const char *m = r->pool + r->mats[i].name;
    size_t s = name_slot(m, strlen(m), r->mat_table_cap);
    while (r->mat_table[s]) s = (s + 1) & (r->mat_table_cap - 1);
    r->mat_table[s] = (uint32_t)i + 1;
    return PERSP_OK;
}

/* A material as Assimp's MTL reader starts one (ObjFile::Material): grey
 * diffuse 0.6, black ambient and specular, shininess 0. */
static persp_status new_material(obj_reader *r, const char *name, size_t n, size_t lib, int *out)
{
    if (persp__grow(r->ctx, (void **)&r->mats, &r->mats_cap, r->nmats + 1, sizeof *r->mats) !=
        PERSP_OK)
        return persp__obj_oom(r);
    obj_mat *m = &r->mats[r->nmats];
    memset(m, 0, sizeof *m);
    for (int k = 0; k < 3; k++)
        m->kd[k] = 0.6f;
    m->tex = m->glow = NO_NAME;
    m->lib = lib;
    m->scene = -1;
    persp_status st = pool_add(r, name, n, &m->name);
    if (st == PERSP_OK) st = hash_material(r, r->nmats);
    if (st != PERSP_OK) return st;
    *out = (int)r->nmats++;
    return PERSP_OK;
}

/* "Kd r [g b]": one value stands for all three (MTL specification). */
static int mtl_colour(const char *p, const char *e, float *c)
{
    float v[3];
    int n = 0;
    for (p = skip_blanks(p, e); p < e && n < 3; p = skip_blanks(p, e)) {
        const char *q = token_end(p, e);
        if (!parse_number(p, q, &v[n])) return -1;
        n++;
        p = q;
    }
    if (n == 0) return 0;
    for (int k = 0; k < 3; k++)
        c[k] = v[n == 3 ? k : 0];
    return 1;
}

/* map_Kd [options] file: the options of the MTL specification ("-o u v w",
 * "-clamp on", ...) are skipped with their arguments; the rest of the line
 * is the file, spaces included (as exporters write names). */
static void mtl_map(const char *p, const char *e, int *clamp, const char **s, const char **t)
{
    static const struct {
        const char *name;
        int args; /* -1: up to three numbers */
    } opts[] = {{"-blendu", 1}, {"-blendv", 1},  {"-bm", 1},  {"-boost", 1}, {"-cc", 1},
                {"-clamp", 1},  {"-imfchan", 1}, {"-mm", 2},  {"-o", -1},    {"-s", -1},
                {"-t", -1},     {"-texres", 1},  {"-type", 1}};
    *clamp = 0;
    for (p = skip_blanks(p, e); p < e && *p == '-'; p = skip_blanks(p, e)) {
        const char *q = token_end(p, e);
        int args = 0;
        for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
            if (token_is(p, q, opts[i].name)) args = opts[i].args;
        int is_clamp = token_is(p, q, "-clamp");
        p = q;
        for (int a = 0; args < 0 ? a < 3 : a < args; a++) {
            const char *v = skip_blanks(p, e), *w = token_end(v, e);
            float f;
            if (v == e || (args < 0 && !parse_number(v, w, &f))) break;
            if (is_clamp) *clamp = token_is_nocase(v, w, "on");
            p = w;
        }
    }
    rest_of_line(p, e, s, t);
}

static persp_status read_mtl(obj_reader *r, const char *libname, const char *text, size_t size)
{
    size_t lib = 0;
    persp_status st = pool_add(r, libname, strlen(libname), &lib);
    if (st != PERSP_OK) return st;
    obj_lines l;
    memset(&l, 0, sizeof l);
    l.ctx = r->ctx;
    l.display = libname; /* not the pool, which moves as it grows */
    if (lines_rewind(&l, text, size) != 0) return l.status;
    int cur = -1;
    const char *s, *e;
    size_t at;
    int got;
    while ((got = next_line(&l, &s, &e, &at)) == 1) {
        const char *p = skip_blanks(s, e), *q = token_end(p, e);
        if (p == e || *p == '#') continue;
        if (token_is_nocase(p, q, "newmtl")) {
            const char *a, *b;
            rest_of_line(q, e, &a, &b);
            /* A name given twice names one material (Assimp's reader). */
            cur = find_material(r, a, (size_t)(b - a));
            if (cur < 0 && (st = new_material(r, a, (size_t)(b - a), lib, &cur)) != PERSP_OK) break;
            continue;
        }
        if (cur < 0) continue;
        obj_mat *m = &r->mats[cur];
        int bad = 0;
        if (token_is_nocase(p, q, "kd"))
            bad = mtl_colour(q, e, m->kd) < 0;
        else if (token_is_nocase(p, q, "ks"))
            bad = mtl_colour(q, e, m->ks) < 0;
        else if (token_is_nocase(p, q, "ka"))
            bad = mtl_colour(q, e, m->ka) < 0;
        else if (token_is_nocase(p, q, "ke")) /* emission: the PBR extension of MTL, Blender's exporter */
            bad = mtl_colour(q, e, m->ke) < 0;
        else if (token_is_nocase(p, q, "ns")) {
            const char *a = skip_blanks(q, e), *b = token_end(a, e);
            bad = a < e && !parse_number(a, b, &m->ns);
        } else if (token_is_nocase(p, q, "map_kd")) {
            const char *a, *b;
            mtl_map(q, e, &m->clamp, &a, &b);
            if (a < b) {
                if ((st = pool_add(r, a, (size_t)(b - a), &m->tex)) != PERSP_OK) break;
                r->mats[cur].tex_line = at;
                r->mats[cur].lib = lib;
            }
        } else if (token_is_nocase(p, q, "map_ke")) {
            const char *a, *b;
            int clamp = 0;
            mtl_map(q, e, &clamp, &a, &b);
            if (a < b) {
                if ((st = pool_add(r, a, (size_t)(b - a), &m->glow)) != PERSP_OK) break;
                r->mats[cur].glow_line = at;
                r->mats[cur].lib = lib;
            }
        }
        /* d and Tr (transparency) and the other keys: persp draws opaque
         * surfaces and uses no other maps. A value that is not a number is
         * refused, as Assimp's reader refused it; the library's text is not
         * quoted (it is another file than the model). */
        if (bad) {
            st = persp__fail(r->ctx, PERSP_ERR_FORMAT,
                             "%s (via %s:%zu): malformed number after '%.*s'", r->display,
                             r->pool + lib, at, (int)PERSP_MIN(q - p, 16), p);
            break;
        }
    }
    persp__free(r->ctx, l.join);
    if (st != PERSP_OK) return st;
    return got < 0 ? l.status : PERSP_OK;
}

/* Reads one material library; 0 when it could not be read (why set). */
static persp_status load_library(obj_reader *r, const char *name, size_t n, const char **why,
                                 int *loaded)
{
    char raw[PERSP_PATH_MAX], rel[PERSP_PATH_MAX];
    *loaded = 0;
    if (n >= sizeof raw) {
        *why = "name too long";
        return PERSP_OK;
    }
    memcpy(raw, name, n);
    raw[n] = '\0';
    persp__model_clean_rel(raw, rel, sizeof rel);
    if (!r->base_dir) {
        *why = "no folder to read it from";
        return PERSP_OK;
    }
    char *text = NULL;
    size_t size = 0;
    persp_status st = persp__model_read_ref(r->ctx, r->base_dir, r->root, rel, &text, &size, why);
    if (st == PERSP_ERR_OUT_OF_MEMORY) return persp__obj_oom(r);
    if (st != PERSP_OK) return PERSP_OK;
    st = read_mtl(r, rel, text, size);
    persp__free(r->ctx, text);
    *loaded = st == PERSP_OK;
    return st;
}

static void warn_library(obj_reader *r, size_t line, const char *name, size_t n, const char *why)
{
    char q[PERSP_QUOTE_BYTES];
    r->libs_failed = 1;
    persp__warn(r->ctx, "%s:%zu: cannot read '%s' (%s); going on without it", r->display, line,
                persp__quote(name, n, q, sizeof q), why);
}

/* mtllib: the whole rest of the line names one library where that file
 * exists (Assimp's reading; names with spaces), else each blank-separated
 * name is one (the OBJ specification's list). A library that cannot be read
 * is a warning; then, as Assimp did, the model's own name with .mtl is
 * tried without one. */
static persp_status mtllib(obj_reader *r, const char *p, const char *e, size_t line)
{
    const char *s, *t;
    rest_of_line(p, e, &s, &t);
    if (s == t) return PERSP_OK;
    for (const char *c = s; c + 3 <= t; c++)
        if (c[0] == ':' && c[1] == '/' && c[2] == '/')
            return line_error(r, line, "the material library is named like a URL, not a file", NULL,
                              NULL);
    /* A statement repeated (some exporters write one per group) is read
     * once; past OBJ_LIBS_MAX different ones the rest are passed over, so
     * that a file of mtllib lines cannot make thousands of folder scans. */
    size_t n = (size_t)(t - s);
    /* nlibs counts one past OBJ_LIBS_MAX once the rest are passed over. */
    for (int i = 0; i < r->nlibs && i < OBJ_LIBS_MAX; i++)
        if (r->libs[i].len == n && !memcmp(r->pool + r->libs[i].name, s, n)) return PERSP_OK;
    if (r->nlibs == OBJ_LIBS_MAX) {
        persp__warn(r->ctx,
                    "%s:%zu: more than %d material library statements; the rest are passed over",
                    r->display, line, OBJ_LIBS_MAX);
        r->nlibs++;
        return PERSP_OK;
    }
    if (r->nlibs > OBJ_LIBS_MAX) return PERSP_OK;
    persp_status st = pool_add(r, s, n, &r->libs[r->nlibs].name);
    if (st != PERSP_OK) return st;
    r->libs[r->nlibs++].len = n;
    const char *why = "no such file or unreadable";
    int loaded = 0, any = 0;
    st = load_library(r, s, n, &why, &loaded);
    if (st != PERSP_OK) return st;
    if (loaded) return PERSP_OK;
    if (token_end(s, t) == t) {
        warn_library(r, line, s, (size_t)(t - s), why);
    } else {
        for (const char *a = s; a < t; a = skip_blanks(a, t)) {
            const char *b = token_end(a, t);
            why = "no such file or unreadable";
            if ((st = load_library(r, a, (size_t)(b - a), &why, &loaded)) != PERSP_OK) return st;
            if (!loaded) warn_library(r, line, a, (size_t)(b - a), why);
            any |= loaded;
            a = b;
        }
    }
    if (any || !r->base_dir) return PERSP_OK;
    char guess[PERSP_PATH_MAX];
    const char *dot = strrchr(r->main_name, '.');
    int stem = (int)(dot ? (size_t)(dot - r->main_name) : strlen(r->main_name));
    int gn = snprintf(guess, sizeof guess, "%.*s.mtl", stem, r->main_name);
    if (gn <= 0 || (size_t)gn >= sizeof guess) return PERSP_OK;
    if ((size_t)gn == (size_t)(t - s) && !memcmp(guess, s, (size_t)gn)) return PERSP_OK;
    return load_library(r, guess, (size_t)gn, &why, &loaded);
}

static void where_material(const void *user, const char *rel, char *out, size_t cap)
{
    const obj_reader *r = user;
    (void)rel;
    const obj_mat *m = r->where_mat;
    snprintf(out, cap, "%s (via %s:%zu)", r->display, r->pool + m->lib, r->where_glow ? m->glow_line : m->tex_line);
}

/* The scene material of a run: the record's (made once) or persp's default
 * for faces before any usemtl. */
static persp_status scene_material(obj_reader *r, int rec, int *out)
{
    persp_status st;
    if (rec < 0) {
        if (r->default_material < 0) {
            persp_material d = persp__material_default();
            if ((st = persp__scene_add_material(r->scene, &d, &r->default_material)) != PERSP_OK)
                return st;
        }
        *out = r->default_material;
        return PERSP_OK;
    }
    obj_mat *m = &r->mats[rec];
    if (m->scene < 0) {
        persp_material pm = persp__material_default();
        persp__model_set_colours(&pm, m->kd, m->ks, m->ka, m->ns);
        if (m->tex != NO_NAME) {
            r->where_mat = m;
            pm.texture = persp__model_texture_file(&r->refs, r->pool + m->name, r->pool + m->tex);
            /* The detail names the texture and the budget. */
            if (r->refs.out_of_memory) return PERSP_ERR_OUT_OF_MEMORY;
            if (pm.texture >= 0) {
                pm.env = PERSP_TEXENV_MODULATE;
                pm.sampler.wrap_s = pm.sampler.wrap_t =
                    m->clamp ? PERSP_WRAP_CLAMP_TO_EDGE : PERSP_WRAP_REPEAT;
            }
        }
        if (persp__model_set_emission(&pm, m->ke) && m->glow != NO_NAME) {
            r->where_mat = m;
            r->where_glow = 1;
            const int glow = persp__model_texture_file(&r->refs, r->pool + m->name, r->pool + m->glow);
            r->where_glow = 0;
            if (r->refs.out_of_memory) return PERSP_ERR_OUT_OF_MEMORY;
            persp__model_set_glow_map(r->ctx, r->display, r->pool + m->name, &pm, glow, PERSP_WRAP_REPEAT,
                                      PERSP_WRAP_REPEAT);
        }
        int index;
        if ((st = persp__scene_add_material(r->scene, &pm, &index)) != PERSP_OK) return st;
        r->mats[rec].scene = index;
    }
    *out = r->mats[rec].scene;
    return PERSP_OK;
}

/* ---------------------------------------------------------------- runs */

/* A group, object or material statement: a new run of faces starts at the
 * next face when the name changes (Assimp 5.2 made a mesh per group and
 * object, and a new one where the material changed after faces). */
static persp_status set_name(obj_reader *r, char *cur, int *has, const char *p, const char *e,
                             size_t line)
{
    const char *s, *t;
    rest_of_line(p, e, &s, &t);
    size_t n = (size_t)(t - s);
    if (n >= OBJ_NAME_MAX) return line_error(r, line, "a name longer than 1023 bytes", NULL, NULL);
    if (*has && strlen(cur) == n && !memcmp(cur, s, n)) return PERSP_OK;
    memcpy(cur, s, n);
    cur[n] = '\0';
    *has = 1;
    r->split = 1;
    return PERSP_OK;
}

static void free_run(obj_reader *r)
{
    persp__free(r->ctx, r->idx);
    persp__free(r->ctx, r->tuples);
    persp__free(r->ctx, r->table);
    r->idx = r->tuples = r->table = NULL;
    r->nidx = r->ntuples = r->tuples_cap = r->table_cap = 0;
    r->open = 0;
}

/* The run read so far becomes a scene mesh and a model part. */
static persp_status close_run(obj_reader *r)
{
    if (!r->open) return PERSP_OK;
    persp_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    persp_status st = PERSP_OK;
    if (r->nidx != r->idx_cap) {
        free_run(r);
        return persp__fail(r->ctx, PERSP_ERR_FORMAT, "%s: the file changed while it was read",
                           r->display);
    }
    /* The corners are all read: their hash is done before the vertices
     * are made. */
    persp__free(r->ctx, r->table);
    r->table = NULL;
    r->table_cap = 0;
    st = persp__obj_run_vertices(r, &mesh);
    if (st != PERSP_OK) {
        persp__mesh_free(r->ctx, &mesh);
        free_run(r);
        return st;
    }
    for (size_t c = 0; c < r->nidx; c++)
        r->idx[c] &= ~OWNER_BIT;
    /* The index array is handed over as it is: allocated at its final size. */
    mesh.indices = r->idx;
    mesh.index_count = r->nidx;
    mesh.has_normals = 1;
    mesh.no_uv = !r->run_uv;
    r->idx = NULL;
    r->vertices_used += mesh.vertex_count;
    int rec = r->run_mat;
    free_run(r);
    int mi = -1, material = -1;
    if ((st = persp__scene_add_mesh(r->scene, &mesh, &mi)) != PERSP_OK) return st;
    if ((st = scene_material(r, rec, &material)) != PERSP_OK) return st;
    persp_mat4 id = persp_mat4_identity();
    const char *name = rec >= 0 ? r->pool + r->mats[rec].name : "";
    return persp__model_add_part(r->scene, r->out, &r->part_cap, mi, material, name, &id, r->display);
}

static persp_status open_run(obj_reader *r, size_t line)
{
    persp_status st = close_run(r);
    if (st != PERSP_OK) return st;
    const obj_run *run = &r->runs[r->run];
    r->run_mat = -1;
    r->run_uv = 0;
    if (r->has_mtl) {
        size_t n = strlen(r->mtl);
        r->run_mat = find_material(r, r->mtl, n);
        /* A material no library defines: Assimp made an empty one of that
         * name (grey), not its default. Said once, at the first face that
         * uses it, unless a library could not be read (that was said). */
        if (r->run_mat < 0) {
            char q[PERSP_QUOTE_BYTES];
            if (!r->libs_failed)
                persp__warn(r->ctx, "%s:%zu: material '%s' is defined by no material library; drawn grey",
                            r->display, line, persp__quote(r->mtl, n, q, sizeof q));
            if ((st = new_material(r, r->mtl, n, 0, &r->run_mat)) != PERSP_OK) return st;
        }
    }
    r->file_normals = run->normals == 1 && !r->force_normals;
    size_t cap = 16;
    while (cap < run->corners + run->corners / 3)
        cap *= 2;
    r->idx = persp__alloc(r->ctx, 3 * run->tris * sizeof *r->idx);
    r->idx_cap = 3 * run->tris;
    r->table = persp__calloc(r->ctx, cap, sizeof *r->table);
    if (!r->idx || !r->table) {
        free_run(r);
        return persp__obj_oom(r);
    }
    r->table_cap = cap;
    r->open = 1;
    return PERSP_OK;
}

/* ---------------------------------------------------------------- faces */

static uint32_t tuple_hash(uint32_t v, uint32_t t, uint32_t n)
{
    uint64_t h = (uint64_t)v * 0x9e3779b97f4a7c15ull ^ (uint64_t)t * 0xc2b2ae3d27d4eb4full ^
                 (uint64_t)n * 0x165667b19e3779f9ull;
    return (uint32_t)(h ^ (h >> 32));
}

static persp_status corner_tuple(obj_reader *r, uint32_t v, uint32_t t, uint32_t n, uint32_t *out)
{
    size_t slot = tuple_hash(v, t, n) & (r->table_cap - 1);
    for (;; slot = (slot + 1) & (r->table_cap - 1)) {
        uint32_t e = r->table[slot];
        if (!e) break;
        const uint32_t *k = r->tuples + 3 * (size_t)(e - 1);
        if (k[0] == v && k[1] == t && k[2] == n) {
            *out = e - 1;
            return PERSP_OK;
        }
    }
    if (r->ntuples >= PERSP_SCENE_MAX_VERTICES || r->ntuples >= r->max_vertices - r->vertices_used)
        return persp__obj_too_large(r);
    if (persp__grow(r->ctx, (void **)&r->tuples, &r->tuples_cap, 3 * (r->ntuples + 1),
                    sizeof *r->tuples) != PERSP_OK)
        return persp__obj_oom(r);
    uint32_t *k = r->tuples + 3 * r->ntuples;
    k[0] = v, k[1] = t, k[2] = n;
    r->table[slot] = (uint32_t)++r->ntuples;
    *out = (uint32_t)(r->ntuples - 1);
    return PERSP_OK;
}

/* An index of a face corner: 1-based, or negative counting back from the
 * latest (OBJ specification, "Referencing vertex data"). */
static persp_status resolve(obj_reader *r, size_t line, const char *p, const char *q, size_t count,
                            const char *what, uint32_t *out)
{
    const char *s = p;
    int neg = 0;
    if (s < q && (*s == '-' || *s == '+')) neg = *s++ == '-';
    if (s == q) return line_error(r, line, "malformed face corner", p, q);
    unsigned long long v = 0;
    for (; s < q; s++) {
        if (*s < '0' || *s > '9') return line_error(r, line, "malformed face corner", p, q);
        if (v < (1ull << 40)) v = v * 10 + (unsigned long long)(*s - '0');
    }
    if (v == 0) {
        char m[96];
        snprintf(m, sizeof m, "%s index 0 (OBJ indices start at 1)", what);
        return line_error(r, line, m, NULL, NULL);
    }
    if (v > count) {
        char m[160];
        snprintf(m, sizeof m, "%s index %s%llu out of range (%zu defined before this line)", what,
                 neg ? "-" : "", v, count);
        return line_error(r, line, m, NULL, NULL);
    }
    *out = (uint32_t)(neg ? count - v : v - 1);
    return PERSP_OK;
}

static int corner_has_normal(const char *p, const char *q)
{
    const char *a = memchr(p, '/', (size_t)(q - p));
    const char *b = a ? memchr(a + 1, '/', (size_t)(q - a - 1)) : NULL;
    return b && b + 1 < q;
}

/* Ear clipping of a polygon of n > 4 corners in the plane it is flattest
 * in, as Assimp's triangulation does for polygons; corners that leave no ear
 * (a self-crossing outline) finish as a fan. Writes n - 2 triangles. */
static void clip_ears(obj_reader *r, int n)
{
    float nx = 0, ny = 0, nz = 0;
    for (int i = 0; i < n; i++) {
        const float *a = r->pos + 3 * (size_t)r->poly_v[i];
        const float *b = r->pos + 3 * (size_t)r->poly_v[(i + 1) % n];
        nx += (a[1] - b[1]) * (a[2] + b[2]);
        ny += (a[2] - b[2]) * (a[0] + b[0]);
        nz += (a[0] - b[0]) * (a[1] + b[1]);
    }
    /* Newell's normal; dropping its largest axis keeps the polygon's area,
     * the sign keeps its winding counter-clockwise in the plane. */
    int ax =
        fabsf(nx) > fabsf(ny) ? (fabsf(nx) > fabsf(nz) ? 0 : 2) : (fabsf(ny) > fabsf(nz) ? 1 : 2);
    int u = (ax + 1) % 3, v = (ax + 2) % 3;
    float sign = (ax == 0 ? nx : ax == 1 ? ny : nz) < 0 ? -1.0f : 1.0f;
    int *next = r->link, *prev = r->link + n;
    for (int i = 0; i < n; i++) {
        const float *a = r->pos + 3 * (size_t)r->poly_v[i];
        r->flat[2 * i] = a[u];
        r->flat[2 * i + 1] = a[v] * sign;
        next[i] = (i + 1) % n;
        prev[i] = (i + n - 1) % n;
    }
    int left = n, cur = 0, ntri = 0, miss = 0;
    while (left > 3 && miss < left) {
        int a = prev[cur], b = cur, c = next[cur];
        const float *pa = r->flat + 2 * a, *pb = r->flat + 2 * b, *pc = r->flat + 2 * c;
        float cross = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
        /* A straight corner may go (a triangle of no area); a reflex one
         * may not. */
        int ear = cross >= 0;
        for (int k = next[c]; ear && k != a; k = next[k]) {
            const float *p = r->flat + 2 * k;
            /* Corners at the place of the ear's own (the two sides of a cut
             * joining an outline to a hole, as in Assimp's
             * concave_polygon.obj) do not block it; others block it when
             * inside or on its sides (a reflex corner touching the cut). */
            if ((p[0] == pa[0] && p[1] == pa[1]) || (p[0] == pb[0] && p[1] == pb[1]) ||
                (p[0] == pc[0] && p[1] == pc[1]))
                continue;
            float d0 = (pb[0] - pa[0]) * (p[1] - pa[1]) - (pb[1] - pa[1]) * (p[0] - pa[0]);
            float d1 = (pc[0] - pb[0]) * (p[1] - pb[1]) - (pc[1] - pb[1]) * (p[0] - pb[0]);
            float d2 = (pa[0] - pc[0]) * (p[1] - pc[1]) - (pa[1] - pc[1]) * (p[0] - pc[0]);
            if (d0 >= 0 && d1 >= 0 && d2 >= 0) ear = 0;
        }
        if (!ear) {
            cur = next[cur];
            miss++;
            continue;
        }
        r->tri[3 * ntri] = a, r->tri[3 * ntri + 1] = b, r->tri[3 * ntri + 2] = c;
        ntri++;
        next[a] = c, prev[c] = a;
        left--;
        cur = c;
        miss = 0;
    }
    /* The rest (a triangle, or an outline without ears) as a fan. */
    int start = cur;
    for (int k = next[start]; next[k] != start; k = next[k]) {
        r->tri[3 * ntri] = start, r->tri[3 * ntri + 1] = k, r->tri[3 * ntri + 2] = next[k];
        ntri++;
    }
}

/* The triangles of a polygon of n corners into the run. A quad is cut from
 * its concave corner if it has one (Assimp's quad rule); a larger polygon
 * by ear clipping. The last triangle that holds a polygon corner stands for
 * it in the normals (Assimp kept one vertex per polygon corner, carrying
 * the normal of the last triangle written to it). */
static void emit_polygon(obj_reader *r, int n)
{
    int ntri = n - 2;
    if (n == 3) {
        r->tri[0] = 0, r->tri[1] = 1, r->tri[2] = 2;
    } else if (n == 4) {
        int start = 0;
        for (int i = 0; i < 4; i++) {
            const float *v0 = r->pos + 3 * (size_t)r->poly_v[(i + 3) % 4];
            const float *v1 = r->pos + 3 * (size_t)r->poly_v[(i + 2) % 4];
            const float *v2 = r->pos + 3 * (size_t)r->poly_v[(i + 1) % 4];
            const float *v = r->pos + 3 * (size_t)r->poly_v[i];
            float left[3], diag[3], right[3];
            for (int k = 0; k < 3; k++)
                left[k] = v0[k] - v[k], diag[k] = v1[k] - v[k], right[k] = v2[k] - v[k];
            persp__obj_normalize(left), persp__obj_normalize(diag), persp__obj_normalize(right);
            float angle = acosf(left[0] * diag[0] + left[1] * diag[1] + left[2] * diag[2]) +
                          acosf(right[0] * diag[0] + right[1] * diag[1] + right[2] * diag[2]);
            if (angle > 3.14159265358979f) {
                start = i;
                break;
            }
        }
        r->tri[0] = start, r->tri[1] = (start + 1) % 4, r->tri[2] = (start + 2) % 4;
        r->tri[3] = start, r->tri[4] = (start + 2) % 4, r->tri[5] = (start + 3) % 4;
    } else if (n <= OBJ_EAR_MAX) {
        clip_ears(r, n);
    } else {
        /* Ear clipping takes up to n^3 steps: beyond OBJ_EAR_MAX corners a
         * polygon (a disc's cap, convex) is cut as a fan. */
        for (int t = 0; t < ntri; t++)
            r->tri[3 * t] = 0, r->tri[3 * t + 1] = t + 1, r->tri[3 * t + 2] = t + 2;
    }
    memset(r->seen, 0, (size_t)n);
    size_t base = r->nidx;
    for (int t = ntri - 1; t >= 0; t--)
        for (int k = 2; k >= 0; k--) {
            int c = r->tri[3 * t + k];
            uint32_t e = r->poly[c];
            if (!r->seen[c]) e |= OWNER_BIT, r->seen[c] = 1;
            r->idx[base + 3 * (size_t)t + (size_t)k] = e;
        }
    r->nidx += 3 * (size_t)ntri;
    for (int t = 0; !r->area && t < ntri; t++)
        r->area = persp__model_triangle_has_area(r->pos + 3 * (size_t)r->poly_v[r->tri[3 * t]],
                                                 r->pos + 3 * (size_t)r->poly_v[r->tri[3 * t + 1]],
                                                 r->pos + 3 * (size_t)r->poly_v[r->tri[3 * t + 2]]);
}

static persp_status face(obj_reader *r, const char *p, const char *e, size_t line)
{
    size_t n = count_tokens(p, e);
    /* Fewer than three corners draw nothing (Assimp dropped them with the
     * points and lines); counted for one warning a file. */
    if (n < 3) {
        if (r->pass == 1 && !r->short_faces++) r->short_line = line;
        return PERSP_OK;
    }
    persp_status st;
    if (r->pass == 1) {
        if (r->split || r->nruns == 0) {
            if (r->nruns >= PERSP_SCENE_MAX_OBJECTS)
                return persp__fail(r->ctx, PERSP_ERR_TOO_LARGE, "%s: more than %d mesh instances",
                                   r->display, PERSP_SCENE_MAX_OBJECTS);
            if (persp__grow(r->ctx, (void **)&r->runs, &r->runs_cap, r->nruns + 1,
                            sizeof *r->runs) != PERSP_OK)
                return persp__obj_oom(r);
            memset(&r->runs[r->nruns++], 0, sizeof *r->runs);
            r->split = 0;
        }
        obj_run *run = &r->runs[r->nruns - 1];
        if (n - 2 > PERSP_SCENE_MAX_INDICES / 3 - run->tris) return persp__obj_too_large(r);
        run->tris += n - 2;
        run->corners += n;
        if (n > r->max_poly) r->max_poly = n;
        int with = 0;
        for (p = skip_blanks(p, e); p < e; p = skip_blanks(p, e)) {
            const char *q = token_end(p, e);
            with += corner_has_normal(p, q);
            p = q;
        }
        int kind = with == 0 ? 0 : (size_t)with == n ? 1 : 2;
        if (run->tris == n - 2)
            run->normals = kind;
        else if (run->normals != kind)
            run->normals = 2;
        return PERSP_OK;
    }
    if (n > r->max_poly)
        return line_error(r, line, "the file changed while it was read", NULL, NULL);
    if (r->split || !r->open) {
        if (r->run >= r->nruns)
            return line_error(r, line, "the file changed while it was read", NULL, NULL);
        if ((st = open_run(r, line)) != PERSP_OK) return st;
        r->run++;
        r->split = 0;
    }
    int k = 0;
    for (p = skip_blanks(p, e); p < e; p = skip_blanks(p, e), k++) {
        const char *q = token_end(p, e);
        const char *s1 = memchr(p, '/', (size_t)(q - p));
        const char *s2 = s1 ? memchr(s1 + 1, '/', (size_t)(q - s1 - 1)) : NULL;
        uint32_t v, t = NO_INDEX, nn = NO_INDEX;
        if ((st = resolve(r, line, p, s1 ? s1 : q, r->iv, "vertex", &v)) != PERSP_OK) return st;
        if (s1) {
            const char *te = s2 ? s2 : q;
            if (te > s1 + 1 &&
                (st = resolve(r, line, s1 + 1, te, r->ivt, "texture coordinate", &t)) != PERSP_OK)
                return st;
            r->run_uv |= t != NO_INDEX;
        }
        if (s2 && s2 + 1 < q) {
            if (memchr(s2 + 1, '/', (size_t)(q - s2 - 1)))
                return line_error(r, line, "malformed face corner", p, q);
            if ((st = resolve(r, line, s2 + 1, q, r->ivn, "normal", &nn)) != PERSP_OK) return st;
        }
        if (!r->file_normals) nn = NO_INDEX;
        if ((st = corner_tuple(r, v, t, nn, &r->poly[k])) != PERSP_OK) return st;
        r->poly_v[k] = v;
        p = q;
    }
    if (r->nidx + 3 * (size_t)(k - 2) > r->idx_cap)
        return line_error(r, line, "the file changed while it was read", NULL, NULL);
    emit_polygon(r, k);
    return PERSP_OK;
}

/* ------------------------------------------------------------- statements */

static persp_status vertex(obj_reader *r, const char *p, const char *e, size_t line)
{
    float v[7];
    int n = 0;
    for (p = skip_blanks(p, e); p < e; p = skip_blanks(p, e)) {
        const char *q = token_end(p, e);
        if (n == 7) return line_error(r, line, "expected 3, 4 or 6 numbers after 'v'", NULL, NULL);
        if (r->pass == 2 && !parse_number(p, q, &v[n]))
            return line_error(r, line, "malformed number", p, q);
        n++;
        p = q;
    }
    if (n != 3 && n != 4 && n != 6)
        return line_error(r, line, "expected 3, 4 or 6 numbers after 'v'", NULL, NULL);
    if (r->pass == 1) {
        if (r->nv >= PERSP_SCENE_MAX_INDICES) return persp__obj_too_large(r);
        r->nv++;
        r->colours |= n == 6;
        return PERSP_OK;
    }
    if (n == 4) {
        /* Homogeneous "v x y z w" (OBJ specification): the point is x/w. */
        if (v[3] == 0.0f) return line_error(r, line, "a vertex with w = 0", NULL, NULL);
        for (int k = 0; k < 3; k++)
            v[k] /= v[3];
    }
    if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]))
        return line_error(r, line, "a vertex position is not finite", NULL, NULL);
    if (r->iv >= r->nv)
        return line_error(r, line, "the file changed while it was read", NULL, NULL);
    memcpy(r->pos + 3 * r->iv, v, 3 * sizeof *v);
    if (r->canon) persp__obj_canon_add(r, r->iv);
    if (r->col) {
        float *c = r->col + 3 * r->iv;
        /* Vertices without a colour in a file with colours: white. */
        c[0] = n == 6 ? v[3] : 1.0f, c[1] = n == 6 ? v[4] : 1.0f, c[2] = n == 6 ? v[5] : 1.0f;
    }
    r->iv++;
    return PERSP_OK;
}

static persp_status numbers(obj_reader *r, const char *p, const char *e, size_t line, int lo,
                            int hi, const char *what, float *v)
{
    int n = 0;
    for (p = skip_blanks(p, e); p < e; p = skip_blanks(p, e)) {
        const char *q = token_end(p, e);
        if (n == hi) break;
        if (!parse_number(p, q, &v[n])) return line_error(r, line, "malformed number", p, q);
        n++;
        p = q;
    }
    if (n < lo || p < e) return line_error(r, line, what, NULL, NULL);
    return PERSP_OK;
}

static persp_status statement(obj_reader *r, const char *s, const char *e, size_t line)
{
    const char *p = skip_blanks(s, e), *q = token_end(p, e);
    if (p == e || *p == '#') return PERSP_OK;
    if (token_is(p, q, "v")) return vertex(r, q, e, line);
    if (token_is(p, q, "f")) return face(r, q, e, line);
    persp_status st;
    if (token_is(p, q, "vt")) {
        float v[3] = {0, 0, 0};
        if (r->pass == 1) {
            if (r->nvt >= PERSP_SCENE_MAX_INDICES) return persp__obj_too_large(r);
            r->nvt++;
            return PERSP_OK;
        }
        if ((st = numbers(r, q, e, line, 1, 3, "expected 1 to 3 numbers after 'vt'", v)) !=
            PERSP_OK)
            return st;
        if (r->ivt >= r->nvt)
            return line_error(r, line, "the file changed while it was read", NULL, NULL);
        r->tc[2 * r->ivt] = v[0], r->tc[2 * r->ivt + 1] = v[1];
        r->ivt++;
        return PERSP_OK;
    }
    if (token_is(p, q, "vn")) {
        float v[3];
        if ((st = numbers(r, q, e, line, 3, 3, "expected 3 numbers after 'vn'", v)) != PERSP_OK)
            return st;
        if (r->pass == 1) {
            if (r->nvn >= PERSP_SCENE_MAX_INDICES) return persp__obj_too_large(r);
            r->nvn++;
            /* Zero or non-finite normals (some exporters write them) leave
             * a surface unlit: the model's normals are made afresh, as the
             * Assimp path did. */
            if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]) ||
                !(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 1e-12f))
                r->bad_vn = 1;
            return PERSP_OK;
        }
        if (r->ivn >= r->nvn)
            return line_error(r, line, "the file changed while it was read", NULL, NULL);
        memcpy(r->nrm + 3 * r->ivn++, v, sizeof v);
        return PERSP_OK;
    }
    if (token_is(p, q, "g")) return set_name(r, r->group, &r->has_group, q, e, line);
    if (token_is(p, q, "o")) return set_name(r, r->object, &r->has_object, q, e, line);
    if (token_is(p, q, "usemtl")) {
        /* Only a change of material after faces starts a run (Assimp). */
        int had = r->split;
        int open_with_faces = r->pass == 1 ? r->nruns > 0 : r->open;
        st = set_name(r, r->mtl, &r->has_mtl, q, e, line);
        if (!open_with_faces) r->split = had;
        return st;
    }
    if (token_is(p, q, "mtllib")) return r->pass == 1 ? mtllib(r, q, e, line) : PERSP_OK;
    /* s (smoothing groups: Assimp's normals ignored them too), l and p
     * (lines and points: persp draws triangles), and the statements of
     * curves and surfaces or other programs' extensions are passed over,
     * as Assimp did. */
    return PERSP_OK;
}

static persp_status run_pass(obj_reader *r, obj_lines *l, const char *data, size_t size)
{
    if (lines_rewind(l, data, size) != 0) return l->status;
    r->has_group = r->has_object = r->has_mtl = 0;
    r->split = 0;
    r->run = 0;
    const char *s, *e;
    size_t line;
    int got;
    while ((got = next_line(l, &s, &e, &line)) == 1) {
        persp_status st = statement(r, s, e, line);
        if (st != PERSP_OK) return st;
    }
    return got < 0 ? l->status : PERSP_OK;
}

static void free_reader(obj_reader *r)
{
    free_run(r);
    void *blocks[] = {r->runs, r->pos,   r->col,      r->tc,    r->nrm,  r->mats,
                      r->pool, r->poly,  r->poly_v,   r->tri,   r->link, r->flat,
                      r->seen, r->canon, r->group_of, r->ctable, r->mat_table};
    for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; i++)
        persp__free(r->ctx, blocks[i]);
}

/* No faces: when the file's first bytes are another model format's (a
 * GLB named .obj), that is the cause to name. */
static persp_status nothing_to_draw(obj_reader *r, obj_lines *l, const char *data, size_t size)
{
    char head[4096];
    size_t n = size < sizeof head ? size : sizeof head;
    if (l->f) n = fseek(l->f, 0, SEEK_SET) == 0 ? fread(head, 1, sizeof head, l->f) : 0;
    else if (n) memcpy(head, data, n);
    const char *ext = NULL, *other = persp__model_content_format(head, n, &ext);
    if (other)
        return persp__fail(r->ctx, PERSP_ERR_FORMAT,
                           "%s: the content is not that of an OBJ file (it looks like %s: rename it .%s)",
                           r->display, other, ext);
    return persp__fail(r->ctx, PERSP_ERR_FORMAT, "%s: the model has no triangles to draw", r->display);
}

static persp_status load(obj_reader *r, obj_lines *l, const char *data, size_t size)
{
    r->pass = 1;
    persp_status st = run_pass(r, l, data, size);
    if (st != PERSP_OK) return st;
    if (r->nruns == 0) return nothing_to_draw(r, l, data, size);
    for (size_t i = 0; i < r->nruns; i++)
        if (r->runs[i].normals == 2 || (r->bad_vn && r->runs[i].normals)) r->force_normals = 1;
    size_t mp = r->max_poly;
    r->pos = persp__alloc(r->ctx, (r->nv ? r->nv : 1) * 3 * sizeof *r->pos);
    r->tc = persp__alloc(r->ctx, (r->nvt ? r->nvt : 1) * 2 * sizeof *r->tc);
    r->nrm = persp__alloc(r->ctx, (r->nvn ? r->nvn : 1) * 3 * sizeof *r->nrm);
    if (r->colours) r->col = persp__alloc(r->ctx, (r->nv ? r->nv : 1) * 3 * sizeof *r->col);
    r->poly = persp__alloc(r->ctx, mp * sizeof *r->poly);
    r->poly_v = persp__alloc(r->ctx, mp * sizeof *r->poly_v);
    r->tri = persp__alloc(r->ctx, 3 * mp * sizeof *r->tri);
    r->link = persp__alloc(r->ctx, 2 * mp * sizeof *r->link);
    r->flat = persp__alloc(r->ctx, 2 * mp * sizeof *r->flat);
    r->seen = persp__alloc(r->ctx, mp);
    if (!r->pos || !r->tc || !r->nrm || (r->colours && !r->col) || !r->poly || !r->poly_v ||
        !r->tri || !r->link || !r->flat || !r->seen)
        return persp__obj_oom(r);
    int generate = 0;
    for (size_t i = 0; i < r->nruns; i++)
        generate |= r->runs[i].normals != 1 || r->force_normals;
    if (generate && (st = persp__obj_canon_init(r)) != PERSP_OK) return st;
    if (r->short_faces)
        persp__warn(r->ctx, "%s:%zu: %zu face%s of fewer than three corners dropped (the first here)", r->display,
                    r->short_line, r->short_faces, r->short_faces == 1 ? "" : "s");
    r->pass = 2;
    if ((st = run_pass(r, l, data, size)) != PERSP_OK) return st;
    /* The text is read: the window and the hash that found equal positions
     * are done before the last mesh is made. */
    persp__free(r->ctx, r->ctable);
    r->ctable = NULL;
    persp__free(r->ctx, l->buf);
    l->buf = NULL;
    if ((st = close_run(r)) != PERSP_OK) return st;
    if (!r->area)
        return persp__fail(r->ctx, PERSP_ERR_FORMAT,
                           "%s: the model's triangles all have zero area (nothing to draw)",
                           r->display);
    if (!(r->out->bbox_min[0] <= r->out->bbox_max[0]))
        return persp__fail(r->ctx, PERSP_ERR_FORMAT,
                           "%s: the model's transformed vertices are not finite", r->display);
    return PERSP_OK;
}

persp_status persp__obj_load(persp_scene *scene, const char *data, size_t size, const char *name,
                             const char *base_dir, persp_texcache *cache, size_t max_vertices,
                             persp_model *out)
{
    persp_context *ctx = scene->ctx;
    memset(out, 0, sizeof *out);
    obj_reader *r = persp__calloc(ctx, 1, sizeof *r);
    const char *display = name ? name : "<model>";
    if (!r) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", display);
    r->scene = scene;
    r->ctx = ctx;
    r->display = display;
    r->main_name = persp__path_base(display);
    r->base_dir = base_dir;
    r->root = scene->load_root;
    r->out = out;
    r->max_vertices = max_vertices ? max_vertices : PERSP_SCENE_MAX_VERTICES;
    r->crease_deg = persp__model_crease(scene->load_desc);
    r->default_material = -1;
    r->refs.scene = scene;
    r->refs.cache = cache;
    r->refs.display = display;
    r->refs.base_dir = base_dir;
    r->refs.root = scene->load_root;
    r->refs.where = where_material;
    r->refs.where_user = r;
    for (int k = 0; k < 3; k++)
        out->bbox_min[k] = INFINITY, out->bbox_max[k] = -INFINITY;
    obj_lines l;
    memset(&l, 0, sizeof l);
    l.ctx = ctx;
    l.display = display;
    persp_status st = PERSP_OK;
    if (!data) {
        size_t file_size = 0;
        st = persp__open_stream_inside(ctx, scene->load_root, display, &l.f, &file_size);
        /* A window of a chunk (a small file: itself), grown only for a
         * longer line (refill). */
        l.cap = file_size < OBJ_CHUNK ? file_size + 1 : OBJ_CHUNK;
        if (st == PERSP_OK && !(l.buf = persp__alloc(ctx, l.cap)))
            st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", display);
    }
    if (st == PERSP_OK) st = load(r, &l, data ? data : "", size);
    if (l.f) fclose(l.f);
    persp__free(ctx, l.buf);
    persp__free(ctx, l.join);
    free_reader(r);
    persp__free(ctx, r);
    /* Files worked around left their failures in the detail: warnings. */
    if (st == PERSP_OK)
        persp__clear_error(ctx);
    else
        persp__model_free(ctx, out);
    return st;
}
