/*
 * JSON scene files (format reference: docs/SCENES.md). Parsed with jansson;
 * since jansson keeps no positions for values, errors found after parsing
 * are located by re-scanning the text along the JSON path of the offending
 * value, so every message reads "file:line:col: path: what was expected".
 * Unknown keys are errors: a misspelt key must not silently do nothing.
 */
#include "core/internal.h"
#include "io/json_text.h"
#include "model/model.h"
#include "io/text.h"

#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define JPATH_MAX 16

typedef struct jcomp {
    const char *key; /* NULL: array index */
    size_t index;
} jcomp;

typedef struct named_material {
    const char *name; /* owned by the JSON tree */
    int index;
} named_material;

typedef struct jctx {
    persp_context *ctx;
    const char *name, *text, *base_dir;
    size_t size;
    persp_scene *scene;
    persp_texcache cache;
    jcomp path[JPATH_MAX];
    int depth;
    named_material *mats;
    size_t mat_count;
    size_t vertices, max_vertices;
} jctx;

/* ------------------------------------------------------------ positions */

typedef struct jscan {
    const char *s;
    size_t n, i, line, line_start;
} jscan;

static void scan_ws(jscan *sc)
{
    while (sc->i < sc->n) {
        char c = sc->s[sc->i];
        if (c == '\n') {
            sc->line++;
            sc->line_start = sc->i + 1;
        } else if (c != ' ' && c != '\t' && c != '\r') {
            break;
        }
        sc->i++;
    }
}

/* Skips a string starting at '"'; returns the raw bytes between quotes. */
static void scan_string(jscan *sc, const char **raw, size_t *len)
{
    size_t start = ++sc->i;
    while (sc->i < sc->n && sc->s[sc->i] != '"') sc->i += sc->s[sc->i] == '\\' ? 2 : 1;
    if (sc->i > sc->n) sc->i = sc->n;
    *raw = sc->s + start;
    *len = sc->i - start;
    if (sc->i < sc->n) sc->i++;
}

static int is_delim(char c)
{
    return c == ',' || c == ']' || c == '}' || c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

/* Skips one value without recursion (nesting depth is only counted). */
static void scan_skip(jscan *sc)
{
    size_t depth = 0;
    do {
        scan_ws(sc);
        if (sc->i >= sc->n) return;
        char c = sc->s[sc->i];
        if (c == '"') {
            const char *r;
            size_t l;
            scan_string(sc, &r, &l);
        } else if (c == '{' || c == '[') {
            depth++;
            sc->i++;
        } else if (c == '}' || c == ']') {
            if (depth) depth--;
            sc->i++;
        } else if (c == ',' || c == ':') {
            sc->i++;
        } else {
            /* A scalar (or a stray byte, e.g. a NUL jansson stopped at):
             * always consume at least one byte so the scan terminates. */
            sc->i++;
            while (sc->i < sc->n && !is_delim(sc->s[sc->i])) sc->i++;
        }
    } while (depth > 0 && sc->i < sc->n);
}

/* Line and column of the value at path[0..depth) (of its key when at_key),
 * or of the deepest part of the path that exists in the text. */
static void locate(const jctx *j, int at_key, size_t *line, size_t *col)
{
    jscan sc = {j->text, j->size, 0, 1, 0};
    scan_ws(&sc);
    size_t best = sc.i, best_line = sc.line, best_start = sc.line_start;
    for (int d = 0; d < j->depth; d++) {
        scan_ws(&sc);
        if (sc.i >= sc.n) break;
        const jcomp *c = &j->path[d];
        int found = 0;
        if (c->key && sc.s[sc.i] == '{') {
            sc.i++;
            for (;;) {
                scan_ws(&sc);
                if (sc.i >= sc.n || sc.s[sc.i] != '"') break;
                size_t kpos = sc.i, kline = sc.line, kstart = sc.line_start;
                const char *raw;
                size_t len;
                scan_string(&sc, &raw, &len);
                scan_ws(&sc);
                if (sc.i < sc.n && sc.s[sc.i] == ':') sc.i++;
                scan_ws(&sc);
                if (len == strlen(c->key) && memcmp(raw, c->key, len) == 0) {
                    found = 1;
                    if (at_key && d == j->depth - 1) {
                        sc.i = kpos, sc.line = kline, sc.line_start = kstart;
                    }
                    break;
                }
                scan_skip(&sc);
                scan_ws(&sc);
                if (sc.i < sc.n && sc.s[sc.i] == ',') sc.i++;
            }
        } else if (!c->key && sc.s[sc.i] == '[') {
            sc.i++;
            size_t k = 0;
            for (;;) {
                scan_ws(&sc);
                if (sc.i >= sc.n || sc.s[sc.i] == ']') break;
                if (k == c->index) {
                    found = 1;
                    break;
                }
                scan_skip(&sc);
                scan_ws(&sc);
                if (sc.i < sc.n && sc.s[sc.i] == ',') sc.i++;
                k++;
            }
        }
        if (!found) break;
        best = sc.i, best_line = sc.line, best_start = sc.line_start;
    }
    *line = best_line;
    *col = best - best_start + 1;
}

/* A string of the file for a message: escaped and capped, so that control
 * bytes (a terminal escape, say) never reach the user's terminal. */
static const char *qs(const char *s, char buf[PERSP_QUOTE_BYTES])
{
    return persp__quote(s, strlen(s), buf, PERSP_QUOTE_BYTES);
}

static void path_string(const jctx *j, char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int d = 0; d < j->depth && n < size; d++) {
        int w;
        char q[PERSP_QUOTE_BYTES];
        if (j->path[d].key)
            w = snprintf(buf + n, size - n, "%s%s", d ? "." : "",
                         persp__quote(j->path[d].key, strlen(j->path[d].key), q, sizeof q));
        else
            w = snprintf(buf + n, size - n, "[%zu]", j->path[d].index);
        if (w < 0) break;
        n += (size_t)w;
    }
}

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static persp_status jfail(jctx *j, int at_key, persp_status st, const char *fmt, ...)
{
    char msg[PERSP_ERRMSG_BYTES], path[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    size_t line, col;
    locate(j, at_key, &line, &col);
    path_string(j, path, sizeof path);
    return persp__fail(j->ctx, st, "%s:%zu:%zu: %s%s%s", j->name, line, col, path, path[0] ? ": " : "",
                              msg);
}

/* Wraps a failure reported by another module with this value's position. */
static persp_status jwrap(jctx *j, persp_status st)
{
    char inner[PERSP_ERRMSG_BYTES];
    snprintf(inner, sizeof inner, "%s", persp_context_error(j->ctx));
    return jfail(j, 0, st, "%s", inner);
}

static int push_key(jctx *j, const char *key)
{
    if (j->depth >= JPATH_MAX) return 0;
    j->path[j->depth].key = key;
    j->path[j->depth].index = 0;
    j->depth++;
    return 1;
}

static int push_index(jctx *j, size_t index)
{
    if (j->depth >= JPATH_MAX) return 0;
    j->path[j->depth].key = NULL;
    j->path[j->depth].index = index;
    j->depth++;
    return 1;
}

static void pop(jctx *j) { j->depth--; }

/* --------------------------------------------------------------- values */

static persp_status check_keys(jctx *j, json_t *obj, const char *const *allowed)
{
    if (!json_is_object(obj)) return jfail(j, 0, PERSP_ERR_FORMAT, "expected an object");
    const char *key;
    json_t *v;
    json_object_foreach(obj, key, v) {
        int ok = !strcmp(key, "comment");
        for (size_t i = 0; allowed[i] && !ok; i++) ok = !strcmp(key, allowed[i]);
        if (!ok) {
            char list[256];
            size_t n = 0;
            list[0] = '\0';
            for (size_t i = 0; allowed[i] && n < sizeof list; i++) {
                int w = snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", allowed[i]);
                if (w < 0) break;
                n += (size_t)w;
            }
            push_key(j, key);
            persp_status st = jfail(j, 1, PERSP_ERR_FORMAT, "unknown key (expected one of: %s)", list);
            pop(j);
            return st;
        }
    }
    return PERSP_OK;
}

static persp_status read_float(jctx *j, json_t *v, double lo, double hi, float *out)
{
    double d = json_number_value(v);
    if (!json_is_number(v) || !(d >= lo && d <= hi))
        return jfail(j, 0, PERSP_ERR_FORMAT, "expected a number in [%g, %g]", lo, hi);
    *out = (float)d;
    return PERSP_OK;
}

static persp_status read_int(jctx *j, json_t *v, long lo, long hi, int *out)
{
    if (!json_is_integer(v) || json_integer_value(v) < lo || json_integer_value(v) > hi)
        return jfail(j, 0, PERSP_ERR_FORMAT, "expected an integer in [%ld, %ld]", lo, hi);
    *out = (int)json_integer_value(v);
    return PERSP_OK;
}

static persp_status read_vec(jctx *j, json_t *v, size_t n, double lo, double hi, float *out)
{
    if (!json_is_array(v) || json_array_size(v) != n)
        return jfail(j, 0, PERSP_ERR_FORMAT, "expected an array of %zu numbers", n);
    for (size_t i = 0; i < n; i++) {
        push_index(j, i);
        persp_status st = read_float(j, json_array_get(v, i), lo, hi, &out[i]);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static persp_status read_string(jctx *j, json_t *v, const char **out)
{
    if (!json_is_string(v)) return jfail(j, 0, PERSP_ERR_FORMAT, "expected a string");
    if (strlen(json_string_value(v)) != json_string_length(v))
        return jfail(j, 0, PERSP_ERR_FORMAT, "string contains a NUL character");
    *out = json_string_value(v);
    return PERSP_OK;
}

static persp_status read_bool(jctx *j, json_t *v, int *out)
{
    if (!json_is_boolean(v)) return jfail(j, 0, PERSP_ERR_FORMAT, "expected true or false");
    *out = json_is_true(v);
    return PERSP_OK;
}

/* Looks up key in obj: returns NULL if absent, else pushes key on the path
 * (the caller pops). */
static json_t *field(jctx *j, json_t *obj, const char *key)
{
    json_t *v = json_object_get(obj, key);
    if (v) push_key(j, key);
    return v;
}

#define LARGE 1.0e30

static persp_status field_vec(jctx *j, json_t *obj, const char *key, size_t n, double lo, double hi, float *out)
{
    json_t *v = field(j, obj, key);
    if (!v) return PERSP_OK;
    persp_status st = read_vec(j, v, n, lo, hi, out);
    pop(j);
    return st;
}

static persp_status field_float(jctx *j, json_t *obj, const char *key, double lo, double hi, float *out)
{
    json_t *v = field(j, obj, key);
    if (!v) return PERSP_OK;
    persp_status st = read_float(j, v, lo, hi, out);
    pop(j);
    return st;
}

static persp_status field_int(jctx *j, json_t *obj, const char *key, long lo, long hi, int *out)
{
    json_t *v = field(j, obj, key);
    if (!v) return PERSP_OK;
    persp_status st = read_int(j, v, lo, hi, out);
    pop(j);
    return st;
}

/* A filter name: an unknown one, or aniso with a tap count out of range
 * (persp_filter_parse's INVALID_ARGUMENT), each with its own message. */
static persp_status filter_field(jctx *j, const char *name, persp_filter *f, int *aniso)
{
    char q[PERSP_QUOTE_BYTES];
    persp_status st = persp_filter_parse(name, f, aniso);
    if (st == PERSP_ERR_INVALID_ARGUMENT)
        return jfail(j, 0, PERSP_ERR_FORMAT, "bad filter '%s': aniso taps must be 2..%d",
                     qs(name, q), PERSP_MAX_ANISO);
    if (st != PERSP_OK) return jfail(j, 0, PERSP_ERR_FORMAT, "unknown filter '%s'", qs(name, q));
    return PERSP_OK;
}

static persp_status resolve_file(jctx *j, const char *rel, char *path, size_t size)
{
    if (!rel[0]) return jfail(j, 0, PERSP_ERR_FORMAT, "expected a file name");
    if (!j->base_dir) return jfail(j, 0, PERSP_ERR_UNSUPPORTED, "file references are not allowed here");
    if (!persp__path_join(j->base_dir, rel, path, size)) return jfail(j, 0, PERSP_ERR_FORMAT, "file name too long");
    /* This check of the name gives the message its line and key; the read
     * that follows is confined again by its open (persp__open_inside), which
     * is what decides, since a link can be swapped after this check. */
    if (persp__path_inside(j->scene->load_root, path) == 0) {
        char q[PERSP_QUOTE_BYTES];
        return jfail(j, 0, PERSP_ERR_IO, "'%s' is outside the folder the scene may read from (%s)",
                     qs(rel, q), j->scene->load_root);
    }
    return PERSP_OK;
}

/* ------------------------------------------------------------- sections */

static persp_status parse_camera(jctx *j, json_t *cam)
{
    static const char *const keys[] = {"position", "target", "up", "fov", "near", "far", NULL};
    persp_status st = check_keys(j, cam, keys);
    if (st != PERSP_OK) return st;
    persp_camera *c = &j->scene->camera;
    float p[3] = {c->eye.x, c->eye.y, c->eye.z}, t[3] = {c->target.x, c->target.y, c->target.z},
          u[3] = {c->up.x, c->up.y, c->up.z};
    if ((st = field_vec(j, cam, "position", 3, -LARGE, LARGE, p)) != PERSP_OK ||
        (st = field_vec(j, cam, "target", 3, -LARGE, LARGE, t)) != PERSP_OK ||
        (st = field_vec(j, cam, "up", 3, -LARGE, LARGE, u)) != PERSP_OK ||
        (st = field_float(j, cam, "fov", 1e-3, 179.0, &c->fovy_deg)) != PERSP_OK ||
        (st = field_float(j, cam, "near", 1e-6, LARGE, &c->znear)) != PERSP_OK ||
        (st = field_float(j, cam, "far", 1e-6, LARGE, &c->zfar)) != PERSP_OK)
        return st;
    c->eye = (persp_vec3){p[0], p[1], p[2]};
    c->target = (persp_vec3){t[0], t[1], t[2]};
    c->up = (persp_vec3){u[0], u[1], u[2]};
    double d[3] = {(double)t[0] - p[0], (double)t[1] - p[1], (double)t[2] - p[2]};
    double cr[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] == 0.0)
        return jfail(j, 0, PERSP_ERR_FORMAT, "camera target must differ from its position");
    if (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2] == 0.0)
        return jfail(j, 0, PERSP_ERR_FORMAT, "camera up must not be parallel to the viewing direction");
    if (!(c->zfar > c->znear)) {
        push_key(j, json_object_get(cam, "far") ? "far" : "near");
        st = jfail(j, 0, PERSP_ERR_FORMAT, "expected far > near");
        pop(j);
        return st;
    }
    return PERSP_OK;
}

static persp_status parse_render(jctx *j, json_t *r)
{
    char q[PERSP_QUOTE_BYTES];
    static const char *const keys[] = {"size", "method", "filter", "shading", "clear", "cull", NULL};
    persp_status st = check_keys(j, r, keys);
    if (st != PERSP_OK) return st;
    persp_scene *s = j->scene;
    json_t *v;
    if ((v = field(j, r, "size"))) {
        float wh[2] = {0, 0};
        st = read_vec(j, v, 2, 1, PERSP_IMAGE_MAX_SIDE, wh);
        if (st == PERSP_OK && (wh[0] != floorf(wh[0]) || wh[1] != floorf(wh[1])))
            st = jfail(j, 0, PERSP_ERR_FORMAT, "expected integer width and height");
        if (st == PERSP_OK && (double)wh[0] * wh[1] > (double)PERSP_IMAGE_MAX_PIXELS)
            st = jfail(j, 0, PERSP_ERR_TOO_LARGE, "more than %u pixels", PERSP_IMAGE_MAX_PIXELS);
        s->width = (int)wh[0], s->height = (int)wh[1];
        pop(j);
        if (st != PERSP_OK) return st;
    }
    const char *str = NULL;
    if ((v = field(j, r, "method"))) {
        st = read_string(j, v, &str);
        if (st == PERSP_OK && strlen(str) >= sizeof s->method)
            st = jfail(j, 0, PERSP_ERR_FORMAT, "method spec too long");
        if (st == PERSP_OK && (st = persp_method_check(str)) != PERSP_OK)
            st = jfail(j, 0, st, "unknown method or bad parameters '%s' (`persp methods` prints them)",
                       qs(str, q));
        if (st == PERSP_OK) snprintf(s->method, sizeof s->method, "%s", str);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, r, "filter"))) {
        st = read_string(j, v, &str);
        if (st == PERSP_OK) st = filter_field(j, str, &s->filter, &s->max_aniso);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, r, "shading"))) {
        st = read_string(j, v, &str);
        if (st == PERSP_OK && persp_shading_parse(str, &s->shading) != PERSP_OK)
            st = jfail(j, 0, PERSP_ERR_FORMAT, "unknown shading '%s'", qs(str, q));
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, r, "clear"))) {
        float c[4] = {0, 0, 0, 1};
        if (json_is_array(v) && json_array_size(v) == 3) st = read_vec(j, v, 3, 0, 1, c);
        else if (json_is_array(v) && json_array_size(v) == 4) st = read_vec(j, v, 4, 0, 1, c);
        else st = jfail(j, 0, PERSP_ERR_FORMAT, "expected an array of 3 or 4 numbers in [0, 1]");
        for (int i = 0; i < 4; i++) s->clear[i] = (uint8_t)lrintf(c[i] * 255.0f);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, r, "cull"))) {
        st = read_bool(j, v, &s->cull_backfaces);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static persp_status parse_light(jctx *j, json_t *l)
{
    static const char *const keys[] = {"type", "position", "direction", "color", "attenuation", NULL};
    persp_status st = check_keys(j, l, keys);
    if (st != PERSP_OK) return st;
    persp_light light;
    memset(&light, 0, sizeof light);
    light.color[0] = light.color[1] = light.color[2] = 1.0f;
    light.attenuation[0] = 1.0f;
    json_t *v = field(j, l, "type");
    const char *type = NULL;
    if (!v) return jfail(j, 0, PERSP_ERR_FORMAT, "missing key 'type' (\"point\" or \"directional\")");
    st = read_string(j, v, &type);
    if (st == PERSP_OK && strcmp(type, "point") && strcmp(type, "directional"))
        st = jfail(j, 0, PERSP_ERR_FORMAT, "expected \"point\" or \"directional\"");
    pop(j);
    if (st != PERSP_OK) return st;
    int point = !strcmp(type, "point");
    light.type = point ? PERSP_LIGHT_POINT : PERSP_LIGHT_DIRECTIONAL;
    const char *need = point ? "position" : "direction", *forbid = point ? "direction" : "position";
    /* A directional light is not attenuated (GL 1.5 §2.14.1): the key
     * would do nothing, and is refused as the wrong position key is. */
    if (!point && json_object_get(l, "attenuation")) forbid = "attenuation";
    if (json_object_get(l, forbid)) {
        push_key(j, forbid);
        st = jfail(j, 1, PERSP_ERR_FORMAT, "a %s light has no '%s'", type, forbid);
        pop(j);
        return st;
    }
    if (!json_object_get(l, need)) return jfail(j, 0, PERSP_ERR_FORMAT, "missing key '%s'", need);
    float p[3];
    if ((st = field_vec(j, l, need, 3, -LARGE, LARGE, p)) != PERSP_OK) return st;
    if (point) {
        memcpy(light.position, p, sizeof p);
    } else {
        /* The file gives the direction the light travels; the scene stores
         * the direction towards the light, as used in N·L. */
        double len = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        if (!(len > 0.0)) {
            push_key(j, "direction");
            st = jfail(j, 0, PERSP_ERR_FORMAT, "expected a non-zero direction");
            pop(j);
            return st;
        }
        for (int i = 0; i < 3; i++) light.position[i] = (float)(-p[i] / len);
    }
    if ((st = field_vec(j, l, "color", 3, 0, LARGE, light.color)) != PERSP_OK ||
        (st = field_vec(j, l, "attenuation", 3, 0, LARGE, light.attenuation)) != PERSP_OK)
        return st;
    if (light.attenuation[0] + light.attenuation[1] + light.attenuation[2] <= 0.0f) {
        push_key(j, "attenuation");
        st = jfail(j, 0, PERSP_ERR_FORMAT, "expected at least one positive coefficient");
        pop(j);
        return st;
    }
    j->scene->lights[j->scene->light_count++] = light;
    return PERSP_OK;
}

static persp_status parse_lights(jctx *j, json_t *a)
{
    if (!json_is_array(a)) return jfail(j, 0, PERSP_ERR_FORMAT, "expected an array of lights");
    if (json_array_size(a) > PERSP_SCENE_MAX_LIGHTS)
        return jfail(j, 0, PERSP_ERR_TOO_LARGE, "more than %d lights", PERSP_SCENE_MAX_LIGHTS);
    for (size_t i = 0; i < json_array_size(a); i++) {
        push_index(j, i);
        persp_status st = parse_light(j, json_array_get(a, i));
        pop(j);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static persp_status parse_wrap(jctx *j, json_t *v, persp_sampler_desc *sd)
{
    const char *a = NULL, *b = NULL;
    persp_status st;
    if (json_is_array(v) && json_array_size(v) == 2) {
        push_index(j, 0);
        st = read_string(j, json_array_get(v, 0), &a);
        pop(j);
        if (st != PERSP_OK) return st;
        push_index(j, 1);
        st = read_string(j, json_array_get(v, 1), &b);
        pop(j);
        if (st != PERSP_OK) return st;
    } else if (json_is_string(v)) {
        if ((st = read_string(j, v, &a)) != PERSP_OK) return st;
        b = a;
    } else {
        return jfail(j, 0, PERSP_ERR_FORMAT, "expected a wrap mode or a [s, t] pair of them");
    }
    if (persp_wrap_parse(a, &sd->wrap_s) != PERSP_OK || persp_wrap_parse(b, &sd->wrap_t) != PERSP_OK)
        return jfail(j, 0, PERSP_ERR_FORMAT,
                     "unknown wrap mode (repeat, clamp-to-edge, mirrored-repeat, clamp-to-border)");
    return PERSP_OK;
}

static persp_status parse_texture(jctx *j, json_t *v, persp_material *m, int *filter_given)
{
    static const char *const keys[] = {"file", "wrap", "filter", "border", "specular", NULL};
    const char *file = NULL;
    persp_status st;
    json_t *obj = NULL;
    if (json_is_string(v)) {
        if ((st = read_string(j, v, &file)) != PERSP_OK) return st;
    } else {
        obj = v;
        if ((st = check_keys(j, obj, keys)) != PERSP_OK) return st;
        json_t *f = field(j, obj, "file");
        if (!f) return jfail(j, 0, PERSP_ERR_FORMAT, "missing key 'file'");
        st = read_string(j, f, &file);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if (obj) {
        json_t *w;
        if ((w = field(j, obj, "wrap"))) {
            st = parse_wrap(j, w, &m->sampler);
            pop(j);
            if (st != PERSP_OK) return st;
        }
        if ((w = field(j, obj, "filter"))) {
            const char *name = NULL;
            st = read_string(j, w, &name);
            if (st == PERSP_OK)
                st = filter_field(j, name, &m->sampler.filter, &m->sampler.max_aniso);
            *filter_given = 1;
            pop(j);
            if (st != PERSP_OK) return st;
        }
        float border[4] = {0, 0, 0, 0};
        if ((st = field_vec(j, obj, "border", 4, 0, 1, border)) != PERSP_OK) return st;
        for (int i = 0; i < 4; i++) m->sampler.border[i] = (uint8_t)lrintf(border[i] * 255.0f);
        int spec = 0;
        if ((w = field(j, obj, "specular"))) {
            st = read_bool(j, w, &spec);
            pop(j);
            if (st != PERSP_OK) return st;
        }
        m->specular_texture = spec; /* resolved to the index below */
    }
    char path[PERSP_PATH_MAX];
    if (obj) push_key(j, "file");
    st = resolve_file(j, file, path, sizeof path);
    int index = -1;
    if (st == PERSP_OK && (st = persp__texcache_load(j->scene, &j->cache, path, &index)) != PERSP_OK)
        st = jwrap(j, st);
    if (obj) pop(j);
    if (st != PERSP_OK) return st;
    m->texture = index;
    m->specular_texture = m->specular_texture == 1 ? index : -1;
    return PERSP_OK;
}

static persp_status parse_material(jctx *j, json_t *o, persp_material *m, int *filter_given)
{
    static const char *const keys[] = {"ambient", "diffuse", "specular", "shininess", "texture", "env", NULL};
    persp_status st = check_keys(j, o, keys);
    if (st != PERSP_OK) return st;
    *m = persp__material_default();
    if ((st = field_vec(j, o, "ambient", 3, 0, LARGE, m->ambient)) != PERSP_OK ||
        (st = field_vec(j, o, "diffuse", 3, 0, LARGE, m->diffuse)) != PERSP_OK ||
        (st = field_vec(j, o, "specular", 3, 0, LARGE, m->specular)) != PERSP_OK ||
        (st = field_float(j, o, "shininess", 0, 1e4, &m->shininess)) != PERSP_OK)
        return st;
    json_t *v;
    if ((v = field(j, o, "env"))) {
        const char *env = NULL;
        st = read_string(j, v, &env);
        if (st == PERSP_OK) {
            if (!strcmp(env, "replace")) m->env = PERSP_TEXENV_REPLACE;
            else if (!strcmp(env, "modulate")) m->env = PERSP_TEXENV_MODULATE;
            else st = jfail(j, 0, PERSP_ERR_FORMAT, "expected \"replace\" or \"modulate\"");
        }
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, o, "texture"))) {
        st = parse_texture(j, v, m, filter_given);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static persp_status parse_materials(jctx *j, json_t *o)
{
    if (!json_is_object(o)) return jfail(j, 0, PERSP_ERR_FORMAT, "expected an object of named materials");
    size_t n = json_object_size(o);
    if (n > PERSP_SCENE_MAX_OBJECTS) return jfail(j, 0, PERSP_ERR_TOO_LARGE, "too many materials");
    j->mats = persp__calloc(j->ctx, n ? n : 1, sizeof *j->mats);
    if (!j->mats) return persp__fail(j->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", j->name);
    const char *key;
    json_t *v;
    json_object_foreach(o, key, v) {
        /* "Any object may carry a comment": here a string named comment is
         * one, not a material. */
        if (!strcmp(key, "comment") && json_is_string(v)) continue;
        persp_material m;
        int filter_given = 0;
        push_key(j, key);
        persp_status st = parse_material(j, v, &m, &filter_given);
        pop(j);
        if (st != PERSP_OK) return st;
        if (!filter_given && j->scene->filter != PERSP_FILTER_DEFAULT) {
            m.sampler.filter = j->scene->filter;
            m.sampler.max_aniso = j->scene->max_aniso;
        }
        int index;
        if ((st = persp__scene_add_material(j->scene, &m, &index)) != PERSP_OK) return st;
        j->mats[j->mat_count].name = key;
        j->mats[j->mat_count].index = index;
        j->mat_count++;
    }
    return PERSP_OK;
}

/* Transform: scale first, then the rotations in the order listed, then the
 * translation: M = T · R_k ⋯ R_1 · S (column vectors, OpenGL order). */
static persp_status parse_transform(jctx *j, json_t *t, persp_mat4 *model)
{
    static const char *const keys[] = {"translate", "rotate", "scale", NULL};
    persp_status st = check_keys(j, t, keys);
    if (st != PERSP_OK) return st;
    float tr[3] = {0, 0, 0}, sc[3] = {1, 1, 1};
    if ((st = field_vec(j, t, "translate", 3, -LARGE, LARGE, tr)) != PERSP_OK) return st;
    json_t *v;
    if ((v = field(j, t, "scale"))) {
        /* One number or three: the same range, any sign but zero (a
         * negative one mirrors, SCENES.md `cull`). */
        if (json_is_number(v)) {
            st = read_float(j, v, -LARGE, LARGE, &sc[0]);
            sc[1] = sc[2] = sc[0];
        } else {
            st = read_vec(j, v, 3, -LARGE, LARGE, sc);
        }
        if (st == PERSP_OK && (sc[0] == 0.0f || sc[1] == 0.0f || sc[2] == 0.0f))
            st = jfail(j, 0, PERSP_ERR_FORMAT, "expected non-zero scale factors");
        pop(j);
        if (st != PERSP_OK) return st;
    }
    persp_mat4 m = persp_mat4_scale(sc[0], sc[1], sc[2]);
    if ((v = field(j, t, "rotate"))) {
        /* One rotation [degrees, ax, ay, az] or a list of them. */
        const int none = json_is_array(v) && json_array_size(v) == 0; /* an empty list */
        int list = json_is_array(v) && json_array_size(v) > 0 && json_is_array(json_array_get(v, 0));
        size_t n = none ? 0 : list ? json_array_size(v) : 1;
        for (size_t i = 0; i < n && st == PERSP_OK; i++) {
            json_t *r = list ? json_array_get(v, i) : v;
            if (list) push_index(j, i);
            float a[4];
            st = read_vec(j, r, 4, -LARGE, LARGE, a);
            if (st == PERSP_OK && a[1] == 0.0f && a[2] == 0.0f && a[3] == 0.0f)
                st = jfail(j, 0, PERSP_ERR_FORMAT, "expected a non-zero rotation axis");
            if (st == PERSP_OK) m = persp_mat4_mul(persp_mat4_rotate(a[0], a[1], a[2], a[3]), m);
            if (list) pop(j);
        }
        pop(j);
        if (st != PERSP_OK) return st;
    }
    *model = persp_mat4_mul(persp_mat4_translate(tr[0], tr[1], tr[2]), m);
    return PERSP_OK;
}

static persp_status parse_texgen(jctx *j, json_t *v, persp_object *o)
{
    static const char *const names[] = {"uv", "planar", "cylindrical", "spherical", "cube", "reflection"};
    static const char *const keys[] = {"mode", "s", "t", "scale", "axis", "center", NULL};
    const char *mode = NULL;
    persp_status st;
    json_t *obj = NULL;
    o->texgen_axis = 1;
    o->texgen_s[0] = 1.0f; /* planar default: the xy plane, u = x, v = y */
    o->texgen_t[1] = 1.0f;
    if (json_is_string(v)) {
        if ((st = read_string(j, v, &mode)) != PERSP_OK) return st;
    } else {
        obj = v;
        if ((st = check_keys(j, obj, keys)) != PERSP_OK) return st;
        json_t *m = field(j, obj, "mode");
        if (!m) return jfail(j, 0, PERSP_ERR_FORMAT, "missing key 'mode'");
        st = read_string(j, m, &mode);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    int found = -1;
    for (int i = 0; i < 6; i++)
        if (!strcmp(mode, names[i])) found = i;
    if (found < 0) {
        if (obj) push_key(j, "mode");
        st = jfail(j, 0, PERSP_ERR_FORMAT, "expected uv, planar, cylindrical, spherical, cube or reflection");
        if (obj) pop(j);
        return st;
    }
    o->texgen = (persp_texgen)found;
    if (!obj) return PERSP_OK;
    /* A key the mode does not read would do nothing: refused, as a
     * misspelt one is. Per mode (the order of names): s, t, axis, center,
     * scale. */
    static const char used[6][5] = {{0, 0, 0, 0, 0}, {1, 1, 0, 0, 1}, {0, 0, 1, 1, 1},
                                    {0, 0, 1, 1, 1}, {0, 0, 0, 1, 1}, {0, 0, 0, 0, 1}};
    static const char *const mode_keys[] = {"s", "t", "axis", "center", "scale"};
    for (int k = 0; k < 5; k++)
        if (!used[found][k] && json_object_get(obj, mode_keys[k])) {
            push_key(j, mode_keys[k]);
            st = jfail(j, 1, PERSP_ERR_FORMAT, "not used by mode %s", mode);
            pop(j);
            return st;
        }
    if ((st = field_vec(j, obj, "s", 4, -LARGE, LARGE, o->texgen_s)) != PERSP_OK ||
        (st = field_vec(j, obj, "t", 4, -LARGE, LARGE, o->texgen_t)) != PERSP_OK ||
        (st = field_vec(j, obj, "center", 3, -LARGE, LARGE, o->texgen_center)) != PERSP_OK)
        return st;
    json_t *s;
    if ((s = field(j, obj, "scale"))) {
        if (json_is_number(s)) {
            st = read_float(j, s, -LARGE, LARGE, &o->texgen_scale[0]);
            o->texgen_scale[1] = o->texgen_scale[0];
        } else {
            st = read_vec(j, s, 2, -LARGE, LARGE, o->texgen_scale);
        }
        if (st == PERSP_OK && (o->texgen_scale[0] == 0.0f || o->texgen_scale[1] == 0.0f))
            st = jfail(j, 0, PERSP_ERR_FORMAT, "expected non-zero repeats");
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((s = field(j, obj, "axis"))) {
        const char *ax = NULL;
        st = read_string(j, s, &ax);
        if (st == PERSP_OK) {
            if (!strcmp(ax, "x")) o->texgen_axis = 0;
            else if (!strcmp(ax, "y")) o->texgen_axis = 1;
            else if (!strcmp(ax, "z")) o->texgen_axis = 2;
            else st = jfail(j, 0, PERSP_ERR_FORMAT, "expected \"x\", \"y\" or \"z\"");
        }
        pop(j);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static int find_material(const jctx *j, const char *name)
{
    for (size_t i = 0; i < j->mat_count; i++)
        if (!strcmp(j->mats[i].name, name)) return j->mats[i].index;
    return -1;
}

static persp_status count_vertices(jctx *j, size_t n)
{
    if (n > j->max_vertices - j->vertices)
        return jfail(j, 0, PERSP_ERR_TOO_LARGE, "the scene's meshes exceed %zu vertices", j->max_vertices);
    j->vertices += n;
    return PERSP_OK;
}

/* A primitive's parameters, validated here so the error points at them. */
static persp_status make_primitive(jctx *j, const char *prim, json_t *obj, persp_mesh *mesh)
{
    char q[PERSP_QUOTE_BYTES];
    int subdiv = 1, slices = 32, stacks = 16, rings = 16;
    float major = 1.0f, minor = 0.25f;
    const char *allowed_plane[] = {"primitive", "subdivisions", NULL};
    const char *allowed_cube[] = {"primitive", NULL};
    const char *allowed_sphere[] = {"primitive", "slices", "stacks", NULL};
    const char *allowed_cyl[] = {"primitive", "slices", NULL};
    const char *allowed_torus[] = {"primitive", "slices", "rings", "major", "minor", NULL};
    const char *allowed_soup[] = {"primitive", "count", "seed", "size", NULL};
    int count = 1000, seed = 1;
    float size[2] = {0.02f, 0.05f};
    const char *const *allowed;
    if (!strcmp(prim, "plane")) allowed = allowed_plane;
    else if (!strcmp(prim, "cube")) allowed = allowed_cube;
    else if (!strcmp(prim, "sphere")) allowed = allowed_sphere;
    else if (!strcmp(prim, "cylinder")) allowed = allowed_cyl;
    else if (!strcmp(prim, "torus")) allowed = allowed_torus;
    else if (!strcmp(prim, "soup")) allowed = allowed_soup;
    else {
        if (obj) push_key(j, "primitive");
        persp_status st = jfail(j, 0, PERSP_ERR_FORMAT,
                                "unknown primitive '%s' (plane, cube, sphere, cylinder, torus, soup)",
                                qs(prim, q));
        if (obj) pop(j);
        return st;
    }
    persp_status st = PERSP_OK;
    if (obj) {
        if ((st = check_keys(j, obj, allowed)) != PERSP_OK ||
            (st = field_int(j, obj, "subdivisions", 1, 1024, &subdiv)) != PERSP_OK ||
            (st = field_int(j, obj, "slices", 3, 1024, &slices)) != PERSP_OK ||
            (st = field_int(j, obj, "stacks", 2, 1024, &stacks)) != PERSP_OK ||
            (st = field_int(j, obj, "rings", 3, 1024, &rings)) != PERSP_OK ||
            (st = field_float(j, obj, "major", 1e-6, LARGE, &major)) != PERSP_OK ||
            (st = field_float(j, obj, "minor", 1e-6, LARGE, &minor)) != PERSP_OK ||
            (st = field_int(j, obj, "count", 1, (int)(PERSP_SCENE_MAX_VERTICES / 3), &count)) != PERSP_OK ||
            (st = field_int(j, obj, "seed", 0, 2147483647, &seed)) != PERSP_OK ||
            (st = field_vec(j, obj, "size", 2, 1e-6, LARGE, size)) != PERSP_OK)
            return st;
        if (size[1] < size[0]) {
            push_key(j, "size");
            st = jfail(j, 0, PERSP_ERR_FORMAT, "size [min, max] needs min <= max (got [%g, %g])",
                       (double)size[0], (double)size[1]);
            pop(j);
            return st;
        }
    }
    size_t nv;
    const char kind = strcmp(prim, "soup") ? prim[1] : 'S';
    switch (kind) {
    case 'l': nv = (size_t)(subdiv + 1) * (size_t)(subdiv + 1); break;
    case 'u': nv = 24; break;
    case 'p': nv = (size_t)(slices + 1) * (size_t)(stacks + 1); break;
    case 'y': nv = 4 * (size_t)(slices + 1) + 2; break;
    case 'S': nv = 3 * (size_t)count; break;
    default: nv = (size_t)(slices + 1) * (size_t)(rings + 1); break;
    }
    if ((st = count_vertices(j, nv)) != PERSP_OK) return st;
    switch (kind) {
    case 'l': st = persp__mesh_plane(j->ctx, subdiv, mesh); break;
    case 'u': st = persp__mesh_cube(j->ctx, mesh); break;
    case 'p': st = persp__mesh_sphere(j->ctx, slices, stacks, mesh); break;
    case 'y': st = persp__mesh_cylinder(j->ctx, slices, mesh); break;
    case 'S': st = persp__mesh_soup(j->ctx, count, (uint64_t)seed, size[0], size[1], mesh); break;
    default: st = persp__mesh_torus(j->ctx, major, minor, slices, rings, mesh); break;
    }
    return st == PERSP_OK ? PERSP_OK : jwrap(j, st);
}

static int is_primitive(const char *s)
{
    return !strcmp(s, "plane") || !strcmp(s, "cube") || !strcmp(s, "sphere") || !strcmp(s, "cylinder") ||
           !strcmp(s, "torus") || !strcmp(s, "soup");
}

/* An object's "name", "transform", "texgen" and "material" (*material: its
 * index, or -1 where none is named). */
static persp_status parse_object_settings(jctx *j, json_t *o, persp_object *obj, int *material)
{
    char q[PERSP_QUOTE_BYTES];
    json_t *v;
    const char *str = NULL;
    persp_status st = PERSP_OK;
    *material = -1;
    if ((v = field(j, o, "name"))) {
        st = read_string(j, v, &str);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, o, "transform"))) {
        st = parse_transform(j, v, &obj->model);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, o, "texgen"))) {
        st = parse_texgen(j, v, obj);
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((v = field(j, o, "material"))) {
        st = read_string(j, v, &str);
        if (st == PERSP_OK && (*material = find_material(j, str)) < 0)
            st = jfail(j, 0, PERSP_ERR_NOT_FOUND, "no material named '%s' in \"materials\"",
                       qs(str, q));
        pop(j);
    }
    return st;
}

/* The "mesh" value (its key on the path): a primitive name, a model file
 * name, or an object with "file" or "primitive" (*params: that object, for
 * the primitive's parameters). */
static persp_status read_mesh_ref(jctx *j, json_t *v, const char **file, const char **prim, json_t **params)
{
    const char *str = NULL;
    persp_status st = PERSP_OK;
    if (json_is_string(v)) {
        st = read_string(j, v, &str);
        if (st == PERSP_OK) {
            if (is_primitive(str)) *prim = str;
            else *file = str;
        }
    } else if (json_is_object(v)) {
        json_t *f = json_object_get(v, "file"), *p = json_object_get(v, "primitive");
        if (f && !p) {
            static const char *const fkeys[] = {"file", NULL};
            st = check_keys(j, v, fkeys);
            push_key(j, "file");
            if (st == PERSP_OK) st = read_string(j, f, file);
            pop(j);
        } else if (p && !f) {
            push_key(j, "primitive");
            st = read_string(j, p, prim);
            pop(j);
            *params = v;
        } else {
            st = jfail(j, 0, PERSP_ERR_FORMAT, "expected exactly one of 'file' and 'primitive'");
        }
    } else {
        st = jfail(j, 0, PERSP_ERR_FORMAT,
                   "expected a primitive name, a model file name or an object");
    }
    return st;
}

/* A primitive's mesh and its object; takes the "mesh" key off the path. */
static persp_status add_primitive_object(jctx *j, persp_object *obj, const char *prim, json_t *params,
                                         int material)
{
    persp_mesh mesh;
    persp_status st = make_primitive(j, prim, params, &mesh);
    pop(j);
    if (st != PERSP_OK) return st;
    if (material < 0) {
        persp_material m = persp__material_default();
        if ((st = persp__scene_add_material(j->scene, &m, &material)) != PERSP_OK) return st;
    }
    if ((st = persp__scene_add_mesh(j->scene, &mesh, &obj->mesh)) != PERSP_OK) return st;
    obj->material = material;
    return persp__scene_add_object(j->scene, obj);
}

/* A model file's meshes, one object a part, placed by the object's
 * transform; takes the "mesh" key (and "file" where sub) off the path. */
static persp_status add_model_objects(jctx *j, persp_object *obj, const char *file, int sub, int material)
{
    char path[PERSP_PATH_MAX];
    if (sub) push_key(j, "file");
    persp_status st = resolve_file(j, file, path, sizeof path);
    persp_model res;
    size_t before = j->scene->mesh_count;
    if (st == PERSP_OK)
        st = persp__model_load_file(j->scene, path, &j->cache, j->max_vertices - j->vertices, &res);
    /* A model that cannot be opened is pointed at in the scene, as a
     * missing texture is; the model's own errors name its file and line. */
    if (st == PERSP_ERR_IO && strncmp(persp_context_error(j->ctx), j->name, strlen(j->name)) != 0)
        st = jwrap(j, st);
    if (sub) pop(j);
    pop(j);
    if (st != PERSP_OK) return st;
    for (size_t i = before; i < j->scene->mesh_count && st == PERSP_OK; i++) {
        push_key(j, "mesh");
        st = count_vertices(j, j->scene->meshes[i].vertex_count);
        pop(j);
    }
    if (st == PERSP_OK) persp__model_warn_no_uv(j->scene, &res, path, material, (int)obj->texgen);
    persp_mat4 placed = obj->model;
    for (size_t i = 0; i < res.part_count && st == PERSP_OK; i++) {
        obj->mesh = res.parts[i].mesh;
        obj->material = material >= 0 ? material : res.parts[i].material;
        obj->model = persp_mat4_mul(placed, res.parts[i].transform);
        st = persp__scene_add_object(j->scene, obj);
    }
    persp__model_free(j->ctx, &res);
    return st;
}

static persp_status parse_object(jctx *j, json_t *o)
{
    static const char *const keys[] = {"name", "mesh", "transform", "material", "texgen", NULL};
    persp_status st = check_keys(j, o, keys);
    if (st != PERSP_OK) return st;
    persp_object obj;
    memset(&obj, 0, sizeof obj);
    obj.model = persp_mat4_identity();
    obj.texgen_axis = 1;
    int material = -1;
    if ((st = parse_object_settings(j, o, &obj, &material)) != PERSP_OK) return st;
    json_t *v = field(j, o, "mesh");
    if (!v) return jfail(j, 0, PERSP_ERR_FORMAT, "missing key 'mesh'");
    const char *file = NULL, *prim = NULL;
    json_t *params = NULL;
    if ((st = read_mesh_ref(j, v, &file, &prim, &params)) != PERSP_OK) {
        pop(j);
        return st;
    }
    if (prim) return add_primitive_object(j, &obj, prim, params, material);
    return add_model_objects(j, &obj, file, json_is_object(v), material);
}

static persp_status parse_objects(jctx *j, json_t *a)
{
    if (!json_is_array(a)) return jfail(j, 0, PERSP_ERR_FORMAT, "expected an array of objects");
    if (json_array_size(a) > PERSP_SCENE_MAX_OBJECTS)
        return jfail(j, 0, PERSP_ERR_TOO_LARGE, "more than %d objects", PERSP_SCENE_MAX_OBJECTS);
    for (size_t i = 0; i < json_array_size(a); i++) {
        push_index(j, i);
        persp_status st = parse_object(j, json_array_get(a, i));
        pop(j);
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static persp_status parse_root(jctx *j, json_t *root)
{
    static const char *const keys[] = {"camera", "render", "ambient", "lights", "materials", "objects", NULL};
    persp_status st = check_keys(j, root, keys);
    if (st != PERSP_OK) return st;
    json_t *v;
    /* render first: its filter is the default of the materials' textures. */
    static const char *const order[] = {"render", "camera", "lights", "materials", "objects"};
    for (size_t i = 0; i < sizeof order / sizeof order[0]; i++) {
        if (!(v = field(j, root, order[i]))) continue;
        switch (i) {
        case 0: st = parse_render(j, v); break;
        case 1: st = parse_camera(j, v); break;
        case 2: st = parse_lights(j, v); break;
        case 3: st = parse_materials(j, v); break;
        default: st = parse_objects(j, v); break;
        }
        pop(j);
        if (st != PERSP_OK) return st;
    }
    if ((st = field_vec(j, root, "ambient", 3, 0, LARGE, j->scene->ambient)) != PERSP_OK) return st;
    if (!json_object_get(root, "objects") || j->scene->object_count == 0)
        return jfail(j, 0, PERSP_ERR_FORMAT, "the scene has no objects (key 'objects')");
    /* The render section's filter is the default of every texture that
     * chose none, those of MTL files included (docs/SCENES.md). */
    persp_scene *sc = j->scene;
    for (size_t i = 0; i < sc->material_count && sc->filter != PERSP_FILTER_DEFAULT; i++) {
        persp_material *m = &sc->materials[i];
        if (m->sampler.filter != PERSP_FILTER_DEFAULT) continue;
        m->sampler.filter = sc->filter;
        m->sampler.max_aniso = sc->max_aniso;
    }
    return PERSP_OK;
}

static persp_status load_json(persp_context *ctx, const char *data, size_t size, const char *name,
                              const char *base_dir, const char *allowed, size_t max_vertices,
                              const persp_scene_load_desc *desc, persp_scene **out)
{
    if (!ctx || (!data && size) || !out) return PERSP_ERR_INVALID_ARGUMENT;
    *out = NULL;
    jctx j;
    memset(&j, 0, sizeof j);
    j.ctx = ctx;
    j.name = name ? name : "<scene>";
    j.text = data ? data : "";
    j.size = size;
    j.base_dir = base_dir;
    j.max_vertices = max_vertices ? max_vertices : PERSP_SCENE_MAX_VERTICES;
    json_error_t err;
    char what[PERSP_ERRMSG_BYTES / 2];
    snprintf(what, sizeof what, "%s: parsing the JSON", j.name);
    size_t parse_bytes = persp__json_parse_bound(j.text, size);
    persp_status rst = persp__mem_reserve(ctx, parse_bytes, what);
    if (rst != PERSP_OK) return rst;
    json_t *root = json_loadb(j.text, size, JSON_REJECT_DUPLICATES, &err);
    if (!root) persp__mem_release(ctx, parse_bytes);
    if (!root && persp__json_parse_ran_out(j.text, size, &err))
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory parsing the JSON",
                           j.name);
    if (root && !persp__json_tree_matches(ctx, j.text, size, root)) {
        json_decref(root);
        persp__mem_release(ctx, parse_bytes);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory parsing the JSON",
                           j.name);
    }
    if (!root) {
        char q[PERSP_QUOTE_BYTES * 2];
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s:%d:%d: invalid JSON: %s%s", j.name, err.line,
                           err.column, persp__quote(err.text, strlen(err.text), q, sizeof q),
                           persp__json_trailing_comma(j.text, size, err.position)
                               ? " (a comma before the closing bracket: JSON allows none)"
                               : "");
    }
    persp_status st = persp__scene_new(ctx, &j.scene);
    if (st == PERSP_OK) {
        j.scene->load_root = allowed;
        j.scene->load_desc = desc;
        st = parse_root(&j, root);
        j.scene->load_root = NULL;
        j.scene->load_desc = NULL;
    }
    json_decref(root);
    persp__mem_release(ctx, parse_bytes);
    persp__texcache_free(ctx, &j.cache);
    persp__free(ctx, j.mats);
    if (st != PERSP_OK) {
        persp_scene_destroy(j.scene);
        return st;
    }
    *out = j.scene;
    return PERSP_OK;
}

persp_status persp__scene_load_memory(persp_context *ctx, const char *data, size_t size,
                                      const char *name, const char *base_dir, size_t max_vertices,
                                      persp_scene **out)
{
    return load_json(ctx, data, size, name, base_dir, NULL, max_vertices, NULL, out);
}

static persp_status load_ex(persp_context *ctx, const char *path, const persp_scene_load_desc *desc,
                            persp_scene **out)
{
    persp__clear_error(ctx);
    if (!path || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "scene: no path or no scene to fill");
    *out = NULL;
    if (desc && (unsigned)desc->any_folder > (unsigned)PERSP_TOGGLE_OFF)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "invalid persp_scene_load_desc.any_folder");
    if (desc && (unsigned)desc->model_up > (unsigned)PERSP_MODEL_UP_NEG_Z)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "invalid persp_scene_load_desc.model_up");
    if (desc && (unsigned)desc->import > (unsigned)PERSP_MODEL_IMPORT_IN_PROCESS)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "invalid persp_scene_load_desc.import");
    if (desc && !(desc->crease_deg >= 0.0f && desc->crease_deg <= 180.0f))
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "invalid persp_scene_load_desc.crease_deg (0 to 180)");
    if (desc && (unsigned)desc->formats > (unsigned)PERSP_MODEL_FORMATS_ALL)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "invalid persp_scene_load_desc.formats");
    char root[PERSP_PATH_MAX];
    const int restricted = !desc || desc->any_folder != PERSP_TOGGLE_ON;
    char *data = NULL;
    size_t size = 0;
    /* An OBJ model is streamed by its reader, not read whole here. */
    const int stream = persp__model_streams(path);
    persp_status st = stream ? PERSP_OK : persp__read_file(ctx, path, &data, &size);
    if (st == PERSP_OK && restricted) st = persp__path_root(ctx, path, root, sizeof root);
    if (st != PERSP_OK) {
        persp__free(ctx, data);
        return st;
    }
    const char *allowed = restricted ? root : NULL;
    char dir[PERSP_PATH_MAX];
    persp__path_dir(path, dir, sizeof dir);
    if (stream || persp__model_is_model(path, data, size))
        return persp__scene_from_model(ctx, data, size, path, dir[0] ? dir : "./", allowed, desc, out);
    st = load_json(ctx, data, size, path, dir[0] ? dir : "./", allowed, 0, desc, out);
    persp__free(ctx, data);
    return st;
}

persp_status persp_scene_load_ex(persp_context *ctx, const char *path,
                                 const persp_scene_load_desc *desc, persp_scene **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    /* A file that fails ends with its error alone: the warnings of its
     * load (a missing texture, then a face out of range) are given only
     * when it has loaded. */
    persp__warn_hold(ctx);
    persp_status st = load_ex(ctx, path, desc, out);
    persp__warn_release(ctx, st == PERSP_OK);
    return st;
}

persp_status persp_scene_load(persp_context *ctx, const char *path, persp_scene **out)
{
    return persp_scene_load_ex(ctx, path, NULL, out);
}
