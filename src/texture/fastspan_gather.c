/*
 * The AVX2 and AVX-512 span samplers of fastspan.c compiled with GCC's
 * -mtune-ctrl=use_gather (CMakeLists.txt), so that the vectoriser fetches
 * texels with vpgatherdd instead of building each vector from scalar loads
 * and inserts. Which is faster depends on the core: the inserts all go to
 * one port on Intel's AVX-512 cores, while gathers are microcoded and slow
 * on AMD's Zen and on Intel cores with the 2023 "Downfall" (GDS)
 * mitigation (docs/PERFORMANCE.md, "On an Intel Xeon: samplers with
 * gathers, 16 threads"). Same
 * operations on the same texels, so the same bits as every other variant.
 */
#include "texture/fastspan_body.h"

#if PERSP_HAVE_ISA_VARIANTS
FAST_VARIANT(, persp__fast_avx2g, avx2g, PERSP_TARGET_AVX2, 0)
FAST_VARIANT(, persp__fast_avx512g, avx512g, PERSP_TARGET_AVX512, 0)
#else
/* ISO C forbids an empty translation unit. */
typedef int persp__fastspan_gather_unused;
#endif
