/*
 * Small helpers shared by the loaders (scene JSON, models, images):
 * whole-file reading with a size limit and path joining.
 */
#ifndef PERSP_IO_TEXT_H
#define PERSP_IO_TEXT_H

#include "persp.h"

#include <stddef.h>

/* Largest text file a loader reads (checked before allocating). */
#define PERSP_TEXT_MAX_BYTES ((size_t)512 * 1024 * 1024)
#define PERSP_PATH_MAX 4096

/* Reads a whole file into a NUL-terminated buffer owned by the caller
 * (persp__free). PERSP_ERR_IO / PERSP_ERR_TOO_LARGE with the path in the detail. */
persp_status persp__read_file(persp_context *ctx, const char *path, char **data, size_t *size);

/* The folder part of path, "" for a bare name ("a/b.obj" -> "a/"). */
void persp__path_dir(const char *path, char *out, size_t size);
/* dir + rel unless rel is absolute; 0 if it does not fit. */
int persp__path_join(const char *dir, const char *rel, char *out, size_t size);
/* The last path component, for short error prefixes. */
const char *persp__path_base(const char *path);

#endif
