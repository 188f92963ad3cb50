/*
 * Wavefront MTL reader (the subset persp uses): newmtl, Ka, Kd, Ks, Ns, d,
 * Tr and map_Kd. Other statements of the format that do not change how
 * persp draws (illum, Ni, Ke, the other maps, ...) are accepted and
 * skipped; anything else is an error, so typos do not pass silently.
 */
#include "core/internal.h"
#include "io/obj.h"
#include "io/text.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------ texture cache */

persp_status persp__texcache_load(persp_scene *scene, persp_texcache *cache, const char *path, int *index)
{
    persp_context *ctx = scene->ctx;
    if (cache)
        for (size_t i = 0; i < cache->count; i++)
            if (strcmp(cache->entries[i].path, path) == 0) {
                *index = cache->entries[i].index;
                return PERSP_OK;
            }
    persp_image img;
    memset(&img, 0, sizeof img);
    persp_status st = persp_image_load(ctx, path, &img);
    if (st != PERSP_OK) return st;
    persp_texture *tex = NULL;
    st = persp_texture_create(ctx, &img, &tex);
    persp_image_free(ctx, &img);
    if (st != PERSP_OK) return st;
    st = persp__scene_add_texture(scene, tex, index);
    if (st != PERSP_OK || !cache) return st;
    if (persp__grow(ctx, (void **)&cache->entries, &cache->cap, cache->count + 1,
                    sizeof *cache->entries) != PERSP_OK)
        return PERSP_OK; /* the cache is an optimisation only */
    size_t len = strlen(path);
    char *copy = persp__alloc(ctx, len + 1);
    if (!copy) return PERSP_OK;
    memcpy(copy, path, len + 1);
    cache->entries[cache->count].path = copy;
    cache->entries[cache->count].index = *index;
    cache->count++;
    return PERSP_OK;
}

void persp__texcache_free(persp_context *ctx, persp_texcache *cache)
{
    if (!cache) return;
    for (size_t i = 0; i < cache->count; i++) persp__free(ctx, cache->entries[i].path);
    persp__free(ctx, cache->entries);
    memset(cache, 0, sizeof *cache);
}

/* ------------------------------------------------------------------ library */

int persp__mtl_find(const persp_mtl_lib *lib, const char *name, size_t len)
{
    for (size_t i = lib->count; i-- > 0;)
        if (strlen(lib->entries[i].name) == len && memcmp(lib->entries[i].name, name, len) == 0) return (int)i;
    return -1;
}

void persp__mtl_lib_free(persp_context *ctx, persp_mtl_lib *lib)
{
    if (!lib) return;
    persp__free(ctx, lib->entries);
    memset(lib, 0, sizeof *lib);
}

/* ------------------------------------------------------------------- parser */

typedef struct mtl_parser {
    persp_scene *scene;
    persp_context *ctx;
    const char *name, *base_dir;
    persp_mtl_lib *lib;
    persp_texcache *cache;
    persp_line_cursor cur;
    int current;         /* scene material index being defined, -1 before newmtl */
    persp_material mat;  /* working copy, stored at each newmtl and at the end */
} mtl_parser;

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static persp_status fail(mtl_parser *p, persp_status st, size_t col, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    persp_status r = persp__text_failv(p->ctx, st, p->name, p->cur.lineno, col, fmt, ap);
    va_end(ap);
    return r;
}

/* Statements of the format accepted and skipped: they describe effects
 * (emission, refraction, bump, ...) that persp does not draw. */
static int ignored_statement(const char *tok, size_t len)
{
    static const char *const names[] = {"illum", "Ni", "Ke", "Tf", "map_Ka", "map_Ks", "map_Ns", "map_d",
                                        "map_bump", "map_Bump", "bump", "disp", "decal", "refl", "sharpness",
                                        "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor", "norm", "map_Pr",
                                        "map_Pm", "map_Ps", "map_Ke", "map_Kn"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (persp__keyword_is(tok, len, names[i])) return 1;
    return 0;
}

static persp_status store_current(mtl_parser *p)
{
    if (p->current >= 0) p->scene->materials[p->current] = p->mat;
    return PERSP_OK;
}

static persp_status parse_numbers(mtl_parser *p, const char *kw, size_t kwlen, float *out, int min, int max,
                                  int *count)
{
    int n = 0;
    for (;;) {
        const char *tok;
        size_t col, len = persp__token(&p->cur, &tok, &col);
        if (len == 0) break;
        if (n == max)
            return fail(p, PERSP_ERR_FORMAT, col, "expected at most %d numbers after '%.*s'", max, (int)kwlen, kw);
        if (!persp__parse_float(tok, len, &out[n]))
            return fail(p, PERSP_ERR_FORMAT, col, "expected a finite number after '%.*s', found '%.*s'", (int)kwlen,
                        kw, (int)(len > 32 ? 32 : len), tok);
        n++;
    }
    if (n < min)
        return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected %s%d number%s after '%.*s'",
                    min == max ? "" : "at least ", min, min == 1 ? "" : "s", (int)kwlen, kw);
    *count = n;
    return PERSP_OK;
}

static persp_status parse_color(mtl_parser *p, const char *kw, size_t kwlen, float rgb[3])
{
    persp__skip_blanks(&p->cur);
    const char *rest = p->cur.line + p->cur.pos;
    size_t restlen = p->cur.len - p->cur.pos;
    if ((restlen >= 8 && memcmp(rest, "spectral", 8) == 0) || (restlen >= 3 && memcmp(rest, "xyz", 3) == 0))
        return fail(p, PERSP_ERR_UNSUPPORTED, persp__column(&p->cur),
                    "only RGB colours are supported after '%.*s'", (int)kwlen, kw);
    float v[3];
    int n = 0;
    persp_status st = parse_numbers(p, kw, kwlen, v, 1, 3, &n);
    if (st != PERSP_OK) return st;
    if (n == 2) return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected 1 or 3 numbers after '%.*s'",
                            (int)kwlen, kw);
    for (int c = 0; c < 3; c++) rgb[c] = v[n == 1 ? 0 : c];
    return PERSP_OK;
}

/* map_Kd [-options] file: the options of the MTL format and how many
 * arguments each takes; the file name is the rest of the line. */
static persp_status parse_map(mtl_parser *p)
{
    static const struct {
        const char *name;
        int args;
    } opts[] = {{"-blendu", 1}, {"-blendv", 1}, {"-clamp", 1}, {"-cc", 1},     {"-bm", 1},    {"-mm", 2},
                {"-o", 3},      {"-s", 3},      {"-t", 3},      {"-texres", 1}, {"-imfchan", 1}, {"-boost", 1}};
    for (;;) {
        persp__skip_blanks(&p->cur);
        if (p->cur.pos >= p->cur.len || p->cur.line[p->cur.pos] != '-') break;
        const char *tok;
        size_t col, len = persp__token(&p->cur, &tok, &col);
        int args = -1;
        for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
            if (persp__keyword_is(tok, len, opts[i].name)) args = opts[i].args;
        if (args < 0)
            return fail(p, PERSP_ERR_FORMAT, col, "unknown map_Kd option '%.*s'", (int)(len > 32 ? 32 : len), tok);
        /* -o, -s, -t take 1 to 3 numbers: stop at the first non-number. */
        for (int a = 0; a < args; a++) {
            persp_line_cursor save = p->cur;
            const char *arg;
            size_t acol, alen = persp__token(&p->cur, &arg, &acol);
            float dummy;
            if (alen == 0) return fail(p, PERSP_ERR_FORMAT, acol, "expected an argument after '%.*s'", (int)len, tok);
            if (args == 3 && a > 0 && !persp__parse_float(arg, alen, &dummy)) {
                p->cur = save;
                break;
            }
        }
    }
    size_t col = persp__column(&p->cur);
    size_t start = p->cur.pos, end = p->cur.len;
    while (end > start && (p->cur.line[end - 1] == ' ' || p->cur.line[end - 1] == '\t')) end--;
    if (end == start) return fail(p, PERSP_ERR_FORMAT, col, "expected a file name after 'map_Kd'");
    char rel[PERSP_PATH_MAX], path[PERSP_PATH_MAX];
    if (end - start >= sizeof rel) return fail(p, PERSP_ERR_FORMAT, col, "file name too long");
    memcpy(rel, p->cur.line + start, end - start);
    rel[end - start] = '\0';
    if (memchr(rel, '\0', end - start)) return fail(p, PERSP_ERR_FORMAT, col, "file name contains a NUL byte");
    p->cur.pos = p->cur.len;
    p->mat.env = PERSP_TEXENV_MODULATE;
    if (!p->base_dir) return PERSP_OK;
    if (!persp__path_join(p->base_dir, rel, path, sizeof path))
        return fail(p, PERSP_ERR_FORMAT, col, "file name too long");
    int index = -1;
    persp_status st = persp__texcache_load(p->scene, p->cache, path, &index);
    if (st != PERSP_OK) {
        char inner[PERSP_ERRMSG_BYTES];
        snprintf(inner, sizeof inner, "%s", persp_context_error(p->ctx));
        return fail(p, st, col, "cannot load texture '%s': %s", rel, inner);
    }
    p->mat.texture = index;
    return PERSP_OK;
}

static persp_status statement(mtl_parser *p, const char *kw, size_t kwlen, size_t kwcol)
{
    persp_status st;
    int n;
    if (persp__keyword_is(kw, kwlen, "newmtl")) {
        const char *tok;
        size_t col, len = persp__token(&p->cur, &tok, &col);
        if (len == 0) return fail(p, PERSP_ERR_FORMAT, col, "expected a material name after 'newmtl'");
        if (len >= PERSP_MTL_NAME_MAX)
            return fail(p, PERSP_ERR_FORMAT, col, "material name longer than %d bytes", PERSP_MTL_NAME_MAX - 1);
        const char *extra;
        size_t ecol;
        if (persp__token(&p->cur, &extra, &ecol))
            return fail(p, PERSP_ERR_FORMAT, ecol, "expected the end of the line after the material name");
        store_current(p);
        if (p->lib->count >= PERSP_SCENE_MAX_OBJECTS)
            return fail(p, PERSP_ERR_TOO_LARGE, kwcol, "more than %d materials", PERSP_SCENE_MAX_OBJECTS);
        if (persp__grow(p->ctx, (void **)&p->lib->entries, &p->lib->cap, p->lib->count + 1,
                        sizeof *p->lib->entries) != PERSP_OK)
            return fail(p, PERSP_ERR_OUT_OF_MEMORY, kwcol, "out of memory");
        p->mat = persp__material_default();
        int index;
        st = persp__scene_add_material(p->scene, &p->mat, &index);
        if (st != PERSP_OK) return fail(p, st, kwcol, "cannot add material");
        persp_mtl_entry *e = &p->lib->entries[p->lib->count++];
        memcpy(e->name, tok, len);
        e->name[len] = '\0';
        e->material = index;
        p->current = index;
        return PERSP_OK;
    }
    if (ignored_statement(kw, kwlen)) {
        p->cur.pos = p->cur.len;
        return PERSP_OK;
    }
    int known = persp__keyword_is(kw, kwlen, "Ka") || persp__keyword_is(kw, kwlen, "Kd") || persp__keyword_is(kw, kwlen, "Ks") ||
                persp__keyword_is(kw, kwlen, "Ns") || persp__keyword_is(kw, kwlen, "d") || persp__keyword_is(kw, kwlen, "Tr") ||
                persp__keyword_is(kw, kwlen, "map_Kd");
    if (!known)
        return fail(p, PERSP_ERR_FORMAT, kwcol, "unknown statement '%.*s'", (int)(kwlen > 32 ? 32 : kwlen), kw);
    if (p->current < 0)
        return fail(p, PERSP_ERR_FORMAT, kwcol, "expected 'newmtl' before '%.*s'", (int)kwlen, kw);
    if (persp__keyword_is(kw, kwlen, "Ka")) return parse_color(p, kw, kwlen, p->mat.ambient);
    if (persp__keyword_is(kw, kwlen, "Kd")) return parse_color(p, kw, kwlen, p->mat.diffuse);
    if (persp__keyword_is(kw, kwlen, "Ks")) return parse_color(p, kw, kwlen, p->mat.specular);
    if (persp__keyword_is(kw, kwlen, "map_Kd")) return parse_map(p);
    float v[1];
    if (persp__keyword_is(kw, kwlen, "d")) {
        /* "d -halo f" is a variant of the format: the option changes nothing here. */
        persp__skip_blanks(&p->cur);
        if (p->cur.len - p->cur.pos >= 5 && memcmp(p->cur.line + p->cur.pos, "-halo", 5) == 0) p->cur.pos += 5;
    }
    persp__skip_blanks(&p->cur);
    size_t col0 = persp__column(&p->cur);
    st = parse_numbers(p, kw, kwlen, v, 1, 1, &n);
    if (st != PERSP_OK) return st;
    if (persp__keyword_is(kw, kwlen, "Ns")) {
        if (v[0] < 0.0f) return fail(p, PERSP_ERR_FORMAT, col0, "expected a shininess >= 0 after 'Ns'");
        p->mat.shininess = v[0];
    } else if (v[0] < 0.0f || v[0] > 1.0f) {
        /* Opacity is checked but not stored: persp draws opaque surfaces. */
        return fail(p, PERSP_ERR_FORMAT, col0, "expected a number in [0, 1] after '%.*s'", (int)kwlen, kw);
    }
    return PERSP_OK;
}

persp_status persp__mtl_load_memory(persp_scene *scene, const char *data, size_t size, const char *name,
                                    const char *base_dir, persp_mtl_lib *lib, persp_texcache *cache)
{
    if (!scene || (!data && size) || !lib) return PERSP_ERR_INVALID_ARGUMENT;
    mtl_parser p;
    memset(&p, 0, sizeof p);
    p.scene = scene;
    p.ctx = scene->ctx;
    p.name = name ? name : "<mtl>";
    p.base_dir = base_dir;
    p.lib = lib;
    p.cache = cache;
    p.current = -1;
    size_t offset = 0;
    while (persp__next_line(data, size, &offset, &p.cur)) {
        const char *kw;
        size_t col, len = persp__token(&p.cur, &kw, &col);
        if (len == 0 || kw[0] == '#') continue;
        persp_status st = statement(&p, kw, len, col);
        if (st != PERSP_OK) return st;
        const char *extra;
        size_t ecol;
        if (persp__token(&p.cur, &extra, &ecol) && extra[0] != '#')
            return fail(&p, PERSP_ERR_FORMAT, ecol, "expected the end of the line after '%.*s'", (int)len, kw);
    }
    return store_current(&p);
}
