/*
 * Shading modes (seed 000 §4.2–4.3, seed 003) and the span shaders they
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

static void unpack(uint32_t p, float c[4])
{
    for (int k = 0; k < 4; k++) c[k] = (float)((p >> (8 * k)) & 255u) * (1.0f / 255.0f);
}

/* Blinn–Phong at eye-space point e with unit normal n. Writes the ambient +
 * diffuse part (which a texture modulates) and the specular part. */
static void light_point(const persp_draw_state *ds, const float n_in[3], const float e[3], float side,
                        float diff[3], float spec[3])
{
    const persp_material *m = &ds->material;
    const persp_lighting *L = &ds->lighting;
    /* Two-sided lighting: side = −1 lights the other face (see face_side). */
    float n[3] = {side * n_in[0], side * n_in[1], side * n_in[2]};
    float vlen = sqrtf(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    float v[3] = {0.0f, 0.0f, 1.0f};
    if (vlen > 0.0f) v[0] = -e[0] / vlen, v[1] = -e[1] / vlen, v[2] = -e[2] / vlen;
    for (int c = 0; c < 3; c++) {
        diff[c] = L->ambient[c] * m->ambient[c];
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
            if (dist > 0.0f) d[0] /= dist, d[1] /= dist, d[2] /= dist;
            float den = l->atten[0] + l->atten[1] * dist + l->atten[2] * dist * dist;
            att = den > 0.0f ? 1.0f / den : 1.0f;
        }
        float ndl = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        if (ndl <= 0.0f) continue;
        float h[3] = {d[0] + v[0], d[1] + v[1], d[2] + v[2]};
        float hl = sqrtf(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        float ndh = hl > 0.0f ? (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hl : 0.0f;
        float sp = ndh > 0.0f && m->shininess > 0.0f ? powf(ndh, m->shininess) : 0.0f;
        for (int c = 0; c < 3; c++) {
            diff[c] += att * l->color[c] * m->diffuse[c] * ndl;
            spec[c] += att * l->color[c] * m->specular[c] * sp;
        }
    }
}

/* Combines lighting with the texel per the texture environment (seed 002):
 * replace takes the texel, modulate multiplies the lit diffuse colour by it
 * and adds the specular highlight, itself multiplied by the texel when the
 * material uses the texture as specular colour too. */
static uint32_t combine(const persp_draw_state *ds, const float diff[3], const float spec[3],
                        const uint32_t *texel, int k)
{
    float c[4] = {diff[0] + spec[0], diff[1] + spec[1], diff[2] + spec[2], 1.0f};
    if (texel) {
        float t[4];
        unpack(texel[k], t);
        if (ds->material.env == PERSP_TEXENV_REPLACE) return texel[k];
        const int spec_tex = ds->material.specular_texture >= 0;
        for (int i = 0; i < 3; i++) c[i] = diff[i] * t[i] + (spec_tex ? spec[i] * t[i] : spec[i]);
        c[3] = t[3];
    }
    return pack(c);
}

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

/* Two-sided lighting decided once per triangle, as OpenGL picks the front
 * or back colour by the polygon's facing: −1 when the triangle's vertex
 * normals, summed, face away from the eye at its centroid. A per-pixel test
 * of N·E would flip the smooth normals of front faces near silhouettes
 * (where they turn away from the eye) and light a rim on the dark side. */
static float face_side(const persp_tri *t)
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
static void shade_gouraud(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    bary_for(ds, t, b, b1, b2);
    const float zero[3] = {0, 0, 0};
    /* Front or back colour by the triangle's facing (face_side), as
     * OpenGL's two-sided lighting picks them per polygon. */
    const int attr = face_side(t) < 0.0f ? PERSP_A_BR : PERSP_A_R;
    for (int k = 0; k < b->n; k++) {
        float c[3];
        interp3(t, attr, b1[k], b2[k], c);
        out[k] = combine(ds, c, zero, texel, k);
    }
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
static void flat_normals(const persp_tri *t, int n, float (*nrm)[3], float (*eye)[3])
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
        memcpy(nrm[k], f, sizeof f);
        memcpy(eye[k], c, sizeof c);
    }
}

/* Phong: normals interpolated with the mode's weights (screen-linear, exact
 * t_w or its polynomial approximations, §4.3) and renormalised. The eye
 * position is always perspective-correct (where the pixel's ray meets the
 * triangle's plane) so that modes differ only in the normal scheme. */
static void phong_normals(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          float (*nrm)[3], float (*eye)[3])
{
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    bary_for(ds, t, b, b1, b2);
    for (int k = 0; k < b->n; k++) {
        interp3(t, PERSP_A_NX, b1[k], b2[k], nrm[k]);
        normalize3(nrm[k]);
    }
    if (!ds->shade_method.m || ds->shading != PERSP_SHADING_PHONG_PC) bary_exact(t, b, b1, b2);
    for (int k = 0; k < b->n; k++) interp3(t, PERSP_A_EX, b1[k], b2[k], eye[k]);
}

/* Spherical-angular normals along the span (§4.3). The end normals are
 * exact (perspective-correct weights at the span's first and last pixels,
 * normalised); ħ = z_b/z_a = q_a/q_b from the 1/w plane. Batches without a
 * span (custom traversals) or of one pixel get exact per-pixel normals. */
static void slerp_normals(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          int perspective, float (*nrm)[3], float (*eye)[3])
{
    float b1[PERSP_SPAN_MAX], b2[PERSP_SPAN_MAX];
    bary_exact(t, b, b1, b2);
    (void)ds;
    for (int k = 0; k < b->n; k++) interp3(t, PERSP_A_EX, b1[k], b2[k], eye[k]);
    if (b->px || b->n < 2) {
        for (int k = 0; k < b->n; k++) {
            interp3(t, PERSP_A_NX, b1[k], b2[k], nrm[k]);
            normalize3(nrm[k]);
        }
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
    for (int k = 0; k < b->n; k++) persp__slerp_eval(&sl, (double)k / last, perspective, nrm[k]);
}

int persp__shade_normals(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                         float (*nrm)[3], float (*eye)[3])
{
    switch (ds->shading) {
    case PERSP_SHADING_FLAT: flat_normals(t, b->n, nrm, eye); return 1;
    case PERSP_SHADING_PHONG:
    case PERSP_SHADING_PHONG_PC:
    case PERSP_SHADING_PHONG_PC_QUAD:
    case PERSP_SHADING_PHONG_PC_PWQUAD:
    case PERSP_SHADING_PHONG_PC_CUBIC: phong_normals(ds, t, b, nrm, eye); return 1;
    case PERSP_SHADING_PHONG_SLERP: slerp_normals(ds, t, b, 1, nrm, eye); return 1;
    case PERSP_SHADING_PHONG_SLERP_SCREEN: slerp_normals(ds, t, b, 0, nrm, eye); return 1;
    default: return 0;
    }
}

static void light_span(const persp_draw_state *ds, const persp_tri *t, int n, const float (*nrm)[3],
                       const float (*eye)[3], const uint32_t *texel, uint32_t *out)
{
    const float side = face_side(t);
    for (int k = 0; k < n; k++) {
        float diff[3], spec[3];
        light_point(ds, nrm[k], eye[k], side, diff, spec);
        out[k] = combine(ds, diff, spec, texel, k);
    }
}

/* Flat: one lighting evaluation per triangle. */
static void shade_flat(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                       const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    float nrm[1][3], eye[1][3], diff[3], spec[3];
    flat_normals(t, 1, nrm, eye);
    const float *f = nrm[0], *c = eye[0];
    light_point(ds, f, c, f[0] * c[0] + f[1] * c[1] + f[2] * c[2] > 0.0f ? -1.0f : 1.0f, diff, spec);
    for (int k = 0; k < b->n; k++) out[k] = combine(ds, diff, spec, texel, k);
}

static void shade_phong(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                        const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    float nrm[PERSP_SPAN_MAX][3], eye[PERSP_SPAN_MAX][3];
    phong_normals(ds, t, b, nrm, eye);
    light_span(ds, t, b->n, (const float(*)[3])nrm, (const float(*)[3])eye, texel, out);
}

static void shade_slerp(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                        const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)q;
    float nrm[PERSP_SPAN_MAX][3], eye[PERSP_SPAN_MAX][3];
    slerp_normals(ds, t, b, 1, nrm, eye);
    light_span(ds, t, b->n, (const float(*)[3])nrm, (const float(*)[3])eye, texel, out);
}

static void shade_slerp_screen(const persp_draw_state *ds, const persp_tri *t,
                               const persp_frag_batch *b, const float *q, const uint32_t *texel,
                               uint32_t *out)
{
    (void)q;
    float nrm[PERSP_SPAN_MAX][3], eye[PERSP_SPAN_MAX][3];
    slerp_normals(ds, t, b, 0, nrm, eye);
    light_span(ds, t, b->n, (const float(*)[3])nrm, (const float(*)[3])eye, texel, out);
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

persp_status persp__shade_resolve(persp_context *ctx, persp_draw_state *ds)
{
    memset(&ds->shade_method, 0, sizeof ds->shade_method);
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
    ds->shade_is_texel = ds->shading == PERSP_SHADING_NONE && ds->tex != NULL;
    switch (ds->shading) {
    case PERSP_SHADING_NONE: ds->shade = ds->tex ? shade_replace : shade_vertex_color; break;
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

void persp__shade_vertices(const persp_draw_state *ds, persp_clipvert *v, size_t n)
{
    if (ds->shading != PERSP_SHADING_GOURAUD && ds->shading != PERSP_SHADING_GOURAUD_PC) return;
    for (size_t i = 0; i < n; i++) {
        float nn[3] = {v[i].attr[PERSP_A_NX], v[i].attr[PERSP_A_NY], v[i].attr[PERSP_A_NZ]};
        normalize3(nn);
        float diff[3], spec[3];
        /* Vertices are lit before their triangles are known (render.c), so
         * both sides are lit here, as OpenGL's two-sided lighting does, and
         * shade_gouraud picks one per triangle. */
        const float *e = &v[i].attr[PERSP_A_EX];
        light_point(ds, nn, e, 1.0f, diff, spec);
        for (int c = 0; c < 3; c++) v[i].attr[PERSP_A_R + c] = diff[c] + spec[c];
        light_point(ds, nn, e, -1.0f, diff, spec);
        for (int c = 0; c < 3; c++) v[i].attr[PERSP_A_BR + c] = diff[c] + spec[c];
        v[i].attr[PERSP_A_A] = 1.0f;
    }
}
