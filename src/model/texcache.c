/* Texture files shared by the objects and materials of one scene load. */
#include "core/internal.h"
#include "model/model.h"
#include "io/text.h"

#include <string.h>

persp_status persp__texcache_load(persp_scene *scene, persp_texcache *cache, const char *path,
                                  int *index)
{
    persp_context *ctx = scene->ctx;
    if (cache)
        for (size_t i = 0; i < cache->count; i++)
            if (strcmp(cache->entries[i].path, path) == 0) {
                *index = cache->entries[i].index;
                return PERSP_OK;
            }
    persp_image img;
    memset(&img, 0, sizeof img);
    /* Confined by the open itself (persp__open_inside): the scene's or
     * model's earlier check of the name does not cover a link swapped
     * before this read. */
    persp_status st = persp__image_load_inside(ctx, scene->load_root, path, &img);
    if (st != PERSP_OK) return st;
    persp__image_set_opaque(&img);
    persp_texture *tex = NULL;
    st = persp_texture_create(ctx, &img, &tex);
    persp_image_free(ctx, &img);
    if (st != PERSP_OK) return st;
    st = persp__scene_add_texture(scene, tex, index);
    if (st != PERSP_OK || !cache) return st;
    /* The cache only saves loading a file twice, but a refused allocation is
     * still reported: a caller with a memory budget must learn that it ran
     * out (PERSP_ERR_OUT_OF_MEMORY, persp.h) rather than get a scene that
     * quietly took another path. The texture already belongs to the scene. */
    if (persp__grow(ctx, (void **)&cache->entries, &cache->cap, cache->count + 1,
                    sizeof *cache->entries) != PERSP_OK)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    size_t len = strlen(path);
    char *copy = persp__alloc(ctx, len + 1);
    if (!copy) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    memcpy(copy, path, len + 1);
    cache->entries[cache->count].path = copy;
    cache->entries[cache->count].index = *index;
    cache->count++;
    return PERSP_OK;
}

void persp__texcache_free(persp_context *ctx, persp_texcache *cache)
{
    if (!cache) return;
    for (size_t i = 0; i < cache->count; i++)
        persp__free(ctx, cache->entries[i].path);
    persp__free(ctx, cache->entries);
    memset(cache, 0, sizeof *cache);
}
