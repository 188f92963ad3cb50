/*
 * The AVX2 and AVX-512 span samplers of fastspan.c compiled with GCC's
 * -mtune-ctrl=use_gather (CMakeLists.txt), so that the vectoriser fetches
 * texels with vpgatherdd instead of building each vector from scalar loads
 * and inserts. Which is faster depends on the core: the inserts all go to
 * one port on Intel's AVX-512 cores, while gathers are microcoded and slow
 * on AMD's Zen and on Intel cores with the 2023 "Downfall" (GDS)
 * mitigation (docs/PERFORMANCE.md, "Samplers on Intel and AMD"). Same
 * operations on the same texels, so the same bits as every other variant.
 */
#include "texture/fastspan_body.h"

#if PERSP_HAVE_ISA_VARIANTS
FAST4_EXPORT(nearest_avx2g, PERSP_TARGET_AVX2, span_nearest)
FAST4_EXPORT(bilinear_avx2g, PERSP_TARGET_AVX2, span_bilinear)
FAST4_EXPORT(nmn_avx2g, PERSP_TARGET_AVX2, span_nmn)
FAST4_EXPORT(bmn_avx2g, PERSP_TARGET_AVX2, span_bmn)
FAST4_EXPORT(nml_avx2g, PERSP_TARGET_AVX2, span_nml)
FAST4_EXPORT(trilinear_avx2g, PERSP_TARGET_AVX2, span_trilinear)
FAST4_EXPORT(aniso_avx2g, PERSP_TARGET_AVX2, span_aniso)
FAST4_EXPORT(nearest_avx512g, PERSP_TARGET_AVX512, span_nearest)
FAST4_EXPORT(bilinear_avx512g, PERSP_TARGET_AVX512, span_bilinear)
FAST4_EXPORT(nmn_avx512g, PERSP_TARGET_AVX512, span_nmn)
FAST4_EXPORT(bmn_avx512g, PERSP_TARGET_AVX512, span_bmn)
FAST4_EXPORT(nml_avx512g, PERSP_TARGET_AVX512, span_nml)
FAST4_EXPORT(trilinear_avx512g, PERSP_TARGET_AVX512, span_trilinear)
FAST4_EXPORT(aniso_avx512g, PERSP_TARGET_AVX512, span_aniso)
#else
/* ISO C forbids an empty translation unit. */
typedef int persp__fastspan_gather_unused;
#endif
