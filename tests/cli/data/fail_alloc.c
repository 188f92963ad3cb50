/* LD_PRELOAD shim for tests: malloc, calloc and realloc return NULL when
 * called directly from a shared object whose path contains the text in
 * PERSP_FAIL_ALLOC_IN (e.g. "libjpeg"), so that a test sees how persp
 * reports a decoder's own allocation failure. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

static int from_target(void *caller)
{
    const char *want = getenv("PERSP_FAIL_ALLOC_IN");
    Dl_info info;
    return want && want[0] && dladdr(caller, &info) && info.dli_fname &&
           strstr(info.dli_fname, want);
}

extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);

void *malloc(size_t n)
{
    if (from_target(__builtin_return_address(0))) return NULL;
    return __libc_malloc(n);
}

void *calloc(size_t n, size_t s)
{
    if (from_target(__builtin_return_address(0))) return NULL;
    return __libc_calloc(n, s);
}

void *realloc(void *p, size_t n)
{
    if (from_target(__builtin_return_address(0))) return NULL;
    return __libc_realloc(p, n);
}
