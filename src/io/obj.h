/*
 * Wavefront OBJ / MTL and JSON scene loaders (internal entry points). All
 * parse from memory; the file functions are thin wrappers. Errors go to the
 * context as "name:line:col: what was expected".
 */
#ifndef PERSP_IO_OBJ_H
#define PERSP_IO_OBJ_H

#include "geom/scene.h"

#define PERSP_MTL_NAME_MAX 128

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
persp_status persp__texcache_load(persp_scene *scene, persp_texcache *cache, const char *path, int *index);
void persp__texcache_free(persp_context *ctx, persp_texcache *cache);

/* Material names of the MTL files read so far -> scene material indices. */
typedef struct persp_mtl_entry {
    char name[PERSP_MTL_NAME_MAX];
    int material;
} persp_mtl_entry;

typedef struct persp_mtl_lib {
    persp_mtl_entry *entries;
    size_t count, cap;
} persp_mtl_lib;

/* Parses MTL text, appending one scene material per newmtl to scene and lib.
 * base_dir: folder that map_Kd paths are relative to; NULL opens no files
 * (texture statements are checked but not loaded). cache may be NULL. */
persp_status persp__mtl_load_memory(persp_scene *scene, const char *data, size_t size, const char *name,
                                    const char *base_dir, persp_mtl_lib *lib, persp_texcache *cache);
/* Index into lib->entries of the last material called name, or -1. */
int persp__mtl_find(const persp_mtl_lib *lib, const char *name, size_t len);
void persp__mtl_lib_free(persp_context *ctx, persp_mtl_lib *lib);

/* One mesh per material used by an OBJ file. */
typedef struct persp_obj_part {
    int mesh;     /* scene->meshes index */
    int material; /* scene->materials index */
} persp_obj_part;

typedef struct persp_obj_result {
    persp_obj_part *parts;
    size_t part_count;
} persp_obj_result;

/* Parses OBJ text into scene: appends its meshes (triangulated as fans,
 * normals computed where any corner lacks one) and the materials of its
 * mtllib files. Faces before any usemtl get a default material.
 * base_dir: folder for mtllib; NULL opens no files (mtllib is checked but
 * not read and usemtl names are then not resolved). cache may be NULL. */
persp_status persp__obj_load_memory(persp_scene *scene, const char *data, size_t size, const char *name,
                                    const char *base_dir, persp_texcache *cache, persp_obj_result *res);
persp_status persp__obj_load_file(persp_scene *scene, const char *path, persp_texcache *cache,
                                  persp_obj_result *res);
void persp__obj_result_free(persp_context *ctx, persp_obj_result *res);

/* JSON scene from memory. name appears in errors; base_dir resolves the
 * files the scene names; NULL: any file reference is refused. max_vertices
 * bounds the vertices of all meshes together (0: PERSP_SCENE_MAX_VERTICES),
 * so that a short file cannot ask for gigabytes of primitives. */
persp_status persp__scene_load_memory(persp_context *ctx, const char *data, size_t size, const char *name,
                                      const char *base_dir, size_t max_vertices, persp_scene **out);

#endif
