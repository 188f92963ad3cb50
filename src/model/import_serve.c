/*
 * The importer's side of the conversation of src/model/import_wire.h: Assimp
 * reads the model persp sent, the scene it makes is checked, triangulated
 * and turned into persp's vertices, materials and instances, which go back
 * as records. This runs in persp-import (tools/import/), a process of its
 * own with limits on memory and time, so that a reader that crashes, loops
 * or allocates without bound on a hostile file takes down that process
 * only; or on a thread of persp's when a caller asks for the import in its
 * own process (PERSP_MODEL_IMPORT_IN_PROCESS).
 *
 * Nothing here opens a file: the files a model names (material libraries,
 * glTF buffers) are asked of persp, which resolves, confines and reads
 * them. Memory comes from malloc (the process's own limit bounds it), and
 * every block the importer was handed is freed at the end, including those
 * of files Assimp left open when it gave up.
 */
#include "io/json_text.h"
#include "model/import_wire.h"
#include "model/model.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------ the channel */

typedef struct serve {
    wire_chan chan;
    char out[1 << 16]; /* records are buffered: a mesh is many small writes */
    size_t out_len;
    const char *main_name;
    const char *data; /* the model file */
    size_t size;
    /* Blocks handed to Assimp as files, freed at the end whether or not
     * Assimp closed them (it does not when a reader throws). */
    struct served_file **files;
    size_t file_count, file_cap;
    int out_of_memory;
} serve;

typedef struct served_file {
    char *data;
    size_t size, pos;
    int open;
} served_file;

static int flush_out(serve *s)
{
    if (s->out_len && !persp__wire_write(&s->chan, s->out, s->out_len)) return 0;
    s->out_len = 0;
    return 1;
}

static int put(serve *s, const void *p, size_t n)
{
    if (s->chan.failed) return 0;
    if (n > sizeof s->out - s->out_len) {
        if (!flush_out(s)) return 0;
        if (n > sizeof s->out) return persp__wire_write(&s->chan, p, n);
    }
    memcpy(s->out + s->out_len, p, n);
    s->out_len += n;
    return 1;
}

static int put_u8(serve *s, unsigned v)
{
    uint8_t b = (uint8_t)v;
    return put(s, &b, 1);
}
static int put_u32(serve *s, uint32_t v) { return put(s, &v, sizeof v); }
static int put_u64(serve *s, uint64_t v) { return put(s, &v, sizeof v); }
static int put_text(serve *s, const char *t)
{
    size_t n = strlen(t);
    if (n > WIRE_MAX_TEXT) n = WIRE_MAX_TEXT;
    return put_u32(s, (uint32_t)n) && put(s, t, n);
}

static int send_error(serve *s, int kind, const char *msg)
{
    return put_u8(s, WIRE_ERROR) && put_u8(s, (unsigned)kind) && put_text(s, msg) && flush_out(s);
}

/* ------------------------------------------------------------ file access */

static size_t file_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    served_file *sf = (served_file *)(void *)f->UserData;
    if (size == 0 || count == 0) return 0;
    size_t n = (sf->size - sf->pos) / size;
    if (n > count) n = count;
    memcpy(buf, sf->data + sf->pos, n * size);
    sf->pos += n * size;
    return n;
}

static size_t file_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0;
}

static size_t file_tell(struct aiFile *f) { return ((served_file *)(void *)f->UserData)->pos; }
static size_t file_size(struct aiFile *f) { return ((served_file *)(void *)f->UserData)->size; }
static void file_flush(struct aiFile *f) { (void)f; }

static enum aiReturn file_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    served_file *sf = (served_file *)(void *)f->UserData;
    if (origin != aiOrigin_SET && origin != aiOrigin_CUR && origin != aiOrigin_END)
        return aiReturn_FAILURE;
    size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? sf->pos : sf->size;
    if (offset > sf->size - base) return aiReturn_FAILURE;
    sf->pos = base + offset;
    return aiReturn_SUCCESS;
}

/* Asks persp for a file the model names: its bytes, or NULL (missing,
 * refused, or no memory for it). */
static char *ask_file(serve *s, const char *name, size_t *size)
{
    uint8_t reply = WIRE_FILE_MISSING;
    uint64_t n = 0;
    if (!(put_u8(s, WIRE_FILE) && put_text(s, name) && flush_out(s))) return NULL;
    if (!persp__wire_read(&s->chan, &reply, 1)) return NULL;
    if (reply != WIRE_FILE_OK) return NULL;
    if (!persp__wire_read(&s->chan, &n, sizeof n)) return NULL;
    char *data = n < SIZE_MAX ? malloc((size_t)n + 1) : NULL;
    if (!data) {
        s->out_of_memory = 1;
        persp__wire_skip(&s->chan, n);
        return NULL;
    }
    if (!persp__wire_read(&s->chan, data, (size_t)n)) {
        free(data);
        return NULL;
    }
    data[n] = '\0';
    *size = (size_t)n;
    return data;
}

static struct aiFile *file_open(struct aiFileIO *fio, const char *name, const char *mode)
{
    serve *s = (serve *)(void *)fio->UserData;
    if (!name || !mode || mode[0] != 'r' || s->chan.failed) return NULL;
    if (s->file_count == s->file_cap) {
        size_t cap = s->file_cap ? 2 * s->file_cap : 8;
        void *grown = realloc(s->files, cap * sizeof *s->files);
        if (!grown) return s->out_of_memory = 1, NULL;
        s->files = grown;
        s->file_cap = cap;
    }
    served_file *sf = calloc(1, sizeof *sf);
    struct aiFile *f = calloc(1, sizeof *f);
    if (!sf || !f) {
        free(sf), free(f);
        s->out_of_memory = 1;
        return NULL;
    }
    if (!strcmp(name, s->main_name)) {
        /* A copy: the reader may hold it past the scene's import. */
        sf->data = malloc(s->size + 1);
        if (sf->data) memcpy(sf->data, s->data, s->size), sf->data[s->size] = '\0';
        else s->out_of_memory = 1;
        sf->size = s->size;
    } else {
        sf->data = ask_file(s, name, &sf->size);
    }
    if (!sf->data) {
        free(sf), free(f);
        return NULL;
    }
    sf->open = 1;
    s->files[s->file_count++] = sf;
    f->ReadProc = file_read;
    f->WriteProc = file_write;
    f->TellProc = file_tell;
    f->FileSizeProc = file_size;
    f->SeekProc = file_seek;
    f->FlushProc = file_flush;
    f->UserData = (aiUserData)(void *)sf;
    return f;
}

static void file_close(struct aiFileIO *fio, struct aiFile *f)
{
    (void)fio;
    if (!f) return;
    served_file *sf = (served_file *)(void *)f->UserData;
    free(sf->data);
    sf->data = NULL;
    sf->open = 0;
    free(f);
}

static void free_files(serve *s)
{
    for (size_t i = 0; i < s->file_count; i++) {
        free(s->files[i]->data);
        free(s->files[i]);
    }
    free(s->files);
    s->files = NULL;
    s->file_count = s->file_cap = 0;
}

/* ------------------------------------------------------- scene checks */

/* Some exporters write zero facet normals (Blender's old binary STL writer,
 * for one); drawn as they are, such a surface gets no diffuse light at all.
 * A mesh with one unusable normal is sent without normals, and persp makes
 * them (persp__mesh_crease_normals). */
static int normals_unusable(const struct aiMesh *m)
{
    if (!m->mNormals) return 0;
    for (unsigned v = 0; v < m->mNumVertices; v++) {
        const struct aiVector3D n = m->mNormals[v];
        if (!persp__model_finite3(n.x, n.y, n.z) || !(n.x * n.x + n.y * n.y + n.z * n.z > 1e-12f)) return 1;
    }
    return 0;
}

/* Whether a face spans any area: a model whose faces all lie on a line or a
 * point would render as an empty picture. The fan from the first corner
 * covers the polygon; "no area" is relative to the edges' lengths. Corners
 * out of range have no area (the validation step refuses them later). */
static int face_has_area(const struct aiMesh *m, const struct aiFace *f)
{
    if (f->mNumIndices < 3 || !f->mIndices) return 0;
    for (unsigned i = 0; i < f->mNumIndices; i++)
        if (f->mIndices[i] >= m->mNumVertices) return 0;
    const struct aiVector3D a = m->mVertices[f->mIndices[0]];
    const float pa[3] = {a.x, a.y, a.z};
    for (unsigned i = 1; i + 1 < f->mNumIndices; i++) {
        const struct aiVector3D b = m->mVertices[f->mIndices[i]];
        const struct aiVector3D c = m->mVertices[f->mIndices[i + 1]];
        const float pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z};
        if (persp__model_triangle_has_area(pa, pb, pc)) return 1;
    }
    return 0;
}

/* What the post-processing steps need and do not check themselves: the
 * primitive types recomputed from the faces (some readers, PLY's among
 * them, get them wrong on malformed input, and Debian's Assimp aborts on
 * the internal check that catches it), finite positions, and something to
 * triangulate. Returns NULL or what is wrong. */
static const char *prepare_scene(const struct aiScene *ai)
{
    int any = 0, area = 0;
    for (unsigned i = 0; i < ai->mNumMeshes; i++) {
        struct aiMesh *m = ai->mMeshes[i]; /* the scene is this import's own */
        if (!m || !m->mVertices) continue;
        /* Faces without corners pass Assimp 5.2's validation and then break
         * its post-processing: Triangulate asserts, SortByPType crashed the
         * process (SIGBUS, a 288-byte PLY found by the model fuzzer). They
         * are moved behind the others and left out of the count. Moved by
         * swapping, so that every index array is still owned by exactly
         * one face when Assimp frees the whole array. */
        unsigned kept = 0;
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            if (m->mFaces[f].mNumIndices == 0) continue;
            if (f != kept) {
                struct aiFace t = m->mFaces[kept];
                m->mFaces[kept] = m->mFaces[f];
                m->mFaces[f] = t;
            }
            kept++;
        }
        m->mNumFaces = kept;
        unsigned types = 0;
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            unsigned n = m->mFaces[f].mNumIndices;
            types |= n == 1   ? aiPrimitiveType_POINT
                     : n == 2 ? aiPrimitiveType_LINE
                     : n == 3 ? aiPrimitiveType_TRIANGLE
                              : aiPrimitiveType_POLYGON;
        }
        m->mPrimitiveTypes = types;
        any |= (types & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)) != 0;
        for (unsigned v = 0; v < m->mNumVertices; v++)
            if (!persp__model_finite3(m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z))
                return "a vertex position is not finite";
        for (unsigned f = 0; f < m->mNumFaces && !area; f++)
            area = face_has_area(m, &m->mFaces[f]);
    }
    if (!any) return "the model has no triangles to draw";
    return area ? NULL : "the model's triangles all have zero area (nothing to draw)";
}

/* ------------------------------------------------------------- conversion */

typedef struct conv {
    serve *s;
    const struct aiScene *ai;
    uint64_t max_vertices, vertices, parts;
    uint8_t *mesh_sent;     /* per aiMesh: 0 not yet, 1 sent, 2 nothing to draw */
    uint8_t *material_sent; /* per aiMaterial */
    uint8_t *embedded_sent; /* per aiTexture */
    int stand_in;           /* every material is the reader's stand-in (ply_has_materials) */
    int gltf;               /* a glTF or GLB: its texture transforms are applied (gltf_uv_map) */
    int *texcoord;          /* glTF: per aiMaterial, the set KHR_texture_transform's texCoord
                               names for the base colour texture, -1 none (gltf_texcoords) */
    int error;              /* an 'E' was sent, or the socket failed */
} conv;

static int fail(conv *c, int kind, const char *msg)
{
    if (!c->error) send_error(c->s, kind, msg);
    c->error = 1;
    return 0;
}

static void to_floats(const struct aiMatrix4x4 *a, float m[16])
{
    const float rows[4][4] = {{a->a1, a->a2, a->a3, a->a4},
                              {a->b1, a->b2, a->b3, a->b4},
                              {a->c1, a->c2, a->c3, a->c4},
                              {a->d1, a->d2, a->d3, a->d4}};
    for (int r = 0; r < 4; r++)
        for (int col = 0; col < 4; col++)
            m[col * 4 + r] = rows[r][col];
}

static void mul(const float a[16], const float b[16], float out[16])
{
    float t[16];
    for (int col = 0; col < 4; col++)
        for (int r = 0; r < 4; r++) {
            float v = 0;
            for (int k = 0; k < 4; k++) v += a[k * 4 + r] * b[col * 4 + k];
            t[col * 4 + r] = v;
        }
    memcpy(out, t, sizeof t);
}

/* The texture's KHR_texture_transform texCoord, -1 when it names none. */
static int transform_texcoord(json_t *texture_info)
{
    json_t *t = json_object_get(json_object_get(json_object_get(texture_info, "extensions"), "KHR_texture_transform"),
                                "texCoord");
    return json_is_integer(t) && json_integer_value(t) >= 0 && json_integer_value(t) < AI_MAX_NUMBER_OF_TEXTURECOORDS
               ? (int)json_integer_value(t)
               : -1;
}

/* KHR_texture_transform's texCoord "overrides the textureInfo texCoord
 * value if supplied" (the extension's README), which Assimp 5.2's reader
 * does not read: taken from the JSON here for each material's base colour
 * (or, with KHR_materials_pbrSpecularGlossiness, diffuse) texture. The
 * reader makes one aiMaterial per glTF material, in their order (its
 * ImportMaterials; a default one may follow). Fills out[0..n) (-1: none);
 * 0 when out of memory. */
static int gltf_texcoords(const serve *s, unsigned n, int *out)
{
    for (unsigned i = 0; i < n; i++) out[i] = -1;
    const char *json = s->data;
    size_t len = s->size;
    if (len >= 20 && !memcmp(s->data, "glTF", 4)) {
        /* GLB: the JSON chunk (checked by persp before it was sent). */
        uint32_t chunk;
        memcpy(&chunk, s->data + 12, sizeof chunk);
        json = s->data + 20;
        len = chunk <= s->size - 20 ? chunk : s->size - 20;
    }
    json_error_t err;
    json_t *root = json_loadb(json, len, 0, &err);
    if (!root) return !persp__json_parse_ran_out(json, len, &err);
    json_t *used = json_object_get(root, "extensionsUsed");
    int supported = 0;
    for (size_t k = 0; k < json_array_size(used); k++)
        supported |= json_is_string(json_array_get(used, k)) &&
                     !strcmp(json_string_value(json_array_get(used, k)), "KHR_texture_transform");
    json_t *mats = json_object_get(root, "materials");
    for (unsigned i = 0; supported && i < n && i < json_array_size(mats); i++) {
        json_t *m = json_array_get(mats, i);
        int tc = transform_texcoord(json_object_get(json_object_get(m, "pbrMetallicRoughness"), "baseColorTexture"));
        if (tc < 0)
            tc = transform_texcoord(json_object_get(
                json_object_get(json_object_get(m, "extensions"), "KHR_materials_pbrSpecularGlossiness"),
                "diffuseTexture"));
        out[i] = tc;
    }
    json_decref(root);
    return 1;
}

/* The UV channel the material's diffuse texture reads, or 0. */
static unsigned material_uv(const struct aiMaterial *mat)
{
    struct aiString path;
    unsigned uv = 0;
    enum aiTextureType types[2] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR};
    for (int t = 0; t < 2; t++)
        if (aiGetMaterialTexture(mat, types[t], 0, &path, NULL, &uv, NULL, NULL, NULL, NULL) ==
            aiReturn_SUCCESS)
            return uv < AI_MAX_NUMBER_OF_TEXTURECOORDS ? uv : 0;
    return 0;
}

/* glTF's KHR_texture_transform of the material's base colour texture as
 * the affine map of the coordinates Assimp gives (u' = m0 u + m1 v + m2,
 * v' = m3 u + m4 v + m5); 0 when it has none. The extension (its README:
 * offset, rotation, scale; "rotation": counter-clockwise, its example of
 * the lower left quadrant fixes the sign) maps glTF coordinates, whose v
 * runs down the image, by uv' = T(offset) R(rotation) S(scale) uv with
 * u' = cos·sx·u + sin·sy·v + ox, v' = −sin·sx·u + cos·sy·v + oy. Assimp 5.2
 * hands it on as an aiUVTransform for its own convention (rotation
 * negated, about the texture's centre, v flipped: glTF2Importer), which
 * its TransformUVCoords step misapplies; the offset is recovered from that
 * translation and the map applied here, on coordinates whose v Assimp has
 * already flipped (v_gltf = 1 − v). Affine in uv, so applying it to the
 * vertices is exact and costs nothing per pixel. */
static int gltf_uv_map(const struct aiMaterial *mat, float m[6])
{
    static const enum aiTextureType types[2] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR};
    struct aiUVTransform x;
    int found = 0;
    for (int t = 0; t < 2 && !found; t++)
        found = aiGetMaterialUVTransform(mat, _AI_MATKEY_UVTRANSFORM_BASE, types[t], 0, &x) == aiReturn_SUCCESS;
    if (!found) return 0;
    const double r = -(double)x.mRotation, sx = x.mScaling.x, sy = x.mScaling.y;
    const double cr = cos(r), sr = sin(r);
    const double ox = x.mTranslation.x - 0.5 * sx * (-cr + sr + 1.0);
    const double oy = 0.5 * sy * (sr + cr - 1.0) + 1.0 - sy - x.mTranslation.y;
    if (!isfinite(ox) || !isfinite(oy) || !isfinite(sx) || !isfinite(sy) || !isfinite(r)) return 0;
    /* u' from (u, v_g = 1 − v); v' = 1 − v_g'. */
    const double a = cr * sx, b = sr * sy, d = -sr * sx, e = cr * sy;
    m[0] = (float)a, m[1] = (float)-b, m[2] = (float)(b + ox);
    m[3] = (float)-d, m[4] = (float)e, m[5] = (float)(1.0 - e - oy);
    return 1;
}

/* A vertex as persp stores it (position, normal, uv, rgba); 0 if its
 * position is not finite. */
static int convert_vertex(const struct aiMesh *am, unsigned i, const struct aiVector3D *tc,
                          const struct aiColor4D *col, const float *uvmap, float v[12])
{
    memset(v, 0, 12 * sizeof *v);
    const struct aiVector3D *p = &am->mVertices[i];
    if (!persp__model_finite3(p->x, p->y, p->z)) return 0;
    v[0] = p->x, v[1] = p->y, v[2] = p->z;
    if (am->mNormals && persp__model_finite3(am->mNormals[i].x, am->mNormals[i].y, am->mNormals[i].z))
        v[3] = am->mNormals[i].x, v[4] = am->mNormals[i].y, v[5] = am->mNormals[i].z;
    if (tc && isfinite(tc[i].x) && isfinite(tc[i].y)) {
        v[6] = tc[i].x, v[7] = tc[i].y;
        if (uvmap) {
            const float u = v[6], w = v[7];
            v[6] = uvmap[0] * u + uvmap[1] * w + uvmap[2];
            v[7] = uvmap[3] * u + uvmap[4] * w + uvmap[5];
            if (!isfinite(v[6]) || !isfinite(v[7])) v[6] = v[7] = 0.0f;
        }
    }
    if (col) {
        const float c[3] = {col[i].r, col[i].g, col[i].b};
        for (int k = 0; k < 3; k++)
            v[8 + k] = isfinite(c[k]) ? fminf(fmaxf(c[k], 0.0f), 1.0f) : 1.0f;
    } else {
        v[8] = v[9] = v[10] = 1.0f;
    }
    v[11] = 1.0f; /* opaque surfaces: no coverage into the image */
    return 1;
}

static uint64_t vertex_hash(const float v[12])
{
    const unsigned char *b = (const unsigned char *)v;
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (size_t k = 0; k < 12 * sizeof *v; k++) h = (h ^ b[k]) * 1099511628211ull;
    return h;
}

#define NO_VERTEX UINT32_MAX

/* Identical vertices joined here rather than by Assimp's
 * aiProcess_JoinIdenticalVertices: on a million-triangle OBJ that step
 * doubled the importer's peak (311 MB to 608 MB) for 44 bytes of index
 * tables per corner here. One hash table of the first occurrence of each
 * distinct vertex (compared bit for bit) gives remap[i], the distinct
 * vertex of vertex i, numbered in order of first occurrence; returns the
 * distinct count, or SIZE_MAX (out of memory) or SIZE_MAX - 1 (a position
 * is not finite). */
static size_t join_vertices(const struct aiMesh *am, const struct aiVector3D *tc,
                            const struct aiColor4D *col, const float *uvmap, uint32_t *remap)
{
    const size_t n = am->mNumVertices;
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    uint32_t *table = malloc(cap * sizeof *table);
    if (!table) return SIZE_MAX;
    memset(table, 0xff, cap * sizeof *table);
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        float v[12], r[12];
        if (!convert_vertex(am, (unsigned)i, tc, col, uvmap, v)) {
            free(table);
            return SIZE_MAX - 1;
        }
        for (size_t slot = (size_t)vertex_hash(v) & (cap - 1);; slot = (slot + 1) & (cap - 1)) {
            uint32_t first = table[slot];
            if (first == NO_VERTEX) {
                table[slot] = (uint32_t)i;
                remap[i] = (uint32_t)count++;
                break;
            }
            (void)convert_vertex(am, first, tc, col, uvmap, r);
            if (!memcmp(r, v, sizeof v)) {
                remap[i] = remap[first];
                break;
            }
        }
    }
    free(table);
    return count;
}

/* Some exporters write a colour channel that holds nothing (old Blender
 * versions and AMF writers: every colour zero, or -1): drawn as it is, the
 * model is black. Such a channel is left out, as if the file had none. */
static int colours_usable(const struct aiMesh *am)
{
    const struct aiColor4D *c = am->mColors[0];
    if (!c) return 0;
    for (unsigned i = 0; i < am->mNumVertices; i++)
        if (c[i].r > 0.0f || c[i].g > 0.0f || c[i].b > 0.0f) return 1;
    return 0;
}

/* Sends mesh index ('M'), or marks it as having nothing to draw. */
static int send_mesh(conv *c, unsigned index)
{
    const struct aiMesh *am = c->ai->mMeshes[index];
    char msg[160];
    size_t tris = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++)
        if (am->mFaces[f].mNumIndices == 3) tris++;
    if (tris == 0 || am->mNumVertices == 0 || !am->mVertices) {
        c->mesh_sent[index] = 2;
        return 1;
    }
    if (tris > PERSP_SCENE_MAX_INDICES / 3 || am->mNumVertices > PERSP_SCENE_MAX_INDICES) {
        snprintf(msg, sizeof msg, "more than %llu vertices or %u triangle corners",
                 (unsigned long long)c->max_vertices, PERSP_SCENE_MAX_INDICES);
        return fail(c, WIRE_ERR_TOO_LARGE, msg);
    }
    unsigned uv = am->mMaterialIndex < c->ai->mNumMaterials
                      ? material_uv(c->ai->mMaterials[am->mMaterialIndex])
                      : 0;
    if (c->texcoord && am->mMaterialIndex < c->ai->mNumMaterials && c->texcoord[am->mMaterialIndex] >= 0)
        uv = (unsigned)c->texcoord[am->mMaterialIndex];
    const struct aiVector3D *tc = am->mTextureCoords[uv] ? am->mTextureCoords[uv] : am->mTextureCoords[0];
    float uvmap[6];
    const float *map = c->gltf && am->mMaterialIndex < c->ai->mNumMaterials &&
                               gltf_uv_map(c->ai->mMaterials[am->mMaterialIndex], uvmap)
                           ? uvmap
                           : NULL;
    const struct aiColor4D *col = colours_usable(am) ? am->mColors[0] : NULL;
    uint32_t *remap = malloc((size_t)am->mNumVertices * sizeof *remap);
    if (!remap) return fail(c, WIRE_ERR_OUT_OF_MEMORY, "out of memory converting a mesh");
    size_t unique = join_vertices(am, tc, col, map, remap);
    if (unique == SIZE_MAX) {
        free(remap);
        return fail(c, WIRE_ERR_OUT_OF_MEMORY, "out of memory converting a mesh");
    }
    if (unique == SIZE_MAX - 1) {
        free(remap);
        snprintf(msg, sizeof msg, "mesh %u has a vertex position that is not finite", index);
        return fail(c, WIRE_ERR_FORMAT, msg);
    }
    if (unique > PERSP_SCENE_MAX_VERTICES || unique > c->max_vertices - c->vertices) {
        free(remap);
        snprintf(msg, sizeof msg, "more than %llu vertices or %u triangle corners",
                 (unsigned long long)c->max_vertices, PERSP_SCENE_MAX_INDICES);
        return fail(c, WIRE_ERR_TOO_LARGE, msg);
    }
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3) continue;
        for (int k = 0; k < 3; k++)
            if (face->mIndices[k] >= am->mNumVertices) {
                free(remap);
                snprintf(msg, sizeof msg, "mesh %u has a vertex index out of range", index);
                return fail(c, WIRE_ERR_FORMAT, msg);
            }
    }
    c->vertices += unique;
    const int normals = am->mNormals && !normals_unusable(am);
    unsigned flags = (normals ? WIRE_MESH_NORMALS : 0u) | (tc ? 0u : WIRE_MESH_NO_UV);
    int ok = put_u8(c->s, WIRE_MESH) && put_u32(c->s, index) && put_u8(c->s, flags) &&
             put_u64(c->s, unique) && put_u64(c->s, 3 * (uint64_t)tris);
    /* Each distinct vertex at its first occurrence. */
    size_t emitted = 0;
    for (unsigned i = 0; ok && i < am->mNumVertices; i++)
        if (remap[i] == emitted) {
            float v[12];
            (void)convert_vertex(am, i, tc, col, map, v);
            ok = put(c->s, v, sizeof v);
            emitted++;
        }
    for (unsigned f = 0; ok && f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3) continue;
        const uint32_t t[3] = {remap[face->mIndices[0]], remap[face->mIndices[1]],
                               remap[face->mIndices[2]]};
        ok = put(c->s, t, sizeof t);
    }
    free(remap);
    if (!ok) return c->error = 1, 0;
    c->mesh_sent[index] = 1;
    return 1;
}

/* An embedded texture ('X'): an encoded image's bytes, or raw BGRA texels
 * turned into RGBA rows bottom first (persp's row 0 is the bottom). */
static int send_embedded(conv *c, unsigned index)
{
    const struct aiTexture *t = c->ai->mTextures[index];
    char hint[9];
    memset(hint, 0, sizeof hint);
    memcpy(hint, t->achFormatHint, sizeof t->achFormatHint < 8 ? sizeof t->achFormatHint : 8);
    const uint64_t bytes = t->mHeight == 0 ? (uint64_t)t->mWidth : (uint64_t)t->mWidth * t->mHeight * 4;
    if (!t->pcData && bytes) return fail(c, WIRE_ERR_FORMAT, "an embedded texture has no data");
    if (!(put_u8(c->s, WIRE_EMBEDDED) && put_u32(c->s, index) && put_u32(c->s, t->mWidth) &&
          put_u32(c->s, t->mHeight) && put(c->s, hint, sizeof hint)))
        return c->error = 1, 0;
    int ok = 1;
    if (t->mHeight == 0) {
        ok = put(c->s, t->pcData, t->mWidth);
    } else {
        uint8_t row[4096];
        for (unsigned y = 0; ok && y < t->mHeight; y++) {
            const struct aiTexel *src = &t->pcData[(size_t)(t->mHeight - 1 - y) * t->mWidth];
            for (unsigned x0 = 0; ok && x0 < t->mWidth; x0 += sizeof row / 4) {
                unsigned n = t->mWidth - x0 < sizeof row / 4 ? t->mWidth - x0 : (unsigned)(sizeof row / 4);
                for (unsigned x = 0; x < n; x++) {
                    row[4 * x] = src[x0 + x].r, row[4 * x + 1] = src[x0 + x].g;
                    row[4 * x + 2] = src[x0 + x].b, row[4 * x + 3] = src[x0 + x].a;
                }
                ok = put(c->s, row, 4 * (size_t)n);
            }
        }
    }
    if (!ok) return c->error = 1, 0;
    c->embedded_sent[index] = 1;
    return 1;
}

static unsigned wrap_of(enum aiTextureMapMode m)
{
    switch (m) {
    case aiTextureMapMode_Clamp: return WIRE_WRAP_CLAMP;
    case aiTextureMapMode_Mirror: return WIRE_WRAP_MIRROR;
    case aiTextureMapMode_Decal: return WIRE_WRAP_DECAL;
    default: return WIRE_WRAP_REPEAT;
    }
}

/* The embedded texture a material's texture path names ("*N", or the
 * name an embedded texture carries): its index, -1 none, -2 a "*N" the
 * file lacks. */
static long embedded_of(const struct aiScene *ai, const char *file)
{
    if (file[0] == '*') {
        char *end = NULL;
        long emb = strtol(file + 1, &end, 10);
        return !end || *end || emb < 0 || (unsigned long)emb >= ai->mNumTextures ? -2 : emb;
    }
    long emb = -1;
    for (unsigned i = 0; i < ai->mNumTextures; i++)
        if (ai->mTextures[i] && ai->mTextures[i]->mFilename.length &&
            !strcmp(ai->mTextures[i]->mFilename.data, file))
            emb = (long)i;
    return emb;
}

/* A texture of a material: where its image is (a file, an embedded
 * texture, or a "*N" the file lacks) and how it wraps. */
typedef struct mat_tex {
    unsigned kind, wrap[2];
    long emb;
    struct aiString file;
} mat_tex;

/* The first texture of the given types the material names. */
static void material_texture(const conv *c, const struct aiMaterial *am, const enum aiTextureType *types,
                             int ntypes, mat_tex *t)
{
    t->kind = WIRE_TEX_NONE, t->wrap[0] = t->wrap[1] = WIRE_WRAP_REPEAT, t->emb = -1;
    t->file.length = 0, t->file.data[0] = '\0';
    enum aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    for (int k = 0; k < ntypes; k++) {
        if (aiGetMaterialTexture(am, types[k], 0, &t->file, NULL, NULL, NULL, NULL, modes, NULL) !=
            aiReturn_SUCCESS)
            continue;
        if (t->file.length == 0) return;
        t->emb = embedded_of(c->ai, t->file.data);
        t->kind = t->emb >= 0 ? WIRE_TEX_EMBEDDED : t->emb == -2 ? WIRE_TEX_EMBEDDED_MISSING : WIRE_TEX_FILE;
        t->wrap[0] = wrap_of(modes[0]), t->wrap[1] = wrap_of(modes[1]);
        return;
    }
    t->file.length = 0, t->file.data[0] = '\0';
}

static int put_texture(conv *c, const mat_tex *t)
{
    return put_u8(c->s, (uint8_t)t->kind) && put_u32(c->s, t->emb >= 0 ? (uint32_t)t->emb : WIRE_NONE) &&
           put_u8(c->s, (uint8_t)t->wrap[0]) && put_u8(c->s, (uint8_t)t->wrap[1]);
}

/* Colours (diffuse, specular, ambient, emissive), shininess and the
 * shading model into *flags. An unlit material (glTF's
 * KHR_materials_unlit, which Assimp 5.2 gives as aiShadingMode_Unlit;
 * COLLADA's <constant>) is drawn with its base colour alone. */
static void material_colours(const struct aiMaterial *am, unsigned *flags, float col[12], float *shin)
{
    static const struct {
        const char *key;
        unsigned flag;
    } keys[4] = {{"$clr.diffuse", WIRE_MAT_KD},
                 {"$clr.specular", WIRE_MAT_KS},
                 {"$clr.ambient", WIRE_MAT_KA},
                 {"$clr.emissive", WIRE_MAT_KE}};
    for (int k = 0; k < 4; k++) {
        struct aiColor4D v;
        if (aiGetMaterialColor(am, keys[k].key, 0, 0, &v) != aiReturn_SUCCESS) continue;
        *flags |= keys[k].flag;
        col[3 * k] = v.r, col[3 * k + 1] = v.g, col[3 * k + 2] = v.b;
    }
    unsigned one = 1;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_SHININESS, shin, &one) != aiReturn_SUCCESS) *shin = 0;
    int model = 0;
    one = 1;
    if (aiGetMaterialIntegerArray(am, AI_MATKEY_SHADING_MODEL, &model, &one) == aiReturn_SUCCESS &&
        model == aiShadingMode_Unlit)
        *flags |= WIRE_MAT_UNLIT;
}

static int send_material(conv *c, unsigned index)
{
    const struct aiMaterial *am = c->ai->mMaterials[index];
    struct aiString name;
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
        name.length = 0, name.data[0] = '\0';
    unsigned flags = 0;
    float col[12] = {0}, shin = 0;
    mat_tex base, glow;
    memset(&base, 0, sizeof base);
    memset(&glow, 0, sizeof glow);
    base.emb = glow.emb = -1;
    /* Assimp's stand-in for geometry without a material: persp's default. */
    if (c->stand_in || !strcmp(name.data, AI_DEFAULT_MATERIAL_NAME)) {
        flags |= WIRE_MAT_STAND_IN;
    } else {
        material_colours(am, &flags, col, &shin);
        static const enum aiTextureType base_types[2] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR};
        static const enum aiTextureType glow_types[1] = {aiTextureType_EMISSIVE};
        material_texture(c, am, base_types, 2, &base);
        material_texture(c, am, glow_types, 1, &glow);
    }
    const mat_tex *tex[2] = {&base, &glow};
    for (int k = 0; k < 2; k++)
        if (tex[k]->kind == WIRE_TEX_EMBEDDED && !c->embedded_sent[tex[k]->emb] &&
            !send_embedded(c, (unsigned)tex[k]->emb))
            return 0;
    if (!(put_u8(c->s, WIRE_MATERIAL) && put_u32(c->s, index) && put_u8(c->s, (uint8_t)flags) &&
          put(c->s, col, 9 * sizeof *col) && put(c->s, &shin, sizeof shin) && put_texture(c, &base) &&
          put_text(c->s, name.data) && put_text(c->s, base.kind == WIRE_TEX_NONE ? "" : base.file.data) &&
          put(c->s, col + 9, 3 * sizeof *col) && put_texture(c, &glow) &&
          put_text(c->s, glow.kind == WIRE_TEX_NONE ? "" : glow.file.data)))
        return c->error = 1, 0;
    c->material_sent[index] = 1;
    return 1;
}

static int walk(conv *c, const struct aiNode *node, const float parent[16], int depth)
{
    if (depth > PERSP_MODEL_MAX_DEPTH) {
        char msg[64];
        snprintf(msg, sizeof msg, "node hierarchy deeper than %d", PERSP_MODEL_MAX_DEPTH);
        return fail(c, WIRE_ERR_TOO_LARGE, msg);
    }
    float local[16], xf[16];
    to_floats(&node->mTransformation, local);
    mul(parent, local, xf);
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        unsigned mi = node->mMeshes[i];
        if (mi >= c->ai->mNumMeshes || !c->ai->mMeshes[mi]) continue;
        if (!c->mesh_sent[mi] && !send_mesh(c, mi)) return 0;
        if (c->mesh_sent[mi] != 1) continue;
        unsigned mat = c->ai->mMeshes[mi]->mMaterialIndex;
        struct aiString name;
        name.length = 0, name.data[0] = '\0';
        if (mat < c->ai->mNumMaterials && c->ai->mMaterials[mat]) {
            if (aiGetMaterialString(c->ai->mMaterials[mat], AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
                name.length = 0, name.data[0] = '\0';
            if (!c->material_sent[mat] && !send_material(c, mat)) return 0;
        } else {
            mat = WIRE_NONE;
        }
        /* A node graph that names a subtree many times (a glTF DAG doubling
         * per level) instances without bound: stop at persp's limit. */
        if (++c->parts > PERSP_SCENE_MAX_OBJECTS) {
            char msg[64];
            snprintf(msg, sizeof msg, "more than %d mesh instances", PERSP_SCENE_MAX_OBJECTS);
            return fail(c, WIRE_ERR_TOO_LARGE, msg);
        }
        if (!(put_u8(c->s, WIRE_PART) && put_u32(c->s, mi) && put_u32(c->s, mat) &&
              put(c->s, xf, sizeof xf) && put_text(c->s, name.data)))
            return c->error = 1, 0;
    }
    for (unsigned i = 0; i < node->mNumChildren; i++)
        if (node->mChildren[i] && !walk(c, node->mChildren[i], xf, depth + 1)) return 0;
    return 1;
}

/* A number of the scene's metadata, as Assimp stores it by type; 0 when
 * the key is missing or not a number. */
static int meta_number(const struct aiScene *ai, const char *key, double *out)
{
    const struct aiMetadata *md = ai->mMetaData;
    if (!md || !md->mKeys || !md->mValues) return 0;
    for (unsigned i = 0; i < md->mNumProperties; i++) {
        if (strcmp(md->mKeys[i].data, key) != 0) continue;
        const struct aiMetadataEntry *e = &md->mValues[i];
        if (!e->mData) return 0;
        switch (e->mType) {
        case AI_INT32: *out = *(const int32_t *)e->mData; return 1;
        case AI_UINT64: *out = (double)*(const uint64_t *)e->mData; return 1;
        case AI_FLOAT: *out = *(const float *)e->mData; return 1;
        case AI_DOUBLE: *out = *(const double *)e->mData; return 1;
        default: return 0;
        }
    }
    return 0;
}

/* FBX files declare their axes and unit (GlobalSettings: UpAxis, FrontAxis,
 * CoordAxis with their signs, UnitScaleFactor in centimetres per unit),
 * which Assimp 5.2 passes on as metadata without applying them: a file
 * exported with +z up lay on its side, and one in centimetres (Blender's
 * default FBX) came out 100 times the size of the same model as glTF. The
 * root transform turns the declared axes into persp's (x right, y up, z
 * towards the viewer: CoordAxis, UpAxis, FrontAxis) and the unit into
 * metres, glTF's. Axes that are not three distinct ones with signs ±1 are
 * left as they are. */
static void fbx_root(const struct aiScene *ai, float m[16])
{
    memset(m, 0, 16 * sizeof *m);
    m[0] = m[5] = m[10] = m[15] = 1.0f;
    static const char *const axis_keys[3][2] = {
        {"CoordAxis", "CoordAxisSign"}, {"UpAxis", "UpAxisSign"}, {"FrontAxis", "FrontAxisSign"}};
    int axis[3], sign[3], used = 0, ok = 1;
    for (int k = 0; k < 3 && ok; k++) {
        double a, s;
        ok = meta_number(ai, axis_keys[k][0], &a) && meta_number(ai, axis_keys[k][1], &s) &&
             (a == 0 || a == 1 || a == 2) && (s == 1 || s == -1) && !(used & (1 << (int)a));
        if (!ok) break;
        axis[k] = (int)a, sign[k] = (int)s;
        used |= 1 << axis[k];
    }
    if (ok) {
        memset(m, 0, 16 * sizeof *m);
        for (int k = 0; k < 3; k++) m[axis[k] * 4 + k] = (float)sign[k];
        m[15] = 1.0f;
    }
    double unit;
    if (meta_number(ai, "UnitScaleFactor", &unit) && isfinite(unit) && unit > 0.0 && unit != 100.0) {
        const float sc = (float)(unit / 100.0);
        for (int col = 0; col < 3; col++)
            for (int r = 0; r < 3; r++) m[col * 4 + r] *= sc;
    }
}

/* Whether a PLY file defines materials ("element material" in its header).
 * Without one, Assimp 5.2's PLY reader makes a stand-in that is not named
 * as its others are (AI_DEFAULT_MATERIAL_NAME) and is white in ambient,
 * diffuse and specular: the same mesh drew washed out next to its STL,
 * which gets persp's default material. */
static int ply_has_materials(const char *data, size_t size)
{
    const char *end = NULL;
    for (size_t i = 0; i + 10 <= size && !end; i++)
        if (!memcmp(data + i, "end_header", 10)) end = data + i;
    const size_t header = end ? (size_t)(end - data) : size;
    static const char key[] = "element material";
    for (size_t i = 0; i + sizeof key - 1 <= header; i++)
        if (!memcmp(data + i, key, sizeof key - 1)) return 1;
    return 0;
}

/* FBX by its name or its first bytes (binary, or ASCII's comment line). */
static int is_fbx(const char *name, const char *data, size_t size)
{
    return persp__model_has_ext(name, "fbx") || (size >= 18 && !memcmp(data, "Kaydara FBX Binary", 18)) ||
           (size >= 5 && !memcmp(data, "; FBX", 5));
}

/* ----------------------------------------------------------------- import */

/* Whether Assimp's message says an allocation failed (its readers catch
 * std::bad_alloc and report what() as the reason). */
static int says_out_of_memory(const char *why)
{
    return strstr(why, "bad_alloc") != NULL || strstr(why, "out of memory") != NULL;
}

static void import_and_send(serve *s, uint64_t max_vertices, int (*out_of_memory)(void))
{
    struct aiFileIO fio = {file_open, file_close, (aiUserData)(void *)s};
    struct aiPropertyStore *props = aiCreatePropertyStore();
    if (!props) {
        send_error(s, WIRE_ERR_OUT_OF_MEMORY, "out of memory");
        return;
    }
    aiSetImportPropertyInteger(props, AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    /* Read and validated first, then prepared (prepare_scene) for the
     * post-processing steps. A scene they would fail on is refused before
     * them: Assimp 5.2 crashes releasing a scene whose post-processing
     * failed. GenUVCoords turns a texture projected by the file's mapping
     * (sphere, cylinder, box, plane: LightWave and others) into coordinates
     * per vertex; without it such a texture was drawn as one texel's
     * colour. TransformUVCoords is left out: Assimp 5.2 scales glTF's
     * KHR_texture_transform about the texture's centre, not its origin as
     * the extension says (a scale of 2 gave u in [-0.5, 1.5]); persp
     * applies the extension itself (gltf_uv_map). Normals the
     * file lacks are not Assimp's to make: its GenSmoothNormals cannot split
     * a vertex the file shares between faces (a PLY cube of 8 vertices came
     * out with one normal a corner), so persp makes them after the import,
     * by the format's rule (persp__mesh_crease_normals). */
    const unsigned steps = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_GenUVCoords;
    const char *wrong = NULL;
    const struct aiScene *ai =
        aiImportFileExWithProperties(s->main_name, aiProcess_ValidateDataStructure, &fio, props);
    if (ai && (wrong = prepare_scene(ai)) != NULL) {
        aiReleaseImport(ai);
        ai = NULL;
    }
    if (ai) ai = aiApplyPostProcessing(ai, steps);
    aiReleasePropertyStore(props);
    if (!ai) {
        char why[512];
        snprintf(why, sizeof why, "%s", wrong ? "" : aiGetErrorString());
        why[strcspn(why, "\r\n")] = '\0';
        if (s->chan.failed) return;
        if (s->out_of_memory || (out_of_memory && out_of_memory()) || says_out_of_memory(why))
            send_error(s, WIRE_ERR_OUT_OF_MEMORY, "the importer ran out of memory");
        else if (wrong)
            send_error(s, WIRE_ERR_FORMAT, wrong);
        /* Assimp 5.2's words when no reader takes the file. */
        else if (!strncmp(why, "No suitable reader found", 24))
            send_error(s, WIRE_ERR_NO_READER, why);
        else
            send_error(s, WIRE_ERR_IMPORT, why);
        return;
    }
    conv c;
    memset(&c, 0, sizeof c);
    c.s = s;
    c.ai = ai;
    c.max_vertices = max_vertices;
    c.mesh_sent = calloc(ai->mNumMeshes + 1u, 1);
    c.material_sent = calloc(ai->mNumMaterials + 1u, 1);
    c.embedded_sent = calloc(ai->mNumTextures + 1u, 1);
    c.stand_in = (persp__model_has_ext(s->main_name, "ply") ||
                  (s->size >= 4 && !memcmp(s->data, "ply", 3) && (s->data[3] == '\n' || s->data[3] == '\r'))) &&
                 !ply_has_materials(s->data, s->size);
    c.gltf = persp__model_has_ext(s->main_name, "gltf") || persp__model_has_ext(s->main_name, "glb");
    int texcoords_read = 1;
    if (c.gltf)
        texcoords_read = (c.texcoord = malloc((ai->mNumMaterials + 1u) * sizeof *c.texcoord)) != NULL &&
                         gltf_texcoords(s, ai->mNumMaterials, c.texcoord);
    if (!texcoords_read || !c.mesh_sent || !c.material_sent || !c.embedded_sent) {
        fail(&c, WIRE_ERR_OUT_OF_MEMORY, "out of memory");
    } else if (put_u8(s, WIRE_HEADER) && put_u32(s, ai->mNumMeshes) && put_u32(s, ai->mNumMaterials) &&
               put_u32(s, ai->mNumTextures)) {
        float root[16];
        if (is_fbx(s->main_name, s->data, s->size))
            fbx_root(ai, root);
        else
            memset(root, 0, sizeof root), root[0] = root[5] = root[10] = root[15] = 1.0f;
        if (ai->mRootNode && walk(&c, ai->mRootNode, root, 0)) put_u8(s, WIRE_DONE), flush_out(s);
        else if (!c.error && !ai->mRootNode) put_u8(s, WIRE_DONE), flush_out(s);
    }
    free(c.mesh_sent);
    free(c.material_sent);
    free(c.texcoord);
    free(c.embedded_sent);
    aiReleaseImport(ai);
}

int persp__import_serve(int fd, int (*out_of_memory)(void))
{
    serve *s = calloc(1, sizeof *s);
    if (!s) return -1;
    s->chan.fd = fd;
    uint32_t head[2], name_len = 0;
    uint64_t max_vertices = 0, size = 0;
    char *name = NULL, *data = NULL;
    int rc = -1;
    if (!persp__wire_read(&s->chan, head, sizeof head) || head[0] != WIRE_MAGIC || head[1] != WIRE_VERSION ||
        !persp__wire_read(&s->chan, &max_vertices, sizeof max_vertices) ||
        !persp__wire_read(&s->chan, &name_len, sizeof name_len) || name_len == 0 || name_len > WIRE_MAX_TEXT)
        goto done;
    if (!(name = malloc((size_t)name_len + 1)) || !persp__wire_read(&s->chan, name, name_len)) goto done;
    name[name_len] = '\0';
    if (!persp__wire_read(&s->chan, &size, sizeof size) || size >= SIZE_MAX) goto done;
    if (!(data = malloc((size_t)size + 1))) {
        persp__wire_skip(&s->chan, size);
        send_error(s, WIRE_ERR_OUT_OF_MEMORY, "the importer ran out of memory");
        rc = 0;
        goto done;
    }
    if (!persp__wire_read(&s->chan, data, (size_t)size)) goto done;
    data[size] = '\0';
    s->main_name = name;
    s->data = data;
    s->size = (size_t)size;
    import_and_send(s, max_vertices, out_of_memory);
    rc = s->chan.failed ? -1 : 0;
done:
    free_files(s);
    free(name);
    free(data);
    free(s);
    return rc;
}
