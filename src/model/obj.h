/*
 * persp's own Wavefront OBJ + MTL reader (src/model/obj.c), used for every OBJ
 * model in place of Assimp's (docs/SCENES.md, "Models").
 */
#ifndef PERSP_IO_OBJ_H
#define PERSP_IO_OBJ_H

#include "model/model.h"

/* Reads an OBJ model into scene, with the contract of
 * persp__model_load_memory: from data (size bytes, the caller's, read in
 * place) or, when data is NULL, streamed from the file name in chunks, so
 * that the file's text is never held whole. */
persp_status persp__obj_load(persp_scene *scene, const char *data, size_t size, const char *name,
                             const char *base_dir, persp_texcache *cache, size_t max_vertices,
                             persp_model *out);

#endif
