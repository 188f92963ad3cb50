/*
 * Elliptical weighted average (Heckbert, "Fundamentals of Texture Mapping
 * and Image Warping", 1989, §3.5.8): the quality reference among the filters.
 *
 * With the Jacobian (Ux, Vx) = d(u,v)/dx, (Uy, Vy) = d(u,v)/dy in texels, the
 * image of the pixel's unit circle is the ellipse
 *   Q(du, dv) = A du² + B du dv + C dv² <= F,
 *   A = Vx² + Vy² + 1,  B = -2 (Ux Vx + Uy Vy),  C = Ux² + Uy² + 1,
 *   F = A C - B² / 4,
 * where the "+ 1" terms convolve it with a one-texel reconstruction filter so
 * that it never falls between texel centres (Heckbert's practical form).
 * Each texel centre inside gets the Gaussian weight exp(-alpha·Q/F), read
 * from a table built once per sampler (persp__ewa_init); the result is the
 * weighted mean.
 *
 * To bound the work the ellipse is evaluated on the mip level where its
 * minor semi-axis is one to two texels, the minor axis taken as at least
 * major / max_aniso (the eccentricity limit that renderers using EWA apply,
 * e.g. pbrt; the "+ 1" terms then do the widening): on that level the major
 * semi-axis is at most 2·max_aniso texels, so at most about pi·(2·max_aniso + 1)·3 texels
 * are visited. Rows are clipped to the ellipse exactly (the quadratic in du
 * for each dv), so no bounding-box texel outside it is touched.
 */
#include "texture/sample.h"

#include <math.h>

/* Heckbert's Gaussian falloff; exp(-2) ~ 0.135 at the ellipse's edge. */
#define EWA_ALPHA 2.0

void persp__ewa_init(persp_sampler_state *st)
{
    for (int k = 0; k < PERSP_EWA_TABLE; k++) {
        double r2 = (double)k / (double)(PERSP_EWA_TABLE - 1);
        st->ewa_weight[k] = (float)exp(-EWA_ALPHA * r2);
    }
}

/* count != NULL: also counts the texels read (persp__ewa_fetches); the
 * span functions pass a constant NULL, so the count is compiled out. */
static inline void ewa_pixel(const persp_sampler_state *st, int ws, int wt, float u, float v,
                             persp_tex_jac j, float c[4], int *count)
{
    const persp_texture *tex = st->tex;
    int top = tex->levels - 1;
    /* Singular values of the Jacobian: the semi-axes of the footprint. */
    double ux = j.ux, vx = j.vx, uy = j.uy, vy = j.vy;
    double s = ux * ux + vx * vx + uy * uy + vy * vy;
    if (!(s < 1e30)) {
        /* Unbounded (or NaN) footprint: the whole texture's average. */
        persp__bilinear(st, top, ws, wt, u, v, c);
        if (count) *count += 4;
        return;
    }
    double det = fabs(ux * vy - uy * vx);
    double disc = s * s - 4.0 * det * det;
    double major = sqrt(0.5 * (s + sqrt(disc > 0.0 ? disc : 0.0)));
    double minor = major > 0.0 ? det / major : 0.0;
    double ecc = (double)st->max_aniso;
    if (minor * ecc < major) minor = major / ecc;
    float lam = minor > 0.0 ? (float)log2(minor) : -PERSP_LOD_LIMIT;
    lam = persp__clamp_lod(st, lam + st->lod_bias);
    int level = lam <= 0.0f ? 0 : lam >= (float)top ? top : (int)floorf(lam);
    const persp_tex_level *lv = &tex->level[level];
    double sx = (double)lv->w / (double)tex->width, sy = (double)lv->h / (double)tex->height;
    ux *= sx;
    uy *= sx;
    vx *= sy;
    vy *= sy;
    /* A level clamped by max_lod or by the chain's end can leave the ellipse
     * larger than the bound; shrink it to keep the work bounded. */
    double lmajor = major * (sx > sy ? sx : sy), cap = 2.0 * ecc;
    if (lmajor > cap) {
        double f = cap / lmajor;
        ux *= f;
        uy *= f;
        vx *= f;
        vy *= f;
    }
    double A = vx * vx + vy * vy + 1.0;
    double B = -2.0 * (ux * vx + uy * vy);
    double C = ux * ux + uy * uy + 1.0;
    double F = A * C - 0.25 * B * B;
    double invF = 1.0 / F, tscale = (double)(PERSP_EWA_TABLE - 1) * invF;
    /* Centre in the level's texel-index space: texel i has its centre at
     * i + 1/2. */
    double cu = (double)persp__tex_safe(u * (float)lv->w) - 0.5;
    double cv = (double)persp__tex_safe(v * (float)lv->h) - 0.5;
    /* min over du of Q at fixed dv is (F/A)·dv², so |dv| <= sqrt(A). */
    double rv = sqrt(A);
    int j0 = (int)ceil(cv - rv), j1 = (int)floor(cv + rv);
    float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f}, wsum = 0.0f;
    for (int jj = j0; jj <= j1; jj++) {
        double dv = (double)jj - cv;
        double d = B * B * dv * dv - 4.0 * A * (C * dv * dv - F);
        if (d < 0.0) continue;
        double sd = sqrt(d), inv2a = 0.5 / A;
        int i0 = (int)ceil(cu + (-B * dv - sd) * inv2a);
        int i1 = (int)floor(cu + (-B * dv + sd) * inv2a);
        for (int ii = i0; ii <= i1; ii++) {
            double du = (double)ii - cu;
            double qv = (A * du + B * dv) * du + C * dv * dv;
            int t = (int)(qv * tscale);
            if (t < 0) t = 0;
            if (t >= PERSP_EWA_TABLE) continue;
            float w = st->ewa_weight[t];
            persp__acc(acc, persp__texel(st, lv, ws, wt, ii, jj), w);
            wsum += w;
            if (count) (*count)++;
        }
    }
    if (wsum > 0.0f) {
        float inv = 1.0f / wsum;
        for (int k = 0; k < 4; k++) c[k] = acc[k] * inv;
    } else {
        persp__bilinear(st, level, ws, wt, u, v, c);
        if (count) *count += 4;
    }
}

int persp__ewa_fetches(const persp_sampler_state *st, float u, float v, persp_tex_jac j)
{
    float c[4];
    int n = 0;
    ewa_pixel(st, PERSP_WRAP_REPEAT, PERSP_WRAP_REPEAT, u, v, j, c, &n);
    return n;
}

static inline void span_ewa(const persp_sampler_state *st, const persp_tex_span_in *in,
                            uint32_t *out, int ws, int wt)
{
    for (int k = 0; k < in->n; k++) {
        float c[4];
        ewa_pixel(st, ws, wt, in->u[k], in->v[k], persp__span_jacobian(st, in, k), c, NULL);
        out[k] = persp__pack(c);
    }
}

#define SPAN_EWA(NAME, WS, WT)                                                                  \
    static void NAME(const persp_sampler_state *st, const persp_tex_span_in *in, uint32_t *out) \
    {                                                                                           \
        span_ewa(st, in, out, WS, WT);                                                          \
    }
#define R PERSP_WRAP_REPEAT
#define E PERSP_WRAP_CLAMP_TO_EDGE
#define M PERSP_WRAP_MIRRORED_REPEAT
#define B PERSP_WRAP_CLAMP_TO_BORDER
SPAN_EWA(ewa_RR, R, R) SPAN_EWA(ewa_RE, R, E) SPAN_EWA(ewa_RM, R, M) SPAN_EWA(ewa_RB, R, B)
SPAN_EWA(ewa_ER, E, R) SPAN_EWA(ewa_EE, E, E) SPAN_EWA(ewa_EM, E, M) SPAN_EWA(ewa_EB, E, B)
SPAN_EWA(ewa_MR, M, R) SPAN_EWA(ewa_ME, M, E) SPAN_EWA(ewa_MM, M, M) SPAN_EWA(ewa_MB, M, B)
SPAN_EWA(ewa_BR, B, R) SPAN_EWA(ewa_BE, B, E) SPAN_EWA(ewa_BM, B, M) SPAN_EWA(ewa_BB, B, B)
#undef R
#undef E
#undef M
#undef B

const persp_tex_span_fn persp__ewa_spans[16] = {
    ewa_RR, ewa_RE, ewa_RM, ewa_RB, ewa_ER, ewa_EE, ewa_EM, ewa_EB,
    ewa_MR, ewa_ME, ewa_MM, ewa_MB, ewa_BR, ewa_BE, ewa_BM, ewa_BB};
