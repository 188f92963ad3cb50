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
/* The folder a loaded file may read from: the real path (links and ".."
 * resolved) of path's folder. */
persp_status persp__path_root(persp_context *ctx, const char *path, char *out, size_t size);
/* 1 when the existing file path, resolved, lies in root or below (NULL
 * root: anywhere), 0 when it lies elsewhere, -1 when it cannot be resolved
 * (missing), in which case opening it fails on its own. The check and the
 * later open are two steps: a link swapped in between is not caught. */
int persp__path_inside(const char *root, const char *path);
/* The last path component, for short error prefixes. */
const char *persp__path_base(const char *path);

#endif
