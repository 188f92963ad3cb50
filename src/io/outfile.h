/*
 * Output files written safely (persp_image_write, the analysis reports).
 *
 * A regular file, or a path that names nothing yet, is written through a
 * temporary file in the same folder and renamed over the target only once
 * everything was written, flushed and closed: a reader never sees half a
 * file and a failure leaves the old file (or none). Through a symbolic link
 * the file it points to is replaced and the link stays a link. Anything
 * else that exists (a device such as /dev/null, a FIFO) is written in place,
 * since renaming over it would replace the device node itself.
 */
#ifndef PERSP_IO_OUTFILE_H
#define PERSP_IO_OUTFILE_H

#include "core/shared.h"

#include "persp.h"

#include <stdio.h>

typedef struct persp_outfile {
    FILE *f;
    const char *path; /* as given, for messages */
    char *tmp;        /* the temporary file; NULL when written in place */
    char *target;     /* what tmp is renamed to (the link's target, or path) */
} persp_outfile;

/* Opens path for writing (binary). Refuses a folder, a read-only file and a
 * link to nothing, with the path in the detail. The context's temp-file
 * handler (persp_context_set_temp_file_handler) hears of the temporary file. */
PERSP_INTERNAL persp_status persp__outfile_open(persp_context *ctx, const char *path,
                                                persp_outfile *out);
/* Flushes and closes; with st PERSP_OK renames the temporary file over the
 * target, else (or when that fails) removes it. Returns st or the first
 * failure of its own. */
PERSP_INTERNAL persp_status persp__outfile_close(persp_context *ctx, persp_outfile *out,
                                                 persp_status st);

#endif
