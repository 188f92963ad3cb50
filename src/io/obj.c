/*
 * Wavefront OBJ reader, polygonal subset: v (optionally with w or an r g b
 * colour), vt, vn, f in the forms v, v/vt, v//vn, v/vt/vn with positive or
 * negative (relative) indices, g, o, s, usemtl and mtllib. Polygons become
 * triangle fans (v0, v1, v2), (v0, v2, v3), ... which is exact for the
 * convex polygons the format expects. Each distinct (v, vt, vn) triple of a
 * material becomes one persp_vertex so that smooth normals can be computed
 * across shared corners.
 */
#include "core/internal.h"
#include "io/obj.h"
#include "io/text.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

typedef struct obj_key {
    int32_t v, t, n; /* 0-based; t, n = -1 when absent */
} obj_key;

typedef struct obj_part {
    int lib_entry; /* persp_mtl_lib entry, -1: default material */
    persp_vertex *verts;
    size_t nverts, capverts;
    uint32_t *idx;
    size_t nidx, capidx;
    obj_key *keys;   /* the (v, vt, vn) triple of each vertex */
    size_t capkeys;
    uint32_t *table; /* open addressing: vertex index + 1, 0 = empty */
    size_t tabcap;
    int missing_normals;
} obj_part;

typedef struct obj_parser {
    persp_scene *scene;
    persp_context *ctx;
    const char *name, *base_dir;
    persp_texcache *cache;
    persp_line_cursor cur;
    float *pos, *col; /* 3 per v; col NULL until a v has a colour */
    float *tex;       /* 2 per vt */
    float *nrm;       /* 3 per vn */
    size_t npos, cappos, ntex, captex, nnrm, capnrm, capcol;
    obj_part *parts;
    size_t nparts, capparts;
    int current; /* part index, -1: none yet */
    persp_mtl_lib lib;
    int lib_files; /* mtllib files actually read */
    uint32_t *face;
    size_t capface;
} obj_parser;

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static persp_status fail(obj_parser *p, persp_status st, size_t col, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    persp_status r = persp__text_failv(p->ctx, st, p->name, p->cur.lineno, col, fmt, ap);
    va_end(ap);
    return r;
}

/* Grows *arr to hold need elements, refusing past limit before anything is
 * allocated. */
static int reserve(persp_context *ctx, void **arr, size_t *cap, size_t need, size_t elem, size_t limit)
{
    return need <= limit && persp__grow(ctx, arr, cap, need, elem) == PERSP_OK;
}

static persp_status numbers(obj_parser *p, const char *kw, float *out, int max, int *count)
{
    int n = 0;
    for (;;) {
        const char *tok;
        size_t col, len = persp__token(&p->cur, &tok, &col);
        if (len == 0 || tok[0] == '#') break;
        if (n == max) return fail(p, PERSP_ERR_FORMAT, col, "expected the end of the line after '%s' data", kw);
        if (!persp__parse_float(tok, len, &out[n]))
            return fail(p, PERSP_ERR_FORMAT, col, "expected a finite number after '%s', found '%.*s'", kw,
                        (int)(len > 32 ? 32 : len), tok);
        n++;
    }
    *count = n;
    return PERSP_OK;
}

static persp_status vertex_statement(obj_parser *p, size_t kwcol)
{
    float v[6];
    int n = 0;
    persp_status st = numbers(p, "v", v, 6, &n);
    if (st != PERSP_OK) return st;
    if (n < 3)
        return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected a number after 'v' (3 coordinates)");
    if (n == 5) return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected x y z [w] or x y z r g b after 'v'");
    if (!reserve(p->ctx, (void **)&p->pos, &p->cappos, p->npos + 1, 3 * sizeof(float), PERSP_SCENE_MAX_VERTICES))
        return fail(p, p->npos + 1 > PERSP_SCENE_MAX_VERTICES ? PERSP_ERR_TOO_LARGE : PERSP_ERR_OUT_OF_MEMORY, kwcol,
                    "more than %u vertex positions, or out of memory", PERSP_SCENE_MAX_VERTICES);
    memcpy(&p->pos[3 * p->npos], v, 3 * sizeof(float));
    /* x y z r g b: a common extension carrying a vertex colour. */
    if (n >= 6 || p->col) {
        int first = p->col == NULL;
        if (!reserve(p->ctx, (void **)&p->col, &p->capcol, p->cappos, 3 * sizeof(float), PERSP_SCENE_MAX_VERTICES))
            return fail(p, PERSP_ERR_OUT_OF_MEMORY, kwcol, "out of memory");
        /* Earlier vertices had no colour: mark them so they stay white. */
        if (first)
            for (size_t i = 0; i < 3 * p->npos; i++) p->col[i] = -1.0f;
        float *c = &p->col[3 * p->npos];
        if (n >= 6) {
            c[0] = v[3], c[1] = v[4], c[2] = v[5];
        } else {
            c[0] = c[1] = c[2] = -1.0f; /* none: white */
        }
    }
    p->npos++;
    return PERSP_OK;
}

static persp_status part_for(obj_parser *p, int lib_entry, size_t col)
{
    for (size_t i = 0; i < p->nparts; i++)
        if (p->parts[i].lib_entry == lib_entry) {
            p->current = (int)i;
            return PERSP_OK;
        }
    if (!reserve(p->ctx, (void **)&p->parts, &p->capparts, p->nparts + 1, sizeof *p->parts, PERSP_SCENE_MAX_OBJECTS))
        return fail(p, PERSP_ERR_TOO_LARGE, col, "too many materials in use");
    memset(&p->parts[p->nparts], 0, sizeof p->parts[0]);
    p->parts[p->nparts].lib_entry = lib_entry;
    p->current = (int)p->nparts++;
    return PERSP_OK;
}

static size_t hash_key(obj_key k)
{
    uint64_t h = (uint32_t)k.v * 0x9E3779B97F4A7C15ull;
    h ^= ((uint64_t)(uint32_t)k.t + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull;
    h ^= ((uint64_t)(uint32_t)k.n + 0x85EBCA77C2B2AE63ull) * 0x94D049BB133111EBull;
    return (size_t)(h ^ (h >> 31));
}

/* Vertex index of the corner k in part, creating it on first use. The
 * table holds vertex indices only; the keys live in part->keys. It is kept
 * at most half full so probes stay short. */
static persp_status corner_vertex(obj_parser *p, obj_part *part, obj_key k, size_t col, uint32_t *out)
{
    if (2 * (part->nverts + 1) > part->tabcap) {
        size_t cap = part->tabcap ? part->tabcap * 2 : 256;
        uint32_t *t = persp__calloc(p->ctx, cap, sizeof *t);
        if (!t) return fail(p, PERSP_ERR_OUT_OF_MEMORY, col, "out of memory");
        persp__free(p->ctx, part->table);
        part->table = t;
        part->tabcap = cap;
        for (size_t i = 0; i < part->nverts; i++) {
            size_t h = hash_key(part->keys[i]) & (cap - 1);
            while (part->table[h]) h = (h + 1) & (cap - 1);
            part->table[h] = (uint32_t)i + 1;
        }
    }
    size_t mask = part->tabcap - 1, h = hash_key(k) & mask;
    while (part->table[h]) {
        obj_key o = part->keys[part->table[h] - 1];
        if (o.v == k.v && o.t == k.t && o.n == k.n) {
            *out = part->table[h] - 1;
            return PERSP_OK;
        }
        h = (h + 1) & mask;
    }
    if (!reserve(p->ctx, (void **)&part->verts, &part->capverts, part->nverts + 1, sizeof *part->verts,
                 PERSP_SCENE_MAX_VERTICES) ||
        !reserve(p->ctx, (void **)&part->keys, &part->capkeys, part->nverts + 1, sizeof *part->keys,
                 PERSP_SCENE_MAX_VERTICES))
        return fail(p, part->nverts + 1 > PERSP_SCENE_MAX_VERTICES ? PERSP_ERR_TOO_LARGE : PERSP_ERR_OUT_OF_MEMORY,
                    col, "more than %u distinct vertices, or out of memory", PERSP_SCENE_MAX_VERTICES);
    persp_vertex *v = &part->verts[part->nverts];
    memset(v, 0, sizeof *v);
    memcpy(v->pos, &p->pos[3 * (size_t)k.v], 3 * sizeof(float));
    if (k.t >= 0) memcpy(v->uv, &p->tex[2 * (size_t)k.t], 2 * sizeof(float));
    if (k.n >= 0) memcpy(v->normal, &p->nrm[3 * (size_t)k.n], 3 * sizeof(float));
    else part->missing_normals = 1;
    v->color[0] = v->color[1] = v->color[2] = v->color[3] = 1.0f;
    if (p->col && p->col[3 * (size_t)k.v] >= 0.0f) memcpy(v->color, &p->col[3 * (size_t)k.v], 3 * sizeof(float));
    part->keys[part->nverts] = k;
    part->table[h] = (uint32_t)part->nverts + 1;
    *out = (uint32_t)part->nverts++;
    return PERSP_OK;
}

/* One index field: 1-based, or negative counting back from the last element
 * defined so far (OBJ spec, "Referencing vertex data"). */
static persp_status resolve_index(obj_parser *p, const char *s, size_t len, size_t col, size_t count,
                                  const char *what, int32_t *out)
{
    long i;
    if (!persp__parse_long(s, len, 1L << 40, &i))
        return fail(p, PERSP_ERR_FORMAT, col, "expected a %s index, found '%.*s'", what, (int)(len > 32 ? 32 : len), s);
    if (i == 0) return fail(p, PERSP_ERR_FORMAT, col, "%s index 0 is invalid (indices start at 1)", what);
    long r = i > 0 ? i - 1 : (long)count + i;
    if (r < 0 || (size_t)r >= count)
        return fail(p, PERSP_ERR_FORMAT, col, "%s index %ld out of range (%zu defined so far)", what, i, count);
    *out = (int32_t)r;
    return PERSP_OK;
}

static persp_status face_statement(obj_parser *p, size_t kwcol)
{
    if (p->current < 0) {
        persp_status st = part_for(p, -1, kwcol);
        if (st != PERSP_OK) return st;
    }
    obj_part *part = &p->parts[p->current];
    size_t n = 0;
    for (;;) {
        const char *tok;
        size_t col, len = persp__token(&p->cur, &tok, &col);
        if (len == 0 || tok[0] == '#') break;
        obj_key k = {-1, -1, -1};
        const char *s1 = memchr(tok, '/', len);
        size_t l0 = s1 ? (size_t)(s1 - tok) : len;
        persp_status st = resolve_index(p, tok, l0, col, p->npos, "vertex", &k.v);
        if (st != PERSP_OK) return st;
        if (s1) {
            const char *f1 = s1 + 1, *end = tok + len;
            const char *s2 = memchr(f1, '/', (size_t)(end - f1));
            size_t l1 = s2 ? (size_t)(s2 - f1) : (size_t)(end - f1);
            if (l1 > 0) {
                st = resolve_index(p, f1, l1, col + (size_t)(f1 - tok), p->ntex, "texture", &k.t);
                if (st != PERSP_OK) return st;
            } else if (!s2) {
                return fail(p, PERSP_ERR_FORMAT, col + (size_t)(f1 - tok), "expected a texture index after '/'");
            }
            if (s2) {
                const char *f2 = s2 + 1;
                size_t l2 = (size_t)(end - f2);
                if (l2 == 0) return fail(p, PERSP_ERR_FORMAT, col + (size_t)(f2 - tok), "expected a normal index after '/'");
                if (memchr(f2, '/', l2))
                    return fail(p, PERSP_ERR_FORMAT, col, "expected v, v/vt, v//vn or v/vt/vn");
                st = resolve_index(p, f2, l2, col + (size_t)(f2 - tok), p->nnrm, "normal", &k.n);
                if (st != PERSP_OK) return st;
            }
        }
        uint32_t vi = 0;
        st = corner_vertex(p, part, k, col, &vi);
        if (st != PERSP_OK) return st;
        if (!reserve(p->ctx, (void **)&p->face, &p->capface, n + 1, sizeof *p->face, PERSP_SCENE_MAX_INDICES))
            return fail(p, PERSP_ERR_OUT_OF_MEMORY, col, "out of memory");
        p->face[n++] = vi;
    }
    if (n < 3)
        return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected at least 3 vertices after 'f' (found %zu)", n);
    size_t add = 3 * (n - 2);
    if (!reserve(p->ctx, (void **)&part->idx, &part->capidx, part->nidx + add, sizeof *part->idx,
                 PERSP_SCENE_MAX_INDICES))
        return fail(p, part->nidx + add > PERSP_SCENE_MAX_INDICES ? PERSP_ERR_TOO_LARGE : PERSP_ERR_OUT_OF_MEMORY,
                    kwcol, "more than %u indices, or out of memory", PERSP_SCENE_MAX_INDICES);
    for (size_t i = 1; i + 1 < n; i++) {
        part->idx[part->nidx++] = p->face[0];
        part->idx[part->nidx++] = p->face[i];
        part->idx[part->nidx++] = p->face[i + 1];
    }
    return PERSP_OK;
}

static persp_status mtllib_statement(obj_parser *p, size_t kwcol)
{
    const char *tok;
    size_t col, len;
    int any = 0;
    while ((len = persp__token(&p->cur, &tok, &col)) != 0 && tok[0] != '#') {
        any = 1;
        if (!p->base_dir) continue;
        char rel[PERSP_PATH_MAX], path[PERSP_PATH_MAX], dir[PERSP_PATH_MAX];
        if (len >= sizeof rel) return fail(p, PERSP_ERR_FORMAT, col, "file name too long");
        memcpy(rel, tok, len);
        rel[len] = '\0';
        if (strlen(rel) != len) return fail(p, PERSP_ERR_FORMAT, col, "file name contains a NUL byte");
        if (!persp__path_join(p->base_dir, rel, path, sizeof path))
            return fail(p, PERSP_ERR_FORMAT, col, "file name too long");
        char *data = NULL;
        size_t size = 0;
        persp_status st = persp__read_file(p->ctx, path, &data, &size);
        if (st != PERSP_OK) {
            char inner[PERSP_ERRMSG_BYTES];
            snprintf(inner, sizeof inner, "%s", persp_context_error(p->ctx));
            return fail(p, st, col, "cannot read material library '%s': %s", rel, inner);
        }
        persp__path_dir(path, dir, sizeof dir);
        st = persp__mtl_load_memory(p->scene, data, size, path, dir, &p->lib, p->cache);
        persp__free(p->ctx, data);
        if (st != PERSP_OK) return st;
        p->lib_files++;
    }
    if (!any) return fail(p, PERSP_ERR_FORMAT, kwcol + 6, "expected a file name after 'mtllib'");
    return PERSP_OK;
}

static persp_status usemtl_statement(obj_parser *p)
{
    const char *tok;
    size_t col, len = persp__token(&p->cur, &tok, &col);
    if (len == 0 || tok[0] == '#') return fail(p, PERSP_ERR_FORMAT, col, "expected a material name after 'usemtl'");
    int entry = persp__mtl_find(&p->lib, tok, len);
    /* Without files (parsing from memory only) names cannot be resolved. */
    if (entry < 0 && p->base_dir)
        return fail(p, PERSP_ERR_NOT_FOUND, col, "unknown material '%.*s' (not defined by any mtllib file)",
                    (int)(len > 64 ? 64 : len), tok);
    return part_for(p, entry, col);
}

/* Statements of the format that do not describe polygons persp draws
 * (smoothing groups: normals are computed smooth; lines, points, display
 * attributes) are accepted and skipped. Free-form geometry is refused. */
static int ignored_statement(const char *kw, size_t len)
{
    static const char *const names[] = {"s",        "g",         "o",   "l",     "p",        "vp",      "mg",
                                        "usemap",   "maplib",    "lod", "bevel", "c_interp", "d_interp", "call",
                                        "csh",      "shadow_obj", "trace_obj"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (persp__keyword_is(kw, len, names[i])) return 1;
    return 0;
}

static int freeform_statement(const char *kw, size_t len)
{
    static const char *const names[] = {"cstype", "deg", "bmat", "step", "curv", "curv2", "surf",
                                        "parm",   "trim", "hole", "scrv", "sp",   "end",   "con"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (persp__keyword_is(kw, len, names[i])) return 1;
    return 0;
}

static persp_status parse(obj_parser *p, const char *data, size_t size)
{
    size_t offset = 0;
    while (persp__next_line(data, size, &offset, &p->cur)) {
        const char *kw;
        size_t col, len = persp__token(&p->cur, &kw, &col);
        if (len == 0 || kw[0] == '#') continue;
        persp_status st = PERSP_OK;
        int n = 0;
        float v[3];
        if (persp__keyword_is(kw, len, "v")) {
            st = vertex_statement(p, col);
        } else if (persp__keyword_is(kw, len, "vt")) {
            if ((st = numbers(p, "vt", v, 3, &n)) != PERSP_OK) return st;
            if (n < 1) return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected a number after 'vt'");
            if (n == 1) v[1] = 0.0f;
            if (!reserve(p->ctx, (void **)&p->tex, &p->captex, p->ntex + 1, 2 * sizeof(float), PERSP_SCENE_MAX_VERTICES))
                return fail(p, PERSP_ERR_TOO_LARGE, col, "more than %u texture coordinates, or out of memory",
                            PERSP_SCENE_MAX_VERTICES);
            memcpy(&p->tex[2 * p->ntex++], v, 2 * sizeof(float));
        } else if (persp__keyword_is(kw, len, "vn")) {
            if ((st = numbers(p, "vn", v, 3, &n)) != PERSP_OK) return st;
            if (n < 3)
                return fail(p, PERSP_ERR_FORMAT, persp__column(&p->cur), "expected a number after 'vn' (3 components)");
            if (!reserve(p->ctx, (void **)&p->nrm, &p->capnrm, p->nnrm + 1, 3 * sizeof(float), PERSP_SCENE_MAX_VERTICES))
                return fail(p, PERSP_ERR_TOO_LARGE, col, "more than %u normals, or out of memory",
                            PERSP_SCENE_MAX_VERTICES);
            memcpy(&p->nrm[3 * p->nnrm++], v, 3 * sizeof(float));
        } else if (persp__keyword_is(kw, len, "f") || persp__keyword_is(kw, len, "fo")) {
            st = face_statement(p, col);
        } else if (persp__keyword_is(kw, len, "usemtl")) {
            st = usemtl_statement(p);
        } else if (persp__keyword_is(kw, len, "mtllib")) {
            st = mtllib_statement(p, col);
        } else if (ignored_statement(kw, len)) {
            p->cur.pos = p->cur.len;
        } else if (freeform_statement(kw, len)) {
            return fail(p, PERSP_ERR_UNSUPPORTED, col, "free-form geometry ('%.*s') is not supported", (int)len, kw);
        } else {
            return fail(p, PERSP_ERR_FORMAT, col, "unknown statement '%.*s'", (int)(len > 32 ? 32 : len), kw);
        }
        if (st != PERSP_OK) return st;
    }
    return PERSP_OK;
}

static void parser_free(obj_parser *p)
{
    for (size_t i = 0; i < p->nparts; i++) {
        persp__free(p->ctx, p->parts[i].verts);
        persp__free(p->ctx, p->parts[i].idx);
        persp__free(p->ctx, p->parts[i].table);
        persp__free(p->ctx, p->parts[i].keys);
    }
    persp__free(p->ctx, p->parts);
    persp__free(p->ctx, p->pos);
    persp__free(p->ctx, p->col);
    persp__free(p->ctx, p->tex);
    persp__free(p->ctx, p->nrm);
    persp__free(p->ctx, p->face);
    persp__mtl_lib_free(p->ctx, &p->lib);
}

/* Moves the parts into the scene as meshes and records (mesh, material). */
static persp_status commit(obj_parser *p, persp_obj_result *res)
{
    int default_material = -1;
    size_t used = 0;
    for (size_t i = 0; i < p->nparts; i++) used += p->parts[i].nidx > 0;
    if (used == 0) return persp__fail(p->ctx, PERSP_ERR_FORMAT, "%s: no faces", p->name);
    res->parts = persp__calloc(p->ctx, used, sizeof *res->parts);
    if (!res->parts) return persp__fail(p->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", p->name);
    for (size_t i = 0; i < p->nparts; i++) {
        obj_part *part = &p->parts[i];
        if (part->nidx == 0) continue;
        int material;
        if (part->lib_entry >= 0) {
            material = p->lib.entries[part->lib_entry].material;
        } else {
            if (default_material < 0) {
                persp_material m = persp__material_default();
                persp_status st = persp__scene_add_material(p->scene, &m, &default_material);
                if (st != PERSP_OK) return st;
            }
            material = default_material;
        }
        persp_mesh mesh;
        memset(&mesh, 0, sizeof mesh);
        mesh.vertices = part->verts;
        mesh.vertex_count = part->nverts;
        mesh.indices = part->idx;
        mesh.index_count = part->nidx;
        mesh.has_normals = !part->missing_normals;
        part->verts = NULL;
        part->idx = NULL;
        if (part->missing_normals) persp__mesh_compute_normals(&mesh);
        int index;
        persp_status st = persp__scene_add_mesh(p->scene, &mesh, &index);
        if (st != PERSP_OK) return st;
        res->parts[res->part_count].mesh = index;
        res->parts[res->part_count].material = material;
        res->part_count++;
    }
    return PERSP_OK;
}

persp_status persp__obj_load_memory(persp_scene *scene, const char *data, size_t size, const char *name,
                                    const char *base_dir, persp_texcache *cache, persp_obj_result *res)
{
    if (!scene || (!data && size) || !res) return PERSP_ERR_INVALID_ARGUMENT;
    memset(res, 0, sizeof *res);
    obj_parser p;
    memset(&p, 0, sizeof p);
    p.scene = scene;
    p.ctx = scene->ctx;
    p.name = name ? name : "<obj>";
    p.base_dir = base_dir;
    p.cache = cache;
    p.current = -1;
    persp_status st = parse(&p, data ? data : "", size);
    if (st == PERSP_OK) st = commit(&p, res);
    if (st != PERSP_OK) persp__obj_result_free(p.ctx, res);
    parser_free(&p);
    return st;
}

persp_status persp__obj_load_file(persp_scene *scene, const char *path, persp_texcache *cache,
                                  persp_obj_result *res)
{
    char *data = NULL;
    size_t size = 0;
    persp_status st = persp__read_file(scene->ctx, path, &data, &size);
    if (st != PERSP_OK) return st;
    char dir[PERSP_PATH_MAX];
    persp__path_dir(path, dir, sizeof dir);
    st = persp__obj_load_memory(scene, data, size, path, dir[0] ? dir : "./", cache, res);
    persp__free(scene->ctx, data);
    return st;
}

void persp__obj_result_free(persp_context *ctx, persp_obj_result *res)
{
    if (!res) return;
    persp__free(ctx, res->parts);
    memset(res, 0, sizeof *res);
}
