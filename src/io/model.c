/*
 * Models through Assimp's C API: every format Assimp reads (glTF 2.0 and
 * GLB, PLY, STL, FBX, COLLADA, 3DS, ...) becomes persp meshes, materials
 * and textures. OBJ/MTL goes to persp's own reader (src/io/obj.c); what
 * the two share (the files a model names, colours, parts) is in
 * src/io/model_refs.c.
 *
 * Assimp reads the model through persp's own file callbacks: the main file
 * is served from memory (so that loading from a file and from memory take
 * the same path, and text files can be normalised first), the files it
 * refers to are opened relative to the model's folder, and a file that
 * cannot be opened becomes a warning, Assimp carrying on without it.
 * Textures are decoded by persp (persp_image_load / _load_memory), so the
 * image limits and decoders are the same as everywhere else.
 */
#include "core/internal.h"
#include "io/model.h"
#include "io/obj.h"
#include "io/text.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <ctype.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Assimp's C API keeps the last error message in a process-wide string;
 * imports are serialised so that each reads its own. */
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

/* ------------------------------------------------------------ file access */

typedef struct model_io {
    persp_context *ctx;
    const char *display;   /* the model's name in messages */
    const char *main_name; /* what Assimp is asked to read */
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
    int others;           /* files other than the main one were opened */
    /* Text files the model named (material libraries, glTF), kept until the
     * load ends: for the line a texture is named on, and to tell whether
     * Assimp's message quotes one of them. */
    struct {
        char name[256];
        char *text;
        size_t size;
    } kept[4];
    int nkept;
    int out_of_memory; /* a file could not be opened for want of memory */
    int uri;           /* glTF: the names are URIs (persp__uri_decode) */
} model_io;

typedef struct model_file {
    const char *data;
    size_t size, pos;
    char *owned;
} model_file;

static size_t file_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    model_file *mf = (model_file *)(void *)f->UserData;
    if (size == 0 || count == 0) return 0;
    size_t left = mf->size - mf->pos, n = left / size;
    if (n > count) n = count;
    memcpy(buf, mf->data + mf->pos, n * size);
    mf->pos += n * size;
    return n;
}

static size_t file_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0;
}

static size_t file_tell(struct aiFile *f)
{
    return ((model_file *)(void *)f->UserData)->pos;
}
static size_t file_size(struct aiFile *f)
{
    return ((model_file *)(void *)f->UserData)->size;
}
static void file_flush(struct aiFile *f)
{
    (void)f;
}

static enum aiReturn file_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    model_file *mf = (model_file *)(void *)f->UserData;
    size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? mf->pos : mf->size;
    if (origin != aiOrigin_SET && origin != aiOrigin_CUR && origin != aiOrigin_END)
        return aiReturn_FAILURE;
    if (offset > mf->size - base) return aiReturn_FAILURE;
    mf->pos = base + offset;
    return aiReturn_SUCCESS;
}

/* Assimp's OBJ reader, when a material library is missing, tries the
 * model's own name with .mtl: a guess, not a reference worth a warning. */
static int is_guess(const model_io *io, const char *rel)
{
    const char *dot = strrchr(io->main_name, '.');
    size_t stem = dot ? (size_t)(dot - io->main_name) : strlen(io->main_name);
    if (strncmp(rel, io->main_name, stem) != 0 || strcmp(rel + stem, ".mtl") != 0) return 0;
    size_t n = strlen(rel);
    for (size_t i = 0; i + n <= io->size; i++)
        if (memcmp(io->data + i, rel, n) == 0) return 0;
    return 1;
}

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

static void warn_missing(model_io *io, const char *rel, const char *why)
{
    if (is_guess(io, rel)) return;
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

static struct aiFile *file_open(struct aiFileIO *fio, const char *name, const char *mode)
{
    model_io *io = (model_io *)(void *)fio->UserData;
    if (!name || !mode || mode[0] != 'r') return NULL;
    const char *data = NULL;
    size_t size = 0;
    char *owned = NULL;
    if (!strcmp(name, io->main_name)) {
        data = io->data;
        size = io->size;
    } else {
        char rel[PERSP_PATH_MAX];
        persp__model_clean_rel(name, rel, sizeof rel);
        if (!io->base_dir) {
            warn_missing(io, rel, "no folder to read it from");
            return NULL;
        }
        const char *why = NULL;
        char decoded[PERSP_PATH_MAX];
        persp_status st = PERSP_ERR_IO;
        /* A glTF names its buffers by URI; the name as written is the
         * fallback, should a reader have decoded it already. */
        if (io->uri && persp__uri_decode(rel, decoded, sizeof decoded)) {
            st = persp__model_read_ref(io->ctx, io->base_dir, io->root, decoded, &owned, &size, &why);
            if (st != PERSP_OK && st != PERSP_ERR_OUT_OF_MEMORY) {
                const char *raw_why = NULL;
                if (persp__model_read_ref(io->ctx, io->base_dir, io->root, rel, &owned, &size, &raw_why) ==
                    PERSP_OK)
                    st = PERSP_OK;
                else
                    memcpy(rel, decoded, strlen(decoded) + 1);
            }
        } else {
            st = persp__model_read_ref(io->ctx, io->base_dir, io->root, rel, &owned, &size, &why);
        }
        if (st == PERSP_ERR_OUT_OF_MEMORY) {
            io->out_of_memory = 1;
            return NULL;
        }
        if (st != PERSP_OK) {
            warn_missing(io, rel, why);
            return NULL;
        }
        io->others = 1;
        if (is_line_text(rel) || persp__model_has_ext(rel, "gltf")) {
            size = normalise_text(owned, size, is_line_text(rel));
            keep_text(io, rel, owned, size);
        }
        data = owned;
    }
    struct aiFile *f = persp__calloc(io->ctx, 1, sizeof *f);
    model_file *mf = persp__calloc(io->ctx, 1, sizeof *mf);
    if (!f || !mf) {
        persp__free(io->ctx, f);
        persp__free(io->ctx, mf);
        persp__free(io->ctx, owned);
        io->out_of_memory = 1;
        return NULL;
    }
    mf->data = data ? data : "";
    mf->size = size;
    mf->owned = owned;
    f->ReadProc = file_read;
    f->WriteProc = file_write;
    f->TellProc = file_tell;
    f->FileSizeProc = file_size;
    f->SeekProc = file_seek;
    f->FlushProc = file_flush;
    f->UserData = (aiUserData)(void *)mf;
    return f;
}

static void file_close(struct aiFileIO *fio, struct aiFile *f)
{
    model_io *io = (model_io *)(void *)fio->UserData;
    if (!f) return;
    model_file *mf = (model_file *)(void *)f->UserData;
    if (mf) persp__free(io->ctx, mf->owned);
    persp__free(io->ctx, mf);
    persp__free(io->ctx, f);
}

/* ------------------------------------------------------------- conversion */

typedef struct importer {
    persp_scene *scene;
    persp_context *ctx;
    const struct aiScene *ai;
    const char *display, *base_dir, *root;
    const model_io *io; /* the model's text and the text files it named */
    persp_texcache *cache;
    size_t max_vertices, vertices;
    int *mesh_index;     /* per aiMesh: scene mesh, -1 not yet, -2 nothing to draw */
    int *material_index; /* per aiMaterial: scene material, -1 not yet */
    int *embedded_index; /* per aiTexture: scene texture, -1 not yet, -2 failed */
    persp_model *out;
    size_t part_cap;
    persp_model_refs refs; /* texture files */
    int out_of_memory;     /* a texture could not be loaded for want of memory */
    int stand_in;          /* every material is the reader's stand-in (ply_has_materials) */
} importer;

static void where_io(const void *user, const char *rel, char *out, size_t cap)
{
    where((const model_io *)user, rel, out, cap);
}

static persp_mat4 to_mat4(const struct aiMatrix4x4 *a)
{
    const float rows[4][4] = {{a->a1, a->a2, a->a3, a->a4},
                              {a->b1, a->b2, a->b3, a->b4},
                              {a->c1, a->c2, a->c3, a->c4},
                              {a->d1, a->d2, a->d3, a->d4}};
    persp_mat4 m;
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            m.m[c * 4 + r] = rows[r][c];
    return m;
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

/* Vertex i of an Assimp mesh as persp stores it; 0 if its position is
 * not finite. */
static int convert_vertex(const struct aiMesh *am, unsigned i, const struct aiVector3D *tc,
                          const struct aiColor4D *col, persp_vertex *v)
{
    memset(v, 0, sizeof *v);
    const struct aiVector3D *p = &am->mVertices[i];
    if (!persp__model_finite3(p->x, p->y, p->z)) return 0;
    v->pos[0] = p->x, v->pos[1] = p->y, v->pos[2] = p->z;
    if (am->mNormals && persp__model_finite3(am->mNormals[i].x, am->mNormals[i].y, am->mNormals[i].z)) {
        v->normal[0] = am->mNormals[i].x, v->normal[1] = am->mNormals[i].y,
        v->normal[2] = am->mNormals[i].z;
    }
    if (tc && isfinite(tc[i].x) && isfinite(tc[i].y)) v->uv[0] = tc[i].x, v->uv[1] = tc[i].y;
    if (col) {
        const float c[4] = {col[i].r, col[i].g, col[i].b, col[i].a};
        for (int k = 0; k < 3; k++)
            v->color[k] = isfinite(c[k]) ? fminf(fmaxf(c[k], 0.0f), 1.0f) : 1.0f;
        v->color[3] = 1.0f; /* opaque surfaces: no coverage into the image */
    } else {
        v->color[0] = v->color[1] = v->color[2] = v->color[3] = 1.0f;
    }
    return 1;
}

static uint64_t vertex_hash(const persp_vertex *v)
{
    const unsigned char *b = (const unsigned char *)v;
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (size_t k = 0; k < sizeof *v; k++) h = (h ^ b[k]) * 1099511628211ull;
    return h;
}

#define NO_VERTEX UINT32_MAX

/* Identical vertices joined here rather than by Assimp's
 * aiProcess_JoinIdenticalVertices: on a million-triangle OBJ that step
 * doubled the importer's peak (311 MB to 608 MB) for 44 bytes of index
 * tables per corner here. One hash table of the first occurrence of each
 * distinct vertex (compared byte for byte as persp stores it) gives
 * remap[i], the distinct vertex of corner vertex i, numbered in order of
 * first occurrence as Assimp numbers them; *unique is the distinct count. */
static persp_status join_vertices(importer *im, unsigned index, const struct aiVector3D *tc,
                                  const struct aiColor4D *col, uint32_t *remap, size_t *unique)
{
    const struct aiMesh *am = im->ai->mMeshes[index];
    const size_t n = am->mNumVertices;
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    uint32_t *table = persp__alloc(im->ctx, cap * sizeof *table);
    if (!table) return persp__fail(im->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", im->display);
    memset(table, 0xff, cap * sizeof *table);
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        persp_vertex v, r;
        if (!convert_vertex(am, (unsigned)i, tc, col, &v)) {
            persp__free(im->ctx, table);
            return persp__fail(im->ctx, PERSP_ERR_FORMAT,
                               "%s: mesh %u has a vertex position that is not finite", im->display,
                               index);
        }
        size_t slot = (size_t)vertex_hash(&v) & (cap - 1);
        for (;; slot = (slot + 1) & (cap - 1)) {
            uint32_t first = table[slot];
            if (first == NO_VERTEX) {
                table[slot] = (uint32_t)i;
                remap[i] = (uint32_t)count++;
                break;
            }
            (void)convert_vertex(am, first, tc, col, &r);
            if (!memcmp(&r, &v, sizeof v)) {
                remap[i] = remap[first];
                break;
            }
        }
    }
    persp__free(im->ctx, table);
    *unique = count;
    return PERSP_OK;
}

static persp_status convert_mesh(importer *im, unsigned index, int *out)
{
    const struct aiMesh *am = im->ai->mMeshes[index];
    size_t tris = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++)
        if (am->mFaces[f].mNumIndices == 3) tris++;
    if (tris == 0 || am->mNumVertices == 0) {
        *out = -2;
        return PERSP_OK;
    }
    if (tris > PERSP_SCENE_MAX_INDICES / 3 || am->mNumVertices > PERSP_SCENE_MAX_INDICES)
        return persp__fail(im->ctx, PERSP_ERR_TOO_LARGE,
                           "%s: more than %zu vertices or %u triangle corners", im->display,
                           im->max_vertices, PERSP_SCENE_MAX_INDICES);
    unsigned uv = am->mMaterialIndex < im->ai->mNumMaterials
                      ? material_uv(im->ai->mMaterials[am->mMaterialIndex])
                      : 0;
    const struct aiVector3D *tc =
        am->mTextureCoords[uv] ? am->mTextureCoords[uv] : am->mTextureCoords[0];
    const struct aiColor4D *col = am->mColors[0];
    uint32_t *remap = persp__calloc(im->ctx, am->mNumVertices, sizeof *remap);
    if (!remap) return persp__fail(im->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", im->display);
    size_t unique = 0;
    persp_status st = join_vertices(im, index, tc, col, remap, &unique);
    if (st == PERSP_OK && (unique > PERSP_SCENE_MAX_VERTICES || unique > im->max_vertices - im->vertices))
        st = persp__fail(im->ctx, PERSP_ERR_TOO_LARGE,
                         "%s: more than %zu vertices or %u triangle corners", im->display,
                         im->max_vertices, PERSP_SCENE_MAX_INDICES);
    if (st != PERSP_OK) {
        persp__free(im->ctx, remap);
        return st;
    }
    im->vertices += unique;
    persp_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.vertex_count = unique;
    mesh.index_count = 3 * tris;
    mesh.vertices = persp__calloc(im->ctx, mesh.vertex_count, sizeof *mesh.vertices);
    mesh.indices = persp__calloc(im->ctx, mesh.index_count, sizeof *mesh.indices);
    if (!mesh.vertices || !mesh.indices) {
        persp__free(im->ctx, remap);
        persp__mesh_free(im->ctx, &mesh);
        return persp__fail(im->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", im->display);
    }
    /* Each distinct vertex is stored at its first occurrence. */
    size_t emitted = 0;
    for (unsigned i = 0; i < am->mNumVertices; i++)
        if (remap[i] == emitted) (void)convert_vertex(am, i, tc, col, &mesh.vertices[emitted++]);
    size_t k = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3) continue;
        for (int c = 0; c < 3; c++) {
            if (face->mIndices[c] >= am->mNumVertices) {
                persp__free(im->ctx, remap);
                persp__mesh_free(im->ctx, &mesh);
                return persp__fail(im->ctx, PERSP_ERR_FORMAT,
                                   "%s: mesh %u has a vertex index out of range", im->display,
                                   index);
            }
            mesh.indices[k++] = remap[face->mIndices[c]];
        }
    }
    persp__free(im->ctx, remap);
    mesh.no_uv = tc == NULL;
    mesh.has_normals = am->mNormals != NULL;
    if (!mesh.has_normals) persp__mesh_compute_normals(&mesh);
    return persp__scene_add_mesh(im->scene, &mesh, out);
}

/* An embedded texture: compressed (PNG, JPEG bytes) or raw BGRA texels. */
static persp_status embedded_texture(importer *im, unsigned index, int *out)
{
    const struct aiTexture *t = im->ai->mTextures[index];
    persp_image img;
    memset(&img, 0, sizeof img);
    persp_status st;
    char name[512];
    snprintf(name, sizeof name, "%s: embedded texture %u", im->display, index);
    if (t->mHeight == 0) {
        st = persp_image_load_memory(im->ctx, t->pcData, t->mWidth, name, &img);
    } else {
        st = persp__image_check_size(im->ctx, name, t->mWidth, t->mHeight);
        if (st == PERSP_OK) st = persp_image_alloc(im->ctx, (int)t->mWidth, (int)t->mHeight, &img);
        if (st == PERSP_OK) /* Texel rows run top to bottom; persp's row 0 is the bottom. */
            for (unsigned y = 0; y < t->mHeight; y++) {
                const struct aiTexel *src = &t->pcData[(size_t)(t->mHeight - 1 - y) * t->mWidth];
                uint8_t *dst = img.pixels + (size_t)y * img.stride;
                for (unsigned x = 0; x < t->mWidth; x++) {
                    dst[4 * x] = src[x].r, dst[4 * x + 1] = src[x].g;
                    dst[4 * x + 2] = src[x].b, dst[4 * x + 3] = src[x].a;
                }
            }
    }
    persp_texture *tex = NULL;
    persp__image_set_opaque(&img);
    if (st == PERSP_OK) st = persp_texture_create(im->ctx, &img, &tex);
    persp_image_free(im->ctx, &img);
    if (st == PERSP_OK) st = persp__scene_add_texture(im->scene, tex, out);
    return st;
}

/* The scene texture for a material's texture path, or -1 with a warning. */
static int material_texture(importer *im, const char *material, const char *file)
{
    const struct aiTexture *const *texs = (const struct aiTexture *const *)im->ai->mTextures;
    long emb = -1;
    if (file[0] == '*') {
        char *end = NULL;
        emb = strtol(file + 1, &end, 10);
        if (!end || *end || emb < 0 || (unsigned long)emb >= im->ai->mNumTextures) emb = -2;
    } else {
        for (unsigned i = 0; i < im->ai->mNumTextures; i++)
            if (texs[i]->mFilename.length && !strcmp(texs[i]->mFilename.data, file)) emb = (long)i;
    }
    char qm[PERSP_QUOTE_BYTES], qf[PERSP_QUOTE_BYTES];
    persp__quote(material, strlen(material), qm, sizeof qm);
    if (emb == -2) {
        persp__warn(im->ctx,
                    "%s: material '%s' names embedded texture '%s', which the file lacks; drawing "
                    "it untextured",
                    im->display, qm, persp__quote(file, strlen(file), qf, sizeof qf));
        return -1;
    }
    if (emb >= 0) {
        int *slot = &im->embedded_index[emb];
        persp_status est = *slot == -1 ? embedded_texture(im, (unsigned)emb, slot) : PERSP_OK;
        if (est == PERSP_ERR_OUT_OF_MEMORY) {
            im->out_of_memory = 1;
            persp__model_texture_oom(im->ctx, im->display, persp__quote(file, strlen(file), qf, sizeof qf), qm);
            return -1;
        }
        if (est != PERSP_OK) {
            persp__warn(im->ctx, "%s: material '%s': %s; drawing it untextured", im->display, qm,
                        persp_context_error(im->ctx));
            *slot = -2;
        }
        return *slot >= 0 ? *slot : -1;
    }
    int index = persp__model_texture_file(&im->refs, material, file);
    if (im->refs.out_of_memory) im->out_of_memory = 1;
    return index;
}

static persp_wrap wrap_of(enum aiTextureMapMode m)
{
    switch (m) {
    case aiTextureMapMode_Clamp:
        return PERSP_WRAP_CLAMP_TO_EDGE;
    case aiTextureMapMode_Mirror:
        return PERSP_WRAP_MIRRORED_REPEAT;
    case aiTextureMapMode_Decal:
        return PERSP_WRAP_CLAMP_TO_BORDER;
    default:
        return PERSP_WRAP_REPEAT;
    }
}

static persp_status convert_material(importer *im, unsigned index, int *out)
{
    const struct aiMaterial *am = im->ai->mMaterials[index];
    persp_material m = persp__material_default();
    struct aiString name;
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
        name.length = 0, name.data[0] = '\0';
    /* Assimp's stand-in for geometry without a material: persp's default. */
    if (!im->stand_in && strcmp(name.data, AI_DEFAULT_MATERIAL_NAME) != 0) {
        struct aiColor4D c;
        float kd[3], ks[3], ka[3], shin = 0;
        int has_kd = aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS;
        if (has_kd) kd[0] = c.r, kd[1] = c.g, kd[2] = c.b;
        int has_ks = aiGetMaterialColor(am, AI_MATKEY_COLOR_SPECULAR, &c) == aiReturn_SUCCESS;
        if (has_ks) ks[0] = c.r, ks[1] = c.g, ks[2] = c.b;
        int has_ka = aiGetMaterialColor(am, AI_MATKEY_COLOR_AMBIENT, &c) == aiReturn_SUCCESS;
        if (has_ka) ka[0] = c.r, ka[1] = c.g, ka[2] = c.b;
        unsigned one = 1;
        if (aiGetMaterialFloatArray(am, AI_MATKEY_SHININESS, &shin, &one) != aiReturn_SUCCESS)
            shin = 0;
        persp__model_set_colours(&m, has_kd ? kd : NULL, has_ks ? ks : NULL, has_ka ? ka : NULL,
                                 shin);
        struct aiString file;
        enum aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
        enum aiTextureType types[2] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR};
        for (int t = 0; t < 2; t++) {
            if (aiGetMaterialTexture(am, types[t], 0, &file, NULL, NULL, NULL, NULL, modes, NULL) !=
                aiReturn_SUCCESS)
                continue;
            if (file.length == 0) break;
            m.texture = material_texture(im, name.data, file.data);
            if (m.texture >= 0) {
                m.env = PERSP_TEXENV_MODULATE;
                m.sampler.wrap_s = wrap_of(modes[0]);
                m.sampler.wrap_t = wrap_of(modes[1]);
            }
            break;
        }
    }
    return persp__scene_add_material(im->scene, &m, out);
}

static persp_status add_part(importer *im, int mesh, int material, const char *material_name,
                             const persp_mat4 *xf)
{
    return persp__model_add_part(im->scene, im->out, &im->part_cap, mesh, material, material_name, xf,
                                 im->display);
}

static persp_status walk(importer *im, const struct aiNode *node, persp_mat4 parent, int depth)
{
    if (depth > PERSP_MODEL_MAX_DEPTH)
        return persp__fail(im->ctx, PERSP_ERR_TOO_LARGE, "%s: node hierarchy deeper than %d",
                           im->display, PERSP_MODEL_MAX_DEPTH);
    persp_mat4 xf = persp_mat4_mul(parent, to_mat4(&node->mTransformation));
    persp_status st;
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        unsigned mi = node->mMeshes[i];
        if (mi >= im->ai->mNumMeshes) continue;
        if (im->mesh_index[mi] == -1 &&
            (st = convert_mesh(im, mi, &im->mesh_index[mi])) != PERSP_OK)
            return st;
        if (im->mesh_index[mi] < 0) continue;
        unsigned mat = im->ai->mMeshes[mi]->mMaterialIndex;
        int material;
        struct aiString name;
        name.length = 0, name.data[0] = '\0';
        if (mat < im->ai->mNumMaterials) {
            if (aiGetMaterialString(im->ai->mMaterials[mat], AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
                name.length = 0, name.data[0] = '\0';
            if (im->material_index[mat] == -1 &&
                (st = convert_material(im, mat, &im->material_index[mat])) != PERSP_OK)
                return st;
            material = im->material_index[mat];
        } else {
            persp_material d = persp__material_default();
            if ((st = persp__scene_add_material(im->scene, &d, &material)) != PERSP_OK) return st;
        }
        if ((st = add_part(im, im->mesh_index[mi], material, name.data, &xf)) != PERSP_OK) return st;
    }
    for (unsigned i = 0; i < node->mNumChildren; i++)
        if ((st = walk(im, node->mChildren[i], xf, depth + 1)) != PERSP_OK) return st;
    return PERSP_OK;
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
static persp_mat4 fbx_root(const struct aiScene *ai)
{
    persp_mat4 m = persp_mat4_identity();
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
        memset(m.m, 0, sizeof m.m);
        for (int k = 0; k < 3; k++) m.m[axis[k] * 4 + k] = (float)sign[k];
        m.m[15] = 1.0f;
    }
    double unit;
    if (meta_number(ai, "UnitScaleFactor", &unit) && isfinite(unit) && unit > 0.0 && unit != 100.0) {
        const float s = (float)(unit / 100.0);
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++) m.m[c * 4 + r] *= s;
    }
    return m;
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

static persp_status fill_slots(persp_context *ctx, int **slots, unsigned n)
{
    *slots = persp__calloc(ctx, n ? n : 1, sizeof **slots);
    if (!*slots) return PERSP_ERR_OUT_OF_MEMORY;
    for (unsigned i = 0; i < n; i++)
        (*slots)[i] = -1;
    return PERSP_OK;
}

/* ----------------------------------------------------------------- import */

/* What the post-processing steps need and do not check themselves: the
 * primitive types recomputed from the faces (some readers, PLY's among
 * them, get them wrong on malformed input, and Debian's Assimp aborts on
 * the internal check that catches it), finite positions, and something to
 * triangulate. Returns NULL or what is wrong. */
/* Some exporters write zero facet normals (Blender's old binary STL writer,
 * for one); drawn as they are, such a surface gets no diffuse light at all.
 * One unusable normal has the scene's normals made afresh. */
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
 * covers the polygon; "no area" is relative to the edges' lengths. */
static int face_has_area(const struct aiMesh *m, const struct aiFace *f)
{
    if (f->mNumIndices < 3) return 0;
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

static const char *prepare_scene(const struct aiScene *ai, int *regen_normals)
{
    int any = 0, area = 0;
    for (unsigned i = 0; i < ai->mNumMeshes; i++) {
        struct aiMesh *m = ai->mMeshes[i]; /* the scene is this import's own */
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
            types |= n == 0   ? 0u /* an empty face: nothing to draw */
                     : n == 1 ? aiPrimitiveType_POINT
                     : n == 2 ? aiPrimitiveType_LINE
                     : n == 3 ? aiPrimitiveType_TRIANGLE
                              : aiPrimitiveType_POLYGON;
        }
        m->mPrimitiveTypes = types;
        any |= (types & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)) != 0;
        if (!*regen_normals) *regen_normals = normals_unusable(m);
        for (unsigned v = 0; v < m->mNumVertices; v++)
            if (!persp__model_finite3(m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z))
                return "a vertex position is not finite";
        for (unsigned f = 0; f < m->mNumFaces && !area; f++)
            area = face_has_area(m, &m->mFaces[f]);
    }
    if (!any) return "the model has no triangles to draw";
    return area ? NULL : "the model's triangles all have zero area (nothing to draw)";
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
        persp_status ost =
            persp__obj_load(scene, buf, size, name, base_dir, cache, max_vertices, out);
        persp__free(ctx, buf);
        return ost;
    }
    /* Assimp picks the reader by the name's extension and then the content;
     * a name without a usable one still gets the content sniffed. */
    const char *main_name = persp__path_base(display);
    if (!main_name[0]) main_name = "model";
    if (is_line_text(main_name) || persp__model_has_ext(main_name, "gltf"))
        size = normalise_text(buf, size, is_line_text(main_name));

    persp_status cst = persp__model_check(ctx, display, buf, size);
    if (cst != PERSP_OK) {
        persp__free(ctx, buf);
        return cst;
    }
    model_io io;
    memset(&io, 0, sizeof io);
    io.ctx = ctx;
    io.display = display;
    io.main_name = main_name;
    io.data = buf;
    io.size = size;
    io.base_dir = base_dir;
    io.root = scene->load_root;
    /* glTF 2.0 §3.3.1: URIs are RFC 3986, so "%20" in a name is a space. */
    io.uri = persp__model_has_ext(main_name, "gltf") || persp__model_has_ext(main_name, "glb") ||
             (size >= 4 && !memcmp(buf, "glTF", 4));
    struct aiFileIO fio = {file_open, file_close, (aiUserData)(void *)&io};

    /* Assimp allocates with new/malloc and its C API has no allocator hook:
     * its need is reserved from the budget by the file's size. Importing a
     * 68.5 MB OBJ grid of a million triangles with these steps peaked at
     * 311 MB of process memory (docs/RELIABILITY.md), 4.5 bytes per byte of
     * the file. */
    size_t import_bytes = size > ((size_t)-1 - (1u << 20)) / MODEL_IMPORT_PER_BYTE
                              ? (size_t)-1
                              : size * MODEL_IMPORT_PER_BYTE + ((size_t)1 << 20);
    char what[PERSP_ERRMSG_BYTES / 2];
    snprintf(what, sizeof what, "%s: importing the model", display);
    if (persp__mem_reserve(ctx, import_bytes, what) != PERSP_OK) {
        persp__free(ctx, buf);
        return PERSP_ERR_OUT_OF_MEMORY;
    }
    struct aiPropertyStore *props = aiCreatePropertyStore();
    if (!props) {
        persp__mem_release(ctx, import_bytes);
        persp__free(ctx, buf);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", display);
    }
    aiSetImportPropertyFloat(props, AI_CONFIG_PP_GSN_MAX_SMOOTHING_ANGLE, PERSP_MODEL_CREASE_DEG);
    aiSetImportPropertyInteger(props, AI_CONFIG_PP_SBP_REMOVE,
                               aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    /* Read and validated first, then prepared (prepare_scene) for the
     * post-processing steps. A scene they would fail on is refused before
     * them: Assimp 5.2 crashes releasing a scene whose post-processing
     * failed. */
    /* GenUVCoords turns a texture projected by the file's mapping (sphere,
     * cylinder, box, plane: LightWave and others) into coordinates per
     * vertex; without it such a texture was drawn as one texel's colour.
     * TransformUVCoords is left out: Assimp 5.2 scales glTF's
     * KHR_texture_transform about the texture's centre, not its origin as
     * the extension says (a scale of 2 gave u in [-0.5, 1.5]). */
    unsigned steps = aiProcess_Triangulate | aiProcess_GenSmoothNormals | aiProcess_SortByPType |
                     aiProcess_GenUVCoords;
    int regen_normals = 0;
    char why[256] = "";
    const char *wrong = NULL;
    pthread_mutex_lock(&import_lock);
    const struct aiScene *ai =
        aiImportFileExWithProperties(main_name, aiProcess_ValidateDataStructure, &fio, props);
    if (ai && (wrong = prepare_scene(ai, &regen_normals)) != NULL) {
        aiReleaseImport(ai);
        ai = NULL;
    }
    if (regen_normals) steps |= aiProcess_ForceGenNormals;
    if (ai) ai = aiApplyPostProcessing(ai, steps);
    if (!ai && !wrong) snprintf(why, sizeof why, "%s", aiGetErrorString());
    pthread_mutex_unlock(&import_lock);
    aiReleasePropertyStore(props);
    int withhold = !ai && io.others && quotes_other(&io, why);
    /* Assimp takes a file that could not be opened for a missing or
     * unreadable one, so the reason is kept on this side. */
    if (io.out_of_memory) {
        if (ai) aiReleaseImport(ai);
        persp__free(ctx, buf);
        free_kept(&io);
        persp__mem_release(ctx, import_bytes);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", display);
    }
    if (wrong || !ai) {
        persp__free(ctx, buf);
        free_kept(&io);
        persp__mem_release(ctx, import_bytes);
    }
    if (wrong) return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: %s", display, wrong);
    if (!ai && io.nmissing)
        return persp__fail(ctx, PERSP_ERR_IO, "%s, which the model cannot be imported without",
                           io.notes[0]);
    for (int i = 0; ai && i < io.nmissing; i++)
        persp__warn(ctx, "%s; going on without it", io.notes[i]);
    if (!ai) {
        why[strcspn(why, "\r\n")] = '\0';
        /* Assimp's message may quote the text it choked on; once another
         * file (a material library, a buffer) has been read, that text may
         * be that file's, which is not the user's to see through a model
         * (a material library naming /etc/passwd, with any_folder on). */
        if (withhold)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: cannot import the model or a file it names (Assimp's "
                               "message withheld: it may quote that file)",
                               display);
        /* Assimp 5.2's words when no reader takes the file: a format it
         * does not read, not a malformed file of one it does. */
        if (!strncmp(why, "No suitable reader found", 24))
            return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                               "%s: not a model format persp reads (OBJ, or one Assimp reads: "
                               "glTF, PLY, STL, FBX, COLLADA, 3DS, ...)",
                               display);
        char q[PERSP_QUOTE_BYTES * 2];
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: cannot import the model: %s", display,
                           why[0] ? persp__quote(why, strlen(why), q, sizeof q)
                                  : "unknown format or malformed file");
    }

    importer im;
    memset(&im, 0, sizeof im);
    im.scene = scene;
    im.ctx = ctx;
    im.ai = ai;
    im.display = display;
    im.base_dir = base_dir;
    im.root = scene->load_root;
    im.io = &io;
    im.cache = cache;
    im.max_vertices = max_vertices ? max_vertices : PERSP_SCENE_MAX_VERTICES;
    im.out = out;
    im.refs.scene = scene;
    im.refs.cache = cache;
    im.refs.display = display;
    im.refs.base_dir = base_dir;
    im.refs.root = scene->load_root;
    im.refs.where = where_io;
    im.refs.where_user = &io;
    im.refs.uri = io.uri;
    for (int k = 0; k < 3; k++)
        out->bbox_min[k] = INFINITY, out->bbox_max[k] = -INFINITY;
    persp_status st = PERSP_OK;
    if (fill_slots(ctx, &im.mesh_index, ai->mNumMeshes) != PERSP_OK ||
        fill_slots(ctx, &im.material_index, ai->mNumMaterials) != PERSP_OK ||
        fill_slots(ctx, &im.embedded_index, ai->mNumTextures) != PERSP_OK)
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", display);
    im.stand_in = (persp__model_has_ext(main_name, "ply") || (size >= 4 && !memcmp(buf, "ply", 3) &&
                                                                (buf[3] == '\n' || buf[3] == '\r'))) &&
                  !ply_has_materials(buf, size);
    const persp_mat4 root = is_fbx(main_name, buf, size) ? fbx_root(ai) : persp_mat4_identity();
    if (st == PERSP_OK && ai->mRootNode) st = walk(&im, ai->mRootNode, root, 0);
    /* A texture refused for want of memory is not drawn untextured with a
     * warning, as a missing file is: the allocator's refusal is the caller's
     * to see (PERSP_ERR_OUT_OF_MEMORY). */
    if (st == PERSP_OK && im.out_of_memory) st = PERSP_ERR_OUT_OF_MEMORY; /* detail: model_texture_oom */
    if (st == PERSP_OK && out->part_count == 0)
        st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the model has no triangles to draw", display);
    if (st == PERSP_OK && !(out->bbox_min[0] <= out->bbox_max[0]))
        st = persp__fail(ctx, PERSP_ERR_FORMAT,
                         "%s: the model's transformed vertices are not finite", display);
    persp__free(ctx, im.mesh_index);
    persp__free(ctx, im.material_index);
    persp__free(ctx, im.embedded_index);
    persp__free(ctx, buf);
    free_kept(&io);
    aiReleaseImport(ai);
    persp__mem_release(ctx, import_bytes);
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

persp_status persp__scene_from_model(persp_context *ctx, char *data, size_t size, const char *name,
                                     const char *base_dir, const char *root, int up_z,
                                     persp_scene **out)
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
    st = data ? load_owned(s, data, size, name, base_dir, &cache, 0, &model)
              : persp__obj_load(s, NULL, 0, name, base_dir, &cache, 0, &model);
    s->load_root = NULL;
    persp__texcache_free(ctx, &cache);
    if (st == PERSP_OK) persp__model_warn_no_uv(s, &model, name ? name : "<model>", -1, PERSP_TEXGEN_UV);
    if (st == PERSP_OK && up_z) {
        /* −90° about x: +z becomes +y, +y becomes −z; the box turns with
         * it exactly (a quarter turn keeps it axis-aligned). */
        persp_mat4 turn = persp_mat4_identity(); /* exact: y' = z, z' = −y */
        turn.m[1 * 4 + 1] = 0.0f, turn.m[2 * 4 + 1] = 1.0f;
        turn.m[1 * 4 + 2] = -1.0f, turn.m[2 * 4 + 2] = 0.0f;
        for (size_t i = 0; i < model.part_count; i++)
            model.parts[i].transform = persp_mat4_mul(turn, model.parts[i].transform);
        const float ymin = model.bbox_min[1], ymax = model.bbox_max[1];
        model.bbox_min[1] = model.bbox_min[2], model.bbox_max[1] = model.bbox_max[2];
        model.bbox_min[2] = -ymax, model.bbox_max[2] = -ymin;
    }
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
