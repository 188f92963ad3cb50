/*
 * Model import (Assimp) and the JSON scene loader (internal entry points).
 * Errors go to the context as one line naming the file; problems that are
 * worked around (a missing material library or texture) go to the
 * context's warning handler.
 */
#ifndef PERSP_IO_MODEL_H
#define PERSP_IO_MODEL_H

#include "geom/scene.h"

/* Textures loaded by one scene load, so a file used twice is decoded once. */
typedef struct persp_texcache_entry {
    char *path;
    int index; /* into scene->textures */
} persp_texcache_entry;

typedef struct persp_texcache {
    persp_texcache_entry *entries;
    size_t count, cap;
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
} persp_model;

/* Imports a model from memory into scene: appends its meshes, materials and
 * textures and lists the instances in *out. name (its extension picks the
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

/* 1 when path names a model rather than a JSON scene: an extension Assimp
 * reads other than .json, or (data given) content that is not a JSON
 * object. */
int persp__model_is_model(const char *path, const char *data, size_t size);

/* A scene showing a model: the default camera and light rig
 * (docs/SCENES.md, "Models without a scene file"). Takes data, a buffer
 * from persp__read_file (NUL-terminated, size + 1 bytes), and frees it.
 * root: the folder the model's references must stay in, NULL: anywhere. */
persp_status persp__scene_from_model(persp_context *ctx, char *data, size_t size, const char *name,
                                     const char *base_dir, const char *root, persp_scene **out);

/* JSON scene from memory. name appears in errors; base_dir resolves the
 * files the scene names; NULL: any file reference is refused. max_vertices
 * bounds the vertices of all meshes together (0: PERSP_SCENE_MAX_VERTICES),
 * so that a short file cannot ask for gigabytes of primitives. */
persp_status persp__scene_load_memory(persp_context *ctx, const char *data, size_t size,
                                      const char *name, const char *base_dir, size_t max_vertices,
                                      persp_scene **out);

#endif
