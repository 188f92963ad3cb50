/*
 * Model import (persp's OBJ reader, Assimp for the rest) and the JSON scene
 * loader (internal entry points).
 * Errors go to the context as one line naming the file; problems that are
 * worked around (a missing material library or texture) go to the
 * context's warning handler.
 */
#ifndef PERSP_IO_MODEL_H
#define PERSP_IO_MODEL_H

#include "geom/scene.h"

#include <math.h>

/* Textures loaded by one scene load, so a file used twice is decoded once. */
typedef struct persp_texcache_entry {
    char *path;
    int index; /* into scene->textures */
} persp_texcache_entry;

typedef struct persp_texcache {
    persp_texcache_entry *entries;
    size_t count, cap;
    size_t case_misses; /* textures looked for in any case and not found (model_refs.c) */
} persp_texcache;

/* Loads an image file as a scene texture (or finds it in the cache). */
persp_status persp__texcache_load(persp_scene *scene, persp_texcache *cache, const char *path,
                                  int *index);
void persp__texcache_free(persp_context *ctx, persp_texcache *cache);

/* Deepest node hierarchy walked. */
#define PERSP_MODEL_MAX_DEPTH 256

/* One drawable instance: a mesh of the scene, its material and the product
 * of the node transforms above it. */
typedef struct persp_model_part {
    int mesh, material;
    persp_mat4 transform;
} persp_model_part;

typedef struct persp_model {
    persp_model_part *parts;
    size_t part_count;
    float bbox_min[3], bbox_max[3]; /* of the transformed parts */
    /* Parts whose textured material meets a mesh without texture
     * coordinates, and the first such material's name (persp__model_warn_no_uv). */
    size_t no_uv_parts;
    char no_uv_material[64];
} persp_model;

/* Imports a model from memory into scene: appends its meshes, materials and
 * textures and lists the instances in *out. scene->load_desc says how
 * (persp_model_import, persp_model_formats; NULL: the defaults). name (its extension picks the
 * format when the content does not) appears in messages; base_dir resolves
 * the files the model refers to (material libraries, textures, buffers);
 * NULL: none are opened. Files outside scene->load_root (when set) are
 * refused with a warning. max_vertices bounds the vertices added (0:
 * PERSP_SCENE_MAX_VERTICES). Free *out with persp__model_free. */
persp_status persp__model_load_memory(persp_scene *scene, const void *data, size_t size,
                                      const char *name, const char *base_dir, persp_texcache *cache,
                                      size_t max_vertices, persp_model *out);
persp_status persp__model_load_file(persp_scene *scene, const char *path, persp_texcache *cache,
                                    size_t max_vertices, persp_model *out);
void persp__model_free(persp_context *ctx, persp_model *model);

/* 1 when a model file is streamed rather than read whole (OBJ, by the
 * name): persp__scene_from_model then takes no data. */
int persp__model_streams(const char *path);
/* The model format the first bytes of a file show ("binary glTF", "PLY",
 * ...; *ext its extension), or NULL: for a message when a file named for
 * one format holds another. */
const char *persp__model_content_format(const char *data, size_t size, const char **ext);
/* "a" or "an" before a format's name as it is spoken ("an STL", "a PLY"). */
const char *persp__model_article(const char *format);

/* 1 when path names a model rather than a JSON scene: an extension Assimp
 * reads other than .json, or (data given) content that is not a JSON
 * object. */
int persp__model_is_model(const char *path, const char *data, size_t size);

/* A scene showing a model: the default camera and light rig
 * (docs/SCENES.md, "Models without a scene file"). Takes data, a buffer
 * from persp__read_file (NUL-terminated, size + 1 bytes), and frees it;
 * data NULL: name is an OBJ file to stream (persp__model_streams).
 * root: the folder the model's references must stay in, NULL: anywhere.
 * desc (NULL: defaults): the model's up axis and how it is imported. */
persp_status persp__scene_from_model(persp_context *ctx, char *data, size_t size, const char *name,
                                     const char *base_dir, const char *root,
                                     const persp_scene_load_desc *desc, persp_scene **out);

/* JSON scene from memory. name appears in errors; base_dir resolves the
 * files the scene names; NULL: any file reference is refused. max_vertices
 * bounds the vertices of all meshes together (0: PERSP_SCENE_MAX_VERTICES),
 * so that a short file cannot ask for gigabytes of primitives. */
persp_status persp__scene_load_memory(persp_context *ctx, const char *data, size_t size,
                                      const char *name, const char *base_dir, size_t max_vertices,
                                      persp_scene **out);

/* --------------------- shared by model.c and obj.c (src/model/model_refs.c) */

static inline int persp__model_finite3(float x, float y, float z)
{
    return isfinite(x) && isfinite(y) && isfinite(z);
}

/* Faces meeting at more than this angle keep separate normals where the
 * file has none: cube edges stay sharp, tessellated curves come out smooth
 * (persp_scene_load_desc.crease_deg, --crease). */
#define PERSP_MODEL_CREASE_DEG 80.0f

/* The crease angle a load uses (desc NULL or crease_deg 0: the default). */
static inline float persp__model_crease(const persp_scene_load_desc *desc)
{
    return desc && desc->crease_deg > 0.0f ? desc->crease_deg : PERSP_MODEL_CREASE_DEG;
}

/* 1 when name ends in "." ext, in any case (ext in lower case). */
int persp__model_has_ext(const char *name, const char *ext);
/* A URI's percent-encoding decoded ("%20" a space; RFC 3986 §2.1) into out:
 * 1 when something was decoded, 0 when nothing was or the result would be
 * cut or hold a NUL (out then unusable). */
int persp__uri_decode(const char *in, char *out, size_t size);
/* Windows separators, "./" prefixes and Blender's "//" (relative to the
 * .blend file) of a name a model gives. */
void persp__model_clean_rel(const char *in, char *out, size_t size);
/* Reads a file a model names (rel, cleaned): relative to base_dir, then its
 * last part next to the model, then both in any case, each only inside root
 * (NULL: anywhere). On failure other than PERSP_ERR_OUT_OF_MEMORY, *why
 * says why for a warning. */
persp_status persp__model_read_ref(persp_context *ctx, const char *base_dir, const char *root,
                                   const char *rel, char **data, size_t *size, const char **why);

/* What a model's texture files are resolved with. */
typedef struct persp_model_refs {
    persp_scene *scene;
    persp_texcache *cache;
    const char *display, *base_dir, *root;
    /* Writes where the user finds the name rel ("a.obj (via b.mtl:3)");
     * NULL: the model's name. */
    void (*where)(const void *user, const char *rel, char *out, size_t cap);
    const void *where_user;
    int out_of_memory; /* set when a texture was refused for want of memory */
    int uri;           /* names are URIs (glTF): decoded first (persp__uri_decode) */
    int quiet;         /* no warning when the texture cannot be loaded */
} persp_model_refs;

/* Fails ctx with PERSP_ERR_OUT_OF_MEMORY: its detail (what the budget
 * refused) prefixed with the model, texture and material. */
void persp__model_texture_oom(persp_context *ctx, const char *display, const char *texture,
                              const char *material);
/* The scene texture of a texture file a material names, or -1 after a
 * warning (the material is drawn untextured). */
int persp__model_texture_file(persp_model_refs *refs, const char *material, const char *file);
/* A model material's colours onto m (persp__material_default): each given
 * (non-NULL) finite colour, ambient only when not black, shininess when
 * positive (at most 1000), all clamped to [0, 1000]. */
void persp__model_set_colours(persp_material *m, const float *kd, const float *ks,
                              const float *ka, float shininess);
/* The emissive colour ke (NULL: none) onto m, each channel clamped to
 * [0, 1]; 1 when m glows (a channel above 0): its emissive map is then
 * worth reading. */
int persp__model_set_emission(persp_material *m, const float *ke);
/* A glowing m's emissive map (scene texture glow, -1: none). Emission is
 * added before the texel modulates (persp_material.emission), so the map
 * is exact as the base colour texture itself (a label drawn in both) or,
 * with no base colour texture, as the texture (exact for a black base
 * colour: ambient and diffuse then add nothing); another image beside a
 * base colour texture is drawn through that texture, with a warning. */
void persp__model_set_glow_map(persp_context *ctx, const char *display, const char *material, persp_material *m,
                               int glow, persp_wrap wrap_s, persp_wrap wrap_t);
/* Appends a part and grows out's bounding box by its transformed vertices;
 * material_name: the material's name in the file, for messages. */
persp_status persp__model_add_part(persp_scene *scene, persp_model *out, size_t *cap, int mesh,
                                   int material, const char *material_name, const persp_mat4 *xf,
                                   const char *display);
/* Warns once where the model's meshes lack the texture coordinates a
 * texture would be read through, as exporters write a mesh whose UV layer
 * was removed: persp__object_texture draws those parts untextured.
 * material: the scene's material replacing the model's own, -1: none;
 * texgen: the objects' (coordinates generated: nothing to say). */
void persp__model_warn_no_uv(const persp_scene *scene, const persp_model *model, const char *display,
                             int material, int texgen);
/* 1 when the triangle spans an area, relative to its edges' lengths. */
int persp__model_triangle_has_area(const float *a, const float *b, const float *c);

/* The checks a model file must pass before Assimp reads it
 * (src/model/model_check.c): PERSP_ERR_FORMAT or PERSP_ERR_TOO_LARGE with the
 * detail set, or PERSP_OK (possibly after a warning). buf: the file's
 * bytes, text normalised; display: its name in messages. */
persp_status persp__model_check(persp_context *ctx, const char *display, const char *buf,
                                size_t size);

#endif
