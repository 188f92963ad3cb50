/*
 * Models through Assimp: every format Assimp reads (glTF 2.0 and GLB, PLY,
 * STL, FBX, COLLADA, 3DS, ...) becomes persp meshes, materials and
 * textures. OBJ/MTL goes to persp's own reader (src/model/obj.c); what the
 * two share (the files a model names, colours, parts) is in
 * src/model/model_refs.c.
 *
 * Assimp itself runs in persp-import, a process of its own with limits
 * (src/model/import_run.c), or on request on a thread of this one; the two
 * talk over a socket (src/model/import_wire.h). This side picks the reader
 * (the formats enabled, the content agreeing with the name), sends the
 * model, serves the files the model names from the model's folder (Assimp
 * opens none itself), checks everything that comes back before it is used
 * and builds the scene from it. Textures are decoded here by persp
 * (persp_image_load / _load_memory), so the image limits and decoders are
 * the same as everywhere else.
 */
#include "core/internal.h"
#include "model/import_run.h"
#include "model/import_wire.h"
#include "model/model.h"
#include "model/obj.h"
#include "io/text.h"

#include <assimp/cimport.h>

#include <ctype.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Assimp's C API keeps the last error message in a process-wide string;
 * imports in this process (PERSP_MODEL_IMPORT_IN_PROCESS) take turns so
 * that each reads its own. Imports in persp-import need no turn. */
static pthread_mutex_t import_lock = PTHREAD_MUTEX_INITIALIZER;

/* ---------------------------------------------------------- text cleanup */

/* Text formats whose readers stumble on a UTF-8 byte-order mark or on
 * classic Mac line endings (CR only). */
static int is_line_text(const char *name)
{
    return persp__model_has_ext(name, "obj") || persp__model_has_ext(name, "mtl");
}

/* Drops a byte-order mark and turns lone CRs into LFs, in place; returns the
 * new size. */
static size_t normalise_text(char *buf, size_t size, int lines)
{
    size_t start = 0;
    if (size >= 3 && (unsigned char)buf[0] == 0xef && (unsigned char)buf[1] == 0xbb &&
        (unsigned char)buf[2] == 0xbf)
        start = 3;
    if (start) memmove(buf, buf + start, size - start);
    size -= start;
    if (lines)
        for (size_t i = 0; i < size; i++)
            if (buf[i] == '\r' && (i + 1 == size || buf[i + 1] != '\n')) buf[i] = '\n';
    return size;
}

/* Bytes of Assimp's working memory reserved per byte of a model file (see
 * persp__model_load_memory). */
#define MODEL_IMPORT_PER_BYTE 6u

/* Bytes of Assimp's working memory reserved per byte of a model file for
 * an import in this process (persp-import is held by its own limit). */
#define MODEL_IMPORT_PER_BYTE 6u

/* ------------------------------------------------------------ file access */

typedef struct model_io {
    persp_context *ctx;
    const char *display;   /* the model's name in messages */
    const char *data;      /* the main file */
    size_t size;
    const char *base_dir; /* NULL: no other files */
    const char *root;     /* references must resolve inside it; NULL: anywhere */
    char missing[8][256]; /* already noted */
    /* "where: cannot read 'name' (why)" of each file the import could not
     * read: warnings once the import succeeds, the error if it fails for
     * want of one (a glTF buffer), which Assimp itself words as "could not
     * open" after persp had said it goes on without it. */
    char notes[8][PERSP_ERRMSG_BYTES];
    int nmissing;
    int others;           /* files other than the main one were served */
    /* Text files the model named (material libraries, glTF), kept until the
     * load ends: for the line a texture is named on, and to tell whether
     * Assimp's message quotes one of them. */
    struct {
        char name[256];
        char *text;
        size_t size;
    } kept[4];
    int nkept;
    int out_of_memory; /* a file could not be served for want of memory */
    int uri;           /* glTF: the names are URIs (persp__uri_decode) */
} model_io;

/* The line of the model's text where name first appears, 0 when it does
 * not (binary formats, names Assimp built): where the user should look. */
static size_t line_of(const char *data, size_t size, const char *name)
{
    size_t n = strlen(name), line = 1;
    if (!n) return 0;
    for (size_t i = 0; i + n <= size; i++) {
        if (data[i] == '\0') return 0;
        if (data[i] == '\n') line++;
        if (memcmp(data + i, name, n) == 0) return line;
    }
    return 0;
}

/* "model.obj:12" or "room.mtl:8" where the name is found in the model's
 * text or a text file it named, else "model.obj". */
static void where(const model_io *io, const char *name, char *out, size_t cap)
{
    size_t line = line_of(io->data, io->size, name);
    if (line) {
        snprintf(out, cap, "%s:%zu", io->display, line);
        return;
    }
    for (int i = 0; i < io->nkept; i++) {
        if ((line = line_of(io->kept[i].text, io->kept[i].size, name)) != 0) {
            snprintf(out, cap, "%s (via %s:%zu)", io->display, io->kept[i].name, line);
            return;
        }
    }
    snprintf(out, cap, "%s", io->display);
}

/* 1 when msg shares 8 bytes in a row with a kept file other than the model:
 * it may quote that file. */
static int quotes_other(const model_io *io, const char *msg)
{
    size_t n = strlen(msg);
    for (int i = 0; i < io->nkept; i++)
        for (size_t a = 0; a + 8 <= n; a++)
            for (size_t b = 0; b + 8 <= io->kept[i].size; b++)
                if (!memcmp(msg + a, io->kept[i].text + b, 8)) return 1;
    return 0;
}

static void keep_text(model_io *io, const char *rel, const char *text, size_t size)
{
    if (io->nkept >= (int)(sizeof io->kept / sizeof io->kept[0])) return;
    char *copy = persp__alloc(io->ctx, size + 1);
    if (!copy) {
        io->out_of_memory = 1;
        return;
    }
    memcpy(copy, text, size);
    copy[size] = '\0';
    snprintf(io->kept[io->nkept].name, sizeof io->kept[0].name, "%.255s", rel);
    io->kept[io->nkept].text = copy;
    io->kept[io->nkept].size = size;
    io->nkept++;
}

static void free_kept(model_io *io)
{
    for (int i = 0; i < io->nkept; i++)
        persp__free(io->ctx, io->kept[i].text);
    io->nkept = 0;
}


/* Whether the model's own bytes, or a text file it named, hold name (or
 * its last part): a file the user's model names. Readers also look for
 * files nobody named (an .md5anim beside an .md5mesh, SMD animation lists,
 * a model's own name with .mtl); those are no business of the user's. */
static int named(const model_io *io, const char *name)
{
    const char *base = persp__path_base(name);
    const char *const look[2] = {name, base};
    for (int k = 0; k < 2; k++) {
        size_t n = strlen(look[k]);
        if (!n) continue;
        for (size_t i = 0; i + n <= io->size; i++)
            if (io->data[i] == look[k][0] && !memcmp(io->data + i, look[k], n)) return 1;
        for (int t = 0; t < io->nkept; t++)
            for (size_t i = 0; i + n <= io->kept[t].size; i++)
                if (!memcmp(io->kept[t].text + i, look[k], n)) return 1;
    }
    return 0;
}

static void warn_missing(model_io *io, const char *asked, const char *rel, const char *why)
{
    if (!named(io, asked) && !named(io, rel)) return;
    for (int i = 0; i < io->nmissing; i++)
        if (!strcmp(io->missing[i], rel)) return;
    if (io->nmissing >= (int)(sizeof io->missing / sizeof io->missing[0])) return;
    snprintf(io->missing[io->nmissing], sizeof io->missing[0], "%.255s", rel);
    char at[PERSP_PATH_MAX + 32], q[PERSP_QUOTE_BYTES];
    where(io, rel, at, sizeof at);
    snprintf(io->notes[io->nmissing], sizeof io->notes[0], "%.300s: cannot read '%s' (%.64s)", at,
             persp__quote(rel, strlen(rel), q, sizeof q), why);
    io->nmissing++;
}

/* A file the importer asks for: its bytes (the context's, *size of them)
 * or NULL after noting why. Resolved relative to the model's folder,
 * inside the load root, regular files only (persp__model_read_ref). */
static char *serve_file(model_io *io, const char *name, size_t *size)
{
    char rel[PERSP_PATH_MAX];
    char *owned = NULL;
    *size = 0;
    persp__model_clean_rel(name, rel, sizeof rel);
    if (!io->base_dir) {
        warn_missing(io, name, rel, "no folder to read it from");
        return NULL;
    }
    const char *why = NULL;
    char decoded[PERSP_PATH_MAX];
    persp_status st = PERSP_ERR_IO;
    /* A glTF names its buffers by URI; the name as written is the
     * fallback, should a reader have decoded it already. */
    if (io->uri && persp__uri_decode(rel, decoded, sizeof decoded)) {
        st = persp__model_read_ref(io->ctx, io->base_dir, io->root, decoded, &owned, size, &why);
        if (st != PERSP_OK && st != PERSP_ERR_OUT_OF_MEMORY) {
            const char *raw_why = NULL;
            if (persp__model_read_ref(io->ctx, io->base_dir, io->root, rel, &owned, size, &raw_why) ==
                PERSP_OK)
                st = PERSP_OK;
            else
                memcpy(rel, decoded, strlen(decoded) + 1);
        }
    } else {
        st = persp__model_read_ref(io->ctx, io->base_dir, io->root, rel, &owned, size, &why);
    }
    if (st == PERSP_ERR_OUT_OF_MEMORY) {
        io->out_of_memory = 1;
        return NULL;
    }
    if (st != PERSP_OK) {
        warn_missing(io, name, rel, why);
        return NULL;
    }
    io->others = 1;
    if (is_line_text(rel) || persp__model_has_ext(rel, "gltf")) {
        *size = normalise_text(owned, *size, is_line_text(rel));
        keep_text(io, rel, owned, *size);
    }
    return owned;
}

static void where_io(const void *user, const char *rel, char *out, size_t cap)
{
    where((const model_io *)user, rel, out, cap);
}

/* ------------------------------------------------------ the importer's answer */

typedef struct receiver {
    persp_scene *scene;
    persp_context *ctx;
    wire_chan *chan;
    model_io *io;
    const char *display;
    size_t max_vertices, vertices;
    float crease_deg;    /* for meshes without normals (persp__mesh_crease_normals) */
    uint32_t counts[3];  /* meshes, materials, embedded textures of the importer's scene */
    int header;          /* 'H' came */
    int *mesh_index;     /* per importer mesh: scene mesh, -1 not yet */
    int *material_index; /* per importer material: scene material, -1 not yet */
    /* per embedded texture: scene texture, -1 not yet, -2 not decodable,
     * -3 refused for want of memory */
    int *embedded_index;
    persp_model *out;
    size_t part_cap;
    persp_model_refs refs;
    int out_of_memory; /* a texture could not be loaded for want of memory */
    int malformed;     /* the answer broke the protocol: the importer is not trusted further */
    int lost;          /* a read or write failed: the importer ended or the time ran out */
    persp_importer_opts *opts; /* time_limit_ms grows with what is handed over (grant_time) */
    int64_t started_ms;
} receiver;

static persp_status bad_answer(receiver *r, const char *what)
{
    r->malformed = 1;
    return persp__fail(r->ctx, PERSP_ERR_FORMAT,
                       "%s: the model importer's answer is malformed (%s); the file is malformed or "
                       "hostile",
                       r->display, what);
}

/* A failed read: the importer ended or the time ran out (the caller tells
 * which from the channel and the helper's end). */
#define LOST PERSP_ERR_IO

static int get(receiver *r, void *p, size_t n)
{
    if (persp__wire_read(r->chan, p, n)) return 1;
    r->lost = 1;
    return 0;
}

/* A name or message: at most WIRE_MAX_TEXT bytes, no NUL inside. */
static persp_status get_text(receiver *r, char out[WIRE_MAX_TEXT + 1])
{
    uint32_t n;
    if (!get(r, &n, sizeof n)) return LOST;
    if (n > WIRE_MAX_TEXT) return bad_answer(r, "a name too long");
    if (!get(r, out, n)) return LOST;
    out[n] = '\0';
    if (strlen(out) != n) return bad_answer(r, "a name with a NUL byte");
    return PERSP_OK;
}

/* The default limit grows with the bytes handed to the importer (the
 * model, each file it names): big models take long to read, hostile tiny
 * ones do not need to. */
static void grant_time(receiver *r, size_t bytes)
{
    if (!r->opts->time_scales || !r->chan->deadline_ms) return;
    const double more = (double)bytes / (1024.0 * 1024.0) * PERSP_IMPORT_TIME_PER_MIB_MS;
    double limit = (double)r->opts->time_limit_ms + more;
    if (limit > PERSP_IMPORT_TIME_LIMIT_MAX_MS) limit = PERSP_IMPORT_TIME_LIMIT_MAX_MS;
    r->opts->time_limit_ms = (unsigned)limit;
    r->chan->deadline_ms = r->started_ms + r->opts->time_limit_ms;
}

static persp_status answer_file(receiver *r)
{
    char name[WIRE_MAX_TEXT + 1];
    persp_status st = get_text(r, name);
    if (st != PERSP_OK) return st;
    size_t size = 0;
    char *data = name[0] ? serve_file(r->io, name, &size) : NULL;
    uint8_t reply = data ? WIRE_FILE_OK : WIRE_FILE_MISSING;
    uint64_t n = size;
    int ok = persp__wire_write(r->chan, &reply, 1) && (!data || (persp__wire_write(r->chan, &n, sizeof n) &&
                                                                persp__wire_write(r->chan, data, size)));
    persp__free(r->ctx, data);
    if (ok && data) grant_time(r, size);
    if (!ok) r->lost = 1;
    return ok ? PERSP_OK : LOST;
}

static persp_status take_header(receiver *r)
{
    if (r->header) return bad_answer(r, "a second header");
    if (!get(r, r->counts, sizeof r->counts)) return LOST;
    /* Slots for what the importer made: no more than a scene can hold of
     * meshes, and the texture limit of embedded textures, so that a count
     * cannot size the tables by itself. */
    if (r->counts[0] > PERSP_SCENE_MAX_INDICES || r->counts[1] > PERSP_SCENE_MAX_INDICES ||
        r->counts[2] > PERSP_SCENE_MAX_INDICES)
        return persp__fail(r->ctx, PERSP_ERR_TOO_LARGE, "%s: more than %u meshes, materials or textures",
                           r->display, PERSP_SCENE_MAX_INDICES);
    int **slots[3] = {&r->mesh_index, &r->material_index, &r->embedded_index};
    for (int k = 0; k < 3; k++) {
        *slots[k] = persp__calloc(r->ctx, r->counts[k] ? r->counts[k] : 1, sizeof(int));
        if (!*slots[k])
            return persp__fail(r->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", r->display);
        for (uint32_t i = 0; i < r->counts[k]; i++) (*slots[k])[i] = -1;
    }
    r->header = 1;
    return PERSP_OK;
}

static persp_status take_mesh(receiver *r)
{
    uint32_t index;
    uint8_t flags;
    uint64_t nv, ni;
    if (!get(r, &index, sizeof index) || !get(r, &flags, 1) || !get(r, &nv, sizeof nv) ||
        !get(r, &ni, sizeof ni))
        return LOST;
    if (!r->header || index >= r->counts[0] || r->mesh_index[index] != -1)
        return bad_answer(r, "a mesh out of order");
    if (nv == 0 || ni == 0 || ni % 3 != 0) return bad_answer(r, "an empty mesh");
    if (nv > PERSP_SCENE_MAX_VERTICES || nv > r->max_vertices - r->vertices || ni > PERSP_SCENE_MAX_INDICES)
        return persp__fail(r->ctx, PERSP_ERR_TOO_LARGE, "%s: more than %zu vertices or %u triangle corners",
                           r->display, r->max_vertices, PERSP_SCENE_MAX_INDICES);
    persp_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.vertex_count = (size_t)nv;
    mesh.index_count = (size_t)ni;
    mesh.vertices = persp__calloc(r->ctx, mesh.vertex_count, sizeof *mesh.vertices);
    mesh.indices = persp__calloc(r->ctx, mesh.index_count, sizeof *mesh.indices);
    if (!mesh.vertices || !mesh.indices) {
        persp__mesh_free(r->ctx, &mesh);
        return persp__fail(r->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", r->display);
    }
    persp_status st = PERSP_OK;
    float v[256][12];
    for (size_t i = 0; i < mesh.vertex_count && st == PERSP_OK;) {
        size_t n = mesh.vertex_count - i < 256 ? mesh.vertex_count - i : 256;
        if (!get(r, v, n * sizeof v[0])) {
            st = LOST;
            break;
        }
        for (size_t k = 0; k < n; k++, i++) {
            persp_vertex *pv = &mesh.vertices[i];
            for (int c = 0; c < 12; c++)
                if (!isfinite(v[k][c])) st = bad_answer(r, "a number that is not finite");
            memcpy(pv->pos, v[k], 3 * sizeof(float));
            memcpy(pv->normal, v[k] + 3, 3 * sizeof(float));
            memcpy(pv->uv, v[k] + 6, 2 * sizeof(float));
            memcpy(pv->color, v[k] + 8, 4 * sizeof(float));
        }
    }
    for (size_t i = 0; i < mesh.index_count && st == PERSP_OK;) {
        size_t n = mesh.index_count - i < 3072 ? mesh.index_count - i : 3072;
        if (!get(r, mesh.indices + i, n * sizeof *mesh.indices)) {
            st = LOST;
            break;
        }
        for (size_t k = 0; k < n; k++, i++)
            if (mesh.indices[i] >= mesh.vertex_count) st = bad_answer(r, "a vertex index out of range");
    }
    if (st != PERSP_OK) {
        persp__mesh_free(r->ctx, &mesh);
        return st;
    }
    mesh.no_uv = (flags & WIRE_MESH_NO_UV) != 0;
    mesh.has_normals = (flags & WIRE_MESH_NORMALS) != 0;
    if (!mesh.has_normals) {
        st = persp__mesh_crease_normals(r->ctx, &mesh, r->crease_deg, r->max_vertices - r->vertices);
        if (st != PERSP_OK) {
            persp__mesh_free(r->ctx, &mesh);
            if (st == PERSP_ERR_OUT_OF_MEMORY)
                return persp__fail(r->ctx, st, "%s: out of memory making normals", r->display);
            return persp__fail(r->ctx, st, "%s: more than %zu vertices once normals are made", r->display,
                               r->max_vertices);
        }
    }
    r->vertices += mesh.vertex_count;
    return persp__scene_add_mesh(r->scene, &mesh, &r->mesh_index[index]);
}

/* An embedded texture: an encoded image decoded by persp, or RGBA texels. */
static persp_status take_embedded(receiver *r)
{
    uint32_t index, w, h;
    char hint[9];
    if (!get(r, &index, sizeof index) || !get(r, &w, sizeof w) || !get(r, &h, sizeof h) ||
        !get(r, hint, sizeof hint))
        return LOST;
    if (!r->header || index >= r->counts[2] || r->embedded_index[index] != -1)
        return bad_answer(r, "an embedded texture out of order");
    char name[PERSP_PATH_MAX + 48];
    /* The reader's format hint ("png", "jpg", "tga", ...) names it: TGA
     * has no signature and is read by its name (persp_image_load_memory). */
    hint[sizeof hint - 1] = '\0';
    for (size_t k = 0; hint[k]; k++)
        if (!isalnum((unsigned char)hint[k])) hint[k] = '\0';
    snprintf(name, sizeof name, "%s: embedded texture %u%s%s", r->display, index, hint[0] ? "." : "", hint);
    persp_image img;
    memset(&img, 0, sizeof img);
    persp_status st;
    int drained = 0;
    if (h == 0) {
        /* An encoded image is no larger than a text file persp reads. */
        if (w > PERSP_TEXT_MAX_BYTES) return bad_answer(r, "an embedded texture too large");
        char *bytes = persp__alloc(r->ctx, (size_t)w + 1);
        if (!bytes) {
            st = persp__fail(r->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
        } else if (!get(r, bytes, w)) {
            persp__free(r->ctx, bytes);
            return LOST;
        } else {
            drained = 1;
            st = persp_image_load_memory(r->ctx, bytes, w, name, &img);
            persp__free(r->ctx, bytes);
        }
        if (!drained && !persp__wire_skip(r->chan, w)) return r->lost = 1, LOST;
    } else {
        st = persp__image_check_size(r->ctx, name, w, h);
        if (st != PERSP_OK) return bad_answer(r, "an embedded texture too large");
        st = persp_image_alloc(r->ctx, (int)w, (int)h, &img);
        for (uint32_t y = 0; y < h; y++) {
            if (st == PERSP_OK ? !get(r, img.pixels + (size_t)y * img.stride, (size_t)w * 4)
                               : !persp__wire_skip(r->chan, (uint64_t)w * 4)) {
                persp_image_free(r->ctx, &img);
                r->lost = 1;
                return LOST;
            }
        }
    }
    persp_texture *tex = NULL;
    if (st == PERSP_OK) persp__image_set_opaque(&img);
    if (st == PERSP_OK) st = persp_texture_create(r->ctx, &img, &tex);
    persp_image_free(r->ctx, &img);
    if (st == PERSP_OK) st = persp__scene_add_texture(r->scene, tex, &r->embedded_index[index]);
    if (st == PERSP_ERR_OUT_OF_MEMORY) {
        r->embedded_index[index] = -3;
        return PERSP_OK; /* refused when a material names it */
    }
    if (st != PERSP_OK) {
        persp__warn(r->ctx, "%s; drawing it untextured", persp_context_error(r->ctx));
        r->embedded_index[index] = -2;
    }
    return PERSP_OK;
}

static persp_wrap wrap_of(unsigned m)
{
    switch (m) {
    case WIRE_WRAP_CLAMP: return PERSP_WRAP_CLAMP_TO_EDGE;
    case WIRE_WRAP_MIRROR: return PERSP_WRAP_MIRRORED_REPEAT;
    case WIRE_WRAP_DECAL: return PERSP_WRAP_CLAMP_TO_BORDER;
    default: return PERSP_WRAP_REPEAT;
    }
}

/* A material's texture as the wire gives it. */
typedef struct wire_tex {
    uint8_t kind, wrap[2];
    uint32_t emb;
    char file[WIRE_MAX_TEXT + 1];
} wire_tex;

static persp_status get_texture_head(receiver *r, wire_tex *t)
{
    if (!get(r, &t->kind, 1) || !get(r, &t->emb, sizeof t->emb) || !get(r, t->wrap, 2)) return LOST;
    return PERSP_OK;
}

/* Whether the texture names what the importer sent: an embedded texture
 * it announced, a kind persp knows. */
static int texture_sound(const receiver *r, const wire_tex *t)
{
    if (t->kind > WIRE_TEX_EMBEDDED_MISSING) return 0;
    if (t->kind != WIRE_TEX_EMBEDDED) return 1;
    return t->emb < r->counts[2] && r->embedded_index[t->emb] != -1;
}

/* The scene texture of t (-1: none, after saying why where it is the
 * model's fault); material: its quoted name. */
static int texture_of(receiver *r, const char *name, const wire_tex *t)
{
    char qm[PERSP_QUOTE_BYTES], qf[PERSP_QUOTE_BYTES];
    persp__quote(name, strlen(name), qm, sizeof qm);
    persp__quote(t->file, strlen(t->file), qf, sizeof qf);
    if (t->kind == WIRE_TEX_FILE) {
        int index = persp__model_texture_file(&r->refs, name, t->file);
        if (r->refs.out_of_memory) r->out_of_memory = 1;
        return index;
    }
    if (t->kind == WIRE_TEX_EMBEDDED_MISSING) {
        persp__warn(r->ctx,
                    "%s: material '%s' names embedded texture '%s', which the file lacks; drawing it "
                    "untextured",
                    r->display, qm, qf);
        return -1;
    }
    if (t->kind == WIRE_TEX_EMBEDDED) {
        if (r->embedded_index[t->emb] == -3) {
            r->out_of_memory = 1;
            persp__model_texture_oom(r->ctx, r->display, qf, qm);
        }
        return r->embedded_index[t->emb] >= 0 ? r->embedded_index[t->emb] : -1;
    }
    return -1;
}

static persp_status take_material(receiver *r)
{
    uint32_t index;
    uint8_t flags;
    float col[9], shin, ke[3];
    char name[WIRE_MAX_TEXT + 1];
    wire_tex base, glow;
    if (!get(r, &index, sizeof index) || !get(r, &flags, 1) || !get(r, col, sizeof col) ||
        !get(r, &shin, sizeof shin))
        return LOST;
    persp_status st = get_texture_head(r, &base);
    if (st == PERSP_OK) st = get_text(r, name);
    if (st == PERSP_OK) st = get_text(r, base.file);
    if (st == PERSP_OK && !get(r, ke, sizeof ke)) st = LOST;
    if (st == PERSP_OK) st = get_texture_head(r, &glow);
    if (st == PERSP_OK) st = get_text(r, glow.file);
    if (st != PERSP_OK) return st;
    if (!r->header || index >= r->counts[1] || r->material_index[index] != -1)
        return bad_answer(r, "a material out of order");
    if (!texture_sound(r, &base) || !texture_sound(r, &glow)) return bad_answer(r, "a material's texture");
    persp_material m = persp__material_default();
    if (!(flags & WIRE_MAT_STAND_IN)) {
        persp__model_set_colours(&m, flags & WIRE_MAT_KD ? col : NULL, flags & WIRE_MAT_KS ? col + 3 : NULL,
                                 flags & WIRE_MAT_KA ? col + 6 : NULL, isfinite(shin) ? shin : 0.0f);
        m.texture = texture_of(r, name, &base);
        if (m.texture >= 0) {
            m.env = PERSP_TEXENV_MODULATE;
            m.sampler.wrap_s = wrap_of(base.wrap[0]);
            m.sampler.wrap_t = wrap_of(base.wrap[1]);
        }
        if (persp__model_set_emission(&m, flags & WIRE_MAT_KE ? ke : NULL) && glow.kind != WIRE_TEX_NONE)
            persp__model_set_glow_map(r->ctx, r->display, name, &m, texture_of(r, name, &glow),
                                      wrap_of(glow.wrap[0]), wrap_of(glow.wrap[1]));
        m.unlit = (flags & WIRE_MAT_UNLIT) != 0;
    }
    return persp__scene_add_material(r->scene, &m, &r->material_index[index]);
}

static persp_status take_part(receiver *r)
{
    uint32_t mesh, material;
    float xf[16];
    char name[WIRE_MAX_TEXT + 1];
    if (!get(r, &mesh, sizeof mesh) || !get(r, &material, sizeof material) || !get(r, xf, sizeof xf))
        return LOST;
    persp_status st = get_text(r, name);
    if (st != PERSP_OK) return st;
    if (!r->header || mesh >= r->counts[0] || r->mesh_index[mesh] < 0 ||
        (material != WIRE_NONE && (material >= r->counts[1] || r->material_index[material] < 0)))
        return bad_answer(r, "an instance of a mesh or material not sent");
    int mat;
    if (material == WIRE_NONE) {
        persp_material d = persp__material_default();
        if ((st = persp__scene_add_material(r->scene, &d, &mat)) != PERSP_OK) return st;
    } else {
        mat = r->material_index[material];
    }
    persp_mat4 m;
    memcpy(m.m, xf, sizeof xf);
    return persp__model_add_part(r->scene, r->out, &r->part_cap, r->mesh_index[mesh], mat, name, &m,
                                 r->display);
}

/* Reads the importer's records up to its last: PERSP_OK after 'D', the
 * refusal's status after 'E' (*kind and why set), LOST when the importer
 * went away or the time ran out, another status when this side refused. */
static persp_status take_answer(receiver *r, int *kind, char why[WIRE_MAX_TEXT + 1])
{
    for (;;) {
        uint8_t type;
        if (!get(r, &type, 1)) return LOST;
        persp_status st;
        /* What the header sizes comes after it: said before anything of it is read. */
        if (!r->header && (type == WIRE_MESH || type == WIRE_EMBEDDED || type == WIRE_MATERIAL || type == WIRE_PART))
            return bad_answer(r, "a record before the header");
        switch (type) {
        case WIRE_FILE: st = answer_file(r); break;
        case WIRE_HEADER: st = take_header(r); break;
        case WIRE_MESH: st = take_mesh(r); break;
        case WIRE_EMBEDDED: st = take_embedded(r); break;
        case WIRE_MATERIAL: st = take_material(r); break;
        case WIRE_PART: st = take_part(r); break;
        case WIRE_DONE: return PERSP_OK;
        case WIRE_ERROR: {
            uint8_t k;
            if (!get(r, &k, 1)) return LOST;
            st = get_text(r, why);
            if (st != PERSP_OK) return st;
            *kind = k;
            return PERSP_ERR_FORMAT;
        }
        default: return bad_answer(r, "an unknown record");
        }
        if (st != PERSP_OK) return st;
    }
}

/* ---------------------------------------------------------------- formats */

/* The formats read by default (PERSP_MODEL_FORMATS_COMMON): those users
 * bring and persp's tests cover, each with the content its name promises.
 * Assimp picks a reader by the name's extension and then by content, so a
 * file named for one format could reach another's reader; here the name
 * and the content must agree, and a name without a known extension gets
 * the reader its content shows. Every other reader only with
 * PERSP_MODEL_FORMATS_ALL. */
typedef struct model_format {
    const char *ext, *name;
    int (*looks)(const char *data, size_t size);  /* the content of a file so named */
    int (*sniff)(const char *data, size_t size);  /* NULL: looks; a file of no known name */
} model_format;

/* The first non-blank byte. */
static const char *skip_blank(const char *p, const char *end)
{
    while (p < end && isspace((unsigned char)*p)) p++;
    return p;
}

/* 1 when the first 4 KiB hold word. */
static int early(const char *data, size_t size, const char *word)
{
    size_t n = strlen(word), lim = size < 4096 ? size : 4096;
    for (size_t i = 0; i + n <= lim; i++)
        if (!memcmp(data + i, word, n)) return 1;
    return 0;
}

static int looks_gltf(const char *d, size_t n)
{
    const char *p = skip_blank(d, d + n);
    return p < d + n && *p == '{';
}
static int looks_glb(const char *d, size_t n) { return n >= 4 && !memcmp(d, "glTF", 4); }
static int looks_ply(const char *d, size_t n)
{
    return n >= 4 && !memcmp(d, "ply", 3) && (d[3] == '\n' || d[3] == '\r');
}
/* ASCII STL begins "solid"; binary STL is an 80-byte header, a count and
 * 50 bytes a triangle (a binary header may begin "solid" too). */
static int looks_stl(const char *d, size_t n)
{
    const char *p = skip_blank(d, d + n);
    if ((size_t)(d + n - p) >= 5 && !strncmp(p, "solid", 5)) return 1;
    if (n < 84) return 0;
    const unsigned char *u = (const unsigned char *)d + 80;
    uint64_t count = (uint64_t)u[0] | (uint64_t)u[1] << 8 | (uint64_t)u[2] << 16 | (uint64_t)u[3] << 24;
    return 84 + 50 * count == n;
}
/* OFF's first token: [ST][C][N][4][n]OFF (Princeton's and Geomview's
 * variants), or OFF BINARY. */
static int off_keyword(const char *d, size_t n)
{
    const char *p = skip_blank(d, d + n), *end = d + n;
    size_t len = 0;
    while (p + len < end && !isspace((unsigned char)p[len]) && len < 12) len++;
    return len >= 3 && len < 12 && !strncmp(p + len - 3, "OFF", 3);
}
/* The keyword is optional: the first line may hold the counts. The
 * checks of src/model/model_check.c have read the header by then. */
static int looks_off(const char *d, size_t n)
{
    const char *p = skip_blank(d, d + n);
    return off_keyword(d, n) || (p < d + n && (isdigit((unsigned char)*p) || *p == '-'));
}
static int looks_fbx(const char *d, size_t n)
{
    return (n >= 18 && !memcmp(d, "Kaydara FBX Binary", 18)) || early(d, n, "FBXHeaderExtension") ||
           early(d, n, "; FBX");
}
static int looks_dae(const char *d, size_t n) { return early(d, n, "<COLLADA"); }
/* 3DS: the main chunk 0x4D4D, little-endian, with its length. */
static int looks_3ds(const char *d, size_t n)
{
    return n >= 6 && (unsigned char)d[0] == 0x4d && (unsigned char)d[1] == 0x4d;
}

static const model_format common_formats[] = {
    {"gltf", "glTF", looks_gltf, NULL},    {"glb", "binary glTF", looks_glb, NULL},
    {"ply", "PLY", looks_ply, NULL},       {"stl", "STL", looks_stl, NULL},
    {"off", "OFF", looks_off, off_keyword}, {"fbx", "FBX", looks_fbx, NULL},
    {"dae", "COLLADA", looks_dae, NULL},   {"3ds", "3DS", looks_3ds, NULL},
};
#define COMMON_COUNT (sizeof common_formats / sizeof common_formats[0])

static const model_format *format_of_name(const char *name)
{
    for (size_t i = 0; i < COMMON_COUNT; i++)
        if (persp__model_has_ext(name, common_formats[i].ext)) return &common_formats[i];
    return NULL;
}

static const model_format *format_of_content(const char *data, size_t size)
{
    /* Binary signatures first: an STL header is free text. */
    static const size_t order[] = {1, 5, 7, 2, 6, 0, 4, 3};
    for (size_t i = 0; i < COMMON_COUNT; i++) {
        const model_format *f = &common_formats[order[i]];
        if ((f->sniff ? f->sniff : f->looks)(data, size)) return f;
    }
    return NULL;
}

const char *persp__model_content_format(const char *data, size_t size, const char **ext)
{
    const model_format *f = format_of_content(data, size);
    if (ext) *ext = f ? f->ext : NULL;
    return f ? f->name : NULL;
}

const char *persp__model_article(const char *format)
{
    /* Initials read as letters that begin with a vowel sound: F, L, M, N,
     * S, X (eff, el, em, en, ess, ex), and the vowels. */
    return format && strchr("AEIOUFLMNSXaeiou", format[0]) ? "an" : "a";
}

/* The name Assimp is given for the model (its extension picks the reader),
 * or an error: a format not enabled, or content that is not what the name
 * says. */
static persp_status pick_reader(persp_context *ctx, const char *display, const char *data, size_t size,
                                int all, char *main_name, size_t cap)
{
    const char *base = persp__path_base(display);
    /* A text model saved as UTF-16 or UTF-32 (Windows tools offer it):
     * some readers take it for another format or find nothing to draw in
     * it ("zero area"). Binary STL's free 80-byte header may begin with
     * any bytes. */
    const int wide = size >= 2 && (!memcmp(data, "\xff\xfe", 2) || !memcmp(data, "\xfe\xff", 2) ||
                                   (size >= 4 && !memcmp(data, "\0\0\xfe\xff", 4)));
    if (wide && !persp__model_has_ext(base, "stl"))
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: a model file in UTF-16 or UTF-32 (persp reads ASCII or UTF-8: save it as "
                           "UTF-8)",
                           display);
    if (size == 0) return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the file is empty", display);
    const model_format *by_name = format_of_name(base);
    const model_format *by_content = format_of_content(data, size);
    if (by_name) {
        if (!by_name->looks(data, size)) {
            char seems[96] = "";
            if (by_content)
                snprintf(seems, sizeof seems, " (it looks like %s: rename it .%s)", by_content->name,
                         by_content->ext);
            return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the content is not that of %s %s file%s", display,
                               persp__model_article(by_name->name), by_name->name, seems);
        }
        snprintf(main_name, cap, "%s", base[0] ? base : "model");
        return PERSP_OK;
    }
    const char *dot = strrchr(base, '.');
    const int known = dot && dot[1] && aiIsExtensionSupported(dot);
    if (!known && by_content) {
        snprintf(main_name, cap, "model.%s", by_content->ext);
        return PERSP_OK;
    }
    if (!all) {
        char q[PERSP_QUOTE_BYTES];
        if (known)
            return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                               "%s: '%s' models are not read by default (persp reads OBJ, glTF/GLB, PLY, "
                               "STL, OFF, FBX, COLLADA and 3DS; --formats all enables the rest, read in "
                               "the isolated importer)",
                               display, persp__quote(dot + 1, strlen(dot + 1), q, sizeof q));
        return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                           "%s: not a model format persp reads (OBJ, glTF/GLB, PLY, STL, OFF, FBX, "
                           "COLLADA, 3DS; --formats all tries every reader of Assimp's)",
                           display);
    }
    snprintf(main_name, cap, "%s", base[0] ? base : "model");
    return PERSP_OK;
}
void persp__model_free(persp_context *ctx, persp_model *model)
{
    if (!model) return;
    persp__free(ctx, model->parts);
    memset(model, 0, sizeof *model);
}

int persp__model_streams(const char *path)
{
    return persp__model_has_ext(path, "obj");
}

/* Whether persp's OBJ reader takes the model: a .obj name, or a name
 * without an extension Assimp reads whose first 200 bytes hold an OBJ
 * statement at a line start (the content test of Assimp's OBJ reader,
 * which took such files before). */
static int is_obj(const char *name, const char *data, size_t size)
{
    if (persp__model_has_ext(name, "obj")) return 1;
    const char *base = persp__path_base(name);
    const char *dot = strrchr(base, '.');
    if (dot && dot[1] && aiIsExtensionSupported(dot)) return 0;
    static const char *const words[] = {"mtllib", "usemtl", "v ", "vt ", "vn ",
                                        "o ",      "g ",      "s ", "f "};
    size_t n = size < 200 ? size : 200;
    for (size_t i = 0; i < n; i++) {
        if (i > 0 && data[i - 1] != '\n' && data[i - 1] != '\r') continue;
        for (size_t w = 0; w < sizeof words / sizeof words[0]; w++) {
            size_t len = strlen(words[w]);
            if (i + len <= size && !memcmp(data + i, words[w], len)) return 1;
        }
    }
    return 0;
}

/* ----------------------------------------------------------------- import */

/* The importer's memory when the context has no budget: half of this
 * machine's, so that one hostile file cannot take all of it. */
static size_t unbudgeted_import_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return (size_t)4 << 30;
    return (size_t)pages / 2 * (size_t)page;
}

static void mib(char *out, size_t cap, size_t bytes)
{
    snprintf(out, cap, "%.1f MiB", (double)bytes / (1024.0 * 1024.0));
}

static int send_request(wire_chan *c, const char *main_name, const char *data, size_t size,
                        size_t max_vertices)
{
    const uint32_t head[2] = {WIRE_MAGIC, WIRE_VERSION};
    const uint64_t mv = max_vertices, n = size;
    const uint32_t len = (uint32_t)strlen(main_name);
    return persp__wire_write(c, head, sizeof head) && persp__wire_write(c, &mv, sizeof mv) &&
           persp__wire_write(c, &len, sizeof len) && persp__wire_write(c, main_name, len) &&
           persp__wire_write(c, &n, sizeof n) && persp__wire_write(c, data, size);
}

/* The time limit's failure; earlier_ms: what the scene's earlier imports
 * took of the limit they share with this one. */
static persp_status out_of_time(persp_context *ctx, const char *display, const persp_importer_opts *o,
                                int64_t earlier_ms)
{
    if (earlier_ms > 0)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE,
                           "%s: the scene's model imports took longer than the limit of %.1f s they share "
                           "(--import-timeout; %.1f s before this one); a model is malformed or hostile, "
                           "or they need more time",
                           display, o->time_limit_ms / 1000.0, (double)earlier_ms / 1000.0);
    return persp__fail(ctx, PERSP_ERR_TOO_LARGE,
                       "%s: the import took longer than its limit of %.1f s (--import-timeout); the "
                       "file is malformed or hostile, or needs more time",
                       display, o->time_limit_ms / 1000.0);
}

/* The failure of an import whose importer went away without an answer. */
static persp_status lost_importer(persp_context *ctx, const char *display, const wire_chan *c,
                                  const persp_importer_end *end, const persp_importer_opts *o, int64_t earlier_ms)
{
    char lim[32], used[32];
    mib(lim, sizeof lim, o->memory);
    mib(used, sizeof used, end->peak_bytes);
    if (c->failed == 2 || end->signal == SIGXCPU) return out_of_time(ctx, display, o, earlier_ms);
    if (end->exit_code == PERSP_IMPORT_EXIT_OUT_OF_MEMORY)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY,
                           "%s: importing the model needs more than the %s of memory it may use (what "
                           "the memory budget leaves: --max-memory)",
                           display, lim);
    if (end->signal) {
        /* A reader that fails an allocation it does not check crashes
         * rather than reporting it: near the limit, say so. */
        char near[192] = "";
        if (end->peak_bytes >= o->memory / 10 * 9)
            snprintf(near, sizeof near, "; it had used %s of the %s it may use, so it may have run out "
                     "(--max-memory)", used, lim);
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: the importer crashed on this file (signal %d, %s); the file is malformed "
                           "or hostile%s",
                           display, end->signal, strsignal(end->signal), near);
    }
    if (end->exit_code == PERSP_IMPORT_EXIT_LIMITS)
        return persp__fail(ctx, PERSP_ERR_IO, "%s: the model importer could not set its limits", display);
    return persp__fail(ctx, PERSP_ERR_IO, "%s: the model importer ended without an answer%s", display,
                       end->known ? "" : " (its exit status is unknown: SIGCHLD ignored?)");
}

/* The failure the importer reported ('E'). */
static persp_status refused(persp_context *ctx, const char *display, const model_io *io, int kind,
                            const char *why, const persp_importer_opts *o)
{
    if (kind == WIRE_ERR_OUT_OF_MEMORY) {
        char lim[32];
        mib(lim, sizeof lim, o->memory);
        if (o->in_process)
            return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: the model importer ran out of memory",
                               display);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY,
                           "%s: importing the model needs more than the %s of memory it may use (what "
                           "the memory budget leaves: --max-memory)",
                           display, lim);
    }
    /* Assimp takes a file that could not be opened for a missing or
     * unreadable one, so a file the model names and persp could not read
     * is the reason. */
    if (io->nmissing)
        return persp__fail(ctx, PERSP_ERR_IO, "%s, which the model cannot be imported without", io->notes[0]);
    if (kind == WIRE_ERR_FORMAT) return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: %s", display, why);
    if (kind == WIRE_ERR_TOO_LARGE) return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "%s: %s", display, why);
    if (kind == WIRE_ERR_NO_READER)
        return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                           "%s: not a model format persp reads (OBJ, or one Assimp reads: glTF, PLY, "
                           "STL, FBX, COLLADA, 3DS, ...)",
                           display);
    /* Assimp's message may quote the text it choked on; once another file
     * (a material library, a buffer) has been read, that text may be that
     * file's, which is not the user's to see through a model (a material
     * library naming /etc/passwd, with any_folder on). */
    if (io->others && quotes_other(io, why))
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: cannot import the model or a file it names (Assimp's message withheld: "
                           "it may quote that file)",
                           display);
    char q[PERSP_QUOTE_BYTES * 2];
    return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: cannot import the model: %s", display,
                       why[0] ? persp__quote(why, strlen(why), q, sizeof q) : "unknown format or malformed file");
}

/* What an import through Assimp needs before it starts: the reader
 * (pick_reader, after the header checks of src/model/model_check.c, whose
 * messages say more than that a file is not what its name says), where it
 * runs, and its memory: in this process Assimp allocates with new/malloc
 * and its C API has no allocator hook, so its need is reserved from the
 * budget by the file's size (a 68.5 MB OBJ grid of a million triangles
 * peaked at 311 MB, 4.5 bytes per byte of the file: *reserved); persp-import
 * is held to what the budget leaves instead, and what it sends back is
 * charged as it arrives. buf's text may be normalised (*size). */
static persp_status prepare_import(persp_scene *scene, const char *display, char *buf, size_t *size,
                                   char *main_name, size_t name_cap, char *helper, size_t helper_cap,
                                   persp_importer_opts *o, size_t *reserved)
{
    persp_context *ctx = scene->ctx;
    const persp_scene_load_desc *d = scene->load_desc;
    memset(o, 0, sizeof *o);
    *reserved = 0;
    o->in_process = d && d->import == PERSP_MODEL_IMPORT_IN_PROCESS;
#ifdef PERSP_IMPORT_IN_PROCESS_DEFAULT
    /* An emulated test build (cmake/aarch64-linux-gnu.cmake). */
    if (!d || d->import == PERSP_MODEL_IMPORT_DEFAULT) o->in_process = 1;
#endif
    o->time_limit_ms = d && d->import_time_limit_ms ? d->import_time_limit_ms : PERSP_IMPORT_TIME_LIMIT_MS;
    o->time_scales = !(d && d->import_time_limit_ms);
    const char *base = persp__path_base(display);
    if (is_line_text(base) || persp__model_has_ext(base, "gltf"))
        *size = normalise_text(buf, *size, is_line_text(base));
    persp_status st = persp__model_check(ctx, display, buf, *size);
    if (st == PERSP_OK)
        st = pick_reader(ctx, display, buf, *size, d && d->formats == PERSP_MODEL_FORMATS_ALL, main_name, name_cap);
    if (st != PERSP_OK) return st;
    if (o->in_process) {
        *reserved = *size > ((size_t)-1 - (1u << 20)) / MODEL_IMPORT_PER_BYTE
                        ? (size_t)-1
                        : *size * MODEL_IMPORT_PER_BYTE + ((size_t)1 << 20);
        char what[PERSP_ERRMSG_BYTES / 2];
        snprintf(what, sizeof what, "%s: importing the model", display);
        st = persp__mem_reserve(ctx, *reserved, what);
        if (st != PERSP_OK) *reserved = 0;
        return st;
    }
    if (!persp__import_helper_path(d ? d->import_helper : NULL, helper, helper_cap))
        return persp__fail(ctx, PERSP_ERR_UNAVAILABLE,
                           "%s: cannot find the model importer %s (beside libpersp, or in "
                           "PREFIX/libexec/persp/; persp_scene_load_desc.import_helper names it)",
                           display, d && d->import_helper ? d->import_helper : "persp-import");
    o->helper = helper;
    size_t avail = persp__mem_available(ctx);
    o->memory = avail == (size_t)-1 ? unbudgeted_import_memory() : avail;
    return PERSP_OK;
}

/* The conversation: the importer started, the model sent, its answer taken
 * into the scene (take_answer), the importer ended. *kind and why: the
 * importer's refusal ('E'), if it sent one. */
static persp_status run_import(receiver *r, persp_importer_opts *o, const char *main_name,
                               int *kind, char why[WIRE_MAX_TEXT + 1])
{
    persp_context *ctx = r->ctx;
    persp_scene *scene = r->scene;
    if (o->in_process) pthread_mutex_lock(&import_lock);
    /* A scene's imports share one limit, so that a scene naming a model
     * that takes the whole limit a thousand times ends as soon as one
     * would: the clock starts where the earlier imports left it, and what
     * their files granted stays granted. */
    const int64_t earlier_ms = o->in_process ? 0 : scene->import_used_ms;
    if (!o->in_process && scene->import_limit_ms) o->time_limit_ms = scene->import_limit_ms;
    wire_chan chan = {-1, 0, 0};
    r->chan = &chan;
    r->opts = o;
    r->started_ms = persp__wire_now_ms() - earlier_ms;
    if (!o->in_process) {
        chan.deadline_ms = r->started_ms + o->time_limit_ms;
        grant_time(r, r->io->size);
    }
    persp_importer imp;
    persp_status st = !o->in_process && persp__wire_now_ms() >= chan.deadline_ms
                          ? out_of_time(ctx, r->display, o, earlier_ms)
                          : persp__importer_start(ctx, o, r->display, &imp);
    const int started = st == PERSP_OK;
    chan.fd = started ? imp.fd : -1;
    if (started) {
        if (!send_request(&chan, main_name, r->io->data, r->io->size, r->max_vertices))
            r->lost = 1, st = PERSP_ERR_IO;
        else
            st = take_answer(r, kind, why);
        persp_importer_end end;
        /* Anything but a complete answer or refusal stops the importer. */
        persp__importer_finish(&imp, st != PERSP_OK && !*kind, &end);
        if (r->lost) st = lost_importer(ctx, r->display, &chan, &end, o, earlier_ms);
    }
    if (!o->in_process) {
        scene->import_used_ms = persp__wire_now_ms() - r->started_ms;
        scene->import_limit_ms = o->time_limit_ms;
    }
    if (o->in_process) pthread_mutex_unlock(&import_lock);
    r->chan = NULL;
    if (st == PERSP_OK || *kind) {
        if (r->io->out_of_memory)
            st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory reading a file the model names",
                             r->display);
        else if (*kind)
            st = refused(ctx, r->display, r->io, *kind, why, o);
    }
    return st;
}

/* persp__model_load_memory on buf, size + 1 bytes from the context's
 * allocator with buf[size] = '\0', which it modifies and frees: a file's
 * text is then held once, not read and copied (docs/RELIABILITY.md). */
static persp_status load_owned(persp_scene *scene, char *buf, size_t size, const char *name,
                               const char *base_dir, persp_texcache *cache, size_t max_vertices,
                               persp_model *out)
{
    persp_context *ctx = scene->ctx;
    memset(out, 0, sizeof *out);
    const char *display = name ? name : "<model>";
    if (is_obj(display, buf, size)) {
        persp_status ost = persp__obj_load(scene, buf, size, name, base_dir, cache, max_vertices, out);
        persp__free(ctx, buf);
        return ost;
    }
    char main_name[256], helper[PERSP_PATH_MAX];
    persp_importer_opts o;
    size_t reserved = 0;
    persp_status st = prepare_import(scene, display, buf, &size, main_name, sizeof main_name, helper,
                                     sizeof helper, &o, &reserved);
    if (st != PERSP_OK) {
        persp__free(ctx, buf);
        return st;
    }
    model_io io;
    memset(&io, 0, sizeof io);
    io.ctx = ctx;
    io.display = display;
    io.data = buf;
    io.size = size;
    io.base_dir = base_dir;
    io.root = scene->load_root;
    /* glTF 2.0 §3.3.1: URIs are RFC 3986, so "%20" in a name is a space. */
    io.uri = persp__model_has_ext(main_name, "gltf") || persp__model_has_ext(main_name, "glb") ||
             (size >= 4 && !memcmp(buf, "glTF", 4));
    receiver r;
    memset(&r, 0, sizeof r);
    r.scene = scene;
    r.ctx = ctx;
    r.io = &io;
    r.display = display;
    r.max_vertices = max_vertices ? max_vertices : PERSP_SCENE_MAX_VERTICES;
    /* glTF 2.0 §3.7.2.1: "When normals are not specified, client
     * implementations MUST calculate flat normals". */
    r.crease_deg = persp__model_has_ext(main_name, "gltf") || persp__model_has_ext(main_name, "glb")
                       ? 0.0f
                       : persp__model_crease(scene->load_desc);
    r.out = out;
    r.refs = (persp_model_refs){.scene = scene, .cache = cache, .display = display, .base_dir = base_dir,
                                .root = scene->load_root, .where = where_io, .where_user = &io, .uri = io.uri};
    for (int k = 0; k < 3; k++)
        out->bbox_min[k] = INFINITY, out->bbox_max[k] = -INFINITY;
    int kind = 0;
    char why[WIRE_MAX_TEXT + 1] = "";
    st = run_import(&r, &o, main_name, &kind, why);
    for (int i = 0; st == PERSP_OK && i < io.nmissing; i++)
        persp__warn(ctx, "%s; going on without it", io.notes[i]);
    /* A texture refused for want of memory is not drawn untextured with a
     * warning, as a missing file is: the allocator's refusal is the caller's
     * to see (PERSP_ERR_OUT_OF_MEMORY). */
    if (st == PERSP_OK && (r.out_of_memory || r.refs.out_of_memory)) st = PERSP_ERR_OUT_OF_MEMORY;
    if (st == PERSP_OK && out->part_count == 0)
        st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the model has no triangles to draw", display);
    if (st == PERSP_OK && !(out->bbox_min[0] <= out->bbox_max[0]))
        st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the model's transformed vertices are not finite", display);
    persp__free(ctx, r.mesh_index);
    persp__free(ctx, r.material_index);
    persp__free(ctx, r.embedded_index);
    persp__free(ctx, buf);
    free_kept(&io);
    if (reserved) persp__mem_release(ctx, reserved);
    /* Files worked around left their failures in the detail: warnings. */
    if (st == PERSP_OK)
        persp__clear_error(ctx);
    else
        persp__model_free(ctx, out);
    return st;
}

persp_status persp__model_load_memory(persp_scene *scene, const void *data, size_t size,
                                      const char *name, const char *base_dir, persp_texcache *cache,
                                      size_t max_vertices, persp_model *out)
{
    if (!scene || (!data && size) || !out) return PERSP_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    /* persp's OBJ reader parses the caller's buffer in place. */
    if (is_obj(name ? name : "<model>", data, size))
        return persp__obj_load(scene, size ? data : "", size, name, base_dir, cache, max_vertices,
                               out);
    char *buf = persp__alloc(scene->ctx, size + 1);
    if (!buf)
        return persp__fail(scene->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory",
                           name ? name : "<model>");
    if (size) memcpy(buf, data, size);
    buf[size] = '\0';
    return load_owned(scene, buf, size, name, base_dir, cache, max_vertices, out);
}

persp_status persp__model_load_file(persp_scene *scene, const char *path, persp_texcache *cache,
                                    size_t max_vertices, persp_model *out)
{
    if (!scene || !path || !out) return PERSP_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    char dir[PERSP_PATH_MAX];
    persp__path_dir(path, dir, sizeof dir);
    /* An OBJ file is streamed, never held whole (docs/RELIABILITY.md). */
    if (persp__model_streams(path))
        return persp__obj_load(scene, NULL, 0, path, dir[0] ? dir : "./", cache, max_vertices,
                               out);
    char *data = NULL;
    size_t size = 0;
    persp_status st = persp__read_file_inside(scene->ctx, scene->load_root, path, &data, &size);
    if (st != PERSP_OK) return st;
    return load_owned(scene, data, size, path, dir[0] ? dir : "./", cache, max_vertices, out);
}

int persp__model_is_model(const char *path, const char *data, size_t size)
{
    if (persp__model_has_ext(path, "json")) return 0;
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (dot && (!slash || dot > slash) && dot[1] && aiIsExtensionSupported(dot)) return 1;
    if (!data) return 0;
    size_t i = 0;
    if (size >= 3 && (unsigned char)data[0] == 0xef && (unsigned char)data[1] == 0xbb &&
        (unsigned char)data[2] == 0xbf)
        i = 3;
    while (i < size && isspace((unsigned char)data[i]))
        i++;
    return i < size && data[i] != '{';
}

/* ------------------------------------------------- scene around a model */

static persp_vec3 from_angles(float elev_deg, float azim_deg)
{
    const float d2r = 3.14159265f / 180.0f;
    float e = elev_deg * d2r, a = azim_deg * d2r;
    return (persp_vec3){cosf(e) * sinf(a), sinf(e), cosf(e) * cosf(a)};
}

/* Turns the model so that its up axis is +y, by a quarter or half turn,
 * which maps the axis-aligned box onto one exactly: +z up: −90° about x
 * (y' = z, z' = −y); −z: +90° about x; +x: +90° about z (y' = x, x' = −y);
 * −x: −90° about z; −y: 180° about x. */
static void turn_up(persp_model *model, persp_model_up up)
{
    /* Rows of the turn: the new x, y, z as ±(old axis). */
    int axis[3] = {0, 1, 2}, sign[3] = {1, 1, 1};
    switch (up) {
    case PERSP_MODEL_UP_Z: axis[1] = 2, axis[2] = 1, sign[2] = -1; break;
    case PERSP_MODEL_UP_NEG_Z: axis[1] = 2, sign[1] = -1, axis[2] = 1; break;
    case PERSP_MODEL_UP_X: axis[0] = 1, sign[0] = -1, axis[1] = 0; break;
    case PERSP_MODEL_UP_NEG_X: axis[0] = 1, axis[1] = 0, sign[1] = -1; break;
    case PERSP_MODEL_UP_NEG_Y: sign[1] = -1, sign[2] = -1; break;
    default: return;
    }
    persp_mat4 turn;
    memset(&turn, 0, sizeof turn);
    for (int r = 0; r < 3; r++) turn.m[axis[r] * 4 + r] = (float)sign[r];
    turn.m[15] = 1.0f;
    for (size_t i = 0; i < model->part_count; i++)
        model->parts[i].transform = persp_mat4_mul(turn, model->parts[i].transform);
    float lo[3], hi[3];
    for (int r = 0; r < 3; r++) {
        const float a = model->bbox_min[axis[r]], b = model->bbox_max[axis[r]];
        lo[r] = sign[r] > 0 ? a : -b;
        hi[r] = sign[r] > 0 ? b : -a;
    }
    memcpy(model->bbox_min, lo, sizeof lo);
    memcpy(model->bbox_max, hi, sizeof hi);
}

persp_status persp__scene_from_model(persp_context *ctx, char *data, size_t size, const char *name,
                                     const char *base_dir, const char *root,
                                     const persp_scene_load_desc *desc, persp_scene **out)
{
    *out = NULL;
    persp_scene *s = NULL;
    persp_status st = persp__scene_new(ctx, &s);
    if (st != PERSP_OK) {
        persp__free(ctx, data);
        return st;
    }
    persp_texcache cache;
    memset(&cache, 0, sizeof cache);
    persp_model model;
    s->load_root = root;
    s->load_desc = desc;
    st = data ? load_owned(s, data, size, name, base_dir, &cache, 0, &model)
              : persp__obj_load(s, NULL, 0, name, base_dir, &cache, 0, &model);
    s->load_root = NULL;
    s->load_desc = NULL;
    persp__texcache_free(ctx, &cache);
    if (st == PERSP_OK) persp__model_warn_no_uv(s, &model, name ? name : "<model>", -1, PERSP_TEXGEN_UV);
    persp_model_up up = desc ? desc->model_up : PERSP_MODEL_UP_DEFAULT;
    if (up == PERSP_MODEL_UP_DEFAULT && name &&
        (persp__model_has_ext(name, "blend") || persp__model_has_ext(name, "smd") || persp__model_has_ext(name, "cob")))
        up = PERSP_MODEL_UP_Z;
    if (st == PERSP_OK && up != PERSP_MODEL_UP_DEFAULT && up != PERSP_MODEL_UP_Y) turn_up(&model, up);
    for (size_t i = 0; st == PERSP_OK && i < model.part_count; i++) {
        persp_object o;
        memset(&o, 0, sizeof o);
        o.mesh = model.parts[i].mesh;
        o.material = model.parts[i].material;
        o.model = model.parts[i].transform;
        o.texgen_axis = 1;
        st = persp__scene_add_object(s, &o);
    }
    if (st != PERSP_OK) {
        persp__model_free(ctx, &model);
        persp_scene_destroy(s);
        return st;
    }
    /* Camera: 30 degrees above and 35 around the front (+z) of the bounding
     * box, far enough for the bounding sphere to fill a 45-degree view of
     * the image's shorter side. */
    float c[3], r2 = 0;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5f * (model.bbox_min[k] + model.bbox_max[k]);
        float h = 0.5f * (model.bbox_max[k] - model.bbox_min[k]);
        r2 += h * h;
    }
    persp__model_free(ctx, &model);
    float r = sqrtf(r2);
    if (!(r > 1e-6f) || !isfinite(r)) r = 1.0f;
    const float fov = 45.0f;
    float dist = 1.05f * r / sinf(0.5f * fov * 3.14159265f / 180.0f);
    persp_vec3 dir = from_angles(30.0f, 35.0f);
    s->camera.eye = (persp_vec3){c[0] + dist * dir.x, c[1] + dist * dir.y, c[2] + dist * dir.z};
    s->camera.target = (persp_vec3){c[0], c[1], c[2]};
    s->camera.up = (persp_vec3){0, 1, 0};
    s->camera.fovy_deg = fov;
    s->camera.fov_shorter_side = 1;
    s->camera.znear = 0.5f * (dist - r);
    s->camera.zfar = 1.5f * (dist + r);
    /* Three-point rig, directions relative to the camera's 35 degrees:
     * key above and to the left, fill low on the right, rim from behind. */
    static const float rig[3][3] = {{50.0f, 35.0f - 45.0f, 0.85f},
                                    {10.0f, 35.0f + 60.0f, 0.35f},
                                    {40.0f, 35.0f + 180.0f, 0.45f}};
    for (int i = 0; i < 3; i++) {
        persp_light *l = &s->lights[i];
        memset(l, 0, sizeof *l);
        l->type = PERSP_LIGHT_DIRECTIONAL;
        persp_vec3 d = from_angles(rig[i][0], rig[i][1]);
        l->position[0] = d.x, l->position[1] = d.y, l->position[2] = d.z;
        l->color[0] = l->color[1] = l->color[2] = rig[i][2];
        l->attenuation[0] = 1.0f;
    }
    s->light_count = 3;
    for (int k = 0; k < 3; k++)
        s->ambient[k] = 0.15f;
    s->shading = PERSP_SHADING_PHONG;
    s->clear[0] = s->clear[1] = s->clear[2] = 40;
    s->clear[3] = 255;
    *out = s;
    return PERSP_OK;
}
