/* Shading (src/shade/): per-vertex lighting for Gouraud, per-span colour
 * for every persp_shading mode. */
#ifndef PERSP_SHADE_SHADE_H
#define PERSP_SHADE_SHADE_H

#include "raster/frame.h"

/* Chooses ds->shade (and ds->shade_method) from ds->shading, the texture
 * environment and whether a texture is bound. */
persp_status persp__shade_resolve(persp_context *ctx, persp_draw_state *ds);
/* Per-vertex stage: Gouraud modes write lit colours into the R, G, B, A
 * attributes; other modes leave the vertices alone. */
void persp__shade_vertices(const persp_draw_state *ds, persp_clipvert *v, size_t n);
static inline void persp__shade_span(const persp_draw_state *ds, const persp_tri *t,
                                     const persp_frag_batch *b, const float *q,
                                     const uint32_t *texel, uint32_t *out)
{
    ds->shade(ds, t, b, q, texel, out);
}

#endif
