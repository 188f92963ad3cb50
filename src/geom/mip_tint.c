/*
 * Mip levels as colours: every level of every texture of a scene becomes one
 * flat colour, so that an image shows which levels the filters read (and
 * how trilinear and anisotropic filters blend them), as GL tools do with
 * coloured mip chains.
 */
#include "core/internal.h"
#include "geom/scene.h"
#include "texture/texture.h"

#include <string.h>

/* Level 0 white, then hues around the colour wheel; alternating brightness
 * keeps neighbouring levels apart. */
static const uint8_t palette[][3] = {
    {255, 255, 255}, {255, 64, 64},  {255, 190, 40}, {170, 255, 60}, {40, 200, 90},
    {50, 230, 230},  {40, 110, 255}, {160, 70, 255}, {255, 80, 220}, {150, 150, 150},
};

void persp_mip_level_color(int level, uint8_t rgba[4])
{
    if (!rgba) return;
    int n = (int)(sizeof palette / sizeof palette[0]);
    int i = level < 0 ? 0 : level >= n ? n - 1 : level;
    memcpy(rgba, palette[i], 3);
    rgba[3] = 255;
}

persp_status persp_scene_tint_mip_levels(persp_scene *scene)
{
    if (!scene) return PERSP_ERR_INVALID_ARGUMENT;
    for (size_t t = 0; t < scene->texture_count; t++) {
        persp_texture *tex = scene->textures[t];
        if (!tex) continue;
        for (int l = 0; l < tex->levels; l++) {
            uint8_t c[4];
            persp_mip_level_color(l, c);
            uint32_t packed =
                (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16 | (uint32_t)c[3] << 24;
            /* The levels are views into the texture's own storage. */
            uint32_t *texels = (uint32_t *)(uintptr_t)tex->level[l].texels;
            size_t n = (size_t)tex->level[l].w * (size_t)tex->level[l].h;
            for (size_t i = 0; i < n; i++)
                texels[i] = packed;
        }
    }
    return PERSP_OK;
}
