/*
 * Vectorised span samplers for the states that dominate real workloads:
 * power-of-two textures, wrap repeat or clamp-to-edge on each axis, and the
 * filters of OpenGL (nearest, bilinear, nearest-mip-nearest,
 * bilinear-mip-nearest, nearest-mip-linear, trilinear, and the anisotropic
 * filter of EXT_texture_filter_anisotropic).
 *
 * They compute exactly what the general samplers of sampler.c compute (GL
 * 4.6 §8.14: texel i = wrap(floor(s·W)), linear taps at floor(s·W − 1/2)
 * with weight frac(s·W − 1/2), lambda from the analytic Jacobian), with the
 * same floating-point operations in the same order, so the two agree bit for
 * bit; what differs is the shape of the code. Every stage is a loop over the
 * whole span (structure of arrays, at most PERSP_LANE_MAX pixels) without
 * calls or data-dependent branches, which GCC turns into 8- or 16-lane code
 * in the AVX2 and AVX-512 variants and 4-lane SSE2 code in the baseline one:
 *   1. coordinates → integer texel indices and fractions,
 *   2. wrap by masks (power-of-two sizes) or clamps → addresses,
 *   3. fetch,
 *   4. weights and the per-channel sums, rounded once at the end.
 * The general samplers wrap with an integer remainder per tap, which is
 * what made them several times slower.
 *
 * The bodies are in fastspan_body.h; this file instantiates them per
 * instruction set, fastspan_gather.c once more with the texels fetched by
 * gather instructions, and persp__fast_span_auto_isa (below) times the two
 * fetches to choose between them.
 */
#include "texture/fastspan_body.h"

/* The baseline variants (SSE2 on x86-64: 4 lanes) and, where the compiler
 * can target them, AVX2 (8 lanes) and AVX-512 (16 lanes) ones, picked at
 * sampler set-up from the CPU. */
FAST_VARIANT(static, variant_base, base, , 0)
#if PERSP_HAVE_ISA_VARIANTS
FAST_VARIANT(static, variant_avx2, avx2, PERSP_TARGET_AVX2, 1)
FAST_VARIANT(static, variant_avx512, avx512, PERSP_TARGET_AVX512, 0)
#endif

static int is_pot(int n) { return n > 0 && (n & (n - 1)) == 0; }

static int log2_int(int n)
{
    int s = 0;
    while ((1 << s) < n) s++;
    return s;
}

persp_tex_span_fn persp__fast_span_select(persp_sampler_state *st)
{
    return persp__fast_span_select_isa(st, persp__cpu_isa());
}

persp_tex_span_fn persp__fast_span_select_isa(persp_sampler_state *st, int isa)
{
    const struct persp_texture *tex = st->tex;
    memset(&st->pot, 0, sizeof st->pot);
    int ws = (int)st->desc.wrap_s, wt = (int)st->desc.wrap_t;
    if (ws > PERSP_WRAP_CLAMP_TO_EDGE || wt > PERSP_WRAP_CLAMP_TO_EDGE) return NULL;
    if (tex->levels < 1 || tex->levels > PERSP_TEX_MAX_LEVELS) return NULL;
    for (int l = 0; l < tex->levels; l++) {
        const persp_tex_level *lv = &tex->level[l];
        ptrdiff_t off = lv->texels - tex->storage;
        if (!is_pot(lv->w) || !is_pot(lv->h) || off < 0 || off > INT32_MAX / 2) return NULL;
        st->pot.fw[l] = (float)lv->w;
        st->pot.fh[l] = (float)lv->h;
        st->pot.wmask[l] = lv->w - 1;
        st->pot.hmask[l] = lv->h - 1;
        st->pot.shift[l] = log2_int(lv->w);
        st->pot.off[l] = (int32_t)off;
    }
    if (tex->level[0].texels != tex->storage) return NULL;
    st->pot.coord_limit = PERSP_TEX_COORD_LIMIT;
    st->pot.pot = 1;
    int w = (ws - PERSP_WRAP_REPEAT) * 2 + (wt - PERSP_WRAP_REPEAT);
    /* Indexed by PERSP_ISA_*. */
    static const persp_tex_span_fn *const *const table[] = {
        variant_base,
#if PERSP_HAVE_ISA_VARIANTS
        variant_avx2, variant_avx512, persp__fast_avx2g, persp__fast_avx512g,
#endif
    };
    if (st->desc.filter < PERSP_FILTER_NEAREST || st->desc.filter > PERSP_FILTER_ANISO) return NULL;
    if (isa < PERSP_ISA_BASE ||
        isa > (PERSP_HAVE_ISA_VARIANTS ? PERSP_ISA_AVX512_GATHER : PERSP_ISA_BASE))
        isa = PERSP_ISA_BASE;
    return table[isa][st->desc.filter - PERSP_FILTER_NEAREST][w];
}

/* Which variant runs fastest depends on the core, and not only on its
 * vendor or on what it reports:
 * - Gathers are microcoded and slow on AMD's Zen, fast on Intel's cores
 *   from Skylake on, and several times slower again on those with the 2023
 *   "Downfall" (GDS) microcode.
 * - AVX-512 is not always the faster width: on the AMD EPYC (Zen 5) VM of
 *   docs/PERFORMANCE.md its bilinear spans took 1.2-1.3 times as long as
 *   AVX2's at every length from 8 to 256 lanes, and whole frames were up to
 *   10 % slower (corridor bilinear 237 against 260 Mpix/s), its 16-lane
 *   groups padding the short rows of small triangles further besides.
 * So the candidates are timed here, on a bilinear span of an L1-resident
 * texture (the fetch and the width are what differ between them;
 * docs/PERFORMANCE.md, "On an Intel Xeon: samplers with gathers, 16
 * threads"): a few spans each, interleaved, best of several rounds, under
 * a millisecond in all. First the width: AVX-512 must beat AVX2 by 10 %,
 * for its wider padding costs on short rows that a long span does not
 * show. Then the fetch at that width: the gather variant must also win by
 * 10 %; where the two are close (Zen 5: gathers 1 % slower here, and timing
 * noise of a few per cent) the scalar loads are kept, as they cost less on
 * the cache misses of large textures; on the Intel Xeon measured (Emerald
 * Rapids) gathers made the corridor's bilinear frame 22 % faster. Whatever
 * the choice, the images are the same. */
#if PERSP_HAVE_ISA_VARIANTS
#define TIMED_SIDE 64
typedef struct timed_span {
    struct persp_texture tex;
    uint32_t texels[TIMED_SIDE * TIMED_SIDE];
    float u[N], v[N];
    uint32_t out[N];
} timed_span;

/* Best time of a few spans of each of two variants (PERSP_ISA_*),
 * interleaved; 0 if a variant has no sampler here. */
static int time_variants(timed_span *ts, const int variant[2], double best[2])
{
    enum { ROUNDS = 11, SPANS = 6 };
    persp_sampler_state st[2];
    persp_tex_span_fn fn[2];
    memset(st, 0, sizeof st);
    for (int v = 0; v < 2; v++) {
        st[v].tex = &ts->tex;
        st[v].desc.filter = PERSP_FILTER_BILINEAR;
        st[v].desc.wrap_s = st[v].desc.wrap_t = PERSP_WRAP_REPEAT;
        fn[v] = persp__fast_span_select_isa(&st[v], variant[v]);
        if (!fn[v]) return 0;
        best[v] = 1e30;
    }
    persp_tex_span_in in = {.n = N, .u = ts->u, .v = ts->v};
    for (int r = 0; r < ROUNDS; r++)
        for (int v = 0; v < 2; v++) {
            double t0 = persp__now_seconds();
            for (int i = 0; i < SPANS; i++) fn[v](&st[v], &in, ts->out);
            double t = persp__now_seconds() - t0;
            best[v] = t < best[v] ? t : best[v];
        }
    return 1;
}
#endif

int persp__fast_span_auto_isa(void)
{
    int isa = persp__cpu_isa();
#if PERSP_HAVE_ISA_VARIANTS
    if (isa == PERSP_ISA_BASE) return isa;
    enum { S = TIMED_SIDE };
    timed_span ts;
    memset(&ts.tex, 0, sizeof ts.tex);
    for (uint32_t i = 0; i < S * S; i++) ts.texels[i] = i * 2654435761u;
    ts.tex.width = ts.tex.height = S;
    ts.tex.levels = 1;
    ts.tex.level[0] = (persp_tex_level){S, S, ts.texels};
    ts.tex.storage = ts.texels;
    /* A span crossing the texture at an angle, minified about 1.5 times,
     * as the corridor's floor is on most rows. */
    for (int k = 0; k < N; k++) {
        ts.u[k] = 0.137f + (float)k * (1.5f / S);
        ts.v[k] = 0.711f + (float)k * (0.6f / S);
    }
    double best[2];
    if (isa == PERSP_ISA_AVX512) {
        const int width[2] = {PERSP_ISA_AVX2, PERSP_ISA_AVX512};
        if (time_variants(&ts, width, best) && !(best[1] < 0.9 * best[0])) isa = PERSP_ISA_AVX2;
    }
    const int fetch[2] = {isa, isa == PERSP_ISA_AVX512 ? PERSP_ISA_AVX512_GATHER : PERSP_ISA_AVX2_GATHER};
    if (!time_variants(&ts, fetch, best)) return isa;
    return best[1] < 0.9 * best[0] ? fetch[1] : isa;
#else
    return isa;
#endif
}
