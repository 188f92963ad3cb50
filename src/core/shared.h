/*
 * PERSP_INTERNAL marks the internal functions that libpersp_analysis.so
 * calls in libpersp.so: the library exports them beside the public API,
 * under the persp__ prefix that says they are no part of it (no promise of
 * a stable interface; declared in src/ only, never installed). Everything
 * else not marked PERSP_API stays hidden. The analysis library thus links
 * against libpersp.so instead of carrying a copy of the core, so a process
 * using both has one copy of its state (the import lock, the allocator
 * paths). tests/package/test_install.sh checks that exactly what the
 * analysis library needs is exported.
 */
#ifndef PERSP_CORE_SHARED_H
#define PERSP_CORE_SHARED_H

#if defined(__GNUC__) || defined(__clang__)
#define PERSP_INTERNAL __attribute__((visibility("default")))
#else
#define PERSP_INTERNAL
#endif

#endif
