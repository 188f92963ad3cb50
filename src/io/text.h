/*
 * Small helpers shared by the loaders (scene JSON, models, images):
 * whole-file reading with a size limit and path joining.
 */
#ifndef PERSP_IO_TEXT_H
#define PERSP_IO_TEXT_H

#include "core/shared.h"
#include "persp.h"

#include <stddef.h>
#include <stdio.h>

/* Largest text file a loader reads (checked before allocating). */
#define PERSP_TEXT_MAX_BYTES ((size_t)512 * 1024 * 1024)
#define PERSP_PATH_MAX 4096

/* Reads a whole file into a NUL-terminated buffer owned by the caller
 * (persp__free). PERSP_ERR_IO / PERSP_ERR_TOO_LARGE with the path in the detail. */
PERSP_INTERNAL persp_status persp__read_file(persp_context *ctx, const char *path, char **data, size_t *size);

/* The folder part of path, "" for a bare name ("a/b.obj" -> "a/"). */
void persp__path_dir(const char *path, char *out, size_t size);
/* dir + rel unless rel is absolute; 0 if it does not fit. */
int persp__path_join(const char *dir, const char *rel, char *out, size_t size);
/* The folder a loaded file may read from: the real path (links and ".."
 * resolved) of path's folder. */
persp_status persp__path_root(persp_context *ctx, const char *path, char *out, size_t size);
/* 1 when the existing file path, resolved, lies in root or below (NULL
 * root: anywhere), 0 when it lies elsewhere, -1 when it cannot be resolved
 * (missing). A check of the name only: it words early messages, while what
 * is read must come from persp__open_inside, which checks the file opened. */
int persp__path_inside(const char *root, const char *path);

/* persp__open_inside's answer for a file refused as outside root. */
#define PERSP_OPEN_OUTSIDE (-2)
/* persp__open_inside's answer for a FIFO, device, socket or folder. */
#define PERSP_OPEN_NOT_REGULAR (-3)
/* Opens path read-only and keeps it only when it is a regular file and
 * the file opened is the one path resolves to (realpath) and that lies in
 * root or below; NULL root: any file. The descriptor (caller closes), -1
 * when the open fails (errno says why), PERSP_OPEN_NOT_REGULAR for
 * anything but a regular file, PERSP_OPEN_OUTSIDE when the file lies
 * elsewhere or path no longer names the file opened (a link swapped after
 * the open). */
int persp__open_inside(const char *root, const char *path);
/* Why path is not a regular file, for a message: "a directory", "a FIFO
 * (named pipe)", "a device", "a socket" or "not a regular file". */
const char *persp__not_regular_what(const char *path);
/* "a FIFO (named pipe), not a regular file" and the like for a path that
 * exists and is not a regular file; NULL otherwise. */
const char *persp__not_regular_why(const char *path);
/* The check of persp__open_inside on an open descriptor: 1 when fd is the
 * file that path resolves to and that lies in root or below (NULL root:
 * anywhere), 0 otherwise, -1 when fd or path cannot be examined. */
int persp__fd_inside(int fd, const char *root, const char *path);
/* persp__read_file through persp__open_inside: PERSP_ERR_IO, saying so,
 * for a file refused as outside root. */
persp_status persp__read_file_inside(persp_context *ctx, const char *root, const char *path,
                                     char **data, size_t *size);
/* Opens path through persp__open_inside for a reader that streams it (read
 * more than once): *out positioned at the start, *size its length; a folder
 * or a stream that cannot seek is refused. The caller closes *out. */
persp_status persp__open_stream_inside(persp_context *ctx, const char *root, const char *path,
                                       FILE **out, size_t *size);
/* persp_image_load of a file read through persp__read_file_inside. */
persp_status persp__image_load_inside(persp_context *ctx, const char *root, const char *path,
                                      persp_image *out);
/* The last path component, for short error prefixes. */
const char *persp__path_base(const char *path);

#endif
