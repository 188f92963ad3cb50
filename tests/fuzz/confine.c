/* File access of the fuzz harnesses. persp's loaders follow the file names
 * a scene or model gives (textures, models, material libraries, buffers);
 * a fuzzed input names any path, so the harnesses are linked with
 * -Wl,--wrap=fopen,--wrap=open,--wrap=openat,--wrap=opendir (GNU ld's and
 * lld's --wrap: undefined references to SYM resolve to __wrap_SYM, and
 * __real_SYM to the original) and, while confinement is on, only paths
 * inside PERSP_FUZZ_FILES (tests/fuzz/files/) without a ".." component are
 * opened for reading. Anything else fails with EACCES, as an unreadable
 * file would. Opening for writing is left alone: persp's loaders never
 * write, and libFuzzer, linked into the same program, writes its crash
 * reproducer from inside the input that crashed. */
#include "confine.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/types.h>

FILE *__real_fopen(const char *path, const char *mode);
FILE *__wrap_fopen(const char *path, const char *mode);
int __real_open(const char *path, int flags, ...);
int __wrap_open(const char *path, int flags, ...);
int __real_openat(int dirfd, const char *path, int flags, ...);
int __wrap_openat(int dirfd, const char *path, int flags, ...);
DIR *__real_opendir(const char *path);
DIR *__wrap_opendir(const char *path);

/* The harness process is single-threaded; the flag is set only around one
 * input so that the fuzzer's own files (corpus, artefacts) stay reachable. */
static int confined;

void fuzz_confine(int on)
{
    confined = on;
}

/* The comparisons are spelled out rather than left to strncmp: libFuzzer
 * watches the arguments of the string functions and would copy this
 * folder's absolute path, which names the machine, into the corpus. */
static int allowed(const char *path)
{
    if (!confined) return 1;
    if (!path) return 0;
    static const char dir[] = PERSP_FUZZ_FILES;
    size_t n = 0;
    while (dir[n] && path[n] == dir[n])
        n++;
    if (dir[n] || (path[n] != '/' && path[n] != '\0')) return 0;
    for (const char *p = path + n; *p;) {
        while (*p == '/')
            p++;
        size_t len = 0;
        while (p[len] && p[len] != '/')
            len++;
        if (len == 2 && p[0] == '.' && p[1] == '.') return 0;
        p += len;
    }
    return 1;
}

FILE *__wrap_fopen(const char *path, const char *mode)
{
    if (mode && mode[0] == 'r' && !strchr(mode, '+') && !allowed(path)) {
        errno = EACCES;
        return NULL;
    }
    return __real_fopen(path, mode);
}

int __wrap_open(const char *path, int flags, ...)
{
    mode_t mode = 0;
    if (flags & O_CREAT) {
        va_list ap;
        va_start(ap, flags);
        mode = (mode_t)va_arg(ap, int);
        va_end(ap);
    }
    if ((flags & O_ACCMODE) == O_RDONLY && !allowed(path)) {
        errno = EACCES;
        return -1;
    }
    return __real_open(path, flags, mode);
}

int __wrap_openat(int dirfd, const char *path, int flags, ...)
{
    mode_t mode = 0;
    if (flags & O_CREAT) {
        va_list ap;
        va_start(ap, flags);
        mode = (mode_t)va_arg(ap, int);
        va_end(ap);
    }
    /* Relative to a folder descriptor the path alone says nothing: refused. */
    if (confined && (flags & O_ACCMODE) == O_RDONLY && (!path || path[0] != '/' || !allowed(path))) {
        errno = EACCES;
        return -1;
    }
    return __real_openat(dirfd, path, flags, mode);
}

DIR *__wrap_opendir(const char *path)
{
    if (!allowed(path)) {
        errno = EACCES;
        return NULL;
    }
    return __real_opendir(path);
}
