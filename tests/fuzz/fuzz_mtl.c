/* libFuzzer harness: MTL text from memory (texture statements are checked,
 * no files are opened). */
#include "geom/scene.h"
#include "io/obj.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = NULL;
    if (persp__scene_new(ctx, &scene) == PERSP_OK) {
        persp_mtl_lib lib = {0};
        persp__mtl_load_memory(scene, (const char *)data, size, "fuzz.mtl", NULL, &lib, NULL);
        persp__mtl_lib_free(ctx, &lib);
        persp_scene_destroy(scene);
    }
    persp_context_destroy(ctx);
    return 0;
}
