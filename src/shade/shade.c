/* Shading modes and the span shaders they resolve to. */
#include "shade/shade.h"

#include "core/internal.h"

#include <string.h>

static const char *const shading_names[PERSP_SHADING_COUNT] = {
    "none", "flat", "gouraud", "gouraud-pc", "phong", "phong-pc", "phong-pc:quad",
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

/* Texture replaces the fragment colour (seed 002 "texture environment"). */
static void shade_replace(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                          const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)ds, (void)t, (void)q;
    memcpy(out, texel, (size_t)b->n * sizeof *out);
}

static void shade_constant(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                           const float *q, const uint32_t *texel, uint32_t *out)
{
    (void)t, (void)q, (void)texel;
    float c[4] = {ds->material.diffuse[0], ds->material.diffuse[1], ds->material.diffuse[2], 1.0f};
    uint32_t p = pack(c);
    for (int k = 0; k < b->n; k++) out[k] = p;
}

persp_status persp__shade_resolve(persp_context *ctx, persp_draw_state *ds)
{
    switch (ds->shading) {
    case PERSP_SHADING_NONE:
        ds->shade = ds->tex ? shade_replace : shade_constant;
        return PERSP_OK;
    default:
        return persp_context_fail(ctx, PERSP_ERR_UNSUPPORTED, "shading '%s' is not supported",
                                  persp_shading_name(ds->shading));
    }
}

void persp__shade_vertices(const persp_draw_state *ds, persp_clipvert *v, size_t n)
{
    (void)ds, (void)v, (void)n;
}
