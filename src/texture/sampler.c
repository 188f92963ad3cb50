/*
 * Span samplers for the point, mip-mapped and anisotropic filters, and the
 * sampler set-up that picks one of them per draw.
 *
 * Level selection follows the OpenGL 4.6 specification §8.14: lambda =
 * log2(rho) + bias clamped to [min_lod, max_lod], rho the longer of the two
 * screen-axis footprints in texels; lambda <= 0 is magnification (bilinear
 * for the linear filters, nearest for nearest-*, c = 0 in §8.14.3 since the
 * magnification filter matches the minification filter's in-level filter);
 * *_MIP_NEAREST takes level ceil(lambda + 1/2) - 1, *_MIP_LINEAR blends
 * levels floor(lambda) and floor(lambda) + 1 by frac(lambda).
 *
 * The anisotropic filter is the EXT_texture_filter_anisotropic rule:
 * Px, Py the footprint lengths along the screen axes, N = min(ceil(Pmax /
 * Pmin), max_aniso), lambda' = log2(Pmax / N), and N trilinear taps spread
 * evenly along the major axis.
 *
 * Every filter × wrap_s × wrap_t combination is a separate function built
 * from one inline body with constant arguments, so the per-pixel loops carry
 * no test of the sampler state.
 */
#include "texture/sample.h"

#include "core/internal.h"

#include <math.h>
#include <string.h>

/* Level for *_MIP_NEAREST at a clamped lambda > 0 (GL 4.6 eq. 8.17). */
static inline int mip_nearest_level(const persp_sampler_state *st, float lam)
{
    int q = st->tex->levels - 1;
    if (lam <= 0.5f) return 0;
    float d = ceilf(lam + 0.5f) - 1.0f;
    return d >= (float)q ? q : (int)d;
}

/* One pixel of an isotropic filter at a clamped lambda. */
static inline uint32_t iso_pixel(const persp_sampler_state *st, int filter, int ws, int wt,
                                 float u, float v, float lam)
{
    float c[4], c2[4];
    int q = st->tex->levels - 1;
    switch (filter) {
    case PERSP_FILTER_NEAREST:
        persp__nearest(st, 0, ws, wt, u, v, c);
        break;
    case PERSP_FILTER_BILINEAR:
        persp__bilinear(st, 0, ws, wt, u, v, c);
        break;
    case PERSP_FILTER_NEAREST_MIP_NEAREST:
        persp__nearest(st, lam <= 0.0f ? 0 : mip_nearest_level(st, lam), ws, wt, u, v, c);
        break;
    case PERSP_FILTER_BILINEAR_MIP_NEAREST:
        persp__bilinear(st, lam <= 0.0f ? 0 : mip_nearest_level(st, lam), ws, wt, u, v, c);
        break;
    case PERSP_FILTER_NEAREST_MIP_LINEAR: {
        if (lam <= 0.0f) {
            persp__nearest(st, 0, ws, wt, u, v, c);
            break;
        }
        float fl = floorf(lam);
        if (fl >= (float)q) {
            persp__nearest(st, q, ws, wt, u, v, c);
            break;
        }
        int d1 = (int)fl;
        float f = lam - fl;
        persp__nearest(st, d1, ws, wt, u, v, c);
        persp__nearest(st, d1 + 1, ws, wt, u, v, c2);
        for (int k = 0; k < 4; k++) c[k] += f * (c2[k] - c[k]);
        break;
    }
    default: /* PERSP_FILTER_TRILINEAR */
        persp__trilinear(st, ws, wt, u, v, lam, c);
        break;
    }
    return persp__pack(c);
}

static inline void span_iso(const persp_sampler_state *st, const persp_tex_span_in *in,
                            uint32_t *out, int filter, int ws, int wt)
{
    int n = in->n;
    if (filter == PERSP_FILTER_NEAREST || filter == PERSP_FILTER_BILINEAR) {
        for (int k = 0; k < n; k++) out[k] = iso_pixel(st, filter, ws, wt, in->u[k], in->v[k], 0.0f);
    } else if (st->desc.lod_mode == PERSP_LOD_POLYGON) {
        float lam = persp__clamp_lod(st, in->poly_lambda + st->lod_bias);
        for (int k = 0; k < n; k++) out[k] = iso_pixel(st, filter, ws, wt, in->u[k], in->v[k], lam);
    } else {
        for (int k = 0; k < n; k++) {
            float lam = persp__jac_lambda(st, persp__span_jacobian(st, in, k));
            out[k] = iso_pixel(st, filter, ws, wt, in->u[k], in->v[k], lam);
        }
    }
}

static inline void span_aniso(const persp_sampler_state *st, const persp_tex_span_in *in,
                              uint32_t *out, int ws, int wt)
{
    float W = (float)st->tex->width, H = (float)st->tex->height;
    for (int k = 0; k < in->n; k++) {
        persp_tex_jac j = persp__span_jacobian(st, in, k);
        float lam;
        int major_x;
        int n = persp__aniso_rule(st, j, &lam, &major_x);
        /* The major axis in normalised coordinates; taps at its (k+1/2)/N - 1/2
         * fractions so they are centred on (u, v) and one Pmax long in all. */
        float du = (major_x ? j.ux : j.uy) / W, dv = (major_x ? j.vx : j.vy) / H;
        float inv = 1.0f / (float)n, acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int t = 0; t < n; t++) {
            float s = ((float)t + 0.5f) * inv - 0.5f, c[4];
            persp__trilinear(st, ws, wt, in->u[k] + s * du, in->v[k] + s * dv, lam, c);
            for (int m = 0; m < 4; m++) acc[m] += c[m];
        }
        for (int m = 0; m < 4; m++) acc[m] *= inv;
        out[k] = persp__pack(acc);
    }
}

#define SPAN_ISO(NAME, FILTER, WS, WT)                                                          \
    static void NAME(const persp_sampler_state *st, const persp_tex_span_in *in, uint32_t *out) \
    {                                                                                           \
        span_iso(st, in, out, FILTER, WS, WT);                                                  \
    }
#define SPAN_ANISO(NAME, WS, WT)                                                                \
    static void NAME(const persp_sampler_state *st, const persp_tex_span_in *in, uint32_t *out) \
    {                                                                                           \
        span_aniso(st, in, out, WS, WT);                                                        \
    }

#define R PERSP_WRAP_REPEAT
#define E PERSP_WRAP_CLAMP_TO_EDGE
#define M PERSP_WRAP_MIRRORED_REPEAT
#define B PERSP_WRAP_CLAMP_TO_BORDER
#define WRAPS_ISO(P, F)                                                                            \
    SPAN_ISO(P##_RR, F, R, R) SPAN_ISO(P##_RE, F, R, E) SPAN_ISO(P##_RM, F, R, M)                  \
    SPAN_ISO(P##_RB, F, R, B) SPAN_ISO(P##_ER, F, E, R) SPAN_ISO(P##_EE, F, E, E)                  \
    SPAN_ISO(P##_EM, F, E, M) SPAN_ISO(P##_EB, F, E, B) SPAN_ISO(P##_MR, F, M, R)                  \
    SPAN_ISO(P##_ME, F, M, E) SPAN_ISO(P##_MM, F, M, M) SPAN_ISO(P##_MB, F, M, B)                  \
    SPAN_ISO(P##_BR, F, B, R) SPAN_ISO(P##_BE, F, B, E) SPAN_ISO(P##_BM, F, B, M)                  \
    SPAN_ISO(P##_BB, F, B, B)
#define TABLE(P)                                                                                   \
    {P##_RR, P##_RE, P##_RM, P##_RB, P##_ER, P##_EE, P##_EM, P##_EB,                              \
     P##_MR, P##_ME, P##_MM, P##_MB, P##_BR, P##_BE, P##_BM, P##_BB}

WRAPS_ISO(nearest, PERSP_FILTER_NEAREST)
WRAPS_ISO(bilinear, PERSP_FILTER_BILINEAR)
WRAPS_ISO(nmn, PERSP_FILTER_NEAREST_MIP_NEAREST)
WRAPS_ISO(bmn, PERSP_FILTER_BILINEAR_MIP_NEAREST)
WRAPS_ISO(nml, PERSP_FILTER_NEAREST_MIP_LINEAR)
WRAPS_ISO(tri, PERSP_FILTER_TRILINEAR)
SPAN_ANISO(aniso_RR, R, R) SPAN_ANISO(aniso_RE, R, E) SPAN_ANISO(aniso_RM, R, M)
SPAN_ANISO(aniso_RB, R, B) SPAN_ANISO(aniso_ER, E, R) SPAN_ANISO(aniso_EE, E, E)
SPAN_ANISO(aniso_EM, E, M) SPAN_ANISO(aniso_EB, E, B) SPAN_ANISO(aniso_MR, M, R)
SPAN_ANISO(aniso_ME, M, E) SPAN_ANISO(aniso_MM, M, M) SPAN_ANISO(aniso_MB, M, B)
SPAN_ANISO(aniso_BR, B, R) SPAN_ANISO(aniso_BE, B, E) SPAN_ANISO(aniso_BM, B, M)
SPAN_ANISO(aniso_BB, B, B)

static const persp_tex_span_fn span_table[7][16] = {
    TABLE(nearest), TABLE(bilinear), TABLE(nmn), TABLE(bmn), TABLE(nml), TABLE(tri),
    TABLE(aniso)};

#undef R
#undef E
#undef M
#undef B

persp_status persp__sampler_init(persp_sampler_state *st, const struct persp_texture *tex,
                                 const persp_sampler_desc *given)
{
    return persp__sampler_init_isa(st, tex, given, persp__cpu_isa());
}

const char *persp__sampler_desc_problem(const persp_sampler_desc *d)
{
    return (unsigned)d->wrap_s > PERSP_WRAP_CLAMP_TO_BORDER             ? "wrap_s"
           : (unsigned)d->wrap_t > PERSP_WRAP_CLAMP_TO_BORDER           ? "wrap_t"
           : (unsigned)d->filter >= (unsigned)PERSP_FILTER_COUNT        ? "filter"
           : d->max_aniso < 0 || d->max_aniso == 1 || d->max_aniso > PERSP_MAX_ANISO ? "max_aniso (0, or 2..16)"
           : !isfinite(d->lod_bias)                                     ? "lod_bias (finite)"
           : (unsigned)d->lod_mode > PERSP_LOD_POLYGON                  ? "lod_mode"
           : (unsigned)d->lod_clamp > PERSP_TOGGLE_OFF                  ? "lod_clamp"
           : d->lod_clamp == PERSP_TOGGLE_ON &&
                   !(isfinite(d->min_lod) && isfinite(d->max_lod) && d->min_lod <= d->max_lod)
               ? "min_lod, max_lod (finite, min_lod <= max_lod)"
               : NULL;
}

persp_status persp__sampler_init_isa(persp_sampler_state *st, const struct persp_texture *tex,
                                     const persp_sampler_desc *given, int isa)
{
    if (!st || !tex || !given) return PERSP_ERR_INVALID_ARGUMENT;
    persp_sampler_desc d = *given;
    if (d.wrap_s == PERSP_WRAP_DEFAULT) d.wrap_s = PERSP_WRAP_REPEAT;
    if (d.wrap_t == PERSP_WRAP_DEFAULT) d.wrap_t = PERSP_WRAP_REPEAT;
    if (d.filter == PERSP_FILTER_DEFAULT) d.filter = PERSP_FILTER_BILINEAR;
    if (d.lod_mode == PERSP_LOD_DEFAULT) d.lod_mode = PERSP_LOD_PIXEL;
    if (d.lod_clamp == PERSP_TOGGLE_DEFAULT) d.lod_clamp = PERSP_TOGGLE_OFF;
    if (persp__sampler_desc_problem(&d)) return PERSP_ERR_INVALID_ARGUMENT;
    memset(st, 0, sizeof *st);
    st->tex = tex;
    st->desc = d;
    st->max_aniso = d.max_aniso == 0 ? PERSP_MAX_ANISO : d.max_aniso;
    st->lod_bias = d.lod_bias;
    /* GL's defaults are min -1000, max 1000; the level index is clamped to
     * the chain separately, so max_lod = levels - 1 is equivalent. */
    float top = (float)(tex->levels - 1);
    if (d.lod_clamp == PERSP_TOGGLE_OFF) {
        st->min_lod = -PERSP_LOD_LIMIT;
        st->max_lod = top;
    } else {
        st->min_lod = d.min_lod;
        st->max_lod = d.max_lod < top ? d.max_lod : top;
        if (st->max_lod < st->min_lod) st->max_lod = st->min_lod;
    }
    const uint8_t *b = d.border;
    st->border = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    int wrap = persp__wrap_pair_index(d.wrap_s, d.wrap_t);
    switch (d.filter) {
    case PERSP_FILTER_EWA:
        persp__ewa_init(st);
        st->span = persp__ewa_spans[wrap];
        break;
    case PERSP_FILTER_ANISO_WINDOW:
        st->span = persp__window_spans[wrap];
        break;
    default:
        st->span = persp__fast_span_select_isa(st, isa);
        if (!st->span) st->span = span_table[d.filter - PERSP_FILTER_NEAREST][wrap];
        break;
    }
    return PERSP_OK;
}

persp_tex_span_fn persp__general_span(persp_filter filter, persp_wrap ws, persp_wrap wt)
{
    if (ws == PERSP_WRAP_DEFAULT) ws = PERSP_WRAP_REPEAT;
    if (wt == PERSP_WRAP_DEFAULT) wt = PERSP_WRAP_REPEAT;
    if (filter < PERSP_FILTER_NEAREST || filter > PERSP_FILTER_ANISO || ws < PERSP_WRAP_REPEAT ||
        ws > PERSP_WRAP_CLAMP_TO_BORDER || wt < PERSP_WRAP_REPEAT || wt > PERSP_WRAP_CLAMP_TO_BORDER)
        return NULL;
    return span_table[filter - PERSP_FILTER_NEAREST][persp__wrap_pair_index(ws, wt)];
}

int persp__sampler_needs_lod(const persp_sampler_state *st)
{
    return st && st->desc.filter != PERSP_FILTER_NEAREST && st->desc.filter != PERSP_FILTER_BILINEAR;
}

/* Texels read by one bilinear or trilinear lookup at a clamped lambda. */
static int trilinear_fetches(const persp_sampler_state *st, float lam)
{
    if (lam <= 0.0f || floorf(lam) >= (float)(st->tex->levels - 1)) return 4;
    return 8;
}

int persp__sampler_fetches(const persp_sampler_state *st, const persp_tex_span_in *in, int k)
{
    int filter = (int)st->desc.filter;
    if (filter == PERSP_FILTER_NEAREST) return 1;
    if (filter == PERSP_FILTER_BILINEAR) return 4;
    persp_tex_jac j = persp__span_jacobian(st, in, k);
    float lam;
    switch (filter) {
    case PERSP_FILTER_ANISO: {
        int major_x;
        int n = persp__aniso_rule(st, j, &lam, &major_x);
        return n * trilinear_fetches(st, lam);
    }
    case PERSP_FILTER_ANISO_WINDOW: {
        float W = (float)st->tex->width, H = (float)st->tex->height;
        persp_tex_window w;
        if (persp__window_setup(st, in->u[k], in->v[k], j.ux / W, j.vx / H, j.uy / W, j.vy / H, &w))
            return w.len * w.rows;
        return 4;
    }
    case PERSP_FILTER_EWA:
        return persp__ewa_fetches(st, in->u[k], in->v[k], j);
    default:
        break;
    }
    lam = st->desc.lod_mode == PERSP_LOD_POLYGON ? persp__clamp_lod(st, in->poly_lambda + st->lod_bias)
                                                  : persp__jac_lambda(st, j);
    switch (filter) {
    case PERSP_FILTER_NEAREST_MIP_NEAREST:
        return 1;
    case PERSP_FILTER_BILINEAR_MIP_NEAREST:
        return 4;
    case PERSP_FILTER_NEAREST_MIP_LINEAR:
        return trilinear_fetches(st, lam) / 4;
    default:
        return trilinear_fetches(st, lam);
    }
}

int persp__aniso_taps(const persp_sampler_state *st, float dudx, float dvdx, float dudy,
                      float dvdy, float *lambda)
{
    persp_tex_jac j = {dudx * (float)st->tex->width, dvdx * (float)st->tex->height,
                       dudy * (float)st->tex->width, dvdy * (float)st->tex->height};
    float lam;
    int major_x;
    int n = persp__aniso_rule(st, j, &lam, &major_x);
    if (lambda) *lambda = lam;
    return n;
}

float persp__pixel_lambda(const persp_sampler_state *st, float dudx, float dvdx, float dudy,
                          float dvdy)
{
    persp_tex_jac j = {dudx * (float)st->tex->width, dvdx * (float)st->tex->height,
                       dudy * (float)st->tex->width, dvdy * (float)st->tex->height};
    return persp__jac_lambda(st, j);
}

void persp_texture_sample(const persp_texture *tex, const persp_sampler_desc *sampler, float u,
                          float v, float dudx, float dvdx, float dudy, float dvdy,
                          uint8_t rgba_out[4])
{
    if (!rgba_out) return;
    memset(rgba_out, 0, 4);
    if (!tex || !sampler) return;
    persp_sampler_state st;
    if (persp__sampler_init(&st, tex, sampler) != PERSP_OK) return;
    /* With Q = 1 and g = h = 0 the span derivatives (a - u·g)/Q, ... are the
     * given derivatives themselves. */
    float one = 1.0f;
    /* The polygon mode's texel/pixel area ratio of this footprint. */
    float area = fabsf(dudx * dvdy - dudy * dvdx) * (float)tex->width * (float)tex->height;
    float poly = area > 0.0f ? 0.5f * log2f(area) : -PERSP_LOD_LIMIT;
    persp_tex_span_in in = {.n = 1, .u = &u, .v = &v, .q = &one, .a = dudx, .b = dudy,
                            .d = dvdx, .e = dvdy, .g = 0.0f, .h = 0.0f, .poly_lambda = poly};
    uint32_t t;
    persp__sample_span(&st, &in, &t);
    for (int k = 0; k < 4; k++) rgba_out[k] = (uint8_t)(t >> (8 * k));
}
