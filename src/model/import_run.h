/* Starting and ending the model importer (src/model/import_run.c). */
#ifndef PERSP_IO_IMPORT_RUN_H
#define PERSP_IO_IMPORT_RUN_H

#include "persp.h"

#include <pthread.h>
#include <stddef.h>
#include <sys/types.h>

typedef struct persp_importer_opts {
    int in_process;          /* a thread of this process instead of persp-import */
    const char *helper;      /* persp-import's path (persp__import_helper_path) */
    size_t memory;           /* bytes the helper may use besides its own code */
    unsigned time_limit_ms;  /* CPU time of the helper (wall clock: the caller's deadline) */
    int time_scales;         /* the default limit, grown with the bytes handed over */
} persp_importer_opts;

typedef struct persp_importer {
    int fd; /* persp's end of the socket */
    pid_t pid;
    pthread_t thread;
    int has_thread, thread_fd;
} persp_importer;

/* How the helper ended (known 0: in-process, or it could not be waited for). */
typedef struct persp_importer_end {
    int known;
    int signal;        /* the signal that ended it, 0 if none */
    int exit_code;
    size_t peak_bytes; /* its peak resident memory */
} persp_importer_end;

/* The helper's exit codes besides 0. */
#define PERSP_IMPORT_EXIT_USAGE 2
#define PERSP_IMPORT_EXIT_OUT_OF_MEMORY 3
#define PERSP_IMPORT_EXIT_LIMITS 4 /* its limits could not be set */

/* Finds persp-import: given (when not NULL), else beside this library or
 * program, then in ../libexec/persp/ and ../../libexec/persp/ from there.
 * 1 when out names a program that can run. */
int persp__import_helper_path(const char *given, char *out, size_t cap);

persp_status persp__importer_start(persp_context *ctx, const persp_importer_opts *o, const char *display,
                                   persp_importer *imp);
/* Closes persp's end, waits for the helper or thread (stop: kills the
 * helper first) and says how the helper ended. */
void persp__importer_finish(persp_importer *imp, int stop, persp_importer_end *end);

#endif
