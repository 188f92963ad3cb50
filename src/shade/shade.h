/* Shading (src/shade/): per-vertex lighting for Gouraud, per-span colour
 * for every persp_shading mode. */
#ifndef PERSP_SHADE_SHADE_H
#define PERSP_SHADE_SHADE_H

#include "core/shared.h"

#include "pipeline/types.h"

/* Chooses ds->shade (and ds->shade_method) from ds->shading, the texture
 * environment and whether a texture is bound. */
PERSP_INTERNAL persp_status persp__shade_resolve(persp_context *ctx, persp_draw_state *ds);
/* The lighting loops' variant PERSP_SIMD_AUTO stands for on this CPU
 * (PERSP_ISA_*): AVX2, or AVX-512 where the CPU has it and it times faster. */
int persp__shade_auto_isa(void);
/* The shading modes that light vertices (gouraud, gouraud-pc). */
static inline int persp__shade_is_gouraud(const persp_draw_state *ds)
{
    return ds->shading == PERSP_SHADING_GOURAUD || ds->shading == PERSP_SHADING_GOURAUD_PC;
}

/* Per-vertex stage: Gouraud modes write lit colours into the R, G, B, A
 * attributes and the back face's into BR, BG, BB (two-sided lighting);
 * other modes leave the vertices alone. */
PERSP_INTERNAL void persp__shade_vertices(const persp_draw_state *ds, persp_clipvert *v, size_t n);

/* Vertices given component-wise: eye-space normals (not necessarily unit),
 * eye-space positions, and vertex colours (read only with
 * ds->color_material). */
typedef struct persp_light_in {
    const float *n[3], *e[3], *c[3];
} persp_light_in;
/* Gouraud colours of n <= PERSP_SPAN_MAX vertices, the front's into
 * front[0..2] (r, g, b arrays) and the back's into back[0..2], either NULL
 * when not wanted: the colours persp__shade_vertices writes. The renderer
 * lights fronts in its vertex stage and backs there or at set-up, for the
 * triangles that show them. */
void persp__light_vertices(const persp_draw_state *ds, int n, const persp_light_in *in, float *const front[3],
                           float *const back[3]);
static inline void persp__shade_span(const persp_draw_state *ds, const persp_tri *t,
                                     const persp_frag_batch *b, const float *q,
                                     const uint32_t *texel, uint32_t *out)
{
    ds->shade(ds, t, b, q, texel, out);
}

/* Two-sided lighting decided once per triangle (at set-up, into
 * persp_tri.light_side), as OpenGL picks the front or back colour by the
 * polygon's facing: -1 (light the back) when the triangle's vertex normals,
 * summed, face away from the eye at its centroid, else 1. A per-pixel test
 * of N·E would flip the smooth normals of front faces near silhouettes
 * (where they turn away from the eye) and light a rim on the dark side. */
float persp__shade_light_side(const persp_tri *t);
/* Perspective-correct Gouraud modulating texels for pixels given by their
 * weights w1, w2 alone (in any arrangement: the small-triangle path of
 * tiles.c packs several rows); the same colours as the span shader. It
 * reads and writes whole groups of PERSP_SHADE_GROUP lanes: up to
 * PERSP_SHADE_GROUP - 1 past n, which must be there (their values are
 * read, any, and overwritten). Segments of a few pixels (small triangles)
 * then run no scalar remainder, which cost more than the vector loop. */
#define PERSP_SHADE_GROUP 8
void persp__shade_gouraud_lanes(const persp_draw_state *ds, const persp_tri *t, int n, const float *w1,
                                const float *w2, const uint32_t *texel, uint32_t *out);
/* The same for perspective-correct Phong (phong-pc with the exact weights). */
void persp__shade_phong_lanes(const persp_draw_state *ds, const persp_tri *t, int n, const float *w1,
                              const float *w2, const uint32_t *texel, uint32_t *out);
/* The same for lanes [seg_start[s], seg_start[s + 1]) of triangle
 * seg_tri[s], s < nseg: one lighting pass over all seg_start[nseg] lanes
 * (the renderer has packed out those the depth test hid). */
void persp__shade_phong_segments(const persp_draw_state *ds, int nseg, const int *seg_start,
                                 const persp_tri *const *seg_tri, const float *w1, const float *w2,
                                 const uint32_t *texel, uint32_t *out);

/* The unit normal and eye-space position each pixel of batch b is lit with
 * under ds->shading (the same code the span shaders use), for accuracy
 * analysis. Returns 0 for modes without per-pixel normals (none, gouraud,
 * gouraud-pc); nrm and eye then stay untouched. */
PERSP_INTERNAL int persp__shade_normals(const persp_draw_state *ds, const persp_tri *t,
                                        const persp_frag_batch *b, float (*nrm)[3],
                                        float (*eye)[3]);

/*
 * Spherical-angular interpolation of unit normals along a span ([Romanyuk-PCF]
 * §4.3), in the cotangent form that yields unit vectors without
 * renormalisation: with ψ = ∠(Na, Nb), Nk the unit vector orthogonal to Na
 * in their plane, and b = ctg(angle from Na), N = (Na·b + Nk)/sqrt(1 + b²).
 * Perspective-correct: b = ctg ψ + ħ·(ctg(ηψ) − ctg ψ) (§4.3), where ηψ is
 * the angle whose chord parameter is the screen parameter t_v, i.e.
 * ctg(ηψ) − ctg ψ = (1/t_v − 1)/sin ψ; so b = ctg ψ + ħ·(1/t_v − 1)/sin ψ,
 * ħ = z_b/z_a. Screen-space counterpart: b = ctg(t_v·ψ) (angle linear on
 * screen, plain slerp).
 */
typedef struct persp_slerp {
    double na[3], nk[3];
    double psi, ctg_psi, inv_sin_psi, hbar;
    int straight; /* Na ∥ Nb: nothing to interpolate */
} persp_slerp;

void persp__slerp_init(persp_slerp *s, const float na[3], const float nb[3], double hbar);
/* Normal at screen parameter tv in [0, 1]; perspective != 0 for the
 * perspective-correct form. */
void persp__slerp_eval(const persp_slerp *s, double tv, int perspective, float out[3]);

#endif
