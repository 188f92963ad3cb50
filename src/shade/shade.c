/*
 * Shading modes ([Romanyuk-PCF] §4.2–4.3, [Romaniuk-ACIT18]) and the span shaders they
 * resolve to.
 *
 * Every mode reduces to barycentric weights (b0, b1, b2) per pixel:
 *  - screen-linear weights give classical Gouraud / Phong;
 *  - perspective-correct weights are the rational form b_k = (b_k/w)/(1/w),
 *    i.e. the perspective parameter t_w of (4.6) in two dimensions, computed
 *    by a texture-coordinate method run on the planes of b1/w, b2/w. The
 *    polynomial t_w approximations of §4.3 are therefore the span methods
 *    `quadratic`, `quadratic-pw` and `cubic` of src/interp, whose fitting
 *    and forward differences are poly.c's: written once.
 * Lighting is Blinn–Phong with ambient, diffuse and specular terms.
 */
#include "shade/shade.h"

#include "core/fmath.h"
#include "core/internal.h"
#include "interp/poly.h"

#include <math.h>
#include <string.h>

static const char *const shading_names[PERSP_SHADING_COUNT] = {
    "default", "none", "flat", "gouraud", "gouraud-pc", "phong", "phong-pc", "phong-pc:quad",
    "phong-pc:pwquad", "phong-pc:cubic", "phong-slerp", "phong-slerp-screen",
};

persp_status persp_shading_parse(const char *name, persp_shading *out)
{
    if (!name || !out) return PERSP_ERR_INVALID_ARGUMENT;
    for (int i = 0; i < PERSP_SHADING_COUNT; i++)
        if (!strcmp(name, shading_names[i])) {
            *out = (persp_shading)i;
            return PERSP_OK;
        }
    return PERSP_ERR_NOT_FOUND;
}

const char *persp_shading_name(persp_shading s)
{
    return (unsigned)s < PERSP_SHADING_COUNT ? shading_names[s] : "unknown";
}

static uint32_t pack(const float c[4])
{
    uint32_t r = 0;
    for (int k = 0; k < 4; k++) {
        float x = c[k] * 255.0f + 0.5f;
        x = x < 0.0f ? 0.0f : x > 255.0f ? 255.0f : x;
        r |= (uint32_t)x << (8 * k);
    }
    return r;
}

/* Blinn–Phong at eye-space point e with unit normal n. Writes the ambient +
 * diffuse part (which a texture modulates) and the specular part. */
static void light_point(const persp_draw_state *ds, const float n_in[3], const float e[3], float side,
                        float diff[3], float spec[3])
{
    const persp_material *m = &ds->material;
    const persp_lighting *L = &ds->lighting;
    /* Two-sided lighting: side = −1 lights the other face (persp_tri.light_side). */
    float n[3] = {side * n_in[0], side * n_in[1], side * n_in[2]};
    float vlen = sqrtf(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    float v[3] = {0.0f, 0.0f, 1.0f};
    if (vlen > 0.0f) {
        float inv = -1.0f / vlen;
        v[0] = e[0] * inv, v[1] = e[1] * inv, v[2] = e[2] * inv;
    }
    for (int c = 0; c < 3; c++) {
        diff[c] = L->ambient[c] * m->ambient[c] + m->emission[c];
        spec[c] = 0.0f;
    }
    for (int i = 0; i < L->count; i++) {
        const persp_eye_light *l = &L->light[i];
        float d[3], att = 1.0f;
        if (l->type == PERSP_LIGHT_DIRECTIONAL) {
            d[0] = l->pos[0], d[1] = l->pos[1], d[2] = l->pos[2];
        } else {
            d[0] = l->pos[0] - e[0], d[1] = l->pos[1] - e[1], d[2] = l->pos[2] - e[2];
            float dist = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            float inv = 1.0f / (dist > 0.0f ? dist : 1.0f);
            d[0] *= inv, d[1] *= inv, d[2] *= inv;
            float den = l->atten[0] + l->atten[1] * dist + l->atten[2] * dist * dist;
            att = den > 0.0f ? 1.0f / den : 1.0f;
        }
        float ndl = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        if (ndl <= 0.0f) continue;
        float h[3] = {d[0] + v[0], d[1] + v[1], d[2] + v[2]};
        float hl = sqrtf(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        float ndh = hl > 0.0f ? (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hl : 0.0f;
        float sp = ndh > 0.0f && m->shininess > 0.0f ? persp__powf_unit(ndh, m->shininess) : 0.0f;
        for (int c = 0; c < 3; c++) {
            diff[c] += att * l->color[c] * m->diffuse[c] * ndl;
            spec[c] += att * l->color[c] * m->specular[c] * sp;
        }
    }
}

/* ------------------------------------------------- lighting across a span */

/* What each pixel of a span is lit with, one array per component, so that
 * the lighting loops run across pixels in vector lanes (the same operations
 * in the same order as light_point, so the scalar and the vector paths
 * agree wherever both are used). */
typedef struct lit_span {
    float nx[PERSP_LANE_MAX], ny[PERSP_LANE_MAX], nz[PERSP_LANE_MAX];
    float ex[PERSP_LANE_MAX], ey[PERSP_LANE_MAX], ez[PERSP_LANE_MAX];
    /* The vertex colour, perspective-correct, when ds->color_material. */
    float cr[PERSP_LANE_MAX], cg[PERSP_LANE_MAX], cb[PERSP_LANE_MAX];
} lit_span;

/* Lighting loops run over whole vectors of 16 lanes: the spans of small
 * triangles are short, and a loop's scalar remainder would otherwise cost
 * more than its vector body. Lanes past the span's end hold zero normals
 * and positions, which light to finite values that are never stored. */
static int span_lanes(int n) { return (n + 15) & ~15; }

static void pad_lit_span(lit_span *g, int n)
{
    for (int k = n; k < span_lanes(n); k++)
        g->nx[k] = g->ny[k] = g->nz[k] = g->ex[k] = g->ey[k] = g->ez[k] = 0.0f;
}

/* One light's contribution across a span; directional is a constant at
 * each call site, so each instance is a straight-line loop. */
static inline __attribute__((always_inline)) void
light_add(const persp_material *m, const persp_eye_light *l, const int directional, int n, const lit_span *g,
          const float *nx, const float *ny, const float *nz, const float *vx, const float *vy,
          const float *vz, float *restrict dr, float *restrict dg, float *restrict db, float *restrict sr,
          float *restrict sg, float *restrict sb)
{
    const float lx = l->pos[0], ly = l->pos[1], lz = l->pos[2];
    const float k0 = l->atten[0], k1 = l->atten[1], k2 = l->atten[2];
    const float shin = m->shininess;
    const int shiny = shin > 0.0f;
    const float c0 = l->color[0], c1 = l->color[1], c2 = l->color[2];
    const float md0 = m->diffuse[0], md1 = m->diffuse[1], md2 = m->diffuse[2];
    const float ms0 = m->specular[0], ms1 = m->specular[1], ms2 = m->specular[2];
    for (int k = 0; k < n; k++) {
        float dx = lx, dy = ly, dz = lz, att = 1.0f;
        if (!directional) {
            dx = lx - g->ex[k], dy = ly - g->ey[k], dz = lz - g->ez[k];
            float dist = sqrtf(dx * dx + dy * dy + dz * dz);
            float inv = 1.0f / (dist > 0.0f ? dist : 1.0f);
            dx *= inv, dy *= inv, dz *= inv;
            float den = k0 + k1 * dist + k2 * dist * dist;
            att = den > 0.0f ? 1.0f / (den > 0.0f ? den : 1.0f) : 1.0f;
        }
        float ndl = nx[k] * dx + ny[k] * dy + nz[k] * dz;
        float hx = dx + vx[k], hy = dy + vy[k], hz = dz + vz[k];
        float hl = sqrtf(hx * hx + hy * hy + hz * hz);
        float ndh = hl > 0.0f ? (nx[k] * hx + ny[k] * hy + nz[k] * hz) / (hl > 0.0f ? hl : 1.0f) : 0.0f;
        float sp = persp__powf_unit(ndh, shin);
        sp = ((ndh > 0.0f) & shiny) ? sp : 0.0f;
        int lit = ndl > 0.0f;
        dr[k] += lit ? att * c0 * md0 * ndl : 0.0f;
        dg[k] += lit ? att * c1 * md1 * ndl : 0.0f;
        db[k] += lit ? att * c2 * md2 * ndl : 0.0f;
        sr[k] += lit ? att * c0 * ms0 * sp : 0.0f;
        sg[k] += lit ? att * c1 * ms1 * sp : 0.0f;
        sb[k] += lit ? att * c2 * ms2 * sp : 0.0f;
    }
}

/* Ambient + diffuse (d*) and specular (s*) light per pixel: Blinn–Phong,
 * light_point's arithmetic with its branches turned into selects. */
static PERSP_ALWAYS_INLINE void light_soa_body(const persp_draw_state *ds, const float *side, int n,
                                               const lit_span *g, float *restrict dr, float *restrict dg,
                                               float *restrict db, float *restrict sr, float *restrict sg,
                                               float *restrict sb)
{
    const persp_material *m = &ds->material;
    const persp_lighting *L = &ds->lighting;
    float vx[PERSP_LANE_MAX], vy[PERSP_LANE_MAX], vz[PERSP_LANE_MAX];
    float nx[PERSP_LANE_MAX], ny[PERSP_LANE_MAX], nz[PERSP_LANE_MAX];
    /* The material's emission joins the ambient term, a constant of the
     * draw (GL 1.5 §2.14.1: c = e_cm + a_cm·a_cs + ...). */
    const float a0 = L->ambient[0] * m->ambient[0] + m->emission[0],
                a1 = L->ambient[1] * m->ambient[1] + m->emission[1],
                a2 = L->ambient[2] * m->ambient[2] + m->emission[2];
    n = span_lanes(n);
    for (int k = 0; k < n; k++) {
        nx[k] = side[k] * g->nx[k], ny[k] = side[k] * g->ny[k], nz[k] = side[k] * g->nz[k];
        float ex = g->ex[k], ey = g->ey[k], ez = g->ez[k];
        float vlen = sqrtf(ex * ex + ey * ey + ez * ez);
        float inv = -1.0f / (vlen > 0.0f ? vlen : 1.0f);
        vx[k] = vlen > 0.0f ? ex * inv : 0.0f;
        vy[k] = vlen > 0.0f ? ey * inv : 0.0f;
        vz[k] = vlen > 0.0f ? ez * inv : 1.0f;
        dr[k] = a0, dg[k] = a1, db[k] = a2;
        sr[k] = sg[k] = sb[k] = 0.0f;
    }
    for (int i = 0; i < L->count; i++) {
        if (L->light[i].type == PERSP_LIGHT_DIRECTIONAL)
            light_add(m, &L->light[i], 1, n, g, nx, ny, nz, vx, vy, vz, dr, dg, db, sr, sg, sb);
        else
            light_add(m, &L->light[i], 0, n, g, nx, ny, nz, vx, vy, vz, dr, dg, db, sr, sg, sb);
    }
}
PERSP_ISA_VARIANTS(light_soa,
                   (const persp_draw_state *ds, const float *side, int n, const lit_span *g,
                    float *restrict dr, float *restrict dg, float *restrict db, float *restrict sr,
                    float *restrict sg, float *restrict sb),
                   (ds, side, n, g, dr, dg, db, sr, sg, sb))

/* The lower clamp is a float select (a NaN becomes 0), the upper one an
 * integer minimum of the bit patterns, which order non-negative floats as
 * their values (IEEE 754 §3.4); the conversion is a signed one: AVX2 has
 * no float to unsigned conversion. Written as two float selects, GCC
 * pushed the conversion and the shift through both (the bounds convert to
 * constants) and built every channel from three compares, three logic
 * operations and a blend: 17 instructions per 8 pixels where these are 5
 * (it converts before the lower clamp and masks after). Every float gives
 * the channel the float clamps gave (checked on all 2^32). */
static inline uint32_t pack_channel(float c, int shift)
{
    float x = c * 255.0f + 0.5f;
    x = x > 0.0f ? x : 0.0f;
    int32_t bits;
    memcpy(&bits, &x, sizeof bits);
    bits = bits < 0x437f0000 ? bits : 0x437f0000; /* 255.0f */
    memcpy(&x, &bits, sizeof x);
    return (uint32_t)(int32_t)x << shift;
}

/* Combines lighting with the texels per the texture environment
 * ([CS300-TexMap]): replace takes the texel, modulate multiplies the lit
 * diffuse colour (d*) by it and adds the specular highlight (s*), itself
 * multiplied by the texel when the material uses the texture as specular
 * colour too; packed to RGBA8 like pack(). */
static PERSP_ALWAYS_INLINE void combine_soa_body(const persp_draw_state *ds, int n, const float *dr,
                                                 const float *dg, const float *db, const float *sr,
                                                 const float *sg, const float *sb, const uint32_t *texel,
                                                 uint32_t *out)
{
    if (texel && ds->material.env == PERSP_TEXENV_REPLACE) {
        memcpy(out, texel, (size_t)n * sizeof *out);
        return;
    }
    if (!texel) {
        for (int k = 0; k < n; k++)
            out[k] = pack_channel(dr[k] + sr[k], 0) | pack_channel(dg[k] + sg[k], 8) |
                     pack_channel(db[k] + sb[k], 16) | 255u << 24;
        return;
    }
    const float inv = 1.0f / 255.0f;
    const int spec_tex = ds->material.specular_texture >= 0;
    for (int k = 0; k < n; k++) {
        uint32_t p = texel[k];
        float t0 = (float)(p & 255u) * inv, t1 = (float)((p >> 8) & 255u) * inv;
        float t2 = (float)((p >> 16) & 255u) * inv;
        float s0 = spec_tex ? sr[k] * t0 : sr[k], s1 = spec_tex ? sg[k] * t1 : sg[k];
        float s2 = spec_tex ? sb[k] * t2 : sb[k];
        out[k] = pack_channel(dr[k] * t0 + s0, 0) | pack_channel(dg[k] * t1 + s1, 8) |
                 pack_channel(db[k] * t2 + s2, 16) | (p & 0xff000000u);
    }
}
PERSP_ISA_VARIANTS(combine_soa,
                   (const persp_draw_state *ds, int n, const float *dr, const float *dg, const float *db,
                    const float *sr, const float *sg, const float *sb, const uint32_t *texel,
                    uint32_t *out),
                   (ds, n, dr, dg, db, sr, sg, sb, texel, out))

/* ----------------------------------------------------------- barycentrics */

/* Screen-linear weights b1, b2 at the batch's pixels. */
static void bary_linear(const persp_tri *t, const persp_frag_batch *b, float *b1, float *b2)
{
    if (!b->px) {
        double px = b->x0 + 0.5, py = b->y + 0.5;
        double s1 = t->lb1[0] * px + t->lb1[1] * py + t->lb1[2];
        double s2 = t->lb2[0] * px + t->lb2[1] * py + t->lb2[2];
        for (int k = 0; k < b->n; k++) {
            b1[k] = (float)(s1 + k * t->lb1[0]);
            b2[k] = (float)(s2 + k * t->lb2[0]);
        }
        return;
    }
    for (int k = 0; k < b->n; k++) {
        double px = b->px[k] + 0.5, py = b->py[k] + 0.5;
        b1[k] = (float)(t->lb1[0] * px + t->lb1[1] * py + t->lb1[2]);
        b2[k] = (float)(t->lb2[0] * px + t->lb2[1] * py + t->lb2[2]);
    }
}

/* Perspective-correct weights: the draw's shading method on the barycentric
 * rational. Batches with explicit pixel positions (custom traversals) have
 * no span for a span method to work along, so they use the exact form. */
static void bary_perspective(const persp_draw_state *ds, const persp_tri *t,
                             const persp_frag_batch *b, float *b1, float *b2)
{
    if (b->w1) {
        memcpy(b1, b->w1, (size_t)b->n * sizeof *b1);
        memcpy(b2, b->w2, (size_t)b->n * sizeof *b2);
        return;
    }
    if (!b->px) {
        ds->shade_method.m->span(&t->bary, &ds->shade_method.params, NULL, b->x0, b->y, b->n, b1,
                                 b2, NULL);
        return;
    }
    for (int k = 0; k < b->n; k++) {
        double s1, s2;
        persp__rational_eval(&t->bary, b->px[k], b->py[k], &s1, &s2);
        b1[k] = (float)s1;
        b2[k] = (float)s2;
    }
}

static void bary_for(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                     float *b1, float *b2)
{
    if (ds->shade_method.m)
        bary_perspective(ds, t, b, b1, b2);
    else
        bary_linear(t, b, b1, b2);
}

static void interp3(const persp_tri *t, int attr, float b1, float b2, float out[3])
{
    float b0 = 1.0f - b1 - b2;
    for (int c = 0; c < 3; c++)
        out[c] = b0 * t->vattr[0][attr + c] + b1 * t->vattr[1][attr + c] + b2 * t->vattr[2][attr + c];
}

/* interp3 for a span, one output array per component. */
static void interp_soa(const persp_tri *t, int attr, int n, const float *b1, const float *b2, float *o0,
                       float *o1, float *o2)
{
    float *o[3] = {o0, o1, o2};
    for (int c = 0; c < 3; c++) {
        const float v0 = t->vattr[0][attr + c], v1 = t->vattr[1][attr + c], v2 = t->vattr[2][attr + c];
        float *restrict oc = o[c];
        for (int k = 0; k < n; k++) {
            float b0 = 1.0f - b1[k] - b2[k];
            oc[k] = b0 * v0 + b1[k] * v1 + b2[k] * v2;
        }
    }
}

/* normalize3 for a span of vectors. */
static void normalize_soa(int n, float *restrict x, float *restrict y, float *restrict z)
{
    for (int k = 0; k < n; k++) {
        float l = sqrtf(x[k] * x[k] + y[k] * y[k] + z[k] * z[k]);
        float d = l > 0.0f ? l : 1.0f;
        x[k] = l > 0.0f ? x[k] / d : x[k];
        y[k] = l > 0.0f ? y[k] / d : y[k];
        z[k] = l > 0.0f ? z[k] / d : z[k];
    }
}

static void normalize3(float v[3])
{
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.0f) v[0] /= l, v[1] /= l, v[2] /= l;
}

/* ------------------------------------------------------------ span shaders */

static void shade_replace(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)ds, (void)t, (void)q;
    memcpy(out, texel, (size_t)b->n * sizeof *out);
}

/* Untextured, unlit: the vertex colour, interpolated perspective-correctly
 * as OpenGL does for varyings, times the material's diffuse colour. */
static void shade_vertex_color(const persp_draw_state *ds, const persp_tri *t,
                               const persp_frag_batch *b, const float *q, const uint32_t *texel,
                               uint32_t *out)
{
    (void)q, (void)texel;
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    bary_perspective(ds, t, b, b1, b2);
    for (int k = 0; k < b->n; k++) {
        float c[4], a[3];
        interp3(t, PERSP_A_R, b1[k], b2[k], c);
        float b0 = 1.0f - b1[k] - b2[k];
        c[3] = b0 * t->vattr[0][PERSP_A_A] + b1[k] * t->vattr[1][PERSP_A_A] + b2[k] * t->vattr[2][PERSP_A_A];
        for (int i = 0; i < 3; i++) a[i] = c[i] * ds->material.diffuse[i];
        float o[4] = {a[0], a[1], a[2], c[3]};
        out[k] = pack(o);
    }
}

/* Textured, unlit material (persp_material.unlit): the vertex colour
 * times the material's diffuse colour times the texel, without lighting
 * (glTF KHR_materials_unlit: base colour factor × texture × COLOR_0). */
static void shade_unlit_modulate(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                                 const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    bary_perspective(ds, t, b, b1, b2);
    const float inv = 1.0f / 255.0f;
    for (int k = 0; k < b->n; k++) {
        float c[3];
        interp3(t, PERSP_A_R, b1[k], b2[k], c);
        const uint32_t p = texel[k];
        const float tx[3] = {(float)(p & 255u) * inv, (float)((p >> 8) & 255u) * inv,
                             (float)((p >> 16) & 255u) * inv};
        out[k] = pack_channel(c[0] * ds->material.diffuse[0] * tx[0], 0) |
                 pack_channel(c[1] * ds->material.diffuse[1] * tx[1], 8) |
                 pack_channel(c[2] * ds->material.diffuse[2] * tx[2], 16) | (p & 0xff000000u);
    }
}

float persp__shade_light_side(const persp_tri *t)
{
    float d = 0.0f;
    for (int c = 0; c < 3; c++) {
        float n = t->vattr[0][PERSP_A_NX + c] + t->vattr[1][PERSP_A_NX + c] + t->vattr[2][PERSP_A_NX + c];
        float e = t->vattr[0][PERSP_A_EX + c] + t->vattr[1][PERSP_A_EX + c] + t->vattr[2][PERSP_A_EX + c];
        d += n * e;
    }
    return d > 0.0f ? -1.0f : 1.0f;
}

/* Gouraud: colours lit per vertex (persp__shade_vertices), interpolated with
 * screen-linear (classical) or perspective-correct (§4.2) weights. The
 * vertex colour carries ambient + diffuse + specular, so modulate scales all. */
/* Gouraud colour modulating the texels: interp_soa and combine_soa's
 * texel path in one loop, the same operations in the same order, but for
 * the zero specular the combine adds (the specular term of a Gouraud
 * vertex colour is in the colour): x + 0 differs from x only where x is
 * −0, whose channel is 0 either way. whole: the loop runs over whole
 * groups of PERSP_SHADE_GROUP lanes, past n (see
 * persp__shade_gouraud_lanes). */
static PERSP_ALWAYS_INLINE void gouraud_pixels(const persp_tri *t, int attr, int n, const float *restrict b1,
                                               const float *restrict b2, const uint32_t *restrict texel,
                                               uint32_t *restrict out, const int whole)
{
    const float r0 = t->vattr[0][attr], r1 = t->vattr[1][attr], r2 = t->vattr[2][attr];
    const float g0 = t->vattr[0][attr + 1], g1 = t->vattr[1][attr + 1], g2 = t->vattr[2][attr + 1];
    const float c0 = t->vattr[0][attr + 2], c1 = t->vattr[1][attr + 2], c2 = t->vattr[2][attr + 2];
    const float inv = 1.0f / 255.0f;
    const int step = whole ? PERSP_SHADE_GROUP : 1;
    for (int k0 = 0; k0 < n; k0 += step)
        for (int j = 0; j < step; j++) {
            const int k = k0 + j;
            const float w0 = 1.0f - b1[k] - b2[k];
            const float cr = w0 * r0 + b1[k] * r1 + b2[k] * r2;
            const float cg = w0 * g0 + b1[k] * g1 + b2[k] * g2;
            const float cb = w0 * c0 + b1[k] * c1 + b2[k] * c2;
            const uint32_t p = texel[k];
            const float t0 = (float)(p & 255u) * inv, t1 = (float)((p >> 8) & 255u) * inv;
            const float t2 = (float)((p >> 16) & 255u) * inv;
            out[k] = pack_channel(cr * t0, 0) | pack_channel(cg * t1, 8) | pack_channel(cb * t2, 16) |
                     (p & 0xff000000u);
        }
}
static PERSP_ALWAYS_INLINE void gouraud_modulate_body(const persp_tri *t, int attr, int n, const float *b1,
                                                      const float *b2, const uint32_t *texel, uint32_t *out)
{
    gouraud_pixels(t, attr, n, b1, b2, texel, out, 0);
}
PERSP_ISA_VARIANTS(gouraud_modulate,
                   (const persp_tri *t, int attr, int n, const float *b1, const float *b2,
                    const uint32_t *texel, uint32_t *out),
                   (t, attr, n, b1, b2, texel, out))
static PERSP_ALWAYS_INLINE void gouraud_whole_body(const persp_tri *t, int attr, int n, const float *b1,
                                                   const float *b2, const uint32_t *texel, uint32_t *out)
{
    gouraud_pixels(t, attr, n, b1, b2, texel, out, 1);
}
PERSP_ISA_VARIANTS(gouraud_whole,
                   (const persp_tri *t, int attr, int n, const float *b1, const float *b2,
                    const uint32_t *texel, uint32_t *out),
                   (t, attr, n, b1, b2, texel, out))

void persp__shade_gouraud_lanes(const persp_draw_state *ds, const persp_tri *t, int n, const float *w1,
                                const float *w2, const uint32_t *texel, uint32_t *out)
{
    gouraud_whole(ds->isa, t, t->light_side < 0.0f ? PERSP_A_BR : PERSP_A_R, n, w1, w2, texel, out);
}

static void shade_gouraud(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    /* Front or back colour by the triangle's facing (light_side), as
     * OpenGL's two-sided lighting picks them per polygon. */
    const int attr = t->light_side < 0.0f ? PERSP_A_BR : PERSP_A_R;
    if (texel && ds->material.env != PERSP_TEXENV_REPLACE) {
        if (b->w1) {
            gouraud_modulate(ds->isa, t, attr, b->n, b->w1, b->w2, texel, out);
        } else {
            bary_for(ds, t, b, b1, b2);
            gouraud_modulate(ds->isa, t, attr, b->n, b1, b2, texel, out);
        }
        return;
    }
    bary_for(ds, t, b, b1, b2);
    float c[3][PERSP_SPAN_MAX], zero[PERSP_SPAN_MAX];
    interp_soa(t, attr, b->n, b1, b2, c[0], c[1], c[2]);
    for (int k = 0; k < b->n; k++) zero[k] = 0.0f;
    combine_soa(ds->isa, ds, b->n, c[0], c[1], c[2], zero, zero, zero, texel, out);
}

void persp__slerp_init(persp_slerp *s, const float na[3], const float nb[3], double hbar)
{
    double a[3] = {na[0], na[1], na[2]}, b[3] = {nb[0], nb[1], nb[2]};
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    memset(s, 0, sizeof *s);
    s->hbar = hbar;
    if (!(la > 0.0) || !(lb > 0.0)) {
        s->straight = 1;
        s->na[2] = 1.0;
        return;
    }
    for (int i = 0; i < 3; i++) a[i] /= la, b[i] /= lb;
    memcpy(s->na, a, sizeof a);
    double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    c = c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c;
    double k[3] = {b[0] - c * a[0], b[1] - c * a[1], b[2] - c * a[2]};
    double kl = sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
    s->psi = acos(c);
    if (!(s->psi > 1e-7) || !(kl > 1e-12)) {
        s->straight = 1;
        return;
    }
    for (int i = 0; i < 3; i++) s->nk[i] = k[i] / kl;
    s->inv_sin_psi = 1.0 / sin(s->psi);
    s->ctg_psi = cos(s->psi) * s->inv_sin_psi;
}

void persp__slerp_eval(const persp_slerp *s, double tv, int perspective, float out[3])
{
    if (s->straight || !(tv > 0.0)) {
        for (int i = 0; i < 3; i++) out[i] = (float)s->na[i];
        return;
    }
    double b = perspective ? s->ctg_psi + s->hbar * (1.0 / tv - 1.0) * s->inv_sin_psi
                           : cos(tv * s->psi) / sin(tv * s->psi);
    double r = 1.0 / sqrt(1.0 + b * b);
    for (int i = 0; i < 3; i++) out[i] = (float)((s->na[i] * b + s->nk[i]) * r);
}

/* Exact perspective-correct weights in double (Heckbert's form along the
 * span); used for eye positions under screen-linear normal schemes. */
static void bary_exact(const persp_tri *t, const persp_frag_batch *b, float *b1, float *b2)
{
    if (b->px) {
        for (int k = 0; k < b->n; k++) {
            double s1, s2;
            persp__rational_eval(&t->bary, b->px[k], b->py[k], &s1, &s2);
            b1[k] = (float)s1, b2[k] = (float)s2;
        }
        return;
    }
    persp_span_rat s;
    persp__span_rat_init(&t->bary, b->x0, b->y, &s);
    for (int k = 0; k < b->n; k++) {
        double s1, s2;
        persp__span_rat_at(&s, (double)k, &s1, &s2);
        b1[k] = (float)s1, b2[k] = (float)s2;
    }
}

/* Flat: the face normal, lit at the centroid. */
static void flat_normals(const persp_tri *t, int n, lit_span *g)
{
    const float *p0 = &t->vattr[0][PERSP_A_EX], *p1 = &t->vattr[1][PERSP_A_EX],
                *p2 = &t->vattr[2][PERSP_A_EX];
    float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    float f[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                  e1[0] * e2[1] - e1[1] * e2[0]};
    normalize3(f);
    float c[3] = {(p0[0] + p1[0] + p2[0]) / 3.0f, (p0[1] + p1[1] + p2[1]) / 3.0f,
                  (p0[2] + p1[2] + p2[2]) / 3.0f};
    for (int k = 0; k < n; k++) {
        g->nx[k] = f[0], g->ny[k] = f[1], g->nz[k] = f[2];
        g->ex[k] = c[0], g->ey[k] = c[1], g->ez[k] = c[2];
    }
}

/* Phong: normals interpolated with the mode's weights (screen-linear, exact
 * t_w or its polynomial approximations, §4.3) and renormalised. The eye
 * position is always perspective-correct (where the pixel's ray meets the
 * triangle's plane) so that modes differ only in the normal scheme. */
PERSP_SIMD_CLONES static void phong_normals(const persp_draw_state *ds, const persp_tri *t,
                                            const persp_frag_batch *b, lit_span *g)
{
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    const int lanes = span_lanes(b->n);
    bary_for(ds, t, b, b1, b2);
    for (int k = b->n; k < lanes; k++) b1[k] = b2[k] = 0.0f;
    interp_soa(t, PERSP_A_NX, lanes, b1, b2, g->nx, g->ny, g->nz);
    normalize_soa(lanes, g->nx, g->ny, g->nz);
    if (!ds->shade_method.m || ds->shading != PERSP_SHADING_PHONG_PC) {
        bary_exact(t, b, b1, b2);
        for (int k = b->n; k < lanes; k++) b1[k] = b2[k] = 0.0f;
    }
    interp_soa(t, PERSP_A_EX, lanes, b1, b2, g->ex, g->ey, g->ez);
    if (ds->color_material) interp_soa(t, PERSP_A_R, lanes, b1, b2, g->cr, g->cg, g->cb);
}

/* Spherical-angular normals along the span (§4.3). The end normals are
 * exact (perspective-correct weights at the span's first and last pixels,
 * normalised); ħ = z_b/z_a = q_a/q_b from the 1/w plane. Batches without a
 * span (custom traversals) or of one pixel get exact per-pixel normals. */
static void slerp_normals(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          int perspective, lit_span *g)
{
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    bary_exact(t, b, b1, b2);
    interp_soa(t, PERSP_A_EX, b->n, b1, b2, g->ex, g->ey, g->ez);
    if (ds->color_material) interp_soa(t, PERSP_A_R, b->n, b1, b2, g->cr, g->cg, g->cb);
    if (b->px || b->n < 2) {
        interp_soa(t, PERSP_A_NX, b->n, b1, b2, g->nx, g->ny, g->nz);
        normalize_soa(b->n, g->nx, g->ny, g->nz);
        return;
    }
    const int last = b->n - 1;
    float na[3], nb[3];
    interp3(t, PERSP_A_NX, b1[0], b2[0], na);
    interp3(t, PERSP_A_NX, b1[last], b2[last], nb);
    double px = b->x0 + 0.5, py = b->y + 0.5;
    double qa = t->rat.g * px + t->rat.h * py + t->rat.i;
    double qb = qa + t->rat.g * last;
    /* The end normals are blends of unit vertex normals, so |na| ≠ |nb| in
     * general, while the cotangent form assumes unit ends. The exact normal
     * normalise(na + t_w·(nb − na)) = normalise((1 − t_w)|na|·n̂a + t_w|nb|·n̂b)
     * has (1 − t')/t' = ħ·(|na|/|nb|)·(1/t_v − 1) along the unit arc, so
     * folding |na|/|nb| into ħ keeps the form exact (§4.3 with unit ends is
     * the case |na| = |nb|). */
    double la = sqrt((double)na[0] * na[0] + (double)na[1] * na[1] + (double)na[2] * na[2]);
    double lb = sqrt((double)nb[0] * nb[0] + (double)nb[1] * nb[1] + (double)nb[2] * nb[2]);
    double hbar = qa / qb;
    if (perspective && la > 0.0 && lb > 0.0) hbar *= la / lb;
    persp_slerp sl;
    persp__slerp_init(&sl, na, nb, hbar);
    for (int k = 0; k < b->n; k++) {
        float nk[3];
        persp__slerp_eval(&sl, (double)k / last, perspective, nk);
        g->nx[k] = nk[0], g->ny[k] = nk[1], g->nz[k] = nk[2];
    }
}

int persp__shade_normals(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                         float (*nrm)[3], float (*eye)[3])
{
    lit_span g;
    switch (ds->shading) {
    case PERSP_SHADING_FLAT: flat_normals(t, b->n, &g); break;
    case PERSP_SHADING_PHONG:
    case PERSP_SHADING_PHONG_PC:
    case PERSP_SHADING_PHONG_PC_QUAD:
    case PERSP_SHADING_PHONG_PC_PWQUAD:
    case PERSP_SHADING_PHONG_PC_CUBIC: phong_normals(ds, t, b, &g); break;
    case PERSP_SHADING_PHONG_SLERP: slerp_normals(ds, t, b, 1, &g); break;
    case PERSP_SHADING_PHONG_SLERP_SCREEN: slerp_normals(ds, t, b, 0, &g); break;
    default: return 0;
    }
    for (int k = 0; k < b->n; k++) {
        nrm[k][0] = g.nx[k], nrm[k][1] = g.ny[k], nrm[k][2] = g.nz[k];
        eye[k][0] = g.ex[k], eye[k][1] = g.ey[k], eye[k][2] = g.ez[k];
    }
    return 1;
}

/* Lights, colours and combines lanes [0, n) whose sides (persp_tri.light_side
 * of each lane's triangle) are given per lane, for all span_lanes(n). */
static void light_lanes(const persp_draw_state *ds, const float *side, int n, lit_span *g,
                        const uint32_t *texel, uint32_t *out)
{
    float c[6][PERSP_LANE_MAX];
    pad_lit_span(g, n);
    light_soa(ds->isa, ds, side, n, g, c[0], c[1], c[2], c[3], c[4], c[5]);
    if (ds->color_material)
        for (int k = 0; k < n; k++) c[0][k] *= g->cr[k], c[1][k] *= g->cg[k], c[2][k] *= g->cb[k];
    combine_soa(ds->isa, ds, n, c[0], c[1], c[2], c[3], c[4], c[5], texel, out);
}

static void light_span(const persp_draw_state *ds, const persp_tri *t, int n, lit_span *g,
                       const uint32_t *texel, uint32_t *out)
{
    float side[PERSP_LANE_MAX];
    for (int k = 0; k < span_lanes(n); k++) side[k] = t->light_side;
    light_lanes(ds, side, n, g, texel, out);
}

/* phong_normals with perspective-correct weights given (phong-pc); a
 * variant per instruction set for its interpolation and normalisation
 * loops. */
static PERSP_ALWAYS_INLINE void phong_lanes_body(const persp_draw_state *ds, const persp_tri *t, int n,
                                                 const float *w1, const float *w2, const uint32_t *texel,
                                                 uint32_t *out)
{
    float b1[PERSP_LANE_MAX], b2[PERSP_LANE_MAX];
    const int lanes = span_lanes(n);
    memcpy(b1, w1, (size_t)n * sizeof *b1);
    memcpy(b2, w2, (size_t)n * sizeof *b2);
    for (int k = n; k < lanes; k++) b1[k] = b2[k] = 0.0f;
    lit_span g;
    interp_soa(t, PERSP_A_NX, lanes, b1, b2, g.nx, g.ny, g.nz);
    normalize_soa(lanes, g.nx, g.ny, g.nz);
    interp_soa(t, PERSP_A_EX, lanes, b1, b2, g.ex, g.ey, g.ez);
    if (ds->color_material) interp_soa(t, PERSP_A_R, lanes, b1, b2, g.cr, g.cg, g.cb);
    light_span(ds, t, n, &g, texel, out);
}
PERSP_ISA_VARIANTS(phong_lanes,
                   (const persp_draw_state *ds, const persp_tri *t, int n, const float *w1, const float *w2,
                    const uint32_t *texel, uint32_t *out),
                   (ds, t, n, w1, w2, texel, out))

void persp__shade_phong_lanes(const persp_draw_state *ds, const persp_tri *t, int n, const float *w1,
                              const float *w2, const uint32_t *texel, uint32_t *out)
{
    phong_lanes(ds->isa, ds, t, n, w1, w2, texel, out);
}

/* phong_lanes for a batch whose lanes come from several triangles
 * (segments): each segment's attributes are interpolated into its lanes,
 * then the whole batch is padded to whole vectors, normalised and lit at
 * once, so that a segment of one or two pixels does not light a vector of
 * 16 by itself (on the 2M-triangle torus lighting was a fifth of a frame,
 * mostly padding). The same operations per lane as phong_lanes. */
static PERSP_ALWAYS_INLINE void phong_segments_body(const persp_draw_state *ds, int nseg, const int *seg_start,
                                                    const persp_tri *const *seg_tri, const float *w1,
                                                    const float *w2, const uint32_t *texel, uint32_t *out)
{
    lit_span g;
    float side[PERSP_LANE_MAX];
    for (int s = 0; s < nseg; s++) {
        const persp_tri *t = seg_tri[s];
        const int s0 = seg_start[s], m = seg_start[s + 1] - s0;
        interp_soa(t, PERSP_A_NX, m, w1 + s0, w2 + s0, g.nx + s0, g.ny + s0, g.nz + s0);
        interp_soa(t, PERSP_A_EX, m, w1 + s0, w2 + s0, g.ex + s0, g.ey + s0, g.ez + s0);
        if (ds->color_material) interp_soa(t, PERSP_A_R, m, w1 + s0, w2 + s0, g.cr + s0, g.cg + s0, g.cb + s0);
        for (int k = s0; k < s0 + m; k++) side[k] = t->light_side;
    }
    const int n = seg_start[nseg], lanes = span_lanes(n);
    for (int k = n; k < lanes; k++) {
        g.nx[k] = g.ny[k] = g.nz[k] = 0.0f;
        side[k] = 1.0f;
    }
    normalize_soa(lanes, g.nx, g.ny, g.nz);
    light_lanes(ds, side, n, &g, texel, out);
}
PERSP_ISA_VARIANTS(phong_segments,
                   (const persp_draw_state *ds, int nseg, const int *seg_start,
                    const persp_tri *const *seg_tri, const float *w1, const float *w2,
                    const uint32_t *texel, uint32_t *out),
                   (ds, nseg, seg_start, seg_tri, w1, w2, texel, out))

void persp__shade_phong_segments(const persp_draw_state *ds, int nseg, const int *seg_start,
                                 const persp_tri *const *seg_tri, const float *w1, const float *w2,
                                 const uint32_t *texel, uint32_t *out)
{
    phong_segments(ds->isa, ds, nseg, seg_start, seg_tri, w1, w2, texel, out);
}

/* Flat: one lighting evaluation per triangle. */
static void shade_flat(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                       const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    lit_span g;
    float diff[3], spec[3];
    flat_normals(t, 1, &g);
    const float f[3] = {g.nx[0], g.ny[0], g.nz[0]}, c[3] = {g.ex[0], g.ey[0], g.ez[0]};
    light_point(ds, f, c, f[0] * c[0] + f[1] * c[1] + f[2] * c[2] > 0.0f ? -1.0f : 1.0f, diff, spec);
    /* One colour per face as one normal: the corners' mean. */
    if (ds->color_material)
        for (int k = 0; k < 3; k++)
            diff[k] *= (t->vattr[0][PERSP_A_R + k] + t->vattr[1][PERSP_A_R + k] + t->vattr[2][PERSP_A_R + k]) / 3.0f;
    float d[6][PERSP_SPAN_MAX];
    for (int k = 0; k < b->n; k++) {
        d[0][k] = diff[0], d[1][k] = diff[1], d[2][k] = diff[2];
        d[3][k] = spec[0], d[4][k] = spec[1], d[5][k] = spec[2];
    }
    combine_soa(ds->isa, ds, b->n, d[0], d[1], d[2], d[3], d[4], d[5], texel, out);
}

static void shade_phong(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                        const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    lit_span g;
    phong_normals(ds, t, b, &g);
    light_span(ds, t, b->n, &g, texel, out);
}

static void shade_slerp(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                        const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    lit_span g;
    slerp_normals(ds, t, b, 1, &g);
    light_span(ds, t, b->n, &g, texel, out);
}

static void shade_slerp_screen(const persp_draw_state *ds, const persp_tri *t,
                               const persp_frag_batch *b, const float *q, const uint32_t *texel,
                               uint32_t *out)
{
    (void)q;
    lit_span g;
    slerp_normals(ds, t, b, 0, &g);
    light_span(ds, t, b->n, &g, texel, out);
}

/* The method computing perspective-correct weights for each mode (NULL:
 * screen-linear). Approximations of t_w are the span methods themselves. */
static const char *shade_method_spec(persp_shading s)
{
    switch (s) {
    case PERSP_SHADING_NONE:
    case PERSP_SHADING_GOURAUD_PC:
    case PERSP_SHADING_PHONG_PC:
    case PERSP_SHADING_PHONG_SLERP:
    case PERSP_SHADING_PHONG_SLERP_SCREEN: return "exact";
    case PERSP_SHADING_PHONG_PC_QUAD: return "quadratic";
    case PERSP_SHADING_PHONG_PC_PWQUAD: return "quadratic-pw";
    case PERSP_SHADING_PHONG_PC_CUBIC: return "cubic";
    default: return NULL;
    }
}

/* The samplers' variant is timed on their spans (texture/fastspan.c); the
 * lighting loops' apart, since the two need not agree: on the Zen 5 VM of
 * docs/PERFORMANCE.md AVX-512's bilinear spans take 1.2-1.3 times as long
 * as AVX2's, while its lighting loops lit the 2k and 20k tori's phong-pc
 * frames 17-18 % faster with the samplers at AVX2. So light_soa, the
 * per-pixel Blinn-Phong of both per-pixel modes and of the vertices, is
 * timed here at both widths on one span of lanes with a point light, a
 * directional one and a specular highlight (the benchmark scenes'
 * lights): a few spans each, interleaved, best of several rounds, well
 * under a millisecond; AVX-512 must win by 10 %, as for the samplers. The
 * images are the same either way. */
int persp__shade_auto_isa(void)
{
    const int isa = persp__cpu_isa();
#if PERSP_HAVE_ISA_VARIANTS
    if (isa != PERSP_ISA_AVX512) return isa;
    enum { LANES = 64, ROUNDS = 11, SPANS = 6 };
    persp_draw_state ds;
    memset(&ds, 0, sizeof ds);
    for (int c = 0; c < 3; c++) {
        ds.material.ambient[c] = 0.2f;
        ds.material.diffuse[c] = 0.8f;
        ds.material.specular[c] = 0.6f;
        ds.lighting.ambient[c] = 0.15f;
    }
    ds.material.shininess = 40.0f;
    ds.lighting.count = 2;
    ds.lighting.light[0] =
        (persp_eye_light){PERSP_LIGHT_POINT, {1.0f, 1.5f, 1.0f}, {1.0f, 0.97f, 0.9f}, {1.0f, 0.0f, 0.01f}};
    ds.lighting.light[1] =
        (persp_eye_light){PERSP_LIGHT_DIRECTIONAL, {0.87f, -0.43f, -0.26f}, {0.25f, 0.3f, 0.4f}, {1.0f, 0.0f, 0.0f}};
    lit_span g;
    float side[LANES], d[6][LANES];
    for (int k = 0; k < LANES; k++) {
        const float a = 0.05f * (float)k;
        g.nx[k] = 0.3f * a - 0.5f, g.ny[k] = 0.6f - 0.2f * a, g.nz[k] = 0.7f;
        g.ex[k] = 0.02f * (float)k - 0.6f, g.ey[k] = 0.3f, g.ez[k] = -2.0f;
        side[k] = 1.0f;
    }
    double best[2] = {1e30, 1e30};
    for (int r = 0; r < ROUNDS; r++)
        for (int w = 0; w < 2; w++) {
            const double t0 = persp__now_seconds();
            for (int i = 0; i < SPANS; i++)
                light_soa(w ? PERSP_ISA_AVX512 : PERSP_ISA_AVX2, &ds, side, LANES, &g, d[0], d[1], d[2], d[3], d[4],
                          d[5]);
            const double t = persp__now_seconds() - t0;
            best[w] = t < best[w] ? t : best[w];
        }
    return best[1] < 0.9 * best[0] ? PERSP_ISA_AVX512 : PERSP_ISA_AVX2;
#else
    return isa;
#endif
}

persp_status persp__shade_resolve(persp_context *ctx, persp_draw_state *ds)
{
    memset(&ds->shade_method, 0, sizeof ds->shade_method);
    /* The lighting loops take the context's variant for them
     * (persp_context_desc.simd, or for AUTO timed when a frame begins,
     * persp__shade_auto_isa); before any frame, the widest this CPU has. */
    ds->isa = ctx && ctx->shade_isa >= 0 ? ctx->shade_isa : persp__cpu_isa();
    if (ds->shading == PERSP_SHADING_DEFAULT) ds->shading = PERSP_SHADING_NONE;
    const char *spec = shade_method_spec(ds->shading);
    if (spec) {
        persp_status st = persp__method_resolve(ctx, spec, &ds->shade_method);
        if (st != PERSP_OK)
            return persp__fail(ctx, PERSP_ERR_UNAVAILABLE, "shading '%s' needs the method '%s'",
                                      persp_shading_name(ds->shading), spec);
        if (ds->shade_method.m->prepare || !ds->shade_method.m->span)
            return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                                      "shading '%s': method '%s' needs per-triangle preparation",
                                      persp_shading_name(ds->shading), spec);
    }
    /* An unlit material tinted by its colour or its vertices' multiplies
     * the texel; untinted, the texel is the colour. */
    const float *kd = ds->material.diffuse;
    const int tinted = ds->material.unlit && ds->material.env == PERSP_TEXENV_MODULATE &&
                       (ds->color_material || kd[0] != 1.0f || kd[1] != 1.0f || kd[2] != 1.0f);
    ds->shade_is_texel =
        ds->tex != NULL && !tinted &&
        (ds->shading == PERSP_SHADING_NONE || ds->material.env == PERSP_TEXENV_REPLACE);
    switch (ds->shading) {
    case PERSP_SHADING_NONE:
        ds->shade = !ds->tex ? shade_vertex_color : tinted ? shade_unlit_modulate : shade_replace;
        break;
    case PERSP_SHADING_FLAT: ds->shade = shade_flat; break;
    case PERSP_SHADING_GOURAUD:
    case PERSP_SHADING_GOURAUD_PC: ds->shade = shade_gouraud; break;
    case PERSP_SHADING_PHONG:
    case PERSP_SHADING_PHONG_PC:
    case PERSP_SHADING_PHONG_PC_QUAD:
    case PERSP_SHADING_PHONG_PC_PWQUAD:
    case PERSP_SHADING_PHONG_PC_CUBIC: ds->shade = shade_phong; break;
    case PERSP_SHADING_PHONG_SLERP: ds->shade = shade_slerp; break;
    case PERSP_SHADING_PHONG_SLERP_SCREEN: ds->shade = shade_slerp_screen; break;
    default:
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "unknown shading mode %d", (int)ds->shading);
    }
    return PERSP_OK;
}

void persp__light_vertices(const persp_draw_state *ds, int n, const persp_light_in *in, float *const front[3],
                           float *const back[3])
{
    /* Through the span lighting (light_soa: light_point's operations in
     * the same order), so that a vertex gets the same colour whether it is
     * lit in a block of the vertex stage or alone at set-up. */
    if (n <= 0 || n > PERSP_SPAN_MAX) return;
    lit_span s;
    for (int k = 0; k < n; k++) {
        /* normalize3's operations, with its branch as selects. */
        const float x = in->n[0][k], y = in->n[1][k], z = in->n[2][k];
        const float l = sqrtf(x * x + y * y + z * z);
        const float d = l > 0.0f ? l : 1.0f;
        s.nx[k] = l > 0.0f ? x / d : x;
        s.ny[k] = l > 0.0f ? y / d : y;
        s.nz[k] = l > 0.0f ? z / d : z;
        s.ex[k] = in->e[0][k], s.ey[k] = in->e[1][k], s.ez[k] = in->e[2][k];
    }
    pad_lit_span(&s, n);
    for (int side = 0; side < 2; side++) {
        float *const *out = side ? back : front;
        if (!out) continue;
        float sides[PERSP_SPAN_MAX], d[6][PERSP_SPAN_MAX];
        for (int k = 0; k < span_lanes(n); k++) sides[k] = side ? -1.0f : 1.0f;
        light_soa(ds->isa, ds, sides, n, &s, d[0], d[1], d[2], d[3], d[4], d[5]);
        if (ds->color_material)
            for (int k = 0; k < n; k++) d[0][k] *= in->c[0][k], d[1][k] *= in->c[1][k], d[2][k] *= in->c[2][k];
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < n; k++) out[c][k] = d[c][k] + d[3 + c][k];
    }
}

void persp__shade_vertices(const persp_draw_state *ds, persp_clipvert *v, size_t n)
{
    if (!persp__shade_is_gouraud(ds)) return;
    float a[9][PERSP_SPAN_MAX], out[6][PERSP_SPAN_MAX];
    const persp_light_in in = {{a[0], a[1], a[2]}, {a[3], a[4], a[5]}, {a[6], a[7], a[8]}};
    for (size_t i0 = 0; i0 < n; i0 += PERSP_SPAN_MAX) {
        const int m = (int)(n - i0 < PERSP_SPAN_MAX ? n - i0 : PERSP_SPAN_MAX);
        for (int k = 0; k < m; k++) {
            const float *at = v[i0 + (size_t)k].attr;
            for (int c = 0; c < 3; c++) {
                a[c][k] = at[PERSP_A_NX + c];
                a[3 + c][k] = at[PERSP_A_EX + c];
                a[6 + c][k] = at[PERSP_A_R + c];
            }
        }
        float *const front[3] = {out[0], out[1], out[2]}, *const back[3] = {out[3], out[4], out[5]};
        persp__light_vertices(ds, m, &in, front, back);
        for (int k = 0; k < m; k++)
            for (int c = 0; c < 3; c++) {
                v[i0 + (size_t)k].attr[PERSP_A_R + c] = out[c][k];
                v[i0 + (size_t)k].attr[PERSP_A_BR + c] = out[3 + c][k];
            }
        for (int k = 0; k < m; k++) v[i0 + (size_t)k].attr[PERSP_A_A] = 1.0f;
    }
}
