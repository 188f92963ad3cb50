/*
 * Small float functions written so that GCC vectorises the loops that call
 * them, and so that the scalar and the vectorised span code give identical
 * bits (both call these, never libm, for the values they must agree on).
 */
#ifndef PERSP_CORE_FMATH_H
#define PERSP_CORE_FMATH_H

#include <stdint.h>
#include <string.h>

/* Vectorised variants of the hottest span loops: an AVX2 clone picked at
 * load time by the dynamic loader on CPUs that have it (GCC function
 * multi-versioning), the baseline x86-64 code elsewhere. Only floating-point
 * operations that are exactly rounded in IEEE 754 are used in such loops and
 * -ffp-contract=off forbids fused multiply-adds, so every clone computes the
 * same bits. Not under ThreadSanitizer: the clones' resolver runs while
 * the dynamic loader relocates the program, before the TSan runtime has
 * started, and GCC instruments it, so the program crashes on load
 * (google/sanitizers issue 342; llvm-project pull request 167516 exempts
 * such resolvers in clang). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__gnu_linux__) &&  \
    !defined(__SANITIZE_THREAD__)
#define PERSP_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define PERSP_SIMD_CLONES
#endif

/* Explicit instruction-set variants of a function, for code whose variants
 * must be selectable (and therefore testable) one by one: the baseline
 * variant is compiled as usual, the others with these attributes, and the
 * caller picks with persp__cpu_isa(). AVX-512 code uses 512-bit vectors
 * (GCC prefers 256 by default). */
enum {
    PERSP_ISA_BASE = 0,
    PERSP_ISA_AVX2 = 1,
    PERSP_ISA_AVX512 = 2,
    /* The same compiled with the vectoriser's gathers enabled
     * (fastspan_gather.c): same instruction set, so the CPU checks are
     * those of the variant without. */
    PERSP_ISA_AVX2_GATHER = 3,
    PERSP_ISA_AVX512_GATHER = 4,
    PERSP_ISA_COUNT = 5
};
#if defined(__GNUC__) && defined(__x86_64__)
#define PERSP_HAVE_ISA_VARIANTS 1
#define PERSP_TARGET_AVX2 __attribute__((target("avx2")))
#if defined(__clang__)
#define PERSP_TARGET_AVX512                                                                        \
    __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq"), min_vector_width(512)))
#else
#define PERSP_TARGET_AVX512                                                                        \
    __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq,prefer-vector-width=512")))
#endif
static inline int persp__cpu_isa(void)
{
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq"))
        return PERSP_ISA_AVX512;
    return __builtin_cpu_supports("avx2") ? PERSP_ISA_AVX2 : PERSP_ISA_BASE;
}
#else
#define PERSP_HAVE_ISA_VARIANTS 0
static inline int persp__cpu_isa(void) { return PERSP_ISA_BASE; }
#endif

/* Variants of a loop that the vector width decides (lighting, the vertex
 * stage), selectable at run time: NAME##_body, a static always-inline
 * function without a target, is compiled into a baseline, an AVX2 and an
 * AVX-512 function, and NAME(isa, ...) calls the one of PERSP_ISA_*
 * variant isa (a gather variant: its instruction set's). Unlike
 * PERSP_SIMD_CLONES, which the dynamic loader resolves for the CPU, this
 * follows the context's persp_context_desc.simd, so that `--simd avx2` runs
 * 256-bit lighting on an AVX-512 CPU (where 512-bit arithmetic may lower
 * the clock). params: the parenthesised parameter list; args: the
 * parenthesised arguments that name them. Every variant computes the same
 * bits (exactly rounded operations, no contraction). */
#define PERSP_ALWAYS_INLINE inline __attribute__((always_inline))
#define PERSP_UNPAREN(...) __VA_ARGS__
#if PERSP_HAVE_ISA_VARIANTS
/* Never inlined into their callers, and AVX-512 as plain avx512f, as the
 * target clones they replace were: inlined, or with PERSP_TARGET_AVX512's
 * extensions, the Phong loops took about 1 % more CPU on the 2M-triangle
 * torus (AMD Zen 5). */
#define PERSP_ISA_VARIANTS(name, params, args)                                                     \
    static __attribute__((noinline)) void name##_base params { name##_body args; }                 \
    PERSP_TARGET_AVX2 static __attribute__((noinline)) void name##_avx2 params                     \
    {                                                                                              \
        name##_body args;                                                                          \
    }                                                                                              \
    __attribute__((target("avx512f"), noinline)) static void name##_avx512 params                  \
    {                                                                                              \
        name##_body args;                                                                          \
    }                                                                                              \
    static inline void name(int isa, PERSP_UNPAREN params)                                         \
    {                                                                                              \
        if (isa == PERSP_ISA_AVX512 || isa == PERSP_ISA_AVX512_GATHER)                             \
            name##_avx512 args;                                                                    \
        else if (isa == PERSP_ISA_AVX2 || isa == PERSP_ISA_AVX2_GATHER)                            \
            name##_avx2 args;                                                                      \
        else                                                                                       \
            name##_base args;                                                                      \
    }
#else
#define PERSP_ISA_VARIANTS(name, params, args)                                                     \
    static inline void name(int isa, PERSP_UNPAREN params)                                         \
    {                                                                                              \
        (void)isa;                                                                                 \
        name##_body args;                                                                          \
    }
#endif

/* Whether this build and CPU can run variant isa. */
static inline int persp__isa_runs(int isa)
{
    const int need = isa == PERSP_ISA_AVX2_GATHER     ? PERSP_ISA_AVX2
                     : isa == PERSP_ISA_AVX512_GATHER ? PERSP_ISA_AVX512
                                                      : isa;
    return isa >= PERSP_ISA_BASE && isa < PERSP_ISA_COUNT && need <= persp__cpu_isa();
}

/* log2(x) for normal positive x with an absolute error below 1e-6: x =
 * m·2^e, m in [1, 2), log2 x = e + p(m - 1), p the degree-7 polynomial
 * interpolating log2(1 + t) at the Chebyshev-Lobatto points of [0, 1]
 * (p(0) = 0 and p(1) = 1, so exact powers of two give exact integers,
 * which keeps mip levels exact at level boundaries). Zero, negative,
 * subnormal and NaN arguments give -1e30 and +Inf gives +1e30, which every
 * caller clamps. */
static inline float persp__log2f(float x)
{
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    int32_t e = (int32_t)(bits >> 23) - 127;
    uint32_t mb = (bits & 0x007fffffu) | 0x3f800000u;
    float m;
    memcpy(&m, &mb, sizeof m);
    float t = m - 1.0f;
    float p = 0.014778720765862436f;
    p = p * t + -0.07740339450744271f;
    p = p * t + 0.1921059850316152f;
    p = p * t + -0.3250416278946991f;
    p = p * t + 0.47351812105207003f;
    p = p * t + -0.720631704101052f;
    p = p * t + 1.4426738996536466f;
    p = p * t;
    float r = (float)e + p;
    r = x > 3.40282347e38f ? 1e30f : r;
    r = x >= 1.17549435e-38f ? r : -1e30f;
    return r;
}


/* x^s for x in (0, 1] and s > 0, the specular term of Blinn–Phong, with an
 * absolute error below 1e-6 (relative below 1e-5 where x^s >= 1e-3 and s
 * <= 128, GL's largest shininess; the rounding of the exponent s·log2 x
 * dominates), measured in tests/unit/test_shading.c. libm's powf is a call per pixel, which no loop
 * around it can vectorise. x^s = 2^(s·log2 x):
 *  - log2 x = e + ln(m)/ln 2 with x = m·2^e, m in [√½, √2), and
 *    ln m = 2·atanh(r) = 2r(1 + r²/3 + r⁴/5 + r⁶/7 + r⁸/9), r = (m−1)/(m+1),
 *    |r| ≤ 0.172, so the next term is below 3e-9 of the sum;
 *  - 2^y = 2^i·2^f, i = y rounded to the nearest integer, |f| ≤ ½, 2^f by its Taylor
 *    series to degree 7 (remainder below 6e-9).
 * y below -126 gives 0 (the result is below 1e-38); x ≤ 0 gives 0. */
static inline float persp__powf_unit(float x, float s)
{
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    int32_t e = (int32_t)((bits >> 23) & 0xffu) - 127;
    uint32_t mb = (bits & 0x007fffffu) | 0x3f800000u;
    float m;
    memcpy(&m, &mb, sizeof m);
    e = m > 1.41421356f ? e + 1 : e;
    m = m > 1.41421356f ? m * 0.5f : m;
    float r = (m - 1.0f) / (m + 1.0f), r2 = r * r;
    float series = 1.0f / 9.0f;
    series = series * r2 + 1.0f / 7.0f;
    series = series * r2 + 1.0f / 5.0f;
    series = series * r2 + 1.0f / 3.0f;
    series = series * r2 + 1.0f;
    float lg = (float)e + (2.0f * 1.44269504f) * r * series;
    float y = s * lg;
    y = y > 1.0f ? 1.0f : y;
    float yc = y >= -126.0f ? y : 0.0f;
    /* Rounding by adding 1.5·2^23: the integer lands in the low mantissa
     * bits (a float-to-int conversion here keeps GCC from vectorising). */
    float big_t = yc + 12582912.0f;
    float yi = big_t - 12582912.0f;
    uint32_t tb;
    memcpy(&tb, &big_t, sizeof tb);
    const uint32_t i = tb - 0x4b400000u;
    float f = (yc - yi) * 0.693147181f;
    float p = 1.0f / 5040.0f;
    p = p * f + 1.0f / 720.0f;
    p = p * f + 1.0f / 120.0f;
    p = p * f + 1.0f / 24.0f;
    p = p * f + 1.0f / 6.0f;
    p = p * f + 0.5f;
    p = p * f + 1.0f;
    p = p * f + 1.0f;
    uint32_t sb = (i + 127u) << 23;
    float scale;
    memcpy(&scale, &sb, sizeof scale);
    float out = p * scale;
    out = y >= -126.0f ? out : 0.0f;
    return x > 0.0f ? out : 0.0f;
}

#endif
