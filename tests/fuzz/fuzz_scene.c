/* libFuzzer harness: JSON scene from memory. File references are refused
 * (no base folder) and the meshes of one input are held to 2^18 vertices so
 * that a short input cannot ask for gigabytes of primitives. */
#include "geom/scene.h"
#include "io/model.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = NULL;
    if (persp__scene_load_memory(ctx, (const char *)data, size, "fuzz.json", NULL, (size_t)1 << 18, &scene) ==
        PERSP_OK)
        persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return 0;
}
